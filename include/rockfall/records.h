/* records.h - what a simulation produces, row by row, before it reaches the database. */
#ifndef ROCKFALL_RECORDS_H
#define ROCKFALL_RECORDS_H

#include "rockfall/project.h" /* rf_outcome */
#include "rockfall/vec3.h"

typedef enum rf_stop_reason {
    RF_END_REST,     /* came to rest on the slope */
    RF_END_EXITED,   /* left the terrain (edge or nodata hole) */
    RF_END_STOPPED,  /* stopped by a measure */
    RF_END_MAX_TIME  /* simulation.max_time reached */
} rf_stop_reason;

typedef struct rf_trajectory_record {
    rf_vec3 stop;            /* centre of the rock at the end */
    rf_stop_reason reason;
    double duration_s;
    double path_length_m;    /* length of the centre's path */
    double max_energy_kj;    /* largest total kinetic energy along the path */
    long n_impacts;
    long n_tree_hits;
    /* The work of the trajectory, for the bench (not stored): flights (one per pass of
     * the event loop in flight, one per step of the fixed-step engine), surface segments
     * (the set-ups of a segment on a face, a wall or a crease: one per pass on the
     * surface, one per step), and the grid edges crossed onto a rising face without an
     * impact (docs/engine.md, "The rolling phase"). */
    long n_flights;
    long n_segments;
    long n_edge_transitions;
    double edge_loss_kj;     /* energy the edge transitions took: kinetic, and with
                              * centre contact the offset planes' step down (not stored) */
    int rest_on_steep_face;  /* 1: the fixed-step engine put the rock to rest on a face
                              * steeper than its friction holds (tan theta > mu), which
                              * the exact engine would not; 0 otherwise (the exact engine
                              * never sets it); trajectories.rest_steep */
    double mass_kg;          /* the drawn mass the trajectory ran with; 0: not known
                              * (stored NULL); trajectories.mass_kg */
    rf_vec3 start;           /* the rock's centre at the start; trajectories.start_x/y/z
                              * (stored NULL with mass_kg 0) */
} rf_trajectory_record;

typedef struct rf_interception_record {
    int measure;             /* index into the project's measures */
    double t_s;
    rf_vec3 p;               /* centre of the rock at the crossing */
    double speed_ms;
    double energy_kj, energy_trans_kj, energy_rot_kj;
    double passing_height_m; /* centre above the ground at the crossing */
    rf_outcome outcome;
} rf_interception_record;

typedef struct rf_tree_hit_record {
    double t_s;
    rf_vec3 p;
    double speed_before_ms, speed_after_ms;
    double energy_lost_kj;
} rf_tree_hit_record;

typedef struct rf_path_point {
    double t_s;
    rf_vec3 p;
    double speed_ms, energy_kj;
} rf_path_point;

typedef struct rf_hazard_cell_record {
    long ix, iy;
    double x, y;             /* cell centre */
    long passes;             /* trajectories that crossed the cell */
    double reach_probability;
    double energy_max_kj, energy_p95_kj, height_p95_m;
} rf_hazard_cell_record;

const char *rf_stop_reason_name(rf_stop_reason r);
const char *rf_outcome_name(rf_outcome o);
/* The outcome named `text` (as rf_outcome_name writes it); RF_OUT_PASSED for any other
 * text or NULL. */
rf_outcome rf_outcome_from_name(const char *text);

#endif
