/* report_measures.c - the measures section: the energy at each structure (barrier,
 * embankment) against its capacities and its passing height against its height, its
 * classifications and its checks; the control lines as what they are, lines whose
 * crossings are counted. */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The energy figure's stacks, bottom up: the stack of each outcome, then the labels
 * and colours of the stacks. */
#define N_OUTCOMES 4
static const int OUTCOME_STACK[N_OUTCOMES] = {[RF_OUT_STOPPED] = 0, [RF_OUT_PASSED] = 1,
                                              [RF_OUT_OVERTOPPED] = 2, [RF_OUT_BROKE_THROUGH] = 3};
static const char *const OUTCOME_LABELS[N_OUTCOMES] = {"stopped", "passed", "overtopped",
                                                       "broke through"};
static const char *const OUTCOME_COLOURS[N_OUTCOMES] = {"#4daf4a", "#9ecae1", "#ff7f0e",
                                                        "#d62728"};

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

/* The energy figure of a structure: a histogram of its crossings' energies by outcome
 * with its capacities as dashed lines.  Returns the number of capacities drawn, or -1. */
static int figure_measure(report *r, const rep_measure *m, const rf_crossing_row *x, size_t n,
                          const char *file)
{
    capacity_line caps[RF_N_LIMIT_STATES + 2];
    size_t ncaps = capacity_lines(m, caps);
    double hi = 1.0;
    for (size_t i = 0; i < n; i++)
        rep_grow(&hi, &hi, x[i].energy);
    for (size_t k = 0; k < ncaps; k++)
        rep_grow(&hi, &hi, caps[k].kj);
    hi *= 1.06;
    double lo = 0.0, bw = rf_svg_nice_step(hi, 30);
    hist_chart h = {.ns = N_OUTCOMES, .nlegend = N_OUTCOMES, .fills = OUTCOME_COLOURS,
                    .labels = OUTCOME_LABELS};
    if (rep_hist_bins(r, &h, &lo, &hi, bw))
        return -1;
    for (size_t i = 0; i < n; i++)
        rep_hist_add(&h, (size_t)OUTCOME_STACK[x[i].outcome], x[i].energy);
    double cmax = rep_hist_top(&h);
    char title[600];
    snprintf(title, sizeof title, "Energy at %s (%s) against its capacities", m->name,
             m->kind_name);
    if (rep_hist_open(r, &h, file, title, cmax * 1.12))
        return -1;
    rf_svg *s = &h.s;
    for (size_t k = 0; k < ncaps; k++)
        rep_vertical_marker(s, caps[k].kj,
                        "class=\"capacity\" stroke=\"#000\" stroke-width=\"1.5\" "
                        "stroke-dasharray=\"6 3\"",
                        caps[k].label);
    if (rep_hist_close(r, &h, "kinetic energy at the crossing (kJ)", "number of crossings"))
        return -1;
    return (int)ncaps;
}

/* The passing-height figure of a structure: a histogram of its crossings' passing
 * heights by outcome, with its height (dashed) and the crossings' 95th percentile
 * (dotted).  Returns the number of crossings drawn (those with a height), or -1. */
static int figure_height(report *r, const rep_measure *m, const rf_crossing_row *x, size_t n,
                         double h95, const char *file)
{
    double hi = 0.5;
    long drawn = 0;
    for (size_t i = 0; i < n; i++) {
        rep_grow(&hi, &hi, x[i].height);
        drawn += isfinite(x[i].height);
    }
    rep_grow(&hi, &hi, m->height);
    hi *= 1.08;
    double lo = 0.0, bw = rf_svg_nice_step(hi, 30);
    hist_chart h = {.ns = N_OUTCOMES, .nlegend = N_OUTCOMES, .fills = OUTCOME_COLOURS,
                    .labels = OUTCOME_LABELS};
    if (rep_hist_bins(r, &h, &lo, &hi, bw))
        return -1;
    for (size_t i = 0; i < n; i++)
        rep_hist_add(&h, (size_t)OUTCOME_STACK[x[i].outcome], x[i].height);
    double cmax = rep_hist_top(&h);
    char title[600], label[64];
    snprintf(title, sizeof title, "Passing height at %s (%s) against its height", m->name,
             m->kind_name);
    if (rep_hist_open(r, &h, file, title, cmax * 1.12))
        return -1;
    if (isfinite(m->height)) {
        snprintf(label, sizeof label, "height %.1f m", m->height);
        rep_vertical_marker(&h.s, m->height,
                            "class=\"structure-height\" stroke=\"#000\" stroke-width=\"1.5\" "
                            "stroke-dasharray=\"6 3\"",
                            label);
    }
    if (isfinite(h95)) {
        snprintf(label, sizeof label, "h95 %.2f m", h95);
        rep_vertical_marker(&h.s, h95,
                            "class=\"h95\" stroke=\"#555\" stroke-width=\"1.5\" "
                            "stroke-dasharray=\"2 3\"",
                            label);
    }
    if (rep_hist_close(r, &h, "passing height above the ground at the crossing (m)",
                       "number of crossings"))
        return -1;
    return (int)drawn;
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
    if (rep_each_row(r, sql, id, table_row, &t))
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
    rep_td_text(f, ls ? ls : "(none)");
    double n = sqlite3_column_double(st, 1);
    fprintf(f, "<td>%.0f</td>", n);
    rep_td_num(f, rep_pct(n, sqlite3_column_double(st, 3)), 1);
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
    rep_td_text(f, (const char *)sqlite3_column_text(st, 0));
    rep_td_num(f, rf_query_column_real(st, 1), 3);
    rep_td_num(f, rf_query_column_real(st, 2), 3);
    fprintf(f, "<td class=\"%s\">%s</td>", passed ? "pass" : "fail", passed ? "pass" : "FAIL");
    if (passed)
        (*c->npass)++;
    else
        (*c->nfail)++;
    return 0;
}

/* The checks of a measure, or with measure_id 0 those of the whole run; returns the
 * number of rows or -1. */
int rep_checks_table(report *r, FILE *f, int64_t measure_id, long *npass, long *nfail)
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

/* What the section found of a measure (its crossings are read one measure at a time,
 * for its statistics, share and figures). */
typedef struct measure_found {
    rf_measure_stats stats;
    double share;   /* % within serviceability, not overtopped; NAN when not defined */
    long ntraj;     /* trajectories that crossed it */
    int ncaps;      /* capacities drawn on its energy figure */
    long nheights;  /* crossings with a passing height, drawn on its height figure */
} measure_found;

/* The file of a structure's figure: "measure-IDX-energy.svg", "measure-IDX-height.svg". */
static void measure_figure_file(const rep_measure *m, const char *what, char *file, size_t n)
{
    snprintf(file, n, "measure-%ld-%s.svg", m->idx, what);
}

/* The share of the crossings with an energy within `capacity` that are not
 * overtopped, counted as SQL's avg(energy_kj <= capacity AND outcome <> 'overtopped'):
 * a crossing without an energy counts (as outside) only when overtopped. */
double rep_share_within(const rf_crossing_row *x, size_t n, double capacity)
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

static double serviceability_capacity(const rep_measure *m)
{
    return isfinite(m->cap[RF_SERVICEABILITY]) ? m->cap[RF_SERVICEABILITY] : m->sel;
}

static double ultimate_capacity(const rep_measure *m)
{
    return isfinite(m->cap[RF_ULTIMATE]) ? m->cap[RF_ULTIMATE] : m->mel;
}

/* Reads a measure's crossings into c; a structure (not a control line) crossed at
 * least once gets its energy and passing-height figures. */
static int read_measure(report *r, const rep_measure *m, measure_found *c)
{
    rf_crossing_row *x = NULL;
    size_t nx = 0;
    int failed = rf_query_crossings(r->db, m->id, &x, &nx, r->err) ||
                 rf_measure_stats_of(x, nx, &c->stats, r->err);
    double service = serviceability_capacity(m);
    c->share = NAN;
    if (!failed && !rep_is_control(m) && c->stats.n) {
        char file[64];
        if (isfinite(service))
            c->share = 100.0 * rep_share_within(x, nx, service);
        measure_figure_file(m, "energy", file, sizeof file);
        int ncaps = figure_measure(r, m, x, nx, file);
        measure_figure_file(m, "height", file, sizeof file);
        int nheights = ncaps < 0 ? -1 : figure_height(r, m, x, nx, c->stats.height_p95, file);
        failed = ncaps < 0 || nheights < 0;
        c->ncaps = ncaps;
        c->nheights = nheights;
    }
    free(x);
    if (!failed) {
        sqlite3_stmt *st = rep_prep(r, "SELECT count(DISTINCT trajectory_id) FROM interceptions"
                                       " WHERE measure_id = ?1", m->id);
        if (!st || sqlite3_step(st) != SQLITE_ROW)
            failed = st ? rep_db_error(r) : -1;
        else
            c->ntraj = (long)sqlite3_column_int64(st, 0);
        sqlite3_finalize(st);
    }
    return failed ? -1 : 0;
}

/* The structures' tables: their crossings, then their energies and heights (two
 * tables, so that each fits the page's width). */
static void structure_tables(report *r, const measure_found *mc)
{
    FILE *f = r->body;
    fputs("<table class=\"measures\"><tr><th>structure</th><th>kind</th><th>importance</th>"
          "<th>height (m)</th><th>crossings</th><th>stopped</th><th>overtopped</th>"
          "<th>broke through</th><th>passed</th>"
          "<th>within serviceability, not overtopped (%)</th></tr>\n",
          f);
    for (size_t k = 0; k < r->nmea; k++) {
        const rep_measure *m = &r->mea[k];
        const rf_measure_stats *s = &mc[k].stats;
        if (rep_is_control(m))
            continue;
        fputs("<tr>", f);
        rep_td_text(f, m->name);
        rep_td_text(f, m->kind_name);
        rep_td_text(f, m->importance_name);
        rep_td_num(f, m->height, 1);
        fprintf(f, "<td>%ld</td><td>%ld</td><td>%ld</td><td>%ld</td><td>%ld</td>", s->n,
                s->n_stopped, s->n_overtopped, s->n_broke_through, s->n_passed);
        rep_td_num(f, mc[k].share, 1);
        fputs("</tr>\n", f);
    }
    fputs("</table>\n<table class=\"measures\"><tr><th>structure</th><th>E50 (kJ)</th>"
          "<th>E90 (kJ)</th><th>E95 (kJ)</th><th>E99 (kJ)</th><th>Emax (kJ)</th>"
          "<th>h95 (m)</th><th>SEL / serviceability (kJ)</th><th>MEL / ultimate (kJ)</th>"
          "</tr>\n",
          f);
    for (size_t k = 0; k < r->nmea; k++) {
        const rep_measure *m = &r->mea[k];
        const rf_measure_stats *s = &mc[k].stats;
        if (rep_is_control(m))
            continue;
        fputs("<tr>", f);
        rep_td_text(f, m->name);
        rep_td_num(f, s->energy_p50, 0);
        rep_td_num(f, s->energy_p90, 0);
        rep_td_num(f, s->energy_p95, 0);
        rep_td_num(f, s->energy_p99, 0);
        rep_td_num(f, s->energy_max, 0);
        rep_td_num(f, s->height_p95, 2);
        rep_td_num(f, serviceability_capacity(m), 0);
        rep_td_num(f, ultimate_capacity(m), 0);
        fputs("</tr>\n", f);
    }
    fputs("</table>\n<p>Energies in kJ, nearest-rank percentiles over all crossings; h95 the "
          "95th percentile of the passing height. The paper's check: a layout passes when the "
          "serviceability limit state holds for over 90 % of the expected rockfalls.</p>\n",
          f);
}

/* The control lines: no structure (no capacity, no height), only their crossings. */
static int control_table(report *r, const measure_found *mc, long *npass, long *nfail)
{
    FILE *f = r->body;
    fputs("<h3 id=\"control-lines\">Control lines</h3>\n<p>A control line (kind "
          "<code>control</code>, such as the mountainside edge of the road) is no structure: "
          "it stops nothing and has no capacity or height. Its crossings are counted, with "
          "the rocks' energy and passing height there (the arrivals: the road section "
          "above).</p>\n<table class=\"control\"><tr><th>control line</th>"
          "<th>trajectories crossing</th><th>share of all (%)</th><th>crossings</th>"
          "<th>E50 (kJ)</th><th>E95 (kJ)</th><th>Emax (kJ)</th><th>h95 (m)</th></tr>\n",
          f);
    for (size_t k = 0; k < r->nmea; k++) {
        const rep_measure *m = &r->mea[k];
        const rf_measure_stats *s = &mc[k].stats;
        if (!rep_is_control(m))
            continue;
        fputs("<tr>", f);
        rep_td_text(f, m->name);
        fprintf(f, "<td>%ld</td>", mc[k].ntraj);
        rep_td_num(f, rep_pct((double)mc[k].ntraj, (double)r->n_traj), 1);
        fprintf(f, "<td>%ld</td>", s->n);
        rep_td_num(f, s->energy_p50, 0);
        rep_td_num(f, s->energy_p95, 0);
        rep_td_num(f, s->energy_max, 0);
        rep_td_num(f, s->height_p95, 2);
        fputs("</tr>\n", f);
    }
    fputs("</table>\n", f);
    for (size_t k = 0; k < r->nmea; k++)
        if (rep_is_control(&r->mea[k]) && rep_checks_table(r, f, r->mea[k].id, npass, nfail) < 0)
            return -1;
    return 0;
}

/* A structure's line in the summary: its crossings and its share within serviceability,
 * the rules engine's as stored in `checks` when there. */
static void structure_summary(report *r, const rep_measure *m, const measure_found *c)
{
    const rf_measure_stats *s = &c->stats;
    fputs("<li>", r->summary);
    rf_svg_escape(r->summary, m->name);
    fprintf(r->summary, " (%s): %ld crossings, %ld stopped, %ld overtopped, %ld broke through",
            m->kind_name, s->n, s->n_stopped, s->n_overtopped, s->n_broke_through);
    double stored = NAN, passed = NAN;
    sqlite3_stmt *st = rep_prep(r,
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
        rep_put_num(r->summary, 100.0 * stored, 1);
        fprintf(r->summary, " %% (%s the serviceability check)",
                passed == 1.0 ? "passes" : "fails");
    } else if (isfinite(c->share)) {
        fputs("; within serviceability: ", r->summary);
        rep_put_num(r->summary, c->share, 1);
        fputs(" % (no design check stored for this run: rockfall check)", r->summary);
    }
    fputs(".</li>\n", r->summary);
}

/* A structure's part: its figures, with captions that say what each draws, its
 * classifications and its checks. */
static int structure_part(report *r, const rep_measure *m, const measure_found *c, long *npass,
                          long *nfail)
{
    FILE *f = r->body;
    fputs("<h3>", f);
    rf_svg_escape(f, m->name);
    fputs(" (", f);
    rf_svg_escape(f, m->kind_name);
    fputs(")</h3>\n", f);
    structure_summary(r, m, c);
    if (c->stats.n == 0) {
        fputs("<p>No rock crossed this structure.</p>\n", f);
        return rep_checks_table(r, f, m->id, npass, nfail) < 0 ? -1 : 0;
    }
    char cap[800], file[64];
    if (c->ncaps)
        snprintf(cap, sizeof cap,
                 "Energy of the rocks crossing %s by outcome, with its %d capacit%s (dashed)",
                 m->name, c->ncaps, c->ncaps == 1 ? "y" : "ies");
    else
        snprintf(cap, sizeof cap,
                 "Energy of the rocks crossing %s by outcome (the run stores no capacity of it)",
                 m->name);
    measure_figure_file(m, "energy", file, sizeof file);
    rep_figure_html(f, file, cap);
    int n = snprintf(cap, sizeof cap,
                     "Passing height of the %ld of %ld crossings of %s that have one, by outcome",
                     c->nheights, c->stats.n, m->name);
    if (isfinite(m->height))
        snprintf(cap + n, sizeof cap - (size_t)n, ", with its height %.1f m (dashed)%s", m->height,
                 isfinite(c->stats.height_p95) ? " and their 95th percentile (dotted)" : "");
    else if (isfinite(c->stats.height_p95))
        snprintf(cap + n, sizeof cap - (size_t)n,
                 ", with their 95th percentile (dotted); the run stores no height of it");
    measure_figure_file(m, "height", file, sizeof file);
    rep_figure_html(f, file, cap);
    if (measure_classifications(r, m))
        return -1;
    return rep_checks_table(r, f, m->id, npass, nfail) < 0 ? -1 : 0;
}

int rep_section_measures(report *r, long *npass, long *nfail)
{
    FILE *f = r->body;
    fputs("<h2 id=\"measures\">The structures: energy and passing height</h2>\n", f);
    if (!r->nmea) {
        fputs("<p>The project has no measures.</p>\n", f);
        return 0;
    }
    measure_found *mc = calloc(r->nmea, sizeof *mc);
    if (!mc)
        return rep_oom(r);
    size_t ncontrol = 0;
    int status = 0;
    for (size_t k = 0; k < r->nmea && !status; k++) {
        ncontrol += rep_is_control(&r->mea[k]);
        status = read_measure(r, &r->mea[k], &mc[k]);
    }
    if (!status && ncontrol < r->nmea)
        structure_tables(r, mc);
    else if (!status)
        fputs("<p>The project has no barrier or embankment.</p>\n", f);
    if (!status && ncontrol)
        status = control_table(r, mc, npass, nfail);
    for (size_t k = 0; k < r->nmea && !status; k++)
        if (!rep_is_control(&r->mea[k]))
            status = structure_part(r, &r->mea[k], &mc[k], npass, nfail);
    free(mc);
    return status;
}
