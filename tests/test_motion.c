/* test_motion.c - the motion engine against closed forms (Eq. 1-2, 5/7 rolling,
 * parabolic landing, bounce sequence). */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "rockfall/montecarlo.h"

#define PI 3.14159265358979323846
#define G RF_GRAVITY

/* ---- launch from a cliff -------------------------------------------------------------- */

TEST(motion_launch_from_cliff_lands_at_v0_sqrt_2h_over_g)
{
    const double h = 23.85, xc = 50.0;
    /* flat top, a near-vertical face (1 mm wide), flat base */
    double prof[8] = {0.0, h, xc, h, xc + 0.001, 0.0, 400.0, 0.0};
    rf_terrain t;
    mt_profile(&t, prof, 4, 40.0, (rf_surface){{0.0, 0.0}, {0.7, 0.0}, {0.0, 0.0}});
    const double v0s[] = {4.2, 11.3, 27.9};
    for (size_t k = 0; k < 3; k++) {
        double v0 = v0s[k];
        /* point mass sliding on a frictionless top keeps v0 (mu only at the base) */
        rf_terrain_free(&t);
        mt_profile(&t, prof, 4, 40.0, (rf_surface){{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}});
        rf_state s = mt_state(rf_v3(xc - 10.0, 20.0, h), rf_v3(v0, 0, 0));
        mt_run r;
        mt_simulate_t(&t, RF_MODEL_POINT, 100.0, RF_CONTACT_FULL, &s, 1, 1e9, &r);
        /* the first impact point */
        const rf_path_point *imp = mt_first_impact(&r);
        ENSURE(imp != NULL);
        ENSURE_REL(imp->p.x, xc + v0 * sqrt(2.0 * h / G), 1e-9);
        ENSURE_SMALL(imp->p.z, 1e-9);
        ENSURE_REL(imp->t_s, 10.0 / v0 + sqrt(2.0 * h / G), 1e-9);
        mt_run_free(&r);

        /* rolling sphere: the centre is r above the top and lands r above the base */
        rf_body b = rf_body_make(1000.0, 2650.0, RF_MODEL_SPHERE);
        if (v0 * v0 < b.radius * G)
            continue; /* too slow to fly off the edge */
        rf_state ss = mt_state(rf_v3(xc - 10.0, 20.0, h + b.radius), rf_v3(v0, 0, 0));
        ss.w = rf_v3(0, v0 / b.radius, 0); /* rolling: w = n x v / r */
        mt_simulate_t(&t, RF_MODEL_SPHERE, 1000.0, RF_CONTACT_FULL, &ss, 1, 1e9, &r);
        imp = mt_first_impact(&r);
        ENSURE(imp != NULL);
        ENSURE_REL(imp->p.x, xc + v0 * sqrt(2.0 * h / G), 1e-9);
        ENSURE_REL(imp->p.z, b.radius, 1e-9);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* ---- arcs --------------------------------------------------------------------------- */

TEST(motion_flight_path_length_and_max_energy)
{
    /* a throw onto flat ground that stops dead at the landing (e = 0, huge mu): the
     * path length is the parabola's arc length */
    rf_terrain t;
    mt_incline(&t, 0.0, 1000.0, 100.0, (rf_surface){{0.0, 0.0}, {1e3, 0.0}, {1e3, 0.0}});
    rf_state s = mt_state(rf_v3(10.0, 50.0, 0.0), rf_v3(13.1, 0.0, 17.9));
    mt_run r;
    mt_simulate(&t, RF_MODEL_POINT, 1.0, RF_CONTACT_FULL, &s, 1, &r);
    ENSURE(r.rec.reason == RF_END_REST);
    double T = 2.0 * 17.9 / G;
    ENSURE_REL(r.rec.duration_s, T, 1e-12);
    ENSURE_REL(r.rec.stop.x, 10.0 + 13.1 * T, 1e-12);
    /* numeric arc length by Simpson's rule */
    int N = 20000;
    double sum = 0;
    for (int i = 0; i <= N; i++) {
        double tt = T * i / N, vz = 17.9 - G * tt;
        double f = hypot(13.1, vz);
        sum += f * (i == 0 || i == N ? 1 : (i % 2 ? 4 : 2));
    }
    double len = sum * T / N / 3.0;
    ENSURE_REL(r.rec.path_length_m, len, 1e-9);
    ENSURE_REL(r.rec.max_energy_kj, 0.5 * (13.1 * 13.1 + 17.9 * 17.9) / 1000.0, 1e-12);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* ---- helpers of sim.h ------------------------------------------------------------- */

TEST(motion_body_and_energy)
{
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    ENSURE_REL(4.0 / 3.0 * PI * pow(b.radius, 3) * 2650.0, 2385.0, 1e-14);
    ENSURE_REL(b.inertia, 0.4 * 2385.0 * b.radius * b.radius, 1e-14);
    rf_vec3 v = rf_v3(1.5, -2.0, 0.25), w = rf_v3(0.3, 0.1, -0.7);
    ENSURE_REL(rf_kinetic_energy(&b, v, w),
               0.5 * 2385.0 * rf_v3_norm2(v) + 0.5 * b.inertia * rf_v3_norm2(w), 1e-14);
    rf_body p = rf_body_make(2385.0, 2650.0, RF_MODEL_POINT);
    ENSURE_REL(rf_kinetic_energy(&p, v, w), 0.5 * 2385.0 * rf_v3_norm2(v), 1e-14);
}

/* A release's `height` is that of the rock's lowest point above the ground: a point
 * mass starts on the ground (at height 0) or `height` above it; a sphere touches the
 * face under the release point, or is `height` higher, its centre r off that face. */
TEST(motion_release_puts_the_lowest_point_at_the_release_height)
{
    rf_project p;
    rf_error err;
    ENSURE(rf_project_load("projects/noto/noto-3.1-no-trees.yaml", &p, &err) == 0);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    ENSURE(rng);
    const double heights[] = {0.0, 1.5};
    for (int h = 0; h < 2; h++) {
        p.releases[0].height = heights[h];
        p.releases[0].jitter = 2.0;
        for (int k = 0; k < 20; k++) {
            gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
            rf_body pt = rf_release_body(&p, 0, RF_MODEL_POINT);
            rf_state s = rf_release_start(&p, 0, &pt, rng);
            double zg;
            int32_t tri = rf_terrain_height(&p.terrain, s.p.x, s.p.y, &zg);
            ENSURE(tri >= 0);
            ENSURE_MSG(fabs(s.p.z - heights[h] - zg) < 1e-9,
                       "point mass %d starts %.6f m above the ground, not %g", k, s.p.z - zg,
                       heights[h]);

            gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
            rf_body sp = rf_release_body(&p, 0, RF_MODEL_SPHERE);
            rf_state ss = rf_release_start(&p, 0, &sp, rng);
            rf_vec3 n = RF_TRI(&p.terrain, tri)->n;
            ENSURE_MSG(fabs(rf_v3_dot(rf_v3_sub(ss.p, rf_v3(s.p.x, s.p.y, zg)), n) -
                            sp.radius - heights[h] * n.z) < 1e-9,
                       "sphere %d: centre not r + height above the face", k);
        }
    }
    gsl_rng_free(rng);
    rf_project_free(&p);
}

TEST(motion_draw_truncated)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 2385);
    ENSURE(rf_draw_truncated(rng, (rf_dist){0.385, 0.0}, 0.0, 1.0) == 0.385);
    ENSURE(rf_draw_truncated(rng, (rf_dist){1.7, 0.0}, 0.0, 1.0) == 1.0);
    ENSURE(rf_draw_truncated(rng, (rf_dist){-0.2, 0.0}, 0.0, INFINITY) == 0.0);
    double sum = 0;
    for (int i = 0; i < 20000; i++) {
        double x = rf_draw_truncated(rng, (rf_dist){0.9, 0.3}, 0.0, 1.0);
        ENSURE(x >= 0.0 && x <= 1.0);
        sum += x;
    }
    /* the mean of N(0.9, 0.3) cut to [0, 1] is below 0.9 */
    ENSURE(sum / 20000 < 0.8 && sum / 20000 > 0.7);
    /* far in the tail: no hang, the clamped mean */
    double x = rf_draw_truncated(rng, (rf_dist){-50.0, 0.1}, 0.0, 1.0);
    ENSURE(x == 0.0);
    gsl_rng_free(rng);
}

/* ---- samples, max_time, centre contact ------------------------------------------------ */

TEST(motion_samples_every_spacing)
{
    const double theta = 30.0 * PI / 180.0;
    double prof[6] = {0.0, 60.0 * tan(theta), 60.0, 0.0, 200.0, 0.0};
    rf_terrain t;
    mt_profile(&t, prof, 3, 40.0, (rf_surface){{0.3, 0.0}, {0.4, 0.0}, {0.1, 0.0}});
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(500.0, 2650.0, md);
        rf_simulation sim = mt_sim(md, RF_CONTACT_FULL, 300.0);
        rf_state s = mt_state(rf_v3(3.0, 20.0, 60.0 * tan(theta) + 2.0), rf_v3(1.0, 0.5, 0.0));
        mt_run r;
        mt_simulate_opts(&t, &sim, &b, &s, 3, 0.37, &r);
        ENSURE(!r.nan_seen);
        ENSURE(r.samples > 10);
        ENSURE_MSG(r.max_sample_gap <= 0.37 * (1 + 1e-9), "gap %.17g", r.max_sample_gap);
        double hd = hypot(r.rec.stop.x - 3.0, r.rec.stop.y - 20.0);
        ENSURE(r.samples >= (long)(hd / 0.37));
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* Every sample's energy is the state of its time, spin included: the spin follows the
 * velocity along a piece on a face (taken from the piece's start, a rolling sphere's
 * samples had 5/7 of its energy after a start from rest).  A rolling sphere has
 * 7/10 m v^2 everywhere (on the fall line, along the hodograph's path across it, and in
 * fixed steps), and on the fall line 7/5 m a d after d from rest; a sphere sliding from
 * rest down a steep face spins up at 5/2 mu g cos(theta) / r. */
TEST(motion_samples_carry_the_spin_of_their_time)
{
    const double mass = 2385.0;
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_SPHERE);
    for (int k = 0; k < 5; k++) {
        /* 0, 1: rolling down the fall line (full, centre contact); 2: rolling across it;
         * 3: fixed steps; 4: sliding down a steep face */
        double theta = (k == 4 ? 62.0 : 27.3) * PI / 180.0, mu = k == 4 ? 0.2 : 0.9;
        double mu_r = k == 4 ? 0.05 : 0.115;
        rf_terrain t;
        mt_incline(&t, theta, 300.0, 400.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {mu_r, 0.0}});
        rf_simulation sim = mt_sim(RF_MODEL_SPHERE, k == 1 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL,
                                   k == 2 ? 2.6 : 4.1);
        if (k == 3)
            sim.engine = RF_ENGINE_FIXED_STEP, sim.contact = RF_CONTACT_CENTRE, sim.dt = 0.01;
        rf_vec3 n = rf_v3(sin(theta), 0.0, cos(theta));
        rf_vec3 v0 = k == 2 ? rf_v3_madd(rf_v3(0.0, 8.0, 0.0), -1.5, rf_v3(cos(theta), 0, -sin(theta)))
                            : rf_v3(0, 0, 0);
        rf_state s = mt_incline_state(theta, 300.0, 30.0, 150.0, b.radius, v0);
        s.w = rf_v3_scale(rf_v3_cross(n, v0), 1.0 / b.radius); /* rolling */
        mt_run r;
        mt_simulate_opts(&t, &sim, &b, &s, 1, 0.5, &r);
        ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "case %d: reason %d", k, (int)r.rec.reason);
        ENSURE_MSG(r.samples > 20, "case %d: %ld samples", k, r.samples);
        double worst = 0.0;
        for (long i = 0; i < r.samples; i++) {
            const mt_sample *q = &r.sample[i];
            double want;
            if (k < 4) {
                want = 0.7 * mass * q->speed_ms * q->speed_ms / 1000.0;
                if (k < 2) {
                    double a = 5.0 / 7.0 * G * (sin(theta) - mu_r * cos(theta));
                    double d = rf_v3_norm(rf_v3_sub(q->p, s.p));
                    ENSURE_REL(q->energy_kj, 1.4 * mass * a * d / 1000.0, 1e-9);
                }
            } else {
                double a = G * (sin(theta) - mu * cos(theta));
                double d = rf_v3_norm(rf_v3_sub(q->p, s.p)), ts = sqrt(2.0 * d / a);
                double w = 2.5 * mu * G * cos(theta) * ts / b.radius;
                want = (mass * a * d + 0.5 * b.inertia * w * w) / 1000.0;
            }
            double e = fabs(q->energy_kj - want) / want;
            if (e > worst)
                worst = e;
        }
        ENSURE_MSG(worst <= 1e-9, "case %d: a sample's energy off by %.3g", k, worst);
        mt_run_free(&r);
        rf_terrain_free(&t);
    }
}

/* A sphere set on an incline at rest with top spin W / r: its slip runs up the slope,
 * so friction speeds it up (a = g (sin + mu cos)) while spinning it down
 * (r w = W - 5/2 mu g cos(theta) t); stopped by max_time before the slip ends, the
 * largest energy along it is its start's (E(t) is convex), not the end's speed with the
 * start's spin.  Both engines. */
TEST(motion_max_energy_of_a_sphere_spun_down_while_it_speeds_up)
{
    const double theta = 30.0 * PI / 180.0, mu = 0.3, W = 6.0, T = 0.3, mass = 2385.0;
    rf_terrain t;
    mt_incline(&t, theta, 300.0, 60.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {0.05, 0.0}});
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_SPHERE);
    rf_vec3 n = rf_v3(sin(theta), 0.0, cos(theta)), e1 = rf_v3(cos(theta), 0.0, -sin(theta));
    rf_state s = mt_incline_state(theta, 300.0, 100.0, 30.0, b.radius, rf_v3(0, 0, 0));
    s.w = rf_v3_scale(rf_v3_cross(n, e1), W / b.radius);
    double a = G * (sin(theta) + mu * cos(theta));
    double rw = W - 2.5 * mu * G * cos(theta) * T;
    ENSURE(T < W / (G * sin(theta) + 3.5 * mu * G * cos(theta))); /* the slip is not over */
    double e0 = 0.2 * mass * W * W / 1000.0;
    double eT = (0.5 * mass * a * a * T * T + 0.2 * mass * rw * rw) / 1000.0;
    for (int fixed = 0; fixed < 2; fixed++) {
        rf_simulation sim = mt_sim(RF_MODEL_SPHERE, RF_CONTACT_FULL, T);
        if (fixed)
            sim.engine = RF_ENGINE_FIXED_STEP, sim.contact = RF_CONTACT_CENTRE, sim.dt = 0.01;
        mt_run r;
        mt_simulate_opts(&t, &sim, &b, &s, 1, 0.0, &r);
        ENSURE_MSG(r.rec.reason == RF_END_MAX_TIME, "reason %d", (int)r.rec.reason);
        ENSURE(r.rec.n_impacts == 0);
        ENSURE_REL(r.last.speed_ms, a * T, 1e-9);
        ENSURE_REL(r.last.energy_kj, eT, 1e-9);
        ENSURE_MSG(fabs(r.rec.max_energy_kj - fmax(e0, eT)) <= 1e-9 * e0,
                   "engine %d: max energy %.12g kJ, want %.12g (start %.12g, end %.12g)", fixed,
                   r.rec.max_energy_kj, fmax(e0, eT), e0, eT);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

TEST(motion_max_time_ends_a_trajectory)
{
    const double theta = 30.0 * PI / 180.0;
    rf_terrain t;
    mt_incline(&t, theta, 500.0, 40.0, (rf_surface){{0.3, 0.0}, {0.2, 0.0}, {0.1, 0.0}});
    rf_state s = mt_state(rf_v3(3.0, 20.0, 497.0 * tan(theta) + 5.0), rf_v3(0, 0, 0));
    mt_run r;
    mt_simulate_t(&t, RF_MODEL_POINT, 100.0, RF_CONTACT_FULL, &s, 1, 2.385, &r);
    ENSURE(r.rec.reason == RF_END_MAX_TIME);
    ENSURE(r.rec.duration_s == 2.385);
    ENSURE(r.last.t_s == 2.385);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* Impacts counted are approaches: on the Noto slope (1 m grid, releases at whole
 * metres) centre-mode rocks run exactly along grid lines, where the faces on both sides
 * take turns as the face under the centre at one instant; those grazing touches change
 * nothing and must not count as impacts. */
typedef struct impact_count {
    long n, grazing;
} impact_count;

static void count_impacts(void *ctx, double t, double e0, double e1, double vin)
{
    impact_count *ic = ctx;
    (void)t, (void)e0, (void)e1;
    ic->n++;
    if (!(vin > 1e-7))
        ic->grazing++;
}

TEST(motion_grazing_touches_are_not_impacts)
{
    rf_project p;
    rf_error err;
    ENSURE(rf_project_load("projects/noto/noto-3.1-no-trees.yaml", &p, &err) == 0);
    p.sim.contact = RF_CONTACT_CENTRE;
    rf_scene sc = {&p.terrain, &p.sim, NULL, 0, p.measures, p.nmeasures};
    rf_body b = rf_release_body(&p, 0, p.sim.model);
    rf_workspace *ws = rf_workspace_alloc(&p.terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    long total = 0;
    for (int k = 0; k < 40; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
        rf_state s = rf_release_start(&p, 0, &b, rng);
        impact_count ic = {0, 0};
        rf_sink sk;
        memset(&sk, 0, sizeof sk);
        sk.ctx = &ic;
        sk.impact = count_impacts;
        rf_trajectory_record rec;
        rf_simulate(&sc, &b, &s, rng, ws, &sk, &rec);
        ENSURE_MSG(ic.grazing == 0, "trajectory %d: %ld grazing impacts", k, ic.grazing);
        ENSURE(rec.n_impacts == ic.n);
        total += ic.n;
    }
    printf("    %.1f impacts per trajectory (centre contact)\n", total / 40.0);
    ENSURE(total > 0);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_project_free(&p);
}

/* ---- tables shared between threads ---------------------------------------------------- */

static double shared_z(int i, int j, void *ctx)
{
    gsl_rng *g = ctx;
    (void)j;
    return 60.0 - 0.9 * i + 0.6 * gsl_rng_uniform(g);
}

/* The same trajectories from a workspace over tables built once for the terrain (as the
 * Monte Carlo threads share them) and from one that builds its own: the records (stop
 * point, duration, path length, largest energy, impacts) the same bytes, on a grid and
 * on a mesh of the same surface, in full and centre contact. */
TEST(motion_shared_terrain_tables_give_the_private_tables_results)
{
    for (int mesh = 0; mesh < 2; mesh++) {
        gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
        gsl_rng_set(g, 2385);
        rf_terrain t;
        mt_grid_terrain(&t, mesh, 41, 21, 1.5, shared_z, g,
                        (rf_surface){{0.35, 0.1}, {0.45, 0.05}});
        gsl_rng_free(g);
        rf_terrain_tables *tt = rf_terrain_tables_build(&t);
        ENSURE(tt != NULL);
        rf_workspace *shared = rf_workspace_alloc_shared(tt), *own = rf_workspace_alloc(&t);
        ENSURE(shared && own);
        for (int k = 0; k < 16; k++) {
            rf_contact_kind contact = k % 2 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL;
            rf_simulation sim = mt_sim(RF_MODEL_SPHERE, contact, 60.0);
            rf_scene scene = {.terrain = &t, .sim = &sim};
            rf_body b = rf_body_make(800.0 + 150.0 * k, 2650.0, RF_MODEL_SPHERE);
            rf_state s = mt_state(rf_v3(2.0 + 0.37 * k, 3.0 + 0.9 * k, 62.0), rf_v3(1.5, 0.2 * k, 0.0));
            rf_trajectory_record ra, rb;
            gsl_rng *ga = gsl_rng_alloc(rf_rng_type()), *gb = gsl_rng_alloc(rf_rng_type());
            gsl_rng_set(ga, 77 + (unsigned long)k);
            gsl_rng_set(gb, 77 + (unsigned long)k);
            ENSURE(rf_simulate(&scene, &b, &s, ga, shared, NULL, &ra) == 0);
            ENSURE(rf_simulate(&scene, &b, &s, gb, own, NULL, &rb) == 0);
            ENSURE_MSG(memcmp(&ra, &rb, sizeof ra) == 0, "mesh %d, trajectory %d", mesh, k);
            ENSURE(ra.n_impacts > 0);
            gsl_rng_free(ga);
            gsl_rng_free(gb);
        }
        rf_workspace_free(shared);
        rf_workspace_free(own);
        rf_terrain_tables_free(tt);
        rf_terrain_free(&t);
    }
}
