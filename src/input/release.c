/* release.c - where a release's trajectories start and what their rocks weigh, as a
 * planner draws them: a `point`, an `area` polygon (triangulated here, so that a start
 * is drawn uniformly by picking a triangle by its area) or a `cells` raster mask (every
 * non-zero cell a source); a rock's `mass` as a number, a log-normal {mean, sd} or a
 * list.  The draws themselves are in src/run/montecarlo.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/body.h"

#include "input/bounds.h"
#include "input/project_private.h"
#include "input/terrain_io.h"

/* ---- areas -------------------------------------------------------------------- */

static double cross3(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* 1 when the closed segments ab and cd cross or touch. */
static int segments_meet(const double *a, const double *b, const double *c, const double *d)
{
    double d1 = cross3(c, d, a), d2 = cross3(c, d, b), d3 = cross3(a, b, c), d4 = cross3(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return 1;
    return 0;
}

/* 1 when two edges that share no vertex cross (the polygon is not simple). */
static int polygon_crosses(const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1)
                continue;
            if (segments_meet(v + 2 * i, v + 2 * ((i + 1) % n), v + 2 * j, v + 2 * ((j + 1) % n)))
                return 1;
        }
    return 0;
}

static int inside_triangle(const double *p, const double *a, const double *b, const double *c)
{
    return cross3(a, b, p) >= 0 && cross3(b, c, p) >= 0 && cross3(c, a, p) >= 0;
}

/* Ear clipping of a simple counter-clockwise polygon into n - 2 triangles (collinear
 * vertices give triangles of zero area); 0, or -1 when no ear is found. */
static int clip_ears(const double *v, size_t n, size_t *idx, size_t *tri, size_t *ntri)
{
    size_t m = n, t = 0;
    while (m > 3) {
        size_t found = m;
        for (size_t k = 0; k < m && found == m; k++) {
            size_t a = idx[(k + m - 1) % m], b = idx[k], c = idx[(k + 1) % m];
            double cr = cross3(v + 2 * a, v + 2 * b, v + 2 * c);
            if (cr < 0)
                continue;
            int ear = 1;
            for (size_t j = 0; j < m && ear && cr > 0; j++) {
                size_t q = idx[j];
                if (q != a && q != b && q != c &&
                    inside_triangle(v + 2 * q, v + 2 * a, v + 2 * b, v + 2 * c))
                    ear = 0;
            }
            if (ear)
                found = k;
        }
        if (found == m)
            return -1;
        tri[3 * t] = idx[(found + m - 1) % m];
        tri[3 * t + 1] = idx[found];
        tri[3 * t + 2] = idx[(found + 1) % m];
        t++;
        memmove(idx + found, idx + found + 1, (m - found - 1) * sizeof *idx);
        m--;
    }
    tri[3 * t] = idx[0], tri[3 * t + 1] = idx[1], tri[3 * t + 2] = idx[2];
    *ntri = t + 1;
    return 0;
}

static int read_area(loader *L, const rf_ynode *n, rf_release *r)
{
    if (rf_load_points(L, n, "area", 3, &r->area, &r->narea))
        return -1;
    size_t np = r->narea;
    if (np > RF_RELEASE_AREA_POINTS_MAX)
        return rf_ydoc_error(&L->d, n, L->err, "'area' has %zu points; it may have at most %d",
                             np, RF_RELEASE_AREA_POINTS_MAX);
    double a2 = 0.0, cx = 0.0, cy = 0.0;
    for (size_t i = 0; i < np; i++) {
        const double *p = r->area + 2 * i, *q = r->area + 2 * ((i + 1) % np);
        double c = p[0] * q[1] - q[0] * p[1];
        a2 += c;
        cx += (p[0] + q[0]) * c;
        cy += (p[1] + q[1]) * c;
    }
    double scale = 0.0;
    for (size_t i = 0; i < 2 * np; i++)
        scale = fmax(scale, fabs(r->area[i] - r->area[i % 2]));
    if (!(fabs(a2) > 1e-12 * scale * scale) || !isfinite(a2))
        return rf_ydoc_error(&L->d, n, L->err, "'area' encloses no area (its points are "
                                               "collinear or repeated)");
    if (polygon_crosses(r->area, np))
        return rf_ydoc_error(&L->d, n, L->err, "'area' is not a simple polygon: two of its "
                                               "edges cross");
    r->x = cx / (3.0 * a2);
    r->y = cy / (3.0 * a2);
    size_t *idx = malloc(np * sizeof *idx);
    r->area_tri = malloc(3 * (np - 2) * sizeof *r->area_tri);
    r->area_cum = malloc((np - 2) * sizeof *r->area_cum);
    if (!idx || !r->area_tri || !r->area_cum) {
        free(idx);
        return rf_load_oom(L);
    }
    for (size_t i = 0; i < np; i++) /* counter-clockwise */
        idx[i] = a2 > 0 ? i : np - 1 - i;
    int rc = clip_ears(r->area, np, idx, r->area_tri, &r->ntri);
    free(idx);
    if (rc)
        return rf_ydoc_error(&L->d, n, L->err, "'area' is not a simple polygon");
    double cum = 0.0;
    for (size_t t = 0; t < r->ntri; t++) {
        const size_t *k = r->area_tri + 3 * t;
        cum += 0.5 * fabs(cross3(r->area + 2 * k[0], r->area + 2 * k[1], r->area + 2 * k[2]));
        r->area_cum[t] = cum;
    }
    return 0;
}

/* ---- cells masks -------------------------------------------------------------- */

static int read_cells(loader *L, const rf_ynode *n, rf_release *r)
{
    const char *s;
    if (rf_ydoc_string(&L->d, n, "cells", &s, L->err))
        return -1;
    char *path = rf_load_resolve(L->p->dir, s);
    if (!path)
        return rf_load_oom(L);
    char why[256];
    if (!rf_load_readable(path, why, sizeof why)) {
        rf_ydoc_error(&L->d, n, L->err, "cannot open cells mask '%s': %s", path, why);
        free(path);
        return -1;
    }
    rf_asc_grid g;
    int rc = rf_asc_read(path, &g, L->err);
    free(path);
    if (rc)
        return -1;
    size_t ns = 0, total = g.ncols * g.nrows;
    for (size_t k = 0; k < total; k++)
        ns += g.z[k] != 0.0 && !(g.has_nodata && g.z[k] == g.nodata);
    if (ns == 0 || ns > RF_RELEASE_CELLS_MAX) {
        rf_asc_free(&g);
        return ns ? rf_ydoc_error(&L->d, n, L->err, "cells mask has %zu source cells; at most "
                                                    "%g", ns, RF_RELEASE_CELLS_MAX)
                  : rf_ydoc_error(&L->d, n, L->err, "cells mask has no source cell (no cell "
                                                    "other than 0 and nodata)");
    }
    r->cells = malloc(2 * ns * sizeof *r->cells);
    if (!r->cells) {
        rf_asc_free(&g);
        return rf_load_oom(L);
    }
    size_t m = 0;
    for (size_t j = 0; j < g.nrows; j++)
        for (size_t i = 0; i < g.ncols; i++) {
            double z = g.z[j * g.ncols + i];
            if (z != 0.0 && !(g.has_nodata && z == g.nodata)) {
                r->cells[2 * m] = g.x0 + (double)i * g.cell;
                r->cells[2 * m + 1] = g.y0 + (double)j * g.cell;
                m++;
            }
        }
    r->ncells = ns;
    r->cell = g.cell;
    r->x = r->cells[0];
    r->y = r->cells[1];
    rf_asc_free(&g);
    return 0;
}

/* ---- a release's source ------------------------------------------------------- */

int rf_load_release_source(loader *L, const rf_ynode *n, rf_release *r, const char *what,
                           rf_ynode **where)
{
    static const char *const keys[] = {"point", "area", "cells"};
    rf_ynode *given[3];
    int ngiven = 0, k = -1;
    for (int i = 0; i < 3; i++)
        if ((given[i] = rf_ydoc_get(&L->d, n, keys[i])))
            ngiven++, k = k < 0 ? i : k;
    if (ngiven != 1) {
        const rf_ynode *at = ngiven ? given[2] ? given[2] : given[1] : n;
        return rf_ydoc_error(&L->d, at, L->err, "%s must give exactly one of 'point', 'area' "
                                                "and 'cells'; it gives %d",
                             what, ngiven);
    }
    *where = given[k];
    r->source = (rf_release_source)k;
    if (k == 0) {
        double xy[2];
        if (rf_load_tuple(L, given[0], "point", 2, "a point [x, y]", RF_COORD_MAX, "m", xy))
            return -1;
        r->x = xy[0];
        r->y = xy[1];
        return 0;
    }
    rf_ynode *jitter = rf_ydoc_get(&L->d, n, "jitter");
    if (jitter)
        return rf_ydoc_error(&L->d, jitter, L->err, "'jitter' applies to a 'point' release; "
                                                    "an 'area' or 'cells' release draws its "
                                                    "starts over its sources");
    return k == 1 ? read_area(L, given[1], r) : read_cells(L, given[2], r);
}

long rf_release_trajectories(const rf_release *r)
{
    return r->source == RF_SOURCE_CELLS ? r->count * (long)r->ncells : r->count;
}

long rf_release_source_cell(const rf_release *r, long idx)
{
    return r->source == RF_SOURCE_CELLS ? (idx / r->count) % (long)r->ncells : -1;
}

static int off_terrain(loader *L, const rf_ynode *where, const rf_release *r, const char *which,
                       double x, double y)
{
    const rf_terrain *t = &L->p->terrain;
    return rf_ydoc_error(&L->d, where, L->err,
                         "release '%s' %s (%g, %g) is off the terrain or in a hole of it "
                         "(x %g..%g, y %g..%g)",
                         r->name, which, x, y, t->xmin, t->xmax, t->ymin, t->ymax);
}

int rf_place_release(loader *L, rf_release *r, const rf_ynode *where)
{
    const rf_terrain *t = &L->p->terrain;
    double z;
    if (r->source == RF_SOURCE_AREA) {
        for (size_t i = 0; i < r->narea; i++)
            if (rf_terrain_height(t, r->area[2 * i], r->area[2 * i + 1], &z) < 0)
                return off_terrain(L, where, r, "area point", r->area[2 * i],
                                   r->area[2 * i + 1]);
        if (rf_terrain_height(t, r->x, r->y, &r->z) < 0)
            rf_terrain_height(t, r->area[0], r->area[1], &r->z);
    } else if (r->source == RF_SOURCE_CELLS) {
        if (r->count > RF_COUNT_MAX / (long)r->ncells)
            return rf_ydoc_error(&L->d, where, L->err, "release '%s': %ld per cell over %zu "
                                                       "cells is over %ld trajectories",
                                 r->name, r->count, r->ncells, RF_COUNT_MAX);
        for (size_t i = 0; i < r->ncells; i++)
            if (rf_terrain_height(t, r->cells[2 * i], r->cells[2 * i + 1], &z) < 0)
                return off_terrain(L, where, r, "source cell centre", r->cells[2 * i],
                                   r->cells[2 * i + 1]);
        rf_terrain_height(t, r->x, r->y, &r->z);
    }
    return 0;
}

void rf_release_free(rf_release *r)
{
    free(r->area);
    free(r->area_tri);
    free(r->area_cum);
    free(r->cells);
}

/* ---- a rock's mass ------------------------------------------------------------ */

static int read_mass_list(loader *L, const rf_ynode *n, rf_rock *r)
{
    size_t k = rf_ydoc_seq_size(n);
    if (k == 0)
        return rf_ydoc_error(&L->d, n, L->err, "'mass' is an empty list; give at least one "
                                               "mass");
    if (k > RF_MASS_LIST_MAX)
        return rf_ydoc_error(&L->d, n, L->err, "'mass' lists %zu masses; at most %d", k,
                             RF_MASS_LIST_MAX);
    if (!(r->masses = malloc(k * sizeof *r->masses)))
        return rf_load_oom(L);
    r->nmasses = k;
    double sum = 0.0;
    for (size_t i = 0; i < k; i++) {
        rf_ynode *m = rf_ydoc_seq_item(&L->d, n, i);
        if (rf_ydoc_number(&L->d, m, "mass", RF_YR_POSITIVE, &r->masses[i], L->err) ||
            rf_load_bounded(L, m, "mass", r->masses[i], 0.0, RF_ROCK_MASS_MAX, "kg"))
            return -1;
        sum += r->masses[i];
    }
    r->mass_kind = RF_MASS_LIST;
    r->mass = sum / (double)k;
    return 0;
}

int rf_load_rock_mass(loader *L, const rf_ynode *n, rf_rock *r, const char *what,
                      rf_ynode **where)
{
    static const char *const keys[] = {"mean", "sd", NULL};
    rf_ynode *mass;
    if (rf_ydoc_require(&L->d, n, "mass", what, &mass, L->err))
        return -1;
    *where = mass;
    r->mass_kind = RF_MASS_FIXED;
    if (mass->type == YAML_SEQUENCE_NODE)
        return read_mass_list(L, mass, r);
    if (mass->type != YAML_MAPPING_NODE)
        return rf_ydoc_number(&L->d, mass, "mass", RF_YR_POSITIVE, &r->mass, L->err);
    rf_ynode *mean, *sd;
    if (rf_ydoc_mapping_of(&L->d, mass, keys, "'mass'", L->err) ||
        rf_ydoc_require(&L->d, mass, "mean", "'mass'", &mean, L->err) ||
        rf_ydoc_require(&L->d, mass, "sd", "'mass'", &sd, L->err) ||
        rf_ydoc_number(&L->d, mean, "mean", RF_YR_POSITIVE, &r->mass, L->err) ||
        rf_ydoc_number(&L->d, sd, "sd", RF_YR_NONNEG, &r->mass_sd, L->err) ||
        rf_load_bounded(L, sd, "sd", r->mass_sd, 0.0, RF_ROCK_MASS_MAX, "kg"))
        return -1;
    if (!(r->mass_sd <= RF_MASS_CV_MAX * r->mass))
        return rf_ydoc_error(&L->d, sd, L->err, "'sd' is %g times the mean; it may be at most "
                                                "%g times",
                             r->mass_sd / r->mass, RF_MASS_CV_MAX);
    r->mass_kind = RF_MASS_LOGNORMAL;
    return 0;
}

int rf_check_mass_radii(loader *L, const rf_ynode *mass, const rf_rock *r)
{
    for (size_t i = 0; i < r->nmasses; i++) {
        double radius = rf_body_make(r->masses[i], r->density, RF_MODEL_SPHERE).radius;
        if (!(radius >= RF_ROCK_RADIUS_MIN && radius <= RF_ROCK_RADIUS_MAX))
            return rf_ydoc_error(&L->d, rf_ydoc_seq_item(&L->d, mass, i), L->err,
                                 "'mass' %g kg and 'density' give a rock of radius %g m; it "
                                 "must be %g to %g m",
                                 r->masses[i], radius, RF_ROCK_RADIUS_MIN, RF_ROCK_RADIUS_MAX);
    }
    return 0;
}
