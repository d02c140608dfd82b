/* progress.c - the start of a trajectory, the watch on its progress and the rescue of
 * a rock that makes none; shared by both engines. */
#include "engine/progress.h"

#include <math.h>
#include <string.h>

#include "engine/contact.h"
#include "engine/face_entry.h"
#include "engine/feature.h"
#include "engine/geometry.h"
#include "engine/rock.h"

/* rf_motion_start without the progress watch. */
static int place_start(rf_motion *m)
{
    const rf_terrain *t = m->cfg.terrain;
    int32_t tri = rf_terrain_locate(t, m->rock.s.p.x, m->rock.s.p.y);
    if (tri < 0)
        return RF_END_EXITED;
    m->rock.sup.n = 0;
    m->rock.sup.left = -1;
    m->rock.flight_ex.n = 0;
    rf_contact c;
    memset(&c, 0, sizeof c);
    double dist;
    if (m->cfg.point || m->cfg.centre) {
        const rf_triangle *T = RF_FACE(m, tri);
        dist = rf_v3_dot(T->n, m->rock.s.p) - T->d;
        c.tri = tri;
        c.kind = RF_FEAT_FACE;
        c.n = T->n;
        c.point = rf_v3_madd(m->rock.s.p, -dist, T->n);
        if (m->cfg.point && T->n.z > 0) {
            /* the point's height above the face, measured vertically */
            double zs = rf_triangle_z_at(T, m->rock.s.p.x, m->rock.s.p.y);
            dist = (m->rock.s.p.z - zs) * T->n.z;
        }
    } else {
        /* a sphere into the terrain (released in a hollow, or below the ground) is
         * pushed out of the feature nearest its centre; when that leaves it in another
         * one or under the ground, it is raised on its vertical instead, until it just
         * touches the terrain */
        const rf_triangle *T = RF_FACE(m, tri);
        double dp = rf_v3_dot(T->n, m->rock.s.p) - T->d;
        if (dp < m->cfg.rho)
            m->rock.s.p = rf_v3_madd(m->rock.s.p, m->cfg.rho - dp, T->n);
        dist = rf_closest_feature(m, m->rock.s.p, m->cfg.rho + 1.0, &c);
        if (dist < m->cfg.rho - m->cfg.tol_len) {
            rf_vec3 p0 = m->rock.s.p;
            m->rock.s.p = rf_v3_madd(m->rock.s.p, m->cfg.rho - dist, c.n);
            dist = rf_closest_feature(m, m->rock.s.p, m->cfg.rho + 1.0, &c);
            /* a push that leaves it in the terrain or puts it under the ground (clear
             * of every feature, but below them) is not taken */
            int32_t under = rf_terrain_locate(t, m->rock.s.p.x, m->rock.s.p.y);
            if (dist < m->cfg.rho - m->cfg.tol_len || under < 0 ||
                rf_triangle_plane_distance(RF_FACE(m, under), m->rock.s.p) < m->cfg.rho - m->cfg.tol_len) {
                m->rock.s.p = p0;
                m->rock.s.p.z = rf_clear_height(m, p0);
                dist = rf_closest_feature(m, m->rock.s.p, m->cfg.rho + 1.0, &c);
            }
        }
    }
    if (!(dist <= m->cfg.rho + RF_START_TOUCH))
        return -1; /* in the air */
    double gap;
    if (m->cfg.point && RF_FACE(m, c.tri)->n.z > 0)
        m->rock.s.p.z = rf_triangle_z_at(RF_FACE(m, c.tri), m->rock.s.p.x, m->rock.s.p.y);
    else if (m->cfg.centre && dist < m->cfg.rho)
        m->rock.s.p = rf_v3_add(m->rock.s.p, rf_centre_lift_move(m, RF_FACE(m, c.tri), &gap));
    else if (c.kind == RF_FEAT_FACE)
        m->rock.s.p = rf_v3_madd(m->rock.s.p, m->cfg.rho - dist, c.n);
    double vn = rf_v3_dot(m->rock.s.v, c.n);
    if (vn > m->cfg.v_stay)
        return -1; /* launched off the ground */
    if (c.kind == RF_FEAT_FACE && vn > -m->cfg.v_stay) {
        rf_surface_enter(m, c.tri);
        return -1;
    }
    rf_contact_resolve(m, &c);
    return -1;
}

int rf_motion_start(rf_motion *m)
{
    int end = place_start(m);
    if (end < 0) {
        m->book.stall_t = m->rock.s.t;
        m->book.creep_p = m->rock.s.p;
    }
    return end;
}

/* The height of face T's offset plane (r above it) on the vertical through p. */
static double offset_plane_z(const rf_motion *m, const rf_triangle *T, rf_vec3 p)
{
    return rf_triangle_z_at(T, p.x, p.y) + m->cfg.rho / T->n.z;
}

/* Of the columns of upward faces holding p within `reach`, the one whose offset plane
 * is highest there (highest = 1) or lowest (0); tri, unless -1, counts as holding p.
 * -1 when none does. */
static int32_t column_extreme(rf_motion *m, rf_vec3 p, double reach, int32_t tri, int highest)
{
    const rf_terrain *t = m->cfg.terrain;
    double sign = highest ? 1.0 : -1.0; /* the lowest is the highest of -z */
    double best = tri >= 0 ? sign * offset_plane_z(m, RF_TRI(t, tri), p) : -INFINITY;
    int32_t skip = tri;
    size_t n = rf_gather(m, p.x - reach, p.y - reach, p.x + reach, p.y + reach);
    for (size_t i = 0; i < n; i++) {
        int32_t k = m->ws->cand[i];
        const rf_triangle *T = RF_TRI(t, k);
        if (k == skip || !(T->n.z > 0))
            continue;
        double z = sign * offset_plane_z(m, T, p);
        if (z > best && rf_in_column(T, p, -reach))
            best = z, tri = k;
    }
    return tri;
}

int32_t rf_highest_column(rf_motion *m, int32_t tri)
{
    return column_extreme(m, m->rock.s.p, m->cfg.tol_len, tri, 1);
}

/* Centre mode: the rock wedged among walls, at p before the rescue's free motion, is
 * put in the column, of those within a micrometre of p (RF_SETTLE_REACH length
 * tolerances: a rock reflected off a wall lies a few tolerances beyond the border of
 * the column it came from), whose offset plane is lowest there (it stood on that one or
 * higher), moved towards the column's centroid until it is inside by twice the length
 * tolerance, where no other column holds it, and lifted onto that plane should it be
 * under it (the least lift that leaves it over the terrain; none usually).  Returns 0,
 * or -1 when no column will do (the rock is left where it is). */
static int settle_in_lowest_column(rf_motion *m, rf_vec3 p)
{
    const rf_terrain *t = m->cfg.terrain;
    double tol = m->cfg.tol_len;
    int32_t best = column_extreme(m, p, RF_SETTLE_REACH * tol, -1, 0);
    if (best < 0)
        return -1;
    const rf_triangle *T = RF_TRI(t, best);
    /* the least part f of the way to the centroid g that puts it inside by 2 tol: the
     * distances to the column's edges are linear along the way */
    rf_vec3 g = rf_v3((T->a.x + T->b.x + T->c.x) / 3.0, (T->a.y + T->b.y + T->c.y) / 3.0, p.z);
    rf_face_edges fe;
    rf_column_edges(T, &fe);
    double f = 0.0;
    for (int e = 0; e < 3; e++) {
        double sp = rf_v3_dot(fe.m[e], p) - fe.o[e], sg = rf_v3_dot(fe.m[e], g) - fe.o[e];
        if (sp < 2.0 * tol && sg > sp)
            f = fmax(f, (2.0 * tol - sp) / (sg - sp));
    }
    rf_vec3 q = rf_v3(p.x + fmin(f, 0.5) * (g.x - p.x), p.y + fmin(f, 0.5) * (g.y - p.y), p.z);
    if (!rf_in_column(T, q, tol) || column_extreme(m, q, tol, best, 1) != best)
        return -1;
    m->rock.s.p = q;
    double gap;
    m->rock.s.p = rf_v3_add(q, rf_centre_lift_move(m, T, &gap));
    return 0;
}

/* A full-contact sphere: the move that takes it out of the terrain it is in (its
 * centre within r plus the length tolerance of a feature): along the normal of the
 * nearest feature, where that leaves it clear of every feature and not under the face
 * under it; else up its vertical to where it is clear (an edge's normal has no side,
 * and a centre under a valley line would be pushed deeper).  Zero when it is clear. */
static rf_vec3 sphere_out(rf_motion *m)
{
    const rf_terrain *t = m->cfg.terrain;
    rf_vec3 p = m->rock.s.p;
    rf_contact c;
    double d = rf_closest_feature(m, p, m->cfg.rho + 1.0, &c);
    if (c.kind == RF_FEAT_FACE)
        d = rf_triangle_plane_distance(RF_FACE(m, c.tri), p);
    if (!(d < m->cfg.rho + m->cfg.tol_len))
        return rf_v3(0, 0, 0);
    rf_vec3 q = rf_v3_madd(p, m->cfg.rho + m->cfg.tol_len - d, c.n);
    rf_contact near;
    int32_t under = rf_terrain_locate(t, q.x, q.y);
    if (rf_closest_feature(m, q, m->cfg.rho + 1.0, &near) < m->cfg.rho - m->cfg.tol_len || under < 0 ||
        rf_triangle_plane_distance(RF_FACE(m, under), q) < 0) {
        q = p;
        q.z = rf_clear_height(m, p) + m->cfg.tol_len;
    }
    return rf_v3_sub(q, p);
}

/* Returns 1 when the rock rests: wedged again where a rescue last found it wedged
 * (centre mode), or too slow to pay its way out of the terrain (a full-contact
 * sphere). */
static int unstall(rf_motion *m)
{
    const rf_terrain *t = m->cfg.terrain;
    rf_vec3 p0 = m->rock.s.p;
    rf_arc arc = {m->rock.s.p, m->rock.s.v, rf_v3(0, 0, -RF_GRAVITY)};
    rf_motion_advance(m, &arc, RF_UNSTALL_TIME, NULL);
    rf_motion_note_energy(m);
    int32_t tri = rf_terrain_locate(t, m->rock.s.p.x, m->rock.s.p.y);
    if (tri >= 0) {
        const rf_triangle *T = RF_FACE(m, tri);
        rf_vec3 n = T->n; /* the velocity into the terrain is taken along it */
        if (m->cfg.centre) {
            tri = rf_highest_column(m, tri);
            T = RF_FACE(m, tri);
            n = T->n;
            double gap;
            /* onto the offset plane of the column now under the centre (Eq. 6), as a
             * centre moving over a column is lifted, and not along the normal, which
             * can end under the next column's plane.  Wedged among walls it cannot pay
             * the lift onto, it is stopped in the lowest column where it was wedged,
             * just inside it, and goes on from there (settle_in_lowest_column): a lift
             * is always paid, never given (docs/engine.md).  Wedged again within r of
             * where it was last wedged, it rests where it is. */
            rf_vec3 move = rf_centre_lift_move(m, T, &gap);
            if (gap > 0 && !rf_pay_lift(m, move)) {
                if (m->book.wedged && rf_v3_norm(rf_v3_sub(m->rock.s.p, m->book.wedge_p)) <= m->cfg.rho) {
                    if (rf_triangle_plane_distance(T, m->rock.s.p) < 0)
                        m->rock.s.p = rf_v3_add(m->rock.s.p, move); /* not under the face */
                    return 1;
                }
                m->book.wedged = 1;
                m->book.wedge_p = m->rock.s.p;
                if (settle_in_lowest_column(m, p0))
                    m->rock.s.p = rf_v3_add(m->rock.s.p, move);
                m->rock.s.v = rf_v3(0, 0, 0);
                m->rock.s.w = rf_v3(0, 0, 0);
            }
        } else if (m->cfg.point) {
            double dp = rf_triangle_plane_distance(T, m->rock.s.p);
            if (dp < m->cfg.tol_len)
                m->rock.s.p = rf_v3_madd(m->rock.s.p, m->cfg.tol_len - dp, T->n);
        } else {
            /* out of the terrain along the nearest feature's normal (sphere_out), paid
             * from the kinetic energy: not onto the offset plane of the face under the
             * centre, which reaches beyond the face the sphere touches */
            rf_vec3 move = sphere_out(m);
            if (rf_v3_norm(move) > 0) {
                if (!rf_pay_lift(m, move)) {
                    /* too slow to pay its way out: it rests out of the terrain (where
                     * it was, it could lie under a face) */
                    m->rock.s.p = rf_v3_add(m->rock.s.p, move);
                    return 1;
                }
                n = rf_v3_unit(move);
            }
        }
        double vn = rf_v3_dot(m->rock.s.v, n);
        if (vn < 0)
            m->rock.s.v = rf_v3_madd(m->rock.s.v, -vn, n);
    }
    m->rock.sup.n = 0;
    m->rock.flight_ex.n = 0;
    return 0;
}

int rf_progress(rf_motion *m, int events)
{
    double stop = m->cfg.scene->sim->stop_speed;
    if (events) {
        if (rf_v3_norm(m->rock.s.v) > stop ||
            rf_v3_norm(rf_v3_sub(m->rock.s.p, m->book.creep_p)) > RF_CREEP_DIST) {
            m->book.creep_p = m->rock.s.p;
            m->book.creep = 0;
        } else if (++m->book.creep > RF_CREEP_EVENTS) {
            return RF_END_REST;
        }
    }
    if (m->rock.s.t > m->book.stall_t + RF_STALL_TIME) {
        m->book.stall_t = m->rock.s.t;
        m->book.stall = 0;
    } else if (++m->book.stall > RF_STALL_EVENTS) {
        /* no progress in time: a rock wedged between features */
        if (rf_v3_norm(m->rock.s.v) <= stop)
            return RF_END_REST;
        return rf_rescue(m);
    }
    return -1;
}

int rf_rescue(rf_motion *m)
{
    if (++m->book.rescues > RF_MAX_RESCUES)
        return RF_END_MAX_TIME;
    if (unstall(m))
        return RF_END_REST;
    m->book.stall = 0;
    m->book.stall_t = m->rock.s.t;
    return RF_RESCUED;
}
