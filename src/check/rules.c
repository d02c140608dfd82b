/* rules.c - the rules engine against a run: Table 3 classification of the run's
 * interceptions and its design checks, written in one transaction with the rule file
 * used (docs/rules.md).  The run is read through the run view, never the project
 * file. */
#include "check/rules.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"
#include "check/rules_private.h"
#include "input/measure_kinds.h"
#include "results/run_view.h"
#include "results/schema.h"

/* ---- classification ------------------------------------------------------------- */

void rf_rules_capacities(const rf_rules *r, rf_measure_kind kind, double mel, double sel,
                         const double project_capacity[RF_N_LIMIT_STATES],
                         double capacity[RF_N_LIMIT_STATES])
{
    for (int s = 0; s < RF_N_LIMIT_STATES; s++) {
        capacity[s] = NAN;
        if ((unsigned)kind >= RF_N_MEASURE_KINDS || !rf_measure_kinds[kind].classified)
            continue;
        switch (r->capacity[kind][s]) {
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


/* ---- the database ---------------------------------------------------------------- */

static int db_error(sqlite3 *db, const char *doing, rf_error *err)
{
    return rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0, "%s: %s", doing,
                        sqlite3_errmsg(db));
}

/* Prepares sql; on failure err says what was being done. */
int rf_rules_prepare_for(sqlite3 *db, const char *sql, sqlite3_stmt **st, const char *doing,
                         rf_error *err)
{
    if (sqlite3_prepare_v2(db, sql, -1, st, NULL) != SQLITE_OK)
        return db_error(db, doing, err);
    return 0;
}

static int prepare(sqlite3 *db, const char *sql, sqlite3_stmt **st, rf_error *err)
{
    return rf_rules_prepare_for(db, sql, st, "reading the run", err);
}

int rf_rules_path_of_run(sqlite3 *db, int64_t run, char **path, rf_error *err)
{
    *path = NULL;
    rf_run_view v;
    if (rf_run_view_load(db, run, &v, err))
        return -1;
    int status = 0;
    if (!v.rules_path)
        status = rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0,
                              "the project of run %lld names no rule file ('rules:'); pass "
                              "--rules FILE (e.g. rules/table3.yaml)",
                              (long long)run);
    else
        *path = v.rules_path, v.rules_path = NULL;
    rf_run_view_free(&v);
    return status;
}

char *rf_rules_reach_kinds_sql(void)
{
    return rf_reach_kinds_sql(); /* the same list the integrity counts use */
}

static void rules_run_free(rf_rules_run *L)
{
    for (size_t i = 0; i < L->n; i++)
        free(L->m[i].name);
    free(L->m);
    free(L->kept);
    free(L->project);
    memset(L, 0, sizeof *L);
}

/* Fills the empty L with the run's measures that Table 3 classifies, read through the
 * run view; on failure L may hold part of them (the caller frees it).  A barrier whose
 * SEL the database marks as the default has no SEL of the project's: the rule file's
 * sel_default decides, and without one it has none. */
static int read_run_measures(sqlite3 *db, int64_t run, const rf_rules *r, rf_rules_run *L,
                             rf_error *err)
{
    rf_run_view v;
    if (rf_run_view_load(db, run, &v, err))
        return -1;
    int status = 0;
    if (!(L->project = strdup(v.project)) ||
        !(L->m = calloc(v.nmea + 1, sizeof *L->m)))
        status = rf_error_set(err, "", 0, 0, "out of memory");
    for (size_t i = 0; status == 0 && i < v.nmea; i++) {
        const rf_view_measure *vm = &v.mea[i];
        if (vm->kind < 0 || !rf_measure_kinds[vm->kind].classified)
            continue;
        if (vm->importance < 0) {
            status = rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0,
                                  "measure '%s' has importance '%s'; expected most_important, "
                                  "important or usual",
                                  vm->name, vm->importance_name);
            break;
        }
        rf_rules_measure *m = &L->m[L->n];
        *m = (rf_rules_measure){.id = vm->id, .kind = (rf_measure_kind)vm->kind,
                                .importance = vm->importance, .name = strdup(vm->name)};
        if (!m->name) {
            status = rf_error_set(err, "", 0, 0, "out of memory");
            break;
        }
        L->n++;
        double sel = vm->sel, project[RF_N_LIMIT_STATES];
        memcpy(project, vm->cap, sizeof project);
        if (vm->sel_given == 0)
            sel = project[RF_SERVICEABILITY] = NAN;
        rf_rules_capacities(r, m->kind, vm->mel, sel, project, m->capacity);
    }
    rf_run_view_free(&v);
    return status;
}

static int classify_measure(sqlite3 *db, const rf_rules *r, const rf_rules_measure *m,
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

static int write_checks(sqlite3 *db, int64_t run, const rf_rules *r, const rf_rules_measure *m,
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
long rf_rules_query_count(sqlite3 *db, const char *sql, int64_t run, const char *what,
                          rf_error *err)
{
    sqlite3_stmt *st;
    if (rf_rules_prepare_for(db, sql, &st, what, err))
        return -1;
    sqlite3_bind_int64(st, 1, run);
    long n = sqlite3_step(st) == SQLITE_ROW ? (long)sqlite3_column_int64(st, 0) : -1;
    sqlite3_finalize(st);
    if (n < 0)
        db_error(db, what, err);
    return n;
}

/* The run's trajectories kept within limit state index `state`: no crossing of a
 * protected line (a kind with reach_line: a control line), every interception of a barrier or embankment classified (by
 * evaluate, just before) into `state` or an earlier one; -1 on error (err set). */
static long layout_kept(sqlite3 *db, int64_t run, const rf_rules *r, int state, rf_error *err)
{
    char *within = sqlite3_mprintf("%Q", rf_rules_state_name(r, 0));
    for (int i = 1; within && i <= state; i++) {
        char *more = sqlite3_mprintf("%s, %Q", within, rf_rules_state_name(r, i));
        sqlite3_free(within);
        within = more;
    }
    char *reach = rf_rules_reach_kinds_sql();
    char *sql = within && reach
                    ? sqlite3_mprintf(
                          "SELECT count(*) FROM trajectories t WHERE t.run_id = ?1 AND NOT "
                          "EXISTS (SELECT 1 FROM interceptions i JOIN measures m ON m.id = "
                          "i.measure_id LEFT JOIN classifications c ON c.interception_id = "
                          "i.id WHERE i.trajectory_id = t.id AND (m.kind IN (%s) OR "
                          "c.limit_state IS NULL OR c.limit_state NOT IN (%s)))",
                          reach, within)
                    : NULL;
    sqlite3_free(within);
    sqlite3_free(reach);
    long kept = sql ? rf_rules_query_count(db, sql, run, "counting the rockfalls the layout keeps", err)
                    : (rf_error_set(err, "", 0, 0, "out of memory"), -1L);
    sqlite3_free(sql);
    return kept;
}

/* The layout's checks; the run's rockfalls into L->n_rockfalls, those each check
 * kept into L->kept[c], for print_run. */
static int write_layout_checks(sqlite3 *db, int64_t run, const rf_rules *r, sqlite3_stmt *ins,
                               rf_rules_run *L, long *n_failed, rf_error *err)
{
    if (r->nlayout == 0)
        return 0;
    if (!(L->kept = calloc(r->nlayout, sizeof *L->kept)))
        return rf_error_set(err, "", 0, 0, "out of memory");
    L->n_rockfalls =
        rf_rules_query_count(db, "SELECT count(*) FROM trajectories WHERE run_id = ?1", run,
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

int rf_rules_within_allowance(long count, long n, double allowance)
{
    /* count / n correctly rounded against the allowance as the file gives it: 5 of 500
     * compares equal to 0.01, as the shares of the checks do */
    return n <= 0 || (double)count / (double)n <= allowance;
}

/* The integrity checks: one row per kind of trajectory that cannot support a verdict,
 * value the share of the run's trajectories (NULL when the run has none, or the file
 * does not record the kind), passed when within the rule file's allowance; a failed
 * one makes the verdict inconclusive (on_failure, from schema version 3; a file of an
 * earlier version, which check does not upgrade, stores the row without it). */
static int write_integrity_checks(sqlite3 *db, int64_t run, const rf_rules *r,
                                  rf_rules_run *L, long *n_inconclusive, rf_error *err)
{
    if (rf_run_integrity_count(db, run, &L->integrity, err))
        return -1;
    sqlite3_stmt *ins;
    if (prepare(db,
                rf_db_has_column(db, "checks", "on_failure")
                    ? "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed,"
                      " on_failure) VALUES (?1, NULL, ?2, ?3, ?4, ?5, 'inconclusive')"
                    : "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed)"
                      " VALUES (?1, NULL, ?2, ?3, ?4, ?5)",
                &ins, err))
        return -1;
    const rf_run_integrity *g = &L->integrity;
    int status = 0;
    for (int k = 0; status == 0 && k < RF_N_INTEGRITY; k++) {
        int known = g->recorded[k] && g->n_trajectories > 0;
        /* unrecorded, a fixed-step run's rests on steep faces cannot be ruled out */
        L->within[k] = g->recorded[k] ? rf_rules_within_allowance(g->count[k], g->n_trajectories,
                                                                  r->allowance[k])
                                      : !(k == RF_INTEGRITY_REST_STEEP && g->fixed_step);
        *n_inconclusive += !L->within[k];
        sqlite3_bind_int64(ins, 1, run);
        sqlite3_bind_text(ins, 2, rf_integrity_rules[k], -1, SQLITE_STATIC);
        if (known)
            sqlite3_bind_double(ins, 3, (double)g->count[k] / (double)g->n_trajectories);
        else
            sqlite3_bind_null(ins, 3);
        sqlite3_bind_double(ins, 4, r->allowance[k]);
        sqlite3_bind_int(ins, 5, L->within[k]);
        if (sqlite3_step(ins) != SQLITE_DONE)
            status = db_error(db, "writing an integrity check", err);
        sqlite3_reset(ins);
    }
    sqlite3_finalize(ins);
    return status;
}

static int evaluate(sqlite3 *db, int64_t run, const rf_rules *r, rf_rules_run *L,
                    long *n_failed, long *n_inconclusive, rf_error *err)
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
    if (write_layout_checks(db, run, r, ins_check, L, n_failed, err) ||
        write_integrity_checks(db, run, r, L, n_inconclusive, err))
        goto done;
    status = 0;
done:
    sqlite3_finalize(ins_class);
    sqlite3_finalize(ins_check);
    free(n_within);
    return status;
}

/* The rule file of this check of the run (check_rules), replacing an earlier one's; a
 * file of schema version 1 has no such table and keeps only the checks. */
static int store_rule_file(sqlite3 *db, int64_t run, const rf_rules *r, rf_error *err)
{
    if (!rf_db_has_table(db, "check_rules"))
        return 0;
    sqlite3_stmt *st;
    if (rf_rules_prepare_for(db,
                             "INSERT OR REPLACE INTO check_rules (run_id, path, name, text,"
                             " checked_at) VALUES (?1, ?2, ?3, ?4,"
                             " strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))",
                             &st, "writing the rule file", err))
        return -1;
    sqlite3_bind_int64(st, 1, run);
    sqlite3_bind_text(st, 2, r->path ? r->path : "", -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 3, r->name, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 4, r->text ? r->text : "", -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : db_error(db, "writing the rule file", err);
}

int rf_rules_evaluate(sqlite3 *db, int64_t run, const rf_rules *r, FILE *out, long *n_failed,
                      rf_error *err)
{
    rf_rules_result res;
    int status = rf_rules_evaluate_verdict(db, run, r, out, &res, err);
    if (n_failed)
        *n_failed = status == 0 ? res.failed : 0;
    return status;
}

int rf_rules_evaluate_verdict(sqlite3 *db, int64_t run, const rf_rules *r, FILE *out,
                              rf_rules_result *res, rf_error *err)
{
    long failed = 0, inconclusive = 0;
    /* a run that kept only its maps has no row of most of its trajectories: neither the
     * layout's share nor the integrity counts can be taken (docs/scaling.md) */
    long maps = rf_db_has_column(db, "runs", "store")
                    ? rf_rules_query_count(db, "SELECT count(*) FROM runs WHERE id = ?1 AND"
                                               " store = 'maps'",
                                           run, "reading the run", err)
                    : 0;
    if (maps < 0)
        return -1;
    if (maps > 0)
        return rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0,
                            "run %lld kept only its maps (run --store maps): its checks need "
                            "the row of every trajectory; run the project without --store maps",
                            (long long)run);
    if (sqlite3_exec(db, "BEGIN IMMEDIATE", NULL, NULL, NULL) != SQLITE_OK)
        return db_error(db, "evaluating the rules", err);
    /* the run's measures are read in the transaction that writes their checks */
    rf_rules_run L = {0};
    int status = read_run_measures(db, run, r, &L, err);
    if (status == 0)
        status = evaluate(db, run, r, &L, &failed, &inconclusive, err);
    if (status == 0)
        status = store_rule_file(db, run, r, err);
    if (status == 0 && sqlite3_exec(db, "COMMIT", NULL, NULL, NULL) != SQLITE_OK)
        status = db_error(db, "committing the checks", err);
    if (status != 0 && !sqlite3_get_autocommit(db))
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
    rf_rules_result got = {.failed = failed, .inconclusive = inconclusive,
                           .verdict = inconclusive ? RF_VERDICT_INCONCLUSIVE
                                      : failed     ? RF_VERDICT_FAIL
                                                   : RF_VERDICT_PASS};
    if (status == 0 && out)
        status = rf_rules_print_run(db, run, r, &L, &got, out, err);
    if (res)
        *res = status == 0 ? got : (rf_rules_result){0};
    rules_run_free(&L);
    return status;
}
