/* vec3.h - double-precision 3-vector value type with inline operations. */
#ifndef ROCKFALL_VEC3_H
#define ROCKFALL_VEC3_H

#include <math.h>

typedef struct rf_vec3 {
    double x, y, z;
} rf_vec3;

static inline rf_vec3 rf_v3(double x, double y, double z) { rf_vec3 v = {x, y, z}; return v; }
static inline rf_vec3 rf_v3_add(rf_vec3 a, rf_vec3 b) { return rf_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline rf_vec3 rf_v3_sub(rf_vec3 a, rf_vec3 b) { return rf_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline rf_vec3 rf_v3_scale(rf_vec3 a, double s) { return rf_v3(a.x * s, a.y * s, a.z * s); }
/* a + s b */
static inline rf_vec3 rf_v3_madd(rf_vec3 a, double s, rf_vec3 b) { return rf_v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z); }
static inline double rf_v3_dot(rf_vec3 a, rf_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline rf_vec3 rf_v3_cross(rf_vec3 a, rf_vec3 b)
{
    return rf_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double rf_v3_norm2(rf_vec3 a) { return rf_v3_dot(a, a); }
static inline double rf_v3_norm(rf_vec3 a) { return sqrt(rf_v3_dot(a, a)); }
/* Unit vector along a; the zero vector stays zero. */
static inline rf_vec3 rf_v3_unit(rf_vec3 a)
{
    double n = rf_v3_norm(a);
    return n > 0.0 ? rf_v3_scale(a, 1.0 / n) : a;
}
static inline double rf_v3_hnorm(rf_vec3 a) { return hypot(a.x, a.y); } /* horizontal length */

/* The point of the segment a-b closest to p (a when the segment is a point). */
static inline rf_vec3 rf_v3_closest_on_segment(rf_vec3 a, rf_vec3 b, rf_vec3 p)
{
    rf_vec3 ab = rf_v3_sub(b, a);
    double l2 = rf_v3_norm2(ab);
    if (!(l2 > 0))
        return a;
    double s = rf_v3_dot(rf_v3_sub(p, a), ab) / l2;
    s = s < 0 ? 0 : (s > 1 ? 1 : s);
    return rf_v3_madd(a, s, ab);
}

#endif
