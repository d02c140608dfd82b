/* svg_test_util.h - what the tests read back from the report's SVG figures: the tick
 * labels of an axis with their extents, and the axis titles. */
#ifndef ROCKFALL_SVG_TEST_UTIL_H
#define ROCKFALL_SVG_TEST_UTIL_H

#include <stddef.h>

/* One tick label: its anchor (px), its text, and its extent along the axis (px). */
typedef struct svg_tick {
    double x, y;
    char text[64];
    double lo, hi;
} svg_tick;

/* The labels of the elements <text ... class="CLS" ...>TEXT</text> of svg (xtick or
 * ytick), in the order written, at most max; returns their number.  An x label's extent
 * is its width centred on x, a y label's its 13 px height at y: the width counts every
 * character as 0.64 em of the 13 px font, wider than DejaVu Sans sets any digit,
 * sign or point (0.636 em at most). */
size_t svgt_ticks(const char *svg, const char *cls, svg_tick *t, size_t max);

/* ENSUREs that no two x tick labels of svg overlap, with at least `gap` px between
 * them, and that there are at least `least`; returns their number. */
size_t svgt_x_ticks_apart(const char *svg, double gap, size_t least);

#endif
