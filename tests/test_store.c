/* test_store.c - the results database: schema, runs, reopening, rejection of foreign
 * files, and a writer killed in the middle of a run. */
#include "db_test_util.h"
#include "test.h"

#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "rockfall/records.h"
#include "rockfall/version.h"
#include "input/measure_kinds.h"
#include "results/gpkg.h"
#include "results/schema.h"
#include "results/store.h"

#define RF_STR_(x) #x
#define RF_STR(x) RF_STR_(x)

/* ---- a small project, built by hand ------------------------------------------- */

typedef struct test_project {
    rf_project p;
    rf_rock rocks[1];
    rf_release releases[2];
    rf_measure measures[3];
    double lines[3][6];
} test_project;

static void make_project(test_project *t)
{
    memset(t, 0, sizeof *t);
    t->p.name = "store-test-slope";
    t->p.path = "projects/store-test/slope.yaml";
    t->p.yaml_text = "name: store-test-slope\nseed: 2009\n";
    t->p.seed = 2009;

    t->rocks[0] = (rf_rock){.name = "r4500", .mass = 4500.0, .density = 2650.0,
                            .action_level = 2, .radius = 0.7403};
    t->p.rocks = t->rocks;
    t->p.nrocks = 1;

    t->releases[0] = (rf_release){.name = "C", .x = 12.25, .y = 48.5, .z = 131.875,
                                  .rock = 0, .count = 5};
    t->releases[1] = (rf_release){.name = "D", .x = 17.75, .y = 52.125, .z = 129.5, .rock = 0,
                                  .count = 5, .height = 1.5, .velocity = {0.25, -1.5, 0.0},
                                  .jitter = 2.385};
    t->p.releases = t->releases;
    t->p.nreleases = 2;

    static const double xy[3][6] = {
        {0.0, 10.0, 20.0, 10.5, 40.0, 11.0},
        {0.0, 30.0, 40.0, 30.25, 0, 0},
        {0.0, 60.0, 40.0, 60.1, 0, 0},
    };
    memcpy(t->lines, xy, sizeof xy);
    t->measures[0] = (rf_measure){.name = "road", .kind = RF_CONTROL, .height = 0.0,
                                  .importance = RF_IMPORTANT, .behaviour = RF_COLLECT,
                                  .capacity = {-1, -1, -1, -1}};
    t->measures[0].line = (rf_polyline){t->lines[0], 3};
    t->measures[1] = (rf_measure){.name = "E1", .kind = RF_EMBANKMENT, .height = 6.0,
                                  .importance = RF_MOST_IMPORTANT, .behaviour = RF_STOP,
                                  .capacity = {3000, 6000, 9000, -1}};
    t->measures[1].line = (rf_polyline){t->lines[1], 2};
    t->measures[2] = (rf_measure){.name = "B1", .kind = RF_BARRIER, .height = 5.0,
                                  .importance = RF_USUAL, .behaviour = RF_STOP,
                                  .mel = 3000, .sel = 1000,
                                  .capacity = {1000, -1, 3000, -1}};
    t->measures[2].line = (rf_polyline){t->lines[2], 2};
    t->p.measures = t->measures;
    t->p.nmeasures = 3;
}

/* ---- helpers -------------------------------------------------------------------- */

static rf_store *open_store(const char *path)
{
    rf_store *s = NULL;
    rf_error err = {0};
    int rc = rf_store_open(path, &s, &err);
    ENSURE_MSG(rc == 0 && s, "rf_store_open(%s): %s", path, err.message);
    return s;
}

static sqlite3 *open_raw(const char *path)
{
    sqlite3 *db = NULL;
    ENSURE(sqlite3_open_v2(path, &db, SQLITE_OPEN_READWRITE, NULL) == SQLITE_OK);
    sqlite3_busy_timeout(db, 10000);
    return db;
}

static void exec_raw(sqlite3 *db, const char *sql)
{
    char *msg = NULL;
    int rc = sqlite3_exec(db, sql, NULL, NULL, &msg);
    ENSURE_MSG(rc == SQLITE_OK, "%s: %s", sql, msg ? msg : "?");
}

/* Rows of a table that belong to run `run`. */
static int64_t run_rows(sqlite3 *db, const char *table, long long run)
{
    return dbt_int(db, "SELECT count(*) FROM %s WHERE run_id = %lld", table, run);
}

/* Every row of a query as text, columns joined by '|', rows by '\n' (malloc'd). */
static char *dump(sqlite3 *db, const char *sql)
{
    sqlite3_stmt *st = NULL;
    ENSURE_MSG(sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK, "%s: %s", sql,
               sqlite3_errmsg(db));
    size_t cap = 1024, len = 0;
    char *out = malloc(cap);
    ENSURE(out);
    out[0] = '\0';
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        for (int c = 0; c < sqlite3_column_count(st); c++) {
            char cell[64];
            const char *v;
            if (sqlite3_column_type(st, c) == SQLITE_FLOAT) {
                snprintf(cell, sizeof cell, "%.17g", sqlite3_column_double(st, c));
                v = cell;
            } else {
                v = (const char *)sqlite3_column_text(st, c);
                if (!v)
                    v = "NULL";
            }
            size_t need = len + strlen(v) + 3;
            if (need > cap) {
                cap = 2 * need;
                out = realloc(out, cap);
                ENSURE(out);
            }
            len += (size_t)sprintf(out + len, "%s%s", v, c + 1 < sqlite3_column_count(st) ? "|" : "\n");
        }
    }
    ENSURE_MSG(rc == SQLITE_DONE, "%s: %s", sql, sqlite3_errmsg(db));
    sqlite3_finalize(st);
    return out;
}

/* Everything stored for one run, as text. */
static char *run_dump(sqlite3 *db, int64_t run_id)
{
    static const char *const queries[] = {
        "SELECT * FROM runs WHERE id = %lld",
        "SELECT * FROM releases WHERE run_id = %lld ORDER BY id",
        "SELECT * FROM measures WHERE run_id = %lld ORDER BY id",
        "SELECT * FROM trajectories WHERE run_id = %lld ORDER BY id",
        ("SELECT p.* FROM path_points p JOIN trajectories t ON t.id = p.trajectory_id"
         " WHERE t.run_id = %lld ORDER BY p.trajectory_id, p.seq"),
        "SELECT * FROM interceptions WHERE run_id = %lld ORDER BY id",
        "SELECT * FROM tree_hits WHERE run_id = %lld ORDER BY id",
        "SELECT * FROM hazard_cells WHERE run_id = %lld ORDER BY ix, iy",
    };
    size_t n = sizeof queries / sizeof queries[0];
    char *all = calloc(1, 1);
    ENSURE(all);
    for (size_t i = 0; i < n; i++) {
        char sql[512];
        snprintf(sql, sizeof sql, queries[i], (long long)run_id);
        char *part = dump(db, sql);
        size_t la = strlen(all), lp = strlen(part);
        all = realloc(all, la + lp + 3);
        ENSURE(all);
        memcpy(all + la, part, lp);
        memcpy(all + la + lp, "#\n", 3);
        free(part);
    }
    return all;
}

/* A value that depends on the run, the release, the trajectory and a field. */
static double value_of(int64_t run, size_t release, long idx, int field)
{
    return 1.125 * (double)run + 10.5 * (double)release + 0.0625 * (double)idx + 100.25 * field;
}

static void write_trajectory(rf_store *s, int64_t run, size_t release, long idx, int with_rows)
{
    rf_error err = {0};
    rf_trajectory_record tr = {
        .stop = {value_of(run, release, idx, 0), value_of(run, release, idx, 1),
                 value_of(run, release, idx, 2)},
        .reason = (rf_stop_reason)(idx % 4),
        .duration_s = value_of(run, release, idx, 3),
        .path_length_m = value_of(run, release, idx, 4),
        .max_energy_kj = value_of(run, release, idx, 5),
        .n_impacts = idx + 3,
        .n_tree_hits = idx % 2,
    };
    int64_t tid = 0;
    ENSURE_MSG(rf_store_add_trajectory(s, release, idx, &tr, &tid, &err) == 0, "%s",
               err.message);
    ENSURE(tid > 0);
    if (!with_rows)
        return;
    for (long k = 0; k < 3; k++) {
        rf_path_point pt = {.t_s = 0.5 * (double)k, .p = {1.0 * (double)k, 2.0, 3.0},
                            .speed_ms = 4.5, .energy_kj = value_of(run, release, idx, 6)};
        ENSURE_MSG(rf_store_add_path_point(s, tid, k, &pt, &err) == 0, "%s", err.message);
    }
    rf_interception_record ic = {
        .measure = (int)(idx % 3), .t_s = 2.5, .p = {1, 2, 3}, .speed_ms = 12.5,
        .energy_kj = value_of(run, release, idx, 7), .energy_trans_kj = 7.25,
        .energy_rot_kj = 0.5, .passing_height_m = 1.75, .outcome = (rf_outcome)(idx % 4),
    };
    int64_t iid = 0;
    ENSURE_MSG(rf_store_add_interception(s, tid, &ic, &iid, &err) == 0, "%s", err.message);
    ENSURE(iid > 0);
    if (idx % 2) {
        rf_tree_hit_record th = {.t_s = 1.5, .p = {4, 5, 6}, .speed_before_ms = 9.5,
                                 .speed_after_ms = 6.25,
                                 .energy_lost_kj = value_of(run, release, idx, 8)};
        ENSURE_MSG(rf_store_add_tree_hit(s, tid, &th, &err) == 0, "%s", err.message);
    }
}

/* The test's project and a new store in the file `name` of the test's directory
 * (*path: that file). */
static rf_store *open_project_store(test_project *t, const char *name, const char **path)
{
    make_project(t);
    *path = rf_test_path(name);
    return open_store(*path);
}

/* Begins a run of `total` trajectories; returns its id. */
static int64_t begin_run(rf_store *s, const rf_project *p, long total)
{
    rf_error err = {0};
    int64_t run = 0;
    ENSURE_MSG(rf_store_run_begin(s, p, total, &run, &err) == 0, "%s", err.message);
    return run;
}

/* Writes a run of n trajectories per release with all their rows; returns its id. */
static int64_t write_run(rf_store *s, const rf_project *p, long n, const char *status)
{
    rf_error err = {0};
    long total = n * (long)p->nreleases;
    int64_t run = begin_run(s, p, total);
    ENSURE(run > 0 && rf_store_run_id(s) == run);
    ENSURE(rf_store_batch_begin(s, &err) == 0);
    for (size_t r = 0; r < p->nreleases; r++)
        for (long i = 0; i < n; i++)
            write_trajectory(s, run, r, i, 1);
    for (long c = 0; c < 4; c++) {
        rf_hazard_cell_record hc = {.ix = c % 2, .iy = c / 2, .x = 2.5 + 5.0 * (double)(c % 2),
                                    .y = 2.5 + 5.0 * (double)(c / 2), .passes = c + 1,
                                    .reach_probability = 0.125 * (double)c,
                                    .energy_max_kj = (double)run, .energy_p95_kj = 0.95,
                                    .height_p95_m = 1.25};
        ENSURE_MSG(rf_store_add_hazard_cell(s, &hc, &err) == 0, "%s", err.message);
    }
    ENSURE(rf_store_batch_commit(s, &err) == 0);
    ENSURE_MSG(rf_store_run_finish(s, status, total, &err) == 0, "%s", err.message);
    return run;
}

/* ---- schema ----------------------------------------------------------------------- */

static int has_column(sqlite3 *db, const char *table, const char *column)
{
    return dbt_int(db, "SELECT count(*) FROM pragma_table_info('%s') WHERE name = '%s'", table,
                     column) == 1;
}

/* An index whose first column is `column` (a primary key's index counts). */
static int has_index_on(sqlite3 *db, const char *table, const char *column)
{
    return dbt_int(db,
                     "SELECT count(*) FROM pragma_index_list('%s') AS il,"
                     " pragma_index_info(il.name) AS ii WHERE ii.seqno = 0 AND ii.name = '%s'",
                     table, column) > 0;
}

static int rejected(sqlite3 *db, const char *sql)
{
    return sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_CONSTRAINT;
}

TEST(store_schema_has_every_table_and_column)
{
    static const char *const tables[][20] = {
        {"runs", "id", "project", "seed", "status", "started_at", "finished_at",
         "n_trajectories", "version", "project_yaml", "rules_path", "surface_friction",
         "hazard_cell_m"},
        {"releases", "id", "run_id", "name", "x", "y", "z", "rock", "mass_kg", "radius_m",
         "action_level", "count", "velocity_x", "velocity_y", "velocity_z", "height_m",
         "jitter_m"},
        {"trajectories", "id", "run_id", "release_id", "idx", "stop_x", "stop_y", "stop_z",
         "stop_reason", "duration_s", "path_length_m", "max_energy_kj", "n_impacts",
         "n_tree_hits", "rest_steep", "mass_kg", "start_x", "start_y", "start_z"},
        {"measures", "id", "run_id", "name", "kind", "importance", "height_m", "behaviour",
         "mel_kj", "sel_kj", "cap_serviceability_kj", "cap_restorability_kj",
         "cap_ultimate_kj", "cap_near_collapse_kj", "line", "sel_source"},
        {"measure_kinds", "name", "label", "classified", "reach_line", "limit_states"},
        {"rockfall_schema", "version", "application"},
        {"terrain_grids", "run_id", "xmin", "xmax", "ymin", "ymax", "x0", "y0", "x1", "y1",
         "step", "nx", "ny", "z"},
        {"ground_points", "run_id", "release_id", "measure_id", "x", "y", "z"},
        {"check_rules", "run_id", "path", "name", "text", "checked_at"},
        {"interceptions", "id", "run_id", "trajectory_id", "measure_id", "t_s", "x", "y", "z",
         "speed_ms", "energy_kj", "energy_trans_kj", "energy_rot_kj", "passing_height_m",
         "outcome"},
        {"classifications", "interception_id", "action_level", "importance", "limit_state",
         "required_state", "ok"},
        {"checks", "id", "run_id", "measure_id", "rule", "value", "threshold", "passed"},
        {"hazard_cells", "run_id", "ix", "iy", "x", "y", "passes", "reach_probability",
         "energy_max_kj", "energy_p95_kj", "height_p95_m"},
        {"path_points", "trajectory_id", "seq", "t_s", "x", "y", "z", "speed_ms", "energy_kj"},
        {"tree_hits", "id", "run_id", "trajectory_id", "t_s", "x", "y", "z", "speed_before_ms",
         "speed_after_ms", "energy_lost_kj"},
        {"calibrations", "id", "project", "project_path", "observed_path", "n_observed", "seed",
         "created_at", "version", "objective", "value", "ks_runout", "ks_lateral",
         "inside_share", "n_simulations", "n_trajectories", "converged"},
        {"calibration_values", "calibration_id", "key", "start", "value"},
    };
    const char *path = rf_test_path("schema.db");
    rf_store *s = open_store(path);
    sqlite3 *db = rf_store_db(s);
    for (size_t t = 0; t < sizeof tables / sizeof tables[0]; t++) {
        const char *table = tables[t][0];
        ENSURE_MSG(dbt_int(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table'"
                                 " AND name = '%s'", table) == 1,
                   "no table %s", table);
        for (size_t c = 1; c < 20 && tables[t][c]; c++)
            ENSURE_MSG(has_column(db, table, tables[t][c]), "no column %s.%s", table,
                       tables[t][c]);
        if (has_column(db, table, "run_id")) {
            ENSURE_MSG(has_index_on(db, table, "run_id") ||
                           dbt_int(db, "SELECT pk FROM pragma_table_info('%s') WHERE name ="
                                       " 'run_id'", table) == 1,
                       "no index on %s(run_id)", table);
            ENSURE_MSG(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_list('%s')"
                                     " WHERE \"from\" = 'run_id' AND \"table\" = 'runs'",
                                 table) == 1,
                       "%s.run_id is no foreign key", table);
        }
    }
    ENSURE(has_index_on(db, "interceptions", "measure_id"));
    ENSURE(has_index_on(db, "path_points", "trajectory_id"));
    ENSURE(has_index_on(db, "classifications", "interception_id"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_list('path_points')"
                         " WHERE \"table\" = 'trajectories'") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_list('interceptions')") == 3);

    /* the file a GeoPackage: GeoPackage's user_version, the version in rockfall_schema */
    ENSURE(dbt_int(db, "PRAGMA user_version") == RF_GPKG_USER_VERSION);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_STORE_SCHEMA_VERSION);
    char *mode = dump(db, "PRAGMA journal_mode");
    ENSURE_MSG(strcmp(mode, "wal\n") == 0, "journal_mode %s", mode);
    free(mode);
    ENSURE(dbt_int(db, "PRAGMA synchronous") == 1); /* NORMAL */
    ENSURE(dbt_int(db, "PRAGMA foreign_keys") == 1);

    /* CHECK constraints on the enumerated columns. */
    exec_raw(db, "INSERT INTO runs (id, project, seed, status, started_at, n_trajectories,"
                 " version) VALUES (1, 'p', 1, 'running', 'now', 0, 'v')");
    ENSURE(rejected(db, "UPDATE runs SET status = 'done' WHERE id = 1"));
    exec_raw(db, "INSERT INTO releases (id, run_id, idx, name, rock, action_level, count)"
                 " VALUES (1, 1, 0, 'C', 'r', 2, 1)");
    ENSURE(rejected(db, "INSERT INTO trajectories (run_id, release_id, idx, stop_reason)"
                        " VALUES (1, 1, 0, 'resting')"));
    exec_raw(db, "INSERT INTO trajectories (id, run_id, release_id, idx, stop_reason)"
                 " VALUES (1, 1, 1, 0, 'rest')");
    ENSURE(rejected(db, "INSERT INTO measures (run_id, idx, name, kind, importance, behaviour,"
                        " line) VALUES (1, 0, 'm', 'wall', 'usual', 'stop', '[]')"));
    ENSURE(rejected(db, "INSERT INTO measures (run_id, idx, name, kind, importance, behaviour,"
                        " line) VALUES (1, 0, 'm', 'barrier', 'usual', 'catch', '[]')"));
    exec_raw(db, "INSERT INTO measures (id, run_id, idx, name, kind, importance, behaviour,"
                 " line) VALUES (1, 1, 0, 'm', 'barrier', 'usual', 'stop', '[]')");
    ENSURE(rejected(db, "INSERT INTO interceptions (run_id, trajectory_id, measure_id, outcome)"
                        " VALUES (1, 1, 1, 'bounced')"));
    exec_raw(db, "INSERT INTO interceptions (run_id, trajectory_id, measure_id, outcome)"
                 " VALUES (1, 1, 1, 'overtopped')");
    /* Foreign keys are enforced. */
    ENSURE(rejected(db, "INSERT INTO path_points (trajectory_id, seq) VALUES (99, 0)"));
    rf_store_close(s);
}

TEST(store_record_names)
{
    ENSURE(strcmp(rf_stop_reason_name(RF_END_REST), "rest") == 0);
    ENSURE(strcmp(rf_stop_reason_name(RF_END_EXITED), "exited") == 0);
    ENSURE(strcmp(rf_stop_reason_name(RF_END_STOPPED), "stopped") == 0);
    ENSURE(strcmp(rf_stop_reason_name(RF_END_MAX_TIME), "max_time") == 0);
    ENSURE(strcmp(rf_outcome_name(RF_OUT_STOPPED), "stopped") == 0);
    ENSURE(strcmp(rf_outcome_name(RF_OUT_OVERTOPPED), "overtopped") == 0);
    ENSURE(strcmp(rf_outcome_name(RF_OUT_BROKE_THROUGH), "broke_through") == 0);
    ENSURE(strcmp(rf_outcome_name(RF_OUT_PASSED), "passed") == 0);
}

/* ---- runs ------------------------------------------------------------------------- */

TEST(store_run_row_releases_and_measures)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "rows.db", &path);
    rf_error err = {0};
    int64_t run = begin_run(s, &t.p, 10);

    /* Committed before any row of the run: visible from another connection. */
    sqlite3 *other = open_raw(path);
    ENSURE(dbt_int(other, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'running'"
                            " AND finished_at IS NULL AND n_trajectories = 10 AND seed = 2009",
                     (long long)run) == 1);
    ENSURE(dbt_int(other, "SELECT count(*) FROM runs WHERE started_at GLOB"
                            " '[0-9][0-9][0-9][0-9]-[0-1][0-9]-[0-3][0-9]T[0-2][0-9]:[0-5][0-9]:"
                            "[0-6][0-9]*Z'") == 1);
    ENSURE(dbt_int(other, "SELECT count(*) FROM runs WHERE project = 'store-test-slope'"
                            " AND version = '" ROCKFALL_VERSION "'"
                            " AND project_yaml = 'name: store-test-slope' || char(10) ||"
                            " 'seed: 2009' || char(10)") == 1);
    ENSURE(run_rows(other, "releases", (long long)run) == 2);
    ENSURE(run_rows(other, "measures", (long long)run) == 3);

    /* Ids in the order of the project's arrays. */
    ENSURE(rf_store_release_id(s, 0) < rf_store_release_id(s, 1));
    ENSURE(rf_store_measure_id(s, 0) < rf_store_measure_id(s, 1));
    ENSURE(rf_store_measure_id(s, 1) < rf_store_measure_id(s, 2));
    ENSURE(dbt_int(other, "SELECT idx FROM releases WHERE id = %lld",
                     (long long)rf_store_release_id(s, 1)) == 1);
    ENSURE(dbt_int(other, "SELECT count(*) FROM releases WHERE id = %lld AND name = 'D'"
                            " AND x = 17.75 AND y = 52.125 AND z = 129.5 AND rock = 'r4500'"
                            " AND mass_kg = 4500 AND radius_m = 0.7403 AND action_level = 2"
                            " AND count = 5 AND velocity_x = 0.25 AND velocity_y = -1.5"
                            " AND velocity_z = 0 AND height_m = 1.5 AND jitter_m = 2.385",
                     (long long)rf_store_release_id(s, 1)) == 1);

    char sql[256];
    snprintf(sql, sizeof sql,
             "SELECT name, kind, importance, height_m, behaviour, mel_kj, sel_kj,"
             " cap_serviceability_kj, cap_restorability_kj, cap_ultimate_kj,"
             " cap_near_collapse_kj, line FROM measures WHERE run_id = %lld ORDER BY id",
             (long long)run);
    char *rows = dump(other, sql);
    char expected[512];
    snprintf(expected, sizeof expected,
             "road|control|%s|0|collect|NULL|NULL|NULL|NULL|NULL|NULL|[[0,10],[20,10.5],[40,11]]\n"
             "E1|embankment|%s|6|stop|NULL|NULL|3000|6000|9000|NULL|[[0,30],[40,30.25]]\n"
             "B1|barrier|%s|5|stop|3000|1000|1000|NULL|3000|NULL|[[0,60],[40,60.1]]\n",
             rf_importance_name(RF_IMPORTANT), rf_importance_name(RF_MOST_IMPORTANT),
             rf_importance_name(RF_USUAL));
    ENSURE_MSG(strcmp(rows, expected) == 0, "measures:\n%s", rows);
    free(rows);
    /* The line is JSON. */
    ENSURE(dbt_real(other, "SELECT json_extract(line, '$[1][1]') FROM measures"
                             " WHERE name = 'E1'") == 30.25);
    sqlite3_close(other);

    ENSURE(rf_store_run_finish(s, "complete", 0, &err) == 0);
    rf_store_close(s);
}

TEST(store_two_runs_in_one_file)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "two.db", &path);
    int64_t a = write_run(s, &t.p, 5, "complete");
    t.p.seed = 2010;
    int64_t b = write_run(s, &t.p, 7, "complete");
    ENSURE(a > 0 && b > a);
    rf_store_close(s);

    sqlite3 *db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs") == 2);
    const int64_t runs[2] = {a, b};
    const long n[2] = {5, 7};
    for (int k = 0; k < 2; k++) {
        long long r = (long long)runs[k];
        ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'complete'"
                             " AND finished_at >= started_at AND n_trajectories = %ld",
                         r, 2 * n[k]) == 1);
        ENSURE(dbt_int(db, "SELECT seed FROM runs WHERE id = %lld", r) == 2009 + k);
        ENSURE(run_rows(db, "trajectories", r) == 2 * n[k]);
        ENSURE(dbt_int(db, "SELECT count(*) FROM path_points p JOIN trajectories t"
                             " ON t.id = p.trajectory_id WHERE t.run_id = %lld", r) == 6 * n[k]);
        ENSURE(run_rows(db, "interceptions", r) == 2 * n[k]);
        ENSURE(run_rows(db, "tree_hits", r) == 2 * (n[k] / 2));
        ENSURE(run_rows(db, "hazard_cells", r) == 4);
        ENSURE(dbt_real(db, "SELECT max(energy_max_kj) FROM hazard_cells WHERE run_id = %lld",
                          r) == (double)runs[k]);
        /* Every row references rows of its own run. */
        ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories t JOIN releases r"
                             " ON r.id = t.release_id WHERE t.run_id = %lld AND r.run_id <> t.run_id",
                         r) == 0);
        ENSURE(dbt_int(db, "SELECT count(*) FROM interceptions i JOIN measures m"
                             " ON m.id = i.measure_id JOIN trajectories t ON t.id = i.trajectory_id"
                             " WHERE i.run_id = %lld AND (m.run_id <> i.run_id"
                             " OR t.run_id <> i.run_id)", r) == 0);
        ENSURE(dbt_int(db, "SELECT count(*) FROM tree_hits h JOIN trajectories t"
                             " ON t.id = h.trajectory_id WHERE h.run_id = %lld"
                             " AND t.run_id <> h.run_id", r) == 0);
        /* A value written is the value read: release D, trajectory 3. */
        ENSURE(dbt_real(db, "SELECT t.stop_x FROM trajectories t JOIN releases r"
                              " ON r.id = t.release_id WHERE t.run_id = %lld AND r.name = 'D'"
                              " AND t.idx = 3", r) == value_of(runs[k], 1, 3, 0));
        ENSURE(dbt_real(db, "SELECT i.energy_kj FROM interceptions i JOIN trajectories t"
                              " ON t.id = i.trajectory_id JOIN measures m ON m.id = i.measure_id"
                              " WHERE i.run_id = %lld AND t.idx = 4 AND m.name = 'E1'"
                              " AND t.release_id = (SELECT id FROM releases WHERE run_id = %lld"
                              " AND idx = 0)", r, r) == value_of(runs[k], 0, 4, 7));
        ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE run_id = %lld"
                             " AND stop_reason = 'max_time'", r) == 2 * (n[k] / 4));
    }
    sqlite3_close(db);
}

TEST(store_failed_run_is_failed)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "failed.db", &path);
    int64_t ok = write_run(s, &t.p, 3, "complete");

    /* Ended as failed in the middle of a batch: the batch is committed first. */
    rf_error err = {0};
    int64_t bad = begin_run(s, &t.p, 6);
    ENSURE(rf_store_batch_begin(s, &err) == 0);
    write_trajectory(s, bad, 0, 0, 1);
    write_trajectory(s, bad, 1, 0, 1);
    ENSURE_MSG(rf_store_run_finish(s, "failed", 2, &err) == 0, "%s", err.message);

    /* A status other than complete or failed is refused. */
    ENSURE(rf_store_run_finish(s, "done", 2, &err) != 0);
    ENSURE(strstr(err.message, "'done'") != NULL);
    ENSURE(strcmp(err.file, path) == 0);
    rf_store_close(s);

    sqlite3 *db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'complete'",
                     (long long)ok) == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'failed'"
                         " AND finished_at IS NOT NULL AND n_trajectories = 2",
                     (long long)bad) == 1);
    ENSURE(run_rows(db, "trajectories", (long long)bad) == 2);
    sqlite3_close(db);
}

/* A run of 4 in the file `name` with trajectory 0 of release 0 committed in one batch
 * and trajectory 1 written in a second batch left open; its id in *run. */
static rf_store *second_batch_open(test_project *t, const char *name, const char **path,
                                   int64_t *run)
{
    rf_store *s = open_project_store(t, name, path);
    rf_error err = {0};
    *run = begin_run(s, &t->p, 4);
    ENSURE(rf_store_batch_begin(s, &err) == 0);
    write_trajectory(s, *run, 0, 0, 1);
    ENSURE(rf_store_batch_commit(s, &err) == 0);
    ENSURE(rf_store_batch_begin(s, &err) == 0);
    write_trajectory(s, *run, 0, 1, 1);
    return s;
}

TEST(store_uncommitted_batch_is_lost_on_close)
{
    test_project t;
    const char *path;
    int64_t run;
    rf_store *s = second_batch_open(&t, "uncommitted.db", &path, &run);
    rf_store_close(s); /* without finishing: an interrupted run */

    sqlite3 *db = open_raw(path);
    ENSURE(run_rows(db, "trajectories", (long long)run) == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'running'",
                     (long long)run) == 1);
    sqlite3_close(db);
}

TEST(store_bad_row_is_an_error_naming_the_file)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "duplicate.db", &path);
    rf_error err = {0};
    int64_t run = begin_run(s, &t.p, 2);
    write_trajectory(s, run, 0, 0, 0);
    rf_trajectory_record tr = {.reason = RF_END_REST};
    int64_t tid = 0;
    /* The same trajectory index of the same release twice. */
    ENSURE(rf_store_add_trajectory(s, 0, 0, &tr, &tid, &err) != 0);
    ENSURE(strcmp(err.file, path) == 0);
    ENSURE_MSG(strstr(err.message, "writing a trajectory") && strstr(err.message, "UNIQUE"),
               "%s", err.message);
    rf_path_point pt = {0};
    ENSURE(rf_store_add_path_point(s, 424242, 0, &pt, &err) != 0);
    ENSURE_MSG(strstr(err.message, "FOREIGN KEY"), "%s", err.message);
    ENSURE(rf_store_run_finish(s, "failed", 1, &err) == 0);
    rf_store_close(s);
}

/* A row that fails rolls its whole batch back: the rows before it in the batch are not
 * in the file, those of batches committed before are, and the store writes on. */
TEST(store_failed_row_rolls_its_batch_back)
{
    test_project t;
    const char *path;
    int64_t run;
    rf_store *s = second_batch_open(&t, "failed-row.db", &path, &run);
    rf_error err = {0};
    rf_path_point pt = {0};
    ENSURE(rf_store_add_path_point(s, 424242, 0, &pt, &err) != 0); /* no such trajectory */
    ENSURE(sqlite3_get_autocommit(rf_store_db(s))); /* the batch is closed */
    write_trajectory(s, run, 1, 0, 0);
    ENSURE(rf_store_run_finish(s, "failed", 2, &err) == 0);
    rf_store_close(s);

    sqlite3 *db = open_raw(path);
    ENSURE(run_rows(db, "trajectories", (long long)run) == 2);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE run_id = %lld AND idx = 1",
                   (long long)run) == 0);
    sqlite3_close(db);
}

TEST(store_reopen_adds_a_third_run)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "reopen.db", &path);
    write_run(s, &t.p, 4, "complete");
    write_run(s, &t.p, 2, "complete");
    rf_store_close(s);

    sqlite3 *db = open_raw(path);
    char *first = run_dump(db, 1), *second = run_dump(db, 2);
    sqlite3_close(db);

    s = open_store(path);
    int64_t third = write_run(s, &t.p, 3, "complete");
    ENSURE(third == 3);
    rf_store_close(s);

    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE status = 'complete'") == 3);
    ENSURE(dbt_int(db, "SELECT group_concat(id) = '1,2,3' FROM runs") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE run_id = 3") == 6);
    char *first_after = run_dump(db, 1), *second_after = run_dump(db, 2);
    ENSURE(strcmp(first, first_after) == 0);
    ENSURE(strcmp(second, second_after) == 0);
    sqlite3_close(db);
    free(first);
    free(second);
    free(first_after);
    free(second_after);
}

/* A file written by an earlier rockfall, with an older measure_summary and without
 * run_verdicts: opened, it gets this version's views, its data untouched; a file whose
 * views are current does not have its schema rewritten on opening. */
TEST(store_reopen_brings_old_views_up_to_date)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "oldviews.db", &path);
    write_run(s, &t.p, 4, "complete");
    rf_store_close(s);

    sqlite3 *db = open_raw(path);
    exec_raw(db, "DROP VIEW measure_summary");
    exec_raw(db, "CREATE VIEW measure_summary AS SELECT m.id AS measure_id, count(i.id) AS "
                 "interceptions FROM measures m LEFT JOIN interceptions i ON "
                 "i.measure_id = m.id GROUP BY m.id");
    exec_raw(db, "DROP VIEW run_verdicts");
    ENSURE(!has_column(db, "measure_summary", "checks_failed"));
    char *before = run_dump(db, 1);
    sqlite3_close(db);

    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(has_column(db, "measure_summary", "checks_failed"));
    ENSURE(has_column(db, "measure_summary", "share_serviceability"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM run_verdicts") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measure_summary WHERE run_id = 1") ==
           dbt_int(db, "SELECT count(*) FROM measures WHERE run_id = 1"));
    char *after = run_dump(db, 1);
    ENSURE(strcmp(before, after) == 0);
    int cookie = dbt_int(db, "PRAGMA schema_version");
    sqlite3_close(db);

    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "PRAGMA schema_version") == cookie);
    sqlite3_close(db);
    free(before);
    free(after);
}

/* ---- foreign files ------------------------------------------------------------------- */

TEST(store_rejects_another_schema_version)
{
    const char *path = rf_test_path("future.db");
    rf_store *s = open_store(path);
    rf_store_close(s);
    sqlite3 *db = open_raw(path);
    /* the version is the row of rockfall_schema */
    exec_raw(db, "UPDATE rockfall_schema SET version = 7; PRAGMA user_version = 7");
    sqlite3_close(db);

    rf_error err = {0};
    s = NULL;
    ENSURE(rf_store_open(path, &s, &err) != 0);
    ENSURE(s == NULL);
    ENSURE(strcmp(err.file, path) == 0);
    ENSURE_MSG(strstr(err.message, "version 7") && strstr(err.message, "versions 1 to " RF_STR(RF_SCHEMA_VERSION)),
               "%s",
               err.message);

    /* Still version 7: nothing was written. */
    db = open_raw(path);
    ENSURE(dbt_int(db, "PRAGMA user_version") == 7);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 7);
    sqlite3_close(db);

    /* Another application's SQLite database (no schema version, some tables). */
    const char *other = rf_test_path("other.db");
    sqlite3_open_v2(other, &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, NULL);
    exec_raw(db, "CREATE TABLE photos (id INTEGER PRIMARY KEY, file TEXT)");
    sqlite3_close(db);
    ENSURE(rf_store_open(other, &s, &err) != 0);
    ENSURE(strcmp(err.file, other) == 0);
    ENSURE_MSG(strstr(err.message, "not a rockfall results database"), "%s", err.message);
}

static char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    ENSURE(f);
    char *buf = malloc(1 << 16);
    ENSURE(buf);
    *len = fread(buf, 1, 1 << 16, f);
    fclose(f);
    return buf;
}

static int exists(const char *path)
{
    return access(path, F_OK) == 0;
}

TEST(store_rejects_a_file_that_is_no_database)
{
    const char *path = rf_test_path("project.yaml");
    FILE *f = fopen(path, "w");
    ENSURE(f);
    for (int i = 0; i < 40; i++)
        fprintf(f, "- {name: B%d, kind: barrier, line: [[0, %d], [40, %d]], mel: 3000}\n", i, i, i);
    fclose(f);
    size_t len_before = 0, len_after = 0;
    char *before = read_all(path, &len_before);

    rf_store *s = NULL;
    rf_error err = {0};
    ENSURE(rf_store_open(path, &s, &err) != 0);
    ENSURE(s == NULL);
    ENSURE(strcmp(err.file, path) == 0);
    ENSURE_MSG(strstr(err.message, "not a database"), "%s", err.message);

    char *after = read_all(path, &len_after);
    ENSURE(len_before == len_after && memcmp(before, after, len_before) == 0);
    char side[600];
    snprintf(side, sizeof side, "%s-wal", path);
    ENSURE(!exists(side));
    snprintf(side, sizeof side, "%s-journal", path);
    ENSURE(!exists(side));
    free(before);
    free(after);

    /* A directory that does not exist. */
    ENSURE(rf_store_open(rf_test_path("no/such/dir/results.db"), &s, &err) != 0);
    ENSURE(strstr(err.message, "opening the results database") != NULL);
}

/* ---- a writer killed in the middle of a run ---------------------------------------- */

enum { KILL_BATCH = 200 };

/* The child: a second run, trajectories in batches, forever. */
static void write_until_killed(const char *path, const rf_project *p)
{
    rf_store *s = NULL;
    rf_error err = {0};
    if (rf_store_open(path, &s, &err) || rf_store_run_begin(s, p, 1000000, NULL, &err))
        _exit(3);
    int64_t run = rf_store_run_id(s);
    for (long idx = 0;;) {
        if (rf_store_batch_begin(s, &err))
            _exit(4);
        for (int k = 0; k < KILL_BATCH; k++, idx++)
            write_trajectory(s, run, (size_t)(idx % 2), idx, 1);
        if (rf_store_batch_commit(s, &err))
            _exit(5);
    }
}

TEST(store_survives_a_writer_killed_mid_run)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "killed.db", &path);
    int64_t first = write_run(s, &t.p, 6, "complete");
    rf_store_close(s);
    sqlite3 *db = open_raw(path);
    char *before = run_dump(db, first);
    sqlite3_close(db);

    fflush(NULL);
    pid_t child = fork();
    ENSURE(child >= 0);
    if (child == 0)
        write_until_killed(path, &t.p);

    /* Wait for a few committed batches, watching from a separate connection. */
    sqlite3 *watch = open_raw(path);
    int64_t seen = 0;
    struct timespec pause = {0, 2 * 1000 * 1000};
    for (int i = 0; i < 30000 && seen < 3 * KILL_BATCH; i++) {
        int status = 0;
        ENSURE_MSG(waitpid(child, &status, WNOHANG) == 0, "writer exited early (%d)",
                   WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        seen = dbt_int(watch, "SELECT count(*) FROM trajectories WHERE run_id > %lld",
                         (long long)first);
        nanosleep(&pause, NULL);
    }
    sqlite3_close(watch);
    ENSURE_MSG(seen >= 3 * KILL_BATCH, "only %lld trajectories written", (long long)seen);
    kill(child, SIGKILL);
    int status = 0;
    ENSURE(waitpid(child, &status, 0) == child);
    ENSURE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

    db = open_raw(path);
    char *check = dump(db, "PRAGMA integrity_check");
    ENSURE_MSG(strcmp(check, "ok\n") == 0, "integrity_check: %s", check);
    free(check);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs") == 2);
    char *after = run_dump(db, first);
    ENSURE_MSG(strcmp(before, after) == 0, "first run changed:\n%s\n---\n%s", before, after);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'complete'",
                     (long long)first) == 1);
    int64_t second = first + 1;
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status <> 'complete'",
                     (long long)second) == 1);
    /* Batches are all or nothing. */
    int64_t n = run_rows(db, "trajectories", (long long)second);
    ENSURE_MSG(n >= 3 * KILL_BATCH && n % KILL_BATCH == 0, "%lld trajectories", (long long)n);
    ENSURE(dbt_int(db, "SELECT count(*) FROM path_points p JOIN trajectories t"
                         " ON t.id = p.trajectory_id WHERE t.run_id = %lld",
                     (long long)second) == 3 * n);
    ENSURE(run_rows(db, "interceptions", (long long)second) == n);
    sqlite3_close(db);

    /* The file takes further runs. */
    s = open_store(path);
    int64_t third = write_run(s, &t.p, 2, "complete");
    rf_store_close(s);
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = %lld AND status = 'complete'",
                     (long long)third) == 1);
    char *still = run_dump(db, first);
    ENSURE(strcmp(before, still) == 0);
    sqlite3_close(db);
    free(before);
    free(after);
    free(still);
}

/* Several writers opening one new file at once: each opens it (one creates the schema,
 * the others wait for it), none fails on the lock that switching to WAL takes. */
TEST(store_writers_opening_a_new_file_at_once_all_succeed)
{
    enum { FILES = 12, WRITERS = 6 };
    int failed = 0;
    for (int f = 0; f < FILES; f++) {
        char name[40];
        snprintf(name, sizeof name, "race-%d.db", f);
        const char *path = rf_test_path(name);
        int go[2];
        ENSURE(pipe(go) == 0);
        fflush(NULL);
        pid_t kids[WRITERS];
        for (int k = 0; k < WRITERS; k++) {
            kids[k] = fork();
            ENSURE(kids[k] >= 0);
            if (kids[k] == 0) {
                close(go[1]);
                char c;
                (void)!read(go[0], &c, 1); /* all start when the pipe closes */
                rf_store *s;
                rf_error err = {0};
                if (rf_store_open(path, &s, &err)) {
                    fprintf(stderr, "writer %d: %s\n", k, err.message);
                    _exit(1);
                }
                rf_store_close(s);
                _exit(0);
            }
        }
        close(go[0]);
        close(go[1]);
        for (int k = 0; k < WRITERS; k++) {
            int status = 0;
            ENSURE(waitpid(kids[k], &status, 0) == kids[k]);
            failed += !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
        }
        sqlite3 *db = open_raw(path);
        ENSURE(dbt_int(db, "SELECT count(*) FROM sqlite_master WHERE name = 'runs'") == 1);
        char *mode = dump(db, "PRAGMA journal_mode");
        /* the last writer to close put the file back in the rollback journal */
        ENSURE_MSG(strcmp(mode, "delete\n") == 0, "journal mode %s", mode);
        free(mode);
        sqlite3_close(db);
    }
    ENSURE_MSG(failed == 0, "%d of %d writers could not open a new file", failed,
               FILES * WRITERS);
}

/* ---- schema versions ------------------------------------------------------------------ */

/* A database written by rockfall before schema version 2 (`rockfall run
 * projects/noto/noto-3.3.yaml --count 5` at schema version 1, checked): five releases of
 * five trajectories, the measures B1 (a barrier without sel), E1 and road. */
#define V1_FIXTURE "tests/data/results-v1.db"

/* The rows of a version-1 file in the columns of version 1. */
static char *v1_dump(sqlite3 *db)
{
    char *a = dump(db, "SELECT id, project, project_path, seed, status, started_at,"
                       " finished_at, n_trajectories, version, project_yaml FROM runs"
                       " ORDER BY id");
    char *b = dump(db, "SELECT id, run_id, idx, name, kind, importance, height_m, behaviour,"
                       " mel_kj, sel_kj, cap_serviceability_kj, cap_restorability_kj,"
                       " cap_ultimate_kj, cap_near_collapse_kj, line FROM measures ORDER BY id");
    char *c = dump(db, "SELECT (SELECT group_concat(x) FROM (SELECT quote(t.id) || quote(stop_x)"
                       " || quote(max_energy_kj) AS x FROM trajectories t ORDER BY id)),"
                       " (SELECT group_concat(quote(energy_kj) || outcome) FROM interceptions),"
                       " (SELECT group_concat(quote(x) || quote(z)) FROM path_points),"
                       " (SELECT group_concat(quote(energy_p95_kj)) FROM hazard_cells),"
                       " (SELECT group_concat(limit_state || ok) FROM classifications),"
                       " (SELECT group_concat(rule || quote(value)) FROM checks),"
                       " (SELECT group_concat(name || quote(z)) FROM releases)");
    size_t n = strlen(a) + strlen(b) + strlen(c) + 1;
    char *all = malloc(n);
    ENSURE(all);
    snprintf(all, n, "%s%s%s", a, b, c);
    free(a);
    free(b);
    free(c);
    return all;
}

/* A copy of a fixture file in the case's directory. */
static const char *copy_fixture(const char *fixture, const char *name)
{
    size_t len = 0;
    FILE *f = fopen(fixture, "rb");
    ENSURE_MSG(f, "cannot open %s", fixture);
    char *buf = malloc(1 << 20);
    ENSURE(buf);
    len = fread(buf, 1, 1 << 20, f);
    fclose(f);
    ENSURE(len > 0 && len < (1 << 20));
    const char *path = rf_test_path(name);
    FILE *o = fopen(path, "wb");
    ENSURE(o && fwrite(buf, 1, len, o) == len);
    fclose(o);
    free(buf);
    return path;
}

/* A copy of the version-1 fixture in the case's directory. */
static const char *copy_v1(const char *name) { return copy_fixture(V1_FIXTURE, name); }

TEST(store_measure_kinds_are_rows_that_measures_reference)
{
    test_project t;
    const char *path;
    rf_store *s = open_project_store(&t, "kinds.db", &path);
    write_run(s, &t.p, 2, "complete");
    sqlite3 *db = rf_store_db(s);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measure_kinds") == RF_N_MEASURE_KINDS);
    for (int k = 0; k < RF_N_MEASURE_KINDS; k++)
        ENSURE(dbt_int(db, "SELECT count(*) FROM measure_kinds WHERE name = '%s' AND label = '%s'"
                           " AND classified = %d", rf_measure_kinds[k].name,
                       rf_measure_kinds[k].label, rf_measure_kinds[k].classified) == 1);
    /* every measure's kind is a row; the foreign key is declared and enforced */
    ENSURE(dbt_int(db, "SELECT count(*) FROM measures m JOIN measure_kinds k ON k.name = m.kind") ==
           dbt_int(db, "SELECT count(*) FROM measures"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_list('measures')"
                       " WHERE \"table\" = 'measure_kinds' AND \"from\" = 'kind'") == 1);
    ENSURE(rejected(db, "UPDATE measures SET kind = 'wall'"));
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    ENSURE(dbt_int(db, "PRAGMA user_version") == RF_GPKG_USER_VERSION);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    rf_store_close(s);
}

TEST(store_upgrades_a_version_1_file_in_place)
{
    const char *path = copy_v1("v1.db");
    sqlite3 *db = open_raw(path);
    ENSURE(dbt_int(db, "PRAGMA user_version") == 1);
    char *before = v1_dump(db);
    long long checks = dbt_int(db, "SELECT count(*) FROM checks");
    sqlite3_close(db);

    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    ENSURE(dbt_int(db, "PRAGMA user_version") == RF_GPKG_USER_VERSION);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measure_kinds") == RF_N_MEASURE_KINDS);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_check") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measures m JOIN measure_kinds k ON k.name = m.kind") ==
           3);
    /* what version 1 kept only in the project text */
    ENSURE(dbt_int(db, "SELECT count(*) FROM measures WHERE name = 'B1'"
                       " AND sel_source = 'default: MEL/3'") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measures WHERE kind <> 'barrier'"
                       " AND sel_source IS NULL") == 2);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE rules_path LIKE '%%rules/table3.yaml'") ==
           1);
    /* the run's rows as they were, and the views */
    char *after = v1_dump(db);
    ENSURE(strcmp(before, after) == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks") == checks);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measure_summary") == 3);
    sqlite3_close(db);
    free(before);
    free(after);

    /* a second opening finds the current version and changes nothing */
    db = open_raw(path);
    int cookie = (int)dbt_int(db, "PRAGMA schema_version");
    sqlite3_close(db);
    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "PRAGMA schema_version") == cookie);
    sqlite3_close(db);
}

TEST(store_check_and_read_modes_leave_the_schema_alone)
{
    const char *path = copy_v1("v1-read.db");
    sqlite3 *db = NULL;
    rf_error err = {0};
    int version = 0;
    ENSURE_MSG(rf_db_open(path, RF_DB_CHECK, &db, &version, &err) == 0, "%s", err.message);
    ENSURE(version == 1);
    ENSURE(!rf_db_has_table(db, "measure_kinds"));
    sqlite3_close(db);
    ENSURE_MSG(rf_db_open(path, RF_DB_READ, &db, &version, &err) == 0, "%s", err.message);
    ENSURE(version == 1);
    ENSURE(sqlite3_db_readonly(db, "main") == 1);
    ENSURE(sqlite3_exec(db, "DELETE FROM checks", NULL, NULL, NULL) != SQLITE_OK);
    sqlite3_close(db);
    db = open_raw(path);
    ENSURE(dbt_int(db, "PRAGMA user_version") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks") > 0);
    sqlite3_close(db);

    /* neither mode creates a file or takes another program's */
    ENSURE(rf_db_open(rf_test_path("none.db"), RF_DB_READ, &db, NULL, &err) != 0 && !db);
    ENSURE(access(rf_test_path("none.db"), F_OK) != 0);
    const char *other = rf_test_path("photos.db");
    sqlite3_open_v2(other, &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, NULL);
    exec_raw(db, "CREATE TABLE photos (id INTEGER PRIMARY KEY, file TEXT)");
    sqlite3_close(db);
    for (int mode = RF_DB_READ; mode <= RF_DB_CHECK; mode++) {
        ENSURE(rf_db_open(other, (rf_db_mode)mode, &db, NULL, &err) != 0 && !db);
        ENSURE_MSG(strstr(err.message, "not a rockfall results database"), "%s", err.message);
    }
}

/* A database written by rockfall at schema version 2 (`rockfall run
 * projects/noto/noto-3.3.yaml --count 5`, checked by that run): five releases of five
 * trajectories, the measures B1, E1 and road, five checks. */
#define V2_FIXTURE "tests/data/results-v2.db"

/* The rows of a version-2 file in the columns of version 2. */
static char *v2_dump(sqlite3 *db)
{
    return dump(db, "SELECT (SELECT group_concat(x, ';') FROM (SELECT quote(id) || quote(run_id)"
                    " || quote(release_id) || quote(idx) || quote(stop_x) || quote(stop_y) ||"
                    " quote(stop_z) || stop_reason || quote(duration_s) || quote(path_length_m)"
                    " || quote(max_energy_kj) || quote(n_impacts) || quote(n_tree_hits) AS x"
                    " FROM trajectories ORDER BY id)),"
                    " (SELECT group_concat(x, ';') FROM (SELECT quote(id) || quote(run_id) ||"
                    " quote(measure_id) || rule || quote(value) || quote(threshold) ||"
                    " quote(passed) AS x FROM checks ORDER BY id)),"
                    " (SELECT group_concat(quote(energy_kj) || outcome) FROM interceptions),"
                    " (SELECT group_concat(limit_state || ok) FROM classifications),"
                    " (SELECT group_concat(quote(energy_p95_kj)) FROM hazard_cells),"
                    " (SELECT count(*) || sum(length(z)) FROM terrain_grids),"
                    " (SELECT group_concat(rules_path) FROM runs)");
}

/* Version 2 to 3 in place: the rows kept in their columns, the trajectories of the
 * old run not recorded as to a rest on a steep face (NULL), every old check a design
 * check, the views current; a later run's trajectories record it. */
TEST(store_upgrades_a_version_2_file_in_place)
{
    const char *path = copy_fixture(V2_FIXTURE, "v2.db");
    sqlite3 *db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 2);
    ENSURE(dbt_int(db, "PRAGMA user_version") == 2);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_table_info('trajectories')"
                       " WHERE name = 'rest_steep'") == 0);
    char *before = v2_dump(db);
    sqlite3_close(db);

    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    ENSURE(dbt_int(db, "PRAGMA user_version") == RF_GPKG_USER_VERSION);
    char *after = v2_dump(db);
    ENSURE_MSG(strcmp(before, after) == 0, "%s\n%s", before, after);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories") == 25);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE rest_steep IS NULL") == 25);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks WHERE on_failure = 'fail'") == 5);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_check") == 0);
    /* the views of version 3: the run's verdict as its checks left it (Table 3 failed
     * E1's share at five rocks a release) */
    ENSURE(dbt_int(db, "SELECT count(*) FROM run_verdicts WHERE verdict = 'fail'"
                       " AND checks_inconclusive = 0") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM check_results WHERE verdict = 'fail'") == 1);
    sqlite3_close(db);
    free(before);
    free(after);

    /* a run into the upgraded file records the rest of every trajectory */
    test_project t;
    make_project(&t);
    rf_store *s = open_store(path);
    write_run(s, &t.p, 2, "complete");
    rf_store_close(s);
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE run_id = 2") > 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE run_id = 2 AND"
                       " rest_steep IS NOT 0") == 0);
    sqlite3_close(db);
}

/* A check of schema version 3 writes its integrity checks into a version-2 file without
 * on_failure; the upgrade gives those rows 'inconclusive' (and the design checks
 * 'fail'), so the upgraded file's verdict is the one check printed. */
TEST(store_upgrade_from_version_2_keeps_an_inconclusive_check_inconclusive)
{
    const char *path = copy_fixture(V2_FIXTURE, "v2-checked.db");
    sqlite3 *db = open_raw(path);
    exec_raw(db, "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed)"
                 " VALUES (1, NULL, 'trajectories_max_time', 0.04, 0, 0),"
                 " (1, NULL, 'trajectories_left_terrain', 0, 0.01, 1),"
                 " (1, NULL, 'trajectories_rest_on_steep_face', NULL, 0, 1)");
    sqlite3_close(db);
    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks WHERE measure_id IS NULL AND"
                       " rule LIKE 'trajectories_%%' AND on_failure = 'inconclusive'") == 3);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks WHERE on_failure = 'fail'") == 5);
    ENSURE(dbt_int(db, "SELECT count(*) FROM run_verdicts WHERE run_id = 1 AND"
                       " verdict = 'inconclusive' AND checks_inconclusive = 1") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM check_results WHERE rule = 'trajectories_max_time'"
                       " AND verdict = 'inconclusive'") == 1);
    sqlite3_close(db);
}

/* The upgrade is one transaction: failing at its last step leaves the file at
 * version 2 without the new columns. */
TEST(store_failed_upgrade_from_version_2_leaves_the_file_as_it_was)
{
    const char *path = copy_fixture(V2_FIXTURE, "v2-fail.db");
    sqlite3 *db = open_raw(path);
    exec_raw(db, "CREATE TRIGGER refuse BEFORE UPDATE ON rockfall_schema"
                 " BEGIN SELECT RAISE(ABORT, 'refused by a test'); END");
    char *before = v2_dump(db);
    sqlite3_close(db);
    rf_store *s = NULL;
    rf_error err = {0};
    ENSURE(rf_store_open(path, &s, &err) != 0 && s == NULL);
    ENSURE_MSG(strstr(err.message, "from schema version 2") &&
                   strstr(err.message, "refused by a test"), "%s", err.message);
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 2);
    ENSURE(dbt_int(db, "PRAGMA user_version") == 2);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_table_info('trajectories')"
                       " WHERE name = 'rest_steep'") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_table_info('checks')"
                       " WHERE name = 'on_failure'") == 0);
    char *after = v2_dump(db);
    ENSURE(strcmp(before, after) == 0);
    sqlite3_close(db);
    free(before);
    free(after);
}

#define V3_FIXTURE "tests/data/results-v3.db"

/* Version 3 to 4 in place, in one transaction: every row kept in its columns (the
 * version-2 dump's columns and rest_steep), the old trajectories' drawn mass and start
 * NULL, the views current; a later run's trajectories store their mass and start. */
TEST(store_upgrades_a_version_3_file_in_place)
{
    const char *path = copy_fixture(V3_FIXTURE, "v3.db");
    sqlite3 *db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 3);
    ENSURE(!has_column(db, "trajectories", "mass_kg"));
    char *before = v2_dump(db);
    char *steep_before = dump(db, "SELECT group_concat(quote(rest_steep)) FROM trajectories");
    long n = dbt_int(db, "SELECT count(*) FROM trajectories");
    ENSURE(n > 0);
    sqlite3_close(db);

    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == RF_SCHEMA_VERSION);
    ENSURE(dbt_int(db, "PRAGMA user_version") == RF_GPKG_USER_VERSION);
    ENSURE(has_column(db, "trajectories", "mass_kg") && has_column(db, "trajectories", "start_x") &&
           has_column(db, "trajectories", "start_y") && has_column(db, "trajectories", "start_z"));
    char *after = v2_dump(db);
    char *steep_after = dump(db, "SELECT group_concat(quote(rest_steep)) FROM trajectories");
    ENSURE_MSG(strcmp(before, after) == 0, "%s\n%s", before, after);
    ENSURE(strcmp(steep_before, steep_after) == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE mass_kg IS NULL AND start_x IS"
                       " NULL AND start_y IS NULL AND start_z IS NULL") == n);
    /* and on to version 5: no source cell, no number of cells in the old rows */
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE source_cell IS NULL") == n);
    ENSURE(dbt_int(db, "SELECT count(*) FROM releases WHERE n_cells IS NOT NULL") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_check") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM run_verdicts") == 1);
    sqlite3_close(db);
    free(before);
    free(after);
    free(steep_before);
    free(steep_after);
}

#define V4_FIXTURE "tests/data/results-v4.db"

/* Version 4 to 5 in place: the file a GeoPackage (its layers filled from the run
 * already there), the calibration tables added, empty; every row kept in its columns,
 * trajectories.source_cell and releases.n_cells NULL in them, runs.store 'all' and
 * runs.host, ranks and threads NULL. */
TEST(store_upgrades_a_version_4_file_in_place)
{
    const char *path = copy_fixture(V4_FIXTURE, "v4.db");
    sqlite3 *db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 4);
    ENSURE(dbt_int(db, "SELECT count(*) FROM sqlite_master WHERE name = 'calibrations'") == 0);
    char *before = v2_dump(db);
    char *starts = dump(db, "SELECT group_concat(quote(mass_kg) || quote(start_x)) FROM trajectories");
    sqlite3_close(db);

    rf_store_close(open_store(path));
    db = open_raw(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 5);
    ENSURE(dbt_int(db, "PRAGMA user_version") == RF_GPKG_USER_VERSION);
    ENSURE(dbt_int(db, "PRAGMA application_id") == 0x47504B47);
    ENSURE(dbt_int(db, "SELECT count(*) FROM stop_points") ==
           dbt_int(db, "SELECT count(*) FROM trajectories"));
    ENSURE(has_column(db, "calibrations", "objective") && has_column(db, "calibrations", "value") &&
           has_column(db, "calibration_values", "key"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM calibrations") == 0);
    char *after = v2_dump(db);
    char *starts_after =
        dump(db, "SELECT group_concat(quote(mass_kg) || quote(start_x)) FROM trajectories");
    ENSURE_MSG(strcmp(before, after) == 0, "%s\n%s", before, after);
    ENSURE(strcmp(starts, starts_after) == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_check") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM trajectories WHERE source_cell IS NULL") ==
           dbt_int(db, "SELECT count(*) FROM trajectories"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM releases WHERE n_cells IS NULL") ==
           dbt_int(db, "SELECT count(*) FROM releases"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE store = 'all' AND host IS NULL AND"
                       " ranks IS NULL AND threads IS NULL") == 1);
    sqlite3_close(db);
    free(before);
    free(after);
    free(starts);
    free(starts_after);
}
