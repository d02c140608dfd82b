/* report_road.c - the road section: arrivals along and velocity at each control line
 * (Fig. 10a, 10b), the histograms they share with the measures' figures, and the
 * empirical crosscheck (Eq. 1-2, Fig. 1b). */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/tolerances.h"
#include "rockfall/empirical.h"

/* Fig. 1b: the largest empirical spreading angle. */
#define ATTAINMENT_BETA_DEG 45.0
/* Most releases whose Eq. 1 velocities Fig. 10b draws (two lines each, labelled along
 * them); with more the crosscheck table holds them. */
#define MAX_EQ1_RELEASES 3
/* Right edge of the plot area of the 820 px charts; their legend goes beside it. */
#define CHART_RIGHT 670

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
    rep_arrival *a = rep_next_elem(r, &c->g);
    if (!a)
        return -1;
    a->rel = rep_release_index(r, sqlite3_column_int64(st, 0));
    a->s = rf_polyline_station(c->m->xy, c->m->n, rf_query_column_real(st, 1),
                               rf_query_column_real(st, 2), NULL, NULL, NULL);
    a->speed = rf_query_column_real(st, 3);
    a->energy = rf_query_column_real(st, 4);
    a->zground = rf_query_column_real(st, 5);
    rep_grow(&rs->s_min, &rs->s_max, a->s);
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
    if (rep_each_row(r,
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
        rep_grow(&c->s_min, &c->s_max, a->s);
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
    *lo = floor(*lo / bw + RF_TICK_SNAP) * bw;
    double top = ceil(*hi / bw - RF_TICK_SNAP) * bw;
    if (top <= *hi)
        top += bw;
    *hi = top;
    return (size_t)lround((*hi - *lo) / bw);
}

/* Empty bins [*lo, *hi) of width bw, widened to whole bins. */
int rep_hist_bins(report *r, hist_chart *h, double *lo, double *hi, double bw)
{
    h->nb = make_bins(lo, hi, bw);
    h->lo = *lo;
    h->hi = *hi;
    h->bw = bw;
    h->counts = calloc(h->ns * h->nb, sizeof *h->counts);
    return h->counts ? 0 : rep_oom(r);
}

/* Counts v in series k; a value outside the bins (or NAN) is left out. */
void rep_hist_add(hist_chart *h, size_t k, double v)
{
    double b = floor((v - h->lo) / h->bw);
    if (b >= 0 && b < (double)h->nb)
        h->counts[k * h->nb + (size_t)b] += 1;
}

/* The highest stack, at least 1. */
double rep_hist_top(const hist_chart *h)
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
int rep_hist_open(report *r, hist_chart *h, const char *file, const char *title, double ytop)
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
int rep_hist_close(report *r, hist_chart *h, const char *xlabel, const char *ylabel)
{
    rf_svg_axes(&h->s, xlabel, ylabel);
    legend l = {&h->s, h->s.right + 18, h->s.top + 10};
    for (size_t k = 0; k < h->nlegend; k++) {
        char attrs[80];
        snprintf(attrs, sizeof attrs, "fill=\"%s\" stroke=\"#222\" stroke-width=\"0.5\"",
                 h->fills[k]);
        rep_legend_swatch(&l, attrs, h->labels[k]);
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
    if (rep_hist_bins(r, h, lo, hi, bw))
        return -1;
    for (size_t i = 0; i < rs->n; i++)
        rep_hist_add(h, rs->a[i].rel, speed ? rs->a[i].speed : rs->a[i].s);
    return 0;
}

/* A vertical line at x across the plot, with its label along it from the top. */
void rep_vertical_marker(rf_svg *s, double x, const char *line_attrs, const char *label)
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

/* Fig. 10a with the attainment range of each release that has one; returns the number
 * of ranges drawn, or -1. */
static int figure_road_position(report *r, const rep_measure *m, const road_stats *rs,
                                const crosscheck *cc, const char *file)
{
    int ndrawn = 0;
    double lo = rs->s_min, hi = rs->s_max;
    double spread = hi - lo;
    for (size_t k = 0; k < r->nrel; k++) {
        if (!isfinite(cc[k].L))
            continue;
        rep_grow(&lo, &hi, fmax(0.0, cc[k].s_centre - cc[k].width / 2));
        rep_grow(&lo, &hi, fmin(rs->length, cc[k].s_centre + cc[k].width / 2));
    }
    double bw = rf_svg_nice_step(fmax(spread, 1.0), 15);
    while ((hi - lo) / bw > 300)
        bw = rf_svg_nice_step(bw * 2.1, 1);
    hist_chart h;
    if (arrivals_hist(r, rs, 0, &lo, &hi, bw, &h))
        return -1;
    double cmax = rep_hist_top(&h);
    double band = 0.09 * cmax;
    double ytop = cmax * 1.08 + band * (double)r->nrel + band * 0.5;

    char title[600];
    snprintf(title, sizeof title, "Arrival position along %s (Fig. 10a)", m->name);
    if (rep_hist_open(r, &h, file, title, ytop))
        return -1;
    rf_svg *s = &h.s;
    /* Fig. 1b: attainment range of each release at beta = 45 degrees */
    for (size_t k = 0; k < r->nrel; k++) {
        if (!isfinite(cc[k].L))
            continue;
        ndrawn++;
        double y = cmax * 1.08 + band * ((double)k + 0.5);
        double a = fmax(lo, cc[k].s_centre - cc[k].width / 2);
        double b = fmin(hi, cc[k].s_centre + cc[k].width / 2);
        char attrs[120];
        snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"3\"", rep_release_colour(k));
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
    return rep_hist_close(r, &h, xlabel, "number of rocks") ? -1 : ndrawn;
}

/* Fig. 10b with the Eq. 1 velocities of each release as lines when there are at most
 * MAX_EQ1_RELEASES releases; returns the number of lines drawn, or -1. */
static int figure_road_velocity(report *r, const rep_measure *m, const road_stats *rs,
                                const crosscheck *cc, const char *file)
{
    int lines = r->nrel <= MAX_EQ1_RELEASES, ndrawn = 0;
    double hi = rs->v_max;
    for (size_t k = 0; lines && k < r->nrel; k++) {
        rep_grow(&hi, &hi, cc[k].v_class_d);
        rep_grow(&hi, &hi, cc[k].v_project);
    }
    hi = fmax(hi * 1.05, 1.0);
    double lo = 0.0;
    double bw = rf_svg_nice_step(hi, 25);
    hist_chart h;
    if (arrivals_hist(r, rs, 1, &lo, &hi, bw, &h))
        return -1;
    double cmax = rep_hist_top(&h);
    char title[600];
    snprintf(title, sizeof title, "Velocity at %s (Fig. 10b)", m->name);
    if (rep_hist_open(r, &h, file, title, cmax * 1.15))
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
            ndrawn++;
            char attrs[120];
            snprintf(attrs, sizeof attrs, "stroke=\"%s\" stroke-width=\"2\" stroke-dasharray=\"%s\"",
                     j ? "#555" : "#000", j ? "3 3" : "8 4");
            char label[2048]; /* as long as rf_svg_text's */
            snprintf(label, sizeof label, "Eq. 1 from %s, %s: %.1f m/s", r->rel[k].name,
                     what[j], v[j]);
            rep_vertical_marker(s, v[j], attrs, label);
        }
    }
    char xlabel[600];
    snprintf(xlabel, sizeof xlabel, "velocity at %s (m/s)", m->name);
    return rep_hist_close(r, &h, xlabel, "number of rocks") ? -1 : ndrawn;
}

/* ---- section: the road ---------------------------------------------------------------- */

/* The line's arrivals in words, in the section and the summary. */
static void road_text(report *r, const rep_measure *m, const road_stats *rs)
{
    FILE *f = r->body;
    fputs("<h3>", f);
    rf_svg_escape(f, m->name);
    fputs("</h3>\n<p>", f);
    fprintf(f, "%zu of %ld trajectories (", rs->n, r->n_traj);
    rep_put_num(f, rep_pct((double)rs->n, (double)r->n_traj), 1);
    fputs(" %) crossed this line", f);
    if (rs->n) {
        fputs(", at positions ", f);
        rep_put_num(f, rs->s_min, 1);
        fputs(" to ", f);
        rep_put_num(f, rs->s_max, 1);
        fputs(" m along it (spread ", f);
        rep_put_num(f, rs->s_max - rs->s_min, 1);
        fputs(" m), with a mean velocity of ", f);
        rep_put_num(f, rs->v_mean, 1);
        fputs(" m/s, at most ", f);
        rep_put_num(f, rs->v_max, 1);
        fputs(" m/s, and at most ", f);
        rep_put_num(f, rs->e_max, 0);
        fputs(" kJ", f);
    }
    fputs(". Positions are measured along the line from its first point; each trajectory "
          "counts once, at its first crossing.</p>\n",
          f);

    fprintf(r->summary, "<li>");
    rf_svg_escape(r->summary, m->name);
    fprintf(r->summary, ": %zu of %ld rocks (", rs->n, r->n_traj);
    rep_put_num(r->summary, rep_pct((double)rs->n, (double)r->n_traj), 1);
    fputs(" %) arrive", r->summary);
    if (rs->n) {
        fputs(", spread over ", r->summary);
        rep_put_num(r->summary, rs->s_max - rs->s_min, 1);
        fputs(" m; velocity mean ", r->summary);
        rep_put_num(r->summary, rs->v_mean, 1);
        fputs(" m/s, max ", r->summary);
        rep_put_num(r->summary, rs->v_max, 1);
        fputs(" m/s", r->summary);
    }
    fputs(".</li>\n", r->summary);

}

/* The line's arrival figures (Fig. 10a, 10b). */
static int road_figures(report *r, const rep_measure *m, const road_stats *rs,
                        const crosscheck *cc)
{
    FILE *f = r->body;
    if (rs->n) {
        char fpos[64], fvel[64];
        snprintf(fpos, sizeof fpos, "road-%ld-position.svg", m->idx);
        snprintf(fvel, sizeof fvel, "road-%ld-velocity.svg", m->idx);
        int nranges = figure_road_position(r, m, rs, cc, fpos);
        int nlines = nranges < 0 ? -1 : figure_road_velocity(r, m, rs, cc, fvel);
        if (nranges < 0 || nlines < 0)
            return -1;
        char cap[800];
        int n = snprintf(cap, sizeof cap, "Fig. 10a: where the rocks cross %s, by release",
                         m->name);
        if (nranges)
            snprintf(cap + n, sizeof cap - (size_t)n,
                     ", with the empirical attainment range of %d release%s (Fig. 1b, "
                     "2 L tan 45 deg)",
                     nranges, nranges == 1 ? "" : "s");
        rep_figure_html(f, fpos, cap);
        n = snprintf(cap, sizeof cap, "Fig. 10b: velocity of the rocks crossing %s, by release",
                     m->name);
        if (nlines)
            snprintf(cap + n, sizeof cap - (size_t)n,
                     ", with %d Eq. 1 velocit%s of the releases (long dashes: mu of Table 2, "
                     "class D; short dashes: the project's mu)",
                     nlines, nlines == 1 ? "y" : "ies");
        else if (r->nrel > MAX_EQ1_RELEASES)
            snprintf(cap + n, sizeof cap - (size_t)n,
                     "; the Eq. 1 velocities of the %zu releases are not drawn (more than %d): "
                     "they are in the crosscheck table below",
                     r->nrel, MAX_EQ1_RELEASES);
        rep_figure_html(f, fvel, cap);
    } else {
        fputs("<p>No rock reached this line: no arrival figures.</p>\n", f);
    }
    return 0;
}

/* The empirical crosscheck of every release at the line, beside the simulated values. */
static void road_crosscheck(report *r, const rep_measure *m, const crosscheck *cc)
{
    FILE *f = r->body;
    fputs("<p>Empirical crosscheck (section 2.1): Eq. 1 velocity V = &radic;(1 &minus; "
          "&mu;/tan &theta;) &radic;(2 g H) on the equivalent straight slope from the "
          "release to this line (H the drop, L the horizontal distance, &theta; = atan(H/L)"
          "), and the attainment width 2 L tan 45&deg; of Fig. 1b.</p>\n",
          f);
    fputs("<table><tr><th>release</th><th>L (m)</th><th>H (m)</th><th>&theta; (&deg;)</th>",
          f);
    if (isfinite(r->mu)) {
        fputs("<th>V Eq. 1, &mu; = ", f);
        rep_put_num(f, r->mu, 2);
        fputs(" (project) (m/s)</th>", f);
    }
    fputs("<th>V Eq. 1, &mu; = ", f);
    rep_put_num(f, rf_table2_friction('D'), 2);
    fputs(" (Table 2, D) (m/s)</th><th>simulated V mean (m/s)</th>"
          "<th>simulated V max (m/s)</th><th>rocks arriving</th>"
          "<th>attainment width 2 L tan 45&deg; (m)</th><th>simulated spread (m)</th></tr>\n",
          f);
    for (size_t j = 0; j < r->nrel; j++) {
        const crosscheck *c = &cc[j];
        fputs("<tr>", f);
        rep_td_text(f, r->rel[j].name);
        rep_td_num(f, c->L, 1);
        rep_td_num(f, c->H, 1);
        rep_td_num(f, c->theta * 180.0 / M_PI, 1);
        if (isfinite(r->mu))
            rep_td_num(f, c->v_project, 1);
        rep_td_num(f, c->v_class_d, 1);
        rep_td_num(f, c->v_mean, 1);
        rep_td_num(f, c->v_max, 1);
        fprintf(f, "<td>%ld</td>", c->n);
        rep_td_num(f, c->width, 0);
        rep_td_num(f, c->n ? c->s_max - c->s_min : NAN, 1);
        fputs("</tr>\n", f);
        if (j < 4 && isfinite(c->v_class_d)) {
            fputs("<li>Crosscheck from ", r->summary);
            rf_svg_escape(r->summary, r->rel[j].name);
            fputs(" to ", r->summary);
            rf_svg_escape(r->summary, m->name);
            fputs(": Eq. 1 with &mu; = ", r->summary);
            rep_put_num(r->summary, rf_table2_friction('D'), 2);
            fputs(" gives ", r->summary);
            rep_put_num(r->summary, c->v_class_d, 1);
            fputs(" m/s and the empirical attainment width is ", r->summary);
            rep_put_num(r->summary, c->width, 0);
            if (c->n) {
                fputs(" m, against a simulated maximum velocity of ", r->summary);
                rep_put_num(r->summary, c->v_max, 1);
                fputs(" m/s and a simulated spread of ", r->summary);
                rep_put_num(r->summary, c->s_max - c->s_min, 1);
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
}

int rep_section_road(report *r)
{
    FILE *f = r->body;
    size_t ncontrol = 0;
    for (size_t k = 0; k < r->nmea; k++)
        ncontrol += rep_is_control(&r->mea[k]);
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
        return rep_oom(r);
    int status = 0;
    for (size_t k = 0; k < r->nmea && !status; k++) {
        const rep_measure *m = &r->mea[k];
        if (!rep_is_control(m))
            continue;
        road_stats rs;
        if (load_arrivals(r, m, &rs)) {
            status = -1;
            break;
        }
        for (size_t j = 0; j < r->nrel; j++)
            crosscheck_release(r, m, &rs, j, &cc[j]);
        road_text(r, m, &rs);
        if (road_figures(r, m, &rs, cc)) {
            status = -1;
            free(rs.a);
            break;
        }
        road_crosscheck(r, m, cc);
        free(rs.a);
    }
    free(cc);
    return status;
}
