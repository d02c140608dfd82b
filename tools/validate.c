/* validate.c - the engine against real rockfalls (`make validate`).
 *
 * The Authume quarry tests (../shared/validation/authume; docs/validation.md): 89
 * boulders of 170 to 1 870 kg dropped from a shovel on two profiles, P1 (benches with
 * hard platforms) and P2 (a corridor on softer ground), with their measured stop
 * points.  Each measured boulder is simulated n times with its own mass, released at
 * rest with its centre at the shovel's height, uniformly over the release zone's
 * rectangle.  For each rock model (the sphere in full contact, the paper's centre
 * contact, the point mass) the restitution and friction means, one pair for the whole
 * slope, are fitted on P1 over a grid (the pair whose runouts are nearest the measured
 * ones: the smallest Kolmogorov-Smirnov distance, ties to the smaller error of the
 * median) and then run on P2, where nothing was fitted.  The paper's own values
 * (restitution 0.15, friction 0.30) are run on both profiles for comparison.
 *
 * usage: validate [PROJECT] [--data DIR] [--n N] [--fit-n N]
 *   PROJECT   the terrain and simulation settings (projects/authume/authume.yaml)
 *   --data    the field data (../shared/validation/authume)
 *   --n       simulations per measured boulder in the reported runs (50)
 *   --fit-n   the same in the fitting grid (10) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "rockfall/sim.h"
#include "fixtures/field.h"

#define SD_RESTITUTION 0.05
#define SD_FRICTION 0.05

typedef struct setting {
    const char *name;
    rf_rock_model model;
    rf_contact_kind contact;
} setting;

static const setting SETTINGS[] = {
    {"sphere, full contact", RF_MODEL_SPHERE, RF_CONTACT_FULL},
    {"sphere, centre contact", RF_MODEL_SPHERE, RF_CONTACT_CENTRE},
    {"point mass", RF_MODEL_POINT, RF_CONTACT_FULL},
};

static const double GRID_E[] = {0.00, 0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45};
static const double GRID_MU[] = {0.20, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80, 0.90, 1.00, 1.20};
#define NE (sizeof GRID_E / sizeof *GRID_E)
#define NMU (sizeof GRID_MU / sizeof *GRID_MU)

/* One result: the agreement and how many simulated rocks did not come to rest. */
typedef struct outcome {
    rf_agreement a;
    size_t not_rest;
} outcome;

/* Every zone of the slope gets restitution e and friction mu (rolling resistance: the
 * friction, as the project file's default). */
static void set_surface(rf_project *p, double e, double mu)
{
    rf_field_set_surface(&p->terrain, (rf_surface){{e, SD_RESTITUTION}, {mu, SD_FRICTION},
                                                   {mu, SD_FRICTION}});
}

/* Runs n simulations per measured boulder of profile `ip` and compares the stops. */
static int run_profile(rf_project *p, const setting *st, const rf_field_profile *pr, size_t ip,
                       long n, rf_workspace *ws, gsl_rng *rng, outcome *out)
{
    rf_simulation sim = p->sim;
    sim.model = st->model;
    sim.contact = st->contact;
    rf_scene scene = {&p->terrain, &sim, NULL, 0, NULL, 0};
    return rf_field_run(&scene, p->seed, pr, ip, n, ws, rng, &out->a, &out->not_rest);
}

static void print_row(const char *label, const char *fit, double e, double mu,
                      const rf_field_profile *pr, const outcome *o)
{
    const rf_agreement *a = &o->a;
    printf("| %s | %s | %.2f | %.2f | %s | %.1f / %.1f / %.1f | %.1f / %.1f / %.1f | "
           "%+.1f (%.1f) | %.1f | %.2f (%.2f) | %.0f %% | %.1f %% |\n",
           label, fit, e, mu, pr->name, a->runout_sim[0], a->runout_sim[1], a->runout_sim[2],
           a->runout_meas[0], a->runout_meas[1], a->runout_meas[2], a->lateral_mean_sim,
           a->lateral_sd_sim, a->lateral_sd_meas, a->ks, a->ks_crit,
           100.0 * a->inside, 100.0 * (double)o->not_rest / (double)a->n_sim);
}

int main(int argc, char **argv)
{
    const char *project = "projects/authume/authume.yaml";
    const char *data = "../shared/validation/authume";
    long n = 50, fit_n = 10;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--data") == 0 && i + 1 < argc)
            data = argv[++i];
        else if (strcmp(argv[i], "--n") == 0 && i + 1 < argc)
            n = atol(argv[++i]);
        else if (strcmp(argv[i], "--fit-n") == 0 && i + 1 < argc)
            fit_n = atol(argv[++i]);
        else if (argv[i][0] != '-')
            project = argv[i];
        else {
            fprintf(stderr, "usage: validate [PROJECT] [--data DIR] [--n N] [--fit-n N]\n");
            return 2;
        }
    }
    if (n < 1 || fit_n < 1) {
        fprintf(stderr, "validate: --n and --fit-n must be at least 1\n");
        return 2;
    }
    rf_project p;
    rf_error err;
    if (rf_project_load(project, &p, &err)) {
        rf_error_print(&err, stderr);
        return 2;
    }
    rf_field_profile pr[2];
    if (rf_field_profile_load(data, "P1", &pr[0], &err)) {
        rf_error_print(&err, stderr);
        rf_project_free(&p);
        return 2;
    }
    if (rf_field_profile_load(data, "P2", &pr[1], &err)) {
        rf_error_print(&err, stderr);
        rf_field_profile_free(&pr[0]);
        rf_project_free(&p);
        return 2;
    }
    rf_workspace *ws = rf_workspace_alloc(&p.terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    int rc = ws && rng ? 0 : 1;
    printf("Authume quarry: %zu boulders on P1, %zu on P2; %ld simulations per boulder "
           "(fit: %ld, over %zu x %zu pairs on P1)\n\n",
           pr[0].stops.n, pr[1].stops.n, n, fit_n, NE, NMU);
    printf("| setting | values | restitution | friction | profile | simulated runout P5 / "
           "median / P95 (m) | measured | simulated lateral offset mean (sd) (m) | measured sd | KS "
           "distance (5 %% critical) | measured stops in the simulated 95 %% envelope | "
           "simulated rocks not at rest (off the mesh) |\n");
    printf("|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (size_t s = 0; rc == 0 && s < sizeof SETTINGS / sizeof *SETTINGS; s++) {
        const setting *st = &SETTINGS[s];
        outcome o;
        /* the paper's values, on both profiles */
        set_surface(&p, 0.15, 0.30);
        for (size_t ip = 0; rc == 0 && ip < 2; ip++) {
            rc = run_profile(&p, st, &pr[ip], ip, n, ws, rng, &o);
            if (rc == 0)
                print_row(st->name, "paper", 0.15, 0.30, &pr[ip], &o);
        }
        /* fitted on P1 */
        double best_e = NAN, best_mu = NAN, best_ks = INFINITY, best_med = INFINITY;
        for (size_t i = 0; rc == 0 && i < NE; i++) {
            for (size_t j = 0; rc == 0 && j < NMU; j++) {
                set_surface(&p, GRID_E[i], GRID_MU[j]);
                rc = run_profile(&p, st, &pr[0], 0, fit_n, ws, rng, &o);
                double med = rc == 0 ? fabs(o.a.runout_sim[1] - o.a.runout_meas[1]) : NAN;
                if (rc == 0 && (o.a.ks < best_ks || (o.a.ks == best_ks && med < best_med))) {
                    best_ks = o.a.ks, best_med = med;
                    best_e = GRID_E[i], best_mu = GRID_MU[j];
                }
            }
        }
        set_surface(&p, best_e, best_mu);
        for (size_t ip = 0; rc == 0 && ip < 2; ip++) {
            rc = run_profile(&p, st, &pr[ip], ip, n, ws, rng, &o);
            if (rc == 0)
                print_row(st->name, ip == 0 ? "fitted on P1" : "fitted on P1, tested",
                          best_e, best_mu, &pr[ip], &o);
        }
        fflush(stdout);
    }
    if (rc)
        fprintf(stderr, "validate: out of memory\n");
    gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_field_profile_free(&pr[0]);
    rf_field_profile_free(&pr[1]);
    rf_project_free(&p);
    return rc ? 1 : 0;
}
