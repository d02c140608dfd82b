/* rules_load.c - a rule file (YAML) into rf_rules, validated once with
 * file:line:column errors (docs/rules.md). */
#include "check/rules.h"

#include <stdlib.h>
#include <string.h>

#include "base/names.h"
#include "base/util.h"
#include "check/rules_private.h"
#include "input/bounds.h"
#include "input/measure_kinds.h"
#include "input/yamldoc.h"

static const char *const source_names[] = {"none", "mel", "sel", "project", NULL};
const char *const rf_rules_comparison_names[] = {">", ">=", NULL};
#define comparison_names rf_rules_comparison_names
static const char *const value_names[] = {"share_within", "share_meeting_required",
                                           "share_of_rockfalls_kept", NULL};
static const char *const verdict_names[] = {"fail", "pass", NULL};
const char *const rf_allowance_keys[RF_N_INTEGRITY + 1] = {"max_time", "left_terrain",
                                                           "rest_on_steep_face", NULL};

/* ---- loading ------------------------------------------------------------------ */

typedef struct loader {
    rf_ydoc d;
    rf_rules *r;
    rf_error *err;
    rf_names check_names; /* the names of the checks read so far, over both lists */
} loader;

static int out_of_memory(loader *L)
{
    return rf_error_set(L->err, L->d.file, 0, 0, "out of memory reading the rule file");
}

/* The mapping under `key` of `parent` (required; `in` names parent when it is missing),
 * with keys among `keys`: `what` names the mapping in messages, `keys_what` it in the
 * message about a wrong key. */
static int read_mapping(loader *L, const rf_ynode *parent, const char *key, const char *in,
                        const char *what, const char *const *keys, const char *keys_what,
                        rf_ynode **map)
{
    if (rf_ydoc_require(&L->d, parent, key, in, map, L->err) ||
        rf_ydoc_mapping(&L->d, *map, what, L->err) ||
        rf_ydoc_check_keys(&L->d, *map, keys, keys_what, L->err))
        return -1;
    return 0;
}

/* The rule file's list under `key`, of at least one item (`items` names them): its node
 * and its size. */
static int read_list(loader *L, const rf_ynode *root, const char *key, const char *items,
                     rf_ynode **seq, size_t *n)
{
    if (rf_ydoc_require(&L->d, root, key, "the rule file", seq, L->err) ||
        rf_ydoc_sequence(&L->d, *seq, key, 1, items, L->err))
        return -1;
    *n = rf_ydoc_seq_size(*seq);
    return 0;
}

/* Index in r->states of a state named by a scalar node, or an error at the node. */
static int read_state(loader *L, const rf_ynode *n, const char *key, int *out)
{
    int s;
    if (rf_ydoc_enum(&L->d, n, key, rf_limit_state_names, &s, L->err))
        return -1;
    for (int i = 0; i < L->r->nstates; i++) {
        if ((int)L->r->states[i] == s) {
            *out = i;
            return 0;
        }
    }
    return rf_ydoc_error(&L->d, n, L->err,
                         "'%s' is not one of the limit states listed in 'limit_states'",
                         rf_limit_state_names[s]);
}

static int read_limit_states(loader *L, rf_ynode *root)
{
    rf_ynode *seq;
    size_t n;
    if (read_list(L, root, "limit_states", "limit states", &seq, &n))
        return -1;
    if (n > RF_N_LIMIT_STATES)
        return rf_ydoc_error(&L->d, rf_ydoc_seq_item(&L->d, seq, RF_N_LIMIT_STATES), L->err,
                             "'limit_states' lists at most the %d limit states "
                             "serviceability, restorability, ultimate, near_collapse",
                             RF_N_LIMIT_STATES);
    for (size_t i = 0; i < n; i++) {
        rf_ynode *item = rf_ydoc_seq_item(&L->d, seq, i);
        int s;
        if (rf_ydoc_enum(&L->d, item, "limit_states", rf_limit_state_names, &s, L->err))
            return -1;
        for (size_t j = 0; j < i; j++)
            if ((int)L->r->states[j] == s)
                return rf_ydoc_error(&L->d, item, L->err, "'%s' is listed twice in 'limit_states'",
                                     rf_limit_state_names[s]);
        L->r->states[i] = (rf_limit_state)s;
    }
    L->r->nstates = (int)n;

    rf_ynode *beyond;
    const char *text;
    if (rf_ydoc_require(&L->d, root, "beyond_last", "the rule file", &beyond, L->err) ||
        rf_ydoc_string(&L->d, beyond, "beyond_last", &text, L->err))
        return -1;
    int taken = !strcmp(text, "overtopped");
    for (int s = 0; rf_limit_state_names[s]; s++)
        taken |= !strcmp(text, rf_limit_state_names[s]);
    if (taken)
        return rf_ydoc_error(&L->d, beyond, L->err,
                             "'beyond_last' must name a state other than the limit states "
                             "and 'overtopped', got %s",
                             text);
    if (!(L->r->beyond_last = strdup(text)))
        return out_of_memory(L);
    return 0;
}

static int read_required(loader *L, rf_ynode *root)
{
    static const char *const levels[] = {"1", "2", "3", NULL};
    rf_ynode *table;
    if (read_mapping(L, root, "required_state", "the rule file", "'required_state'", levels,
                     "'required_state' (action levels)", &table))
        return -1;
    for (int level = 0; level < 3; level++) {
        char what[64];
        snprintf(what, sizeof what, "'required_state' for action level %s", levels[level]);
        rf_ynode *row;
        if (read_mapping(L, table, levels[level], "'required_state'", what, rf_importance_names,
                         what, &row))
            return -1;
        for (int imp = 0; imp < RF_N_IMPORTANCES; imp++) {
            rf_ynode *cell;
            if (rf_ydoc_require(&L->d, row, rf_importance_names[imp], what, &cell, L->err) ||
                read_state(L, cell, rf_importance_names[imp], &L->r->required[level][imp]))
                return -1;
        }
    }
    return 0;
}

/* The `capacities` entry of measure kind `kind` (a classified row of rf_measure_kinds):
 * where each limit state's capacity comes from; mel and sel only for a kind that has
 * them (a barrier), and with them the SEL default. */
static int read_kind_capacities(loader *L, rf_ynode *caps, int kind)
{
    static const char *const mel_keys[] = {"serviceability", "restorability", "ultimate",
                                           "near_collapse", "sel_default", NULL};
    static const char *const divisor_keys[] = {"mel_divided_by", NULL};
    const rf_measure_kind_class *c = &rf_measure_kinds[kind];
    char what[64];
    snprintf(what, sizeof what, "'capacities' of %s", c->label);
    rf_ynode *map;
    if (read_mapping(L, caps, c->name, "'capacities'", what,
                     c->has_mel ? mel_keys : rf_limit_state_names, what, &map))
        return -1;
    int uses_sel = 0, any = 0;
    for (int s = 0; s < RF_N_LIMIT_STATES; s++) {
        rf_ynode *v = rf_ydoc_get(&L->d, map, rf_limit_state_names[s]);
        L->r->capacity[kind][s] = RF_CAP_NONE;
        if (!v)
            continue;
        int source;
        if (rf_ydoc_enum(&L->d, v, rf_limit_state_names[s], source_names + 1, &source, L->err))
            return -1;
        source += 1;
        if (!c->has_mel && (source == RF_CAP_MEL || source == RF_CAP_SEL))
            return rf_ydoc_error(&L->d, v, L->err,
                                 "%s has no %s: its capacities come from the project "
                                 "('project')",
                                 c->label, source == RF_CAP_MEL ? "MEL" : "SEL");
        L->r->capacity[kind][s] = (rf_capacity_source)source;
        uses_sel |= source == RF_CAP_SEL;
        any = 1;
    }
    if (!any)
        return rf_ydoc_error(&L->d, map, L->err,
                             "%s must give the capacity of at least one limit state", what);
    rf_ynode *def = c->has_mel ? rf_ydoc_get(&L->d, map, "sel_default") : NULL;
    if (def) {
        if (!uses_sel)
            return rf_ydoc_error(&L->d, def, L->err,
                                 "'sel_default' is given but no limit state of %s takes its "
                                 "capacity from 'sel'",
                                 c->label);
        rf_ynode *divisor;
        if (rf_ydoc_mapping_of(&L->d, def, divisor_keys, "'sel_default'", L->err) ||
            rf_ydoc_require(&L->d, def, "mel_divided_by", "'sel_default'", &divisor, L->err) ||
            rf_ydoc_number(&L->d, divisor, "mel_divided_by", RF_YR_AT_LEAST(1.0),
                           &L->r->sel_divisor, L->err))
            return -1;
    }
    return 0;
}

/* A capacity for a state the file does not list would never be used. */
static int capacities_listed(loader *L, rf_ynode *caps, int kind)
{
    rf_ynode *map = rf_ydoc_get(&L->d, caps, rf_measure_kinds[kind].name);
    for (int s = 0; s < RF_N_LIMIT_STATES; s++) {
        if (L->r->capacity[kind][s] == RF_CAP_NONE)
            continue;
        int index;
        size_t n = rf_ydoc_map_size(map);
        for (size_t i = 0; i < n; i++) {
            rf_ynode *k = rf_ydoc_map_key(&L->d, map, i);
            if (k && k->type == YAML_SCALAR_NODE &&
                !strcmp((const char *)k->data.scalar.value, rf_limit_state_names[s]) &&
                read_state(L, k, "capacities", &index))
                return -1;
        }
    }
    return 0;
}

/* `capacities`: one entry for each kind Table 3 classifies (rf_measure_kinds). */
static int read_capacities(loader *L, rf_ynode *root)
{
    const char *kind_names[RF_N_MEASURE_KINDS + 1] = {NULL};
    int n = 0;
    for (int kind = 0; kind < RF_N_MEASURE_KINDS; kind++)
        if (rf_measure_kinds[kind].classified)
            kind_names[n++] = rf_measure_kinds[kind].name;
    rf_ynode *caps;
    if (read_mapping(L, root, "capacities", "the rule file", "'capacities'", kind_names,
                     "'capacities' (structure kinds)", &caps))
        return -1;
    for (int kind = 0; kind < RF_N_MEASURE_KINDS; kind++)
        if (rf_measure_kinds[kind].classified && read_kind_capacities(L, caps, kind))
            return -1;
    for (int kind = 0; kind < RF_N_MEASURE_KINDS; kind++)
        if (rf_measure_kinds[kind].classified && capacities_listed(L, caps, kind))
            return -1;
    return 0;
}

/* Check i of the measures' checks, or with `layout` set of the layout's. */
static int read_check(loader *L, rf_ynode *n, int layout, size_t i)
{
    static const char *const keys[] = {"rule", "value", "state", "comparison", "threshold",
                                       NULL};
    rf_rule_check *c = layout ? &L->r->layout_checks[i] : &L->r->checks[i];
    char what[48];
    snprintf(what, sizeof what, "%s %zu", layout ? "layout check" : "check", i + 1);
    rf_ynode *name, *value, *comparison, *threshold;
    const char *text;
    int v, cmp;
    if (rf_ydoc_mapping_of(&L->d, n, keys, what, L->err) ||
        rf_ydoc_require(&L->d, n, "rule", what, &name, L->err) ||
        rf_ydoc_string(&L->d, name, "rule", &text, L->err))
        return -1;
    /* rule names are unique over both lists and the integrity checks: they name the
     * rows of `checks`; an index of them keeps a file of many checks linear */
    if (rf_names_find(&L->check_names, text) != RF_NAMES_ABSENT)
        return rf_ydoc_error(&L->d, name, L->err, "two checks are named '%s'", text);
    for (int k = 0; k < RF_N_INTEGRITY; k++)
        if (!strcmp(text, rf_integrity_rules[k]))
            return rf_ydoc_error(&L->d, name, L->err,
                                 "'%s' names the check of allowance '%s'; choose another "
                                 "name", text, rf_allowance_keys[k]);
    int oom;
    if (!(c->name = strdup(text)) || (rf_names_add(&L->check_names, c->name, i, &oom), oom))
        return out_of_memory(L);
    if (rf_ydoc_require(&L->d, n, "value", what, &value, L->err) ||
        rf_ydoc_enum(&L->d, value, "value", value_names, &v, L->err) ||
        rf_ydoc_require(&L->d, n, "comparison", what, &comparison, L->err) ||
        rf_ydoc_enum(&L->d, comparison, "comparison", comparison_names, &cmp, L->err) ||
        rf_ydoc_require(&L->d, n, "threshold", what, &threshold, L->err) ||
        rf_ydoc_number(&L->d, threshold, "threshold", RF_YR_UNIT, &c->threshold, L->err))
        return -1;
    c->value = (rf_check_value)v;
    c->comparison = (rf_comparison)cmp;
    if (layout && c->value != RF_VALUE_SHARE_KEPT)
        return rf_ydoc_error(&L->d, value, L->err,
                             "a layout check's value is share_of_rockfalls_kept (%s is a "
                             "measure's: put it under 'checks')",
                             value_names[v]);
    if (!layout && c->value == RF_VALUE_SHARE_KEPT)
        return rf_ydoc_error(&L->d, value, L->err,
                             "share_of_rockfalls_kept judges the whole layout: put it under "
                             "'layout_checks'");
    rf_ynode *state = rf_ydoc_get(&L->d, n, "state");
    if (c->value != RF_VALUE_SHARE_MEETING) {
        if (!state)
            return rf_ydoc_error(&L->d, n, L->err, "missing required key 'state' in %s (%s)",
                                 what,
                                 layout ? "share_of_rockfalls_kept counts the rockfalls "
                                          "kept within a limit state"
                                        : "share_within counts the interceptions within a "
                                          "limit state");
        if (read_state(L, state, "state", &c->state))
            return -1;
    } else if (state) {
        return rf_ydoc_error(&L->d, state, L->err,
                             "'state' belongs to a share_within check; "
                             "share_meeting_required uses each interception's required "
                             "state");
    }
    return 0;
}

/* The list `key` of checks (required for the measures' checks, optional for the
 * layout's). */
static int read_checks(loader *L, rf_ynode *root, const char *key, int layout)
{
    rf_ynode *seq;
    size_t n;
    if (layout && !rf_ydoc_get(&L->d, root, key))
        return 0;
    if (read_list(L, root, key, key, &seq, &n))
        return -1;
    rf_rule_check *c = calloc(n, sizeof *c);
    if (!c)
        return out_of_memory(L);
    if (layout)
        L->r->layout_checks = c, L->r->nlayout = n;
    else
        L->r->checks = c, L->r->nchecks = n;
    for (size_t i = 0; i < n; i++)
        if (read_check(L, rf_ydoc_seq_item(&L->d, seq, i), layout, i))
            return -1;
    return 0;
}

/* `allowance:`, optional, each key optional: the share of the trajectories of each
 * kind that leaves the verdict standing (defaults in rules.h). */
static int read_allowance(loader *L, rf_ynode *root)
{
    L->r->allowance[RF_INTEGRITY_MAX_TIME] = RF_ALLOWANCE_MAX_TIME;
    L->r->allowance[RF_INTEGRITY_LEFT_TERRAIN] = RF_ALLOWANCE_LEFT_TERRAIN;
    L->r->allowance[RF_INTEGRITY_REST_STEEP] = RF_ALLOWANCE_REST_STEEP;
    rf_ynode *map = rf_ydoc_get(&L->d, root, "allowance");
    if (!map)
        return 0;
    if (rf_ydoc_mapping_of(&L->d, map, rf_allowance_keys, "allowance", L->err))
        return -1;
    for (int k = 0; k < RF_N_INTEGRITY; k++)
        if (rf_ydoc_opt_number(&L->d, map, rf_allowance_keys[k], RF_YR_UNIT,
                               &L->r->allowance[k], L->err))
            return -1;
    return 0;
}

static int read_rules(loader *L)
{
    static const char *const keys[] = {"name",       "limit_states",  "beyond_last",
                                       "required_state", "capacities", "checks",
                                       "layout_checks", "no_interceptions", "allowance",
                                       NULL};
    rf_ynode *root = rf_ydoc_root(&L->d);
    if (!root)
        return rf_ydoc_error(&L->d, NULL, L->err, "the rule file is empty");
    rf_ynode *name;
    const char *text;
    int verdict = 1;
    if (rf_ydoc_mapping_of(&L->d, root, keys, "the rule file", L->err) ||
        rf_ydoc_require(&L->d, root, "name", "the rule file", &name, L->err) ||
        rf_ydoc_string(&L->d, name, "name", &text, L->err))
        return -1;
    if (!(L->r->name = strdup(text)))
        return out_of_memory(L);
    if (read_limit_states(L, root) || read_required(L, root) || read_capacities(L, root) ||
        read_checks(L, root, "checks", 0) || read_checks(L, root, "layout_checks", 1) ||
        read_allowance(L, root) ||
        rf_ydoc_opt_enum(&L->d, root, "no_interceptions", verdict_names, &verdict, L->err))
        return -1;
    L->r->empty_passes = verdict;
    return 0;
}

static int finish_load(loader *L, const char *path)
{
    int rc = read_rules(L);
    if (rc == 0 && !(L->r->path = strdup(path)))
        rc = out_of_memory(L);
    rf_ydoc_free(&L->d);
    rf_names_free(&L->check_names);
    if (rc)
        rf_rules_free(L->r);
    return rc;
}

int rf_rules_load(const char *path, rf_rules *r, rf_error *err)
{
    memset(r, 0, sizeof *r);
    char *text;
    size_t len;
    if (rf_read_file(path, RF_TEXT_FILE_MAX, &text, &len, err))
        return -1;
    int rc = rf_rules_load_text(path, text, len, r, err);
    free(text);
    return rc;
}

int rf_rules_load_text(const char *file, const char *text, size_t len, rf_rules *r,
                       rf_error *err)
{
    memset(r, 0, sizeof *r);
    loader L = {.r = r, .err = err};
    if (rf_ydoc_load_text(&L.d, file, text, len, err) || finish_load(&L, file))
        return -1;
    if (!(r->text = malloc(len + 1))) {
        rf_rules_free(r);
        return rf_error_set(err, file, 0, 0, "out of memory reading the rule file");
    }
    memcpy(r->text, text, len);
    r->text[len] = '\0';
    return 0;
}

void rf_rules_free(rf_rules *r)
{
    if (!r)
        return;
    for (size_t i = 0; i < r->nchecks; i++)
        free(r->checks[i].name);
    free(r->checks);
    for (size_t i = 0; i < r->nlayout; i++)
        free(r->layout_checks[i].name);
    free(r->layout_checks);
    free(r->path);
    free(r->text);
    free(r->name);
    free(r->beyond_last);
    memset(r, 0, sizeof *r);
}

