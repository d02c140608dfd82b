/* util.c - growing arrays, reading and mapping files, comparing doubles, the clock (see util.h). */
#include "base/util.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

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

/* Opens path for reading when it names a regular file of at most max_bytes: the
 * descriptor, with its size in *size; else -1 with err set.  O_NONBLOCK keeps the open of
 * a FIFO from waiting for a writer; a device, FIFO or directory is then refused. */
static int open_regular(const char *path, uint64_t max_bytes, uint64_t *size, rf_error *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return rf_error_set(err, path, 0, 0, "cannot open '%s': %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        rf_error_set(err, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        rf_error_set(err, path, 0, 0, "cannot read '%s': %s", path,
                     S_ISDIR(st.st_mode) ? strerror(EISDIR) : "not a regular file");
        close(fd);
        return -1;
    }
    if ((uint64_t)st.st_size > max_bytes) {
        rf_error_set(err, path, 0, 0, "'%s' is %llu bytes; at most %llu are read", path,
                     (unsigned long long)st.st_size, (unsigned long long)max_bytes);
        close(fd);
        return -1;
    }
    *size = (uint64_t)st.st_size;
    return fd;
}

int rf_read_file(const char *path, size_t max_bytes, char **text, size_t *len, rf_error *err)
{
    uint64_t size;
    int fd = open_regular(path, max_bytes, &size, err);
    if (fd < 0)
        return -1;
    /* the file may grow after fstat: read to its end, but never past max_bytes */
    char *buf = NULL;
    size_t cap = 0, n = 0;
    int status = 0;
    for (;;) {
        if (rf_grow((void **)&buf, &cap, n + 65536 + 1, 1)) {
            status = rf_error_set(err, path, 0, 0, "out of memory reading '%s'", path);
            break;
        }
        ssize_t got = read(fd, buf + n, cap - n - 1);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            status = rf_error_set(err, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
            break;
        }
        if (got == 0)
            break;
        n += (size_t)got;
        if (n > max_bytes) {
            status = rf_error_set(err, path, 0, 0, "'%s' is over %zu bytes; at most %zu are read",
                                  path, max_bytes, max_bytes);
            break;
        }
    }
    close(fd);
    if (status) {
        free(buf);
        return status;
    }
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return 0;
}

int rf_map_file(const char *path, uint64_t max_bytes, rf_mapped *m, rf_error *err)
{
    memset(m, 0, sizeof *m);
    uint64_t size = 0;
    int fd = open_regular(path, max_bytes, &size, err);
    if (fd < 0)
        return -1;
    if (size > (uint64_t)SIZE_MAX) {
        close(fd);
        return rf_error_set(err, path, 0, 0, "'%s' is too large to map", path);
    }
    m->data = "";
    if (size > 0) {
        void *p = mmap(NULL, (size_t)size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (p == MAP_FAILED) {
            rf_error_set(err, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
            close(fd);
            return -1;
        }
        m->data = p;
        m->mapped = 1;
    }
    close(fd);
    m->len = (size_t)size;
    return 0;
}

void rf_map_release(const rf_mapped *m, size_t upto)
{
    long page = sysconf(_SC_PAGESIZE);
    if (!m->mapped || page <= 0 || upto > m->len)
        return;
    size_t n = upto - upto % (size_t)page;
    if (n > 0)
        madvise((void *)m->data, n, MADV_DONTNEED);
}

void rf_unmap_file(rf_mapped *m)
{
    if (m->mapped)
        munmap((void *)m->data, m->len);
    memset(m, 0, sizeof *m);
}

FILE *rf_create_file(const char *path, rf_error *err)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
    if (fd < 0) {
        struct stat st;
        if (errno == ELOOP || (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)))
            rf_error_set(err, path, 0, 0,
                         "cannot write: it is a symbolic link, and no file is written through "
                         "one");
        else
            rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
        return NULL;
    }
    /* O_NONBLOCK kept the open of a FIFO without a reader from waiting; writes block */
    int flags = fcntl(fd, F_GETFL);
    if (flags != -1)
        fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    FILE *f = fdopen(fd, "w");
    if (!f) {
        close(fd);
        rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
    }
    return f;
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
