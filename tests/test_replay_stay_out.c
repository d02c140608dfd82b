/* test_replay_stay_out.c - hard cases that pin the terrain's surface as a hard one: a
 * full-contact sphere never comes nearer to it than 0.99 r, whether it is big against
 * the cells, started overlapping the terrain, or one of the replays that sank into it. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

/* ---- a rock twice the cell size against a step ---------------------------------------- */

static double step_z(int i, int j, void *ctx)
{
    (void)j;
    (void)ctx;
    /* 0.5 m cells sloping down in +x, a 0.6 m step up at x = 10 m, then level */
    double x = 0.5 * i;
    return x < 10.0 ? 4.0 - 0.3 * x : 1.6;
}

TEST(hard_big_rock_against_step_no_penetration)
{
    char *txt = mt_grid_text(61, 21, 0.5, 0.0, 0.0, step_z, NULL);
    rf_terrain t;
    mt_dem_text(&t, "step.asc", txt, ROCKY);
    free(txt);
    double mass = 4.0 / 3.0 * PI * 1.0 * 2650.0; /* r = 1 m, twice the cell */
    rf_body b = rf_body_make(mass, 2650.0, RF_MODEL_SPHERE);
    ENSURE_REL(b.radius, 1.0, 1e-12);
    for (int k = 0; k < 12; k++) {
        double y = 3.0 + 0.37 * k, vx = 1.0 + 1.5 * k;
        rf_state s = mt_state(rf_v3(2.0, y, 4.0 - 0.6 + 1.2), rf_v3(vx, 0.3 * (k % 3) - 0.3, 0));
        mt_run r;
        mt_simulate_t(&t, RF_MODEL_SPHERE, mass, RF_CONTACT_FULL, &s, 100 + k, 60.0, &r);
        ensure_sane(&r, 60.0);
        for (size_t i = 0; i < r.npoints; i++) {
            double d = mt_terrain_distance(&t, r.points[i].p);
            ENSURE_MSG(d >= 0.99, "run %d point %zu: distance %.6g", k, i, d);
        }
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* A full-contact sphere of the replay never comes closer to the terrain than 0.99 r at
 * a path point after its start, gains no energy at an impact and does not end under
 * the terrain. */
static void replay_sphere_stays_out(unsigned long seed, long it, long k)
{
    replay rp;
    replay_scene(seed, it, k, 0, &rp);
    ENSURE(rp.sim.model == RF_MODEL_SPHERE && rp.sim.contact == RF_CONTACT_FULL);
    mt_run r;
    replay_run(&rp, 0.0, &r);
    double worst = INFINITY; /* the smallest distance of a path point after the first */
    for (size_t i = 1; i < r.npoints; i++)
        worst = fmin(worst, mt_terrain_distance(&rp.t, r.points[i].p) / rp.b.radius);
    ENSURE_MSG(worst >= 0.99, "scene %lu/%ld/%ld: penetrates to %.3f r", seed, it, k, worst);
    replay_finish(&rp, &r, seed, it, k);
}

/* Full-contact spheres that went into the terrain; each now stays out. */
TEST(hard_replay_spheres_stay_out)
{
    REPLAY_EACH(replay_sphere_stays_out,
        /* in a crease, a face whose vertices each lie below one or the other of the
         * crease's planes but which rises above both between them (sank to 0.06 r) */
        {2, 8, 85},
        /* leaving a face over an edge it shares with a ridge: the edge has one end on
         * the support and the other on the face just left, and the sphere touches it
         * tangentially and curves into it (sank to 0.22 r) */
        {2, 12, 45},
        /* a hop off a vertex at a hair of a mm/s back onto the face it was on, rising
         * less than the length tolerance above its plane (fell through, to 0.48 r) */
        {1, 13, 175},
        /* flying off a face and coming down on its edge on the grid's border, which no
         * other triangle holds (passed through that edge) */
        {2, 21, 215},
        /* a crease whose one face ends at the terrain's edge: on on the other face (it
         * flew off with both faces left out, and came down through the other one) */
        {8, 10, 150},
        /* a 1 kg sphere in a concave corner of its support and a steep face, its
         * contact point 2e-8 m across their common edge (sank to 0.08 r) */
        {4, 43, 50},
        /* spheres leaving a pocket already a hair within reach of an edge (below what
         * a path point shows) and going deeper: a 12 t sphere sank to 0.11 r, a 98 t
         * one to 0.47 r, an 8 t one to 0.36 r */
        {6, 12, 105},
        {5, 23, 245},
        {1, 31, 120},
        /* a 9 t sphere sliding out of a pocket, touching an edge and rising less than
         * the tolerance from it before it falls into it at a clear approach speed
         * (sank to 0.05 r) */
        {3, 18, 135},
        /* a flight leaving a face over an edge it touches tangentially, the path then
         * dipping into that edge: the entry follows a rise smaller than the tolerance
         * at a slow approach, but goes on deeper than the touch band (sank to 0.12 r
         * and to 0.06 r) */
        {3, 35, 290},
        {10, 3, 225},
        /* already within reach of a face's plane beyond the touch band (left so by a
         * rebound in a corner), its contact point on the face, and going deeper: met
         * at once (sank to 0.24 r) */
        {5, 26, 40},
        /* sliding down one wall of a narrow gully, touching a ridge of the other wall
         * at the start: the step's event locator took the touch for a near miss and
         * dropped the face met later in the same step with it (sank to the centre) */
        {10, 46, 40},
        /* resting in a corner of three faces, hopping off the edge of the third ever
         * more gently: the last hop, from a hair inside the other two faces' planes,
         * never cleared them, and the flight fell 0.37 r through them unseen */
        {14, 11, 140},
        /* an 80 t sphere hopping on an edge, each hop smaller, until the rise of one
         * stays within the tolerance: it then fell 13 mm into the edge unseen (0.99 r),
         * the path never having been clear of it */
        {10, 26, 130},
        /* rolling out of a crease of two faces of different cells when the contact
         * point leaves one of them over its edge: on the other face, a segment of half
         * a second with the face left out of the search altogether, and the sphere
         * curved back through that face's edge (sank to 0.46 r) */
        {12, 56, 195},
        /* an 18 kg sphere on a face whose step's parabola touched an edge of the face
         * just left at the start, tangent and curving in, which the path itself does
         * not: the step was taken whole, and with it a face the search had found later
         * in it (sank to 0.035 r) */
        {28, 59, 215},
        /* touching an edge with the path tangent to it up to second order, curving in
         * by its cubic term: a 540 kg sphere flying off over the edge it touched, and
         * into the face beyond it (sank to 0.47 r) */
        {12, 59, 51},
        /* touching an edge and moving apart from it by a few um/s, then curving in
         * hard: an 8 t sphere starting on a steep face in a pocket passed through the
         * edge, never having been clear of it (sank to 0.73 r, then fell through) */
        {43, 59, 138},
        /* a 2.8 t sphere on a face at the terrain's border, its contact point on the
         * border edge at that edge's end and moving along it: it left the face over
         * the edge, and the flight met the edge at once, curving in, but a hair before
         * its end by rounding, which was not taken; the face flown off left out, it
         * sank into it (to 0.81 r) */
        {326, 57, 174},
        /* a 10 kg sphere rolling along a sharp ridge (110 degrees between the normals),
         * a hair of a velocity across it: rolled over the ridge onto the other face,
         * whose slope sent it back at once, from side to side in no time, until it was
         * put onto the other face's plane along its normal and then over a third edge
         * (to 0.99 r).  The roll over a ridge is now paid: it stays on its face */
        {303, 7, 186});
}

/* Spheres released overlapping the terrain (their centre r above the ground point
 * under them, in a hollow or beside a rise): the start pushed them out of the nearest
 * feature only, or not at all when that was an edge or vertex, and the flight search,
 * which finds only contacts entered, let them fall through (to 35 m under the
 * ground); one, under a steep edge, was pushed along that edge's normal to below the
 * ground.  They are now raised out first. */
TEST(hard_replay_spheres_released_into_the_terrain_start_out)
{
    REPLAY_EACH(replay_sphere_stays_out, {1, 43, 95}, {2, 26, 143}, {2, 39, 96}, {3, 8, 154}, {4, 4, 178}, {96, 42, 92});
}
