/* report_private.h - what the files of the report share: the run as the report holds
 * it and the helpers of its sections (report.c assembles the page). */
#ifndef ROCKFALL_REPORT_PRIVATE_H
#define ROCKFALL_REPORT_PRIVATE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <sqlite3.h>

#include "base/util.h"
#include "report/report.h"
#include "report/svg.h"
#include "input/measure_kinds.h"
#include "results/run_view.h"

/* The run's releases and measures, as the run view holds them. */
typedef rf_view_release rep_release;
typedef rf_view_measure rep_measure;

typedef struct rep_arrival {
    double s, speed, energy, zground;
    size_t rel;
} rep_arrival;

typedef struct contour_grid {
    const double *z; /* nx * ny heights, NAN off the terrain (the run view's); NULL
                      * without a terrain */
    size_t nx, ny;
    double x0, y0, step;
    double zmin, zmax, interval;
} contour_grid;

typedef struct report {
    sqlite3 *db;
    int64_t run;
    const char *dir;
    rf_error *err;
    rf_run_view view; /* everything the report reads of the run but its bulk rows */
    const char *project, *project_path, *seed, *status, *started, *finished, *version;
    rep_release *rel;
    size_t nrel;
    const char **rel_fills, **rel_names; /* of each release (at least one), for the charts */
    rep_measure *mea;
    size_t nmea;
    long n_traj, n_path_traj;
    long n_stop_points;      /* end points drawn on the plan */
    int have_terrain;        /* the run stored its terrain (terrain_grids) */
    double mu;               /* the surface's mean friction; NaN when not stored */
    contour_grid grid;
    double bx0, bx1, by0, by1; /* plan extent (m) */
    double pw, ph;             /* plan plot size (px) */
    FILE *summary, *notes, *body; /* parts of index.html */
} report;

/* The empirical crosscheck of one release at one control line (Eq. 1-2, Fig. 1b). */
typedef struct crosscheck {
    double L, H, theta, s_centre;
    double v_project, v_class_d, width;
    long n;
    double v_mean, v_max, s_min, s_max;
} crosscheck;

/* A growing array for rep_each_row: the next element of *a (n in use, cap allocated), or
 * NULL with r->err set. */
typedef struct rows {
    void **a;
    size_t *n, cap, size;
} row_array;

/* A histogram of ns series stacked over bins of width bw, drawn in an 820 px chart with
 * a legend of its first nlegend series beside the plot. */
typedef struct hist_chart {
    size_t ns, nlegend;
    const char *const *fills, *const *labels; /* of each series */
    double *counts;                           /* ns x nb */
    size_t nb;
    double lo, hi, bw;
    rf_svg s;
} hist_chart;

typedef struct legend {
    rf_svg *s;
    double x, y;
} legend;

/* A row handler of rep_each_row: returns 0, or -1 with r->err set (out of memory). */
typedef int (*row_fn)(report *r, sqlite3_stmt *st, void *ctx);

/* Sets r->err to the database's last error; returns -1. */
int rep_db_error(report *r);

/* report_data.c */
/* Runs sql with ?1 = id and hands each row to row(r, st, ctx).  Returns 0, or -1 with
 * r->err set. */
int rep_each_row(report *r, const char *sql, int64_t id, row_fn row, void *ctx);
void rep_figure_html(FILE *f, const char *file, const char *caption);
void rep_grow(double *lo, double *hi, double v);
int rep_is_control(const rep_measure *m);
int rep_load_releases(report *r);
int rep_load_rows(report *r, const char *sql, int64_t id, row_fn row, void **a, size_t *n,
                  size_t size);
int rep_load_run(report *r);
const char *rep_measure_colour(const rep_measure *m);
void *rep_next_elem(report *r, row_array *g);
void rep_note_terrain(report *r);
int rep_oom(report *r);
double rep_pct(double part, double whole);
sqlite3_stmt *rep_prep(report *r, const char *sql, int64_t id);
void rep_put_num(FILE *f, double v, int decimals);
const char *rep_release_colour(size_t k);
size_t rep_release_index(const report *r, int64_t id);
void rep_td_num(FILE *f, double v, int decimals);
void rep_td_text(FILE *f, const char *text);

/* report_plan.c */
int rep_build_contour_grid(report *r);
int rep_close_plan(report *r, legend *l);
int rep_compute_extent(report *r);
void rep_draw_contours(report *r, rf_svg *s, int faint);
int rep_figure_plan(report *r, const char *file);
void rep_plan_caption(const report *r, char *buf, size_t n);
void rep_legend_classes(legend *l, const char *title, const double *lim, int nlim,
                        double scale, const char *unit, const char *const *colours,
                        const char *swatch_class);
void rep_legend_counts(legend *l, const char *title, const double *lim, int nlim,
                       const char *const *colours);
void rep_legend_swatch(legend *l, const char *swatch_attrs, const char *label);
int rep_open_plan(report *r, rf_svg *s, const char *file, const char *title);
legend rep_plan_overlays(report *r, rf_svg *s);

/* report_road.c */
void rep_hist_add(hist_chart *h, size_t k, double v);
int rep_hist_bins(report *r, hist_chart *h, double *lo, double *hi, double bw);
int rep_hist_close(report *r, hist_chart *h, const char *xlabel, const char *ylabel);
int rep_hist_open(report *r, hist_chart *h, const char *file, const char *title, double ytop);
double rep_hist_top(const hist_chart *h);
int rep_section_road(report *r);
void rep_vertical_marker(rf_svg *s, double x, const char *line_attrs, const char *label);

/* report_hazard.c */
int rep_section_hazard(report *r);

/* report.c */
int rep_make_dirs(const char *dir, rf_error *err);
void rep_free_report(report *r);
/* The page's head: <html>, the title (escaped), the style sheet, <body>. */
void rep_page_head(FILE *f, const char *title);

/* report_measures.c */
/* The share of the crossings within `capacity` and not overtopped, as the checks count it. */
double rep_share_within(const rf_crossing_row *x, size_t n, double capacity);
int rep_checks_table(report *r, FILE *f, int64_t measure_id, long *npass, long *nfail);
int rep_section_measures(report *r, long *npass, long *nfail);

#endif
