/* project_read.c - the project loader's readers of the values every section uses
 * (see project_private.h). */
#include "input/project_private.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "input/bounds.h"

static const char *const dist_keys[] = {"mean", "sd", NULL};
static const char *const class_names[] = {"A", "B", "C", "D", NULL};
static const char *const impact_names[] = {"eq8", "rt", NULL};

/* ---- helpers ----------------------------------------------------------------- */

int rf_load_oom(loader *L)
{
    return rf_error_set(L->err, L->d.file, 0, 0, "out of memory");
}

char *rf_load_resolve(const char *dir, const char *rel)
{
    if (rel[0] == '/' || !strcmp(dir, "."))
        return strdup(rel);
    size_t n = strlen(dir) + strlen(rel) + 2;
    char *s = malloc(n);
    if (s)
        snprintf(s, n, "%s/%s", dir, rel);
    return s;
}

/* A directory or a pipe opens too, but is no file to read. */
int rf_load_readable(const char *path, char *why, size_t size)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        snprintf(why, size, "%s", S_ISDIR(st.st_mode) ? strerror(EISDIR) : "not a regular file");
        return 0;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(why, size, "%s", strerror(errno));
        return 0;
    }
    fclose(f);
    return 1;
}

int rf_load_name(loader *L, const rf_ynode *map, const char *what, char **out)
{
    rf_ynode *n;
    const char *s = NULL;
    if (rf_ydoc_require(&L->d, map, "name", what, &n, L->err) ||
        rf_ydoc_string(&L->d, n, "name", &s, L->err))
        return -1;
    *out = strdup(s);
    return *out ? 0 : rf_load_oom(L);
}

/* The name of item i of a list's array. */
static char **item_name(const item_list *list, void *array, size_t i)
{
    return (char **)((char *)array + i * list->size + list->name_offset);
}

/* Starts item i of a list: a mapping with only the list's keys and a name that no
 * earlier item has (names indexes them).  *count becomes i + 1 once the item holds its
 * name, so that freeing the project frees it.  `what` gets "LIST item N", which names
 * the item in its other messages. */
static int read_item(loader *L, const rf_ynode *n, size_t i, const item_list *list,
                     void *array, size_t *count, rf_names *names, char what[WHAT_SIZE])
{
    char **name = item_name(list, array, i);
    snprintf(what, WHAT_SIZE, "%s item %zu", list->key, i + 1);
    if (rf_ydoc_mapping_of(&L->d, n, list->keys, what, L->err) || rf_load_name(L, n, what, name))
        return -1;
    *count = i + 1;
    int oom;
    size_t j = rf_names_add(names, *name, i, &oom);
    if (oom)
        return rf_load_oom(L);
    if (j != RF_NAMES_ABSENT)
        return rf_ydoc_error(&L->d, rf_ydoc_get(&L->d, n, "name"), L->err,
                             "duplicate %s name '%s' (%s item %zu has it too)", list->kind,
                             *name, list->key, j + 1);
    return 0;
}

int rf_load_list(loader *L, const rf_ynode *parent, const item_list *list, int required,
                 void **array, size_t *count,
                 int (*item)(loader *, const rf_ynode *, size_t, const char *), rf_names *names)
{
    rf_ynode *n = rf_ydoc_get(&L->d, parent, list->key);
    if (!n) {
        if (required)
            return rf_ydoc_error(&L->d, parent, L->err,
                                 "missing required key '%s' in the project file", list->key);
        return 0;
    }
    if (rf_ydoc_sequence(&L->d, n, list->key, required ? 1 : 0, list->items, L->err))
        return -1;
    size_t size = rf_ydoc_seq_size(n);
    if (!size)
        return 0;
    *array = calloc(size, list->size);
    rf_names own;
    if (!*array || rf_names_init(&own, size))
        return rf_load_oom(L);
    int rc = 0;
    for (size_t i = 0; i < size && rc == 0; i++) {
        rf_ynode *node = rf_ydoc_seq_item(&L->d, n, i);
        char what[WHAT_SIZE];
        rc = read_item(L, node, i, list, *array, count, &own, what) || item(L, node, i, what);
    }
    if (rc == 0 && names)
        *names = own;
    else
        rf_names_free(&own);
    return rc ? -1 : 0;
}

int rf_load_bounded(loader *L, const rf_ynode *n, const char *key, double v, double lo,
                    double hi, const char *unit)
{
    if (v >= lo && v <= hi)
        return 0;
    char got[64];
    return rf_ydoc_error(&L->d, n, L->err, "'%s' must be from %g to %g%s%s, got %s", key, lo, hi,
                         unit[0] ? " " : "", unit, rf_ydoc_describe(n, got, sizeof got));
}

int rf_load_dist(loader *L, const rf_ynode *n, const char *key, rf_yrange mean_range,
                 double mean_max, double sd_max, rf_dist *out)
{
    char k[64];
    if (n->type == YAML_SCALAR_NODE) {
        out->sd = 0.0;
        return rf_ydoc_number(&L->d, n, key, mean_range, &out->mean, L->err) ||
                       rf_load_bounded(L, n, key, out->mean, mean_range.lo, mean_max, "")
                   ? -1
                   : 0;
    }
    if (n->type != YAML_MAPPING_NODE) {
        char got[64];
        return rf_ydoc_error(&L->d, n, L->err,
                             "'%s' must be a number or a mapping {mean, sd}, got %s", key,
                             rf_ydoc_describe(n, got, sizeof got));
    }
    snprintf(k, sizeof k, "'%s'", key);
    rf_ynode *mean;
    if (rf_ydoc_check_keys(&L->d, n, dist_keys, k, L->err) ||
        rf_ydoc_require(&L->d, n, "mean", k, &mean, L->err))
        return -1;
    snprintf(k, sizeof k, "%s.mean", key);
    if (rf_ydoc_number(&L->d, mean, k, mean_range, &out->mean, L->err) ||
        rf_load_bounded(L, mean, k, out->mean, mean_range.lo, mean_max, ""))
        return -1;
    out->sd = 0.0;
    snprintf(k, sizeof k, "%s.sd", key);
    rf_ynode *sd = rf_ydoc_get(&L->d, n, "sd");
    if (sd && (rf_ydoc_number(&L->d, sd, k, RF_YR_NONNEG, &out->sd, L->err) ||
               rf_load_bounded(L, sd, k, out->sd, 0.0, sd_max, "")))
        return -1;
    return 0;
}

int rf_load_opt_dist(loader *L, const rf_ynode *map, const char *key, rf_yrange mean_range,
                     double mean_max, double sd_max, rf_dist *out)
{
    rf_ynode *n = rf_ydoc_get(&L->d, map, key);
    return n ? rf_load_dist(L, n, key, mean_range, mean_max, sd_max, out) : 0;
}

int rf_load_tuple(loader *L, const rf_ynode *n, const char *key, size_t dims, const char *shape,
                  double max_abs, const char *unit, double *out)
{
    char got[64];
    if (n->type != YAML_SEQUENCE_NODE)
        return rf_ydoc_error(&L->d, n, L->err, "'%s' must be %s, got %s", key, shape,
                             rf_ydoc_describe(n, got, sizeof got));
    size_t size = rf_ydoc_seq_size(n);
    if (size != dims)
        return rf_ydoc_error(&L->d, n, L->err, "'%s' must be %s (%zu numbers), got %zu", key,
                             shape, dims, size);
    for (size_t i = 0; i < dims; i++) {
        rf_ynode *item = rf_ydoc_seq_item(&L->d, n, i);
        if (rf_ydoc_number(&L->d, item, key, RF_YR_ANY, &out[i], L->err) ||
            rf_load_bounded(L, item, key, out[i], -max_abs, max_abs, unit))
            return -1;
    }
    return 0;
}

int rf_load_points(loader *L, const rf_ynode *n, const char *key, size_t min_points, double **xy,
                   size_t *count)
{
    if (rf_ydoc_sequence(&L->d, n, key, min_points, "points [x, y]", L->err))
        return -1;
    size_t np = rf_ydoc_seq_size(n);
    double *v = malloc(2 * np * sizeof *v);
    if (!v)
        return rf_load_oom(L);
    for (size_t i = 0; i < np; i++) {
        if (rf_load_tuple(L, rf_ydoc_seq_item(&L->d, n, i), key, 2, "a list of points [x, y]",
                          RF_COORD_MAX, "m", v + 2 * i)) {
            free(v);
            return -1;
        }
    }
    *xy = v;
    *count = np;
    return 0;
}

int rf_load_polyline(loader *L, const rf_ynode *n, const char *key, size_t min_points,
                     rf_polyline *out)
{
    return rf_load_points(L, n, key, min_points, &out->xy, &out->n);
}

/* roughness, impact and tangential of a surface (absent: those of the base).  A zone
 * that names no law keeps the base's law and R_t; `tangential` belongs to the rt law
 * and is required with it (the zone's own or its base's). */
static int load_impact(loader *L, const rf_ynode *map, rf_surface *out)
{
    if (rf_ydoc_opt_number(&L->d, map, "roughness", RF_YR_BETWEEN(0.0, RF_ROUGHNESS_MAX),
                           &out->roughness, L->err))
        return -1;
    rf_ynode *law = rf_ydoc_get(&L->d, map, "impact");
    rf_ynode *tangential = rf_ydoc_get(&L->d, map, "tangential");
    int given_law = -1, had_rt = out->law == RF_IMPACT_RT;
    if (law) {
        if (rf_ydoc_enum(&L->d, law, "impact", impact_names, &given_law, L->err))
            return -1;
        out->law = given_law == 1 ? RF_IMPACT_RT : RF_IMPACT_EQ8;
    }
    if (tangential) {
        if (out->law != RF_IMPACT_RT)
            return rf_ydoc_error(&L->d, tangential, L->err,
                                 "'tangential' is the rt impact law's R_t; give 'impact: rt' "
                                 "with it");
        if (rf_load_dist(L, tangential, "tangential", RF_YR_UNIT, 1.0, 1.0, &out->tangential))
            return -1;
    } else if (given_law == 1 && !had_rt) {
        return rf_ydoc_error(&L->d, law, L->err,
                             "'impact: rt' needs 'tangential' (R_t, from 0 to 1) beside it");
    }
    return 0;
}

int rf_load_surface(loader *L, const rf_ynode *map, const rf_surface *base, int inherit_rolling,
                    rf_surface *out, int *rolling_given)
{
    *out = *base;
    rf_ynode *cls = rf_ydoc_get(&L->d, map, "class");
    rf_ynode *friction = rf_ydoc_get(&L->d, map, "friction");
    rf_ynode *rolling = rf_ydoc_get(&L->d, map, "rolling");
    if (rf_load_opt_dist(L, map, "restitution", RF_YR_UNIT, 1.0, 1.0, &out->restitution))
        return -1;
    if (friction &&
        rf_load_dist(L, friction, "friction", RF_YR_NONNEG, RF_FRICTION_MAX, RF_FRICTION_MAX,
                     &out->friction))
        return -1;
    if (cls) {
        int c;
        if (rf_ydoc_enum(&L->d, cls, "class", class_names, &c, L->err))
            return -1;
        if (friction)
            return rf_ydoc_error(&L->d, cls, L->err,
                                 "'class' sets the friction from Table 2 and cannot be "
                                 "given together with 'friction'");
        out->friction = rf_table2_friction_dist((char)('A' + c));
    }
    if (rolling) {
        if (rf_load_dist(L, rolling, "rolling", RF_YR_NONNEG, RF_FRICTION_MAX, RF_FRICTION_MAX,
                         &out->rolling))
            return -1;
        out->rolling_is_friction = 0;
    } else if (!inherit_rolling) {
        out->rolling = out->friction;
        out->rolling_is_friction = 1;
    }
    if (rolling_given)
        *rolling_given = rolling != NULL;
    return load_impact(L, map, out);
}
