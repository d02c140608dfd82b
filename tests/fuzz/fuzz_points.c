/* fuzz_points.c - the reader of rows of numbers (rf_points_read, from a file); the
 * first byte chooses the columns (1 to 8). */
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
    char path[400];
    fuzz_write("points.txt", data + 1, size - 1, path, sizeof path);
    rf_points pts = {0};
    rf_error err;
    if (rf_points_read(path, 1 + data[0] % 8, &pts, &err) == 0)
        rf_points_free(&pts);
    return 0;
}
