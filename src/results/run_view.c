/* run_view.c - a run as its readers see it, and the statistics of its rows (see
 * run_view.h). */
#include "results/run_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/stats.h"
#include "base/term.h"
#include "rockfall/records.h"
#include "base/util.h"
#include "input/measure_kinds.h"
#include "results/schema.h"
#include "results/schema_legacy.h"

int rf_query_db_error(sqlite3 *db, rf_error *err)
{
    return rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0, "%s", sqlite3_errmsg(db));
}

double rf_query_column_real(sqlite3_stmt *st, int i)
{
    return sqlite3_column_type(st, i) == SQLITE_NULL ? NAN : sqlite3_column_double(st, i);
}

int rf_query_resolve_run(sqlite3 *db, long wanted, int64_t *run, rf_error *err)
{
    const char *file = sqlite3_db_filename(db, "main");
    sqlite3_stmt *st;
    const char *sql = wanted > 0 ? "SELECT id, status FROM runs WHERE id = ?1"
                                 : "SELECT id, status FROM runs WHERE status = 'complete' "
                                   "ORDER BY id DESC LIMIT 1";
    if (sqlite3_prepare_v2(db, sql, -1, &st, NULL) != SQLITE_OK)
        return rf_query_db_error(db, err);
    if (wanted > 0)
        sqlite3_bind_int64(st, 1, wanted);
    int rc = sqlite3_step(st), status = 0;
    if (rc == SQLITE_ROW) {
        *run = sqlite3_column_int64(st, 0);
        const char *s = (const char *)sqlite3_column_text(st, 1);
        if (s && strcmp(s, "complete"))
            status = rf_error_set(err, file, 0, 0, "run %ld is '%s', not complete", wanted, s);
    } else if (rc == SQLITE_DONE) {
        status = wanted > 0 ? rf_error_set(err, file, 0, 0, "no run %ld in this database", wanted)
                            : rf_error_set(err, file, 0, 0, "no complete run in this database");
    } else {
        status = rf_query_db_error(db, err);
    }
    sqlite3_finalize(st);
    return status;
}

int rf_query_crossings(sqlite3 *db, int64_t measure_id, rf_crossing_row **rows, size_t *n,
                       rf_error *err)
{
    *rows = NULL;
    *n = 0;
    sqlite3_stmt *st;
    if (sqlite3_prepare_v2(db,
                           "SELECT energy_kj, passing_height_m, outcome FROM interceptions"
                           " WHERE measure_id = ?1 ORDER BY id",
                           -1, &st, NULL) != SQLITE_OK)
        return rf_query_db_error(db, err);
    sqlite3_bind_int64(st, 1, measure_id);
    size_t cap = 0;
    int rc, oom = 0;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        if ((oom = rf_grow((void **)rows, &cap, *n + 1, sizeof **rows)) != 0)
            break;
        rf_crossing_row *x = &(*rows)[(*n)++];
        x->energy = rf_query_column_real(st, 0);
        x->height = rf_query_column_real(st, 1);
        x->outcome = rf_outcome_from_name((const char *)sqlite3_column_text(st, 2));
    }
    sqlite3_finalize(st);
    if (!oom && rc == SQLITE_DONE)
        return 0;
    free(*rows);
    *rows = NULL;
    *n = 0;
    return oom ? rf_error_set(err, "", 0, 0, "out of memory") : rf_query_db_error(db, err);
}

/* The values of one field of the rows that have one (NULL in the database is NAN
 * here, e.g. a passing height over a hole), as floats in v. */
static size_t gather(const rf_crossing_row *x, size_t n, int height, float *v)
{
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        double d = height ? x[i].height : x[i].energy;
        if (!isnan(d))
            v[m++] = (float)d;
    }
    return m;
}

int rf_measure_stats_of(const rf_crossing_row *x, size_t n, rf_measure_stats *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    s->n = (long)n;
    for (size_t i = 0; i < n; i++)
        switch (x[i].outcome) {
        case RF_OUT_STOPPED: s->n_stopped++; break;
        case RF_OUT_OVERTOPPED: s->n_overtopped++; break;
        case RF_OUT_BROKE_THROUGH: s->n_broke_through++; break;
        case RF_OUT_PASSED: s->n_passed++; break;
        }
    float *v = malloc((n ? n : 1) * sizeof *v);
    if (!v)
        return rf_error_set(err, "", 0, 0, "out of memory");
    size_t m = gather(x, n, 0, v);
    s->energy_p50 = rf_percentile_nearest_rank(v, m, 0.50); /* sorts v */
    s->energy_p90 = rf_percentile_sorted(v, m, 0.90);
    s->energy_p95 = rf_percentile_sorted(v, m, 0.95);
    s->energy_p99 = rf_percentile_sorted(v, m, 0.99);
    s->energy_max = m ? v[m - 1] : NAN;
    m = gather(x, n, 1, v);
    s->height_p95 = rf_percentile_nearest_rank(v, m, 0.95);
    free(v);
    return 0;
}

int rf_query_measure_stats(sqlite3 *db, int64_t measure_id, rf_measure_stats *s, rf_error *err)
{
    rf_crossing_row *x;
    size_t n;
    if (rf_query_crossings(db, measure_id, &x, &n, err))
        return -1;
    int rc = rf_measure_stats_of(x, n, s, err);
    free(x);
    return rc;
}

/* A number of the statistics columns, "-" when there is none. */
static void print_number(FILE *out, int width, int decimals, double v)
{
    if (isnan(v))
        fprintf(out, " %*s", width, "-");
    else
        fprintf(out, " %*.*f", width, decimals, v);
}

void rf_query_print_stats_header(FILE *out)
{
    fprintf(out, " %7s %9s %9s %9s %9s %9s %8s\n", "count", "E50", "E90", "E95", "E99", "Emax",
            "h95 (m)");
}

void rf_query_print_stats(FILE *out, const rf_measure_stats *s)
{
    fprintf(out, " %7ld", s->n);
    double e[] = {s->energy_p50, s->energy_p90, s->energy_p95, s->energy_p99, s->energy_max};
    for (int i = 0; i < 5; i++)
        print_number(out, 9, 1, e[i]);
    print_number(out, 8, 2, s->height_p95);
    fputc('\n', out);
}

void rf_query_print_measures(sqlite3 *db, int64_t run, FILE *out)
{
    sqlite3_stmt *st;
    if (sqlite3_prepare_v2(db, "SELECT id, name, kind FROM measures WHERE run_id = ?1 ORDER BY id",
                           -1, &st, NULL) != SQLITE_OK)
        return;
    sqlite3_bind_int64(st, 1, run);
    fprintf(out, "run %lld: interceptions per measure (energies in kJ, nearest-rank percentiles)\n",
            (long long)run);
    fprintf(out, "%-16s %-10s", "measure", "kind");
    rf_query_print_stats_header(out);
    while (sqlite3_step(st) == SQLITE_ROW) {
        rf_measure_stats s;
        rf_error err;
        if (rf_query_measure_stats(db, sqlite3_column_int64(st, 0), &s, &err)) {
            rf_error_print(&err, stderr);
            break;
        }
        char name[256], kind[64]; /* text from a file: escaped for the terminal */
        fprintf(out, "%-16s %-10s",
                rf_term_escape((const char *)sqlite3_column_text(st, 1), name, sizeof name),
                rf_term_escape((const char *)sqlite3_column_text(st, 2), kind, sizeof kind));
        rf_query_print_stats(out, &s);
    }
    sqlite3_finalize(st);
}

/* ---- the run view ---------------------------------------------------------------------- */

static char *col_dup(sqlite3_stmt *st, int i)
{
    const char *t = (const char *)sqlite3_column_text(st, i);
    return strdup(t ? t : "");
}

static int view_oom(rf_error *err)
{
    return rf_error_set(err, "", 0, 0, "out of memory reading the run");
}

/* A statement of the view with ?1 bound to id. */
static sqlite3_stmt *view_prepare(rf_run_view *v, const char *sql, int64_t id, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(v->db, sql, -1, &st, NULL) != SQLITE_OK) {
        rf_query_db_error(v->db, err);
        return NULL;
    }
    if (sqlite3_bind_parameter_count(st) >= 1)
        sqlite3_bind_int64(st, 1, id);
    return st;
}

/* Ends a loop over a statement's rows: 0 when it ran to the end. */
static int view_done(rf_run_view *v, sqlite3_stmt *st, int rc, rf_error *err)
{
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : rf_query_db_error(v->db, err);
}

/* Reads every row of sql (?1 bound to id) into the array *rows of *n elements of size
 * elem, one element a row, filled by row(v, st, element); row returns -1 when memory
 * runs out. */
static int load_rows(rf_run_view *v, const char *sql, int64_t id, void **rows, size_t *n,
                     size_t elem, int (*row)(rf_run_view *v, sqlite3_stmt *st, void *e),
                     rf_error *err)
{
    sqlite3_stmt *st = view_prepare(v, sql, id, err);
    if (!st)
        return -1;
    size_t cap = 0;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        if (rf_grow(rows, &cap, *n + 1, elem) ||
            row(v, st, (char *)*rows + elem * (*n)++)) {
            sqlite3_finalize(st);
            return view_oom(err);
        }
    }
    return view_done(v, st, rc, err);
}

static int load_run_row(rf_run_view *v, rf_error *err)
{
    sqlite3_stmt *st = view_prepare(
        v,
        v->schema >= 2 ? "SELECT project, project_path, seed, status, started_at, finished_at,"
                         " version, project_yaml, rules_path, surface_friction, hazard_cell_m,"
                         " (SELECT count(*) FROM trajectories WHERE run_id = ?1)"
                         " FROM runs WHERE id = ?1"
                       : "SELECT project, project_path, seed, status, started_at, finished_at,"
                         " version, project_yaml, NULL, NULL, NULL,"
                         " (SELECT count(*) FROM trajectories WHERE run_id = ?1)"
                         " FROM runs WHERE id = ?1",
        v->id, err);
    if (!st)
        return -1;
    int rc = sqlite3_step(st);
    if (rc == SQLITE_ROW) {
        char **text[] = {&v->project, &v->project_path, &v->seed, &v->status, &v->started,
                         &v->finished, &v->version, &v->yaml};
        for (int i = 0; i < 8; i++)
            if (!(*text[i] = col_dup(st, i)))
                rc = SQLITE_NOMEM;
        if (sqlite3_column_type(st, 8) != SQLITE_NULL) {
            if (!(v->rules_path = col_dup(st, 8)))
                rc = SQLITE_NOMEM;
        } else if (v->schema < 2) {
            v->rules_path = rf_legacy_rules_path(v->yaml, v->project_path);
        }
        v->surface_friction = rf_query_column_real(st, 9);
        v->hazard_cell = rf_query_column_real(st, 10);
        v->n_trajectories = (long)sqlite3_column_int64(st, 11);
    }
    sqlite3_finalize(st);
    if (rc == SQLITE_DONE)
        return rf_error_set(err, sqlite3_db_filename(v->db, "main"), 0, 0,
                            "no run %lld in this database", (long long)v->id);
    if (rc == SQLITE_NOMEM)
        return view_oom(err);
    return rc == SQLITE_ROW ? 0 : rf_query_db_error(v->db, err);
}

static int release_of_row(rf_run_view *v, sqlite3_stmt *st, void *e)
{
    (void)v;
    rf_view_release *r = e;
    *r = (rf_view_release){.id = sqlite3_column_int64(st, 0), .name = col_dup(st, 1),
                           .rock = col_dup(st, 2), .x = rf_query_column_real(st, 3),
                           .y = rf_query_column_real(st, 4), .z = rf_query_column_real(st, 5),
                           .mass = rf_query_column_real(st, 6),
                           .action_level = sqlite3_column_int(st, 7),
                           .count = (long)sqlite3_column_int64(st, 8)};
    return r->name && r->rock ? 0 : -1;
}

static int load_releases(rf_run_view *v, rf_error *err)
{
    return load_rows(v,
                     "SELECT id, name, rock, x, y, z, mass_kg, action_level, count"
                     " FROM releases WHERE run_id = ?1 ORDER BY idx, id",
                     v->id, (void **)&v->rel, &v->nrel, sizeof *v->rel, release_of_row, err);
}

/* One vertex (x, y) of a measure's polyline. */
static int vertex_of_row(rf_run_view *v, sqlite3_stmt *st, void *e)
{
    (void)v;
    double *xy = e;
    xy[0] = rf_query_column_real(st, 0);
    xy[1] = rf_query_column_real(st, 1);
    return 0;
}

/* The measure's polyline from its JSON text. */
static int load_line(rf_run_view *v, rf_view_measure *m, rf_error *err)
{
    return load_rows(v,
                     "SELECT json_extract(j.value, '$[0]'), json_extract(j.value, '$[1]')"
                     " FROM measures m, json_each(m.line) j WHERE m.id = ?1 ORDER BY j.key",
                     m->id, (void **)&m->xy, &m->n, 2 * sizeof *m->xy, vertex_of_row, err);
}

static int importance_of(const char *text)
{
    for (int i = 0; text && i < RF_N_IMPORTANCES; i++)
        if (!strcmp(text, rf_importance_names[i]))
            return i;
    return -1;
}

/* One measure row (the columns of load_measures) into e. */
static int measure_of_row(rf_run_view *v, sqlite3_stmt *st, void *e)
{
    rf_view_measure *m = e;
    *m = (rf_view_measure){.id = sqlite3_column_int64(st, 0),
                           .idx = (long)sqlite3_column_int64(st, 1), .name = col_dup(st, 2),
                           .kind_name = col_dup(st, 3), .importance_name = col_dup(st, 4),
                           .height = rf_query_column_real(st, 5),
                           .mel = rf_query_column_real(st, 6), .sel = rf_query_column_real(st, 7),
                           .sel_given = -1};
    for (int k = 0; k < RF_N_LIMIT_STATES; k++)
        m->cap[k] = rf_query_column_real(st, 8 + k);
    if (!m->name || !m->kind_name || !m->importance_name)
        return -1;
    m->kind = rf_measure_kind_find(m->kind_name);
    m->importance = importance_of(m->importance_name);
    const char *source = (const char *)sqlite3_column_text(st, 12);
    if (source)
        m->sel_given = !strcmp(source, "given");
    else if (v->schema < 2 && m->kind == RF_BARRIER)
        m->sel_given = rf_legacy_sel_given(v->yaml, m->name);
    return 0;
}

static int load_measures(rf_run_view *v, rf_error *err)
{
    if (load_rows(v,
                  v->schema >= 2 ? "SELECT id, idx, name, kind, importance, height_m, mel_kj, sel_kj,"
                                   " cap_serviceability_kj, cap_restorability_kj, cap_ultimate_kj,"
                                   " cap_near_collapse_kj, sel_source"
                                   " FROM measures WHERE run_id = ?1 ORDER BY idx, id"
                                 : "SELECT id, idx, name, kind, importance, height_m, mel_kj, sel_kj,"
                                   " cap_serviceability_kj, cap_restorability_kj, cap_ultimate_kj,"
                                   " cap_near_collapse_kj, NULL"
                                   " FROM measures WHERE run_id = ?1 ORDER BY idx, id",
                  v->id, (void **)&v->mea, &v->nmea, sizeof *v->mea, measure_of_row, err))
        return -1;
    for (size_t k = 0; k < v->nmea; k++)
        if (load_line(v, &v->mea[k], err))
            return -1;
    return 0;
}

static int load_grid(rf_run_view *v, rf_error *err)
{
    if (v->schema < 2)
        return 0;
    sqlite3_stmt *st = view_prepare(v,
                                    "SELECT xmin, xmax, ymin, ymax, x0, y0, x1, y1, step, nx, ny,"
                                    " z FROM terrain_grids WHERE run_id = ?1",
                                    v->id, err);
    if (!st)
        return -1;
    int rc = sqlite3_step(st), status = 0;
    if (rc == SQLITE_ROW) {
        rf_terrain_grid *g = &v->grid;
        double *at[] = {&g->xmin, &g->xmax, &g->ymin, &g->ymax, &g->x0,
                        &g->y0,   &g->x1,   &g->y1,   &g->step};
        for (int i = 0; i < 9; i++)
            *at[i] = sqlite3_column_double(st, i);
        g->nx = (size_t)sqlite3_column_int64(st, 9);
        g->ny = (size_t)sqlite3_column_int64(st, 10);
        if (rf_terrain_grid_decode(g, sqlite3_column_blob(st, 11),
                                   (size_t)sqlite3_column_bytes(st, 11)))
            status = rf_error_set(err, sqlite3_db_filename(v->db, "main"), 0, 0,
                                  "run %lld: its terrain grid is damaged", (long long)v->id);
        else
            v->has_grid = 1;
    } else if (rc != SQLITE_DONE) {
        status = rf_query_db_error(v->db, err);
    }
    sqlite3_finalize(st);
    return status;
}

static int ground_of_row(rf_run_view *v, sqlite3_stmt *st, void *e)
{
    (void)v;
    *(rf_view_ground *)e =
        (rf_view_ground){sqlite3_column_int64(st, 0), sqlite3_column_int64(st, 1),
                         rf_query_column_real(st, 2), rf_query_column_real(st, 3),
                         rf_query_column_real(st, 4)};
    return 0;
}

static int load_ground(rf_run_view *v, rf_error *err)
{
    if (v->schema < 2)
        return 0;
    return load_rows(v,
                     "SELECT release_id, measure_id, x, y, z FROM ground_points"
                     " WHERE run_id = ?1 ORDER BY release_id, measure_id",
                     v->id, (void **)&v->ground, &v->nground, sizeof *v->ground, ground_of_row,
                     err);
}

int rf_run_view_load(sqlite3 *db, int64_t run, rf_run_view *v, rf_error *err)
{
    memset(v, 0, sizeof *v);
    v->db = db;
    v->id = run;
    v->surface_friction = v->hazard_cell = NAN;
    if (rf_schema_version(db, sqlite3_db_filename(db, "main"), &v->schema, err) ||
        load_run_row(v, err) || load_releases(v, err) || load_measures(v, err) ||
        load_grid(v, err) || load_ground(v, err)) {
        rf_run_view_free(v);
        return -1;
    }
    return 0;
}

void rf_run_view_free(rf_run_view *v)
{
    char *text[] = {v->project, v->project_path, v->seed,    v->status,    v->started,
                    v->finished, v->version,     v->yaml,    v->rules_path};
    for (size_t i = 0; i < sizeof text / sizeof *text; i++)
        free(text[i]);
    for (size_t k = 0; k < v->nrel; k++) {
        free(v->rel[k].name);
        free(v->rel[k].rock);
    }
    free(v->rel);
    for (size_t k = 0; k < v->nmea; k++) {
        free(v->mea[k].name);
        free(v->mea[k].kind_name);
        free(v->mea[k].importance_name);
        free(v->mea[k].xy);
    }
    free(v->mea);
    rf_terrain_grid_free(&v->grid);
    free(v->ground);
    memset(v, 0, sizeof *v);
}

const rf_view_ground *rf_run_view_ground(const rf_run_view *v, int64_t release_id,
                                         int64_t measure_id)
{
    for (size_t k = 0; k < v->nground; k++)
        if (v->ground[k].release_id == release_id && v->ground[k].measure_id == measure_id)
            return &v->ground[k];
    return NULL;
}
