/* store.c - the SQLite results database (DESIGN.md section 4, docs/database.md).
 *
 * Every SQLite return code passes through sql_status(), the one place where it
 * becomes the rf_error convention (0 or -1 with a message naming the file).  The
 * statements of the hot path are prepared once in rf_store_open and reset and bound
 * per row. */
#include "results/store.h"

#include <assert.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rockfall/version.h"
#include "base/util.h"

#define RF_STR_(x) #x
#define RF_STR(x) RF_STR_(x)

/* How long a writer waits for another connection's lock before giving up. */
#define RF_STORE_BUSY_TIMEOUT_MS 10000

/* The schema of version RF_STORE_SCHEMA_VERSION.  Ids of the rows of a run follow
 * the order of the project's arrays; every row of a run carries its run_id, except
 * path points and classifications, which belong to a trajectory and an
 * interception.  Real columns are nullable: SQLite stores a NaN as NULL. */
static const char schema_sql[] =
    "CREATE TABLE runs (\n"
    "  id INTEGER PRIMARY KEY AUTOINCREMENT,\n"
    "  project TEXT NOT NULL,\n"
    "  project_path TEXT,\n"
    "  seed NOT NULL,  -- integer; a seed above 2^63-1 as its decimal text\n"
    "  status TEXT NOT NULL CHECK (status IN ('running', 'complete', 'failed')),\n"
    "  started_at TEXT NOT NULL,\n"
    "  finished_at TEXT,\n"
    "  n_trajectories INTEGER NOT NULL CHECK (n_trajectories >= 0),\n"
    "  version TEXT NOT NULL,\n"
    "  project_yaml TEXT\n"
    ");\n"
    "CREATE TABLE releases (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  idx INTEGER NOT NULL,\n"
    "  name TEXT NOT NULL,\n"
    "  x REAL, y REAL, z REAL,\n"
    "  rock TEXT NOT NULL,\n"
    "  mass_kg REAL, radius_m REAL, density_kgm3 REAL,\n"
    "  action_level INTEGER NOT NULL CHECK (action_level BETWEEN 1 AND 3),\n"
    "  count INTEGER NOT NULL CHECK (count >= 0),\n"
    "  velocity_x REAL, velocity_y REAL, velocity_z REAL,\n"
    "  height_m REAL, jitter_m REAL,\n"
    "  UNIQUE (run_id, idx)\n"
    ");\n"
    "CREATE TABLE measures (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  idx INTEGER NOT NULL,\n"
    "  name TEXT NOT NULL,\n"
    "  kind TEXT NOT NULL CHECK (kind IN ('barrier', 'embankment', 'control')),\n"
    "  importance TEXT NOT NULL,\n"
    "  height_m REAL,\n"
    "  behaviour TEXT NOT NULL CHECK (behaviour IN ('stop', 'collect')),\n"
    "  mel_kj REAL, sel_kj REAL,\n"
    "  cap_serviceability_kj REAL, cap_restorability_kj REAL,\n"
    "  cap_ultimate_kj REAL, cap_near_collapse_kj REAL,\n"
    "  line TEXT NOT NULL,\n"
    "  UNIQUE (run_id, idx)\n"
    ");\n"
    "CREATE TABLE trajectories (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  release_id INTEGER NOT NULL REFERENCES releases(id),\n"
    "  idx INTEGER NOT NULL,\n"
    "  stop_x REAL, stop_y REAL, stop_z REAL,\n"
    "  stop_reason TEXT NOT NULL\n"
    "    CHECK (stop_reason IN ('rest', 'exited', 'stopped', 'max_time')),\n"
    "  duration_s REAL, path_length_m REAL, max_energy_kj REAL,\n"
    "  n_impacts INTEGER, n_tree_hits INTEGER\n"
    ");\n"
    "CREATE UNIQUE INDEX trajectories_run ON trajectories(run_id, release_id, idx);\n"
    "CREATE INDEX trajectories_release ON trajectories(release_id);\n"
    "CREATE TABLE interceptions (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  trajectory_id INTEGER NOT NULL REFERENCES trajectories(id),\n"
    "  measure_id INTEGER NOT NULL REFERENCES measures(id),\n"
    "  t_s REAL, x REAL, y REAL, z REAL,\n"
    "  speed_ms REAL, energy_kj REAL, energy_trans_kj REAL, energy_rot_kj REAL,\n"
    "  passing_height_m REAL,\n"
    "  outcome TEXT NOT NULL\n"
    "    CHECK (outcome IN ('stopped', 'overtopped', 'broke_through', 'passed'))\n"
    ");\n"
    "CREATE INDEX interceptions_run ON interceptions(run_id);\n"
    "CREATE INDEX interceptions_measure ON interceptions(measure_id);\n"
    "CREATE INDEX interceptions_trajectory ON interceptions(trajectory_id);\n"
    "CREATE TABLE classifications (\n"
    "  interception_id INTEGER NOT NULL REFERENCES interceptions(id),\n"
    "  action_level INTEGER,\n"
    "  importance TEXT,\n"
    "  limit_state TEXT,\n"
    "  required_state TEXT,\n"
    "  ok INTEGER CHECK (ok IN (0, 1))\n"
    ");\n"
    "CREATE INDEX classifications_interception ON classifications(interception_id);\n"
    "CREATE TABLE checks (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  measure_id INTEGER REFERENCES measures(id),\n"
    "  rule TEXT NOT NULL,\n"
    "  value REAL,\n"
    "  threshold REAL,\n"
    "  passed INTEGER CHECK (passed IN (0, 1))\n"
    ");\n"
    "CREATE INDEX checks_run ON checks(run_id);\n"
    "CREATE TABLE hazard_cells (\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  ix INTEGER NOT NULL, iy INTEGER NOT NULL,\n"
    "  x REAL, y REAL,\n"
    "  passes INTEGER,\n"
    "  reach_probability REAL,\n"
    "  energy_max_kj REAL, energy_p95_kj REAL, height_p95_m REAL,\n"
    "  PRIMARY KEY (run_id, ix, iy)\n"
    ");\n"
    "CREATE TABLE path_points (\n"
    "  trajectory_id INTEGER NOT NULL REFERENCES trajectories(id),\n"
    "  seq INTEGER NOT NULL,\n"
    "  t_s REAL, x REAL, y REAL, z REAL,\n"
    "  speed_ms REAL, energy_kj REAL,\n"
    "  PRIMARY KEY (trajectory_id, seq)\n"
    ") WITHOUT ROWID;\n"
    "CREATE TABLE tree_hits (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  trajectory_id INTEGER NOT NULL REFERENCES trajectories(id),\n"
    "  t_s REAL, x REAL, y REAL, z REAL,\n"
    "  speed_before_ms REAL, speed_after_ms REAL,\n"
    "  energy_lost_kj REAL\n"
    ");\n"
    "CREATE INDEX tree_hits_run ON tree_hits(run_id);\n"
    "CREATE INDEX tree_hits_trajectory ON tree_hits(trajectory_id);\n"
    "PRAGMA user_version = " RF_STR(RF_STORE_SCHEMA_VERSION) ";\n";

/* Views for the questions planners ask (docs/database.md, README).  Part of every
 * database: created with the schema, and on opening a file made before they existed.
 * IF NOT EXISTS makes this a no-op on a file that has them. */
static const char views_sql[] =
    "CREATE VIEW IF NOT EXISTS classified_interceptions AS\n"
    "SELECT i.run_id, i.id AS interception_id, m.id AS measure_id, m.name AS measure,\n"
    "  m.kind, r.name AS release, r.action_level, m.importance, i.energy_kj,\n"
    "  i.passing_height_m, i.outcome, c.limit_state, c.required_state, c.ok\n"
    "FROM interceptions i\n"
    "JOIN measures m ON m.id = i.measure_id\n"
    "JOIN trajectories t ON t.id = i.trajectory_id\n"
    "JOIN releases r ON r.id = t.release_id\n"
    "LEFT JOIN classifications c ON c.interception_id = i.id;\n"
    "CREATE VIEW IF NOT EXISTS measure_summary AS\n"
    "SELECT m.run_id, m.id AS measure_id, m.idx, m.name AS measure, m.kind, m.importance,\n"
    "  m.height_m, m.mel_kj, m.sel_kj,\n"
    "  count(i.id) AS interceptions,\n"
    "  max(i.energy_kj) AS energy_max_kj, avg(i.energy_kj) AS energy_mean_kj,\n"
    "  max(i.passing_height_m) AS height_max_m,\n"
    "  coalesce(sum(i.outcome = 'stopped'), 0) AS stopped,\n"
    "  coalesce(sum(i.outcome = 'overtopped'), 0) AS overtopped,\n"
    "  coalesce(sum(i.outcome = 'broke_through'), 0) AS broke_through,\n"
    "  coalesce(sum(i.outcome = 'passed'), 0) AS passed,\n"
    "  count(c.interception_id) AS classified,\n"
    "  avg(CASE WHEN c.interception_id IS NOT NULL\n"
    "      THEN coalesce(c.limit_state = 'serviceability', 0) END) AS share_serviceability,\n"
    "  avg(c.ok) AS share_meeting_required,\n"
    "  (SELECT count(*) FROM checks k WHERE k.measure_id = m.id) AS checks,\n"
    "  (SELECT count(*) FROM checks k WHERE k.measure_id = m.id AND k.passed = 0)\n"
    "    AS checks_failed\n"
    "FROM measures m\n"
    "LEFT JOIN interceptions i ON i.measure_id = m.id\n"
    "LEFT JOIN classifications c ON c.interception_id = i.id\n"
    "GROUP BY m.id;\n"
    "CREATE VIEW IF NOT EXISTS limit_state_shares AS\n"
    "SELECT i.run_id, m.id AS measure_id, m.name AS measure, c.limit_state,\n"
    "  count(*) AS interceptions,\n"
    "  count(*) * 1.0 / (SELECT count(*) FROM interceptions j WHERE j.measure_id = m.id)\n"
    "    AS share\n"
    "FROM classifications c\n"
    "JOIN interceptions i ON i.id = c.interception_id\n"
    "JOIN measures m ON m.id = i.measure_id\n"
    "GROUP BY m.id, c.limit_state;\n"
    "CREATE VIEW IF NOT EXISTS check_results AS\n"
    "SELECT k.run_id, k.id AS check_id, k.measure_id, m.name AS measure, m.kind, k.rule,\n"
    "  k.value, k.threshold, k.passed,\n"
    "  CASE k.passed WHEN 1 THEN 'pass' ELSE 'fail' END AS verdict\n"
    "FROM checks k LEFT JOIN measures m ON m.id = k.measure_id;\n"
    "CREATE VIEW IF NOT EXISTS run_verdicts AS\n"
    "SELECT run_id, project, status, started_at, checks, checks_failed,\n"
    "  CASE WHEN checks = 0 THEN 'unchecked' WHEN checks_failed > 0 THEN 'fail'\n"
    "       ELSE 'pass' END AS verdict\n"
    "FROM (SELECT r.id AS run_id, r.project, r.status, r.started_at,\n"
    "        coalesce(k.n, 0) AS checks, coalesce(k.failed, 0) AS checks_failed\n"
    "      FROM runs r\n"
    "      LEFT JOIN (SELECT run_id, count(*) AS n, sum(passed = 0) AS failed\n"
    "                 FROM checks GROUP BY run_id) k ON k.run_id = r.id);\n";

#define RF_NOW_SQL "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"

enum {
    ST_BEGIN, ST_COMMIT, ST_ROLLBACK,
    ST_RUN, ST_RELEASE, ST_MEASURE, ST_FINISH,
    ST_TRAJECTORY, ST_PATH_POINT, ST_INTERCEPTION, ST_TREE_HIT, ST_HAZARD_CELL,
    ST_COUNT
};

static const char *const statement_sql[ST_COUNT] = {
    [ST_BEGIN] = "BEGIN IMMEDIATE",
    [ST_COMMIT] = "COMMIT",
    [ST_ROLLBACK] = "ROLLBACK",
    [ST_RUN] = "INSERT INTO runs (project, project_path, seed, status, started_at,"
               " n_trajectories, version, project_yaml)"
               " VALUES (?1, ?2, ?3, 'running', " RF_NOW_SQL ", ?4, ?5, ?6)",
    [ST_RELEASE] = "INSERT INTO releases (run_id, idx, name, x, y, z, rock, mass_kg,"
                   " radius_m, density_kgm3, action_level, count, velocity_x,"
                   " velocity_y, velocity_z, height_m, jitter_m)"
                   " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13,"
                   " ?14, ?15, ?16, ?17)",
    [ST_MEASURE] = "INSERT INTO measures (run_id, idx, name, kind, importance, height_m,"
                   " behaviour, mel_kj, sel_kj, cap_serviceability_kj,"
                   " cap_restorability_kj, cap_ultimate_kj, cap_near_collapse_kj, line)"
                   " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)",
    [ST_FINISH] = "UPDATE runs SET status = ?1, finished_at = " RF_NOW_SQL ","
                  " n_trajectories = coalesce(?2, n_trajectories) WHERE id = ?3",
    [ST_TRAJECTORY] = "INSERT INTO trajectories (run_id, release_id, idx, stop_x, stop_y,"
                      " stop_z, stop_reason, duration_s, path_length_m, max_energy_kj,"
                      " n_impacts, n_tree_hits)"
                      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)",
    [ST_PATH_POINT] = "INSERT INTO path_points (trajectory_id, seq, t_s, x, y, z,"
                      " speed_ms, energy_kj) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
    [ST_INTERCEPTION] = "INSERT INTO interceptions (run_id, trajectory_id, measure_id,"
                        " t_s, x, y, z, speed_ms, energy_kj, energy_trans_kj,"
                        " energy_rot_kj, passing_height_m, outcome)"
                        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)",
    [ST_TREE_HIT] = "INSERT INTO tree_hits (run_id, trajectory_id, t_s, x, y, z,"
                    " speed_before_ms, speed_after_ms, energy_lost_kj)"
                    " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
    [ST_HAZARD_CELL] = "INSERT INTO hazard_cells (run_id, ix, iy, x, y, passes,"
                       " reach_probability, energy_max_kj, energy_p95_kj, height_p95_m)"
                       " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
};

struct rf_store {
    sqlite3 *db;
    char *path;
    sqlite3_stmt *stmt[ST_COUNT];
    int64_t run_id;          /* 0 before the first rf_store_run_begin */
    int64_t *release_ids;    /* by project release index */
    size_t nreleases;
    int64_t *measure_ids;    /* by project measure index */
    size_t nmeasures;
};

/* The one place SQLite's return codes become the rf_error convention: 0 for success
 * (SQLITE_OK, SQLITE_ROW, SQLITE_DONE), otherwise -1 with "doing: sqlite's message"
 * and the database file named in err. */
static int sql_status(sqlite3 *db, const char *path, int rc, const char *doing, rf_error *err)
{
    if (rc == SQLITE_OK || rc == SQLITE_ROW || rc == SQLITE_DONE)
        return 0;
    const char *why = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
    return rf_error_set(err, path, 0, 0, "%s: %s", doing, why);
}

static int exec_sql(rf_store *s, const char *sql, const char *doing, rf_error *err)
{
    return sql_status(s->db, s->path, sqlite3_exec(s->db, sql, NULL, NULL, NULL), doing, err);
}

/* Runs a prepared statement that returns no rows, and resets it for the next use. */
static int step_statement(rf_store *s, int which, const char *doing, rf_error *err)
{
    sqlite3_stmt *st = s->stmt[which];
    int status = sql_status(s->db, s->path, sqlite3_step(st), doing, err);
    sqlite3_reset(st);
    return status;
}

/* Drops the open transaction's rows: a batch's, or a run's start (nothing when none
 * is open). */
static void batch_rollback(rf_store *s)
{
    if (!sqlite3_get_autocommit(s->db))
        step_statement(s, ST_ROLLBACK, "rolling back a batch", NULL);
}

/* Binding fails only on a programmer's error (bad index, statement in use). */
static void bind_int(sqlite3_stmt *st, int col, int64_t v)
{
    int rc = sqlite3_bind_int64(st, col, v);
    assert(rc == SQLITE_OK);
    (void)rc;
}

static void bind_real(sqlite3_stmt *st, int col, double v)
{
    int rc = sqlite3_bind_double(st, col, v);
    assert(rc == SQLITE_OK);
    (void)rc;
}

/* The x, y and z of a vector into parameters i, i + 1 and i + 2. */
static void bind_vec3(sqlite3_stmt *st, int i, rf_vec3 p)
{
    bind_real(st, i, p.x);
    bind_real(st, i + 1, p.y);
    bind_real(st, i + 2, p.z);
}

/* A value that is NULL when negative: a capacity that was not given. */
static void bind_given(sqlite3_stmt *st, int col, double v)
{
    int rc = v < 0.0 ? sqlite3_bind_null(st, col) : sqlite3_bind_double(st, col, v);
    assert(rc == SQLITE_OK);
    (void)rc;
}

/* Text that lives until the statement has been stepped. */
static void bind_text(sqlite3_stmt *st, int col, const char *v)
{
    int rc = v ? sqlite3_bind_text(st, col, v, -1, SQLITE_STATIC) : sqlite3_bind_null(st, col);
    assert(rc == SQLITE_OK);
    (void)rc;
}

/* ---- opening ----------------------------------------------------------------- */

/* user_version and the number of objects in the schema; fails on a non-database. */
static int read_schema_state(rf_store *s, int *version, int *nobjects, rf_error *err)
{
    static const char sql[] = "SELECT (SELECT user_version FROM pragma_user_version),"
                              " (SELECT count(*) FROM sqlite_master)";
    const char *doing = "reading the results database";
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(s->db, sql, -1, &st, NULL);
    if (rc == SQLITE_OK) {
        rc = sqlite3_step(st);
        if (rc == SQLITE_ROW) {
            *version = sqlite3_column_int(st, 0);
            *nobjects = sqlite3_column_int(st, 1);
        }
    }
    int status = sql_status(s->db, s->path, rc, doing, err);
    sqlite3_finalize(st);
    return status;
}

/* Switches the file to the WAL journal.  The switch needs the file to itself, and
 * SQLite returns "locked" at once, without waiting, when another connection opening
 * the file at the same moment holds it too: tried again until the busy timeout has
 * passed (each try may itself wait in the busy handler). */
static int set_wal(rf_store *s, rf_error *err)
{
    struct timespec pause = {0, 5 * 1000 * 1000};
    double deadline = rf_now_s() + RF_STORE_BUSY_TIMEOUT_MS / 1000.0;
    int rc;
    while ((rc = sqlite3_exec(s->db, "PRAGMA journal_mode = WAL", NULL, NULL, NULL)) ==
               SQLITE_BUSY ||
           rc == SQLITE_LOCKED) {
        if (rf_now_s() > deadline)
            break;
        nanosleep(&pause, NULL);
    }
    return sql_status(s->db, s->path, rc, "setting the WAL journal", err);
}

static int version_error(rf_store *s, int version, rf_error *err)
{
    return rf_error_set(err, s->path, 0, 0,
                        "results database schema version %d; rockfall %s reads schema "
                        "version %d",
                        version, ROCKFALL_VERSION, RF_STORE_SCHEMA_VERSION);
}

/* Ends the transaction begun by BEGIN IMMEDIATE: committed after status 0, else
 * rolled back; returns the status. */
static int end_transaction(rf_store *s, int status, const char *doing, rf_error *err)
{
    if (status == 0)
        status = exec_sql(s, "COMMIT", doing, err);
    if (status != 0 && !sqlite3_get_autocommit(s->db))
        sqlite3_exec(s->db, "ROLLBACK", NULL, NULL, NULL);
    return status;
}

/* Brings the views of a database of this schema version up to date: each view whose
 * stored definition differs from this version's (both as SQLite stores them: the
 * current ones are made in a scratch database in memory) is dropped, and the missing
 * ones are created.  Views hold no data: a file written by an earlier rockfall kept
 * its old measure_summary, without the columns the report and docs name.  A file
 * whose views are current is not written to. */
static int refresh_views(rf_store *s, rf_error *err)
{
    static const char list[] = "SELECT name, sql FROM sqlite_master WHERE type = 'view'";
    const char *doing = "updating the views";
    sqlite3 *mem = NULL;
    sqlite3_stmt *cur = NULL, *old = NULL;
    char *drops = NULL; /* the DROP statements of the views that differ */
    int stale = 0, rc = sqlite3_open(":memory:", &mem);
    if (rc == SQLITE_OK) /* a view is stored as written: it needs none of the tables */
        rc = sqlite3_exec(mem, views_sql, NULL, NULL, NULL);
    if (rc != SQLITE_OK) {
        /* a fault of this build, not of the file */
        rc = rf_error_set(err, s->path, 0, 0, "%s: %s", doing,
                          mem ? sqlite3_errmsg(mem) : "out of memory");
        sqlite3_close(mem);
        return rc;
    }
    rc = sqlite3_prepare_v2(mem, list, -1, &cur, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(s->db, "SELECT sql FROM sqlite_master WHERE type = 'view' AND name = ?",
                                -1, &old, NULL);
    while (rc == SQLITE_OK && (rc = sqlite3_step(cur)) == SQLITE_ROW) {
        const char *name = (const char *)sqlite3_column_text(cur, 0);
        const char *sql = (const char *)sqlite3_column_text(cur, 1);
        sqlite3_bind_text(old, 1, name, -1, SQLITE_TRANSIENT);
        rc = sqlite3_step(old);
        if (rc == SQLITE_DONE) { /* missing */
            stale = 1;
            rc = SQLITE_OK;
        } else if (rc == SQLITE_ROW) {
            const char *have = (const char *)sqlite3_column_text(old, 0);
            rc = SQLITE_OK;
            if (!have || strcmp(have, sql) != 0) {
                char *more = sqlite3_mprintf("%sDROP VIEW IF EXISTS \"%w\";\n", drops ? drops : "", name);
                sqlite3_free(drops);
                drops = more;
                rc = more ? SQLITE_OK : SQLITE_NOMEM;
                stale = 1;
            }
        }
        sqlite3_reset(old);
    }
    if (rc == SQLITE_DONE)
        rc = SQLITE_OK;
    sqlite3_finalize(old);
    sqlite3_finalize(cur);
    sqlite3_close(mem);
    int status = sql_status(s->db, s->path, rc, doing, err);
    if (status == 0 && stale) {
        /* another process may have done it meanwhile: the drops are IF EXISTS and the
         * creations IF NOT EXISTS */
        status = exec_sql(s, "BEGIN IMMEDIATE", doing, err);
        if (status == 0 && drops)
            status = exec_sql(s, drops, doing, err);
        if (status == 0)
            status = exec_sql(s, views_sql, doing, err);
        status = end_transaction(s, status, doing, err);
    }
    sqlite3_free(drops);
    return status;
}

/* Checks the version of an existing database or creates the schema of a new (empty)
 * one.  Nothing is written to a file that is rejected. */
static int prepare_schema(rf_store *s, rf_error *err)
{
    int version = 0, nobjects = 0;
    if (read_schema_state(s, &version, &nobjects, err))
        return -1;
    if (version == RF_STORE_SCHEMA_VERSION)
        return set_wal(s, err) || refresh_views(s, err) ? -1 : 0;
    if (version != 0)
        return version_error(s, version, err);
    if (nobjects != 0)
        return rf_error_set(err, s->path, 0, 0,
                            "not a rockfall results database (an SQLite database with "
                            "%d schema objects and no rockfall schema version)",
                            nobjects);

    /* An empty database: create the schema, unless another process just did. */
    if (set_wal(s, err) ||
        exec_sql(s, "BEGIN IMMEDIATE", "creating the schema", err))
        return -1;
    int status = read_schema_state(s, &version, &nobjects, err);
    if (status == 0 && version == 0 && nobjects == 0)
        status = exec_sql(s, schema_sql, "creating the schema", err) ||
                         exec_sql(s, views_sql, "creating the views", err)
                     ? -1
                     : 0;
    else if (status == 0 && version != RF_STORE_SCHEMA_VERSION)
        status = version_error(s, version, err);
    return end_transaction(s, status, "creating the schema", err);
}

int rf_store_open(const char *path, rf_store **out, rf_error *err)
{
    *out = NULL;
    rf_store *s = calloc(1, sizeof *s);
    if (!s || !(s->path = strdup(path))) {
        free(s);
        return rf_error_set(err, path, 0, 0, "out of memory opening the results database");
    }
    int rc = sqlite3_open_v2(path, &s->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, NULL);
    if (sql_status(s->db, s->path, rc, "opening the results database", err))
        goto fail;
    sqlite3_busy_timeout(s->db, RF_STORE_BUSY_TIMEOUT_MS);
    if (prepare_schema(s, err) ||
        exec_sql(s, "PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON",
                 "configuring the results database", err))
        goto fail;
    for (int i = 0; i < ST_COUNT; i++) {
        rc = sqlite3_prepare_v3(s->db, statement_sql[i], -1, SQLITE_PREPARE_PERSISTENT,
                                &s->stmt[i], NULL);
        if (sql_status(s->db, s->path, rc, "preparing the results database", err))
            goto fail;
    }
    *out = s;
    return 0;
fail:
    rf_store_close(s);
    return -1;
}

void rf_store_close(rf_store *s)
{
    if (!s)
        return;
    for (int i = 0; i < ST_COUNT; i++)
        sqlite3_finalize(s->stmt[i]);
    /* An open batch is rolled back: its rows never reached the file. */
    if (s->db && !sqlite3_get_autocommit(s->db))
        sqlite3_exec(s->db, "ROLLBACK", NULL, NULL, NULL);
    sqlite3_close(s->db);
    free(s->release_ids);
    free(s->measure_ids);
    free(s->path);
    free(s);
}

sqlite3 *rf_store_db(rf_store *s)
{
    return s->db;
}

/* ---- runs -------------------------------------------------------------------- */

/* The shortest of %.15g .. %.17g that reads back as the same double. */
static int format_number(char *buf, size_t cap, double v)
{
    int n = 0;
    for (int digits = 15; digits <= 17; digits++) {
        n = snprintf(buf, cap, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return n;
}

/* A polyline as text: "[[x0,y0],[x1,y1],...]" (JSON, readable by SQLite's json1). */
static char *polyline_text(const rf_polyline *line)
{
    enum { NUMBER_MAX = 32 };
    size_t cap = 3 + line->n * (2 * NUMBER_MAX + 4);
    char *text = malloc(cap);
    if (!text)
        return NULL;
    size_t len = 0;
    text[len++] = '[';
    for (size_t i = 0; i < line->n; i++) {
        char x[NUMBER_MAX], y[NUMBER_MAX];
        format_number(x, sizeof x, line->xy[2 * i]);
        format_number(y, sizeof y, line->xy[2 * i + 1]);
        len += (size_t)snprintf(text + len, cap - len, "%s[%s,%s]", i ? "," : "", x, y);
    }
    snprintf(text + len, cap - len, "]");
    return text;
}

static int insert_run_row(rf_store *s, const rf_project *p, long n_trajectories, rf_error *err)
{
    sqlite3_stmt *st = s->stmt[ST_RUN];
    bind_text(st, 1, p->name);
    /* absolute, so that check and report find the project from any folder */
    char *abs_path = realpath(p->path, NULL);
    bind_text(st, 2, abs_path ? abs_path : p->path);
    assert(p->seed <= (uint64_t)INT64_MAX); /* the loader and --seed allow no more */
    bind_int(st, 3, (int64_t)p->seed);
    bind_int(st, 4, n_trajectories);
    bind_text(st, 5, ROCKFALL_VERSION);
    bind_text(st, 6, p->yaml_text);
    int failed = step_statement(s, ST_RUN, "writing the run", err);
    free(abs_path);
    if (failed)
        return -1;
    s->run_id = sqlite3_last_insert_rowid(s->db);
    return 0;
}

static int insert_release_row(rf_store *s, const rf_project *p, size_t i, rf_error *err)
{
    const rf_release *r = &p->releases[i];
    assert(r->rock >= 0 && (size_t)r->rock < p->nrocks);
    const rf_rock *rock = &p->rocks[r->rock];
    sqlite3_stmt *st = s->stmt[ST_RELEASE];
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, (int64_t)i);
    bind_text(st, 3, r->name);
    bind_real(st, 4, r->x);
    bind_real(st, 5, r->y);
    bind_real(st, 6, r->z);
    bind_text(st, 7, rock->name);
    bind_real(st, 8, rock->mass);
    bind_real(st, 9, rock->radius);
    bind_real(st, 10, rock->density);
    bind_int(st, 11, rock->action_level);
    bind_int(st, 12, r->count);
    bind_vec3(st, 13, r->velocity);
    bind_real(st, 16, r->height);
    bind_real(st, 17, r->jitter);
    if (step_statement(s, ST_RELEASE, "writing a release", err))
        return -1;
    s->release_ids[i] = sqlite3_last_insert_rowid(s->db);
    return 0;
}

static int insert_measure_row(rf_store *s, const rf_project *p, size_t i, rf_error *err)
{
    const rf_measure *m = &p->measures[i];
    char *line = polyline_text(&m->line);
    if (!line)
        return rf_error_set(err, s->path, 0, 0, "out of memory writing measure '%s'", m->name);
    sqlite3_stmt *st = s->stmt[ST_MEASURE];
    int barrier = m->kind == RF_BARRIER;
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, (int64_t)i);
    bind_text(st, 3, m->name);
    bind_text(st, 4, rf_measure_kind_name(m->kind));
    bind_text(st, 5, rf_importance_name(m->importance));
    bind_real(st, 6, m->height);
    bind_text(st, 7, rf_behaviour_name(m->behaviour));
    bind_given(st, 8, barrier ? m->mel : -1.0);
    bind_given(st, 9, barrier ? m->sel : -1.0);
    for (int k = 0; k < RF_N_LIMIT_STATES; k++)
        bind_given(st, 10 + k, m->capacity[k]);
    bind_text(st, 14, line);
    int status = step_statement(s, ST_MEASURE, "writing a measure", err);
    free(line);
    if (status)
        return -1;
    s->measure_ids[i] = sqlite3_last_insert_rowid(s->db);
    return 0;
}

int rf_store_run_begin(rf_store *s, const rf_project *p, long n_trajectories,
                       int64_t *run_id, rf_error *err)
{
    assert(sqlite3_get_autocommit(s->db) && "rf_store_run_begin inside a batch");
    free(s->release_ids);
    free(s->measure_ids);
    s->run_id = 0;
    s->nreleases = p->nreleases;
    s->nmeasures = p->nmeasures;
    s->release_ids = calloc(p->nreleases + 1, sizeof *s->release_ids);
    s->measure_ids = calloc(p->nmeasures + 1, sizeof *s->measure_ids);
    if (!s->release_ids || !s->measure_ids)
        return rf_error_set(err, s->path, 0, 0, "out of memory starting a run");

    if (step_statement(s, ST_BEGIN, "starting a run", err))
        return -1;
    int status = insert_run_row(s, p, n_trajectories, err);
    for (size_t i = 0; status == 0 && i < p->nreleases; i++)
        status = insert_release_row(s, p, i, err);
    for (size_t i = 0; status == 0 && i < p->nmeasures; i++)
        status = insert_measure_row(s, p, i, err);
    if (status == 0)
        status = step_statement(s, ST_COMMIT, "starting a run", err);
    if (status != 0) {
        batch_rollback(s);
        s->run_id = 0;
        return -1;
    }
    if (run_id)
        *run_id = s->run_id;
    return 0;
}

int rf_store_run_finish(rf_store *s, const char *status, long n_trajectories, rf_error *err)
{
    if (!status || (strcmp(status, "complete") != 0 && strcmp(status, "failed") != 0))
        return rf_error_set(err, s->path, 0, 0,
                            "a run ends 'complete' or 'failed', not '%s'",
                            status ? status : "(null)");
    assert(s->run_id > 0 && "rf_store_run_finish without a run");
    int committed = 0;
    if (!sqlite3_get_autocommit(s->db))
        committed = rf_store_batch_commit(s, err);
    if (committed != 0)
        status = "failed"; /* rows were lost: the run cannot be complete */

    sqlite3_stmt *st = s->stmt[ST_FINISH];
    bind_text(st, 1, status);
    if (n_trajectories >= 0)
        bind_int(st, 2, n_trajectories);
    else
        sqlite3_bind_null(st, 2);
    bind_int(st, 3, s->run_id);
    /* The first error is the one reported. */
    int finished = step_statement(s, ST_FINISH, "finishing the run",
                                  committed == 0 ? err : NULL);
    return committed != 0 || finished != 0 ? -1 : 0;
}

int rf_store_batch_begin(rf_store *s, rf_error *err)
{
    assert(sqlite3_get_autocommit(s->db) && "nested batch");
    return step_statement(s, ST_BEGIN, "starting a batch", err);
}

/* One statement of a batch (a row, or the commit); one that fails rolls the open batch
 * back: a batch is all or none. */
static int step_in_batch(rf_store *s, int which, const char *doing, rf_error *err)
{
    if (step_statement(s, which, doing, err) == 0)
        return 0;
    batch_rollback(s);
    return -1;
}

int rf_store_batch_commit(rf_store *s, rf_error *err)
{
    return step_in_batch(s, ST_COMMIT, "committing a batch", err);
}

/* ---- rows of a run ------------------------------------------------------------- */

int rf_store_add_trajectory(rf_store *s, size_t release_index, long idx,
                            const rf_trajectory_record *r, int64_t *trajectory_id,
                            rf_error *err)
{
    assert(s->run_id > 0 && release_index < s->nreleases);
    sqlite3_stmt *st = s->stmt[ST_TRAJECTORY];
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, s->release_ids[release_index]);
    bind_int(st, 3, idx);
    bind_vec3(st, 4, r->stop);
    bind_text(st, 7, rf_stop_reason_name(r->reason));
    bind_real(st, 8, r->duration_s);
    bind_real(st, 9, r->path_length_m);
    bind_real(st, 10, r->max_energy_kj);
    bind_int(st, 11, r->n_impacts);
    bind_int(st, 12, r->n_tree_hits);
    if (step_in_batch(s, ST_TRAJECTORY, "writing a trajectory", err))
        return -1;
    if (trajectory_id)
        *trajectory_id = sqlite3_last_insert_rowid(s->db);
    return 0;
}

int rf_store_add_path_point(rf_store *s, int64_t trajectory_id, long seq,
                            const rf_path_point *pt, rf_error *err)
{
    sqlite3_stmt *st = s->stmt[ST_PATH_POINT];
    bind_int(st, 1, trajectory_id);
    bind_int(st, 2, seq);
    bind_real(st, 3, pt->t_s);
    bind_vec3(st, 4, pt->p);
    bind_real(st, 7, pt->speed_ms);
    bind_real(st, 8, pt->energy_kj);
    return step_in_batch(s, ST_PATH_POINT, "writing a path point", err);
}

int rf_store_add_interception(rf_store *s, int64_t trajectory_id,
                              const rf_interception_record *r, int64_t *interception_id,
                              rf_error *err)
{
    assert(s->run_id > 0 && r->measure >= 0 && (size_t)r->measure < s->nmeasures);
    sqlite3_stmt *st = s->stmt[ST_INTERCEPTION];
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, trajectory_id);
    bind_int(st, 3, s->measure_ids[r->measure]);
    bind_real(st, 4, r->t_s);
    bind_vec3(st, 5, r->p);
    bind_real(st, 8, r->speed_ms);
    bind_real(st, 9, r->energy_kj);
    bind_real(st, 10, r->energy_trans_kj);
    bind_real(st, 11, r->energy_rot_kj);
    bind_real(st, 12, r->passing_height_m);
    bind_text(st, 13, rf_outcome_name(r->outcome));
    if (step_in_batch(s, ST_INTERCEPTION, "writing an interception", err))
        return -1;
    if (interception_id)
        *interception_id = sqlite3_last_insert_rowid(s->db);
    return 0;
}

int rf_store_add_tree_hit(rf_store *s, int64_t trajectory_id, const rf_tree_hit_record *r,
                          rf_error *err)
{
    assert(s->run_id > 0);
    sqlite3_stmt *st = s->stmt[ST_TREE_HIT];
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, trajectory_id);
    bind_real(st, 3, r->t_s);
    bind_vec3(st, 4, r->p);
    bind_real(st, 7, r->speed_before_ms);
    bind_real(st, 8, r->speed_after_ms);
    bind_real(st, 9, r->energy_lost_kj);
    return step_in_batch(s, ST_TREE_HIT, "writing a tree hit", err);
}

int rf_store_add_hazard_cell(rf_store *s, const rf_hazard_cell_record *r, rf_error *err)
{
    assert(s->run_id > 0);
    sqlite3_stmt *st = s->stmt[ST_HAZARD_CELL];
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, r->ix);
    bind_int(st, 3, r->iy);
    bind_real(st, 4, r->x);
    bind_real(st, 5, r->y);
    bind_int(st, 6, r->passes);
    bind_real(st, 7, r->reach_probability);
    bind_real(st, 8, r->energy_max_kj);
    bind_real(st, 9, r->energy_p95_kj);
    bind_real(st, 10, r->height_p95_m);
    return step_in_batch(s, ST_HAZARD_CELL, "writing a hazard cell", err);
}

/* ---- ids ------------------------------------------------------------------------ */

int64_t rf_store_run_id(const rf_store *s)
{
    return s->run_id;
}

int64_t rf_store_release_id(const rf_store *s, size_t release_index)
{
    assert(release_index < s->nreleases);
    return s->release_ids[release_index];
}

int64_t rf_store_measure_id(const rf_store *s, size_t measure_index)
{
    assert(measure_index < s->nmeasures);
    return s->measure_ids[measure_index];
}
