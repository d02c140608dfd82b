/* test_surface.c - rolling and sliding on a face (surface.c): a point mass sliding
 * (Eq. 1-2), a sphere slipping and rolling (a = 5/7 g (sin - mu_r cos)), across the fall
 * line against the hodograph's closed form, on level ground to rest, and a slipping
 * sphere spun up until it rolls. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"

#define PI 3.14159265358979323846
#define G RF_GRAVITY

/* ---- Eq. 1-2: a point mass slides down a plane ------------------------------------ */

TEST(motion_point_slides_eq1_eq2)
{
    const double theta = 33.7 * PI / 180.0, mu = 0.385, L = 120.0;
    const double top = L * tan(theta);
    rf_terrain t;
    mt_incline(&t, theta, L, 40.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu, 0.0}});
    const double heights[] = {2.385, 17.3, 48.9, top - 0.01};
    for (size_t k = 0; k < sizeof heights / sizeof *heights; k++) {
        double H = heights[k];
        double x0 = L - H / tan(theta);
        rf_state s = mt_state(rf_v3(x0, 13.7, H), rf_v3(0, 0, 0));
        mt_run r;
        mt_simulate(&t, RF_MODEL_POINT, 2385.0, RF_CONTACT_FULL, &s, 1, &r);
        ENSURE_MSG(r.rec.reason == RF_END_EXITED, "reason %d", (int)r.rec.reason);
        double V = sqrt(1.0 - mu / tan(theta)) * sqrt(2.0 * G * H); /* Eq. 1-2 */
        ENSURE_REL(r.last.speed_ms, V, 1e-9);
        ENSURE_REL(r.rec.stop.x, L, 1e-12);
        ENSURE_SMALL(r.rec.stop.y - 13.7, 1e-9);
        /* time and path length of uniform acceleration */
        double a = G * (sin(theta) - mu * cos(theta)), len = H / sin(theta);
        ENSURE_REL(r.rec.duration_s, sqrt(2.0 * len / a), 1e-9);
        ENSURE_REL(r.rec.path_length_m, len, 1e-9);
        ENSURE_REL(r.rec.max_energy_kj, 0.5 * 2385.0 * V * V / 1000.0, 1e-9);
        ENSURE(r.rec.n_impacts == 0);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* ---- across the fall line: the hodograph's closed form ----------------------------- */

/* The in-plane laws integrated by classical Runge-Kutta in the incline's coordinates
 * (xi down the fall line, eta along y): y = (v_xi, v_eta, u_xi, u_eta, xi, eta).  Point
 * mass: v' = g_t - mu g_n v^; slipping sphere (K = 1 + m r^2 / I = 7/2): v' = g_t -
 * mu g_n u^, u' = g_t - K mu g_n u^; rolling sphere: v' = 5/7 (g_t - mu_r g_n v^). */
typedef enum { ACROSS_POINT, ACROSS_SLIP, ACROSS_ROLL } across_law;

typedef struct across {
    across_law law;
    double theta, c; /* c: mu, or mu_r for the rolling sphere */
} across;

static void across_rhs(const double *y, double *dy, const void *ctx)
{
    const across *a = ctx;
    double G_t = G * sin(a->theta), gn = G * cos(a->theta), c = a->c;
    const double *d = a->law == ACROSS_SLIP ? y + 2 : y; /* the direction of friction */
    double dl = hypot(d[0], d[1]);
    double k = a->law == ACROSS_ROLL ? 5.0 / 7.0 : 1.0;
    dy[0] = k * (G_t - c * gn * d[0] / dl);
    dy[1] = k * (-c * gn * d[1] / dl);
    dy[2] = a->law == ACROSS_SLIP ? G_t - 3.5 * c * gn * d[0] / dl : 0.0;
    dy[3] = a->law == ACROSS_SLIP ? -3.5 * c * gn * d[1] / dl : 0.0;
    dy[4] = y[0];
    dy[5] = y[1];
}

/* A rock set moving across an incline at (v_xi, v_eta): after T its centre and speed
 * match the integration to 2e-12 relative (the closed form is within 2e-14; the
 * Dormand-Prince integrator it replaced, at 1e-9 per step, erred by 2e-11). */
static void across_incline(across_law law, double theta, double mu, double mu_r, double vxi,
                           double veta, double T)
{
    const double L = 200.0, mass = 2385.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 400.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
    rf_rock_model model = law == ACROSS_POINT ? RF_MODEL_POINT : RF_MODEL_SPHERE;
    rf_body b = rf_body_make(mass, 2650.0, model);
    rf_vec3 e1 = rf_v3(cos(theta), 0.0, -sin(theta)), n = rf_v3(sin(theta), 0.0, cos(theta));
    rf_vec3 v0 = rf_v3_madd(rf_v3(0.0, veta, 0.0), vxi, e1);
    rf_state s = mt_incline_state(theta, L, 30.0, 150.0, rf_body_contact_radius(&b), v0);
    if (law == ACROSS_ROLL)
        s.w = rf_v3_scale(rf_v3_cross(n, v0), 1.0 / b.radius); /* no slip */
    mt_run r;
    mt_simulate_t(&t, model, mass, RF_CONTACT_FULL, &s, 1, T, &r);
    ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "reason %d", (int)r.rec.reason);
    ENSURE(r.rec.n_impacts == 0);
    double y[6] = {vxi, veta, vxi, veta, 0.0, 0.0}; /* a sphere without spin slips at v */
    across ref = {law, theta, law == ACROSS_ROLL ? mu_r : mu};
    mt_rk4(across_rhs, &ref, y, 6, T, 200000);
    rf_vec3 p = rf_v3_madd(rf_v3_madd(s.p, y[4], e1), y[5], rf_v3(0, 1, 0));
    double path = hypot(y[4], y[5]);
    ENSURE_MSG(rf_v3_norm(rf_v3_sub(r.rec.stop, p)) <= 2e-12 * path,
               "law %d: at (%.15g, %.15g, %.15g), integrated (%.15g, %.15g, %.15g)", (int)law,
               r.rec.stop.x, r.rec.stop.y, r.rec.stop.z, p.x, p.y, p.z);
    ENSURE_REL(r.last.speed_ms, hypot(y[0], y[1]), 2e-12);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

TEST(motion_point_slides_across_fall_line_in_closed_form)
{
    across_incline(ACROSS_POINT, 31.0 * PI / 180.0, 0.21, 0.0, 3.0, 9.5, 2.4);
    across_incline(ACROSS_POINT, 31.0 * PI / 180.0, 0.21, 0.0, -4.0, -6.0, 2.4); /* uphill */
}

TEST(motion_sphere_slips_across_fall_line_in_closed_form)
{
    across_incline(ACROSS_SLIP, 35.0 * PI / 180.0, 0.12, 0.05, 2.0, -7.5, 2.1);
}

TEST(motion_sphere_rolls_across_fall_line_in_closed_form)
{
    across_incline(ACROSS_ROLL, 27.3 * PI / 180.0, 0.9, 0.115, -1.5, 8.0, 2.6);
}

/* ---- rolling sphere: a = 5/7 g (sin theta - mu_r cos theta) ------------------------ */

TEST(motion_sphere_rolls_five_sevenths)
{
    const double theta = 27.3 * PI / 180.0, mu = 0.9, mu_r = 0.115, L = 300.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 60.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_incline_state(theta, L, 30.0, 23.85, b.radius, rf_v3(0, 0, 0));
    const double T[] = {0.75, 2.385, 4.1};
    for (size_t k = 0; k < 3; k++) {
        mt_run r;
        mt_simulate_t(&t, RF_MODEL_SPHERE, 2385.0, RF_CONTACT_FULL, &s, 1, T[k], &r);
        ENSURE(r.rec.reason == RF_END_MAX_TIME);
        double a = 5.0 / 7.0 * G * (sin(theta) - mu_r * cos(theta));
        ENSURE_REL(r.last.speed_ms, a * T[k], 1e-9);
        double d = rf_v3_norm(rf_v3_sub(r.rec.stop, s.p));
        ENSURE_REL(d, 0.5 * a * T[k] * T[k], 1e-9);
        ENSURE_REL(r.rec.path_length_m, 0.5 * a * T[k] * T[k], 1e-9);
        /* rolling: total energy 7/10 m v^2 */
        ENSURE_REL(r.last.energy_kj, 0.7 * 2385.0 * a * a * T[k] * T[k] / 1000.0, 1e-9);
        ENSURE_SMALL(r.rec.stop.y - 23.85, 1e-9);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* A sphere released at rest on a face too steep to roll without slipping
 * ((2/7) tan(theta) > mu): it slides at g (sin theta - mu cos theta) from the start,
 * friction spinning it up at 5/2 mu g cos(theta) / r, and never rolls. */
TEST(motion_sphere_at_rest_on_steep_face_slides)
{
    const double theta = 62.0 * PI / 180.0, mu = 0.2, mu_r = 0.05, L = 300.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 60.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_incline_state(theta, L, 100.0, 23.85, b.radius, rf_v3(0, 0, 0));
    const double T[] = {0.3, 1.7};
    for (size_t k = 0; k < 2; k++) {
        mt_run r;
        mt_simulate_t(&t, RF_MODEL_SPHERE, 2385.0, RF_CONTACT_FULL, &s, 1, T[k], &r);
        ENSURE(r.rec.reason == RF_END_MAX_TIME);
        double a = G * (sin(theta) - mu * cos(theta));
        ENSURE_REL(r.last.speed_ms, a * T[k], 1e-9);
        ENSURE_REL(rf_v3_norm(rf_v3_sub(r.rec.stop, s.p)), 0.5 * a * T[k] * T[k], 1e-9);
        /* translation plus spin: w = 5/2 mu g cos(theta) t / r, I = 2/5 m r^2 */
        double w = 2.5 * mu * G * cos(theta) * T[k] / b.radius;
        double e = 0.5 * 2385.0 * a * a * T[k] * T[k] + 0.5 * b.inertia * w * w;
        ENSURE_REL(r.last.energy_kj, e / 1000.0, 1e-9);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* ---- level ground and rest ------------------------------------------------------- */

TEST(motion_centre_contact_rolls_five_sevenths_on_a_plane)
{
    /* on one plane the paper's centre test and the full test agree */
    const double theta = 24.1 * PI / 180.0, mu_r = 0.2, L = 200.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 60.0, (rf_surface){{0.0, 0.0}, {0.9, 0.0}, {mu_r, 0.0}});
    rf_body b = rf_body_make(900.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_incline_state(theta, L, 20.0, 30.0, b.radius, rf_v3(0, 0, 0));
    for (int contact = 0; contact < 2; contact++) {
        mt_run r;
        mt_simulate_t(&t, RF_MODEL_SPHERE, 900.0, contact ? RF_CONTACT_CENTRE : RF_CONTACT_FULL,
                      &s, 1, 3.0, &r);
        double a = 5.0 / 7.0 * G * (sin(theta) - mu_r * cos(theta));
        ENSURE_REL(r.last.speed_ms, a * 3.0, 1e-9);
        ENSURE_REL(rf_v3_norm(rf_v3_sub(r.rec.stop, s.p)), 4.5 * a, 1e-9);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

TEST(motion_rolling_sphere_decelerates_to_rest)
{
    /* rolling on level ground: rest where the speed falls to stop_speed, v^2 - s^2 = 2 a d */
    rf_terrain t;
    const double mu_r = 0.13;
    mt_incline(&t, 0.0, 300.0, 60.0, (rf_surface){{0.0, 0.0}, {0.9, 0.0}, {mu_r, 0.0}});
    rf_body b = rf_body_make(900.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_state(rf_v3(10.0, 30.0, b.radius), rf_v3(7.3, 0, 0));
    s.w = rf_v3(0, 7.3 / b.radius, 0);
    mt_run r;
    mt_simulate(&t, RF_MODEL_SPHERE, 900.0, RF_CONTACT_FULL, &s, 1, &r);
    ENSURE(r.rec.reason == RF_END_REST);
    double a = 5.0 / 7.0 * G * mu_r, stop = 0.1;
    ENSURE_REL(r.rec.stop.x - 10.0, (7.3 * 7.3 - stop * stop) / (2 * a), 1e-9);
    ENSURE_REL(r.rec.duration_s, (7.3 - stop) / a, 1e-9);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A point mass slid along level ground decelerates at mu g (Eq. 1-2 with theta = 0) and
 * rests where its speed falls to stop_speed (0.1 m/s): v0^2 - s^2 = 2 mu g d. */
TEST(surface_point_slides_to_rest_on_level_ground_at_mu_g)
{
    const double mu = 0.385, v0 = 8.35, stop = 0.1;
    rf_terrain t;
    mt_incline(&t, 0.0, 300.0, 60.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {0.0, 0.0}});
    rf_state s = mt_state(rf_v3(12.5, 30.0, 0.0), rf_v3(v0 * 0.6, v0 * 0.8, 0));
    mt_run r;
    mt_simulate(&t, RF_MODEL_POINT, 1250.0, RF_CONTACT_FULL, &s, 3, &r);
    ENSURE(r.rec.reason == RF_END_REST);
    ENSURE(r.rec.n_impacts == 0);
    double a = mu * G, d = (v0 * v0 - stop * stop) / (2.0 * a);
    ENSURE_REL(r.rec.stop.x - 12.5, 0.6 * d, 1e-9);
    ENSURE_REL(r.rec.stop.y - 30.0, 0.8 * d, 1e-9);
    ENSURE_SMALL(r.rec.stop.z, 1e-12);
    ENSURE_REL(r.rec.duration_s, (v0 - stop) / a, 1e-9);
    ENSURE_REL(r.rec.path_length_m, d, 1e-9);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A sphere set down on level ground moving at v0 without spin slips: friction mu g
 * slows the centre and spins the sphere up, the slip u = v - w r falling at
 * (1 + m r^2 / I) mu g = 7/2 mu g, until it rolls at t1 = 2 v0 / (7 mu g) with 5/7 v0;
 * then it rolls on, decelerating at 5/7 mu_r g, to rest at stop_speed (0.1 m/s). */
TEST(surface_slipping_sphere_rolls_at_five_sevenths_of_its_speed)
{
    const double mu = 0.2385, mu_r = 0.0415, v0 = 6.85, stop = 0.1;
    rf_terrain t;
    mt_incline(&t, 0.0, 300.0, 60.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
    rf_body b = rf_body_make(1500.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s = mt_state(rf_v3(10.0, 30.0, b.radius), rf_v3(v0, 0, 0));
    mt_run r;
    mt_simulate(&t, RF_MODEL_SPHERE, 1500.0, RF_CONTACT_FULL, &s, 3, &r);
    ENSURE(r.rec.reason == RF_END_REST);
    ENSURE(r.rec.n_impacts == 0);
    double t1 = 2.0 * v0 / (7.0 * mu * G), v1 = 5.0 / 7.0 * v0;
    double d1 = v0 * t1 - 0.5 * mu * G * t1 * t1;
    double a2 = 5.0 / 7.0 * mu_r * G, d2 = (v1 * v1 - stop * stop) / (2.0 * a2);
    ENSURE_REL(r.rec.stop.x - 10.0, d1 + d2, 1e-9);
    ENSURE_SMALL(r.rec.stop.y - 30.0, 1e-12);
    ENSURE_REL(r.rec.duration_s, t1 + (v1 - stop) / a2, 1e-9);
    /* the largest kinetic energy is the start's: 1/2 m v0^2, nothing rotational */
    ENSURE_REL(r.rec.max_energy_kj, 0.5 * 1500.0 * v0 * v0 / 1000.0, 1e-12);
    mt_run_free(&r);
    rf_terrain_free(&t);
}
