/* exit.c - where the centre's horizontal path leaves the terrain: outside its bounds
 * or over a hole. */
#include "engine/exit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/contact.h"
#include "engine/geometry.h"
#include "engine/tables.h"

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* ---- leaving the terrain -------------------------------------------------------------- */

/* Time at which the straight horizontal line p + v t enters the 2D triangle (A, B, C),
 * within [t0, t1], and in *out the time it leaves it (at most t1); INFINITY when it
 * does not (a start inside counts as t0). */
static double line_enters_triangle(rf_vec3 p, rf_vec3 v, const double *xy, double t0, double t1,
                                   double *out)
{
    *out = t1;
    double orient = (xy[2] - xy[0]) * (xy[5] - xy[1]) - (xy[3] - xy[1]) * (xy[4] - xy[0]);
    double sg = orient > 0 ? 1.0 : -1.0;
    double lo = t0, hi = t1;
    for (int k = 0; k < 3; k++) {
        int j = (k + 1) % 3;
        double ex = xy[2 * j] - xy[2 * k], ey = xy[2 * j + 1] - xy[2 * k + 1];
        double alpha = sg * (ex * (p.y - xy[2 * k + 1]) - ey * (p.x - xy[2 * k]));
        double beta = sg * (ex * v.y - ey * v.x);
        if (beta > 0)
            lo = dmax(lo, -alpha / beta);
        else if (beta < 0)
            hi = dmin(hi, -alpha / beta);
        else if (alpha < 0)
            return INFINITY;
    }
    /* only the interior counts: a path along the border stays on the terrain */
    *out = hi;
    return lo < hi ? lo : INFINITY;
}

/* 1 when no triangle holds the centre's horizontal path at time tm. */
static int over_gap(const rf_terrain *t, const rf_arc *arc, double tm)
{
    return rf_terrain_locate(t, arc->p.x + arc->v.x * tm, arc->p.y + arc->v.y * tm) < 0;
}

/* Grids: the earliest time in [ta, tb] the path enters a nodata triangle of the cells
 * around it (te: the end of the whole path); INFINITY when none. */
static double grid_gap_entry(const rf_terrain *t, const rf_arc *arc, double ta, double tb,
                             double te)
{
    double cell = t->cell;
    double xa = arc->p.x + arc->v.x * ta, xb = arc->p.x + arc->v.x * tb;
    double ya = arc->p.y + arc->v.y * ta, yb = arc->p.y + arc->v.y * tb;
    size_t ncx = t->nx - 1, ncy = t->ny - 1;
    long i0 = (long)floor((dmin(xa, xb) - t->x0) / cell) - 1;
    long i1 = (long)floor((dmax(xa, xb) - t->x0) / cell) + 1;
    long j0 = (long)floor((dmin(ya, yb) - t->y0) / cell) - 1;
    long j1 = (long)floor((dmax(ya, yb) - t->y0) / cell) + 1;
    if (i0 < 0)
        i0 = 0;
    if (j0 < 0)
        j0 = 0;
    if (i1 > (long)ncx - 1)
        i1 = (long)ncx - 1;
    if (j1 > (long)ncy - 1)
        j1 = (long)ncy - 1;
    double best = INFINITY;
    for (long j = j0; j <= j1; j++)
        for (long ii = i0; ii <= i1; ii++)
            for (int k = 0; k < 2; k++) {
                if (rf_grid_slot(t, 2 * ((size_t)j * ncx + (size_t)ii) + (size_t)k) >= 0)
                    continue;
                double x0 = t->x0 + (double)ii * cell, y0 = t->y0 + (double)j * cell;
                double x1 = x0 + cell, y1 = y0 + cell;
                /* k = 0: SW, SE, NE;  k = 1: SW, NE, NW */
                double xy[6] = {x0, y0, x1, k == 0 ? y0 : y1, k == 0 ? x1 : x0, y1};
                double out, th = line_enters_triangle(arc->p, arc->v, xy, ta, te, &out);
                /* over the hole only if no triangle holds the centre halfway across it
                 * (a path along a hole's border stays on the terrain, and the locator
                 * holds a point a hair past the border on the cell next to it) */
                if (th <= tb && th < best && over_gap(t, arc, 0.5 * (th + out)))
                    best = th;
            }
    return best;
}

/* Meshes: the earliest time in [ta, tb] the path crosses outwards an edge that only one
 * triangle holds in plan (a border of the mesh or of a hole in it) into where no
 * triangle is; INFINITY when it does not.  A gap narrower than `bridge` along the path
 * (a sphere in full contact: r) is passed over, as is a crack at a seam between two
 * files of the mesh narrower than a hundredth of the triangles' size.  vh: the path's
 * horizontal speed. */
static double mesh_gap_entry(rf_motion *m, const rf_arc *arc, double vh, double ta, double tb,
                             double bridge)
{
    const rf_terrain *t = m->cfg.terrain;
    double xa = arc->p.x + arc->v.x * ta, xb = arc->p.x + arc->v.x * tb;
    double ya = arc->p.y + arc->v.y * ta, yb = arc->p.y + arc->v.y * tb;
    double pad = RF_REACH_TOLS * m->cfg.tol_len;
    size_t n = rf_gather(m, dmin(xa, xb) - pad, dmin(ya, yb) - pad, dmax(xa, xb) + pad,
                         dmax(ya, yb) + pad);
    double best = INFINITY;
    for (size_t i = 0; i < n; i++) {
        int32_t idx = m->ws->cand[i];
        unsigned border = m->ws->tables->edge_live[idx] / RF_EDGE_BORDER;
        if (!border)
            continue;
        const rf_triangle *T = RF_FACE(m, idx);
        for (int k = 0; k < 3; k++) {
            if (!(border >> k & 1))
                continue;
            rf_vec3 A = rf_tri_vertex(T, k), B = rf_tri_vertex(T, k + 1), C = rf_tri_vertex(T, k + 2);
            double ex = B.x - A.x, ey = B.y - A.y, el = m->ws->tables->hedge[3 * (size_t)idx + k];
            /* the side of the edge line the centre is on: s0 + s1 t, the triangle's
             * side positive */
            double sc = ex * (C.y - A.y) - ey * (C.x - A.x);
            if (!(el > 0) || sc == 0.0)
                continue;
            double sg = sc > 0 ? 1.0 : -1.0;
            double s0 = sg * (ex * (arc->p.y - A.y) - ey * (arc->p.x - A.x));
            double s1 = sg * (ex * arc->v.y - ey * arc->v.x);
            if (!(s1 < 0))
                continue; /* not moving outwards */
            /* the crossing; one more than a few tolerances behind the start is before
             * it (a gap under the start is the caller's) */
            if (s0 < -pad * el)
                continue;
            double th = dmax(0.0, -s0 / s1);
            if (!(th <= tb) || th >= best)
                continue;
            /* along the edge, from A (within a few tolerances of its ends) */
            double u = ((arc->p.x + arc->v.x * th - A.x) * ex +
                        (arc->p.y + arc->v.y * th - A.y) * ey) / el;
            if (u < -pad || u > el + pad)
                continue;
            /* a gap when the centre is over no triangle `bridge` past the edge (and
             * at least a hundredth of the holder's height over it, far beyond the
             * locator's tolerance), along the path, but no more than 100 times that
             * for a path nearly along the edge */
            double d = dmax(bridge, RF_GAP_PROBE * fabs(sc) / el);
            double dt = d * dmin(vh * el / -s1, RF_GAP_PROBE_MAX) / vh;
            if (over_gap(t, arc, th + dt))
                best = th;
        }
    }
    return best;
}

double rf_terrain_exit_time(rf_motion *m, const rf_arc *arc, double T)
{
    const rf_terrain *t = m->cfg.terrain;
    double te = T;
    double px = arc->p.x, py = arc->p.y, vx = arc->v.x, vy = arc->v.y;
    double xmin = t->xmin, xmax = t->xmax, ymin = t->ymin, ymax = t->ymax;
    if (t->is_grid) {
        xmin = t->x0;
        ymin = t->y0;
        rf_grid_far(t, &xmax, &ymax);
    }
    if (vx > 0)
        te = dmin(te, (xmax - px) / vx);
    else if (vx < 0)
        te = dmin(te, (xmin - px) / vx);
    if (vy > 0)
        te = dmin(te, (ymax - py) / vy);
    else if (vy < 0)
        te = dmin(te, (ymin - py) / vy);
    if (te < 0)
        te = 0;
    if (!m->ws->tables->has_gaps)
        return te;
    double vh = hypot(vx, vy);
    /* meshes: a gap under the start, still there `bridge` on (a grid's: a start inside
     * a nodata triangle, below) */
    double bridge = m->cfg.centre || m->cfg.point ? 0.0 : m->cfg.rho;
    if (!t->is_grid && over_gap(t, arc, 0.0) &&
        (!(vh > 0) || over_gap(t, arc, dmax(bridge, RF_GAP_PROBE * t->bsize) / vh)))
        return 0.0;
    /* the gaps along the path, a few cells at a time */
    double cell = t->is_grid ? t->cell : t->bsize;
    double np = ceil(vh * te / (8.0 * cell));
    long npieces = np >= 1.0 ? (np < RF_MAX_SEARCH_PIECES ? (long)np : RF_MAX_SEARCH_PIECES) : 1;
    for (long i = 0; i < npieces; i++) {
        double ta = te * (double)i / (double)npieces, tb = te * (double)(i + 1) / (double)npieces;
        double best = t->is_grid ? grid_gap_entry(t, arc, ta, tb, te)
                                  : mesh_gap_entry(m, arc, vh, ta, tb, bridge);
        if (best < INFINITY)
            return best;
    }
    return te;
}

