/* face_entry.h - the rock arrives on the surface (face_entry.c): a contact resolved by an
 * impact (Eq. 8), then a flight, a landing on a face or in a crease, or a roll over an
 * edge or vertex; the lift of a centre (Eq. 6-7) onto a face's offset plane, paid
 * from the kinetic energy, and the walls it cannot pay for. */
#ifndef ROCKFALL_ENGINE_FACE_ENTRY_H
#define ROCKFALL_ENGINE_FACE_ENTRY_H

#include "engine/state.h"

/* The rock on face tri alone: on its offset plane with a tangent velocity, rolling when
 * the slip vanishes; the coefficients are drawn when fresh, after a flight or when the
 * zone changes. */
void rf_support_single(rf_motion *m, int32_t tri, int fresh);
/* Puts the rock onto face tri after a landing or at the start (velocity made tangent,
 * coefficients drawn when the zone changes, rolling when the slip vanishes). */
void rf_surface_enter(rf_motion *m, int32_t tri);
/* The rock on face A meets face B gently: a crease when both faces press on it. */
int rf_try_crease(rf_motion *m, int32_t a, int32_t b);
/* 1 when a sphere rolled over q onto face `to` would touch no other feature: the
 * roll is only taken where the two faces are all there is. */
int rf_pivot_clear(rf_motion *m, rf_vec3 q, int32_t to);
/* The rock takes off: no support; face `exclude` (-1: none) is left out of the flight's
 * contact search. */
void rf_go_flight(rf_motion *m, int32_t exclude);
/* A slow sphere on a convex edge or vertex (unit normal u) that cannot roll over it
 * cleanly hops off: its velocity is turned, at the same speed, to leave the feature
 * at the stay speed, so that it is never dragged through the feature. */
void rf_hop(rf_motion *m, rf_vec3 u);
/* Centre mode: the move that puts the centre onto face T's offset plane when it is
 * closer to that plane than r by *gap > 0: vertical, so that it stays over the face
 * (Eq. 6); on a face steeper than n.z = 0.2, where that would be over five times the
 * gap, along the normal as far as the centre stays over the face's column, and
 * vertical for the rest. */
rf_vec3 rf_centre_lift_move(const rf_motion *m, const rf_triangle *T, double *gap);
/* The potential energy (J) a lift by `move` costs. */
double rf_lift_cost(const rf_motion *m, rf_vec3 move);
/* Moves the rock by a lift `move` paid from the kinetic energy; 0 (and nothing
 * changed) when the rock cannot pay it, or has no kinetic energy. */
int rf_pay_lift(rf_motion *m, rf_vec3 move);
/* Centre mode: 1 when face `to`'s offset plane is above the centre's reach and a rock
 * of kinetic energy ke (J) cannot pay the lift onto it: a wall. */
int rf_wall_for(const rf_motion *m, int32_t to, double ke);
/* Centre mode (Eq. 6-7), the rolling phase on grids: at a concave grid edge the offset
 * planes of the two faces step down at their columns' border, so a centre that crosses
 * it on its support's offset plane is above the next face `to`'s.  Met slower than
 * v_stay along that face's normal, the rock changes face there as full contact does
 * (the velocity projected, the turn's plastic tangential impulse, counted in
 * n_edge_transitions, no impact): the centre is put on the offset plane vertically, the
 * potential energy of the step given up (T is face `to`, as the caller has it).
 * rf_centre_edge_step_taken: 1 when the change of face applies to the current state, the centre crossing the border in the
 * horizontal direction `out` into a face that falls that way (a rock moving along the
 * border, or into a face that would take it back over it, makes its flight). */
int rf_centre_edge_step_taken(const rf_motion *m, int32_t to, const rf_triangle *T, rf_vec3 out);
void rf_centre_edge_step(rf_motion *m, int32_t to, const rf_triangle *T);
/* Handles a contact found by the search (or a concave face change): impact (Eq. 8),
 * then flight, landing on a face or in a crease, or a roll over an edge or vertex. */
void rf_contact_resolve(rf_motion *m, const rf_contact *c);
/* A crease ends: the rock goes on on face `on` alone, `left` (-1: none) the face just
 * left; a sphere that rolled in the crease rolls on only when its spin does not slip
 * on that face. */
void rf_crease_ends(rf_motion *m, int32_t on, int32_t left);
/* The scene event rf_scene_horizon found (rf_scene_event), with a rock that a tree
 * hit leaves on the surface put back onto its face.  Returns -1 or an end reason. */
int rf_surface_scene_event(rf_motion *m);

#endif
