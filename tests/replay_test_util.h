/* replay_test_util.h - what the hard cases and the replays of random scenes share
 * (tests/test_replay_*.c, tests/test_fixed_step.c, tests/test_determinism.c). */
#ifndef ROCKFALL_REPLAY_TEST_UTIL_H
#define ROCKFALL_REPLAY_TEST_UTIL_H

#include <gsl/gsl_rng.h>

#include "motion_test_util.h"
#include "rockfall/sim.h"

#define PI 3.14159265358979323846
#define G RF_GRAVITY

/* A rough rocky surface: e, mu and mu_r with their spreads. */
extern const rf_surface ROCKY;

/* No NaN, no time past max_time (max_time reached only at max_time), no kinetic energy
 * gained at an impact. */
void ensure_sane(const mt_run *r, double max_time);

/* A 61 x 41 rough slope of 1 m cells with a nodata hole, its heights drawn from rng. */
void rough_terrain(rf_terrain *t, const char *name, gsl_rng *rng);

/* ---- replays of random scenes that once went wrong ------------------------------------
 *
 * A randomised search over rough grids, surfaces, rocks and engine settings found these.
 * Scene `it` of search `seed`: the grid and its surface, then per trajectory its
 * settings and start, all drawn in a fixed order from one stream, so that trajectory k
 * is replayed alone (the draws of the ones before it are made and dropped). */

typedef struct replay {
    rf_terrain t;
    rf_simulation sim;
    rf_body b;
    rf_state s;
    unsigned long seed;
} replay;

/* A replayed scene's name: its seed, its index and the trajectory's index. */
typedef struct replay_id {
    unsigned long seed;
    long it, k;
} replay_id;

/* Runs check on each replayed scene of the list ({seed, it, k}, ...). */
#define REPLAY_EACH(check, ...)                                                         \
    do {                                                                                  \
        static const replay_id cases_[] = {__VA_ARGS__};                                  \
        for (size_t i_ = 0; i_ < sizeof cases_ / sizeof *cases_; i_++)                    \
            check(cases_[i_].seed, cases_[i_].it, cases_[i_].k);                          \
    } while (0)

/* Scene `it` of search `seed`, trajectory k; mesh: the scene as a mesh, each cell split
 * along a diagonal that alternates with its parity (unlike a grid), nodata left open. */
void replay_scene(unsigned long seed, long it, long k, int mesh, replay *rp);

/* Runs the replay. */
void replay_run(replay *rp, double sample_spacing, mt_run *r);

/* The replayed rock does not end under the terrain. */
void ensure_ends_above(const replay *rp, const mt_run *r, unsigned long seed, long it,
                       long k);

/* The checks every replay ends with - no energy gained at an impact, not ending under
 * the terrain - and its clean-up. */
void replay_finish(replay *rp, mt_run *r, unsigned long seed, long it, long k);

/* Builds the replay, a rock of `model` in the exact engine. */
void replay_pick(unsigned long seed, long it, long k, rf_rock_model model, replay *rp);

/* replay_pick, and runs it into r. */
void replay_open(unsigned long seed, long it, long k, rf_rock_model model, replay *rp,
                 mt_run *r);

/* A rock of the exact engine in the replay ends for `reason` within 2 000 events; the
 * run is left in r for more checks and replay_finish. */
void replay_ends_open(unsigned long seed, long it, long k, rf_rock_model model, int reason,
                      replay *rp, mt_run *r);

/* replay_ends_open, gaining no energy at an impact, and not under the terrain. */
void replay_ends(unsigned long seed, long it, long k, rf_rock_model model, int reason);

/* A rock of the exact engine in the replay rests (replay_ends): a sphere, a point mass. */
void replay_sphere_rests(unsigned long seed, long it, long k);
void replay_point_rests(unsigned long seed, long it, long k);

/* The most path points in a row within a nanosecond of the one before: 16 events
 * without progress in time (RF_STALL_EVENTS) is a stall, which the engine rescues. */
size_t longest_stall(const mt_run *r);

/* Runs the replay: it rests, without a stall (the engine never had to rescue it)
 * unless `rescued`, gaining no energy at an impact, and not under the terrain. */
void replay_rests(replay *rp, unsigned long seed, long it, long k, int rescued);

/* As replay_sphere_rests (a centre-contact sphere), and without a stall. */
void replay_centre_rests_unstalled(unsigned long seed, long it, long k);

/* The built replay's mechanical energy (kinetic and m g z) never rises along its path
 * after the start (where a centre may be put onto its face's offset plane) above the
 * least it has had, by more than 1e-9 m g r; it ends for `reason`. */
void replay_energy_stays_down(replay *rp, unsigned long seed, long it, long k, int reason);

/* replay_energy_stays_down for the replay as the scene has it. */
void replay_energy_never_rises(unsigned long seed, long it, long k, int reason);

#endif
