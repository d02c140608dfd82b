/* fuzz_grid.c - the ESRI ASCII grid reader, from memory (rf_asc_read_from_memory). */
#include "input/terrain_io.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_asc_grid g;
    rf_error err;
    if (rf_asc_read_from_memory((const char *)data, size, "grid.asc", &g, &err) == 0)
        rf_asc_free(&g);
    return 0;
}
