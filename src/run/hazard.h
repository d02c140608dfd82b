/* hazard.h - the hazard map: per cell of a square grid over the terrain, how many
 * trajectories passed, and the distribution of their energy and passing height.
 *
 * Each trajectory contributes once per cell it crosses: its largest kinetic energy
 * and largest passing height in that cell.  A point on the grid's far edge belongs to
 * the last cell.  Percentiles are nearest-rank over those
 * per-trajectory values, so they do not depend on the order of work. */
#ifndef ROCKFALL_HAZARD_H
#define ROCKFALL_HAZARD_H

#include <stddef.h>
#include <stdint.h>

#include "rockfall/error.h"
#include "rockfall/terrain.h"

struct rf_store;

typedef struct rf_hazard_cell {
    float *energy_kj, *height_m; /* one value per trajectory that crossed the cell */
    uint32_t n, cap;
} rf_hazard_cell;

typedef struct rf_hazard_touch {
    uint32_t cell;
    float energy_kj, height_m;
} rf_hazard_touch;

typedef struct rf_hazard {
    double x0, y0, cell;
    size_t nx, ny;
    rf_hazard_cell *cells;
    /* the trajectory under way: the cells it touched so far */
    uint32_t *slot_epoch, *slot;
    uint32_t epoch;
    rf_hazard_touch *touched;
    size_t ntouched, cap_touched;
    double last[4];         /* the last sample: x, y, energy, height; x NaN before one */
    double last_fx, last_fy; /* its cell (cell_index) */
    int oom;
} rf_hazard;

int rf_hazard_init(rf_hazard *h, const rf_terrain *t, double cell);
void rf_hazard_free(rf_hazard *h);
void rf_hazard_begin(rf_hazard *h);
/* A sample of the trajectory under way.  Between two samples the path is taken as the
 * straight line, the values as linear along it: every cell the line crosses is
 * reached, even one it only clips between them. */
void rf_hazard_sample(rf_hazard *h, double x, double y, double energy_kj, double height_m);
/* Adds the trajectory's values to the cells; returns -1 when memory ran out. */
int rf_hazard_end(rf_hazard *h);
/* Moves the values of `from` into `into` (same grid). */
int rf_hazard_merge(rf_hazard *into, const rf_hazard *from);
/* Writes one hazard_cells row per cell crossed at least once. */
int rf_hazard_write(rf_hazard *h, long n_trajectories, struct rf_store *s, rf_error *err);

#endif
