/* test_report.c - `rockfall report`: index.html and its SVG figures from a small
 * database written by hand through the store API. */
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>

#include "report/report.h"
#include "rockfall/empirical.h"
#include "rockfall/montecarlo.h"
#include "rockfall/records.h"
#include "results/run_view.h"
#include "results/store.h"
#include "db_test_util.h"
#include "svg_test_util.h"

/* ---- a small slope, built by hand ------------------------------------------------ */

/* A 100 m high section falling along +x onto a flat strip, 80 m wide along y. */
static const char PROJECT_YAML[] =
    "name: report-test\n"
    "seed: 7\n"
    "terrain:\n"
    "  profile: {points: [[0, 100], [100, 0], [130, 0]], width: 80}\n"
    "  surface: {restitution: {mean: 0.15, sd: 0.05}, friction: {mean: 0.3, sd: 0.05}}\n"
    "rocks:\n"
    "  - {name: r4500, mass: 4500}\n"
    "releases:\n"
    "  - {name: C, point: [5, 30], rock: r4500, count: 5}\n"
    "  - {name: D, point: [5, 50], rock: r4500, count: 5}\n"
    "measures:\n"
    "  - {name: road, kind: control, line: [[105, 0], [105, 80]]}\n";

typedef struct test_project {
    rf_project p;
    rf_rock rocks[1];
    rf_release releases[4];
    rf_measure measures[3];
    double lines[3][4];
    rf_project loaded; /* the project file, loaded for its terrain when it exists */
    int has_loaded;
} test_project;

enum { M_ROAD, M_E1, M_B1 };

/* The project as its rows; with_road 0 leaves out the control line. */
static void make_project(test_project *t, const char *project_path, int with_road)
{
    memset(t, 0, sizeof *t);
    t->p.name = "slope <test> & 'co'";
    t->p.path = (char *)project_path;
    t->p.yaml_text = (char *)PROJECT_YAML;
    t->p.seed = 7;
    t->rocks[0] = (rf_rock){.name = "r4500", .mass = 4500.0, .density = 2650.0,
                            .action_level = 2, .radius = 0.7403};
    t->p.rocks = t->rocks;
    t->p.nrocks = 1;
    t->releases[0] = (rf_release){.name = "C", .x = 5.0, .y = 30.0, .z = 95.0, .count = 5};
    t->releases[1] = (rf_release){.name = "D", .x = 5.0, .y = 50.0, .z = 95.0, .count = 5};
    t->p.releases = t->releases;
    t->p.nreleases = 2;
    static const double xy[3][4] = {
        {105.0, 0.0, 105.0, 80.0}, {95.0, 0.0, 95.0, 80.0}, {60.0, 10.0, 60.0, 70.0}};
    memcpy(t->lines, xy, sizeof xy);
    size_t n = 0;
    if (with_road) {
        t->measures[n] = (rf_measure){.name = "road", .kind = RF_CONTROL, .importance = RF_IMPORTANT,
                                      .behaviour = RF_COLLECT, .capacity = {-1, -1, -1, -1}};
        t->measures[n++].line = (rf_polyline){t->lines[0], 2};
    }
    t->measures[n] = (rf_measure){.name = "E1", .kind = RF_EMBANKMENT, .height = 6.0,
                                  .importance = RF_IMPORTANT, .behaviour = RF_COLLECT,
                                  .capacity = {3000, 6000, 9000, -1}};
    t->measures[n++].line = (rf_polyline){t->lines[1], 2};
    t->measures[n] = (rf_measure){.name = "B<1>&\"x\"", .kind = RF_BARRIER, .height = 5.0,
                                  .importance = RF_USUAL, .behaviour = RF_COLLECT, .mel = 3000,
                                  .sel = 1000, .capacity = {1000, -1, 3000, -1}};
    t->measures[n++].line = (rf_polyline){t->lines[2], 2};
    t->p.measures = t->measures;
    t->p.nmeasures = n;
}

static char *read_text(const char *path)
{
    char *s = rf_test_read_text(path);
    ENSURE_MSG(s, "cannot read %s", path);
    return s;
}

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

static size_t count(const char *text, const char *needle)
{
    size_t n = 0;
    for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

/* Writes one complete run: 5 trajectories per release.  Each crosses the control
 * line (when there is one) at y = release y + 2.5 idx, and the embankment with an
 * energy from 500 to 8500 kJ; every other one crosses the barrier. */
static int64_t write_run(rf_store *s, const test_project *t, int with_paths, int with_cells)
{
    rf_error err = {0};
    int64_t run = 0;
    ENSURE_MSG(rf_store_run_begin(s, &t->p, 10, &run, &err) == 0, "%s", err.message);
    ENSURE(rf_store_batch_begin(s, &err) == 0);
    int road = t->p.measures[0].kind == RF_CONTROL;
    int e1 = road ? M_E1 : M_E1 - 1, b1 = e1 + 1;
    for (size_t r = 0; r < 2; r++)
        for (long i = 0; i < 5; i++) {
            double y = t->releases[r].y + 2.5 * (double)i;
            rf_trajectory_record tr = {.stop = {118.0, y, 0.74}, .reason = RF_END_REST,
                                       .duration_s = 9.5, .path_length_m = 150.0,
                                       .max_energy_kj = 4000.0 + 500.0 * (double)i,
                                       .n_impacts = 7};
            int64_t tid = 0;
            ENSURE_MSG(rf_store_add_trajectory(s, r, i, &tr, &tid, &err) == 0, "%s",
                       err.message);
            if (with_paths)
                for (long k = 0; k <= 12; k++) {
                    double x = 5.0 + 9.4 * (double)k;
                    rf_path_point pt = {.t_s = 0.75 * (double)k, .p = {x, y, 100.0 - x},
                                        .speed_ms = 2.0 * (double)k, .energy_kj = 10.0 * (double)k};
                    ENSURE(rf_store_add_path_point(s, tid, k, &pt, &err) == 0);
                }
            double e = 500.0 + 1000.0 * (double)(i + 5 * (long)r) * 0.8;
            rf_interception_record ic = {.measure = e1, .t_s = 8.0, .p = {95.0, y, 5.7},
                                         .speed_ms = 30.0, .energy_kj = e,
                                         .energy_trans_kj = e, .passing_height_m = 0.74,
                                         .outcome = i == 4 ? RF_OUT_OVERTOPPED : RF_OUT_PASSED};
            int64_t iid = 0;
            ENSURE(rf_store_add_interception(s, tid, &ic, &iid, &err) == 0);
            if (i % 2 == 0 && b1 < (int)t->p.nmeasures) {
                ic.measure = b1;
                ic.p = (rf_vec3){60.0, y, 40.74};
                ic.t_s = 5.0;
                ic.energy_kj = 700.0 + 400.0 * (double)i;
                ENSURE(rf_store_add_interception(s, tid, &ic, &iid, &err) == 0);
            }
            if (road) {
                ic = (rf_interception_record){.measure = M_ROAD, .t_s = 9.0, .p = {105.0, y, 0.74},
                                              .speed_ms = 12.5 + (double)i + 5.0 * (double)r,
                                              .energy_kj = 350.0, .passing_height_m = 0.74,
                                              .outcome = RF_OUT_PASSED};
                ENSURE(rf_store_add_interception(s, tid, &ic, &iid, &err) == 0);
                /* a later second crossing does not count as an arrival */
                ic.t_s = 9.5;
                ic.p.y = 0.5;
                ENSURE(rf_store_add_interception(s, tid, &ic, &iid, &err) == 0);
            }
        }
    if (with_cells)
        for (long c = 0; c < 6; c++) {
            static const double energy[6] = {250.0, 999.0, 1000.0, 3000.0, 5999.0, 7250.0};
            rf_hazard_cell_record hc = {.ix = c, .iy = 3, .x = 2.5 + 5.0 * (double)c,
                                        .y = 17.5, .passes = c + 1,
                                        .reach_probability = 0.1 * (double)(c + 1),
                                        .energy_max_kj = energy[c],
                                        .energy_p95_kj = 0.9 * energy[c], .height_p95_m = 1.25};
            ENSURE(rf_store_add_hazard_cell(s, &hc, &err) == 0);
        }
    ENSURE(rf_store_batch_commit(s, &err) == 0);
    ENSURE_MSG(rf_store_run_finish(s, "complete", 10, &err) == 0, "%s", err.message);
    return run;
}

static rf_store *open_store(const char *path)
{
    rf_store *s = NULL;
    rf_error err = {0};
    ENSURE_MSG(rf_store_open(path, &s, &err) == 0, "%s", err.message);
    return s;
}

static void report_ok(rf_store *s, int64_t run, const char *dir)
{
    rf_error err = {0};
    int rc = rf_report_write(rf_store_db(s), run, dir, &err);
    ENSURE_MSG(rc == 0, "rf_report_write: %s: %s", err.file, err.message);
}

/* The project (make_project) and a store in the file `db` of the test's directory. */
static rf_store *project_store(test_project *t, const char *project_path, int with_road,
                               const char *db)
{
    make_project(t, project_path, with_road);
    rf_error err = {0};
    if (rf_project_load(project_path, &t->loaded, &err) == 0) {
        t->has_loaded = 1;
        t->p.terrain = t->loaded.terrain;
        t->p.terrain_spec = t->loaded.terrain_spec;
        t->p.hazard_cell = t->loaded.hazard_cell;
    }
    return open_store(rf_test_path(db));
}

/* Writes the report of the run into dir; returns its index.html (malloc'd). */
static char *report_html(rf_store *s, int64_t run, const char *dir)
{
    report_ok(s, run, dir);
    char path[700];
    snprintf(path, sizeof path, "%s/index.html", dir);
    return read_text(path);
}

/* Every SVG is one <svg> element, and index.html shows it. */
static char *svg_ok(const char *dir, const char *name, const char *html)
{
    char path[700], ref[200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    ENSURE_MSG(exists(path), "%s missing", path);
    char *svg = read_text(path);
    ENSURE_MSG(strncmp(svg, "<svg ", 5) == 0, "%s does not start with <svg", name);
    size_t n = strlen(svg);
    ENSURE_MSG(n > 7 && strcmp(svg + n - 7, "</svg>\n") == 0, "%s does not end with </svg>", name);
    ENSURE_MSG(count(svg, "<svg") == 1 && count(svg, "</svg>") == 1, "%s", name);
    ENSURE_MSG(count(svg, "<text") == count(svg, "</text>"), "%s: unbalanced <text>", name);
    ENSURE_MSG(!strstr(svg, "nan") && !strstr(svg, "inf\""), "%s has a NaN or inf", name);
    snprintf(ref, sizeof ref, "<img src=\"%s\"", name);
    ENSURE_MSG(strstr(html, ref), "index.html does not show %s", name);
    return svg;
}

/* ---- tests ------------------------------------------------------------------------- */

TEST(report_polyline_station)
{
    const double xy[] = {0.0, 0.0, 10.0, 0.0, 10.0, 10.0};
    double d, nx, ny;
    ENSURE_SMALL(rf_polyline_station(xy, 3, 12.0, 5.0, &d, &nx, &ny) - 15.0, 1e-12);
    ENSURE_SMALL(d - 2.0, 1e-12);
    ENSURE(nx == 10.0 && ny == 5.0);
    ENSURE_SMALL(rf_polyline_station(xy, 3, -3.0, 4.0, &d, NULL, NULL), 1e-12);
    ENSURE_SMALL(d - 5.0, 1e-12);
    ENSURE_SMALL(rf_polyline_station(xy, 3, 4.25, -2.385, &d, NULL, NULL) - 4.25, 1e-12);
    ENSURE_SMALL(rf_polyline_station(xy, 3, 30.0, 30.0, NULL, NULL, NULL) - 20.0, 1e-12);
    ENSURE_SMALL(rf_polyline_length(xy, 3) - 20.0, 1e-12);
}

TEST(report_full_run_writes_every_figure)
{
    const char *yaml = rf_test_write("slope.yaml", PROJECT_YAML);
    test_project t;
    rf_store *s = project_store(&t, yaml, 1, "full.db");
    int64_t run = write_run(s, &t, 1, 1);
    /* rows of `rockfall check` */
    char sql[1024];
    snprintf(sql, sizeof sql,
             "INSERT INTO classifications SELECT i.id, 2, 'important',"
             " CASE WHEN i.energy_kj <= 3000 THEN 'serviceability' ELSE 'restorability' END,"
             " 'restorability', 1 FROM interceptions i JOIN measures m ON m.id = i.measure_id"
             " WHERE m.name = 'E1';"
             "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed)"
             " SELECT %lld, id, 'serviceability share', 0.25, 0.9, 0 FROM measures"
             " WHERE name = 'E1';"
             "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed)"
             " VALUES (%lld, NULL, 'all measures <pass>', 1, 1, 1);",
             (long long)run, (long long)run);
    ENSURE_MSG(sqlite3_exec(rf_store_db(s), sql, NULL, NULL, NULL) == SQLITE_OK, "%s",
               sqlite3_errmsg(rf_store_db(s)));

    const char *dir = rf_test_path("report");
    char *html = report_html(s, run, dir);
    ENSURE(strncmp(html, "<!doctype html>", 15) == 0);
    ENSURE(strstr(html, "</body></html>\n"));

    /* plan view: one polyline per sampled path, labels of releases and measures,
     * contours from the reloaded project */
    char *plan = svg_ok(dir, "plan.svg", html);
    ENSURE_MSG(count(plan, "class=\"path\"") == 10, "%zu paths", count(plan, "class=\"path\""));
    ENSURE(strstr(plan, ">road</text>") && strstr(plan, ">E1</text>"));
    ENSURE(strstr(plan, ">B&lt;1&gt;&amp;&quot;x&quot;</text>"));
    ENSURE(strstr(plan, ">C</text>") && strstr(plan, ">D</text>"));
    ENSURE(strstr(plan, "contours every 5 m"));
    ENSURE(!strstr(plan, "no terrain contours"));
    ENSURE(count(plan, "<circle") == 10);
    ENSURE(strstr(plan, ">N</text>"));

    /* the road: arrival position and velocity */
    char *pos = svg_ok(dir, "road-0-position.svg", html);
    ENSURE(strstr(pos, "Fig. 10a") && strstr(pos, "attainment range from C"));
    char *vel = svg_ok(dir, "road-0-velocity.svg", html);
    ENSURE(strstr(vel, "Fig. 10b") && strstr(vel, "Eq. 1 from C"));

    /* the empirical crosscheck: H = 95 m, L = 100 m */
    double theta = atan2(95.0, 100.0);
    char want[64];
    snprintf(want, sizeof want, "<td>%.1f</td>", rf_empirical_velocity(95.0, theta, 0.35));
    ENSURE_MSG(strstr(html, want), "no %s", want);
    snprintf(want, sizeof want, "<td>%.1f</td>", rf_empirical_velocity(95.0, theta, 0.30));
    ENSURE_MSG(strstr(html, want), "no %s", want);
    ENSURE(strstr(html, "<td>200</td>")); /* 2 L tan 45 deg */
    ENSURE(strstr(html, "<td>10.0</td>")); /* spread of each release's arrivals */
    ENSURE(strstr(html, "10 of 10 trajectories (100.0 %) crossed this line"));
    ENSURE(strstr(html, "mean velocity of 17.0 m/s, at most 21.5 m/s"));

    /* hazard map: classes 1000, 3000, 6000 kJ, one rectangle per cell */
    char *haz = svg_ok(dir, "hazard-energy.svg", html);
    ENSURE(strstr(haz, "Fig. 12"));
    ENSURE(strstr(haz, "3000") && strstr(haz, "6000") && strstr(haz, "1000"));
    ENSURE(count(haz, "class=\"cell\"") == 6);
    ENSURE(count(haz, "class=\"class\"") == 4);
    for (int c = 0; c < 4; c++) /* one cell of each class is coloured as the legend */
        ENSURE(count(haz, (const char *[]){"fill=\"#fecc5c\"", "fill=\"#fd8d3c\"",
                                           "fill=\"#e31a1c\"", "fill=\"#800026\""}[c]) >= 2);
    ENSURE(strstr(html, "3 reach 3000 kJ or more, 1 reach 6000 kJ or more"));
    free(svg_ok(dir, "hazard-reach.svg", html));

    /* beside it E95, passing height p95 and passages, each cell in the colour of its
     * class (the counts hold the legend's swatch too) */
    static const struct {
        const char *file, *title;
        const char *fills[5];
        size_t want[5];
    } maps[3] = {
        /* E95 = 0.9 of the largest: 225, 899.1, 900, 2700, 5399.1, 6525 kJ */
        {"hazard-energy-p95.svg", "E95: 95th percentile of the kinetic energy per 5 m cell",
         {"#fecc5c", "#fd8d3c", "#e31a1c", "#800026", NULL}, {4, 2, 2, 2, 0}},
        /* 1.25 m everywhere: the class 1 - 2 m */
        {"hazard-height-p95.svg", "Passing height: 95th percentile per 5 m cell",
         {"#edf8e9", "#bae4b3", "#74c476", "#31a354", "#006d2c"}, {1, 7, 1, 1, 1}},
        /* 1 to 6 passes: classes < 2, 2 - 5, 5 - 20 */
        {"hazard-passages.svg", "Passages: trajectories that crossed each 5 m cell",
         {"#f2f0f7", "#cbc9e2", "#9e9ac8", "#756bb1", "#54278f"}, {2, 4, 3, 1, 1}},
    };
    for (size_t k = 0; k < 3; k++) {
        char *m = svg_ok(dir, maps[k].file, html);
        ENSURE_MSG(strstr(m, maps[k].title), "%s: no title", maps[k].file);
        ENSURE_MSG(count(m, "class=\"cell\"") == 6, "%s", maps[k].file);
        for (size_t c = 0; c < 5 && maps[k].fills[c]; c++) {
            char fill[40];
            snprintf(fill, sizeof fill, "fill=\"%s\"", maps[k].fills[c]);
            ENSURE_MSG(count(m, fill) == maps[k].want[c], "%s: %zu of %s, not %zu", maps[k].file,
                       count(m, fill), fill, maps[k].want[c]);
        }
        if (k == 2) /* passages are whole numbers from 1: classes as such */
            for (size_t c = 0; c < 5; c++)
                ENSURE_MSG(strstr(m, (const char *[]){">1</text>", ">2 - 4</text>",
                                                      ">5 - 19</text>", ">20 - 99</text>",
                                                      ">&gt;= 100</text>"}[c]),
                           "passages legend class %zu", c);
        free(m);
    }
    ENSURE(strstr(html, "E95: the 95th percentile (nearest rank) of the kinetic energy"));

    /* energy at the measures against their capacities */
    char *e1 = svg_ok(dir, "measure-1-energy.svg", html);
    ENSURE(count(e1, "class=\"capacity\"") == 3);
    ENSURE(strstr(e1, "serviceability 3000 kJ") && strstr(e1, "restorability 6000 kJ") &&
           strstr(e1, "ultimate 9000 kJ"));
    char *b1 = svg_ok(dir, "measure-2-energy.svg", html);
    ENSURE(count(b1, "class=\"capacity\"") == 2);
    ENSURE(strstr(b1, "SEL 1000 kJ") && strstr(b1, "MEL 3000 kJ"));
    ENSURE(strstr(b1, "Energy at B&lt;1&gt;&amp;&quot;x&quot; (barrier)"));
    /* the control line is no structure: no energy or height figure, no row in the
     * structures' tables, a row of its own among the control lines */
    char path[700];
    snprintf(path, sizeof path, "%s/measure-0-energy.svg", dir);
    ENSURE(!exists(path) && !strstr(html, "measure-0-"));
    ENSURE(!strstr(html, "<td class=\"t\">control</td>"));
    ENSURE(!strstr(html, "Energy at road") && !strstr(html, "<h3>road (control)</h3>"));
    const char *ctl = strstr(html, "<table class=\"control\">");
    ENSURE(ctl);
    /* 10 trajectories, 100 % of them, 20 crossings (each crosses twice) */
    ENSURE_MSG(strstr(ctl, "<td class=\"t\">road</td><td>10</td><td>100.0</td><td>20</td>"),
               "%.600s", ctl);
    const char *structures = strstr(html, "<table class=\"measures\">");
    ENSURE(structures && structures < ctl);
    /* the structures' numbers fit the page: two tables of at most 10 columns */
    size_t ntables = 0;
    for (const char *tb = structures; tb; tb = strstr(tb + 1, "<table class=\"measures\">")) {
        const char *row_end = strstr(tb, "</tr>");
        size_t cols = 0;
        for (const char *th = strstr(tb, "<th>"); th && th < row_end; th = strstr(th + 1, "<th>"))
            cols++;
        ENSURE_MSG(cols >= 9 && cols <= 10, "a structures' table of %zu columns", cols);
        ntables++;
    }
    ENSURE(ntables == 2);
    ENSURE(strstr(structures, "<td class=\"t\">E1</td><td class=\"t\">embankment</td>"));

    /* the passing height at each structure against its height, and the 95th
     * percentile of the crossings' heights (all 0.74 m) */
    char *e1h = svg_ok(dir, "measure-1-height.svg", html);
    ENSURE(strstr(e1h, "Passing height at E1 (embankment) against its height"));
    ENSURE(count(e1h, "class=\"structure-height\"") == 1);
    ENSURE(strstr(e1h, ">height 6.0 m</text>") && strstr(e1h, ">h95 0.74 m</text>"));
    ENSURE_MSG(count(e1h, "fill=\"#9ecae1\"") == 2, "%zu", count(e1h, "fill=\"#9ecae1\""));
    char *b1h = svg_ok(dir, "measure-2-height.svg", html);
    ENSURE(strstr(b1h, ">height 5.0 m</text>"));
    ENSURE(strstr(html, "Passing height of the 10 of 10 crossings of E1 that have one, by "
                        "outcome, with its height 6.0 m (dashed) and their 95th percentile "
                        "(dotted)"));
    ENSURE(strstr(html, "Energy of the rocks crossing E1 by outcome, with its 3 capacities"));
    ENSURE(strstr(html, "crossing B&lt;1&gt;&amp;&quot;x&quot; by outcome, with its 2 "
                        "capacities"));

    /* the plan's legend sets the control line apart from the structures */
    ENSURE(strstr(plan, ">Structures</text>") && strstr(plan, ">Control lines</text>"));
    ENSURE(strstr(plan, ">E1 (embankment)</text>") && !strstr(plan, "road (control)"));
    ENSURE(strstr(plan, ">x (m)</text>") && !strstr(plan, "\xe2\x88\x92")); /* no origin */

    /* captions say what is drawn: 10 sampled paths and end points; 2 attainment ranges;
     * 2 releases, 2 Eq. 1 lines each */
    ENSURE(strstr(html, "the sampled paths of 10 of the 10 trajectories, coloured by release, "
                        "the end points of 10,"));
    ENSURE(strstr(html, "with the empirical attainment range of 2 releases"));
    ENSURE(strstr(html, "with 4 Eq. 1 velocities of the releases"));
    ENSURE(count(vel, "stroke-dasharray=\"8 4\"") == 2 && count(vel, "stroke-dasharray=\"3 3\"") == 2);

    /* classifications and checks */
    ENSURE(strstr(html, "limit state reached"));
    ENSURE(strstr(html, "<td class=\"t\">serviceability</td><td>4</td><td>40.0</td>"));
    ENSURE(strstr(html, "<td class=\"fail\">FAIL</td>"));
    ENSURE(strstr(html, "<td class=\"t\">all measures &lt;pass&gt;</td>"));
    ENSURE(strstr(html, "Design checks: 1 passed, 1 failed."));

    /* text from the database is escaped */
    ENSURE(strstr(html, "<h1>slope &lt;test&gt; &amp; &#39;co&#39;</h1>"));
    ENSURE(!strstr(html, "<test>") && !strstr(html, "B<1>"));
    ENSURE(!strstr(html, "nan") && !strstr(html, "stores no terrain"));

    /* deterministic, and from the database alone: a second report is the same, byte
     * for byte, after the project file (which holds the terrain) is changed to another
     * slope, and a third after it is deleted */
    rf_test_write("slope.yaml", "name: other\n"
                                "terrain:\n"
                                "  profile: {points: [[0, 10], [50, 0], [130, 0]], width: 30}\n");
    const char *dirs[2] = {"again", "gone"};
    for (int d = 0; d < 2; d++) {
        if (d == 1)
            ENSURE(remove(rf_test_path("slope.yaml")) == 0);
        char dir2[600];
        snprintf(dir2, sizeof dir2, "%.500s", rf_test_path(dirs[d]));
        report_ok(s, run, dir2);
        const char *files[] = {"index.html", "plan.svg", "hazard-energy.svg",
                               "road-0-position.svg", "road-0-velocity.svg",
                               "measure-1-energy.svg"};
        for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
            char a[700], b[700];
            snprintf(a, sizeof a, "%s/%s", dir, files[k]);
            snprintf(b, sizeof b, "%s/%s", dir2, files[k]);
            char *ta = read_text(a), *tb = read_text(b);
            ENSURE_MSG(strcmp(ta, tb) == 0, "%s differs (%s)", files[k], dirs[d]);
            free(ta);
            free(tb);
        }
    }
    free(plan);
    free(pos);
    free(vel);
    free(haz);
    free(e1);
    free(b1);
    free(e1h);
    free(b1h);
    free(html);
    rf_store_close(s);
    rf_project_free(&t.loaded);
}

TEST(report_without_road_paths_cells_or_project)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 0, "bare.db");
    int64_t run = write_run(s, &t, 0, 0);
    const char *dir = rf_test_path("bare/deeper/report");
    char *html = report_html(s, run, dir);
    ENSURE(strstr(html, "no control line"));
    ENSURE(strstr(html, "stores no terrain"));
    ENSURE(strstr(html, "/nonexistent/slope.yaml"));
    ENSURE(strstr(html, "No sampled paths"));
    ENSURE(strstr(html, "no hazard cells"));
    ENSURE(!strstr(html, "road-"));
    char path[700];
    snprintf(path, sizeof path, "%s/road-0-position.svg", dir);
    ENSURE(!exists(path));
    char *plan = svg_ok(dir, "plan.svg", html);
    ENSURE(count(plan, "class=\"path\"") == 0);
    ENSURE(count(plan, "<circle") == 10);
    ENSURE(strstr(plan, "no terrain contours"));
    ENSURE(strstr(plan, ">E1</text>"));
    char *e1 = svg_ok(dir, "measure-0-energy.svg", html);
    ENSURE(count(e1, "class=\"capacity\"") == 3);
    ENSURE(strstr(html, "No classifications stored"));
    ENSURE(strstr(html, "No design checks stored yet"));
    free(plan);
    free(e1);
    free(html);
    rf_store_close(s);
}

TEST(report_missing_run_and_bad_folder_are_errors)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 1, "err.db");
    int64_t run = write_run(s, &t, 1, 1);
    rf_error err = {0};
    const char *dir = rf_test_path("missing");
    ENSURE(rf_report_write(rf_store_db(s), run + 41, dir, &err) != 0);
    ENSURE_MSG(strstr(err.message, "no run"), "%s", err.message);
    ENSURE(!exists(dir));

    const char *file = rf_test_write("a-file", "not a folder\n");
    char sub[700];
    snprintf(sub, sizeof sub, "%s/report", file);
    memset(&err, 0, sizeof err);
    ENSURE(rf_report_write(rf_store_db(s), run, sub, &err) != 0);
    ENSURE_MSG(strstr(err.file, "a-file"), "%s: %s", err.file, err.message);
    rf_store_close(s);
}

/* An empty run (no trajectories at all) still gives a report. */
TEST(report_of_an_empty_run)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 1, "empty.db");
    rf_error err = {0};
    int64_t run = 0;
    ENSURE(rf_store_run_begin(s, &t.p, 0, &run, &err) == 0);
    ENSURE(rf_store_run_finish(s, "complete", 0, &err) == 0);
    const char *dir = rf_test_path("empty");
    char *html = report_html(s, run, dir);
    ENSURE(strstr(html, "0 of 0 trajectories"));
    ENSURE(strstr(html, "No rock reached this line"));
    free(svg_ok(dir, "plan.svg", html));
    free(html);
    rf_store_close(s);
}

/* With more releases than Fig. 10b labels Eq. 1 lines for, the figure draws none and
 * its caption says so, and where the velocities are instead. */
TEST(report_captions_say_what_is_drawn)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 1, "captions.db");
    t.releases[2] = (rf_release){.name = "E", .x = 5.0, .y = 60.0, .z = 95.0, .count = 5};
    t.releases[3] = (rf_release){.name = "F", .x = 5.0, .y = 70.0, .z = 95.0, .count = 5};
    t.p.nreleases = 4;
    int64_t run = write_run(s, &t, 0, 1);
    const char *dir = rf_test_path("captions");
    char *html = report_html(s, run, dir);
    ENSURE(strstr(html, "Fig. 10b: velocity of the rocks crossing road, by release; the Eq. 1 "
                        "velocities of the 4 releases are not drawn (more than 3): they are in "
                        "the crosscheck table below"));
    ENSURE(!strstr(html, "Eq. 1 velocities of the releases (long dashes"));
    char *vel = svg_ok(dir, "road-0-velocity.svg", html);
    ENSURE(!strstr(vel, "Eq. 1 from"));
    ENSURE(strstr(html, "<td class=\"t\">F</td>")); /* the crosscheck has every release */
    ENSURE(strstr(html, "the sampled paths of 0 of the 10 trajectories"));
    ENSURE(!strstr(html, "over the terrain contours</fig")); /* no terrain stored */
    free(vel);
    free(html);
    rf_store_close(s);
}

/* The test's slope (PROJECT_YAML) as a DEM in LV95: 100 m falling along +x over 100 m
 * onto a flat strip, 130 m by 80 m in 5 m cells, its lower left corner at
 * (2 600 000, 1 200 000); the releases and measures shifted with it. */
static const char *lv95_project(void)
{
    char dem[4096] = "ncols 27\nnrows 17\nxllcorner 2600000\nyllcorner 1200000\ncellsize 5\n"
                     "NODATA_value -9999\n";
    for (int j = 0; j < 17; j++) {
        for (int i = 0; i < 27; i++) {
            char v[16];
            snprintf(v, sizeof v, "%s%d", i ? " " : "", i < 20 ? 100 - 5 * i : 0);
            strcat(dem, v);
        }
        strcat(dem, "\n");
    }
    rf_test_write("lv95.asc", dem);
    return rf_test_write(
        "lv95.yaml",
        "name: lv95\n"
        "seed: 7\n"
        "terrain:\n"
        "  dem: lv95.asc\n"
        "  surface: {restitution: {mean: 0.15, sd: 0.05}, friction: {mean: 0.3, sd: 0.05}}\n"
        "rocks:\n"
        "  - {name: r4500, mass: 4500}\n"
        "releases:\n"
        "  - {name: C, point: [2600005, 1200030], rock: r4500, count: 4}\n"
        "  - {name: D, point: [2600005, 1200050], rock: r4500, count: 4}\n"
        "measures:\n"
        "  - {name: E1, kind: embankment, line: [[2600095, 1200000], [2600095, 1200080]],\n"
        "     height: 6, capacity: {serviceability: 3000, restorability: 6000}}\n"
        "  - {name: road, kind: control, line: [[2600105, 1200000], [2600105, 1200080]]}\n"
        "simulation: {paths: 8}\n"
        "hazard: {cell: 5.0}\n");
}

/* The pixel position of the release marker of colour `fill` (its apex is 8 px above
 * the release). */
static void release_marker(const char *svg, const char *fill, double *px, double *py)
{
    char key[80];
    snprintf(key, sizeof key, "fill=\"%s\" stroke=\"black\"", fill);
    const char *p = strstr(svg, key);
    ENSURE_MSG(p, "no release marker %s", fill);
    while (p > svg && strncmp(p, "<path d=\"M", 10))
        p--;
    ENSURE(sscanf(p, "<path d=\"M%lf %lf", px, py) == 2);
    *py += 8.0;
}

/* The data coordinate (from the axis's origin) at pixel px of an axis, from its first
 * two tick labels. */
static double tick_value_at(const svg_tick *t, size_t n, int y, double px)
{
    ENSURE(n >= 2);
    double a = y ? t[0].y - 4.0 : t[0].x, b = y ? t[1].y - 4.0 : t[1].x;
    double va = atof(t[0].text), vb = atof(t[1].text);
    return va + (px - a) * (vb - va) / (b - a);
}

/* A run on a terrain in national coordinates (LV95): every plan-like figure labels
 * its axes from the stated origin 2 600 000 / 1 200 000, in labels that do not overlap,
 * and a release drawn at (2 600 005, 1 200 030) reads as (5, 30) against them. */
TEST(report_on_national_coordinates_states_its_origin)
{
    const char *yaml = lv95_project();
    rf_project p;
    rf_error err = {0};
    ENSURE_MSG(rf_project_load(yaml, &p, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
    rf_store *s = open_store(rf_test_path("lv95.db"));
    rf_run_options o = {.threads = 1};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    const char *dir = rf_test_path("lv95-report");
    char *html = report_html(s, sum.run_id, dir);
    static const char *const figures[] = {"plan.svg", "hazard-energy.svg",
                                          "hazard-energy-p95.svg", "hazard-height-p95.svg",
                                          "hazard-passages.svg", "hazard-reach.svg"};
    for (size_t k = 0; k < sizeof figures / sizeof *figures; k++) {
        char *svg = svg_ok(dir, figures[k], html);
        ENSURE_MSG(strstr(svg, ">x \xe2\x88\x92 2 600 000 (m)</text>") &&
                       strstr(svg, ">y \xe2\x88\x92 1 200 000 (m)</text>"),
                   "%s states no origin", figures[k]);
        size_t nx = svgt_x_ticks_apart(svg, 0.0, 5);
        svg_tick tx[64], ty[64];
        ENSURE(svgt_ticks(svg, "xtick", tx, 64) == nx);
        size_t ny = svgt_ticks(svg, "ytick", ty, 64);
        for (size_t i = 0; i < nx; i++)
            ENSURE_MSG(strlen(tx[i].text) <= 3, "%s: x label %s", figures[k], tx[i].text);
        for (size_t i = 0; i < ny; i++)
            ENSURE_MSG(strlen(ty[i].text) <= 3, "%s: y label %s", figures[k], ty[i].text);
        for (size_t i = 1; i < ny; i++) /* y labels, one above the other, apart */
            ENSURE(ty[i - 1].lo - ty[i].hi >= 0.0);
        double px, py;
        release_marker(svg, "#1f77b4", &px, &py);
        /* the contours run along y: their labels sit halfway up the plan (20 - 60 m of
         * about 0 - 80), not on its lower edge */
        size_t nlabels = 0;
        for (const char *c = strstr(svg, "fill=\"#6b5a47\""); c;
             c = strstr(c + 1, "fill=\"#6b5a47\"")) {
            const char *el = c;
            while (el > svg && strncmp(el, "<text ", 6))
                el--;
            double ly;
            ENSURE(sscanf(el, "<text x=\"%*f\" y=\"%lf\"", &ly) == 1);
            double v = tick_value_at(ty, ny, 1, ly - 4.0);
            ENSURE_MSG(v > 20.0 && v < 60.0, "%s: a contour label at y %.1f", figures[k], v);
            nlabels++;
        }
        ENSURE(nlabels >= 3 || k > 0); /* the plan labels its bold contours */
        ENSURE_MSG(fabs(tick_value_at(tx, nx, 0, px) - 5.0) < 0.2, "%s: C at x %.2f", figures[k],
                   tick_value_at(tx, nx, 0, px));
        ENSURE_MSG(fabs(tick_value_at(ty, ny, 1, py) - 30.0) < 0.2, "%s: C at y %.2f",
                   figures[k], tick_value_at(ty, ny, 1, py));
        free(svg);
    }
    /* the histograms keep their own numbers: energies from 0 have no origin */
    char *e1 = svg_ok(dir, "measure-0-energy.svg", html);
    ENSURE(!strstr(e1, "\xe2\x88\x92"));
    svgt_x_ticks_apart(e1, 0.0, 3);
    free(e1);
    free(html);
    rf_store_close(s);
    rf_project_free(&p);
}

/* Two layout variants side by side: each run's verdict from its stored checks, every
 * structure's crossings and percentiles with "not in this run" where a run lacks it,
 * the arrivals at the road, one plan view each; the same runs compared again give the
 * same page. */
TEST(report_compares_layout_variants)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 1, "variants.db");
    int64_t a = write_run(s, &t, 1, 1);
    t.p.name = "without B1";
    t.p.nmeasures = 2; /* road and E1 */
    int64_t b = write_run(s, &t, 1, 0);
    char sql[1024];
    snprintf(sql, sizeof sql,
             "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed)"
             " VALUES (%lld, NULL, 'layout_serviceability_share', 0.5, 0.9, 0);"
             "INSERT INTO checks (run_id, measure_id, rule, value, threshold, passed, on_failure)"
             " VALUES (%lld, NULL, 'layout_serviceability_share', 0.95, 0.9, 1, 'fail'),"
             " (%lld, NULL, 'trajectories_max_time', 0.2, 0.0, 0, 'inconclusive');",
             (long long)a, (long long)b, (long long)b);
    sqlite3 *db = rf_store_db(s);
    ENSURE_MSG(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK, "%s", sqlite3_errmsg(db));
    const char *dir = rf_test_path("variants");
    int64_t runs[2] = {a, b};
    rf_error err = {0};
    ENSURE_MSG(rf_report_compare(db, runs, 2, dir, &err) == 0, "%s: %s", err.file, err.message);
    char path[700];
    snprintf(path, sizeof path, "%s/index.html", dir);
    char *html = read_text(path);
    /* one column per run, headed by its project and id */
    char head[200];
    snprintf(head, sizeof head, "<th>slope &lt;test&gt; &amp; &#39;co&#39;<br>run %lld</th>"
                                "<th>without B1<br>run %lld</th>", (long long)a, (long long)b);
    ENSURE_MSG(strstr(html, head), "no %s", head);
    ENSURE(strstr(html, "<td class=\"verdict fail\">FAIL</td><td class=\"verdict fail\">"
                        "INCONCLUSIVE</td>"));
    ENSURE(strstr(html, "<td>0 / 1</td><td>1 / 1</td>"));
    /* B1: 3 crossings of each release's 5 in run a, none in run b */
    const char *b1 = strstr(html, "B&lt;1&gt;&amp;&quot;x&quot; (barrier)");
    ENSURE(b1);
    ENSURE_MSG(strstr(b1, "<td class=\"t\">crossings</td><td>6</td><td class=\"absent\">not in "
                          "this run</td>"), "%.400s", b1);
    /* E1 in both, with the statistics of its interceptions */
    const char *e1 = strstr(html, ">E1 (embankment)</th>");
    ENSURE(e1);
    rf_measure_stats st;
    int64_t e1_id = dbt_int(db, "SELECT id FROM measures WHERE run_id = %lld AND name = 'E1'",
                            (long long)a);
    ENSURE(rf_query_measure_stats(db, e1_id, &st, &err) == 0);
    char want[200];
    snprintf(want, sizeof want, "<td class=\"t\">E95 (kJ)</td><td>%.0f</td><td>%.0f</td>",
             st.energy_p95, st.energy_p95);
    ENSURE_MSG(strstr(e1, want), "no %s", want);
    snprintf(want, sizeof want, "<td class=\"t\">Emax (kJ)</td><td>%.0f</td><td>%.0f</td>",
             st.energy_max, st.energy_max);
    ENSURE_MSG(strstr(e1, want), "no %s", want);
    /* the road: 10 trajectories cross it in each run, twice each */
    const char *road = strstr(html, "<h2 id=\"control-lines\">");
    ENSURE(road && strstr(road, "<td class=\"t\">trajectories crossing</td><td>10</td><td>10</td>"));
    ENSURE(strstr(road, "<td class=\"t\">crossings</td><td>20</td><td>20</td>"));
    ENSURE(!strstr(html, "<td class=\"t\">E1</td>")); /* structures are rows, not columns */
    /* one plan each; hazard cells only in run a */
    for (int k = 0; k < 2; k++) {
        char file[64];
        snprintf(file, sizeof file, "plan-run-%lld.svg", (long long)runs[k]);
        free(svg_ok(dir, file, html));
    }
    ENSURE(strstr(html, "<td class=\"t\">hazard cells crossed</td><td>6</td><td>0</td>"));
    /* the same again, byte for byte */
    char dir2[600];
    snprintf(dir2, sizeof dir2, "%.500s", rf_test_path("variants-again"));
    ENSURE(rf_report_compare(db, runs, 2, dir2, &err) == 0);
    snprintf(path, sizeof path, "%s/index.html", dir2);
    char *again = read_text(path);
    ENSURE(!strcmp(html, again));
    free(again);
    free(html);
    rf_store_close(s);
}

/* `report --out DIR` wrote through symbolic links already in DIR: a link named
 * index.html or plan.svg sent the report over any file its user may write. */
#include <unistd.h>

TEST(report_refuses_to_write_through_symlinks_in_the_folder)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 1, "links.db");
    int64_t run = write_run(s, &t, 1, 1);
    const char *victim = rf_test_write("victim.txt", "keep me\n");
    char victim_path[700], dir[700], link[800];
    snprintf(victim_path, sizeof victim_path, "%s", victim);
    snprintf(dir, sizeof dir, "%s", rf_test_path("out"));
    ENSURE(mkdir(dir, 0777) == 0);
    const char *names[2] = {"index.html", "plan.svg"};
    for (int k = 0; k < 2; k++) {
        snprintf(link, sizeof link, "%s/%s", dir, names[k]);
        unlink(link); /* written by the round before, which failed at index.html */
        ENSURE_MSG(symlink(victim_path, link) == 0, "symlink %s: %s", link, strerror(errno));
        rf_error err = {0};
        ENSURE_MSG(rf_report_write(rf_store_db(s), run, dir, &err) != 0, "%s written through",
                   names[k]);
        ENSURE_MSG(strstr(err.message, "symbolic link") && strstr(err.file, names[k]), "%s: %s",
                   err.file, err.message);
        char *text = read_text(victim_path);
        ENSURE_MSG(!strcmp(text, "keep me\n"), "the link's target was written");
        free(text);
        ENSURE(unlink(link) == 0);
    }
    report_ok(s, run, dir); /* without links it writes */
    rf_store_close(s);
}

/* An infinite energy was stored as Inf; a value that is not finite is no measurement and
 * is stored as NULL. */
TEST(store_keeps_non_finite_values_as_null)
{
    test_project t;
    rf_store *s = project_store(&t, "/nonexistent/slope.yaml", 1, "inf.db");
    rf_error err = {0};
    int64_t run = 0, tid = 0, iid = 0;
    ENSURE_MSG(rf_store_run_begin(s, &t.p, 1, &run, &err) == 0, "%s", err.message);
    ENSURE(rf_store_batch_begin(s, &err) == 0);
    rf_trajectory_record tr = {.stop = {118.0, 30.0, 0.74}, .reason = RF_END_REST,
                               .duration_s = 9.5, .path_length_m = 150.0,
                               .max_energy_kj = INFINITY, .n_impacts = 7};
    ENSURE(rf_store_add_trajectory(s, 0, 0, &tr, &tid, &err) == 0);
    rf_interception_record ic = {.measure = 0, .t_s = 8.0, .p = {95.0, 30.0, 5.7},
                                 .speed_ms = -INFINITY, .energy_kj = NAN,
                                 .energy_trans_kj = 12.5, .passing_height_m = 0.74,
                                 .outcome = RF_OUT_PASSED};
    ENSURE(rf_store_add_interception(s, tid, &ic, &iid, &err) == 0);
    ENSURE(rf_store_batch_commit(s, &err) == 0);
    sqlite3_stmt *st;
    ENSURE(sqlite3_prepare_v2(rf_store_db(s),
                              "SELECT typeof(t.max_energy_kj), typeof(i.speed_ms),"
                              " typeof(i.energy_kj), typeof(i.energy_trans_kj)"
                              " FROM trajectories t JOIN interceptions i ON i.trajectory_id = t.id"
                              " WHERE t.id = ?1",
                              -1, &st, NULL) == SQLITE_OK);
    sqlite3_bind_int64(st, 1, tid);
    ENSURE(sqlite3_step(st) == SQLITE_ROW);
    const char *want[4] = {"null", "null", "null", "real"};
    for (int c = 0; c < 4; c++)
        ENSURE_MSG(!strcmp((const char *)sqlite3_column_text(st, c), want[c]), "column %d: %s", c,
                   (const char *)sqlite3_column_text(st, c));
    sqlite3_finalize(st);
    rf_store_close(s);
}
