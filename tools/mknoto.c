/* mknoto.c - writes the synthetic Suzu-Maura-like slope of projects/noto/terrain.asc.
 *
 * The paper's DEM is not public.  This terrain is SYNTHETIC, in the spirit of its
 * Fig. 9: a 1 m ESRI ASCII grid, x along the coast (0..300 m), y up the slope
 * (0..240 m); a coastal strip with the road (z about 3-4 m, y < 25 m), a concave
 * slope rising 175 m over 180 m (average gradient about 44 degrees, 34 degrees at the
 * foot, 52 at the top), a plateau above; ridges and gullies across the slope, the
 * main gully at x = 170 m, and a small-scale irregular surface (deterministic value
 * noise).  Usage: mknoto > projects/noto/terrain.asc   (byte-for-byte reproducible) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "noise.h"

#define NX 301
#define NY 241

static double elevation(double x, double y)
{
    const double foot = 25.0, top = 205.0, rise = 175.0;
    double z, env; /* env: 0 off the slope, 1 on it */
    if (y <= foot) {
        z = 3.0 + 0.02 * y;
        env = 0.0;
    } else if (y <= top) {
        double s = (y - foot) / (top - foot);
        z = 3.5 + rise * (0.7 * s + 0.3 * s * s);
        env = sin(M_PI * s);
        env = env > 0 ? sqrt(env) : 0;
    } else {
        z = 3.5 + rise + 0.05 * (y - top);
        env = 0.0;
    }
    /* the main gully at x = 170 m, deepest mid-slope */
    double g = (x - 170.0) / 14.0;
    z -= 7.0 * env * exp(-g * g);
    /* ridges and lesser gullies across the slope */
    z += 3.0 * env * cos(2.0 * M_PI * (x - 170.0) / 62.0 + 0.015 * y);
    /* the whole slope leans gently towards the main gully */
    z += 0.015 * env * fabs(x - 170.0);
    /* small-scale irregularity */
    double rough = y > foot - 5.0 ? 1.0 : 0.2;
    z += rough * (0.8 * noise(x, y, 9.0, 1u) + 0.35 * noise(x, y, 3.5, 2u));
    return z;
}

int main(void)
{
    printf("ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize 1\nNODATA_value -9999\n", NX, NY);
    for (int j = NY - 1; j >= 0; j--) {
        for (int i = 0; i < NX; i++)
            printf(i ? " %.2f" : "%.2f", elevation(i, j));
        putchar('\n');
    }
    return 0;
}
