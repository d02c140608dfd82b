/* test_yamldoc.c - the YAML access layer (yamldoc.c): typed scalars and their ranges,
 * keys with "did you mean" hints, syntax errors, tags, and every error at the
 * file:line:column of the node at fault, nested in flow or block collections; the
 * nesting limit. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "input/yamldoc.h"
#include "test.h"

/* ---- the YAML access layer --------------------------------------------------------- */

static rf_ydoc load_text(const char *text)
{
    rf_ydoc d;
    rf_error err = {{0}};
    int rc = rf_ydoc_load_text(&d, "mem.yaml", text, strlen(text), &err);
    ENSURE_MSG(rc == 0, "%s", err.message);
    return d;
}

TEST(yamldoc_scalars)
{
    rf_ydoc d = load_text("a: 2.385\nb: 7\nc: 2.5\nd: \"7\"\ne: yes\nf: -1e3\ng: .inf\nh: 0x10\n"
                          "i:\n");
    rf_ynode *root = rf_ydoc_root(&d);
    rf_error err = {{0}};
    double x = 0;
    long long i = 0;
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "a"), "a", RF_YR_ANY, &x, &err) == 0);
    ENSURE(x == 2.385);
    ENSURE(rf_ydoc_integer(&d, rf_ydoc_get(&d, root, "b"), "b", RF_YR_ANY, &i, &err) == 0);
    ENSURE(i == 7);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "b"), "b", RF_YR_ANY, &x, &err) == 0);
    ENSURE(x == 7.0);
    ENSURE(rf_ydoc_integer(&d, rf_ydoc_get(&d, root, "c"), "c", RF_YR_AT_LEAST(1), &i,
                           &err) != 0);
    ENSURE(!strcmp(err.message, "'c' must be an integer >= 1, got 2.5"));
    ENSURE(err.line == 3 && err.column == 4 && !strcmp(err.file, "mem.yaml"));
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "d"), "d", RF_YR_ANY, &x, &err) != 0);
    ENSURE(strstr(err.message, "got \"7\""));
    int flag = 0;
    ENSURE(rf_ydoc_bool(&d, rf_ydoc_get(&d, root, "e"), "e", &flag, &err) == 0 && flag == 1);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "f"), "f", RF_YR_ANY, &x, &err) == 0);
    ENSURE(x == -1000.0);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "f"), "f", RF_YR_NONNEG, &x, &err) != 0);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "g"), "g", RF_YR_ANY, &x, &err) != 0);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "h"), "h", RF_YR_ANY, &x, &err) != 0);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "i"), "i", RF_YR_ANY, &x, &err) != 0);
    ENSURE(!strcmp(err.message, "'i' must be a number, got nothing"));
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, root, "a"), "a", RF_YR_UNIT, &x, &err) != 0);
    ENSURE(!strcmp(err.message, "'a' must be a number in [0, 1], got 2.385"));
    ENSURE(rf_ydoc_get(&d, root, "zz") == NULL);
    rf_ydoc_free(&d);
}

TEST(yamldoc_keys_and_hints)
{
    static const char *const allowed[] = {"restitution", "friction", "rolling", NULL};
    rf_ydoc d = load_text("friction: 1\nrestitusion: 2\n");
    rf_error err = {{0}};
    ENSURE(rf_ydoc_check_keys(&d, rf_ydoc_root(&d), allowed, "'surface'", &err) != 0);
    ENSURE(err.line == 2 && err.column == 1);
    ENSURE(!strcmp(err.message,
                   "unknown key 'restitusion' in 'surface' (did you mean 'restitution'?)"));
    rf_ydoc_free(&d);

    d = load_text("friction: 1\nfriction: 2\n");
    ENSURE(rf_ydoc_check_keys(&d, rf_ydoc_root(&d), allowed, "'surface'", &err) != 0);
    ENSURE(strstr(err.message, "duplicate key 'friction'") && err.line == 2);
    rf_ydoc_free(&d);

    ENSURE(rf_edit_distance("mass", "mass") == 0);
    ENSURE(rf_edit_distance("mas", "mass") == 1);
    ENSURE(rf_edit_distance("kitten", "sitting") == 3);
    char buf[64];
    ENSURE(!strcmp(rf_yrange_describe(RF_YR_BETWEEN(1, 3), 1, buf, sizeof buf),
                   "an integer in 1..3"));
    ENSURE(!strcmp(rf_yrange_describe(RF_YR_POSITIVE, 0, buf, sizeof buf), "a number > 0"));
}

TEST(yamldoc_syntax_errors)
{
    rf_ydoc d;
    rf_error err = {{0}};
    const char *text = "a: [1, 2\nb: 3\n";
    ENSURE(rf_ydoc_load_text(&d, "s.yaml", text, strlen(text), &err) != 0);
    ENSURE(strstr(err.message, "YAML syntax error") && err.line >= 1 && err.column >= 1);
    ENSURE(d.text == NULL && d.loaded == 0);
    text = "a: 1\n---\nb: 2\n";
    ENSURE(rf_ydoc_load_text(&d, "s.yaml", text, strlen(text), &err) != 0);
    ENSURE(err.line == 3 && err.column == 1 && strstr(err.message, "second YAML document"));
    text = "# nothing\n";
    ENSURE(rf_ydoc_load_text(&d, "s.yaml", text, strlen(text), &err) == 0);
    ENSURE(rf_ydoc_root(&d) == NULL);
    rf_ydoc_free(&d);
    text = "a: \xff\xfe\n";
    ENSURE(rf_ydoc_load_text(&d, "s.yaml", text, strlen(text), &err) != 0);
    ENSURE(err.line == 1 && strstr(err.message, "YAML syntax error"));
}

/* A scalar with an explicit tag other than a number's, a boolean's or null's is a
 * string, whatever the file's line breaks (LF, CR, U+2028 in a quoted string), a byte
 * order mark, anchors, comments between anchor and tag, or aliases: no number is read
 * from it; !!int and untagged numbers still are. */
TEST(project_tagged_scalars_are_strings)
{
    static const struct {
        const char *text;
        const char *key;
        int number; /* 1: read as a number (100), 0: refused */
    } cases[] = {
        {"a: !!str 100\n", "a", 0},
        {"a: !!int 100\n", "a", 1},
        {"a: !!float 100\n", "a", 1},
        {"a: !foo 100\n", "a", 0},
        {"a: ! 100\n", "a", 0},
        {"a: &x !!str 100\nb: *x\n", "b", 0},
        {"a: &x 100\nb: *x\n", "b", 1},
        {"s: \"x\xe2\x80\xa8y\"\nb: !!str 5\na: 100\n", "a", 1},
        {"s: \"x\xe2\x80\xa8y\"\na: !!str 100\n", "a", 0},
        {"s: x\rb: 5\ra: !!str 100\r", "a", 0},
        {"s: x\rb: !!str 5\ra: 100\r", "a", 1},
        {"\xef\xbb\xbf" "a: !!str 100\n", "a", 0},
        {"a: &x # comment\n  !!str 100\n", "a", 0},
        {"q: [&y , !!str 5]\na: 100\n", "a", 1},
        {"n: \xc3\xbc\xc3\xbc\na: {b: !!str 1, c: 2}\nc: 100\n", "c", 1},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        rf_ydoc d;
        rf_error err;
        ENSURE_MSG(rf_ydoc_load_text(&d, "t.yaml", cases[k].text, strlen(cases[k].text), &err) == 0,
                   "case %zu: %s", k, err.message);
        rf_ynode *n = rf_ydoc_get(&d, rf_ydoc_root(&d), cases[k].key);
        ENSURE_MSG(n != NULL, "case %zu: no '%s'", k, cases[k].key);
        double v = 0.0;
        int rc = rf_ydoc_number(&d, n, cases[k].key, RF_YR_POSITIVE, &v, &err);
        ENSURE_MSG((rc == 0) == cases[k].number, "case %zu: read %s", k, rc == 0 ? "a number" : "no number");
        if (cases[k].number)
            ENSURE(v == 100.0);
        rf_ydoc_free(&d);
    }
}

/* Every reader's error names the node at fault by file:line:column (1-based), however
 * deep it sits in flow and block collections; a missing key is reported at its mapping,
 * a wrong kind of node at that node, an error of the whole document at 1:1. */
TEST(yamldoc_errors_point_at_the_node_at_fault)
{
    const char *text = "rocks:\n  - {name: a, mass: -3}\nterrain:\n  surface:\n    restitution: abc\n";
    rf_ydoc d;
    rf_error err = {{0}};
    ENSURE(rf_ydoc_load_text(&d, "p.yaml", text, strlen(text), &err) == 0);
    rf_ynode *root = rf_ydoc_root(&d);
    rf_ynode *rocks = rf_ydoc_get(&d, root, "rocks");
    ENSURE(rocks != NULL && rf_ydoc_seq_size(rocks) == 1);
    rf_ynode *rock = rf_ydoc_seq_item(&d, rocks, 0);
    rf_mark m = rf_ydoc_mark(rock);
    ENSURE(m.line == 2 && m.column == 5); /* the '{' */
    double x = 0.0;
    /* the flow mapping's value: "  - {name: a, mass: -3}", column 21 */
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, rock, "mass"), "mass", RF_YR_POSITIVE, &x, &err) != 0);
    ENSURE_MSG(!strcmp(err.file, "p.yaml") && err.line == 2 && err.column == 21, "%s:%d:%d",
               err.file, err.line, err.column);
    ENSURE(!strcmp(err.message, "'mass' must be a number > 0, got -3"));
    /* three block levels down: "    restitution: abc", column 18 */
    rf_ynode *surface = rf_ydoc_get(&d, rf_ydoc_get(&d, root, "terrain"), "surface");
    ENSURE(surface != NULL);
    ENSURE(rf_ydoc_number(&d, rf_ydoc_get(&d, surface, "restitution"), "restitution", RF_YR_UNIT,
                          &x, &err) != 0);
    ENSURE(err.line == 5 && err.column == 18);
    ENSURE(!strcmp(err.message, "'restitution' must be a number in [0, 1], got abc"));
    /* a missing key: at the mapping it is missing from */
    rf_ynode *out = NULL;
    ENSURE(rf_ydoc_require(&d, surface, "friction", "'surface'", &out, &err) != 0);
    ENSURE(err.line == 5 && err.column == 5);
    ENSURE(!strcmp(err.message, "missing required key 'friction' in 'surface'"));
    /* too short a sequence, a sequence where a mapping belongs, a mapping where a string
     * does, a value not among the names: each at its node */
    ENSURE(rf_ydoc_sequence(&d, rocks, "rocks", 2, "rocks", &err) != 0);
    ENSURE(err.line == 2 && err.column == 3);
    ENSURE(!strcmp(err.message, "'rocks' must have at least 2 rocks, got 1"));
    ENSURE(rf_ydoc_mapping(&d, rocks, "'rocks'", &err) != 0);
    ENSURE(err.line == 2 && err.column == 3);
    ENSURE(!strcmp(err.message, "'rocks' must be a mapping (key: value pairs), got a sequence"));
    const char *str = NULL;
    ENSURE(rf_ydoc_string(&d, rf_ydoc_get(&d, root, "terrain"), "terrain", &str, &err) != 0);
    ENSURE(err.line == 4 && err.column == 3);
    ENSURE(!strcmp(err.message, "'terrain' must be a non-empty string, got a mapping"));
    static const char *const models[] = {"sphere", "point", NULL};
    int which = -1;
    ENSURE(rf_ydoc_enum(&d, rf_ydoc_get(&d, rock, "name"), "model", models, &which, &err) != 0);
    ENSURE(err.line == 2 && err.column == 12 && which == -1);
    ENSURE(!strcmp(err.message, "'model' must be one of sphere, point; got a"));
    ENSURE(rf_ydoc_error(&d, NULL, &err, "the whole file: %d", 7) == -1);
    ENSURE(err.line == 1 && err.column == 1 && !strcmp(err.message, "the whole file: 7"));
    rf_ydoc_free(&d);
}

/* A collection nested 64 levels deep loads; one level more is refused before the
 * document is built, at the bracket that opens the 65th level (1:65). */
TEST(yamldoc_nesting_limit_is_64_levels)
{
    char text[256];
    for (int depth = 64; depth <= 65; depth++) {
        int n = 0;
        for (int i = 0; i < depth; i++)
            text[n++] = '[';
        text[n++] = '1';
        for (int i = 0; i < depth; i++)
            text[n++] = ']';
        text[n++] = '\n';
        text[n] = '\0';
        rf_ydoc d;
        rf_error err = {{0}};
        int rc = rf_ydoc_load_text(&d, "deep.yaml", text, strlen(text), &err);
        if (depth == 64) {
            ENSURE_MSG(rc == 0, "%s", err.message);
            rf_ynode *n1 = rf_ydoc_root(&d);
            for (int i = 1; i < 64; i++) {
                ENSURE(n1 != NULL && rf_ydoc_seq_size(n1) == 1);
                n1 = rf_ydoc_seq_item(&d, n1, 0);
            }
            ENSURE(rf_ydoc_seq_size(n1) == 1);
            double one = 0.0;
            ENSURE(rf_ydoc_number(&d, rf_ydoc_seq_item(&d, n1, 0), "x", RF_YR_ANY, &one, &err) == 0);
            ENSURE(one == 1.0);
            rf_ydoc_free(&d);
        } else {
            ENSURE(rc != 0);
            ENSURE(!strcmp(err.file, "deep.yaml") && err.line == 1 && err.column == 65);
            ENSURE(!strcmp(err.message, "YAML nested deeper than 64 levels"));
            ENSURE(d.text == NULL && d.loaded == 0);
        }
    }
}

/* "got ..." in messages: a scalar's text, shortened to 40 characters and "..." when
 * long; "a mapping", "a sequence"; "nothing" for an empty value or no node. */
TEST(yamldoc_describe_names_what_was_found)
{
    const char *text = "a: abcdefghijklmnopqrstuvwxyz0123456789abcdefghijklmnopqrstuvwxyz\n"
                       "b:\nc: {x: 1}\nd: [1]\ne: 2.5\n";
    rf_ydoc d;
    rf_error err = {{0}};
    ENSURE(rf_ydoc_load_text(&d, "l.yaml", text, strlen(text), &err) == 0);
    rf_ynode *root = rf_ydoc_root(&d);
    char buf[128];
    ENSURE(!strcmp(rf_ydoc_describe(rf_ydoc_get(&d, root, "a"), buf, sizeof buf),
                   "abcdefghijklmnopqrstuvwxyz0123456789abcd..."));
    ENSURE(!strcmp(rf_ydoc_describe(rf_ydoc_get(&d, root, "b"), buf, sizeof buf), "nothing"));
    ENSURE(!strcmp(rf_ydoc_describe(rf_ydoc_get(&d, root, "c"), buf, sizeof buf), "a mapping"));
    ENSURE(!strcmp(rf_ydoc_describe(rf_ydoc_get(&d, root, "d"), buf, sizeof buf), "a sequence"));
    ENSURE(!strcmp(rf_ydoc_describe(rf_ydoc_get(&d, root, "e"), buf, sizeof buf), "2.5"));
    ENSURE(!strcmp(rf_ydoc_describe(NULL, buf, sizeof buf), "nothing"));
    ENSURE(rf_ydoc_map_size(root) == 5);
    rf_ydoc_free(&d);
}

/* ---- aliases expanded within a budget -------------------------------------------- */

/* "measures:" with `uses` items, each `line: *l` naming one line of `points` points. */
static char *aliased_lines(size_t points, size_t uses)
{
    size_t cap = 64 + points * 16 + uses * 48, used = 0;
    char *text = malloc(cap);
    ENSURE(text);
    used += (size_t)snprintf(text, cap, "line: &l [");
    for (size_t i = 0; i < points; i++)
        used += (size_t)snprintf(text + used, cap - used, "%s[%zu, 1]", i ? ", " : "", i);
    used += (size_t)snprintf(text + used, cap - used, "]\nmeasures:\n");
    for (size_t i = 0; i < uses; i++)
        used += (size_t)snprintf(text + used, cap - used, "  - {name: m%zu, line: *l}\n", i);
    return text;
}

/* One 30 000-point line aliased by 1 000 measures was read as 30 million points (71 s,
 * 510 MB): the expansion is refused at load, at the node that expands too far. */
TEST(yamldoc_alias_expansion_beyond_the_budget_refused)
{
    char *text = aliased_lines(30000, 1000);
    rf_ydoc d;
    rf_error err = {{0}};
    ENSURE(rf_ydoc_load_text(&d, "a.yaml", text, strlen(text), &err) != 0);
    ENSURE_MSG(strstr(err.message, "through its YAML aliases this expands to") &&
                   strstr(err.message, "at most 10 times as many"),
               "%s", err.message);
    ENSURE_MSG(err.line == 3 && err.column == 3, "%d:%d %s", err.line, err.column, err.message);
    ENSURE(d.text == NULL && d.loaded == 0);
    free(text);
    /* a few uses of a line, and of a small mapping by many items, are fine */
    text = aliased_lines(30000, 5);
    ENSURE_MSG(rf_ydoc_load_text(&d, "a.yaml", text, strlen(text), &err) == 0, "%s", err.message);
    rf_ydoc_free(&d);
    free(text);
    text = aliased_lines(2, 5000);
    ENSURE_MSG(rf_ydoc_load_text(&d, "a.yaml", text, strlen(text), &err) == 0, "%s", err.message);
    rf_ydoc_free(&d);
    free(text);
}

/* Aliases of aliases double at each level ("billion laughs"): refused at once. */
TEST(yamldoc_nested_aliases_refused)
{
    char text[4096];
    size_t used = (size_t)snprintf(text, sizeof text, "a0: &a0 [x, x]\n");
    for (int i = 1; i < 60; i++)
        used += (size_t)snprintf(text + used, sizeof text - used, "a%d: &a%d [*a%d, *a%d]\n", i, i,
                                 i - 1, i - 1);
    rf_ydoc d;
    rf_error err = {{0}};
    ENSURE(rf_ydoc_load_text(&d, "b.yaml", text, strlen(text), &err) != 0);
    ENSURE_MSG(strstr(err.message, "expands to"), "%s", err.message);
    /* an alias inside the node it names */
    const char *self = "a: &s [1, *s]\n";
    int rc = rf_ydoc_load_text(&d, "c.yaml", self, strlen(self), &err);
    if (rc == 0) /* libyaml refused to name the node from inside it: nothing to expand */
        rf_ydoc_free(&d);
    else
        ENSURE_MSG(strstr(err.message, "alias") && err.line == 1, "%s", err.message);
}

/* An unclosed '[' was reported at the end of the file, lines below it; libyaml's context
 * mark is where it opened. */
TEST(yamldoc_unclosed_bracket_reported_where_it_opens)
{
    rf_ydoc d;
    rf_error err = {{0}};
    const char *text = "name: x\nline: [[0, 1], [2, 3]\nb: 3\nc: 4\n\n\n";
    ENSURE(rf_ydoc_load_text(&d, "u.yaml", text, strlen(text), &err) != 0);
    ENSURE_MSG(err.line == 2 && err.column == 7, "%d:%d %s", err.line, err.column, err.message);
    ENSURE_MSG(strstr(err.message, "in the flow sequence that starts here") &&
                   strstr(err.message, "(at line 3, column 1)"),
               "%s", err.message);
    text = "a: {x: 1\n";
    ENSURE(rf_ydoc_load_text(&d, "u.yaml", text, strlen(text), &err) != 0);
    ENSURE(err.line == 1 && err.column == 4 && strstr(err.message, "flow mapping"));
    text = "a: \"open\nb: 2\n";
    ENSURE(rf_ydoc_load_text(&d, "u.yaml", text, strlen(text), &err) != 0);
    ENSURE(err.line == 1 && err.column == 4 && strstr(err.message, "quoted scalar"));
    /* other errors stay where libyaml finds them */
    text = "a: b: c\n";
    ENSURE(rf_ydoc_load_text(&d, "u.yaml", text, strlen(text), &err) != 0);
    ENSURE(err.line == 1 && err.column == 5);
}
