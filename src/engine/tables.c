/* tables.c - the tables of a terrain the contact search reads: boxes, edge lengths in
 * plan, and the edges that can be met first. */
#include "engine/tables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/geometry.h"

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

static inline float float_down(double x)
{
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}

static inline float float_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

/* Fills box (6 per triangle: xmin, xmax, ymin, ymax, zmin, zmax, rounded outwards). */
static void tri_box_build(const rf_terrain *t, float *box)
{
    for (size_t i = 0; i < t->ntri; i++, box += 6) {
        const rf_triangle *T = &t->tri[i];
        box[0] = float_down(dmin(T->a.x, dmin(T->b.x, T->c.x)));
        box[1] = float_up(dmax(T->a.x, dmax(T->b.x, T->c.x)));
        box[2] = float_down(dmin(T->a.y, dmin(T->b.y, T->c.y)));
        box[3] = float_up(dmax(T->a.y, dmax(T->b.y, T->c.y)));
        box[4] = float_down(dmin(T->a.z, dmin(T->b.z, T->c.z)));
        box[5] = float_up(dmax(T->a.z, dmax(T->b.z, T->c.z)));
    }
}

/* Fills hedge (3 per triangle: the horizontal lengths of edges ab, bc, ca). */
static void hedge_build(const rf_terrain *t, double *hedge)
{
    for (size_t i = 0; i < t->ntri; i++, hedge += 3) {
        const rf_triangle *T = &t->tri[i];
        rf_vec3 P[3] = {T->a, T->b, T->c};
        for (int k = 0; k < 3; k++)
            hedge[k] = hypot(P[(k + 1) % 3].x - P[k].x, P[(k + 1) % 3].y - P[k].y);
    }
}

/* ---- concave edges ---------------------------------------------------------------------
 *
 * The point of the terrain closest to a centre above it is never inside a strictly
 * concave edge (there the two faces rise from the edge: the centre would have to be
 * below them), so a rock from above meets such an edge only together with a face,
 * another edge or a vertex, which the search finds.  Its edge test is skipped.  Edges
 * on the border, shared by other than two triangles, or whose faces are within about
 * 1e-6 rad of one plane are always tested. */

/* 1 when the edge va-vb of triangle A is strictly concave with triangle B, whose
 * vertex off the edge is ob (oa: A's vertex off the edge). */
static int edge_concave(const rf_triangle *A, const rf_triangle *B, rf_vec3 va, rf_vec3 vb,
                        rf_vec3 oa, rf_vec3 ob)
{
    rf_vec3 e = rf_v3_sub(vb, va);
    double el = rf_v3_norm(e);
    if (!(el > 0))
        return 0;
    /* heights of each off vertex above the other face's plane, against its distance
     * from the edge line */
    double hb = rf_v3_dot(A->n, ob) - A->d, ha = rf_v3_dot(B->n, oa) - B->d;
    double db = rf_v3_norm(rf_v3_cross(e, rf_v3_sub(ob, va))) / el;
    double da = rf_v3_norm(rf_v3_cross(e, rf_v3_sub(oa, va))) / el;
    return hb > RF_CONCAVE_MIN_ANGLE * db && ha > RF_CONCAVE_MIN_ANGLE * da && db > 0 && da > 0;
}

/* Clears bit ka of triangle a's flags when its edge ka, shared with triangle b, is
 * strictly concave (b's own flag bit too, when b's flags are set). */
static void mark_pair(const rf_terrain *t, uint8_t *live, int32_t a, int ka, int32_t b)
{
    if (a < 0 || b < 0)
        return;
    const rf_triangle *A = &t->tri[a], *B = &t->tri[b];
    rf_vec3 va = rf_tri_vertex(A, ka), vb = rf_tri_vertex(A, ka + 1), oa = rf_tri_vertex(A, ka + 2);
    int kb = -1;
    for (int k = 0; k < 3; k++)
        if (rf_same_feature(A, ka | 4, B, k | 4))
            kb = k;
    if (kb < 0)
        return;
    rf_vec3 ob = rf_tri_vertex(B, kb + 2);
    if (edge_concave(A, B, va, vb, oa, ob))
        live[a] &= (uint8_t)~(1u << ka);
}

/* Grids: the flags of triangle idx, from its neighbours by cell arithmetic (cell (i, j)
 * holds triangle 0 (SW, SE, NE) and triangle 1 (SW, NE, NW); a is SW in both). */
static void grid_edge_live(const rf_terrain *t, uint8_t *live, int32_t idx)
{
    live[idx] = 8 | 7;
    size_t ncx = t->nx - 1, ncy = t->ny - 1;
    size_t n = (size_t)t->grid_node[idx] >> 1, j = n / t->nx, i = n - j * t->nx;
    const int32_t *g = t->grid_tri + 2 * (j * ncx + i);
    if ((t->grid_node[idx] & 1) == 0) {
        if (j > 0)
            mark_pair(t, live, idx, 0, t->grid_tri[2 * ((j - 1) * ncx + i) + 1]); /* south */
        if (i + 1 < ncx)
            mark_pair(t, live, idx, 1, g[3]);                                      /* east */
        mark_pair(t, live, idx, 2, g[1]);                                          /* diagonal */
    } else {
        mark_pair(t, live, idx, 0, g[0]);                                          /* diagonal */
        if (j + 1 < ncy)
            mark_pair(t, live, idx, 1, t->grid_tri[2 * ((j + 1) * ncx + i)]);     /* north */
        if (i > 0)
            mark_pair(t, live, idx, 2, g[-2]);                                     /* west */
    }
}

typedef struct edge_ref {
    uint64_t key;
    int32_t tri;
    int32_t k;
} edge_ref;

static int edge_ref_cmp(const void *x, const void *y)
{
    const edge_ref *a = x, *b = y;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    if (a->tri != b->tri)
        return a->tri < b->tri ? -1 : 1;
    return (a->k > b->k) - (a->k < b->k);
}

/* 1 when T's projection on the ground has an area (not a vertical face, nor one within
 * rounding of it: twice the area against the squares of its sides). */
static int covers_ground(const rf_triangle *T)
{
    double ux = T->b.x - T->a.x, uy = T->b.y - T->a.y;
    double wx = T->c.x - T->a.x, wy = T->c.y - T->a.y;
    return fabs(ux * wy - uy * wx) > RF_VERTICAL_EPS * (ux * ux + uy * uy + wx * wx + wy * wy);
}

/* Fills the live-edge flags of terrain t (one per triangle: bit k, edge k can be met
 * first; RF_EDGE_BORDER << k, edge k is a border in plan); 0, or -1 out of memory. */
static int edge_live_build(const rf_terrain *t, uint8_t *live)
{
    if (t->is_grid) {
        for (size_t i = 0; i < t->ntri; i++)
            grid_edge_live(t, live, (int32_t)i);
        return 0;
    }
    memset(live, 8 | 7, t->ntri ? t->ntri : 1);
    size_t n = 3 * t->ntri;
    edge_ref *r = malloc((n ? n : 1) * sizeof *r);
    if (!r)
        return -1;
    for (size_t i = 0; i < t->ntri; i++)
        for (int k = 0; k < 3; k++) {
            uint64_t ha = rf_point_hash(rf_tri_vertex(&t->tri[i], k)),
                     hb = rf_point_hash(rf_tri_vertex(&t->tri[i], k + 1));
            r[3 * i + (size_t)k] = (edge_ref){rf_mesh_edge_key(ha, hb), (int32_t)i, k};
        }
    qsort(r, n, sizeof *r, edge_ref_cmp);
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && r[j].key == r[i].key)
            j++;
        if (j - i == 2) {
            mark_pair(t, live, r[i].tri, r[i].k, r[i + 1].tri);
            mark_pair(t, live, r[i + 1].tri, r[i + 1].k, r[i].tri);
        }
        /* a border in plan: one holder covers ground (vertical ones, a skirt under a
         * rim, do not) */
        size_t flat = 0, last = i;
        for (size_t k = i; k < j; k++)
            if (covers_ground(&t->tri[r[k].tri]))
                flat++, last = k;
        if (flat == 1)
            live[r[last].tri] |= (uint8_t)(RF_EDGE_BORDER << r[last].k);
        i = j;
    }
    free(r);
    return 0;
}

/* 1 when terrain t has holes: a nodata triangle of a grid; a border edge in plan of a
 * mesh (RF_EDGE_BORDER) whose ends do not both lie on one side of the bounding box. */
static int terrain_has_gaps(const rf_terrain *t, const uint8_t *live)
{
    if (t->is_grid) {
        size_t ncell = 2 * (t->nx - 1) * (t->ny - 1);
        for (size_t i = 0; i < ncell; i++)
            if (t->grid_tri[i] < 0)
                return 1;
        return 0;
    }
    for (size_t i = 0; i < t->ntri; i++) {
        unsigned border = live[i] / RF_EDGE_BORDER;
        for (int k = 0; k < 3; k++) {
            if (!(border >> k & 1))
                continue;
            rf_vec3 A = rf_tri_vertex(&t->tri[i], k), B = rf_tri_vertex(&t->tri[i], k + 1);
            int side = (A.x == t->xmin && B.x == t->xmin) || (A.x == t->xmax && B.x == t->xmax) ||
                       (A.y == t->ymin && B.y == t->ymin) || (A.y == t->ymax && B.y == t->ymax);
            if (!side)
                return 1;
        }
    }
    return 0;
}

rf_terrain_tables *rf_terrain_tables_build(const rf_terrain *t)
{
    rf_terrain_tables *tt = calloc(1, sizeof *tt);
    if (!tt)
        return NULL;
    size_t n = t->ntri ? t->ntri : 1;
    tt->terrain = t;
    tt->edge_live = malloc(n);
    tt->tri_box = malloc(6 * n * sizeof *tt->tri_box);
    tt->hedge = malloc(3 * n * sizeof *tt->hedge);
    if (!tt->edge_live || !tt->tri_box || !tt->hedge || edge_live_build(t, tt->edge_live)) {
        rf_terrain_tables_free(tt);
        return NULL;
    }
    tri_box_build(t, tt->tri_box);
    hedge_build(t, tt->hedge);
    tt->has_gaps = terrain_has_gaps(t, tt->edge_live);
    tt->nz_min = 1.0;
    for (size_t k = 0; k < t->ntri; k++)
        tt->nz_min = fmin(tt->nz_min, t->tri[k].n.z);
    tt->nz_min = fmax(tt->nz_min, RF_NZ_MIN);
    return tt;
}

void rf_terrain_tables_free(rf_terrain_tables *tt)
{
    if (!tt)
        return;
    free(tt->edge_live);
    free(tt->tri_box);
    free(tt->hedge);
    free(tt);
}
