/* query.h - reading runs back from the results database for check and report. */
#ifndef ROCKFALL_QUERY_H
#define ROCKFALL_QUERY_H

#include <stdint.h>
#include <stdio.h>

#include <sqlite3.h>

#include "rockfall/error.h"
#include "rockfall/records.h"

/* Sets err to the database's last error (file: the database); returns -1. */
int rf_query_db_error(sqlite3 *db, rf_error *err);
/* Column i of the current row as a double; NAN where it holds NULL. */
double rf_query_column_real(sqlite3_stmt *st, int i);

/* The run to read: `wanted` when > 0 (it must exist), else the newest complete run. */
int rf_query_resolve_run(sqlite3 *db, long wanted, int64_t *run, rf_error *err);

/* Interception statistics of one measure of a run (energies in kJ). */
typedef struct rf_measure_stats {
    long n;
    long n_stopped, n_overtopped, n_broke_through, n_passed;
    double energy_p50, energy_p90, energy_p95, energy_p99, energy_max;
    double height_p95;
} rf_measure_stats;

/* One interception of a measure as the statistics need it; NAN where the database
 * holds NULL. */
typedef struct rf_crossing_row {
    double energy, height; /* energy_kj, passing_height_m */
    rf_outcome outcome;
} rf_crossing_row;

/* Every interception of the measure, in id order, into a malloc'd array. */
int rf_query_crossings(sqlite3 *db, int64_t measure_id, rf_crossing_row **rows, size_t *n,
                       rf_error *err);
/* The statistics of these rows (the percentiles over the rows that have the value). */
int rf_measure_stats_of(const rf_crossing_row *x, size_t n, rf_measure_stats *st, rf_error *err);
/* Both: one read of the measure's interceptions. */
int rf_query_measure_stats(sqlite3 *db, int64_t measure_id, rf_measure_stats *st,
                           rf_error *err);
/* The statistics columns of a measure's row (count, E50, E90, E95, E99, Emax, h95;
 * "-" where there is none) and their header, for every table that shows them. */
void rf_query_print_stats_header(FILE *out);
void rf_query_print_stats(FILE *out, const rf_measure_stats *s);
/* A table of every measure of the run with its statistics. */
void rf_query_print_measures(sqlite3 *db, int64_t run, FILE *out);

#endif
