/* error.c - filling and printing the bad-input error record. */
#include "rockfall/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "base/term.h"

int rf_error_set(rf_error *err, const char *file, int line, int column, const char *fmt, ...)
{
    if (!err)
        return -1;
    snprintf(err->file, sizeof err->file, "%s", file ? file : "");
    err->line = line;
    err->column = column;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return -1;
}

void rf_error_print(const rf_error *err, FILE *out)
{
    if (err->file[0]) {
        rf_term_fputs(err->file, out);
        if (err->line > 0) {
            fprintf(out, ":%d", err->line);
            if (err->column > 0)
                fprintf(out, ":%d", err->column);
        }
        fputs(": ", out);
    }
    fputs("error: ", out);
    rf_term_fputs(err->message, out); /* it may quote a file's text */
    fputc('\n', out);
}
