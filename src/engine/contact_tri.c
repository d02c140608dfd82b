/* contact_tri.c - the contact tests of one triangle: its face, edges and vertices
 * against the centre's arc (a quadratic for a plane, a quartic for a line or a point). */
#include "engine/contact_tri.h"

#include <math.h>
#include <string.h>

#include "engine/geometry.h"
#include "engine/tables.h"

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* ---- triangle helpers ---------------------------------------------------------------- */



int rf_excluded_tri(const rf_support *ex, int32_t idx)
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

/* Bounding box of the arc over [t0, t1] (componentwise extremes). */
void rf_arc_box(const rf_arc *arc, double t0, double t1, rf_vec3 *lo, rf_vec3 *hi)
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


void rf_support_planes_set(const rf_motion *m, rf_support_planes *sp)
{
    sp->n = 0;
    for (int k = 0; k < m->rock.sup.n && k < 2; k++) {
        const rf_triangle *S = RF_FACE(m, m->rock.sup.tri[k]);
        sp->nrm[sp->n] = S->n;
        sp->d[sp->n] = S->d;
        sp->n++;
    }
    sp->tol = m->cfg.tol_len;
}


/* An arc's horizontal speed at its start (search.vh). */
double rf_start_hspeed(const rf_arc *arc)
{
    return sqrt(arc->v.x * arc->v.x + arc->v.y * arc->v.y);
}

/* The support planes vertex v is on or below, a bit each, in a surface segment (a
 * centre r above such a plane never reaches it, nor the support's own vertices); none
 * in a flight (the face flown off is touched at the start only as the rock leaves it,
 * which the start rule of the quartic passes over).  A vertex is passed over when it
 * is below any; an edge only when both its ends are below the same plane: between ends
 * below different planes of a crease its points can lie above both. */
unsigned rf_vertex_out(const rf_support_planes *sp, rf_vec3 v)
{
    unsigned bits = 0;
    for (int k = 0; k < sp->n; k++)
        if (rf_v3_dot(sp->nrm[k], v) - sp->d[k] <= sp->tol)
            bits |= 1u << k;
    return bits;
}

/* 1 when the edge or vertex (kind, index) of triangle idx is one of s->skip (a shared
 * one may be asked for by another holder). */
static int skipped(const rf_search *s, int32_t idx, rf_feature kind, int index)
{
    int e = kind == RF_FEAT_EDGE ? 4 : 0;
    for (int k = 0; k < s->nskip; k++) {
        const rf_contact *c = &s->skip[k];
        if (c->kind == kind && (kind == RF_FEAT_FACE ? c->tri == idx
                                                     : rf_same_feature(RF_FACE(s->m, c->tri), c->index | e,
                                                                       RF_FACE(s->m, idx), index | e)))
            return 1;
    }
    return 0;
}

/* The earliest contact so far (features in s->skip are passed over by their tests,
 * before any root is sought). */
static void take(rf_search *s, double t, int32_t idx, rf_feature kind, int index, rf_vec3 point)
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
static int entries(const rf_search *s, rf_vec3 W, rf_vec3 V, rf_vec3 H, double w0, double w1,
                   double roots[3])
{
    double rho = s->m->cfg.rho;
    if (stays_beyond(W, V, H, w0, w1, rho + s->m->cfg.tol_len))
        return 0;
    double c[5] = {rf_v3_norm2(W) - rho * rho, 2 * rf_v3_dot(W, V),
                   rf_v3_norm2(V) + 2 * rf_v3_dot(W, H), 2 * rf_v3_dot(V, H), rf_v3_norm2(H)};
    double tol = 2 * rho * s->m->cfg.tol_len, slope = 2 * rho * RF_APPROACH_EPS;
    return rf_poly_contact_entries(c, w0, w1, tol, slope, 4 * rho * RF_CURVE_EPS, roots);
}

/* Edge from va to vb against the centre over [w0, w1]. */
void rf_test_edge(rf_search *s, int32_t idx, int ei, rf_vec3 va, rf_vec3 vb, double w0,
                      double w1, rf_vec3 blo, rf_vec3 bhi)
{
    double reach = s->m->cfg.rho + s->m->cfg.tol_len;
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
        double sp = rf_v3_dot(w, e), tol = s->m->cfg.tol_len;
        if (sp >= -tol && sp <= len + tol) {
            take(s, t, idx, RF_FEAT_EDGE, ei, rf_v3_madd(va, dmin(dmax(sp, 0.0), len), e));
            return;
        }
    }
}

void rf_test_vertex(rf_search *s, int32_t idx, int vi, rf_vec3 q, double w0, double w1,
                        rf_vec3 blo, rf_vec3 bhi)
{
    double reach = s->m->cfg.rho + s->m->cfg.tol_len;
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
        if (d0 < -RF_APPROACH_EPS || (fabs(f0) <= tol && d0 <= RF_APPROACH_EPS && f[2] < -RF_CURVE_EPS)) {
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
 * the triangle (in its column) and within rho of its plane, the window over the
 * triangle found exactly from its edges' columns, never from a sphere's test of the
 * face along its normal.  The centre's horizontal path is taken as straight (flight).
 * `left`: the face flown off, met only once the centre moves over its column again. */
void rf_test_centre(rf_search *s, int32_t idx, double t0, double t1, int left)
{
    const rf_triangle *T = RF_FACE(s->m, idx);
    const rf_arc *arc = s->arc;
    double tol = s->m->cfg.tol_len;
    double f[3] = {rf_v3_dot(T->n, arc->p) - T->d - s->m->cfg.rho, rf_v3_dot(T->n, arc->v),
                   0.5 * rf_v3_dot(T->n, arc->a)};
    /* beyond reach of the plane over all of [t0, t1]: never met */
    double fmin, fmax;
    rf_quadratic_range(f, t0, t1, &fmin, &fmax);
    if (fmin > tol)
        return;
    double lo = t0, hi = t1;
    double al[3], be[3]; /* the centre's inward distance from edge k: al + be t */
    rf_vec3 P[3] = {T->a, T->b, T->c};
    double hedge_buf[3];
    const double *hedge = rf_tri_hedge(s->m->ws->tables, idx, hedge_buf);
    double orient = (P[1].x - P[0].x) * (P[2].y - P[0].y) - (P[1].y - P[0].y) * (P[2].x - P[0].x);
    if (orient == 0.0)
        return;
    double sg = orient > 0 ? 1.0 : -1.0;
    int at_start = s->sp.n == 0 && t0 == 0.0; /* a flight's start */
    int moves_in = 0, moves_out = 0; /* on the column's border: in over an edge, out over one */
    /* an edge the centre moves along, by less than the tolerance across it over the
     * edge's length, is crossed neither in nor out: rounding does not take it out of
     * both columns of the edge at once */
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
         * tolerance outside the column's edge, so that the face's surface phase starts
         * within its column's tolerance, not beyond its edge */
        double in = lo; /* the centre half the tolerance outside the edges it crosses */
        for (int k = 0; k < 3; k++)
            if (be[k] > 0 && crosses[k])
                in = dmax(in, (-0.5 * tol - al[k]) / be[k]);
        t = dmin(in, hi);
    } else if (!face_entry(f, lo, hi, s->m->cfg.tol_len, &t)) {
        return;
    }
    if (t < s->best) {
        rf_vec3 q = rf_v3_madd(rf_arc_pos(arc, t), -(f[0] + t * (f[1] + t * f[2])) - s->m->cfg.rho, T->n);
        take(s, t, idx, RF_FEAT_FACE, 0, q);
    }
}

/* Face of triangle idx over [t0, t1].  Returns 1 when its edges and vertices must be
 * tested too, from *w0 on. */
int rf_test_face(rf_search *s, int32_t idx, double t0, double t1, double *w0)
{
    rf_motion *m = s->m;
    const rf_triangle *T = RF_FACE(m, idx);
    const rf_arc *arc = s->arc;
    double rho = m->cfg.rho, tol = m->cfg.tol_len;
    if (t1 > s->best)
        t1 = s->best;
    if (!(t1 >= t0))
        return 0;
    if (m->cfg.centre || m->cfg.point) {
        /* the face under the centre; a point mass is its own centre.  Below, rho > 0:
         * a sphere in full contact (the only rock the surface phase searches for) */
        rf_test_centre(s, idx, t0, t1, 0);
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
        if (rf_inside_closed(T, q) || inside_margin(T, q) >= -RF_RADIUS_REL_TOL * rho) {
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

void rf_test_edges(rf_search *s, int32_t idx, double w0, double t1)
{
    rf_motion *m = s->m;
    const rf_triangle *T = RF_FACE(m, idx);
    double w1 = t1 < s->best ? t1 : s->best;
    if (!(w1 >= w0))
        return;
    rf_vec3 blo, bhi;
    rf_arc_box(s->arc, w0, w1, &blo, &bhi);
    rf_vec3 tlo = rf_v3(dmin(T->a.x, dmin(T->b.x, T->c.x)), dmin(T->a.y, dmin(T->b.y, T->c.y)),
                        dmin(T->a.z, dmin(T->b.z, T->c.z)));
    rf_vec3 thi = rf_v3(dmax(T->a.x, dmax(T->b.x, T->c.x)), dmax(T->a.y, dmax(T->b.y, T->c.y)),
                        dmax(T->a.z, dmax(T->b.z, T->c.z)));
    double reach = m->cfg.rho + m->cfg.tol_len;
    if (box_box_dist2(blo, bhi, tlo, thi) > reach * reach)
        return;
    unsigned x[3] = {rf_vertex_out(&s->sp, T->a), rf_vertex_out(&s->sp, T->b), rf_vertex_out(&s->sp, T->c)};
    unsigned live = rf_edge_live(m->ws, idx);
    for (int k = 0; k < 3; k++) {
        rf_vec3 va = rf_tri_vertex(T, k), vb = rf_tri_vertex(T, k + 1);
        if (!(x[k] & x[(k + 1) % 3]) && (live >> k & 1))
            rf_test_edge(s, idx, k, va, vb, w0, w1 < s->best ? w1 : s->best, blo, bhi);
        if (!x[k])
            rf_test_vertex(s, idx, k, va, w0, w1 < s->best ? w1 : s->best, blo, bhi);
    }
}

int rf_coplanar_with_support(const rf_terrain *t, const rf_support *ex, const rf_triangle *T,
                                 double tol)
{
    if (!ex)
        return 0;
    for (int k = 0; k < ex->n; k++) {
        const rf_triangle *S = RF_TRI(t, ex->tri[k]);
        if (rf_coplanar(S, T, tol))
            return 1;
    }
    return 0;
}

