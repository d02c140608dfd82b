/* state.h - the types the engine's files share: the rock's state on the terrain
 * (rf_motion), its support, a contact found by the search, the workspace, and how a
 * piece of surface motion ends.  Functions live with their concern:
 *
 *   geometry    triangles, columns, planes               (no state)
 *   hodograph   sliding and rolling off the fall line in closed form (no state)
 *   rock        the rock's records, energy, spin, draws  (bottom)
 *   travel      lines being passed, the tree odometer
 *   tables      per-terrain tables: boxes, edge lengths, live edges, holes
 *   contact     the earliest contact along an arc; contact_tri: one triangle's tests
 *   exit        where the centre leaves the terrain
 *   feature     distances to the terrain's features
 *   impact      every impact (Eq. 8; walls; trees) and the roll over an edge
 *   scene_events  measure crossings and tree hits
 *   surface_law   the laws on a face and in a crease (Eq. 1-2, 5/7 law)
 *   face_entry    landing, creases, walls of the centre mode
 *   face_exit     leaving a face over an edge
 *   segment, path closed-form segments on the fall line, and off it
 *   surface     one step of the surface phase (face, wall, crease)
 *   progress    the start, the progress watch and the rescue
 *   fixed_step  the fixed-step engine;  motion: the exact engine and sim.h
 *
 * docs/engine.md describes the phases, events, root finding and tolerances. */
#ifndef ROCKFALL_ENGINE_STATE_H
#define ROCKFALL_ENGINE_STATE_H

#include <stdint.h>

#include "rockfall/sim.h"
#include "scene/measures.h"
#include "base/arc.h"
#include "base/tolerances.h"
#include "base/util.h"

typedef enum rf_feature { RF_FEAT_FACE, RF_FEAT_EDGE, RF_FEAT_VERTEX } rf_feature;

typedef struct rf_contact {
    double t;        /* time along the searched arc */
    int32_t tri;     /* triangle whose face, edge or vertex is met */
    rf_feature kind;
    int index;       /* edge (0: ab, 1: bc, 2: ca) or vertex (0: a, 1: b, 2: c) */
    rf_vec3 point;   /* contact point on the terrain */
    rf_vec3 n;       /* unit contact normal, from the terrain towards the centre */
} rf_contact;

/* Support of a rock on the surface: none (flight), one face, or a crease of two. */
typedef struct rf_support {
    int n;
    int32_t tri[3];   /* tri[0], tri[1]: the faces; tri[2] only in search exclusions */
    int32_t left;     /* a face the rock has just left over its edge (or -1): the next
                         segment's contact search ignores its face, not its edges and
                         vertices */
    int rolling;      /* sphere rolls without slip */
    int32_t zone;     /* zone whose coefficients mu and mu_r were drawn */
    double mu, mu_r;
} rf_support;

/* contact.c: a table of the distinct edges and vertices met in one search */
#define RF_FEAT_SLOTS 1024
typedef struct rf_feat_slot {
    uint64_t key;
    uint32_t gen;     /* slot in use when equal to rf_workspace.feat_gen */
    int32_t tri, k;   /* first triangle holding it; vertex k, or edge (k & 3) | 4 */
} rf_feat_slot;

/* The read-only tables of one terrain (tables.c), built once and shared by the
 * workspaces of all threads. */
struct rf_terrain_tables {
    const rf_terrain *terrain;
    /* meshes and profiles, and grids that keep their triangles; NULL for a grid that
     * derives them, whose boxes and lengths are derived too (rf_tri_box, rf_tri_hedge) */
    float *tri_box;   /* per triangle: xmin, xmax, ymin, ymax, zmin, zmax (rounded
                         outwards) */
    double *hedge;    /* per triangle: the horizontal lengths of edges ab, bc, ca */
    uint8_t *edge_live; /* per triangle, bit k: edge k can be met first (not strictly
                           concave: convex, nearly flat, or on the border); meshes, bit
                           RF_EDGE_BORDER << k: edge k is a border in plan (one
                           holder covers ground: no other, or only vertical ones) */
    uint8_t *cell_live; /* grids: per cell, bits 0-2 triangle 0's edge_live bits, bits
                           3-5 triangle 1's (rf_edge_live) */
    int has_gaps;     /* the terrain has holes: nodata triangles of a grid, or edges of
                         a mesh on its border in plan off its bounding box's sides */
    double nz_min;    /* the smallest z component of the faces' unit normals, at least
                         RF_NZ_MIN (centre contact: a centre meets a face r / n.z
                         above) */
};

/* Slots of a workspace's cache of a grid's derived triangles (a power of two). */
#define RF_FACE_CACHE 256

/* contact.c: a slot of the set of triangles a flight's search has tested */
typedef struct rf_tested_slot {
    int32_t tri;
    uint32_t gen;     /* slot in use when equal to rf_workspace.tested_gen */
} rf_tested_slot;

/* One thread's scratch for the motion of its rocks, over the shared tables; none of it
 * grows with a grid that derives its triangles (a terrain that keeps its triangles, a
 * mesh or a grid of at most RF_GRID_KEEP_TRIANGLES, has a mark per triangle for a
 * flight's tested set, and a mesh a stamp per triangle for its box queries). */
struct rf_workspace {
    const rf_terrain_tables *tables;
    rf_terrain_tables *own; /* the tables, when the workspace built them itself */
    int32_t *cand;    /* candidate triangles */
    size_t cap;
    uint32_t *stamp;  /* meshes: query stamps, one per triangle; NULL for a grid */
    uint32_t epoch;
    int32_t *near_hit; /* candidates of a surface segment */
    size_t near_cap;
    int32_t *pend_idx; /* triangles whose edges and vertices are still to test */
    double *pend_w0;
    size_t pend_cap;
    rf_tested_slot *tested; /* flights: the triangles tested in the current search, an
                               open-addressing set of tested_cap (a power of two) slots
                               at most half full, emptied by a new tested_gen */
    size_t tested_cap, tested_n;
    uint32_t tested_gen;
    uint32_t *tested_mark; /* a terrain that keeps its triangles: the set as one mark per
                              triangle (tested_gen: in the set), NULL otherwise */
    /* a grid's triangles derived lately (rf_face): face[h] is triangle face_key[h]
       (-1: none), h its index modulo RF_FACE_CACHE */
    int32_t face_key[RF_FACE_CACHE];
    rf_triangle face[RF_FACE_CACHE];
    int32_t box_key[RF_FACE_CACHE]; /* the same for the boxes of rf_tri_box */
    float box[RF_FACE_CACHE][6];
    /* contact.c: shared edges and vertices (zeroed by calloc; no allocation) */
    uint32_t feat_gen;
    size_t feat_used; /* slots in use in the current generation */
    rf_feat_slot feat[RF_FEAT_SLOTS];
};

/* Triangle idx of terrain t as the workspace sees it: a mesh's own; a grid's copied into
 * buf from the workspace's cache of derived triangles (rf_grid_triangle on a miss), so
 * that the pointer stays valid while buf does, whatever is derived meanwhile. */
static inline const rf_triangle *rf_face(rf_workspace *ws, const rf_terrain *t, int32_t idx,
                                         rf_triangle *buf)
{
    if (t->tri)
        return &t->tri[idx];
    if (ws->tables->terrain != t) {
        rf_grid_triangle(t, idx, buf);
        return buf;
    }
    unsigned h = (unsigned)idx & (RF_FACE_CACHE - 1);
    if (ws->face_key[h] != idx) {
        rf_grid_triangle(t, idx, &ws->face[h]);
        ws->face_key[h] = idx;
    }
    *buf = ws->face[h];
    return buf;
}

/* rf_face for motion m into a buffer of the enclosing block (a compound literal, made
 * only for a grid that derives its triangles). */
#define RF_FACE(m, idx)                                                                          \
    ((m)->cfg.terrain->tri ? &(m)->cfg.terrain->tri[idx]                                         \
                           : rf_face((m)->ws, (m)->cfg.terrain, (idx), &(rf_triangle){.zone = 0}))

/* rf_tri_corners for motion m: a full face in centre mode (which reads its normal),
 * else only the corners. */
#define RF_CORNERS(m, idx)                                                                       \
    ((m)->cfg.terrain->tri ? &(m)->cfg.terrain->tri[idx]                                         \
     : (m)->cfg.centre     ? RF_FACE(m, idx)                                                     \
                           : rf_tri_corners((m)->cfg.terrain, (idx), &(rf_triangle){.zone = 0}))

/* A measure's line the rock has just crossed (scene_events.c): the crossed segment's
 * line, through (ax, ay) with unit normal (nx, ny) in plan. */
typedef struct rf_passage {
    int measure;
    double ax, ay, nx, ny;
} rf_passage;

/* The rock's hot state: what every piece of motion reads and moves (b2BodyState's
 * counterpart). */
typedef struct rf_rock_state {
    rf_state s;           /* p, v, w, t */
    rf_support sup;       /* none (flight), a face or a crease; its coefficients */
    rf_support flight_ex; /* faces a flight ignores (the face it rolled off) */
} rf_rock_state;

/* What stays the same over a trajectory: the scene and the body, and the tolerances
 * scaled to the terrain. */
typedef struct rf_motion_config {
    const rf_scene *scene;
    const rf_terrain *terrain;
    const rf_body *body;
    double rho;        /* contact radius: r for the sphere, 0 for the point */
    int point;         /* point model: no size, no rotation */
    int centre;        /* contact `centre`: only the face under the centre (Eq. 6-7) */
    double tol_len;    /* length tolerance for this terrain */
    double v_stay;     /* rebound normal speed below which the rock stays on the surface */
    double t_end;      /* max_time */
} rf_motion_config;

/* The bookkeeping of a trajectory: its records and sink, and the watch on its
 * progress (stalls, creep, rescues). */
typedef struct rf_motion_book {
    const rf_sink *sink;
    rf_trajectory_record *rec;
    double sample_acc; /* horizontal travel since the last sample */
    long events;
    long marked;       /* events marked (rf_motion_event) */
    double stall_t;    /* time of the last event that advanced time by RF_STALL_TIME */
    int stall;         /* events since */
    rf_vec3 creep_p;   /* where the rock was when it last moved on or was fast */
    int creep;         /* events since */
    long rescues;
    int wedged;        /* centre mode: a rescue found the rock wedged among walls at wedge_p */
    rf_vec3 wedge_p;
} rf_motion_book;

/* The scene events of a trajectory (scene_events.c, travel.c): measure crossings and
 * tree collisions. */
typedef struct rf_scene_state {
    int pending;             /* what rf_scene_horizon found: RF_SCENE_NONE, _MEASURE or _TREE */
    rf_vec3 seen;            /* where the measures last saw the centre: the end of the last
                                piece of motion or scene event (a move in no time since, a
                                roll over an edge or a lift, is checked for crossings) */
    int jumping;             /* the crossings pending are of that move, from seen */
    rf_crossing crossings[RF_MAX_COINCIDENT_CROSSINGS]; /* the measures crossed, at once */
    int ncrossings;
    rf_passage passing[RF_MAX_COINCIDENT_CROSSINGS]; /* lines being passed (travel.c) */
    int npassing;
    int tree_forest;         /* the forest of the tree collision found */
    double tree_bound;       /* summed rate bound of the forests per metre; 0: none */
    double phi_r;            /* rock diameter in Eq. 12 */
    double odo;              /* horizontal distance travelled */
    double tree_next;        /* odometer of the next candidate tree event (thinning) */
    double tree_u;           /* its uniform acceptance draw */
    long tree_draws;         /* candidate tree events drawn so far (RF_TREE_MAX_DRAWS) */
    int trees_given_up;      /* the draws ran out: the trajectory ends (max_time) */
} rf_scene_state;

/* One rock's trajectory under way. */
typedef struct rf_motion {
    rf_rock_state rock;
    rf_motion_config cfg;
    gsl_rng *rng;
    rf_workspace *ws;
    rf_motion_book book;
    rf_scene_state scn;
} rf_motion;

/* How a piece of surface motion ends. */
typedef enum rf_surface_end {
    RF_SURF_CONTINUE,  /* the support changed; carry on */
    RF_SURF_FLIGHT,    /* left the surface */
    RF_SURF_REST,
    RF_SURF_EXITED,
    RF_SURF_MAX_TIME,
    RF_SURF_STOPPED    /* stopped by a scene event (a measure) */
} rf_surface_end;

/* What rf_scene_horizon found (rf_motion.scene_pending). */
enum { RF_SCENE_NONE, RF_SCENE_MEASURE, RF_SCENE_TREE };

/* Bit RF_EDGE_BORDER << k of a triangle's live-edge flags: edge k is a border in plan. */
#define RF_EDGE_BORDER 16u

#endif
