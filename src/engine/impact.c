/* impact.c - the impact law (Eq. 8) and the transfers of a slow rock between faces.
 *
 * Impact: contact normal n, e_n and mu drawn per impact from the zone's surface.  The
 * normal impulse reverses the normal velocity with restitution e_n; the tangential
 * Coulomb impulse reduces the slip of the contact point and stops at rolling.  Both
 * only remove kinetic energy.
 *
 * Pivot: a slow sphere that reaches a convex edge or vertex rolls over it onto the
 * next face.  The roll about the edge is short (the angle between the faces) and is
 * taken as instantaneous: the centre moves along the arc of radius r about the edge
 * from q + r u to q + r n_to, and the total energy (kinetic plus potential) is
 * conserved. */
#include "engine/impact.h"

#include <math.h>

#include "engine/rock.h"

static const rf_surface *surface_of(const rf_motion *m, int32_t tri)
{
    const rf_terrain *t = m->terrain;
    int32_t z = t->tri[tri].zone;
    if (z < 0 || (size_t)z >= t->nzones)
        z = 0;
    return &t->zones[z].surface;
}

void rf_support_draw(rf_motion *m, int32_t tri)
{
    const rf_surface *s = surface_of(m, tri);
    m->sup.zone = m->terrain->tri[tri].zone;
    m->sup.mu = rf_draw_truncated(m->rng, s->friction, 0.0, INFINITY);
    m->sup.mu_r = rf_draw_truncated(m->rng, s->rolling, 0.0, INFINITY);
}

double rf_impact(rf_motion *m, int32_t tri, rf_vec3 n)
{
    const rf_surface *s = surface_of(m, tri);
    double e = rf_draw_truncated(m->rng, s->restitution, 0.0, 1.0);
    double mu = rf_draw_truncated(m->rng, s->friction, 0.0, INFINITY);
    return rf_impact_apply(m, n, e, mu);
}

void rf_impact_count(rf_motion *m, double e0, double vin)
{
    if (!(vin > RF_APPROACH_EPS))
        return;
    m->rec->n_impacts++;
    if (m->sink && m->sink->impact)
        m->sink->impact(m->sink->ctx, m->s.t, e0 / 1000.0, rf_motion_energy(m) / 1000.0, vin);
}

double rf_impact_apply(rf_motion *m, rf_vec3 n, double e, double mu)
{
    const rf_body *b = m->body;
    rf_vec3 v = m->s.v, w = m->s.w;
    double vn = rf_v3_dot(v, n);
    if (vn >= 0.0)
        return vn;
    /* Eq. 8, normal: v_n' = -e_n v_n, J_n = m (1 + e_n) |v_n| */
    double jn = b->mass * (1.0 + e) * (-vn);
    rf_vec3 vt = rf_v3_madd(v, -vn, n);
    rf_vec3 jt = rf_v3(0, 0, 0);
    if (m->point) {
        /* point mass: |J_t| <= mu J_n, at most stopping the tangential motion */
        double ut = rf_v3_norm(vt);
        double cap = b->mass * ut;
        double mag = fmin(mu * jn, cap);
        if (ut > 0)
            jt = rf_v3_scale(vt, -mag / ut);
    } else {
        /* Eq. 8a-b: slip of the contact point u = v_t + w x (-r n); Coulomb impulse
         * opposite u, capped where the slip vanishes (rolling): |J_t| <= |u| /
         * (1/m + r^2/I) = 2/7 m |u| for the solid sphere. */
        rf_vec3 u = rf_v3_add(vt, rf_v3_cross(w, rf_v3_scale(n, -m->rho)));
        u = rf_v3_madd(u, -rf_v3_dot(u, n), n);
        double ul = rf_v3_norm(u);
        double cap = ul / (1.0 / b->mass + m->rho * m->rho / b->inertia);
        double mag = fmin(mu * jn, cap);
        if (ul > 0)
            jt = rf_v3_scale(u, -mag / ul);
        /* delta omega = r (-n) x J_t / I */
        m->s.w = rf_v3_add(w, rf_v3_scale(rf_v3_cross(rf_v3_scale(n, -m->rho), jt), 1.0 / b->inertia));
    }
    m->s.v = rf_v3_add(v, rf_v3_scale(rf_v3_add(rf_v3_scale(n, jn), jt), 1.0 / b->mass));
    return e * (-vn);
}

/* The centre's arc of a roll about q onto a face of normal n: u(th) = u0 cos th +
 * w sin th for th in [0, ang], from over q (u0) to over the face (n); returns ang. */
static double pivot_arc(const rf_motion *m, rf_vec3 q, rf_vec3 n, rf_vec3 *u0, rf_vec3 *w)
{
    *u0 = rf_v3_unit(rf_v3_sub(m->s.p, q));
    if (w) {
        *w = rf_v3_madd(n, -rf_v3_dot(n, *u0), *u0);
        double wl = rf_v3_norm(*w);
        if (wl > 0)
            *w = rf_v3_scale(*w, 1.0 / wl);
    }
    return atan2(rf_v3_norm(rf_v3_cross(*u0, n)), rf_v3_dot(*u0, n));
}

double rf_pivot_rise(const rf_motion *m, rf_vec3 q, rf_vec3 n)
{
    rf_vec3 u0, w;
    double ang = pivot_arc(m, q, n, &u0, &w);
    /* z(th) = u0.z cos th + w.z sin th is highest at th = atan2(w.z, u0.z) */
    double top = atan2(w.z, u0.z);
    double zmax = top > 0 && top < ang ? hypot(u0.z, w.z) : fmax(u0.z, n.z);
    return m->rho * fmax(0.0, zmax - u0.z);
}

int rf_pivot(rf_motion *m, rf_vec3 q, int32_t to)
{
    const rf_body *b = m->body;
    const rf_triangle *T = &m->terrain->tri[to];
    rf_vec3 n = T->n;
    rf_vec3 c_new = rf_v3_madd(q, m->rho, n);
    double e = rf_kinetic_energy(b, m->s.v, m->s.w) + b->mass * RF_GRAVITY * (m->s.p.z - c_new.z);
    if (!(e > 0.0))
        return -1;
    rf_vec3 dir = rf_v3_madd(m->s.v, -rf_v3_dot(m->s.v, n), n);
    if (!(rf_v3_norm(dir) > 1e-12)) {
        dir = rf_v3(n.x * n.z, n.y * n.z, n.z * n.z - 1.0); /* fall line */
    }
    double dl = rf_v3_norm(dir);
    dir = dl > 0 ? rf_v3_scale(dir, 1.0 / dl) : dir;
    /* after the roll the sphere rolls on `to`: e = 1/2 (m + I / r^2) s^2 */
    double s = sqrt(2.0 * e / (b->mass + b->inertia / (m->rho * m->rho)));
    /* the centre's arc about q: its length, and samples along it */
    rf_vec3 u0;
    double ang = pivot_arc(m, q, n, &u0, NULL);
    m->rec->path_length_m += m->rho * ang;
    const rf_sink *sk = m->sink;
    if (sk && sk->sample && sk->sample_spacing > 0 && ang > 0) {
        int steps = (int)ceil(m->rho * ang / sk->sample_spacing);
        double ekj = rf_motion_energy(m) / 1000.0;
        for (int k = 0; k <= steps; k++) {
            double f = (double)k / steps;
            /* spherical interpolation between u0 and n */
            double a0 = sin((1 - f) * ang) / sin(ang), a1 = sin(f * ang) / sin(ang);
            rf_vec3 u = rf_v3_add(rf_v3_scale(u0, a0), rf_v3_scale(n, a1));
            rf_vec3 p = rf_v3_madd(q, m->rho, u);
            rf_motion_sample(m, p, m->s.v, ekj);
        }
        m->sample_acc = 0.0;
    }
    m->s.p = c_new;
    m->s.v = rf_v3_scale(dir, dl > 0 ? s : 0.0);
    m->s.w = rf_v3_scale(rf_v3_cross(n, m->s.v), 1.0 / m->rho);
    return 0;
}
