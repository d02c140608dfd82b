/* util.h - small helpers shared by the modules: growing arrays, reading files, cell
 * ranges. */
#ifndef ROCKFALL_UTIL_H
#define ROCKFALL_UTIL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "rockfall/error.h"

/* Makes room for at least `need` elements of `elem` bytes in *v (capacity *cap),
 * doubling; returns 0, or -1 when memory runs out (then *v is unchanged). */
int rf_grow(void **v, size_t *cap, size_t need, size_t elem);

/* Reads a whole regular file of at most max_bytes into a NUL-terminated malloc'd buffer
 * (*len excludes the NUL).  A directory, device or FIFO is refused at once, before any
 * read, and so is a larger file.  Errors name the file: "cannot open 'PATH': reason",
 * "cannot read 'PATH': not a regular file", "'PATH' is N bytes; at most M are read". */
int rf_read_file(const char *path, size_t max_bytes, char **text, size_t *len, rf_error *err);

/* A regular file mapped read-only: len bytes at data (not NUL-terminated; "" when
 * empty).  The pages are the file's own, read as they are touched: a large terrain file
 * costs no heap. */
typedef struct rf_mapped {
    const char *data;
    size_t len;
    int mapped;
} rf_mapped;

/* Gives back the memory of the pages of m wholly before byte `upto` (a mapped file read
 * from front to back holds only what is still to be read); reading them again reads
 * the file again.  Nothing for a file that is not mapped. */
void rf_map_release(const rf_mapped *m, size_t upto);

/* Maps a regular file of at most max_bytes, refused as rf_read_file refuses. */
int rf_map_file(const char *path, uint64_t max_bytes, rf_mapped *m, rf_error *err);
void rf_unmap_file(rf_mapped *m);

/* Creates or truncates the file at path for writing.  A symbolic link there is refused,
 * not followed (O_NOFOLLOW): an output folder may hold links planted to send the writes
 * elsewhere.  NULL with err set ("cannot write: ..."). */
FILE *rf_create_file(const char *path, rf_error *err);

/* qsort comparison of doubles, ascending. */
int rf_cmp_double(const void *a, const void *b);

/* Seconds on the monotonic clock (for intervals). */
double rf_now_s(void);

/* Index range [*lo, *hi] of n cells of size `size` from c0 that [a, b] touches; 0 when
 * none. */
static inline int rf_cell_range(double a, double b, double c0, double size, size_t n,
                                size_t *lo, size_t *hi)
{
    double fa = floor((a - c0) / size), fb = floor((b - c0) / size);
    if (!(fb >= 0 && fa <= (double)n - 1))
        return 0;
    *lo = fa < 0 ? 0 : (size_t)fa;
    *hi = fb > (double)n - 1 ? n - 1 : (size_t)fb;
    return 1;
}

/* fmin and fmax inline (the other argument when one is NaN) */
static inline double rf_fmin(double a, double b) { return (a < b || b != b) ? a : b; }
static inline double rf_fmax(double a, double b) { return (a > b || b != b) ? a : b; }

#endif
