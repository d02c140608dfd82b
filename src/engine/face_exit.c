/* face_exit.c - the rock's contact point leaves its face over an edge: onto a face in
 * the same plane (the path goes on), a concave edge (an impact on the next face), a
 * convex one (a flight, or a slow sphere's roll over it paid from the motion across
 * the edge), or off the terrain; and the crease's law, which ends the crease where a
 * normal force would pull. */
#include "engine/face_exit.h"

#include <math.h>
#include <string.h>

#include "engine/contact.h"
#include "engine/face_entry.h"
#include "engine/feature.h"
#include "engine/impact.h"
#include "engine/rock.h"
#include "engine/scene_events.h"
#include "engine/surface_law.h"

void rf_face_edges_setup(const rf_motion *m, const rf_triangle *T, rf_face_edges *fe)
{
    if (m->cfg.centre) {
        rf_column_edges(T, fe);
        return;
    }
    rf_vec3 P[3] = {T->a, T->b, T->c};
    rf_vec3 ab = rf_v3_sub(P[1], P[0]), ac = rf_v3_sub(P[2], P[0]);
    double sg = rf_v3_dot(rf_v3_cross(ab, ac), T->n) >= 0 ? 1.0 : -1.0;
    rf_vec3 lift = rf_v3_scale(T->n, m->cfg.rho);
    for (int k = 0; k < 3; k++) {
        rf_vec3 A = P[k], B = P[(k + 1) % 3];
        rf_vec3 in = rf_v3_scale(rf_v3_cross(T->n, rf_v3_sub(B, A)), sg);
        fe->m[k] = rf_v3_unit(in);
        fe->o[k] = rf_v3_dot(fe->m[k], rf_v3_add(A, lift));
    }
}

/* 1 when p lies on edge k's line (within the length tolerance). */
int rf_on_edge(const rf_motion *m, const rf_face_edges *fe, int k, rf_vec3 p)
{
    return fabs(rf_v3_dot(fe->m[k], p) - fe->o[k]) <= m->cfg.tol_len;
}

/* Unit vector along edge k of F, from vertex k to vertex k + 1. */
rf_vec3 rf_edge_dir(const rf_triangle *F, int k)
{
    return rf_v3_unit(rf_v3_sub(rf_tri_vertex(F, k + 1), rf_tri_vertex(F, k)));
}

/* First time in [0, T] the contact point of the arc leaves the face, not over edge
 * `skip` (-1: none); T when it does not.  *edge receives the edge. */
double rf_exit_time(const rf_motion *m, const rf_face_edges *fe, const rf_arc *arc, double T,
                        int skip, int *edge)
{
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (k == skip)
            continue;
        double f[3] = {rf_v3_dot(fe->m[k], arc->p) - fe->o[k], rf_v3_dot(fe->m[k], arc->v),
                       0.5 * rf_v3_dot(fe->m[k], arc->a)};
        double r[3], t = INFINITY;
        double tol = m->cfg.tol_len;
        /* inside the edge by more than tol over all of [0, min(T, best)]: not left there */
        double fminv, fmaxv;
        rf_quadratic_range(f, 0.0, rf_fmin(T, best), &fminv, &fmaxv);
        if (fminv > tol)
            continue;
        if (f[0] < -tol && f[1] > RF_APPROACH_EPS)
            rf_quadratic_range(f, 0.0, T, &fminv, &fmaxv); /* coming back within T? */
        if (f[0] < -tol && (f[1] <= RF_APPROACH_EPS || fmaxv <= tol)) {
            t = 0.0; /* already beyond the edge and not coming back */
        } else if (rf_poly_entries(f, 2, 0.0, rf_fmin(T, best), tol, RF_APPROACH_EPS, r) > 0) {
            t = r[0];
        } else if (fabs(f[0]) <= tol && fabs(f[1]) <= RF_APPROACH_EPS && f[2] < -RF_EXIT_CURVE_EPS) {
            t = 0.0;
        }
        if (t < best) {
            best = t;
            *edge = k;
        }
    }
    return best < T ? best : T;
}

/* The edge of A whose ends are both vertices of B, or -1. */
int rf_shared_edge(const rf_triangle *A, const rf_triangle *B)
{
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            if (rf_same_feature(A, k | 4, B, j | 4))
                return k;
    return -1;
}

/* How a rock that reaches the edge of its face meets the next face `to` (not coplanar
 * with it): it rises into it (an impact; in centre mode also when the centre is below
 * its offset plane), the path goes on along it, or it falls away (in centre mode also
 * when the centre is above its offset plane).  Along the edge the acceleration acc
 * decides. */
typedef enum next_kind { RF_NEXT_IMPACT, RF_NEXT_ON, RF_NEXT_AWAY } next_kind;

static next_kind next_face(const rf_motion *m, int32_t to, rf_vec3 acc)
{
    const rf_triangle *Tn = RF_FACE(m, to);
    double vn = rf_v3_dot(m->rock.s.v, Tn->n);
    if (fabs(vn) <= RF_APPROACH_EPS) {
        /* moving along the edge: the acceleration decides */
        double an = rf_v3_dot(acc, Tn->n);
        if (fabs(an) > RF_ACCEL_EPS)
            vn = an > 0 ? INFINITY : -INFINITY;
    }
    if (m->cfg.centre) {
        /* over the next face the centre is above, on or below its offset plane */
        double gap = rf_v3_dot(Tn->n, m->rock.s.p) - Tn->d - m->cfg.rho;
        if (gap > m->cfg.tol_len)
            return RF_NEXT_AWAY;
        if (gap < -m->cfg.tol_len)
            return RF_NEXT_IMPACT;
    }
    if (vn < -RF_APPROACH_EPS)
        return RF_NEXT_IMPACT;
    return vn <= RF_APPROACH_EPS ? RF_NEXT_ON : RF_NEXT_AWAY;
}

/* The impact on the next face at a concave edge (the point model is put on it). */
static void impact_on_face(rf_motion *m, int32_t to)
{
    const rf_triangle *Tn = RF_FACE(m, to);
    rf_contact c;
    memset(&c, 0, sizeof c);
    c.tri = to;
    c.kind = RF_FEAT_FACE;
    c.n = Tn->n;
    c.point = rf_v3_madd(m->rock.s.p, -(rf_v3_dot(Tn->n, m->rock.s.p) - Tn->d), Tn->n);
    if (m->cfg.point)
        m->rock.s.p = c.point;
    rf_contact_resolve(m, &c);
}

/* The face across edge `edge` of face `from`, stepping over the edge's middle (-1:
 * none). */
int32_t rf_face_over_edge(const rf_terrain *t, int32_t from, int edge, const rf_face_edges *fe)
{
    const rf_triangle *F = RF_TRI(t, from);
    rf_vec3 mid = rf_v3_scale(rf_v3_add(rf_tri_vertex(F, edge), rf_tri_vertex(F, edge + 1)), 0.5);
    int32_t to = rf_face_beyond(t, from, mid, rf_v3_scale(fe->m[edge], -1.0));
    return to == from ? -1 : to;
}

int32_t rf_face_after(const rf_motion *m, int32_t from, int edge, const rf_face_edges *fe,
                      rf_vec3 q, rf_vec3 acc)
{
    const rf_terrain *t = m->cfg.terrain;
    rf_vec3 dir = m->rock.s.v;
    if (rf_v3_norm(dir) < RF_DIR_SPEED_EPS)
        dir = acc;
    if (rf_v3_hnorm(dir) < RF_VEC_ZERO)
        dir = rf_v3_scale(fe->m[edge], -1.0);
    int32_t to = rf_face_beyond(t, from, q, dir);
    if (to == from)
        to = rf_face_over_edge(t, from, edge, fe); /* numerically still inside */
    return to;
}

/* 1 when a sphere whose contact point q crosses an edge, moving across it at vp, can
 * roll over it onto the face of normal n: the rise of its centre on the way (over the
 * top of a ridge, or up onto a shoulder) is paid from the energy of the motion across
 * the edge (energy conserved, as rf_pivot); the motion along it does not turn the
 * sphere about it. */
static int climbs_over(const rf_motion *m, rf_vec3 q, rf_vec3 n, rf_vec3 vp)
{
    const rf_body *b = m->cfg.body;
    double mass = b->mass + (m->rock.sup.rolling ? b->inertia / (m->cfg.rho * m->cfg.rho) : 0.0);
    return 0.5 * mass * rf_v3_norm2(vp) >= rf_lift_cost(m, rf_v3(0, 0, rf_pivot_rise(m, q, n)));
}

/* The contact point crossed edge `edge` of the support face at the current state. */
rf_surface_end rf_leave_face(rf_motion *m, int slot, int edge, const rf_face_edges *fe,
                             rf_vec3 acc)
{
    const rf_terrain *t = m->cfg.terrain;
    int32_t from = m->rock.sup.tri[slot];
    const rf_triangle *F = RF_TRI(t, from);
    rf_vec3 q = m->cfg.centre ? m->rock.s.p : rf_v3_madd(m->rock.s.p, -m->cfg.rho, F->n);
    int32_t to = rf_face_after(m, from, edge, fe, q, acc);
    if (to < 0 && (m->cfg.point || m->cfg.centre))
        return RF_SURF_EXITED;
    if (m->rock.sup.n == 2) {
        int32_t other = m->rock.sup.tri[1 - slot];
        if (to >= 0 && rf_coplanar(F, RF_TRI(t, to), m->cfg.tol_len)) {
            m->rock.sup.tri[slot] = to;
            m->rock.sup.left = from;
            return RF_SURF_CONTINUE;
        }
        /* the crease goes on between the other face and the next one, or ends (also
         * over the terrain's edge): carry on on the other face */
        if (m->cfg.point && rf_try_crease(m, other, to) == 0)
            return RF_SURF_CONTINUE; /* a point moves on along the valley line */
        rf_crease_ends(m, other, from);
        return RF_SURF_CONTINUE;
    }
    if (to < 0) {
        rf_go_flight(m, from);
        return RF_SURF_FLIGHT;
    }
    const rf_triangle *Tn = RF_TRI(t, to);
    if (rf_coplanar(F, Tn, m->cfg.tol_len)) {
        rf_support_single(m, to, 0);
        m->rock.sup.left = from;
        return RF_SURF_CONTINUE;
    }
    next_kind next = next_face(m, to, acc);
    if (next == RF_NEXT_AWAY && rf_centre_edge_step_taken(m, to, Tn, rf_v3_scale(fe->m[edge], -1.0))) {
        if (rf_scene_at_once(m) >= 0)
            return RF_SURF_STOPPED;
        rf_centre_edge_step(m, to, Tn); /* the centre's offset planes step down at a concave edge */
        return RF_SURF_CONTINUE;
    }
    switch (next) {
    case RF_NEXT_IMPACT:
        if (rf_scene_at_once(m) >= 0)
            return RF_SURF_STOPPED;
        impact_on_face(m, to);
        return m->rock.sup.n == 0 ? RF_SURF_FLIGHT : RF_SURF_CONTINUE;
    case RF_NEXT_ON:
        rf_support_single(m, to, 0); /* tangent: the path continues on the next face */
        m->rock.sup.left = from;
        return RF_SURF_CONTINUE;
    case RF_NEXT_AWAY:
        break;
    }
    /* convex: the next face falls away */
    if (m->cfg.point || m->cfg.centre) {
        rf_go_flight(m, from);
        return RF_SURF_FLIGHT;
    }
    rf_vec3 e = rf_edge_dir(F, edge);
    rf_vec3 vp = rf_in_plane(m->rock.s.v, e);
    if (rf_v3_norm2(vp) >= m->cfg.rho * RF_GRAVITY * F->n.z) {
        rf_go_flight(m, from); /* fast enough to fly off the edge */
        return RF_SURF_FLIGHT;
    }
    if (climbs_over(m, q, Tn->n, vp)) {
        if (!rf_pivot_clear(m, q, to)) {
            rf_hop(m, F->n);
            return RF_SURF_FLIGHT;
        }
        if (rf_pivot(m, q, to) == 0) {
            rf_support_single(m, to, 0);
            m->rock.sup.rolling = 1;
            return RF_SURF_CONTINUE;
        }
    }
    /* cannot climb over: rolls back onto the face */
    rf_vec3 mo = rf_v3_scale(fe->m[edge], -1.0);
    double vo = rf_v3_dot(m->rock.s.v, mo);
    if (vo > 0) {
        m->rock.s.v = rf_v3_madd(m->rock.s.v, -2.0 * vo, mo);
        if (m->rock.sup.rolling)
            rf_set_spin(m, F->n, rf_v3(0, 0, 0));
    }
    return RF_SURF_CONTINUE;
}

rf_crease_kind rf_crease_law(rf_motion *m, rf_crease *cr)
{
    const rf_terrain *t = m->cfg.terrain;
    const rf_triangle *A = RF_TRI(t, m->rock.sup.tri[0]), *B = RF_TRI(t, m->rock.sup.tri[1]);
    double xA = 0.0, xB = 0.0; /* crease_forces may fail before setting them */
    rf_vec3 l;
    if (rf_crease_forces(A->n, B->n, &xA, &xB, &l) || xA < 0 || xB < 0) {
        rf_crease_ends(m, m->rock.sup.tri[xA < 0 ? 1 : 0], m->rock.sup.left);
        return RF_CREASE_ENDED;
    }
    double s = rf_v3_dot(m->rock.s.v, l);
    if (s < 0) {
        l = rf_v3_scale(l, -1.0);
        s = -s;
    }
    m->rock.s.v = rf_v3_scale(l, s);
    double gl = -RF_GRAVITY * l.z, N = xA + xB;
    int rolling = !m->cfg.point && m->rock.sup.rolling;
    if (rolling && (1.0 - rf_roll_factor(m->cfg.body, m->cfg.rho)) * fabs(gl) > m->rock.sup.mu * N)
        m->rock.sup.rolling = rolling = 0; /* friction cannot make it roll down the crease */
    double k = rolling ? rf_roll_factor(m->cfg.body, m->cfg.rho) : 1.0;
    double c = rolling ? m->rock.sup.mu_r : m->rock.sup.mu;
    cr->holds = fabs(gl) <= c * N;
    cr->rolling = rolling;
    if (s <= m->cfg.scene->sim->stop_speed && cr->holds)
        return RF_CREASE_REST;
    if (s == 0.0 && gl < 0) {
        l = rf_v3_scale(l, -1.0);
        gl = -gl;
    }
    cr->l = l;
    cr->s = s;
    cr->as = k * (gl - c * N);
    return RF_CREASE_MOVES;
}
