/* measures.c - crossings of measure polylines and their outcomes (see measures.h). */
#include "scene/measures.h"

#include <math.h>

#include "base/arc.h" /* rf_quadratic_roots */
#include "base/tolerances.h"
#include "base/util.h"

/* Which side of the path through vertex V, along the horizontal direction (wx, wy),
 * vertex k of l lies on: > 0 left, < 0 right, 0 on the path's line. */
static double side_of(const rf_polyline *l, const double *V, size_t k, double wx, double wy)
{
    const double *Q = &l->xy[2 * k];
    return wx * (Q[1] - V[1]) - wy * (Q[0] - V[0]);
}

/* Walking l from vertex k away from V (step -1 or +1) past the vertices on the path's
 * line: the side of the first vertex off it, or 0 when the line ends on it. */
static double side_beyond(const rf_polyline *l, const double *V, size_t k, int step, double wx,
                          double wy)
{
    for (;;) {
        double sk = side_of(l, V, k, wx, wy);
        if (sk != 0.0 || (step < 0 ? k == 0 : k + 1 == l->n))
            return sk;
        k = step < 0 ? k - 1 : k + 1;
    }
}

/* 1 when the path, through vertex j of l (an inner one) with horizontal direction
 * (wx, wy), does not cross the polyline there: it leaves both neighbouring vertices on
 * one side (it touches the polyline), or it runs along a segment from there or to there
 * (exactly collinear, as on a profile terrain).  Such a stretch is one crossing, at its
 * far end, when the polyline goes on to the other side of the path there than the side
 * it came from, and none when to the same side; a line that ends on the stretch is
 * crossed once, where the path meets its other part. */
static int vertex_touch(const rf_polyline *l, size_t j, double wx, double wy)
{
    if (j == 0 || j + 1 >= l->n)
        return 0;
    /* the nearest vertices on either side that are not V itself (a point repeated) */
    const double *V = &l->xy[2 * j];
    size_t ip = j - 1, in = j + 1;
    while (ip > 0 && l->xy[2 * ip] == V[0] && l->xy[2 * ip + 1] == V[1])
        ip--;
    while (in + 1 < l->n && l->xy[2 * in] == V[0] && l->xy[2 * in + 1] == V[1])
        in++;
    double sp = side_of(l, V, ip, wx, wy), sn = side_of(l, V, in, wx, wy);
    if (sp != 0.0 && sn != 0.0)
        return sp * sn > 0.0;
    if (sp == 0.0 && sn == 0.0)
        return 1; /* inside a stretch along the path */
    /* one arm X along the path, the other on side so */
    size_t ix = sp == 0.0 ? ip : in;
    int step = sp == 0.0 ? -1 : 1;
    double so = sp == 0.0 ? sn : sp;
    double sx = side_beyond(l, V, ix, step, wx, wy);
    const double *X = &l->xy[2 * ix];
    if (wx * (X[0] - V[0]) + wy * (X[1] - V[1]) > 0.0)
        return sx != 0.0; /* the stretch ahead: decided at its far end, if it has one */
    return sx != 0.0 && sx * so > 0.0; /* behind: the side the polyline came from */
}

/* Earliest crossing of segment s of l, A-B, over (t_after, T]; returns the time or
 * INFINITY. */
static double segment_crossing(const rf_polyline *l, size_t s, rf_vec3 p, rf_vec3 v, rf_vec3 a,
                               double t_after, double T, double *u_out)
{
    const double *A = &l->xy[2 * s], *B = A + 2;
    double dx = B[0] - A[0], dy = B[1] - A[1];
    double len2 = dx * dx + dy * dy;
    if (len2 == 0.0)
        return INFINITY;
    /* signed distance (times |AB|) of the horizontal path from the segment's line */
    double nx = -dy, ny = dx;
    double c0 = nx * (p.x - A[0]) + ny * (p.y - A[1]);
    double c1 = nx * v.x + ny * v.y;
    double c2 = 0.5 * (nx * a.x + ny * a.y);
    double r[2];
    int k = rf_quadratic_roots(c2, c1, c0, r);
    if (k == 2 && r[0] == r[1])
        return INFINITY; /* touches the line without crossing it */
    for (int i = 0; i < k; i++) {
        double t = r[i];
        if (!(t > t_after && t <= T))
            continue;
        double x = p.x + v.x * t + 0.5 * a.x * t * t - A[0];
        double y = p.y + v.y * t + 0.5 * a.y * t * t - A[1];
        double u = (x * dx + y * dy) / len2;
        if (u >= -RF_SEGMENT_FRACTION_TOL && u <= 1.0 + RF_SEGMENT_FRACTION_TOL) {
            /* through an inner vertex with both arms on one side: touched (j = 0, no
             * vertex, is an end vertex to vertex_touch: never only touched) */
            size_t j = u <= RF_SEGMENT_FRACTION_TOL ? s : u >= 1.0 - RF_SEGMENT_FRACTION_TOL ? s + 1 : 0;
            if (vertex_touch(l, j, v.x + a.x * t, v.y + a.y * t))
                continue;
            *u_out = rf_fmin(rf_fmax(u, 0.0), 1.0);
            return t;
        }
    }
    return INFINITY;
}

int rf_measures_first_crossings(const rf_measure *ms, size_t n, rf_vec3 p, rf_vec3 v,
                                rf_vec3 a, double t_after, double T, rf_crossing *out,
                                int cap)
{
    /* horizontal bounding box of the path over [t_after, T] */
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    double ts[4] = {rf_fmin(t_after, 0.0), T, -1.0, -1.0};
    if (a.x != 0.0)
        ts[2] = -v.x / a.x;
    if (a.y != 0.0)
        ts[3] = -v.y / a.y;
    for (int i = 0; i < 4; i++) {
        double t = ts[i];
        if (i >= 2 && !(t > ts[0] && t < T))
            continue;
        double x = p.x + v.x * t + 0.5 * a.x * t * t, y = p.y + v.y * t + 0.5 * a.y * t * t;
        xlo = rf_fmin(xlo, x), xhi = rf_fmax(xhi, x), ylo = rf_fmin(ylo, y), yhi = rf_fmax(yhi, y);
    }
    int count = 0;
    double best = INFINITY;
    for (size_t mi = 0; mi < n; mi++) {
        const rf_polyline *l = &ms[mi].line;
        rf_crossing c = {(int)mi, 0, INFINITY, 0.0};
        for (size_t s = 0; s + 1 < l->n; s++) {
            const double *A = &l->xy[2 * s], *B = &l->xy[2 * s + 2];
            if (rf_fmax(A[0], B[0]) < xlo || rf_fmin(A[0], B[0]) > xhi || rf_fmax(A[1], B[1]) < ylo ||
                rf_fmin(A[1], B[1]) > yhi)
                continue;
            double u = 0.0, t = segment_crossing(l, s, p, v, a, t_after, T, &u);
            if (t < c.t) { /* strictly earlier: a vertex crossing stays on its first segment */
                c.segment = s;
                c.t = t;
                c.u = u;
            }
        }
        if (!(c.t <= T))
            continue;
        if (c.t < best - RF_CROSSING_EPS) { /* a new earliest time: drop the later ones */
            best = c.t;
            count = 0;
        } else if (c.t > best + RF_CROSSING_EPS) {
            continue;
        }
        if (count < cap)
            out[count++] = c;
    }
    /* all kept are within RF_CROSSING_EPS of best: it only falls with a reset */
    return count;
}

int rf_measures_first_crossing(const rf_measure *ms, size_t n, rf_vec3 p, rf_vec3 v,
                               rf_vec3 a, double t_after, double T, rf_crossing *c)
{
    return rf_measures_first_crossings(ms, n, p, v, a, t_after, T, c, 1) > 0;
}

rf_outcome rf_measure_outcome(const rf_measure *m, double passing_height_m, double energy_kj)
{
    return rf_measure_kinds[m->kind].outcome(m, passing_height_m, energy_kj);
}
