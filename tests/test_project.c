/* test_project.c - the project-file loader: example projects, the bad-file corpus,
 * defaults, a fully specified project read back. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "corpus_test_util.h"
#include "rockfall/project.h"
#include "test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define DATA "tests/data/project/"

static int load_ok(const char *path, rf_project *p)
{
    rf_error err = {{0}};
    if (rf_project_load(path, p, &err) == 0)
        return 1;
    rf_error_print(&err, stderr);
    return 0;
}

static const rf_measure *measure_named(const rf_project *p, const char *name)
{
    for (size_t i = 0; i < p->nmeasures; i++)
        if (!strcmp(p->measures[i].name, name))
            return &p->measures[i];
    return NULL;
}

/* ---- the example projects ------------------------------------------------------ */

TEST(project_examples_load)
{
    glob_t g;
    int rc = glob("projects/*/*.yaml", 0, NULL, &g);
    ENSURE_MSG(rc == 0 && g.gl_pathc > 0, "no project found under projects/*/*.yaml");
    for (size_t i = 0; i < g.gl_pathc; i++) {
        rf_project p;
        ENSURE_MSG(load_ok(g.gl_pathv[i], &p), "%s does not load", g.gl_pathv[i]);
        ENSURE(p.nrocks >= 1 && p.nreleases >= 1 && p.terrain.ntri > 0);
        rf_project_free(&p);
    }
    globfree(&g);
}

/* ---- the bad-file corpus ------------------------------------------------------- */

/* A file of tests/bad: the error may be in a file it includes (named in its text). */
static int check_bad_project(const ct_expect *e)
{
    rf_project p;
    rf_error err = {{0}};
    if (rf_project_load(e->path, &p, &err) == 0) {
        fprintf(stderr, "    %s: loaded, expected an error\n", e->path);
        rf_project_free(&p);
        return 0;
    }
    const char *base = strrchr(err.file, '/');
    base = base ? base + 1 : err.file;
    int right_file = !strcmp(err.file, e->path) || (base[0] && strstr(e->text, base) &&
                                                    !strstr(base, ".yaml"));
    int ok = ct_error_as_expected(e, &err, right_file);
    /* The project is left empty after a failure. */
    if (p.name || p.rocks || p.releases || p.terrain.tri || p.yaml_text) {
        fprintf(stderr, "    %s: project not emptied after an error\n", e->path);
        ok = 0;
    }
    return ok;
}

TEST(project_bad_files)
{
    ct_bad_corpus("tests/bad", "bad", 30, check_bad_project);
}

TEST(project_missing_file)
{
    rf_project p;
    rf_error err = {{0}};
    ENSURE(rf_project_load(DATA "no_such_project.yaml", &p, &err) != 0);
    ENSURE(!strcmp(err.file, DATA "no_such_project.yaml"));
    ENSURE(strstr(err.message, "cannot open"));
    ENSURE(p.name == NULL && p.path == NULL);
}

/* A writer for the named pipe at path: a child process that opens it, writes text and
 * ends, once something opens the pipe to read.  Reading it without one would wait for
 * ever; with it, a loader that reads the pipe reads text. */
static pid_t pipe_writer(const char *path, const char *text)
{
    pid_t pid = fork();
    if (pid == 0) {
        FILE *f = fopen(path, "w");
        if (f) {
            fputs(text, f);
            fclose(f);
        }
        _exit(0);
    }
    return pid;
}

/* A terrain or rule file that is a named pipe opens, but is no file to read (a first
 * open to check it would take what the writer sends): refused at its key without
 * opening it, with the project left empty.  The pipe's writer sends a valid grid or
 * rule file, so that a loader that opens it fails this test instead of waiting. */
TEST(project_referenced_pipe_is_refused)
{
    static const char *const cases[2] = {
        "name: p\nterrain:\n  dem: fifo\nrocks: [{name: r, mass: 1}]\n"
        "releases: [{name: A, point: [5, 35], rock: r}]\n",
        "name: p\nterrain: {dem: g.asc}\nrocks: [{name: r, mass: 1}]\n"
        "releases: [{name: A, point: [5, 35], rock: r}]\nrules: fifo\n",
    };
    char *grid = rf_test_read_text(DATA "grid5.asc");
    ENSURE(grid);
    rf_test_write("g.asc", grid);
    const char *fifo = rf_test_path("fifo");
    ENSURE(mkfifo(fifo, 0600) == 0);
    for (int k = 0; k < 2; k++) {
        const char *path = rf_test_write("project.yaml", cases[k]);
        pid_t writer = pipe_writer(fifo, k == 0 ? grid : "rules: []\n");
        ENSURE(writer > 0);
        rf_project p;
        rf_error err = {{0}};
        int rc = rf_project_load(path, &p, &err);
        kill(writer, SIGKILL);
        waitpid(writer, NULL, 0);
        ENSURE_MSG(rc != 0, "case %d: the pipe was read", k);
        fprintf(stderr, "    %s:%d:%d: %s\n", err.file, err.line, err.column, err.message);
        ENSURE(!strcmp(err.file, path) && err.line == 3 + 2 * k && err.column == 8);
        ENSURE(strstr(err.message, "not a regular file") && strstr(err.message, "fifo"));
        ENSURE(p.name == NULL && p.terrain.tri == NULL);
    }
    free(grid);
}

/* ---- defaults ------------------------------------------------------------------ */

TEST(project_defaults)
{
    rf_project p;
    ENSURE(load_ok(DATA "defaults.yaml", &p));
    ENSURE(!strcmp(p.name, "defaults"));
    ENSURE(p.seed == 1);
    ENSURE(!strcmp(p.path, DATA "defaults.yaml"));
    ENSURE(!strcmp(p.dir, "tests/data/project"));
    ENSURE(p.yaml_text && strstr(p.yaml_text, "The smallest valid project"));
    ENSURE(p.terrain_spec.source == RF_TERRAIN_DEM);
    ENSURE(p.terrain_spec.nfiles == 1 && !strcmp(p.terrain_spec.files[0], DATA "grid5.asc"));
    ENSURE(p.terrain_spec.up == 'z' && p.terrain_spec.nzones == 0);
    const rf_surface *s = &p.terrain_spec.surface;
    ENSURE(s->restitution.mean == 0.3 && s->restitution.sd == 0.0);
    ENSURE(s->friction.mean == 0.3 && s->friction.sd == 0.0);
    ENSURE(s->rolling.mean == 0.3 && s->rolling.sd == 0.0);
    ENSURE(p.nforests == 0 && p.forests == NULL);
    ENSURE(p.nmeasures == 0 && p.measures == NULL);
    ENSURE(p.nrocks == 1);
    ENSURE(p.rocks[0].mass == 100.0 && p.rocks[0].density == 2650.0);
    ENSURE(p.rocks[0].action_level == 2);
    ENSURE_REL(p.rocks[0].radius, cbrt(3.0 * 100.0 / (4.0 * M_PI * 2650.0)), 1e-15);
    ENSURE(p.nreleases == 1);
    const rf_release *r = &p.releases[0];
    ENSURE(r->x == 5.0 && r->y == 35.0 && r->rock == 0 && r->count == 1);
    ENSURE(r->height == 0.0 && r->jitter == 0.0);
    ENSURE(r->velocity.x == 0.0 && r->velocity.y == 0.0 && r->velocity.z == 0.0);
    /* Cell (0, 3) of the grid: SW 130, SE 125, NE 135, NW 140; (5, 35) is on the
     * SW-NE diagonal, z = 130 - 5 * 0.5 + 10 * 0.5. */
    ENSURE_REL(r->z, 132.5, 1e-12);
    ENSURE(p.sim.model == RF_MODEL_SPHERE && p.sim.engine == RF_ENGINE_EXACT);
    ENSURE(p.sim.dt == 0.001 && p.sim.contact == RF_CONTACT_FULL);
    ENSURE(p.sim.stop_speed == 0.1 && p.sim.max_time == 300.0 && p.sim.paths == 10);
    ENSURE(p.hazard_cell == 5.0);
    ENSURE(p.rules_path == NULL);
    ENSURE(p.terrain.ntri > 0);
    rf_project_free(&p);
    ENSURE(p.name == NULL && p.rocks == NULL);
}

TEST(project_barrier_and_rolling_defaults)
{
    char dir[512], grid[600];
    snprintf(dir, sizeof dir, "%s", rf_test_tmpdir());
    char cwd[256];
    ENSURE(getcwd(cwd, sizeof cwd));
    snprintf(grid, sizeof grid, "%s/" DATA "grid5.asc", cwd);
    char text[2048];
    snprintf(text, sizeof text,
             "name: tmp\n"
             "seed: 18446744073\n"
             "terrain:\n"
             "  dem: %s\n"
             "  surface: {friction: {mean: 0.4, sd: 0.02}}\n"
             "  zones:\n"
             "    - {name: talus, polygon: [[0, 0], [10, 0], [10, 10]], class: C}\n"
             "    - {name: plain, polygon: [[0, 0], [10, 0], [10, 10]]}\n"
             "rocks: [{name: r, mass: 2.385}]\n"
             "releases: [{name: A, point: [5, 35], rock: r}]\n"
             "measures:\n"
             "  - {name: B, kind: barrier, line: [[0, 5], [40, 5]], height: 3, mel: 2385}\n"
             "  - {name: B2, kind: barrier, line: [[0, 6], [40, 6]], height: 3, mel: 2385,\n"
             "     capacity: {restorability: 500}}\n"
             "  - {name: road, kind: control, line: [[0, 1], [40, 1]], behaviour: collect}\n",
             grid);
    rf_project p;
    ENSURE(load_ok(rf_test_write("p.yaml", text), &p));
    /* An absolute terrain path stays as it is. */
    ENSURE(!strcmp(p.terrain_spec.files[0], grid));
    ENSURE(!strcmp(p.dir, dir));
    ENSURE(p.seed == 18446744073ull);
    /* rolling follows the friction of each surface when no rolling is given. */
    const rf_surface *s = &p.terrain_spec.surface;
    ENSURE(s->rolling.mean == 0.4 && s->rolling.sd == 0.02);
    rf_dist c = rf_table2_friction_dist('C');
    const rf_zone_spec *talus = &p.terrain_spec.zones[0], *plain = &p.terrain_spec.zones[1];
    ENSURE(!strcmp(talus->name, "talus") && talus->npoly == 3 && talus->file == NULL);
    ENSURE(talus->surface.friction.mean == c.mean && talus->surface.friction.sd == c.sd);
    ENSURE(talus->surface.rolling.mean == c.mean && talus->surface.rolling.sd == c.sd);
    ENSURE(talus->surface.restitution.mean == 0.3);
    ENSURE(plain->surface.friction.mean == 0.4 && plain->surface.rolling.mean == 0.4);
    const rf_measure *b = measure_named(&p, "B");
    ENSURE(b && b->kind == RF_BARRIER && b->behaviour == RF_STOP);
    ENSURE(b->importance == RF_IMPORTANT);
    ENSURE(b->mel == 2385.0 && b->sel == 2385.0 / 3.0);
    ENSURE(b->sel_given == 0); /* stored as sel_source 'default: MEL/3' */
    ENSURE(b->capacity[RF_SERVICEABILITY] == 2385.0 / 3.0);
    ENSURE(b->capacity[RF_ULTIMATE] == 2385.0);
    ENSURE(b->capacity[RF_RESTORABILITY] < 0 && b->capacity[RF_NEAR_COLLAPSE] < 0);
    /* without 'sel', the SEL of MEL / 3 is the rule file's to set (docs/rules.md): a
     * restorability capacity below it is no error */
    const rf_measure *b2 = measure_named(&p, "B2");
    ENSURE(b2 && b2->capacity[RF_RESTORABILITY] == 500.0 && b2->sel == 2385.0 / 3.0);
    const rf_measure *road = measure_named(&p, "road");
    ENSURE(road && road->kind == RF_CONTROL && road->behaviour == RF_COLLECT);
    ENSURE(road->height == 0.0);
    for (int k = 0; k < RF_N_LIMIT_STATES; k++)
        ENSURE(road->capacity[k] < 0);
    rf_project_free(&p);
}

/* roughness and the impact law: defaults (0, Eq. 8); a zone keeps the surface's values
 * it does not give, takes its own, and may switch the law either way. */
TEST(project_roughness_and_impact_law)
{
    static const char text[] =
        "name: r\nterrain:\n  profile: {points: [[0, 100], [100, 0]], width: 50}\n"
        "  surface: {roughness: 0.2, impact: rt, tangential: {mean: 0.8, sd: 0.05}}\n"
        "  zones:\n"
        "    - {name: a, polygon: [[0, 0], [10, 0], [10, 10]]}\n"
        "    - {name: b, polygon: [[0, 0], [10, 0], [10, 10]], roughness: 0, impact: eq8}\n"
        "    - {name: c, polygon: [[0, 0], [10, 0], [10, 10]], tangential: 0.6}\n"
        "    - {name: d, polygon: [[0, 0], [10, 0], [10, 10]], impact: rt}\n"
        "rocks:\n  - {name: r, mass: 100}\n"
        "releases:\n  - {name: A, point: [5, 25], rock: r}\n";
    rf_project p;
    rf_error err = {{0}};
    ENSURE_MSG(rf_project_load_from_memory(text, strlen(text), "mem/p.yaml", &p, &err) == 0,
               "%s", err.message);
    const rf_surface *s = &p.terrain_spec.surface;
    ENSURE(s->roughness == 0.2 && s->law == RF_IMPACT_RT);
    ENSURE(s->tangential.mean == 0.8 && s->tangential.sd == 0.05);
    const rf_zone_spec *z = p.terrain_spec.zones;
    ENSURE(z[0].surface.roughness == 0.2 && z[0].surface.law == RF_IMPACT_RT &&
           z[0].surface.tangential.mean == 0.8);
    ENSURE(z[1].surface.roughness == 0.0 && z[1].surface.law == RF_IMPACT_EQ8);
    ENSURE(z[2].surface.law == RF_IMPACT_RT && z[2].surface.tangential.mean == 0.6 &&
           z[2].surface.tangential.sd == 0.0);
    ENSURE(z[3].surface.law == RF_IMPACT_RT && z[3].surface.tangential.mean == 0.8);
    rf_project_free(&p);
    static const char plain[] =
        "name: r\nterrain:\n  profile: {points: [[0, 100], [100, 0]], width: 50}\n"
        "rocks:\n  - {name: r, mass: 100}\n"
        "releases:\n  - {name: A, point: [5, 25], rock: r}\n";
    ENSURE(rf_project_load_from_memory(plain, strlen(plain), "mem/p.yaml", &p, &err) == 0);
    ENSURE(p.terrain_spec.surface.roughness == 0.0);
    ENSURE(p.terrain_spec.surface.law == RF_IMPACT_EQ8);
    rf_project_free(&p);
}

/* ---- a fully specified project --------------------------------------------------- */

TEST(project_full_read_back)
{
    rf_project p;
    ENSURE(load_ok(DATA "full.yaml", &p));
    ENSURE(!strcmp(p.name, "full-project") && p.seed == 2009);
    ENSURE(!strcmp(p.rules_path, DATA "rules.yaml"));

    const rf_terrain_spec *t = &p.terrain_spec;
    ENSURE(t->source == RF_TERRAIN_DEM && !strcmp(t->files[0], DATA "grid5.asc"));
    ENSURE(t->surface.restitution.mean == 0.15 && t->surface.restitution.sd == 0.05);
    ENSURE(t->surface.friction.mean == 0.32 && t->surface.friction.sd == 0.04);
    ENSURE(t->surface.rolling.mean == 0.12 && t->surface.rolling.sd == 0.0);
    ENSURE(t->nzones == 2);
    const rf_zone_spec *z0 = &t->zones[0], *z1 = &t->zones[1];
    ENSURE(!strcmp(z0->name, "talus") && z0->npoly == 4);
    ENSURE(z0->poly_xy[2] == 20.0 && z0->poly_xy[3] == 0.0 && z0->poly_xy[7] == 20.0);
    rf_dist d = rf_table2_friction_dist('D');
    ENSURE(z0->surface.friction.mean == d.mean && z0->surface.friction.sd == d.sd);
    ENSURE(z0->surface.restitution.mean == 0.15 && z0->surface.restitution.sd == 0.05);
    ENSURE(z0->surface.rolling.mean == 0.12); /* the terrain's explicit rolling */
    ENSURE(!strcmp(z1->name, "rockface") && z1->npoly == 3);
    ENSURE(z1->surface.restitution.mean == 0.45 && z1->surface.restitution.sd == 0.0);
    ENSURE(z1->surface.friction.mean == 0.55 && z1->surface.friction.sd == 0.07);
    ENSURE(z1->surface.rolling.mean == 0.2 && z1->surface.rolling.sd == 0.0);

    ENSURE(p.nforests == 2);
    const rf_forest *f = &p.forests[0];
    ENSURE(!strcmp(f->name, "forest") && f->polygon.n == 3 && f->polygon.xy[5] == 15.0);
    ENSURE(f->density == 0.012 && f->height.mean == 5.5 && f->height.sd == 1.25);
    ENSURE(f->diameter == 0.23);
    ENSURE(f->restitution.mean == 0.22 && f->restitution.sd == 0.03);
    ENSURE(f->friction.mean == 0.35 && f->friction.sd == 0.06);
    f = &p.forests[1];
    ENSURE(!strcmp(f->name, "scrub") && f->polygon.n == 0 && f->polygon.xy == NULL);
    ENSURE(f->density == 0.5 && f->height.mean == 1.5 && f->height.sd == 0.0);
    ENSURE(f->restitution.mean == 0.2 && f->restitution.sd == 0.0);
    ENSURE(f->friction.mean == 0.3 && f->friction.sd == 0.0);

    ENSURE(p.nrocks == 2);
    ENSURE(!strcmp(p.rocks[0].name, "r4500") && p.rocks[0].mass == 4500.0);
    ENSURE(p.rocks[0].density == 2700.0 && p.rocks[0].action_level == 3);
    ENSURE_REL(p.rocks[0].radius, cbrt(3.0 * 4500.0 / (4.0 * M_PI * 2700.0)), 1e-15);
    ENSURE(!strcmp(p.rocks[1].name, "small") && p.rocks[1].mass == 12.5);

    ENSURE(p.nreleases == 2);
    const rf_release *r = &p.releases[0];
    ENSURE(!strcmp(r->name, "C") && r->x == 5.5 && r->y == 35.25 && r->rock == 0);
    ENSURE(r->count == 100 && r->height == 1.5 && r->jitter == 0.75);
    ENSURE(r->velocity.x == 1.25 && r->velocity.y == -0.5 && r->velocity.z == 2.0);
    /* Below the diagonal of cell (0, 3): z = 130 - 5 * 0.55 + 10 * 0.525. */
    ENSURE_REL(r->z, 132.5, 1e-12);
    r = &p.releases[1];
    ENSURE(!strcmp(r->name, "D") && r->rock == 1 && r->count == 1);
    ENSURE_REL(r->z, 87.5, 1e-12);

    ENSURE(p.nmeasures == 5);
    const rf_measure *m = measure_named(&p, "road");
    ENSURE(m && m->kind == RF_CONTROL && m->importance == RF_USUAL);
    ENSURE(m->behaviour == RF_COLLECT && m->line.n == 2 && m->line.xy[2] == 40.0);
    m = measure_named(&p, "E1");
    ENSURE(m && m->kind == RF_EMBANKMENT && m->line.n == 3 && m->line.xy[3] == 12.0);
    ENSURE(m->height == 6.0 && m->importance == RF_MOST_IMPORTANT);
    ENSURE(m->behaviour == RF_COLLECT);
    ENSURE(m->capacity[RF_SERVICEABILITY] == 3000.0 && m->capacity[RF_RESTORABILITY] == 6000.0);
    ENSURE(m->capacity[RF_ULTIMATE] == 9000.0 && m->capacity[RF_NEAR_COLLAPSE] == 12000.0);
    m = measure_named(&p, "B1");
    ENSURE(m && m->kind == RF_BARRIER && m->height == 5.0 && m->mel == 3000.0);
    ENSURE(m->sel == 1000.0 && m->behaviour == RF_STOP && m->importance == RF_IMPORTANT);
    ENSURE(m->sel_given == 0); /* 1000 = MEL / 3, the default */
    m = measure_named(&p, "B2");
    ENSURE(m && m->mel == 2000.0 && m->sel == 1000.0 && m->sel_given == 1);
    ENSURE(m->capacity[RF_SERVICEABILITY] == 1000.0 && m->capacity[RF_RESTORABILITY] == 1500.0);
    ENSURE(m->capacity[RF_ULTIMATE] == 2000.0 && m->capacity[RF_NEAR_COLLAPSE] < 0);
    m = measure_named(&p, "E2");
    ENSURE(m && m->height == 3.5 && m->capacity[RF_ULTIMATE] == 5000.0);
    ENSURE(m->capacity[RF_SERVICEABILITY] < 0 && m->capacity[RF_RESTORABILITY] < 0);
    ENSURE(m->capacity[RF_NEAR_COLLAPSE] < 0 && m->mel < 0 && m->sel < 0);

    ENSURE(p.sim.model == RF_MODEL_POINT && p.sim.engine == RF_ENGINE_FIXED_STEP);
    ENSURE(p.sim.dt == 0.002 && p.sim.contact == RF_CONTACT_CENTRE);
    ENSURE(p.sim.stop_speed == 0.05 && p.sim.max_time == 120.0 && p.sim.paths == 25);
    ENSURE(p.hazard_cell == 2.5);
    rf_project_free(&p);
}

TEST(project_mesh_and_profile)
{
    rf_project p;
    ENSURE(load_ok(DATA "mesh.yaml", &p));
    const rf_terrain_spec *t = &p.terrain_spec;
    ENSURE(t->source == RF_TERRAIN_MESH && t->nfiles == 2 && t->up == 'z');
    ENSURE(!strcmp(t->files[0], DATA "upper.obj") && !strcmp(t->files[1], DATA "lower.stl"));
    ENSURE(t->nzones == 1 && !strcmp(t->zones[0].file, DATA "lower.stl"));
    ENSURE(t->zones[0].poly_xy == NULL);
    ENSURE(t->zones[0].surface.restitution.mean == 0.5);
    ENSURE(t->zones[0].surface.friction.mean == 0.4 && t->zones[0].surface.rolling.mean == 0.4);
    ENSURE_REL(p.releases[0].z, 25.0, 1e-12);  /* z = 30 - x / 2 */
    ENSURE_REL(p.releases[1].z, 12.5, 1e-12);  /* z = 20 - 0.75 (x - 20) */
    rf_project_free(&p);

    ENSURE(load_ok(DATA "mesh_yup.yaml", &p));
    ENSURE(p.terrain_spec.up == 'y' && p.terrain_spec.nfiles == 1);
    ENSURE_REL(p.releases[0].z, 25.0, 1e-12);
    rf_project_free(&p);

    ENSURE(load_ok(DATA "profile.yaml", &p));
    t = &p.terrain_spec;
    ENSURE(t->source == RF_TERRAIN_PROFILE && t->nprofile == 3 && t->width == 20.0);
    ENSURE(t->profile[0] == 0.0 && t->profile[1] == 100.0 && t->profile[4] == 80.0);
    rf_dist b = rf_table2_friction_dist('B');
    ENSURE(t->surface.friction.mean == b.mean && t->surface.rolling.mean == b.mean);
    ENSURE_REL(p.releases[0].z, 80.0, 1e-12);
    rf_project_free(&p);
}

/* Paths in a project are relative to the project file, not to the working directory. */
TEST(project_paths_relative_to_file)
{
    char mk[700], text[1024];
    snprintf(mk, sizeof mk, "mkdir -p '%s'", rf_test_path("terrain"));
    ENSURE(system(mk) == 0);
    char *grid = rf_test_read_text(DATA "grid5.asc");
    ENSURE(grid);
    rf_test_write("terrain/g.asc", grid);
    free(grid);
    rf_test_write("rules.yaml", "rules: []\n");
    snprintf(text, sizeof text,
             "name: rel\nterrain: {dem: terrain/g.asc}\nrocks: [{name: r, mass: 1}]\n"
             "releases: [{name: A, point: [35, 5], rock: r}]\nrules: rules.yaml\n");
    rf_project p;
    ENSURE(load_ok(rf_test_write("project.yaml", text), &p));
    ENSURE(!strcmp(p.terrain_spec.files[0], rf_test_path("terrain/g.asc")));
    ENSURE(!strcmp(p.rules_path, rf_test_path("rules.yaml")));
    ENSURE(!strcmp(p.yaml_text, text));
    rf_project_free(&p);
}

TEST(project_enum_names)
{
    ENSURE(!strcmp(rf_measure_kind_name(RF_BARRIER), "barrier"));
    ENSURE(!strcmp(rf_measure_kind_name(RF_EMBANKMENT), "embankment"));
    ENSURE(!strcmp(rf_measure_kind_name(RF_CONTROL), "control"));
    ENSURE(!strcmp(rf_importance_name(RF_MOST_IMPORTANT), "most_important"));
    ENSURE(!strcmp(rf_importance_name(RF_USUAL), "usual"));
    ENSURE(!strcmp(rf_behaviour_name(RF_STOP), "stop"));
    ENSURE(!strcmp(rf_behaviour_name(RF_COLLECT), "collect"));
    ENSURE(!strcmp(rf_limit_state_name(RF_SERVICEABILITY), "serviceability"));
    ENSURE(!strcmp(rf_limit_state_name(RF_NEAR_COLLAPSE), "near_collapse"));
    ENSURE(!strcmp(rf_limit_state_name(RF_COLLAPSE), "collapse"));
}

/* ---- loads linear in the input ------------------------------------------------- */

#include "base/names.h"

/* A project of n rocks and n releases on a profile, each release naming its own rock. */
static const char *many_items_project(size_t n)
{
    size_t cap = 128 + n * 96, used = 0;
    char *text = malloc(cap);
    ENSURE(text);
    used += (size_t)snprintf(text, cap,
                             "name: many\nterrain:\n  profile: {points: [[0, 100], [100, 0]], "
                             "width: 100}\nrocks:\n");
    for (size_t i = 0; i < n; i++)
        used += (size_t)snprintf(text + used, cap - used, "  - {name: r%zu, mass: 100}\n", i);
    used += (size_t)snprintf(text + used, cap - used, "releases:\n");
    for (size_t i = 0; i < n; i++)
        used += (size_t)snprintf(text + used, cap - used,
                                 "  - {name: a%zu, point: [5, 35], rock: r%zu}\n", i, n - 1 - i);
    const char *path = rf_test_write("many.yaml", text);
    free(text);
    return path;
}

/* 100 000 rocks took 22 s: every name was compared with every earlier one, and every
 * release's rock was looked for among all rocks.  The names are now found in a hash:
 * the slots looked at stay a few per name (counted, not timed). */
TEST(project_100000_rocks_and_releases_load_in_linear_work)
{
    const size_t n = 100000;
    const char *path = many_items_project(n);
    rf_project p;
    unsigned long long before = rf_names_probes();
    ENSURE(load_ok(path, &p));
    unsigned long long probes = rf_names_probes() - before;
    ENSURE(p.nrocks == n && p.nreleases == n);
    ENSURE(p.releases[0].rock == (int)(n - 1) && p.releases[n - 1].rock == 0);
    /* 3 n lookups: each rock's and each release's name added, each release's rock found */
    ENSURE_MSG(probes <= 3 * 3 * n, "%llu slots looked at for %zu names", probes, 3 * n);
    rf_project_free(&p);
}

/* The index itself: a duplicate is found, and a name's lookup looks at few slots even as
 * the table grows from its smallest size. */
TEST(names_index_finds_duplicates_in_few_probes)
{
    rf_names h;
    ENSURE(rf_names_init(&h, 0) == 0);
    enum { N = 50000 };
    static char keys[N][16];
    int oom;
    unsigned long long before = rf_names_probes();
    for (size_t i = 0; i < N; i++) {
        snprintf(keys[i], sizeof keys[i], "k%zu", i);
        ENSURE(rf_names_add(&h, keys[i], i, &oom) == RF_NAMES_ABSENT && !oom);
    }
    ENSURE(rf_names_add(&h, "k123", 7, &oom) == 123);
    ENSURE(rf_names_find(&h, "k49999") == 49999);
    ENSURE(rf_names_find(&h, "k50000") == RF_NAMES_ABSENT);
    ENSURE(h.n == N);
    unsigned long long probes = rf_names_probes() - before;
    ENSURE_MSG(probes <= 8ull * N, "%llu probes for %d names", probes, N);
    rf_names_free(&h);
}

/* The loader from memory (for fuzzing and embedding) reads what the file loader reads;
 * the buffer needs no NUL and is bounded as a file is. */
TEST(project_load_from_memory_reads_as_the_file_does)
{
    static const char text[] = "name: mem\nterrain:\n  profile: {points: [[0, 100], [100, 0]], "
                               "width: 50}\nrocks:\n  - {name: r, mass: 100}\n"
                               "releases:\n  - {name: A, point: [5, 25], rock: r, count: 3}\n"
                               "TRAILING GARBAGE NOT PART OF THE BUFFER";
    size_t len = strstr(text, "TRAILING") - text;
    rf_project p;
    rf_error err = {{0}};
    ENSURE_MSG(rf_project_load_from_memory(text, len, "mem/p.yaml", &p, &err) == 0, "%s",
               err.message);
    ENSURE(!strcmp(p.name, "mem") && p.nreleases == 1 && p.releases[0].count == 3);
    ENSURE(!strcmp(p.dir, "mem") && strlen(p.yaml_text) == len);
    rf_project_free(&p);
    ENSURE(rf_project_load_from_memory(text, 20, "mem/p.yaml", &p, &err) != 0);
    ENSURE(!strcmp(err.file, "mem/p.yaml"));
    ENSURE(rf_project_load_from_memory(text, ((size_t)16 << 20) + 1, "big.yaml", &p, &err) != 0);
    ENSURE_MSG(strstr(err.message, "at most 16777216"), "%s", err.message);
}

/* ---- releases as a planner draws them ------------------------------------------ */

/* An area is read, triangulated (a concave L of six vertices into four triangles of
 * 972 m^2 in all) and placed at its centroid; a cells mask gives its non-zero cells in
 * row order from the south; masses are a log-normal or a list (its mean the rock's). */
TEST(project_area_cells_and_mass_kinds_read)
{
    rf_project p;
    ENSURE(load_ok(DATA "release_area.yaml", &p));
    const rf_release *a = &p.releases[0];
    ENSURE(a->source == RF_SOURCE_AREA && a->narea == 6 && a->ntri == 4);
    ENSURE(fabs(a->area_cum[3] - 972.0) < 1e-9);
    /* centroid of the L: (3 squares of 18 m) */
    ENSURE(fabs(a->x - (11.0 * 2 + 29.0) / 3.0) < 1e-9 && fabs(a->y - (11.0 * 2 + 29.0) / 3.0) < 1e-9);
    ENSURE(p.releases[1].source == RF_SOURCE_POINT && rf_release_trajectories(&p.releases[1]) == 3);
    ENSURE(p.rocks[0].mass_kind == RF_MASS_LOGNORMAL && p.rocks[0].mass == 1000.0 &&
           p.rocks[0].mass_sd == 500.0);
    ENSURE(p.rocks[1].mass_kind == RF_MASS_LIST && p.rocks[1].nmasses == 4 &&
           p.rocks[1].mass == 450.0);
    rf_project_free(&p);
    ENSURE(load_ok(DATA "release_cells.yaml", &p));
    const rf_release *c = &p.releases[0];
    ENSURE(c->source == RF_SOURCE_CELLS && c->ncells == 3 && c->cell == 10.0);
    ENSURE(c->cells[0] == 10 && c->cells[1] == 10 && c->cells[2] == 30 && c->cells[3] == 20 &&
           c->cells[4] == 10 && c->cells[5] == 30);
    ENSURE(rf_release_trajectories(c) == 9);
    rf_project_free(&p);
}
