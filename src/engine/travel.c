/* travel.c - passages of measures' lines and the tree odometer.
 *
 * One passage of a line: a rock that crosses a measure's line and comes back across it
 * before its centre has been further than its radius from the crossed segment's line
 * passes the line once, and its crossings back and forth are not recorded again.  Once
 * further than its radius from it, the passage is over and the next crossing is a new
 * one.  The same rule passes over a crossing seen again: by the next piece of motion,
 * which starts on the line (rounded to either side of it), and as the neighbouring
 * segment's root of a crossing through a polyline vertex. */
#include "engine/travel.h"

#include <math.h>
#include <string.h>

#include "scene/vegetation.h"

/* The largest horizontal distance from the passage's line over [0, T] of the arc. */
double rf_passage_reach(const rf_passage *ps, const rf_arc *arc, double T)
{
    double f[3] = {ps->nx * (arc->p.x - ps->ax) + ps->ny * (arc->p.y - ps->ay),
                   ps->nx * arc->v.x + ps->ny * arc->v.y,
                   0.5 * (ps->nx * arc->a.x + ps->ny * arc->a.y)};
    double lo, hi;
    rf_quadratic_range(f, 0.0, fmax(T, 0.0), &lo, &hi);
    return fmax(-lo, hi);
}

/* The passage of measure `which`, or NULL. */
rf_passage *rf_passage_of(rf_motion *m, int which)
{
    for (int i = 0; i < m->scn.npassing; i++)
        if (m->scn.passing[i].measure == which)
            return &m->scn.passing[i];
    return NULL;
}

/* A crossing of segment c->segment of its measure recorded: that measure's passage
 * starts (the oldest passage makes room when all are taken). */
void rf_passage_start(rf_motion *m, const rf_crossing *c)
{
    const double *A = &m->cfg.scene->measures[c->measure].line.xy[2 * c->segment], *B = A + 2;
    double dx = B[0] - A[0], dy = B[1] - A[1], len = hypot(dx, dy);
    rf_passage *ps = rf_passage_of(m, c->measure);
    if (!ps) {
        if (m->scn.npassing == RF_MAX_COINCIDENT_CROSSINGS) {
            memmove(m->scn.passing, m->scn.passing + 1,
                    (size_t)(m->scn.npassing - 1) * sizeof *m->scn.passing);
            m->scn.npassing--;
        }
        ps = &m->scn.passing[m->scn.npassing++];
    }
    /* a crossed segment has a length (measures.c passes over a zero one) */
    *ps = (rf_passage){c->measure, A[0], A[1], -dy / len, dx / len};
}

void rf_scene_travel(rf_motion *m, const rf_arc *arc, double T)
{
    for (int i = 0; i < m->scn.npassing;) {
        if (rf_passage_reach(&m->scn.passing[i], arc, T) > m->cfg.body->radius) {
            memmove(m->scn.passing + i, m->scn.passing + i + 1,
                    (size_t)(m->scn.npassing - i - 1) * sizeof *m->scn.passing);
            m->scn.npassing--;
        } else {
            i++;
        }
    }
    m->scn.seen = rf_arc_pos(arc, T);
    if (m->scn.tree_bound > 0.0)
        m->scn.odo += rf_horizontal_length(arc->v, arc->a, T);
}
