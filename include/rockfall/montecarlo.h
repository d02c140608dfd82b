/* montecarlo.h - Monte Carlo runs over a project's releases, into the results database.
 *
 * Trajectory k of release i draws only from its own GSL stream seeded from
 * (project seed, i, k), and rows are written in (release, index) order whatever the
 * number of threads: the same project and seed give the same database contents. */
#ifndef ROCKFALL_MONTECARLO_H
#define ROCKFALL_MONTECARLO_H

#include <signal.h>
#include <stdint.h>

#include <gsl/gsl_rng.h>

#include "rockfall/error.h"
#include "rockfall/project.h"
#include "rockfall/sim.h"

struct rf_store;

typedef struct rf_run_options {
    int threads;  /* worker threads, >= 1 */
    int maps;     /* keep the maps only (run --store maps): the run, releases, measures,
                   * interceptions, hazard cells and the sampled paths, with the
                   * trajectory rows those need and no tree hits (docs/scaling.md) */
    int progress; /* progress on stderr: 0 none, 1 one line rewritten (a terminal),
                   * 2 a line every 10 s (a log; mpirun's forwarded stderr) */
    /* may be NULL; once it reads nonzero (set by a signal handler), the run ends after
     * the rows being written, as failed ("interrupted") */
    const volatile sig_atomic_t *interrupted;
} rf_run_options;

typedef struct rf_run_summary {
    int64_t run_id;
    long n_trajectories;
    long by_reason[4]; /* indexed by rf_stop_reason */
    /* The engine's work summed over the trajectories (rf_trajectory_record): flights,
     * surface segments, impacts and edge transitions, the events the time divides. */
    double events[4];
    double seconds;    /* wall-clock time of the simulation and writing */
} rf_run_summary;

/* Runs every release of the project and writes one complete run into the store (its
 * row is 'failed' when anything goes wrong after it was begun). */
int rf_montecarlo_run(const rf_project *p, struct rf_store *s, const rf_run_options *o,
                      rf_run_summary *sum, rf_error *err);

/* Seed of trajectory `idx` of release `release` (a 64-bit mix of the three). */
unsigned long rf_trajectory_seed(uint64_t project_seed, size_t release, long idx);
/* The generator every trajectory uses. */
const gsl_rng_type *rf_rng_type(void);
/* The rock body of a release under a rock model (the project's: p->sim.model), with
 * the rock's mass (a distribution's mean, a list's mean). */
rf_body rf_release_body(const rf_project *p, size_t release, rf_rock_model model);
/* Start state of one trajectory of a release: the release point moved by the random
 * horizontal jitter (uniform in a disc), the rock resting on the ground along the
 * surface normal, raised by the release height, with the release velocity. */
rf_state rf_release_start(const rf_project *p, size_t release, const rf_body *b, gsl_rng *rng);

/* What a trajectory draws, in this order from its own stream: its mass (nothing drawn
 * for a fixed mass; a log-normal with mu = ln(mean) - sigma^2 / 2 and
 * sigma^2 = ln(1 + sd^2 / mean^2); a list's masses with equal probability, one
 * gsl_rng_uniform_int), then its start (nothing drawn for a point without jitter; a
 * point of an area: one uniform picks a triangle by its area, two place the point in it;
 * of a cell: two uniforms), each redrawn while off the terrain, at most 64 times. */
double rf_release_mass(const rf_project *p, size_t release, gsl_rng *rng);
rf_body rf_release_draw_body(const rf_project *p, size_t release, rf_rock_model model,
                             gsl_rng *rng, double *mass);
/* The start of trajectory idx of a release (idx picks a `cells` release's cell:
 * trajectory idx starts in source cell idx / count). */
rf_state rf_release_start_of(const rf_project *p, size_t release, long idx, const rf_body *b,
                             gsl_rng *rng);

#endif
