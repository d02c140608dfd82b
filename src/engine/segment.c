/* segment.c - segments of surface motion at constant acceleration, and the dispatch
 * of their events.
 *
 * On the fall line, on a level face, along a wall or a crease, the surface law's
 * acceleration is constant (Eq. 1-2, the 5/7 law): the path is a parabola and every
 * event time (exit over an edge, rest, zero speed, rolling) is the root of a
 * quadratic; contacts and scene events are searched along it. */
#include "engine/segment.h"

#include <math.h>

#include "engine/contact.h"
#include "engine/face_entry.h"
#include "engine/face_exit.h"
#include "engine/scene_events.h"

/* The faces a surface segment's contact search ignores: the support, and once the face
 * just left over an edge. */
rf_support rf_segment_exclusion(rf_motion *m)
{
    rf_support ex = m->rock.sup;
    if (ex.left >= 0 && ex.n < 3)
        ex.tri[ex.n++] = ex.left;
    m->rock.sup.left = -1;
    return ex;
}

void rf_seg_consider(rf_seg_event *ev, rf_ev_kind kind, double t)
{
    if (t < ev->t) {
        ev->t = t;
        ev->kind = kind;
    }
}

/* Finishes a segment at the event: records the motion and dispatches. */
rf_surface_end rf_seg_dispatch(rf_motion *m, rf_seg_event *ev, rf_vec3 acc, const rf_face_edges *fe)
{
    switch (ev->kind) {
    case RF_EV_MAX_TIME:
        return RF_SURF_MAX_TIME;
    case RF_EV_REST:
        return RF_SURF_REST;
    case RF_EV_ZERO:
        m->rock.s.v = rf_v3(0, 0, 0);
        if (!m->cfg.point && m->rock.sup.rolling)
            m->rock.s.w = rf_v3(0, 0, 0);
        rf_motion_event(m);
        return RF_SURF_CONTINUE;
    case RF_EV_SLIP:
        m->rock.sup.rolling = 1;
        rf_set_spin(m, RF_FACE(m, m->rock.sup.tri[0])->n, rf_v3(0, 0, 0));
        rf_motion_event(m);
        return RF_SURF_CONTINUE;
    case RF_EV_EXIT: {
        rf_surface_end r = rf_leave_face(m, ev->slot, ev->edge, fe, acc);
        rf_motion_event(m);
        return r;
    }
    case RF_EV_CONTACT:
        if (rf_scene_at_once(m) >= 0)
            return RF_SURF_STOPPED;
        rf_contact_resolve(m, &ev->con);
        rf_motion_event(m);
        return m->rock.sup.n == 0 ? RF_SURF_FLIGHT : RF_SURF_CONTINUE;
    case RF_EV_SCENE:
        if (rf_surface_scene_event(m) >= 0)
            return RF_SURF_STOPPED;
        return m->rock.sup.n == 0 ? RF_SURF_FLIGHT : RF_SURF_CONTINUE;
    default:
        return RF_SURF_CONTINUE;
    }
}

/* The end of a constant-acceleration segment along arc (face or crease), whose other
 * events are in ev: contacts with the terrain (full contact; ex ignored) and scene
 * events come first when earlier; the state is moved to the event, the spin by its
 * law (NULL: it stays), and its energy noted. */
void rf_seg_closed_finish(rf_motion *m, const rf_arc *arc, const rf_spin_law *spin,
                          const rf_support *ex, rf_seg_event *ev)
{
    if (!m->cfg.point && !m->cfg.centre && ev->t > 0) {
        rf_contact con;
        if (rf_contact_search_near(m, arc, ev->t, ex, NULL, 0, &con) && con.t < ev->t) {
            rf_seg_consider(ev, RF_EV_CONTACT, con.t);
            ev->con = con;
        }
    }
    double ts = rf_scene_horizon(m, arc, ev->t);
    if (m->scn.pending && ts < ev->t)
        rf_seg_consider(ev, RF_EV_SCENE, ts);
    rf_motion_advance(m, arc, ev->t, spin);
    if (spin && !m->cfg.point)
        m->rock.s.w = rf_spin_at(spin, m->cfg.rho, m->rock.s.v, ev->t > 0 ? ev->t : 0.0);
    rf_motion_note_energy(m);
}

/* A segment of constant acceleration on one face; along the wall at its column edge
 * `wall` (centre mode, -1: none; dir along that edge), which takes the part of the
 * acceleration across it. */
rf_surface_end rf_face_closed(rf_motion *m, const rf_face_dyn *f, rf_vec3 dir, rf_vec3 u0,
                                  const rf_face_edges *fe, int holds, int wall)
{
    rf_support ex = rf_segment_exclusion(m);
    rf_vec3 a = rf_law_accel(f, dir);
    rf_vec3 du = f->mode == RF_LAW_SLIDE ? rf_law_slip_rate(f, dir) : rf_v3(0, 0, 0);
    if (wall >= 0)
        rf_wall_law(dir, &a, &du);
    double speed = rf_v3_norm(m->rock.s.v);
    rf_seg_event ev = {RF_EV_MAX_TIME, m->cfg.t_end - m->rock.s.t, 0, 0, {0}, 0.0};
    if (ev.t < 0)
        ev.t = 0;
    if (f->mode == RF_LAW_SLIDE) {
        double dus = rf_v3_dot(du, dir);
        if (dus < 0)
            rf_seg_consider(&ev, RF_EV_SLIP, rf_v3_norm(u0) / -dus);
    } else if (speed > 0) {
        double as = rf_v3_dot(a, dir);
        if (as < 0) {
            if (holds)
                rf_seg_consider(&ev, RF_EV_REST, speed > m->cfg.scene->sim->stop_speed
                                            ? (speed - m->cfg.scene->sim->stop_speed) / -as : 0.0);
            else
                rf_seg_consider(&ev, RF_EV_ZERO, speed / -as);
        }
    }
    rf_arc arc = {m->rock.s.p, m->rock.s.v, a};
    int edge = 0;
    double tx = rf_exit_time(m, fe, &arc, ev.t, wall, &edge);
    if (tx < ev.t) {
        rf_seg_consider(&ev, RF_EV_EXIT, tx);
        ev.edge = edge;
        ev.slot = 0;
    }
    rf_vec3 z = rf_v3(0, 0, 0);
    int slide = f->mode == RF_LAW_SLIDE;
    rf_spin_law spin = rf_spin_law_of(m, f->n, slide ? u0 : z, slide ? du : z);
    rf_seg_closed_finish(m, &arc, &spin, &ex, &ev);
    return rf_seg_dispatch(m, &ev, a, fe);
}
