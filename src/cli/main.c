/* main.c - the rockfall command line: run, check, report, empirical.
 * Exit status: 0 success (all checks pass), 1 a design check fails or the run cannot
 * support a verdict (INCONCLUSIVE), 2 bad usage or bad input. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rockfall/empirical.h"
#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "rockfall/version.h"
#include "base/term.h"
#include "results/run_view.h"
#include "report/report.h"
#include "check/rules.h"
#include "results/integrity.h"
#include "results/schema.h"
#include "results/store.h"
#ifdef RF_MPI
#include "run/mpi.h"
#endif

#include "cli/cli.h"

static const char USAGE[] =
    "usage: rockfall COMMAND [OPTIONS]\n"
    "\n"
    "Design checks for rockfall protection measures (Masuya et al. 2009).\n"
    "\n"
    "commands:\n"
    "  run PROJECT.yaml [-o results.gpkg] [--seed N] [--count N] [--threads N] [--store maps]\n"
    "      simulate the project's releases into a results database (a GeoPackage)\n"
    "  check results.gpkg [--rules FILE] [--run ID]\n"
    "      classify every interception (Table 3 limit states) and run the design checks\n"
    "  report results.gpkg [--run ID | --runs ID,ID,...] --out DIR\n"
    "      DIR/index.html with the run's summary, or layout variants side by side\n"
    "  export results.gpkg [--run ID] --out DIR\n"
    "      the run's hazard maps as ESRI ASCII grids with their .prj\n"
    "  empirical --height H --slope DEG (--mu MU | --class A..D) [--distance L]\n"
    "      Eq. 1-2 velocity at the slope foot and the attainment width of Fig. 1b\n"
    "  calibrate PROJECT.yaml --observed STOPS --fit KEY [--fit KEY ...]\n"
    "      fit surface values to observed stop points; prints them as YAML\n"
    "\n"
    "  rockfall COMMAND --help   help on one command\n"
    "  rockfall --version\n"
    "\n"
    "exit status: 0 success, 1 a design check fails or the verdict is inconclusive,\n"
    "2 bad usage or input\n";

static const char RUN_HELP[] =
    "usage: rockfall run PROJECT.yaml [-o results.gpkg] [--seed N] [--count N] [--threads N]\n"
    "                    [--store all|maps]\n"
    "\n"
    "Loads and validates the project, runs every release's Monte Carlo trajectories\n"
    "and writes one run (trajectories, sampled paths, interceptions, tree hits, hazard\n"
    "cells) into the results database, which may already hold other runs.\n"
    "\n"
    "  -o, --output FILE   results database, a GeoPackage (default: results.gpkg)\n"
    "  --seed N            override the project's seed\n"
    "  --count N           trajectories per release, per cell of a `cells` release\n"
    "                      (overrides the project's counts)\n"
    "  --threads N         worker threads (default: the machine's cores online, at most\n"
    "                      256; results do not depend on it); per rank under mpirun\n"
    "                      (build/mpi/rockfall, docs/scaling.md: default 1 per rank)\n"
    "  --store maps        keep the run, releases, measures, interceptions, hazard cells and\n"
    "                      the sampled paths, with only the trajectories those need and no\n"
    "                      tree hits (a regional map); no checks.  Default: all\n"
    "  -q, --quiet         no progress or summary\n";

static const char CHECK_HELP[] =
    "usage: rockfall check results.gpkg [--rules FILE] [--run ID]\n"
    "\n"
    "Classifies every interception of a run (default: the newest complete run) into\n"
    "the limit states of the rule file, writes the classifications and each measure's\n"
    "checks into the database (replacing an earlier check of the run) and prints per\n"
    "measure: the number of interceptions, energy at the 50th, 90th, 95th and 99th\n"
    "percentiles and maximum, the 95th-percentile passing height, the share per limit\n"
    "state and each check's verdict, then the trajectories that cannot support a\n"
    "verdict (ended by max_time, left the terrain before any control line, at rest on\n"
    "a face steeper than their friction holds) against the rule file's allowance.\n"
    "\n"
    "  --run ID       the run to check\n"
    "  --rules FILE   rule file (default: the 'rules:' of the run's project),\n"
    "                 e.g. rules/table3.yaml\n"
    "\n"
    "exit status: 0 every check passes (PASS), 1 a check fails (FAIL) or the\n"
    "trajectories cannot support a verdict (INCONCLUSIVE), 2 bad usage or input\n";

static const char REPORT_HELP[] =
    "usage: rockfall report results.gpkg [--run ID | --runs ID,ID,...] --out DIR\n"
    "\n"
    "Writes DIR/index.html: the run, where its trajectories ended and what every\n"
    "measure saw.\n"
    "\n"
    "  --run ID         the run (default: the newest complete run)\n"
    "  --runs ID,ID,... layout variants side by side (2 to 8 runs): verdicts,\n"
    "                   interceptions and energy percentiles per structure,\n"
    "                   arrivals at the control lines, one plan view each\n"
    "  --out DIR        output folder (created when missing)\n";

static const char EXPORT_HELP[] =
    "usage: rockfall export results.gpkg [--run ID] --out DIR\n"
    "\n"
    "Writes the run's hazard maps on its hazard grid as ESRI ASCII grids, each with a\n"
    ".prj (the run's CRS, when its project has one): energy_max.asc, energy_p95.asc\n"
    "(kJ), height_p95.asc (m), reach_probability.asc, passages.asc and deposits.asc,\n"
    "and DIR/README.txt saying what each holds.  The database is opened read-only.\n"
    "\n"
    "  --run ID    the run (default: the newest complete run)\n"
    "  --out DIR   output folder (created when missing)\n";

static const char EMPIRICAL_HELP[] =
    "usage: rockfall empirical --height H --slope DEG (--mu MU | --class A..D) [--distance L] [--beta DEG]\n"
    "\n"
    "Velocity at the foot of an equivalent straight slope, Eq. 1-2:\n"
    "  V = sqrt(1 - mu / tan(theta)) sqrt(2 g H)\n"
    "with mu given or taken from Table 2 by slope class (A 0.05, B 0.15, C 0.25, D 0.35),\n"
    "and the attainment width at the foot (Fig. 1b): lines at beta (default 45 degrees)\n"
    "to both sides of the fall line from the release, over the horizontal distance L\n"
    "from the release to the foot (default H / tan(theta)): width = 2 L tan(beta).\n"
    "\n"
    "  --height H     vertical drop (m, > 0)\n"
    "  --slope DEG    average gradient (degrees, 0 < DEG < 90)\n"
    "  --mu MU        equivalent friction coefficient (>= 0)\n"
    "  --class C      Table 2 class A, B, C or D instead of --mu\n"
    "  --distance L   horizontal distance from the release to the foot (m)\n"
    "  --beta DEG     spreading angle (default 45)\n";

int usage_error(const char *cmd, const char *fmt, const char *arg)
{
    fprintf(stderr, "rockfall%s%s: ", cmd ? " " : "", cmd ? cmd : "");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(rockfall %s%s--help for usage)\n", cmd ? cmd : "", cmd ? " " : "");
    return EXIT_BAD_INPUT;
}

/* Parses a whole number in [lo, hi]; returns 0 on success. */
int parse_long(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

/* A plain decimal number: [+-]digits[.digits][e[+-]digits] (at least one digit before
 * or after the point).  strtod alone takes "0x10", "inf", "nan" and leading blanks. */
static int is_decimal(const char *s)
{
    const char *c = s + (*s == '+' || *s == '-');
    size_t digits = strspn(c, "0123456789");
    c += digits;
    if (*c == '.') {
        size_t frac = strspn(c + 1, "0123456789");
        digits += frac;
        c += 1 + frac;
    }
    if (digits == 0)
        return 0;
    if (*c == 'e' || *c == 'E') {
        c++;
        c += *c == '+' || *c == '-';
        size_t exp = strspn(c, "0123456789");
        if (exp == 0)
            return 0;
        c += exp;
    }
    return *c == '\0';
}

/* A finite decimal number (is_decimal); 0 on success. */
int parse_double(const char *s, double *out)
{
    if (!is_decimal(s))
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

static int wants_help(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h"))
            return 1;
    return 0;
}

/* ---- checks ---------------------------------------------------------------------- */

/* Classifies the run's interceptions, writes and prints its checks: EXIT_OK for a
 * PASS, EXIT_CHECK_FAILED for a FAIL or an INCONCLUSIVE verdict, EXIT_BAD_INPUT on an
 * error. */
static int check_run(sqlite3 *db, int64_t run, const rf_rules *rules, int print)
{
    rf_error err;
    rf_rules_result res;
    if (rf_rules_evaluate_verdict(db, run, rules, print ? stdout : NULL, &res, &err)) {
        rf_error_print(&err, stderr);
        return EXIT_BAD_INPUT;
    }
    return res.verdict == RF_VERDICT_PASS ? EXIT_OK : EXIT_CHECK_FAILED;
}

/* After a run: its trajectories that cannot support a verdict, counted as check counts
 * them (the allowances are the rule file's, applied by check). */
static int print_run_integrity(sqlite3 *db, int64_t run)
{
    rf_run_integrity g;
    rf_error err;
    if (rf_run_integrity_count(db, run, &g, &err)) {
        rf_error_print(&err, stderr);
        return EXIT_BAD_INPUT;
    }
    printf("  ended by max_time %ld, left the terrain before any control line %ld, at rest on "
           "a face steeper than its friction holds %ld\n",
           g.count[RF_INTEGRITY_MAX_TIME], g.count[RF_INTEGRITY_LEFT_TERRAIN],
           g.count[RF_INTEGRITY_REST_STEEP]);
    return EXIT_OK;
}

/* ---- run ---------------------------------------------------------------------- */

/* How the run's trajectories ended, and the engine's events per trajectory. */
static void print_run_ends(const rf_run_summary *sum)
{
    printf("  rest %ld, exited %ld, stopped %ld, max_time %ld\n", sum->by_reason[RF_END_REST],
           sum->by_reason[RF_END_EXITED], sum->by_reason[RF_END_STOPPED],
           sum->by_reason[RF_END_MAX_TIME]);
    double n = sum->n_trajectories > 0 ? (double)sum->n_trajectories : 1.0;
    printf("  engine events per trajectory: %.1f flights, %.1f surface segments, %.1f impacts, "
           "%.1f edge transitions\n",
           sum->events[0] / n, sum->events[1] / n, sum->events[2] / n, sum->events[3] / n);
}

static volatile sig_atomic_t interrupted;

static void on_interrupt(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* A run of --store maps kept not the rows its integrity counts and checks need. */
static int print_maps_kept(void)
{
    printf("  maps kept (--store maps): no per-trajectory counts, no checks\n");
    return 0;
}

/* A project that cannot be loaded: the error printed (under MPI, by rank 0, which the
 * other ranks tell). */
static int load_failed(const rf_error *err)
{
#ifdef RF_MPI
    if (rf_mpi_rank() > 0) {
        rf_mpi_report_failure(err);
        return EXIT_BAD_INPUT;
    }
#endif
    rf_error_print(err, stderr);
    return EXIT_BAD_INPUT;
}

/* The run itself; under MPI with more than one rank, shared among them (run/mpi.h),
 * its progress as lines (mpirun forwards stderr, not a terminal). */
static int simulate(const rf_project *p, rf_store *s, rf_run_options *o, int quiet,
                    rf_run_summary *sum, rf_error *err)
{
#ifdef RF_MPI
    if (rf_mpi_size() > 1) {
        o->progress = quiet ? 0 : 2;
        return rf_mpi_run(p, s, o, sum, err);
    }
#endif
    (void)quiet;
    return rf_montecarlo_run(p, s, o, sum, err);
}

#ifdef RF_MPI
/* A rank above 0: serves rank 0 until the run is done (frees p).  SIGINT and SIGTERM,
 * which mpirun sends every rank when the job is stopped, are caught and left to rank 0,
 * which marks the run failed and closes the file within mpirun's grace before it kills
 * the job. */
static int serve_rank(rf_project *p, int threads)
{
    struct sigaction sa = {.sa_handler = on_interrupt};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    rf_run_options wo = {.threads = threads};
    rf_error err;
    int served = rf_mpi_serve(p, &wo, &err);
    rf_project_free(p);
    return served ? EXIT_BAD_INPUT : EXIT_OK;
}
#endif

static int run_command(int argc, char **argv)
{
    static const struct option opts[] = {
        {"output", required_argument, 0, 'o'}, {"seed", required_argument, 0, 's'},
        {"count", required_argument, 0, 'c'},  {"threads", required_argument, 0, 't'},
        {"quiet", no_argument, 0, 'q'},        {"store", required_argument, 0, 'S'},
        {0, 0, 0, 0}};
    const char *out = "results.gpkg";
    long seed = -1, count = 0, threads = rf_cli_default_threads();
    int quiet = 0, maps = 0, c;
#ifdef RF_MPI
    if (rf_mpi_size() > 1)
        threads = 1; /* under mpirun: one thread per rank unless --threads is given */
#endif
    optind = 1;
    while ((c = getopt_long(argc, argv, "o:q", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case 's':
            if (parse_long(optarg, 0, 0x7fffffffffffffffL, &seed))
                return usage_error("run", "--seed takes a whole number >= 0, got '%s'", optarg);
            break;
        case 'c':
            if (parse_long(optarg, 1, RF_COUNT_MAX, &count))
                return usage_error("run", "--count takes a whole number >= 1, got '%s'", optarg);
            break;
        case 't':
            if (parse_long(optarg, 1, 256, &threads))
                return usage_error("run", "--threads takes a whole number 1..256, got '%s'", optarg);
            break;
        case 'q': quiet = 1; break;
        case 'S':
            if ((maps = !strcmp(optarg, "maps")) == 0 && strcmp(optarg, "all"))
                return usage_error("run", "--store takes all or maps, got '%s'", optarg);
            break;
        default: return usage_error("run", "%s", "bad option");
        }
    }
    if (optind != argc - 1)
        return usage_error("run", "%s", "expects exactly one PROJECT.yaml");

    rf_project p;
    rf_error err;
    if (rf_project_load(argv[optind], &p, &err))
        return load_failed(&err);
    if (seed >= 0)
        p.seed = (uint64_t)seed;
    if (count > 0)
        for (size_t i = 0; i < p.nreleases; i++) {
            p.releases[i].count = count;
            /* a mask release runs count trajectories in each of its cells */
            if (rf_release_trajectories(&p.releases[i]) > RF_COUNT_MAX) {
                char name[256];
                rf_term_escape(p.releases[i].name, name, sizeof name);
                rf_project_free(&p);
                return usage_error("run",
                                   "--count gives release '%s' over 1000000000 trajectories "
                                   "(its cells times the count)",
                                   name);
            }
        }

#ifdef RF_MPI
    if (rf_mpi_rank() > 0) /* simulates what rank 0 hands out; rank 0 writes */
        return serve_rank(&p, (int)threads);
#endif
    /* The project's rules are read before the simulation: a bad rule file costs
     * nothing. */
    rf_rules rules = {0};
    if (p.rules_path && rf_rules_load(p.rules_path, &rules, &err)) {
        rf_error_print(&err, stderr);
        rf_project_free(&p);
        return EXIT_BAD_INPUT;
    }
    rf_store *s;
    if (rf_store_open(out, &s, &err)) {
        rf_error_print(&err, stderr);
        rf_rules_free(&rules);
        rf_project_free(&p);
        return EXIT_BAD_INPUT;
    }
    /* SIGINT or SIGTERM: the run ends as failed after the rows being written, and the
     * database is closed (no -wal or -shm file left behind) */
    struct sigaction sa = {.sa_handler = on_interrupt}, old_int, old_term;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    rf_run_options o = {.threads = (int)threads, .progress = !quiet && isatty(2),
                        .interrupted = &interrupted, .maps = maps};
    rf_run_summary sum;
    int rc = simulate(&p, s, &o, quiet, &sum, &err);
    if (rc) {
        rf_error_print(&err, stderr);
    } else if (!quiet) {
        char name[256], db[1024];
        printf("run %lld of '%s' into %s: %ld trajectories in %.2f s on %ld threads (%.0f per "
               "second)\n",
               (long long)sum.run_id, rf_term_escape(p.name, name, sizeof name),
               rf_term_escape(out, db, sizeof db), sum.n_trajectories, sum.seconds, threads,
               sum.seconds > 0 ? (double)sum.n_trajectories / sum.seconds : 0.0);
        print_run_ends(&sum);
        rc = maps ? print_maps_kept() : print_run_integrity(rf_store_db(s), sum.run_id);
    }
    int status = rc ? EXIT_BAD_INPUT : EXIT_OK;
    if (rc == 0 && p.rules_path && !maps) {
        if (!quiet)
            printf("\n");
        status = check_run(rf_store_db(s), sum.run_id, &rules, !quiet);
    } else if (rc == 0 && p.nmeasures > 0 && !quiet) {
        rf_query_print_measures(rf_store_db(s), sum.run_id, stdout);
    }
    rf_store_close(s);
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    rf_rules_free(&rules);
    rf_project_free(&p);
    return status;
}

/* Under MPI (make mpi) every rank runs the command: rank 0 as above, the others
 * serving it (run/mpi.h); a failure anywhere ends every rank. */
static int cmd_run(int argc, char **argv)
{
#ifdef RF_MPI
    if (rf_mpi_init(NULL, NULL)) {
        fprintf(stderr, "rockfall: MPI could not be started\n");
        return EXIT_BAD_INPUT;
    }
    int status = run_command(argc, argv);
    rf_mpi_end(status == EXIT_BAD_INPUT ? status : 0);
    return status;
#else
    return run_command(argc, argv);
#endif
}

/* ---- check and report ----------------------------------------------------------- */

/* The arguments of check and report: "DB [--run ID] [--out DIR | --rules FILE]". */
typedef struct db_args {
    const char *db;
    long run;
    const char *out, *rules;
    const char *runs; /* report --runs: the list as given */
} db_args;

/* Opens an existing database as the command may (docs/database.md, "Schema policy":
 * check read-write without touching the schema, report read-only) and resolves the run
 * (the newest complete one by default). */
static int open_run(const db_args *a, rf_db_mode mode, sqlite3 **db, int64_t *run)
{
    rf_error err;
    if (rf_db_open(a->db, mode, db, NULL, &err)) {
        rf_error_print(&err, stderr);
        return EXIT_BAD_INPUT;
    }
    if (rf_query_resolve_run(*db, a->run, run, &err)) {
        rf_error_print(&err, stderr);
        sqlite3_close(*db);
        return EXIT_BAD_INPUT;
    }
    return EXIT_OK;
}

/* Shared by check and report: parses their arguments into *a.  Returns EXIT_OK or an
 * exit status. */
static int parse_db_args(const char *cmd, int argc, char **argv, db_args *a, int want_out)
{
    static const struct option opts[] = {{"run", required_argument, 0, 'r'},
                                         {"out", required_argument, 0, 'o'},
                                         {"rules", required_argument, 0, 'R'},
                                         {"runs", required_argument, 0, 'n'},
                                         {0, 0, 0, 0}};
    memset(a, 0, sizeof *a);
    a->run = -1;
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'r':
            if (parse_long(optarg, 1, 0x7fffffffffffffffL, &a->run))
                return usage_error(cmd, "--run takes a run id >= 1, got '%s'", optarg);
            break;
        case 'o':
            if (!want_out)
                return usage_error(cmd, "%s", "--out is an option of report");
            a->out = optarg;
            break;
        case 'R':
            if (want_out)
                return usage_error(cmd, "%s", "--rules is an option of check");
            a->rules = optarg;
            break;
        case 'n':
            if (!want_out)
                return usage_error(cmd, "%s", "--runs is an option of report");
            a->runs = optarg;
            break;
        default: return usage_error(cmd, "%s", "bad option");
        }
    }
    if (optind != argc - 1)
        return usage_error(cmd, "%s", "expects exactly one results database");
    a->db = argv[optind];
    if (want_out && !a->out)
        return usage_error(cmd, "%s", "--out DIR is required");
    if (a->runs && a->run > 0)
        return usage_error(cmd, "%s", "--run and --runs exclude each other");
    if (access(a->db, R_OK) != 0) {
        fprintf(stderr, "%s: error: cannot open results database: %s\n", a->db, strerror(errno));
        return EXIT_BAD_INPUT;
    }
    return EXIT_OK;
}

/* Runs check or report: their arguments, the database and run opened, then the
 * command's body on the open database, which is closed whatever the body returns. */
static int db_command(const char *cmd, int argc, char **argv, int want_out,
                      int (*body)(const db_args *a, sqlite3 *db, int64_t run))
{
    db_args a;
    sqlite3 *db;
    int64_t run;
    int rc = parse_db_args(cmd, argc, argv, &a, want_out);
    if (!rc)
        rc = open_run(&a, want_out ? RF_DB_READ : RF_DB_CHECK, &db, &run);
    if (rc)
        return rc;
    rc = body(&a, db, run);
    sqlite3_close(db);
    return rc;
}

static int check_body(const db_args *a, sqlite3 *db, int64_t run)
{
    rf_error err;
    char *path = NULL;
    rf_rules rules;
    if ((!a->rules && rf_rules_path_of_run(db, run, &path, &err)) ||
        rf_rules_load(a->rules ? a->rules : path, &rules, &err)) {
        rf_error_print(&err, stderr);
        free(path);
        return EXIT_BAD_INPUT;
    }
    int rc = check_run(db, run, &rules, 1);
    rf_rules_free(&rules);
    free(path);
    return rc;
}

static int cmd_check(int argc, char **argv)
{
    return db_command("check", argc, argv, 0, check_body);
}

/* Most runs `report --runs` compares. */
#define MAX_COMPARED_RUNS 8

/* The ids of --runs ("3,4"): 2 to MAX_COMPARED_RUNS distinct ids >= 1, each a run of
 * the database.  Returns EXIT_OK or an exit status. */
static int parse_runs(const char *list, sqlite3 *db, int64_t *ids, size_t *n)
{
    char buf[256];
    size_t len = strlen(list);
    if (len >= sizeof buf || !len || list[0] == ',' || list[len - 1] == ',' || strstr(list, ",,"))
        return usage_error("report", "--runs takes 2 to 8 run ids >= 1 apart by commas, "
                                     "got '%s'", list);
    snprintf(buf, sizeof buf, "%s", list);
    *n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        long id;
        if (*n == MAX_COMPARED_RUNS || parse_long(tok, 1, 0x7fffffffffffffffL, &id))
            return usage_error("report", "--runs takes 2 to 8 run ids >= 1 apart by commas, "
                                         "got '%s'", list);
        for (size_t k = 0; k < *n; k++)
            if (ids[k] == id)
                return usage_error("report", "--runs names a run twice: '%s'", list);
        ids[(*n)++] = id;
    }
    if (*n < 2)
        return usage_error("report", "--runs takes 2 to 8 run ids apart by commas, got '%s'",
                           list);
    for (size_t k = 0; k < *n; k++) {
        rf_error err;
        if (rf_query_resolve_run(db, (long)ids[k], &ids[k], &err)) {
            rf_error_print(&err, stderr);
            return EXIT_BAD_INPUT;
        }
    }
    return EXIT_OK;
}

static int report_body(const db_args *a, sqlite3 *db, int64_t run)
{
    rf_error err;
    int64_t ids[MAX_COMPARED_RUNS];
    size_t n = 0;
    if (a->runs) {
        int rc = parse_runs(a->runs, db, ids, &n);
        if (rc)
            return rc;
    }
    if (a->runs ? rf_report_compare(db, ids, n, a->out, &err)
                : rf_report_write(db, run, a->out, &err)) {
        rf_error_print(&err, stderr);
        return EXIT_BAD_INPUT;
    }
    printf("%s/index.html\n", a->out);
    return EXIT_OK;
}

static int cmd_report(int argc, char **argv)
{
    return db_command("report", argc, argv, 1, report_body);
}

/* ---- export ------------------------------------------------------------------- */

static int export_body(const db_args *a, sqlite3 *db, int64_t run)
{
    rf_error err;
    if (rf_export_write(db, run, a->out, &err)) {
        rf_error_print(&err, stderr);
        return EXIT_BAD_INPUT;
    }
    printf("%s/README.txt\n", a->out);
    return EXIT_OK;
}

static int cmd_export(int argc, char **argv)
{
    return db_command("export", argc, argv, 1, export_body);
}

/* ---- empirical ---------------------------------------------------------------- */

static int cmd_empirical(int argc, char **argv)
{
    static const struct option opts[] = {
        {"height", required_argument, 0, 'H'}, {"slope", required_argument, 0, 'S'},
        {"mu", required_argument, 0, 'm'},     {"class", required_argument, 0, 'C'},
        {"distance", required_argument, 0, 'L'}, {"beta", required_argument, 0, 'b'},
        {0, 0, 0, 0}};
    double height = NAN, slope = NAN, mu = NAN, distance = NAN, beta = 45.0;
    char cls = 0;
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'H':
            if (parse_double(optarg, &height) || height <= 0)
                return usage_error("empirical", "--height takes a number > 0, got '%s'", optarg);
            break;
        case 'S':
            if (parse_double(optarg, &slope) || slope <= 0 || slope >= 90)
                return usage_error("empirical", "--slope takes degrees in (0, 90), got '%s'", optarg);
            break;
        case 'm':
            if (parse_double(optarg, &mu) || mu < 0)
                return usage_error("empirical", "--mu takes a number >= 0, got '%s'", optarg);
            break;
        case 'C':
            if (strlen(optarg) != 1 || rf_table2_friction(optarg[0]) < 0)
                return usage_error("empirical", "--class takes A, B, C or D, got '%s'", optarg);
            cls = optarg[0];
            break;
        case 'L':
            if (parse_double(optarg, &distance) || distance <= 0)
                return usage_error("empirical", "--distance takes a number > 0, got '%s'", optarg);
            break;
        case 'b':
            if (parse_double(optarg, &beta) || beta < 0 || beta >= 90)
                return usage_error("empirical", "--beta takes degrees in [0, 90), got '%s'", optarg);
            break;
        default: return usage_error("empirical", "%s", "bad option");
        }
    }
    if (optind != argc)
        return usage_error("empirical", "unexpected argument '%s'", argv[optind]);
    if (isnan(height) || isnan(slope))
        return usage_error("empirical", "%s", "--height and --slope are required");
    if (isnan(mu) == !cls)
        return usage_error("empirical", "%s", "give exactly one of --mu and --class");
    if (cls)
        mu = rf_table2_friction(cls);
    double theta = slope * M_PI / 180.0;
    if (isnan(distance))
        distance = height / tan(theta);
    double alpha = rf_empirical_alpha(mu, theta);
    double v = rf_empirical_velocity(height, theta, mu);
    double width = rf_empirical_attainment_width(distance, beta * M_PI / 180.0);
    if (!isfinite(distance) || !isfinite(v) || !isfinite(width)) {
        fprintf(stderr, "rockfall empirical: the velocity or the attainment width of --height "
                        "%g is beyond what a double holds; give a smaller height or distance\n",
                height);
        return EXIT_BAD_INPUT;
    }
    printf("height H            %.1f m\n", height);
    printf("gradient theta      %.1f deg\n", slope);
    if (cls)
        printf("friction mu         %.2f (Table 2 class %c)\n", mu, cls);
    else
        printf("friction mu         %.3g\n", mu);
    printf("alpha (Eq. 2)       %.4f\n", alpha);
    printf("velocity (Eq. 1)    %.1f m/s\n", v);
    printf("attainment width    %.1f m (beta %.0f deg to both sides over %.1f m, Fig. 1b)\n",
           width, beta, distance);
    if (alpha == 0.0)
        printf("note: mu >= tan(theta): a sliding rock does not keep moving on this slope\n");
    return EXIT_OK;
}

/* The commands with their help texts: `rockfall NAME --help` prints the text. */
static const struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *help;
} commands[] = {
    {"run", cmd_run, RUN_HELP},
    {"check", cmd_check, CHECK_HELP},
    {"report", cmd_report, REPORT_HELP},
    {"export", cmd_export, EXPORT_HELP},
    {"empirical", cmd_empirical, EMPIRICAL_HELP},
    {"calibrate", cmd_calibrate, CALIBRATE_HELP},
};

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(USAGE, stderr);
        return EXIT_BAD_INPUT;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        fputs(USAGE, stdout);
        return EXIT_OK;
    }
    if (!strcmp(cmd, "--version")) {
        printf("rockfall %s\n", ROCKFALL_VERSION);
        return EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof *commands; i++) {
        if (strcmp(cmd, commands[i].name))
            continue;
        /* --help anywhere among a command's arguments wins over parsing them */
        if (wants_help(argc - 1, argv + 1)) {
            fputs(commands[i].help, stdout);
            return EXIT_OK;
        }
        return commands[i].run(argc - 1, argv + 1);
    }
    fprintf(stderr, "rockfall: unknown command '%s'\n\n%s", cmd, USAGE);
    return EXIT_BAD_INPUT;
}
