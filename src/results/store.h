/* store.h - the SQLite results database (DESIGN.md section 4).
 *
 * One file holds many runs.  A run row is written as 'running' and committed before
 * any of its rows; its rows follow in batched transactions; the row becomes
 * 'complete' or 'failed' at the end.  WAL journal: a process killed at any point
 * leaves the file consistent, earlier runs untouched and its own run not 'complete'. */
#ifndef ROCKFALL_STORE_H
#define ROCKFALL_STORE_H

#include <stddef.h>
#include <stdint.h>

#include <sqlite3.h>

#include "rockfall/error.h"
#include "rockfall/project.h"
#include "rockfall/records.h"

#include "results/schema.h"

#define RF_STORE_SCHEMA_VERSION RF_SCHEMA_VERSION

typedef struct rf_store rf_store;

/* Opens a results database for writing runs: creates the schema in a new file or
 * upgrades a file of an older version (rf_schema_prepare).  A file of a newer schema
 * version, another program's database or no database is an error, and left as it
 * was. */
int rf_store_open(const char *path, rf_store **out, rf_error *err);
void rf_store_close(rf_store *s);
sqlite3 *rf_store_db(rf_store *s);

/* What the next run is: whether it keeps only its maps (runs.store 'maps',
 * docs/scaling.md: the writer then adds the trajectories of its interceptions and
 * sampled paths only, and no tree hits), and where it runs (runs.ranks, runs.threads,
 * with runs.host this machine's name).  Default: every row, 1 rank of 1 thread. */
void rf_store_describe_run(rf_store *s, int maps, int ranks, int threads);
/* Writes the run row ('running'), its releases and measures, and commits. */
int rf_store_run_begin(rf_store *s, const rf_project *p, long n_trajectories,
                       int64_t *run_id, rf_error *err);
/* Ends the run: status "complete" or "failed". Commits any open batch first. */
int rf_store_run_finish(rf_store *s, const char *status, long n_trajectories, rf_error *err);

/* Batches: rows between begin and commit land in one transaction, all or none: a row
 * that fails to be written (rf_store_add_*) rolls the open batch back, and so does a
 * failed commit. */
int rf_store_batch_begin(rf_store *s, rf_error *err);
int rf_store_batch_commit(rf_store *s, rf_error *err);

int rf_store_add_trajectory(rf_store *s, size_t release_index, long idx,
                            const rf_trajectory_record *r, int64_t *trajectory_id,
                            rf_error *err);
int rf_store_add_path_point(rf_store *s, int64_t trajectory_id, long seq,
                            const rf_path_point *pt, rf_error *err);
int rf_store_add_interception(rf_store *s, int64_t trajectory_id,
                              const rf_interception_record *r, int64_t *interception_id,
                              rf_error *err);
int rf_store_add_tree_hit(rf_store *s, int64_t trajectory_id, const rf_tree_hit_record *r,
                          rf_error *err);
int rf_store_add_hazard_cell(rf_store *s, const rf_hazard_cell_record *r, rf_error *err);

/* A fit of `rockfall calibrate` (run/calibrate.h): what was fitted, to what, how well. */
typedef struct rf_calibration_record {
    const char *observed_path;
    size_t n_observed;
    const char *objective;   /* its name, e.g. "ks_runout + ks_lateral" */
    double value, ks_runout, ks_lateral, inside_share;
    long n_simulations, n_trajectories;
    int converged;
    size_t nkeys;
    const char *const *keys;  /* per key: its path, start and fitted value */
    const double *start, *fitted;
} rf_calibration_record;

/* Writes one calibrations row and its values in one transaction; its id into *id. */
int rf_store_calibration(rf_store *s, const rf_project *p, const rf_calibration_record *c,
                         int64_t *id, rf_error *err);

/* Ids of the current run and of its release and measure rows (by project index). */
int64_t rf_store_run_id(const rf_store *s);
int64_t rf_store_release_id(const rf_store *s, size_t release_index);
int64_t rf_store_measure_id(const rf_store *s, size_t measure_index);

#endif
