/* vp_meshio — triangle meshes on the PC side: PLY (binary little-endian, ASCII) and OFF.
 *
 * Writers are deterministic: the same mesh gives the same bytes (no dates, no variable text).
 * Readers take a memory buffer (the file readers are thin wrappers) and never trust a count:
 * every count and index is checked against the bytes that remain, so hostile input gives
 * VP_ECORRUPT with a message naming the line (text) or byte offset (binary), never a crash.
 * Text (OFF, an ASCII PLY's body, any PLY header) must not hold a NUL byte: refused, naming
 * the line.
 * Polygons with more than 3 corners are split into a fan of triangles.
 */
#ifndef VP_MESHIO_H
#define VP_MESHIO_H
#include <stddef.h>
#include <stdint.h>

typedef struct vp_mesh {
    double   *xyz;   /* 3 * nv coordinates */
    uint32_t *tri;   /* 3 * nt vertex indices */
    size_t    nv, nt;
} vp_mesh_t;

enum vp_mesh_format {
    VP_MESH_PLY_BIN = 0,   /* binary_little_endian, double x y z, list uchar int (default) */
    VP_MESH_PLY_ASCII = 1,
    VP_MESH_OFF = 2
};

void vp_mesh_init(vp_mesh_t *m);                          /* empty mesh */
void vp_mesh_free(vp_mesh_t *m);                          /* frees and empties */
int  vp_mesh_alloc(vp_mesh_t *m, size_t nv, size_t nt);   /* replaces the contents; VP_ENOMEM */

/* Writes m in the given format to a malloc'ed buffer (*out, *len); caller frees *out. */
int  vp_mesh_write_buf(const vp_mesh_t *m, int format, unsigned char **out, size_t *len);
int  vp_mesh_write_file(const vp_mesh_t *m, const char *path, int format);
/* Format from the file name: .off -> OFF, otherwise PLY binary. */
int  vp_mesh_format_from_name(const char *path);

/* Readers: on success *out holds a new mesh (its old contents are freed); on failure *out is
 * unchanged and err (if not NULL) gets a one-line message. */
int  vp_mesh_read_off_buf(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen);
int  vp_mesh_read_ply_buf(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen);
/* Chooses by the first bytes ("ply" or "OFF"). */
int  vp_mesh_read_buf(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen);
/* A regular file of at most VP_MESH_MAX_FILE bytes (a device, a pipe or a folder is refused at
 * once; so is a file whose first bytes are neither "ply" nor "OFF"). */
#define VP_MESH_MAX_FILE (1ULL << 31)
int  vp_mesh_read_file(const char *path, vp_mesh_t *out, char *err, size_t errlen);

#endif
