/* terrain_grid.c - the terrain sampled for the report (see terrain_grid.h). */
#include "results/terrain_grid.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void rf_plan_extent_fit(double *x0, double *x1, double *y0, double *y1)
{
    double dx = *x1 - *x0, dy = *y1 - *y0;
    if (dy < 0.25 * dx) {
        double extra = (0.25 * dx - dy) / 2;
        *y0 -= extra;
        *y1 += extra;
        dy = *y1 - *y0;
    }
    if (dx < 0.4 * dy) {
        double extra = (0.4 * dy - dx) / 2;
        *x0 -= extra;
        *x1 += extra;
    }
}

int rf_terrain_grid_sample(const rf_terrain *t, rf_terrain_grid *g)
{
    memset(g, 0, sizeof *g);
    g->xmin = g->x0 = t->xmin;
    g->xmax = g->x1 = t->xmax;
    g->ymin = g->y0 = t->ymin;
    g->ymax = g->y1 = t->ymax;
    rf_plan_extent_fit(&g->x0, &g->x1, &g->y0, &g->y1);
    double dx = g->x1 - g->x0, dy = g->y1 - g->y0;
    g->step = fmax(dx, dy) / RF_TERRAIN_GRID_NODES;
    g->nx = (size_t)ceil(dx / g->step) + 1;
    g->ny = (size_t)ceil(dy / g->step) + 1;
    g->z = malloc(g->nx * g->ny * sizeof *g->z);
    if (!g->z)
        return -1;
    for (size_t j = 0; j < g->ny; j++)
        for (size_t i = 0; i < g->nx; i++) {
            double z = NAN;
            double x = fmin(g->x0 + (double)i * g->step, g->x1);
            double y = fmin(g->y0 + (double)j * g->step, g->y1);
            if (rf_terrain_height(t, x, y, &z) < 0)
                z = NAN;
            g->z[j * g->nx + i] = z;
        }
    return 0;
}

void rf_terrain_grid_free(rf_terrain_grid *g)
{
    free(g->z);
    g->z = NULL;
}

void rf_terrain_grid_encode(const rf_terrain_grid *g, unsigned char *out)
{
    for (size_t k = 0; k < g->nx * g->ny; k++) {
        uint64_t u;
        memcpy(&u, &g->z[k], sizeof u);
        for (int b = 0; b < 8; b++)
            out[8 * k + (size_t)b] = (unsigned char)(u >> (8 * b));
    }
}

int rf_terrain_grid_decode(rf_terrain_grid *g, const void *blob, size_t len)
{
    size_t n = g->nx * g->ny;
    if (g->nx < 2 || g->ny < 2 || n / g->ny != g->nx || len != 8 * n || !blob)
        return -1;
    if (!(g->z = malloc(n * sizeof *g->z)))
        return -1;
    const unsigned char *in = blob;
    for (size_t k = 0; k < n; k++) {
        uint64_t u = 0;
        for (int b = 0; b < 8; b++)
            u |= (uint64_t)in[8 * k + (size_t)b] << (8 * b);
        memcpy(&g->z[k], &u, sizeof u);
    }
    return 0;
}
