/* report.c - DIR/index.html and its SVG figures for one run of a results database:
 * the page, its head and closing sections; the figures are drawn by report_plan.c,
 * report_road.c, report_hazard.c and report_measures.c.
 *
 * Figures (the paper's numbers): plan view of the sampled trajectories over the
 * terrain contours with releases, measures and stop points (Fig. 9, 11); arrival
 * position along and velocity at each control line (Fig. 10a, 10b); hazard map of the
 * largest kinetic energy per cell in classes (Fig. 12) and the reach probability; the
 * energy at each measure against its capacities.  Beside them the empirical
 * crosscheck: Eq. 1-2 velocity and the attainment width of Fig. 1b. */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>

/* ---- the other sections -------------------------------------------------------------- */

void rep_page_head(FILE *f, const char *title)
{
    fputs("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>", f);
    rf_svg_escape(f, title);
    fputs("</title>\n<style>\n"
          "body{font-family:\"DejaVu Sans\",Arial,Helvetica,sans-serif;max-width:72em;"
          "margin:1.5em auto;padding:0 1em;color:#222;line-height:1.4}\n"
          "h1{margin-bottom:.2em}h2{border-bottom:2px solid #ccc;padding-bottom:.2em;"
          "margin-top:1.8em}\n"
          "table{border-collapse:collapse;margin:.6em 0;font-size:.92em;display:block;"
          "overflow-x:auto;max-width:100%}\n"
          "td,th{border:1px solid #aaa;padding:.2em .5em;text-align:right}\n"
          "th{background:#eee;max-width:11em;vertical-align:bottom}\n"
          "td.t,th.t{text-align:left}tr.line th{background:#dde4ee}\n"
          "td.pass{color:#1a7f1a;font-weight:bold}td.fail{color:#b00;font-weight:bold}\n"
          "td.absent{color:#888;font-style:italic}\n"
          "figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}\n"
          "figcaption{font-size:.9em;color:#444}\n"
          ".plans{display:flex;flex-wrap:wrap;gap:1em}.plans figure{flex:1 1 30em;margin:0}\n"
          ".summary{background:#f5f7fa;border:1px solid #d0d7e0;padding:.6em 1.2em}\n"
          ".notes{background:#fff8e5;border:1px solid #e6c96b;padding:.6em 1.2em}\n"
          "</style></head><body>\n",
          f);
}

static void section_head(report *r, FILE *f)
{
    char title[600];
    snprintf(title, sizeof title, "rockfall report: %s", r->project);
    rep_page_head(f, title);
    fputs("<h1>", f);
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
        rep_td_text(f, e->name);
        rep_td_num(f, e->x, 1);
        rep_td_num(f, e->y, 1);
        rep_td_num(f, e->z, 1);
        rep_td_text(f, e->rock);
        rep_td_num(f, e->mass, 0);
        fprintf(f, "<td>%d</td><td>%ld</td></tr>\n", e->action_level, e->count);
    }
    fputs("</table>\n", f);
}

static int end_row(report *r, sqlite3_stmt *st, void *ctx)
{
    (void)r;
    FILE *f = ctx;
    fputs("<tr>", f);
    rep_td_text(f, (const char *)sqlite3_column_text(st, 0));
    rep_td_text(f, (const char *)sqlite3_column_text(st, 1));
    fprintf(f, "<td>%lld</td>", (long long)sqlite3_column_int64(st, 2));
    rep_td_num(f, rf_query_column_real(st, 3), 1);
    rep_td_num(f, rf_query_column_real(st, 4), 1);
    rep_td_num(f, rf_query_column_real(st, 5), 0);
    rep_td_num(f, rf_query_column_real(st, 6), 0);
    fputs("</tr>\n", f);
    return 0;
}

static int section_ends(report *r, FILE *f)
{
    fputs("<h2 id=\"ends\">Where the trajectories ended</h2>\n<table><tr><th>release</th><th>end</th>"
          "<th>count</th><th>mean duration (s)</th><th>mean path length (m)</th>"
          "<th>mean largest energy (kJ)</th><th>largest energy (kJ)</th></tr>\n",
          f);
    int rc = rep_each_row(r,
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

int rep_make_dirs(const char *dir, rf_error *err)
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

void rep_free_report(report *r)
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
    if (rep_figure_plan(r, "plan.svg"))
        return -1;
    fputs("<h2 id=\"plan\">Plan view (Fig. 9, 11)</h2>\n", r->body);
    fprintf(r->body,
            "<p>The sampled paths (%ld trajectories with stored path points) over the terrain "
            "contours, the release points, the measures and the points where the "
            "trajectories ended (%ld drawn). North is up; x and y in metres.</p>\n",
            r->n_path_traj, r->n_stop_points);
    char caption[600];
    rep_plan_caption(r, caption, sizeof caption);
    rep_figure_html(r->body, "plan.svg", caption);
    if (!r->n_path_traj)
        fputs("<li>No sampled paths are stored for this run (<code>simulation.paths</code>): the "
              "plan view shows only where the trajectories ended.</li>\n",
              r->notes);
    if (rep_section_road(r) || rep_section_hazard(r) || rep_section_measures(r, npass, nfail))
        return -1;
    fputs("<h2 id=\"checks\">Checks of the whole run</h2>\n", r->body);
    int rows = rep_checks_table(r, r->body, 0, npass, nfail);
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
    int status = rep_load_run(&r);
    if (!status)
        status = rep_make_dirs(dir, err);
    if (!status)
        status = rep_load_releases(&r);
    if (!status) {
        r.summary = open_memstream(&sum_text, &sum_len);
        r.notes = open_memstream(&notes_text, &notes_len);
        r.body = open_memstream(&body_text, &body_len);
        if (!r.summary || !r.notes || !r.body)
            status = rep_oom(&r);
    }
    if (!status) {
        if (strcmp(r.status, "complete"))
            fputs("<li>This run is not complete: its results are partial.</li>\n", r.notes);
        rep_note_terrain(&r);
        status = rep_compute_extent(&r) || rep_build_contour_grid(&r) ? -1 : 0;
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
        status = rep_oom(&r);
    if (!status) {
        char path[4096];
        snprintf(path, sizeof path, "%s/index.html", dir);
        FILE *f = rf_create_file(path, err);
        if (!f) {
            status = -1;
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
    rep_free_report(&r);
    return status;
}
