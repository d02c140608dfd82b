/* polyline.h - stations along a polyline in the plane. */
#ifndef ROCKFALL_POLYLINE_H
#define ROCKFALL_POLYLINE_H

#include <stddef.h>

/* The station of (x, y) along a polyline of n points (xy: x0, y0, x1, y1, ...): the
 * distance along the line from its first point to the line's point nearest (x, y).
 * *dist (may be NULL) gets the horizontal distance to that nearest point, *nx, *ny
 * (may be NULL) the point itself. */
double rf_polyline_station(const double *xy, size_t n, double x, double y, double *dist,
                           double *nx, double *ny);
/* Length of a polyline. */
double rf_polyline_length(const double *xy, size_t n);

#endif
