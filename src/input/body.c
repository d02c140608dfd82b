/* body.c - the rock as a rigid body (body.h). */
#include "rockfall/body.h"

#include <math.h>

#include "base/util.h"

rf_body rf_body_make(double mass, double density, rf_rock_model model)
{
    rf_body b;
    b.mass = mass;
    b.model = model;
    b.radius = cbrt(3.0 * mass / (4.0 * RF_PI * density));
    b.inertia = 0.4 * mass * b.radius * b.radius; /* solid sphere (Eq. 8b) */
    return b;
}

double rf_body_contact_radius(const rf_body *b) { return b->model == RF_MODEL_POINT ? 0.0 : b->radius; }

double rf_kinetic_energy(const rf_body *b, rf_vec3 v, rf_vec3 w)
{
    double e = 0.5 * b->mass * rf_v3_norm2(v);
    if (b->model == RF_MODEL_SPHERE)
        e += 0.5 * b->inertia * rf_v3_norm2(w);
    return e;
}
