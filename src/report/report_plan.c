/* report_plan.c - the plan: its extent, the terrain contours from the stored grid,
 * the measures, releases and legends drawn on it, and the plan view (Fig. 9, 11). */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Two contour segments this close (m) to the labels' x are equally near. */
#define RF_LABEL_TIE 1e-6
/* Most stop points drawn on the plan. */
#define MAX_STOP_POINTS 20000

/* ---- extent and contours -------------------------------------------------------- */

int rep_compute_extent(report *r)
{
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    if (r->have_terrain) { /* the extent fitted when the terrain was stored */
        x0 = r->view.grid.x0;
        x1 = r->view.grid.x1;
        y0 = r->view.grid.y0;
        y1 = r->view.grid.y1;
    } else {
        for (size_t k = 0; k < r->nrel; k++) {
            rep_grow(&x0, &x1, r->rel[k].x);
            rep_grow(&y0, &y1, r->rel[k].y);
        }
        for (size_t k = 0; k < r->nmea; k++)
            for (size_t i = 0; i < r->mea[k].n; i++) {
                rep_grow(&x0, &x1, r->mea[k].xy[2 * i]);
                rep_grow(&y0, &y1, r->mea[k].xy[2 * i + 1]);
            }
        static const char *const sql[] = {
            "SELECT min(p.x), max(p.x), min(p.y), max(p.y) FROM path_points p"
            " JOIN trajectories t ON t.id = p.trajectory_id WHERE t.run_id = ?1",
            "SELECT min(stop_x), max(stop_x), min(stop_y), max(stop_y) FROM trajectories"
            " WHERE run_id = ?1",
            "SELECT min(x), max(x), min(y), max(y) FROM hazard_cells WHERE run_id = ?1",
        };
        for (size_t q = 0; q < sizeof sql / sizeof sql[0]; q++) {
            sqlite3_stmt *st = rep_prep(r, sql[q], r->run);
            if (!st)
                return -1;
            if (sqlite3_step(st) == SQLITE_ROW) {
                rep_grow(&x0, &x1, rf_query_column_real(st, 0));
                rep_grow(&x0, &x1, rf_query_column_real(st, 1));
                rep_grow(&y0, &y1, rf_query_column_real(st, 2));
                rep_grow(&y0, &y1, rf_query_column_real(st, 3));
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
int rep_build_contour_grid(report *r)
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
        rep_grow(&g->zmin, &g->zmax, t->z[k]);
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

void rep_draw_contours(report *r, rf_svg *s, int faint)
{
    const contour_grid *g = &r->grid;
    if (!g->z)
        return;
    double label_x = r->bx0 + 0.1 * (r->bx1 - r->bx0), label_y = 0.5 * (r->by0 + r->by1);
    rf_svg_raw(s, "<g fill=\"none\" stroke=\"%s\" stroke-linejoin=\"round\">\n",
               faint ? "#b0a597" : "#8c7b68");
    for (double level = ceil(g->zmin / g->interval) * g->interval; level <= g->zmax;
         level += g->interval) {
        int major = labs(lround(level / g->interval)) % 5 == 0;
        rf_svg_path_begin(s, major ? "stroke-width=\"1.2\"" : "stroke-width=\"0.5\"");
        double best = INFINITY, best_dy = INFINITY, lx = 0, ly = 0;
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
                    /* nearest the label's x; of equals (a contour along y), the one
                     * nearest the plot's middle height */
                    double d = fabs(0.5 * (xa + xb) - label_x);
                    double dy = fabs(0.5 * (ya + yb) - label_y);
                    if (major && (d < best - RF_LABEL_TIE || (d <= best + RF_LABEL_TIE &&
                                                              dy < best_dy))) {
                        best = d;
                        best_dy = dy;
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

int rep_open_plan(report *r, rf_svg *s, const char *file, const char *title)
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
                 rep_measure_colour(m), rep_is_control(m) ? "3" : "5",
                 rep_is_control(m) ? " stroke-dasharray=\"12 6\"" : "");
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
                 rep_measure_colour(m));
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
                   px, py - 8, px + 7, py + 5, px - 7, py + 5, rep_release_colour(k));
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

static void legend_title(legend *l, const char *title)
{
    rf_svg_text(l->s, l->x, l->y, "font-weight=\"bold\"", "%s", title);
    l->y += 20;
}

void rep_legend_swatch(legend *l, const char *swatch_attrs, const char *label)
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

/* The measures in the legend: the structures under their heading, the control lines
 * (dashed, thinner: lines whose crossings are counted) under theirs. */
static void legend_measures(report *r, legend *l)
{
    for (int control = 0; control < 2; control++) {
        int any = 0;
        for (size_t k = 0; k < r->nmea; k++) {
            const rep_measure *m = &r->mea[k];
            if (rep_is_control(m) != control)
                continue;
            if (!any++) {
                l->y += 8;
                legend_title(l, control ? "Control lines" : "Structures");
            }
            char attrs[160], label[300];
            snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"%s\"%s",
                     rep_measure_colour(m), control ? "3" : "5",
                     control ? " stroke-dasharray=\"8 4\"" : "");
            if (control)
                snprintf(label, sizeof label, "%s", m->name);
            else
                snprintf(label, sizeof label, "%s (%s)", m->name, m->kind_name);
            legend_line(l, attrs, label);
        }
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
void rep_legend_classes(legend *l, const char *title, const double *lim, int nlim,
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
        rep_legend_swatch(l, attrs, label);
    }
}

/* The classes of a map of counts from 1 (whole numbers), the highest first: "1" (or
 * "1 - a-1"), "a - b-1", ">= b". */
void rep_legend_counts(legend *l, const char *title, const double *lim, int nlim,
                       const char *const *colours)
{
    legend_title(l, title);
    for (int c = nlim; c >= 0; c--) {
        char label[120], attrs[120];
        double lo = c ? lim[c - 1] : 1.0, hi = c < nlim ? lim[c] - 1.0 : INFINITY;
        if (c == nlim)
            snprintf(label, sizeof label, ">= %g", lo);
        else if (hi > lo)
            snprintf(label, sizeof label, "%g - %g", lo, hi);
        else
            snprintf(label, sizeof label, "%g", lo);
        snprintf(attrs, sizeof attrs, "fill=\"%s\" stroke=\"#444\" stroke-width=\"0.5\"",
                 colours[c]);
        rep_legend_swatch(l, attrs, label);
    }
}

/* Over a plan's own layers: the measures, the releases, the north arrow, the scale bar
 * and the axes.  Returns the legend beside the plot, for the plan's own entries. */
legend rep_plan_overlays(report *r, rf_svg *s)
{
    draw_measures(r, s);
    draw_releases(r, s);
    draw_north_and_scale(s);
    rf_svg_axes(s, "x (m)", "y (m)");
    return (legend){s, s->right + 20, s->top + 10};
}

/* The measures and the contours in the legend, below the plan's own entries, and the
 * end of the plan. */
int rep_close_plan(report *r, legend *l)
{
    legend_measures(r, l);
    l->y += 8;
    legend_contours(r, l);
    return rf_svg_close(l->s, r->err);
}

/* ---- figure: plan view (Fig. 9, 11) -------------------------------------------------- */

/* The plan view's caption: what it draws, counted. */
void rep_plan_caption(const report *r, char *buf, size_t n)
{
    snprintf(buf, n,
             "Fig. 9 and 11: the sampled paths of %ld of the %ld trajectories, coloured by "
             "release, the end points of %ld, the release points and the measures in plan%s",
             r->n_path_traj, r->n_traj, r->n_stop_points,
             r->grid.z ? ", over the terrain contours" : "");
}


int rep_figure_plan(report *r, const char *file)
{
    rf_svg s;
    if (rep_open_plan(r, &s, file, "Plan view: trajectories, releases and measures"))
        return -1;
    rep_draw_contours(r, &s, 0);

    /* sampled paths, one polyline per trajectory, coloured by release */
    sqlite3_stmt *st = rep_prep(r,
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
                     rep_release_colour(rep_release_index(r, sqlite3_column_int64(st, 1))));
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
        return rep_db_error(r);
    }
    r->n_path_traj = npaths;

    /* where every trajectory ended */
    char sql[128];
    snprintf(sql, sizeof sql,
             "SELECT stop_x, stop_y FROM trajectories WHERE run_id = ?1 ORDER BY id LIMIT %d",
             MAX_STOP_POINTS);
    st = rep_prep(r, sql, r->run);
    if (!st) {
        rf_svg_close(&s, NULL);
        return -1;
    }
    rf_svg_raw(&s, "<g clip-path=\"url(#plot)\" fill=\"black\" fill-opacity=\"0.55\">\n");
    r->n_stop_points = 0;
    while (sqlite3_step(st) == SQLITE_ROW) {
        double x = rf_query_column_real(st, 0), y = rf_query_column_real(st, 1);
        if (isfinite(x) && isfinite(y) && ++r->n_stop_points)
            rf_svg_raw(&s, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"1.8\"/>\n", rf_svg_px(&s, x),
                       rf_svg_py(&s, y));
    }
    sqlite3_finalize(st);
    rf_svg_raw(&s, "</g>\n");

    legend l = rep_plan_overlays(r, &s);
    legend_title(&l, "Releases and sampled paths");
    for (size_t k = 0; k < r->nrel; k++) {
        char attrs[80];
        snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"2\"", rep_release_colour(k));
        legend_line(&l, attrs, r->rel[k].name);
    }
    rep_legend_swatch(&l, "fill=\"black\" fill-opacity=\"0.55\" rx=\"6\"", "end points");
    return rep_close_plan(r, &l);
}
