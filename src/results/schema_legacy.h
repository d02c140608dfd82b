/* schema_legacy.h - what a file of schema version 1 kept only in each run's project
 * text (runs.project_yaml), read from that text: whether a barrier's SEL was given and
 * which rule file the project names.  Used once, by the upgrade to version 2, and by
 * the run view on a version-1 file that has not been upgraded. */
#ifndef ROCKFALL_SCHEMA_LEGACY_H
#define ROCKFALL_SCHEMA_LEGACY_H

#include <sqlite3.h>

#include "rockfall/error.h"

/* 1 when the project text gives measure `name` a sel, 0 when not, -1 when unknown (no
 * text, or text that does not parse). */
int rf_legacy_sel_given(const char *project_yaml, const char *name);
/* 1 when the project text's simulation.engine is fixed_step, else 0 (also for no text). */
int rf_legacy_fixed_step(const char *project_yaml);

/* The rule file the project text names (`rules:`), resolved from the directory of
 * project_path; malloc'd, NULL when it names none. */
char *rf_legacy_rules_path(const char *project_yaml, const char *project_path);

/* Fills, within the caller's transaction, runs.rules_path and the barriers'
 * measures.sel_source of a file just upgraded from version 1. */
int rf_legacy_fill(sqlite3 *db, const char *path, rf_error *err);

#endif
