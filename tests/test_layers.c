/* test_layers.c - the house rules of src/ (tools/layers.sh, docs/architecture.md): a
 * file includes and calls only its own layer and those below, the engine's files depend
 * on each other without a cycle, no file is over 1000 lines and no function over 120. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "test.h"

/* Runs a shell command; its exit status, with stdout and stderr in out. */
static int run_sh(const char *cmd, char *out, size_t cap)
{
    char full[8192];
    snprintf(full, sizeof full, "(%s) 2>&1", cmd);
    FILE *p = popen(full, "r");
    ENSURE(p != NULL);
    size_t n = fread(out, 1, cap - 1, p);
    out[n] = '\0';
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The build folder of the binary under test ($ROCKFALL_BIN's folder, else build). */
static const char *build_dir(void)
{
    static char dir[2048];
    const char *bin = getenv("ROCKFALL_BIN");
    snprintf(dir, sizeof dir, "%s", bin ? bin : "build/rockfall");
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(dir, sizeof dir, ".");
    return dir;
}

/* A copy of src/ and include/ in the case's directory, to plant a violation in. */
static const char *copy_tree(void)
{
    const char *dir = rf_test_tmpdir();
    char cmd[4096], out[4096];
    snprintf(cmd, sizeof cmd, "cp -r src include %s/", dir);
    ENSURE_MSG(run_sh(cmd, out, sizeof out) == 0, "%s", out);
    return dir;
}

static int check_tree(const char *root, char *out, size_t cap)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "sh tools/layers.sh %s", root);
    return run_sh(cmd, out, cap);
}

TEST(layers_hold_on_the_sources_and_objects)
{
    static char out[1 << 16];
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "sh tools/layers.sh . %s", build_dir());
    int rc = run_sh(cmd, out, sizeof out);
    ENSURE_MSG(rc == 0 && out[0] == '\0', "tools/layers.sh exit %d:\n%s", rc, out);
}

TEST(layers_refuse_an_upward_include)
{
    static char out[1 << 16];
    const char *root = copy_tree();
    ENSURE(check_tree(root, out, sizeof out) == 0);
    char cmd[4096];
    /* base may not include the report layer */
    snprintf(cmd, sizeof cmd, "printf '#include \"report/report.h\"\\n' >> %s/src/base/util.c", root);
    ENSURE(run_sh(cmd, out, sizeof out) == 0);
    ENSURE(check_tree(root, out, sizeof out) == 1);
    ENSURE_MSG(strstr(out, "src/base/util.c:") && strstr(out, "\"report/report.h\" of layer 'report'"),
               "%s", out);
}

TEST(layers_refuse_a_public_header_above_its_layer)
{
    static char out[1 << 16];
    const char *root = copy_tree();
    char cmd[4096];
    /* project.h is of the input layer; sim.h of the engine */
    snprintf(cmd, sizeof cmd, "printf '#include \"rockfall/sim.h\"\\n' >> %s/include/rockfall/project.h",
             root);
    ENSURE(run_sh(cmd, out, sizeof out) == 0);
    ENSURE(check_tree(root, out, sizeof out) == 1);
    ENSURE_MSG(strstr(out, "include/rockfall/project.h:") && strstr(out, "layer 'engine'"), "%s", out);
    /* a public header the table does not place */
    snprintf(cmd, sizeof cmd, "cp %s/include/rockfall/units.h %s/include/rockfall/stray.h", root, root);
    ENSURE(run_sh(cmd, out, sizeof out) == 0);
    ENSURE(check_tree(root, out, sizeof out) == 1);
    ENSURE_MSG(strstr(out, "include/rockfall/stray.h:1: public header without a layer"), "%s", out);
}

TEST(layers_refuse_an_include_cycle_in_the_engine)
{
    static char out[1 << 16];
    const char *root = copy_tree();
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "cd %s/src/engine && printf '#include \"engine/zz_b.h\"\\n' > zz_a.c && "
             "printf 'int zz;\\n' > zz_a.h && printf '#include \"engine/zz_a.h\"\\n' > zz_b.c && "
             "printf 'int zz;\\n' > zz_b.h",
             root);
    ENSURE(run_sh(cmd, out, sizeof out) == 0);
    ENSURE(check_tree(root, out, sizeof out) == 1);
    ENSURE_MSG(strstr(out, "include each other in a cycle") && strstr(out, "zz_a") && strstr(out, "zz_b"),
               "%s", out);
}

TEST(layers_refuse_a_long_file_and_a_long_function)
{
    static char out[1 << 16];
    const char *root = copy_tree();
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "cd %s/src/base && { echo 'int zz_long(void);'; echo 'int zz_long(void)'; echo '{'; "
             "i=0; while [ $i -lt 119 ]; do echo '    ;'; i=$((i+1)); done; echo '    return 0;'; "
             "echo '}'; } > zz_long.c && i=0; while [ $i -lt 1001 ]; do echo; i=$((i+1)); done > zz_big.h",
             root);
    ENSURE(run_sh(cmd, out, sizeof out) == 0);
    ENSURE(check_tree(root, out, sizeof out) == 1);
    ENSURE_MSG(strstr(out, "src/base/zz_big.h:1: 1001 lines (at most 1000)"), "%s", out);
    ENSURE_MSG(strstr(out, "src/base/zz_long.c:2: function zz_long is 122 lines (at most 120)"), "%s", out);
}
