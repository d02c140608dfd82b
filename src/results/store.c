/* store.c - the SQLite results database (DESIGN.md section 4, docs/database.md).
 *
 * Every SQLite return code passes through sql_status(), the one place where it
 * becomes the rf_error convention (0 or -1 with a message naming the file).  The
 * statements of the hot path are prepared once in rf_store_open and reset and bound
 * per row. */
#include "results/store.h"

#include <assert.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/polyline.h"
#include "base/util.h"
#include "input/measure_kinds.h"
#include "results/gpkg.h"
#include "results/schema.h"
#include "results/terrain_grid.h"
#include "rockfall/version.h"

/* How long a writer waits for another connection's lock before giving up. */
#define RF_STORE_BUSY_TIMEOUT_MS 10000

/* Tries of the switch back to the rollback journal when closing (leave_wal). */
#define RF_STORE_LEAVE_WAL_TRIES 6

#define RF_NOW_SQL "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"

enum {
    ST_BEGIN, ST_COMMIT, ST_ROLLBACK,
    ST_RUN, ST_RELEASE, ST_MEASURE, ST_GRID, ST_GROUND, ST_FINISH,
    ST_TRAJECTORY, ST_PATH_POINT, ST_INTERCEPTION, ST_TREE_HIT, ST_HAZARD_CELL,
    ST_COUNT
};

static const char *const statement_sql[ST_COUNT] = {
    [ST_BEGIN] = "BEGIN IMMEDIATE",
    [ST_COMMIT] = "COMMIT",
    [ST_ROLLBACK] = "ROLLBACK",
    [ST_RUN] = "INSERT INTO runs (project, project_path, seed, status, started_at,"
               " n_trajectories, version, project_yaml, rules_path, surface_friction,"
               " hazard_cell_m, crs, srs_id, store, host, ranks, threads)"
               " VALUES (?1, ?2, ?3, 'running', " RF_NOW_SQL ", ?4, ?5, ?6, ?7, ?8, ?9,"
               " ?10, ?11, ?12, ?13, ?14, ?15)",
    [ST_RELEASE] = "INSERT INTO releases (run_id, idx, name, x, y, z, rock, mass_kg,"
                   " radius_m, density_kgm3, action_level, count, velocity_x,"
                   " velocity_y, velocity_z, height_m, jitter_m, n_cells)"
                   " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13,"
                   " ?14, ?15, ?16, ?17, ?18)",
    [ST_MEASURE] = "INSERT INTO measures (run_id, idx, name, kind, importance, height_m,"
                   " behaviour, mel_kj, sel_kj, cap_serviceability_kj,"
                   " cap_restorability_kj, cap_ultimate_kj, cap_near_collapse_kj, line,"
                   " sel_source)"
                   " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14,"
                   " ?15)",
    [ST_GRID] = "INSERT INTO terrain_grids (run_id, xmin, xmax, ymin, ymax, x0, y0, x1, y1,"
                " step, nx, ny, z)"
                " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)",
    [ST_GROUND] = "INSERT INTO ground_points (run_id, release_id, measure_id, x, y, z)"
                  " VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
    [ST_FINISH] = "UPDATE runs SET status = ?1, finished_at = " RF_NOW_SQL ","
                  " n_trajectories = coalesce(?2, n_trajectories) WHERE id = ?3",
    [ST_TRAJECTORY] = "INSERT INTO trajectories (run_id, release_id, idx, stop_x, stop_y,"
                      " stop_z, stop_reason, duration_s, path_length_m, max_energy_kj,"
                      " n_impacts, n_tree_hits, rest_steep, mass_kg, start_x, start_y,"
                      " start_z, source_cell) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9,"
                      " ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18)",
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
    int prepared;            /* the schema is ours and current (rf_schema_prepare) */
    int64_t run_id;          /* 0 before the first rf_store_run_begin */
    int64_t *release_ids;    /* by project release index */
    rf_release *sources;     /* by project release index: what rf_release_source_cell
                              * reads of each (count, ncells, source; no arrays) */
    size_t nreleases;
    int64_t *measure_ids;    /* by project measure index */
    size_t nmeasures;
    int maps;                /* the next run keeps its maps only (rf_store_describe_run) */
    int ranks, threads;      /* and where it runs */
};

static int sql_status(sqlite3 *db, const char *path, int rc, const char *doing, rf_error *err)
{
    return rf_sql_status(db, path, rc, doing, err);
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

/* A real, NULL when it is not finite: an infinite energy is no measurement, and SQLite
 * would store it as Inf (and a NaN as NULL anyway). */
static void bind_real(sqlite3_stmt *st, int col, double v)
{
    int rc = isfinite(v) ? sqlite3_bind_double(st, col, v) : sqlite3_bind_null(st, col);
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

/* A value that is NULL when negative (a capacity that was not given) or not finite. */
static void bind_given(sqlite3_stmt *st, int col, double v)
{
    int rc = v < 0.0 || !isfinite(v) ? sqlite3_bind_null(st, col)
                                      : sqlite3_bind_double(st, col, v);
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
    if (rf_schema_prepare(s->db, s->path, err) ||
        exec_sql(s, "PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON",
                 "configuring the results database", err))
        goto fail;
    s->prepared = 1;
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

/* The last writer to close puts the file back in the rollback journal (DELETE), the
 * mode a GeoPackage is read in anywhere (no -wal or -shm needed beside it).  The switch
 * needs the file to itself: it is made on a connection of its own once the writer's is
 * closed, and fails at once while another connection has the file open (that one makes
 * it when it closes).  Writers closing at the same moment would each see the other, so
 * a few tries follow, apart by pauses that differ between processes. */
static void leave_wal(const char *path)
{
    for (int k = 0; k < RF_STORE_LEAVE_WAL_TRIES; k++) {
        sqlite3 *db = NULL;
        sqlite3_stmt *st = NULL;
        int done = 0;
        if (sqlite3_open_v2(path, &db, SQLITE_OPEN_READWRITE, NULL) == SQLITE_OK &&
            sqlite3_prepare_v2(db, "PRAGMA journal_mode = DELETE", -1, &st, NULL) == SQLITE_OK &&
            sqlite3_step(st) == SQLITE_ROW)
            done = !strcmp((const char *)sqlite3_column_text(st, 0), "delete");
        sqlite3_finalize(st);
        sqlite3_close(db);
        if (done)
            return;
        struct timespec pause = {0, (long)(1 + (getpid() * 7 + k * 13) % 17) * 1000 * 1000};
        nanosleep(&pause, NULL);
    }
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
    if (s->prepared)
        leave_wal(s->path);
    free(s->release_ids);
    free(s->measure_ids);
    free(s->sources);
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
    /* the rule file absolute, for a check run from any folder */
    char *rules = p->rules_path ? realpath(p->rules_path, NULL) : NULL;
    bind_text(st, 7, rules ? rules : p->rules_path);
    /* what the report needs of the project besides its rows; NULL without a terrain */
    int terrain = p->terrain.ntri > 0;
    bind_real(st, 8, terrain ? p->terrain_spec.surface.friction.mean : NAN);
    bind_real(st, 9, p->hazard_cell > 0 ? p->hazard_cell : NAN);
    /* the CRS as given and its row in gpkg_spatial_ref_sys (results/gpkg.h) */
    int64_t srs = RF_GPKG_SRS_UNDEFINED;
    if (rf_gpkg_srs_for_run(s->db, s->path, &p->crs, &srs, err)) {
        free(rules);
        free(abs_path);
        return -1;
    }
    bind_text(st, 10, p->crs.source);
    bind_int(st, 11, srs);
    bind_text(st, 12, s->maps ? "maps" : "all");
    char host[256] = "";
    if (gethostname(host, sizeof host - 1) == 0)
        bind_text(st, 13, host);
    else
        sqlite3_bind_null(st, 13);
    bind_int(st, 14, s->ranks > 0 ? s->ranks : 1); /* 0: never described, one of each */
    bind_int(st, 15, s->threads > 0 ? s->threads : 1);
    int failed = step_statement(s, ST_RUN, "writing the run", err);
    free(rules);
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
    bind_int(st, 12, rf_release_trajectories(r));
    bind_vec3(st, 13, r->velocity);
    bind_real(st, 16, r->height);
    bind_real(st, 17, r->jitter);
    if (r->source == RF_SOURCE_CELLS)
        bind_int(st, 18, (int64_t)r->ncells);
    else
        sqlite3_bind_null(st, 18);
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
    assert((unsigned)m->kind < RF_N_MEASURE_KINDS);
    int has_mel = rf_measure_kinds[m->kind].has_mel;
    bind_int(st, 1, s->run_id);
    bind_int(st, 2, (int64_t)i);
    bind_text(st, 3, m->name);
    bind_text(st, 4, rf_measure_kind_name(m->kind));
    bind_text(st, 5, rf_importance_name(m->importance));
    bind_real(st, 6, m->height);
    bind_text(st, 7, rf_behaviour_name(m->behaviour));
    bind_given(st, 8, has_mel ? m->mel : -1.0);
    bind_given(st, 9, has_mel ? m->sel : -1.0);
    for (int k = 0; k < RF_N_LIMIT_STATES; k++)
        bind_given(st, 10 + k, m->capacity[k]);
    bind_text(st, 14, line);
    bind_text(st, 15, !has_mel ? NULL : m->sel_given ? "given" : "default: MEL/3");
    int status = step_statement(s, ST_MEASURE, "writing a measure", err);
    free(line);
    if (status)
        return -1;
    s->measure_ids[i] = sqlite3_last_insert_rowid(s->db);
    return 0;
}

/* The terrain as the report draws it (terrain_grids). */
static int insert_terrain_grid(rf_store *s, const rf_terrain *t, rf_error *err)
{
    rf_terrain_grid g;
    unsigned char *blob = NULL;
    if (rf_terrain_grid_sample(t, &g) || !(blob = malloc(8 * g.nx * g.ny))) {
        rf_terrain_grid_free(&g);
        return rf_error_set(err, s->path, 0, 0, "out of memory sampling the terrain");
    }
    rf_terrain_grid_encode(&g, blob);
    sqlite3_stmt *st = s->stmt[ST_GRID];
    bind_int(st, 1, s->run_id);
    const double v[9] = {g.xmin, g.xmax, g.ymin, g.ymax, g.x0, g.y0, g.x1, g.y1, g.step};
    for (int k = 0; k < 9; k++)
        bind_real(st, 2 + k, v[k]);
    bind_int(st, 11, (int64_t)g.nx);
    bind_int(st, 12, (int64_t)g.ny);
    int rc = sqlite3_bind_blob64(st, 13, blob, 8 * g.nx * g.ny, SQLITE_STATIC);
    int status = rc == SQLITE_OK ? step_statement(s, ST_GRID, "writing the terrain", err)
                                 : sql_status(s->db, s->path, rc, "writing the terrain", err);
    free(blob);
    rf_terrain_grid_free(&g);
    return status;
}

/* For each release and measure, the point of the measure's line nearest the release
 * and the ground's height there (NULL off the terrain): the report's empirical
 * crosscheck measures the drop to the line from it. */
static int insert_ground_points(rf_store *s, const rf_project *p, rf_error *err)
{
    sqlite3_stmt *st = s->stmt[ST_GROUND];
    for (size_t k = 0; k < p->nreleases; k++)
        for (size_t i = 0; i < p->nmeasures; i++) {
            const rf_polyline *l = &p->measures[i].line;
            double x = NAN, y = NAN, z = NAN;
            rf_polyline_station(l->xy, l->n, p->releases[k].x, p->releases[k].y, NULL, &x, &y);
            if (rf_terrain_height(&p->terrain, x, y, &z) < 0)
                z = NAN;
            bind_int(st, 1, s->run_id);
            bind_int(st, 2, s->release_ids[k]);
            bind_int(st, 3, s->measure_ids[i]);
            bind_real(st, 4, x);
            bind_real(st, 5, y);
            bind_real(st, 6, z);
            if (step_statement(s, ST_GROUND, "writing a ground point", err))
                return -1;
        }
    return 0;
}

void rf_store_describe_run(rf_store *s, int maps, int ranks, int threads)
{
    s->maps = maps != 0;
    s->ranks = ranks > 1 ? ranks : 1;
    s->threads = threads > 1 ? threads : 1;
}

int rf_store_run_begin(rf_store *s, const rf_project *p, long n_trajectories,
                       int64_t *run_id, rf_error *err)
{
    assert(sqlite3_get_autocommit(s->db) && "rf_store_run_begin inside a batch");
    free(s->release_ids);
    free(s->measure_ids);
    free(s->sources);
    s->run_id = 0;
    s->nreleases = p->nreleases;
    s->nmeasures = p->nmeasures;
    s->release_ids = calloc(p->nreleases + 1, sizeof *s->release_ids);
    s->measure_ids = calloc(p->nmeasures + 1, sizeof *s->measure_ids);
    s->sources = calloc(p->nreleases + 1, sizeof *s->sources);
    if (!s->release_ids || !s->measure_ids || !s->sources)
        return rf_error_set(err, s->path, 0, 0, "out of memory starting a run");
    for (size_t i = 0; i < p->nreleases; i++) {
        s->sources[i].source = p->releases[i].source;
        s->sources[i].count = p->releases[i].count;
        s->sources[i].ncells = p->releases[i].ncells;
    }

    if (step_statement(s, ST_BEGIN, "starting a run", err))
        return -1;
    int status = rf_schema_add_kinds(s->db, s->path, err) ||
                         insert_run_row(s, p, n_trajectories, err)
                     ? -1
                     : 0;
    for (size_t i = 0; status == 0 && i < p->nreleases; i++)
        status = insert_release_row(s, p, i, err);
    for (size_t i = 0; status == 0 && i < p->nmeasures; i++)
        status = insert_measure_row(s, p, i, err);
    if (status == 0 && p->terrain.ntri > 0)
        status = insert_terrain_grid(s, &p->terrain, err) || insert_ground_points(s, p, err)
                     ? -1
                     : 0;
    if (status == 0)
        status = rf_gpkg_fill_run(s->db, s->path, s->run_id, p, 1, err);
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
    /* the layers of the rows written, in one transaction with the run's end */
    int filled = step_statement(s, ST_BEGIN, "finishing the run", committed == 0 ? err : NULL);
    if (filled == 0)
        filled = rf_gpkg_fill_run(s->db, s->path, s->run_id, NULL, 0,
                                  committed == 0 ? err : NULL);
    if (filled != 0) {
        batch_rollback(s);
        if (committed == 0)
            status = "failed";
    }

    sqlite3_stmt *st = s->stmt[ST_FINISH];
    bind_text(st, 1, status);
    if (n_trajectories >= 0)
        bind_int(st, 2, n_trajectories);
    else
        sqlite3_bind_null(st, 2);
    bind_int(st, 3, s->run_id);
    /* The first error is the one reported. */
    int first = committed == 0 && filled == 0;
    int finished = step_statement(s, ST_FINISH, "finishing the run", first ? err : NULL);
    if (!sqlite3_get_autocommit(s->db)) {
        if (finished == 0)
            finished = step_statement(s, ST_COMMIT, "finishing the run", first ? err : NULL);
        if (finished != 0)
            batch_rollback(s);
    }
    return committed != 0 || filled != 0 || finished != 0 ? -1 : 0;
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
    bind_int(st, 13, r->rest_on_steep_face != 0);
    /* the drawn mass and start; NULL when the writer did not give them */
    bind_real(st, 14, r->mass_kg > 0.0 ? r->mass_kg : NAN);
    bind_vec3(st, 15, r->mass_kg > 0.0 ? r->start : rf_v3(NAN, NAN, NAN));
    long cell = rf_release_source_cell(&s->sources[release_index], idx);
    if (cell >= 0)
        bind_int(st, 18, cell);
    else
        sqlite3_bind_null(st, 18);
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

/* ---- calibrations ---------------------------------------------------------------- */

int rf_store_calibration(rf_store *s, const rf_project *p, const rf_calibration_record *c,
                         int64_t *id, rf_error *err)
{
    static const char row[] =
        "INSERT INTO calibrations (project, project_path, observed_path, n_observed, seed,"
        " created_at, version, objective, value, ks_runout, ks_lateral, inside_share,"
        " n_simulations, n_trajectories, converged) VALUES (?1, ?2, ?3, ?4, ?5,"
        " strftime('%Y-%m-%dT%H:%M:%SZ', 'now'), ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)";
    static const char value[] =
        "INSERT INTO calibration_values (calibration_id, key, start, value)"
        " VALUES (?1, ?2, ?3, ?4)";
    const char *doing = "writing the calibration";
    sqlite3_stmt *st = NULL, *sv = NULL;
    if (exec_sql(s, "BEGIN IMMEDIATE", doing, err))
        return -1;
    int rc = sqlite3_prepare_v2(s->db, row, -1, &st, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(s->db, value, -1, &sv, NULL);
    char *abs_path = realpath(p->path, NULL), *obs = realpath(c->observed_path, NULL);
    if (rc == SQLITE_OK) {
        bind_text(st, 1, p->name);
        bind_text(st, 2, abs_path ? abs_path : p->path);
        bind_text(st, 3, obs ? obs : c->observed_path);
        bind_int(st, 4, (int64_t)c->n_observed);
        assert(p->seed <= (uint64_t)INT64_MAX);
        bind_int(st, 5, (int64_t)p->seed);
        bind_text(st, 6, ROCKFALL_VERSION);
        bind_text(st, 7, c->objective);
        bind_real(st, 8, c->value);
        bind_real(st, 9, c->ks_runout);
        bind_real(st, 10, c->ks_lateral);
        bind_real(st, 11, c->inside_share);
        bind_int(st, 12, c->n_simulations);
        bind_int(st, 13, c->n_trajectories);
        bind_int(st, 14, c->converged != 0);
        rc = sqlite3_step(st);
    }
    if (rc == SQLITE_DONE) {
        *id = sqlite3_last_insert_rowid(s->db);
        rc = SQLITE_OK;
    }
    for (size_t i = 0; rc == SQLITE_OK && i < c->nkeys; i++) {
        bind_int(sv, 1, *id);
        bind_text(sv, 2, c->keys[i]);
        bind_real(sv, 3, c->start[i]);
        bind_real(sv, 4, c->fitted[i]);
        rc = sqlite3_step(sv);
        rc = rc == SQLITE_DONE ? sqlite3_reset(sv) : rc;
    }
    int status = sql_status(s->db, s->path, rc, doing, err);
    sqlite3_finalize(st);
    sqlite3_finalize(sv);
    free(abs_path);
    free(obs);
    if (status == 0)
        return exec_sql(s, "COMMIT", doing, err);
    sqlite3_exec(s->db, "ROLLBACK", NULL, NULL, NULL);
    return -1;
}
