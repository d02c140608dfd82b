/* test_replay_creases.c - hard cases that pin creases, edges and ridges: a gully's
 * thalweg, valley lines, convex edges and shoulders, a sharp ridge; the rock goes on
 * along them or off them without looping between faces in no time, and pays for every
 * rise. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

/* ---- a frictionless V-shaped gully ---------------------------------------------------- */

static void v_gully(rf_terrain *t, double slope, double side, double L, double W, rf_surface s)
{
    /* z = -slope x + side |y| on x in [0, L], y in [-W, W]: two planes, four triangles */
    rf_vec3 P[6] = {{0, -W, side * W},         {L, -W, -slope * L + side * W},
                    {0, 0, 0},                 {L, 0, -slope * L},
                    {0, W, side * W},          {L, W, -slope * L + side * W}};
    static const int tris[4][3] = {{0, 1, 3}, {0, 3, 2}, {2, 3, 5}, {2, 5, 4}};
    char *buf = mt_stl_text(P, tris, 4);
    mt_mesh_text(t, "v.stl", buf, s);
    free(buf);
}

TEST(hard_frictionless_v_gully_energy)
{
    const double slope = tan(12.0 * PI / 180.0), side = tan(35.0 * PI / 180.0);
    rf_terrain t;
    v_gully(&t, slope, side, 80.0, 20.0, (rf_surface){{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}});
    for (int model = 0; model < 2; model++) {
        rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_body b = rf_body_make(2385.0, 2650.0, md);
        double rho = rf_body_contact_radius(&b);
        double x0 = 3.7;
        /* on the thalweg, touching both faces */
        double zc = rho * sqrt(1.0 + slope * slope + side * side) - slope * x0;
        rf_state s = mt_state(rf_v3(x0, 0.0, zc), rf_v3(0, 0, 0));
        mt_run r;
        mt_simulate(&t, md, 2385.0, RF_CONTACT_FULL, &s, 3, &r);
        ensure_sane(&r, 300);
        ENSURE_MSG(r.rec.reason == RF_END_EXITED, "reason %d", (int)r.rec.reason);
        ENSURE(r.npoints < 50);
        /* the outlet: where the rock leaves the faces at x = 80 */
        const rf_path_point *out = NULL;
        for (size_t k = 0; k < r.npoints && !out; k++)
            if (r.points[k].p.x >= 80.0 - 1e-9)
                out = &r.points[k];
        ENSURE(out != NULL);
        ENSURE(out->p.x <= 80.0 + rho);
        double ke = out->energy_kj * 1000.0, pe = 2385.0 * G * (s.p.z - out->p.z);
        ENSURE_REL(ke, pe, 1e-3);
        ENSURE_SMALL(out->p.y, 1e-6);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* A sphere rolling fast over a convex edge flies off it on a path that dips back into
 * the edge's reach, but only far along the edge's line beyond its end.  The dip was
 * taken for a contact at the start: the sphere rolled back onto the face, flew off
 * again, and so on, 65 000 events until the event cap; it now flies on, and rests. */
TEST(hard_replay_flight_off_an_edge_past_its_end_goes_on)
{
    replay_sphere_rests(16, 51, 25);
}

/* A point mass sliding along the valley line of two faces 3e-5 rad apart, exactly on
 * their common edge: the crease's direction, from the two normals, strayed from that
 * edge by a hair, and the point left the crease over it at once, flew, landed on the
 * first face, crossed onto the second, and so on in no time, until the rescues ran out
 * (17 000 events).  It now slides on along the valley (y = 2051.2814, over 3.5 m of it)
 * and, its friction drawn at 0.88, rests beyond it. */
TEST(hard_replay_point_along_a_shallow_valley_line_goes_on)
{
    replay rp;
    mt_run r;
    replay_ends_open(1, 40, 251, RF_MODEL_POINT, RF_END_REST, &rp, &r);
    double x0 = INFINITY, x1 = -INFINITY;
    for (size_t i = 0; i < r.npoints; i++)
        if (fabs(r.points[i].p.y - 2051.2814) < 1e-3) {
            x0 = fmin(x0, r.points[i].p.x);
            x1 = fmax(x1, r.points[i].p.x);
        }
    ENSURE_MSG(x1 - x0 > 3.5, "along the valley from x %.3f to %.3f", x0, x1);
    replay_finish(&rp, &r, 1, 40, 251);
}

/* A point mass landing on one wall of a narrow gully exactly on its thalweg, moving a
 * hair into the face: the exit the step's parabola found 3.5 ms later, where gravity
 * has turned it back to the other wall, was taken at the start, a hair beyond the edge
 * but moving in.  Leaving there it flew off the face it was moving into, which the
 * flight leaves out, and fell 18 m through it.  It now meets the other wall. */
TEST(hard_replay_point_leaving_a_face_it_moves_into_stays_on)
{
    replay_point_rests(1, 9, 111);
}

/* A point mass bouncing in a frictionless pit (e = 1) for 48 s, its path on a face out
 * over one edge and back within one step (0.1 mm beyond it): Newton's method on the
 * path stopped at the rounding of the edge's function, a step's worth short of the time
 * tolerance, and the bracket search that followed started after the path's return, found
 * no crossing and passed over that edge.  The rock was taken out over another edge, in
 * the column beyond, under the face there, and fell through it (9.6 m under the
 * terrain).  The exit is now narrowed within Newton's bracket, and the rock rests. */
TEST(hard_replay_point_out_and_back_over_an_edge_within_a_step_rests)
{
    REPLAY_EACH(replay_point_rests, {301, 59, 93});
}

/* Point masses slowing to rest on a face as they reach a valley line: the step in which
 * they fell below the stop speed ended at rest although they left the face earlier in
 * it, and they rested beyond the edge, under the steeper face there (by 0.35 mm and
 * 2.5 mm).  Leaving the face still faster than the stop speed, they now meet the face
 * beyond. */
TEST(hard_replay_point_slowing_to_rest_beyond_an_edge_meets_the_next_face)
{
    REPLAY_EACH(replay_point_rests, {300, 15, 226}, {304, 6, 282});
}

/* A 62 t sphere rolling along a convex edge of its face, its velocity almost along the
 * edge: it left the face over that edge, met the edge at once curving in, rolled over
 * it back onto the face it had just left, left it again, and so on in no time until
 * the rescues ran out (17 000 events).  It now hops off the edge and goes on. */
TEST(hard_replay_sphere_along_a_convex_edge_goes_on)
{
    replay_ends(88, 44, 66, RF_MODEL_SPHERE, RF_END_EXITED);
}

/* A 1 t sphere rolling fast along a convex shoulder (40 degrees up to the edge, 10
 * degrees up beyond it) on the steep face, its contact point on the edge, moving across
 * it at 2 cm/s: rolling onto the upper face would lift its centre by 0.2 m, which the
 * motion across the edge cannot pay (the motion along it does not turn the sphere
 * about the edge), so it rolls back down.  The roll was paid from the whole energy:
 * it went onto the upper face, 5 m/s slowing to 4.86, and was back 28 ms later. */
TEST(hard_sphere_along_a_shoulder_pays_its_rise_from_the_motion_across)
{
    const double th1 = 40.0 * PI / 180.0, th2 = 10.0 * PI / 180.0, L = 10.0;
    const double prof[6] = {0.0, 0.0, L, L * tan(th1), 2.0 * L, L * tan(th1) + L * tan(th2)};
    rf_terrain t;
    mt_profile(&t, prof, 3, 20.0, (rf_surface){{0.0, 0.0}, {0.5, 0.0}, {0.0, 0.0}});
    rf_body b = rf_body_make(1000.0, 2650.0, RF_MODEL_SPHERE);
    rf_vec3 n = rf_v3(-sin(th1), 0.0, cos(th1)), up = rf_v3(cos(th1), 0.0, sin(th1));
    double x = L - 1e-9 * cos(th1), y = 0.5 * (t.ymin + t.ymax);
    rf_vec3 v = rf_v3_madd(rf_v3(0.0, 5.0, 0.0), 0.02, up);
    rf_state s = mt_state(rf_v3_madd(rf_v3(x, y, x * tan(th1)), b.radius, n), v);
    s.w = rf_v3_scale(rf_v3_cross(n, v), 1.0 / b.radius); /* rolling */
    mt_run r;
    mt_simulate(&t, RF_MODEL_SPHERE, 1000.0, RF_CONTACT_FULL, &s, 3, &r);
    ensure_sane(&r, 300);
    double zmax = -INFINITY;
    for (size_t i = 0; i < r.npoints; i++)
        zmax = fmax(zmax, r.points[i].p.z);
    /* the motion across pays 0.7 (0.02 m/s)^2 / g = 29 um of rise */
    ENSURE_MSG(zmax <= s.p.z + 1e-4, "rose %.3g m", zmax - s.p.z);
    ENSURE(r.rec.stop.x < L);
    mt_run_free(&r);
    rf_terrain_free(&t);
}

/* A 10 kg sphere rolling along the crest of a sharp ridge (its faces 55 degrees either
 * side, 110 degrees between their normals) on one face, its contact point on the crest,
 * moving across it towards the other face at up to 0.7 m/s: rolling over the crest
 * would lift its centre by 0.43 r, more than that motion can pay, so it rolls back
 * down its own face, never moving from face to face in no time and never into the
 * terrain.  It was rolled over onto the other face, whose slope sent it back at once,
 * over and over (up to 15 events in no time, then a rescue), and it ended down either
 * side (cf. 303/7/186 of the random scenes). */
TEST(hard_sphere_along_a_sharp_ridge_rolls_down_its_own_side)
{
    const double slope = tan(3.0 * PI / 180.0), side = tan(55.0 * PI / 180.0);
    rf_terrain t;
    v_gully(&t, slope, -side, 40.0, 6.0, (rf_surface){{0.0, 0.0}, {0.6, 0.0}, {0.0, 0.0}});
    static const double across[] = {1e-8, 1e-5, 1e-3, 0.05, 0.3, 0.7};
    rf_body b = rf_body_make(10.0, 2650.0, RF_MODEL_SPHERE);
    double rho = b.radius, x0 = 2.0;
    double cn = sqrt(1.0 + slope * slope), nn = sqrt(1.0 + slope * slope + side * side);
    rf_vec3 n0 = rf_v3(slope / nn, -side / nn, 1.0 / nn); /* the face on the side y < 0 */
    rf_vec3 along = rf_v3(1.0 / cn, 0.0, -slope / cn);
    rf_vec3 up = rf_v3(0.0, 1.0 / sqrt(1.0 + side * side), side / sqrt(1.0 + side * side));
    for (size_t k = 0; k < sizeof across / sizeof *across; k++) {
        /* on the face y < 0, touching the crest at x0, 2 m/s along it */
        rf_vec3 q = rf_v3(x0, 0.0, -slope * x0);
        rf_state s = mt_state(rf_v3_madd(q, rho, n0),
                              rf_v3_madd(rf_v3_scale(along, 2.0), across[k], up));
        mt_run r;
        mt_simulate(&t, RF_MODEL_SPHERE, 10.0, RF_CONTACT_FULL, &s, 5, &r);
        double vy = across[k]; /* the speed across the crest, named in the messages */
        ensure_sane(&r, 300);
        ENSURE_MSG(r.rec.reason == RF_END_EXITED, "%g m/s: reason %d", vy, (int)r.rec.reason);
        ENSURE_MSG(longest_stall(&r) <= 2, "%g m/s: %zu events in no time", vy,
                   longest_stall(&r));
        ENSURE_MSG(r.rec.stop.y < -5.0, "%g m/s: ends at y = %.3g", vy, r.rec.stop.y);
        double e0 = rf_kinetic_energy(&b, s.v, s.w) + b.mass * G * s.p.z;
        for (size_t i = 1; i < r.npoints; i++) {
            rf_vec3 c = r.points[i].p;
            ENSURE_MSG(mt_terrain_distance(&t, c) >= rho * (1.0 - 1e-6),
                       "%g m/s: point %zu at %.6g r", vy, i, mt_terrain_distance(&t, c) / rho);
            ENSURE(r.points[i].energy_kj * 1000.0 + b.mass * G * c.z <= e0 * (1.0 + 1e-9) + 1e-9);
        }
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}
