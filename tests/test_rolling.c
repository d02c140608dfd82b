/* test_rolling.c - the work a trajectory records (flights, surface segments, impacts,
 * edge transitions; rf_trajectory_record) and the rolling phase on grids. */
#include "test.h"

#include <string.h>

#include "motion_test_util.h"

#define PI 3.14159265358979323846

/* A point mass released on an incline slides down it in one segment: no flight, no
 * impact, no grid edge (the incline is one plane). */
TEST(motion_counts_a_slide_as_one_segment)
{
    const double theta = 33.7 * PI / 180.0, L = 120.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 40.0, (rf_surface){{0.0, 0.0}, {0.2, 0.0}, {0.2, 0.0}});
    rf_state s = mt_state(rf_v3(30.0, 13.7, (L - 30.0) * tan(theta)), rf_v3(0, 0, 0));
    mt_run r;
    mt_simulate(&t, RF_MODEL_POINT, 2385.0, RF_CONTACT_FULL, &s, 1, &r);
    ENSURE(r.rec.reason == RF_END_EXITED);
    ENSURE(r.rec.n_flights == 0 && r.rec.n_impacts == 0 && r.rec.n_edge_transitions == 0);
    ENSURE(r.rec.n_segments >= 1 && r.rec.n_segments <= 3);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A sphere dropped onto a gentle incline bounces: every flight but the last ends in an
 * impact, and the exact engine's flights and segments are events, not steps; the
 * fixed-step engine counts a flight or a segment per step. */
TEST(motion_counts_flights_between_impacts)
{
    const double theta = 10.0 * PI / 180.0, L = 200.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 40.0, (rf_surface){{0.5, 0.0}, {0.3, 0.0}, {0.3, 0.0}});
    rf_state s = mt_state(rf_v3(20.0, 20.0, (L - 20.0) * tan(theta) + 3.0), rf_v3(1.0, 0, 0));
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    rf_simulation sim = mt_sim(RF_MODEL_SPHERE, RF_CONTACT_FULL, 4.0);
    mt_run r;
    mt_simulate_opts(&t, &sim, &b, &s, 1, 0.0, &r);
    ENSURE_MSG(r.rec.n_flights >= 2 && r.rec.n_impacts >= r.rec.n_flights - 1,
               "flights %ld impacts %ld", r.rec.n_flights, r.rec.n_impacts);
    ENSURE(r.rec.n_segments >= 1 && r.rec.n_segments < 100 && r.rec.n_flights < 100);
    ENSURE(r.rec.n_edge_transitions == 0);
    mt_run_free(&r);
    sim.engine = RF_ENGINE_FIXED_STEP;
    sim.dt = 0.01;
    mt_simulate_opts(&t, &sim, &b, &s, 1, 0.0, &r);
    long steps = r.rec.n_flights + r.rec.n_segments;
    ENSURE_MSG(steps >= (long)(r.rec.duration_s / sim.dt) && r.rec.n_flights >= 50,
               "flights %ld segments %ld over %g s", r.rec.n_flights, r.rec.n_segments,
               r.rec.duration_s);
    mt_run_free(&r);
    rf_terrain_free(&t);
}
