/* fuzz_layout.c - layouts drawn in QGIS (src/input/layout.c): the input becomes one
 * feature of a GeoPackage layer that a project names, its first byte choosing the list
 * the layer fills (measures, releases, zones, vegetation) and the type of its
 * attribute, the next bytes the attribute's value and the rest the geometry blob (the
 * GeoPackage header and WKB the reader parses); then the project is loaded. */
#include <sqlite3.h>

#include "rockfall/project.h"
#include "fuzz_util.h"

static const char *const lists[4] = {
    "measures:\n  - {gpkg: layout.gpkg, layer: f}\n",
    "releases:\n  - {gpkg: layout.gpkg, layer: f}\n",
    "terrain:\n  dem: grid5.asc\n  zones:\n    - {gpkg: layout.gpkg, layer: f}\n",
    "vegetation:\n  - {gpkg: layout.gpkg, layer: f}\n",
};
/* the attribute each list's items need most, given a value from the input */
static const char *const keys[4] = {"mel", "count", "restitution", "density"};

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    fuzz_copy_data("grid5.asc", "grid5.asc");
    return 0;
}

/* The GeoPackage of one layer `f` with one feature: geometry blob g, a name, and the
 * attribute `key` = value (as text when `text`, else as a real). */
static int write_layer(const char *path, const char *key, const uint8_t *v, size_t nv,
                       int text, const uint8_t *g, size_t ng)
{
    static const char schema[] =
        "PRAGMA application_id = 1196444487; PRAGMA user_version = 10300;"
        "CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL, srs_id INTEGER PRIMARY KEY,"
        " organization TEXT NOT NULL, organization_coordsys_id INTEGER NOT NULL,"
        " definition TEXT NOT NULL, description TEXT);"
        "INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined cartesian SRS', -1, 'NONE', -1,"
        " 'undefined', NULL);"
        "CREATE TABLE gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL,"
        " identifier TEXT, description TEXT DEFAULT '', last_change DATETIME, min_x DOUBLE,"
        " min_y DOUBLE, max_x DOUBLE, max_y DOUBLE, srs_id INTEGER);"
        "INSERT INTO gpkg_contents (table_name, data_type, srs_id) VALUES ('f', 'features', -1);"
        "CREATE TABLE gpkg_geometry_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL,"
        " geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL, z TINYINT NOT NULL,"
        " m TINYINT NOT NULL);"
        "INSERT INTO gpkg_geometry_columns VALUES ('f', 'geom', 'GEOMETRY', -1, 0, 0);";
    unlink(path);
    sqlite3 *db = NULL;
    sqlite3_stmt *st = NULL;
    char sql[256];
    snprintf(sql, sizeof sql,
             "CREATE TABLE f (fid INTEGER PRIMARY KEY, geom BLOB, name TEXT, %s %s)", key,
             text ? "TEXT" : "REAL");
    int rc = sqlite3_open(path, &db);
    if (rc == SQLITE_OK)
        rc = sqlite3_exec(db, schema, NULL, NULL, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_exec(db, sql, NULL, NULL, NULL);
    snprintf(sql, sizeof sql, "INSERT INTO f (geom, name, %s) VALUES (?1, 'a', ?2)", key);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
    if (rc == SQLITE_OK) {
        sqlite3_bind_blob(st, 1, g, (int)ng, SQLITE_STATIC);
        if (text)
            sqlite3_bind_text(st, 2, (const char *)v, (int)nv, SQLITE_STATIC);
        else {
            double d = 0.0;
            memcpy(&d, v, nv < sizeof d ? nv : sizeof d);
            sqlite3_bind_double(st, 2, d);
        }
        rc = sqlite3_step(st) == SQLITE_DONE ? SQLITE_OK : SQLITE_ERROR;
    }
    sqlite3_finalize(st);
    sqlite3_close(db);
    return rc == SQLITE_OK ? 0 : -1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    int list = data[0] & 3, text = (data[0] >> 2) & 1;
    size_t nv = data[1] % 16;
    if (size < 2 + nv)
        return 0;
    char gpkg[400], path[400], yaml[512];
    snprintf(gpkg, sizeof gpkg, "%s/layout.gpkg", fuzz_scratch());
    snprintf(path, sizeof path, "%s/project.yaml", fuzz_scratch());
    if (write_layer(gpkg, keys[list], data + 2, nv, text, data + 2 + nv, size - 2 - nv))
        return 0;
    int n = snprintf(yaml, sizeof yaml,
                     "name: f\n%s%s"
                     "rocks: [{name: r, mass: 500}]\n",
                     list == 2 ? "" : "terrain: {dem: grid5.asc}\n", lists[list]);
    if (list != 1)
        n += snprintf(yaml + n, sizeof yaml - (size_t)n,
                      "releases: [{name: p, point: [1, 1], rock: r}]\n");
    rf_project p;
    rf_error err;
    if (rf_project_load_from_memory(yaml, (size_t)n, path, &p, &err) == 0)
        rf_project_free(&p);
    return 0;
}
