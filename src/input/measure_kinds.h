/* measure_kinds.h - the class table of protection-measure kinds.
 *
 * A kind of measure (barrier, embankment, control line) is one row of rf_measure_kinds,
 * indexed by rf_measure_kind: its name in the project file and the results database
 * (measures.kind, a row of measure_kinds), its name in the report, what Table 3
 * classifies for it, the keys the project loader reads for it and the outcome of a
 * rock crossing it.  The loader, the store, the rules and the report read a kind's
 * facts only from here; a new kind is its name in rf_measure_kind (project.h), one row
 * here and its functions, and, when Table 3 classifies it, its `capacities` entry in
 * the rule file. */
#ifndef ROCKFALL_MEASURE_KINDS_H
#define ROCKFALL_MEASURE_KINDS_H

#include "input/yamldoc.h"
#include "rockfall/error.h"
#include "rockfall/project.h"

/* One measure item of a project file, as a kind's reader sees it. */
typedef struct rf_measure_item {
    rf_ydoc *d;
    const rf_ynode *node; /* the item's mapping */
    const char *what;     /* "measures item N", naming the item in messages */
    rf_error *err;
} rf_measure_item;

typedef struct rf_measure_kind_class {
    const char *name;    /* in YAML (`kind:`), in measures.kind and measure_kinds.name */
    const char *label;   /* in the report and messages: "a barrier" */
    const char *colour;  /* its line on the report's plan */
    int classified;      /* Table 3 classifies its interceptions: the rule file gives its
                          * `capacities`, the checks judge it */
    int reach_line;      /* the protected line: the layout counts the rockfalls across
                          * it, the report draws their arrivals along it */
    int has_mel;         /* it has a MEL and a SEL (measures.mel_kj, sel_kj, sel_source), from
                          * which a rule file may take its capacities */
    const char *states;  /* JSON list of the limit states it may have a capacity for
                          * (measure_kinds.limit_states) */
    const char *const *keys; /* its keys besides name, kind, line, importance, behaviour */
    /* Reads the kind's keys of the item into m (kind, line, importance and behaviour
     * are read); 0, or -1 with it->err at the offending node. */
    int (*read)(const rf_measure_item *it, rf_measure *m);
    /* What it does to a rock whose centre passes at passing_height_m above the ground
     * with kinetic energy energy_kj (see rf_measure_outcome). */
    rf_outcome (*outcome)(const rf_measure *m, double passing_height_m, double energy_kj);
} rf_measure_kind_class;

extern const rf_measure_kind_class rf_measure_kinds[RF_N_MEASURE_KINDS];

/* Every key a measure item may have: the common ones and every kind's, NULL-ended. */
extern const char *const rf_measure_item_keys[];

/* The row of a kind named `name`; -1 when no kind has that name. */
int rf_measure_kind_find(const char *name);

/* The energy (kJ) above which a structure breaks through: its last limit state's
 * capacity (a barrier's MEL; an embankment's largest capacity given).  Infinite for a
 * measure without capacities (control lines) and `collect` measures. */
double rf_measure_breaking_energy(const rf_measure *m);

#endif
