/* montecarlo.c - runs a project's trajectories on worker threads and writes them in
 * a deterministic order: work is cut into chunks of consecutive trajectories, workers
 * fill chunks, and the calling thread writes finished chunks in order.  The chunks in
 * flight live in a ring of `ahead` slots (chunk i in slot i mod ahead), so the memory
 * depends on the threads, not on the number of trajectories. */
#include "rockfall/montecarlo.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>

#include "base/tolerances.h"
#include "input/bounds.h"
#include "run/hazard.h"
#include "results/store.h"
#include "base/util.h"

#define CHUNK_SIZE 256
#define CHUNKS_AHEAD_PER_THREAD 4
#define JITTER_TRIES 64

/* ---- seeding ------------------------------------------------------------------ */

static uint64_t splitmix64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

unsigned long rf_trajectory_seed(uint64_t project_seed, size_t release, long idx)
{
    uint64_t h = splitmix64(project_seed);
    h = splitmix64(h ^ (uint64_t)release);
    h = splitmix64(h ^ (uint64_t)idx);
    unsigned long s = (unsigned long)h;
    return s ? s : 1ul; /* some generators treat seed 0 specially */
}

/* taus2: a maximally equidistributed combined Tausworthe generator with a tiny state,
 * so seeding one stream per trajectory costs almost nothing. */
const gsl_rng_type *rf_rng_type(void) { return gsl_rng_taus2; }

/* ---- start states ------------------------------------------------------------- */

rf_body rf_release_body(const rf_project *p, size_t release, rf_rock_model model)
{
    const rf_rock *rock = &p->rocks[p->releases[release].rock];
    return rf_body_make(rock->mass, rock->density, model);
}

double rf_release_mass(const rf_project *p, size_t release, gsl_rng *rng)
{
    const rf_rock *rock = &p->rocks[p->releases[release].rock];
    switch (rock->mass_kind) {
    case RF_MASS_LOGNORMAL: {
        /* the log-normal with the given mean and sd of the mass, truncated to the masses a
         * rock may have (its radius and mass bounds, input/bounds.h): drawn again when
         * outside, the bound itself after RF_DRAW_MAX_TRIES */
        double cv = rock->mass_sd / rock->mass;
        double sigma2 = log1p(cv * cv);
        double ball = 4.0 / 3.0 * RF_PI * rock->density;
        double lo = ball * pow(RF_ROCK_RADIUS_MIN, 3.0);
        double hi = fmin(RF_ROCK_MASS_MAX, ball * pow(RF_ROCK_RADIUS_MAX, 3.0));
        double m = rock->mass;
        for (int k = 0; k < RF_DRAW_MAX_TRIES; k++) {
            m = gsl_ran_lognormal(rng, log(rock->mass) - 0.5 * sigma2, sqrt(sigma2));
            if (m >= lo && m <= hi)
                return m;
        }
        return fmin(fmax(m, lo), hi);
    }
    case RF_MASS_LIST:
        return rock->masses[gsl_rng_uniform_int(rng, rock->nmasses)];
    case RF_MASS_FIXED:
    default:
        return rock->mass; /* no number drawn */
    }
}

rf_body rf_release_draw_body(const rf_project *p, size_t release, rf_rock_model model,
                             gsl_rng *rng, double *mass)
{
    const rf_rock *rock = &p->rocks[p->releases[release].rock];
    *mass = rf_release_mass(p, release, rng);
    return rf_body_make(*mass, rock->density, model);
}

/* A point uniform over the release's polygon: a triangle picked by its area, then a
 * point uniform in it (square-root rule). */
static void area_point(const rf_release *rel, gsl_rng *rng, double *x, double *y)
{
    double u = gsl_rng_uniform(rng) * rel->area_cum[rel->ntri - 1];
    size_t lo = 0, hi = rel->ntri - 1; /* first triangle whose cumulative area is > u */
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (rel->area_cum[mid] > u)
            hi = mid;
        else
            lo = mid + 1;
    }
    const size_t *k = rel->area_tri + 3 * lo;
    double r1 = sqrt(gsl_rng_uniform(rng)), r2 = gsl_rng_uniform(rng);
    double wa = 1.0 - r1, wb = r1 * (1.0 - r2), wc = r1 * r2;
    const double *a = rel->area + 2 * k[0], *b = rel->area + 2 * k[1], *c = rel->area + 2 * k[2];
    *x = wa * a[0] + wb * b[0] + wc * c[0];
    *y = wa * a[1] + wb * b[1] + wc * c[1];
}

/* The ground point a trajectory starts over: the release point moved by the random
 * horizontal jitter (uniform in a disc), or a point uniform over the area, or uniform
 * within the trajectory's source cell (trajectory idx of cell idx / count).  A draw off
 * the terrain (a hole) is drawn again, at most JITTER_TRIES times, then the point, the
 * area's first vertex or the cell's centre (on the terrain, as loading checked). */
static int32_t start_ground(const rf_project *p, const rf_release *rel, long idx, gsl_rng *rng,
                            double *x, double *y, double *z)
{
    const rf_terrain *t = &p->terrain;
    double x0 = rel->x, y0 = rel->y;
    if (rel->source == RF_SOURCE_AREA)
        x0 = rel->area[0], y0 = rel->area[1];
    else if (rel->source == RF_SOURCE_CELLS) {
        size_t c = (size_t)(idx / rel->count) % rel->ncells;
        x0 = rel->cells[2 * c], y0 = rel->cells[2 * c + 1];
    }
    if (rel->source != RF_SOURCE_POINT || rel->jitter > 0.0) {
        for (int k = 0; k < JITTER_TRIES; k++) {
            double xj, yj, zj;
            if (rel->source == RF_SOURCE_AREA)
                area_point(rel, rng, &xj, &yj);
            else if (rel->source == RF_SOURCE_CELLS) {
                xj = x0 + (gsl_rng_uniform(rng) - 0.5) * rel->cell;
                yj = y0 + (gsl_rng_uniform(rng) - 0.5) * rel->cell;
            } else {
                /* Uniform in the disc. */
                double rr = rel->jitter * sqrt(gsl_rng_uniform(rng));
                double phi = 2.0 * M_PI * gsl_rng_uniform(rng);
                xj = rel->x + rr * cos(phi), yj = rel->y + rr * sin(phi);
            }
            int32_t tj = rf_terrain_height(t, xj, yj, &zj);
            if (tj >= 0) {
                *x = xj, *y = yj, *z = zj;
                return tj;
            }
        }
    }
    *x = x0, *y = y0;
    if (rel->source == RF_SOURCE_POINT) {
        *z = rel->z;
        return rf_terrain_locate(t, x0, y0);
    }
    return rf_terrain_height(t, x0, y0, z);
}

rf_state rf_release_start_of(const rf_project *p, size_t release, long idx, const rf_body *b,
                             gsl_rng *rng)
{
    const rf_release *rel = &p->releases[release];
    const rf_terrain *t = &p->terrain;
    double x = 0.0, y = 0.0, z = 0.0; /* start_ground sets them; the loader put every
                                        source on the terrain */
    int32_t tri = start_ground(p, rel, idx, rng, &x, &y, &z);
    rf_vec3 n = tri >= 0 ? t->tri[tri].n : rf_v3(0, 0, 1);
    rf_state s;
    memset(&s, 0, sizeof s);
    /* `height` above the ground, a sphere touching the face there (its centre r off
     * it along the normal), a point mass on it (the point itself). */
    s.p = rf_v3_madd(rf_v3(x, y, z), rf_body_contact_radius(b), n);
    s.p.z += rel->height;
    s.v = rel->velocity;
    return s;
}

rf_state rf_release_start(const rf_project *p, size_t release, const rf_body *b, gsl_rng *rng)
{
    return rf_release_start_of(p, release, 0, b, rng);
}

/* ---- chunks ------------------------------------------------------------------- */

typedef struct traj_out {
    rf_trajectory_record rec;
    size_t release;
    long idx;
    size_t path_begin, path_end;
    size_t icpt_begin, icpt_end;
    size_t tree_begin, tree_end;
} traj_out;

#define DYNARRAY(T, name)                                                              \
    typedef struct {                                                                   \
        T *v;                                                                          \
        size_t n, cap;                                                                 \
    } name;
DYNARRAY(rf_path_point, path_array)
DYNARRAY(rf_interception_record, icpt_array)
DYNARRAY(rf_tree_hit_record, tree_array)

#define PUSH(arr, x, flag)                                                             \
    do {                                                                               \
        if (rf_grow((void **)&(arr).v, &(arr).cap, (arr).n + 1, sizeof *(arr).v))       \
            (flag) = 1;                                                                \
        else                                                                           \
            (arr).v[(arr).n++] = (x);                                                  \
    } while (0)

typedef struct chunk {
    size_t first, n; /* global trajectory numbers first .. first+n-1 */
    traj_out *traj;
    path_array paths;
    icpt_array icpts;
    tree_array trees;
    int done, oom;
} chunk;

static void chunk_clear(chunk *c)
{
    free(c->traj);
    free(c->paths.v);
    free(c->icpts.v);
    free(c->trees.v);
    memset(c, 0, sizeof *c);
}

/* ---- the run ------------------------------------------------------------------ */

typedef struct run_ctx {
    const rf_project *p;
    rf_scene scene;
    int nthreads;          /* workers, at least 1 */
    size_t total;          /* trajectories in all */
    size_t *release_start; /* global number of each release's first trajectory */
    size_t nchunks;
    chunk *ring;           /* `ahead` slots: the chunks claimed and not yet written */
    rf_hazard *hazard;     /* per worker */

    pthread_mutex_t mu;
    pthread_cond_t cv;
    size_t next_chunk;     /* next chunk to claim */
    size_t written;        /* chunks written so far */
    size_t ahead;          /* how far workers may run ahead of the writer: the ring's size */
    int abort;
} run_ctx;

typedef struct worker {
    run_ctx *ctx;
    int id;
    rf_workspace *ws;
    gsl_rng *rng;
    chunk *cur;
} worker;

static void sink_path(void *vw, const rf_path_point *pt)
{
    worker *w = vw;
    PUSH(w->cur->paths, *pt, w->cur->oom);
}

static void sink_icpt(void *vw, const rf_interception_record *r)
{
    worker *w = vw;
    PUSH(w->cur->icpts, *r, w->cur->oom);
}

static void sink_tree(void *vw, const rf_tree_hit_record *r)
{
    worker *w = vw;
    PUSH(w->cur->trees, *r, w->cur->oom);
}

static void sink_sample(void *vw, rf_vec3 p, double speed, double energy_kj, double height)
{
    (void)speed;
    worker *w = vw;
    rf_hazard_sample(w->ctx->hazard + w->id, p.x, p.y, energy_kj, height);
}

static size_t release_of(const run_ctx *c, size_t g)
{
    size_t lo = 0, hi = c->p->nreleases; /* last release whose start <= g */
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (c->release_start[mid] <= g)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static void run_chunk(worker *w, chunk *c)
{
    run_ctx *ctx = w->ctx;
    const rf_project *p = ctx->p;
    w->cur = c;
    c->traj = calloc(c->n, sizeof *c->traj);
    if (!c->traj) {
        c->oom = 1;
        return;
    }
    for (size_t k = 0; k < c->n; k++) {
        size_t g = c->first + k;
        size_t rel = release_of(ctx, g);
        long idx = (long)(g - ctx->release_start[rel]);
        traj_out *o = &c->traj[k];
        o->release = rel;
        o->idx = idx;
        gsl_rng_set(w->rng, rf_trajectory_seed(p->seed, rel, idx));
        double mass;
        rf_body body = rf_release_draw_body(p, rel, p->sim.model, w->rng, &mass);
        rf_state start = rf_release_start_of(p, rel, idx, &body, w->rng);
        rf_sink sink = {0};
        sink.ctx = w;
        sink.path_point = idx < p->sim.paths ? sink_path : NULL;
        sink.sample = sink_sample;
        sink.sample_spacing = 0.25 * p->hazard_cell;
        sink.interception = sink_icpt;
        sink.tree_hit = sink_tree;
        o->path_begin = c->paths.n;
        o->icpt_begin = c->icpts.n;
        o->tree_begin = c->trees.n;
        rf_hazard_begin(ctx->hazard + w->id);
        rf_simulate(&ctx->scene, &body, &start, w->rng, w->ws, &sink, &o->rec);
        o->rec.mass_kg = mass;
        o->rec.start = start.p;
        if (rf_hazard_end(ctx->hazard + w->id))
            c->oom = 1;
        o->path_end = c->paths.n;
        o->icpt_end = c->icpts.n;
        o->tree_end = c->trees.n;
    }
}

static void *worker_main(void *vw)
{
    worker *w = vw;
    run_ctx *ctx = w->ctx;
    for (;;) {
        pthread_mutex_lock(&ctx->mu);
        while (!ctx->abort && ctx->next_chunk < ctx->nchunks &&
               ctx->next_chunk >= ctx->written + ctx->ahead)
            pthread_cond_wait(&ctx->cv, &ctx->mu);
        if (ctx->abort || ctx->next_chunk >= ctx->nchunks) {
            pthread_mutex_unlock(&ctx->mu);
            return NULL;
        }
        /* the slot's last chunk was written and cleared: no other thread holds it */
        size_t ci = ctx->next_chunk++;
        chunk *c = &ctx->ring[ci % ctx->ahead];
        c->first = ci * CHUNK_SIZE;
        c->n = ci + 1 < ctx->nchunks ? CHUNK_SIZE : ctx->total - ci * CHUNK_SIZE;
        pthread_mutex_unlock(&ctx->mu);
        run_chunk(w, c);
        pthread_mutex_lock(&ctx->mu);
        c->done = 1;
        pthread_cond_broadcast(&ctx->cv);
        pthread_mutex_unlock(&ctx->mu);
    }
}

/* Writes one chunk's rows in one batch, all or none (a failed chunk is rolled back,
 * so a failed run holds whole trajectories); by_reason counts the trajectories
 * committed. */
static int write_chunk(rf_store *s, const chunk *c, long by_reason[4], rf_error *err)
{
    if (c->oom)
        return rf_error_set(err, "", 0, 0, "out of memory while simulating");
    if (rf_store_batch_begin(s, err))
        return -1;
    long counted[4] = {0};
    for (size_t k = 0; k < c->n; k++) {
        const traj_out *o = &c->traj[k];
        int64_t tid;
        /* a row that fails rolls the batch back */
        if (rf_store_add_trajectory(s, o->release, o->idx, &o->rec, &tid, err))
            return -1;
        counted[o->rec.reason]++;
        for (size_t i = o->path_begin; i < o->path_end; i++)
            if (rf_store_add_path_point(s, tid, (long)(i - o->path_begin), &c->paths.v[i], err))
                return -1;
        for (size_t i = o->icpt_begin; i < o->icpt_end; i++)
            if (rf_store_add_interception(s, tid, &c->icpts.v[i], NULL, err))
                return -1;
        for (size_t i = o->tree_begin; i < o->tree_end; i++)
            if (rf_store_add_tree_hit(s, tid, &c->trees.v[i], err))
                return -1;
    }
    if (rf_store_batch_commit(s, err))
        return -1;
    for (int r = 0; r < 4; r++)
        by_reason[r] += counted[r];
    return 0;
}

/* Simulates every chunk and writes them in order; returns 0 or -1 with err set. */
static int simulate_and_write(run_ctx *ctx, rf_store *s, const rf_run_options *o,
                              rf_run_summary *sum, rf_error *err)
{
    int nthreads = ctx->nthreads;
    worker *workers = calloc((size_t)nthreads, sizeof *workers);
    pthread_t *tids = calloc((size_t)nthreads, sizeof *tids);
    int status = 0, started = 0;
    /* the terrain's tables, read by every worker's workspace */
    rf_terrain_tables *tables = rf_terrain_tables_build(&ctx->p->terrain);
    if (!workers || !tids || !tables) {
        status = rf_error_set(err, "", 0, 0, "out of memory");
        goto done;
    }
    for (int i = 0; i < nthreads; i++) {
        workers[i].ctx = ctx;
        workers[i].id = i;
        workers[i].ws = rf_workspace_alloc_shared(tables);
        workers[i].rng = gsl_rng_alloc(rf_rng_type());
        if (!workers[i].ws || !workers[i].rng) {
            status = rf_error_set(err, "", 0, 0, "out of memory");
            goto done;
        }
    }
    for (int i = 0; i < nthreads; i++) {
        if (pthread_create(&tids[i], NULL, worker_main, &workers[i])) {
            status = rf_error_set(err, "", 0, 0, "cannot start worker thread %d", i);
            break;
        }
        started++;
    }
    double t0 = rf_now_s(), last_report = t0;
    for (size_t ci = 0; status == 0 && ci < ctx->nchunks; ci++) {
        if (o->interrupted && *o->interrupted) {
            status = rf_error_set(err, "", 0, 0, "interrupted after %zu of %zu trajectories",
                                  ci * CHUNK_SIZE < ctx->total ? ci * CHUNK_SIZE : ctx->total,
                                  ctx->total);
            break;
        }
        chunk *c = &ctx->ring[ci % ctx->ahead];
        pthread_mutex_lock(&ctx->mu);
        while (!c->done && started > 0)
            pthread_cond_wait(&ctx->cv, &ctx->mu);
        pthread_mutex_unlock(&ctx->mu);
        if (!c->done) {
            status = rf_error_set(err, "", 0, 0, "no worker thread could be started");
            break;
        }
        status = write_chunk(s, c, sum->by_reason, err);
        chunk_clear(c);
        pthread_mutex_lock(&ctx->mu);
        ctx->written = ci + 1;
        pthread_cond_broadcast(&ctx->cv);
        pthread_mutex_unlock(&ctx->mu);
        double t = rf_now_s();
        if (o->progress && t - last_report > 1.0) {
            size_t n = (ci + 1) * CHUNK_SIZE < ctx->total ? (ci + 1) * CHUNK_SIZE : ctx->total;
            fprintf(stderr, "\r%zu / %zu trajectories", n, ctx->total);
            last_report = t;
        }
    }
    if (o->progress)
        fprintf(stderr, "\r%*s\r", 40, "");
    pthread_mutex_lock(&ctx->mu);
    if (status)
        ctx->abort = 1;
    pthread_cond_broadcast(&ctx->cv);
    pthread_mutex_unlock(&ctx->mu);
    for (int i = 0; i < started; i++)
        pthread_join(tids[i], NULL);
    sum->seconds = rf_now_s() - t0;
done:
    if (workers)
        for (int i = 0; i < nthreads; i++) {
            rf_workspace_free(workers[i].ws);
            if (workers[i].rng)
                gsl_rng_free(workers[i].rng);
        }
    rf_terrain_tables_free(tables);
    free(workers);
    free(tids);
    return status;
}

int rf_montecarlo_run(const rf_project *p, rf_store *s, const rf_run_options *o,
                      rf_run_summary *sum, rf_error *err)
{
    memset(sum, 0, sizeof *sum);
    int nthreads = o->threads > 1 ? o->threads : 1;
    run_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.nthreads = nthreads;
    ctx.p = p;
    ctx.scene.terrain = &p->terrain;
    ctx.scene.sim = &p->sim;
    ctx.scene.forests = p->forests;
    ctx.scene.nforests = p->nforests;
    ctx.scene.measures = p->measures;
    ctx.scene.nmeasures = p->nmeasures;
    ctx.ahead = (size_t)nthreads * CHUNKS_AHEAD_PER_THREAD;
    ctx.release_start = calloc(p->nreleases + 1, sizeof *ctx.release_start);
    for (size_t i = 0; ctx.release_start && i < p->nreleases; i++)
        ctx.release_start[i + 1] = ctx.release_start[i] + (size_t)rf_release_trajectories(&p->releases[i]);
    ctx.total = ctx.release_start ? ctx.release_start[p->nreleases] : 0;
    ctx.nchunks = (ctx.total + CHUNK_SIZE - 1) / CHUNK_SIZE;
    ctx.ring = calloc(ctx.ahead, sizeof *ctx.ring);
    ctx.hazard = calloc((size_t)nthreads, sizeof *ctx.hazard);
    int status = 0;
    if (!ctx.release_start || !ctx.ring || !ctx.hazard) {
        status = rf_error_set(err, "", 0, 0, "out of memory");
        goto cleanup;
    }
    for (int i = 0; i < nthreads; i++)
        if (rf_hazard_init(&ctx.hazard[i], &p->terrain, p->hazard_cell)) {
            status = rf_error_set(err, "", 0, 0, "out of memory for the hazard grid");
            goto cleanup;
        }
    pthread_mutex_init(&ctx.mu, NULL);
    pthread_cond_init(&ctx.cv, NULL);

    if (rf_store_run_begin(s, p, (long)ctx.total, &sum->run_id, err)) {
        status = -1;
        goto cleanup_sync;
    }
    status = simulate_and_write(&ctx, s, o, sum, err);
    /* any order of merging gives the same cells (hazard.h); each worker's map is freed
     * once merged */
    for (int i = 1; status == 0 && i < nthreads; i++) {
        if (rf_hazard_merge(&ctx.hazard[0], &ctx.hazard[i]))
            status = rf_error_set(err, "", 0, 0, "out of memory merging the hazard grid");
        rf_hazard_free(&ctx.hazard[i]);
    }
    if (status == 0)
        status = rf_hazard_write(&ctx.hazard[0], (long)ctx.total, s, err);
    sum->n_trajectories = (long)ctx.total;
    if (status == 0)
        status = rf_store_run_finish(s, "complete", (long)ctx.total, err);
    else
        rf_store_run_finish(s, "failed",
                            sum->by_reason[0] + sum->by_reason[1] + sum->by_reason[2] +
                                sum->by_reason[3],
                            NULL); /* the trajectories written */

cleanup_sync:
    pthread_mutex_destroy(&ctx.mu);
    pthread_cond_destroy(&ctx.cv);
cleanup:
    if (ctx.hazard)
        for (int i = 0; i < nthreads; i++)
            rf_hazard_free(&ctx.hazard[i]);
    for (size_t ci = 0; ctx.ring && ci < ctx.ahead; ci++)
        chunk_clear(&ctx.ring[ci]);
    free(ctx.ring);
    free(ctx.hazard);
    free(ctx.release_start);
    return status;
}
