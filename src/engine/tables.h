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

/* Bit k: edge k of triangle idx can be met first. */
static inline unsigned rf_edge_live(const rf_workspace *ws, int32_t idx)
{
    return ws->tables->edge_live[idx];
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
