/* test_noto.c - the Noto case study end to end on a reduced run: the paper's
 * qualitative findings (section 3.1, Fig. 10) and the layout check of section 3.3. */
#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "check/rules.h"
#include "results/store.h"
#include "db_test_util.h"
#include "test.h"

static void run_into(const char *yaml, const char *db, long count)
{
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s: %s", err.file, err.message);
    for (size_t i = 0; i < p.nreleases; i++)
        p.releases[i].count = count;
    rf_store *s;
    ENSURE(rf_store_open(db, &s, &err) == 0);
    rf_run_options o = {.threads = 2};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    rf_store_close(s);
    rf_project_free(&p);
}

/* Arrivals at the road (first crossing of the control line per trajectory). */
#define ARRIVALS                                                                        \
    "(SELECT i.x AS x, i.speed_ms AS v FROM interceptions i JOIN measures m ON "        \
    "m.id = i.measure_id WHERE m.name = 'road' AND i.t_s = (SELECT min(t_s) FROM "      \
    "interceptions j WHERE j.trajectory_id = i.trajectory_id AND j.measure_id = i.measure_id))"

TEST(noto_trees_widen_the_spread_and_slow_the_rocks)
{
    const long n = 60;
    char a[600], b[600];
    snprintf(a, sizeof a, "%s/no-trees.db", rf_test_tmpdir());
    snprintf(b, sizeof b, "%s/trees.db", rf_test_tmpdir());
    run_into("projects/noto/noto-3.1-no-trees.yaml", a, n);
    run_into("projects/noto/noto-3.1-trees.yaml", b, n);
    sqlite3 *ha, *hb;
    ENSURE(sqlite3_open(a, &ha) == SQLITE_OK && sqlite3_open(b, &hb) == SQLITE_OK);
    /* without trees every rockfall reaches the road, in a narrow band */
    ENSURE(dbt_real(ha, "SELECT count(*) FROM " ARRIVALS) == n);
    double width0 = dbt_real(ha, "SELECT max(x) - min(x) FROM " ARRIVALS);
    ENSURE_MSG(width0 < 15.0, "arrival band %.1f m wide without trees", width0);
    /* with trees: markedly wider spread, lower mean velocity */
    double sd0 = dbt_real(ha, "SELECT sqrt(avg(x * x) - avg(x) * avg(x)) FROM " ARRIVALS);
    double sd1 = dbt_real(hb, "SELECT sqrt(avg(x * x) - avg(x) * avg(x)) FROM " ARRIVALS);
    double v0 = dbt_real(ha, "SELECT avg(v) FROM " ARRIVALS), v1 = dbt_real(hb, "SELECT avg(v) FROM " ARRIVALS);
    ENSURE_MSG(sd1 > 3.0 * sd0, "spread sd %.2f m with trees vs %.2f m without", sd1, sd0);
    ENSURE_MSG(v1 < 0.8 * v0, "mean speed %.1f m/s with trees vs %.1f m/s without", v1, v0);
    ENSURE(dbt_real(hb, "SELECT count(*) FROM tree_hits") > 0);
    ENSURE(dbt_real(hb, "SELECT sum(n_tree_hits) FROM trajectories") ==
           dbt_real(hb, "SELECT count(*) FROM tree_hits"));
    /* the paper's crosscheck: no trees, max velocity near Eq. 1's 47 m/s, on the safe side */
    double vmax = dbt_real(ha, "SELECT max(v) FROM " ARRIVALS);
    ENSURE_MSG(vmax > 30.0 && vmax < 50.0, "max arrival speed %.1f m/s", vmax);
    sqlite3_close(ha);
    sqlite3_close(hb);
}

/* The share of the trajectories that cross no road and, at every structure they meet,
 * stay within one of `states` (an SQL list), counted here independently of rules.c. */
static double kept_share(sqlite3 *h, const char *states)
{
    return dbt_real(h, "SELECT 1.0 * sum(NOT EXISTS (SELECT 1 FROM interceptions i JOIN measures m"
                       " ON m.id = i.measure_id LEFT JOIN classifications c ON"
                       " c.interception_id = i.id WHERE i.trajectory_id = t.id AND (m.name ="
                       " 'road' OR coalesce(c.limit_state, '') NOT IN (%s)))) / count(*) FROM"
                       " trajectories t",
                    states);
}

TEST(noto_layout_checked_and_stored)
{
    char a[600];
    snprintf(a, sizeof a, "%s/layout.db", rf_test_tmpdir());
    run_into("projects/noto/noto-3.3.yaml", a, 40);
    static char out[65536];
    char args[700];
    snprintf(args, sizeof args, "check %s", a);
    int status = rf_test_rockfall(args, out, sizeof out);
    /* the layout of projects/noto passes: what the README reports */
    ENSURE_MSG(status == 0, "%s", out);
    ENSURE_MSG(strstr(out, "verdict: PASS"), "%s", out);
    sqlite3 *h;
    ENSURE(sqlite3_open(a, &h) == SQLITE_OK);
    /* two checks for each of the barrier and the embankment, none for the control
     * line, and the layout's; and the three integrity checks of the run */
    ENSURE(dbt_real(h, "SELECT count(*) FROM checks WHERE on_failure = 'fail'") == 5);
    ENSURE(dbt_real(h, "SELECT count(*) FROM checks WHERE measure_id IS NULL AND"
                       " on_failure = 'fail'") == 1);
    ENSURE(dbt_real(h, "SELECT count(*) FROM checks WHERE on_failure = 'inconclusive'") == 3);
    /* the layout's share, counted again here: no crossing of the road, every
     * interception of B1 and E1 within serviceability */
    ENSURE(dbt_real(h, "SELECT value FROM checks WHERE measure_id IS NULL") ==
           kept_share(h, "'serviceability'"));
    /* the same for a later state: kept within serviceability or restorability */
    char *text = rf_test_read_text("rules/table3.yaml");
    ENSURE(text);
    static const char from[] = "value: share_of_rockfalls_kept\n    state: serviceability";
    char *at = strstr(text, from);
    ENSURE(at);
    char rules_text[16384];
    snprintf(rules_text, sizeof rules_text, "%.*svalue: share_of_rockfalls_kept\n    state: "
             "restorability%s", (int)(at - text), text, at + strlen(from));
    free(text);
    rf_rules r;
    rf_error err;
    ENSURE_MSG(rf_rules_load_text("later.yaml", rules_text, strlen(rules_text), &r, &err) == 0,
               "%s", err.message);
    ENSURE(r.nlayout == 1 && r.layout_checks[0].state == 1);
    ENSURE(rf_rules_evaluate(h, 1, &r, NULL, NULL, &err) == 0);
    rf_rules_free(&r);
    ENSURE(dbt_real(h, "SELECT value FROM checks WHERE measure_id IS NULL") ==
           kept_share(h, "'serviceability', 'restorability'"));
    ENSURE(dbt_real(h, "SELECT count(DISTINCT measure_id) FROM checks") == 2);
    ENSURE(dbt_real(h, "SELECT count(*) FROM checks c JOIN measures m ON m.id = c.measure_id "
                 "WHERE m.kind = 'control'") == 0);
    /* the exit status agrees with the stored verdicts */
    double failed = dbt_real(h, "SELECT count(*) FROM checks WHERE passed = 0");
    ENSURE(status == (failed > 0 ? 1 : 0));
    /* the barrier stops what reaches it: nothing it stopped is seen downstream */
    ENSURE(dbt_real(h, "SELECT count(*) FROM interceptions i JOIN measures m ON m.id = i.measure_id "
                 "WHERE m.name = 'B1' AND i.outcome = 'stopped'") > 0);
    ENSURE(dbt_real(h, "SELECT count(*) FROM interceptions a JOIN measures m ON m.id = a.measure_id "
                 "JOIN interceptions b ON b.trajectory_id = a.trajectory_id AND b.t_s > a.t_s "
                 "WHERE a.outcome = 'stopped'") == 0);
    /* a trajectory's largest energy is at least the energy of each of its crossings
     * (rolling into the barrier, the spin of the last event was taken, and the stop
     * took the energy before it was noted) */
    ENSURE(dbt_real(h, "SELECT count(*) FROM interceptions i JOIN trajectories t "
                 "ON t.id = i.trajectory_id WHERE i.energy_kj > t.max_energy_kj") == 0);
    sqlite3_close(h);
}

/* The committed terrain is what its generator writes, byte for byte. */
TEST(noto_terrain_is_reproducible)
{
    const char *tools = getenv("ROCKFALL_TOOLS");
    char cmd[2400], out[600];
    snprintf(out, sizeof out, "%s/terrain.asc", rf_test_tmpdir());
    snprintf(cmd, sizeof cmd, "%s/mknoto > %s && cmp -s %s projects/noto/terrain.asc",
             tools ? tools : "build/tools", out, out);
    ENSURE_MSG(system(cmd) == 0, "'%s' differs from the committed terrain", cmd);
}
