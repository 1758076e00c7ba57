/* vp_meshio: round trips (PLY binary/ASCII, OFF), byte-identical rewrites, the reader variants
 * (float/double, extra properties, big endian, quads, comments, CRLF), and hostile input:
 * every truncation, huge counts, bad indices, random byte flips, NUL bytes inside text; files that
 * are not regular (/dev/zero), too large or without a header are refused at once.
 * With "--write-ply FILE" it writes a 12x8 torus grid (R=1, r=0.3) as binary PLY to FILE and
 * as ASCII PLY to FILE.ascii.ply, for tests/t_ply_open3d.sh. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <unistd.h>
#include "vp_meshgen.h"
#include "vp_meshio.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_test.h"

static int same_mesh(const vp_mesh_t *a, const vp_mesh_t *b)
{
    return a->nv == b->nv && a->nt == b->nt && !memcmp(a->xyz, b->xyz, a->nv * 3 * sizeof(double)) &&
           !memcmp(a->tri, b->tri, a->nt * 3 * sizeof(uint32_t));
}

static int read_str(const char *text, vp_mesh_t *m, char *err, size_t errlen)
{
    return vp_mesh_read_buf(text, strlen(text), m, err, errlen);
}

static void round_trips(void)
{
    vp_mesh_t m, r, r2;
    int fmt;
    vp_mesh_init(&m); vp_mesh_init(&r); vp_mesh_init(&r2);
    CHECK(vp_meshgen_icosphere(2, &m) == VP_OK);
    m.xyz[0] = 1.0 / 3.0; m.xyz[1] = -1e-300; m.xyz[2] = 123456789.123456789;   /* awkward values */
    for (fmt = VP_MESH_PLY_BIN; fmt <= VP_MESH_OFF; fmt++) {
        unsigned char *b1, *b2;
        size_t n1, n2;
        char err[256] = "";
        CHECK(vp_mesh_write_buf(&m, fmt, &b1, &n1) == VP_OK);
        CHECKF(vp_mesh_read_buf(b1, n1, &r, err, sizeof err) == VP_OK, "format %d: %s", fmt, err);
        CHECKF(same_mesh(&m, &r), "format %d: round trip changed the mesh", fmt);
        CHECK(vp_mesh_write_buf(&r, fmt, &b2, &n2) == VP_OK);
        CHECKF(n1 == n2 && !memcmp(b1, b2, n1), "format %d: rewrite not byte-identical", fmt);
        free(b2);
        CHECK(vp_mesh_write_buf(&m, fmt, &b2, &n2) == VP_OK);   /* writing twice: same bytes */
        CHECK(n1 == n2 && !memcmp(b1, b2, n1));
        free(b1); free(b2);
    }
    /* file wrappers */
    {
        char path[64], err[256];
        snprintf(path, sizeof path, "/tmp/vp_test_meshio_%ld.ply", (long)getpid());
        CHECK(vp_mesh_write_file(&m, path, VP_MESH_PLY_BIN) == VP_OK);
        CHECK(vp_mesh_read_file(path, &r2, err, sizeof err) == VP_OK && same_mesh(&m, &r2));
        remove(path);
        CHECK(vp_mesh_read_file(path, &r2, err, sizeof err) == VP_EIO && strstr(err, path));
        CHECK(vp_mesh_format_from_name("a/b.off") == VP_MESH_OFF && vp_mesh_format_from_name("x.ply") == VP_MESH_PLY_BIN);
    }
    /* exact header text of the default format */
    {
        unsigned char *b;
        size_t n;
        const char *hdr = "ply\nformat binary_little_endian 1.0\nelement vertex 162\nproperty double x\nproperty double y\n"
                          "property double z\nelement face 320\nproperty list uchar int vertex_indices\nend_header\n";
        CHECK(vp_mesh_write_buf(&m, VP_MESH_PLY_BIN, &b, &n) == VP_OK);
        CHECK(n == strlen(hdr) + 162 * 24 + 320 * 13 && !memcmp(b, hdr, strlen(hdr)));
        free(b);
    }
    vp_mesh_free(&m); vp_mesh_free(&r); vp_mesh_free(&r2);
}

static void variants(void)
{
    vp_mesh_t m;
    char err[256];
    vp_mesh_init(&m);
    /* ascii, float, extra properties, a quad, comments, CRLF, extra element */
    CHECKF(read_str("ply\r\nformat ascii 1.0\r\ncomment hi\r\nelement vertex 4\r\nproperty float x\r\nproperty float y\r\n"
                    "property float z\r\nproperty uchar red\r\nproperty float nx\r\nelement face 1\r\n"
                    "property list uchar uint vertex_index\r\nproperty int flags\r\nelement edge 1\r\nproperty int a\r\n"
                    "property int b\r\nend_header\r\n0 0 0 255 1\r\n1 0 0 0 1\n1 1 0.5 0 1\n0 1 0 9 1\n4 0 1 2 3 7\n0 1\n",
                    &m, err, sizeof err) == VP_OK, "%s", err);
    CHECK(m.nv == 4 && m.nt == 2 && m.xyz[8] == 0.5 && m.tri[3] == 0 && m.tri[4] == 2 && m.tri[5] == 3);
    /* binary big endian: float vertices, int count, short indices */
    {
        unsigned char buf[512];
        const char *hdr = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list int short vertex_indices\nend_header\n";
        size_t n = strlen(hdr), i;
        const unsigned char one[4] = { 0x3f, 0x80, 0, 0 };   /* 1.0f */
        memcpy(buf, hdr, n);
        for (i = 0; i < 9; i++) { if (i == 0 || i == 4) memcpy(buf + n, one, 4); else memset(buf + n, 0, 4); n += 4; }
        buf[n++] = 0; buf[n++] = 0; buf[n++] = 0; buf[n++] = 3;
        buf[n++] = 0; buf[n++] = 0; buf[n++] = 0; buf[n++] = 1; buf[n++] = 0; buf[n++] = 2;
        CHECKF(vp_mesh_read_buf(buf, n, &m, err, sizeof err) == VP_OK, "%s", err);
        CHECK(m.nv == 3 && m.nt == 1 && m.xyz[0] == 1 && m.xyz[4] == 1 && m.tri[2] == 2);
        CHECK(vp_mesh_read_buf(buf, n - 1, &m, err, sizeof err) == VP_ECORRUPT && strstr(err, "byte"));
    }
    /* OFF: comments, colours after coordinates, counts on the first line, a pentagon */
    CHECKF(read_str("# comment\nCOFF 5 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n1 1 0 # c\n0.5 2 0\n0 1 0\n5 0 1 2 3 4 255 0 0\n",
                    &m, err, sizeof err) == VP_OK, "%s", err);
    CHECK(m.nv == 5 && m.nt == 3);
    vp_mesh_free(&m);
}

static void expect_bad(const char *text, const char *needle)
{
    vp_mesh_t m;
    char err[256] = "";
    int st;
    vp_mesh_init(&m);
    st = read_str(text, &m, err, sizeof err);
    CHECKF(st == VP_ECORRUPT, "accepted: %.60s", text);
    CHECKF(strstr(err, needle) != NULL, "message '%s' lacks '%s'", err, needle);
    CHECK(m.nv == 0 && m.xyz == NULL);   /* output untouched */
    vp_mesh_free(&m);
}

static void hostile(void)
{
    vp_mesh_t m, ico;
    unsigned char *bytes[3];
    size_t len[3], cut;
    int fmt, i;
    vp_rng_t r;
    char err[256];
    vp_mesh_init(&m); vp_mesh_init(&ico);
    expect_bad("ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", "impossible");
    expect_bad("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 99999999999\nproperty list uchar int vertex_indices\nend_header\n", "impossible");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "line 13: vertex index 3 out of range");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "out of range");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "corners");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n250 0 1 2\n", "impossible");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 nan 0\n", "line 8: bad number");
    expect_bad("ply\nformat ascii 2.0\nend_header\n", "line 2: bad format");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", "lacks x, y or z");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n", "line 4: unknown type");
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\n", "before 'end_header'");
    expect_bad("plyx\n", "not a PLY");
    expect_bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", "line 6: vertex index 5 out of range");
    expect_bad("OFF\n99999999999 1 0\n0 0 0\n", "impossible");
    expect_bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n", "unexpected end of file");
    expect_bad("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "corners");
    expect_bad("OFF\n3 -1 0\n", "impossible");
    expect_bad("NOTOFF", "not an OFF");
    expect_bad("", "not an OFF");
    /* Every truncation of valid files: binary PLY must fail at each cut; text formats may parse a
     * shorter number, but never crash or return indices out of range. */
    CHECK(vp_meshgen_icosphere(0, &ico) == VP_OK);
    for (fmt = 0; fmt < 3; fmt++) CHECK(vp_mesh_write_buf(&ico, fmt, &bytes[fmt], &len[fmt]) == VP_OK);
    for (fmt = 0; fmt < 3; fmt++)
        for (cut = 0; cut < len[fmt]; cut++) {
            unsigned char *copy = malloc(cut + 1);   /* exact-size buffer: overreads are caught by ASan */
            int st;
            memcpy(copy, bytes[fmt], cut);
            st = vp_mesh_read_buf(copy, cut, &m, err, sizeof err);
            if (fmt == VP_MESH_PLY_BIN) CHECKF(st == VP_ECORRUPT, "binary cut at %lu accepted", (unsigned long)cut);
            if (st == VP_OK) {
                size_t k;
                for (k = 0; k < 3 * m.nt; k++) CHECK(m.tri[k] < m.nv);
            }
            free(copy);
        }
    /* Random byte flips. */
    vp_rng_seed(&r, 2024);
    for (i = 0; i < 30000; i++) {
        int f = i % 3, nflip = 1 + (int)vp_rng_below(&r, 4), j, st;
        unsigned char *copy = malloc(len[f]);
        memcpy(copy, bytes[f], len[f]);
        for (j = 0; j < nflip; j++) copy[vp_rng_below(&r, len[f])] ^= (unsigned char)(1u << vp_rng_below(&r, 8));
        st = vp_mesh_read_buf(copy, len[f], &m, err, sizeof err);
        CHECK(st == VP_OK || st == VP_ECORRUPT);
        if (st == VP_OK) {
            size_t k;
            for (k = 0; k < 3 * m.nt; k++) CHECK(m.tri[k] < m.nv);
        } else CHECK(strlen(err) > 0);
        free(copy);
    }
    for (fmt = 0; fmt < 3; fmt++) free(bytes[fmt]);
    vp_mesh_free(&m); vp_mesh_free(&ico);
}

static void expect_bad_n(const char *text, size_t n, const char *needle, const char *needle2)
{
    vp_mesh_t m;
    char err[256] = "";
    int st;
    vp_mesh_init(&m);
    st = vp_mesh_read_buf(text, n, &m, err, sizeof err);
    CHECKF(st == VP_ECORRUPT, "accepted: %.60s", text);
    CHECKF(strstr(err, needle) != NULL && strstr(err, needle2) != NULL, "message '%s' lacks '%s' or '%s'", err, needle, needle2);
    CHECK(m.nv == 0 && m.xyz == NULL);
    vp_mesh_free(&m);
}

/* A NUL byte inside text is refused, naming the line (it was read as the part before it:
 * "-0.2986" became "-0."); files that are not regular, too large or without a header are
 * refused before they are read (off:/dev/zero grew to gigabytes). */
static void nul_and_files(void)
{
    char t[256], err[400], path[96];
    vp_mesh_t m;
    size_t n;
    int fd;
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    vp_mesh_init(&m);
    n = (size_t)snprintf(t, sizeof t, "OFF\n3 1 0\n-0.2986 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    CHECK(read_str(t, &m, err, sizeof err) == VP_OK && m.xyz[0] == -0.2986);
    t[strchr(t, '2') - t] = 0;          /* "-0.<NUL>986" */
    expect_bad_n(t, n, "line 3", "NUL");
    n = (size_t)snprintf(t, sizeof t, "%s", ply);
    CHECK(read_str(t, &m, err, sizeof err) == VP_OK && m.nv == 3);
    t[strstr(t, "1 0 0\n0 1 0") - t + 2] = 0;   /* a vertex line of the body: line 11 */
    expect_bad_n(t, n, "line 11", "NUL");
    n = (size_t)snprintf(t, sizeof t, "%s", ply);
    t[strstr(t, "vertex 3") - t + 7] = 0;       /* "element vertex <NUL>": line 3 of the header */
    expect_bad_n(t, n, "line 3", "NUL");
    /* files: a device, a folder, a file of zeros, a file over the size bound */
    CHECKF(vp_mesh_read_file("/dev/zero", &m, err, sizeof err) == VP_EIO && strstr(err, "not a regular file"), "%s", err);
    CHECKF(vp_mesh_read_file("/tmp", &m, err, sizeof err) == VP_EIO && strstr(err, "not a regular file"), "%s", err);
    snprintf(path, sizeof path, "/tmp/vp_test_meshio_z_%ld.off", (long)getpid());
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    CHECK(fd >= 0 && ftruncate(fd, 1 << 20) == 0);            /* a megabyte of zeros */
    CHECKF(vp_mesh_read_file(path, &m, err, sizeof err) == VP_ECORRUPT && strstr(err, "neither 'ply' nor 'OFF'"), "%s", err);
    CHECK(ftruncate(fd, (off_t)VP_MESH_MAX_FILE + 1) == 0);   /* sparse: nothing is written */
    CHECKF(vp_mesh_read_file(path, &m, err, sizeof err) == VP_EIO && strstr(err, "bytes, more than"), "%s", err);
    close(fd);
    remove(path);
    vp_mesh_free(&m);
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--write-ply")) {
        vp_mesh_t m;
        char path[1024];
        vp_mesh_init(&m);
        if (vp_meshgen_torus(1.0, 0.3, 12, 8, &m) < 0) return 1;
        snprintf(path, sizeof path, "%s.ascii.ply", argv[2]);
        if (vp_mesh_write_file(&m, argv[2], VP_MESH_PLY_BIN) < 0 || vp_mesh_write_file(&m, path, VP_MESH_PLY_ASCII) < 0) return 1;
        vp_mesh_free(&m);
        return 0;
    }
    round_trips();
    variants();
    hostile();
    nul_and_files();
    return vp_test_done("test_meshio");
}
