/* surface_law.h - the laws of motion on one face and in a crease of two (surface_law.c).
 *
 * On a face with normal n gravity splits into g_t (along the face) and the pressure
 * g_n = g n.z.  The point mass and the slipping sphere feel Coulomb friction opposite
 * the slip of the contact point; the rolling sphere feels rolling resistance:
 *
 *   point mass        a = g_t - mu g_n v^                 (Eq. 1-2 on a plane)
 *   slipping sphere   a = g_t - mu g_n u^,   du/dt = g_t - (1 + m r^2 / I) mu g_n u^
 *   rolling sphere    a = 5/7 (g_t - mu_r g_n v^)         (I = 2/5 m r^2)
 *
 * A crease (two faces touched at once, as in a gully) is a straight line: the rock
 * moves along it with the normal forces of both faces. */
#ifndef ROCKFALL_ENGINE_SURFACE_LAW_H
#define ROCKFALL_ENGINE_SURFACE_LAW_H

#include "engine/state.h"
#include "engine/rock.h"

/* The surface law of the rock's current mode (surface_law.c). */
typedef enum rf_law { RF_LAW_POINT, RF_LAW_SLIDE, RF_LAW_ROLL } rf_law;

/* The dynamics of one face. */
typedef struct rf_face_dyn {
    rf_vec3 n, gt, e1;
    double G, gn;       /* |g_t|, g n.z */
    rf_law mode;
    double k, c;        /* a = k (g_t - c g_n dir) */
    double K;           /* slip factor 1 + m r^2 / I */
    double mu;
} rf_face_dyn;

/* The dynamics of a face of normal n for the rock's current mode and support
 * coefficients: g_t, g_n and the fall line e1 (any in-plane direction on a level
 * face), and the law (Eq. 1-2 for the point mass, the 5/7 law rolling). */
void rf_face_setup(const rf_motion *m, rf_vec3 n, rf_face_dyn *f);
/* The surface laws (above): acceleration of the centre, a = k (g_t - c g_n dir), with
 * dir the unit direction friction opposes. */
rf_vec3 rf_law_accel(const rf_face_dyn *f, rf_vec3 dir);
/* The rate of the slip of a slipping sphere, du/dt = g_t - K mu g_n u^ (udir = u^). */
rf_vec3 rf_law_slip_rate(const rf_face_dyn *f, rf_vec3 udir);
/* The direction the laws act along: the slip's for a slipping sphere, else the
 * velocity's; the fall line when it is zero. */
rf_vec3 rf_law_dir(const rf_face_dyn *f, rf_vec3 v, rf_vec3 u);
/* Along a wall (centre contact: the steep face beyond an edge of the column, dir along
 * that edge): the wall takes the parts across it of the acceleration a and of the
 * slip's rate du. */
void rf_wall_law(rf_vec3 dir, rf_vec3 *a, rf_vec3 *du);
/* The surface law on a face with normal n for the rock's current mode (point, slipping
 * or rolling sphere; coefficients of m->rock.sup): acceleration of the centre, and in *du
 * the rate of the slip u of a slipping sphere. */
rf_vec3 rf_surface_accel(const rf_motion *m, rf_vec3 n, rf_vec3 v, rf_vec3 u, rf_vec3 *du);
/* Normal pressures (per unit mass) of the two faces of a crease with normals nA, nB,
 * and its direction l; -1 when the faces are (nearly) parallel. */
int rf_crease_forces(rf_vec3 nA, rf_vec3 nB, double *xA, double *xB, rf_vec3 *l);
/* The point nearest p at height rho above both planes n.x = d of a crease (its faces
 * not parallel): the centre of a sphere touching both. */
rf_vec3 rf_crease_centre(const rf_triangle *A, const rf_triangle *B, double rho, rf_vec3 p);
/* The spin law of a sphere rolling along a crease: w = n_m x v / r, n_m the mean
 * normal. */
rf_spin_law rf_crease_roll(const rf_motion *m);
/* 1 when the rock at rest on its support would stay there. */
int rf_surface_holds(const rf_motion *m);
/* 1 when the rock's support (a face or a crease; not a flight) is steeper than the
 * friction that holds a rock at rest there: on a face tan theta > c, in a crease the
 * gravity along its line above c times the normal forces, c being mu for a point mass
 * and mu_r for a sphere (at rest it rolls off unless rolling resistance holds it), as
 * drawn for the support.  A rock at rest there is held by something else (a wall, a
 * corner) or was put to rest by the integration. */
int rf_support_steep(const rf_motion *m);
/* 1 when friction (mu) can keep the sphere on face n rolling without slip: the contact
 * force rolling needs, 2/7 m g_t with the rolling resistance, is at most mu m g_n
 * (a rock at rest where it stays needs none). */
int rf_roll_holds(const rf_motion *m, rf_vec3 n);

#endif
