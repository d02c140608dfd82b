/* bench.c - speed against error of the motion engines (`make bench`).
 *
 * One row per engine setting: the exact event-driven engine, and the fixed-step
 * integrator at several dt.  Columns: trajectories per second on one thread on the
 * example slope (projects/noto, no trees, no database); the relative error against
 * four closed forms (Eq. 1-2 sliding, 5/7 g rolling, horizontal launch, bounce
 * heights); the relative error of the mean and 95th-percentile runout and maximum
 * energy against a converged reference (the exact engine over many more
 * trajectories).  It ends with the throughput ratio of the exact engine over the
 * fixed-step settings whose errors are all at least as large. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "rockfall/sim.h"
#include "scenes.h"

#define N_STATS 2000      /* trajectories per row for the statistics */
#define N_REFERENCE 40000 /* trajectories of the converged reference */
#define MIN_TIMING_S 2.0  /* each throughput measurement runs at least this long */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct stats {
    double runout_mean, runout_p95, energy_mean, energy_p95;
    double runout_se, energy_se; /* standard errors of the means */
} stats;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double p95(double *v, size_t n)
{
    qsort(v, n, sizeof *v, cmp_double);
    size_t rank = (size_t)ceil(0.95 * (double)n);
    return v[(rank ? rank : 1) - 1];
}

/* Runs trajectories first .. first+n-1 of release 0; fills stats when wanted. */
static void run_slope(const rf_project *p, const rf_simulation *sim, long first, long n,
                      stats *st)
{
    rf_scene scene = {&p->terrain, sim, NULL, 0, NULL, 0};
    rf_workspace *ws = rf_workspace_alloc(&p->terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    double *runout = st ? malloc((size_t)n * sizeof *runout) : NULL;
    double *energy = st ? malloc((size_t)n * sizeof *energy) : NULL;
    const rf_release *rel = &p->releases[0];
    for (long k = 0; k < n; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p->seed, 0, first + k));
        rf_body body = rf_release_body(p, 0);
        body.model = sim->model;
        rf_state s0 = rf_release_start(p, 0, &body, rng);
        rf_trajectory_record rec;
        rf_simulate(&scene, &body, &s0, rng, ws, NULL, &rec);
        if (st) {
            runout[k] = hypot(rec.stop.x - rel->x, rec.stop.y - rel->y);
            energy[k] = rec.max_energy_kj;
        }
    }
    if (st) {
        double sr = 0, se = 0, sr2 = 0, se2 = 0;
        for (long k = 0; k < n; k++) {
            sr += runout[k], sr2 += runout[k] * runout[k];
            se += energy[k], se2 += energy[k] * energy[k];
        }
        double dn = (double)n;
        st->runout_mean = sr / dn;
        st->energy_mean = se / dn;
        st->runout_se = sqrt(fmax(sr2 / dn - st->runout_mean * st->runout_mean, 0) / dn);
        st->energy_se = sqrt(fmax(se2 / dn - st->energy_mean * st->energy_mean, 0) / dn);
        st->runout_p95 = p95(runout, (size_t)n);
        st->energy_p95 = p95(energy, (size_t)n);
    }
    free(runout);
    free(energy);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
}

/* Trajectories per second on one thread. */
static double throughput(const rf_project *p, const rf_simulation *sim)
{
    long n = 16, done = 0;
    double t0 = now_s(), t;
    for (;;) {
        run_slope(p, sim, done, n, NULL);
        done += n;
        t = now_s() - t0;
        if (t >= MIN_TIMING_S)
            break;
        n *= 2;
    }
    return (double)done / t;
}

static double rel_err(double a, double b) { return fabs(a - b) / fabs(b); }

typedef struct row {
    const char *name;
    rf_simulation sim;
    double per_s;
    double closed[RF_N_CLOSED_FORMS];
    double err_runout_mean, err_runout_p95, err_energy_mean, err_energy_p95;
} row;

static double worst_closed(const row *r)
{
    double w = 0;
    for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
        w = fmax(w, r->closed[k]);
    return w;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "projects/noto/noto-3.1-no-trees.yaml";
    rf_project p;
    rf_error err;
    if (rf_project_load(path, &p, &err)) {
        rf_error_print(&err, stderr);
        return 2;
    }
    static const double dts[] = {0.01, 0.003, 0.001, 0.0003};
    enum { NROWS = 1 + sizeof dts / sizeof dts[0] };
    row rows[NROWS];
    char names[NROWS][32];
    for (int i = 0; i < NROWS; i++) {
        memset(&rows[i], 0, sizeof rows[i]);
        rows[i].sim = p.sim;
        if (i == 0) {
            rows[i].sim.engine = RF_ENGINE_EXACT;
            snprintf(names[i], sizeof names[i], "exact");
        } else {
            rows[i].sim.engine = RF_ENGINE_FIXED_STEP;
            rows[i].sim.dt = dts[i - 1];
            snprintf(names[i], sizeof names[i], "fixed dt=%g s", dts[i - 1]);
        }
        rows[i].name = names[i];
    }

    fprintf(stderr, "reference: exact engine, %d trajectories ...\n", N_REFERENCE);
    stats ref;
    rf_simulation ref_sim = rows[0].sim;
    run_slope(&p, &ref_sim, 0, N_REFERENCE, &ref);

    for (int i = 0; i < NROWS; i++) {
        row *r = &rows[i];
        fprintf(stderr, "%s ...\n", r->name);
        r->per_s = throughput(&p, &r->sim);
        for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
            r->closed[k] = rf_closed_form_error(k, &r->sim);
        stats st;
        /* Trajectories beyond the reference's, so the row is an independent sample. */
        run_slope(&p, &r->sim, N_REFERENCE, N_STATS, &st);
        r->err_runout_mean = rel_err(st.runout_mean, ref.runout_mean);
        r->err_runout_p95 = rel_err(st.runout_p95, ref.runout_p95);
        r->err_energy_mean = rel_err(st.energy_mean, ref.energy_mean);
        r->err_energy_p95 = rel_err(st.energy_p95, ref.energy_p95);
        if (i == 0)
            printf("Monte Carlo noise of a %d-trajectory mean: runout %.2g, energy %.2g (relative "
                   "standard error)\n\n",
                   N_STATS, st.runout_se / st.runout_mean, st.energy_se / st.energy_mean);
    }

    printf("Example slope %s (%zu triangles), release %s, %g kg, model %s; one thread.\n"
           "Closed-form errors are relative; runout and energy errors are relative to the\n"
           "exact engine over %d trajectories (reference: runout mean %.1f m, p95 %.1f m;\n"
           "max energy mean %.0f kJ, p95 %.0f kJ).\n\n",
           path, p.terrain.ntri, p.releases[0].name, p.rocks[p.releases[0].rock].mass,
           p.sim.model == RF_MODEL_SPHERE ? "sphere" : "point", N_REFERENCE, ref.runout_mean,
           ref.runout_p95, ref.energy_mean, ref.energy_p95);
    printf("| engine | traj/s |");
    for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
        printf(" %s |", rf_closed_form_name(k));
    printf(" runout mean | runout p95 | energy mean | energy p95 |\n|---|---:|");
    for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
        printf("---:|");
    printf("---:|---:|---:|---:|\n");
    for (int i = 0; i < NROWS; i++) {
        const row *r = &rows[i];
        printf("| %s | %.0f |", r->name, r->per_s);
        for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
            printf(" %.1e |", r->closed[k]);
        printf(" %.1e | %.1e | %.1e | %.1e |\n", r->err_runout_mean, r->err_runout_p95,
               r->err_energy_mean, r->err_energy_p95);
    }
    printf("\n");
    /* Fixed-step rows whose every closed-form error is at least the exact engine's. */
    double exact_worst = worst_closed(&rows[0]);
    for (int i = 1; i < NROWS; i++) {
        int all_worse = 1;
        for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
            if (rows[i].closed[k] < rows[0].closed[k])
                all_worse = 0;
        if (all_worse)
            printf("exact / %s: %.1fx the throughput at %.1e vs %.1e worst closed-form error\n",
                   rows[i].name, rows[0].per_s / rows[i].per_s, exact_worst,
                   worst_closed(&rows[i]));
        else
            printf("%s: some closed-form error below the exact engine's; not compared\n",
                   rows[i].name);
    }
    rf_project_free(&p);
    return 0;
}
