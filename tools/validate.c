/* validate.c - the engine against real rockfalls (`make validate`, docs/validation.md).
 *
 * The Authume quarry tests (../shared/validation/authume): 89 boulders dropped from a
 * shovel on two profiles, their stop points measured.  projects/authume/authume-p1.yaml
 * and authume-p2.yaml simulate every measured boulder (its mass, 20 trajectories, from
 * the drop zone); their terrain sections are identical, fitted on P1's stops alone by
 * `rockfall calibrate` (the sphere, Eq. 8, with slope roughness).  P2 is the blind
 * test.  Each setting below is run on both profiles with the projects' releases and
 * seed; the other settings' values were fitted on P1 the same way (the commands in
 * docs/validation.md).
 *
 * For each run: the share of the measured stops inside the simulated 95 % envelope,
 * the Kolmogorov-Smirnov distances on runout and lateral offset, the ratios of the
 * simulated lateral sd and robust sigma (IQR / 1.349) to the measured ones, the runout
 * percentiles (base/stats.h: the frame from the mean start point across the measured
 * stops' mean direction); each with a bootstrap 90 % interval (B resamples of the
 * measured and of the simulated stops, with replacement, the 5th and 95th percentiles
 * of each measure).
 *
 * usage: validate [--dir DIR] [--threads N] [--boot B]
 *   --dir      the projects and stop files (projects/authume)
 *   --threads  simulation threads (2; results do not depend on it)
 *   --boot     bootstrap resamples (400) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_rng.h>

#include "base/stats.h"
#include "input/terrain_io.h"
#include "rockfall/project.h"
#include "run/calibrate.h"
#include "fixtures/field.h"

typedef struct setting {
    const char *name;
    rf_rock_model model;
    int own;                       /* 1: the projects' values as they are */
    double e, mu, rolling, rs;     /* else every zone's means and roughness (a rolling
                                      resistance < 0: the projects') */
} setting;

/* The other settings' values were fitted on P1 by `rockfall calibrate` (field.h). */static const setting SETTINGS[] = {
    {"sphere, Eq. 8, roughness (the projects)", RF_MODEL_SPHERE, 1, 0, 0, 0, 0},
    {"sphere, Eq. 8, no roughness", RF_MODEL_SPHERE, 0, RF_AUTHUME_SPHERE0_E,
     RF_AUTHUME_SPHERE0_MU, RF_AUTHUME_SPHERE0_ROLLING, 0.0},
    {"point mass, roughness", RF_MODEL_POINT, 0, RF_AUTHUME_POINT_E, RF_AUTHUME_POINT_MU,
     -1.0, RF_AUTHUME_POINT_RS},
};

enum { M_INSIDE, M_KS, M_KS_LAT, M_SD_RATIO, M_RSIG_RATIO, M_P5, M_P50, M_P95, M_DMED, NM };

static void measures(const rf_agreement *a, double *m)
{
    m[M_INSIDE] = 100.0 * a->inside;
    m[M_KS] = a->ks;
    m[M_KS_LAT] = a->ks_lateral;
    m[M_SD_RATIO] = a->lateral_sd_sim / a->lateral_sd_meas;
    m[M_RSIG_RATIO] = a->lateral_rsigma_sim / a->lateral_rsigma_meas;
    m[M_P5] = a->runout_sim[0];
    m[M_P50] = a->runout_sim[1];
    m[M_P95] = a->runout_sim[2];
    m[M_DMED] = a->runout_sim[1] - a->runout_meas[1];
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The 90 % bootstrap interval of every measure into lo, hi. */
static int bootstrap(const double *meas, size_t nm, const double *sim, size_t ns, double x0,
                     double y0, int boot, double *lo, double *hi)
{
    double *bm = malloc(2 * nm * sizeof *bm), *bs = malloc(2 * ns * sizeof *bs);
    double *v = malloc((size_t)boot * NM * sizeof *v);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    int rc = bm && bs && v && rng ? 0 : -1;
    if (rng)
        gsl_rng_set(rng, 20221);
    for (int b = 0; rc == 0 && b < boot; b++) {
        for (size_t i = 0; i < nm; i++) {
            size_t k = gsl_rng_uniform_int(rng, nm);
            bm[2 * i] = meas[2 * k], bm[2 * i + 1] = meas[2 * k + 1];
        }
        for (size_t i = 0; i < ns; i++) {
            size_t k = gsl_rng_uniform_int(rng, ns);
            bs[2 * i] = sim[2 * k], bs[2 * i + 1] = sim[2 * k + 1];
        }
        rf_agreement a;
        double m[NM];
        rc = rf_agreement_compute(bm, nm, bs, ns, x0, y0, &a);
        measures(&a, m);
        for (int j = 0; j < NM; j++)
            v[(size_t)j * (size_t)boot + (size_t)b] = m[j];
    }
    for (int j = 0; rc == 0 && j < NM; j++) {
        double *col = v + (size_t)j * (size_t)boot;
        qsort(col, (size_t)boot, sizeof *col, cmp_double);
        lo[j] = rf_quantile(col, (size_t)boot, 0.05);
        hi[j] = rf_quantile(col, (size_t)boot, 0.95);
    }
    free(bm);
    free(bs);
    free(v);
    if (rng)
        gsl_rng_free(rng);
    return rc;
}

static void apply(rf_project *p, const setting *s)
{
    p->sim.model = s->model;
    if (s->own)
        return;
    for (size_t z = 0; z < p->terrain.nzones; z++) {
        rf_surface *f = &p->terrain.zones[z].surface;
        f->restitution.mean = s->e;
        f->friction.mean = s->mu;
        if (s->rolling >= 0.0)
            f->rolling.mean = s->rolling;
        f->roughness = s->rs;
    }
}

static void print_row(const setting *s, const char *profile, const rf_agreement *a,
                      const double *m, const double *lo, const double *hi, size_t not_rest)
{
    printf("| %s | %s | %.0f %% [%.0f, %.0f] | %.2f [%.2f, %.2f] | %.2f [%.2f, %.2f] | "
           "%.2f [%.2f, %.2f] | %.2f [%.2f, %.2f] | %.1f / %.1f / %.1f (%.1f / %.1f / %.1f) | "
           "%+.1f [%+.1f, %+.1f] | %.1f %% |\n",
           s->name, profile, m[M_INSIDE], lo[M_INSIDE], hi[M_INSIDE], m[M_KS], lo[M_KS], hi[M_KS],
           m[M_KS_LAT], lo[M_KS_LAT], hi[M_KS_LAT], m[M_SD_RATIO], lo[M_SD_RATIO],
           hi[M_SD_RATIO], m[M_RSIG_RATIO], lo[M_RSIG_RATIO], hi[M_RSIG_RATIO], m[M_P5], m[M_P50],
           m[M_P95], a->runout_meas[0], a->runout_meas[1], a->runout_meas[2], m[M_DMED],
           lo[M_DMED], hi[M_DMED], 100.0 * (double)not_rest / (double)a->n_sim);
}

/* One setting on one profile: simulate, compare, bootstrap, print. */
static int run_row(const char *dir, const char *profile, const setting *s, int threads, int boot)
{
    char path[4096], stops[4096];
    snprintf(path, sizeof path, "%s/authume-%s.yaml", dir, profile);
    snprintf(stops, sizeof stops, "%s/stops-%s.txt", dir, profile);
    rf_project p;
    rf_error err;
    rf_points obs;
    if (rf_project_load(path, &p, &err)) {
        rf_error_print(&err, stderr);
        return -1;
    }
    if (rf_points_read(stops, 2, &obs, &err)) {
        rf_error_print(&err, stderr);
        rf_project_free(&p);
        return -1;
    }
    apply(&p, s);
    double *sim, *start;
    size_t not_rest = 0;
    long n = rf_stops_simulate(&p, threads, &sim, &start, &not_rest);
    int rc = n > 0 ? 0 : -1;
    double x0 = 0.0, y0 = 0.0;
    for (long i = 0; i < n; i++)
        x0 += start[2 * i] / (double)n, y0 += start[2 * i + 1] / (double)n;
    rf_agreement a;
    double m[NM], lo[NM], hi[NM];
    if (rc == 0)
        rc = rf_agreement_compute(obs.v, obs.n, sim, (size_t)n, x0, y0, &a);
    if (rc == 0) {
        measures(&a, m);
        rc = bootstrap(obs.v, obs.n, sim, (size_t)n, x0, y0, boot, lo, hi);
    }
    if (rc == 0)
        print_row(s, profile[1] == '1' ? "P1 (fitted)" : "P2 (blind)", &a, m, lo, hi, not_rest);
    fflush(stdout);
    if (n > 0) {
        free(sim);
        free(start);
    }
    rf_points_free(&obs);
    rf_project_free(&p);
    return rc;
}

int main(int argc, char **argv)
{
    const char *dir = "projects/authume";
    int threads = 2, boot = 400;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--dir") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--boot") && i + 1 < argc)
            boot = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: validate [--dir DIR] [--threads N] [--boot B]\n");
            return 2;
        }
    }
    if (threads < 1 || boot < 10) {
        fprintf(stderr, "validate: --threads >= 1 and --boot >= 10\n");
        return 2;
    }
    printf("Authume quarry: every measured boulder 20 times (41 on P1, 48 on P2); in brackets "
           "the bootstrap 90 %% interval (%d resamples)\n\n", boot);
    printf("| setting | profile | measured stops in the simulated 95 %% envelope | KS runout | "
           "KS lateral | lateral sd ratio (sim / measured) | robust sigma ratio | runout P5 / "
           "P50 / P95, m (measured) | median runout - measured, m | not at rest |\n");
    printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    int rc = 0;
    for (size_t s = 0; rc == 0 && s < sizeof SETTINGS / sizeof *SETTINGS; s++)
        for (int k = 0; rc == 0 && k < 2; k++)
            rc = run_row(dir, k ? "p2" : "p1", &SETTINGS[s], threads, boot);
    printf("| discrete elements, real block shapes (Garcia et al. 2022; 4 shapes x 4 drop points "
           "x 64 orientations) | P2 (forecast) | 81 %% | 0.24 | 0.34 | 0.69 | | median 55.7 "
           "(56.3) | -0.6 | |\n");
    printf("| targets | P2 (blind) | >= 90 %% | <= 0.25 | <= 0.30 | 0.7 - 1.3 | | | within 3 | |\n");
    printf("| targets | P1 (fitted) | >= 90 %% | <= 0.22 | | | | | | |\n");
    if (rc)
        fprintf(stderr, "validate: a run failed\n");
    return rc ? 1 : 0;
}
