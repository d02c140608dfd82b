/* hodograph.h - sliding and rolling off the fall line, in closed form (hodograph.c). */
#ifndef ROCKFALL_HODOGRAPH_H
#define ROCKFALL_HODOGRAPH_H

#include "rockfall/vec3.h"

/* The in-plane laws off the fall line:
 * w' = A e1 - B w^ on a face of normal n with fall line e1, solved in closed form in a
 * parameter lambda >= 0 that grows with time (lambda = INFINITY: the end, w = 0, when
 * B > A). */
typedef struct rf_hodograph {
    rf_vec3 e1, e2;    /* the fall line; in-plane across it, on the side of w0 */
    double A, k;       /* k = B / A */
    double P, Q, R;    /* |w0| + w0.e1, |w0| - w0.e1, w0.e2 */
    double inv[6];     /* 1 / a (0 for a = 0) for a = k-1, k+1, 2k-2, 2k+2, 2k-1, 2k+1 */
    double c[6];       /* P / 2A, Q / 2A, P^2 / 4A, Q^2 / 4A, R P / 2A, R Q / 2A */
    double tend;       /* the time w vanishes at (k > 1), else INFINITY */
} rf_hodograph;

/* w0 in the plane of n, not along e1; A > 0, B >= 0. */
void rf_hodograph_init(rf_hodograph *h, rf_vec3 w0, rf_vec3 n, rf_vec3 e1, double A, double B);
/* Time at lambda, and the speed |w| there when speed is not NULL. */
double rf_hodograph_time(const rf_hodograph *h, double lam, double *speed);
/* w and x (the integral of w over time from lambda = 0) at lambda; returns its time. */
double rf_hodograph_at(const rf_hodograph *h, double lam, rf_vec3 *w, rf_vec3 *x);
/* The lambda in [lo, hi] (hi may be INFINITY) at which the time is t, t(lo) <= t <= t(hi),
 * by Newton's method from guess. */
double rf_hodograph_lambda(const rf_hodograph *h, double t, double lo, double hi, double guess);

#endif
