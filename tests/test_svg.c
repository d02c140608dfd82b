/* test_svg.c - the report's SVG writer (svg.c): escaping of text and attribute values,
 * the fixed number formats of every element, the mapping of data to pixels, round tick
 * steps and their labels, stacked bars, and write errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "report/svg.h"
#include "svg_test_util.h"
#include "test.h"

/* What f holds from its start, NUL-terminated and malloc'd (the file is left open). */
static char *file_text(FILE *f)
{
    ENSURE(fflush(f) == 0);
    long n = ftell(f);
    ENSURE(n >= 0);
    char *s = malloc((size_t)n + 1);
    ENSURE(s != NULL);
    rewind(f);
    ENSURE(fread(s, 1, (size_t)n, f) == (size_t)n);
    s[n] = '\0';
    return s;
}

/* Opens an SVG in the case's directory with the frame used below: 400 x 300 px of plot
 * area at (100, 50) showing x in [0, 1], y in [0, 1]. */
static void open_plain(rf_svg *s, const char *name)
{
    rf_error err = {{0}};
    ENSURE_MSG(rf_svg_open(s, rf_test_path(name), 600, 400, "t", &err) == 0, "%s", err.message);
    rf_svg_frame(s, 100, 50, 500, 350, 0.0, 1.0, 0.0, 1.0);
}

/* The text written from the head on, after rf_svg_close. */
static char *close_and_read(rf_svg *s, const char *name)
{
    rf_error err = {{0}};
    ENSURE_MSG(rf_svg_close(s, &err) == 0, "%s", err.message);
    char *t = rf_test_read_text(rf_test_path(name));
    ENSURE(t != NULL);
    return t;
}

/* The five XML specials become entities (so the result is safe in text and in a quoted
 * attribute value alike), control characters other than tab and newline become '?',
 * everything else (UTF-8 included) passes as it is; NULL writes nothing. */
TEST(svg_escape_text_and_attribute_values)
{
    FILE *f = tmpfile();
    ENSURE(f != NULL);
    rf_svg_escape(f, "a<b>&\"c\"'d'\x01" "e\tf\ng \xc3\xa9 &amp;");
    rf_svg_escape(f, NULL);
    char *t = file_text(f);
    ENSURE_MSG(!strcmp(t, "a&lt;b&gt;&amp;&quot;c&quot;&#39;d&#39;?e\tf\ng \xc3\xa9 &amp;amp;"),
               "%s", t);
    free(t);
    fclose(f);
}

/* The document's head: integral width, height and viewBox, the title escaped both in
 * <title> and in the heading centred at the top (x to 0.1 px), one </svg> at the end. */
TEST(svg_document_head_title_escaped_and_closed)
{
    rf_svg s;
    rf_error err = {{0}};
    const char *name = "head.svg";
    ENSURE(rf_svg_open(&s, rf_test_path(name), 640.4, 480.6, "E < 5 & \"h\" > 'x'", &err) == 0);
    char *t = close_and_read(&s, name);
    static const char head[] = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" "
                               "height=\"481\" viewBox=\"0 0 640 481\" ";
    ENSURE_MSG(!strncmp(t, head, sizeof head - 1), "%.120s", t);
    ENSURE(strstr(t, "<title>E &lt; 5 &amp; &quot;h&quot; &gt; &#39;x&#39;</title>\n"));
    ENSURE(strstr(t, "<rect x=\"0\" y=\"0\" width=\"640\" height=\"481\" fill=\"white\"/>\n"));
    ENSURE(strstr(t, "<text x=\"320.2\" y=\"22.0\" text-anchor=\"middle\" font-size=\"16\" "
                     "font-weight=\"bold\">E &lt; 5 &amp; &quot;h&quot; &gt; &#39;x&#39;</text>\n"));
    size_t n = strlen(t);
    ENSURE(n > 7 && !strcmp(t + n - 7, "</svg>\n"));
    ENSURE(strstr(t, "</svg>") == t + n - 7);
    free(t);
}

/* Data to pixels: x from left to right, y up from bottom to top; an empty or reversed
 * range is widened to one unit. */
TEST(svg_frame_maps_data_to_pixels)
{
    rf_svg s;
    memset(&s, 0, sizeof s);
    rf_svg_frame(&s, 50, 20, 550, 420, 0.0, 100.0, -10.0, 10.0);
    ENSURE(rf_svg_px(&s, 0.0) == 50.0 && rf_svg_px(&s, 100.0) == 550.0);
    ENSURE(rf_svg_px(&s, 25.0) == 175.0);
    ENSURE(rf_svg_py(&s, -10.0) == 420.0 && rf_svg_py(&s, 10.0) == 20.0);
    ENSURE(rf_svg_py(&s, 0.0) == 220.0);
    rf_svg_frame(&s, 0, 0, 200, 100, 3.0, 3.0, 7.0, 2.0);
    ENSURE(s.x1 == 4.0 && s.y1 == 8.0);
    ENSURE(rf_svg_px(&s, 3.5) == 100.0 && rf_svg_py(&s, 7.25) == 75.0);
}

/* Elements in data coordinates with fixed formats: path and line points to 0.1 px,
 * rectangles to 0.01 px with their corners ordered, text positions to 0.1 px with the
 * formatted text escaped and the attributes written as given. */
TEST(svg_number_formats_of_paths_rects_lines_and_text)
{
    rf_svg s;
    const char *name = "fmt.svg";
    open_plain(&s, name);
    rf_svg_path_begin(&s, "stroke=\"red\"");
    rf_svg_path_move(&s, 0.123, 0.5);
    rf_svg_path_line(&s, 1.0, 1.0);
    rf_svg_path_line(&s, 0.33333, 0.0);
    rf_svg_path_end(&s);
    rf_svg_rect(&s, 0.5, 0.75, 0.25, 0.25, "fill=\"#abc\"");
    rf_svg_line(&s, 0.0, 0.0, 1.0, 0.5, "stroke=\"#333\"");
    rf_svg_text(&s, 12.345, 6.78, NULL, "%d < %s", 3, "a&b");
    rf_svg_text(&s, 1.0, 2.0, "class=\"k\"", "%.2f kJ", 2.385);
    rf_svg_raw(&s, "<g id=\"%s\"/>\n", "raw&kept");
    char *t = close_and_read(&s, name);
    ENSURE_MSG(strstr(t, "<path stroke=\"red\" d=\"M149.2 200.0L500.0 50.0L233.3 350.0\"/>\n"),
               "%s", t);
    ENSURE(strstr(t, "<rect x=\"200.00\" y=\"125.00\" width=\"100.00\" height=\"150.00\" "
                     "fill=\"#abc\"/>\n"));
    ENSURE(strstr(t, "<line x1=\"100.0\" y1=\"350.0\" x2=\"500.0\" y2=\"200.0\" stroke=\"#333\"/>\n"));
    ENSURE(strstr(t, "<text x=\"12.3\" y=\"6.8\">3 &lt; a&amp;b</text>\n"));
    /* 2.385 is 2.38499... in binary */
    ENSURE(strstr(t, "<text x=\"1.0\" y=\"2.0\" class=\"k\">2.38 kJ</text>\n"));
    ENSURE(strstr(t, "<g id=\"raw&kept\"/>\n"));
    free(t);
}

/* Tick steps are 1, 2 or 5 times a power of ten near range / target; a range that is
 * no number or not positive gets 1. */
TEST(svg_nice_step_is_one_two_or_five_times_a_power_of_ten)
{
    ENSURE_REL(rf_svg_nice_step(100.0, 5), 20.0, 1e-15);
    ENSURE_REL(rf_svg_nice_step(1.0, 10), 0.1, 1e-15);
    ENSURE_REL(rf_svg_nice_step(7.0, 1), 5.0, 1e-15);
    ENSURE_REL(rf_svg_nice_step(8.0, 1), 10.0, 1e-15);
    ENSURE_REL(rf_svg_nice_step(0.37, 4), 0.1, 1e-15);
    ENSURE_REL(rf_svg_nice_step(2385.0, 6), 500.0, 1e-15);
    ENSURE_REL(rf_svg_nice_step(2.4, 0), 2.0, 1e-15); /* target 0 taken as 1 */
    ENSURE(rf_svg_nice_step(0.0, 5) == 1.0);
    ENSURE(rf_svg_nice_step(-3.0, 5) == 1.0);
    ENSURE(rf_svg_nice_step(NAN, 5) == 1.0);
    ENSURE(rf_svg_nice_step(INFINITY, 5) == 1.0);
}

/* Tick labels show the step's decimals and no "-0.0" where the ticks, added up from
 * -0.3 in steps of 0.1, land a rounding error below zero; count axes tick whole
 * numbers only; the axis titles are escaped. */
TEST(svg_axes_labels_round_and_never_negative_zero)
{
    rf_svg s;
    const char *name = "axes.svg";
    open_plain(&s, name);
    rf_svg_frame(&s, 100, 50, 500, 350, -0.3, 0.3, 0.0, 3.0);
    s.y_counts = 1;
    rf_svg_axes(&s, "x <m>", "n & m");
    char *t = close_and_read(&s, name);
    static const char *const xs[] = {">-0.3<", ">-0.2<", ">-0.1<", ">0.0<", ">0.1<", ">0.2<", ">0.3<"};
    for (size_t k = 0; k < sizeof xs / sizeof *xs; k++)
        ENSURE_MSG(strstr(t, xs[k]), "no label %s", xs[k]);
    ENSURE(!strstr(t, "-0.0"));
    /* y: 0..3 in whole steps, no decimals */
    static const char *const ys[] = {"\">0</text>", "\">1</text>", "\">2</text>", "\">3</text>"};
    for (size_t k = 0; k < sizeof ys / sizeof *ys; k++)
        ENSURE_MSG(strstr(t, ys[k]), "no label %s", ys[k]);
    ENSURE(!strstr(t, ">0.5<") && !strstr(t, ">1.5<"));
    ENSURE(strstr(t, ">x &lt;m&gt;</text>"));
    ENSURE(strstr(t, "rotate(-90 48.0 200.0)\">n &amp; m</text>"));
    free(t);
}

/* The width of text as DejaVu Sans sets it: digits 1303/2048 em, '.' and ' ' 651/2048,
 * '-' 739/2048, the minus sign U+2212 1716/2048, any other character (one, whatever its
 * UTF-8 length) 0.7 em. */
TEST(svg_text_width_of_digits_signs_and_other_characters)
{
    ENSURE_REL(rf_svg_text_width("2600000", 13.0), 7.0 * 1303.0 / 2048.0 * 13.0, 1e-12);
    ENSURE_REL(rf_svg_text_width("-1.5", 10.0), (739.0 + 2 * 1303.0 + 651.0) / 2048.0 * 10.0,
               1e-12);
    ENSURE_REL(rf_svg_text_width("\xe2\x88\x92" "5", 13.0), (1716.0 + 1303.0) / 2048.0 * 13.0,
               1e-12);
    ENSURE_REL(rf_svg_text_width("\xc3\xa9x", 13.0), 2 * 0.7 * 13.0, 1e-12);
    ENSURE(rf_svg_text_width("", 13.0) == 0.0 && rf_svg_text_width(NULL, 13.0) == 0.0);
}

/* An axis is labelled from an origin only when its values are large against its span:
 * national coordinates (LV95, Lambert-93, UTM) get the round number at or below the
 * low end that is a multiple of the power of ten above the span; local coordinates,
 * energies from 0 and axes across 0 keep 0. */
TEST(svg_axis_origin_only_for_national_coordinates)
{
    ENSURE(rf_svg_axis_origin(2600000.0, 2600130.0) == 2600000.0);   /* LV95 easting */
    ENSURE(rf_svg_axis_origin(1200002.5, 1200082.5) == 1200000.0);   /* LV95 northing */
    ENSURE(rf_svg_axis_origin(2600950.0, 2601080.0) == 2600000.0);   /* across a thousand */
    ENSURE(rf_svg_axis_origin(6600123.0, 6600423.0) == 6600000.0);   /* Lambert-93 */
    ENSURE(rf_svg_axis_origin(700000.0, 750000.0) == 700000.0);      /* 50 km of UTM */
    ENSURE(rf_svg_axis_origin(-2600130.0, -2600000.0) == -2601000.0);
    ENSURE(rf_svg_axis_origin(2600000.0, 2600000.4) == 2600000.0);   /* a span below 1 m */
    ENSURE(rf_svg_axis_origin(0.0, 300.0) == 0.0);
    ENSURE(rf_svg_axis_origin(0.0, 32000.0) == 0.0);                 /* energies from 0 */
    ENSURE(rf_svg_axis_origin(5000.0, 5100.0) == 0.0);               /* short labels */
    ENSURE(rf_svg_axis_origin(10000.0, 20000.0) == 0.0);             /* span a tenth or more */
    ENSURE(rf_svg_axis_origin(-50000.0, 50000.0) == 0.0);            /* both signs */
    ENSURE(rf_svg_axis_origin(NAN, 3.0) == 0.0);
}

TEST(svg_format_grouped_sets_thousands_apart)
{
    char b[64];
    rf_svg_format_grouped(b, sizeof b, 2600000.0, 0);
    ENSURE_MSG(!strcmp(b, "2 600 000"), "%s", b);
    rf_svg_format_grouped(b, sizeof b, -1234.5, 1);
    ENSURE_MSG(!strcmp(b, "-1 234.5"), "%s", b);
    rf_svg_format_grouped(b, sizeof b, 999.0, 0);
    ENSURE_MSG(!strcmp(b, "999"), "%s", b);
    rf_svg_format_grouped(b, sizeof b, 123456.0, 0);
    ENSURE_MSG(!strcmp(b, "123 456"), "%s", b);
    rf_svg_format_grouped(b, 5, 2600000.0, 0); /* cut to the buffer, terminated */
    ENSURE_MSG(strlen(b) == 4, "%s", b);
}

/* On LV95 coordinates the ticks are labelled in metres from the stated origin: the
 * titles say "x - 2 600 000 (m)" (with a minus sign) and "y - 1 200 000 (m)", no label
 * repeats the millions, and each label sits where its coordinate is. */
TEST(svg_axes_on_national_coordinates_label_from_a_stated_origin)
{
    rf_svg s;
    const char *name = "lv95.svg";
    open_plain(&s, name);
    rf_svg_frame(&s, 100, 50, 500, 350, 2600000.0, 2600130.0, 1200000.0, 1200080.0);
    rf_svg_axes(&s, "x (m)", "y (m)");
    ENSURE(s.x_origin == 2600000.0 && s.y_origin == 1200000.0);
    double px20 = rf_svg_px(&s, 2600020.0), py40 = rf_svg_py(&s, 1200040.0);
    char *t = close_and_read(&s, name);
    ENSURE_MSG(strstr(t, ">x \xe2\x88\x92 2 600 000 (m)</text>"), "%s", t);
    ENSURE(strstr(t, ">y \xe2\x88\x92 1 200 000 (m)</text>"));
    svg_tick k[64];
    size_t nx = svgt_ticks(t, "xtick", k, 64);
    ENSURE_MSG(nx >= 4 && !strcmp(k[0].text, "0"), "%zu: %s", nx, nx ? k[0].text : "");
    int found = 0;
    for (size_t i = 0; i < nx; i++) {
        ENSURE_MSG(strlen(k[i].text) <= 3, "label %s", k[i].text);
        if (!strcmp(k[i].text, "20"))
            found = fabs(k[i].x - px20) < 0.06;
    }
    ENSURE_MSG(found, "no label 20 at %.1f px", px20);
    size_t ny = svgt_ticks(t, "ytick", k, 64);
    found = 0;
    for (size_t i = 0; i < ny; i++) {
        ENSURE_MSG(strlen(k[i].text) <= 3, "label %s", k[i].text);
        if (!strcmp(k[i].text, "40"))
            found = fabs(k[i].y - 4.0 - py40) < 0.06;
    }
    ENSURE_MSG(found, "no label 40 at %.1f px", py40);
    svgt_x_ticks_apart(t, 0.0, 4);
    ENSURE(!strstr(t, "2600"));
    free(t);
}

/* Whatever the plot's width and the values, no two x tick labels overlap (read back with
 * a width per character above DejaVu Sans's widest digit): the step widens until they
 * fit, down to a single label on a plot too narrow for two. */
TEST(svg_x_tick_labels_never_overlap)
{
    static const double widths[] = {110, 160, 220, 300, 450, 760};
    static const double ranges[][2] = {{0, 1e6}, {123456, 987654}, {0, 0.0037}, {-3.3, 2.1},
                                       {2600000, 2600130}, {700000, 712345.6}, {0, 32000},
                                       {-0.0071, -0.0012}, {1234567, 7654321}};
    for (size_t w = 0; w < sizeof widths / sizeof *widths; w++)
        for (size_t r = 0; r < sizeof ranges / sizeof *ranges; r++) {
            rf_svg s;
            const char *name = "ticks.svg";
            open_plain(&s, name);
            rf_svg_frame(&s, 100, 50, 100 + widths[w], 350, ranges[r][0], ranges[r][1], 0, 1);
            rf_svg_axes(&s, "x", "y");
            char *t = close_and_read(&s, name);
            /* two labels at least where two fit: 0.64 em a digit, 8 px apart */
            size_t n = svgt_x_ticks_apart(t, 0.0, 1);
            ENSURE_MSG(n >= 2 || widths[w] < 300, "%zu labels on %g px", n, widths[w]);
            free(t);
        }
}

/* Stacked bars: one rectangle per positive count, each series on top of the ones
 * before in its bin, in the series' fill. */
TEST(svg_stacked_bars_stack_positive_counts)
{
    rf_svg s;
    const char *name = "bars.svg";
    open_plain(&s, name);
    rf_svg_frame(&s, 100, 50, 500, 350, 0.0, 4.0, 0.0, 6.0);
    const double counts[2 * 2] = {2.0, 0.0, /* series 0: bins 0, 1 */
                                  1.0, 3.0}; /* series 1 */
    static const char *const fills[2] = {"#111", "#222"};
    rf_svg_stacked_bars(&s, counts, 2, 2, 0.0, 2.0, fills);
    char *t = close_and_read(&s, name);
    int nrect = 0;
    for (const char *p = t; (p = strstr(p, "<rect x=\"")) != NULL; p++)
        nrect++;
    ENSURE_MSG(nrect == 1 + 3, "%d rectangles", nrect); /* the background and three bars */
    /* bin 0: series 0 from 0 to 2, series 1 from 2 to 3; bin 1: series 1 from 0 to 3 */
    ENSURE(strstr(t, "<rect x=\"100.00\" y=\"250.00\" width=\"200.00\" height=\"100.00\" "
                     "fill=\"#111\""));
    ENSURE(strstr(t, "<rect x=\"100.00\" y=\"200.00\" width=\"200.00\" height=\"50.00\" "
                     "fill=\"#222\""));
    ENSURE(strstr(t, "<rect x=\"300.00\" y=\"200.00\" width=\"200.00\" height=\"150.00\" "
                     "fill=\"#222\""));
    free(t);
}

/* A file that cannot be created, and one whose writes fail (a full device), are errors
 * with the path in the message; closing twice is harmless. */
TEST(svg_open_and_close_report_write_errors)
{
    rf_svg s;
    rf_error err = {{0}};
    ENSURE(rf_svg_open(&s, rf_test_path("no/such/dir/x.svg"), 10, 10, "t", &err) != 0);
    ENSURE(strstr(err.message, "cannot write"));
    ENSURE(strstr(err.file, "no/such/dir/x.svg"));
    FILE *probe = fopen("/dev/full", "w");
    if (probe) { /* Linux: every write fails with ENOSPC */
        fclose(probe);
        memset(&err, 0, sizeof err);
        ENSURE(rf_svg_open(&s, "/dev/full", 10, 10, "t", &err) == 0);
        ENSURE(rf_svg_close(&s, &err) != 0);
        ENSURE(strstr(err.message, "cannot write") && !strcmp(err.file, "/dev/full"));
        ENSURE(rf_svg_close(&s, &err) == 0);
    }
}
