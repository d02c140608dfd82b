/* sim.h - one rock's trajectory over the terrain (Eq. 1-8, Fig. 2-4 and 8).
 *
 * rf_simulate moves one rock from its start until it rests, leaves the terrain, is
 * stopped or runs out of time.  The exact engine is event driven: flight is an exact
 * parabola whose next contact is found by root finding; impacts follow Eq. 8;
 * rolling and sliding are moved per face in closed form, or integrated under error
 * control where the friction direction turns (docs/engine.md).  The fixed-step engine
 * integrates the same model with a time step dt (the paper's successive integration)
 * as the baseline for speed against error.  Everything random is drawn from the
 * caller's GSL stream, so a trajectory depends on its stream alone. */
#ifndef ROCKFALL_SIM_H
#define ROCKFALL_SIM_H

#include <gsl/gsl_rng.h>

#include "rockfall/body.h"
#include "rockfall/project.h"
#include "rockfall/records.h"
#include "rockfall/terrain.h"
#include "rockfall/units.h"


/* The static scene a trajectory moves through. */
typedef struct rf_scene {
    const rf_terrain *terrain;
    const rf_simulation *sim;
    const rf_forest *forests;   /* may be empty */
    size_t nforests;
    const rf_measure *measures; /* may be empty */
    size_t nmeasures;
} rf_scene;

/* Kinematic state of the rock's centre. */
typedef struct rf_state {
    double t;
    rf_vec3 p, v, w; /* position, velocity, angular velocity */
} rf_state;

/* Observers of a trajectory; every callback may be NULL. */
typedef struct rf_sink {
    void *ctx;
    /* At the start, at every event (impact, phase change, crossing) and at the end. */
    void (*path_point)(void *ctx, const rf_path_point *pt);
    /* At least every `sample_spacing` metres of horizontal travel, and at events:
     * centre position, speed, total kinetic energy (kJ), height of the centre above
     * the ground.  For hazard maps. */
    void (*sample)(void *ctx, rf_vec3 p, double speed_ms, double energy_kj, double height_m);
    double sample_spacing;
    void (*interception)(void *ctx, const rf_interception_record *r);
    void (*tree_hit)(void *ctx, const rf_tree_hit_record *r);
    /* At every impact on the terrain or a tree: time, total kinetic energy before and after (kJ)
     * and the normal approach speed (m/s).  For checks and diagnostics. */
    void (*impact)(void *ctx, double t_s, double energy_before_kj, double energy_after_kj,
                   double approach_ms);
} rf_sink;

/* The read-only tables of a terrain the engine searches (triangle boxes, edge lengths
 * in plan, the edges that can be met first, holes): built once per terrain and shared
 * by the workspaces of all threads; t must outlive them.  NULL when out of memory. */
typedef struct rf_terrain_tables rf_terrain_tables;
rf_terrain_tables *rf_terrain_tables_build(const rf_terrain *t);
void rf_terrain_tables_free(rf_terrain_tables *tt);

/* Per-thread scratch reused across trajectories (no allocation in the inner loop).
 * rf_workspace_alloc_shared reads the shared tables tt, which must outlive it;
 * rf_workspace_alloc builds tables of its own for t (one thread, or a test). */
typedef struct rf_workspace rf_workspace;
rf_workspace *rf_workspace_alloc_shared(const rf_terrain_tables *tt);
rf_workspace *rf_workspace_alloc(const rf_terrain *t);
void rf_workspace_free(rf_workspace *ws);

/* Simulates one trajectory from `start` (the centre is placed where the caller says;
 * the caller puts it on or above the ground).  Returns 0; fills out. */
int rf_simulate(const rf_scene *scene, const rf_body *body, const rf_state *start,
                gsl_rng *rng, rf_workspace *ws, const rf_sink *sink,
                rf_trajectory_record *out);

/* Draws from a normal distribution truncated to [lo, hi] (rejection; sd = 0 gives the
 * mean clamped into the interval). */
double rf_draw_truncated(gsl_rng *rng, rf_dist d, double lo, double hi);

#endif
