/* terrain_io.h - readers of terrain files: ESRI ASCII grids, STL (ascii and binary)
 * and OBJ meshes.  Every reader fills an rf_error naming the file (with line and
 * column for malformed text) and leaves nothing allocated when it fails. */
#ifndef ROCKFALL_TERRAIN_IO_H
#define ROCKFALL_TERRAIN_IO_H

#include <stddef.h>

#include "rockfall/error.h"
#include "rockfall/vec3.h"

/* An ESRI ASCII grid: node (i, j) is at (x0 + i cell, y0 + j cell) with elevation
 * z[j * ncols + i]; j = 0 is the southernmost row. */
typedef struct rf_asc_grid {
    size_t ncols, nrows;
    double x0, y0, cell;
    int has_nodata;
    double nodata;
    double *z;
} rf_asc_grid;

/* Terrain and points files are mapped, not copied: each is a regular file of at most
 * RF_TERRAIN_FILE_MAX bytes (input/bounds.h).  The *_from_memory readers parse len bytes
 * at data (no NUL needed) as the file `name`, which names it in errors. */
int rf_asc_read(const char *path, rf_asc_grid *g, rf_error *err);
int rf_asc_read_from_memory(const char *data, size_t len, const char *name, rf_asc_grid *g,
                            rf_error *err);
void rf_asc_free(rf_asc_grid *g);

/* A growing list of triangles, three vertices each (v[3k], v[3k+1], v[3k+2]). */
typedef struct rf_tri_list {
    rf_vec3 *v;
    size_t n, cap; /* triangles */
} rf_tri_list;

/* Appends the triangles of an STL (ascii or binary) or OBJ file to out, chosen by the
 * extension (".obj", case-insensitive, is OBJ; anything else STL).  With up == 'y' the
 * file's (x, y, z) becomes the world's (x, z, y).  On failure out keeps what it held
 * before the call. */
int rf_mesh_read(const char *path, char up, rf_tri_list *out, rf_error *err);
/* obj: 1 for OBJ, 0 for STL (binary when the size matches its triangle count). */
int rf_mesh_read_from_memory(const char *data, size_t len, const char *name, int obj, char up,
                             rf_tri_list *out, rf_error *err);
void rf_tri_list_free(rf_tri_list *l);

/* Rows of at least ncol numbers from a text file (blank lines and lines starting with
 * '#' skipped; columns beyond ncol ignored): v[row * ncol + col]. */
typedef struct rf_points {
    double *v;
    size_t n;
} rf_points;

/* Reads path; a bad row is an error at its line and column. */
int rf_points_read(const char *path, size_t ncol, rf_points *out, rf_error *err);
int rf_points_read_from_memory(const char *data, size_t len, const char *name, size_t ncol,
                               rf_points *out, rf_error *err);
void rf_points_free(rf_points *p);

#endif
