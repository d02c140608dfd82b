/* terrain_io.c - readers of terrain files: ESRI ASCII grids, STL and OBJ meshes. */
#include "input/terrain_io.h"
#include "base/util.h"
#include "input/bounds.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* ---- a text scanner that knows its line and column ------------------------------ */

typedef struct scanner {
    const char *path;
    const char *p, *end, *line_start;
    int line;
    const rf_mapped *map; /* the mapped file scanned, or NULL */
    size_t released;      /* its bytes given back so far (rf_map_release) */
} scanner;

/* Bytes of a mapped file read between two releases of what was read. */
#define SCAN_RELEASE_BYTES ((size_t)8 << 20)

/* Gives back the pages of a mapped file already scanned, every SCAN_RELEASE_BYTES: a
 * large grid's text is read through a window of that size, not held whole. */
static void scan_release(scanner *s)
{
    if (!s->map)
        return;
    size_t at = (size_t)(s->p - s->map->data);
    if (at - s->released >= SCAN_RELEASE_BYTES) {
        rf_map_release(s->map, at);
        s->released = at;
    }
}

static void scan_init(scanner *s, const char *path, const char *buf, size_t len)
{
    s->path = path;
    s->p = s->line_start = buf;
    s->end = buf + len;
    s->line = 1;
    s->map = NULL;
    s->released = 0;
}

static int scan_column(const scanner *s, const char *at) { return (int)(at - s->line_start) + 1; }

/* Skips blanks; also newlines when cross_lines.  Returns 1 when a token follows. */
static int scan_skip(scanner *s, int cross_lines)
{
    while (s->p < s->end) {
        char c = *s->p;
        if (c == '\n') {
            if (!cross_lines)
                return 0;
            s->p++;
            s->line++;
            s->line_start = s->p;
        } else if (isspace((unsigned char)c) || c == '\0') {
            s->p++;
        } else {
            return 1;
        }
    }
    return 0;
}

/* The token at s->p (after scan_skip returned 1): [*start, return value). */
static const char *scan_token(scanner *s, const char **start)
{
    *start = s->p;
    while (s->p < s->end && !isspace((unsigned char)*s->p) && *s->p != '\0')
        s->p++;
    return s->p;
}

static void scan_to_next_line(scanner *s)
{
    while (s->p < s->end && *s->p != '\n')
        s->p++;
}

static int token_is(const char *a, const char *a_end, const char *word)
{
    size_t n = (size_t)(a_end - a);
    if (strlen(word) != n)
        return 0;
    for (size_t i = 0; i < n; i++)
        if (tolower((unsigned char)a[i]) != tolower((unsigned char)word[i]))
            return 0;
    return 1;
}

/* A finite decimal number filling the whole token. */
static int parse_number(const char *a, const char *a_end, double *x)
{
    if (a == a_end)
        return 0;
    char tmp[128];
    size_t n = (size_t)(a_end - a);
    if (n >= sizeof tmp)
        return 0;
    memcpy(tmp, a, n);
    tmp[n] = '\0';
    char *e;
    errno = 0;
    double v = strtod(tmp, &e);
    if (e != tmp + n || !isfinite(v))
        return 0;
    *x = v;
    return 1;
}

/* How much of the text [a, b) an error message shows: 40 characters at most. */
static int shown_len(const char *a, const char *b) { return (int)(b - a > 40 ? 40 : b - a); }

/* Reads the next token as a number (crossing lines when cross_lines). */
static int scan_number(scanner *s, int cross_lines, double *x, rf_error *err)
{
    if (!scan_skip(s, cross_lines))
        return rf_error_set(err, s->path, s->line, scan_column(s, s->p), "expected a number");
    const char *a, *b = scan_token(s, &a);
    if (!parse_number(a, b, x))
        return rf_error_set(err, s->path, s->line, scan_column(s, a),
                            "expected a number, found '%.*s'", shown_len(a, b), a);
    return 0;
}

/* ---- ESRI ASCII grid ---------------------------------------------------------------- */

void rf_asc_free(rf_asc_grid *g)
{
    free(g->z);
    memset(g, 0, sizeof *g);
}

static int looks_numeric(char c) { return isdigit((unsigned char)c) || c == '-' || c == '+' || c == '.'; }

static int asc_parse(scanner *s, rf_asc_grid *g, rf_error *err)
{
    enum { NCOLS, NROWS, XLL, YLL, CELL, NKEYS };
    static const char *key_name[NKEYS] = {"ncols", "nrows", "xllcorner", "yllcorner", "cellsize"};
    double val[NKEYS] = {0};
    int have[NKEYS] = {0}, x_corner = 0, y_corner = 0;
    rf_mark mark[NKEYS] = {{0, 0}};

    while (scan_skip(s, 1) && !looks_numeric(*s->p)) {
        const char *k, *k_end = scan_token(s, &k);
        int line = s->line, col = scan_column(s, k);
        int klen = shown_len(k, k_end);
        int key = -1, is_nodata = 0;
        if (token_is(k, k_end, "ncols"))
            key = NCOLS;
        else if (token_is(k, k_end, "nrows"))
            key = NROWS;
        else if (token_is(k, k_end, "xllcorner"))
            key = XLL, x_corner = 1;
        else if (token_is(k, k_end, "xllcenter"))
            key = XLL, x_corner = 0;
        else if (token_is(k, k_end, "yllcorner"))
            key = YLL, y_corner = 1;
        else if (token_is(k, k_end, "yllcenter"))
            key = YLL, y_corner = 0;
        else if (token_is(k, k_end, "cellsize"))
            key = CELL;
        else if (token_is(k, k_end, "nodata_value"))
            is_nodata = 1;
        else
            return rf_error_set(err, s->path, line, col, "unknown grid header key '%.*s'",
                                klen, k);
        if ((is_nodata && g->has_nodata) || (!is_nodata && have[key]))
            return rf_error_set(err, s->path, line, col, "grid header key '%.*s' given twice",
                                klen, k);
        double v;
        if (scan_number(s, 0, &v, err))
            return -1;
        if (is_nodata) {
            g->has_nodata = 1;
            g->nodata = v;
        } else {
            val[key] = v;
            have[key] = 1;
            mark[key] = (rf_mark){line, col};
        }
        scan_to_next_line(s);
    }
    int data_line = s->line, data_col = scan_column(s, s->p);
    for (int k = 0; k < NKEYS; k++)
        if (!have[k])
            return rf_error_set(err, s->path, data_line, data_col, "missing grid header key '%s'",
                                key_name[k]);
    for (int k = NCOLS; k <= NROWS; k++)
        if (val[k] < 2 || val[k] > RF_GRID_NODES_MAX / 2 || val[k] != floor(val[k]))
            return rf_error_set(err, s->path, mark[k].line, mark[k].column,
                                "%s must be a whole number from 2 to %.0f, got %g", key_name[k],
                                RF_GRID_NODES_MAX / 2, val[k]);
    if (val[NCOLS] * val[NROWS] > RF_GRID_NODES_MAX)
        return rf_error_set(err, s->path, mark[NROWS].line, mark[NROWS].column,
                            "ncols x nrows is %.0f nodes; at most %.0f (crop the grid to the "
                            "slope, or resample it to larger cells)",
                            val[NCOLS] * val[NROWS], RF_GRID_NODES_MAX);
    /* every value takes a character and a separator but the last */
    if (val[NCOLS] * val[NROWS] > (double)(s->end - s->p + 1) / 2)
        return rf_error_set(err, s->path, data_line, data_col,
                            "a %.0f x %.0f grid needs %.0f values; the %zu bytes left in the file "
                            "hold at most %zu",
                            val[NCOLS], val[NROWS], val[NCOLS] * val[NROWS],
                            (size_t)(s->end - s->p), (size_t)(s->end - s->p + 1) / 2);
    if (!(val[CELL] >= RF_CELL_MIN && val[CELL] <= RF_CELL_MAX))
        return rf_error_set(err, s->path, mark[CELL].line, mark[CELL].column,
                            "cellsize must be from %g to %g m, got %g", RF_CELL_MIN, RF_CELL_MAX,
                            val[CELL]);
    for (int k = XLL; k <= YLL; k++)
        if (!(fabs(val[k]) <= RF_COORD_MAX))
            return rf_error_set(err, s->path, mark[k].line, mark[k].column,
                                "%s must be from -%g to %g m, got %g", key_name[k], RF_COORD_MAX,
                                RF_COORD_MAX, val[k]);

    g->ncols = (size_t)val[NCOLS];
    g->nrows = (size_t)val[NROWS];
    g->cell = val[CELL];
    /* With *llcorner the nodes are the cell centres, half a cell in from the corner. */
    g->x0 = val[XLL] + (x_corner ? 0.5 * g->cell : 0.0);
    g->y0 = val[YLL] + (y_corner ? 0.5 * g->cell : 0.0);
    size_t count = g->ncols * g->nrows;
    g->z = malloc(count * sizeof *g->z);
    if (!g->z)
        return rf_error_set(err, s->path, 0, 0, "out of memory for a %zu x %zu grid", g->ncols,
                            g->nrows);
    /* The first data row is the northernmost. */
    for (size_t r = 0; r < g->nrows; r++) {
        size_t j = g->nrows - 1 - r;
        scan_release(s);
        for (size_t i = 0; i < g->ncols; i++) {
            if (!scan_skip(s, 1))
                return rf_error_set(err, s->path, s->line, scan_column(s, s->p),
                                    "expected %zu values, found %zu", count, r * g->ncols + i);
            int line = s->line, col = scan_column(s, s->p);
            double *z = &g->z[j * g->ncols + i];
            if (scan_number(s, 1, z, err))
                return -1;
            if (!(fabs(*z) <= RF_ELEVATION_MAX) && !(g->has_nodata && *z == g->nodata))
                return rf_error_set(err, s->path, line, col,
                                    "an elevation must be from -%g to %g m (or the "
                                    "NODATA_value), got %g",
                                    RF_ELEVATION_MAX, RF_ELEVATION_MAX, *z);
        }
    }
    if (scan_skip(s, 1))
        return rf_error_set(err, s->path, s->line, scan_column(s, s->p),
                            "more than the %zu values of a %zu x %zu grid", count, g->ncols,
                            g->nrows);
    return 0;
}

/* Parses the grid of scanner s (of file `map`, or NULL). */
static int asc_read(scanner *s, const rf_mapped *map, rf_asc_grid *g, rf_error *err)
{
    memset(g, 0, sizeof *g);
    s->map = map;
    int rc = asc_parse(s, g, err);
    if (rc)
        rf_asc_free(g);
    return rc;
}

int rf_asc_read_from_memory(const char *data, size_t len, const char *name, rf_asc_grid *g,
                            rf_error *err)
{
    scanner s;
    scan_init(&s, name, data, len);
    return asc_read(&s, NULL, g, err);
}

int rf_asc_read(const char *path, rf_asc_grid *g, rf_error *err)
{
    memset(g, 0, sizeof *g);
    rf_mapped m;
    if (rf_map_file(path, RF_TERRAIN_FILE_MAX, &m, err))
        return -1;
    scanner s;
    scan_init(&s, path, m.data, m.len);
    int rc = asc_read(&s, &m, g, err);
    rf_unmap_file(&m);
    return rc;
}

/* ---- triangle lists --------------------------------------------------------------- */

void rf_tri_list_free(rf_tri_list *l)
{
    free(l->v);
    memset(l, 0, sizeof *l);
}

static rf_vec3 to_world(double x, double y, double z, char up)
{
    /* up 'y': the file's x and z are the horizontal plane, so world (X, Y, Z) = (x, z, y). */
    return up == 'y' ? rf_v3(x, z, y) : rf_v3(x, y, z);
}

/* 0, or 1 when the list holds RF_MESH_TRIANGLES_MAX triangles already, or -1 when memory
 * runs out (push_failed says which). */
static int tri_push(rf_tri_list *l, rf_vec3 a, rf_vec3 b, rf_vec3 c)
{
    if ((double)l->n >= RF_MESH_TRIANGLES_MAX)
        return 1;
    if (rf_grow((void **)&l->v, &l->cap, l->n + 1, 3 * sizeof *l->v))
        return -1;
    l->v[3 * l->n] = a;
    l->v[3 * l->n + 1] = b;
    l->v[3 * l->n + 2] = c;
    l->n++;
    return 0;
}

static int push_failed(const char *path, int rc, rf_error *err)
{
    if (rc > 0)
        return rf_error_set(err, path, 0, 0, "the mesh files hold more than %.0f triangles",
                            RF_MESH_TRIANGLES_MAX);
    return rf_error_set(err, path, 0, 0, "out of memory");
}

/* 1 when a vertex lies within RF_COORD_MAX across and RF_ELEVATION_MAX up and down. */
static int vertex_in_bounds(rf_vec3 v)
{
    return fabs(v.x) <= RF_COORD_MAX && fabs(v.y) <= RF_COORD_MAX &&
           fabs(v.z) <= RF_ELEVATION_MAX;
}

static int vertex_error(const char *path, int line, int column, rf_vec3 v, rf_error *err)
{
    return rf_error_set(err, path, line, column,
                        "vertex (%g, %g, %g) is out of bounds: x and y must be within %g m, "
                        "the elevation within %g m",
                        v.x, v.y, v.z, RF_COORD_MAX, RF_ELEVATION_MAX);
}

/* ---- STL ------------------------------------------------------------------------------ */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static double le_float(const unsigned char *b)
{
    uint32_t u = le32(b);
    float f;
    memcpy(&f, &u, sizeof f);
    return (double)f;
}

static int stl_binary_size_matches(size_t len, const unsigned char *b)
{
    if (len < 84)
        return 0;
    uint64_t n = le32(b + 80);
    return (uint64_t)len == 84 + 50 * n;
}

/* A NUL byte among the first facet's bytes: no ascii STL has one, a binary STL almost
 * always does (its header's padding, the high bytes of its triangle count and of small
 * floats). */
static int stl_looks_binary(const char *data, size_t len)
{
    return memchr(data, '\0', len < 134 ? len : 134) != NULL;
}

static int stl_binary_size_error(const char *path, const unsigned char *b, size_t len,
                                 rf_error *err)
{
    if (len < 84)
        return rf_error_set(err, path, 0, 0,
                            "binary STL of %zu bytes is truncated: its header and triangle "
                            "count take 84",
                            len);
    uint64_t n = le32(b + 80), want = 84 + 50 * n;
    return rf_error_set(err, path, 0, 0,
                        "binary STL of %llu triangles needs %llu bytes, the file has %zu (%s)",
                        (unsigned long long)n, (unsigned long long)want, len,
                        len < want ? "truncated" : "bytes after the last triangle");
}

static int stl_read_binary(const char *path, const unsigned char *b, char up, rf_tri_list *out,
                           rf_error *err)
{
    uint32_t n = le32(b + 80);
    for (uint32_t k = 0; k < n; k++) {
        const unsigned char *f = b + 84 + 50 * (size_t)k + 12; /* skip the facet normal */
        rf_vec3 v[3];
        for (int i = 0; i < 3; i++) {
            const unsigned char *q = f + 12 * i;
            v[i] = to_world(le_float(q), le_float(q + 4), le_float(q + 8), up);
            if (!isfinite(v[i].x) || !isfinite(v[i].y) || !isfinite(v[i].z))
                return rf_error_set(err, path, 0, 0, "facet %u of binary STL has a non-finite vertex",
                                    (unsigned)k + 1);
            if (!vertex_in_bounds(v[i]))
                return rf_error_set(err, path, 0, 0,
                                    "facet %u of binary STL: vertex (%g, %g, %g) is out of "
                                    "bounds: x and y must be within %g m, the elevation within "
                                    "%g m",
                                    (unsigned)k + 1, v[i].x, v[i].y, v[i].z, RF_COORD_MAX,
                                    RF_ELEVATION_MAX);
        }
        int rc = tri_push(out, v[0], v[1], v[2]);
        if (rc)
            return push_failed(path, rc, err);
    }
    return 0;
}

/* Ascii STL: the vertices between "outer loop" and "endloop" form one facet (a polygon
 * with more than three is fan-triangulated). */
static int stl_read_ascii(scanner *s, char up, rf_tri_list *out, rf_error *err)
{
    rf_vec3 first = {0, 0, 0}, prev = {0, 0, 0};
    int nloop = 0, in_loop = 0, loop_line = 0, loop_col = 0;
    while (scan_skip(s, 1)) {
        const char *a, *b = scan_token(s, &a);
        if (token_is(a, b, "loop")) {
            in_loop = 1;
            nloop = 0;
            loop_line = s->line;
            loop_col = scan_column(s, a);
        } else if (token_is(a, b, "vertex")) {
            if (!in_loop)
                return rf_error_set(err, s->path, s->line, scan_column(s, a),
                                    "'vertex' outside 'outer loop'");
            double x, y, z;
            int vline = s->line, vcol = scan_column(s, a);
            if (scan_number(s, 0, &x, err) || scan_number(s, 0, &y, err) ||
                scan_number(s, 0, &z, err))
                return -1;
            rf_vec3 v = to_world(x, y, z, up);
            if (!vertex_in_bounds(v))
                return vertex_error(s->path, vline, vcol, v, err);
            int rc = nloop >= 2 ? tri_push(out, first, prev, v) : 0;
            if (rc)
                return push_failed(s->path, rc, err);
            if (nloop == 0)
                first = v;
            prev = v;
            nloop++;
        } else if (token_is(a, b, "endloop")) {
            if (!in_loop || nloop < 3)
                return rf_error_set(err, s->path, loop_line, loop_col,
                                    "a facet needs at least 3 vertices");
            in_loop = 0;
        } else if (token_is(a, b, "solid") || token_is(a, b, "endsolid")) {
            scan_to_next_line(s); /* the name may be anything */
        } else if (token_is(a, b, "normal")) {
            double x;
            for (int i = 0; i < 3; i++)
                if (scan_number(s, 0, &x, err))
                    return -1;
        } else if (!token_is(a, b, "facet") && !token_is(a, b, "outer") &&
                   !token_is(a, b, "endfacet")) {
            return rf_error_set(err, s->path, s->line, scan_column(s, a),
                                "unexpected '%.*s' in ascii STL", shown_len(a, b), a);
        }
    }
    if (in_loop)
        return rf_error_set(err, s->path, s->line, scan_column(s, s->p),
                            "file ends inside a facet");
    return 0;
}

/* ---- OBJ ------------------------------------------------------------------------------ */

typedef struct vert_list {
    rf_vec3 *v;
    size_t n, cap;
} vert_list;

/* An OBJ face index ("7", "7/2", "7//3", "7/2/3", "-1"): the 0-based vertex index. */
static int obj_index(const char *a, const char *b, size_t nverts, size_t *idx)
{
    const char *slash = memchr(a, '/', (size_t)(b - a));
    const char *e = slash ? slash : b;
    if (e == a || (size_t)(e - a) > 20)
        return 0;
    char tmp[24];
    memcpy(tmp, a, (size_t)(e - a));
    tmp[e - a] = '\0';
    char *end;
    long long k = strtoll(tmp, &end, 10);
    if (*end != '\0' || k == 0)
        return 0;
    if (k > 0 && (unsigned long long)k <= nverts)
        *idx = (size_t)(k - 1);
    else if (k < 0 && (unsigned long long)(-k) <= nverts)
        *idx = nverts - (size_t)(-k);
    else
        return 0;
    return 1;
}

static int obj_parse(scanner *s, char up, rf_tri_list *out, vert_list *vl, rf_error *err)
{
    while (scan_skip(s, 1)) {
        const char *a, *b = scan_token(s, &a);
        if (token_is(a, b, "v")) {
            double x, y, z;
            int vline = s->line, vcol = scan_column(s, a);
            if (scan_number(s, 0, &x, err) || scan_number(s, 0, &y, err) ||
                scan_number(s, 0, &z, err))
                return -1;
            if ((double)vl->n >= RF_MESH_VERTICES_MAX)
                return rf_error_set(err, s->path, vline, vcol, "more than %.0f vertices",
                                    RF_MESH_VERTICES_MAX);
            if (rf_grow((void **)&vl->v, &vl->cap, vl->n + 1, sizeof *vl->v))
                return rf_error_set(err, s->path, 0, 0, "out of memory");
            rf_vec3 v = to_world(x, y, z, up);
            if (!vertex_in_bounds(v))
                return vertex_error(s->path, vline, vcol, v, err);
            vl->v[vl->n++] = v;
        } else if (token_is(a, b, "f")) {
            int fline = s->line, fcol = scan_column(s, a);
            size_t first = 0, prev = 0, n = 0;
            while (scan_skip(s, 0)) {
                const char *ia, *ib = scan_token(s, &ia);
                size_t idx;
                if (!obj_index(ia, ib, vl->n, &idx))
                    return rf_error_set(err, s->path, s->line, scan_column(s, ia),
                                        "bad vertex index '%.*s' (%zu vertices so far)",
                                        shown_len(ia, ib), ia, vl->n);
                int rc = n >= 2 ? tri_push(out, vl->v[first], vl->v[prev], vl->v[idx]) : 0;
                if (rc)
                    return push_failed(s->path, rc, err);
                if (n == 0)
                    first = idx;
                prev = idx;
                n++;
            }
            if (n < 3)
                return rf_error_set(err, s->path, fline, fcol, "a face needs at least 3 vertices");
        }
        /* Anything else (vt, vn, g, o, s, usemtl, mtllib, l, comments) does not shape
         * the surface. */
        scan_to_next_line(s);
    }
    return 0;
}

/* ---- meshes ------------------------------------------------------------------------- */

static int has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext);
    return n >= m && token_is(path + n - m, path + n, ext);
}

int rf_mesh_read_from_memory(const char *data, size_t len, const char *name, int obj, char up,
                             rf_tri_list *out, rf_error *err)
{
    size_t n_before = out->n;
    scanner s;
    scan_init(&s, name, data, len);
    int rc;
    if (obj) {
        vert_list vl = {NULL, 0, 0};
        rc = obj_parse(&s, up, out, &vl, err);
        free(vl.v);
    } else if (stl_binary_size_matches(len, (const unsigned char *)data)) {
        rc = stl_read_binary(name, (const unsigned char *)data, up, out, err);
    } else if (stl_looks_binary(data, len)) {
        rc = stl_binary_size_error(name, (const unsigned char *)data, len, err);
    } else {
        rc = stl_read_ascii(&s, up, out, err);
    }
    if (rc)
        out->n = n_before;
    return rc;
}

int rf_mesh_read(const char *path, char up, rf_tri_list *out, rf_error *err)
{
    rf_mapped m;
    if (rf_map_file(path, RF_TERRAIN_FILE_MAX, &m, err))
        return -1;
    int rc = rf_mesh_read_from_memory(m.data, m.len, path, has_extension(path, ".obj"), up, out,
                                      err);
    rf_unmap_file(&m);
    return rc;
}

/* ---- rows of numbers ------------------------------------------------------------ */

int rf_points_read_from_memory(const char *data, size_t len, const char *name, size_t ncol,
                               rf_points *out, rf_error *err)
{
    memset(out, 0, sizeof *out);
    size_t cap = 0;
    scanner s;
    scan_init(&s, name, data, len);
    int rc = 0;
    while (rc == 0 && scan_skip(&s, 1)) {
        if (*s.p == '#') {
            scan_to_next_line(&s);
            continue;
        }
        if ((double)out->n >= RF_POINTS_ROWS_MAX) {
            rc = rf_error_set(err, name, s.line, 1, "more than %.0f rows", RF_POINTS_ROWS_MAX);
            break;
        }
        if (rf_grow((void **)&out->v, &cap, (out->n + 1) * ncol, sizeof *out->v)) {
            rc = rf_error_set(err, name, s.line, 0, "out of memory");
            break;
        }
        for (size_t k = 0; rc == 0 && k < ncol; k++)
            rc = scan_number(&s, 0, &out->v[out->n * ncol + k], err);
        if (rc == 0)
            out->n++;
        scan_to_next_line(&s);
    }
    if (rc)
        rf_points_free(out);
    return rc;
}

int rf_points_read(const char *path, size_t ncol, rf_points *out, rf_error *err)
{
    memset(out, 0, sizeof *out);
    rf_mapped m;
    if (rf_map_file(path, RF_TERRAIN_FILE_MAX, &m, err))
        return -1;
    int rc = rf_points_read_from_memory(m.data, m.len, path, ncol, out, err);
    rf_unmap_file(&m);
    return rc;
}

void rf_points_free(rf_points *p)
{
    free(p->v);
    p->v = NULL;
    p->n = 0;
}
