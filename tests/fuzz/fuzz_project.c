/* fuzz_project.c - the project loader, from memory (rf_project_load_from_memory): the
 * input is read as bad/project.yaml of the scratch folder, beside the test terrains
 * under the names the seed projects give them, so that their terrains load. */
#include "rockfall/project.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    static const char *const files[] = {"grid5.asc", "upper.obj", "lower.stl", "upper_yup.obj",
                                        "header_twice.asc", "malformed.asc"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        char to[300];
        snprintf(to, sizeof to, "data/project/%s", files[i]);
        fuzz_copy_data(files[i], to);
        snprintf(to, sizeof to, "bad/%s", files[i]);
        fuzz_copy_data(files[i], to);
    }
    fuzz_copy_data("grid5.asc", "bad/terrain.asc");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[400];
    snprintf(path, sizeof path, "%s/bad/project.yaml", fuzz_scratch());
    rf_project p;
    rf_error err;
    if (rf_project_load_from_memory((const char *)data, size, path, &p, &err) == 0)
        rf_project_free(&p);
    return 0;
}
