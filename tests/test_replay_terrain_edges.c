/* test_replay_terrain_edges.c - hard cases that pin where the terrain ends: nodata
 * holes in a grid, holes, cracks and outlines of meshes, and a real mesh of three files;
 * a rock leaves the terrain where its centre comes over no ground, and only there. */
#include "test.h"

#include <stdlib.h>
#include <string.h>

#include "motion_test_util.h"
#include "replay_test_util.h"

/* 21 x 11 nodes at spacing c = *ctx, a plane falling at 0.8 along x, nodata nodes i in
 * 10..12, j in 4..6 (holes: the cells x in [9.5, 13.5] c, y in [3.5, 7.5] c). */
static double holed_z(int i, int j, void *ctx)
{
    if (i >= 10 && i <= 12 && j >= 4 && j <= 6)
        return -9999.0;
    return *(const double *)ctx * (20.0 - 0.8 * i);
}

/* The 50 kg rock of model md: its contact radius. */
static double rock50_rho(rf_rock_model md)
{
    rf_body b = rf_body_make(50.0, 2650.0, md);
    return rf_body_contact_radius(&b);
}

/* One 50 kg rock from s on terrain t: model, contact, engine; sane, and it leaves the
 * terrain. */
static void rock50_exits(const rf_terrain *t, rf_rock_model md, rf_contact_kind ck, int fixed,
                         const rf_state *s, mt_run *r)
{
    rf_simulation sim = mt_sim(md, ck, 300.0);
    if (fixed)
        sim.engine = RF_ENGINE_FIXED_STEP;
    rf_body b = rf_body_make(50.0, 2650.0, md);
    mt_simulate_opts(t, &sim, &b, s, 9, 0.0, r);
    ensure_sane(r, 300);
    ENSURE(r->rec.reason == RF_END_EXITED);
}

/* The rock's way into the hole (rolling, and thrown over its rim), beside it off the
 * lower edge, and sideways off the terrain, on the grid or the same surface as a mesh
 * of spacing c, for each rock model, contact and engine (the fixed step once: it tests
 * contact as the paper does whatever the contact option). */
static void holes_and_edges(const rf_terrain *t, double c)
{
    for (int run = 0; run < 4; run++) {
        rf_rock_model md = run == 3 ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_contact_kind ck = run == 1 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL;
        int fixed = run == 2;
        double rho = rock50_rho(md);
        /* down the fall line into the hole: it ends where its centre comes over it,
         * above the ground at the rim (z = c (20.4 - 0.8 x / c)) */
        double z;
        ENSURE(rf_terrain_height(t, 2.0 * c, 5.0 * c, &z) >= 0);
        rf_state s = mt_state(rf_v3(2.0 * c, 5.0 * c, z + rho + 0.01), rf_v3(0, 0, 0));
        mt_run r;
        rock50_exits(t, md, ck, fixed, &s, &r);
        ENSURE(rf_terrain_locate(t, r.rec.stop.x + 1e-6 * c, r.rec.stop.y) < 0);
        ENSURE(r.rec.stop.x > 9.5 * c - 1e-9 * c && r.rec.stop.x < 9.5 * c + 2.0 * rho + 1e-6);
        ENSURE(r.rec.stop.z > c * (20.4 - 0.8 * 9.5) - 1e-6 * c);
        mt_run_free(&r);
        /* thrown over the rim (from 1 m up, 5 m/s): it ends at the rim, in flight where
         * the spacing is 1 m (on the coarser grid it may land first) */
        ENSURE(rf_terrain_height(t, 9.0 * c, 5.3 * c, &z) >= 0);
        s = mt_state(rf_v3(9.0 * c, 5.3 * c, z + rho + 1.0), rf_v3(5.0, 0.1, 0.0));
        rock50_exits(t, md, ck, fixed, &s, &r);
        ENSURE_SMALL(r.rec.stop.x - 9.5 * c, 1e-6 * c);
        ENSURE(r.rec.n_impacts == 0 || c > 1.0);
        mt_run_free(&r);
        /* beside the hole, off the lower edge (x = 20.5 c) */
        ENSURE(rf_terrain_height(t, 2.0 * c, 1.5 * c, &z) >= 0);
        s = mt_state(rf_v3(2.0 * c, 1.5 * c, z + rho + 0.01), rf_v3(0, 0, 0));
        rock50_exits(t, md, ck, fixed, &s, &r);
        ENSURE(r.rec.stop.x >= 20.5 * c - 1e-9 * c || r.rec.stop.z < t->zmin);
        mt_run_free(&r);
        /* thrown sideways off the terrain */
        s = mt_state(rf_v3(5.0 * c, 8.0 * c, 30.0 * c), rf_v3(0, 6.0, 0));
        rock50_exits(t, md, ck, fixed, &s, &r);
        ENSURE_SMALL(r.rec.stop.y - 10.5 * c, 1e-9 * c);
        mt_run_free(&r);
    }
}

/* holes_and_edges on the grid with its nodata hole, or on the same surface as a mesh
 * with the hole left open (the ESRI grid's nodes are at its cells' centres), with cells
 * of 1 m and of 10 m (a point a hair past a 10 m cell's border is on it still, within
 * the locator's tolerance: the hole was missed). */
static void holed_terrain(int mesh)
{
    for (int k = 0; k < 2; k++) {
        double c = k ? 10.0 : 1.0;
        rf_terrain t;
        mt_grid_terrain(&t, mesh, 21, 11, c, holed_z, &c,
                        (rf_surface){{0.2, 0.0}, {0.1, 0.0}, {0.05, 0.0}});
        holes_and_edges(&t, c);
        rf_terrain_free(&t);
    }
}

TEST(hard_nodata_holes_and_terrain_edges)
{
    holed_terrain(0);
}

/* A hole in a mesh ends the trajectory where the centre comes over it, as a grid's
 * nodata does (the rock fell through it until it was below every face). */
TEST(hard_mesh_holes_and_terrain_edges)
{
    holed_terrain(1);
}

/* A mesh of two tiles of one plane falling along x, a crack between them (0.8 cm, under
 * a hundredth of the 1 m cells; 5 cm, under the radius of the 50 kg sphere).  A sphere in
 * full contact bridges either, rolling or thrown over it, and leaves the terrain at its
 * lower edge; any rock thrown over the narrow one does so too, in either engine (a gap
 * is one the centre is over that far on).  (Not tested here: a point mass or a centre
 * sliding into a crack leaves the terrain there, as the surface phase looks for the
 * next face within 0.1 mm.) */
TEST(hard_mesh_crack_between_tiles_is_bridged)
{
    const double cracks[2] = {0.008, 0.05};
    for (int w = 0; w < 2; w++) {
        rf_vec3 P[2 * 11 * 11];
        int tri[2 * 2 * 10 * 10][3];
        size_t nt = 0;
        for (int tile = 0; tile < 2; tile++) {
            int o = tile * 121;
            for (int j = 0; j < 11; j++)
                for (int i = 0; i < 11; i++) {
                    double x = 0.5 + i + tile * (10.0 + cracks[w]);
                    P[o + j * 11 + i] = rf_v3(x, 0.5 + j, 20.0 - 0.8 * x);
                }
            for (int j = 0; j < 10; j++)
                for (int i = 0; i < 10; i++) {
                    int a = o + j * 11 + i;
                    int t2[2][3] = {{a, a + 1, a + 12}, {a, a + 12, a + 11}};
                    memcpy(tri[nt++], t2[0], sizeof t2[0]);
                    memcpy(tri[nt++], t2[1], sizeof t2[1]);
                }
        }
        char *txt = mt_stl_text(P, (const int(*)[3])tri, nt);
        rf_terrain t;
        mt_mesh_text(&t, "tiles.stl", txt, (rf_surface){{0.2, 0.0}, {0.1, 0.0}, {0.05, 0.0}});
        free(txt);
        double xend = 20.5 + cracks[w];
        /* run 0, 1: a full-contact sphere rolling and thrown; 2-4 (the narrow crack),
         * thrown: a point mass, a centre, and the fixed step */
        for (int run = 0; run < (w ? 2 : 5); run++) {
            rf_rock_model md = run == 2 ? RF_MODEL_POINT : RF_MODEL_SPHERE;
            rf_contact_kind ck = run == 3 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL;
            double rho = rock50_rho(md), z, x0 = run ? 8.0 : 2.0;
            ENSURE(rf_terrain_height(&t, x0, 5.0, &z) >= 0);
            rf_state s = mt_state(rf_v3(x0, 5.0, z + rho + (run ? 1.0 : 0.01)),
                                  rf_v3(run ? 5.0 : 0.0, 0, 0));
            mt_run r;
            rock50_exits(&t, md, ck, run == 4, &s, &r);
            ENSURE_MSG(r.rec.stop.x >= xend - 1e-9, "crack %g, run %d: ends at x = %.6f", cracks[w],
                       run, r.rec.stop.x);
            mt_run_free(&r);
        }
        rf_terrain_free(&t);
    }
}

/* An L-shaped mesh (a plane falling along x, its quarter x > 5, y > 5 cut out), with
 * and without a vertical skirt hanging from the cut: a rock thrown across the cut
 * leaves the terrain there, not at the bounding box (the rim, held by the ground and
 * the skirt, is a border in plan). */
TEST(hard_mesh_outline_with_a_skirt)
{
    for (int skirt = 0; skirt < 2; skirt++) {
        rf_vec3 P[11];
        const double xy[8][2] = {{0, 0}, {5, 0}, {10, 0}, {0, 5}, {5, 5}, {10, 5}, {0, 10}, {5, 10}};
        for (int k = 0; k < 8; k++)
            P[k] = rf_v3(xy[k][0], xy[k][1], 10.0 - 0.5 * xy[k][0]);
        P[8] = rf_v3(5, 5, -5), P[9] = rf_v3(10, 5, -5), P[10] = rf_v3(5, 10, -5);
        const int tri[10][3] = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {3, 4, 7},
                                {3, 7, 6}, {4, 5, 9}, {4, 9, 8}, {4, 7, 10}, {4, 10, 8}};
        char *txt = mt_stl_text(P, tri, skirt ? 10 : 6);
        rf_terrain t;
        mt_mesh_text(&t, "l.stl", txt, (rf_surface){{0.2, 0.0}, {0.1, 0.0}, {0.05, 0.0}});
        free(txt);
        for (int model = 0; model < 2; model++) {
            rf_state s = mt_state(rf_v3(1.0, 7.5, 11.5), rf_v3(6.0, 0.0, 0.0));
            mt_run r;
            rock50_exits(&t, model ? RF_MODEL_POINT : RF_MODEL_SPHERE, RF_CONTACT_FULL, 0, &s,
                         &r);
            ENSURE_SMALL(r.rec.stop.x - 5.0, 1e-9);
            mt_run_free(&r);
        }
        rf_terrain_free(&t);
    }
}

/* How many of 8 points round (x, y) at distance d have terrain under them. */
static int terrain_round(const rf_terrain *t, double x, double y, double d)
{
    int n = 0;
    for (int k = 0; k < 8; k++) {
        double a = k * 0.25 * M_PI, z;
        n += rf_terrain_height(t, x + d * cos(a), y + d * sin(a), &z) >= 0;
    }
    return n;
}

/* A real terrain: the Authume quarry's mesh (../shared/validation/authume), three STL
 * files of about 0.5 m triangles in a y-up frame, one zone each, with vertical rock
 * walls and flat benches, and an outline that is not its bounding box.  Rocks of 300 to
 * 1 800 kg dropped from the shovel on both profiles, in every rock model, contact and
 * engine: sane, each rests or leaves the mesh at its outline (where ground is on one
 * side only; without the outline's gaps they left at the bounding box), none under the
 * ground, and the first four full-contact spheres of each drop in the exact engine
 * never nearer the terrain than 0.99 r (without edge contacts, 0.57 r). */
TEST(hard_real_mesh_of_three_files_all_engines)
{
    char paths[3][4096], *files[3];
    rf_test_authume_files(paths, files);
    /* hard ground (Gray) bouncier than the slopes */
    rf_zone_spec zones[1] = {{.name = (char *)"gray", .file = paths[1],
                              .surface = {{0.4, 0.05}, {0.5, 0.1}, {0.3, 0.02}}}};
    rf_terrain_spec spec = {.source = RF_TERRAIN_MESH, .files = files, .nfiles = 3, .up = 'y',
                            .surface = {{0.25, 0.05}, {0.5, 0.1}, {0.3, 0.02}},
                            .zones = zones, .nzones = 1};
    rf_terrain t;
    rf_error err;
    memset(&err, 0, sizeof err);
    ENSURE_MSG(rf_terrain_build(&spec, &t, &err) == 0, "%s", err.message);
    /* the drop zones' centres (file x, z) and the shovel's height (file y) */
    const double drop[2][3] = {{0.32, 370.4, 211.75}, {-1.83, 289.85, 209.48}};
    const double mass[4] = {300.0, 700.0, 1200.0, 1800.0};
    long rest = 0, exited = 0;
    for (int mode = 0; mode < 5; mode++) {
        rf_rock_model md = mode == 2 || mode == 4 ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_simulation sim = mt_sim(md, mode == 1 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL, 300.0);
        if (mode >= 3)
            sim.engine = RF_ENGINE_FIXED_STEP, sim.dt = 0.002;
        for (int p = 0; p < 2; p++)
            for (int k = 0; k < 8; k++) {
                rf_body b = rf_body_make(mass[k % 4], 2650.0, md);
                double rho = rf_body_contact_radius(&b);
                rf_state s = mt_state(rf_v3(drop[p][0] - 1.5 + k % 4, drop[p][1] - 1.0 + k / 4,
                                            drop[p][2]),
                                      rf_v3(0.5 * (k % 3), 0.2 * (k % 2), 0.0));
                mt_run r;
                mt_simulate_opts(&t, &sim, &b, &s, 100 * (unsigned long)mode + 10 * p + k, 0.0, &r);
                ensure_sane(&r, 300);
                ENSURE(r.rec.reason == RF_END_REST || r.rec.reason == RF_END_EXITED);
                rest += r.rec.reason == RF_END_REST;
                exited += r.rec.reason == RF_END_EXITED;
                double x = r.rec.stop.x, y = r.rec.stop.y, z;
                ENSURE_MSG(r.rec.reason == RF_END_REST ||
                               (terrain_round(&t, x, y, 1.0) < 8 && terrain_round(&t, x, y, 0.1) > 0),
                           "mode %d, drop %d, rock %d left the terrain at (%.3f, %.3f), not at "
                           "its outline", mode, p, k, x, y);
                if (rf_terrain_height(&t, x, y, &z) >= 0)
                    ENSURE_MSG(r.rec.stop.z > z - 1e-6, "mode %d, drop %d, rock %d ends %.3g m "
                               "under the ground", mode, p, k, z - r.rec.stop.z);
                if (mode == 0 && k < 4)
                    for (size_t i = 1; i < r.npoints; i++)
                        ENSURE_MSG(mt_terrain_distance(&t, r.points[i].p) > 0.99 * rho,
                                   "drop %d, rock %d, point %zu: %.4f r from the terrain", p, k,
                                   i, mt_terrain_distance(&t, r.points[i].p) / rho);
                mt_run_free(&r);
            }
    }
    /* both ends are taken (benches hold some rocks, others run off the quarry's end) */
    ENSURE_MSG(rest > 10 && exited > 10, "rest %ld, exited %ld", rest, exited);
    rf_terrain_free(&t);
}
