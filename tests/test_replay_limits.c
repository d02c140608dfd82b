/* test_replay_limits.c - hard cases that pin the limits of the inputs: restitution and
 * friction at and beyond their truncation limits, e = 1 bouncing for ever, and rocks of
 * 1 kg and 100 t. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

/* ---- truncation limits ----------------------------------------------------------------- */

TEST(hard_restitution_and_friction_at_limits)
{
    double prof[6] = {0.0, 30.0, 60.0, 0.0, 160.0, 0.0};
    const rf_surface cases[] = {
        {{0.0, 0.0}, {0.4, 0.0}, {0.1, 0.0}},   /* e = 0 */
        {{1.0, 0.0}, {0.4, 0.0}, {0.1, 0.0}},   /* e = 1 */
        {{0.4, 0.0}, {0.0, 0.0}, {0.0, 0.0}},   /* mu = 0 */
        {{0.4, 0.0}, {1e9, 0.0}, {1e9, 0.0}},   /* huge mu */
        {{0.5, 10.0}, {0.3, 10.0}, {0.1, 10.0}}, /* draws cut at the limits */
        {{-3.0, 0.1}, {-2.0, 0.1}, {-1.0, 0.1}}, /* means outside: clamped */
    };
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        rf_terrain t;
        mt_profile(&t, prof, 3, 30.0, cases[c]);
        for (int model = 0; model < 2; model++) {
            rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
            rf_state s = mt_state(rf_v3(5.0, 15.0, 35.0), rf_v3(2.0, 0.3, 0.0));
            mt_run r;
            mt_simulate_t(&t, md, 1000.0, RF_CONTACT_FULL, &s, 21 + c, 40.0, &r);
            ensure_sane(&r, 40.0);
            ENSURE(r.rec.n_impacts >= 1);
            mt_run_free(&r);
        }
        rf_terrain_free(&t);
    }
}

TEST(hard_e_one_bounces_forever_without_loss)
{
    rf_terrain t;
    mt_incline(&t, 0.0, 100.0, 100.0, (rf_surface){{1.0, 0.0}, {0.5, 0.0}, {0.1, 0.0}});
    rf_state s = mt_state(rf_v3(50.0, 50.0, 2.5), rf_v3(0, 0, 0));
    mt_run r;
    mt_simulate_t(&t, RF_MODEL_POINT, 10.0, RF_CONTACT_FULL, &s, 1, 20.0, &r);
    ENSURE(r.rec.reason == RF_END_MAX_TIME);
    double tb = 2.0 * sqrt(2.0 * 2.5 / G);
    ENSURE(labs(r.rec.n_impacts - (long)(20.0 / tb + 0.5)) <= 1);
    for (size_t k = 0; k < r.n_impacts; k++)
        ENSURE_REL(r.impacts[k].speed_ms, sqrt(2.0 * G * 2.5), 1e-9);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* ---- extreme masses -------------------------------------------------------------------- */

TEST(hard_one_kg_and_hundred_tonnes)
{
    double prof[6] = {0.0, 60.0, 80.0, 0.0, 200.0, 0.0};
    rf_terrain t;
    mt_profile(&t, prof, 3, 50.0, ROCKY);
    const double masses[] = {1.0, 1e5};
    for (int k = 0; k < 2; k++) {
        rf_body b = rf_body_make(masses[k], 2650.0, RF_MODEL_SPHERE);
        rf_state s = mt_state(rf_v3(3.0, 25.0, 60.0 - 0.75 * 3.0 + b.radius * 1.3), rf_v3(1, 0, 0));
        mt_run r;
        mt_simulate(&t, RF_MODEL_SPHERE, masses[k], RF_CONTACT_FULL, &s, 4, &r);
        ensure_sane(&r, 300);
        ENSURE(r.rec.reason == RF_END_REST || r.rec.reason == RF_END_EXITED);
        ENSURE(r.rec.stop.x > 60.0);
        ENSURE(r.rec.max_energy_kj <= masses[k] * G * 62.0 / 1000.0);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}
