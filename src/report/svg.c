/* svg.c - the small SVG writer of the report. */
#include "report/svg.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "base/tolerances.h"
#include "base/util.h"

#define SVG_FONT "font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\""
/* The axes' tick labels: the document's font size, and the least gap between two. */
#define AXIS_FONT_PX 13.0
#define TICK_LABEL_GAP 8.0

int rf_svg_open(rf_svg *s, const char *path, double width, double height, const char *title,
                rf_error *err)
{
    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "%s", path);
    s->f = rf_create_file(path, err);
    if (!s->f)
        return -1;
    fprintf(s->f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
            "viewBox=\"0 0 %.0f %.0f\" " SVG_FONT " font-size=\"13\">\n",
            width, height, width, height);
    fputs("<title>", s->f);
    rf_svg_escape(s->f, title);
    fputs("</title>\n", s->f);
    fprintf(s->f, "<rect x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", width,
            height);
    rf_svg_text(s, width / 2, 22, "text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\"",
                "%s", title);
    return 0;
}

int rf_svg_close(rf_svg *s, rf_error *err)
{
    if (!s->f)
        return 0;
    fputs("</svg>\n", s->f);
    int bad = ferror(s->f);
    if (fclose(s->f))
        bad = 1;
    s->f = NULL;
    if (bad)
        return rf_error_set(err, s->path, 0, 0, "cannot write: %s", strerror(errno));
    return 0;
}

void rf_svg_frame(rf_svg *s, double left, double top, double right, double bottom, double x0,
                  double x1, double y0, double y1)
{
    s->left = left;
    s->top = top;
    s->right = right;
    s->bottom = bottom;
    s->x0 = x0;
    s->x1 = x1 > x0 ? x1 : x0 + 1.0;
    s->y0 = y0;
    s->y1 = y1 > y0 ? y1 : y0 + 1.0;
}

double rf_svg_px(const rf_svg *s, double x)
{
    return s->left + (x - s->x0) / (s->x1 - s->x0) * (s->right - s->left);
}

double rf_svg_py(const rf_svg *s, double y)
{
    return s->bottom - (y - s->y0) / (s->y1 - s->y0) * (s->bottom - s->top);
}

void rf_svg_escape(FILE *f, const char *text)
{
    for (const char *c = text; c && *c; c++) {
        switch (*c) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&#39;", f); break;
        default:
            /* control characters are not allowed in XML 1.0 */
            if ((unsigned char)*c < 0x20 && *c != '\n' && *c != '\t')
                fputc('?', f);
            else
                fputc(*c, f);
        }
    }
}

void rf_svg_text(rf_svg *s, double px, double py, const char *attrs, const char *fmt, ...)
{
    char buf[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fprintf(s->f, "<text x=\"%.1f\" y=\"%.1f\"%s%s>", px, py, attrs && *attrs ? " " : "",
            attrs ? attrs : "");
    rf_svg_escape(s->f, buf);
    fputs("</text>\n", s->f);
}

void rf_svg_raw(rf_svg *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfprintf(s->f, fmt, ap);
    va_end(ap);
}

double rf_svg_nice_step(double range, int target)
{
    if (!(range > 0.0) || !isfinite(range))
        return 1.0;
    double raw = range / (target > 0 ? target : 1);
    double p = pow(10.0, floor(log10(raw)));
    double m = raw / p;
    double nice = m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0;
    return nice * p;
}

/* Decimals that show a tick step exactly. */
static int step_decimals(double step)
{
    int d = (int)-floor(log10(step) + RF_TICK_SNAP);
    return d < 0 ? 0 : d > 6 ? 6 : d;
}

/* Advance widths of DejaVu Sans (the figures' first font), in em: digits 1303 of its
 * 2048 units per em, '.' and ' ' 651, '-' 739, U+2212 1716. */
#define EM_DIGIT (1303.0 / 2048.0)
#define EM_POINT (651.0 / 2048.0)
#define EM_HYPHEN (739.0 / 2048.0)
#define EM_MINUS (1716.0 / 2048.0)
#define EM_OTHER 0.7

double rf_svg_text_width(const char *text, double font_size)
{
    double em = 0.0;
    for (const unsigned char *c = (const unsigned char *)text; c && *c; c++) {
        if (*c >= '0' && *c <= '9')
            em += EM_DIGIT;
        else if (*c == '.' || *c == ' ' || *c == ',')
            em += EM_POINT;
        else if (*c == '-')
            em += EM_HYPHEN;
        else if (c[0] == 0xe2 && c[1] == 0x88 && c[2] == 0x92) {
            em += EM_MINUS;
            c += 2;
        } else if ((*c & 0xc0) != 0x80)
            em += EM_OTHER; /* one per character: UTF-8 continuation bytes add nothing */
    }
    return em * font_size;
}

double rf_svg_axis_origin(double lo, double hi)
{
    double span = hi - lo, big = fmax(fabs(lo), fabs(hi));
    if (!isfinite(span) || !(span >= 0.0) || big < 1e4 || lo * hi <= 0.0 || big < 10.0 * span)
        return 0.0;
    double p = span > 1.0 ? pow(10.0, ceil(log10(span))) : 1.0;
    return floor(lo / p) * p;
}

void rf_svg_format_grouped(char *buf, size_t n, double v, int decimals)
{
    char raw[64];
    snprintf(raw, sizeof raw, "%.*f", decimals, fabs(v) < 1e300 ? v : 0.0);
    const char *digits = raw + (raw[0] == '-');
    size_t nint = strcspn(digits, ".");
    size_t o = 0;
    if (raw[0] == '-' && o + 1 < n)
        buf[o++] = '-';
    for (size_t i = 0; digits[i] && o + 1 < n; i++) {
        if (i > 0 && i < nint && (nint - i) % 3 == 0 && o + 2 < n)
            buf[o++] = ' ';
        buf[o++] = digits[i];
    }
    if (n)
        buf[o < n ? o : n - 1] = '\0';
}

/* The first tick at or above lo, a whole number of steps from 0. */
static double first_tick(double lo, double step)
{
    return ceil(lo / step - RF_TICK_SNAP) * step;
}

/* The label of the tick at v: v - origin with the step's decimals, never "-0". */
static void tick_label(char *buf, size_t n, double v, double origin, double step)
{
    double shown = v - origin;
    snprintf(buf, n, "%.*f", step_decimals(step), fabs(shown) < RF_TICK_SNAP * step ? 0.0 : shown);
}

/* The widest x tick label at this step (px, the axes' 13 px font). */
static double widest_label(const rf_svg *s, double step)
{
    double w = 0.0;
    char buf[64];
    for (double v = first_tick(s->x0, step); v <= s->x1 + RF_TICK_SNAP * step; v += step) {
        tick_label(buf, sizeof buf, v, s->x_origin, step);
        w = fmax(w, rf_svg_text_width(buf, AXIS_FONT_PX));
    }
    return w;
}

/* The next round step above `step`: 1 -> 2 -> 5 -> 10 times a power of ten. */
static double next_step(double step)
{
    double p = pow(10.0, floor(log10(step) + RF_TICK_SNAP));
    double m = step / p;
    return (m < 1.5 ? 2.0 : m < 3.5 ? 5.0 : 10.0) * p;
}

/* The number of ticks at this step within [x0, x1]. */
static long tick_count(const rf_svg *s, double step)
{
    return (long)(floor(s->x1 / step + RF_TICK_SNAP) - ceil(s->x0 / step - RF_TICK_SNAP)) + 1;
}

/* The x tick step: about one per 90 px, widened until the widest label and a gap of
 * TICK_LABEL_GAP px fit between two ticks.  *nmax gets the number of ticks to draw:
 * all of them, or 1 on a plot too narrow for two labels. */
static double x_tick_step(const rf_svg *s, long *nmax)
{
    double px_per_unit = (s->right - s->left) / (s->x1 - s->x0);
    double step = rf_svg_nice_step(s->x1 - s->x0, (int)((s->right - s->left) / 90.0) + 1);
    *nmax = LONG_MAX;
    while (tick_count(s, step) > 1 &&
           widest_label(s, step) + TICK_LABEL_GAP > step * px_per_unit) {
        if (tick_count(s, next_step(step)) < 1) {
            *nmax = 1;
            break;
        }
        step = next_step(step);
    }
    return step;
}

/* An axis title with the origin its labels count from: "x (m)" and 2 600 000 give
 * "x \u2212 2 600 000 (m)" (the origin before a closing "(unit)"). */
static void origin_title(char *buf, size_t n, const char *label, double origin)
{
    if (origin == 0.0) {
        snprintf(buf, n, "%s", label);
        return;
    }
    char num[64];
    rf_svg_format_grouped(num, sizeof num, fabs(origin), 0);
    const char *sign = origin > 0 ? "\xe2\x88\x92" : "+";
    size_t len = strlen(label);
    const char *unit = len && label[len - 1] == ')' ? strrchr(label, '(') : NULL;
    if (unit && unit > label && unit[-1] == ' ')
        snprintf(buf, n, "%.*s %s %s %s", (int)(unit - label - 1), label, sign, num, unit);
    else
        snprintf(buf, n, "%s %s %s", label, sign, num);
}

void rf_svg_axes(rf_svg *s, const char *xlabel, const char *ylabel)
{
    FILE *f = s->f;
    fprintf(f,
            "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
            "stroke=\"#333\" stroke-width=\"1\"/>\n",
            s->left, s->top, s->right - s->left, s->bottom - s->top);
    s->x_origin = rf_svg_axis_origin(s->x0, s->x1);
    s->y_origin = rf_svg_axis_origin(s->y0, s->y1);
    long nxmax;
    double xstep = x_tick_step(s, &nxmax);
    double ystep = rf_svg_nice_step(s->y1 - s->y0, (int)((s->bottom - s->top) / 60.0) + 1);
    if (s->y_counts && ystep < 1.0)
        ystep = 1.0;
    fputs("<g stroke=\"#333\" stroke-width=\"1\">\n", f);
    long nx = 0;
    for (double v = first_tick(s->x0, xstep); v <= s->x1 + RF_TICK_SNAP * xstep && nx++ < nxmax;
         v += xstep) {
        double px = rf_svg_px(s, v);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", px, s->bottom, px,
                s->bottom + 5);
    }
    for (double v = first_tick(s->y0, ystep); v <= s->y1 + RF_TICK_SNAP * ystep; v += ystep) {
        double py = rf_svg_py(s, v);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", s->left - 5, py,
                s->left, py);
    }
    fputs("</g>\n", f);
    char label[64];
    nx = 0;
    for (double v = first_tick(s->x0, xstep); v <= s->x1 + RF_TICK_SNAP * xstep && nx++ < nxmax;
         v += xstep) {
        tick_label(label, sizeof label, v, s->x_origin, xstep);
        rf_svg_text(s, rf_svg_px(s, v), s->bottom + 19, "class=\"xtick\" text-anchor=\"middle\"",
                    "%s", label);
    }
    for (double v = first_tick(s->y0, ystep); v <= s->y1 + RF_TICK_SNAP * ystep; v += ystep) {
        tick_label(label, sizeof label, v, s->y_origin, ystep);
        rf_svg_text(s, s->left - 8, rf_svg_py(s, v) + 4, "class=\"ytick\" text-anchor=\"end\"",
                    "%s", label);
    }
    char title[1024];
    if (xlabel) {
        origin_title(title, sizeof title, xlabel, s->x_origin);
        rf_svg_text(s, (s->left + s->right) / 2, s->bottom + 40, "text-anchor=\"middle\"", "%s",
                    title);
    }
    if (ylabel) {
        double cx = s->left - 52, cy = (s->top + s->bottom) / 2;
        char attrs[160];
        snprintf(attrs, sizeof attrs, "text-anchor=\"middle\" transform=\"rotate(-90 %.1f %.1f)\"",
                 cx, cy);
        origin_title(title, sizeof title, ylabel, s->y_origin);
        rf_svg_text(s, cx, cy, attrs, "%s", title);
    }
}

void rf_svg_path_begin(rf_svg *s, const char *attrs)
{
    fprintf(s->f, "<path %s d=\"", attrs ? attrs : "");
}

void rf_svg_path_move(rf_svg *s, double x, double y)
{
    fprintf(s->f, "M%.1f %.1f", rf_svg_px(s, x), rf_svg_py(s, y));
}

void rf_svg_path_line(rf_svg *s, double x, double y)
{
    fprintf(s->f, "L%.1f %.1f", rf_svg_px(s, x), rf_svg_py(s, y));
}

void rf_svg_path_end(rf_svg *s)
{
    fputs("\"/>\n", s->f);
}

void rf_svg_rect(rf_svg *s, double xa, double ya, double xb, double yb, const char *attrs)
{
    double pxa = rf_svg_px(s, xa), pxb = rf_svg_px(s, xb);
    double pya = rf_svg_py(s, ya), pyb = rf_svg_py(s, yb);
    fprintf(s->f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" %s/>\n",
            fmin(pxa, pxb), fmin(pya, pyb), fabs(pxb - pxa), fabs(pyb - pya), attrs ? attrs : "");
}

void rf_svg_line(rf_svg *s, double xa, double ya, double xb, double yb, const char *attrs)
{
    fprintf(s->f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" %s/>\n", rf_svg_px(s, xa),
            rf_svg_py(s, ya), rf_svg_px(s, xb), rf_svg_py(s, yb), attrs ? attrs : "");
}

void rf_svg_stacked_bars(rf_svg *s, const double *counts, size_t nseries, size_t nbins, double lo,
                         double bin, const char *const *fills)
{
    for (size_t i = 0; i < nbins; i++) {
        double base = 0.0;
        double xa = lo + (double)i * bin, xb = xa + bin;
        for (size_t k = 0; k < nseries; k++) {
            double c = counts[k * nbins + i];
            if (c <= 0.0)
                continue;
            char attrs[128];
            snprintf(attrs, sizeof attrs, "fill=\"%s\" stroke=\"#222\" stroke-width=\"0.5\"",
                     fills[k]);
            rf_svg_rect(s, xa, base, xb, base + c, attrs);
            base += c;
        }
    }
}
