/* exit.h - where the centre leaves the terrain (exit.c). */
#ifndef ROCKFALL_ENGINE_EXIT_H
#define ROCKFALL_ENGINE_EXIT_H

#include "engine/state.h"

/* Time (<= T) at which the centre's horizontal path leaves the terrain (outside its
 * bounds or over a hole); T when it does not. */
double rf_terrain_exit_time(rf_motion *m, const rf_arc *arc, double T);

#endif
