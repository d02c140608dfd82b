/* test_scene_events.c - the events of a scene beyond its terrain (scene_events.c):
 * crossings of measure lines offered for every piece of motion the engines take - found
 * once each, at any speed, on a curved path or a fixed step's, on the terrain's own
 * edges, where the rock leaves, and before an impact at the same instant takes energy. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "rockfall/montecarlo.h"
#include "scene_test_util.h"
#include "test.h"

#define G RF_GRAVITY

/* ---- a line where an impact happens ----------------------------------------------- */

/* A control line on the foot of the plane of measures_engine_slide_control_eq12, where
 * it meets flat ground without restitution: the point mass reaches the line and the
 * concave edge at the same moment.  The line records the energy the impact starts from,
 * not what is left after the flat ground took the speed across it: sliding down the
 * fall line from rest (a segment of constant acceleration), the speed of Eq. 1-2; set
 * off across the fall line, along a path that turns towards it (hodograph.c); in either
 * engine.  A barrier there stops the rock before the impact. */
TEST(measures_engine_line_on_a_concave_break_sees_the_rock_before_the_impact)
{
    const double theta = 37.85 * M_PI / 180.0, mu = 0.2385, len = 123.85;
    const double pts[6] = {0.0, len * tan(theta), len, 0.0, len + 100.0, 0.0};
    rf_terrain t;
    mt_profile(&t, pts, 3, 100.0, surface(0.0, mu, mu));
    double line[] = {len, -10.0, len, 110.0};
    rf_measure ms[2] = {mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0),
                        mt_measure(RF_BARRIER, RF_STOP, line, 2, 2.385, 1e6)};
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_POINT);
    /* where the line is met on it, the crossing's time and the edge's can round apart
     * either way by a hair: several starts */
    const double ys[3] = {27.25, 47.25, 62.85};
    for (int k = 0; k < 12; k++) {
        int across = k % 2, engine = k / 2 % 2;
        rf_vec3 v0 = rf_v3(0, across ? 3.85 : 0.0, 0);
        rf_state s0 = mt_state(rf_v3(6.35, ys[k / 4], (len - 6.35) * tan(theta)), v0);
        mt_scene_run run;
        run_engine(&t, RF_MODEL_POINT, engine, &b, &ms[0], 1, &s0, 1, &run);
        const rf_interception_record *r = &run.icpt[0];
        ENSURE_SMALL(r->p.x - len, 1e-9);
        ENSURE_SMALL(r->p.z, 1e-9);
        ENSURE_MSG(run.nimp > 0, "start %d: no impact on the flat ground", k);
        ENSURE_SMALL(r->t_s - run.imp_t[0], 1e-9);
        ENSURE_MSG(fabs(r->energy_kj - run.imp_e0[0]) <= 1e-9 * run.imp_e0[0],
                   "start %d: %.9g kJ at the line, %.9g kJ before the impact", k, r->energy_kj,
                   run.imp_e0[0]);
        if (!across && !engine) {
            double V = sqrt(1.0 - mu / tan(theta)) * sqrt(2.0 * G * s0.p.z);
            ENSURE_REL(r->speed_ms, V, 1e-6);
        }
        run_engine(&t, RF_MODEL_POINT, engine, &b, &ms[1], 1, &s0, 1, &run);
        ENSURE_MSG(run.rec.reason == RF_END_STOPPED && run.icpt[0].outcome == RF_OUT_STOPPED,
                   "start %d: reason %d, outcome %d", k, run.rec.reason, run.icpt[0].outcome);
        ENSURE_SMALL(run.rec.stop.x - len, 1e-9);
        ENSURE_MSG(run.nimp == 0, "start %d: an impact at %g s", k, run.imp_t[0]);
    }
    rf_terrain_free(&t);
}

/* A control line at the foot of a 30-degree rise, across flat frictionless ground: the
 * rock slides to it with its start's energy and meets the rise there; every model and
 * both engines record that energy, not what the impact on the rise (and in centre
 * contact the lift onto its offset plane) leaves.  In centre contact the centre meets
 * the rise's face a hair before the column's edge, which is the line (the crossing was
 * recorded after that impact, within 1e-9 m of it). */
TEST(measures_engine_line_at_the_foot_of_a_rise_sees_the_rock_before_the_impact)
{
    const double len = 62.85, rise = 30.0 * M_PI / 180.0;
    const double pts[6] = {0.0, 0.0, len, 0.0, len + 50.0, 50.0 * tan(rise)};
    rf_terrain t;
    mt_profile(&t, pts, 3, 100.0, surface(0.0, 0.0, 0.0));
    double line[] = {len, -10.0, len, 110.0};
    rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0);
    static const struct {
        rf_rock_model model;
        rf_contact_kind contact;
        rf_engine_kind engine;
    } cases[4] = {{RF_MODEL_POINT, RF_CONTACT_FULL, RF_ENGINE_EXACT},
                  {RF_MODEL_SPHERE, RF_CONTACT_CENTRE, RF_ENGINE_EXACT},
                  {RF_MODEL_SPHERE, RF_CONTACT_FULL, RF_ENGINE_EXACT},
                  {RF_MODEL_SPHERE, RF_CONTACT_CENTRE, RF_ENGINE_FIXED_STEP}};
    for (int k = 0; k < 4 * 3; k++) {
        rf_simulation sim = engine_sim(cases[k % 4].model, cases[k % 4].engine, 0.001);
        sim.contact = cases[k % 4].contact;
        rf_body b = rf_body_make(2385.0, 2650.0, sim.model);
        double r = rf_body_contact_radius(&b);
        rf_state s0 = mt_state(rf_v3(12.35, 23.85 + 17.0 * (k / 4), r), rf_v3(12.85, 0, 0));
        double E0 = 0.5 * b.mass * rf_v3_norm2(s0.v) / 1000.0;
        mt_scene_run run;
        run_scene(&t, &sim, &b, &m, 1, &s0, &run);
        ENSURE_MSG(run.n >= 1, "case %d: no crossing", k);
        const rf_interception_record *ic = &run.icpt[0];
        check_record(ic, &b);
        ENSURE_SMALL(ic->p.x - len, 1e-8);
        ENSURE_MSG(run.nimp > 0 && run.imp_t[0] < ic->t_s + 1e-3, "case %d: no impact on the rise", k);
        /* a full-contact sphere meets the rise before its centre reaches the line */
        if (sim.model == RF_MODEL_SPHERE && sim.contact == RF_CONTACT_FULL)
            ENSURE(ic->energy_kj < E0 * (1.0 - 1e-6));
        else
            ENSURE_MSG(fabs(ic->energy_kj - E0) <= 1e-9 * E0, "case %d: %.9g kJ at the line, %.9g before", k,
                       ic->energy_kj, E0);
    }
    rf_terrain_free(&t);
}

/* ---- lines drawn on the terrain's own edges ------------------------------------------ */

/* A control line drawn along a break line of the terrain (a profile's vertex line, as
 * a line along a DEM grid line): the crossing coincides with the move from one face
 * to the next, and is recorded once, by sliding and rolling rocks and by flights
 * that land exactly on it, under both engines. */
TEST(measures_engine_line_on_terrain_edge)
{
    const double pts[6] = {0.0, 23.85, 100.0, 13.85, 300.0, 11.35};
    rf_terrain t;
    mt_profile(&t, pts, 3, 100.0, surface(0.0, 0.0385, 0.005));
    double line[] = {100.0, -5.0, 100.0, 105.0};
    double diag[] = {-5.0, -5.0, 105.0, 105.0}; /* the diagonal of the first segment's faces */
    rf_measure ms[2] = {mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0, 0),
                        mt_measure(RF_CONTROL, RF_COLLECT, diag, 2, 0, 0)};
    const double slope = 10.0 / 100.0;
    for (int mode = 0; mode < 4 * 6; mode++) {
        rf_rock_model model = mode & 1 ? RF_MODEL_SPHERE : RF_MODEL_POINT;
        int fixed = (mode >> 1) & 1, start = mode >> 2;
        rf_simulation sim = engine_k(model, fixed);
        rf_body b = rf_body_make(2385.0, 2650.0, model);
        double x0 = 12.385 + 1.7 * start, y0 = 30.5 + 2.385 * start, vy = 3.85 - 0.55 * start;
        double r = rf_body_contact_radius(&b);
        double nz = 1.0 / sqrt(1.0 + slope * slope);
        rf_state s0 = mt_state(rf_v3(x0 + r * slope * nz, y0, 23.85 - slope * x0 + r * nz),
                               rf_v3(8.5, vy, -8.5 * slope));
        mt_scene_run run;
        run_scene(&t, &sim, &b, ms, 2, &s0, &run);
        int n_line = 0, n_diag = 0;
        for (int i = 0; i < run.n; i++) {
            check_record(&run.icpt[i], &b);
            n_line += run.icpt[i].measure == 0;
            n_diag += run.icpt[i].measure == 1;
        }
        ENSURE_MSG(n_line == 1 && n_diag == 1, "mode %d: %d crossings of the break line, %d of the diagonal",
                   mode, n_line, n_diag);
    }
    rf_terrain_free(&t);
}

/* ---- fixed steps: each step's path is the one it takes ------------------------------ */

/* A point mass slides from rest down a 30 degree plane (mu 0.2, 3.2 m/s^2) under fixed
 * steps of 0.1 s.  A semi-implicit Euler step ends at p + h v_new, 14 mm beyond the
 * parabola through its end velocities at these speeds.  A control line placed anywhere
 * along the path - scanned in 2 mm steps over more than a step's length, so that some
 * positions fall in those slivers - is crossed exactly once. */
TEST(measures_engine_fixed_step_crosses_every_line_once)
{
    const double theta = 30.0 * M_PI / 180.0, L = 40.0, H = L * tan(theta);
    const double pts[4] = {0.0, H, L, 0.0};
    rf_terrain t;
    mt_profile(&t, pts, 2, 40.0, surface(0.0, 0.2, 0.0));
    rf_simulation sim = engine_sim(RF_MODEL_POINT, RF_ENGINE_FIXED_STEP, 0.1);
    rf_body b = rf_body_make(385.0, 2650.0, RF_MODEL_POINT);
    rf_state s0 = mt_state(rf_v3(2.0, 20.0, H - 2.0 * tan(theta)), rf_v3(0.0, 0.0, 0.0));
    int missed = 0, twice = 0;
    for (int k = 0; k < 400; k++) {
        double x = 10.0 + 0.002 * k;
        double line[4] = {x, 10.0, x, 30.0};
        rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0);
        mt_scene_run run;
        run_scene(&t, &sim, &b, &m, 1, &s0, &run);
        ENSURE(run.rec.reason == RF_END_EXITED);
        missed += run.n == 0;
        twice += run.n > 1;
        for (int i = 0; i < run.n; i++)
            ENSURE_SMALL(run.icpt[i].p.x - x, 1e-9);
    }
    ENSURE_MSG(missed == 0 && twice == 0, "%d of 400 lines missed, %d counted twice", missed, twice);
    rf_terrain_free(&t);
}

/* ---- the exact engine off the fall line: each crossing recorded once -------------- */

/* A rock launched across a 30 degree plane turns towards the fall line (the closed-form
 * surface law, hodograph.c), and a control line at 45 degrees across the slope is placed
 * anywhere along its curved path (400 positions 1.3 mm apart, over more than a step of
 * the path), for both senses of the launch and both slants of the line.  The step's
 * parabola departs from the path by up to about RF_PATH_DEV; a crossing located on it
 * left the state a hair short of the line, the next step found the same crossing again
 * just after its start, and it was recorded twice (in 1 554 of these 3 200 runs, and in
 * 19 of the example slope's 485 road crossings).  Located on the path, each is recorded
 * once, on the line. */
TEST(measures_engine_exact_curved_path_crosses_every_line_once)
{
    const double theta = 30.0 * M_PI / 180.0, L = 60.0, H = L * tan(theta);
    const double pts[4] = {0.0, H, L, 0.0};
    rf_terrain t;
    mt_profile(&t, pts, 2, 80.0, surface(0.0, 0.3, 0.05));
    for (int mode = 0; mode < 8; mode++) {
        rf_rock_model rm = mode & 1 ? RF_MODEL_SPHERE : RF_MODEL_POINT;
        double side = mode & 2 ? -1.0 : 1.0, slant = mode & 4 ? -1.0 : 1.0;
        rf_simulation sim = engine_k(rm, 0);
        rf_body b = rf_body_make(385.0, 2650.0, rm);
        double r = rf_body_contact_radius(&b);
        rf_state s0 = mt_state(rf_v3(2.0 + r * sin(theta), 40.0, H - 2.0 * tan(theta) + r * cos(theta)),
                               rf_v3(0.5 * cos(theta), 7.385 * side, -0.5 * sin(theta)));
        int missed = 0, twice = 0;
        for (int k = 0; k < 400; k++) {
            double x = 12.0 + 0.0013 * k;
            double line[4] = {x - 40.0 * slant, 0.0, x + 40.0 * slant, 80.0};
            rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0);
            mt_scene_run run;
            run_scene(&t, &sim, &b, &m, 1, &s0, &run);
            missed += run.n == 0;
            twice += run.n > 1;
            for (int i = 0; i < run.n; i++) {
                check_record(&run.icpt[i], &b);
                /* on the line x - slant (y - 40) = x0 */
                double off = run.icpt[i].p.x - x - slant * (run.icpt[i].p.y - 40.0);
                ENSURE_MSG(fabs(off) <= 1e-9, "mode %d line %d: crossing %.3g m off the line",
                           mode, k, off);
            }
        }
        ENSURE_MSG(missed == 0 && twice == 0, "mode %d: %d of 400 lines missed, %d counted twice",
                   mode, missed, twice);
    }
    rf_terrain_free(&t);
}

/* ---- one passage of a line ------------------------------------------------------------ */

/* A point mass launched up a 30 degree plane (mu 0.2) across a control line along the
 * contour turns and slides back across it.  When it turns within its radius beyond
 * the line, that is one passage of the line: one crossing, on the way up (at the
 * valley line that the example's road edge follows, a point mass wandered across it
 * by 0.2 mm and was recorded twice).  Turning further beyond, it crosses twice: up and
 * back down.  Both engines. */
TEST(measures_engine_back_within_radius_is_one_passage)
{
    const double theta = 30.0 * M_PI / 180.0, mu = 0.2, L = 60.0, xc = 30.0, x0 = 34.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 40.0, surface(0.0, mu, 0.0));
    double line[] = {xc, -5.0, xc, 45.0};
    rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0);
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_POINT);
    const double decel = G * (sin(theta) + mu * cos(theta)); /* sliding up (Eq. 1-2) */
    const double beyond[6] = {0.1, 0.5, 0.8, 1.25, 2.0, 5.0}; /* turning point, in radii */
    for (int k = 0; k < 6 * 2; k++) {
        int engine = k & 1;
        double e = beyond[k >> 1] * b.radius; /* horizontal, beyond the line */
        double s = (x0 - xc + e) / cos(theta); /* along the plane to the turning point */
        double V = sqrt(2.0 * decel * s);
        rf_state s0 = mt_incline_state(theta, L, x0, 20.0, 0.0,
                                       rf_v3(-V * cos(theta), 0.0, V * sin(theta)));
        int want = beyond[k >> 1] < 1.0 ? 1 : 2;
        mt_scene_run run;
        run_engine(&t, RF_MODEL_POINT, engine, &b, &m, 1, &s0, want, &run);
        for (int i = 0; i < run.n; i++)
            ENSURE_SMALL(run.icpt[i].p.x - xc, 1e-9);
        /* the first on the way up, the second on the way back down */
        ENSURE(run.icpt[0].t_s < (V / decel));
        if (run.n > 1)
            ENSURE(run.icpt[1].t_s > (V / decel));
    }
    rf_terrain_free(&t);
}

/* ---- the largest energy of a trajectory ------------------------------------------------ */

/* A sphere rolls from rest down a 30 degree plane (mu_r 0.1) into a barrier that stops
 * it: the interception carries m g dh (1 - mu_r / tan(theta)), 2/7 of it rotational,
 * and the trajectory's max_energy_kj is that energy (it was the translational energy
 * with the spin of the last event, 15 % short, and the stop took the rest). */
TEST(measures_engine_max_energy_is_the_stopped_rocks)
{
    const double theta = 30.0 * M_PI / 180.0, mu_r = 0.1, L = 100.0, x0 = 10.0, xb = 60.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 40.0, surface(0.0, 0.9, mu_r));
    double line[] = {xb, -5.0, xb, 45.0};
    rf_measure m = mt_measure(RF_BARRIER, RF_STOP, line, 2, 5.0, 1e6);
    rf_body b = rf_body_make(1000.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s0 = mt_incline_state(theta, L, x0, 20.0, b.radius, rf_v3(0, 0, 0));
    double dx = xb - (x0 + b.radius * sin(theta)); /* the centre's horizontal travel */
    double E = b.mass * G * dx * tan(theta) * (1.0 - mu_r / tan(theta)) / 1000.0;
    for (int engine = 0; engine < 2; engine++) {
        mt_scene_run run;
        run_engine(&t, RF_MODEL_SPHERE, engine, &b, &m, 1, &s0, 1, &run);
        const rf_interception_record *r = &run.icpt[0];
        ENSURE(r->outcome == RF_OUT_STOPPED && run.rec.reason == RF_END_STOPPED);
        fprintf(stderr, "engine %d: interception %.9g kJ (rotational %.9g), max %.9g, want %.9g\n",
                engine, r->energy_kj, r->energy_rot_kj, run.rec.max_energy_kj, E);
        ENSURE(run.rec.max_energy_kj >= r->energy_kj);
        ENSURE_REL(run.rec.max_energy_kj, r->energy_kj, engine ? 1e-3 : 1e-12);
        if (engine == 0) {
            ENSURE_REL(r->energy_kj, E, 1e-9);
            ENSURE_REL(r->energy_rot_kj, 2.0 / 7.0 * E, 1e-9);
        }
    }
    rf_terrain_free(&t);
}

/* ---- a line on the terrain's edge ------------------------------------------------------ */

/* A rock leaves the terrain exactly where a line is drawn along its edge: sliding off
 * the end of a flat profile, or flying over it.  The crossing is recorded at the edge
 * (it was left to the next piece of motion, which a rock that has left never takes); a
 * stop barrier there stops the rock.  Both rock models, both engines. */
TEST(measures_engine_line_where_the_rock_leaves)
{
    const double flat[4] = {0.0, 5.0, 60.0, 5.0};
    rf_terrain t;
    mt_profile(&t, flat, 2, 40.0, surface(0.0, 0.1, 0.01));
    double edge[] = {60.0, -5.0, 60.0, 45.0};
    for (int mode = 0; mode < 16; mode++) {
        rf_rock_model model = mode & 1 ? RF_MODEL_SPHERE : RF_MODEL_POINT;
        int engine = (mode >> 1) & 1, stop = (mode >> 2) & 1, fly = mode >> 3;
        rf_measure m = stop ? mt_measure(RF_BARRIER, RF_STOP, edge, 2, 8.0, 1e6)
                            : mt_measure(RF_CONTROL, RF_COLLECT, edge, 2, 0.0, 0.0);
        rf_body b = rf_body_make(1000.0, 2650.0, model);
        double r = rf_body_contact_radius(&b);
        /* sliding or rolling off the end, or in flight over it (4.9 m lower there) */
        rf_state s0 = fly ? mt_state(rf_v3(40.0, 20.0, 15.0 + r), rf_v3(20.0, 0.0, 0.0))
                          : mt_state(rf_v3(40.0, 20.0, 5.0 + r), rf_v3(8.0, 0.0, 0.0));
        mt_scene_run run;
        run_engine(&t, model, engine, &b, &m, 1, &s0, 1, &run);
        ENSURE_SMALL(run.icpt[0].p.x - 60.0, 1e-9);
        ENSURE_MSG(run.icpt[0].outcome == (stop ? RF_OUT_STOPPED : RF_OUT_PASSED), "mode %d: outcome %d, height %g", mode, (int)run.icpt[0].outcome, run.icpt[0].passing_height_m);
        ENSURE(run.rec.reason == (stop ? RF_END_STOPPED : RF_END_EXITED));
    }
    rf_terrain_free(&t);
}

/* ---- a flight at any speed ------------------------------------------------------------ */

/* A point mass launched horizontally at 250 m/s, 200 m above level ground, across eight
 * control lines (seven across its path, one oblique): the flight's crossings are roots
 * of the horizontal path, so each line is recorded once, in order, at t = (x - x0) / vx,
 * with the centre at z0 - g t^2 / 2, the speed hypot(vx, g t), 1/2 m V^2 and nothing
 * rotational, and the height above the ground z; the rock then leaves the terrain. */
TEST(scene_events_fast_flight_crosses_each_line_at_its_exact_time)
{
    const double x0 = 10.0, y0 = 50.0, z0 = 200.0, vx = 250.0, mass = 385.0;
    rf_terrain t;
    mt_incline(&t, 0.0, 300.0, 100.0, surface(0.3, 0.3, 0.05));
    double lines[8][4];
    rf_measure ms[8];
    double xs[8];
    for (int k = 0; k < 7; k++) {
        xs[k] = 20.0 + 40.0 * k + 0.385 * k * k;
        double *q = lines[k];
        q[0] = q[2] = xs[k], q[1] = -5.0, q[3] = 105.0;
        ms[k] = mt_measure(RF_CONTROL, RF_COLLECT, q, 2, 0.0, 0.0);
    }
    /* oblique: from (140, -50) to (180, 150), crossed at y = 50, x = 160 */
    lines[7][0] = 140.0, lines[7][1] = -50.0, lines[7][2] = 180.0, lines[7][3] = 150.0;
    ms[7] = mt_measure(RF_CONTROL, RF_COLLECT, lines[7], 2, 0.0, 0.0);
    xs[7] = 160.0;
    rf_simulation sim = mt_sim(RF_MODEL_POINT, RF_CONTACT_FULL, 300.0);
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_POINT);
    rf_state s0 = mt_state(rf_v3(x0, y0, z0), rf_v3(vx, 0.0, 0.0));
    mt_scene_run *run = malloc(sizeof *run);
    ENSURE(run != NULL);
    run_scene(&t, &sim, &b, ms, 8, &s0, run);
    ENSURE(run->rec.reason == RF_END_EXITED);
    ENSURE(run->rec.n_impacts == 0);
    ENSURE_MSG(run->n == 8, "%d crossings", run->n);
    double last_t = 0.0;
    for (int i = 0; i < run->n; i++) {
        const rf_interception_record *r = &run->icpt[i];
        check_record(r, &b);
        ENSURE(r->measure >= 0 && r->measure < 8);
        double x = xs[r->measure], tc = (x - x0) / vx;
        ENSURE_MSG(r->t_s > last_t, "crossing %d out of order", i);
        last_t = r->t_s;
        ENSURE_REL(r->t_s, tc, 1e-12);
        ENSURE_REL(r->p.x, x, 1e-12);
        ENSURE_SMALL(r->p.y - y0, 1e-9);
        double z = z0 - 0.5 * G * tc * tc, V = hypot(vx, G * tc);
        ENSURE_REL(r->p.z, z, 1e-12);
        ENSURE_REL(r->speed_ms, V, 1e-12);
        ENSURE_REL(r->energy_kj, 0.5 * mass * V * V / 1000.0, 1e-12);
        ENSURE(r->energy_rot_kj == 0.0);
        ENSURE_REL(r->passing_height_m, z, 1e-12);
        ENSURE(r->outcome == RF_OUT_PASSED);
    }
    free(run);
    rf_terrain_free(&t);
}

/* ---- the tree process ends: bounded draws ----------------------------------------- */

/* One trajectory of a sphere through the forest f (engine 0: exact, 1: fixed step at
 * dt 0.01) down a 30 degree incline from speed v0; returns its record. */
static rf_trajectory_record through_forest(const rf_forest *f, int engine, rf_vec3 v0)
{
    rf_terrain t;
    const double theta = 30.0 * M_PI / 180.0;
    mt_incline(&t, theta, 100.0, 40.0, surface(0.3, 0.5, 0.5));
    rf_simulation sim = mt_sim(RF_MODEL_SPHERE, RF_CONTACT_FULL, 60.0);
    sim.paths = 0;
    if (engine) {
        sim.engine = RF_ENGINE_FIXED_STEP;
        sim.dt = 0.01;
    }
    rf_body b = rf_body_make(1500.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_incline_state(theta, 100.0, 10.0, 20.0, b.radius + 0.5, v0);
    rf_scene sc = {&t, &sim, f, 1, NULL, 0};
    rf_workspace *ws = rf_workspace_alloc(&t);
    ENSURE(ws);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 38);
    rf_trajectory_record rec;
    rf_simulate(&sc, &b, &s, rng, ws, NULL, &rec);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_terrain_free(&t);
    return rec;
}

/* A forest on a patch off the rock's way (every candidate is rejected), of this
 * density and stem diameter. */
static rf_forest patch_forest(double density, double diameter, double *xy)
{
    rf_forest f;
    memset(&f, 0, sizeof f);
    f.name = "patch";
    xy[0] = 90.0, xy[1] = 0.0, xy[2] = 99.0, xy[3] = 0.0, xy[4] = 99.0, xy[5] = 1.0;
    f.polygon.xy = xy;
    f.polygon.n = 3;
    f.density = density;
    f.height = (rf_dist){20.0, 0.0};
    f.diameter = diameter;
    f.restitution = (rf_dist){0.2, 0.0};
    f.friction = (rf_dist){0.3, 0.0};
    return f;
}

/* Candidate gaps of 1e-24 m (density 1e12) or 1e-10 m (stem diameter 1e12): the
 * odometer's candidates no longer passed the end of a piece (below its rounding, or
 * after 1e10 draws per metre) and the run never ended.  The draws are bounded: the
 * trajectory is given up, as one that runs out of time. */
TEST(scene_events_absurd_forest_density_or_diameter_ends_the_trajectory)
{
    double xy[6];
    const rf_forest fs[2] = {patch_forest(1e12, 0.3, xy), patch_forest(0.01, 1e12, xy)};
    for (int k = 0; k < 4; k++) {
        rf_trajectory_record rec = through_forest(&fs[k % 2], k / 2, rf_v3(1.0, 0.0, 0.0));
        ENSURE_MSG(rec.reason == RF_END_MAX_TIME, "case %d: reason %d", k, rec.reason);
        ENSURE_MSG(isfinite(rec.duration_s) && rec.duration_s < 60.0, "case %d: %g s", k,
                   rec.duration_s);
    }
}

/* Released at 1e300 m/s through an ordinary forest: the horizontal length of its first
 * piece overflows to infinity and no candidate passed it.  It ends, and the same forest
 * at an ordinary speed is sampled as before (no bound is met). */
TEST(scene_events_release_at_1e300_through_a_forest_ends)
{
    rf_forest f;
    memset(&f, 0, sizeof f);
    f.name = "forest";
    f.density = 0.05;
    f.height = (rf_dist){20.0, 5.0};
    f.diameter = 0.3;
    f.restitution = (rf_dist){0.2, 0.0};
    f.friction = (rf_dist){0.3, 0.0};
    for (int engine = 0; engine < 2; engine++) {
        rf_trajectory_record rec = through_forest(&f, engine, rf_v3(1e300, 0.0, 0.0));
        ENSURE_MSG(rec.reason >= RF_END_REST && rec.reason <= RF_END_MAX_TIME, "reason %d",
                   rec.reason);
        rec = through_forest(&f, engine, rf_v3(1.0, 0.0, 0.0));
        ENSURE_MSG(rec.reason != RF_END_MAX_TIME && rec.n_tree_hits > 0,
                   "engine %d: reason %d, %ld tree hits", engine, rec.reason, rec.n_tree_hits);
    }
}

/* ---- lines crossed by a move in no time ------------------------------------------- */

typedef struct line_count {
    int n;
    double y;
} line_count;

static void count_line(void *ctx, const rf_interception_record *r)
{
    line_count *c = ctx;
    c->n++;
    c->y = r->p.y;
}

/* Three rocks of the Noto 3.2 run roll over an edge of the slope (the centre turns about
 * the edge in no time) from one side of the road's control line (y = 22) to the other:
 * each crossing is recorded, once, within a radius of the line. */
TEST(scene_events_roll_over_an_edge_across_a_line_is_recorded)
{
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load("projects/noto/noto-3.2.yaml", &p, &err) == 0, "%s", err.message);
    ENSURE(p.nmeasures == 1 && p.measures[0].line.n == 2 && p.measures[0].line.xy[1] == 22.0);
    rf_scene scene = {&p.terrain, &p.sim, p.forests, p.nforests, p.measures, p.nmeasures};
    rf_workspace *ws = rf_workspace_alloc(&p.terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    const struct {
        size_t release;
        long idx;
    } rocks[3] = {{0, 54}, {1, 21}, {2, 7}};
    for (int k = 0; k < 3; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, rocks[k].release, rocks[k].idx));
        rf_body b = rf_release_body(&p, rocks[k].release, p.sim.model);
        rf_state s = rf_release_start(&p, rocks[k].release, &b, rng);
        line_count c = {0, NAN};
        rf_sink sink = {.ctx = &c, .interception = count_line};
        rf_trajectory_record rec;
        ENSURE(rf_simulate(&scene, &b, &s, rng, ws, &sink, &rec) == 0);
        ENSURE_MSG(rec.stop.y < 22.0, "rock %d stops at y %.3f", k, rec.stop.y);
        ENSURE_MSG(c.n == 1, "rock %d: %d crossings of the road", k, c.n);
        ENSURE_MSG(fabs(c.y - 22.0) <= b.radius, "rock %d crossed at y %.4f, r %.3f", k, c.y, b.radius);
    }
    gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_project_free(&p);
}

typedef struct lines_seen {
    int n[2];
    double t[2];
} lines_seen;

static void note_line(void *ctx, const rf_interception_record *r)
{
    lines_seen *c = ctx;
    c->n[r->measure]++;
    c->t[r->measure] = r->t_s;
}

/* Two control lines 3 cm apart, both inside the move of rock E 67 of Noto 3.2 over an
 * edge (in no time): each is recorded once, in the order the move crosses them, at the
 * moment of the move. */
TEST(scene_events_roll_over_an_edge_across_two_lines_records_both)
{
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load("projects/noto/noto-3.2.yaml", &p, &err) == 0, "%s", err.message);
    double xy[2][4] = {{0, 22.03, 300, 22.03}, {0, 22.0, 300, 22.0}};
    rf_measure ms[2] = {p.measures[0], p.measures[0]};
    for (int k = 0; k < 2; k++)
        ms[k].line = (rf_polyline){xy[k], 2};
    rf_scene scene = {&p.terrain, &p.sim, p.forests, p.nforests, ms, 2};
    rf_workspace *ws = rf_workspace_alloc(&p.terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    gsl_rng_set(rng, rf_trajectory_seed(p.seed, 2, 67));
    rf_body b = rf_release_body(&p, 2, p.sim.model);
    rf_state s = rf_release_start(&p, 2, &b, rng);
    lines_seen c = {{0, 0}, {NAN, NAN}};
    rf_sink sink = {.ctx = &c, .interception = note_line};
    rf_trajectory_record rec;
    ENSURE(rf_simulate(&scene, &b, &s, rng, ws, &sink, &rec) == 0);
    ENSURE_MSG(c.n[0] == 1 && c.n[1] == 1, "crossings %d and %d", c.n[0], c.n[1]);
    ENSURE_MSG(c.t[0] == c.t[1] && fabs(c.t[0] - 23.194682151) < 1e-6, "at %.9f and %.9f", c.t[0],
               c.t[1]);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_project_free(&p);
}
