/* impact.c - every impact of the rock (Eq. 8 on the slope and on stems; the walls of
 * the centre mode) and the transfers of a slow rock between faces.
 *
 * Impact: one function, rf_impact, for every kind (rf_impact_kind), with one place
 * that draws the coefficients (draw_coefficients): e_n, and mu where the law takes
 * it, from the zone's surface or the forest, in that order.  Eq. 8: the normal
 * impulse reverses the normal velocity with restitution e_n; the tangential Coulomb
 * impulse reduces the slip of the contact point and stops at rolling.  Both only
 * remove kinetic energy.  A zone may take the rt law instead (tangential restitution,
 * rt_law) and tilt the slope's contact normal by its roughness (roughness.c), both
 * opt-in; without them no random number is drawn beyond Eq. 8's.
 *
 * Pivot: a slow sphere that reaches a convex edge or vertex rolls over it onto the
 * next face.  The roll about the edge is short (the angle between the faces) and is
 * taken as instantaneous: the centre moves along the arc of radius r about the edge
 * from q + r u to q + r n_to, and the total energy (kinetic plus potential) is
 * conserved. */
#include "engine/impact.h"

#include <math.h>

#include "engine/geometry.h"
#include "engine/rock.h"
#include "engine/roughness.h"

/* The surface of triangle tri's zone (zone 0 for a triangle without one). */
static const rf_surface *surface_of(const rf_motion *m, int32_t tri)
{
    const rf_terrain *t = m->cfg.terrain;
    int32_t z = rf_tri_zone(t, tri);
    if (z < 0 || (size_t)z >= t->nzones)
        z = 0;
    return &t->zones[z].surface;
}

void rf_support_draw(rf_motion *m, int32_t tri)
{
    const rf_surface *s = surface_of(m, tri);
    m->rock.sup.zone = rf_tri_zone(m->cfg.terrain, tri);
    m->rock.sup.mu = rf_draw_truncated(m->rng, s->friction, 0.0, INFINITY);
    m->rock.sup.mu_r = rf_draw_truncated(m->rng, s->rolling, 0.0, INFINITY);
}

/* The coefficients of one impact. */
typedef struct impact_coeffs {
    double e, mu, rt;
} impact_coeffs;

/* The one place an impact's coefficients are drawn: e_n in [0, 1], then mu >= 0 where
 * the kind's law takes it (slope under Eq. 8, and tree), or R_t in [0, 1] instead (slope
 * under the rt law); a wall's reflection takes e_n alone, its meeting along it
 * nothing. */
static impact_coeffs draw_coefficients(rf_motion *m, const rf_impact_site *site)
{
    impact_coeffs k = {0.0, 0.0, 0.0};
    rf_dist e, mu;
    int rt = 0;
    switch (site->kind) {
    case RF_IMPACT_SLOPE:
    case RF_IMPACT_WALL: {
        const rf_surface *s = surface_of(m, site->id);
        e = s->restitution, mu = s->friction;
        if (site->kind == RF_IMPACT_SLOPE && s->law == RF_IMPACT_RT)
            mu = s->tangential, rt = 1;
        break;
    }
    case RF_IMPACT_TREE: {
        const rf_forest *f = &m->cfg.scene->forests[site->id];
        e = f->restitution, mu = f->friction;
        break;
    }
    default:
        return k; /* RF_IMPACT_WALL_MEET: no coefficient */
    }
    k.e = rf_draw_truncated(m->rng, e, 0.0, 1.0);
    if (rt)
        k.rt = rf_draw_truncated(m->rng, mu, 0.0, 1.0);
    else if (site->kind != RF_IMPACT_WALL)
        k.mu = rf_draw_truncated(m->rng, mu, 0.0, INFINITY);
    return k;
}

/* An impact with approach speed vin (m/s; kinetic energy e0 J before it) counts and is
 * reported when the rock approached the surface; a touch at a grazing speed (the path
 * tangent to the face, as when a centre runs exactly along an edge line) changes
 * nothing and is not an impact. */
static void count_impact(rf_motion *m, double e0, double vin)
{
    if (!(vin > RF_APPROACH_EPS))
        return;
    m->book.rec->n_impacts++;
    if (m->book.sink && m->book.sink->impact)
        m->book.sink->impact(m->book.sink->ctx, m->rock.s.t, e0 / 1000.0,
                             rf_motion_energy(m) / 1000.0, vin);
}

/* The impact law (Eq. 8) with unit normal n (towards the centre), restitution e and
 * friction mu, on the current state.  Returns the rebound normal speed. */
static double impact_law(rf_motion *m, rf_vec3 n, double e, double mu)
{
    const rf_body *b = m->cfg.body;
    rf_vec3 v = m->rock.s.v, w = m->rock.s.w;
    double vn = rf_v3_dot(v, n);
    if (vn >= 0.0)
        return vn;
    /* Eq. 8, normal: v_n' = -e_n v_n, J_n = m (1 + e_n) |v_n| */
    double jn = b->mass * (1.0 + e) * (-vn);
    rf_vec3 vt = rf_v3_madd(v, -vn, n);
    rf_vec3 jt = rf_v3(0, 0, 0);
    if (m->cfg.point) {
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
        rf_vec3 u = rf_v3_add(vt, rf_v3_cross(w, rf_v3_scale(n, -m->cfg.rho)));
        u = rf_v3_madd(u, -rf_v3_dot(u, n), n);
        double ul = rf_v3_norm(u);
        double cap = ul / (1.0 / b->mass + m->cfg.rho * m->cfg.rho / b->inertia);
        double mag = fmin(mu * jn, cap);
        if (ul > 0)
            jt = rf_v3_scale(u, -mag / ul);
        /* delta omega = r (-n) x J_t / I */
        m->rock.s.w = rf_v3_add(w, rf_v3_scale(rf_v3_cross(rf_v3_scale(n, -m->cfg.rho), jt),
                                               1.0 / b->inertia));
    }
    m->rock.s.v = rf_v3_add(v, rf_v3_scale(rf_v3_add(rf_v3_scale(n, jn), jt), 1.0 / b->mass));
    return e * (-vn);
}

/* The tangential-restitution law (RF_IMPACT_RT) with unit normal n, restitution e and
 * tangential restitution rt, on the current state; returns the rebound normal speed.
 * Normal as Eq. 8: v_n' = -e_n v_n.  Tangential (RocFall, Stevens 1998, and Rockyfor3D,
 * Dorren 2016: v_t' = R_t v_t): the centre's tangential velocity is scaled by R_t, and
 * the sphere leaves rolling on the surface (w' = w_n n + n x v_t' / r, the spin about n
 * kept), as RocFall's rigid-body rebound does.  The centre's velocity, not the contact
 * point's slip, is scaled: scaling the slip can take no more than Eq. 8's rolling cap
 * (a sphere keeps 5/7 of its tangential speed), the loss this law exists to exceed.
 * Energy: where rolling at R_t v_t needs more than the tangential and rotational
 * energy before, m |v_t|^2 + I |w_t|^2 (a sphere without spin, R_t > sqrt(5/7)), v_t' is
 * the rolling speed that energy pays; so kinetic energy never rises.  The point mass:
 * v_t' = R_t v_t. */
static double rt_law(rf_motion *m, rf_vec3 n, double e, double rt)
{
    const rf_body *b = m->cfg.body;
    rf_vec3 v = m->rock.s.v;
    double vn = rf_v3_dot(v, n);
    if (vn >= 0.0)
        return vn;
    rf_vec3 vt0 = rf_v3_madd(v, -vn, n);
    rf_vec3 vt = rf_v3_scale(vt0, rt);
    double r = m->cfg.rho;
    if (!m->cfg.point && r > 0.0) {
        rf_vec3 w = m->rock.s.w;
        double wn = rf_v3_dot(w, n);
        double before = b->mass * rf_v3_norm2(vt0) + b->inertia * rf_v3_norm2(rf_v3_madd(w, -wn, n));
        double after = (b->mass + b->inertia / (r * r)) * rf_v3_norm2(vt);
        if (after > before)
            vt = rf_v3_scale(vt, sqrt(before / after));
        m->rock.s.w = rf_v3_madd(rf_v3_scale(rf_v3_cross(n, vt), 1.0 / r), wn, n);
    }
    m->rock.s.v = rf_v3_madd(vt, -e * vn, n);
    return e * (-vn);
}

/* A slope impact: the zone's law (Eq. 8 or rt) along the contact normal, tilted by the
 * zone's roughness (roughness.c) at a real bounce: an approach speed vin above v_stay,
 * the speed of a RF_STAY_HEIGHT hop, below which the rock stays on the surface anyway -
 * so a rock rolling across the grid's edges, meeting the next face at a speed below it,
 * is not deflected there.  No random number is drawn without roughness.  The rebound
 * speed returned decides the flight along the real normal n: after a tilted impact it
 * is the velocity's component along n, and never more than e_n vin, so the tilt never
 * launches a rock that the real normal keeps on the surface. */
static double slope_impact(rf_motion *m, const rf_impact_site *site, impact_coeffs k,
                           double vin)
{
    const rf_surface *s = surface_of(m, site->id);
    rf_vec3 n = site->n;
    int tilted = s->roughness > 0.0 && vin > m->cfg.v_stay &&
                 rf_rough_normal(m->rng, site->n, m->rock.s.v, s->roughness,
                                 m->cfg.body->radius, &n, NULL);
    double rebound = s->law == RF_IMPACT_RT ? rt_law(m, n, k.e, k.rt)
                                            : impact_law(m, n, k.e, k.mu);
    if (tilted)
        rebound = fmin(k.e * vin, rf_v3_dot(m->rock.s.v, site->n));
    return rebound;
}

/* Centre mode, a column's wall (Eq. 6-7: the face under the centre alone counts, and
 * the rock cannot pay the lift onto the next one): the velocity into the wall (along
 * site->n, approach speed site->vin) is reversed with restitution e_n.  Where the
 * reflected velocity leaves the rock against another wall (site->corner), the whole
 * horizontal velocity is reversed instead, which leaves the corner.  Returns the
 * approach speed. */
static double wall_law(rf_motion *m, const rf_impact_site *site, double e)
{
    double vin = site->vin;
    if (vin > 0) {
        rf_vec3 v = rf_v3_madd(m->rock.s.v, -(1.0 + e) * vin, site->n);
        if (site->corner(m, v, site->ctx)) {
            v = rf_v3(-e * m->rock.s.v.x, -e * m->rock.s.v.y, m->rock.s.v.z);
            vin = rf_v3_hnorm(m->rock.s.v);
        }
        m->rock.s.v = v;
    }
    return vin;
}

/* Centre mode, the rock on its face meets a wall along direction site->l: the part of
 * its velocity across the wall is taken (perfectly plastic); in a corner of two walls
 * (site->corner_stop) it stops.  A slipping sphere's slip across the wall is taken by
 * friction at its contact (its spin set, on the face of normal site->n): *u.  Returns
 * the approach speed. */
static double wall_meet_law(rf_motion *m, const rf_impact_site *site, rf_vec3 *u)
{
    rf_vec3 L = site->l;
    double s = rf_v3_dot(m->rock.s.v, L);
    double vin = rf_v3_norm(rf_in_plane(m->rock.s.v, L));
    m->rock.s.v = rf_v3_scale(L, s);
    *u = rf_v3(0, 0, 0);
    if (site->corner_stop) {
        m->rock.s.v = rf_v3(0, 0, 0);
        m->rock.s.w = rf_v3(0, 0, 0);
        m->rock.sup.rolling = 1;
        return vin + fabs(s);
    }
    if (site->slide) {
        *u = rf_in_plane(rf_slip_of(m, site->n), rf_v3_cross(site->n, L));
        rf_set_spin(m, site->n, *u);
    }
    return vin;
}

/* A tree's stem (Fig. 6b): Eq. 8 with the forest's coefficients, recorded as a tree
 * hit. */
static double tree_law(rf_motion *m, const rf_impact_site *site, impact_coeffs k)
{
    double e0 = rf_motion_energy(m), v0 = rf_v3_norm(m->rock.s.v);
    double vin = -rf_v3_dot(m->rock.s.v, site->n);
    double rebound = impact_law(m, site->n, k.e, k.mu);
    double e1 = rf_motion_energy(m);
    m->book.rec->n_tree_hits++;
    if (m->book.sink && m->book.sink->impact)
        m->book.sink->impact(m->book.sink->ctx, m->rock.s.t, e0 / 1000.0, e1 / 1000.0, vin);
    if (m->book.sink && m->book.sink->tree_hit) {
        rf_tree_hit_record r = {m->rock.s.t, m->rock.s.p, v0, rf_v3_norm(m->rock.s.v), (e0 - e1) / 1000.0};
        m->book.sink->tree_hit(m->book.sink->ctx, &r);
    }
    return rebound;
}

double rf_impact(rf_motion *m, const rf_impact_site *site, rf_impact_out *out)
{
    impact_coeffs k = draw_coefficients(m, site);
    if (site->kind == RF_IMPACT_TREE)
        return tree_law(m, site, k);
    double e0 = rf_motion_energy(m);
    double vin, rebound = 0.0;
    switch (site->kind) {
    case RF_IMPACT_SLOPE:
        vin = -rf_v3_dot(m->rock.s.v, site->n);
        rebound = slope_impact(m, site, k, vin);
        break;
    case RF_IMPACT_WALL:
        vin = wall_law(m, site, k.e);
        break;
    default:
        vin = wall_meet_law(m, site, &out->u);
        break;
    }
    count_impact(m, e0, vin);
    return rebound;
}

/* The centre's arc of a roll about q onto a face of normal n: u(th) = u0 cos th +
 * w sin th for th in [0, ang], from over q (u0) to over the face (n); returns ang. */
static double pivot_arc(const rf_motion *m, rf_vec3 q, rf_vec3 n, rf_vec3 *u0, rf_vec3 *w)
{
    *u0 = rf_v3_unit(rf_v3_sub(m->rock.s.p, q));
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
    return m->cfg.rho * fmax(0.0, zmax - u0.z);
}

int rf_pivot(rf_motion *m, rf_vec3 q, int32_t to)
{
    const rf_body *b = m->cfg.body;
    const rf_triangle *T = RF_FACE(m, to);
    rf_vec3 n = T->n;
    rf_vec3 c_new = rf_v3_madd(q, m->cfg.rho, n);
    double e = rf_kinetic_energy(b, m->rock.s.v, m->rock.s.w) +
               b->mass * RF_GRAVITY * (m->rock.s.p.z - c_new.z);
    if (!(e > 0.0))
        return -1;
    rf_vec3 dir = rf_v3_madd(m->rock.s.v, -rf_v3_dot(m->rock.s.v, n), n);
    if (!(rf_v3_norm(dir) > RF_VEC_ZERO)) {
        dir = rf_v3(n.x * n.z, n.y * n.z, n.z * n.z - 1.0); /* fall line */
    }
    double dl = rf_v3_norm(dir);
    dir = dl > 0 ? rf_v3_scale(dir, 1.0 / dl) : dir;
    /* after the roll the sphere rolls on `to`: e = 1/2 (m + I / r^2) s^2 */
    double s = sqrt(2.0 * e / (b->mass + b->inertia / (m->cfg.rho * m->cfg.rho)));
    /* the centre's arc about q: its length, and samples along it */
    rf_vec3 u0;
    double ang = pivot_arc(m, q, n, &u0, NULL);
    m->book.rec->path_length_m += m->cfg.rho * ang;
    const rf_sink *sk = m->book.sink;
    if (sk && sk->sample && sk->sample_spacing > 0 && ang > 0) {
        double ns = ceil(m->cfg.rho * ang / sk->sample_spacing);
        int steps = ns < RF_MAX_ARC_SAMPLES ? (int)ns : RF_MAX_ARC_SAMPLES;
        double ekj = rf_motion_energy(m) / 1000.0;
        for (int k = 0; k <= steps; k++) {
            double f = (double)k / steps;
            /* spherical interpolation between u0 and n */
            double a0 = sin((1 - f) * ang) / sin(ang), a1 = sin(f * ang) / sin(ang);
            rf_vec3 u = rf_v3_add(rf_v3_scale(u0, a0), rf_v3_scale(n, a1));
            rf_vec3 p = rf_v3_madd(q, m->cfg.rho, u);
            rf_motion_sample(m, p, m->rock.s.v, ekj);
        }
        m->book.sample_acc = 0.0;
    }
    m->rock.s.p = c_new;
    m->rock.s.v = rf_v3_scale(dir, dl > 0 ? s : 0.0);
    m->rock.s.w = rf_v3_scale(rf_v3_cross(n, m->rock.s.v), 1.0 / m->cfg.rho);
    return 0;
}
