/* surface_law.c - the laws of motion on a face and in a crease (surface_law.h states
 * them, Eq. 1-2 and the 5/7 law). */
#include "engine/surface_law.h"

#include <math.h>

#include "engine/geometry.h"
#include "engine/rock.h"

void rf_face_setup(const rf_motion *m, rf_vec3 n, rf_face_dyn *f)
{
    f->n = n;
    f->gn = RF_GRAVITY * n.z;
    /* g_t = g - (g.n) n with g = (0, 0, -G) */
    f->gt = rf_v3(RF_GRAVITY * n.z * n.x, RF_GRAVITY * n.z * n.y, RF_GRAVITY * n.z * n.z - RF_GRAVITY);
    f->G = rf_v3_norm(f->gt);
    if (f->G > RF_VEC_ZERO) {
        f->e1 = rf_v3_scale(f->gt, 1.0 / f->G);
    } else {
        f->G = 0.0;
        f->gt = rf_v3(0, 0, 0);
        rf_vec3 x = fabs(n.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 1, 0);
        f->e1 = rf_v3_unit(rf_v3_madd(x, -rf_v3_dot(x, n), n));
    }
    f->mu = m->rock.sup.mu;
    if (m->cfg.point) {
        f->mode = RF_LAW_POINT, f->k = 1.0, f->c = m->rock.sup.mu;
    } else if (m->rock.sup.rolling) {
        f->mode = RF_LAW_ROLL, f->k = rf_roll_factor(m->cfg.body, m->cfg.rho), f->c = m->rock.sup.mu_r;
    } else {
        f->mode = RF_LAW_SLIDE, f->k = 1.0, f->c = m->rock.sup.mu;
    }
    f->K = m->cfg.point ? 1.0 : rf_slip_factor(m->cfg.body, m->cfg.rho);
}

/* The surface laws (module comment): acceleration of the centre and rate of the slip. */
rf_vec3 rf_law_accel(const rf_face_dyn *f, rf_vec3 dir)
{
    return rf_v3_scale(rf_v3_madd(f->gt, -f->c * f->gn, dir), f->k);
}

rf_vec3 rf_law_slip_rate(const rf_face_dyn *f, rf_vec3 udir)
{
    return rf_v3_madd(f->gt, -f->K * f->mu * f->gn, udir);
}

/* The direction the laws act along: the slip's for a slipping sphere, else the
 * velocity's; the fall line when it is zero. */
rf_vec3 rf_law_dir(const rf_face_dyn *f, rf_vec3 v, rf_vec3 u)
{
    rf_vec3 x = f->mode == RF_LAW_SLIDE ? u : v;
    double xl = rf_v3_norm(x);
    return xl > 0 ? rf_v3_scale(x, 1.0 / xl) : f->e1;
}

void rf_wall_law(rf_vec3 dir, rf_vec3 *a, rf_vec3 *du)
{
    *a = rf_v3_scale(dir, rf_v3_dot(*a, dir));
    *du = rf_v3_scale(dir, rf_v3_dot(*du, dir)); /* the wall's push changes no spin */
}

rf_vec3 rf_surface_accel(const rf_motion *m, rf_vec3 n, rf_vec3 v, rf_vec3 u, rf_vec3 *du)
{
    rf_face_dyn f;
    rf_face_setup(m, n, &f);
    rf_vec3 dir = rf_law_dir(&f, v, u);
    *du = f.mode == RF_LAW_SLIDE ? rf_law_slip_rate(&f, dir) : rf_v3(0, 0, 0);
    return rf_law_accel(&f, dir);
}

int rf_crease_forces(rf_vec3 nA, rf_vec3 nB, double *xA, double *xB, rf_vec3 *l)
{
    rf_vec3 c = rf_v3_cross(nA, nB);
    double cl = rf_v3_norm(c);
    if (!(cl > RF_CREASE_MIN_ANGLE))
        return -1;
    *l = rf_v3_scale(c, 1.0 / cl);
    double bA = RF_GRAVITY * nA.z, bB = RF_GRAVITY * nB.z, nab = rf_v3_dot(nA, nB);
    double den = 1.0 - nab * nab;
    *xA = (bA - nab * bB) / den;
    *xB = (bB - nab * bA) / den;
    return 0;
}

rf_vec3 rf_crease_centre(const rf_triangle *A, const rf_triangle *B, double rho, rf_vec3 p)
{
    /* p + a nA + b nB with nA.x = dA + rho and nB.x = dB + rho: a 2 x 2 system, solved
     * exactly (alternate projections onto the two planes converge slowly where the
     * faces are nearly parallel) */
    double eA = A->d + rho - rf_v3_dot(A->n, p), eB = B->d + rho - rf_v3_dot(B->n, p);
    double c = rf_v3_dot(A->n, B->n), den = 1.0 - c * c;
    return rf_v3_madd(rf_v3_madd(p, (eA - c * eB) / den, A->n), (eB - c * eA) / den, B->n);
}

rf_spin_law rf_crease_roll(const rf_motion *m)
{
    const rf_terrain *t = m->cfg.terrain;
    rf_vec3 nm = rf_v3_unit(rf_v3_add(RF_TRI(t, m->rock.sup.tri[0])->n, RF_TRI(t, m->rock.sup.tri[1])->n));
    rf_vec3 z = rf_v3(0, 0, 0);
    return (rf_spin_law){nm, 0.0, z, z};
}

int rf_surface_holds(const rf_motion *m)
{
    const rf_terrain *t = m->cfg.terrain;
    double c = m->cfg.point ? m->rock.sup.mu : (m->rock.sup.rolling ? m->rock.sup.mu_r : -1.0);
    if (m->rock.sup.n == 1) {
        if (c < 0)
            return 0; /* a slipping sphere first rolls */
        rf_vec3 n = RF_TRI(t, m->rock.sup.tri[0])->n;
        double G = RF_GRAVITY * sqrt(rf_fmax(0.0, 1.0 - n.z * n.z));
        return G <= c * RF_GRAVITY * n.z;
    }
    if (m->rock.sup.n == 2) {
        if (c < 0)
            c = m->rock.sup.mu;
        double xA = 0.0, xB = 0.0; /* crease_forces may fail before setting them */
        rf_vec3 l;
        if (rf_crease_forces(RF_TRI(t, m->rock.sup.tri[0])->n, RF_TRI(t, m->rock.sup.tri[1])->n, &xA, &xB, &l))
            return 0;
        return fabs(RF_GRAVITY * l.z) <= c * (xA + xB);
    }
    return 0;
}

int rf_support_steep(const rf_motion *m)
{
    const rf_terrain *t = m->cfg.terrain;
    double c = m->cfg.point ? m->rock.sup.mu : m->rock.sup.mu_r;
    if (m->rock.sup.n == 1) {
        rf_vec3 n = RF_TRI(t, m->rock.sup.tri[0])->n;
        return RF_GRAVITY * sqrt(rf_fmax(0.0, 1.0 - n.z * n.z)) > c * RF_GRAVITY * n.z;
    }
    if (m->rock.sup.n == 2) {
        double xA = 0.0, xB = 0.0;
        rf_vec3 l;
        if (rf_crease_forces(RF_TRI(t, m->rock.sup.tri[0])->n, RF_TRI(t, m->rock.sup.tri[1])->n, &xA, &xB, &l))
            return 0;
        return fabs(RF_GRAVITY * l.z) > c * (xA + xB);
    }
    return 0;
}

int rf_roll_holds(const rf_motion *m, rf_vec3 n)
{
    rf_face_dyn f;
    rf_face_setup(m, n, &f);
    double k = rf_roll_factor(m->cfg.body, m->cfg.rho);
    double vl = rf_v3_norm(m->rock.s.v);
    if (!(vl > 0) && rf_surface_holds(m))
        return 1; /* at rest where it stays: no force is needed */
    rf_vec3 dir = vl > 0 ? rf_v3_scale(m->rock.s.v, 1.0 / vl) : f.e1;
    rf_vec3 need = rf_v3_madd(rf_v3_scale(f.gt, 1.0 - k), -k * m->rock.sup.mu_r * f.gn, dir);
    double cap = m->rock.sup.mu * f.gn * (1 + RF_FRICTION_SLACK);
    /* or the slip law lets no slip grow from zero (|g_t| <= K mu g_n, the demand
     * without the resistance): where the two laws disagree (uphill, see docs/engine.md)
     * the sphere rolls on instead of switching between them at every instant */
    return rf_v3_norm(need) <= cap || f.G * (1.0 - k) <= cap;
}
