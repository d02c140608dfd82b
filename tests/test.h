/* test.h - the test harness: TEST(name) registers a case; ENSURE* check inside it.
 * Every case runs in its own process (a crash or hang fails that case only). */
#ifndef ROCKFALL_TEST_H
#define ROCKFALL_TEST_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

typedef void (*rf_test_fn)(void);
void rf_test_register(const char *name, rf_test_fn fn, const char *file);
/* Reports the failure and ends the case's process: it does not return. */
void rf_test_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4), noreturn));
/* Path of a file under ../shared (the shared folder beside the repository). */
const char *rf_test_shared(const char *rel);
/* The Authume quarry's mesh (../shared/validation/authume): the paths of its three STL
 * files, DTM_Blue_zone, DTM_Gray_zone and DTM_Red_zone in that order, into paths, and
 * files[i] pointing at paths[i]. */
void rf_test_authume_files(char paths[3][4096], char *files[3]);
/* Runs the rockfall binary ($ROCKFALL_BIN, else build/rockfall) with `args`; returns
 * its exit status, with its stdout and stderr together in out (NUL-terminated). */
int rf_test_rockfall(const char *args, char *out, size_t cap);
/* A fresh temporary directory for this case (removed by nobody: under /tmp). */
const char *rf_test_tmpdir(void);
/* The whole text of a file, NUL-terminated and malloc'd; NULL when it cannot be read. */
char *rf_test_read_text(const char *path);
/* The path of file `name` in the case's directory (valid for the next three calls). */
const char *rf_test_path(const char *name);
/* Writes text to file `name` of the case's directory (ENSUREs); returns rf_test_path. */
const char *rf_test_write(const char *name, const char *text);

#define TEST(name)                                                                     \
    static void name(void);                                                            \
    __attribute__((constructor)) static void rf_register_##name(void)                  \
    {                                                                                  \
        rf_test_register(#name, name, __FILE__);                                       \
    }                                                                                  \
    static void name(void)

/* A failed ENSURE ends the case (the case runs in a child process). */
#define ENSURE(cond)                                                                   \
    do {                                                                               \
        if (!(cond))                                                                   \
            rf_test_fail(__FILE__, __LINE__, "%s", #cond);                              \
    } while (0)
#define ENSURE_MSG(cond, ...)                                                          \
    do {                                                                               \
        if (!(cond))                                                                   \
            rf_test_fail(__FILE__, __LINE__, __VA_ARGS__);                             \
    } while (0)
/* |x| <= tol */
#define ENSURE_SMALL(x, tol)                                                           \
    do {                                                                               \
        double rf_x_ = (x), rf_t_ = (tol);                                             \
        if (!(fabs(rf_x_) <= rf_t_))                                                   \
            rf_test_fail(__FILE__, __LINE__, "|%s| = %.17g > %.3g", #x, rf_x_, rf_t_); \
    } while (0)
/* |a - b| <= tol * max(|b|, tiny) */
#define ENSURE_REL(a, b, tol)                                                          \
    do {                                                                               \
        double rf_a_ = (a), rf_b_ = (b), rf_t_ = (tol);                                \
        double rf_s_ = fabs(rf_b_) > 1e-300 ? fabs(rf_b_) : 1e-300;                    \
        if (!(fabs(rf_a_ - rf_b_) <= rf_t_ * rf_s_))                                   \
            rf_test_fail(__FILE__, __LINE__, "%s = %.17g, %s = %.17g, rel err %.3g > %.3g", \
                         #a, rf_a_, #b, rf_b_, fabs(rf_a_ - rf_b_) / rf_s_, rf_t_);     \
    } while (0)

#endif
