/* fuzz_grid.c - the ESRI ASCII grid reader (rf_asc_read, from a file). */
#include "input/terrain_io.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[400];
    fuzz_write("grid.asc", data, size, path, sizeof path);
    rf_asc_grid g;
    rf_error err;
    if (rf_asc_read(path, &g, &err) == 0)
        rf_asc_free(&g);
    return 0;
}
