/* mkroll.c - writes the rolling-dominated bench slope of projects/bench/ (`make bench`).
 *
 * A SYNTHETIC ESRI ASCII grid at the cell size given (1 m by default; 2 and 0.5 m give
 * the same surface sampled coarser or finer), x across the slope (0..100 m), y up it:
 *   - y in [0, 80): the run-out, counter-sloped at 14 degrees (it rises away from the
 *     slope's foot, towards y = 0);
 *   - y in [80, 260]: the slope, 175 m long along the ground, dropping 170 m over its
 *     180 m in plan: z = 170 (0.55 s + 0.45 s^2), s = (y - 80) / 180, about 28 degrees
 *     at the foot and 50 at the top;
 *   - y in (260, 270]: a level release shelf;
 *   - gentle gullies across the slope: 1.2 m deep, 25 m apart, fading out on the run-out
 *     and the shelf; no small-scale roughness, so rocks roll rather than bounce.
 * The surface is a smooth function sampled at the nodes, so the grids differ only by
 * their sampling.  Usage: mkroll [cell] > roll.asc   (byte-for-byte reproducible) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define WIDTH 100.0
#define LENGTH 270.0
#define FOOT 80.0
#define TOP 260.0
#define DROP 170.0

static double elevation(double x, double y)
{
    const double counter = tan(14.0 * M_PI / 180.0);
    double z, env; /* env: the gullies' depth factor, 1 on the slope */
    if (y < FOOT) {
        z = counter * (FOOT - y);
        env = y > FOOT - 20.0 ? (y - (FOOT - 20.0)) / 20.0 : 0.0;
    } else if (y <= TOP) {
        double s = (y - FOOT) / (TOP - FOOT);
        z = DROP * (0.55 * s + 0.45 * s * s);
        env = 1.0;
    } else {
        z = DROP;
        env = 0.0;
    }
    if (y > TOP - 10.0 && y <= TOP)
        env = (TOP - y) / 10.0;
    /* the gullies, with a slight skew so that they are not aligned with the grid */
    z -= 1.2 * env * 0.5 * (1.0 + cos(2.0 * M_PI * (x - 0.08 * y) / 25.0));
    return z;
}

int main(int argc, char **argv)
{
    double cell = argc > 1 ? atof(argv[1]) : 1.0;
    if (!(cell >= 0.1 && cell <= 10.0)) {
        fprintf(stderr, "mkroll: cell size %s: expected a number from 0.1 to 10 (m)\n",
                argc > 1 ? argv[1] : "");
        return 2;
    }
    int nx = (int)lround(WIDTH / cell) + 1, ny = (int)lround(LENGTH / cell) + 1;
    printf("ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize %g\nNODATA_value -9999\n",
           nx, ny, cell);
    for (int j = ny - 1; j >= 0; j--) {
        for (int i = 0; i < nx; i++)
            printf(i ? " %.4f" : "%.4f", elevation(i * cell, j * cell));
        putchar('\n');
    }
    return 0;
}
