/* rules_print.c - the printed account of a checked run: per measure its statistics,
 * capacities, shares per limit state and checks, then the layout and the verdict. */
#include "check/rules.h"

#include <math.h>
#include <string.h>

#include "base/term.h"
#include "check/rules_private.h"
#include "results/run_view.h"

static void print_capacities(const rf_rules *r, const rf_rules_measure *m, FILE *out)
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

/* Every name from the rule file or the database reaches the terminal escaped
 * (base/term.h): a name is text from a file, and may hold a newline or ESC. */
#define NAME_SIZE 256

/* The shares of the measure's interceptions in each limit state (one classification
 * each); nothing without interceptions. */
static int print_states(sqlite3 *db, const rf_rules *r, const rf_rules_measure *m, FILE *out,
                        rf_error *err)
{
    sqlite3_stmt *st;
    if (rf_rules_prepare_for(db,
                "SELECT c.limit_state, count(*) FROM classifications c"
                " JOIN interceptions i ON i.id = c.interception_id"
                " WHERE i.measure_id = ?1 GROUP BY c.limit_state",
                &st, "reading the run", err))
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
        char safe[NAME_SIZE];
        fprintf(out, "%s %s %.1f %%", shown++ ? "," : "", rf_term_escape(name, safe, sizeof safe),
                100.0 * (double)counts[i] / (double)n);
    }
    fprintf(out, "\n");
    return 0;
}

static int is_integrity_rule(const char *rule)
{
    for (int k = 0; rule && k < RF_N_INTEGRITY; k++)
        if (!strcmp(rule, rf_integrity_rules[k]))
            return 1;
    return 0;
}

/* The checks of measure m, or with m NULL the layout's checks of the run (the
 * integrity checks, also run-wide, are print_integrity's). */
static int print_checks(sqlite3 *db, int64_t run, const rf_rules *r, const rf_rules_measure *m,
                        FILE *out, rf_error *err)
{
    sqlite3_stmt *st;
    if (rf_rules_prepare_for(db,
                m ? "SELECT rule, value, threshold, passed FROM checks WHERE measure_id = ?1"
                    " ORDER BY id"
                  : "SELECT rule, value, threshold, passed FROM checks WHERE run_id = ?1 AND"
                    " measure_id IS NULL ORDER BY id",
                &st, "reading the run", err))
        return -1;
    sqlite3_bind_int64(st, 1, m ? m->id : run);
    const rf_rule_check *list = m ? r->checks : r->layout_checks;
    size_t nlist = m ? r->nchecks : r->nlayout;
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *rule = (const char *)sqlite3_column_text(st, 0);
        if (!m && is_integrity_rule(rule))
            continue;
        const char *cmp = ">=";
        for (size_t c = 0; c < nlist; c++)
            if (rule && !strcmp(rule, list[c].name))
                cmp = rf_rules_comparison_names[list[c].comparison];
        int passed = sqlite3_column_int(st, 3);
        char safe[NAME_SIZE];
        rf_term_escape(rule, safe, sizeof safe);
        if (sqlite3_column_type(st, 1) == SQLITE_NULL)
            fprintf(out, "  %s %-24s %s\n", passed ? "PASS" : "FAIL", safe,
                    m ? "no interceptions" : "no rockfalls");
        else
            fprintf(out, "  %s %-24s %.4f %s %g\n", passed ? "PASS" : "FAIL", safe,
                    sqlite3_column_double(st, 1), cmp, sqlite3_column_double(st, 2));
    }
    sqlite3_finalize(st);
    return 0;
}

/* By rf_integrity_kind: what the trajectories counted did, and what to change so that
 * the run can support a verdict. */
static const char *const integrity_what[RF_N_INTEGRITY] = {
    "ended by max_time", "left the terrain before any control line",
    "came to rest on a face steeper than their friction holds"};
static const char *const integrity_remedy[RF_N_INTEGRITY] = {
    ("raise simulation.max_time until no rock is cut short (a forest that makes a rock draw "
     "over a million candidate trees ends it so too: check the forests' density and diameter)"),
    "extend the terrain past the protected line and draw that line as a control line",
    "use the exact engine or a smaller time step"};

/* The integrity checks: for each kind, the count, its share and the allowance. */
static void print_integrity(const rf_rules *r, const rf_rules_run *L, FILE *out)
{
    const rf_run_integrity *g = &L->integrity;
    fprintf(out, "\ntrajectories that cannot support a verdict (of %ld):\n", g->n_trajectories);
    for (int k = 0; k < RF_N_INTEGRITY; k++) {
        const char *tag = L->within[k] ? "PASS" : "INCONCLUSIVE";
        if (!g->recorded[k])
            fprintf(out, "  %s %-31s not recorded (trajectories written before schema "
                         "version 3)\n", tag, rf_integrity_rules[k]);
        else
            fprintf(out, "  %s %-31s %ld %s (%.4f %s allowance %g)\n", tag,
                    rf_integrity_rules[k], g->count[k], integrity_what[k],
                    g->n_trajectories > 0 ? (double)g->count[k] / (double)g->n_trajectories
                                          : 0.0,
                    L->within[k] ? "<=" : ">", r->allowance[k]);
    }
}

/* The kinds beyond their allowance, each with its remedy. */
static void print_reasons(const rf_rules_run *L, FILE *out)
{
    const rf_run_integrity *g = &L->integrity;
    for (int k = 0; k < RF_N_INTEGRITY; k++)
        if (!L->within[k] && !g->recorded[k])
            fprintf(out, "  a fixed-step run written before schema version 3 does not record "
                         "which trajectories %s: run it again\n", integrity_what[k]);
        else if (!L->within[k])
            fprintf(out, "  %ld of %ld trajectories %s: %s\n", g->count[k], g->n_trajectories,
                    integrity_what[k], integrity_remedy[k]);
}

/* The verdict line: INCONCLUSIVE wins over FAIL (docs/rules.md: trajectories that cannot
 * support a verdict support no FAIL either), then the reasons. */
static void print_verdict(const rf_rules_run *L, const rf_rules_result *res, long nc, FILE *out)
{
    if (res->inconclusive && res->failed)
        fprintf(out, "\nverdict: INCONCLUSIVE (%ld of %ld checks failed, on trajectories that "
                     "cannot support a verdict)\n", res->failed, nc);
    else if (res->inconclusive)
        fprintf(out, "\nverdict: INCONCLUSIVE (all %ld checks passed, but the trajectories "
                     "cannot support a PASS)\n", nc);
    else if (res->failed)
        fprintf(out, "\nverdict: FAIL (%ld of %ld checks failed)\n", res->failed, nc);
    else
        fprintf(out, "\nverdict: PASS (all %ld checks passed)\n", nc);
    if (res->inconclusive)
        print_reasons(L, out);
}

/* The run's measures, their limit states and checks, the trajectories that cannot
 * support a verdict, and the verdict (nchecks per measure). */
int rf_rules_print_run(sqlite3 *db, int64_t run, const rf_rules *r, const rf_rules_run *L,
                     const rf_rules_result *res, FILE *out, rf_error *err)
{
    if (!L->project)
        return rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0, "no run %lld",
                            (long long)run);
    char project[NAME_SIZE], path[NAME_SIZE * 4], name[NAME_SIZE], safe[NAME_SIZE];
    fprintf(out, "run %lld of '%s' checked against %s (%s)\n\n", (long long)run,
            rf_term_escape(L->project, project, sizeof project),
            rf_term_escape(r->path, path, sizeof path), rf_term_escape(r->name, name, sizeof name));
    fprintf(out, "%-16s %-10s %-14s", "measure", "kind", "importance");
    rf_query_print_stats_header(out);
    for (size_t i = 0; i < L->n; i++) {
        const rf_rules_measure *m = &L->m[i];
        rf_measure_stats st;
        if (rf_query_measure_stats(db, m->id, &st, err))
            return -1;
        fprintf(out, "%-16s %-10s %-14s", rf_term_escape(m->name, safe, sizeof safe),
                rf_measure_kind_name(m->kind), rf_importance_name(m->importance));
        rf_query_print_stats(out, &st);
    }
    fprintf(out, "energies in kJ at the 50th, 90th, 95th, 99th percentiles (nearest rank) and "
                 "maximum; h95: 95th-percentile passing height\n");
    for (size_t i = 0; i < L->n; i++) {
        const rf_rules_measure *m = &L->m[i];
        fprintf(out, "\n%s (%s, %s)\n", rf_term_escape(m->name, safe, sizeof safe),
                rf_measure_kind_name(m->kind), rf_importance_name(m->importance));
        print_capacities(r, m, out);
        if (print_states(db, r, m, out, err) || print_checks(db, run, r, m, out, err))
            return -1;
    }
    if (r->nlayout) {
        long n = L->n_rockfalls;
        char *kinds = rf_rules_reach_kinds_sql();
        char *sql = kinds ? sqlite3_mprintf("SELECT count(DISTINCT i.trajectory_id) FROM"
                                            " interceptions i JOIN measures m ON m.id ="
                                            " i.measure_id WHERE m.run_id = ?1 AND m.kind IN"
                                            " (%s)",
                                            kinds)
                          : NULL;
        long reach = sql ? rf_rules_query_count(db, sql, run,
                                                "counting the rockfalls across a control line",
                                                err)
                         : (rf_error_set(err, "", 0, 0, "out of memory"), -1L);
        sqlite3_free(kinds);
        sqlite3_free(sql);
        if (reach < 0)
            return -1;
        fprintf(out, "\nlayout: %ld rockfalls, %ld of them across a control line\n", n, reach);
        for (size_t c = 0; c < r->nlayout; c++)
            fprintf(out, "  kept within %s: %ld (%.1f %%)\n",
                    rf_term_escape(rf_rules_state_name(r, r->layout_checks[c].state), safe,
                                   sizeof safe),
                    L->kept[c],
                    n > 0 ? 100.0 * (double)L->kept[c] / (double)n : 0.0);
        if (print_checks(db, run, r, NULL, out, err))
            return -1;
    }
    print_integrity(r, L, out);
    print_verdict(L, res, (long)(L->n * r->nchecks + r->nlayout), out);
    return 0;
}

