/* report.h - `rockfall report`: DIR/index.html with a text summary and SVG figures of
 * one run (plan view of the trajectories over the terrain contours, arrival position
 * and velocity at the road, the hazard map, the energy at each measure against its
 * capacities) and the empirical crosscheck of Eq. 1-2 and Fig. 1b. */
#ifndef ROCKFALL_REPORT_H
#define ROCKFALL_REPORT_H

#include <stddef.h>
#include <stdint.h>

#include <sqlite3.h>

#include "base/polyline.h" /* rf_polyline_station, rf_polyline_length */
#include "rockfall/error.h"

/* Class limits of the hazard map (kJ), as in the paper's Fig. 12 (3 000 and 6 000 kJ)
 * with a lower class below 1 000 kJ. */
#define RF_REPORT_N_ENERGY_LIMITS 3
extern const double rf_report_energy_limits[RF_REPORT_N_ENERGY_LIMITS];

/* Writes DIR/index.html and its figures (DIR is created when missing) for run `run`
 * of the database.  The run must exist.  The run's project file (runs.project_path)
 * is reloaded for the terrain contours; when it cannot be, the figures are drawn
 * without contours and the report says so.  Returns 0, or fills err. */
int rf_report_write(sqlite3 *db, int64_t run, const char *dir, rf_error *err);

/* Writes DIR/index.html comparing the runs (layout variants) side by side - each run's
 * verdict from its stored checks, the crossings and energy percentiles of each
 * structure, the arrivals at each control line, the hazard cells - and one plan view
 * per run (DIR/plan-run-ID.svg).  Every run must exist.  Returns 0, or fills err. */
int rf_report_compare(sqlite3 *db, const int64_t *runs, size_t nruns, const char *dir,
                      rf_error *err);
/* `rockfall export` (report/export.c): the run's hazard maps as ESRI ASCII grids with
 * their .prj and a README.txt in DIR (created when missing).  Returns 0, or fills err. */
int rf_export_write(sqlite3 *db, int64_t run, const char *dir, rf_error *err);

#endif
