/* test_terrain.c - terrain geometry (Eq. 3-7), readers, point location, zones. */
#include "test.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/terrain.h"

#define DATA "tests/data/terrain/"
#define PI 3.14159265358979323846

static const rf_surface SURF_DEFAULT = {{0.385, 0.05}, {0.55, 0.1}, {0.12, 0.0}};
static const rf_surface SURF_OTHER = {{0.215, 0.0}, {0.71, 0.0}, {0.3, 0.0}};

static void build_ok(const rf_terrain_spec *spec, rf_terrain *t)
{
    rf_error err = {0};
    int rc = rf_terrain_build(spec, t, &err);
    ENSURE_MSG(rc == 0, "%s:%d:%d: %s", err.file, err.line, err.column, err.message);
}

static void build_dem(const char *path, rf_terrain *t)
{
    char *files[1] = {(char *)path};
    rf_terrain_spec spec = {.source = RF_TERRAIN_DEM, .files = files, .nfiles = 1, .up = 'z',
                            .surface = SURF_DEFAULT};
    build_ok(&spec, t);
}

static void build_mesh(const char *path, char up, rf_terrain *t)
{
    char *files[1] = {(char *)path};
    rf_terrain_spec spec = {.source = RF_TERRAIN_MESH, .files = files, .nfiles = 1, .up = up,
                            .surface = SURF_DEFAULT};
    build_ok(&spec, t);
}

/* A terrain of the single triangle (a, b, c), read back from an OBJ written with
 * round-trip precision, so its normal and offset come from the library. */
static void one_triangle(rf_vec3 a, rf_vec3 b, rf_vec3 c, rf_terrain *t)
{
    const char *path = rf_test_path("one.obj");
    FILE *f = fopen(path, "w");
    ENSURE(f != NULL);
    fprintf(f, "v %.17g %.17g %.17g\nv %.17g %.17g %.17g\nv %.17g %.17g %.17g\nf 1 2 3\n",
            a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z);
    fclose(f);
    build_mesh(path, 'z', t);
    ENSURE(t->ntri == 1);
}

static void ensure_plane_consistent(const rf_triangle *tri)
{
    ENSURE_SMALL(rf_v3_norm(tri->n) - 1.0, 1e-14);
    ENSURE(tri->n.z >= 0);
    double scale = 1.0 + rf_v3_norm(tri->a) + rf_v3_norm(tri->b) + rf_v3_norm(tri->c);
    ENSURE_SMALL(rf_v3_dot(tri->n, tri->a) - tri->d, 1e-14 * scale);
    ENSURE_SMALL(rf_v3_dot(tri->n, tri->b) - tri->d, 1e-14 * scale);
    ENSURE_SMALL(rf_v3_dot(tri->n, tri->c) - tri->d, 1e-14 * scale);
}

/* ---- Table 2 ----------------------------------------------------------------------- */

TEST(terrain_table2_friction)
{
    ENSURE_SMALL(rf_table2_friction('A') - 0.05, 1e-15);
    ENSURE_SMALL(rf_table2_friction('B') - 0.15, 1e-15);
    ENSURE_SMALL(rf_table2_friction('C') - 0.25, 1e-15);
    ENSURE_SMALL(rf_table2_friction('D') - 0.35, 1e-15);
    ENSURE(rf_table2_friction('E') < 0);
    ENSURE(rf_table2_friction('?') < 0);
    rf_dist d = rf_table2_friction_dist('C');
    ENSURE_SMALL(d.mean - 0.25, 1e-15);
    ENSURE_SMALL(d.sd - 0.025, 1e-15);
    ENSURE(rf_table2_friction_dist('Z').mean < 0);
}

/* ---- Eq. 3-7 on hand-computed triangles ------------------------------------------- */

/* Eq. 4a-c as the paper gives them, except 4a's denominator: the paper prints
 * (Xi - Xj)(Yj - Yk), which fails unless Yi = Yj; the plane through i, j, k needs
 * (Xi - Xj)(Yi - Yk), the negative of 4b's denominator. */
static void paper_eq4(rf_vec3 i, rf_vec3 j, rf_vec3 k, double *a, double *b, double *d)
{
    *a = ((i.z - k.z) * (i.y - j.y) - (i.z - j.z) * (i.y - k.y)) /
         ((i.x - j.x) * (i.y - k.y) - (i.x - k.x) * (i.y - j.y));
    *b = ((i.z - k.z) * (i.x - j.x) - (i.z - j.z) * (i.x - k.x)) /
         ((i.y - j.y) * (i.x - k.x) - (i.y - k.y) * (i.x - j.x));
    *d = *a * i.x + *b * i.y + i.z;
}

TEST(terrain_eq4_plane_coefficients)
{
    /* z = 2.385 + 0.5 (x - 1.25) - 0.5 (y - 0.5), i.e. -0.5 X + 0.5 Y + Z = 2.01. */
    rf_terrain t;
    one_triangle(rf_v3(1.25, 0.5, 2.385), rf_v3(3.25, 0.5, 3.385), rf_v3(1.25, 4.5, 0.385), &t);
    double a, b, d;
    rf_triangle_plane_abd(RF_TRI(&t, 0), &a, &b, &d);
    ENSURE_SMALL(a - (-0.5), 1e-14);
    ENSURE_SMALL(b - 0.5, 1e-14);
    ENSURE_SMALL(d - 2.01, 1e-13);
    ensure_plane_consistent(RF_TRI(&t, 0));
    ENSURE_SMALL(rf_triangle_z_at(RF_TRI(&t, 0), 2.0, 3.0) - (2.385 + 0.375 - 1.25), 1e-13);
    rf_terrain_free(&t);

    /* A general triangle (clockwise in xy) against the paper's formulas. */
    rf_vec3 i = rf_v3(-3.17, 12.4, 48.215), j = rf_v3(5.83, 2.915, 41.06),
            k = rf_v3(9.44, 17.2, 39.7);
    one_triangle(i, j, k, &t);
    double ea, eb, ed;
    paper_eq4(i, j, k, &ea, &eb, &ed);
    rf_triangle_plane_abd(RF_TRI(&t, 0), &a, &b, &d);
    ENSURE_REL(a, ea, 1e-12);
    ENSURE_REL(b, eb, 1e-12);
    ENSURE_REL(d, ed, 1e-12);
    rf_vec3 ijk[3] = {i, j, k};
    for (int m = 0; m < 3; m++)
        ENSURE_SMALL(a * ijk[m].x + b * ijk[m].y + ijk[m].z - d, 1e-12);
    ensure_plane_consistent(RF_TRI(&t, 0));
    rf_terrain_free(&t);
}

TEST(terrain_eq5_6_point_location_on_triangle)
{
    rf_terrain t;
    one_triangle(rf_v3(1.25, 0.5, 2.385), rf_v3(3.25, 0.5, 3.385), rf_v3(1.25, 4.5, 0.385), &t);
    const rf_triangle *tri = RF_TRI(&t, 0);
    double ts, ss;
    /* P = (0.5, 1.0) = 0.25 u + 0.25 v */
    ENSURE(rf_triangle_contains_xy(tri, 1.75, 1.5, 0.0, &ts, &ss));
    ENSURE_SMALL(ts - 0.25, 1e-15);
    ENSURE_SMALL(ss - 0.25, 1e-15);
    /* P = (1.75, 1.5): t = 0.875, s = 0.375, t + s > 1 */
    ENSURE(!rf_triangle_contains_xy(tri, 3.0, 2.0, 1e-9, &ts, &ss));
    ENSURE_SMALL(ts - 0.875, 1e-15);
    ENSURE_SMALL(ss - 0.375, 1e-15);
    /* s < 0 and t < 0 */
    ENSURE(!rf_triangle_contains_xy(tri, 2.0, 0.4, 1e-9, NULL, NULL));
    ENSURE(!rf_triangle_contains_xy(tri, 1.2, 2.0, 1e-9, NULL, NULL));
    /* On the edge j-k (t + s = 1) and on the vertices. */
    ENSURE(rf_triangle_contains_xy(tri, 2.25, 2.5, 0.0, &ts, &ss));
    ENSURE_SMALL(ts + ss - 1.0, 1e-15);
    ENSURE(rf_triangle_contains_xy(tri, 3.25, 0.5, 0.0, &ts, &ss));
    ENSURE_SMALL(ts - 1.0, 1e-15);
    ENSURE(rf_triangle_contains_xy(tri, 1.25, 4.5, 0.0, NULL, NULL));
    ENSURE(rf_triangle_contains_xy(tri, 1.25, 0.5, 0.0, NULL, NULL));
    /* Just beyond the edge: out, unless the tolerance covers it. */
    ENSURE(!rf_triangle_contains_xy(tri, 2.25 + 1e-6, 2.5, 1e-9, NULL, NULL));
    ENSURE(rf_triangle_contains_xy(tri, 2.25 + 1e-6, 2.5, 1e-5, NULL, NULL));
    /* Through the terrain: inside, on an edge and a vertex, outside. */
    double z;
    ENSURE(rf_terrain_height(&t, 1.75, 1.5, &z) == 0);
    ENSURE_SMALL(z - (2.385 + 0.25 - 0.5), 1e-13);
    ENSURE(rf_terrain_locate(&t, 2.25, 2.5) == 0);
    ENSURE(rf_terrain_locate(&t, 1.25, 0.5) == 0);
    ENSURE(rf_terrain_locate(&t, 3.0, 2.0) == -1);
    ENSURE(rf_terrain_locate(&t, -7.3, 2.0) == -1);
    rf_terrain_free(&t);
}

TEST(terrain_eq7_plane_distance)
{
    rf_terrain t;
    one_triangle(rf_v3(1.25, 0.5, 2.385), rf_v3(3.25, 0.5, 3.385), rf_v3(1.25, 4.5, 0.385), &t);
    const rf_triangle *tri = RF_TRI(&t, 0);
    /* |a X + b Y + Z - d| / sqrt(a^2 + b^2 + 1) with a = -0.5, b = 0.5, d = 2.01 */
    double expect = (-0.5 * 2.0 + 0.5 * 3.0 + 5.0 - 2.01) / sqrt(1.5);
    ENSURE_SMALL(rf_triangle_plane_distance(tri, rf_v3(2.0, 3.0, 5.0)) - expect, 1e-13);
    double below = (-0.5 * 2.7 + 0.5 * 1.1 - 4.2 - 2.01) / sqrt(1.5);
    ENSURE(below < 0);
    ENSURE_SMALL(rf_triangle_plane_distance(tri, rf_v3(2.7, 1.1, -4.2)) - below, 1e-13);
    ENSURE_SMALL(rf_triangle_plane_distance(tri, rf_v3(1.25, 4.5, 0.385)), 1e-14);
    rf_terrain_free(&t);
}

/* ---- steep faces ------------------------------------------------------------------ */

static void check_steep(double deg)
{
    double th = deg * PI / 180.0, h = 1.93;
    rf_vec3 a = rf_v3(10.3, 20.7, 5.1), b = rf_v3(12.685, 20.7, 5.1);
    rf_vec3 c = rf_v3(10.7, 20.7 + h * cos(th), 5.1 + h * sin(th));
    rf_terrain t;
    one_triangle(a, b, c, &t);
    const rf_triangle *tri = RF_TRI(&t, 0);
    ENSURE_MSG(fabs(rf_triangle_slope(tri) - th) < 1e-12, "slope %.17g at %g deg",
               rf_triangle_slope(tri), deg);
    ensure_plane_consistent(tri);
    ENSURE_SMALL(tri->n.x, 1e-15);
    ENSURE_SMALL(tri->n.y + sin(th), 1e-14);
    ENSURE_SMALL(tri->n.z - cos(th), 1e-14);
    rf_vec3 g = rf_v3_scale(rf_v3_add(a, rf_v3_add(b, c)), 1.0 / 3.0);
    for (int side = -1; side <= 1; side += 2) {
        rf_vec3 p = rf_v3_madd(g, side * 0.37, tri->n);
        ENSURE_SMALL(rf_triangle_plane_distance(tri, p) - side * 0.37, 1e-13);
        rf_vec3 q = rf_triangle_closest_point(tri, p);
        ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, g)), 1e-13);
    }
    rf_terrain_free(&t);
}

TEST(terrain_steep_faces)
{
    check_steep(85.0);
    check_steep(89.0);
    check_steep(89.9);
}

TEST(terrain_vertical_face)
{
    rf_terrain t;
    rf_vec3 a = rf_v3(10.3, 20.7, 5.1), b = rf_v3(12.685, 20.7, 5.1), c = rf_v3(10.7, 20.7, 7.03);
    one_triangle(a, b, c, &t);
    const rf_triangle *tri = RF_TRI(&t, 0);
    ENSURE(tri->n.z == 0.0);
    ENSURE_SMALL(fabs(tri->n.y) - 1.0, 1e-15);
    ENSURE_SMALL(rf_triangle_slope(tri) - PI / 2, 1e-15);
    ensure_plane_consistent(tri);
    rf_vec3 q = rf_triangle_closest_point(tri, rf_v3(11.0, 23.5, 5.5));
    ENSURE_SMALL(q.x - 11.0, 1e-13);
    ENSURE_SMALL(q.y - 20.7, 1e-13);
    ENSURE_SMALL(q.z - 5.5, 1e-13);
    /* A vertical face has no xy area: point location never returns it. */
    ENSURE(rf_terrain_locate(&t, 11.0, 20.7) == -1);
    rf_terrain_free(&t);
}

/* ---- closest point ---------------------------------------------------------------- */

/* Brute force: the nearest of a fine barycentric lattice. */
static double lattice_distance(const rf_triangle *tri, rf_vec3 p)
{
    const int m = 400;
    double best = INFINITY;
    for (int i = 0; i <= m; i++)
        for (int j = 0; i + j <= m; j++) {
            double u = (double)i / m, v = (double)j / m;
            rf_vec3 q = rf_v3_add(tri->a, rf_v3_add(rf_v3_scale(rf_v3_sub(tri->b, tri->a), u),
                                                    rf_v3_scale(rf_v3_sub(tri->c, tri->a), v)));
            double dd = rf_v3_norm(rf_v3_sub(p, q));
            if (dd < best)
                best = dd;
        }
    return best;
}

TEST(terrain_closest_point_regions)
{
    rf_vec3 a = rf_v3(0.3, -0.2, 1.1), b = rf_v3(4.1, 0.5, 1.7), c = rf_v3(1.2, 3.6, 2.9);
    rf_terrain t;
    one_triangle(a, b, c, &t);
    const rf_triangle *tri = RF_TRI(&t, 0);
    rf_vec3 n = tri->n;

    /* Face: a point above an inner point projects onto it. */
    rf_vec3 inner = rf_v3_add(rf_v3_scale(a, 0.2), rf_v3_add(rf_v3_scale(b, 0.35), rf_v3_scale(c, 0.45)));
    rf_vec3 q = rf_triangle_closest_point(tri, rf_v3_madd(inner, 2.385, n));
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, inner)), 1e-13);
    q = rf_triangle_closest_point(tri, rf_v3_madd(inner, -0.715, n));
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, inner)), 1e-13);

    /* Edge: from a point of edge ab, outwards in the plane and up. */
    rf_vec3 ab = rf_v3_sub(b, a);
    rf_vec3 out = rf_v3_unit(rf_v3_cross(ab, n));
    if (rf_v3_dot(out, rf_v3_sub(c, a)) > 0)
        out = rf_v3_scale(out, -1.0);
    rf_vec3 on_edge = rf_v3_madd(a, 0.63, ab);
    q = rf_triangle_closest_point(tri, rf_v3_madd(rf_v3_madd(on_edge, 1.47, out), 0.81, n));
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, on_edge)), 1e-13);

    /* Edge bc likewise. */
    rf_vec3 bc = rf_v3_sub(c, b);
    out = rf_v3_unit(rf_v3_cross(bc, n));
    if (rf_v3_dot(out, rf_v3_sub(a, b)) > 0)
        out = rf_v3_scale(out, -1.0);
    on_edge = rf_v3_madd(b, 0.29, bc);
    q = rf_triangle_closest_point(tri, rf_v3_madd(rf_v3_madd(on_edge, 0.93, out), -0.44, n));
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, on_edge)), 1e-13);

    /* Vertices: p - v points away from both edges at v. */
    rf_vec3 verts[3] = {a, b, c};
    for (int i = 0; i < 3; i++) {
        rf_vec3 v = verts[i], e1 = rf_v3_sub(verts[(i + 1) % 3], v), e2 = rf_v3_sub(verts[(i + 2) % 3], v);
        rf_vec3 dir = rf_v3_scale(rf_v3_add(rf_v3_unit(e1), rf_v3_unit(e2)), -1.0);
        rf_vec3 p = rf_v3_madd(rf_v3_madd(v, 1.73, dir), 0.52, n);
        ENSURE(rf_v3_dot(rf_v3_sub(p, v), e1) <= 0 && rf_v3_dot(rf_v3_sub(p, v), e2) <= 0);
        q = rf_triangle_closest_point(tri, p);
        ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, v)), 1e-13);
    }

    /* Scattered points against a brute-force lattice. */
    unsigned s = 12345u;
    for (int k = 0; k < 60; k++) {
        double r[3];
        for (int m = 0; m < 3; m++) {
            s = s * 1103515245u + 12345u;
            r[m] = (double)(s >> 8 & 0xffff) / 65535.0;
        }
        rf_vec3 p = rf_v3(-3 + 10 * r[0], -4 + 11 * r[1], -2 + 7 * r[2]);
        double dq = rf_v3_norm(rf_v3_sub(p, rf_triangle_closest_point(tri, p)));
        double dl = lattice_distance(tri, p);
        ENSURE_MSG(dq <= dl + 1e-12 && dq >= dl - 0.02, "point %d: %.17g vs lattice %.17g", k, dq, dl);
    }
    rf_terrain_free(&t);
}

TEST(terrain_closest_point_sliver)
{
    /* A needle 9.6 long and 2e-7 wide. */
    rf_vec3 a = rf_v3(100.25, 200.5, 30.125), b = rf_v3(109.85, 200.5, 34.0),
            c = rf_v3(104.09, 200.5000002, 31.675);
    rf_terrain t;
    one_triangle(a, b, c, &t);
    const rf_triangle *tri = RF_TRI(&t, 0);
    ENSURE_SMALL(rf_v3_norm(tri->n) - 1.0, 1e-14);
    ENSURE(tri->n.z >= 0);
    /* Beyond vertex b along the needle. */
    rf_vec3 q = rf_triangle_closest_point(tri, rf_v3(112.3, 200.6, 35.2));
    ENSURE_SMALL(rf_v3_norm(rf_v3_sub(q, b)), 1e-9);
    /* Beside the middle of edge ab: the closest point is within the needle's width of
     * the point's projection on ab. */
    rf_vec3 p = rf_v3(104.8, 203.25, 31.5);
    q = rf_triangle_closest_point(tri, p);
    double dq = rf_v3_norm(rf_v3_sub(p, q));
    rf_vec3 ab = rf_v3_sub(b, a);
    double u = rf_v3_dot(rf_v3_sub(p, a), ab) / rf_v3_norm2(ab);
    double de = rf_v3_norm(rf_v3_sub(p, rf_v3_madd(a, u, ab)));
    ENSURE(dq <= de + 1e-12);
    ENSURE(dq >= de - 3e-7);
    rf_terrain_free(&t);
}

/* ---- ESRI ASCII grids ------------------------------------------------------------- */

TEST(terrain_asc_corner_nodata)
{
    static const double rows[3][4] = {{12.385, 13.71, -9999, 15.02},
                                      {11.93, 12.604, 13.877, 14.45},
                                      {10.12, 11.447, 12.93, 13.308}};
    rf_terrain t;
    build_dem(DATA "grid_corner.asc", &t);
    ENSURE(t.is_grid == 1);
    ENSURE(t.nx == 4 && t.ny == 3);
    ENSURE_SMALL(t.x0 - (502.385 + 1.25), 1e-12);
    ENSURE_SMALL(t.y0 - (7211.64 + 1.25), 1e-12);
    ENSURE_SMALL(t.cell - 2.5, 0);
    ENSURE(t.ntri == 12 && t.grid_hole != NULL);
    size_t holes = 0;
    for (size_t m = 0; m < t.ntri; m++)
        holes += rf_grid_slot(&t, m) < 0;
    ENSURE(holes == 3); /* 12 triangles, 3 touch the nodata node */
    ENSURE(t.grid_hole[4] == 3 && t.grid_hole[5] == 2); /* cell (1, 1), the top of (2, 1) */
    ENSURE(t.nzones == 1 && strcmp(t.zones[0].name, "default") == 0);
    for (size_t j = 0; j < 3; j++)
        for (size_t i = 0; i < 4; i++) {
            double zin = rows[2 - j][i], x = t.x0 + (double)i * t.cell, y = t.y0 + (double)j * t.cell;
            double z = -1e300;
            int32_t k = rf_terrain_height(&t, x, y, &z);
            if (zin == -9999) {
                ENSURE(k == -1);
                continue;
            }
            ENSURE_MSG(k >= 0, "node (%zu, %zu) not located", i, j);
            ENSURE_SMALL(z - zin, 1e-12);
        }
    /* The hole: cell (1, 1) entirely, the upper triangle of cell (2, 1). */
    ENSURE(rf_terrain_locate(&t, t.x0 + 1.5 * t.cell, t.y0 + 1.5 * t.cell) == -1);
    ENSURE(rf_terrain_locate(&t, t.x0 + 2.2 * t.cell, t.y0 + 1.7 * t.cell) == -1);
    ENSURE(rf_terrain_locate(&t, t.x0 + 2.7 * t.cell, t.y0 + 1.3 * t.cell) >= 0);
    /* Middle of cell (0, 0), lower triangle: SW 10.12, SE 11.447, NE 12.604. */
    double z;
    int32_t k = rf_terrain_height(&t, t.x0 + 0.6 * t.cell, t.y0 + 0.25 * t.cell, &z);
    ENSURE(k == 0);
    ENSURE_SMALL(z - (10.12 + 0.6 * (11.447 - 10.12) + 0.25 * (12.604 - 11.447)), 1e-12);
    /* Outside the grid. */
    ENSURE(rf_terrain_locate(&t, t.x0 - 0.01, t.y0 + 1.0) == -1);
    ENSURE(rf_terrain_locate(&t, t.x0 + 1.0, t.y0 + 2 * t.cell + 0.01) == -1);
    /* Triangle shapes as terrain.h describes. */
    ENSURE(t.tri != NULL); /* a grid this small keeps its triangles */
    const rf_triangle *lo = RF_TRI(&t, 0), *hi = RF_TRI(&t, 1);
    ENSURE(lo->a.x == t.x0 && lo->a.y == t.y0 && lo->b.x > t.x0 && lo->b.y == t.y0);
    ENSURE(hi->c.x == t.x0 && hi->c.y > t.y0);
    for (size_t m = 0; m < t.ntri; m++)
        if (rf_grid_slot(&t, m) >= 0)
            ensure_plane_consistent(RF_TRI(&t, (int32_t)m));
    rf_terrain_free(&t);
}

TEST(terrain_asc_center)
{
    static const double rows[4][3] = {{101.17, 99.835, 98.4},
                                      {100.62, 99.01, 97.93},
                                      {99.705, 98.441, 97.2},
                                      {98.8, 97.66, 96.05}};
    rf_terrain t;
    build_dem(DATA "grid_center.asc", &t);
    ENSURE(t.nx == 3 && t.ny == 4 && t.ntri == 12);
    ENSURE(t.x0 == -41.75 && t.y0 == 18.2);
    for (size_t j = 0; j < 4; j++)
        for (size_t i = 0; i < 3; i++) {
            double z;
            ENSURE(rf_terrain_height(&t, -41.75 + (double)i * 1.35, 18.2 + (double)j * 1.35, &z) >= 0);
            ENSURE_SMALL(z - rows[3 - j][i], 1e-12);
        }
    ENSURE_SMALL(t.xmin - (-41.75), 1e-12);
    ENSURE_SMALL(t.xmax - (-41.75 + 2.7), 1e-12);
    ENSURE_SMALL(t.zmax - 101.17, 0);
    ENSURE_SMALL(t.zmin - 96.05, 0);
    rf_terrain_free(&t);
}

static void ensure_build_error(const char *path, rf_terrain_source src, int line, int column,
                               const char *needle)
{
    char *files[1] = {(char *)path};
    rf_terrain_spec spec = {.source = src, .files = files, .nfiles = 1, .up = 'z',
                            .surface = SURF_DEFAULT};
    rf_terrain t;
    rf_error err = {0};
    ENSURE(rf_terrain_build(&spec, &t, &err) != 0);
    ENSURE_MSG(strcmp(err.file, path) == 0, "error file '%s'", err.file);
    ENSURE_MSG(err.line == line && err.column == column, "%s:%d:%d: %s (expected %d:%d)",
               err.file, err.line, err.column, err.message, line, column);
    ENSURE_MSG(strstr(err.message, needle) != NULL, "message '%s' lacks '%s'", err.message, needle);
    ENSURE(t.tri == NULL && t.zones == NULL && t.z == NULL && t.grid_hole == NULL && t.bucket_start == NULL);
}

TEST(terrain_bad_files)
{
    ensure_build_error(DATA "no_such_grid.asc", RF_TERRAIN_DEM, 0, 0,
                       "cannot open '" DATA "no_such_grid.asc': ");
    ensure_build_error(DATA "no_such_mesh.stl", RF_TERRAIN_MESH, 0, 0,
                       "cannot open '" DATA "no_such_mesh.stl': ");
    ensure_build_error(DATA "bad_value.asc", RF_TERRAIN_DEM, 7, 5, "5.x25");
    ensure_build_error(DATA "short.asc", RF_TERRAIN_DEM, 8, 1, "expected 6 values, found 5");
    ensure_build_error(DATA "bad_header.asc", RF_TERRAIN_DEM, 5, 10, "two");

    ensure_build_error(rf_test_write("bad.obj", "v 0 0 1.5\nv 2.5 0 1.25\nv 0 3.5 1.75\n"
                                           "f 1 2 3\nf 1 2 4\n"),
                       RF_TERRAIN_MESH, 5, 7, "bad vertex index");
    ensure_build_error(rf_test_write("bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\n"
                                           "  vertex 4 5 six\n"),
                       RF_TERRAIN_MESH, 5, 14, "six");
    /* A mesh whose only triangle has no area. */
    ensure_build_error(rf_test_write("flat.obj", "v 0 0 1.5\nv 2.5 0 1.25\nv 5 0 1.0\nf 1 2 3\n"),
                       RF_TERRAIN_MESH, 0, 0, "no triangle");
}

/* ---- meshes ------------------------------------------------------------------------ */

TEST(terrain_stl_ascii)
{
    static const double v[4][3] = {{3.125, -1.75, 10.385}, {8.375, -1.75, 11.02},
                                   {8.375, 4.5, 12.71}, {3.125, 4.5, 11.63}};
    rf_terrain t;
    build_mesh(DATA "slab.stl", 'z', &t);
    ENSURE(t.is_grid == 0 && t.ntri == 2);
    ENSURE(t.nzones == 2 && strcmp(t.zones[1].name, "slab") == 0);
    ENSURE(RF_TRI(&t, 0)->zone == 1 && RF_TRI(&t, 1)->zone == 1);
    for (int i = 0; i < 4; i++) {
        double z;
        ENSURE(rf_terrain_height(&t, v[i][0], v[i][1], &z) >= 0);
        ENSURE_SMALL(z - v[i][2], 1e-12);
    }
    /* On the shared diagonal both triangles agree. */
    double z;
    ENSURE(rf_terrain_height(&t, 3.125 + 0.4 * 5.25, -1.75 + 0.4 * 6.25, &z) >= 0);
    ENSURE_SMALL(z - (10.385 + 0.4 * (12.71 - 10.385)), 1e-12);
    ENSURE(rf_terrain_locate(&t, 2.0, 0.0) == -1);
    rf_terrain_free(&t);
}

static void put_le32(FILE *f, uint32_t u)
{
    unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8), (unsigned char)(u >> 16),
                          (unsigned char)(u >> 24)};
    fwrite(b, 1, 4, f);
}

static void put_float(FILE *f, float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    put_le32(f, u);
}

TEST(terrain_stl_binary)
{
    /* Values exact in float. */
    static const float v[4][3] = {{3.125f, -1.75f, 10.375f}, {8.375f, -1.75f, 11.0f},
                                  {8.375f, 4.5f, 12.6875f}, {3.125f, 4.5f, 11.625f}};
    static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    const char *path = rf_test_path("slab_bin.stl");
    FILE *f = fopen(path, "wb");
    ENSURE(f != NULL);
    char header[80];
    memset(header, ' ', sizeof header);
    memcpy(header, "solid but binary", 16); /* the word "solid" must not fool the reader */
    fwrite(header, 1, sizeof header, f);
    put_le32(f, 2);
    for (int k = 0; k < 2; k++) {
        for (int m = 0; m < 3; m++)
            put_float(f, 0.0f);
        for (int i = 0; i < 3; i++)
            for (int m = 0; m < 3; m++)
                put_float(f, v[tri[k][i]][m]);
        fputc(0, f);
        fputc(0, f);
    }
    fclose(f);

    rf_terrain t;
    build_mesh(path, 'z', &t);
    ENSURE(t.ntri == 2);
    ENSURE(strcmp(t.zones[1].name, "slab_bin") == 0);
    for (int i = 0; i < 4; i++) {
        double z;
        ENSURE(rf_terrain_height(&t, v[i][0], v[i][1], &z) >= 0);
        ENSURE_SMALL(z - v[i][2], 1e-12);
    }
    rf_terrain_free(&t);
}

TEST(terrain_obj)
{
    static const double v[7][3] = {{0.0, 0.0, 5.125}, {4.2, 0.0, 6.385}, {4.2, 3.7, 7.01},
                                   {0.0, 3.7, 5.9},   {8.6, 0.0, 6.95},  {8.6, 3.7, 8.22},
                                   {4.2, 6.1, 7.73}};
    rf_terrain t;
    build_mesh(DATA "quads.obj", 'z', &t);
    ENSURE(t.ntri == 5); /* two quads fanned into 2 each, one triangle */
    for (int i = 0; i < 7; i++) {
        double z;
        ENSURE_MSG(rf_terrain_height(&t, v[i][0], v[i][1], &z) >= 0, "vertex %d", i + 1);
        ENSURE_SMALL(z - v[i][2], 1e-12);
    }
    /* The last face is (3, 6, 7) through negative indices. */
    const rf_triangle *last = RF_TRI(&t, 4);
    ENSURE(last->a.x == 4.2 && last->a.y == 3.7 && last->b.x == 8.6 && last->c.y == 6.1);
    ENSURE(rf_terrain_locate(&t, 8.0, 5.9) == -1);
    rf_terrain_free(&t);
}

TEST(terrain_obj_y_up)
{
    /* File (x, y, z) with y up: world (X, Y, Z) = (x, z, y). */
    const char *path = rf_test_write("yup.obj", "v 1.5 7.25 -2.0\nv 6.5 8.125 -2.0\nv 1.5 9.375 3.75\n"
                                           "f 1 2 3\n");
    rf_terrain t;
    build_mesh(path, 'y', &t);
    ENSURE(t.ntri == 1);
    ENSURE(RF_TRI(&t, 0)->a.x == 1.5 && RF_TRI(&t, 0)->a.y == -2.0 && RF_TRI(&t, 0)->a.z == 7.25);
    double z;
    ENSURE(rf_terrain_height(&t, 1.5, 3.75, &z) >= 0);
    ENSURE_SMALL(z - 9.375, 1e-12);
    ENSURE(rf_terrain_height(&t, 6.5, -2.0, &z) >= 0);
    ENSURE_SMALL(z - 8.125, 1e-12);
    rf_terrain_free(&t);
}

TEST(terrain_mesh_files_and_zones)
{
    /* Two files form one surface; the STL has a surface of its own, the OBJ takes the
     * default; a polygon zone then covers part of both. */
    char *files[2] = {(char *)DATA "quads.obj", (char *)DATA "slab.stl"};
    double poly[8] = {2.5, -1.0, 5.0, -1.0, 5.0, 10.0, 2.5, 10.0};
    rf_zone_spec zones[2] = {
        {.name = (char *)"slab", .file = (char *)DATA "slab.stl", .surface = SURF_OTHER},
        {.name = (char *)"strip", .poly_xy = poly, .npoly = 4, .surface = SURF_OTHER},
    };
    rf_terrain_spec spec = {.source = RF_TERRAIN_MESH, .files = files, .nfiles = 2, .up = 'z',
                            .surface = SURF_DEFAULT, .zones = zones, .nzones = 2};
    rf_terrain t;
    build_ok(&spec, &t);
    ENSURE(t.ntri == 7);
    ENSURE(t.nzones == 4);
    ENSURE(strcmp(t.zones[0].name, "default") == 0);
    ENSURE(strcmp(t.zones[1].name, "quads") == 0);
    ENSURE(strcmp(t.zones[2].name, "slab") == 0);
    ENSURE(strcmp(t.zones[3].name, "strip") == 0);
    ENSURE(t.zones[0].surface.restitution.mean == SURF_DEFAULT.restitution.mean);
    ENSURE(t.zones[1].surface.restitution.mean == SURF_DEFAULT.restitution.mean);
    ENSURE(t.zones[2].surface.restitution.mean == SURF_OTHER.restitution.mean);
    for (size_t k = 0; k < t.ntri; k++) {
        const rf_triangle *tri = RF_TRI(&t, k);
        double cx = (tri->a.x + tri->b.x + tri->c.x) / 3;
        int in_strip = cx >= 2.5 && cx <= 5.0;
        int32_t want = in_strip ? 3 : (k < 5 ? 1 : 2);
        ENSURE_MSG(tri->zone == want, "triangle %zu zone %d, want %d", k, tri->zone, want);
    }
    rf_terrain_free(&t);
}

/* ---- profile ---------------------------------------------------------------------- */

TEST(terrain_profile)
{
    double prof[6] = {0.0, 50.3, 12.385, 41.2, 30.7, 22.9};
    rf_terrain_spec spec = {.source = RF_TERRAIN_PROFILE, .profile = prof, .nprofile = 3,
                            .width = 7.25, .surface = SURF_DEFAULT};
    rf_terrain t;
    build_ok(&spec, &t);
    ENSURE(t.is_grid == 0 && t.ntri == 4);
    ENSURE_SMALL(t.ymin, 0);
    ENSURE_SMALL(t.ymax - 7.25, 0);
    ENSURE_SMALL(t.xmax - 30.7, 0);
    double xs[5] = {0.0, 6.2, 12.385, 20.05, 30.7}, ys[4] = {0.0, 1.9, 5.35, 7.25};
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 4; j++) {
            double x = xs[i], expect;
            if (x <= 12.385)
                expect = 50.3 + (41.2 - 50.3) * x / 12.385;
            else
                expect = 41.2 + (22.9 - 41.2) * (x - 12.385) / (30.7 - 12.385);
            double z;
            ENSURE_MSG(rf_terrain_height(&t, x, ys[j], &z) >= 0, "(%g, %g)", x, ys[j]);
            ENSURE_SMALL(z - expect, 1e-12);
        }
    ENSURE(rf_terrain_locate(&t, 5.0, 7.26) == -1);
    ENSURE(rf_terrain_locate(&t, 5.0, -0.01) == -1);
    ENSURE(rf_terrain_locate(&t, -0.01, 3.0) == -1);
    ENSURE(rf_terrain_locate(&t, 30.72, 3.0) == -1);
    /* Slope of the second segment. */
    int32_t k = rf_terrain_locate(&t, 20.0, 3.3);
    ENSURE(k >= 0);
    ENSURE_SMALL(rf_triangle_slope(RF_TRI(&t, k)) - atan((41.2 - 22.9) / (30.7 - 12.385)), 1e-14);
    rf_terrain_free(&t);
}

/* ---- box queries -------------------------------------------------------------------- */

static int tri_bbox_overlaps(const rf_triangle *tri, double x0, double y0, double x1, double y1)
{
    double tx0 = fmin(tri->a.x, fmin(tri->b.x, tri->c.x)), tx1 = fmax(tri->a.x, fmax(tri->b.x, tri->c.x));
    double ty0 = fmin(tri->a.y, fmin(tri->b.y, tri->c.y)), ty1 = fmax(tri->a.y, fmax(tri->b.y, tri->c.y));
    return tx0 <= x1 && tx1 >= x0 && ty0 <= y1 && ty1 >= y0;
}

static void check_boxes(const rf_terrain *t, const double (*box)[4], int nbox)
{
    uint32_t *stamp = calloc(t->ntri, sizeof *stamp);
    unsigned char *seen = calloc(t->ntri, 1);
    int32_t *out = malloc(t->ntri * sizeof *out);
    uint32_t epoch = 0;
    ENSURE(stamp && seen && out);
    for (int b = 0; b < nbox; b++) {
        const double *q = box[b];
        size_t n = rf_terrain_query_box(t, q[0], q[1], q[2], q[3], out, t->ntri, stamp, &epoch);
        ENSURE(n <= t->ntri);
        memset(seen, 0, t->ntri);
        for (size_t i = 0; i < n; i++) {
            ENSURE(out[i] >= 0 && (size_t)out[i] < t->ntri);
            ENSURE_MSG(!seen[out[i]], "box %d: triangle %d twice", b, out[i]);
            seen[out[i]] = 1;
        }
        size_t expect = 0;
        for (size_t k = 0; k < t->ntri; k++)
            if ((!t->is_grid || rf_grid_slot(t, k) >= 0) &&
                tri_bbox_overlaps(RF_TRI(t, k), q[0], q[1], q[2], q[3])) {
                expect++;
                ENSURE_MSG(seen[k], "box %d: triangle %zu missing", b, k);
            }
        ENSURE_MSG(n == expect, "box %d: %zu found, %zu overlap", b, n, expect);
        if (n > 1) {
            size_t n2 = rf_terrain_query_box(t, q[0], q[1], q[2], q[3], out, 1, stamp, &epoch);
            ENSURE(n2 == n);
        }
    }
    free(stamp);
    free(seen);
    free(out);
}

TEST(terrain_query_box_grid)
{
    rf_terrain t;
    build_dem(DATA "grid_corner.asc", &t);
    double x0 = t.x0, y0 = t.y0;
    const double boxes[][4] = {
        {x0 + 0.3, y0 + 0.2, x0 + 0.9, y0 + 0.7},
        {x0 + 1.1, y0 + 1.3, x0 + 5.2, y0 + 4.4},
        {x0 - 10, y0 - 10, x0 + 100, y0 + 100},
        {x0 + 2.5, y0 + 2.5, x0 + 2.5, y0 + 2.5}, /* a node */
        {x0 + 20, y0, x0 + 30, y0 + 1},           /* beyond */
    };
    check_boxes(&t, boxes, 5);
    rf_terrain_free(&t);
}

TEST(terrain_query_box_mesh)
{
    rf_terrain t;
    build_mesh(DATA "quads.obj", 'z', &t);
    const double boxes[][4] = {
        {0.3, 0.2, 0.9, 0.7}, {3.9, 2.1, 4.5, 4.0}, {-5, -5, 20, 20}, {4.2, 3.7, 4.2, 3.7},
        {9.0, 0.0, 9.5, 1.0},
    };
    check_boxes(&t, boxes, 5);
    rf_terrain_free(&t);

    double prof[8] = {0.0, 50.3, 12.385, 41.2, 30.7, 22.9, 35.15, 22.0};
    rf_terrain_spec spec = {.source = RF_TERRAIN_PROFILE, .profile = prof, .nprofile = 4,
                            .width = 7.25, .surface = SURF_DEFAULT};
    build_ok(&spec, &t);
    const double boxes2[][4] = {{11.0, 1.0, 13.0, 2.0}, {12.385, 0, 12.385, 7.25}, {-1, -1, 40, 9}};
    check_boxes(&t, boxes2, 3);
    rf_terrain_free(&t);
}

TEST(terrain_query_box_epoch_wrap)
{
    rf_terrain t;
    build_mesh(DATA "quads.obj", 'z', &t);
    uint32_t stamp[5];
    memset(stamp, 0, sizeof stamp);
    uint32_t epoch = UINT32_MAX - 1;
    int32_t out[5];
    for (int r = 0; r < 4; r++)
        ENSURE(rf_terrain_query_box(&t, -5, -5, 20, 20, out, 5, stamp, &epoch) == 5);
    ENSURE(epoch == 3);
    rf_terrain_free(&t);
}

/* ---- point in polygon ------------------------------------------------------------ */

TEST(terrain_point_in_polygon)
{
    /* An L shape. */
    double L[12] = {0.5, 0.25, 6.75, 0.25, 6.75, 2.125, 2.375, 2.125, 2.375, 5.5, 0.5, 5.5};
    ENSURE(rf_point_in_polygon(L, 6, 1.2, 1.1));
    ENSURE(rf_point_in_polygon(L, 6, 5.9, 1.7));
    ENSURE(rf_point_in_polygon(L, 6, 1.4, 4.9));
    ENSURE(!rf_point_in_polygon(L, 6, 4.1, 3.3)); /* in the notch */
    ENSURE(!rf_point_in_polygon(L, 6, -0.2, 1.0));
    ENSURE(!rf_point_in_polygon(L, 6, 7.0, 1.0));
    ENSURE(!rf_point_in_polygon(L, 6, 1.0, 5.6));
    /* Boundary: edges and vertices count as inside. */
    ENSURE(rf_point_in_polygon(L, 6, 3.3, 0.25));
    ENSURE(rf_point_in_polygon(L, 6, 6.75, 1.0));
    ENSURE(rf_point_in_polygon(L, 6, 4.0, 2.125));
    ENSURE(rf_point_in_polygon(L, 6, 2.375, 2.125));
    ENSURE(rf_point_in_polygon(L, 6, 0.5, 5.5));
    ENSURE(rf_point_in_polygon(L, 6, 2.375, 3.8));
    /* A slanted edge. */
    double tri[6] = {0.0, 0.0, 4.4, 1.1, 1.3, 3.9};
    ENSURE(rf_point_in_polygon(tri, 3, 2.2, 0.55));
    ENSURE(!rf_point_in_polygon(tri, 3, 2.2, 0.5));
    ENSURE(rf_point_in_polygon(tri, 3, 2.2, 0.6));
    /* A ray through a vertex must not double count. */
    double diamond[8] = {2.0, 0.0, 4.0, 2.0, 2.0, 4.0, 0.0, 2.0};
    ENSURE(rf_point_in_polygon(diamond, 4, 1.0, 2.0));
    ENSURE(!rf_point_in_polygon(diamond, 4, -1.0, 2.0));
    ENSURE(!rf_point_in_polygon(diamond, 4, 5.0, 2.0));
}

/* ---- the Authume quarry mesh --------------------------------------------------- */

TEST(terrain_authume_mesh)
{
    static const char *names[3] = {"DTM_Blue_zone", "DTM_Gray_zone", "DTM_Red_zone"};
    static const size_t facets[3] = {5300, 2953, 748};
    char paths[3][4096], *files[3];
    rf_test_authume_files(paths, files);
    rf_zone_spec zones[1] = {{.name = (char *)"gray", .file = paths[1], .surface = SURF_OTHER}};
    rf_terrain_spec spec = {.source = RF_TERRAIN_MESH, .files = files, .nfiles = 3, .up = 'y',
                            .surface = SURF_DEFAULT, .zones = zones, .nzones = 1};
    rf_terrain t;
    build_ok(&spec, &t);
    ENSURE(t.nzones == 4);
    ENSURE(strcmp(t.zones[0].name, "default") == 0);
    /* a file's zone takes the name of its zone entry, else the file's */
    ENSURE(strcmp(t.zones[1].name, names[0]) == 0);
    ENSURE(strcmp(t.zones[2].name, "gray") == 0);
    ENSURE(strcmp(t.zones[3].name, names[2]) == 0);
    ENSURE(t.zones[2].surface.friction.mean == SURF_OTHER.friction.mean);
    ENSURE(t.zones[3].surface.friction.mean == SURF_DEFAULT.friction.mean);
    ENSURE_MSG(t.ntri == 9001, "%zu triangles", t.ntri);
    /* Files are read in order, so triangle k's zone follows from the facet counts. */
    size_t count[4] = {0};
    for (size_t k = 0; k < t.ntri; k++) {
        int32_t want = k < facets[0] ? 1 : (k < facets[0] + facets[1] ? 2 : 3);
        ENSURE_MSG(RF_TRI(&t, k)->zone == want, "triangle %zu in zone %d", k, RF_TRI(&t, k)->zone);
        count[RF_TRI(&t, k)->zone]++;
        ENSURE(RF_TRI(&t, k)->n.z >= 0);
    }
    ENSURE(count[1] == 5300 && count[2] == 2953 && count[3] == 748);

    /* Drop positions: file (x, y, z) with y up, so the ground under them is at
     * world (x, z). */
    FILE *f = fopen(rf_test_shared("validation/authume/Drop_conditions/positions_P1.xyz"), "r");
    ENSURE(f != NULL);
    double x, y, z;
    int n = 0;
    while (fscanf(f, "%lf %lf %lf", &x, &y, &z) == 3) {
        double zg;
        int32_t k = rf_terrain_height(&t, x, z, &zg);
        ENSURE_MSG(k >= 0, "drop position %d (%g, %g) off the terrain", n, x, z);
        ENSURE_MSG(zg < y && zg > y - 30, "ground %g under drop height %g", zg, y);
        n++;
    }
    fclose(f);
    ENSURE(n == 4);

    /* Location agrees with a scan over all triangles at scattered points. */
    unsigned s = 987u;
    for (int m = 0; m < 300; m++) {
        s = s * 1103515245u + 12345u;
        double px = t.xmin + (t.xmax - t.xmin) * (double)(s >> 8 & 0xffff) / 65535.0;
        s = s * 1103515245u + 12345u;
        double py = t.ymin + (t.ymax - t.ymin) * (double)(s >> 8 & 0xffff) / 65535.0;
        double best = -INFINITY;
        for (size_t k = 0; k < t.ntri; k++) {
            double tt, ss;
            if (rf_triangle_contains_xy(RF_TRI(&t, k), px, py, 1e-9, &tt, &ss)) {
                const rf_triangle *tri = RF_TRI(&t, k);
                double zz = tri->a.z + tt * (tri->b.z - tri->a.z) + ss * (tri->c.z - tri->a.z);
                if (zz > best)
                    best = zz;
            }
        }
        double zg = 0;
        int32_t k = rf_terrain_height(&t, px, py, &zg);
        if (best == -INFINITY) {
            ENSURE(k == -1);
        } else {
            ENSURE_MSG(k >= 0, "(%g, %g) not located", px, py);
            ENSURE_SMALL(zg - best, 1e-9);
        }
    }

    const double boxes[][4] = {{t.xmin + 5, t.ymin + 5, t.xmin + 6.3, t.ymin + 5.9},
                               {0.1, 330.0, 1.4, 331.2},
                               {-2.0, 365.0, 4.5, 375.0}};
    check_boxes(&t, boxes, 3);
    rf_terrain_free(&t);
}

/* ---- bucket grid limits and overlapping projections ------------------------------ */

TEST(terrain_mesh_highest_and_bucket_memory)
{
    const char *path = rf_test_path("mixed.obj");
    FILE *f = fopen(path, "w");
    ENSURE(f != NULL);
    /* 40 x 40 tiny cells of 0.025 m near the origin, two triangles each ... */
    int m = 40;
    double h = 0.025;
    for (int j = 0; j <= m; j++)
        for (int i = 0; i <= m; i++)
            fprintf(f, "v %.17g %.17g %.17g\n", i * h, j * h, 3.125 + 0.1 * i * h);
    for (int j = 0; j < m; j++)
        for (int i = 0; i < m; i++) {
            int sw = j * (m + 1) + i + 1, se = sw + 1, nw = sw + m + 1, ne = nw + 1;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", sw, se, ne, sw, ne, nw);
        }
    /* ... one huge triangle far away, and two stacked ones over the same ground. */
    fputs("v 50 50 -7.5\nv 950 50 -7.5\nv 50 950 -2.25\nf -3 -2 -1\n", f);
    fputs("v 2 2 1.5\nv 3 2 1.5\nv 2 3 1.5\nf -3 -2 -1\n", f);
    fputs("v 2 2 4.25\nv 3.5 2 4.25\nv 2 3.5 4.25\nf -1 -2 -3\n", f);
    fclose(f);
    rf_terrain t;
    build_mesh(path, 'z', &t);
    ENSURE(t.ntri == (size_t)(2 * m * m + 3));
    size_t nb = t.nbx * t.nby;
    ENSURE(nb <= 2 * t.ntri);
    ENSURE_MSG(t.bucket_start[nb] <= 16 * t.ntri + 2 * t.ntri, "%u bucket entries",
               t.bucket_start[nb]);
    double z;
    ENSURE(rf_terrain_height(&t, 0.5125, 0.3375, &z) >= 0);
    ENSURE_SMALL(z - (3.125 + 0.1 * 0.5125), 1e-12);
    ENSURE(rf_terrain_height(&t, 400.0, 300.0, &z) >= 0);
    int32_t k = rf_terrain_height(&t, 2.2, 2.3, &z);
    ENSURE(k == (int32_t)t.ntri - 1);
    ENSURE_SMALL(z - 4.25, 1e-12);
    ENSURE(rf_terrain_locate(&t, 20.0, 20.0) == -1);
    rf_terrain_free(&t);
}

/* ---- bounds on the files ----------------------------------------------------------- */

#include "input/terrain_io.h"

/* A terrain file must be a regular file: /dev/zero was read until memory ran out. */
TEST(terrain_device_and_directory_refused_at_once)
{
    ensure_build_error("/dev/zero", RF_TERRAIN_DEM, 0, 0, "not a regular file");
    ensure_build_error("/dev/zero", RF_TERRAIN_MESH, 0, 0, "not a regular file");
    ensure_build_error("/tmp", RF_TERRAIN_MESH, 0, 0, "Is a directory");
    rf_points p;
    rf_error err = {0};
    ENSURE(rf_points_read("/dev/zero", 3, &p, &err) != 0);
    ENSURE_MSG(strstr(err.message, "not a regular file"), "%s", err.message);
}

/* The in-memory readers parse what the file readers parse. */
TEST(terrain_readers_from_memory)
{
    static const char grid[] = "ncols 2\nnrows 2\nxllcenter 0\nyllcenter 0\ncellsize 1\n"
                               "1 2\n3 4\n";
    rf_asc_grid g;
    rf_error err = {0};
    ENSURE(rf_asc_read_from_memory(grid, sizeof grid - 1, "g.asc", &g, &err) == 0);
    ENSURE(g.ncols == 2 && g.nrows == 2 && g.z[0] == 3 && g.z[3] == 2);
    rf_asc_free(&g);
    ENSURE(rf_asc_read_from_memory(grid, 20, "g.asc", &g, &err) != 0);
    ENSURE(strcmp(err.file, "g.asc") == 0 && g.z == NULL);

    static const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    rf_tri_list l = {0};
    ENSURE(rf_mesh_read_from_memory(obj, sizeof obj - 1, "m.obj", 1, 'z', &l, &err) == 0);
    ENSURE(l.n == 1 && l.v[1].x == 1);
    static const char stl[] = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
    ENSURE(rf_mesh_read_from_memory(stl, sizeof stl - 1, "m.stl", 0, 'z', &l, &err) == 0);
    ENSURE(l.n == 2);
    rf_tri_list_free(&l);

    static const char rows[] = "# x y z\n1 2 3\n4 5 6\n";
    rf_points p;
    ENSURE(rf_points_read_from_memory(rows, sizeof rows - 1, "p.txt", 3, &p, &err) == 0);
    ENSURE(p.n == 2 && p.v[5] == 6);
    rf_points_free(&p);
}

static void ensure_asc_error(const char *name, const char *text, int line, int column,
                             const char *needle)
{
    ensure_build_error(rf_test_write(name, text), RF_TERRAIN_DEM, line, column, needle);
}

#define GRID_HEAD(ncols, nrows, cell) \
    "ncols " ncols "\nnrows " nrows "\nxllcenter 0\nyllcenter 0\ncellsize " cell "\n"

/* `ncols 1000000000` said "must be at least 2": the message gives the real bounds. */
TEST(terrain_asc_ncols_beyond_the_limit_says_the_limit)
{
    ensure_asc_error("wide.asc", GRID_HEAD("1000000000", "2", "1") "1 2\n3 4\n", 1, 1,
                     "from 2 to 50000000, got 1e+09");
    ensure_asc_error("square.asc", GRID_HEAD("20000", "20000", "1") "1 2\n3 4\n", 2, 1,
                     "ncols x nrows is 400000000 nodes; at most 100000000 (crop the grid to the "
                     "slope, or resample it to larger cells)");
    /* a grid the file cannot hold is refused before its nodes are allocated */
    ensure_asc_error("claims.asc", GRID_HEAD("10000", "10000", "1") "1 2\n3 4\n", 6, 1,
                     "needs 100000000 values");
}

/* `cellsize 1e-300` said "no cell without nodata". */
TEST(terrain_asc_tiny_cellsize_refused_with_its_bounds)
{
    ensure_asc_error("tiny.asc", GRID_HEAD("2", "2", "1e-300") "1 2\n3 4\n", 5, 1,
                     "cellsize must be from 0.001 to 100000 m, got 1e-300");
}

/* A node of 1e300 made a release on it "in a nodata hole". */
TEST(terrain_asc_absurd_elevation_refused_at_its_node)
{
    ensure_asc_error("high.asc", GRID_HEAD("2", "2", "1") "1 2\n3 1e300\n", 7, 3,
                     "an elevation must be from -100000 to 100000 m");
    /* the NODATA_value may be anything */
    const char *ok = rf_test_write("nodata.asc", GRID_HEAD("2", "2", "1")
                                   "NODATA_value -3.4e38\n1 2\n3 -3.4e38\n");
    rf_asc_grid g;
    rf_error err = {0};
    ENSURE_MSG(rf_asc_read(ok, &g, &err) == 0, "%s", err.message);
    rf_asc_free(&g);
}

/* A truncated binary STL was parsed as ascii ("unexpected ... at 1:1"). */
TEST(terrain_truncated_binary_stl_says_truncated)
{
    unsigned char b[84 + 50 + 20] = {0};
    memcpy(b, "binary", 6);
    b[80] = 2; /* two triangles: 184 bytes */
    rf_tri_list l = {0};
    rf_error err = {0};
    ENSURE(rf_mesh_read_from_memory((const char *)b, sizeof b, "cut.stl", 0, 'z', &l, &err) != 0);
    ENSURE_MSG(strstr(err.message, "binary STL of 2 triangles needs 184 bytes, the file has "
                                   "154 (truncated)"),
               "%s", err.message);
    ENSURE(rf_mesh_read_from_memory((const char *)b, 50, "cut.stl", 0, 'z', &l, &err) != 0);
    ENSURE_MSG(strstr(err.message, "truncated"), "%s", err.message);
    ENSURE(l.n == 0);
}

/* Mesh vertices far beyond any terrain are refused at their line. */
TEST(terrain_mesh_vertex_out_of_bounds)
{
    ensure_build_error(rf_test_write("far.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n"),
                       RF_TERRAIN_MESH, 2, 1, "out of bounds");
    ensure_build_error(rf_test_write("deep.stl", "solid x\nfacet normal 0 0 1\nouter loop\n"
                                                 "vertex 0 0 0\n vertex 1 0 -1e6\n"),
                       RF_TERRAIN_MESH, 5, 2, "out of bounds");
}

/* ---- polygons through an index of their edges --------------------------------------- */

#include "base/polygon.h"

/* A wavy ring of n vertices around (cx, cy): radius 40 +- 15, folding in and out. */
static double *wavy_polygon(size_t n, double cx, double cy)
{
    double *xy = malloc(2 * n * sizeof *xy);
    ENSURE(xy);
    for (size_t k = 0; k < n; k++) {
        double a = 2 * PI * (double)k / (double)n, r = 40 + 15 * sin(37 * a) * cos(5 * a);
        xy[2 * k] = cx + r * cos(a);
        xy[2 * k + 1] = cy + r * sin(a);
    }
    return xy;
}

/* The index answers as the plain test does, to the bit, on vertices, on edges' midpoints,
 * on a lattice and beyond the polygon, with few edges per point. */
TEST(polygon_index_answers_as_the_plain_test_with_few_edges)
{
    const size_t n = 30000;
    double *xy = wavy_polygon(n, 50, 50);
    rf_polygon_index ix;
    ENSURE(rf_polygon_index_build(&ix, xy, n) == 0);
    size_t queries = 0;
    for (size_t k = 0; k < n; k += 7) {
        size_t j = (k + 1) % n;
        double pts[3][2] = {{xy[2 * k], xy[2 * k + 1]},
                            {0.5 * (xy[2 * k] + xy[2 * j]), 0.5 * (xy[2 * k + 1] + xy[2 * j + 1])},
                            {xy[2 * k] + 1e-9, xy[2 * k + 1]}};
        for (int q = 0; q < 3; q++, queries++)
            ENSURE_MSG(rf_polygon_index_contains(&ix, pts[q][0], pts[q][1]) ==
                           rf_point_in_polygon(xy, n, pts[q][0], pts[q][1]),
                       "vertex %zu point %d", k, q);
    }
    for (double y = -5; y <= 105; y += 1.7)
        for (double x = -5; x <= 105; x += 2.3, queries++)
            ENSURE_MSG(rf_polygon_index_contains(&ix, x, y) == rf_point_in_polygon(xy, n, x, y),
                       "(%g, %g)", x, y);
    ENSURE_MSG(ix.tests <= 64 * queries, "%zu edges tested for %zu points", ix.tests, queries);
    rf_polygon_index_free(&ix);
    /* long edges only: a zigzag whose every edge spans the whole height */
    double zig[2 * 1000];
    for (size_t k = 0; k < 1000; k++) {
        zig[2 * k] = (double)k;
        zig[2 * k + 1] = k % 2 ? 100.0 : 0.0;
    }
    ENSURE(rf_polygon_index_build(&ix, zig, 1000) == 0);
    ENSURE(ix.start[ix.nstrips] <= 8 * 1000); /* the entries stay linear */
    for (double y = 0; y <= 100; y += 3.3)
        ENSURE(rf_polygon_index_contains(&ix, 500.5, y) == rf_point_in_polygon(zig, 1000, 500.5, y));
    rf_polygon_index_free(&ix);
    free(xy);
}

/* One 30 000-vertex zone polygon over a grid took 102 s: every triangle was tested
 * against every edge.  The zones are those the plain test gives. */
TEST(terrain_30000_vertex_zone_polygon_zones_as_the_plain_test)
{
    const size_t n = 30000, side = 201;
    size_t cap = 128 + side * side * 8, used = 0;
    char *text = malloc(cap);
    ENSURE(text);
    used += (size_t)snprintf(text, cap,
                             "ncols %zu\nnrows %zu\nxllcenter 0\nyllcenter 0\ncellsize 0.5\n",
                             side, side);
    for (size_t j = 0; j < side; j++)
        for (size_t i = 0; i < side; i++)
            used += (size_t)snprintf(text + used, cap - used, "%zu%c", (i + j) % 7,
                                     i + 1 == side ? '\n' : ' ');
    const char *path = rf_test_write("zones.asc", text);
    free(text);
    double *xy = wavy_polygon(n, 50, 50);
    char *files[1] = {(char *)path};
    rf_zone_spec zones[1] = {
        {.name = (char *)"wavy", .poly_xy = xy, .npoly = n, .surface = SURF_OTHER}};
    rf_terrain_spec spec = {.source = RF_TERRAIN_DEM, .files = files, .nfiles = 1, .up = 'z',
                            .surface = SURF_DEFAULT, .zones = zones, .nzones = 1};
    rf_terrain t;
    build_ok(&spec, &t);
    ENSURE(t.ntri == 2 * (side - 1) * (side - 1));
    size_t inside = 0;
    for (size_t k = 0; k < t.ntri; k++) {
        const rf_triangle *tri = RF_TRI(&t, k);
        inside += tri->zone == 1;
        if (k % 53)
            continue;
        double cx = (tri->a.x + tri->b.x + tri->c.x) / 3.0;
        double cy = (tri->a.y + tri->b.y + tri->c.y) / 3.0;
        ENSURE(tri->zone == (rf_point_in_polygon(xy, n, cx, cy) ? 1 : 0));
    }
    ENSURE(inside > t.ntri / 4 && inside < t.ntri);
    rf_terrain_free(&t);
    free(xy);
}
