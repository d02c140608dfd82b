/* corpus_test_util.h - the bad-file corpora: files a loader must refuse, each naming
 * the error it must give. */
#ifndef ROCKFALL_CORPUS_TEST_UTIL_H
#define ROCKFALL_CORPUS_TEST_UTIL_H

#include <stddef.h>

#include "rockfall/error.h"

/* One file of a corpus and the error its first line, "# expect: LINE:COLUMN SUBSTRING",
 * asks for. */
typedef struct ct_expect {
    const char *path;
    const char *text; /* the whole file */
    int line, column;
    const char *want; /* the SUBSTRING */
} ct_expect;

/* Loads e->path with the loader under test; 1 when it gave the expected error (and left
 * nothing behind), else 0 after saying on stderr what went wrong. */
typedef int (*ct_check_fn)(const ct_expect *e);

/* 1 when err is at e's line and column with e's words in its message, and file_ok (the
 * error names the right file); else 0, printing what was expected and what came. */
int ct_error_as_expected(const ct_expect *e, const rf_error *err, int file_ok);

/* Checks every .yaml file in dir with check; ENSUREs there are at least min of them and that
 * every one gives its error (noun: what the files are, for the messages). */
void ct_bad_corpus(const char *dir, const char *noun, size_t min, ct_check_fn check);

#endif
