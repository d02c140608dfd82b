/* terrain.h - the triangulated slope (Eq. 3-7): sources, surface zones, point location.
 *
 * A terrain is a height field z = f(x, y) made of triangles.  Each triangle keeps its
 * vertices, its unit normal n (always pointing up: n.z >= 0) and its offset d with
 * dot(n, p) = d on the plane.  That form stays exact for near-vertical faces, where
 * Eq. 3's a, b blow up; rf_triangle_plane_abd() still gives Eq. 4 for tests.
 *
 * Point location is O(1) on grids (direct cell arithmetic) and goes through a uniform
 * bucket grid on meshes; neither scans all triangles. */
#ifndef ROCKFALL_TERRAIN_H
#define ROCKFALL_TERRAIN_H

#include <stddef.h>
#include <stdint.h>

#include "rockfall/error.h"
#include "rockfall/vec3.h"

/* A normal distribution given by mean and standard deviation (sd = 0: constant). */
typedef struct rf_dist {
    double mean, sd;
} rf_dist;

/* The impact law of a surface (docs/engine.md, "Impact"). */
typedef enum rf_impact_law {
    RF_IMPACT_EQ8, /* the paper's Eq. 8: restitution e_n, Coulomb impulse up to rolling */
    RF_IMPACT_RT   /* tangential restitution: the centre's tangential velocity times R_t */
} rf_impact_law;

/* Contact properties of a surface; drawn per impact, truncated (restitution and
 * tangential to [0, 1], friction and rolling resistance to [0, inf)).  Zeroed fields
 * beyond rolling are the defaults: Eq. 8, no roughness. */
typedef struct rf_surface {
    rf_dist restitution; /* normal coefficient of restitution e_n (Eq. 8) */
    rf_dist friction;    /* Coulomb friction mu at impacts and in sliding */
    rf_dist rolling;     /* rolling resistance coefficient mu_r of a rolling sphere */
    double roughness;    /* r_s (m, >= 0): the contact normal's random tilt at a bounce */
    rf_impact_law law;   /* default RF_IMPACT_EQ8 */
    rf_dist tangential;  /* R_t of RF_IMPACT_RT (unused by Eq. 8) */
    int rolling_is_friction; /* the project gave no rolling resistance: it is the
                                friction (a calibration moving one moves both) */
} rf_surface;

/* Table 2: recommended equivalent friction coefficient of slope classes 'A'..'D'.
 * Returns the recommended value, or a negative number for an unknown class. */
double rf_table2_friction(char slope_class);
/* Table 2's range of the class as a normal distribution (mean = recommended value). */
rf_dist rf_table2_friction_dist(char slope_class);

typedef struct rf_triangle {
    rf_vec3 a, b, c; /* vertices */
    rf_vec3 n;       /* unit normal, n.z >= 0 */
    double d;        /* plane offset: dot(n, p) = d */
    int32_t zone;    /* index into rf_terrain.zones */
} rf_triangle;

typedef struct rf_zone {
    char *name;
    rf_surface surface;
} rf_zone;

/* A polygon zone as the project file gives it. */
typedef struct rf_zone_spec {
    char *name;
    double *poly_xy;   /* 2 * npoly numbers (x0, y0, x1, y1, ...); NULL for a file zone */
    size_t npoly;
    char *file;        /* mesh file this zone is (resolved path), or NULL */
    rf_surface surface;
} rf_zone_spec;

typedef enum rf_terrain_source {
    RF_TERRAIN_DEM,     /* ESRI ASCII grid */
    RF_TERRAIN_MESH,    /* one or more STL (ascii/binary) or OBJ files forming one surface */
    RF_TERRAIN_PROFILE  /* 2D slope profile (distance, elevation) extruded across a width */
} rf_terrain_source;

/* What the project file says about the terrain; paths are already resolved. */
typedef struct rf_terrain_spec {
    rf_terrain_source source;
    char **files;          /* DEM: 1 file; MESH: nfiles files */
    size_t nfiles;
    char up;               /* 'z' (default) or 'y' for meshes in a y-up frame */
    double *profile;       /* PROFILE: 2 * nprofile numbers (distance, elevation) */
    size_t nprofile;
    double width;          /* PROFILE: extrusion width; y runs from 0 to width */
    double tolerance;      /* DEM: > 0 makes the grid a TIN within this vertical error
                              (m; input/tin.h), a mesh (is_grid 0); 0 keeps the grid */
    int grid_derive;       /* DEM: 1 derives the triangles of the grid from its heights
                              whatever its size (tests); 0 keeps them in an array up to
                              RF_GRID_KEEP_TRIANGLES (rf_terrain.tri) */
    rf_surface surface;    /* default surface (zone 0) */
    rf_zone_spec *zones;   /* polygon zones and file zones */
    size_t nzones;
} rf_terrain_spec;

/* A grid of at most this many triangles keeps them in an array besides its heights (the
 * same triangles rf_grid_triangle derives, read faster: docs/terrain.md); a larger one
 * derives them where needed. */
#define RF_GRID_KEEP_TRIANGLES (1 << 20)

typedef struct rf_terrain {
    rf_triangle *tri; /* meshes and profiles, and grids of at most RF_GRID_KEEP_TRIANGLES
                         triangles (holes among them unset); NULL for a larger grid, whose
                         triangles rf_tri derives */
    size_t ntri;      /* triangle indices 0 .. ntri - 1 (a grid's include its holes) */
    rf_zone *zones; /* zones[0] is the default surface ("default") */
    size_t nzones;
    double xmin, xmax, ymin, ymax, zmin, zmax;

    /* DEM grids: O(1) location, kept as their heights.  Nodes at x0 + i*cell,
     * y0 + j*cell (i < nx, j < ny) of height z[j*nx+i] (NaN at nodata); cell (i, j)
     * spans nodes i..i+1, j..j+1 and holds triangles 2*(j*(nx-1)+i)+k, k = 0 below the
     * SW-NE diagonal (SW,SE,NE), k = 1 above it (SW,NE,NW).  grid_hole: per cell, bit k
     * set when triangle k is a hole (a nodata vertex, or no area); NULL when none is.
     * zone8 / zone16 / zone32: per triangle its zone when polygon zones exist (uint8_t
     * up to 256 zones, uint16_t up to 65 536, int32_t beyond); all NULL: zone 0. */
    int is_grid;
    size_t nx, ny;
    double x0, y0, cell;
    double *z;
    uint8_t *grid_hole;
    uint8_t *zone8;
    uint16_t *zone16;
    int32_t *zone32;

    /* Meshes and profiles (is_grid == 0): uniform bucket grid over the xy bounding box; the triangles whose
     * xy bounding box overlaps bucket b are bucket_items[bucket_start[b] ..
     * bucket_start[b+1]). */
    size_t nbx, nby;
    double bx0, by0, bsize;
    uint32_t *bucket_start;
    int32_t *bucket_items;
} rf_terrain;

/* A grid's triangle idx (not a hole), derived from its heights into out with the
 * arithmetic the grid's build and a mesh's triangles use: bit for bit the same. */
void rf_grid_triangle(const rf_terrain *t, int32_t idx, rf_triangle *out);
/* The vertices of a grid's triangle idx (a, b, c as rf_grid_triangle gives them). */
static inline void rf_grid_vertices(const rf_terrain *t, int32_t idx, rf_vec3 v[3])
{
    size_t c = (size_t)idx >> 1, row = t->nx - 1, j = c / row, i = c - j * row;
    const double *z = t->z + j * t->nx + i;
    double xw = t->x0 + (double)i * t->cell, xe = t->x0 + (double)(i + 1) * t->cell;
    double ys = t->y0 + (double)j * t->cell, yn = t->y0 + (double)(j + 1) * t->cell;
    v[0] = rf_v3(xw, ys, z[0]); /* SW */
    if ((idx & 1) == 0) {
        v[1] = rf_v3(xe, ys, z[1]);         /* SE */
        v[2] = rf_v3(xe, yn, z[t->nx + 1]); /* NE */
    } else {
        v[1] = rf_v3(xe, yn, z[t->nx + 1]); /* NE */
        v[2] = rf_v3(xw, yn, z[t->nx]);     /* NW */
    }
}

/* Triangle idx of terrain t (not a hole): a mesh's own, held in t; a grid's derived
 * into buf, which the pointer returned then points to (valid while buf is). */
static inline const rf_triangle *rf_tri(const rf_terrain *t, int32_t idx, rf_triangle *buf)
{
    if (t->tri)
        return &t->tri[idx];
    rf_grid_triangle(t, idx, buf);
    return buf;
}

/* Triangle idx of terrain t with only its vertices a, b, c to be read (a grid's derived
 * into buf without its plane): for culls before the face itself is needed. */
static inline const rf_triangle *rf_tri_corners(const rf_terrain *t, int32_t idx, rf_triangle *buf)
{
    if (t->tri)
        return &t->tri[idx];
    rf_vec3 v[3];
    rf_grid_vertices(t, idx, v);
    buf->a = v[0], buf->b = v[1], buf->c = v[2];
    return buf;
}

/* rf_tri into a buffer of the enclosing block (a compound literal): the pointer is not
 * to be kept beyond that block. */
#define RF_TRI(t, idx)                                                                           \
    ((t)->tri ? &(t)->tri[idx] : rf_tri((t), (idx), &(rf_triangle){.zone = 0}))

/* A grid's triangle index at slot 2*(j*(nx-1)+i)+k of cell (i, j), or -1 for a hole. */
static inline int32_t rf_grid_slot(const rf_terrain *t, size_t slot)
{
    return t->grid_hole && (t->grid_hole[slot >> 1] >> (slot & 1) & 1) ? -1 : (int32_t)slot;
}

/* A grid's triangle idx as 2 * (node index of its SW node) + k. */
static inline int64_t rf_grid_node(const rf_terrain *t, int32_t idx)
{
    size_t c = (size_t)idx >> 1, row = t->nx - 1, j = c / row, i = c - j * row;
    return 2 * (int64_t)(j * t->nx + i) + (idx & 1);
}

/* The zone of triangle idx. */
static inline int32_t rf_tri_zone(const rf_terrain *t, int32_t idx)
{
    if (t->tri)
        return t->tri[idx].zone;
    return t->zone8    ? t->zone8[idx]
           : t->zone16 ? t->zone16[idx]
           : t->zone32 ? t->zone32[idx]
                       : 0;
}

/* Builds a terrain from its spec.  Errors (missing or unreadable files, malformed
 * content with file:line:column inside the terrain file, empty meshes) fill err.
 * Returns 0 on success.  On failure nothing is left allocated in t. */
int rf_terrain_build(const rf_terrain_spec *spec, rf_terrain *t, rf_error *err);
void rf_terrain_free(rf_terrain *t);

/* Index of the triangle under (x, y), or -1 (outside the terrain or in a hole).  Where
 * projections overlap (a vertical wall), the triangle with the highest z there wins. */
int32_t rf_terrain_locate(const rf_terrain *t, double x, double y);
/* Height of the surface at (x, y); returns the triangle index or -1 (z untouched). */
int32_t rf_terrain_height(const rf_terrain *t, double x, double y, double *z);
/* Slope angle of a triangle in radians (0 flat, pi/2 vertical). */
double rf_triangle_slope(const rf_triangle *tri);
/* Height of the triangle's plane above (x, y) (undefined for a vertical face). */
double rf_triangle_z_at(const rf_triangle *tri, double x, double y);
/* Eq. 4: the coefficients of a X + b Y + Z = d (Eq. 3) of a non-vertical triangle. */
void rf_triangle_plane_abd(const rf_triangle *tri, double *a, double *b, double *d);
/* Eq. 5-6: barycentric (t, s) of the vertical projection of (x, y) with
 * P = t u + s v, u = j' - i', v = k' - i'.  Returns 1 when t, s >= -tol and
 * t + s <= 1 + tol. */
int rf_triangle_contains_xy(const rf_triangle *tri, double x, double y, double tol,
                            double *t_out, double *s_out);
/* Eq. 7 (and 9): signed distance of a point from the triangle's plane (positive above). */
double rf_triangle_plane_distance(const rf_triangle *tri, rf_vec3 p);
/* Closest point of the (closed) triangle to p: face, edge or vertex. */
rf_vec3 rf_triangle_closest_point(const rf_triangle *tri, rf_vec3 p);

/* Triangles whose xy bounding box may overlap [xmin,xmax] x [ymin,ymax].  Writes at
 * most cap indices into out, without duplicates, and returns how many there are in
 * all (may exceed cap: then call again with a larger buffer).  `stamp` is a caller-
 * owned workspace of t->ntri uint32 zeroed once, and `*epoch` a counter the call
 * advances (no hidden state: one workspace per thread). */
size_t rf_terrain_query_box(const rf_terrain *t, double xmin, double ymin, double xmax,
                            double ymax, int32_t *out, size_t cap, uint32_t *stamp,
                            uint32_t *epoch);

/* 1 when (x, y) is inside the polygon (even-odd rule; points on the boundary count as
 * inside), else 0.  Shared by terrain zones, forests and tests. */
int rf_point_in_polygon(const double *poly_xy, size_t npoly, double x, double y);

/* The most cells a hazard grid may have (each thread keeps one). */
#define RF_HAZARD_CELLS_MAX 1e7

/* The hazard grid's columns and rows over the terrain for square cells of `cell` (at
 * least one each, as numbers: no overflow). */
void rf_hazard_grid(const rf_terrain *t, double cell, double *nx, double *ny);

#endif
