/* libFuzzer target: the OFF reader; what it accepts is written and read back unchanged. */
#include <stddef.h>
#include <stdint.h>
#include "fuzz_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_mesh_roundtrip(data, size, vp_mesh_read_off_buf, VP_MESH_OFF, 0, 1);
    return 0;
}
