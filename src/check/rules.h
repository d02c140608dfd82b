/* rules.h - the rules engine: Table 3 limit states and the design checks (DESIGN.md
 * section 3, docs/rules.md).
 *
 * Three stages, each usable on its own:
 *   load      a rule file (YAML) -> rf_rules, validated once with file:line:column
 *             errors (rf_rules_load);
 *   classify  pure functions of the rules: the limit state an interception reaches,
 *             the state Table 3 requires, whether a check passes;
 *   evaluate  against a results database: every interception of a run classified into
 *             `classifications`, every measure's checks into `checks`, then a printed
 *             table (rf_rules_evaluate). */
#ifndef ROCKFALL_RULES_H
#define ROCKFALL_RULES_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <sqlite3.h>

#include "rockfall/error.h"
#include "input/measure_kinds.h" /* RF_N_MEASURE_KINDS */
#include "rockfall/project.h"
#include "rockfall/records.h"
#include "results/integrity.h" /* rf_integrity_kind */

/* Where a structure kind's capacity for one limit state comes from. */
typedef enum rf_capacity_source {
    RF_CAP_NONE,    /* the kind has no capacity for this state: the state is skipped */
    RF_CAP_MEL,     /* a barrier's MEL (measures.mel_kj) */
    RF_CAP_SEL,     /* a barrier's SEL: the project's sel, else MEL / sel_divisor */
    RF_CAP_PROJECT  /* the project's capacity for the state (measures.cap_<state>_kj) */
} rf_capacity_source;

typedef enum rf_comparison { RF_CMP_GREATER, RF_CMP_AT_LEAST } rf_comparison;

typedef enum rf_check_value {
    RF_VALUE_SHARE_WITHIN,  /* share of interceptions reaching `state` or an earlier one */
    RF_VALUE_SHARE_MEETING, /* share of interceptions within their required state */
    RF_VALUE_SHARE_KEPT     /* layout: share of the run's rockfalls that cross no control
                             * line and whose every interception with a barrier or
                             * embankment reaches `state` or an earlier one */
} rf_check_value;

typedef struct rf_rule_check {
    char *name;               /* checks.rule */
    rf_check_value value;
    int state;                /* SHARE_WITHIN: index into rf_rules.states */
    rf_comparison comparison; /* value > threshold or value >= threshold */
    double threshold;         /* 0..1 */
} rf_rule_check;


/* Reached limit states that are not an index into rf_rules.states. */
#define RF_REACHED_OVERTOPPED (-1) /* passed over the structure: fails its function */
#define RF_REACHED_UNKNOWN (-2)    /* no energy recorded */

typedef struct rf_rules {
    char *path;                  /* the rule file as given */
    char *text;                  /* its text, stored with the checks (check_rules) */
    char *name;                  /* its `name` */
    rf_limit_state states[RF_N_LIMIT_STATES]; /* in order, first = serviceability */
    int nstates;                 /* index nstates = beyond the last (`beyond_last`) */
    char *beyond_last;           /* "collapse" */
    int required[3][3];          /* [action level - 1][rf_importance] -> state index */
    /* by measure kind (rf_measure_kinds; only the classified kinds' rows are set) and
     * rf_limit_state */
    rf_capacity_source capacity[RF_N_MEASURE_KINDS][RF_N_LIMIT_STATES];
    double sel_divisor;          /* barrier SEL = MEL / sel_divisor; 0 when not given */
    rf_rule_check *checks;       /* of every barrier and embankment */
    size_t nchecks;
    rf_rule_check *layout_checks; /* of the run's layout as a whole */
    size_t nlayout;
    int empty_passes;            /* a measure without interceptions passes its checks */
    /* by rf_integrity_kind: the largest share of the run's trajectories of that kind
     * with which the run still supports a verdict (`allowance:`, docs/rules.md) */
    double allowance[RF_N_INTEGRITY];
} rf_rules;

/* The defaults of `allowance:`: no trajectory ended by max_time or put to rest on a
 * steep face, 1 % of the trajectories leaving the terrain before any control line. */
#define RF_ALLOWANCE_MAX_TIME 0.0
#define RF_ALLOWANCE_LEFT_TERRAIN 0.01
#define RF_ALLOWANCE_REST_STEEP 0.0

/* By rf_integrity_kind: the key of `allowance:` (the rule of its checks row is
 * rf_integrity_rules, results/integrity.h). */
extern const char *const rf_allowance_keys[RF_N_INTEGRITY + 1];

/* A checked run's verdict.  INCONCLUSIVE wins over FAIL (docs/rules.md). */
typedef enum rf_verdict { RF_VERDICT_PASS, RF_VERDICT_FAIL, RF_VERDICT_INCONCLUSIVE } rf_verdict;

typedef struct rf_rules_result {
    long failed;        /* design checks failed */
    long inconclusive;  /* integrity checks beyond their allowance */
    rf_verdict verdict;
} rf_rules_result;

/* Loads and validates a rule file.  On error fills err with file:line:column and
 * returns nonzero; r is then left empty. */
int rf_rules_load(const char *path, rf_rules *r, rf_error *err);
/* The same from text in memory; `file` names it in errors. */
int rf_rules_load_text(const char *file, const char *text, size_t len, rf_rules *r,
                       rf_error *err);
void rf_rules_free(rf_rules *r);

/* Name of a reached state: a limit state, beyond_last, "overtopped" or NULL (unknown). */
const char *rf_rules_state_name(const rf_rules *r, int reached);

/* ---- classification (pure) ---------------------------------------------------- */

/* Capacities of one measure in kJ, by rf_limit_state (NaN: none) from what the
 * project gave: mel (barrier), sel (barrier; NaN when the project gave none),
 * project_capacity[] by rf_limit_state (NaN when not given). */
void rf_rules_capacities(const rf_rules *r, rf_measure_kind kind, double mel, double sel,
                         const double project_capacity[RF_N_LIMIT_STATES],
                         double capacity[RF_N_LIMIT_STATES]);
/* The state an interception reaches: the index of the first state in order whose
 * capacity holds the energy (energy <= capacity; states without a capacity are
 * skipped), nstates beyond the last, RF_REACHED_OVERTOPPED for an overtopping,
 * nstates for a break-through and RF_REACHED_UNKNOWN for an energy not known (NaN). */
int rf_rules_reached(const rf_rules *r, const double capacity[RF_N_LIMIT_STATES],
                     double energy_kj, rf_outcome outcome);
/* Table 3: the state index required for an action level (1..3) and an importance. */
int rf_rules_required(const rf_rules *r, int action_level, rf_importance importance);
/* Whether a reached state meets the required one. */
int rf_rules_meets(const rf_rules *r, int reached, int required);
/* Whether a check's value passes its threshold. */
int rf_rules_check_passes(const rf_rule_check *c, double value);
/* Whether `count` of n trajectories is within a share `allowance` (count / n <=
 * allowance; nothing is beyond an allowance in a run without trajectories). */
int rf_rules_within_allowance(long count, long n, double allowance);

/* ---- against the database ----------------------------------------------------- */

/* The rule file named by a run's project (runs.rules_path, resolved when the run was
 * written).  *path is malloc'd; an error says to pass --rules when the run names
 * none. */
int rf_rules_path_of_run(sqlite3 *db, int64_t run, char **path, rf_error *err);

/* Classifies every interception of the run's measures of the kinds Table 3 classifies
 * and writes the checks of each, the layout's (measure_id NULL) and the rule file
 * (check_rules), replacing what an earlier evaluation of the run wrote, in one
 * transaction; nothing else in the file is written.  When out is not NULL it then prints the evaluated run there: per
 * measure the statistics, capacities, share per limit state and each check's verdict,
 * then the overall verdict.  *n_failed (may be NULL) gets the number of failed checks. */
int rf_rules_evaluate(sqlite3 *db, int64_t run, const rf_rules *r, FILE *out, long *n_failed,
                      rf_error *err);
/* The same, with the integrity checks' outcome and the verdict in *res (may be NULL):
 * every evaluation also writes one checks row per rf_integrity_kind (measure_id NULL,
 * rule rf_integrity_rules[k], value the share of the run's trajectories of the kind,
 * threshold its allowance, on_failure 'inconclusive' where the file has the column). */
int rf_rules_evaluate_verdict(sqlite3 *db, int64_t run, const rf_rules *r, FILE *out,
                              rf_rules_result *res, rf_error *err);

#endif
