/* test_calibrate.c - `rockfall calibrate` (run/calibrate.c): the Wasserstein-1 distance
 * by hand; keys parsed, refused and applied; the objective a deterministic function of
 * the values whatever the threads; values known on a synthetic slope fitted back; the
 * command line's YAML and the fit stored in the database. */
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/stats.h"
#include "rockfall/project.h"
#include "run/calibrate.h"
#include "db_test_util.h"

/* A point mass bouncing down a 45-degree slope of 100 m onto a long flat: its runout
 * follows the restitution and the friction at the impacts, its lateral spread the
 * roughness (the point mass has no rolling cap: the friction acts at every impact). */
#define SLOPE_PROJECT(seed, e, mu, rs, count)                                             \
    "name: synthetic\n"                                                                 \
    "seed: " seed "\n"                                                                  \
    "terrain:\n"                                                                        \
    "  profile: {points: [[0, 100], [100, 0], [600, 0]], width: 600}\n"                 \
    "  surface: {restitution: {mean: " e ", sd: 0.05}, friction: {mean: " mu            \
    ", sd: 0.05}, rolling: {mean: 0.6, sd: 0.05}, roughness: " rs "}\n"                 \
    "rocks:\n"                                                                          \
    "  - {name: r, mass: {mean: 500, sd: 200}}\n"                                       \
    "releases:\n"                                                                       \
    "  - {name: top, point: [2, 300], rock: r, count: " count ", height: 3}\n"          \
    "simulation: {model: point, stop_speed: 0.1, max_time: 120}\n"                      \
    "hazard: {cell: 5}\n"

static void load(const char *text, rf_project *p)
{
    rf_error err;
    int rc = rf_project_load_from_memory(text, strlen(text), "mem.yaml", p, &err);
    ENSURE_MSG(rc == 0, "%s:%d:%d: %s", err.file, err.line, err.column, err.message);
}

TEST(calibrate_w1_distance_by_hand)
{
    const double a[] = {0.0, 1.0}, b[] = {0.5, 1.5}, c[] = {0.0, 0.0, 3.0};
    /* equal samples: 0; a shift by s moves every value by s: W1 = s */
    ENSURE_SMALL(rf_w1_distance(a, 2, a, 2), 1e-15);
    ENSURE_SMALL(rf_w1_distance(a, 2, b, 2) - 0.5, 1e-15);
    ENSURE_SMALL(rf_w1_distance(b, 2, a, 2) - 0.5, 1e-15);
    /* F_a - F_c: 1/2 - 2/3 on [0, 1), 1 - 2/3 on [1, 3): 1/6 + 2/3 */
    ENSURE_SMALL(rf_w1_distance(a, 2, c, 3) - (1.0 / 6.0 + 2.0 / 3.0), 1e-15);
}

/* The lateral KS distance and the robust sigma of rf_agreement_compute: stops along
 * +x from the origin, the measured ones at lateral offsets -2, -1, 1, 2 (their mean
 * direction +x; IQR by type 7: 1.25 - (-1.25) = 2.5), the simulated ones shifted by
 * 10 m sideways: KS 1, W1 10 m. */
TEST(calibrate_agreement_lateral_measures_by_hand)
{
    const double meas[] = {10, -2, 20, -1, 30, 1, 40, 2};
    double sim[8];
    memcpy(sim, meas, sizeof sim);
    for (int i = 0; i < 4; i++)
        sim[2 * i + 1] += 10.0;
    rf_agreement a;
    ENSURE(rf_agreement_compute(meas, 4, meas, 4, 0.0, 0.0, &a) == 0);
    ENSURE_SMALL(a.ks_lateral, 1e-15);
    ENSURE_SMALL(a.w1_lateral, 1e-15);
    ENSURE(rf_agreement_compute(meas, 4, sim, 4, 0.0, 0.0, &a) == 0);
    ENSURE_SMALL(a.ks_lateral - 1.0, 1e-15);
    ENSURE_SMALL(a.w1_lateral - 10.0, 1e-12);
    ENSURE_SMALL(a.lateral_rsigma_meas - 2.5 / 1.349, 1e-12);
    ENSURE_SMALL(a.lateral_rsigma_sim - 2.5 / 1.349, 1e-12);
}

TEST(calibrate_keys_are_parsed_refused_and_applied)
{
    static const char text[] =
        "name: keys\n"
        "terrain:\n"
        "  profile: {points: [[0, 30], [60, 0], [100, 0]], width: 40}\n"
        "  surface: {restitution: 0.3, friction: 0.5}\n"
        "  zones:\n"
        "    - {name: upper, polygon: [[0, 0], [30, 0], [30, 40], [0, 40]], rolling: 0.2}\n"
        "    - {name: lower, polygon: [[30, 0], [100, 0], [100, 40], [30, 40]],\n"
        "       impact: rt, tangential: 0.6}\n"
        "rocks: [{name: r, mass: 500}]\n"
        "releases: [{name: a, point: [2, 20], rock: r, count: 3}]\n";
    rf_project p;
    load(text, &p);
    rf_error err;
    rf_fit_key k;
    ENSURE(rf_fit_key_parse(&p, "zones.upper.rolling", &k, &err) == 0);
    ENSURE(k.field == RF_FIT_ROLLING && k.zone >= 0 && rf_fit_key_get(&p, &k) == 0.2);
    /* one value for two zones */
    ENSURE(rf_fit_key_parse(&p, "zones.upper+lower.restitution", &k, &err) == 0);
    rf_fit_key_set(&p, &k, 0.42);
    size_t set = 0;
    for (size_t z = 0; z < p.terrain.nzones; z++)
        set += p.terrain.zones[z].surface.restitution.mean == 0.42;
    ENSURE(set == 2);
    /* the friction of a zone without its own rolling resistance moves it too */
    ENSURE(rf_fit_key_parse(&p, "zones.lower.friction", &k, &err) == 0);
    rf_fit_key_set(&p, &k, 0.9);
    for (size_t z = 0; z < p.terrain.nzones; z++)
        if (!strcmp(p.terrain.zones[z].name, "lower"))
            ENSURE(p.terrain.zones[z].surface.rolling.mean == 0.9);
        else if (!strcmp(p.terrain.zones[z].name, "upper"))
            ENSURE(p.terrain.zones[z].surface.rolling.mean == 0.2);
    /* values are clamped to their bounds */
    ENSURE(rf_fit_key_parse(&p, "surface.roughness", &k, &err) == 0);
    rf_fit_key_set(&p, &k, -3.0);
    ENSURE(rf_fit_key_get(&p, &k) == 0.0);
    static const struct {
        const char *key, *msg;
    } bad[] = {
        {"zones.middle.friction", "no zone 'middle'"},
        {"zones.upper.hardness", "FIELD is one of"},
        {"restitution", "a key is surface.FIELD"},
        {"terrain.restitution", "a key is surface.FIELD"},
        {"zones.upper.tangential", "impact law is eq8"},
        {"zones.lower.rolling", "no rolling resistance of its own"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        ENSURE_MSG(rf_fit_key_parse(&p, bad[i].key, &k, &err) != 0, "%s accepted", bad[i].key);
        ENSURE_MSG(strstr(err.message, bad[i].msg), "%s: %s", bad[i].key, err.message);
    }
    rf_project_free(&p);
}

/* The same values give the same objective, with 1 or 3 threads: every trajectory
 * draws from its own stream (common random numbers). */
TEST(calibrate_objective_is_deterministic_whatever_the_threads)
{
    rf_project p;
    load(SLOPE_PROJECT("7", "0.35", "0.4", "0.1", "60"), &p);
    double *obs, *start;
    long n = rf_stops_simulate(&p, 1, &obs, &start, NULL);
    ENSURE(n == 60);
    rf_project q;
    load(SLOPE_PROJECT("11", "0.3", "0.5", "0.05", "60"), &q);
    double o1, o3, o1b;
    rf_agreement a1, a3;
    ENSURE(rf_calibrate_objective(&q, obs, 60, 1, RF_OBJECTIVE_W1, &o1, &a1, NULL) == 0);
    ENSURE(rf_calibrate_objective(&q, obs, 60, 3, RF_OBJECTIVE_W1, &o3, &a3, NULL) == 0);
    ENSURE(rf_calibrate_objective(&q, obs, 60, 1, RF_OBJECTIVE_W1, &o1b, &a1, NULL) == 0);
    ENSURE(o1 == o3 && o1 == o1b && o1 > 0.0);
    ENSURE(a1.ks == a3.ks && a1.w1_runout == a3.w1_runout);
    free(obs);
    free(start);
    rf_project_free(&q);
    rf_project_free(&p);
}

/* Fits `nkeys` of restitution, friction and roughness (in that order, from `first`)
 * to the stops of the truth, 0.35 / 0.4 / 0.05 m (600 rocks, seed 7), from the start
 * values 0.15 / 0.8 / 0.02 with other random numbers (seed 11, 300 rocks per
 * simulation); the keys not fitted stay at the truth. */
static void fit_synthetic(int first, int nkeys, double *value)
{
    rf_project truth;
    load(SLOPE_PROJECT("7", "0.35", "0.4", "0.05", "600"), &truth);
    double *obs, *start;
    size_t not_rest = 0;
    long n = rf_stops_simulate(&truth, 2, &obs, &start, &not_rest);
    ENSURE(n == 600 && not_rest == 0);
    rf_project p;
    if (first == 0)
        load(SLOPE_PROJECT("11", "0.15", "0.4", "0.05", "300"), &p);
    else
        load(SLOPE_PROJECT("11", "0.35", "0.8", "0.02", "300"), &p);
    const char *paths[3] = {"surface.restitution", "surface.friction", "surface.roughness"};
    const double from[3] = {0.15, 0.8, 0.02};
    rf_fit_key keys[3];
    rf_error err;
    for (int i = 0; i < nkeys; i++)
        ENSURE(rf_fit_key_parse(&p, paths[first + i], &keys[i], &err) == 0);
    rf_calibrate_options o = {RF_OBJECTIVE_W1, 2, 300, 10 * nkeys, 0.02, NULL};
    rf_calibration c;
    ENSURE(rf_calibrate(&p, obs, (size_t)n, keys, (size_t)nkeys, &o, &c, &err) == 0);
    ENSURE(c.n_evals <= 300 + 2 * nkeys + 2 && c.n_trajectories == 300);
    for (int i = 0; i < nkeys; i++) {
        ENSURE(c.start[i] == from[first + i]);
        /* the project is left at the fitted values */
        ENSURE(rf_fit_key_get(&p, &keys[i]) == c.value[i]);
        value[i] = c.value[i];
    }
    rf_calibration_free(&c);
    free(obs);
    free(start);
    rf_project_free(&p);
    rf_project_free(&truth);
}

/* The restitution alone, within 0.05 of the truth. */
TEST(calibrate_recovers_a_known_restitution_on_a_synthetic_slope)
{
    double v[1];
    fit_synthetic(0, 1, v);
    ENSURE_MSG(fabs(v[0] - 0.35) < 0.05, "fitted %g", v[0]);
}

/* Friction and roughness together, within 0.05 and 0.02 m of the truth.  (Restitution
 * and roughness fitted together trade off on this slope - both brake the bounces: with
 * these samples the three values come back as about 0.23-0.30 / 0.40 / 0.055-0.065,
 * the objective at the fit below its value at the truth; docs/calibration.md.) */
TEST(calibrate_recovers_known_friction_and_roughness_on_a_synthetic_slope)
{
    double v[2];
    fit_synthetic(1, 2, v);
    ENSURE_MSG(fabs(v[0] - 0.4) < 0.05 && fabs(v[1] - 0.05) < 0.02, "fitted %g %g", v[0], v[1]);
}

/* The command: its YAML, pasted into the project, loads and gives the fitted values;
 * -o stores the fit; bad arguments are refused. */
TEST(calibrate_command_prints_yaml_and_stores_the_fit)
{
    rf_project truth;
    load(SLOPE_PROJECT("7", "0.35", "0.4", "0.1", "200"), &truth);
    double *obs, *start;
    long n = rf_stops_simulate(&truth, 1, &obs, &start, NULL);
    ENSURE(n == 200);
    FILE *f = fopen(rf_test_path("stops.txt"), "w");
    ENSURE(f);
    fprintf(f, "# observed\n");
    for (long i = 0; i < n; i++)
        fprintf(f, "%.6f %.6f 0.0\n", obs[2 * i], obs[2 * i + 1]);
    fclose(f);
    free(obs);
    free(start);
    rf_project_free(&truth);
    char proj[4096], db[4096], stops[4096];
    snprintf(proj, sizeof proj, "%s",
             rf_test_write("fit.yaml", SLOPE_PROJECT("11", "0.2", "0.4", "0.1", "100")));
    snprintf(db, sizeof db, "%s", rf_test_path("fit.db"));
    snprintf(stops, sizeof stops, "%s", rf_test_path("stops.txt"));
    char args[16384], out[16384];
    snprintf(args, sizeof args,
             "calibrate %s --observed %s --fit surface.restitution --max-evals 40 -q -o %s", proj,
             stops, db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    ENSURE_MSG(strstr(out, "terrain:\n  surface: {restitution: "), "%s", out);
    double e = -1.0;
    ENSURE(sscanf(strstr(out, "{restitution: ") + 14, "%lf", &e) == 1 && e >= 0.0 && e <= 1.0);
    sqlite3 *h = NULL;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM calibrations") == 1);
    ENSURE(dbt_int(h, "SELECT n_observed FROM calibrations") == 200);
    ENSURE(dbt_int(h, "SELECT n_trajectories FROM calibrations") == 100);
    ENSURE(dbt_int(h, "SELECT n_simulations BETWEEN 2 AND 40 FROM calibrations") == 1);
    ENSURE(dbt_int(h, "SELECT count(*) FROM calibration_values WHERE key = "
                      "'surface.restitution' AND start = 0.2") == 1);
    ENSURE(fabs(dbt_real(h, "SELECT value FROM calibration_values") - e) < 1e-3);
    sqlite3_close(h);

    static const struct {
        const char *args, *msg;
    } bad[] = {
        {"calibrate %s --fit surface.restitution", "--observed STOPS is required"},
        {"calibrate %s --observed x.txt", "at least one --fit KEY"},
        {"calibrate %s --observed %s --fit zones.none.friction", "no zone 'none'"},
        {"calibrate %s --observed %s --fit surface.restitution --objective l2", "w1 or ks"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        snprintf(args, sizeof args, bad[i].args, proj, stops);
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s", args);
        ENSURE_MSG(strstr(out, bad[i].msg), "%s: %s", args, out);
    }
}
