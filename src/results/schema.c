/* schema.c - the results database's schema, its versions and the ways to open a file
 * (docs/database.md "Schema policy").
 *
 * Version 1 was marked by PRAGMA user_version alone; from version 2 the version is the
 * row of the table rockfall_schema, which also marks the file as ours (user_version
 * keeps the number too, so that an older rockfall refuses the file).  `run` creates the
 * schema in an empty file or upgrades an older one in one transaction; `check` opens a
 * file of any version it reads without changing its schema; `report` opens it
 * read-only. */
#include "results/schema.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/util.h"
#include "input/measure_kinds.h"
#include "results/gpkg.h"
#include "results/integrity.h"
#include "results/schema_legacy.h"
#include "rockfall/version.h"

#define RF_STR_(x) #x
#define RF_STR(x) RF_STR_(x)

/* How long a writer waits for another connection's lock before giving up. */
#define RF_SCHEMA_BUSY_TIMEOUT_MS 10000

/* The columns version 2 adds to runs: what check and report need of the project
 * besides its rows (docs/database.md). */
#define RUNS_V2_COLUMNS \
    "  rules_path TEXT,\n" \
    "  surface_friction REAL,\n" \
    "  hazard_cell_m REAL\n"
#define RUNS_V2_ADD \
    "ALTER TABLE runs ADD COLUMN rules_path TEXT;\n" \
    "ALTER TABLE runs ADD COLUMN surface_friction REAL;\n" \
    "ALTER TABLE runs ADD COLUMN hazard_cell_m REAL;\n"

/* The measures table of version 2: its kind a row of measure_kinds (a foreign key
 * follows the kinds of later versions, which a CHECK written into a file cannot), a
 * barrier's SEL marked as given or defaulted. */
#define MEASURES_TABLE(name) \
    "CREATE TABLE " name " (\n" \
    "  id INTEGER PRIMARY KEY,\n" \
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n" \
    "  idx INTEGER NOT NULL,\n" \
    "  name TEXT NOT NULL,\n" \
    "  kind TEXT NOT NULL REFERENCES measure_kinds(name),\n" \
    "  importance TEXT NOT NULL,\n" \
    "  height_m REAL,\n" \
    "  behaviour TEXT NOT NULL CHECK (behaviour IN ('stop', 'collect')),\n" \
    "  mel_kj REAL, sel_kj REAL,\n" \
    "  cap_serviceability_kj REAL, cap_restorability_kj REAL,\n" \
    "  cap_ultimate_kj REAL, cap_near_collapse_kj REAL,\n" \
    "  line TEXT NOT NULL,\n" \
    "  sel_source TEXT CHECK (sel_source IN ('given', 'default: MEL/3')),\n" \
    "  UNIQUE (run_id, idx)\n" \
    ");\n"

#define KINDS_TABLE \
    "CREATE TABLE measure_kinds (\n" \
    "  name TEXT PRIMARY KEY,\n" \
    "  label TEXT NOT NULL,\n" \
    "  classified INTEGER NOT NULL CHECK (classified IN (0, 1)),\n" \
    "  reach_line INTEGER NOT NULL CHECK (reach_line IN (0, 1)),\n" \
    "  limit_states TEXT NOT NULL\n" \
    ");\n"

/* The tables version 2 adds: the terrain as the report draws it, the ground under
 * the line points nearest each release, and the rule file of each run's check. */
#define V2_TABLES \
    "CREATE TABLE terrain_grids (\n" \
    "  run_id INTEGER PRIMARY KEY REFERENCES runs(id),\n" \
    "  xmin REAL NOT NULL, xmax REAL NOT NULL, ymin REAL NOT NULL, ymax REAL NOT NULL,\n" \
    "  x0 REAL NOT NULL, y0 REAL NOT NULL, x1 REAL NOT NULL, y1 REAL NOT NULL,\n" \
    "  step REAL NOT NULL,\n" \
    "  nx INTEGER NOT NULL CHECK (nx >= 2), ny INTEGER NOT NULL CHECK (ny >= 2),\n" \
    "  z BLOB NOT NULL CHECK (length(z) = 8 * nx * ny)\n" \
    ");\n" \
    "CREATE TABLE ground_points (\n" \
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n" \
    "  release_id INTEGER NOT NULL REFERENCES releases(id),\n" \
    "  measure_id INTEGER NOT NULL REFERENCES measures(id),\n" \
    "  x REAL, y REAL, z REAL,\n" \
    "  PRIMARY KEY (release_id, measure_id)\n" \
    ");\n" \
    "CREATE INDEX ground_points_run ON ground_points(run_id);\n" \
    "CREATE TABLE check_rules (\n" \
    "  run_id INTEGER PRIMARY KEY REFERENCES runs(id),\n" \
    "  path TEXT NOT NULL,\n" \
    "  name TEXT,\n" \
    "  text TEXT NOT NULL,\n" \
    "  checked_at TEXT NOT NULL\n" \
    ");\n"

/* The columns version 3 adds: whether the fixed-step engine put a trajectory to rest
 * on a face steeper than its friction holds (NULL: not recorded, a trajectory written
 * before version 3; every writer of version 3 writes 0 or 1), and what a failed check
 * makes of the run's verdict (a design check fails it; an integrity check, which says
 * whether the trajectories can support a verdict at all, makes it inconclusive:
 * docs/rules.md). */
#define TRAJECTORIES_V3_COLUMN "rest_steep INTEGER CHECK (rest_steep IN (0, 1))"
#define CHECKS_V3_COLUMN \
    "on_failure TEXT NOT NULL DEFAULT 'fail' CHECK (on_failure IN ('fail', 'inconclusive'))"

/* The columns version 4 adds: the mass each trajectory drew and the rock's centre at
 * its start (NULL for a trajectory written before version 4). */
#define TRAJECTORIES_V4_COLUMNS "mass_kg REAL, start_x REAL, start_y REAL, start_z REAL"

/* The tables version 5 adds: the fits of `rockfall calibrate -o` (docs/calibration.md),
 * one row per fit and one per fitted value. */
#define CALIBRATION_TABLES \
    "CREATE TABLE calibrations (\n" \
    "  id INTEGER PRIMARY KEY AUTOINCREMENT,\n" \
    "  project TEXT NOT NULL,\n" \
    "  project_path TEXT,\n" \
    "  observed_path TEXT NOT NULL,\n" \
    "  n_observed INTEGER NOT NULL,\n" \
    "  seed INTEGER NOT NULL,\n" \
    "  created_at TEXT NOT NULL,\n" \
    "  version TEXT NOT NULL,\n" \
    "  objective TEXT NOT NULL,\n" \
    "  value REAL NOT NULL,\n" \
    "  ks_runout REAL, ks_lateral REAL, inside_share REAL,\n" \
    "  n_simulations INTEGER NOT NULL,\n" \
    "  n_trajectories INTEGER NOT NULL,\n" \
    "  converged INTEGER NOT NULL CHECK (converged IN (0, 1))\n" \
    ");\n" \
    "CREATE TABLE calibration_values (\n" \
    "  calibration_id INTEGER NOT NULL REFERENCES calibrations(id),\n" \
    "  key TEXT NOT NULL,\n" \
    "  start REAL, value REAL NOT NULL,\n" \
    "  PRIMARY KEY (calibration_id, key)\n" \
    ") WITHOUT ROWID;\n"

/* The columns the GeoPackage version (results/gpkg.h) adds to runs: the project's CRS as
 * given, and its row in gpkg_spatial_ref_sys (-1: none, the undefined Cartesian CRS). */
#define RUNS_GPKG_COLUMNS "crs TEXT, srs_id INTEGER"

/* The columns version 5 adds: a trajectory's source cell, and a release's number of
 * source cells (both NULL for a point or area release, and for rows written before
 * version 5). */
#define TRAJECTORIES_V5_COLUMN "source_cell INTEGER CHECK (source_cell >= 0)"
#define RELEASES_V5_COLUMN "n_cells INTEGER CHECK (n_cells >= 1)"
/* What the run kept (version 5): 'all' its rows, or 'maps' (run --store maps) its
 * releases, interceptions, hazard cells and sampled paths, with the trajectory rows of
 * those interceptions and paths only, and no tree hits (docs/scaling.md). */
#define RUNS_V5_COLUMN "store TEXT NOT NULL DEFAULT 'all' CHECK (store IN ('all', 'maps'))"
/* Where the run ran (version 5): the host of the process that wrote it, its MPI ranks
 * and the threads of each (NULL for the runs before). */
#define RUNS_V5_WHERE "host TEXT, ranks INTEGER CHECK (ranks >= 1), threads INTEGER CHECK (threads >= 1)"

static const char schema_sql[] =
    "CREATE TABLE rockfall_schema (version INTEGER NOT NULL, application TEXT NOT NULL);\n"
    "INSERT INTO rockfall_schema VALUES (" RF_STR(RF_SCHEMA_VERSION) ", 'rockfall');\n"
    "CREATE TABLE runs (\n"
    "  id INTEGER PRIMARY KEY AUTOINCREMENT,\n"
    "  project TEXT NOT NULL,\n"
    "  project_path TEXT,\n"
    "  seed INTEGER NOT NULL,\n"
    "  status TEXT NOT NULL CHECK (status IN ('running', 'complete', 'failed')),\n"
    "  started_at TEXT NOT NULL,\n"
    "  finished_at TEXT,\n"
    "  n_trajectories INTEGER NOT NULL CHECK (n_trajectories >= 0),\n"
    "  version TEXT NOT NULL,\n"
    "  project_yaml TEXT,\n"
    RUNS_V2_COLUMNS
    "  , " RUNS_GPKG_COLUMNS ",\n"
    "  " RUNS_V5_COLUMN ",\n"
    "  " RUNS_V5_WHERE "\n"
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
    "  " RELEASES_V5_COLUMN ",\n"
    "  UNIQUE (run_id, idx)\n"
    ");\n"
    MEASURES_TABLE("measures")
    "CREATE TABLE trajectories (\n"
    "  id INTEGER PRIMARY KEY,\n"
    "  run_id INTEGER NOT NULL REFERENCES runs(id),\n"
    "  release_id INTEGER NOT NULL REFERENCES releases(id),\n"
    "  idx INTEGER NOT NULL,\n"
    "  stop_x REAL, stop_y REAL, stop_z REAL,\n"
    "  stop_reason TEXT NOT NULL\n"
    "    CHECK (stop_reason IN ('rest', 'exited', 'stopped', 'max_time')),\n"
    "  duration_s REAL, path_length_m REAL, max_energy_kj REAL,\n"
    "  n_impacts INTEGER, n_tree_hits INTEGER,\n"
    "  " TRAJECTORIES_V3_COLUMN ",\n"
    "  " TRAJECTORIES_V4_COLUMNS ",\n"
    "  " TRAJECTORIES_V5_COLUMN "\n"
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
    "  passed INTEGER CHECK (passed IN (0, 1)),\n"
    "  " CHECKS_V3_COLUMN "\n"
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
    KINDS_TABLE V2_TABLES CALIBRATION_TABLES
    "PRAGMA user_version = " RF_STR(RF_SCHEMA_VERSION) ";\n";

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
    "  CASE k.passed WHEN 1 THEN 'pass' ELSE k.on_failure END AS verdict\n"
    "FROM checks k LEFT JOIN measures m ON m.id = k.measure_id;\n"
    "CREATE VIEW IF NOT EXISTS run_verdicts AS\n"
    "SELECT run_id, project, status, started_at, checks, checks_failed,\n"
    "  checks_inconclusive,\n"
    "  CASE WHEN checks = 0 THEN 'unchecked' WHEN checks_inconclusive > 0 THEN 'inconclusive'\n"
    "       WHEN checks_failed > 0 THEN 'fail' ELSE 'pass' END AS verdict\n"
    "FROM (SELECT r.id AS run_id, r.project, r.status, r.started_at,\n"
    "        coalesce(k.n, 0) AS checks, coalesce(k.failed, 0) AS checks_failed,\n"
    "        coalesce(k.inconclusive, 0) AS checks_inconclusive\n"
    "      FROM runs r\n"
    "      LEFT JOIN (SELECT run_id, count(*) AS n,\n"
    "                   sum(passed = 0 AND on_failure = 'fail') AS failed,\n"
    "                   sum(passed = 0 AND on_failure = 'inconclusive') AS inconclusive\n"
    "                 FROM checks GROUP BY run_id) k ON k.run_id = r.id);\n";


/* ---- SQLite's return codes ---------------------------------------------------------- */

int rf_sql_status(sqlite3 *db, const char *path, int rc, const char *doing, rf_error *err)
{
    if (rc == SQLITE_OK || rc == SQLITE_ROW || rc == SQLITE_DONE)
        return 0;
    const char *why = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
    return rf_error_set(err, path, 0, 0, "%s: %s", doing, why);
}

static int exec_sql(sqlite3 *db, const char *path, const char *sql, const char *doing,
                    rf_error *err)
{
    return rf_sql_status(db, path, sqlite3_exec(db, sql, NULL, NULL, NULL), doing, err);
}

/* Ends the transaction begun by BEGIN IMMEDIATE: committed after status 0, else
 * rolled back; returns the status. */
static int end_transaction(sqlite3 *db, const char *path, int status, const char *doing,
                           rf_error *err)
{
    if (status == 0)
        status = exec_sql(db, path, "COMMIT", doing, err);
    if (status != 0 && !sqlite3_get_autocommit(db))
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
    return status;
}

/* ---- the version ---------------------------------------------------------------------- */

/* The file's schema version (rockfall_schema's row, else 1 for a file of version 1,
 * marked by user_version = 1 alone, and 0 for a file that is not ours: a GeoPackage's
 * user_version is GeoPackage's own) and the number of objects in its schema (-1 for
 * another program's GeoPackage); fails on a file that is not a database. */
static int read_schema_state(sqlite3 *db, const char *path, int *version, int *nobjects,
                             rf_error *err)
{
    static const char sql[] =
        "SELECT (SELECT user_version = 1 FROM pragma_user_version),"
        " (SELECT count(*) FROM sqlite_master),"
        " (SELECT count(*) FROM sqlite_master WHERE type = 'table'"
        "  AND name = 'rockfall_schema'),"
        " (SELECT application_id FROM pragma_application_id)";
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL), marked = 0;
    if (rc == SQLITE_OK && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        *version = sqlite3_column_int(st, 0);
        *nobjects = sqlite3_column_int(st, 1);
        marked = sqlite3_column_int(st, 2);
        /* another program's GeoPackage: -1, for the message */
        if (!marked && *nobjects && sqlite3_column_int64(st, 3) == RF_GPKG_APPLICATION_ID)
            *nobjects = -1;
    }
    sqlite3_finalize(st);
    st = NULL;
    if (rc == SQLITE_ROW && marked) {
        rc = sqlite3_prepare_v2(db, "SELECT max(version) FROM rockfall_schema", -1, &st, NULL);
        if (rc == SQLITE_OK && (rc = sqlite3_step(st)) == SQLITE_ROW)
            *version = sqlite3_column_int(st, 0);
        sqlite3_finalize(st);
    }
    return rf_sql_status(db, path, rc, "reading the results database", err);
}

static int version_error(const char *path, int version, rf_error *err)
{
    return rf_error_set(err, path, 0, 0,
                        "results database schema version %d; rockfall %s reads schema "
                        "versions 1 to %d",
                        version, ROCKFALL_VERSION, RF_SCHEMA_VERSION);
}

static int foreign_error(const char *path, int nobjects, rf_error *err)
{
    if (nobjects < 0)
        return rf_error_set(err, path, 0, 0,
                            "a GeoPackage of another program (no rockfall_schema table): "
                            "rockfall writes only into its own results files, and reads "
                            "only them");
    return rf_error_set(err, path, 0, 0,
                        "not a rockfall results database (an SQLite database with %d schema "
                        "objects and no rockfall schema version)",
                        nobjects);
}

int rf_schema_version(sqlite3 *db, const char *path, int *version, rf_error *err)
{
    int nobjects = 0;
    if (read_schema_state(db, path, version, &nobjects, err))
        return -1;
    if (*version == 0)
        return nobjects ? foreign_error(path, nobjects, err)
                        : rf_error_set(err, path, 0, 0, "an empty file: no results database");
    if (*version > RF_SCHEMA_VERSION)
        return version_error(path, *version, err);
    return 0;
}

/* ---- writing the schema ---------------------------------------------------------------- */

/* The rows of measure_kinds from the class table; kinds already there are kept. */
static int insert_kinds(sqlite3 *db, const char *path, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db,
                                "INSERT OR IGNORE INTO measure_kinds (name, label, classified,"
                                " reach_line, limit_states) VALUES (?1, ?2, ?3, ?4, ?5)",
                                -1, &st, NULL);
    for (int k = 0; rc == SQLITE_OK && k < RF_N_MEASURE_KINDS; k++) {
        const rf_measure_kind_class *c = &rf_measure_kinds[k];
        sqlite3_bind_text(st, 1, c->name, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 2, c->label, -1, SQLITE_STATIC);
        sqlite3_bind_int(st, 3, c->classified);
        sqlite3_bind_int(st, 4, c->reach_line);
        sqlite3_bind_text(st, 5, c->states, -1, SQLITE_STATIC);
        rc = sqlite3_step(st);
        rc = rc == SQLITE_DONE ? sqlite3_reset(st) : rc;
    }
    sqlite3_finalize(st);
    return rf_sql_status(db, path, rc, "writing the measure kinds", err);
}

int rf_schema_add_kinds(sqlite3 *db, const char *path, rf_error *err)
{
    return insert_kinds(db, path, err);
}

/* Brings the views up to date: each view whose stored definition differs from this
 * version's (both as SQLite stores them: the current ones are made in a scratch
 * database in memory) is dropped, and the missing ones are created, all within the
 * caller's transaction.  Views hold no data. */
static int refresh_views(sqlite3 *db, const char *path, rf_error *err)
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
        rc = rf_error_set(err, path, 0, 0, "%s: %s", doing,
                          mem ? sqlite3_errmsg(mem) : "out of memory");
        sqlite3_close(mem);
        return rc;
    }
    rc = sqlite3_prepare_v2(mem, list, -1, &cur, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(db, "SELECT sql FROM sqlite_master WHERE type = 'view' AND name = ?",
                                -1, &old, NULL);
    while (rc == SQLITE_OK && (rc = sqlite3_step(cur)) == SQLITE_ROW) {
        const char *name = (const char *)sqlite3_column_text(cur, 0);
        const char *sql = (const char *)sqlite3_column_text(cur, 1);
        sqlite3_bind_text(old, 1, name, -1, SQLITE_TRANSIENT);
        rc = sqlite3_step(old);
        const char *have = rc == SQLITE_ROW ? (const char *)sqlite3_column_text(old, 0) : NULL;
        if (rc == SQLITE_DONE || (rc == SQLITE_ROW && (!have || strcmp(have, sql) != 0))) {
            char *more = sqlite3_mprintf("%sDROP VIEW IF EXISTS \"%w\";\n", drops ? drops : "", name);
            sqlite3_free(drops);
            drops = more;
            stale = 1;
            rc = more ? SQLITE_OK : SQLITE_NOMEM;
        } else if (rc == SQLITE_ROW) {
            rc = SQLITE_OK;
        }
        sqlite3_reset(old);
    }
    if (rc == SQLITE_DONE)
        rc = SQLITE_OK;
    sqlite3_finalize(old);
    sqlite3_finalize(cur);
    sqlite3_close(mem);
    int status = rf_sql_status(db, path, rc, doing, err);
    if (status == 0 && stale)
        status = (drops && exec_sql(db, path, drops, doing, err)) ||
                         exec_sql(db, path, views_sql, doing, err)
                     ? -1
                     : 0;
    sqlite3_free(drops);
    return status;
}

/* Version 1 to 2, within the caller's transaction (foreign keys off, as on every
 * connection until rf_schema_prepare is done): the version table, the kinds, the
 * measures table rebuilt with its kind a foreign key and sel_source, the new columns
 * and tables; then what version 1 kept only in the project text (whether a barrier's
 * SEL was given, the rule file) is read from it once (schema_legacy.c). */
static int upgrade_1_to_2(sqlite3 *db, const char *path, rf_error *err)
{
    static const char sql[] =
        "CREATE TABLE rockfall_schema (version INTEGER NOT NULL, application TEXT NOT NULL);\n"
        "INSERT INTO rockfall_schema VALUES (2, 'rockfall');\n"
        KINDS_TABLE
        "DROP VIEW IF EXISTS classified_interceptions;\n"
        "DROP VIEW IF EXISTS measure_summary;\n"
        "DROP VIEW IF EXISTS limit_state_shares;\n"
        "DROP VIEW IF EXISTS check_results;\n"
        MEASURES_TABLE("measures_v2")
        "INSERT INTO measures_v2 (id, run_id, idx, name, kind, importance, height_m,"
        " behaviour, mel_kj, sel_kj, cap_serviceability_kj, cap_restorability_kj,"
        " cap_ultimate_kj, cap_near_collapse_kj, line)"
        " SELECT id, run_id, idx, name, kind, importance, height_m, behaviour, mel_kj,"
        " sel_kj, cap_serviceability_kj, cap_restorability_kj, cap_ultimate_kj,"
        " cap_near_collapse_kj, line FROM measures;\n"
        "DROP TABLE measures;\n"
        "ALTER TABLE measures_v2 RENAME TO measures;\n"
        RUNS_V2_ADD
        V2_TABLES
        "PRAGMA user_version = 2;\n";
    const char *doing = "upgrading the results database from schema version 1";
    if (exec_sql(db, path, sql, doing, err) || insert_kinds(db, path, err) ||
        rf_legacy_fill(db, path, err))
        return -1;
    return 0;
}

/* Version 2 to 3, within the caller's transaction: the two new columns (the earlier
 * trajectories' rest_steep NULL, not recorded: a fixed-step run of an earlier rockfall
 * may have rested on a steep face unseen; every earlier check a design check, on_failure
 * 'fail'); the views follow in refresh_views. */
static int upgrade_2_to_3(sqlite3 *db, const char *path, rf_error *err)
{
    static const char sql[] =
        "ALTER TABLE trajectories ADD COLUMN " TRAJECTORIES_V3_COLUMN ";\n"
        "ALTER TABLE checks ADD COLUMN " CHECKS_V3_COLUMN ";\n"
        "UPDATE rockfall_schema SET version = 3;\n"
        "PRAGMA user_version = 3;\n";
    const char *doing = "upgrading the results database from schema version 2";
    if (exec_sql(db, path, sql, doing, err))
        return -1;
    /* the integrity checks a check of version 3 wrote into the version-2 file */
    sqlite3_stmt *st;
    int rc = sqlite3_prepare_v2(db,
                                "UPDATE checks SET on_failure = 'inconclusive'"
                                " WHERE measure_id IS NULL AND rule = ?1",
                                -1, &st, NULL);
    for (int k = 0; rc == SQLITE_OK && k < RF_N_INTEGRITY; k++) {
        sqlite3_bind_text(st, 1, rf_integrity_rules[k], -1, SQLITE_STATIC);
        rc = sqlite3_step(st) == SQLITE_DONE ? sqlite3_reset(st) : SQLITE_ERROR;
    }
    sqlite3_finalize(st);
    return rf_sql_status(db, path, rc, doing, err);
}

/* Version 3 to 4, within the caller's transaction: each trajectory's drawn mass and
 * start (NULL for the earlier trajectories, whose releases had one fixed mass and
 * point, stored in releases). */
static int upgrade_3_to_4(sqlite3 *db, const char *path, rf_error *err)
{
    static const char sql[] =
        "ALTER TABLE trajectories ADD COLUMN mass_kg REAL;\n"
        "ALTER TABLE trajectories ADD COLUMN start_x REAL;\n"
        "ALTER TABLE trajectories ADD COLUMN start_y REAL;\n"
        "ALTER TABLE trajectories ADD COLUMN start_z REAL;\n"
        "UPDATE rockfall_schema SET version = 4;\n"
        "PRAGMA user_version = 4;\n";
    return exec_sql(db, path, sql, "upgrading the results database from schema version 3",
                    err);
}

/* Version 4 to 5, within the caller's transaction: the file made a GeoPackage
 * (results/gpkg.c, which writes the version), the calibration tables, each trajectory's
 * source cell and each release's number of cells (NULL for the earlier rows, which had
 * no `cells` releases stored by cell), what each run kept and where it ran. */
static int upgrade_4_to_5(sqlite3 *db, const char *path, rf_error *err)
{
    static const char sql[] =
        CALIBRATION_TABLES
        "ALTER TABLE trajectories ADD COLUMN " TRAJECTORIES_V5_COLUMN ";\n"
        "ALTER TABLE releases ADD COLUMN " RELEASES_V5_COLUMN ";\n"
        "ALTER TABLE runs ADD COLUMN " RUNS_V5_COLUMN ";\n"
        "ALTER TABLE runs ADD COLUMN host TEXT;\n"
        "ALTER TABLE runs ADD COLUMN ranks INTEGER CHECK (ranks >= 1);\n"
        "ALTER TABLE runs ADD COLUMN threads INTEGER CHECK (threads >= 1);\n";
    return rf_gpkg_create(db, path, 1, err) ||
                   exec_sql(db, path, sql, "upgrading the results database from schema version 4",
                            err)
               ? -1
               : 0;
}

/* Switches the file to the WAL journal.  The switch needs the file to itself, and
 * SQLite returns "locked" at once, without waiting, when another connection opening
 * the file at the same moment holds it too: tried again until the busy timeout has
 * passed (each try may itself wait in the busy handler). */
static int set_wal(sqlite3 *db, const char *path, rf_error *err)
{
    struct timespec pause = {0, 5 * 1000 * 1000};
    double deadline = rf_now_s() + RF_SCHEMA_BUSY_TIMEOUT_MS / 1000.0;
    int rc;
    while ((rc = sqlite3_exec(db, "PRAGMA journal_mode = WAL", NULL, NULL, NULL)) ==
               SQLITE_BUSY ||
           rc == SQLITE_LOCKED) {
        if (rf_now_s() > deadline)
            break;
        nanosleep(&pause, NULL);
    }
    return rf_sql_status(db, path, rc, "setting the WAL journal", err);
}

int rf_schema_prepare(sqlite3 *db, const char *path, rf_error *err)
{
    int version = 0, nobjects = 0;
    if (rf_sql_status(db, path, rf_gpkg_register(db), "preparing the results database", err))
        return -1;
    if (read_schema_state(db, path, &version, &nobjects, err))
        return -1;
    if (version > RF_SCHEMA_VERSION)
        return version_error(path, version, err);
    if (version == 0 && nobjects != 0)
        return foreign_error(path, nobjects, err);
    if (set_wal(db, path, err))
        return -1;
    /* Another process may be creating or upgrading the file at this moment: the state
     * is read again inside the transaction. */
    const char *doing = "preparing the results database";
    if (exec_sql(db, path, "BEGIN IMMEDIATE", doing, err))
        return -1;
    int status = read_schema_state(db, path, &version, &nobjects, err);
    if (status == 0 && version > RF_SCHEMA_VERSION)
        status = version_error(path, version, err);
    else if (status == 0 && version == 0 && nobjects != 0)
        status = foreign_error(path, nobjects, err);
    else if (status == 0 && version == 0)
        status = exec_sql(db, path, schema_sql, "creating the schema", err) ||
                         insert_kinds(db, path, err) ||
                         exec_sql(db, path, views_sql, "creating the views", err) ||
                         rf_gpkg_create(db, path, 0, err)
                     ? -1
                     : 0;
    else if (status == 0 && version == 1)
        status = upgrade_1_to_2(db, path, err) || upgrade_2_to_3(db, path, err) ||
                         upgrade_3_to_4(db, path, err)
                     ? -1
                     : 0;
    else if (status == 0 && version == 2)
        status = upgrade_2_to_3(db, path, err) || upgrade_3_to_4(db, path, err) ? -1 : 0;
    else if (status == 0 && version == 3)
        status = upgrade_3_to_4(db, path, err);
    if (status == 0 && version >= 1 && version < RF_GPKG_SCHEMA_VERSION)
        status = upgrade_4_to_5(db, path, err);
    if (status == 0)
        status = refresh_views(db, path, err) || rf_gpkg_declare(db, path, err) ? -1 : 0;
    return end_transaction(db, path, status, doing, err);
}

/* ---- opening ---------------------------------------------------------------------------- */

/* "file:PATH?immutable=1" with PATH's URI-special characters escaped. */
static char *immutable_uri(const char *path)
{
    size_t n = strlen(path);
    char *uri = malloc(3 * n + 32);
    if (!uri)
        return NULL;
    char *o = uri + sprintf(uri, "file:");
    for (const unsigned char *c = (const unsigned char *)path; *c; c++)
        o += strchr("?#%", *c) || *c < 0x20 ? sprintf(o, "%%%02X", *c) : sprintf(o, "%c", *c);
    strcpy(o, "?immutable=1");
    return uri;
}

/* A read-only connection.  A file in the WAL journal needs its -shm beside it, which a
 * reader cannot create in a folder it may not write: such a file, which no process
 * can be writing either, is read as immutable. */
static int open_readonly(const char *path, sqlite3 **db, int *version, rf_error *err)
{
    int rc = sqlite3_open_v2(path, db, SQLITE_OPEN_READONLY, NULL);
    if (rf_sql_status(*db, path, rc, "opening the results database", err))
        return -1;
    sqlite3_busy_timeout(*db, RF_SCHEMA_BUSY_TIMEOUT_MS);
    rf_error first = {0};
    if (rf_schema_version(*db, path, version, &first) == 0)
        return 0;
    int code = sqlite3_errcode(*db) & 0xff;
    sqlite3_close(*db);
    *db = NULL;
    if (code != SQLITE_CANTOPEN && code != SQLITE_READONLY) {
        *err = first;
        return -1;
    }
    char *uri = immutable_uri(path);
    if (!uri)
        return rf_error_set(err, path, 0, 0, "out of memory opening the results database");
    rc = sqlite3_open_v2(uri, db, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, NULL);
    free(uri);
    if (rf_sql_status(*db, path, rc, "opening the results database", err) ||
        rf_schema_version(*db, path, version, err))
        return -1;
    return 0;
}

int rf_db_open(const char *path, rf_db_mode mode, sqlite3 **db, int *version, rf_error *err)
{
    *db = NULL;
    int v = 0, status;
    if (mode == RF_DB_READ) {
        status = open_readonly(path, db, &v, err);
    } else {
        int rc = sqlite3_open_v2(path, db, SQLITE_OPEN_READWRITE, NULL);
        status = rf_sql_status(*db, path, rc, "opening the results database", err);
        if (status == 0) {
            sqlite3_busy_timeout(*db, RF_SCHEMA_BUSY_TIMEOUT_MS);
            status = rf_schema_version(*db, path, &v, err) ||
                             exec_sql(*db, path, "PRAGMA foreign_keys = ON",
                                      "configuring the results database", err)
                         ? -1
                         : 0;
        }
    }
    if (status != 0) {
        sqlite3_close(*db);
        *db = NULL;
        return -1;
    }
    if (version)
        *version = v;
    return 0;
}

int rf_db_has_table(sqlite3 *db, const char *table)
{
    sqlite3_stmt *st = NULL;
    int has = 0;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?1",
                           -1, &st, NULL) == SQLITE_OK) {
        sqlite3_bind_text(st, 1, table, -1, SQLITE_STATIC);
        has = sqlite3_step(st) == SQLITE_ROW;
    }
    sqlite3_finalize(st);
    return has;
}

int rf_db_has_column(sqlite3 *db, const char *table, const char *column)
{
    sqlite3_stmt *st = NULL;
    int has = 0;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM pragma_table_info(?1) WHERE name = ?2", -1, &st,
                           NULL) == SQLITE_OK) {
        sqlite3_bind_text(st, 1, table, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 2, column, -1, SQLITE_STATIC);
        has = sqlite3_step(st) == SQLITE_ROW;
    }
    sqlite3_finalize(st);
    return has;
}
