/* fuzz_stl.c - the STL mesh reader, from memory (rf_mesh_read_from_memory), z up and
 * y up. */
#include "input/terrain_io.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_tri_list l = {0};
    rf_error err;
    rf_mesh_read_from_memory((const char *)data, size, "mesh.stl", 0, size % 2 ? 'y' : 'z', &l,
                             &err);
    rf_tri_list_free(&l);
    return 0;
}
