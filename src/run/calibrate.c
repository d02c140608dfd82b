/* calibrate.c - surface values fitted to observed stop points (calibrate.h). */
#include "run/calibrate.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_multimin.h>

#include "input/bounds.h"
#include "rockfall/montecarlo.h"
#include "rockfall/sim.h"

/* ---- keys ------------------------------------------------------------------------ */

static const struct field_info {
    const char *name;
    double lo, hi, step;
} FIELDS[RF_FIT_NFIELDS] = {
    [RF_FIT_RESTITUTION] = {"restitution", 0.0, 1.0, 0.1},
    [RF_FIT_FRICTION] = {"friction", 0.0, RF_FRICTION_MAX, 0.1},
    [RF_FIT_ROLLING] = {"rolling", 0.0, RF_FRICTION_MAX, 0.1},
    [RF_FIT_ROUGHNESS] = {"roughness", 0.0, RF_ROUGHNESS_MAX, 0.05},
    [RF_FIT_TANGENTIAL] = {"tangential", 0.0, 1.0, 0.1},
};

int rf_fit_key_parse(const rf_project *p, const char *path, rf_fit_key *k, rf_error *err)
{
    memset(k, 0, sizeof *k);
    size_t len = strlen(path);
    if (len >= sizeof k->path)
        return rf_error_set(err, "--fit", 0, 0, "a key of %zu characters (at most %zu)", len,
                            sizeof k->path - 1);
    memcpy(k->path, path, len + 1);
    const char *field = strrchr(path, '.');
    if (!field)
        return rf_error_set(err, "--fit", 0, 0,
                            "'%s': a key is surface.FIELD or zones.NAME.FIELD", path);
    field++;
    size_t head = (size_t)(field - 1 - path);
    if (head == 7 && !strncmp(path, "surface", 7)) {
        k->zone = -1;
    } else if (head > 6 && !strncmp(path, "zones.", 6)) {
        if (p->terrain.nzones > RF_FIT_ZONES_MAX)
            return rf_error_set(err, "--fit", 0, 0, "'%s': a terrain of over %d zones", path,
                                RF_FIT_ZONES_MAX);
        k->zone = -2;
        /* NAME+NAME+...: the zones sharing the value */
        for (const char *zn = path + 6, *end = field - 1; zn < end;) {
            const char *plus = memchr(zn, '+', (size_t)(end - zn));
            size_t zl = (size_t)((plus ? plus : end) - zn);
            long found = -1;
            for (size_t z = 0; z < p->terrain.nzones; z++)
                if (strlen(p->terrain.zones[z].name) == zl &&
                    !strncmp(p->terrain.zones[z].name, zn, zl))
                    found = (long)z;
            if (found < 0)
                return rf_error_set(err, "--fit", 0, 0, "'%s': the terrain has no zone '%.*s'",
                                    path, (int)zl, zn);
            k->zones[found] = 1;
            if (k->zone == -2)
                k->zone = found;
            zn += zl + (plus != NULL);
        }
    } else {
        return rf_error_set(err, "--fit", 0, 0,
                            "'%s': a key is surface.FIELD or zones.NAME.FIELD", path);
    }
    int f = -1;
    for (int i = 0; i < RF_FIT_NFIELDS; i++)
        if (!strcmp(field, FIELDS[i].name))
            f = i;
    if (f < 0)
        return rf_error_set(err, "--fit", 0, 0,
                            "'%s': FIELD is one of restitution, friction, rolling, roughness, "
                            "tangential",
                            path);
    k->field = (rf_fit_field)f;
    k->lo = FIELDS[f].lo, k->hi = FIELDS[f].hi, k->step = FIELDS[f].step;
    if (k->field == RF_FIT_ROLLING)
        for (size_t z = 0; z < p->terrain.nzones; z++)
            if ((k->zone < 0 || k->zones[z]) && p->terrain.zones[z].surface.rolling_is_friction)
                return rf_error_set(err, "--fit", 0, 0,
                                    "'%s': zone '%s' has no rolling resistance of its own (it is "
                                    "its friction): give 'rolling' in the project, or fit the "
                                    "friction",
                                    path, p->terrain.zones[z].name);
    if (k->field == RF_FIT_TANGENTIAL)
        for (size_t z = 0; z < p->terrain.nzones; z++)
            if ((k->zone < 0 || k->zones[z]) && p->terrain.zones[z].surface.law != RF_IMPACT_RT)
                return rf_error_set(err, "--fit", 0, 0,
                                    "'%s': zone '%s' has no tangential restitution (its impact "
                                    "law is eq8)",
                                    path, p->terrain.zones[z].name);
    return 0;
}

static double *field_of(rf_surface *s, rf_fit_field f)
{
    switch (f) {
    case RF_FIT_RESTITUTION: return &s->restitution.mean;
    case RF_FIT_FRICTION: return &s->friction.mean;
    case RF_FIT_ROLLING: return &s->rolling.mean;
    case RF_FIT_ROUGHNESS: return &s->roughness;
    case RF_FIT_TANGENTIAL: return &s->tangential.mean;
    default: return NULL;
    }
}

double rf_fit_key_get(const rf_project *p, const rf_fit_key *k)
{
    size_t z = k->zone < 0 ? 0 : (size_t)k->zone;
    if (z >= p->terrain.nzones)
        return NAN;
    rf_surface s = p->terrain.zones[z].surface;
    return *field_of(&s, k->field);
}

void rf_fit_key_set(rf_project *p, const rf_fit_key *k, double v)
{
    v = fmin(fmax(v, k->lo), k->hi);
    for (size_t z = 0; z < p->terrain.nzones; z++)
        if (k->zone < 0 || k->zones[z]) {
            rf_surface *s = &p->terrain.zones[z].surface;
            *field_of(s, k->field) = v;
            /* the project's rolling resistance is its friction */
            if (k->field == RF_FIT_FRICTION && s->rolling_is_friction)
                s->rolling.mean = v;
        }
}

/* ---- the project's stops ------------------------------------------------------------ */

typedef struct stops_ctx {
    const rf_project *p;
    rf_scene scene;
    const rf_terrain_tables *tables;
    const size_t *release_start; /* global number of each release's first trajectory */
    size_t total;
    int nthreads;
    double *stop, *start;
    size_t not_rest[256];
    int oom[256];
} stops_ctx;

typedef struct stops_worker {
    stops_ctx *c;
    int id;
} stops_worker;

static void *stops_main(void *vw)
{
    stops_worker *w = vw;
    stops_ctx *c = w->c;
    const rf_project *p = c->p;
    rf_workspace *ws = rf_workspace_alloc_shared(c->tables);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    if (!ws || !rng) {
        c->oom[w->id] = 1;
    } else {
        size_t rel = 0;
        /* trajectories id, id + nthreads, ...: each from its own stream, so the split
         * changes nothing */
        for (size_t g = (size_t)w->id; g < c->total; g += (size_t)c->nthreads) {
            while (c->release_start[rel + 1] <= g)
                rel++;
            long idx = (long)(g - c->release_start[rel]);
            gsl_rng_set(rng, rf_trajectory_seed(p->seed, rel, idx));
            double mass;
            rf_body body = rf_release_draw_body(p, rel, p->sim.model, rng, &mass);
            rf_state s0 = rf_release_start_of(p, rel, idx, &body, rng);
            rf_trajectory_record rec;
            rf_simulate(&c->scene, &body, &s0, rng, ws, NULL, &rec);
            c->stop[2 * g] = rec.stop.x, c->stop[2 * g + 1] = rec.stop.y;
            if (c->start)
                c->start[2 * g] = s0.p.x, c->start[2 * g + 1] = s0.p.y;
            c->not_rest[w->id] += rec.reason != RF_END_REST;
        }
    }
    rf_workspace_free(ws);
    if (rng)
        gsl_rng_free(rng);
    return NULL;
}

/* rf_stops_simulate on the terrain's tables, built by the caller (once for a whole
 * calibration). */
static long simulate_stops(const rf_project *p, const rf_terrain_tables *tables, int threads,
                           double **stop, double **start, size_t *not_rest)
{
    *stop = NULL;
    if (start)
        *start = NULL;
    int nt = threads < 1 ? 1 : threads > 256 ? 256 : threads;
    stops_ctx *c = calloc(1, sizeof *c);
    size_t *rs = calloc(p->nreleases + 1, sizeof *rs);
    pthread_t tids[256];
    stops_worker w[256];
    long result = -1;
    if (!c || !rs)
        goto done;
    for (size_t i = 0; i < p->nreleases; i++)
        rs[i + 1] = rs[i] + (size_t)rf_release_trajectories(&p->releases[i]);
    c->p = p;
    c->scene = (rf_scene){&p->terrain, &p->sim, p->forests, p->nforests, p->measures,
                          p->nmeasures};
    c->release_start = rs;
    c->total = rs[p->nreleases];
    c->nthreads = nt;
    c->stop = malloc((2 * c->total + 1) * sizeof *c->stop);
    c->start = start ? malloc((2 * c->total + 1) * sizeof *c->start) : NULL;
    c->tables = tables;
    if (!c->stop || (start && !c->start)) {
        free(c->stop);
        free(c->start);
        goto done;
    }
    int created[256] = {0};
    for (int i = 0; i < nt; i++) {
        w[i] = (stops_worker){c, i};
        if (i > 0) {
            created[i] = pthread_create(&tids[i], NULL, stops_main, &w[i]) == 0;
            c->oom[i] = !created[i]; /* not started: its trajectories are missing */
        }
    }
    stops_main(&w[0]);
    for (int i = 1; i < nt; i++)
        if (created[i])
            pthread_join(tids[i], NULL);
    size_t nr = 0;
    int failed = 0;
    for (int i = 0; i < nt; i++)
        nr += c->not_rest[i], failed |= c->oom[i];
    if (failed) {
        free(c->stop);
        free(c->start);
        goto done;
    }
    *stop = c->stop;
    if (start)
        *start = c->start;
    if (not_rest)
        *not_rest = nr;
    result = (long)c->total;
done:
    free(rs);
    free(c);
    return result;
}

long rf_stops_simulate(const rf_project *p, int threads, double **stop, double **start,
                       size_t *not_rest)
{
    rf_terrain_tables *tables = rf_terrain_tables_build(&p->terrain);
    long n = tables ? simulate_stops(p, tables, threads, stop, start, not_rest) : -1;
    if (!tables)
        *stop = NULL;
    rf_terrain_tables_free(tables);
    return n;
}

/* ---- the objective ------------------------------------------------------------------ */

/* The origin of the stops' frame: the mean start point. */
static void mean_point(const double *xy, size_t n, double *x0, double *y0)
{
    double sx = 0.0, sy = 0.0;
    for (size_t i = 0; i < n; i++)
        sx += xy[2 * i], sy += xy[2 * i + 1];
    *x0 = n ? sx / (double)n : 0.0;
    *y0 = n ? sy / (double)n : 0.0;
}

double rf_objective_value(rf_objective k, const rf_agreement *a)
{
    if (k == RF_OBJECTIVE_KS)
        return a->ks + a->ks_lateral;
    /* a sample without spread (one stop, or all at one point) is taken in metres */
    double sr = a->runout_sd_meas > 1e-3 ? a->runout_sd_meas : 1.0;
    double sl = a->lateral_sd_meas > 1e-3 ? a->lateral_sd_meas : 1.0;
    return a->w1_runout / sr + a->w1_lateral / sl;
}

const char *rf_objective_name(rf_objective k)
{
    return k == RF_OBJECTIVE_KS ? "ks_runout + ks_lateral"
                                : "w1_runout / sd_runout + w1_lateral / sd_lateral";
}

/* rf_calibrate_objective on the terrain's tables, built by the caller. */
static int objective_on(const rf_project *p, const rf_terrain_tables *tables, const double *obs,
                        size_t nobs, int threads, rf_objective kind, double *objective,
                        rf_agreement *a, size_t *not_rest)
{
    double *stop, *start;
    long n = simulate_stops(p, tables, threads, &stop, &start, not_rest);
    if (n < 0)
        return -1;
    double x0, y0;
    mean_point(start, (size_t)n, &x0, &y0);
    int rc = rf_agreement_compute(obs, nobs, stop, (size_t)n, x0, y0, a);
    free(stop);
    free(start);
    if (rc == 0)
        *objective = rf_objective_value(kind, a);
    return rc;
}

int rf_calibrate_objective(const rf_project *p, const double *obs, size_t nobs, int threads,
                           rf_objective kind, double *objective, rf_agreement *a,
                           size_t *not_rest)
{
    rf_terrain_tables *tables = rf_terrain_tables_build(&p->terrain);
    int rc = tables ? objective_on(p, tables, obs, nobs, threads, kind, objective, a, not_rest)
                    : -1;
    rf_terrain_tables_free(tables);
    return rc;
}

typedef struct fit_ctx {
    rf_project *p;
    const double *obs;
    size_t nobs;
    const rf_fit_key *keys;
    size_t nkeys;
    const rf_calibrate_options *o;
    const rf_terrain_tables *tables; /* the terrain's, built once for every simulation */
    long evals;
    int failed;
    /* the best point seen: its values, objective, agreement */
    double *best;
    double best_f;
    rf_agreement best_a;
    size_t best_not_rest;
} fit_ctx;

/* The objective at values x (natural units): each value clamped to its bounds, the
 * objective raised by the distance outside them in initial steps. */
static double evaluate(fit_ctx *f, const double *x)
{
    double penalty = 0.0;
    for (size_t i = 0; i < f->nkeys; i++) {
        const rf_fit_key *k = &f->keys[i];
        double v = fmin(fmax(x[i], k->lo), k->hi);
        penalty += fabs(x[i] - v) / k->step;
        rf_fit_key_set(f->p, k, v);
    }
    double obj;
    rf_agreement a;
    size_t nr = 0;
    f->evals++;
    if (objective_on(f->p, f->tables, f->obs, f->nobs, f->o->threads, f->o->objective, &obj, &a,
                     &nr)) {
        f->failed = 1;
        return GSL_POSINF;
    }
    if (obj < f->best_f) {
        f->best_f = obj;
        f->best_a = a;
        f->best_not_rest = nr;
        for (size_t i = 0; i < f->nkeys; i++)
            f->best[i] = fmin(fmax(x[i], f->keys[i].lo), f->keys[i].hi);
    }
    return obj + penalty;
}

/* The simplex works on u = (x - x_start) / step: every key moves in units of its step. */
typedef struct simplex_ctx {
    fit_ctx *f;
    const double *x0;
    double *x;
} simplex_ctx;

static double simplex_f(const gsl_vector *u, void *vc)
{
    simplex_ctx *s = vc;
    for (size_t i = 0; i < s->f->nkeys; i++)
        s->x[i] = s->x0[i] + s->f->keys[i].step * gsl_vector_get(u, i);
    return evaluate(s->f, s->x);
}

/* The i-th point (i >= 1) of the Halton sequence in base b: the radical inverse. */
static double halton(unsigned long i, unsigned b)
{
    double f = 1.0, r = 0.0;
    for (; i > 0; i /= b) {
        f /= (double)b;
        r += f * (double)(i % b);
    }
    return r;
}

/* The coarse scan: `coarse` points of the Halton sequence (bases 2, 3, 5, ...: evenly
 * spread in any number of keys) over the box of the keys' ranges, each key within
 * [lo, min(hi, lo + 20 steps)] (a friction of 100 is a bound, not a guess).  The best
 * point so far (the project's values included) starts the simplex. */
static void coarse_scan(fit_ctx *f, double *x)
{
    static const unsigned primes[] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31,
                                      37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79,
                                      83, 89, 97, 101, 103, 107, 109, 113, 127, 131};
    for (int j = 1; j <= f->o->coarse && f->evals < f->o->max_evals && !f->failed; j++) {
        for (size_t i = 0; i < f->nkeys; i++) {
            const rf_fit_key *k = &f->keys[i];
            double hi = fmin(k->hi, k->lo + 20.0 * k->step);
            x[i] = k->lo + (hi - k->lo) * halton((unsigned long)j, primes[i % 32]);
        }
        evaluate(f, x);
    }
}

static void print_progress(const fit_ctx *f, long iter, double size)
{
    FILE *out = f->o->progress;
    if (!out)
        return;
    fprintf(out, "calibrate: iteration %ld, %ld simulations, best objective %.4f (KS runout "
                 "%.3f, lateral %.3f), simplex size %.3g\n",
            iter, f->evals, f->best_f, f->best_a.ks, f->best_a.ks_lateral, size);
    fflush(out);
}

/* Nelder-Mead from x (natural units) until the simplex is smaller than tol steps or the
 * simulations run out; 1 when it converged. */
static int simplex(fit_ctx *f, const double *x)
{
    size_t n = f->nkeys;
    const gsl_multimin_fminimizer_type *T = gsl_multimin_fminimizer_nmsimplex2;
    gsl_multimin_fminimizer *m = gsl_multimin_fminimizer_alloc(T, n);
    gsl_vector *u = gsl_vector_calloc(n), *step = gsl_vector_alloc(n);
    double *xs = malloc(n * sizeof *xs);
    int converged = 0;
    if (!m || !u || !step || !xs) {
        f->failed = 1;
    } else {
        gsl_vector_set_all(step, 1.0);
        simplex_ctx sc = {f, x, xs};
        gsl_multimin_function fn = {simplex_f, n, &sc};
        gsl_multimin_fminimizer_set(m, &fn, u, step);
        for (long iter = 1; f->evals < f->o->max_evals && !f->failed; iter++) {
            if (gsl_multimin_fminimizer_iterate(m))
                break;
            double size = gsl_multimin_fminimizer_size(m);
            print_progress(f, iter, size);
            if (gsl_multimin_test_size(size, f->o->tol) == GSL_SUCCESS) {
                converged = 1;
                break;
            }
        }
    }
    free(xs);
    if (step)
        gsl_vector_free(step);
    if (u)
        gsl_vector_free(u);
    if (m)
        gsl_multimin_fminimizer_free(m);
    return converged;
}

int rf_calibrate(rf_project *p, const double *obs, size_t nobs, const rf_fit_key *keys,
                 size_t nkeys, const rf_calibrate_options *o, rf_calibration *out,
                 rf_error *err)
{
    memset(out, 0, sizeof *out);
    if (nkeys == 0 || nobs == 0)
        return rf_error_set(err, "", 0, 0, nkeys ? "no observed stop points" : "nothing to fit");
    out->nkeys = nkeys;
    out->start = malloc(nkeys * sizeof *out->start);
    out->value = malloc(nkeys * sizeof *out->value);
    double *x = malloc(nkeys * sizeof *x);
    rf_terrain_tables *tables = rf_terrain_tables_build(&p->terrain);
    fit_ctx f = {p, obs, nobs, keys, nkeys, o, tables, 0, 0, malloc(nkeys * sizeof(double)),
                 GSL_POSINF, {0}, 0};
    int rc = -1;
    if (!out->start || !out->value || !x || !f.best || !tables) {
        rf_error_set(err, "", 0, 0, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < nkeys; i++)
        out->start[i] = x[i] = f.best[i] = rf_fit_key_get(p, &keys[i]);
    evaluate(&f, x);
    coarse_scan(&f, x);
    /* the simplex again from the best point while that improves it by more than 1e-3:
     * a simplex shrinks onto the first valley it finds on a rough objective */
    double before = GSL_POSINF;
    for (int r = 0; r < 4 && !f.failed && f.evals < o->max_evals && f.best_f < before - 1e-3;
         r++) {
        before = f.best_f;
        memcpy(x, f.best, nkeys * sizeof *x);
        out->converged = simplex(&f, x);
    }
    if (f.failed) {
        rf_error_set(err, "", 0, 0, "out of memory simulating the project");
        goto done;
    }
    for (size_t i = 0; i < nkeys; i++) {
        out->value[i] = f.best[i];
        rf_fit_key_set(p, &keys[i], f.best[i]);
    }
    out->objective = f.best_f;
    out->agreement = f.best_a;
    out->not_rest = f.best_not_rest;
    out->n_evals = f.evals;
    for (size_t i = 0; i < p->nreleases; i++)
        out->n_trajectories += rf_release_trajectories(&p->releases[i]);
    rc = 0;
done:
    free(x);
    free(f.best);
    rf_terrain_tables_free(tables);
    if (rc)
        rf_calibration_free(out);
    return rc;
}

void rf_calibration_free(rf_calibration *c)
{
    free(c->start);
    free(c->value);
    c->start = c->value = NULL;
}
