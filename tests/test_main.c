/* test_main.c - runs every registered case in its own process and counts.
 * Usage: run_tests [SUBSTRING...]  (only cases whose name contains one of them). */
#define _POSIX_C_SOURCE 200809L
#include "test.h"

#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#define MAX_TESTS 2048
#define CASE_TIMEOUT_S 600

typedef struct {
    const char *name, *file;
    rf_test_fn fn;
} test_case;

static test_case g_tests[MAX_TESTS];
static int g_ntests;

void rf_test_register(const char *name, rf_test_fn fn, const char *file)
{
    if (g_ntests < MAX_TESTS)
        g_tests[g_ntests++] = (test_case){name, file, fn};
}

void rf_test_fail(const char *file, int line, const char *fmt, ...)
{
    fflush(stdout); /* what the case printed before it failed */
    fprintf(stderr, "    %s:%d: ", file, line);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    fflush(stderr);
    _exit(1);
}

const char *rf_test_shared(const char *rel)
{
    static char buf[4096];
    const char *root = getenv("ROCKFALL_SHARED");
    snprintf(buf, sizeof buf, "%s/%s", root ? root : "../shared", rel);
    return buf;
}

void rf_test_authume_files(char paths[3][4096], char *files[3])
{
    static const char *names[3] = {"Blue", "Gray", "Red"};
    for (int i = 0; i < 3; i++) {
        char rel[256];
        snprintf(rel, sizeof rel, "validation/authume/Geometries/STL/DTM_%s_zone.stl", names[i]);
        snprintf(paths[i], 4096, "%s", rf_test_shared(rel));
        files[i] = paths[i];
    }
}

int rf_test_rockfall(const char *args, char *out, size_t cap)
{
    const char *bin = getenv("ROCKFALL_BIN");
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "%s %s 2>&1", bin ? bin : "build/rockfall", args);
    FILE *f = popen(cmd, "r");
    ENSURE(f != NULL);
    size_t n = fread(out, 1, cap - 1, f);
    out[n] = 0;
    int st = pclose(f);
    ENSURE_MSG(WIFEXITED(st), "'%s' did not exit normally", cmd);
    return WEXITSTATUS(st);
}

const char *rf_test_tmpdir(void)
{
    static char dir[256];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/rockfall-test-XXXXXX");
        if (!mkdtemp(dir)) {
            perror("mkdtemp");
            _exit(1);
        }
    }
    return dir;
}

char *rf_test_read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (s) {
        size_t got = fread(s, 1, (size_t)n, f);
        s[got] = '\0';
    }
    fclose(f);
    return s;
}

const char *rf_test_path(const char *name)
{
    static char buf[4][600];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", rf_test_tmpdir(), name);
    return buf[k];
}

const char *rf_test_write(const char *name, const char *text)
{
    const char *path = rf_test_path(name);
    FILE *f = fopen(path, "w");
    ENSURE_MSG(f != NULL, "cannot write %s", path);
    ENSURE(fputs(text, f) >= 0);
    ENSURE(fclose(f) == 0);
    return path;
}

static int selected(const char *name, int argc, char **argv)
{
    if (argc < 2)
        return 1;
    for (int i = 1; i < argc; i++)
        if (strstr(name, argv[i]))
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    int passed = 0, failed = 0;
    for (int i = 0; i < g_ntests; i++) {
        test_case *tc = &g_tests[i];
        if (!selected(tc->name, argc, argv))
            continue;
        fflush(stdout);
        pid_t pid = fork();
        if (pid < 0) {
            perror("fork");
            return 2;
        }
        if (pid == 0) {
            alarm(CASE_TIMEOUT_S);
            tc->fn();
            fflush(stdout);
            _exit(0);
        }
        int status = 0;
        while (waitpid(pid, &status, 0) < 0)
            ;
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
            printf("ok   %s\n", tc->name);
            passed++;
        } else {
            if (WIFSIGNALED(status))
                printf("FAIL %s (%s, signal %d)\n", tc->name, tc->file, WTERMSIG(status));
            else
                printf("FAIL %s (%s)\n", tc->name, tc->file);
            failed++;
        }
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
