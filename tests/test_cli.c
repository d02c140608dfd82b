/* test_cli.c - the command line as a user calls it: exit statuses, help, empirical,
 * and a bad project that must not create a database. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "db_test_util.h"
#include "rockfall/empirical.h"
#include "test.h"


TEST(cli_version_and_help)
{
    char out[8192];
    ENSURE(rf_test_rockfall("--version", out, sizeof out) == 0);
    ENSURE(strstr(out, "rockfall ") == out);
    ENSURE(rf_test_rockfall("--help", out, sizeof out) == 0);
    ENSURE(strstr(out, "usage: rockfall COMMAND"));
    const char *cmds[] = {"run", "check", "report", "export", "empirical"};
    for (int i = 0; i < 5; i++) {
        char args[64];
        snprintf(args, sizeof args, "%s --help", cmds[i]);
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s --help", cmds[i]);
        char want[64];
        snprintf(want, sizeof want, "usage: rockfall %s", cmds[i]);
        ENSURE_MSG(strstr(out, want), "%s --help says: %s", cmds[i], out);
    }
}

TEST(cli_bad_usage_exits_2)
{
    char out[8192];
    ENSURE(rf_test_rockfall("", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("frobnicate", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("run", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("run a.yaml b.yaml", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("run projects/noto/noto-3.1-no-trees.yaml --count 0", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("check", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("check /nonexistent/results.db", out, sizeof out) == 2);
    ENSURE(strstr(out, "/nonexistent/results.db"));
    ENSURE(rf_test_rockfall("report x.db", out, sizeof out) == 2); /* --out missing */
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45 --mu 0.3 --class D", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("empirical --height -1 --slope 45 --mu 0.3", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 95 --mu 0.3", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45 --class E", out, sizeof out) == 2);
}

/* The paper's crosscheck (section 3.1): H = 175 m, 45 degrees, mu = 0.35 -> 47.2 m/s. */
TEST(cli_empirical_paper_crosscheck)
{
    char out[8192];
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45 --mu 0.35", out, sizeof out) == 0);
    ENSURE_MSG(strstr(out, "47.2 m/s"), "output: %s", out);
    /* Table 2 class D is the paper's 0.35 */
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45 --class D", out, sizeof out) == 0);
    ENSURE_MSG(strstr(out, "47.2 m/s"), "output: %s", out);
    ENSURE(strstr(out, "class D"));
    /* attainment width: 2 L tan(45) with L = 175 / tan(45) */
    ENSURE_MSG(strstr(out, "350.0 m"), "output: %s", out);
}

TEST(empirical_equations_1_2)
{
    double theta = 38.5 * M_PI / 180.0, mu = 0.2385, h = 61.7;
    double alpha = sqrt(1.0 - mu / tan(theta));
    ENSURE_REL(rf_empirical_alpha(mu, theta), alpha, 1e-15);
    ENSURE_REL(rf_empirical_velocity(h, theta, mu), alpha * sqrt(2 * 9.81 * h), 1e-15);
    ENSURE(rf_empirical_alpha(0.9, 30 * M_PI / 180) == 0.0); /* too gentle to move */
    ENSURE_REL(rf_empirical_attainment_width(95.0, M_PI / 4), 190.0, 1e-12);
}

/* Bad input: clear message with file:line:column, exit 2, no database written. */
TEST(cli_bad_project_touches_no_database)
{
    char dir[512], yaml[600], db[600], args[2048], out[8192];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    snprintf(yaml, sizeof yaml, "%s/bad.yaml", dir);
    snprintf(db, sizeof db, "%s/results.db", dir);
    FILE *f = fopen(yaml, "w");
    ENSURE(f);
    fputs("name: bad\nterrain:\n  dem: nowhere.asc\nrocks:\n  - {name: r, mass: 100}\n"
          "releases:\n  - {name: a, point: [0, 0], rock: r}\n",
          f);
    fclose(f);
    snprintf(args, sizeof args, "run %s -o %s", yaml, db);
    ENSURE(rf_test_rockfall(args, out, sizeof out) == 2);
    char want[700];
    snprintf(want, sizeof want, "%s:3:", yaml);
    ENSURE_MSG(strstr(out, want), "message: %s", out);
    struct stat st;
    ENSURE_MSG(stat(db, &st) != 0, "a database was created for a bad project");
}

/* ---- the results database's schema policy ------------------------------------------- */

#include <unistd.h>

/* A database written by rockfall at schema version 1 (tests/test_store.c). */
#define V1_FIXTURE "tests/data/results-v1.db"

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    ENSURE_MSG(f, "cannot open %s", path);
    char *buf = malloc(1 << 20);
    ENSURE(buf);
    *len = fread(buf, 1, 1 << 20, f);
    fclose(f);
    ENSURE(*len > 0 && *len < (1 << 20));
    return buf;
}

static void copy_file(const char *from, const char *to)
{
    size_t len;
    char *buf = slurp(from, &len);
    FILE *o = fopen(to, "wb");
    ENSURE(o && fwrite(buf, 1, len, o) == len);
    fclose(o);
    free(buf);
}

static int exists_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* `rockfall ARGS` as the user nobody when this runs as root (who may write anywhere),
 * else as ourselves: its exit status. */
static int rockfall_unprivileged(const char *args, char *out, size_t cap)
{
    if (geteuid() != 0)
        return rf_test_rockfall(args, out, cap);
    fflush(NULL);
    pid_t pid = fork();
    ENSURE(pid >= 0);
    if (pid == 0) {
        if (setgid(65534) != 0 || setuid(65534) != 0)
            _exit(99);
        _exit(rf_test_rockfall(args, out, cap));
    }
    int st;
    ENSURE(waitpid(pid, &st, 0) == pid && WIFEXITED(st));
    return WEXITSTATUS(st);
}

/* report opens the file read-only: a file it may only read, in a folder it may not
 * write, of schema version 1 (in the WAL journal) and of the current version, gives a
 * report and stays byte for byte as it was. */
TEST(cli_report_on_a_read_only_file_in_a_read_only_folder)
{
    char dir[512], ro[600], v1[700], v2[700], args[2048], out[8192];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    ENSURE(chmod(dir, 0777) == 0);
    snprintf(ro, sizeof ro, "%s/ro", dir);
    ENSURE(mkdir(ro, 0755) == 0);
    snprintf(v1, sizeof v1, "%s/v1.db", ro);
    snprintf(v2, sizeof v2, "%s/v2.db", ro);
    copy_file(V1_FIXTURE, v1);
    snprintf(args, sizeof args, "run projects/noto/noto-3.3.yaml --count 2 --quiet -o %s", v2);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) <= 1, "%s", out);
    ENSURE(chmod(v1, 0444) == 0 && chmod(v2, 0444) == 0 && chmod(ro, 0555) == 0);
    const char *dbs[2] = {v1, v2};
    for (int k = 0; k < 2; k++) {
        size_t la, lb;
        char *before = slurp(dbs[k], &la);
        snprintf(args, sizeof args, "report %s --out %s/report-%d", dbs[k], dir, k);
        ENSURE_MSG(rockfall_unprivileged(args, out, sizeof out) == 0, "%s: %s", dbs[k], out);
        char *after = slurp(dbs[k], &lb);
        ENSURE_MSG(la == lb && memcmp(before, after, la) == 0, "%s changed", dbs[k]);
        free(before);
        free(after);
        char index[700];
        snprintf(index, sizeof index, "%s/report-%d/index.html", dir, k);
        ENSURE(exists_file(index));
    }
    chmod(ro, 0755);
}

/* A file of schema version 1 is read by check and report as it is, and upgraded by
 * run; another program's SQLite file is refused by all three and left alone. */
TEST(cli_version_1_file_checked_reported_and_upgraded)
{
    char dir[512], db[600], args[2048], out[16384];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    snprintf(db, sizeof db, "%s/v1.db", dir);
    copy_file(V1_FIXTURE, db);
    snprintf(args, sizeof args, "check %s", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 1, "%s", out); /* Table 3 fails */
    ENSURE_MSG(strstr(out, "B1 (barrier, important)"), "%s", out);
    snprintf(args, sizeof args, "report %s --out %s/report-v1", db, dir);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    char path[700];
    snprintf(path, sizeof path, "%s/report-v1/index.html", dir);
    char *html = rf_test_read_text(path);
    ENSURE(html && strstr(html, "stores no terrain"));
    free(html);

    snprintf(args, sizeof args, "run projects/noto/noto-3.3.yaml --count 2 --quiet -o %s", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) <= 1, "%s", out);
    snprintf(args, sizeof args, "check %s --run 1", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 1, "%s", out);
    snprintf(args, sizeof args, "report %s --run 2 --out %s/report-v2", db, dir);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    snprintf(path, sizeof path, "%s/report-v2/plan.svg", dir);
    char *plan = rf_test_read_text(path);
    ENSURE(plan && strstr(plan, "contours every") && !strstr(plan, "no terrain contours"));
    free(plan);

    /* not ours: refused, untouched */
    const char *other = rf_test_write("photos.db", "");
    char sql[1024];
    snprintf(sql, sizeof sql, "sqlite3 %s 'CREATE TABLE photos (id INTEGER PRIMARY KEY)'", other);
    if (system(sql) != 0)
        return; /* no sqlite3 shell: the store's tests cover the library */
    size_t la, lb;
    char *before = slurp(other, &la);
    const char *cmds[3] = {"run projects/noto/noto-3.3.yaml --count 2 -o", "check", "report"};
    for (int k = 0; k < 3; k++) {
        snprintf(args, sizeof args, "%s %s%s", cmds[k], other, k == 2 ? " --out x" : "");
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s: %s", cmds[k], out);
        ENSURE_MSG(strstr(out, "not a rockfall results database"), "%s: %s", cmds[k], out);
    }
    char *after = slurp(other, &lb);
    ENSURE(la == lb && memcmp(before, after, la) == 0);
    free(before);
    free(after);
}

/* The report draws the terrain the run stored: after the project's DEM file is
 * changed, and after it is deleted, the plan is the same, byte for byte. */
TEST(cli_report_keeps_the_terrain_of_the_run)
{
    char dir[512], path[700], db[700], args[2048], out[16384];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    /* the Noto project beside a copy of its DEM, without its rule file */
    char *yaml = rf_test_read_text("projects/noto/noto-3.3.yaml");
    ENSURE(yaml);
    char *rules = strstr(yaml, "\nrules:");
    ENSURE(rules);
    rules[1] = '\0';
    snprintf(path, sizeof path, "%s/noto.yaml", dir);
    FILE *f = fopen(path, "w");
    ENSURE(f && fputs(yaml, f) >= 0);
    fclose(f);
    free(yaml);
    char dem[700];
    snprintf(dem, sizeof dem, "%s/terrain.asc", dir);
    copy_file("projects/noto/terrain.asc", dem);
    snprintf(db, sizeof db, "%s/noto.db", dir);
    snprintf(args, sizeof args, "run %s --count 2 --quiet -o %s", path, db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);

    const char *steps[3] = {"as run", "changed", "deleted"};
    char *first = NULL;
    for (int k = 0; k < 3; k++) {
        if (k == 1) { /* another slope: a plane 100 m lower */
            f = fopen(dem, "w");
            ENSURE(f);
            fputs("ncols 3\nnrows 3\nxllcenter 0\nyllcenter 0\ncellsize 150\n"
                  "NODATA_value -9999\n0 0 0\n0 0 0\n0 0 0\n", f);
            fclose(f);
        } else if (k == 2) {
            ENSURE(remove(dem) == 0);
        }
        snprintf(args, sizeof args, "report %s --out %s/report-%d", db, dir, k);
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s: %s", steps[k], out);
        snprintf(path, sizeof path, "%s/report-%d/plan.svg", dir, k);
        char *plan = rf_test_read_text(path);
        ENSURE(plan && strstr(plan, "contours every"));
        if (!first)
            first = plan;
        else {
            ENSURE_MSG(!strcmp(first, plan), "plan.svg differs with the DEM %s", steps[k]);
            free(plan);
        }
    }
    free(first);
}

/* ---- verdict integrity ------------------------------------------------------------ */

/* A slope (a profile 40 m wide) with a barrier across it that stops every rock it
 * meets and the road (a control line) below it, checked against Table 3: a PASS when
 * the rocks reach the barrier.  `simulation` and `velocity` vary the run. */
static const char *integrity_project(const char *name, const char *simulation,
                                     const char *velocity)
{
    char cwd[512], text[4096];
    ENSURE(getcwd(cwd, sizeof cwd));
    snprintf(text, sizeof text,
             "name: %s\n"
             "seed: 38\n"
             "terrain:\n"
             "  profile: {points: [[0, 120], [60, 60], [100, 40], [160, 35]], width: 40}\n"
             "  surface: {restitution: {mean: 0.3, sd: 0.1}, friction: {mean: 0.4, sd: 0.1}}\n"
             "rocks:\n"
             "  - {name: r, mass: 1500, action_level: 2}\n"
             "releases:\n"
             "  - {name: top, point: [5, 20], rock: r, count: 40, jitter: 5, velocity: %s}\n"
             "measures:\n"
             "  - {name: B, kind: barrier, line: [[80, 0.5], [80, 39.5]], height: 50,"
             " importance: usual, behaviour: stop, mel: 1e7}\n"
             "  - {name: road, kind: control, line: [[150, 0.5], [150, 39.5]],"
             " importance: usual}\n"
             "simulation: {paths: 0%s%s}\n"
             "rules: %s/rules/table3.yaml\n",
             name, velocity, simulation[0] ? ", " : "", simulation, cwd);
    char file[64];
    snprintf(file, sizeof file, "%s.yaml", name);
    return rf_test_write(file, text);
}

/* `rockfall run` of the project into a new database, which prints `counts` in its
 * summary, then `rockfall check` of it: both exit with `status` and print `verdict`. */
static void run_and_check(const char *project, const char *counts, int status,
                          const char *verdict, char *out, size_t cap)
{
    char db[700], args[2048];
    snprintf(db, sizeof db, "%s.db", project);
    snprintf(args, sizeof args, "run %s -o %s", project, db);
    ENSURE_MSG(rf_test_rockfall(args, out, cap) == status, "%s", out);
    ENSURE_MSG(strstr(out, verdict) && strstr(out, counts), "%s", out);
    snprintf(args, sizeof args, "check %s", db);
    ENSURE_MSG(rf_test_rockfall(args, out, cap) == status, "%s", out);
    ENSURE_MSG(strstr(out, verdict), "%s", out);
}

TEST(cli_rocks_reaching_the_barrier_pass)
{
    static char out[65536];
    run_and_check(integrity_project("reached", "", "[0, 0, 0]"),
                  "  ended by max_time 0, left the terrain before any control line 0, at rest on"
                  " a face steeper than its friction holds 0\n",
                  0, "verdict: PASS", out, sizeof out);
    ENSURE_MSG(strstr(out, "PASS trajectories_max_time           0 ended by max_time"), "%s",
               out);
}

/* max_time shorter than the rocks need: every trajectory ends on the slope above the
 * barrier, which no rock reached; that is no PASS. */
TEST(cli_max_time_too_short_is_inconclusive)
{
    static char out[65536];
    run_and_check(integrity_project("short", "max_time: 0.5", "[0, 0, 0]"),
                  "  ended by max_time 40, left the terrain before any control line 0,", 1,
                  "verdict: INCONCLUSIVE", out, sizeof out);
    ENSURE_MSG(strstr(out, "40 of 40 trajectories ended by max_time") &&
                   strstr(out, "INCONCLUSIVE trajectories_max_time") && !strstr(out, "PASS (all"),
               "%s", out);
}

/* A release velocity that throws every rock off the side of the terrain: none reaches
 * the barrier or the road, and none is counted as kept for a PASS. */
TEST(cli_rocks_thrown_off_the_terrain_are_inconclusive)
{
    static char out[65536];
    run_and_check(integrity_project("thrown", "", "[0, 60, 0]"),
                  "  ended by max_time 0, left the terrain before any control line 40,", 1,
                  "verdict: INCONCLUSIVE", out, sizeof out);
    ENSURE_MSG(strstr(out, "40 of 40 trajectories left the terrain before any control line"),
               "%s", out);
}

/* ---- files named on the command line --------------------------------------------- */

/* A sparse file of `size` bytes (its blocks are never written). */
static const char *sparse_file(const char *name, long size)
{
    const char *path = rf_test_write(name, "");
    ENSURE(truncate(path, size) == 0);
    return path;
}

/* `rockfall run /dev/zero` read the device until memory ran out (22 GB): a project
 * named on the command line must be a regular file, of at most 16 MiB. */
TEST(cli_run_refuses_dev_zero_and_a_huge_project_at_once)
{
    char args[2048], out[8192];
    ENSURE_MSG(rf_test_rockfall("run /dev/zero -o /nonexistent/x.db", out, sizeof out) == 2,
               "%s", out);
    ENSURE_MSG(strstr(out, "/dev/zero") && strstr(out, "not a regular file"), "%s", out);
    ENSURE_MSG(rf_test_rockfall("run /tmp -o /nonexistent/x.db", out, sizeof out) == 2, "%s",
               out);
    ENSURE_MSG(strstr(out, "Is a directory"), "%s", out);
    const char *big = sparse_file("big.yaml", (16L << 20) + 1);
    snprintf(args, sizeof args, "run %s -o /nonexistent/x.db", big);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s", out);
    ENSURE_MSG(strstr(out, "at most 16777216"), "%s", out);
}

/* `rockfall check DB --rules /dev/zero` likewise grew to 22.7 GB. */
TEST(cli_check_refuses_dev_zero_rules_at_once)
{
    char dir[512], db[600], args[2048], out[16384];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    snprintf(db, sizeof db, "%s/r.db", dir);
    snprintf(args, sizeof args, "run projects/noto/noto-3.3.yaml --count 1 --quiet -o %s", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) <= 1, "%s", out);
    snprintf(args, sizeof args, "check %s --rules /dev/zero", db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s", out);
    ENSURE_MSG(strstr(out, "/dev/zero") && strstr(out, "not a regular file"), "%s", out);
    const char *big = sparse_file("big-rules.yaml", (16L << 20) + 1);
    snprintf(args, sizeof args, "check %s --rules %s", db, big);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s", out);
    ENSURE_MSG(strstr(out, "at most 16777216"), "%s", out);
}

/* ---- text from files reaches the terminal escaped ---------------------------------- */

#include <limits.h>

#include "base/term.h"

TEST(term_escape_controls_bidi_and_bad_utf8)
{
    char buf[256];
    ENSURE(!strcmp(rf_term_escape("B1 Ü 東 ok", buf, sizeof buf), "B1 Ü 東 ok"));
    ENSURE(!strcmp(rf_term_escape("a\nb\tc\rd\x1b[8m\x7f", buf, sizeof buf),
                   "a\\nb\\tc\\rd\\x1B[8m\\x7F"));
    /* C1 controls (U+009B is CSI) and the bidirectional controls */
    ENSURE(!strcmp(rf_term_escape("\xc2\x9b" "2J", buf, sizeof buf), "\\u009B2J"));
    ENSURE(!strcmp(rf_term_escape("x\xe2\x80\xae" "y\xe2\x81\xa6z\xe2\x80\x8f\xd8\x9c", buf,
                                  sizeof buf),
                   "x\\u202Ey\\u2066z\\u200F\\u061C"));
    /* not UTF-8: a stray continuation, an overlong '/', a surrogate, a cut sequence */
    ENSURE(!strcmp(rf_term_escape("\x80\xc0\xaf\xed\xa0\x80\xe6\x9d", buf, sizeof buf),
                   "\\x80\\xC0\\xAF\\xED\\xA0\\x80\\xE6\\x9D"));
    /* too long: cut, marked, never inside an escape */
    ENSURE(!strcmp(rf_term_escape("abcdefgh", buf, 8), "abcd..."));
    ENSURE(!strcmp(rf_term_escape("\n\n\n\n", buf, 8), "\\n\\n..."));
    ENSURE(!strcmp(rf_term_escape("abc", buf, 4), "abc"));
}

/* A measure named with a newline and ESC [ 8 m printed a forged line on the terminal
 * and hid what followed; its name is now printed escaped by run, check and the errors. */
TEST(cli_measure_name_with_newline_and_escape_prints_escaped)
{
    char here[1024], yaml[8192], args[4096], out[65536];
    ENSURE(getcwd(here, sizeof here));
    snprintf(yaml, sizeof yaml,
             "name: \"forged\\e[8m\"\nseed: 1\nterrain:\n  dem: %s/projects/noto/terrain.asc\n"
             "rocks:\n  - {name: r, mass: 1000}\n"
             "releases:\n  - {name: C, point: [110, 202], rock: r, count: 1}\n"
             "measures:\n"
             "  - {name: \"B1\\n\\e[8mverdict: FORGED PASS\", kind: barrier,\n"
             "     line: [[130, 185], [210, 185]], height: 5, mel: 8000}\n"
             "rules: %s/rules/table3.yaml\n",
             here, here);
    const char *path = rf_test_write("forged.yaml", yaml);
    const char *db = rf_test_path("forged.db");
    char dbcopy[1024];
    snprintf(dbcopy, sizeof dbcopy, "%s", db);
    snprintf(args, sizeof args, "run %s -o %s", path, dbcopy);
    int rc = rf_test_rockfall(args, out, sizeof out);
    ENSURE_MSG(rc == 0 || rc == 1, "%s", out);
    const char *cmds[2] = {"run", "check"};
    for (int k = 0; k < 2; k++) {
        if (k == 1) {
            snprintf(args, sizeof args, "check %s", dbcopy);
            rc = rf_test_rockfall(args, out, sizeof out);
            ENSURE_MSG(rc == 0 || rc == 1, "%s", out);
        }
        ENSURE_MSG(!strchr(out, '\x1b'), "%s prints a raw ESC: %s", cmds[k], out);
        ENSURE_MSG(!strstr(out, "\nverdict: FORGED"), "%s prints a forged line: %s", cmds[k], out);
        ENSURE_MSG(strstr(out, "B1\\n\\x1B[8mverdict: FORGED PASS"), "%s: %s", cmds[k], out);
        ENSURE_MSG(strstr(out, "forged\\x1B[8m"), "%s: %s", cmds[k], out);
    }
    /* an error quoting the name */
    char *dup = strstr(yaml, "rules:");
    ENSURE(dup);
    snprintf(dup, sizeof yaml - (size_t)(dup - yaml),
             "  - {name: \"B1\\n\\e[8mverdict: FORGED PASS\", kind: control,\n"
             "     line: [[130, 185], [210, 185]]}\n");
    path = rf_test_write("forged2.yaml", yaml);
    snprintf(args, sizeof args, "run %s -o %s", path, dbcopy);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s", out);
    ENSURE_MSG(strstr(out, "duplicate measure name 'B1\\n\\x1B[8mverdict: FORGED PASS'"), "%s",
               out);
    ENSURE_MSG(!strchr(out, '\x1b') && !strstr(out, "\nverdict: FORGED"), "%s", out);
}

/* run without a rule file prints its measures' table: the names escaped there too. */
TEST(cli_run_without_rules_prints_measure_names_escaped)
{
    char here[1024], yaml[4096], args[4096], out[65536];
    ENSURE(getcwd(here, sizeof here));
    snprintf(yaml, sizeof yaml,
             "name: plain\nterrain:\n  dem: %s/projects/noto/terrain.asc\n"
             "rocks:\n  - {name: r, mass: 1000}\n"
             "releases:\n  - {name: C, point: [110, 202], rock: r, count: 1}\n"
             "measures:\n  - {name: \"road\\n\\e[8mFORGED\", kind: control,\n"
             "     line: [[0, 22], [300, 22]]}\n",
             here);
    const char *path = rf_test_write("plain.yaml", yaml);
    char db[1024];
    snprintf(db, sizeof db, "%s", rf_test_path("plain.db"));
    snprintf(args, sizeof args, "run %s -o %s", path, db);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    ENSURE_MSG(strstr(out, "road\\n\\x1B[8mFORGED"), "%s", out);
    ENSURE_MSG(!strchr(out, '\x1b') && !strstr(out, "\nFORGED"), "%s", out);
}

/* ---- rule files load in linear work ------------------------------------------------ */

#include "base/names.h"
#include "check/rules.h"

/* Each check's name was compared with every earlier one: a rule file of many checks
 * loaded in time growing with their square.  The names are found in a hash. */
TEST(rules_many_checks_load_in_linear_work)
{
    char *head = rf_test_read_text("rules/table3.yaml");
    ENSURE(head);
    char *cut = strstr(head, "\nchecks:");
    ENSURE(cut);
    cut[1] = '\0';
    const size_t n = 50000;
    size_t cap = strlen(head) + 64 + n * 128, used = 0;
    char *text = malloc(cap);
    ENSURE(text);
    used += (size_t)snprintf(text, cap, "%schecks:\n", head);
    for (size_t i = 0; i < n; i++)
        used += (size_t)snprintf(text + used, cap - used,
                                 "  - {rule: c%zu, value: share_within, state: serviceability, "
                                 "comparison: '>=', threshold: 0.9}\n",
                                 i);
    rf_rules r;
    rf_error err = {{0}};
    unsigned long long before = rf_names_probes();
    ENSURE_MSG(rf_rules_load_text("many.yaml", text, used, &r, &err) == 0, "%s", err.message);
    unsigned long long probes = rf_names_probes() - before;
    ENSURE(r.nchecks == n);
    ENSURE_MSG(probes <= 6 * n, "%llu slots looked at for %zu names", probes, n);
    rf_rules_free(&r);
    /* a duplicate is still found */
    used += (size_t)snprintf(text + used, cap - used,
                             "  - {rule: c7, value: share_within, state: serviceability, "
                             "comparison: '>=', threshold: 0.9}\n");
    ENSURE(rf_rules_load_text("many.yaml", text, used, &r, &err) != 0);
    ENSURE_MSG(strstr(err.message, "two checks are named 'c7'"), "%s", err.message);
    free(text);
    free(head);
}

/* empirical took --height 0x10 (strtod reads hexadecimal, "inf" and "nan") and printed
 * "inf m/s" for 1e308: numbers are decimal, results finite. */
TEST(cli_empirical_decimal_numbers_and_finite_results_only)
{
    char out[8192];
    const char *bad[] = {"0x10", "inf", "nan", "' 5'", "1e", "5e+", "1,5", "--"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char args[256];
        snprintf(args, sizeof args, "empirical --height %s --slope 45 --mu 0.3", bad[i]);
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s: %s", bad[i], out);
    }
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45 --mu 0x0.3", out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("empirical --height 1e308 --slope 45 --mu 0.3", out, sizeof out) == 2);
    ENSURE_MSG(!strstr(out, "inf") && strstr(out, "beyond what a double holds"), "%s", out);
    ENSURE(rf_test_rockfall("empirical --height 175 --slope 45 --mu 0.3 --distance 1e308 "
                            "--beta 89",
                            out, sizeof out) == 2);
    ENSURE(rf_test_rockfall("empirical --height +1.75e2 --slope 45. --mu .35", out, sizeof out) == 0);
    ENSURE_MSG(strstr(out, "47.2 m/s"), "%s", out);
}

/* ---- an interrupted run ----------------------------------------------------------- */

#include <fcntl.h>
#include <signal.h>
#include <sqlite3.h>
#include <time.h>

/* SIGINT (Ctrl-C) or SIGTERM in the middle of a run: the run ends as failed with the
 * rows written so far, the database is closed, and neither a -wal nor a -shm file is
 * left beside it. */
TEST(cli_interrupted_run_is_failed_and_leaves_no_stray_files)
{
    const int sigs[2] = {SIGINT, SIGTERM};
    for (int k = 0; k < 2; k++) {
        char db[600], wal[620], shm[620];
        snprintf(db, sizeof db, "%s/interrupted-%d.db", rf_test_tmpdir(), k);
        snprintf(wal, sizeof wal, "%s-wal", db);
        snprintf(shm, sizeof shm, "%s-shm", db);
        const char *bin = getenv("ROCKFALL_BIN") ? getenv("ROCKFALL_BIN") : "build/rockfall";
        pid_t pid = fork();
        ENSURE(pid >= 0);
        if (pid == 0) {
            int devnull = open("/dev/null", O_WRONLY);
            dup2(devnull, 1);
            dup2(devnull, 2);
            execl(bin, bin, "run", "projects/noto/noto-3.1-no-trees.yaml", "--count", "1000000",
                  "--quiet", "-o", db, (char *)NULL);
            _exit(127);
        }
        /* until the run has written rows (at most 60 s) */
        long rows = 0;
        for (int tries = 0; tries < 600 && rows == 0; tries++) {
            nanosleep(&(struct timespec){0, 100 * 1000 * 1000}, NULL);
            sqlite3 *h;
            if (sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK) {
                sqlite3_stmt *st;
                if (sqlite3_prepare_v2(h, "SELECT count(*) FROM trajectories", -1, &st, NULL) ==
                        SQLITE_OK &&
                    sqlite3_step(st) == SQLITE_ROW)
                    rows = sqlite3_column_int64(st, 0);
                sqlite3_finalize(st);
            }
            sqlite3_close(h);
        }
        ENSURE_MSG(rows > 0, "the run wrote no row in 60 s");
        ENSURE(kill(pid, sigs[k]) == 0);
        int st;
        ENSURE(waitpid(pid, &st, 0) == pid);
        ENSURE_MSG(WIFEXITED(st) && WEXITSTATUS(st) == 2, "status %d", st);
        struct stat sb;
        ENSURE_MSG(stat(wal, &sb) != 0 && stat(shm, &sb) != 0, "%s or %s left behind", wal, shm);
        sqlite3 *h;
        ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
        sqlite3_stmt *q;
        ENSURE(sqlite3_prepare_v2(h, "SELECT status, n_trajectories, (SELECT count(*) FROM"
                                     " trajectories) FROM runs", -1, &q, NULL) == SQLITE_OK);
        ENSURE(sqlite3_step(q) == SQLITE_ROW);
        ENSURE_MSG(!strcmp((const char *)sqlite3_column_text(q, 0), "failed") &&
                       sqlite3_column_int64(q, 1) == sqlite3_column_int64(q, 2) &&
                       sqlite3_column_int64(q, 1) < 1000000,
                   "%s, %lld rows", sqlite3_column_text(q, 0), sqlite3_column_int64(q, 1));
        sqlite3_finalize(q);
        sqlite3_close(h);
    }
}

/* --count is per cell of a `cells` release: a count that gives a mask release over
 * 10^9 trajectories is refused before the run, as the project file's own count is. */
TEST(cli_count_per_cell_of_a_mask_release_is_bounded)
{
    char out[8192];
    ENSURE(rf_test_rockfall("run tests/data/project/release_cells.yaml --count 400000000 --quiet -o "
                            "/nonexistent/never.db", out, sizeof out) == 2);
    ENSURE_MSG(strstr(out, "over 1000000000 trajectories (its cells times the count)"), "%s", out);
}

/* `report --runs` compares layout variants: 2 to 8 distinct runs of the database, apart
 * by commas; not with --run, not an option of check; a run that is not there is named.
 * --run alone still writes the one run's report. */
TEST(cli_report_runs_compares_variants_and_keeps_run)
{
    char dir[512], db[600], args[2048], out[16384];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    snprintf(db, sizeof db, "%s/variants.db", dir);
    const char *projects[2] = {"noto-3.2", "noto-3.3"};
    for (int k = 0; k < 2; k++) {
        snprintf(args, sizeof args, "run projects/noto/%s.yaml --count 2 --quiet -o %s",
                 projects[k], db);
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) <= 1, "%s", out);
    }
    snprintf(args, sizeof args, "report %s --runs 1,2 --out %s/cmp", db, dir);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    char path[700];
    snprintf(path, sizeof path, "%s/cmp/index.html", dir);
    char *html = rf_test_read_text(path);
    ENSURE(html && strstr(html, "<th>noto-3.2<br>run 1</th><th>noto-3.3<br>run 2</th>"));
    ENSURE(strstr(html, "<img src=\"plan-run-1.svg\"") && strstr(html, "<img src=\"plan-run-2.svg\""));
    ENSURE(strstr(html, ">B1 (barrier)</th>") && strstr(html, "not in this run"));
    free(html);
    snprintf(path, sizeof path, "%s/cmp/plan-run-2.svg", dir);
    ENSURE(exists_file(path));

    static const struct {
        const char *opts, *says;
    } bad[] = {
        {"--runs 1", "2 to 8 run ids"},
        {"--runs 1,x", "2 to 8 run ids"},
        {"--runs 1,,2", "2 to 8 run ids"},
        {"--runs 1,2,", "2 to 8 run ids"},
        {"--runs 1,2,1", "names a run twice"},
        {"--runs 1,2,3,4,5,6,7,8,9", "2 to 8 run ids"},
        {"--run 1 --runs 1,2", "exclude each other"},
        {"--runs 1,7", "no run 7"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(args, sizeof args, "report %s %s --out %s/bad", db, bad[k].opts, dir);
        ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 2, "%s: %s", bad[k].opts, out);
        ENSURE_MSG(strstr(out, bad[k].says), "%s: %s", bad[k].opts, out);
    }
    snprintf(path, sizeof path, "%s/bad", dir);
    ENSURE(!exists_file(path));
    snprintf(args, sizeof args, "check %s --runs 1,2", db);
    ENSURE(rf_test_rockfall(args, out, sizeof out) == 2 && strstr(out, "option of report"));

    snprintf(args, sizeof args, "report %s --run 1 --out %s/one", db, dir);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    snprintf(path, sizeof path, "%s/one/index.html", dir);
    html = rf_test_read_text(path);
    ENSURE(html && strstr(html, "<h1>noto-3.2</h1>") && strstr(html, "plan.svg"));
    free(html);
}

/* `run` without --threads takes the processors online and writes the rows that one
 * thread writes (the order of release and index, each trajectory on its own stream). */
TEST(cli_run_default_threads_are_the_cores_and_rows_match_one_thread)
{
    static char out[65536];
    char args[2048], want[64];
    const char *dir = rf_test_tmpdir();
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    snprintf(want, sizeof want, " on %ld threads (", cores < 1 ? 1 : (cores > 256 ? 256 : cores));
    snprintf(args, sizeof args, "run projects/noto/noto-3.2.yaml --count 40 -o %s/default.db",
             dir);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    ENSURE_MSG(strstr(out, want), "expected '%s' in: %s", want, out);
    snprintf(args, sizeof args,
             "run projects/noto/noto-3.2.yaml --count 40 --threads 1 -o %s/one.db", dir);
    ENSURE_MSG(rf_test_rockfall(args, out, sizeof out) == 0, "%s", out);
    ENSURE_MSG(strstr(out, " on 1 threads ("), "%s", out);

    char path[1024];
    snprintf(path, sizeof path, "%s/default.db", dir);
    sqlite3 *db;
    ENSURE(sqlite3_open(path, &db) == SQLITE_OK);
    char attach[1100];
    snprintf(attach, sizeof attach, "ATTACH '%s/one.db' AS one", dir);
    ENSURE(sqlite3_exec(db, attach, NULL, NULL, NULL) == SQLITE_OK);
    static const char *const tables[] = {"trajectories", "interceptions", "path_points",
                                         "hazard_cells"};
    for (size_t k = 0; k < sizeof tables / sizeof *tables; k++) {
        long long n = dbt_int(db, "SELECT count(*) FROM main.%s", tables[k]);
        ENSURE_MSG(n == dbt_int(db, "SELECT count(*) FROM one.%s", tables[k]), "%s", tables[k]);
        ENSURE_MSG(dbt_int(db, "SELECT count(*) FROM (SELECT * FROM main.%s EXCEPT "
                               "SELECT * FROM one.%s)", tables[k], tables[k]) == 0,
                   "%s differ", tables[k]);
    }
    ENSURE(dbt_int(db, "SELECT count(*) FROM main.trajectories") == 5 * 40);
    sqlite3_close(db);
}
