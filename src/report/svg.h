/* svg.h - a small writer of self-contained SVG figures: a plot frame mapping data
 * coordinates to pixels, axes with round ticks, paths, rectangles, escaped text and
 * stacked histograms.  Output is deterministic: fixed number formats, no clock. */
#ifndef ROCKFALL_SVG_H
#define ROCKFALL_SVG_H

#include <stddef.h>
#include <stdio.h>

#include "rockfall/error.h"

typedef struct rf_svg {
    FILE *f;
    char path[4096];
    double left, top, right, bottom;  /* plot area (px) */
    double x0, x1, y0, y1;            /* data range of the plot area; y up */
    int y_counts;                     /* y ticks at whole numbers only (counts) */
    double x_origin, y_origin;        /* subtracted from the tick labels (rf_svg_axes) */
} rf_svg;

/* Creates the file and writes the <svg> head, a white background and the title
 * (escaped) at the top.  Returns 0, or fills err. */
int rf_svg_open(rf_svg *s, const char *path, double width, double height, const char *title,
                rf_error *err);
/* Writes </svg> and closes the file; an error when anything failed to write. */
int rf_svg_close(rf_svg *s, rf_error *err);

/* The plot area in pixels and the data range it shows. */
void rf_svg_frame(rf_svg *s, double left, double top, double right, double bottom, double x0,
                  double x1, double y0, double y1);
double rf_svg_px(const rf_svg *s, double x);
double rf_svg_py(const rf_svg *s, double y);

/* XML text escaping (& < > " '). */
void rf_svg_escape(FILE *f, const char *text);
/* <text> at a pixel position; `attrs` are literal attributes (not escaped), the
 * formatted text is escaped. */
void rf_svg_text(rf_svg *s, double px, double py, const char *attrs, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* A literal element or fragment, written as given (the caller's own markup). */
void rf_svg_raw(rf_svg *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A round step (1, 2 or 5 times a power of ten) giving about `target` steps over
 * `range`. */
double rf_svg_nice_step(double range, int target);
/* The width (px) of text at font_size as the figures' font (DejaVu Sans) sets it: its
 * advance widths for digits, signs and spaces, 0.7 em (wider than any of its Latin
 * letters but W and M) for every other byte. */
double rf_svg_text_width(const char *text, double font_size);
/* The origin an axis over [lo, hi] counts its tick labels from: 0 when its labels are
 * short (below 10 000, or a span of at least a tenth of the values, or both signs);
 * else the round number at or below lo that is a multiple of the power of ten at or
 * above the span (at least 1), so national coordinates (LV95 2 600 000 / 1 200 000,
 * Lambert-93 700 000 / 6 600 000) are labelled as metres within the site. */
double rf_svg_axis_origin(double lo, double hi);
/* v with its thousands set apart by spaces ("2 600 000"), as many decimals as given. */
void rf_svg_format_grouped(char *buf, size_t n, double v, int decimals);
/* Frame, ticks with labels on both axes and the axis titles (escaped).  The x ticks
 * are spaced so that no two labels overlap (rf_svg_text_width, 8 px apart at least).
 * An axis with an origin (rf_svg_axis_origin, kept in x_origin / y_origin) labels its
 * ticks from it and its title says so: "x (m)" becomes "x - 2 600 000 (m)". */
void rf_svg_axes(rf_svg *s, const char *xlabel, const char *ylabel);

/* One <path> in data coordinates: begin, move/line, end. */
void rf_svg_path_begin(rf_svg *s, const char *attrs);
void rf_svg_path_move(rf_svg *s, double x, double y);
void rf_svg_path_line(rf_svg *s, double x, double y);
void rf_svg_path_end(rf_svg *s);
/* A rectangle between two data corners. */
void rf_svg_rect(rf_svg *s, double xa, double ya, double xb, double yb, const char *attrs);
/* A line between two data points. */
void rf_svg_line(rf_svg *s, double xa, double ya, double xb, double yb, const char *attrs);

/* Bars of nseries stacked series over nbins bins [lo + i*bin, lo + (i+1)*bin):
 * counts[k * nbins + i] is series k in bin i; fills[k] its colour. */
void rf_svg_stacked_bars(rf_svg *s, const double *counts, size_t nseries, size_t nbins, double lo,
                         double bin, const char *const *fills);

#endif
