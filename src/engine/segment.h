/* segment.h - segments of surface motion at constant acceleration (segment.c): on the
 * fall line, or with no slope, every event time is the root of a quadratic. */
#ifndef ROCKFALL_ENGINE_SEGMENT_H
#define ROCKFALL_ENGINE_SEGMENT_H

#include "engine/state.h"
#include "engine/geometry.h"
#include "engine/rock.h"
#include "engine/surface_law.h"

/* The events that end a segment of surface motion. */
typedef enum rf_ev_kind {
    RF_EV_NONE, RF_EV_MAX_TIME, RF_EV_REST, RF_EV_ZERO, RF_EV_SLIP, RF_EV_EXIT, RF_EV_CONTACT,
    RF_EV_SCENE,
    RF_EV_LINE /* a measure's line crossed, located on a path off the fall line */
} rf_ev_kind;

/* The earliest event of a segment. */
typedef struct rf_seg_event {
    rf_ev_kind kind;
    double t;
    int edge, slot;
    rf_contact con;
    double level; /* RF_EV_REST, RF_EV_ZERO: the speed it falls to; RF_EV_EXIT: how far
                     beyond the edge */
    double line[4]; /* RF_EV_LINE: a point of the line and its unit normal towards the side
                     * the rock comes from */
} rf_seg_event;

/* The faces a surface segment's contact search ignores: the support, and once the face
 * just left over an edge. */
rf_support rf_segment_exclusion(rf_motion *m);
/* Makes (kind, t) the segment's event when it is earlier than ev's. */
void rf_seg_consider(rf_seg_event *ev, rf_ev_kind kind, double t);
/* Finishes a segment at the event: records the motion and dispatches. */
rf_surface_end rf_seg_dispatch(rf_motion *m, rf_seg_event *ev, rf_vec3 acc, const rf_face_edges *fe);
/* The end of a constant-acceleration segment along arc (face or crease), whose other
 * events are in ev: contacts with the terrain (full contact; ex ignored) and scene
 * events come first when earlier; the state is moved to the event, the spin by its
 * law (NULL: it stays), and its energy noted. */
void rf_seg_closed_finish(rf_motion *m, const rf_arc *arc, const rf_spin_law *spin,
                          const rf_support *ex, rf_seg_event *ev);
/* A segment of constant acceleration on one face; along the wall at its column edge
 * `wall` (centre mode, -1: none; dir along that edge), which takes the part of the
 * acceleration across it. */
rf_surface_end rf_face_closed(rf_motion *m, const rf_face_dyn *f, rf_vec3 dir, rf_vec3 u0,
                                  const rf_face_edges *fe, int holds, int wall);

#endif
