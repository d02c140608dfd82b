/* tables.h - per-terrain tables the contact search reads (tables.c): each triangle's
 * box, the horizontal lengths of its edges, and which of its edges can be met first
 * (not strictly concave) or are borders in plan. */
#ifndef ROCKFALL_ENGINE_TABLES_H
#define ROCKFALL_ENGINE_TABLES_H

#include <stdint.h>
#include <string.h>

#include "engine/state.h"

/* The tables of terrain t are built and released by rf_terrain_tables_build and
 * rf_terrain_tables_free (sim.h); the engine reads them through its workspace. */

/* Bit k: edge k of triangle idx can be met first (a grid's flags hold bit 3 as a
 * mesh's before its borders are marked: 8 | bits). */
static inline unsigned rf_edge_live(const rf_workspace *ws, int32_t idx)
{
    const rf_terrain_tables *tt = ws->tables;
    if (tt->edge_live)
        return tt->edge_live[idx];
    return 8u | ((unsigned)tt->cell_live[idx >> 1] >> (3 * (idx & 1)) & 7u);
}

/* A grid's box and edge lengths of triangle idx, derived from its heights with the
 * arithmetic of a mesh's tables (tables.c). */
void rf_grid_box(const rf_terrain *t, int32_t idx, float box[6]);
void rf_grid_hedge(const rf_terrain *t, int32_t idx, double hedge[3]);

/* Triangle idx's box: xmin, xmax, ymin, ymax, zmin, zmax rounded outwards to floats
 * (a grid's copied into buf from the workspace's cache, derived on a miss). */
static inline const float *rf_tri_box(rf_workspace *ws, int32_t idx, float buf[6])
{
    const rf_terrain_tables *tt = ws->tables;
    if (tt->tri_box)
        return tt->tri_box + 6 * (size_t)idx;
    unsigned h = (unsigned)idx & (RF_FACE_CACHE - 1);
    if (ws->box_key[h] != idx) {
        rf_grid_box(tt->terrain, idx, ws->box[h]);
        ws->box_key[h] = idx;
    }
    memcpy(buf, ws->box[h], 6 * sizeof *buf);
    return buf;
}

/* Triangle idx's horizontal edge lengths, ab, bc, ca (a grid's into buf). */
static inline const double *rf_tri_hedge(const rf_terrain_tables *tt, int32_t idx, double buf[3])
{
    if (tt->hedge)
        return tt->hedge + 3 * (size_t)idx;
    rf_grid_hedge(tt->terrain, idx, buf);
    return buf;
}

/* Hashes of coordinates, for the keys of a mesh's vertices and edges. */
static inline uint64_t rf_mix64(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    h ^= h >> 33;
    return h;
}

static inline uint64_t rf_point_hash(rf_vec3 p)
{
    uint64_t a, b, c;
    memcpy(&a, &p.x, 8);
    memcpy(&b, &p.y, 8);
    memcpy(&c, &p.z, 8);
    return rf_mix64(a ^ rf_mix64(b ^ rf_mix64(c)));
}

/* The key of a mesh edge between vertices of hashes ha and hb (either order). */
static inline uint64_t rf_mesh_edge_key(uint64_t ha, uint64_t hb)
{
    return ha < hb ? rf_mix64(ha ^ rf_mix64(hb)) : rf_mix64(hb ^ rf_mix64(ha));
}

#endif
