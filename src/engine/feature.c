/* feature.c - distances from a point to the terrain's faces, edges and vertices. */
#include "engine/feature.h"

#include <math.h>
#include <string.h>

#include "engine/contact.h"
#include "engine/geometry.h"

static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* ---- distances --------------------------------------------------------------------- */

double rf_feature_distance(const rf_terrain *t, const rf_contact *c, rf_vec3 p)
{
    const rf_triangle *T = RF_TRI(t, c->tri);
    switch (c->kind) {
    case RF_FEAT_FACE:
        return rf_v3_dot(T->n, p) - T->d;
    case RF_FEAT_EDGE: {
        rf_vec3 q = rf_v3_closest_on_segment(rf_tri_vertex(T, c->index), rf_tri_vertex(T, c->index + 1), p);
        return rf_v3_norm(rf_v3_sub(p, q));
    }
    default:
        return rf_v3_norm(rf_v3_sub(p, rf_tri_vertex(T, c->index)));
    }
}

double rf_closest_feature(rf_motion *m, rf_vec3 p, double reach, rf_contact *c)
{
    const rf_terrain *t = m->cfg.terrain;
    size_t n = rf_gather(m, p.x - reach, p.y - reach, p.x + reach, p.y + reach);
    double best = INFINITY;
    c->kind = RF_FEAT_EDGE;
    for (size_t k = 0; k < n; k++) {
        int32_t idx = m->ws->cand[k];
        const rf_triangle *T = RF_TRI(t, idx);
        rf_vec3 q = rf_triangle_closest_point(T, p);
        double d = rf_v3_norm(rf_v3_sub(p, q));
        double dplane = fabs(rf_v3_dot(T->n, p) - T->d);
        /* prefer a face over its own edges at the same distance */
        int face = fabs(d - dplane) <= m->cfg.tol_len;
        if (d < best - m->cfg.tol_len || (d <= best + m->cfg.tol_len && face && c->kind != RF_FEAT_FACE)) {
            best = dmin(best, d);
            c->t = 0;
            c->tri = idx;
            c->point = q;
            if (face) {
                c->kind = RF_FEAT_FACE;
                c->index = 0;
                c->n = T->n;
            } else {
                c->kind = RF_FEAT_EDGE;
                c->index = 0;
                for (int i = 0; i < 3; i++) {
                    if (rf_v3_norm(rf_v3_sub(q, rf_tri_vertex(T, i))) <= m->cfg.tol_len) {
                        c->kind = RF_FEAT_VERTEX;
                        c->index = i;
                        break;
                    }
                }
                if (c->kind == RF_FEAT_EDGE) {
                    double bd = INFINITY;
                    for (int i = 0; i < 3; i++) {
                        rf_vec3 qq = rf_v3_closest_on_segment(rf_tri_vertex(T, i), rf_tri_vertex(T, i + 1), p);
                        double dd = rf_v3_norm(rf_v3_sub(qq, q));
                        if (dd < bd)
                            bd = dd, c->index = i;
                    }
                }
                rf_vec3 dv = rf_v3_sub(p, q);
                c->n = d > 0 ? rf_v3_scale(dv, 1.0 / d) : T->n;
            }
        }
    }
    return best;
}

/* Widens [*lo, *hi] by the interval in which the vertical line through (x, y) meets
 * the set within rho of triangle T (T swept by the ball: its two offset faces, the
 * cylinders round its edges and the balls round its vertices; the set is convex, so
 * the pieces' intervals make one). */
static void vertical_overlap(const rf_triangle *T, double x, double y, double rho,
                             double *lo, double *hi)
{
    double r2 = rho * rho;
    for (int i = 0; i < 3; i++) {
        rf_vec3 a = rf_tri_vertex(T, i), b = rf_tri_vertex(T, i + 1);
        double ux = x - a.x, uy = y - a.y, u2 = ux * ux + uy * uy;
        if (u2 <= r2) {
            double h = sqrt(r2 - u2);
            *lo = dmin(*lo, a.z - h);
            *hi = dmax(*hi, a.z + h);
        }
        /* the cylinder: |w|^2 - (w.d)^2 / D = rho^2 for w = (ux, uy, s), quadratic in s */
        rf_vec3 d = rf_v3_sub(b, a);
        double H = d.x * d.x + d.y * d.y, D = H + d.z * d.z, ud = ux * d.x + uy * d.y;
        if (!(H > 0))
            continue;
        double disc = ud * ud * d.z * d.z - H * (D * u2 - ud * ud - r2 * D);
        if (!(disc >= 0))
            continue;
        double sq = sqrt(disc);
        for (int k = -1; k <= 1; k += 2) {
            double s = (ud * d.z + k * sq) / H, along = (ud + s * d.z) / D;
            if (along >= 0 && along <= 1) {
                *lo = dmin(*lo, a.z + s);
                *hi = dmax(*hi, a.z + s);
            }
        }
    }
    if (T->n.z > RF_NZ_MIN) {
        /* each offset face is met where the foot of the line's point lies in T (n.z
         * >= 0: the normals point up) */
        double zp = rf_triangle_z_at(T, x, y), dz = rho / T->n.z;
        if (rf_inside_closed(T, rf_v3_madd(rf_v3(x, y, zp + dz), -rho, T->n)))
            *hi = dmax(*hi, zp + dz);
        if (rf_inside_closed(T, rf_v3_madd(rf_v3(x, y, zp - dz), rho, T->n)))
            *lo = dmin(*lo, zp - dz);
    }
}

double rf_clear_height(rf_motion *m, rf_vec3 p)
{
    const rf_terrain *t = m->cfg.terrain;
    double rho = m->cfg.rho, z = p.z;
    size_t n = rf_gather(m, p.x - rho, p.y - rho, p.x + rho, p.y + rho);
    /* the lowest z >= p.z outside every triangle's interval: raised past each interval
     * it lies in until none is left (each pass clears at least one) */
    for (size_t pass = 0; pass <= n; pass++) {
        int moved = 0;
        for (size_t k = 0; k < n; k++) {
            double lo = INFINITY, hi = -INFINITY;
            vertical_overlap(RF_TRI(t, m->ws->cand[k]), p.x, p.y, rho, &lo, &hi);
            if (lo < z && z < hi) {
                z = hi;
                moved = 1;
            }
        }
        if (!moved)
            break;
    }
    return z;
}

int32_t rf_face_beyond(const rf_terrain *t, int32_t from, rf_vec3 q, rf_vec3 dir)
{
    double h = rf_v3_hnorm(dir);
    if (!(h > 0))
        return rf_terrain_locate(t, q.x, q.y);
    double ux = dir.x / h, uy = dir.y / h;
    double scale = 1.0 + dmax(fabs(q.x), fabs(q.y)) * RF_BEYOND_REL;
    int32_t idx = -1;
    for (double step = RF_BEYOND_STEP * scale; step < RF_BEYOND_MAX; step *= 10) {
        idx = rf_terrain_locate(t, q.x + step * ux, q.y + step * uy);
        if (idx != from)
            return idx;
    }
    return idx;
}
