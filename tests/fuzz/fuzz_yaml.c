/* fuzz_yaml.c - the YAML document reader (rf_ydoc_load_text, in memory). */
#include "input/yamldoc.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_ydoc d;
    rf_error err;
    if (rf_ydoc_load_text(&d, "fuzz.yaml", (const char *)data, size, &err) == 0)
        rf_ydoc_free(&d);
    return 0;
}
