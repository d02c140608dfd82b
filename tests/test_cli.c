/* test_cli.c - the command line as a user calls it: exit statuses, help, empirical,
 * and a bad project that must not create a database. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "rockfall/empirical.h"
#include "test.h"


TEST(cli_version_and_help)
{
    char out[8192];
    ENSURE(rf_test_rockfall("--version", out, sizeof out) == 0);
    ENSURE(strstr(out, "rockfall ") == out);
    ENSURE(rf_test_rockfall("--help", out, sizeof out) == 0);
    ENSURE(strstr(out, "usage: rockfall COMMAND"));
    const char *cmds[] = {"run", "check", "report", "empirical"};
    for (int i = 0; i < 4; i++) {
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
