/* impact.h - every impact of the rock, through one function (Eq. 8 on the slope and
 * on stems; the walls of the centre mode), and the transfers of a slow rock between
 * faces (impact.c). */
#ifndef ROCKFALL_ENGINE_IMPACT_H
#define ROCKFALL_ENGINE_IMPACT_H

#include "engine/state.h"

/* The kinds of impact: each is a row of draw_coefficients (where e_n and mu come
 * from) and of rf_impact (its law). */
typedef enum rf_impact_kind {
    RF_IMPACT_SLOPE,     /* a face, edge or vertex of the terrain: the zone's law (Eq. 8,
                            e_n and mu, or rt, e_n and R_t) of triangle id's zone, along
                            the normal tilted by its roughness */
    RF_IMPACT_WALL,      /* centre mode, the border of a column the rock cannot pay the
                            lift onto, met in flight: reflection with e_n of id's zone */
    RF_IMPACT_WALL_MEET, /* centre mode, such a wall met by a rock on its face: the
                            velocity across it is taken; no coefficient */
    RF_IMPACT_TREE       /* a stem of forest id (Fig. 6b): Eq. 8 with its e_n and mu */
} rf_impact_kind;

/* Where and how the rock meets what it hits. */
typedef struct rf_impact_site {
    rf_impact_kind kind;
    int32_t id;       /* the triangle met (slope, wall), or the forest (tree) */
    rf_vec3 n;        /* slope, tree: unit normal towards the centre; wall: horizontal,
                         into the wall; wall meet: the face's normal */
    double vin;       /* wall: the approach speed along n */
    /* wall: 1 when the reflected velocity v leaves the rock against another wall */
    int (*corner)(rf_motion *m, rf_vec3 v, const void *ctx);
    const void *ctx;
    rf_vec3 l;        /* wall meet: unit direction along the wall */
    int corner_stop;  /* wall meet: in a corner of two walls (the rock stops) */
    int slide;        /* wall meet: a slipping sphere */
} rf_impact_site;

/* What an impact leaves besides the state. */
typedef struct rf_impact_out {
    rf_vec3 u;        /* wall meet: the slip left along the wall */
} rf_impact_out;

/* The impact of the rock on `site` at the current state: its coefficients drawn, its
 * law applied, and the impact counted and reported (a tree hit as such).  Returns the
 * rebound normal speed (slope and tree; 0 for walls).  out: NULL but for a wall
 * meet. */
double rf_impact(rf_motion *m, const rf_impact_site *site, rf_impact_out *out);
/* Draws the surface phase's mu and mu_r of triangle tri's zone into m->rock.sup. */
void rf_support_draw(rf_motion *m, int32_t tri);
/* A slow sphere rolls over a convex edge or vertex at q onto face `to`: its centre
 * goes from q + rho u to q + rho n_to, conserving total energy.  Returns 0, or -1 when
 * it cannot climb there (the state is untouched). */
int rf_pivot(rf_motion *m, rf_vec3 q, int32_t to);
/* How far (m) the centre rises above where it is on the way of such a roll onto a face
 * of normal n: over the top of a ridge, or to the end of a roll up onto a shoulder. */
double rf_pivot_rise(const rf_motion *m, rf_vec3 q, rf_vec3 n);

#endif
