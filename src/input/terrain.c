/* terrain.c - the triangulated slope (Eq. 3-7): triangle geometry, point location on
 * grids and bucketed meshes, box queries, surface zones and Table 2. */
#include "rockfall/terrain.h"

#include <assert.h>
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "input/terrain_io.h"
#include "input/tin.h"
#include "base/names.h"
#include "base/polygon.h"
#include "base/tolerances.h"
#include "base/util.h"

/* Bucket edge as a multiple of the mean horizontal triangle edge. */
#define BUCKET_EDGE_FACTOR 1.0
/* At most this many buckets per triangle (and at least MIN_BUCKETS in all), and at
 * most ITEMS_PER_TRIANGLE bucket entries per triangle on average: a few huge
 * triangles among many small ones widen the buckets instead of filling memory. */
#define BUCKETS_PER_TRIANGLE 2
#define MIN_BUCKETS 64
#define ITEMS_PER_TRIANGLE 16

/* ---- Table 2 --------------------------------------------------------------------------- */

double rf_table2_friction(char slope_class)
{
    switch (toupper((unsigned char)slope_class)) {
    case 'A': return 0.05;
    case 'B': return 0.15;
    case 'C': return 0.25;
    case 'D': return 0.35;
    default: return -1.0;
    }
}

rf_dist rf_table2_friction_dist(char slope_class)
{
    /* Each class spans about 0.1 of mu (A under 0.10, B 0.11-0.20, ...); a quarter of
     * that width, 0.025, as the standard deviation keeps about 95 % of the draws within
     * +-0.05 of the recommended value, i.e. inside the class. */
    double mean = rf_table2_friction(slope_class);
    rf_dist d = {mean, mean < 0 ? 0.0 : 0.025};
    return d;
}

/* ---- triangle geometry ---------------------------------------------------------------- */

/* Sets t from its vertices and cr, the cross product of its edges ab and ac, of length
 * len > 0. */
static inline void triangle_fill(rf_triangle *t, rf_vec3 a, rf_vec3 b, rf_vec3 c, rf_vec3 cr,
                                 double len, int32_t zone)
{
    rf_vec3 n = rf_v3_scale(cr, 1.0 / len);
    if (n.z < 0)
        n = rf_v3_scale(n, -1.0);
    if (n.z == 0)
        n.z = 0.0; /* no negative zero */
    t->a = a;
    t->b = b;
    t->c = c;
    t->n = n;
    t->d = rf_v3_dot(n, a);
    t->zone = zone;
}

/* Sets vertices, unit upward normal, offset and zone; returns 0 for a triangle with no
 * area (or a NaN vertex), leaving t's fields unspecified. */
static int triangle_set(rf_triangle *t, rf_vec3 a, rf_vec3 b, rf_vec3 c, int32_t zone)
{
    rf_vec3 ab = rf_v3_sub(b, a), ac = rf_v3_sub(c, a), bc = rf_v3_sub(c, b);
    rf_vec3 cr = rf_v3_cross(ab, ac);
    double len = rf_v3_norm(cr);
    double e2 = fmax(rf_v3_norm2(ab), fmax(rf_v3_norm2(ac), rf_v3_norm2(bc)));
    if (!(len > RF_DEGENERATE_REL * e2))
        return 0;
    triangle_fill(t, a, b, c, cr, len, zone);
    return 1;
}

double rf_triangle_slope(const rf_triangle *tri)
{
    return atan2(hypot(tri->n.x, tri->n.y), tri->n.z);
}

double rf_triangle_z_at(const rf_triangle *tri, double x, double y)
{
    return (tri->d - tri->n.x * x - tri->n.y * y) / tri->n.z;
}

void rf_triangle_plane_abd(const rf_triangle *tri, double *a, double *b, double *d)
{
    /* Eq. 3-4: n.x X + n.y Y + n.z Z = d divided by n.z. */
    *a = tri->n.x / tri->n.z;
    *b = tri->n.y / tri->n.z;
    *d = tri->d / tri->n.z;
}

int rf_triangle_contains_xy(const rf_triangle *tri, double x, double y, double tol,
                            double *t_out, double *s_out)
{
    /* Eq. 5-6: P = t u + s v in the xy projection. */
    double ux = tri->b.x - tri->a.x, uy = tri->b.y - tri->a.y;
    double vx = tri->c.x - tri->a.x, vy = tri->c.y - tri->a.y;
    double px = x - tri->a.x, py = y - tri->a.y;
    double det = ux * vy - uy * vx;
    if (det == 0.0)
        return 0;
    double t = (px * vy - py * vx) / det;
    double s = (ux * py - uy * px) / det;
    if (t_out)
        *t_out = t;
    if (s_out)
        *s_out = s;
    return t >= -tol && s >= -tol && t + s <= 1.0 + tol;
}

double rf_triangle_plane_distance(const rf_triangle *tri, rf_vec3 p)
{
    /* Eq. 7 with the unit normal: (a X + b Y + Z - d) / sqrt(a^2 + b^2 + 1). */
    return rf_v3_dot(tri->n, p) - tri->d;
}

rf_vec3 rf_triangle_closest_point(const rf_triangle *tri, rf_vec3 p)
{
    /* Inside the prism over the face (p is on the inner side of all three edges, seen
     * along the face normal) the answer is p's projection on the plane; otherwise it
     * lies on an edge whose outer side holds p.  Edge tests use only vertex
     * differences, so slivers stay well-conditioned. */
    rf_vec3 a = tri->a, b = tri->b, c = tri->c;
    rf_vec3 ab = rf_v3_sub(b, a), bc = rf_v3_sub(c, b), ca = rf_v3_sub(a, c);
    rf_vec3 ap = rf_v3_sub(p, a), bp = rf_v3_sub(p, b), cp = rf_v3_sub(p, c);
    rf_vec3 nn = rf_v3_cross(ab, rf_v3_scale(ca, -1.0));
    double nn2 = rf_v3_norm2(nn);
    double s_ab = rf_v3_dot(rf_v3_cross(ab, ap), nn);
    double s_bc = rf_v3_dot(rf_v3_cross(bc, bp), nn);
    double s_ca = rf_v3_dot(rf_v3_cross(ca, cp), nn);
    if (nn2 > 0 && s_ab >= 0 && s_bc >= 0 && s_ca >= 0)
        return rf_v3_madd(p, -rf_v3_dot(nn, ap) / nn2, nn);

    rf_vec3 best = a;
    double best_d2 = INFINITY;
    int all = !(nn2 > 0);
    if (all || s_ab < 0) {
        rf_vec3 q = rf_v3_closest_on_segment(a, b, p);
        double d2 = rf_v3_norm2(rf_v3_sub(p, q));
        if (d2 < best_d2)
            best = q, best_d2 = d2;
    }
    if (all || s_bc < 0) {
        rf_vec3 q = rf_v3_closest_on_segment(b, c, p);
        double d2 = rf_v3_norm2(rf_v3_sub(p, q));
        if (d2 < best_d2)
            best = q, best_d2 = d2;
    }
    if (all || s_ca < 0) {
        rf_vec3 q = rf_v3_closest_on_segment(c, a, p);
        double d2 = rf_v3_norm2(rf_v3_sub(p, q));
        if (d2 < best_d2)
            best = q, best_d2 = d2;
    }
    return best;
}

/* ---- polygons ------------------------------------------------------------------------- */

int rf_point_in_polygon(const double *poly_xy, size_t npoly, double x, double y)
{
    int inside = 0;
    for (size_t i = 0, j = npoly ? npoly - 1 : 0; i < npoly; j = i++) {
        int r = rf_polygon_edge(poly_xy[2 * i], poly_xy[2 * i + 1], poly_xy[2 * j],
                                poly_xy[2 * j + 1], x, y);
        if (r == RF_EDGE_ON)
            return 1; /* on the boundary */
        if (r == RF_EDGE_CROSSES)
            inside = !inside;
    }
    return inside;
}

/* ---- point location ----------------------------------------------------------------- */

/* Height of the triangle's surface at barycentric (t, s): bounded by the vertex
 * heights, so steep faces stay well-behaved. */
static double bary_z(const rf_triangle *tri, double t, double s)
{
    return tri->a.z + t * (tri->b.z - tri->a.z) + s * (tri->c.z - tri->a.z);
}

/* A grid point next to a cell border whose own triangle is a hole: the neighbouring
 * cells' triangles may still hold it within the tolerance. */
static int32_t grid_locate_near(const rf_terrain *t, double x, double y, long ci, long cj,
                                double *z)
{
    int32_t best = -1;
    double best_z = -INFINITY;
    for (long j = cj - 1; j <= cj + 1; j++) {
        for (long i = ci - 1; i <= ci + 1; i++) {
            if (i < 0 || j < 0 || (size_t)i + 1 >= t->nx || (size_t)j + 1 >= t->ny)
                continue;
            for (int k = 0; k < 2; k++) {
                int32_t idx = rf_grid_slot(t, 2 * ((size_t)j * (t->nx - 1) + (size_t)i) + (size_t)k);
                double tt = 0.0, ss = 0.0;
                rf_triangle buf;
                const rf_triangle *T = idx >= 0 ? rf_tri(t, idx, &buf) : NULL;
                if (T && rf_triangle_contains_xy(T, x, y, RF_LOCATE_TOL, &tt, &ss)) {
                    double zz = bary_z(T, tt, ss);
                    if (zz > best_z)
                        best = idx, best_z = zz;
                }
            }
        }
    }
    if (best >= 0 && z)
        *z = best_z;
    return best;
}

static int32_t grid_locate(const rf_terrain *t, double x, double y, double *z)
{
    double fx = (x - t->x0) / t->cell, fy = (y - t->y0) / t->cell;
    double wx = (double)(t->nx - 1), wy = (double)(t->ny - 1);
    if (!(fx >= -RF_LOCATE_TOL && fx <= wx + RF_LOCATE_TOL && fy >= -RF_LOCATE_TOL &&
          fy <= wy + RF_LOCATE_TOL))
        return -1;
    double fi = floor(fx), fj = floor(fy);
    fi = fi < 0 ? 0 : (fi > wx - 1 ? wx - 1 : fi);
    fj = fj < 0 ? 0 : (fj > wy - 1 ? wy - 1 : fj);
    size_t i = (size_t)fi, j = (size_t)fj;
    double u = fx - fi, v = fy - fj;
    int k = v <= u ? 0 : 1; /* below or above the SW-NE diagonal */
    int32_t idx = rf_grid_slot(t, 2 * (j * (t->nx - 1) + i) + (size_t)k);
    if (idx < 0)
        return grid_locate_near(t, x, y, (long)i, (long)j, z);
    if (z) {
        rf_triangle buf;
        const rf_triangle *tri = rf_tri(t, idx, &buf);
        double tt = 0.0, ss = 0.0;
        rf_triangle_contains_xy(tri, x, y, RF_LOCATE_TOL, &tt, &ss);
        *z = bary_z(tri, tt, ss);
    }
    return idx;
}

/* The bucket holding coordinate c along an axis of n buckets from c0, or -1. */
static long bucket_of(double c, double c0, double size, size_t n)
{
    double f = (c - c0) / size;
    if (!(f >= -RF_LOCATE_TOL && f <= (double)n + RF_LOCATE_TOL))
        return -1;
    long b = (long)floor(f);
    if (b < 0)
        b = 0;
    if ((size_t)b >= n)
        b = (long)n - 1;
    return b;
}

static int32_t mesh_locate(const rf_terrain *t, double x, double y, double *z)
{
    long bi = bucket_of(x, t->bx0, t->bsize, t->nbx);
    long bj = bucket_of(y, t->by0, t->bsize, t->nby);
    if (bi < 0 || bj < 0)
        return -1;
    size_t b = (size_t)bj * t->nbx + (size_t)bi;
    int32_t best = -1;
    double best_z = -INFINITY;
    for (uint32_t k = t->bucket_start[b]; k < t->bucket_start[b + 1]; k++) {
        int32_t idx = t->bucket_items[k];
        const rf_triangle *tri = &t->tri[idx];
        double tt = 0.0, ss = 0.0;
        if (rf_triangle_contains_xy(tri, x, y, RF_LOCATE_TOL, &tt, &ss)) {
            double zz = bary_z(tri, tt, ss);
            if (zz > best_z)
                best = idx, best_z = zz;
        }
    }
    if (best >= 0 && z)
        *z = best_z;
    return best;
}

int32_t rf_terrain_locate(const rf_terrain *t, double x, double y)
{
    return t->is_grid ? grid_locate(t, x, y, NULL) : mesh_locate(t, x, y, NULL);
}

int32_t rf_terrain_height(const rf_terrain *t, double x, double y, double *z)
{
    double zz = 0;
    int32_t idx = t->is_grid ? grid_locate(t, x, y, &zz) : mesh_locate(t, x, y, &zz);
    if (idx >= 0)
        *z = zz;
    return idx;
}

/* ---- box queries ---------------------------------------------------------------------- */

static int box_overlap(rf_vec3 a, rf_vec3 b, rf_vec3 c, double xmin, double ymin, double xmax,
                       double ymax)
{
    double tx0 = fmin(a.x, fmin(b.x, c.x));
    double tx1 = fmax(a.x, fmax(b.x, c.x));
    double ty0 = fmin(a.y, fmin(b.y, c.y));
    double ty1 = fmax(a.y, fmax(b.y, c.y));
    return tx0 <= xmax && tx1 >= xmin && ty0 <= ymax && ty1 >= ymin;
}

static int tri_box_overlap(const rf_triangle *tri, double xmin, double ymin, double xmax,
                           double ymax)
{
    return box_overlap(tri->a, tri->b, tri->c, xmin, ymin, xmax, ymax);
}

size_t rf_terrain_query_box(const rf_terrain *t, double xmin, double ymin, double xmax,
                            double ymax, int32_t *out, size_t cap, uint32_t *stamp,
                            uint32_t *epoch)
{
    size_t count = 0, i0, i1, j0, j1;
    if (t->is_grid) {
        /* Cell (i, j) spans [x0 + i cell, x0 + (i + 1) cell]: each triangle is in one
         * cell, so no duplicates arise. */
        if (!rf_cell_range(xmin, xmax, t->x0, t->cell, t->nx - 1, &i0, &i1) ||
            !rf_cell_range(ymin, ymax, t->y0, t->cell, t->ny - 1, &j0, &j1))
            return 0;
        /* A box edge exactly on a node line also touches the cell before it. */
        if (i0 > 0 && xmin <= t->x0 + (double)i0 * t->cell)
            i0--;
        if (j0 > 0 && ymin <= t->y0 + (double)j0 * t->cell)
            j0--;
        for (size_t j = j0; j <= j1; j++)
            for (size_t i = i0; i <= i1; i++)
                for (size_t k = 0; k < 2; k++) {
                    int32_t idx = rf_grid_slot(t, 2 * (j * (t->nx - 1) + i) + k);
                    rf_vec3 v[3];
                    if (idx < 0)
                        continue;
                    rf_grid_vertices(t, idx, v);
                    if (!box_overlap(v[0], v[1], v[2], xmin, ymin, xmax, ymax))
                        continue;
                    if (count < cap)
                        out[count] = idx;
                    count++;
                }
        return count;
    }
    if (++*epoch == 0) {
        memset(stamp, 0, t->ntri * sizeof *stamp);
        *epoch = 1;
    }
    uint32_t mark = *epoch;
    if (!rf_cell_range(xmin, xmax, t->bx0, t->bsize, t->nbx, &i0, &i1) ||
        !rf_cell_range(ymin, ymax, t->by0, t->bsize, t->nby, &j0, &j1))
        return 0;
    for (size_t j = j0; j <= j1; j++)
        for (size_t i = i0; i <= i1; i++) {
            size_t b = j * t->nbx + i;
            for (uint32_t k = t->bucket_start[b]; k < t->bucket_start[b + 1]; k++) {
                int32_t idx = t->bucket_items[k];
                if (stamp[idx] == mark)
                    continue;
                stamp[idx] = mark;
                if (!tri_box_overlap(&t->tri[idx], xmin, ymin, xmax, ymax))
                    continue;
                if (count < cap)
                    out[count] = idx;
                count++;
            }
        }
    return count;
}

/* ---- building ------------------------------------------------------------------------- */

void rf_terrain_free(rf_terrain *t)
{
    if (!t)
        return;
    free(t->tri);
    for (size_t i = 0; i < t->nzones; i++)
        free(t->zones[i].name);
    free(t->zones);
    free(t->z);
    free(t->grid_hole);
    free(t->zone8);
    free(t->zone16);
    free(t->zone32);
    free(t->bucket_start);
    free(t->bucket_items);
    memset(t, 0, sizeof *t);
}

static int add_zone(rf_terrain *t, const char *name, size_t name_len, rf_surface surface)
{
    rf_zone *z = realloc(t->zones, (t->nzones + 1) * sizeof *z);
    if (!z)
        return -1;
    t->zones = z;
    char *s = malloc(name_len + 1);
    if (!s)
        return -1;
    memcpy(s, name, name_len);
    s[name_len] = '\0';
    t->zones[t->nzones].name = s;
    t->zones[t->nzones].surface = surface;
    t->nzones++;
    return 0;
}

/* The vertices of triangle k, kept or derived; 0 for a grid's hole (v untouched). */
static int tri_vertices_at(const rf_terrain *t, size_t k, rf_vec3 v[3])
{
    if (t->is_grid && rf_grid_slot(t, k) < 0)
        return 0;
    if (t->tri)
        v[0] = t->tri[k].a, v[1] = t->tri[k].b, v[2] = t->tri[k].c;
    else
        rf_grid_vertices(t, (int32_t)k, v);
    return 1;
}

static void compute_bounds(rf_terrain *t)
{
    t->xmin = t->ymin = t->zmin = INFINITY;
    t->xmax = t->ymax = t->zmax = -INFINITY;
    for (size_t k = 0; k < t->ntri; k++) {
        rf_vec3 v[3];
        if (!tri_vertices_at(t, k, v))
            continue; /* a hole */
        for (int i = 0; i < 3; i++) {
            t->xmin = fmin(t->xmin, v[i].x), t->xmax = fmax(t->xmax, v[i].x);
            t->ymin = fmin(t->ymin, v[i].y), t->ymax = fmax(t->ymax, v[i].y);
            t->zmin = fmin(t->zmin, v[i].z), t->zmax = fmax(t->zmax, v[i].z);
        }
    }
}

/* Bounding boxes are widened by the location tolerance so that a point on an edge
 * finds the triangle from either bucket. */
static void bucket_span(const rf_terrain *t, const rf_triangle *tri, double size, size_t nbx,
                        size_t nby, size_t *i0, size_t *i1, size_t *j0, size_t *j1, int *any)
{
    double pad = RF_LOCATE_TOL * size;
    double tx0 = fmin(tri->a.x, fmin(tri->b.x, tri->c.x)) - pad;
    double tx1 = fmax(tri->a.x, fmax(tri->b.x, tri->c.x)) + pad;
    double ty0 = fmin(tri->a.y, fmin(tri->b.y, tri->c.y)) - pad;
    double ty1 = fmax(tri->a.y, fmax(tri->b.y, tri->c.y)) + pad;
    *any = rf_cell_range(tx0, tx1, t->xmin, size, nbx, i0, i1) &&
           rf_cell_range(ty0, ty1, t->ymin, size, nby, j0, j1);
}

/* The bucket grid over the xy bounds: buckets about BUCKET_EDGE_FACTOR mean horizontal
 * edges wide; each triangle is listed in every bucket its xy bounding box overlaps. */
static int build_buckets(rf_terrain *t)
{
    double w = t->xmax - t->xmin, h = t->ymax - t->ymin;
    double edge_sum = 0;
    for (size_t k = 0; k < t->ntri; k++) {
        const rf_triangle *tri = &t->tri[k];
        edge_sum += hypot(tri->b.x - tri->a.x, tri->b.y - tri->a.y) +
                    hypot(tri->c.x - tri->b.x, tri->c.y - tri->b.y) +
                    hypot(tri->a.x - tri->c.x, tri->a.y - tri->c.y);
    }
    double size = BUCKET_EDGE_FACTOR * edge_sum / (3.0 * (double)t->ntri);
    double extent = fmax(w, h);
    if (!(size > 0))
        size = extent > 0 ? extent : 1.0;
    double max_buckets = fmax((double)MIN_BUCKETS, BUCKETS_PER_TRIANGLE * (double)t->ntri);
    double max_items = ITEMS_PER_TRIANGLE * (double)t->ntri + max_buckets;
    size_t nbx, nby;
    for (;;) {
        while ((floor(w / size) + 1) * (floor(h / size) + 1) > max_buckets)
            size *= 1.25;
        nbx = (size_t)floor(w / size) + 1;
        nby = (size_t)floor(h / size) + 1;
        double items = 0;
        for (size_t k = 0; k < t->ntri && items <= max_items; k++) {
            size_t i0, i1, j0, j1;
            int any;
            bucket_span(t, &t->tri[k], size, nbx, nby, &i0, &i1, &j0, &j1, &any);
            if (any)
                items += (double)(i1 - i0 + 1) * (double)(j1 - j0 + 1);
        }
        if (items <= max_items || size >= extent)
            break;
        size *= 2;
    }
    if (ITEMS_PER_TRIANGLE * (double)t->ntri + max_buckets >= (double)UINT32_MAX)
        return -1;
    t->bsize = size;
    t->bx0 = t->xmin;
    t->by0 = t->ymin;
    t->nbx = nbx;
    t->nby = nby;
    size_t nb = nbx * nby;

    t->bucket_start = calloc(nb + 1, sizeof *t->bucket_start);
    if (!t->bucket_start)
        return -1;
    for (int pass = 0; pass < 2; pass++) {
        for (size_t k = 0; k < t->ntri; k++) {
            size_t i0, i1, j0, j1;
            int any;
            bucket_span(t, &t->tri[k], size, nbx, nby, &i0, &i1, &j0, &j1, &any);
            if (!any)
                continue;
            for (size_t j = j0; j <= j1; j++)
                for (size_t i = i0; i <= i1; i++) {
                    size_t b = j * nbx + i;
                    if (pass == 0)
                        t->bucket_start[b + 1]++;
                    else
                        t->bucket_items[t->bucket_start[b]++] = (int32_t)k;
                }
        }
        if (pass == 0) {
            for (size_t b = 0; b < nb; b++)
                t->bucket_start[b + 1] += t->bucket_start[b];
            t->bucket_items = malloc((t->bucket_start[nb] ? t->bucket_start[nb] : 1) *
                                     sizeof *t->bucket_items);
            if (!t->bucket_items)
                return -1;
        }
    }
    /* Pass 1 advanced every start to the next bucket's start: shift back. */
    memmove(t->bucket_start + 1, t->bucket_start, nb * sizeof *t->bucket_start);
    t->bucket_start[0] = 0;
    return 0;
}

/* A triangle whose xy centroid lies in a polygon zone takes the first such zone.  Each
 * polygon is tested through an index of its edges (base/polygon.h): a triangle costs the
 * few edges near its centroid's y, not all of them, and gets the zone the plain test
 * gives.  0, or -1 when memory runs out. */
static int apply_polygon_zones(rf_terrain *t, const rf_terrain_spec *spec,
                               const int32_t *poly_zone)
{
    rf_polygon_index *ix = calloc(spec->nzones, sizeof *ix);
    if (!ix)
        return -1;
    int rc = 0;
    for (size_t z = 0; z < spec->nzones && rc == 0; z++)
        if (spec->zones[z].poly_xy)
            rc = rf_polygon_index_build(&ix[z], spec->zones[z].poly_xy, spec->zones[z].npoly);
    if (rc == 0 && !t->tri) {
        size_t n = t->ntri ? t->ntri : 1;
        if (t->nzones <= 256)
            rc = (t->zone8 = calloc(n, sizeof *t->zone8)) ? 0 : -1;
        else if (t->nzones <= 65536)
            rc = (t->zone16 = calloc(n, sizeof *t->zone16)) ? 0 : -1;
        else
            rc = (t->zone32 = calloc(n, sizeof *t->zone32)) ? 0 : -1;
    }
    for (size_t k = 0; k < t->ntri && rc == 0; k++) {
        rf_vec3 v[3];
        if (!tri_vertices_at(t, k, v))
            continue; /* a hole */
        double cx = (v[0].x + v[1].x + v[2].x) / 3.0;
        double cy = (v[0].y + v[1].y + v[2].y) / 3.0;
        for (size_t z = 0; z < spec->nzones; z++) {
            if (spec->zones[z].poly_xy && rf_polygon_index_contains(&ix[z], cx, cy)) {
                if (t->tri)
                    t->tri[k].zone = poly_zone[z];
                else if (t->zone8)
                    t->zone8[k] = (uint8_t)poly_zone[z];
                else if (t->zone16)
                    t->zone16[k] = (uint16_t)poly_zone[z];
                else
                    t->zone32[k] = poly_zone[z];
                break;
            }
        }
    }
    for (size_t z = 0; z < spec->nzones; z++)
        rf_polygon_index_free(&ix[z]);
    free(ix);
    return rc;
}

static int set_from_list(rf_terrain *t, const rf_tri_list *l, const int32_t *zone_of);

/* A grid made a TIN within spec->tolerance (input/tin.h): a mesh from here on. */
static int build_tin(const rf_terrain_spec *spec, rf_asc_grid *g, rf_terrain *t, rf_error *err)
{
    const char *path = spec->files[0];
    rf_tri_list l = {NULL, 0, 0};
    rf_tin_stats st;
    int rc = rf_tin_build(g, spec->tolerance, path, &l, &st, err);
    rf_asc_free(g);
    if (rc)
        return -1;
    rc = set_from_list(t, &l, NULL);
    rf_tri_list_free(&l);
    if (rc)
        return rf_error_set(err, path, 0, 0, "out of memory for the TIN of the grid");
    if (t->ntri == 0)
        return rf_error_set(err, path, 0, 0, "the grid has no cell without nodata");
    return 0;
}

static int build_grid(const rf_terrain_spec *spec, rf_terrain *t, rf_error *err)
{
    assert(spec->nfiles == 1);
    const char *path = spec->files[0];
    rf_asc_grid g;
    if (rf_asc_read(path, &g, err))
        return -1;
    if (spec->tolerance > 0)
        return build_tin(spec, &g, t, err);
    size_t nx = g.ncols, ny = g.nrows, ncell = (nx - 1) * (ny - 1);
    t->is_grid = 1;
    t->nx = nx;
    t->ny = ny;
    t->x0 = g.x0;
    t->y0 = g.y0;
    t->cell = g.cell;
    if (2 * nx * ny > INT32_MAX) {
        rf_asc_free(&g);
        return rf_error_set(err, path, 0, 0, "grid too large (%zu cells)", ncell);
    }
    /* the heights are the terrain: nodata becomes NaN, whose triangles have no area */
    t->z = g.z;
    g.z = NULL;
    if (g.has_nodata)
        for (size_t k = 0; k < nx * ny; k++)
            if (t->z[k] == g.nodata)
                t->z[k] = NAN;
    t->ntri = 2 * ncell;
    size_t nvalid = 0;
    for (size_t c = 0; c < ncell; c++)
        for (int32_t k = 0; k < 2; k++) {
            rf_triangle T;
            rf_vec3 v[3];
            rf_grid_vertices(t, (int32_t)(2 * c) + k, v);
            if (triangle_set(&T, v[0], v[1], v[2], 0)) {
                nvalid++;
                continue;
            }
            if (!t->grid_hole && !(t->grid_hole = calloc(ncell, 1)))
                return rf_error_set(err, path, 0, 0, "out of memory for a %zu x %zu grid", nx, ny);
            t->grid_hole[c] |= (uint8_t)(1u << k);
        }
    if (nvalid == 0)
        return rf_error_set(err, path, 0, 0, "the grid has no cell without nodata");
    if (spec->grid_derive || t->ntri > RF_GRID_KEEP_TRIANGLES)
        return 0;
    /* small enough to keep its triangles, derived once (holes zeroed, never read) */
    if (!(t->tri = calloc(t->ntri, sizeof *t->tri)))
        return rf_error_set(err, path, 0, 0, "out of memory for a %zu x %zu grid", nx, ny);
    for (size_t k = 0; k < t->ntri; k++)
        if (rf_grid_slot(t, k) >= 0)
            rf_grid_triangle(t, (int32_t)k, &t->tri[k]);
    return 0;
}

void rf_grid_triangle(const rf_terrain *t, int32_t idx, rf_triangle *out)
{
    rf_vec3 v[3];
    rf_grid_vertices(t, idx, v);
    /* as triangle_set, which the build found the triangle to have an area with */
    rf_vec3 cr = rf_v3_cross(rf_v3_sub(v[1], v[0]), rf_v3_sub(v[2], v[0]));
    triangle_fill(out, v[0], v[1], v[2], cr, rf_v3_norm(cr), rf_tri_zone(t, idx));
}

static int set_from_list(rf_terrain *t, const rf_tri_list *l, const int32_t *zone_of)
{
    t->tri = malloc((l->n ? l->n : 1) * sizeof *t->tri);
    if (!t->tri)
        return -1;
    size_t n = 0;
    for (size_t k = 0; k < l->n; k++)
        if (triangle_set(&t->tri[n], l->v[3 * k], l->v[3 * k + 1], l->v[3 * k + 2],
                         zone_of ? zone_of[k] : 0))
            n++;
    t->ntri = n;
    return 0;
}

static const char *base_name(const char *path, size_t *len)
{
    const char *slash = strrchr(path, '/');
    const char *b = slash ? slash + 1 : path;
    const char *dot = strrchr(b, '.');
    *len = dot && dot != b ? (size_t)(dot - b) : strlen(b);
    return b;
}

static int build_mesh(const rf_terrain_spec *spec, rf_terrain *t, rf_error *err)
{
    rf_tri_list l = {NULL, 0, 0};
    int32_t *zone_of = NULL;
    size_t zone_cap = 0;
    /* the zones that name a file, by its path (the first of them for each) */
    rf_names by_file;
    int oom = rf_names_init(&by_file, spec->nzones) != 0;
    for (size_t z = 0; z < spec->nzones && !oom; z++)
        if (spec->zones[z].file)
            rf_names_add(&by_file, spec->zones[z].file, z, &oom);
    if (oom) {
        rf_names_free(&by_file);
        return rf_error_set(err, NULL, 0, 0, "out of memory building the terrain");
    }
    for (size_t f = 0; f < spec->nfiles; f++) {
        const char *path = spec->files[f];
        size_t before = l.n;
        if (rf_mesh_read(path, spec->up, &l, err))
            goto fail;
        /* The file's zone: named and surfaced by its zone entry, else by the file. */
        rf_surface surface = spec->surface;
        size_t len;
        const char *name = base_name(path, &len);
        size_t z = rf_names_find(&by_file, path);
        if (z != RF_NAMES_ABSENT) {
            surface = spec->zones[z].surface;
            if (spec->zones[z].name) {
                name = spec->zones[z].name;
                len = strlen(name);
            }
        }
        int32_t zone = (int32_t)t->nzones;
        if (add_zone(t, name, len, surface)) {
            rf_error_set(err, path, 0, 0, "out of memory");
            goto fail;
        }
        if (rf_grow((void **)&zone_of, &zone_cap, l.n, sizeof *zone_of)) {
            rf_error_set(err, path, 0, 0, "out of memory");
            goto fail;
        }
        for (size_t k = before; k < l.n; k++)
            zone_of[k] = zone;
    }
    if (l.n > INT32_MAX) {
        rf_error_set(err, spec->files[0], 0, 0, "mesh too large (%zu triangles)", l.n);
        goto fail;
    }
    if (set_from_list(t, &l, zone_of)) {
        rf_error_set(err, spec->files[0], 0, 0, "out of memory");
        goto fail;
    }
    rf_tri_list_free(&l);
    free(zone_of);
    rf_names_free(&by_file);
    if (t->ntri == 0)
        return rf_error_set(err, spec->nfiles ? spec->files[0] : "", 0, 0,
                            "the terrain mesh has no triangle with an area");
    return 0;
fail:
    rf_tri_list_free(&l);
    free(zone_of);
    rf_names_free(&by_file);
    return -1;
}

static int build_profile(const rf_terrain_spec *spec, rf_terrain *t, rf_error *err)
{
    assert(spec->nprofile >= 2 && spec->width > 0);
    rf_tri_list l = {NULL, 0, 0};
    const double *p = spec->profile, w = spec->width;
    size_t nseg = spec->nprofile - 1;
    l.v = malloc(6 * nseg * sizeof *l.v);
    if (!l.v)
        return rf_error_set(err, NULL, 0, 0, "out of memory for the terrain profile");
    for (size_t k = 0; k < nseg; k++) {
        assert(p[2 * k + 2] > p[2 * k]);
        rf_vec3 s0 = rf_v3(p[2 * k], 0, p[2 * k + 1]), s1 = rf_v3(p[2 * k + 2], 0, p[2 * k + 3]);
        rf_vec3 n0 = rf_v3(p[2 * k], w, p[2 * k + 1]), n1 = rf_v3(p[2 * k + 2], w, p[2 * k + 3]);
        rf_vec3 *v = &l.v[6 * k];
        v[0] = s0, v[1] = s1, v[2] = n1;
        v[3] = s0, v[4] = n1, v[5] = n0;
    }
    l.n = l.cap = 2 * nseg;
    int rc = set_from_list(t, &l, NULL);
    rf_tri_list_free(&l);
    if (rc)
        return rf_error_set(err, NULL, 0, 0, "out of memory for the terrain profile");
    return 0;
}

int rf_terrain_build(const rf_terrain_spec *spec, rf_terrain *t, rf_error *err)
{
    memset(t, 0, sizeof *t);
    int32_t *poly_zone = NULL;
    if (add_zone(t, "default", strlen("default"), spec->surface))
        goto oom;
    int rc;
    switch (spec->source) {
    case RF_TERRAIN_DEM: rc = build_grid(spec, t, err); break;
    case RF_TERRAIN_MESH: rc = build_mesh(spec, t, err); break;
    case RF_TERRAIN_PROFILE: rc = build_profile(spec, t, err); break;
    default: rc = rf_error_set(err, NULL, 0, 0, "unknown terrain source %d", (int)spec->source);
    }
    if (rc)
        goto fail;

    if (spec->nzones) {
        poly_zone = malloc(spec->nzones * sizeof *poly_zone);
        if (!poly_zone)
            goto oom;
        int any = 0;
        for (size_t z = 0; z < spec->nzones; z++) {
            poly_zone[z] = -1;
            const rf_zone_spec *zs = &spec->zones[z];
            if (!zs->poly_xy)
                continue;
            poly_zone[z] = (int32_t)t->nzones;
            const char *name = zs->name ? zs->name : "";
            if (add_zone(t, name, strlen(name), zs->surface))
                goto oom;
            any = 1;
        }
        if (any && apply_polygon_zones(t, spec, poly_zone))
            goto oom;
        free(poly_zone);
        poly_zone = NULL;
    }
    compute_bounds(t);
    if (!t->is_grid && build_buckets(t))
        goto oom;
    return 0;
oom:
    rf_error_set(err, NULL, 0, 0, "out of memory building the terrain");
fail:
    free(poly_zone);
    rf_terrain_free(t);
    return -1;
}

void rf_hazard_grid(const rf_terrain *t, double cell, double *nx, double *ny)
{
    *nx = fmax(ceil((t->xmax - t->xmin) / cell), 1.0);
    *ny = fmax(ceil((t->ymax - t->ymin) / cell), 1.0);
}
