/* test_run.c - Monte Carlo runs end to end through the library: determinism across
 * seeds and threads, and the rows a run writes. */
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "results/store.h"
#include "db_test_util.h"
#include "test.h"

/* Runs the project with `count` trajectories per release into `db`. */
static void run_project(const char *yaml, const char *db, long count, int threads, long seed)
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
    rf_store_close(s);
    rf_project_free(&p);
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
