/* arc.c - constant-acceleration arcs and the polynomial roots of contact times.
 *
 * Every contact time of the engine is the root of a polynomial in time of degree at
 * most 4: the distance of the centre of a parabola to a plane (degree 2) and the
 * squared distance to a line or a point (degree 4).  Roots are isolated between the
 * critical points (found from the derivative, recursively) and refined by Newton's
 * method kept inside the bracket, so none is skipped and each is located to
 * RF_TIME_TOL. */
#include "motion_private.h"

#include <math.h>

double rf_arc_length(rf_vec3 v, rf_vec3 a, double T)
{
    if (!(T > 0))
        return 0.0;
    double A = rf_v3_norm2(a);
    double C = rf_v3_norm2(v);
    if (!(A > 1e-300))
        return sqrt(C) * T;
    /* |v + a t| = sqrt(A) sqrt(u^2 + k^2), u = t + v.a / A, k = |v x a| / A. */
    double sa = sqrt(A);
    double u0 = rf_v3_dot(v, a) / A, u1 = u0 + T;
    double k = rf_v3_norm(rf_v3_cross(v, a)) / A;
    double f0, f1;
    if (k > 1e-12 * (fabs(u0) + fabs(u1))) {
        f0 = u0 * hypot(u0, k) + k * k * asinh(u0 / k);
        f1 = u1 * hypot(u1, k) + k * k * asinh(u1 / k);
    } else {
        f0 = u0 * fabs(u0);
        f1 = u1 * fabs(u1);
    }
    double len = 0.5 * sa * (f1 - f0);
    /* The chord is a lower bound; the integral is exact up to rounding. */
    return len > 0 ? len : 0.0;
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
    for (int it = 0; it < 200; it++) {
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
        if (fabs(tn - t) <= RF_TIME_TOL * 1e-2 + 1e-16 * fabs(t) || hi - lo <= 1e-16 * (1 + fabs(t)))
            return tn;
        t = tn;
    }
    return t;
}

/* Critical points of P (roots of P') strictly inside (t0, t1), ascending; count. */
static int critical_points(const double *c, int deg, double t0, double t1, double *cp)
{
    int n = 0;
    double d[4] = {0, 0, 0, 0};
    if (deg <= 1)
        return 0;
    derivative(c, deg, d);
    if (deg == 2) {
        double r[2];
        int k = rf_quadratic_roots(0.0, d[1], d[0], r);
        for (int i = 0; i < k; i++)
            if (r[i] > t0 && r[i] < t1)
                cp[n++] = r[i];
        return n;
    }
    if (deg == 3) {
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

int rf_poly_entries(const double *c, int deg, double t0, double t1, double tol,
                    double slope_eps, double *roots)
{
    while (deg > 0 && c[deg] == 0.0)
        deg--;
    if (!(t1 >= t0))
        return 0;
    double d[4] = {0, 0, 0, 0};
    if (deg >= 1)
        derivative(c, deg, d);
    double p0 = rf_poly_eval(c, deg, t0);
    double dp0 = deg >= 1 ? rf_poly_eval(d, deg - 1, t0) : 0.0;
    if (p0 <= tol && p0 >= -RF_TOUCH_BAND * tol && dp0 < -slope_eps) {
        roots[0] = t0; /* touching and approaching */
        return 1;
    }
    if (deg == 0)
        return 0;
    double pts[5];
    int np = 0;
    pts[np++] = t0;
    np += critical_points(c, deg, t0, t1, pts + 1);
    pts[np++] = t1;
    int n = 0;
    double pa = p0;
    for (int i = 0; i + 1 < np && n < 3; i++) {
        double a = pts[i], b = pts[i + 1];
        double pb = rf_poly_eval(c, deg, b);
        if (pa > tol && pb <= 0.0) {
            double x = pb == 0.0 ? b : bracketed_root(c, deg, a, b, pa);
            if (rf_poly_eval(d, deg - 1, x) < -slope_eps)
                roots[n++] = x;
        }
        pa = pb;
    }
    return n;
}
