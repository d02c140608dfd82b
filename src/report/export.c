/* export.c - `rockfall export`: a run's hazard maps as ESRI ASCII grids (docs/gis.md).
 *
 * The grids lie on the run's hazard grid: its origin the terrain's (xmin, ymin), its
 * cell runs.hazard_cell_m, ceil(extent / cell) cells along each axis (rf_hazard_grid),
 * exactly the cells of hazard_cells.  A cell no rock passed holds 0 passages, deposits
 * and reach probability and no energy or height (nodata) where it lies on the terrain
 * (its centre's nearest node of the stored terrain grid has a height), and nodata in
 * every map off the terrain.  Each grid has a .prj beside it, the run's CRS as ESRI WKT
 * (PROJ), when the run has a CRS.  Everything is read from the database, opened
 * read-only by the caller. */
#include "report/report.h"
#include "report/report_private.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"
#include "input/crs.h"
#include "results/run_view.h"
#include "results/schema.h"
#include "rockfall/terrain.h"

#define NODATA (-9999.0)

enum { M_ENERGY_MAX, M_ENERGY_P95, M_HEIGHT_P95, M_REACH, M_PASSAGES, M_DEPOSITS, N_MAPS };

static const struct map_kind {
    const char *name, *what, *unit;
    int counted; /* 0 where no rock passed on the terrain (else nodata there) */
} maps[N_MAPS] = {
    [M_ENERGY_MAX] = {"energy_max", "the largest kinetic energy of a rock in the cell", "kJ", 0},
    [M_ENERGY_P95] = {"energy_p95",
                      "the 95th percentile (nearest rank) of the largest kinetic energy of "
                      "each rock that passed the cell", "kJ", 0},
    [M_HEIGHT_P95] = {"height_p95",
                      "the 95th percentile (nearest rank) of the largest passing height (the "
                      "rock's lowest point above the ground) of each rock that passed the cell",
                      "m", 0},
    [M_REACH] = {"reach_probability",
                 "the share of the run's trajectories that passed the cell", "0 to 1", 1},
    [M_PASSAGES] = {"passages", "the number of trajectories that passed the cell",
                    "trajectories", 1},
    [M_DEPOSITS] = {"deposits",
                    "the number of trajectories that ended in the cell at rest or stopped by "
                    "a measure", "trajectories", 1},
};

typedef struct grid {
    double x0, y0, cell;
    size_t nx, ny;
    double *v[N_MAPS];  /* nx * ny each, row iy from the south; NaN: nodata */
    unsigned char *live; /* 1 on the terrain, or reached */
} grid;

/* The cell of a coordinate along one axis, the far edge in the last cell (as the run's
 * hazard grid counts it); -1 outside. */
static long cell_of(double x, double x0, double cell, size_t n)
{
    double f = floor((x - x0) / cell);
    if (f == (double)n && x - x0 <= (double)n * cell)
        f = (double)n - 1;
    return f >= 0 && f < (double)n ? (long)f : -1;
}

/* Whether the stored terrain has a height at (x, y): its nearest node's. */
static int on_terrain(const rf_terrain_grid *g, double x, double y)
{
    double i = floor((x - g->x0) / g->step + 0.5), j = floor((y - g->y0) / g->step + 0.5);
    if (!(i >= 0 && j >= 0 && i < (double)g->nx && j < (double)g->ny))
        return 0;
    return !isnan(g->z[(size_t)j * g->nx + (size_t)i]);
}

static int db_error(sqlite3 *db, rf_error *err)
{
    return rf_query_db_error(db, err);
}

/* The hazard cells and the deposits of the run into the maps. */
static int read_cells(sqlite3 *db, int64_t run, grid *G, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(db,
                           "SELECT ix, iy, passes, reach_probability, energy_max_kj,"
                           " energy_p95_kj, height_p95_m FROM hazard_cells WHERE run_id = ?1",
                           -1, &st, NULL) != SQLITE_OK)
        return db_error(db, err);
    sqlite3_bind_int64(st, 1, run);
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        sqlite3_int64 ix = sqlite3_column_int64(st, 0), iy = sqlite3_column_int64(st, 1);
        if (ix < 0 || iy < 0 || (size_t)ix >= G->nx || (size_t)iy >= G->ny)
            continue;
        size_t k = (size_t)iy * G->nx + (size_t)ix;
        G->live[k] = 1;
        G->v[M_PASSAGES][k] = rf_query_column_real(st, 2);
        G->v[M_REACH][k] = rf_query_column_real(st, 3);
        G->v[M_ENERGY_MAX][k] = rf_query_column_real(st, 4);
        G->v[M_ENERGY_P95][k] = rf_query_column_real(st, 5);
        G->v[M_HEIGHT_P95][k] = rf_query_column_real(st, 6);
    }
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE)
        return db_error(db, err);
    if (sqlite3_prepare_v2(db,
                           "SELECT stop_x, stop_y FROM trajectories WHERE run_id = ?1"
                           " AND stop_reason IN ('rest', 'stopped') AND stop_x IS NOT NULL"
                           " AND stop_y IS NOT NULL",
                           -1, &st, NULL) != SQLITE_OK)
        return db_error(db, err);
    sqlite3_bind_int64(st, 1, run);
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        long ix = cell_of(sqlite3_column_double(st, 0), G->x0, G->cell, G->nx);
        long iy = cell_of(sqlite3_column_double(st, 1), G->y0, G->cell, G->ny);
        if (ix < 0 || iy < 0)
            continue;
        size_t k = (size_t)iy * G->nx + (size_t)ix;
        G->live[k] = 1;
        G->v[M_DEPOSITS][k] = (isnan(G->v[M_DEPOSITS][k]) ? 0.0 : G->v[M_DEPOSITS][k]) + 1.0;
    }
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : db_error(db, err);
}

/* The run's CRS as ESRI WKT (malloc'd); NULL when the run has none (or the file is
 * older than the CRS columns). */
static int run_esri_wkt(sqlite3 *db, int64_t run, char **esri, rf_error *err)
{
    *esri = NULL;
    if (!rf_db_has_column(db, "runs", "srs_id") || !rf_db_has_table(db, "gpkg_spatial_ref_sys"))
        return 0;
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(db,
                           "SELECT s.definition FROM runs r JOIN gpkg_spatial_ref_sys s"
                           " ON s.srs_id = r.srs_id WHERE r.id = ?1 AND s.definition <> 'undefined'",
                           -1, &st, NULL) != SQLITE_OK)
        return db_error(db, err);
    sqlite3_bind_int64(st, 1, run);
    int status = 0;
    if (sqlite3_step(st) == SQLITE_ROW) {
        char why[512];
        *esri = rf_crs_esri_wkt((const char *)sqlite3_column_text(st, 0), why, sizeof why);
        if (!*esri)
            status = rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0,
                                  "run %lld's CRS: %s", (long long)run, why);
    }
    sqlite3_finalize(st);
    return status;
}

static int write_grid(const char *dir, const grid *G, int m, const char *esri, rf_error *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s.asc", dir, maps[m].name);
    FILE *f = rf_create_file(path, err);
    if (!f)
        return -1;
    fprintf(f, "ncols %zu\nnrows %zu\nxllcorner %.17g\nyllcorner %.17g\ncellsize %.17g\n"
               "NODATA_value %g\n",
            G->nx, G->ny, G->x0, G->y0, G->cell, NODATA);
    for (size_t r = 0; r < G->ny; r++) {
        size_t iy = G->ny - 1 - r; /* the first row is the northern one */
        for (size_t ix = 0; ix < G->nx; ix++) {
            size_t k = iy * G->nx + ix;
            double v = G->v[m][k];
            if (isnan(v))
                v = G->live[k] && maps[m].counted ? 0.0 : NODATA;
            fprintf(f, ix ? " %.17g" : "%.17g", v);
        }
        fputc('\n', f);
    }
    int bad = ferror(f);
    if (fclose(f) || bad)
        return rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
    if (!esri)
        return 0;
    snprintf(path, sizeof path, "%s/%s.prj", dir, maps[m].name);
    if (!(f = rf_create_file(path, err)))
        return -1;
    fputs(esri, f);
    bad = ferror(f);
    if (fclose(f) || bad)
        return rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
    return 0;
}

static int write_readme(const char *dir, const rf_run_view *v, const grid *G, const char *esri,
                        rf_error *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/README.txt", dir);
    FILE *f = rf_create_file(path, err);
    if (!f)
        return -1;
    fprintf(f,
            "Hazard maps of run %lld (project '%s', %ld trajectories), written by rockfall.\n"
            "\n"
            "ESRI ASCII grids on the run's hazard grid: %zu x %zu cells of %g m, lower left\n"
            "corner (%.17g, %.17g). NODATA_value -9999: off the terrain in every map, and\n"
            "in the energy and height maps wherever no rock passed. Passages, deposits and\n"
            "reach probability are 0 where no rock passed on the terrain.\n"
            "%s\n",
            (long long)v->id, v->project ? v->project : "", v->n_trajectories, G->nx, G->ny,
            G->cell, G->x0, G->y0,
            esri ? "Each grid's .prj holds the run's coordinate reference system (ESRI WKT)."
                 : "The run has no coordinate reference system (no `crs` in its project):\n"
                   "the grids have no .prj, and their coordinates are the project's.");
    for (int m = 0; m < N_MAPS; m++)
        fprintf(f, "%s.asc  %s (%s)\n", maps[m].name, maps[m].what, maps[m].unit);
    fputs("\nThe percentiles are those of hazard_cells (docs/database.md): exact up to 128\n"
          "passes, within 1.09 % beyond.\n",
          f);
    int bad = ferror(f);
    if (fclose(f) || bad)
        return rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
    return 0;
}

int rf_export_write(sqlite3 *db, int64_t run, const char *dir, rf_error *err)
{
    rf_run_view v;
    if (rf_run_view_load(db, run, &v, err))
        return -1;
    grid G = {0};
    char *esri = NULL;
    int status = 0;
    if (!v.has_grid || !(v.hazard_cell > 0)) {
        status = rf_error_set(err, sqlite3_db_filename(db, "main"), 0, 0,
                              "run %lld stored no terrain grid or hazard cell (a run of "
                              "schema version 1): no hazard maps to export",
                              (long long)run);
        goto done;
    }
    rf_terrain extent = {0};
    extent.xmin = v.grid.xmin;
    extent.xmax = v.grid.xmax;
    extent.ymin = v.grid.ymin;
    extent.ymax = v.grid.ymax;
    double nx, ny;
    rf_hazard_grid(&extent, v.hazard_cell, &nx, &ny);
    G.x0 = v.grid.xmin;
    G.y0 = v.grid.ymin;
    G.cell = v.hazard_cell;
    G.nx = (size_t)nx;
    G.ny = (size_t)ny;
    size_t n = G.nx * G.ny;
    G.live = calloc(n, 1);
    for (int m = 0; m < N_MAPS; m++)
        G.v[m] = malloc(n * sizeof(double));
    for (int m = 0; m < N_MAPS; m++)
        if (!G.v[m])
            G.live = (free(G.live), NULL);
    if (!G.live) {
        status = rf_error_set(err, dir, 0, 0, "out of memory for a %zu x %zu grid", G.nx, G.ny);
        goto done;
    }
    for (size_t k = 0; k < n; k++) {
        for (int m = 0; m < N_MAPS; m++)
            G.v[m][k] = NAN;
        G.live[k] = (unsigned char)on_terrain(&v.grid, G.x0 + ((double)(k % G.nx) + 0.5) * G.cell,
                                              G.y0 + ((double)(k / G.nx) + 0.5) * G.cell);
    }
    status = read_cells(db, run, &G, err) || run_esri_wkt(db, run, &esri, err) ||
                     rep_make_dirs(dir, err)
                 ? -1
                 : 0;
    for (int m = 0; status == 0 && m < N_MAPS; m++)
        status = write_grid(dir, &G, m, esri, err);
    if (status == 0)
        status = write_readme(dir, &v, &G, esri, err);
done:
    for (int m = 0; m < N_MAPS; m++)
        free(G.v[m]);
    free(G.live);
    free(esri);
    rf_run_view_free(&v);
    return status;
}
