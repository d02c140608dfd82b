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
#include "run/montecarlo_private.h"
#include "results/store.h"
#include "base/util.h"

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
        size_t c = (size_t)rf_release_source_cell(rel, idx);
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
    rf_vec3 n = tri >= 0 ? RF_TRI(t, tri)->n : rf_v3(0, 0, 1);
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

/* ---- the workers -------------------------------------------------------------- */

typedef struct rf_mc_worker {
    rf_mc *m;
    int id;
    rf_workspace *ws;
    gsl_rng *rng;
    rf_chunk *cur;
} rf_mc_worker;

#define PUSH(v, n, cap, x, flag)                                                       \
    do {                                                                               \
        if (rf_grow((void **)&(v), &(cap), (n) + 1, sizeof *(v)))                      \
            (flag) = 1;                                                                \
        else                                                                           \
            (v)[(n)++] = (x);                                                          \
    } while (0)

static void sink_path(void *vw, const rf_path_point *pt)
{
    rf_chunk *c = ((rf_mc_worker *)vw)->cur;
    PUSH(c->paths, c->npaths, c->cap_paths, *pt, c->oom);
}

static void sink_icpt(void *vw, const rf_interception_record *r)
{
    rf_chunk *c = ((rf_mc_worker *)vw)->cur;
    PUSH(c->icpts, c->nicpts, c->cap_icpts, *r, c->oom);
}

static void sink_tree(void *vw, const rf_tree_hit_record *r)
{
    rf_chunk *c = ((rf_mc_worker *)vw)->cur;
    PUSH(c->trees, c->ntrees, c->cap_trees, *r, c->oom);
}

static void sink_sample(void *vw, rf_vec3 p, double speed, double energy_kj, double height)
{
    (void)speed;
    rf_mc_worker *w = vw;
    rf_hazard_sample(w->m->hazard + w->id, p.x, p.y, energy_kj, height);
}

static size_t release_of(const rf_mc *m, size_t g)
{
    size_t lo = 0, hi = m->p->nreleases; /* last release whose start <= g */
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (m->release_start[mid] <= g)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static void run_chunk(rf_mc_worker *w, rf_chunk *c)
{
    rf_mc *m = w->m;
    const rf_project *p = m->p;
    w->cur = c;
    c->traj = calloc(c->n, sizeof *c->traj);
    if (!c->traj) {
        c->oom = 1;
        return;
    }
    for (size_t k = 0; k < c->n; k++) {
        pthread_mutex_lock(&m->mu);
        int stop = m->abort;
        pthread_mutex_unlock(&m->mu);
        if (stop) { /* the run ends: the chunk is never written */
            c->n = k;
            break;
        }
        size_t g = c->first + k;
        size_t rel = release_of(m, g);
        long idx = (long)(g - m->release_start[rel]);
        rf_traj_out *o = &c->traj[k];
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
        o->path_begin = c->npaths;
        o->icpt_begin = c->nicpts;
        o->tree_begin = c->ntrees;
        rf_hazard_begin(m->hazard + w->id);
        rf_simulate(&m->scene, &body, &start, w->rng, w->ws, &sink, &o->rec);
        o->rec.mass_kg = mass;
        o->rec.start = start.p;
        if (rf_hazard_end(m->hazard + w->id))
            c->oom = 1;
        o->path_end = c->npaths;
        o->icpt_end = c->nicpts;
        o->tree_end = c->ntrees;
    }
}

void rf_mc_chunk_range(const rf_mc *m, size_t ci, rf_chunk *c)
{
    c->first = ci * RF_CHUNK_SIZE;
    c->n = ci + 1 < m->nchunks ? RF_CHUNK_SIZE : m->total - ci * RF_CHUNK_SIZE;
}

int rf_mc_claim_in_order(rf_mc *m, size_t *ci, rf_chunk **slot)
{
    if (m->next_chunk >= m->nchunks)
        return -1;
    if (m->next_chunk >= m->written + m->ahead)
        return 0;
    /* the slot's last chunk was written and cleared: no other thread holds it */
    *ci = m->next_chunk++;
    *slot = &m->ring[*ci % m->ahead];
    return 1;
}

static void *worker_main(void *vw)
{
    rf_mc_worker *w = vw;
    rf_mc *m = w->m;
    for (;;) {
        size_t ci = 0;
        rf_chunk *c = NULL;
        int got = 0;
        pthread_mutex_lock(&m->mu);
        while (!m->abort && (got = m->claim(m, &ci, &c)) == 0)
            pthread_cond_wait(&m->cv, &m->mu);
        pthread_mutex_unlock(&m->mu);
        if (m->abort || got < 0)
            return NULL;
        rf_mc_chunk_range(m, ci, c);
        run_chunk(w, c);
        pthread_mutex_lock(&m->mu);
        c->done = 1;
        pthread_cond_broadcast(&m->cv);
        pthread_mutex_unlock(&m->mu);
    }
}

void rf_mc_wait(rf_mc *m, double seconds)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    double ns = (double)until.tv_nsec + seconds * 1e9;
    until.tv_sec += (time_t)(ns / 1e9);
    until.tv_nsec = (long)fmod(ns, 1e9);
    pthread_cond_timedwait(&m->cv, &m->mu, &until);
}

int rf_mc_start(rf_mc *m, rf_error *err)
{
    int n = m->nthreads;
    m->workers = calloc((size_t)n, sizeof *m->workers);
    m->tids = calloc((size_t)n, sizeof *m->tids);
    /* the terrain's tables, read by every worker's workspace */
    m->tables = rf_terrain_tables_build(&m->p->terrain);
    if (!m->workers || !m->tids || !m->tables)
        return rf_error_set(err, "", 0, 0, "out of memory");
    for (int i = 0; i < n; i++) {
        m->workers[i].m = m;
        m->workers[i].id = i;
        m->workers[i].ws = rf_workspace_alloc_shared(m->tables);
        m->workers[i].rng = gsl_rng_alloc(rf_rng_type());
        if (!m->workers[i].ws || !m->workers[i].rng)
            return rf_error_set(err, "", 0, 0, "out of memory");
    }
    for (int i = 0; i < n; i++) {
        if (pthread_create(&m->tids[i], NULL, worker_main, &m->workers[i]))
            return rf_error_set(err, "", 0, 0, "cannot start worker thread %d", i);
        m->started++;
    }
    return 0;
}

void rf_mc_stop(rf_mc *m, int abort)
{
    pthread_mutex_lock(&m->mu);
    if (abort)
        m->abort = 1;
    pthread_cond_broadcast(&m->cv);
    pthread_mutex_unlock(&m->mu);
    for (int i = 0; i < m->started; i++)
        pthread_join(m->tids[i], NULL);
    m->started = 0;
    if (m->workers)
        for (int i = 0; i < m->nthreads; i++) {
            rf_workspace_free(m->workers[i].ws);
            if (m->workers[i].rng)
                gsl_rng_free(m->workers[i].rng);
        }
    rf_terrain_tables_free(m->tables);
    free(m->workers);
    free(m->tids);
    m->tables = NULL;
    m->workers = NULL;
    m->tids = NULL;
}

/* ---- writing ------------------------------------------------------------------- */

int rf_mc_write_chunk(rf_store *s, const rf_chunk *c, int maps, rf_run_summary *sum,
                      rf_error *err)
{
    if (c->oom)
        return rf_error_set(err, "", 0, 0, "out of memory while simulating");
    if (rf_store_batch_begin(s, err))
        return -1;
    long counted[4] = {0};
    double events[4] = {0};
    for (size_t k = 0; k < c->n; k++) {
        const rf_traj_out *o = &c->traj[k];
        int64_t tid;
        counted[o->rec.reason]++;
        events[0] += (double)o->rec.n_flights;
        events[1] += (double)o->rec.n_segments;
        events[2] += (double)o->rec.n_impacts;
        events[3] += (double)o->rec.n_edge_transitions;
        if (maps && o->path_end == o->path_begin && o->icpt_end == o->icpt_begin)
            continue;
        /* a row that fails rolls the batch back */
        if (rf_store_add_trajectory(s, o->release, o->idx, &o->rec, &tid, err))
            return -1;
        for (size_t i = o->path_begin; i < o->path_end; i++)
            if (rf_store_add_path_point(s, tid, (long)(i - o->path_begin), &c->paths[i], err))
                return -1;
        for (size_t i = o->icpt_begin; i < o->icpt_end; i++)
            if (rf_store_add_interception(s, tid, &c->icpts[i], NULL, err))
                return -1;
        for (size_t i = o->tree_begin; !maps && i < o->tree_end; i++)
            if (rf_store_add_tree_hit(s, tid, &c->trees[i], err))
                return -1;
    }
    if (rf_store_batch_commit(s, err))
        return -1;
    for (int r = 0; r < 4; r++) {
        sum->by_reason[r] += counted[r];
        sum->events[r] += events[r];
    }
    return 0;
}

void rf_mc_progress(int mode, size_t done, size_t total, double t0, double *last)
{
    double t = rf_now_s();
    if (mode == 0 || (done < total && t - *last < (mode == 1 ? 1.0 : 10.0)))
        return;
    *last = t;
    double rate = t > t0 ? (double)done / (t - t0) : 0.0;
    double left = rate > 0 ? (double)(total - done) / rate : 0.0;
    if (mode == 1 && done == total) { /* the line cleared */
        fprintf(stderr, "\r%*s\r", 72, "");
        return;
    }
    fprintf(stderr, "%s%zu / %zu trajectories, %.0f per second, %.0f:%02.0f left%s",
            mode == 1 ? "\r" : "", done, total, rate, floor(left / 60.0),
            fmod(floor(left), 60.0), mode == 1 ? "   " : "\n");
}

int rf_mc_check_interrupted(const rf_mc *m, size_t ci, const rf_run_options *o, rf_error *err)
{
    if (!o->interrupted || !*o->interrupted)
        return 0;
    size_t n = ci * RF_CHUNK_SIZE < m->total ? ci * RF_CHUNK_SIZE : m->total;
    return rf_error_set(err, "", 0, 0, "interrupted after %zu of %zu trajectories", n, m->total);
}

int rf_mc_write_next(rf_mc *m, rf_store *s, size_t ci, const rf_run_options *o,
                     rf_run_summary *sum, double t0, double *last_report, rf_error *err)
{
    rf_chunk *c = &m->ring[ci % m->ahead];
    int status = rf_mc_write_chunk(s, c, o->maps, sum, err);
    rf_chunk_clear(c);
    pthread_mutex_lock(&m->mu);
    m->written = ci + 1;
    pthread_cond_broadcast(&m->cv);
    pthread_mutex_unlock(&m->mu);
    size_t n = (ci + 1) * RF_CHUNK_SIZE < m->total ? (ci + 1) * RF_CHUNK_SIZE : m->total;
    rf_mc_progress(status ? 0 : o->progress, n, m->total, t0, last_report);
    return status;
}

/* Simulates every chunk on the worker threads and writes them in order; 0 or -1 with
 * err set. */
static int simulate_and_write(rf_mc *m, rf_store *s, const rf_run_options *o,
                              rf_run_summary *sum, rf_error *err)
{
    int status = rf_mc_start(m, err);
    double t0 = rf_now_s(), last_report = t0;
    for (size_t ci = 0; status == 0 && ci < m->nchunks; ci++) {
        if ((status = rf_mc_check_interrupted(m, ci, o, err)) != 0)
            break;
        rf_chunk *c = &m->ring[ci % m->ahead];
        pthread_mutex_lock(&m->mu);
        while (!c->done)
            pthread_cond_wait(&m->cv, &m->mu);
        pthread_mutex_unlock(&m->mu);
        status = rf_mc_write_next(m, s, ci, o, sum, t0, &last_report, err);
    }
    if (status && o->progress == 1)
        fprintf(stderr, "\r%*s\r", 72, "");
    rf_mc_stop(m, status != 0);
    sum->seconds = rf_now_s() - t0;
    return status;
}

/* ---- the run ------------------------------------------------------------------ */

int rf_mc_init(rf_mc *m, const rf_project *p, int nthreads, size_t ahead, rf_error *err)
{
    memset(m, 0, sizeof *m);
    m->nthreads = nthreads > 1 ? nthreads : 1;
    m->p = p;
    m->scene.terrain = &p->terrain;
    m->scene.sim = &p->sim;
    m->scene.forests = p->forests;
    m->scene.nforests = p->nforests;
    m->scene.measures = p->measures;
    m->scene.nmeasures = p->nmeasures;
    m->ahead = ahead > 0 ? ahead : 1;
    m->claim = rf_mc_claim_in_order;
    pthread_mutex_init(&m->mu, NULL);
    pthread_cond_init(&m->cv, NULL);
    m->release_start = calloc(p->nreleases + 1, sizeof *m->release_start);
    for (size_t i = 0; m->release_start && i < p->nreleases; i++)
        m->release_start[i + 1] =
            m->release_start[i] + (size_t)rf_release_trajectories(&p->releases[i]);
    m->total = m->release_start ? m->release_start[p->nreleases] : 0;
    m->nchunks = (m->total + RF_CHUNK_SIZE - 1) / RF_CHUNK_SIZE;
    m->ring = calloc(m->ahead, sizeof *m->ring);
    m->hazard = calloc((size_t)m->nthreads, sizeof *m->hazard);
    if (!m->release_start || !m->ring || !m->hazard)
        return rf_error_set(err, "", 0, 0, "out of memory");
    for (int i = 0; i < m->nthreads; i++)
        if (rf_hazard_init(&m->hazard[i], &p->terrain, p->hazard_cell))
            return rf_error_set(err, "", 0, 0, "out of memory for the hazard grid");
    return 0;
}

void rf_mc_free(rf_mc *m)
{
    if (m->hazard)
        for (int i = 0; i < m->nthreads; i++)
            rf_hazard_free(&m->hazard[i]);
    for (size_t ci = 0; m->ring && ci < m->ahead; ci++)
        rf_chunk_clear(&m->ring[ci]);
    free(m->ring);
    free(m->hazard);
    free(m->release_start);
    pthread_mutex_destroy(&m->mu);
    pthread_cond_destroy(&m->cv);
    memset(m, 0, sizeof *m);
}

int rf_mc_finish(rf_mc *m, const rf_hazard *extra, rf_store *s, int status,
                 rf_run_summary *sum, rf_error *err)
{
    /* any order of merging gives the same cells (hazard.h); each worker's map is freed
     * once merged */
    for (int i = 1; status == 0 && i < m->nthreads; i++) {
        if (rf_hazard_merge(&m->hazard[0], &m->hazard[i]))
            status = rf_error_set(err, "", 0, 0, "out of memory merging the hazard grid");
        rf_hazard_free(&m->hazard[i]);
    }
    if (status == 0 && extra && rf_hazard_merge(&m->hazard[0], extra))
        status = rf_error_set(err, "", 0, 0, "out of memory merging the hazard grid");
    if (status == 0)
        status = rf_hazard_write(&m->hazard[0], (long)m->total, s, err);
    sum->n_trajectories = (long)m->total;
    if (status == 0)
        return rf_store_run_finish(s, "complete", (long)m->total, err);
    rf_store_run_finish(s, "failed",
                        sum->by_reason[0] + sum->by_reason[1] + sum->by_reason[2] +
                            sum->by_reason[3],
                        NULL); /* the trajectories written */
    return status;
}

int rf_montecarlo_run(const rf_project *p, rf_store *s, const rf_run_options *o,
                      rf_run_summary *sum, rf_error *err)
{
    memset(sum, 0, sizeof *sum);
    rf_mc m;
    int nthreads = o->threads > 1 ? o->threads : 1;
    int status = rf_mc_init(&m, p, nthreads, (size_t)nthreads * RF_CHUNKS_AHEAD_PER_THREAD, err);
    rf_store_describe_run(s, o->maps, 1, nthreads);
    if (status == 0 && rf_store_run_begin(s, p, (long)m.total, &sum->run_id, err))
        status = -1;
    else if (status == 0)
        status = rf_mc_finish(&m, NULL, s, simulate_and_write(&m, s, o, sum, err), sum, err);
    rf_mc_free(&m);
    return status;
}
