/* contact_tri.h - the tests of one triangle in a contact search (contact_tri.c): its
 * face, its edges and its vertices against the centre's arc.  contact.c runs the
 * search over the triangles near the path. */
#ifndef ROCKFALL_ENGINE_CONTACT_TRI_H
#define ROCKFALL_ENGINE_CONTACT_TRI_H

#include "engine/state.h"

/* The planes of the support faces of a surface segment (none in a flight). */
typedef struct rf_support_planes {
    int n;
    rf_vec3 nrm[2];
    double d[2], tol;
} rf_support_planes;

/* One contact search: the arc, what it ignores, and the earliest contact so far. */
typedef struct rf_search {
    rf_motion *m;
    const rf_arc *arc;
    const rf_support *ex;
    double best;      /* earliest contact so far (exclusive bound) */
    int found;
    rf_contact *c;
    double vh; /* the horizontal speed at the start */
    /* a flight (no horizontal acceleration): the horizontal path is the straight line
     * s0 + vh t along the unit direction (ux, uy), at perpendicular offset d0 */
    int line;
    double ux, uy, s0, d0;
    double hr, reach;  /* the line's reach (line_reach) and a centre's reach of a face */
    double zq[3];      /* the centre's height: zq[0] + zq[1] t + zq[2] t^2 */
    rf_support_planes sp; /* a surface segment's support planes (n = 0 in a flight) */
    const rf_contact *skip; /* features passed over (rf_contact_search_near) */
    int nskip;
    /* a flight off a face: the reach bound of its plane (contact.c), and R0^2 */
    const struct rf_reach_bound *flight_bound;
    double r0sq;
} rf_search;

/* 1 when triangle idx is one of the support triangles ex ignores (NULL: none). */
int rf_excluded_tri(const rf_support *ex, int32_t idx);
/* Bounding box of the arc over [t0, t1] (componentwise extremes). */
void rf_arc_box(const rf_arc *arc, double t0, double t1, rf_vec3 *lo, rf_vec3 *hi);
/* The planes of m's support faces (none in a flight). */
void rf_support_planes_set(const rf_motion *m, rf_support_planes *sp);
/* An arc's horizontal speed at its start (search.vh). */
double rf_start_hspeed(const rf_arc *arc);
/* The support planes vertex v is on or below, a bit each, in a surface segment (a
 * centre r above such a plane never reaches it, nor the support's own vertices); none
 * in a flight (the face flown off is touched at the start only as the rock leaves it,
 * which the start rule of the quartic passes over).  A vertex is passed over when it
 * is below any; an edge only when both its ends are below the same plane: between ends
 * below different planes of a crease its points can lie above both. */
unsigned rf_vertex_out(const rf_support_planes *sp, rf_vec3 v);
/* Edge from va to vb against the centre over [w0, w1]. */
void rf_test_edge(rf_search *s, int32_t idx, int ei, rf_vec3 va, rf_vec3 vb, double w0,
                      double w1, rf_vec3 blo, rf_vec3 bhi);
void rf_test_vertex(rf_search *s, int32_t idx, int vi, rf_vec3 q, double w0, double w1,
                        rf_vec3 blo, rf_vec3 bhi);
/* Centre mode (Eq. 6-7) and the point mass (rho 0): contact while the centre is over
 * the triangle (in its column) and within rho of its plane, the window over the
 * triangle found exactly from its edges' columns.  The centre's horizontal path is
 * taken as straight (flight).  `left`: the face flown off, met only once the centre
 * moves over its column again. */
void rf_test_centre(rf_search *s, int32_t idx, double t0, double t1, int left);
/* Face of triangle idx over [t0, t1].  Returns 1 when its edges and vertices must be
 * tested too, from *w0 on. */
int rf_test_face(rf_search *s, int32_t idx, double t0, double t1, double *w0);
/* The edges and vertices of triangle idx over [w0, t1] that can be met first (the
 * live ones, rf_edge_live; on the support planes or below them none). */
void rf_test_edges(rf_search *s, int32_t idx, double w0, double t1);
int rf_coplanar_with_support(const rf_terrain *t, const rf_support *ex, const rf_triangle *T,
                                 double tol);

#endif
