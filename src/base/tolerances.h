/* tolerances.h - every tolerance and iteration bound of the program, in one place.
 * docs/engine.md says how the engine's are used.  Related ones are derived from each
 * other. */
#ifndef ROCKFALL_TOLERANCES_H
#define ROCKFALL_TOLERANCES_H

/* ---- the motion engine ------------------------------------------------------------ */
#define RF_TIME_TOL 1e-13          /* root finding in time (s) */
#define RF_LEN_TOL 1e-9            /* lengths (m); scaled up for large coordinates */
#define RF_REACH_TOLS 4.0          /* a feature, a line or a column within this many length
                                      tolerances is reached */
#define RF_APPROACH_EPS 1e-7       /* approach speeds below this (m/s) are grazing */
#define RF_TOUCH_BAND 1000.0       /* a start within this many length tolerances behind a
                                      surface still touches it */
#define RF_START_TOUCH 1e-6        /* (m) a start this close to the ground touches it */
#define RF_STAY_HEIGHT 1e-3        /* a rebound lower than this (m) stays on the surface */
#define RF_COPLANAR_EPS 1e-9       /* faces whose normals differ less are one plane */
#define RF_CONCAVE_MIN_ANGLE 1e-6  /* (rad) an edge whose faces bend by less is not strictly
                                      concave: the contact search tests it */
#define RF_SLIP_EPS RF_SPEED_EPS   /* slip speed (m/s) below which a sphere rolls */
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
#define RF_CREEP_EVENTS RF_STALL_EVENTS /* events of a slow rock within RF_CREEP_DIST:
                                      it rests */
#define RF_CREEP_DIST 1e-3         /* (m) a slow rock that moves no further creeps */

/* ---- lengths and directions ---------------------------------------------------------- */
#define RF_LEN_TOL_REL 1e-14       /* the length tolerance of a terrain: at least this times
                                      its largest coordinate (rounding of coordinates) */
#define RF_NZ_MIN 1e-12            /* a face's normal z above this is not vertical: the centre
                                      mode divides by it (a centre meets a face r / n.z above) */
#define RF_VERTICAL_EPS 1e-12      /* a face whose area in plan is under this times the sum of
                                      its sides' squares in plan covers no ground (vertical) */
#define RF_PARALLEL_EPS 1e-12      /* a vector within this angle (rad) of the fall line moves
                                      along it (a closed-form segment) */
#define RF_VEC_ZERO 1e-12          /* a velocity (m/s) or acceleration (m/s^2) shorter than
                                      this has no direction to take */
#define RF_DIR_SPEED_EPS 1e-9      /* (m/s) a velocity slower than this does not decide which
                                      way a rock leaves a feature (its acceleration does) */
#define RF_CREASE_MIN_ANGLE RF_CONCAVE_MIN_ANGLE /* (rad) two faces closer than this to
                                      parallel make no crease */
#define RF_CREASE_SNAP 0.01        /* a crease takes a centre at most this part of r (r taken
                                      as at least this many m) from where it is */
#define RF_RADIUS_REL_TOL 1e-6     /* part of r by which a contact point may lie outside its
                                      face, or a feature within r, and still count */
#define RF_PIVOT_REACH 1e-3        /* (m) beyond r: the features a roll over an edge looks at */
#define RF_STEEP_NZ 0.2            /* centre mode: on a face with n.z below this a lift onto its
                                      plane goes along the normal first (Eq. 6) */
#define RF_LINE_MIN_TRAVEL 1e-3    /* part of r: a flight travelling further in plan is
                                      searched along its line in plan */
#define RF_GAP_PROBE 0.01          /* a hole is probed this part of the holder's height over the
                                      edge (of the locator's bucket at a start) beyond it */
#define RF_GAP_PROBE_MAX 100.0     /* ... and at most this many times as far along the path */
#define RF_BEYOND_REL 1e-9         /* the first probe beyond a point (rf_face_beyond) grows
                                      with its coordinates by this part of them */
#define RF_BEYOND_STEP 1e-7        /* (m) the first probe's distance, ten times more each */
#define RF_BEYOND_MAX 1e-3         /* (m) up to this */

/* ---- accelerations and friction ---------------------------------------------------- */
#define RF_ACCEL_EPS 1e-9          /* (m/s^2) an acceleration along a normal below this does not
                                      decide whether a rock moving along a face rises into it */
#define RF_CURVE_EPS RF_ACCEL_EPS  /* (m/s^2) half a normal acceleration below this does not
                                      curve a touching path into a face (f'' / 2; for an edge
                                      or a vertex the quartic's 4 r RF_CURVE_EPS) */
#define RF_EXIT_CURVE_EPS 1e-12    /* (m/s^2) an edge function curving out by more than this
                                      leaves the face at once from on its edge */
#define RF_FRICTION_SLACK 1e-12    /* rolling holds when it needs at most 1 + this times the
                                      friction cap (rounding) */

/* ---- times and iterations ------------------------------------------------------------ */
#define RF_BRACKET_REL 1e-6        /* an event's bracket on a path step ends this part of the
                                      step after the parabola's estimate ... */
#define RF_BRACKET_ABS 1e-12       /* ... plus this (s) */
#define RF_NARROW_MAX_ITER 60      /* regula falsi steps locating an event on a path step */
#define RF_NEWTON_MAX_ITER 8       /* Newton steps from the parabola's estimate first */
#define RF_HODOGRAPH_REL_TOL 4e-16 /* the hodograph's parameter of a time: relative precision */
#define RF_HODOGRAPH_MAX_ITER 200  /* Newton steps of that inversion */
#define RF_ROUGH_MAX_DRAWS 10      /* draws of a rough slope's tilted normal that must face the
                                      incoming velocity; then the real normal is kept */
#define RF_DRAW_MAX_TRIES 1000     /* rejections of a truncated normal draw before its mean is
                                      taken (clamped) */
#define RF_MAX_ARC_SAMPLES 10000000 /* samples of one arc at most */
#define RF_FIXED_MAX_STEPS 1e15    /* steps of one fixed-step trajectory at most */
#define RF_MAX_SEARCH_PIECES 1000000L /* pieces a contact or gap search splits an arc into at
                                      most (a longer arc's pieces are longer) */

/* ---- polynomials and arcs (arc.c) ---------------------------------------------------- */
#define RF_QUAD_ZERO 1e-300        /* a squared acceleration below this is none: the arc is a
                                      straight line */
#define RF_ASINH_REL 1e-30         /* an arc length's asinh term is left out where the squared
                                      offset is under this part of the squared speeds (the
                                      term is then under 1e-28 of the length) */
#define RF_ROOT_MAX_ITER 200       /* Newton steps of a bracketed root at most */
#define RF_ROOT_STEP_TOL (RF_TIME_TOL * 1e-2) /* (s) a Newton step this short ends it ... */
#define RF_ROOT_REL 1e-16          /* ... or shorter than this part of t (or the bracket than
                                      this part of 1 + |t|) */
#define RF_BERNSTEIN_REL 1e-14     /* a quartic is above a level with this part of the size of
                                      its coefficients to spare */
#define RF_DIP_SLOPE 100.0         /* a root below tol is an entry when the polynomial falls
                                      this many times slope_eps there */

/* ---- the terrain ------------------------------------------------------------------- */
#define RF_LOCATE_TOL 1e-9         /* barycentric slack of point location: a point on a shared
                                      edge or vertex is in both triangles, never in the crack
                                      between them */
#define RF_DEGENERATE_REL 1e-12    /* a triangle with |(b - a) x (c - a)| below this times its
                                      longest edge squared has no area and is dropped */
#define RF_ON_EDGE_REL RF_DEGENERATE_REL /* a point whose cross product with a polygon's edge
                                      is below this times the edge squared lies on it */

/* ---- the scene: measures' lines and trees ------------------------------------------ */
#define RF_SEGMENT_FRACTION_TOL 1e-12 /* a crossing's fraction along a line's segment may lie
                                      this far outside [0, 1], so a crossing through a vertex
                                      is on both neighbouring segments (reported once) */
#define RF_CROSSING_EPS 1e-12      /* (s) a motion piece looks for crossings after this: one
                                      that starts on a line (the piece before counted it) does
                                      not count it again, and a crossing through a vertex of a
                                      line (a root of both its segments) counts once */
#define RF_ODOMETER_REL 1e-15      /* the time at which a flight has travelled a distance in
                                      plan: relative precision (of max(1, T)) */
#define RF_ODOMETER_MAX_ITER 100   /* Newton steps of that search at most */
#define RF_TREE_MAX_DRAWS 1000000L /* candidate tree events one trajectory draws at most; then
                                      it is given up (max_time): 400 km of travel at a rate
                                      bound of 2.5 per m (1 stem per m^2 of 0.5 m, a 2 m rock) */

/* ---- statistics and figures --------------------------------------------------------- */
#define RF_HULL_TOL 1e-9           /* (m) a point this close outside a hull is inside it */
#define RF_TICK_SNAP 1e-9          /* part of a step: an axis tick or a bin edge this close to a
                                      multiple of its step is on it */

#endif
