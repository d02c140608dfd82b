/* geometry.c - columns and planes of the terrain's triangles. */
#include "engine/geometry.h"

#include <math.h>

#include "base/tolerances.h"

void rf_column_edges(const rf_triangle *T, rf_face_edges *fe)
{
    rf_vec3 P[3] = {T->a, T->b, T->c};
    double orient = (P[1].x - P[0].x) * (P[2].y - P[0].y) - (P[1].y - P[0].y) * (P[2].x - P[0].x);
    double sg = orient >= 0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; k++) {
        rf_vec3 A = P[k], B = P[(k + 1) % 3];
        double ex = B.x - A.x, ey = B.y - A.y, el = hypot(ex, ey);
        fe->m[k] = el > 0 ? rf_v3(-sg * ey / el, sg * ex / el, 0.0) : rf_v3(0, 0, 0);
        fe->o[k] = rf_v3_dot(fe->m[k], A);
    }
}

int rf_in_column(const rf_triangle *T, rf_vec3 p, double margin)
{
    rf_face_edges fe;
    rf_column_edges(T, &fe);
    for (int e = 0; e < 3; e++)
        if (!(rf_v3_dot(fe.m[e], p) - fe.o[e] >= margin))
            return 0;
    return 1;
}

int rf_coplanar(const rf_triangle *A, const rf_triangle *B, double tol)
{
    return rf_v3_norm(rf_v3_sub(A->n, B->n)) <= RF_COPLANAR_EPS && fabs(A->d - B->d) <= tol;
}

int rf_inside_closed(const rf_triangle *T, rf_vec3 q)
{
    rf_vec3 ab = rf_v3_sub(T->b, T->a), bc = rf_v3_sub(T->c, T->b), ca = rf_v3_sub(T->a, T->c);
    double orient = rf_v3_dot(rf_v3_cross(ab, rf_v3_scale(ca, -1.0)), T->n) >= 0 ? 1.0 : -1.0;
    if (!(orient * rf_v3_dot(rf_v3_cross(ab, rf_v3_sub(q, T->a)), T->n) >= 0.0))
        return 0;
    if (!(orient * rf_v3_dot(rf_v3_cross(bc, rf_v3_sub(q, T->b)), T->n) >= 0.0))
        return 0;
    return orient * rf_v3_dot(rf_v3_cross(ca, rf_v3_sub(q, T->c)), T->n) >= 0.0;
}
