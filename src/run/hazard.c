/* hazard.c - accumulating the hazard map (see hazard.h). */
#include "run/hazard.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "results/store.h"
#include "base/stats.h"
#include "base/util.h"

int rf_hazard_init(rf_hazard *h, const rf_terrain *t, double cell)
{
    memset(h, 0, sizeof *h);
    h->cell = cell;
    h->x0 = t->xmin;
    h->y0 = t->ymin;
    double nx, ny;
    rf_hazard_grid(t, cell, &nx, &ny);
    h->nx = (size_t)nx;
    h->ny = (size_t)ny;
    size_t n = h->nx * h->ny;
    h->cells = calloc(n, sizeof *h->cells);
    h->slot_epoch = calloc(n, sizeof *h->slot_epoch);
    h->slot = calloc(n, sizeof *h->slot);
    if (!h->cells || !h->slot_epoch || !h->slot) {
        rf_hazard_free(h);
        return -1;
    }
    return 0;
}

void rf_hazard_free(rf_hazard *h)
{
    if (h->cells)
        for (size_t i = 0; i < h->nx * h->ny; i++) {
            free(h->cells[i].energy_kj);
            free(h->cells[i].height_m);
        }
    free(h->cells);
    free(h->slot_epoch);
    free(h->slot);
    free(h->touched);
    memset(h, 0, sizeof *h);
}

void rf_hazard_begin(rf_hazard *h)
{
    h->ntouched = 0;
    h->last[0] = NAN;
    if (++h->epoch == 0) { /* wrapped: forget every old mark */
        memset(h->slot_epoch, 0, h->nx * h->ny * sizeof *h->slot_epoch);
        h->epoch = 1;
    }
}

/* The cell index along one axis of a point at x (floor), a point on the grid's far
 * edge in the last cell: the quotient is the one rf_hazard_grid took the cell count
 * from, so it reaches n exactly there and nowhere on the terrain beyond. */
static double cell_index(double x, double x0, double cell, size_t n)
{
    double q = (x - x0) / cell, f = floor(q);
    if (q == (double)n)
        f -= 1.0;
    return f;
}

/* The trajectory reached cell (fx, fy) with these values (outside the grid: nothing). */
static void touch(rf_hazard *h, double fx, double fy, double energy_kj, double height_m)
{
    if (!(fx >= 0 && fy >= 0 && fx < (double)h->nx && fy < (double)h->ny))
        return;
    uint32_t c = (uint32_t)((size_t)fy * h->nx + (size_t)fx);
    if (h->slot_epoch[c] == h->epoch) {
        rf_hazard_touch *tc = &h->touched[h->slot[c]];
        if (energy_kj > tc->energy_kj)
            tc->energy_kj = (float)energy_kj;
        if (height_m > tc->height_m)
            tc->height_m = (float)height_m;
        return;
    }
    if (rf_grow((void **)&h->touched, &h->cap_touched, h->ntouched + 1, sizeof *h->touched)) {
        h->oom = 1;
        return;
    }
    h->slot_epoch[c] = h->epoch;
    h->slot[c] = (uint32_t)h->ntouched;
    h->touched[h->ntouched++] = (rf_hazard_touch){c, (float)energy_kj, (float)height_m};
}

/* The most cells between two samples walked.  A run's samples are at most a quarter
 * cell apart; two farther apart than this (never in a run) reach only the new
 * sample's cell. */
#define HAZARD_WALK_MAX 64

/* From the last sample a to the new one b, along the straight line between them: every
 * cell the line crosses, in order, with the largest of the values interpolated linearly
 * over its stretch of the line (so at one of the stretch's ends).  Through a grid
 * corner exactly the line goes on diagonally: the two cells it only touches at the
 * corner are not reached. */
static void walk(rf_hazard *h, const double a[4], double fx, double fy, const double b[4],
                 double gx, double gy)
{
    double steps = fabs(gx - fx) + fabs(gy - fy);
    if (!(steps <= HAZARD_WALK_MAX)) {
        touch(h, gx, gy, b[2], b[3]);
        return;
    }
    double dx = b[0] - a[0], dy = b[1] - a[1];
    double sx = gx > fx ? 1.0 : gx < fx ? -1.0 : 0.0, sy = gy > fy ? 1.0 : gy < fy ? -1.0 : 0.0;
    double s0 = 0.0;
    /* each step moves towards b's cell in x, in y or in both, never past it: the walk
     * ends there after at most `steps` steps */
    for (double k = 0;; k++) {
        int end = (fx == gx && fy == gy) || k >= steps;
        /* the line's parameter where it leaves the cell in x and in y */
        double ux = fx != gx ? (h->x0 + (sx > 0 ? fx + 1 : fx) * h->cell - a[0]) / dx : INFINITY;
        double uy = fy != gy ? (h->y0 + (sy > 0 ? fy + 1 : fy) * h->cell - a[1]) / dy : INFINITY;
        double s1 = end ? 1.0 : fmin(fmax(fmin(ux, uy), s0), 1.0);
        touch(h, fx, fy, fmax(a[2] + (b[2] - a[2]) * s0, a[2] + (b[2] - a[2]) * s1),
              fmax(a[3] + (b[3] - a[3]) * s0, a[3] + (b[3] - a[3]) * s1));
        if (end)
            break;
        if (ux <= uy)
            fx += sx;
        if (uy <= ux)
            fy += sy;
        s0 = s1;
    }
}

void rf_hazard_sample(rf_hazard *h, double x, double y, double energy_kj, double height_m)
{
    if (!isfinite(x) || !isfinite(y))
        return; /* no cell, and no line to the next sample */
    double b[4] = {x, y, energy_kj, height_m};
    double gx = cell_index(x, h->x0, h->cell, h->nx), gy = cell_index(y, h->y0, h->cell, h->ny);
    if (isnan(h->last[0]))
        touch(h, gx, gy, energy_kj, height_m);
    else
        walk(h, h->last, h->last_fx, h->last_fy, b, gx, gy);
    memcpy(h->last, b, sizeof b);
    h->last_fx = gx, h->last_fy = gy;
}

static int cell_push(rf_hazard_cell *c, float e, float hgt)
{
    if (c->n == c->cap) {
        uint32_t nc = c->cap ? 2 * c->cap : 16;
        float *ne = realloc(c->energy_kj, nc * sizeof *ne);
        if (!ne)
            return -1;
        c->energy_kj = ne;
        float *nh = realloc(c->height_m, nc * sizeof *nh);
        if (!nh)
            return -1;
        c->height_m = nh;
        c->cap = nc;
    }
    c->energy_kj[c->n] = e;
    c->height_m[c->n] = hgt;
    c->n++;
    return 0;
}

int rf_hazard_end(rf_hazard *h)
{
    for (size_t i = 0; i < h->ntouched; i++) {
        const rf_hazard_touch *tc = &h->touched[i];
        if (cell_push(&h->cells[tc->cell], tc->energy_kj, tc->height_m))
            h->oom = 1;
    }
    h->ntouched = 0;
    return h->oom ? -1 : 0;
}

int rf_hazard_merge(rf_hazard *into, const rf_hazard *from)
{
    for (size_t i = 0; i < into->nx * into->ny; i++)
        for (uint32_t k = 0; k < from->cells[i].n; k++)
            if (cell_push(&into->cells[i], from->cells[i].energy_kj[k], from->cells[i].height_m[k]))
                return -1;
    return 0;
}

int rf_hazard_write(rf_hazard *h, long n_trajectories, rf_store *s, rf_error *err)
{
    if (rf_store_batch_begin(s, err))
        return -1;
    for (size_t iy = 0; iy < h->ny; iy++)
        for (size_t ix = 0; ix < h->nx; ix++) {
            rf_hazard_cell *c = &h->cells[iy * h->nx + ix];
            if (c->n == 0)
                continue;
            rf_hazard_cell_record r;
            r.ix = (long)ix;
            r.iy = (long)iy;
            r.x = h->x0 + ((double)ix + 0.5) * h->cell;
            r.y = h->y0 + ((double)iy + 0.5) * h->cell;
            r.passes = c->n;
            r.reach_probability = (double)c->n / (double)n_trajectories;
            r.energy_p95_kj = rf_percentile_nearest_rank(c->energy_kj, c->n, 0.95);
            r.energy_max_kj = c->energy_kj[c->n - 1]; /* sorted by the percentile */
            r.height_p95_m = rf_percentile_nearest_rank(c->height_m, c->n, 0.95);
            if (rf_store_add_hazard_cell(s, &r, err))
                return -1; /* the batch rolled back: all cells or none */
        }
    return rf_store_batch_commit(s, err);
}
