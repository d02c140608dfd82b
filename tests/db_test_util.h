/* db_test_util.h - single values read from a results database in the tests. */
#ifndef ROCKFALL_DB_TEST_UTIL_H
#define ROCKFALL_DB_TEST_UTIL_H

#include <sqlite3.h>

/* The first column of the first row of a query (printf-style); ENSUREs the query runs
 * and returns a row. */
__attribute__((format(printf, 2, 3))) long long dbt_int(sqlite3 *db, const char *fmt, ...);
/* The same as a real; NaN for NULL. */
__attribute__((format(printf, 2, 3))) double dbt_real(sqlite3 *db, const char *fmt, ...);

#endif
