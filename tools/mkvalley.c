/* mkvalley.c - writes the synthetic valley of projects/regional: a DEM of 2001 x 2001
 * nodes at 2 m (4 x 4 km, 16 km^2) and a mask of its source cells (20 m cells where the
 * ground is steeper than 45 degrees: the cliff bands, about three thousand).
 *
 * The valley is SYNTHETIC: a floor meandering along y and falling 3 % towards y = 0, on
 * each side a concave talus rising 250 m over 500 m, a cliff band of 53 degrees rising
 * 200 m over 150 m, and an upper slope of 34 degrees flattening towards the ridges;
 * gullies cut the sides, and deterministic value noise roughens the ground.
 * Usage: mkvalley DIR   (writes DIR/valley.asc and DIR/sources.asc; byte-for-byte
 * reproducible) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "noise.h"
#include <stdlib.h>

#define NODES 2001     /* per side */
#define CELL 2.0       /* m */
#define MASK_CELL 20.0 /* m */
#define MASK_N 200     /* mask cells per side */
#define STEEP_DEG 45.0 /* a source cell is steeper than this at its centre */

/* The height of a valley side at distance d (m) from the floor's axis. */
static double side(double d)
{
    if (d <= 100.0)
        return 0.02 * d;
    if (d <= 600.0)
        return 2.0 + 250.0 * pow((d - 100.0) / 500.0, 1.6);
    if (d <= 750.0)
        return 252.0 + 200.0 * (d - 600.0) / 150.0;
    return 452.0 + 400.0 * (1.0 - exp(-(d - 750.0) / 600.0));
}

static double elevation(double x, double y)
{
    double axis = 2000.0 + 150.0 * sin(y / 700.0);
    double d = fabs(x - axis);
    double gully = pow(fabs(sin(y / 160.0 + d / 500.0)), 6.0) * fmin(d / 400.0, 1.0);
    double z = 400.0 + 0.03 * y + side(d) - 25.0 * gully;
    return z + 6.0 * noise(x, y, 55.0, 1u) + 1.5 * noise(x, y, 13.0, 2u);
}

static double slope_deg(double x, double y)
{
    double h = 1.0;
    double gx = (elevation(x + h, y) - elevation(x - h, y)) / (2.0 * h);
    double gy = (elevation(x, y + h) - elevation(x, y - h)) / (2.0 * h);
    return atan(sqrt(gx * gx + gy * gy)) * 180.0 / M_PI;
}

static FILE *open_in(const char *dir, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f)
        perror(path);
    return f;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: mkvalley DIR\n");
        return 2;
    }
    FILE *f = open_in(argv[1], "valley.asc");
    if (!f)
        return 1;
    fprintf(f, "ncols %d\nnrows %d\nxllcorner 0\nyllcorner 0\ncellsize %g\nNODATA_value -9999\n",
            NODES, NODES, CELL);
    for (int j = NODES - 1; j >= 0; j--) /* the first row is the northernmost */
        for (int i = 0; i < NODES; i++)
            fprintf(f, "%.2f%c", elevation(i * CELL, j * CELL), i + 1 < NODES ? ' ' : '\n');
    if (fclose(f))
        return 1;
    f = open_in(argv[1], "sources.asc");
    if (!f)
        return 1;
    fprintf(f, "ncols %d\nnrows %d\nxllcenter %g\nyllcenter %g\ncellsize %g\n"
               "NODATA_value -9999\n",
            MASK_N, MASK_N, MASK_CELL / 2, MASK_CELL / 2, MASK_CELL);
    long n = 0;
    for (int j = MASK_N - 1; j >= 0; j--)
        for (int i = 0; i < MASK_N; i++) {
            double x = (i + 0.5) * MASK_CELL, y = (j + 0.5) * MASK_CELL;
            int src = slope_deg(x, y) > STEEP_DEG;
            n += src;
            fprintf(f, "%d%c", src, i + 1 < MASK_N ? ' ' : '\n');
        }
    if (fclose(f))
        return 1;
    fprintf(stderr, "mkvalley: %s/valley.asc (%d x %d nodes, %g m), %s/sources.asc (%ld source "
                    "cells of %g m)\n",
            argv[1], NODES, NODES, CELL, argv[1], n, MASK_CELL);
    return 0;
}
