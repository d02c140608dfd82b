/* report_data.c - what every part of the report shares: the run as the report reads
 * it (through the run view), its rows, colours and HTML cells. */
#include "report/report_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const RELEASE_COLOURS[] = {"#1f77b4", "#2ca02c", "#9467bd", "#17becf",
                                              "#e377c2", "#bcbd22", "#ff7f0e", "#7f7f7f"};
#define N_RELEASE_COLOURS (sizeof RELEASE_COLOURS / sizeof RELEASE_COLOURS[0])

/* ---- data of the run ------------------------------------------------------------ */

int rep_db_error(report *r)
{
    return rf_query_db_error(r->db, r->err);
}

/* A statement with ?1 bound to `id`; NULL (err filled) on failure. */
sqlite3_stmt *rep_prep(report *r, const char *sql, int64_t id)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(r->db, sql, -1, &st, NULL) != SQLITE_OK) {
        rep_db_error(r);
        return NULL;
    }
    if (sqlite3_bind_parameter_count(st) >= 1)
        sqlite3_bind_int64(st, 1, id);
    return st;
}

int rep_oom(report *r)
{
    return rf_error_set(r->err, r->dir, 0, 0, "out of memory");
}

int rep_each_row(report *r, const char *sql, int64_t id, row_fn row, void *ctx)
{
    sqlite3_stmt *st = rep_prep(r, sql, id);
    if (!st)
        return -1;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW)
        if (row(r, st, ctx)) {
            sqlite3_finalize(st);
            return -1;
        }
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : rep_db_error(r);
}

void *rep_next_elem(report *r, row_array *g)
{
    if (rf_grow(g->a, &g->cap, *g->n + 1, g->size)) {
        rep_oom(r);
        return NULL;
    }
    return (char *)*g->a + (*g->n)++ * g->size;
}

/* rep_each_row into the array *a (*n elements of size bytes): row fills rep_next_elem(r, ctx). */
int rep_load_rows(report *r, const char *sql, int64_t id, row_fn row, void **a, size_t *n,
                  size_t size)
{
    row_array g = {a, n, 0, size};
    return rep_each_row(r, sql, id, row, &g);
}

size_t rep_release_index(const report *r, int64_t id)
{
    for (size_t k = 0; k < r->nrel; k++)
        if (r->rel[k].id == id)
            return k;
    return 0;
}

const char *rep_release_colour(size_t k)
{
    return RELEASE_COLOURS[k % N_RELEASE_COLOURS];
}

const char *rep_measure_colour(const rep_measure *m)
{
    return m->kind >= 0 ? rf_measure_kinds[m->kind].colour : "#252525";
}

/* A protected line (a control line): the report draws the arrivals along it. */
int rep_is_control(const rep_measure *m)
{
    return m->kind >= 0 && rf_measure_kinds[m->kind].reach_line;
}

/* ---- loading ---------------------------------------------------------------------- */

/* The run through the run view; the report's names point into it. */
int rep_load_run(report *r)
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

int rep_load_releases(report *r)
{
    size_t n = r->nrel ? r->nrel : 1;
    r->rel_fills = calloc(n, sizeof *r->rel_fills);
    r->rel_names = calloc(n, sizeof *r->rel_names);
    if (!r->rel_fills || !r->rel_names)
        return rep_oom(r);
    for (size_t k = 0; k < n; k++) {
        r->rel_fills[k] = rep_release_colour(k);
        r->rel_names[k] = k < r->nrel ? r->rel[k].name : "";
    }
    return 0;
}

/* What the report says of a run without its terrain. */
void rep_note_terrain(report *r)
{
    if (!r->have_terrain)
        fputs("<li>The run stores no terrain (a run without one, or one written before "
              "schema version 2 of the results database): the figures have no terrain "
              "contours.</li>\n",
              r->notes);
}

/* ---- HTML helpers ------------------------------------------------------------------- */

void rep_put_num(FILE *f, double v, int decimals)
{
    if (isfinite(v))
        fprintf(f, "%.*f", decimals, v);
    else
        fputs("&ndash;", f);
}

void rep_td_num(FILE *f, double v, int decimals)
{
    fputs("<td>", f);
    rep_put_num(f, v, decimals);
    fputs("</td>", f);
}

void rep_td_text(FILE *f, const char *text)
{
    fputs("<td class=\"t\">", f);
    rf_svg_escape(f, text);
    fputs("</td>", f);
}

void rep_figure_html(FILE *f, const char *file, const char *caption)
{
    fprintf(f, "<figure><img src=\"%s\" alt=\"", file);
    rf_svg_escape(f, caption);
    fputs("\"><figcaption>", f);
    rf_svg_escape(f, caption);
    fputs("</figcaption></figure>\n", f);
}

double rep_pct(double part, double whole)
{
    return whole > 0 ? 100.0 * part / whole : NAN;
}

void rep_grow(double *lo, double *hi, double v)
{
    if (isfinite(v)) {
        if (v < *lo)
            *lo = v;
        if (v > *hi)
            *hi = v;
    }
}
