/* tin.c - greedy insertion of grid nodes into a Delaunay triangulation until the TIN
 * is within a tolerance of the grid's surface (Garland and Heckbert 1995); the
 * contracts are in tin.h. */
#include "input/tin.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"

enum { NODE_INSERTED = 1, NODE_NODATA = 2 };
enum { CLS_VALID, CLS_HOLE, CLS_STRADDLE };

/* A triangle of the TIN: grid node indices counter-clockwise, the triangle across the
 * edge opposite v[k] (-1 on the grid's outline), and what insertion needs of it. */
typedef struct tri {
    int32_t v[3], nb[3];
    int32_t cand;   /* the node to insert next in it, or -1 */
    int32_t pos;    /* its place in the heap, or -1 */
    double err;     /* the largest error measured in it (INFINITY: it straddles a hole) */
    uint32_t mark;  /* touched by the insertion numbered mark */
    int cls;        /* CLS_* */
} tri;

typedef struct tin {
    const rf_asc_grid *g;
    long nx, ny;
    double tol;
    unsigned char *node;  /* NODE_* per grid node */
    uint32_t *hole_sum;   /* hole cells with ci < i, cj < j at [j * nx + i]; NULL: none */
    tri *t;
    size_t nt, cap;
    int32_t *heap;        /* triangles whose error is over the tolerance, largest first */
    size_t nheap, heap_cap;
    int32_t *stack, *touched;
    size_t nstack, ntouched, stack_cap, touched_cap;
    uint32_t epoch;
    size_t unresolved;
    int oom;
} tin;

/* ---- exact predicates on grid indices ------------------------------------------------ */

static long nx_of(const tin *m, int32_t v) { return (long)v % m->nx; }
static long ny_of(const tin *m, int32_t v) { return (long)v / m->nx; }

static int64_t orient(long ax, long ay, long bx, long by, long px, long py)
{
    return (int64_t)(bx - ax) * (py - ay) - (int64_t)(by - ay) * (px - ax);
}

static int64_t orient_v(const tin *m, int32_t a, int32_t b, long px, long py)
{
    return orient(nx_of(m, a), ny_of(m, a), nx_of(m, b), ny_of(m, b), px, py);
}

/* > 0 when d is inside the circle through a, b, c (counter-clockwise), < 0 outside.
 * Cocircular points are decided by the lifting x^2 + y^2 + eps (x - y)^2, which keeps a
 * cell's SW-NE diagonal (tin.h). */
static int incircle(const tin *m, int32_t a, int32_t b, int32_t c, int32_t d)
{
    long dx = nx_of(m, d), dy = ny_of(m, d);
    int64_t adx = nx_of(m, a) - dx, ady = ny_of(m, a) - dy;
    int64_t bdx = nx_of(m, b) - dx, bdy = ny_of(m, b) - dy;
    int64_t cdx = nx_of(m, c) - dx, cdy = ny_of(m, c) - dy;
    int64_t ab = adx * bdy - bdx * ady, bc = bdx * cdy - cdx * bdy, ca = cdx * ady - adx * cdy;
    int64_t det = (adx * adx + ady * ady) * bc + (bdx * bdx + bdy * bdy) * ca +
                  (cdx * cdx + cdy * cdy) * ab;
    if (det != 0)
        return det > 0 ? 1 : -1;
    int64_t gd = (dx - dy) * (dx - dy);
    int64_t ga = (nx_of(m, a) - ny_of(m, a)) * (nx_of(m, a) - ny_of(m, a)) - gd;
    int64_t gb = (nx_of(m, b) - ny_of(m, b)) * (nx_of(m, b) - ny_of(m, b)) - gd;
    int64_t gc = (nx_of(m, c) - ny_of(m, c)) * (nx_of(m, c) - ny_of(m, c)) - gd;
    int64_t pert = ga * bc + gb * ca + gc * ab;
    return pert > 0 ? 1 : (pert < 0 ? -1 : 0);
}

/* ---- the heap of triangles over the tolerance ---------------------------------------- */

static void heap_swap(tin *m, size_t i, size_t j)
{
    int32_t a = m->heap[i], b = m->heap[j];
    m->heap[i] = b, m->heap[j] = a;
    m->t[b].pos = (int32_t)i, m->t[a].pos = (int32_t)j;
}

static void heap_fix(tin *m, size_t i)
{
    while (i > 0 && m->t[m->heap[(i - 1) / 2]].err < m->t[m->heap[i]].err) {
        heap_swap(m, i, (i - 1) / 2);
        i = (i - 1) / 2;
    }
    for (;;) {
        size_t l = 2 * i + 1, r = l + 1, big = i;
        if (l < m->nheap && m->t[m->heap[l]].err > m->t[m->heap[big]].err)
            big = l;
        if (r < m->nheap && m->t[m->heap[r]].err > m->t[m->heap[big]].err)
            big = r;
        if (big == i)
            return;
        heap_swap(m, i, big);
        i = big;
    }
}

/* Puts triangle k in the heap, moves it, or takes it out, by its error. */
static void heap_update(tin *m, int32_t k)
{
    tri *T = &m->t[k];
    int want = T->cand >= 0 && T->err > m->tol;
    if (T->pos < 0 && want) {
        T->pos = (int32_t)m->nheap;
        m->heap[m->nheap++] = k;
        heap_fix(m, (size_t)T->pos);
    } else if (T->pos >= 0 && !want) {
        size_t i = (size_t)T->pos;
        T->pos = -1;
        m->nheap--;
        if (i < m->nheap) {
            m->heap[i] = m->heap[m->nheap];
            m->t[m->heap[i]].pos = (int32_t)i;
            heap_fix(m, i);
        }
    } else if (T->pos >= 0) {
        heap_fix(m, (size_t)T->pos);
    }
}

/* ---- classing a triangle against the holes -------------------------------------------- */

static int node_bad(const tin *m, long x, long y)
{
    return m->node[(size_t)y * (size_t)m->nx + (size_t)x] & NODE_NODATA;
}

/* Hole cells (a nodata corner) among cells [i0, i1] x [j0, j1]. */
static uint32_t holes_in(const tin *m, long i0, long j0, long i1, long j1)
{
    const uint32_t *s = m->hole_sum;
    size_t w = (size_t)m->nx;
    return s[(size_t)(j1 + 1) * w + (size_t)(i1 + 1)] - s[(size_t)j0 * w + (size_t)(i1 + 1)] -
           s[(size_t)(j1 + 1) * w + (size_t)i0] + s[(size_t)j0 * w + (size_t)i0];
}

/* 1 when the interiors of the counter-clockwise triangles p and q overlap: no edge line
 * of either has the other on its closed outer side (separating axes, exact). */
static int interiors_overlap(const long p[6], const long q[6])
{
    for (int side = 0; side < 2; side++) {
        const long *a = side ? q : p, *b = side ? p : q;
        for (int e = 0; e < 3; e++) {
            int f = (e + 1) % 3, out = 1;
            for (int k = 0; k < 3 && out; k++)
                out = orient(a[2 * e], a[2 * e + 1], a[2 * f], a[2 * f + 1], b[2 * k],
                             b[2 * k + 1]) <= 0;
            if (out)
                return 0;
        }
    }
    return 1;
}

/* Classes triangle T by the grid triangles its interior overlaps; for one that
 * straddles, *cand is a node of an overlapped valid grid triangle not yet inserted. */
static int classify(tin *m, const tri *T, int32_t *cand)
{
    long p[6];
    for (int k = 0; k < 3; k++)
        p[2 * k] = nx_of(m, T->v[k]), p[2 * k + 1] = ny_of(m, T->v[k]);
    long x0 = p[0] < p[2] ? p[0] : p[2], x1 = p[0] > p[2] ? p[0] : p[2];
    long y0 = p[1] < p[3] ? p[1] : p[3], y1 = p[1] > p[3] ? p[1] : p[3];
    x0 = p[4] < x0 ? p[4] : x0, x1 = p[4] > x1 ? p[4] : x1;
    y0 = p[5] < y0 ? p[5] : y0, y1 = p[5] > y1 ? p[5] : y1;
    int any_valid = 0, any_hole = 0;
    *cand = -1;
    for (long j = y0; j < y1; j++)
        for (long i = x0; i < x1; i++)
            for (int k = 0; k < 2; k++) {
                long q[6] = {i, j, i + 1, j + 1, i, j + 1};
                if (k == 0)
                    q[2] = i + 1, q[3] = j, q[4] = i + 1, q[5] = j + 1;
                if (!interiors_overlap(p, q))
                    continue;
                int bad = 0;
                for (int c = 0; c < 3; c++)
                    bad |= node_bad(m, q[2 * c], q[2 * c + 1]);
                if (bad) {
                    any_hole = 1;
                    continue;
                }
                any_valid = 1;
                for (int c = 0; c < 3 && *cand < 0; c++) {
                    int32_t v = (int32_t)(q[2 * c + 1] * m->nx + q[2 * c]);
                    if (!(m->node[v] & NODE_INSERTED))
                        *cand = v;
                }
                if (any_hole && *cand >= 0)
                    return CLS_STRADDLE;
            }
    if (!any_valid)
        return CLS_HOLE;
    if (!any_hole)
        return CLS_VALID;
    if (*cand >= 0)
        return CLS_STRADDLE;
    m->unresolved++; /* cannot happen (tin.h): dropped, and counted */
    return CLS_HOLE;
}

/* ---- the error of a triangle ------------------------------------------------------------ */

static double zg(const tin *m, long x, long y)
{
    return m->g->z[(size_t)y * (size_t)m->nx + (size_t)x];
}

/* The plane of T: z = za + gx (x - ax) + gy (y - ay). */
typedef struct plane {
    long ax, ay;
    double za, gx, gy;
} plane;

static plane plane_of(const tin *m, const tri *T)
{
    long ax = nx_of(m, T->v[0]), ay = ny_of(m, T->v[0]);
    long bx = nx_of(m, T->v[1]) - ax, by = ny_of(m, T->v[1]) - ay;
    long cx = nx_of(m, T->v[2]) - ax, cy = ny_of(m, T->v[2]) - ay;
    double za = zg(m, ax, ay), zb = zg(m, ax + bx, ay + by) - za, zc = zg(m, ax + cx, ay + cy) - za;
    double det = (double)orient(0, 0, bx, by, cx, cy);
    plane pl = {ax, ay, za, (zb * (double)cy - zc * (double)by) / det,
                (zc * (double)bx - zb * (double)cx) / det};
    return pl;
}

static double plane_z(const plane *pl, double x, double y)
{
    return pl->za + pl->gx * (x - (double)pl->ax) + pl->gy * (y - (double)pl->ay);
}

/* The end of grid edge e0-e1 to insert for a crossing at fraction f from e0: the nearer
 * one not inserted, or -1. */
static int32_t edge_end(const tin *m, int32_t e0, int32_t e1, double f)
{
    int32_t first = f < 0.5 ? e0 : e1, second = f < 0.5 ? e1 : e0;
    if (!(m->node[first] & NODE_INSERTED))
        return first;
    if (!(m->node[second] & NODE_INSERTED))
        return second;
    return -1;
}

/* One crossing of edge (a + s (b - a)) with a grid edge from node (x0, y0) to
 * (x0 + sx, y0 + sy) at fraction f: updates the largest error and its candidate. */
static void crossing(tin *m, double zt, long x0, long y0, long sx, long sy, double f,
                     double *best, int32_t *cand)
{
    double z = (1.0 - f) * zg(m, x0, y0) + f * zg(m, x0 + sx, y0 + sy);
    double e = fabs(zt - z);
    if (!(e > *best))
        return;
    int32_t v = edge_end(m, (int32_t)(y0 * m->nx + x0), (int32_t)((y0 + sy) * m->nx + x0 + sx), f);
    if (v < 0) {
        m->unresolved++; /* an inserted grid edge is never crossed (tin.h) */
        return;
    }
    *best = e, *cand = v;
}

/* The crossings of the edge from vertex a to vertex b with the grid lines x = i,
 * y = j and x - y = k strictly between its ends (a lattice point there is a node,
 * measured by the node scan). */
static void edge_crossings(tin *m, int32_t a, int32_t b, double *best, int32_t *cand)
{
    long ax = nx_of(m, a), ay = ny_of(m, a), dx = nx_of(m, b) - ax, dy = ny_of(m, b) - ay;
    double za = zg(m, ax, ay), dz = zg(m, ax + dx, ay + dy) - za;
    if (dx != 0) {
        long lo = dx > 0 ? ax : ax + dx, hi = dx > 0 ? ax + dx : ax;
        for (long k = lo + 1; k < hi; k++) {
            long num = (k - ax) * dy;
            if (num % dx == 0)
                continue;
            double s = (double)(k - ax) / (double)dx, y = (double)ay + (double)num / (double)dx;
            long j = (long)floor(y);
            crossing(m, za + s * dz, k, j, 0, 1, y - (double)j, best, cand);
        }
    }
    if (dy != 0) {
        long lo = dy > 0 ? ay : ay + dy, hi = dy > 0 ? ay + dy : ay;
        for (long k = lo + 1; k < hi; k++) {
            long num = (k - ay) * dx;
            if (num % dy == 0)
                continue;
            double s = (double)(k - ay) / (double)dy, x = (double)ax + (double)num / (double)dy;
            long i = (long)floor(x);
            crossing(m, za + s * dz, i, k, 1, 0, x - (double)i, best, cand);
        }
    }
    long de = dx - dy, ea = ax - ay;
    if (de != 0) {
        long lo = de > 0 ? ea : ea + de, hi = de > 0 ? ea + de : ea;
        for (long k = lo + 1; k < hi; k++) {
            long num = (k - ea) * dx;
            if (num % de == 0)
                continue;
            double s = (double)(k - ea) / (double)de, x = (double)ax + (double)num / (double)de;
            long i = (long)floor(x);
            crossing(m, za + s * dz, i, i - k, 1, 1, x - (double)i, best, cand);
        }
    }
}

/* The largest error over a valid triangle (tin.h: its nodes and its edges' crossings)
 * and the node to insert for it. */
static void measure(tin *m, const tri *T, double *best, int32_t *cand)
{
    plane pl = plane_of(m, T);
    long x[3], y[3];
    for (int k = 0; k < 3; k++)
        x[k] = nx_of(m, T->v[k]), y[k] = ny_of(m, T->v[k]);
    long y0 = y[0], y1 = y[0];
    for (int k = 1; k < 3; k++)
        y0 = y[k] < y0 ? y[k] : y0, y1 = y[k] > y1 ? y[k] : y1;
    *best = 0.0;
    *cand = -1;
    for (long j = y0; j <= y1; j++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int k = 0; k < 3; k++) {
            int f = (k + 1) % 3;
            if ((y[k] - j) * (y[f] - j) > 0)
                continue;
            if (y[k] == y[f]) {
                lo = fmin(lo, (double)fmin(x[k], x[f])), hi = fmax(hi, (double)fmax(x[k], x[f]));
                continue;
            }
            double xs = (double)x[k] + (double)(j - y[k]) * (double)(x[f] - x[k]) /
                                           (double)(y[f] - y[k]);
            lo = fmin(lo, xs), hi = fmax(hi, xs);
        }
        for (long i = (long)floor(lo); i <= (long)ceil(hi); i++) {
            if (orient(x[0], y[0], x[1], y[1], i, j) < 0 ||
                orient(x[1], y[1], x[2], y[2], i, j) < 0 ||
                orient(x[2], y[2], x[0], y[0], i, j) < 0)
                continue;
            int32_t v = (int32_t)(j * m->nx + i);
            if (m->node[v])
                continue; /* a vertex (inserted); nodata is never in a valid triangle */
            double e = fabs(plane_z(&pl, (double)i, (double)j) - zg(m, i, j));
            if (e > *best)
                *best = e, *cand = v;
        }
    }
    for (int k = 0; k < 3; k++)
        edge_crossings(m, T->v[k], T->v[(k + 1) % 3], best, cand);
}

/* Classes and measures triangle k afresh and files it in the heap. */
static void scan(tin *m, int32_t k)
{
    tri *T = &m->t[k];
    int phantom = 0;
    long x0 = m->nx, x1 = 0, y0 = m->ny, y1 = 0;
    for (int c = 0; c < 3; c++) {
        long x = nx_of(m, T->v[c]), y = ny_of(m, T->v[c]);
        phantom |= node_bad(m, x, y);
        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
        y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
    }
    T->cls = CLS_VALID;
    if (phantom || (m->hole_sum && holes_in(m, x0, y0, x1 - 1, y1 - 1) > 0))
        T->cls = classify(m, T, &T->cand);
    if (T->cls == CLS_VALID)
        measure(m, T, &T->err, &T->cand);
    else
        T->err = T->cls == CLS_STRADDLE ? INFINITY : -1.0;
    if (T->cls == CLS_HOLE)
        T->cand = -1;
    heap_update(m, k);
}

/* ---- insertion ------------------------------------------------------------------------------ */

static void touch(tin *m, int32_t k)
{
    if (m->t[k].mark == m->epoch)
        return;
    m->t[k].mark = m->epoch;
    if (rf_grow((void **)&m->touched, &m->touched_cap, m->ntouched + 1, sizeof *m->touched)) {
        m->oom = 1;
        return;
    }
    m->touched[m->ntouched++] = k;
}

static void push(tin *m, int32_t k)
{
    if (rf_grow((void **)&m->stack, &m->stack_cap, m->nstack + 1, sizeof *m->stack)) {
        m->oom = 1;
        return;
    }
    m->stack[m->nstack++] = k;
    touch(m, k);
}

/* In triangle k, the neighbour pointer to `from` now points to `to`. */
static void relink(tin *m, int32_t k, int32_t from, int32_t to)
{
    if (k < 0)
        return;
    for (int c = 0; c < 3; c++)
        if (m->t[k].nb[c] == from) {
            m->t[k].nb[c] = to;
            return;
        }
    assert(0 && "neighbours out of step");
}

static int32_t new_tri(tin *m, int32_t a, int32_t b, int32_t c, int32_t na, int32_t nb, int32_t nc)
{
    tri *T = &m->t[m->nt];
    *T = (tri){{a, b, c}, {na, nb, nc}, -1, -1, 0.0, 0, CLS_VALID};
    return (int32_t)m->nt++;
}

static void set_tri(tin *m, int32_t k, int32_t a, int32_t b, int32_t c, int32_t na, int32_t nb,
                    int32_t nc)
{
    tri *T = &m->t[k];
    T->v[0] = a, T->v[1] = b, T->v[2] = c;
    T->nb[0] = na, T->nb[1] = nb, T->nb[2] = nc;
}

/* Lawson's flips of the edges opposite the new vertex (index 2 of every pushed
 * triangle) until each is locally Delaunay. */
static void legalize(tin *m)
{
    while (m->nstack > 0) {
        int32_t t = m->stack[--m->nstack];
        int32_t u = m->t[t].nb[2];
        if (u < 0)
            continue;
        int mu = 0;
        while (m->t[u].nb[mu] != t)
            mu++;
        int32_t a = m->t[t].v[0], b = m->t[t].v[1], p = m->t[t].v[2], d = m->t[u].v[mu];
        if (incircle(m, a, b, p, d) <= 0)
            continue;
        int32_t tb = m->t[t].nb[0], ta = m->t[t].nb[1];
        int32_t u_ad = m->t[u].nb[(mu + 1) % 3], u_db = m->t[u].nb[(mu + 2) % 3];
        assert(m->t[u].v[(mu + 1) % 3] == b && m->t[u].v[(mu + 2) % 3] == a);
        set_tri(m, t, a, d, p, u, ta, u_ad);
        set_tri(m, u, d, b, p, tb, t, u_db);
        relink(m, tb, t, u);
        relink(m, u_ad, u, t);
        push(m, t);
        push(m, u);
    }
}

/* The triangle holding node (px, py) by a visibility walk from `start` (it ends on a
 * Delaunay triangulation; a scan of all triangles backs it up); *edge is the edge p is
 * on (opposite v[*edge]) or -1. */
static int32_t locate(const tin *m, int32_t start, long px, long py, int *edge)
{
    int32_t k = start;
    for (size_t steps = 0; steps <= m->nt; steps++) {
        const tri *T = &m->t[k];
        int on = -1, moved = 0;
        for (int c = 0; c < 3 && !moved; c++) {
            int64_t o = orient_v(m, T->v[(c + 1) % 3], T->v[(c + 2) % 3], px, py);
            if (o < 0 && T->nb[c] >= 0)
                k = T->nb[c], moved = 1;
            else if (o == 0)
                on = c;
        }
        if (!moved) {
            *edge = on;
            return k;
        }
    }
    for (size_t j = 0; j < m->nt; j++) {
        const tri *T = &m->t[j];
        int on = -1, in = 1;
        for (int c = 0; c < 3 && in; c++) {
            int64_t o = orient_v(m, T->v[(c + 1) % 3], T->v[(c + 2) % 3], px, py);
            in = o >= 0;
            on = o == 0 ? c : on;
        }
        if (in) {
            *edge = on;
            return (int32_t)j;
        }
    }
    assert(0 && "a grid node outside the grid's corners");
    return -1;
}

/* Inserts node p (inside the grid's outline), keeping the triangulation Delaunay; the
 * triangles made or changed are in m->touched. */
static void insert(tin *m, int32_t start, int32_t p)
{
    if (rf_grow((void **)&m->t, &m->cap, m->nt + 3, sizeof *m->t) ||
        rf_grow((void **)&m->heap, &m->heap_cap, m->nt + 3, sizeof *m->heap)) {
        m->oom = 1;
        return;
    }
    m->epoch++;
    m->ntouched = 0;
    m->node[p] |= NODE_INSERTED;
    int edge;
    int32_t t = locate(m, start, nx_of(m, p), ny_of(m, p), &edge);
    if (edge < 0) {
        int32_t a = m->t[t].v[0], b = m->t[t].v[1], c = m->t[t].v[2];
        int32_t na = m->t[t].nb[0], nb = m->t[t].nb[1], nc = m->t[t].nb[2];
        int32_t t1 = (int32_t)m->nt, t2 = t1 + 1;
        set_tri(m, t, a, b, p, t1, t2, nc);
        new_tri(m, b, c, p, t2, t, na);
        new_tri(m, c, a, p, t, t1, nb);
        relink(m, na, t, t1);
        relink(m, nb, t, t2);
        push(m, t), push(m, t1), push(m, t2);
    } else {
        int32_t c = m->t[t].v[edge], a = m->t[t].v[(edge + 1) % 3], b = m->t[t].v[(edge + 2) % 3];
        int32_t na = m->t[t].nb[(edge + 1) % 3], nb = m->t[t].nb[(edge + 2) % 3];
        int32_t u = m->t[t].nb[edge];
        int32_t t1 = (int32_t)m->nt, u1 = u >= 0 ? t1 + 1 : -1;
        set_tri(m, t, c, a, p, u, t1, nb);
        new_tri(m, b, c, p, t, u1, na);
        relink(m, na, t, t1);
        push(m, t), push(m, t1);
        if (u >= 0) {
            int mu = 0;
            while (m->t[u].nb[mu] != t)
                mu++;
            int32_t d = m->t[u].v[mu];
            int32_t u_ad = m->t[u].nb[(mu + 1) % 3], u_db = m->t[u].nb[(mu + 2) % 3];
            set_tri(m, u, a, d, p, u1, t, u_ad);
            new_tri(m, d, b, p, t1, u, u_db);
            relink(m, u_db, u, u1);
            push(m, u), push(m, u1);
        }
    }
    legalize(m);
}

/* ---- the whole ---------------------------------------------------------------------------- */

static int setup(tin *m, const rf_asc_grid *g, double tolerance)
{
    size_t n = g->ncols * g->nrows;
    *m = (tin){.g = g, .nx = (long)g->ncols, .ny = (long)g->nrows, .tol = tolerance};
    m->node = calloc(n, 1);
    if (!m->node)
        return -1;
    size_t bad = 0;
    for (size_t v = 0; v < n; v++)
        if (g->has_nodata && g->z[v] == g->nodata)
            m->node[v] = NODE_NODATA, bad++;
    if (bad) {
        m->hole_sum = calloc(n, sizeof *m->hole_sum);
        if (!m->hole_sum)
            return -1;
        size_t w = g->ncols;
        for (size_t j = 0; j + 1 < g->nrows; j++) {
            uint32_t row = 0;
            for (size_t i = 0; i + 1 < w; i++) {
                row += (m->node[j * w + i] | m->node[j * w + i + 1] | m->node[(j + 1) * w + i] |
                        m->node[(j + 1) * w + i + 1]) != 0;
                m->hole_sum[(j + 1) * w + i + 1] = m->hole_sum[j * w + i + 1] + row;
            }
        }
    }
    m->cap = m->heap_cap = 1024;
    m->t = malloc(m->cap * sizeof *m->t);
    m->heap = malloc(m->heap_cap * sizeof *m->heap);
    if (!m->t || !m->heap)
        return -1;
    int32_t sw = 0, se = (int32_t)(m->nx - 1), ne = (int32_t)(n - 1),
            nw = (int32_t)((size_t)(m->ny - 1) * g->ncols);
    m->node[sw] |= NODE_INSERTED, m->node[se] |= NODE_INSERTED;
    m->node[ne] |= NODE_INSERTED, m->node[nw] |= NODE_INSERTED;
    /* the corners are cocircular: the SW-NE diagonal, as the perturbation takes it */
    new_tri(m, sw, se, ne, -1, 1, -1);
    new_tri(m, sw, ne, nw, -1, -1, 0);
    scan(m, 0);
    scan(m, 1);
    return 0;
}

static void teardown(tin *m)
{
    free(m->node);
    free(m->hole_sum);
    free(m->t);
    free(m->heap);
    free(m->stack);
    free(m->touched);
}

static int emit(const tin *m, const rf_asc_grid *g, rf_tri_list *out, rf_tin_stats *st)
{
    size_t keep = 0;
    for (size_t k = 0; k < m->nt; k++)
        keep += m->t[k].cls == CLS_VALID;
    if (rf_grow((void **)&out->v, &out->cap, out->n + keep, 3 * sizeof *out->v))
        return -1;
    *st = (rf_tin_stats){0, keep, m->nt - keep, 0.0, m->unresolved};
    for (size_t v = 0; v < g->ncols * g->nrows; v++)
        st->vertices += (m->node[v] & NODE_INSERTED) != 0;
    for (size_t k = 0; k < m->nt; k++) {
        const tri *T = &m->t[k];
        if (T->cls != CLS_VALID)
            continue;
        st->max_error = fmax(st->max_error, T->err);
        for (int c = 0; c < 3; c++) {
            long x = nx_of(m, T->v[c]), y = ny_of(m, T->v[c]);
            out->v[3 * out->n + (size_t)c] =
                rf_v3(g->x0 + (double)x * g->cell, g->y0 + (double)y * g->cell, zg(m, x, y));
        }
        out->n++;
    }
    return 0;
}

int rf_tin_build(const rf_asc_grid *g, double tolerance, const char *path, rf_tri_list *out,
                 rf_tin_stats *stats, rf_error *err)
{
    assert(tolerance >= 0 && g->ncols >= 2 && g->nrows >= 2);
    if (g->ncols > RF_TIN_SIDE_MAX || g->nrows > RF_TIN_SIDE_MAX)
        return rf_error_set(err, path, 0, 0,
                            "a grid of %zu x %zu nodes is too large for 'tolerance' (at most "
                            "%d nodes a side); crop it to the slope",
                            g->ncols, g->nrows, RF_TIN_SIDE_MAX);
    tin m;
    int rc = setup(&m, g, tolerance);
    while (rc == 0 && !m.oom && m.nheap > 0) {
        int32_t k = m.heap[0];
        if (m.node[m.t[k].cand] & NODE_INSERTED) {
            scan(&m, k); /* its candidate came in through a neighbour */
            continue;
        }
        insert(&m, k, m.t[k].cand);
        for (size_t i = 0; i < m.ntouched && !m.oom; i++)
            scan(&m, m.touched[i]);
    }
    size_t before = out->n;
    if (rc || m.oom || emit(&m, g, out, stats)) {
        out->n = before;
        teardown(&m);
        return rf_error_set(err, path, 0, 0, "out of memory making the grid a TIN");
    }
    teardown(&m);
    return 0;
}
