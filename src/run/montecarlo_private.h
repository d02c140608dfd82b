/* montecarlo_private.h - the parts of a Monte Carlo run that the one-process run
 * (montecarlo.c) and the run over MPI ranks (mpi.c, built by `make mpi`) share: the
 * chunks of consecutive trajectories and their rows, the worker threads that fill them,
 * writing a chunk, and the end of a run.
 *
 * A chunk is the unit of work everywhere: chunk ci holds the trajectories
 * ci * RF_CHUNK_SIZE .. (ci + 1) * RF_CHUNK_SIZE - 1 in the global order (release, then
 * index), each drawing only from its own stream (rf_trajectory_seed), so the rows of a
 * chunk do not depend on which thread or rank made it. */
#ifndef ROCKFALL_MONTECARLO_PRIVATE_H
#define ROCKFALL_MONTECARLO_PRIVATE_H

#include <pthread.h>
#include <stddef.h>

#include "rockfall/montecarlo.h"
#include "rockfall/records.h"
#include "run/hazard.h"

struct rf_store;

#define RF_CHUNK_SIZE 256
#define RF_CHUNKS_AHEAD_PER_THREAD 4

typedef struct rf_traj_out {
    rf_trajectory_record rec;
    size_t release;
    long idx;
    size_t path_begin, path_end; /* the chunk's arrays, [begin, end) */
    size_t icpt_begin, icpt_end;
    size_t tree_begin, tree_end;
} rf_traj_out;

typedef struct rf_chunk {
    size_t first, n; /* global trajectory numbers first .. first+n-1 */
    rf_traj_out *traj;
    rf_path_point *paths;
    size_t npaths, cap_paths;
    rf_interception_record *icpts;
    size_t nicpts, cap_icpts;
    rf_tree_hit_record *trees;
    size_t ntrees, cap_trees;
    int done, oom;
} rf_chunk;

void rf_chunk_clear(rf_chunk *c);

/* A chunk as bytes, to be sent to another process of the same build and machine kind
 * (the records' own layout): its first and n, the counts, then the arrays.  Bytes
 * rf_chunk_pack writes (rf_chunk_packed_size of them). */
size_t rf_chunk_packed_size(const rf_chunk *c);
void rf_chunk_pack(const rf_chunk *c, unsigned char *buf);
/* Fills an empty chunk from packed bytes (done stays 0); -1 when the bytes are not a
 * chunk of n <= RF_CHUNK_SIZE (or memory ran out), the chunk then empty. */
int rf_chunk_unpack(rf_chunk *c, const unsigned char *buf, size_t len);

typedef struct rf_mc rf_mc;

/* Under rf_mc.mu: the next chunk for a worker thread.  1: chunk *ci in slot *slot; 0:
 * none yet (the thread waits on rf_mc.cv); -1: no more. */
typedef int (*rf_mc_claim_fn)(rf_mc *m, size_t *ci, rf_chunk **slot);

struct rf_mc {
    const rf_project *p;
    rf_scene scene;
    int nthreads;          /* workers, at least 1 */
    size_t total;          /* trajectories in all */
    size_t *release_start; /* global number of each release's first trajectory */
    size_t nchunks;
    rf_chunk *ring;        /* `ahead` slots: the chunks claimed and not yet written */
    size_t ahead;
    rf_hazard *hazard;     /* per worker thread */
    rf_mc_claim_fn claim;
    void *claim_ctx;       /* what claim needs besides (may be NULL) */

    pthread_mutex_t mu;
    pthread_cond_t cv;
    size_t next_chunk;     /* rf_mc_claim_in_order: the next chunk to claim */
    size_t written;        /* chunks written so far */
    int abort;

    pthread_t *tids;       /* the started workers */
    struct rf_mc_worker *workers;
    int started;
    rf_terrain_tables *tables;
};

/* Sets up a run of the project: its chunks, a ring of `ahead` slots, nthreads hazard
 * maps (claim: rf_mc_claim_in_order).  0, or -1 with err set (rf_mc_free frees what was
 * made). */
int rf_mc_init(rf_mc *m, const rf_project *p, int nthreads, size_t ahead, rf_error *err);
void rf_mc_free(rf_mc *m);
/* The claim of a one-process run: chunks in order, at most `ahead` beyond the last
 * written (chunk ci in slot ci mod ahead). */
int rf_mc_claim_in_order(rf_mc *m, size_t *ci, rf_chunk **slot);
/* Sets a slot's first and n for chunk ci. */
void rf_mc_chunk_range(const rf_mc *m, size_t ci, rf_chunk *c);
/* Starts the worker threads (each with a workspace on the shared terrain tables and a
 * generator); 0 or -1 with err set (those started keep running: rf_mc_stop). */
int rf_mc_start(rf_mc *m, rf_error *err);
/* Sets abort when `abort` is nonzero, wakes and joins the workers, frees their state. */
void rf_mc_stop(rf_mc *m, int abort);
/* Waits (under m->mu, which the caller holds) at most `seconds` for a change. */
void rf_mc_wait(rf_mc *m, double seconds);

/* Writes one chunk's rows in one batch, all or none (with `maps`, only the trajectories
 * that crossed a measure or have sampled path points, and no tree hits); sum's
 * by_reason and events count the trajectories committed. */
int rf_mc_write_chunk(struct rf_store *s, const rf_chunk *c, int maps, rf_run_summary *sum,
                      rf_error *err);
/* The writer's step for chunk ci, filled (c->done): writes it, clears its slot, lets the
 * workers run on (m->written), reports progress; the write's status. */
int rf_mc_write_next(rf_mc *m, struct rf_store *s, size_t ci, const rf_run_options *o,
                     rf_run_summary *sum, double t0, double *last_report, rf_error *err);
/* -1 with err set when the run was interrupted before chunk ci was written, else 0. */
int rf_mc_check_interrupted(const rf_mc *m, size_t ci, const rf_run_options *o, rf_error *err);
/* Progress on stderr (mode: rf_run_options.progress): done of total trajectories,
 * their rate since t0 and the time left at that rate, when a second (mode 1) or ten
 * (mode 2) have passed since *last; mode 1 clears its line once done == total. */
void rf_mc_progress(int mode, size_t done, size_t total, double t0, double *last);
/* Ends the run: merges the worker threads' hazard maps (and `extra`, may be NULL) when
 * status is 0, writes the hazard cells and marks the run complete; otherwise marks it
 * failed with the trajectories written.  Returns the final status. */
int rf_mc_finish(rf_mc *m, const rf_hazard *extra, struct rf_store *s, int status,
                 rf_run_summary *sum, rf_error *err);

#endif
