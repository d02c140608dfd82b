/* layout.c - {gpkg: FILE, layer: NAME} items expanded into one item per feature
 * (input/layout.h).
 *
 * Geometries are read as GeoPackage binary (OGC 12-128r18, 2.1.3): the header "GP",
 * its flags (byte order, envelope size, empty and extended bits) and srs_id, then WKB
 * in either byte order, ISO (Z +1000, M +2000, ZM +3000) or extended (0x80000000 Z,
 * 0x40000000 M) type codes. */
#include "input/layout.h"

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <sqlite3.h>

#include "input/crs.h"
#include "input/project_private.h"

/* ---- geometry ------------------------------------------------------------------------ */

enum { G_POINT = 1, G_LINE = 2, G_POLYGON = 3, G_MULTILINE = 5, G_MULTIPOLYGON = 6 };

/* The rings (or lines, or the point) of a geometry: ring k is xy[2 start[k] ..] with
 * n[k] points, in part part[k]. */
typedef struct shape {
    int type;                 /* the outermost type */
    double *xy;
    size_t nxy, capxy;
    size_t *start, *n, *part;
    size_t nrings, caprings, nparts;
} shape;

typedef struct reader {
    const unsigned char *b;
    size_t len, at;
    int le, bad;
} reader;

static uint32_t rd_u32(reader *r)
{
    if (r->bad || r->len - r->at < 4) {
        r->bad = 1;
        return 0;
    }
    const unsigned char *p = r->b + r->at;
    r->at += 4;
    return r->le ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
                 : (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
}

static double rd_f64(reader *r)
{
    if (r->bad || r->len - r->at < 8) {
        r->bad = 1;
        return 0.0;
    }
    uint64_t u = 0;
    for (int k = 0; k < 8; k++)
        u |= (uint64_t)r->b[r->at + (size_t)(r->le ? k : 7 - k)] << (8 * k);
    r->at += 8;
    double v;
    memcpy(&v, &u, 8);
    return v;
}

static int add_ring(shape *s, size_t part)
{
    if (s->nrings == s->caprings) {
        size_t cap = s->caprings ? 2 * s->caprings : 8;
        size_t *a = realloc(s->start, cap * sizeof *a), *b, *c;
        if (!a)
            return -1;
        s->start = a;
        if (!(b = realloc(s->n, cap * sizeof *b)))
            return -1;
        s->n = b;
        if (!(c = realloc(s->part, cap * sizeof *c)))
            return -1;
        s->part = c;
        s->caprings = cap;
    }
    s->start[s->nrings] = s->nxy;
    s->n[s->nrings] = 0;
    s->part[s->nrings] = part;
    s->nrings++;
    return 0;
}

static int add_xy(shape *s, double x, double y)
{
    if (2 * s->nxy + 2 > s->capxy) {
        size_t cap = s->capxy ? 2 * s->capxy : 64;
        double *v = realloc(s->xy, cap * sizeof *v);
        if (!v)
            return -1;
        s->xy = v;
        s->capxy = cap;
    }
    s->xy[2 * s->nxy] = x;
    s->xy[2 * s->nxy + 1] = y;
    s->nxy++;
    s->n[s->nrings - 1]++;
    return 0;
}

/* Points of a ring or line: a count, then each point's coordinates. */
static int read_points(reader *r, shape *s, size_t part, int dims, size_t count)
{
    if (add_ring(s, part))
        return -1;
    for (size_t i = 0; i < count && !r->bad; i++) {
        double x = rd_f64(r), y = rd_f64(r);
        for (int k = 2; k < dims; k++)
            rd_f64(r); /* Z and M ignored */
        if (add_xy(s, x, y))
            return -1;
    }
    return 0;
}

/* One WKB geometry; a multi geometry's parts are read with depth 1. */
static int read_wkb(reader *r, shape *s, int depth)
{
    if (r->at >= r->len) {
        r->bad = 1;
        return 0;
    }
    r->le = r->b[r->at++] == 1;
    uint32_t code = rd_u32(r), base;
    int dims = 2;
    if (code & 0xE0000000u) {
        dims += !!(code & 0x80000000u) + !!(code & 0x40000000u);
        base = code & 0x0fffffffu;
    } else {
        base = code % 1000;
        dims += code / 1000 == 1 || code / 1000 == 2 ? 1 : code / 1000 == 3 ? 2 : 0;
    }
    if (depth == 0)
        s->type = (int)base;
    size_t part = s->nparts;
    if (base == G_POINT) {
        s->nparts++;
        return read_points(r, s, part, dims, 1);
    }
    if (base == G_LINE) {
        s->nparts++;
        uint32_t n = rd_u32(r);
        return n > (r->len - r->at) / 16 ? (r->bad = 1, 0) : read_points(r, s, part, dims, n);
    }
    if (base == G_POLYGON) {
        s->nparts++;
        uint32_t rings = rd_u32(r);
        for (uint32_t k = 0; k < rings && !r->bad; k++) {
            uint32_t n = rd_u32(r);
            if (n > (r->len - r->at) / 16)
                r->bad = 1;
            else if (read_points(r, s, part, dims, n))
                return -1;
        }
        return 0;
    }
    if ((base == G_MULTILINE || base == G_MULTIPOLYGON) && depth == 0) {
        uint32_t parts = rd_u32(r);
        for (uint32_t k = 0; k < parts && !r->bad; k++)
            if (read_wkb(r, s, 1))
                return -1;
        return 0;
    }
    s->type = -(int)base; /* a type no list takes */
    return 0;
}

/* The geometry of a GeoPackage blob into s; -1 with why set when it is none. */
static int read_geometry(const unsigned char *b, size_t len, shape *s, char *why, size_t cap)
{
    static const size_t envelope[] = {0, 32, 48, 48, 64};
    memset(s, 0, sizeof *s);
    if (!b || len < 8 || b[0] != 'G' || b[1] != 'P') {
        snprintf(why, cap, "no GeoPackage geometry");
        return -1;
    }
    int flags = b[3], env = (flags >> 1) & 7;
    if (env > 4 || (flags & 0x20)) {
        snprintf(why, cap, "a geometry of an extended or unknown encoding");
        return -1;
    }
    if (flags & 0x10) {
        snprintf(why, cap, "an empty geometry");
        return -1;
    }
    reader r = {b, len, 8 + envelope[env], 1, 0};
    if (r.at > len || read_wkb(&r, s, 0) || r.bad || s->nrings == 0) {
        snprintf(why, cap, "a truncated or malformed geometry");
        return -1;
    }
    for (size_t i = 0; i < s->nxy; i++)
        if (!isfinite(s->xy[2 * i]) || !isfinite(s->xy[2 * i + 1])) {
            snprintf(why, cap, "a coordinate that is not a finite number");
            return -1;
        }
    return 0;
}

static void free_shape(shape *s)
{
    free(s->xy);
    free(s->start);
    free(s->n);
    free(s->part);
    memset(s, 0, sizeof *s);
}

/* ---- YAML nodes ------------------------------------------------------------------------ */

enum { K_MEASURE, K_RELEASE, K_ZONE, K_FOREST };

/* Where the nodes of one feature come from: their mark (the {gpkg, layer} item's) and
 * the text their errors start with. */
typedef struct builder {
    rf_ydoc *d;
    yaml_mark_t at;
    char origin[600];
} builder;

static int mark_node(builder *b, int id, const char *what)
{
    if (!id)
        return 0;
    yaml_node_t *n = yaml_document_get_node(&b->d->doc, id);
    n->start_mark = n->end_mark = b->at;
    char text[800];
    snprintf(text, sizeof text, "%s%s%s", b->origin, what ? ", " : "", what ? what : "");
    return rf_ydoc_set_origin(b->d, id, text) ? 0 : id;
}

static int new_scalar(builder *b, const char *text, const char *what)
{
    int id = yaml_document_add_scalar(&b->d->doc, NULL, (yaml_char_t *)text, (int)strlen(text),
                                      YAML_PLAIN_SCALAR_STYLE);
    return mark_node(b, id, what);
}

static int new_node(builder *b, int mapping, const char *what)
{
    int id = mapping ? yaml_document_add_mapping(&b->d->doc, NULL, YAML_FLOW_MAPPING_STYLE)
                     : yaml_document_add_sequence(&b->d->doc, NULL, YAML_FLOW_SEQUENCE_STYLE);
    return mark_node(b, id, what);
}

/* The shortest of %.15g .. %.17g that reads back as the same double. */
static void number_text(char *buf, size_t cap, double v)
{
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(buf, cap, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            return;
    }
}

/* [x, y] */
static int point_node(builder *b, const double *xy)
{
    int seq = new_node(b, 0, "its geometry");
    for (int k = 0; seq && k < 2; k++) {
        char t[40];
        number_text(t, sizeof t, xy[k]);
        int v = new_scalar(b, t, "its geometry");
        if (!v || !yaml_document_append_sequence_item(&b->d->doc, seq, v))
            return 0;
    }
    return seq;
}

/* [[x, y], ...] of a ring or line; a ring's closing point (the first again) left out. */
static int points_node(builder *b, const shape *s, size_t ring, int closed)
{
    size_t n = s->n[ring];
    /* an empty ring or line has no points (and xy may be NULL): an empty sequence, which
     * the project's reader refuses as too short */
    const double *xy = n ? s->xy + 2 * s->start[ring] : NULL;
    if (closed && n > 1 && xy[0] == xy[2 * (n - 1)] && xy[1] == xy[2 * (n - 1) + 1])
        n--;
    int seq = new_node(b, 0, "its geometry");
    for (size_t i = 0; seq && i < n; i++) {
        int p = point_node(b, xy + 2 * i);
        if (!p || !yaml_document_append_sequence_item(&b->d->doc, seq, p))
            return 0;
    }
    return seq;
}

static int add_pair(builder *b, int map, const char *key, int value, const char *what)
{
    int k = new_scalar(b, key, what);
    return k && value && yaml_document_append_mapping_pair(&b->d->doc, map, k, value) ? 0 : -1;
}

/* Every ring of a polygon with holes, or of several polygons, as one vertex list for
 * the even-odd rule, by which zones and forests hold a point (base/polygon.h): the
 * first ring, closed, then each other ring, closed, between a cut from the first
 * ring's first vertex to it and back.  Each cut is two edges on one segment in opposite
 * directions, which a ray crosses both or neither, so they change no point's parity;
 * a point exactly on a cut lies on an edge, and is held like a point on the
 * boundary. */
static int joined_rings_node(builder *b, const shape *s)
{
    int seq = new_node(b, 0, "its geometry");
    if (s->nxy == 0)
        return seq; /* no points: an empty polygon, which the project's reader refuses */
    const double *first = s->xy + 2 * s->start[0];
    for (size_t r = 0; seq && r < s->nrings; r++) {
        size_t n = s->n[r];
        if (n == 0)
            continue; /* an empty ring has no points and no cut */
        const double *xy = s->xy + 2 * s->start[r];
        if (n > 1 && xy[0] == xy[2 * (n - 1)] && xy[1] == xy[2 * (n - 1) + 1])
            n--; /* the closing point: written once, below */
        for (size_t i = 0; seq && i <= n; i++) {
            int p = point_node(b, i < n ? xy + 2 * i : xy);
            if (!p || !yaml_document_append_sequence_item(&b->d->doc, seq, p))
                seq = 0;
        }
        if (seq && r > 0 && r + 1 < s->nrings) { /* back along the cut */
            int p = point_node(b, first);
            if (!p || !yaml_document_append_sequence_item(&b->d->doc, seq, p))
                seq = 0;
        }
    }
    return seq; /* the last ring's cut back is the list's closing edge */
}

/* The feature's geometry as its list's key; -1 with why set when the list takes no such
 * geometry. */
static int geometry_pair(builder *b, int map, int kind, const shape *s, char *why, size_t cap)
{
    static const char *const type_names[] = {"?", "Point", "LineString", "Polygon",
                                             "MultiPoint", "MultiLineString", "MultiPolygon",
                                             "GeometryCollection"};
    const char *name = s->type >= 1 && s->type <= 7 ? type_names[s->type] : "an unknown type";
    int is_line = s->type == G_LINE || s->type == G_MULTILINE;
    int is_area = s->type == G_POLYGON || s->type == G_MULTIPOLYGON;
    if (kind == K_MEASURE && is_line && s->nparts == 1)
        return add_pair(b, map, "line", points_node(b, s, 0, 0), "its geometry");
    if (kind == K_RELEASE && s->type == G_POINT)
        return add_pair(b, map, "point", point_node(b, s->xy), "its geometry");
    if (kind != K_MEASURE && is_area && s->nparts == 1 && s->nrings == 1)
        return add_pair(b, map, kind == K_RELEASE ? "area" : "polygon", points_node(b, s, 0, 1),
                        "its geometry");
    if ((kind == K_ZONE || kind == K_FOREST) && is_area)
        return add_pair(b, map, "polygon", joined_rings_node(b, s), "its geometry");
    if (is_line && kind == K_MEASURE)
        snprintf(why, cap, "a MultiLineString of %zu lines; a measure is one line (split it: "
                           "QGIS's Multipart to Singleparts)", s->nparts);
    else if (is_area && kind != K_MEASURE)
        snprintf(why, cap, "a %s of %zu parts and %zu rings; a release area is one outer "
                           "ring without holes (split it, or fill its holes)",
                 name, s->nparts, s->nrings);
    else
        snprintf(why, cap, "a %s; %s", name,
                 kind == K_MEASURE   ? "a measure takes a LineString"
                 : kind == K_RELEASE ? "a release takes a Point or a Polygon"
                                     : "a zone or forest takes a Polygon");
    return -1;
}

/* Columns that stand for a nested key: PREFIX_SUB is PREFIX: {SUB: value}. */
static const char *const nest_prefix[] = {"capacity", "restitution", "friction", "height",
                                          "mass", "rolling", NULL};
static const char *const nest_sub[] = {"serviceability", "restorability", "ultimate",
                                       "near_collapse", "mean", "sd", NULL};

static int find(const char *const *list, const char *s, size_t len)
{
    for (int i = 0; list[i]; i++)
        if (strlen(list[i]) == len && !strncmp(list[i], s, len))
            return i;
    return -1;
}

/* ---- a layer's features ------------------------------------------------------------------ */

/* The error at the {gpkg, layer} item; returns -1. */
static int item_error(const rf_ydoc *d, rf_mark at, rf_error *err, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int item_error(const rf_ydoc *d, rf_mark at, rf_error *err, const char *fmt, ...)
{
    char msg[sizeof err->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return rf_error_set(err, d->file, at.line, at.column, "%s", msg);
}

/* One feature's item: its attributes (pk and geometry columns left out), then its
 * geometry; a feature without a `name` is named LAYER-FID. */
static int feature_item(builder *b, sqlite3_stmt *st, int kind, const char *layer,
                        int pk_col, int geom_col, int *out, rf_error *err, rf_mark at)
{
    int map = new_node(b, 1, NULL);
    int nested[sizeof nest_prefix / sizeof *nest_prefix] = {0};
    int named = 0;
    if (!map)
        return item_error(b->d, at, err, "out of memory reading %s", b->origin);
    for (int c = 0; c < sqlite3_column_count(st); c++) {
        const char *col = sqlite3_column_name(st, c);
        int type = sqlite3_column_type(st, c);
        if (c == pk_col || c == geom_col || type == SQLITE_NULL)
            continue;
        char what[300], text[64];
        snprintf(what, sizeof what, "attribute '%s'", col);
        const char *value = text;
        if (type == SQLITE_INTEGER)
            snprintf(text, sizeof text, "%lld", (long long)sqlite3_column_int64(st, c));
        else if (type == SQLITE_FLOAT)
            number_text(text, sizeof text, sqlite3_column_double(st, c));
        else if (type == SQLITE_TEXT)
            value = (const char *)sqlite3_column_text(st, c);
        else
            return item_error(b->d, at, err, "%s, %s: a BLOB; an attribute is a number or text",
                              b->origin, what);
        int v = new_scalar(b, value, what);
        const char *us = strchr(col, '_');
        int np = us ? find(nest_prefix, col, (size_t)(us - col)) : -1;
        if (np >= 0 && find(nest_sub, us + 1, strlen(us + 1)) >= 0) {
            if (!nested[np]) {
                nested[np] = new_node(b, 1, what);
                if (add_pair(b, map, nest_prefix[np], nested[np], what))
                    return item_error(b->d, at, err, "out of memory reading %s", b->origin);
            }
            if (add_pair(b, nested[np], us + 1, v, what))
                return item_error(b->d, at, err, "out of memory reading %s", b->origin);
            continue;
        }
        named |= !strcmp(col, "name");
        if (add_pair(b, map, col, v, what))
            return item_error(b->d, at, err, "out of memory reading %s", b->origin);
    }
    if (!named) {
        char name[400];
        snprintf(name, sizeof name, "%s-%lld", layer, (long long)sqlite3_column_int64(st, pk_col));
        if (add_pair(b, map, "name", new_scalar(b, name, "its name"), "its name"))
            return item_error(b->d, at, err, "out of memory reading %s", b->origin);
    }
    shape s;
    char why[300];
    const void *blob = sqlite3_column_blob(st, geom_col);
    int status = read_geometry(blob, (size_t)sqlite3_column_bytes(st, geom_col), &s, why, sizeof why);
    if (status == 0)
        status = geometry_pair(b, map, kind, &s, why, sizeof why);
    free_shape(&s);
    if (status)
        return item_error(b->d, at, err, "%s, its geometry: %s", b->origin, why);
    *out = map;
    return 0;
}

/* The layer's geometry column, srs and primary key; its srs row into l. */
static int describe_layer(sqlite3 *db, rf_layout_layer *l, char **geom, char **pk, char *why,
                          size_t cap)
{
    sqlite3_stmt *st = NULL;
    int found = 0;
    if (sqlite3_prepare_v2(db,
                           "SELECT g.column_name, g.srs_id, s.srs_name, s.organization,"
                           " s.organization_coordsys_id, s.definition FROM gpkg_geometry_columns g"
                           " LEFT JOIN gpkg_spatial_ref_sys s ON s.srs_id = g.srs_id"
                           " WHERE g.table_name = ?1",
                           -1, &st, NULL) == SQLITE_OK) {
        sqlite3_bind_text(st, 1, l->layer, -1, SQLITE_STATIC);
        if (sqlite3_step(st) == SQLITE_ROW) {
            found = 1;
            *geom = strdup((const char *)sqlite3_column_text(st, 0));
            l->srs_id = sqlite3_column_int64(st, 1);
            const unsigned char *t;
            l->srs_name = strdup((t = sqlite3_column_text(st, 2)) ? (const char *)t : "?");
            l->organization = strdup((t = sqlite3_column_text(st, 3)) ? (const char *)t : "NONE");
            l->code = sqlite3_column_int64(st, 4);
            l->definition = strdup((t = sqlite3_column_text(st, 5)) ? (const char *)t : "undefined");
        }
    } else {
        snprintf(why, cap, "not a GeoPackage (%s)", sqlite3_errmsg(db));
        sqlite3_finalize(st);
        return -1;
    }
    sqlite3_finalize(st);
    if (!found) {
        snprintf(why, cap, "no feature layer '%s'", l->layer);
        return -1;
    }
    if (sqlite3_prepare_v2(db, "SELECT name FROM pragma_table_info(?1) WHERE pk = 1", -1, &st,
                           NULL) == SQLITE_OK) {
        sqlite3_bind_text(st, 1, l->layer, -1, SQLITE_STATIC);
        if (sqlite3_step(st) == SQLITE_ROW)
            *pk = strdup((const char *)sqlite3_column_text(st, 0));
    }
    sqlite3_finalize(st);
    if (!*geom || !l->srs_name || !l->organization || !l->definition || !*pk) {
        snprintf(why, cap, *geom && !*pk ? "layer '%s' has no integer primary key"
                                         : "out of memory reading layer '%s'", l->layer);
        return -1;
    }
    return 0;
}

/* The {gpkg, layer} item at `item`: each feature's item appended to seq. */
static int expand_item(rf_ydoc *d, int item, int seq, int kind, const char *dir,
                       rf_layouts *used, rf_error *err)
{
    static const char *const keys[] = {"gpkg", "layer", NULL};
    yaml_node_t *n = yaml_document_get_node(&d->doc, item);
    yaml_mark_t mark = n->start_mark;
    rf_mark at = rf_ydoc_mark(n);
    const char *file = NULL, *name = NULL;
    rf_ynode *layer_node;
    if (rf_ydoc_check_keys(d, n, keys, "a layout item {gpkg, layer}", err) ||
        rf_ydoc_string(d, rf_ydoc_get(d, n, "gpkg"), "gpkg", &file, err) ||
        rf_ydoc_require(d, n, "layer", "a layout item {gpkg, layer}", &layer_node, err) ||
        rf_ydoc_string(d, layer_node, "layer", &name, err))
        return -1;
    rf_layout_layer *grown = realloc(used->v, (used->n + 1) * sizeof *grown);
    if (!grown)
        return item_error(d, at, err, "out of memory");
    used->v = grown;
    rf_layout_layer *l = &used->v[used->n++];
    memset(l, 0, sizeof *l);
    l->at = at;
    l->file = rf_load_resolve(dir, file);
    l->layer = strdup(name);
    char why[512];
    if (!l->file || !l->layer)
        return item_error(d, at, err, "out of memory");
    if (!rf_load_readable(l->file, why, sizeof why))
        return item_error(d, at, err, "cannot open GeoPackage '%s': %s", l->file, why);
    sqlite3 *db = NULL;
    char *geom = NULL, *pk = NULL, *sql = NULL;
    int status = -1;
    sqlite3_stmt *st = NULL;
    if (sqlite3_open_v2(l->file, &db, SQLITE_OPEN_READONLY, NULL) != SQLITE_OK) {
        item_error(d, at, err, "cannot open GeoPackage '%s': %s", l->file, sqlite3_errmsg(db));
        goto done;
    }
    if (describe_layer(db, l, &geom, &pk, why, sizeof why)) {
        item_error(d, at, err, "GeoPackage '%s': %s", l->file, why);
        goto done;
    }
    sql = sqlite3_mprintf("SELECT * FROM \"%w\" ORDER BY \"%w\"", l->layer, pk);
    if (!sql || sqlite3_prepare_v2(db, sql, -1, &st, NULL) != SQLITE_OK) {
        item_error(d, at, err, "GeoPackage '%s', layer '%s': %s", l->file, l->layer,
                   sqlite3_errmsg(db));
        goto done;
    }
    int pk_col = -1, geom_col = -1;
    for (int c = 0; c < sqlite3_column_count(st); c++) {
        if (!strcmp(sqlite3_column_name(st, c), pk))
            pk_col = c;
        if (!strcmp(sqlite3_column_name(st, c), geom))
            geom_col = c;
    }
    builder b = {d, mark, {0}};
    long count = 0;
    int rc;
    status = 0;
    while (status == 0 && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        if (++count > RF_LAYOUT_FEATURES_MAX) {
            status = item_error(d, at, err, "GeoPackage '%s', layer '%s': more than %d features",
                                l->file, l->layer, RF_LAYOUT_FEATURES_MAX);
            break;
        }
        snprintf(b.origin, sizeof b.origin, "%s, layer '%s', feature %lld", file, l->layer,
                 (long long)sqlite3_column_int64(st, pk_col));
        int map = 0;
        status = feature_item(&b, st, kind, l->layer, pk_col, geom_col, &map, err, at);
        if (status == 0 && !yaml_document_append_sequence_item(&d->doc, seq, map))
            status = item_error(d, at, err, "out of memory");
    }
    if (status == 0 && rc != SQLITE_DONE)
        status = item_error(d, at, err, "GeoPackage '%s', layer '%s': %s", l->file, l->layer,
                            sqlite3_errmsg(db));
done:
    sqlite3_finalize(st);
    sqlite3_free(sql);
    sqlite3_close(db);
    free(geom);
    free(pk);
    return status;
}

/* Whether the item is a {gpkg, ...} mapping. */
static int is_layout_item(rf_ydoc *d, int id)
{
    yaml_node_t *n = yaml_document_get_node(&d->doc, id);
    return n && n->type == YAML_MAPPING_NODE && rf_ydoc_get(d, n, "gpkg") != NULL;
}

/* The list under `key` of mapping `map` with its layout items expanded. */
static int expand_list(rf_ydoc *d, int map, const char *key, int kind, const char *dir,
                       rf_layouts *used, rf_error *err)
{
    yaml_node_t *m = yaml_document_get_node(&d->doc, map);
    if (!m || m->type != YAML_MAPPING_NODE)
        return 0;
    ptrdiff_t pair = -1;
    for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; p++) {
        yaml_node_t *k = yaml_document_get_node(&d->doc, p->key);
        if (k && k->type == YAML_SCALAR_NODE && !strcmp((const char *)k->data.scalar.value, key))
            pair = p - m->data.mapping.pairs.start;
    }
    yaml_node_t *list = pair >= 0 ? yaml_document_get_node(&d->doc,
                                                           m->data.mapping.pairs.start[pair].value)
                                  : NULL;
    if (!list || list->type != YAML_SEQUENCE_NODE)
        return 0;
    size_t n = (size_t)(list->data.sequence.items.top - list->data.sequence.items.start);
    int *items = malloc((n ? n : 1) * sizeof *items), any = 0;
    if (!items)
        return rf_error_set(err, d->file, 0, 0, "out of memory");
    memcpy(items, list->data.sequence.items.start, n * sizeof *items);
    yaml_mark_t mark = list->start_mark;
    for (size_t i = 0; i < n; i++)
        any |= is_layout_item(d, items[i]);
    int status = 0;
    if (any) {
        int seq = yaml_document_add_sequence(&d->doc, NULL, YAML_BLOCK_SEQUENCE_STYLE);
        if (seq)
            yaml_document_get_node(&d->doc, seq)->start_mark = mark;
        status = seq ? 0 : rf_error_set(err, d->file, 0, 0, "out of memory");
        for (size_t i = 0; status == 0 && i < n; i++) {
            if (is_layout_item(d, items[i]))
                status = expand_item(d, items[i], seq, kind, dir, used, err);
            else if (!yaml_document_append_sequence_item(&d->doc, seq, items[i]))
                status = rf_error_set(err, d->file, 0, 0, "out of memory");
        }
        if (status == 0) /* the nodes may have moved: the mapping is found again */
            yaml_document_get_node(&d->doc, map)->data.mapping.pairs.start[pair].value = seq;
    }
    free(items);
    return status;
}

int rf_layout_expand(rf_ydoc *d, const char *dir, rf_layouts *used, rf_error *err)
{
    memset(used, 0, sizeof *used);
    rf_ynode *root = rf_ydoc_root(d);
    if (!root || root->type != YAML_MAPPING_NODE)
        return 0;
    int root_id = (int)(root - d->doc.nodes.start) + 1;
    rf_ynode *terrain = rf_ydoc_get(d, root, "terrain");
    int terrain_id = terrain ? (int)(terrain - d->doc.nodes.start) + 1 : 0;
    if (expand_list(d, root_id, "releases", K_RELEASE, dir, used, err) ||
        expand_list(d, root_id, "measures", K_MEASURE, dir, used, err) ||
        expand_list(d, root_id, "vegetation", K_FOREST, dir, used, err) ||
        (terrain_id && expand_list(d, terrain_id, "zones", K_ZONE, dir, used, err)))
        return -1;
    return 0;
}

/* ---- the CRS --------------------------------------------------------------------------- */

int rf_layout_check_crs(const rf_ydoc *d, const rf_layouts *used, const rf_crs *crs,
                        rf_error *err)
{
    for (size_t i = 0; i < used->n; i++) {
        const rf_layout_layer *l = &used->v[i];
        int undefined = !strcmp(l->definition, "undefined");
        if (!crs->wkt && undefined)
            continue;
        if (!crs->wkt)
            return item_error(d, l->at, err,
                              "layer '%s' of '%s' is in the CRS '%s' (%s:%lld) and the project "
                              "names none: give the project `crs:` (or the DEM its .prj)",
                              l->layer, l->file, l->srs_name, l->organization, l->code);
        int same = 0;
        if (!undefined && crs->auth && !strcasecmp(l->organization, crs->auth))
            same = l->code == crs->code;
        else if (!undefined) {
            rf_crs theirs;
            char why[256];
            if (rf_crs_resolve(l->definition, l->srs_name, &theirs, why, sizeof why) == 0) {
                same = (theirs.auth && crs->auth && !strcmp(theirs.auth, crs->auth) &&
                        theirs.code == crs->code) ||
                       !strcmp(theirs.wkt, crs->wkt);
                rf_crs_free(&theirs);
            }
        }
        if (!same)
            return item_error(d, l->at, err,
                              "layer '%s' of '%s' is in the CRS '%s' and the project's is '%s': "
                              "rockfall does not reproject; save the layer in the project's CRS "
                              "(QGIS: Export > Save Features As, CRS)",
                              l->layer, l->file, undefined ? "undefined" : l->srs_name, crs->name);
    }
    return 0;
}

void rf_layouts_free(rf_layouts *used)
{
    for (size_t i = 0; i < used->n; i++) {
        rf_layout_layer *l = &used->v[i];
        free(l->file);
        free(l->layer);
        free(l->srs_name);
        free(l->organization);
        free(l->definition);
    }
    free(used->v);
    memset(used, 0, sizeof *used);
}
