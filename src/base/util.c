/* util.c - growing arrays, reading files, comparing doubles, the clock (see util.h). */
#include "base/util.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int rf_grow(void **v, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return 0;
    size_t nc = *cap ? *cap : 16;
    while (nc < need)
        nc *= 2;
    void *nv = realloc(*v, nc * elem);
    if (!nv)
        return -1;
    *v = nv;
    *cap = nc;
    return 0;
}

int rf_read_file(const char *path, char **text, size_t *len, rf_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return rf_error_set(err, path, 0, 0, "cannot open '%s': %s", path, strerror(errno));
    char *buf = NULL;
    size_t cap = 0, n = 0;
    int status = 0;
    for (;;) {
        if (rf_grow((void **)&buf, &cap, n + 65536 + 1, 1)) {
            status = rf_error_set(err, path, 0, 0, "out of memory reading '%s'", path);
            break;
        }
        size_t got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0)
            break;
    }
    if (status == 0 && ferror(f))
        status = rf_error_set(err, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
    fclose(f);
    if (status) {
        free(buf);
        return status;
    }
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return 0;
}

int rf_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double rf_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
