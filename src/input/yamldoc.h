/* yamldoc.h - strict, typed access to a YAML document with file:line:column errors.
 *
 * A thin layer over libyaml's document API (yaml_parser_load).  Every node keeps its
 * mark; every reader checks the node's type and range and, on bad input, fills an
 * rf_error that points at the node ("'mass' must be a number > 0, got -3") and
 * returns -1.  All readers return 0 on success.  Shared by the project and rules
 * loaders; nothing here knows either schema. */
#ifndef ROCKFALL_YAMLDOC_H
#define ROCKFALL_YAMLDOC_H

#include <math.h>
#include <stddef.h>

#include <yaml.h>

#include "rockfall/error.h"

typedef yaml_node_t rf_ynode;

typedef struct rf_ydoc {
    char *file;  /* the file name used in errors */
    char *text;  /* the whole file, NUL-terminated */
    size_t len;
    yaml_document_t doc;
    int loaded;  /* doc holds a document */
    char **origin; /* by node id - 1: where a node made from another file came from
                    * (input/layout.h), prefixed to its errors; NULL: the text's own */
    size_t norigin;
} rf_ydoc;

/* Allowed values of a number: lo .. hi, each end open (excluded) or closed. */
typedef struct rf_yrange {
    double lo, hi;
    int lo_open, hi_open;
} rf_yrange;

#define RF_YR_ANY ((rf_yrange){-HUGE_VAL, HUGE_VAL, 0, 0})
#define RF_YR_POSITIVE ((rf_yrange){0.0, HUGE_VAL, 1, 0})
#define RF_YR_NONNEG ((rf_yrange){0.0, HUGE_VAL, 0, 0})
#define RF_YR_UNIT ((rf_yrange){0.0, 1.0, 0, 0})
#define RF_YR_AT_LEAST(x) ((rf_yrange){(x), HUGE_VAL, 0, 0})
#define RF_YR_BETWEEN(a, b) ((rf_yrange){(a), (b), 0, 0})

/* Reads and parses one YAML document.  A file with no document (empty or comments
 * only) loads with a NULL root.  Syntax errors are reported at libyaml's problem
 * mark; a second document in the file is an error.  On failure d is left empty. */
int rf_ydoc_load_file(rf_ydoc *d, const char *path, rf_error *err);
/* The same from text in memory; `file` names it in errors. */
int rf_ydoc_load_text(rf_ydoc *d, const char *file, const char *text, size_t len,
                      rf_error *err);
void rf_ydoc_free(rf_ydoc *d);

rf_ynode *rf_ydoc_root(rf_ydoc *d);
/* 1-based position of a node. */
rf_mark rf_ydoc_mark(const rf_ynode *n);
/* Marks node `id` (yaml_document_add_*) as made from another file: `text` (copied) says
 * where ("layout.gpkg, layer 'barriers', feature 3, attribute 'mel'") and is prefixed
 * to every error at the node.  Returns 0, or -1 when memory runs out. */
int rf_ydoc_set_origin(rf_ydoc *d, int id, const char *text);
/* Fills err at the node's position (the document's start when n is NULL); returns -1. */
int rf_ydoc_error(const rf_ydoc *d, const rf_ynode *n, rf_error *err, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Describes a node for "got ..." in messages: the scalar text (shortened), "a mapping",
 * "a sequence" or "nothing" for an empty value.  Writes into buf and returns it. */
const char *rf_ydoc_describe(const rf_ynode *n, char *buf, size_t size);

/* ---- mappings ---------------------------------------------------------------- */
/* `what` names the value in messages ("'terrain'", "rock 2"). */
int rf_ydoc_mapping(const rf_ydoc *d, const rf_ynode *n, const char *what, rf_error *err);
size_t rf_ydoc_map_size(const rf_ynode *map);
rf_ynode *rf_ydoc_map_key(rf_ydoc *d, const rf_ynode *map, size_t i);
rf_ynode *rf_ydoc_map_value(rf_ydoc *d, const rf_ynode *map, size_t i);
/* Value of `key` in the mapping, or NULL when absent. */
rf_ynode *rf_ydoc_get(rf_ydoc *d, const rf_ynode *map, const char *key);
/* Every key must be a plain scalar, appear once and be one of `allowed` (a NULL-ended
 * list).  An unknown key is reported at the key with a "did you mean" hint when an
 * allowed key is close to it. */
int rf_ydoc_check_keys(rf_ydoc *d, const rf_ynode *map, const char *const *allowed,
                       const char *what, rf_error *err);
/* rf_ydoc_mapping, then rf_ydoc_check_keys, with `what` naming it in both. */
int rf_ydoc_mapping_of(rf_ydoc *d, const rf_ynode *n, const char *const *allowed,
                       const char *what, rf_error *err);
/* Value of a required key; when missing, an error at the mapping. */
int rf_ydoc_require(rf_ydoc *d, const rf_ynode *map, const char *key, const char *what,
                    rf_ynode **out, rf_error *err);

/* ---- sequences --------------------------------------------------------------- */
/* A sequence with at least `min_items` items ("'line' must be a sequence of at least 2
 * points"; `item_what` names the items, e.g. "points"). */
int rf_ydoc_sequence(const rf_ydoc *d, const rf_ynode *n, const char *key, size_t min_items,
                     const char *item_what, rf_error *err);
size_t rf_ydoc_seq_size(const rf_ynode *seq);
rf_ynode *rf_ydoc_seq_item(rf_ydoc *d, const rf_ynode *seq, size_t i);

/* ---- scalars ----------------------------------------------------------------- */
/* `key` names the value in messages.  Numbers and booleans must be plain (unquoted)
 * scalars; numbers must be finite and lie in the range. */
int rf_ydoc_number(const rf_ydoc *d, const rf_ynode *n, const char *key, rf_yrange range,
                   double *out, rf_error *err);
/* An integer literal (no fraction, no exponent) within the range. */
int rf_ydoc_integer(const rf_ydoc *d, const rf_ynode *n, const char *key, rf_yrange range,
                    long long *out, rf_error *err);
/* A non-empty string; *out points into the document. */
int rf_ydoc_string(const rf_ydoc *d, const rf_ynode *n, const char *key, const char **out,
                   rf_error *err);
/* true/false (also yes/no, on/off). */
int rf_ydoc_bool(const rf_ydoc *d, const rf_ynode *n, const char *key, int *out,
                 rf_error *err);
/* One of `names` (a NULL-ended list); *out is its index. */
int rf_ydoc_enum(const rf_ydoc *d, const rf_ynode *n, const char *key,
                 const char *const *names, int *out, rf_error *err);

/* Optional keys of a mapping: leave *out alone when the key is absent. */
int rf_ydoc_opt_number(rf_ydoc *d, const rf_ynode *map, const char *key, rf_yrange range,
                       double *out, rf_error *err);
int rf_ydoc_opt_integer(rf_ydoc *d, const rf_ynode *map, const char *key, rf_yrange range,
                        long long *out, rf_error *err);
int rf_ydoc_opt_enum(rf_ydoc *d, const rf_ynode *map, const char *key,
                     const char *const *names, int *out, rf_error *err);

/* Describes a range ("a number > 0", "an integer in 1..3") into buf. */
const char *rf_yrange_describe(rf_yrange r, int integer, char *buf, size_t size);
/* Edit distance of two strings (for "did you mean" hints). */
size_t rf_edit_distance(const char *a, const char *b);

#endif
