/* gpkg.c - the results database as an extended OGC GeoPackage 1.3 (results/gpkg.h).
 *
 * Geometries are GeoPackage binary (OGC 12-128r18, 2.1.3): the header "GP", version 0,
 * flags (little endian, an [minx, maxx, miny, maxy] envelope), the srs_id, the
 * envelope, then ISO WKB in little endian (Point 1, LineString 2, Polygon 3; with Z
 * 1000 more).  They are built by SQL functions registered on the connection, so that a
 * layer is one INSERT ... SELECT over the run's rows, the same when a run ends and when
 * an older file is upgraded. */
#include "results/gpkg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "results/schema.h"

#define RF_NOW_SQL "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"

/* ---- geometry blobs ------------------------------------------------------------------ */

enum { WKB_POINT = 1, WKB_LINESTRING = 2, WKB_POLYGON = 3, WKB_Z = 1000 };
enum { GP_HEADER = 8, GP_ENVELOPE = 32 };

typedef struct gbuf {
    unsigned char *b;
    size_t n, cap;
    int oom;
    double env[4]; /* minx, maxx, miny, maxy */
} gbuf;

static void put(gbuf *g, const void *p, size_t len)
{
    if (g->oom)
        return;
    if (g->n + len > g->cap) {
        size_t cap = g->cap ? 2 * g->cap : 256;
        while (cap < g->n + len)
            cap *= 2;
        unsigned char *b = realloc(g->b, cap);
        if (!b) {
            g->oom = 1;
            return;
        }
        g->b = b;
        g->cap = cap;
    }
    memcpy(g->b + g->n, p, len);
    g->n += len;
}

static void put_u32(gbuf *g, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    put(g, b, 4);
}

static void put_f64(gbuf *g, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    unsigned char b[8];
    for (int k = 0; k < 8; k++)
        b[k] = (unsigned char)(u >> (8 * k));
    put(g, b, 8);
}

static double get_f64(const unsigned char *b)
{
    uint64_t u = 0;
    for (int k = 7; k >= 0; k--)
        u = (u << 8) | b[k];
    double v;
    memcpy(&v, &u, 8);
    return v;
}

/* The header with room for the envelope, and the WKB's byte order and type. */
static void begin_geometry(gbuf *g, int32_t srs, uint32_t wkb_type)
{
    g->n = 0;
    g->oom = 0;
    g->env[0] = g->env[2] = INFINITY;
    g->env[1] = g->env[3] = -INFINITY;
    const unsigned char head[4] = {'G', 'P', 0, 0x01 | (1 << 1)}; /* LE, xy envelope */
    put(g, head, 4);
    put_u32(g, (uint32_t)srs);
    for (int k = 0; k < 4; k++)
        put_f64(g, 0.0);
    const unsigned char order = 1;
    put(g, &order, 1);
    put_u32(g, wkb_type);
}

static void put_xy(gbuf *g, double x, double y)
{
    put_f64(g, x);
    put_f64(g, y);
    g->env[0] = fmin(g->env[0], x);
    g->env[1] = fmax(g->env[1], x);
    g->env[2] = fmin(g->env[2], y);
    g->env[3] = fmax(g->env[3], y);
}

/* Writes the envelope into the header; 0, or -1 when memory ran out. */
static int end_geometry(gbuf *g)
{
    if (g->oom)
        return -1;
    for (int k = 0; k < 4; k++) {
        uint64_t u;
        memcpy(&u, &g->env[k], 8);
        for (int i = 0; i < 8; i++)
            g->b[GP_HEADER + 8 * k + i] = (unsigned char)(u >> (8 * i));
    }
    return 0;
}

/* A closed ring of polygon vertices (xy pairs, n of them, not repeated at the end). */
static void put_ring(gbuf *g, const double *xy, size_t n)
{
    put_u32(g, (uint32_t)(n + 1));
    for (size_t i = 0; i <= n; i++)
        put_xy(g, xy[2 * (i % n)], xy[2 * (i % n) + 1]);
}

/* ---- SQL functions ------------------------------------------------------------------- */

static void result_blob(sqlite3_context *ctx, gbuf *g)
{
    if (end_geometry(g)) {
        free(g->b);
        sqlite3_result_error_nomem(ctx);
        return;
    }
    sqlite3_result_blob(ctx, g->b, (int)g->n, free);
}

static int all_numbers(int argc, sqlite3_value **argv)
{
    for (int i = 0; i < argc; i++) {
        int t = sqlite3_value_type(argv[i]);
        if (t != SQLITE_INTEGER && t != SQLITE_FLOAT)
            return 0;
    }
    return 1;
}

/* rf_gpkg_point(srs, x, y): a Point; NULL where x or y is. */
static void fn_point(sqlite3_context *ctx, int argc, sqlite3_value **argv)
{
    if (!all_numbers(argc, argv)) {
        sqlite3_result_null(ctx);
        return;
    }
    gbuf g = {0};
    begin_geometry(&g, sqlite3_value_int(argv[0]), WKB_POINT);
    put_xy(&g, sqlite3_value_double(argv[1]), sqlite3_value_double(argv[2]));
    result_blob(ctx, &g);
}

/* rf_gpkg_box(srs, x0, y0, x1, y1): the rectangle as a Polygon, counter-clockwise. */
static void fn_box(sqlite3_context *ctx, int argc, sqlite3_value **argv)
{
    if (!all_numbers(argc, argv)) {
        sqlite3_result_null(ctx);
        return;
    }
    double x0 = sqlite3_value_double(argv[1]), y0 = sqlite3_value_double(argv[2]);
    double x1 = sqlite3_value_double(argv[3]), y1 = sqlite3_value_double(argv[4]);
    const double xy[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    gbuf g = {0};
    begin_geometry(&g, sqlite3_value_int(argv[0]), WKB_POLYGON);
    put_u32(&g, 1);
    put_ring(&g, xy, 4);
    result_blob(ctx, &g);
}

/* rf_gpkg_line(srs, line): a LineString from a measure's line as measures.line holds it,
 * JSON [[x0,y0],[x1,y1],...]; NULL when it is not that or has fewer than 2 points. */
static void fn_line(sqlite3_context *ctx, int argc, sqlite3_value **argv)
{
    (void)argc;
    const char *s = (const char *)sqlite3_value_text(argv[1]);
    double *v = NULL;
    size_t n = 0, cap = 0;
    int bad = !s;
    while (!bad && *s) {
        if (strchr("[], \t\r\n", *s)) {
            s++;
            continue;
        }
        char *end;
        double x = strtod(s, &end);
        if (end == s || !isfinite(x)) {
            bad = 1;
            break;
        }
        if (n == cap) {
            double *w = realloc(v, (cap ? 2 * cap : 16) * sizeof *v);
            if (!w) {
                free(v);
                sqlite3_result_error_nomem(ctx);
                return;
            }
            v = w;
            cap = cap ? 2 * cap : 16;
        }
        v[n++] = x;
        s = end;
    }
    if (bad || n % 2 || n < 4) {
        free(v);
        sqlite3_result_null(ctx);
        return;
    }
    gbuf g = {0};
    begin_geometry(&g, sqlite3_value_int(argv[0]), WKB_LINESTRING);
    put_u32(&g, (uint32_t)(n / 2));
    for (size_t i = 0; i < n; i += 2)
        put_xy(&g, v[i], v[i + 1]);
    free(v);
    result_blob(ctx, &g);
}

/* rf_gpkg_env(geom, k): component k of the geometry's envelope (0 minx, 1 maxx, 2 miny,
 * 3 maxy); NULL when it has none. */
static void fn_env(sqlite3_context *ctx, int argc, sqlite3_value **argv)
{
    (void)argc;
    const unsigned char *b = sqlite3_value_blob(argv[0]);
    int n = sqlite3_value_bytes(argv[0]), k = sqlite3_value_int(argv[1]);
    if (!b || n < GP_HEADER + GP_ENVELOPE || b[0] != 'G' || b[1] != 'P' ||
        ((b[3] >> 1) & 7) == 0 || !(b[3] & 1) || k < 0 || k > 3) {
        sqlite3_result_null(ctx);
        return;
    }
    sqlite3_result_double(ctx, get_f64(b + GP_HEADER + 8 * k));
}

int rf_gpkg_register(sqlite3 *db)
{
    const int flags = SQLITE_UTF8 | SQLITE_DETERMINISTIC;
    int rc = sqlite3_create_function(db, "rf_gpkg_point", 3, flags, NULL, fn_point, NULL, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_create_function(db, "rf_gpkg_box", 5, flags, NULL, fn_box, NULL, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_create_function(db, "rf_gpkg_line", 2, flags, NULL, fn_line, NULL, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_create_function(db, "rf_gpkg_env", 2, flags, NULL, fn_env, NULL, NULL);
    return rc;
}

/* ---- the tables --------------------------------------------------------------------- */

/* The required tables, as OGC 12-128r18 Annex C declares them, and the extension table
 * (Annex F.1). */
static const char required_sql[] =
    "CREATE TABLE gpkg_spatial_ref_sys (\n"
    "  srs_name TEXT NOT NULL,\n"
    "  srs_id INTEGER PRIMARY KEY,\n"
    "  organization TEXT NOT NULL,\n"
    "  organization_coordsys_id INTEGER NOT NULL,\n"
    "  definition TEXT NOT NULL,\n"
    "  description TEXT\n"
    ");\n"
    "CREATE TABLE gpkg_contents (\n"
    "  table_name TEXT NOT NULL PRIMARY KEY,\n"
    "  data_type TEXT NOT NULL,\n"
    "  identifier TEXT UNIQUE,\n"
    "  description TEXT DEFAULT '',\n"
    "  last_change DATETIME NOT NULL DEFAULT (" RF_NOW_SQL "),\n"
    "  min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE,\n"
    "  srs_id INTEGER,\n"
    "  CONSTRAINT fk_gc_r_srs_id FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id)\n"
    ");\n"
    "CREATE TABLE gpkg_geometry_columns (\n"
    "  table_name TEXT NOT NULL,\n"
    "  column_name TEXT NOT NULL,\n"
    "  geometry_type_name TEXT NOT NULL,\n"
    "  srs_id INTEGER NOT NULL,\n"
    "  z TINYINT NOT NULL,\n"
    "  m TINYINT NOT NULL,\n"
    "  CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),\n"
    "  CONSTRAINT uk_gc_table_name UNIQUE (table_name),\n"
    "  CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),\n"
    "  CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id)\n"
    ");\n"
    "CREATE TABLE gpkg_extensions (\n"
    "  table_name TEXT,\n"
    "  column_name TEXT,\n"
    "  extension_name TEXT NOT NULL,\n"
    "  definition TEXT NOT NULL,\n"
    "  scope TEXT NOT NULL,\n"
    "  CONSTRAINT ge_tce UNIQUE (table_name, column_name, extension_name)\n"
    ");\n"
    "INSERT INTO gpkg_spatial_ref_sys VALUES ('WGS 84 geodetic', 4326, 'EPSG', 4326,\n"
    "  'GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
    "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
    "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\","
    "\"9122\"]],AXIS[\"Latitude\",NORTH],AXIS[\"Longitude\",EAST],AUTHORITY[\"EPSG\",\"4326\"]]',\n"
    "  'longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid');\n"
    "INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined cartesian SRS', -1, 'NONE', -1,\n"
    "  'undefined', 'undefined cartesian coordinate reference system');\n"
    "INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined geographic SRS', 0, 'NONE', 0,\n"
    "  'undefined', 'undefined geographic coordinate reference system');\n"
    "PRAGMA application_id = 1196444487;\n" /* RF_GPKG_APPLICATION_ID */
    "PRAGMA user_version = 10300;\n";       /* RF_GPKG_USER_VERSION */

/* One feature layer: its table's columns after fid and geom, its geometry. */
typedef struct layer {
    const char *name, *geometry, *description, *columns;
    int z;
} layer;

static const layer layers[] = {
    {"release_points", "POINT", "each release's point (an area's centroid, a mask's first cell)",
     "run_id INTEGER NOT NULL, release_id INTEGER NOT NULL, name TEXT, rock TEXT,"
     " mass_kg REAL, action_level INTEGER, count INTEGER, z REAL", 0},
    {"release_areas", "POLYGON", "each area release's polygon",
     "run_id INTEGER NOT NULL, release_id INTEGER NOT NULL, name TEXT, rock TEXT,"
     " count INTEGER", 0},
    {"measure_lines", "LINESTRING", "the barriers, embankments and control lines",
     "run_id INTEGER NOT NULL, measure_id INTEGER NOT NULL, idx INTEGER, name TEXT,"
     " kind TEXT, importance TEXT, height_m REAL, behaviour TEXT, mel_kj REAL, sel_kj REAL",
     0},
    {"stop_points", "POINT", "where each trajectory ended",
     "run_id INTEGER NOT NULL, trajectory_id INTEGER NOT NULL, release TEXT, idx INTEGER,"
     " stop_reason TEXT, z REAL, mass_kg REAL, max_energy_kj REAL, path_length_m REAL,"
     " duration_s REAL, n_impacts INTEGER", 0},
    {"paths", "LINESTRING", "the sampled trajectories (simulation.paths per release), in 3D",
     "run_id INTEGER NOT NULL, trajectory_id INTEGER NOT NULL, release TEXT, idx INTEGER,"
     " stop_reason TEXT, max_energy_kj REAL, path_length_m REAL", 1},
    {"interception_points", "POINT", "each crossing of a measure's line",
     "run_id INTEGER NOT NULL, interception_id INTEGER NOT NULL, trajectory_id INTEGER,"
     " measure_id INTEGER, measure TEXT, kind TEXT, release TEXT, z REAL, energy_kj REAL,"
     " speed_ms REAL, passing_height_m REAL, outcome TEXT", 0},
    {"hazard_map", "POLYGON", "the hazard grid's cells reached by a rock",
     "run_id INTEGER NOT NULL, ix INTEGER, iy INTEGER, passes INTEGER,"
     " reach_probability REAL, energy_max_kj REAL, energy_p95_kj REAL, height_p95_m REAL", 0},
};
enum { N_LAYERS = sizeof layers / sizeof layers[0] };

/* The extension every table and view of the tool's own belongs to (OGC 12-128r18,
 * 2.3.2: the author "rockfall"); write-only: a GeoPackage reader may read the file
 * without knowing it, a writer must keep the tables' rules (docs/database.md). */
#define EXTENSION_NAME "rockfall_results"
#define EXTENSION_DEFINITION "rockfall: docs/database.md, the results database"

static int exec_sql(sqlite3 *db, const char *path, const char *sql, const char *doing,
                    rf_error *err)
{
    return rf_sql_status(db, path, sqlite3_exec(db, sql, NULL, NULL, NULL), doing, err);
}

static int create_layers(sqlite3 *db, const char *path, rf_error *err)
{
    for (int i = 0; i < N_LAYERS; i++) {
        const layer *l = &layers[i];
        char *sql = sqlite3_mprintf(
            "CREATE TABLE \"%w\" (fid INTEGER PRIMARY KEY AUTOINCREMENT, geom %s, %s);\n"
            "CREATE INDEX \"%w_run\" ON \"%w\"(run_id);\n"
            "INSERT INTO gpkg_contents (table_name, data_type, identifier, description,"
            " srs_id) VALUES (%Q, 'features', %Q, %Q, -1);\n"
            "INSERT INTO gpkg_geometry_columns VALUES (%Q, 'geom', %Q, -1, %d, 0);\n",
            l->name, l->geometry, l->columns, l->name, l->name, l->name, l->name,
            l->description, l->name, l->geometry, l->z);
        if (!sql)
            return rf_error_set(err, path, 0, 0, "out of memory creating the layers");
        int status = exec_sql(db, path, sql, "creating the GeoPackage layers", err);
        sqlite3_free(sql);
        if (status)
            return -1;
    }
    return 0;
}

/* The runs table of an older file rebuilt with its seed declared INTEGER (a GeoPackage
 * declares every column's type, Requirement 5), then the CRS columns. */
static int rebuild_runs(sqlite3 *db, const char *path, rf_error *err)
{
    const char *doing = "upgrading the runs table";
    sqlite3_stmt *st = NULL;
    char *create = NULL;
    int rc = sqlite3_prepare_v2(db, "SELECT sql FROM sqlite_master WHERE name = 'runs'", -1,
                                &st, NULL);
    if (rc == SQLITE_OK && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        const char *sql = (const char *)sqlite3_column_text(st, 0);
        const char *open = sql ? strchr(sql, '(') : NULL, *seed = sql ? strstr(sql, "seed NOT NULL") : NULL;
        if (open && seed)
            create = sqlite3_mprintf("CREATE TABLE runs_v5 %.*sseed INTEGER NOT NULL%s",
                                     (int)(seed - open), open, seed + strlen("seed"));
        else if (open)
            create = sqlite3_mprintf("CREATE TABLE runs_v5 %s", open);
        rc = create ? SQLITE_OK : SQLITE_NOMEM;
    }
    sqlite3_finalize(st);
    if (rf_sql_status(db, path, rc, doing, err))
        return -1;
    int status = exec_sql(db, path, create, doing, err);
    sqlite3_free(create);
    return status ||
                   exec_sql(db, path,
                            "INSERT INTO runs_v5 SELECT * FROM runs;\n"
                            "UPDATE sqlite_sequence SET seq = (SELECT seq FROM sqlite_sequence"
                            " WHERE name = 'runs') WHERE name = 'runs_v5';\n"
                            "DROP TABLE runs;\n"
                            "ALTER TABLE runs_v5 RENAME TO runs;\n"
                            "ALTER TABLE runs ADD COLUMN crs TEXT;\n"
                            "ALTER TABLE runs ADD COLUMN srs_id INTEGER;\n"
                            "UPDATE runs SET srs_id = -1;\n",
                            doing, err)
               ? -1
               : 0;
}

/* Every table and view of the tool's own, declared in gpkg_extensions (those of later
 * versions too: called at every opening for writing). */
static const char declare_sql[] =
    "INSERT INTO gpkg_extensions (table_name, column_name, extension_name, definition, scope)\n"
    "SELECT name, NULL, '" EXTENSION_NAME "', '" EXTENSION_DEFINITION "', 'write-only'\n"
    "FROM sqlite_master m WHERE type IN ('table', 'view') AND name NOT LIKE 'gpkg%'\n"
    "  AND name NOT LIKE 'sqlite%' AND name NOT LIKE 'rtree%'\n"
    "  AND name NOT IN (SELECT table_name FROM gpkg_contents)\n"
    "  AND NOT EXISTS (SELECT 1 FROM gpkg_extensions e WHERE e.table_name = m.name\n"
    "                  AND e.extension_name = '" EXTENSION_NAME "');\n";

int rf_gpkg_declare(sqlite3 *db, const char *path, rf_error *err)
{
    return exec_sql(db, path, declare_sql, "declaring the tool's tables", err);
}

int rf_gpkg_create(sqlite3 *db, const char *path, int upgrade, rf_error *err)
{
    if (upgrade) {
        /* a rename checks every view: they are made again by the caller */
        static const char drop_views[] =
            "SELECT 'DROP VIEW \"' || replace(name, '\"', '\"\"') || '\";'"
            " FROM sqlite_master WHERE type = 'view'";
        sqlite3_stmt *st = NULL;
        int rc = sqlite3_prepare_v2(db, drop_views, -1, &st, NULL);
        while (rc == SQLITE_OK && (rc = sqlite3_step(st)) == SQLITE_ROW)
            rc = sqlite3_exec(db, (const char *)sqlite3_column_text(st, 0), NULL, NULL, NULL);
        sqlite3_finalize(st);
        if (rf_sql_status(db, path, rc == SQLITE_DONE ? SQLITE_OK : rc,
                          "upgrading the results database to a GeoPackage", err) ||
            rebuild_runs(db, path, err))
            return -1;
    }
    char version[64];
    snprintf(version, sizeof version, "UPDATE rockfall_schema SET version = %d;\n",
             RF_GPKG_SCHEMA_VERSION);
    if (exec_sql(db, path, required_sql, "creating the GeoPackage tables", err) ||
        create_layers(db, path, err))
        return -1;
    /* a new file has the version of its whole schema already (schema.c) */
    if (!upgrade)
        return 0;
    if (exec_sql(db, path, version, "upgrading the results database to a GeoPackage", err))
        return -1;
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db, "SELECT id FROM runs ORDER BY id", -1, &st, NULL);
    int status = 0;
    while (status == 0 && rc == SQLITE_OK && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        int64_t run = sqlite3_column_int64(st, 0);
        status = rf_gpkg_fill_run(db, path, run, NULL, 1, err) ||
                         rf_gpkg_fill_run(db, path, run, NULL, 0, err)
                     ? -1
                     : 0;
    }
    sqlite3_finalize(st);
    if (status)
        return -1;
    return rf_sql_status(db, path, rc == SQLITE_DONE ? SQLITE_OK : rc,
                         "upgrading the results database to a GeoPackage", err);
}

/* ---- the CRS of a run ------------------------------------------------------------------ */

/* One integer from a query with one parameter of text (NULL: none); *found 0 when it
 * returns no row. */
static int query_int(sqlite3 *db, const char *path, const char *sql, const char *text,
                     int64_t *out, int *found, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
    if (rc == SQLITE_OK && text)
        sqlite3_bind_text(st, 1, text, -1, SQLITE_STATIC);
    *found = 0;
    if (rc == SQLITE_OK && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        *found = sqlite3_column_type(st, 0) != SQLITE_NULL;
        *out = sqlite3_column_int64(st, 0);
    }
    sqlite3_finalize(st);
    return rf_sql_status(db, path, rc, "reading the GeoPackage's CRS", err);
}

/* The srs_id of the CRS in gpkg_spatial_ref_sys, its row added when missing: an EPSG
 * code is its own srs_id (as GDAL numbers them); another CRS takes the row of the same
 * definition, or a new number from 100000. */
static int srs_row(sqlite3 *db, const char *path, const rf_crs *crs, int64_t *srs,
                   rf_error *err)
{
    int found = 0, epsg = crs->auth && !strcmp(crs->auth, "EPSG") && crs->code > 0;
    char by_code[96];
    snprintf(by_code, sizeof by_code,
             "SELECT srs_id FROM gpkg_spatial_ref_sys WHERE srs_id = %ld", crs->code);
    if (epsg ? query_int(db, path, by_code, NULL, srs, &found, err)
             : query_int(db, path,
                         "SELECT min(srs_id) FROM gpkg_spatial_ref_sys WHERE definition = ?1",
                         crs->wkt, srs, &found, err))
        return -1;
    if (found)
        return 0;
    if (epsg) {
        *srs = crs->code;
    } else if (query_int(db, path, "SELECT max(100000, max(srs_id) + 1) FROM gpkg_spatial_ref_sys",
                         NULL, srs, &found, err)) {
        return -1;
    }
    char *sql = sqlite3_mprintf(
        "INSERT INTO gpkg_spatial_ref_sys VALUES (%Q, %lld, %Q, %lld, %Q, %Q)", crs->name,
        (long long)*srs, crs->auth ? crs->auth : "NONE",
        (long long)(crs->auth && crs->code > 0 ? crs->code : *srs), crs->wkt, crs->source);
    if (!sql)
        return rf_error_set(err, path, 0, 0, "out of memory writing the CRS");
    int status = exec_sql(db, path, sql, "writing the project's CRS", err);
    sqlite3_free(sql);
    return status;
}

/* The name of an srs_id's row, for a message (sqlite3_malloc'd). */
static char *srs_name(sqlite3 *db, int64_t srs)
{
    sqlite3_stmt *st = NULL;
    char *name = NULL;
    if (sqlite3_prepare_v2(db, "SELECT srs_name FROM gpkg_spatial_ref_sys WHERE srs_id = ?1",
                           -1, &st, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(st, 1, srs);
        if (sqlite3_step(st) == SQLITE_ROW)
            name = sqlite3_mprintf("%s", sqlite3_column_text(st, 0));
    }
    sqlite3_finalize(st);
    return name ? name : sqlite3_mprintf("srs_id %lld", (long long)srs);
}

int rf_gpkg_srs_for_run(sqlite3 *db, const char *path, const rf_crs *crs, int64_t *srs_id,
                        rf_error *err)
{
    *srs_id = RF_GPKG_SRS_UNDEFINED;
    if (crs && crs->wkt && srs_row(db, path, crs, srs_id, err))
        return -1;
    int64_t have = 0, features = 0;
    int found = 0;
    if (query_int(db, path,
                  "SELECT srs_id FROM gpkg_geometry_columns WHERE table_name = 'stop_points'",
                  NULL, &have, &found, err))
        return -1;
    if (found && have == *srs_id)
        return 0;
    char *count = sqlite3_mprintf("SELECT 0");
    for (int i = 0; count && i < N_LAYERS; i++) {
        char *more = sqlite3_mprintf("%s + (SELECT count(*) FROM \"%w\")", count, layers[i].name);
        sqlite3_free(count);
        count = more;
    }
    if (!count)
        return rf_error_set(err, path, 0, 0, "out of memory reading the layers");
    int status = query_int(db, path, count, NULL, &features, &found, err);
    sqlite3_free(count);
    if (status)
        return -1;
    if (features > 0) {
        char *mine = srs_name(db, have), *theirs = srs_name(db, *srs_id);
        rf_error_set(err, path, 0, 0,
                     "the file's layers are in the CRS '%s' and the project's is '%s': a "
                     "GeoPackage layer has one CRS, so this run goes into another file (-o)",
                     mine ? mine : "?", theirs ? theirs : "?");
        sqlite3_free(mine);
        sqlite3_free(theirs);
        return -1;
    }
    char *sql = sqlite3_mprintf("UPDATE gpkg_geometry_columns SET srs_id = %lld;\n"
                                "UPDATE gpkg_contents SET srs_id = %lld"
                                " WHERE data_type = 'features';\n",
                                (long long)*srs_id, (long long)*srs_id);
    status = sql ? exec_sql(db, path, sql, "setting the layers' CRS", err)
                 : rf_error_set(err, path, 0, 0, "out of memory setting the layers' CRS");
    sqlite3_free(sql);
    return status;
}

/* ---- a run's features ------------------------------------------------------------------ */

/* The layers' rows of a run from its rows; ?1 the run, ?2 the layers' srs_id. */
static const char *const start_sql[] = {
    "INSERT INTO release_points (geom, run_id, release_id, name, rock, mass_kg, action_level,"
    " count, z) SELECT rf_gpkg_point(?2, x, y), run_id, id, name, rock, mass_kg,"
    " action_level, count, z FROM releases WHERE run_id = ?1 AND x IS NOT NULL"
    " AND y IS NOT NULL ORDER BY idx",
    "INSERT INTO measure_lines (geom, run_id, measure_id, idx, name, kind, importance,"
    " height_m, behaviour, mel_kj, sel_kj) SELECT rf_gpkg_line(?2, line), run_id, id, idx,"
    " name, kind, importance, height_m, behaviour, mel_kj, sel_kj FROM measures"
    " WHERE run_id = ?1 ORDER BY idx",
};
static const char *const end_sql[] = {
    "INSERT INTO stop_points (geom, run_id, trajectory_id, release, idx, stop_reason, z,"
    " mass_kg, max_energy_kj, path_length_m, duration_s, n_impacts)"
    " SELECT rf_gpkg_point(?2, t.stop_x, t.stop_y), t.run_id, t.id, r.name, t.idx,"
    " t.stop_reason, t.stop_z, coalesce(t.mass_kg, r.mass_kg), t.max_energy_kj,"
    " t.path_length_m, t.duration_s, t.n_impacts"
    " FROM trajectories t JOIN releases r ON r.id = t.release_id"
    " WHERE t.run_id = ?1 AND t.stop_x IS NOT NULL AND t.stop_y IS NOT NULL ORDER BY t.id",
    "INSERT INTO interception_points (geom, run_id, interception_id, trajectory_id,"
    " measure_id, measure, kind, release, z, energy_kj, speed_ms, passing_height_m, outcome)"
    " SELECT rf_gpkg_point(?2, i.x, i.y), i.run_id, i.id, i.trajectory_id, m.id, m.name,"
    " m.kind, r.name, i.z, i.energy_kj, i.speed_ms, i.passing_height_m, i.outcome"
    " FROM interceptions i JOIN measures m ON m.id = i.measure_id"
    " JOIN trajectories t ON t.id = i.trajectory_id JOIN releases r ON r.id = t.release_id"
    " WHERE i.run_id = ?1 AND i.x IS NOT NULL AND i.y IS NOT NULL ORDER BY i.id",
    "INSERT INTO hazard_map (geom, run_id, ix, iy, passes, reach_probability, energy_max_kj,"
    " energy_p95_kj, height_p95_m)"
    " SELECT rf_gpkg_box(?2, h.x - u.hazard_cell_m / 2, h.y - u.hazard_cell_m / 2,"
    " h.x + u.hazard_cell_m / 2, h.y + u.hazard_cell_m / 2), h.run_id, h.ix, h.iy,"
    " h.passes, h.reach_probability, h.energy_max_kj, h.energy_p95_kj, h.height_p95_m"
    " FROM hazard_cells h JOIN runs u ON u.id = h.run_id"
    " WHERE h.run_id = ?1 AND u.hazard_cell_m > 0 AND h.x IS NOT NULL AND h.y IS NOT NULL"
    " ORDER BY h.iy, h.ix",
};

static int run_statement(sqlite3 *db, const char *path, const char *sql, int64_t run,
                         int64_t srs, const void *blob, int nblob, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
    if (rc == SQLITE_OK) {
        sqlite3_bind_int64(st, 1, run);
        if (sqlite3_bind_parameter_count(st) >= 2)
            sqlite3_bind_int64(st, 2, srs);
        if (sqlite3_bind_parameter_count(st) >= 3)
            sqlite3_bind_blob(st, 3, blob, nblob, SQLITE_STATIC);
        rc = sqlite3_step(st);
    }
    sqlite3_finalize(st);
    return rf_sql_status(db, path, rc, "writing the GeoPackage layers", err);
}

/* The release areas' polygons, from the project (the releases table keeps their
 * centroids only). */
static int fill_areas(sqlite3 *db, const char *path, int64_t run, int64_t srs,
                      const rf_project *p, rf_error *err)
{
    static const char sql[] =
        "INSERT INTO release_areas (geom, run_id, release_id, name, rock, count)"
        " SELECT ?3, run_id, id, name, rock, count FROM releases"
        " WHERE run_id = ?1 AND idx = ?4 AND ?2 = ?2";
    gbuf g = {0};
    int status = 0;
    for (size_t i = 0; status == 0 && p && i < p->nreleases; i++) {
        const rf_release *r = &p->releases[i];
        if (r->source != RF_SOURCE_AREA || r->narea < 3)
            continue;
        begin_geometry(&g, (int32_t)srs, WKB_POLYGON);
        put_u32(&g, 1);
        put_ring(&g, r->area, r->narea);
        if (end_geometry(&g)) {
            status = rf_error_set(err, path, 0, 0, "out of memory writing a release area");
            break;
        }
        sqlite3_stmt *st = NULL;
        int rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
        if (rc == SQLITE_OK) {
            sqlite3_bind_int64(st, 1, run);
            sqlite3_bind_int64(st, 2, srs);
            sqlite3_bind_blob(st, 3, g.b, (int)g.n, SQLITE_STATIC);
            sqlite3_bind_int64(st, 4, (int64_t)i);
            rc = sqlite3_step(st);
        }
        sqlite3_finalize(st);
        status = rf_sql_status(db, path, rc, "writing a release area", err);
    }
    free(g.b);
    return status;
}

/* One path's row: its points so far in g (LineString Z), its attributes from the
 * trajectory. */
static int insert_path(sqlite3 *db, const char *path, sqlite3_stmt *ins, int64_t trajectory,
                       gbuf *g, size_t npoints, rf_error *err)
{
    if (npoints < 2)
        return 0; /* a line needs two points */
    /* the point count sits after the header, the envelope, the byte order and the type */
    size_t at = GP_HEADER + GP_ENVELOPE + 5;
    for (int k = 0; k < 4; k++)
        g->b[at + (size_t)k] = (unsigned char)(npoints >> (8 * k));
    if (end_geometry(g))
        return rf_error_set(err, path, 0, 0, "out of memory writing a path");
    sqlite3_bind_blob(ins, 1, g->b, (int)g->n, SQLITE_STATIC);
    sqlite3_bind_int64(ins, 2, trajectory);
    int rc = sqlite3_step(ins);
    sqlite3_reset(ins);
    return rf_sql_status(db, path, rc, "writing a path", err);
}

/* The sampled paths as LineString Z, their points in seq order. */
static int fill_paths(sqlite3 *db, const char *path, int64_t run, int64_t srs, rf_error *err)
{
    sqlite3_stmt *pts = NULL, *ins = NULL;
    int rc = sqlite3_prepare_v2(db,
                                "SELECT p.trajectory_id, p.x, p.y, p.z FROM path_points p"
                                " JOIN trajectories t ON t.id = p.trajectory_id"
                                " WHERE t.run_id = ?1 AND p.x IS NOT NULL AND p.y IS NOT NULL"
                                " AND p.z IS NOT NULL ORDER BY p.trajectory_id, p.seq",
                                -1, &pts, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(db,
                                "INSERT INTO paths (geom, run_id, trajectory_id, release, idx,"
                                " stop_reason, max_energy_kj, path_length_m)"
                                " SELECT ?1, t.run_id, t.id, r.name, t.idx, t.stop_reason,"
                                " t.max_energy_kj, t.path_length_m FROM trajectories t"
                                " JOIN releases r ON r.id = t.release_id WHERE t.id = ?2",
                                -1, &ins, NULL);
    if (rc == SQLITE_OK)
        sqlite3_bind_int64(pts, 1, run);
    gbuf g = {0};
    int64_t current = 0;
    size_t n = 0;
    int status = rf_sql_status(db, path, rc, "writing the paths", err);
    while (status == 0 && (rc = sqlite3_step(pts)) == SQLITE_ROW) {
        int64_t id = sqlite3_column_int64(pts, 0);
        if (id != current) {
            status = n ? insert_path(db, path, ins, current, &g, n, err) : 0;
            begin_geometry(&g, (int32_t)srs, WKB_LINESTRING + WKB_Z);
            put_u32(&g, 0); /* the count, set when the line is done */
            current = id;
            n = 0;
        }
        put_xy(&g, sqlite3_column_double(pts, 1), sqlite3_column_double(pts, 2));
        put_f64(&g, sqlite3_column_double(pts, 3));
        n++;
    }
    if (status == 0 && rc != SQLITE_DONE)
        status = rf_sql_status(db, path, rc, "reading the path points", err);
    if (status == 0 && n)
        status = insert_path(db, path, ins, current, &g, n, err);
    free(g.b);
    sqlite3_finalize(pts);
    sqlite3_finalize(ins);
    return status;
}

/* The layer's extent in gpkg_contents, from its geometries' envelopes. */
static int update_extent(sqlite3 *db, const char *path, const char *table, rf_error *err)
{
    char *sql = sqlite3_mprintf(
        "UPDATE gpkg_contents SET min_x = (SELECT min(rf_gpkg_env(geom, 0)) FROM \"%w\"),"
        " max_x = (SELECT max(rf_gpkg_env(geom, 1)) FROM \"%w\"),"
        " min_y = (SELECT min(rf_gpkg_env(geom, 2)) FROM \"%w\"),"
        " max_y = (SELECT max(rf_gpkg_env(geom, 3)) FROM \"%w\"),"
        " last_change = strftime('%%Y-%%m-%%dT%%H:%%M:%%fZ', 'now') WHERE table_name = %Q",
        table, table, table, table, table);
    int status = sql ? exec_sql(db, path, sql, "writing the layers' extents", err)
                     : rf_error_set(err, path, 0, 0, "out of memory");
    sqlite3_free(sql);
    return status;
}

int rf_gpkg_fill_run(sqlite3 *db, const char *path, int64_t run, const rf_project *p,
                     int at_start, rf_error *err)
{
    int64_t srs = RF_GPKG_SRS_UNDEFINED;
    int found = 0;
    if (query_int(db, path,
                  "SELECT srs_id FROM gpkg_geometry_columns WHERE table_name = 'stop_points'",
                  NULL, &srs, &found, err))
        return -1;
    const char *const *sql = at_start ? start_sql : end_sql;
    size_t nsql = at_start ? sizeof start_sql / sizeof *start_sql
                           : sizeof end_sql / sizeof *end_sql;
    for (size_t i = 0; i < nsql; i++)
        if (run_statement(db, path, sql[i], run, srs, NULL, 0, err))
            return -1;
    if (at_start ? fill_areas(db, path, run, srs, p, err) : fill_paths(db, path, run, srs, err))
        return -1;
    static const char *const start_tables[] = {"release_points", "release_areas",
                                               "measure_lines"};
    static const char *const end_tables[] = {"stop_points", "paths", "interception_points",
                                             "hazard_map"};
    const char *const *tables = at_start ? start_tables : end_tables;
    size_t ntables = at_start ? 3 : 4;
    for (size_t i = 0; i < ntables; i++)
        if (update_extent(db, path, tables[i], err))
            return -1;
    return 0;
}
