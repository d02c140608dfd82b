/* units.h - SI units throughout (m, kg, s; energies reported in kJ); gravity along -z. */
#ifndef ROCKFALL_UNITS_H
#define ROCKFALL_UNITS_H

#define RF_GRAVITY 9.81 /* m/s^2 */
#define RF_PI 3.14159265358979323846

#endif
