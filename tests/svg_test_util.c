/* svg_test_util.c - the tick labels of the report's figures, read back from the SVG. */
#include "svg_test_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

/* The width the tests give a character of a tick label (em) and the labels' font (px). */
#define TEST_EM_PER_CHAR 0.64
#define TICK_FONT_PX 13.0

/* The value of attribute `name` in the element that starts at el (up to its '>'). */
static int attr_value(const char *el, const char *name, double *v)
{
    char key[32];
    snprintf(key, sizeof key, " %s=\"", name);
    const char *end = strchr(el, '>');
    const char *p = strstr(el, key);
    if (!p || !end || p > end)
        return -1;
    *v = strtod(p + strlen(key), NULL);
    return 0;
}

size_t svgt_ticks(const char *svg, const char *cls, svg_tick *t, size_t max)
{
    char key[64];
    snprintf(key, sizeof key, "class=\"%s\"", cls);
    size_t n = 0;
    for (const char *p = strstr(svg, key); p && n < max; p = strstr(p + 1, key)) {
        const char *el = p;
        while (el > svg && strncmp(el, "<text ", 6))
            el--;
        svg_tick *k = &t[n];
        ENSURE_MSG(attr_value(el, "x", &k->x) == 0 && attr_value(el, "y", &k->y) == 0,
                   "a tick label without its position: %.80s", el);
        const char *open = strchr(p, '>'), *close = open ? strstr(open, "</text>") : NULL;
        ENSURE(open && close && (size_t)(close - open - 1) < sizeof k->text);
        memcpy(k->text, open + 1, (size_t)(close - open - 1));
        k->text[close - open - 1] = '\0';
        size_t chars = 0;
        for (const unsigned char *c = (const unsigned char *)k->text; *c; c++)
            chars += (*c & 0xc0) != 0x80;
        double w = (double)chars * TEST_EM_PER_CHAR * TICK_FONT_PX;
        if (!strcmp(cls, "ytick")) {
            k->lo = k->y - TICK_FONT_PX;
            k->hi = k->y;
        } else {
            k->lo = k->x - w / 2;
            k->hi = k->x + w / 2;
        }
        n++;
    }
    return n;
}

size_t svgt_x_ticks_apart(const char *svg, double gap, size_t least)
{
    svg_tick t[200];
    size_t n = svgt_ticks(svg, "xtick", t, 200);
    ENSURE_MSG(n >= least, "%zu x tick labels, fewer than %zu", n, least);
    for (size_t i = 1; i < n; i++)
        ENSURE_MSG(t[i].lo - t[i - 1].hi >= gap,
                   "x tick labels '%s' [%.1f, %.1f] and '%s' [%.1f, %.1f] are less than %g px "
                   "apart",
                   t[i - 1].text, t[i - 1].lo, t[i - 1].hi, t[i].text, t[i].lo, t[i].hi, gap);
    return n;
}
