/* db_test_util.c - single values read from a results database in the tests. */
#include "db_test_util.h"

#include <stdarg.h>
#include <stdio.h>

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
