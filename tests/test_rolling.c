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

/* ---- the rolling phase on grids ----------------------------------------------------- */

#define G RF_GRAVITY

/* A plane falling by 0.5 per m along x and 0.2 along y as a grid of 1 m cells (node i,
 * j at x = i + 0.5, y = j + 0.5): its fall line crosses the grid's lines and diagonals
 * at an angle. */
static double tilted_plane(int i, int j, void *ctx)
{
    (void)ctx;
    return 100.0 - 0.5 * i - 0.2 * j;
}

/* A rock set on the grid plane from rest moves down its fall line across many grid
 * edges (every face is coplanar with the next: no impact, no edge transition), and after
 * T its centre is where the closed form puts it: Eq. 1-2 for the point mass (a = g (sin
 * theta - mu cos theta)), the 5/7 law for the rolling sphere (a = 5/7 g (sin theta -
 * mu_r cos theta)), to 1e-12 of the path. */
TEST(rolling_down_a_grid_plane_across_its_edges_matches_the_closed_forms)
{
    const double mu = 0.45, mu_r = 0.1, T = 5.0;
    rf_terrain t;
    mt_grid_terrain(&t, 0, 80, 60, 1.0, tilted_plane, NULL,
                    (rf_surface){{0.2, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
    double gx = 0.5, gy = 0.2, gl = hypot(gx, gy);
    double tan_t = gl, cos_t = 1.0 / sqrt(1.0 + tan_t * tan_t), sin_t = tan_t * cos_t;
    rf_vec3 n = rf_v3_scale(rf_v3(gx, gy, 1.0), cos_t); /* the plane's upward unit normal */
    rf_vec3 e1 = rf_v3(cos_t * gx / gl, cos_t * gy / gl, -sin_t); /* down the fall line */
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(2385.0, 2650.0, md);
        double r0 = rf_body_contact_radius(&b);
        rf_vec3 q = rf_v3(10.3, 20.7, 100.0 - 0.5 * (10.3 - 0.5) - 0.2 * (20.7 - 0.5));
        rf_state s = mt_state(rf_v3_madd(q, r0, n), rf_v3(0, 0, 0));
        rf_simulation sim = mt_sim(md, RF_CONTACT_FULL, T);
        mt_run r;
        mt_simulate_opts(&t, &sim, &b, &s, 7, 0.0, &r);
        ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "reason %d", (int)r.rec.reason);
        double a = model ? G * (sin_t - mu * cos_t) : 5.0 / 7.0 * G * (sin_t - mu_r * cos_t);
        double len = 0.5 * a * T * T;
        rf_vec3 want = rf_v3_madd(s.p, len, e1);
        ENSURE_MSG(rf_v3_norm(rf_v3_sub(r.rec.stop, want)) <= 1e-12 * len,
                   "model %d: at (%.15g, %.15g, %.15g), closed form (%.15g, %.15g, %.15g)", model,
                   r.rec.stop.x, r.rec.stop.y, r.rec.stop.z, want.x, want.y, want.z);
        ENSURE_REL(r.last.speed_ms, a * T, 1e-12);
        ENSURE(len > 9.0 && r.rec.n_segments > 10); /* a segment per face crossed */
        ENSURE(r.rec.n_impacts == 0 && r.rec.n_edge_transitions == 0 && r.rec.n_flights == 0);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* A profile along x as a grid of 1 m cells (node i at x = i + 0.5): a slope of tan 0.6
 * down to x = 30.5, then, beyond that concave grid edge, a slope of tan `after` (ctx). */
static double bent_slope(int i, int j, void *ctx)
{
    (void)j;
    double after = *(const double *)ctx;
    return i <= 30 ? 60.0 - 0.6 * i : 60.0 - 0.6 * 30 - after * (i - 30);
}

/* A rock running down the bent slope meets the next face at the concave edge x = 30.
 * Bent by 0.3 degrees it meets it slower than v_stay along its normal: a change of face,
 * counted as an edge transition and not as an impact, and the energy it takes is in the
 * record.  Met fast - a counter-slope beyond the edge - it is an impact (n_impacts
 * counts impacts at an approach above RF_APPROACH_EPS that are not such changes of
 * face).  The same with centre contact, whose centre crosses the column border above
 * the next face's offset plane: slow, a change of face and no flight; fast, a flight
 * onto the counter-slope and an impact there. */
TEST(rolling_concave_grid_edge_slow_is_a_face_change_fast_an_impact)
{
    for (int model = 0; model < 3; model++) {
        /* 0: sphere, 1: point mass, 2: sphere with centre contact (Eq. 6-7) */
        rf_rock_model md = model == 1 ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(2385.0, 2650.0, md);
        double r0 = rf_body_contact_radius(&b);
        rf_vec3 n = rf_v3_scale(rf_v3(0.6, 0.0, 1.0), 1.0 / sqrt(1.36));
        rf_vec3 q = rf_v3(24.0, 10.0, 60.0 - 0.6 * 23.5);
        rf_state s = mt_state(rf_v3_madd(q, r0, n), rf_v3(3.0 / sqrt(1.36), 0, -1.8 / sqrt(1.36)));
        double gentle = tan(atan(0.6) - 0.3 * PI / 180.0), counter = -0.4;
        rf_terrain t;
        mt_grid_terrain(&t, 0, 60, 20, 1.0, bent_slope, &gentle,
                        (rf_surface){{0.2, 0.0}, {0.5, 0.0}, {0.2, 0.0}});
        rf_simulation sim = mt_sim(md, model == 2 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL, 3.0);
        mt_run r;
        mt_simulate_opts(&t, &sim, &b, &s, 3, 0.0, &r);
        ENSURE_MSG(r.rec.stop.x > 32.5, "model %d: stops at x %.3f", model, r.rec.stop.x);
        ENSURE_MSG(r.rec.n_edge_transitions == 1 && r.rec.n_impacts == 0,
                   "model %d: %ld edge transitions, %ld impacts", model,
                   r.rec.n_edge_transitions, r.rec.n_impacts);
        /* the projection takes sin^2(0.3 deg) of the energy, the turn's friction (mu (1 +
         * e) = 0.6 of the normal impulse) at most 2 x 0.6 sin(0.3 deg): under 1 % */
        ENSURE(r.rec.edge_loss_kj > 0.0 && r.rec.edge_loss_kj < 1e-2 * r.rec.max_energy_kj);
        mt_run_free(&r);
        rf_terrain_free(&t);

        mt_grid_terrain(&t, 0, 60, 20, 1.0, bent_slope, &counter,
                        (rf_surface){{0.2, 0.0}, {0.5, 0.0}, {0.2, 0.0}});
        mt_simulate_opts(&t, &sim, &b, &s, 3, 0.0, &r);
        ENSURE_MSG(r.rec.n_impacts >= 1 && r.rec.n_edge_transitions == 0,
                   "model %d, counter-slope: %ld edge transitions, %ld impacts", model,
                   r.rec.n_edge_transitions, r.rec.n_impacts);
        ENSURE(r.rec.edge_loss_kj == 0.0);
        mt_run_free(&r);
        rf_terrain_free(&t);
    }
}

/* A point mass sliding down the fall line of the slope bent by 0.3 degrees: before the
 * edge Eq. 1-2 on the first face, at the edge the velocity projected onto the next face
 * (v cos delta) less Eq. 8's plastic friction of the turn (mu (1 + e) v sin delta), then
 * Eq. 1-2 on the next face: its speed after T matches that closed form to 1e-12, and
 * the energy the change took (a difference of two energies 0.6 % apart) to 1e-11. */
TEST(rolling_point_across_a_concave_grid_edge_matches_the_closed_form)
{
    const double mu = 0.5, e = 0.2, mass = 2385.0, T = 3.0, v0 = 3.0, x0 = 24.0;
    double gentle = tan(atan(0.6) - 0.3 * PI / 180.0);
    rf_terrain t;
    mt_grid_terrain(&t, 0, 60, 20, 1.0, bent_slope, &gentle,
                    (rf_surface){{e, 0.0}, {mu, 0.0}, {0.2, 0.0}});
    double th1 = atan(0.6), th2 = atan(gentle), delta = th1 - th2;
    rf_vec3 dir = rf_v3(cos(th1), 0.0, -sin(th1));
    rf_state s = mt_state(rf_v3(x0, 10.0, 60.0 - 0.6 * (x0 - 0.5)), rf_v3_scale(dir, v0));
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_POINT);
    rf_simulation sim = mt_sim(RF_MODEL_POINT, RF_CONTACT_FULL, T);
    mt_run r;
    mt_simulate_opts(&t, &sim, &b, &s, 5, 0.0, &r);
    ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "reason %d", (int)r.rec.reason);
    ENSURE(r.rec.n_edge_transitions == 1 && r.rec.n_impacts == 0 && r.rec.n_flights == 0);
    double a1 = G * (sin(th1) - mu * cos(th1)), a2 = G * (sin(th2) - mu * cos(th2));
    double L1 = (30.5 - x0) / cos(th1);
    double v1 = sqrt(v0 * v0 + 2.0 * a1 * L1), t1 = (v1 - v0) / a1;
    double v2 = v1 * cos(delta) - mu * (1.0 + e) * v1 * sin(delta);
    ENSURE_REL(r.last.speed_ms, v2 + a2 * (T - t1), 1e-12);
    ENSURE_REL(r.rec.edge_loss_kj, 0.5 * mass * (v1 * v1 - v2 * v2) / 1000.0, 1e-11);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A plane falling by `fall` per m along the grid's x (ctx: 0) or along its diagonal
 * x = y (ctx: 1), as a grid of 1 m cells (node i, j at x = i + 0.5, y = j + 0.5). */
static double grid_line_plane(int i, int j, void *ctx)
{
    return *(const int *)ctx ? 100.0 - 0.3 * (i + j) : 100.0 - 0.5 * i;
}

/* A rock set from rest on a grid line (the fall line along x, the contact point on the
 * line of nodes y = 20.5) or on a diagonal of the cells (the fall line along x = y,
 * through the nodes) runs along the grid's edges, not across them: its contact point
 * lies on an edge shared by two coplanar faces all the way down, and after T its centre
 * and speed are the closed form's (Eq. 1-2, the 5/7 law) to 1e-12, with no impact and
 * no edge transition. */
TEST(rolling_along_grid_lines_and_diagonals_matches_the_closed_forms)
{
    const double mu = 0.3, mu_r = 0.1, T = 6.0;
    for (int diag = 0; diag < 2; diag++) {
        rf_terrain t;
        mt_grid_terrain(&t, 0, 90, 90, 1.0, grid_line_plane, &diag,
                        (rf_surface){{0.2, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
        double gx = diag ? 0.3 : 0.5, gy = diag ? 0.3 : 0.0, gl = hypot(gx, gy);
        double cos_t = 1.0 / sqrt(1.0 + gl * gl), sin_t = gl * cos_t;
        rf_vec3 n = rf_v3_scale(rf_v3(gx, gy, 1.0), cos_t);
        rf_vec3 e1 = rf_v3(cos_t * gx / gl, cos_t * gy / gl, -sin_t);
        for (int model = 0; model < 2; model++) {
            rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
            rf_body b = rf_body_make(2385.0, 2650.0, md);
            double r0 = rf_body_contact_radius(&b);
            double x = 10.5, y = diag ? 10.5 : 20.5; /* a node */
            rf_vec3 q = rf_v3(x, y, diag ? 100.0 - 0.3 * (x - 0.5 + y - 0.5) : 100.0 - 0.5 * (x - 0.5));
            rf_state s = mt_state(rf_v3_madd(q, r0, n), rf_v3(0, 0, 0));
            rf_simulation sim = mt_sim(md, RF_CONTACT_FULL, T);
            mt_run r;
            mt_simulate_opts(&t, &sim, &b, &s, 11, 0.0, &r);
            ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "diag %d model %d: reason %d", diag, model,
                       (int)r.rec.reason);
            double a = model ? G * (sin_t - mu * cos_t) : 5.0 / 7.0 * G * (sin_t - mu_r * cos_t);
            double len = 0.5 * a * T * T;
            rf_vec3 want = rf_v3_madd(s.p, len, e1);
            ENSURE_MSG(rf_v3_norm(rf_v3_sub(r.rec.stop, want)) <= 1e-12 * len,
                       "diag %d model %d: at (%.15g, %.15g, %.15g), closed form (%.15g, %.15g, "
                       "%.15g)", diag, model, r.rec.stop.x, r.rec.stop.y, r.rec.stop.z, want.x,
                       want.y, want.z);
            ENSURE_REL(r.last.speed_ms, a * T, 1e-12);
            ENSURE(len > 15.0); /* over many cells */
            ENSURE_MSG(r.rec.n_impacts == 0 && r.rec.n_edge_transitions == 0 && r.rec.n_flights == 0,
                       "diag %d model %d: %ld impacts, %ld edge transitions, %ld flights", diag,
                       model, r.rec.n_impacts, r.rec.n_edge_transitions, r.rec.n_flights);
            mt_run_free(&r);
        }
        rf_terrain_free(&t);
    }
}

/* A profile along x as a grid of 1 m cells (node i at x = i + 0.5) that bends up by
 * BEND_DEG at each of the nodes i = 20 .. 20 + BENDS - 1: a concave curve sampled on the
 * grid, its slope tan(theta_k), theta_k = BEND_THETA0 - k BEND_DEG between nodes. */
#define BENDS 12
#define BEND_DEG 0.4
#define BEND_THETA0 35.0
static double bend_angle(int i)
{
    int k = i < 20 ? 0 : i - 19 > BENDS ? BENDS : i - 19;
    return (BEND_THETA0 - k * BEND_DEG) * PI / 180.0;
}

/* The closed form of a point (or sliding centre) on the bent curve, face by face from
 * x0 at speed v0 at t = 0: Eq. 1-2 along face i (from node i + 0.5 to i + 1.5), and at
 * each concave edge the turn v cos delta - mu (1 + e) v sin delta.  Its speed at time
 * T; *face the face it ends on. */
static double bent_closed_form(double x0, double v0, double mu, double e, double T, int *face)
{
    double tt = 0.0, v = v0, x = x0;
    int i = 18;
    for (;;) {
        double th = bend_angle(i), a = G * (sin(th) - mu * cos(th));
        double L = (i + 1.5 - x) / cos(th); /* to the next node along the face */
        double v1 = sqrt(v * v + 2.0 * a * L), t1 = (v1 - v) / a;
        if (tt + t1 >= T) {
            v += a * (T - tt);
            break;
        }
        tt += t1;
        double delta = th - bend_angle(i + 1);
        v = delta > 0 ? v1 * cos(delta) - mu * (1.0 + e) * v1 * sin(delta) : v1;
        x = i + 1.5;
        i++;
    }
    *face = i;
    return v;
}

static double bent_curve(int i, int j, void *ctx)
{
    (void)j, (void)ctx;
    double z = 60.0;
    for (int k = 0; k < i; k++)
        z -= tan(bend_angle(k));
    return z;
}

/* A point mass sliding down the fall line of the curve crosses its BENDS concave grid
 * edges, each met slower than v_stay along the next face's normal: BENDS edge
 * transitions and no impact, and its speed after T is the closed form's to 1e-12: Eq.
 * 1-2 on each face, and at each edge v cos delta - mu (1 + e) v sin delta (the velocity
 * projected less Eq. 8's plastic friction of the turn).  A rolling sphere crosses the
 * same edges by BENDS transitions too (it meets each next face before its contact point
 * reaches the edge) and gains no energy. */
TEST(rolling_across_many_concave_grid_edges_matches_the_closed_form)
{
    const double mu = 0.4, e = 0.25, mass = 1830.0, T = 3.2, v0 = 2.0, x0 = 18.7;
    rf_terrain t;
    mt_grid_terrain(&t, 0, 60, 20, 1.0, bent_curve, NULL,
                    (rf_surface){{e, 0.0}, {mu, 0.0}, {0.15, 0.0}});
    double th0 = bend_angle(0);
    rf_vec3 dir = rf_v3(cos(th0), 0.0, -sin(th0));
    rf_state s = mt_state(rf_v3(x0, 10.0, bent_curve(18, 0, NULL) - tan(th0) * (x0 - 18.5)),
                          rf_v3_scale(dir, v0));
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_POINT);
    rf_simulation sim = mt_sim(RF_MODEL_POINT, RF_CONTACT_FULL, T);
    mt_run r;
    mt_simulate_opts(&t, &sim, &b, &s, 5, 0.0, &r);
    ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "reason %d", (int)r.rec.reason);
    ENSURE_MSG(r.rec.n_edge_transitions == BENDS && r.rec.n_impacts == 0 && r.rec.n_flights == 0,
               "%ld edge transitions, %ld impacts, %ld flights", r.rec.n_edge_transitions,
               r.rec.n_impacts, r.rec.n_flights);
    /* the closed form, face by face: node i at x = i + 0.5, face i from node i to i + 1 */
    int i;
    double v = bent_closed_form(x0, v0, mu, e, T, &i);
    ENSURE_MSG(i >= 20 + BENDS, "the closed form ends on face %d", i);
    ENSURE_REL(r.last.speed_ms, v, 1e-12);
    mt_run_free(&r);

    rf_body bs = rf_body_make(mass, 2650.0, RF_MODEL_SPHERE);
    double r0 = rf_body_contact_radius(&bs);
    rf_vec3 n = rf_v3(sin(th0), 0.0, cos(th0));
    rf_state ss = mt_state(rf_v3_madd(s.p, r0, n), rf_v3_scale(dir, v0));
    ss.w = rf_v3_scale(rf_v3_cross(n, ss.v), 1.0 / r0); /* rolling */
    rf_simulation ssim = mt_sim(RF_MODEL_SPHERE, RF_CONTACT_FULL, T);
    mt_simulate_opts(&t, &ssim, &bs, &ss, 5, 0.0, &r);
    ENSURE_MSG(r.rec.n_edge_transitions == BENDS && r.rec.n_impacts == 0 && r.rec.n_flights == 0,
               "sphere: %ld edge transitions, %ld impacts, %ld flights", r.rec.n_edge_transitions,
               r.rec.n_impacts, r.rec.n_flights);
    ENSURE(r.rec.edge_loss_kj > 0.0 && r.energy_gain_kj <= 0.0);
    ENSURE_MSG(mt_energy_rise(&r, mass) <= 1e-6 * mass * G, "sphere: mechanical energy rises");
    ENSURE(r.last.p.x > 20.5 + BENDS);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* Centre contact (Eq. 6-7) on the same curve: the offset planes of the faces step down
 * at each bend's column border, and the centre, crossing it on one face's offset plane,
 * is above the next one's.  A sphere sliding down the fall line (tan theta > 3.5 mu, so
 * the slip never vanishes and the centre accelerates by Eq. 1-2, as the point mass does)
 * changes face at each bend: BENDS edge transitions, no impact, no flight, and its speed
 * after T is the closed form's to 1e-12 - Eq. 1-2 on each face from the column border
 * the centre crossed, and at each border v cos delta - mu (1 + e) v sin delta, the step
 * down taking no time.  A rolling sphere makes the same BENDS transitions, with no impact
 * and no flight, and gains no energy. */
TEST(rolling_centre_contact_across_many_concave_grid_edges_matches_the_closed_form)
{
    const double mu = 0.15, e = 0.25, mass = 1830.0, T = 3.2, v0 = 2.0, x0 = 18.7;
    rf_terrain t;
    mt_grid_terrain(&t, 0, 60, 20, 1.0, bent_curve, NULL,
                    (rf_surface){{e, 0.0}, {mu, 0.0}, {0.05, 0.0}});
    double th0 = bend_angle(0);
    ENSURE(tan(bend_angle(BENDS + 20)) > 3.5 * mu);
    rf_vec3 dir = rf_v3(cos(th0), 0.0, -sin(th0)), n = rf_v3(sin(th0), 0.0, cos(th0));
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_SPHERE);
    double r0 = rf_body_contact_radius(&b);
    rf_vec3 q = rf_v3(x0, 10.0, bent_curve(18, 0, NULL) - tan(th0) * (x0 - 18.5));
    for (int rolling = 0; rolling < 2; rolling++) {
        rf_state s = mt_state(rf_v3(x0, 10.0, q.z + r0 / n.z), rf_v3_scale(dir, v0));
        if (rolling)
            s.w = rf_v3_scale(rf_v3_cross(n, s.v), 1.0 / r0);
        rf_simulation sim = mt_sim(RF_MODEL_SPHERE, RF_CONTACT_CENTRE, T);
        mt_run r;
        mt_simulate_opts(&t, &sim, &b, &s, 5, 0.0, &r);
        ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "rolling %d: reason %d", rolling,
                   (int)r.rec.reason);
        ENSURE_MSG(r.rec.n_edge_transitions == BENDS && r.rec.n_impacts == 0 && r.rec.n_flights == 0,
                   "rolling %d: %ld edge transitions, %ld impacts, %ld flights", rolling,
                   r.rec.n_edge_transitions, r.rec.n_impacts, r.rec.n_flights);
        ENSURE(r.rec.edge_loss_kj > 0.0 && r.energy_gain_kj <= 0.0);
        ENSURE_MSG(mt_energy_rise(&r, mass) <= 1e-6 * mass * G, "rolling %d: energy rises", rolling);
        ENSURE(r.last.p.x > 20.5 + BENDS);
        if (!rolling) {
            /* the closed form, face by face: the centre crosses node i at x = i + 0.5 */
            int i;
            double v = bent_closed_form(x0, v0, mu, e, T, &i);
            ENSURE_MSG(i >= 20 + BENDS, "the closed form ends on face %d", i);
            ENSURE_REL(r.last.speed_ms, v, 1e-12);
        }
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

