/* hazard.c - accumulating the hazard map (see hazard.h). */
#include "run/hazard.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "results/store.h"
#include "base/util.h"

const rf_qsum_scale RF_HAZARD_ENERGY_SCALE = {-10, 30}, RF_HAZARD_HEIGHT_SCALE = {-10, 14};

/* ---- cell number -> position ----------------------------------------------------- */

static size_t map_home(const rf_hazard_map *m, uint32_t key)
{
    return (size_t)((key * 0x9E3779B1u) ^ (key >> 15)) & (m->cap - 1);
}

/* The entry of key, or the empty slot where it would go (cap > n). */
static size_t map_slot(const rf_hazard_map *m, uint32_t key)
{
    size_t i = map_home(m, key);
    while (m->epoch[i] == m->cur && m->key[i] != key)
        i = (i + 1) & (m->cap - 1);
    return i;
}

static const uint32_t *map_get(const rf_hazard_map *m, uint32_t key)
{
    if (m->cap == 0)
        return NULL;
    size_t i = map_slot(m, key);
    return m->epoch[i] == m->cur ? &m->val[i] : NULL;
}

static int map_put(rf_hazard_map *m, uint32_t key, uint32_t val)
{
    if (2 * (m->n + 1) > m->cap) { /* at most half full */
        rf_hazard_map g = {0};
        g.cap = m->cap ? 2 * m->cap : 64;
        g.cur = 1;
        g.key = malloc(g.cap * sizeof *g.key);
        g.val = malloc(g.cap * sizeof *g.val);
        g.epoch = calloc(g.cap, sizeof *g.epoch);
        if (!g.key || !g.val || !g.epoch) {
            free(g.key), free(g.val), free(g.epoch);
            return -1;
        }
        for (size_t i = 0; i < m->cap; i++)
            if (m->epoch[i] == m->cur) {
                size_t j = map_slot(&g, m->key[i]);
                g.key[j] = m->key[i], g.val[j] = m->val[i], g.epoch[j] = g.cur;
                g.n++;
            }
        free(m->key), free(m->val), free(m->epoch);
        *m = g;
    }
    size_t i = map_slot(m, key);
    m->n += m->epoch[i] != m->cur;
    m->key[i] = key, m->val[i] = val, m->epoch[i] = m->cur;
    return 0;
}

static void map_clear(rf_hazard_map *m)
{
    m->n = 0;
    if (m->cap && ++m->cur == 0) { /* wrapped: forget every old mark */
        memset(m->epoch, 0, m->cap * sizeof *m->epoch);
        m->cur = 1;
    }
}

static void map_free(rf_hazard_map *m)
{
    free(m->key), free(m->val), free(m->epoch);
    memset(m, 0, sizeof *m);
}

static size_t map_bytes(const rf_hazard_map *m)
{
    return m->cap * (sizeof *m->key + sizeof *m->val + sizeof *m->epoch);
}

/* ---- the map ------------------------------------------------------------------------ */

int rf_hazard_init(rf_hazard *h, const rf_terrain *t, double cell)
{
    memset(h, 0, sizeof *h);
    h->cell = cell;
    h->x0 = t->xmin;
    h->y0 = t->ymin;
    double nx, ny;
    rf_hazard_grid(t, cell, &nx, &ny);
    h->nx = (size_t)nx;
    h->ny = (size_t)ny;
    h->last[0] = NAN;
    return 0;
}

void rf_hazard_free(rf_hazard *h)
{
    for (size_t i = 0; i < h->ncells; i++) {
        rf_qsum_free(&h->cells[i].energy_kj);
        rf_qsum_free(&h->cells[i].height_m);
    }
    free(h->cells);
    map_free(&h->where);
    map_free(&h->slot);
    free(h->touched);
    memset(h, 0, sizeof *h);
}

void rf_hazard_begin(rf_hazard *h)
{
    h->ntouched = 0;
    h->last[0] = NAN;
    map_clear(&h->slot);
}

/* The cell index along one axis of a point at x (floor), a point on the grid's far
 * edge in the last cell: the quotient is the one rf_hazard_grid took the cell count
 * from, so it reaches n exactly there and nowhere on the terrain beyond. */
static double cell_index(double x, double x0, double cell, size_t n)
{
    double q = (x - x0) / cell, f = floor(q);
    if (q == (double)n)
        f -= 1.0;
    return f;
}

/* The trajectory reached cell (fx, fy) with these values (outside the grid: nothing). */
static void touch(rf_hazard *h, double fx, double fy, double energy_kj, double height_m)
{
    if (!(fx >= 0 && fy >= 0 && fx < (double)h->nx && fy < (double)h->ny))
        return;
    uint32_t c = (uint32_t)((size_t)fy * h->nx + (size_t)fx);
    const uint32_t *at = map_get(&h->slot, c);
    if (at) {
        rf_hazard_touch *tc = &h->touched[*at];
        if (energy_kj > tc->energy_kj)
            tc->energy_kj = (float)energy_kj;
        if (height_m > tc->height_m)
            tc->height_m = (float)height_m;
        return;
    }
    if (rf_grow((void **)&h->touched, &h->cap_touched, h->ntouched + 1, sizeof *h->touched) ||
        map_put(&h->slot, c, (uint32_t)h->ntouched)) {
        h->oom = 1;
        return;
    }
    h->touched[h->ntouched++] = (rf_hazard_touch){c, (float)energy_kj, (float)height_m};
}

/* The most cells between two samples walked.  A run's samples are at most a quarter
 * cell apart; two farther apart than this (never in a run) reach only the new
 * sample's cell. */
#define HAZARD_WALK_MAX 64

/* From the last sample a to the new one b, along the straight line between them: every
 * cell the line crosses, in order, with the largest of the values interpolated linearly
 * over its stretch of the line (so at one of the stretch's ends).  Through a grid
 * corner exactly the line goes on diagonally: the two cells it only touches at the
 * corner are not reached. */
static void walk(rf_hazard *h, const double a[4], double fx, double fy, const double b[4],
                 double gx, double gy)
{
    double steps = fabs(gx - fx) + fabs(gy - fy);
    if (!(steps <= HAZARD_WALK_MAX)) {
        touch(h, gx, gy, b[2], b[3]);
        return;
    }
    double dx = b[0] - a[0], dy = b[1] - a[1];
    double sx = gx > fx ? 1.0 : gx < fx ? -1.0 : 0.0, sy = gy > fy ? 1.0 : gy < fy ? -1.0 : 0.0;
    double s0 = 0.0;
    /* each step moves towards b's cell in x, in y or in both, never past it: the walk
     * ends there after at most `steps` steps */
    for (double k = 0;; k++) {
        int end = (fx == gx && fy == gy) || k >= steps;
        /* the line's parameter where it leaves the cell in x and in y */
        double ux = fx != gx ? (h->x0 + (sx > 0 ? fx + 1 : fx) * h->cell - a[0]) / dx : INFINITY;
        double uy = fy != gy ? (h->y0 + (sy > 0 ? fy + 1 : fy) * h->cell - a[1]) / dy : INFINITY;
        double s1 = end ? 1.0 : fmin(fmax(fmin(ux, uy), s0), 1.0);
        touch(h, fx, fy, fmax(a[2] + (b[2] - a[2]) * s0, a[2] + (b[2] - a[2]) * s1),
              fmax(a[3] + (b[3] - a[3]) * s0, a[3] + (b[3] - a[3]) * s1));
        if (end)
            break;
        if (ux <= uy)
            fx += sx;
        if (uy <= ux)
            fy += sy;
        s0 = s1;
    }
}

void rf_hazard_sample(rf_hazard *h, double x, double y, double energy_kj, double height_m)
{
    if (!isfinite(x) || !isfinite(y))
        return; /* no cell, and no line to the next sample */
    double b[4] = {x, y, energy_kj, height_m};
    double gx = cell_index(x, h->x0, h->cell, h->nx), gy = cell_index(y, h->y0, h->cell, h->ny);
    if (isnan(h->last[0]))
        touch(h, gx, gy, energy_kj, height_m);
    else
        walk(h, h->last, h->last_fx, h->last_fy, b, gx, gy);
    memcpy(h->last, b, sizeof b);
    h->last_fx = gx, h->last_fy = gy;
}

/* Cell c's summaries, added when no trajectory reached it before; NULL: no memory. */
static rf_hazard_cell *cell_of(rf_hazard *h, uint32_t c)
{
    const uint32_t *at = map_get(&h->where, c);
    if (at)
        return &h->cells[*at];
    if (rf_grow((void **)&h->cells, &h->cap_cells, h->ncells + 1, sizeof *h->cells) ||
        map_put(&h->where, c, (uint32_t)h->ncells))
        return NULL;
    rf_hazard_cell *nc = &h->cells[h->ncells++];
    memset(nc, 0, sizeof *nc);
    nc->cell = c;
    return nc;
}

int rf_hazard_end(rf_hazard *h)
{
    for (size_t i = 0; i < h->ntouched; i++) {
        const rf_hazard_touch *tc = &h->touched[i];
        rf_hazard_cell *c = cell_of(h, tc->cell);
        if (!c || rf_qsum_add(&c->energy_kj, &RF_HAZARD_ENERGY_SCALE, tc->energy_kj) ||
            rf_qsum_add(&c->height_m, &RF_HAZARD_HEIGHT_SCALE, tc->height_m))
            h->oom = 1;
    }
    h->ntouched = 0;
    map_clear(&h->slot);
    return h->oom ? -1 : 0;
}

int rf_hazard_merge(rf_hazard *into, const rf_hazard *from)
{
    for (size_t i = 0; i < from->ncells; i++) {
        const rf_hazard_cell *f = &from->cells[i];
        rf_hazard_cell *c = cell_of(into, f->cell);
        if (!c || rf_qsum_merge(&c->energy_kj, &f->energy_kj, &RF_HAZARD_ENERGY_SCALE) ||
            rf_qsum_merge(&c->height_m, &f->height_m, &RF_HAZARD_HEIGHT_SCALE))
            return -1;
    }
    return 0;
}

/* A packed cell: its number (4 bytes, little-endian), then the energy's and the height's
 * summaries in their canonical bytes (rf_qsum_encode). */
size_t rf_hazard_pack(const rf_hazard *h, size_t *next, unsigned char *buf, size_t cap)
{
    size_t at = 0;
    for (; *next < h->ncells; (*next)++) {
        const rf_hazard_cell *c = &h->cells[*next];
        size_t ne = rf_qsum_encode(&c->energy_kj, NULL, 0);
        size_t nh = rf_qsum_encode(&c->height_m, NULL, 0);
        if (4 + ne + nh > cap - at)
            break;
        for (int k = 0; k < 4; k++)
            buf[at++] = (unsigned char)(c->cell >> (8 * k));
        at += rf_qsum_encode(&c->energy_kj, buf + at, ne);
        at += rf_qsum_encode(&c->height_m, buf + at, nh);
    }
    return at;
}

int rf_hazard_unpack_merge(rf_hazard *into, const unsigned char *buf, size_t len)
{
    size_t at = 0;
    while (at < len) {
        if (len - at < 4)
            return -1;
        uint32_t cell = 0;
        for (int k = 0; k < 4; k++)
            cell |= (uint32_t)buf[at++] << (8 * k);
        rf_qsum e, hm;
        size_t ue = 0, uh = 0;
        if (rf_qsum_decode(&e, buf + at, len - at, &ue))
            return -1;
        at += ue;
        if (rf_qsum_decode(&hm, buf + at, len - at, &uh)) {
            rf_qsum_free(&e);
            return -1;
        }
        at += uh;
        rf_hazard_cell *c = cell < into->nx * into->ny ? cell_of(into, cell) : NULL;
        int bad = !c || e.n != hm.n ||
                  rf_qsum_merge(&c->energy_kj, &e, &RF_HAZARD_ENERGY_SCALE) ||
                  rf_qsum_merge(&c->height_m, &hm, &RF_HAZARD_HEIGHT_SCALE);
        rf_qsum_free(&e);
        rf_qsum_free(&hm);
        if (bad)
            return -1;
    }
    return 0;
}

const rf_hazard_cell *rf_hazard_at(const rf_hazard *h, size_t ix, size_t iy)
{
    if (ix >= h->nx || iy >= h->ny)
        return NULL;
    const uint32_t *at = map_get(&h->where, (uint32_t)(iy * h->nx + ix));
    return at ? &h->cells[*at] : NULL;
}

size_t rf_hazard_bytes(const rf_hazard *h)
{
    size_t b = h->cap_cells * sizeof *h->cells + h->cap_touched * sizeof *h->touched +
               map_bytes(&h->where) + map_bytes(&h->slot);
    for (size_t i = 0; i < h->ncells; i++)
        b += rf_qsum_bytes(&h->cells[i].energy_kj) + rf_qsum_bytes(&h->cells[i].height_m);
    return b;
}

static int by_cell(const void *a, const void *b)
{
    uint32_t x = (*(rf_hazard_cell *const *)a)->cell, y = (*(rf_hazard_cell *const *)b)->cell;
    return (x > y) - (x < y);
}

int rf_hazard_write(rf_hazard *h, long n_trajectories, rf_store *s, rf_error *err)
{
    rf_hazard_cell **order = malloc((h->ncells ? h->ncells : 1) * sizeof *order);
    if (!order)
        return rf_error_set(err, "", 0, 0, "out of memory writing the hazard map");
    for (size_t i = 0; i < h->ncells; i++)
        order[i] = &h->cells[i];
    qsort(order, h->ncells, sizeof *order, by_cell); /* iy, then ix */
    int status = rf_store_batch_begin(s, err);
    for (size_t i = 0; status == 0 && i < h->ncells; i++) {
        const rf_hazard_cell *c = order[i];
        size_t ix = c->cell % h->nx, iy = c->cell / h->nx;
        rf_hazard_cell_record r;
        r.ix = (long)ix;
        r.iy = (long)iy;
        r.x = h->x0 + ((double)ix + 0.5) * h->cell;
        r.y = h->y0 + ((double)iy + 0.5) * h->cell;
        r.passes = (long)c->energy_kj.n;
        r.reach_probability = (double)c->energy_kj.n / (double)n_trajectories;
        r.energy_p95_kj = rf_qsum_quantile(&c->energy_kj, &RF_HAZARD_ENERGY_SCALE, 0.95);
        r.energy_max_kj = c->energy_kj.max;
        r.height_p95_m = rf_qsum_quantile(&c->height_m, &RF_HAZARD_HEIGHT_SCALE, 0.95);
        status = rf_store_add_hazard_cell(s, &r, err); /* a failure rolls the batch back */
    }
    free(order);
    return status ? -1 : rf_store_batch_commit(s, err);
}
