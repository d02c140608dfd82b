/* test_replay_rest.c - hard cases that pin rest: a rock bouncing to rest, a resting
 * rock staying put, and replays that stalled (events in no time, the event cap) where
 * they should rest. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

TEST(hard_bounce_to_rest_on_flat_ground)
{
    rf_terrain t;
    mt_incline(&t, 0.0, 100.0, 100.0, (rf_surface){{0.55, 0.0}, {0.4, 0.0}, {0.1, 0.0}});
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(2385.0, 2650.0, md);
        double r0 = rf_body_contact_radius(&b);
        rf_state s = mt_state(rf_v3(31.7, 44.9, 7.3 + r0), rf_v3(0, 0, 0));
        mt_run r;
        mt_simulate(&t, md, 2385.0, RF_CONTACT_FULL, &s, 7, &r);
        ensure_sane(&r, 300);
        ENSURE(r.rec.reason == RF_END_REST);
        ENSURE(r.rec.n_impacts > 3 && r.rec.n_impacts < 40);
        ENSURE(r.npoints < 100);
        ENSURE(r.rec.stop.x == 31.7 && r.rec.stop.y == 44.9);
        ENSURE_SMALL(r.rec.stop.z - r0, 1e-12);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

TEST(hard_resting_rock_stays_put)
{
    const double theta = 20.0 * PI / 180.0;
    rf_terrain t;
    mt_incline(&t, theta, 100.0, 50.0, (rf_surface){{0.3, 0.0}, {0.8, 0.0}, {0.5, 0.0}});
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(4500.0, 2650.0, md);
        rf_state s = mt_incline_state(theta, 100.0, 40.0, 20.0, rf_body_contact_radius(&b), rf_v3(0, 0, 0));
        mt_run r;
        mt_simulate(&t, md, 4500.0, RF_CONTACT_FULL, &s, 7, &r);
        ENSURE(r.rec.reason == RF_END_REST);
        ENSURE(r.rec.duration_s == 0.0);
        ENSURE(r.rec.n_impacts == 0);
        ENSURE_SMALL(rf_v3_norm(rf_v3_sub(r.rec.stop, s.p)), 1e-12);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* A 4 t sphere jiggles in a pocket of faces, slower than stop_speed, every event
 * moving it a hair (no single face or crease holds it): it rests within a few dozen
 * events, where it ran into the event cap (200 000 events, 10 s of computing). */
TEST(hard_replay_rock_creeping_in_a_pocket_rests)
{
    replay_sphere_rests(2, 8, 97);
}

/* A sphere rolling up a steep face, where rolling against its resistance needs more
 * friction than mu N but the slip law lets no slip grow from zero: it rolls on (it
 * switched between the two laws at every instant, 17 000 events until the rescues ran
 * out). */
TEST(hard_replay_rolling_uphill_where_the_laws_disagree)
{
    replay_sphere_rests(4, 3, 79);
}
