/* test_roughness.c - slope roughness, the random tilt of the contact normal at a bounce
 * (roughness.c, impact.c): the drawn angle follows theta = U1 atan(r_s / R); kinetic
 * energy never rises at an impact, under Eq. 8 and the rt law, with roughness; a
 * project without the new keys and one with their defaults give the same trajectory to
 * the byte; the lateral spread of the stops does not depend on the grid's cell size. */
#include "test.h"

#include <gsl/gsl_rng.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine/roughness.h"
#include "rockfall/project.h"
#include "motion_test_util.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* 10^4 tilts of an impact steep enough that no draw is rejected (|v_t| tan theta_max <
 * |v_n|): the drawn angles against the CDF theta / atan(r_s / R) of the law, by the
 * Kolmogorov-Smirnov distance D (the 1 % critical value 1.63 / sqrt(N)); every tilted
 * normal is a unit vector tilted by acos(cos alpha cos beta) <= theta from n, towards
 * the incoming velocity (braking: its component along d is <= 0). */
TEST(roughness_tilt_angle_follows_u1_atan_rs_over_r)
{
    enum { N = 10000 };
    const double rs = 0.3, R = 0.6, tmax = atan(rs / R);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 7);
    rf_vec3 n = rf_v3_unit(rf_v3(0.3, -0.2, 1.0));
    rf_vec3 d = rf_v3_unit(rf_v3_cross(n, rf_v3(0, 1, 0)));
    rf_vec3 v = rf_v3_add(rf_v3_scale(n, -10.0), rf_v3_scale(d, 2.0));
    static double th[N];
    for (int i = 0; i < N; i++) {
        rf_vec3 nt;
        ENSURE(rf_rough_normal(rng, n, v, rs, R, &nt, &th[i]) == 1);
        ENSURE_SMALL(rf_v3_norm(nt) - 1.0, 1e-14);
        ENSURE(acos(fmin(1.0, rf_v3_dot(nt, n))) <= th[i] + 1e-12);
        ENSURE(rf_v3_dot(nt, d) <= 1e-15);
        ENSURE(rf_v3_dot(v, nt) < 0.0);
    }
    qsort(th, N, sizeof th[0], cmp_double);
    double D = 0.0;
    for (int i = 0; i < N; i++) {
        double F = th[i] / tmax;
        D = fmax(D, fmax(F - (double)i / N, (double)(i + 1) / N - F));
    }
    fprintf(stderr, "roughness KS D = %.5f (N = %d, 1%% critical %.5f)\n", D, N, 1.63 / sqrt(N));
    ENSURE(D < 1.63 / sqrt((double)N));
    ENSURE(th[N - 1] <= tmax);
    /* no tangential velocity: d is drawn, and every tilt faces v */
    rf_vec3 nt;
    ENSURE(rf_rough_normal(rng, n, rf_v3_scale(n, -1.0), rs, R, &nt, NULL) == 1);
    ENSURE(rf_v3_dot(nt, n) < 1.0 && rf_v3_dot(nt, n) >= cos(tmax) - 1e-15);
    gsl_rng_free(rng);
}

/* Over at least 10^4 impacts of rocks thrown onto a rough 35 degree incline (random
 * restitution, friction and R_t; sphere and point mass; Eq. 8 and the rt law) the
 * kinetic energy right after an impact never exceeds that right before it. */
TEST(roughness_energy_never_rises_over_1e4_impacts)
{
    const double th = 35.0 * RF_PI / 180.0;
    for (int law = 0; law < 2; law++) {
        for (int model = 0; model < 2; model++) {
            rf_surface s = {{0.5, 0.25}, {0.5, 0.3}, {0.3, 0.0}, 0.5,
                            law ? RF_IMPACT_RT : RF_IMPACT_EQ8, {0.7, 0.3}};
            rf_terrain t;
            mt_incline(&t, th, 400.0, 400.0, s);
            rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
            long impacts = 0;
            double gain = 0.0;
            for (unsigned long seed = 1; impacts < 10000 && seed < 5000; seed++) {
                rf_state st = mt_incline_state(th, 400.0, 20.0 + (double)(seed % 7), 200.0,
                                               3.0 + (double)(seed % 5),
                                               rf_v3(4.0 + (double)(seed % 9), 0.5 * (double)(seed % 3), -2.0));
                st.w = rf_v3(0.0, (double)(seed % 11) - 5.0, (double)(seed % 4));
                mt_run r;
                mt_simulate_t(&t, md, 800.0, RF_CONTACT_FULL, &st, seed, 60.0, &r);
                ENSURE(!r.nan_seen);
                impacts += (long)r.rec.n_impacts;
                gain = fmax(gain, r.energy_gain_kj);
                mt_run_free(&r);
            }
            fprintf(stderr, "law %d model %d: %ld impacts, largest energy gain %.3g kJ\n", law,
                    model, impacts, gain);
            ENSURE(impacts >= 10000);
            ENSURE(gain <= 1e-9);
            rf_terrain_free(&t);
        }
    }
}

/* The trajectory of a rock on the terrain of project `yaml` (a profile): its path
 * points, written into r. */
static void run_project_terrain(const char *yaml, mt_run *r, rf_surface *zone0)
{
    rf_project p;
    rf_error err = {{0}};
    ENSURE_MSG(rf_project_load_from_memory(yaml, strlen(yaml), "mem/p.yaml", &p, &err) == 0,
               "%s", err.message);
    *zone0 = p.terrain.zones[0].surface;
    double z;
    ENSURE(rf_terrain_height(&p.terrain, 5.0, 20.0, &z) >= 0);
    rf_state s = mt_state(rf_v3(5.0, 20.0, z + 3.0), rf_v3(6.0, 0.7, 0.0));
    mt_simulate(&p.terrain, RF_MODEL_SPHERE, 1500.0, RF_CONTACT_FULL, &s, 11, r);
    rf_project_free(&p);
}

/* The same project without the new keys and with their defaults written out
 * (roughness 0, impact eq8): the same surface and the same trajectory, every path point
 * equal to the byte (no random number drawn for the tilt, Eq. 8 unchanged). */
TEST(roughness_zero_gives_the_same_trajectory_to_the_byte)
{
    static const char *const texts[2] = {
        "name: a\nterrain:\n  profile: {points: [[0, 60], [40, 30], [70, 25], [120, 0]], "
        "width: 40}\n  surface: {restitution: {mean: 0.4, sd: 0.1}, friction: 0.5}\n"
        "rocks:\n  - {name: r, mass: 1500}\n"
        "releases:\n  - {name: A, point: [5, 20], rock: r}\n",
        "name: a\nterrain:\n  profile: {points: [[0, 60], [40, 30], [70, 25], [120, 0]], "
        "width: 40}\n  surface: {restitution: {mean: 0.4, sd: 0.1}, friction: 0.5, "
        "roughness: 0, impact: eq8}\n"
        "rocks:\n  - {name: r, mass: 1500}\n"
        "releases:\n  - {name: A, point: [5, 20], rock: r}\n"};
    mt_run r[2];
    rf_surface s[2];
    for (int i = 0; i < 2; i++)
        run_project_terrain(texts[i], &r[i], &s[i]);
    ENSURE(s[1].roughness == 0.0 && s[1].law == RF_IMPACT_EQ8);
    ENSURE(!memcmp(&s[0].restitution, &s[1].restitution, 3 * sizeof(rf_dist)));
    ENSURE(r[0].n_impacts >= 3 && r[0].npoints == r[1].npoints);
    ENSURE(!memcmp(r[0].points, r[1].points, r[0].npoints * sizeof r[0].points[0]));
    ENSURE(r[0].rec.n_impacts == r[1].rec.n_impacts);
    ENSURE(!memcmp(&r[0].rec.stop, &r[1].rec.stop, sizeof r[0].rec.stop));
    mt_run_free(&r[0]);
    mt_run_free(&r[1]);
}

/* A plane falling along +x at 20 degrees over the grid's nodes (i, j) of cell *(double *)
 * ctx. */
static double rough_plane_z(int i, int j, void *ctx)
{
    (void)j;
    double cell = *(const double *)ctx;
    return (80.0 - i * cell) * tan(20.0 * RF_PI / 180.0);
}

/* The lateral spread that roughness gives does not depend on the cell size of the grid
 * that meshes one planar slope: 300 rocks thrown down a 20 degree plane (roughness 0.3
 * m, 1 t rocks of radius 0.45 m, rolling resistance that stops them on it) meshed at
 * 0.5, 1 and 2 m: the sd of the stops' y differs between any two sizes by less than 3
 * standard errors (se of an sd ~ sd / sqrt(2 (n - 1))).  On the plane the grid's edges
 * meet the rock at no speed, so only real bounces draw a tilt. */
TEST(roughness_lateral_spread_does_not_depend_on_the_cell_size)
{
    enum { NR = 300 };
    const double cells[3] = {0.5, 1.0, 2.0};
    double sd[3], se[3];
    for (int c = 0; c < 3; c++) {
        double cell = cells[c];
        int nx = (int)(80.0 / cell) + 1, ny = (int)(60.0 / cell) + 1;
        rf_surface s = {{0.3, 0.1}, {0.6, 0.0}, {0.9, 0.0}, 0.15, RF_IMPACT_EQ8, {0.0, 0.0}};
        rf_terrain t;
        mt_grid_terrain(&t, 0, nx, ny, cell, rough_plane_z, &cell, s);
        double sum = 0.0, sum2 = 0.0;
        int n = 0;
        for (int k = 0; k < NR; k++) {
            double z;
            ENSURE(rf_terrain_height(&t, 5.0, 30.0, &z) >= 0);
            rf_state st = mt_state(rf_v3(5.0, 30.0, z + 2.5), rf_v3(5.0, 0.0, 0.0));
            mt_run r;
            mt_simulate(&t, RF_MODEL_SPHERE, 1000.0, RF_CONTACT_FULL, &st, 1000 + k, &r);
            if (r.rec.reason == RF_END_REST) {
                double y = r.rec.stop.y - 30.0;
                sum += y, sum2 += y * y, n++;
            }
            mt_run_free(&r);
        }
        ENSURE(n >= NR * 9 / 10);
        double mean = sum / n;
        sd[c] = sqrt((sum2 - n * mean * mean) / (n - 1));
        se[c] = sd[c] / sqrt(2.0 * (n - 1));
        fprintf(stderr, "cell %.1f m: %d stops, lateral sd %.3f m (se %.3f)\n", cell, n, sd[c],
                se[c]);
        rf_terrain_free(&t);
    }
    ENSURE(sd[0] > 0.1);
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            ENSURE(fabs(sd[a] - sd[b]) < 3.0 * hypot(se[a], se[b]));
}
