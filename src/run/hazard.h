/* hazard.h - the hazard map: per cell of a square grid over the terrain, how many
 * trajectories passed, and the distribution of their energy and passing height.
 *
 * Each trajectory contributes once per cell it crosses: its largest kinetic energy
 * and largest passing height in that cell.  A point on the grid's far edge belongs to
 * the last cell.  A cell's values are kept in a bounded summary (base/qsum.h): exact up
 * to RF_QSUM_EXACT passes, then in fixed logarithmic bins; it depends only on the set
 * of values, so neither the order of work nor its split over threads changes a row.
 * Only the cells a trajectory reached are held (a hash of cell numbers), so the memory
 * grows with the cells reached, never with the number of trajectories. */
#ifndef ROCKFALL_HAZARD_H
#define ROCKFALL_HAZARD_H

#include <stddef.h>
#include <stdint.h>

#include "base/qsum.h"
#include "rockfall/error.h"
#include "rockfall/terrain.h"

struct rf_store;

/* The bins' scales: energy 2^-10 (about 1e-3) to 2^30 (about 1.07e9) kJ, height 2^-10
 * to 2^14 (16 384) m. */
extern const rf_qsum_scale RF_HAZARD_ENERGY_SCALE, RF_HAZARD_HEIGHT_SCALE;

typedef struct rf_hazard_cell {
    uint32_t cell;              /* iy * nx + ix */
    rf_qsum energy_kj, height_m; /* one value per trajectory that crossed the cell */
} rf_hazard_cell;

typedef struct rf_hazard_touch {
    uint32_t cell;
    float energy_kj, height_m;
} rf_hazard_touch;

/* cell number -> position, open addressing; an entry is there when its epoch is the
 * map's (so the map empties at once). */
typedef struct rf_hazard_map {
    uint32_t *key, *val, *epoch;
    uint32_t cur;
    size_t cap, n;
} rf_hazard_map;

typedef struct rf_hazard {
    double x0, y0, cell;
    size_t nx, ny;
    rf_hazard_cell *cells; /* the cells reached, in the order first reached */
    size_t ncells, cap_cells;
    rf_hazard_map where;   /* a cell's position in cells */
    /* the trajectory under way: the cells it touched so far */
    rf_hazard_map slot;    /* a cell's position in touched */
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
/* Adds the values of `from` to `into` (same grid); the result does not depend on the
 * order of merging. */
int rf_hazard_merge(rf_hazard *into, const rf_hazard *from);
/* The cells as bytes, for another process (the MPI ranks): packs cells *next, *next + 1,
 * ... into buf while they fit in cap bytes (a cell takes at most about 10 kB), advances
 * *next past them and returns the bytes written. */
size_t rf_hazard_pack(const rf_hazard *h, size_t *next, unsigned char *buf, size_t cap);
/* Adds packed cells to `into` (a map of the same grid) as rf_hazard_merge adds a map's;
 * -1 when the bytes are not packed cells of this grid or memory ran out. */
int rf_hazard_unpack_merge(rf_hazard *into, const unsigned char *buf, size_t len);
/* Cell (ix, iy), or NULL when no trajectory reached it. */
const rf_hazard_cell *rf_hazard_at(const rf_hazard *h, size_t ix, size_t iy);
/* Bytes of memory the map holds (its cells, their summaries, its indexes). */
size_t rf_hazard_bytes(const rf_hazard *h);
/* Writes one hazard_cells row per cell crossed at least once, in the order of iy, ix. */
int rf_hazard_write(rf_hazard *h, long n_trajectories, struct rf_store *s, rf_error *err);

#endif
