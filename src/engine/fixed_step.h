/* fixed_step.h - the fixed-step baseline engine (fixed_step.c). */
#ifndef ROCKFALL_ENGINE_FIXED_STEP_H
#define ROCKFALL_ENGINE_FIXED_STEP_H

#include "engine/state.h"

/* Runs the trajectory of m, set up by rf_simulate, with the fixed-step engine; returns
 * its end reason. */
int rf_simulate_fixed_step(rf_motion *m);

#endif
