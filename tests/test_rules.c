/* test_rules.c - the rules engine: Table 3, the rule-file format and its bad-file
 * corpus, classification of constructed interceptions with known energies, the checks
 * at and around the 90 % boundary, the views, and `rockfall check` end to end. */
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rockfall/project.h"
#include "check/rules.h"
#include "results/schema.h"
#include "results/store.h"
#include "corpus_test_util.h"
#include "db_test_util.h"
#include "test.h"

#define TABLE3 "rules/table3.yaml"

static void load_rules(const char *path, rf_rules *r)
{
    rf_error err = {{0}};
    ENSURE_MSG(rf_rules_load(path, r, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
}

/* Table 3 with one line of the file replaced (`from` -> `to`). */
static void load_variant(const char *from, const char *to, rf_rules *r)
{
    FILE *f = fopen(TABLE3, "rb");
    ENSURE(f);
    static char text[16384], out[16384];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    char *at = strstr(text, from);
    ENSURE_MSG(at, "'%s' not in %s", from, TABLE3);
    snprintf(out, sizeof out, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
    rf_error err = {{0}};
    ENSURE_MSG(rf_rules_load_text("variant.yaml", out, strlen(out), r, &err) == 0,
               "%d:%d: %s", err.line, err.column, err.message);
}

/* Table 3's text with its `allowance:` block (the end of the file) replaced by
 * `allowance` (a whole line, or "" for none); malloc'd. */
static char *table3_with_allowance(const char *allowance)
{
    char *text = rf_test_read_text(TABLE3);
    ENSURE(text);
    char *at = strstr(text, "\nallowance:\n");
    ENSURE_MSG(at, "no allowance block in %s", TABLE3);
    size_t n = (size_t)(at - text) + 1 + strlen(allowance) + 1;
    char *out = malloc(n);
    ENSURE(out);
    snprintf(out, n, "%.*s\n%s", (int)(at - text), text, allowance);
    free(text);
    return out;
}

/* Table 3 with its allowances replaced */
static void load_allowance(const char *allowance, rf_rules *r)
{
    char *text = table3_with_allowance(allowance);
    rf_error err = {{0}};
    ENSURE_MSG(rf_rules_load_text("allowance.yaml", text, strlen(text), r, &err) == 0,
               "%d:%d: %s", err.line, err.column, err.message);
    free(text);
}

/* ---- Table 3 --------------------------------------------------------------------- */

TEST(rules_table3_every_cell)
{
    rf_rules r;
    load_rules(TABLE3, &r);
    /* Table 3 of the paper, rows action level 1..3, columns most important, important,
     * usual. */
    static const char *const want[3][3] = {
        {"serviceability", "serviceability", "restorability"},
        {"serviceability", "restorability", "ultimate"},
        {"restorability", "ultimate", "near_collapse"},
    };
    static const rf_importance imp[3] = {RF_MOST_IMPORTANT, RF_IMPORTANT, RF_USUAL};
    for (int level = 1; level <= 3; level++)
        for (int i = 0; i < 3; i++) {
            const char *got = rf_rules_state_name(&r, rf_rules_required(&r, level, imp[i]));
            ENSURE_MSG(!strcmp(got, want[level - 1][i]), "level %d, %s: %s", level,
                       rf_importance_name(imp[i]), got);
        }
    rf_rules_free(&r);
}

TEST(rules_table3_layout)
{
    rf_rules r;
    load_rules(TABLE3, &r);
    ENSURE(r.nstates == 4);
    ENSURE(r.states[0] == RF_SERVICEABILITY && r.states[1] == RF_RESTORABILITY);
    ENSURE(r.states[2] == RF_ULTIMATE && r.states[3] == RF_NEAR_COLLAPSE);
    ENSURE(!strcmp(r.beyond_last, "collapse"));
    ENSURE(!strcmp(rf_rules_state_name(&r, 4), "collapse"));
    ENSURE(!strcmp(rf_rules_state_name(&r, RF_REACHED_OVERTOPPED), "overtopped"));
    /* barrier: serviceability = SEL = MEL / 3, restorability from the project when it
     * gives one, ultimate = MEL; no near collapse */
    ENSURE(r.capacity[0][RF_SERVICEABILITY] == RF_CAP_SEL);
    ENSURE(r.capacity[0][RF_ULTIMATE] == RF_CAP_MEL);
    ENSURE(r.capacity[0][RF_RESTORABILITY] == RF_CAP_PROJECT);
    ENSURE(r.capacity[0][RF_NEAR_COLLAPSE] == RF_CAP_NONE);
    ENSURE(r.sel_divisor == 3.0);
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        ENSURE(r.capacity[1][s] == RF_CAP_PROJECT);
    ENSURE(r.nchecks == 2);
    ENSURE(!strcmp(r.checks[0].name, "serviceability_share"));
    ENSURE(r.checks[0].value == RF_VALUE_SHARE_WITHIN && r.checks[0].state == 0);
    ENSURE(r.checks[0].comparison == RF_CMP_AT_LEAST && r.checks[0].threshold == 0.9);
    ENSURE(!strcmp(r.checks[1].name, "required_state"));
    ENSURE(r.checks[1].value == RF_VALUE_SHARE_MEETING && r.checks[1].threshold == 1.0);
    ENSURE(r.empty_passes == 1);
    rf_rules_free(&r);
}

TEST(rules_limit_state_reached)
{
    rf_rules r;
    load_rules(TABLE3, &r);
    const double none[RF_N_LIMIT_STATES] = {NAN, NAN, NAN, NAN};
    double cap[RF_N_LIMIT_STATES];
    /* A barrier of MEL 2385 kJ without a sel: SEL = 795 kJ from the rule file. */
    rf_rules_capacities(&r, RF_BARRIER, 2385.0, NAN, none, cap);
    ENSURE(cap[RF_SERVICEABILITY] == 795.0 && cap[RF_ULTIMATE] == 2385.0);
    ENSURE(isnan(cap[RF_RESTORABILITY]) && isnan(cap[RF_NEAR_COLLAPSE]));
    ENSURE(rf_rules_reached(&r, cap, 12.5, RF_OUT_STOPPED) == 0);
    ENSURE(rf_rules_reached(&r, cap, 795.0, RF_OUT_STOPPED) == 0); /* capacity holds it */
    ENSURE(rf_rules_reached(&r, cap, 795.125, RF_OUT_STOPPED) == 2); /* restorability skipped */
    ENSURE(rf_rules_reached(&r, cap, 2385.0, RF_OUT_STOPPED) == 2);
    ENSURE(rf_rules_reached(&r, cap, 2385.5, RF_OUT_PASSED) == 4);  /* collapse */
    ENSURE(rf_rules_reached(&r, cap, 12.5, RF_OUT_BROKE_THROUGH) == 4);
    /* An overtopping fails the structure's function: never serviceable. */
    ENSURE(rf_rules_reached(&r, cap, 0.5, RF_OUT_OVERTOPPED) == RF_REACHED_OVERTOPPED);
    ENSURE(rf_rules_reached(&r, cap, NAN, RF_OUT_STOPPED) == RF_REACHED_UNKNOWN);
    /* The project's sel wins over the default. */
    rf_rules_capacities(&r, RF_BARRIER, 2385.0, 1000.0, none, cap);
    ENSURE(cap[RF_SERVICEABILITY] == 1000.0);
    /* An embankment takes the project's capacities; a missing one is skipped. */
    const double given[RF_N_LIMIT_STATES] = {3000.0, NAN, 9000.0, 12000.0};
    rf_rules_capacities(&r, RF_EMBANKMENT, NAN, NAN, given, cap);
    ENSURE(rf_rules_reached(&r, cap, 2999.5, RF_OUT_STOPPED) == 0);
    ENSURE(rf_rules_reached(&r, cap, 4500.0, RF_OUT_STOPPED) == 2);
    ENSURE(rf_rules_reached(&r, cap, 10500.0, RF_OUT_STOPPED) == 3);
    ENSURE(rf_rules_reached(&r, cap, 12000.25, RF_OUT_STOPPED) == 4);
    /* meets: at or before the required state; overtopped, collapse, unknown never */
    ENSURE(rf_rules_meets(&r, 0, 1) && rf_rules_meets(&r, 1, 1) && !rf_rules_meets(&r, 2, 1));
    ENSURE(rf_rules_meets(&r, 3, 3) && !rf_rules_meets(&r, 4, 3));
    ENSURE(!rf_rules_meets(&r, RF_REACHED_OVERTOPPED, 3));
    ENSURE(!rf_rules_meets(&r, RF_REACHED_UNKNOWN, 3));
    rf_rules_free(&r);
}

TEST(rules_check_comparison_at_the_boundary)
{
    rf_rules at_least, over;
    load_rules(TABLE3, &at_least);
    load_variant("comparison: \">=\"\n    threshold: 0.9", "comparison: \">\"\n    threshold: 0.9",
                 &over);
    ENSURE(over.checks[0].comparison == RF_CMP_GREATER);
    /* exactly 90 % of several counts: count / n is the double nearest 0.9 */
    for (long n = 10; n <= 100000; n *= 10) {
        double v = (double)(9 * n / 10) / (double)n;
        ENSURE_MSG(rf_rules_check_passes(&at_least.checks[0], v), "n = %ld", n);
        ENSURE_MSG(!rf_rules_check_passes(&over.checks[0], v), "n = %ld", n);
    }
    ENSURE(rf_rules_check_passes(&over.checks[0], 0.92));
    ENSURE(!rf_rules_check_passes(&at_least.checks[0], 0.88));
    ENSURE(!rf_rules_check_passes(&at_least.checks[0], 899.0 / 1000.0));
    rf_rules_free(&at_least);
    rf_rules_free(&over);
}

/* ---- the bad-file corpus ------------------------------------------------------- */

/* A file of tests/bad_rules. */
static int check_bad_rules(const ct_expect *e)
{
    rf_rules r;
    rf_error err = {{0}};
    if (rf_rules_load(e->path, &r, &err) == 0) {
        fprintf(stderr, "    %s: loaded, expected an error\n", e->path);
        rf_rules_free(&r);
        return 0;
    }
    int ok = ct_error_as_expected(e, &err, strcmp(err.file, e->path) == 0);
    if (r.name || r.checks || r.path || r.beyond_last) {
        fprintf(stderr, "    %s: rules not emptied after an error\n", e->path);
        ok = 0;
    }
    return ok;
}

TEST(rules_bad_files)
{
    ct_bad_corpus("tests/bad_rules", "bad rule", 30, check_bad_rules);
}

TEST(rules_missing_file)
{
    rf_rules r;
    rf_error err = {{0}};
    ENSURE(rf_rules_load("rules/no_such_rules.yaml", &r, &err) != 0);
    ENSURE(!strcmp(err.file, "rules/no_such_rules.yaml"));
    ENSURE(strstr(err.message, "cannot open"));
    ENSURE(r.name == NULL && r.checks == NULL);
}

/* ---- constructed runs -------------------------------------------------------------- */

enum { M_ROAD, M_B1, M_B2, M_E1, M_B3, N_MEASURES };

/* A project with three releases (action levels 1, 2, 3) and five measures: a control
 * line, barriers B1 and B2 (MEL 3000 kJ, SEL 1000 kJ), embankment E1 (3000, 6000,
 * 9000, 12000 kJ) and barrier B3, which no rock reaches. */
typedef struct scene {
    rf_project p;
    rf_rock rocks[3];
    rf_release releases[3];
    rf_measure measures[N_MEASURES];
    double line[4];
    rf_store *s;
    int64_t run;
    long next_idx[3];
} scene;

static void scene_init(scene *t, rf_importance importance, const char *yaml)
{
    memset(t, 0, sizeof *t);
    t->p.name = "constructed";
    t->p.path = "constructed.yaml";
    t->p.yaml_text = (char *)yaml;
    t->p.seed = 2009;
    for (int i = 0; i < 3; i++) {
        static const char *const names[] = {"r1", "r2", "r3"};
        static const char *const releases[] = {"L1", "L2", "L3"};
        t->rocks[i] = (rf_rock){.name = (char *)names[i], .mass = 2385.0, .density = 2650.0,
                                .action_level = i + 1, .radius = 0.6};
        t->releases[i] = (rf_release){.name = (char *)releases[i], .x = 10.0 * i, .y = 50.0,
                                      .z = 100.0, .rock = i, .count = 1};
    }
    t->p.rocks = t->rocks;
    t->p.nrocks = 3;
    t->p.releases = t->releases;
    t->p.nreleases = 3;
    static const double xy[4] = {0.0, 10.0, 40.0, 10.5};
    memcpy(t->line, xy, sizeof xy);
    rf_polyline line = {t->line, 2};
    t->measures[M_ROAD] = (rf_measure){.name = "road", .kind = RF_CONTROL, .line = line,
                                       .importance = importance, .behaviour = RF_COLLECT,
                                       .mel = -1, .sel = -1, .capacity = {-1, -1, -1, -1}};
    static const char *const barriers[] = {"B1", "B2", "B3"};
    static const int at[] = {M_B1, M_B2, M_B3};
    for (int i = 0; i < 3; i++)
        t->measures[at[i]] = (rf_measure){.name = (char *)barriers[i], .kind = RF_BARRIER,
                                          .line = line, .height = 5.0,
                                          .importance = importance, .behaviour = RF_STOP,
                                          .mel = 3000.0, .sel = 1000.0, .sel_given = 1,
                                          .capacity = {1000.0, -1, 3000.0, -1}};
    t->measures[M_E1] = (rf_measure){.name = "E1", .kind = RF_EMBANKMENT, .line = line,
                                     .height = 6.0, .importance = importance,
                                     .behaviour = RF_STOP, .mel = -1, .sel = -1,
                                     .capacity = {3000.0, 6000.0, 9000.0, 12000.0}};
    t->p.measures = t->measures;
    t->p.nmeasures = N_MEASURES;
}

static void scene_begin(scene *t, const char *db)
{
    rf_error err = {{0}};
    ENSURE_MSG(rf_store_open(db, &t->s, &err) == 0, "%s", err.message);
    ENSURE_MSG(rf_store_run_begin(t->s, &t->p, 0, &t->run, &err) == 0, "%s", err.message);
    ENSURE(rf_store_batch_begin(t->s, &err) == 0);
}

/* A scene (scene_init) whose run is begun in the database `db` of the test's directory. */
static void scene_open(scene *t, rf_importance importance, const char *yaml, const char *db)
{
    scene_init(t, importance, yaml);
    scene_begin(t, rf_test_path(db));
}

/* One trajectory of the release of `level` that meets `measure` with this energy. */
static void hit(scene *t, int level, int measure, double energy_kj, rf_outcome outcome)
{
    rf_error err = {{0}};
    rf_trajectory_record tr = {.stop = {5.0, 5.0, 80.0}, .reason = RF_END_STOPPED,
                               .duration_s = 12.5, .path_length_m = 90.0,
                               .max_energy_kj = energy_kj, .n_impacts = 7};
    int64_t id;
    ENSURE(rf_store_add_trajectory(t->s, (size_t)(level - 1), t->next_idx[level - 1]++, &tr,
                                   &id, &err) == 0);
    rf_interception_record in = {.measure = measure, .t_s = 10.25, .p = {20.0, 10.25, 82.0},
                                 .speed_ms = 20.0, .energy_kj = energy_kj,
                                 .energy_trans_kj = energy_kj, .passing_height_m = 1.25,
                                 .outcome = outcome};
    ENSURE_MSG(rf_store_add_interception(t->s, id, &in, NULL, &err) == 0, "%s", err.message);
}

/* n hits at a measure, `within` of them at 0.5 SEL and the rest between SEL and MEL. */
static void hits(scene *t, int level, int measure, int n, int within)
{
    for (int i = 0; i < n; i++)
        hit(t, level, measure, i < within ? 500.0 + i : 1500.0 + i, RF_OUT_STOPPED);
}

static void scene_finish(scene *t)
{
    rf_error err = {{0}};
    ENSURE(rf_store_run_finish(t->s, "complete", -1, &err) == 0);
}

/* Evaluates the run, the verdict printed to out (NULL: not printed); the checks
 * failed. */
static long evaluate_to(scene *t, const rf_rules *r, FILE *out)
{
    rf_error err = {{0}};
    long failed = -1;
    ENSURE_MSG(rf_rules_evaluate(rf_store_db(t->s), t->run, r, out, &failed, &err) == 0, "%s",
               err.message);
    return failed;
}

static long evaluate(scene *t, const rf_rules *r) { return evaluate_to(t, r, NULL); }

/* B1's share within serviceability in both views is the stored check value. */
static void ensure_views_share(sqlite3 *db, double stored)
{
    ENSURE(dbt_real(db, "SELECT share_serviceability FROM measure_summary WHERE measure ="
                          " 'B1'") == stored);
    ENSURE(dbt_real(db, "SELECT share FROM limit_state_shares WHERE measure = 'B1' AND"
                          " limit_state = 'serviceability'") == stored);
}

/* value and passed of the run's one check row matching `where` (k: checks, m: its
 * measure, if any) */
static double check_row(scene *t, const char *where, int *passed)
{
    sqlite3 *db = rf_store_db(t->s);
    const char *q = "FROM checks k LEFT JOIN measures m ON m.id = k.measure_id WHERE k.run_id = "
                    "%lld AND %s";
    char fmt[512];
    snprintf(fmt, sizeof fmt, "SELECT count(*) %s", q);
    ENSURE_MSG(dbt_real(db, fmt, (long long)t->run, where) == 1.0, "not one check %s", where);
    snprintf(fmt, sizeof fmt, "SELECT passed %s", q);
    *passed = (int)dbt_real(db, fmt, (long long)t->run, where);
    snprintf(fmt, sizeof fmt, "SELECT value %s", q);
    return dbt_real(db, fmt, (long long)t->run, where);
}

/* value and passed of a measure's check */
static double check_value(scene *t, const char *measure, const char *rule, int *passed)
{
    char where[256];
    snprintf(where, sizeof where, "m.name = '%s' AND k.rule = '%s'", measure, rule);
    return check_row(t, where, passed);
}

/* One trajectory of the release of `level` that meets measures ms[0..n) in turn. */
static void journey(scene *t, int level, int n, const int *ms, const double *energy,
                    const rf_outcome *outcome)
{
    rf_error err = {{0}};
    rf_trajectory_record tr = {.stop = {5.0, 5.0, 80.0}, .reason = RF_END_REST};
    int64_t id;
    ENSURE(rf_store_add_trajectory(t->s, (size_t)(level - 1), t->next_idx[level - 1]++, &tr,
                                   &id, &err) == 0);
    for (int k = 0; k < n; k++) {
        rf_interception_record in = {.measure = ms[k], .t_s = 10.0 + k, .p = {20.0, 10.0, 82.0},
                                     .speed_ms = 20.0, .energy_kj = energy[k],
                                     .energy_trans_kj = energy[k], .passing_height_m = 1.0,
                                     .outcome = outcome[k]};
        ENSURE_MSG(rf_store_add_interception(t->s, id, &in, NULL, &err) == 0, "%s", err.message);
    }
}

/* value and passed of the layout's check `rule` (measure_id NULL) */
static double layout_value(scene *t, const char *rule, int *passed)
{
    char where[256];
    snprintf(where, sizeof where, "k.measure_id IS NULL AND k.rule = '%s'", rule);
    return check_row(t, where, passed);
}

/* The paper's aim for the layout: the share of all rockfalls kept within
 * serviceability.  A rock that rests on the slope is kept, one that reaches the road
 * (a control line) is not, even when every structure it met held it within
 * serviceability; one beyond serviceability or over the top at any structure is not. */
TEST(rules_layout_share_counts_the_rockfalls_kept)
{
    scene t;
    scene_open(&t, RF_IMPORTANT, NULL, "layout.db");
    for (int k = 0; k < 10; k++)
        journey(&t, 1, 0, NULL, NULL, NULL);                 /* at rest on the slope: kept */
    hits(&t, 1, M_B1, 30, 28);                               /* 28 kept */
    for (int k = 0; k < 3; k++)
        hit(&t, 1, M_ROAD, 100.0, RF_OUT_PASSED);           /* on the road: not kept */
    journey(&t, 1, 2, (int[]){M_B1, M_ROAD}, (double[]){500.0, 100.0},
            (rf_outcome[]){RF_OUT_PASSED, RF_OUT_PASSED});  /* through B1 to the road */
    journey(&t, 2, 2, (int[]){M_B1, M_E1}, (double[]){500.0, 400.0},
            (rf_outcome[]){RF_OUT_PASSED, RF_OUT_STOPPED}); /* held by E1: kept */
    journey(&t, 1, 2, (int[]){M_E1, M_B2}, (double[]){400.0, 600.0},
            (rf_outcome[]){RF_OUT_PASSED, RF_OUT_OVERTOPPED}); /* over B2: not kept */
    hit(&t, 1, M_B1, 0.5, RF_OUT_OVERTOPPED);               /* over B1: not kept */
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    ENSURE(r.nlayout == 1 && r.layout_checks[0].value == RF_VALUE_SHARE_KEPT);
    /* evaluated once, the verdict printed */
    char *buf = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    long failed = evaluate_to(&t, &r, out);
    fclose(out);
    int passed;
    /* 10 + 30 + 3 + 1 + 1 + 1 + 1 = 47 rockfalls, 10 + 28 + 1 = 39 kept */
    ENSURE(layout_value(&t, "layout_serviceability_share", &passed) == 39.0 / 47.0 && !passed);
    /* B1's own check: 30 + 1 + 1 + 1 interceptions, 28 + 2 within */
    ENSURE(check_value(&t, "B1", "serviceability_share", &passed) == 30.0 / 33.0 && passed);
    ENSURE(failed == (long)dbt_real(rf_store_db(t.s), "SELECT count(*) FROM checks WHERE"
                                                       " passed = 0"));
    /* the verdict printed, with the layout's counts */
    ENSURE_MSG(strstr(buf, "layout: 47 rockfalls, 4 of them across a control line") &&
                   strstr(buf, "kept within serviceability: 39 (83.0 %)") &&
                   strstr(buf, "FAIL layout_serviceability_share 0.8298 >= 0.9"),
               "%s", buf);
    free(buf);
    rf_store_close(t.s);

    /* a run without rockfalls: no value, and it passes as a measure nothing reached */
    scene_open(&t, RF_IMPORTANT, NULL, "layout-empty.db");
    scene_finish(&t);
    ENSURE(evaluate(&t, &r) == 0);
    ENSURE(dbt_real(rf_store_db(t.s), "SELECT count(*) FROM checks WHERE measure_id IS NULL AND"
                                      " value IS NULL AND passed = 1 AND on_failure = 'fail'")
           == 1.0);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* Denies reading the classifications' limit states, which only the layout's count reads
 * before the verdict is printed. */
static int deny_limit_state(void *ctx, int action, const char *table, const char *column,
                            const char *db, const char *trigger)
{
    (void)ctx, (void)db, (void)trigger;
    return action == SQLITE_READ && table && column && !strcmp(table, "classifications") &&
                   !strcmp(column, "limit_state")
               ? SQLITE_DENY
               : SQLITE_OK;
}

/* A failed count says which count failed, and the run's earlier checks stay. */
TEST(rules_layout_count_failure_names_the_count)
{
    scene t;
    scene_open(&t, RF_IMPORTANT, NULL, "layout-denied.db");
    hits(&t, 1, M_B1, 3, 3);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    sqlite3 *db = rf_store_db(t.s);
    evaluate(&t, &r);
    const char *checks = "SELECT count(*) FROM checks";
    const char *classes = "SELECT count(*) FROM classifications";
    double checks_before = dbt_real(db, "%s", checks);
    ENSURE(checks_before >= 1.0 && dbt_real(db, "%s", classes) == 3.0);
    sqlite3_set_authorizer(db, deny_limit_state, NULL);
    rf_error err = {{0}};
    ENSURE(rf_rules_evaluate(db, t.run, &r, NULL, NULL, &err) != 0);
    ENSURE_MSG(strstr(err.message, "counting the rockfalls the layout keeps"), "%s", err.message);
    sqlite3_set_authorizer(db, NULL, NULL);
    ENSURE(dbt_real(db, "%s", checks) == checks_before && dbt_real(db, "%s", classes) == 3.0);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* 92 % within serviceability passes, 88 % fails. */
TEST(rules_serviceability_92_passes_88_fails)
{
    scene t;
    scene_open(&t, RF_USUAL, NULL, "share.db");
    hits(&t, 2, M_B1, 50, 46);
    hits(&t, 2, M_B2, 50, 44);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    ENSURE(evaluate(&t, &r) == 1);
    int passed;
    ENSURE(check_value(&t, "B1", "serviceability_share", &passed) == 46.0 / 50.0 && passed);
    ENSURE(check_value(&t, "B2", "serviceability_share", &passed) == 44.0 / 50.0 && !passed);
    /* level 2, usual: ultimate required; every energy is within MEL */
    ENSURE(check_value(&t, "B1", "required_state", &passed) == 1.0 && passed);
    ENSURE(check_value(&t, "B2", "required_state", &passed) == 1.0 && passed);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* Exactly 90 %: passes with ">=" (table3.yaml), fails with ">". */
TEST(rules_exactly_90_percent)
{
    scene t;
    scene_open(&t, RF_USUAL, NULL, "ninety.db");
    hits(&t, 2, M_B1, 50, 45);
    hits(&t, 1, M_B2, 200, 180);
    scene_finish(&t);
    rf_rules at_least, over;
    load_rules(TABLE3, &at_least);
    load_variant("comparison: \">=\"\n    threshold: 0.9", "comparison: \">\"\n    threshold: 0.9",
                 &over);
    int passed;
    evaluate(&t, &at_least);
    ENSURE(check_value(&t, "B1", "serviceability_share", &passed) == 0.9 && passed);
    ENSURE(check_value(&t, "B2", "serviceability_share", &passed) == 0.9 && passed);
    evaluate(&t, &over);
    ENSURE(check_value(&t, "B1", "serviceability_share", &passed) == 0.9 && !passed);
    ENSURE(check_value(&t, "B2", "serviceability_share", &passed) == 0.9 && !passed);
    rf_rules_free(&at_least);
    rf_rules_free(&over);
    rf_store_close(t.s);
}

TEST(rules_overtopping_is_never_serviceable)
{
    scene t;
    scene_open(&t, RF_USUAL, NULL, "over.db");
    hits(&t, 2, M_B1, 9, 9);
    hit(&t, 2, M_B1, 0.5, RF_OUT_OVERTOPPED); /* a tiny energy, over the top */
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    ENSURE(evaluate(&t, &r) == 1);
    sqlite3 *db = rf_store_db(t.s);
    ENSURE(dbt_real(db, "SELECT count(*) FROM classifications c JOIN interceptions i"
                          " ON i.id = c.interception_id WHERE i.outcome = 'overtopped'"
                          " AND c.limit_state = 'overtopped' AND c.ok = 0") == 1.0);
    int passed;
    /* 9 of 10: below 90 % only because the overtopping is not serviceable */
    ENSURE(check_value(&t, "B1", "serviceability_share", &passed) == 0.9 && passed);
    ENSURE(check_value(&t, "B1", "required_state", &passed) == 0.9 && !passed);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* Required states by level and importance, written per interception. */
TEST(rules_required_state_per_interception)
{
    scene t;
    scene_open(&t, RF_IMPORTANT, NULL, "required.db");
    /* E1 (3000/6000/9000/12000 kJ), important: level 1 serviceability, 2 restorability,
     * 3 ultimate */
    hit(&t, 1, M_E1, 2500.0, RF_OUT_STOPPED);       /* serviceability, ok */
    hit(&t, 1, M_E1, 3500.0, RF_OUT_STOPPED);       /* restorability, not ok */
    hit(&t, 2, M_E1, 5500.0, RF_OUT_STOPPED);       /* restorability, ok */
    hit(&t, 3, M_E1, 8500.0, RF_OUT_STOPPED);       /* ultimate, ok */
    hit(&t, 3, M_E1, 11000.0, RF_OUT_STOPPED);      /* near collapse, not ok */
    hit(&t, 3, M_E1, 15000.0, RF_OUT_BROKE_THROUGH); /* collapse, not ok */
    hit(&t, 1, M_ROAD, 15000.0, RF_OUT_PASSED);     /* control lines are not classified */
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    evaluate(&t, &r);
    sqlite3 *db = rf_store_db(t.s);
    sqlite3_stmt *st;
    ENSURE(sqlite3_prepare_v2(db,
                              "SELECT c.action_level, c.importance, c.limit_state,"
                              " c.required_state, c.ok FROM classifications c"
                              " JOIN interceptions i ON i.id = c.interception_id"
                              " ORDER BY i.id",
                              -1, &st, NULL) == SQLITE_OK);
    static const struct {
        int level;
        const char *state, *required;
        int ok;
    } want[] = {
        {1, "serviceability", "serviceability", 1}, {1, "restorability", "serviceability", 0},
        {2, "restorability", "restorability", 1},   {3, "ultimate", "ultimate", 1},
        {3, "near_collapse", "ultimate", 0},        {3, "collapse", "ultimate", 0},
    };
    for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
        ENSURE(sqlite3_step(st) == SQLITE_ROW);
        ENSURE(sqlite3_column_int(st, 0) == want[i].level);
        ENSURE(!strcmp((const char *)sqlite3_column_text(st, 1), "important"));
        ENSURE_MSG(!strcmp((const char *)sqlite3_column_text(st, 2), want[i].state), "%zu: %s",
                   i, (const char *)sqlite3_column_text(st, 2));
        ENSURE(!strcmp((const char *)sqlite3_column_text(st, 3), want[i].required));
        ENSURE(sqlite3_column_int(st, 4) == want[i].ok);
    }
    ENSURE(sqlite3_step(st) == SQLITE_DONE); /* nothing for the road */
    sqlite3_finalize(st);
    int passed;
    ENSURE(check_value(&t, "E1", "required_state", &passed) == 3.0 / 6.0 && !passed);
    ENSURE(check_value(&t, "E1", "serviceability_share", &passed) == 1.0 / 6.0 && !passed);
    ENSURE(dbt_real(db, "SELECT count(*) FROM checks c JOIN measures m ON m.id = c.measure_id"
                          " WHERE m.kind = 'control'") == 0.0);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* An interception without an energy reaches no limit state and counts against the
 * share; the measure_summary view agrees with the check (it left it out: 9 of 9). */
TEST(rules_interception_without_energy_counts_against_the_share)
{
    scene t;
    scene_open(&t, RF_IMPORTANT, NULL, "noenergy.db");
    hits(&t, 1, M_B1, 9, 9);
    hit(&t, 1, M_B1, NAN, RF_OUT_STOPPED);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    evaluate(&t, &r);
    sqlite3 *db = rf_store_db(t.s);
    ENSURE(dbt_real(db, "SELECT count(*) FROM interceptions WHERE energy_kj IS NULL") == 1.0);
    int passed;
    double stored = check_value(&t, "B1", "serviceability_share", &passed);
    ENSURE(stored == 0.9 && passed);
    ensure_views_share(db, stored);
    /* a measure no check has classified yet has no share */
    ENSURE(isnan(dbt_real(db, "SELECT share_serviceability FROM measure_summary WHERE"
                                " measure = 'road'")));
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* The stored fraction is a plain count over classifications; re-evaluating replaces. */
TEST(rules_stored_fraction_equals_sql_count_and_is_idempotent)
{
    scene t;
    scene_open(&t, RF_MOST_IMPORTANT, NULL, "count.db");
    hits(&t, 1, M_B1, 37, 31);
    hits(&t, 3, M_B1, 11, 10);
    hit(&t, 2, M_B1, 25.0, RF_OUT_OVERTOPPED);
    hits(&t, 2, M_E1, 23, 23);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    sqlite3 *db = rf_store_db(t.s);
    for (int round = 0; round < 3; round++) {
        evaluate(&t, &r);
        ENSURE(dbt_real(db, "SELECT count(*) FROM classifications") == 37 + 11 + 1 + 23);
        /* B1 B2 E1 B3, the layout's, and the three integrity checks */
        ENSURE(dbt_real(db, "SELECT count(*) FROM checks") == 2.0 * 4 + 1 + 3);
    }
    int passed;
    double stored = check_value(&t, "B1", "serviceability_share", &passed);
    double counted = dbt_real(db,
                                "SELECT (SELECT count(*) FROM classifications c JOIN interceptions"
                                " i ON i.id = c.interception_id JOIN measures m ON m.id ="
                                " i.measure_id WHERE m.name = 'B1' AND c.limit_state ="
                                " 'serviceability') * 1.0 / (SELECT count(*) FROM"
                                " interceptions i JOIN measures m ON m.id = i.measure_id"
                                " WHERE m.name = 'B1')");
    ENSURE(stored == counted && stored == 41.0 / 49.0 && !passed);
    double meeting = check_value(&t, "B1", "required_state", &passed);
    ENSURE(meeting == dbt_real(db, "SELECT avg(c.ok) FROM classifications c JOIN"
                                     " interceptions i ON i.id = c.interception_id JOIN measures"
                                     " m ON m.id = i.measure_id WHERE m.name = 'B1'"));
    /* 72 rockfalls; 6 + 1 beyond serviceability at B1 and one over it */
    ENSURE(layout_value(&t, "layout_serviceability_share", &passed) == 64.0 / 72.0 && !passed);
    /* the views agree */
    ensure_views_share(db, stored);
    ENSURE(dbt_real(db, "SELECT interceptions FROM measure_summary WHERE measure = 'B1'") ==
           49.0);
    ENSURE(dbt_real(db, "SELECT checks_failed FROM run_verdicts") == 3.0); /* B1's, layout */
    ENSURE(dbt_real(db, "SELECT verdict = 'fail' FROM run_verdicts") == 1.0);
    ENSURE(dbt_real(db, "SELECT count(*) FROM check_results WHERE verdict = 'fail'") == 3.0);
    ENSURE(dbt_real(db, "SELECT count(*) FROM check_results WHERE measure IS NULL AND rule ="
                          " 'layout_serviceability_share' AND verdict = 'fail'") == 1.0);
    ENSURE(dbt_real(db, "SELECT count(*) FROM classified_interceptions WHERE measure = 'B1'"
                          " AND ok = 0") == 8.0);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* A measure no rock reaches: its checks are recorded with value NULL and pass (the
 * rule file's no_interceptions); with `no_interceptions: fail` they fail. */
TEST(rules_measure_without_interceptions)
{
    scene t;
    scene_open(&t, RF_IMPORTANT, NULL, "empty.db");
    hits(&t, 1, M_B1, 10, 10);
    scene_finish(&t);
    rf_rules r, strict;
    load_rules(TABLE3, &r);
    load_variant("no_interceptions: pass", "no_interceptions: fail", &strict);
    ENSURE(evaluate(&t, &r) == 0);
    int passed;
    ENSURE(isnan(check_value(&t, "B3", "serviceability_share", &passed)) && passed);
    ENSURE(isnan(check_value(&t, "B3", "required_state", &passed)) && passed);
    ENSURE(evaluate(&t, &strict) == 3 * 2); /* B2, E1, B3 */
    ENSURE(isnan(check_value(&t, "B3", "required_state", &passed)) && !passed);
    rf_rules_free(&r);
    rf_rules_free(&strict);
    rf_store_close(t.s);
}

/* SEL from the rule file when the project gives none; the project's sel otherwise.
 * A rule file without sel_default gives a barrier without sel no SEL, also when it
 * takes the barrier's serviceability capacity from the project (the loader's MEL / 3
 * in sel_kj and cap_serviceability_kj is not the project's). */
TEST(rules_sel_default_lives_in_the_rule_file)
{
    static const char yaml[] = "name: constructed\n"
                               "measures:\n"
                               "  - {name: B1, kind: barrier, mel: 3000, height: 5}\n"
                               "  - {name: B2, kind: barrier, mel: 3000, sel: 1000, height: 5}\n"
                               "  - {name: B3, kind: barrier, mel: 3000, height: 5}\n";
    scene t;
    scene_init(&t, RF_USUAL, yaml);
    /* as the loader leaves B1 and B3: SEL = MEL / 3, marked as the default */
    t.measures[M_B1].sel_given = t.measures[M_B3].sel_given = 0;
    scene_begin(&t, rf_test_path("sel.db"));
    hit(&t, 2, M_B1, 1250.0, RF_OUT_STOPPED);
    hit(&t, 2, M_B2, 1250.0, RF_OUT_STOPPED);
    hit(&t, 2, M_B3, 800.0, RF_OUT_STOPPED);
    scene_finish(&t);
    rf_rules half;
    load_variant("{mel_divided_by: 3}", "{mel_divided_by: 2}", &half);
    evaluate(&t, &half);
    sqlite3 *db = rf_store_db(t.s);
    const char *q = "SELECT c.limit_state = 'serviceability' FROM classifications c JOIN"
                    " interceptions i ON i.id = c.interception_id JOIN measures m ON m.id ="
                    " i.measure_id WHERE m.name = '%s'";
    ENSURE(dbt_real(db, q, "B1") == 1.0); /* SEL = 3000 / 2 */
    ENSURE(dbt_real(db, q, "B2") == 0.0); /* the project's sel = 1000 */
    rf_rules r;
    load_rules(TABLE3, &r);
    evaluate(&t, &r);
    ENSURE(dbt_real(db, q, "B1") == 0.0); /* SEL = 3000 / 3 */
    ENSURE(dbt_real(db, q, "B3") == 1.0); /* 800 within SEL = 3000 / 3 */
    static const char sel_rules[] =
        "    serviceability: sel\n"
        "    restorability: project   # when the project gives one (between SEL and MEL)\n"
        "    ultimate: mel\n"
        "    # SEL = MEL / 3 unless the project gives sel (ETAG 027 / EAD 340059-00-0106).\n"
        "    sel_default: {mel_divided_by: 3}\n";
    const char *no_default[2] = {"    serviceability: sel\n    ultimate: mel\n",
                                 "    serviceability: project\n    ultimate: mel\n"};
    const char *ultimate = "SELECT c.limit_state = 'ultimate' FROM classifications c JOIN"
                           " interceptions i ON i.id = c.interception_id JOIN measures m ON"
                           " m.id = i.measure_id WHERE m.name = 'B3'";
    for (int k = 0; k < 2; k++) {
        rf_rules none;
        load_variant(sel_rules, no_default[k], &none);
        evaluate(&t, &none);
        ENSURE_MSG(dbt_int(db, "%s", ultimate) == 1, "%s: B3 at 800 kJ not at ultimate",
                   no_default[k]);
        rf_rules_free(&none);
    }
    /* the database, not the project text, says whether SEL was given: B1 marked as
     * given keeps its stored SEL = 1000 under the rule file's MEL / 2 */
    ENSURE(sqlite3_exec(db, "UPDATE measures SET sel_source = 'given' WHERE name = 'B1'", NULL,
                        NULL, NULL) == SQLITE_OK);
    evaluate(&t, &half);
    ENSURE(dbt_real(db, q, "B1") == 0.0);
    ENSURE(sqlite3_exec(db, "UPDATE measures SET sel_source = 'default: MEL/3' WHERE name = 'B2'",
                        NULL, NULL, NULL) == SQLITE_OK);
    evaluate(&t, &half);
    ENSURE(dbt_real(db, q, "B2") == 1.0); /* 1250 within SEL = 3000 / 2 */
    rf_rules_free(&half);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

TEST(rules_views_added_to_an_older_database)
{
    const char *path = rf_test_path("old.db");
    rf_store *s;
    rf_error err = {{0}};
    ENSURE(rf_store_open(path, &s, &err) == 0);
    static const char *const views[] = {"classified_interceptions", "measure_summary",
                                        "limit_state_shares", "check_results", "run_verdicts"};
    for (int i = 0; i < 5; i++) {
        char sql[128];
        snprintf(sql, sizeof sql, "DROP VIEW %s", views[i]);
        ENSURE_MSG(sqlite3_exec(rf_store_db(s), sql, NULL, NULL, NULL) == SQLITE_OK, "%s",
                   views[i]);
    }
    ENSURE(dbt_real(rf_store_db(s), "SELECT count(*) FROM sqlite_master WHERE type = 'view'")
           == 0.0);
    rf_store_close(s);
    ENSURE(rf_store_open(path, &s, &err) == 0);
    ENSURE(dbt_real(rf_store_db(s), "SELECT count(*) FROM sqlite_master WHERE type = 'view'")
           == 5.0);
    rf_store_close(s);
}

TEST(rules_path_of_run)
{
    scene t;
    scene_init(&t, RF_USUAL, "name: x\nrules: ../../rules/table3.yaml\n");
    t.p.path = "projects/site/site.yaml";
    t.p.rules_path = "projects/site/../../rules/table3.yaml"; /* as the loader resolves it */
    scene_begin(&t, rf_test_path("path.db"));
    scene_finish(&t);
    char *path = NULL;
    rf_error err = {{0}};
    ENSURE(rf_rules_path_of_run(rf_store_db(t.s), t.run, &path, &err) == 0);
    ENSURE_MSG(!strcmp(path, "projects/site/../../rules/table3.yaml"), "%s", path);
    free(path);
    rf_store_close(t.s);

    /* the stored path, not the project text, names the rule file */
    scene_open(&t, RF_USUAL, "name: x\nrules: ../../rules/table3.yaml\n", "path2.db");
    scene_finish(&t);
    ENSURE(rf_rules_path_of_run(rf_store_db(t.s), t.run, &path, &err) != 0);
    ENSURE(path == NULL && strstr(err.message, "--rules"));
    rf_store_close(t.s);
}

/* ---- verdict integrity ------------------------------------------------------------- */

TEST(rules_allowance_defaults_and_keys)
{
    rf_rules r;
    load_rules(TABLE3, &r);
    ENSURE(r.allowance[RF_INTEGRITY_MAX_TIME] == 0.0);
    ENSURE(r.allowance[RF_INTEGRITY_LEFT_TERRAIN] == 0.01);
    ENSURE(r.allowance[RF_INTEGRITY_REST_STEEP] == 0.0);
    rf_rules_free(&r);
    /* the defaults, without the block: those table3.yaml states */
    load_allowance("", &r);
    ENSURE(r.allowance[RF_INTEGRITY_MAX_TIME] == RF_ALLOWANCE_MAX_TIME);
    ENSURE(r.allowance[RF_INTEGRITY_LEFT_TERRAIN] == RF_ALLOWANCE_LEFT_TERRAIN);
    ENSURE(r.allowance[RF_INTEGRITY_REST_STEEP] == RF_ALLOWANCE_REST_STEEP);
    ENSURE(RF_ALLOWANCE_MAX_TIME == 0.0 && RF_ALLOWANCE_LEFT_TERRAIN == 0.01 &&
           RF_ALLOWANCE_REST_STEEP == 0.0);
    rf_rules_free(&r);
    /* each key on its own; the others keep their defaults */
    load_allowance("allowance: {max_time: 0.05}\n", &r);
    ENSURE(r.allowance[RF_INTEGRITY_MAX_TIME] == 0.05);
    ENSURE(r.allowance[RF_INTEGRITY_LEFT_TERRAIN] == 0.01);
    ENSURE(r.allowance[RF_INTEGRITY_REST_STEEP] == 0.0);
    rf_rules_free(&r);
    load_allowance("allowance: {left_terrain: 0, rest_on_steep_face: 0.5}\n", &r);
    ENSURE(r.allowance[RF_INTEGRITY_LEFT_TERRAIN] == 0.0);
    ENSURE(r.allowance[RF_INTEGRITY_REST_STEEP] == 0.5);
    rf_rules_free(&r);
    /* the boundary: count / n equal to the allowance is within it */
    ENSURE(rf_rules_within_allowance(5, 500, 0.01) && !rf_rules_within_allowance(6, 500, 0.01));
    ENSURE(rf_rules_within_allowance(0, 500, 0.0) && !rf_rules_within_allowance(1, 500, 0.0));
    ENSURE(rf_rules_within_allowance(1, 0, 0.0));
    for (long n = 100; n <= 100000; n *= 10)
        ENSURE(rf_rules_within_allowance(n / 100, n, 0.01) &&
               !rf_rules_within_allowance(n / 100 + 1, n, 0.01));
}

/* One trajectory of the release of `level` that ended for `reason`, across the road
 * (a control line) or not, at rest on a steep face or not. */
static void ending(scene *t, int level, rf_stop_reason reason, int across_road, int steep)
{
    rf_error err = {{0}};
    rf_trajectory_record tr = {.stop = {5.0, 5.0, 80.0}, .reason = reason, .duration_s = 3.0,
                               .rest_on_steep_face = steep};
    int64_t id;
    ENSURE(rf_store_add_trajectory(t->s, (size_t)(level - 1), t->next_idx[level - 1]++, &tr,
                                   &id, &err) == 0);
    if (!across_road)
        return;
    rf_interception_record in = {.measure = M_ROAD, .t_s = 2.0, .p = {20.0, 10.25, 82.0},
                                 .speed_ms = 20.0, .energy_kj = 300.0, .energy_trans_kj = 300.0,
                                 .passing_height_m = 1.0, .outcome = RF_OUT_PASSED};
    ENSURE_MSG(rf_store_add_interception(t->s, id, &in, NULL, &err) == 0, "%s", err.message);
}

/* Evaluates the run into res, the printout into a string (malloc'd) */
static char *evaluate_verdict(scene *t, const rf_rules *r, rf_rules_result *res)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    ENSURE(out);
    rf_error err = {{0}};
    ENSURE_MSG(rf_rules_evaluate_verdict(rf_store_db(t->s), t->run, r, out, res, &err) == 0,
               "%s", err.message);
    fclose(out);
    return buf;
}

/* A layout whose design checks all pass: 48 of 50 rocks within serviceability at B1,
 * 20 of 20 at E1, and `rest` trajectories at rest on the slope. */
static void passing_layout(scene *t, const char *db, int rest)
{
    scene_open(t, RF_USUAL, NULL, db);
    hits(t, 2, M_B1, 50, 48);
    hits(t, 2, M_E1, 20, 20);
    for (int i = 0; i < rest; i++)
        ending(t, 1, RF_END_REST, 0, 0);
}

/* The verdict stored for the run: in run_verdicts and, for integrity check `rule`,
 * in checks and check_results. */
static void ensure_stored(scene *t, const char *verdict, const char *rule, double value,
                          int passed)
{
    sqlite3 *db = rf_store_db(t->s);
    ENSURE_MSG(dbt_int(db, "SELECT verdict = '%s' FROM run_verdicts WHERE run_id = %lld",
                       verdict, (long long)t->run) == 1,
               "run_verdicts does not say %s", verdict);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks WHERE run_id = %lld AND rule = '%s' AND"
                       " measure_id IS NULL AND on_failure = 'inconclusive' AND passed = %d",
                   (long long)t->run, rule, passed) == 1);
    ENSURE(dbt_real(db, "SELECT value FROM checks WHERE run_id = %lld AND rule = '%s'",
                    (long long)t->run, rule) == value);
    ENSURE(dbt_int(db, "SELECT verdict = '%s' FROM check_results WHERE rule = '%s'",
                   passed ? "pass" : "inconclusive", rule) == 1);
}

/* Trajectories cut short by max_time say nothing of where the rocks would have gone:
 * a layout whose design checks pass is not a PASS then. */
TEST(rules_max_time_trajectories_make_a_pass_inconclusive)
{
    scene t;
    passing_layout(&t, "max-time.db", 29);
    ending(&t, 1, RF_END_MAX_TIME, 0, 0);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    rf_rules_result res;
    char *buf = evaluate_verdict(&t, &r, &res);
    ENSURE_MSG(res.verdict == RF_VERDICT_INCONCLUSIVE && res.failed == 0 &&
                   res.inconclusive == 1, "%s", buf);
    ENSURE_MSG(strstr(buf, "verdict: INCONCLUSIVE") && !strstr(buf, "verdict: PASS") &&
                   strstr(buf, "INCONCLUSIVE trajectories_max_time") &&
                   strstr(buf, "1 of 100 trajectories ended by max_time") &&
                   strstr(buf, "simulation.max_time"),
               "%s", buf);
    free(buf);
    ensure_stored(&t, "inconclusive", "trajectories_max_time", 0.01, 0);
    ENSURE(dbt_int(rf_store_db(t.s), "SELECT checks_failed = 0 AND checks_inconclusive = 1"
                                     " FROM run_verdicts") == 1);
    /* the rule file may allow them */
    rf_rules_free(&r);
    load_allowance("allowance: {max_time: 0.01}\n", &r);
    buf = evaluate_verdict(&t, &r, &res);
    ENSURE_MSG(res.verdict == RF_VERDICT_PASS && strstr(buf, "verdict: PASS"), "%s", buf);
    free(buf);
    ensure_stored(&t, "pass", "trajectories_max_time", 0.01, 1);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* A rock that left the terrain before any control line may have reached the road past
 * the terrain's edge: 1 % of the trajectories is allowed by default, one more is not;
 * one that crossed the road before it left is no such rock. */
TEST(rules_left_terrain_before_a_control_line_beyond_the_allowance_is_inconclusive)
{
    rf_rules r;
    load_rules(TABLE3, &r);
    for (int over = 0; over <= 1; over++) {
        scene t;
        passing_layout(&t, over ? "left-over.db" : "left-within.db", 24 - over);
        /* 100 trajectories: 70 hits, 24 or 23 at rest, 5 across the road and gone, and
         * 1 or 2 gone before any control line */
        for (int i = 0; i < 5; i++)
            ending(&t, 3, RF_END_EXITED, 1, 0);
        for (int i = 0; i < 1 + over; i++)
            ending(&t, 3, RF_END_EXITED, 0, 0);
        scene_finish(&t);
        rf_rules_result res;
        char *buf = evaluate_verdict(&t, &r, &res);
        ENSURE(dbt_int(rf_store_db(t.s), "SELECT count(*) FROM trajectories") == 100);
        if (!over) {
            ENSURE_MSG(res.verdict == RF_VERDICT_PASS && strstr(buf, "verdict: PASS"), "%s", buf);
            ENSURE_MSG(strstr(buf, "PASS trajectories_left_terrain       1 left the terrain"
                                   " before any control line (0.0100 <= allowance 0.01)"),
                       "%s", buf);
            ensure_stored(&t, "pass", "trajectories_left_terrain", 0.01, 1);
        } else {
            ENSURE_MSG(res.verdict == RF_VERDICT_INCONCLUSIVE &&
                           strstr(buf, "verdict: INCONCLUSIVE") &&
                           strstr(buf, "2 of 100 trajectories left the terrain before any "
                                       "control line"),
                       "%s", buf);
            ensure_stored(&t, "inconclusive", "trajectories_left_terrain", 0.02, 0);
        }
        free(buf);
        rf_store_close(t.s);
    }
    rf_rules_free(&r);
}

/* A rock the fixed-step engine put to rest on a face steeper than its friction holds
 * would have moved on: none is allowed by default. */
TEST(rules_rest_on_a_steep_face_is_inconclusive)
{
    scene t;
    passing_layout(&t, "steep.db", 29);
    ending(&t, 1, RF_END_REST, 0, 1);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    rf_rules_result res;
    char *buf = evaluate_verdict(&t, &r, &res);
    ENSURE_MSG(res.verdict == RF_VERDICT_INCONCLUSIVE &&
                   strstr(buf, "1 of 100 trajectories came to rest on a face steeper than "
                               "their friction holds"),
               "%s", buf);
    free(buf);
    ensure_stored(&t, "inconclusive", "trajectories_rest_on_steep_face", 0.01, 0);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* A run beyond an allowance is INCONCLUSIVE also when a design check fails on it (the
 * unsupported trajectories may be what failed it): the failed checks and the reasons
 * are printed with the verdict. */
TEST(rules_inconclusive_wins_over_a_failed_check)
{
    scene t;
    scene_open(&t, RF_USUAL, NULL, "fail-and-max-time.db");
    hits(&t, 2, M_B1, 50, 40);
    ending(&t, 1, RF_END_MAX_TIME, 0, 0);
    scene_finish(&t);
    rf_rules r;
    load_rules(TABLE3, &r);
    rf_rules_result res;
    char *buf = evaluate_verdict(&t, &r, &res);
    ENSURE_MSG(res.verdict == RF_VERDICT_INCONCLUSIVE && res.failed == 2 && res.inconclusive == 1,
               "%s", buf);
    ENSURE_MSG(strstr(buf, "verdict: INCONCLUSIVE (2 of 9 checks failed, on trajectories that "
                           "cannot support a verdict)") &&
                   strstr(buf, "1 of 51 trajectories ended by max_time") && !strstr(buf, "FAIL ("),
               "%s", buf);
    free(buf);
    ensure_stored(&t, "inconclusive", "trajectories_max_time", 1.0 / 51.0, 0);
    ENSURE(dbt_int(rf_store_db(t.s), "SELECT checks_failed = 2 AND checks_inconclusive = 1"
                                     " AND verdict = 'inconclusive' FROM run_verdicts") == 1);
    rf_rules_free(&r);
    rf_store_close(t.s);
}

/* A copy of the version-2 fixture as `name`, changed by `sql` (when not NULL) and opened
 * as check opens it. */
static sqlite3 *copy_v2_for_check(const char *name, const char *sql)
{
    const char *path = rf_test_path(name);
    FILE *in = fopen("tests/data/results-v2.db", "rb"), *out = fopen(path, "wb");
    ENSURE(in && out);
    char chunk[65536];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, in)) > 0)
        ENSURE(fwrite(chunk, 1, n, out) == n);
    fclose(in);
    fclose(out);
    sqlite3 *db;
    if (sql) {
        ENSURE(sqlite3_open(path, &db) == SQLITE_OK);
        ENSURE(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK);
        sqlite3_close(db);
    }
    rf_error err = {{0}};
    ENSURE_MSG(rf_db_open(path, RF_DB_CHECK, &db, NULL, &err) == 0, "%s", err.message);
    return db;
}

/* The verdict of run 1 under r, and what check prints of it (malloc'd). */
static char *verdict_of_run_1(sqlite3 *db, const rf_rules *r, rf_rules_result *res)
{
    char *text = NULL;
    size_t len = 0;
    rf_error err = {{0}};
    FILE *pr = open_memstream(&text, &len);
    ENSURE_MSG(rf_rules_evaluate_verdict(db, 1, r, pr, res, &err) == 0, "%s", err.message);
    fclose(pr);
    return text;
}

/* check writes into a file of schema version 2 without upgrading it: the integrity
 * checks are rows of its checks table as it is, and a rest on a steep face, which
 * version 2 did not record, is not counted. */
TEST(rules_integrity_checked_in_a_version_2_file)
{
    sqlite3 *db = copy_v2_for_check("v2.db", NULL);
    rf_rules r;
    load_rules(TABLE3, &r);
    rf_rules_result res;
    char *text = verdict_of_run_1(db, &r, &res);
    ENSURE_MSG(res.verdict == RF_VERDICT_FAIL && res.inconclusive == 0, "%s", text);
    ENSURE_MSG(strstr(text, "PASS trajectories_rest_on_steep_face not recorded"), "%s", text);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") == 2);
    ENSURE(dbt_int(db, "SELECT count(*) FROM checks WHERE rule LIKE 'trajectories_%%'") == 3);
    ENSURE(dbt_int(db, "SELECT value IS NULL FROM checks WHERE"
                       " rule = 'trajectories_rest_on_steep_face'") == 1);
    free(text);
    rf_rules_free(&r);
    sqlite3_close(db);
}

/* A fixed-step run written before schema version 3 does not say which of its rocks came
 * to rest on a steep face: such a run supports no PASS (an exact run's, as above, does:
 * that engine never rests a rock so). */
TEST(rules_unrecorded_rests_of_a_fixed_step_run_are_inconclusive)
{
    sqlite3 *db = copy_v2_for_check("v2-fixed.db",
                                    "UPDATE runs SET project_yaml = replace(project_yaml,"
                                    " 'simulation: {', 'simulation: {engine: fixed_step, dt: 0.01, ')");
    ENSURE(dbt_int(db, "SELECT instr(project_yaml, 'engine: fixed_step') > 0 FROM runs") == 1);
    rf_rules r;
    load_rules(TABLE3, &r);
    rf_rules_result res;
    char *text = verdict_of_run_1(db, &r, &res);
    ENSURE_MSG(res.verdict == RF_VERDICT_INCONCLUSIVE && res.inconclusive == 1, "%s", text);
    ENSURE_MSG(strstr(text, "INCONCLUSIVE trajectories_rest_on_steep_face not recorded") &&
                   strstr(text, "a fixed-step run written before schema version 3 does not "
                                "record"),
               "%s", text);
    free(text);
    rf_rules_free(&r);
    sqlite3_close(db);
}

/* ---- the command line -------------------------------------------------------------- */

/* The exit status of `rockfall check` agrees with the stored checks. */
TEST(rules_cli_check_exit_status)
{
    scene t;
    scene_init(&t, RF_USUAL, NULL);
    char pass_db[600], fail_db[600], args[2048];
    static char out[65536];
    snprintf(pass_db, sizeof pass_db, "%s", rf_test_path("pass.db"));
    snprintf(fail_db, sizeof fail_db, "%s", rf_test_path("fail.db"));
    scene_begin(&t, pass_db);
    hits(&t, 2, M_B1, 50, 48);
    hits(&t, 2, M_E1, 20, 20);
    scene_finish(&t);
    rf_store_close(t.s);
    scene_init(&t, RF_USUAL, NULL);
    scene_begin(&t, fail_db);
    hits(&t, 2, M_B1, 50, 48);
    hits(&t, 2, M_B2, 50, 40);
    scene_finish(&t);
    rf_store_close(t.s);

    snprintf(args, sizeof args, "check %s --rules " TABLE3, pass_db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    ENSURE_MSG(strstr(out, "verdict: PASS"), "%s", out);
    ENSURE(strstr(out, "E50") && strstr(out, "h95") && strstr(out, "serviceability 96.0 %"));
    snprintf(args, sizeof args, "check %s --rules " TABLE3, fail_db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 1, "%s", out);
    ENSURE_MSG(strstr(out, "FAIL serviceability_share") && strstr(out, "0.8000 >= 0.9"), "%s",
               out);
    /* the layout: 100 rockfalls, 2 + 10 beyond serviceability */
    ENSURE_MSG(strstr(out, "FAIL layout_serviceability_share 0.8800 >= 0.9"), "%s", out);
    ENSURE(strstr(out, "verdict: FAIL (2 of 9 checks failed)"));
    /* again: same verdict, same rows */
    ENSURE(rf_test_rockfall(args, out, sizeof out) == 1);
    sqlite3 *db;
    ENSURE(sqlite3_open(fail_db, &db) == SQLITE_OK);
    ENSURE(dbt_real(db, "SELECT count(*) FROM checks WHERE on_failure = 'fail'") == 9.0);
    ENSURE(dbt_real(db, "SELECT count(*) FROM checks WHERE passed = 0") == 2.0);
    sqlite3_close(db);
    /* no --rules and no rules in the project; a bad rule file: bad input */
    snprintf(args, sizeof args, "check %s", pass_db);
    ENSURE(rf_test_rockfall(args, out, sizeof out) == 2);
    ENSURE_MSG(strstr(out, "--rules"), "%s", out);
    snprintf(args, sizeof args, "check %s --rules tests/bad_rules/threshold_above_one.yaml",
             pass_db);
    ENSURE(rf_test_rockfall(args, out, sizeof out) == 2);
    ENSURE_MSG(strstr(out, "threshold_above_one.yaml:24:16"), "%s", out);
}

/* A simulated scene: `rockfall run` of a project naming the rules, with one barrier
 * whose MEL gives a serviceable share clearly above 0.9 and one clearly below. */
TEST(rules_end_to_end_simulated_scene)
{
    char rules[700], project[700], db[700], args[2048];
    static char out[65536];
    /* Table 3, allowing every rock to leave the terrain: the profile ends 80 m past the
     * barriers' line, with no road drawn, and this case is about the classification */
    char *table3 = table3_with_allowance("allowance: {left_terrain: 1}\n");
    snprintf(rules, sizeof rules, "%s/rules.yaml", rf_test_tmpdir());
    FILE *rf = fopen(rules, "w");
    ENSURE(rf);
    fputs(table3, rf);
    fclose(rf);
    free(table3);
    snprintf(project, sizeof project, "%s/scene.yaml", rf_test_tmpdir());
    snprintf(db, sizeof db, "%s/scene.db", rf_test_tmpdir());
    /* Both barriers are evaluation lines (collect) on the same line, tall enough that
     * nothing overtops: their interceptions are the same, only the MELs differ. */
    const char *fmt =
        "name: scene\n"
        "seed: 2385\n"
        "terrain:\n"
        "  profile: {points: [[0, 120], [60, 60], [100, 40], [160, 35]], width: 40}\n"
        "  surface: {restitution: {mean: 0.3, sd: 0.1}, friction: {mean: 0.4, sd: 0.1}}\n"
        "rocks:\n"
        "  - {name: r, mass: 1500, action_level: 2}\n"
        "releases:\n"
        "  - {name: top, point: [5, 20], rock: r, count: 200, jitter: 5}\n"
        "measures:\n"
        "  - {name: high, kind: barrier, line: [[80, 0.5], [80, 39.5]], height: 50,"
        " importance: usual, behaviour: collect, mel: %.6f}\n"
        "  - {name: low, kind: barrier, line: [[80, 0.5], [80, 39.5]], height: 50,"
        " importance: usual, behaviour: collect, mel: %.6f}\n"
        "simulation: {paths: 0}\n"
        "rules: %s\n";
    FILE *f = fopen(project, "w");
    ENSURE(f);
    fprintf(f, fmt, 1e7, 1e7, rules);
    fclose(f);
    snprintf(args, sizeof args, "run %s -o %s -q", project, db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);

    /* The energies at the line, to place the MELs. */
    sqlite3 *h;
    ENSURE(sqlite3_open(db, &h) == SQLITE_OK);
    double n = dbt_real(h, "SELECT count(*) FROM interceptions i JOIN measures m ON m.id ="
                             " i.measure_id WHERE m.name = 'high'");
    ENSURE_MSG(n >= 100, "only %g rocks reached the line", n);
    const char *pct = "SELECT energy_kj FROM interceptions i JOIN measures m ON m.id ="
                      " i.measure_id WHERE m.name = 'high' ORDER BY energy_kj LIMIT 1"
                      " OFFSET %d";
    double e97 = dbt_real(h, pct, (int)(0.97 * n));
    double e75 = dbt_real(h, pct, (int)(0.75 * n));
    double emax = dbt_real(h, "SELECT max(energy_kj) FROM interceptions");
    sqlite3_close(h);
    ENSURE(e75 > 0 && e97 > e75);
    double mel_high = 3.0 * e97 > 1.01 * emax ? 3.0 * e97 : 1.01 * emax;
    double mel_low = 3.0 * e75;

    f = fopen(project, "w");
    ENSURE(f);
    fprintf(f, fmt, mel_high, mel_low, rules);
    fclose(f);
    snprintf(args, sizeof args, "run %s -o %s", project, db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 1, "%s", out);
    ENSURE_MSG(strstr(out, "verdict: FAIL"), "%s", out);

    ENSURE(sqlite3_open(db, &h) == SQLITE_OK);
    const char *share = "SELECT k.value FROM checks k JOIN measures m ON m.id = k.measure_id"
                        " WHERE k.run_id = 2 AND m.name = '%s' AND k.rule ="
                        " 'serviceability_share'";
    const char *count = "SELECT avg(c.limit_state = 'serviceability') FROM classifications c"
                        " JOIN interceptions i ON i.id = c.interception_id JOIN measures m"
                        " ON m.id = i.measure_id WHERE i.run_id = 2 AND m.name = '%s'";
    double high = dbt_real(h, share, "high"), low = dbt_real(h, share, "low");
    ENSURE_MSG(high > 0.95 && low < 0.8, "high %g, low %g", high, low);
    ENSURE(high == dbt_real(h, count, "high") && low == dbt_real(h, count, "low"));
    const char *verdict = "SELECT k.passed FROM checks k JOIN measures m ON m.id = k.measure_id"
                          " WHERE k.run_id = 2 AND m.name = '%s' AND k.rule = '%s'";
    ENSURE(dbt_real(h, verdict, "high", "serviceability_share") == 1.0);
    ENSURE(dbt_real(h, verdict, "high", "required_state") == 1.0);
    ENSURE(dbt_real(h, verdict, "low", "serviceability_share") == 0.0);
    sqlite3_close(h);

    /* check agrees: by default with the project's rules, and for the first run */
    snprintf(args, sizeof args, "check %s", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 1, "%s", out);
    snprintf(args, sizeof args, "check %s --run 1", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
}
