/* progress.h - the start of a trajectory, the progress watch and the rescue
 * (progress.c), shared by both engines. */
#ifndef ROCKFALL_ENGINE_PROGRESS_H
#define ROCKFALL_ENGINE_PROGRESS_H

#include "engine/state.h"

/* Places the rock at the start of a trajectory: on the surface when it touches it
 * (landing, or an impact when it moves into it), else in flight.  Returns -1 to go on
 * or an end reason; going on, progress (rf_progress) is watched from there.  Shared by
 * both engines. */
int rf_motion_start(rf_motion *m);
/* Centre mode: of the faces whose columns hold the centre (several on a border, within
 * the length tolerance), the one whose offset plane is highest there; tri is the one
 * located.  A centre lifted onto it lies on or above every plane of a column that
 * holds it. */
int32_t rf_highest_column(rf_motion *m, int32_t tri);
/* The rock's progress, at every turn of either engine's loop: a rock that meets events
 * without moving in time (degenerate contact geometry) rests when slow, else moves free
 * for a moment (RF_UNSTALL_TIME) and is put back on or above the surface under it.
 * With `events` (every turn is an event: the exact engine), a slow rock that creeps on
 * the spot (RF_CREEP_EVENTS events within RF_CREEP_DIST, below stop_speed: wedged in a
 * pocket of faces that no single face or crease law holds, each event moving it a
 * little) rests too; the fixed-step engine's turns are mostly plain steps.  Returns an
 * end reason, RF_RESCUED after a rescue, or -1. */
#define RF_RESCUED -2
int rf_progress(rf_motion *m, int events);
/* The rescue of rf_progress, at once: RF_RESCUED; rest for a rock in centre mode
 * wedged among walls (it cannot pay the lift onto the column under it) where it was
 * last wedged; max_time after RF_MAX_RESCUES. */
int rf_rescue(rf_motion *m);

#endif
