/* test_replay_nodes.c - hard cases that pin rocks on vertices, edges and node lines:
 * exact hits on a pyramid's peak, its edges and grid corners, point masses falling
 * along a column's border, and measure lines lying on the grid's node lines. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

/* ---- exact hits on vertices, edges and grid corners ------------------------------------ */

static double pyramid_z(int i, int j, void *ctx)
{
    (void)ctx;
    /* a four-sided pyramid peaking at node (5, 5), 1 m cells, on a gentle slope */
    double d = fmax(abs(i - 5), abs(j - 5));
    return 6.0 - 1.2 * d + 0.1 * (10 - i);
}

TEST(hard_exact_hits_on_vertices_edges_corners)
{
    char *txt = mt_grid_text(11, 11, 1.0, 0.0, 0.0, pyramid_z, NULL);
    rf_terrain t;
    mt_dem_text(&t, "pyr.asc", txt, ROCKY);
    free(txt);
    /* drop points: the peak vertex, an edge midpoint, a cell corner, a diagonal
     * midpoint, a node on the flank */
    const double xy[][2] = {{5, 5}, {5.5, 5}, {3, 7}, {6.5, 6.5}, {2, 5}, {7, 3.5}};
    for (int model = 0; model < 2; model++) {
        for (int contact = 0; contact < 2; contact++) {
            for (size_t k = 0; k < sizeof xy / sizeof *xy; k++) {
                rf_rock_model md = model ? RF_MODEL_POINT : RF_MODEL_SPHERE;
                rf_state s = mt_state(rf_v3(xy[k][0], xy[k][1], 12.0), rf_v3(0, 0, 0));
                mt_run r;
                mt_simulate_t(&t, md, 300.0, contact ? RF_CONTACT_CENTRE : RF_CONTACT_FULL, &s,
                              11 + k, 60.0, &r);
                ensure_sane(&r, 60.0);
                ENSURE(r.rec.n_impacts >= 1);
                ENSURE(r.npoints < 5000);
                if (!model && !contact) {
                    rf_body b = rf_body_make(300.0, 2650.0, md);
                    for (size_t i = 0; i < r.npoints; i++) {
                        double d = mt_terrain_distance(&t, r.points[i].p);
                        ENSURE_MSG(d >= 0.99 * b.radius, "point %zu: distance %.6g r %.6g", i, d,
                                   b.radius);
                    }
                }
                mt_run_free(&r);
            }
        }
    }
    rf_terrain_free(&t);
}

/* Point masses creeping at a grid node in a pit, hopping off one face and falling along
 * a column's border a hair under a steep face's plane: that face was tested as a
 * sphere's, at one time from the start of the window the flight's gathering gave it,
 * where the point, projected along the normal, lay just outside it.  They fell through
 * the terrain (by up to 60 m).  A point mass now meets the face under it over the exact
 * window of its column, as in centre contact, and rests. */
TEST(hard_replay_point_masses_along_a_column_border_rest)
{
    REPLAY_EACH(replay_point_rests, {10, 46, 210}, {20, 50, 65}, {29, 3, 55}, {61, 2, 103},
                {94, 45, 298});
}

/* ---- measure lines on the grid's node lines --------------------------------------- */

/* A replay with a control line across the slope on every third node line of the grid:
 * a crossing at the moment of an impact that takes energy (within 1e-9 s) records no
 * less than the impact starts from (more when the lift onto the column's offset plane
 * was paid first).  The centre meets a column's face a hair before the column's edge,
 * where the line is: these crossings were recorded after the impact, 1e-10 s later,
 * with what it left (222.98 kJ in 1/1/12, where the rock arrived with 226.07). */
static void replay_lines_see_the_rock_before_impacts(unsigned long seed, long it, long k)
{
    replay rp;
    replay_pick(seed, it, k, RF_MODEL_SPHERE, &rp);
    ENSURE(rp.t.is_grid);
    rp.sim.contact = RF_CONTACT_CENTRE;
    double xy[40][4];
    rf_measure ms[40];
    size_t nms = 0;
    for (double x = rp.t.x0 + 3 * rp.t.cell; x < rp.t.xmax - rp.t.cell && nms < 40; x += 3 * rp.t.cell) {
        double *q = xy[nms];
        q[0] = q[2] = rp.t.x0 + round((x - rp.t.x0) / rp.t.cell) * rp.t.cell;
        q[1] = rp.t.ymin - 5.0, q[3] = rp.t.ymax + 5.0;
        ms[nms++] = mt_measure(RF_CONTROL, RF_COLLECT, q, 2, 0.0, 0.0);
    }
    mt_scene_run *lr = malloc(sizeof *lr);
    ENSURE(lr != NULL);
    mt_run_scene(&rp.t, &rp.sim, &rp.b, ms, nms, &rp.s, rp.seed, lr);
    int met = 0;
    for (int i = 0; i < lr->n; i++) {
        const rf_interception_record *c = &lr->icpt[i];
        ENSURE_SMALL(c->p.x - xy[c->measure][0], 1e-8);
        for (size_t j = 0; j < lr->nimp; j++) {
            if (fabs(lr->imp_t[j] - c->t_s) > 1e-9 || !(lr->imp_e1[j] < lr->imp_e0[j] * (1.0 - 1e-6)))
                continue;
            met++;
            ENSURE_MSG(c->energy_kj >= lr->imp_e0[j] * (1.0 - 1e-9),
                       "%lu/%ld/%ld: %.9g kJ at line %d, an impact at %.15g s: %.9g -> %.9g kJ", seed, it,
                       k, c->energy_kj, c->measure, lr->imp_t[j], lr->imp_e0[j], lr->imp_e1[j]);
            break;
        }
    }
    ENSURE_MSG(met > 0, "%lu/%ld/%ld: no crossing at an impact", seed, it, k);
    free(lr);
    rf_terrain_free(&rp.t);
}

TEST(hard_replay_centre_contact_lines_on_node_lines_see_the_rock_before_impacts)
{
    REPLAY_EACH(replay_lines_see_the_rock_before_impacts, {1, 1, 12}, {1, 1, 16}, {1, 2, 5});
}
