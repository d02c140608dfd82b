/* body.h - the rock as a rigid body: a sphere of the rock's mass and density, or a
 * point mass. */
#ifndef ROCKFALL_BODY_H
#define ROCKFALL_BODY_H

#include "rockfall/project.h"
#include "rockfall/units.h"
#include "rockfall/vec3.h"

/* The rock: mass, radius and moment of inertia (I = 2/5 m r^2 for the sphere). */
typedef struct rf_body {
    double mass, radius, inertia;
    rf_rock_model model;
} rf_body;

rf_body rf_body_make(double mass, double density, rf_rock_model model);
/* How far from the terrain the centre touches it: r for the sphere, 0 for the point
 * mass (Fig. 2, left). */
double rf_body_contact_radius(const rf_body *b);

/* Total kinetic energy (J): translational plus rotational. */
double rf_kinetic_energy(const rf_body *b, rf_vec3 v, rf_vec3 w);

#endif
