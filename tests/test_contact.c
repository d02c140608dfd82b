/* The flight contact search (contact.c) against brute force: random flights over a
 * random rough surface (a grid, and the same surface as a mesh), for the sphere
 * touching every feature, the centre-only contact (Eq. 6-7) and the point.  Sampled against every triangle, the rock penetrates nothing
 * before the time the search returns, and touches at that time; with no contact
 * returned, it penetrates nothing until it leaves the terrain.  A cull that drops a
 * triangle it should have kept shows as a rock passing through a face. */
#include "engine/contact.h"
#include "engine/exit.h"
#include "engine/geometry.h"
#include "engine/progress.h"
#include "engine/state.h"
#include "engine/surface_law.h"
#include "motion_test_util.h"
#include "test.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum { FULL, CENTRE, POINT } mode;

static const rf_surface PLAIN = {{0.3, 0.0}, {0.4, 0.0}, {0.0, 0.0}};

#define N 16 /* nodes a side, 1 m apart */

static double node_z(int i, int j, void *ctx)
{
    return ((const double *)ctx)[j * N + i];
}

/* How far the rock is from penetrating the terrain at centre p (< 0: it penetrates):
 * the sphere's distance beyond rho from the nearest triangle; the centre's distance
 * beyond rho from the plane of face k (-1: the least over the faces under it); the
 * point's height above that face.  INFINITY off the terrain. */
static double gap(const rf_terrain *t, mode md, double rho, rf_vec3 p, int32_t k)
{
    if (md == FULL)
        return mt_terrain_distance(t, p) - rho;
    if (k < 0) {
        /* the faces under it: on the border of two columns (within the length
         * tolerance), both */
        double g = INFINITY;
        for (int dx = -1; dx <= 1; dx++)
            for (int dy = -1; dy <= 1; dy++) {
                int32_t j = rf_terrain_locate(t, p.x + 2e-10 * dx, p.y + 2e-10 * dy);
                if (j >= 0)
                    g = fmin(g, gap(t, md, rho, p, j));
            }
        return g;
    }
    const rf_triangle *T = RF_TRI(t, k);
    if (md == POINT)
        return p.z - rf_triangle_z_at(T, p.x, p.y);
    return rf_v3_dot(T->n, p) - T->d - rho;
}

/* A motion on terrain t for the contact search alone: mode md, radius rho, with its
 * own workspace (the caller frees m.ws). */
static rf_motion motion_on(const rf_terrain *t, mode md, double rho)
{
    rf_motion m;
    memset(&m, 0, sizeof m);
    m.cfg.terrain = t;
    m.ws = rf_workspace_alloc(t);
    ENSURE(m.ws != NULL);
    m.cfg.point = md == POINT;
    m.cfg.centre = md == CENTRE;
    m.cfg.rho = rho;
    m.cfg.tol_len = RF_LEN_TOL;
    return m;
}

/* Flight k (arc over [0, te]) against every triangle: nothing penetrated before the
 * contact returned, or before te when none is; touching at the contact. */
static void check_flight(rf_motion *m, const rf_arc *arc, double te, int k, int *hits,
                         int *misses)
{
    const rf_terrain *t = m->cfg.terrain;
    mode md = m->cfg.point ? POINT : m->cfg.centre ? CENTRE : FULL;
    double rho = m->cfg.rho;
    rf_contact c;
    int found = rf_contact_search(m, arc, te, NULL, &c) && c.t <= te;
    double tend = found ? c.t : te;
    *hits += found, *misses += !found;
    for (int i = 0; i < 1000; i++) {
        double ts = tend * i / 1000.0;
        double g = gap(t, md, rho, rf_arc_pos(arc, ts), -1);
        ENSURE_MSG(g >= -1e-6,
                   "mode %d, %s, flight %d from (%.9g, %.9g, %.9g) at (%.9g, %.9g, %.9g): "
                   "penetrates by %.3g at t = %.9g, before %s at %.9g",
                   md, t->is_grid ? "grid" : "mesh", k, arc->p.x, arc->p.y, arc->p.z, arc->v.x,
                   arc->v.y, arc->v.z, -g, ts,
                   found ? "the contact returned" : "leaving the terrain", tend);
    }
    if (found) {
        double g = gap(t, md, rho, rf_arc_pos(arc, c.t), c.tri);
        ENSURE_MSG(md == CENTRE ? g <= 1e-6 : fabs(g) <= 1e-6,
                   "mode %d, %s, flight %d: at the contact returned (t = %.9g) the gap is %.3g",
                   md, t->is_grid ? "grid" : "mesh", k, c.t, g);
    }
}

/* A random rough surface over N x N nodes, 1 m apart (a grid, or a mesh). */
static void rough_terrain(rf_terrain *t, double *z, gsl_rng *rng, int mesh)
{
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            z[j * N + i] = 12.0 - 0.7 * i + 0.15 * j + 1.5 * gsl_rng_uniform(rng);
    mt_grid_terrain(t, mesh, N, N, 1.0, node_z, z, PLAIN);
    ENSURE(t->is_grid == !mesh && t->ntri == 2 * (N - 1) * (N - 1));
}

static void flights_against_brute_force(mode md, double rho, int nflights, int mesh)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 3 + (unsigned long)md);
    double z[N * N];
    rf_terrain t;
    rough_terrain(&t, z, rng, mesh);
    rf_motion m = motion_on(&t, md, rho);
    int hits = 0, misses = 0;
    for (int k = 0; k < nflights; k++) {
        /* a start clear of the terrain, a flight in any direction */
        rf_vec3 p;
        do {
            p.x = 2.0 + 11.0 * gsl_rng_uniform(rng);
            p.y = 2.0 + 11.0 * gsl_rng_uniform(rng);
            double zs;
            ENSURE(rf_terrain_height(&t, p.x, p.y, &zs) >= 0);
            p.z = zs + 1.5 * rho + 3.0 * gsl_rng_uniform(rng) * gsl_rng_uniform(rng);
        } while (gap(&t, md, rho, p, -1) < 0.05);
        double az = 2.0 * M_PI * gsl_rng_uniform(rng), vh = 0.3 + 12.0 * gsl_rng_uniform(rng);
        rf_arc arc = {p, rf_v3(vh * cos(az), vh * sin(az), -4.0 + 10.0 * gsl_rng_uniform(rng)),
                      rf_v3(0, 0, -RF_GRAVITY)};
        check_flight(&m, &arc, rf_terrain_exit_time(&m, &arc, 4.0), k, &hits, &misses);
    }
    /* the flights exercise both outcomes */
    ENSURE(hits > nflights / 2 && misses > 0);
    rf_workspace_free(m.ws);
    rf_terrain_free(&t);
    gsl_rng_free(rng);
}

/* Flights on the grid's own lines: along the node rows and columns, along the cells'
 * diagonals (their triangles' shared edges) and across them through the nodes (the
 * cells' corners), and from off the terrain into it.  A grid's cells are searched in
 * the order the flight's horizontal line crosses them; these lines lie on the borders
 * between cells all the way. */
static void grid_line_flights_against_brute_force(mode md, double rho, int mesh)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 11 + (unsigned long)md);
    double z[N * N];
    rf_terrain t;
    rough_terrain(&t, z, rng, mesh);
    ENSURE(!t.is_grid || (t.x0 == 0.5 && t.y0 == 0.5));
    rf_motion m = motion_on(&t, md, rho);
    int hits = 0, misses = 0;
    static const double dirs[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1},
                                      {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
    for (int k = 0; k < 160; k++) {
        const double *d = dirs[k % 8];
        int outside = k % 5 == 4;
        double vh = 0.3 + 12.0 * gsl_rng_uniform(rng), vz = -4.0 + 10.0 * gsl_rng_uniform(rng);
        /* a node (the grid's border lines too), and the centre on the vertical through it */
        double i0 = (int)(N * gsl_rng_uniform(rng)), j0 = (int)(N * gsl_rng_uniform(rng));
        rf_vec3 p = rf_v3(0.5 + i0, 0.5 + j0, 0.0); /* node (0, 0) at (0.5, 0.5) */
        if (outside) {
            /* back along the line from the node to 3 m off the terrain, high over it */
            double back = INFINITY; /* to the nearer border it heads away from, and 3 more */
            if (d[0] != 0.0)
                back = d[0] > 0 ? i0 : N - 1 - i0;
            if (d[1] != 0.0)
                back = fmin(back, d[1] > 0 ? j0 : N - 1 - j0);
            back += 3.0;
            p.x -= d[0] * back, p.y -= d[1] * back;
            /* over the border 3 m on, above the terrain's top (not below it, which would
             * enter the terrain's side) */
            vh = 6.0 + 6.0 * gsl_rng_uniform(rng);
            double tin = 3.0 * hypot(d[0], d[1]) / vh;
            p.z = 16.0 + 1.5 * rho + 2.0 * gsl_rng_uniform(rng) - vz * tin +
                  0.5 * RF_GRAVITY * tin * tin;
        } else {
            double zs;
            ENSURE(rf_terrain_height(&t, p.x, p.y, &zs) >= 0);
            p.z = zs + 1.5 * rho + 2.0 * gsl_rng_uniform(rng);
            while (gap(&t, md, rho, p, -1) < 0.05)
                p.z += 0.1;
        }
        double dl = hypot(d[0], d[1]);
        rf_arc arc = {p, rf_v3(vh * d[0] / dl, vh * d[1] / dl, vz), rf_v3(0, 0, -RF_GRAVITY)};
        check_flight(&m, &arc, outside ? 4.0 : rf_terrain_exit_time(&m, &arc, 4.0), k,
                     &hits, &misses);
    }
    ENSURE(hits > 40 && misses > 0);
    rf_workspace_free(m.ws);
    rf_terrain_free(&t);
    gsl_rng_free(rng);
}

TEST(contact_flight_search_full_sphere_matches_brute_force)
{
    for (int mesh = 0; mesh < 2; mesh++) {
        flights_against_brute_force(FULL, 0.74, 60, mesh);
        flights_against_brute_force(FULL, 2.1, 30, mesh); /* a rock twice the cell */
    }
}

TEST(contact_flight_search_centre_matches_brute_force)
{
    for (int mesh = 0; mesh < 2; mesh++)
        flights_against_brute_force(CENTRE, 0.74, 300, mesh);
}

TEST(contact_flight_search_point_matches_brute_force)
{
    for (int mesh = 0; mesh < 2; mesh++)
        flights_against_brute_force(POINT, 0.0, 300, mesh);
}

TEST(contact_flight_search_on_the_grid_lines_matches_brute_force)
{
    for (int mesh = 0; mesh < 2; mesh++) {
        grid_line_flights_against_brute_force(FULL, 0.74, mesh);
        grid_line_flights_against_brute_force(CENTRE, 0.74, mesh);
        grid_line_flights_against_brute_force(POINT, 0.0, mesh);
    }
}

/* A cliff rising 10 m over 1 m to the terrain's top (nodes i = 0, 1, 2 a metre apart). */
static double cliff_z(int i, int j, void *ctx)
{
    (void)j, (void)ctx;
    return i == 2 ? 10.0 : 0.0;
}

/* Centre mode meets a face r / n.z above its plane, vertically: over the top of a
 * cliff that is far more than r above the terrain's highest point.  A short piece
 * falling onto the cliff there (as a fixed step's is) is met at the offset plane; it
 * was culled as higher than the reach above the top, and a rock lifted onto a cliff's
 * plane at the top fell through the terrain from there. */
TEST(contact_centre_meets_a_cliff_above_the_terrain_top)
{
    rf_terrain t;
    mt_grid_terrain(&t, 0, 3, 3, 1.0, cliff_z, NULL, PLAIN);
    rf_motion m = motion_on(&t, CENTRE, 0.5);
    double x = t.x0 + 1.9, y = t.y0 + 0.5; /* 0.1 m from the top, over the cliff */
    int32_t k = rf_terrain_locate(&t, x, y);
    ENSURE(k >= 0 && t.zmax == 10.0);
    const rf_triangle *T = RF_TRI(&t, k);
    double zc = rf_triangle_z_at(T, x, y) + m.cfg.rho / T->n.z; /* the offset plane, 14.02 */
    ENSURE(zc > t.zmax + 3.0);
    /* straight down from 0.1 m above it, and a falling parabola from 0.2 m */
    rf_arc arcs[2] = {{rf_v3(x, y, zc + 0.1), rf_v3(0, 0, -1.0), rf_v3(0, 0, 0)},
                      {rf_v3(x, y, zc + 0.2), rf_v3(0, 0, 0), rf_v3(0, 0, -RF_GRAVITY)}};
    for (int a = 0; a < 2; a++) {
        rf_contact c;
        ENSURE_MSG(rf_contact_search(&m, &arcs[a], 0.3, NULL, &c), "arc %d: not met", a);
        ENSURE(c.tri == k && c.kind == RF_FEAT_FACE);
        ENSURE_MSG(fabs(rf_arc_pos(&arcs[a], c.t).z - zc) < 1e-9, "arc %d: met %.3g m off the plane", a,
                   rf_arc_pos(&arcs[a], c.t).z - zc);
    }
    rf_workspace_free(m.ws);
    rf_terrain_free(&t);
}

/* At a node of a mesh, where six columns meet, the column whose offset plane is the
 * highest there (the one a rescue lifts a centre onto) is found: every plane passes
 * through the node, so it is the steepest face's, r / n.z above it. */
TEST(contact_centre_at_a_node_takes_the_highest_column)
{
    double z[N * N];
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            z[j * N + i] = 0.3 * (i * 7 % 5) + 0.8 * (j * 3 % 4);
    char *txt = mt_grid_stl_text(N, N, 1.0, 0.0, 0.0, 0, node_z, z);
    rf_terrain t;
    mt_mesh_text(&t, "nodes.stl", txt, PLAIN);
    free(txt);
    rf_motion m = motion_on(&t, CENTRE, 0.5);
    for (int node = 0; node < 3; node++) {
        int i = 4 + node, j = 6 + 2 * node;
        m.rock.s.p = rf_v3(i, j, z[j * N + i] + 0.5);
        int32_t steepest = -1, got = rf_highest_column(&m, rf_terrain_locate(&t, i, j));
        int got_at = 0;
        for (size_t k = 0; k < t.ntri; k++) {
            const rf_triangle *T = RF_TRI(&t, k);
            int at = 0;
            for (int v = 0; v < 3; v++)
                at |= rf_tri_vertex(T, v).x == i && rf_tri_vertex(T, v).y == j;
            if (at && (steepest < 0 || T->n.z < RF_TRI(&t, steepest)->n.z))
                steepest = (int32_t)k;
            got_at |= at && (int32_t)k == got;
        }
        /* one of the steepest (several can be as steep) */
        ENSURE(steepest >= 0 && got >= 0 && got_at);
        ENSURE_MSG(RF_TRI(&t, got)->n.z == RF_TRI(&t, steepest)->n.z, "node %d: n.z %.17g, the steepest %.17g",
                   node, RF_TRI(&t, got)->n.z, RF_TRI(&t, steepest)->n.z);
    }
    rf_workspace_free(m.ws);
    rf_terrain_free(&t);
}

/* A sphere set into a crease lies exactly r above both faces, at the nearest such
 * point, even where the faces are nearly parallel (a shallow fold, 1 degree). */
TEST(contact_crease_centre_on_both_offset_planes)
{
    const double rho = 0.5;
    for (int k = 0; k < 3; k++) {
        double half = (k == 0 ? 0.5 : k == 1 ? 20.0 : 70.0) * M_PI / 180.0;
        rf_triangle A, B;
        memset(&A, 0, sizeof A);
        memset(&B, 0, sizeof B);
        /* a valley along y: A rises to -x, B to +x, their line at x = 0, z = 2 */
        A.n = rf_v3(sin(half), 0.0, cos(half));
        B.n = rf_v3(-sin(half), 0.0, cos(half));
        A.d = rf_v3_dot(A.n, rf_v3(0, 0, 2));
        B.d = rf_v3_dot(B.n, rf_v3(0, 0, 2));
        rf_vec3 p = rf_v3(0.03, 1.0, 2.0 + rho / cos(half) - 0.02);
        rf_vec3 c = rf_crease_centre(&A, &B, rho, p);
        ENSURE_MSG(fabs(rf_v3_dot(A.n, c) - A.d - rho) < 1e-12, "fold %d: off A by %g", k,
                   rf_v3_dot(A.n, c) - A.d - rho);
        ENSURE_MSG(fabs(rf_v3_dot(B.n, c) - B.d - rho) < 1e-12, "fold %d: off B by %g", k,
                   rf_v3_dot(B.n, c) - B.d - rho);
        /* the nearest: moved across the line only (y kept), onto its centre line */
        ENSURE(c.y == p.y);
        ENSURE(fabs(c.x) < 1e-12);
        ENSURE_REL(c.z, 2.0 + rho / cos(half), 1e-12);
    }
}
