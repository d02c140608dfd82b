/* report_measures.c - the measures section: the energy at each measure against its
 * capacities, its classifications and its checks. */
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
    return rep_hist_close(r, &h, "kinetic energy at the crossing (kJ)", "number of crossings");
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

int rep_section_measures(report *r, long *npass, long *nfail)
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
        return rep_oom(r);
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
            c->share = !rep_is_control(m) && isfinite(service) && s->n
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
        rep_td_text(f, m->name);
        rep_td_text(f, m->kind_name);
        rep_td_text(f, m->importance_name);
        rep_td_num(f, m->height, 1);
        fprintf(f, "<td>%ld</td><td>%ld</td><td>%ld</td><td>%ld</td><td>%ld</td>", s->n,
                s->n_stopped, s->n_overtopped, s->n_broke_through, s->n_passed);
        rep_td_num(f, s->energy_p50, 0);
        rep_td_num(f, s->energy_p90, 0);
        rep_td_num(f, s->energy_p95, 0);
        rep_td_num(f, s->energy_p99, 0);
        rep_td_num(f, s->energy_max, 0);
        rep_td_num(f, s->height_p95, 2);
        rep_td_num(f, service, 0);
        rep_td_num(f, isfinite(m->cap[RF_ULTIMATE]) ? m->cap[RF_ULTIMATE] : m->mel, 0);
        rep_td_num(f, c->share, 1);
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
        if (!rep_is_control(m)) {
            fputs("<li>", r->summary);
            rf_svg_escape(r->summary, m->name);
            fprintf(r->summary,
                    " (%s): %ld crossings, %ld stopped, %ld overtopped, %ld broke through",
                    m->kind_name, s->n, s->n_stopped, s->n_overtopped, s->n_broke_through);
            /* the verdict is the rules engine's, as stored in `checks` */
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
            } else if (isfinite(mc[k].share)) {
                fputs("; within serviceability: ", r->summary);
                rep_put_num(r->summary, mc[k].share, 1);
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
        rep_figure_html(f, file, cap);
        if (!rep_is_control(m) && measure_classifications(r, m)) {
            status = -1;
            break;
        }
        if (rep_checks_table(r, f, m->id, npass, nfail) < 0)
            status = -1;
    }
    free(mc);
    return status;
}
