/* scene_events.c - the events of a scene beyond its terrain: crossings of protection
 * measures and collisions with trees, offered for every piece of motion the engines
 * take (a flight, a closed-form surface segment, an integrator step, a fixed step).
 *
 * Measures: the horizontal path of a piece is an exact quadratic in time, so its
 * crossings of the measures' polylines are roots of quadratics (measures.c); none is
 * missed at any speed.
 *
 * Trees (Eq. 9-12): collisions are a Poisson process along the horizontal path whose
 * rate depends on where the rock is and how high its centre is.  It is sampled by
 * thinning: candidate events at the bound rate (exponential gaps of horizontal
 * distance, kept as an odometer reading), each accepted with the true rate at the
 * candidate's position over the bound (vegetation.c).  Gaps are measured in distance,
 * not time, so no time step enters: the exact and the fixed-step engines sample the
 * same process. */
#include "engine/scene_events.h"

#include <gsl/gsl_randist.h>
#include <math.h>
#include <string.h>

#include "engine/impact.h"
#include "engine/rock.h"
#include "engine/travel.h"
#include "scene/vegetation.h"

/* The next candidate tree event: its gap from `from` on the odometer and its
 * acceptance draw.  Every draw counts towards RF_TREE_MAX_DRAWS: when they run out the
 * process is no longer sampled (a forest too dense, or a piece too long, for the
 * odometer's precision or for bounded work) and the trajectory is given up. */
static void draw_candidate(rf_motion *m, double from)
{
    m->scn.tree_next = from + gsl_ran_exponential(m->rng, 1.0 / m->scn.tree_bound);
    m->scn.tree_u = gsl_rng_uniform(m->rng);
    if (++m->scn.tree_draws >= RF_TREE_MAX_DRAWS) {
        m->scn.tree_bound = 0.0;
        m->scn.trees_given_up = 1;
    }
}

void rf_scene_begin(rf_motion *m)
{
    const rf_scene *sc = m->cfg.scene;
    m->scn.pending = RF_SCENE_NONE;
    m->scn.seen = m->rock.s.p;
    m->scn.jumping = 0;
    m->scn.odo = 0.0;
    m->scn.phi_r = 2.0 * m->cfg.body->radius;
    const rf_terrain *t = m->cfg.terrain;
    /* forests that cover no part of the terrain cost nothing */
    int any = rf_vegetation_touches(sc->forests, sc->nforests, t->xmin, t->ymin, t->xmax, t->ymax);
    m->scn.tree_bound = any ? rf_vegetation_rate_bound(sc->forests, sc->nforests, m->scn.phi_r) : 0.0;
    m->scn.tree_draws = 0;
    m->scn.trees_given_up = 0;
    if (m->scn.tree_bound > 0.0)
        draw_candidate(m, 0.0);
}


/* The earliest tree collision over [0, T] of the arc, or T.  Rejected candidates on
 * the way are used up.  Each pass draws a candidate, and the draws are bounded
 * (draw_candidate): the loop ends although a gap below the rounding of the odometer,
 * or an infinite L, does not move the candidate past the piece's end. */
static double tree_horizon(rf_motion *m, const rf_arc *arc, double T)
{
    const rf_scene *sc = m->cfg.scene;
    double L = rf_horizontal_length(arc->v, arc->a, T);
    while (m->scn.tree_bound > 0.0 && m->scn.tree_next - m->scn.odo <= L) {
        double s = fmax(m->scn.tree_next - m->scn.odo, 0.0);
        double t = rf_horizontal_time_at(arc->v, arc->a, s, T);
        rf_vec3 p = rf_arc_pos(arc, t);
        double zg;
        if (rf_terrain_height(m->cfg.terrain, p.x, p.y, &zg) >= 0) {
            double h_r = p.z - zg; /* Eq. 9-10: the centre's vertical height above the slope */
            int f = rf_vegetation_accept(sc->forests, sc->nforests, p.x, p.y, h_r, m->scn.phi_r,
                                         m->scn.tree_bound, m->scn.tree_u);
            if (f >= 0) {
                m->scn.tree_forest = f;
                return t;
            }
        }
        draw_candidate(m, m->scn.tree_next);
    }
    return T;
}

/* The measures' part of rf_scene_horizon: the first crossings within T into
 * m->scn.crossings (m->scn.ncrossings of them; 0: none). */
static void measure_horizon(rf_motion *m, const rf_arc *arc, double T)
{
    const rf_scene *sc = m->cfg.scene;
    m->scn.ncrossings = 0;
    if (sc->nmeasures == 0)
        return;
    /* from just before the start: a crossing at the very end of the previous piece that
     * it left to this one (it ended on the line at another event) is found here; the
     * ones of a passage under way are passed over */
    double after = -RF_CROSSING_EPS;
    for (;;) {
        int k = rf_measures_first_crossings(sc->measures, sc->nmeasures, arc->p, arc->v, arc->a,
                                            after, T, m->scn.crossings, RF_MAX_COINCIDENT_CROSSINGS);
        double t0 = k > 0 ? m->scn.crossings[0].t : INFINITY;
        int kept = 0;
        for (int i = 0; i < k; i++) {
            rf_crossing c = m->scn.crossings[i];
            const rf_passage *ps = rf_passage_of(m, c.measure);
            if (!ps || rf_passage_reach(ps, arc, c.t) > m->cfg.body->radius)
                m->scn.crossings[kept++] = c;
        }
        m->scn.ncrossings = kept;
        if (kept > 0 || k == 0)
            return;
        /* strictly later (the eps alone rounds away beyond 1e4 s): each pass passes
         * over roots of the lines' quadratics, of which there are finitely many */
        after = fmax(t0 + RF_CROSSING_EPS, nextafter(t0, INFINITY));
    }
}

/* The measures' lines crossed by a move in no time: the centre was last seen at
 * m->scn.seen and the next piece starts at p.  The straight move in plan is searched
 * (a roll over an edge turns the centre about the edge by an angle under pi, on an
 * arc of radius r at most); 1 when it crossed a line (m->scn.crossings).  Otherwise the
 * move is taken as seen. */
static int jump_crossings(rf_motion *m, rf_vec3 p)
{
    rf_vec3 from = m->scn.seen;
    if (m->cfg.scene->nmeasures == 0 || (from.x == p.x && from.y == p.y))
        return 0;
    rf_arc move = {from, rf_v3_sub(p, from), rf_v3(0, 0, 0)};
    measure_horizon(m, &move, 1.0);
    if (m->scn.ncrossings > 0)
        return m->scn.jumping = 1;
    m->scn.seen = p;
    return 0;
}

double rf_scene_horizon(rf_motion *m, const rf_arc *arc, double T)
{
    m->scn.pending = RF_SCENE_NONE;
    m->scn.jumping = 0;
    if (jump_crossings(m, arc->p)) {
        m->scn.pending = RF_SCENE_MEASURE;
        return 0.0;
    }
    double best = T;
    measure_horizon(m, arc, T);
    if (m->scn.ncrossings > 0) {
        best = fmax(m->scn.crossings[0].t, 0.0);
        m->scn.pending = RF_SCENE_MEASURE;
    }
    if (m->scn.tree_bound > 0.0) {
        double tt = tree_horizon(m, arc, best);
        if (tt < best) {
            best = tt;
            m->scn.pending = RF_SCENE_TREE;
        }
    }
    return best;
}

/* A crossing of measure `which` at the current state: recorded, then the measure
 * acts.  Returns RF_END_STOPPED or -1. */
static int cross_measure(rf_motion *m, int which)
{
    const rf_measure *ms = &m->cfg.scene->measures[which];
    const rf_body *b = m->cfg.body;
    double zg;
    rf_vec3 p = m->rock.s.p;
    double hpass = rf_terrain_height(m->cfg.terrain, p.x, p.y, &zg) >= 0 ? p.z - zg : NAN;
    double et = 0.5 * b->mass * rf_v3_norm2(m->rock.s.v);
    double e = rf_motion_energy(m);
    rf_motion_note_energy(m); /* before a stop takes it */
    rf_interception_record r;
    r.measure = which;
    r.t_s = m->rock.s.t;
    r.p = m->rock.s.p;
    r.speed_ms = rf_v3_norm(m->rock.s.v);
    r.energy_kj = e / 1000.0;
    r.energy_trans_kj = et / 1000.0;
    r.energy_rot_kj = (e - et) / 1000.0;
    r.passing_height_m = hpass;
    r.outcome = rf_measure_outcome(ms, hpass, r.energy_kj);
    if (m->book.sink && m->book.sink->interception)
        m->book.sink->interception(m->book.sink->ctx, &r);
    if (r.outcome == RF_OUT_STOPPED) {
        m->rock.s.v = rf_v3(0, 0, 0);
        m->rock.s.w = rf_v3(0, 0, 0);
        return RF_END_STOPPED;
    }
    if (r.outcome == RF_OUT_BROKE_THROUGH) {
        /* it goes on with the residual energy E - E_capacity, in the same direction */
        double k = sqrt(fmax(r.energy_kj - rf_measure_breaking_energy(ms), 0.0) / r.energy_kj);
        m->rock.s.v = rf_v3_scale(m->rock.s.v, k);
        m->rock.s.w = rf_v3_scale(m->rock.s.w, k);
    }
    return -1;
}

/* The measures crossed at this moment, in the project's order: a rock stopped by one
 * is never seen by the next. */
static int measure_event(rf_motion *m)
{
    /* seen moves on to the crossing: a move in no time may cross further lines after it */
    if (m->scn.jumping)
        m->scn.seen = rf_v3_madd(m->scn.seen, m->scn.crossings[0].t,
                                 rf_v3_sub(m->rock.s.p, m->scn.seen));
    else
        m->scn.seen = m->rock.s.p;
    m->scn.jumping = 0;
    for (int i = 0; i < m->scn.ncrossings; i++) {
        rf_passage_start(m, &m->scn.crossings[i]);
        if (cross_measure(m, m->scn.crossings[i].measure) >= 0)
            return RF_END_STOPPED;
    }
    rf_motion_event(m);
    return -1;
}

/* Fig. 6b: a collision with a vertical rigid stem at a uniformly random lateral offset
 * across the swept band; horizontal contact normal; the forest's restitution and
 * friction applied by the impact law, rotation included. */
static int tree_event(rf_motion *m, int32_t *onto)
{
    draw_candidate(m, m->scn.odo);
    rf_vec3 vh = rf_v3(m->rock.s.v.x, m->rock.s.v.y, 0.0);
    if (!(rf_v3_norm(vh) > 0.0))
        return -1;
    double q = 2.0 * gsl_rng_uniform(m->rng) - 1.0;
    rf_vec3 n = rf_tree_contact_normal(vh, q);
    rf_impact_site site = {RF_IMPACT_TREE, m->scn.tree_forest, n};
    rf_impact(m, &site, NULL);
    if (m->rock.sup.n > 0) {
        /* on the surface: off into flight when the stem throws it up, else back onto
         * the face it was on (*onto), its velocity made tangent there */
        int32_t tri = m->rock.sup.tri[0];
        double vn = rf_v3_dot(m->rock.s.v, RF_FACE(m, tri)->n);
        m->rock.sup.n = 0;
        if (vn <= m->cfg.v_stay) {
            *onto = tri;
            return -1;
        }
    }
    rf_motion_event(m);
    return -1;
}

int rf_scene_at_once(rf_motion *m)
{
    /* the measures alone: the trees' search draws the next tree and can put a tree
     * in the crossing's place.  At once: within RF_CROSSING_EPS, or within four length
     * tolerances of travel, the precision an event on the terrain is placed with (the
     * centre meets a column's face a hair before the column's edge) */
    rf_arc arc = {m->rock.s.p, m->rock.s.v, rf_v3(0, 0, -RF_GRAVITY)};
    double vh = rf_v3_hnorm(m->rock.s.v);
    m->scn.jumping = 0;
    measure_horizon(m, &arc, vh > 0 ? fmax(RF_CROSSING_EPS, RF_REACH_TOLS * m->cfg.tol_len / vh) : RF_CROSSING_EPS);
    m->scn.pending = RF_SCENE_NONE;
    return m->scn.ncrossings > 0 ? measure_event(m) : -1;
}

int rf_scene_event(rf_motion *m, int32_t *onto)
{
    int kind = m->scn.pending;
    *onto = -1;
    m->scn.pending = RF_SCENE_NONE;
    if (kind == RF_SCENE_MEASURE)
        return measure_event(m);
    if (kind == RF_SCENE_TREE)
        return tree_event(m, onto);
    rf_motion_event(m);
    return -1;
}
