/* fuzz_stl.c - the STL mesh reader (rf_mesh_read, from a file), z up and y up. */
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
    fuzz_write("mesh.stl", data, size, path, sizeof path);
    rf_tri_list l = {0};
    rf_error err;
    rf_mesh_read(path, size % 2 ? 'y' : 'z', &l, &err);
    rf_tri_list_free(&l);
    return 0;
}
