/* The round trip both mesh fuzz targets make: what the reader accepts is written in the given
 * format and read back unchanged (faces always, coordinates when same_xyz). */
#ifndef FUZZ_MESH_H
#define FUZZ_MESH_H
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_meshio.h"

typedef int (*fuzz_mesh_reader_t)(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen);

static void fuzz_mesh_roundtrip(const uint8_t *data, size_t size, fuzz_mesh_reader_t rd, int format, int same_xyz,
                                int then_any)
{
    vp_mesh_t m, m2;
    char err[300];
    vp_mesh_init(&m);
    vp_mesh_init(&m2);
    if (rd(data, size, &m, err, sizeof err) == 0) {
        unsigned char *out;
        size_t len;
        if (vp_mesh_write_buf(&m, format, &out, &len) == 0) {
            if (rd(out, len, &m2, err, sizeof err) != 0 || m2.nv != m.nv || m2.nt != m.nt ||
                (m.nt && memcmp(m.tri, m2.tri, 3 * m.nt * sizeof *m.tri) != 0) ||
                (same_xyz && m.nv && memcmp(m.xyz, m2.xyz, 3 * m.nv * sizeof *m.xyz) != 0))
                __builtin_trap();
            free(out);
        }
    }
    if (then_any) (void)vp_mesh_read_buf(data, size, &m, err, sizeof err);
    vp_mesh_free(&m);
    vp_mesh_free(&m2);
}

#endif
