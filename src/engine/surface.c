/* surface.c - rolling and sliding on one face or in a crease of two faces.
 *
 * On a face with normal n gravity splits into g_t (along the face) and the pressure
 * g_n = g n.z.  The point mass and the slipping sphere feel Coulomb friction opposite
 * the slip of the contact point; the rolling sphere feels rolling resistance:
 *
 *   point mass        a = g_t - mu g_n v^                 (Eq. 1-2 on a plane)
 *   slipping sphere   a = g_t - mu g_n u^,   du/dt = g_t - (1 + m r^2 / I) mu g_n u^
 *   rolling sphere    a = 5/7 (g_t - mu_r g_n v^)         (I = 2/5 m r^2)
 *
 * When the friction direction stays constant (velocity or slip along the fall line,
 * or a level face) the acceleration is constant and every event time is the root of
 * a quadratic.  Otherwise each law is w' = A e1 - B w^ (e1 the fall line; w the
 * velocity, or the slip of the slipping sphere), whose solution hodograph.c gives in
 * closed form.  Such a segment is cut into steps, each short enough that its parabola
 * (start, start velocity, end) departs from the path by about RF_PATH_DEV at most: the
 * contact and scene searches run on the parabola, and what they find is located to
 * ~1e-13 s on the path itself.
 *
 * Events: the contact point leaves the face (over a convex edge: flight or a roll
 * over the edge; a concave edge: impact on the next face; the same plane: carry on),
 * another face, edge or vertex is met (impact), the slip vanishes (rolling), the
 * velocity vanishes, the speed falls below stop_speed where friction holds (rest),
 * max_time.  A crease (two faces touched at once, as in a gully) is a straight line:
 * the rock moves along it with the normal forces of both faces. */
#include "engine/motion_private.h"

#include <math.h>
#include <string.h>

#define G_ACC RF_GRAVITY

typedef enum ev_kind {
    EV_NONE, EV_MAX_TIME, EV_REST, EV_ZERO, EV_SLIP, EV_EXIT, EV_CONTACT, EV_SCENE,
    EV_LINE /* a measure's line crossed, located on a path off the fall line */
} ev_kind;

typedef enum law { LAW_POINT, LAW_SLIDE, LAW_ROLL } law;

/* The dynamics of one face. */
typedef struct face_dyn {
    rf_vec3 n, gt, e1;
    double G, gn;       /* |g_t|, g n.z */
    law mode;
    double k, c;        /* a = k (g_t - c g_n dir) */
    double K;           /* slip factor 1 + m r^2 / I */
    double mu;
} face_dyn;

double rf_roll_factor(const rf_body *b, double rho)
{
    return 1.0 / (1.0 + b->inertia / (b->mass * rho * rho)); /* 5/7 for I = 2/5 m r^2 */
}

double rf_slip_factor(const rf_body *b, double rho)
{
    return 1.0 + b->mass * rho * rho / b->inertia; /* 7/2 for I = 2/5 m r^2 */
}

static void face_setup(const rf_motion *m, rf_vec3 n, face_dyn *f)
{
    f->n = n;
    f->gn = G_ACC * n.z;
    /* g_t = g - (g.n) n with g = (0, 0, -G) */
    f->gt = rf_v3(G_ACC * n.z * n.x, G_ACC * n.z * n.y, G_ACC * n.z * n.z - G_ACC);
    f->G = rf_v3_norm(f->gt);
    if (f->G > 1e-12) {
        f->e1 = rf_v3_scale(f->gt, 1.0 / f->G);
    } else {
        f->G = 0.0;
        f->gt = rf_v3(0, 0, 0);
        rf_vec3 x = fabs(n.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 1, 0);
        f->e1 = rf_v3_unit(rf_v3_madd(x, -rf_v3_dot(x, n), n));
    }
    f->mu = m->sup.mu;
    if (m->point) {
        f->mode = LAW_POINT, f->k = 1.0, f->c = m->sup.mu;
    } else if (m->sup.rolling) {
        f->mode = LAW_ROLL, f->k = rf_roll_factor(m->body, m->rho), f->c = m->sup.mu_r;
    } else {
        f->mode = LAW_SLIDE, f->k = 1.0, f->c = m->sup.mu;
    }
    f->K = m->point ? 1.0 : rf_slip_factor(m->body, m->rho);
}

/* The surface laws (module comment): acceleration of the centre and rate of the slip. */
static rf_vec3 law_accel(const face_dyn *f, rf_vec3 dir)
{
    return rf_v3_scale(rf_v3_madd(f->gt, -f->c * f->gn, dir), f->k);
}
static rf_vec3 law_slip_rate(const face_dyn *f, rf_vec3 udir)
{
    return rf_v3_madd(f->gt, -f->K * f->mu * f->gn, udir);
}


/* The direction the laws act along: the slip's for a slipping sphere, else the
 * velocity's; the fall line when it is zero. */
static rf_vec3 law_dir(const face_dyn *f, rf_vec3 v, rf_vec3 u)
{
    rf_vec3 x = f->mode == LAW_SLIDE ? u : v;
    double xl = rf_v3_norm(x);
    return xl > 0 ? rf_v3_scale(x, 1.0 / xl) : f->e1;
}

void rf_wall_law(rf_vec3 dir, rf_vec3 *a, rf_vec3 *du)
{
    *a = rf_v3_scale(dir, rf_v3_dot(*a, dir));
    *du = rf_v3_scale(dir, rf_v3_dot(*du, dir)); /* the wall's push changes no spin */
}

rf_vec3 rf_surface_accel(const rf_motion *m, rf_vec3 n, rf_vec3 v, rf_vec3 u, rf_vec3 *du)
{
    face_dyn f;
    face_setup(m, n, &f);
    rf_vec3 dir = law_dir(&f, v, u);
    *du = f.mode == LAW_SLIDE ? law_slip_rate(&f, dir) : rf_v3(0, 0, 0);
    return law_accel(&f, dir);
}

/* Slip of the contact point of the sphere on a face with normal n. */
rf_vec3 rf_slip_of(const rf_motion *m, rf_vec3 n)
{
    rf_vec3 u = rf_v3_add(m->s.v, rf_v3_cross(m->s.w, rf_v3_scale(n, -m->rho)));
    return rf_in_plane(u, n);
}

/* The law of a piece on face n from the current state, its slip u0 at the start
 * changing at the rate du. */
static rf_spin_law rf_spin_law_of(const rf_motion *m, rf_vec3 n, rf_vec3 u0, rf_vec3 du)
{
    return (rf_spin_law){n, rf_v3_dot(m->s.w, n), u0, du};
}

rf_spin_law rf_spin_law_over(const rf_motion *m, rf_vec3 n, rf_vec3 u, rf_vec3 u1, double h)
{
    return h > 0 ? rf_spin_law_of(m, n, u, rf_v3_scale(rf_v3_sub(u1, u), 1.0 / h))
                 : rf_spin_law_of(m, n, u1, rf_v3(0, 0, 0));
}

rf_vec3 rf_spin_at(const rf_spin_law *l, double rho, rf_vec3 v, double t)
{
    rf_vec3 u = rf_v3_madd(l->u0, t, l->du);
    rf_vec3 wt = rf_v3_scale(rf_v3_cross(l->n, rf_v3_sub(v, u)), 1.0 / rho);
    return rf_v3_madd(wt, l->wn, l->n);
}

/* Angular velocity from v and slip u on a face (w . n kept): w_t = n x (v - u) / r. */
void rf_set_spin(rf_motion *m, rf_vec3 n, rf_vec3 u)
{
    if (m->point) {
        m->s.w = rf_v3(0, 0, 0);
    } else {
        rf_spin_law l = rf_spin_law_of(m, n, u, rf_v3(0, 0, 0));
        m->s.w = rf_spin_at(&l, m->rho, m->s.v, 0.0);
    }
    rf_motion_note_energy(m);
}

rf_vec3 rf_face_slip(rf_motion *m, rf_vec3 n)
{
    rf_vec3 u = rf_slip_of(m, n);
    if (!m->sup.rolling && rf_v3_norm(u) <= RF_SLIP_EPS) {
        m->sup.rolling = 1;
        rf_set_spin(m, n, rf_v3(0, 0, 0));
        return rf_v3(0, 0, 0);
    }
    return u;
}

int rf_coplanar(const rf_triangle *A, const rf_triangle *B, double tol)
{
    return rf_v3_norm(rf_v3_sub(A->n, B->n)) <= RF_COPLANAR_EPS && fabs(A->d - B->d) <= tol;
}

/* The faces a surface segment's contact search ignores: the support, and once the face
 * just left over an edge. */
static rf_support segment_exclusion(rf_motion *m)
{
    rf_support ex = m->sup;
    if (ex.left >= 0 && ex.n < 3)
        ex.tri[ex.n++] = ex.left;
    m->sup.left = -1;
    return ex;
}

/* ---- entering a face or a crease ---------------------------------------------------- */

void rf_support_single(rf_motion *m, int32_t tri, int fresh)
{
    const rf_triangle *T = &m->terrain->tri[tri];
    if (fresh || m->sup.n == 0 || m->sup.zone != T->zone)
        rf_support_draw(m, tri);
    m->sup.n = 1;
    m->sup.tri[0] = tri;
    m->sup.tri[1] = -1;
    m->sup.left = -1;
    /* on the offset plane, velocity tangent */
    m->s.p = rf_v3_madd(m->s.p, T->d + m->rho - rf_v3_dot(T->n, m->s.p), T->n);
    m->s.v = rf_in_plane(m->s.v, T->n);
    m->sup.rolling = 0;
    if (!m->point)
        rf_face_slip(m, T->n);
}

void rf_surface_enter(rf_motion *m, int32_t tri) { rf_support_single(m, tri, 1); }

int rf_crease_forces(rf_vec3 nA, rf_vec3 nB, double *xA, double *xB, rf_vec3 *l)
{
    rf_vec3 c = rf_v3_cross(nA, nB);
    double cl = rf_v3_norm(c);
    if (!(cl > 1e-6))
        return -1;
    *l = rf_v3_scale(c, 1.0 / cl);
    double bA = G_ACC * nA.z, bB = G_ACC * nB.z, nab = rf_v3_dot(nA, nB);
    double den = 1.0 - nab * nab;
    *xA = (bA - nab * bB) / den;
    *xB = (bB - nab * bA) / den;
    return 0;
}

rf_vec3 rf_crease_centre(const rf_triangle *A, const rf_triangle *B, double rho, rf_vec3 p)
{
    /* p + a nA + b nB with nA.x = dA + rho and nB.x = dB + rho: a 2 x 2 system, solved
     * exactly (alternate projections onto the two planes converge slowly where the
     * faces are nearly parallel) */
    double eA = A->d + rho - rf_v3_dot(A->n, p), eB = B->d + rho - rf_v3_dot(B->n, p);
    double c = rf_v3_dot(A->n, B->n), den = 1.0 - c * c;
    return rf_v3_madd(rf_v3_madd(p, (eA - c * eB) / den, A->n), (eB - c * eA) / den, B->n);
}

/* The rock on face A meets face B gently: a crease when both faces press on it. */
static int try_crease(rf_motion *m, int32_t a, int32_t b)
{
    const rf_triangle *A = &m->terrain->tri[a], *B = &m->terrain->tri[b];
    if (a == b || rf_coplanar(A, B, m->tol_len))
        return -1;
    if (rf_v3_dot(m->s.v, A->n) > m->v_stay)
        return -1; /* leaving A */
    double xA = 0.0, xB = 0.0; /* crease_forces may fail before setting them */
    rf_vec3 l;
    if (rf_crease_forces(A->n, B->n, &xA, &xB, &l) || xA < 0 || xB < 0)
        return -1;
    /* both faces touched: the centre lies on both offset planes */
    double s = rf_v3_dot(m->s.v, l);
    m->s.v = rf_v3_scale(l, s);
    rf_vec3 p = rf_crease_centre(A, B, m->rho, m->s.p);
    if (rf_v3_norm(rf_v3_sub(p, m->s.p)) > 0.01 * rf_fmax(m->rho, 0.01))
        return -1;
    m->s.p = p;
    if (m->sup.n == 0 || m->sup.zone != B->zone)
        rf_support_draw(m, b);
    int rolling = !m->point && m->sup.n >= 1 && m->sup.rolling;
    m->sup.n = 2;
    m->sup.tri[0] = a;
    m->sup.tri[1] = b;
    m->sup.left = -1;
    m->sup.rolling = rolling;
    if (rolling) {
        rf_spin_law roll = rf_crease_roll(m);
        m->s.w = rf_spin_at(&roll, m->rho, m->s.v, 0.0);
    }
    return 0;
}

/* Landing gently on face tri (rebound below the stay threshold). */
static void land(rf_motion *m, int32_t tri)
{
    if (m->sup.n == 1 && try_crease(m, m->sup.tri[0], tri) == 0)
        return;
    if (m->sup.n == 2) {
        int32_t a = m->sup.tri[0], b = m->sup.tri[1];
        if (try_crease(m, a, tri) == 0 || try_crease(m, b, tri) == 0)
            return;
    }
    rf_support_single(m, tri, m->sup.n == 0);
}

/* 1 when a sphere rolled over q onto face `to` would touch no other feature: the
 * roll is only taken where the two faces are all there is. */
static int pivot_clear(rf_motion *m, rf_vec3 q, int32_t to)
{
    rf_vec3 c = rf_v3_madd(q, m->rho, m->terrain->tri[to].n);
    rf_contact near;
    double d = rf_closest_feature(m, c, m->rho + 1e-3, &near);
    return d >= m->rho - 1e-6 * m->rho - m->tol_len;
}

/* The rock takes off: no support; face `exclude` (-1: none) is left out of the flight's
 * contact search. */
static void go_flight(rf_motion *m, int32_t exclude)
{
    m->sup.n = 0;
    m->flight_ex.n = exclude >= 0 ? 1 : 0;
    m->flight_ex.tri[0] = exclude;
}

/* A slow sphere on a convex edge or vertex (unit normal u) that cannot roll over it
 * cleanly hops off: its velocity is turned, at the same speed, to leave the feature
 * at the stay speed, so that it is never dragged through the feature. */
static void hop(rf_motion *m, rf_vec3 u)
{
    double speed = rf_v3_norm(m->s.v);
    double vn = rf_fmin(speed, m->v_stay);
    rf_vec3 vt = rf_v3_madd(m->s.v, -rf_v3_dot(m->s.v, u), u);
    double vtl = rf_v3_norm(vt);
    double st = sqrt(rf_fmax(0.0, speed * speed - vn * vn));
    m->s.v = rf_v3_add(rf_v3_scale(u, vn), vtl > 0 ? rf_v3_scale(vt, st / vtl) : rf_v3(0, 0, 0));
    go_flight(m, -1);
}

/* An impact with approach speed vin (m/s; kinetic energy e0 J before it) counts and is
 * reported when the rock approached the surface; a touch at a grazing speed (the path
 * tangent to the face, as when a centre runs exactly along an edge line) changes
 * nothing and is not an impact. */
static void count_impact(rf_motion *m, double e0, double vin)
{
    if (!(vin > RF_APPROACH_EPS))
        return;
    m->rec->n_impacts++;
    if (m->sink && m->sink->impact)
        m->sink->impact(m->sink->ctx, m->s.t, e0 / 1000.0, rf_motion_energy(m) / 1000.0, vin);
}

rf_vec3 rf_centre_lift_move(const rf_motion *m, const rf_triangle *T, double *gap)
{
    *gap = m->rho - (rf_v3_dot(T->n, m->s.p) - T->d);
    if (!(*gap > 0))
        return rf_v3(0, 0, 0);
    double along = 0.0;
    if (T->n.z < 0.2) {
        rf_face_edges fe;
        rf_column_edges(T, &fe);
        along = *gap;
        for (int k = 0; k < 3; k++) {
            double mn = rf_v3_dot(fe.m[k], T->n);
            if (mn < 0)
                along = rf_fmin(along, rf_fmax(0.0, (rf_v3_dot(fe.m[k], m->s.p) - fe.o[k]) / -mn));
        }
    }
    return rf_v3_madd(rf_v3(0, 0, (*gap - along) / T->n.z), along, T->n);
}

/* The potential energy (J) a lift by `move` costs. */
static double lift_cost(const rf_motion *m, rf_vec3 move)
{
    return m->body->mass * RF_GRAVITY * move.z;
}

int rf_pay_lift(rf_motion *m, rf_vec3 move)
{
    double cost = lift_cost(m, move);
    double ke = rf_motion_energy(m);
    if (!(ke > cost) || !(ke > 0.0))
        return 0;
    double s = sqrt((ke - cost) / ke);
    m->s.v = rf_v3_scale(m->s.v, s);
    m->s.w = rf_v3_scale(m->s.w, s);
    m->s.p = rf_v3_add(m->s.p, move);
    return 1;
}

/* Centre mode: 1 when face `to`'s offset plane is above the centre's reach and a rock
 * of kinetic energy ke (J) cannot pay the lift onto it: a wall. */
static int wall_for(const rf_motion *m, int32_t to, double ke)
{
    double gap;
    rf_vec3 move = rf_centre_lift_move(m, &m->terrain->tri[to], &gap);
    return gap > m->tol_len && lift_cost(m, move) >= ke;
}

/* 1 when the centre, moving horizontally along v (with its spin) from where it is, goes
 * on into the column of a face other than `skip` that is a wall to it: another wall,
 * meeting the one it was reflected off where the centre is. */
static int wall_ahead(rf_motion *m, int32_t skip, rf_vec3 v)
{
    double h = rf_v3_hnorm(v), tol = m->tol_len;
    if (!(h > 0))
        return 0;
    rf_vec3 q = m->s.p;
    q.x += 4.0 * tol * v.x / h;
    q.y += 4.0 * tol * v.y / h;
    double ke = rf_kinetic_energy(m->body, v, m->s.w);
    size_t n = rf_gather(m, q.x - tol, q.y - tol, q.x + tol, q.y + tol);
    for (size_t i = 0; i < n; i++) {
        int32_t k = m->ws->cand[i];
        if (k != skip && m->terrain->tri[k].n.z > 0 && rf_in_column(&m->terrain->tri[k], q, 0.5 * tol) &&
            wall_for(m, k, ke))
            return 1;
    }
    return 0;
}

/* Centre mode (Eq. 6-7) tests only the face under the centre, so the centre can move
 * over a face whose plane it is already closer to than r.  It is lifted onto that
 * face's offset plane, and the lift is paid from the kinetic energy; when the rock
 * cannot pay, the face acts as a wall at the border of its column and the horizontal
 * velocity into it is reflected with restitution e.  Returns 1 after a reflection. */
static int centre_lift(rf_motion *m, const rf_contact *c)
{
    const rf_triangle *T = &m->terrain->tri[c->tri];
    double gap;
    rf_vec3 move = rf_centre_lift_move(m, T, &gap);
    if (!(gap > 0) || rf_pay_lift(m, move))
        return 0;
    /* the border of the face's column the centre is crossing: nearest to it among
     * those it moves in through */
    rf_face_edges fe;
    rf_column_edges(T, &fe);
    rf_vec3 P[3] = {T->a, T->b, T->c};
    double best = INFINITY, side[3];
    rf_vec3 in = rf_v3(0, 0, 0);
    for (int k = 0; k < 3; k++) {
        rf_vec3 mk = fe.m[k];
        side[k] = mk.x * (m->s.p.x - P[k].x) + mk.y * (m->s.p.y - P[k].y);
        if (rf_v3_dot(m->s.v, mk) > 0 && side[k] < best)
            best = side[k], in = mk;
    }
    double vin = rf_v3_dot(m->s.v, in);
    const rf_surface *sf = &m->terrain->zones[T->zone].surface;
    double e = rf_draw_truncated(m->rng, sf->restitution, 0.0, 1.0);
    double e0 = rf_motion_energy(m);
    if (vin > 0) {
        rf_vec3 v = rf_v3_madd(m->s.v, -(1.0 + e) * vin, in);
        /* at a corner of the column, a reflection off one edge that leaves the rock
         * moving in over the other (along the first: it ran on between two walls,
         * under both), or into the column of another wall that meets this one there,
         * takes the whole horizontal velocity instead, which leaves the corner */
        int corner = 0;
        for (int k = 0; k < 3 && !corner; k++)
            corner = fabs(side[k]) <= m->tol_len && rf_v3_dot(v, fe.m[k]) > RF_APPROACH_EPS;
        if (corner || wall_ahead(m, c->tri, v)) {
            v = rf_v3(-e * m->s.v.x, -e * m->s.v.y, m->s.v.z);
            vin = rf_v3_hnorm(m->s.v);
        }
        m->s.v = v;
    }
    count_impact(m, e0, vin);
    return 1;
}

void rf_contact_resolve(rf_motion *m, const rf_contact *c)
{
    const rf_terrain *t = m->terrain;
    if (m->centre && centre_lift(m, c))
        return; /* reflected: the support is unchanged */
    rf_vec3 n = c->n;
    if (c->kind != RF_FEAT_FACE) {
        rf_vec3 d = rf_v3_sub(m->s.p, c->point);
        double dl = rf_v3_norm(d);
        if (dl > 0)
            n = rf_v3_scale(d, 1.0 / dl);
    }
    /* exactly at the contact distance */
    if (!m->centre) {
        double dist = rf_feature_distance(t, c, m->s.p);
        m->s.p = rf_v3_madd(m->s.p, m->rho - dist, n);
    }
    double e0 = rf_motion_energy(m);
    double vn = rf_v3_dot(m->s.v, n);
    double rebound = rf_impact(m, c->tri, n);
    count_impact(m, e0, -vn);
    if (rebound >= m->v_stay) {
        go_flight(m, -1);
        return;
    }
    m->s.v = rf_v3_madd(m->s.v, -rf_v3_dot(m->s.v, n), n);
    if (c->kind == RF_FEAT_FACE || m->point || m->centre) {
        land(m, c->tri);
        return;
    }
    /* a slow sphere on a convex edge or vertex rolls over it onto a face */
    rf_vec3 w = m->s.v;
    if (rf_v3_hnorm(w) < 1e-9)
        w = rf_v3(n.x, n.y, 0.0); /* gravity pulls the centre further over that side */
    int32_t to = rf_face_beyond(t, -2, c->point, w);
    /* not back onto the face just flown off, met at its own edge as the rock leaves
     * it along that edge: it would leave it again at once */
    if (m->flight_ex.n > 0 && to == m->flight_ex.tri[0])
        to = -1;
    if (to >= 0 && pivot_clear(m, c->point, to) && rf_pivot(m, c->point, to) == 0) {
        rf_support_single(m, to, m->sup.n == 0);
        m->sup.rolling = 1;
        return;
    }
    hop(m, n);
}

/* ---- face edges and exits ----------------------------------------------------------- */

/* Edge functions of a face: E_i(c) = m_i . c - o_i >= 0 while the contact point of a
 * centre c is inside edge i (in-plane distances; over the xy projection in centre
 * mode). */
void rf_column_edges(const rf_triangle *T, rf_face_edges *fe)
{
    rf_vec3 P[3] = {T->a, T->b, T->c};
    double orient = (P[1].x - P[0].x) * (P[2].y - P[0].y) - (P[1].y - P[0].y) * (P[2].x - P[0].x);
    double sg = orient >= 0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; k++) {
        rf_vec3 A = P[k], B = P[(k + 1) % 3];
        double ex = B.x - A.x, ey = B.y - A.y, el = hypot(ex, ey);
        fe->m[k] = el > 0 ? rf_v3(-sg * ey / el, sg * ex / el, 0.0) : rf_v3(0, 0, 0);
        fe->o[k] = rf_v3_dot(fe->m[k], A);
    }
}

int rf_in_column(const rf_triangle *T, rf_vec3 p, double margin)
{
    rf_face_edges fe;
    rf_column_edges(T, &fe);
    for (int e = 0; e < 3; e++)
        if (!(rf_v3_dot(fe.m[e], p) - fe.o[e] >= margin))
            return 0;
    return 1;
}

static void edges_setup(const rf_motion *m, const rf_triangle *T, rf_face_edges *fe)
{
    if (m->centre) {
        rf_column_edges(T, fe);
        return;
    }
    rf_vec3 P[3] = {T->a, T->b, T->c};
    rf_vec3 ab = rf_v3_sub(P[1], P[0]), ac = rf_v3_sub(P[2], P[0]);
    double sg = rf_v3_dot(rf_v3_cross(ab, ac), T->n) >= 0 ? 1.0 : -1.0;
    rf_vec3 lift = rf_v3_scale(T->n, m->rho);
    for (int k = 0; k < 3; k++) {
        rf_vec3 A = P[k], B = P[(k + 1) % 3];
        rf_vec3 in = rf_v3_scale(rf_v3_cross(T->n, rf_v3_sub(B, A)), sg);
        fe->m[k] = rf_v3_unit(in);
        fe->o[k] = rf_v3_dot(fe->m[k], rf_v3_add(A, lift));
    }
}

/* 1 when p lies on edge k's line (within the length tolerance). */
static int on_edge(const rf_motion *m, const rf_face_edges *fe, int k, rf_vec3 p)
{
    return fabs(rf_v3_dot(fe->m[k], p) - fe->o[k]) <= m->tol_len;
}

/* Unit vector along edge k of F, from vertex k to vertex k + 1. */
static rf_vec3 edge_dir(const rf_triangle *F, int k)
{
    return rf_v3_unit(rf_v3_sub(rf_tri_vertex(F, k + 1), rf_tri_vertex(F, k)));
}

/* First time in [0, T] the contact point of the arc leaves the face, not over edge
 * `skip` (-1: none); T when it does not.  *edge receives the edge. */
static double exit_time(const rf_motion *m, const rf_face_edges *fe, const rf_arc *arc, double T,
                        int skip, int *edge)
{
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (k == skip)
            continue;
        double f[3] = {rf_v3_dot(fe->m[k], arc->p) - fe->o[k], rf_v3_dot(fe->m[k], arc->v),
                       0.5 * rf_v3_dot(fe->m[k], arc->a)};
        double r[3], t = INFINITY;
        double tol = m->tol_len;
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
        } else if (fabs(f[0]) <= tol && fabs(f[1]) <= RF_APPROACH_EPS && f[2] < -1e-12) {
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
static int shared_edge(const rf_triangle *A, const rf_triangle *B)
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
    const rf_triangle *Tn = &m->terrain->tri[to];
    double vn = rf_v3_dot(m->s.v, Tn->n);
    if (fabs(vn) <= RF_APPROACH_EPS) {
        /* moving along the edge: the acceleration decides */
        double an = rf_v3_dot(acc, Tn->n);
        if (fabs(an) > 1e-9)
            vn = an > 0 ? INFINITY : -INFINITY;
    }
    if (m->centre) {
        /* over the next face the centre is above, on or below its offset plane */
        double gap = rf_v3_dot(Tn->n, m->s.p) - Tn->d - m->rho;
        if (gap > m->tol_len)
            return RF_NEXT_AWAY;
        if (gap < -m->tol_len)
            return RF_NEXT_IMPACT;
    }
    if (vn < -RF_APPROACH_EPS)
        return RF_NEXT_IMPACT;
    return vn <= RF_APPROACH_EPS ? RF_NEXT_ON : RF_NEXT_AWAY;
}

/* The impact on the next face at a concave edge (the point model is put on it). */
static void impact_on_face(rf_motion *m, int32_t to)
{
    const rf_triangle *Tn = &m->terrain->tri[to];
    rf_contact c;
    memset(&c, 0, sizeof c);
    c.tri = to;
    c.kind = RF_FEAT_FACE;
    c.n = Tn->n;
    c.point = rf_v3_madd(m->s.p, -(rf_v3_dot(Tn->n, m->s.p) - Tn->d), Tn->n);
    if (m->point)
        m->s.p = c.point;
    rf_contact_resolve(m, &c);
}

/* The face across edge `edge` of face `from`, stepping over the edge's middle (-1:
 * none). */
static int32_t face_over_edge(const rf_terrain *t, int32_t from, int edge, const rf_face_edges *fe)
{
    const rf_triangle *F = &t->tri[from];
    rf_vec3 mid = rf_v3_scale(rf_v3_add(rf_tri_vertex(F, edge), rf_tri_vertex(F, edge + 1)), 0.5);
    int32_t to = rf_face_beyond(t, from, mid, rf_v3_scale(fe->m[edge], -1.0));
    return to == from ? -1 : to;
}

int32_t rf_face_after(const rf_motion *m, int32_t from, int edge, const rf_face_edges *fe,
                      rf_vec3 q, rf_vec3 acc)
{
    const rf_terrain *t = m->terrain;
    rf_vec3 dir = m->s.v;
    if (rf_v3_norm(dir) < 1e-9)
        dir = acc;
    if (rf_v3_hnorm(dir) < 1e-12)
        dir = rf_v3_scale(fe->m[edge], -1.0);
    int32_t to = rf_face_beyond(t, from, q, dir);
    if (to == from)
        to = face_over_edge(t, from, edge, fe); /* numerically still inside */
    return to;
}

/* 1 when a sphere whose contact point q crosses an edge, moving across it at vp, can
 * roll over it onto the face of normal n: the rise of its centre on the way (over the
 * top of a ridge, or up onto a shoulder) is paid from the energy of the motion across
 * the edge; the motion along it does not turn the sphere about it.  Rolled over a
 * sharp ridge along which it ran, with a hair of a velocity across it, a sphere was
 * turned onto the other face, where it crossed back at once, from side to side in no
 * time. */
static int climbs_over(const rf_motion *m, rf_vec3 q, rf_vec3 n, rf_vec3 vp)
{
    const rf_body *b = m->body;
    double mass = b->mass + (m->sup.rolling ? b->inertia / (m->rho * m->rho) : 0.0);
    return 0.5 * mass * rf_v3_norm2(vp) >= lift_cost(m, rf_v3(0, 0, rf_pivot_rise(m, q, n)));
}

void rf_crease_ends(rf_motion *m, int32_t on, int32_t left)
{
    m->sup.n = 1;
    m->sup.tri[0] = on;
    m->sup.tri[1] = -1;
    m->sup.left = left;
    if (!m->point && m->sup.rolling) {
        /* it rolled on the plane of the bisector n_m of the two normals (w = n_m x v /
         * r), which slips on the face by v (1 - n . n_m): it slides until the slip
         * vanishes.  Rolled on, the face's law (w . n kept, the rest from v) made
         * energy: 1.64 kJ on 11.3 kJ in no time (30/9/1). */
        m->sup.rolling = 0;
        rf_face_slip(m, m->terrain->tri[on].n);
    }
}

/* The contact point crossed edge `edge` of the support face at the current state. */
rf_surface_end rf_leave_face(rf_motion *m, int slot, int edge, const rf_face_edges *fe,
                             rf_vec3 acc)
{
    const rf_terrain *t = m->terrain;
    int32_t from = m->sup.tri[slot];
    const rf_triangle *F = &t->tri[from];
    rf_vec3 q = m->centre ? m->s.p : rf_v3_madd(m->s.p, -m->rho, F->n);
    int32_t to = rf_face_after(m, from, edge, fe, q, acc);
    if (to < 0 && (m->point || m->centre))
        return RF_SURF_EXITED;
    if (m->sup.n == 2) {
        int32_t other = m->sup.tri[1 - slot];
        if (to >= 0 && rf_coplanar(F, &t->tri[to], m->tol_len)) {
            m->sup.tri[slot] = to;
            m->sup.left = from;
            return RF_SURF_CONTINUE;
        }
        /* the crease goes on between the other face and the next one, or ends (also
         * over the terrain's edge): carry on on the other face */
        if (m->point && try_crease(m, other, to) == 0)
            return RF_SURF_CONTINUE; /* a point moves on along the valley line */
        rf_crease_ends(m, other, from);
        return RF_SURF_CONTINUE;
    }
    if (to < 0) {
        go_flight(m, from);
        return RF_SURF_FLIGHT;
    }
    const rf_triangle *Tn = &t->tri[to];
    if (rf_coplanar(F, Tn, m->tol_len)) {
        rf_support_single(m, to, 0);
        m->sup.left = from;
        return RF_SURF_CONTINUE;
    }
    switch (next_face(m, to, acc)) {
    case RF_NEXT_IMPACT:
        if (rf_scene_at_once(m) >= 0)
            return RF_SURF_STOPPED;
        impact_on_face(m, to);
        return m->sup.n == 0 ? RF_SURF_FLIGHT : RF_SURF_CONTINUE;
    case RF_NEXT_ON:
        rf_support_single(m, to, 0); /* tangent: the path continues on the next face */
        m->sup.left = from;
        return RF_SURF_CONTINUE;
    case RF_NEXT_AWAY:
        break;
    }
    /* convex: the next face falls away */
    if (m->point || m->centre) {
        go_flight(m, from);
        return RF_SURF_FLIGHT;
    }
    rf_vec3 e = edge_dir(F, edge);
    rf_vec3 vp = rf_in_plane(m->s.v, e);
    if (rf_v3_norm2(vp) >= m->rho * G_ACC * F->n.z) {
        go_flight(m, from); /* fast enough to fly off the edge */
        return RF_SURF_FLIGHT;
    }
    if (climbs_over(m, q, Tn->n, vp)) {
        if (!pivot_clear(m, q, to)) {
            hop(m, F->n);
            return RF_SURF_FLIGHT;
        }
        if (rf_pivot(m, q, to) == 0) {
            rf_support_single(m, to, 0);
            m->sup.rolling = 1;
            return RF_SURF_CONTINUE;
        }
    }
    /* cannot climb over: rolls back onto the face */
    rf_vec3 mo = rf_v3_scale(fe->m[edge], -1.0);
    double vo = rf_v3_dot(m->s.v, mo);
    if (vo > 0) {
        m->s.v = rf_v3_madd(m->s.v, -2.0 * vo, mo);
        if (m->sup.rolling)
            rf_set_spin(m, F->n, rf_v3(0, 0, 0));
    }
    return RF_SURF_CONTINUE;
}

/* ---- rest ---------------------------------------------------------------------------- */

int rf_surface_holds(const rf_motion *m)
{
    const rf_terrain *t = m->terrain;
    double c = m->point ? m->sup.mu : (m->sup.rolling ? m->sup.mu_r : -1.0);
    if (m->sup.n == 1) {
        if (c < 0)
            return 0; /* a slipping sphere first rolls */
        rf_vec3 n = t->tri[m->sup.tri[0]].n;
        double G = G_ACC * sqrt(rf_fmax(0.0, 1.0 - n.z * n.z));
        return G <= c * G_ACC * n.z;
    }
    if (m->sup.n == 2) {
        if (c < 0)
            c = m->sup.mu;
        double xA = 0.0, xB = 0.0; /* crease_forces may fail before setting them */
        rf_vec3 l;
        if (rf_crease_forces(t->tri[m->sup.tri[0]].n, t->tri[m->sup.tri[1]].n, &xA, &xB, &l))
            return 0;
        return fabs(G_ACC * l.z) <= c * (xA + xB);
    }
    return 0;
}

int rf_roll_holds(const rf_motion *m, rf_vec3 n)
{
    face_dyn f;
    face_setup(m, n, &f);
    double k = rf_roll_factor(m->body, m->rho);
    double vl = rf_v3_norm(m->s.v);
    if (!(vl > 0) && rf_surface_holds(m))
        return 1; /* at rest where it stays: no force is needed */
    rf_vec3 dir = vl > 0 ? rf_v3_scale(m->s.v, 1.0 / vl) : f.e1;
    rf_vec3 need = rf_v3_madd(rf_v3_scale(f.gt, 1.0 - k), -k * m->sup.mu_r * f.gn, dir);
    double cap = m->sup.mu * f.gn * (1 + 1e-12);
    /* or the slip law lets no slip grow from zero (|g_t| <= K mu g_n, the demand
     * without the resistance): where the two laws disagree (uphill, see docs/engine.md)
     * the sphere rolls on instead of switching between them at every instant */
    return rf_v3_norm(need) <= cap || f.G * (1.0 - k) <= cap;
}

/* ---- closed-form segments ------------------------------------------------------------ */

typedef struct seg_event {
    ev_kind kind;
    double t;
    int edge, slot;
    rf_contact con;
    double level; /* EV_REST, EV_ZERO: the speed it falls to; EV_EXIT: how far beyond the edge */
    double line[4]; /* EV_LINE: a point of the line and its unit normal towards the side the
                     * rock comes from */
} seg_event;

static void consider(seg_event *ev, ev_kind kind, double t)
{
    if (t < ev->t) {
        ev->t = t;
        ev->kind = kind;
    }
}

/* Finishes a segment at the event: records the motion and dispatches. */
static rf_surface_end dispatch(rf_motion *m, seg_event *ev, rf_vec3 acc, const rf_face_edges *fe)
{
    switch (ev->kind) {
    case EV_MAX_TIME:
        return RF_SURF_MAX_TIME;
    case EV_REST:
        return RF_SURF_REST;
    case EV_ZERO:
        m->s.v = rf_v3(0, 0, 0);
        if (!m->point && m->sup.rolling)
            m->s.w = rf_v3(0, 0, 0);
        rf_motion_event(m);
        return RF_SURF_CONTINUE;
    case EV_SLIP:
        m->sup.rolling = 1;
        rf_set_spin(m, m->terrain->tri[m->sup.tri[0]].n, rf_v3(0, 0, 0));
        rf_motion_event(m);
        return RF_SURF_CONTINUE;
    case EV_EXIT: {
        rf_surface_end r = rf_leave_face(m, ev->slot, ev->edge, fe, acc);
        rf_motion_event(m);
        return r;
    }
    case EV_CONTACT:
        if (rf_scene_at_once(m) >= 0)
            return RF_SURF_STOPPED;
        rf_contact_resolve(m, &ev->con);
        rf_motion_event(m);
        return m->sup.n == 0 ? RF_SURF_FLIGHT : RF_SURF_CONTINUE;
    case EV_SCENE:
        if (rf_scene_event(m) >= 0)
            return RF_SURF_STOPPED;
        return m->sup.n == 0 ? RF_SURF_FLIGHT : RF_SURF_CONTINUE;
    default:
        return RF_SURF_CONTINUE;
    }
}

/* The end of a constant-acceleration segment along arc (face or crease), whose other
 * events are in ev: contacts with the terrain (full contact; ex ignored) and scene
 * events come first when earlier; the state is moved to the event, the spin by its
 * law (NULL: it stays), and its energy noted. */
static void closed_finish(rf_motion *m, const rf_arc *arc, const rf_spin_law *spin,
                          const rf_support *ex, seg_event *ev)
{
    if (!m->point && !m->centre && ev->t > 0) {
        rf_contact con;
        if (rf_contact_search_near(m, arc, ev->t, ex, NULL, 0, &con) && con.t < ev->t) {
            consider(ev, EV_CONTACT, con.t);
            ev->con = con;
        }
    }
    double ts = rf_scene_horizon(m, arc, ev->t);
    if (m->scene_pending && ts < ev->t)
        consider(ev, EV_SCENE, ts);
    rf_motion_advance(m, arc, ev->t, spin);
    if (spin && !m->point)
        m->s.w = rf_spin_at(spin, m->rho, m->s.v, ev->t > 0 ? ev->t : 0.0);
    rf_motion_note_energy(m);
}

/* A segment of constant acceleration on one face; along the wall at its column edge
 * `wall` (centre mode, -1: none; dir along that edge), which takes the part of the
 * acceleration across it. */
static rf_surface_end face_closed(rf_motion *m, const face_dyn *f, rf_vec3 dir, rf_vec3 u0,
                                  const rf_face_edges *fe, int holds, int wall)
{
    rf_support ex = segment_exclusion(m);
    rf_vec3 a = law_accel(f, dir);
    rf_vec3 du = f->mode == LAW_SLIDE ? law_slip_rate(f, dir) : rf_v3(0, 0, 0);
    if (wall >= 0)
        rf_wall_law(dir, &a, &du);
    double speed = rf_v3_norm(m->s.v);
    seg_event ev = {EV_MAX_TIME, m->t_end - m->s.t, 0, 0, {0}, 0.0};
    if (ev.t < 0)
        ev.t = 0;
    if (f->mode == LAW_SLIDE) {
        double dus = rf_v3_dot(du, dir);
        if (dus < 0)
            consider(&ev, EV_SLIP, rf_v3_norm(u0) / -dus);
    } else if (speed > 0) {
        double as = rf_v3_dot(a, dir);
        if (as < 0) {
            if (holds)
                consider(&ev, EV_REST, speed > m->scene->sim->stop_speed
                                            ? (speed - m->scene->sim->stop_speed) / -as : 0.0);
            else
                consider(&ev, EV_ZERO, speed / -as);
        }
    }
    rf_arc arc = {m->s.p, m->s.v, a};
    int edge = 0;
    double tx = exit_time(m, fe, &arc, ev.t, wall, &edge);
    if (tx < ev.t) {
        consider(&ev, EV_EXIT, tx);
        ev.edge = edge;
        ev.slot = 0;
    }
    rf_vec3 z = rf_v3(0, 0, 0);
    int slide = f->mode == LAW_SLIDE;
    rf_spin_law spin = rf_spin_law_of(m, f->n, slide ? u0 : z, slide ? du : z);
    closed_finish(m, &arc, &spin, &ex, &ev);
    return dispatch(m, &ev, a, fe);
}

/* ---- segments off the fall line (closed form, hodograph.c) ------------------------- */

/* The path of a segment off the fall line: the state y (centre relative to the start,
 * v, u) as a function of the hodograph's parameter. */
typedef struct seg_path {
    const face_dyn *f;
    rf_hodograph h;
    rf_vec3 v0, u0; /* the slipping sphere: v = v0 + (1 - 1/K) g_t t + (u - u0) / K */
    double iK;      /* 1 / K */
} seg_path;

static void path_init(seg_path *P, const face_dyn *f, rf_vec3 v0, rf_vec3 u0)
{
    P->f = f, P->v0 = v0, P->u0 = u0;
    P->iK = 1.0 / f->K;
    if (f->mode == LAW_SLIDE)
        rf_hodograph_init(&P->h, u0, f->n, f->e1, f->G, f->K * f->mu * f->gn);
    else
        rf_hodograph_init(&P->h, v0, f->n, f->e1, f->k * f->G, f->k * f->c * f->gn);
}

static void y_set(double *y, rf_vec3 c, rf_vec3 v, rf_vec3 u)
{
    y[0] = c.x, y[1] = c.y, y[2] = c.z, y[3] = v.x, y[4] = v.y, y[5] = v.z;
    y[6] = u.x, y[7] = u.y, y[8] = u.z;
}
static rf_vec3 y_c(const double *y) { return rf_v3(y[0], y[1], y[2]); }
static rf_vec3 y_v(const double *y) { return rf_v3(y[3], y[4], y[5]); }
static rf_vec3 y_u(const double *y) { return rf_v3(y[6], y[7], y[8]); }

/* The hodograph's vector of a state: the slip of the slipping sphere, else the velocity. */
static rf_vec3 path_w(const seg_path *P, const double *y)
{
    return P->f->mode == LAW_SLIDE ? y_u(y) : y_v(y);
}

/* The parabola from p at velocity v that has moved by dc after h (no acceleration
 * for h = 0): a step's, for the searches, or its part up to an event. */
static rf_arc fit_arc(rf_vec3 p, rf_vec3 v, rf_vec3 dc, double h)
{
    rf_vec3 a = h > 0 ? rf_v3_scale(rf_v3_madd(dc, -h, v), 2.0 / (h * h)) : rf_v3(0, 0, 0);
    return (rf_arc){p, v, a};
}

/* Moves the rock along a path's step from y to ye (centre relative to c0) over h on
 * the step's parabola `arc`, the spin by the slip linear between them, and ends it in
 * ye's state, as the path, not the parabola, has it. */
static void path_advance(rf_motion *m, const face_dyn *f, const rf_arc *arc, double h,
                         rf_vec3 c0, const double *y, const double *ye)
{
    /* the law only serves the samples: the end's spin is set from ye */
    rf_spin_law spin;
    const rf_spin_law *sampled = NULL;
    if (rf_motion_samples(m)) {
        spin = rf_spin_law_over(m, f->n, y_u(y), y_u(ye), h);
        sampled = &spin;
    }
    rf_motion_advance(m, arc, h, sampled);
    m->s.p = rf_v3_add(c0, y_c(ye));
    m->s.v = y_v(ye);
    rf_set_spin(m, f->n, y_u(ye));
}

/* The state at parameter lam in y; returns its time from the segment's start. */
static double path_at(const seg_path *P, double lam, double *y)
{
    const face_dyn *f = P->f;
    rf_vec3 w, x;
    double t = rf_hodograph_at(&P->h, lam, &w, &x);
    if (f->mode != LAW_SLIDE) {
        y_set(y, x, w, rf_v3(0, 0, 0));
        return t;
    }
    double b = 1.0 - P->iK;
    rf_vec3 v = rf_v3_add(rf_v3_madd(P->v0, b * t, f->gt), rf_v3_scale(rf_v3_sub(w, P->u0), P->iK));
    rf_vec3 c = rf_v3_add(rf_v3_madd(rf_v3_scale(P->v0, t), 0.5 * b * t * t, f->gt),
                          rf_v3_scale(rf_v3_madd(x, -t, P->u0), P->iK));
    y_set(y, c, v, w);
    return t;
}

/* The parameter step from a state where the hodograph's vector is w: the path departs
 * from the step's parabola by at most about RF_PATH_DEV (the jerk B A sin(psi) / |w|
 * times h^3 / 40, h = dlambda |w| / A) and the step lasts about RF_PATH_MAX_DT at most.
 * |w| falls with lambda for k >= 1; for k < 1 the step is at most 1 / (1 - k), over
 * which |w| grows by a factor e at most, so that the estimate of its length holds. */
static double path_step(const seg_path *P, rf_vec3 w)
{
    const rf_hodograph *h = &P->h;
    double wl = rf_v3_norm(w);
    double dl = RF_PATH_MAX_DT * h->A / wl;
    if (h->k < 1.0)
        dl = rf_fmin(dl, 1.0 / (1.0 - h->k));
    double jerk = h->k * h->A * fabs(rf_v3_dot(w, h->e2)) * wl;
    if (jerk > 0)
        dl = rf_fmin(dl, cbrt(40.0 * RF_PATH_DEV * h->A * h->A / jerk));
    return dl;
}

/* One step of a segment: parameters la to lb, starting ta after the segment's start and
 * lasting h; lg is the parameter last found for a time in it.  Events are located in
 * the parameter: the rate of an event function in it is its rate in time times
 * dt/dlambda = |w| / A. */
typedef struct seg_step {
    const seg_path *p;
    double la, lb, ta, h, lg;
} seg_step;

/* The state at parameter lam of the step in y; returns its time from the step's start. */
static double step_eval(const seg_step *s, double lam, double *y)
{
    return path_at(s->p, lam, y) - s->ta;
}

/* The parameter at time tau in [0, h] of the step. */
static double step_lam(seg_step *s, double tau)
{
    if (tau <= 0.0)
        return s->la;
    if (tau >= s->h)
        return s->lb;
    if (s->lg == s->la && s->lb < INFINITY)
        s->lg = s->la + (s->lb - s->la) * tau / s->h; /* the first: in proportion */
    return s->lg = rf_hodograph_lambda(&s->p->h, s->ta + tau, s->la, s->lb, s->lg);
}

/* The state at time tau in [0, h] of the step. */
static void step_at(seg_step *s, double tau, double *y) { step_eval(s, step_lam(s, tau), y); }

/* dlambda/dt at a state of the step. */
static double step_pace(const seg_step *s, const double *y)
{
    return s->p->h.A / rf_v3_norm(path_w(s->p, y));
}

/* The parameter a fraction r of the way from (llo, tlo) to (lhi, thi): of the parameter,
 * or of the time when lhi is infinite (the last step of a motion that ends). */
static double step_between(seg_step *s, double llo, double lhi, double tlo, double thi, double r)
{
    return lhi < INFINITY ? llo + (lhi - llo) * r : step_lam(s, tlo + (thi - tlo) * r);
}

/* Scalar event function at a state (relative centre c + c0). */
static double event_value(rf_motion *m, ev_kind kind, const seg_event *ev, const rf_face_edges *fe,
                          rf_vec3 c0, const double *y)
{
    rf_vec3 c = rf_v3_add(c0, y_c(y));
    switch (kind) {
    case EV_EXIT: /* level: how far beyond the edge it counts (0, or the tolerance) */
        return rf_v3_dot(fe->m[ev->edge], c) - fe->o[ev->edge] + ev->level;
    case EV_REST:
    case EV_ZERO:
        return rf_v3_norm2(y_v(y)) - ev->level * ev->level;
    case EV_CONTACT:
        return rf_feature_distance(m->terrain, &ev->con, c) - m->rho;
    case EV_LINE:
        return ev->line[2] * (c.x - ev->line[0]) + ev->line[3] * (c.y - ev->line[1]);
    default:
        return 0.0;
    }
}

/* Rate of change of the event function at a state (relative centre c + c0). */
static double event_rate(rf_motion *m, const face_dyn *f, ev_kind kind, const seg_event *ev,
                         const rf_face_edges *fe, rf_vec3 c0, const double *y)
{
    rf_vec3 v = y_v(y);
    switch (kind) {
    case EV_EXIT:
        return rf_v3_dot(fe->m[ev->edge], v);
    case EV_REST:
    case EV_ZERO: { /* the point mass and the rolling sphere */
        double vl = rf_v3_norm(v);
        return vl > 0 ? 2.0 * rf_v3_dot(v, law_accel(f, rf_v3_scale(v, 1.0 / vl))) : 0.0;
    }
    case EV_CONTACT: {
        const rf_contact *c = &ev->con;
        const rf_triangle *T = &m->terrain->tri[c->tri];
        if (c->kind == RF_FEAT_FACE)
            return rf_v3_dot(T->n, v);
        rf_vec3 p = rf_v3_add(c0, y_c(y));
        rf_vec3 q = rf_tri_vertex(T, c->index);
        if (c->kind == RF_FEAT_EDGE)
            q = rf_v3_closest_on_segment(q, rf_tri_vertex(T, c->index + 1), p);
        rf_vec3 d = rf_v3_sub(p, q);
        double dl = rf_v3_norm(d);
        return dl > 0 ? rf_v3_dot(d, v) / dl : 0.0;
    }
    case EV_LINE:
        return ev->line[2] * v.x + ev->line[3] * v.y;
    default:
        return 0.0;
    }
}

/* A bracket of the event on a step: parameters and times where the event function is
 * still positive (lo) and no longer (hi). */
typedef struct ev_bracket {
    double llo, lo, flo, lhi, hi, fhi;
} ev_bracket;

/* The bracket b narrowed (regula falsi, Illinois, in the parameter) to within
 * RF_TIME_TOL, ye holding the state at its hi on entry and on return; returns hi, a
 * time where the event has happened. */
static double narrow(rf_motion *m, ev_kind kind, const seg_event *ev, const rf_face_edges *fe,
                     rf_vec3 c0, seg_step *st, ev_bracket b, double x, double *ye)
{
    double tmp[9];
    int side = 0;
    for (int it = 0; it < 60 && b.hi - b.lo > RF_TIME_TOL; it++) {
        double t = step_eval(st, x, tmp);
        double ft = event_value(m, kind, ev, fe, c0, tmp);
        if (ft > 0) {
            b.llo = x, b.lo = t, b.flo = ft;
            if (side == 1)
                b.fhi *= 0.5; /* Illinois */
            side = 1;
        } else {
            b.lhi = x, b.hi = t, b.fhi = ft;
            memcpy(ye, tmp, sizeof tmp);
            if (side == -1)
                b.flo *= 0.5;
            side = -1;
            if (ft == 0.0)
                break;
        }
        x = step_between(st, b.llo, b.lhi, b.lo, b.hi, b.flo / (b.flo - b.fhi));
        if (!(x > b.llo && x < b.lhi))
            x = step_between(st, b.llo, b.lhi, b.lo, b.hi, 0.5);
    }
    return b.hi; /* the event has happened at hi */
}

/* Time in (0, h] where the event function crosses zero on the step from y, on
 * the closed-form path (regula falsi, Illinois, in the parameter), and in ye the state
 * there; -1 when it does not (the step's parabola was only close). */
static double locate_bracket(rf_motion *m, ev_kind kind, const seg_event *ev,
                             const rf_face_edges *fe, rf_vec3 c0, seg_step *st,
                             double flo, double guess, double *ye)
{
    double h = st->h;
    double llo = st->la, lo = 0.0, lhi = st->lb, hi = h;
    double fhi = 1.0;
    if (guess > 0 && guess < h) {
        /* just after the parabola's estimate, the usual bracket */
        lhi = step_lam(st, rf_fmin(h, guess + 1e-6 * h + 1e-12));
        hi = step_eval(st, lhi, ye);
        fhi = event_value(m, kind, ev, fe, c0, ye);
    }
    if (fhi > 0.0) {
        lhi = st->lb;
        hi = step_eval(st, lhi, ye);
        fhi = event_value(m, kind, ev, fe, c0, ye);
    }
    if (fhi > 0.0)
        return -1.0;
    double x = (guess > lo && guess < hi) ? step_lam(st, guess)
                                          : step_between(st, llo, lhi, lo, hi, flo / (flo - fhi));
    return narrow(m, kind, ev, fe, c0, st, (ev_bracket){llo, lo, flo, lhi, hi, fhi}, x, ye);
}

/* Time in [0, h] where the event function crosses zero on the closed-form path, and in
 * ye the state there; -1 when it does not cross (the step's parabola was only close).
 * Newton's method in the step's parameter from the parabola's estimate (the event
 * function's rate is known at every state): the time returned is where the event has
 * happened, within RF_TIME_TOL after the crossing; a bracketing regula falsi when
 * Newton's method leaves the bracket. */
static double locate(rf_motion *m, const face_dyn *f, ev_kind kind, const seg_event *ev,
                     const rf_face_edges *fe, rf_vec3 c0, seg_step *st, const double *y,
                     double guess, double *ye)
{
    double h = st->h;
    double f0 = event_value(m, kind, ev, fe, c0, y);
    int start = f0 <= 0.0, reentry = 0;
    int found_later = guess > 0.0 && guess < h;
    if (kind == EV_CONTACT && guess == 0.0 && f0 <= m->tol_len) {
        /* touching and approaching, as the search found it at the start */
        start = start || event_rate(m, f, kind, ev, fe, c0, y) < -RF_APPROACH_EPS;
    } else if (start && found_later &&
               (kind == EV_CONTACT || (kind == EV_EXIT && f0 >= -m->tol_len))) {
        /* found later, the rock moving out of the contact's reach or in over the edge
         * (a hair beyond it): the re-entry or the exit the parabola found, not the start */
        reentry = event_rate(m, f, kind, ev, fe, c0, y) > 0.0;
    }
    if (start && !reentry) {
        if (kind == EV_EXIT && !found_later && f0 >= -m->tol_len &&
            event_rate(m, f, kind, ev, fe, c0, y) > 0.0) {
            /* a hair beyond the edge (within the tolerance, as exit_time takes it) but
             * moving in, and beyond it by more at the step's end, where the step's
             * parabola saw no crossing: the exit where the path is the tolerance
             * beyond the edge.  Taken at the start, the rock left a face it was moving
             * into, which the flight leaves out, and fell through it. */
            seg_event beyond = *ev;
            beyond.level = m->tol_len;
            return locate_bracket(m, kind, &beyond, fe, c0, st, f0 + m->tol_len, guess, ye);
        }
        memcpy(ye, y, 9 * sizeof *ye);
        return 0.0;
    }
    if (found_later) {
        ev_bracket b = {st->la, 0.0, f0, st->lb, -1.0, 0.0};
        double lam = step_lam(st, guess);
        double tmp[9];
        for (int it = 0; it < 8; it++) {
            double t = step_eval(st, lam, tmp);
            double ft = event_value(m, kind, ev, fe, c0, tmp);
            double rate = event_rate(m, f, kind, ev, fe, c0, tmp);
            if (ft <= 0.0) {
                b.lhi = lam, b.hi = t, b.fhi = ft;
                memcpy(ye, tmp, sizeof tmp);
                /* past the crossing: done when it lies within the tolerance before */
                if (rate < 0.0 && -ft / rate >= -0.5 * RF_TIME_TOL)
                    return b.hi;
            } else {
                b.llo = lam, b.lo = t, b.flo = ft;
            }
            if (b.hi >= 0.0 && b.hi - b.lo <= RF_TIME_TOL)
                return b.hi;
            if (!(rate < 0.0))
                break;
            double dt = -ft / rate;
            if (ft > 0.0 && dt < 0.25 * RF_TIME_TOL)
                dt = 0.25 * RF_TIME_TOL; /* just past the crossing */
            double tn = t + dt;
            if (!(tn > b.lo && tn <= h && (b.hi < 0.0 || tn < b.hi)))
                break;
            lam = rf_fmax(st->la, rf_fmin(st->lb, lam + dt * step_pace(st, tmp)));
        }
        if (b.hi >= 0.0 && !reentry) {
            /* Newton's method stopped short of the tolerance (the event function's
             * rounding at the root, a step's worth in time), with the event happened at
             * hi: narrowed within its bracket.  The parabola's estimate and the step's
             * end, which the search below starts from, can both lie before the path's
             * crossing and after its return (a short excursion over an edge): a point
             * mass left its face over the one edge, was taken out over another, and fell
             * through the face beyond. */
            return narrow(m, kind, ev, fe, c0, st, b, step_between(st, b.llo, b.lhi, b.lo, b.hi, 0.5),
                          ye);
        }
    }
    if (reentry) {
        /* no bracket from the start: the search's estimate on the step */
        step_at(st, guess, ye);
        return guess;
    }
    return locate_bracket(m, kind, ev, fe, c0, st, f0, guess, ye);
}

/* The time of the step's scene event found at ts on its parabola, and in ye the state
 * there.  A measure's crossing is located on the path itself: the parabola departs from
 * it by up to about RF_PATH_DEV, and a state a hair short of the line would have the
 * next step find the same crossing again just after its start.  On the line (a hair
 * beyond), the next step sees it as the one recorded. */
static double scene_time(rf_motion *m, const face_dyn *f, seg_event *ev, const rf_face_edges *fe,
                         rf_vec3 c0, seg_step *st, const rf_arc *arc, const double *y, double ts,
                         double *ye)
{
    if (m->scene_pending == RF_SCENE_MEASURE && ts > 0.0) {
        const rf_crossing *cr = &m->crossings[0];
        const double *A = &m->scene->measures[cr->measure].line.xy[2 * cr->segment], *B = A + 2;
        double nx = A[1] - B[1], ny = B[0] - A[0], len = hypot(nx, ny);
        rf_vec3 v = rf_arc_vel(arc, ts);
        if (nx * v.x + ny * v.y > 0)
            len = -len; /* the normal towards the side the rock comes from */
        ev->line[0] = A[0], ev->line[1] = A[1], ev->line[2] = nx / len, ev->line[3] = ny / len;
        double te = locate(m, f, EV_LINE, ev, fe, c0, st, y, ts, ye);
        if (te > 0.0)
            return te;
    }
    step_at(st, ts, ye);
    return ts;
}

static rf_surface_end face_path(rf_motion *m, const face_dyn *f, rf_vec3 u0, const rf_face_edges *fe,
                                int holds)
{
    rf_support ex = segment_exclusion(m);
    seg_path P;
    path_init(&P, f, m->s.v, u0);
    int slide = f->mode == LAW_SLIDE;
    double weps = slide ? RF_SLIP_EPS : RF_SPEED_EPS;
    rf_vec3 c0 = m->s.p;
    double y[9], yn[9];
    y_set(y, rf_v3(0, 0, 0), m->s.v, slide ? u0 : rf_v3(0, 0, 0));
    double lam = 0.0, t = 0.0, tcap = m->t_end - m->s.t;
    double stop = m->scene->sim->stop_speed;
    for (long steps = 0;; steps++) {
        if (t >= tcap)
            return RF_SURF_MAX_TIME;
        if (steps > RF_PATH_MAX_STEPS)
            return RF_SURF_CONTINUE; /* start a fresh segment */
        if (rf_v3_norm(path_w(&P, y)) <= weps) {
            if (!slide) {
                m->s.v = rf_v3(0, 0, 0);
                return RF_SURF_CONTINUE; /* from rest: a closed-form segment */
            }
            m->sup.rolling = 1; /* the slip has vanished */
            rf_set_spin(m, f->n, rf_v3(0, 0, 0));
            rf_motion_event(m);
            return RF_SURF_CONTINUE;
        }
        seg_step st = {&P, lam, lam + path_step(&P, path_w(&P, y)), t, 0.0, lam};
        double tb = path_at(&P, st.lb, yn);
        if (P.h.k > 1.0 && rf_v3_norm(path_w(&P, yn)) <= weps) {
            st.lb = INFINITY; /* on to the end, where w vanishes */
            tb = path_at(&P, st.lb, yn);
        }
        if (tb > tcap) {
            st.lb = rf_hodograph_lambda(&P.h, tcap, lam, st.lb, lam);
            path_at(&P, st.lb, yn);
            tb = tcap;
        }
        double hs = tb - t;
        st.h = hs;
        /* the step [t, t + hs]: its parabola, for the searches */
        rf_vec3 cn = y_c(yn), vn = y_v(yn);
        rf_vec3 ck = rf_v3_add(c0, y_c(y)), vk = y_v(y);
        rf_arc arc = fit_arc(ck, vk, rf_v3_sub(cn, y_c(y)), hs);
        rf_vec3 cabs = rf_v3_add(c0, cn);
        /* the step's events; again without an edge or contact of its parabola that the
         * path does not cross or make, which may have hidden a later event */
        rf_contact skip[RF_PATH_MAX_SKIPS];
        int nskip = 0, skip_edge = -1;
        seg_event ev;
        double te, ts, tx, ye[9];
        for (;;) {
            ev = (seg_event){EV_NONE, hs, 0, 0, {0}, 0.0};
            double guess = -1;
            st.lg = st.la;
            int edge = 0;
            tx = exit_time(m, fe, &arc, hs, skip_edge, &edge);
            int outside = 0;
            for (int k = 0; k < 3; k++) {
                if (k != skip_edge && rf_v3_dot(fe->m[k], cabs) - fe->o[k] < -m->tol_len) {
                    outside = 1;
                    if (!(tx < hs))
                        edge = k, tx = hs;
                }
            }
            if (tx < hs || outside) {
                ev.kind = EV_EXIT, ev.t = tx, ev.edge = edge;
                guess = tx;
            }
            /* rest, or a speed so small that friction's direction is undefined: stop
             * there and go on from rest (along the fall line) */
            double level = holds ? stop : RF_SPEED_EPS;
            /* unless the rock leaves the face first, still faster than that (its speed
             * falls all along): a point mass slowing to rest beyond an edge of its face
             * rested 2.5 mm under the steeper face beyond a valley line */
            if (!slide && rf_v3_norm(vn) <= level && rf_v3_norm(vk) > level &&
                !(ev.kind == EV_EXIT && rf_v3_norm(rf_arc_vel(&arc, ev.t)) > level)) {
                ev.kind = holds ? EV_REST : EV_ZERO, ev.t = hs, ev.level = level;
                guess = -1;
            }
            if (!m->point && !m->centre) {
                rf_contact con;
                double tl = rf_fmin(hs, ev.t + 0.1 * hs);
                if (rf_contact_search_near(m, &arc, tl, &ex, skip, nskip, &con) && con.t <= ev.t) {
                    ev.kind = EV_CONTACT, ev.t = con.t, ev.con = con;
                    guess = con.t;
                }
            }
            /* scene events on the step's parabola, before any terrain event */
            ts = rf_scene_horizon(m, &arc, ev.t);
            if (m->scene_pending && ts < ev.t) {
                ev.kind = EV_SCENE, ev.t = ts;
            } else {
                m->scene_pending = 0;
            }
            te = -1.0;
            if (ev.kind == EV_SCENE) {
                te = scene_time(m, f, &ev, fe, c0, &st, &arc, y, ts, ye);
            } else if (ev.kind == EV_EXIT && tx <= 0.0) {
                te = 0.0;
                memcpy(ye, y, sizeof ye);
            } else if (ev.kind != EV_NONE) {
                te = locate(m, f, ev.kind, &ev, fe, c0, &st, y, guess, ye);
            }
            if (te >= 0.0 || ev.kind == EV_NONE)
                break;
            if (ev.kind == EV_CONTACT && nskip < RF_PATH_MAX_SKIPS)
                skip[nskip++] = ev.con;
            else if (ev.kind == EV_EXIT && skip_edge < 0)
                skip_edge = ev.edge;
            else
                break;
        }
        if (te >= 0.0) {
            rf_arc ea = fit_arc(ck, vk, rf_v3_sub(y_c(ye), y_c(y)), te);
            path_advance(m, f, &ea, te, c0, y, ye);
            return dispatch(m, &ev, law_accel(f, f->e1), fe);
        }
        path_advance(m, f, &arc, hs, c0, y, yn);
        memcpy(y, yn, sizeof y);
        lam = st.lb;
        t = tb;
    }
}

/* ---- one face ----------------------------------------------------------------------- */

static int along(rf_vec3 x, rf_vec3 e1)
{
    double xl = rf_v3_norm(x);
    return xl == 0.0 || rf_v3_norm(rf_v3_cross(x, e1)) <= 1e-12 * xl;
}

/* Centre mode: 1 when face `to` lies above the centre's reach and the rock cannot pay
 * the lift onto it (centre_lift would reflect it). */
static int is_wall(const rf_motion *m, int32_t to)
{
    return to >= 0 && wall_for(m, to, rf_motion_energy(m));
}

/* Centre mode: the edge of the support's column that the centre lies on and is pressed
 * against by the surface law, beyond which lies a face whose offset plane is above the
 * centre and which the rock cannot pay the lift onto: a wall (centre_lift reflects the
 * velocity into it), along which the rock moves on.  -1 when none.  Without it, the
 * rock left the face over that edge, was reflected and turned back into it, ever more
 * nearly along it, at every event in no time. */
static int wall_edge(rf_motion *m, const face_dyn *f, const rf_face_edges *fe, rf_vec3 dir,
                     rf_vec3 *L)
{
    const rf_terrain *t = m->terrain;
    int32_t from = m->sup.tri[0];
    const rf_triangle *F = &t->tri[from];
    for (int k = 0; k < 3; k++) {
        if (!on_edge(m, fe, k, m->s.p) ||
            rf_v3_dot(fe->m[k], m->s.v) > RF_APPROACH_EPS ||
            !(rf_v3_dot(fe->m[k], law_accel(f, dir)) < 0))
            continue;
        /* into it slower than the stay speed: the wall keeps it (as a face does) */
        *L = edge_dir(F, k);
        if (rf_v3_norm(rf_in_plane(m->s.v, *L)) > m->v_stay)
            continue;
        if (is_wall(m, face_over_edge(t, from, k, fe)))
            return k;
    }
    return -1;
}

/* Centre mode: 1 when the wall slide along dir has the centre at the end of its wall,
 * where it would enter a face that is a wall too: a corner. */
static int wall_corner(const rf_motion *m, const rf_face_edges *fe, int wall, rf_vec3 dir)
{
    int at_end = 0; /* on another edge of the column, moving out over it */
    for (int k = 0; k < 3; k++)
        at_end |= k != wall && on_edge(m, fe, k, m->s.p) &&
                  rf_v3_dot(fe->m[k], dir) < 0;
    return at_end && is_wall(m, rf_face_beyond(m->terrain, m->sup.tri[0], m->s.p, dir));
}

/* Centre mode: the rock on its face meets the wall at column edge `wall` (direction
 * L): it keeps the velocity's part along it (the rest counts as an impact); a slipping
 * sphere's slip across the wall is taken by friction at its contact, the wall's push
 * keeping the centre along it (the spin changes, and energy is lost); in a corner of
 * two walls it stops.  Returns RF_SURF_REST, or RF_SURF_CONTINUE when it stopped in a
 * corner and goes on from rest; else -1: it moves along the wall in direction *dir
 * with the slip *u, under the law *f (set up anew when it rolls), and *stays tells
 * whether friction holds it there. */
static int wall_meet(rf_motion *m, face_dyn *f, const rf_face_edges *fe, int wall, rf_vec3 L,
                     rf_vec3 *dir, rf_vec3 *u, int *stays)
{
    double s = rf_v3_dot(m->s.v, L), gl = rf_v3_dot(f->gt, L);
    double e0 = rf_motion_energy(m);
    double vin = rf_v3_norm(rf_in_plane(m->s.v, L));
    m->s.v = rf_v3_scale(L, s);
    *dir = rf_v3_scale(L, (s != 0 ? s : gl) < 0 ? -1.0 : 1.0);
    *u = rf_v3(0, 0, 0);
    *stays = 0;
    if (wall_corner(m, fe, wall, *dir)) {
        /* wedged in the corner, it stops; it rests when gravity presses it in, else it
         * goes on from rest */
        m->s.v = rf_v3(0, 0, 0);
        m->s.w = rf_v3(0, 0, 0);
        m->sup.rolling = 1;
        count_impact(m, e0, vin + fabs(s));
        return rf_v3_dot(f->gt, *dir) >= 0 ? RF_SURF_REST : RF_SURF_CONTINUE;
    }
    int slide = f->mode == LAW_SLIDE;
    if (slide) {
        *u = rf_in_plane(rf_slip_of(m, f->n), rf_v3_cross(f->n, L));
        rf_set_spin(m, f->n, *u);
    }
    count_impact(m, e0, vin);
    if (slide) {
        /* it slides along the wall the way it slips; with no slip along it, one grows
         * from zero when gravity along it exceeds what friction holds (|g_l| > K mu
         * g_n, as rf_roll_holds on a face), else it rolls along the wall.  Returning to
         * roll from here (the face's own test, with the part of gravity across the
         * wall, slides it again) went back and forth between the two laws at every
         * event, in no time. */
        double ul = rf_v3_dot(*u, L);
        double way = fabs(ul) > RF_SLIP_EPS ? ul : (fabs(gl) > f->K * f->mu * f->gn ? gl : 0.0);
        if (way != 0.0) {
            *dir = rf_v3_scale(L, way < 0 ? -1.0 : 1.0);
            return -1;
        }
        m->sup.rolling = 1;
        *u = rf_v3(0, 0, 0);
        rf_set_spin(m, f->n, *u);
        face_setup(m, f->n, f); /* rolling: no slip */
    }
    *stays = fabs(gl) <= f->c * f->gn;
    if (fabs(s) <= m->scene->sim->stop_speed && *stays)
        return RF_SURF_REST;
    return -1;
}

/* Centre mode: the rock moves along the wall at column edge `wall` (wall_meet), with
 * the part of the law's acceleration along it. */
static rf_surface_end wall_step(rf_motion *m, face_dyn *f, const rf_face_edges *fe, int wall,
                                rf_vec3 L)
{
    rf_vec3 dir, u;
    int stays;
    int end = wall_meet(m, f, fe, wall, L, &dir, &u, &stays);
    if (end >= 0)
        return (rf_surface_end)end;
    return face_closed(m, f, dir, u, fe, stays, wall);
}

int rf_wall_meet(rf_motion *m, const rf_face_edges *col, int edge, int *wall, rf_vec3 *dir)
{
    *wall = -1;
    if (!on_edge(m, col, edge, m->s.p))
        return -1;
    int32_t from = m->sup.tri[0];
    const rf_triangle *T = &m->terrain->tri[from];
    face_dyn f;
    face_setup(m, T->n, &f);
    rf_vec3 u = m->sup.rolling ? rf_v3(0, 0, 0) : rf_slip_of(m, T->n);
    /* the face the rock would enter there (rf_leave_face), which at a vertex need not
     * be the one over the edge's middle */
    rf_vec3 acc = law_accel(&f, law_dir(&f, m->s.v, u));
    if (!is_wall(m, rf_face_after(m, from, edge, col, m->s.p, acc)))
        return -1;
    int stays;
    int end = wall_meet(m, &f, col, edge, edge_dir(T, edge), dir, &u, &stays);
    if (end < 0)
        *wall = edge;
    return end;
}

static rf_surface_end face_step(rf_motion *m)
{
    int32_t tri = m->sup.tri[0];
    const rf_triangle *T = &m->terrain->tri[tri];
    m->s.v = rf_in_plane(m->s.v, T->n);
    face_dyn f;
    rf_vec3 u0 = rf_v3(0, 0, 0);
    if (!m->point)
        u0 = rf_face_slip(m, T->n);
    face_setup(m, T->n, &f);
    if (f.mode == LAW_ROLL) {
        if (!rf_roll_holds(m, T->n)) {
            m->sup.rolling = 0;
            face_setup(m, T->n, &f);
            u0 = rf_v3(0, 0, 0);
        }
    }
    double speed = rf_v3_norm(m->s.v);
    int holds = rf_surface_holds(m);
    if (speed <= m->scene->sim->stop_speed && f.mode != LAW_SLIDE && holds)
        return RF_SURF_REST;
    rf_face_edges fe;
    edges_setup(m, T, &fe);
    rf_vec3 dir = law_dir(&f, m->s.v, u0);
    int closed = f.G == 0.0 || along(f.mode == LAW_SLIDE ? u0 : m->s.v, f.e1);
    rf_vec3 L;
    int wall = m->centre ? wall_edge(m, &f, &fe, dir, &L) : -1;
    if (wall >= 0)
        return wall_step(m, &f, &fe, wall, L);
    if (closed)
        return face_closed(m, &f, dir, u0, &fe, holds, -1);
    return face_path(m, &f, u0, &fe, holds);
}

/* ---- a crease ---------------------------------------------------------------------- */

rf_crease_kind rf_crease_law(rf_motion *m, rf_crease *cr)
{
    const rf_terrain *t = m->terrain;
    const rf_triangle *A = &t->tri[m->sup.tri[0]], *B = &t->tri[m->sup.tri[1]];
    double xA = 0.0, xB = 0.0; /* crease_forces may fail before setting them */
    rf_vec3 l;
    if (rf_crease_forces(A->n, B->n, &xA, &xB, &l) || xA < 0 || xB < 0) {
        rf_crease_ends(m, m->sup.tri[xA < 0 ? 1 : 0], m->sup.left);
        return RF_CREASE_ENDED;
    }
    double s = rf_v3_dot(m->s.v, l);
    if (s < 0) {
        l = rf_v3_scale(l, -1.0);
        s = -s;
    }
    m->s.v = rf_v3_scale(l, s);
    double gl = -G_ACC * l.z, N = xA + xB;
    int rolling = !m->point && m->sup.rolling;
    if (rolling && (1.0 - rf_roll_factor(m->body, m->rho)) * fabs(gl) > m->sup.mu * N)
        m->sup.rolling = rolling = 0; /* friction cannot make it roll down the crease */
    double k = rolling ? rf_roll_factor(m->body, m->rho) : 1.0;
    double c = rolling ? m->sup.mu_r : m->sup.mu;
    cr->holds = fabs(gl) <= c * N;
    cr->rolling = rolling;
    if (s <= m->scene->sim->stop_speed && cr->holds)
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

rf_spin_law rf_crease_roll(const rf_motion *m)
{
    const rf_terrain *t = m->terrain;
    rf_vec3 nm = rf_v3_unit(rf_v3_add(t->tri[m->sup.tri[0]].n, t->tri[m->sup.tri[1]].n));
    rf_vec3 z = rf_v3(0, 0, 0);
    return (rf_spin_law){nm, 0.0, z, z};
}

static rf_surface_end crease_step(rf_motion *m)
{
    rf_crease cr;
    switch (rf_crease_law(m, &cr)) {
    case RF_CREASE_ENDED: return RF_SURF_CONTINUE;
    case RF_CREASE_REST: return RF_SURF_REST;
    case RF_CREASE_MOVES: break;
    }
    const rf_terrain *t = m->terrain;
    rf_support ex = segment_exclusion(m);
    double stop = m->scene->sim->stop_speed;
    rf_vec3 a = rf_v3_scale(cr.l, cr.as);
    seg_event ev = {EV_MAX_TIME, rf_fmax(0.0, m->t_end - m->s.t), 0, 0, {0}, 0.0};
    if (cr.as < 0 && cr.s > 0) {
        if (cr.holds)
            consider(&ev, EV_REST, (cr.s - stop) / -cr.as);
        else
            consider(&ev, EV_ZERO, cr.s / -cr.as);
    }
    rf_arc arc = {m->s.p, m->s.v, a};
    rf_face_edges fe[2];
    for (int slot = 0; slot < 2; slot++) {
        const rf_triangle *S = &t->tri[m->sup.tri[slot]];
        edges_setup(m, S, &fe[slot]);
        int edge = 0;
        /* not over the edge the faces share: the contact points move along it (the
         * point mass on it), and the crease's direction, from two nearly parallel
         * normals, may stray from it by a hair (in centre mode the centre lies over
         * one face, beyond the other's column, and the crease ends there) */
        int shared = m->centre ? -1 : shared_edge(S, &t->tri[m->sup.tri[1 - slot]]);
        double tx = exit_time(m, &fe[slot], &arc, ev.t, shared, &edge);
        if (tx < ev.t) {
            consider(&ev, EV_EXIT, tx);
            ev.edge = edge;
            ev.slot = slot;
        }
    }
    rf_spin_law roll;
    if (cr.rolling)
        roll = rf_crease_roll(m);
    closed_finish(m, &arc, cr.rolling ? &roll : NULL, &ex, &ev);
    return dispatch(m, &ev, a, &fe[ev.slot]);
}

rf_surface_end rf_surface_step(rf_motion *m)
{
    return m->sup.n == 2 ? crease_step(m) : face_step(m);
}
