/* scenes.c - closed-form scenes (see scenes.h). */
#include "scenes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/empirical.h"
#include "rockfall/montecarlo.h"

#define MAX_POINTS 4096

int rf_scene_profile_surface(rf_terrain *t, const double *points, size_t npoints, double width,
                             rf_surface s, rf_error *err)
{
    rf_terrain_spec spec;
    memset(&spec, 0, sizeof spec);
    spec.source = RF_TERRAIN_PROFILE;
    spec.profile = (double *)points;
    spec.nprofile = npoints;
    spec.width = width;
    spec.up = 'z';
    spec.surface = s;
    return rf_terrain_build(&spec, t, err);
}

int rf_scene_profile(rf_terrain *t, const double *points, size_t npoints, double width,
                     double restitution, double friction, double rolling)
{
    rf_surface s;
    memset(&s, 0, sizeof s);
    s.restitution = (rf_dist){restitution, 0.0};
    s.friction = (rf_dist){friction, 0.0};
    s.rolling = (rf_dist){rolling, 0.0};
    rf_error err;
    return rf_scene_profile_surface(t, points, npoints, width, s, &err);
}

typedef struct trace {
    rf_path_point pt[MAX_POINTS];
    int n;
} trace;

static void trace_point(void *ctx, const rf_path_point *p)
{
    trace *tr = ctx;
    if (tr->n < MAX_POINTS)
        tr->pt[tr->n++] = *p;
}

/* The ground of a scene: a two-point profile (distance, elevation) 100 m wide with
 * constant coefficients. */
typedef struct ground {
    double pts[4];
    double restitution, friction, rolling;
} ground;

/* Runs one trajectory of body b (under base's engine, in b's model) from `start` over
 * the ground and records its path points; 0 when it gave at least two. */
static int run_traced(const rf_simulation *base, const ground *g, const rf_body *b,
                      rf_state start, trace *tr)
{
    rf_terrain t;
    if (rf_scene_profile(&t, g->pts, 2, 100.0, g->restitution, g->friction, g->rolling))
        return -1;
    rf_simulation sim = *base;
    sim.model = b->model;
    rf_scene scene = {&t, &sim, NULL, 0, NULL, 0};
    rf_workspace *ws = rf_workspace_alloc(&t);
    gsl_rng *rng = gsl_rng_alloc(rf_rng_type());
    int rc = -1;
    if (ws && rng) {
        gsl_rng_set(rng, 2385);
        rf_sink sink;
        memset(&sink, 0, sizeof sink);
        sink.ctx = tr;
        sink.path_point = trace_point;
        tr->n = 0;
        rf_trajectory_record rec;
        rf_simulate(&scene, b, &start, rng, ws, &sink, &rec);
        rc = tr->n >= 2 ? 0 : -1;
    }
    if (rng)
        gsl_rng_free(rng);
    rf_workspace_free(ws);
    rf_terrain_free(&t);
    return rc;
}

const char *rf_closed_form_name(int which)
{
    static const char *names[RF_N_CLOSED_FORMS] = {"slide Eq.1-2", "roll 5/7 g", "launch",
                                                   "bounce h e^2k"};
    return which >= 0 && which < RF_N_CLOSED_FORMS ? names[which] : "?";
}

/* Eq. 1-2: a point mass slides from rest down a 35 degree plane with mu = 0.3 and
 * leaves it at its foot; its speed there against alpha sqrt(2 g H). */
static double slide_error(const rf_simulation *base, trace *tr)
{
    const double theta = 35.0 * M_PI / 180.0, mu = 0.3, len = 200.0;
    const ground g = {{0.0, len * tan(theta), len, 0.0}, 0.0, mu, mu};
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_POINT);
    rf_state s0 = {.p = rf_v3(5.0, 50.0, (len - 5.0) * tan(theta))};
    if (run_traced(base, &g, &b, s0, tr))
        return NAN;
    const rf_path_point *end = &tr->pt[tr->n - 1];
    double h = s0.p.z - end->p.z;
    double v = rf_empirical_velocity(h, theta, mu);
    return h > 100.0 ? fabs(end->speed_ms - v) / v : NAN;
}

/* A sphere rolls from rest down a 25 degree plane with rolling resistance 0.1 (and
 * friction high enough to roll without slipping): v^2 = 2 a s, a = 5/7 g (sin - mu_r cos). */
static double roll_error(const rf_simulation *base, trace *tr)
{
    const double theta = 25.0 * M_PI / 180.0, mu_r = 0.1, len = 150.0;
    const ground g = {{0.0, len * tan(theta), len, 0.0}, 0.0, 0.9, mu_r};
    rf_body b = rf_body_make(1000.0, 2650.0, RF_MODEL_SPHERE);
    rf_vec3 n = rf_v3(sin(theta), 0.0, cos(theta));
    rf_state s0 = {.p = rf_v3_madd(rf_v3(5.0, 50.0, (len - 5.0) * tan(theta)), b.radius, n)};
    if (run_traced(base, &g, &b, s0, tr))
        return NAN;
    const rf_path_point *end = &tr->pt[tr->n - 1];
    double s = (s0.p.z - end->p.z) / sin(theta);
    double a = 5.0 / 7.0 * RF_GRAVITY * (sin(theta) - mu_r * cos(theta));
    double v = sqrt(2.0 * a * s);
    return s > 100.0 ? fabs(end->speed_ms - v) / v : NAN;
}

/* A sphere launched horizontally at v0 with its centre h above its touching height
 * lands v0 sqrt(2 h / g) further on. */
static double launch_error(const rf_simulation *base, trace *tr)
{
    const double v0 = 12.385, h = 23.85;
    const ground g = {{0.0, 0.0, 400.0, 0.0}, 0.0, 0.5, 0.1};
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s0 = {.p = rf_v3(10.0, 50.0, b.radius + h), .v = rf_v3(v0, 0.0, 0.0)};
    if (run_traced(base, &g, &b, s0, tr))
        return NAN;
    double want = v0 * sqrt(2.0 * h / RF_GRAVITY);
    return fabs((tr->pt[1].p.x - s0.p.x) - want) / want;
}

/* A sphere dropped from h onto flat ground with restitution e = 0.6 and no friction:
 * the k-th bounce rises to h e^(2k); from the time between impacts k and k+1,
 * height = g dt^2 / 8.  The worst of k = 1..3. */
static double bounce_error(const rf_simulation *base, trace *tr)
{
    const double e = 0.6, h = 10.0;
    const ground g = {{0.0, 0.0, 100.0, 0.0}, e, 0.0, 0.0};
    rf_body b = rf_body_make(2385.0, 2650.0, RF_MODEL_SPHERE);
    rf_state s0 = {.p = rf_v3(50.0, 50.0, b.radius + h)};
    if (run_traced(base, &g, &b, s0, tr) || tr->n < 6)
        return NAN;
    double err = 0.0;
    for (int k = 1; k <= 3; k++) {
        double dt = tr->pt[k + 1].t_s - tr->pt[k].t_s;
        double got = RF_GRAVITY * dt * dt / 8.0, want = h * pow(e, 2.0 * k);
        err = fmax(err, fabs(got - want) / want);
    }
    return err;
}

double rf_closed_form_error(int which, const rf_simulation *sim)
{
    trace *tr = malloc(sizeof *tr); /* large: kept off the stack */
    double err = NAN;
    if (tr) {
        switch (which) {
        case RF_CF_SLIDE: err = slide_error(sim, tr); break;
        case RF_CF_ROLL: err = roll_error(sim, tr); break;
        case RF_CF_LAUNCH: err = launch_error(sim, tr); break;
        case RF_CF_BOUNCE: err = bounce_error(sim, tr); break;
        default: break;
        }
    }
    free(tr);
    return err;
}
