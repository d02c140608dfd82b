/* scene_test_util.h - the scenes of measures through the engines (test_measures_engine.c,
 * test_scene_events.c): the engine settings every scene runs under and the checks of an
 * interception record. */
#ifndef ROCKFALL_SCENE_TEST_UTIL_H
#define ROCKFALL_SCENE_TEST_UTIL_H

#include "motion_test_util.h"
#include "rockfall/sim.h"

/* Full-contact options of the tests (mt_sim) under engine `engine` with step dt. */
rf_simulation engine_sim(rf_rock_model model, rf_engine_kind engine, double dt);

/* Engine 0 (exact) or 1 (fixed steps of 1 ms), the two every scene runs under. */
rf_simulation engine_k(rf_rock_model model, int engine);

/* mt_run_scene with the stream every scene here runs with. */
void run_scene(const rf_terrain *t, const rf_simulation *sim, const rf_body *b,
               const rf_measure *ms, size_t nms, const rf_state *s, mt_scene_run *run);

/* A surface of constant e, mu and mu_r. */
rf_surface surface(double e, double mu, double mu_r);

/* The recorded values of one interception are consistent with each other and with
 * the body: energies from the speed, the total as their sum. */
void check_record(const rf_interception_record *r, const rf_body *b);

/* The scene under engine `engine` (engine_k): ENSUREs it records `want` interceptions,
 * each consistent (check_record). */
void run_engine(const rf_terrain *t, rf_rock_model model, int engine, const rf_body *b,
                const rf_measure *ms, size_t nms, const rf_state *s, int want, mt_scene_run *run);

/* Horizontal intersection of the line through p with direction d and segment A-B:
 * the path parameter s (p + s d) and the segment fraction u. */
int line_segment(double px, double py, double dx, double dy, const double *A, const double *B,
                 double *s, double *u);

#endif
