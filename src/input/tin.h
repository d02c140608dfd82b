/* tin.h - a grid terrain turned into a triangulated irregular network (TIN) whose
 * vertical error against the grid's own surface is at most a tolerance.
 *
 * The grid's surface is its triangles: cell (i, j) split along its SW-NE diagonal, as
 * terrain.h builds it.  The TIN is made by greedy insertion (Garland and Heckbert 1995,
 * "Fast polygonal approximation of terrains and height fields", algorithm III): start
 * from the grid's four corners, insert the grid node where the error is largest, keep
 * the triangulation Delaunay (Lawson's flips), repeat until the largest error is at
 * most the tolerance.
 *
 * The error of a TIN triangle is measured where its largest value over the triangle
 * must lie: both surfaces are linear on each piece of the overlay of the triangle with
 * the grid's triangles, so |TIN - grid| is largest at a vertex of that overlay, i.e. at
 * a grid node in the triangle or where an edge of the triangle crosses a grid edge
 * (the lines x = i, y = j and the diagonals x - y = i - j).  Both are measured, so the
 * bound holds everywhere on the TIN, not only at the nodes.  A crossing over the
 * tolerance inserts an end of the grid edge it crosses.
 *
 * Predicates are exact: the triangulation works in grid indices (integers), the
 * orientation and in-circle tests in 64-bit integers (sides up to RF_TIN_SIDE_MAX
 * nodes).  Four grid nodes of a cell lie on one circle; the tie is broken by a
 * symbolic perturbation of the lifting (x^2 + y^2 + eps (x - y)^2) that takes the
 * grid's own SW-NE diagonal, so a tolerance of 0 returns the grid's triangles.
 *
 * Nodata holes stay holes.  A TIN triangle is classed by the grid triangles whose
 * interiors it overlaps (grid triangles with a nodata node are holes): only valid
 * ones - kept and measured; only holes - dropped; both - it straddles a hole's edge and
 * a node of a valid grid triangle it overlaps, not yet inserted, is inserted first.  A
 * valid grid triangle whose three nodes are inserted is a Delaunay triangle (its axis
 * edges and its diagonal have no lattice point inside their diametral circles), so the
 * straddling ends and the kept triangles cover exactly the valid grid triangles'
 * area.  A grid corner at nodata is a vertex without a height: its triangles are holes
 * or straddle. */
#ifndef ROCKFALL_INPUT_TIN_H
#define ROCKFALL_INPUT_TIN_H

#include <stddef.h>

#include "input/bounds.h"
#include "input/terrain_io.h"
#include "rockfall/error.h"

typedef struct rf_tin_stats {
    size_t vertices;   /* grid nodes inserted (with the corners) */
    size_t triangles;  /* kept triangles */
    size_t dropped;    /* triangles over holes, dropped */
    double max_error;  /* the largest measured error of a kept triangle (m) */
    size_t unresolved; /* measurements with no node to insert (0 by construction) */
} rf_tin_stats;

/* Appends to `out` the triangles (world coordinates) of the TIN of grid g whose error
 * is at most `tolerance` (m, >= 0).  `path` names the grid in errors.  Returns 0, or -1
 * with err filled (a side over RF_TIN_SIDE_MAX, out of memory); out is unchanged then. */
int rf_tin_build(const rf_asc_grid *g, double tolerance, const char *path, rf_tri_list *out,
                 rf_tin_stats *stats, rf_error *err);

#endif
