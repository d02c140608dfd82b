/* test_measures_engine.c - protection measures through the real engines: crossings
 * recorded in every phase, the recorded values against closed forms, stop / overtop /
 * break-through, measures in series, and the database rows of a Monte Carlo run. */
#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <string.h>

#include "motion_test_util.h"
#include "scene_test_util.h"
#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "results/store.h"
#include "db_test_util.h"
#include "test.h"

#define G RF_GRAVITY

/* ---- Eq. 1-2 at a control line ------------------------------------------------- */

/* A point mass slides from rest down a plane (theta, mu) across a control line: the
 * recorded speed is sqrt(1 - mu / tan(theta)) sqrt(2 g H), H the drop of the centre
 * from the release to the crossing; the energies are 1/2 m V^2, nothing rotational,
 * and the centre passes on the ground. */
TEST(measures_engine_slide_control_eq12)
{
    const double theta = 37.85 * M_PI / 180.0, mu = 0.2385, len = 210.0, xc = 123.85;
    const double pts[4] = {0.0, len * tan(theta), len, 0.0};
    rf_terrain t;
    mt_profile(&t, pts, 2, 100.0, surface(0.0, mu, mu));
    double line[] = {xc, -10.0, xc, 110.0};
    rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, line, 2, 0.0, 0.0);
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_POINT);
    rf_state s0 = mt_state(rf_v3(6.35, 47.25, (len - 6.35) * tan(theta)), rf_v3(0, 0, 0));
    const double alpha = sqrt(1.0 - mu / tan(theta));
    for (int engine = 0; engine < 2; engine++) {
        mt_scene_run run;
        run_engine(&t, RF_MODEL_POINT, engine, &b, &m, 1, &s0, 1, &run);
        const rf_interception_record *r = &run.icpt[0];
        ENSURE(r->measure == 0 && r->outcome == RF_OUT_PASSED);
        ENSURE_SMALL(r->p.x - xc, 1e-9);
        double H = s0.p.z - r->p.z;
        ENSURE_REL(H, (xc - s0.p.x) * tan(theta), engine ? 1e-3 : 1e-9);
        double V = alpha * sqrt(2.0 * G * H);
        double tol = engine ? 2e-3 : 1e-6;
        fprintf(stderr, "slide engine %d: speed rel err %.3g, passing height %.3g m\n", engine,
                fabs(r->speed_ms - V) / V, r->passing_height_m);
        ENSURE_REL(r->speed_ms, V, tol);
        ENSURE_REL(r->energy_kj, 0.5 * b.mass * V * V / 1000.0, 2.0 * tol);
        ENSURE_REL(r->energy_trans_kj, r->energy_kj, 1e-12);
        ENSURE(r->energy_rot_kj == 0.0);
        ENSURE_SMALL(r->passing_height_m, 1e-6);
        /* the time of the crossing: uniform acceleration g (sin - mu cos) along the slope */
        double a = G * (sin(theta) - mu * cos(theta));
        double dist = (xc - s0.p.x) / cos(theta);
        ENSURE_REL(r->t_s, sqrt(2.0 * dist / a), engine ? 1e-2 : 1e-6);
        /* the rock goes on to the foot of the plane */
        ENSURE(run.rec.reason == RF_END_EXITED);
    }
    rf_terrain_free(&t);
}

/* ---- passing height of a flight --------------------------------------------------- */

/* A spinning sphere flies over an inclined plane across an oblique evaluation line
 * (a barrier in `collect`): the crossing is where the straight horizontal path meets
 * the line, the passing height is the parabola's height above the plane there, the
 * rotational energy is 1/2 I w^2 and the flight goes on unchanged. */
TEST(measures_engine_flight_passing_height)
{
    const double phi = 12.385 * M_PI / 180.0, z0 = 150.0;
    const double pts[4] = {0.0, z0, 400.0, z0 - 400.0 * tan(phi)};
    rf_terrain t;
    mt_profile(&t, pts, 2, 100.0, surface(0.3, 0.4, 0.1));
    double line[] = {40.0, 20.0, 52.5, 95.0};
    rf_measure m = mt_measure(RF_BARRIER, RF_COLLECT, line, 2, 4.85, 1.385);
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    double x0 = 20.5, y0 = 43.85;
    rf_state s0 = mt_state(rf_v3(x0, y0, z0 - x0 * tan(phi) + b.radius + 31.7),
                           rf_v3(14.385, 3.85, 6.25));
    s0.w = rf_v3(1.1, -2.385, 0.7);
    double sp = 0.0, u = 0.0;
    ENSURE(line_segment(x0, y0, s0.v.x, s0.v.y, &line[0], &line[2], &sp, &u));
    double tc = sp; /* the direction is the horizontal velocity: s is the time */
    double xc = x0 + s0.v.x * tc, yc = y0 + s0.v.y * tc;
    double zc = s0.p.z + s0.v.z * tc - 0.5 * G * tc * tc;
    double hc = zc - (z0 - xc * tan(phi));
    rf_vec3 vc = rf_v3(s0.v.x, s0.v.y, s0.v.z - G * tc);
    double erot = 0.5 * b.inertia * rf_v3_norm2(s0.w) / 1000.0;
    for (int engine = 0; engine < 2; engine++) {
        mt_scene_run run;
        run_engine(&t, RF_MODEL_SPHERE, engine, &b, &m, 1, &s0, 1, &run);
        const rf_interception_record *r = &run.icpt[0];
        /* far above the 4.85 m screen: recorded as an overtopping, the flight unchanged */
        ENSURE(r->outcome == RF_OUT_OVERTOPPED);
        fprintf(stderr, "flight engine %d: passing height error %.3g m (height %.6f m)\n", engine,
                r->passing_height_m - hc, hc);
        if (engine == 0) {
            ENSURE_SMALL(r->passing_height_m - hc, 1e-6);
            ENSURE_REL(r->t_s, tc, 1e-9);
            ENSURE_SMALL(r->p.x - xc, 1e-9);
            ENSURE_SMALL(r->p.y - yc, 1e-9);
            ENSURE_SMALL(r->p.z - zc, 1e-9);
            ENSURE_REL(r->speed_ms, rf_v3_norm(vc), 1e-9);
            ENSURE_REL(r->energy_rot_kj, erot, 1e-9);
        } else {
            /* semi-implicit Euler: O(dt) off the parabola */
            ENSURE_SMALL(r->passing_height_m - hc, 0.05);
            ENSURE_REL(r->speed_ms, rf_v3_norm(vc), 1e-3);
            /* the crossing point is still on the line */
            ENSURE(line_segment(x0, y0, s0.v.x, s0.v.y, &line[0], &line[2], &sp, &u));
            ENSURE_SMALL((r->p.x - line[0]) * (line[3] - line[1]) -
                             (r->p.y - line[1]) * (line[2] - line[0]),
                         1e-9);
        }
        ENSURE(run.rec.n_impacts > 0); /* it flew on and landed beyond the line */
    }
    rf_terrain_free(&t);
}

/* ---- fast crossings of a kinked polyline -------------------------------------------- */

/* The crossings of polyline line (n points) that a rock of radius r on the straight
 * horizontal path p + s d (s > 0) records, in order, as path parameters in want_s: the
 * path's points on the segments (one at a vertex), without those back across a line
 * passed within r of the crossed segment's line (docs/measures.md; on a straight
 * path the distance from a line is largest at the end of a stretch). */
static int kink_crossings(const double *line, int n, double px, double py, double dx, double dy,
                          double r, double *want_s)
{
    double s_all[8];
    int seg[8], nall = 0;
    for (int sgi = 0; sgi + 1 < n && nall < 8; sgi++) {
        double s, u;
        if (!line_segment(px, py, dx, dy, &line[2 * sgi], &line[2 * sgi + 2], &s, &u) || !(s > 0))
            continue;
        int dup = 0;
        for (int j = 0; j < nall; j++)
            dup |= fabs(s_all[j] - s) < 1e-9;
        if (!dup)
            s_all[nall] = s, seg[nall++] = sgi;
    }
    for (int i = 0; i < nall; i++)
        for (int j = i + 1; j < nall; j++)
            if (s_all[j] < s_all[i]) {
                double ts = s_all[i];
                int tg = seg[i];
                s_all[i] = s_all[j], seg[i] = seg[j];
                s_all[j] = ts, seg[j] = tg;
            }
    int nwant = 0, last = -1;
    for (int i = 0; i < nall; i++) {
        if (last >= 0) {
            const double *A = &line[2 * seg[last]], *B = A + 2;
            double x = px + s_all[i] * dx - A[0], y = py + s_all[i] * dy - A[1];
            double ex = B[0] - A[0], ey = B[1] - A[1];
            if (fabs(ex * y - ey * x) / hypot(ex, ey) <= r)
                continue;
        }
        want_s[nwant++] = s_all[i];
        last = i;
    }
    return nwant;
}

/* The ground of the line scenes: flat at LINE_Z, rough for flights (fly) and of low
 * friction for sliding (slide). */
#define LINE_Z 7.385
static void line_grounds(rf_terrain *fly, rf_terrain *slide)
{
    const double pts[4] = {0.0, LINE_Z, 100.0, LINE_Z};
    mt_profile(fly, pts, 2, 100.0, surface(0.2, 0.3, 0.05));
    mt_profile(slide, pts, 2, 100.0, surface(0.0, 0.1385, 0.0));
}

/* A rock of 385 kg sent at 60 m/s along (dx, dy) from (px, py) over the line grounds
 * with measure m, in mode bits: 1, a sphere 23.85 m up in flight (else a point mass
 * sliding); 2, fixed steps of 0.01 s (else the exact engine).  Returns the body. */
static rf_body run_line_mode(const rf_terrain *fly, const rf_terrain *slide, int mode,
                             const rf_measure *m, double px, double py, double dx, double dy,
                             mt_scene_run *run)
{
    int flight = mode & 1, fixed = mode >> 1;
    rf_rock_model model = flight ? RF_MODEL_SPHERE : RF_MODEL_POINT;
    rf_simulation sim = engine_sim(model, fixed ? RF_ENGINE_FIXED_STEP : RF_ENGINE_EXACT, 0.01);
    rf_body b = rf_body_make(385.0, 2650.0, model);
    rf_state s0 = mt_state(rf_v3(px, py, flight ? LINE_Z + 23.85 : LINE_Z),
                           rf_v3(60.0 * dx, 60.0 * dy, 0));
    run_scene(flight ? fly : slide, &sim, &b, m, 1, &s0, run);
    return b;
}

static const char *const line_modes[4] = {"sliding, exact", "flight, exact",
                                          "sliding, fixed step", "flight, fixed step"};

/* A polyline along y = 50 with a kink at x = 50, crossed at 60 m/s in flight and
 * sliding, under the exact engine and fixed steps of 0.6 m, each crossing at the point
 * where the straight horizontal path meets the segments.  A notch 0.1 m wide and high:
 * a path through its apex vertex, through the vertex at its foot, or through a leg is
 * recorded once; a diagonal path through both legs and the straight part passes the
 * line once (0.33 m rocks), recorded at the first leg.  The kink 20 times larger: the
 * diagonal path is recorded three times, as are the vertices and legs once. */
TEST(measures_engine_kink_at_60ms)
{
    rf_terrain t, slide_t;
    line_grounds(&t, &slide_t);
    double kinks[2][10] = {{20.0, 50.0, 50.0, 50.0, 50.05, 50.1, 50.1, 50.0, 80.0, 50.0},
                                 {20.0, 50.0, 50.0, 50.0, 51.0, 52.0, 52.0, 50.0, 80.0, 50.0}};
    struct {
        double x, y, dx, dy; /* through the notch (scaled for the larger kink); from 5 m back */
        int want[2];         /* crossings at the notch and at the kink 20 times larger */
    } paths[] = {
        {50.05, 50.1, 0.0, -1.0, {1, 1}},     /* through the apex vertex */
        {50.0, 50.0, 0.0, -1.0, {1, 1}},      /* through the vertex at the kink's foot */
        {50.02, 50.04, 0.0, -1.0, {1, 1}},    /* through the first leg */
        {49.9, 50.12, 0.3, -0.14, {1, 3}},    /* both legs, then the straight part */
        {50.075, 50.05, 0.0, 1.0, {1, 1}},    /* upwards through the second leg */
    };
    for (int big = 0; big < 2; big++) {
        const double sc = big ? 20.0 : 1.0;
        double *line = kinks[big];
        rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, line, 5, 0.0, 0.0);
        for (size_t k = 0; k < sizeof paths / sizeof *paths; k++) {
            double d = hypot(paths[k].dx, paths[k].dy), dx = paths[k].dx / d, dy = paths[k].dy / d;
            double px = 50.0 + (paths[k].x - 50.0) * sc - 5.0 * dx;
            double py = 50.0 + (paths[k].y - 50.0) * sc - 5.0 * dy;
            for (int mode = 0; mode < 4; mode++) {
                mt_scene_run run;
                rf_body b = run_line_mode(&t, &slide_t, mode, &m, px, py, dx, dy, &run);
                double want_s[8];
                int nwant = kink_crossings(line, 5, px, py, dx, dy, b.radius, want_s);
                ENSURE_MSG(nwant == paths[k].want[big], "path %zu, kink %g: %d expected crossings",
                           k, sc, nwant);
                ENSURE_MSG(run.n == nwant, "path %zu, kink %g, %s: %d crossings recorded, %d expected",
                           k, sc, line_modes[mode], run.n, nwant);
                for (int i = 0; i < run.n; i++) {
                    const rf_interception_record *r = &run.icpt[i];
                    check_record(r, &b);
                    ENSURE(r->outcome == RF_OUT_PASSED);
                    ENSURE(i == 0 || r->t_s > run.icpt[i - 1].t_s);
                    ENSURE_MSG(fabs(r->p.x - (px + want_s[i] * dx)) < 1e-9 &&
                                   fabs(r->p.y - (py + want_s[i] * dy)) < 1e-9,
                               "path %zu kink %g mode %d crossing %d at (%.12g, %.12g), expected (%.12g, %.12g)",
                               k, sc, mode, i, r->p.x, r->p.y, px + want_s[i] * dx, py + want_s[i] * dy);
                    ENSURE(r->speed_ms > 59.0 && r->speed_ms < 61.0);
                }
            }
        }
    }
    rf_terrain_free(&t);
    rf_terrain_free(&slide_t);
}

/* A path exactly along a segment of the line (x = 50, as on a profile terrain), in
 * flight and sliding, under both engines, down from y = 60 or up from y = 30: the
 * stretch is one crossing, at its far end, when the line goes on to the other side there
 * than it came from (a step), and none when it returns to the same side (a bay); a line
 * that ends on the stretch is crossed once, where the path meets its other part.  Each
 * stretch was two crossings, one at either end. */
TEST(measures_engine_path_along_a_segment)
{
    rf_terrain t, slide_t;
    line_grounds(&t, &slide_t);
    struct {
        double xy[10];
        int n;
        double dir;   /* -1: down from y = 60, +1: up from y = 30 */
        int want;     /* crossings */
        double y;     /* where the one crossing is */
    } cases[] = {
        {{20.0, 50.0, 50.0, 50.0, 50.0, 40.0, 80.0, 40.0}, 4, -1.0, 1, 40.0},   /* step */
        {{20.0, 50.0, 50.0, 50.0, 50.0, 40.0, 80.0, 40.0}, 4, 1.0, 1, 50.0},
        {{20.0, 50.0, 50.0, 50.0, 50.0, 45.0, 50.0, 40.0, 80.0, 40.0}, 5, -1.0, 1, 40.0},
        {{20.0, 50.0, 50.0, 50.0, 50.0, 40.0, 20.0, 40.0}, 4, -1.0, 0, 0.0},    /* bay */
        {{20.0, 50.0, 50.0, 50.0, 50.0, 40.0, 20.0, 40.0}, 4, 1.0, 0, 0.0},
        {{50.0, 50.0, 50.0, 40.0, 80.0, 40.0}, 3, -1.0, 1, 40.0},                /* ends on it */
        {{50.0, 50.0, 50.0, 40.0, 80.0, 40.0}, 3, 1.0, 1, 40.0},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        rf_measure m = mt_measure(RF_CONTROL, RF_COLLECT, cases[k].xy, (size_t)cases[k].n, 0.0, 0.0);
        double y0 = cases[k].dir < 0 ? 60.0 : 30.0;
        for (int mode = 0; mode < 4; mode++) {
            mt_scene_run run;
            rf_body b = run_line_mode(&t, &slide_t, mode, &m, 50.0, y0, 0.0, cases[k].dir, &run);
            ENSURE_MSG(run.n == cases[k].want, "case %zu, %s: %d crossings recorded, %d expected",
                       k, line_modes[mode], run.n, cases[k].want);
            if (run.n == 1) {
                check_record(&run.icpt[0], &b);
                ENSURE_MSG(run.icpt[0].p.x == 50.0 && fabs(run.icpt[0].p.y - cases[k].y) < 1e-9,
                           "case %zu mode %d: at (%.12g, %.12g)", k, mode, run.icpt[0].p.x,
                           run.icpt[0].p.y);
            }
        }
    }
    rf_terrain_free(&t);
    rf_terrain_free(&slide_t);
}

/* ---- stop, overtop, break through ---------------------------------------------------- */

/* The flat frictionless plane of the outcome scenes: a point mass slides on it at
 * constant speed, so its kinetic energy is E everywhere it is not acted upon. */
#define FLAT_Z 3.85
static const double flat_pts[4] = {0.0, FLAT_Z, 300.0, FLAT_Z};

static rf_state slide_start(void)
{
    return mt_state(rf_v3(10.0, 20.0, FLAT_Z), rf_v3(17.85, 2.5, 0.0));
}

static double slide_energy_kj(const rf_body *b)
{
    rf_state s = slide_start();
    return 0.5 * b->mass * rf_v3_norm2(s.v) / 1000.0;
}

/* The flat plane (friction mu, no restitution) and a rock of 2385 kg on it. */
static rf_body flat_scene(rf_terrain *t, double mu, rf_rock_model model)
{
    mt_profile(t, flat_pts, 2, 100.0, surface(0.0, mu, 0.0));
    return rf_body_make(2385.0, 2650.0, model);
}

static double barrier_line[] = {100.0, -5.0, 103.85, 105.0};
static double control_line[] = {200.0, -5.0, 196.15, 105.0};

/* Below its height and within its MEL: the rock stops on the barrier line, its
 * trajectory ends there (stopped) and the control downstream never sees it. */
TEST(measures_engine_barrier_stops)
{
    rf_terrain t;
    rf_body b = flat_scene(&t, 0.0, RF_MODEL_POINT);
    double E = slide_energy_kj(&b);
    rf_measure ms[2] = {mt_measure(RF_BARRIER, RF_STOP, barrier_line, 2, 2.385, E + 12.385),
                        mt_measure(RF_CONTROL, RF_COLLECT, control_line, 2, 0, 0)};
    rf_state s0 = slide_start();
    for (int engine = 0; engine < 2; engine++) {
        mt_scene_run run;
        run_engine(&t, RF_MODEL_POINT, engine, &b, ms, 2, &s0, 1, &run);
        const rf_interception_record *r = &run.icpt[0];
        ENSURE(r->measure == 0 && r->outcome == RF_OUT_STOPPED);
        ENSURE_REL(r->energy_kj, E, 1e-12);
        ENSURE_SMALL(r->passing_height_m, 1e-9);
        ENSURE(run.rec.reason == RF_END_STOPPED);
        /* the trajectory ends at the crossing, on the barrier's line */
        ENSURE_SMALL(run.rec.stop.x - r->p.x, 1e-12);
        ENSURE_SMALL(run.rec.stop.y - r->p.y, 1e-12);
        ENSURE_REL(run.rec.duration_s, r->t_s, 1e-12);
        ENSURE_SMALL((r->p.x - barrier_line[0]) * (barrier_line[3] - barrier_line[1]) -
                         (r->p.y - barrier_line[1]) * (barrier_line[2] - barrier_line[0]),
                     1e-9);
        ENSURE(run.last.speed_ms == 0.0 && run.last.energy_kj == 0.0);
        double sp = 0.0, u = 0.0;
        ENSURE(line_segment(s0.p.x, s0.p.y, s0.v.x, s0.v.y, &barrier_line[0], &barrier_line[2],
                            &sp, &u));
        ENSURE_REL(r->t_s, sp, 1e-9);
    }
    rf_terrain_free(&t);
}

/* Above its capacity: the rock breaks through and goes on with E - MEL, which the
 * control downstream records exactly (the plane takes nothing).  A `collect` barrier
 * of the same MEL leaves E unchanged. */
TEST(measures_engine_barrier_break_through_residual)
{
    rf_terrain t;
    rf_body b = flat_scene(&t, 0.0, RF_MODEL_POINT);
    double E = slide_energy_kj(&b), mel = 123.85;
    rf_state s0 = slide_start();
    for (int collect = 0; collect < 2; collect++) {
        rf_measure ms[2] = {
            mt_measure(RF_BARRIER, collect ? RF_COLLECT : RF_STOP, barrier_line, 2, 2.385, mel),
            mt_measure(RF_CONTROL, RF_COLLECT, control_line, 2, 0, 0)};
        for (int engine = 0; engine < 2; engine++) {
            mt_scene_run run;
            run_engine(&t, RF_MODEL_POINT, engine, &b, ms, 2, &s0, 2, &run);
            ENSURE(run.icpt[0].measure == 0 && run.icpt[1].measure == 1);
            ENSURE(run.icpt[0].outcome == (collect ? RF_OUT_PASSED : RF_OUT_BROKE_THROUGH));
            ENSURE(run.icpt[1].outcome == RF_OUT_PASSED);
            ENSURE_REL(run.icpt[0].energy_kj, E, 1e-12);
            double want = collect ? E : E - mel;
            fprintf(stderr, "break-through collect %d engine %d: downstream %.12g kJ, want %.12g\n",
                    collect, engine, run.icpt[1].energy_kj, want);
            ENSURE_REL(run.icpt[1].energy_kj, want, 1e-12);
            ENSURE_REL(run.icpt[1].speed_ms, sqrt(2000.0 * want / b.mass), 1e-12);
            /* it goes on in the same direction */
            ENSURE(run.icpt[1].t_s > run.icpt[0].t_s);
            double dx = run.icpt[1].p.x - run.icpt[0].p.x, dy = run.icpt[1].p.y - run.icpt[0].p.y;
            ENSURE_SMALL(dx * s0.v.y - dy * s0.v.x, 1e-9 * hypot(dx, dy) * 18.0);
            ENSURE(run.rec.reason == RF_END_EXITED);
        }
    }
    rf_terrain_free(&t);
}

/* A rolling sphere breaks through with E - MEL, its translational and rotational
 * energy scaled alike (it stays rolling): the control downstream sees 5/7 and 2/7 of
 * E - MEL. */
TEST(measures_engine_rolling_break_through_residual)
{
    rf_terrain t;
    rf_body b = flat_scene(&t, 0.6, RF_MODEL_SPHERE);
    rf_state s0 = slide_start();
    s0.p.z += b.radius;
    s0.w = rf_v3_scale(rf_v3_cross(rf_v3(0, 0, 1), s0.v), 1.0 / b.radius);
    double E = rf_kinetic_energy(&b, s0.v, s0.w) / 1000.0, mel = 238.5;
    ENSURE(E > mel);
    rf_measure ms[2] = {mt_measure(RF_BARRIER, RF_STOP, barrier_line, 2, 2.385, mel),
                        mt_measure(RF_CONTROL, RF_COLLECT, control_line, 2, 0, 0)};
    for (int engine = 0; engine < 2; engine++) {
        mt_scene_run run;
        run_engine(&t, RF_MODEL_SPHERE, engine, &b, ms, 2, &s0, 2, &run);
        const rf_interception_record *r0 = &run.icpt[0], *r1 = &run.icpt[1];
        ENSURE(r0->outcome == RF_OUT_BROKE_THROUGH && r1->outcome == RF_OUT_PASSED);
        ENSURE_REL(r0->energy_kj, E, 1e-9);
        ENSURE_REL(r0->energy_rot_kj, 2.0 / 7.0 * E, 1e-9);
        ENSURE_SMALL(r0->passing_height_m - b.radius, 1e-9);
        fprintf(stderr, "rolling break-through engine %d: downstream %.12g kJ, want %.12g\n", engine,
                r1->energy_kj, E - mel);
        ENSURE_REL(r1->energy_kj, E - mel, 1e-9);
        ENSURE_REL(r1->energy_trans_kj, 5.0 / 7.0 * (E - mel), 1e-9);
        ENSURE_REL(r1->energy_rot_kj, 2.0 / 7.0 * (E - mel), 1e-9);
    }
    rf_terrain_free(&t);
}

/* A flight over a barrier: above its height the rock overtops with its energy
 * unchanged (1/2 m |v(t)|^2 of the parabola) and goes on exactly as without the
 * barrier; a barrier taller than the passing height stops the same flight. */
TEST(measures_engine_barrier_overtopped)
{
    rf_terrain t;
    rf_body b = flat_scene(&t, 0.0, RF_MODEL_POINT);
    rf_state s0 = mt_state(rf_v3(90.0, 20.0, FLAT_Z + 12.385), rf_v3(17.85, 2.5, 0.0));
    double sp = 0.0, u = 0.0;
    ENSURE(line_segment(s0.p.x, s0.p.y, s0.v.x, s0.v.y, &barrier_line[0], &barrier_line[2], &sp,
                        &u));
    double tc = sp, hc = 12.385 - 0.5 * G * tc * tc;
    double Ec = 0.5 * b.mass * (rf_v3_norm2(s0.v) + G * tc * G * tc) / 1000.0;
    double Eh = 0.5 * b.mass * rf_v3_norm2(s0.v) / 1000.0; /* after landing with e = 0 */
    ENSURE(hc > 2.385 && hc < 11.5);
    for (int engine = 0; engine < 2; engine++) {
        rf_simulation sim = engine_k(RF_MODEL_POINT, engine);
        rf_measure ms[2] = {mt_measure(RF_BARRIER, RF_STOP, barrier_line, 2, 2.385, 12.385),
                            mt_measure(RF_CONTROL, RF_COLLECT, control_line, 2, 0, 0)};
        mt_scene_run run, bare;
        run_scene(&t, &sim, &b, ms, 2, &s0, &run);
        run_scene(&t, &sim, &b, &ms[1], 1, &s0, &bare);
        ENSURE_MSG(run.n == 2 && bare.n == 1, "engine %d: %d, %d interceptions", engine, run.n,
                   bare.n);
        const rf_interception_record *r0 = &run.icpt[0], *r1 = &run.icpt[1];
        check_record(r0, &b);
        check_record(r1, &b);
        ENSURE(r0->outcome == RF_OUT_OVERTOPPED && r1->outcome == RF_OUT_PASSED);
        ENSURE(r0->energy_kj > 12.385 && r0->passing_height_m > 2.385);
        double tol = engine ? 1e-2 : 1e-9;
        ENSURE_SMALL(r0->passing_height_m - hc, engine ? 0.05 : 1e-6);
        ENSURE_REL(r0->energy_kj, Ec, tol);
        ENSURE_REL(r1->energy_kj, Eh, 1e-9);
        /* the same downstream as without the barrier */
        ENSURE_REL(r1->energy_kj, bare.icpt[0].energy_kj, 1e-12);
        ENSURE_REL(r1->t_s, bare.icpt[0].t_s, 1e-9);
        ENSURE_SMALL(r1->p.x - bare.icpt[0].p.x, 1e-9);
        ENSURE_SMALL(r1->p.y - bare.icpt[0].p.y, 1e-9);
        ENSURE(run.rec.reason == RF_END_EXITED && bare.rec.reason == RF_END_EXITED);

        /* a taller barrier of a larger MEL stops the flight at the crossing */
        ms[0] = mt_measure(RF_BARRIER, RF_STOP, barrier_line, 2, 11.5, Ec + 23.85);
        run_scene(&t, &sim, &b, ms, 2, &s0, &run);
        ENSURE_MSG(run.n == 1, "engine %d: %d interceptions", engine, run.n);
        ENSURE(run.icpt[0].outcome == RF_OUT_STOPPED);
        ENSURE_REL(run.icpt[0].energy_kj, Ec, tol);
        ENSURE(run.rec.reason == RF_END_STOPPED);
        ENSURE_SMALL(run.rec.stop.x - run.icpt[0].p.x, 1e-12);
        ENSURE_SMALL(run.rec.stop.z - run.icpt[0].p.z, 1e-12);
        ENSURE(run.rec.n_impacts == 0);
    }
    rf_terrain_free(&t);
}

/* Measures in series: a barrier then an embankment then a control line.  A rock that
 * breaks through the barrier meets the embankment with E - MEL; if the embankment
 * stops it the control never sees it, if it breaks through as well the control sees
 * E - MEL - C_ultimate. */
TEST(measures_engine_in_series)
{
    rf_terrain t;
    rf_body b = flat_scene(&t, 0.0, RF_MODEL_POINT);
    double E = slide_energy_kj(&b), mel = 123.85;
    double emb_line[] = {150.0, -5.0, 151.0, 40.0, 149.5, 105.0};
    rf_state s0 = slide_start();
    const double caps[2] = {238.5, 300.0}; /* breaks through / stops */
    for (int k = 0; k < 2; k++) {
        rf_measure ms[3] = {mt_measure(RF_BARRIER, RF_STOP, barrier_line, 2, 2.385, mel),
                            mt_measure(RF_EMBANKMENT, RF_STOP, emb_line, 3, 4.85, caps[k]),
                            mt_measure(RF_CONTROL, RF_COLLECT, control_line, 2, 0, 0)};
        for (int engine = 0; engine < 2; engine++) {
            mt_scene_run run;
            run_engine(&t, RF_MODEL_POINT, engine, &b, ms, 3, &s0, k == 0 ? 3 : 2, &run);
            for (int i = 0; i < run.n; i++)
                ENSURE(run.icpt[i].measure == i);
            ENSURE(run.icpt[0].outcome == RF_OUT_BROKE_THROUGH);
            ENSURE_REL(run.icpt[0].energy_kj, E, 1e-12);
            ENSURE_REL(run.icpt[1].energy_kj, E - mel, 1e-12);
            if (k == 0) {
                ENSURE(run.icpt[1].outcome == RF_OUT_BROKE_THROUGH);
                ENSURE(run.icpt[2].outcome == RF_OUT_PASSED);
                ENSURE_REL(run.icpt[2].energy_kj, E - mel - caps[0], 1e-12);
                ENSURE(run.rec.reason == RF_END_EXITED);
            } else {
                ENSURE(run.icpt[1].outcome == RF_OUT_STOPPED);
                ENSURE(run.rec.reason == RF_END_STOPPED);
                ENSURE_SMALL(run.rec.stop.x - run.icpt[1].p.x, 1e-12);
            }
        }
    }
    /* measures drawn on the same line: a rock stopped by the first listed is not seen
     * by the second; one that passes the first is */
    double same[] = {120.0, -5.0, 120.0, 105.0};
    for (int k = 0; k < 2; k++) {
        rf_measure ms[2] = {mt_measure(RF_BARRIER, RF_STOP, same, 2, 2.385, k ? E - 1.0 : E + 1.0),
                            mt_measure(RF_CONTROL, RF_COLLECT, same, 2, 0, 0)};
        rf_simulation sim = engine_sim(RF_MODEL_POINT, RF_ENGINE_EXACT, 0.001);
        mt_scene_run run;
        run_scene(&t, &sim, &b, ms, 2, &s0, &run);
        ENSURE_MSG(run.n == (k ? 2 : 1), "same line, case %d: %d interceptions", k, run.n);
        if (k) {
            ENSURE(run.icpt[1].measure == 1 && run.icpt[1].t_s == run.icpt[0].t_s);
            ENSURE_REL(run.icpt[1].energy_kj, 1.0, 1e-9);
        }
    }
    rf_terrain_free(&t);
}

/* ---- end to end: project file, Monte Carlo run, database ------------------------------ */

static sqlite3 *open_db(const char *path)
{
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(path, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    return h;
}

#define ENSURE_ZERO(h, sql)                                                            \
    do {                                                                               \
        long long n_ = dbt_int((h), (sql));                                          \
        ENSURE_MSG(n_ == 0, "%lld rows: %s", n_, (sql));                              \
    } while (0)

TEST(measures_engine_montecarlo_database)
{
    const char *db = rf_test_path("results.db");
    const char *yaml = rf_test_write("measures.yaml",
          "name: measures-e2e\n"
          "seed: 2385\n"
          "terrain:\n"
          "  profile:\n"
          "    points: [[0, 140], [90, 60], [120, 52.5], [300, 50]]\n"
          "    width: 40\n"
          "  surface: {restitution: {mean: 0.3, sd: 0.05}, friction: {mean: 0.45, sd: 0.05},\n"
          "            rolling: 0.12}\n"
          "rocks:\n"
          "  - {name: small, mass: 150}\n"
          "  - {name: big, mass: 24000, action_level: 3}\n"
          "releases:\n"
          "  - {name: S, point: [4.5, 20.5], rock: small, count: 16, jitter: 2.5}\n"
          "  - {name: L, point: [4.5, 19.5], rock: big, count: 16, jitter: 2.5}\n"
          "measures:\n"
          "  - {name: up, kind: control, line: [[70.5, -5], [70.5, 45]]}\n"
          "  - {name: B1, kind: barrier, line: [[125.5, -5], [126.5, 20], [125.5, 45]],\n"
          "     height: 6.385, mel: 850, importance: most_important}\n"
          "  - name: E1\n"
          "    kind: embankment\n"
          "    line: [[180.5, -5], [180.5, 45]]\n"
          "    height: 4.85\n"
          "    capacity: {serviceability: 1200, restorability: 2400, ultimate: 3850}\n"
          "  - {name: road, kind: control, line: [[230.5, -5], [230.5, 45]], importance: usual}\n"
          "simulation: {model: sphere, stop_speed: 0.1, max_time: 120, paths: 2}\n");

    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
    rf_store *s;
    ENSURE(rf_store_open(db, &s, &err) == 0);
    rf_run_options o = {.threads = 2};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    ENSURE(sum.n_trajectories == 32);
    rf_store_close(s);
    rf_project_free(&p);

    sqlite3 *h = open_db(db);
    /* the measures with their capacities */
    ENSURE(dbt_int(h, "SELECT count(*) FROM measures") == 4);
    ENSURE(dbt_int(h, "SELECT count(*) FROM measures WHERE name = 'B1' AND kind = 'barrier'"
                        " AND behaviour = 'stop' AND importance = 'most_important'"
                        " AND abs(height_m - 6.385) < 1e-12 AND mel_kj = 850"
                        " AND abs(sel_kj - 850.0 / 3) < 1e-9"
                        " AND abs(cap_serviceability_kj - 850.0 / 3) < 1e-9"
                        " AND cap_restorability_kj IS NULL AND cap_ultimate_kj = 850"
                        " AND cap_near_collapse_kj IS NULL") == 1);
    ENSURE(dbt_int(h, "SELECT count(*) FROM measures WHERE name = 'E1' AND kind = 'embankment'"
                        " AND behaviour = 'stop' AND importance = 'important'"
                        " AND height_m = 4.85 AND mel_kj IS NULL AND sel_kj IS NULL"
                        " AND cap_serviceability_kj = 1200 AND cap_restorability_kj = 2400"
                        " AND cap_ultimate_kj = 3850 AND cap_near_collapse_kj IS NULL") == 1);
    ENSURE(dbt_int(h, "SELECT count(*) FROM measures WHERE kind = 'control'"
                        " AND behaviour = 'collect' AND height_m = 0 AND mel_kj IS NULL"
                        " AND sel_kj IS NULL AND cap_serviceability_kj IS NULL"
                        " AND cap_restorability_kj IS NULL AND cap_ultimate_kj IS NULL"
                        " AND cap_near_collapse_kj IS NULL") == 2);

    /* interceptions: every column there, consistent with each other */
    long long n_icpt = dbt_int(h, "SELECT count(*) FROM interceptions");
    ENSURE(n_icpt > 0);
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions WHERE run_id IS NULL"
                   " OR trajectory_id IS NULL OR measure_id IS NULL OR t_s IS NULL"
                   " OR x IS NULL OR y IS NULL OR z IS NULL OR speed_ms IS NULL"
                   " OR energy_kj IS NULL OR energy_trans_kj IS NULL OR energy_rot_kj IS NULL"
                   " OR passing_height_m IS NULL OR outcome IS NULL");
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i"
                   " LEFT JOIN trajectories t ON t.id = i.trajectory_id"
                   " LEFT JOIN measures m ON m.id = i.measure_id"
                   " WHERE t.id IS NULL OR m.id IS NULL OR t.run_id != i.run_id"
                   " OR m.run_id != i.run_id");
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions"
                   " WHERE abs(energy_kj - energy_trans_kj - energy_rot_kj) > 1e-9 * energy_kj"
                   " OR energy_rot_kj < 0 OR speed_ms <= 0 OR t_s <= 0");
    /* no trajectory's largest energy is below one of its crossings' */
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i JOIN trajectories t"
                   " ON t.id = i.trajectory_id WHERE i.energy_kj > t.max_energy_kj");
    /* 1/2 m v^2 from the recorded speed */
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i"
                   " JOIN trajectories t ON t.id = i.trajectory_id"
                   " JOIN releases r ON r.id = t.release_id"
                   " WHERE abs(i.energy_trans_kj - 0.5 * r.mass_kg * i.speed_ms * i.speed_ms"
                   " / 1000.0) > 1e-9 * i.energy_trans_kj");
    /* the centre passes at least a radius above the ground; on the straight lines'
     * x; ordered by time along a trajectory */
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i"
                   " JOIN trajectories t ON t.id = i.trajectory_id"
                   " JOIN releases r ON r.id = t.release_id"
                   " WHERE i.passing_height_m < r.radius_m * (1 - 1e-6)");
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i JOIN measures m ON m.id = i.measure_id"
                   " WHERE m.name IN ('up', 'E1', 'road')"
                   " AND abs(i.x - CASE m.name WHEN 'up' THEN 70.5 WHEN 'E1' THEN 180.5"
                   " ELSE 230.5 END) > 1e-9");
    /* outcomes follow the rules of each measure */
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i JOIN measures m ON m.id = i.measure_id"
                   " WHERE (m.kind = 'control') != (i.outcome = 'passed')");
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions i JOIN measures m ON m.id = i.measure_id"
                   " WHERE m.kind != 'control' AND NOT CASE i.outcome"
                   "  WHEN 'overtopped' THEN i.passing_height_m >= m.height_m"
                   "  WHEN 'stopped' THEN i.passing_height_m < m.height_m"
                   "   AND i.energy_kj <= m.cap_ultimate_kj"
                   "  WHEN 'broke_through' THEN i.passing_height_m < m.height_m"
                   "   AND i.energy_kj > m.cap_ultimate_kj"
                   "  ELSE 0 END");
    long long stopped = dbt_int(h, "SELECT count(*) FROM trajectories"
                                     " WHERE stop_reason = 'stopped'");
    long long broke = dbt_int(h, "SELECT count(*) FROM interceptions"
                                   " WHERE outcome = 'broke_through'");
    fprintf(stderr, "e2e: %lld interceptions, %lld stopped trajectories, %lld break-throughs\n",
            n_icpt, stopped, broke);
    ENSURE(stopped > 0);
    ENSURE(broke > 0);
    /* stopped <=> exactly one 'stopped' interception, where the trajectory ends */
    ENSURE(dbt_int(h, "SELECT count(*) FROM interceptions WHERE outcome = 'stopped'") == stopped);
    ENSURE_ZERO(h, "SELECT count(*) FROM trajectories t WHERE t.stop_reason = 'stopped'"
                   " AND (SELECT count(*) FROM interceptions i WHERE i.trajectory_id = t.id"
                   " AND i.outcome = 'stopped') != 1");
    ENSURE_ZERO(h, "SELECT count(*) FROM trajectories t JOIN interceptions i"
                   " ON i.trajectory_id = t.id AND i.outcome = 'stopped'"
                   " WHERE t.stop_reason != 'stopped' OR abs(t.stop_x - i.x) > 1e-9"
                   " OR abs(t.stop_y - i.y) > 1e-9 OR abs(t.stop_z - i.z) > 1e-9"
                   " OR abs(t.duration_s - i.t_s) > 1e-9");
    /* nothing downstream of a stop */
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions s JOIN interceptions d"
                   " ON d.trajectory_id = s.trajectory_id AND d.id != s.id"
                   " WHERE s.outcome = 'stopped' AND d.t_s >= s.t_s");
    /* no rock reaches the road without passing both B1 and E1 on the way (the lines
     * span the whole slope) */
    ENSURE_ZERO(h, "SELECT count(*) FROM interceptions d JOIN measures m ON m.id = d.measure_id"
                   " WHERE m.name = 'road' AND (SELECT count(*) FROM interceptions u"
                   " JOIN measures mu ON mu.id = u.measure_id WHERE u.trajectory_id ="
                   " d.trajectory_id AND mu.name IN ('B1', 'E1') AND u.t_s < d.t_s) < 2");
    sqlite3_close(h);
}
