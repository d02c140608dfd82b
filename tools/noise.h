/* noise.h - deterministic value noise for the synthetic terrains of tools/ (mknoto,
 * mkvalley): the same inputs give the same heights, byte for byte, on any machine. */
#ifndef ROCKFALL_TOOLS_NOISE_H
#define ROCKFALL_TOOLS_NOISE_H

#include <math.h>
#include <stdint.h>

static inline double hash01(int32_t i, int32_t j, uint32_t salt)
{
    uint32_t h = (uint32_t)i * 0x8da6b343u ^ (uint32_t)j * 0xd8163841u ^ salt * 0xcb1ab31fu;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (double)(h & 0xffffffu) / (double)0x1000000u;
}

static inline double smooth(double t) { return t * t * (3.0 - 2.0 * t); }

/* Value noise in [-1, 1] on a lattice of spacing `scale`. */
static inline double noise(double x, double y, double scale, uint32_t salt)
{
    double fx = x / scale, fy = y / scale;
    int32_t i = (int32_t)floor(fx), j = (int32_t)floor(fy);
    double u = smooth(fx - i), v = smooth(fy - j);
    double a = hash01(i, j, salt), b = hash01(i + 1, j, salt);
    double c = hash01(i, j + 1, salt), d = hash01(i + 1, j + 1, salt);
    return 2.0 * ((a * (1 - u) + b * u) * (1 - v) + (c * (1 - u) + d * u) * v) - 1.0;
}

#endif
