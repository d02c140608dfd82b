/* bounds.h - the bounds of what an input file may hold and of the values it may give.
 *
 * Each bound is far beyond any real rockfall site, so that no real project meets it, and
 * close enough that the simulation's arithmetic stays meaningful (a speed of 1e300 m/s or
 * a forest of 1e12 stems per m^2 is a typo or an attack, not a design case).  The reasons
 * are in docs/project-file.md, "Bounds". */
#ifndef ROCKFALL_INPUT_BOUNDS_H
#define ROCKFALL_INPUT_BOUNDS_H

#include <stddef.h>
#include <stdint.h>

/* ---- files ---------------------------------------------------------------------- */
#define RF_TEXT_FILE_MAX ((size_t)16 << 20) /* bytes of a project or rule file */
#define RF_TERRAIN_FILE_MAX ((uint64_t)4 << 30) /* bytes of a terrain or points file */
#define RF_YAML_EXPANSION_MAX 10.0  /* a YAML document's nodes with its aliases expanded, per
                                     * node it writes out */
#define RF_YAML_EXPANSION_FLOOR 1e5 /* ... and in any case (small files may alias freely) */
#define RF_GRID_NODES_MAX 1e8       /* nodes of an ASCII grid, ncols x nrows (as triangles,
                                       about 24 GB) */
#define RF_MESH_TRIANGLES_MAX 5e7   /* triangles of all mesh files together */
#define RF_MESH_VERTICES_MAX 5e7    /* vertices of one OBJ file */
#define RF_POINTS_ROWS_MAX 1e7      /* rows of a points file (field data) */

/* ---- places and the terrain ----------------------------------------------------- */
#define RF_COORD_MAX 1e8            /* |x|, |y| of any point, node or vertex (m) */
#define RF_ELEVATION_MAX 1e5        /* |z| of a terrain node or vertex (m) */
#define RF_CELL_MIN 1e-3            /* an ASCII grid's cellsize, least (m) */
#define RF_CELL_MAX 1e5             /* an ASCII grid's cellsize, most (m) */
#define RF_PROFILE_WIDTH_MAX 1e5    /* a profile terrain's width (m) */
#define RF_TIN_TOLERANCE_MAX 1e3    /* a grid's 'tolerance' as a TIN (m; > 0) */
#define RF_TIN_SIDE_MAX 16384       /* nodes along a side of a grid made a TIN: the exact
                                       in-circle test's terms stay below 2^60 in int64 */

/* ---- vegetation ----------------------------------------------------------------- */
#define RF_FOREST_DENSITY_MAX 10.0  /* stems per m^2 (100 000 per hectare) */
#define RF_STEM_DIAMETER_MAX 5.0    /* a stem's diameter (m) */
#define RF_TREE_HEIGHT_MAX 150.0    /* a tree's mean height (m) */

/* ---- rocks and releases --------------------------------------------------------- */
#define RF_ROCK_MASS_MAX 1e9        /* kg */
#define RF_ROCK_RADIUS_MIN 1e-3     /* the radius mass and density give (m) */
#define RF_ROCK_RADIUS_MAX 100.0    /* the radius mass and density give (m) */
#define RF_ROCK_DENSITY_MIN 100.0   /* kg/m^3 */
#define RF_ROCK_DENSITY_MAX 20000.0 /* kg/m^3 */
#define RF_RELEASE_SPEED_MAX 200.0  /* |velocity| of a release (m/s) */
#define RF_RELEASE_HEIGHT_MAX 1e4   /* a release's height above the ground (m) */
#define RF_RELEASE_JITTER_MAX 1e4   /* a release's jitter radius (m) */
#define RF_RELEASE_AREA_POINTS_MAX 1000 /* vertices of a release's area polygon */
#define RF_RELEASE_CELLS_MAX 1e7    /* source cells of a release's cells mask */
#define RF_MASS_LIST_MAX 100000     /* masses in a rock's mass list */
#define RF_MASS_CV_MAX 10.0         /* a log-normal mass's sd over its mean */

/* ---- measures ------------------------------------------------------------------ */
#define RF_MEASURE_HEIGHT_MAX 1000.0 /* a barrier's or embankment's height (m) */
#define RF_CAPACITY_MAX 1e9         /* an energy capacity, MEL or SEL (kJ) */

/* ---- surfaces and the simulation ------------------------------------------------ */
#define RF_FRICTION_MAX 100.0       /* friction and rolling coefficients, their mean and sd */
#define RF_ROUGHNESS_MAX 10.0       /* a surface's roughness length r_s (m) */
#define RF_MAX_TIME_MAX 86400.0     /* simulation max_time (s) */
#define RF_DT_MIN 1e-7              /* simulation dt, least (s) */
#define RF_DT_MAX 1.0               /* simulation dt, most (s) */
#define RF_STOP_SPEED_MAX 100.0     /* simulation stop_speed (m/s) */

#endif
