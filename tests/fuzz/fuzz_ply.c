/* libFuzzer target: the PLY reader (binary and ASCII); what it accepts is written as binary
 * PLY and read back unchanged. */
#include <stddef.h>
#include <stdint.h>
#include "fuzz_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_mesh_roundtrip(data, size, vp_mesh_read_ply_buf, VP_MESH_PLY_BIN, 1, 0);
    return 0;
}
