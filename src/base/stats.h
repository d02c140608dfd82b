/* stats.h - simulated stop points against measured ones, and the percentiles of
 * stored values.
 *
 * The statistics `make validate` (tools/validate.c) uses to compare the engine with
 * the Authume quarry tests (docs/validation.md).  The stop points of a
 * release are taken in a frame of their own: the runout is the horizontal distance
 * from the release centre, the lateral offset the signed distance across the mean
 * direction of the measured stops.  The measures of agreement: runout percentiles,
 * the lateral mean and spread (the sample sd, and the robust sigma IQR / 1.349, which
 * is the sd for a normal sample and ignores a few far stops), the two-sample
 * Kolmogorov-Smirnov distances on runout and on the lateral offset,
 * and the share of measured stops inside the simulated 95 % envelope (the convex hull
 * of the 95 % of simulated stops nearest their mean in the Mahalanobis distance). */
#ifndef ROCKFALL_STATS_H
#define ROCKFALL_STATS_H

#include <stddef.h>

#include "rockfall/error.h"

/* Nearest-rank percentile q in (0, 1] of n values (sorts them in place); NaN for none. */
double rf_percentile_nearest_rank(float *v, size_t n, double q);
/* The same of n values sorted ascending already. */
double rf_percentile_sorted(const float *v, size_t n, double q);
/* Quantile q in [0, 1] of n >= 1 values sorted ascending: linear between the order
 * statistics (Hyndman and Fan's type 7, as R and numpy by default); NaN for none. */
double rf_quantile(const double *sorted, size_t n, double q);

/* Two-sample Kolmogorov-Smirnov distance sup |F_a - F_b| of two samples sorted
 * ascending (n, m >= 1). */
double rf_ks_distance(const double *a, size_t n, const double *b, size_t m);

/* Wasserstein-1 (earth mover's) distance between two samples sorted ascending (n, m >=
 * 1): the area between their empirical distribution functions, in their unit.  Unlike
 * the Kolmogorov-Smirnov distance it moves continuously with the values. */
double rf_w1_distance(const double *a, size_t n, const double *b, size_t m);

/* Convex hull of n points xy[2k], xy[2k+1] into hull (room for 2 (n + 1) numbers),
 * counter-clockwise, without collinear points; returns its number of vertices. */
size_t rf_convex_hull(const double *xy, size_t n, double *hull);

/* 1 when (x, y) lies in the closed convex polygon of nh counter-clockwise vertices
 * (for nh < 3, on the segment or at the point). */
int rf_hull_contains(const double *hull, size_t nh, double x, double y, double tol);

/* The envelope of n points: the convex hull (into hull, room for 2 (n + 1) numbers) of the
 * ceil(keep n) nearest their mean in the Mahalanobis distance; returns its vertices. */
size_t rf_envelope(const double *xy, size_t n, double keep, double *hull);

/* How simulated stops agree with measured ones, in the release's frame. */
typedef struct rf_agreement {
    size_t n_sim;
    double runout_meas[3], runout_sim[3]; /* 5th percentile, median, 95th (m) */
    double lateral_mean_meas, lateral_mean_sim;
    double lateral_sd_meas, lateral_sd_sim; /* sample standard deviations (m) */
    double lateral_rsigma_meas, lateral_rsigma_sim; /* robust sigma: IQR / 1.349 (m) */
    double ks;                              /* Kolmogorov-Smirnov distance on runout */
    double ks_lateral;                      /* the same on the lateral offset */
    double w1_runout, w1_lateral;           /* Wasserstein-1 distances (m) */
    double runout_sd_meas;                  /* the measured runouts' sample sd (m) */
    double ks_crit;                         /* its 5 % critical value, 1.358 sqrt((n+m)/(n m)) */
    double inside;                          /* share of measured stops in the 95 % envelope */
} rf_agreement;

/* Compares nm measured and ns simulated horizontal stop points (x, y pairs) from the
 * release centre (x0, y0); -1 when either set is empty or memory runs out. */
int rf_agreement_compute(const double *meas, size_t nm, const double *sim, size_t ns, double x0,
                         double y0, rf_agreement *out);

#endif
