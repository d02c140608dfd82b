/* empirical.c - Eq. 1-2 and the attainment width of Fig. 1b. */
#include "rockfall/empirical.h"

#include <math.h>

#include "rockfall/units.h"

double rf_empirical_alpha(double mu, double slope_rad)
{
    double r = 1.0 - mu / tan(slope_rad); /* Eq. 2 */
    return r > 0.0 ? sqrt(r) : 0.0;
}

double rf_empirical_velocity(double height_m, double slope_rad, double mu)
{
    return rf_empirical_alpha(mu, slope_rad) * sqrt(2.0 * RF_GRAVITY * height_m); /* Eq. 1 */
}

double rf_empirical_attainment_width(double horizontal_distance_m, double beta_rad)
{
    return 2.0 * horizontal_distance_m * tan(beta_rad); /* Fig. 1b */
}
