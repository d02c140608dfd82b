/* error.h - the one error record for bad input: a location and a message.
 * Library code never prints or exits; it fills an rf_error and returns nonzero. */
#ifndef ROCKFALL_ERROR_H
#define ROCKFALL_ERROR_H

#include <stdio.h>

typedef struct rf_error {
    char file[1024]; /* file the error is in ("" when none) */
    int line;        /* 1-based; 0 when unknown */
    int column;      /* 1-based; 0 when unknown */
    char message[1024];
} rf_error;

/* Where a value came from in a text file (1-based line and column). */
typedef struct rf_mark {
    int line, column;
} rf_mark;

/* Fills err (when not NULL) and returns -1, so callers can `return rf_error_set(...)`. */
int rf_error_set(rf_error *err, const char *file, int line, int column, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* Prints "file:line:column: error: message" (parts that are unknown are left out), the
 * file and message escaped for a terminal (base/term.h). */
void rf_error_print(const rf_error *err, FILE *out);

#endif
