/* rock.h - the rock's own state and records (rock.c): its energy, the spin by the
 * surface laws, path length and samples, path points, and the draws of coefficients
 * from their distributions.  The bottom of the engine: it calls only travel.c. */
#ifndef ROCKFALL_ENGINE_ROCK_H
#define ROCKFALL_ENGINE_ROCK_H

#include "engine/state.h"

/* m / (m + I / r^2) of a body rolling with contact radius rho: 5/7 for the sphere. */
double rf_roll_factor(const rf_body *b, double rho);
/* 1 + m r^2 / I of a body slipping with contact radius rho: the slip grows K times
 * faster than the centre's velocity under friction (7/2 for the sphere). */
double rf_slip_factor(const rf_body *b, double rho);

/* The spin along a piece of motion on a face with normal n: w(t) = wn n +
 * n x (v(t) - u(t)) / r, the slip u(t) = u0 + t du (none when rolling) and the spin wn
 * about the normal, which the face's friction leaves alone. */
typedef struct rf_spin_law {
    rf_vec3 n;
    double wn;
    rf_vec3 u0, du;
} rf_spin_law;
/* The law of a step of length h on face n whose slip goes linearly from u to u1 (for
 * h = 0, u1 throughout). */
rf_spin_law rf_spin_law_over(const rf_motion *m, rf_vec3 n, rf_vec3 u, rf_vec3 u1, double h);
/* The spin by law l at time t, at velocity v, of a sphere of contact radius rho. */
rf_vec3 rf_spin_at(const rf_spin_law *l, double rho, rf_vec3 v, double t);
/* The law of a piece on face n from the current state, its slip u0 at the start
 * changing at the rate du. */
rf_spin_law rf_spin_law_of(const rf_motion *m, rf_vec3 n, rf_vec3 u0, rf_vec3 du);
/* Slip of the sphere's contact point on a face with normal n: u = v + w x (-r n), in
 * the plane (Eq. 8a). */
rf_vec3 rf_slip_of(const rf_motion *m, rf_vec3 n);
/* A sphere's slip on the face of normal n; one whose slip has vanished rolls from then
 * on (its spin set from the velocity; the slip returned is then 0). */
rf_vec3 rf_face_slip(rf_motion *m, rf_vec3 n);
/* Spin from v and the slip u on a face (w . n kept): w_t = n x (v - u) / r; none for
 * the point model.  The state is whole again: its energy is noted. */
void rf_set_spin(rf_motion *m, rf_vec3 n, rf_vec3 u);

/* Records the motion along an arc over [0, T] from the current state (path length,
 * samples, their spin by the law: NULL, it stays, as in flight) and moves the state to
 * its end: p, v, t.  The caller sets the end's spin and notes the energy once the state
 * is whole (rf_set_spin, or rf_motion_note_energy), never in between: the end's
 * velocity with the start's spin is no state the rock is in. */
void rf_motion_advance(rf_motion *m, const rf_arc *arc, double T, const rf_spin_law *law);
/* 1 when the motion is sampled along the way (the sink takes samples), the only use
 * rf_motion_advance makes of its spin law. */
static inline int rf_motion_samples(const rf_motion *m)
{
    return m->book.sink && m->book.sink->sample && m->book.sink->sample_spacing > 0;
}
/* rf_motion_advance with the velocity along the way from `vel` (its v + a t) rather
 * than from the arc of the positions: a step of the fixed-step engine moves the centre
 * with the step's end velocity, while its velocity changes linearly over the step. */
void rf_motion_advance_split(rf_motion *m, const rf_arc *arc, const rf_arc *vel, double T,
                             const rf_spin_law *law);
/* A sample at p (speed |v|, energy ekj, height above the ground) to the sink. */
void rf_motion_sample(rf_motion *m, rf_vec3 p, rf_vec3 v, double ekj);
/* A path point at the current state. */
void rf_motion_event(rf_motion *m);
/* Total kinetic energy of the current state (J). */
double rf_motion_energy(const rf_motion *m);
/* The kinetic energy of the current state (kJ), kept as the trajectory's
 * max_energy_kj when it is the largest: at every whole state (the end of a piece of
 * motion, before an impact or a measure's stop takes energy). */
double rf_motion_note_energy(rf_motion *m);

#endif
