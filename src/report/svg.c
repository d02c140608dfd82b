/* svg.c - the small SVG writer of the report. */
#include "report/svg.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "base/tolerances.h"
#include "base/util.h"

#define SVG_FONT "font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\""

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

void rf_svg_axes(rf_svg *s, const char *xlabel, const char *ylabel)
{
    FILE *f = s->f;
    fprintf(f,
            "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
            "stroke=\"#333\" stroke-width=\"1\"/>\n",
            s->left, s->top, s->right - s->left, s->bottom - s->top);
    double xstep = rf_svg_nice_step(s->x1 - s->x0, (int)((s->right - s->left) / 90.0) + 1);
    double ystep = rf_svg_nice_step(s->y1 - s->y0, (int)((s->bottom - s->top) / 60.0) + 1);
    if (s->y_counts && ystep < 1.0)
        ystep = 1.0;
    int xd = step_decimals(xstep), yd = step_decimals(ystep);
    fputs("<g stroke=\"#333\" stroke-width=\"1\">\n", f);
    for (double v = ceil(s->x0 / xstep - RF_TICK_SNAP) * xstep; v <= s->x1 + RF_TICK_SNAP * xstep; v += xstep) {
        double px = rf_svg_px(s, v);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", px, s->bottom, px,
                s->bottom + 5);
    }
    for (double v = ceil(s->y0 / ystep - RF_TICK_SNAP) * ystep; v <= s->y1 + RF_TICK_SNAP * ystep; v += ystep) {
        double py = rf_svg_py(s, v);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", s->left - 5, py,
                s->left, py);
    }
    fputs("</g>\n", f);
    for (double v = ceil(s->x0 / xstep - RF_TICK_SNAP) * xstep; v <= s->x1 + RF_TICK_SNAP * xstep; v += xstep)
        rf_svg_text(s, rf_svg_px(s, v), s->bottom + 19, "text-anchor=\"middle\"", "%.*f", xd,
                    fabs(v) < RF_TICK_SNAP * xstep ? 0.0 : v);
    for (double v = ceil(s->y0 / ystep - RF_TICK_SNAP) * ystep; v <= s->y1 + RF_TICK_SNAP * ystep; v += ystep)
        rf_svg_text(s, s->left - 8, rf_svg_py(s, v) + 4, "text-anchor=\"end\"", "%.*f", yd,
                    fabs(v) < RF_TICK_SNAP * ystep ? 0.0 : v);
    if (xlabel)
        rf_svg_text(s, (s->left + s->right) / 2, s->bottom + 40, "text-anchor=\"middle\"", "%s",
                    xlabel);
    if (ylabel) {
        double cx = s->left - 52, cy = (s->top + s->bottom) / 2;
        char attrs[160];
        snprintf(attrs, sizeof attrs, "text-anchor=\"middle\" transform=\"rotate(-90 %.1f %.1f)\"",
                 cx, cy);
        rf_svg_text(s, cx, cy, attrs, "%s", ylabel);
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
