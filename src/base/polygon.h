/* polygon.h - point in polygon, one edge at a time or through an index of the edges.
 *
 * rf_polygon_edge is the one test of a point against an edge; rf_point_in_polygon
 * (rockfall/terrain.h) runs it over every edge, rf_polygon_index_contains over the edges
 * whose y-range holds the point's y, which are the only ones that can answer anything
 * but "nothing": the two give the same answer for every point, to the bit. */
#ifndef ROCKFALL_POLYGON_H
#define ROCKFALL_POLYGON_H

#include <math.h>
#include <stddef.h>

#include "base/tolerances.h"

enum { RF_EDGE_NOTHING = 0, RF_EDGE_CROSSES = 1, RF_EDGE_ON = 2 };

/* The point (x, y) against the edge from (xi, yi) to (xj, yj): RF_EDGE_ON when it lies
 * on the edge (within RF_ON_EDGE_REL), RF_EDGE_CROSSES when the ray from it towards +x
 * crosses the edge (even-odd rule), else RF_EDGE_NOTHING.  Anything but nothing needs
 * min(yi, yj) <= y <= max(yi, yj). */
static inline int rf_polygon_edge(double xi, double yi, double xj, double yj, double x, double y)
{
    double dx = xj - xi, dy = yj - yi;
    double cross = dx * (y - yi) - dy * (x - xi);
    if (fabs(cross) <= RF_ON_EDGE_REL * (dx * dx + dy * dy) && x >= fmin(xi, xj) &&
        x <= fmax(xi, xj) && y >= fmin(yi, yj) && y <= fmax(yi, yj))
        return RF_EDGE_ON;
    if ((yi > y) != (yj > y) && x < xi + (y - yi) * dx / dy)
        return RF_EDGE_CROSSES;
    return RF_EDGE_NOTHING;
}

/* A polygon's edges sorted into horizontal strips: strip s, from y0 + s h to
 * y0 + (s + 1) h, lists the edges whose y-range meets it.  There are as many strips as
 * edges, fewer when long edges would otherwise be listed more than 8 times per edge on
 * average. */
typedef struct rf_polygon_index {
    const double *xy; /* the polygon's n vertices (not copied) */
    size_t n;
    double y0, ymax, h;
    size_t nstrips;
    size_t *start;    /* strip s: edge[start[s] .. start[s + 1]) */
    size_t *edge;     /* edge k runs from vertex k - 1 (n - 1 for k = 0) to vertex k */
    size_t tests;     /* edges tested by rf_polygon_index_contains (for tests) */
} rf_polygon_index;

/* 0, or -1 when memory runs out. */
int rf_polygon_index_build(rf_polygon_index *ix, const double *xy, size_t n);
void rf_polygon_index_free(rf_polygon_index *ix);
/* What rf_point_in_polygon(xy, n, x, y) answers, from the edges of y's strip. */
int rf_polygon_index_contains(rf_polygon_index *ix, double x, double y);

#endif
