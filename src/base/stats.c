/* stats.c - simulated stop points against measured ones: quantiles, KS distance,
 * hulls, envelopes and their agreement (stats.h). */
#include "base/stats.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/tolerances.h"
#include "base/util.h"

/* ---- statistics ---------------------------------------------------------------- */

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

double rf_percentile_sorted(const float *v, size_t n, double q)
{
    if (n == 0)
        return NAN;
    size_t rank = (size_t)ceil(q * (double)n); /* 1-based */
    if (rank < 1)
        rank = 1;
    if (rank > n)
        rank = n;
    return v[rank - 1];
}

double rf_percentile_nearest_rank(float *v, size_t n, double q)
{
    if (n > 0)
        qsort(v, n, sizeof *v, cmp_float);
    return rf_percentile_sorted(v, n, q);
}


double rf_quantile(const double *sorted, size_t n, double q)
{
    if (n == 0)
        return NAN;
    double h = (double)(n - 1) * q;
    size_t lo = (size_t)floor(h);
    if (lo >= n - 1)
        return sorted[n - 1];
    return sorted[lo] + (h - (double)lo) * (sorted[lo + 1] - sorted[lo]);
}

double rf_ks_distance(const double *a, size_t n, const double *b, size_t m)
{
    size_t i = 0, j = 0;
    double d = 0.0;
    while (i < n && j < m) {
        /* step past every value equal to the smaller of the two, in both samples */
        double x = a[i] < b[j] ? a[i] : b[j];
        while (i < n && a[i] <= x)
            i++;
        while (j < m && b[j] <= x)
            j++;
        double gap = fabs((double)i / (double)n - (double)j / (double)m);
        if (gap > d)
            d = gap;
    }
    return d;
}

/* ---- hulls --------------------------------------------------------------------- */

static int cmp_xy(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* > 0 when o, a, b turn counter-clockwise */
static double cross(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

size_t rf_convex_hull(const double *xy, size_t n, double *hull)
{
    if (n == 0)
        return 0;
    double *p = malloc(2 * n * sizeof *p);
    if (!p)
        return 0;
    memcpy(p, xy, 2 * n * sizeof *p);
    qsort(p, n, 2 * sizeof *p, cmp_xy);
    /* Andrew's monotone chain: the lower chain left to right, the upper right to left */
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        while (k >= 2 && cross(hull + 2 * (k - 2), hull + 2 * (k - 1), p + 2 * i) <= 0)
            k--;
        hull[2 * k] = p[2 * i], hull[2 * k + 1] = p[2 * i + 1];
        k++;
    }
    for (size_t i = n - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull + 2 * (k - 2), hull + 2 * (k - 1), p + 2 * i) <= 0)
            k--;
        hull[2 * k] = p[2 * i], hull[2 * k + 1] = p[2 * i + 1];
        k++;
    }
    free(p);
    /* the chain closes on its first point; all points equal leave one */
    if (k > 1)
        k--;
    if (k == 2 && hull[0] == hull[2] && hull[1] == hull[3])
        k = 1;
    return k;
}

int rf_hull_contains(const double *hull, size_t nh, double x, double y, double tol)
{
    const double q[2] = {x, y};
    if (nh == 0)
        return 0;
    if (nh == 1)
        return hypot(x - hull[0], y - hull[1]) <= tol;
    if (nh == 2) {
        double ex = hull[2] - hull[0], ey = hull[3] - hull[1];
        double len2 = ex * ex + ey * ey;
        double s = ((x - hull[0]) * ex + (y - hull[1]) * ey) / len2;
        s = s < 0 ? 0 : (s > 1 ? 1 : s);
        return hypot(x - hull[0] - s * ex, y - hull[1] - s * ey) <= tol;
    }
    for (size_t i = 0; i < nh; i++) {
        const double *a = hull + 2 * i, *b = hull + 2 * ((i + 1) % nh);
        double len = hypot(b[0] - a[0], b[1] - a[1]);
        if (cross(a, b, q) < -tol * len)
            return 0;
    }
    return 1;
}

size_t rf_envelope(const double *xy, size_t n, double keep, double *hull)
{
    if (n == 0)
        return 0;
    double mx = 0, my = 0;
    for (size_t i = 0; i < n; i++)
        mx += xy[2 * i], my += xy[2 * i + 1];
    mx /= (double)n, my /= (double)n;
    double sxx = 0, sxy = 0, syy = 0;
    for (size_t i = 0; i < n; i++) {
        double dx = xy[2 * i] - mx, dy = xy[2 * i + 1] - my;
        sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
    }
    double det = sxx * syy - sxy * sxy;
    double *d = malloc(n * sizeof *d), *sorted = malloc(n * sizeof *sorted);
    double *kept = malloc(2 * n * sizeof *kept);
    size_t nk = 0, nh = 0;
    if (d && sorted && kept) {
        for (size_t i = 0; i < n; i++) {
            double dx = xy[2 * i] - mx, dy = xy[2 * i + 1] - my;
            /* the squared Mahalanobis distance (up to a common factor); the Euclidean
             * one when the points are collinear or equal */
            d[i] = det > 0 ? (syy * dx * dx - 2 * sxy * dx * dy + sxx * dy * dy) / det
                           : dx * dx + dy * dy;
            sorted[i] = d[i];
        }
        qsort(sorted, n, sizeof *sorted, rf_cmp_double);
        size_t want = (size_t)ceil(keep * (double)n);
        if (want < 1)
            want = 1;
        if (want > n)
            want = n;
        double limit = sorted[want - 1];
        for (size_t i = 0; i < n; i++)
            if (d[i] <= limit)
                kept[2 * nk] = xy[2 * i], kept[2 * nk + 1] = xy[2 * i + 1], nk++;
        nh = rf_convex_hull(kept, nk, hull);
    }
    free(d);
    free(sorted);
    free(kept);
    return nh;
}

/* ---- agreement ----------------------------------------------------------------- */

static void mean_sd(const double *v, size_t n, double *mean, double *sd)
{
    double s = 0, s2 = 0;
    for (size_t i = 0; i < n; i++)
        s += v[i];
    *mean = s / (double)n;
    for (size_t i = 0; i < n; i++)
        s2 += (v[i] - *mean) * (v[i] - *mean);
    *sd = n > 1 ? sqrt(s2 / (double)(n - 1)) : 0.0;
}

/* Runout and lateral offset of n points in the frame (x0, y0, direction ux, uy). */
static void to_frame(const double *xy, size_t n, double x0, double y0, double ux, double uy,
                     double *runout, double *lateral)
{
    for (size_t i = 0; i < n; i++) {
        double dx = xy[2 * i] - x0, dy = xy[2 * i + 1] - y0;
        runout[i] = hypot(dx, dy);
        lateral[i] = ux * dy - uy * dx;
    }
}

double rf_w1_distance(const double *a, size_t n, const double *b, size_t m)
{
    /* walk both samples in order: between consecutive values x the distribution
     * functions are constant at i / n and j / m */
    size_t i = 0, j = 0;
    double area = 0.0, x = fmin(a[0], b[0]);
    while (i < n || j < m) {
        double next = j >= m || (i < n && a[i] <= b[j]) ? a[i] : b[j];
        area += fabs((double)i / (double)n - (double)j / (double)m) * (next - x);
        x = next;
        if (i < n && a[i] == next)
            i++;
        else
            j++;
    }
    return area;
}

/* IQR / 1.349 of n values sorted ascending: a normal sample's sd, robust to outliers. */
static double robust_sigma(const double *sorted, size_t n)
{
    return (rf_quantile(sorted, n, 0.75) - rf_quantile(sorted, n, 0.25)) / 1.349;
}

int rf_agreement_compute(const double *meas, size_t nm, const double *sim, size_t ns, double x0,
                         double y0, rf_agreement *out)
{
    memset(out, 0, sizeof *out);
    if (nm == 0 || ns == 0)
        return -1;
    /* the mean direction of the measured stops from the release centre */
    double mx = 0, my = 0;
    for (size_t i = 0; i < nm; i++)
        mx += meas[2 * i] - x0, my += meas[2 * i + 1] - y0;
    double ml = hypot(mx, my);
    double ux = ml > 0 ? mx / ml : 1.0, uy = ml > 0 ? my / ml : 0.0;
    double *rm = malloc(nm * sizeof *rm), *lm = malloc(nm * sizeof *lm);
    double *rs = malloc(ns * sizeof *rs), *ls = malloc(ns * sizeof *ls);
    double *hull = malloc(2 * (ns + 1) * sizeof *hull);
    int rc = -1;
    if (rm && lm && rs && ls && hull) {
        to_frame(meas, nm, x0, y0, ux, uy, rm, lm);
        to_frame(sim, ns, x0, y0, ux, uy, rs, ls);
        mean_sd(lm, nm, &out->lateral_mean_meas, &out->lateral_sd_meas);
        mean_sd(ls, ns, &out->lateral_mean_sim, &out->lateral_sd_sim);
        qsort(rm, nm, sizeof *rm, rf_cmp_double);
        qsort(rs, ns, sizeof *rs, rf_cmp_double);
        qsort(lm, nm, sizeof *lm, rf_cmp_double);
        qsort(ls, ns, sizeof *ls, rf_cmp_double);
        out->ks_lateral = rf_ks_distance(lm, nm, ls, ns);
        out->w1_runout = rf_w1_distance(rm, nm, rs, ns);
        out->w1_lateral = rf_w1_distance(lm, nm, ls, ns);
        double rmean;
        mean_sd(rm, nm, &rmean, &out->runout_sd_meas);
        out->lateral_rsigma_meas = robust_sigma(lm, nm);
        out->lateral_rsigma_sim = robust_sigma(ls, ns);
        const double q[3] = {0.05, 0.5, 0.95};
        for (int k = 0; k < 3; k++) {
            out->runout_meas[k] = rf_quantile(rm, nm, q[k]);
            out->runout_sim[k] = rf_quantile(rs, ns, q[k]);
        }
        out->ks = rf_ks_distance(rm, nm, rs, ns);
        out->ks_crit = 1.358 * sqrt((double)(nm + ns) / ((double)nm * (double)ns));
        size_t nh = rf_envelope(sim, ns, 0.95, hull);
        size_t in = 0;
        for (size_t i = 0; i < nm; i++)
            in += (size_t)rf_hull_contains(hull, nh, meas[2 * i], meas[2 * i + 1], RF_HULL_TOL);
        out->inside = (double)in / (double)nm;
        out->n_sim = ns;
        rc = 0;
    }
    free(rm);
    free(lm);
    free(rs);
    free(ls);
    free(hull);
    return rc;
}
