/* replay_test_util.c - what the hard cases and the replays of random scenes share: the
 * sanity checks of a run, the rough test slope, and the replayed scenes with the
 * checks they end with. */
#include "replay_test_util.h"

#include <stdlib.h>

#include "base/tolerances.h" /* RF_STALL_EVENTS */
#include "test.h"

const rf_surface ROCKY = {{0.35, 0.1}, {0.45, 0.15}, {0.12, 0.04}};

void ensure_sane(const mt_run *r, double max_time)
{
    ENSURE(!r->nan_seen);
    ENSURE(r->rec.duration_s <= max_time + 1e-9);
    ENSURE(r->rec.reason != RF_END_MAX_TIME || r->rec.duration_s >= max_time - 1e-6);
    ENSURE_MSG(r->energy_gain_kj <= 1e-12 + 1e-12 * r->rec.max_energy_kj,
               "energy gain %.3g kJ at an impact", r->energy_gain_kj);
}

static double rough_z(int i, int j, void *ctx)
{
    gsl_rng *rng = ctx;
    double z = 40.0 - 0.7 * i + 0.1 * j + 1.2 * gsl_rng_uniform(rng);
    if (i >= 30 && i <= 31 && j >= 20 && j <= 22)
        return -9999.0;
    return z;
}

/* A 61 x 41 rough slope of 1 m cells with a nodata hole, its heights drawn from rng. */
void rough_terrain(rf_terrain *t, const char *name, gsl_rng *rng)
{
    char *txt = mt_grid_text(61, 41, 1.0, 0.0, 0.0, rough_z, rng);
    mt_dem_text(t, name, txt, ROCKY);
    free(txt);
}

/* ---- replays of random scenes that once went wrong -------------------------------------
 *
 * A randomised search over rough grids, surfaces, rocks and engine settings found these.
 * Scene `it` of search `seed`: the grid and its surface, then per trajectory its
 * settings and start, all drawn in a fixed order from one stream, so that trajectory k
 * is replayed alone (the draws of the ones before it are made and dropped). */

/* The heights of a replayed scene's grid, drawn from g node by node. */
typedef struct replay_grid {
    gsl_rng *g;
    double cell, slope, rough, holes;
    int steps;
} replay_grid;

static double replay_z(int i, int j, void *ctx)
{
    const replay_grid *q = ctx;
    (void)j;
    double z = 100.0 - q->slope * i * q->cell + q->rough * gsl_rng_uniform(q->g);
    if (q->steps && i % 7 == 3)
        z -= 3.0 * q->cell * gsl_rng_uniform(q->g);
    if (q->holes > 0 && gsl_rng_uniform(q->g) < q->holes)
        z = -9999;
    if (gsl_rng_uniform(q->g) < 0.1)
        z = floor(z); /* flat patches and shared heights */
    return z;
}

/* Scene `it` of search `seed`, trajectory k; mesh: the scene as a mesh, each cell split
 * along a diagonal that alternates with its parity (unlike a grid), nodata left open. */
void replay_scene(unsigned long seed, long it, long k, int mesh, replay *rp)
{
    gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(g, seed * 7919 + (unsigned long)it);
    int nx = 20 + (int)(gsl_rng_uniform(g) * 60), ny = 15 + (int)(gsl_rng_uniform(g) * 40);
    double cell = gsl_rng_uniform(g) < 0.5 ? 1.0 : (0.25 + 2.0 * gsl_rng_uniform(g));
    double slope = gsl_rng_uniform(g) * 1.6, rough = gsl_rng_uniform(g) * 2.0 * cell;
    double holes = gsl_rng_uniform(g) < 0.3 ? 0.02 : 0.0;
    int steps = gsl_rng_uniform(g) < 0.3;
    replay_grid q = {g, cell, slope, rough, holes, steps};
    char *txt = mesh ? mt_grid_stl_text(nx, ny, cell, 1000.0, 2000.0, 1, replay_z, &q)
                     : mt_grid_text(nx, ny, cell, 1000.0, 2000.0, replay_z, &q);
    ENSURE(txt != NULL);
    double e = gsl_rng_uniform(g), esd = gsl_rng_uniform(g) < 0.5 ? 0 : 0.3 * gsl_rng_uniform(g);
    if (gsl_rng_uniform(g) < 0.2)
        e = gsl_rng_uniform(g) < 0.5 ? 0.0 : 1.0;
    double mu = 2.0 * gsl_rng_uniform(g), mur = 0.5 * gsl_rng_uniform(g);
    if (gsl_rng_uniform(g) < 0.15)
        mu = 0.0;
    double musd = 0.2 * gsl_rng_uniform(g);
    rf_surface surf = {{e, esd}, {mu, musd}, {mur, 0.05 * gsl_rng_uniform(g)}};
    if (mesh)
        mt_mesh_text(&rp->t, "replay.stl", txt, surf);
    else
        mt_dem_text(&rp->t, "replay.asc", txt, surf);
    free(txt);
    for (long j = 0;; j++) {
        rf_rock_model md = gsl_rng_uniform(g) < 0.3 ? RF_MODEL_POINT : RF_MODEL_SPHERE;
        rf_contact_kind ck = gsl_rng_uniform(g) < 0.25 ? RF_CONTACT_CENTRE : RF_CONTACT_FULL;
        rp->sim = mt_sim(md, ck, 120.0);
        rp->sim.engine = gsl_rng_uniform(g) < 0.1 ? RF_ENGINE_FIXED_STEP : RF_ENGINE_EXACT;
        rp->sim.dt = 0.001 + 0.01 * gsl_rng_uniform(g);
        double mass = exp(log(1e5) * gsl_rng_uniform(g));
        rp->b = rf_body_make(mass, 2650.0, md);
        const rf_terrain *t = &rp->t;
        double x = t->xmin + (t->xmax - t->xmin) * (0.05 + 0.5 * gsl_rng_uniform(g));
        double y = t->ymin + (t->ymax - t->ymin) * (0.1 + 0.8 * gsl_rng_uniform(g));
        double z;
        if (rf_terrain_height(t, x, y, &z) < 0) {
            ENSURE(j != k);
            continue;
        }
        double lift = gsl_rng_uniform(g) < 0.3 ? 0.0 : 5.0 * gsl_rng_uniform(g);
        double vx = 10 * gsl_rng_uniform(g) - 2, vy = 6 * gsl_rng_uniform(g) - 3;
        double vz = gsl_rng_uniform(g) < 0.3 ? -20 * gsl_rng_uniform(g) : 0;
        if (j < k)
            continue;
        rp->s = mt_state(rf_v3(x, y, z + rf_body_contact_radius(&rp->b) * 1.0001 + lift),
                         rf_v3(vx, vy, vz));
        if (md == RF_MODEL_SPHERE && lift > 0)
            rp->s.p.z += 2.0 * rp->b.radius; /* well clear of the ground */
        rp->seed = (unsigned long)(it * 100000 + k + 1);
        break;
    }
    gsl_rng_free(g);
}

/* Runs the replay. */
void replay_run(replay *rp, double sample_spacing, mt_run *r)
{
    mt_simulate_opts(&rp->t, &rp->sim, &rp->b, &rp->s, rp->seed, sample_spacing, r);
}

/* The replayed rock does not end under the terrain. */
void ensure_ends_above(const replay *rp, const mt_run *r, unsigned long seed, long it,
                       long k)
{
    double zh;
    rf_vec3 end = r->rec.stop;
    if (rf_terrain_height(&rp->t, end.x, end.y, &zh) >= 0)
        ENSURE_MSG(end.z >= zh - 1e-6, "scene %lu/%ld/%ld: ends %.3g m under the terrain", seed, it,
                   k, zh - end.z);
}

/* The checks every replay ends with - no energy gained at an impact, not ending under
 * the terrain - and its clean-up. */
void replay_finish(replay *rp, mt_run *r, unsigned long seed, long it, long k)
{
    ENSURE_MSG(r->energy_gain_kj <= 1e-9 * (1.0 + r->rec.max_energy_kj),
               "scene %lu/%ld/%ld: energy gain", seed, it, k);
    ensure_ends_above(rp, r, seed, it, k);
    mt_run_free(r);
    rf_terrain_free(&rp->t);
}

/* Builds the replay, a rock of `model` in the exact engine. */
void replay_pick(unsigned long seed, long it, long k, rf_rock_model model, replay *rp)
{
    replay_scene(seed, it, k, 0, rp);
    ENSURE(rp->sim.model == model && rp->sim.engine == RF_ENGINE_EXACT);
}

/* replay_pick, and runs it into r. */
void replay_open(unsigned long seed, long it, long k, rf_rock_model model, replay *rp,
                 mt_run *r)
{
    replay_pick(seed, it, k, model, rp);
    replay_run(rp, 0.0, r);
}

/* A rock of the exact engine in the replay ends for `reason` within 2 000 events; the
 * run is left in r for more checks and replay_finish. */
void replay_ends_open(unsigned long seed, long it, long k, rf_rock_model model, int reason,
                      replay *rp, mt_run *r)
{
    replay_open(seed, it, k, model, rp, r);
    ENSURE_MSG((int)r->rec.reason == reason, "reason %d after %zu points", (int)r->rec.reason,
               r->npoints);
    ENSURE_MSG(r->npoints < 2000, "%zu points", r->npoints);
}

/* replay_ends_open, gaining no energy at an impact, and not under the terrain. */
void replay_ends(unsigned long seed, long it, long k, rf_rock_model model, int reason)
{
    replay rp;
    mt_run r;
    replay_ends_open(seed, it, k, model, reason, &rp, &r);
    replay_finish(&rp, &r, seed, it, k);
}

void replay_sphere_rests(unsigned long seed, long it, long k)
{
    replay_ends(seed, it, k, RF_MODEL_SPHERE, RF_END_REST);
}

void replay_point_rests(unsigned long seed, long it, long k)
{
    replay_ends(seed, it, k, RF_MODEL_POINT, RF_END_REST);
}

/* The most path points in a row within a nanosecond of the one before: 16 events
 * without progress in time (RF_STALL_EVENTS) is a stall, which the engine rescues. */
size_t longest_stall(const mt_run *r)
{
    size_t best = 0, run = 0;
    for (size_t i = 1; i < r->npoints; i++) {
        run = r->points[i].t_s - r->points[i - 1].t_s < 1e-9 ? run + 1 : 0;
        if (run > best)
            best = run;
    }
    return best;
}

/* Runs the replay: it rests, without a stall (the engine never had to rescue it)
 * unless `rescued`, gaining no energy at an impact, and not under the terrain. */
void replay_rests(replay *rp, unsigned long seed, long it, long k, int rescued)
{
    mt_run r;
    replay_run(rp, 0.0, &r);
    ENSURE_MSG(r.rec.reason == RF_END_REST, "scene %lu/%ld/%ld: reason %d after %zu points",
               seed, it, k, (int)r.rec.reason, r.npoints);
    size_t stall = longest_stall(&r);
    ENSURE_MSG(rescued || stall < RF_STALL_EVENTS, "scene %lu/%ld/%ld: %zu events in no time",
               seed, it, k, stall);
    replay_finish(rp, &r, seed, it, k);
}

/* As replay_sphere_rests (a centre-contact sphere), and without a stall. */
void replay_centre_rests_unstalled(unsigned long seed, long it, long k)
{
    replay rp;
    replay_scene(seed, it, k, 0, &rp);
    ENSURE(rp.sim.model == RF_MODEL_SPHERE && rp.sim.contact == RF_CONTACT_CENTRE &&
           rp.sim.engine == RF_ENGINE_EXACT);
    replay_rests(&rp, seed, it, k, 0);
}

/* The built replay's mechanical energy (kinetic and m g z) never rises along its path
 * after the start (where a centre may be put onto its face's offset plane) above the
 * least it has had, by more than 1e-9 m g r; it ends for `reason`. */
void replay_energy_stays_down(replay *rp, unsigned long seed, long it, long k, int reason)
{
    mt_run r;
    replay_run(rp, 0.0, &r);
    ENSURE(r.npoints > 2);
    double mgr = rp->b.mass * G * rp->b.radius, rise = mt_energy_rise(&r, rp->b.mass);
    ENSURE_MSG(rise <= 1e-9 * mgr, "scene %lu/%ld/%ld: energy rises by %.3g m g r", seed, it, k,
               rise / mgr);
    ENSURE_MSG((int)r.rec.reason == reason, "scene %lu/%ld/%ld: reason %d", seed, it, k,
               (int)r.rec.reason);
    replay_finish(rp, &r, seed, it, k);
}

/* replay_energy_stays_down for the replay as the scene has it. */
void replay_energy_never_rises(unsigned long seed, long it, long k, int reason)
{
    replay rp;
    replay_scene(seed, it, k, 0, &rp);
    replay_energy_stays_down(&rp, seed, it, k, reason);
}
