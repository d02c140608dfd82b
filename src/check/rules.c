/* rules.c - the rules engine: load a rule file, classify interceptions against the
 * limit states of Table 3, write and print the design checks (docs/rules.md). */
#include "check/rules.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "results/query.h"
#include "base/util.h"
#include "input/yamldoc.h"

static const char *const kind_names[] = {"barrier", "embankment", NULL};
static const char *const source_names[] = {"none", "mel", "sel", "project", NULL};
static const char *const comparison_names[] = {">", ">=", NULL};
static const char *const value_names[] = {"share_within", "share_meeting_required",
                                           "share_of_rockfalls_kept", NULL};
static const char *const verdict_names[] = {"fail", "pass", NULL};

/* ---- loading ------------------------------------------------------------------ */

typedef struct loader {
    rf_ydoc d;
    rf_rules *r;
    rf_error *err;
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

static int read_kind_capacities(loader *L, rf_ynode *caps, int kind)
{
    static const char *const barrier_keys[] = {"serviceability", "restorability", "ultimate",
                                               "near_collapse", "sel_default", NULL};
    static const char *const divisor_keys[] = {"mel_divided_by", NULL};
    char what[64];
    snprintf(what, sizeof what, "'capacities' of %s", kind == 0 ? "a barrier" : "an embankment");
    rf_ynode *map;
    if (read_mapping(L, caps, kind_names[kind], "'capacities'", what,
                     kind == 0 ? barrier_keys : rf_limit_state_names, what, &map))
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
        if (kind == 1 && (source == RF_CAP_MEL || source == RF_CAP_SEL))
            return rf_ydoc_error(&L->d, v, L->err,
                                 "an embankment has no %s: its capacities come from the "
                                 "project ('project')",
                                 source == RF_CAP_MEL ? "MEL" : "SEL");
        L->r->capacity[kind][s] = (rf_capacity_source)source;
        uses_sel |= source == RF_CAP_SEL;
        any = 1;
    }
    if (!any)
        return rf_ydoc_error(&L->d, map, L->err,
                             "%s must give the capacity of at least one limit state", what);
    rf_ynode *def = kind == 0 ? rf_ydoc_get(&L->d, map, "sel_default") : NULL;
    if (def) {
        if (!uses_sel)
            return rf_ydoc_error(&L->d, def, L->err,
                                 "'sel_default' is given but no limit state of a barrier "
                                 "takes its capacity from 'sel'");
        rf_ynode *divisor;
        if (rf_ydoc_mapping_of(&L->d, def, divisor_keys, "'sel_default'", L->err) ||
            rf_ydoc_require(&L->d, def, "mel_divided_by", "'sel_default'", &divisor, L->err) ||
            rf_ydoc_number(&L->d, divisor, "mel_divided_by", RF_YR_AT_LEAST(1.0),
                           &L->r->sel_divisor, L->err))
            return -1;
    }
    return 0;
}

static int read_capacities(loader *L, rf_ynode *root)
{
    rf_ynode *caps;
    if (read_mapping(L, root, "capacities", "the rule file", "'capacities'", kind_names,
                     "'capacities' (structure kinds)", &caps))
        return -1;
    for (int kind = 0; kind < RF_N_RULE_KINDS; kind++)
        if (read_kind_capacities(L, caps, kind))
            return -1;
    /* A capacity for a state the file does not list would never be used. */
    for (int kind = 0; kind < RF_N_RULE_KINDS; kind++) {
        rf_ynode *map = rf_ydoc_get(&L->d, caps, kind_names[kind]);
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
    }
    return 0;
}

/* 1 when one of the checks read so far (a NULL name ends them) is named `name`. */
static int check_named(const rf_rule_check *c, size_t n, const char *name)
{
    for (size_t j = 0; j < n && c[j].name; j++)
        if (!strcmp(c[j].name, name))
            return 1;
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
    /* rule names are unique over both lists: they name the rows of `checks` */
    if (check_named(L->r->checks, L->r->nchecks, text) ||
        check_named(L->r->layout_checks, L->r->nlayout, text))
        return rf_ydoc_error(&L->d, name, L->err, "two checks are named '%s'", text);
    if (!(c->name = strdup(text)))
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

static int read_rules(loader *L)
{
    static const char *const keys[] = {"name",       "limit_states",  "beyond_last",
                                       "required_state", "capacities", "checks",
                                       "layout_checks", "no_interceptions", NULL};
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
    if (rc)
        rf_rules_free(L->r);
    return rc;
}

int rf_rules_load(const char *path, rf_rules *r, rf_error *err)
{
    memset(r, 0, sizeof *r);
    loader L = {.r = r, .err = err};
    if (rf_ydoc_load_file(&L.d, path, err))
        return -1;
    return finish_load(&L, path);
}

int rf_rules_load_text(const char *file, const char *text, size_t len, rf_rules *r,
                       rf_error *err)
{
    memset(r, 0, sizeof *r);
    loader L = {.r = r, .err = err};
    if (rf_ydoc_load_text(&L.d, file, text, len, err))
        return -1;
    return finish_load(&L, file);
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
    free(r->name);
    free(r->beyond_last);
    memset(r, 0, sizeof *r);
}

const char *rf_rules_state_name(const rf_rules *r, int reached)
{
    if (reached == RF_REACHED_OVERTOPPED)
        return "overtopped";
    if (reached >= 0 && reached < r->nstates)
        return rf_limit_state_name(r->states[reached]);
    if (reached == r->nstates)
        return r->beyond_last;
    return NULL;
}

/* ---- classification ------------------------------------------------------------- */

void rf_rules_capacities(const rf_rules *r, rf_measure_kind kind, double mel, double sel,
                         const double project_capacity[RF_N_LIMIT_STATES],
                         double capacity[RF_N_LIMIT_STATES])
{
    for (int s = 0; s < RF_N_LIMIT_STATES; s++) {
        capacity[s] = NAN;
        if (kind != RF_BARRIER && kind != RF_EMBANKMENT)
            continue;
        switch (r->capacity[kind == RF_BARRIER ? 0 : 1][s]) {
        case RF_CAP_NONE: break;
        case RF_CAP_MEL: capacity[s] = mel; break;
        case RF_CAP_SEL:
            /* SEL = MEL / divisor unless the project gives it (ETAG 027). */
            capacity[s] = !isnan(sel) ? sel : r->sel_divisor > 0 ? mel / r->sel_divisor : NAN;
            break;
        case RF_CAP_PROJECT: capacity[s] = project_capacity[s]; break;
        }
    }
}

int rf_rules_reached(const rf_rules *r, const double capacity[RF_N_LIMIT_STATES],
                     double energy_kj, rf_outcome outcome)
{
    if (outcome == RF_OUT_OVERTOPPED)
        return RF_REACHED_OVERTOPPED;
    if (outcome == RF_OUT_BROKE_THROUGH)
        return r->nstates;
    if (isnan(energy_kj))
        return RF_REACHED_UNKNOWN;
    for (int i = 0; i < r->nstates; i++) {
        double cap = capacity[r->states[i]];
        if (!isnan(cap) && energy_kj <= cap)
            return i;
    }
    return r->nstates;
}

int rf_rules_required(const rf_rules *r, int action_level, rf_importance importance)
{
    assert(action_level >= 1 && action_level <= 3 && (unsigned)importance < 3);
    return r->required[action_level - 1][importance];
}

int rf_rules_meets(const rf_rules *r, int reached, int required)
{
    return reached >= 0 && reached < r->nstates && reached <= required;
}

int rf_rules_check_passes(const rf_rule_check *c, double value)
{
    /* value is count / n, correctly rounded, and the threshold the correctly rounded
     * decimal of the file: exactly 90 % of n compares equal to 0.9. */
    return c->comparison == RF_CMP_GREATER ? value > c->threshold : value >= c->threshold;
}

/* ---- the database ---------------------------------------------------------------- */

static int db_error(sqlite3 *db, const char *doing, rf_error *err)
{
    return rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0, "%s: %s", doing,
                        sqlite3_errmsg(db));
}

/* Prepares sql; on failure err says what was being done. */
static int prepare_for(sqlite3 *db, const char *sql, sqlite3_stmt **st, const char *doing,
                       rf_error *err)
{
    if (sqlite3_prepare_v2(db, sql, -1, st, NULL) != SQLITE_OK)
        return db_error(db, doing, err);
    return 0;
}

static int prepare(sqlite3 *db, const char *sql, sqlite3_stmt **st, rf_error *err)
{
    return prepare_for(db, sql, st, "reading the run", err);
}

/* The run's project text as a document in d; NULL when there is none or it does not
 * load. */
static rf_ydoc *project_doc(const char *yaml, rf_ydoc *d)
{
    if (!yaml || rf_ydoc_load_text(d, "project", yaml, strlen(yaml), NULL))
        return NULL;
    return d;
}

/* The value of a top-level key of the project document d (may be NULL), NULL when there
 * is none. */
static rf_ynode *project_get(rf_ydoc *d, const char *key)
{
    rf_ynode *root = d ? rf_ydoc_root(d) : NULL;
    return root && root->type == YAML_MAPPING_NODE ? rf_ydoc_get(d, root, key) : NULL;
}

/* 1 when the project document gives measure `name` a sel, 0 when not, -1 when unknown
 * (no document). */
static int project_gives_sel(rf_ydoc *d, const char *name)
{
    if (!d)
        return -1;
    int gives = -1;
    rf_ynode *seq = project_get(d, "measures");
    size_t n = seq && seq->type == YAML_SEQUENCE_NODE ? rf_ydoc_seq_size(seq) : 0;
    for (size_t i = 0; i < n && gives < 0; i++) {
        rf_ynode *m = rf_ydoc_seq_item(d, seq, i);
        rf_ynode *mname = m && m->type == YAML_MAPPING_NODE ? rf_ydoc_get(d, m, "name") : NULL;
        if (mname && mname->type == YAML_SCALAR_NODE &&
            !strcmp((const char *)mname->data.scalar.value, name))
            gives = rf_ydoc_get(d, m, "sel") != NULL;
    }
    return gives;
}

int rf_rules_path_of_run(sqlite3 *db, int64_t run, char **path, rf_error *err)
{
    *path = NULL;
    const char *file = sqlite3_db_filename(db, "main");
    sqlite3_stmt *st;
    if (prepare(db, "SELECT project_path, project_yaml FROM runs WHERE id = ?1", &st, err))
        return -1;
    sqlite3_bind_int64(st, 1, run);
    int status = -1;
    if (sqlite3_step(st) != SQLITE_ROW) {
        status = rf_error_set(err, file, 0, 0, "no run %lld in this database", (long long)run);
        goto done;
    }
    const char *project = (const char *)sqlite3_column_text(st, 0);
    rf_ydoc doc, *pd = project_doc((const char *)sqlite3_column_text(st, 1), &doc);
    rf_ynode *given = project_get(pd, "rules");
    const char *rules = given && given->type == YAML_SCALAR_NODE
                            ? (const char *)given->data.scalar.value
                            : NULL;
    if (!rules) {
        status = rf_error_set(err, file, 0, 0,
                              "the project of run %lld names no rule file ('rules:'); pass "
                              "--rules FILE (e.g. rules/table3.yaml)",
                              (long long)run);
    } else {
        const char *slash = project ? strrchr(project, '/') : NULL;
        size_t dir = rules[0] == '/' || !slash ? 0 : (size_t)(slash - project) + 1;
        size_t n = dir + strlen(rules) + 1;
        if ((*path = malloc(n))) {
            snprintf(*path, n, "%.*s%s", (int)dir, dir ? project : "", rules);
            status = 0;
        } else {
            status = rf_error_set(err, file, 0, 0, "out of memory");
        }
    }
    if (pd)
        rf_ydoc_free(pd);
done:
    sqlite3_finalize(st);
    return status;
}

static int importance_of(const char *text)
{
    for (int i = 0; text && i < RF_N_IMPORTANCES; i++)
        if (!strcmp(text, rf_importance_names[i]))
            return i;
    return -1;
}

static int kind_of(const char *text)
{
    if (text && !strcmp(text, "barrier"))
        return RF_BARRIER;
    if (text && !strcmp(text, "embankment"))
        return RF_EMBANKMENT;
    return RF_CONTROL;
}

/* One measure of the run as the classification needs it. */
typedef struct measure_row {
    int64_t id;
    char *name;
    rf_measure_kind kind;
    int importance;
    double capacity[RF_N_LIMIT_STATES];
} measure_row;

/* The measures of a run that the rules judge, in the columns read_measure_row reads. */
static const char measures_sql[] =
    "SELECT id, name, kind, importance, mel_kj, sel_kj, cap_serviceability_kj,"
    " cap_restorability_kj, cap_ultimate_kj, cap_near_collapse_kj"
    " FROM measures WHERE run_id = ?1 AND kind <> 'control' ORDER BY idx, id";

static int read_measure_row(sqlite3_stmt *st, const rf_rules *r, rf_ydoc *doc, measure_row *m,
                            rf_error *err)
{
    const char *name = (const char *)sqlite3_column_text(st, 1);
    m->id = sqlite3_column_int64(st, 0);
    m->kind = (rf_measure_kind)kind_of((const char *)sqlite3_column_text(st, 2));
    const char *importance = (const char *)sqlite3_column_text(st, 3);
    m->importance = importance_of(importance);
    if (m->importance < 0)
        return rf_error_set(err, sqlite3_db_filename(sqlite3_db_handle(st), "main"), 0, 0,
                            "measure '%s' has importance '%s'; expected most_important, "
                            "important or usual",
                            name, importance ? importance : "NULL");
    if (!(m->name = strdup(name ? name : "")))
        return rf_error_set(err, "", 0, 0, "out of memory");
    double mel = rf_query_column_real(st, 4), sel = rf_query_column_real(st, 5);
    double project[RF_N_LIMIT_STATES];
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        project[s] = rf_query_column_real(st, 6 + s);
    /* The project loader fills sel = MEL / 3 (sel_kj, and cap_serviceability_kj) when
     * the project gives none; whenever the project text shows no sel, that value is
     * not the project's: the rule file's sel_default decides, and without one a
     * barrier has no SEL. */
    if (m->kind == RF_BARRIER && project_gives_sel(doc, m->name) == 0)
        sel = project[RF_SERVICEABILITY] = NAN;
    rf_rules_capacities(r, m->kind, mel, sel, project, m->capacity);
    return 0;
}

/* A run's measures that the rules judge, read once for the evaluation and the
 * printout, with the project document parsed once for them. */
typedef struct run_measures {
    char *project;   /* runs.project; NULL when the run does not exist */
    measure_row *m;
    size_t n;
    long n_rockfalls; /* the run's trajectories, when the rules have layout checks */
    long *kept;       /* those each layout check kept */
} run_measures;

static void run_measures_free(run_measures *L)
{
    for (size_t i = 0; i < L->n; i++)
        free(L->m[i].name);
    free(L->m);
    free(L->kept);
    free(L->project);
    memset(L, 0, sizeof *L);
}

/* Fills the empty L with the run's measures; on failure L may hold part of them (the
 * caller frees it). */
static int read_run_measures(sqlite3 *db, int64_t run, const rf_rules *r, run_measures *L,
                             rf_error *err)
{
    sqlite3_stmt *runs = NULL, *measures = NULL;
    rf_ydoc doc, *pd = NULL;
    size_t cap = 0;
    int status = -1, rc;
    if (prepare(db, "SELECT project, project_yaml FROM runs WHERE id = ?1", &runs, err) ||
        prepare(db, measures_sql, &measures, err))
        goto done;
    sqlite3_bind_int64(runs, 1, run);
    if (sqlite3_step(runs) == SQLITE_ROW) {
        const char *project = (const char *)sqlite3_column_text(runs, 0);
        if (!(L->project = strdup(project ? project : ""))) {
            rf_error_set(err, "", 0, 0, "out of memory");
            goto done;
        }
        pd = project_doc((const char *)sqlite3_column_text(runs, 1), &doc);
    }
    sqlite3_bind_int64(measures, 1, run);
    while ((rc = sqlite3_step(measures)) == SQLITE_ROW) {
        if (rf_grow((void **)&L->m, &cap, L->n + 1, sizeof *L->m)) {
            rf_error_set(err, "", 0, 0, "out of memory");
            goto done;
        }
        if (read_measure_row(measures, r, pd, &L->m[L->n], err))
            goto done;
        L->n++;
    }
    if (rc != SQLITE_DONE) {
        db_error(db, "reading measures", err);
        goto done;
    }
    status = 0;
done:
    if (pd)
        rf_ydoc_free(pd);
    sqlite3_finalize(runs);
    sqlite3_finalize(measures);
    return status;
}

static int classify_measure(sqlite3 *db, const rf_rules *r, const measure_row *m,
                            sqlite3_stmt *ins, long *n, long *n_within, long *n_meeting,
                            rf_error *err)
{
    sqlite3_stmt *st;
    if (prepare(db,
                "SELECT i.id, i.energy_kj, i.outcome, r.action_level FROM interceptions i"
                " JOIN trajectories t ON t.id = i.trajectory_id"
                " JOIN releases r ON r.id = t.release_id"
                " WHERE i.measure_id = ?1 ORDER BY i.id",
                &st, err))
        return -1;
    sqlite3_bind_int64(st, 1, m->id);
    const char *file = sqlite3_db_filename(db, "main");
    int rc, status = 0;
    while (status == 0 && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        int level = sqlite3_column_int(st, 3);
        if (level < 1 || level > 3) {
            status = rf_error_set(err, file, 0, 0, "interception %lld has action level %d",
                                  (long long)sqlite3_column_int64(st, 0), level);
            break;
        }
        rf_outcome outcome = rf_outcome_from_name((const char *)sqlite3_column_text(st, 2));
        int reached = rf_rules_reached(r, m->capacity, rf_query_column_real(st, 1), outcome);
        int required = rf_rules_required(r, level, (rf_importance)m->importance);
        int ok = rf_rules_meets(r, reached, required);
        (*n)++;
        *n_meeting += ok;
        for (size_t c = 0; c < r->nchecks; c++)
            if (r->checks[c].value == RF_VALUE_SHARE_WITHIN)
                n_within[c] += rf_rules_meets(r, reached, r->checks[c].state);
        const char *reached_name = rf_rules_state_name(r, reached);
        sqlite3_bind_int64(ins, 1, sqlite3_column_int64(st, 0));
        sqlite3_bind_int(ins, 2, level);
        sqlite3_bind_text(ins, 3, rf_importance_name(m->importance), -1, SQLITE_STATIC);
        if (reached_name)
            sqlite3_bind_text(ins, 4, reached_name, -1, SQLITE_STATIC);
        else
            sqlite3_bind_null(ins, 4);
        sqlite3_bind_text(ins, 5, rf_rules_state_name(r, required), -1, SQLITE_STATIC);
        sqlite3_bind_int(ins, 6, ok);
        if (sqlite3_step(ins) != SQLITE_DONE)
            status = db_error(db, "writing a classification", err);
        sqlite3_reset(ins);
    }
    if (status == 0 && rc != SQLITE_DONE)
        status = db_error(db, "reading interceptions", err);
    sqlite3_finalize(st);
    return status;
}

/* One checks row: the measure's (measure_id > 0) or the layout's (NULL); the value
 * count / n, NULL when n = 0, which passes as the rules say for nothing reached. */
static int insert_check(sqlite3 *db, sqlite3_stmt *ins, int64_t run, int64_t measure_id,
                        const rf_rules *r, const rf_rule_check *check, long count, long n,
                        long *n_failed, rf_error *err)
{
    double value = n > 0 ? (double)count / (double)n : NAN;
    int passed = n > 0 ? rf_rules_check_passes(check, value) : r->empty_passes;
    *n_failed += !passed;
    sqlite3_bind_int64(ins, 1, run);
    if (measure_id > 0)
        sqlite3_bind_int64(ins, 2, measure_id);
    else
        sqlite3_bind_null(ins, 2);
    sqlite3_bind_text(ins, 3, check->name, -1, SQLITE_STATIC);
    if (n > 0)
        sqlite3_bind_double(ins, 4, value);
    else
        sqlite3_bind_null(ins, 4);
    sqlite3_bind_double(ins, 5, check->threshold);
    sqlite3_bind_int(ins, 6, passed);
    int rc = sqlite3_step(ins);
    sqlite3_reset(ins);
    return rc == SQLITE_DONE ? 0 : db_error(db, "writing a check", err);
}

static int write_checks(sqlite3 *db, int64_t run, const rf_rules *r, const measure_row *m,
                        sqlite3_stmt *ins, long n, const long *n_within, long n_meeting,
                        long *n_failed, rf_error *err)
{
    for (size_t c = 0; c < r->nchecks; c++) {
        const rf_rule_check *check = &r->checks[c];
        long count = check->value == RF_VALUE_SHARE_WITHIN ? n_within[c] : n_meeting;
        if (insert_check(db, ins, run, m->id, r, check, count, n, n_failed, err))
            return -1;
    }
    return 0;
}

/* The first integer of a query's first row; -1 on error (err set, saying what was
 * being counted). */
static long query_count(sqlite3 *db, const char *sql, int64_t run, const char *what,
                        rf_error *err)
{
    sqlite3_stmt *st;
    if (prepare_for(db, sql, &st, what, err))
        return -1;
    sqlite3_bind_int64(st, 1, run);
    long n = sqlite3_step(st) == SQLITE_ROW ? (long)sqlite3_column_int64(st, 0) : -1;
    sqlite3_finalize(st);
    if (n < 0)
        db_error(db, what, err);
    return n;
}

/* The run's trajectories kept within limit state index `state`: no crossing of a
 * control line, every interception of a barrier or embankment classified (by
 * evaluate, just before) into `state` or an earlier one; -1 on error (err set). */
static long layout_kept(sqlite3 *db, int64_t run, const rf_rules *r, int state, rf_error *err)
{
    char *within = sqlite3_mprintf("%Q", rf_rules_state_name(r, 0));
    for (int i = 1; within && i <= state; i++) {
        char *more = sqlite3_mprintf("%s, %Q", within, rf_rules_state_name(r, i));
        sqlite3_free(within);
        within = more;
    }
    char *sql = within ? sqlite3_mprintf(
                             "SELECT count(*) FROM trajectories t WHERE t.run_id = ?1 AND NOT "
                             "EXISTS (SELECT 1 FROM interceptions i JOIN measures m ON m.id = "
                             "i.measure_id LEFT JOIN classifications c ON c.interception_id = "
                             "i.id WHERE i.trajectory_id = t.id AND (m.kind = 'control' OR "
                             "c.limit_state IS NULL OR c.limit_state NOT IN (%s)))",
                             within)
                       : NULL;
    sqlite3_free(within);
    long kept = sql ? query_count(db, sql, run, "counting the rockfalls the layout keeps", err)
                    : (rf_error_set(err, "", 0, 0, "out of memory"), -1L);
    sqlite3_free(sql);
    return kept;
}

/* The layout's checks; the run's rockfalls into L->n_rockfalls, those each check
 * kept into L->kept[c], for print_run. */
static int write_layout_checks(sqlite3 *db, int64_t run, const rf_rules *r, sqlite3_stmt *ins,
                               run_measures *L, long *n_failed, rf_error *err)
{
    if (r->nlayout == 0)
        return 0;
    if (!(L->kept = calloc(r->nlayout, sizeof *L->kept)))
        return rf_error_set(err, "", 0, 0, "out of memory");
    L->n_rockfalls =
        query_count(db, "SELECT count(*) FROM trajectories WHERE run_id = ?1", run,
                    "counting the run's rockfalls", err);
    if (L->n_rockfalls < 0)
        return -1;
    for (size_t c = 0; c < r->nlayout; c++) {
        const rf_rule_check *check = &r->layout_checks[c];
        L->kept[c] = layout_kept(db, run, r, check->state, err);
        if (L->kept[c] < 0 ||
            insert_check(db, ins, run, 0, r, check, L->kept[c], L->n_rockfalls, n_failed, err))
            return -1;
    }
    return 0;
}

static int evaluate(sqlite3 *db, int64_t run, const rf_rules *r, run_measures *L,
                    long *n_failed, rf_error *err)
{
    sqlite3_stmt *ins_class = NULL, *ins_check = NULL;
    long *n_within = calloc(r->nchecks + 1, sizeof *n_within);
    int status = -1;
    if (!n_within) {
        rf_error_set(err, "", 0, 0, "out of memory");
        goto done;
    }
    char *del = sqlite3_mprintf("DELETE FROM classifications WHERE interception_id IN"
                                " (SELECT id FROM interceptions WHERE run_id = %lld);"
                                " DELETE FROM checks WHERE run_id = %lld;",
                                (long long)run, (long long)run);
    int rc = del ? sqlite3_exec(db, del, NULL, NULL, NULL) : SQLITE_NOMEM;
    sqlite3_free(del);
    if (rc != SQLITE_OK) {
        db_error(db, "replacing the run's classifications", err);
        goto done;
    }
    if (prepare(db,
                "INSERT INTO classifications (interception_id, action_level, importance,"
                " limit_state, required_state, ok) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                &ins_class, err) ||
        prepare(db,
                "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed)"
                " VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                &ins_check, err))
        goto done;
    for (size_t i = 0; i < L->n; i++) {
        long n = 0, n_meeting = 0;
        memset(n_within, 0, (r->nchecks + 1) * sizeof *n_within);
        if (classify_measure(db, r, &L->m[i], ins_class, &n, n_within, &n_meeting, err) ||
            write_checks(db, run, r, &L->m[i], ins_check, n, n_within, n_meeting, n_failed,
                         err))
            goto done;
    }
    if (write_layout_checks(db, run, r, ins_check, L, n_failed, err))
        goto done;
    status = 0;
done:
    sqlite3_finalize(ins_class);
    sqlite3_finalize(ins_check);
    free(n_within);
    return status;
}

/* ---- printing -------------------------------------------------------------------- */

static void print_capacities(const rf_rules *r, const measure_row *m, FILE *out)
{
    fprintf(out, "  capacities (kJ):");
    int any = 0;
    for (int i = 0; i < r->nstates; i++) {
        double cap = m->capacity[r->states[i]];
        if (isnan(cap))
            continue;
        fprintf(out, "%s %s %.1f", any ? "," : "", rf_limit_state_name(r->states[i]), cap);
        any = 1;
    }
    fprintf(out, "%s\n", any ? "" : " none");
}

/* The shares of the measure's interceptions in each limit state (one classification
 * each); nothing without interceptions. */
static int print_states(sqlite3 *db, const rf_rules *r, const measure_row *m, FILE *out,
                        rf_error *err)
{
    sqlite3_stmt *st;
    if (prepare(db,
                "SELECT c.limit_state, count(*) FROM classifications c"
                " JOIN interceptions i ON i.id = c.interception_id"
                " WHERE i.measure_id = ?1 GROUP BY c.limit_state",
                &st, err))
        return -1;
    sqlite3_bind_int64(st, 1, m->id);
    long counts[RF_N_LIMIT_STATES + 3] = {0}; /* states, beyond, overtopped, unknown */
    long n = 0;
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *name = (const char *)sqlite3_column_text(st, 0);
        long c = (long)sqlite3_column_int64(st, 1);
        int slot = r->nstates + 2;
        for (int i = -1; i <= r->nstates; i++) {
            const char *s = rf_rules_state_name(r, i);
            if (name && s && !strcmp(name, s))
                slot = i < 0 ? r->nstates + 1 : i;
        }
        counts[slot] += c;
        n += c;
    }
    sqlite3_finalize(st);
    if (n == 0)
        return 0;
    fprintf(out, "  limit states:");
    int shown = 0;
    for (int i = 0; i <= r->nstates + 2; i++) {
        const char *name = i <= r->nstates       ? rf_rules_state_name(r, i)
                           : i == r->nstates + 1 ? "overtopped"
                                                 : "no energy";
        /* a state without a capacity for this measure is shown only when reached */
        int no_capacity = i < r->nstates && isnan(m->capacity[r->states[i]]);
        if ((i == r->nstates + 2 || no_capacity) && counts[i] == 0)
            continue;
        fprintf(out, "%s %s %.1f %%", shown++ ? "," : "", name,
                100.0 * (double)counts[i] / (double)n);
    }
    fprintf(out, "\n");
    return 0;
}

/* The checks of measure m, or with m NULL the layout's checks of the run. */
static int print_checks(sqlite3 *db, int64_t run, const rf_rules *r, const measure_row *m,
                        FILE *out, rf_error *err)
{
    sqlite3_stmt *st;
    if (prepare(db,
                m ? "SELECT rule, value, threshold, passed FROM checks WHERE measure_id = ?1"
                    " ORDER BY id"
                  : "SELECT rule, value, threshold, passed FROM checks WHERE run_id = ?1 AND"
                    " measure_id IS NULL ORDER BY id",
                &st, err))
        return -1;
    sqlite3_bind_int64(st, 1, m ? m->id : run);
    const rf_rule_check *list = m ? r->checks : r->layout_checks;
    size_t nlist = m ? r->nchecks : r->nlayout;
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *rule = (const char *)sqlite3_column_text(st, 0);
        const char *cmp = ">=";
        for (size_t c = 0; c < nlist; c++)
            if (rule && !strcmp(rule, list[c].name))
                cmp = comparison_names[list[c].comparison];
        int passed = sqlite3_column_int(st, 3);
        if (sqlite3_column_type(st, 1) == SQLITE_NULL)
            fprintf(out, "  %s %-24s %s\n", passed ? "PASS" : "FAIL", rule,
                    m ? "no interceptions" : "no rockfalls");
        else
            fprintf(out, "  %s %-24s %.4f %s %g\n", passed ? "PASS" : "FAIL", rule,
                    sqlite3_column_double(st, 1), cmp, sqlite3_column_double(st, 2));
    }
    sqlite3_finalize(st);
    return 0;
}

/* The run's measures, their limit states and checks, and the verdict (failed of the
 * checks evaluate has just written, nchecks per measure). */
static int print_run(sqlite3 *db, int64_t run, const rf_rules *r, const run_measures *L,
                     long failed, FILE *out, rf_error *err)
{
    if (!L->project)
        return rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0, "no run %lld",
                            (long long)run);
    fprintf(out, "run %lld of '%s' checked against %s (%s)\n\n", (long long)run, L->project,
            r->path, r->name);
    fprintf(out, "%-16s %-10s %-14s", "measure", "kind", "importance");
    rf_query_print_stats_header(out);
    for (size_t i = 0; i < L->n; i++) {
        const measure_row *m = &L->m[i];
        rf_measure_stats st;
        if (rf_query_measure_stats(db, m->id, &st, err))
            return -1;
        fprintf(out, "%-16s %-10s %-14s", m->name, rf_measure_kind_name(m->kind),
                rf_importance_name(m->importance));
        rf_query_print_stats(out, &st);
    }
    fprintf(out, "energies in kJ at the 50th, 90th, 95th, 99th percentiles (nearest rank) and "
                 "maximum; h95: 95th-percentile passing height\n");
    for (size_t i = 0; i < L->n; i++) {
        const measure_row *m = &L->m[i];
        fprintf(out, "\n%s (%s, %s)\n", m->name, rf_measure_kind_name(m->kind),
                rf_importance_name(m->importance));
        print_capacities(r, m, out);
        if (print_states(db, r, m, out, err) || print_checks(db, run, r, m, out, err))
            return -1;
    }
    if (r->nlayout) {
        long n = L->n_rockfalls;
        long reach = query_count(db,
                                 "SELECT count(DISTINCT i.trajectory_id) FROM interceptions i"
                                 " JOIN measures m ON m.id = i.measure_id WHERE m.run_id = ?1"
                                 " AND m.kind = 'control'",
                                 run, "counting the rockfalls across a control line", err);
        if (reach < 0)
            return -1;
        fprintf(out, "\nlayout: %ld rockfalls, %ld of them across a control line\n", n, reach);
        for (size_t c = 0; c < r->nlayout; c++)
            fprintf(out, "  kept within %s: %ld (%.1f %%)\n",
                    rf_rules_state_name(r, r->layout_checks[c].state), L->kept[c],
                    n > 0 ? 100.0 * (double)L->kept[c] / (double)n : 0.0);
        if (print_checks(db, run, r, NULL, out, err))
            return -1;
    }
    long nc = (long)(L->n * r->nchecks + r->nlayout);
    if (failed)
        fprintf(out, "\nverdict: FAIL (%ld of %ld checks failed)\n", failed, nc);
    else
        fprintf(out, "\nverdict: PASS (all %ld checks passed)\n", nc);
    return 0;
}

int rf_rules_evaluate(sqlite3 *db, int64_t run, const rf_rules *r, FILE *out, long *n_failed,
                      rf_error *err)
{
    long failed = 0;
    if (n_failed)
        *n_failed = 0;
    if (sqlite3_exec(db, "BEGIN IMMEDIATE", NULL, NULL, NULL) != SQLITE_OK)
        return db_error(db, "evaluating the rules", err);
    /* the run's measures are read in the transaction that writes their checks */
    run_measures L = {0};
    int status = read_run_measures(db, run, r, &L, err);
    if (status == 0)
        status = evaluate(db, run, r, &L, &failed, err);
    if (status == 0 && sqlite3_exec(db, "COMMIT", NULL, NULL, NULL) != SQLITE_OK)
        status = db_error(db, "committing the checks", err);
    if (status != 0 && !sqlite3_get_autocommit(db))
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
    if (status == 0 && out)
        status = print_run(db, run, r, &L, failed, out, err);
    if (n_failed)
        *n_failed = status == 0 ? failed : 0;
    run_measures_free(&L);
    return status;
}
