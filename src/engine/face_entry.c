/* face_entry.c - the rock meets the terrain.
 *
 * A contact is an impact (Eq. 8, rf_impact); then the rock flies off when the
 * rebound's normal speed reaches v_stay (the speed of a RF_STAY_HEIGHT hop), lands on
 * the face or in a crease (both faces pressing on it), or, a slow sphere on a convex
 * edge or vertex, rolls over it onto the next face (rf_pivot, total energy conserved).
 * In centre mode (Eq. 6-7) a centre moving over a column closer to its face's plane
 * than r is lifted onto the offset plane, the lift paid from the kinetic energy;
 * where it cannot be paid the face is a wall (RF_IMPACT_WALL). */
#include "engine/face_entry.h"

#include <math.h>

#include "engine/feature.h"
#include "engine/contact.h"
#include "engine/geometry.h"
#include "engine/impact.h"
#include "engine/rock.h"
#include "engine/scene_events.h"
#include "engine/surface_law.h"

void rf_support_single(rf_motion *m, int32_t tri, int fresh)
{
    const rf_triangle *T = RF_FACE(m, tri);
    if (fresh || m->rock.sup.n == 0 || m->rock.sup.zone != T->zone)
        rf_support_draw(m, tri);
    m->rock.sup.n = 1;
    m->rock.sup.tri[0] = tri;
    m->rock.sup.tri[1] = -1;
    m->rock.sup.left = -1;
    /* on the offset plane, velocity tangent */
    m->rock.s.p = rf_v3_madd(m->rock.s.p, T->d + m->cfg.rho - rf_v3_dot(T->n, m->rock.s.p), T->n);
    m->rock.s.v = rf_in_plane(m->rock.s.v, T->n);
    m->rock.sup.rolling = 0;
    if (!m->cfg.point)
        rf_face_slip(m, T->n);
}

void rf_surface_enter(rf_motion *m, int32_t tri) { rf_support_single(m, tri, 1); }

/* The rock on face A meets face B gently: a crease when both faces press on it. */
int rf_try_crease(rf_motion *m, int32_t a, int32_t b)
{
    const rf_triangle *A = RF_FACE(m, a), *B = RF_FACE(m, b);
    if (a == b || rf_coplanar(A, B, m->cfg.tol_len))
        return -1;
    if (rf_v3_dot(m->rock.s.v, A->n) > m->cfg.v_stay)
        return -1; /* leaving A */
    double xA = 0.0, xB = 0.0; /* crease_forces may fail before setting them */
    rf_vec3 l;
    if (rf_crease_forces(A->n, B->n, &xA, &xB, &l) || xA < 0 || xB < 0)
        return -1;
    /* both faces touched: the centre lies on both offset planes */
    double s = rf_v3_dot(m->rock.s.v, l);
    m->rock.s.v = rf_v3_scale(l, s);
    rf_vec3 p = rf_crease_centre(A, B, m->cfg.rho, m->rock.s.p);
    if (rf_v3_norm(rf_v3_sub(p, m->rock.s.p)) > RF_CREASE_SNAP * rf_fmax(m->cfg.rho, RF_CREASE_SNAP))
        return -1;
    m->rock.s.p = p;
    if (m->rock.sup.n == 0 || m->rock.sup.zone != B->zone)
        rf_support_draw(m, b);
    int rolling = !m->cfg.point && m->rock.sup.n >= 1 && m->rock.sup.rolling;
    m->rock.sup.n = 2;
    m->rock.sup.tri[0] = a;
    m->rock.sup.tri[1] = b;
    m->rock.sup.left = -1;
    m->rock.sup.rolling = rolling;
    if (rolling) {
        rf_spin_law roll = rf_crease_roll(m);
        m->rock.s.w = rf_spin_at(&roll, m->cfg.rho, m->rock.s.v, 0.0);
    }
    return 0;
}

/* Landing gently on face tri (rebound below the stay threshold). */
static void land(rf_motion *m, int32_t tri)
{
    if (m->rock.sup.n == 1 && rf_try_crease(m, m->rock.sup.tri[0], tri) == 0)
        return;
    if (m->rock.sup.n == 2) {
        int32_t a = m->rock.sup.tri[0], b = m->rock.sup.tri[1];
        if (rf_try_crease(m, a, tri) == 0 || rf_try_crease(m, b, tri) == 0)
            return;
    }
    rf_support_single(m, tri, m->rock.sup.n == 0);
}

/* 1 when a sphere rolled over q onto face `to` would touch no other feature: the
 * roll is only taken where the two faces are all there is. */
int rf_pivot_clear(rf_motion *m, rf_vec3 q, int32_t to)
{
    rf_vec3 c = rf_v3_madd(q, m->cfg.rho, RF_FACE(m, to)->n);
    rf_contact near;
    double d = rf_closest_feature(m, c, m->cfg.rho + RF_PIVOT_REACH, &near);
    return d >= m->cfg.rho - RF_RADIUS_REL_TOL * m->cfg.rho - m->cfg.tol_len;
}

/* The rock takes off: no support; face `exclude` (-1: none) is left out of the flight's
 * contact search. */
void rf_go_flight(rf_motion *m, int32_t exclude)
{
    m->rock.sup.n = 0;
    m->rock.flight_ex.n = exclude >= 0 ? 1 : 0;
    m->rock.flight_ex.tri[0] = exclude;
}

/* A slow sphere on a convex edge or vertex (unit normal u) that cannot roll over it
 * cleanly hops off: its velocity is turned, at the same speed, to leave the feature
 * at the stay speed, so that it is never dragged through the feature. */
void rf_hop(rf_motion *m, rf_vec3 u)
{
    double speed = rf_v3_norm(m->rock.s.v);
    double vn = rf_fmin(speed, m->cfg.v_stay);
    rf_vec3 vt = rf_v3_madd(m->rock.s.v, -rf_v3_dot(m->rock.s.v, u), u);
    double vtl = rf_v3_norm(vt);
    double st = sqrt(rf_fmax(0.0, speed * speed - vn * vn));
    m->rock.s.v = rf_v3_add(rf_v3_scale(u, vn), vtl > 0 ? rf_v3_scale(vt, st / vtl) : rf_v3(0, 0, 0));
    rf_go_flight(m, -1);
}

rf_vec3 rf_centre_lift_move(const rf_motion *m, const rf_triangle *T, double *gap)
{
    *gap = m->cfg.rho - (rf_v3_dot(T->n, m->rock.s.p) - T->d);
    if (!(*gap > 0))
        return rf_v3(0, 0, 0);
    double along = 0.0;
    if (T->n.z < RF_STEEP_NZ) {
        rf_face_edges fe;
        rf_column_edges(T, &fe);
        along = *gap;
        for (int k = 0; k < 3; k++) {
            double mn = rf_v3_dot(fe.m[k], T->n);
            if (mn < 0)
                along = rf_fmin(along, rf_fmax(0.0, (rf_v3_dot(fe.m[k], m->rock.s.p) - fe.o[k]) / -mn));
        }
    }
    return rf_v3_madd(rf_v3(0, 0, (*gap - along) / T->n.z), along, T->n);
}

/* The potential energy (J) a lift by `move` costs. */
double rf_lift_cost(const rf_motion *m, rf_vec3 move)
{
    return m->cfg.body->mass * RF_GRAVITY * move.z;
}

int rf_pay_lift(rf_motion *m, rf_vec3 move)
{
    double cost = rf_lift_cost(m, move);
    double ke = rf_motion_energy(m);
    if (!(ke > cost) || !(ke > 0.0))
        return 0;
    double s = sqrt((ke - cost) / ke);
    m->rock.s.v = rf_v3_scale(m->rock.s.v, s);
    m->rock.s.w = rf_v3_scale(m->rock.s.w, s);
    m->rock.s.p = rf_v3_add(m->rock.s.p, move);
    return 1;
}

/* Centre mode: 1 when face `to`'s offset plane is above the centre's reach and a rock
 * of kinetic energy ke (J) cannot pay the lift onto it: a wall. */
int rf_wall_for(const rf_motion *m, int32_t to, double ke)
{
    double gap;
    rf_vec3 move = rf_centre_lift_move(m, RF_FACE(m, to), &gap);
    return gap > m->cfg.tol_len && rf_lift_cost(m, move) >= ke;
}

/* 1 when the centre, moving horizontally along v (with its spin) from where it is, goes
 * on into the column of a face other than `skip` that is a wall to it: another wall,
 * meeting the one it was reflected off where the centre is. */
static int wall_ahead(rf_motion *m, int32_t skip, rf_vec3 v)
{
    double h = rf_v3_hnorm(v), tol = m->cfg.tol_len;
    if (!(h > 0))
        return 0;
    rf_vec3 q = m->rock.s.p;
    q.x += RF_REACH_TOLS * tol * v.x / h;
    q.y += RF_REACH_TOLS * tol * v.y / h;
    double ke = rf_kinetic_energy(m->cfg.body, v, m->rock.s.w);
    size_t n = rf_gather(m, q.x - tol, q.y - tol, q.x + tol, q.y + tol);
    for (size_t i = 0; i < n; i++) {
        int32_t k = m->ws->cand[i];
        const rf_triangle *T = RF_FACE(m, k);
        if (k != skip && T->n.z > 0 && rf_in_column(T, q, 0.5 * tol) &&
            rf_wall_for(m, k, ke))
            return 1;
    }
    return 0;
}

/* Centre mode (Eq. 6-7) tests only the face under the centre, so the centre can move
 * over a face whose plane it is already closer to than r.  It is lifted onto that
 * face's offset plane, and the lift is paid from the kinetic energy; when the rock
 * cannot pay, the face acts as a wall at the border of its column and the horizontal
 * velocity into it is reflected with restitution e.  Returns 1 after a reflection. */
/* The column a wall reflection happens at: its edge functions, and how far inside
 * each edge the centre is. */
typedef struct wall_column {
    rf_face_edges fe;
    double side[3];
    int32_t tri;
} wall_column;

/* At a corner of the column, a reflection off one edge that leaves the rock moving in
 * over the other (along the first: it ran on between two walls, under both), or into
 * the column of another wall that meets this one there, takes the whole horizontal
 * velocity instead, which leaves the corner (rf_impact_site.corner). */
static int wall_corner_ahead(rf_motion *m, rf_vec3 v, const void *ctx)
{
    const wall_column *wc = ctx;
    int corner = 0;
    for (int k = 0; k < 3 && !corner; k++)
        corner = fabs(wc->side[k]) <= m->cfg.tol_len && rf_v3_dot(v, wc->fe.m[k]) > RF_APPROACH_EPS;
    return corner || wall_ahead(m, wc->tri, v);
}

static int centre_lift(rf_motion *m, const rf_contact *c)
{
    const rf_triangle *T = RF_FACE(m, c->tri);
    double gap;
    rf_vec3 move = rf_centre_lift_move(m, T, &gap);
    if (!(gap > 0) || rf_pay_lift(m, move))
        return 0;
    /* the border of the face's column the centre is crossing: nearest to it among
     * those it moves in through */
    wall_column wc;
    wc.tri = c->tri;
    rf_column_edges(T, &wc.fe);
    rf_vec3 P[3] = {T->a, T->b, T->c};
    double best = INFINITY;
    rf_vec3 in = rf_v3(0, 0, 0);
    for (int k = 0; k < 3; k++) {
        rf_vec3 mk = wc.fe.m[k];
        wc.side[k] = mk.x * (m->rock.s.p.x - P[k].x) + mk.y * (m->rock.s.p.y - P[k].y);
        if (rf_v3_dot(m->rock.s.v, mk) > 0 && wc.side[k] < best)
            best = wc.side[k], in = mk;
    }
    rf_impact_site site = {RF_IMPACT_WALL, c->tri, in, rf_v3_dot(m->rock.s.v, in), wall_corner_ahead, &wc};
    rf_impact(m, &site, NULL);
    return 1;
}

/* 1 when faces a and b of a grid lie in the same or neighbouring cells (they share a
 * node, or nearly: the grid's own neighbourhood, by cell arithmetic in O(1)). */
static int grid_neighbours(const rf_terrain *t, int32_t a, int32_t b)
{
    if (a < 0 || b < 0)
        return 0;
    long na = (long)(rf_grid_node(t, a) / 2), nb = (long)(rf_grid_node(t, b) / 2);
    long nx = (long)t->nx;
    long di = na % nx - nb % nx, dj = na / nx - nb / nx;
    return di >= -1 && di <= 1 && dj >= -1 && dj <= 1;
}

/* The tangential impulse of the turn onto face `to` (normal n), whose normal approach
 * speed is jn (m/s): Eq. 8's Coulomb impulse, |J_t| <= mu J_n with J_n = m (1 + e_n) jn,
 * with the support's drawn friction mu (the mean friction of the face's zone where that
 * is another zone) and the mean restitution e_n of the face's zone (the rebound itself,
 * below v_stay, is not kept: the rock stays on the surface).  A
 * point mass loses at most all of its tangential speed; a sphere's slip u on the new
 * face is opposed, capped where the slip vanishes (|u| / K per unit mass, K = 1 + m r^2
 * / I, Eq. 8's rolling cap), its spin changed by the same impulse (Eq. 8b). */
static void turn_resistance(rf_motion *m, int32_t to, rf_vec3 n, double jn)
{
    const rf_body *b = m->cfg.body;
    const rf_terrain *t = m->cfg.terrain;
    int32_t z = rf_tri_zone(t, to);
    const rf_surface *sf = &t->zones[z >= 0 && (size_t)z < t->nzones ? z : 0].surface;
    double mu = z == m->rock.sup.zone ? m->rock.sup.mu : rf_fmax(0.0, sf->friction.mean);
    mu *= 1.0 + rf_fmin(1.0, rf_fmax(0.0, sf->restitution.mean));
    if (m->cfg.point) {
        double speed = rf_v3_norm(m->rock.s.v);
        if (speed > 0)
            m->rock.s.v = rf_v3_scale(m->rock.s.v, rf_fmax(0.0, speed - mu * jn) / speed);
        return;
    }
    rf_vec3 u = rf_slip_of(m, n);
    double ul = rf_v3_norm(u);
    if (!(ul > 0))
        return;
    double p = rf_fmin(mu * jn, ul / rf_slip_factor(b, m->cfg.rho));
    rf_vec3 jt = rf_v3_scale(u, -b->mass * p / ul);
    m->rock.s.v = rf_v3_madd(m->rock.s.v, 1.0 / b->mass, jt);
    m->rock.s.w = rf_v3_add(m->rock.s.w, rf_v3_scale(rf_v3_cross(rf_v3_scale(n, -m->cfg.rho), jt),
                                                     1.0 / b->inertia));
}

/* 1 when the rolling phase on grids takes a meeting of face `to` at normal velocity vn
 * (m/s, negative towards it) by a rock on the surface: the grid's next face in the
 * neighbourhood of its support, met slower than v_stay along its normal (so that the
 * rock stays on the surface after any impact), where the face's zone has Eq. 8's law
 * (the rt law's tangential restitution is no turn's). */
static int grid_turn_taken(const rf_motion *m, int32_t to, double vn)
{
    const rf_terrain *t = m->cfg.terrain;
    if (!t->is_grid || m->rock.sup.n == 0)
        return 0;
    int32_t z = rf_tri_zone(t, to);
    if (t->zones[z >= 0 && (size_t)z < t->nzones ? z : 0].surface.law != RF_IMPACT_EQ8)
        return 0;
    if (!(-vn < m->cfg.v_stay))
        return 0;
    int near = 0;
    for (int k = 0; k < m->rock.sup.n; k++)
        near |= grid_neighbours(t, m->rock.sup.tri[k], to);
    return near;
}

/* The change of face (docs/engine.md, "The rolling phase on grids"): the velocity is
 * projected onto face `to` (normal n) and the turn's tangential impulse taken
 * (turn_resistance); no coefficient is drawn and no impact counted (n_edge_transitions
 * counts it).  The energy it takes (Eq. 8 with e_n = 0 only takes energy), with
 * drop_j (J) of potential energy the move onto the face gave up, is added to the
 * record's edge_loss_kj. */
static void take_grid_turn(rf_motion *m, int32_t to, rf_vec3 n, double drop_j)
{
    double e0 = rf_motion_energy(m);
    double vn = rf_v3_dot(m->rock.s.v, n);
    if (vn < 0) {
        m->rock.s.v = rf_v3_madd(m->rock.s.v, -vn, n);
        turn_resistance(m, to, n, -vn);
    }
    m->book.rec->n_edge_transitions++;
    m->book.rec->edge_loss_kj += (rf_fmax(0.0, e0 - rf_motion_energy(m)) + drop_j) / 1000.0;
}

/* The rolling phase on grids for a contact of full contact with face c->tri (the next
 * face at a concave edge): a change of face where grid_turn_taken allows it.  (Centre
 * contact changes face where its offset planes step down, rf_centre_edge_step; a centre
 * it lifts onto a face's offset plane meets that face by an impact.)  Returns 1 when
 * the contact was such a change of face. */
static int edge_transition(rf_motion *m, const rf_contact *c)
{
    if (m->cfg.centre || c->kind != RF_FEAT_FACE ||
        !grid_turn_taken(m, c->tri, rf_v3_dot(m->rock.s.v, c->n)))
        return 0;
    take_grid_turn(m, c->tri, c->n, 0.0);
    return 1;
}

int rf_centre_edge_step_taken(const rf_motion *m, int32_t to, const rf_triangle *T, rf_vec3 out)
{
    if (!m->cfg.centre)
        return 0;
    double vn = rf_v3_dot(m->rock.s.v, T->n);
    /* moving on into the face's column, which falls that way: gravity on the face does
     * not take the rock back over the border (along a valley line it would, at once
     * with the fixed step's semi-implicit steps) */
    rf_vec3 on = rf_v3_madd(m->rock.s.v, -vn, T->n);
    return rf_v3_dot(T->n, m->rock.s.p) - T->d - m->cfg.rho > 0 && vn < 0 &&
           T->n.z > 0 && rf_v3_dot(on, out) > RF_APPROACH_EPS && rf_v3_dot(T->n, out) >= 0 &&
           grid_turn_taken(m, to, vn);
}

void rf_centre_edge_step(rf_motion *m, int32_t to, const rf_triangle *T)
{
    /* vertically onto the offset plane: the centre stays over the face's column (Eq. 6) */
    double drop = (rf_v3_dot(T->n, m->rock.s.p) - T->d - m->cfg.rho) / T->n.z;
    m->rock.s.p.z -= drop;
    take_grid_turn(m, to, T->n, m->cfg.body->mass * RF_GRAVITY * drop);
    land(m, to);
}

void rf_contact_resolve(rf_motion *m, const rf_contact *c)
{
    const rf_terrain *t = m->cfg.terrain;
    if (m->cfg.centre && centre_lift(m, c))
        return; /* reflected: the support is unchanged */
    rf_vec3 n = c->n;
    if (c->kind != RF_FEAT_FACE) {
        rf_vec3 d = rf_v3_sub(m->rock.s.p, c->point);
        double dl = rf_v3_norm(d);
        if (dl > 0)
            n = rf_v3_scale(d, 1.0 / dl);
    }
    /* exactly at the contact distance */
    if (!m->cfg.centre) {
        double dist = rf_feature_distance(t, c, m->rock.s.p);
        m->rock.s.p = rf_v3_madd(m->rock.s.p, m->cfg.rho - dist, n);
    }
    if (edge_transition(m, c)) {
        land(m, c->tri);
        return;
    }
    rf_impact_site site = {RF_IMPACT_SLOPE, c->tri, n};
    double rebound = rf_impact(m, &site, NULL);
    if (rebound >= m->cfg.v_stay) {
        rf_go_flight(m, -1);
        return;
    }
    m->rock.s.v = rf_v3_madd(m->rock.s.v, -rf_v3_dot(m->rock.s.v, n), n);
    if (c->kind == RF_FEAT_FACE || m->cfg.point || m->cfg.centre) {
        land(m, c->tri);
        return;
    }
    /* a slow sphere on a convex edge or vertex rolls over it onto a face */
    rf_vec3 w = m->rock.s.v;
    if (rf_v3_hnorm(w) < RF_DIR_SPEED_EPS)
        w = rf_v3(n.x, n.y, 0.0); /* gravity pulls the centre further over that side */
    int32_t to = rf_face_beyond(t, -2, c->point, w);
    /* not back onto the face just flown off, met at its own edge as the rock leaves
     * it along that edge: it would leave it again at once */
    if (m->rock.flight_ex.n > 0 && to == m->rock.flight_ex.tri[0])
        to = -1;
    if (to >= 0 && rf_pivot_clear(m, c->point, to) && rf_pivot(m, c->point, to) == 0) {
        rf_support_single(m, to, m->rock.sup.n == 0);
        m->rock.sup.rolling = 1;
        return;
    }
    rf_hop(m, n);
}

void rf_crease_ends(rf_motion *m, int32_t on, int32_t left)
{
    m->rock.sup.n = 1;
    m->rock.sup.tri[0] = on;
    m->rock.sup.tri[1] = -1;
    m->rock.sup.left = left;
    if (!m->cfg.point && m->rock.sup.rolling) {
        /* it rolled on the plane of the bisector n_m of the two normals (w = n_m x v /
         * r), which slips on the face by v (1 - n . n_m): it slides until the slip
         * vanishes (the spin is kept, so no energy is made) */
        m->rock.sup.rolling = 0;
        rf_face_slip(m, RF_FACE(m, on)->n);
    }
}

int rf_surface_scene_event(rf_motion *m)
{
    int32_t onto;
    int end = rf_scene_event(m, &onto);
    if (onto >= 0) {
        rf_surface_enter(m, onto);
        rf_motion_event(m);
    }
    return end;
}
