/* vegetation.c - tree collisions as a Poisson process (see vegetation.h). */
#include "scene/vegetation.h"

#include <math.h>

#include <gsl/gsl_cdf.h>

#include "base/arc.h" /* rf_arc_length */
#include "base/tolerances.h"
#include "base/util.h"

double rf_forest_density_above(const rf_forest *f, double h_r)
{
    if (f->height.sd <= 0.0) /* sigma = 0: every tree is M_ht tall (a step) */
        return h_r < f->height.mean ? f->density : 0.0;
    return f->density * gsl_cdf_gaussian_Q(h_r - f->height.mean, f->height.sd); /* Eq. 11 */
}

double rf_forest_rate(const rf_forest *f, double h_r, double phi_r)
{
    return rf_forest_density_above(f, h_r) * (phi_r + f->diameter); /* Eq. 12, per metre */
}

/* Forest f's rate with every tree taller than the rock's centre (Eq. 12 with the
 * density of Eq. 11 at its largest): its share of the thinning bound. */
static double forest_bound(const rf_forest *f, double phi_r)
{
    return f->density * (phi_r + f->diameter);
}

double rf_vegetation_rate_bound(const rf_forest *fs, size_t n, double phi_r)
{
    double b = 0.0;
    for (size_t i = 0; i < n; i++)
        b += forest_bound(&fs[i], phi_r);
    return b;
}

int rf_vegetation_touches(const rf_forest *fs, size_t n, double xmin, double ymin, double xmax,
                          double ymax)
{
    for (size_t i = 0; i < n; i++) {
        const rf_polyline *pg = &fs[i].polygon;
        if (!(fs[i].density > 0.0))
            continue;
        if (pg->n == 0)
            return 1;
        double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
        for (size_t k = 0; k < pg->n; k++) {
            x0 = fmin(x0, pg->xy[2 * k]), x1 = fmax(x1, pg->xy[2 * k]);
            y0 = fmin(y0, pg->xy[2 * k + 1]), y1 = fmax(y1, pg->xy[2 * k + 1]);
        }
        if (x0 <= xmax && x1 >= xmin && y0 <= ymax && y1 >= ymin)
            return 1;
    }
    return 0;
}

int rf_forest_covers(const rf_forest *f, double x, double y)
{
    return f->polygon.n == 0 || rf_point_in_polygon(f->polygon.xy, f->polygon.n, x, y);
}

int rf_vegetation_accept(const rf_forest *fs, size_t n, double x, double y, double h_r,
                         double phi_r, double bound, double u)
{
    double target = u * bound, acc = 0.0;
    for (size_t i = 0; i < n; i++) {
        double share = forest_bound(&fs[i], phi_r);
        if (target < acc + share) {
            /* inside forest i's share: accepted with its true rate */
            if (!rf_forest_covers(&fs[i], x, y))
                return -1;
            return target - acc < rf_forest_rate(&fs[i], h_r, phi_r) ? (int)i : -1;
        }
        acc += share;
    }
    return -1;
}

static rf_vec3 horizontal(rf_vec3 v) { return rf_v3(v.x, v.y, 0.0); }

double rf_horizontal_length(rf_vec3 v, rf_vec3 a, double T)
{
    return rf_arc_length(horizontal(v), horizontal(a), T);
}

double rf_horizontal_time_at(rf_vec3 v, rf_vec3 a, double s, double T)
{
    rf_vec3 vh = horizontal(v), ah = horizontal(a);
    if (rf_v3_norm2(ah) == 0.0) {
        double sp = rf_v3_norm(vh);
        return sp > 0.0 ? fmin(s / sp, T) : T;
    }
    /* s(t) is increasing: Newton's method kept inside a shrinking bracket. */
    double lo = 0.0, hi = T, t = T * fmin(1.0, s / fmax(rf_horizontal_length(vh, ah, T), RF_QUAD_ZERO));
    for (int it = 0; it < RF_ODOMETER_MAX_ITER; it++) {
        double f = rf_arc_length(vh, ah, t) - s;
        if (f > 0)
            hi = t;
        else
            lo = t;
        double d = rf_v3_norm(rf_v3_madd(vh, t, ah));
        double tn = d > 0 ? t - f / d : 0.5 * (lo + hi);
        if (!(tn > lo && tn < hi))
            tn = 0.5 * (lo + hi);
        if (fabs(tn - t) <= RF_ODOMETER_REL * fmax(1.0, T) || hi - lo <= RF_ODOMETER_REL * fmax(1.0, T))
            return tn;
        t = tn;
    }
    return t;
}

rf_vec3 rf_tree_contact_normal(rf_vec3 vh, double q)
{
    rf_vec3 d = rf_v3_unit(rf_v3(vh.x, vh.y, 0.0));
    rf_vec3 side = rf_v3(-d.y, d.x, 0.0);
    /* the centre meets the stem at distance R, offset q R sideways: it is
     * sqrt(1 - q^2) R behind the stem along the motion */
    return rf_v3_add(rf_v3_scale(d, -sqrt(fmax(0.0, 1.0 - q * q))), rf_v3_scale(side, q));
}
