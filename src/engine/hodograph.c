/* hodograph.c - sliding and rolling on a plane off the fall line, in closed form.
 *
 * Every in-plane law of surface.c is w' = A e1 - B w^ for an in-plane vector w (the
 * velocity of the point mass and of the rolling sphere, the slip of the slipping
 * sphere), with e1 the fall line and A, B constant on a face.  With psi the angle of w
 * from e1, the speed obeys |w|' = A (cos psi - k) and the direction |w| psi' = -A sin psi
 * (k = B / A), so |w| = C s^(k-1) (1 + s^2) with s = tan(psi / 2): the rock turns towards
 * the fall line and s falls.  In the parameter lambda = ln(s0 / s) >= 0, sigma = e^-lambda,
 * with P = |w0| + w0.e1, Q = |w0| - w0.e1 and R = |w0 . e2| = sqrt(P Q):
 *
 *   w.e1 = (P sigma^(k-1) - Q sigma^(k+1)) / 2         w.e2 = R sigma^k
 *   t    = (P I(k-1) + Q I(k+1)) / 2A                   dt/dlambda = |w| / A
 *   x.e1 = (P^2 I(2k-2) - Q^2 I(2k+2)) / 4A            x.e2 = R (P I(2k-1) + Q I(2k+1)) / 2A
 *
 * where x is the integral of w over time, e2 the in-plane unit vector across e1 on the
 * side of w0, and I(a) = (1 - sigma^a) / a (lambda for a = 0) is evaluated with expm1,
 * so that the exponents near 0 (k near 1 or 1/2) lose no digits.  For k > 1 the motion
 * ends (w = 0) at the finite time t(inf); otherwise t grows without bound with lambda. */
#include "engine/hodograph.h"

#include <math.h>
#include <stddef.h>

#include "base/tolerances.h"

void rf_hodograph_init(rf_hodograph *h, rf_vec3 w0, rf_vec3 n, rf_vec3 e1, double A, double B)
{
    *h = (rf_hodograph){.e1 = e1}; /* every field set below; none left to chance */
    h->e2 = rf_v3_cross(n, e1);
    double a = rf_v3_dot(w0, e1), b = rf_v3_dot(w0, h->e2);
    if (b < 0) {
        h->e2 = rf_v3_scale(h->e2, -1.0);
        b = -b;
    }
    double W = sqrt(a * a + b * b);
    /* P Q = R^2: the smaller of the two from the larger, without cancellation */
    h->P = a >= 0 ? W + a : b * b / (W - a);
    h->Q = a <= 0 ? W - a : b * b / (W + a);
    h->R = b;
    h->A = A;
    double k = h->k = B / A;
    const double ex[6] = {k - 1.0, k + 1.0, 2.0 * k - 2.0, 2.0 * k + 2.0, 2.0 * k - 1.0, 2.0 * k + 1.0};
    for (int i = 0; i < 6; i++)
        h->inv[i] = ex[i] != 0.0 ? 1.0 / ex[i] : 0.0;
    double P = h->P, Q = h->Q;
    h->c[0] = P / (2.0 * A), h->c[1] = Q / (2.0 * A);
    h->c[2] = P * P / (4.0 * A), h->c[3] = Q * Q / (4.0 * A);
    h->c[4] = b * P / (2.0 * A), h->c[5] = b * Q / (2.0 * A);
    h->tend = k > 1.0 ? rf_hodograph_time(h, INFINITY, NULL) : INFINITY;
}

/* I(a) from inv = 1 / a (0 for a = 0) and e = sigma^a - 1 = expm1(-a lambda) */
static double integral(double inv, double e, double lam) { return inv != 0.0 ? -e * inv : lam; }

/* t from em = sigma^(k-1) - 1 and ep = sigma^(k+1) - 1 */
static double time_of(const rf_hodograph *h, double em, double ep, double lam)
{
    return h->c[0] * integral(h->inv[0], em, lam) + h->c[1] * integral(h->inv[1], ep, lam);
}

double rf_hodograph_time(const rf_hodograph *h, double lam, double *speed)
{
    double k = h->k;
    double em = expm1(-(k - 1.0) * lam), ep = expm1(-(k + 1.0) * lam);
    if (speed)
        *speed = 0.5 * (h->P * (1.0 + em) + h->Q * (1.0 + ep));
    return time_of(h, em, ep, lam);
}

double rf_hodograph_at(const rf_hodograph *h, double lam, rf_vec3 *w, rf_vec3 *x)
{
    double k = h->k;
    double em = expm1(-(k - 1.0) * lam), e0 = expm1(-k * lam), ep = expm1(-(k + 1.0) * lam);
    /* sigma^(2k-2) - 1, sigma^(2k+2) - 1, sigma^(2k-1) - 1, sigma^(2k+1) - 1; the third
     * directly, as the sum of em and e0 would cancel for k near 1/2 */
    double e2m = em * (em + 2.0), e2p = ep * (ep + 2.0), e1m = expm1(-(2.0 * k - 1.0) * lam),
           e1p = ep + e0 + ep * e0;
    const double *c = h->c, *inv = h->inv;
    double t = time_of(h, em, ep, lam);
    double wa = 0.5 * (h->P * (1.0 + em) - h->Q * (1.0 + ep)), wb = h->R * (1.0 + e0);
    double xa = c[2] * integral(inv[2], e2m, lam) - c[3] * integral(inv[3], e2p, lam);
    double xb = c[4] * integral(inv[4], e1m, lam) + c[5] * integral(inv[5], e1p, lam);
    *w = rf_v3_add(rf_v3_scale(h->e1, wa), rf_v3_scale(h->e2, wb));
    *x = rf_v3_add(rf_v3_scale(h->e1, xa), rf_v3_scale(h->e2, xb));
    return t;
}

double rf_hodograph_lambda(const rf_hodograph *h, double t, double lo, double hi, double guess)
{
    if (hi == INFINITY && t >= h->tend)
        return INFINITY;
    /* Newton's method (dt/dlambda = |w| / A) kept inside the bracket [lo, hi] */
    double lam = guess >= lo && guess <= hi ? guess : lo;
    for (int it = 0; it < RF_HODOGRAPH_MAX_ITER; it++) {
        double speed, g = rf_hodograph_time(h, lam, &speed) - t;
        if (g >= 0)
            hi = lam;
        else
            lo = lam;
        if (g == 0.0 || (hi < INFINITY && hi - lo <= RF_HODOGRAPH_REL_TOL * hi) ||
            fabs(g) <= RF_HODOGRAPH_REL_TOL * t)
            return lam;
        lam = speed > 0 ? lam - g * h->A / speed : INFINITY;
        if (!(lam > lo && lam < hi))
            lam = hi < INFINITY ? 0.5 * (lo + hi) : 2.0 * lo + 1.0;
    }
    return lam;
}
