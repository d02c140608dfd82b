/* report.c - DIR/index.html and its SVG figures for one run of a results database.
 *
 * Figures (the paper's numbers): plan view of the sampled trajectories over the
 * terrain contours with releases, measures and stop points (Fig. 9, 11); arrival
 * position along and velocity at each control line (Fig. 10a, 10b); hazard map of the
 * largest kinetic energy per cell in classes (Fig. 12) and the reach probability; the
 * energy at each measure against its capacities.  Beside them the empirical
 * crosscheck: Eq. 1-2 velocity and the attainment width of Fig. 1b. */
#include "report/report.h"
#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "input/measure_kinds.h"
#include "rockfall/empirical.h"
#include "rockfall/project.h"
#include "results/run_view.h"
#include "report/svg.h"

const double rf_report_energy_limits[RF_REPORT_N_ENERGY_LIMITS] = {1000.0, 3000.0, 6000.0};
static const char *const ENERGY_COLOURS[RF_REPORT_N_ENERGY_LIMITS + 1] = {
    "#fecc5c", "#fd8d3c", "#e31a1c", "#800026"};

#define N_REACH_CLASSES 5
static const double REACH_LIMITS[N_REACH_CLASSES - 1] = {0.01, 0.05, 0.2, 0.5};
static const char *const REACH_COLOURS[N_REACH_CLASSES] = {"#deebf7", "#9ecae1", "#4292c6",
                                                           "#08519c", "#08306b"};

static const char *const RELEASE_COLOURS[] = {"#1f77b4", "#2ca02c", "#9467bd", "#17becf",
                                              "#e377c2", "#bcbd22", "#ff7f0e", "#7f7f7f"};
#define N_RELEASE_COLOURS (sizeof RELEASE_COLOURS / sizeof RELEASE_COLOURS[0])

/* The energy figure's stacks, bottom up: the stack of each outcome, then the labels
 * and colours of the stacks. */
#define N_OUTCOMES 4
static const int OUTCOME_STACK[N_OUTCOMES] = {[RF_OUT_STOPPED] = 0, [RF_OUT_PASSED] = 1,
                                              [RF_OUT_OVERTOPPED] = 2, [RF_OUT_BROKE_THROUGH] = 3};
static const char *const OUTCOME_LABELS[N_OUTCOMES] = {"stopped", "passed", "overtopped",
                                                       "broke through"};
static const char *const OUTCOME_COLOURS[N_OUTCOMES] = {"#4daf4a", "#9ecae1", "#ff7f0e",
                                                        "#d62728"};

/* Fig. 1b: the largest empirical spreading angle. */
#define ATTAINMENT_BETA_DEG 45.0
/* The paper's headline check: serviceability kept for over 90 % of the rockfalls. */
/* Nodes of the contour grid along the longer side of the plan. */
#define CONTOUR_NODES 240
/* Right edge of the plot area of the 820 px charts; their legend goes beside it. */
#define CHART_RIGHT 670
/* Most stop points drawn on the plan. */
#define MAX_STOP_POINTS 20000

/* ---- data of the run ------------------------------------------------------------ */

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
    int have_terrain;        /* the run stored its terrain (terrain_grids) */
    double mu;               /* the surface's mean friction; NaN when not stored */
    contour_grid grid;
    double bx0, bx1, by0, by1; /* plan extent (m) */
    double pw, ph;             /* plan plot size (px) */
    FILE *summary, *notes, *body; /* parts of index.html */
} report;

static int db_error(report *r) { return rf_query_db_error(r->db, r->err); }

/* A statement with ?1 bound to `id`; NULL (err filled) on failure. */
static sqlite3_stmt *prep(report *r, const char *sql, int64_t id)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(r->db, sql, -1, &st, NULL) != SQLITE_OK) {
        db_error(r);
        return NULL;
    }
    if (sqlite3_bind_parameter_count(st) >= 1)
        sqlite3_bind_int64(st, 1, id);
    return st;
}

static int oom(report *r)
{
    return rf_error_set(r->err, r->dir, 0, 0, "out of memory");
}

/* Runs sql with ?1 = id and hands each row to row(r, st, ctx), which returns 0, or -1
 * with r->err set (out of memory).  Returns 0, or -1 with r->err set. */
typedef int (*row_fn)(report *r, sqlite3_stmt *st, void *ctx);
static int each_row(report *r, const char *sql, int64_t id, row_fn row, void *ctx)
{
    sqlite3_stmt *st = prep(r, sql, id);
    if (!st)
        return -1;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW)
        if (row(r, st, ctx)) {
            sqlite3_finalize(st);
            return -1;
        }
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : db_error(r);
}

/* A growing array for each_row: the next element of *a (n in use, cap allocated), or
 * NULL with r->err set. */
typedef struct rows {
    void **a;
    size_t *n, cap, size;
} row_array;

static void *next_elem(report *r, row_array *g)
{
    if (rf_grow(g->a, &g->cap, *g->n + 1, g->size)) {
        oom(r);
        return NULL;
    }
    return (char *)*g->a + (*g->n)++ * g->size;
}

/* each_row into the array *a (*n elements of size bytes): row fills next_elem(r, ctx). */
static int load_rows(report *r, const char *sql, int64_t id, row_fn row, void **a, size_t *n,
                     size_t size)
{
    row_array g = {a, n, 0, size};
    return each_row(r, sql, id, row, &g);
}

static size_t release_index(const report *r, int64_t id)
{
    for (size_t k = 0; k < r->nrel; k++)
        if (r->rel[k].id == id)
            return k;
    return 0;
}

static const char *release_colour(size_t k)
{
    return RELEASE_COLOURS[k % N_RELEASE_COLOURS];
}

static const char *measure_colour(const rep_measure *m)
{
    return m->kind >= 0 ? rf_measure_kinds[m->kind].colour : "#252525";
}

/* A protected line (a control line): the report draws the arrivals along it. */
static int is_control(const rep_measure *m)
{
    return m->kind >= 0 && rf_measure_kinds[m->kind].reach_line;
}

/* ---- loading ---------------------------------------------------------------------- */

/* The run through the run view; the report's names point into it. */
static int load_run(report *r)
{
    if (rf_run_view_load(r->db, r->run, &r->view, r->err))
        return -1;
    const rf_run_view *v = &r->view;
    r->project = v->project;
    r->project_path = v->project_path;
    r->seed = v->seed;
    r->status = v->status;
    r->started = v->started;
    r->finished = v->finished;
    r->version = v->version;
    r->rel = v->rel;
    r->nrel = v->nrel;
    r->mea = v->mea;
    r->nmea = v->nmea;
    r->n_traj = v->n_trajectories;
    r->have_terrain = v->has_grid;
    r->mu = v->surface_friction;
    return 0;
}

static int load_releases(report *r)
{
    size_t n = r->nrel ? r->nrel : 1;
    r->rel_fills = calloc(n, sizeof *r->rel_fills);
    r->rel_names = calloc(n, sizeof *r->rel_names);
    if (!r->rel_fills || !r->rel_names)
        return oom(r);
    for (size_t k = 0; k < n; k++) {
        r->rel_fills[k] = release_colour(k);
        r->rel_names[k] = k < r->nrel ? r->rel[k].name : "";
    }
    return 0;
}

/* What the report says of a run without its terrain. */
static void note_terrain(report *r)
{
    if (!r->have_terrain)
        fputs("<li>The run stores no terrain (a run without one, or one written before "
              "schema version 2 of the results database): the figures have no terrain "
              "contours.</li>\n",
              r->notes);
}

/* ---- extent and contours -------------------------------------------------------- */

static void grow(double *lo, double *hi, double v)
{
    if (isfinite(v)) {
        if (v < *lo)
            *lo = v;
        if (v > *hi)
            *hi = v;
    }
}

static int compute_extent(report *r)
{
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    if (r->have_terrain) { /* the extent fitted when the terrain was stored */
        x0 = r->view.grid.x0;
        x1 = r->view.grid.x1;
        y0 = r->view.grid.y0;
        y1 = r->view.grid.y1;
    } else {
        for (size_t k = 0; k < r->nrel; k++) {
            grow(&x0, &x1, r->rel[k].x);
            grow(&y0, &y1, r->rel[k].y);
        }
        for (size_t k = 0; k < r->nmea; k++)
            for (size_t i = 0; i < r->mea[k].n; i++) {
                grow(&x0, &x1, r->mea[k].xy[2 * i]);
                grow(&y0, &y1, r->mea[k].xy[2 * i + 1]);
            }
        static const char *const sql[] = {
            "SELECT min(p.x), max(p.x), min(p.y), max(p.y) FROM path_points p"
            " JOIN trajectories t ON t.id = p.trajectory_id WHERE t.run_id = ?1",
            "SELECT min(stop_x), max(stop_x), min(stop_y), max(stop_y) FROM trajectories"
            " WHERE run_id = ?1",
            "SELECT min(x), max(x), min(y), max(y) FROM hazard_cells WHERE run_id = ?1",
        };
        for (size_t q = 0; q < sizeof sql / sizeof sql[0]; q++) {
            sqlite3_stmt *st = prep(r, sql[q], r->run);
            if (!st)
                return -1;
            if (sqlite3_step(st) == SQLITE_ROW) {
                grow(&x0, &x1, rf_query_column_real(st, 0));
                grow(&x0, &x1, rf_query_column_real(st, 1));
                grow(&y0, &y1, rf_query_column_real(st, 2));
                grow(&y0, &y1, rf_query_column_real(st, 3));
            }
            sqlite3_finalize(st);
        }
        if (!(x1 >= x0)) {
            x0 = y0 = 0.0;
            x1 = y1 = 100.0;
        }
        double pad = 0.04 * fmax(x1 - x0, y1 - y0) + 2.0;
        x0 -= pad;
        x1 += pad;
        y0 -= pad;
        y1 += pad;
        rf_plan_extent_fit(&x0, &x1, &y0, &y1);
    }
    /* The plot keeps 1 m the same in x and y (the extent is fitted to that). */
    double dx = x1 - x0, dy = y1 - y0;
    r->bx0 = x0;
    r->bx1 = x1;
    r->by0 = y0;
    r->by1 = y1;
    r->pw = 760.0;
    r->ph = r->pw * dy / dx;
    if (r->ph > 900.0) {
        r->ph = 900.0;
        r->pw = r->ph * dx / dy;
    }
    return 0;
}

/* The contour levels of the stored terrain grid. */
static int build_contour_grid(report *r)
{
    if (!r->have_terrain)
        return 0;
    contour_grid *g = &r->grid;
    const rf_terrain_grid *t = &r->view.grid;
    g->step = t->step;
    g->nx = t->nx;
    g->ny = t->ny;
    g->x0 = t->x0;
    g->y0 = t->y0;
    g->zmin = INFINITY;
    g->zmax = -INFINITY;
    for (size_t k = 0; k < t->nx * t->ny; k++)
        grow(&g->zmin, &g->zmax, t->z[k]);
    if (!(g->zmax > g->zmin))
        return 0;
    g->z = t->z;
    g->interval = rf_svg_nice_step(g->zmax - g->zmin, 14);
    return 0;
}

/* Marching squares: segments of the level through one cell (corners counter-
 * clockwise from the lower left; edges 0 bottom, 1 right, 2 top, 3 left). */
static int cell_segments(const double c[4], double level, int seg[4])
{
    int idx = (c[0] >= level) | (c[1] >= level) << 1 | (c[2] >= level) << 2 | (c[3] >= level) << 3;
    double centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
    switch (idx) {
    case 1: case 14: seg[0] = 3; seg[1] = 0; return 1;
    case 2: case 13: seg[0] = 0; seg[1] = 1; return 1;
    case 3: case 12: seg[0] = 3; seg[1] = 1; return 1;
    case 4: case 11: seg[0] = 1; seg[1] = 2; return 1;
    case 6: case 9: seg[0] = 0; seg[1] = 2; return 1;
    case 7: case 8: seg[0] = 3; seg[1] = 2; return 1;
    case 5: case 10: {
        /* a saddle: the two corners on the centre's side of the level are joined */
        static const int pairs[2][4] = {{3, 0, 1, 2}, {0, 1, 2, 3}};
        memcpy(seg, pairs[(centre >= level) == (idx == 5)], sizeof pairs[0]);
        return 2;
    }
    default: return 0;
    }
}

static void edge_point(const contour_grid *g, size_t i, size_t j, const double c[4], int edge,
                       double level, double *x, double *y)
{
    static const int a[4] = {0, 1, 2, 3}, b[4] = {1, 2, 3, 0};
    static const double cx[4] = {0, 1, 1, 0}, cy[4] = {0, 0, 1, 1};
    double za = c[a[edge]], zb = c[b[edge]];
    double t = zb != za ? (level - za) / (zb - za) : 0.5;
    double u = cx[a[edge]] + t * (cx[b[edge]] - cx[a[edge]]);
    double v = cy[a[edge]] + t * (cy[b[edge]] - cy[a[edge]]);
    *x = g->x0 + ((double)i + u) * g->step;
    *y = g->y0 + ((double)j + v) * g->step;
}

static void draw_contours(report *r, rf_svg *s, int faint)
{
    const contour_grid *g = &r->grid;
    if (!g->z)
        return;
    double label_x = r->bx0 + 0.1 * (r->bx1 - r->bx0);
    rf_svg_raw(s, "<g fill=\"none\" stroke=\"%s\" stroke-linejoin=\"round\">\n",
               faint ? "#b0a597" : "#8c7b68");
    for (double level = ceil(g->zmin / g->interval) * g->interval; level <= g->zmax;
         level += g->interval) {
        int major = labs(lround(level / g->interval)) % 5 == 0;
        rf_svg_path_begin(s, major ? "stroke-width=\"1.2\"" : "stroke-width=\"0.5\"");
        double best = INFINITY, lx = 0, ly = 0;
        for (size_t j = 0; j + 1 < g->ny; j++)
            for (size_t i = 0; i + 1 < g->nx; i++) {
                double c[4] = {g->z[j * g->nx + i], g->z[j * g->nx + i + 1],
                               g->z[(j + 1) * g->nx + i + 1], g->z[(j + 1) * g->nx + i]};
                if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]) || !isfinite(c[3]))
                    continue;
                int seg[4];
                int ns = cell_segments(c, level, seg);
                for (int k = 0; k < ns; k++) {
                    double xa, ya, xb, yb;
                    edge_point(g, i, j, c, seg[2 * k], level, &xa, &ya);
                    edge_point(g, i, j, c, seg[2 * k + 1], level, &xb, &yb);
                    rf_svg_path_move(s, xa, ya);
                    rf_svg_path_line(s, xb, yb);
                    double d = fabs(0.5 * (xa + xb) - label_x);
                    if (major && d < best) {
                        best = d;
                        lx = 0.5 * (xa + xb);
                        ly = 0.5 * (ya + yb);
                    }
                }
            }
        rf_svg_path_end(s);
        if (major && !faint && isfinite(best))
            rf_svg_text(s, rf_svg_px(s, lx), rf_svg_py(s, ly) + 4,
                        "text-anchor=\"middle\" font-size=\"11\" fill=\"#6b5a47\" stroke=\"none\""
                        " paint-order=\"stroke\"",
                        "%.0f", level);
    }
    rf_svg_raw(s, "</g>\n");
}

/* ---- plan-view pieces ------------------------------------------------------------- */

static int open_plan(report *r, rf_svg *s, const char *file, const char *title)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", r->dir, file);
    double left = 80, top = 50;
    if (rf_svg_open(s, path, left + r->pw + 250, top + r->ph + 70, title, r->err))
        return -1;
    rf_svg_frame(s, left, top, left + r->pw, top + r->ph, r->bx0, r->bx1, r->by0, r->by1);
    rf_svg_raw(s, "<clipPath id=\"plot\"><rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" "
                  "height=\"%.1f\"/></clipPath>\n",
               left, top, r->pw, r->ph);
    return 0;
}

static void draw_measures(report *r, rf_svg *s)
{
    for (size_t k = 0; k < r->nmea; k++) {
        const rep_measure *m = &r->mea[k];
        if (m->n < 2)
            continue;
        char attrs[200];
        snprintf(attrs, sizeof attrs,
                 "fill=\"none\" stroke=\"%s\" stroke-width=\"%s\" stroke-linecap=\"round\"%s",
                 measure_colour(m), is_control(m) ? "3" : "5",
                 is_control(m) ? " stroke-dasharray=\"12 6\"" : "");
        rf_svg_path_begin(s, attrs);
        rf_svg_path_move(s, m->xy[0], m->xy[1]);
        for (size_t i = 1; i < m->n; i++)
            rf_svg_path_line(s, m->xy[2 * i], m->xy[2 * i + 1]);
        rf_svg_path_end(s);
        /* label beside the end of the line that lies more to the right */
        size_t e = m->xy[2 * (m->n - 1)] >= m->xy[0] ? m->n - 1 : 0;
        double px = rf_svg_px(s, m->xy[2 * e]), py = rf_svg_py(s, m->xy[2 * e + 1]);
        px = fmin(px, s->right - 4);
        snprintf(attrs, sizeof attrs,
                 "text-anchor=\"end\" font-weight=\"bold\" fill=\"%s\" stroke=\"white\" "
                 "stroke-width=\"3\" paint-order=\"stroke\"",
                 measure_colour(m));
        rf_svg_text(s, px - 4, py - 8, attrs, "%s", m->name);
    }
}

static void draw_releases(report *r, rf_svg *s)
{
    for (size_t k = 0; k < r->nrel; k++) {
        const rep_release *e = &r->rel[k];
        if (!isfinite(e->x) || !isfinite(e->y))
            continue;
        double px = rf_svg_px(s, e->x), py = rf_svg_py(s, e->y);
        rf_svg_raw(s,
                   "<path d=\"M%.1f %.1fL%.1f %.1fL%.1f %.1fZ\" fill=\"%s\" stroke=\"black\" "
                   "stroke-width=\"1.2\"/>\n",
                   px, py - 8, px + 7, py + 5, px - 7, py + 5, release_colour(k));
        rf_svg_text(s, px + 10, py - 4,
                    "font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"",
                    "%s", e->name);
    }
}

/* North arrow (top right) and scale bar (bottom left) inside the plot. */
static void draw_north_and_scale(rf_svg *s)
{
    double nx = s->right - 28, ny = s->top + 14;
    rf_svg_raw(s,
               "<path d=\"M%.1f %.1fL%.1f %.1fL%.1f %.1fL%.1f %.1fZ\" fill=\"black\" "
               "stroke=\"white\" stroke-width=\"1\"/>\n",
               nx, ny, nx + 8, ny + 26, nx, ny + 20, nx - 8, ny + 26);
    rf_svg_text(s, nx, ny + 42,
                "text-anchor=\"middle\" font-weight=\"bold\" stroke=\"white\" stroke-width=\"3\" "
                "paint-order=\"stroke\"",
                "N");
    double len = rf_svg_nice_step(s->x1 - s->x0, 5);
    double px0 = s->left + 14, py = s->bottom - 16;
    double plen = len / (s->x1 - s->x0) * (s->right - s->left);
    rf_svg_raw(s,
               "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"26\" fill=\"white\" "
               "fill-opacity=\"0.85\"/>\n"
               "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"5\" fill=\"black\"/>\n"
               "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"5\" fill=\"white\" "
               "stroke=\"black\" stroke-width=\"0.8\"/>\n",
               px0 - 6, py - 17, plen + 12, px0, py, plen / 2, px0 + plen / 2, py, plen / 2);
    rf_svg_text(s, px0 + plen / 2, py - 4, "text-anchor=\"middle\" font-size=\"11\"", "%g m",
                len);
}

typedef struct legend {
    rf_svg *s;
    double x, y;
} legend;

static void legend_title(legend *l, const char *title)
{
    rf_svg_text(l->s, l->x, l->y, "font-weight=\"bold\"", "%s", title);
    l->y += 20;
}

static void legend_swatch(legend *l, const char *swatch_attrs, const char *label)
{
    rf_svg_raw(l->s, "<rect x=\"%.1f\" y=\"%.1f\" width=\"22\" height=\"12\" %s/>\n", l->x,
               l->y - 10, swatch_attrs);
    rf_svg_text(l->s, l->x + 30, l->y, "", "%s", label);
    l->y += 19;
}

static void legend_line(legend *l, const char *stroke_attrs, const char *label)
{
    rf_svg_raw(l->s, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" %s/>\n", l->x,
               l->y - 4, l->x + 22, l->y - 4, stroke_attrs);
    rf_svg_text(l->s, l->x + 30, l->y, "", "%s", label);
    l->y += 19;
}

static void legend_measures(report *r, legend *l)
{
    for (size_t k = 0; k < r->nmea; k++) {
        const rep_measure *m = &r->mea[k];
        char attrs[160], label[300];
        snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"%s\"%s", measure_colour(m),
                 is_control(m) ? "3" : "5", is_control(m) ? " stroke-dasharray=\"8 4\"" : "");
        snprintf(label, sizeof label, "%s (%s)", m->name, m->kind_name);
        legend_line(l, attrs, label);
    }
}

static void legend_contours(report *r, legend *l)
{
    char label[120];
    if (r->grid.z) {
        snprintf(label, sizeof label, "contours every %g m", r->grid.interval);
        legend_line(l, "stroke=\"#8c7b68\" stroke-width=\"0.5\"", label);
        snprintf(label, sizeof label, "(bold every %g m)", 5 * r->grid.interval);
        rf_svg_text(l->s, l->x + 30, l->y, "", "%s", label);
        l->y += 19;
    } else {
        rf_svg_text(l->s, l->x, l->y, "fill=\"#a00\"", "no terrain contours");
        l->y += 19;
    }
}

/* The classes of a map, the highest first: their colour and limits ("< a", "a - b",
 * ">= b"), shown as scale times the limits in the unit. */
static void legend_classes(legend *l, const char *title, const double *lim, int nlim,
                           double scale, const char *unit, const char *const *colours,
                           const char *swatch_class)
{
    legend_title(l, title);
    for (int c = nlim; c >= 0; c--) {
        char label[120], attrs[120];
        if (c == nlim)
            snprintf(label, sizeof label, ">= %g %s", scale * lim[c - 1], unit);
        else if (c == 0)
            snprintf(label, sizeof label, "< %g %s", scale * lim[0], unit);
        else
            snprintf(label, sizeof label, "%g - %g %s", scale * lim[c - 1], scale * lim[c], unit);
        snprintf(attrs, sizeof attrs, "%sfill=\"%s\" stroke=\"#444\" stroke-width=\"0.5\"",
                 swatch_class, colours[c]);
        legend_swatch(l, attrs, label);
    }
}

/* Over a plan's own layers: the measures, the releases, the north arrow, the scale bar
 * and the axes.  Returns the legend beside the plot, for the plan's own entries. */
static legend plan_overlays(report *r, rf_svg *s)
{
    draw_measures(r, s);
    draw_releases(r, s);
    draw_north_and_scale(s);
    rf_svg_axes(s, "x (m)", "y (m)");
    return (legend){s, s->right + 20, s->top + 10};
}

/* The measures and the contours in the legend, below the plan's own entries, and the
 * end of the plan. */
static int close_plan(report *r, legend *l)
{
    l->y += 8;
    legend_title(l, "Measures");
    legend_measures(r, l);
    l->y += 8;
    legend_contours(r, l);
    return rf_svg_close(l->s, r->err);
}

/* ---- figure: plan view (Fig. 9, 11) -------------------------------------------------- */

static int figure_plan(report *r)
{
    rf_svg s;
    if (open_plan(r, &s, "plan.svg", "Plan view: trajectories, releases and measures"))
        return -1;
    draw_contours(r, &s, 0);

    /* sampled paths, one polyline per trajectory, coloured by release */
    sqlite3_stmt *st = prep(r,
                            "SELECT p.trajectory_id, t.release_id, p.x, p.y FROM path_points p"
                            " JOIN trajectories t ON t.id = p.trajectory_id WHERE t.run_id = ?1"
                            " ORDER BY p.trajectory_id, p.seq",
                            r->run);
    if (!st) {
        rf_svg_close(&s, NULL);
        return -1;
    }
    rf_svg_raw(&s, "<g clip-path=\"url(#plot)\" fill=\"none\" stroke-width=\"1\" "
                   "stroke-opacity=\"0.6\" stroke-linejoin=\"round\">\n");
    int64_t cur = -1;
    long npaths = 0;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        int64_t tid = sqlite3_column_int64(st, 0);
        double x = rf_query_column_real(st, 2), y = rf_query_column_real(st, 3);
        if (!isfinite(x) || !isfinite(y))
            continue;
        if (tid != cur) {
            if (cur >= 0)
                rf_svg_path_end(&s);
            char attrs[64];
            snprintf(attrs, sizeof attrs, "class=\"path\" stroke=\"%s\"",
                     release_colour(release_index(r, sqlite3_column_int64(st, 1))));
            rf_svg_path_begin(&s, attrs);
            rf_svg_path_move(&s, x, y);
            cur = tid;
            npaths++;
        } else {
            rf_svg_path_line(&s, x, y);
        }
    }
    if (cur >= 0)
        rf_svg_path_end(&s);
    sqlite3_finalize(st);
    rf_svg_raw(&s, "</g>\n");
    if (rc != SQLITE_DONE) {
        rf_svg_close(&s, NULL);
        return db_error(r);
    }
    r->n_path_traj = npaths;

    /* where every trajectory ended */
    char sql[128];
    snprintf(sql, sizeof sql,
             "SELECT stop_x, stop_y FROM trajectories WHERE run_id = ?1 ORDER BY id LIMIT %d",
             MAX_STOP_POINTS);
    st = prep(r, sql, r->run);
    if (!st) {
        rf_svg_close(&s, NULL);
        return -1;
    }
    rf_svg_raw(&s, "<g clip-path=\"url(#plot)\" fill=\"black\" fill-opacity=\"0.55\">\n");
    while (sqlite3_step(st) == SQLITE_ROW) {
        double x = rf_query_column_real(st, 0), y = rf_query_column_real(st, 1);
        if (isfinite(x) && isfinite(y))
            rf_svg_raw(&s, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"1.8\"/>\n", rf_svg_px(&s, x),
                       rf_svg_py(&s, y));
    }
    sqlite3_finalize(st);
    rf_svg_raw(&s, "</g>\n");

    legend l = plan_overlays(r, &s);
    legend_title(&l, "Releases and sampled paths");
    for (size_t k = 0; k < r->nrel; k++) {
        char attrs[80];
        snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"2\"", release_colour(k));
        legend_line(&l, attrs, r->rel[k].name);
    }
    legend_swatch(&l, "fill=\"black\" fill-opacity=\"0.55\" rx=\"6\"", "end points");
    return close_plan(r, &l);
}

/* ---- figures: arrivals at a control line (Fig. 10) ----------------------------------- */

typedef struct road_stats {
    rep_arrival *a;
    size_t n;
    double length;          /* of the control line */
    double s_min, s_max, v_mean, v_max, e_max;
} road_stats;

typedef struct arrivals_ctx {
    row_array g;
    const rep_measure *m;
    road_stats *rs;
    double vsum;
} arrivals_ctx;

static int arrival_row(report *r, sqlite3_stmt *st, void *ctx)
{
    arrivals_ctx *c = ctx;
    road_stats *rs = c->rs;
    rep_arrival *a = next_elem(r, &c->g);
    if (!a)
        return -1;
    a->rel = release_index(r, sqlite3_column_int64(st, 0));
    a->s = rf_polyline_station(c->m->xy, c->m->n, rf_query_column_real(st, 1),
                               rf_query_column_real(st, 2), NULL, NULL, NULL);
    a->speed = rf_query_column_real(st, 3);
    a->energy = rf_query_column_real(st, 4);
    a->zground = rf_query_column_real(st, 5);
    grow(&rs->s_min, &rs->s_max, a->s);
    if (isfinite(a->speed)) {
        c->vsum += a->speed;
        rs->v_max = fmax(rs->v_max, a->speed);
    }
    if (isfinite(a->energy))
        rs->e_max = fmax(rs->e_max, a->energy);
    return 0;
}

static int load_arrivals(report *r, const rep_measure *m, road_stats *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->length = rf_polyline_length(m->xy, m->n);
    rs->s_min = INFINITY;
    rs->s_max = -INFINITY;
    rs->v_max = rs->e_max = -INFINITY;
    arrivals_ctx c = {{(void **)&rs->a, &rs->n, 0, sizeof *rs->a}, m, rs, 0.0};
    /* the first crossing of each trajectory */
    if (each_row(r,
                 "SELECT t.release_id, i.x, i.y, i.speed_ms, i.energy_kj,"
                 " i.z - i.passing_height_m, min(i.t_s)"
                 " FROM interceptions i JOIN trajectories t ON t.id = i.trajectory_id"
                 " WHERE i.measure_id = ?1 GROUP BY i.trajectory_id"
                 " ORDER BY i.trajectory_id",
                 m->id, arrival_row, &c))
        return -1;
    rs->v_mean = rs->n ? c.vsum / (double)rs->n : NAN;
    return 0;
}

/* The empirical crosscheck of one release at one control line (Eq. 1-2, Fig. 1b). */
typedef struct crosscheck {
    double L, H, theta, s_centre;
    double v_project, v_class_d, width;
    long n;
    double v_mean, v_max, s_min, s_max;
} crosscheck;

static void crosscheck_release(report *r, const rep_measure *m, const road_stats *rs, size_t k,
                               crosscheck *c)
{
    const rep_release *e = &r->rel[k];
    double px, py;
    c->s_centre = rf_polyline_station(m->xy, m->n, e->x, e->y, &c->L, &px, &py);
    (void)px, (void)py;
    const rf_view_ground *gp = rf_run_view_ground(&r->view, e->id, m->id);
    double zroad = gp ? gp->z : NAN;
    double zsum = 0, vsum = 0;
    long nz = 0;
    c->n = 0;
    c->v_max = -INFINITY;
    c->s_min = INFINITY;
    c->s_max = -INFINITY;
    for (size_t i = 0; i < rs->n; i++) {
        const rep_arrival *a = &rs->a[i];
        if (a->rel != k)
            continue;
        c->n++;
        if (isfinite(a->zground)) {
            zsum += a->zground;
            nz++;
        }
        if (isfinite(a->speed)) {
            vsum += a->speed;
            c->v_max = fmax(c->v_max, a->speed);
        }
        grow(&c->s_min, &c->s_max, a->s);
    }
    if (!isfinite(zroad) && nz)
        zroad = zsum / (double)nz;
    c->v_mean = c->n ? vsum / (double)c->n : NAN;
    if (!c->n)
        c->v_max = NAN;
    c->H = e->z - zroad;
    c->theta = c->L > 0 ? atan2(c->H, c->L) : NAN;
    double mu = r->mu;
    c->v_project = c->H > 0 && isfinite(mu) ? rf_empirical_velocity(c->H, c->theta, mu) : NAN;
    /* the paper's crosscheck uses Table 2 class D */
    double mu_d = rf_table2_friction('D');
    c->v_class_d = c->H > 0 ? rf_empirical_velocity(c->H, c->theta, mu_d) : NAN;
    c->width = rf_empirical_attainment_width(c->L, ATTAINMENT_BETA_DEG * M_PI / 180.0);
}

/* Bins [lo, hi) of width bw covering the values; returns the number of bins. */
static size_t make_bins(double *lo, double *hi, double bw)
{
    *lo = floor(*lo / bw + 1e-9) * bw;
    double top = ceil(*hi / bw - 1e-9) * bw;
    if (top <= *hi)
        top += bw;
    *hi = top;
    return (size_t)lround((*hi - *lo) / bw);
}

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

/* Empty bins [*lo, *hi) of width bw, widened to whole bins. */
static int hist_bins(report *r, hist_chart *h, double *lo, double *hi, double bw)
{
    h->nb = make_bins(lo, hi, bw);
    h->lo = *lo;
    h->hi = *hi;
    h->bw = bw;
    h->counts = calloc(h->ns * h->nb, sizeof *h->counts);
    return h->counts ? 0 : oom(r);
}

/* Counts v in series k; a value outside the bins (or NAN) is left out. */
static void hist_add(hist_chart *h, size_t k, double v)
{
    double b = floor((v - h->lo) / h->bw);
    if (b >= 0 && b < (double)h->nb)
        h->counts[k * h->nb + (size_t)b] += 1;
}

/* The highest stack, at least 1. */
static double hist_top(const hist_chart *h)
{
    double m = 0;
    for (size_t i = 0; i < h->nb; i++) {
        double t = 0;
        for (size_t k = 0; k < h->ns; k++)
            t += h->counts[k * h->nb + i];
        m = fmax(m, t);
    }
    return fmax(1.0, m);
}

/* Opens the chart's file and draws the bars, under a y axis up to ytop. */
static int hist_open(report *r, hist_chart *h, const char *file, const char *title, double ytop)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", r->dir, file);
    if (rf_svg_open(&h->s, path, 820, 420, title, r->err)) {
        free(h->counts);
        return -1;
    }
    h->s.y_counts = 1;
    rf_svg_frame(&h->s, 80, 45, CHART_RIGHT, 360, h->lo, h->hi, 0, ytop);
    rf_svg_stacked_bars(&h->s, h->counts, h->ns, h->nb, h->lo, h->bw, h->fills);
    return 0;
}

/* The axes, the legend and the end of the chart. */
static int hist_close(report *r, hist_chart *h, const char *xlabel, const char *ylabel)
{
    rf_svg_axes(&h->s, xlabel, ylabel);
    legend l = {&h->s, h->s.right + 18, h->s.top + 10};
    for (size_t k = 0; k < h->nlegend; k++) {
        char attrs[80];
        snprintf(attrs, sizeof attrs, "fill=\"%s\" stroke=\"#222\" stroke-width=\"0.5\"",
                 h->fills[k]);
        legend_swatch(&l, attrs, h->labels[k]);
    }
    free(h->counts);
    return rf_svg_close(&h->s, r->err);
}

/* The arrivals' speeds (speed) or positions along the line per release, in bins
 * [*lo, *hi) of width bw; the legend names the releases when there are several. */
static int arrivals_hist(report *r, const road_stats *rs, int speed, double *lo, double *hi,
                         double bw, hist_chart *h)
{
    *h = (hist_chart){.ns = r->nrel ? r->nrel : 1,
                      .nlegend = r->nrel < 2 ? 0 : r->nrel < 12 ? r->nrel : 12,
                      .fills = r->rel_fills, .labels = r->rel_names};
    if (hist_bins(r, h, lo, hi, bw))
        return -1;
    for (size_t i = 0; i < rs->n; i++)
        hist_add(h, rs->a[i].rel, speed ? rs->a[i].speed : rs->a[i].s);
    return 0;
}

/* A vertical line at x across the plot, with its label along it from the top. */
static void vertical_marker(rf_svg *s, double x, const char *line_attrs, const char *label)
{
    rf_svg_line(s, x, s->y0, x, s->y1, line_attrs);
    double px = rf_svg_px(s, x) - 4, py = s->top + 8;
    char attrs[200];
    snprintf(attrs, sizeof attrs,
             "text-anchor=\"end\" font-size=\"11\" transform=\"rotate(-90 %.1f %.1f)\" "
             "stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"",
             px, py);
    rf_svg_text(s, px, py, attrs, "%s", label);
}

static int figure_road_position(report *r, const rep_measure *m, const road_stats *rs,
                                const crosscheck *cc, const char *file)
{
    double lo = rs->s_min, hi = rs->s_max;
    double spread = hi - lo;
    for (size_t k = 0; k < r->nrel; k++) {
        if (!isfinite(cc[k].L))
            continue;
        grow(&lo, &hi, fmax(0.0, cc[k].s_centre - cc[k].width / 2));
        grow(&lo, &hi, fmin(rs->length, cc[k].s_centre + cc[k].width / 2));
    }
    double bw = rf_svg_nice_step(fmax(spread, 1.0), 15);
    while ((hi - lo) / bw > 300)
        bw = rf_svg_nice_step(bw * 2.1, 1);
    hist_chart h;
    if (arrivals_hist(r, rs, 0, &lo, &hi, bw, &h))
        return -1;
    double cmax = hist_top(&h);
    double band = 0.09 * cmax;
    double ytop = cmax * 1.08 + band * (double)r->nrel + band * 0.5;

    char title[600];
    snprintf(title, sizeof title, "Arrival position along %s (Fig. 10a)", m->name);
    if (hist_open(r, &h, file, title, ytop))
        return -1;
    rf_svg *s = &h.s;
    /* Fig. 1b: attainment range of each release at beta = 45 degrees */
    for (size_t k = 0; k < r->nrel; k++) {
        if (!isfinite(cc[k].L))
            continue;
        double y = cmax * 1.08 + band * ((double)k + 0.5);
        double a = fmax(lo, cc[k].s_centre - cc[k].width / 2);
        double b = fmin(hi, cc[k].s_centre + cc[k].width / 2);
        char attrs[120];
        snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"3\"", release_colour(k));
        rf_svg_line(s, a, y, b, y, attrs);
        rf_svg_line(s, a, y - band * 0.3, a, y + band * 0.3, attrs);
        rf_svg_line(s, b, y - band * 0.3, b, y + band * 0.3, attrs);
        rf_svg_text(s, rf_svg_px(s, 0.5 * (a + b)), rf_svg_py(s, y) - 5,
                    "text-anchor=\"middle\" font-size=\"11\" stroke=\"white\" stroke-width=\"3\" "
                    "paint-order=\"stroke\"",
                    "empirical attainment range from %s (Fig. 1b, beta = 45 deg): %.0f m",
                    r->rel[k].name, cc[k].width);
    }
    char xlabel[600];
    snprintf(xlabel, sizeof xlabel, "position along %s from its first point (m)", m->name);
    return hist_close(r, &h, xlabel, "number of rocks");
}

static int figure_road_velocity(report *r, const rep_measure *m, const road_stats *rs,
                                const crosscheck *cc, const char *file)
{
    int lines = r->nrel <= 3;
    double hi = rs->v_max;
    for (size_t k = 0; lines && k < r->nrel; k++) {
        grow(&hi, &hi, cc[k].v_class_d);
        grow(&hi, &hi, cc[k].v_project);
    }
    hi = fmax(hi * 1.05, 1.0);
    double lo = 0.0;
    double bw = rf_svg_nice_step(hi, 25);
    hist_chart h;
    if (arrivals_hist(r, rs, 1, &lo, &hi, bw, &h))
        return -1;
    double cmax = hist_top(&h);
    char title[600];
    snprintf(title, sizeof title, "Velocity at %s (Fig. 10b)", m->name);
    if (hist_open(r, &h, file, title, cmax * 1.15))
        return -1;
    rf_svg *s = &h.s;
    char mu_d_text[64], mu_text[64];
    snprintf(mu_d_text, sizeof mu_d_text, "mu = %.2f (Table 2, D)", rf_table2_friction('D'));
    const char *what[2] = {mu_d_text, "mu of the project"};
    if (isfinite(r->mu)) {
        snprintf(mu_text, sizeof mu_text, "mu = %.2f (project)", r->mu);
        what[1] = mu_text;
    }
    for (size_t k = 0; lines && k < r->nrel; k++) {
        double v[2] = {cc[k].v_class_d, cc[k].v_project};
        for (int j = 0; j < 2; j++) {
            if (!isfinite(v[j]))
                continue;
            char attrs[120];
            snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"2\" stroke-dasharray=\"%s\"",
                     j ? "#555" : "#000", j ? "3 3" : "8 4");
            char label[2048]; /* as long as rf_svg_text's */
            snprintf(label, sizeof label, "Eq. 1 from %s, %s: %.1f m/s", r->rel[k].name,
                     what[j], v[j]);
            vertical_marker(s, v[j], attrs, label);
        }
    }
    char xlabel[600];
    snprintf(xlabel, sizeof xlabel, "velocity at %s (m/s)", m->name);
    return hist_close(r, &h, xlabel, "number of rocks");
}

/* ---- HTML helpers ------------------------------------------------------------------- */

static void put_num(FILE *f, double v, int decimals)
{
    if (isfinite(v))
        fprintf(f, "%.*f", decimals, v);
    else
        fputs("&ndash;", f);
}

static void td_num(FILE *f, double v, int decimals)
{
    fputs("<td>", f);
    put_num(f, v, decimals);
    fputs("</td>", f);
}

static void td_text(FILE *f, const char *text)
{
    fputs("<td class=\"t\">", f);
    rf_svg_escape(f, text);
    fputs("</td>", f);
}

static void figure_html(FILE *f, const char *file, const char *caption)
{
    fprintf(f, "<figure><img src=\"%s\" alt=\"", file);
    rf_svg_escape(f, caption);
    fputs("\"><figcaption>", f);
    rf_svg_escape(f, caption);
    fputs("</figcaption></figure>\n", f);
}

static double pct(double part, double whole)
{
    return whole > 0 ? 100.0 * part / whole : NAN;
}

/* ---- section: the road ---------------------------------------------------------------- */

static int section_road(report *r)
{
    FILE *f = r->body;
    size_t ncontrol = 0;
    for (size_t k = 0; k < r->nmea; k++)
        ncontrol += is_control(&r->mea[k]);
    fputs("<h2 id=\"road\">At the road: arrival position and velocity (Fig. 10)</h2>\n", f);
    if (!ncontrol) {
        fputs("<p>The project has no control line (a measure of kind <code>control</code>, such "
              "as the mountainside edge of the road), so there are no arrival figures and no "
              "empirical crosscheck.</p>\n",
              f);
        fputs("<li>No control line in the project: arrival position and velocity at the road "
              "and the empirical crosscheck are skipped.</li>\n",
              r->notes);
        return 0;
    }
    crosscheck *cc = calloc(r->nrel ? r->nrel : 1, sizeof *cc);
    if (!cc)
        return oom(r);
    int status = 0;
    for (size_t k = 0; k < r->nmea && !status; k++) {
        const rep_measure *m = &r->mea[k];
        if (!is_control(m))
            continue;
        road_stats rs;
        if (load_arrivals(r, m, &rs)) {
            status = -1;
            break;
        }
        for (size_t j = 0; j < r->nrel; j++)
            crosscheck_release(r, m, &rs, j, &cc[j]);
        fputs("<h3>", f);
        rf_svg_escape(f, m->name);
        fputs("</h3>\n<p>", f);
        fprintf(f, "%zu of %ld trajectories (", rs.n, r->n_traj);
        put_num(f, pct((double)rs.n, (double)r->n_traj), 1);
        fputs(" %) crossed this line", f);
        if (rs.n) {
            fputs(", at positions ", f);
            put_num(f, rs.s_min, 1);
            fputs(" to ", f);
            put_num(f, rs.s_max, 1);
            fputs(" m along it (spread ", f);
            put_num(f, rs.s_max - rs.s_min, 1);
            fputs(" m), with a mean velocity of ", f);
            put_num(f, rs.v_mean, 1);
            fputs(" m/s, at most ", f);
            put_num(f, rs.v_max, 1);
            fputs(" m/s, and at most ", f);
            put_num(f, rs.e_max, 0);
            fputs(" kJ", f);
        }
        fputs(". Positions are measured along the line from its first point; each trajectory "
              "counts once, at its first crossing.</p>\n",
              f);

        fprintf(r->summary, "<li>");
        rf_svg_escape(r->summary, m->name);
        fprintf(r->summary, ": %zu of %ld rocks (", rs.n, r->n_traj);
        put_num(r->summary, pct((double)rs.n, (double)r->n_traj), 1);
        fputs(" %) arrive", r->summary);
        if (rs.n) {
            fputs(", spread over ", r->summary);
            put_num(r->summary, rs.s_max - rs.s_min, 1);
            fputs(" m; velocity mean ", r->summary);
            put_num(r->summary, rs.v_mean, 1);
            fputs(" m/s, max ", r->summary);
            put_num(r->summary, rs.v_max, 1);
            fputs(" m/s", r->summary);
        }
        fputs(".</li>\n", r->summary);

        if (rs.n) {
            char fpos[64], fvel[64];
            snprintf(fpos, sizeof fpos, "road-%ld-position.svg", m->idx);
            snprintf(fvel, sizeof fvel, "road-%ld-velocity.svg", m->idx);
            if (figure_road_position(r, m, &rs, cc, fpos) ||
                figure_road_velocity(r, m, &rs, cc, fvel)) {
                status = -1;
                free(rs.a);
                break;
            }
            char cap[600];
            snprintf(cap, sizeof cap,
                     "Fig. 10a: where the rocks cross %s, with the empirical attainment range "
                     "of each release (Fig. 1b, 2 L tan 45 deg)",
                     m->name);
            figure_html(f, fpos, cap);
            snprintf(cap, sizeof cap,
                     "Fig. 10b: velocity of the rocks crossing %s, with Eq. 1 velocities", m->name);
            figure_html(f, fvel, cap);
        } else {
            fputs("<p>No rock reached this line: no arrival figures.</p>\n", f);
        }

        /* the empirical crosscheck, beside the simulated values */
        fputs("<p>Empirical crosscheck (section 2.1): Eq. 1 velocity V = &radic;(1 &minus; "
              "&mu;/tan &theta;) &radic;(2 g H) on the equivalent straight slope from the "
              "release to this line (H the drop, L the horizontal distance, &theta; = atan(H/L)"
              "), and the attainment width 2 L tan 45&deg; of Fig. 1b.</p>\n",
              f);
        fputs("<table><tr><th>release</th><th>L (m)</th><th>H (m)</th><th>&theta; (&deg;)</th>",
              f);
        if (isfinite(r->mu)) {
            fputs("<th>V Eq. 1, &mu; = ", f);
            put_num(f, r->mu, 2);
            fputs(" (project) (m/s)</th>", f);
        }
        fputs("<th>V Eq. 1, &mu; = ", f);
        put_num(f, rf_table2_friction('D'), 2);
        fputs(" (Table 2, D) (m/s)</th><th>simulated V mean (m/s)</th>"
              "<th>simulated V max (m/s)</th><th>rocks arriving</th>"
              "<th>attainment width 2 L tan 45&deg; (m)</th><th>simulated spread (m)</th></tr>\n",
              f);
        for (size_t j = 0; j < r->nrel; j++) {
            const crosscheck *c = &cc[j];
            fputs("<tr>", f);
            td_text(f, r->rel[j].name);
            td_num(f, c->L, 1);
            td_num(f, c->H, 1);
            td_num(f, c->theta * 180.0 / M_PI, 1);
            if (isfinite(r->mu))
                td_num(f, c->v_project, 1);
            td_num(f, c->v_class_d, 1);
            td_num(f, c->v_mean, 1);
            td_num(f, c->v_max, 1);
            fprintf(f, "<td>%ld</td>", c->n);
            td_num(f, c->width, 0);
            td_num(f, c->n ? c->s_max - c->s_min : NAN, 1);
            fputs("</tr>\n", f);
            if (j < 4 && isfinite(c->v_class_d)) {
                fputs("<li>Crosscheck from ", r->summary);
                rf_svg_escape(r->summary, r->rel[j].name);
                fputs(" to ", r->summary);
                rf_svg_escape(r->summary, m->name);
                fputs(": Eq. 1 with &mu; = ", r->summary);
                put_num(r->summary, rf_table2_friction('D'), 2);
                fputs(" gives ", r->summary);
                put_num(r->summary, c->v_class_d, 1);
                fputs(" m/s and the empirical attainment width is ", r->summary);
                put_num(r->summary, c->width, 0);
                if (c->n) {
                    fputs(" m, against a simulated maximum velocity of ", r->summary);
                    put_num(r->summary, c->v_max, 1);
                    fputs(" m/s and a simulated spread of ", r->summary);
                    put_num(r->summary, c->s_max - c->s_min, 1);
                    fputs(" m.</li>\n", r->summary);
                } else {
                    fputs(" m; no simulated rock from there reached the line.</li>\n",
                          r->summary);
                }
            }
        }
        fputs("</table>\n", f);
        if (!isfinite(r->mu))
            fputs("<p>The run stores no terrain: the mean surface friction is unknown, and "
                  "the road's height comes from the crossings (centre height minus passing "
                  "height).</p>\n",
                  f);
        free(rs.a);
    }
    free(cc);
    return status;
}

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
    sqlite3_stmt *st = prep(r, sql, r->run);
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
        db_error(r); /* an aggregate always gives a row */
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
    map_cell *c = next_elem(r, ctx);
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
    if (open_plan(r, &s, reach ? "hazard-reach.svg" : "hazard-energy.svg", title))
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
    draw_contours(r, &s, 1);
    legend l = plan_overlays(r, &s);
    if (reach)
        legend_classes(&l, "Reach probability", REACH_LIMITS, N_REACH_CLASSES - 1, 100.0, "%",
                       REACH_COLOURS, "");
    else
        legend_classes(&l, "Largest energy (kJ)", rf_report_energy_limits,
                       RF_REPORT_N_ENERGY_LIMITS, 1.0, "kJ", ENERGY_COLOURS, "class=\"class\" ");
    return close_plan(r, &l);
}

static int section_hazard(report *r)
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
    int status = load_rows(r,
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
    put_num(f, h.emax, 0);
    fputs(" kJ (95th percentile ", f);
    put_num(f, h.p95max, 0);
    fputs(" kJ).</p>\n", f);
    figure_html(f, "hazard-energy.svg",
                "Fig. 12: hazard map, largest kinetic energy per cell (kJ) in classes");
    figure_html(f, "hazard-reach.svg",
                "Reach probability: share of all trajectories that crossed each cell");
    fprintf(r->summary, "<li>Hazard map: %ld cells; %ld reach 3000 kJ or more, %ld reach 6000 kJ "
                        "or more; largest energy ",
            h.ncells, over3000, over6000);
    put_num(r->summary, h.emax, 0);
    fputs(" kJ.</li>\n", r->summary);
    return 0;
}

/* ---- section: measures ---------------------------------------------------------------- */

typedef struct capacity_line {
    double kj;
    char label[64];
} capacity_line;

static size_t capacity_lines(const rep_measure *m, capacity_line *out)
{
    size_t n = 0;
    if (isfinite(m->sel)) {
        out[n].kj = m->sel;
        snprintf(out[n++].label, sizeof out->label, "SEL %.0f kJ", m->sel);
    }
    if (isfinite(m->mel)) {
        out[n].kj = m->mel;
        snprintf(out[n++].label, sizeof out->label, "MEL %.0f kJ", m->mel);
    }
    for (int k = 0; k < RF_N_LIMIT_STATES; k++) {
        if (!isfinite(m->cap[k]))
            continue;
        int dup = 0;
        for (size_t j = 0; j < n; j++)
            dup |= out[j].kj == m->cap[k];
        if (dup)
            continue;
        out[n].kj = m->cap[k];
        static const char *const names[RF_N_LIMIT_STATES] = {"serviceability", "restorability",
                                                             "ultimate", "near collapse"};
        snprintf(out[n++].label, sizeof out->label, "%s %.0f kJ", names[k], m->cap[k]);
    }
    return n;
}

static int figure_measure(report *r, const rep_measure *m, const rf_crossing_row *x, size_t n,
                          const char *file)
{
    capacity_line caps[RF_N_LIMIT_STATES + 2];
    size_t ncaps = capacity_lines(m, caps);
    double hi = 1.0;
    for (size_t i = 0; i < n; i++)
        grow(&hi, &hi, x[i].energy);
    for (size_t k = 0; k < ncaps; k++)
        grow(&hi, &hi, caps[k].kj);
    hi *= 1.06;
    double lo = 0.0, bw = rf_svg_nice_step(hi, 30);
    hist_chart h = {.ns = N_OUTCOMES, .nlegend = N_OUTCOMES, .fills = OUTCOME_COLOURS,
                    .labels = OUTCOME_LABELS};
    if (hist_bins(r, &h, &lo, &hi, bw))
        return -1;
    for (size_t i = 0; i < n; i++)
        hist_add(&h, (size_t)OUTCOME_STACK[x[i].outcome], x[i].energy);
    double cmax = hist_top(&h);
    char title[600];
    snprintf(title, sizeof title, "Energy at %s (%s) against its capacities", m->name,
             m->kind_name);
    if (hist_open(r, &h, file, title, cmax * 1.12))
        return -1;
    rf_svg *s = &h.s;
    for (size_t k = 0; k < ncaps; k++)
        vertical_marker(s, caps[k].kj,
                        "class=\"capacity\" stroke=\"#000\" stroke-width=\"1.5\" "
                        "stroke-dasharray=\"6 3\"",
                        caps[k].label);
    return hist_close(r, &h, "kinetic energy at the crossing (kJ)", "number of crossings");
}

/* A table of a query's rows: the table and its header row go out before the first
 * row, so a query without rows writes nothing. */
typedef struct table_ctx {
    FILE *f;
    const char *header; /* the <tr> of <th> cells */
    int rows;
    row_fn cells;       /* writes the <td> cells of one row */
    void *ctx;
} table_ctx;

static int table_row(report *r, sqlite3_stmt *st, void *ctx)
{
    table_ctx *t = ctx;
    if (!t->rows++) {
        fputs("<table>", t->f);
        fputs(t->header, t->f);
    }
    fputs("<tr>", t->f);
    if (t->cells(r, st, t->ctx))
        return -1;
    fputs("</tr>\n", t->f);
    return 0;
}

/* Writes the table of the rows of sql (?1 = id) to f; returns the number of rows, or
 * -1 with r->err set. */
static int query_table(report *r, FILE *f, const char *header, const char *sql, int64_t id,
                       row_fn cells, void *ctx)
{
    table_ctx t = {f, header, 0, cells, ctx};
    if (each_row(r, sql, id, table_row, &t))
        return -1;
    if (t.rows)
        fputs("</table>\n", f);
    return t.rows;
}

static int classification_cells(report *r, sqlite3_stmt *st, void *ctx)
{
    (void)r;
    FILE *f = ctx;
    const char *ls = (const char *)sqlite3_column_text(st, 0);
    td_text(f, ls ? ls : "(none)");
    double n = sqlite3_column_double(st, 1);
    fprintf(f, "<td>%.0f</td>", n);
    td_num(f, pct(n, sqlite3_column_double(st, 3)), 1);
    fprintf(f, "<td>%.0f</td>", sqlite3_column_double(st, 2));
    return 0;
}

/* Shares of the limit states from `rockfall check` (classifications), when present. */
static int measure_classifications(report *r, const rep_measure *m)
{
    FILE *f = r->body;
    /* the total over the groups is the measure's count of classifications */
    int rows = query_table(r, f,
                           "<tr><th>limit state reached</th><th>crossings</th><th>share (%)</th>"
                           "<th>meet the required state</th></tr>\n",
                           "SELECT c.limit_state, count(*), sum(c.ok), sum(count(*)) OVER ()"
                           " FROM classifications c"
                           " JOIN interceptions i ON i.id = c.interception_id"
                           " WHERE i.measure_id = ?1 GROUP BY c.limit_state"
                           " ORDER BY CASE c.limit_state WHEN 'serviceability' THEN 0"
                           " WHEN 'restorability' THEN 1 WHEN 'ultimate' THEN 2"
                           " WHEN 'near_collapse' THEN 3 WHEN 'collapse' THEN 4"
                           " WHEN 'overtopped' THEN 5 ELSE 6 END, c.limit_state",
                           m->id, classification_cells, f);
    if (rows < 0)
        return -1;
    if (!rows)
        fputs("<p>No classifications stored for this measure (run <code>rockfall check</code> "
              "to classify each crossing against Table 3).</p>\n",
              f);
    return 0;
}

/* The cells of a check, counted as passed or failed. */
typedef struct check_tally {
    FILE *f;
    long *npass, *nfail;
} check_tally;

static int check_cells(report *r, sqlite3_stmt *st, void *ctx)
{
    (void)r;
    check_tally *c = ctx;
    FILE *f = c->f;
    int passed = sqlite3_column_int(st, 3);
    td_text(f, (const char *)sqlite3_column_text(st, 0));
    td_num(f, rf_query_column_real(st, 1), 3);
    td_num(f, rf_query_column_real(st, 2), 3);
    fprintf(f, "<td class=\"%s\">%s</td>", passed ? "pass" : "fail", passed ? "pass" : "FAIL");
    if (passed)
        (*c->npass)++;
    else
        (*c->nfail)++;
    return 0;
}

/* The checks of a measure, or with measure_id 0 those of the whole run; returns the
 * number of rows or -1. */
static int checks_table(report *r, FILE *f, int64_t measure_id, long *npass, long *nfail)
{
    check_tally c = {f, npass, nfail};
    return query_table(r, f,
                       "<tr><th>check</th><th>value</th><th>threshold</th><th>result</th></tr>\n",
                       measure_id > 0 ? "SELECT rule, value, threshold, passed FROM checks"
                                        " WHERE measure_id = ?1 ORDER BY id"
                                      : "SELECT rule, value, threshold, passed FROM checks"
                                        " WHERE run_id = ?1 AND measure_id IS NULL ORDER BY id",
                       measure_id > 0 ? measure_id : r->run, check_cells, &c);
}

/* What the measure table found for a measure, kept for its section (its crossings
 * are read one measure at a time, for its statistics, share and figure). */
typedef struct measure_found {
    rf_measure_stats stats;
    double share; /* % within serviceability, not overtopped; NAN when not defined */
} measure_found;

/* The file of a measure's energy figure. */
static void measure_figure_file(const rep_measure *m, char *file, size_t n)
{
    snprintf(file, n, "measure-%ld-energy.svg", m->idx);
}

/* The share of the crossings with an energy within `capacity` that are not
 * overtopped, counted as SQL's avg(energy_kj <= capacity AND outcome <> 'overtopped'):
 * a crossing without an energy counts (as outside) only when overtopped. */
static double share_within(const rf_crossing_row *x, size_t n, double capacity)
{
    long within = 0, counted = 0;
    for (size_t i = 0; i < n; i++) {
        int over = x[i].outcome == RF_OUT_OVERTOPPED;
        if (isnan(x[i].energy) && !over)
            continue;
        counted++;
        within += !over && x[i].energy <= capacity;
    }
    return counted ? (double)within / (double)counted : NAN;
}

static int section_measures(report *r, long *npass, long *nfail)
{
    FILE *f = r->body;
    fputs("<h2 id=\"measures\">Energy at the measures</h2>\n", f);
    if (!r->nmea) {
        fputs("<p>The project has no measures.</p>\n", f);
        return 0;
    }
    fputs("<table><tr><th>measure</th><th>kind</th><th>importance</th><th>height (m)</th>"
          "<th>crossings</th><th>stopped</th><th>overtopped</th><th>broke through</th>"
          "<th>passed</th><th>E50</th><th>E90</th><th>E95</th><th>E99</th><th>Emax (kJ)</th>"
          "<th>h95 (m)</th><th>SEL / serviceability (kJ)</th><th>MEL / ultimate (kJ)</th>"
          "<th>within serviceability, not overtopped (%)</th></tr>\n",
          f);
    measure_found *mc = calloc(r->nmea, sizeof *mc);
    if (!mc)
        return oom(r);
    for (size_t k = 0; k < r->nmea; k++) {
        const rep_measure *m = &r->mea[k];
        measure_found *c = &mc[k];
        rf_crossing_row *x = NULL;
        size_t nx = 0;
        const rf_measure_stats *s = &c->stats;
        double service = isfinite(m->cap[RF_SERVICEABILITY]) ? m->cap[RF_SERVICEABILITY] : m->sel;
        int failed = rf_query_crossings(r->db, m->id, &x, &nx, r->err) ||
                     rf_measure_stats_of(x, nx, &c->stats, r->err);
        if (!failed) {
            c->share = !is_control(m) && isfinite(service) && s->n
                           ? 100.0 * share_within(x, nx, service)
                           : NAN;
            char file[64];
            measure_figure_file(m, file, sizeof file);
            failed = s->n > 0 && figure_measure(r, m, x, nx, file);
        }
        free(x);
        if (failed) {
            free(mc);
            return -1;
        }
        fputs("<tr>", f);
        td_text(f, m->name);
        td_text(f, m->kind_name);
        td_text(f, m->importance_name);
        td_num(f, m->height, 1);
        fprintf(f, "<td>%ld</td><td>%ld</td><td>%ld</td><td>%ld</td><td>%ld</td>", s->n,
                s->n_stopped, s->n_overtopped, s->n_broke_through, s->n_passed);
        td_num(f, s->energy_p50, 0);
        td_num(f, s->energy_p90, 0);
        td_num(f, s->energy_p95, 0);
        td_num(f, s->energy_p99, 0);
        td_num(f, s->energy_max, 0);
        td_num(f, s->height_p95, 2);
        td_num(f, service, 0);
        td_num(f, isfinite(m->cap[RF_ULTIMATE]) ? m->cap[RF_ULTIMATE] : m->mel, 0);
        td_num(f, c->share, 1);
        fputs("</tr>\n", f);
    }
    fputs("</table>\n<p>Energies in kJ, nearest-rank percentiles over all crossings. The "
          "paper's check: a layout passes when the serviceability limit state holds for over "
          "90 % of the expected rockfalls.</p>\n",
          f);
    int status = 0;
    for (size_t k = 0; k < r->nmea && !status; k++) {
        const rep_measure *m = &r->mea[k];
        const rf_measure_stats *s = &mc[k].stats;
        fputs("<h3>", f);
        rf_svg_escape(f, m->name);
        fputs(" (", f);
        rf_svg_escape(f, m->kind_name);
        fputs(")</h3>\n", f);
        if (!is_control(m)) {
            fputs("<li>", r->summary);
            rf_svg_escape(r->summary, m->name);
            fprintf(r->summary,
                    " (%s): %ld crossings, %ld stopped, %ld overtopped, %ld broke through",
                    m->kind_name, s->n, s->n_stopped, s->n_overtopped, s->n_broke_through);
            /* the verdict is the rules engine's, as stored in `checks` */
            double stored = NAN, passed = NAN;
            sqlite3_stmt *st = prep(r,
                                    "SELECT value, passed FROM checks WHERE measure_id = ?1 AND"
                                    " rule = 'serviceability_share'",
                                    m->id);
            if (st && sqlite3_step(st) == SQLITE_ROW) {
                stored = rf_query_column_real(st, 0);
                passed = rf_query_column_real(st, 1);
            }
            sqlite3_finalize(st);
            if (isfinite(stored)) {
                fputs("; within serviceability: ", r->summary);
                put_num(r->summary, 100.0 * stored, 1);
                fprintf(r->summary, " %% (%s the serviceability check)",
                        passed == 1.0 ? "passes" : "fails");
            } else if (isfinite(mc[k].share)) {
                fputs("; within serviceability: ", r->summary);
                put_num(r->summary, mc[k].share, 1);
                fputs(" % (no design check stored for this run: rockfall check)", r->summary);
            }
            fputs(".</li>\n", r->summary);
        }
        if (s->n == 0) {
            fputs("<p>No rock crossed this measure.</p>\n", f);
            continue;
        }
        char cap[600];
        snprintf(cap, sizeof cap,
                 "Energy of the rocks crossing %s by outcome, with its capacities (dashed)",
                 m->name);
        char file[64];
        measure_figure_file(m, file, sizeof file);
        figure_html(f, file, cap);
        if (!is_control(m) && measure_classifications(r, m)) {
            status = -1;
            break;
        }
        if (checks_table(r, f, m->id, npass, nfail) < 0)
            status = -1;
    }
    free(mc);
    return status;
}

/* ---- the other sections -------------------------------------------------------------- */

static void section_head(report *r, FILE *f)
{
    fputs("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>rockfall "
          "report: ",
          f);
    rf_svg_escape(f, r->project);
    fputs("</title>\n<style>\n"
          "body{font-family:\"DejaVu Sans\",Arial,Helvetica,sans-serif;max-width:72em;"
          "margin:1.5em auto;padding:0 1em;color:#222;line-height:1.4}\n"
          "h1{margin-bottom:.2em}h2{border-bottom:2px solid #ccc;padding-bottom:.2em;"
          "margin-top:1.8em}\n"
          "table{border-collapse:collapse;margin:.6em 0;font-size:.92em;display:block;"
          "overflow-x:auto;max-width:100%}\n"
          "td,th{border:1px solid #aaa;padding:.2em .5em;text-align:right}\n"
          "td.t{text-align:left}th{background:#eee}\n"
          "td.pass{color:#1a7f1a;font-weight:bold}td.fail{color:#b00;font-weight:bold}\n"
          "figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}\n"
          "figcaption{font-size:.9em;color:#444}\n"
          ".summary{background:#f5f7fa;border:1px solid #d0d7e0;padding:.6em 1.2em}\n"
          ".notes{background:#fff8e5;border:1px solid #e6c96b;padding:.6em 1.2em}\n"
          "</style></head><body>\n<h1>",
          f);
    rf_svg_escape(f, r->project);
    fputs("</h1>\n<p>Run ", f);
    fprintf(f, "%lld (", (long long)r->run);
    rf_svg_escape(f, r->status);
    fputs("), seed ", f);
    rf_svg_escape(f, r->seed);
    fprintf(f, ", %ld trajectories, started ", r->n_traj);
    rf_svg_escape(f, r->started);
    if (r->finished[0]) {
        fputs(", finished ", f);
        rf_svg_escape(f, r->finished);
    }
    fputs(", rockfall ", f);
    rf_svg_escape(f, r->version);
    fputs(". Project file: <code>", f);
    rf_svg_escape(f, r->project_path[0] ? r->project_path : "(not recorded)");
    fputs("</code>.</p>\n", f);
}

static void section_releases(report *r, FILE *f)
{
    fputs("<h2>Releases</h2>\n<table><tr><th>release</th><th>x (m)</th><th>y (m)</th>"
          "<th>z (m)</th><th>rock</th><th>mass (kg)</th><th>action level</th>"
          "<th>trajectories</th></tr>\n",
          f);
    for (size_t k = 0; k < r->nrel; k++) {
        const rep_release *e = &r->rel[k];
        fputs("<tr>", f);
        td_text(f, e->name);
        td_num(f, e->x, 1);
        td_num(f, e->y, 1);
        td_num(f, e->z, 1);
        td_text(f, e->rock);
        td_num(f, e->mass, 0);
        fprintf(f, "<td>%d</td><td>%ld</td></tr>\n", e->action_level, e->count);
    }
    fputs("</table>\n", f);
}

static int end_row(report *r, sqlite3_stmt *st, void *ctx)
{
    (void)r;
    FILE *f = ctx;
    fputs("<tr>", f);
    td_text(f, (const char *)sqlite3_column_text(st, 0));
    td_text(f, (const char *)sqlite3_column_text(st, 1));
    fprintf(f, "<td>%lld</td>", (long long)sqlite3_column_int64(st, 2));
    td_num(f, rf_query_column_real(st, 3), 1);
    td_num(f, rf_query_column_real(st, 4), 1);
    td_num(f, rf_query_column_real(st, 5), 0);
    td_num(f, rf_query_column_real(st, 6), 0);
    fputs("</tr>\n", f);
    return 0;
}

static int section_ends(report *r, FILE *f)
{
    fputs("<h2 id=\"ends\">Where the trajectories ended</h2>\n<table><tr><th>release</th><th>end</th>"
          "<th>count</th><th>mean duration (s)</th><th>mean path length (m)</th>"
          "<th>mean largest energy (kJ)</th><th>largest energy (kJ)</th></tr>\n",
          f);
    int rc = each_row(r,
                      "SELECT r.name, t.stop_reason, count(*), avg(t.duration_s),"
                      " avg(t.path_length_m), avg(t.max_energy_kj), max(t.max_energy_kj)"
                      " FROM trajectories t JOIN releases r ON r.id = t.release_id"
                      " WHERE t.run_id = ?1 GROUP BY r.id, t.stop_reason"
                      " ORDER BY r.idx, t.stop_reason",
                      r->run, end_row, f);
    fputs("</table>\n", f);
    return rc;
}

/* ---- the report ------------------------------------------------------------------------ */

static int make_dirs(const char *dir, rf_error *err)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0777) && errno != EEXIST)
            return rf_error_set(err, buf, 0, 0, "cannot create folder: %s", strerror(errno));
        *p = '/';
    }
    if (mkdir(buf, 0777) && errno != EEXIST)
        return rf_error_set(err, dir, 0, 0, "cannot create folder: %s", strerror(errno));
    struct stat sb;
    if (stat(buf, &sb) || !S_ISDIR(sb.st_mode))
        return rf_error_set(err, dir, 0, 0, "not a folder");
    return 0;
}

static void free_report(report *r)
{
    free(r->rel_fills);
    free(r->rel_names);
    rf_run_view_free(&r->view);
}

/* A memory stream's text, closed. */
static int close_stream(FILE *f)
{
    return f ? fclose(f) : 0;
}

static int write_sections(report *r, long *npass, long *nfail)
{
    if (figure_plan(r))
        return -1;
    fputs("<h2 id=\"plan\">Plan view (Fig. 9, 11)</h2>\n", r->body);
    fprintf(r->body,
            "<p>The sampled paths (%ld trajectories with stored path points) over the terrain "
            "contours, the release points, the measures and the points where every trajectory "
            "ended. North is up; x and y in metres.</p>\n",
            r->n_path_traj);
    figure_html(r->body, "plan.svg",
                "Fig. 9 and 11: trajectories of the rocks in plan, with releases and measures");
    if (!r->n_path_traj)
        fputs("<li>No sampled paths are stored for this run (<code>simulation.paths</code>): the "
              "plan view shows only where the trajectories ended.</li>\n",
              r->notes);
    if (section_road(r) || section_hazard(r) || section_measures(r, npass, nfail))
        return -1;
    fputs("<h2 id=\"checks\">Checks of the whole run</h2>\n", r->body);
    int rows = checks_table(r, r->body, 0, npass, nfail);
    if (rows < 0)
        return -1;
    if (!rows)
        fputs("<p>No run-wide checks stored.</p>\n", r->body);
    return section_ends(r, r->body);
}

int rf_report_write(sqlite3 *db, int64_t run, const char *dir, rf_error *err)
{
    report r = {.db = db, .run = run, .dir = dir, .err = err};
    char *sum_text = NULL, *notes_text = NULL, *body_text = NULL;
    size_t sum_len = 0, notes_len = 0, body_len = 0;
    long npass = 0, nfail = 0;
    int status = load_run(&r);
    if (!status)
        status = make_dirs(dir, err);
    if (!status)
        status = load_releases(&r);
    if (!status) {
        r.summary = open_memstream(&sum_text, &sum_len);
        r.notes = open_memstream(&notes_text, &notes_len);
        r.body = open_memstream(&body_text, &body_len);
        if (!r.summary || !r.notes || !r.body)
            status = oom(&r);
    }
    if (!status) {
        if (strcmp(r.status, "complete"))
            fputs("<li>This run is not complete: its results are partial.</li>\n", r.notes);
        note_terrain(&r);
        status = compute_extent(&r) || build_contour_grid(&r) ? -1 : 0;
    }
    if (!status) {
        fprintf(r.summary, "<li>%ld trajectories from %zu release point%s.</li>\n", r.n_traj,
                r.nrel, r.nrel == 1 ? "" : "s");
        status = write_sections(&r, &npass, &nfail);
    }
    if (!status) {
        if (npass + nfail)
            fprintf(r.summary, "<li>Design checks: %ld passed, %ld failed.</li>\n", npass, nfail);
        else
            fputs("<li>No design checks stored yet (<code>rockfall check</code> writes "
                  "them).</li>\n",
                  r.summary);
    }
    int bad_stream = close_stream(r.summary) | close_stream(r.notes) | close_stream(r.body);
    if (!status && bad_stream)
        status = oom(&r);
    if (!status) {
        char path[4096];
        snprintf(path, sizeof path, "%s/index.html", dir);
        FILE *f = fopen(path, "w");
        if (!f) {
            status = rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
        } else {
            section_head(&r, f);
            fputs("<div class=\"summary\"><h2 style=\"margin-top:.3em\">Summary</h2><ul>\n", f);
            fwrite(sum_text, 1, sum_len, f);
            fputs("</ul></div>\n", f);
            if (notes_len) {
                fputs("<div class=\"notes\"><ul>\n", f);
                fwrite(notes_text, 1, notes_len, f);
                fputs("</ul></div>\n", f);
            }
            section_releases(&r, f);
            fwrite(body_text, 1, body_len, f);
            fputs("</body></html>\n", f);
            int bad = ferror(f);
            if (fclose(f) || bad)
                status = rf_error_set(err, path, 0, 0, "cannot write: %s", strerror(errno));
        }
    }
    free(sum_text);
    free(notes_text);
    free(body_text);
    free_report(&r);
    return status;
}
