/* contact.h - the earliest contact of the rock with the terrain along an arc
 * (contact.c), and the triangles near a box. */
#ifndef ROCKFALL_ENGINE_CONTACT_H
#define ROCKFALL_ENGINE_CONTACT_H

#include "engine/state.h"

/* Gathers the triangles whose xy box overlaps the box into ws->cand; returns count. */
size_t rf_gather(rf_motion *m, double xmin, double ymin, double xmax, double ymax);
/* Earliest contact along `arc` over [0, T] of the rock (contact radius m->cfg.rho; centre
 * mode tests the face under the centre only).  The faces, edges and vertices of the
 * support triangles in `ex` are ignored.  Returns 1 and fills *c when there is one. */
int rf_contact_search(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                      rf_contact *c);
/* rf_contact_search for a surface segment: the arc lies on the support planes (m->rock.sup),
 * the support faces, faces in their planes and features on or below a support plane
 * are skipped (a centre r above the plane cannot reach them), and so are the nskip
 * features in skip (contacts of the step's parabola that the exact path does not
 * make). */
int rf_contact_search_near(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                           const rf_contact *skip, int nskip, rf_contact *c);
/* The first contact of a flight along arc over [0, T], the face flown off (flight_ex)
 * left out; both engines' flights take it. */
int rf_flight_contact(rf_motion *m, const rf_arc *arc, double T, rf_contact *c);

#endif
