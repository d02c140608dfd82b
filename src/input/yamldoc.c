/* yamldoc.c - strict, typed access to a YAML document with file:line:column errors. */
#include "input/yamldoc.h"
#include "base/util.h"
#include "input/bounds.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- loading ----------------------------------------------------------------- */

/* 1-based line and column of a byte offset in the text (for reader errors, which
 * libyaml reports as an offset). */
static rf_mark mark_of_offset(const char *text, size_t len, size_t offset)
{
    rf_mark m = {1, 1};
    for (size_t i = 0; i < offset && i < len; i++) {
        if (text[i] == '\n') {
            m.line++;
            m.column = 1;
        } else if (((unsigned char)text[i] & 0xC0) != 0x80) {
            m.column++;
        }
    }
    return m;
}

/* What libyaml's context names when it is a collection or scalar that must be closed
 * ("while parsing a flow sequence" -> "flow sequence"), else NULL. */
static const char *opened_here(const char *context)
{
    static const char *const openers[] = {"while parsing a flow ", "while scanning a quoted "};
    for (size_t i = 0; i < sizeof openers / sizeof *openers; i++)
        if (!strncmp(context, openers[i], strlen(openers[i])))
            return strstr(context, " a ") + 3;
    return NULL;
}

static int parser_error(const rf_ydoc *d, const yaml_parser_t *parser, rf_error *err)
{
    const char *problem = parser->problem ? parser->problem : "unknown problem";
    switch (parser->error) {
    case YAML_MEMORY_ERROR:
        return rf_error_set(err, d->file, 0, 0, "out of memory while reading YAML");
    case YAML_READER_ERROR: {
        rf_mark m = mark_of_offset(d->text, d->len, parser->problem_offset);
        if (parser->problem_value != -1)
            return rf_error_set(err, d->file, m.line, m.column,
                                "YAML syntax error: %s (byte #%X)", problem,
                                (unsigned)parser->problem_value);
        return rf_error_set(err, d->file, m.line, m.column, "YAML syntax error: %s",
                            problem);
    }
    default:
        if (parser->context && opened_here(parser->context))
            /* an unclosed '[', '{' or quote is found at the end of the file or of the
             * next lines: the place to look is where it opened */
            return rf_error_set(err, d->file, (int)parser->context_mark.line + 1,
                                (int)parser->context_mark.column + 1,
                                "YAML syntax error in the %s that starts here: %s (at line %d, "
                                "column %d)",
                                opened_here(parser->context), problem,
                                (int)parser->problem_mark.line + 1,
                                (int)parser->problem_mark.column + 1);
        if (parser->context)
            return rf_error_set(err, d->file, (int)parser->problem_mark.line + 1,
                                (int)parser->problem_mark.column + 1,
                                "YAML syntax error: %s %s (from line %d, column %d)",
                                parser->context, problem,
                                (int)parser->context_mark.line + 1,
                                (int)parser->context_mark.column + 1);
        return rf_error_set(err, d->file, (int)parser->problem_mark.line + 1,
                            (int)parser->problem_mark.column + 1, "YAML syntax error: %s",
                            problem);
    }
}

/* Hands the text's events to visit, in order, until it returns nonzero or the stream
 * ends; a syntax error ends them too (the loading reports it).  Returns what visit
 * returned last, 0 at the end, or -1 when no parser could be made. */
static int each_event(const rf_ydoc *d, int (*visit)(const yaml_event_t *e, void *ctx),
                      void *ctx)
{
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser))
        return -1;
    yaml_parser_set_input_string(&parser, (const unsigned char *)d->text, d->len);
    int rc = 0;
    for (int end = 0; !end && !rc;) {
        yaml_event_t e;
        if (!yaml_parser_parse(&parser, &e))
            break;
        end = e.type == YAML_STREAM_END_EVENT;
        rc = visit(&e, ctx);
        yaml_event_delete(&e);
    }
    yaml_parser_delete(&parser);
    return rc;
}

typedef struct {
    rf_ydoc *d;
    size_t k, n; /* the node of the next scalar or collection start; the nodes */
} tag_walk;

static int quote_tagged_event(const yaml_event_t *e, void *ctx)
{
    static const char *const typed[] = {YAML_INT_TAG, YAML_FLOAT_TAG, YAML_BOOL_TAG,
                                        YAML_NULL_TAG};
    tag_walk *w = ctx;
    yaml_node_t *nodes = w->d->doc.nodes.start;
    switch (e->type) {
    case YAML_SCALAR_EVENT:
        if (w->k < w->n && e->data.scalar.tag && nodes[w->k].type == YAML_SCALAR_NODE) {
            int is_typed = 0;
            for (size_t i = 0; i < sizeof typed / sizeof *typed; i++)
                is_typed |= strcmp((const char *)e->data.scalar.tag, typed[i]) == 0;
            if (!is_typed)
                nodes[w->k].data.scalar.style = YAML_SINGLE_QUOTED_SCALAR_STYLE;
        }
        w->k++;
        return 0;
    case YAML_SEQUENCE_START_EVENT:
    case YAML_MAPPING_START_EVENT:
        w->k++;
        return 0;
    case YAML_DOCUMENT_END_EVENT:
        return 1; /* the loaded document's events are all read */
    default:
        return 0;
    }
}

/* A scalar tagged as anything but a number, boolean or null (!!str 100, !local 100,
 * ! 100) is a string, as a quoted scalar is: it is given a quoted style, so that no
 * number or boolean is read from it.  The loaded document keeps no trace of an explicit
 * tag (the loader gives every untagged scalar the string tag too), so the text's events
 * are read again: the loader made one node of each scalar and each start of a sequence
 * or mapping, in their order. */
static void quote_tagged_strings(rf_ydoc *d)
{
    if (!memchr(d->text, '!', d->len))
        return; /* no tag anywhere */
    tag_walk w = {d, 0, (size_t)(d->doc.nodes.top - d->doc.nodes.start)};
    each_event(d, quote_tagged_event, &w);
}

/* Deeper than this, a sequence or mapping is refused: no project or rule file nests
 * more than a few levels, and libyaml's scanner takes a time growing with the square of
 * a flow collection's depth (100 000 levels of '[' took 30 s before an error). */
#define RF_YAML_MAX_DEPTH 64

typedef struct {
    const rf_ydoc *d;
    int depth;
    rf_error *err;
} depth_walk;

static int depth_event(const yaml_event_t *e, void *ctx)
{
    depth_walk *w = ctx;
    if (e->type == YAML_SEQUENCE_START_EVENT || e->type == YAML_MAPPING_START_EVENT) {
        if (++w->depth > RF_YAML_MAX_DEPTH) {
            rf_error_set(w->err, w->d->file, (int)e->start_mark.line + 1,
                         (int)e->start_mark.column + 1, "YAML nested deeper than %d levels",
                         RF_YAML_MAX_DEPTH);
            return 1;
        }
    } else if (e->type == YAML_SEQUENCE_END_EVENT || e->type == YAML_MAPPING_END_EVENT) {
        w->depth--;
    }
    return 0;
}

/* Refuses a collection nested deeper than RF_YAML_MAX_DEPTH, reading the events before
 * the document is loaded. */
static int check_depth(const rf_ydoc *d, rf_error *err)
{
    depth_walk w = {d, 0, err};
    int rc = each_event(d, depth_event, &w);
    if (rc < 0)
        return rf_error_set(err, d->file, 0, 0, "out of memory while reading YAML");
    return rc ? -1 : 0;
}

/* The children of node n (1-based ids): the items of a sequence, the keys and values of
 * a mapping, in order; *count of them. */
static yaml_node_item_t child_of(const yaml_node_t *n, size_t k)
{
    if (n->type == YAML_SEQUENCE_NODE)
        return n->data.sequence.items.start[k];
    const yaml_node_pair_t *pair = &n->data.mapping.pairs.start[k / 2];
    return k % 2 ? pair->value : pair->key;
}

static size_t child_count(const yaml_node_t *n)
{
    if (n->type == YAML_SEQUENCE_NODE)
        return (size_t)(n->data.sequence.items.top - n->data.sequence.items.start);
    if (n->type == YAML_MAPPING_NODE)
        return 2 * (size_t)(n->data.mapping.pairs.top - n->data.mapping.pairs.start);
    return 0;
}

/* The document as the readers see it, every alias replaced by the node it names, may
 * hold at most RF_YAML_EXPANSION_MAX times the nodes the file writes out (and
 * RF_YAML_EXPANSION_FLOOR in any case), so that reading it costs time linear in the
 * file.  An alias inside the node it names (&a [*a]) expands without end and is refused
 * too.  Counted depth first without recursion, each node's expanded size once. */
static int check_expansion(rf_ydoc *d, rf_error *err)
{
    yaml_node_t *nodes = d->doc.nodes.start;
    size_t n = (size_t)(d->doc.nodes.top - nodes);
    if (n == 0)
        return 0;
    double budget = fmax(RF_YAML_EXPANSION_MAX * (double)n, RF_YAML_EXPANSION_FLOOR);
    double *size = calloc(n, sizeof *size);
    unsigned char *state = calloc(n, 1); /* 0 not seen, 1 open, 2 counted */
    size_t *stack = malloc(n * sizeof *stack), *next = malloc(n * sizeof *next);
    int rc = 0;
    if (!size || !state || !stack || !next) {
        rc = rf_error_set(err, d->file, 0, 0, "out of memory while reading YAML");
        goto done;
    }
    size_t top = 0;
    stack[top] = 0; /* the root is node 1 */
    next[top++] = 0;
    state[0] = 1;
    size[0] = 1;
    while (top && rc == 0) {
        size_t i = stack[top - 1];
        if (next[top - 1] < child_count(&nodes[i])) {
            size_t c = (size_t)child_of(&nodes[i], next[top - 1]++) - 1;
            if (state[c] == 2) {
                size[i] += size[c];
            } else if (state[c] == 1) {
                rf_mark m = rf_ydoc_mark(&nodes[c]);
                rc = rf_error_set(err, d->file, m.line, m.column,
                                  "a YAML alias refers to this node from inside it");
            } else {
                state[c] = 1;
                size[c] = 1;
                stack[top] = c;
                next[top++] = 0;
            }
            continue;
        }
        state[i] = 2;
        if (size[i] > budget) {
            rf_mark m = rf_ydoc_mark(&nodes[i]);
            rc = rf_error_set(err, d->file, m.line, m.column,
                              "through its YAML aliases this expands to %.3g nodes; the file "
                              "writes out %zu, and may expand to at most %g times as many",
                              size[i], n, RF_YAML_EXPANSION_MAX);
        }
        if (--top)
            size[stack[top - 1]] += size[i];
    }
done:
    free(size);
    free(state);
    free(stack);
    free(next);
    return rc ? -1 : 0;
}

static int parse_text(rf_ydoc *d, rf_error *err)
{
    if (check_depth(d, err))
        return -1;
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser))
        return rf_error_set(err, d->file, 0, 0, "out of memory while reading YAML");
    yaml_parser_set_input_string(&parser, (const unsigned char *)d->text, d->len);
    if (!yaml_parser_load(&parser, &d->doc)) {
        parser_error(d, &parser, err);
        yaml_parser_delete(&parser);
        return -1;
    }
    d->loaded = 1;
    if (check_expansion(d, err)) {
        yaml_parser_delete(&parser);
        return -1;
    }
    quote_tagged_strings(d);
    if (yaml_document_get_root_node(&d->doc)) {
        yaml_document_t next;
        if (!yaml_parser_load(&parser, &next)) {
            parser_error(d, &parser, err);
            yaml_parser_delete(&parser);
            return -1;
        }
        yaml_node_t *root = yaml_document_get_root_node(&next);
        if (root) {
            rf_mark m = rf_ydoc_mark(root);
            yaml_document_delete(&next);
            yaml_parser_delete(&parser);
            return rf_error_set(err, d->file, m.line, m.column,
                                "a second YAML document starts here; the file must hold "
                                "exactly one");
        }
        yaml_document_delete(&next);
    }
    yaml_parser_delete(&parser);
    return 0;
}

/* Takes `text` (len bytes and a NUL, malloc'd; NULL when that failed) into d and
 * parses it: the text is read into memory once and kept, not copied again. */
static int load_owned(rf_ydoc *d, const char *file, char *text, size_t len, rf_error *err)
{
    memset(d, 0, sizeof *d);
    d->text = text;
    d->len = len;
    d->file = strdup(file ? file : "");
    if (!d->file || !d->text) {
        rf_ydoc_free(d);
        return rf_error_set(err, file, 0, 0, "out of memory");
    }
    if (parse_text(d, err)) {
        rf_ydoc_free(d);
        return -1;
    }
    return 0;
}

int rf_ydoc_load_text(rf_ydoc *d, const char *file, const char *text, size_t len,
                      rf_error *err)
{
    char *copy = malloc(len + 1);
    if (copy) {
        memcpy(copy, text, len);
        copy[len] = '\0';
    }
    return load_owned(d, file, copy, len, err);
}

int rf_ydoc_load_file(rf_ydoc *d, const char *path, rf_error *err)
{
    memset(d, 0, sizeof *d);
    char *text;
    size_t len;
    if (rf_read_file(path, RF_TEXT_FILE_MAX, &text, &len, err))
        return -1;
    return load_owned(d, path, text, len, err);
}

void rf_ydoc_free(rf_ydoc *d)
{
    if (d->loaded)
        yaml_document_delete(&d->doc);
    for (size_t i = 0; i < d->norigin; i++)
        free(d->origin[i]);
    free(d->origin);
    free(d->file);
    free(d->text);
    memset(d, 0, sizeof *d);
}

rf_ynode *rf_ydoc_root(rf_ydoc *d)
{
    return d->loaded ? yaml_document_get_root_node(&d->doc) : NULL;
}

rf_mark rf_ydoc_mark(const rf_ynode *n)
{
    rf_mark m = {1, 1};
    if (n) {
        m.line = (int)n->start_mark.line + 1;
        m.column = (int)n->start_mark.column + 1;
    }
    return m;
}

int rf_ydoc_set_origin(rf_ydoc *d, int id, const char *text)
{
    if (id < 1)
        return -1;
    size_t need = (size_t)id;
    if (need > d->norigin) {
        size_t cap = d->norigin ? d->norigin : 64;
        while (cap < need)
            cap *= 2;
        char **o = realloc(d->origin, cap * sizeof *o);
        if (!o)
            return -1;
        memset(o + d->norigin, 0, (cap - d->norigin) * sizeof *o);
        d->origin = o;
        d->norigin = cap;
    }
    free(d->origin[id - 1]);
    d->origin[id - 1] = strdup(text);
    return d->origin[id - 1] ? 0 : -1;
}

/* Where a node made from another file came from; NULL for the text's own nodes. */
static const char *origin_of(const rf_ydoc *d, const rf_ynode *n)
{
    if (!n || !d->loaded || !d->origin || n < d->doc.nodes.start || n >= d->doc.nodes.top)
        return NULL;
    size_t i = (size_t)(n - d->doc.nodes.start);
    return i < d->norigin ? d->origin[i] : NULL;
}

int rf_ydoc_error(const rf_ydoc *d, const rf_ynode *n, rf_error *err, const char *fmt, ...)
{
    if (!err)
        return -1;
    char msg[sizeof err->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    rf_mark m = rf_ydoc_mark(n);
    const char *from = origin_of(d, n);
    if (from)
        return rf_error_set(err, d->file, m.line, m.column, "%s: %s", from, msg);
    return rf_error_set(err, d->file, m.line, m.column, "%s", msg);
}

static const char *scalar_text(const rf_ynode *n)
{
    return (const char *)n->data.scalar.value;
}

static int is_plain(const rf_ynode *n)
{
    return n->type == YAML_SCALAR_NODE && n->data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
}

static int is_null(const rf_ynode *n)
{
    if (!is_plain(n))
        return 0;
    const char *s = scalar_text(n);
    return !s[0] || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") ||
           !strcmp(s, "NULL");
}

const char *rf_ydoc_describe(const rf_ynode *n, char *buf, size_t size)
{
    if (!n) {
        snprintf(buf, size, "nothing");
    } else if (n->type == YAML_MAPPING_NODE) {
        snprintf(buf, size, "a mapping");
    } else if (n->type == YAML_SEQUENCE_NODE) {
        snprintf(buf, size, "a sequence");
    } else if (is_null(n)) {
        snprintf(buf, size, "nothing");
    } else {
        const char *s = scalar_text(n);
        const char *quote = is_plain(n) ? "" : "\"";
        size_t len = strlen(s);
        if (len > 40)
            snprintf(buf, size, "%s%.40s...%s", quote, s, quote);
        else
            snprintf(buf, size, "%s%s%s", quote, s, quote);
        for (char *c = buf; *c; c++)
            if (*c == '\n' || *c == '\t')
                *c = ' ';
    }
    return buf;
}

/* ---- mappings ---------------------------------------------------------------- */

int rf_ydoc_mapping(const rf_ydoc *d, const rf_ynode *n, const char *what, rf_error *err)
{
    if (n && n->type == YAML_MAPPING_NODE)
        return 0;
    char got[64];
    return rf_ydoc_error(d, n, err, "%s must be a mapping (key: value pairs), got %s", what,
                         rf_ydoc_describe(n, got, sizeof got));
}

size_t rf_ydoc_map_size(const rf_ynode *map)
{
    return (size_t)(map->data.mapping.pairs.top - map->data.mapping.pairs.start);
}

rf_ynode *rf_ydoc_map_key(rf_ydoc *d, const rf_ynode *map, size_t i)
{
    return yaml_document_get_node(&d->doc, map->data.mapping.pairs.start[i].key);
}

rf_ynode *rf_ydoc_map_value(rf_ydoc *d, const rf_ynode *map, size_t i)
{
    return yaml_document_get_node(&d->doc, map->data.mapping.pairs.start[i].value);
}

rf_ynode *rf_ydoc_get(rf_ydoc *d, const rf_ynode *map, const char *key)
{
    size_t n = rf_ydoc_map_size(map);
    for (size_t i = 0; i < n; i++) {
        rf_ynode *k = rf_ydoc_map_key(d, map, i);
        if (k && k->type == YAML_SCALAR_NODE && !strcmp(scalar_text(k), key))
            return rf_ydoc_map_value(d, map, i);
    }
    return NULL;
}

size_t rf_edit_distance(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b);
    if (na > 64 || nb > 64)
        return na > nb ? na : nb;
    size_t row[65];
    for (size_t j = 0; j <= nb; j++)
        row[j] = j;
    for (size_t i = 1; i <= na; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= nb; j++) {
            size_t up = row[j];
            int same = tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 1]);
            size_t cost = same ? 0 : 1;
            size_t best = diag + cost;
            if (up + 1 < best)
                best = up + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[nb];
}

/* The entry of `names` closest to s, when it is close enough to be a likely typo. */
static const char *closest(const char *s, const char *const *names)
{
    size_t len = strlen(s);
    size_t limit = len / 3 > 1 ? len / 3 : 1;
    if (limit > 3)
        limit = 3;
    const char *best = NULL;
    size_t best_d = limit + 1;
    for (const char *const *n = names; *n; n++) {
        size_t dist = rf_edit_distance(s, *n);
        if (dist < best_d) {
            best_d = dist;
            best = *n;
        }
    }
    return best;
}

static void join_names(const char *const *names, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (const char *const *n = names; *n && used < size; n++) {
        int w = snprintf(buf + used, size - used, "%s%s", n == names ? "" : ", ", *n);
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

int rf_ydoc_mapping_of(rf_ydoc *d, const rf_ynode *n, const char *const *allowed,
                       const char *what, rf_error *err)
{
    if (rf_ydoc_mapping(d, n, what, err))
        return -1;
    return rf_ydoc_check_keys(d, n, allowed, what, err);
}

int rf_ydoc_check_keys(rf_ydoc *d, const rf_ynode *map, const char *const *allowed,
                       const char *what, rf_error *err)
{
    size_t n = rf_ydoc_map_size(map);
    for (size_t i = 0; i < n; i++) {
        rf_ynode *k = rf_ydoc_map_key(d, map, i);
        if (!k || k->type != YAML_SCALAR_NODE || is_null(k))
            return rf_ydoc_error(d, k, err, "keys of %s must be names", what);
        const char *name = scalar_text(k);
        for (size_t j = 0; j < i; j++) {
            rf_ynode *prev = rf_ydoc_map_key(d, map, j);
            if (prev && prev->type == YAML_SCALAR_NODE && !strcmp(scalar_text(prev), name)) {
                rf_mark m = rf_ydoc_mark(prev);
                return rf_ydoc_error(d, k, err,
                                     "duplicate key '%s' in %s (first given at line %d)", name,
                                     what, m.line);
            }
        }
        int known = 0;
        for (const char *const *a = allowed; *a && !known; a++)
            known = !strcmp(*a, name);
        if (known)
            continue;
        const char *hint = closest(name, allowed);
        if (hint)
            return rf_ydoc_error(d, k, err, "unknown key '%s' in %s (did you mean '%s'?)",
                                 name, what, hint);
        char list[512];
        join_names(allowed, list, sizeof list);
        return rf_ydoc_error(d, k, err, "unknown key '%s' in %s (expected one of: %s)", name,
                             what, list);
    }
    return 0;
}

int rf_ydoc_require(rf_ydoc *d, const rf_ynode *map, const char *key, const char *what,
                    rf_ynode **out, rf_error *err)
{
    *out = rf_ydoc_get(d, map, key);
    if (*out)
        return 0;
    return rf_ydoc_error(d, map, err, "missing required key '%s' in %s", key, what);
}

/* ---- sequences --------------------------------------------------------------- */

int rf_ydoc_sequence(const rf_ydoc *d, const rf_ynode *n, const char *key, size_t min_items,
                     const char *item_what, rf_error *err)
{
    char got[64];
    if (!n || n->type != YAML_SEQUENCE_NODE)
        return rf_ydoc_error(d, n, err, "'%s' must be a sequence of %s, got %s", key,
                             item_what, rf_ydoc_describe(n, got, sizeof got));
    size_t size = rf_ydoc_seq_size(n);
    if (size == 0 && min_items == 1)
        return rf_ydoc_error(d, n, err, "'%s' must not be empty", key);
    if (size < min_items)
        return rf_ydoc_error(d, n, err, "'%s' must have at least %zu %s, got %zu", key,
                             min_items, item_what, size);
    return 0;
}

size_t rf_ydoc_seq_size(const rf_ynode *seq)
{
    return (size_t)(seq->data.sequence.items.top - seq->data.sequence.items.start);
}

rf_ynode *rf_ydoc_seq_item(rf_ydoc *d, const rf_ynode *seq, size_t i)
{
    return yaml_document_get_node(&d->doc, seq->data.sequence.items.start[i]);
}

/* ---- scalars ----------------------------------------------------------------- */

const char *rf_yrange_describe(rf_yrange r, int integer, char *buf, size_t size)
{
    const char *kind = integer ? "an integer" : "a number";
    int has_lo = isfinite(r.lo), has_hi = isfinite(r.hi);
    if (has_lo && has_hi) {
        if (integer)
            snprintf(buf, size, "%s in %.0f..%.0f", kind, r.lo, r.hi);
        else
            snprintf(buf, size, "%s in %c%g, %g%c", kind, r.lo_open ? '(' : '[', r.lo, r.hi,
                     r.hi_open ? ')' : ']');
    } else if (has_lo) {
        snprintf(buf, size, "%s %s %g", kind, r.lo_open ? ">" : ">=", r.lo);
    } else if (has_hi) {
        snprintf(buf, size, "%s %s %g", kind, r.hi_open ? "<" : "<=", r.hi);
    } else {
        snprintf(buf, size, "%s", kind);
    }
    return buf;
}

static int in_range(double v, rf_yrange r)
{
    if (r.lo_open ? !(v > r.lo) : !(v >= r.lo))
        return 0;
    if (r.hi_open ? !(v < r.hi) : !(v <= r.hi))
        return 0;
    return 1;
}

static int range_error(const rf_ydoc *d, const rf_ynode *n, const char *key, rf_yrange range,
                       int integer, rf_error *err)
{
    char want[96], got[64];
    return rf_ydoc_error(d, n, err, "'%s' must be %s, got %s", key,
                         rf_yrange_describe(range, integer, want, sizeof want),
                         rf_ydoc_describe(n, got, sizeof got));
}

int rf_ydoc_number(const rf_ydoc *d, const rf_ynode *n, const char *key, rf_yrange range,
                   double *out, rf_error *err)
{
    if (!n || !is_plain(n) || is_null(n))
        return range_error(d, n, key, range, 0, err);
    const char *s = scalar_text(n);
    for (const char *c = s; *c; c++)
        if (!isdigit((unsigned char)*c) && !strchr("+-.eE", *c))
            return range_error(d, n, key, range, 0, err);
    errno = 0;
    char *end = NULL;
    double v = strtod(s, &end);
    if (end == s || *end || errno == ERANGE || !isfinite(v) || !in_range(v, range))
        return range_error(d, n, key, range, 0, err);
    *out = v;
    return 0;
}

int rf_ydoc_integer(const rf_ydoc *d, const rf_ynode *n, const char *key, rf_yrange range,
                    long long *out, rf_error *err)
{
    if (!n || !is_plain(n) || is_null(n))
        return range_error(d, n, key, range, 1, err);
    const char *s = scalar_text(n);
    const char *c = s;
    if (*c == '+' || *c == '-')
        c++;
    if (!*c)
        return range_error(d, n, key, range, 1, err);
    for (; *c; c++)
        if (!isdigit((unsigned char)*c))
            return range_error(d, n, key, range, 1, err);
    errno = 0;
    char *end = NULL;
    long long v = strtoll(s, &end, 10);
    if (*end || errno == ERANGE || !in_range((double)v, range))
        return range_error(d, n, key, range, 1, err);
    *out = v;
    return 0;
}

int rf_ydoc_string(const rf_ydoc *d, const rf_ynode *n, const char *key, const char **out,
                   rf_error *err)
{
    char got[64];
    if (!n || n->type != YAML_SCALAR_NODE || is_null(n) || !scalar_text(n)[0])
        return rf_ydoc_error(d, n, err, "'%s' must be a non-empty string, got %s", key,
                             rf_ydoc_describe(n, got, sizeof got));
    *out = scalar_text(n);
    return 0;
}

int rf_ydoc_bool(const rf_ydoc *d, const rf_ynode *n, const char *key, int *out,
                 rf_error *err)
{
    static const char *const yes[] = {"true", "yes", "on", NULL};
    static const char *const no[] = {"false", "no", "off", NULL};
    if (n && is_plain(n) && strlen(scalar_text(n)) < 8) {
        char lower[8];
        const char *s = scalar_text(n);
        size_t i = 0;
        for (; s[i]; i++)
            lower[i] = (char)tolower((unsigned char)s[i]);
        lower[i] = '\0';
        for (int k = 0; yes[k]; k++) {
            if (!strcmp(lower, yes[k]) || !strcmp(lower, no[k])) {
                *out = !strcmp(lower, yes[k]);
                return 0;
            }
        }
    }
    char got[64];
    return rf_ydoc_error(d, n, err, "'%s' must be true or false, got %s", key,
                         rf_ydoc_describe(n, got, sizeof got));
}

int rf_ydoc_enum(const rf_ydoc *d, const rf_ynode *n, const char *key,
                 const char *const *names, int *out, rf_error *err)
{
    if (n && n->type == YAML_SCALAR_NODE) {
        for (int i = 0; names[i]; i++) {
            if (!strcmp(scalar_text(n), names[i])) {
                *out = i;
                return 0;
            }
        }
    }
    char list[256], got[64];
    join_names(names, list, sizeof list);
    rf_ydoc_describe(n, got, sizeof got);
    const char *hint = n && n->type == YAML_SCALAR_NODE ? closest(scalar_text(n), names) : NULL;
    if (hint)
        return rf_ydoc_error(d, n, err, "'%s' must be one of %s; got %s (did you mean '%s'?)",
                             key, list, got, hint);
    return rf_ydoc_error(d, n, err, "'%s' must be one of %s; got %s", key, list, got);
}

int rf_ydoc_opt_number(rf_ydoc *d, const rf_ynode *map, const char *key, rf_yrange range,
                       double *out, rf_error *err)
{
    rf_ynode *n = rf_ydoc_get(d, map, key);
    return n ? rf_ydoc_number(d, n, key, range, out, err) : 0;
}

int rf_ydoc_opt_integer(rf_ydoc *d, const rf_ynode *map, const char *key, rf_yrange range,
                        long long *out, rf_error *err)
{
    rf_ynode *n = rf_ydoc_get(d, map, key);
    return n ? rf_ydoc_integer(d, n, key, range, out, err) : 0;
}

int rf_ydoc_opt_enum(rf_ydoc *d, const rf_ynode *map, const char *key,
                     const char *const *names, int *out, rf_error *err)
{
    rf_ynode *n = rf_ydoc_get(d, map, key);
    return n ? rf_ydoc_enum(d, n, key, names, out, err) : 0;
}
