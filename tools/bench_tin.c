/* bench_tin.c - a grid made a TIN (`terrain: {tolerance: T}`): set-up time and size,
 * and speed against error on the example slope (`make bench`, after bench).
 *
 * Part 1: the TIN's set-up (input/tin.c) on the Noto DEM and on synthetic slopes of
 * 500 x 500 to 2 000 x 2 000 nodes: nodes kept, triangles, seconds, and microseconds
 * per grid node (flat when the set-up is linear).
 * Part 2: projects/noto/noto-3.1-no-trees.yaml with T = 0 (the grid) and several T:
 * triangles, load time, trajectories per second on one thread, and the runout, road
 * speed, road energy and maximum energy statistics over the same trajectories (same
 * streams), each with its Monte Carlo standard error; the last columns give each
 * mean's difference from the grid's in units of the standard error of that difference
 * (|z| under 2: within Monte Carlo noise). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/util.h"
#include "input/terrain_io.h"
#include "input/tin.h"
#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "rockfall/sim.h"

#define N_STATS 4000 /* trajectories per row */

static const double TOLS[] = {0.0, 0.01, 0.05, 0.2, 0.5};
enum { NT = sizeof TOLS / sizeof TOLS[0] };

/* ---- part 1: set-up ---------------------------------------------------------------- */

static double synthetic(size_t i, size_t j)
{
    /* a 44-degree slope with gullies and ridges of a few metres and 2 cm of roughness */
    double x = (double)i, y = (double)j;
    uint64_t h = (uint64_t)i * 0x9E3779B97F4A7C15ull ^ (uint64_t)j * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return 0.97 * y + 3.0 * sin(0.045 * x) * cos(0.021 * y) + 1.5 * sin(0.11 * x + 0.07 * y) +
           0.02 * (double)(h % 1000003) / 1000003.0;
}

static void setup_row(const char *name, const rf_asc_grid *g, double tol)
{
    rf_tri_list l = {NULL, 0, 0};
    rf_tin_stats st;
    rf_error err;
    double t0 = rf_now_s();
    if (rf_tin_build(g, tol, name, &l, &st, &err)) {
        rf_error_print(&err, stderr);
        exit(2);
    }
    double s = rf_now_s() - t0;
    size_t n = g->ncols * g->nrows;
    printf("| %s | %zu x %zu | %g | %zu (%.1f %%) | %zu | %.3f | %.2f |\n", name, g->ncols,
           g->nrows, tol, st.vertices, 100.0 * (double)st.vertices / (double)n, st.triangles, s,
           1e6 * s / (double)n);
    rf_tri_list_free(&l);
}

static void part_setup(void)
{
    printf("TIN set-up (greedy insertion, input/tin.c), one thread:\n\n");
    printf("| grid | nodes | T (m) | nodes kept | triangles | seconds | us per grid node |\n");
    printf("|---|---|---:|---:|---:|---:|---:|\n");
    rf_asc_grid g;
    rf_error err;
    if (rf_asc_read("projects/noto/terrain.asc", &g, &err)) {
        rf_error_print(&err, stderr);
        exit(2);
    }
    for (int k = 1; k < NT; k++)
        setup_row("Noto DEM", &g, TOLS[k]);
    rf_asc_free(&g);
    static const size_t sides[] = {500, 1000, 2000};
    for (size_t s = 0; s < sizeof sides / sizeof *sides; s++) {
        size_t n = sides[s];
        rf_asc_grid syn = {n, n, 0.0, 0.0, 1.0, 0, 0.0, malloc(n * n * sizeof(double))};
        if (!syn.z)
            exit(2);
        for (size_t j = 0; j < n; j++)
            for (size_t i = 0; i < n; i++)
                syn.z[j * n + i] = synthetic(i, j);
        setup_row("synthetic slope", &syn, 0.05);
        if (n == 2000)
            setup_row("synthetic slope", &syn, 0.01);
        free(syn.z);
    }
    printf("\n");
}

/* ---- part 2: speed against error ------------------------------------------------------ */

typedef struct sample {
    double mean, se;
} sample;

typedef struct row {
    size_t ntri;
    double load_s, per_s;
    sample runout, runout_p95, road_speed, road_p95, road_energy, energy, energy_p95;
} row;

typedef struct road_probe {
    const rf_measure *measures;
    double speed, energy;
} road_probe;

static void on_crossing(void *ctx, const rf_interception_record *r)
{
    road_probe *rp = ctx;
    if (isnan(rp->speed) && rp->measures[r->measure].kind == RF_CONTROL)
        rp->speed = r->speed_ms, rp->energy = r->energy_kj;
}

static sample mean_se(const double *v, long n)
{
    double s = 0, s2 = 0;
    for (long k = 0; k < n; k++)
        s += v[k], s2 += v[k] * v[k];
    sample m = {n ? s / (double)n : NAN, NAN};
    if (n > 1)
        m.se = sqrt(fmax(s2 / (double)n - m.mean * m.mean, 0) / (double)(n - 1));
    return m;
}

/* The 95th percentile and, as its standard error, a quarter of the distribution-free
 * 95 % interval of order statistics (ranks n p -+ 1.96 sqrt(n p (1 - p))). */
static sample p95(double *v, long n)
{
    sample s = {NAN, NAN};
    if (n < 2)
        return s;
    qsort(v, (size_t)n, sizeof *v, rf_cmp_double);
    double c = 0.95 * (double)n, w = 1.96 * sqrt((double)n * 0.95 * 0.05);
    long r = (long)ceil(c), lo = (long)floor(c - w), hi = (long)ceil(c + w);
    lo = lo < 1 ? 1 : lo, hi = hi > n ? n : hi;
    s.mean = v[(r ? r : 1) - 1];
    s.se = (v[hi - 1] - v[lo - 1]) / (2.0 * 1.96);
    return s;
}

/* The grid's own triangles (SW-NE) as an OBJ file, exact in %.17g: the same surface
 * through the engine's mesh path, which tells the mesh path's share of a TIN's
 * difference from its approximation's. */
static void write_grid_obj(const char *path)
{
    rf_asc_grid g;
    rf_error err;
    FILE *f = fopen(path, "w");
    if (!f || rf_asc_read("projects/noto/terrain.asc", &g, &err))
        exit(2);
    for (size_t j = 0; j < g.nrows; j++)
        for (size_t i = 0; i < g.ncols; i++)
            fprintf(f, "v %.17g %.17g %.17g\n", g.x0 + (double)i * g.cell,
                    g.y0 + (double)j * g.cell, g.z[j * g.ncols + i]);
    for (size_t j = 0; j + 1 < g.nrows; j++)
        for (size_t i = 0; i + 1 < g.ncols; i++) {
            size_t sw = j * g.ncols + i + 1, se = sw + 1, nw = sw + g.ncols, ne = nw + 1;
            fprintf(f, "f %zu %zu %zu\nf %zu %zu %zu\n", sw, se, ne, sw, ne, nw);
        }
    rf_asc_free(&g);
    fclose(f);
}

/* One row: the example project on the grid made a TIN within tol, or (mesh) on the
 * grid's triangles read as a mesh. */
static row run_row(const char *yaml, double tol, const char *mesh)
{
    row r;
    memset(&r, 0, sizeof r);
    char path[] = "/tmp/rockfall-bench-tin-XXXXXX.yaml";
    int fd = mkstemps(path, 5);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f)
        exit(2);
    /* the example project with its dem made absolute and the tolerance beside it */
    const char *dem = strstr(yaml, "  dem: terrain.asc\n");
    if (!dem)
        exit(2);
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd))
        exit(2);
    if (mesh)
        fprintf(f, "%.*s  mesh: %s\n", (int)(dem - yaml), yaml, mesh);
    else
        fprintf(f, "%.*s  dem: %s/projects/noto/terrain.asc\n", (int)(dem - yaml), yaml, cwd);
    if (tol > 0)
        fprintf(f, "  tolerance: %g\n", tol);
    fputs(dem + strlen("  dem: terrain.asc\n"), f);
    fclose(f);

    rf_project p;
    rf_error err;
    double t0 = rf_now_s();
    if (rf_project_load(path, &p, &err)) {
        rf_error_print(&err, stderr);
        exit(2);
    }
    r.load_s = rf_now_s() - t0;
    remove(path);
    r.ntri = p.terrain.ntri;

    rf_scene scene = {&p.terrain, &p.sim, NULL, 0, p.measures, p.nmeasures};
    rf_workspace *ws = rf_workspace_alloc(&p.terrain);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    double *runout = malloc(N_STATS * sizeof *runout), *energy = malloc(N_STATS * sizeof *energy);
    double *speed = malloc(N_STATS * sizeof *speed), *road_e = malloc(N_STATS * sizeof *road_e);
    if (!ws || !rng || !runout || !energy || !speed || !road_e)
        exit(2);
    long nroad = 0;
    const rf_release *rel = &p.releases[0];
    road_probe rp = {p.measures, NAN, NAN};
    rf_sink sink;
    memset(&sink, 0, sizeof sink);
    sink.ctx = &rp;
    sink.interception = on_crossing;
    rf_body body = rf_release_body(&p, 0, p.sim.model);
    t0 = rf_now_s();
    for (long k = 0; k < N_STATS; k++) {
        gsl_rng_set(rng, rf_trajectory_seed(p.seed, 0, k));
        rf_state s0 = rf_release_start(&p, 0, &body, rng);
        rf_trajectory_record rec;
        rp.speed = rp.energy = NAN;
        rf_simulate(&scene, &body, &s0, rng, ws, &sink, &rec);
        runout[k] = hypot(rec.stop.x - rel->x, rec.stop.y - rel->y);
        energy[k] = rec.max_energy_kj;
        if (!isnan(rp.speed))
            speed[nroad] = rp.speed, road_e[nroad++] = rp.energy;
    }
    r.per_s = N_STATS / (rf_now_s() - t0);
    r.runout = mean_se(runout, N_STATS);
    r.energy = mean_se(energy, N_STATS);
    r.road_speed = mean_se(speed, nroad);
    r.road_energy = mean_se(road_e, nroad);
    r.runout_p95 = p95(runout, N_STATS);
    r.energy_p95 = p95(energy, N_STATS);
    r.road_p95 = p95(speed, nroad);
    free(runout), free(energy), free(speed), free(road_e);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_project_free(&p);
    return r;
}

/* The difference of a from the grid's b in standard errors of the difference. */
static double z_of(sample a, sample b) { return (a.mean - b.mean) / hypot(a.se, b.se); }

/* Each row's difference from the reference row g: in standard errors of the
 * difference, z (|z| < 2: within Monte Carlo noise), and relative to g's value. */
static void z_table(const row *rows, int n, const row *extra, const row *g, const char *what)
{
    printf("\nDifference from %s in standard errors of the difference, z (|z| < 2: within\n"
           "Monte Carlo noise), and relative to its value:\n\n", what);
    printf("| T (m) | runout mean | runout p95 | road speed mean | road speed p95 |"
           " road energy mean | max energy mean | max energy p95 |\n");
    printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int k = 1; k <= n; k++) {
        const row *r = k < n ? &rows[k] : extra;
        if (!r)
            continue;
        if (k == n)
            printf("| grid as a mesh");
        else
            printf("| %g", TOLS[k]);
        const sample *a[7] = {&r->runout, &r->runout_p95, &r->road_speed, &r->road_p95,
                              &r->road_energy, &r->energy, &r->energy_p95};
        const sample *b[7] = {&g->runout, &g->runout_p95, &g->road_speed, &g->road_p95,
                              &g->road_energy, &g->energy, &g->energy_p95};
        for (int c = 0; c < 7; c++)
            printf(" | %+.1f (%+.2f %%)", z_of(*a[c], *b[c]),
                   100.0 * (a[c]->mean - b[c]->mean) / b[c]->mean);
        printf(" |\n");
    }
}

static void part_speed_error(void)
{
    char *yaml;
    size_t len;
    rf_error err;
    if (rf_read_file("projects/noto/noto-3.1-no-trees.yaml", 1 << 20, &yaml, &len, &err)) {
        rf_error_print(&err, stderr);
        exit(2);
    }
    row rows[NT], as_mesh;
    for (int k = 0; k < NT; k++)
        rows[k] = run_row(yaml, TOLS[k], NULL);
    char obj[] = "/tmp/rockfall-bench-tin-XXXXXX.obj";
    int fd = mkstemps(obj, 4);
    if (fd < 0)
        exit(2);
    close(fd);
    write_grid_obj(obj);
    as_mesh = run_row(yaml, 0.0, obj);
    remove(obj);
    free(yaml);
    printf("Speed against error of the TIN on the example slope (noto-3.1-no-trees, %d\n"
           "trajectories on one thread, the same streams in every row; mean +- standard error):\n\n",
           N_STATS);
    printf("| T (m) | triangles | load s | trajectories/s | runout mean (m) | runout p95 (m) |"
           " road speed mean (m/s) | road speed p95 (m/s) | road energy mean (kJ) |"
           " max energy mean (kJ) | max energy p95 (kJ) |\n");
    printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int k = 0; k <= NT; k++) {
        const row *r = k < NT ? &rows[k] : &as_mesh;
        if (k == NT)
            printf("| grid as a mesh");
        else
            printf("| %s%g", k ? "" : "grid ", TOLS[k]);
        printf(" | %zu | %.3f | %.0f | %.2f +- %.2f | %.1f +- %.1f | %.2f +- %.2f | "
               "%.2f +- %.2f | %.0f +- %.0f | %.0f +- %.0f | %.0f +- %.0f |\n",
               r->ntri, r->load_s, r->per_s, r->runout.mean,
               r->runout.se, r->runout_p95.mean, r->runout_p95.se, r->road_speed.mean,
               r->road_speed.se, r->road_p95.mean, r->road_p95.se, r->road_energy.mean,
               r->road_energy.se, r->energy.mean, r->energy.se, r->energy_p95.mean,
               r->energy_p95.se);
    }
    z_table(rows, NT, &as_mesh, &rows[0], "the grid");
    z_table(rows, NT, NULL, &as_mesh, "the grid as a mesh (the engine's same path)");
}

int main(void)
{
    part_setup();
    part_speed_error();
    return 0;
}
