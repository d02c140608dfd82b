/* fixed_step.c - the fixed-step baseline: the paper's successive integration over time.
 *
 * The same rock, the same impact law (Eq. 8) and the same surface laws as the exact
 * engine, advanced with semi-implicit Euler steps of dt.  Contact is detected per step
 * as the paper does (Eq. 6-7): the face under the centre, penetration of its plane by
 * the sphere.  A penetrating rock is put back on the plane; an approaching one gets an
 * impact, and a rebound below the stay threshold leaves it on the surface, where the
 * next steps slide or roll it.  It converges to the exact engine as dt -> 0 with
 * first-order error, and its cost grows with the simulated time: it is the reference
 * for the speed-against-error report. */
#include "motion_private.h"

#include <math.h>

static rf_vec3 in_plane(rf_vec3 x, rf_vec3 n) { return rf_v3_madd(x, -rf_v3_dot(x, n), n); }

/* Path point and bookkeeping at an event of the stepping. */
static void step_event(rf_motion *m) { rf_motion_event(m); }

int rf_simulate_fixed_step(rf_motion *m)
{
    const rf_terrain *t = m->terrain;
    const double dt = m->scene->sim->dt > 0 ? m->scene->sim->dt : 1e-3;
    const double stop = m->scene->sim->stop_speed;
    const double tol = 1e-9;
    int on = 0; /* on the surface of face m->sup.tri[0]; m->sup.n follows it (tree hits read it) */
    m->sup.n = 0;
    for (;;) {
        if (m->s.t >= m->t_end)
            return RF_END_MAX_TIME;
        double h = fmin(dt, m->t_end - m->s.t);
        /* Eq. 6: the face under the centre */
        int32_t tri = rf_terrain_locate(t, m->s.p.x, m->s.p.y);
        if (tri < 0)
            return RF_END_EXITED;
        const rf_triangle *T = &t->tri[tri];
        double gap = rf_v3_dot(T->n, m->s.p) - T->d - m->rho; /* Eq. 7 */
        rf_vec3 p0 = m->s.p, v0 = m->s.v;
        if (on && gap <= tol) {
            if (m->sup.tri[0] != tri) {
                if (T->zone != m->sup.zone)
                    rf_support_draw(m, tri);
                m->sup.tri[0] = tri;
                m->s.v = in_plane(m->s.v, T->n);
            }
            rf_vec3 n = T->n;
            rf_vec3 u = rf_v3(0, 0, 0);
            if (!m->point) {
                u = in_plane(rf_v3_add(m->s.v, rf_v3_cross(m->s.w, rf_v3_scale(n, -m->rho))), n);
                if (!m->sup.rolling && rf_v3_norm(u) <= RF_SLIP_EPS)
                    m->sup.rolling = 1;
                if (m->sup.rolling)
                    u = rf_v3(0, 0, 0);
            }
            double speed = rf_v3_norm(m->s.v);
            if (speed <= stop && (m->point || m->sup.rolling) && rf_surface_holds(m))
                return RF_END_REST;
            rf_vec3 du;
            rf_vec3 a = rf_surface_accel(m, n, m->s.v, u, &du);
            rf_vec3 v1 = rf_v3_madd(m->s.v, h, a);
            if (m->point || m->sup.rolling) {
                /* friction stops the rock, it does not push it back */
                if (speed > 0 && rf_v3_dot(v1, m->s.v) < 0)
                    v1 = rf_v3(0, 0, 0);
            } else {
                rf_vec3 u1 = rf_v3_madd(u, h, du);
                if (rf_v3_dot(u1, u) <= 0) {
                    u1 = rf_v3(0, 0, 0);
                    m->sup.rolling = 1;
                }
                u = u1;
            }
            m->s.v = in_plane(v1, n);
            m->s.p = rf_v3_madd(m->s.p, h, m->s.v);
            if (!m->point) {
                double wn = rf_v3_dot(m->s.w, n);
                rf_vec3 wt = rf_v3_scale(rf_v3_cross(n, rf_v3_sub(m->s.v, u)), 1.0 / m->rho);
                m->s.w = rf_v3_madd(wt, wn, n);
            }
        } else {
            on = 0;
            m->sup.n = 0;
            m->s.v.z -= RF_GRAVITY * h;
            m->s.p = rf_v3_madd(m->s.p, h, m->s.v);
        }
        m->s.t += h;
        /* records along the step */
        rf_arc arc = {p0, v0, rf_v3_scale(rf_v3_sub(m->s.v, v0), 1.0 / h)};
        rf_vec3 pe = m->s.p, ve = m->s.v;
        m->s.p = p0;
        m->s.v = v0;
        m->s.t -= h;
        double ts = rf_scene_horizon(m, &arc, h);
        if (m->scene_pending && ts < h) {
            rf_motion_advance(m, &arc, ts);
            int end = rf_scene_event(m);
            if (end >= 0)
                return end;
            on = m->sup.n > 0; /* a tree may throw the rock up off the surface */
            continue;
        }
        rf_motion_advance(m, &arc, h);
        m->s.p = pe;
        m->s.v = ve;
        /* Eq. 6-7 at the new position: penetration, then impact or contact */
        int32_t tri2 = rf_terrain_locate(t, m->s.p.x, m->s.p.y);
        if (tri2 < 0) {
            step_event(m);
            return RF_END_EXITED;
        }
        const rf_triangle *T2 = &t->tri[tri2];
        double gap2 = rf_v3_dot(T2->n, m->s.p) - T2->d - m->rho;
        if (gap2 < 0) {
            m->s.p = rf_v3_madd(m->s.p, -gap2, T2->n);
            double vn = rf_v3_dot(m->s.v, T2->n);
            int was_on = on;
            if (vn < -RF_APPROACH_EPS) {
                double e0 = rf_motion_energy(m);
                double rebound = rf_impact(m, tri2, T2->n, NULL);
                m->rec->n_impacts++;
                if (m->sink && m->sink->impact)
                    m->sink->impact(m->sink->ctx, m->s.t, e0 / 1000.0, rf_motion_energy(m) / 1000.0, -vn);
                on = rebound < m->v_stay;
            } else {
                on = 1;
            }
            if (on) {
                m->s.v = in_plane(m->s.v, T2->n);
                if (!was_on || T2->zone != m->sup.zone)
                    rf_support_draw(m, tri2);
                m->sup.n = 1;
                m->sup.tri[0] = tri2;
                if (!m->point) {
                    rf_vec3 u = in_plane(rf_v3_add(m->s.v, rf_v3_cross(m->s.w, rf_v3_scale(T2->n, -m->rho))), T2->n);
                    m->sup.rolling = rf_v3_norm(u) <= RF_SLIP_EPS;
                }
            } else {
                m->sup.n = 0;
            }
            if (!was_on || !on)
                step_event(m);
        } else if (on && gap2 > tol) {
            on = 0; /* the face fell away: flight */
            m->sup.n = 0;
            step_event(m);
        }
    }
}
