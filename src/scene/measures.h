/* measures.h - protection measures on the slope: exact crossings of their polylines
 * by the horizontal path of the rock's centre, and what a measure does to a rock. */
#ifndef ROCKFALL_MEASURES_H
#define ROCKFALL_MEASURES_H

#include <stddef.h>

#include "base/tolerances.h" /* RF_CROSSING_EPS */
#include "input/measure_kinds.h" /* rf_measure_breaking_energy */
#include "rockfall/project.h"
#include "rockfall/records.h"
#include "rockfall/vec3.h"

/* A crossing of measure `measure`'s polyline at time t of a motion piece, on its
 * segment `segment` at fraction u (0 at its first point, 1 at its second). */
typedef struct rf_crossing {
    int measure;
    size_t segment;
    double t, u;
} rf_crossing;

/* Earliest crossing over (t_after, T] of any measure's polyline by the horizontal
 * path of p(t) = p + v t + a t^2 / 2 (the centre over one motion piece: a flight
 * parabola or a piece of rolling, both exact quadratics).  A path that only touches a
 * polyline without crossing it is no crossing.  Returns 1 and fills *c when there is
 * one. */
int rf_measures_first_crossing(const rf_measure *ms, size_t n, rf_vec3 p, rf_vec3 v,
                               rf_vec3 a, double t_after, double T, rf_crossing *c);
/* Every measure crossed at that earliest time (measures drawn on the same line are
 * crossed together), one crossing per measure in the order of the measures, at most
 * `cap`; returns how many. */
#define RF_MAX_COINCIDENT_CROSSINGS 32
int rf_measures_first_crossings(const rf_measure *ms, size_t n, rf_vec3 p, rf_vec3 v,
                                rf_vec3 a, double t_after, double T, rf_crossing *out,
                                int cap);

/* What measure m does to a rock whose centre passes at `passing_height_m` above the
 * ground with total kinetic energy `energy_kj`: a control line lets it pass; above a
 * barrier's or embankment's height (or at a height not known: NaN) it overtops; below
 * it, a `collect` measure lets it pass, and a `stop` measure stops it within its
 * capacity and lets it break through above.  Only `stopped` and `broke_through` change
 * the rock. */
rf_outcome rf_measure_outcome(const rf_measure *m, double passing_height_m, double energy_kj);

#endif
