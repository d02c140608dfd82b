/* bench_load.c - the project loader on the inputs that once made it quadratic or
 * unbounded (`make bench-load`): 100 000 rocks and releases, a zone polygon of
 * 30 000 vertices over a 201 x 201 grid, and a YAML alias of a 30 000-point line
 * used by 1 000 measures.  Each is written to a scratch folder, loaded from its file,
 * and its wall-clock time and outcome printed; the tests count the work instead
 * (project_100000_rocks_and_releases_load_in_linear_work,
 * terrain_30000_vertex_zone_polygon_zones_as_the_plain_test,
 * yamldoc_alias_expansion_beyond_the_budget_refused). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/util.h"
#include "rockfall/project.h"

typedef struct text {
    char *s;
    size_t n, cap;
} text;

static void put(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text *t, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(t->s + t->n, t->cap - t->n, fmt, ap);
        va_end(ap);
        if (k >= 0 && (size_t)k < t->cap - t->n) {
            t->n += (size_t)k;
            return;
        }
        t->cap = 2 * t->cap + (size_t)k + 64;
        t->s = realloc(t->s, t->cap);
        if (!t->s) {
            perror("bench_load");
            exit(2);
        }
    }
}

static void write_file(const char *path, const text *t)
{
    FILE *f = fopen(path, "w");
    if (!f || fwrite(t->s, 1, t->n, f) != t->n || fclose(f)) {
        perror(path);
        exit(2);
    }
}

/* Loads path; prints its time and outcome. */
static void load(const char *what, const char *path)
{
    rf_project p;
    rf_error err;
    double t0 = rf_now_s();
    int rc = rf_project_load(path, &p, &err);
    double dt = rf_now_s() - t0;
    if (rc == 0) {
        printf("| %s | %.2f s | loaded: %zu rocks, %zu releases, %zu measures, %zu triangles |\n",
               what, dt, p.nrocks, p.nreleases, p.nmeasures, p.terrain.ntri);
        rf_project_free(&p);
    } else {
        printf("| %s | %.2f s | refused: %s |\n", what, dt, err.message);
    }
    fflush(stdout);
}

int main(void)
{
    char dir[] = "/tmp/rockfall-bench-load-XXXXXX", path[256];
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 2;
    }
    printf("| input | load time | outcome |\n|---|---:|---|\n");

    /* 100 000 rocks and releases, each release naming a rock from the other end */
    enum { NITEMS = 100000 };
    text t = {0};
    put(&t, "name: many\nterrain:\n  profile: {points: [[0, 100], [100, 0]], width: 100}\n"
            "rocks:\n");
    for (int i = 0; i < NITEMS; i++)
        put(&t, "  - {name: r%d, mass: 100}\n", i);
    put(&t, "releases:\n");
    for (int i = 0; i < NITEMS; i++)
        put(&t, "  - {name: a%d, point: [5, 35], rock: r%d}\n", i, NITEMS - 1 - i);
    snprintf(path, sizeof path, "%s/many.yaml", dir);
    write_file(path, &t);
    load("100 000 rocks and 100 000 releases", path);

    /* a 30 000-vertex zone polygon over a 201 x 201 grid (80 000 triangles) */
    enum { SIDE = 201, NPOLY = 30000 };
    t.n = 0;
    put(&t, "ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize 0.5\nNODATA_value -9999\n",
        SIDE, SIDE);
    for (int j = 0; j < SIDE; j++)
        for (int i = 0; i < SIDE; i++)
            put(&t, "%d%c", 100 - j / 2 + (i + j) % 7, i + 1 == SIDE ? '\n' : ' ');
    snprintf(path, sizeof path, "%s/zones.asc", dir);
    write_file(path, &t);
    t.n = 0;
    put(&t, "name: zones\nterrain:\n  dem: zones.asc\n  zones:\n    - name: wavy\n"
            "      class: C\n      polygon: [");
    for (int k = 0; k < NPOLY; k++) {
        double a = 2.0 * 3.14159265358979 * k / NPOLY, r = 40.0 + 8.0 * sin(50.0 * a);
        put(&t, "%s[%.6f, %.6f]", k ? ", " : "", 50.0 + r * cos(a), 50.0 + r * sin(a));
    }
    put(&t, "]\nrocks:\n  - {name: r, mass: 100}\nreleases:\n  - {name: A, point: [50, 90], "
            "rock: r}\n");
    snprintf(path, sizeof path, "%s/zones.yaml", dir);
    write_file(path, &t);
    load("a zone polygon of 30 000 vertices", path);

    /* one 30 000-point line, aliased by 1 000 measures */
    enum { NLINE = 30000, NMEAS = 1000 };
    t.n = 0;
    put(&t, "name: alias\nterrain:\n  profile: {points: [[0, 100], [100, 0]], width: 100}\n"
            "rocks:\n  - {name: r, mass: 100}\nreleases:\n  - {name: A, point: [5, 35], rock: r}\n"
            "measures:\n  - {name: m0, kind: control, line: &long [");
    for (int k = 0; k < NLINE; k++)
        put(&t, "%s[%.4f, %.4f]", k ? ", " : "", 100.0 * k / NLINE, 20.0 + (k % 2) * 0.01);
    put(&t, "]}\n");
    for (int k = 1; k < NMEAS; k++)
        put(&t, "  - {name: m%d, kind: control, line: *long}\n", k);
    snprintf(path, sizeof path, "%s/alias.yaml", dir);
    write_file(path, &t);
    load("a 30 000-point line aliased by 1 000 measures", path);

    free(t.s);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : 2;
}
