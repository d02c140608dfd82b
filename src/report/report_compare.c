/* report_compare.c - layout variants side by side: `rockfall report DB --runs 3,4 --out
 * DIR` writes DIR/index.html with one column per run (its verdict, the crossings and
 * energy percentiles of each structure, the arrivals at each control line, the hazard
 * cells) and one plan view per run (DIR/plan-run-ID.svg).  Structures and control lines
 * are matched across the runs by name. */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>

/* What the comparison reads of one run. */
typedef struct variant {
    report r;
    long checks, failed, inconclusive;
    long cells, cells_over_3000;
    double energy_max;
} variant;

/* One structure or control line, by name, with its row in each run (NULL where the run
 * has none). */
typedef struct matched {
    const char *name;
    int control;
    const rep_measure **m; /* nruns */
} matched;

typedef struct compare {
    sqlite3 *db;
    const char *dir;
    rf_error *err;
    variant *v;
    size_t nv;
    matched *lines;
    size_t nlines;
    FILE *f;
} compare;

/* ---- reading ------------------------------------------------------------------------ */

/* The verdict's counts from the stored checks (before schema version 3 every check is a
 * design check). */
static int read_checks(variant *v)
{
    report *r = &v->r;
    sqlite3_stmt *st = rep_prep(r,
                                r->view.schema >= 3
                                    ? "SELECT count(*), coalesce(sum(passed = 0 AND on_failure ="
                                      " 'fail'), 0), coalesce(sum(passed = 0 AND on_failure ="
                                      " 'inconclusive'), 0) FROM checks WHERE run_id = ?1"
                                    : "SELECT count(*), coalesce(sum(passed = 0), 0), 0"
                                      " FROM checks WHERE run_id = ?1",
                                r->run);
    if (!st)
        return -1;
    int ok = sqlite3_step(st) == SQLITE_ROW;
    if (ok) {
        v->checks = (long)sqlite3_column_int64(st, 0);
        v->failed = (long)sqlite3_column_int64(st, 1);
        v->inconclusive = (long)sqlite3_column_int64(st, 2);
    }
    sqlite3_finalize(st);
    return ok ? 0 : rep_db_error(r);
}

static int read_cells(variant *v)
{
    report *r = &v->r;
    char sql[300];
    snprintf(sql, sizeof sql,
             "SELECT count(*), count(*) FILTER (WHERE energy_p95_kj >= %.0f), max(energy_max_kj)"
             " FROM hazard_cells WHERE run_id = ?1",
             rf_report_energy_limits[1]);
    sqlite3_stmt *st = rep_prep(r, sql, r->run);
    if (!st)
        return -1;
    int ok = sqlite3_step(st) == SQLITE_ROW;
    if (ok) {
        v->cells = (long)sqlite3_column_int64(st, 0);
        v->cells_over_3000 = (long)sqlite3_column_int64(st, 1);
        v->energy_max = rf_query_column_real(st, 2);
    }
    sqlite3_finalize(st);
    return ok ? 0 : rep_db_error(r);
}

/* Loads run `run` as the report holds it and draws its plan into plan-run-ID.svg. */
static int read_variant(compare *c, variant *v, int64_t run)
{
    report *r = &v->r;
    *r = (report){.db = c->db, .run = run, .dir = c->dir, .err = c->err};
    if (rep_load_run(r) || rep_load_releases(r) || rep_compute_extent(r) ||
        rep_build_contour_grid(r))
        return -1;
    char file[64];
    snprintf(file, sizeof file, "plan-run-%lld.svg", (long long)run);
    return rep_figure_plan(r, file) || read_checks(v) || read_cells(v) ? -1 : 0;
}

/* The structures and control lines of all runs, matched by name, in the order they
 * first appear. */
static int match_lines(compare *c)
{
    size_t cap = 0;
    for (size_t k = 0; k < c->nv; k++)
        cap += c->v[k].r.nmea;
    c->lines = calloc(cap ? cap : 1, sizeof *c->lines);
    if (!c->lines)
        return rep_oom(&c->v[0].r);
    for (size_t k = 0; k < c->nv; k++)
        for (size_t i = 0; i < c->v[k].r.nmea; i++) {
            const rep_measure *m = &c->v[k].r.mea[i];
            size_t j = 0;
            while (j < c->nlines && (strcmp(c->lines[j].name, m->name) ||
                                     c->lines[j].control != rep_is_control(m)))
                j++;
            if (j == c->nlines) {
                c->lines[j] = (matched){m->name, rep_is_control(m),
                                        calloc(c->nv, sizeof *c->lines[j].m)};
                if (!c->lines[j].m)
                    return rep_oom(&c->v[0].r);
                c->nlines++;
            }
            if (!c->lines[j].m[k])
                c->lines[j].m[k] = m;
        }
    return 0;
}

/* ---- the page ------------------------------------------------------------------------- */

static void header_row(compare *c, const char *first)
{
    fprintf(c->f, "<tr><th>%s</th>", first);
    for (size_t k = 0; k < c->nv; k++) {
        fputs("<th>", c->f);
        rf_svg_escape(c->f, c->v[k].r.project);
        fprintf(c->f, "<br>run %lld</th>", (long long)c->v[k].r.run);
    }
    fputs("</tr>\n", c->f);
}

static const char *verdict_of(const variant *v)
{
    if (!v->checks)
        return "not checked";
    return v->inconclusive ? "INCONCLUSIVE" : v->failed ? "FAIL" : "PASS";
}

static void runs_table(compare *c)
{
    FILE *f = c->f;
    fputs("<h2 id=\"runs\">The variants</h2>\n<table class=\"compare\">\n", f);
    header_row(c, "");
    fputs("<tr><td class=\"t\">verdict (stored checks)</td>", f);
    for (size_t k = 0; k < c->nv; k++) {
        const char *v = verdict_of(&c->v[k]);
        fprintf(f, "<td class=\"verdict %s\">%s</td>",
                !strcmp(v, "PASS") ? "pass" : c->v[k].checks ? "fail" : "none", v);
    }
    fputs("</tr>\n<tr><td class=\"t\">checks passed / failed</td>", f);
    for (size_t k = 0; k < c->nv; k++)
        fprintf(f, "<td>%ld / %ld</td>", c->v[k].checks - c->v[k].failed - c->v[k].inconclusive,
                c->v[k].failed + c->v[k].inconclusive);
    fputs("</tr>\n<tr><td class=\"t\">trajectories</td>", f);
    for (size_t k = 0; k < c->nv; k++)
        fprintf(f, "<td>%ld</td>", c->v[k].r.n_traj);
    fputs("</tr>\n<tr><td class=\"t\">seed</td>", f);
    for (size_t k = 0; k < c->nv; k++)
        rep_td_text(f, c->v[k].r.seed);
    fputs("</tr>\n<tr><td class=\"t\">hazard cells crossed</td>", f);
    for (size_t k = 0; k < c->nv; k++)
        fprintf(f, "<td>%ld</td>", c->v[k].cells);
    fputs("</tr>\n<tr><td class=\"t\">cells with E95 &ge; 3000 kJ</td>", f);
    for (size_t k = 0; k < c->nv; k++)
        fprintf(f, "<td>%ld</td>", c->v[k].cells_over_3000);
    fputs("</tr>\n<tr><td class=\"t\">largest energy in a cell (kJ)</td>", f);
    for (size_t k = 0; k < c->nv; k++)
        rep_td_num(f, c->v[k].energy_max, 0);
    fputs("</tr>\n</table>\n", f);
}

/* What one run holds of one line: its statistics, trajectories and share. */
typedef struct line_values {
    rf_measure_stats s;
    long ntraj;
    double share;
} line_values;

/* The statistics of a line, row by row. */
typedef enum stat_kind {
    ST_CROSSINGS, ST_STOPPED, ST_OVERTOPPED, ST_BROKE, ST_PASSED, ST_SHARE, ST_E50, ST_E90,
    ST_E95, ST_E99, ST_EMAX, ST_H95, ST_TRAJECTORIES
} stat_kind;

typedef struct stat_row {
    const char *label;
    stat_kind kind;
    int decimals;
} stat_row;

static const stat_row STRUCTURE_ROWS[] = {
    {"crossings", ST_CROSSINGS, 0},
    {"stopped", ST_STOPPED, 0},
    {"overtopped", ST_OVERTOPPED, 0},
    {"broke through", ST_BROKE, 0},
    {"passed", ST_PASSED, 0},
    {"within serviceability, not overtopped (%)", ST_SHARE, 1},
    {"E50 (kJ)", ST_E50, 0},
    {"E90 (kJ)", ST_E90, 0},
    {"E95 (kJ)", ST_E95, 0},
    {"E99 (kJ)", ST_E99, 0},
    {"Emax (kJ)", ST_EMAX, 0},
    {"h95 (m)", ST_H95, 2},
};

static const stat_row CONTROL_ROWS[] = {
    {"trajectories crossing", ST_TRAJECTORIES, 0},
    {"crossings", ST_CROSSINGS, 0},
    {"E50 (kJ)", ST_E50, 0},
    {"E95 (kJ)", ST_E95, 0},
    {"Emax (kJ)", ST_EMAX, 0},
    {"h95 (m)", ST_H95, 2},
};

static double stat_value(const line_values *v, stat_kind k)
{
    const rf_measure_stats *s = &v->s;
    switch (k) {
    case ST_CROSSINGS: return (double)s->n;
    case ST_STOPPED: return (double)s->n_stopped;
    case ST_OVERTOPPED: return (double)s->n_overtopped;
    case ST_BROKE: return (double)s->n_broke_through;
    case ST_PASSED: return (double)s->n_passed;
    case ST_SHARE: return v->share;
    case ST_E50: return s->energy_p50;
    case ST_E90: return s->energy_p90;
    case ST_E95: return s->energy_p95;
    case ST_E99: return s->energy_p99;
    case ST_EMAX: return s->energy_max;
    case ST_H95: return s->height_p95;
    case ST_TRAJECTORIES: return (double)v->ntraj;
    }
    return NAN;
}

static int read_line(compare *c, const rep_measure *m, line_values *lv)
{
    rf_crossing_row *x = NULL;
    size_t nx = 0;
    if (rf_query_crossings(c->db, m->id, &x, &nx, c->err) ||
        rf_measure_stats_of(x, nx, &lv->s, c->err)) {
        free(x);
        return -1;
    }
    double service = isfinite(m->cap[RF_SERVICEABILITY]) ? m->cap[RF_SERVICEABILITY] : m->sel;
    lv->share = !rep_is_control(m) && isfinite(service) && nx
                    ? 100.0 * rep_share_within(x, nx, service)
                    : NAN;
    free(x);
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(c->db,
                           "SELECT count(DISTINCT trajectory_id) FROM interceptions"
                           " WHERE measure_id = ?1",
                           -1, &st, NULL) != SQLITE_OK) {
        sqlite3_finalize(st);
        return rf_query_db_error(c->db, c->err);
    }
    sqlite3_bind_int64(st, 1, m->id);
    int ok = sqlite3_step(st) == SQLITE_ROW;
    lv->ntraj = ok ? (long)sqlite3_column_int64(st, 0) : 0;
    sqlite3_finalize(st);
    return ok ? 0 : rf_query_db_error(c->db, c->err);
}

/* The rows of one line: a heading row with its name, then one row per statistic. */
static int line_rows(compare *c, const matched *l, const stat_row *rows, size_t nrows)
{
    FILE *f = c->f;
    line_values *lv = calloc(c->nv, sizeof *lv);
    if (!lv)
        return rep_oom(&c->v[0].r);
    for (size_t k = 0; k < c->nv; k++)
        if (l->m[k] && read_line(c, l->m[k], &lv[k])) {
            free(lv);
            return -1;
        }
    fprintf(f, "<tr class=\"line\"><th class=\"t\" colspan=\"%zu\">", c->nv + 1);
    rf_svg_escape(f, l->name);
    for (size_t k = 0; k < c->nv; k++)
        if (l->m[k] && !l->control) {
            fputs(" (", f);
            rf_svg_escape(f, l->m[k]->kind_name);
            fputs(")", f);
            break;
        }
    fputs("</th></tr>\n", f);
    for (size_t i = 0; i < nrows; i++) {
        fputs("<tr>", f);
        rep_td_text(f, rows[i].label);
        for (size_t k = 0; k < c->nv; k++) {
            if (!l->m[k]) {
                fputs("<td class=\"absent\">not in this run</td>", f);
                continue;
            }
            rep_td_num(f, stat_value(&lv[k], rows[i].kind), rows[i].decimals);
        }
        fputs("</tr>\n", f);
    }
    free(lv);
    return 0;
}

static int lines_table(compare *c, int control)
{
    FILE *f = c->f;
    size_t n = 0;
    for (size_t j = 0; j < c->nlines; j++)
        n += c->lines[j].control == control;
    if (control)
        fputs("<h2 id=\"control-lines\">Arrivals at the control lines</h2>\n", f);
    else
        fputs("<h2 id=\"structures\">Interceptions and energy percentiles per structure</h2>\n", f);
    if (!n) {
        fprintf(f, "<p>No run has %s.</p>\n",
                control ? "a control line" : "a barrier or an embankment");
        return 0;
    }
    fputs("<table class=\"compare\">\n", f);
    header_row(c, control ? "control line" : "structure");
    int status = 0;
    for (size_t j = 0; j < c->nlines && !status; j++)
        if (c->lines[j].control == control)
            status = control ? line_rows(c, &c->lines[j], CONTROL_ROWS,
                                         sizeof CONTROL_ROWS / sizeof CONTROL_ROWS[0])
                             : line_rows(c, &c->lines[j], STRUCTURE_ROWS,
                                         sizeof STRUCTURE_ROWS / sizeof STRUCTURE_ROWS[0]);
    fputs("</table>\n", f);
    if (!control)
        fputs("<p>Nearest-rank percentiles over all crossings of the structure; the share "
              "within serviceability as in the run's own report.</p>\n",
              f);
    return status;
}

static void plans(compare *c)
{
    FILE *f = c->f;
    fputs("<h2 id=\"plans\">Plan views</h2>\n<div class=\"plans\">\n", f);
    for (size_t k = 0; k < c->nv; k++) {
        char file[64], caption[800];
        snprintf(file, sizeof file, "plan-run-%lld.svg", (long long)c->v[k].r.run);
        int n = snprintf(caption, sizeof caption, "Run %lld (%.200s): ",
                         (long long)c->v[k].r.run, c->v[k].r.project);
        rep_plan_caption(&c->v[k].r, caption + n, sizeof caption - (size_t)n);
        rep_figure_html(f, file, caption);
    }
    fputs("</div>\n", f);
}

static int write_page(compare *c)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/index.html", c->dir);
    c->f = rf_create_file(path, c->err);
    if (!c->f)
        return -1;
    rep_page_head(c->f, "rockfall: layout variants");
    fputs("<h1>Layout variants</h1>\n<p>Runs", c->f);
    for (size_t k = 0; k < c->nv; k++)
        fprintf(c->f, "%s %lld", k ? "," : "", (long long)c->v[k].r.run);
    fputs(" of the same database side by side. Structures and control lines are matched by "
          "name; each run's own report (<code>rockfall report DB --run ID</code>) has the "
          "details.</p>\n",
          c->f);
    runs_table(c);
    int status = lines_table(c, 0);
    if (!status)
        status = lines_table(c, 1);
    if (!status)
        plans(c);
    fputs("</body></html>\n", c->f);
    int bad = ferror(c->f);
    if (fclose(c->f) || bad)
        status = status ? status : rf_error_set(c->err, path, 0, 0, "cannot write: %s",
                                                 strerror(errno));
    c->f = NULL;
    return status;
}

int rf_report_compare(sqlite3 *db, const int64_t *runs, size_t nruns, const char *dir,
                      rf_error *err)
{
    if (!nruns)
        return rf_error_set(err, dir, 0, 0, "no run to compare");
    compare c = {.db = db, .dir = dir, .err = err};
    c.v = calloc(nruns, sizeof *c.v);
    if (!c.v)
        return rf_error_set(err, dir, 0, 0, "out of memory");
    int status = rep_make_dirs(dir, err);
    for (size_t k = 0; k < nruns && !status; k++, c.nv++)
        status = read_variant(&c, &c.v[k], runs[k]);
    if (!status)
        status = match_lines(&c);
    if (!status)
        status = write_page(&c);
    for (size_t j = 0; j < c.nlines; j++)
        free(c.lines[j].m);
    free(c.lines);
    for (size_t k = 0; k < c.nv; k++)
        rep_free_report(&c.v[k].r);
    free(c.v);
    return status;
}
