/* test_gis.c - the planner's GIS round trip: the project's CRS, the results database as
 * a GeoPackage (read back by GDAL's ogrinfo where it is installed), the hazard rasters
 * of `rockfall export` (read back by gdalinfo), and the files that are not ours. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sqlite3.h>

#include "db_test_util.h"
#include "input/crs.h"
#include "rockfall/terrain.h"
#include "rockfall/project.h"
#include "test.h"

/* A slope (tests/data/project/plane5.asc) with an area and a point release, a barrier
 * and a control line below them; `crs` the line that names the CRS ("" none). */
static const char *write_project_on(const char *name, const char *crs, const char *dem_file)
{
    char *dem = realpath(dem_file, NULL);
    ENSURE(dem);
    char text[2048];
    snprintf(text, sizeof text,
             "name: gis\n"
             "seed: 3\n"
             "%s\n"
             "terrain: {dem: %s}\n"
             "rocks: [{name: r, mass: 500}]\n"
             "releases:\n"
             "  - {name: A, area: [[5, 30], [35, 30], [35, 36], [5, 36]], rock: r, count: 20}\n"
             "  - {name: P, point: [20, 35], rock: r, count: 10}\n"
             "measures:\n"
             "  - {name: road, kind: control, line: [[0, 10], [40, 10]]}\n"
             "  - {name: B1, kind: barrier, line: [[0, 20], [40, 20]], height: 3, mel: 1000}\n"
             "simulation: {model: point, paths: 4}\n"
             "hazard: {cell: 4}\n",
             crs, dem);
    free(dem);
    return rf_test_write(name, text);
}

static const char *write_project(const char *name, const char *crs)
{
    return write_project_on(name, crs, "tests/data/project/plane5.asc");
}

static sqlite3 *open_db(const char *path)
{
    sqlite3 *db = NULL;
    ENSURE(sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    return db;
}

/* Runs `rockfall ARGS`, ENSUREs the status, returns its output (static). */
static const char *rockfall(int want, const char *fmt, const char *a, const char *b)
{
    static char out[65536];
    char args[4096];
    snprintf(args, sizeof args, fmt, a, b);
    int rc = rf_test_rockfall(args, out, sizeof out);
    ENSURE_MSG(rc == want, "rockfall %s: status %d, want %d: %s", args, rc, want, out);
    return out;
}

/* A command's stdout and stderr together (malloc'd); NULL when it cannot start. */
static char *capture(const char *cmd)
{
    char full[8192];
    snprintf(full, sizeof full, "%s 2>&1", cmd);
    FILE *p = popen(full, "r");
    if (!p)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    ENSURE(buf);
    size_t got;
    while ((got = fread(buf + n, 1, cap - n - 1, p)) > 0) {
        n += got;
        if (n + 1 == cap) {
            buf = realloc(buf, cap *= 2);
            ENSURE(buf);
        }
    }
    buf[n] = '\0';
    pclose(p);
    return buf;
}

static int have_tool(const char *tool)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tool);
    if (system(cmd) == 0)
        return 1;
    printf("note: %s is not installed (Debian: gdal-bin); this check is skipped\n", tool);
    return 0;
}

/* ---- the CRS ------------------------------------------------------------------------ */

TEST(gis_crs_epsg_code_stored_with_the_run)
{
    const char *yaml = write_project("p.yaml", "crs: EPSG:2154");
    const char *db_path = rf_test_path("r.gpkg");
    char keep[4096];
    snprintf(keep, sizeof keep, "%s", db_path);
    rockfall(0, "run %s -o %s -q", yaml, keep);
    sqlite3 *db = open_db(keep);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE crs = 'EPSG:2154' AND srs_id = 2154") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM gpkg_spatial_ref_sys WHERE srs_id = 2154"
                       " AND organization = 'EPSG' AND organization_coordsys_id = 2154"
                       " AND definition LIKE 'PROJCS[\"RGF93%%Lambert-93\"%%'"
                       " AND definition LIKE '%%AUTHORITY[\"EPSG\",\"2154\"]]'") == 1);
    /* every layer in the project's CRS */
    ENSURE(dbt_int(db, "SELECT count(*) FROM gpkg_geometry_columns WHERE srs_id <> 2154") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM gpkg_contents WHERE data_type = 'features'"
                       " AND srs_id = 2154") == 7);
    sqlite3_close(db);
}

TEST(gis_crs_unknown_to_proj_is_refused_with_its_location)
{
    const char *yaml = write_project("p.yaml", "crs: EPSG:999999");
    char keep[4096];
    snprintf(keep, sizeof keep, "%s", rf_test_path("r.gpkg"));
    const char *out = rockfall(2, "run %s -o %s", yaml, keep);
    char want[4200];
    snprintf(want, sizeof want, "%s:3:6: error: crs: 'EPSG:999999' is not a coordinate "
                                "reference system PROJ knows", yaml);
    ENSURE_MSG(strstr(out, want), "output: %s", out);
    ENSURE(access(keep, F_OK) != 0); /* no database was opened */
    /* a WKT file that holds no CRS */
    rf_test_write("bad.wkt", "PROJCS[\"broken\"");
    yaml = write_project("q.yaml", "crs: bad.wkt");
    out = rockfall(2, "run %s -o %s", yaml, keep);
    ENSURE_MSG(strstr(out, "q.yaml:3:6: error: crs: '") && strstr(out, "bad.wkt' holds no "
               "coordinate reference system PROJ knows"), "output: %s", out);
    ENSURE(access(keep, F_OK) != 0);
}

/* A DEM's .prj (ESRI WKT, no authority code in it) is the CRS when the project names
 * none; PROJ identifies its EPSG code. A `crs:` WKT file reads the same. */
TEST(gis_crs_from_the_dems_prj_and_from_a_wkt_file)
{
    rf_crs swiss;
    char why[512];
    ENSURE_MSG(rf_crs_resolve("EPSG:2056", "EPSG:2056", &swiss, why, sizeof why) == 0, "%s", why);
    char *esri = rf_crs_esri_wkt(swiss.wkt, why, sizeof why);
    ENSURE_MSG(esri && strstr(esri, "PROJCS[\"CH1903+_LV95\"") && !strstr(esri, "AUTHORITY"),
               "%s", esri ? esri : why);
    char *dem = rf_test_read_text("tests/data/project/plane5.asc");
    ENSURE(dem);
    rf_test_write("slope.asc", dem);
    rf_test_write("slope.prj", esri);
    const char *yaml = rf_test_write("p.yaml", "name: prj\nterrain: {dem: slope.asc}\n"
                                               "rocks: [{name: r, mass: 100}]\n"
                                               "releases: [{name: a, point: [20, 30], rock: r}]\n");
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s", err.message);
    ENSURE(p.crs.source && strstr(p.crs.source, "slope.prj"));
    ENSURE(p.crs.auth && !strcmp(p.crs.auth, "EPSG") && p.crs.code == 2056);
    rf_project_free(&p);

    rf_test_write("lv95.wkt", swiss.wkt);
    yaml = rf_test_write("q.yaml", "name: wkt\ncrs: lv95.wkt\nterrain: {dem: slope.asc}\n"
                                   "rocks: [{name: r, mass: 100}]\n"
                                   "releases: [{name: a, point: [20, 30], rock: r}]\n");
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s", err.message);
    ENSURE(p.crs.code == 2056 && !strcmp(p.crs.wkt, swiss.wkt));
    rf_project_free(&p);

    /* a .prj PROJ cannot read: the error points at the DEM */
    rf_test_write("slope.prj", "GEOGCS[nonsense");
    yaml = rf_test_write("r.yaml", "name: prj\nterrain: {dem: slope.asc}\n"
                                   "rocks: [{name: r, mass: 100}]\n"
                                   "releases: [{name: a, point: [20, 30], rock: r}]\n");
    ENSURE(rf_project_load(yaml, &p, &err) != 0);
    ENSURE_MSG(err.line == 2 && err.column == 16 && strstr(err.message, "slope.prj' holds no"),
               "%d:%d %s", err.line, err.column, err.message);
    free(esri);
    free(dem);
    rf_crs_free(&swiss);
}

/* ---- the GeoPackage ------------------------------------------------------------------- */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static double le64(const unsigned char *b)
{
    uint64_t u = 0;
    for (int k = 7; k >= 0; k--)
        u = u << 8 | b[k];
    double v;
    memcpy(&v, &u, 8);
    return v;
}

/* A run into a fresh file; its path (static). */
static const char *one_run(const char *crs)
{
    static char keep[4096];
    const char *yaml = write_project("p.yaml", crs);
    snprintf(keep, sizeof keep, "%s", rf_test_path("r.gpkg"));
    rockfall(0, "run %s -o %s -q", yaml, keep);
    return keep;
}

/* OGC 12-128r18: application id and user_version, the required tables and rows, the
 * layers registered, the tool's tables declared, the journal back to DELETE; and the
 * geometry blobs in the standard encoding, at the rows' coordinates. */
TEST(gis_results_file_is_a_geopackage)
{
    const char *path = one_run("");
    char wal[4200];
    snprintf(wal, sizeof wal, "%s-wal", path);
    ENSURE(access(wal, F_OK) != 0);
    sqlite3 *db = open_db(path);
    ENSURE(dbt_int(db, "PRAGMA application_id") == 0x47504B47);
    ENSURE(dbt_int(db, "PRAGMA user_version") == 10300);
    sqlite3_stmt *st;
    ENSURE(sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &st, NULL) == SQLITE_OK &&
           sqlite3_step(st) == SQLITE_ROW);
    ENSURE(!strcmp((const char *)sqlite3_column_text(st, 0), "delete"));
    sqlite3_finalize(st);
    ENSURE(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, NULL) == SQLITE_OK &&
           sqlite3_step(st) == SQLITE_ROW);
    ENSURE(!strcmp((const char *)sqlite3_column_text(st, 0), "ok"));
    sqlite3_finalize(st);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_check") == 0);
    /* the three required rows of gpkg_spatial_ref_sys */
    ENSURE(dbt_int(db, "SELECT count(*) FROM gpkg_spatial_ref_sys WHERE"
                       " (srs_id = 4326 AND organization = 'EPSG' AND organization_coordsys_id = 4326)"
                       " OR (srs_id = -1 AND organization = 'NONE' AND definition = 'undefined')"
                       " OR (srs_id = 0 AND organization = 'NONE' AND definition = 'undefined')") == 3);
    static const char *const layer[] = {"release_points", "release_areas", "measure_lines",
                                        "stop_points", "paths", "interception_points",
                                        "hazard_map"};
    static const char *const type[] = {"POINT", "POLYGON", "LINESTRING", "POINT",
                                       "LINESTRING", "POINT", "POLYGON"};
    for (int i = 0; i < 7; i++) {
        ENSURE_MSG(dbt_int(db, "SELECT count(*) FROM gpkg_contents c JOIN gpkg_geometry_columns g"
                               " USING (table_name) WHERE table_name = '%s' AND data_type = 'features'"
                               " AND g.column_name = 'geom' AND geometry_type_name = '%s'"
                               " AND g.srs_id = -1 AND c.srs_id = -1 AND g.z = %d",
                           layer[i], type[i], i == 4) == 1, "%s", layer[i]);
        ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_table_info('%s') WHERE name = 'fid'"
                           " AND type = 'INTEGER' AND pk = 1", layer[i]) == 1);
        ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_table_info('%s') WHERE name = 'run_id'",
                       layer[i]) == 1);
        ENSURE(dbt_int(db, "SELECT count(*) FROM %s", layer[i]) > 0);
    }
    /* the layers hold the run's rows */
    ENSURE(dbt_int(db, "SELECT count(*) FROM stop_points") ==
           dbt_int(db, "SELECT count(*) FROM trajectories WHERE stop_x IS NOT NULL"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM interception_points") ==
           dbt_int(db, "SELECT count(*) FROM interceptions"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM hazard_map") ==
           dbt_int(db, "SELECT count(*) FROM hazard_cells"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM paths") ==
           dbt_int(db, "SELECT count(DISTINCT trajectory_id) FROM path_points"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM release_areas") == 1);
    /* every table and view of the tool's own declared, no layer among them */
    ENSURE(dbt_int(db, "SELECT count(*) FROM sqlite_master WHERE type IN ('table', 'view')"
                       " AND name NOT LIKE 'gpkg%%' AND name NOT LIKE 'sqlite%%'"
                       " AND name NOT IN (SELECT table_name FROM gpkg_contents)"
                       " AND name NOT IN (SELECT table_name FROM gpkg_extensions"
                       "  WHERE extension_name = 'rockfall_results' AND scope = 'write-only')") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM gpkg_extensions WHERE table_name IN"
                       " ('runs', 'hazard_cells', 'measure_summary', 'run_verdicts')") == 4);
    ENSURE(dbt_int(db, "SELECT count(*) FROM gpkg_extensions e JOIN gpkg_contents c"
                       " USING (table_name)") == 0);

    /* a stop point's blob: "GP", version 0, little endian with an xy envelope, srs -1,
     * then WKB Point (little endian, type 1) at the trajectory's stop */
    ENSURE(sqlite3_prepare_v2(db, "SELECT s.geom, t.stop_x, t.stop_y FROM stop_points s"
                                  " JOIN trajectories t ON t.id = s.trajectory_id LIMIT 1",
                              -1, &st, NULL) == SQLITE_OK &&
           sqlite3_step(st) == SQLITE_ROW);
    const unsigned char *b = sqlite3_column_blob(st, 0);
    ENSURE(sqlite3_column_bytes(st, 0) == 8 + 32 + 5 + 16);
    ENSURE(b[0] == 'G' && b[1] == 'P' && b[2] == 0 && b[3] == 0x03);
    ENSURE((int32_t)le32(b + 4) == -1);
    ENSURE(b[40] == 1 && le32(b + 41) == 1);
    ENSURE(le64(b + 45) == sqlite3_column_double(st, 1) && le64(b + 53) == sqlite3_column_double(st, 2));
    ENSURE(le64(b + 8) == le64(b + 45) && le64(b + 16) == le64(b + 45)); /* envelope x */
    sqlite3_finalize(st);
    /* a path: LineString Z (1002), its points those of path_points in order */
    ENSURE(sqlite3_prepare_v2(db, "SELECT geom, trajectory_id FROM paths LIMIT 1", -1, &st,
                              NULL) == SQLITE_OK &&
           sqlite3_step(st) == SQLITE_ROW);
    b = sqlite3_column_blob(st, 0);
    long long tid = sqlite3_column_int64(st, 1);
    uint32_t n = le32(b + 45);
    ENSURE(le32(b + 41) == 1002);
    ENSURE(n == dbt_int(db, "SELECT count(*) FROM path_points WHERE trajectory_id = %lld", tid));
    ENSURE(sqlite3_column_bytes(st, 0) == (int)(8 + 32 + 9 + 24 * n));
    ENSURE(le64(b + 49 + 24 * (n - 1) + 16) ==
           dbt_real(db, "SELECT z FROM path_points WHERE trajectory_id = %lld ORDER BY seq DESC", tid));
    sqlite3_finalize(st);
    /* a hazard cell: the square of the cell's size about its centre */
    ENSURE(sqlite3_prepare_v2(db, "SELECT m.geom, h.x, h.y FROM hazard_map m JOIN hazard_cells h"
                                  " USING (run_id, ix, iy) LIMIT 1", -1, &st, NULL) == SQLITE_OK &&
           sqlite3_step(st) == SQLITE_ROW);
    b = sqlite3_column_blob(st, 0);
    ENSURE(le32(b + 41) == 3 && le32(b + 45) == 1 && le32(b + 49) == 5);
    ENSURE(le64(b + 8) == sqlite3_column_double(st, 1) - 2 &&
           le64(b + 32) == sqlite3_column_double(st, 2) + 2); /* minx, maxy */
    sqlite3_finalize(st);
    sqlite3_close(db);
}

/* GDAL opens the file as a GeoPackage and lists every layer with its geometry type,
 * feature count and CRS, without a warning. */
TEST(gis_ogrinfo_reads_the_results_as_a_geopackage)
{
    if (!have_tool("ogrinfo"))
        return;
    const char *path = one_run("crs: EPSG:2154");
    char cmd[4300];
    snprintf(cmd, sizeof cmd, "ogrinfo -ro -so -al '%s'", path);
    char *out = capture(cmd);
    ENSURE(out);
    ENSURE_MSG(strstr(out, "using driver `GPKG' successful"), "%s", out);
    ENSURE_MSG(!strstr(out, "Warning") && !strstr(out, "ERROR"), "%s", out);
    sqlite3 *db = open_db(path);
    static const char *const layer[] = {"release_points", "release_areas", "measure_lines",
                                        "stop_points", "paths", "interception_points",
                                        "hazard_map"};
    static const char *const type[] = {"Point", "Polygon", "Line String", "Point",
                                       "3D Line String", "Point", "Polygon"};
    for (int i = 0; i < 7; i++) {
        char want[512];
        snprintf(want, sizeof want, "Layer name: %s\n", layer[i]);
        const char *at = strstr(out, want);
        ENSURE_MSG(at, "no layer %s in: %s", layer[i], out);
        snprintf(want, sizeof want, "Geometry: %s\nFeature Count: %lld\n", type[i],
                 dbt_int(db, "SELECT count(*) FROM %s", layer[i]));
        ENSURE_MSG(strstr(at, want), "%s: want '%s' in %s", layer[i], want, at);
        const char *crs = strstr(at, "Layer SRS WKT:\nPROJCRS[\"RGF93 v1 / Lambert-93\"");
        const char *next = strstr(at + 1, "Layer name:");
        ENSURE_MSG(crs && (!next || crs < next), "%s: no Lambert-93 CRS", layer[i]);
    }
    sqlite3_close(db);
    free(out);
}

/* ---- the export ------------------------------------------------------------------------ */

typedef struct asc {
    long nx, ny;
    double x0, y0, cell, nodata;
    double *v; /* row iy from the south */
} asc;

static void read_asc(const char *path, asc *g)
{
    FILE *f = fopen(path, "r");
    ENSURE_MSG(f, "cannot open %s", path);
    ENSURE(fscanf(f, " ncols %ld nrows %ld xllcorner %lf yllcorner %lf cellsize %lf"
                     " NODATA_value %lf",
                  &g->nx, &g->ny, &g->x0, &g->y0, &g->cell, &g->nodata) == 6);
    g->v = malloc((size_t)(g->nx * g->ny) * sizeof *g->v);
    ENSURE(g->v);
    for (long r = 0; r < g->ny; r++)
        for (long ix = 0; ix < g->nx; ix++)
            ENSURE(fscanf(f, "%lf", &g->v[(g->ny - 1 - r) * g->nx + ix]) == 1);
    double extra;
    ENSURE(fscanf(f, "%lf", &extra) != 1);
    fclose(f);
}

/* The six maps on the hazard grid, each cell as hazard_cells holds it (to the bit), 0
 * passages, deposits and reach probability where no rock passed on the terrain and
 * nodata in the energies and heights there, nodata in every map in the terrain's hole;
 * deposits count the trajectories ended at rest or stopped; .prj from PROJ. */
TEST(gis_export_writes_the_hazard_grids)
{
    const char *yaml = write_project_on("p.yaml", "crs: EPSG:2154", "tests/data/project/grid5.asc");
    char db_path[4096], dir[4096], path[4200];
    snprintf(db_path, sizeof db_path, "%s", rf_test_path("r.gpkg"));
    snprintf(dir, sizeof dir, "%s", rf_test_path("maps"));
    rockfall(0, "run %s -o %s -q", yaml, db_path);
    rockfall(0, "export %s --out %s", db_path, dir);
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s", err.message);
    sqlite3 *db = open_db(db_path);
    static const char *const name[] = {"passages", "reach_probability", "energy_max",
                                       "energy_p95", "height_p95", "deposits"};
    static const char *const column[] = {"passes", "reach_probability", "energy_max_kj",
                                         "energy_p95_kj", "height_p95_m", NULL};
    asc g[6];
    for (int m = 0; m < 6; m++) {
        snprintf(path, sizeof path, "%s/%s.asc", dir, name[m]);
        read_asc(path, &g[m]);
        ENSURE(g[m].nx == 10 && g[m].ny == 10 && g[m].x0 == 0 && g[m].y0 == 0 &&
               g[m].cell == 4 && g[m].nodata == -9999);
        snprintf(path, sizeof path, "%s/%s.prj", dir, name[m]);
        char *prj = rf_test_read_text(path);
        ENSURE_MSG(prj && strstr(prj, "PROJCS[\"RGF_1993_Lambert_93\""), "%s", prj ? prj : path);
        free(prj);
    }
    long reached = 0, zero = 0, hole = 0;
    for (long iy = 0; iy < 10; iy++)
        for (long ix = 0; ix < 10; ix++) {
            long k = iy * 10 + ix;
            int in_db = (int)dbt_int(db, "SELECT count(*) FROM hazard_cells WHERE ix = %ld AND iy = %ld",
                                     ix, iy);
            if (in_db) {
                reached++;
                for (int m = 0; m < 5; m++) {
                    double want = dbt_real(db, "SELECT %s FROM hazard_cells WHERE ix = %ld AND iy = %ld",
                                           column[m], ix, iy);
                    ENSURE_MSG(g[m].v[k] == (isnan(want) ? -9999 : want), "%s (%ld, %ld): %.17g, want %.17g",
                               name[m], ix, iy, g[m].v[k], want);
                }
                continue;
            }
            /* a cell no rock passed: on the terrain, or in its hole (unambiguously) */
            double cx = 4.0 * (double)ix + 2.0, cy = 4.0 * (double)iy + 2.0, z;
            int on = 0;
            for (int c = 0; c < 5; c++)
                on += rf_terrain_height(&p.terrain, cx + (c == 1 ? 0.5 : c == 2 ? -0.5 : 0),
                                        cy + (c == 3 ? 0.5 : c == 4 ? -0.5 : 0), &z) >= 0;
            if (on == 5) {
                zero++;
                ENSURE(g[0].v[k] == 0 && g[1].v[k] == 0 && g[5].v[k] == 0);
                ENSURE(g[2].v[k] == -9999 && g[3].v[k] == -9999 && g[4].v[k] == -9999);
            } else if (on == 0) {
                hole++;
                for (int m = 0; m < 6; m++)
                    ENSURE_MSG(g[m].v[k] == -9999, "%s (%ld, %ld) in the hole: %g", name[m], ix, iy,
                               g[m].v[k]);
            }
        }
    ENSURE_MSG(reached > 0 && zero > 0 && hole > 0, "%ld reached, %ld zero, %ld in the hole",
               reached, zero, hole);
    double deposits = 0;
    for (int k = 0; k < 100; k++)
        deposits += g[5].v[k] > 0 ? g[5].v[k] : 0;
    ENSURE(deposits == (double)dbt_int(db, "SELECT count(*) FROM trajectories WHERE stop_reason"
                                           " IN ('rest', 'stopped') AND stop_x BETWEEN 0 AND 40"
                                           " AND stop_y BETWEEN 0 AND 40"));
    snprintf(path, sizeof path, "%s/README.txt", dir);
    char *readme = rf_test_read_text(path);
    ENSURE(readme);
    for (int m = 0; m < 6; m++) {
        char want[64];
        snprintf(want, sizeof want, "%s.asc", name[m]);
        ENSURE_MSG(strstr(readme, want), "%s not in README", want);
    }
    ENSURE(strstr(readme, "(kJ)") && strstr(readme, "(m)") && strstr(readme, "-9999"));
    free(readme);

    /* GDAL reads every grid at the hazard grid's origin and cell, in the project's CRS,
     * with the database's values */
    if (have_tool("gdalinfo")) {
        for (int m = 0; m < 6; m++) {
            char cmd[4400];
            snprintf(cmd, sizeof cmd, "gdalinfo '%s/%s.asc'", dir, name[m]);
            char *out = capture(cmd);
            ENSURE(out);
            ENSURE_MSG(strstr(out, "Driver: AAIGrid") && strstr(out, "Size is 10, 10") &&
                           strstr(out, "Origin = (0.000000000000000,40.000000000000000)") &&
                           strstr(out, "Pixel Size = (4.000000000000000,-4.000000000000000)") &&
                           strstr(out, "Lambert-93") && strstr(out, "NoData Value=-9999") &&
                           !strstr(out, "Warning") && !strstr(out, "ERROR"),
                       "%s", out);
            free(out);
        }
        /* the cell most passed, read by GDAL at its pixel (row 0 the northern one) */
        long ix = dbt_int(db, "SELECT ix FROM hazard_cells ORDER BY passes DESC, ix, iy");
        long iy = dbt_int(db, "SELECT iy FROM hazard_cells ORDER BY passes DESC, ix, iy");
        for (int m = 0; m < 5; m++) {
            char cmd[4400];
            snprintf(cmd, sizeof cmd, "gdallocationinfo -valonly '%s/%s.asc' %ld %ld", dir,
                     name[m], ix, 9 - iy);
            char *out = capture(cmd);
            double want = dbt_real(db, "SELECT %s FROM hazard_cells WHERE ix = %ld AND iy = %ld",
                                   column[m], ix, iy);
            ENSURE(out);
            ENSURE_REL(strtod(out, NULL), want, 1e-6); /* AAIGrid reads reals as Float32 */
            free(out);
        }
    }
    for (int m = 0; m < 6; m++)
        free(g[m].v);
    sqlite3_close(db);
    rf_project_free(&p);
}

/* ---- files that are not ours, and older ones -------------------------------------------- */

static char *read_bytes(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    ENSURE(f);
    char *b = malloc(1 << 20);
    ENSURE(b);
    *n = fread(b, 1, 1 << 20, f);
    fclose(f);
    return b;
}

/* A planner's own GeoPackage named as -o is refused and left byte for byte as it was;
 * the readers refuse it too. */
TEST(gis_another_geopackage_is_refused_and_untouched)
{
    const char *yaml = write_project("p.yaml", "");
    char theirs[4096];
    snprintf(theirs, sizeof theirs, "%s", rf_test_path("theirs.gpkg"));
    if (have_tool("ogr2ogr")) {
        const char *json = rf_test_write("road.geojson",
                                         "{\"type\": \"FeatureCollection\", \"features\": [{\"type\":"
                                         " \"Feature\", \"properties\": {\"name\": \"road\"},"
                                         " \"geometry\": {\"type\": \"LineString\", \"coordinates\":"
                                         " [[0, 10], [40, 10]]}}]}");
        char cmd[8400];
        snprintf(cmd, sizeof cmd, "ogr2ogr -f GPKG '%s' '%s'", theirs, json);
        ENSURE(system(cmd) == 0);
    } else {
        sqlite3 *db = NULL;
        ENSURE(sqlite3_open(theirs, &db) == SQLITE_OK);
        ENSURE(sqlite3_exec(db, "PRAGMA application_id = 1196444487; PRAGMA user_version = 10300;"
                                " CREATE TABLE gpkg_contents (table_name TEXT PRIMARY KEY);",
                            NULL, NULL, NULL) == SQLITE_OK);
        sqlite3_close(db);
    }
    size_t n0, n1;
    char *before = read_bytes(theirs, &n0);
    const char *out = rockfall(2, "run %s -o %s", yaml, theirs);
    ENSURE_MSG(strstr(out, "a GeoPackage of another program"), "%s", out);
    out = rockfall(2, "export %s --out %s", theirs, rf_test_path("maps"));
    ENSURE_MSG(strstr(out, "a GeoPackage of another program"), "%s", out);
    char *after = read_bytes(theirs, &n1);
    ENSURE(n0 == n1 && memcmp(before, after, n0) == 0);
    char side[4200];
    snprintf(side, sizeof side, "%s-journal", theirs);
    ENSURE(access(side, F_OK) != 0);
    snprintf(side, sizeof side, "%s-wal", theirs);
    ENSURE(access(side, F_OK) != 0);
    free(before);
    free(after);
}

/* A file of schema version 3 becomes a GeoPackage in the one transaction of its
 * upgrade: its run's rows kept, its layers filled from them in the undefined CRS; a
 * later run with a CRS is refused there (a layer has one CRS), the file unchanged. */
TEST(gis_older_file_upgraded_to_a_geopackage)
{
    size_t n;
    char *v3 = read_bytes("tests/data/results-v3.db", &n);
    FILE *f = fopen(rf_test_path("old.gpkg"), "wb");
    ENSURE(f && fwrite(v3, 1, n, f) == n);
    fclose(f);
    free(v3);
    char path[4096];
    snprintf(path, sizeof path, "%s", rf_test_path("old.gpkg"));
    sqlite3 *db = open_db(path);
    const char *rows = "SELECT group_concat(id || stop_x || stop_reason || max_energy_kj) FROM"
                       " (SELECT * FROM trajectories ORDER BY id)";
    sqlite3_stmt *st;
    ENSURE(sqlite3_prepare_v2(db, rows, -1, &st, NULL) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW);
    char *before = strdup((const char *)sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    long long old_stops = dbt_int(db, "SELECT count(*) FROM trajectories WHERE stop_x IS NOT NULL");
    sqlite3_close(db);

    rockfall(0, "run %s -o %s -q", write_project("p.yaml", ""), path);
    db = open_db(path);
    ENSURE(dbt_int(db, "SELECT version FROM rockfall_schema") >= 5);
    ENSURE(dbt_int(db, "PRAGMA application_id") == 0x47504B47 &&
           dbt_int(db, "PRAGMA user_version") == 10300);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_table_info('runs') WHERE name = 'seed'"
                       " AND type = 'INTEGER'") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs WHERE id = 1 AND crs IS NULL AND srs_id = -1") == 1);
    ENSURE(dbt_int(db, "SELECT count(*) FROM stop_points WHERE run_id = 1") == old_stops);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measure_lines WHERE run_id = 1") ==
           dbt_int(db, "SELECT count(*) FROM measures WHERE run_id = 1"));
    ENSURE(dbt_int(db, "SELECT count(*) FROM stop_points WHERE run_id = 2") > 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM pragma_foreign_key_check") == 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM run_verdicts") == 2);
    ENSURE(sqlite3_prepare_v2(db, "SELECT group_concat(id || stop_x || stop_reason || max_energy_kj)"
                                  " FROM (SELECT * FROM trajectories WHERE run_id = 1 ORDER BY id)",
                              -1, &st, NULL) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW);
    ENSURE(!strcmp(before, (const char *)sqlite3_column_text(st, 0)));
    sqlite3_finalize(st);
    sqlite3_close(db);
    if (have_tool("ogrinfo")) {
        char cmd[4200];
        snprintf(cmd, sizeof cmd, "ogrinfo -ro -so '%s' stop_points measure_lines", path);
        char *info = capture(cmd);
        ENSURE(info);
        ENSURE_MSG(strstr(info, "using driver `GPKG' successful") && !strstr(info, "Warning") &&
                       !strstr(info, "ERROR") && strstr(info, "Layer name: stop_points"),
                   "%s", info);
        free(info);
    }

    const char *out = rockfall(2, "run %s -o %s", write_project("q.yaml", "crs: EPSG:2154"), path);
    ENSURE_MSG(strstr(out, "the file's layers are in the CRS 'Undefined cartesian SRS' and the "
                           "project's is 'RGF93 v1 / Lambert-93'"), "%s", out);
    db = open_db(path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM runs") == 2);
    sqlite3_close(db);
    free(before);
}

/* ---- layouts drawn in QGIS --------------------------------------------------------------- */

/* A GeoPackage layer NAME in DIR's FILE made by ogr2ogr from GeoJSON features (in
 * Lambert-93 unless crs says another); 0 when ogr2ogr is not installed. */
static int make_layer(const char *file, const char *layer, const char *crs, const char *features)
{
    if (!have_tool("ogr2ogr"))
        return 0;
    char json[8192], name[300], cmd[9000];
    snprintf(json, sizeof json,
             "{\"type\": \"FeatureCollection\", \"crs\": {\"type\": \"name\", \"properties\":"
             " {\"name\": \"urn:ogc:def:crs:%s\"}}, \"features\": [%s]}",
             crs, features);
    snprintf(name, sizeof name, "%s.geojson", layer);
    const char *src = rf_test_write(name, json);
    char src_keep[4096];
    snprintf(src_keep, sizeof src_keep, "%s", src);
    const char *dst = rf_test_path(file);
    snprintf(cmd, sizeof cmd, "ogr2ogr -f GPKG %s-nln %s '%s' '%s'",
             access(dst, F_OK) == 0 ? "-update " : "", layer, dst, src_keep);
    ENSURE_MSG(system(cmd) == 0, "%s", cmd);
    return 1;
}

#define L93 "EPSG::2154"
#define FEATURE(props, geom) \
    "{\"type\": \"Feature\", \"properties\": {" props "}, \"geometry\": " geom "}"

static const char layout_measures[] =
    FEATURE("\"name\": \"B1\", \"kind\": \"barrier\", \"height\": 3, \"mel\": 1000",
            "{\"type\": \"LineString\", \"coordinates\": [[0, 20], [40, 20.5]]}") ","
    FEATURE("\"name\": \"E1\", \"kind\": \"embankment\", \"height\": 4,"
            " \"capacity_serviceability\": 500, \"capacity_ultimate\": 2000",
            "{\"type\": \"LineString\", \"coordinates\": [[0, 15, 3], [40, 15, 3]]}") ","
    FEATURE("\"name\": \"road\", \"kind\": \"control\"",
            "{\"type\": \"MultiLineString\", \"coordinates\": [[[0, 10], [40, 10]]]}");

static const char layout_releases[] =
    FEATURE("\"rock\": \"r\", \"count\": 3", "{\"type\": \"Point\", \"coordinates\": [20, 35]}") ","
    FEATURE("\"name\": \"scarp\", \"rock\": \"r\", \"count\": 5",
            "{\"type\": \"Polygon\", \"coordinates\": [[[5, 30], [35, 30], [35, 36], [5, 36], [5, 30]]]}");

static const char *layout_project(const char *name, const char *crs, const char *measures_layer)
{
    char *dem = realpath("tests/data/project/plane5.asc", NULL);
    ENSURE(dem);
    char text[2048];
    snprintf(text, sizeof text,
             "name: layout\n"
             "crs: %s\n"
             "terrain: {dem: %s}\n"
             "rocks: [{name: r, mass: 500}]\n"
             "releases:\n"
             "  - {gpkg: layout.gpkg, layer: releases}\n"
             "measures:\n"
             "  - {gpkg: layout.gpkg, layer: %s}\n"
             "vegetation:\n"
             "  - {gpkg: layout.gpkg, layer: forest}\n"
             "simulation: {model: point, paths: 2}\n",
             crs, dem, measures_layer);
    free(dem);
    return rf_test_write(name, text);
}

/* A layout written by ogr2ogr from GeoJSON is read back as the project's measures,
 * releases and forest, and the rocks cross its barrier. */
TEST(gis_layout_from_a_geopackage_read_back_and_crossed)
{
    if (!make_layer("layout.gpkg", "measures", L93, layout_measures))
        return;
    make_layer("layout.gpkg", "releases", L93, layout_releases);
    make_layer("layout.gpkg", "forest", L93,
               FEATURE("\"name\": \"wood\", \"density\": 0.01, \"height_mean\": 5, \"height_sd\": 1,"
                       " \"diameter\": 0.2",
                       "{\"type\": \"MultiPolygon\", \"coordinates\": [[[[0, 0], [40, 0], [40, 12],"
                       " [0, 12], [0, 0]]]]}"));
    char yaml[4096];
    snprintf(yaml, sizeof yaml, "%s", layout_project("p.yaml", "EPSG:2154", "measures"));
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%d:%d %s", err.line, err.column, err.message);
    ENSURE(p.nmeasures == 3 && p.nreleases == 2 && p.nforests == 1);
    ENSURE(!strcmp(p.measures[0].name, "B1") && p.measures[0].kind == RF_BARRIER &&
           p.measures[0].height == 3 && p.measures[0].mel == 1000);
    ENSURE(p.measures[0].line.n == 2 && p.measures[0].line.xy[3] == 20.5);
    ENSURE(p.measures[1].kind == RF_EMBANKMENT && p.measures[1].capacity[RF_SERVICEABILITY] == 500 &&
           p.measures[1].capacity[RF_ULTIMATE] == 2000);
    ENSURE(p.measures[2].kind == RF_CONTROL && p.measures[2].line.n == 2);
    /* a feature without a name is named after its layer and id */
    ENSURE(!strcmp(p.releases[0].name, "releases-1") && p.releases[0].source == RF_SOURCE_POINT &&
           p.releases[0].count == 3);
    ENSURE(p.releases[1].source == RF_SOURCE_AREA && p.releases[1].narea == 4); /* not closed again */
    ENSURE(p.forests[0].density == 0.01 && p.forests[0].height.mean == 5 &&
           p.forests[0].height.sd == 1 && p.forests[0].polygon.n == 4);
    rf_project_free(&p);

    /* a zone of two parts: one zone holding both (even-odd over the joined rings) */
    make_layer("layout.gpkg", "zones", L93,
               FEATURE("\"name\": \"talus\", \"class\": \"D\"",
                       "{\"type\": \"MultiPolygon\", \"coordinates\": [[[[0, 0], [10, 0], [10, 10],"
                       " [0, 10], [0, 0]]], [[[30, 30], [40, 30], [40, 40], [30, 40], [30, 30]]]]}"));
    char *text = rf_test_read_text(yaml);
    ENSURE(text);
    char *dem = strstr(text, "terrain: {dem: ");
    ENSURE(dem && strchr(dem, '}'));
    char zoned[4096];
    snprintf(zoned, sizeof zoned, "%.*s, zones: [{gpkg: layout.gpkg, layer: zones}]%s",
             (int)(strchr(dem, '}') - text), text, strchr(dem, '}'));
    ENSURE_MSG(rf_project_load(rf_test_write("z.yaml", zoned), &p, &err) == 0, "%s", err.message);
    ENSURE(p.terrain_spec.nzones == 1);
    const rf_zone_spec *z = &p.terrain_spec.zones[0];
    ENSURE(rf_point_in_polygon(z->poly_xy, z->npoly, 5, 5) &&
           rf_point_in_polygon(z->poly_xy, z->npoly, 35, 35) &&
           !rf_point_in_polygon(z->poly_xy, z->npoly, 20, 5) &&
           !rf_point_in_polygon(z->poly_xy, z->npoly, 5, 30));
    rf_project_free(&p);
    free(text);

    char db_path[4096];
    snprintf(db_path, sizeof db_path, "%s", rf_test_path("r.gpkg"));
    rockfall(0, "run %s -o %s -q", yaml, db_path);
    sqlite3 *db = open_db(db_path);
    ENSURE(dbt_int(db, "SELECT count(*) FROM interceptions i JOIN measures m ON m.id = i.measure_id"
                       " WHERE m.name = 'B1'") > 0);
    ENSURE(dbt_int(db, "SELECT count(*) FROM measure_lines WHERE name IN ('B1', 'E1', 'road')") == 3);
    sqlite3_close(db);
}

/* Errors name the file, the layer, the feature id and the attribute, at the item's line
 * and column; a layer in another CRS is refused; a geometry the list does not take is
 * an error. */
TEST(gis_layout_errors_name_the_feature)
{
    if (!make_layer("layout.gpkg", "measures", L93,
                    FEATURE("\"name\": \"B1\", \"kind\": \"barrier\", \"height\": 3, \"mel\": 1000",
                            "{\"type\": \"LineString\", \"coordinates\": [[0, 20], [40, 20]]}") ","
                    FEATURE("\"name\": \"B2\", \"kind\": \"barrier\", \"height\": 3, \"mel\": -3",
                            "{\"type\": \"LineString\", \"coordinates\": [[0, 25], [40, 25]]}")))
        return;
    make_layer("layout.gpkg", "releases", L93, layout_releases);
    make_layer("layout.gpkg", "forest", L93,
               FEATURE("\"name\": \"wood\", \"density\": 0.01, \"height\": 5, \"diameter\": 0.2",
                       "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [40, 0], [40, 12], [0, 12],"
                       " [0, 0]]]}"));
    make_layer("holes.gpkg", "forest", L93,
               FEATURE("\"name\": \"wood\", \"density\": 0.01, \"height\": 5, \"diameter\": 0.2",
                       "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [40, 0], [40, 12], [0, 12],"
                       " [0, 0]], [[10, 2], [20, 2], [20, 8], [10, 2]]]}"));
    make_layer("layout.gpkg", "points", L93,
               FEATURE("\"name\": \"B3\", \"kind\": \"barrier\"",
                       "{\"type\": \"Point\", \"coordinates\": [20, 35]}"));
    rf_project p;
    rf_error err;
    ENSURE(rf_project_load(layout_project("a.yaml", "EPSG:2154", "measures"), &p, &err) != 0);
    ENSURE_MSG(err.line == 8 && err.column == 5 &&
                   strstr(err.message, "layout.gpkg, layer 'measures', feature 2, attribute 'mel': "
                                       "'mel' must be a number > 0, got -3"),
               "%d:%d %s", err.line, err.column, err.message);
    ENSURE(rf_project_load(layout_project("b.yaml", "EPSG:2154", "points"), &p, &err) != 0);
    ENSURE_MSG(strstr(err.message, "layer 'points', feature 1, its geometry: a Point; a measure "
                                   "takes a LineString"), "%s", err.message);
    ENSURE(rf_project_load(layout_project("c.yaml", "EPSG:2154", "nothere"), &p, &err) != 0);
    ENSURE_MSG(err.line == 8 && strstr(err.message, "no feature layer 'nothere'"), "%s", err.message);
    /* a forest's hole is kept (even-odd: its cut changes nothing); a release area's is
     * refused */
    char *text = rf_test_read_text(layout_project("d.yaml", "EPSG:2154", "points"));
    ENSURE(text);
    char *at = strstr(text, "  - {gpkg: layout.gpkg, layer: forest}");
    ENSURE(at);
    memcpy(at, "  - {gpkg:  holes.gpkg, layer: forest}", 38);
    at = strstr(text, "measures:\n  - {gpkg: layout.gpkg, layer: points}\n");
    ENSURE(at);
    memset(at, ' ', strlen("measures:\n  - {gpkg: layout.gpkg, layer: points}"));
    at[strlen("measures:")] = '\n';
    ENSURE_MSG(rf_project_load(rf_test_write("d.yaml", text), &p, &err) == 0, "%s", err.message);
    ENSURE(p.nforests == 1);
    const rf_polyline *f = &p.forests[0].polygon;
    ENSURE(rf_point_in_polygon(f->xy, f->n, 5, 5) && rf_point_in_polygon(f->xy, f->n, 30, 6));
    ENSURE(!rf_point_in_polygon(f->xy, f->n, 18, 3)); /* in the hole */
    ENSURE(!rf_point_in_polygon(f->xy, f->n, 20, 20)); /* outside */
    rf_project_free(&p);
    free(text);
    make_layer("holes.gpkg", "releases", L93,
               FEATURE("\"name\": \"scarp\", \"rock\": \"r\"",
                       "{\"type\": \"Polygon\", \"coordinates\": [[[5, 30], [35, 30], [35, 36], [5, 36],"
                       " [5, 30]], [[10, 31], [12, 31], [12, 33], [10, 31]]]}"));
    text = rf_test_read_text(layout_project("g.yaml", "EPSG:2154", "measures"));
    ENSURE(text);
    at = strstr(text, "  - {gpkg: layout.gpkg, layer: releases}");
    ENSURE(at);
    memcpy(at, "  - {gpkg:  holes.gpkg, layer: releases}", 40);
    ENSURE(rf_project_load(rf_test_write("g.yaml", text), &p, &err) != 0);
    ENSURE_MSG(err.line == 6 && strstr(err.message, "holes.gpkg, layer 'releases', feature 1, its "
                                                     "geometry: a Polygon of 1 parts and 2 rings; a "
                                                     "release area is one outer ring without holes"),
               "%s", err.message);
    free(text);
    /* a project in another CRS than the layers' */
    ENSURE(rf_project_load(layout_project("e.yaml", "EPSG:2056", "measures"), &p, &err) != 0);
    ENSURE_MSG(err.line == 6 && err.column == 5 &&
                   strstr(err.message, "layer 'releases' of '") &&
                   strstr(err.message, "is in the CRS 'RGF93 v1 / Lambert-93' and the project's is "
                                       "'CH1903+ / LV95': rockfall does not reproject"),
               "%d:%d %s", err.line, err.column, err.message);
}

/* Runs sql on a GeoPackage made by ogr2ogr, its triggers dropped (they call GDAL's own
 * SQL functions). */
static void exec_on_layout(const char *file, const char *sql)
{
    sqlite3 *db = NULL;
    ENSURE(sqlite3_open(rf_test_path(file), &db) == SQLITE_OK);
    ENSURE(sqlite3_exec(db,
                        "CREATE TEMP TABLE t AS SELECT name FROM sqlite_master WHERE type = 'trigger'",
                        NULL, NULL, NULL) == SQLITE_OK);
    sqlite3_stmt *st;
    ENSURE(sqlite3_prepare_v2(db, "SELECT name FROM t", -1, &st, NULL) == SQLITE_OK);
    while (sqlite3_step(st) == SQLITE_ROW) {
        char drop[512];
        snprintf(drop, sizeof drop, "DROP TRIGGER \"%s\"", (const char *)sqlite3_column_text(st, 0));
        ENSURE(sqlite3_exec(db, drop, NULL, NULL, NULL) == SQLITE_OK);
    }
    sqlite3_finalize(st);
    ENSURE_MSG(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK, "%s", sqlite3_errmsg(db));
    sqlite3_close(db);
}

/* A feature whose geometry has no points (a LineString of 0 points, a Polygon of one
 * empty ring: WKB a GIS may write for an emptied shape) is refused by the item's own
 * check, naming the feature. */
TEST(gis_layout_empty_geometry_is_refused_naming_the_feature)
{
    /* GeoPackage header (little-endian, no envelope, srs 2154), then the WKB */
    static const char *const empty[2] = {
        "X'4750000168080000' || X'010200000000000000'",         /* LineString, 0 points */
        "X'4750000168080000' || X'01030000000100000000000000'", /* Polygon, 1 ring of 0 */
    };
    static const char *const table[2] = {"measures", "forest"};
    for (int k = 0; k < 2; k++) {
        char file[32];
        snprintf(file, sizeof file, "layout.gpkg");
        unlink(rf_test_path(file));
        if (!make_layer(file, "measures", L93, layout_measures))
            return;
        make_layer(file, "releases", L93, layout_releases);
        make_layer(file, "forest", L93,
                   FEATURE("\"name\": \"wood\", \"density\": 0.01, \"height\": 5, \"diameter\": 0.2",
                           "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [40, 0], [40, 12],"
                           " [0, 12], [0, 0]]]}"));
        char sql[256], want[64];
        snprintf(sql, sizeof sql, "UPDATE %s SET geom = %s WHERE fid = 1", table[k], empty[k]);
        exec_on_layout(file, sql);
        snprintf(want, sizeof want, "layer '%s', feature 1", table[k]);
        rf_project p;
        rf_error err;
        ENSURE(rf_project_load(layout_project("e.yaml", "EPSG:2154", "measures"), &p, &err) != 0);
        ENSURE_MSG(strstr(err.message, want), "%d:%d %s", err.line, err.column, err.message);
        printf("    %d:%d %s\n", err.line, err.column, err.message);
    }
}
