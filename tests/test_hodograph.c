/* The in-plane laws off the fall line in closed form (hodograph.c) against a fine
 * Runge-Kutta integration of w' = A e1 - B w^, x' = w, over the regimes of k = B / A:
 * speeding up (k < 1), the exponents that vanish (k = 1, 1/2 and next to them), slowing
 * to a stop (k > 1), and starting nearly up and nearly down the fall line. */
#include "base/arc.h"
#include "base/tolerances.h"
#include "engine/hodograph.h"
#include "motion_test_util.h"
#include "test.h"

#include <math.h>

#define PI 3.14159265358979323846

/* w' = A e1 - B w^ in the plane's coordinates (e1 = x axis); y = (wx, wy, x, y),
 * ctx = {A, B}. */
static void law(const double *y, double *dy, const void *ctx)
{
    const double *AB = ctx;
    double wl = hypot(y[0], y[1]);
    dy[0] = AB[0] - AB[1] * y[0] / wl;
    dy[1] = -AB[1] * y[1] / wl;
    dy[2] = y[0];
    dy[3] = y[1];
}

/* The law integrated over [0, T] in n steps from y. */
static void rk4(double A, double B, double *y, double T, long n)
{
    const double AB[2] = {A, B};
    mt_rk4(law, AB, y, 4, T, n);
}

/* A plane tilted about x and y, so that e1 and e2 are not along the axes. */
static void plane(rf_vec3 *n, rf_vec3 *e1, rf_vec3 *e2)
{
    *n = rf_v3_unit(rf_v3(0.4, -0.3, 1.0));
    *e1 = rf_v3_unit(rf_v3_madd(rf_v3(0, 0, -1), n->z, *n));
    *e2 = rf_v3_cross(*n, *e1);
}

/* The closed form at time T against the integration, from w0 at angle psi0 from the
 * fall line (speed w0l); frac > 0: T is that fraction of the time the motion ends at. */
static void against_rk4(double A, double k, double w0l, double psi0, double frac)
{
    rf_vec3 n, e1, e2;
    plane(&n, &e1, &e2);
    rf_vec3 w0 = rf_v3_add(rf_v3_scale(e1, w0l * cos(psi0)), rf_v3_scale(e2, w0l * sin(psi0)));
    rf_hodograph h;
    rf_hodograph_init(&h, w0, n, e1, A, k * A);
    double tend = h.tend;
    ENSURE(k > 1.0 ? tend < INFINITY : tend == INFINITY);
    double T = frac > 0 ? frac * tend : 1.7;
    double lam = rf_hodograph_lambda(&h, T, 0.0, INFINITY, 0.0);
    ENSURE_REL(rf_hodograph_time(&h, lam, NULL), T, 1e-14);
    rf_vec3 w, x;
    ENSURE_REL(rf_hodograph_at(&h, lam, &w, &x), T, 1e-14);
    double y[4] = {w0l * cos(psi0), w0l * sin(psi0), 0.0, 0.0};
    rk4(A, k * A, y, T, 200000);
    double ws = w0l + A * T, xs = w0l * T + A * T * T; /* scales of w and x */
    ENSURE_MSG(fabs(rf_v3_dot(w, e1) - y[0]) <= 1e-11 * ws && fabs(rf_v3_dot(w, e2) - y[1]) <= 1e-11 * ws,
               "k %g psi0 %g: w (%.15g, %.15g), integrated (%.15g, %.15g)", k, psi0,
               rf_v3_dot(w, e1), rf_v3_dot(w, e2), y[0], y[1]);
    ENSURE_MSG(fabs(rf_v3_dot(x, e1) - y[2]) <= 1e-11 * xs && fabs(rf_v3_dot(x, e2) - y[3]) <= 1e-11 * xs,
               "k %g psi0 %g: x (%.15g, %.15g), integrated (%.15g, %.15g)", k, psi0,
               rf_v3_dot(x, e1), rf_v3_dot(x, e2), y[2], y[3]);
    ENSURE_SMALL(rf_v3_dot(w, n), 1e-14 * ws);
    ENSURE_SMALL(rf_v3_dot(x, n), 1e-14 * xs);
}

TEST(hodograph_speeding_up_matches_integration)
{
    const double psi[] = {0.3, 1.2, PI / 2, 2.4, 3.0};
    for (size_t i = 0; i < sizeof psi / sizeof *psi; i++) {
        against_rk4(5.2, 0.3, 3.1, psi[i], 0.0);
        against_rk4(5.2, 0.0, 3.1, psi[i], 0.0); /* frictionless: a parabola */
    }
}

TEST(hodograph_vanishing_exponents_match_integration)
{
    /* k = 1 (I(k-1), I(2k-2)), k = 1/2 (I(2k-1)) and next to them */
    const double ks[] = {1.0, 1.0 - 1e-9, 1.0 + 1e-9, 0.5, 0.5 + 1e-12, 0.999};
    for (size_t i = 0; i < sizeof ks / sizeof *ks; i++) {
        against_rk4(4.0, ks[i], 2.0, 1.1, 0.0); /* 1 + 1e-9 ends only after ~1e9 s */
        against_rk4(4.0, ks[i], 2.0, 2.9, 0.0);
    }
}

TEST(hodograph_slowing_to_a_stop_matches_integration)
{
    const double ks[] = {1.05, 1.6, 4.0};
    const double psi[] = {0.2, 1.4, 2.8};
    for (size_t i = 0; i < 3; i++)
        for (size_t j = 0; j < 3; j++)
            against_rk4(3.3, ks[i], 4.5, psi[j], 0.97);
}

TEST(hodograph_stops_exactly_at_its_end)
{
    rf_vec3 n, e1, e2;
    plane(&n, &e1, &e2);
    rf_hodograph h;
    rf_hodograph_init(&h, rf_v3_add(rf_v3_scale(e1, 1.5), rf_v3_scale(e2, -2.0)), n, e1, 2.0, 3.0);
    double tend = h.tend;
    rf_vec3 w, x, wl, xl;
    ENSURE(rf_hodograph_at(&h, INFINITY, &w, &x) == tend);
    ENSURE(rf_v3_norm(w) == 0.0);
    /* the limit: far along the parameter the state is the end's */
    double tl = rf_hodograph_at(&h, 80.0, &wl, &xl);
    ENSURE_REL(tl, tend, 1e-14);
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(xl, x)), 1e-14);
    /* it turns towards the fall line on the side of w0 (e2 flipped to it) */
    ENSURE(rf_v3_dot(x, rf_v3_cross(n, e1)) < 0);
    ENSURE(rf_hodograph_lambda(&h, tend, 0.0, INFINITY, 0.0) == INFINITY);
    /* integrated to 1 - 1e-6 of the end, the rest of the way at the end's deceleration
     * A (k - 1) along the limiting direction e1 */
    double y[4] = {1.5, -2.0, 0.0, 0.0};
    double T = tend * (1.0 - 1e-6);
    rk4(2.0, 3.0, y, T, 400000);
    double rest = tend - T;
    ENSURE_SMALL(rf_v3_dot(x, e1) - (y[2] + 0.5 * 1.0 * 2.0 * rest * rest), 1e-10);
    ENSURE_SMALL(rf_v3_dot(x, rf_v3_cross(n, e1)) - y[3], 1e-10);
}

/* The parameter at a time is found from any guess within the bracket. */
TEST(hodograph_time_inverts_from_any_guess)
{
    rf_vec3 n, e1, e2;
    plane(&n, &e1, &e2);
    const double ks[] = {0.2, 1.0, 2.5};
    for (size_t i = 0; i < 3; i++) {
        rf_hodograph h;
        rf_hodograph_init(&h, rf_v3_add(rf_v3_scale(e1, -3.0), rf_v3_scale(e2, 0.01)), n, e1, 6.0,
                          6.0 * ks[i]);
        double lo = 0.5, hi = 9.0, tlo = rf_hodograph_time(&h, lo, NULL), thi = rf_hodograph_time(&h, hi, NULL);
        for (int j = 0; j <= 10; j++) {
            double t = tlo + (thi - tlo) * j / 10.0;
            const double guesses[] = {lo, hi, 0.5 * (lo + hi), 1.3};
            for (size_t g = 0; g < 4; g++) {
                double lam = rf_hodograph_lambda(&h, t, lo, hi, guesses[g]);
                ENSURE(lam >= lo && lam <= hi);
                ENSURE_SMALL(rf_hodograph_time(&h, lam, NULL) - t, 1e-15 * (1.0 + t));
            }
        }
    }
}
