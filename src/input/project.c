/* project.c - the project file (YAML): parse, validate and build at the boundary.
 *
 * One pass over the document fills rf_project with defaults and checks every value;
 * then the terrain is built and each release is placed on it.  Every error names the
 * file, line and column of the offending YAML node. */
#include "rockfall/project.h"
#include "rockfall/body.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/util.h"
#include "input/bounds.h"
#include "input/crs.h"
#include "input/measure_kinds.h"
#include "input/project_private.h"
#include "input/yamldoc.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif


static const char *const top_keys[] = {"name", "seed", "terrain", "vegetation", "rocks",
                                       "releases", "measures", "simulation", "hazard",
                                       "rules", "crs", NULL};
static const char *const terrain_keys[] = {"dem", "mesh", "profile", "up", "surface",
                                           "zones", "tolerance", NULL};
static const char *const profile_keys[] = {"points", "width", NULL};
static const char *const surface_keys[] = {"restitution", "friction", "rolling", "class",
                                           "roughness", "impact", "tangential", NULL};
static const char *const zone_keys[] = {"name", "polygon", "file", "restitution",
                                        "friction", "rolling", "class", "roughness",
                                        "impact", "tangential", NULL};
static const char *const forest_keys[] = {"name", "polygon", "density", "height", "diameter",
                                          "restitution", "friction", NULL};
static const char *const rock_keys[] = {"name", "mass", "density", "action_level", NULL};
static const char *const release_keys[] = {"name", "point", "area", "cells", "rock", "count", "height",
                                           "velocity", "jitter", NULL};
static const char *const simulation_keys[] = {"model", "engine", "dt", "contact",
                                              "stop_speed", "max_time", "paths", NULL};
static const char *const hazard_keys[] = {"cell", NULL};

static const item_list zone_list = {"zones", "zone", "zones", zone_keys,
                                    sizeof(rf_zone_spec), offsetof(rf_zone_spec, name)};
static const item_list forest_list = {"vegetation", "vegetation", "entries", forest_keys,
                                      sizeof(rf_forest), offsetof(rf_forest, name)};
static const item_list rock_list = {"rocks", "rock", "entries", rock_keys, sizeof(rf_rock),
                                    offsetof(rf_rock, name)};
static const item_list release_list = {"releases", "release", "entries", release_keys,
                                       sizeof(rf_release), offsetof(rf_release, name)};
static const item_list measure_list = {"measures", "measure", "entries", rf_measure_item_keys,
                                       sizeof(rf_measure), offsetof(rf_measure, name)};

const char *const rf_limit_state_names[RF_N_LIMIT_STATES + 1] = {
    "serviceability", "restorability", "ultimate", "near_collapse", NULL};
const char *const rf_importance_names[RF_N_IMPORTANCES + 1] = {"most_important", "important",
                                                               "usual", NULL};

static const char *const behaviour_names[] = {"stop", "collect", NULL};
static const char *const model_names[] = {"sphere", "point", NULL};
static const char *const engine_names[] = {"exact", "fixed_step", NULL};
static const char *const contact_names[] = {"full", "centre", NULL};
static const char *const up_names[] = {"z", "y", NULL};

const char *rf_importance_name(rf_importance i)
{
    return (unsigned)i < RF_N_IMPORTANCES ? rf_importance_names[i] : "?";
}

const char *rf_behaviour_name(rf_behaviour b)
{
    return (unsigned)b < 2 ? behaviour_names[b] : "?";
}

const char *rf_limit_state_name(rf_limit_state s)
{
    if (s == RF_COLLAPSE)
        return "collapse";
    return (unsigned)s < RF_N_LIMIT_STATES ? rf_limit_state_names[s] : "?";
}

/* ---- terrain ----------------------------------------------------------------- */

static int add_file(loader *L, rf_ynode *n)
{
    rf_terrain_spec *s = &L->p->terrain_spec;
    const char *path = NULL;
    if (rf_ydoc_string(&L->d, n, s->source == RF_TERRAIN_DEM ? "dem" : "mesh", &path, L->err))
        return -1;
    char *resolved = rf_load_resolve(L->p->dir, path);
    if (!resolved)
        return rf_load_oom(L);
    s->files[s->nfiles] = resolved;
    L->file_nodes[s->nfiles] = n;
    s->nfiles++;
    char why[256];
    if (!rf_load_readable(resolved, why, sizeof why))
        return rf_ydoc_error(&L->d, n, L->err, "cannot open terrain file '%s': %s", resolved,
                             why);
    return 0;
}

static int read_profile(loader *L, const rf_ynode *n)
{
    rf_terrain_spec *s = &L->p->terrain_spec;
    rf_ynode *points, *width;
    if (rf_ydoc_mapping_of(&L->d, n, profile_keys, "'profile'", L->err) ||
        rf_ydoc_require(&L->d, n, "points", "'profile'", &points, L->err) ||
        rf_ydoc_require(&L->d, n, "width", "'profile'", &width, L->err))
        return -1;
    if (rf_load_points(L, points, "points", 2, &s->profile, &s->nprofile))
        return -1;
    for (size_t i = 1; i < s->nprofile; i++) {
        if (!(s->profile[2 * i] > s->profile[2 * (i - 1)]))
            return rf_ydoc_error(&L->d, rf_ydoc_seq_item(&L->d, points, i), L->err,
                                 "profile 'points' must have strictly increasing distances; "
                                 "point %zu has distance %g after %g",
                                 i + 1, s->profile[2 * i], s->profile[2 * (i - 1)]);
    }
    if (rf_ydoc_number(&L->d, width, "width", RF_YR_POSITIVE, &s->width, L->err))
        return -1;
    return rf_load_bounded(L, width, "width", s->width, 0.0, RF_PROFILE_WIDTH_MAX, "m");
}

static int read_zone(loader *L, const rf_ynode *n, size_t index, const char *what)
{
    rf_terrain_spec *s = &L->p->terrain_spec;
    rf_zone_spec *z = &s->zones[index];
    rf_ynode *polygon = rf_ydoc_get(&L->d, n, "polygon");
    rf_ynode *file = rf_ydoc_get(&L->d, n, "file");
    if (polygon && file)
        return rf_ydoc_error(&L->d, file, L->err,
                             "a zone has either 'polygon' or 'file', not both");
    if (!polygon && !file)
        return rf_ydoc_error(&L->d, n, L->err, "%s needs 'polygon' or 'file'", what);
    if (polygon && rf_load_points(L, polygon, "polygon", 3, &z->poly_xy, &z->npoly))
        return -1;
    if (file) {
        const char *path = NULL;
        if (rf_ydoc_string(&L->d, file, "file", &path, L->err))
            return -1;
        if (s->source != RF_TERRAIN_MESH)
            return rf_ydoc_error(&L->d, file, L->err,
                                 "a zone 'file' needs a 'mesh' terrain; use 'polygon' here");
        z->file = rf_load_resolve(L->p->dir, path);
        if (!z->file)
            return rf_load_oom(L);
        if (rf_names_find(&L->file_names, z->file) == RF_NAMES_ABSENT)
            return rf_ydoc_error(&L->d, file, L->err,
                                 "zone 'file' must be one of the terrain's 'mesh' files, got "
                                 "'%s'",
                                 path);
    }
    return rf_load_surface(L, n, &s->surface, L->rolling_given, &z->surface, NULL);
}

static int read_terrain(loader *L, const rf_ynode *n)
{
    rf_terrain_spec *s = &L->p->terrain_spec;
    if (rf_ydoc_mapping_of(&L->d, n, terrain_keys, "'terrain'", L->err))
        return -1;
    rf_ynode *source = NULL;
    const char *source_key = NULL;
    size_t npairs = rf_ydoc_map_size(n);
    for (size_t i = 0; i < npairs; i++) {
        rf_ynode *k = rf_ydoc_map_key(&L->d, n, i);
        const char *key = (const char *)k->data.scalar.value;
        if (strcmp(key, "dem") && strcmp(key, "mesh") && strcmp(key, "profile"))
            continue;
        if (source)
            return rf_ydoc_error(&L->d, k, L->err,
                                 "'terrain' has both '%s' and '%s'; give exactly one of "
                                 "'dem', 'mesh' or 'profile'",
                                 source_key, key);
        source = rf_ydoc_map_value(&L->d, n, i);
        source_key = key;
    }
    if (!source)
        return rf_ydoc_error(&L->d, n, L->err,
                             "'terrain' needs one of 'dem', 'mesh' or 'profile'");

    s->up = 'z';
    rf_ynode *up = rf_ydoc_get(&L->d, n, "up");
    if (up) {
        int u;
        if (rf_ydoc_enum(&L->d, up, "up", up_names, &u, L->err))
            return -1;
        if (strcmp(source_key, "mesh"))
            return rf_ydoc_error(&L->d, up, L->err, "'up' applies to 'mesh' terrains only");
        s->up = u ? 'y' : 'z';
    }

    rf_ynode *tolerance = rf_ydoc_get(&L->d, n, "tolerance");
    if (tolerance) {
        if (rf_ydoc_number(&L->d, tolerance, "tolerance",
                           (rf_yrange){0.0, RF_TIN_TOLERANCE_MAX, 1, 0}, &s->tolerance, L->err))
            return -1;
        if (strcmp(source_key, "dem"))
            return rf_ydoc_error(&L->d, tolerance, L->err,
                                 "'tolerance' applies to 'dem' terrains only");
    }

    if (!strcmp(source_key, "profile")) {
        s->source = RF_TERRAIN_PROFILE;
        if (read_profile(L, source))
            return -1;
    } else {
        s->source = !strcmp(source_key, "dem") ? RF_TERRAIN_DEM : RF_TERRAIN_MESH;
        size_t count = 1;
        if (source->type == YAML_SEQUENCE_NODE) {
            if (s->source == RF_TERRAIN_DEM)
                return rf_ydoc_error(&L->d, source, L->err,
                                     "'dem' must be one file path, got a sequence");
            if (rf_ydoc_sequence(&L->d, source, "mesh", 1, "file paths", L->err))
                return -1;
            count = rf_ydoc_seq_size(source);
        }
        s->files = calloc(count, sizeof *s->files);
        L->file_nodes = calloc(count, sizeof *L->file_nodes);
        if (!s->files || !L->file_nodes)
            return rf_load_oom(L);
        for (size_t i = 0; i < count; i++)
            if (add_file(L, source->type == YAML_SEQUENCE_NODE
                                ? rf_ydoc_seq_item(&L->d, source, i)
                                : source))
                return -1;
    }

    rf_surface base = {{0.3, 0.0}, {0.3, 0.0}, {0.3, 0.0}};
    rf_ynode *surface = rf_ydoc_get(&L->d, n, "surface");
    s->surface = base;
    if (surface) {
        if (rf_ydoc_mapping_of(&L->d, surface, surface_keys, "'surface'", L->err) ||
            rf_load_surface(L, surface, &base, 0, &s->surface, &L->rolling_given))
            return -1;
    }

    /* the terrain's files by name, for the zones that name one */
    int oom = rf_names_init(&L->file_names, s->nfiles) != 0;
    for (size_t i = 0; i < s->nfiles && !oom; i++)
        rf_names_add(&L->file_names, s->files[i], i, &oom);
    if (oom)
        return rf_load_oom(L);
    return rf_load_list(L, n, &zone_list, 0, (void **)&s->zones, &s->nzones, read_zone, NULL);
}

/* ---- vegetation, rocks, releases --------------------------------------------- */

static int read_forest(loader *L, const rf_ynode *n, size_t i, const char *what)
{
    rf_forest *f = &L->p->forests[i];
    f->restitution = (rf_dist){0.2, 0.0};
    f->friction = (rf_dist){0.3, 0.0};
    rf_ynode *polygon = rf_ydoc_get(&L->d, n, "polygon");
    if (polygon && rf_load_polyline(L, polygon, "polygon", 3, &f->polygon))
        return -1;
    rf_ynode *density, *height, *diameter;
    if (rf_ydoc_require(&L->d, n, "density", what, &density, L->err) ||
        rf_ydoc_require(&L->d, n, "height", what, &height, L->err) ||
        rf_ydoc_require(&L->d, n, "diameter", what, &diameter, L->err))
        return -1;
    if (rf_ydoc_number(&L->d, density, "density", RF_YR_NONNEG, &f->density, L->err) ||
        rf_load_bounded(L, density, "density", f->density, 0.0, RF_FOREST_DENSITY_MAX,
                        "trees per m^2") ||
        rf_load_dist(L, height, "height", RF_YR_POSITIVE, RF_TREE_HEIGHT_MAX, RF_TREE_HEIGHT_MAX,
                     &f->height) ||
        rf_ydoc_number(&L->d, diameter, "diameter", RF_YR_POSITIVE, &f->diameter, L->err) ||
        rf_load_bounded(L, diameter, "diameter", f->diameter, 0.0, RF_STEM_DIAMETER_MAX, "m") ||
        rf_load_opt_dist(L, n, "restitution", RF_YR_UNIT, 1.0, 1.0, &f->restitution) ||
        rf_load_opt_dist(L, n, "friction", RF_YR_NONNEG, RF_FRICTION_MAX, RF_FRICTION_MAX,
                         &f->friction))
        return -1;
    return 0;
}

static int read_rock(loader *L, const rf_ynode *n, size_t i, const char *what)
{
    rf_rock *r = &L->p->rocks[i];
    rf_ynode *mass;
    long long level = 2;
    r->density = 2650.0;
    if (rf_load_rock_mass(L, n, r, what, &mass) ||
        rf_ydoc_opt_number(&L->d, n, "density", RF_YR_POSITIVE, &r->density, L->err) ||
        rf_ydoc_opt_integer(&L->d, n, "action_level", RF_YR_BETWEEN(1, 3), &level, L->err))
        return -1;
    r->action_level = (int)level;
    r->radius = rf_body_make(r->mass, r->density, RF_MODEL_SPHERE).radius;
    if (!(r->radius >= RF_ROCK_RADIUS_MIN && r->radius <= RF_ROCK_RADIUS_MAX))
        return rf_ydoc_error(&L->d, mass, L->err,
                             "'mass' and 'density' give a rock of radius %g m; it must be "
                             "%g to %g m",
                             r->radius, RF_ROCK_RADIUS_MIN, RF_ROCK_RADIUS_MAX);
    if (rf_check_mass_radii(L, mass, r))
        return -1;
    rf_ynode *density = rf_ydoc_get(&L->d, n, "density");
    if (rf_load_bounded(L, mass, "mass", r->mass, 0.0, RF_ROCK_MASS_MAX, "kg") ||
        (density && rf_load_bounded(L, density, "density", r->density, RF_ROCK_DENSITY_MIN,
                                    RF_ROCK_DENSITY_MAX, "kg/m^3")))
        return -1;
    return 0;
}

static int read_release(loader *L, const rf_ynode *n, size_t i, const char *what)
{
    rf_project *p = L->p;
    rf_release *r = &p->releases[i];
    rf_ynode *point = NULL, *rock = NULL;
    const char *rock_name = NULL;
    if (rf_load_release_source(L, n, r, what, &point))
        return -1;
    L->point_nodes[i] = point;
    if (rf_ydoc_require(&L->d, n, "rock", what, &rock, L->err) ||
        rf_ydoc_string(&L->d, rock, "rock", &rock_name, L->err))
        return -1;
    size_t k = rf_names_find(&L->rock_names, rock_name);
    r->rock = k == RF_NAMES_ABSENT ? -1 : (int)k;
    if (r->rock < 0) {
        char names[512] = "";
        size_t used = 0;
        for (size_t j = 0; j < p->nrocks && used < sizeof names; j++) {
            int w = snprintf(names + used, sizeof names - used, "%s%s", j ? ", " : "",
                             p->rocks[j].name);
            if (w < 0)
                break;
            used += (size_t)w;
        }
        return rf_ydoc_error(&L->d, rock, L->err,
                             "'rock' must name a rock defined under 'rocks' (%s); got %s",
                             names, rock_name);
    }
    long long count = 1;
    r->velocity = rf_v3(0.0, 0.0, 0.0);
    if (rf_ydoc_opt_integer(&L->d, n, "count", RF_YR_BETWEEN(1, RF_COUNT_MAX), &count, L->err) ||
        rf_ydoc_opt_number(&L->d, n, "height", RF_YR_NONNEG, &r->height, L->err) ||
        rf_ydoc_opt_number(&L->d, n, "jitter", RF_YR_NONNEG, &r->jitter, L->err) ||
        rf_load_bounded(L, rf_ydoc_get(&L->d, n, "height"), "height", r->height, 0.0,
                        RF_RELEASE_HEIGHT_MAX, "m") ||
        rf_load_bounded(L, rf_ydoc_get(&L->d, n, "jitter"), "jitter", r->jitter, 0.0,
                        RF_RELEASE_JITTER_MAX, "m"))
        return -1;
    r->count = (long)count;
    rf_ynode *velocity = rf_ydoc_get(&L->d, n, "velocity");
    if (velocity) {
        double v[3];
        if (rf_load_tuple(L, velocity, "velocity", 3, "a vector [vx, vy, vz]",
                          RF_RELEASE_SPEED_MAX, "m/s", v))
            return -1;
        r->velocity = rf_v3(v[0], v[1], v[2]);
        double speed = rf_v3_norm(r->velocity);
        if (!(speed <= RF_RELEASE_SPEED_MAX))
            return rf_ydoc_error(&L->d, velocity, L->err,
                                 "'velocity' is %g m/s; a release may be at most %g m/s",
                                 speed, RF_RELEASE_SPEED_MAX);
    }
    return 0;
}

/* ---- measures ---------------------------------------------------------------- */

/* The key of a measure item that its kind does not read, or NULL. */
static rf_ynode *foreign_key(loader *L, const rf_ynode *map, const rf_measure_kind_class *c)
{
    static const char *const common[] = {"name", "kind", "line", "importance", "behaviour",
                                         NULL};
    size_t n = rf_ydoc_map_size(map);
    for (size_t i = 0; i < n; i++) {
        rf_ynode *k = rf_ydoc_map_key(&L->d, map, i);
        const char *key = (const char *)k->data.scalar.value;
        int known = 0;
        for (const char *const *a = common; *a && !known; a++)
            known = !strcmp(*a, key);
        for (const char *const *a = c->keys; *a && !known; a++)
            known = !strcmp(*a, key);
        if (!known)
            return k;
    }
    return NULL;
}

/* The keys every measure has, then its kind's own (rf_measure_kinds). */
static int read_measure(loader *L, const rf_ynode *n, size_t i, const char *what)
{
    rf_measure *m = &L->p->measures[i];
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        m->capacity[s] = -1.0;
    m->mel = m->sel = -1.0;
    const char *kind_names[RF_N_MEASURE_KINDS + 1] = {NULL};
    for (int j = 0; j < RF_N_MEASURE_KINDS; j++)
        kind_names[j] = rf_measure_kinds[j].name;
    rf_ynode *kind_node, *line;
    int k;
    if (rf_ydoc_require(&L->d, n, "kind", what, &kind_node, L->err) ||
        rf_ydoc_enum(&L->d, kind_node, "kind", kind_names, &k, L->err))
        return -1;
    if (rf_ydoc_require(&L->d, n, "line", what, &line, L->err) ||
        rf_load_polyline(L, line, "line", 2, &m->line))
        return -1;
    L->line_nodes[i] = line;
    m->kind = (rf_measure_kind)k;
    int importance = RF_IMPORTANT, behaviour = RF_STOP;
    if (rf_ydoc_opt_enum(&L->d, n, "importance", rf_importance_names, &importance, L->err))
        return -1;
    rf_ynode *behaviour_node = rf_ydoc_get(&L->d, n, "behaviour");
    if (behaviour_node &&
        rf_ydoc_enum(&L->d, behaviour_node, "behaviour", behaviour_names, &behaviour, L->err))
        return -1;
    m->importance = (rf_importance)importance;
    m->behaviour = (rf_behaviour)behaviour;
    const rf_measure_kind_class *c = &rf_measure_kinds[k];
    rf_ynode *foreign = foreign_key(L, n, c);
    if (foreign)
        return rf_ydoc_error(&L->d, foreign, L->err, "'%s' is not allowed on %s",
                             (const char *)foreign->data.scalar.value, c->label);
    rf_measure_item item = {&L->d, n, what, L->err};
    return c->read(&item, m);
}

/* ---- simulation, hazard ------------------------------------------------------ */

static int read_simulation(loader *L, const rf_ynode *n)
{
    rf_simulation *s = &L->p->sim;
    if (rf_ydoc_mapping_of(&L->d, n, simulation_keys, "'simulation'", L->err))
        return -1;
    int model = (int)s->model, engine = (int)s->engine, contact = (int)s->contact;
    long long paths = s->paths;
    if (rf_ydoc_opt_enum(&L->d, n, "model", model_names, &model, L->err) ||
        rf_ydoc_opt_enum(&L->d, n, "engine", engine_names, &engine, L->err) ||
        rf_ydoc_opt_number(&L->d, n, "dt", RF_YR_POSITIVE, &s->dt, L->err) ||
        rf_ydoc_opt_enum(&L->d, n, "contact", contact_names, &contact, L->err) ||
        rf_ydoc_opt_number(&L->d, n, "stop_speed", RF_YR_POSITIVE, &s->stop_speed, L->err) ||
        rf_ydoc_opt_number(&L->d, n, "max_time", RF_YR_POSITIVE, &s->max_time, L->err) ||
        rf_ydoc_opt_integer(&L->d, n, "paths", RF_YR_NONNEG, &paths, L->err))
        return -1;
    if (rf_load_bounded(L, rf_ydoc_get(&L->d, n, "dt"), "dt", s->dt, RF_DT_MIN, RF_DT_MAX, "s") ||
        rf_load_bounded(L, rf_ydoc_get(&L->d, n, "stop_speed"), "stop_speed", s->stop_speed, 0.0,
                        RF_STOP_SPEED_MAX, "m/s") ||
        rf_load_bounded(L, rf_ydoc_get(&L->d, n, "max_time"), "max_time", s->max_time, 0.0,
                        RF_MAX_TIME_MAX, "s"))
        return -1;
    s->model = (rf_rock_model)model;
    s->engine = (rf_engine_kind)engine;
    s->contact = (rf_contact_kind)contact;
    s->paths = (long)paths;
    return 0;
}

/* ---- the coordinate reference system ------------------------------------------ */

/* `crs:` an authority code or a WKT file (a value naming an existing file is the
 * file); without it, the DEM's .prj beside it when there is one (input/crs.h). */
static int read_crs(loader *L, rf_ynode *root)
{
    rf_project *p = L->p;
    rf_ynode *n = rf_ydoc_get(&L->d, root, "crs");
    const rf_terrain_spec *t = &p->terrain_spec;
    char *file = NULL, *text = NULL, why[512];
    const char *given = NULL;
    if (n) {
        if (rf_ydoc_string(&L->d, n, "crs", &given, L->err))
            return -1;
        if (!(file = rf_load_resolve(p->dir, given)))
            return rf_load_oom(L);
        if (!rf_load_readable(file, why, sizeof why)) {
            free(file);
            file = NULL;
        }
    } else if (t->source == RF_TERRAIN_DEM && t->nfiles == 1) {
        size_t len = strlen(t->files[0]);
        const char *dot = strrchr(t->files[0], '.'), *slash = strrchr(t->files[0], '/');
        size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - t->files[0]) : len;
        if (!(file = malloc(stem + 5)))
            return rf_load_oom(L);
        memcpy(file, t->files[0], stem);
        memcpy(file + stem, ".prj", 5);
        if (!rf_load_readable(file, why, sizeof why)) {
            free(file);
            return 0; /* no CRS: GeoPackage's undefined Cartesian one */
        }
        n = L->file_nodes[0];
    } else {
        return 0;
    }
    rf_error ferr = {0};
    size_t len = 0;
    if (file && rf_read_file(file, RF_CRS_FILE_MAX, &text, &len, &ferr)) {
        free(file);
        return rf_ydoc_error(&L->d, n, L->err, "crs: %s", ferr.message);
    }
    int status = rf_crs_resolve(file ? text : given, file ? file : given, &p->crs, why,
                                sizeof why);
    if (status)
        status = file ? rf_ydoc_error(&L->d, n, L->err,
                                      "crs: '%s' holds no coordinate reference system PROJ "
                                      "knows: %s",
                                      file, why)
                      : rf_ydoc_error(&L->d, n, L->err,
                                      "crs: '%s' is not a coordinate reference system PROJ "
                                      "knows (an authority code such as 'EPSG:2154', or a "
                                      "WKT file): %s",
                                      given, why);
    free(text);
    free(file);
    return status;
}

/* ---- the document ------------------------------------------------------------ */

static int read_document(loader *L)
{
    rf_project *p = L->p;
    rf_ynode *root = rf_ydoc_root(&L->d);
    if (!root)
        return rf_error_set(L->err, L->d.file, 1, 1,
                            "the project file is empty; expected a mapping with 'name', "
                            "'terrain', 'rocks' and 'releases'");
    if (rf_ydoc_mapping_of(&L->d, root, top_keys, "the project file", L->err))
        return -1;

    rf_ynode *terrain;
    const char *s = NULL;
    if (rf_load_name(L, root, "the project file", &p->name))
        return -1;
    long long seed = 1;
    if (rf_ydoc_opt_integer(&L->d, root, "seed", RF_YR_NONNEG, &seed, L->err))
        return -1;
    p->seed = (uint64_t)seed;

    if (rf_ydoc_require(&L->d, root, "terrain", "the project file", &terrain, L->err) ||
        read_terrain(L, terrain) || read_crs(L, root) ||
        rf_layout_check_crs(&L->d, &L->layouts, &p->crs, L->err))
        return -1;
    if (rf_load_list(L, root, &forest_list, 0, (void **)&p->forests, &p->nforests, read_forest,
                     NULL) ||
        rf_load_list(L, root, &rock_list, 1, (void **)&p->rocks, &p->nrocks, read_rock,
                     &L->rock_names))
        return -1;
    rf_ynode *releases = rf_ydoc_get(&L->d, root, "releases");
    if (releases && releases->type == YAML_SEQUENCE_NODE && rf_ydoc_seq_size(releases)) {
        L->point_nodes = calloc(rf_ydoc_seq_size(releases), sizeof *L->point_nodes);
        if (!L->point_nodes)
            return rf_load_oom(L);
    }
    rf_ynode *measures = rf_ydoc_get(&L->d, root, "measures");
    if (measures && measures->type == YAML_SEQUENCE_NODE && rf_ydoc_seq_size(measures)) {
        L->line_nodes = calloc(rf_ydoc_seq_size(measures), sizeof *L->line_nodes);
        if (!L->line_nodes)
            return rf_load_oom(L);
    }
    if (rf_load_list(L, root, &release_list, 1, (void **)&p->releases, &p->nreleases,
                     read_release, NULL) ||
        rf_load_list(L, root, &measure_list, 0, (void **)&p->measures, &p->nmeasures,
                     read_measure, NULL))
        return -1;

    rf_ynode *sim = rf_ydoc_get(&L->d, root, "simulation");
    if (sim && read_simulation(L, sim))
        return -1;
    rf_ynode *hazard = rf_ydoc_get(&L->d, root, "hazard");
    if (hazard && (rf_ydoc_mapping_of(&L->d, hazard, hazard_keys, "'hazard'", L->err) ||
                   rf_ydoc_opt_number(&L->d, hazard, "cell", RF_YR_POSITIVE, &p->hazard_cell,
                                      L->err)))
        return -1;
    L->cell_node = hazard ? rf_ydoc_get(&L->d, hazard, "cell") : NULL;

    rf_ynode *rules = rf_ydoc_get(&L->d, root, "rules");
    if (rules) {
        if (rf_ydoc_string(&L->d, rules, "rules", &s, L->err))
            return -1;
        if (!(p->rules_path = rf_load_resolve(p->dir, s)))
            return rf_load_oom(L);
        char why[256];
        if (!rf_load_readable(p->rules_path, why, sizeof why))
            return rf_ydoc_error(&L->d, rules, L->err, "cannot open rules file '%s': %s",
                                 p->rules_path, why);
    }
    return 0;
}

/* Builds the terrain; file-level failures of the builder (no line) point at the path
 * in the YAML, errors inside a terrain file keep that file's own location. */
static int build_terrain(loader *L)
{
    rf_project *p = L->p;
    rf_terrain_spec *s = &p->terrain_spec;
    if (rf_terrain_build(s, &p->terrain, L->err) == 0)
        return 0;
    if (L->err && L->err->line == 0) {
        for (size_t i = 0; i < s->nfiles; i++) {
            if (!strcmp(L->err->file, s->files[i])) {
                char msg[sizeof L->err->message];
                snprintf(msg, sizeof msg, "%s", L->err->message);
                return rf_ydoc_error(&L->d, L->file_nodes[i], L->err, "terrain file '%s': %s",
                                     s->files[i], msg);
            }
        }
        if (!L->err->file[0]) {
            char msg[sizeof L->err->message];
            snprintf(msg, sizeof msg, "%s", L->err->message);
            return rf_ydoc_error(&L->d, rf_ydoc_get(&L->d, rf_ydoc_root(&L->d), "terrain"),
                                 L->err, "terrain: %s", msg);
        }
    }
    return -1;
}

static int place_releases(loader *L)
{
    rf_project *p = L->p;
    const rf_terrain *t = &p->terrain;
    for (size_t i = 0; i < p->nreleases; i++) {
        rf_release *r = &p->releases[i];
        double z = 0.0;
        if (r->source != RF_SOURCE_POINT) {
            if (rf_place_release(L, r, L->point_nodes[i]))
                return -1;
            continue;
        }
        if (rf_terrain_height(t, r->x, r->y, &z) >= 0) {
            r->z = z;
            continue;
        }
        if (r->x >= t->xmin && r->x <= t->xmax && r->y >= t->ymin && r->y <= t->ymax)
            return rf_ydoc_error(&L->d, L->point_nodes[i], L->err,
                                 "release '%s' point (%g, %g) is in a hole of the terrain "
                                 "(nodata); it must be on the terrain",
                                 r->name, r->x, r->y);
        return rf_ydoc_error(&L->d, L->point_nodes[i], L->err,
                             "release '%s' point (%g, %g) is off the terrain (x %g..%g, "
                             "y %g..%g)",
                             r->name, r->x, r->y, t->xmin, t->xmax, t->ymin, t->ymax);
    }
    return 0;
}

/* 1 when the segment a-b meets the box [x0, x1] x [y0, y1] (Liang-Barsky clipping). */
static int segment_meets_box(const double *a, const double *b, double x0, double x1, double y0,
                             double y1)
{
    double t0 = 0.0, t1 = 1.0, d[2] = {b[0] - a[0], b[1] - a[1]};
    double lo[2] = {x0, y0}, hi[2] = {x1, y1};
    for (int k = 0; k < 2; k++) {
        if (d[k] == 0.0) {
            if (a[k] < lo[k] || a[k] > hi[k])
                return 0;
            continue;
        }
        double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
        if (ta > tb) {
            double tmp = ta;
            ta = tb;
            tb = tmp;
        }
        t0 = fmax(t0, ta);
        t1 = fmin(t1, tb);
        if (t0 > t1)
            return 0;
    }
    return 1;
}

/* A measure is draped on the terrain: its line must reach the terrain somewhere. */
static int check_measures_on_terrain(loader *L)
{
    const rf_project *p = L->p;
    const rf_terrain *t = &p->terrain;
    for (size_t i = 0; i < p->nmeasures; i++) {
        const rf_polyline *l = &p->measures[i].line;
        int meets = 0;
        for (size_t k = 0; k + 1 < l->n && !meets; k++)
            meets = segment_meets_box(&l->xy[2 * k], &l->xy[2 * k + 2], t->xmin, t->xmax,
                                      t->ymin, t->ymax);
        if (!meets)
            return rf_ydoc_error(&L->d, L->line_nodes[i], L->err,
                                 "measure '%s' line lies entirely off the terrain (x %g..%g, "
                                 "y %g..%g)",
                                 p->measures[i].name, t->xmin, t->xmax, t->ymin, t->ymax);
    }
    return 0;
}

static int set_paths(loader *L, const char *path)
{
    rf_project *p = L->p;
    p->path = strdup(path);
    if (!p->path)
        return rf_load_oom(L);
    const char *slash = strrchr(path, '/');
    if (!slash) {
        p->dir = strdup(".");
    } else if (slash == path) {
        p->dir = strdup("/");
    } else {
        p->dir = strndup(path, (size_t)(slash - path));
    }
    if (!p->dir)
        return rf_load_oom(L);
    p->yaml_text = strdup(L->d.text);
    return p->yaml_text ? 0 : rf_load_oom(L);
}

/* The hazard map's grid over the terrain stays within RF_HAZARD_CELLS_MAX cells (each
 * thread keeps one). */
static int check_hazard_grid(loader *L)
{
    const rf_terrain *t = &L->p->terrain;
    double c = L->p->hazard_cell, nx, ny;
    rf_hazard_grid(t, c, &nx, &ny);
    double cells = nx * ny;
    if (cells <= RF_HAZARD_CELLS_MAX)
        return 0;
    if (L->cell_node)
        return rf_ydoc_error(&L->d, L->cell_node, L->err,
                             "'cell' %g m makes a hazard grid of %.3g cells over the terrain; "
                             "at most %g",
                             c, cells, RF_HAZARD_CELLS_MAX);
    return rf_error_set(L->err, L->p->path, 0, 0,
                        "the default hazard cell of %g m makes a grid of %.3g cells over the "
                        "terrain; set a larger 'hazard: {cell: ...}' (at most %g cells)",
                        c, cells, RF_HAZARD_CELLS_MAX);
}

/* Loads the project from `text` (len bytes, from the file `path`, or NULL to read the
 * file). */
static int load(const char *path, const char *text, size_t len, rf_project *p, rf_error *err)
{
    memset(p, 0, sizeof *p);
    p->seed = 1;
    p->sim = (rf_simulation){RF_MODEL_SPHERE, RF_ENGINE_EXACT, 0.001, RF_CONTACT_FULL,
                             0.1, 300.0, 10};
    p->hazard_cell = 5.0;
    p->terrain_spec.up = 'z';

    loader L;
    memset(&L, 0, sizeof L);
    L.p = p;
    L.err = err;
    int rc;
    if (!text)
        rc = rf_ydoc_load_file(&L.d, path, err);
    else if (len > RF_TEXT_FILE_MAX)
        rc = rf_error_set(err, path, 0, 0, "'%s' is %zu bytes; at most %zu are read", path, len,
                          RF_TEXT_FILE_MAX);
    else
        rc = rf_ydoc_load_text(&L.d, path, text, len, err);
    if (rc == 0)
        rc = set_paths(&L, path);
    if (rc == 0)
        rc = rf_layout_expand(&L.d, p->dir, &L.layouts, err);
    if (rc == 0)
        rc = read_document(&L);
    if (rc == 0)
        rc = build_terrain(&L);
    if (rc == 0)
        rc = place_releases(&L);
    if (rc == 0)
        rc = check_measures_on_terrain(&L);
    if (rc == 0)
        rc = check_hazard_grid(&L);
    free(L.file_nodes);
    free(L.point_nodes);
    free(L.line_nodes);
    rf_names_free(&L.rock_names);
    rf_names_free(&L.file_names);
    rf_layouts_free(&L.layouts);
    rf_ydoc_free(&L.d);
    if (rc)
        rf_project_free(p);
    return rc;
}

int rf_project_load(const char *path, rf_project *p, rf_error *err)
{
    return load(path, NULL, 0, p, err);
}

int rf_project_load_from_memory(const char *data, size_t len, const char *path, rf_project *p,
                                rf_error *err)
{
    return load(path, data, len, p, err);
}

static void free_spec(rf_terrain_spec *s)
{
    for (size_t i = 0; i < s->nfiles; i++)
        free(s->files[i]);
    free(s->files);
    free(s->profile);
    for (size_t i = 0; i < s->nzones; i++) {
        free(s->zones[i].name);
        free(s->zones[i].poly_xy);
        free(s->zones[i].file);
    }
    free(s->zones);
}

void rf_project_free(rf_project *p)
{
    free(p->path);
    free(p->dir);
    free(p->yaml_text);
    free(p->name);
    free_spec(&p->terrain_spec);
    rf_terrain_free(&p->terrain);
    for (size_t i = 0; i < p->nforests; i++) {
        free(p->forests[i].name);
        free(p->forests[i].polygon.xy);
    }
    free(p->forests);
    for (size_t i = 0; i < p->nrocks; i++) {
        free(p->rocks[i].name);
        free(p->rocks[i].masses);
    }
    free(p->rocks);
    for (size_t i = 0; i < p->nreleases; i++) {
        free(p->releases[i].name);
        rf_release_free(&p->releases[i]);
    }
    free(p->releases);
    for (size_t i = 0; i < p->nmeasures; i++) {
        free(p->measures[i].name);
        free(p->measures[i].line.xy);
    }
    free(p->measures);
    free(p->rules_path);
    rf_crs_free(&p->crs);
    memset(p, 0, sizeof *p);
}
