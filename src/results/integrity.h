/* integrity.h - whether a run's trajectories can support a verdict (DESIGN.md section 6
 * "Trust", docs/rules.md "Verdict integrity"): the trajectories whose end says nothing
 * about the layout, counted from the database so that `run` and `check` count the same
 * rows the same way. */
#ifndef ROCKFALL_INTEGRITY_H
#define ROCKFALL_INTEGRITY_H

#include <stdint.h>

#include <sqlite3.h>

#include "rockfall/error.h"

/* The kinds of trajectories that cannot support a verdict. */
typedef enum rf_integrity_kind {
    RF_INTEGRITY_MAX_TIME,     /* ended by simulation.max_time: cut short on the slope */
    RF_INTEGRITY_LEFT_TERRAIN, /* left the terrain before crossing any control line (a
                                * measure of a reach_line kind): the terrain ends before
                                * the protected line, or the rock passed it by */
    RF_INTEGRITY_REST_STEEP,   /* put to rest by the fixed-step engine on a face steeper
                                * than its friction holds (tan theta > mu) */
    RF_N_INTEGRITY
} rf_integrity_kind;

/* By rf_integrity_kind: the rule of its row in `checks` (measure_id NULL). */
extern const char *const rf_integrity_rules[RF_N_INTEGRITY + 1];

typedef struct rf_run_integrity {
    long n_trajectories;
    long count[RF_N_INTEGRITY];
    /* whether the file records the kind for every trajectory of the run: rest_steep
     * is recorded from schema version 3 (a file of an earlier version, or its runs
     * written before an upgrade, do not say) */
    int recorded[RF_N_INTEGRITY];
    /* the run used the fixed-step engine (its stored project text says so): where the
     * file does not record rest_steep, a rest on a steep face may have gone unrecorded */
    int fixed_step;
} rf_run_integrity;

/* The names of the kinds with reach_line (control lines) as a quoted SQL list
 * ('control'), or NULL when memory runs out; sqlite3_free it. */
char *rf_reach_kinds_sql(void);

/* Counts the run's trajectories of each kind.  Returns 0, or -1 with err set. */
int rf_run_integrity_count(sqlite3 *db, int64_t run, rf_run_integrity *out, rf_error *err);

#endif
