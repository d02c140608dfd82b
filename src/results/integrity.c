/* integrity.c - the run's trajectories that cannot support a verdict, counted in one
 * query over its rows (integrity.h). */
#include "results/integrity.h"

#include <string.h>

#include "input/measure_kinds.h"
#include "results/schema.h"
#include "results/schema_legacy.h"

const char *const rf_integrity_rules[RF_N_INTEGRITY + 1] = {
    "trajectories_max_time", "trajectories_left_terrain", "trajectories_rest_on_steep_face",
    NULL};

char *rf_reach_kinds_sql(void)
{
    char *list = NULL;
    for (int k = 0; k < RF_N_MEASURE_KINDS; k++) {
        if (!rf_measure_kinds[k].reach_line)
            continue;
        char *more = sqlite3_mprintf("%s%s%Q", list ? list : "", list ? ", " : "",
                                     rf_measure_kinds[k].name);
        sqlite3_free(list);
        if (!(list = more))
            return NULL;
    }
    return list ? list : sqlite3_mprintf("NULL");
}

int rf_run_integrity_count(sqlite3 *db, int64_t run, rf_run_integrity *out, rf_error *err)
{
    memset(out, 0, sizeof *out);
    const char *file = sqlite3_db_filename(db, "main");
    int steep = rf_db_has_column(db, "trajectories", "rest_steep");
    char *kinds = rf_reach_kinds_sql();
    char *sql = kinds ? sqlite3_mprintf(
                            "SELECT count(*), coalesce(sum(stop_reason = 'max_time'), 0),"
                            " coalesce(sum(stop_reason = 'exited' AND NOT EXISTS (SELECT 1"
                            " FROM interceptions i JOIN measures m ON m.id = i.measure_id"
                            " WHERE i.trajectory_id = t.id AND m.kind IN (%s))), 0),"
                            " %s, %s FROM trajectories t WHERE t.run_id = ?1",
                            kinds, steep ? "coalesce(sum(rest_steep = 1), 0)" : "0",
                            steep ? "count(rest_steep)" : "0")
                      : NULL;
    sqlite3_free(kinds);
    if (!sql)
        return rf_error_set(err, file, 0, 0, "out of memory counting the trajectories");
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
    sqlite3_free(sql);
    if (rc == SQLITE_OK) {
        sqlite3_bind_int64(st, 1, run);
        rc = sqlite3_step(st);
    }
    if (rc == SQLITE_ROW) {
        out->n_trajectories = (long)sqlite3_column_int64(st, 0);
        for (int k = 0; k < RF_N_INTEGRITY; k++)
            out->count[k] = (long)sqlite3_column_int64(st, 1 + k);
        out->recorded[RF_INTEGRITY_MAX_TIME] = out->recorded[RF_INTEGRITY_LEFT_TERRAIN] = 1;
        out->recorded[RF_INTEGRITY_REST_STEEP] =
            sqlite3_column_int64(st, 4) == sqlite3_column_int64(st, 0);
    }
    int status = rf_sql_status(db, file, rc, "counting the trajectories that cannot support "
                               "a verdict", err);
    sqlite3_finalize(st);
    if (status == 0 && !out->recorded[RF_INTEGRITY_REST_STEEP]) {
        /* which engine ran it, from the project text the run stores */
        rc = sqlite3_prepare_v2(db, "SELECT project_yaml FROM runs WHERE id = ?1", -1, &st,
                                NULL);
        if (rc == SQLITE_OK) {
            sqlite3_bind_int64(st, 1, run);
            rc = sqlite3_step(st);
            if (rc == SQLITE_ROW)
                out->fixed_step =
                    rf_legacy_fixed_step((const char *)sqlite3_column_text(st, 0));
        }
        status = rf_sql_status(db, file, rc == SQLITE_DONE ? SQLITE_ROW : rc,
                               "reading the run's engine", err);
        sqlite3_finalize(st);
    }
    return status;
}
