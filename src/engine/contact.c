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
#include "engine/motion_private.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* Grid terrains: both triangles of each cell the box touches (a few more than the box
 * holds, none missing), by index arithmetic on the documented layout. */
static size_t gather_grid(rf_motion *m, double xmin, double ymin, double xmax, double ymax)
{
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->terrain;
    size_t r[4];
    if (!rf_cell_range(xmin, xmax, t->x0, t->cell, t->nx - 1, &r[0], &r[1]) ||
        !rf_cell_range(ymin, ymax, t->y0, t->cell, t->ny - 1, &r[2], &r[3]))
        return 0;
    size_t need = 2 * (r[1] - r[0] + 1) * (r[3] - r[2] + 1);
    if (rf_grow((void **)&ws->cand, &ws->cap, need, sizeof *ws->cand))
        return 0;
    size_t n = 0, row = t->nx - 1;
    for (size_t j = r[2]; j <= r[3]; j++) {
        const int32_t *g = t->grid_tri + 2 * (j * row + r[0]);
        for (size_t i = r[0]; i <= r[1]; i++, g += 2) {
            if (g[0] >= 0)
                ws->cand[n++] = g[0];
            if (g[1] >= 0)
                ws->cand[n++] = g[1];
        }
    }
    return n;
}

size_t rf_gather(rf_motion *m, double xmin, double ymin, double xmax, double ymax)
{
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->terrain;
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

/* Bit k: edge k of triangle idx can be met first (concave edges below). */
static inline unsigned edge_live(rf_workspace *ws, int32_t idx);

/* ---- triangle helpers ---------------------------------------------------------------- */



static int excluded_tri(const rf_support *ex, int32_t idx)
{
    if (!ex)
        return 0;
    for (int k = 0; k < ex->n; k++)
        if (ex->tri[k] == idx)
            return 1;
    return 0;
}

/* Signed in-plane distance of q (on the plane) inside the triangle's edges: >= 0 on
 * the inner side of all three; returns the smallest of the three. */
static double inside_margin(const rf_triangle *T, rf_vec3 q)
{
    rf_vec3 ab = rf_v3_sub(T->b, T->a), bc = rf_v3_sub(T->c, T->b), ca = rf_v3_sub(T->a, T->c);
    double orient = rf_v3_dot(rf_v3_cross(ab, rf_v3_scale(ca, -1.0)), T->n) >= 0 ? 1.0 : -1.0;
    double s0 = orient * rf_v3_dot(rf_v3_cross(ab, rf_v3_sub(q, T->a)), T->n) / rf_v3_norm(ab);
    double s1 = orient * rf_v3_dot(rf_v3_cross(bc, rf_v3_sub(q, T->b)), T->n) / rf_v3_norm(bc);
    double s2 = orient * rf_v3_dot(rf_v3_cross(ca, rf_v3_sub(q, T->c)), T->n) / rf_v3_norm(ca);
    return dmin(s0, dmin(s1, s2));
}

/* 1 when q (on the plane) lies on the inner side of all three edges or on them: the
 * signs of inside_margin's three distances. */
static int inside_closed(const rf_triangle *T, rf_vec3 q)
{
    rf_vec3 ab = rf_v3_sub(T->b, T->a), bc = rf_v3_sub(T->c, T->b), ca = rf_v3_sub(T->a, T->c);
    double orient = rf_v3_dot(rf_v3_cross(ab, rf_v3_scale(ca, -1.0)), T->n) >= 0 ? 1.0 : -1.0;
    if (!(orient * rf_v3_dot(rf_v3_cross(ab, rf_v3_sub(q, T->a)), T->n) >= 0.0))
        return 0;
    if (!(orient * rf_v3_dot(rf_v3_cross(bc, rf_v3_sub(q, T->b)), T->n) >= 0.0))
        return 0;
    return orient * rf_v3_dot(rf_v3_cross(ca, rf_v3_sub(q, T->c)), T->n) >= 0.0;
}

/* Bounding box of the arc over [t0, t1] (componentwise extremes). */
static void arc_box(const rf_arc *arc, double t0, double t1, rf_vec3 *lo, rf_vec3 *hi)
{
    rf_vec3 a = rf_arc_pos(arc, t0), b = rf_arc_pos(arc, t1);
    double l[3] = {dmin(a.x, b.x), dmin(a.y, b.y), dmin(a.z, b.z)};
    double h[3] = {dmax(a.x, b.x), dmax(a.y, b.y), dmax(a.z, b.z)};
    double p[3] = {arc->p.x, arc->p.y, arc->p.z};
    double v[3] = {arc->v.x, arc->v.y, arc->v.z};
    double ac[3] = {arc->a.x, arc->a.y, arc->a.z};
    for (int k = 0; k < 3; k++) {
        if (ac[k] != 0.0) {
            double tv = -v[k] / ac[k];
            if (tv > t0 && tv < t1) {
                double x = p[k] + v[k] * tv + 0.5 * ac[k] * tv * tv;
                l[k] = dmin(l[k], x);
                h[k] = dmax(h[k], x);
            }
        }
    }
    *lo = rf_v3(l[0], l[1], l[2]);
    *hi = rf_v3(h[0], h[1], h[2]);
}

static double box_point_dist2(rf_vec3 lo, rf_vec3 hi, rf_vec3 q)
{
    double dx = dmax(0.0, dmax(lo.x - q.x, q.x - hi.x));
    double dy = dmax(0.0, dmax(lo.y - q.y, q.y - hi.y));
    double dz = dmax(0.0, dmax(lo.z - q.z, q.z - hi.z));
    return dx * dx + dy * dy + dz * dz;
}


static double box_box_dist2(rf_vec3 alo, rf_vec3 ahi, rf_vec3 blo, rf_vec3 bhi)
{
    double dx = dmax(0.0, dmax(alo.x - bhi.x, blo.x - ahi.x));
    double dy = dmax(0.0, dmax(alo.y - bhi.y, blo.y - ahi.y));
    double dz = dmax(0.0, dmax(alo.z - bhi.z, blo.z - ahi.z));
    return dx * dx + dy * dy + dz * dz;
}

/* ---- one triangle ------------------------------------------------------------------- */

/* The planes of the support faces of a surface segment (none in a flight). */
typedef struct support_planes {
    int n;
    rf_vec3 nrm[2];
    double d[2], tol;
} support_planes;

static void support_planes_set(const rf_motion *m, support_planes *sp)
{
    sp->n = 0;
    for (int k = 0; k < m->sup.n && k < 2; k++) {
        const rf_triangle *S = &m->terrain->tri[m->sup.tri[k]];
        sp->nrm[sp->n] = S->n;
        sp->d[sp->n] = S->d;
        sp->n++;
    }
    sp->tol = m->tol_len;
}

typedef struct search {
    rf_motion *m;
    const rf_arc *arc;
    const rf_support *ex;
    double best;      /* earliest contact so far (exclusive bound) */
    int found;
    rf_contact *c;
    double vh; /* the horizontal speed at the start */
    /* a flight (no horizontal acceleration): the horizontal path is the straight line
     * s0 + vh t along the unit direction (ux, uy), at perpendicular offset d0 */
    int line;
    double ux, uy, s0, d0;
    double hr, reach;  /* the line's reach (line_reach) and a centre's reach of a face */
    double zq[3];      /* the centre's height: zq[0] + zq[1] t + zq[2] t^2 */
    support_planes sp; /* a surface segment's support planes (n = 0 in a flight) */
    const rf_contact *skip; /* features passed over (rf_contact_search_near) */
    int nskip;
} search;

/* An arc's horizontal speed at its start (search.vh). */
static double start_hspeed(const rf_arc *arc)
{
    return sqrt(arc->v.x * arc->v.x + arc->v.y * arc->v.y);
}

/* The support planes vertex v is on or below, a bit each, in a surface segment (a
 * centre r above such a plane never reaches it, nor the support's own vertices); none
 * in a flight (the face flown off is touched at the start only as the rock leaves it,
 * which the start rule of the quartic passes over).  A vertex is passed over when it
 * is below any; an edge only when both its ends are below the same plane: between ends
 * below different planes of a crease its points can lie above both. */
static unsigned vertex_out(const support_planes *sp, rf_vec3 v)
{
    unsigned bits = 0;
    for (int k = 0; k < sp->n; k++)
        if (rf_v3_dot(sp->nrm[k], v) - sp->d[k] <= sp->tol)
            bits |= 1u << k;
    return bits;
}

/* 1 when the edge or vertex (kind, index) of triangle idx is one of s->skip (a shared
 * one may be asked for by another holder). */
static int skipped(const search *s, int32_t idx, rf_feature kind, int index)
{
    const rf_triangle *tri = s->m->terrain->tri;
    int e = kind == RF_FEAT_EDGE ? 4 : 0;
    for (int k = 0; k < s->nskip; k++) {
        const rf_contact *c = &s->skip[k];
        if (c->kind == kind && (kind == RF_FEAT_FACE ? c->tri == idx
                                                     : rf_same_feature(&tri[c->tri], c->index | e,
                                                                       &tri[idx], index | e)))
            return 1;
    }
    return 0;
}

/* The earliest contact so far (features in s->skip are passed over by their tests,
 * before any root is sought). */
static void take(search *s, double t, int32_t idx, rf_feature kind, int index, rf_vec3 point)
{
    s->best = t;
    s->found = 1;
    s->c->t = t;
    s->c->tri = idx;
    s->c->kind = kind;
    s->c->index = index;
    s->c->point = point;
}

/* 1 when |W + V t + H t^2| stays above reach over [w0, w1]: a lower bound from the
 * exact expansion about the window's middle. */
static int stays_beyond(rf_vec3 W, rf_vec3 V, rf_vec3 H, double w0, double w1, double reach)
{
    double tm = 0.5 * (w0 + w1), d = 0.5 * (w1 - w0);
    rf_vec3 X = rf_v3_add(W, rf_v3_add(rf_v3_scale(V, tm), rf_v3_scale(H, tm * tm)));
    rf_vec3 D = rf_v3_madd(V, 2.0 * tm, H);
    return rf_v3_norm(X) - rf_v3_norm(D) * d - rf_v3_norm(H) * d * d > reach;
}

/* Entering roots over [w0, w1] of |W + V t + H t^2|^2 = rho^2 (the centre's distance
 * from a vertex, or from an edge's line with W, V, H across the edge): a quartic, not
 * solved when the distance stays beyond reach, with a contact's start rules. */
static int entries(const search *s, rf_vec3 W, rf_vec3 V, rf_vec3 H, double w0, double w1,
                   double roots[3])
{
    double rho = s->m->rho;
    if (stays_beyond(W, V, H, w0, w1, rho + s->m->tol_len))
        return 0;
    double c[5] = {rf_v3_norm2(W) - rho * rho, 2 * rf_v3_dot(W, V),
                   rf_v3_norm2(V) + 2 * rf_v3_dot(W, H), 2 * rf_v3_dot(V, H), rf_v3_norm2(H)};
    double tol = 2 * rho * s->m->tol_len, slope = 2 * rho * RF_APPROACH_EPS;
    return rf_poly_contact_entries(c, w0, w1, tol, slope, 4 * rho * 1e-9, roots);
}

/* Edge from va to vb against the centre over [w0, w1]. */
static void test_edge(search *s, int32_t idx, int ei, rf_vec3 va, rf_vec3 vb, double w0,
                      double w1, rf_vec3 blo, rf_vec3 bhi)
{
    double reach = s->m->rho + s->m->tol_len;
    rf_vec3 elo = rf_v3(dmin(va.x, vb.x), dmin(va.y, vb.y), dmin(va.z, vb.z));
    rf_vec3 ehi = rf_v3(dmax(va.x, vb.x), dmax(va.y, vb.y), dmax(va.z, vb.z));
    if (box_box_dist2(blo, bhi, elo, ehi) > reach * reach ||
        (s->nskip > 0 && skipped(s, idx, RF_FEAT_EDGE, ei)))
        return;
    rf_vec3 e = rf_v3_sub(vb, va);
    double len = rf_v3_norm(e);
    e = rf_v3_scale(e, 1.0 / len);
    const rf_arc *arc = s->arc;
    rf_vec3 w0v = rf_v3_sub(arc->p, va), v = arc->v, h = rf_v3_scale(arc->a, 0.5);
    /* components perpendicular to the edge */
    rf_vec3 W = rf_in_plane(w0v, e), V = rf_in_plane(v, e), H = rf_in_plane(h, e);
    double roots[3];
    int n = entries(s, W, V, H, w0, w1, roots);
    for (int k = 0; k < n; k++) {
        double t = roots[k];
        if (t >= s->best)
            return;
        rf_vec3 w = rf_v3_sub(rf_arc_pos(arc, t), va);
        double sp = rf_v3_dot(w, e), tol = s->m->tol_len;
        if (sp >= -tol && sp <= len + tol) {
            take(s, t, idx, RF_FEAT_EDGE, ei, rf_v3_madd(va, dmin(dmax(sp, 0.0), len), e));
            return;
        }
    }
}

static void test_vertex(search *s, int32_t idx, int vi, rf_vec3 q, double w0, double w1,
                        rf_vec3 blo, rf_vec3 bhi)
{
    double reach = s->m->rho + s->m->tol_len;
    if (box_point_dist2(blo, bhi, q) > reach * reach ||
        (s->nskip > 0 && skipped(s, idx, RF_FEAT_VERTEX, vi)))
        return;
    const rf_arc *arc = s->arc;
    rf_vec3 W = rf_v3_sub(arc->p, q), V = arc->v, H = rf_v3_scale(arc->a, 0.5);
    double roots[3];
    int n = entries(s, W, V, H, w0, w1, roots);
    if (n > 0 && roots[0] < s->best)
        take(s, roots[0], idx, RF_FEAT_VERTEX, vi, q);
}

/* Entering root of the face plane f(t) = n.p(t) - d - rho on [t0, t1] (closed form):
 * the first root where f falls through 0 after being above tol, a start touching and
 * approaching, or a start touching tangentially while curving into the plane. */
static int face_entry(const double f[3], double t0, double t1, double tol, double *t)
{
    double f0 = f[0] + t0 * (f[1] + t0 * f[2]);
    double f1 = f[0] + t1 * (f[1] + t1 * f[2]);
    if (f0 > tol && f1 > 0.0) {
        /* clear of the plane at both ends: a root needs a minimum inside */
        double tv = f[2] > 0.0 ? -f[1] / (2.0 * f[2]) : t0;
        if (!(tv > t0 && tv < t1 && f[0] + tv * (f[1] + tv * f[2]) <= 0.0))
            return 0;
    }
    double d0 = f[1] + 2.0 * f[2] * t0;
    double band = RF_TOUCH_BAND * tol;
    if (f0 <= tol && f0 >= -band) {
        if (d0 < -RF_APPROACH_EPS || (fabs(f0) <= tol && d0 <= RF_APPROACH_EPS && f[2] < -1e-9)) {
            *t = t0;
            return 1;
        }
    }
    double r[2];
    int n = rf_quadratic_roots(f[2], f[1], f[0], r);
    for (int k = 0; k < n; k++) {
        double x = r[k];
        if (!(x > t0 && x <= t1))
            continue;
        /* falling through the plane faster than a graze; from a start on the plane,
         * also after a rise smaller than the tolerance (a hop of a hair) */
        if (!(f[1] + 2.0 * f[2] * x < -RF_APPROACH_EPS))
            continue;
        *t = x;
        return 1;
    }
    if (f0 <= tol && f0 >= -band) {
        /* no crossing, but touching at the start, never clear of the plane (a hop of
         * less than a hair from a hair inside it) and then deeper than the touch band:
         * met when it is that deep, where the contact point is checked */
        double fmin, fmax;
        rf_quadratic_range(f, t0, t1, &fmin, &fmax);
        if (fmax <= tol && fmin < -band) {
            double g[3] = {f[0] + band, f[1], f[2]};
            n = rf_quadratic_roots(g[2], g[1], g[0], r);
            for (int k = 0; k < n; k++) {
                if (r[k] > t0 && r[k] <= t1 && f[1] + 2.0 * f[2] * r[k] < 0.0) {
                    *t = r[k];
                    return 1;
                }
            }
        }
    }
    return 0;
}

/* Centre mode (Eq. 6-7) and the point mass (rho 0): contact while the centre is over
 * the triangle and within rho of its plane, the window over the triangle found exactly
 * from its edges' columns.  A point mass was tested as a sphere's face, at one time
 * from the gathered window's start: one falling along a column's border, a hair under
 * a steep face's plane, lay outside the face along its normal there and fell through
 * it.  The centre's horizontal path is taken as straight (flight).  `left`: the face
 * flown off, met only once the centre moves over its column again. */
static void test_centre(search *s, int32_t idx, double t0, double t1, int left)
{
    const rf_triangle *T = &s->m->terrain->tri[idx];
    const rf_arc *arc = s->arc;
    double tol = s->m->tol_len;
    double f[3] = {rf_v3_dot(T->n, arc->p) - T->d - s->m->rho, rf_v3_dot(T->n, arc->v),
                   0.5 * rf_v3_dot(T->n, arc->a)};
    /* beyond reach of the plane over all of [t0, t1]: never met */
    double fmin, fmax;
    rf_quadratic_range(f, t0, t1, &fmin, &fmax);
    if (fmin > tol)
        return;
    double lo = t0, hi = t1;
    double al[3], be[3]; /* the centre's inward distance from edge k: al + be t */
    rf_vec3 P[3] = {T->a, T->b, T->c};
    const double *hedge = s->m->ws->hedge + 3 * (size_t)idx;
    double orient = (P[1].x - P[0].x) * (P[2].y - P[0].y) - (P[1].y - P[0].y) * (P[2].x - P[0].x);
    if (orient == 0.0)
        return;
    double sg = orient > 0 ? 1.0 : -1.0;
    int at_start = s->sp.n == 0 && t0 == 0.0; /* a flight's start */
    int moves_in = 0, moves_out = 0; /* on the column's border: in over an edge, out over one */
    /* an edge the centre moves along, by less than the tolerance across it over the
     * edge's length, is crossed neither in nor out (along a grid cell's diagonal from a
     * node, rounding had it moving out of one column and, over the other's edge, reach
     * half the tolerance inside only after a minute: it fell through both) */
    double vh = s->vh;
    int crosses[3];
    for (int k = 0; k < 3; k++) {
        rf_vec3 A = P[k], B = P[(k + 1) % 3];
        double ex = B.x - A.x, ey = B.y - A.y;
        double el = hedge[k];
        if (!(el > 0))
            return;
        double alpha = sg * (ex * (arc->p.y - A.y) - ey * (arc->p.x - A.x)) / el;
        double beta = sg * (ex * arc->v.y - ey * arc->v.x) / el;
        al[k] = alpha, be[k] = beta;
        crosses[k] = fabs(beta) * el > tol * vh;
        if (at_start && fabs(alpha) <= tol && crosses[k])
            moves_in |= beta > 0, moves_out |= beta < 0;
        if (beta > 0) {
            lo = dmax(lo, (-tol - alpha) / beta);
        } else if (beta < 0) {
            hi = dmin(hi, (-tol - alpha) / beta);
        } else if (alpha < -tol) {
            return;
        }
    }
    if (!(lo <= hi))
        return;
    /* over the column later, or moving in from its border at a flight's start
     * (moves_in is only set then) */
    int enters = lo > t0 || (moves_in && !moves_out);
    if (left && !enters)
        return; /* the face flown off, over or on its column and not moving in */
    double f_lo = f[0] + lo * (f[1] + lo * f[2]);
    double d_lo = f[1] + 2.0 * f[2] * lo;
    double t;
    if (enters && (f_lo < -tol || (f_lo <= tol && d_lo < -RF_APPROACH_EPS))) {
        /* the centre moves over a face already within reach of its plane (at the start
         * of a flight, when it approaches the plane: a face that falls away from a
         * flight off the column's border is left alone); met where the centre is half the
         * tolerance outside the column's edge: at the tolerance, rounding put it beyond
         * the edge for the face's surface phase, which left the face at once (on the
         * edge, it was met at once again after a reflection off a wall there) */
        double in = lo; /* the centre half the tolerance outside the edges it crosses */
        for (int k = 0; k < 3; k++)
            if (be[k] > 0 && crosses[k])
                in = dmax(in, (-0.5 * tol - al[k]) / be[k]);
        t = dmin(in, hi);
    } else if (!face_entry(f, lo, hi, s->m->tol_len, &t)) {
        return;
    }
    if (t < s->best) {
        rf_vec3 q = rf_v3_madd(rf_arc_pos(arc, t), -(f[0] + t * (f[1] + t * f[2])) - s->m->rho, T->n);
        take(s, t, idx, RF_FEAT_FACE, 0, q);
    }
}

/* Face of triangle idx over [t0, t1].  Returns 1 when its edges and vertices must be
 * tested too, from *w0 on. */
static int test_face(search *s, int32_t idx, double t0, double t1, double *w0)
{
    rf_motion *m = s->m;
    const rf_triangle *T = &m->terrain->tri[idx];
    const rf_arc *arc = s->arc;
    double rho = m->rho, tol = m->tol_len;
    if (t1 > s->best)
        t1 = s->best;
    if (!(t1 >= t0))
        return 0;
    if (m->centre || m->point) {
        /* the face under the centre; a point mass is its own centre.  Below, rho > 0:
         * a sphere in full contact (the only rock the surface phase searches for) */
        test_centre(s, idx, t0, t1, 0);
        return 0;
    }
    double f[3] = {rf_v3_dot(T->n, arc->p) - T->d - rho, rf_v3_dot(T->n, arc->v),
                   0.5 * rf_v3_dot(T->n, arc->a)};
    double f0 = f[0] + t0 * (f[1] + t0 * f[2]);
    double t_face;
    int has = face_entry(f, t0, t1, tol, &t_face);
    if (!has && f0 < -RF_TOUCH_BAND * tol && f0 > -0.5 * rho &&
        f[1] + 2.0 * f[2] * t0 < -RF_APPROACH_EPS)
        has = 1, t_face = t0; /* already within reach and going deeper: met at once */
    if (has) {
        rf_vec3 q = rf_v3_madd(rf_arc_pos(arc, t_face), -rho, T->n);
        /* a sphere's contact point may lie a hair outside, across an edge on the
         * support's plane, which is not tested (a sphere in a concave corner) */
        if (inside_closed(T, q) || inside_margin(T, q) >= -1e-6 * rho) {
            int skip = s->nskip > 0 && skipped(s, idx, RF_FEAT_FACE, 0);
            if (t_face < s->best && !skip)
                take(s, t_face, idx, RF_FEAT_FACE, 0, q);
            if (f0 > tol && !skip)
                return 0; /* nothing of this triangle is met before its plane */
        }
    }
    /* edges and vertices: only once the plane is within reach */
    *w0 = t0;
    if (f0 > tol) {
        if (!has)
            return 0;
        *w0 = t_face;
    }
    return 1;
}

static void test_edges(search *s, int32_t idx, double w0, double t1)
{
    rf_motion *m = s->m;
    const rf_triangle *T = &m->terrain->tri[idx];
    double w1 = t1 < s->best ? t1 : s->best;
    if (!(w1 >= w0))
        return;
    rf_vec3 blo, bhi;
    arc_box(s->arc, w0, w1, &blo, &bhi);
    rf_vec3 tlo = rf_v3(dmin(T->a.x, dmin(T->b.x, T->c.x)), dmin(T->a.y, dmin(T->b.y, T->c.y)),
                        dmin(T->a.z, dmin(T->b.z, T->c.z)));
    rf_vec3 thi = rf_v3(dmax(T->a.x, dmax(T->b.x, T->c.x)), dmax(T->a.y, dmax(T->b.y, T->c.y)),
                        dmax(T->a.z, dmax(T->b.z, T->c.z)));
    double reach = m->rho + m->tol_len;
    if (box_box_dist2(blo, bhi, tlo, thi) > reach * reach)
        return;
    unsigned x[3] = {vertex_out(&s->sp, T->a), vertex_out(&s->sp, T->b), vertex_out(&s->sp, T->c)};
    unsigned live = edge_live(m->ws, idx);
    for (int k = 0; k < 3; k++) {
        rf_vec3 va = rf_tri_vertex(T, k), vb = rf_tri_vertex(T, k + 1);
        if (!(x[k] & x[(k + 1) % 3]) && (live >> k & 1))
            test_edge(s, idx, k, va, vb, w0, w1 < s->best ? w1 : s->best, blo, bhi);
        if (!x[k])
            test_vertex(s, idx, k, va, w0, w1 < s->best ? w1 : s->best, blo, bhi);
    }
}

static int coplanar_with_support(const rf_terrain *t, const rf_support *ex, const rf_triangle *T,
                                 double tol)
{
    if (!ex)
        return 0;
    for (int k = 0; k < ex->n; k++) {
        const rf_triangle *S = &t->tri[ex->tri[k]];
        if (rf_coplanar(S, T, tol))
            return 1;
    }
    return 0;
}

/* ---- shared edges and vertices --------------------------------------------------------
 *
 * Neighbouring triangles share edges and vertices (on a grid an edge belongs to two
 * triangles and a vertex to up to six).  Each distinct feature is tested once per
 * search, when the first pending triangle holding it asks, from that triangle's window
 * start: a sphere touching a feature is within reach of the plane of every triangle
 * holding it (the feature lies in each plane), so any holder's plane entry bounds the
 * contact time from below. */

static inline uint64_t mix64(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    h ^= h >> 33;
    return h;
}

static inline uint64_t point_hash(rf_vec3 p)
{
    uint64_t a, b, c;
    memcpy(&a, &p.x, 8);
    memcpy(&b, &p.y, 8);
    memcpy(&c, &p.z, 8);
    return mix64(a ^ mix64(b ^ mix64(c)));
}

/* Keys of the three edges (k: vertex k to k + 1) and three vertices of triangle idx.
 * Grids: 4 node + type, from the triangle's SW node n (types 0 east, 1 north, 2
 * north-east from that node, 3 the node itself); cell triangle 0 is (SW, SE, NE), 1 is
 * (SW, NE, NW).  Meshes: hashes of the coordinates (vertex keys even, edge keys odd),
 * confirmed by comparing the coordinates. */
/* The key of a mesh edge between vertices of hashes ha and hb (either order). */
static uint64_t mesh_edge_key(uint64_t ha, uint64_t hb)
{
    return ha < hb ? mix64(ha ^ mix64(hb)) : mix64(hb ^ mix64(ha));
}

static void feature_keys(const rf_terrain *t, int32_t idx, uint64_t ek[3], uint64_t vk[3])
{
    if (t->is_grid) {
        uint64_t n = (uint64_t)t->grid_node[idx] >> 1, nx = t->nx;
        if ((t->grid_node[idx] & 1) == 0) {
            vk[0] = 4 * n + 3, vk[1] = 4 * (n + 1) + 3, vk[2] = 4 * (n + nx + 1) + 3;
            ek[0] = 4 * n, ek[1] = 4 * (n + 1) + 1, ek[2] = 4 * n + 2;
        } else {
            vk[0] = 4 * n + 3, vk[1] = 4 * (n + nx + 1) + 3, vk[2] = 4 * (n + nx) + 3;
            ek[0] = 4 * n + 2, ek[1] = 4 * (n + nx), ek[2] = 4 * n + 1;
        }
        return;
    }
    const rf_triangle *T = &t->tri[idx];
    uint64_t h[3] = {point_hash(T->a), point_hash(T->b), point_hash(T->c)};
    for (int k = 0; k < 3; k++) {
        vk[k] = h[k] << 1;
        ek[k] = mesh_edge_key(h[k], h[(k + 1) % 3]) | 1ULL;
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
    const rf_terrain *t = ws->terrain;
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
static int line_window(const search *s, const rf_vec3 *q, int nq, double reach, double *w0,
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
static void test_feature(search *s, int32_t idx, int k, const rf_vec3 *q, int nq, double w0,
                         double tb, rf_vec3 blo, rf_vec3 bhi)
{
    double w1 = tb < s->best ? tb : s->best;
    if (!(w0 < s->best))
        return;
    rf_vec3 lo = blo, hi = bhi;
    if (s->line) {
        if (!line_window(s, q, nq, s->reach, &w0, &w1))
            return;
        arc_box(s->arc, w0, w1, &lo, &hi);
    }
    if (nq == 2)
        test_edge(s, idx, k, q[0], q[1], w0, w1, lo, hi);
    else
        test_vertex(s, idx, k, q[0], w0, w1, lo, hi);
}

/* The edges and vertices of the pending triangles, each distinct one once per
 * generation of the feature table (a flight's pieces share one), up to tb. */
static void test_features(search *s, size_t npend, double tb, rf_vec3 blo, rf_vec3 bhi)
{
    rf_motion *m = s->m;
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->terrain;
    for (size_t p = 0; p < npend; p++) {
        double w0 = ws->pend_w0[p];
        if (!(w0 < s->best))
            continue;
        int32_t idx = ws->pend_idx[p];
        const rf_triangle *T = &t->tri[idx];
        uint64_t ek[3], vk[3];
        feature_keys(t, idx, ek, vk);
        int xv[3] = {-1, -1, -1}; /* vertex_out of vertex k (-1: not known yet) */
        unsigned live = edge_live(ws, idx);
        for (int k = 0; k < 3; k++) {
            int k1 = (k + 1) % 3;
            rf_vec3 q[2] = {rf_tri_vertex(T, k), rf_tri_vertex(T, k1)};
            if ((live >> k & 1) && feat_first(ws, ek[k], idx, k | 4)) {
                for (int i = 0; i < 2; i++) {
                    int v = i ? k1 : k;
                    if (xv[v] < 0)
                        xv[v] = (int)vertex_out(&s->sp, q[i]);
                }
                if (!(xv[k] & xv[k1]))
                    test_feature(s, idx, k, q, 2, w0, tb, blo, bhi);
            }
            if (feat_first(ws, vk[k], idx, k)) {
                if (xv[k] < 0)
                    xv[k] = (int)vertex_out(&s->sp, q[0]);
                if (!xv[k])
                    test_feature(s, idx, k, q, 1, w0, tb, blo, bhi);
            }
        }
    }
}

/* How far from the centre a feature can be met: the contact radius and four length
 * tolerances. */
static double sphere_reach(const rf_motion *m) { return m->rho + 4 * m->tol_len; }

/* How far from a flight's horizontal line a triangle can be met: the reach of the
 * sphere, or in centre mode (the face under the centre) the length tolerance. */
static double line_reach(const rf_motion *m)
{
    return m->centre ? 4 * m->tol_len : sphere_reach(m);
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
static void pend_push(search *s, int32_t idx, double w0, double t1, size_t *npend)
{
    rf_workspace *ws = s->m->ws;
    if (*npend < ws->pend_cap) {
        ws->pend_idx[*npend] = idx;
        ws->pend_w0[*npend] = w0;
        (*npend)++;
    } else {
        test_edges(s, idx, w0, t1);
    }
}

/* The face flown off (or, in a surface segment, the face just left), triangle idx,
 * over [t0, t1]: for a sphere, not its face, but its edges and vertices (pending up to
 * tend), which the rock can come down on (one on the grid's border has no other
 * holder; in a surface segment, a path on the other face of a crease that ended can
 * curve back into one); for a centre, the face once it moves over its column again
 * (off a vertex, it can clip a corner of the next column first). */
static void test_left(search *s, int32_t idx, double t0, double t1, double tend, size_t *npend)
{
    const rf_motion *m = s->m;
    if (m->centre || m->point)
        test_centre(s, idx, t0, t1, 1);
    else
        pend_push(s, idx, t0, tend, npend);
}

/* The edges and vertices of the pending triangles up to tb (lo, hi: the arc's box,
 * unused in a flight): through the table of shared features when it stays at most a
 * third full (a flight's pieces share one table, other searches start afresh),
 * otherwise triangle by triangle. */
static void test_pending(search *s, size_t npend, double tb, rf_vec3 lo, rf_vec3 hi)
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
            test_edges(s, ws->pend_idx[k], ws->pend_w0[k], tb);
}

/* A flight (s->line) over [0, T]: candidate idx, unless already tested in this search,
 * over the whole time it is within reach of the centre (so once per search); its face
 * now, its edges and vertices pending when its plane is reached before the earliest
 * contact found. */
static void line_candidate(search *s, int32_t idx, double T, size_t *npend)
{
    rf_motion *m = s->m;
    rf_workspace *ws = m->ws;
    if (ws->tested[idx] == ws->test_epoch)
        return;
    ws->tested[idx] = ws->test_epoch;
    const rf_triangle *Tr = &m->terrain->tri[idx];
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
    if (m->centre) {
        /* as test_candidates: the centre meets a face r / n.z above its plane */
        if (zt < zlo - reach / dmax(Tr->n.z, 1e-12) ||
            dmin(Tr->a.z, dmin(Tr->b.z, Tr->c.z)) > zhi + reach)
            return;
    } else if (zt < zlo - reach) {
        return;
    }
    if (excluded_tri(s->ex, idx)) {
        test_left(s, idx, tl, th, T, npend);
        return;
    }
    double w0;
    if (test_face(s, idx, tl, th, &w0)) {
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
static void test_line_candidates(search *s, const int32_t *cand, size_t n, double T)
{
    pend_reserve(s->m->ws, n);
    size_t npend = 0;
    for (size_t k = 0; k < n; k++)
        line_candidate(s, cand[k], T, &npend);
    rf_vec3 z = rf_v3(0, 0, 0);
    test_pending(s, npend, T, z, z);
}

/* The far edges of a grid terrain's nodes. */
static void grid_far(const rf_terrain *t, double *xmax, double *ymax)
{
    *xmax = t->x0 + (double)(t->nx - 1) * t->cell;
    *ymax = t->y0 + (double)(t->ny - 1) * t->cell;
}

/* A flight over a grid terrain in centre mode or of a point mass (the face under the
 * centre, within the length tolerance of the line): the cells under its horizontal
 * line in the order it crosses them, each stretch of the line a piece with the cells
 * within reach of it, until a cell left after the earliest contact found. */
static void walk_grid(search *s, double T)
{
    const rf_terrain *t = s->m->terrain;
    double hr = s->hr;
    double px = s->arc->p.x, py = s->arc->p.y, vx = s->arc->v.x, vy = s->arc->v.y;
    double c = t->cell;
    /* the time over the grid, widened by the reach (slabs in x and y) */
    double ta = 0.0, tb = T;
    double xmax, ymax;
    grid_far(t, &xmax, &ymax);
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
        double t1 = k > steps ? tb : dmin(dmax(dmin(tx, ty), t0), tb);
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
static void test_candidates(search *s, const int32_t *cand, size_t n, double ta, double tb,
                            rf_vec3 lo, rf_vec3 hi)
{
    rf_motion *m = s->m;
    rf_workspace *ws = m->ws;
    const rf_terrain *t = m->terrain;
    const rf_support *ex = s->ex;
    double reach = sphere_reach(m);
    double xl = lo.x - reach, xh = hi.x + reach, yl = lo.y - reach, yh = hi.y + reach;
    double zl = lo.z - reach, zh = hi.z + reach;
    pend_reserve(ws, n);
    size_t npend = 0;
    for (size_t k = 0; k < n; k++) {
        int32_t idx = cand[k];
        const rf_triangle *Tr = &t->tri[idx];
        /* the triangle's box against the arc's box widened by the reach */
        if ((Tr->a.x < xl && Tr->b.x < xl && Tr->c.x < xl) ||
            (Tr->a.x > xh && Tr->b.x > xh && Tr->c.x > xh) ||
            (Tr->a.y < yl && Tr->b.y < yl && Tr->c.y < yl) ||
            (Tr->a.y > yh && Tr->b.y > yh && Tr->c.y > yh) ||
            (Tr->a.z > zh && Tr->b.z > zh && Tr->c.z > zh))
            continue;
        /* below: in centre mode the centre meets a face r / n.z above its plane,
         * more than r above its vertices on a steep face */
        double zlow = m->centre ? lo.z - reach / dmax(Tr->n.z, 1e-12) : zl;
        if (Tr->a.z < zlow && Tr->b.z < zlow && Tr->c.z < zlow)
            continue;
        if (excluded_tri(ex, idx)) {
            test_left(s, idx, ta, tb, tb, &npend); /* the support faces were dropped before */
            continue;
        }
        double w0;
        if (test_face(s, idx, ta, tb, &w0))
            pend_push(s, idx, w0, tb, &npend);
    }
    test_pending(s, npend, tb, lo, hi);
}

/* Contact normal at the contact time. */
static void finish(const rf_motion *m, const rf_arc *arc, rf_contact *c)
{
    rf_vec3 p = rf_arc_pos(arc, c->t);
    if (c->kind == RF_FEAT_FACE) {
        c->n = m->terrain->tri[c->tri].n;
    } else {
        rf_vec3 d = rf_v3_sub(p, c->point);
        double dl = rf_v3_norm(d);
        c->n = dl > 0 ? rf_v3_scale(d, 1.0 / dl) : m->terrain->tri[c->tri].n;
    }
}

/* The arc over [0, T] in pieces along it, in order (s->line: a flight, each triangle
 * tested once over all the time it is within reach), until the first piece that ends
 * after the earliest contact found. */
static void search_pieces(search *s, double T)
{
    rf_motion *m = s->m;
    const rf_terrain *t = m->terrain;
    const rf_arc *arc = s->arc;
    double reach = sphere_reach(m);
    /* higher than this above the terrain's top, nothing is met: the reach (in centre
     * mode the centre meets a face r / n.z above its plane, the furthest above the
     * steepest face; a rock lifted onto a steep face at the top and let fall again
     * fell through it) */
    double up = m->centre ? reach / m->ws->nz_min : reach;
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
        piece = dmax(4.0 * cell, 2.0 * m->rho);
    }
    long npieces = (long)ceil(hlen / piece);
    if (npieces < 1)
        npieces = 1;
    if (npieces > 1000000)
        npieces = 1000000;
    for (long i = 0; i < npieces; i++) {
        double ta = T * (double)i / (double)npieces;
        double tb = i + 1 == npieces ? T : T * (double)(i + 1) / (double)npieces;
        if (ta >= s->best)
            break;
        rf_vec3 lo, hi;
        arc_box(arc, ta, dmin(tb, s->best), &lo, &hi);
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
    const rf_terrain *t = m->terrain;
    search s = {m, arc, ex, INFINITY, 0, c, start_hspeed(arc)};
    if (!(T >= 0))
        return 0;
    double vh0 = s.vh;
    if (arc->a.x == 0.0 && arc->a.y == 0.0 && vh0 * T > 1e-3 * m->rho) {
        s.line = 1;
        s.ux = arc->v.x / vh0;
        s.uy = arc->v.y / vh0;
        s.s0 = s.ux * arc->p.x + s.uy * arc->p.y;
        s.d0 = s.ux * arc->p.y - s.uy * arc->p.x;
        s.hr = line_reach(m);
        s.reach = sphere_reach(m);
        s.zq[0] = arc->p.z, s.zq[1] = arc->v.z, s.zq[2] = 0.5 * arc->a.z;
        rf_workspace *ws = m->ws;
        if (++ws->test_epoch == 0) { /* a new mark for the triangles tested */
            memset(ws->tested, 0, t->ntri * sizeof *ws->tested);
            ws->test_epoch = 1;
        }
    }
    if (s.line && t->is_grid && (m->centre || m->point))
        walk_grid(&s, T);
    else
        search_pieces(&s, T);
    if (!s.found)
        return 0;
    finish(m, arc, c);
    return 1;
}

/* 1 when every vertex of T is on or below one support plane, the same for all three:
 * T lies in that plane's lower half-space, which the sphere, touching the plane from
 * above, never enters.  (Vertices below different planes of a crease are not enough: a
 * point between them can lie above both.) */
static int vertices_below(const support_planes *sp, const rf_triangle *T)
{
    unsigned x = vertex_out(sp, T->a);
    if (x)
        x &= vertex_out(sp, T->b);
    if (x)
        x &= vertex_out(sp, T->c);
    return x != 0;
}

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

void rf_tri_box_build(const rf_terrain *t, float *box)
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

void rf_hedge_build(const rf_terrain *t, double *hedge)
{
    for (size_t i = 0; i < t->ntri; i++, hedge += 3) {
        const rf_triangle *T = &t->tri[i];
        rf_vec3 P[3] = {T->a, T->b, T->c};
        for (int k = 0; k < 3; k++)
            hedge[k] = hypot(P[(k + 1) % 3].x - P[k].x, P[(k + 1) % 3].y - P[k].y);
    }
}

int rf_contact_search_near(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                           const rf_contact *skip, int nskip, rf_contact *c)
{
    search s = {m, arc, ex, INFINITY, 0, c, start_hspeed(arc)};
    s.skip = skip;
    s.nskip = nskip;
    if (!(T >= 0))
        return 0;
    rf_vec3 lo, hi;
    arc_box(arc, 0.0, T, &lo, &hi);
    /* the candidates whose boxes meet the arc's box widened by the reach */
    rf_workspace *ws = m->ws;
    double reach = sphere_reach(m);
    double xl = lo.x - reach, xh = hi.x + reach, yl = lo.y - reach, yh = hi.y + reach;
    double zl = lo.z - reach, zh = hi.z + reach;
    size_t nhit = 0;
    const float *box = ws->tri_box;
    const rf_terrain *t = m->terrain;
    int filter = !m->centre && !m->point;
    support_planes_set(m, &s.sp);
    size_t n = rf_gather(m, xl, yl, xh, yh);
    if (rf_grow((void **)&ws->near_hit, &ws->near_cap, n, sizeof *ws->near_hit))
        return 0;
    for (size_t k = 0; k < n; k++) {
        int32_t idx = ws->cand[k];
        const float *b = box + 6 * (size_t)idx;
        if (b[1] < xl || b[0] > xh || b[3] < yl || b[2] > yh || b[5] < zl || b[4] > zh)
            continue;
        if (excluded_tri(&m->sup, idx))
            continue;
        if (filter) {
            /* faces in a support's plane or wholly on or below a support plane are out
             * of reach for the whole segment */
            const rf_triangle *Tr = &t->tri[idx];
            if (coplanar_with_support(t, &m->sup, Tr, m->tol_len) || vertices_below(&s.sp, Tr))
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

/* ---- concave edges ---------------------------------------------------------------------
 *
 * The point of the terrain closest to a centre above it is never inside a strictly
 * concave edge (there the two faces rise from the edge: the centre would have to be
 * below them), so a rock from above meets such an edge only together with a face,
 * another edge or a vertex, which the search finds.  Its edge test is skipped.  Edges
 * on the border, shared by other than two triangles, or whose faces are within about
 * 1e-6 rad of one plane are always tested. */

#define CONCAVE_MIN_ANGLE 1e-6

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
    return hb > CONCAVE_MIN_ANGLE * db && ha > CONCAVE_MIN_ANGLE * da && db > 0 && da > 0;
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

/* Bit k: edge k of triangle idx can be met first. */
static inline unsigned edge_live(rf_workspace *ws, int32_t idx)
{
    if (!(ws->edge_live[idx] & 8))
        grid_edge_live(ws->terrain, ws->edge_live, idx);
    return ws->edge_live[idx];
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
    return fabs(ux * wy - uy * wx) > 1e-12 * (ux * ux + uy * uy + wx * wx + wy * wy);
}

int rf_edge_live_build(const rf_terrain *t, uint8_t *live)
{
    if (t->is_grid) {
        memset(live, 0, t->ntri ? t->ntri : 1); /* found when first asked for */
        return 0;
    }
    memset(live, 8 | 7, t->ntri ? t->ntri : 1);
    size_t n = 3 * t->ntri;
    edge_ref *r = malloc((n ? n : 1) * sizeof *r);
    if (!r)
        return -1;
    for (size_t i = 0; i < t->ntri; i++)
        for (int k = 0; k < 3; k++) {
            uint64_t ha = point_hash(rf_tri_vertex(&t->tri[i], k)),
                     hb = point_hash(rf_tri_vertex(&t->tri[i], k + 1));
            r[3 * i + (size_t)k] = (edge_ref){mesh_edge_key(ha, hb), (int32_t)i, k};
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

/* ---- leaving the terrain -------------------------------------------------------------- */

/* Time at which the straight horizontal line p + v t enters the 2D triangle (A, B, C),
 * within [t0, t1], and in *out the time it leaves it (at most t1); INFINITY when it
 * does not (a start inside counts as t0). */
static double line_enters_triangle(rf_vec3 p, rf_vec3 v, const double *xy, double t0, double t1,
                                   double *out)
{
    *out = t1;
    double orient = (xy[2] - xy[0]) * (xy[5] - xy[1]) - (xy[3] - xy[1]) * (xy[4] - xy[0]);
    double sg = orient > 0 ? 1.0 : -1.0;
    double lo = t0, hi = t1;
    for (int k = 0; k < 3; k++) {
        int j = (k + 1) % 3;
        double ex = xy[2 * j] - xy[2 * k], ey = xy[2 * j + 1] - xy[2 * k + 1];
        double alpha = sg * (ex * (p.y - xy[2 * k + 1]) - ey * (p.x - xy[2 * k]));
        double beta = sg * (ex * v.y - ey * v.x);
        if (beta > 0)
            lo = dmax(lo, -alpha / beta);
        else if (beta < 0)
            hi = dmin(hi, -alpha / beta);
        else if (alpha < 0)
            return INFINITY;
    }
    /* only the interior counts: a path along the border stays on the terrain */
    *out = hi;
    return lo < hi ? lo : INFINITY;
}

/* 1 when no triangle holds the centre's horizontal path at time tm. */
static int over_gap(const rf_terrain *t, const rf_arc *arc, double tm)
{
    return rf_terrain_locate(t, arc->p.x + arc->v.x * tm, arc->p.y + arc->v.y * tm) < 0;
}

/* Grids: the earliest time in [ta, tb] the path enters a nodata triangle of the cells
 * around it (te: the end of the whole path); INFINITY when none. */
static double grid_gap_entry(const rf_terrain *t, const rf_arc *arc, double ta, double tb,
                             double te)
{
    double cell = t->cell;
    double xa = arc->p.x + arc->v.x * ta, xb = arc->p.x + arc->v.x * tb;
    double ya = arc->p.y + arc->v.y * ta, yb = arc->p.y + arc->v.y * tb;
    size_t ncx = t->nx - 1, ncy = t->ny - 1;
    long i0 = (long)floor((dmin(xa, xb) - t->x0) / cell) - 1;
    long i1 = (long)floor((dmax(xa, xb) - t->x0) / cell) + 1;
    long j0 = (long)floor((dmin(ya, yb) - t->y0) / cell) - 1;
    long j1 = (long)floor((dmax(ya, yb) - t->y0) / cell) + 1;
    if (i0 < 0)
        i0 = 0;
    if (j0 < 0)
        j0 = 0;
    if (i1 > (long)ncx - 1)
        i1 = (long)ncx - 1;
    if (j1 > (long)ncy - 1)
        j1 = (long)ncy - 1;
    double best = INFINITY;
    for (long j = j0; j <= j1; j++)
        for (long ii = i0; ii <= i1; ii++)
            for (int k = 0; k < 2; k++) {
                if (t->grid_tri[2 * ((size_t)j * ncx + (size_t)ii) + (size_t)k] >= 0)
                    continue;
                double x0 = t->x0 + (double)ii * cell, y0 = t->y0 + (double)j * cell;
                double x1 = x0 + cell, y1 = y0 + cell;
                /* k = 0: SW, SE, NE;  k = 1: SW, NE, NW */
                double xy[6] = {x0, y0, x1, k == 0 ? y0 : y1, k == 0 ? x1 : x0, y1};
                double out, th = line_enters_triangle(arc->p, arc->v, xy, ta, te, &out);
                /* over the hole only if no triangle holds the centre halfway across it
                 * (a path along a hole's border stays on the terrain; a point a hair
                 * past the border was still on the cell next to it, within the
                 * locator's tolerance, on large cells) */
                if (th <= tb && th < best && over_gap(t, arc, 0.5 * (th + out)))
                    best = th;
            }
    return best;
}

/* Meshes: the earliest time in [ta, tb] the path crosses outwards an edge that only one
 * triangle holds in plan (a border of the mesh or of a hole in it) into where no
 * triangle is; INFINITY when it does not.  A gap narrower than `bridge` along the path
 * (a sphere in full contact: r) is passed over, as is a crack at a seam between two
 * files of the mesh narrower than a hundredth of the triangles' size.  vh: the path's
 * horizontal speed. */
static double mesh_gap_entry(rf_motion *m, const rf_arc *arc, double vh, double ta, double tb,
                             double bridge)
{
    const rf_terrain *t = m->terrain;
    double xa = arc->p.x + arc->v.x * ta, xb = arc->p.x + arc->v.x * tb;
    double ya = arc->p.y + arc->v.y * ta, yb = arc->p.y + arc->v.y * tb;
    double pad = 4 * m->tol_len;
    size_t n = rf_gather(m, dmin(xa, xb) - pad, dmin(ya, yb) - pad, dmax(xa, xb) + pad,
                         dmax(ya, yb) + pad);
    double best = INFINITY;
    for (size_t i = 0; i < n; i++) {
        int32_t idx = m->ws->cand[i];
        unsigned border = m->ws->edge_live[idx] / RF_EDGE_BORDER;
        if (!border)
            continue;
        const rf_triangle *T = &t->tri[idx];
        for (int k = 0; k < 3; k++) {
            if (!(border >> k & 1))
                continue;
            rf_vec3 A = rf_tri_vertex(T, k), B = rf_tri_vertex(T, k + 1), C = rf_tri_vertex(T, k + 2);
            double ex = B.x - A.x, ey = B.y - A.y, el = m->ws->hedge[3 * (size_t)idx + k];
            /* the side of the edge line the centre is on: s0 + s1 t, the triangle's
             * side positive */
            double sc = ex * (C.y - A.y) - ey * (C.x - A.x);
            if (!(el > 0) || sc == 0.0)
                continue;
            double sg = sc > 0 ? 1.0 : -1.0;
            double s0 = sg * (ex * (arc->p.y - A.y) - ey * (arc->p.x - A.x));
            double s1 = sg * (ex * arc->v.y - ey * arc->v.x);
            if (!(s1 < 0))
                continue; /* not moving outwards */
            /* the crossing; one more than a few tolerances behind the start was
             * before it (a gap under the start is the caller's) */
            if (s0 < -pad * el)
                continue;
            double th = dmax(0.0, -s0 / s1);
            if (!(th <= tb) || th >= best)
                continue;
            /* along the edge, from A (within a few tolerances of its ends) */
            double u = ((arc->p.x + arc->v.x * th - A.x) * ex +
                        (arc->p.y + arc->v.y * th - A.y) * ey) / el;
            if (u < -pad || u > el + pad)
                continue;
            /* a gap when the centre is over no triangle `bridge` past the edge (and
             * at least a hundredth of the holder's height over it, far beyond the
             * locator's tolerance), along the path, but no more than 100 times that
             * for a path nearly along the edge */
            double d = dmax(bridge, 0.01 * fabs(sc) / el);
            double dt = d * dmin(vh * el / -s1, 100.0) / vh;
            if (over_gap(t, arc, th + dt))
                best = th;
        }
    }
    return best;
}

double rf_terrain_exit_time(rf_motion *m, const rf_arc *arc, double T)
{
    const rf_terrain *t = m->terrain;
    double te = T;
    double px = arc->p.x, py = arc->p.y, vx = arc->v.x, vy = arc->v.y;
    double xmin = t->xmin, xmax = t->xmax, ymin = t->ymin, ymax = t->ymax;
    if (t->is_grid) {
        xmin = t->x0;
        ymin = t->y0;
        grid_far(t, &xmax, &ymax);
    }
    if (vx > 0)
        te = dmin(te, (xmax - px) / vx);
    else if (vx < 0)
        te = dmin(te, (xmin - px) / vx);
    if (vy > 0)
        te = dmin(te, (ymax - py) / vy);
    else if (vy < 0)
        te = dmin(te, (ymin - py) / vy);
    if (te < 0)
        te = 0;
    if (!m->ws->has_gaps)
        return te;
    double vh = hypot(vx, vy);
    /* meshes: a gap under the start, still there `bridge` on (a grid's: a start inside
     * a nodata triangle, below) */
    double bridge = m->centre || m->point ? 0.0 : m->rho;
    if (!t->is_grid && over_gap(t, arc, 0.0) &&
        (!(vh > 0) || over_gap(t, arc, dmax(bridge, 0.01 * t->bsize) / vh)))
        return 0.0;
    /* the gaps along the path, a few cells at a time */
    double cell = t->is_grid ? t->cell : t->bsize;
    long npieces = (long)ceil(vh * te / (8.0 * cell));
    if (npieces < 1)
        npieces = 1;
    for (long i = 0; i < npieces; i++) {
        double ta = te * (double)i / (double)npieces, tb = te * (double)(i + 1) / (double)npieces;
        double best = t->is_grid ? grid_gap_entry(t, arc, ta, tb, te)
                                  : mesh_gap_entry(m, arc, vh, ta, tb, bridge);
        if (best < INFINITY)
            return best;
    }
    return te;
}

/* 1 when terrain t has holes: a nodata triangle of a grid; a border edge in plan of a
 * mesh (RF_EDGE_BORDER) whose ends do not both lie on one side of the bounding box. */
int rf_terrain_has_gaps(const rf_terrain *t, const uint8_t *live)
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

/* ---- distances --------------------------------------------------------------------- */

double rf_feature_distance(const rf_terrain *t, const rf_contact *c, rf_vec3 p)
{
    const rf_triangle *T = &t->tri[c->tri];
    switch (c->kind) {
    case RF_FEAT_FACE:
        return rf_v3_dot(T->n, p) - T->d;
    case RF_FEAT_EDGE: {
        rf_vec3 q = rf_v3_closest_on_segment(rf_tri_vertex(T, c->index), rf_tri_vertex(T, c->index + 1), p);
        return rf_v3_norm(rf_v3_sub(p, q));
    }
    default:
        return rf_v3_norm(rf_v3_sub(p, rf_tri_vertex(T, c->index)));
    }
}

double rf_closest_feature(rf_motion *m, rf_vec3 p, double reach, rf_contact *c)
{
    const rf_terrain *t = m->terrain;
    size_t n = rf_gather(m, p.x - reach, p.y - reach, p.x + reach, p.y + reach);
    double best = INFINITY;
    c->kind = RF_FEAT_EDGE;
    for (size_t k = 0; k < n; k++) {
        int32_t idx = m->ws->cand[k];
        const rf_triangle *T = &t->tri[idx];
        rf_vec3 q = rf_triangle_closest_point(T, p);
        double d = rf_v3_norm(rf_v3_sub(p, q));
        double dplane = fabs(rf_v3_dot(T->n, p) - T->d);
        /* prefer a face over its own edges at the same distance */
        int face = fabs(d - dplane) <= m->tol_len;
        if (d < best - m->tol_len || (d <= best + m->tol_len && face && c->kind != RF_FEAT_FACE)) {
            best = dmin(best, d);
            c->t = 0;
            c->tri = idx;
            c->point = q;
            if (face) {
                c->kind = RF_FEAT_FACE;
                c->index = 0;
                c->n = T->n;
            } else {
                c->kind = RF_FEAT_EDGE;
                c->index = 0;
                for (int i = 0; i < 3; i++) {
                    if (rf_v3_norm(rf_v3_sub(q, rf_tri_vertex(T, i))) <= m->tol_len) {
                        c->kind = RF_FEAT_VERTEX;
                        c->index = i;
                        break;
                    }
                }
                if (c->kind == RF_FEAT_EDGE) {
                    double bd = INFINITY;
                    for (int i = 0; i < 3; i++) {
                        rf_vec3 qq = rf_v3_closest_on_segment(rf_tri_vertex(T, i), rf_tri_vertex(T, i + 1), p);
                        double dd = rf_v3_norm(rf_v3_sub(qq, q));
                        if (dd < bd)
                            bd = dd, c->index = i;
                    }
                }
                rf_vec3 dv = rf_v3_sub(p, q);
                c->n = d > 0 ? rf_v3_scale(dv, 1.0 / d) : T->n;
            }
        }
    }
    return best;
}

/* Widens [*lo, *hi] by the interval in which the vertical line through (x, y) meets
 * the set within rho of triangle T (T swept by the ball: its two offset faces, the
 * cylinders round its edges and the balls round its vertices; the set is convex, so
 * the pieces' intervals make one). */
static void vertical_overlap(const rf_triangle *T, double x, double y, double rho,
                             double *lo, double *hi)
{
    double r2 = rho * rho;
    for (int i = 0; i < 3; i++) {
        rf_vec3 a = rf_tri_vertex(T, i), b = rf_tri_vertex(T, i + 1);
        double ux = x - a.x, uy = y - a.y, u2 = ux * ux + uy * uy;
        if (u2 <= r2) {
            double h = sqrt(r2 - u2);
            *lo = dmin(*lo, a.z - h);
            *hi = dmax(*hi, a.z + h);
        }
        /* the cylinder: |w|^2 - (w.d)^2 / D = rho^2 for w = (ux, uy, s), quadratic in s */
        rf_vec3 d = rf_v3_sub(b, a);
        double H = d.x * d.x + d.y * d.y, D = H + d.z * d.z, ud = ux * d.x + uy * d.y;
        if (!(H > 0))
            continue;
        double disc = ud * ud * d.z * d.z - H * (D * u2 - ud * ud - r2 * D);
        if (!(disc >= 0))
            continue;
        double sq = sqrt(disc);
        for (int k = -1; k <= 1; k += 2) {
            double s = (ud * d.z + k * sq) / H, along = (ud + s * d.z) / D;
            if (along >= 0 && along <= 1) {
                *lo = dmin(*lo, a.z + s);
                *hi = dmax(*hi, a.z + s);
            }
        }
    }
    if (T->n.z > 1e-12) {
        /* each offset face is met where the foot of the line's point lies in T (n.z
         * >= 0: the normals point up) */
        double zp = rf_triangle_z_at(T, x, y), dz = rho / T->n.z;
        if (inside_closed(T, rf_v3_madd(rf_v3(x, y, zp + dz), -rho, T->n)))
            *hi = dmax(*hi, zp + dz);
        if (inside_closed(T, rf_v3_madd(rf_v3(x, y, zp - dz), rho, T->n)))
            *lo = dmin(*lo, zp - dz);
    }
}

double rf_clear_height(rf_motion *m, rf_vec3 p)
{
    const rf_terrain *t = m->terrain;
    double rho = m->rho, z = p.z;
    size_t n = rf_gather(m, p.x - rho, p.y - rho, p.x + rho, p.y + rho);
    /* the lowest z >= p.z outside every triangle's interval: raised past each interval
     * it lies in until none is left (each pass clears at least one) */
    for (size_t pass = 0; pass <= n; pass++) {
        int moved = 0;
        for (size_t k = 0; k < n; k++) {
            double lo = INFINITY, hi = -INFINITY;
            vertical_overlap(&t->tri[m->ws->cand[k]], p.x, p.y, rho, &lo, &hi);
            if (lo < z && z < hi) {
                z = hi;
                moved = 1;
            }
        }
        if (!moved)
            break;
    }
    return z;
}

int32_t rf_face_beyond(const rf_terrain *t, int32_t from, rf_vec3 q, rf_vec3 dir)
{
    double h = rf_v3_hnorm(dir);
    if (!(h > 0))
        return rf_terrain_locate(t, q.x, q.y);
    double ux = dir.x / h, uy = dir.y / h;
    double scale = 1.0 + dmax(fabs(q.x), fabs(q.y)) * 1e-9;
    int32_t idx = -1;
    for (double step = 1e-7 * scale; step < 1e-3; step *= 10) {
        idx = rf_terrain_locate(t, q.x + step * ux, q.y + step * uy);
        if (idx != from)
            return idx;
    }
    return idx;
}
