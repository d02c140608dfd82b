/* face_exit.h - the rock leaves its face or its crease (face_exit.c): the edge functions of
 * a face, the time its contact point leaves it, and what follows: the next face in the
 * same plane, an impact on it at a concave edge, a flight or a roll over a convex one. */
#ifndef ROCKFALL_ENGINE_FACE_EXIT_H
#define ROCKFALL_ENGINE_FACE_EXIT_H

#include "engine/state.h"
#include "engine/geometry.h"

/* The motion along a crease (m->rock.sup.n == 2), shared by both engines. */
typedef enum rf_crease_kind {
    RF_CREASE_MOVES, /* uniformly accelerated along l */
    RF_CREASE_REST,  /* slower than stop_speed where friction holds it */
    RF_CREASE_ENDED  /* a normal force is negative: the face kept is the support */
} rf_crease_kind;
typedef struct rf_crease {
    rf_vec3 l;   /* unit direction along the crease, the way the rock moves (or, from
                    rest, the way gravity pulls it) */
    double s;    /* speed along l */
    double as;   /* acceleration along l (sliding, or rolling with the roll factor) */
    int holds;   /* friction (mu, or mu_r rolling) holds the rock at rest there */
    int rolling;
} rf_crease;

/* The edge functions of face T for the centre: in-plane, from its edges lifted by the
 * contact radius along its normal (full contact, point mass), or of its column in plan
 * (centre mode). */
void rf_face_edges_setup(const rf_motion *m, const rf_triangle *T, rf_face_edges *fe);
/* 1 when p lies on edge k's line (within the length tolerance). */
int rf_on_edge(const rf_motion *m, const rf_face_edges *fe, int k, rf_vec3 p);
/* Unit vector along edge k of F, from vertex k to vertex k + 1. */
rf_vec3 rf_edge_dir(const rf_triangle *F, int k);
/* First time in [0, T] the contact point of the arc leaves the face, not over edge
 * `skip` (-1: none); T when it does not.  *edge receives the edge. */
double rf_exit_time(const rf_motion *m, const rf_face_edges *fe, const rf_arc *arc, double T,
                        int skip, int *edge);
/* The edge of A whose ends are both vertices of B, or -1. */
int rf_shared_edge(const rf_triangle *A, const rf_triangle *B);
/* The face across edge `edge` of face `from`, stepping over the edge's middle (-1:
 * none). */
int32_t rf_face_over_edge(const rf_terrain *t, int32_t from, int edge, const rf_face_edges *fe);
/* The face a rock enters when its contact point q (the centre in centre mode) leaves
 * face `from` over edge `edge` (fe: the face's edge functions), moving with the
 * velocity, or the acceleration acc from rest; -1 when there is none. */
int32_t rf_face_after(const rf_motion *m, int32_t from, int edge, const rf_face_edges *fe,
                      rf_vec3 q, rf_vec3 acc);
/* The contact point crossed edge `edge` of the support face at the current state. */
rf_surface_end rf_leave_face(rf_motion *m, int slot, int edge, const rf_face_edges *fe,
                             rf_vec3 acc);
/* Sets the velocity along the crease and decides between rolling and sliding (a
 * rolling sphere slides when friction cannot make it roll down the crease). */
rf_crease_kind rf_crease_law(rf_motion *m, rf_crease *cr);

#endif
