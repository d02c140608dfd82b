/* chunk.c - a chunk's rows (montecarlo_private.h): freeing them, and packing them into
 * bytes for another process of the same build (mpi.c) and back. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "run/montecarlo_private.h"

void rf_chunk_clear(rf_chunk *c)
{
    free(c->traj);
    free(c->paths);
    free(c->icpts);
    free(c->trees);
    memset(c, 0, sizeof *c);
}

/* The packed header: first, n, npaths, nicpts, ntrees, oom. */
#define HEADER_WORDS 6

size_t rf_chunk_packed_size(const rf_chunk *c)
{
    return HEADER_WORDS * sizeof(uint64_t) + c->n * sizeof *c->traj +
           c->npaths * sizeof *c->paths + c->nicpts * sizeof *c->icpts +
           c->ntrees * sizeof *c->trees;
}

static unsigned char *put(unsigned char *at, const void *v, size_t bytes)
{
    if (bytes)
        memcpy(at, v, bytes);
    return at + bytes;
}

void rf_chunk_pack(const rf_chunk *c, unsigned char *buf)
{
    uint64_t h[HEADER_WORDS] = {c->first, c->traj ? c->n : 0, c->npaths, c->nicpts, c->ntrees,
                                (uint64_t)(c->oom || !c->traj)};
    unsigned char *at = put(buf, h, sizeof h);
    at = put(at, c->traj, h[1] * sizeof *c->traj);
    at = put(at, c->paths, c->npaths * sizeof *c->paths);
    at = put(at, c->icpts, c->nicpts * sizeof *c->icpts);
    put(at, c->trees, c->ntrees * sizeof *c->trees);
}

/* A copy of `count` records of `size` bytes at *at, within end; NULL for none. */
static int take(const unsigned char **at, const unsigned char *end, size_t count, size_t size,
                void **out)
{
    *out = NULL;
    if (count > (size_t)(end - *at) / size)
        return -1;
    if (count == 0)
        return 0;
    *out = malloc(count * size);
    if (!*out)
        return -1;
    memcpy(*out, *at, count * size);
    *at += count * size;
    return 0;
}

int rf_chunk_unpack(rf_chunk *c, const unsigned char *buf, size_t len)
{
    memset(c, 0, sizeof *c);
    uint64_t h[HEADER_WORDS];
    if (len < sizeof h)
        return -1;
    memcpy(h, buf, sizeof h);
    const unsigned char *at = buf + sizeof h, *end = buf + len;
    if (h[1] > RF_CHUNK_SIZE || h[5] > 1)
        return -1;
    c->first = (size_t)h[0];
    c->n = (size_t)h[1];
    c->npaths = c->cap_paths = (size_t)h[2];
    c->nicpts = c->cap_icpts = (size_t)h[3];
    c->ntrees = c->cap_trees = (size_t)h[4];
    c->oom = (int)h[5];
    void *traj = NULL, *paths = NULL, *icpts = NULL, *trees = NULL;
    int bad = take(&at, end, c->n, sizeof *c->traj, &traj) ||
              take(&at, end, c->npaths, sizeof *c->paths, &paths) ||
              take(&at, end, c->nicpts, sizeof *c->icpts, &icpts) ||
              take(&at, end, c->ntrees, sizeof *c->trees, &trees) || at != end;
    if (bad) {
        /* what was taken before the failure */
        free(traj);
        free(paths);
        free(icpts);
        free(trees);
        memset(c, 0, sizeof *c);
        return -1;
    }
    c->traj = traj;
    c->paths = paths;
    c->icpts = icpts;
    c->trees = trees;
    /* every row's ranges lie within the arrays, its stop reason is one of the four */
    for (size_t k = 0; k < c->n; k++) {
        const rf_traj_out *o = &c->traj[k];
        if (o->path_begin > o->path_end || o->path_end > c->npaths ||
            o->icpt_begin > o->icpt_end || o->icpt_end > c->nicpts ||
            o->tree_begin > o->tree_end || o->tree_end > c->ntrees ||
            (unsigned)o->rec.reason > RF_END_MAX_TIME) {
            rf_chunk_clear(c);
            return -1;
        }
    }
    return 0;
}
