/* motion_private.h - internals of the motion engine shared by its source files.
 *
 *   arc.c       constant-acceleration arcs: evaluation, arc length, polynomial roots
 *   contact.c   earliest contact of the rock with the terrain along an arc
 *   impact.c    the impact law (Eq. 8) and the transfers of a slow rock between faces
 *   surface.c   rolling and sliding on one face or in a crease (Eq. 1-2, 5/7 law)
 *   hodograph.c sliding and rolling off the fall line, in closed form
 *   motion.c    the event loop, records and the public functions of sim.h
 *   fixed_step.c  the fixed-step baseline engine
 *
 * docs/engine.md describes the phases, events, root finding and tolerances. */
#ifndef ROCKFALL_MOTION_PRIVATE_H
#define ROCKFALL_MOTION_PRIVATE_H

#include <stdint.h>

#include "rockfall/sim.h"
#include "scene/measures.h"
#include "base/arc.h"
#include "base/tolerances.h"
#include "base/util.h"
#include "engine/hodograph.h"

/* Vertex i (taken modulo 3) of a triangle: a, b, c. */
static inline rf_vec3 rf_tri_vertex(const rf_triangle *T, int i)
{
    i %= 3;
    return i == 0 ? T->a : (i == 1 ? T->b : T->c);
}

static inline int rf_same_point(rf_vec3 a, rf_vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* 1 when triangle S's feature j (a vertex, or an edge when j & 4) is T's feature k. */
static inline int rf_same_feature(const rf_triangle *S, int j, const rf_triangle *T, int k)
{
    if ((j ^ k) & 4)
        return 0;
    rf_vec3 sa = rf_tri_vertex(S, j & 3), qa = rf_tri_vertex(T, k & 3);
    if (!(k & 4))
        return rf_same_point(sa, qa);
    rf_vec3 sb = rf_tri_vertex(S, (j & 3) + 1), qb = rf_tri_vertex(T, (k & 3) + 1);
    return (rf_same_point(sa, qa) && rf_same_point(sb, qb)) ||
           (rf_same_point(sa, qb) && rf_same_point(sb, qa));
}

/* The part of x in the plane of unit normal n. */
static inline rf_vec3 rf_in_plane(rf_vec3 x, rf_vec3 n) { return rf_v3_madd(x, -rf_v3_dot(x, n), n); }

/* ---- the run-time context of one trajectory --------------------------------------- */
typedef enum rf_feature { RF_FEAT_FACE, RF_FEAT_EDGE, RF_FEAT_VERTEX } rf_feature;

typedef struct rf_contact {
    double t;        /* time along the searched arc */
    int32_t tri;     /* triangle whose face, edge or vertex is met */
    rf_feature kind;
    int index;       /* edge (0: ab, 1: bc, 2: ca) or vertex (0: a, 1: b, 2: c) */
    rf_vec3 point;   /* contact point on the terrain */
    rf_vec3 n;       /* unit contact normal, from the terrain towards the centre */
} rf_contact;

/* Support of a rock on the surface: none (flight), one face, or a crease of two. */
typedef struct rf_support {
    int n;
    int32_t tri[3];   /* tri[0], tri[1]: the faces; tri[2] only in search exclusions */
    int32_t left;     /* a face the rock has just left over its edge (or -1): the next
                         segment's contact search ignores its face, not its edges and
                         vertices */
    int rolling;      /* sphere rolls without slip */
    int32_t zone;     /* zone whose coefficients mu and mu_r were drawn */
    double mu, mu_r;
} rf_support;

/* contact.c: a table of the distinct edges and vertices met in one search */
#define RF_FEAT_SLOTS 1024
typedef struct rf_feat_slot {
    uint64_t key;
    uint32_t gen;     /* slot in use when equal to rf_workspace.feat_gen */
    int32_t tri, k;   /* first triangle holding it; vertex k, or edge (k & 3) | 4 */
} rf_feat_slot;

struct rf_workspace {
    const rf_terrain *terrain;
    int32_t *cand;    /* candidate triangles */
    size_t cap;
    uint32_t *stamp;  /* query stamps, one per triangle */
    uint32_t epoch;
    int has_gaps;     /* the terrain has holes: nodata triangles of a grid, or edges of
                         a mesh on its border in plan off its bounding box's sides */
    double nz_min;    /* the smallest z component of the faces' unit normals, at least
                         1e-12 (centre contact: a centre meets a face r / n.z above) */
    int32_t *near_hit; /* candidates of a surface segment */
    float *tri_box;   /* per triangle: xmin, xmax, ymin, ymax, zmin, zmax (rounded
                         outwards) */
    double *hedge;    /* per triangle: the horizontal lengths of edges ab, bc, ca */
    size_t near_cap;
    int32_t *pend_idx; /* triangles whose edges and vertices are still to test */
    double *pend_w0;
    size_t pend_cap;
    uint8_t *edge_live; /* per triangle, bit k: edge k can be met first (not strictly
                           concave: convex, nearly flat, or on the border); meshes, bit
                           RF_EDGE_BORDER << k: edge k is a border in plan (one
                           holder covers ground: no other, or only vertical ones) */
    uint32_t *tested; /* flights: triangles tested in the current search (== test_epoch) */
    uint32_t test_epoch;
    /* contact.c: shared edges and vertices (zeroed by calloc; no allocation) */
    uint32_t feat_gen;
    size_t feat_used; /* slots in use in the current generation */
    rf_feat_slot feat[RF_FEAT_SLOTS];
};

/* A measure's line the rock has just crossed (scene_events.c): the crossed segment's
 * line, through (ax, ay) with unit normal (nx, ny) in plan. */
typedef struct rf_passage {
    int measure;
    double ax, ay, nx, ny;
} rf_passage;

typedef struct rf_motion {
    const rf_scene *scene;
    const rf_terrain *terrain;
    const rf_body *body;
    gsl_rng *rng;
    rf_workspace *ws;
    const rf_sink *sink;
    rf_trajectory_record *rec;

    double rho;        /* contact radius: r for the sphere, 0 for the point */
    int point;         /* point model: no size, no rotation */
    int centre;        /* contact `centre`: only the face under the centre (Eq. 6-7) */
    double tol_len;    /* length tolerance for this terrain */
    double v_stay;     /* rebound normal speed below which the rock stays on the surface */
    double t_end;      /* max_time */

    rf_state s;        /* current state */
    rf_support sup;
    rf_support flight_ex; /* faces a flight ignores (the face it rolled off) */
    long events;
    double stall_t;    /* time of the last event that advanced time by RF_STALL_TIME */
    int stall;         /* events since */
    long rescues;
    int wedged;       /* centre mode: a rescue found the rock wedged among walls at wedge_p */
    rf_vec3 wedge_p;
    rf_vec3 creep_p;   /* where the rock was when it last moved on or was fast */
    int creep;         /* events since */
    long marked;       /* events marked (rf_motion_event) */
    int scene_pending; /* what rf_scene_horizon found: RF_SCENE_NONE, _MEASURE or _TREE */

    /* samples */
    double sample_acc; /* horizontal travel since the last sample */

    /* scene events (scene_events.c): measure crossings and tree collisions */
    rf_crossing crossings[RF_MAX_COINCIDENT_CROSSINGS]; /* the measures crossed, at once */
    int ncrossings;
    rf_passage passing[RF_MAX_COINCIDENT_CROSSINGS]; /* lines being passed (scene_events.c) */
    int npassing;
    int tree_forest;         /* the forest of the tree collision found */
    double tree_bound;       /* summed rate bound of the forests per metre; 0: none */
    double phi_r;            /* rock diameter in Eq. 12 */
    double odo;              /* horizontal distance travelled */
    double tree_next;        /* odometer of the next candidate tree event (thinning) */
    double tree_u;           /* its uniform acceptance draw */
} rf_motion;

/* ---- contact.c -------------------------------------------------------------------- */
#define RF_EDGE_BORDER 16u
/* Prepares ws->edge_live for terrain t (meshes: all flags; grids: each triangle's when
 * first asked for); 0, or -1 out of memory. */
int rf_edge_live_build(const rf_terrain *t, uint8_t *live);
/* 1 when terrain t has holes (see rf_workspace.has_gaps); live: from rf_edge_live_build. */
int rf_terrain_has_gaps(const rf_terrain *t, const uint8_t *live);
/* Fills ws->tri_box for terrain t. */
void rf_tri_box_build(const rf_terrain *t, float *box);
/* Fills ws->hedge for terrain t. */
void rf_hedge_build(const rf_terrain *t, double *hedge);
/* Gathers the triangles whose xy box overlaps the box into ws->cand; returns count. */
size_t rf_gather(rf_motion *m, double xmin, double ymin, double xmax, double ymax);
/* Earliest contact along `arc` over [0, T] of the rock (contact radius m->rho; centre
 * mode tests the face under the centre only).  The faces, edges and vertices of the
 * support triangles in `ex` are ignored.  Returns 1 and fills *c when there is one. */
int rf_contact_search(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                      rf_contact *c);
/* rf_contact_search for a surface segment: the arc lies on the support planes (m->sup),
 * the support faces, faces in their planes and features on or below a support plane
 * are skipped (a centre r above the plane cannot reach them), and so are the nskip
 * features in skip (contacts of the step's parabola that the exact path does not
 * make). */
int rf_contact_search_near(rf_motion *m, const rf_arc *arc, double T, const rf_support *ex,
                           const rf_contact *skip, int nskip, rf_contact *c);
/* Time (<= T) at which the centre's horizontal path leaves the terrain (outside its
 * bounds or over a hole); T when it does not. */
double rf_terrain_exit_time(rf_motion *m, const rf_arc *arc, double T);
/* Distance from p to the contact's feature (face plane, edge segment or vertex). */
double rf_feature_distance(const rf_terrain *t, const rf_contact *c, rf_vec3 p);
/* Closest terrain feature to p among triangles within `reach` of it: distance, or
 * INFINITY when there is none; fills *c (t = 0). */
double rf_closest_feature(rf_motion *m, rf_vec3 p, double reach, rf_contact *c);
/* The lowest height >= p.z of a centre on the vertical through p at which the rock
 * (contact radius m->rho) is clear of every face, edge and vertex: p.z when it is. */
double rf_clear_height(rf_motion *m, rf_vec3 p);
/* The triangle under the point a tiny step from q in the horizontal direction dir
 * (the face a rock enters when it leaves `from` at q); -1 for none. */
int32_t rf_face_beyond(const rf_terrain *t, int32_t from, rf_vec3 q, rf_vec3 dir);

/* ---- impact.c --------------------------------------------------------------------- */
/* Draws e_n, mu for the zone of triangle tri and applies the impact (Eq. 8) with unit
 * normal n at the current state.  Returns the rebound normal speed. */
double rf_impact(rf_motion *m, int32_t tri, rf_vec3 n);
/* The impact law itself (Eq. 8) with given e_n and mu, for slope and tree impacts. */
double rf_impact_apply(rf_motion *m, rf_vec3 n, double e, double mu);
/* Draws the surface phase's mu and mu_r of triangle tri's zone into m->sup. */
void rf_support_draw(rf_motion *m, int32_t tri);
/* A slow sphere rolls over a convex edge or vertex at q onto face `to`: its centre
 * goes from q + rho u to q + rho n_to, conserving total energy.  Returns 0, or -1 when
 * it cannot climb there (the state is untouched). */
int rf_pivot(rf_motion *m, rf_vec3 q, int32_t to);
/* How far (m) the centre rises above where it is on the way of such a roll onto a face
 * of normal n: over the top of a ridge, or to the end of a roll up onto a shoulder. */
double rf_pivot_rise(const rf_motion *m, rf_vec3 q, rf_vec3 n);

/* ---- surface.c -------------------------------------------------------------------- */
typedef enum rf_surface_end {
    RF_SURF_CONTINUE,  /* the support changed; carry on */
    RF_SURF_FLIGHT,    /* left the surface */
    RF_SURF_REST,
    RF_SURF_EXITED,
    RF_SURF_MAX_TIME,
    RF_SURF_STOPPED    /* stopped by a scene event (a measure) */
} rf_surface_end;

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
/* Handles a contact found by the search (or a concave face change): impact (Eq. 8),
 * then flight, landing on a face or in a crease, or a roll over an edge or vertex. */
void rf_contact_resolve(rf_motion *m, const rf_contact *c);
/* Normal pressures (per unit mass) of the two faces of a crease with normals nA, nB,
 * and its direction l; -1 when the faces are (nearly) parallel. */
int rf_crease_forces(rf_vec3 nA, rf_vec3 nB, double *xA, double *xB, rf_vec3 *l);
/* The point nearest p at height rho above both planes n.x = d of a crease (its faces
 * not parallel): the centre of a sphere touching both. */
rf_vec3 rf_crease_centre(const rf_triangle *A, const rf_triangle *B, double rho, rf_vec3 p);
/* The motion along a crease (m->sup.n == 2), shared by both engines. */
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
/* Sets the velocity along the crease and decides between rolling and sliding (a
 * rolling sphere slides when friction cannot make it roll down the crease). */
rf_crease_kind rf_crease_law(rf_motion *m, rf_crease *cr);
/* The spin law of a sphere rolling along a crease: w = n_m x v / r, n_m the mean
 * normal. */
rf_spin_law rf_crease_roll(const rf_motion *m);
/* Edge functions of a face: E_k(c) = m_k . c - o_k >= 0 while a point c is inside
 * edge k (the face's xy column: horizontal m_k). */
typedef struct rf_face_edges {
    rf_vec3 m[3];
    double o[3];
} rf_face_edges;
void rf_column_edges(const rf_triangle *T, rf_face_edges *fe);
/* 1 when the point p lies in triangle T's column, more than `margin` inside each of
 * its edges (a negative margin: within -margin outside). */
int rf_in_column(const rf_triangle *T, rf_vec3 p, double margin);
/* The face a rock enters when its contact point q (the centre in centre mode) leaves
 * face `from` over edge `edge` (fe: the face's edge functions), moving with the
 * velocity, or the acceleration acc from rest; -1 when there is none. */
int32_t rf_face_after(const rf_motion *m, int32_t from, int edge, const rf_face_edges *fe,
                      rf_vec3 q, rf_vec3 acc);
/* The contact point of support `slot` crossed edge `edge` of its face: onto the next
 * face, an impact on it, a flight, or exited. */
rf_surface_end rf_leave_face(rf_motion *m, int slot, int edge, const rf_face_edges *fe,
                             rf_vec3 acc);
/* Centre mode: the move that puts the centre onto face T's offset plane when it is
 * closer to that plane than r by *gap > 0: vertical, so that it stays over the face
 * (Eq. 6); on a face steeper than n.z = 0.2, where that would be over five times the
 * gap, along the normal as far as the centre stays over the face's column, and
 * vertical for the rest. */
rf_vec3 rf_centre_lift_move(const rf_motion *m, const rf_triangle *T, double *gap);
/* Moves the rock by a lift `move` paid from the kinetic energy; 0 (and nothing
 * changed) when the rock cannot pay it, or has no kinetic energy. */
int rf_pay_lift(rf_motion *m, rf_vec3 move);
/* Moves the rock on its support until the next event and handles it. */
rf_surface_end rf_surface_step(rf_motion *m);
/* Centre mode, a rock on one face on edge `edge` of its column (col: its edges), which the
 * fixed-step engine's step would leave over at once: when the face it would enter
 * there is one it cannot pay the lift onto (a wall), it meets the wall as the exact
 * engine's segments do.  Returns RF_SURF_REST, or RF_SURF_CONTINUE when it stopped in
 * a corner of two walls; else -1, with *wall the column edge it moves along (-1: no
 * wall) and *dir the way it moves. */
int rf_wall_meet(rf_motion *m, const rf_face_edges *col, int edge, int *wall, rf_vec3 *dir);
/* Puts the rock onto face tri after a landing or at the start (velocity made tangent,
 * coefficients drawn when the zone changes, rolling when the slip vanishes). */
void rf_surface_enter(rf_motion *m, int32_t tri);
/* The rock on face tri alone: on its offset plane with a tangent velocity, rolling when
 * the slip vanishes; the coefficients are drawn when fresh, after a flight or when the
 * zone changes. */
void rf_support_single(rf_motion *m, int32_t tri, int fresh);
/* The surface law on a face with normal n for the rock's current mode (point, slipping
 * or rolling sphere; coefficients of m->sup): acceleration of the centre, and in *du
 * the rate of the slip u of a slipping sphere. */
rf_vec3 rf_surface_accel(const rf_motion *m, rf_vec3 n, rf_vec3 v, rf_vec3 u, rf_vec3 *du);
/* Along a wall (centre contact: the steep face beyond an edge of the column, dir along
 * that edge): the wall takes the parts across it of the acceleration a and of the
 * slip's rate du. */
void rf_wall_law(rf_vec3 dir, rf_vec3 *a, rf_vec3 *du);
/* 1 when the rock at rest on its support would stay there. */
int rf_surface_holds(const rf_motion *m);
/* Slip of the sphere's contact point on a face with normal n: u = v + w x (-r n), in
 * the plane. */
rf_vec3 rf_slip_of(const rf_motion *m, rf_vec3 n);
/* A sphere's slip on the face of normal n; one whose slip has vanished rolls from then
 * on (its spin set from the velocity; the slip returned is then 0). */
rf_vec3 rf_face_slip(rf_motion *m, rf_vec3 n);
/* A crease ends: the rock goes on on face `on` alone, `left` (-1: none) the face just
 * left; a sphere that rolled in the crease rolls on only when its spin does not slip
 * on that face. */
void rf_crease_ends(rf_motion *m, int32_t on, int32_t left);
/* Spin from v and the slip u on a face (w . n kept): w_t = n x (v - u) / r; none for
 * the point model.  The state is whole again: its energy is noted. */
void rf_set_spin(rf_motion *m, rf_vec3 n, rf_vec3 u);
/* 1 when faces A and B lie in one plane (normals within RF_COPLANAR_EPS, offsets
 * within tol). */
int rf_coplanar(const rf_triangle *A, const rf_triangle *B, double tol);
/* m / (m + I / r^2) of a body rolling with contact radius rho: 5/7 for the sphere. */
double rf_roll_factor(const rf_body *b, double rho);
/* 1 + m r^2 / I of a body slipping with contact radius rho: the slip grows K times
 * faster than the centre's velocity under friction (7/2 for the sphere). */
double rf_slip_factor(const rf_body *b, double rho);
/* 1 when friction (mu) can keep the sphere on face n rolling without slip: the contact
 * force rolling needs, 2/7 m g_t with the rolling resistance, is at most mu m g_n
 * (a rock at rest where it stays needs none). */
int rf_roll_holds(const rf_motion *m, rf_vec3 n);

/* ---- motion.c --------------------------------------------------------------------- */
/* Records the motion along an arc over [0, T] from the current state (path length,
 * samples, their spin by the law: NULL, it stays, as in flight) and moves the state to
 * its end: p, v, t.  The caller sets the end's spin and notes the energy once the state
 * is whole (rf_set_spin, or rf_motion_note_energy): noted in between, the end's velocity
 * with the start's spin was more than the rock ever had where slip spun it down while
 * it sped up. */
void rf_motion_advance(rf_motion *m, const rf_arc *arc, double T, const rf_spin_law *law);
/* 1 when the motion is sampled along the way (the sink takes samples), the only use
 * rf_motion_advance makes of its spin law. */
static inline int rf_motion_samples(const rf_motion *m)
{
    return m->sink && m->sink->sample && m->sink->sample_spacing > 0;
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
/* Places the rock at the start of a trajectory: on the surface when it touches it
 * (landing, or an impact when it moves into it), else in flight.  Returns -1 to go on
 * or an end reason; going on, progress (rf_progress) is watched from there.  Shared by
 * both engines. */
int rf_motion_start(rf_motion *m);
/* The first contact of a flight along arc over [0, T], the face flown off (flight_ex)
 * left out; both engines' flights take it. */
int rf_flight_contact(rf_motion *m, const rf_arc *arc, double T, rf_contact *c);
/* Centre mode: of the faces whose columns hold the centre (several on a border, within
 * the length tolerance), the one whose offset plane is highest there; tri is the one
 * located.  Lifted onto another's plane, a rescued centre at a mesh's node lay under a
 * neighbouring column's plane, over that column, and fell through it. */
int32_t rf_highest_column(rf_motion *m, int32_t tri);
/* Total kinetic energy of the current state (J). */
double rf_motion_energy(const rf_motion *m);
/* The kinetic energy of the current state (kJ), kept as the trajectory's
 * max_energy_kj when it is the largest: at every whole state (the end of a piece of
 * motion, before an impact or a measure's stop takes energy). */
double rf_motion_note_energy(rf_motion *m);
/* The rock's progress, at every turn of either engine's loop: a rock that meets events
 * without moving in time (degenerate contact geometry) rests when slow, else moves free
 * for a moment (RF_UNSTALL_TIME) and is put back on or above the surface under it.
 * With `events` (every turn is an event: the exact engine), a slow rock that creeps on
 * the spot (RF_CREEP_EVENTS events within RF_CREEP_DIST, below stop_speed: wedged in a
 * pocket of faces that no single face or crease law holds, each event moving it a
 * little) rests too; the fixed-step engine's turns are mostly plain steps.  Returns an
 * end reason, RF_RESCUED after a rescue, or -1. */
#define RF_RESCUED -2
int rf_progress(rf_motion *m, int events);
/* The rescue of rf_progress, at once: RF_RESCUED; rest for a rock in centre mode
 * wedged among walls (it cannot pay the lift onto the column under it) where it was
 * last wedged; max_time after RF_MAX_RESCUES. */
int rf_rescue(rf_motion *m);

/* Events of the scene beyond the terrain (tree collisions, measure crossings): the
 * extension point of the vegetation and measures modules.  Every piece of exact motion
 * - a flight, a closed-form surface segment, one integrator step - is offered as an
 * arc over [0, T] before it is taken; rf_scene_horizon returns the earliest time in
 * [0, T] at which a scene event cuts it (T when none) and remembers the event;
 * rf_scene_event handles it once the state has been moved there, and returns -1 to go
 * on or an end reason (RF_END_STOPPED). */
double rf_scene_horizon(rf_motion *m, const rf_arc *arc, double T);
int rf_scene_event(rf_motion *m);
/* The crossings at this very moment, which a piece of motion ending here (at another
 * event, or a hair short of the line) leaves to the next one: taken before the rock
 * leaves the terrain (either engine's `exited`: there is no next piece) and before an
 * impact on the terrain takes its energy (a line on a concave edge records the rock as
 * it arrives).  Returns RF_END_STOPPED when a measure stops it here, else -1. */
int rf_scene_at_once(rf_motion *m);
enum { RF_SCENE_NONE, RF_SCENE_MEASURE, RF_SCENE_TREE };
/* Sets up the scene events of a new trajectory (draws the first tree candidate). */
void rf_scene_begin(rf_motion *m);
/* Accounts for horizontal travel along a taken arc over [0, T]. */
void rf_scene_travel(rf_motion *m, const rf_arc *arc, double T);

/* ---- fixed_step.c ----------------------------------------------------------------- */
int rf_simulate_fixed_step(rf_motion *m);

#endif
