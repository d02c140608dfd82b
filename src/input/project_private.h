/* project_private.h - the project loader's shared parts: its state and the readers of
 * the values every section uses (names, lists of named items, distributions, points,
 * surfaces).  project.c reads the sections; project_read.c holds these readers. */
#ifndef ROCKFALL_PROJECT_PRIVATE_H
#define ROCKFALL_PROJECT_PRIVATE_H

#include <stddef.h>

#include "base/names.h"
#include "input/layout.h"
#include "input/yamldoc.h"
#include "rockfall/project.h"

typedef struct loader {
    rf_ydoc d;
    rf_project *p;
    rf_error *err;
    rf_ynode **file_nodes;   /* YAML node of each terrain file path */
    rf_ynode **point_nodes;  /* YAML node of each release point */
    rf_ynode **line_nodes;   /* YAML node of each measure line */
    rf_ynode *cell_node;     /* hazard: cell, when given */
    int rolling_given;       /* the terrain surface sets rolling explicitly */
    rf_names rock_names;     /* the rocks' names: a rock's index by its name */
    rf_names file_names;     /* the terrain files' resolved paths: a file's index */
    rf_layouts layouts;      /* the GeoPackage layers the lists' {gpkg, layer} items read */
} loader;

/* Room for "LIST item N", which names a list item in messages. */
#define WHAT_SIZE 64

/* A list of named items: its key ("rocks"), an item's kind in messages ("rock"), what
 * its items are called when it is no sequence, an item's keys, and an item's size and
 * where it keeps its name. */
typedef struct item_list {
    const char *key, *kind, *items;
    const char *const *keys;
    size_t size, name_offset;
} item_list;

/* "out of memory" at the project file; returns -1. */
int rf_load_oom(loader *L);
/* A path from the project file, relative to the project file's directory (malloc'd). */
char *rf_load_resolve(const char *dir, const char *rel);
/* 1 when path names a regular file that opens for reading; otherwise 0, why set. */
int rf_load_readable(const char *path, char *why, size_t size);
/* The required non-empty string under "name", copied. */
int rf_load_name(loader *L, const rf_ynode *map, const char *what, char **out);
/* The list under its key in `parent` (a sequence; at least one item when required) into
 * a new *array of *count items: each a mapping with only the list's keys and a name no
 * earlier item has (found through a hash of the names: linear in the items), then
 * item(L, node, i, what) reads the rest.  With `names` not NULL the index of the names
 * is kept there (the caller frees it). */
int rf_load_list(loader *L, const rf_ynode *parent, const item_list *list, int required,
                 void **array, size_t *count,
                 int (*item)(loader *, const rf_ynode *, size_t, const char *), rf_names *names);
/* A value v read from node n within the bounds of input/bounds.h: 0 when lo <= v <= hi,
 * else an error at n, "'KEY' must be from LO to HI UNIT, got V" (the bound checked after
 * the value's own reader, whose messages name its type and sign). */
int rf_load_bounded(loader *L, const rf_ynode *n, const char *key, double v, double lo,
                    double hi, const char *unit);
/* A DIST: {mean: number, sd: number >= 0} or a plain number (sd 0); the mean at most
 * mean_max, the sd at most sd_max. */
int rf_load_dist(loader *L, const rf_ynode *n, const char *key, rf_yrange mean_range,
                 double mean_max, double sd_max, rf_dist *out);
int rf_load_opt_dist(loader *L, const rf_ynode *map, const char *key, rf_yrange mean_range,
                     double mean_max, double sd_max, rf_dist *out);
/* [a, b, ...]: exactly `dims` numbers, each within -max_abs..max_abs (unit names their
 * unit in messages). */
int rf_load_tuple(loader *L, const rf_ynode *n, const char *key, size_t dims, const char *shape,
                  double max_abs, const char *unit, double *out);
/* [[x, y], ...] with at least min_points points, each within RF_COORD_MAX; *xy is
 * allocated. */
int rf_load_points(loader *L, const rf_ynode *n, const char *key, size_t min_points, double **xy,
                   size_t *count);
int rf_load_polyline(loader *L, const rf_ynode *n, const char *key, size_t min_points,
                     rf_polyline *out);
/* restitution / friction / rolling / class of a surface; absent values keep `base`.
 * rolling defaults to this surface's friction unless `inherit_rolling` is set. */
int rf_load_surface(loader *L, const rf_ynode *map, const rf_surface *base, int inherit_rolling,
                    rf_surface *out, int *rolling_given);

/* src/input/release.c: a release's `point`, `area` or `cells` (exactly one; *where is
 * set to its node), a rock's `mass`, and the check that a release's sources lie on the
 * built terrain (setting its x, y, z). */
int rf_load_release_source(loader *L, const rf_ynode *n, rf_release *r, const char *what,
                           rf_ynode **where);
int rf_load_rock_mass(loader *L, const rf_ynode *n, rf_rock *r, const char *what,
                      rf_ynode **where);
int rf_place_release(loader *L, rf_release *r, const rf_ynode *where);
/* Each mass of a rock's mass list gives a radius within the bounds (its density read). */
int rf_check_mass_radii(loader *L, const rf_ynode *mass, const rf_rock *r);
void rf_release_free(rf_release *r);

#endif
