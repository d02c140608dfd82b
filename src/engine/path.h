/* path.h - segments of surface motion off the fall line (path.c), in closed form
 * (hodograph.c). */
#ifndef ROCKFALL_ENGINE_PATH_H
#define ROCKFALL_ENGINE_PATH_H

#include "engine/state.h"
#include "engine/geometry.h"
#include "engine/surface_law.h"

rf_surface_end rf_face_path(rf_motion *m, const rf_face_dyn *f, rf_vec3 u0, const rf_face_edges *fe,
                                int holds);

#endif
