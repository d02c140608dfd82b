/* test_grid_compact.c - a grid kept as its heights: the triangles, boxes, edge lengths and
 * live edges it derives are the ones of the grid that keeps its triangles, bit for bit,
 * holes and zones included; a 2 000 x 2 000 grid loads and runs within a memory bound. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gsl/gsl_rng.h>

#include "rockfall/body.h"
#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "engine/state.h"
#include "engine/tables.h"
#include "motion_test_util.h"
#include "results/store.h"
#include "test.h"

static const rf_surface SURF = {{0.35, 0.05}, {0.3, 0.05}, {0.3, 0.05}};

/* The text of an ncols x nrows grid of 2.5 m cells with a wavy, steep surface, nodata
 * in a disc and at one corner node. */
static char *wavy_grid_text(size_t ncols, size_t nrows)
{
    size_t cap = 200 + ncols * nrows * 16, used = 0;
    char *text = malloc(cap);
    ENSURE(text);
    used += (size_t)snprintf(text, cap,
                             "ncols %zu\nnrows %zu\nxllcenter 612.385\nyllcenter -41.75\n"
                             "cellsize 2.5\nNODATA_value -9999\n",
                             ncols, nrows);
    for (size_t r = 0; r < nrows; r++) {
        size_t j = nrows - 1 - r;
        for (size_t i = 0; i < ncols; i++) {
            double di = (double)i - 0.3 * (double)ncols, dj = (double)j - 0.6 * (double)nrows;
            int hole = di * di + dj * dj < 9.0 || (i == ncols - 1 && j == 0);
            double z = 0.9 * (double)j + 2.385 * sin(0.7 * (double)i) * cos(0.45 * (double)j) +
                       0.01 * (double)((i * 7 + j * 13) % 11);
            char sep = i + 1 == ncols ? '\n' : ' ';
            if (hole)
                used += (size_t)snprintf(text + used, cap - used, "-9999%c", sep);
            else
                used += (size_t)snprintf(text + used, cap - used, "%.3f%c", z, sep);
        }
    }
    return text;
}

static void build(const char *path, int derive, const rf_zone_spec *zones, size_t nzones,
                  rf_terrain *t)
{
    char *files[1] = {(char *)path};
    rf_terrain_spec spec = {.source = RF_TERRAIN_DEM, .files = files, .nfiles = 1, .up = 'z',
                            .surface = SURF, .zones = (rf_zone_spec *)zones, .nzones = nzones,
                            .grid_derive = derive};
    rf_error err;
    ENSURE_MSG(rf_terrain_build(&spec, t, &err) == 0, "%s", err.message);
}

static int same_vec(rf_vec3 a, rf_vec3 b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Kept and derived: every triangle, zone, box, edge length and live-edge flag the same
 * bytes; the same holes, bounds, location and tables' summaries. */
static void ensure_same_grid(const rf_terrain *kept, const rf_terrain *der)
{
    ENSURE(kept->tri != NULL && der->tri == NULL && kept->is_grid && der->is_grid);
    ENSURE(kept->ntri == der->ntri && kept->ntri == 2 * (kept->nx - 1) * (kept->ny - 1));
    ENSURE(kept->xmin == der->xmin && kept->xmax == der->xmax && kept->ymin == der->ymin &&
           kept->ymax == der->ymax && kept->zmin == der->zmin && kept->zmax == der->zmax);
    rf_workspace *wk = rf_workspace_alloc(kept), *wd = rf_workspace_alloc(der);
    ENSURE(wk && wd);
    /* nothing per thread grows with a grid */
    ENSURE(wk->stamp == NULL && wd->stamp == NULL && wd->tables->tri_box == NULL &&
           wd->tables->hedge == NULL && wd->tables->edge_live == NULL);
    ENSURE(wk->tables->nz_min == wd->tables->nz_min && wk->tables->has_gaps == wd->tables->has_gaps);
    ENSURE(wd->tables->has_gaps == 1);
    size_t holes = 0, concave = 0;
    for (size_t k = 0; k < der->ntri; k++) {
        int32_t idx = (int32_t)k;
        ENSURE(rf_grid_slot(kept, k) == rf_grid_slot(der, k));
        if (rf_grid_slot(der, k) < 0) {
            holes++;
            continue;
        }
        const rf_triangle *A = &kept->tri[k];
        rf_triangle buf;
        const rf_triangle *B = rf_tri(der, idx, &buf);
        ENSURE_MSG(same_vec(A->a, B->a) && same_vec(A->b, B->b) && same_vec(A->c, B->c) &&
                       same_vec(A->n, B->n) && memcmp(&A->d, &B->d, sizeof A->d) == 0,
                   "triangle %zu differs", k);
        ENSURE_MSG(A->zone == B->zone && A->zone == rf_tri_zone(der, idx), "triangle %zu: zone %d, %d",
                   k, A->zone, B->zone);
        float fa[6], fb[6];
        double ha[3], hb[3];
        ENSURE(memcmp(rf_tri_box(wk, idx, fa), rf_tri_box(wd, idx, fb), sizeof fa) == 0);
        ENSURE(memcmp(rf_tri_box(wd, idx, fb), rf_tri_box(wd, idx, fa), sizeof fa) == 0); /* cached */
        ENSURE(memcmp(rf_tri_hedge(wk->tables, idx, ha), rf_tri_hedge(wd->tables, idx, hb), sizeof ha) == 0);
        ENSURE_MSG(rf_edge_live(wk, idx) == rf_edge_live(wd, idx), "triangle %zu: live %u, %u", k,
                   rf_edge_live(wk, idx), rf_edge_live(wd, idx));
        concave += (rf_edge_live(wd, idx) & 7) != 7;
        /* through the workspace's cache, twice (a miss, then a hit) */
        for (int twice = 0; twice < 2; twice++) {
            rf_triangle cb;
            const rf_triangle *C = rf_face(wd, der, idx, &cb);
            ENSURE(C == &cb && same_vec(C->n, A->n) && same_vec(C->a, A->a) && C->zone == A->zone);
        }
    }
    ENSURE_MSG(holes > 20 && concave > 100, "%zu holes, %zu triangles with a concave edge", holes,
               concave);
    /* location and heights, holes included */
    for (int s = 0; s < 4000; s++) {
        double x = kept->xmin - 1.0 + (kept->xmax - kept->xmin + 2.0) * (double)((s * 7919) % 4001) / 4000.0;
        double y = kept->ymin - 1.0 + (kept->ymax - kept->ymin + 2.0) * (double)((s * 104729) % 3989) / 3988.0;
        double za = NAN, zb = NAN;
        int32_t ka = rf_terrain_height(kept, x, y, &za), kb = rf_terrain_height(der, x, y, &zb);
        ENSURE(ka == kb && (ka < 0 || memcmp(&za, &zb, sizeof za) == 0));
    }
    rf_workspace_free(wk);
    rf_workspace_free(wd);
}

TEST(grid_compact_derives_what_the_kept_grid_holds)
{
    char *text = wavy_grid_text(37, 29);
    const char *path = rf_test_write("wavy.asc", text);
    free(text);
    /* one polygon zone over part of the slope */
    double poly[8] = {640.0, -30.0, 690.0, -35.0, 700.0, 10.0, 645.0, 20.0};
    rf_zone_spec zone = {.name = (char *)"scree", .poly_xy = poly, .npoly = 4, .surface = SURF};
    rf_terrain kept, der;
    build(path, 0, &zone, 1, &kept);
    build(path, 1, &zone, 1, &der);
    ENSURE(der.zone8 != NULL && der.zone16 == NULL && der.nzones == 2);
    ensure_same_grid(&kept, &der);
    rf_terrain_free(&kept);
    rf_terrain_free(&der);
    /* without zones, nothing per triangle */
    build(path, 1, NULL, 0, &der);
    ENSURE(der.zone8 == NULL && der.zone16 == NULL && der.grid_hole != NULL);
    rf_terrain_free(&der);
}

/* More than 255 zones: a zone per triangle takes 16 bits. */
TEST(grid_compact_zones_beyond_255_take_16_bits)
{
    char *text = wavy_grid_text(37, 29);
    const char *path = rf_test_write("wavy.asc", text);
    free(text);
    enum { NZ = 300 };
    rf_zone_spec *zones = calloc(NZ, sizeof *zones);
    double (*sq)[8] = calloc(NZ, sizeof *sq);
    ENSURE(zones && sq);
    for (int z = 0; z < NZ; z++) {
        double x0 = 612.385 + 2.5 * (z % 30), y0 = -41.75 + 7.0 * (z / 30);
        double q[8] = {x0, y0, x0 + 2.5, y0, x0 + 2.5, y0 + 7.0, x0, y0 + 7.0};
        memcpy(sq[z], q, sizeof q);
        zones[z] = (rf_zone_spec){.name = (char *)"z", .poly_xy = sq[z], .npoly = 4, .surface = SURF};
    }
    rf_terrain kept, der;
    build(path, 0, zones, NZ, &kept);
    build(path, 1, zones, NZ, &der);
    ENSURE(der.zone16 != NULL && der.zone8 == NULL && der.nzones == NZ + 1);
    int32_t top = 0;
    for (size_t k = 0; k < der.ntri; k++)
        if (rf_grid_slot(&der, k) >= 0 && rf_tri_zone(&der, (int32_t)k) > top)
            top = rf_tri_zone(&der, (int32_t)k);
    ENSURE_MSG(top > 255, "highest zone %d", top);
    ensure_same_grid(&kept, &der);
    rf_terrain_free(&kept);
    rf_terrain_free(&der);
    free(zones);
    free(sq);
}

/* More zones than 16 bits hold: a derived grid keeps their indices whole (the last zone,
 * covering the grid, is zone 65 538 of the terrain, after the default surface and
 * 65 536 small zones off the grid). */
TEST(grid_compact_zones_beyond_65536_take_32_bits)
{
    char *text = wavy_grid_text(15, 12);
    const char *path = rf_test_write("wavy-small.asc", text);
    free(text);
    enum { NZ = 65537 };
    rf_zone_spec *zones = calloc(NZ, sizeof *zones);
    double (*sq)[8] = calloc(NZ, sizeof *sq);
    ENSURE(zones && sq);
    for (int z = 0; z < NZ; z++) {
        double x0 = z + 1 < NZ ? -1e5 - 3.0 * z : 0.0, y0 = z + 1 < NZ ? -1e5 : -1e3;
        double w = z + 1 < NZ ? 1.0 : 2e3;
        double q[8] = {x0, y0, x0 + w, y0, x0 + w, y0 + w, x0, y0 + w};
        memcpy(sq[z], q, sizeof q);
        zones[z] = (rf_zone_spec){.name = (char *)"z", .poly_xy = sq[z], .npoly = 4, .surface = SURF};
    }
    rf_terrain kept, der;
    build(path, 0, zones, NZ, &kept);
    build(path, 1, zones, NZ, &der);
    ENSURE(der.zone32 != NULL && der.zone16 == NULL && der.zone8 == NULL && der.nzones == NZ + 1);
    size_t n = 0;
    for (size_t k = 0; k < der.ntri; k++)
        if (rf_grid_slot(&der, k) >= 0) {
            ENSURE_MSG(rf_tri_zone(&der, (int32_t)k) == NZ && kept.tri[k].zone == NZ,
                       "triangle %zu: zone %d, kept %d", k, rf_tri_zone(&der, (int32_t)k),
                       kept.tri[k].zone);
            n++;
        }
    ENSURE(n > 50);
    rf_terrain_free(&kept);
    rf_terrain_free(&der);
    free(zones);
    free(sq);
}

/* A grid of ncols x nrows nodes of 1 m cells with its west column at x = x0: a smooth
 * bent surface whose node (i, j) lies at x = x0 + i, at height z(x0 + i, j). */
static char *bent_grid_text(size_t ncols, size_t nrows, size_t x0)
{
    size_t cap = 200 + ncols * nrows * 16, used = 0;
    char *text = malloc(cap);
    ENSURE(text);
    used += (size_t)snprintf(text, cap, "ncols %zu\nnrows %zu\nxllcenter %zu\nyllcenter 0\n"
                                         "cellsize 1\n", ncols, nrows, x0);
    for (size_t r = 0; r < nrows; r++) {
        size_t j = nrows - 1 - r;
        for (size_t i = 0; i < ncols; i++) {
            double x = (double)(x0 + i), y = (double)j;
            double z = 0.6 * y + 0.002 * (x - 650.0) * (x - 650.0) / 10.0 + 0.8 * sin(0.37 * x) * cos(0.9 * y);
            used += (size_t)snprintf(text + used, cap - used, "%.3f%c", z, i + 1 == ncols ? '\n' : ' ');
        }
    }
    return text;
}

/* The live edges of a grid wider than the tables' strips of cells (1 024 columns): every
 * cell of a window across the strips' border has the live bits it has in a grid of that
 * window alone (its neighbours are the same faces), on both sides of the border. */
TEST(grid_compact_live_edges_across_the_tables_strips)
{
    enum { W = 1300, H = 6, X0 = 1000, WW = 60 };
    char *full = bent_grid_text(W, H, 0), *part = bent_grid_text(WW, H, X0);
    const char *pf = rf_test_write("bent-full.asc", full), *pp = rf_test_write("bent-part.asc", part);
    free(full);
    free(part);
    rf_terrain tf, tp;
    build(pf, 1, NULL, 0, &tf);
    build(pp, 1, NULL, 0, &tp);
    rf_workspace *wf = rf_workspace_alloc(&tf), *wp = rf_workspace_alloc(&tp);
    ENSURE(wf && wp);
    size_t ncf = W - 1, ncp = WW - 1, concave = 0, checked = 0;
    for (size_t j = 0; j < H - 1; j++)
        for (size_t l = 1; l + 1 < ncp; l++) /* the window's own border cells lack neighbours */
            for (int k = 0; k < 2; k++) {
                int32_t a = (int32_t)(2 * (j * ncf + X0 + l) + (size_t)k);
                int32_t b = (int32_t)(2 * (j * ncp + l) + (size_t)k);
                ENSURE_MSG(rf_edge_live(wf, a) == rf_edge_live(wp, b), "cell (%zu, %zu) k %d: %u, %u",
                           X0 + l, j, k, rf_edge_live(wf, a), rf_edge_live(wp, b));
                concave += (rf_edge_live(wp, b) & 7) != 7;
                checked++;
            }
    ENSURE_MSG(concave > 50 && checked > 500, "%zu of %zu with a concave edge", concave, checked);
    rf_workspace_free(wf);
    rf_workspace_free(wp);
    rf_terrain_free(&tf);
    rf_terrain_free(&tp);
}

/* ---- a large grid within a memory bound ------------------------------------------------ */

#if defined(__SANITIZE_ADDRESS__)
#define RF_UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RF_UNDER_SANITIZER 1
#endif
#endif

#define BIG_N 2000 /* nodes along each side */
/* The bound: 1.5 times the heights as doubles, and 16 MB for the process itself (the
 * code, the libraries, SQLite's cache, the run's chunks, the threads' stacks and
 * workspaces: about 8 MB measured).  The grid's triangles kept in an array, with their
 * tables and a stamp per triangle and thread, took 1.3 GB. */
#define BIG_BOUND_KB ((long)(1.5 * BIG_N * BIG_N * 8 / 1024) + 16 * 1024)

#ifndef RF_UNDER_SANITIZER
/* Writes a BIG_N x BIG_N grid of 1 m cells (a 30 % slope with waves) and its project. */
static const char *write_big_project(void)
{
    const char *asc = rf_test_path("big.asc");
    FILE *f = fopen(asc, "w");
    ENSURE(f);
    fprintf(f, "ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize 1\n", BIG_N, BIG_N);
    char line[BIG_N * 12];
    for (int r = 0; r < BIG_N; r++) {
        int j = BIG_N - 1 - r, used = 0;
        for (int i = 0; i < BIG_N; i++)
            used += snprintf(line + used, sizeof line - (size_t)used, "%.2f ",
                             0.3 * j + 2.0 * sin(i / 17.0) * cos(j / 13.0));
        line[used - 1] = '\n';
        fwrite(line, 1, (size_t)used, f);
    }
    ENSURE(fclose(f) == 0);
    return rf_test_write("big.yaml",
                         "name: big\nseed: 2385\nterrain:\n  dem: big.asc\n  surface:\n"
                         "    restitution: {mean: 0.3, sd: 0.05}\n    friction: {mean: 0.35, sd: 0.05}\n"
                         "rocks:\n  - {name: r, mass: 2000, density: 2650, action_level: 1}\n"
                         "releases:\n  - {name: top, point: [1000, 1950], rock: r, count: 8}\n"
                         "measures:\n  - {name: foot, kind: control, line: [[500, 1500], [1500, 1500]]}\n"
                         "simulation: {model: sphere, max_time: 60, paths: 8}\nhazard: {cell: 10.0}\n");
}
#endif

TEST(grid_compact_2000_by_2000_grid_runs_within_a_memory_bound)
{
#ifdef RF_UNDER_SANITIZER
    printf("    skipped under the sanitizers (their shadow memory is no measure)\n");
    return;
#else
    const char *yaml = write_big_project();
    char project[4096], db[4096];
    snprintf(project, sizeof project, "%s", yaml);
    snprintf(db, sizeof db, "%s", rf_test_path("big.gpkg"));
    pid_t pid = fork();
    ENSURE(pid >= 0);
    if (pid == 0) {
        /* the run, as `rockfall run` makes it, on two threads */
        rf_project p;
        rf_error err;
        rf_store *s;
        rf_run_summary sum;
        rf_run_options o = {.threads = 2};
        int ok = rf_project_load(project, &p, &err) == 0 && p.terrain.tri == NULL &&
                 rf_store_open(db, &s, &err) == 0 && rf_montecarlo_run(&p, s, &o, &sum, &err) == 0 &&
                 sum.n_trajectories == 8;
        _exit(ok ? 0 : 3);
    }
    int status = 0;
    ENSURE(waitpid(pid, &status, 0) == pid);
    ENSURE_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 0, "the run failed (status %d)", status);
    struct rusage ru;
    ENSURE(getrusage(RUSAGE_CHILDREN, &ru) == 0);
    printf("    peak %ld kB for %d x %d heights (%ld kB as doubles), bound %ld kB\n", ru.ru_maxrss,
           BIG_N, BIG_N, (long)BIG_N * BIG_N * 8 / 1024, BIG_BOUND_KB);
    ENSURE_MSG(ru.ru_maxrss <= BIG_BOUND_KB, "peak %ld kB over the bound %ld kB", ru.ru_maxrss,
               BIG_BOUND_KB);
#endif
}

/* ---- the engine on a derived grid ----------------------------------------------------- */

static double rough_holed_z(int i, int j, void *ctx)
{
    gsl_rng *rng = ctx;
    double z = 60.0 - 0.8 * i + 0.15 * j + 1.385 * gsl_rng_uniform(rng);
    return (i >= 25 && i <= 27 && j >= 12 && j <= 14) ? -9999.0 : z;
}

/* Every engine and contact mode gives the same records and path points, bit for bit, on
 * a rough grid with a hole whether it keeps or derives its triangles. */
TEST(grid_compact_every_engine_runs_as_on_the_kept_grid)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 2385);
    char *txt = mt_grid_text(61, 31, 1.0, 0.0, 0.0, rough_holed_z, rng);
    const char *path = rf_test_write("rough.asc", txt);
    free(txt);
    rf_terrain kept, der;
    build(path, 0, NULL, 0, &kept);
    build(path, 1, NULL, 0, &der);
    ENSURE(kept.tri != NULL && der.tri == NULL && der.grid_hole != NULL);
    const struct {
        rf_rock_model model;
        rf_contact_kind contact;
        rf_engine_kind engine;
    } mode[4] = {{RF_MODEL_SPHERE, RF_CONTACT_FULL, RF_ENGINE_EXACT},
                 {RF_MODEL_SPHERE, RF_CONTACT_CENTRE, RF_ENGINE_EXACT},
                 {RF_MODEL_POINT, RF_CONTACT_FULL, RF_ENGINE_EXACT},
                 {RF_MODEL_SPHERE, RF_CONTACT_FULL, RF_ENGINE_FIXED_STEP}};
    long impacts = 0;
    for (int md = 0; md < 4; md++) {
        rf_simulation sim = mt_sim(mode[md].model, mode[md].contact, 60.0);
        sim.engine = mode[md].engine;
        sim.dt = 0.002;
        rf_body body = rf_body_make(1385.0, 2650.0, mode[md].model);
        for (int k = 0; k < 6; k++) {
            rf_state s = mt_state(rf_v3(3.0 + 0.7 * k, 4.0 + 3.9 * k, 62.0), rf_v3(2.0, 0.3 * k, 0.0));
            mt_run a, b;
            mt_simulate_opts(&kept, &sim, &body, &s, 700 + (unsigned long)k, 0.0, &a);
            mt_simulate_opts(&der, &sim, &body, &s, 700 + (unsigned long)k, 0.0, &b);
            ENSURE_MSG(memcmp(&a.rec, &b.rec, sizeof a.rec) == 0, "mode %d, rock %d: records differ", md, k);
            ENSURE(a.npoints == b.npoints && a.npoints > 0);
            ENSURE_MSG(memcmp(a.points, b.points, a.npoints * sizeof *a.points) == 0,
                       "mode %d, rock %d: path points differ", md, k);
            impacts += a.rec.n_impacts;
            mt_run_free(&a);
            mt_run_free(&b);
        }
    }
    ENSURE_MSG(impacts > 50, "%ld impacts", impacts);
    rf_terrain_free(&kept);
    rf_terrain_free(&der);
    gsl_rng_free(rng);
}
