/* contact.c - the earliest contact of the rock with the terrain along an arc.
 *
 * The centre moves on p(t) = p + v t + a t^2 / 2.  Against a face plane the signed
 * distance minus the contact radius is a quadratic in t; against an edge line or a
 * vertex the squared distance minus rho^2 is a quartic.  The triangles near the path
 * are gathered piece by piece along it (the candidate set stays small however long
 * the arc; on a grid, a centre's or a point's flight walks the cells under its line),
 * culled by height and by the time window in which the face plane is within reach,
 * and the earliest entering root over all of them wins.  No stepping: a contact
 * is found whatever the speed. */
#include "engine/contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/contact_tri.h"
#include "engine/geometry.h"
#include "engine/tables.h"


static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* Grid terrains: both triangles of each cell the box touches (a few more than the box
 * holds, none missing), by index arithmetic on the documented layout. */
static size_t gather_grid(rf_motion *m, double xmin, double ymin, double xmax, double ymax)
{
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->cfg.terrain;
    size_t r[4];
    if (!rf_cell_range(xmin, xmax, t->x0, t->cell, t->nx - 1, &r[0], &r[1]) ||
        !rf_cell_range(ymin, ymax, t->y0, t->cell, t->ny - 1, &r[2], &r[3]))
        return 0;
    size_t need = 2 * (r[1] - r[0] + 1) * (r[3] - r[2] + 1);
    if (rf_grow((void **)&ws->cand, &ws->cap, need, sizeof *ws->cand))
        return 0;
    size_t n = 0, row = t->nx - 1;
    for (size_t j = r[2]; j <= r[3]; j++) {
        size_t g = 2 * (j * row + r[0]);
        for (size_t i = r[0]; i <= r[1]; i++, g += 2) {
            if (rf_grid_slot(t, g) >= 0)
                ws->cand[n++] = (int32_t)g;
            if (rf_grid_slot(t, g + 1) >= 0)
                ws->cand[n++] = (int32_t)g + 1;
        }
    }
    return n;
}

size_t rf_gather(rf_motion *m, double xmin, double ymin, double xmax, double ymax)
{
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->cfg.terrain;
    if (t->is_grid)
        return gather_grid(m, xmin, ymin, xmax, ymax);
    for (;;) {
        size_t n = rf_terrain_query_box(t, xmin, ymin, xmax, ymax, ws->cand, ws->cap,
                                        ws->stamp, &ws->epoch);
        if (n <= ws->cap)
            return n;
        /* Rare: a box larger than any before; grow once and query again. */
        if (rf_grow((void **)&ws->cand, &ws->cap, n, sizeof *ws->cand))
            return ws->cap;
    }
}

/* ---- reach bounds --------------------------------------------------------------------
 *
 * The reach bound of a plane (normal n, offset d) over an arc: a sphere whose centre c
 * is g above the plane's offset (g = n.c - d - rho) touches a point X of height h =
 * n.X - d above the plane, |X - c| <= R0 (R0 = rho and a slack), only when its contact
 * point q = c - rho n is near X: |X - q|^2 = |X - c|^2 + 2 rho (h - g) - rho^2 <= R0^2 -
 * rho^2 + 2 rho (h - g).  Over a triangle whose highest vertex is H above the plane and
 * a stretch of the arc on which g stays above gmin, X lies within sqrt(R0^2 - rho^2 +
 * 2 rho (H - gmin)) of the stretch's points q: a face that rises a little above a
 * support plane is met only near the path (within sqrt(2 rho H)), not anywhere within
 * rho of it, and so is a face near the plane of the face a short hop flew off. */
struct rf_reach_bound {
    rf_vec3 n, sh; /* the plane's normal; -rho n, from a centre to its point q */
    double d;      /* the plane's offset */
    double g[3];   /* g over the arc: g[0] + g[1] t + g[2] t^2 */
    rf_vec3 qlo, qhi; /* a surface search: the box of the arc's points q over [0, T] */
    double gmin;      /* ... and the least g there */
};
typedef struct rf_reach_bound reach_bound;

/* The reach bound of the plane (n, d) along arc; over [0, T] when lo, hi (the arc's box
 * over it) are given. */
static void reach_bound_set(rf_vec3 n, double d, double rho, const rf_arc *arc, double T,
                            const rf_vec3 *lo, const rf_vec3 *hi, reach_bound *rb)
{
    rb->n = n, rb->d = d;
    rb->sh = rf_v3_scale(n, -rho);
    rb->g[0] = rf_v3_dot(n, arc->p) - d - rho;
    rb->g[1] = rf_v3_dot(n, arc->v);
    rb->g[2] = 0.5 * rf_v3_dot(n, arc->a);
    if (lo) {
        rb->qlo = rf_v3_add(*lo, rb->sh), rb->qhi = rf_v3_add(*hi, rb->sh);
        double gmax;
        rf_quadratic_range(rb->g, 0.0, T, &rb->gmin, &gmax);
    }
}

/* The height of T's highest vertex above the bound's plane. */
static double bound_height(const reach_bound *rb, const rf_triangle *T)
{
    rf_vec3 n = rb->n;
    double d = rb->d;
    return dmax(rf_v3_dot(n, T->a) - d, dmax(rf_v3_dot(n, T->b) - d, rf_v3_dot(n, T->c) - d));
}

/* 1 when every point of a triangle whose box is `box` and whose highest vertex is H
 * above the bound's plane is farther than the bound from the box qlo, qhi of the
 * stretch's points q, on which g stays above gmin (r0sq = R0^2): no point of it comes
 * within R0 of the centre there. */
static int beyond_bound(double rho, double r0sq, const float *box, double H, double gmin,
                        rf_vec3 qlo, rf_vec3 qhi)
{
    double r2 = r0sq - rho * rho + 2.0 * rho * (H - gmin);
    if (!(r2 >= 0.0))
        return 1;
    double r = sqrt(r2);
    return box[1] < qlo.x - r || box[0] > qhi.x + r || box[3] < qlo.y - r || box[2] > qhi.y + r ||
           box[5] < qlo.z - r || box[4] > qhi.z + r;
}

/* R0 of the reach bounds: rho and a slack above every tolerance a contact is taken
 * within (the touch band; a contact point outside its face by RF_RADIUS_REL_TOL rho). */
static double bound_r0(const rf_motion *m)
{
    return m->cfg.rho + RF_TOUCH_BAND * m->cfg.tol_len + RF_RADIUS_REL_TOL * m->cfg.rho;
}

/* 1 when T is out of reach of the centre on the arc by one support plane (the reach
 * bounds rb of s->sp's planes over the arc): every vertex of T on or below it (T lies in
 * the plane's lower half-space, which the sphere, touching the plane from above, never
 * enters; vertices below different planes of a crease are not enough, a point between
 * them can lie above both), or beyond the plane's reach bound. */
static int beyond_support_reach(const rf_search *s, const reach_bound *rb, const float *box,
                                const rf_triangle *T, double r0sq)
{
    for (int k = 0; k < s->sp.n; k++) {
        double H = bound_height(&rb[k], T);
        if (H <= s->sp.tol ||
            beyond_bound(s->m->cfg.rho, r0sq, box, H, rb[k].gmin, rb[k].qlo, rb[k].qhi))
            return 1;
    }
    return 0;
}

/* A flight off a face (s->flight_bound): 1 when triangle idx, T, is beyond the reach
 * bound of that face's plane over [tl, th], the window in which it can be within reach. */
static int beyond_flight_reach(const rf_search *s, int32_t idx, const rf_triangle *T, double tl,
                               double th)
{
    const reach_bound *rb = s->flight_bound;
    double gmin, gmax;
    rf_quadratic_range(rb->g, tl, th, &gmin, &gmax);
    double H = bound_height(rb, T), rho = s->m->cfg.rho;
    if (!(s->r0sq - rho * rho + 2.0 * rho * (H - gmin) >= 0.0))
        return 1;
    rf_vec3 lo, hi;
    rf_arc_box(s->arc, tl, th, &lo, &hi);
    float box[6];
    return beyond_bound(rho, s->r0sq, rf_tri_box(s->m->ws, idx, box), H, gmin,
                        rf_v3_add(lo, rb->sh), rf_v3_add(hi, rb->sh));
}

/* ---- the triangles a flight's search has tested ----------------------------------------- */

static inline size_t tested_slot(int32_t tri, size_t cap)
{
    return (size_t)(((uint64_t)(uint32_t)tri * 0x9E3779B97F4A7C15ULL) >> 40) & (cap - 1);
}

/* Empties the set. */
static void tested_clear(rf_workspace *ws)
{
    ws->tested_n = 0;
    if (++ws->tested_gen == 0) {
        memset(ws->tested, 0, ws->tested_cap * sizeof *ws->tested);
        if (ws->tested_mark)
            memset(ws->tested_mark, 0, ws->tables->terrain->ntri * sizeof *ws->tested_mark);
        ws->tested_gen = 1;
    }
}

/* Doubles the set's slots, keeping its members; -1 out of memory. */
static int tested_grow(rf_workspace *ws)
{
    size_t cap = 2 * ws->tested_cap;
    rf_tested_slot *slots = calloc(cap, sizeof *slots);
    if (!slots)
        return -1;
    for (size_t k = 0; k < ws->tested_cap; k++) {
        if (ws->tested[k].gen != ws->tested_gen)
            continue;
        size_t h = tested_slot(ws->tested[k].tri, cap);
        while (slots[h].gen == 1)
            h = (h + 1) & (cap - 1);
        slots[h] = (rf_tested_slot){ws->tested[k].tri, 1};
    }
    free(ws->tested);
    ws->tested = slots;
    ws->tested_cap = cap;
    ws->tested_gen = 1;
    return 0;
}

/* 1 when triangle tri was not in the set (it is now); 0 when it was. */
static inline int tested_add(rf_workspace *ws, int32_t tri)
{
    if (ws->tested_mark) {
        if (ws->tested_mark[tri] == ws->tested_gen)
            return 0;
        ws->tested_mark[tri] = ws->tested_gen;
        return 1;
    }
    size_t mask = ws->tested_cap - 1, h = tested_slot(tri, ws->tested_cap);
    for (; ws->tested[h].gen == ws->tested_gen; h = (h + 1) & mask)
        if (ws->tested[h].tri == tri)
            return 0;
    if (2 * (ws->tested_n + 1) > ws->tested_cap) {
        if (tested_grow(ws))
            return 1; /* out of memory: tested again, as without the set */
        mask = ws->tested_cap - 1;
        for (h = tested_slot(tri, ws->tested_cap); ws->tested[h].gen == ws->tested_gen;
             h = (h + 1) & mask)
            ;
    }
    ws->tested[h] = (rf_tested_slot){tri, ws->tested_gen};
    ws->tested_n++;
    return 1;
}

/* ---- shared edges and vertices --------------------------------------------------------
 *
 * Neighbouring triangles share edges and vertices (on a grid an edge belongs to two
 * triangles and a vertex to up to six).  Each distinct feature is tested once per
 * search, when the first pending triangle holding it asks, from that triangle's window
 * start: a sphere touching a feature is within reach of the plane of every triangle
 * holding it (the feature lies in each plane), so any holder's plane entry bounds the
 * contact time from below. */

/* Keys of the three edges (k: vertex k to k + 1) and three vertices of triangle idx.
 * Grids: 4 node + type, from the triangle's SW node n (types 0 east, 1 north, 2
 * north-east from that node, 3 the node itself); cell triangle 0 is (SW, SE, NE), 1 is
 * (SW, NE, NW).  Meshes: hashes of the coordinates (vertex keys even, edge keys odd),
 * confirmed by comparing the coordinates. */
static void feature_keys(const rf_terrain *t, int32_t idx, uint64_t ek[3], uint64_t vk[3])
{
    if (t->is_grid) {
        uint64_t n = (uint64_t)rf_grid_node(t, idx) >> 1, nx = t->nx;
        if ((idx & 1) == 0) {
            vk[0] = 4 * n + 3, vk[1] = 4 * (n + 1) + 3, vk[2] = 4 * (n + nx + 1) + 3;
            ek[0] = 4 * n, ek[1] = 4 * (n + 1) + 1, ek[2] = 4 * n + 2;
        } else {
            vk[0] = 4 * n + 3, vk[1] = 4 * (n + nx + 1) + 3, vk[2] = 4 * (n + nx) + 3;
            ek[0] = 4 * n + 2, ek[1] = 4 * (n + nx), ek[2] = 4 * n + 1;
        }
        return;
    }
    const rf_triangle *T = &t->tri[idx];
    uint64_t h[3] = {rf_point_hash(T->a), rf_point_hash(T->b), rf_point_hash(T->c)};
    for (int k = 0; k < 3; k++) {
        vk[k] = h[k] << 1;
        ek[k] = rf_mesh_edge_key(h[k], h[(k + 1) % 3]) | 1ULL;
    }
}

static inline unsigned slot_of(uint64_t key)
{
    return (unsigned)((key * 0x9E3779B97F4A7C15ULL) >> 40) & (RF_FEAT_SLOTS - 1);
}

/* 1 the first time the feature with this key (feature k of triangle idx: vertex k, or
 * edge k & 3 when k & 4) is met in the current generation of the table. */
static int feat_first(rf_workspace *ws, uint64_t key, int32_t idx, int k)
{
    const rf_terrain *t = ws->tables->terrain;
    for (unsigned h = slot_of(key);; h = (h + 1) & (RF_FEAT_SLOTS - 1)) {
        rf_feat_slot *sl = &ws->feat[h];
        if (sl->gen != ws->feat_gen) {
            sl->gen = ws->feat_gen;
            sl->key = key;
            sl->tri = idx;
            sl->k = k;
            ws->feat_used++;
            return 1;
        }
        if (sl->key == key && (t->is_grid || rf_same_feature(&t->tri[sl->tri], sl->k, &t->tri[idx], k)))
            return 0;
    }
}

/* A flight (s->line): narrows [*w0, *w1] to the times when the centre is horizontally
 * within reach of the feature with ends q[0 .. nq-1] (a vertex or an edge); 0 when it
 * is never within reach of it (also not in height: the feature lower than the
 * centre's lowest point then minus the reach). */
static int line_window(const rf_search *s, const rf_vec3 *q, int nq, double reach, double *w0,
                       double *w1)
{
    double pmin = INFINITY, pmax = -INFINITY, smin = INFINITY, smax = -INFINITY, zt = -INFINITY;
    for (int i = 0; i < nq; i++) {
        double pp = s->ux * q[i].y - s->uy * q[i].x - s->d0;
        double ss = s->ux * q[i].x + s->uy * q[i].y - s->s0;
        pmin = dmin(pmin, pp), pmax = dmax(pmax, pp);
        smin = dmin(smin, ss), smax = dmax(smax, ss);
        zt = dmax(zt, q[i].z);
    }
    if (pmin > reach || pmax < -reach)
        return 0;
    double tl = (smin - reach) / s->vh, th = (smax + reach) / s->vh;
    if (tl > *w0)
        *w0 = tl;
    if (th < *w1)
        *w1 = th;
    if (!(*w0 <= *w1))
        return 0;
    const rf_arc *arc = s->arc;
    double za = arc->p.z + *w0 * (arc->v.z + 0.5 * *w0 * arc->a.z);
    double zb = arc->p.z + *w1 * (arc->v.z + 0.5 * *w1 * arc->a.z);
    return zt >= dmin(za, zb) - reach;
}

/* Starts a new generation of the feature table (all slots free). */
static void feat_reset(rf_workspace *ws)
{
    if (++ws->feat_gen == 0) {
        for (size_t i = 0; i < RF_FEAT_SLOTS; i++)
            ws->feat[i].gen = 0;
        ws->feat_gen = 1;
    }
    ws->feat_used = 0;
}

/* Edge or vertex (the ends q[0 .. nq-1]) of triangle idx over [w0, min(tb, best)]. */
static void test_feature(rf_search *s, int32_t idx, int k, const rf_vec3 *q, int nq, double w0,
                         double tb, rf_vec3 blo, rf_vec3 bhi)
{
    double w1 = tb < s->best ? tb : s->best;
    if (!(w0 < s->best))
        return;
    rf_vec3 lo = blo, hi = bhi;
    if (s->line) {
        if (!line_window(s, q, nq, s->reach, &w0, &w1))
            return;
        rf_arc_box(s->arc, w0, w1, &lo, &hi);
    }
    if (nq == 2)
        rf_test_edge(s, idx, k, q[0], q[1], w0, w1, lo, hi);
    else
        rf_test_vertex(s, idx, k, q[0], w0, w1, lo, hi);
}

/* The edges and vertices of the pending triangles, each distinct one once per
 * generation of the feature table (a flight's pieces share one), up to tb. */
static void test_features(rf_search *s, size_t npend, double tb, rf_vec3 blo, rf_vec3 bhi)
{
    rf_motion *m = s->m;
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->cfg.terrain;
    for (size_t p = 0; p < npend; p++) {
        double w0 = ws->pend_w0[p];
        if (!(w0 < s->best))
            continue;
        int32_t idx = ws->pend_idx[p];
        const rf_triangle *T = RF_FACE(m, idx);
        uint64_t ek[3], vk[3];
        feature_keys(t, idx, ek, vk);
        int xv[3] = {-1, -1, -1}; /* vertex_out of vertex k (-1: not known yet) */
        unsigned live = rf_edge_live(ws, idx);
        for (int k = 0; k < 3; k++) {
            int k1 = (k + 1) % 3;
            rf_vec3 q[2] = {rf_tri_vertex(T, k), rf_tri_vertex(T, k1)};
            if ((live >> k & 1) && feat_first(ws, ek[k], idx, k | 4)) {
                for (int i = 0; i < 2; i++) {
                    int v = i ? k1 : k;
                    if (xv[v] < 0)
                        xv[v] = (int)rf_vertex_out(&s->sp, q[i]);
                }
                if (!(xv[k] & xv[k1]))
                    test_feature(s, idx, k, q, 2, w0, tb, blo, bhi);
            }
            if (feat_first(ws, vk[k], idx, k)) {
                if (xv[k] < 0)
                    xv[k] = (int)rf_vertex_out(&s->sp, q[0]);
                if (!xv[k])
                    test_feature(s, idx, k, q, 1, w0, tb, blo, bhi);
            }
        }
    }
}

/* How far from the centre a feature can be met: the contact radius and four length
 * tolerances. */
static double sphere_reach(const rf_motion *m)
{
    return m->cfg.rho + RF_REACH_TOLS * m->cfg.tol_len;
}

/* How far from a flight's horizontal line a triangle can be met: the reach of the
 * sphere, or in centre mode (the face under the centre) the length tolerance. */
static double line_reach(const rf_motion *m)
{
    return m->cfg.centre ? RF_REACH_TOLS * m->cfg.tol_len : sphere_reach(m);
}

/* Room for the pending triangles of n candidates. */
static void pend_reserve(rf_workspace *ws, size_t n)
{
    /* both arrays grow alike from the same capacity */
    size_t ci = ws->pend_cap, cw = ws->pend_cap;
    if (rf_grow((void **)&ws->pend_idx, &ci, n, sizeof *ws->pend_idx) == 0 &&
        rf_grow((void **)&ws->pend_w0, &cw, n, sizeof *ws->pend_w0) == 0)
        ws->pend_cap = ci;
}

/* Triangle idx's edges and vertices to test from w0 on: kept pending, or tested now
 * (up to t1) when the pending list is full. */
static void pend_push(rf_search *s, int32_t idx, double w0, double t1, size_t *npend)
{
    rf_workspace *ws = s->m->ws;
    if (*npend < ws->pend_cap) {
        ws->pend_idx[*npend] = idx;
        ws->pend_w0[*npend] = w0;
        (*npend)++;
    } else {
        rf_test_edges(s, idx, w0, t1);
    }
}

/* The face flown off (or, in a surface segment, the face just left), triangle idx,
 * over [t0, t1]: for a sphere, not its face, but its edges and vertices (pending up to
 * tend), which the rock can come down on (one on the grid's border has no other
 * holder; in a surface segment, a path on the other face of a crease that ended can
 * curve back into one); for a centre, the face once it moves over its column again
 * (off a vertex, it can clip a corner of the next column first). */
static void test_left(rf_search *s, int32_t idx, double t0, double t1, double tend, size_t *npend)
{
    const rf_motion *m = s->m;
    if (m->cfg.centre || m->cfg.point)
        rf_test_centre(s, idx, t0, t1, 1);
    else
        pend_push(s, idx, t0, tend, npend);
}

/* The edges and vertices of the pending triangles up to tb (lo, hi: the arc's box,
 * unused in a flight): through the table of shared features when it stays at most a
 * third full (a flight's pieces share one table, other searches start afresh),
 * otherwise triangle by triangle. */
static void test_pending(rf_search *s, size_t npend, double tb, rf_vec3 lo, rf_vec3 hi)
{
    rf_workspace *ws = s->m->ws;
    if (npend == 0)
        return;
    size_t p0 = 0;
    if (npend * 6 <= RF_FEAT_SLOTS / 3) {
        if (!s->line || ws->feat_used + npend * 6 > RF_FEAT_SLOTS / 3)
            feat_reset(ws);
        test_features(s, npend, tb, lo, hi);
        p0 = npend;
    }
    for (size_t k = p0; k < npend; k++)
        if (ws->pend_w0[k] < s->best)
            rf_test_edges(s, ws->pend_idx[k], ws->pend_w0[k], tb);
}

/* A flight (s->line) over [0, T]: candidate idx, unless already tested in this search,
 * over the whole time it is within reach of the centre (so once per search); its face
 * now, its edges and vertices pending when its plane is reached before the earliest
 * contact found. */
static void line_candidate(rf_search *s, int32_t idx, double T, size_t *npend)
{
    rf_motion *m = s->m;
    rf_workspace *ws = m->ws;
    if (!tested_add(ws, idx))
        return;
    const rf_triangle *Tr = RF_CORNERS(m, idx);
    double reach = s->reach, hr = s->hr;
    /* a point of the triangle within reach of the centre: within reach of the
     * horizontal line, the centre horizontally within reach of it meanwhile, and
     * not lower than the centre's lowest height then minus the reach */
    double pa = s->ux * Tr->a.y - s->uy * Tr->a.x - s->d0;
    double pb = s->ux * Tr->b.y - s->uy * Tr->b.x - s->d0;
    double pc = s->ux * Tr->c.y - s->uy * Tr->c.x - s->d0;
    if ((pa > hr && pb > hr && pc > hr) || (pa < -hr && pb < -hr && pc < -hr))
        return;
    double qa = s->ux * Tr->a.x + s->uy * Tr->a.y - s->s0;
    double qb = s->ux * Tr->b.x + s->uy * Tr->b.y - s->s0;
    double qc = s->ux * Tr->c.x + s->uy * Tr->c.y - s->s0;
    double tl = (dmin(qa, dmin(qb, qc)) - hr) / s->vh;
    double th = (dmax(qa, dmax(qb, qc)) + hr) / s->vh;
    if (tl < 0.0)
        tl = 0.0;
    if (th > T)
        th = T;
    if (th > s->best)
        th = s->best;
    if (!(tl <= th))
        return;
    double zlo, zhi; /* the centre's height over [tl, th] */
    rf_quadratic_range(s->zq, tl, th, &zlo, &zhi);
    double zt = dmax(Tr->a.z, dmax(Tr->b.z, Tr->c.z));
    if (m->cfg.centre) {
        /* as test_candidates: the centre meets a face r / n.z above its plane */
        if (zt < zlo - reach / dmax(Tr->n.z, RF_NZ_MIN) ||
            dmin(Tr->a.z, dmin(Tr->b.z, Tr->c.z)) > zhi + reach)
            return;
    } else if (zt < zlo - reach) {
        return;
    }
    if (s->flight_bound && beyond_flight_reach(s, idx, Tr, tl, th))
        return;
    if (rf_excluded_tri(s->ex, idx)) {
        test_left(s, idx, tl, th, T, npend);
        return;
    }
    double w0;
    if (rf_test_face(s, idx, tl, th, &w0)) {
        if (w0 < tl)
            w0 = tl;
        if (w0 > th)
            return;
        pend_push(s, idx, w0, T, npend);
    }
}

/* A flight's candidates cand[0..n) over [0, T]: faces first, then the edges and
 * vertices of the triangles whose planes are reached before the earliest contact
 * found. */
static void test_line_candidates(rf_search *s, const int32_t *cand, size_t n, double T)
{
    pend_reserve(s->m->ws, n);
    size_t npend = 0;
    for (size_t k = 0; k < n; k++)
        line_candidate(s, cand[k], T, &npend);
    rf_vec3 z = rf_v3(0, 0, 0);
    test_pending(s, npend, T, z, z);
}

/* A flight over a grid terrain in centre mode or of a point mass (the face under the
 * centre, within the length tolerance of the line): the cells under its horizontal
 * line in the order it crosses them, each stretch of the line a piece with the cells
 * within reach of it, until a cell left after the earliest contact found. */
static void walk_grid(rf_search *s, double T)
{
    const rf_terrain *t = s->m->cfg.terrain;
    double hr = s->hr;
    double px = s->arc->p.x, py = s->arc->p.y, vx = s->arc->v.x, vy = s->arc->v.y;
    double c = t->cell;
    /* the time over the grid, widened by the reach (slabs in x and y) */
    double ta = 0.0, tb = T;
    double xmax, ymax;
    rf_grid_far(t, &xmax, &ymax);
    double lo[2] = {t->x0 - hr, t->y0 - hr};
    double hi[2] = {xmax + hr, ymax + hr};
    double p[2] = {px, py}, v[2] = {vx, vy};
    /* only faces under the centre: nothing is left pending (test_face and test_left go
     * to test_centre) */
    size_t npend = 0;
    for (int a = 0; a < 2; a++) {
        if (v[a] == 0.0) {
            if (p[a] < lo[a] || p[a] > hi[a])
                return;
            continue;
        }
        double u0 = (lo[a] - p[a]) / v[a], u1 = (hi[a] - p[a]) / v[a];
        ta = dmax(ta, dmin(u0, u1));
        tb = dmin(tb, dmax(u0, u1));
    }
    if (!(ta <= tb))
        return;
    double fi = floor((px + vx * ta - t->x0) / c), fj = floor((py + vy * ta - t->y0) / c);
    int sx = vx > 0 ? 1 : vx < 0 ? -1 : 0, sy = vy > 0 ? 1 : vy < 0 ? -1 : 0;
    double t0 = ta;
    /* each step moves one cell in x or y: at most the cells between the ends and two */
    double steps = fabs(floor((px + vx * tb - t->x0) / c) - fi) +
                   fabs(floor((py + vy * tb - t->y0) / c) - fj) + 2.0;
    for (double k = 0;; k++) {
        /* the next grid line crossed in x and in y (from the index: no drift); should
         * the steps ever run out (they are counted with two to spare), the rest at once */
        double tx = sx > 0   ? (t->x0 + (fi + 1) * c - px) / vx
                    : sx < 0 ? (t->x0 + fi * c - px) / vx
                             : INFINITY;
        double ty = sy > 0   ? (t->y0 + (fj + 1) * c - py) / vy
                    : sy < 0 ? (t->y0 + fj * c - py) / vy
                             : INFINITY;
        double t1 = !(k <= steps) ? tb : dmin(dmax(dmin(tx, ty), t0), tb);
        double xa = px + vx * t0, xb = px + vx * t1, ya = py + vy * t0, yb = py + vy * t1;
        size_t n = gather_grid(s->m, dmin(xa, xb) - hr, dmin(ya, yb) - hr, dmax(xa, xb) + hr,
                               dmax(ya, yb) + hr);
        for (size_t i = 0; i < n; i++)
            line_candidate(s, s->m->ws->cand[i], T, &npend);
        if ((s->found && s->best <= t1) || t1 >= tb)
            break;
        if (tx <= ty)
            fi += sx;
        else
            fj += sy;
        t0 = t1;
    }
}

/* Tests candidates over [ta, tb] (lo, hi: the arc's box over it): faces first, then
 * the edges and vertices of the triangles whose planes are reached before the earliest
 * contact found. */
static void test_candidates(rf_search *s, const int32_t *cand, size_t n, double ta, double tb,
                            rf_vec3 lo, rf_vec3 hi)
{
    rf_motion *m = s->m;
    rf_workspace *ws = m->ws;
    const rf_support *ex = s->ex;
    double reach = sphere_reach(m);
    double xl = lo.x - reach, xh = hi.x + reach, yl = lo.y - reach, yh = hi.y + reach;
    double zl = lo.z - reach, zh = hi.z + reach;
    pend_reserve(ws, n);
    size_t npend = 0;
    for (size_t k = 0; k < n; k++) {
        int32_t idx = cand[k];
        const rf_triangle *Tr = RF_CORNERS(m, idx);
        /* the triangle's box against the arc's box widened by the reach */
        if ((Tr->a.x < xl && Tr->b.x < xl && Tr->c.x < xl) ||
            (Tr->a.x > xh && Tr->b.x > xh && Tr->c.x > xh) ||
            (Tr->a.y < yl && Tr->b.y < yl && Tr->c.y < yl) ||
            (Tr->a.y > yh && Tr->b.y > yh && Tr->c.y > yh) ||
            (Tr->a.z > zh && Tr->b.z > zh && Tr->c.z > zh))
            continue;
        /* below: in centre mode the centre meets a face r / n.z above its plane,
         * more than r above its vertices on a steep face */
        double zlow = m->cfg.centre ? lo.z - reach / dmax(Tr->n.z, RF_NZ_MIN) : zl;
        if (Tr->a.z < zlow && Tr->b.z < zlow && Tr->c.z < zlow)
            continue;
        if (rf_excluded_tri(ex, idx)) {
            test_left(s, idx, ta, tb, tb, &npend); /* the support faces were dropped before */
            continue;
        }
        double w0;
        if (rf_test_face(s, idx, ta, tb, &w0))
            pend_push(s, idx, w0, tb, &npend);
    }
    test_pending(s, npend, tb, lo, hi);
}

/* Contact normal at the contact time. */
static void finish(const rf_motion *m, const rf_arc *arc, rf_contact *c)
{
    rf_vec3 p = rf_arc_pos(arc, c->t);
    if (c->kind == RF_FEAT_FACE) {
        c->n = RF_FACE(m, c->tri)->n;
    } else {
        rf_vec3 d = rf_v3_sub(p, c->point);
        double dl = rf_v3_norm(d);
        c->n = dl > 0 ? rf_v3_scale(d, 1.0 / dl) : RF_FACE(m, c->tri)->n;
    }
}

/* The arc over [0, T] in pieces along it, in order (s->line: a flight, each triangle
 * tested once over all the time it is within reach), until the first piece that ends
 * after the earliest contact found. */
static void search_pieces(rf_search *s, double T)
{
    rf_motion *m = s->m;
    const rf_terrain *t = m->cfg.terrain;
    const rf_arc *arc = s->arc;
    double reach = sphere_reach(m);
    /* higher than this above the terrain's top, nothing is met: the reach (in centre
     * mode the centre meets a face r / n.z above its plane (Eq. 6-7), the furthest
     * above the steepest face) */
    double up = m->cfg.centre ? reach / m->ws->tables->nz_min : reach;
    double cell = t->is_grid ? t->cell : t->bsize;
    double vh = dmax(rf_v3_hnorm(arc->v), rf_v3_hnorm(rf_arc_vel(arc, T)));
    double hlen = vh * T;
    rf_workspace *ws = m->ws;
    double piece;
    if (s->line) {
        /* pieces of about a cell of travel */
        feat_reset(ws);
        piece = t->is_grid ? cell : 2.0 * cell;
    } else {
        /* pieces of about a few cells of horizontal travel */
        piece = dmax(4.0 * cell, 2.0 * m->cfg.rho);
    }
    double np = ceil(hlen / piece);
    long npieces = np >= 1.0 ? (np < RF_MAX_SEARCH_PIECES ? (long)np : RF_MAX_SEARCH_PIECES) : 1;
    for (long i = 0; i < npieces; i++) {
        double ta = T * (double)i / (double)npieces;
        double tb = i + 1 == npieces ? T : T * (double)(i + 1) / (double)npieces;
        if (ta >= s->best)
            break;
        rf_vec3 lo, hi;
        rf_arc_box(arc, ta, dmin(tb, s->best), &lo, &hi);
        if (lo.z - up > t->zmax || hi.z + reach < t->zmin)
            continue;
        double hr = s->line ? s->hr : reach;
        size_t n = rf_gather(m, lo.x - hr, lo.y - hr, hi.x + hr, hi.y + hr);
        if (s->line)
            test_line_candidates(s, ws->cand, n, T);
        else
            test_candidates(s, ws->cand, n, ta, tb, lo, hi);
        if (s->found && s->best <= tb)
            break;
    }
}

int rf_contact_search(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                      rf_contact *c)
{
    const rf_terrain *t = m->cfg.terrain;
    rf_search s = {m, arc, ex, INFINITY, 0, c, rf_start_hspeed(arc)};
    reach_bound fb;
    if (!(T >= 0))
        return 0;
    double vh0 = s.vh;
    if (arc->a.x == 0.0 && arc->a.y == 0.0 && vh0 * T > RF_LINE_MIN_TRAVEL * m->cfg.rho) {
        s.line = 1;
        s.ux = arc->v.x / vh0;
        s.uy = arc->v.y / vh0;
        s.s0 = s.ux * arc->p.x + s.uy * arc->p.y;
        s.d0 = s.ux * arc->p.y - s.uy * arc->p.x;
        s.hr = line_reach(m);
        s.reach = sphere_reach(m);
        s.zq[0] = arc->p.z, s.zq[1] = arc->v.z, s.zq[2] = 0.5 * arc->a.z;
        if (ex && ex->n > 0 && !m->cfg.centre && !m->cfg.point) {
            /* off a face: its plane's reach bound (a hop over a bent grid edge stays
             * near that plane) */
            const rf_triangle *F = RF_FACE(m, ex->tri[0]);
            reach_bound_set(F->n, F->d, m->cfg.rho, arc, T, NULL, NULL, &fb);
            s.flight_bound = &fb;
            s.r0sq = bound_r0(m) * bound_r0(m);
        }
        rf_workspace *ws = m->ws;
        tested_clear(ws);
    }
    if (s.line && t->is_grid && (m->cfg.centre || m->cfg.point))
        walk_grid(&s, T);
    else
        search_pieces(&s, T);
    if (!s.found)
        return 0;
    finish(m, arc, c);
    return 1;
}

int rf_contact_search_near(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                           const rf_contact *skip, int nskip, rf_contact *c)
{
    rf_search s = {m, arc, ex, INFINITY, 0, c, rf_start_hspeed(arc)};
    s.skip = skip;
    s.nskip = nskip;
    if (!(T >= 0))
        return 0;
    rf_vec3 lo, hi;
    rf_arc_box(arc, 0.0, T, &lo, &hi);
    /* the candidates whose boxes meet the arc's box widened by the reach */
    rf_workspace *ws = m->ws;
    double reach = sphere_reach(m);
    double xl = lo.x - reach, xh = hi.x + reach, yl = lo.y - reach, yh = hi.y + reach;
    double zl = lo.z - reach, zh = hi.z + reach;
    size_t nhit = 0;
    const rf_terrain *t = m->cfg.terrain;
    int filter = !m->cfg.centre && !m->cfg.point;
    rf_support_planes_set(m, &s.sp);
    /* the support planes' reach bounds over the arc */
    reach_bound rb[2];
    double r0 = bound_r0(m);
    for (int k = 0; filter && k < s.sp.n; k++)
        reach_bound_set(s.sp.nrm[k], s.sp.d[k], m->cfg.rho, arc, T, &lo, &hi, &rb[k]);
    size_t n = rf_gather(m, xl, yl, xh, yh);
    if (rf_grow((void **)&ws->near_hit, &ws->near_cap, n, sizeof *ws->near_hit))
        return 0;
    for (size_t k = 0; k < n; k++) {
        int32_t idx = ws->cand[k];
        float box[6];
        const float *b = rf_tri_box(ws, idx, box);
        if (b[1] < xl || b[0] > xh || b[3] < yl || b[2] > yh || b[5] < zl || b[4] > zh)
            continue;
        /* the cheapest rejections first: the bound from the vertices' heights above the
         * support planes rejects five in six of the boxes' survivors (the support's own
         * faces among them), so the support list and the planes' comparison are left
         * to the rest */
        if (filter) {
            /* faces in a support's plane or wholly on or below a support plane are out
             * of reach for the whole segment, and so are faces beyond the support's
             * reach bound of this arc */
            if (beyond_support_reach(&s, rb, b, RF_CORNERS(m, idx), r0 * r0) ||
                rf_excluded_tri(&m->rock.sup, idx) ||
                rf_coplanar_with_support(t, &m->rock.sup, RF_FACE(m, idx), m->cfg.tol_len))
                continue;
        } else if (rf_excluded_tri(&m->rock.sup, idx)) {
            continue;
        }
        ws->near_hit[nhit++] = idx;
    }
    if (nhit == 0)
        return 0;
    test_candidates(&s, ws->near_hit, nhit, 0.0, T, lo, hi);
    if (!s.found)
        return 0;
    finish(m, arc, c);
    return 1;
}


int rf_flight_contact(rf_motion *m, const rf_arc *arc, double T, rf_contact *c)
{
    const rf_support *ex = m->rock.flight_ex.n ? &m->rock.flight_ex : NULL;
    return rf_contact_search(m, arc, T, ex, c) && c->t <= T;
}
