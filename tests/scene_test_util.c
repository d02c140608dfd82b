/* scene_test_util.c - the scenes of measures through the engines: the engine settings
 * every scene runs under and the checks of an interception record. */
#include "scene_test_util.h"

#include <math.h>

#include "test.h"

rf_simulation engine_sim(rf_rock_model model, rf_engine_kind engine, double dt)
{
    rf_simulation sim = mt_sim(model, RF_CONTACT_FULL, 300.0);
    sim.engine = engine;
    sim.dt = dt;
    return sim;
}

/* Engine 0 (exact) or 1 (fixed steps of 1 ms), the two every scene runs under. */
rf_simulation engine_k(rf_rock_model model, int engine)
{
    return engine_sim(model, engine ? RF_ENGINE_FIXED_STEP : RF_ENGINE_EXACT, 0.001);
}

/* mt_run_scene with the stream every scene here runs with. */
void run_scene(const rf_terrain *t, const rf_simulation *sim, const rf_body *b,
               const rf_measure *ms, size_t nms, const rf_state *s, mt_scene_run *run)
{
    mt_run_scene(t, sim, b, ms, nms, s, 2385, run);
}

rf_surface surface(double e, double mu, double mu_r)
{
    rf_surface s = {{e, 0.0}, {mu, 0.0}, {mu_r, 0.0}};
    return s;
}

/* The recorded values of one interception are consistent with each other and with
 * the body: energies from the speed, the total as their sum. */
void check_record(const rf_interception_record *r, const rf_body *b)
{
    ENSURE(isfinite(r->t_s) && isfinite(r->p.x) && isfinite(r->p.y) && isfinite(r->p.z));
    ENSURE(isfinite(r->passing_height_m));
    ENSURE_REL(r->energy_trans_kj, 0.5 * b->mass * r->speed_ms * r->speed_ms / 1000.0, 1e-12);
    ENSURE_SMALL(r->energy_kj - r->energy_trans_kj - r->energy_rot_kj, 1e-9 * r->energy_kj);
    ENSURE(r->energy_rot_kj >= -1e-12 * r->energy_kj);
}

/* The scene under engine `engine` (engine_k): ENSUREs it records `want` interceptions,
 * each consistent (check_record). */
void run_engine(const rf_terrain *t, rf_rock_model model, int engine, const rf_body *b,
                const rf_measure *ms, size_t nms, const rf_state *s, int want, mt_scene_run *run)
{
    rf_simulation sim = engine_k(model, engine);
    run_scene(t, &sim, b, ms, nms, s, run);
    ENSURE_MSG(run->n == want, "engine %d: %d interceptions, %d expected", engine, run->n, want);
    for (int i = 0; i < run->n; i++)
        check_record(&run->icpt[i], b);
}

/* Horizontal intersection of the line through p with direction d and segment A-B:
 * the path parameter s (p + s d) and the segment fraction u. */
int line_segment(double px, double py, double dx, double dy, const double *A, const double *B,
                 double *s, double *u)
{
    double ex = B[0] - A[0], ey = B[1] - A[1];
    double det = -dx * ey + dy * ex;
    if (det == 0.0)
        return 0;
    double rx = A[0] - px, ry = A[1] - py;
    *s = (-rx * ey + ry * ex) / det;
    *u = (dx * ry - dy * rx) / det;
    return *u >= 0.0 && *u <= 1.0;
}
