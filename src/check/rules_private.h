/* rules_private.h - what the files of the rules engine share (rules.c evaluates a run,
 * rules_print.c prints it, rules_load.c reads the rule file). */
#ifndef ROCKFALL_RULES_PRIVATE_H
#define ROCKFALL_RULES_PRIVATE_H

#include <stdint.h>
#include <stdio.h>

#include <sqlite3.h>

#include "check/rules.h"

/* ">" and ">=", by rf_comparison, NULL-ended. */
extern const char *const rf_rules_comparison_names[];

/* One measure of the run as the classification needs it. */
typedef struct rf_rules_measure {
    int64_t id;
    char *name;
    rf_measure_kind kind;
    int importance;
    double capacity[RF_N_LIMIT_STATES];
} rf_rules_measure;

/* A run's measures that the rules judge, read once for the evaluation and the
 * printout. */
typedef struct rf_rules_run {
    char *project;     /* runs.project */
    rf_rules_measure *m;
    size_t n;
    long n_rockfalls;  /* the run's trajectories, when the rules have layout checks */
    long *kept;        /* those each layout check kept */
    rf_run_integrity integrity;    /* the trajectories that cannot support a verdict */
    int within[RF_N_INTEGRITY];    /* each kind within its allowance */
} rf_rules_run;


/* Prepares sql; on failure err says what was being done. */
int rf_rules_prepare_for(sqlite3 *db, const char *sql, sqlite3_stmt **st, const char *doing,
                         rf_error *err);
/* The first integer of a query's first row (?1 = run); -1 on error (err set, saying
 * what was being counted). */
long rf_rules_query_count(sqlite3 *db, const char *sql, int64_t run, const char *what,
                          rf_error *err);
/* The names of the kinds with reach_line (control lines) as an SQL list, quoted
 * ('control'), or NULL when memory runs out; sqlite3_free it. */
char *rf_rules_reach_kinds_sql(void);

/* Prints the evaluated run: the checks just written, their outcome in res. */
int rf_rules_print_run(sqlite3 *db, int64_t run, const rf_rules *r, const rf_rules_run *L,
                       const rf_rules_result *res, FILE *out, rf_error *err);

#endif
