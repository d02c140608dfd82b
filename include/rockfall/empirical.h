/* empirical.h - the empirical estimates of the paper's section 2.1 (Eq. 1-2, Table 2,
 * Fig. 1b), used as a crosscheck beside the simulation. */
#ifndef ROCKFALL_EMPIRICAL_H
#define ROCKFALL_EMPIRICAL_H

/* Eq. 2: residual coefficient of velocity alpha = sqrt(1 - mu / tan(theta)); 0 when the
 * slope is too gentle for the rock to keep moving (mu >= tan(theta)). */
double rf_empirical_alpha(double mu, double slope_rad);
/* Eq. 1: V = alpha sqrt(2 g H) (m/s). */
double rf_empirical_velocity(double height_m, double slope_rad, double mu);
/* Fig. 1b: width of the attainment range at the slope foot, the lines at beta to both
 * sides of the release's fall line: 2 L tan(beta), L the horizontal distance from the
 * release to the foot. */
double rf_empirical_attainment_width(double horizontal_distance_m, double beta_rad);

#endif
