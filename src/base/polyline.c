/* polyline.c - stations along polylines (see polyline.h). */
#include "base/polyline.h"

#include <math.h>

double rf_polyline_length(const double *xy, size_t n)
{
    double len = 0.0;
    for (size_t i = 0; i + 1 < n; i++)
        len += hypot(xy[2 * i + 2] - xy[2 * i], xy[2 * i + 3] - xy[2 * i + 1]);
    return len;
}

double rf_polyline_station(const double *xy, size_t n, double x, double y, double *dist,
                           double *nx, double *ny)
{
    double best = INFINITY, station = 0.0, along = 0.0, bx = n ? xy[0] : x, by = n ? xy[1] : y;
    for (size_t i = 0; i + 1 < n || (n == 1 && i == 0); i++) {
        double ax = xy[2 * i], ay = xy[2 * i + 1];
        double ex = n > 1 ? xy[2 * i + 2] : ax, ey = n > 1 ? xy[2 * i + 3] : ay;
        double ux = ex - ax, uy = ey - ay, len2 = ux * ux + uy * uy;
        double t = len2 > 0.0 ? ((x - ax) * ux + (y - ay) * uy) / len2 : 0.0;
        t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
        double px = ax + t * ux, py = ay + t * uy, d = hypot(x - px, y - py);
        if (d < best) {
            best = d;
            station = along + t * sqrt(len2);
            bx = px;
            by = py;
        }
        along += sqrt(len2);
        if (n == 1)
            break;
    }
    if (dist)
        *dist = best;
    if (nx)
        *nx = bx;
    if (ny)
        *ny = by;
    return station;
}

