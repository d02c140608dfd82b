/* scenes.h - analytic scenes with closed-form answers, shared by the tests and the
 * benchmark: each runs one trajectory under a given engine setting and returns its
 * relative error against the closed form. */
#ifndef ROCKFALL_SCENES_H
#define ROCKFALL_SCENES_H

#include "rockfall/project.h"
#include "rockfall/sim.h"

enum {
    RF_CF_SLIDE,  /* point mass sliding down a plane: Eq. 1-2 */
    RF_CF_ROLL,   /* sphere rolling down a plane: a = 5/7 g (sin - mu_r cos) */
    RF_CF_LAUNCH, /* horizontal launch over flat ground: lands at v0 sqrt(2h/g) */
    RF_CF_BOUNCE, /* vertical drop, restitution e: bounce heights h e^(2k) */
    RF_N_CLOSED_FORMS
};

const char *rf_closed_form_name(int which);
/* Relative error of the engine setting `sim` (engine, dt, contact; the model is set
 * by the scene) against closed form `which`; NAN when the run went wrong. */
double rf_closed_form_error(int which, const rf_simulation *sim);

/* A plane profile terrain: (distance, elevation) points extruded over `width`, one
 * surface s; err filled on failure. */
int rf_scene_profile_surface(rf_terrain *t, const double *points, size_t npoints, double width,
                             rf_surface s, rf_error *err);
/* The same with the given constant coefficients. */
int rf_scene_profile(rf_terrain *t, const double *points, size_t npoints, double width,
                     double restitution, double friction, double rolling);

#endif
