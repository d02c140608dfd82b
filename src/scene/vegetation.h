/* vegetation.h - trees on the slope taken into account probabilistically (Eq. 9-12).
 *
 * A forest zone holds trees of density rho0, stem diameter phi_t and heights normal
 * (M_ht, sigma_ht).  A rock whose centre is h_r above the ground (Eq. 9-10) can only
 * meet trees taller than h_r, of density rho = rho0 Q((h_r - M_ht) / sigma_ht)
 * (Eq. 11), and meets them as a Poisson process along its horizontal path with rate
 * rho (phi_r + phi_t) per metre (Eq. 12).  The process is sampled exactly by
 * thinning: candidate events at the bound rate sum(rho0 (phi_r + phi_t)), each
 * accepted with the true rate over the bound at the candidate's position - no time
 * step, so the same holds for the exact and the fixed-step engine. */
#ifndef ROCKFALL_VEGETATION_H
#define ROCKFALL_VEGETATION_H

#include <stddef.h>

#include <gsl/gsl_rng.h>

#include "rockfall/project.h"
#include "rockfall/vec3.h"

/* Eq. 11: density (trees per m^2) of the forest's trees taller than h_r. */
double rf_forest_density_above(const rf_forest *f, double h_r);
/* Eq. 12: expected collisions per metre of horizontal path of a rock of diameter
 * phi_r whose centre is h_r above the ground. */
double rf_forest_rate(const rf_forest *f, double h_r, double phi_r);
/* Upper bound of the summed rate of all forests anywhere (for thinning). */
double rf_vegetation_rate_bound(const rf_forest *fs, size_t n, double phi_r);
/* 1 when some forest with trees (density > 0) may cover part of the box: it covers the
 * whole terrain or its polygon's bounding box overlaps.  A scene whose forests all
 * fail this has no tree events at all (no candidate, no random draw). */
int rf_vegetation_touches(const rf_forest *fs, size_t n, double xmin, double ymin, double xmax,
                          double ymax);
/* 1 when forest f covers (x, y). */
int rf_forest_covers(const rf_forest *f, double x, double y);
/* Thinning: given u uniform in [0, 1), the forest whose share of the bound contains
 * u * bound at (x, y) with centre height h_r - a collision with that forest - or -1
 * (the candidate is rejected). */
int rf_vegetation_accept(const rf_forest *fs, size_t n, double x, double y, double h_r,
                         double phi_r, double bound, double u);

/* Time t in (0, T] at which the horizontal path of p(t) = p + v t + a t^2 / 2 has
 * length s (s no longer than the path over [0, T]). */
double rf_horizontal_time_at(rf_vec3 v, rf_vec3 a, double s, double T);
/* Length of the horizontal path over [0, T]. */
double rf_horizontal_length(rf_vec3 v, rf_vec3 a, double T);

/* Fig. 6b: the horizontal contact normal (from the stem's axis to the rock's centre)
 * of a rock moving horizontally along `vh` that meets a vertical stem at lateral
 * offset fraction q in [-1, 1] of the contact distance (uniform across the swept
 * band). */
rf_vec3 rf_tree_contact_normal(rf_vec3 vh, double q);

#endif
