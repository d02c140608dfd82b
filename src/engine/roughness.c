/* roughness.c - slope roughness as a random tilt of the contact normal (roughness.h).
 *
 * Law (PlatRock, Bourrier and Toe, Common/BounceModels.py, set_updated_normal3D; the
 * angle atan(S / R) of CRSP's slope roughness S for a rock of radius R, Jones et al.
 * 2000): theta = U1 atan(r_s / R) with U1 uniform on [0, 1); a tilt alpha = theta U2
 * about d x n, whose sign turns the tilted face against the motion (it brakes: v . n_t
 * = v_n cos alpha cos beta - |v_t| sin alpha, more negative than v_n cos ...), then a
 * tilt beta = +-theta (1 - U2) about d, the side + where U3 >= 0.5.  The two rotations
 * in that order give, exactly,
 *     n_t = n cos alpha cos beta - d sin alpha + (d x n) cos alpha sin beta,
 * a unit vector.  Where n_t would not face the incoming velocity (v . n_t >= 0: the
 * rock would not approach the tilted face) the three numbers are drawn again, at most
 * RF_ROUGH_MAX_DRAWS times, then the real normal is kept.  With no tangential velocity
 * (|v_t| <= RF_VEC_ZERO) d is drawn uniformly in the plane first, and every tilt faces
 * v (v . n_t = v_n cos alpha cos beta < 0).  When the tilt applies, which rock it
 * applies to, and the stay decision are the caller's (impact.c). */
#include "engine/roughness.h"

#include <math.h>

#include "base/tolerances.h"
#include "base/util.h"
#include "rockfall/units.h"

/* A unit vector in the plane of unit normal n at angle phi from a fixed axis there. */
static rf_vec3 in_plane_direction(rf_vec3 n, double phi)
{
    rf_vec3 a = fabs(n.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 1, 0);
    rf_vec3 e1 = rf_v3_unit(rf_v3_madd(a, -rf_v3_dot(a, n), n));
    rf_vec3 e2 = rf_v3_cross(n, e1);
    return rf_v3_add(rf_v3_scale(e1, cos(phi)), rf_v3_scale(e2, sin(phi)));
}

int rf_rough_normal(gsl_rng *rng, rf_vec3 n, rf_vec3 v, double rs, double radius, rf_vec3 *nt,
                    double *theta)
{
    double tmax = atan(rs / radius);
    rf_vec3 vt = rf_v3_madd(v, -rf_v3_dot(v, n), n);
    double vtl = rf_v3_norm(vt);
    rf_vec3 d = vtl > RF_VEC_ZERO ? rf_v3_scale(vt, 1.0 / vtl)
                                  : in_plane_direction(n, 2.0 * RF_PI * gsl_rng_uniform(rng));
    rf_vec3 side = rf_v3_cross(d, n);
    *nt = n;
    for (int k = 0; k < RF_ROUGH_MAX_DRAWS; k++) {
        double th = gsl_rng_uniform(rng) * tmax;
        double u2 = gsl_rng_uniform(rng);
        double sgn = gsl_rng_uniform(rng) < 0.5 ? -1.0 : 1.0;
        double a = th * u2, b = sgn * th * (1.0 - u2);
        rf_vec3 t = rf_v3_add(rf_v3_scale(n, cos(a) * cos(b)), rf_v3_scale(d, -sin(a)));
        t = rf_v3_madd(t, cos(a) * sin(b), side);
        if (rf_v3_dot(v, t) < 0.0) {
            *nt = t;
            if (theta)
                *theta = th;
            return 1;
        }
    }
    return 0;
}
