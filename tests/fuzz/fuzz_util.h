/* fuzz_util.h - what the libFuzzer targets share: a private scratch folder under
 * /dev/shm (removed at exit) holding copies of the test terrains that project files
 * name.
 *
 * Each target defines LLVMFuzzerTestOneInput; `make fuzz` builds them with clang
 * -fsanitize=fuzzer,address,undefined (tests/fuzz/README.md). */
#ifndef ROCKFALL_FUZZ_UTIL_H
#define ROCKFALL_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef RF_FUZZ_DATA
#define RF_FUZZ_DATA "tests/data/project" /* the test terrains (the Makefile sets it) */
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

static char fuzz_dir[256];

static inline void fuzz_rm(void)
{
    if (fuzz_dir[0]) {
        char cmd[400];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", fuzz_dir);
        if (system(cmd) != 0)
            fprintf(stderr, "fuzz: could not remove %s\n", fuzz_dir);
    }
}

/* The scratch folder, made on first use. */
static inline const char *fuzz_scratch(void)
{
    const char *given = getenv("RF_FUZZ_DIR"); /* tools/fuzz.sh's, removed by it */
    if (!fuzz_dir[0] && given && strlen(given) < sizeof fuzz_dir) {
        snprintf(fuzz_dir, sizeof fuzz_dir, "%s", given);
        return fuzz_dir;
    }
    if (!fuzz_dir[0]) {
        snprintf(fuzz_dir, sizeof fuzz_dir, "/dev/shm/rf_fuzz.XXXXXX");
        if (!mkdtemp(fuzz_dir)) {
            snprintf(fuzz_dir, sizeof fuzz_dir, "/tmp/rf_fuzz.XXXXXX");
            if (!mkdtemp(fuzz_dir)) {
                perror("fuzz: mkdtemp");
                abort();
            }
        }
        atexit(fuzz_rm);
    }
    return fuzz_dir;
}

/* Copies a file of RF_FUZZ_DATA into the scratch folder as `to`. */
static inline void fuzz_copy_data(const char *name, const char *to)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "mkdir -p \"$(dirname '%s/%s')\" && cp '%s/%s' '%s/%s'",
             fuzz_scratch(), to, RF_FUZZ_DATA, name, fuzz_scratch(), to);
    if (system(cmd) != 0) {
        fprintf(stderr, "fuzz: cannot copy %s\n", name);
        abort();
    }
}

#endif
