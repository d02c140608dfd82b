/* report_hazard.c - the hazard section: maps of the largest energy per cell in
 * classes (Fig. 12) and of the reach probability. */
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

/* A hazard cell as the maps draw it: its centre (m), largest energy (kJ) and reach
 * probability. */
typedef struct map_cell {
    double x, y, energy, reach;
} map_cell;

static int map_cell_row(report *r, sqlite3_stmt *st, void *ctx)
{
    map_cell *c = rep_next_elem(r, ctx);
    if (!c)
        return -1;
    *c = (map_cell){rf_query_column_real(st, 0), rf_query_column_real(st, 1),
                    rf_query_column_real(st, 2), rf_query_column_real(st, 3)};
    return 0;
}

/* The energy map, or with reach the reach map, of the cells of size `cell`;
 * class_counts (may be NULL) gets the number of cells in each class. */
static int figure_hazard(report *r, const map_cell *cells, size_t n, double cell, int reach,
                         long *class_counts)
{
    rf_svg s;
    char title[200];
    if (reach)
        snprintf(title, sizeof title, "Reach probability per %g m cell", cell);
    else
        snprintf(title, sizeof title,
                 "Hazard map: largest kinetic energy per %g m cell (Fig. 12)", cell);
    if (rep_open_plan(r, &s, reach ? "hazard-reach.svg" : "hazard-energy.svg", title))
        return -1;
    rf_svg_raw(&s, "<g clip-path=\"url(#plot)\" shape-rendering=\"crispEdges\">\n");
    for (size_t i = 0; i < n; i++) {
        double x = cells[i].x, y = cells[i].y;
        double v = reach ? cells[i].reach : cells[i].energy;
        if (!isfinite(x) || !isfinite(y))
            continue;
        const char *fill = "#cccccc";
        if (isfinite(v)) {
            int c = reach ? class_of(v, REACH_LIMITS, N_REACH_CLASSES - 1)
                          : class_of(v, rf_report_energy_limits, RF_REPORT_N_ENERGY_LIMITS);
            fill = reach ? REACH_COLOURS[c] : ENERGY_COLOURS[c];
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
    if (reach)
        rep_legend_classes(&l, "Reach probability", REACH_LIMITS, N_REACH_CLASSES - 1, 100.0, "%",
                       REACH_COLOURS, "");
    else
        rep_legend_classes(&l, "Largest energy (kJ)", rf_report_energy_limits,
                       RF_REPORT_N_ENERGY_LIMITS, 1.0, "kJ", ENERGY_COLOURS, "class=\"class\" ");
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
                           "SELECT x, y, energy_max_kj, reach_probability FROM hazard_cells"
                           " WHERE run_id = ?1 ORDER BY iy, ix",
                           r->run, map_cell_row, (void **)&cells, &n, sizeof *cells);
    if (!status)
        status = figure_hazard(r, cells, n, cell, 0, counts) ||
                 figure_hazard(r, cells, n, cell, 1, NULL);
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
    rep_figure_html(f, "hazard-energy.svg",
                "Fig. 12: hazard map, largest kinetic energy per cell (kJ) in classes");
    rep_figure_html(f, "hazard-reach.svg",
                "Reach probability: share of all trajectories that crossed each cell");
    fprintf(r->summary, "<li>Hazard map: %ld cells; %ld reach 3000 kJ or more, %ld reach 6000 kJ "
                        "or more; largest energy ",
            h.ncells, over3000, over6000);
    rep_put_num(r->summary, h.emax, 0);
    fputs(" kJ.</li>\n", r->summary);
    return 0;
}
