/* test_replay_walls.c - hard cases that pin walls: near-vertical faces, and centre
 * contact (Eq. 6-7) among the columns of faces whose offset planes rise above the
 * centre - a rock meets them, is reflected off them, slides along them and is never
 * lifted onto them for nothing nor lets through into a column under its plane. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

TEST(hard_near_vertical_faces)
{
    const double angles[] = {85.0, 87.5, 89.0, 89.9};
    for (size_t a = 0; a < 4; a++) {
        double w = 20.0 / tan(angles[a] * PI / 180.0);
        /* level ground, a wall rising 20 m at the given angle, a level top */
        double prof[8] = {0.0, 0.0, 30.0, 0.0, 30.0 + w, 20.0, 60.0 + w, 20.0};
        rf_terrain t;
        mt_profile(&t, prof, 4, 40.0, ROCKY);
        for (int model = 0; model < 2; model++) {
            rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
            rf_body b = rf_body_make(800.0, 2650.0, md);
            double rho = rf_body_contact_radius(&b);
            /* thrown against the wall */
            rf_state s = mt_state(rf_v3(10.0, 20.0, 3.0 + rho), rf_v3(15.0, 1.0, 4.0));
            mt_run r;
            mt_simulate_t(&t, md, 800.0, RF_CONTACT_FULL, &s, 5, 60.0, &r);
            ensure_sane(&r, 60.0);
            ENSURE(r.rec.stop.x <= 30.0 + w + 1e-6); /* never through the wall */
            if (!model)
                for (size_t i = 0; i < r.npoints; i++)
                    ENSURE(mt_terrain_distance(&t, r.points[i].p) >= 0.99 * rho);
            mt_run_free(&r);
            /* rolling off the top and down the wall */
            s = mt_state(rf_v3(32.0 + w, 20.0, 20.0 + rho), rf_v3(-6.0, 0.5, 0.0));
            mt_simulate_t(&t, md, 800.0, RF_CONTACT_FULL, &s, 6, 60.0, &r);
            ensure_sane(&r, 60.0);
            ENSURE(r.rec.stop.z < 20.0);
            mt_run_free(&r);
        }
        rf_terrain_free(&t);
    }
}

/* The paper's centre-only contact meets a face when the centre is r / cos(theta) above
 * its plane - more than r above the vertices of a small steep face.  A rock dropped on
 * an 80 degree slope of 1 m cells lands exactly there and does not fall through. */
TEST(hard_centre_contact_on_steep_small_faces)
{
    const double theta = 80.0 * M_PI / 180.0;
    char text[8192];
    int n = snprintf(text, sizeof text,
                     "ncols 11\nnrows 11\nxllcenter 0\nyllcenter 0\ncellsize 1\n");
    for (int j = 0; j < 11; j++) {
        for (int i = 0; i < 11; i++)
            n += snprintf(text + n, sizeof text - (size_t)n, "%.17g ", tan(theta) * i);
        n += snprintf(text + n, sizeof text - (size_t)n, "\n");
    }
    rf_surface s = {{0.3, 0.0}, {0.3, 0.0}, {0.1, 0.0}};
    rf_terrain t;
    mt_dem_text(&t, "steep80.asc", text, s);
    rf_body b = rf_body_make(4500.0, 2650.0, RF_MODEL_SPHERE);
    const double xs[3] = {5.3, 5.85, 4.05};
    for (int k = 0; k < 3; k++) {
        double zp = tan(theta) * xs[k];
        rf_state s0 = mt_state(rf_v3(xs[k], 5.2, zp + 20.0), rf_v3(0, 0, 0));
        mt_run r;
        mt_simulate(&t, RF_MODEL_SPHERE, 4500.0, RF_CONTACT_CENTRE, &s0, 7, &r);
        const rf_path_point *imp = mt_first_impact(&r);
        ENSURE_MSG(imp != NULL, "x %.2f: no impact (%s)", xs[k], rf_stop_reason_name(r.rec.reason));
        ENSURE_REL(imp->p.x, xs[k], 1e-9);
        ENSURE_REL(imp->p.z, zp + b.radius / cos(theta), 1e-6);
        mt_run_free(&r);
    }
    rf_terrain_free(&t);
}

/* Centre contact (Eq. 6-7) counts only the face under the centre, whose offset plane
 * can lie above the centre once it moves over the next column.  One sphere, released
 * on a steep face, was put onto its offset plane along the normal, out of that face's
 * column and under the next face's offset plane; another, rebounding off a face at the
 * border of a higher column, flew into that column from its border.  Neither entry
 * into a column was seen, and both fell through the terrain (by about 10 m).  The start
 * now lifts the centre within its column, and a flight moving in over a column's
 * border at its start meets that face at once. */
TEST(hard_replay_centre_contact_stays_over_its_columns)
{
    replay_sphere_rests(1, 14, 69);
    replay_sphere_rests(1, 14, 176);
}

/* Centre contact: a slipping sphere pressed against a column wall (a face beyond the
 * column's edge whose offset plane the rock cannot pay the lift onto) left the face,
 * was reflected and turned back into it at every event, in no time, as did a sphere
 * sliding along a wall into a corner where the face ahead is a wall too; the rescue
 * then moved the centre out of its column and it fell through the terrain.  The slip
 * across the wall is now taken by friction (the spin changes, energy is lost) and the
 * sphere slides along the wall; in a corner it stops. */
TEST(hard_replay_centre_contact_slipping_along_a_wall_and_into_a_corner_rests)
{
    REPLAY_EACH(replay_sphere_rests, {1, 14, 235}, {1, 14, 91}, {9, 7, 191}); /* slipping */
    REPLAY_EACH(replay_sphere_rests, {1, 13, 236}, {1, 31, 176});             /* corner */
}

/* Centre contact: spheres on a face whose column they are moving into, their centre
 * a hair outside its edge.  The flight's search met the column at the length
 * tolerance before its edge, which rounding put beyond it for the face's surface phase
 * (52/24/178); an exit the step's parabola did not see, from a start a hair beyond the
 * edge, moving in, was not looked for (40/16/109).  Either way the exit was taken at
 * once, and the rock flew off the face it was moving into, which the flight leaves
 * out, and fell through it (by 4 to 30 m).  The search now meets a column half the
 * tolerance before its edge, and the exit is found where the path leaves the face. */
TEST(hard_replay_centre_contact_moving_into_its_face_stays_on)
{
    REPLAY_EACH(replay_centre_rests_unstalled, {40, 16, 109}, {52, 24, 178});
}

/* Centre contact: a flight that starts on a column's edge under that face's offset
 * plane, moving in over the edge but away from the plane, was not met by that face
 * and fell through it (48/57/241).  Entering a column under its offset plane is now a
 * contact whichever way the path moves relative to the plane, as later in a flight;
 * a path along the edge (27/20/149) is not entering: meeting the face at once at every
 * event, it ran out of rescues. */
TEST(hard_replay_centre_contact_flight_into_a_column_under_its_plane_meets_it)
{
    replay_centre_rests_unstalled(48, 57, 241);
    replay_sphere_rests(27, 20, 149);
}

/* Centre contact: flights from a grid node among walls (faces whose offset planes are
 * above the centre), moving in over a wall's column edge slower than RF_APPROACH_EPS,
 * which was taken as not moving into that column at all: the centre drifted a few
 * nanometres into the column unmet, came down under its offset plane and fell through
 * the terrain (10/11/78 by 12 m; 20/58/124, 24/36/4, 24/54/238 and 26/50/244, by 8 to
 * 38 m, still fell so with the mends below).  A flight starting on a column's border
 * now enters it when it moves in over an edge of the column it lies on, however
 * slowly, and out over none (at a vertex, in over one edge and out over the other is
 * not entering: 40/16/109 above was met at once at every event). */
TEST(hard_replay_centre_contact_drifting_from_a_node_into_a_wall_meets_it)
{
    REPLAY_EACH(replay_sphere_rests, {20, 58, 124}, {24, 36, 4}, {24, 54, 238}, {26, 50, 244});
}

/* Centre contact: spheres reaching a grid node along a column's border, into the corner
 * of a wall's column.  The reflection off the edge they moved in through (restitution
 * near 0) turned them along it, in over the column's other edge there, between two
 * walls and under both, where neither column counts as entered, and they fell through
 * the terrain (18/50/169 by 6 m, 46/18/212 by 24 m).  A reflection at a
 * column's corner that leaves the rock moving in over the other edge reverses the
 * whole horizontal velocity instead (times e), which leaves the corner. */
TEST(hard_replay_centre_contact_reflected_at_a_corner_of_a_wall_leaves_it)
{
    REPLAY_EACH(replay_sphere_rests, {18, 50, 169}, {46, 18, 212});
}

/* Centre contact: a sphere lifted onto a face at a vertex of its column, its centre
 * still a hair outside it, left it at once over an edge; the flight clipped the corner
 * of the next column and moved over the face's column again, coming down onto its
 * plane, but the face flown off was left out of the flight's search and the rock fell
 * through it (7.5 m, 76/2/68).  The face flown off is now met once the centre moves
 * over its column again. */
TEST(hard_replay_centre_contact_flight_back_over_the_face_flown_off_meets_it)
{
    replay_sphere_rests(76, 2, 68);
}

/* Centre contact: a sphere reflected off a wall at a grid node, where the column of a
 * second wall (its offset plane above the centre too) meets the first: the reflection
 * sent it on into the second column, which sent it back, across the line between the
 * two ever less and never back out along it, and it ran between them under both and
 * fell 45 m through the terrain (325/12/46).  A reflection that leaves the rock moving
 * into another wall's column reverses the whole horizontal velocity, as at a corner of
 * one column. */
TEST(hard_replay_centre_contact_reflected_into_a_second_wall_leaves_both)
{
    replay_sphere_rests(325, 12, 46);
}

/* Centre contact: a sphere at a grid node at the bottom of a pit, walls on two sides:
 * it slid into the node, left its face there, was reflected by the walls and landed
 * on its face again, in no time.  The rescue lifted it onto a wall's plane for nothing
 * and stopped it there, from where it fell back into the pit with that height's
 * energy, over and over until the rescues ran out (max_time at 77 s, 320/34/272).  A
 * rock wedged again where it was last wedged now rests where it is. */
TEST(hard_replay_centre_contact_wedged_in_a_pit_rests)
{
    /* as replay_sphere_rests, in one run with the stop point's check */
    replay rp;
    mt_run r;
    replay_ends_open(320, 34, 272, RF_MODEL_SPHERE, RF_END_REST, &rp, &r);
    ENSURE_MSG(r.npoints > 2, "%zu points", r.npoints);
    /* where it was wedged, not lifted onto the wall (by 0.026 m here) */
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(r.rec.stop, r.points[r.npoints - 2].p)), 1e-6);
    replay_finish(&rp, &r, 320, 34, 272);
}

/* Centre contact (the scene's full-contact sphere run in centre contact): reflected off
 * a wall at a grid node exactly along the diagonal of the next cell, whose two columns
 * are both walls.  Rounding had the centre moving out of one column across the
 * diagonal at 2e-16 of its speed, and reaching half the tolerance inside the other
 * only after 114 s: neither met it, and it fell 11.8 m through the terrain along the
 * diagonal (342/1/278).  An edge the centre moves along within the tolerance over the
 * edge's length is now crossed neither in nor out; the rock rests. */
TEST(hard_replay_centre_contact_along_a_cell_diagonal_from_a_node_meets_the_walls)
{
    replay rp;
    replay_pick(342, 1, 278, RF_MODEL_SPHERE, &rp);
    rp.sim.contact = RF_CONTACT_CENTRE;
    replay_rests(&rp, 342, 1, 278, 0);
}

/* Centre contact: spheres rolling along a wall on a face too steep for rolling (the
 * part of gravity across the wall counted): they slid, had no slip along the wall and
 * so rolled again, in no time, until the rescue moved them out of their column and
 * they fell through the terrain (14 m, 85/11/252).  Along a wall the part of gravity
 * along it decides: the sphere rolls on along it, or slides with a slip growing from
 * zero. */
TEST(hard_replay_centre_contact_rolling_along_a_wall_on_a_steep_face_rests)
{
    REPLAY_EACH(replay_centre_rests_unstalled, {85, 11, 252}, {33, 39, 211});
}

/* Centre contact: spheres wedged at a corner of columns among walls, leaving a face and
 * being put back onto it, or reflected off one wall into the next, in no time.  The
 * rescue moved them for a microsecond and pushed them out along the normal of the face
 * then under them, which left them under the next column's offset plane, and they fell
 * through the terrain (by 5 to 40 m; every one of 40 falls sampled from the random
 * scenes went this way).  The rescue now lifts the centre onto its column's offset
 * plane, paid from the kinetic energy, and stops a rock that cannot pay it; all rest. */
TEST(hard_replay_centre_contact_rescued_in_a_corner_stays_over_its_column)
{
    REPLAY_EACH(replay_sphere_rests, {24, 41, 89}, {5, 28, 45}, {55, 57, 28}, {40, 27, 237});
}

/* Centre contact: spheres rolling down a face against the border of its column, beyond
 * which a face rises that they cannot pay the lift onto.  Each event left the face
 * over that border, was reflected off it and turned back into it by the face, ever
 * more nearly along it, in no time, until the rescues ran out (18 500 to 21 400
 * events).  They now roll along that wall, and rest. */
TEST(hard_replay_centre_contact_along_a_wall_rests)
{
    REPLAY_EACH(replay_sphere_rests, {43, 52, 136}, {93, 40, 245}, {94, 3, 253});
}
