/* project.h - a project file (YAML) as plain structs.
 *
 * rf_project_load parses, validates and builds in one pass at the boundary: every
 * value is checked there (unknown keys, types, ranges, references, releases on the
 * terrain) and everything after it trusts the structs.  Defaults are documented next
 * to each field and in docs/project-file.md. */
#ifndef ROCKFALL_PROJECT_H
#define ROCKFALL_PROJECT_H

#include <stddef.h>
#include <stdint.h>

#include "rockfall/error.h"
#include "rockfall/terrain.h"
#include "rockfall/vec3.h"

typedef struct rf_polyline {
    double *xy; /* 2 * n numbers: x0, y0, x1, y1, ... */
    size_t n;
} rf_polyline;

typedef struct rf_forest {
    char *name;
    rf_polyline polygon; /* n == 0: the whole terrain */
    double density;      /* rho0, trees per m^2 (>= 0) */
    rf_dist height;      /* tree height M_ht, sigma_ht (m) */
    double diameter;     /* stem diameter phi_t (m, > 0) */
    rf_dist restitution; /* rock-tree; default {0.2, 0} */
    rf_dist friction;    /* rock-tree; default {0.3, 0} */
} rf_forest;

/* How a rock's mass is given: a number, a log-normal {mean, sd} of the mass
 * (sigma^2 = ln(1 + sd^2 / mean^2), mu = ln(mean) - sigma^2 / 2), or a list of masses
 * each drawn with equal probability. */
typedef enum rf_mass_kind { RF_MASS_FIXED, RF_MASS_LOGNORMAL, RF_MASS_LIST } rf_mass_kind;

typedef struct rf_rock {
    char *name;
    double mass;      /* kg, > 0 (required): the number, the mean, or the list's mean */
    rf_mass_kind mass_kind; /* default fixed */
    double mass_sd;   /* log-normal: the sd of the mass (kg, >= 0) */
    double *masses;   /* list: its masses (kg) */
    size_t nmasses;
    double density;   /* kg/m^3, > 0; default 2650 */
    int action_level; /* 1..3 (Table 3); default 2 */
    double radius;    /* derived: (3 m / (4 pi rho))^(1/3) */
} rf_rock;

/* The most trajectories of one release (the project's `count`, the command line's
 * --count). */
#define RF_COUNT_MAX 1000000000L

/* Where a release's trajectories start: its point, uniform over a polygon (`area`), or
 * uniform within each non-zero cell of a raster mask (`cells`, `count` per cell). */
typedef enum rf_release_source { RF_SOURCE_POINT, RF_SOURCE_AREA, RF_SOURCE_CELLS } rf_release_source;

typedef struct rf_release {
    char *name;
    double x, y;      /* the point; an area's centroid; a mask's first source cell's centre */
    double z;         /* derived: terrain height at (x, y) (area: at its first vertex when
                       * the centroid is off the terrain) */
    rf_release_source source; /* default point */
    double *area;     /* area: the polygon's vertices, x y pairs */
    size_t narea;
    size_t *area_tri; /* area: its triangulation, 3 vertex indices per triangle */
    double *area_cum; /* area: cumulative triangle areas, the last the polygon's area */
    size_t ntri;
    double *cells;    /* cells: each source cell's centre, x y pairs */
    size_t ncells;
    double cell;      /* cells: the mask's cell size (m) */
    int rock;         /* index into rocks (required, by name) */
    long count;       /* trajectories (per source cell for `cells`); >= 1; default 1 */
    double height;    /* height of the rock's lowest point above the ground; default 0 */
    rf_vec3 velocity; /* initial velocity (m/s); default 0 */
    double jitter;    /* radius of the random horizontal offset (m, >= 0); default 0 */
} rf_release;

/* The row of a measure's kind in rf_measure_kinds (src/input/measure_kinds.c), the
 * one table of what each kind is and does; RF_N_MEASURE_KINDS counts them. */
typedef enum rf_measure_kind {
    RF_BARRIER, RF_EMBANKMENT, RF_CONTROL, RF_N_MEASURE_KINDS
} rf_measure_kind;
/* What a measure does to a rock that crosses it (interceptions.outcome). */
typedef enum rf_outcome {
    RF_OUT_STOPPED, RF_OUT_OVERTOPPED, RF_OUT_BROKE_THROUGH, RF_OUT_PASSED
} rf_outcome;
typedef enum rf_importance { RF_MOST_IMPORTANT, RF_IMPORTANT, RF_USUAL } rf_importance;
#define RF_N_IMPORTANCES 3
typedef enum rf_behaviour { RF_STOP, RF_COLLECT } rf_behaviour;
/* Limit states in order (Table 3); RF_COLLAPSE is beyond the last. */
typedef enum rf_limit_state {
    RF_SERVICEABILITY, RF_RESTORABILITY, RF_ULTIMATE, RF_NEAR_COLLAPSE, RF_COLLAPSE
} rf_limit_state;
#define RF_N_LIMIT_STATES 4

typedef struct rf_measure {
    char *name;
    rf_measure_kind kind;
    rf_polyline line;           /* >= 2 points */
    double height;              /* screen height above ground (m); control: 0 */
    rf_importance importance;   /* default RF_IMPORTANT */
    rf_behaviour behaviour;     /* default RF_STOP; control lines are always RF_COLLECT */
    double mel, sel;            /* barrier: MEL (kJ, required), SEL default MEL/3 */
    int sel_given;              /* barrier: 1 when the project gives sel, 0 when sel is
                                   the default MEL/3 (measures.sel_source) */
    double capacity[RF_N_LIMIT_STATES]; /* kJ per limit state; < 0 when not given.
                                           Barrier: serviceability = SEL, ultimate = MEL */
} rf_measure;

typedef enum rf_rock_model { RF_MODEL_SPHERE, RF_MODEL_POINT } rf_rock_model;
typedef enum rf_engine_kind { RF_ENGINE_EXACT, RF_ENGINE_FIXED_STEP } rf_engine_kind;
typedef enum rf_contact_kind { RF_CONTACT_FULL, RF_CONTACT_CENTRE } rf_contact_kind;

typedef struct rf_simulation {
    rf_rock_model model;     /* default sphere */
    rf_engine_kind engine;   /* default exact */
    double dt;               /* fixed-step time step (s); default 0.001 */
    rf_contact_kind contact; /* default full (every face, edge, vertex within r) */
    double stop_speed;       /* m/s; default 0.1 */
    double max_time;         /* s; default 300 */
    long paths;              /* trajectories per release with sampled paths; default 10 */
} rf_simulation;

/* The coordinate reference system of the project's coordinates (input/crs.h); all
 * NULL when the project has none (the results then use GeoPackage's undefined
 * Cartesian CRS). */
typedef struct rf_crs {
    char *source; /* as given: "EPSG:2154", the WKT file's path or the DEM's .prj */
    char *name;   /* PROJ's name of it */
    char *wkt;    /* OGC WKT 1, as gpkg_spatial_ref_sys.definition holds it */
    char *auth;   /* the authority of its code ("EPSG"); NULL when PROJ names none */
    long code;    /* its code in that authority */
} rf_crs;

typedef struct rf_project {
    char *path;       /* the project file as given */
    char *dir;        /* its directory, for relative paths */
    char *yaml_text;  /* the whole file, stored with each run */
    char *name;       /* required */
    uint64_t seed;    /* default 1 */

    rf_terrain_spec terrain_spec;
    rf_terrain terrain;

    rf_forest *forests; size_t nforests;
    rf_rock *rocks; size_t nrocks;
    rf_release *releases; size_t nreleases;
    rf_measure *measures; size_t nmeasures;
    rf_simulation sim;
    double hazard_cell;  /* m, > 0; default 5 */
    char *rules_path;    /* resolved; NULL when the project names no rules */
    rf_crs crs;          /* `crs:`, or the DEM's .prj; source NULL: none */
} rf_project;

/* Loads, validates and builds a project (terrain included).  On error fills err with
 * file:line:column and returns nonzero; nothing is left allocated in p. */
int rf_project_load(const char *path, rf_project *p, rf_error *err);
/* The same from len bytes at data (no NUL needed, at most 16 MiB) as if read from the file
 * `path`, which names it in errors and whose folder the project's own paths (terrain,
 * rules) are relative to: a project with a `profile` terrain and no rules touches no
 * file. */
int rf_project_load_from_memory(const char *data, size_t len, const char *path, rf_project *p,
                                rf_error *err);
void rf_project_free(rf_project *p);
/* The trajectories of a release: count, or count per source cell of a `cells` mask. */
long rf_release_trajectories(const rf_release *r);
/* The source cell trajectory idx of a `cells` release starts in (0 .. ncells - 1, in the
 * mask's order: row by row from the south-west, as rf_release.cells holds them):
 * idx / count; -1 for a point or area release. */
long rf_release_source_cell(const rf_release *r, long idx);

const char *rf_measure_kind_name(rf_measure_kind k);
const char *rf_importance_name(rf_importance i);
const char *rf_behaviour_name(rf_behaviour b);
const char *rf_limit_state_name(rf_limit_state s);

/* The names of the limit states in order (RF_SERVICEABILITY .. RF_NEAR_COLLAPSE; collapse,
 * beyond the last, is no key) and of the importances, NULL-ended: the keys and values
 * the project and the rule files use. */
extern const char *const rf_limit_state_names[RF_N_LIMIT_STATES + 1];
extern const char *const rf_importance_names[RF_N_IMPORTANCES + 1];

#endif
