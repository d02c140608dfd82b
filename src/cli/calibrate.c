/* calibrate.c - `rockfall calibrate`: surface values fitted to observed stop points
 * (run/calibrate.h, docs/calibration.md). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/term.h"
#include "cli/cli.h"
#include "input/terrain_io.h"
#include "results/store.h"
#include "run/calibrate.h"

#define FIT_KEYS_MAX 32

const char CALIBRATE_HELP[] =
    "usage: rockfall calibrate PROJECT.yaml --observed STOPS --fit KEY [--fit KEY ...]\n"
    "                          [--threads N] [--count N] [--max-evals N] [--coarse N]\n"
    "                          [--tol T] [-o results.db] [-q]\n"
    "\n"
    "Fits the named surface values so that the project's simulated stop points match\n"
    "the observed ones, and prints the fitted values as YAML to paste into the project.\n"
    "The stops are compared on runout (from the mean start point) and lateral offset\n"
    "(across the observed stops' mean direction).  Every simulation draws the same\n"
    "random numbers (the run's streams), so the objective is a deterministic function\n"
    "of the values.  A coarse scan over the\n"
    "keys' ranges (evenly spread points of a Halton sequence) with the project's values\n"
    "gives the start of GSL's Nelder-Mead simplex.\n"
    "\n"
    "  --observed STOPS    text file, one stop per line: x y [z] in project coordinates\n"
    "                      (more columns are ignored, # starts a comment)\n"
    "  --fit KEY           surface.FIELD (every zone), zones.NAME.FIELD (one zone) or\n"
    "                      zones.NAME+NAME.FIELD (one value for these zones), FIELD one\n"
    "                      of restitution, friction, rolling, roughness, tangential (the\n"
    "                      mean of a distribution); repeat it or separate keys by commas\n"
    "  --objective w1|ks   w1 (default): the Wasserstein-1 distance of the runouts and\n"
    "                      of the lateral offsets, each over the observed sd; ks: the\n"
    "                      Kolmogorov-Smirnov distances of both, summed\n"
    "  --threads N         worker threads (default: the machine's cores online, at most\n"
    "                      256; results do not depend on it)\n"
    "  --count N           trajectories per release in each simulation (default: the\n"
    "                      project's)\n"
    "  --max-evals N       simulations at most (default 300)\n"
    "  --coarse N          points of the coarse scan (default 10 per key; 0: none)\n"
    "  --tol T             the simplex's size at which it stops, in initial steps\n"
    "                      (restitution, friction, rolling, tangential 0.1, roughness\n"
    "                      0.05 m; default 0.02)\n"
    "  -o, --output FILE   also store the fit in this results database\n"
    "  -q, --quiet         no progress lines\n";

/* Splits a --fit argument at commas and parses each key. */
static int add_keys(const rf_project *p, const char *arg, rf_fit_key *keys, size_t *nkeys,
                    rf_error *err)
{
    char buf[1024];
    if (strlen(arg) >= sizeof buf)
        return rf_error_set(err, "--fit", 0, 0, "an argument of over %zu characters",
                            sizeof buf - 1);
    strcpy(buf, arg);
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
         tok = strtok_r(NULL, ",", &save)) {
        if (*nkeys >= FIT_KEYS_MAX)
            return rf_error_set(err, "--fit", 0, 0, "more than %d keys", FIT_KEYS_MAX);
        if (rf_fit_key_parse(p, tok, &keys[*nkeys], err))
            return -1;
        for (size_t i = 0; i < *nkeys; i++)
            if (!strcmp(keys[i].path, keys[*nkeys].path))
                return rf_error_set(err, "--fit", 0, 0, "'%s' given twice", tok);
        (*nkeys)++;
    }
    return 0;
}

/* The fitted values as the project file writes them: `surface` keys, then one line per
 * zone with fitted values. */
static void print_yaml(const rf_project *p, const rf_fit_key *keys, const rf_calibration *c)
{
    char name[256];
    printf("terrain:\n");
    int any = 0;
    for (size_t i = 0; i < c->nkeys; i++)
        if (keys[i].zone < 0) {
            const char *field = strrchr(keys[i].path, '.') + 1;
            printf("%s%s: %.4g", any ? ", " : "  surface: {", field, c->value[i]);
            any = 1;
        }
    if (any)
        printf("}\n");
    any = 0;
    for (size_t z = 0; z < p->terrain.nzones; z++) {
        int zone_any = 0;
        for (size_t i = 0; i < c->nkeys; i++)
            if (keys[i].zone >= 0 && keys[i].zones[z]) {
                if (!any)
                    printf("  zones:\n");
                if (!zone_any)
                    printf("    - {name: %s",
                           rf_term_escape(p->terrain.zones[z].name, name, sizeof name));
                printf(", %s: %.4g", strrchr(keys[i].path, '.') + 1, c->value[i]);
                any = zone_any = 1;
            }
        if (zone_any)
            printf("}\n");
    }
}

static void print_summary(const rf_fit_key *keys, const rf_calibration *c, size_t nobs,
                          rf_objective objective)
{
    const rf_agreement *a = &c->agreement;
    printf("# rockfall calibrate: objective %.4f (%s) after %ld simulations of %ld "
           "trajectories (%s)\n",
           c->objective, rf_objective_name(objective), c->n_evals, c->n_trajectories,
           c->converged ? "converged" : "stopped at --max-evals");
    printf("# runout P5 / P50 / P95: simulated %.1f / %.1f / %.1f m, observed %.1f / %.1f / "
           "%.1f m (%zu stops)\n",
           a->runout_sim[0], a->runout_sim[1], a->runout_sim[2], a->runout_meas[0],
           a->runout_meas[1], a->runout_meas[2], nobs);
    printf("# KS runout %.3f, KS lateral %.3f; W1 runout %.2f m, W1 lateral %.2f m\n", a->ks,
           a->ks_lateral, a->w1_runout, a->w1_lateral);
    printf("# lateral sd: simulated %.2f m, observed %.2f m; observed stops inside the "
           "simulated 95 %% envelope %.0f %%; simulated rocks not at rest %.1f %%\n",
           a->lateral_sd_sim, a->lateral_sd_meas, 100.0 * a->inside,
           c->n_trajectories ? 100.0 * (double)c->not_rest / (double)c->n_trajectories : 0.0);
    for (size_t i = 0; i < c->nkeys; i++)
        printf("# %s: %.4g (from %.4g)\n", keys[i].path, c->value[i], c->start[i]);
    printf("# the means of these values; their sd as in the project\n");
}

typedef struct calibrate_args {
    const char *observed, *out;
    char *fit[FIT_KEYS_MAX];
    size_t nfit;
    long threads, count, max_evals, coarse;
    double tol;
    int quiet;
    rf_objective objective;
} calibrate_args;

static int parse_args(int argc, char **argv, calibrate_args *a)
{
    static const struct option opts[] = {
        {"observed", required_argument, 0, 'O'}, {"fit", required_argument, 0, 'f'},
        {"threads", required_argument, 0, 't'},  {"count", required_argument, 0, 'c'},
        {"max-evals", required_argument, 0, 'm'}, {"coarse", required_argument, 0, 'C'},
        {"tol", required_argument, 0, 'T'},      {"output", required_argument, 0, 'o'},
        {"quiet", no_argument, 0, 'q'},          {"objective", required_argument, 0, 'j'},
        {0, 0, 0, 0}};
    *a = (calibrate_args){.threads = rf_cli_default_threads(), .max_evals = 300, .coarse = -1, .tol = 0.02};
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "o:q", opts, NULL)) != -1) {
        switch (c) {
        case 'O': a->observed = optarg; break;
        case 'o': a->out = optarg; break;
        case 'q': a->quiet = 1; break;
        case 'j':
            if (strcmp(optarg, "w1") && strcmp(optarg, "ks"))
                return usage_error("calibrate", "--objective takes w1 or ks, got '%s'", optarg);
            a->objective = strcmp(optarg, "ks") ? RF_OBJECTIVE_W1 : RF_OBJECTIVE_KS;
            break;
        case 'f':
            if (a->nfit >= FIT_KEYS_MAX)
                return usage_error("calibrate", "--fit given over %s times", "32");
            a->fit[a->nfit++] = optarg;
            break;
        case 't':
            if (parse_long(optarg, 1, 256, &a->threads))
                return usage_error("calibrate", "--threads takes a whole number 1..256, got '%s'",
                                   optarg);
            break;
        case 'c':
            if (parse_long(optarg, 1, 10000000, &a->count))
                return usage_error("calibrate", "--count takes a whole number 1..10^7, got '%s'",
                                   optarg);
            break;
        case 'm':
            if (parse_long(optarg, 1, 1000000, &a->max_evals))
                return usage_error("calibrate",
                                   "--max-evals takes a whole number 1..10^6, got '%s'", optarg);
            break;
        case 'C':
            if (parse_long(optarg, 0, 1000000, &a->coarse))
                return usage_error("calibrate", "--coarse takes a whole number 0..10^6, got '%s'",
                                   optarg);
            break;
        case 'T':
            if (parse_double(optarg, &a->tol) || !(a->tol > 0.0))
                return usage_error("calibrate", "--tol takes a number > 0, got '%s'", optarg);
            break;
        default: return usage_error("calibrate", "%s", "bad option");
        }
    }
    if (optind != argc - 1)
        return usage_error("calibrate", "%s", "expects exactly one PROJECT.yaml");
    if (!a->observed)
        return usage_error("calibrate", "%s", "--observed STOPS is required");
    if (a->nfit == 0)
        return usage_error("calibrate", "%s", "at least one --fit KEY is required");
    return EXIT_OK;
}

/* Stores the fit in the results database `out`. */
static int store_fit(const char *out, const rf_project *p, const char *observed, size_t nobs,
                     rf_objective objective, const rf_fit_key *keys, const rf_calibration *c,
                     rf_error *err)
{
    rf_store *s;
    if (rf_store_open(out, &s, err))
        return -1;
    const char *paths[FIT_KEYS_MAX];
    for (size_t i = 0; i < c->nkeys; i++)
        paths[i] = keys[i].path;
    rf_calibration_record r = {observed, nobs, rf_objective_name(objective), c->objective,
                               c->agreement.ks, c->agreement.ks_lateral, c->agreement.inside,
                               c->n_evals, c->n_trajectories, c->converged, c->nkeys, paths,
                               c->start, c->value};
    int64_t id;
    int rc = rf_store_calibration(s, p, &r, &id, err);
    rf_store_close(s);
    if (rc == 0) {
        char db[1024];
        printf("# stored as calibration %lld in %s\n", (long long)id,
               rf_term_escape(out, db, sizeof db));
    }
    return rc;
}

int cmd_calibrate(int argc, char **argv)
{
    calibrate_args a;
    int status = parse_args(argc, argv, &a);
    if (status != EXIT_OK)
        return status;
    rf_project p;
    rf_error err;
    if (rf_project_load(argv[optind], &p, &err)) {
        rf_error_print(&err, stderr);
        return EXIT_BAD_INPUT;
    }
    if (a.count > 0)
        for (size_t i = 0; i < p.nreleases; i++)
            p.releases[i].count = a.count;
    rf_fit_key keys[FIT_KEYS_MAX];
    size_t nkeys = 0;
    rf_points obs = {0};
    rf_calibration cal = {0};
    int rc = 0;
    for (size_t i = 0; rc == 0 && i < a.nfit; i++)
        rc = add_keys(&p, a.fit[i], keys, &nkeys, &err);
    if (rc == 0)
        rc = rf_points_read(a.observed, 2, &obs, &err);
    if (rc == 0 && obs.n == 0)
        rc = rf_error_set(&err, a.observed, 0, 0, "no stop points");
    if (rc == 0) {
        long coarse = a.coarse >= 0 ? a.coarse : 10 * (long)nkeys;
        rf_calibrate_options o = {a.objective, (int)a.threads, a.max_evals, (int)coarse, a.tol,
                                  a.quiet ? NULL : stderr};
        rc = rf_calibrate(&p, obs.v, obs.n, keys, nkeys, &o, &cal, &err);
    }
    if (rc == 0) {
        print_summary(keys, &cal, obs.n, a.objective);
        print_yaml(&p, keys, &cal);
        if (a.out)
            rc = store_fit(a.out, &p, a.observed, obs.n, a.objective, keys, &cal, &err);
    }
    if (rc)
        rf_error_print(&err, stderr);
    rf_calibration_free(&cal);
    rf_points_free(&obs);
    rf_project_free(&p);
    return rc ? EXIT_BAD_INPUT : EXIT_OK;
}
