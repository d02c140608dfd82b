/* tables.c - the tables of a terrain the contact search reads: boxes, edge lengths in
 * plan, and the edges that can be met first. */
#include "engine/tables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/geometry.h"

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* nextafterf(f, -INFINITY) and nextafterf(f, INFINITY) of a float f that is not NaN and
 * not already the end of that way, by its bits (IEEE 754 binary32: the next float away
 * from zero is the next integer of the same sign; zero steps to the smallest
 * subnormal). */
static inline float float_step(float f, int up)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    if ((u & 0x7fffffffu) == 0)
        u = up ? 1u : 0x80000001u;
    else if ((u >> 31) == (up ? 0u : 1u))
        u++; /* away from zero */
    else
        u--; /* towards zero */
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline float float_down(double x)
{
    float f = (float)x;
    return (double)f > x ? float_step(f, 0) : f;
}

static inline float float_up(double x)
{
    float f = (float)x;
    return (double)f < x ? float_step(f, 1) : f;
}

/* The box of vertices P (xmin, xmax, ymin, ymax, zmin, zmax, rounded outwards). */
static void box_of(const rf_vec3 P[3], float *box)
{
    box[0] = float_down(dmin(P[0].x, dmin(P[1].x, P[2].x)));
    box[1] = float_up(dmax(P[0].x, dmax(P[1].x, P[2].x)));
    box[2] = float_down(dmin(P[0].y, dmin(P[1].y, P[2].y)));
    box[3] = float_up(dmax(P[0].y, dmax(P[1].y, P[2].y)));
    box[4] = float_down(dmin(P[0].z, dmin(P[1].z, P[2].z)));
    box[5] = float_up(dmax(P[0].z, dmax(P[1].z, P[2].z)));
}

/* The horizontal lengths of the edges of vertices P: ab, bc, ca. */
static void hedge_of(const rf_vec3 P[3], double *hedge)
{
    for (int k = 0; k < 3; k++)
        hedge[k] = hypot(P[(k + 1) % 3].x - P[k].x, P[(k + 1) % 3].y - P[k].y);
}

void rf_grid_box(const rf_terrain *t, int32_t idx, float box[6])
{
    rf_vec3 P[3];
    rf_grid_vertices(t, idx, P);
    box_of(P, box);
}

void rf_grid_hedge(const rf_terrain *t, int32_t idx, double hedge[3])
{
    rf_vec3 P[3];
    rf_grid_vertices(t, idx, P);
    hedge_of(P, hedge);
}

/* Fills box (6 per triangle) and hedge (3 per triangle) of a mesh. */
static void box_hedge_build(const rf_terrain *t, float *box, double *hedge)
{
    for (size_t i = 0; i < t->ntri; i++, box += 6, hedge += 3) {
        const rf_triangle *T = &t->tri[i];
        rf_vec3 P[3] = {T->a, T->b, T->c};
        box_of(P, box);
        hedge_of(P, hedge);
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

/* 1 when edge ka of triangle A, shared with triangle B, is strictly concave (NULL: no
 * neighbour). */
static int pair_concave(const rf_triangle *A, int ka, const rf_triangle *B)
{
    if (!A || !B)
        return 0;
    rf_vec3 va = rf_tri_vertex(A, ka), vb = rf_tri_vertex(A, ka + 1), oa = rf_tri_vertex(A, ka + 2);
    int kb = -1;
    for (int k = 0; k < 3; k++)
        if (rf_same_feature(A, ka | 4, B, k | 4))
            kb = k;
    if (kb < 0)
        return 0;
    rf_vec3 ob = rf_tri_vertex(B, kb + 2);
    return edge_concave(A, B, va, vb, oa, ob);
}

/* Meshes: clears bit ka of triangle a's flags when its edge ka, shared with triangle b,
 * is strictly concave. */
static void mark_pair(const rf_terrain *t, uint8_t *live, int32_t a, int ka, int32_t b)
{
    if (a >= 0 && b >= 0 && pair_concave(&t->tri[a], ka, &t->tri[b]))
        live[a] &= (uint8_t)~(1u << ka);
}

/* Grids: the triangles of the cells c0 .. c1 - 1 of cell row j (2 per cell, NULL for a
 * hole) derived into row, at 2 (i - c0) + k. */
static void grid_row(const rf_terrain *t, size_t j, size_t c0, size_t c1, rf_triangle *row,
                     const rf_triangle **at)
{
    size_t ncx = t->nx - 1;
    for (size_t s = 2 * c0; s < 2 * c1; s++) {
        int32_t idx = rf_grid_slot(t, 2 * j * ncx + s);
        at[s - 2 * c0] = NULL;
        if (idx >= 0) {
            rf_grid_triangle(t, idx, &row[s - 2 * c0]);
            at[s - 2 * c0] = &row[s - 2 * c0];
        }
    }
}

/* Grids: the live bits (0-2) of triangle k of cell (i, j) of row `cur`, from its
 * neighbours in rows `south`, `cur` and `north` (NULL beyond the grid), which hold the
 * cell's triangles at 2 l + k (l = i - the strip's first cell; the strip holds the cells
 * beside it).  Cell (i, j) holds triangle 0 (SW, SE, NE) and triangle 1 (SW, NE, NW); a
 * is SW in both. */
static unsigned grid_edge_live(size_t ncx, size_t i, size_t l, int k,
                               const rf_triangle *const *south, const rf_triangle *const *cur,
                               const rf_triangle *const *north)
{
    const rf_triangle *A = cur[2 * l + (size_t)k];
    int concave[3];
    if (k == 0) {
        concave[0] = south && pair_concave(A, 0, south[2 * l + 1]);     /* south */
        concave[1] = i + 1 < ncx && pair_concave(A, 1, cur[2 * l + 3]); /* east */
        concave[2] = pair_concave(A, 2, cur[2 * l + 1]);                /* diagonal */
    } else {
        concave[0] = pair_concave(A, 0, cur[2 * l]);                    /* diagonal */
        concave[1] = north && pair_concave(A, 1, north[2 * l]);         /* north */
        concave[2] = i > 0 && pair_concave(A, 2, cur[2 * l - 2]);       /* west */
    }
    unsigned live = 7;
    for (int e = 0; e < 3; e++)
        if (concave[e])
            live &= ~(1u << e);
    return live;
}

/* Columns of cells per strip of cell_live_build: its rows of derived triangles take
 * about 3 x 2 x (LIVE_STRIP + 2) x 120 bytes whatever the grid's width. */
#define LIVE_STRIP 1024

/* Grids: the live bits of both triangles of every cell (rf_edge_live), and the
 * smallest n.z of the faces, in strips of LIVE_STRIP columns of cells, three rows of
 * derived triangles at a time (the strip's cells and one beyond each side); 0, or -1
 * out of memory. */
static int cell_live_build(const rf_terrain *t, uint8_t *cell_live, double *nz_min)
{
    size_t ncx = t->nx - 1, ncy = t->ny - 1, w = 2 * (LIVE_STRIP + 2);
    rf_triangle *tri = malloc(3 * w * sizeof *tri);
    const rf_triangle **at = malloc(3 * w * sizeof *at);
    if (!tri || !at) {
        free(tri);
        free(at);
        return -1;
    }
    for (size_t i0 = 0; i0 < ncx; i0 += LIVE_STRIP) {
        size_t i1 = i0 + LIVE_STRIP < ncx ? i0 + LIVE_STRIP : ncx;
        size_t c0 = i0 > 0 ? i0 - 1 : 0, c1 = i1 < ncx ? i1 + 1 : ncx;
        /* row j's triangles are in slot j % 3 */
        grid_row(t, 0, c0, c1, tri, at);
        for (size_t j = 0; j < ncy; j++) {
            if (j + 1 < ncy)
                grid_row(t, j + 1, c0, c1, tri + (j + 1) % 3 * w, at + (j + 1) % 3 * w);
            const rf_triangle *const *cur = at + j % 3 * w;
            const rf_triangle *const *south = j > 0 ? at + (j + 2) % 3 * w : NULL;
            const rf_triangle *const *north = j + 1 < ncy ? at + (j + 1) % 3 * w : NULL;
            for (size_t i = i0; i < i1; i++) {
                unsigned bits = 0;
                for (int k = 0; k < 2; k++) {
                    const rf_triangle *A = cur[2 * (i - c0) + (size_t)k];
                    if (!A) {
                        bits |= 7u << (3 * k);
                        continue;
                    }
                    bits |= grid_edge_live(ncx, i, i - c0, k, south, cur, north) << (3 * k);
                    *nz_min = fmin(*nz_min, A->n.z);
                }
                cell_live[j * ncx + i] = (uint8_t)bits;
            }
        }
    }
    free(tri);
    free(at);
    return 0;
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
    if (t->is_grid)
        return t->grid_hole != NULL;
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
    tt->nz_min = 1.0;
    if (t->is_grid) {
        if (!(tt->cell_live = malloc(n / 2 + 1)) || cell_live_build(t, tt->cell_live, &tt->nz_min)) {
            rf_terrain_tables_free(tt);
            return NULL;
        }
        if (t->tri) { /* a grid that keeps its triangles keeps their boxes and lengths */
            tt->tri_box = malloc(6 * n * sizeof *tt->tri_box);
            tt->hedge = malloc(3 * n * sizeof *tt->hedge);
            if (!tt->tri_box || !tt->hedge) {
                rf_terrain_tables_free(tt);
                return NULL;
            }
            box_hedge_build(t, tt->tri_box, tt->hedge);
        }
    } else {
        tt->edge_live = malloc(n);
        tt->tri_box = malloc(6 * n * sizeof *tt->tri_box);
        tt->hedge = malloc(3 * n * sizeof *tt->hedge);
        if (!tt->edge_live || !tt->tri_box || !tt->hedge || edge_live_build(t, tt->edge_live)) {
            rf_terrain_tables_free(tt);
            return NULL;
        }
        box_hedge_build(t, tt->tri_box, tt->hedge);
        for (size_t k = 0; k < t->ntri; k++)
            tt->nz_min = fmin(tt->nz_min, t->tri[k].n.z);
    }
    tt->has_gaps = terrain_has_gaps(t, tt->edge_live);
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
    free(tt->cell_live);
    free(tt);
}
