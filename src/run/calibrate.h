/* calibrate.h - surface values fitted to observed stop points (`rockfall calibrate`,
 * docs/calibration.md).
 *
 * The project's trajectories are simulated in memory with the run's own random streams
 * (trajectory k of release i from the stream of (seed, i, k)), so one set of values
 * always gives the same stops: the objective is a deterministic function of the values
 * (common random numbers).  The objective compares the simulated stops with the
 * observed ones in the frame of base/stats.h, from the mean start point, on runout
 * and lateral offset: by default the Wasserstein-1 distance of each, in units of the
 * observed sample's sd (it moves continuously with the stops, so the simplex can follow
 * it), or the Kolmogorov-Smirnov distance of each (a step function of the values: the
 * measure the validation reports, but a poor guide for a simplex). */
#ifndef ROCKFALL_CALIBRATE_H
#define ROCKFALL_CALIBRATE_H

#include <stdio.h>

#include "base/stats.h"
#include "rockfall/error.h"
#include "rockfall/project.h"

/* The zones a terrain may have for its values to be fitted by zone. */
#define RF_FIT_ZONES_MAX 256

/* A surface value that may be fitted. */
typedef enum rf_fit_field {
    RF_FIT_RESTITUTION,
    RF_FIT_FRICTION,
    RF_FIT_ROLLING,
    RF_FIT_ROUGHNESS,
    RF_FIT_TANGENTIAL,
    RF_FIT_NFIELDS
} rf_fit_field;

/* One fitted value, named by its path: `surface.FIELD` (every zone of the terrain),
 * `zones.NAME.FIELD` (one zone) or `zones.NAME+NAME+....FIELD` (one value shared by
 * these zones), FIELD one of restitution, friction, rolling, roughness, tangential (a
 * distribution's mean; its sd stays). */
typedef struct rf_fit_key {
    char path[160];
    long zone;          /* the first zone it sets (index into the terrain's zones), -1
                           for every zone */
    unsigned char zones[RF_FIT_ZONES_MAX]; /* 1 for each zone it sets */
    rf_fit_field field;
    double lo, hi;      /* the value's bounds */
    double step;        /* the simplex's initial step */
} rf_fit_key;

/* Parses a key's path against the project's zones; an unknown zone or field, or
 * `tangential` on a zone whose impact law has none, is an error. */
int rf_fit_key_parse(const rf_project *p, const char *path, rf_fit_key *k, rf_error *err);
/* The value a key has in the project (for `surface.`: the first zone's). */
double rf_fit_key_get(const rf_project *p, const rf_fit_key *k);
/* Sets it (the value clamped to the key's bounds). */
void rf_fit_key_set(rf_project *p, const rf_fit_key *k, double v);

/* Simulates every trajectory of the project's releases (no rows, no sink) with
 * `threads` threads; the horizontal stop point of global trajectory g into stop[2 g],
 * stop[2 g + 1], its start point into start (may be NULL); returns the number of
 * trajectories, or -1 when memory runs out.  The counts of trajectories that did not
 * come to rest into *not_rest (may be NULL). */
long rf_stops_simulate(const rf_project *p, int threads, double **stop, double **start,
                       size_t *not_rest);

typedef enum rf_objective {
    RF_OBJECTIVE_W1, /* W1(runout) / sd(observed runout) + W1(lateral) / sd(observed lateral) */
    RF_OBJECTIVE_KS  /* KS(runout) + KS(lateral) */
} rf_objective;

/* The objective's value for an agreement, and its name as the database stores it. */
double rf_objective_value(rf_objective k, const rf_agreement *a);
const char *rf_objective_name(rf_objective k);

typedef struct rf_calibrate_options {
    rf_objective objective;
    int threads;       /* >= 1 */
    long max_evals;    /* simulations at most (coarse scan and simplex together) */
    int coarse;        /* points of the coarse scan before the simplex (0: none) */
    double tol;        /* the simplex's size at which it stops, in initial steps */
    FILE *progress;    /* one line per simplex iteration; NULL for none */
} rf_calibrate_options;

typedef struct rf_calibration {
    size_t nkeys;
    double *start, *value;   /* per key: the project's value, the fitted one */
    double objective;        /* the objective at the fitted values */
    rf_agreement agreement;  /* at the fitted values */
    size_t not_rest;         /* simulated rocks not at rest at the fitted values */
    long n_evals;            /* simulations of the whole project */
    long n_trajectories;     /* trajectories per simulation */
    int converged;           /* the simplex shrank below tol (else max_evals ran out) */
} rf_calibration;

/* Fits the keys' values to the nobs observed stop points (x, y pairs): a coarse scan
 * of `coarse` points spread evenly over the keys' ranges (a Halton sequence), then
 * GSL's Nelder-Mead simplex (nmsimplex2) from the best of them and the project's
 * values.  A
 * value outside its bounds is evaluated at the nearest bound, its objective raised by
 * the distance outside in steps, so the simplex turns back.  The project is left at
 * the fitted values.  -1 with err on failure. */
int rf_calibrate(rf_project *p, const double *obs, size_t nobs, const rf_fit_key *keys,
                 size_t nkeys, const rf_calibrate_options *o, rf_calibration *out,
                 rf_error *err);
void rf_calibration_free(rf_calibration *c);

/* The objective at the project's current values: simulates and compares; -1 when
 * memory runs out. */
int rf_calibrate_objective(const rf_project *p, const double *obs, size_t nobs, int threads,
                           rf_objective kind, double *objective, rf_agreement *a,
                           size_t *not_rest);

#endif
