/* motion_test_util.h - scenes and a recording sink for the motion tests. */
#ifndef ROCKFALL_MOTION_TEST_UTIL_H
#define ROCKFALL_MOTION_TEST_UTIL_H

#include <gsl/gsl_rng.h>

#include "rockfall/sim.h"

/* A sample the sink was given: the centre, speed and kinetic energy there. */
typedef struct mt_sample {
    rf_vec3 p;
    double speed_ms, energy_kj;
} mt_sample;

/* One simulated trajectory and what its sink saw. */
typedef struct mt_run {
    rf_trajectory_record rec;
    rf_path_point *points;   /* every path point */
    size_t npoints, cap;
    rf_path_point *impacts;  /* the path point right after each impact */
    size_t n_impacts, icap;
    rf_path_point last;      /* the end */
    double energy_gain_kj;   /* largest increase of kinetic energy at an impact */
    long pending_impacts;
    int nan_seen;
    long samples;
    double max_sample_gap;   /* largest horizontal distance between samples (m) */
    rf_vec3 last_sample;
    mt_sample *sample;       /* every sample */
    size_t scap;
} mt_run;

/* One trajectory through a scene with measures and what its sink saw. */
#define MT_MAX_ICPT 1024
#define MT_MAX_IMPACTS 4096
typedef struct mt_scene_run {
    rf_trajectory_record rec;
    rf_interception_record icpt[MT_MAX_ICPT];
    int n;
    /* each impact: its time and the kinetic energy before and after it (kJ) */
    double imp_t[MT_MAX_IMPACTS], imp_e0[MT_MAX_IMPACTS], imp_e1[MT_MAX_IMPACTS];
    size_t nimp;
    rf_path_point last;
    long npoints;
} mt_scene_run;

/* Runs one trajectory from s through terrain t with measures ms[0..nms), its random
 * stream seeded with seed, into run (ENSUREs). */
void mt_run_scene(const rf_terrain *t, const rf_simulation *sim, const rf_body *b,
                  const rf_measure *ms, size_t nms, const rf_state *s, unsigned long seed,
                  mt_scene_run *run);
/* A measure named "m" over the polyline xy (n points): a control line collects; a
 * barrier has MEL capacity_kj (SEL a third of it), an embankment capacity_kj as its
 * ultimate capacity (a quarter and a half of it before). */
rf_measure mt_measure(rf_measure_kind kind, rf_behaviour behaviour, double *xy, size_t n,
                      double height, double capacity_kj);

/* Builds a profile terrain (distance, elevation pairs) of the given width; ENSUREs. */
void mt_profile(rf_terrain *t, const double *pts, size_t n, double width, rf_surface s);
/* Builds a terrain from an ESRI ASCII grid or an ascii STL written into the test's
 * temporary directory. */
void mt_dem_text(rf_terrain *t, const char *name, const char *text, rf_surface s);
void mt_mesh_text(rf_terrain *t, const char *name, const char *text, rf_surface s);

/* The text of an ESRI grid of nx * ny nodes at spacing cell from the lower left corner
 * (x0, y0), node (i, j) at height z(i, j, ctx) (-9999: nodata), asked for row by row
 * from the top (j = ny - 1), i ascending in each; malloc'd. */
char *mt_grid_text(int nx, int ny, double cell, double x0, double y0,
                   double (*z)(int i, int j, void *), void *ctx);

/* The text of an ascii STL of ntri triangles, triangle k with corners P[tri[k][0..2]];
 * malloc'd. */
char *mt_stl_text(const rf_vec3 *P, const int (*tri)[3], size_t ntri);

/* The same surface as mt_grid_text's as an ascii STL, nodes at (x0, y0) + (i, j) cell,
 * heights asked for in mt_grid_text's order: each cell split along its SW-NE diagonal,
 * as a grid is, or (alternate) along a diagonal that alternates with the cell's parity
 * (i + j odd: SE-NW); the triangles with a nodata corner left out (holes); malloc'd. */
char *mt_grid_stl_text(int nx, int ny, double cell, double x0, double y0, int alternate,
                       double (*z)(int i, int j, void *), void *ctx);

/* Builds the terrain of mt_grid_text(nx, ny, cell, 0, 0, z, ctx): the ESRI grid, or
 * (mesh) the same surface as an STL (its nodes at the grid's, the cells' centres). */
void mt_grid_terrain(rf_terrain *t, int mesh, int nx, int ny, double cell,
                     double (*z)(int i, int j, void *), void *ctx, rf_surface s);

rf_state mt_state(rf_vec3 p, rf_vec3 v);

/* A plane falling along +x at theta, from height L tan(theta) at x = 0 to 0 at x = L,
 * width wide. */
void mt_incline(rf_terrain *t, double theta, double L, double width, rf_surface s);
/* A state with velocity v whose centre is lift above the incline's point at (x, y),
 * along the plane's normal. */
rf_state mt_incline_state(double theta, double L, double x, double y, double lift, rf_vec3 v);
/* Simulation options of the tests (exact engine, stop_speed 0.1, max_time 300). */
rf_simulation mt_sim(rf_rock_model model, rf_contact_kind contact, double max_time);

void mt_simulate(const rf_terrain *t, rf_rock_model model, double mass, rf_contact_kind contact,
                 const rf_state *s, unsigned long seed, mt_run *r);
void mt_simulate_t(const rf_terrain *t, rf_rock_model model, double mass,
                   rf_contact_kind contact, const rf_state *s, unsigned long seed,
                   double max_time, mt_run *r);
/* Full control: simulation options, body and an optional sample spacing. */
void mt_simulate_opts(const rf_terrain *t, const rf_simulation *sim, const rf_body *b,
                      const rf_state *s, unsigned long seed, double sample_spacing, mt_run *r);
void mt_run_free(mt_run *r);
/* Classical Runge-Kutta for y' = f(y) (at most 8 components) over [0, T] in `steps`
 * equal steps: the tests' reference for laws without a closed form of their own. */
void mt_rk4(void (*f)(const double *y, double *dy, const void *ctx), const void *ctx, double *y,
            int n, double T, long steps);
const rf_path_point *mt_first_impact(const mt_run *r);
/* The most the mechanical energy (kinetic and m g z, J) of a rock of mass `mass` rises
 * along the path points after the start (where the rock may be put onto the terrain)
 * above the least it has had; 0 when it never rises. */
double mt_energy_rise(const mt_run *r, double mass);

/* Smallest distance from p to the terrain (all triangles). */
double mt_terrain_distance(const rf_terrain *t, rf_vec3 p);

#endif
