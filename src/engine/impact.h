/* impact.h - the impact law (Eq. 8) and the transfers of a slow rock between faces
 * (impact.c). */
#ifndef ROCKFALL_ENGINE_IMPACT_H
#define ROCKFALL_ENGINE_IMPACT_H

#include "engine/state.h"

/* Draws e_n, mu for the zone of triangle tri and applies the impact (Eq. 8) with unit
 * normal n at the current state.  Returns the rebound normal speed. */
double rf_impact(rf_motion *m, int32_t tri, rf_vec3 n);
/* The impact law itself (Eq. 8) with given e_n and mu, for slope and tree impacts. */
double rf_impact_apply(rf_motion *m, rf_vec3 n, double e, double mu);
/* An impact with approach speed vin (m/s; kinetic energy e0 J before it) counts and is
 * reported when the rock approached the surface; a touch at a grazing speed (the path
 * tangent to the face, as when a centre runs exactly along an edge line) changes
 * nothing and is not an impact. */
void rf_impact_count(rf_motion *m, double e0, double vin);
/* Draws the surface phase's mu and mu_r of triangle tri's zone into m->sup. */
void rf_support_draw(rf_motion *m, int32_t tri);
/* A slow sphere rolls over a convex edge or vertex at q onto face `to`: its centre
 * goes from q + rho u to q + rho n_to, conserving total energy.  Returns 0, or -1 when
 * it cannot climb there (the state is untouched). */
int rf_pivot(rf_motion *m, rf_vec3 q, int32_t to);
/* How far (m) the centre rises above where it is on the way of such a roll onto a face
 * of normal n: over the top of a ridge, or to the end of a roll up onto a shoulder. */
double rf_pivot_rise(const rf_motion *m, rf_vec3 q, rf_vec3 n);

#endif
