/* rock.c - the rock's records (path length, samples, path points, largest energy),
 * its spin by the surface laws, and the draws of its coefficients. */
#include "engine/rock.h"

#include <gsl/gsl_randist.h>
#include <math.h>

#include "engine/geometry.h"
#include "engine/travel.h"

double rf_draw_truncated(gsl_rng *rng, rf_dist d, double lo, double hi)
{
    if (d.sd > 0.0) {
        for (int k = 0; k < RF_DRAW_MAX_TRIES; k++) {
            double x = d.mean + gsl_ran_gaussian_ziggurat(rng, d.sd);
            if (x >= lo && x <= hi)
                return x;
        }
    }
    return d.mean < lo ? lo : (d.mean > hi ? hi : d.mean);
}

double rf_roll_factor(const rf_body *b, double rho)
{
    return 1.0 / (1.0 + b->inertia / (b->mass * rho * rho)); /* 5/7 for I = 2/5 m r^2 */
}

double rf_slip_factor(const rf_body *b, double rho)
{
    return 1.0 + b->mass * rho * rho / b->inertia; /* 7/2 for I = 2/5 m r^2 */
}


/* Slip of the contact point of the sphere on a face with normal n. */
rf_vec3 rf_slip_of(const rf_motion *m, rf_vec3 n)
{
    rf_vec3 u = rf_v3_add(m->rock.s.v, rf_v3_cross(m->rock.s.w, rf_v3_scale(n, -m->cfg.rho)));
    return rf_in_plane(u, n);
}

/* The law of a piece on face n from the current state, its slip u0 at the start
 * changing at the rate du. */
rf_spin_law rf_spin_law_of(const rf_motion *m, rf_vec3 n, rf_vec3 u0, rf_vec3 du)
{
    return (rf_spin_law){n, rf_v3_dot(m->rock.s.w, n), u0, du};
}

rf_spin_law rf_spin_law_over(const rf_motion *m, rf_vec3 n, rf_vec3 u, rf_vec3 u1, double h)
{
    return h > 0 ? rf_spin_law_of(m, n, u, rf_v3_scale(rf_v3_sub(u1, u), 1.0 / h))
                 : rf_spin_law_of(m, n, u1, rf_v3(0, 0, 0));
}

rf_vec3 rf_spin_at(const rf_spin_law *l, double rho, rf_vec3 v, double t)
{
    rf_vec3 u = rf_v3_madd(l->u0, t, l->du);
    rf_vec3 wt = rf_v3_scale(rf_v3_cross(l->n, rf_v3_sub(v, u)), 1.0 / rho);
    return rf_v3_madd(wt, l->wn, l->n);
}

/* Angular velocity from v and slip u on a face (w . n kept): w_t = n x (v - u) / r. */
void rf_set_spin(rf_motion *m, rf_vec3 n, rf_vec3 u)
{
    if (m->cfg.point) {
        m->rock.s.w = rf_v3(0, 0, 0);
    } else {
        rf_spin_law l = rf_spin_law_of(m, n, u, rf_v3(0, 0, 0));
        m->rock.s.w = rf_spin_at(&l, m->cfg.rho, m->rock.s.v, 0.0);
    }
    rf_motion_note_energy(m);
}

rf_vec3 rf_face_slip(rf_motion *m, rf_vec3 n)
{
    rf_vec3 u = rf_slip_of(m, n);
    if (!m->rock.sup.rolling && rf_v3_norm(u) <= RF_SLIP_EPS) {
        m->rock.sup.rolling = 1;
        rf_set_spin(m, n, rf_v3(0, 0, 0));
        return rf_v3(0, 0, 0);
    }
    return u;
}

double rf_motion_energy(const rf_motion *m)
{
    return rf_kinetic_energy(m->cfg.body, m->rock.s.v, m->rock.s.w);
}

double rf_motion_note_energy(rf_motion *m)
{
    double e = rf_motion_energy(m) / 1000.0;
    if (e > m->book.rec->max_energy_kj)
        m->book.rec->max_energy_kj = e;
    return e;
}

void rf_motion_sample(rf_motion *m, rf_vec3 p, rf_vec3 v, double ekj)
{
    double z;
    double h = rf_terrain_height(m->cfg.terrain, p.x, p.y, &z) >= 0 ? p.z - z : 0.0;
    m->book.sink->sample(m->book.sink->ctx, p, rf_v3_norm(v), ekj, h);
}

void rf_motion_advance(rf_motion *m, const rf_arc *arc, double T, const rf_spin_law *law)
{
    rf_motion_advance_split(m, arc, arc, T, law);
}

void rf_motion_advance_split(rf_motion *m, const rf_arc *arc, const rf_arc *vel, double T,
                             const rf_spin_law *law)
{
    if (!(T > 0))
        return;
    if (m->cfg.point)
        law = NULL; /* no spin */
    m->book.rec->path_length_m += rf_arc_length(arc->v, arc->a, T);
    rf_scene_travel(m, arc, T);
    const rf_sink *sk = m->book.sink;
    if (rf_motion_samples(m)) {
        /* |v_h(t)|^2 is convex on an arc: its larger end bounds the horizontal speed */
        double vmax = fmax(rf_v3_hnorm(arc->v), rf_v3_hnorm(rf_arc_vel(arc, T)));
        double L = vmax * T;
        double next = sk->sample_spacing - m->book.sample_acc, last = -1.0;
        for (long k = 0; next <= L && k < RF_MAX_ARC_SAMPLES; k++) {
            double ts = T * next / L;
            rf_vec3 v = rf_arc_vel(vel, ts);
            rf_vec3 w = law ? rf_spin_at(law, m->cfg.rho, v, ts) : m->rock.s.w;
            rf_motion_sample(m, rf_arc_pos(arc, ts), v, rf_kinetic_energy(m->cfg.body, v, w) / 1000.0);
            last = next;
            next += sk->sample_spacing;
        }
        m->book.sample_acc = last >= 0 ? L - last : m->book.sample_acc + L;
    }
    m->rock.s.p = rf_arc_pos(arc, T);
    m->rock.s.v = rf_arc_vel(vel, T);
    m->rock.s.t += T;
}

void rf_motion_event(rf_motion *m)
{
    m->book.marked++;
    double e = rf_motion_note_energy(m);
    const rf_sink *sk = m->book.sink;
    if (!sk)
        return;
    if (sk->path_point) {
        rf_path_point pt = {m->rock.s.t, m->rock.s.p, rf_v3_norm(m->rock.s.v), e};
        sk->path_point(sk->ctx, &pt);
    }
    if (sk->sample) {
        rf_motion_sample(m, m->rock.s.p, m->rock.s.v, e);
        m->book.sample_acc = 0.0;
    }
}
