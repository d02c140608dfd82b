/* schema.h - the results database's schema and how each command opens a file
 * (docs/database.md "Schema policy").
 *
 *   run      rf_schema_prepare: creates the schema in an empty file, or upgrades a file
 *            of an older version, in one transaction; a file that is not ours (another
 *            program's SQLite database, no database at all) or of a newer version is
 *            refused and left as it was;
 *   check    rf_db_open(RF_DB_CHECK): a file of any version this build reads, opened
 *            read-write; check writes only its own rows and never the schema;
 *   report   rf_db_open(RF_DB_READ): read-only (SQLITE_OPEN_READONLY); the file is
 *            never written, and may lie in a folder the reader cannot write. */
#ifndef ROCKFALL_SCHEMA_H
#define ROCKFALL_SCHEMA_H

#include <sqlite3.h>

#include "rockfall/error.h"

/* The schema this build writes; it reads every version from 1 up to it. */
#define RF_SCHEMA_VERSION 5

/* The one place SQLite's return codes become the rf_error convention: 0 for success
 * (SQLITE_OK, SQLITE_ROW, SQLITE_DONE), otherwise -1 with "doing: sqlite's message"
 * and the database file named in err. */
int rf_sql_status(sqlite3 *db, const char *path, int rc, const char *doing, rf_error *err);

/* Creates or upgrades the schema of the open file (see above), and switches it to the
 * WAL journal. */
int rf_schema_prepare(sqlite3 *db, const char *path, rf_error *err);

/* The rows of measure_kinds for every kind of this build (kinds already there are
 * kept); run writes them with each run, so a file gains the kinds of a newer build. */
int rf_schema_add_kinds(sqlite3 *db, const char *path, rf_error *err);

/* The schema version of an open file: 1 .. RF_SCHEMA_VERSION, else an error (not ours,
 * empty, or newer). */
int rf_schema_version(sqlite3 *db, const char *path, int *version, rf_error *err);

typedef enum rf_db_mode { RF_DB_READ, RF_DB_CHECK } rf_db_mode;
/* Opens an existing results database as `mode` says; *version (may be NULL) gets its
 * schema version.  Returns 0, or -1 with err set and *db NULL. */
int rf_db_open(const char *path, rf_db_mode mode, sqlite3 **db, int *version, rf_error *err);

/* Whether the file has the table (one a later schema version added). */
int rf_db_has_table(sqlite3 *db, const char *table);
/* Whether the file's table has the column (one a later schema version added). */
int rf_db_has_column(sqlite3 *db, const char *table, const char *column);

#endif
