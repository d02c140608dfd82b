/* test_measures.c - crossings of measure polylines and what measures do to rocks. */
#include <math.h>
#include <string.h>

#include "check/rules.h"
#include "input/measure_kinds.h"
#include "scene/measures.h"
#include "test.h"

static rf_measure line_measure(double *xy, size_t n)
{
    rf_measure m;
    memset(&m, 0, sizeof m);
    m.kind = RF_CONTROL;
    m.behaviour = RF_COLLECT;
    m.line.xy = xy;
    m.line.n = n;
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        m.capacity[s] = -1.0;
    return m;
}

/* A straight horizontal path across one segment: time and fraction exact. */
TEST(measures_straight_crossing)
{
    double xy[] = {10.0, -5.0, 10.0, 15.0};
    rf_measure m = line_measure(xy, 2);
    rf_crossing c;
    rf_vec3 p = rf_v3(2.385, 1.25, 40.0), v = rf_v3(3.7, 0.0, -1.0), a = rf_v3(0, 0, -9.81);
    ENSURE(rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 10.0, &c));
    ENSURE_REL(c.t, (10.0 - 2.385) / 3.7, 1e-14);
    ENSURE_REL(c.u, (1.25 + 5.0) / 20.0, 1e-14);
    ENSURE(c.measure == 0 && c.segment == 0);
    /* too short a piece: no crossing */
    ENSURE(!rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 2.0, &c));
    /* moving away: none */
    ENSURE(!rf_measures_first_crossing(&m, 1, p, rf_v3(-3.7, 0, 0), a, RF_CROSSING_EPS, 10.0, &c));
}

/* A curved horizontal path (rolling with a sideways acceleration) crosses a line at
 * the root of the quadratic. */
TEST(measures_quadratic_path_crossing)
{
    double xy[] = {-50.0, 7.5, 50.0, 7.5};
    rf_measure m = line_measure(xy, 2);
    rf_crossing c;
    rf_vec3 p = rf_v3(0.3, 0.0, 0.0), v = rf_v3(1.2, 0.5, 0.0), a = rf_v3(0.0, 2.385, 0.0);
    ENSURE(rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 100.0, &c));
    double t = (-0.5 + sqrt(0.25 + 2.0 * 2.385 * 7.5)) / 2.385;
    ENSURE_REL(c.t, t, 1e-13);
    /* a path that turns back before the line (apex y = 4.5) never crosses it */
    ENSURE(!rf_measures_first_crossing(&m, 1, p, rf_v3(0, 3.0, 0), rf_v3(0, -1.0, 0),
                                       RF_CROSSING_EPS, 100.0, &c));
}

/* A path tangent to the line (touching without crossing) is no crossing. */
TEST(measures_touch_is_no_crossing)
{
    double xy[] = {-50.0, 2.0, 50.0, 2.0};
    rf_measure m = line_measure(xy, 2);
    rf_crossing c;
    /* y(t) = 4 t - t^2 has its apex y = 4 at t = 2; the line y = 4 is touched */
    double xy4[] = {-50.0, 4.0, 50.0, 4.0};
    rf_measure m4 = line_measure(xy4, 2);
    rf_vec3 p = rf_v3(0, 0, 0), v = rf_v3(1, 4, 0), a = rf_v3(0, -2, 0);
    ENSURE(!rf_measures_first_crossing(&m4, 1, p, v, a, RF_CROSSING_EPS, 10.0, &c));
    /* the line y = 2 is crossed twice: first at 2 - sqrt(2) */
    ENSURE(rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 10.0, &c));
    ENSURE_REL(c.t, 2.0 - sqrt(2.0), 1e-14);
    ENSURE(rf_measures_first_crossing(&m, 1, p, v, a, c.t + RF_CROSSING_EPS, 10.0, &c));
    ENSURE_REL(c.t, 2.0 + sqrt(2.0), 1e-14);
}

/* Through a polyline vertex: found once, whichever way the search continues. */
TEST(measures_vertex_crossing_counted_once)
{
    double xy[] = {0.0, 0.0, 10.0, 10.0, 20.0, 0.0};
    rf_measure m = line_measure(xy, 3);
    rf_vec3 p = rf_v3(10.0, 20.0, 0.0), v = rf_v3(0.0, -7.3, 0.0), a = rf_v3(0, 0, -9.81);
    int count = 0;
    double t_after = RF_CROSSING_EPS;
    rf_crossing c;
    while (rf_measures_first_crossing(&m, 1, p, v, a, t_after, 10.0, &c)) {
        count++;
        ENSURE_REL(c.t, 10.0 / 7.3, 1e-14);
        t_after = c.t + RF_CROSSING_EPS;
    }
    ENSURE(count == 1);
    /* a piece that starts exactly at the vertex does not count it again */
    rf_vec3 q = rf_v3(10.0, 10.0, 0.0);
    ENSURE(!rf_measures_first_crossing(&m, 1, q, v, a, RF_CROSSING_EPS, 10.0, &c));
}

/* A path through a polyline's apex with both arms on one side of it touches the line
 * without crossing it; through the apex between the arms it crosses, once. */
TEST(measures_apex_touch_is_no_crossing)
{
    double xy[] = {0.0, 0.0, 10.0, 10.0, 20.0, 0.0};
    rf_measure m = line_measure(xy, 3);
    rf_crossing c;
    rf_vec3 g = rf_v3(0, 0, -9.81);
    /* level through the apex, both ways: both arms below */
    ENSURE(!rf_measures_first_crossing(&m, 1, rf_v3(0, 10, 0), rf_v3(3.1, 0, 0), g,
                                       RF_CROSSING_EPS, 10.0, &c));
    ENSURE(!rf_measures_first_crossing(&m, 1, rf_v3(20, 10, 0), rf_v3(-3.1, 0, 0), g,
                                       RF_CROSSING_EPS, 10.0, &c));
    /* a curved path whose tangent at the apex is level: y = 10 + (x - 10)^2 / 8 */
    rf_vec3 p = rf_v3(6.0, 12.0, 0), v = rf_v3(1.0, -1.0, 0), a = rf_v3(0, 0.25, 0);
    ENSURE(!rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 8.0, &c));
    /* steeper than the arm (slope 2 against 1): between the arms, a crossing */
    ENSURE(rf_measures_first_crossing(&m, 1, rf_v3(5, 20, 0), rf_v3(0.5, -1, 0), g,
                                      RF_CROSSING_EPS, 20.0, &c));
    ENSURE_REL(c.t, 10.0, 1e-14);
    ENSURE(!rf_measures_first_crossing(&m, 1, rf_v3(5, 20, 0), rf_v3(0.5, -1, 0), g,
                                       c.t + RF_CROSSING_EPS, 20.0, &c));
    /* the apex written twice: still a touch */
    double xy2[] = {0.0, 0.0, 10.0, 10.0, 10.0, 10.0, 20.0, 0.0};
    rf_measure m2 = line_measure(xy2, 4);
    ENSURE(!rf_measures_first_crossing(&m2, 1, rf_v3(0, 10, 0), rf_v3(3.1, 0, 0), g,
                                       RF_CROSSING_EPS, 10.0, &c));
    ENSURE(rf_measures_first_crossing(&m2, 1, rf_v3(5, 20, 0), rf_v3(0.5, -1, 0), g,
                                      RF_CROSSING_EPS, 20.0, &c));
    /* a polyline's end vertex is crossed when passed through */
    ENSURE(rf_measures_first_crossing(&m, 1, rf_v3(-5, 5, 0), rf_v3(1, -1, 0), g,
                                      RF_CROSSING_EPS, 10.0, &c));
    ENSURE_REL(c.t, 5.0, 1e-14);
}

/* A polyline with a 0.1 m kink crossed at 60 m/s: every crossing is found, in order. */
TEST(measures_kink_at_60ms)
{
    double xy[] = {0.0, 0.0, 30.0, 0.0, 30.05, 0.1, 30.1, 0.0, 60.0, 0.0};
    rf_measure m = line_measure(xy, 5);
    /* a path along x = 30.05 - crosses the kink's apex region once through (30.05, y) */
    rf_vec3 p = rf_v3(30.05, 5.0, 0.0), v = rf_v3(0.0, -60.0, 0.0), a = rf_v3(0, 0, 0);
    rf_crossing c;
    ENSURE(rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 1.0, &c));
    ENSURE_REL(c.t, (5.0 - 0.1) / 60.0, 1e-13); /* the kink's apex (30.05, 0.1) */
    int count = 1;
    while (rf_measures_first_crossing(&m, 1, p, v, a, c.t + RF_CROSSING_EPS, 1.0, &c))
        count++;
    ENSURE_MSG(count == 1, "count %d", count);
    /* a path at x = 30.02 crosses the kink's first leg only */
    p.x = 30.02;
    ENSURE(rf_measures_first_crossing(&m, 1, p, v, a, RF_CROSSING_EPS, 1.0, &c));
    ENSURE(c.segment == 1);
    ENSURE_REL(c.t, (5.0 - 0.04) / 60.0, 1e-12);
    /* a diagonal fast path crosses the zig-zag three times */
    p = rf_v3(29.9, 0.12, 0.0);
    v = rf_v3(60.0, -60.0 * 0.14 / 0.3, 0.0);
    count = 0;
    double t_after = RF_CROSSING_EPS;
    while (rf_measures_first_crossing(&m, 1, p, v, a, t_after, 1.0, &c)) {
        count++;
        t_after = c.t + RF_CROSSING_EPS;
    }
    ENSURE_MSG(count == 3, "count %d", count);
}

/* The earliest crossing over several measures wins. */
TEST(measures_earliest_of_several)
{
    double a1[] = {20.0, -10.0, 20.0, 10.0}, a2[] = {12.0, -10.0, 12.0, 10.0};
    rf_measure ms[2] = {line_measure(a1, 2), line_measure(a2, 2)};
    rf_crossing c;
    ENSURE(rf_measures_first_crossing(ms, 2, rf_v3(0, 0, 0), rf_v3(4.0, 0, 0), rf_v3(0, 0, 0),
                                      RF_CROSSING_EPS, 100.0, &c));
    ENSURE(c.measure == 1);
    ENSURE_REL(c.t, 3.0, 1e-15);
}

TEST(measures_outcomes)
{
    double xy[] = {0, 0, 1, 0};
    rf_measure b = line_measure(xy, 2);
    b.kind = RF_BARRIER;
    b.behaviour = RF_STOP;
    b.height = 5.0;
    b.mel = 3000.0;
    b.sel = 1000.0;
    b.capacity[RF_SERVICEABILITY] = 1000.0;
    b.capacity[RF_ULTIMATE] = 3000.0;
    ENSURE(rf_measure_breaking_energy(&b) == 3000.0);
    ENSURE(rf_measure_outcome(&b, 2.385, 2999.0) == RF_OUT_STOPPED);
    ENSURE(rf_measure_outcome(&b, 2.385, 3000.0) == RF_OUT_STOPPED);
    ENSURE(rf_measure_outcome(&b, 2.385, 3000.5) == RF_OUT_BROKE_THROUGH);
    ENSURE(rf_measure_outcome(&b, 5.0, 10.0) == RF_OUT_OVERTOPPED);
    ENSURE(rf_measure_outcome(&b, 7.5, 1e6) == RF_OUT_OVERTOPPED);
    /* no ground under the crossing (a hole, a crack between terrain files): not known
     * to pass below the screen, never stopped there */
    ENSURE(rf_measure_outcome(&b, NAN, 10.0) == RF_OUT_OVERTOPPED);
    b.behaviour = RF_COLLECT;
    ENSURE(rf_measure_outcome(&b, NAN, 10.0) == RF_OUT_OVERTOPPED);
    ENSURE(rf_measure_outcome(&b, 2.385, 1e6) == RF_OUT_PASSED);
    /* an evaluation line still records a rock passing above the screen's height */
    ENSURE(rf_measure_outcome(&b, 5.0, 10.0) == RF_OUT_OVERTOPPED);
    ENSURE(isinf(rf_measure_breaking_energy(&b)));
    rf_measure e = b;
    e.kind = RF_EMBANKMENT;
    e.behaviour = RF_STOP;
    for (int s = 0; s < RF_N_LIMIT_STATES; s++)
        e.capacity[s] = 2000.0 * (s + 1);
    ENSURE(rf_measure_breaking_energy(&e) == 8000.0);
    ENSURE(rf_measure_outcome(&e, 1.0, 7999.0) == RF_OUT_STOPPED);
    ENSURE(rf_measure_outcome(&e, 1.0, 8001.0) == RF_OUT_BROKE_THROUGH);
    rf_measure c = line_measure(xy, 2);
    ENSURE(rf_measure_outcome(&c, 0.5, 1e9) == RF_OUT_PASSED);
}

/* Measures drawn on the same line are crossed together, each once, in their order. */
TEST(measures_coincident_lines_all_crossed)
{
    double a1[] = {20.0, -10.0, 20.0, 10.0}, a2[] = {20.0, 10.0, 20.0, -10.0},
           a3[] = {25.0, -10.0, 25.0, 10.0};
    rf_measure ms[3] = {line_measure(a3, 2), line_measure(a1, 2), line_measure(a2, 2)};
    rf_crossing c[RF_MAX_COINCIDENT_CROSSINGS];
    int k = rf_measures_first_crossings(ms, 3, rf_v3(0, 1.5, 0), rf_v3(4.0, 0, 0), rf_v3(0, 0, 0),
                                        RF_CROSSING_EPS, 100.0, c, RF_MAX_COINCIDENT_CROSSINGS);
    ENSURE(k == 2);
    ENSURE(c[0].measure == 1 && c[1].measure == 2);
    ENSURE_REL(c[0].t, 5.0, 1e-15);
    ENSURE_REL(c[1].t, 5.0, 1e-15);
    ENSURE_REL(c[0].u, 11.5 / 20.0, 1e-14);
    ENSURE_REL(c[1].u, 8.5 / 20.0, 1e-14);
    /* after them, the next one */
    k = rf_measures_first_crossings(ms, 3, rf_v3(0, 1.5, 0), rf_v3(4.0, 0, 0), rf_v3(0, 0, 0),
                                    5.0 + RF_CROSSING_EPS, 100.0, c, RF_MAX_COINCIDENT_CROSSINGS);
    ENSURE(k == 1 && c[0].measure == 0);
    ENSURE_REL(c[0].t, 6.25, 1e-15);
}

/* ---- the kind table ------------------------------------------------------------------ */

/* Every kind is one complete row: a unique name found by its name, a label and colour,
 * its reader and outcome; rf_measure_outcome is the row's outcome. */
TEST(measure_kinds_table_rows_are_complete)
{
    for (int k = 0; k < RF_N_MEASURE_KINDS; k++) {
        const rf_measure_kind_class *c = &rf_measure_kinds[k];
        ENSURE_MSG(c->name && c->label && c->colour && c->states && c->keys && c->read &&
                       c->outcome,
                   "kind %d", k);
        ENSURE(rf_measure_kind_find(c->name) == k);
        ENSURE(!strcmp(rf_measure_kind_name((rf_measure_kind)k), c->name));
        ENSURE(c->states[0] == '[');
        for (const char *const *key = c->keys; *key; key++) {
            int listed = 0;
            for (const char *const *all = rf_measure_item_keys; *all; all++)
                listed |= !strcmp(*all, *key);
            ENSURE_MSG(listed, "%s's key %s is no measure item key", c->name, *key);
        }
        rf_measure m = {.kind = (rf_measure_kind)k, .height = 5.0, .behaviour = RF_STOP,
                        .capacity = {1000, -1, 3000, -1}};
        for (double h = 0.5; h < 10.0; h += 3.0)
            for (double e = 10.0; e < 1e4; e *= 7.0)
                ENSURE(rf_measure_outcome(&m, h, e) == c->outcome(&m, h, e));
    }
    ENSURE(rf_measure_kind_find("wall") == -1 && rf_measure_kind_find(NULL) == -1);
    /* only a kind that is no protected line is classified by Table 3 */
    ENSURE(rf_measure_kinds[RF_CONTROL].reach_line && !rf_measure_kinds[RF_CONTROL].classified);
    ENSURE(rf_measure_kinds[RF_BARRIER].has_mel && !rf_measure_kinds[RF_EMBANKMENT].has_mel);
}

/* The rule file gives capacities to exactly the kinds the table says Table 3
 * classifies: a rule file without one of them is refused. */
TEST(measure_kinds_rule_file_covers_the_classified_kinds)
{
    rf_rules r;
    rf_error err = {{0}};
    ENSURE_MSG(rf_rules_load("rules/table3.yaml", &r, &err) == 0, "%s", err.message);
    for (int k = 0; k < RF_N_MEASURE_KINDS; k++) {
        int any = 0;
        for (int s = 0; s < RF_N_LIMIT_STATES; s++)
            any |= r.capacity[k][s] != RF_CAP_NONE;
        ENSURE_MSG(any == rf_measure_kinds[k].classified, "%s", rf_measure_kinds[k].name);
    }
    rf_rules_free(&r);
}
