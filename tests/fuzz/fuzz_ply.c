/* libFuzzer target: the PLY reader (binary and ASCII); what it accepts is written as binary
 * PLY and read back unchanged. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_meshio.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vp_mesh_t m, m2;
    char err[300];
    vp_mesh_init(&m);
    vp_mesh_init(&m2);
    if (vp_mesh_read_ply_buf(data, size, &m, err, sizeof err) == 0) {
        unsigned char *out;
        size_t len;
        if (vp_mesh_write_buf(&m, VP_MESH_PLY_BIN, &out, &len) == 0) {
            if (vp_mesh_read_ply_buf(out, len, &m2, err, sizeof err) != 0 || m2.nv != m.nv || m2.nt != m.nt ||
                (m.nt && memcmp(m.tri, m2.tri, 3 * m.nt * sizeof *m.tri) != 0) ||
                (m.nv && memcmp(m.xyz, m2.xyz, 3 * m.nv * sizeof *m.xyz) != 0))
                __builtin_trap();
            free(out);
        }
    }
    vp_mesh_free(&m);
    vp_mesh_free(&m2);
    return 0;
}
