/* report_hazard.c - the hazard section: maps per cell, in classes, of the largest
 * energy (Fig. 12), the 95th percentiles of the energy and of the passing height, the
 * passages and the reach probability. */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const double rf_report_energy_limits[RF_REPORT_N_ENERGY_LIMITS] = {1000.0, 3000.0, 6000.0};
static const char *const ENERGY_COLOURS[RF_REPORT_N_ENERGY_LIMITS + 1] = {
    "#fecc5c", "#fd8d3c", "#e31a1c", "#800026"};

#define N_REACH_CLASSES 5
static const double REACH_LIMITS[N_REACH_CLASSES - 1] = {0.01, 0.05, 0.2, 0.5};
static const char *const REACH_COLOURS[N_REACH_CLASSES] = {"#deebf7", "#9ecae1", "#4292c6",
                                                           "#08519c", "#08306b"};

/* Passing height classes (m): about the heights of barriers (2 - 8 m) and embankments. */
#define N_HEIGHT_CLASSES 5
static const double HEIGHT_LIMITS[N_HEIGHT_CLASSES - 1] = {1.0, 2.0, 4.0, 6.0};
static const char *const HEIGHT_COLOURS[N_HEIGHT_CLASSES] = {"#edf8e9", "#bae4b3", "#74c476",
                                                             "#31a354", "#006d2c"};

/* Passages per cell (trajectories that crossed it; a cell without one is not stored). */
#define N_PASS_CLASSES 5
static const double PASS_LIMITS[N_PASS_CLASSES - 1] = {2.0, 5.0, 20.0, 100.0};
static const char *const PASS_COLOURS[N_PASS_CLASSES] = {"#f2f0f7", "#cbc9e2", "#9e9ac8",
                                                         "#756bb1", "#54278f"};

/* ---- section: hazard map (Fig. 12) ------------------------------------------------------ */

/* What the hazard section says about the run's cells, from one read of them. */
typedef struct hazard_summary {
    long ncells;
    long p95_over[2];      /* cells whose 95th percentile reaches 3 000 and 6 000 kJ */
    double emax, p95max;   /* kJ */
    double step_x, step_y; /* spacing of the cell centres; NAN with one column (row) */
} hazard_summary;

static int read_hazard_summary(report *r, hazard_summary *h)
{
    char sql[600];
    snprintf(sql, sizeof sql,
             "SELECT count(*), max(energy_max_kj), max(energy_p95_kj),"
             " count(*) FILTER (WHERE energy_p95_kj >= %.0f),"
             " count(*) FILTER (WHERE energy_p95_kj >= %.0f),"
             " CASE WHEN max(ix) > min(ix) THEN (max(x) - min(x)) / (max(ix) - min(ix)) END,"
             " CASE WHEN max(iy) > min(iy) THEN (max(y) - min(y)) / (max(iy) - min(iy)) END"
             " FROM hazard_cells WHERE run_id = ?1",
             rf_report_energy_limits[1], rf_report_energy_limits[2]);
    *h = (hazard_summary){0, {0, 0}, NAN, NAN, NAN, NAN};
    sqlite3_stmt *st = rep_prep(r, sql, r->run);
    if (!st)
        return -1;
    int rc = sqlite3_step(st);
    if (rc == SQLITE_ROW) {
        h->ncells = (long)sqlite3_column_int64(st, 0);
        h->emax = rf_query_column_real(st, 1);
        h->p95max = rf_query_column_real(st, 2);
        h->p95_over[0] = (long)sqlite3_column_int64(st, 3);
        h->p95_over[1] = (long)sqlite3_column_int64(st, 4);
        h->step_x = rf_query_column_real(st, 5);
        h->step_y = rf_query_column_real(st, 6);
    } else {
        rep_db_error(r); /* an aggregate always gives a row */
    }
    sqlite3_finalize(st);
    return rc == SQLITE_ROW ? 0 : -1;
}

/* The project's cell size, else the spacing of the cells (5 m when unknown). */
static double hazard_cell_size(const report *r, const hazard_summary *h)
{
    if (r->view.hazard_cell > 0)
        return r->view.hazard_cell;
    if (h->step_x > 0)
        return h->step_x;
    return h->step_y > 0 ? h->step_y : 5.0;
}

/* The class of v: the number of the ascending limits lim[0 .. nlim-1] it reaches. */
static int class_of(double v, const double *lim, int nlim)
{
    int c = 0;
    while (c < nlim && v >= lim[c])
        c++;
    return c;
}

/* A hazard cell as the maps draw it: its centre (m) and the values of its row. */
typedef struct map_cell {
    double x, y;
    double value[5]; /* in the order of the map_value */
} map_cell;

typedef enum map_value { MAP_ENERGY_MAX, MAP_ENERGY_P95, MAP_HEIGHT_P95, MAP_PASSES, MAP_REACH } map_value;

/* One map of the hazard cells: the column it draws, in classes. */
typedef struct hazard_map {
    map_value value;
    const char *file;
    const char *title;   /* with the cell size (%g m) */
    const char *legend;  /* the legend's title */
    const double *lim;   /* ascending class limits */
    int nlim;
    double scale;        /* the legend shows scale times the limits */
    int counts;          /* whole numbers from 1: the legend shows "1", "2 - 4", ... */
    const char *unit;
    const char *const *colours;
    const char *swatch_class;
    const char *caption;
} hazard_map;

/* The maps, in the order of the report: the Rockyfor3D set of per-cell maps (E_95CI,
 * Ph_95CI, Nr_passages, Reach_probability) besides the paper's Fig. 12. */
static const hazard_map MAPS[] = {
    {MAP_ENERGY_MAX, "hazard-energy.svg",
     "Hazard map: largest kinetic energy per %g m cell (Fig. 12)", "Largest energy (kJ)",
     rf_report_energy_limits, RF_REPORT_N_ENERGY_LIMITS, 1.0, 0, "kJ", ENERGY_COLOURS,
     "class=\"class\" ",
     "Fig. 12: hazard map, the largest kinetic energy of the rocks that crossed each cell "
     "(kJ), in classes"},
    {MAP_ENERGY_P95, "hazard-energy-p95.svg",
     "E95: 95th percentile of the kinetic energy per %g m cell", "E95 (kJ)",
     rf_report_energy_limits, RF_REPORT_N_ENERGY_LIMITS, 1.0, 0, "kJ", ENERGY_COLOURS, "",
     "E95: the 95th percentile (nearest rank) of the kinetic energy of the rocks that "
     "crossed each cell (kJ), in the classes of Fig. 12"},
    {MAP_HEIGHT_P95, "hazard-height-p95.svg",
     "Passing height: 95th percentile per %g m cell", "Passing height p95 (m)", HEIGHT_LIMITS,
     N_HEIGHT_CLASSES - 1, 1.0, 0, "m", HEIGHT_COLOURS, "",
     "Passing height: the 95th percentile (nearest rank) of the rocks' height above the "
     "ground in each cell (m), in classes"},
    {MAP_PASSES, "hazard-passages.svg", "Passages: trajectories that crossed each %g m cell",
     "Passages", PASS_LIMITS, N_PASS_CLASSES - 1, 1.0, 1, "", PASS_COLOURS, "",
     "Passages: the number of trajectories that crossed each cell, in classes"},
    {MAP_REACH, "hazard-reach.svg", "Reach probability per %g m cell", "Reach probability",
     REACH_LIMITS, N_REACH_CLASSES - 1, 100.0, 0, "%", REACH_COLOURS, "",
     "Reach probability: the share of all trajectories that crossed each cell, in classes"},
};
#define N_MAPS (sizeof MAPS / sizeof MAPS[0])

static int map_cell_row(report *r, sqlite3_stmt *st, void *ctx)
{
    map_cell *c = rep_next_elem(r, ctx);
    if (!c)
        return -1;
    c->x = rf_query_column_real(st, 0);
    c->y = rf_query_column_real(st, 1);
    for (int k = 0; k < 5; k++)
        c->value[k] = rf_query_column_real(st, 2 + k);
    return 0;
}

/* Map m of the cells of size `cell`; class_counts (may be NULL) gets the number of
 * cells in each class.  A cell without the value (NULL) is grey. */
static int figure_hazard(report *r, const hazard_map *m, const map_cell *cells, size_t n,
                         double cell, long *class_counts)
{
    rf_svg s;
    char title[200];
    snprintf(title, sizeof title, m->title, cell);
    if (rep_open_plan(r, &s, m->file, title))
        return -1;
    rf_svg_raw(&s, "<g clip-path=\"url(#plot)\" shape-rendering=\"crispEdges\">\n");
    for (size_t i = 0; i < n; i++) {
        double x = cells[i].x, y = cells[i].y, v = cells[i].value[m->value];
        if (!isfinite(x) || !isfinite(y))
            continue;
        const char *fill = "#cccccc";
        if (isfinite(v)) {
            int c = class_of(v, m->lim, m->nlim);
            fill = m->colours[c];
            if (class_counts)
                class_counts[c]++;
        }
        char attrs[80];
        snprintf(attrs, sizeof attrs, "class=\"cell\" fill=\"%s\"", fill);
        rf_svg_rect(&s, x - cell / 2, y - cell / 2, x + cell / 2, y + cell / 2, attrs);
    }
    rf_svg_raw(&s, "</g>\n");
    rep_draw_contours(r, &s, 1);
    legend l = rep_plan_overlays(r, &s);
    if (m->counts)
        rep_legend_counts(&l, m->legend, m->lim, m->nlim, m->colours);
    else
        rep_legend_classes(&l, m->legend, m->lim, m->nlim, m->scale, m->unit, m->colours,
                           m->swatch_class);
    return rep_close_plan(r, &l);
}

int rep_section_hazard(report *r)
{
    FILE *f = r->body;
    fputs("<h2 id=\"hazard\">Hazard map (Fig. 12)</h2>\n", f);
    hazard_summary h;
    if (read_hazard_summary(r, &h))
        return -1;
    if (h.ncells <= 0) {
        fputs("<p>The run has no hazard cells.</p>\n", f);
        fputs("<li>No hazard cells in this run: no hazard maps.</li>\n", r->notes);
        return 0;
    }
    double cell = hazard_cell_size(r, &h);
    /* both maps draw the same cells: one read */
    map_cell *cells = NULL;
    size_t n = 0;
    long counts[RF_REPORT_N_ENERGY_LIMITS + 1] = {0};
    int status = rep_load_rows(r,
                           "SELECT x, y, energy_max_kj, energy_p95_kj, height_p95_m, passes,"
                           " reach_probability FROM hazard_cells"
                           " WHERE run_id = ?1 ORDER BY iy, ix",
                           r->run, map_cell_row, (void **)&cells, &n, sizeof *cells);
    for (size_t k = 0; k < N_MAPS && !status; k++)
        status = figure_hazard(r, &MAPS[k], cells, n, cell, k == 0 ? counts : NULL);
    free(cells);
    if (status)
        return -1;
    long over3000 = counts[2] + counts[3], over6000 = counts[3];
    fprintf(f,
            "<p>%ld cells of %g m were crossed. The largest kinetic energy of the rocks per cell "
            "is shown in classes with limits at %.0f, %.0f and %.0f kJ: %ld cells reach %.0f kJ "
            "or more, %ld of them %.0f kJ or more (the 95th percentile per cell: %ld and %ld). "
            "The largest energy anywhere is ",
            h.ncells, cell, rf_report_energy_limits[0], rf_report_energy_limits[1],
            rf_report_energy_limits[2], over3000, rf_report_energy_limits[1], over6000,
            rf_report_energy_limits[2], h.p95_over[0], h.p95_over[1]);
    rep_put_num(f, h.emax, 0);
    fputs(" kJ (95th percentile ", f);
    rep_put_num(f, h.p95max, 0);
    fputs(" kJ).</p>\n", f);
    fputs("<p>Beside it, per cell, the 95th percentiles of the energy (E95) and of the "
          "passing height, the passages and the reach probability. The percentiles are "
          "exact up to 128 passes of a cell and within 1.09 % beyond "
          "(<code>hazard_cells</code>, docs/database.md).</p>\n",
          f);
    for (size_t k = 0; k < N_MAPS; k++)
        rep_figure_html(f, MAPS[k].file, MAPS[k].caption);
    fprintf(r->summary, "<li>Hazard map: %ld cells; %ld reach 3000 kJ or more, %ld reach 6000 kJ "
                        "or more; largest energy ",
            h.ncells, over3000, over6000);
    rep_put_num(r->summary, h.emax, 0);
    fputs(" kJ.</li>\n", r->summary);
    return 0;
}
