/* path.c - segments off the fall line.
 *
 * Off the fall line each law is w' = A e1 - B w^ (e1 the fall line; w the velocity,
 * or the slip of the slipping sphere), whose solution hodograph.c gives in closed form.
 * Such a segment is cut into steps, each short enough that its parabola (start, start
 * velocity, end) departs from the path by about RF_PATH_DEV at most: the contact and
 * scene searches run on the parabola, and what they find is located to RF_TIME_TOL on
 * the path itself. */
#include "engine/path.h"

#include <math.h>
#include <string.h>

#include "engine/contact.h"
#include "engine/face_exit.h"
#include "engine/feature.h"
#include "engine/hodograph.h"
#include "engine/rock.h"
#include "engine/scene_events.h"
#include "engine/segment.h"

/* The path of a segment off the fall line: the state y (centre relative to the start,
 * v, u) as a function of the hodograph's parameter. */
typedef struct seg_path {
    const rf_face_dyn *f;
    rf_hodograph h;
    rf_vec3 v0, u0; /* the slipping sphere: v = v0 + (1 - 1/K) g_t t + (u - u0) / K */
    double iK;      /* 1 / K */
} seg_path;

static void path_init(seg_path *P, const rf_face_dyn *f, rf_vec3 v0, rf_vec3 u0)
{
    P->f = f, P->v0 = v0, P->u0 = u0;
    P->iK = 1.0 / f->K;
    if (f->mode == RF_LAW_SLIDE)
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
    return P->f->mode == RF_LAW_SLIDE ? y_u(y) : y_v(y);
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
static void path_advance(rf_motion *m, const rf_face_dyn *f, const rf_arc *arc, double h,
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
    m->rock.s.p = rf_v3_add(c0, y_c(ye));
    m->rock.s.v = y_v(ye);
    rf_set_spin(m, f->n, y_u(ye));
}

/* The state at parameter lam in y; returns its time from the segment's start. */
static double path_at(const seg_path *P, double lam, double *y)
{
    const rf_face_dyn *f = P->f;
    rf_vec3 w, x;
    double t = rf_hodograph_at(&P->h, lam, &w, &x);
    if (f->mode != RF_LAW_SLIDE) {
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
static double event_value(rf_motion *m, rf_ev_kind kind, const rf_seg_event *ev, const rf_face_edges *fe,
                          rf_vec3 c0, const double *y)
{
    rf_vec3 c = rf_v3_add(c0, y_c(y));
    switch (kind) {
    case RF_EV_EXIT: /* level: how far beyond the edge it counts (0, or the tolerance) */
        return rf_v3_dot(fe->m[ev->edge], c) - fe->o[ev->edge] + ev->level;
    case RF_EV_REST:
    case RF_EV_ZERO:
        return rf_v3_norm2(y_v(y)) - ev->level * ev->level;
    case RF_EV_CONTACT:
        return rf_feature_distance(m->cfg.terrain, &ev->con, c) - m->cfg.rho;
    case RF_EV_LINE:
        return ev->line[2] * (c.x - ev->line[0]) + ev->line[3] * (c.y - ev->line[1]);
    default:
        return 0.0;
    }
}

/* Rate of change of the event function at a state (relative centre c + c0). */
static double event_rate(rf_motion *m, const rf_face_dyn *f, rf_ev_kind kind, const rf_seg_event *ev,
                         const rf_face_edges *fe, rf_vec3 c0, const double *y)
{
    rf_vec3 v = y_v(y);
    switch (kind) {
    case RF_EV_EXIT:
        return rf_v3_dot(fe->m[ev->edge], v);
    case RF_EV_REST:
    case RF_EV_ZERO: { /* the point mass and the rolling sphere */
        double vl = rf_v3_norm(v);
        return vl > 0 ? 2.0 * rf_v3_dot(v, rf_law_accel(f, rf_v3_scale(v, 1.0 / vl))) : 0.0;
    }
    case RF_EV_CONTACT: {
        const rf_contact *c = &ev->con;
        const rf_triangle *T = RF_FACE(m, c->tri);
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
    case RF_EV_LINE:
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
static double narrow(rf_motion *m, rf_ev_kind kind, const rf_seg_event *ev, const rf_face_edges *fe,
                     rf_vec3 c0, seg_step *st, ev_bracket b, double x, double *ye)
{
    double tmp[9];
    int side = 0;
    for (int it = 0; it < RF_NARROW_MAX_ITER && b.hi - b.lo > RF_TIME_TOL; it++) {
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
static double locate_bracket(rf_motion *m, rf_ev_kind kind, const rf_seg_event *ev,
                             const rf_face_edges *fe, rf_vec3 c0, seg_step *st,
                             double flo, double guess, double *ye)
{
    double h = st->h;
    double llo = st->la, lo = 0.0, lhi = st->lb, hi = h;
    double fhi = 1.0;
    if (guess > 0 && guess < h) {
        /* just after the parabola's estimate, the usual bracket */
        lhi = step_lam(st, rf_fmin(h, guess + RF_BRACKET_REL * h + RF_BRACKET_ABS));
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
static double locate(rf_motion *m, const rf_face_dyn *f, rf_ev_kind kind, const rf_seg_event *ev,
                     const rf_face_edges *fe, rf_vec3 c0, seg_step *st, const double *y,
                     double guess, double *ye)
{
    double h = st->h;
    double f0 = event_value(m, kind, ev, fe, c0, y);
    int start = f0 <= 0.0, reentry = 0;
    int found_later = guess > 0.0 && guess < h;
    if (kind == RF_EV_CONTACT && guess == 0.0 && f0 <= m->cfg.tol_len) {
        /* touching and approaching, as the search found it at the start */
        start = start || event_rate(m, f, kind, ev, fe, c0, y) < -RF_APPROACH_EPS;
    } else if (start && found_later &&
               (kind == RF_EV_CONTACT || (kind == RF_EV_EXIT && f0 >= -m->cfg.tol_len))) {
        /* found later, the rock moving out of the contact's reach or in over the edge
         * (a hair beyond it): the re-entry or the exit the parabola found, not the start */
        reentry = event_rate(m, f, kind, ev, fe, c0, y) > 0.0;
    }
    if (start && !reentry) {
        if (kind == RF_EV_EXIT && !found_later && f0 >= -m->cfg.tol_len &&
            event_rate(m, f, kind, ev, fe, c0, y) > 0.0) {
            /* a hair beyond the edge (within the tolerance, as rf_exit_time takes it) but
             * moving in, and beyond it by more at the step's end, where the step's
             * parabola saw no crossing: the exit where the path is the tolerance
             * beyond the edge, not at the start (the rock does not leave a face it is
             * moving into) */
            rf_seg_event beyond = *ev;
            beyond.level = m->cfg.tol_len;
            return locate_bracket(m, kind, &beyond, fe, c0, st, f0 + m->cfg.tol_len, guess, ye);
        }
        memcpy(ye, y, 9 * sizeof *ye);
        return 0.0;
    }
    if (found_later) {
        ev_bracket b = {st->la, 0.0, f0, st->lb, -1.0, 0.0};
        double lam = step_lam(st, guess);
        double tmp[9];
        for (int it = 0; it < RF_NEWTON_MAX_ITER; it++) {
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
             * crossing and after its return (a short excursion over an edge), so the
             * bracket found here is kept. */
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
static double scene_time(rf_motion *m, const rf_face_dyn *f, rf_seg_event *ev, const rf_face_edges *fe,
                         rf_vec3 c0, seg_step *st, const rf_arc *arc, const double *y, double ts,
                         double *ye)
{
    if (m->scn.pending == RF_SCENE_MEASURE && ts > 0.0) {
        const rf_crossing *cr = &m->scn.crossings[0];
        const double *A = &m->cfg.scene->measures[cr->measure].line.xy[2 * cr->segment], *B = A + 2;
        double nx = A[1] - B[1], ny = B[0] - A[0], len = hypot(nx, ny);
        rf_vec3 v = rf_arc_vel(arc, ts);
        if (nx * v.x + ny * v.y > 0)
            len = -len; /* the normal towards the side the rock comes from */
        ev->line[0] = A[0], ev->line[1] = A[1], ev->line[2] = nx / len, ev->line[3] = ny / len;
        double te = locate(m, f, RF_EV_LINE, ev, fe, c0, st, y, ts, ye);
        if (te > 0.0)
            return te;
    }
    step_at(st, ts, ye);
    return ts;
}

/* The exit of a step of length hs over its parabola arc, not over edge skip_edge
 * (-1: none), into ev (and its time into *guess) when the path leaves the face within
 * the step, or ends it (cabs) beyond an edge by more than the length tolerance.
 * Returns the exit time of the parabola (hs: none). */
static double step_exit(const rf_motion *m, const rf_face_edges *fe, const rf_arc *arc, double hs,
                        int skip_edge, rf_vec3 cabs, rf_seg_event *ev, double *guess)
{
    int edge = 0;
    double tx = rf_exit_time(m, fe, arc, hs, skip_edge, &edge);
    int outside = 0;
    for (int k = 0; k < 3; k++) {
        if (k != skip_edge && rf_v3_dot(fe->m[k], cabs) - fe->o[k] < -m->cfg.tol_len) {
            outside = 1;
            if (!(tx < hs))
                edge = k, tx = hs;
        }
    }
    if (tx < hs || outside) {
        ev->kind = RF_EV_EXIT, ev->t = tx, ev->edge = edge;
        *guess = tx;
    }
    return tx;
}

rf_surface_end rf_face_path(rf_motion *m, const rf_face_dyn *f, rf_vec3 u0, const rf_face_edges *fe,
                                int holds)
{
    rf_support ex = rf_segment_exclusion(m);
    seg_path P;
    path_init(&P, f, m->rock.s.v, u0);
    int slide = f->mode == RF_LAW_SLIDE;
    double weps = slide ? RF_SLIP_EPS : RF_SPEED_EPS;
    rf_vec3 c0 = m->rock.s.p;
    double y[9], yn[9];
    y_set(y, rf_v3(0, 0, 0), m->rock.s.v, slide ? u0 : rf_v3(0, 0, 0));
    double lam = 0.0, t = 0.0, tcap = m->cfg.t_end - m->rock.s.t;
    double stop = m->cfg.scene->sim->stop_speed;
    for (long steps = 0;; steps++) {
        if (t >= tcap)
            return RF_SURF_MAX_TIME;
        if (steps > RF_PATH_MAX_STEPS)
            return RF_SURF_CONTINUE; /* start a fresh segment */
        if (rf_v3_norm(path_w(&P, y)) <= weps) {
            if (!slide) {
                m->rock.s.v = rf_v3(0, 0, 0);
                return RF_SURF_CONTINUE; /* from rest: a closed-form segment */
            }
            m->rock.sup.rolling = 1; /* the slip has vanished */
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
        rf_seg_event ev;
        double te, ts, tx, ye[9];
        for (;;) {
            ev = (rf_seg_event){RF_EV_NONE, hs, 0, 0, {0}, 0.0};
            double guess = -1;
            st.lg = st.la;
            tx = step_exit(m, fe, &arc, hs, skip_edge, cabs, &ev, &guess);
            /* rest, or a speed so small that friction's direction is undefined: stop
             * there and go on from rest (along the fall line) */
            double level = holds ? stop : RF_SPEED_EPS;
            /* unless the rock leaves the face first, still faster than that (its speed
             * falls all along): it does not rest beyond an edge of its face */
            if (!slide && rf_v3_norm(vn) <= level && rf_v3_norm(vk) > level &&
                !(ev.kind == RF_EV_EXIT && rf_v3_norm(rf_arc_vel(&arc, ev.t)) > level)) {
                ev.kind = holds ? RF_EV_REST : RF_EV_ZERO, ev.t = hs, ev.level = level;
                guess = -1;
            }
            if (!m->cfg.point && !m->cfg.centre) {
                rf_contact con;
                double tl = rf_fmin(hs, ev.t + 0.1 * hs);
                if (rf_contact_search_near(m, &arc, tl, &ex, skip, nskip, &con) && con.t <= ev.t) {
                    ev.kind = RF_EV_CONTACT, ev.t = con.t, ev.con = con;
                    guess = con.t;
                }
            }
            /* scene events on the step's parabola, before any terrain event */
            ts = rf_scene_horizon(m, &arc, ev.t);
            if (m->scn.pending && ts < ev.t) {
                ev.kind = RF_EV_SCENE, ev.t = ts;
            } else {
                m->scn.pending = 0;
            }
            te = -1.0;
            if (ev.kind == RF_EV_SCENE) {
                te = scene_time(m, f, &ev, fe, c0, &st, &arc, y, ts, ye);
            } else if (ev.kind == RF_EV_EXIT && tx <= 0.0) {
                te = 0.0;
                memcpy(ye, y, sizeof ye);
            } else if (ev.kind != RF_EV_NONE) {
                te = locate(m, f, ev.kind, &ev, fe, c0, &st, y, guess, ye);
            }
            if (te >= 0.0 || ev.kind == RF_EV_NONE)
                break;
            if (ev.kind == RF_EV_CONTACT && nskip < RF_PATH_MAX_SKIPS)
                skip[nskip++] = ev.con;
            else if (ev.kind == RF_EV_EXIT && skip_edge < 0)
                skip_edge = ev.edge;
            else
                break;
        }
        if (te >= 0.0) {
            rf_arc ea = fit_arc(ck, vk, rf_v3_sub(y_c(ye), y_c(y)), te);
            path_advance(m, f, &ea, te, c0, y, ye);
            return rf_seg_dispatch(m, &ev, rf_law_accel(f, f->e1), fe);
        }
        path_advance(m, f, &arc, hs, c0, y, yn);
        memcpy(y, yn, sizeof y);
        lam = st.lb;
        t = tb;
    }
}
