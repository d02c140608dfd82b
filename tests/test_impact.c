/* test_impact.c - the impact law (Eq. 8, impact.c) on a plane against hand-computed
 * values: the normal velocity reversed with restitution e_n, the tangential Coulomb
 * impulse mu (1 + e_n) m |v_n| taking the slip of the contact point, capped where the
 * slip vanishes (a point mass stops sliding, a sphere rolls at 5/7 of its tangential
 * speed), and the bounce sequence h e^(2k).  Through rf_simulate (motion_test_util.h):
 * each impact's path point is the state right after it. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"

#define G RF_GRAVITY

/* ---- vertical drop: bounce heights h e^(2k) --------------------------------------------- */

TEST(motion_bounce_heights_h_e2k)
{
    const double e = 0.615, h = 3.85;
    rf_terrain t;
    mt_incline(&t, 0.0, 100.0, 100.0, (rf_surface){{e, 0.0}, {0.4, 0.0}, {0.1, 0.0}});
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(2385.0, 2650.0, md);
        double r0 = rf_body_contact_radius(&b);
        rf_state s = mt_state(rf_v3(47.3, 52.1, h + r0), rf_v3(0, 0, 0));
        mt_run r;
        mt_simulate(&t, md, 2385.0, RF_CONTACT_FULL, &s, 1, &r);
        ENSURE(r.rec.reason == RF_END_REST);
        ENSURE(r.n_impacts >= 5);
        double tk = sqrt(2.0 * h / G), vk = sqrt(2.0 * G * h);
        for (int k = 1; k <= 4; k++) {
            double hk = r.impacts[k - 1].speed_ms * r.impacts[k - 1].speed_ms / (2.0 * G);
            ENSURE_REL(hk, h * pow(e, 2.0 * k), 1e-9);
            ENSURE_REL(r.impacts[k - 1].t_s, tk, 1e-9);
            ENSURE_SMALL(r.impacts[k - 1].p.x - 47.3, 1e-12);
            vk *= e;
            tk += 2.0 * vk / G;
        }
        ENSURE_SMALL(r.rec.stop.x - 47.3, 1e-12);
        ENSURE_SMALL(r.rec.stop.y - 52.1, 1e-12);
        ENSURE_REL(r.rec.stop.z, r0 > 0 ? r0 : 1.0, r0 > 0 ? 1e-9 : 1e300);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* A point mass thrown horizontally at vx from height h onto level ground (e, mu fixed):
 * it lands at t = sqrt(2 h / g), x = vx t with v_n = -sqrt(2 g h); after Eq. 8 the
 * normal speed is e |v_n| and the tangential vx - mu (1 + e) |v_n| while that is
 * positive (here at two impacts in a row), then the bounce is vertical. */
TEST(impact_point_mass_restitution_and_friction_by_hand)
{
    const double e = 0.4, mu = 0.3, h = 5.2, vx = 6.1, x0 = 20.0;
    rf_terrain t;
    mt_incline(&t, 0.0, 300.0, 60.0, (rf_surface){{e, 0.0}, {mu, 0.0}, {0.0, 0.0}});
    rf_state s = mt_state(rf_v3(x0, 30.0, h), rf_v3(vx, 0, 0));
    mt_run r;
    mt_simulate(&t, RF_MODEL_POINT, 500.0, RF_CONTACT_FULL, &s, 1, &r);
    ENSURE(r.n_impacts >= 3);
    double t1 = sqrt(2.0 * h / G), vn1 = G * t1;
    const rf_path_point *p1 = &r.impacts[0];
    ENSURE_REL(p1->t_s, t1, 1e-12);
    ENSURE_REL(p1->p.x, x0 + vx * t1, 1e-12);
    ENSURE_SMALL(p1->p.z, 1e-12);
    double u1 = vx - mu * (1.0 + e) * vn1; /* 1.86 m/s: still sliding */
    ENSURE(u1 > 0.0);
    ENSURE_REL(p1->speed_ms, hypot(u1, e * vn1), 1e-12);
    ENSURE_REL(p1->energy_kj, 0.5 * 500.0 * (u1 * u1 + e * e * vn1 * vn1) / 1000.0, 1e-12);
    /* the second flight: up and down at e vn1, 2 e vn1 / g long */
    double t2 = t1 + 2.0 * e * vn1 / G, vn2 = e * vn1;
    const rf_path_point *p2 = &r.impacts[1];
    ENSURE_REL(p2->t_s, t2, 1e-12);
    ENSURE_REL(p2->p.x, p1->p.x + u1 * (t2 - t1), 1e-12);
    double u2 = u1 - mu * (1.0 + e) * vn2; /* 0.16 m/s */
    ENSURE(u2 > 0.0);
    ENSURE_REL(p2->speed_ms, hypot(u2, e * vn2), 1e-12);
    /* the third: the friction impulse mu (1 + e) m e^2 vn1 exceeds m u2, so it stops the
     * sliding and the bounce is vertical */
    double vn3 = e * vn2;
    ENSURE(mu * (1.0 + e) * vn3 > u2);
    ENSURE_REL(r.impacts[2].speed_ms, e * vn3, 1e-12);
    ENSURE_REL(r.impacts[2].p.x, p2->p.x + u2 * 2.0 * vn3 / G, 1e-12);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A point mass striking level ground where mu (1 + e) |v_n| exceeds its tangential
 * speed: the Coulomb impulse is capped where the sliding stops, no further (it does
 * not reverse); after the impact it rises vertically at e |v_n| and lands again at the
 * same point. */
TEST(impact_point_mass_friction_stops_sliding_without_reversing)
{
    const double e = 0.55, mu = 1.7, h = 3.85, vx = 2.385;
    rf_terrain t;
    mt_incline(&t, 0.0, 300.0, 60.0, (rf_surface){{e, 0.0}, {mu, 0.0}, {0.0, 0.0}});
    rf_state s = mt_state(rf_v3(40.0, 30.0, h), rf_v3(vx, 0, 0));
    mt_run r;
    mt_simulate(&t, RF_MODEL_POINT, 500.0, RF_CONTACT_FULL, &s, 1, &r);
    ENSURE(r.n_impacts >= 2);
    double t1 = sqrt(2.0 * h / G), vn = G * t1;
    ENSURE(mu * (1.0 + e) * vn > vx);
    ENSURE_REL(r.impacts[0].speed_ms, e * vn, 1e-12);
    ENSURE_SMALL(r.impacts[1].p.x - r.impacts[0].p.x, 1e-12);
    ENSURE_REL(r.impacts[1].t_s - r.impacts[0].t_s, 2.0 * e * vn / G, 1e-12);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A sphere without spin thrown at vx onto level ground (Eq. 8a-b): the slip of the
 * contact point is vx.  With low friction the Coulomb impulse mu (1 + e) m |v_n| takes
 * that much tangential speed and gives the spin its angular impulse r J_t / I; with
 * high friction it is capped at 2/7 m vx, where the slip vanishes and the sphere rolls
 * at 5/7 vx, w = v / r.  Kinetic energy after: 1/2 m (v_t^2 + e^2 v_n^2) + 1/2 I w^2. */
TEST(impact_sphere_slip_taken_up_to_rolling_by_hand)
{
    const double e = 0.35, h = 4.25, vx = 5.3, mass = 2385.0;
    const double mus[2] = {0.05, 0.9};
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_SPHERE);
    double I = 0.4 * mass * b.radius * b.radius;
    ENSURE_REL(b.inertia, I, 1e-12);
    for (int k = 0; k < 2; k++) {
        double mu = mus[k];
        rf_terrain t;
        mt_incline(&t, 0.0, 300.0, 60.0, (rf_surface){{e, 0.0}, {mu, 0.0}, {0.0, 0.0}});
        rf_state s = mt_state(rf_v3(30.0, 30.0, h + b.radius), rf_v3(vx, 0, 0));
        mt_run r;
        mt_simulate(&t, RF_MODEL_SPHERE, mass, RF_CONTACT_FULL, &s, 1, &r);
        ENSURE(r.n_impacts >= 1);
        double vn = sqrt(2.0 * G * h);
        double jt = fmin(mu * (1.0 + e) * mass * vn, 2.0 / 7.0 * mass * vx);
        double vt = vx - jt / mass, w = b.radius * jt / I;
        if (k == 1) { /* capped: rolling */
            ENSURE_REL(vt, 5.0 / 7.0 * vx, 1e-12);
            ENSURE_REL(w * b.radius, vt, 1e-12);
        } else {
            ENSURE(vt - w * b.radius > 0.1); /* still slipping */
        }
        const rf_path_point *p = &r.impacts[0];
        ENSURE_REL(p->t_s, sqrt(2.0 * h / G), 1e-12);
        ENSURE_REL(p->speed_ms, hypot(vt, e * vn), 1e-12);
        double ke = 0.5 * mass * (vt * vt + e * e * vn * vn) + 0.5 * I * w * w;
        ENSURE_REL(p->energy_kj, ke / 1000.0, 1e-12);
        ENSURE(p->energy_kj < 0.5 * mass * (vx * vx + vn * vn) / 1000.0);
        mt_run_free(&r);
        rf_terrain_free(&t);
    }
}

/* Restitution 0: the normal velocity is taken entirely; on an incline a point mass
 * landing with the rock's tangential velocity along the fall line keeps
 * v_t - mu |v_n| and slides on at once (no bounce: the next event is no impact). */
TEST(impact_zero_restitution_lands_and_slides_on_an_incline)
{
    const double theta = 0.5, mu = 0.25, L = 200.0;
    rf_terrain t;
    mt_incline(&t, theta, L, 60.0, (rf_surface){{0.0, 0.0}, {mu, 0.0}, {0.0, 0.0}});
    /* 2 m above the plane at x = 40, moving down the fall line at 3 m/s along it */
    rf_vec3 along = rf_v3(cos(theta), 0.0, -sin(theta));
    rf_state s = mt_incline_state(theta, L, 40.0, 30.0, 2.0, rf_v3_scale(along, 3.0));
    mt_run r;
    mt_simulate_t(&t, RF_MODEL_POINT, 800.0, RF_CONTACT_FULL, &s, 1, 4.0, &r);
    ENSURE(r.n_impacts >= 1);
    /* the flight to the plane: the normal part of gravity g cos(theta) brings the
     * point down 2 m in sqrt(4 / (g cos theta)), the tangential part speeds it up */
    double tn = sqrt(2.0 * 2.0 / (G * cos(theta)));
    double vn = G * cos(theta) * tn, vt = 3.0 + G * sin(theta) * tn;
    ENSURE_REL(r.impacts[0].t_s, tn, 1e-9);
    ENSURE_REL(r.impacts[0].speed_ms, vt - mu * vn, 1e-9);
    ENSURE(r.rec.n_impacts == 1);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* The rt law (tangential restitution) on level ground, a rock without spin thrown at vx
 * from height h: the normal speed e |v_n| as Eq. 8; the centre's tangential speed R_t vx
 * for the point mass; for the sphere R_t vx and rolling (w = v_t / r) while that costs
 * no more than the energy m vx^2 / 2 it had along the ground (R_t <= sqrt(5/7)), else
 * rolling at sqrt(5/7) vx, the speed that energy pays.  The next flight lands 2 e |v_n|
 * v_t / g further on. */
TEST(impact_rt_law_landing_on_a_plane_by_hand)
{
    const double e = 0.45, h = 3.1, vx = 6.4, mass = 1200.0;
    const double rts[3] = {0.3, 0.8, 0.95};
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(mass, 2650.0, md);
        double r0 = rf_body_contact_radius(&b);
        for (int k = 0; k < 3; k++) {
            double rt = rts[k];
            rf_terrain t;
            mt_incline(&t, 0.0, 300.0, 60.0,
                       (rf_surface){{e, 0.0}, {0.5, 0.0}, {0.1, 0.0}, 0.0, RF_IMPACT_RT,
                                    {rt, 0.0}});
            rf_state s = mt_state(rf_v3(30.0, 30.0, h + r0), rf_v3(vx, 0, 0));
            mt_run r;
            mt_simulate(&t, md, mass, RF_CONTACT_FULL, &s, 1, &r);
            ENSURE(r.n_impacts >= 2);
            double vn = sqrt(2.0 * G * h), vt = rt * vx, rot = 0.0;
            if (md == RF_MODEL_SPHERE) {
                vt = fmin(rt, sqrt(5.0 / 7.0)) * vx;
                rot = 0.5 * b.inertia * (vt / b.radius) * (vt / b.radius);
            }
            const rf_path_point *p = &r.impacts[0];
            ENSURE_REL(p->speed_ms, hypot(vt, e * vn), 1e-12);
            ENSURE_REL(p->energy_kj, (0.5 * mass * (vt * vt + e * e * vn * vn) + rot) / 1000.0,
                       1e-12);
            ENSURE_REL(r.impacts[1].p.x - p->p.x, vt * 2.0 * e * vn / G, 1e-9);
            ENSURE(r.energy_gain_kj <= 0.0);
            mt_run_free(&r);
            rf_terrain_free(&t);
        }
    }
}
