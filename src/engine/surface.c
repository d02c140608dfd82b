/* surface.c - the surface phase: rolling and sliding on one face, along a wall, or in a
 * crease of two faces, until the next event.
 *
 * Events: the contact point leaves the face (over a convex edge: flight or a roll
 * over the edge; a concave edge: impact on the next face; the same plane: carry on),
 * another face, edge or vertex is met (impact), the slip vanishes (rolling), the
 * velocity vanishes, the speed falls below stop_speed where friction holds (rest),
 * max_time. */
#include "engine/surface.h"

#include <math.h>

#include "engine/face_entry.h"
#include "engine/face_exit.h"
#include "engine/feature.h"
#include "engine/impact.h"
#include "engine/path.h"
#include "engine/rock.h"
#include "engine/segment.h"
#include "engine/surface_law.h"

static int along(rf_vec3 x, rf_vec3 e1)
{
    double xl = rf_v3_norm(x);
    return xl == 0.0 || rf_v3_norm(rf_v3_cross(x, e1)) <= RF_PARALLEL_EPS * xl;
}

/* Centre mode: 1 when face `to` lies above the centre's reach and the rock cannot pay
 * the lift onto it (centre_lift would reflect it). */
static int is_wall(const rf_motion *m, int32_t to)
{
    return to >= 0 && rf_wall_for(m, to, rf_motion_energy(m));
}

/* Centre mode: the edge of the support's column that the centre lies on and is pressed
 * against by the surface law, beyond which lies a face whose offset plane is above the
 * centre and which the rock cannot pay the lift onto: a wall (a reflection off it,
 * RF_IMPACT_WALL), along which the rock moves on (RF_IMPACT_WALL_MEET, then the wall's
 * law rf_wall_law).  -1 when none. */
static int wall_edge(rf_motion *m, const rf_face_dyn *f, const rf_face_edges *fe, rf_vec3 dir,
                     rf_vec3 *L)
{
    const rf_terrain *t = m->cfg.terrain;
    int32_t from = m->rock.sup.tri[0];
    const rf_triangle *F = RF_FACE(m, from);
    for (int k = 0; k < 3; k++) {
        if (!rf_on_edge(m, fe, k, m->rock.s.p) ||
            rf_v3_dot(fe->m[k], m->rock.s.v) > RF_APPROACH_EPS ||
            !(rf_v3_dot(fe->m[k], rf_law_accel(f, dir)) < 0))
            continue;
        /* into it slower than the stay speed: the wall keeps it (as a face does) */
        *L = rf_edge_dir(F, k);
        if (rf_v3_norm(rf_in_plane(m->rock.s.v, *L)) > m->cfg.v_stay)
            continue;
        if (is_wall(m, rf_face_over_edge(t, from, k, fe)))
            return k;
    }
    return -1;
}

/* Centre mode: 1 when the wall slide along dir has the centre at the end of its wall,
 * where it would enter a face that is a wall too to a rock of kinetic energy ke (J):
 * a corner. */
static int wall_corner(const rf_motion *m, const rf_face_edges *fe, int wall, rf_vec3 dir, double ke)
{
    int at_end = 0; /* on another edge of the column, moving out over it */
    for (int k = 0; k < 3; k++)
        at_end |= k != wall && rf_on_edge(m, fe, k, m->rock.s.p) &&
                  rf_v3_dot(fe->m[k], dir) < 0;
    if (!at_end)
        return 0;
    int32_t to = rf_face_beyond(m->cfg.terrain, m->rock.sup.tri[0], m->rock.s.p, dir);
    return to >= 0 && rf_wall_for(m, to, ke);
}

/* Centre mode: the rock on its face meets the wall at column edge `wall` (direction
 * L): it keeps the velocity's part along it (the rest counts as an impact); a slipping
 * sphere's slip across the wall is taken by friction at its contact, the wall's push
 * keeping the centre along it (the spin changes, and energy is lost); in a corner of
 * two walls it stops.  Returns RF_SURF_REST, or RF_SURF_CONTINUE when it stopped in a
 * corner and goes on from rest; else -1: it moves along the wall in direction *dir
 * with the slip *u, under the law *f (set up anew when it rolls), and *stays tells
 * whether friction holds it there. */
static int wall_meet(rf_motion *m, rf_face_dyn *f, const rf_face_edges *fe, int wall, rf_vec3 L,
                     rf_vec3 *dir, rf_vec3 *u, int *stays)
{
    double s = rf_v3_dot(m->rock.s.v, L), gl = rf_v3_dot(f->gt, L);
    *dir = rf_v3_scale(L, (s != 0 ? s : gl) < 0 ? -1.0 : 1.0);
    *stays = 0;
    /* the kinetic energy left along the wall decides whether a face is a wall too */
    double ke = rf_kinetic_energy(m->cfg.body, rf_v3_scale(L, s), m->rock.s.w);
    int slide = f->mode == RF_LAW_SLIDE;
    rf_impact_site site = {RF_IMPACT_WALL_MEET, m->rock.sup.tri[0], f->n};
    site.l = L;
    site.corner_stop = wall_corner(m, fe, wall, *dir, ke);
    site.slide = slide;
    rf_impact_out out;
    rf_impact(m, &site, &out);
    *u = out.u;
    if (site.corner_stop) {
        /* wedged in the corner, it stopped; it rests when gravity presses it in, else
         * it goes on from rest */
        return rf_v3_dot(f->gt, *dir) >= 0 ? RF_SURF_REST : RF_SURF_CONTINUE;
    }
    if (slide) {
        /* it slides along the wall the way it slips; with no slip along it, one grows
         * from zero when gravity along it exceeds what friction holds (|g_l| > K mu
         * g_n, as rf_roll_holds on a face), else it rolls along the wall.  The face's
         * own test would count the part of gravity across the wall, which the wall
         * takes: the wall's law decides here. */
        double ul = rf_v3_dot(*u, L);
        double way = fabs(ul) > RF_SLIP_EPS ? ul : (fabs(gl) > f->K * f->mu * f->gn ? gl : 0.0);
        if (way != 0.0) {
            *dir = rf_v3_scale(L, way < 0 ? -1.0 : 1.0);
            return -1;
        }
        m->rock.sup.rolling = 1;
        *u = rf_v3(0, 0, 0);
        rf_set_spin(m, f->n, *u);
        rf_face_setup(m, f->n, f); /* rolling: no slip */
    }
    *stays = fabs(gl) <= f->c * f->gn;
    if (fabs(s) <= m->cfg.scene->sim->stop_speed && *stays)
        return RF_SURF_REST;
    return -1;
}

/* Centre mode: the rock moves along the wall at column edge `wall` (wall_meet), with
 * the part of the law's acceleration along it. */
static rf_surface_end wall_step(rf_motion *m, rf_face_dyn *f, const rf_face_edges *fe, int wall,
                                rf_vec3 L)
{
    rf_vec3 dir, u;
    int stays;
    int end = wall_meet(m, f, fe, wall, L, &dir, &u, &stays);
    if (end >= 0)
        return (rf_surface_end)end;
    return rf_face_closed(m, f, dir, u, fe, stays, wall);
}

int rf_wall_meet(rf_motion *m, const rf_face_edges *col, int edge, int *wall, rf_vec3 *dir)
{
    *wall = -1;
    if (!rf_on_edge(m, col, edge, m->rock.s.p))
        return -1;
    int32_t from = m->rock.sup.tri[0];
    const rf_triangle *T = RF_FACE(m, from);
    rf_face_dyn f;
    rf_face_setup(m, T->n, &f);
    rf_vec3 u = m->rock.sup.rolling ? rf_v3(0, 0, 0) : rf_slip_of(m, T->n);
    /* the face the rock would enter there (rf_leave_face), which at a vertex need not
     * be the one over the edge's middle */
    rf_vec3 acc = rf_law_accel(&f, rf_law_dir(&f, m->rock.s.v, u));
    if (!is_wall(m, rf_face_after(m, from, edge, col, m->rock.s.p, acc)))
        return -1;
    int stays;
    int end = wall_meet(m, &f, col, edge, rf_edge_dir(T, edge), dir, &u, &stays);
    if (end < 0)
        *wall = edge;
    return end;
}

static rf_surface_end face_step(rf_motion *m)
{
    int32_t tri = m->rock.sup.tri[0];
    const rf_triangle *T = RF_FACE(m, tri);
    m->rock.s.v = rf_in_plane(m->rock.s.v, T->n);
    rf_face_dyn f;
    rf_vec3 u0 = rf_v3(0, 0, 0);
    if (!m->cfg.point)
        u0 = rf_face_slip(m, T->n);
    rf_face_setup(m, T->n, &f);
    if (f.mode == RF_LAW_ROLL) {
        if (!rf_roll_holds(m, T->n)) {
            m->rock.sup.rolling = 0;
            rf_face_setup(m, T->n, &f);
            u0 = rf_v3(0, 0, 0);
        }
    }
    double speed = rf_v3_norm(m->rock.s.v);
    int holds = rf_surface_holds(m);
    if (speed <= m->cfg.scene->sim->stop_speed && f.mode != RF_LAW_SLIDE && holds)
        return RF_SURF_REST;
    rf_face_edges fe;
    rf_face_edges_setup(m, T, &fe);
    rf_vec3 dir = rf_law_dir(&f, m->rock.s.v, u0);
    int closed = f.G == 0.0 || along(f.mode == RF_LAW_SLIDE ? u0 : m->rock.s.v, f.e1);
    rf_vec3 L;
    int wall = m->cfg.centre ? wall_edge(m, &f, &fe, dir, &L) : -1;
    if (wall >= 0)
        return wall_step(m, &f, &fe, wall, L);
    if (closed)
        return rf_face_closed(m, &f, dir, u0, &fe, holds, -1);
    return rf_face_path(m, &f, u0, &fe, holds);
}

static rf_surface_end crease_step(rf_motion *m)
{
    rf_crease cr;
    switch (rf_crease_law(m, &cr)) {
    case RF_CREASE_ENDED: return RF_SURF_CONTINUE;
    case RF_CREASE_REST: return RF_SURF_REST;
    case RF_CREASE_MOVES: break;
    }
    const rf_terrain *t = m->cfg.terrain;
    rf_support ex = rf_segment_exclusion(m);
    double stop = m->cfg.scene->sim->stop_speed;
    rf_vec3 a = rf_v3_scale(cr.l, cr.as);
    rf_seg_event ev = {RF_EV_MAX_TIME, rf_fmax(0.0, m->cfg.t_end - m->rock.s.t), 0, 0, {0}, 0.0};
    if (cr.as < 0 && cr.s > 0) {
        if (cr.holds)
            rf_seg_consider(&ev, RF_EV_REST, (cr.s - stop) / -cr.as);
        else
            rf_seg_consider(&ev, RF_EV_ZERO, cr.s / -cr.as);
    }
    rf_arc arc = {m->rock.s.p, m->rock.s.v, a};
    rf_face_edges fe[2];
    for (int slot = 0; slot < 2; slot++) {
        const rf_triangle *S = RF_TRI(t, m->rock.sup.tri[slot]);
        rf_face_edges_setup(m, S, &fe[slot]);
        int edge = 0;
        /* not over the edge the faces share: the contact points move along it (the
         * point mass on it), and the crease's direction, from two nearly parallel
         * normals, may stray from it by a hair (in centre mode the centre lies over
         * one face, beyond the other's column, and the crease ends there) */
        int shared = m->cfg.centre ? -1 : rf_shared_edge(S, RF_TRI(t, m->rock.sup.tri[1 - slot]));
        double tx = rf_exit_time(m, &fe[slot], &arc, ev.t, shared, &edge);
        if (tx < ev.t) {
            rf_seg_consider(&ev, RF_EV_EXIT, tx);
            ev.edge = edge;
            ev.slot = slot;
        }
    }
    rf_spin_law roll;
    if (cr.rolling)
        roll = rf_crease_roll(m);
    rf_seg_closed_finish(m, &arc, cr.rolling ? &roll : NULL, &ex, &ev);
    return rf_seg_dispatch(m, &ev, a, &fe[ev.slot]);
}

rf_surface_end rf_surface_step(rf_motion *m)
{
    return m->rock.sup.n == 2 ? crease_step(m) : face_step(m);
}
