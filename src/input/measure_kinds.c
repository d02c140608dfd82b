/* measure_kinds.c - the class table of measure kinds (see measure_kinds.h). */
#include "input/measure_kinds.h"

#include <math.h>
#include <string.h>

#include "input/bounds.h"

/* ---- the project's keys of each kind --------------------------------------------- */

/* A value within its bound of input/bounds.h, checked after its reader: 0, or an error at
 * n, "'KEY' must be from 0 to MAX UNIT, got V". */
static int at_most(const rf_measure_item *it, const rf_ynode *n, const char *key, double v,
                   double max, const char *unit)
{
    if (v <= max)
        return 0;
    char got[64];
    return rf_ydoc_error(it->d, n, it->err, "'%s' must be from 0 to %g %s, got %s", key, max,
                         unit, rf_ydoc_describe(n, got, sizeof got));
}

/* The capacities under `capacity` (kJ per limit state); nodes[s] gets the node of each
 * one given.  A kind that needs them (an embankment) says so with `required`. */
static int read_capacity(const rf_measure_item *it, rf_measure *m, rf_ynode **nodes,
                         int required)
{
    rf_ydoc *d = it->d;
    rf_ynode *cap = rf_ydoc_get(d, it->node, "capacity");
    if (!cap) {
        if (required)
            return rf_ydoc_error(d, it->node, it->err,
                                 "missing required key 'capacity' in measure '%s' (an "
                                 "embankment needs its capacity in kJ per limit state)",
                                 m->name);
        return 0;
    }
    if (rf_ydoc_mapping_of(d, cap, rf_limit_state_names, "'capacity'", it->err))
        return -1;
    if (rf_ydoc_map_size(cap) == 0)
        return rf_ydoc_error(d, cap, it->err,
                             "'capacity' must give at least one of serviceability, "
                             "restorability, ultimate, near_collapse (kJ)");
    for (int s = 0; s < RF_N_LIMIT_STATES; s++) {
        rf_ynode *v = rf_ydoc_get(d, cap, rf_limit_state_names[s]);
        if (!v)
            continue;
        if (m->kind == RF_BARRIER && (s == RF_SERVICEABILITY || s == RF_ULTIMATE))
            return rf_ydoc_error(d, v, it->err,
                                 "a barrier's %s capacity comes from '%s'; remove it from "
                                 "'capacity'",
                                 rf_limit_state_names[s], s == RF_ULTIMATE ? "mel" : "sel");
        if (m->kind == RF_BARRIER && s == RF_NEAR_COLLAPSE)
            return rf_ydoc_error(d, v, it->err,
                                 "a barrier's last limit state is its MEL (ultimate); "
                                 "'near_collapse' is for embankments");
        if (rf_ydoc_number(d, v, rf_limit_state_names[s], RF_YR_POSITIVE, &m->capacity[s],
                           it->err) ||
            at_most(it, v, rf_limit_state_names[s], m->capacity[s], RF_CAPACITY_MAX, "kJ"))
            return -1;
        nodes[s] = v;
    }
    return 0;
}

/* The capacities given (nodes) must not decrease from serviceability to near_collapse.
 * A barrier's SEL of MEL / 3 for want of 'sel' is a default, which the rule file may
 * set otherwise (docs/rules.md): it bounds nothing. */
static int capacities_ordered(const rf_measure_item *it, const rf_measure *m,
                              rf_ynode *const *nodes)
{
    int prev = -1;
    for (int s = 0; s < RF_N_LIMIT_STATES; s++) {
        if (!nodes[s])
            continue;
        if (prev >= 0 && m->capacity[s] < m->capacity[prev])
            return rf_ydoc_error(it->d, nodes[s], it->err,
                                 "%s capacity (%g kJ) must not be below the %s capacity "
                                 "(%g kJ): capacities must not decrease from serviceability "
                                 "to near_collapse",
                                 rf_limit_state_names[s], m->capacity[s],
                                 rf_limit_state_names[prev], m->capacity[prev]);
        prev = s;
    }
    return 0;
}

/* The screen's height above the ground (required). */
static int read_height(const rf_measure_item *it, rf_measure *m)
{
    rf_ynode *height;
    return rf_ydoc_require(it->d, it->node, "height", it->what, &height, it->err) ||
                   rf_ydoc_number(it->d, height, "height", RF_YR_POSITIVE, &m->height,
                                  it->err) ||
                   at_most(it, height, "height", m->height, RF_MEASURE_HEIGHT_MAX, "m")
               ? -1
               : 0;
}

/* A barrier: MEL required; SEL as given, else MEL / 3 marked as a default
 * (m->sel_given 0), which the rule file may replace. */
static int read_barrier(const rf_measure_item *it, rf_measure *m)
{
    rf_ydoc *d = it->d;
    rf_ynode *mel, *nodes[RF_N_LIMIT_STATES] = {NULL};
    if (read_height(it, m) || rf_ydoc_require(d, it->node, "mel", it->what, &mel, it->err) ||
        rf_ydoc_number(d, mel, "mel", RF_YR_POSITIVE, &m->mel, it->err) ||
        at_most(it, mel, "mel", m->mel, RF_CAPACITY_MAX, "kJ"))
        return -1;
    m->sel = m->mel / 3.0;
    m->sel_given = 0;
    rf_ynode *sel = rf_ydoc_get(d, it->node, "sel");
    if (sel) {
        if (rf_ydoc_number(d, sel, "sel", RF_YR_POSITIVE, &m->sel, it->err))
            return -1;
        if (m->sel > m->mel)
            return rf_ydoc_error(d, sel, it->err, "'sel' (%g kJ) must not exceed 'mel' (%g kJ)",
                                 m->sel, m->mel);
        m->sel_given = 1;
    }
    m->capacity[RF_SERVICEABILITY] = m->sel;
    m->capacity[RF_ULTIMATE] = m->mel;
    nodes[RF_SERVICEABILITY] = sel;
    nodes[RF_ULTIMATE] = mel;
    return read_capacity(it, m, nodes, 0) || capacities_ordered(it, m, nodes) ? -1 : 0;
}

static int read_embankment(const rf_measure_item *it, rf_measure *m)
{
    rf_ynode *nodes[RF_N_LIMIT_STATES] = {NULL};
    return read_height(it, m) || read_capacity(it, m, nodes, 1) ||
                   capacities_ordered(it, m, nodes)
               ? -1
               : 0;
}

/* A control line only counts the rocks that cross it: it collects, at no height. */
static int read_control(const rf_measure_item *it, rf_measure *m)
{
    rf_ynode *behaviour = rf_ydoc_get(it->d, it->node, "behaviour");
    if (behaviour && m->behaviour == RF_STOP)
        return rf_ydoc_error(it->d, behaviour, it->err,
                             "a control line never stops a rock: 'behaviour' must be "
                             "collect (or left out), got stop");
    m->behaviour = RF_COLLECT;
    m->height = 0.0;
    return 0;
}

/* ---- outcomes ---------------------------------------------------------------------- */

double rf_measure_breaking_energy(const rf_measure *m)
{
    if (m->behaviour == RF_COLLECT)
        return INFINITY;
    double cap = -1.0;
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        cap = fmax(cap, m->capacity[s]);
    return cap >= 0.0 ? cap : INFINITY;
}

/* A screen (barrier, embankment): above its height (or at a height not known: NaN,
 * a hole, a crack between terrain files) the rock overtops, whether the measure acts
 * or only collects; below it a `collect` measure lets it pass, and a `stop` measure
 * stops it within its capacity and lets it break through above. */
static rf_outcome outcome_screen(const rf_measure *m, double passing_height_m, double energy_kj)
{
    if (!(passing_height_m < m->height))
        return RF_OUT_OVERTOPPED;
    if (m->behaviour == RF_COLLECT)
        return RF_OUT_PASSED;
    return energy_kj <= rf_measure_breaking_energy(m) ? RF_OUT_STOPPED : RF_OUT_BROKE_THROUGH;
}

static rf_outcome outcome_control(const rf_measure *m, double passing_height_m,
                                  double energy_kj)
{
    (void)m, (void)passing_height_m, (void)energy_kj;
    return RF_OUT_PASSED;
}

/* ---- the table ----------------------------------------------------------------------- */

static const char *const barrier_keys[] = {"height", "mel", "sel", "capacity", NULL};
static const char *const embankment_keys[] = {"height", "capacity", NULL};
static const char *const control_keys[] = {NULL};

const rf_measure_kind_class rf_measure_kinds[RF_N_MEASURE_KINDS] = {
    [RF_BARRIER] = {"barrier", "a barrier", "#d62728", 1, 0, 1,
                    "[\"serviceability\",\"restorability\",\"ultimate\"]", barrier_keys,
                    read_barrier, outcome_screen},
    [RF_EMBANKMENT] = {"embankment", "an embankment", "#8c510a", 1, 0, 0,
                       "[\"serviceability\",\"restorability\",\"ultimate\",\"near_collapse\"]",
                       embankment_keys, read_embankment, outcome_screen},
    [RF_CONTROL] = {"control", "a control line", "#252525", 0, 1, 0, "[]", control_keys,
                    read_control, outcome_control},
};

const char *const rf_measure_item_keys[] = {"name", "kind", "line", "importance", "behaviour",
                                            "height", "mel", "sel", "capacity", NULL};

int rf_measure_kind_find(const char *name)
{
    for (int k = 0; name && k < RF_N_MEASURE_KINDS; k++)
        if (!strcmp(name, rf_measure_kinds[k].name))
            return k;
    return -1;
}

const char *rf_measure_kind_name(rf_measure_kind k)
{
    return (unsigned)k < RF_N_MEASURE_KINDS ? rf_measure_kinds[k].name : "?";
}
