/* bench.c - speed against error of the motion engines (`make bench`).
 *
 * One row per engine setting: the exact event-driven engine (full contact, the
 * paper's centre-only contact, and the point mass), and the fixed-step integrator at
 * several dt (which
 * tests contact as the paper does, Eq. 6-7).  Columns: trajectories per second on one
 * thread on the example slope (projects/noto without trees, no database); the
 * relative error against four closed forms (Eq. 1-2 sliding, 5/7 g rolling,
 * horizontal launch, bounce heights); the relative error of the mean and
 * 95th-percentile runout, speed at the road and maximum energy against a converged
 * reference (the exact engine in the same contact mode and rock model over many more
 * trajectories).
 * It ends with the throughput ratios of the exact engine over the fixed-step
 * settings, all of which have larger errors, and the rolling slope's table
 * (roll_table; `bench --roll` prints it alone). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "rockfall/sim.h"
#include "fixtures/scenes.h"
#include "base/util.h"

#define N_STATS 2000      /* trajectories per row for the statistics */
#define N_REFERENCE 40000 /* trajectories of the converged reference */
#define MIN_TIMING_S 1.0  /* each throughput measurement runs at least this long */
#define TIMING_ROUNDS 3   /* rounds of throughput measurements; the fastest counts */

typedef struct stats {
    double runout_mean, runout_p95, energy_mean, energy_p95, road_mean, road_p95;
    double runout_se, energy_se, road_se; /* standard errors of the means */
    /* per trajectory: simulated seconds, and the work of rf_trajectory_record */
    double sim_s, flights, segments, impacts, edges;
} stats;

/* The speed of a trajectory at its first crossing of a control line (the road). */
typedef struct road_probe {
    const rf_measure *measures;
    double speed;
} road_probe;

static void on_crossing(void *ctx, const rf_interception_record *r)
{
    road_probe *rp = ctx;
    if (isnan(rp->speed) && rp->measures[r->measure].kind == RF_CONTROL)
        rp->speed = r->speed_ms;
}

static void mean_se(const double *v, long n, double *mean, double *se)
{
    double s = 0, s2 = 0;
    for (long k = 0; k < n; k++)
        s += v[k], s2 += v[k] * v[k];
    *mean = s / (double)n;
    *se = sqrt(fmax(s2 / (double)n - *mean * *mean, 0) / (double)n);
}

static double p95(double *v, size_t n)
{
    qsort(v, n, sizeof *v, rf_cmp_double);
    size_t rank = (size_t)ceil(0.95 * (double)n);
    return v[(rank ? rank : 1) - 1];
}

/* Runs trajectories first .. first+n-1 of release 0; fills stats when wanted. */
static void run_slope(const rf_project *p, const rf_simulation *sim, long first, long n,
                      stats *st)
{
    rf_scene scene = {&p->terrain, sim, NULL, 0, p->measures, p->nmeasures};
    rf_workspace *ws = rf_workspace_alloc(&p->terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    double *runout = st ? malloc((size_t)n * sizeof *runout) : NULL;
    double *energy = st ? malloc((size_t)n * sizeof *energy) : NULL;
    double *road = st ? malloc((size_t)n * sizeof *road) : NULL;
    long nroad = 0;
    const rf_release *rel = &p->releases[0];
    road_probe rp = {p->measures, NAN};
    rf_sink sink;
    memset(&sink, 0, sizeof sink);
    sink.ctx = &rp;
    sink.interception = on_crossing;
    rf_body body = rf_release_body(p, 0, sim->model); /* in the row's model */
    double work[5] = {0, 0, 0, 0, 0};
    for (long k = 0; k < n; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p->seed, 0, first + k));
        rf_state s0 = rf_release_start(p, 0, &body, rng);
        rf_trajectory_record rec;
        rp.speed = NAN;
        rf_simulate(&scene, &body, &s0, rng, ws, &sink, &rec);
        work[0] += rec.duration_s;
        work[1] += (double)rec.n_flights;
        work[2] += (double)rec.n_segments;
        work[3] += (double)rec.n_impacts;
        work[4] += (double)rec.n_edge_transitions;
        if (st) {
            runout[k] = hypot(rec.stop.x - rel->x, rec.stop.y - rel->y);
            energy[k] = rec.max_energy_kj;
            if (!isnan(rp.speed))
                road[nroad++] = rp.speed;
        }
    }
    if (st) {
        st->sim_s = work[0] / (double)n;
        st->flights = work[1] / (double)n;
        st->segments = work[2] / (double)n;
        st->impacts = work[3] / (double)n;
        st->edges = work[4] / (double)n;
        mean_se(runout, n, &st->runout_mean, &st->runout_se);
        mean_se(energy, n, &st->energy_mean, &st->energy_se);
        st->runout_p95 = p95(runout, (size_t)n);
        st->energy_p95 = p95(energy, (size_t)n);
        if (nroad > 0) {
            mean_se(road, nroad, &st->road_mean, &st->road_se);
            st->road_p95 = p95(road, (size_t)nroad);
        } else {
            st->road_mean = st->road_p95 = st->road_se = NAN;
        }
    }
    free(runout);
    free(energy);
    free(road);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
}

/* Seconds one thread takes for the first n trajectories of a row's setting. */
static double run_seconds(const rf_project *p, const rf_simulation *sim, long n)
{
    double t0 = rf_now_s();
    run_slope(p, sim, 0, n, NULL);
    return rf_now_s() - t0;
}

/* Trajectories to time for one throughput measurement: doubled from 16 until a run
 * takes at least MIN_TIMING_S; *per_s receives that run's trajectories per second (the
 * first round). */
static long timing_count(const rf_project *p, const rf_simulation *sim, double *per_s)
{
    for (long n = 16;; n *= 2) {
        double t = run_seconds(p, sim, n);
        if (t >= MIN_TIMING_S) {
            *per_s = (double)n / t;
            return n;
        }
    }
}

static double rel_err(double a, double b) { return fabs(a - b) / fabs(b); }

typedef struct row {
    const char *name;
    rf_simulation sim;
    double per_s;
    double closed[RF_N_CLOSED_FORMS];
    double err_runout_mean, err_runout_p95, err_energy_mean, err_energy_p95;
    double err_road_mean, err_road_p95;
} row;

static double worst_closed(const row *r)
{
    double w = 0;
    for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
        w = fmax(w, r->closed[k]);
    return w;
}

/* ---- the rolling slope ------------------------------------------------------------ */

/* The rolling-dominated slope (projects/bench, tools/mkroll.c) at three cell sizes,
 * where rocks roll most of the way and the grid's edges, not the bounces, can make the
 * events: per setting and cell size the throughput on one thread, the work per
 * trajectory (flights, surface segments, impacts, edge transitions: events, whose sum
 * the time per event divides), and the statistics with their standard errors (speed at
 * the slope's foot, maximum energy, runout), which are the reference of any change to
 * the engine's events: a change that keeps the physics keeps them within a few
 * standard errors. */
#define N_ROLL 2000

/* The rolling slope's statistics of the engine before the rolling phase on grids
 * (commit c08debc, where every slow meeting of a concave grid edge was an impact), over
 * the same N_ROLL trajectories of each row, measured once with this bench: foot speed
 * (m/s), maximum energy (kJ), runout (m), each mean and standard error, by cell (2, 1,
 * 0.5 m) and setting (roll_table's order). */
static const double roll_before[3][4][6] = {
    {{41.473, 0.050, 5439, 13, 248.81, 0.26},
     {43.466, 0.011, 5957, 5, 248.57, 0.30},
     {41.560, 0.038, 3903, 6, 213.68, 0.18},
     {43.288, 0.011, 5909, 5, 248.56, 0.30}},
    {{41.634, 0.048, 5481, 12, 249.27, 0.25},
     {44.088, 0.010, 6125, 6, 248.48, 0.33},
     {41.590, 0.032, 3905, 6, 214.31, 0.18},
     {43.689, 0.009, 6012, 7, 248.42, 0.35}},
    {{41.791, 0.045, 5520, 12, 248.89, 0.26},
     {44.973, 0.009, 6369, 7, 248.26, 0.35},
     {41.564, 0.037, 3901, 6, 214.65, 0.17},
     {44.159, 0.009, 6138, 7, 248.15, 0.37}},
};

/* One statistic now and before: both with their standard errors, and their difference
 * in standard errors of the difference. */
static void print_against(double now, double se, double before, double se_before, int digits)
{
    double z = (now - before) / sqrt(se * se + se_before * se_before);
    printf(" %.*f +- %.*f / %.*f +- %.*f (%+.1f) |", digits, now, digits, se, digits, before, digits,
           se_before, z);
}

/* The rolling table's statistics (st, by cell and setting) against the engine before
 * the rolling phase on grids (roll_before): within the Monte Carlo noise where the
 * differences stay within a few standard errors.  Centre contact and the fixed step
 * differ by design: their hops off the offset planes' steps at concave grid edges,
 * without friction, became changes of face (docs/engine.md, "Centre contact at concave
 * grid edges"). */
static void roll_reference(const char *const *names, const double *cells, int ncell, int nset,
                           const stats *st)
{
    printf("\nAgainst the engine before the rolling phase on grids (commit c08debc, the same\n"
           "trajectories): now / before, mean +- standard error, and (the difference in standard\n"
           "errors of the difference).\n\n"
           "| cell | engine | foot speed m/s | max energy kJ | runout m |\n|---:|---|---:|---:|---:|\n");
    for (int c = 0; c < ncell && c < 3; c++) {
        for (int i = 0; i < nset && i < 4; i++) {
            const stats *x = &st[c * nset + i];
            const double *b = roll_before[c][i];
            printf("| %g m | %s |", cells[c], names[i]);
            print_against(x->road_mean, x->road_se, b[0], b[1], 3);
            print_against(x->energy_mean, x->energy_se, b[2], b[3], 0);
            print_against(x->runout_mean, x->runout_se, b[4], b[5], 2);
            printf("\n");
        }
    }
}

static void roll_table(void)
{
    static const char *paths[] = {"projects/bench/roll-2m.yaml", "projects/bench/roll.yaml",
                                  "projects/bench/roll-05m.yaml"};
    static const double cells[] = {2.0, 1.0, 0.5};
    static const struct {
        const char *name;
        rf_engine_kind engine;
        rf_contact_kind contact;
        rf_rock_model model;
    } set[] = {{"sphere, full contact", RF_ENGINE_EXACT, RF_CONTACT_FULL, RF_MODEL_SPHERE},
               {"sphere, centre contact", RF_ENGINE_EXACT, RF_CONTACT_CENTRE, RF_MODEL_SPHERE},
               {"point mass", RF_ENGINE_EXACT, RF_CONTACT_FULL, RF_MODEL_POINT},
               {"fixed dt=0.01 s, centre", RF_ENGINE_FIXED_STEP, RF_CONTACT_CENTRE, RF_MODEL_SPHERE}};
    enum { NSET = sizeof set / sizeof set[0], NCELL = sizeof cells / sizeof cells[0] };
    double per_s[NCELL][NSET];
    stats all[NCELL][NSET];
    const char *names[NSET];
    for (int i = 0; i < NSET; i++)
        names[i] = set[i].name;
    printf("Rolling slope (projects/bench, tools/mkroll.c: a 175 m slope, 170 m drop over 180 m,\n"
           "gentle gullies, a 14-degree counter-sloped run-out), %d trajectories per row, one\n"
           "thread.  Per trajectory: simulated seconds, flights, surface segments, impacts and\n"
           "edge transitions; us/event: time over their sum.  Statistics: mean +- standard error.\n\n",
           N_ROLL);
    printf("| cell | engine | traj/s | sim s | flights | segments | impacts | edge transitions "
           "| us/event | foot speed m/s | max energy kJ | runout m |\n"
           "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int c = 0; c < NCELL; c++) {
        rf_project p;
        rf_error err;
        if (rf_project_load(paths[c], &p, &err)) {
            rf_error_print(&err, stderr);
            exit(2);
        }
        for (int i = 0; i < NSET; i++) {
            rf_simulation sim = p.sim;
            sim.engine = set[i].engine;
            sim.contact = set[i].contact;
            sim.model = set[i].model;
            sim.dt = 0.01;
            fprintf(stderr, "rolling slope, %g m: %s ...\n", cells[c], set[i].name);
            stats st;
            double t0 = rf_now_s();
            run_slope(&p, &sim, 0, N_ROLL, &st);
            double best = rf_now_s() - t0;
            for (int round = 1; round < TIMING_ROUNDS; round++)
                best = fmin(best, run_seconds(&p, &sim, N_ROLL));
            per_s[c][i] = N_ROLL / best;
            double events = st.flights + st.segments + st.impacts + st.edges;
            printf("| %g m | %s | %.0f | %.2f | %.1f | %.1f | %.1f | %.1f | %.2f | %.3f +- %.3f "
                   "| %.0f +- %.0f | %.2f +- %.2f |\n",
                   cells[c], set[i].name, per_s[c][i], st.sim_s, st.flights, st.segments,
                   st.impacts, st.edges, 1e6 * best / N_ROLL / events, st.road_mean, st.road_se,
                   st.energy_mean, st.energy_se, st.runout_mean, st.runout_se);
            fflush(stdout);
            all[c][i] = st;
        }
        rf_project_free(&p);
    }
    roll_reference(names, cells, NCELL, NSET, &all[0][0]);
    printf("\n");
    for (int c = 0; c < NCELL; c++)
        printf("%g m cells: full contact / fixed dt=0.01 s: %.2fx the throughput; centre %.2fx; "
               "point mass %.2fx\n",
               cells[c], per_s[c][0] / per_s[c][NSET - 1], per_s[c][1] / per_s[c][NSET - 1],
               per_s[c][2] / per_s[c][NSET - 1]);
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "--roll") == 0) {
        roll_table(); /* the rolling slope alone */
        return 0;
    }
    const char *path = argc > 1 ? argv[1] : "projects/noto/noto-3.1-no-trees.yaml";
    rf_project p;
    rf_error err;
    if (rf_project_load(path, &p, &err)) {
        rf_error_print(&err, stderr);
        return 2;
    }
    /* The fixed-step engine tests contact as the paper does (Eq. 6-7: the face under
     * the centre), so it is compared with the exact engine in the same contact mode;
     * the first row is the exact engine's default (every face, edge and vertex), the
     * third the point mass (Fig. 2, left; the closed forms keep their own rocks, so
     * its closed-form columns are the engine's in full contact). */
    static const double dts[] = {0.01, 0.003, 0.001, 0.0003};
    enum { NEXACT = 3, NFIXED = sizeof dts / sizeof dts[0], NROWS = NEXACT + NFIXED };
    enum { CENTRE = 1 }; /* the exact row in the fixed-step rows' setting (centre contact) */
    static const struct {
        const char *name;
        rf_contact_kind contact;
        rf_rock_model model;
    } exact[NEXACT] = {{"exact, full contact", RF_CONTACT_FULL, RF_MODEL_SPHERE},
                       {"exact, centre contact", RF_CONTACT_CENTRE, RF_MODEL_SPHERE},
                       {"exact, point mass", RF_CONTACT_FULL, RF_MODEL_POINT}};
    row rows[NROWS];
    char fixed_names[NROWS - NEXACT][48];
    for (int i = 0; i < NROWS; i++) {
        memset(&rows[i], 0, sizeof rows[i]);
        rows[i].sim = p.sim;
        rows[i].sim.engine = i < NEXACT ? RF_ENGINE_EXACT : RF_ENGINE_FIXED_STEP;
        if (i < NEXACT) {
            rows[i].name = exact[i].name;
            rows[i].sim.contact = exact[i].contact;
            rows[i].sim.model = exact[i].model;
        } else {
            char *name = fixed_names[i - NEXACT];
            rows[i].sim.contact = exact[CENTRE].contact;
            rows[i].sim.dt = dts[i - NEXACT];
            snprintf(name, sizeof fixed_names[0], "fixed dt=%g s, centre", dts[i - NEXACT]);
            rows[i].name = name;
        }
    }

    stats ref[NEXACT]; /* the converged references: exact engine, each exact row's setting */
    for (int c = 0; c < NEXACT; c++) {
        fprintf(stderr, "reference: %s, %d trajectories ...\n", rows[c].name, N_REFERENCE);
        run_slope(&p, &rows[c].sim, 0, N_REFERENCE, &ref[c]);
    }
    stats noise;
    memset(&noise, 0, sizeof noise);
    for (int i = 0; i < NROWS; i++) {
        row *r = &rows[i];
        const stats *rf = &ref[i < NEXACT ? i : CENTRE];
        fprintf(stderr, "%s ...\n", r->name);
        for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
            r->closed[k] = rf_closed_form_error(k, &r->sim);
        stats st;
        /* Trajectories beyond the reference's, so the row is an independent sample. */
        run_slope(&p, &r->sim, N_REFERENCE, N_STATS, &st);
        r->err_runout_mean = rel_err(st.runout_mean, rf->runout_mean);
        r->err_runout_p95 = rel_err(st.runout_p95, rf->runout_p95);
        r->err_energy_mean = rel_err(st.energy_mean, rf->energy_mean);
        r->err_energy_p95 = rel_err(st.energy_p95, rf->energy_p95);
        r->err_road_mean = rel_err(st.road_mean, rf->road_mean);
        r->err_road_p95 = rel_err(st.road_p95, rf->road_p95);
        if (i == CENTRE)
            noise = st;
    }

    /* Throughput: TIMING_ROUNDS rounds over all rows, each row's fastest round kept, so
     * that a slow spell of a shared machine does not fall on one row alone. */
    long ntime[NROWS];
    fprintf(stderr, "timing round 1 of %d ...\n", TIMING_ROUNDS);
    for (int i = 0; i < NROWS; i++)
        ntime[i] = timing_count(&p, &rows[i].sim, &rows[i].per_s);
    for (int round = 2; round <= TIMING_ROUNDS; round++) {
        fprintf(stderr, "timing round %d of %d ...\n", round, TIMING_ROUNDS);
        for (int i = 0; i < NROWS; i++)
            rows[i].per_s = fmax(rows[i].per_s, ntime[i] / run_seconds(&p, &rows[i].sim, ntime[i]));
    }

    printf("Example slope %s (%zu triangles), release %s, %g kg, model %s; one thread.\n"
           "Closed-form errors are relative.  Statistics of %d trajectories are relative to a\n"
           "converged reference: the exact engine over %d other trajectories in the same\n"
           "contact mode and rock model (centre reference: runout mean %.1f m, road speed mean %.2f m/s,\n"
           "p95 %.2f m/s; max energy mean %.0f kJ, p95 %.0f kJ).  Monte Carlo noise of a\n"
           "%d-trajectory mean (relative standard error): runout %.1e, road speed %.1e,\n"
           "energy %.1e - differences below about twice these are not significant.\n\n",
           path, p.terrain.ntri, p.releases[0].name, p.rocks[p.releases[0].rock].mass,
           p.sim.model == RF_MODEL_SPHERE ? "sphere" : "point", N_STATS, N_REFERENCE,
           ref[CENTRE].runout_mean, ref[CENTRE].road_mean, ref[CENTRE].road_p95,
           ref[CENTRE].energy_mean, ref[CENTRE].energy_p95, N_STATS, noise.runout_se / noise.runout_mean,
           noise.road_se / noise.road_mean, noise.energy_se / noise.energy_mean);
    printf("| engine | traj/s |");
    for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
        printf(" %s |", rf_closed_form_name(k));
    printf(" runout mean | runout p95 | road speed mean | road speed p95 | energy mean | energy p95 |\n|---|---:|");
    for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
        printf("---:|");
    printf("---:|---:|---:|---:|---:|---:|\n");
    for (int i = 0; i < NROWS; i++) {
        const row *r = &rows[i];
        printf("| %s | %.0f |", r->name, r->per_s);
        for (int k = 0; k < RF_N_CLOSED_FORMS; k++)
            printf(" %.1e |", r->closed[k]);
        printf(" %.1e | %.1e | %.1e | %.1e | %.1e | %.1e |\n", r->err_runout_mean,
               r->err_runout_p95, r->err_road_mean, r->err_road_p95, r->err_energy_mean,
               r->err_energy_p95);
    }
    printf("\n");
    /* Every fixed-step row has a larger worst closed-form error than the exact engine
     * (centre contact): the ratio of throughputs at that larger error. */
    const row *ex = &rows[CENTRE];
    double exact_worst = worst_closed(ex);
    for (int i = NEXACT; i < NROWS; i++) {
        const row *r = &rows[i];
        double w = worst_closed(r);
        if (w >= exact_worst)
            printf("exact (centre) / %s: %.1fx the throughput; worst closed-form error %.1e vs %.1e\n",
                   r->name, ex->per_s / r->per_s, exact_worst, w);
        else
            printf("%s: worst closed-form error below the exact engine's; not compared\n", r->name);
    }
    /* The fixed step's error falls about linearly with dt: the step it would need for
     * a worst closed-form error of 1e-6, and its throughput there (cost ~ 1/dt). */
    const row *fine = &rows[NROWS - 1];
    double dt_need = fine->sim.dt * 1e-6 / worst_closed(fine);
    printf("fixed step for a worst closed-form error of 1e-6: dt ~ %.1e s, ~%.2g traj/s; "
           "exact (centre) is ~%.0fx faster at 1e-6, exact (full) ~%.0fx\n",
           dt_need, fine->per_s * dt_need / fine->sim.dt,
           ex->per_s / (fine->per_s * dt_need / fine->sim.dt),
           rows[0].per_s / (fine->per_s * dt_need / fine->sim.dt));
    rf_project_free(&p);
    printf("\n");
    roll_table();
    return 0;
}
