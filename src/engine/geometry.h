/* geometry.h - the triangles of the terrain: vertices, shared features, the columns
 * of the centre mode (a face's xy projection), one plane (geometry.c). */
#ifndef ROCKFALL_ENGINE_GEOMETRY_H
#define ROCKFALL_ENGINE_GEOMETRY_H

#include "rockfall/terrain.h"
#include "rockfall/vec3.h"

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

/* Edge functions of a face: E_k(c) = m_k . c - o_k >= 0 while a point c is inside
 * edge k (the face's xy column: horizontal m_k). */
typedef struct rf_face_edges {
    rf_vec3 m[3];
    double o[3];
} rf_face_edges;
/* The edge functions of T's column (its xy projection). */
void rf_column_edges(const rf_triangle *T, rf_face_edges *fe);
/* 1 when the point p lies in triangle T's column, more than `margin` inside each of
 * its edges (a negative margin: within -margin outside). */
int rf_in_column(const rf_triangle *T, rf_vec3 p, double margin);
/* 1 when faces A and B lie in one plane (normals within RF_COPLANAR_EPS, offsets
 * within tol). */
int rf_coplanar(const rf_triangle *A, const rf_triangle *B, double tol);
/* 1 when q (on T's plane) lies on the inner side of all three edges or on them. */
int rf_inside_closed(const rf_triangle *T, rf_vec3 q);
/* The far edges of a grid terrain's nodes. */
static inline void rf_grid_far(const rf_terrain *t, double *xmax, double *ymax)
{
    *xmax = t->x0 + (double)(t->nx - 1) * t->cell;
    *ymax = t->y0 + (double)(t->ny - 1) * t->cell;
}

#endif
