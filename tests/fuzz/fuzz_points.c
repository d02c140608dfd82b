/* fuzz_points.c - the reader of rows of numbers, from memory
 * (rf_points_read_from_memory); the first byte chooses the columns (1 to 8). */
#include "input/terrain_io.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    rf_points pts = {0};
    rf_error err;
    if (rf_points_read_from_memory((const char *)data + 1, size - 1, "points.txt", 1 + data[0] % 8,
                                   &pts, &err) == 0)
        rf_points_free(&pts);
    return 0;
}
