/* fixed_step.c - the fixed-step baseline: the paper's successive integration over time.
 *
 * The same model as the exact engine with `centre` contact (the paper's Eq. 6-7: only
 * the face under the centre counts), advanced with semi-implicit Euler steps of dt
 * instead of closed forms and root finding:
 *
 *   flight   v += g h, p += h v.  A step whose centre moves into another face's column,
 *            or below a face's offset plane, is tested as the exact engine tests a
 *            flight (the centre enters a column already within reach of its plane, or
 *            reaches the plane over the column) to find the contact on the step's
 *            straight piece; the exact engine's impact, lift and landing rules
 *            (rf_contact_resolve) handle it.
 *   surface  one face or a crease of two: v += h a with the surface laws (rf_surface_accel,
 *            the crease's line law), the slip integrated alongside for a slipping
 *            sphere.  A step ends early where the centre leaves its face's column (the
 *            exact engine's face exit: same plane, convex edge, concave edge, or off
 *            the terrain), or where the slip vanishes.  A step that would leave at
 *            once over an edge into a wall (centre mode: a face it cannot pay the lift
 *            onto) meets the wall as the exact engine does, and moves along it.
 *
 * Rest, rolling against slipping, coefficient draws and the stay threshold are those
 * of the exact engine, so the trajectories converge to it as dt -> 0 (first order);
 * the cost grows as 1/dt.  It is the reference for the speed-against-error report. */
#include "engine/fixed_step.h"

#include <math.h>

#include "engine/contact.h"
#include "engine/exit.h"
#include "engine/face_entry.h"
#include "engine/face_exit.h"
#include "engine/geometry.h"
#include "engine/progress.h"
#include "engine/rock.h"
#include "engine/scene_events.h"
#include "engine/surface.h"
#include "engine/surface_law.h"

/* ---- the column of a face (its xy projection) ------------------------------------- */

/* First time in [0, T] at which the centre p + v t leaves the column, not over edge
 * `skip` (-1: none; INFINITY when it does not); *edge receives the edge crossed. */
static double column_exit(const rf_motion *m, const rf_face_edges *c, rf_vec3 p, rf_vec3 v, double T,
                          int skip, int *edge)
{
    double best = INFINITY, tol = m->cfg.tol_len;
    for (int k = 0; k < 3; k++) {
        if (k == skip)
            continue;
        double e0 = rf_v3_dot(c->m[k], p) - c->o[k], e1 = rf_v3_dot(c->m[k], v);
        double t = INFINITY;
        if (e0 < -tol && (e1 <= RF_APPROACH_EPS || e0 + T * e1 <= tol))
            t = 0.0; /* already beyond the edge and not coming back */
        else if (e1 < -RF_APPROACH_EPS && e0 >= -RF_TOUCH_BAND * tol)
            t = e0 > 0 ? -e0 / e1 : 0.0;
        if (t <= T && t < best) {
            best = t;
            *edge = k;
        }
    }
    return best;
}

/* ---- leaving a face ----------------------------------------------------------------- */

/* The centre has reached edge `edge` of its single face: the next face is on the same
 * plane, rises (an impact on it; in centre mode also when the centre is below its
 * offset plane, which lifts it), or falls away (flight).  Returns -1 or an end. */
static int leave_face(rf_motion *m, int edge, const rf_face_edges *c, rf_vec3 acc)
{
    rf_surface_end r = rf_leave_face(m, 0, edge, c, acc);
    return r == RF_SURF_EXITED ? RF_END_EXITED : r == RF_SURF_STOPPED ? RF_END_STOPPED : -1;
}

/* ---- one step of each phase: -1 to go on, or an end reason ------------------------- */

/* Moves along the step's straight piece {p, ve} to te (<= the step h), offering it to
 * the scene events first; the velocity there is interpolated between v and ve, the spin
 * follows law (NULL: it stays), and the energy of that whole state is noted.
 * Returns 1 when a scene event cut the piece: the state is at the event, which the
 * caller hands to rf_scene_event. */
static int advance_piece(rf_motion *m, rf_vec3 ve, double te, double h, const rf_spin_law *law)
{
    rf_arc arc = {m->rock.s.p, ve, rf_v3(0, 0, 0)};
    rf_vec3 v0 = m->rock.s.v;
    double ts = rf_scene_horizon(m, &arc, te);
    int scene = m->scn.pending && ts < te;
    double tt = scene ? ts : te;
    /* the velocity changes linearly over the step, to ve at its end; the samples take
     * it so, and none is faster than the rock at either end */
    rf_arc vel = {m->rock.s.p, h > 0 ? v0 : ve,
                  h > 0 ? rf_v3_scale(rf_v3_sub(ve, v0), 1.0 / h) : rf_v3(0, 0, 0)};
    rf_motion_advance_split(m, &arc, &vel, tt, law);
    /* the end as the step's own interpolation rounds it (its results are kept) */
    m->rock.s.v = h > 0 ? rf_v3_add(v0, rf_v3_scale(rf_v3_sub(ve, v0), tt / h)) : ve;
    if (law && !m->cfg.point)
        m->rock.s.w = rf_spin_at(law, m->cfg.rho, m->rock.s.v, tt);
    rf_motion_note_energy(m);
    if (!scene)
        m->scn.pending = RF_SCENE_NONE;
    return scene;
}

/* The rock goes on in the direction of the step's velocity ve at the speed of its
 * time, where the step decides (the piece ended on a feature the velocity of its time
 * does not meet, and ve does): a piece of no time gains no speed (ve itself would add
 * the step's h a at an instant). */
static void take_step_direction(rf_motion *m, rf_vec3 ve)
{
    double vl = rf_v3_norm(ve);
    m->rock.s.v = vl > 0 ? rf_v3_scale(ve, rf_v3_norm(m->rock.s.v) / vl) : ve;
}

static int flight_step(rf_motion *m, double h)
{
    const rf_terrain *t = m->cfg.terrain;
    rf_vec3 p0 = m->rock.s.p;
    rf_vec3 ve = m->rock.s.v;
    ve.z -= RF_GRAVITY * h;
    rf_vec3 pe = rf_v3_madd(p0, h, ve);
    /* Eq. 6-7: a contact needs the centre in another face's column or below the offset
     * plane of the face under it at the step's end */
    int32_t tri0 = rf_terrain_locate(t, p0.x, p0.y);
    if (tri0 >= 0 &&
        rf_triangle_plane_distance(RF_FACE(m, tri0), p0) < -RF_TOUCH_BAND * m->cfg.tol_len &&
        rf_v3_dot(RF_FACE(m, tri0)->n, m->rock.s.v) < 0) {
        /* a centre under the face it is over, sinking further: the search finds no
         * entry into a plane the centre is already under, so it is rescued at once,
         * onto the highest offset plane there.  (Under the offset plane alone is left
         * to the stall rules: a rock wedged among walls is, and is stopped, or rests
         * when wedged there again.) */
        int end = rf_rescue(m);
        return end == RF_RESCUED ? -1 : end;
    }
    int32_t tri1 = rf_terrain_locate(t, pe.x, pe.y);
    double te = h;
    int hit = 0, out = 0;
    rf_contact c;
    if (tri1 != tri0 || tri1 < 0 ||
        rf_v3_dot(RF_FACE(m, tri1)->n, pe) - RF_FACE(m, tri1)->d - m->cfg.rho < m->cfg.tol_len) {
        /* the step's straight piece p0 + ve t, searched as the exact engine searches a
         * flight (Eq. 6-7: the centre moves over a column already within reach of its
         * plane, or reaches the plane over the column) */
        rf_arc piece = {p0, ve, rf_v3(0, 0, 0)};
        double tx = tri1 < 0 ? rf_terrain_exit_time(m, &piece, h) : h;
        hit = rf_flight_contact(m, &piece, tx, &c);
        te = hit ? c.t : tx;
        /* out only where the terrain's gaps end it: the step's end over a crack the
         * rock bridges (rf_terrain_exit_time) is not */
        out = !hit && tri1 < 0 && tx < h;
    }
    if (!hit && pe.z < t->zmin - m->cfg.rho - 1.0)
        out = 1; /* below every face */
    if (advance_piece(m, ve, te, h, NULL))
        return rf_surface_scene_event(m);
    if (hit) {
        /* the velocity at the contact is v + g t; when that leaves the face but the
         * step's velocity meets it, the rock made a hop shorter than the step and is
         * back on the face, in the step's direction */
        if (rf_v3_dot(m->rock.s.v, c.n) >= 0 && rf_v3_dot(ve, c.n) < 0)
            take_step_direction(m, ve);
        m->rock.flight_ex.n = 0;
        if (rf_scene_at_once(m) >= 0)
            return RF_END_STOPPED;
        rf_contact_resolve(m, &c);
        rf_motion_event(m);
        return -1;
    }
    return out ? RF_END_EXITED : -1;
}

/* What the steps on a face carry from one to the next: whether the step is the first
 * after an event, where a segment of the exact engine starts (whether a rolling sphere
 * can keep rolling is decided there), and the wall the rock moves along since it met
 * one (centre mode: the column edge, -1 for none, and the way along it). */
typedef struct face_run {
    int fresh;
    int wall;
    rf_vec3 dir;
} face_run;

/* The velocity v + h a at the end of a step on a face.  Friction stops the rock, it
 * does not push it back: where it would reverse the motion within the step (a rock
 * that does not slip), the step ends where the speed along the rock's way vanishes (*h
 * cut to that time, *zero set), and the next starts from rest - rest where the face
 * holds the rock, else down the fall line. */
static rf_vec3 step_velocity(const rf_motion *m, rf_vec3 a, int slide, double *h, int *zero)
{
    rf_vec3 v = m->rock.s.v;
    double speed = rf_v3_norm(v);
    rf_vec3 v1 = rf_v3_madd(v, *h, a);
    if (!slide && speed > 0 && rf_v3_dot(v1, v) < 0) {
        *h = speed / -(rf_v3_dot(a, v) / speed);
        v1 = rf_v3_madd(v, *h, a);
        *zero = 1;
    }
    return v1;
}

static int face_step(rf_motion *m, double h, face_run *run)
{
    int seg_start = run->fresh;
    run->fresh = 1;
    int32_t tri = m->rock.sup.tri[0];
    const rf_triangle *T = RF_FACE(m, tri);
    rf_vec3 n = T->n;
    m->rock.s.v = rf_in_plane(m->rock.s.v, n);
    rf_vec3 u = rf_v3(0, 0, 0);
    if (!m->cfg.point) {
        u = rf_face_slip(m, n);
        if (m->rock.sup.rolling && seg_start) {
            u = rf_v3(0, 0, 0);
            if (!rf_roll_holds(m, n))
                m->rock.sup.rolling = 0;
        } else if (m->rock.sup.rolling) {
            u = rf_v3(0, 0, 0);
        }
    }
    double speed = rf_v3_norm(m->rock.s.v);
    if (speed <= m->cfg.scene->sim->stop_speed && (m->cfg.point || m->rock.sup.rolling) &&
        rf_surface_holds(m))
        return RF_END_REST;
    if (seg_start)
        run->wall = -1;
    int slide = !m->cfg.point && !m->rock.sup.rolling;
    rf_vec3 du;
    rf_vec3 a;
    if (run->wall >= 0) {
        /* along the wall: the law along it, the wall taking the rest */
        a = rf_surface_accel(m, n, run->dir, run->dir, &du);
        rf_wall_law(run->dir, &a, &du);
    } else {
        a = rf_surface_accel(m, n, m->rock.s.v, u, &du);
    }
    /* a slipping sphere's step ends where the slip vanishes; it can only vanish where
     * friction K mu g_n exceeds the gravity component g_t, else it turns down the
     * fall line and grows */
    double hs = h;
    int slip_end = 0, can_stick = 0;
    if (slide) {
        double K = rf_slip_factor(m->cfg.body, m->cfg.rho);
        /* along a wall the slip ends where it vanishes, and the wall is met anew */
        can_stick = run->wall >= 0 ||
                    K * m->rock.sup.mu * RF_GRAVITY * n.z > RF_GRAVITY * sqrt(fmax(0.0, 1.0 - n.z * n.z));
        double ul = rf_v3_norm(u);
        double dus = ul > 0 ? rf_v3_dot(du, u) / ul : 0.0;
        if (can_stick && ul > 0 && dus < 0 && ul <= -dus * hs) {
            hs = ul / -dus;
            slip_end = 1;
        }
    }
    int zero = 0;
    rf_vec3 v1 = step_velocity(m, a, slide, &hs, &zero);
    rf_vec3 ve = rf_in_plane(v1, n);
    rf_vec3 u1 = rf_v3(0, 0, 0);
    if (slide && !slip_end) {
        u1 = rf_v3_madd(u, hs, du);
        if (can_stick && rf_v3_norm(u) > 0 && rf_v3_dot(u1, u) <= 0) {
            u1 = rf_v3(0, 0, 0);
            slip_end = 1;
        }
    }
    rf_face_edges col;
    rf_column_edges(T, &col);
    int edge = 0;
    double tx = column_exit(m, &col, m->rock.s.p, ve, hs, run->wall, &edge);
    double te = tx < hs ? tx : hs;
    /* the slip from u to u1 over the step */
    rf_spin_law law = rf_spin_law_over(m, n, u, u1, hs);
    int scene = advance_piece(m, ve, te, hs, &law);
    if (scene)
        return rf_surface_scene_event(m);
    if (tx == 0.0 && m->cfg.centre) {
        /* the step would leave over an edge the centre lies on at once: when a wall
         * lies beyond, the rock meets it, as the exact engine's segments do (a
         * reflection would be turned back by the next step's velocity, a step of no
         * time).  Out of a run along another wall, it is in their corner: it meets the
         * wall with the step's velocity, which the corner stops */
        if (run->wall >= 0) /* the edge left over is another (column_exit skips it) */
            take_step_direction(m, ve);
        int end = rf_wall_meet(m, &col, edge, &run->wall, &run->dir);
        if (end == RF_SURF_REST)
            return RF_END_REST;
        if (end >= 0 || run->wall >= 0) {
            rf_motion_event(m);
            run->fresh = end >= 0;
            return -1;
        }
    }
    if (tx <= hs) {
        /* the piece crossed the edge with the step's velocity; when the velocity of
         * its time does not leave over it (along the edge), the rock leaves in the
         * step's direction (else it flew back over the face it left, below its plane) */
        if (rf_v3_dot(col.m[edge], m->rock.s.v) >= -RF_APPROACH_EPS &&
            rf_v3_dot(col.m[edge], ve) < -RF_APPROACH_EPS)
            take_step_direction(m, ve);
        int end = leave_face(m, edge, &col, a);
        rf_motion_event(m);
        return end;
    }
    if (slip_end) {
        m->rock.sup.rolling = 1;
        rf_set_spin(m, n, rf_v3(0, 0, 0));
        rf_motion_event(m);
    } else if (zero) {
        m->rock.s.v = rf_v3(0, 0, 0);
        if (m->rock.sup.rolling)
            m->rock.s.w = rf_v3(0, 0, 0);
        rf_motion_event(m);
    } else {
        run->fresh = 0;
    }
    return -1;
}

/* A crease: the centre moves on the line where the two offset planes meet, with the
 * normal forces of both faces. */
static int crease_step(rf_motion *m, double h)
{
    rf_crease cr;
    switch (rf_crease_law(m, &cr)) {
    case RF_CREASE_ENDED: return -1;
    case RF_CREASE_REST: return RF_END_REST;
    case RF_CREASE_MOVES: break;
    }
    const rf_terrain *t = m->cfg.terrain;
    const rf_triangle *A = RF_TRI(t, m->rock.sup.tri[0]), *B = RF_TRI(t, m->rock.sup.tri[1]);
    double s1 = cr.s + h * cr.as;
    int zero = 0;
    if (s1 < 0) {
        /* friction stops it within the step: the step ends there (as on a face) */
        h = cr.s / -cr.as;
        s1 = 0.0;
        zero = 1;
    }
    rf_vec3 ve = rf_v3_scale(cr.l, s1);
    rf_face_edges col[2];
    int edge = 0, slot = 0;
    double tx = INFINITY;
    for (int k2 = 0; k2 < 2; k2++) {
        rf_column_edges(k2 == 0 ? A : B, &col[k2]);
        int e2 = 0;
        double t2 = column_exit(m, &col[k2], m->rock.s.p, ve, h, -1, &e2);
        if (t2 < tx)
            tx = t2, edge = e2, slot = k2;
    }
    double te = tx < h ? tx : h;
    rf_spin_law roll;
    if (cr.rolling)
        roll = rf_crease_roll(m);
    int scene = advance_piece(m, ve, te, h, cr.rolling ? &roll : NULL);
    if (scene)
        return rf_surface_scene_event(m);
    if (tx <= h) {
        /* the centre leaves one face's column: the crease goes on with the next face
         * on the same plane, or ends on the other face */
        int32_t from = m->rock.sup.tri[slot], other = m->rock.sup.tri[1 - slot];
        int32_t to = rf_face_after(m, from, edge, &col[slot], m->rock.s.p, rf_v3_scale(cr.l, cr.as));
        rf_motion_event(m);
        if (to >= 0 && rf_coplanar(RF_TRI(t, from), RF_TRI(t, to), m->cfg.tol_len)) {
            m->rock.sup.tri[slot] = to;
            m->rock.sup.left = from;
            return -1;
        }
        if (to < 0)
            return RF_END_EXITED;
        rf_crease_ends(m, other, from);
        return -1;
    }
    if (zero) {
        m->rock.s.v = rf_v3(0, 0, 0);
        if (cr.rolling)
            m->rock.s.w = rf_v3(0, 0, 0);
        rf_motion_event(m);
    }
    return -1;
}

/* ---- start, rescue and the loop ---------------------------------------------------- */

int rf_simulate_fixed_step(rf_motion *m)
{
    const double dt = m->cfg.scene->sim->dt > 0 ? m->cfg.scene->sim->dt : 1e-3;
    /* the paper's contact test (Eq. 6-7) whatever the project's contact option */
    m->cfg.centre = !m->cfg.point;
    int end = rf_motion_start(m);
    if (end >= 0)
        return end;
    face_run run = {1, -1, {0, 0, 0}};
    long marked = m->book.marked;
    /* the steps max_time takes and as many events as the exact engine may meet */
    double budget = ceil((m->cfg.t_end - m->rock.s.t) / dt) + RF_MAX_EVENTS;
    long cap = budget < RF_FIXED_MAX_STEPS ? (long)budget : (long)RF_FIXED_MAX_STEPS;
    for (;;) {
        if (m->rock.s.t >= m->cfg.t_end || ++m->book.events > cap || m->scn.trees_given_up)
            return RF_END_MAX_TIME;
        /* a slow rock's creep counts the steps that ended at an event, as the exact
         * engine counts its events (rf_progress) */
        end = rf_progress(m, m->book.marked != marked);
        marked = m->book.marked;
        if (end >= 0) /* after a rescue (RF_RESCUED), in flight: fresh as every flight */
            return end;
        double h = fmin(dt, m->cfg.t_end - m->rock.s.t);
        if (m->rock.sup.n == 0)
            m->book.rec->n_flights++;
        else
            m->book.rec->n_segments++;
        if (m->rock.sup.n == 1) {
            end = face_step(m, h, &run);
        } else {
            end = m->rock.sup.n == 0 ? flight_step(m, h) : crease_step(m, h);
            run.fresh = 1;
        }
        if (end >= 0)
            return end;
    }
}
