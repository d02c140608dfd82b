/* roughness.h - the random tilt of the contact normal at a bounce on a rough slope
 * (roughness.c): the one place that law lives. */
#ifndef ROCKFALL_ENGINE_ROUGHNESS_H
#define ROCKFALL_ENGINE_ROUGHNESS_H

#include <gsl/gsl_rng.h>

#include "rockfall/vec3.h"

/* The tilted contact normal of an impact of velocity v on a surface of unit normal n
 * (towards the centre, v . n < 0) with roughness length rs > 0 (m) and a rock of radius
 * `radius` (m, > 0).  Draws theta = U1 atan(rs / radius), then tilts n by theta U2 about
 * d x n against the motion and by theta (1 - U2) about d to a side drawn by U3, d the
 * unit tangential direction of v (drawn uniformly in the plane when v has none).  A
 * tilted normal that would not face v is drawn again, at most RF_ROUGH_MAX_DRAWS
 * times.  Returns 1 with *nt (unit) and *theta (the drawn angle, rad; theta may be
 * NULL), or 0 with *nt = n when every draw was rejected. */
int rf_rough_normal(gsl_rng *rng, rf_vec3 n, rf_vec3 v, double rs, double radius, rf_vec3 *nt,
                    double *theta);

#endif
