/* surface.h - one step of the surface phase (surface.c): on one face, along a wall of
 * the centre mode, or in a crease. */
#ifndef ROCKFALL_ENGINE_SURFACE_H
#define ROCKFALL_ENGINE_SURFACE_H

#include "engine/state.h"
#include "engine/geometry.h"

/* Centre mode, a rock on one face on edge `edge` of its column (col: its edges), which the
 * fixed-step engine's step would leave over at once: when the face it would enter
 * there is one it cannot pay the lift onto (a wall), it meets the wall as the exact
 * engine's segments do.  Returns RF_SURF_REST, or RF_SURF_CONTINUE when it stopped in
 * a corner of two walls; else -1, with *wall the column edge it moves along (-1: no
 * wall) and *dir the way it moves. */
int rf_wall_meet(rf_motion *m, const rf_face_edges *col, int edge, int *wall, rf_vec3 *dir);
/* Moves the rock on its support until the next event and handles it. */
rf_surface_end rf_surface_step(rf_motion *m);

#endif
