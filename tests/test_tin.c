/* test_tin.c - a grid made a TIN within a tolerance (input/tin.h): the bound at every
 * node and between nodes, a plane, every node at tolerance 0, holes kept as holes, the
 * project key and its bad values. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "input/tin.h"
#include "rockfall/project.h"
#include "rockfall/terrain.h"
#include "test.h"

#define NODATA -9999.0

/* A grid of nx x ny nodes with heights f(i, j) (NODATA for holes). */
static rf_asc_grid grid_of(size_t nx, size_t ny, double (*f)(long, long))
{
    rf_asc_grid g = {nx, ny, 1000.5, -20.0, 1.7, 1, NODATA, malloc(nx * ny * sizeof(double))};
    ENSURE(g.z);
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++)
            g.z[j * nx + i] = f((long)i, (long)j);
    return g;
}

static uint64_t hash_ij(long i, long j)
{
    uint64_t h = (uint64_t)i * 0x9E3779B97F4A7C15ull ^ (uint64_t)(j + 7) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 32);
}

static double noise(long i, long j) { return (double)(hash_ij(i, j) % 1000003) / 1000003.0; }

static double rough(long i, long j)
{
    return 50.0 + 0.4 * (double)i - 0.3 * (double)j + 3.0 * sin(0.21 * (double)i) * cos(0.17 * (double)j) +
           0.2 * noise(i, j);
}

static double plane(long i, long j) { return 12.385 + 0.31 * (double)i - 0.72 * (double)j; }

static double random_heights(long i, long j) { return 5.0 * noise(i, j); }

static double millimetres(long i, long j) { return round(5000.0 * noise(i, j)) / 1000.0; }

/* rough, with a disc of nodata, a nodata corner and a bite out of the east side */
static double holed(long i, long j)
{
    double di = (double)i - 30.0, dj = (double)j - 20.0;
    if (di * di + dj * dj < 40.0 || (i < 3 && j < 2) || (i > 55 && j > 10 && j < 18))
        return NODATA;
    return rough(i, j);
}

static int bad(const rf_asc_grid *g, long i, long j)
{
    return g->z[(size_t)j * g->ncols + (size_t)i] == NODATA;
}

static double zn(const rf_asc_grid *g, long i, long j) { return g->z[(size_t)j * g->ncols + (size_t)i]; }

/* The grid's own surface at grid coordinates (x, y): its cell split along SW-NE. */
static double grid_z(const rf_asc_grid *g, double x, double y)
{
    long i = (long)floor(x), j = (long)floor(y);
    if (i > (long)g->ncols - 2)
        i = (long)g->ncols - 2;
    if (j > (long)g->nrows - 2)
        j = (long)g->nrows - 2;
    double u = x - (double)i, v = y - (double)j;
    double sw = zn(g, i, j), se = zn(g, i + 1, j), ne = zn(g, i + 1, j + 1), nw = zn(g, i, j + 1);
    return v <= u ? sw + u * (se - sw) + v * (ne - se) : sw + v * (nw - sw) + u * (ne - nw);
}

/* A TIN triangle back in grid indices (its vertices are grid nodes). */
typedef struct itri {
    long x[3], y[3];
    double z[3];
} itri;

static itri itri_of(const rf_asc_grid *g, const rf_tri_list *l, size_t k)
{
    itri t;
    for (int c = 0; c < 3; c++) {
        rf_vec3 v = l->v[3 * k + (size_t)c];
        double fx = (v.x - g->x0) / g->cell, fy = (v.y - g->y0) / g->cell;
        t.x[c] = lround(fx), t.y[c] = lround(fy), t.z[c] = v.z;
        ENSURE(fabs(fx - (double)t.x[c]) < 1e-9 && fabs(fy - (double)t.y[c]) < 1e-9);
        ENSURE(t.z[c] == zn(g, t.x[c], t.y[c]));
    }
    return t;
}

static double cross2(long ax, long ay, long bx, long by, long px, long py)
{
    return (double)(bx - ax) * (double)(py - ay) - (double)(by - ay) * (double)(px - ax);
}

/* The TIN's height at (x, y) in triangle t (barycentric). */
static double tri_z(const itri *t, double x, double y)
{
    double d = cross2(t->x[0], t->y[0], t->x[1], t->y[1], t->x[2], t->y[2]);
    double l1 = ((x - (double)t->x[0]) * (double)(t->y[2] - t->y[0]) -
                 (double)(t->x[2] - t->x[0]) * (y - (double)t->y[0])) / d;
    double l2 = ((double)(t->x[1] - t->x[0]) * (y - (double)t->y[0]) -
                 (x - (double)t->x[0]) * (double)(t->y[1] - t->y[0])) / d;
    return t->z[0] + l1 * (t->z[1] - t->z[0]) + l2 * (t->z[2] - t->z[0]);
}

/* The largest |TIN - grid| over every grid node in a TIN triangle, every crossing of a
 * TIN edge with a grid edge (x = i, y = j, x - y = k: where the difference of two
 * piecewise-linear surfaces peaks) and random points inside; also the TIN's area in
 * cells.  Written apart from tin.c, as a reader checks the claim. */
static double tin_error(const rf_asc_grid *g, const rf_tri_list *l, double *area)
{
    double worst = 0.0;
    *area = 0.0;
    uint64_t seed = 12345;
    for (size_t k = 0; k < l->n; k++) {
        itri t = itri_of(g, l, k);
        double d = cross2(t.x[0], t.y[0], t.x[1], t.y[1], t.x[2], t.y[2]);
        ENSURE(d != 0.0);
        *area += fabs(d) / 2.0;
        long x0 = t.x[0], x1 = t.x[0], y0 = t.y[0], y1 = t.y[0];
        for (int c = 1; c < 3; c++) {
            x0 = t.x[c] < x0 ? t.x[c] : x0, x1 = t.x[c] > x1 ? t.x[c] : x1;
            y0 = t.y[c] < y0 ? t.y[c] : y0, y1 = t.y[c] > y1 ? t.y[c] : y1;
        }
        double s = d > 0 ? 1.0 : -1.0;
        for (long j = y0; j <= y1; j++)
            for (long i = x0; i <= x1; i++) {
                int in = 1;
                for (int c = 0; c < 3; c++)
                    in &= s * cross2(t.x[c], t.y[c], t.x[(c + 1) % 3], t.y[(c + 1) % 3], i, j) >= 0;
                if (in)
                    worst = fmax(worst, fabs(tri_z(&t, (double)i, (double)j) - zn(g, i, j)));
            }
        for (int c = 0; c < 3; c++) {
            long ax = t.x[c], ay = t.y[c], bx = t.x[(c + 1) % 3], by = t.y[(c + 1) % 3];
            double za = t.z[c], zb = t.z[(c + 1) % 3];
            /* the three families of grid lines, as a value along the edge */
            long fa[3] = {ax, ay, ax - ay}, fb[3] = {bx, by, bx - by};
            for (int f = 0; f < 3; f++) {
                long lo = fa[f] < fb[f] ? fa[f] : fb[f], hi = fa[f] < fb[f] ? fb[f] : fa[f];
                for (long q = lo + 1; q < hi; q++) {
                    double u = (double)(q - fa[f]) / (double)(fb[f] - fa[f]);
                    double x = (double)ax + u * (double)(bx - ax), y = (double)ay + u * (double)(by - ay);
                    worst = fmax(worst, fabs(za + u * (zb - za) - grid_z(g, x, y)));
                }
            }
        }
        for (int r = 0; r < 8; r++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            double a = (double)(seed >> 11) / 9007199254740992.0;
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            double b = (double)(seed >> 11) / 9007199254740992.0;
            if (a + b > 1)
                a = 1 - a, b = 1 - b;
            double x = (double)t.x[0] + a * (double)(t.x[1] - t.x[0]) + b * (double)(t.x[2] - t.x[0]);
            double y = (double)t.y[0] + a * (double)(t.y[1] - t.y[0]) + b * (double)(t.y[2] - t.y[0]);
            worst = fmax(worst, fabs(tri_z(&t, x, y) - grid_z(g, x, y)));
        }
    }
    return worst;
}

static rf_tri_list tin_of(const rf_asc_grid *g, double tol, rf_tin_stats *st)
{
    rf_tri_list l = {NULL, 0, 0};
    rf_error err;
    ENSURE_MSG(rf_tin_build(g, tol, "grid.asc", &l, st, &err) == 0, "%s", err.message);
    ENSURE_MSG(st->triangles == l.n && st->unresolved == 0, "unresolved %zu", st->unresolved);
    return l;
}

TEST(tin_error_within_tolerance_at_nodes_and_between)
{
    rf_asc_grid g = grid_of(61, 47, rough);
    size_t prev = 0;
    double tols[] = {0.5, 0.2, 0.05, 0.01};
    for (size_t k = 0; k < 4; k++) {
        rf_tin_stats st;
        rf_tri_list l = tin_of(&g, tols[k], &st);
        double area, worst = tin_error(&g, &l, &area);
        ENSURE_MSG(worst <= tols[k] * (1 + 1e-9), "tolerance %g: error %.17g", tols[k], worst);
        ENSURE(st.max_error <= tols[k] && st.max_error <= worst + 1e-12);
        ENSURE_SMALL(area - 60.0 * 46.0, 1e-9); /* covers the grid, no overlap */
        ENSURE(st.vertices > prev && st.vertices < 61 * 47); /* finer with T, fewer nodes */
        prev = st.vertices;
        rf_tri_list_free(&l);
    }
    rf_asc_free(&g);
}

TEST(tin_of_a_plane_is_two_triangles)
{
    rf_asc_grid g = grid_of(37, 23, plane);
    rf_tin_stats st;
    rf_tri_list l = tin_of(&g, 1e-9, &st);
    ENSURE_MSG(l.n == 2 && st.vertices == 4, "%zu triangles, %zu vertices", l.n, st.vertices);
    double area, worst = tin_error(&g, &l, &area);
    ENSURE(worst < 1e-9);
    ENSURE_SMALL(area - 36.0 * 22.0, 1e-9);
    rf_tri_list_free(&l);
    rf_asc_free(&g);
}

/* At tolerance 0 every node of a surface with no four coplanar nodes comes in, and the
 * triangles are the grid's own (the cell's SW-NE diagonal). */
static void check_is_the_grid(const rf_asc_grid *g, double tol)
{
    rf_tin_stats st;
    rf_tri_list l = tin_of(g, tol, &st);
    size_t nx = g->ncols, ny = g->nrows;
    ENSURE_MSG(st.vertices == nx * ny, "%zu of %zu nodes", st.vertices, nx * ny);
    ENSURE(l.n == 2 * (nx - 1) * (ny - 1));
    for (size_t k = 0; k < l.n; k++) {
        itri t = itri_of(g, &l, k);
        long i = t.x[0], j = t.y[0];
        for (int c = 1; c < 3; c++)
            i = t.x[c] < i ? t.x[c] : i, j = t.y[c] < j ? t.y[c] : j;
        int sw = 0, ne = 0, other = 0;
        for (int c = 0; c < 3; c++) {
            sw += t.x[c] == i && t.y[c] == j;
            ne += t.x[c] == i + 1 && t.y[c] == j + 1;
            other += (t.x[c] - i) * (t.x[c] - i) + (t.y[c] - j) * (t.y[c] - j) == 1;
        }
        ENSURE_MSG(sw == 1 && ne == 1 && other == 1, "triangle %zu is not a grid half-cell", k);
    }
    double area;
    ENSURE(tin_error(g, &l, &area) <= tol + 1e-12);
    rf_tri_list_free(&l);
}

TEST(tin_at_tolerance_zero_or_below_the_data_keeps_every_node)
{
    rf_asc_grid g = grid_of(29, 31, random_heights);
    check_is_the_grid(&g, 0.0);
    rf_asc_free(&g);
    rf_asc_grid mm = grid_of(29, 31, millimetres);
    check_is_the_grid(&mm, 1e-4); /* heights in mm: a tenth of a mm keeps them all */
    rf_asc_free(&mm);
}

/* The interiors of two triangles (grid indices) overlap: no separating edge line. */
static int overlap(const long p[6], const long q[6])
{
    for (int side = 0; side < 2; side++) {
        const long *a = side ? q : p, *b = side ? p : q;
        double s = cross2(a[0], a[1], a[2], a[3], a[4], a[5]) > 0 ? 1.0 : -1.0;
        for (int e = 0; e < 3; e++) {
            int f = (e + 1) % 3, out = 1;
            for (int k = 0; k < 3; k++)
                out &= s * cross2(a[2 * e], a[2 * e + 1], a[2 * f], a[2 * f + 1], b[2 * k],
                                  b[2 * k + 1]) <= 0;
            if (out)
                return 0;
        }
    }
    return 1;
}

/* No kept triangle's interior overlaps a grid triangle with a nodata node. */
static void ensure_no_hole_covered(const rf_asc_grid *g, const rf_tri_list *l)
{
    for (size_t k = 0; k < l->n; k++) {
        itri t = itri_of(g, l, k);
        long p[6] = {t.x[0], t.y[0], t.x[1], t.y[1], t.x[2], t.y[2]};
        long x0 = p[0], x1 = p[0], y0 = p[1], y1 = p[1];
        for (int c = 1; c < 3; c++) {
            x0 = p[2 * c] < x0 ? p[2 * c] : x0, x1 = p[2 * c] > x1 ? p[2 * c] : x1;
            y0 = p[2 * c + 1] < y0 ? p[2 * c + 1] : y0, y1 = p[2 * c + 1] > y1 ? p[2 * c + 1] : y1;
        }
        for (long j = y0; j < y1; j++)
            for (long i = x0; i < x1; i++) {
                long lo[6] = {i, j, i + 1, j, i + 1, j + 1}, up[6] = {i, j, i + 1, j + 1, i, j + 1};
                if (bad(g, i, j) || bad(g, i + 1, j) || bad(g, i + 1, j + 1))
                    ENSURE_MSG(!overlap(p, lo), "triangle %zu over the hole at %ld %ld", k, i, j);
                if (bad(g, i, j) || bad(g, i + 1, j + 1) || bad(g, i, j + 1))
                    ENSURE_MSG(!overlap(p, up), "triangle %zu over the hole at %ld %ld", k, i, j);
            }
    }
}

TEST(tin_keeps_nodata_holes_as_holes)
{
    rf_asc_grid g = grid_of(61, 47, holed);
    double valid = 0;
    for (long j = 0; j + 1 < 47; j++)
        for (long i = 0; i + 1 < 61; i++) {
            valid += !bad(&g, i, j) && !bad(&g, i + 1, j) && !bad(&g, i + 1, j + 1);
            valid += !bad(&g, i, j) && !bad(&g, i + 1, j + 1) && !bad(&g, i, j + 1);
        }
    double tols[] = {0.5, 0.05};
    for (size_t n = 0; n < 2; n++) {
        rf_tin_stats st;
        rf_tri_list l = tin_of(&g, tols[n], &st);
        ENSURE_MSG(st.dropped > 0 && st.vertices < (n == 0 ? 61 * 47 / 2 : 61 * 47), "%zu dropped, %zu vertices", st.dropped, st.vertices);
        double area, worst = tin_error(&g, &l, &area);
        ENSURE_MSG(worst <= tols[n] * (1 + 1e-9), "error %.17g", worst);
        /* the kept triangles cover the valid grid triangles' area exactly ... */
        ENSURE_MSG(fabs(area - valid / 2.0) < 1e-9, "area %.17g, valid %.17g", area, valid / 2);
        ensure_no_hole_covered(&g, &l); /* ... and no hole */
        rf_tri_list_free(&l);
    }
    rf_asc_free(&g);
}

/* The project key: the Noto grid as a TIN is a mesh whose height is within the
 * tolerance of the grid's everywhere (nodes and random points), with fewer triangles. */
TEST(tin_project_tolerance_builds_a_mesh_within_it)
{
    rf_terrain_spec spec = {0};
    char *files[1] = {"projects/noto/terrain.asc"};
    spec.source = RF_TERRAIN_DEM;
    spec.files = files;
    spec.nfiles = 1;
    spec.surface = (rf_surface){{0.3, 0}, {0.3, 0}, {0.3, 0}};
    rf_terrain grid, tin;
    rf_error err;
    ENSURE_MSG(rf_terrain_build(&spec, &grid, &err) == 0, "%s", err.message);
    spec.tolerance = 0.05;
    ENSURE_MSG(rf_terrain_build(&spec, &tin, &err) == 0, "%s", err.message);
    ENSURE(grid.is_grid == 1 && tin.is_grid == 0);
    ENSURE(tin.ntri < grid.ntri / 2);
    double worst = 0;
    for (size_t j = 0; j < grid.ny; j++)
        for (size_t i = 0; i < grid.nx; i++) {
            double x = grid.x0 + (double)i * grid.cell, y = grid.y0 + (double)j * grid.cell;
            double zg = 0, zt = 0;
            ENSURE(rf_terrain_height(&grid, x, y, &zg) >= 0 && rf_terrain_height(&tin, x, y, &zt) >= 0);
            worst = fmax(worst, fabs(zg - zt));
        }
    uint64_t s = 99;
    for (int k = 0; k < 100000; k++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        double x = grid.xmin + (grid.xmax - grid.xmin) * (double)(s >> 11) / 9007199254740992.0;
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        double y = grid.ymin + (grid.ymax - grid.ymin) * (double)(s >> 11) / 9007199254740992.0;
        double zg = 0, zt = 0;
        ENSURE(rf_terrain_height(&grid, x, y, &zg) >= 0 && rf_terrain_height(&tin, x, y, &zt) >= 0);
        worst = fmax(worst, fabs(zg - zt));
    }
    ENSURE_MSG(worst <= 0.05 + 1e-9 && worst > 0.01, "worst %.17g", worst);
    rf_terrain_free(&grid);
    rf_terrain_free(&tin);
}

TEST(tin_grid_too_long_a_side_is_refused_at_the_dem)
{
    size_t nx = RF_TIN_SIDE_MAX + 1;
    char *asc = malloc(nx * 2 * 3 + 200);
    ENSURE(asc);
    int n = sprintf(asc, "ncols %zu\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n", nx);
    for (size_t k = 0; k < 2 * nx; k++)
        n += sprintf(asc + n, "%d ", (int)(k % 3));
    rf_test_write("long.asc", asc);
    free(asc);
    const char *path = rf_test_write("long.yaml",
                                     "name: long\n"
                                     "terrain:\n"
                                     "  dem: long.asc\n"
                                     "  tolerance: 0.1\n"
                                     "rocks:\n"
                                     "  - {name: r1, mass: 100}\n"
                                     "releases:\n"
                                     "  - {name: A, point: [5, 0.5], rock: r1}\n");
    rf_project p;
    rf_error err = {{0}};
    ENSURE(rf_project_load(path, &p, &err) != 0);
    ENSURE_MSG(strstr(err.message, "too large for 'tolerance'") && strstr(err.file, "long.yaml") &&
                   err.line == 3 && err.column == 8,
               "%s:%d:%d: %s", err.file, err.line, err.column, err.message);
}

/* Random small grids with random nodata (scattered nodes and blocks, corners among
 * them) and random tolerances: the bound, the exact cover of the valid grid triangles
 * and no measurement left without a node to insert, every time. */
TEST(tin_random_grids_with_holes_keep_bound_and_cover)
{
    uint64_t s = 2385;
    for (int round = 0; round < 300; round++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        size_t nx = 2 + (size_t)(s >> 59), ny = 2 + (size_t)((s >> 54) & 31);
        double share = (double)((s >> 40) & 255) / 600.0; /* nodata share up to 0.43 */
        double tol = round % 5 == 0 ? 0.0 : (double)((s >> 20) & 1023) / 1000.0;
        rf_asc_grid g = {nx, ny, -3.5, 7.25, 0.5, 1, NODATA, malloc(nx * ny * sizeof(double))};
        ENSURE(g.z);
        size_t bx = (size_t)(s >> 8) % nx, by = (size_t)(s >> 16) % ny; /* a nodata block */
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                double u = noise((long)i + 1000 * round, (long)j);
                int block = i >= bx && i < bx + 3 && j >= by && j < by + 2;
                g.z[j * nx + i] = u < share || block ? NODATA : rough((long)i, (long)j) + u;
            }
        double valid = 0;
        for (long j = 0; j + 1 < (long)ny; j++)
            for (long i = 0; i + 1 < (long)nx; i++) {
                valid += !bad(&g, i, j) && !bad(&g, i + 1, j) && !bad(&g, i + 1, j + 1);
                valid += !bad(&g, i, j) && !bad(&g, i + 1, j + 1) && !bad(&g, i, j + 1);
            }
        rf_tin_stats st;
        rf_tri_list l = {NULL, 0, 0};
        rf_error err;
        ENSURE_MSG(rf_tin_build(&g, tol, "grid.asc", &l, &st, &err) == 0, "%s", err.message);
        ENSURE_MSG(st.unresolved == 0 && st.triangles == l.n, "round %d: unresolved %zu", round,
                   st.unresolved);
        double area, worst = tin_error(&g, &l, &area);
        ENSURE_MSG(worst <= tol * (1 + 1e-9) + 1e-12, "round %d (%zu x %zu, T %g): error %.17g",
                   round, nx, ny, tol, worst);
        ENSURE_MSG(fabs(area - valid / 2.0) < 1e-9, "round %d: area %.17g, valid %.17g", round,
                   area, valid / 2);
        ensure_no_hole_covered(&g, &l);
        rf_tri_list_free(&l);
        rf_asc_free(&g);
    }
}
