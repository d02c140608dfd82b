/* query.h - reading runs back from the results database for check and report. */
#ifndef ROCKFALL_QUERY_H
#define ROCKFALL_QUERY_H

#include <stdint.h>
#include <stdio.h>

#include <sqlite3.h>

#include "rockfall/error.h"

/* Sets err to the database's last error (file: the database); returns -1. */
int rf_query_db_error(sqlite3 *db, rf_error *err);

/* The run to read: `wanted` when > 0 (it must exist), else the newest complete run. */
int rf_query_resolve_run(sqlite3 *db, long wanted, int64_t *run, rf_error *err);

/* Interception statistics of one measure of a run (energies in kJ). */
typedef struct rf_measure_stats {
    long n;
    long n_stopped, n_overtopped, n_broke_through, n_passed;
    double energy_p50, energy_p90, energy_p95, energy_p99, energy_max;
    double height_p95;
} rf_measure_stats;

int rf_query_measure_stats(sqlite3 *db, int64_t measure_id, rf_measure_stats *st,
                           rf_error *err);
/* The statistics columns of a measure's row (count, E50, E90, E95, E99, Emax, h95;
 * "-" where there is none) and their header, for every table that shows them. */
void rf_query_print_stats_header(FILE *out);
void rf_query_print_stats(FILE *out, const rf_measure_stats *s);
/* A table of every measure of the run with its statistics. */
void rf_query_print_measures(sqlite3 *db, int64_t run, FILE *out);

#endif
