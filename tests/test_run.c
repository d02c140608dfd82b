/* test_run.c - Monte Carlo runs end to end through the library: determinism across
 * seeds and threads, and the rows a run writes. */
#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "results/store.h"
#include "db_test_util.h"
#include "test.h"

/* Runs the project with `count` trajectories per release into `db`; its summary into
 * *out when out is not NULL. */
static void run_project_summary(const char *yaml, const char *db, long count, int threads,
                                long seed, rf_run_summary *out)
{
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
    for (size_t i = 0; i < p.nreleases; i++)
        p.releases[i].count = count;
    if (seed >= 0)
        p.seed = (uint64_t)seed;
    rf_store *s;
    ENSURE(rf_store_open(db, &s, &err) == 0);
    rf_run_options o = {.threads = threads};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    ENSURE(sum.n_trajectories == count * (long)p.nreleases);
    if (out)
        *out = sum;
    rf_store_close(s);
    rf_project_free(&p);
}

static void run_project(const char *yaml, const char *db, long count, int threads, long seed)
{
    run_project_summary(yaml, db, count, threads, seed, NULL);
}

/* A digest of every value of a query's rows (exact: doubles by their bits). */
static unsigned long long digest(const char *db, const char *sql, long *nrows)
{
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    sqlite3_stmt *st;
    ENSURE_MSG(sqlite3_prepare_v2(h, sql, -1, &st, NULL) == SQLITE_OK, "%s", sqlite3_errmsg(h));
    unsigned long long d = 1469598103934665603ull;
    *nrows = 0;
    while (sqlite3_step(st) == SQLITE_ROW) {
        (*nrows)++;
        for (int c = 0; c < sqlite3_column_count(st); c++) {
            const unsigned char *b;
            int n;
            if (sqlite3_column_type(st, c) == SQLITE_FLOAT) {
                double v = sqlite3_column_double(st, c);
                b = (const unsigned char *)&v;
                n = (int)sizeof v;
                for (int k = 0; k < n; k++)
                    d = (d ^ b[k]) * 1099511628211ull;
            } else {
                b = sqlite3_column_text(st, c);
                n = sqlite3_column_bytes(st, c);
                for (int k = 0; k < n; k++)
                    d = (d ^ b[k]) * 1099511628211ull;
            }
            d = (d ^ 0xff) * 1099511628211ull;
        }
    }
    sqlite3_finalize(st);
    sqlite3_close(h);
    return d;
}

static const char *TRAJ_SQL =
    "SELECT release_id, idx, stop_x, stop_y, stop_z, stop_reason, duration_s, path_length_m, "
    "max_energy_kj, n_impacts, n_tree_hits FROM trajectories ORDER BY release_id, idx";
static const char *HAZARD_SQL =
    "SELECT ix, iy, passes, reach_probability, energy_max_kj, energy_p95_kj, height_p95_m "
    "FROM hazard_cells ORDER BY ix, iy";
static const char *ICPT_SQL =
    "SELECT t.release_id, t.idx, i.measure_id, i.t_s, i.x, i.y, i.z, i.speed_ms, i.energy_kj, "
    "i.energy_trans_kj, i.energy_rot_kj, i.passing_height_m, i.outcome FROM interceptions i "
    "JOIN trajectories t ON t.id = i.trajectory_id ORDER BY t.release_id, t.idx, i.t_s";
static const char *TREE_SQL =
    "SELECT t.release_id, t.idx, h.t_s, h.x, h.y, h.z, h.speed_before_ms, h.speed_after_ms, "
    "h.energy_lost_kj FROM tree_hits h JOIN trajectories t ON t.id = h.trajectory_id "
    "ORDER BY t.release_id, t.idx, h.t_s";
static const char *PATH_SQL =
    "SELECT t.idx, p.seq, p.t_s, p.x, p.y, p.z, p.speed_ms, p.energy_kj FROM path_points p "
    "JOIN trajectories t ON t.id = p.trajectory_id ORDER BY t.idx, p.seq";

TEST(run_same_seed_identical_rows_any_threads)
{
    char a[600], b[600], c[600], d[600];
    snprintf(a, sizeof a, "%s/a.db", rf_test_tmpdir());
    snprintf(b, sizeof b, "%s/b.db", rf_test_tmpdir());
    snprintf(c, sizeof c, "%s/c.db", rf_test_tmpdir());
    snprintf(d, sizeof d, "%s/d.db", rf_test_tmpdir());
    /* 1 200 trajectories: several chunks per thread, finishing out of order */
    run_project("projects/noto/noto-3.2.yaml", a, 240, 1, -1);
    run_project("projects/noto/noto-3.2.yaml", b, 240, 3, -1);
    run_project("projects/noto/noto-3.2.yaml", d, 240, 8, -1);
    run_project("projects/noto/noto-3.2.yaml", c, 60, 1, 77);
    long na, nb, nc;
    unsigned long long da = digest(a, TRAJ_SQL, &na), db = digest(b, TRAJ_SQL, &nb);
    ENSURE(na == 1200 && nb == 1200);
    ENSURE_MSG(da == db, "trajectories differ between 1 and 3 threads");
    ENSURE_MSG(digest(d, TRAJ_SQL, &nb) == da, "trajectories differ between 1 and 8 threads");
    ENSURE(digest(d, HAZARD_SQL, &nb) == digest(a, HAZARD_SQL, &na));
    ENSURE(digest(a, HAZARD_SQL, &na) == digest(b, HAZARD_SQL, &nb));
    ENSURE(na > 0 && na == nb);
    ENSURE(digest(a, PATH_SQL, &na) == digest(b, PATH_SQL, &nb));
    ENSURE(na > 0 && na == nb);
    /* the project has a road control line and a forest: both are sampled identically */
    ENSURE(digest(a, ICPT_SQL, &na) == digest(b, ICPT_SQL, &nb));
    ENSURE(na > 0 && na == nb);
    ENSURE(digest(a, TREE_SQL, &na) == digest(b, TREE_SQL, &nb));
    ENSURE(na > 0 && na == nb);
    ENSURE_MSG(digest(c, TRAJ_SQL, &nc) != da, "another seed gave the same trajectories");
}

/* The summary's engine events are the trajectories' own counters, summed: its impacts
 * are the stored n_impacts, and none depends on the threads. */
TEST(run_summary_counts_the_engine_events_of_its_trajectories)
{
    char a[600], b[600];
    snprintf(a, sizeof a, "%s/ev-a.db", rf_test_tmpdir());
    snprintf(b, sizeof b, "%s/ev-b.db", rf_test_tmpdir());
    rf_run_summary sa, sb;
    run_project_summary("projects/noto/noto-3.2.yaml", a, 100, 1, -1, &sa);
    run_project_summary("projects/noto/noto-3.2.yaml", b, 100, 3, -1, &sb);
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(a, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    double impacts = dbt_real(h, "SELECT SUM(n_impacts) FROM trajectories");
    sqlite3_close(h);
    ENSURE_MSG(sa.events[2] == impacts, "summary %g impacts, stored %g", sa.events[2], impacts);
    ENSURE_MSG(sa.events[0] >= sa.n_trajectories && sa.events[1] > sa.n_trajectories,
               "%g flights, %g segments", sa.events[0], sa.events[1]);
    for (int k = 0; k < 4; k++)
        ENSURE_MSG(sa.events[k] == sb.events[k], "event %d: %g vs %g", k, sa.events[k], sb.events[k]);
}

TEST(run_writes_complete_run_with_paths_and_hazard)
{
    char a[600];
    snprintf(a, sizeof a, "%s/a.db", rf_test_tmpdir());
    run_project("projects/noto/noto-3.1-no-trees.yaml", a, 40, 1, -1);
    run_project("projects/noto/noto-3.1-no-trees.yaml", a, 30, 1, -1);
    sqlite3 *h;
    ENSURE(sqlite3_open(a, &h) == SQLITE_OK);
    sqlite3_stmt *st;
    ENSURE(sqlite3_prepare_v2(h,
                              "SELECT r.id, r.status, r.n_trajectories, "
                              "(SELECT count(*) FROM trajectories t WHERE t.run_id = r.id), "
                              "(SELECT count(DISTINCT trajectory_id) FROM path_points p JOIN "
                              "trajectories t ON t.id = p.trajectory_id WHERE t.run_id = r.id), "
                              "(SELECT sum(passes) FROM hazard_cells h WHERE h.run_id = r.id), "
                              "(SELECT max(reach_probability) FROM hazard_cells h WHERE h.run_id = r.id) "
                              "FROM runs r ORDER BY r.id",
                              -1, &st, NULL) == SQLITE_OK);
    long want[2] = {40, 30};
    for (int k = 0; k < 2; k++) {
        ENSURE(sqlite3_step(st) == SQLITE_ROW);
        ENSURE(!strcmp((const char *)sqlite3_column_text(st, 1), "complete"));
        ENSURE(sqlite3_column_int64(st, 2) == want[k]);
        ENSURE(sqlite3_column_int64(st, 3) == want[k]);
        /* simulation.paths is 100 in the project: every trajectory has its path */
        ENSURE(sqlite3_column_int64(st, 4) == want[k]);
        ENSURE(sqlite3_column_int64(st, 5) > want[k]);
        ENSURE(sqlite3_column_double(st, 6) <= 1.0 && sqlite3_column_double(st, 6) > 0.5);
    }
    ENSURE(sqlite3_step(st) == SQLITE_DONE);
    sqlite3_finalize(st);
    /* a point release has no source cells */
    ENSURE(dbt_int(h, "SELECT count(*) FROM trajectories WHERE source_cell IS NOT NULL") == 0);
    ENSURE(dbt_int(h, "SELECT count(*) FROM releases WHERE n_cells IS NOT NULL") == 0);
    sqlite3_close(h);
}

/* A run that fails while writing keeps whole trajectories only: the failed chunk is
 * rolled back, and n_trajectories counts the rows that reached the file. */
TEST(run_failed_mid_chunk_keeps_whole_trajectories)
{
    char a[600];
    snprintf(a, sizeof a, "%s/fail.db", rf_test_tmpdir());
    run_project("projects/noto/noto-3.1-no-trees.yaml", a, 4, 1, -1);
    sqlite3 *h;
    ENSURE(sqlite3_open(a, &h) == SQLITE_OK);
    /* the 301st trajectory of the next run cannot write its crossing of the road */
    ENSURE(sqlite3_exec(h,
                        "CREATE TRIGGER boom BEFORE INSERT ON interceptions WHEN "
                        "NEW.trajectory_id > (SELECT max(id) FROM trajectories WHERE run_id = 1) "
                        "+ 300 BEGIN SELECT RAISE(ABORT, 'no room'); END",
                        NULL, NULL, NULL) == SQLITE_OK);
    sqlite3_close(h);
    rf_project p;
    rf_error err;
    ENSURE(rf_project_load("projects/noto/noto-3.1-no-trees.yaml", &p, &err) == 0);
    ENSURE(p.nreleases == 1);
    p.releases[0].count = 600;
    rf_store *s;
    ENSURE(rf_store_open(a, &s, &err) == 0);
    rf_run_options o = {.threads = 2};
    rf_run_summary sum;
    ENSURE(rf_montecarlo_run(&p, s, &o, &sum, &err) != 0);
    ENSURE_MSG(strstr(err.message, "no room"), "%s", err.message);
    rf_store_close(s);
    rf_project_free(&p);
    ENSURE(sqlite3_open(a, &h) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT status = 'failed' FROM runs WHERE id = 2") == 1);
    long n = (long)dbt_int(h, "SELECT n_trajectories FROM runs WHERE id = 2");
    long rows = (long)dbt_int(h, "SELECT count(*) FROM trajectories WHERE run_id = 2");
    ENSURE_MSG(n == rows && rows > 0 && rows <= 300, "n_trajectories %ld, rows %ld", n, rows);
    /* every rock of this project crosses the road: none kept without its crossing */
    long long bare = dbt_int(h, "SELECT count(*) FROM trajectories t WHERE run_id = 2 AND NOT "
                                "EXISTS (SELECT 1 FROM interceptions i WHERE i.trajectory_id = "
                                "t.id)");
    ENSURE_MSG(bare == 0, "%lld trajectories without their crossing", bare);
    sqlite3_close(h);
}

/* Cells passed by more trajectories than their summary keeps exactly (binned) give the
 * same rows with 1 and 4 threads: the summary depends on the values, not on which
 * thread saw which.  4 400 trajectories are 18 chunks: the ring of chunks in flight (4
 * slots a thread) goes round more than once with either. */
TEST(run_hazard_rows_identical_1_and_4_threads_past_the_exact_limit)
{
    char a[600], b[600];
    snprintf(a, sizeof a, "%s/h1.db", rf_test_tmpdir());
    snprintf(b, sizeof b, "%s/h4.db", rf_test_tmpdir());
    run_project("projects/noto/noto-3.1-no-trees.yaml", a, 4400, 1, -1);
    run_project("projects/noto/noto-3.1-no-trees.yaml", b, 4400, 4, -1);
    long na, nb;
    ENSURE(digest(a, HAZARD_SQL, &na) == digest(b, HAZARD_SQL, &nb));
    ENSURE(na > 0 && na == nb);
    ENSURE(digest(a, TRAJ_SQL, &na) == digest(b, TRAJ_SQL, &nb));
    ENSURE(na == 4400 && nb == 4400);
    ENSURE(digest(a, ICPT_SQL, &na) == digest(b, ICPT_SQL, &nb));
    sqlite3 *h;
    ENSURE(sqlite3_open(a, &h) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM hazard_cells WHERE passes > 128") > 10);
    sqlite3_close(h);
}

/* ---- releases as a planner draws them ------------------------------------------ */

static void load_or_fail(const char *path, rf_project *p)
{
    rf_error err;
    ENSURE_MSG(rf_project_load(path, p, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
}

/* Starts of the L-shaped area (three 18 m squares) fall uniformly on it: 12 000 draws
 * (the run's own streams) into its twelve 9 m quarter squares, chi-square with 11
 * degrees of freedom below 31.26 (significance 0.001); every start inside the L. */
TEST(run_area_release_starts_uniform_over_a_concave_polygon)
{
    rf_project p;
    load_or_fail("tests/data/project/release_area.yaml", &p);
    ENSURE(p.releases[0].source == RF_SOURCE_AREA && p.releases[0].ntri == 4);
    ENSURE_SMALL(p.releases[0].area_cum[p.releases[0].ntri - 1] - 972.0, 1e-9);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    long n[12] = {0}, N = 12000;
    for (long k = 0; k < N; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
        double m;
        rf_body b = rf_release_draw_body(&p, 0, RF_MODEL_POINT, rng, &m);
        rf_state s = rf_release_start_of(&p, 0, k, &b, rng);
        double x = s.p.x - 2.0, y = s.p.y - 2.0;
        ENSURE_MSG(x >= 0 && y >= 0 && x <= 36 && y <= 36 && (x <= 18 || y <= 18),
                   "start (%g, %g) outside the L", s.p.x, s.p.y);
        int i = (int)fmin(floor(x / 9.0), 3.0), j = (int)fmin(floor(y / 9.0), 3.0);
        int cell = j < 2 ? j * 4 + i : 8 + (j - 2) * 2 + i; /* top arm: i in 0..1 */
        ENSURE(cell >= 0 && cell < 12 && (j < 2 || i < 2));
        n[cell]++;
    }
    double chi2 = 0.0, e = (double)N / 12.0;
    for (int c = 0; c < 12; c++)
        chi2 += (n[c] - e) * (n[c] - e) / e;
    printf("    area: chi-square %.2f (11 dof, 0.001 critical 31.26)\n", chi2);
    ENSURE_MSG(chi2 < 31.26, "chi-square %g", chi2);
    gsl_rng_free(rng);
    rf_project_free(&p);
}

/* Log-normal masses {mean 1000, sd 500}: 40 000 draws have a sample mean within 2 %
 * and a sample sd within 5 % of them; list masses [100, 200, 500, 1000] are drawn
 * uniformly: 8 000 draws, chi-square with 3 degrees of freedom below 16.27
 * (significance 0.001), and nothing else drawn. */
TEST(run_masses_drawn_log_normal_and_from_a_list)
{
    rf_project p;
    load_or_fail("tests/data/project/release_area.yaml", &p);
    ENSURE(p.rocks[0].mass_kind == RF_MASS_LOGNORMAL && p.rocks[1].mass_kind == RF_MASS_LIST);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    double s1 = 0.0, s2 = 0.0;
    long N = 40000;
    for (long k = 0; k < N; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
        double m = rf_release_mass(&p, 0, rng);
        s1 += m;
        s2 += m * m;
    }
    double mean = s1 / N, sd = sqrt((s2 - s1 * s1 / N) / (N - 1));
    printf("    log-normal: mean %.1f sd %.1f (given 1000, 500)\n", mean, sd);
    ENSURE_REL(mean, 1000.0, 0.02);
    ENSURE_REL(sd, 500.0, 0.05);
    long n[4] = {0}, M = 8000;
    const double masses[4] = {100, 200, 500, 1000};
    for (long k = 0; k < M; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 1, k));
        double m = rf_release_mass(&p, 1, rng);
        int hit = 0;
        for (int i = 0; i < 4; i++)
            if (m == masses[i])
                n[i]++, hit = 1;
        ENSURE(hit);
    }
    double chi2 = 0.0, e = M / 4.0;
    for (int i = 0; i < 4; i++)
        chi2 += (n[i] - e) * (n[i] - e) / e;
    printf("    list: chi-square %.2f (3 dof, 0.001 critical 16.27)\n", chi2);
    ENSURE_MSG(chi2 < 16.27, "chi-square %g", chi2);
    gsl_rng_free(rng);
    rf_project_free(&p);
}

/* A log-normal mass is truncated to the masses a rock may have: with mean 5e8 kg and
 * sd 5e9 kg about 8 % of the log-normal lies above the 1e9 kg bound; every drawn mass
 * stays within it. */
TEST(run_log_normal_masses_stay_within_the_rock_bounds)
{
    rf_project p;
    load_or_fail("tests/data/project/release_area.yaml", &p);
    p.rocks[0].mass = 5e8;
    p.rocks[0].mass_sd = 5e9;
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    double sigma2 = log1p(100.0), mu = log(5e8) - 0.5 * sigma2;
    long above = 0, N = 20000;
    double lo = 4.0 / 3.0 * M_PI * p.rocks[0].density * 1e-9, top = 0.0, bottom = INFINITY;
    for (long k = 0; k < N; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
        above += gsl_ran_lognormal(rng, mu, sqrt(sigma2)) > 1e9; /* the stream's first draw */
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
        double m = rf_release_mass(&p, 0, rng);
        top = fmax(top, m);
        bottom = fmin(bottom, m);
    }
    printf("    %ld of %ld first draws above 1e9 kg; drawn masses %.3g to %.3g kg\n", above, N,
           bottom, top);
    ENSURE(above > N / 20);
    ENSURE(top <= 1e9 && bottom >= lo);
    gsl_rng_free(rng);
    rf_project_free(&p);
}

/* A cells mask with three source cells and count 3 runs nine trajectories, three per
 * cell in the mask's order, each starting inside its cell; the stored mass and start
 * are exactly those the run's stream gives the engine. */
TEST(run_cells_release_count_per_cell_and_stored_starts)
{
    char db[600];
    snprintf(db, sizeof db, "%s/cells.db", rf_test_tmpdir());
    rf_project p;
    rf_error err;
    load_or_fail("tests/data/project/release_cells.yaml", &p);
    ENSURE(p.releases[0].source == RF_SOURCE_CELLS && p.releases[0].ncells == 3);
    ENSURE(rf_release_trajectories(&p.releases[0]) == 9);
    rf_store *s;
    ENSURE(rf_store_open(db, &s, &err) == 0);
    rf_run_options o = {.threads = 2};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    ENSURE(sum.n_trajectories == 9);
    rf_store_close(s);
    static const double centre[3][2] = {{10, 10}, {30, 20}, {10, 30}};
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    sqlite3_stmt *st;
    /* the release's cells, each trajectory's cell (idx / count, in the mask's order) */
    ENSURE(dbt_int(h, "SELECT n_cells FROM releases") == 3);
    ENSURE(sqlite3_prepare_v2(h, "SELECT idx, mass_kg, start_x, start_y, start_z, source_cell "
                                 "FROM trajectories ORDER BY idx", -1, &st, NULL) == SQLITE_OK);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    long rows = 0;
    while (sqlite3_step(st) == SQLITE_ROW) {
        long idx = sqlite3_column_int64(st, 0);
        const double *c = centre[idx / 3];
        double x = sqlite3_column_double(st, 2), y = sqlite3_column_double(st, 3);
        ENSURE_MSG(fabs(x - c[0]) <= 5.0 && fabs(y - c[1]) <= 5.0,
                   "trajectory %ld starts at (%g, %g), outside its cell", idx, x, y);
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, idx));
        double m;
        rf_body b = rf_release_draw_body(&p, 0, p.sim.model, rng, &m);
        rf_state s0 = rf_release_start_of(&p, 0, idx, &b, rng);
        ENSURE(sqlite3_column_double(st, 1) == m && x == s0.p.x && y == s0.p.y &&
               sqlite3_column_double(st, 4) == s0.p.z);
        ENSURE(sqlite3_column_type(st, 5) == SQLITE_INTEGER &&
               sqlite3_column_int64(st, 5) == idx / 3);
        rows++;
    }
    ENSURE(rows == 9);
    sqlite3_finalize(st);
    sqlite3_close(h);
    gsl_rng_free(rng);
    rf_project_free(&p);
}
