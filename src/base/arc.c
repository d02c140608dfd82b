/* arc.c - constant-acceleration arcs and the polynomial roots of contact times.
 *
 * Every contact time of the engine is the root of a polynomial in time of degree at
 * most 4: the distance of the centre of a parabola to a plane (degree 2) and the
 * squared distance to a line or a point (degree 4).  Roots are isolated between the
 * critical points (found from the derivative, recursively) and refined by Newton's
 * method kept inside the bracket, so none is skipped and each is located to
 * RF_TIME_TOL.  A quartic whose Bernstein coefficients over the window (or over its
 * halves and quarters) are all above the tolerance stays above it: no root is sought. */
#include "base/arc.h"

#include <math.h>
#include <stddef.h>

double rf_arc_length(rf_vec3 v, rf_vec3 a, double T)
{
    if (!(T > 0))
        return 0.0;
    double A = rf_v3_norm2(a);
    double C = rf_v3_norm2(v);
    if (!(A > RF_QUAD_ZERO))
        return sqrt(C) * T;
    /* |v + a t| = sqrt(A) h(u), h = sqrt(u^2 + k^2), u = t + v.a / A, k = |v x a| / A;
     * the length is sqrt(A) / 2 [u h + k^2 asinh(u / k)] from u0 to u1 = u0 + T, both
     * differences taken without cancellation:
     *   u1 h1 - u0 h0 = T (h1 + u0 (u0 + u1) / (h0 + h1)),
     *   asinh(u1 / k) - asinh(u0 / k) = log1p(T (1 + s) / (u0 + h0))
     *                                 = log1p(T (1 - s) / (h1 - u1)), s = (u0 + u1) / (h0 + h1),
     * the first after the least speed (s >= 0), the second before it; u + h (h - u)
     * for u < 0 (u > 0) as k^2 / (h - u) (k^2 / (h + u)). */
    double u0 = rf_v3_dot(v, a) / A, u1 = u0 + T;
    double k2 = rf_v3_norm2(rf_v3_cross(v, a)) / (A * A);
    double h0 = sqrt(u0 * u0 + k2), h1 = sqrt(u1 * u1 + k2);
    double s = (u0 + u1) / (h0 + h1);
    double len = T * (h1 + u0 * s);
    /* below, the asinh term is under 1e-28 of the length */
    if (k2 > RF_ASINH_REL * (u0 * u0 + u1 * u1)) {
        double L = s >= 0 ? log1p(T * (1.0 + s) / (u0 >= 0 ? u0 + h0 : k2 / (h0 - u0)))
                          : log1p(T * (1.0 - s) / (u1 <= 0 ? h1 - u1 : k2 / (h1 + u1)));
        len += k2 * L;
    }
    return 0.5 * sqrt(A) * len;
}

int rf_quadratic_roots(double c2, double c1, double c0, double r[2])
{
    if (c2 == 0.0) {
        if (c1 == 0.0)
            return 0;
        r[0] = -c0 / c1;
        return 1;
    }
    double disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc < 0.0)
        return 0;
    double q = -0.5 * (c1 + copysign(sqrt(disc), c1));
    double x1 = q / c2;
    double x2 = q != 0.0 ? c0 / q : x1;
    if (x1 > x2) {
        double tmp = x1;
        x1 = x2;
        x2 = tmp;
    }
    r[0] = x1;
    r[1] = x2;
    return 2;
}

double rf_poly_eval(const double *c, int deg, double t)
{
    double p = c[deg];
    for (int i = deg - 1; i >= 0; i--)
        p = p * t + c[i];
    return p;
}

static void derivative(const double *c, int deg, double *d)
{
    for (int i = 1; i <= deg; i++)
        d[i - 1] = (double)i * c[i];
}

/* Root of P in [lo, hi] where P(lo) and P(hi) have opposite signs (or one is 0). */
static double bracketed_root(const double *c, int deg, double lo, double hi, double plo)
{
    double d[4] = {0, 0, 0, 0};
    derivative(c, deg, d);
    int rising = plo < 0;
    double t = 0.5 * (lo + hi);
    for (int it = 0; it < RF_ROOT_MAX_ITER; it++) {
        double p = rf_poly_eval(c, deg, t);
        if (p == 0.0)
            return t;
        if ((p < 0) == rising)
            lo = t;
        else
            hi = t;
        double dp = rf_poly_eval(d, deg - 1, t);
        double tn = dp != 0.0 ? t - p / dp : 0.5 * (lo + hi);
        if (!(tn > lo && tn < hi))
            tn = 0.5 * (lo + hi);
        if (fabs(tn - t) <= RF_ROOT_STEP_TOL + RF_ROOT_REL * fabs(t) ||
            hi - lo <= RF_ROOT_REL * (1 + fabs(t)))
            return tn;
        t = tn;
    }
    return t;
}

/* Where P, falling on [lo, hi] from at least `level` to below it, reaches `level`: a
 * slow crossing of zero that goes on deep is met once it is a touch band deep, where
 * the caller checks that the contact point is on its feature. */
static double level_root(const double *c, int deg, double lo, double hi, double level)
{
    double s[5] = {0, 0, 0, 0, 0};
    for (int k = 0; k <= deg; k++)
        s[k] = c[k];
    s[0] -= level;
    double plo = rf_poly_eval(s, deg, lo);
    return plo <= 0.0 ? lo : bracketed_root(s, deg, lo, hi, plo);
}

/* Critical points of P (roots of P') strictly inside (t0, t1), ascending; count. */
static int critical_points(const double *c, int deg, double t0, double t1, double *cp)
{
    int n = 0;
    double d[4] = {0, 0, 0, 0};
    if (deg <= 1)
        return 0;
    derivative(c, deg, d);
    if (deg <= 3) {
        double r[2];
        int k = rf_quadratic_roots(d[2], d[1], d[0], r);
        for (int i = 0; i < k; i++)
            if (r[i] > t0 && r[i] < t1)
                cp[n++] = r[i];
        return n;
    }
    /* deg 4: P' is a cubic; split at its own critical points and bracket. */
    double dd[3], pts[4];
    derivative(d, 3, dd);
    double r[2];
    int np = 0;
    pts[np++] = t0;
    int k = rf_quadratic_roots(dd[2], dd[1], dd[0], r);
    for (int i = 0; i < k; i++)
        if (r[i] > t0 && r[i] < t1)
            pts[np++] = r[i];
    pts[np++] = t1;
    for (int i = 0; i + 1 < np; i++) {
        double a = pts[i], b = pts[i + 1];
        double pa = rf_poly_eval(d, 3, a), pb = rf_poly_eval(d, 3, b);
        if ((pa < 0 && pb > 0) || (pa > 0 && pb < 0)) {
            double x = bracketed_root(d, 3, a, b, pa);
            if (x > t0 && x < t1 && (n == 0 || x > cp[n - 1]))
                cp[n++] = x;
        } else if (pb == 0.0 && i + 2 < np) {
            cp[n++] = b;
        }
    }
    return n;
}

/* Ends of the pieces of [t0, t1] on which P is monotone: t0, P's critical points
 * inside, t1; their number. */
static int monotone_pieces(const double *c, int deg, double t0, double t1, double pts[5])
{
    int np = 0;
    pts[np++] = t0;
    np += critical_points(c, deg, t0, t1, pts + 1);
    pts[np++] = t1;
    return np;
}

/* P starting within [lo, hi] at pts[0]: 1 and in *t the time it first falls to lo,
 * when it does so before rising above hi; 0 otherwise.  pts[0 .. np-1] are the ends of
 * P's monotone pieces, pv (NULL: evaluated here) P's values there: the ends of each
 * piece tell which bound P leaves by first. */
static int first_below(const double *c, int deg, const double *pts, const double *pv, int np,
                       double lo, double hi, double *t)
{
    for (int i = 1; i < np; i++) {
        double pb = pv ? pv[i] : rf_poly_eval(c, deg, pts[i]);
        if (pb > hi)
            return 0;
        if (pb < lo) {
            *t = level_root(c, deg, pts[i - 1], pts[i], lo);
            return 1;
        }
    }
    return 0;
}

/* 1 when the quartic with Bernstein coefficients b[0 .. 4] over an interval stays
 * above level there: it is a convex combination of them.  Otherwise the halves are
 * tried, down to `depth` more halvings (de Casteljau at the middle). */
static int bernstein4_above(const double b[5], double level, int depth)
{
    if (b[0] <= level || b[4] <= level)
        return 0;
    if (b[1] > level && b[2] > level && b[3] > level)
        return 1;
    if (depth == 0)
        return 0;
    double a1 = 0.5 * (b[0] + b[1]), a2 = 0.5 * (b[1] + b[2]), a3 = 0.5 * (b[2] + b[3]),
           a4 = 0.5 * (b[3] + b[4]);
    double c2 = 0.5 * (a1 + a2), c3 = 0.5 * (a2 + a3), c4 = 0.5 * (a3 + a4);
    double d3 = 0.5 * (c2 + c3), d4 = 0.5 * (c3 + c4);
    double e4 = 0.5 * (d3 + d4);
    double l[5] = {b[0], a1, c2, d3, e4}, r[5] = {e4, d4, c4, a4, b[4]};
    return bernstein4_above(l, level, depth - 1) && bernstein4_above(r, level, depth - 1);
}

/* 1 when the quartic c (five coefficients) is certainly above level over [t0, t1]:
 * from its Bernstein form there, with a margin for the rounding of the change of basis. */
static int quartic_stays_above(const double *c, double t0, double t1, double level)
{
    /* Taylor coefficients at t0, scaled to the interval's length h */
    double h = t1 - t0;
    double q4 = c[4];
    double q3 = c[3] + 4.0 * t0 * c[4];
    double q2 = c[2] + t0 * (3.0 * c[3] + 6.0 * t0 * c[4]);
    double q1 = c[1] + t0 * (2.0 * c[2] + t0 * (3.0 * c[3] + 4.0 * t0 * c[4]));
    double q0 = c[0] + t0 * (c[1] + t0 * (c[2] + t0 * (c[3] + t0 * c[4])));
    q1 *= h, q2 *= h * h, q3 *= h * h * h, q4 *= (h * h) * (h * h);
    double size = fabs(q0) + fabs(q1) + fabs(q2) + fabs(q3) + fabs(q4);
    double b[5] = {q0, q0 + q1 / 4.0, q0 + q1 / 2.0 + q2 / 6.0,
                   q0 + 0.75 * q1 + 0.5 * q2 + 0.25 * q3, q0 + q1 + q2 + q3 + q4};
    return bernstein4_above(b, level + RF_BERNSTEIN_REL * size, 2);
}

static int poly_entries(const double *c, int deg, double t0, double t1, double tol,
                        double slope_eps, double curve_eps, double *roots)
{
    while (deg > 0 && c[deg] == 0.0)
        deg--;
    if (!(t1 >= t0))
        return 0;
    if (deg == 4 && quartic_stays_above(c, t0, t1, tol))
        return 0; /* neither touching nor entering anywhere */
    double d[4] = {0, 0, 0, 0};
    if (deg >= 1)
        derivative(c, deg, d);
    double p0 = rf_poly_eval(c, deg, t0);
    double dp0 = deg >= 1 ? rf_poly_eval(d, deg - 1, t0) : 0.0;
    double deep = RF_TOUCH_BAND * tol;
    if (p0 <= tol && p0 >= -deep && dp0 < -slope_eps) {
        roots[0] = t0; /* touching and approaching */
        return 1;
    }
    if (deg == 0)
        return 0;
    double pts[5];
    int np = monotone_pieces(c, deg, t0, t1, pts);
    double pv[5];
    int n = 0;
    double pa = p0;
    for (int i = 0; i + 1 < np && n < 3; i++) {
        double a = pts[i], b = pts[i + 1];
        double pb = pv[i + 1] = rf_poly_eval(c, deg, b);
        if (pa > 0.0 && pb <= 0.0) {
            /* falling through 0 after having been clear (above tol); after a smaller
             * rise only when approaching clearly faster than a graze (a hop of a hair:
             * grazes along a feature must not become contacts at every step), or when
             * going on deeper than the touch band however slow the crossing (met
             * there, where the caller checks that the contact point is on its feature:
             * the dip may lie far along an edge's line, past the edge's end) */
            double x = pb == 0.0 ? b : bracketed_root(c, deg, a, b, pa);
            double dx = rf_poly_eval(d, deg - 1, x);
            if (dx < -slope_eps && (pa > tol || dx < -RF_DIP_SLOPE * slope_eps))
                roots[n++] = x;
            else if (pb < -deep)
                roots[n++] = level_root(c, deg, x, b, -deep);
        }
        pa = pb;
    }
    if (n > 0 || !(curve_eps >= 0) || !(t1 > t0))
        return n;
    /* a contact's start rules, where no entry was found */
    if (p0 <= tol && p0 >= -deep) {
        double d2 = 2 * c[2] + t0 * (6 * c[3] + t0 * 12 * c[4]);
        if (dp0 <= slope_eps && d2 < -curve_eps) {
            /* touching at the start, not moving apart, and curving in (as a face's
             * path tangent at the start, as when a sphere rolls out of a crease over a
             * ridge): met there, else it would pass into the feature unseen */
            roots[0] = t0;
            return 1;
        }
        /* touching, and going in deeper than the touch band before it comes clear:
         * met where it is a touch band deep, as a slow crossing is.  Neither a tangent
         * path that curves in by a cubic term (12/59/51 sank 0.47 r into a face past the
         * edge it left tangent to) nor one that moves apart by a hair and then curves
         * in (43/59/138, 0.73 r) rises above the touch band first */
        return first_below(c, deg, pts, pv, np, -deep, tol, roots);
    }
    if (p0 < -deep && dp0 < -slope_eps) {
        /* already within reach of it (a penetration below what the path points show,
         * left where a pocket held the rock) and going deeper: met at once, so that it
         * does not grow */
        roots[0] = t0;
        return 1;
    }
    return 0;
}

int rf_poly_entries(const double *c, int deg, double t0, double t1, double tol,
                    double slope_eps, double *roots)
{
    return poly_entries(c, deg, t0, t1, tol, slope_eps, -1.0, roots);
}

int rf_poly_contact_entries(const double *c, double t0, double t1, double tol, double slope_eps,
                            double curve_eps, double *roots)
{
    return poly_entries(c, 4, t0, t1, tol, slope_eps, curve_eps, roots);
}

int rf_poly_sinks(const double *c, int deg, double t0, double t1, double lo, double hi,
                  double *t)
{
    while (deg > 0 && c[deg] == 0.0)
        deg--;
    if (!(t1 > t0) || deg == 0)
        return 0;
    double pts[5];
    int np = monotone_pieces(c, deg, t0, t1, pts);
    return first_below(c, deg, pts, NULL, np, lo, hi, t);
}
