/* run_view.h - one run of a results database as its readers see it: check, report and
 * any later export read a run through here (rf_run_view: the run, its releases and
 * measures, the terrain it stored; the rf_query_* readers of its rows), never through
 * the project or terrain files, which may have changed or gone since the run.
 *
 * It reads every schema version from 1: what version 1 kept only in the project text
 * (whether a barrier's SEL was given, the rule file) comes from that text
 * (schema_legacy.h), and what it did not keep at all (the terrain, the surface
 * friction, the hazard cell) is absent (NaN, has_grid 0). */
#ifndef ROCKFALL_RUN_VIEW_H
#define ROCKFALL_RUN_VIEW_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <sqlite3.h>

#include "results/terrain_grid.h"
#include "rockfall/error.h"
#include "rockfall/project.h"
#include "rockfall/records.h"

typedef struct rf_view_release {
    int64_t id;
    char *name, *rock;
    double x, y, z, mass;
    int action_level;
    long count;
} rf_view_release;

typedef struct rf_view_measure {
    int64_t id;
    long idx;
    char *name;
    char *kind_name;       /* measures.kind */
    int kind;              /* its row in rf_measure_kinds; -1 for a kind this build does
                            * not know */
    char *importance_name; /* measures.importance */
    int importance;        /* rf_importance; -1 when not one */
    double height, mel, sel, cap[RF_N_LIMIT_STATES]; /* NaN where NULL */
    int sel_given;         /* a barrier's SEL: 1 given, 0 the default MEL/3, -1 not known
                            * or no barrier */
    double *xy;            /* its line, n points */
    size_t n;
} rf_view_measure;

/* The point of a measure's line nearest a release, and the ground there (NaN off the
 * terrain). */
typedef struct rf_view_ground {
    int64_t release_id, measure_id;
    double x, y, z;
} rf_view_ground;

typedef struct rf_run_view {
    sqlite3 *db;
    int schema;                /* the file's schema version */
    int64_t id;
    char *project, *project_path, *seed, *status, *started, *finished, *version, *yaml;
    char *rules_path;          /* the rule file the run's project names; NULL: none */
    double surface_friction;   /* mean of the terrain's default surface; NaN: not stored */
    double hazard_cell;        /* m; NaN: not stored */
    long n_trajectories;       /* rows in trajectories */
    rf_view_release *rel;
    size_t nrel;
    rf_view_measure *mea;
    size_t nmea;
    int has_grid;              /* the run stored its terrain */
    rf_terrain_grid grid;
    rf_view_ground *ground;
    size_t nground;
} rf_run_view;

/* Reads run `run` (it must exist) of the open database into v.  Returns 0, or -1 with
 * err set (v is then empty). */
int rf_run_view_load(sqlite3 *db, int64_t run, rf_run_view *v, rf_error *err);
void rf_run_view_free(rf_run_view *v);

/* The ground point of a release and a measure; NULL when the run stored none. */
const rf_view_ground *rf_run_view_ground(const rf_run_view *v, int64_t release_id,
                                         int64_t measure_id);

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
