/* polygon.c - point in polygon through an index of the edges (see polygon.h). */
#include "base/polygon.h"

#include <stdlib.h>
#include <string.h>

/* The strip of y, clamped to the strips.  (v - y0) / h does not decrease as v grows, in
 * floating point too, so an edge from ya to yb is listed in every strip that any y in
 * [ya, yb] falls in. */
static size_t strip_of(const rf_polygon_index *ix, double y)
{
    double s = floor((y - ix->y0) / ix->h);
    if (!(s > 0))
        return 0;
    return s >= (double)(ix->nstrips - 1) ? ix->nstrips - 1 : (size_t)s;
}

static void edge_span(const rf_polygon_index *ix, size_t k, size_t *lo, size_t *hi)
{
    size_t j = k ? k - 1 : ix->n - 1;
    double ya = ix->xy[2 * j + 1], yb = ix->xy[2 * k + 1];
    *lo = strip_of(ix, fmin(ya, yb));
    *hi = strip_of(ix, fmax(ya, yb));
}

/* The number of strip entries with the current strips. */
static size_t count_entries(const rf_polygon_index *ix)
{
    size_t total = 0;
    for (size_t k = 0; k < ix->n; k++) {
        size_t lo, hi;
        edge_span(ix, k, &lo, &hi);
        total += hi - lo + 1;
    }
    return total;
}

int rf_polygon_index_build(rf_polygon_index *ix, const double *xy, size_t n)
{
    memset(ix, 0, sizeof *ix);
    ix->xy = xy;
    ix->n = n;
    if (n == 0)
        return 0;
    ix->y0 = ix->ymax = xy[1];
    for (size_t k = 1; k < n; k++) {
        ix->y0 = fmin(ix->y0, xy[2 * k + 1]);
        ix->ymax = fmax(ix->ymax, xy[2 * k + 1]);
    }
    /* fewer, taller strips while long edges would be listed too often */
    size_t total;
    ix->nstrips = n;
    for (;;) {
        ix->h = (ix->ymax - ix->y0) / (double)ix->nstrips;
        if (!(ix->h > 0)) {
            ix->nstrips = 1;
            ix->h = 1.0;
        }
        total = count_entries(ix);
        if (total <= 8 * n || ix->nstrips == 1)
            break;
        ix->nstrips = (ix->nstrips + 1) / 2;
    }
    ix->start = calloc(ix->nstrips + 1, sizeof *ix->start);
    ix->edge = malloc(total * sizeof *ix->edge);
    if (!ix->start || !ix->edge) {
        rf_polygon_index_free(ix);
        return -1;
    }
    for (size_t k = 0; k < n; k++) {
        size_t lo, hi;
        edge_span(ix, k, &lo, &hi);
        for (size_t s = lo; s <= hi; s++)
            ix->start[s + 1]++;
    }
    for (size_t s = 0; s < ix->nstrips; s++)
        ix->start[s + 1] += ix->start[s];
    size_t *fill = malloc(ix->nstrips * sizeof *fill);
    if (!fill) {
        rf_polygon_index_free(ix);
        return -1;
    }
    memcpy(fill, ix->start, ix->nstrips * sizeof *fill);
    for (size_t k = 0; k < n; k++) {
        size_t lo, hi;
        edge_span(ix, k, &lo, &hi);
        for (size_t s = lo; s <= hi; s++)
            ix->edge[fill[s]++] = k;
    }
    free(fill);
    return 0;
}

void rf_polygon_index_free(rf_polygon_index *ix)
{
    free(ix->start);
    free(ix->edge);
    memset(ix, 0, sizeof *ix);
}

int rf_polygon_index_contains(rf_polygon_index *ix, double x, double y)
{
    if (ix->n == 0 || !(y >= ix->y0 && y <= ix->ymax))
        return 0; /* no edge's y-range holds y */
    size_t s = strip_of(ix, y);
    int inside = 0;
    for (size_t e = ix->start[s]; e < ix->start[s + 1]; e++) {
        size_t k = ix->edge[e], j = k ? k - 1 : ix->n - 1;
        ix->tests++;
        int r = rf_polygon_edge(ix->xy[2 * k], ix->xy[2 * k + 1], ix->xy[2 * j],
                                ix->xy[2 * j + 1], x, y);
        if (r == RF_EDGE_ON)
            return 1;
        if (r == RF_EDGE_CROSSES)
            inside = !inside;
    }
    return inside;
}
