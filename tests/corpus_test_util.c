/* corpus_test_util.c - the bad-file corpora: files a loader must refuse, each naming
 * the error it must give. */
#include "corpus_test_util.h"

#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

/* Reads the file's expectation and hands it to check. */
static int check_file(const char *path, ct_check_fn check)
{
    char *text = rf_test_read_text(path);
    if (!text) {
        fprintf(stderr, "    %s: cannot read\n", path);
        return 0;
    }
    int line = 0, column = 0, used = 0;
    if (sscanf(text, "# expect: %d:%d %n", &line, &column, &used) != 2 || used == 0) {
        fprintf(stderr, "    %s: no '# expect: LINE:COLUMN SUBSTRING' first line\n", path);
        free(text);
        return 0;
    }
    char want[512];
    snprintf(want, sizeof want, "%.*s", (int)strcspn(text + used, "\n"), text + used);
    ct_expect e = {.path = path, .text = text, .line = line, .column = column, .want = want};
    int ok = check(&e);
    free(text);
    return ok;
}

int ct_error_as_expected(const ct_expect *e, const rf_error *err, int file_ok)
{
    if (file_ok && err->line == e->line && err->column == e->column &&
        strstr(err->message, e->want))
        return 1;
    fprintf(stderr, "    %s: expected %d:%d '%s', got: ", e->path, e->line, e->column, e->want);
    rf_error_print(err, stderr);
    return 0;
}

void ct_bad_corpus(const char *dir, const char *noun, size_t min, ct_check_fn check)
{
    char pattern[512];
    snprintf(pattern, sizeof pattern, "%s/*.yaml", dir);
    glob_t g;
    ENSURE_MSG(glob(pattern, 0, NULL, &g) == 0, "no file in %s", dir);
    ENSURE_MSG(g.gl_pathc >= min, "only %zu %s files", (size_t)g.gl_pathc, noun);
    int failed = 0;
    for (size_t i = 0; i < g.gl_pathc; i++)
        failed += !check_file(g.gl_pathv[i], check);
    ENSURE_MSG(failed == 0, "%d of %zu %s files gave the wrong error", failed,
               (size_t)g.gl_pathc, noun);
    globfree(&g);
}
