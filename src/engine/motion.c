/* motion.c - one rock's trajectory: the event loop of the exact engine, the records
 * and the public functions of sim.h.
 *
 * A trajectory alternates flights and surface phases.  Each pass of the loop computes
 * the earliest of the events the current phase can meet (terrain contact, leaving a
 * face, leaving the terrain, max_time; the surface phase adds slip, stop and rest),
 * moves the state there along the exact path and handles the event.  The cost follows
 * the number of events, not the simulated time.  Tree collisions and measure
 * crossings come in as more candidate events of every piece of motion through
 * rf_scene_horizon and rf_scene_event (scene_events.c). */
#include "rockfall/sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/contact.h"
#include "engine/exit.h"
#include "engine/face_entry.h"
#include "engine/fixed_step.h"
#include "engine/progress.h"
#include "engine/rock.h"
#include "engine/scene_events.h"
#include "engine/state.h"
#include "engine/surface.h"
#include "engine/surface_law.h"
#include "engine/tables.h"

rf_workspace *rf_workspace_alloc_shared(const rf_terrain_tables *tt)
{
    const rf_terrain *t = tt->terrain;
    rf_workspace *ws = calloc(1, sizeof *ws);
    if (!ws)
        return NULL;
    ws->tables = tt;
    ws->cap = 256;
    ws->cand = malloc(ws->cap * sizeof *ws->cand);
    ws->stamp = t->is_grid ? NULL : calloc(t->ntri ? t->ntri : 1, sizeof *ws->stamp);
    for (int h = 0; h < RF_FACE_CACHE; h++)
        ws->face_key[h] = ws->box_key[h] = -1;
    ws->tested_cap = 256;
    ws->tested = calloc(ws->tested_cap, sizeof *ws->tested);
    ws->tested_mark = t->tri ? calloc(t->ntri ? t->ntri : 1, sizeof *ws->tested_mark) : NULL;
    if (!ws->cand || (!t->is_grid && !ws->stamp) || !ws->tested || (t->tri && !ws->tested_mark)) {
        rf_workspace_free(ws);
        return NULL;
    }
    return ws;
}

rf_workspace *rf_workspace_alloc(const rf_terrain *t)
{
    rf_terrain_tables *tt = rf_terrain_tables_build(t);
    rf_workspace *ws = tt ? rf_workspace_alloc_shared(tt) : NULL;
    if (!ws) {
        rf_terrain_tables_free(tt);
        return NULL;
    }
    ws->own = tt;
    return ws;
}

void rf_workspace_free(rf_workspace *ws)
{
    if (!ws)
        return;
    free(ws->cand);
    free(ws->stamp);
    free(ws->tested);
    free(ws->tested_mark);
    free(ws->near_hit);
    free(ws->pend_idx);
    free(ws->pend_w0);
    rf_terrain_tables_free(ws->own);
    free(ws);
}

/* One flight until its next event; returns -1 to go on, or the end reason. */
static int flight_step(rf_motion *m)
{
    m->book.rec->n_flights++;
    rf_arc arc = {m->rock.s.p, m->rock.s.v, rf_v3(0, 0, -RF_GRAVITY)};
    double T = fmax(0.0, m->cfg.t_end - m->rock.s.t);
    /* below every face: the rock has left the terrain */
    double zfloor = m->cfg.terrain->zmin - m->cfg.rho - 1.0;
    double t_fall = INFINITY;
    double r[2];
    int nr = rf_quadratic_roots(-0.5 * RF_GRAVITY, arc.v.z, arc.p.z - zfloor, r);
    if (nr == 2)
        t_fall = fmax(0.0, r[1]);
    double tc = fmin(T, t_fall);
    double te = rf_terrain_exit_time(m, &arc, tc);
    rf_contact c;
    int hit = rf_flight_contact(m, &arc, te, &c);
    double tend = hit ? c.t : te;
    double ts = rf_scene_horizon(m, &arc, tend);
    int scene = m->scn.pending && ts < tend;
    rf_motion_advance(m, &arc, scene ? ts : tend, NULL);
    rf_motion_note_energy(m); /* before an impact takes energy */
    if (scene)
        return rf_surface_scene_event(m);
    if (hit) {
        if (rf_scene_at_once(m) >= 0)
            return RF_END_STOPPED;
        rf_contact_resolve(m, &c); /* knows the face flown off from flight_ex */
        m->rock.flight_ex.n = 0;
        rf_motion_event(m);
        return -1;
    }
    if (te < tc || t_fall <= T)
        return RF_END_EXITED;
    return RF_END_MAX_TIME;
}

static int run_exact(rf_motion *m)
{
    int end = rf_motion_start(m);
    if (end >= 0)
        return end;
    for (;;) {
        /* every pass is an event: the events bound the loop */
        if (++m->book.events > RF_MAX_EVENTS || m->scn.trees_given_up)
            return RF_END_MAX_TIME;
        end = rf_progress(m, 1);
        if (end >= 0)
            return end;
        if (m->rock.s.t >= m->cfg.t_end)
            return RF_END_MAX_TIME;
        if (m->rock.sup.n == 0) {
            end = flight_step(m);
            if (end >= 0)
                return end;
            continue;
        }
        m->book.rec->n_segments++;
        switch (rf_surface_step(m)) {
        case RF_SURF_REST:
            return RF_END_REST;
        case RF_SURF_EXITED:
            return RF_END_EXITED;
        case RF_SURF_MAX_TIME:
            return RF_END_MAX_TIME;
        case RF_SURF_STOPPED:
            return RF_END_STOPPED;
        default:
            break;
        }
    }
}

int rf_simulate(const rf_scene *scene, const rf_body *body, const rf_state *start,
                gsl_rng *rng, rf_workspace *ws, const rf_sink *sink,
                rf_trajectory_record *out)
{
    const rf_terrain *t = scene->terrain;
    const rf_simulation *sim = scene->sim;
    rf_motion m;
    memset(&m, 0, sizeof m);
    m.cfg.scene = scene;
    m.cfg.terrain = t;
    m.cfg.body = body;
    m.rng = rng;
    m.ws = ws;
    m.book.sink = sink;
    m.book.rec = out;
    m.cfg.point = body->model == RF_MODEL_POINT;
    m.cfg.rho = rf_body_contact_radius(body);
    m.cfg.centre = !m.cfg.point && sim->contact == RF_CONTACT_CENTRE;
    double scale = fmax(fmax(fabs(t->xmin), fabs(t->xmax)),
                        fmax(fmax(fabs(t->ymin), fabs(t->ymax)), fmax(fabs(t->zmin), fabs(t->zmax))));
    m.cfg.tol_len = fmax(RF_LEN_TOL, RF_LEN_TOL_REL * scale);
    m.cfg.v_stay = sqrt(2.0 * RF_GRAVITY * RF_STAY_HEIGHT);
    m.rock.s = *start;
    if (m.cfg.point)
        m.rock.s.w = rf_v3(0, 0, 0);
    m.cfg.t_end = start->t + sim->max_time;
    memset(out, 0, sizeof *out);
    out->max_energy_kj = rf_motion_energy(&m) / 1000.0;
    rf_scene_begin(&m);
    rf_motion_event(&m);

    int end = sim->engine == RF_ENGINE_FIXED_STEP ? rf_simulate_fixed_step(&m) : run_exact(&m);
    if (end == RF_END_EXITED && rf_scene_at_once(&m) == RF_END_STOPPED)
        end = RF_END_STOPPED;
    if (m.scn.trees_given_up) /* the tree process was not sampled to the end */
        end = RF_END_MAX_TIME;

    out->reason = (rf_stop_reason)end;
    /* the exact engine's rests are its model's: at rest on a steep face only where a
     * wall or a corner of centre contact holds it */
    out->rest_on_steep_face = end == RF_END_REST && sim->engine == RF_ENGINE_FIXED_STEP &&
                              rf_support_steep(&m);
    if (end == RF_END_REST) {
        m.rock.s.v = rf_v3(0, 0, 0);
        m.rock.s.w = rf_v3(0, 0, 0);
    }
    out->stop = m.rock.s.p;
    out->duration_s = m.rock.s.t - start->t;
    rf_motion_event(&m);
    return 0;
}
