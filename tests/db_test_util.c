/* db_test_util.c - single values read from a results database in the tests. */
#include "db_test_util.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "results/run_view.h"
#include "test.h"

/* The query's statement stepped to its first row. */
static sqlite3_stmt *first_row(sqlite3 *db, const char *fmt, va_list ap)
{
    char sql[2048];
    vsnprintf(sql, sizeof sql, fmt, ap);
    sqlite3_stmt *st = NULL;
    ENSURE_MSG(sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK, "%s: %s", sql,
               sqlite3_errmsg(db));
    ENSURE_MSG(sqlite3_step(st) == SQLITE_ROW, "%s: no row", sql);
    return st;
}

long long dbt_int(sqlite3 *db, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    sqlite3_stmt *st = first_row(db, fmt, ap);
    va_end(ap);
    long long v = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    return v;
}

double dbt_real(sqlite3 *db, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    sqlite3_stmt *st = first_row(db, fmt, ap);
    va_end(ap);
    double v = rf_query_column_real(st, 0);
    sqlite3_finalize(st);
    return v;
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t k = 0; k < n; k++)
        h = (h ^ b[k]) * 1099511628211ull;
    return h;
}

unsigned long long dbt_rows_hash(sqlite3 *db, const char *sql, long *nrows)
{
    sqlite3_stmt *st;
    ENSURE_MSG(sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK, "%s: %s", sql,
               sqlite3_errmsg(db));
    uint64_t h = 14695981039346656037ull;
    long n = 0;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        n++;
        for (int c = 0; c < sqlite3_column_count(st); c++) {
            unsigned char type = (unsigned char)sqlite3_column_type(st, c);
            if (type == SQLITE_INTEGER) {
                int64_t v = sqlite3_column_int64(st, c);
                h = fnv(h, &v, sizeof v);
            } else if (type == SQLITE_FLOAT) {
                double v = sqlite3_column_double(st, c);
                h = fnv(h, &v, sizeof v);
            } else if (type != SQLITE_NULL) {
                const void *b = sqlite3_column_blob(st, c);
                h = fnv(h, b, (size_t)sqlite3_column_bytes(st, c));
            }
            h = fnv(h, &type, 1);
        }
        h = fnv(h, "\xff", 1);
    }
    ENSURE_MSG(rc == SQLITE_DONE, "%s: %s", sql, sqlite3_errmsg(db));
    sqlite3_finalize(st);
    if (nrows)
        *nrows = n;
    return (unsigned long long)h;
}

void dbt_tables_hash(sqlite3 *db, char *out, size_t cap)
{
    sqlite3_stmt *tables;
    ENSURE(sqlite3_prepare_v2(db,
                              "SELECT name FROM sqlite_master WHERE type = 'table' AND name "
                              "NOT LIKE 'sqlite_%' ORDER BY name",
                              -1, &tables, NULL) == SQLITE_OK);
    size_t at = 0;
    out[0] = '\0';
    while (sqlite3_step(tables) == SQLITE_ROW) {
        char table[256], cols[4096] = "", sql[8192];
        snprintf(table, sizeof table, "%s", (const char *)sqlite3_column_text(tables, 0));
        snprintf(sql, sizeof sql,
                 "SELECT group_concat('\"' || name || '\"', ', ') FROM pragma_table_info('%s') "
                 "WHERE name NOT LIKE '%%\\_at' ESCAPE '\\' AND name <> 'last_change' AND"
                 " ('%s' <> 'runs' OR name NOT IN ('host', 'ranks', 'threads'))",
                 table, table);
        sqlite3_stmt *st;
        ENSURE(sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK);
        ENSURE(sqlite3_step(st) == SQLITE_ROW);
        snprintf(cols, sizeof cols, "%s", (const char *)sqlite3_column_text(st, 0));
        sqlite3_finalize(st);
        snprintf(sql, sizeof sql, "SELECT %s FROM \"%s\" ORDER BY %s", cols, table, cols);
        long n;
        unsigned long long h = dbt_rows_hash(db, sql, &n);
        at += (size_t)snprintf(out + at, at < cap ? cap - at : 0, "%s %ld %016llx\n", table, n, h);
        ENSURE(at < cap);
    }
    sqlite3_finalize(tables);
}
