/* query.c - statistics read back from the results database. */
#include "results/query.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/stats.h"
#include "rockfall/records.h"
#include "base/util.h"

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
        fprintf(out, "%-16s %-10s", (const char *)sqlite3_column_text(st, 1),
                (const char *)sqlite3_column_text(st, 2));
        rf_query_print_stats(out, &s);
    }
    sqlite3_finalize(st);
}
