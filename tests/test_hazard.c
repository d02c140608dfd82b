/* test_hazard.c - the hazard map: which cells a trajectory reaches, with what values. */
#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/stats.h"
#include "run/hazard.h"
#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "results/store.h"
#include "db_test_util.h"
#include "test.h"

/* A hazard grid of `cell` over a terrain spanning [x0, x1] x [0, y1]. */
static void grid_over(rf_hazard *h, double x0, double x1, double y1, double cell)
{
    rf_terrain t;
    memset(&t, 0, sizeof t);
    t.xmin = x0, t.xmax = x1, t.ymin = 0, t.ymax = y1;
    ENSURE(rf_hazard_init(h, &t, cell) == 0);
}

/* A 4 x 4 grid of 1 m cells over [0, 4]^2. */
static void grid4(rf_hazard *h)
{
    grid_over(h, 0, 4, 4, 1.0);
    ENSURE(h->nx == 4 && h->ny == 4);
}

/* Trajectories that passed cell (ix, iy). */
static long passes(const rf_hazard *h, int ix, int iy)
{
    const rf_hazard_cell *c = rf_hazard_at(h, (size_t)ix, (size_t)iy);
    return c ? (long)c->energy_kj.n : 0;
}

/* The k-th smallest energy and height of a cell that holds its values exactly. */
static double energy(const rf_hazard *h, int ix, int iy, int k)
{
    const rf_hazard_cell *c = rf_hazard_at(h, (size_t)ix, (size_t)iy);
    ENSURE(c && (uint64_t)k < c->energy_kj.n && c->energy_kj.n <= RF_QSUM_EXACT);
    return c->energy_kj.v[k];
}

static double height(const rf_hazard *h, int ix, int iy, int k)
{
    const rf_hazard_cell *c = rf_hazard_at(h, (size_t)ix, (size_t)iy);
    ENSURE(c && (uint64_t)k < c->height_m.n && c->height_m.n <= RF_QSUM_EXACT);
    return c->height_m.v[k];
}

static int reached_cells(const rf_hazard *h)
{
    return (int)h->ncells;
}

TEST(hazard_cell_clipped_between_two_samples_is_reached)
{
    rf_hazard h;
    grid4(&h);
    rf_hazard_begin(&h);
    /* from (0.95, 0.5) to (1.5, 1.05): the line clips cell (1, 0) between x = 1
     * (s = 1/11) and y = 1 (s = 10/11); neither sample lies in it */
    rf_hazard_sample(&h, 0.95, 0.5, 10.0, 1.0);
    rf_hazard_sample(&h, 1.5, 1.05, 21.0, 3.2);
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(passes(&h, 0, 0) == 1 && passes(&h, 1, 0) == 1 && passes(&h, 1, 1) == 1);
    ENSURE(passes(&h, 0, 1) == 0 && passes(&h, 2, 1) == 0);
    ENSURE(reached_cells(&h) == 3);
    /* each cell the largest value over its stretch, linear between the samples */
    ENSURE_REL(energy(&h, 0, 0, 0), 11.0, 1e-6);
    ENSURE_REL(energy(&h, 1, 0, 0), 20.0, 1e-6);
    ENSURE_REL(height(&h, 1, 0, 0), 3.0, 1e-6);
    ENSURE_REL(energy(&h, 1, 1, 0), 21.0, 1e-6);
    ENSURE_REL(height(&h, 0, 0, 0), 1.2, 1e-6);
    rf_hazard_free(&h);
}

TEST(hazard_point_on_the_far_edge_is_in_the_last_cell)
{
    rf_hazard h;
    grid4(&h);
    rf_hazard_begin(&h);
    rf_hazard_sample(&h, 4.0, 4.0, 5.0, 0.0); /* the terrain's far corner */
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(passes(&h, 3, 3) == 1);
    /* beyond the terrain: nothing; a walk there from inside reaches the cells inside */
    rf_hazard_begin(&h);
    rf_hazard_sample(&h, 3.5, 0.5, 1.0, 0.0);
    rf_hazard_sample(&h, 4.5, 0.5, 1.0, 0.0);
    rf_hazard_sample(&h, 5.5, 0.5, 1.0, 0.0);
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(passes(&h, 3, 0) == 1);
    ENSURE(reached_cells(&h) == 2);
    rf_hazard_free(&h);
}

TEST(hazard_samples_of_one_trajectory_count_once_per_cell)
{
    rf_hazard h;
    grid4(&h);
    for (int traj = 0; traj < 2; traj++) {
        rf_hazard_begin(&h);
        /* there and back along row 2: every cell once per trajectory, the largest
         * value kept */
        double xs[] = {0.5, 1.5, 2.5, 3.5, 2.5, 1.5, 0.2};
        for (int k = 0; k < 7; k++)
            rf_hazard_sample(&h, xs[k], 2.5, 1.0 + k, 0.5);
        ENSURE(rf_hazard_end(&h) == 0);
    }
    for (int ix = 0; ix < 4; ix++)
        ENSURE(passes(&h, ix, 2) == 2);
    ENSURE_REL(energy(&h, 0, 2, 1), 7.0, 1e-6);
    ENSURE_REL(energy(&h, 3, 2, 1), 4.5, 1e-6); /* back to x = 3 at 4.5 */
    rf_hazard_free(&h);
}

/* Through a grid corner exactly the path goes on diagonally; a sample that is not a
 * number (or infinite) reaches nothing and breaks no walk; samples farther apart than
 * the walk goes reach the new sample's cell. */
TEST(hazard_walk_corner_nan_and_far_samples)
{
    rf_hazard h;
    grid4(&h);
    rf_hazard_begin(&h);
    rf_hazard_sample(&h, 0.5, 0.5, 1.0, 0.0);
    rf_hazard_sample(&h, 2.5, 2.5, 1.0, 0.0); /* through the corners (1, 1) and (2, 2) */
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(reached_cells(&h) == 3);
    for (int i = 0; i < 3; i++)
        ENSURE(passes(&h, i, i) == 1);
    rf_hazard_free(&h);

    grid4(&h);
    rf_hazard_begin(&h);
    rf_hazard_sample(&h, 0.5, 3.5, 1.0, 0.0);
    rf_hazard_sample(&h, NAN, 3.5, 1.0, 0.0);
    rf_hazard_sample(&h, INFINITY, 3.5, 1.0, 0.0);
    rf_hazard_sample(&h, INFINITY, -INFINITY, 1.0, 0.0);
    rf_hazard_sample(&h, 2.5, 3.5, 1.0, 0.0); /* the walk goes on from (0.5, 3.5) */
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(reached_cells(&h) == 3);
    ENSURE(passes(&h, 1, 3) == 1);
    rf_hazard_free(&h);

    /* a grid of 1000 x 1 cells: 900 cells between two samples is beyond the walk */
    grid_over(&h, 0, 1000, 1, 1.0);
    rf_hazard_begin(&h);
    rf_hazard_sample(&h, 0.5, 0.5, 1.0, 0.0);
    rf_hazard_sample(&h, 900.5, 0.5, 1.0, 0.0);
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(reached_cells(&h) == 2 && passes(&h, 900, 0) == 1);
    rf_hazard_free(&h);
}

/* The far edge of grids whose size is no exact product: a lone sample there is in the
 * last cell (a product test missed about 0.7 % of such grids). */
TEST(hazard_far_edge_of_inexact_grids)
{
    long missed = 0, tried = 0;
    for (int i = 0; i < 2000; i++) {
        double x0 = 100.0 + 0.37 * i, cell = 0.5 + 0.0137 * (i % 617), n = 1 + i % 211;
        double xmax = x0 + n * cell;
        rf_hazard h;
        grid_over(&h, x0, xmax, cell, cell);
        rf_hazard_begin(&h);
        rf_hazard_sample(&h, xmax, 0.5 * cell, 1.0, 0.0);
        ENSURE(rf_hazard_end(&h) == 0);
        missed += reached_cells(&h) != 1;
        tried++;
        rf_hazard_free(&h);
    }
    ENSURE_MSG(missed == 0, "%ld of %ld far edges outside the grid", missed, tried);
    /* the reviewed case */
    rf_hazard h;
    grid_over(&h, 154.9, 1172.95, 1, 6.17);
    rf_hazard_begin(&h);
    rf_hazard_sample(&h, 1172.95, 0.5, 1.0, 0.0);
    ENSURE(rf_hazard_end(&h) == 0);
    ENSURE(passes(&h, (int)h.nx - 1, 0) == 1);
    rf_hazard_free(&h);
}

/* Whether run's hazard cells hold the cell of point (x, y) of the terrain, relative to
 * the grid's origin; -1 when the point lies off the grid (a rock that left the terrain
 * can stop beyond it).  On the far edge the point is in the last cell. */
static int reaches_cell(sqlite3 *h, int run, double x, double y, double cellsz, double nx,
                        double ny)
{
    if (!(x >= 0 && y >= 0 && x <= nx * cellsz && y <= ny * cellsz))
        return -1;
    double fx = fmin(floor(x / cellsz), nx - 1), fy = fmin(floor(y / cellsz), ny - 1);
    return dbt_int(h, "SELECT count(*) FROM hazard_cells WHERE run_id = %d AND ix = %.0f AND "
                      "iy = %.0f", run, fx, fy) == 1;
}

/* One trajectory per run: its cells are one edge-connected chain that holds the
 * release's cell (the first point of its path) and the stop's. */
TEST(hazard_cells_of_a_trajectory_are_an_unbroken_chain)
{
    char db[600];
    snprintf(db, sizeof db, "%s/chain.db", rf_test_tmpdir());
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load("projects/noto/noto-3.3.yaml", &p, &err) == 0, "%s", err.message);
    ENSURE(p.sim.paths >= 1); /* the path's first point is the release */
    rf_store *s;
    ENSURE(rf_store_open(db, &s, &err) == 0);
    const int nruns = 24;
    for (int r = 0; r < nruns; r++) {
        for (size_t i = 0; i < p.nreleases; i++)
            p.releases[i].count = i == (size_t)r % p.nreleases ? 1 : 0;
        p.seed = 100 + (uint64_t)r;
        rf_run_options o = {.threads = 1};
        rf_run_summary sum;
        ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    }
    double cellsz = p.hazard_cell, xmin = p.terrain.xmin, ymin = p.terrain.ymin, nx, ny;
    rf_hazard_grid(&p.terrain, cellsz, &nx, &ny);
    rf_store_close(s);
    rf_project_free(&p);
    sqlite3 *h;
    ENSURE(sqlite3_open(db, &h) == SQLITE_OK);
    long broken_total = 0, stops_checked = 0;
    for (int run = 1; run <= nruns; run++) {
        long n = dbt_int(h, "SELECT count(*) FROM hazard_cells WHERE run_id = %d", run);
        ENSURE_MSG(n >= 1, "run %d: no cell", run);
        ENSURE(dbt_int(h, "SELECT max(passes) FROM hazard_cells WHERE run_id = %d", run) == 1);
        /* the cells reached from the first by steps across an edge */
        long connected = dbt_int(
            h,
            "WITH RECURSIVE c(ix, iy) AS (SELECT ix, iy FROM (SELECT ix, iy FROM hazard_cells "
            "WHERE run_id = %d LIMIT 1) UNION SELECT h.ix, h.iy FROM hazard_cells h, c WHERE "
            "h.run_id = %d AND abs(h.ix - c.ix) + abs(h.iy - c.iy) = 1) SELECT count(*) FROM c",
            run, run);
        broken_total += n - connected;
        const char *first = "SELECT %s - %.17g FROM path_points p JOIN trajectories t ON "
                            "p.trajectory_id = t.id WHERE t.run_id = %d AND p.seq = 0";
        double rx = dbt_real(h, first, "x", xmin, run), ry = dbt_real(h, first, "y", ymin, run);
        ENSURE_MSG(reaches_cell(h, run, rx, ry, cellsz, nx, ny) == 1,
                   "run %d: the release's cell not reached", run);
        double sx = dbt_real(h, "SELECT stop_x - %.17g FROM trajectories WHERE run_id = %d",
                             xmin, run);
        double sy = dbt_real(h, "SELECT stop_y - %.17g FROM trajectories WHERE run_id = %d",
                             ymin, run);
        int stop = reaches_cell(h, run, sx, sy, cellsz, nx, ny);
        ENSURE_MSG(stop != 0, "run %d: the stop's cell not reached", run);
        stops_checked += stop == 1;
    }
    ENSURE(stops_checked >= nruns / 2);
    ENSURE_MSG(broken_total == 0, "%ld cells apart from their trajectory's chain", broken_total);
    sqlite3_close(h);
}

/* ---- the cells' bounded summaries ------------------------------------------------- */

static uint64_t lcg(uint64_t *st)
{
    *st = *st * 6364136223846793005ull + 1442695040888963407ull;
    return *st >> 33;
}

/* A value as a run gives them: mostly spread over decades, some zeros, some below
 * the scale, a few ties. */
static float draw_value(uint64_t *st)
{
    uint64_t r = lcg(st) % 100;
    if (r < 5)
        return 0.0f;
    if (r < 8)
        return (float)(lcg(st) % 1000) * 1e-7f; /* below 2^-10 */
    if (r < 12)
        return 42.0f;
    return (float)pow(10.0, -2.0 + 6.0 * (double)(lcg(st) % 1000003) / 1000003.0);
}

/* The canonical bytes of a summary, in `buf` (at most 64 KiB); their length. */
static size_t encode(const rf_qsum *s, unsigned char *buf)
{
    size_t n = rf_qsum_encode(s, buf, 65536);
    ENSURE(n <= 65536);
    return n;
}

/* n values added one by one in the given order, or cut into `parts` parts (each
 * added in its own order) merged in a shuffled order. */
static void summarise(rf_qsum *out, const float *v, size_t n, int parts, uint64_t *st)
{
    size_t *perm = malloc((n ? n : 1) * sizeof *perm);
    int *part_of = malloc((n ? n : 1) * sizeof *part_of);
    ENSURE(perm && part_of);
    for (size_t i = 0; i < n; i++) {
        perm[i] = i;
        part_of[i] = (int)(lcg(st) % (uint64_t)parts);
    }
    for (size_t i = n; i > 1; i--) { /* Fisher-Yates */
        size_t j = lcg(st) % i, t = perm[i - 1];
        perm[i - 1] = perm[j], perm[j] = t;
    }
    rf_qsum part[8];
    memset(part, 0, sizeof part);
    for (size_t i = 0; i < n; i++)
        ENSURE(rf_qsum_add(&part[part_of[perm[i]]], &RF_HAZARD_ENERGY_SCALE, v[perm[i]]) == 0);
    memset(out, 0, sizeof *out);
    int order[8];
    for (int k = 0; k < parts; k++)
        order[k] = k;
    for (int k = parts; k > 1; k--) {
        int j = (int)(lcg(st) % (uint64_t)k), t = order[k - 1];
        order[k - 1] = order[j], order[j] = t;
    }
    /* half the parts merged pairwise first, as threads and then machines would */
    if (parts >= 4)
        ENSURE(rf_qsum_merge(&part[order[0]], &part[order[1]], &RF_HAZARD_ENERGY_SCALE) == 0);
    for (int k = 0; k < parts; k++)
        if (!(parts >= 4 && k == 1))
            ENSURE(rf_qsum_merge(out, &part[order[k]], &RF_HAZARD_ENERGY_SCALE) == 0);
    for (int k = 0; k < parts; k++)
        rf_qsum_free(&part[k]);
    free(perm);
    free(part_of);
}

/* The same values give the same summary, to the byte, whatever their order and however
 * they are split and merged: below the exact limit, at it, just past it, far past it. */
TEST(hazard_summary_same_bytes_any_order_and_split)
{
    static unsigned char a[65536], b[65536];
    size_t sizes[] = {0, 1, 7, RF_QSUM_EXACT - 1, RF_QSUM_EXACT, RF_QSUM_EXACT + 1, 300, 20000};
    uint64_t st = 12345;
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        size_t n = sizes[k];
        float *v = malloc((n ? n : 1) * sizeof *v);
        ENSURE(v);
        for (size_t i = 0; i < n; i++)
            v[i] = draw_value(&st);
        if (n > 10)
            v[3] = -0.0f, v[4] = 1e30f; /* a signed zero, a value above the scale */
        rf_qsum ref;
        summarise(&ref, v, n, 1, &st);
        size_t la = encode(&ref, a);
        for (int trial = 0; trial < 12; trial++) {
            rf_qsum s;
            summarise(&s, v, n, 1 + trial % 8, &st);
            size_t lb = encode(&s, b);
            ENSURE_MSG(la == lb && memcmp(a, b, la) == 0,
                       "%zu values, %d parts: the summary differs", n, 1 + trial % 8);
            rf_qsum_free(&s);
        }
        rf_qsum_free(&ref);
        free(v);
    }
}

/* Up to RF_QSUM_EXACT values the quantiles are the nearest-rank ones, to the bit;
 * beyond, within 2^(1/64) - 1 of them on the scale (docs/database.md), the largest
 * value exact, a cell of zeros exactly zero. */
TEST(hazard_summary_exact_below_k_then_within_the_stated_error)
{
    const double tol = pow(2.0, 1.0 / 64.0) - 1.0 + 1e-6;
    const double qs[] = {0.05, 0.5, 0.95, 0.99, 1.0};
    uint64_t st = 777;
    size_t sizes[] = {1, 20, RF_QSUM_EXACT, RF_QSUM_EXACT + 1, 1000, 50000};
    double worst = 0;
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        size_t n = sizes[k];
        float *v = malloc(n * sizeof *v);
        ENSURE(v);
        rf_qsum s = {0};
        for (size_t i = 0; i < n; i++) {
            v[i] = (float)pow(10.0, -1.0 + 5.0 * (double)(lcg(&st) % 1000003) / 1000003.0);
            ENSURE(rf_qsum_add(&s, &RF_HAZARD_ENERGY_SCALE, v[i]) == 0);
        }
        for (size_t j = 0; j < sizeof qs / sizeof *qs; j++) {
            double want = rf_percentile_nearest_rank(v, n, qs[j]);
            double got = rf_qsum_quantile(&s, &RF_HAZARD_ENERGY_SCALE, qs[j]);
            if (n <= RF_QSUM_EXACT)
                ENSURE_MSG(got == want, "n %zu q %g: %.9g, exact %.9g", n, qs[j], got, want);
            else
                ENSURE_MSG(fabs(got / want - 1.0) <= tol, "n %zu q %g: %.9g, exact %.9g", n,
                           qs[j], got, want);
            worst = fmax(worst, fabs(got / want - 1.0));
        }
        ENSURE(s.max == v[n - 1]); /* sorted by the percentile */
        rf_qsum_free(&s);
        free(v);
    }
    ENSURE(worst > 1e-4); /* the bins were used */
    /* below the scale: the largest value there; a cell of zeros: zero */
    rf_qsum z = {0};
    for (int i = 0; i < 1000; i++)
        ENSURE(rf_qsum_add(&z, &RF_HAZARD_HEIGHT_SCALE, i < 990 ? 0.0f : 5e-4f) == 0);
    ENSURE(rf_qsum_quantile(&z, &RF_HAZARD_HEIGHT_SCALE, 0.95) == 0.0);
    ENSURE(rf_qsum_quantile(&z, &RF_HAZARD_HEIGHT_SCALE, 1.0) == (double)5e-4f);
    rf_qsum_free(&z);
}

/* Trajectories down the columns of a 10 x 10 grid, each with its energy (spread over
 * three decades) and height.  The memory is bounded by the cells reached, whatever the
 * count: a summary holds at most the bins of its scale (it grows only while the values
 * reach bins not reached before); and from 1 000 passes a cell to 10 000, ten times
 * the trajectories take no more than 10 % more (the values were once kept one per
 * pass: ten times as much). */
TEST(hazard_memory_flat_in_the_trajectories)
{
    rf_hazard h;
    grid_over(&h, 0, 10, 10, 1.0);
    uint64_t st = 99;
    size_t bytes_at[2] = {0, 0};
    for (long traj = 0; traj < 100000; traj++) {
        double x = 0.5 + (double)(traj % 10);
        double e = pow(10.0, 3.0 * (double)(lcg(&st) % 10007) / 10007.0);
        double hgt = 0.5 + 0.01 * (double)(lcg(&st) % 100);
        rf_hazard_begin(&h);
        for (int k = 0; k <= 40; k++)
            rf_hazard_sample(&h, x, 10.0 - 0.25 * k, e, hgt);
        ENSURE(rf_hazard_end(&h) == 0);
        if (traj + 1 == 10000)
            bytes_at[0] = rf_hazard_bytes(&h);
    }
    bytes_at[1] = rf_hazard_bytes(&h);
    ENSURE(rf_hazard_at(&h, 0, 0)->energy_kj.n == 10000);
    ENSURE_MSG((double)bytes_at[1] <= 1.10 * (double)bytes_at[0],
               "hazard map: %zu bytes at 10 000 trajectories, %zu at 100 000", bytes_at[0],
               bytes_at[1]);
    /* the bound: every summary within its scale's bins (and the four beside them) */
    size_t bound = h.cap_cells * sizeof *h.cells + h.cap_touched * sizeof *h.touched +
                   (h.where.cap + h.slot.cap) * 3 * sizeof(uint32_t) +
                   h.ncells * sizeof(uint64_t) *
                       (size_t)(4 + 4 + RF_QSUM_PER_OCTAVE *
                                        (RF_HAZARD_ENERGY_SCALE.hi_exp - RF_HAZARD_ENERGY_SCALE.lo_exp +
                                         RF_HAZARD_HEIGHT_SCALE.hi_exp - RF_HAZARD_HEIGHT_SCALE.lo_exp));
    ENSURE(bytes_at[1] <= bound);
    printf("    hazard map: %zu bytes at 10 000 trajectories, %zu at 100 000 (bound %zu)\n",
           bytes_at[0], bytes_at[1], bound);
    rf_hazard_free(&h);
}
