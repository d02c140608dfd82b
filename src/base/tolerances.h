/* tolerances.h - every tolerance and iteration bound of the program, in one place.
 * docs/engine.md says how the engine's are used.  Related ones are derived from each
 * other. */
#ifndef ROCKFALL_TOLERANCES_H
#define ROCKFALL_TOLERANCES_H

/* ---- the motion engine ------------------------------------------------------------ */
#define RF_TIME_TOL 1e-13          /* root finding in time (s) */
#define RF_LEN_TOL 1e-9            /* lengths (m); scaled up for large coordinates */
#define RF_APPROACH_EPS 1e-7       /* approach speeds below this (m/s) are grazing */
#define RF_TOUCH_BAND 1000.0       /* a start within this many length tolerances behind a
                                      surface still touches it */
#define RF_START_TOUCH 1e-6        /* (m) a start this close to the ground touches it */
#define RF_STAY_HEIGHT 1e-3        /* a rebound lower than this (m) stays on the surface */
#define RF_COPLANAR_EPS 1e-9       /* faces whose normals differ less are one plane */
#define RF_CONCAVE_MIN_ANGLE 1e-6  /* (rad) an edge whose faces bend by less is not strictly
                                      concave: the contact search tests it */
#define RF_SLIP_EPS 1e-6           /* slip speed (m/s) below which a sphere rolls */
#define RF_PATH_DEV 1e-6           /* (m) a surface step's path departs from its parabola
                                      by about this much at most: a contact the parabola
                                      misses is met at the next step's start, within the
                                      touch band (RF_TOUCH_BAND * RF_LEN_TOL) */
#define RF_PATH_MAX_DT 0.05        /* (s) longest step of a surface segment */
#define RF_PATH_MAX_STEPS 100000   /* steps of one surface segment */
#define RF_PATH_MAX_SKIPS 4        /* contacts of a step's parabola its path does not make,
                                      passed over to find a later one */
#define RF_SPEED_EPS 1e-6          /* speeds below this (m/s) on a face count as rest */
#define RF_MAX_EVENTS 200000       /* a trajectory ends (max_time) after this many events */
#define RF_STALL_EVENTS 16         /* events without progress in time before a rescue */
#define RF_STALL_TIME 1e-9         /* (s) less than this is no progress */
#define RF_MAX_RESCUES 1000        /* rescues before a trajectory is given up (max_time) */
#define RF_UNSTALL_TIME 1e-6       /* free motion of a rescue (s) */
#define RF_SETTLE_REACH 1000.0     /* a wedged rock (centre mode) is settled in a column
                                      within this many length tolerances */
#define RF_CREEP_EVENTS 16         /* events of a slow rock within RF_CREEP_DIST: it rests */
#define RF_CREEP_DIST 1e-3         /* (m) */

#endif
