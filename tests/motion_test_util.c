/* motion_test_util.c - scenes and a recording sink for the motion tests. */
#include "motion_test_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures/scenes.h"
#include "test.h"

void mt_profile(rf_terrain *t, const double *pts, size_t n, double width, rf_surface s)
{
    rf_error err;
    memset(&err, 0, sizeof err);
    int rc = rf_scene_profile_surface(t, pts, n, width, s, &err);
    ENSURE_MSG(rc == 0, "profile: %s", err.message);
}

static void build_file(rf_terrain *t, rf_terrain_source src, const char *name, const char *text,
                       rf_surface s)
{
    char *files[1] = {(char *)rf_test_write(name, text)};
    rf_terrain_spec spec;
    memset(&spec, 0, sizeof spec);
    spec.source = src;
    spec.files = files;
    spec.nfiles = 1;
    spec.up = 'z';
    spec.surface = s;
    rf_error err;
    memset(&err, 0, sizeof err);
    int rc = rf_terrain_build(&spec, t, &err);
    ENSURE_MSG(rc == 0, "%s:%d:%d: %s", err.file, err.line, err.column, err.message);
}

void mt_dem_text(rf_terrain *t, const char *name, const char *text, rf_surface s)
{
    build_file(t, RF_TERRAIN_DEM, name, text, s);
}

void mt_mesh_text(rf_terrain *t, const char *name, const char *text, rf_surface s)
{
    build_file(t, RF_TERRAIN_MESH, name, text, s);
}

rf_state mt_state(rf_vec3 p, rf_vec3 v)
{
    rf_state s;
    memset(&s, 0, sizeof s);
    s.p = p;
    s.v = v;
    return s;
}

void mt_incline(rf_terrain *t, double theta, double L, double width, rf_surface s)
{
    double prof[4] = {0.0, L * tan(theta), L, 0.0};
    mt_profile(t, prof, 2, width, s);
}

rf_state mt_incline_state(double theta, double L, double x, double y, double lift, rf_vec3 v)
{
    rf_vec3 n = rf_v3(sin(theta), 0, cos(theta));
    return mt_state(rf_v3_madd(rf_v3(x, y, (L - x) * tan(theta)), lift, n), v);
}

rf_simulation mt_sim(rf_rock_model model, rf_contact_kind contact, double max_time)
{
    rf_simulation sim;
    memset(&sim, 0, sizeof sim);
    sim.model = model;
    sim.engine = RF_ENGINE_EXACT;
    sim.dt = 0.001;
    sim.contact = contact;
    sim.stop_speed = 0.1;
    sim.max_time = max_time;
    sim.paths = 10;
    return sim;
}

static int bad(double x) { return !isfinite(x); }

static void on_point(void *ctx, const rf_path_point *pt)
{
    mt_run *r = ctx;
    if (bad(pt->t_s) || bad(pt->p.x) || bad(pt->p.y) || bad(pt->p.z) || bad(pt->speed_ms) ||
        bad(pt->energy_kj))
        r->nan_seen = 1;
    if (r->npoints == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 64;
        r->points = realloc(r->points, r->cap * sizeof *r->points);
    }
    r->points[r->npoints++] = *pt;
    if (r->pending_impacts > 0) {
        if (r->n_impacts == r->icap) {
            r->icap = r->icap ? 2 * r->icap : 64;
            r->impacts = realloc(r->impacts, r->icap * sizeof *r->impacts);
        }
        r->impacts[r->n_impacts++] = *pt;
        r->pending_impacts = 0;
    }
    r->last = *pt;
}

static void on_impact(void *ctx, double t, double e0, double e1, double vn)
{
    mt_run *r = ctx;
    (void)t;
    if (bad(e0) || bad(e1) || bad(vn))
        r->nan_seen = 1;
    if (e1 - e0 > r->energy_gain_kj)
        r->energy_gain_kj = e1 - e0;
    r->pending_impacts++;
}

static void on_sample(void *ctx, rf_vec3 p, double speed, double ekj, double h)
{
    mt_run *r = ctx;
    if (bad(p.x) || bad(p.y) || bad(p.z) || bad(speed) || bad(ekj) || bad(h))
        r->nan_seen = 1;
    if (r->samples > 0) {
        double d = hypot(p.x - r->last_sample.x, p.y - r->last_sample.y);
        if (d > r->max_sample_gap)
            r->max_sample_gap = d;
    }
    if ((size_t)r->samples == r->scap) {
        r->scap = r->scap ? 2 * r->scap : 64;
        r->sample = realloc(r->sample, r->scap * sizeof *r->sample);
        ENSURE(r->sample != NULL);
    }
    r->sample[r->samples] = (mt_sample){p, speed, ekj};
    r->samples++;
    r->last_sample = p;
}

/* One trajectory of scene from s into sink and rec, its random stream seeded with seed,
 * with a workspace of its own (ENSUREs). */
static void simulate_scene(const rf_scene *scene, const rf_body *b, const rf_state *s,
                           unsigned long seed, const rf_sink *sink, rf_trajectory_record *rec)
{
    rf_workspace *ws = rf_workspace_alloc(scene->terrain);
    ENSURE(ws != NULL);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    ENSURE(rng != NULL);
    gsl_rng_set(rng, seed);
    rf_simulate(scene, b, s, rng, ws, sink, rec);
    gsl_rng_free(rng);
    rf_workspace_free(ws);
}

void mt_simulate_opts(const rf_terrain *t, const rf_simulation *sim, const rf_body *b,
                      const rf_state *s, unsigned long seed, double sample_spacing, mt_run *r)
{
    memset(r, 0, sizeof *r);
    rf_scene scene = {t, sim, NULL, 0, NULL, 0};
    rf_sink sink;
    memset(&sink, 0, sizeof sink);
    sink.ctx = r;
    sink.path_point = on_point;
    sink.impact = on_impact;
    if (sample_spacing > 0) {
        sink.sample = on_sample;
        sink.sample_spacing = sample_spacing;
    }
    simulate_scene(&scene, b, s, seed, &sink, &r->rec);
}

void mt_simulate_t(const rf_terrain *t, rf_rock_model model, double mass,
                   rf_contact_kind contact, const rf_state *s, unsigned long seed,
                   double max_time, mt_run *r)
{
    rf_simulation sim = mt_sim(model, contact, max_time);
    rf_body b = rf_body_make(mass, 2650.0, model);
    mt_simulate_opts(t, &sim, &b, s, seed, 0.0, r);
}

void mt_simulate(const rf_terrain *t, rf_rock_model model, double mass, rf_contact_kind contact,
                 const rf_state *s, unsigned long seed, mt_run *r)
{
    mt_simulate_t(t, model, mass, contact, s, seed, 300.0, r);
}

void mt_run_free(mt_run *r)
{
    free(r->points);
    free(r->impacts);
    free(r->sample);
    memset(r, 0, sizeof *r);
}

const rf_path_point *mt_first_impact(const mt_run *r)
{
    return r->n_impacts ? &r->impacts[0] : NULL;
}

double mt_energy_rise(const mt_run *r, double mass)
{
    double mg = mass * RF_GRAVITY, rise = 0.0, low = INFINITY;
    for (size_t i = 1; i < r->npoints; i++) {
        double e = 1000.0 * r->points[i].energy_kj + mg * r->points[i].p.z;
        rise = fmax(rise, e - low);
        low = fmin(low, e);
    }
    return rise;
}

double mt_terrain_distance(const rf_terrain *t, rf_vec3 p)
{
    double best = INFINITY;
    for (size_t i = 0; i < t->ntri; i++) {
        if (t->is_grid && rf_grid_slot(t, i) < 0)
            continue; /* a hole */
        rf_vec3 q = rf_triangle_closest_point(RF_TRI(t, i), p);
        double d = rf_v3_norm(rf_v3_sub(p, q));
        if (d < best)
            best = d;
    }
    return best;
}

char *mt_grid_text(int nx, int ny, double cell, double x0, double y0,
                   double (*z)(int i, int j, void *), void *ctx)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return NULL;
    fprintf(f, "ncols %d\nnrows %d\nxllcorner %.17g\nyllcorner %.17g\ncellsize %.17g\n"
               "NODATA_value -9999\n",
            nx, ny, x0, y0, cell);
    for (int j = ny - 1; j >= 0; j--) {
        for (int i = 0; i < nx; i++)
            fprintf(f, i ? " %.17g" : "%.17g", z(i, j, ctx));
        fputc('\n', f);
    }
    fclose(f);
    return buf;
}

char *mt_stl_text(const rf_vec3 *P, const int (*tri)[3], size_t ntri)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return NULL;
    fputs("solid mesh\n", f);
    for (size_t k = 0; k < ntri; k++) {
        fputs("facet normal 0 0 0\nouter loop\n", f);
        for (int i = 0; i < 3; i++) {
            rf_vec3 p = P[tri[k][i]];
            fprintf(f, "vertex %.17g %.17g %.17g\n", p.x, p.y, p.z);
        }
        fputs("endloop\nendfacet\n", f);
    }
    fputs("endsolid mesh\n", f);
    fclose(f);
    return buf;
}

char *mt_grid_stl_text(int nx, int ny, double cell, double x0, double y0, int alternate,
                       double (*z)(int i, int j, void *), void *ctx)
{
    size_t nn = (size_t)nx * (size_t)ny;
    rf_vec3 *P = malloc(nn * sizeof *P);
    int(*tri)[3] = malloc(2 * nn * sizeof *tri);
    if (!P || !tri) {
        free(P);
        free(tri);
        return NULL;
    }
    for (int j = ny - 1; j >= 0; j--)
        for (int i = 0; i < nx; i++)
            P[j * nx + i] = rf_v3(x0 + i * cell, y0 + j * cell, z(i, j, ctx));
    /* corners SW, SE, NE, NW; the two triangles of each split */
    static const int split[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};
    size_t nt = 0;
    for (int j = 0; j + 1 < ny; j++)
        for (int i = 0; i + 1 < nx; i++) {
            int c[4] = {j * nx + i, j * nx + i + 1, (j + 1) * nx + i + 1, (j + 1) * nx + i};
            for (int h = 0; h < 2; h++) {
                const int *v = split[alternate && (i + j) % 2][h];
                if (P[c[v[0]]].z == -9999.0 || P[c[v[1]]].z == -9999.0 || P[c[v[2]]].z == -9999.0)
                    continue;
                for (int a = 0; a < 3; a++)
                    tri[nt][a] = c[v[a]];
                nt++;
            }
        }
    char *txt = mt_stl_text(P, (const int(*)[3])tri, nt);
    free(P);
    free(tri);
    return txt;
}

void mt_grid_terrain(rf_terrain *t, int mesh, int nx, int ny, double cell,
                     double (*z)(int i, int j, void *), void *ctx, rf_surface s)
{
    char *txt = mesh ? mt_grid_stl_text(nx, ny, cell, 0.5 * cell, 0.5 * cell, 0, z, ctx)
                     : mt_grid_text(nx, ny, cell, 0.0, 0.0, z, ctx);
    if (mesh)
        mt_mesh_text(t, "grid.stl", txt, s);
    else
        mt_dem_text(t, "grid.asc", txt, s);
    free(txt);
}

void mt_rk4(void (*f)(const double *y, double *dy, const void *ctx), const void *ctx, double *y,
            int n, double T, long steps)
{
    double h = T / steps;
    for (long i = 0; i < steps; i++) {
        double k1[8], k2[8], k3[8], k4[8], tmp[8];
        f(y, k1, ctx);
        for (int j = 0; j < n; j++)
            tmp[j] = y[j] + 0.5 * h * k1[j];
        f(tmp, k2, ctx);
        for (int j = 0; j < n; j++)
            tmp[j] = y[j] + 0.5 * h * k2[j];
        f(tmp, k3, ctx);
        for (int j = 0; j < n; j++)
            tmp[j] = y[j] + h * k3[j];
        f(tmp, k4, ctx);
        for (int j = 0; j < n; j++)
            y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
}

/* ---- scenes with measures ----------------------------------------------------------- */

static void scene_on_interception(void *ctx, const rf_interception_record *r)
{
    mt_scene_run *run = ctx;
    ENSURE(run->n < MT_MAX_ICPT);
    run->icpt[run->n++] = *r;
}

static void scene_on_impact(void *ctx, double t_s, double e0_kj, double e1_kj, double vin)
{
    mt_scene_run *run = ctx;
    (void)vin;
    ENSURE(run->nimp < MT_MAX_IMPACTS);
    run->imp_t[run->nimp] = t_s, run->imp_e0[run->nimp] = e0_kj, run->imp_e1[run->nimp] = e1_kj;
    run->nimp++;
}

static void scene_on_point(void *ctx, const rf_path_point *pt)
{
    mt_scene_run *run = ctx;
    run->last = *pt;
    run->npoints++;
}

void mt_run_scene(const rf_terrain *t, const rf_simulation *sim, const rf_body *b,
                  const rf_measure *ms, size_t nms, const rf_state *s, unsigned long seed,
                  mt_scene_run *run)
{
    memset(run, 0, sizeof *run);
    rf_scene scene = {t, sim, NULL, 0, ms, nms};
    rf_sink sink;
    memset(&sink, 0, sizeof sink);
    sink.ctx = run;
    sink.interception = scene_on_interception;
    sink.path_point = scene_on_point;
    sink.impact = scene_on_impact;
    simulate_scene(&scene, b, s, seed, &sink, &run->rec);
}

rf_measure mt_measure(rf_measure_kind kind, rf_behaviour behaviour, double *xy, size_t n,
                      double height, double capacity_kj)
{
    rf_measure m;
    memset(&m, 0, sizeof m);
    m.name = "m";
    m.kind = kind;
    m.behaviour = kind == RF_CONTROL ? RF_COLLECT : behaviour;
    m.importance = RF_IMPORTANT;
    m.line.xy = xy;
    m.line.n = n;
    m.height = kind == RF_CONTROL ? 0.0 : height;
    m.mel = m.sel = -1.0;
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        m.capacity[s] = -1.0;
    if (kind == RF_BARRIER) {
        m.mel = capacity_kj;
        m.sel = capacity_kj / 3.0;
        m.capacity[RF_SERVICEABILITY] = m.sel;
        m.capacity[RF_ULTIMATE] = m.mel;
    } else if (kind == RF_EMBANKMENT) {
        m.capacity[RF_SERVICEABILITY] = 0.25 * capacity_kj;
        m.capacity[RF_RESTORABILITY] = 0.5 * capacity_kj;
        m.capacity[RF_ULTIMATE] = capacity_kj;
    }
    return m;
}
