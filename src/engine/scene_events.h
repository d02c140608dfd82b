/* scene_events.h - events of the scene beyond the terrain (scene_events.c): tree
 * collisions and measure crossings, the extension point of the vegetation and measures
 * modules. */
#ifndef ROCKFALL_ENGINE_SCENE_EVENTS_H
#define ROCKFALL_ENGINE_SCENE_EVENTS_H

#include "engine/state.h"

/* Sets up the scene events of a new trajectory (draws the first tree candidate). */
void rf_scene_begin(rf_motion *m);
/* Every piece of exact motion - a flight, a closed-form surface segment, one
 * integrator step - is offered as an arc over [0, T] before it is taken: returns the
 * earliest time in [0, T] at which a scene event cuts it (T when none) and remembers
 * the event (m->scn.pending). */
double rf_scene_horizon(rf_motion *m, const rf_arc *arc, double T);
/* Handles the event rf_scene_horizon found, once the state has been moved there.
 * Returns -1 to go on or an end reason (RF_END_STOPPED).  *onto: the face a rock on
 * the surface goes back onto after a tree hit that leaves it there (its velocity to be
 * made tangent, rf_surface_enter; the event's path point is then the caller's to
 * record, after that), or -1: the event is complete. */
int rf_scene_event(rf_motion *m, int32_t *onto);
/* The crossings at this very moment, which a piece of motion ending here (at another
 * event, or a hair short of the line) leaves to the next one: taken before the rock
 * leaves the terrain (either engine's `exited`: there is no next piece) and before an
 * impact on the terrain takes its energy (a line on a concave edge records the rock as
 * it arrives).  Returns RF_END_STOPPED when a measure stops it here, else -1. */
int rf_scene_at_once(rf_motion *m);

#endif
