/* test_fixed_step.c - the fixed-step baseline (fixed_step.c): the paper's successive
 * integration over time converges to the exact engine as the step shrinks, on a plane
 * and on the Noto slope, and the hard cases it once got wrong - energy gained in no
 * time, rocks looping at a pit or along a wall, falling through a wall's column. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"
#include "rockfall/montecarlo.h"

/* ---- the fixed-step baseline converges to the exact engine ------------------------- */

static double fixed_vs_exact(rf_rock_model md, double dt, double *exact_x)
{
    /* a 35 degree slope 30 m long onto level ground; e = 0, mu = 0.3 */
    double prof[6] = {0.0, 21.0, 30.0, 0.0, 200.0, 0.0};
    rf_terrain t;
    mt_profile(&t, prof, 3, 40.0, (rf_surface){{0.0, 0.0}, {0.3, 0.0}, {0.3, 0.0}});
    rf_body b = rf_body_make(1500.0, 2650.0, md);
    double rho = rf_body_contact_radius(&b);
    double theta = atan2(21.0, 30.0);
    rf_vec3 n = rf_v3(sin(theta), 0, cos(theta));
    rf_state s = mt_state(rf_v3_madd(rf_v3(2.0, 20.0, 21.0 - 2.0 * 0.7), rho, n), rf_v3(0, 0, 0));
    /* the baseline tests contact as the paper does (Eq. 6-7): compare with the exact
     * engine's `centre` contact */
    rf_simulation sim = mt_sim(md, RF_CONTACT_CENTRE, 60.0);
    mt_run r;
    mt_simulate_opts(&t, &sim, &b, &s, 5, 0.0, &r);
    ENSURE(r.rec.reason == RF_END_REST);
    *exact_x = r.rec.stop.x;
    mt_run_free(&r);
    sim.engine = RF_ENGINE_FIXED_STEP;
    sim.dt = dt;
    mt_simulate_opts(&t, &sim, &b, &s, 5, 0.0, &r);
    ENSURE(r.rec.reason == RF_END_REST);
    ENSURE(r.energy_gain_kj <= 0.0);
    double err = fabs(r.rec.stop.x - *exact_x);
    mt_run_free(&r);
    rf_terrain_free(&t);
    return err;
}

TEST(motion_fixed_step_converges_to_exact)
{
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        double x, e1 = fixed_vs_exact(md, 1e-2, &x), e2 = fixed_vs_exact(md, 1e-3, &x),
                  e3 = fixed_vs_exact(md, 1e-5, &x);
        ENSURE_MSG(e3 < e1 && e2 < e1, "errors %.3g %.3g %.3g", e1, e2, e3);
        ENSURE_MSG(e3 < 2e-6 * x, "error %.3g at dt = 1e-5", e3);
    }
}

/* On real terrain the baseline must integrate the same model as the exact engine: the
 * same impact law, stay threshold, lifts and wall reflections of centre contact, face
 * changes over convex and concave edges, creases, rolling against slipping.  The Noto
 * slope (1 m grid, 44 degrees, gullies) exercises all of them; a trajectory there has
 * about 100 terrain events.  Both engines run the same trajectories (same streams), so
 * the error of the baseline is the mean of the paired differences, whose Monte Carlo
 * standard error is sd(differences) / sqrt(n). */

static void first_crossing(void *ctx, const rf_interception_record *r)
{
    double *v = ctx;
    if (isnan(*v))
        *v = r->speed_ms;
}

/* n trajectories of the Noto release with centre contact: maximum kinetic energy (kJ)
 * and speed at the road (NaN when it never gets there). */
static void noto_trajectories(rf_project *p, rf_engine_kind engine, double dt, int n, double *e,
                              double *v)
{
    p->sim.engine = engine;
    p->sim.dt = dt;
    p->sim.contact = RF_CONTACT_CENTRE;
    rf_scene sc = {&p->terrain, &p->sim, NULL, 0, p->measures, p->nmeasures};
    rf_body b = rf_release_body(p, 0, p->sim.model);
    rf_workspace *ws = rf_workspace_alloc(&p->terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    ENSURE(ws && rng);
    for (int k = 0; k < n; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p->seed, 0, k));
        rf_state s = rf_release_start(p, 0, &b, rng);
        rf_sink sk;
        memset(&sk, 0, sizeof sk);
        v[k] = NAN;
        sk.ctx = &v[k];
        sk.interception = first_crossing;
        rf_trajectory_record rec;
        rf_simulate(&sc, &b, &s, rng, ws, &sk, &rec);
        ENSURE_MSG(rec.reason == RF_END_EXITED, "trajectory %d ends with %d", k, (int)rec.reason);
        e[k] = rec.max_energy_kj;
    }
    gsl_rng_free(rng);
    rf_workspace_free(ws);
}

/* Mean of the paired differences a - b over the pairs where both are numbers, and its
 * standard error. */
static void paired_difference(const double *a, const double *b, int n, double *mean, double *se)
{
    double s = 0, s2 = 0;
    int m = 0;
    for (int k = 0; k < n; k++) {
        if (isnan(a[k]) || isnan(b[k]))
            continue;
        double d = a[k] - b[k];
        s += d, s2 += d * d, m++;
    }
    ENSURE(m > 1);
    *mean = s / m;
    *se = sqrt(fmax(0.0, s2 / m - *mean * *mean) / (m - 1));
}

TEST(motion_fixed_step_converges_to_exact_on_noto)
{
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load("projects/noto/noto-3.1-no-trees.yaml", &p, &err) == 0, "%s: %s",
               err.file, err.message);
    enum { N = 200 };
    const double dts[2] = {2e-4, 2e-1};
    static double ee[N], ve[N], ef[N], vf[N];
    noto_trajectories(&p, RF_ENGINE_EXACT, 0.0, N, ee, ve);
    double err_e[2], err_v[2], se_e[2], se_v[2];
    for (int i = 0; i < 2; i++) {
        noto_trajectories(&p, RF_ENGINE_FIXED_STEP, dts[i], N, ef, vf);
        paired_difference(ef, ee, N, &err_e[i], &se_e[i]);
        paired_difference(vf, ve, N, &err_v[i], &se_v[i]);
        printf("    dt %g s: max energy %+.1f kJ (SE %.1f), road speed %+.3f m/s (SE %.3f)\n",
               dts[i], err_e[i], se_e[i], err_v[i], se_v[i]);
    }
    /* the small step agrees within the Monte Carlo noise (4 standard errors) ... */
    ENSURE_MSG(fabs(err_e[0]) <= 4.0 * se_e[0], "max energy off by %.1f kJ (SE %.1f)", err_e[0], se_e[0]);
    ENSURE_MSG(fabs(err_v[0]) <= 4.0 * se_v[0], "road speed off by %.3f m/s (SE %.3f)", err_v[0], se_v[0]);
    /* ... and the large one (0.2 s) does not: the error shrinks with the step.  (At
     * 0.05 s the road speed was 1.4 m/s and the energy 416 kJ too high only through
     * the step velocity taken at pieces of no time, energy from nothing; without it
     * the fixed step's road speed is within the noise of 200 rocks up to 0.1 s.) */
    ENSURE_MSG(fabs(err_e[1]) > 4.0 * se_e[1] && fabs(err_e[1]) > 4.0 * fabs(err_e[0]),
               "max energy: %.1f kJ at dt %g, %.1f kJ at dt %g", err_e[1], dts[1], err_e[0], dts[0]);
    ENSURE_MSG(fabs(err_v[1]) > 4.0 * se_v[1] && fabs(err_v[1]) > 4.0 * fabs(err_v[0]),
               "road speed: %.3f m/s at dt %g, %.3f m/s at dt %g", err_v[1], dts[1], err_v[0], dts[0]);
    rf_project_free(&p);
}

/* ---- replays of random scenes that once went wrong (replay_test_util.h) -------------- */

/* The fixed-step engine: where a piece ended on a feature that the velocity of its time
 * does not meet and the step's does (a hop shorter than the step, an edge crossed),
 * the rock took the step's velocity, h a more than it had; at a piece of no time it
 * gained that in no time, every time.  A point mass hopping on and off its faces at a
 * grid node went from 17.1 to 17.8 m/s at one instant (46/1/6: 0.49 m g of energy
 * from nothing), a centre-contact sphere gained 0.083 m g (46/1/16).  It now goes on
 * in the step's direction at the speed of its time. */
TEST(hard_replay_fixed_step_gains_nothing_in_no_time)
{
    replay_energy_never_rises(46, 1, 6, RF_END_EXITED);
    replay_energy_never_rises(46, 1, 16, RF_END_EXITED);
}

/* The fixed-step engine with a point mass that comes to a grid node at the bottom of a
 * pit (a height rounded down beside higher ones), where every step crosses into the
 * next of the six faces around the node after less than a nanosecond: it ends.  It
 * looped for ever: time crept on, too little for the stall guard, and the engine had
 * no event cap.  (A 9 x 9 cut of a random rough grid.) */
TEST(hard_fixed_step_point_in_a_pit_at_a_grid_node_ends)
{
    static const char grid[] =
        "ncols 9\nnrows 9\nxllcorner 1013.0\nyllcorner 2009.0\ncellsize 1\nNODATA_value -9999\n"
        "80.446420156363459 78 77 75.802969849988287 72.950259003730096 72.711152851200211 "
        "71.309327908665423 69.709960410266447 68.278710190648553\n"
        "80.388459164109435 78.851082945499542 77 75.889142300813504 71.450426739469435 "
        "72.802544153648697 71 69.794028425168889 68\n"
        "80.294590132380335 78.892317815389234 77.372637816430768 75.780712352337488 72 "
        "72.794251736945753 71.228905136333012 69.68045885703161 68.290051164566506\n"
        "80.359898423494755 78.842084915002573 77.257650797140613 75.879558465782367 "
        "71.570884654688982 72.750514206061766 71.200144261694021 69.712403492164071 "
        "68.23444510019786\n"
        "80.3146990069976 78.921001170992966 77.359088328174849 75.744343510423093 71 "
        "72.798377220332867 71.244427091222363 69.77786678886342 68.165491125078574\n"
        "80 78.889148884312959 77.287674887063517 75 71.748342965351668 72.754720459148942 71 "
        "69.73932660069346 68.175741770965374\n"
        "80.430591697729227 78.892725877263942 77.297133064792618 75.788899582615173 "
        "72.902582572134236 72.736190437952644 71.204261347768806 69.716026219299238 "
        "68.292825492580377\n"
        "80.41485827330969 78.834214341659049 77 75.813319912554775 73.84943517230856 "
        "72.816161602202598 71.197645138803466 69.730624715976276 68.18845263825601\n"
        "80 78.798444642710081 77.359445339073275 75 74.271338284251314 72.709214144374769 "
        "71.313557320499584 69.730468155036547 68.244910429615743\n";
    rf_terrain t;
    mt_dem_text(&t, "pit.asc", grid,
                (rf_surface){{0.33737238403409719, 0.18536296414677053},
                             {0.0, 0.18762585958465935},
                             {0.42919653397984803, 0.038820552488323307}});
    rf_simulation sim = mt_sim(RF_MODEL_POINT, RF_CONTACT_FULL, 120.0);
    sim.engine = RF_ENGINE_FIXED_STEP;
    sim.dt = 0.0099329566922970111;
    rf_body b = rf_body_make(7246.1540855314861, 2650.0, RF_MODEL_POINT);
    rf_state s = mt_state(rf_v3(1018.0788941085572, 2015.142883110419, 72.306543313840251),
                          rf_v3(0.84324971027672291, -2.9126256904564798, 0.0));
    mt_run r;
    mt_simulate_opts(&t, &sim, &b, &s, 5600193, 0.0, &r);
    ENSURE_MSG(r.npoints < 100000, "%zu points", r.npoints);
    ENSURE(r.rec.reason == RF_END_REST);
    ENSURE_SMALL(r.rec.stop.x - 1017.5, 1e-9);
    ENSURE_SMALL(r.rec.stop.y - 2013.5, 1e-9);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A rock of the fixed-step engine in the replay rests, without a stall unless
 * `rescued` (replay_rests). */
static void replay_fixed_step_ends_at_rest(unsigned long seed, long it, long k, int rescued)
{
    replay rp;
    replay_scene(seed, it, k, 0, &rp);
    ENSURE(rp.sim.engine == RF_ENGINE_FIXED_STEP);
    replay_rests(&rp, seed, it, k, rescued);
}

/* The same scenes as meshes: two fixed-step rocks stopped on a column's border at a pit
 * beside a hole, under the face's offset plane, fell 25 m through the terrain (the
 * step's search finds no entry into a plane the centre is already under, and time went
 * on, so no stall rescued them); a centre sinking under the face is rescued at once,
 * and they end above the ground. */
static void replay_mesh_fixed_step_stays_above(unsigned long seed, long it, long k)
{
    replay rp;
    replay_scene(seed, it, k, 1, &rp);
    ENSURE(!rp.t.is_grid && rp.sim.engine == RF_ENGINE_FIXED_STEP);
    mt_run r;
    replay_run(&rp, 0.0, &r);
    replay_finish(&rp, &r, seed, it, k);
}

TEST(hard_replay_fixed_step_on_a_mesh_at_a_pit_beside_a_hole_stays_above)
{
    REPLAY_EACH(replay_mesh_fixed_step_stays_above, {14, 47, 185}, {10, 57, 194});
}

static void replay_fixed_step_rests(unsigned long seed, long it, long k)
{
    replay_fixed_step_ends_at_rest(seed, it, k, 0);
}

static void replay_fixed_step_rests_rescued(unsigned long seed, long it, long k)
{
    replay_fixed_step_ends_at_rest(seed, it, k, 1);
}

/* The fixed-step engine (centre contact): spheres rolling or sliding on a face against
 * the border of its column, beyond which rises a face they cannot pay the lift onto (a
 * wall).  Each step left the face over that border, was reflected off the wall and
 * turned back into it by the next step, in no time, until the rescue pushed the rock
 * out along the normal, under the next column's plane, and it fell through the terrain
 * (1/5/21 by 10 m, 1/7/48, 1/9/74; 93 % of the 11 742 falls of the fixed-step engine
 * on the random scenes went through a rescue), or, rescued onto that plane, looped on
 * until the rescues ran out (1/5/220).  Its steps now meet the wall as the exact
 * engine's segments do (rf_wall_meet) and move along it, and they rest.  Moving along
 * one wall at a corner of two, a step that leaves over the other at once meets it with
 * the step's velocity, which the corner stops: with the rock's own velocity, out of the
 * corner along the first wall, it went from one wall to the other at every step, in
 * no time (1/5/21, once a reflection at a column's corner, above, turned it back
 * out). */
TEST(hard_replay_fixed_step_along_a_wall_rests)
{
    REPLAY_EACH(replay_fixed_step_rests, {1, 5, 21}, {1, 7, 48}, {1, 9, 74}, {1, 5, 220});
}

/* The fixed-step engine: a step whose velocity carries the centre out over a border of
 * its column that it lies on, where a wall rises, left the face at once at every step
 * (the reflection off the wall turned back out by the step's velocity): on the
 * diagonal of a cell (1/33/29), and at a grid node, where the face entered is not the
 * one over the edge's middle (77/1/174).  The rock now meets the wall there, and rests. */
TEST(hard_replay_fixed_step_leaving_into_a_wall_at_once_meets_it)
{
    REPLAY_EACH(replay_fixed_step_rests, {1, 33, 29}, {77, 1, 174});
}

/* The fixed-step engine: a sphere rolling along the diagonal of a cell crosses it with
 * the step's velocity, but the velocity of the moment of crossing, interpolated within
 * the step, points back along it: it flew off with that velocity back over the face it
 * had left, which a flight does not meet, below that face's plane, and fell 5 m through
 * the terrain.  It now leaves with the step's velocity, and rests. */
TEST(hard_replay_fixed_step_leaving_along_an_edge_does_not_fly_back)
{
    replay_fixed_step_rests(1, 25, 176);
}

/* The fixed-step engine: a point mass on frictionless faces around a pit at a grid
 * node, slower than stop_speed, crossing from face to face at every step within a
 * micrometre: no face holds it (mu = 0), and the slow rock's creep was not counted, so
 * it went on until max_time (250 000 points).  It now rests as in the exact engine. */
TEST(hard_replay_fixed_step_point_creeping_in_a_frictionless_pit_rests)
{
    replay_fixed_step_rests(1, 5, 214);
}

/* The fixed-step engine (centre contact): spheres wedged among walls, stalled in no
 * time, and rescued.  The rescue pushed them out along the normal of the face under
 * them, which left them under the next column's offset plane, and they fell through
 * the terrain (783 falls on the random scenes).  It now lifts the centre onto its
 * column's plane as in the exact engine, and they rest. */
TEST(hard_replay_fixed_step_rescued_among_walls_stays_over_its_column)
{
    REPLAY_EACH(replay_fixed_step_rests_rescued, {56, 3, 268}, {100, 20, 129}, {100, 31, 101});
}

/* The fixed-step engine tested its steps' straight pieces with a copy of the flight's
 * column test that lacked the exact engine's later rules (where a column is met, a
 * flight starting on a column's edge); 3 823 of its rocks fell through the random
 * scenes that way.  The pieces now go through the flight's search (rf_contact_search),
 * and these rest. */
TEST(hard_replay_fixed_step_pieces_searched_as_flights_rest)
{
    REPLAY_EACH(replay_fixed_step_rests, {19, 36, 0}, {100, 11, 60}, {100, 11, 70}, {100, 13, 80});
}

/* The fixed-step engine (centre contact): spheres over a steep face near the top of a
 * grid, within reach of its plane (r / n.z above it, vertically) but more than r above
 * the terrain's highest node, fell through that face: the flight's search dropped
 * every piece higher than r above the terrain's top, a bound that holds for a sphere
 * but not for a centre over a steep face; the fixed step's short pieces met it (37
 * falls on the random scenes, half of them rescued from among walls onto such a face's
 * plane, 10/2/270, and let fall).  The bound is now r over the smallest n.z of the
 * terrain in centre mode, and they rest. */
TEST(hard_replay_fixed_step_over_a_steep_face_at_the_top_rests)
{
    REPLAY_EACH(replay_fixed_step_rests_rescued, {10, 2, 270}, {27, 12, 285}, {30, 35, 232},
                {29, 28, 14});
}

/* ---- friction that stops a rock within a step ---------------------------------------- */

/* On an incline of theta (friction mu, no bounce) a rock starts at x = 20 with speed V0
 * down the fall line (negative: up it).  Engine 0: exact (centre contact), else fixed
 * step dt.  Returns the speed at the control line x = 60 (NaN when it never gets
 * there) and the record. */
static double incline_run(rf_rock_model md, double theta_deg, double mu, double V0, double dt,
                          rf_trajectory_record *rec)
{
    const double theta = theta_deg * M_PI / 180.0, L = 200.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 40.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu, 0.0}});
    rf_body b = rf_body_make(1500.0, 2650.0, md);
    double line[] = {60.0, -10.0, 60.0, 50.0};
    rf_measure ms = mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0);
    rf_vec3 v0 = rf_v3(V0 * cos(theta), 0, -V0 * sin(theta));
    rf_state s = mt_incline_state(theta, L, 20.0, 20.0, rf_body_contact_radius(&b), v0);
    rf_simulation sim = mt_sim(md, RF_CONTACT_CENTRE, 60.0);
    if (dt > 0) {
        sim.engine = RF_ENGINE_FIXED_STEP;
        sim.dt = dt;
    }
    static mt_scene_run run;
    mt_run_scene(&t, &sim, &b, &ms, 1, &s, 38, &run);
    *rec = run.rec;
    rf_terrain_free(&t);
    return run.n > 0 ? run.icpt[0].speed_ms : NAN;
}

/* Friction that would reverse the motion within a step set the velocity to zero for
 * the whole step: the rock stood still for the rest of it (the step's time lost),
 * wherever gravity along the face exceeds friction.  The step now ends where the speed
 * vanishes and the next starts from rest: down the fall line on a face steeper than
 * friction holds, at rest on one that holds it.  Thrown up a 35 degree face (mu 0.3) at
 * 5 m/s, the rock turns within a step and slides down, never resting; its speed 40 m
 * further on converges at first order to the exact engine's, and for a point mass to
 * the closed form sqrt(2 a_down (d_up + s)). */
TEST(motion_fixed_step_turned_back_by_friction_on_a_steep_face_slides_on)
{
    const double g = RF_GRAVITY, th = 35.0 * M_PI / 180.0, mu = 0.3;
    const double a_up = g * (sin(th) + mu * cos(th)), a_dn = g * (sin(th) - mu * cos(th));
    const double closed = sqrt(2.0 * a_dn * (25.0 / a_up / 2.0 + 40.0 / cos(th)));
    const double dts[3] = {0.1, 0.01, 0.001};
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_trajectory_record rec;
        double ve = incline_run(md, 35.0, mu, -5.0, 0.0, &rec), err[3];
        ENSURE(rec.reason == RF_END_EXITED && !rec.rest_on_steep_face);
        if (model)
            ENSURE_REL(ve, closed, 1e-9);
        for (int i = 0; i < 3; i++) {
            double vf = incline_run(md, 35.0, mu, -5.0, dts[i], &rec);
            ENSURE_MSG(rec.reason == RF_END_EXITED && !isnan(vf), "model %d dt %g: reason %d",
                       model, dts[i], rec.reason);
            err[i] = fabs(vf - ve);
            printf("    %s, thrown up: dt %g s: %.4f m/s at 40 m, exact %.4f (error %.2g)\n",
                   model ? "point" : "sphere", dts[i], vf, ve, err[i]);
        }
        ENSURE_MSG(err[1] < 0.2 * err[0] && err[2] < 0.2 * err[1], "errors %.3g %.3g %.3g",
                   err[0], err[1], err[2]);
        ENSURE(err[2] < 1e-3 * ve);
    }
}

/* A rock thrown across the fall line of a face that holds it (10 degrees, mu 0.5)
 * curves down the slope as friction slows it, and rests: the step in which friction
 * stops it ends where its speed vanishes, and the pull down the slope across its path
 * over that step is lost; the stop point still converges at first order to the exact
 * engine's. */
TEST(motion_fixed_step_thrown_across_a_face_that_holds_it_rests_where_the_exact_does)
{
    const double theta = 10.0 * M_PI / 180.0, L = 200.0;
    const double dts[3] = {0.1, 0.01, 0.001};
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_terrain t;
        mt_incline(&t, theta, L, 200.0, (rf_surface){{0.0, 0.0}, {0.5, 0.0}, {0.5, 0.0}});
        rf_body b = rf_body_make(1500.0, 2650.0, md);
        rf_state s = mt_incline_state(theta, L, 60.0, 20.0, rf_body_contact_radius(&b),
                                      rf_v3(0.0, 10.0, 0.0));
        rf_vec3 stop[4];
        for (int i = 0; i < 4; i++) {
            rf_simulation sim = mt_sim(md, RF_CONTACT_CENTRE, 60.0);
            if (i > 0) {
                sim.engine = RF_ENGINE_FIXED_STEP;
                sim.dt = dts[i - 1];
            }
            static mt_scene_run run;
            mt_run_scene(&t, &sim, &b, NULL, 0, &s, 38, &run);
            ENSURE_MSG(run.rec.reason == RF_END_REST && !run.rec.rest_on_steep_face,
                       "model %d run %d: reason %d", model, i, run.rec.reason);
            stop[i] = run.rec.stop;
        }
        /* it went across and down: the stop lies beyond its start on both axes */
        ENSURE(stop[0].y > 25.0 && stop[0].x > 60.0);
        double err[3];
        for (int i = 0; i < 3; i++) {
            err[i] = rf_v3_norm(rf_v3_sub(stop[i + 1], stop[0]));
            printf("    %s, thrown across: dt %g s: stop %.4f m from the exact engine's\n",
                   model ? "point" : "sphere", dts[i], err[i]);
        }
        ENSURE_MSG(err[1] < 0.2 * err[0] && err[2] < 0.2 * err[1], "errors %.3g %.3g %.3g",
                   err[0], err[1], err[2]);
        rf_terrain_free(&t);
    }
}

/* The same rock released at rest on the steep face: it slides (or rolls) from the
 * first step on, at first order towards the exact speed at the line (for a point mass
 * the closed form sqrt(2 a_down s)). */
TEST(motion_fixed_step_from_rest_on_a_steep_face_converges)
{
    const double g = RF_GRAVITY, th = 35.0 * M_PI / 180.0, mu = 0.3;
    const double closed = sqrt(2.0 * g * (sin(th) - mu * cos(th)) * 40.0 / cos(th));
    const double dts[3] = {0.1, 0.01, 0.001};
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_trajectory_record rec;
        double ve = incline_run(md, 35.0, mu, 0.0, 0.0, &rec), err[3];
        if (model)
            ENSURE_REL(ve, closed, 1e-9);
        for (int i = 0; i < 3; i++) {
            double vf = incline_run(md, 35.0, mu, 0.0, dts[i], &rec);
            ENSURE(rec.reason == RF_END_EXITED && !rec.rest_on_steep_face);
            err[i] = fabs(vf - ve);
            printf("    %s, from rest: dt %g s: %.4f m/s at 40 m, exact %.4f (error %.2g)\n",
                   model ? "point" : "sphere", dts[i], vf, ve, err[i]);
        }
        ENSURE_MSG(err[1] < 0.2 * err[0] && err[2] < 0.2 * err[1], "errors %.3g %.3g %.3g",
                   err[0], err[1], err[2]);
    }
}

/* On a face that holds it (10 degrees, mu 0.5) a rock set off down the fall line at
 * 10 m/s decelerates to rest: the fixed step still rests it, not flagged, and its stop
 * converges at first order to the exact engine's (a point mass: the closed form, rest at
 * the stop speed, (V0^2 - v_stop^2) / 2 a along the face). */
TEST(motion_fixed_step_decelerating_on_a_face_that_holds_rests)
{
    const double g = RF_GRAVITY, th = 10.0 * M_PI / 180.0, mu = 0.5;
    const double closed = 20.0 + cos(th) * (100.0 - 0.01) / (2.0 * g * (mu * cos(th) - sin(th)));
    const double dts[3] = {0.1, 0.01, 0.001};
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_trajectory_record rec;
        incline_run(md, 10.0, mu, 10.0, 0.0, &rec);
        ENSURE(rec.reason == RF_END_REST && !rec.rest_on_steep_face);
        double xe = rec.stop.x, err[3];
        if (model)
            ENSURE_REL(xe, closed, 1e-9);
        for (int i = 0; i < 3; i++) {
            incline_run(md, 10.0, mu, 10.0, dts[i], &rec);
            ENSURE(rec.reason == RF_END_REST && !rec.rest_on_steep_face);
            err[i] = fabs(rec.stop.x - xe);
            printf("    %s, decelerating: dt %g s: stops at x %.4f m, exact %.4f (error %.2g)\n",
                   model ? "point" : "sphere", dts[i], rec.stop.x, xe, err[i]);
        }
        ENSURE_MSG(err[1] < 0.2 * err[0] && err[2] < 0.2 * err[1], "errors %.3g %.3g %.3g",
                   err[0], err[1], err[2]);
    }
}

/* ---- rest on a face steeper than friction holds ------------------------------------ */

/* A rough slope of theta on a 1 m grid: heights (60 - i) tan(theta) plus 0, 0.37, ...
 * 1.48 m in a pattern of period 5, whose pits centre contact holds rocks in. */
static double rough_z(int i, int j, void *ctx)
{
    return (60 - i) * *(const double *)ctx + 0.37 * ((i * 7 + j * 3) % 5);
}

/* A sphere of 11 t released 3 m above the rough slope at (x, y); engine 0 exact
 * (centre contact), else fixed step dt. */
static rf_trajectory_record rough_run(double theta_deg, double x, double y, double dt,
                                      unsigned long seed)
{
    double tn = tan(theta_deg * M_PI / 180.0);
    rf_terrain t;
    mt_grid_terrain(&t, 0, 61, 41, 1.0, rough_z, &tn,
                    (rf_surface){{0.15, 0.0}, {0.3, 0.0}, {0.3, 0.0}});
    rf_body b = rf_body_make(11000.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_state(rf_v3(x, y, (60 - x) * tn + 3.0 + b.radius), rf_v3(0, 0, 0));
    rf_simulation sim = mt_sim(RF_MODEL_SPHERE, RF_CONTACT_CENTRE, 60.0);
    if (dt > 0) {
        sim.engine = RF_ENGINE_FIXED_STEP;
        sim.dt = dt;
    }
    static mt_scene_run run;
    mt_run_scene(&t, &sim, &b, NULL, 0, &s, seed, &run);
    rf_terrain_free(&t);
    return run.rec;
}

/* At dt 0.1 s and 0.01 s the fixed step brings a sphere rolling along a column edge of
 * a 65 degree face (mu_r 0.3) exactly onto the column's vertex, where the two walls of
 * centre contact stop it in their corner (gravity pressing it in): it rests after
 * 0.75 s, where the exact engine leaves the wall before the vertex and goes on to leave
 * the terrain with 8 000 kJ.  Such a rest is marked rest_on_steep_face, for the check
 * to count; a rest on a face that holds the rock, and every rest of the exact engine
 * (whose walls and corners of centre contact are its model's), are not. */
TEST(motion_fixed_step_rest_on_a_steep_face_is_marked)
{
    const double x = 5.3 + 15 * 0.77, y = 20.0;
    rf_trajectory_record e = rough_run(65.0, x, y, 0.0, 18), f = rough_run(65.0, x, y, 0.1, 18);
    ENSURE_MSG(e.reason == RF_END_EXITED && !e.rest_on_steep_face, "exact: reason %d", e.reason);
    ENSURE_MSG(f.reason == RF_END_REST && f.rest_on_steep_face, "fixed: reason %d, marked %d",
               f.reason, f.rest_on_steep_face);
    f = rough_run(65.0, x, y, 0.001, 18);
    ENSURE_MSG(f.reason == RF_END_EXITED && !f.rest_on_steep_face, "dt 0.001: reason %d",
               f.reason);
    /* the exact engine held in a pit of the 45 degree face (its walls): not marked */
    e = rough_run(45.0, 5.3, 20.0, 0.0, 3);
    ENSURE_MSG(e.reason == RF_END_REST && !e.rest_on_steep_face, "exact at 45: reason %d, marked %d",
               e.reason, e.rest_on_steep_face);
}
