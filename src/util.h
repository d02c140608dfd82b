/* util.h - small helpers shared by the modules: growing arrays, reading files. */
#ifndef ROCKFALL_UTIL_H
#define ROCKFALL_UTIL_H

#include <stddef.h>

#include "rockfall/error.h"

/* Makes room for at least `need` elements of `elem` bytes in *v (capacity *cap),
 * doubling; returns 0, or -1 when memory runs out (then *v is unchanged). */
int rf_grow(void **v, size_t *cap, size_t need, size_t elem);

/* Reads a whole file into a NUL-terminated malloc'd buffer (*len excludes the NUL).
 * Errors name the file: "cannot open 'PATH': reason", "cannot read ...". */
int rf_read_file(const char *path, char **text, size_t *len, rf_error *err);

#endif
