/* db_test_util.h - single values read from a results database in the tests. */
#ifndef ROCKFALL_DB_TEST_UTIL_H
#define ROCKFALL_DB_TEST_UTIL_H

#include <stddef.h>

#include <sqlite3.h>

/* The first column of the first row of a query (printf-style); ENSUREs the query runs
 * and returns a row. */
__attribute__((format(printf, 2, 3))) long long dbt_int(sqlite3 *db, const char *fmt, ...);
/* The same as a real; NaN for NULL. */
__attribute__((format(printf, 2, 3))) double dbt_real(sqlite3 *db, const char *fmt, ...);

/* A 64-bit FNV-1a hash of a query's rows (every column, its type and value bits; each
 * row ended), and their number in *nrows (may be NULL). */
unsigned long long dbt_rows_hash(sqlite3 *db, const char *sql, long *nrows);
/* The hash of every table of the file (in name order; each table's rows by its
 * columns in order), leaving out when and where a run ran: the columns whose name ends
 * in "_at" (when it started and finished), gpkg_contents's last_change (when a layer
 * was last written) and runs' host, ranks and threads; one line
 * per table into out ("NAME ROWS HASH"). */
void dbt_tables_hash(sqlite3 *db, char *out, size_t cap);

#endif
