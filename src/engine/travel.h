/* travel.h - what the pieces of motion the rock takes pass on the way (travel.c):
 * the lines of measures being passed, and the horizontal distance travelled that the
 * tree process is sampled in. */
#ifndef ROCKFALL_ENGINE_TRAVEL_H
#define ROCKFALL_ENGINE_TRAVEL_H

#include "engine/state.h"

/* The largest horizontal distance from the passage's line over [0, T] of the arc. */
double rf_passage_reach(const rf_passage *ps, const rf_arc *arc, double T);
/* The passage of measure `which`, or NULL. */
rf_passage *rf_passage_of(rf_motion *m, int which);
/* A crossing of segment c->segment of its measure recorded: that measure's passage
 * starts (the oldest passage makes room when all are taken). */
void rf_passage_start(rf_motion *m, const rf_crossing *c);
/* Accounts for horizontal travel along a taken arc over [0, T]: passages the rock has
 * moved further than its radius from are over; the tree odometer moves on. */
void rf_scene_travel(rf_motion *m, const rf_arc *arc, double T);

#endif
