/* mpi.c - a run shared among MPI ranks (mpi.h).  Built only by `make mpi`.
 *
 * The messages, all on MPI_COMM_WORLD, all between rank 0 and one other rank (MPI
 * keeps the order of the messages from one rank to another, so a rank's chunks arrive
 * before its hazard map and its hazard map before its DONE):
 *   TAG_ASK    rank r -> 0: nothing; asks for a chunk
 *   TAG_GIVE   0 -> r: one int64: the chunk's number, GIVE_NONE (there are no more)
 *              or GIVE_LATER (rank 0 holds `ahead` chunks unwritten: ask again later)
 *   TAG_CHUNK  r -> 0: a filled chunk (rf_chunk_pack): on x86-64 48 bytes, and 176 a
 *              trajectory, 48 a sampled path point, 88 an interception, 56 a tree hit
 *   TAG_HAZARD r -> 0: hazard cells (rf_hazard_pack), at most RF_MPI_BATCH bytes
 *   TAG_DONE   r -> 0: nothing; the rank has sent everything
 *   TAG_FAIL   r -> 0: an rf_error; the rank failed */
#include "run/mpi.h"

#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"
#include "results/store.h"
#include "run/hazard.h"
#include "run/montecarlo_private.h"

enum { TAG_ASK = 1, TAG_GIVE, TAG_CHUNK, TAG_HAZARD, TAG_DONE, TAG_FAIL };
enum { GIVE_NONE = -1, GIVE_LATER = -2 };

/* How long rank 0's writer and a rank's sender wait for a change between looks at the
 * messages (s), and how long a rank told GIVE_LATER waits before it asks again. */
#define POLL_S 200e-6
#define LATER_S 2e-3

int rf_mpi_init(int *argc, char ***argv)
{
    int provided = 0;
    return MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) == MPI_SUCCESS &&
                   provided >= MPI_THREAD_FUNNELED
               ? 0
               : -1;
}

int rf_mpi_rank(void)
{
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}

int rf_mpi_size(void)
{
    int n = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    return n;
}

/* Whether this rank told rank 0 of its failure (rf_mpi_report_failure). */
static int reported;

void rf_mpi_report_failure(const rf_error *err)
{
    MPI_Send(err, (int)sizeof *err, MPI_BYTE, 0, TAG_FAIL, MPI_COMM_WORLD);
    reported = 1;
}

void rf_mpi_end(int status)
{
    fflush(stdout);
    fflush(stderr);
    if (status != 0 && rf_mpi_size() > 1) {
        if (rf_mpi_rank() == 0)
            MPI_Abort(MPI_COMM_WORLD, status); /* after the run was marked failed */
        if (!reported) {                       /* a usage error on this rank alone */
            rf_error e;
            rf_error_set(&e, "", 0, 0, "failed (exit status %d; its own messages above)",
                         status);
            rf_mpi_report_failure(&e);
        }
        /* rank 0 marks the run failed and ends the job; this waits for it */
    }
    MPI_Finalize();
}

/* ---- rank 0 ---------------------------------------------------------------------- */

typedef struct root {
    rf_mc *m;
    rf_hazard remote;   /* the other ranks' hazard cells, merged */
    int ndone;          /* ranks that sent everything */
    unsigned char *buf; /* the last message received */
    size_t cap;
} root;

/* Receives the message `st` announced into r->buf; its length in *len. */
static int receive(root *r, const MPI_Status *st, size_t *len, rf_error *err)
{
    int n = 0;
    MPI_Get_count(st, MPI_BYTE, &n);
    if (rf_grow((void **)&r->buf, &r->cap, (size_t)n + 1, 1))
        return rf_error_set(err, "", 0, 0, "out of memory receiving from rank %d",
                            st->MPI_SOURCE);
    MPI_Recv(r->buf, n, MPI_BYTE, st->MPI_SOURCE, st->MPI_TAG, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    *len = (size_t)n;
    return 0;
}

/* A filled chunk from another rank, into its slot of the ring. */
static int take_chunk(root *r, const MPI_Status *st, rf_error *err)
{
    size_t len;
    if (receive(r, st, &len, err))
        return -1;
    rf_mc *m = r->m;
    rf_chunk c;
    if (rf_chunk_unpack(&c, r->buf, len))
        return rf_error_set(err, "", 0, 0, "rank %d sent a malformed chunk (or memory ran out)",
                            st->MPI_SOURCE);
    size_t ci = c.first / RF_CHUNK_SIZE;
    pthread_mutex_lock(&m->mu);
    rf_chunk *slot = &m->ring[ci % m->ahead];
    int ok = c.first % RF_CHUNK_SIZE == 0 && ci >= m->written && ci < m->next_chunk &&
             !slot->done && !slot->traj;
    if (ok) {
        rf_mc_chunk_range(m, ci, slot);
        ok = c.oom || c.n == slot->n;
    }
    if (ok) {
        *slot = c;
        slot->done = 1;
        pthread_cond_broadcast(&m->cv);
    }
    pthread_mutex_unlock(&m->mu);
    if (!ok) {
        rf_chunk_clear(&c);
        return rf_error_set(err, "", 0, 0, "rank %d sent a chunk that was not handed out",
                            st->MPI_SOURCE);
    }
    return 0;
}

/* Handles one message announced by st; 0 or -1 with err set. */
static int handle(root *r, const MPI_Status *st, rf_error *err)
{
    size_t len;
    switch (st->MPI_TAG) {
    case TAG_ASK: {
        MPI_Recv(NULL, 0, MPI_BYTE, st->MPI_SOURCE, TAG_ASK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        size_t ci = 0;
        rf_chunk *slot;
        pthread_mutex_lock(&r->m->mu);
        int got = r->m->abort ? -1 : rf_mc_claim_in_order(r->m, &ci, &slot);
        pthread_mutex_unlock(&r->m->mu);
        int64_t give = got > 0 ? (int64_t)ci : got < 0 ? GIVE_NONE : GIVE_LATER;
        MPI_Send(&give, 1, MPI_INT64_T, st->MPI_SOURCE, TAG_GIVE, MPI_COMM_WORLD);
        return 0;
    }
    case TAG_CHUNK:
        return take_chunk(r, st, err);
    case TAG_HAZARD:
        if (receive(r, st, &len, err))
            return -1;
        if (rf_hazard_unpack_merge(&r->remote, r->buf, len))
            return rf_error_set(err, "", 0, 0,
                                "rank %d sent malformed hazard cells (or memory ran out)",
                                st->MPI_SOURCE);
        return 0;
    case TAG_DONE:
        MPI_Recv(NULL, 0, MPI_BYTE, st->MPI_SOURCE, TAG_DONE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        r->ndone++;
        return 0;
    case TAG_FAIL: {
        rf_error e;
        if (receive(r, st, &len, err))
            return -1;
        memset(&e, 0, sizeof e);
        memcpy(&e, r->buf, len < sizeof e ? len : sizeof e);
        e.file[sizeof e.file - 1] = e.message[sizeof e.message - 1] = '\0';
        *err = e;
        char msg[sizeof e.message];
        snprintf(msg, sizeof msg, "rank %d: %.1000s", st->MPI_SOURCE, e.message);
        memcpy(err->message, msg, sizeof msg);
        return -1;
    }
    default:
        return rf_error_set(err, "", 0, 0, "unexpected message %d from rank %d", st->MPI_TAG,
                            st->MPI_SOURCE);
    }
}

/* Handles the messages waiting, if any; 0 or -1 with err set. */
static int poll_messages(root *r, rf_error *err)
{
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag)
            return 0;
        if (handle(r, &st, err))
            return -1;
    }
}

/* Writes every chunk in order, serving the other ranks meanwhile; then waits for
 * their hazard cells. */
static int write_in_order(root *r, rf_store *s, const rf_run_options *o, rf_run_summary *sum,
                          rf_error *err)
{
    rf_mc *m = r->m;
    int status = 0;
    double t0 = rf_now_s(), last_report = t0;
    for (size_t ci = 0; status == 0 && ci < m->nchunks; ci++) {
        rf_chunk *c = &m->ring[ci % m->ahead];
        for (;;) {
            if ((status = rf_mc_check_interrupted(m, ci, o, err)) != 0)
                break;
            if ((status = poll_messages(r, err)) != 0)
                break;
            pthread_mutex_lock(&m->mu);
            if (!c->done)
                rf_mc_wait(m, POLL_S);
            int done = c->done;
            pthread_mutex_unlock(&m->mu);
            if (done)
                break;
        }
        if (status)
            break;
        status = rf_mc_write_next(m, s, ci, o, sum, t0, &last_report, err);
    }
    if (status && o->progress == 1)
        fprintf(stderr, "\r%*s\r", 72, "");
    /* every rank's hazard cells */
    while (status == 0 && r->ndone < rf_mpi_size() - 1) {
        MPI_Status st;
        MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
        status = handle(r, &st, err);
    }
    sum->seconds = rf_now_s() - t0;
    return status;
}

int rf_mpi_run(const rf_project *p, rf_store *s, const rf_run_options *o,
               rf_run_summary *sum, rf_error *err)
{
    memset(sum, 0, sizeof *sum);
    int threads = o->threads > 1 ? o->threads : 1;
    size_t ahead = (size_t)RF_CHUNKS_AHEAD_PER_THREAD * (size_t)threads * (size_t)rf_mpi_size();
    rf_mc m;
    root r;
    memset(&r, 0, sizeof r);
    r.m = &m;
    int status = rf_mc_init(&m, p, threads, ahead, err);
    if (status == 0 && rf_hazard_init(&r.remote, &p->terrain, p->hazard_cell))
        status = rf_error_set(err, "", 0, 0, "out of memory for the hazard grid");
    rf_store_describe_run(s, o->maps, rf_mpi_size(), threads);
    if (status == 0 && rf_store_run_begin(s, p, (long)m.total, &sum->run_id, err))
        status = -1;
    else if (status == 0) {
        int st = rf_mc_start(&m, err);
        if (st == 0)
            st = write_in_order(&r, s, o, sum, err);
        rf_mc_stop(&m, st != 0);
        status = rf_mc_finish(&m, &r.remote, s, st, sum, err);
    }
    rf_hazard_free(&r.remote);
    free(r.buf);
    rf_mc_free(&m);
    return status;
}

/* ---- the other ranks --------------------------------------------------------------- */

/* The chunks a rank holds: each slot free (ci SIZE_MAX), handed to it and waiting for a
 * thread, being filled, or filled (done). */
typedef struct rank_queue {
    size_t *ci;      /* per slot: its chunk, SIZE_MAX when free */
    int *taken;      /* per slot: a thread is filling it or has filled it */
    int closed;      /* no more chunks will come */
} rank_queue;

/* The claim of a rank's threads: the first slot handed a chunk and not yet taken. */
static int claim_given(rf_mc *m, size_t *ci, rf_chunk **slot)
{
    rank_queue *q = m->claim_ctx;
    for (size_t k = 0; k < m->ahead; k++)
        if (q->ci[k] != SIZE_MAX && !q->taken[k]) {
            q->taken[k] = 1;
            *ci = q->ci[k];
            *slot = &m->ring[k];
            return 1;
        }
    return q->closed ? -1 : 0;
}

/* Sends the filled chunks; the number sent, or -1 (out of memory, err set). */
static int send_filled(rf_mc *m, rank_queue *q, rf_error *err)
{
    int sent = 0;
    for (size_t k = 0; k < m->ahead; k++) {
        pthread_mutex_lock(&m->mu);
        int done = m->ring[k].done;
        pthread_mutex_unlock(&m->mu);
        if (!done)
            continue;
        rf_chunk *c = &m->ring[k];
        size_t n = rf_chunk_packed_size(c);
        unsigned char *buf = n <= (size_t)INT32_MAX ? malloc(n) : NULL;
        if (!buf)
            return rf_error_set(err, "", 0, 0, "out of memory sending a chunk");
        rf_chunk_pack(c, buf);
        MPI_Send(buf, (int)n, MPI_BYTE, 0, TAG_CHUNK, MPI_COMM_WORLD);
        free(buf);
        pthread_mutex_lock(&m->mu);
        rf_chunk_clear(c);
        q->ci[k] = SIZE_MAX;
        q->taken[k] = 0;
        pthread_mutex_unlock(&m->mu);
        sent++;
    }
    return sent;
}

/* Asks rank 0 for chunks while a slot is free; returns GIVE_NONE once there are no
 * more, GIVE_LATER when rank 0 said so, else 0. */
static int ask_for_chunks(rf_mc *m, rank_queue *q)
{
    for (size_t k = 0; k < m->ahead; k++) {
        if (q->ci[k] != SIZE_MAX)
            continue;
        int64_t give = 0;
        MPI_Send(NULL, 0, MPI_BYTE, 0, TAG_ASK, MPI_COMM_WORLD);
        MPI_Recv(&give, 1, MPI_INT64_T, 0, TAG_GIVE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (give < 0)
            return (int)give;
        pthread_mutex_lock(&m->mu);
        q->ci[k] = (size_t)give;
        pthread_cond_broadcast(&m->cv);
        pthread_mutex_unlock(&m->mu);
    }
    return 0;
}

/* Merges the threads' hazard maps and sends them in batches, then DONE. */
static int send_hazard(rf_mc *m, rf_error *err)
{
    for (int i = 1; i < m->nthreads; i++) {
        if (rf_hazard_merge(&m->hazard[0], &m->hazard[i]))
            return rf_error_set(err, "", 0, 0, "out of memory merging the hazard grid");
        rf_hazard_free(&m->hazard[i]);
    }
    unsigned char *buf = malloc(RF_MPI_BATCH);
    if (!buf)
        return rf_error_set(err, "", 0, 0, "out of memory sending the hazard grid");
    size_t next = 0;
    while (next < m->hazard[0].ncells) {
        size_t n = rf_hazard_pack(&m->hazard[0], &next, buf, RF_MPI_BATCH);
        MPI_Send(buf, (int)n, MPI_BYTE, 0, TAG_HAZARD, MPI_COMM_WORLD);
    }
    free(buf);
    MPI_Send(NULL, 0, MPI_BYTE, 0, TAG_DONE, MPI_COMM_WORLD);
    return 0;
}

int rf_mpi_serve(const rf_project *p, const rf_run_options *o, rf_error *err)
{
    int threads = o->threads > 1 ? o->threads : 1;
    size_t slots = 2 * (size_t)threads;
    rf_mc m;
    rank_queue q;
    memset(&q, 0, sizeof q);
    int status = rf_mc_init(&m, p, threads, slots, err);
    q.ci = malloc(slots * sizeof *q.ci);
    q.taken = calloc(slots, sizeof *q.taken);
    if (status == 0 && (!q.ci || !q.taken))
        status = rf_error_set(err, "", 0, 0, "out of memory");
    for (size_t k = 0; q.ci && k < slots; k++)
        q.ci[k] = SIZE_MAX;
    m.claim = claim_given;
    m.claim_ctx = &q;
    if (status == 0)
        status = rf_mc_start(&m, err);
    int more = 1;
    while (status == 0) {
        int sent = send_filled(&m, &q, err);
        if (sent < 0) {
            status = -1;
            break;
        }
        int held = 0;
        for (size_t k = 0; k < slots; k++)
            held += q.ci[k] != SIZE_MAX;
        if (!more && held == 0)
            break;
        int later = 0;
        if (more) {
            int got = ask_for_chunks(&m, &q);
            more = got != GIVE_NONE;
            later = got == GIVE_LATER;
        }
        pthread_mutex_lock(&m.mu);
        if (!more)
            q.closed = 1;
        pthread_cond_broadcast(&m.cv);
        int filled = 0;
        for (size_t k = 0; k < slots; k++)
            filled |= m.ring[k].done;
        if (!filled && sent == 0)
            rf_mc_wait(&m, later ? LATER_S : POLL_S);
        pthread_mutex_unlock(&m.mu);
    }
    rf_mc_stop(&m, status != 0);
    if (status == 0)
        status = send_hazard(&m, err);
    if (status)
        rf_mpi_report_failure(err);
    free(q.ci);
    free(q.taken);
    rf_mc_free(&m);
    return status;
}
