/* arc.h - constant-acceleration arcs p(t) = p + v t + a t^2 / 2, their lengths, and the
 * polynomial roots of contact times (arc.c). */
#ifndef ROCKFALL_ARC_H
#define ROCKFALL_ARC_H

#include "base/tolerances.h"
#include "rockfall/vec3.h"

typedef struct rf_arc {
    rf_vec3 p, v, a;
} rf_arc;

static inline rf_vec3 rf_arc_pos(const rf_arc *c, double t)
{
    return rf_v3_add(c->p, rf_v3_add(rf_v3_scale(c->v, t), rf_v3_scale(c->a, 0.5 * t * t)));
}
static inline rf_vec3 rf_arc_vel(const rf_arc *c, double t) { return rf_v3_madd(c->v, t, c->a); }

/* Length of the path of an arc over [0, T] (closed form). */
double rf_arc_length(rf_vec3 v, rf_vec3 a, double T);
/* Real roots of c2 t^2 + c1 t + c0 in ascending order (numerically stable); count. */
int rf_quadratic_roots(double c2, double c1, double c0, double r[2]);
/* Value of the polynomial c[0] + c[1] t + ... + c[deg] t^deg. */
double rf_poly_eval(const double *c, int deg, double t);
/* Smallest and largest value of c[0] + c[1] t + c[2] t^2 over [t0, t1]. */
static inline void rf_quadratic_range(const double c[3], double t0, double t1, double *lo,
                                      double *hi)
{
    double a = c[0] + t0 * (c[1] + t0 * c[2]), b = c[0] + t1 * (c[1] + t1 * c[2]);
    *lo = a < b ? a : b;
    *hi = a < b ? b : a;
    if (c[2] != 0.0) {
        double tv = -c[1] / (2.0 * c[2]);
        if (tv > t0 && tv < t1) {
            double v = c[0] + tv * (c[1] + tv * c[2]);
            if (c[2] > 0.0)
                *lo = v < *lo ? v : *lo;
            else
                *hi = v > *hi ? v : *hi;
        }
    }
}

/* Entering roots of P (deg <= 4) on [t0, t1]: times where P falls through 0 with
 * P' < -slope_eps, after having been above tol, or above 0 only when P' < -100 slope_eps
 * there (a start with -RF_TOUCH_BAND tol <= P(t0) <= tol counts only when P'(t0) <
 * -slope_eps: touching and approaching).  Writes up to 3 roots in ascending order and
 * returns their number. */
int rf_poly_entries(const double *c, int deg, double t0, double t1, double tol,
                    double slope_eps, double *roots);
/* As rf_poly_entries for a quartic, the distance of a contact (an edge's or a vertex's),
 * with its start rules where no entry is found: touching (-RF_TOUCH_BAND tol <= P(t0)
 * <= tol), not moving apart (P'(t0) <= slope_eps) and curving in (P''(t0) < -curve_eps):
 * t0; touching and falling below the touch band before rising above tol: where it is
 * the band deep; deeper than the band and approaching: t0.  One root at most then. */
int rf_poly_contact_entries(const double *c, double t0, double t1, double tol, double slope_eps,
                            double curve_eps, double *roots);
/* P (deg <= 4) starting within [lo, hi] at t0: 1 and in *t the time it first falls to
 * lo, when it does so on [t0, t1] before rising above hi; 0 otherwise. */
int rf_poly_sinks(const double *c, int deg, double t0, double t1, double lo, double hi,
                  double *t);

#endif
