/* Contact-time roots (arc.c): the first entering root of the quartic |W + V t + H t^2|^2
 * - rho^2 against a fine sampling, above all where the distance grazes rho. */
#include "base/arc.h"
#include "base/tolerances.h"
#include "engine/hodograph.h"
#include "test.h"

#include <gsl/gsl_rng.h>

static double quartic_at(const double c[5], double t)
{
    return c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * c[4])));
}

/* The first time in [t0, t1] where the quartic, above zero at t0, falls to 0 or below:
 * sampled on n points and at tc (where a short dip is), then bisected; -1 when it
 * never does. */
static double sampled_entry(const double c[5], double t0, double t1, double tc, int n)
{
    double prev = t0;
    for (int i = 1; i <= n; i++) {
        double t = t0 + (t1 - t0) * i / n;
        if (tc > prev && tc < t && quartic_at(c, tc) <= 0.0)
            t = tc;
        if (quartic_at(c, t) <= 0.0) {
            double lo = prev, hi = t;
            for (int k = 0; k < 200 && hi - lo > 1e-15; k++) {
                double mid = 0.5 * (lo + hi);
                if (quartic_at(c, mid) <= 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            return hi;
        }
        prev = t;
    }
    return -1.0;
}

/* A sphere centre on a parabola past a point q = 0 at closest distance rho (1 + gap):
 * the coefficients of |p(t)|^2 - rho^2. */
static void grazing_quartic(gsl_rng *r, double gap, double c[5], double *tc)
{
    double rho = 0.1 + 2.0 * gsl_rng_uniform(r);
    rf_vec3 v = rf_v3(4 * gsl_rng_uniform(r) - 2, 4 * gsl_rng_uniform(r) - 2, 4 * gsl_rng_uniform(r) - 2);
    rf_vec3 h = rf_v3(0, 0, -0.5 * 9.81);
    /* the path's closest approach to q: put q at distance rho (1 + gap) from the point
     * of the path at time tc, along the path's normal there */
    *tc = 0.2 + gsl_rng_uniform(r);
    rf_vec3 vel = rf_v3_madd(v, 2.0 * *tc, h);
    rf_vec3 side = rf_v3_cross(vel, rf_v3(gsl_rng_uniform(r), gsl_rng_uniform(r), 1.0));
    side = rf_v3_scale(side, 1.0 / rf_v3_norm(side));
    rf_vec3 at = rf_v3_add(rf_v3_scale(v, *tc), rf_v3_scale(h, *tc * *tc));
    rf_vec3 q = rf_v3_madd(at, rho * (1.0 + gap), side);
    rf_vec3 W = rf_v3_scale(q, -1.0); /* p(0) = 0, so W = p(0) - q */
    c[0] = rf_v3_norm2(W) - rho * rho;
    c[1] = 2 * rf_v3_dot(W, v);
    c[2] = rf_v3_norm2(v) + 2 * rf_v3_dot(W, h);
    c[3] = 2 * rf_v3_dot(v, h);
    c[4] = rf_v3_norm2(h);
}

TEST(arc_quartic_entries_match_sampling_near_grazing)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    const double gaps[] = {-1e-2, -1e-4, -1e-6, 1e-6, 1e-4, 1e-2, 0.3};
    int entered = 0, clear = 0;
    for (int i = 0; i < 20000; i++) {
        double c[5], tc;
        double gap = gaps[i % (int)(sizeof gaps / sizeof gaps[0])];
        grazing_quartic(r, gap, c, &tc);
        double t0 = gsl_rng_uniform(r) * 0.5 * tc, t1 = tc + gsl_rng_uniform(r) * 2.0;
        if (!(quartic_at(c, t0) > 1e-9))
            continue;
        double roots[3];
        int n = rf_poly_entries(c, 4, t0, t1, 1e-12, 1e-12, roots);
        double want = sampled_entry(c, t0, t1, tc, 4000);
        if (want < 0) {
            /* beyond rho all the way (or grazing within the tolerances) */
            ENSURE_MSG(n == 0 || gap < 1e-5, "case %d: gap %g, a root at %.17g where the sampling has none",
                       i, gap, roots[0]);
            clear++;
        } else {
            ENSURE_MSG(n > 0, "case %d: gap %g, no root; the sampling enters at %.17g", i, gap, want);
            ENSURE_MSG(fabs(roots[0] - want) <= 1e-9 * (1 + fabs(want)),
                       "case %d: root %.17g, sampled %.17g", i, roots[0], want);
            entered++;
        }
    }
    /* both kinds occur in numbers */
    ENSURE(entered > 5000 && clear > 5000);
    gsl_rng_free(r);
}

/* A quartic that dips below zero only in a short stretch between long clear ones:
 * the stretch must be found (the Bernstein bound must not rule it out). */
TEST(arc_quartic_entry_in_a_short_dip)
{
    /* (t - 1)^2 (t - 3)^2 - 1e-6 on [0, 4]: enters just before 1 and before 3 */
    double c[5] = {9 - 1e-6, -24, 22, -8, 1};
    double roots[3];
    int n = rf_poly_entries(c, 4, 0.0, 4.0, 1e-12, 1e-12, roots);
    ENSURE(n == 2);
    ENSURE_REL(roots[0], 1.0 - sqrt(1e-6) / 2.0, 1e-6);
    ENSURE(roots[1] > 2.9 && roots[1] < 3.0);
    /* lifted clear of zero by 1e-6: no entry anywhere */
    double up[5] = {9 + 1e-6, -24, 22, -8, 1};
    ENSURE(rf_poly_entries(up, 4, 0.0, 4.0, 1e-12, 1e-12, roots) == 0);
}

/* A start a hair above zero (less than the tolerance) with no approach speed, then a
 * fall far below zero: an entry, though its slope at the root is slow, met once it is a
 * touch band deep (where the caller checks that the contact point is on its feature).
 * A graze of the same start that dips less than the touch band and comes back is not. */
TEST(arc_quartic_entry_after_a_hair_going_deep)
{
    const double tol = 1e-9, slope = 1e-7;
    double roots[3];
    /* 5e-10 - t^3: falls to -1e-3 by t = 0.1 */
    double deep[5] = {5e-10, 0, 0, -1, 0};
    ENSURE(rf_poly_entries(deep, 4, 0.0, 0.1, tol, slope, roots) == 1);
    ENSURE_REL(roots[0], cbrt(5e-10 + RF_TOUCH_BAND * tol), 1e-9);
    /* 5e-10 - 1e-3 t^2 + 250 t^4: its minimum is -5e-10 */
    double graze[5] = {5e-10, 0, -1e-3, 0, 250};
    ENSURE(rf_poly_entries(graze, 4, 0.0, 2e-3, tol, slope, roots) == 0);
}

/* A start a hair below zero (within the touch band) that never rises above zero: no
 * entry for rf_poly_entries, which looks for crossings from above, but a sink for
 * rf_poly_sinks once it is a touch band deep, unless it comes clear first. */
TEST(arc_quartic_sinks_from_a_touch)
{
    const double tol = 1e-9, band = RF_TOUCH_BAND * tol;
    double roots[3], t = -1.0;
    /* -4e-14 + 2e-13 t + 2e-4 t^2 - 8 t^3 + 24 t^4: tangent at second order, cubic in */
    double tangent[5] = {-4e-14, 2e-13, 2e-4, -8, 24};
    ENSURE(rf_poly_entries(tangent, 4, 0.0, 0.4, tol, 1e-7, roots) == 0);
    ENSURE(rf_poly_sinks(tangent, 4, 0.0, 0.4, -band, tol, &t) == 1);
    ENSURE(t > 2.5e-5 && t < 0.1);
    ENSURE(fabs(rf_poly_eval(tangent, 4, t) + band) < 1e-3 * band);
    /* -1e-11 + 4.5e-6 t - 3.85 t^2: moving apart by a hair, then in */
    double apart[5] = {-1e-11, 4.5e-6, -3.85, 0, 0};
    /* where it sinks to the band's depth */
    double t_apart = (4.5e-6 + sqrt(4.5e-6 * 4.5e-6 + 4 * 3.85 * (band - 1e-11))) / (2 * 3.85);
    ENSURE(rf_poly_entries(apart, 2, 0.0, 0.5, tol, 1e-7, roots) == 0);
    ENSURE(rf_poly_sinks(apart, 2, 0.0, 0.5, -band, tol, &t) == 1);
    ENSURE_REL(t, t_apart, 1e-9);
    /* moving apart clearly first (above tol), then in: not a sink (an entry) */
    double clear[5] = {-1e-11, 1e-3, -3.85, 0, 0};
    ENSURE(rf_poly_sinks(clear, 2, 0.0, 0.5, -band, tol, &t) == 0);
    ENSURE(rf_poly_entries(clear, 2, 0.0, 0.5, tol, 1e-7, roots) == 1);
    /* staying within the band: no sink */
    double graze[5] = {-1e-11, 0, -1e-9, 0, 0};
    ENSURE(rf_poly_sinks(graze, 2, 0.0, 0.5, -band, tol, &t) == 0);
    /* a quartic whose top coefficients vanish (an edge along the path's plane) is its
     * lower degree; an empty window sinks nowhere */
    t = -1.0;
    ENSURE(rf_poly_sinks(apart, 4, 0.0, 0.5, -band, tol, &t) == 1);
    ENSURE_REL(t, t_apart, 1e-9);
    ENSURE(rf_poly_sinks(apart, 4, 0.2, 0.2, -band, tol, &t) == 0);
    double flat[5] = {-1e-11, 0, 0, 0, 0};
    ENSURE(rf_poly_sinks(flat, 4, 0.0, 0.5, -band, tol, &t) == 0);
}

/* The integral of |v + a t| over [t0, t1] by 5-point Gauss-Legendre. */
static double speed_gauss(rf_vec3 v, rf_vec3 a, double t0, double t1)
{
    static const double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                0.5384693101056831, 0.9061798459386640};
    static const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                0.4786286704993665, 0.2369268850561891};
    double c = 0.5 * (t0 + t1), h = 0.5 * (t1 - t0), s = 0.0;
    for (int j = 0; j < 5; j++)
        s += w[j] * rf_v3_norm(rf_v3_madd(v, c + h * x[j], a));
    return h * s;
}

/* The same, halving [t0, t1] until its halves agree with it to 1e-17 of scale. */
static double speed_integral(rf_vec3 v, rf_vec3 a, double t0, double t1, double whole,
                             double scale, int depth)
{
    double tm = 0.5 * (t0 + t1);
    double l = speed_gauss(v, a, t0, tm), r = speed_gauss(v, a, tm, t1);
    if (depth > 60 || fabs(l + r - whole) <= 1e-17 * scale)
        return l + r;
    return speed_integral(v, a, t0, tm, l, scale, depth + 1) +
           speed_integral(v, a, tm, t1, r, scale, depth + 1);
}

/* The length of an arc over [0, T], by quadrature split where the speed is least (a
 * kink when it passes through zero). */
static double quadrature_length(rf_vec3 v, rf_vec3 a, double T)
{
    double A = rf_v3_norm2(a);
    double ts = A > 0 ? -rf_v3_dot(v, a) / A : -1.0;
    double scale = speed_gauss(v, a, 0.0, T);
    if (!(ts > 0 && ts < T))
        return speed_integral(v, a, 0.0, T, scale, scale, 0);
    return speed_integral(v, a, 0.0, ts, speed_gauss(v, a, 0.0, ts), scale, 0) +
           speed_integral(v, a, ts, T, speed_gauss(v, a, ts, T), scale, 0);
}

TEST(arc_length_matches_quadrature)
{
    struct {
        rf_vec3 v, a;
        double T;
    } c[] = {
        {{3, 0, 0}, {0, 0, -9.81}, 0.7},          /* a throw: speed perpendicular at first */
        {{0, 0, 4}, {0, 0, -9.81}, 1.0},          /* up and down through zero speed */
        {{0, 0, -4}, {0, 0, -9.81}, 0.3},         /* along the acceleration */
        {{10, 0, 0}, {-9.81, 0, 0.1}, 0.5},       /* slowing, not to zero */
        {{10, 0, 0}, {-9.81, 0, 1e-7}, 1.5},      /* nearly through zero speed */
        {{30, 5, -2}, {2, -1, -9.81}, 1e-4},      /* fast and short */
        {{1e-9, 0, 0}, {0, 0, -9.81}, 2.0},       /* from nearly rest */
        {{12, -7, 3}, {0, 0, 0}, 0.4},            /* no acceleration */
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++)
        ENSURE_REL(rf_arc_length(c[i].v, c[i].a, c[i].T), quadrature_length(c[i].v, c[i].a, c[i].T),
                   1e-14);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    for (int i = 0; i < 300; i++) {
        rf_vec3 v = rf_v3(20 * (gsl_rng_uniform(r) - 0.5), 20 * (gsl_rng_uniform(r) - 0.5),
                          20 * (gsl_rng_uniform(r) - 0.5));
        rf_vec3 a = rf_v3(10 * (gsl_rng_uniform(r) - 0.5), 10 * (gsl_rng_uniform(r) - 0.5),
                          -9.81 * gsl_rng_uniform(r));
        double T = pow(10.0, -4.0 + 4.3 * gsl_rng_uniform(r));
        ENSURE_REL(rf_arc_length(v, a, T), quadrature_length(v, a, T), 1e-14);
    }
    gsl_rng_free(r);
    ENSURE(rf_arc_length(rf_v3(1, 2, 3), rf_v3(0, 0, -9.81), 0.0) == 0.0);
}
