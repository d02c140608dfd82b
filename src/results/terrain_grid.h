/* terrain_grid.h - the terrain as the report draws it, sampled at run time and stored
 * with the run (terrain_grids), so that the report reads the run's terrain and never
 * the terrain files, which may have changed or gone since. */
#ifndef ROCKFALL_TERRAIN_GRID_H
#define ROCKFALL_TERRAIN_GRID_H

#include <stddef.h>

#include "rockfall/terrain.h"

/* Nodes of the grid along the longer side of the plan. */
#define RF_TERRAIN_GRID_NODES 240

typedef struct rf_terrain_grid {
    double xmin, xmax, ymin, ymax; /* the terrain's extent */
    double x0, y0, x1, y1;         /* the plan: that extent fitted (rf_plan_extent_fit) */
    double step;                   /* node spacing (m) */
    size_t nx, ny;                 /* nodes at x0 + i step (capped at x1), likewise y */
    double *z;                     /* nx * ny heights row by row from (x0, y0); NaN off
                                    * the terrain */
} rf_terrain_grid;

/* Widens an extent that is very flat (y span under a quarter of x's) or very tall (x
 * under 0.4 of y's) about its centre, so that a plan drawn with 1 m the same in x and
 * y stays readable. */
void rf_plan_extent_fit(double *x0, double *x1, double *y0, double *y1);

/* Samples the terrain's heights over its fitted extent, RF_TERRAIN_GRID_NODES along
 * the longer side.  Returns 0, or -1 when memory runs out (g then holds nothing). */
int rf_terrain_grid_sample(const rf_terrain *t, rf_terrain_grid *g);
void rf_terrain_grid_free(rf_terrain_grid *g);

/* The heights as the BLOB stored in terrain_grids.z (nx * ny IEEE doubles, little
 * endian) and back; the decoder returns -1 when the size does not match or memory
 * runs out. */
void rf_terrain_grid_encode(const rf_terrain_grid *g, unsigned char *out);
int rf_terrain_grid_decode(rf_terrain_grid *g, const void *blob, size_t len);

#endif
