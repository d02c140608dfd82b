/* test_vegetation.c - trees on the slope (Eq. 9-12, Fig. 5-7 and 10): the density of
 * trees taller than the rock's centre, collisions as a Poisson process along the
 * horizontal path sampled exactly by both engines, the impact with a stem, and what a
 * run records. */
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "rockfall/sim.h"
#include "fixtures/scenes.h"
#include "results/store.h"
#include "db_test_util.h"
#include "motion_test_util.h"
#include "test.h"
#include "base/util.h"
#include "scene/vegetation.h"

/* ---- scenes and observers ---------------------------------------------------------- */

/* What the sink of one trajectory saw. */
typedef struct vt_obs {
    long tree_hits;
    int have_first;
    rf_tree_hit_record first;  /* the first tree hit */
    int outside;               /* a hit outside the observer's box */
    double box[4];             /* xmin, ymin, xmax, ymax; box[0] > box[2]: none */
    double energy_gain_kj;     /* largest increase of kinetic energy at any impact */
    double tree_energy_lost_min_kj;
    long impacts_seen;
    int crossed;
    rf_interception_record crossing; /* the first crossing of a measure */
    int tree_pending;          /* a tree hit whose path point has not come yet */
    rf_vec3 tree_p;            /* where it was */
    double tree_jump_max;      /* largest move of the rock by a tree hit (m) */
} vt_obs;

static void obs_reset(vt_obs *o)
{
    double box[4];
    memcpy(box, o->box, sizeof box);
    memset(o, 0, sizeof *o);
    memcpy(o->box, box, sizeof box);
    o->energy_gain_kj = -INFINITY;
    o->tree_energy_lost_min_kj = INFINITY;
}

static void on_tree(void *ctx, const rf_tree_hit_record *r)
{
    vt_obs *o = ctx;
    if (!o->have_first) {
        o->first = *r;
        o->have_first = 1;
    }
    o->tree_hits++;
    o->tree_pending = 1;
    o->tree_p = r->p;
    if (r->energy_lost_kj < o->tree_energy_lost_min_kj)
        o->tree_energy_lost_min_kj = r->energy_lost_kj;
    if (o->box[0] <= o->box[2] &&
        (r->p.x < o->box[0] || r->p.x > o->box[2] || r->p.y < o->box[1] || r->p.y > o->box[3]))
        o->outside = 1;
}

static void on_impact(void *ctx, double t, double e0, double e1, double vn)
{
    vt_obs *o = ctx;
    (void)t;
    (void)vn;
    o->impacts_seen++;
    /* relative to the energy: the law itself is exact up to rounding */
    double gain = (e1 - e0) - 1e-12 * fmax(e0, 1e-9);
    if (gain > o->energy_gain_kj)
        o->energy_gain_kj = gain;
}

static void on_point(void *ctx, const rf_path_point *pt)
{
    vt_obs *o = ctx;
    if (o->tree_pending) {
        double d = rf_v3_norm(rf_v3_sub(pt->p, o->tree_p));
        if (d > o->tree_jump_max)
            o->tree_jump_max = d;
        o->tree_pending = 0;
    }
}

static void on_crossing(void *ctx, const rf_interception_record *r)
{
    vt_obs *o = ctx;
    if (!o->crossed) {
        o->crossing = *r;
        o->crossed = 1;
    }
}

/* A runner of many trajectories through one scene, one GSL stream per trajectory. */
typedef struct vt_runner {
    rf_scene scene;
    rf_body body;
    rf_workspace *ws;
    gsl_rng *rng;
    rf_sink sink;
    vt_obs obs;
} vt_runner;

static void runner_init(vt_runner *R, const rf_terrain *t, const rf_simulation *sim,
                        const rf_forest *fs, size_t nf, const rf_measure *ms, size_t nm,
                        rf_body body)
{
    memset(R, 0, sizeof *R);
    R->scene = (rf_scene){t, sim, fs, nf, ms, nm};
    R->body = body;
    R->ws = rf_workspace_alloc(t);
    ENSURE(R->ws != NULL);
    R->rng = gsl_rng_alloc(gsl_rng_mt19937);
    ENSURE(R->rng != NULL);
    R->sink.ctx = &R->obs;
    R->sink.tree_hit = on_tree;
    R->sink.impact = on_impact;
    R->sink.interception = on_crossing;
    R->sink.path_point = on_point;
    R->obs.box[0] = 1.0;
    R->obs.box[2] = 0.0;
}

static void runner_free(vt_runner *R)
{
    rf_workspace_free(R->ws);
    gsl_rng_free(R->rng);
}

/* Trajectory `k` (its own seed) from `start`; fills rec and R->obs. */
static void runner_go(vt_runner *R, unsigned long k, rf_state start, rf_trajectory_record *rec)
{
    obs_reset(&R->obs);
    gsl_rng_set(R->rng, 1000003ul * k + 2385ul);
    rf_simulate(&R->scene, &R->body, &start, R->rng, R->ws, &R->sink, rec);
    ENSURE_MSG(R->obs.tree_hits == rec->n_tree_hits, "trajectory %lu: %ld tree_hit records, "
               "n_tree_hits %ld", k, R->obs.tree_hits, rec->n_tree_hits);
}

static rf_forest forest(double density, double h_mean, double h_sd, double diameter,
                        double e, double mu)
{
    rf_forest f;
    memset(&f, 0, sizeof f);
    f.name = "forest";
    f.density = density;
    f.height = (rf_dist){h_mean, h_sd};
    f.diameter = diameter;
    f.restitution = (rf_dist){e, 0.0};
    f.friction = (rf_dist){mu, 0.0};
    return f;
}

/* The motion tests' options, with this engine and no stored paths. */
static rf_simulation sim_opts(rf_rock_model model, rf_engine_kind engine, double max_time)
{
    rf_simulation s = mt_sim(model, RF_CONTACT_FULL, max_time);
    s.engine = engine;
    s.paths = 0;
    return s;
}

/* A sphere of radius r (mass 1 000 kg). */
static rf_body sphere_of_radius(double r, rf_rock_model model)
{
    return rf_body_make(1000.0, 3.0 * 1000.0 / (4.0 * M_PI * r * r * r), model);
}

/* Flat frictionless ground, 2 km square, no bounce. */
#define FLAT_SIZE 2000.0
static void flat_ground(rf_terrain *t)
{
    const double pts[4] = {0.0, 0.0, FLAT_SIZE, 0.0};
    ENSURE(rf_scene_profile(t, pts, 2, FLAT_SIZE, 0.0, 0.0, 0.0) == 0);
}

/* Hits per metre of horizontal path of n rocks sliding at 10 m/s for `duration` s over
 * flat frictionless ground through the forests (elastic frictionless trees keep the
 * speed, so every path is 10 * duration long).  Returns the mean and its standard
 * error; `first` (n values, or NULL) receives the distance to the first hit. */
static void hit_rate(const rf_forest *fs, size_t nf, rf_body body, rf_engine_kind engine,
                     double dt, double duration, long n, double *mean, double *se,
                     double *first)
{
    rf_terrain t;
    flat_ground(&t);
    rf_simulation sim = sim_opts(body.model, engine, duration);
    sim.dt = dt;
    vt_runner R;
    runner_init(&R, &t, &sim, fs, nf, NULL, 0, body);
    double z0 = rf_body_contact_radius(&body);
    const double speed = 10.0, L = speed * duration;
    double sum = 0.0, sum2 = 0.0;
    for (long k = 0; k < n; k++) {
        rf_vec3 p0 = rf_v3(0.5 * FLAT_SIZE, 0.5 * FLAT_SIZE, z0);
        rf_trajectory_record rec;
        runner_go(&R, (unsigned long)k, mt_state(p0, rf_v3(speed, 0.0, 0.0)), &rec);
        ENSURE_MSG(rec.reason == RF_END_MAX_TIME, "trajectory %ld ended as %s", k,
                   rf_stop_reason_name(rec.reason));
        /* the speed is kept: the path is as long as planned (the fixed step adds the
         * settling of its first step) */
        ENSURE_REL(rec.path_length_m, L, engine == RF_ENGINE_EXACT ? 1e-9 : 1e-4);
        double x = (double)rec.n_tree_hits / L;
        sum += x;
        sum2 += x * x;
        if (first) {
            ENSURE_MSG(R.obs.have_first, "trajectory %ld met no tree", k);
            ENSURE_REL(R.obs.first.speed_after_ms, speed, 1e-9);
            first[k] = hypot(R.obs.first.p.x - p0.x, R.obs.first.p.y - p0.y);
        }
    }
    *mean = sum / (double)n;
    double var = (sum2 - (double)n * *mean * *mean) / (double)(n - 1);
    *se = sqrt(fmax(var, 0.0) / (double)n);
    runner_free(&R);
    rf_terrain_free(&t);
}

/* ---- Eq. 11-12 and the thinning, as functions ---------------------------------------- */

/* Eq. 11 at three heights through gsl_cdf_gaussian_Q; sigma = 0 is a step at M_ht. */
TEST(vegetation_eq11_density_above_height)
{
    rf_forest f = forest(0.01, 5.0, 1.5, 0.2, 0.2, 0.3);
    const double h[3] = {2.0, 5.0, 7.5};
    for (int i = 0; i < 3; i++) {
        double want = 0.01 * gsl_cdf_gaussian_Q((h[i] - 5.0) / 1.5, 1.0);
        ENSURE_REL(rf_forest_density_above(&f, h[i]), want, 1e-14);
        /* Eq. 12 per metre: rho (phi_r + phi_t) */
        ENSURE_REL(rf_forest_rate(&f, h[i], 0.9), want * (0.9 + 0.2), 1e-14);
    }
    ENSURE_REL(rf_forest_density_above(&f, 5.0), 0.005, 1e-15);
    /* far above the tallest trees: none */
    ENSURE(rf_forest_density_above(&f, 5.0 + 40.0 * 1.5) < 1e-300);
    /* sigma = 0: every tree is M_ht tall */
    rf_forest s = forest(0.02, 5.0, 0.0, 0.2, 0.2, 0.3);
    ENSURE(rf_forest_density_above(&s, 0.0) == 0.02);
    ENSURE(rf_forest_density_above(&s, 5.0 - 1e-9) == 0.02);
    ENSURE(rf_forest_density_above(&s, 5.0 + 1e-9) == 0.0);
    ENSURE(rf_forest_density_above(&s, 100.0) == 0.0);
    ENSURE(rf_forest_rate(&s, 100.0, 1.0) == 0.0);
    /* the bound over forests is the sum of rho0 (phi_r + phi_t) */
    rf_forest two[2] = {f, s};
    ENSURE_REL(rf_vegetation_rate_bound(two, 2, 0.9), 0.01 * 1.1 + 0.02 * 1.1, 1e-15);
}

/* Fraction of u in [0, 1) for which the thinning accepts a collision with forest `i`
 * (a fine grid of u: exact up to 1 / K). */
static double accept_share(const rf_forest *fs, size_t n, double x, double y, double h_r,
                           double phi_r, int which)
{
    const long K = 200000;
    double bound = rf_vegetation_rate_bound(fs, n, phi_r);
    long c = 0;
    for (long k = 0; k < K; k++) {
        int f = rf_vegetation_accept(fs, n, x, y, h_r, phi_r, bound, ((double)k + 0.5) / (double)K);
        if (which < 0 ? f >= 0 : f == which)
            c++;
    }
    return (double)c / (double)K;
}

/* Thinning: a candidate at (x, y, h_r) is a collision with forest i with probability
 * rate_i(h_r) / bound where forest i covers the point, never elsewhere; overlapping
 * forests add their rates. */
TEST(vegetation_thinning_acceptance)
{
    double square[8] = {0, 0, 10, 0, 10, 10, 0, 10};
    rf_forest fs[2];
    fs[0] = forest(0.02, 5.0, 1.0, 0.3, 0.2, 0.3); /* the whole terrain */
    fs[1] = forest(0.01, 3.0, 0.0, 0.2, 0.2, 0.3); /* the square, trees 3 m tall */
    fs[1].polygon.xy = square;
    fs[1].polygon.n = 4;
    const double phi_r = 1.0, bound = rf_vegetation_rate_bound(fs, 2, phi_r);
    ENSURE_REL(bound, 0.02 * 1.3 + 0.01 * 1.2, 1e-15);
    ENSURE(rf_forest_covers(&fs[0], -1e6, 3e5));
    ENSURE(rf_forest_covers(&fs[1], 5, 5));
    ENSURE(!rf_forest_covers(&fs[1], 15, 5));
    const double tol = 2.0 / 200000.0;
    /* inside the square, below the 3 m trees: both forests */
    double h = 2.0;
    double pa = rf_forest_rate(&fs[0], h, phi_r) / bound, pb = rf_forest_rate(&fs[1], h, phi_r) / bound;
    ENSURE_SMALL(accept_share(fs, 2, 5, 5, h, phi_r, 0) - pa, tol);
    ENSURE_SMALL(accept_share(fs, 2, 5, 5, h, phi_r, 1) - pb, tol);
    ENSURE_SMALL(accept_share(fs, 2, 5, 5, h, phi_r, -1) - (pa + pb), tol);
    /* outside the square: the whole-terrain forest only */
    ENSURE_SMALL(accept_share(fs, 2, 15, 5, h, phi_r, 1), 0.0);
    ENSURE_SMALL(accept_share(fs, 2, 15, 5, h, phi_r, -1) - pa, tol);
    /* above the 3 m trees: none of the square's; the others by Eq. 11 */
    h = 4.0;
    pa = rf_forest_rate(&fs[0], h, phi_r) / bound;
    ENSURE_SMALL(accept_share(fs, 2, 5, 5, h, phi_r, 1), 0.0);
    ENSURE_SMALL(accept_share(fs, 2, 5, 5, h, phi_r, 0) - pa, tol);
    /* on the ground of a forest of step heights: the full rate, acceptance 1 there */
    rf_forest one = forest(0.05, 5.0, 0.0, 0.2, 0.2, 0.3);
    ENSURE_SMALL(accept_share(&one, 1, 0, 0, 0.5, phi_r, 0) - 1.0, 0.0);
    ENSURE_SMALL(accept_share(&one, 1, 0, 0, 5.5, phi_r, -1), 0.0);
}

static double uniform_pm(gsl_rng *rng, double a) { return a * (2.0 * gsl_rng_uniform(rng) - 1.0); }

/* rf_horizontal_time_at inverts rf_horizontal_length (to 1e-12 of the length): straight
 * paths, parabolas of flight (vertical acceleration), sideways and turning-back
 * accelerations, a start from rest. */
TEST(vegetation_horizontal_time_inverts_length)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 2385);
    const double frac[] = {0.0, 1e-9, 1e-3, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999, 1.0};
    for (int k = 0; k < 2000; k++) {
        rf_vec3 v = rf_v3(uniform_pm(rng, 10.0), uniform_pm(rng, 10.0), uniform_pm(rng, 10.0));
        rf_vec3 a = rf_v3(uniform_pm(rng, 10.0), uniform_pm(rng, 10.0), -9.81);
        switch (k % 5) {
        case 0: /* flight: vertical acceleration only */
            a = rf_v3(0, 0, -9.81);
            break;
        case 1: /* turning back along the line of motion */
            a = rf_v3(-2.0 * v.x, -2.0 * v.y, a.z);
            break;
        case 2: /* from rest */
            v = rf_v3(0, 0, v.z);
            break;
        default:
            break;
        }
        double T = 0.01 + 5.0 * gsl_rng_uniform(rng);
        double L = rf_horizontal_length(v, a, T);
        for (size_t i = 0; i < sizeof frac / sizeof frac[0]; i++) {
            double s = frac[i] * L;
            double t = rf_horizontal_time_at(v, a, s, T);
            ENSURE_MSG(t >= 0.0 && t <= T, "t %.17g outside [0, %.17g]", t, T);
            double err = rf_horizontal_length(v, a, t) - s;
            ENSURE_MSG(fabs(err) <= 1e-12 * fmax(L, 1e-300) + 1e-300,
                       "case %d frac %g: length at t is off by %.3g of %.6g", k, frac[i], err, L);
        }
    }
    /* constant horizontal velocity: s / |v_h| */
    ENSURE_REL(rf_horizontal_time_at(rf_v3(3, 4, 7), rf_v3(0, 0, -9.81), 2.5, 10.0), 0.5, 1e-15);
    ENSURE_REL(rf_horizontal_length(rf_v3(3, 4, 7), rf_v3(0, 0, -9.81), 2.0), 10.0, 1e-15);
    gsl_rng_free(rng);
}

/* Fig. 6b: the contact normal with a vertical stem is horizontal, a unit vector facing
 * the rock (against the motion), head-on at q = 0 and sideways at q = +-1. */
TEST(vegetation_tree_contact_normal)
{
    const rf_vec3 dirs[3] = {rf_v3(3.0, 4.0, 0.0), rf_v3(-1e-3, 2e-4, 0.0), rf_v3(0.0, -7.0, -9.0)};
    for (int i = 0; i < 3; i++) {
        rf_vec3 d = rf_v3_unit(rf_v3(dirs[i].x, dirs[i].y, 0.0));
        for (int k = -10; k <= 10; k++) {
            double q = k / 10.0;
            rf_vec3 n = rf_tree_contact_normal(dirs[i], q);
            ENSURE(n.z == 0.0);
            ENSURE_SMALL(rf_v3_norm(n) - 1.0, 1e-15);
            /* facing the rock: the approach speed along -n is sqrt(1 - q^2) |v_h| */
            ENSURE_SMALL(rf_v3_dot(n, d) + sqrt(1.0 - q * q), 1e-15);
            /* the lateral offset: q across the band */
            ENSURE_SMALL(fabs(n.x * d.y - n.y * d.x) - fabs(q), 1e-15);
        }
        rf_vec3 n0 = rf_tree_contact_normal(dirs[i], 0.0);
        ENSURE_SMALL(n0.x + d.x, 1e-15);
        ENSURE_SMALL(n0.y + d.y, 1e-15);
    }
}

/* ---- the Poisson process through the engines ----------------------------------------- */

/* Flat frictionless ground, a uniform forest of elastic frictionless trees: the mean
 * number of hits per metre is rho0 (phi_r + phi_t), phi_r the rock's diameter (also for
 * the point model), within three standard errors over 2 000 trajectories. */
TEST(vegetation_hits_per_metre_uniform_forest)
{
    rf_forest f = forest(0.05, 10.0, 0.0, 0.2, 1.0, 0.0);
    rf_body point = rf_body_make(1000.0, 2650.0, RF_MODEL_POINT);
    double want = 0.05 * (2.0 * point.radius + 0.2);
    double mean, se;
    hit_rate(&f, 1, point, RF_ENGINE_EXACT, 0.0, 10.0, 2000, &mean, &se, NULL);
    printf("    point: %.5f hits/m (SE %.5f), expected rho0 (phi_r + phi_t) = %.5f\n", mean, se, want);
    ENSURE_MSG(fabs(mean - want) <= 3.0 * se, "%.5f hits/m, expected %.5f, SE %.5f", mean, want, se);
    ENSURE(se < 0.03 * want);
    /* a sliding sphere as well */
    rf_body sph = sphere_of_radius(0.6, RF_MODEL_SPHERE);
    want = 0.05 * (1.2 + 0.2);
    hit_rate(&f, 1, sph, RF_ENGINE_EXACT, 0.0, 10.0, 2000, &mean, &se, NULL);
    printf("    sphere: %.5f hits/m (SE %.5f), expected %.5f\n", mean, se, want);
    ENSURE_MSG(fabs(mean - want) <= 3.0 * se, "%.5f hits/m, expected %.5f, SE %.5f", mean, want, se);
}

/* The distance to the first hit is exponential with the rate of Eq. 12
 * (Kolmogorov-Smirnov, alpha = 0.001). */
TEST(vegetation_first_hit_distance_exponential)
{
    const long n = 2000;
    rf_forest f = forest(0.05, 10.0, 0.0, 0.2, 1.0, 0.0);
    rf_body point = rf_body_make(1000.0, 2650.0, RF_MODEL_POINT);
    double lambda = 0.05 * (2.0 * point.radius + 0.2);
    double *d = malloc((size_t)n * sizeof *d);
    ENSURE(d != NULL);
    double mean, se;
    /* 300 m of path: a trajectory without a hit has probability e^-17 */
    hit_rate(&f, 1, point, RF_ENGINE_EXACT, 0.0, 30.0, n, &mean, &se, d);
    qsort(d, (size_t)n, sizeof *d, rf_cmp_double);
    double D = 0.0, sum = 0.0;
    for (long i = 0; i < n; i++) {
        double F = gsl_cdf_exponential_P(d[i], 1.0 / lambda);
        D = fmax(D, fmax(F - (double)i / (double)n, (double)(i + 1) / (double)n - F));
        sum += d[i];
    }
    double crit = sqrt(-0.5 * log(0.001 / 2.0)) / sqrt((double)n);
    printf("    KS D = %.4f (critical %.4f at alpha 0.001, n %ld); mean %.3f m, 1/rate %.3f m\n",
           D, crit, n, sum / (double)n, 1.0 / lambda);
    ENSURE_MSG(D < crit, "KS statistic %.4f >= %.4f", D, crit);
    /* the same exponential is not mistaken for one 20 %% off */
    double D2 = 0.0;
    for (long i = 0; i < n; i++) {
        double F = gsl_cdf_exponential_P(d[i], 1.2 / lambda);
        D2 = fmax(D2, fmax(F - (double)i / (double)n, (double)(i + 1) / (double)n - F));
    }
    ENSURE_MSG(D2 > crit, "KS against a wrong rate: %.4f <= %.4f", D2, crit);
    free(d);
}

/* sigma > 0: spheres sliding with their centres at three heights h_r = r meet the
 * trees at the rate rho0 Q((h_r - M_ht) / sigma_ht) (phi_r + phi_t) of Eq. 11-12. */
TEST(vegetation_rate_follows_eq11_at_three_heights)
{
    rf_forest f = forest(0.05, 1.0, 0.5, 0.2, 1.0, 0.0);
    const double radii[3] = {0.5, 1.0, 1.5};
    for (int i = 0; i < 3; i++) {
        rf_body b = sphere_of_radius(radii[i], RF_MODEL_SPHERE);
        double want = 0.05 * gsl_cdf_gaussian_Q((b.radius - 1.0) / 0.5, 1.0) * (2.0 * b.radius + 0.2);
        double mean, se;
        hit_rate(&f, 1, b, RF_ENGINE_EXACT, 0.0, 10.0, 2000, &mean, &se, NULL);
        printf("    h_r %.2f m: %.5f hits/m (SE %.5f), Eq. 11-12 %.5f\n", b.radius, mean, se, want);
        ENSURE_MSG(fabs(mean - want) <= 3.0 * se, "h_r %.2f: %.5f hits/m, expected %.5f, SE %.5f",
                   b.radius, mean, want, se);
    }
}

/* A rock whose centre passes above every tree (sigma = 0) is never hit: sliding with
 * its centre above the canopy, or flying over it; just below the canopy it is. */
TEST(vegetation_above_the_trees_never_hit)
{
    rf_forest f = forest(0.2, 1.0, 0.0, 0.2, 1.0, 0.0);
    double mean, se;
    hit_rate(&f, 1, sphere_of_radius(1.01, RF_MODEL_SPHERE), RF_ENGINE_EXACT, 0.0, 10.0, 300,
             &mean, &se, NULL);
    ENSURE(mean == 0.0);
    hit_rate(&f, 1, sphere_of_radius(1.01, RF_MODEL_SPHERE), RF_ENGINE_FIXED_STEP, 0.01, 10.0,
             100, &mean, &se, NULL);
    ENSURE(mean == 0.0);
    hit_rate(&f, 1, sphere_of_radius(0.99, RF_MODEL_SPHERE), RF_ENGINE_EXACT, 0.0, 10.0, 100,
             &mean, &se, NULL);
    ENSURE(mean > 0.0);

    /* flight over a canopy 5 m tall */
    rf_terrain t;
    flat_ground(&t);
    rf_forest tall = forest(0.2, 5.0, 0.0, 0.2, 0.5, 0.3);
    rf_simulation sim = sim_opts(RF_MODEL_SPHERE, RF_ENGINE_EXACT, 4.0);
    vt_runner R;
    runner_init(&R, &t, &sim, &tall, 1, NULL, 0, sphere_of_radius(0.5, RF_MODEL_SPHERE));
    long low = 0;
    for (unsigned long k = 0; k < 200; k++) {
        rf_trajectory_record rec;
        /* up to 25 m at 2 s and back to 5.4 m at 4 s: never below the tops */
        runner_go(&R, k, mt_state(rf_v3(100, 1000, 5.4), rf_v3(30, 0.0, 19.62)), &rec);
        ENSURE(rec.reason == RF_END_MAX_TIME && rec.n_impacts == 0);
        ENSURE(rec.n_tree_hits == 0);
        /* the same flight 1 m lower ends inside the canopy */
        runner_go(&R, k, mt_state(rf_v3(100, 1000, 4.4), rf_v3(30, 0.0, 19.62)), &rec);
        low += rec.n_tree_hits;
    }
    ENSURE(low > 0);
    runner_free(&R);
    rf_terrain_free(&t);
}

/* A forest polygon only affects trajectories that cross it: rocks sliding along lanes
 * that miss it end exactly as without trees; rocks through it are hit inside it only. */
TEST(vegetation_polygon_affects_only_crossing_rocks)
{
    rf_terrain t;
    flat_ground(&t);
    double square[8] = {1040, 1040, 1060, 1040, 1060, 1060, 1040, 1060};
    rf_forest f = forest(0.3, 10.0, 0.0, 0.2, 1.0, 0.0);
    f.polygon.xy = square;
    f.polygon.n = 4;
    rf_simulation sim = sim_opts(RF_MODEL_POINT, RF_ENGINE_EXACT, 10.0);
    rf_body b = rf_body_make(1000.0, 2650.0, RF_MODEL_POINT);
    vt_runner with, without;
    runner_init(&with, &t, &sim, &f, 1, NULL, 0, b);
    runner_init(&without, &t, &sim, NULL, 0, NULL, 0, b);
    with.obs.box[0] = 1040 - 1e-9, with.obs.box[1] = 1040 - 1e-9;
    with.obs.box[2] = 1060 + 1e-9, with.obs.box[3] = 1060 + 1e-9;
    long crossing_hits = 0, crossing = 0, missing = 0;
    for (unsigned long k = 0; k < 400; k++) {
        double y = 1000.0 + 100.0 * ((double)k + 0.5) / 400.0;
        rf_state s0 = mt_state(rf_v3(1000, y, 0.0), rf_v3(10.0, 0.0, 0.0));
        rf_trajectory_record a, c;
        runner_go(&with, k, s0, &a);
        runner_go(&without, k, s0, &c);
        ENSURE(!with.obs.outside);
        if (y < 1040.0 || y > 1060.0) {
            missing++;
            ENSURE(a.n_tree_hits == 0);
            ENSURE(a.stop.x == c.stop.x && a.stop.y == c.stop.y && a.stop.z == c.stop.z);
            ENSURE(a.duration_s == c.duration_s && a.path_length_m == c.path_length_m);
        } else {
            crossing++;
            crossing_hits += a.n_tree_hits;
        }
    }
    /* 20 m of forest at 0.3 (0.9 + 0.2) per metre: about 6.5 hits each */
    ENSURE(missing > 300 && crossing > 70);
    ENSURE_MSG((double)crossing_hits / (double)crossing > 3.0, "%ld hits over %ld crossings",
               crossing_hits, crossing);
    runner_free(&with);
    runner_free(&without);
    rf_terrain_free(&t);
}

/* The fixed-step engine samples the same process: a coarse step (a rock moves 0.5 m a
 * step, with 0.1 expected hits) gives the same hits per metre as the exact engine.
 * (Gaps are drawn in distance: with the same streams both engines meet the same trees.) */
TEST(vegetation_fixed_step_same_rate_as_exact)
{
    rf_forest f = forest(0.2, 10.0, 0.0, 0.2, 1.0, 0.0);
    rf_body b = sphere_of_radius(0.4, RF_MODEL_SPHERE);
    double want = 0.2 * (0.8 + 0.2);
    double me, se_e, mf, se_f;
    hit_rate(&f, 1, b, RF_ENGINE_EXACT, 0.0, 10.0, 2000, &me, &se_e, NULL);
    hit_rate(&f, 1, b, RF_ENGINE_FIXED_STEP, 0.05, 10.0, 2000, &mf, &se_f, NULL);
    printf("    exact %.5f (SE %.5f), fixed step dt 0.05 s %.5f (SE %.5f), expected %.5f hits/m\n",
           me, se_e, mf, se_f, want);
    ENSURE_MSG(fabs(me - want) <= 3.0 * se_e, "exact: %.5f, expected %.5f", me, want);
    ENSURE_MSG(fabs(mf - want) <= 3.0 * se_f, "fixed step: %.5f, expected %.5f", mf, want);
    ENSURE_MSG(fabs(mf - me) <= 3.0 * hypot(se_e, se_f), "fixed step %.5f, exact %.5f", mf, me);
}

/* Kinetic energy never increases at an impact, tree or terrain: spinning spheres
 * bouncing and rolling down a slope and over a ramp through forests with scattered
 * coefficients.  A tree hit leaves the rock where it is, in flight as on the surface. */
TEST(vegetation_tree_impacts_never_add_energy)
{
    rf_terrain t;
    /* a slope, a flat, a ramp that throws the rocks up, a flat */
    const double pts[12] = {0.0, 120.0, 100.0, 40.0, 160.0, 10.0, 200.0, 10.0, 215.0, 14.0,
                            300.0, 14.0};
    ENSURE(rf_scene_profile(&t, pts, 6, 200.0, 0.35, 0.4, 0.1) == 0);
    rf_forest fs[2];
    fs[0] = forest(0.05, 3.0, 1.0, 0.3, 0.5, 0.6);
    fs[0].restitution.sd = 0.4;
    fs[0].friction.sd = 0.5;
    fs[1] = forest(0.03, 1.5, 0.5, 0.1, 0.9, 0.1);
    fs[1].restitution.sd = 0.2;
    fs[1].friction.sd = 1.0;
    for (int engine = 0; engine < 2; engine++) {
        rf_simulation sim = sim_opts(RF_MODEL_SPHERE, engine ? RF_ENGINE_FIXED_STEP : RF_ENGINE_EXACT,
                                     60.0);
        sim.dt = 1e-3;
        vt_runner R;
        runner_init(&R, &t, &sim, fs, 2, NULL, 0, rf_body_make(500.0, 2650.0, RF_MODEL_SPHERE));
        long hits = 0;
        int n = engine ? 40 : 400;
        for (int k = 0; k < n; k++) {
            rf_state s0 = mt_state(rf_v3(5.0, 100.0, 120.0), rf_v3(2.0, 0.5 * (k % 7 - 3), 0.0));
            s0.w = rf_v3(0.3 * (k % 5), -5.0 + k % 11, 2.0 - k % 3);
            rf_trajectory_record rec;
            runner_go(&R, (unsigned long)k, s0, &rec);
            hits += rec.n_tree_hits;
            ENSURE_MSG(R.obs.energy_gain_kj <= 0.0, "engine %d trajectory %d: +%.3g kJ at an impact",
                       engine, k, R.obs.energy_gain_kj);
            if (rec.n_tree_hits > 0)
                ENSURE_MSG(R.obs.tree_energy_lost_min_kj >= -1e-12,
                           "a tree hit gave %.3g kJ", -R.obs.tree_energy_lost_min_kj);
            /* a stem changes the velocity, never the position */
            ENSURE_MSG(R.obs.tree_jump_max <= 1e-6, "engine %d trajectory %d: a tree hit moved "
                       "the rock by %.3g m", engine, k, R.obs.tree_jump_max);
        }
        printf("    %s: %ld tree hits\n", engine ? "fixed step" : "exact", hits);
        ENSURE(hits > (engine ? 20 : 200));
        runner_free(&R);
    }
    rf_terrain_free(&t);
}

/* A tree hit changes the velocity, never the position, in flight as on the surface:
 * rocks hop off a steep step onto a plateau through tall trees; with the fixed step a
 * rock in flight was once put back onto the plane of the face it had last rolled on. */
TEST(vegetation_tree_hit_in_flight_leaves_rock_in_place)
{
    rf_terrain t;
    const double pts[8] = {0.0, 0.0, 100.0, 0.0, 103.0, 3.0, 300.0, 3.0};
    ENSURE(rf_scene_profile(&t, pts, 4, 200.0, 0.35, 0.1, 0.02) == 0);
    double plateau[8] = {100, 0, 300, 0, 300, 200, 100, 200};
    rf_forest f = forest(0.3, 20.0, 0.0, 0.2, 0.3, 0.3);
    f.polygon.xy = plateau;
    f.polygon.n = 4;
    for (int engine = 0; engine < 2; engine++) {
        rf_simulation sim = sim_opts(RF_MODEL_SPHERE, engine ? RF_ENGINE_FIXED_STEP : RF_ENGINE_EXACT,
                                     20.0);
        rf_body b = rf_body_make(500.0, 2650.0, RF_MODEL_SPHERE);
        vt_runner R;
        runner_init(&R, &t, &sim, &f, 1, NULL, 0, b);
        long hits = 0, high = 0;
        for (int k = 0; k < 100; k++) {
            rf_trajectory_record rec;
            runner_go(&R, (unsigned long)k, mt_state(rf_v3(50, 100, b.radius), rf_v3(25, 0, 0)), &rec);
            hits += rec.n_tree_hits;
            high += R.obs.have_first && R.obs.first.p.z > 3.0 + b.radius + 1.0;
            ENSURE_MSG(R.obs.tree_jump_max <= 1e-6, "engine %d trajectory %d: a tree hit moved "
                       "the rock by %.3g m", engine, k, R.obs.tree_jump_max);
        }
        ENSURE(hits > 100 && high > 10);
        runner_free(&R);
    }
    rf_terrain_free(&t);
}

/* Compares fields of two trajectory records bit for bit. */
static int same_record(const rf_trajectory_record *a, const rf_trajectory_record *b)
{
    return !memcmp(&a->stop, &b->stop, sizeof a->stop) && a->reason == b->reason &&
           !memcmp(&a->duration_s, &b->duration_s, sizeof(double)) &&
           !memcmp(&a->path_length_m, &b->path_length_m, sizeof(double)) &&
           !memcmp(&a->max_energy_kj, &b->max_energy_kj, sizeof(double)) &&
           a->n_impacts == b->n_impacts && a->n_tree_hits == b->n_tree_hits;
}

/* A scene without forests keeps its random stream: no forest, a forest of density 0
 * and a forest wholly off the terrain give identical trajectories (random surface
 * coefficients, so any extra draw would show). */
TEST(vegetation_no_forest_random_stream_untouched)
{
    rf_terrain t;
    rf_terrain_spec spec;
    memset(&spec, 0, sizeof spec);
    const double pts[6] = {0.0, 80.0, 100.0, 10.0, 150.0, 0.0};
    spec.source = RF_TERRAIN_PROFILE;
    spec.profile = (double *)pts;
    spec.nprofile = 3;
    spec.width = 100.0;
    spec.up = 'z';
    spec.surface.restitution = (rf_dist){0.3, 0.1};
    spec.surface.friction = (rf_dist){0.4, 0.1};
    spec.surface.rolling = (rf_dist){0.1, 0.05};
    rf_error err;
    ENSURE(rf_terrain_build(&spec, &t, &err) == 0);
    rf_simulation sim = sim_opts(RF_MODEL_SPHERE, RF_ENGINE_EXACT, 60.0);
    rf_body b = rf_body_make(800.0, 2650.0, RF_MODEL_SPHERE);
    rf_forest zero = forest(0.0, 5.0, 1.0, 0.2, 0.2, 0.3);
    double away[8] = {500, 500, 600, 500, 600, 600, 500, 600};
    rf_forest off = forest(0.05, 5.0, 1.0, 0.2, 0.2, 0.3);
    off.polygon.xy = away;
    off.polygon.n = 4;
    rf_forest both[2] = {zero, off};
    vt_runner R0, R1, R2, R3;
    runner_init(&R0, &t, &sim, NULL, 0, NULL, 0, b);
    runner_init(&R1, &t, &sim, &zero, 1, NULL, 0, b);
    runner_init(&R2, &t, &sim, &off, 1, NULL, 0, b);
    runner_init(&R3, &t, &sim, both, 2, NULL, 0, b);
    long impacts = 0;
    for (unsigned long k = 0; k < 200; k++) {
        rf_state s0 = mt_state(rf_v3(3.0, 50.0, 80.0 - 0.7 * 3.0 + 5.0), rf_v3(1.0, 0.0, 0.0));
        rf_trajectory_record a, c1, c2, c3;
        runner_go(&R0, k, s0, &a);
        runner_go(&R1, k, s0, &c1);
        runner_go(&R2, k, s0, &c2);
        runner_go(&R3, k, s0, &c3);
        ENSURE_MSG(same_record(&a, &c1), "trajectory %lu differs with a forest of density 0", k);
        ENSURE_MSG(same_record(&a, &c2), "trajectory %lu differs with a forest off the terrain", k);
        ENSURE_MSG(same_record(&a, &c3), "trajectory %lu differs with both", k);
        impacts += a.n_impacts;
    }
    ENSURE(impacts > 200);
    runner_free(&R0);
    runner_free(&R1);
    runner_free(&R2);
    runner_free(&R3);
    rf_terrain_free(&t);
}

/* ---- a real slope: Fig. 10 ---------------------------------------------------------- */

typedef struct vt_line_stats {
    long n, crossed;
    double mean_x, sd_x, mean_speed, se_speed;
} vt_line_stats;

static vt_line_stats line_stats(const rf_project *p, const rf_forest *fs, size_t nf, long n)
{
    rf_body b = rf_release_body(p, 0, p->sim.model);
    vt_runner R;
    runner_init(&R, &p->terrain, &p->sim, fs, nf, p->measures, p->nmeasures, b);
    vt_line_stats st;
    memset(&st, 0, sizeof st);
    double sx = 0, sx2 = 0, sv = 0, sv2 = 0;
    for (long k = 0; k < n; k++) {
        rf_trajectory_record rec;
        runner_go(&R, (unsigned long)k, rf_release_start(p, 0, &b, R.rng), &rec);
        st.n++;
        if (!R.obs.crossed)
            continue;
        st.crossed++;
        double x = R.obs.crossing.p.x, v = R.obs.crossing.speed_ms;
        sx += x, sx2 += x * x, sv += v, sv2 += v * v;
    }
    double c = (double)st.crossed;
    if (st.crossed > 1) {
        st.mean_x = sx / c;
        st.sd_x = sqrt(fmax(0.0, (sx2 - c * st.mean_x * st.mean_x) / (c - 1.0)));
        st.mean_speed = sv / c;
        st.se_speed = sqrt(fmax(0.0, (sv2 - c * st.mean_speed * st.mean_speed) / (c - 1.0)) / c);
    }
    runner_free(&R);
    return st;
}

/* Writes a project on the Noto terrain (the repository's synthetic DEM) into the test's
 * temporary directory; `extra` is appended (vegetation, ...). */
static void noto_project(const char *name, const char *extra, long count, char *path, size_t cap)
{
    char *terrain = realpath("projects/noto/terrain.asc", NULL);
    ENSURE_MSG(terrain != NULL, "projects/noto/terrain.asc not found");
    snprintf(path, cap, "%s/%s", rf_test_tmpdir(), name);
    FILE *f = fopen(path, "w");
    ENSURE(f != NULL);
    fprintf(f,
            "name: %s\n"
            "seed: 2009\n"
            "terrain:\n"
            "  dem: %s\n"
            "  surface:\n"
            "    restitution: {mean: 0.15, sd: 0.05}\n"
            "    friction: {mean: 0.30, sd: 0.05}\n"
            "rocks:\n"
            "  - {name: r4500, mass: 4500, density: 2650}\n"
            "releases:\n"
            "  - {name: top, point: [170, 204], rock: r4500, count: %ld}\n"
            "measures:\n"
            "  - {name: road, kind: control, line: [[0, 22], [300, 22]]}\n"
            "simulation: {model: sphere, stop_speed: 0.1, max_time: 300, paths: 0}\n"
            "%s",
            name, terrain, count, extra);
    fclose(f);
    free(terrain);
}

static void load(const char *path, rf_project *p)
{
    rf_error err;
    ENSURE_MSG(rf_project_load(path, p, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
}

/* The paper's Fig. 10 on the Noto slope (4 500 kg from Z = 175 m, trees 5 m tall,
 * 0.2 m thick, 0.01 per m^2): at the road's mountainside edge the rocks spread wider
 * along the road and arrive slower with trees than without. */
TEST(vegetation_fig10_spread_wider_speed_lower_with_trees)
{
    char path[600];
    noto_project("fig10.yaml", "", 1, path, sizeof path);
    rf_project p;
    load(path, &p);
    ENSURE(p.nmeasures == 1 && p.measures[0].kind == RF_CONTROL);
    rf_forest f = forest(0.01, 5.0, 0.0, 0.2, 0.2, 0.3);
    f.restitution.sd = 0.05;
    f.friction.sd = 0.05;
    double slope[8] = {0, 25, 300, 25, 300, 200, 0, 200};
    f.polygon.xy = slope;
    f.polygon.n = 4;
    const long n = 600;
    vt_line_stats no = line_stats(&p, NULL, 0, n), yes = line_stats(&p, &f, 1, n);
    printf("    without trees: %ld/%ld reach the road, x %.1f +- %.2f m (sd), speed %.2f m/s (SE %.2f)\n",
           no.crossed, no.n, no.mean_x, no.sd_x, no.mean_speed, no.se_speed);
    printf("    with trees:    %ld/%ld reach the road, x %.1f +- %.2f m (sd), speed %.2f m/s (SE %.2f)\n",
           yes.crossed, yes.n, yes.mean_x, yes.sd_x, yes.mean_speed, yes.se_speed);
    ENSURE(no.crossed >= n / 2 && yes.crossed >= n / 4);
    /* the spread along the road: clearly wider (the sd of an sd is about sd / sqrt(2 n)) */
    ENSURE_MSG(yes.sd_x > 1.5 * no.sd_x, "sd along the road %.2f m with trees, %.2f m without",
               yes.sd_x, no.sd_x);
    /* the speed there: lower by far more than its standard errors */
    ENSURE_MSG(yes.mean_speed + 5.0 * hypot(yes.se_speed, no.se_speed) < no.mean_speed,
               "mean speed %.2f m/s with trees, %.2f m/s without", yes.mean_speed, no.mean_speed);
    rf_project_free(&p);
}

/* ---- a run into the database ---------------------------------------------------------- */

/* A project with two forest zones run by rf_montecarlo_run: every trajectory's
 * n_tree_hits equals its rows in tree_hits, every row lost energy and lies where a
 * forest is. */
TEST(vegetation_run_writes_tree_hits)
{
    char path[600], db[600];
    noto_project("run.yaml",
                 "vegetation:\n"
                 "  - name: upper\n"
                 "    polygon: [[0, 110], [300, 110], [300, 200], [0, 200]]\n"
                 "    density: 0.02\n"
                 "    height: {mean: 5.0, sd: 1.0}\n"
                 "    diameter: 0.25\n"
                 "    restitution: {mean: 0.2, sd: 0.05}\n"
                 "    friction: {mean: 0.3, sd: 0.05}\n"
                 "  - name: lower\n"
                 "    polygon: [[0, 25], [300, 25], [300, 110], [0, 110]]\n"
                 "    density: 0.01\n"
                 "    height: {mean: 8.0, sd: 0}\n"
                 "    diameter: 0.2\n",
                 60, path, sizeof path);
    snprintf(db, sizeof db, "%s/run.db", rf_test_tmpdir());
    rf_project p;
    load(path, &p);
    ENSURE(p.nforests == 2);
    rf_store *s;
    rf_error err;
    ENSURE(rf_store_open(db, &s, &err) == 0);
    rf_run_options o = {.threads = 2};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    ENSURE(sum.n_trajectories == 60);
    rf_store_close(s);
    rf_project_free(&p);

    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM trajectories") == 60);
    long rows = dbt_int(h, "SELECT count(*) FROM tree_hits");
    printf("    %ld tree_hits rows over 60 trajectories\n", rows);
    ENSURE(rows > 0);
    ENSURE(dbt_int(h, "SELECT sum(n_tree_hits) FROM trajectories") == rows);
    ENSURE(dbt_int(h, "SELECT count(*) FROM trajectories t WHERE t.n_tree_hits != "
                         "(SELECT count(*) FROM tree_hits h WHERE h.trajectory_id = t.id)") == 0);
    ENSURE(dbt_int(h, "SELECT count(*) FROM tree_hits h JOIN trajectories t ON "
                         "t.id = h.trajectory_id WHERE h.run_id != t.run_id") == 0);
    /* in a forest, after the start and before the end, energy lost */
    ENSURE(dbt_int(h, "SELECT count(*) FROM tree_hits WHERE y < 25 OR y > 200 OR t_s <= 0") == 0);
    ENSURE(dbt_int(h, "SELECT count(*) FROM tree_hits h JOIN trajectories t ON "
                         "t.id = h.trajectory_id WHERE h.t_s > t.duration_s") == 0);
    ENSURE(dbt_real(h, "SELECT min(energy_lost_kj) FROM tree_hits") >= -1e-9);
    ENSURE(dbt_real(h, "SELECT max(energy_lost_kj) FROM tree_hits") > 0.0);
    ENSURE(dbt_int(h, "SELECT count(*) FROM tree_hits WHERE speed_before_ms <= 0") == 0);
    sqlite3_close(h);
}
