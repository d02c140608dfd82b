/* feature.h - distances from a point to the terrain's faces, edges and vertices
 * (feature.c). */
#ifndef ROCKFALL_ENGINE_FEATURE_H
#define ROCKFALL_ENGINE_FEATURE_H

#include "engine/state.h"

/* Distance from p to the contact's feature (face plane, edge segment or vertex). */
double rf_feature_distance(const rf_terrain *t, const rf_contact *c, rf_vec3 p);
/* Closest terrain feature to p among triangles within `reach` of it: distance, or
 * INFINITY when there is none; fills *c (t = 0). */
double rf_closest_feature(rf_motion *m, rf_vec3 p, double reach, rf_contact *c);
/* The lowest height >= p.z of a centre on the vertical through p at which the rock
 * (contact radius m->cfg.rho) is clear of every face, edge and vertex: p.z when it is. */
double rf_clear_height(rf_motion *m, rf_vec3 p);
/* The triangle under the point a tiny step from q in the horizontal direction dir
 * (the face a rock enters when it leaves `from` at q); -1 for none. */
int32_t rf_face_beyond(const rf_terrain *t, int32_t from, rf_vec3 q, rf_vec3 dir);

#endif
