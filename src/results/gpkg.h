/* gpkg.h - the results database as an extended OGC GeoPackage 1.3 (OGC 12-128r18;
 * docs/database.md "GeoPackage").
 *
 * The file carries GeoPackage's application id and version, its required tables
 * (gpkg_spatial_ref_sys with its three required rows, gpkg_contents,
 * gpkg_geometry_columns) and gpkg_extensions declaring the tool's own tables and views.
 * The feature layers (release_points, release_areas, stop_points, paths, measure_lines,
 * interception_points, hazard_map) are plain tables derived from a run's rows: the
 * release and measure layers when the run starts, the others when it ends. */
#ifndef ROCKFALL_GPKG_H
#define ROCKFALL_GPKG_H

#include <stdint.h>

#include <sqlite3.h>

#include "rockfall/error.h"
#include "rockfall/project.h"

/* PRAGMA application_id: 'GPKG' (OGC 12-128r18, Requirement 2). */
#define RF_GPKG_APPLICATION_ID 0x47504B47
/* PRAGMA user_version: GeoPackage 1.3.0 (Requirement 2). */
#define RF_GPKG_USER_VERSION 10300
/* The rockfall schema version that made the file a GeoPackage. */
#define RF_GPKG_SCHEMA_VERSION 5
/* GeoPackage's undefined Cartesian CRS (Requirement 11): a project without `crs`. */
#define RF_GPKG_SRS_UNDEFINED (-1)

/* The SQL functions the layers are built with (rf_gpkg_point, rf_gpkg_box,
 * rf_gpkg_line, rf_gpkg_env), on this connection. */
int rf_gpkg_register(sqlite3 *db);

/* Within the caller's transaction: makes the file a GeoPackage (pragmas, required
 * tables and rows, the layers, the extension rows).  `upgrade`: the file held the
 * tables of schema version 4 and their runs, whose layers are filled here (their CRS
 * the undefined Cartesian one); the runs table is rebuilt with its new columns. */
int rf_gpkg_create(sqlite3 *db, const char *path, int upgrade, rf_error *err);

/* Declares in gpkg_extensions every table and view of the tool's own that is not
 * declared yet (the tables of later versions too); within the caller's transaction. */
int rf_gpkg_declare(sqlite3 *db, const char *path, rf_error *err);

/* The srs_id of a CRS, its gpkg_spatial_ref_sys row added when missing; checks that the
 * layers can take it: every layer of a file has one CRS, so a file whose layers hold
 * features in another CRS refuses the run (nothing written).  Within the caller's
 * transaction. */
int rf_gpkg_srs_for_run(sqlite3 *db, const char *path, const rf_crs *crs, int64_t *srs_id,
                        rf_error *err);

/* The layers of run `run` from its rows: `at_start` the releases' points and areas (the
 * areas from the project p, which may be NULL: none) and the measures' lines, else the
 * stop points, paths, interception points and hazard map.  Within the caller's
 * transaction; the layers' extents in gpkg_contents follow. */
int rf_gpkg_fill_run(sqlite3 *db, const char *path, int64_t run, const rf_project *p,
                     int at_start, rf_error *err);

#endif
