/* vp_meshio — see vp_meshio.h. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_file.h"
#include "vp_meshio.h"
#include "vp_status.h"

/* ---------- small helpers ---------- */

void vp_mesh_init(vp_mesh_t *m)
{
    m->xyz = NULL; m->tri = NULL; m->nv = 0; m->nt = 0;
}

void vp_mesh_free(vp_mesh_t *m)
{
    free(m->xyz); free(m->tri);
    vp_mesh_init(m);
}

int vp_mesh_alloc(vp_mesh_t *m, size_t nv, size_t nt)
{
    double *xyz;
    uint32_t *tri;
    if (nv > SIZE_MAX / (3 * sizeof(double)) || nt > SIZE_MAX / (3 * sizeof(uint32_t)))
        return VP_ENOMEM;
    xyz = malloc(nv ? nv * 3 * sizeof(double) : 1);
    tri = malloc(nt ? nt * 3 * sizeof(uint32_t) : 1);
    if (!xyz || !tri) { free(xyz); free(tri); return VP_ENOMEM; }
    vp_mesh_free(m);
    m->xyz = xyz; m->tri = tri; m->nv = nv; m->nt = nt;
    return VP_OK;
}

/* Growable output bytes. */
typedef struct vp_obuf { unsigned char *p; size_t n, cap; int failed; } vp_obuf_t;

static void vp_obuf_put(vp_obuf_t *b, const void *src, size_t n)
{
    if (b->failed) return;
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        unsigned char *q;
        while (cap < b->n + n) cap *= 2;
        q = realloc(b->p, cap);
        if (!q) { b->failed = 1; return; }
        b->p = q; b->cap = cap;
    }
    memcpy(b->p + b->n, src, n);
    b->n += n;
}

static void vp_obuf_printf(vp_obuf_t *b, const char *fmt, ...)
{
    char tmp[256];
    int k;
    va_list ap;
    va_start(ap, fmt);
    k = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (k < 0 || (size_t)k >= sizeof tmp) { b->failed = 1; return; }
    vp_obuf_put(b, tmp, (size_t)k);
}

static void vp_obuf_le64(vp_obuf_t *b, double v)
{
    unsigned char o[8];
    uint64_t u;
    int i;
    memcpy(&u, &v, 8);
    for (i = 0; i < 8; i++) o[i] = (unsigned char)(u >> (8 * i));
    vp_obuf_put(b, o, 8);
}

static void vp_obuf_le32(vp_obuf_t *b, uint32_t u)
{
    unsigned char o[4];
    int i;
    for (i = 0; i < 4; i++) o[i] = (unsigned char)(u >> (8 * i));
    vp_obuf_put(b, o, 4);
}

/* ---------- writers ---------- */

int vp_mesh_write_buf(const vp_mesh_t *m, int format, unsigned char **out, size_t *len)
{
    vp_obuf_t b = { NULL, 0, 0, 0 };
    size_t i;
    if (!m || !out || !len) return VP_EINVAL;
    if (format < VP_MESH_PLY_BIN || format > VP_MESH_OFF) return VP_EINVAL;
    if (m->nv > (size_t)INT32_MAX) return VP_ERANGE;
    for (i = 0; i < 3 * m->nt; i++)
        if (m->tri[i] >= m->nv) return VP_EINVAL;
    if (format == VP_MESH_OFF) {
        vp_obuf_printf(&b, "OFF\n%lu %lu 0\n", (unsigned long)m->nv, (unsigned long)m->nt);
        for (i = 0; i < m->nv; i++)
            vp_obuf_printf(&b, "%.17g %.17g %.17g\n", m->xyz[3 * i], m->xyz[3 * i + 1], m->xyz[3 * i + 2]);
        for (i = 0; i < m->nt; i++)
            vp_obuf_printf(&b, "3 %lu %lu %lu\n", (unsigned long)m->tri[3 * i],
                           (unsigned long)m->tri[3 * i + 1], (unsigned long)m->tri[3 * i + 2]);
    } else {
        vp_obuf_printf(&b, "ply\nformat %s 1.0\n", format == VP_MESH_PLY_BIN ? "binary_little_endian" : "ascii");
        vp_obuf_printf(&b, "element vertex %lu\nproperty double x\nproperty double y\nproperty double z\n",
                       (unsigned long)m->nv);
        vp_obuf_printf(&b, "element face %lu\nproperty list uchar int vertex_indices\nend_header\n",
                       (unsigned long)m->nt);
        if (format == VP_MESH_PLY_BIN) {
            unsigned char three = 3;
            for (i = 0; i < 3 * m->nv; i++) vp_obuf_le64(&b, m->xyz[i]);
            for (i = 0; i < m->nt; i++) {
                vp_obuf_put(&b, &three, 1);
                vp_obuf_le32(&b, m->tri[3 * i]);
                vp_obuf_le32(&b, m->tri[3 * i + 1]);
                vp_obuf_le32(&b, m->tri[3 * i + 2]);
            }
        } else {
            for (i = 0; i < m->nv; i++)
                vp_obuf_printf(&b, "%.17g %.17g %.17g\n", m->xyz[3 * i], m->xyz[3 * i + 1], m->xyz[3 * i + 2]);
            for (i = 0; i < m->nt; i++)
                vp_obuf_printf(&b, "3 %lu %lu %lu\n", (unsigned long)m->tri[3 * i],
                               (unsigned long)m->tri[3 * i + 1], (unsigned long)m->tri[3 * i + 2]);
        }
    }
    if (b.failed) { free(b.p); return VP_ENOMEM; }
    if (!b.p) b.p = malloc(1);
    *out = b.p; *len = b.n;
    return VP_OK;
}

int vp_mesh_format_from_name(const char *path)
{
    size_t n = strlen(path);
    if (n >= 4 && (!strcmp(path + n - 4, ".off") || !strcmp(path + n - 4, ".OFF"))) return VP_MESH_OFF;
    return VP_MESH_PLY_BIN;
}

int vp_mesh_write_file(const vp_mesh_t *m, const char *path, int format)
{
    unsigned char *bytes;
    size_t len;
    FILE *f;
    int st = vp_mesh_write_buf(m, format, &bytes, &len);
    if (st < 0) return st;
    f = fopen(path, "wb");
    if (!f) { free(bytes); return VP_EIO; }
    if (fwrite(bytes, 1, len, f) != len) st = VP_EIO;
    if (fclose(f) != 0) st = VP_EIO;
    free(bytes);
    return st;
}

/* ---------- text scanning ---------- */

typedef struct vp_lex {
    const char *p;
    size_t len, pos;
    size_t line;      /* 1-based line of pos */
    int hash_comments;
} vp_lex_t;

static int vp_is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

static void vp_lex_skip(vp_lex_t *lx)
{
    while (lx->pos < lx->len) {
        char c = lx->p[lx->pos];
        if (c == '\n') { lx->line++; lx->pos++; }
        else if (vp_is_space(c)) lx->pos++;
        else if (c == '#' && lx->hash_comments) {
            while (lx->pos < lx->len && lx->p[lx->pos] != '\n') lx->pos++;
        } else break;
    }
}

/* Next token copied into tok (NUL-terminated); 0 at end of input, -1 if too long. */
static int vp_lex_token(vp_lex_t *lx, char *tok, size_t toklen)
{
    size_t n = 0;
    vp_lex_skip(lx);
    if (lx->pos >= lx->len) return 0;
    while (lx->pos < lx->len && !vp_is_space(lx->p[lx->pos]) &&
           !(lx->hash_comments && lx->p[lx->pos] == '#')) {
        if (n + 1 >= toklen) return -1;
        tok[n++] = lx->p[lx->pos++];
    }
    tok[n] = 0;
    return 1;
}

/* Skips the rest of the current line (extra values such as colours). */
static void vp_lex_skip_line(vp_lex_t *lx)
{
    while (lx->pos < lx->len && lx->p[lx->pos] != '\n') lx->pos++;
}

static int vp_parse_double(const char *tok, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(tok, &end);
    if (end == tok || *end) return -1;
    if (!isfinite(*v)) return -1;
    return 0;
}

static int vp_parse_long(const char *tok, long long *v)
{
    char *end;
    errno = 0;
    *v = strtoll(tok, &end, 10);
    if (end == tok || *end || errno == ERANGE) return -1;
    return 0;
}

/* Reads a number token; err names the line. */
static int vp_lex_double(vp_lex_t *lx, double *v, const char *what, char *err, size_t errlen)
{
    char tok[96];
    int k = vp_lex_token(lx, tok, sizeof tok);
    if (k == 0) { vp_seterr(err, errlen, "line %lu: unexpected end of file, expected %s", (unsigned long)lx->line, what); return VP_ECORRUPT; }
    if (k < 0 || vp_parse_double(tok, v) < 0) {
        vp_seterr(err, errlen, "line %lu: bad number for %s", (unsigned long)lx->line, what);
        return VP_ECORRUPT;
    }
    return VP_OK;
}

static int vp_lex_long(vp_lex_t *lx, long long *v, const char *what, char *err, size_t errlen)
{
    char tok[96];
    int k = vp_lex_token(lx, tok, sizeof tok);
    if (k == 0) { vp_seterr(err, errlen, "line %lu: unexpected end of file, expected %s", (unsigned long)lx->line, what); return VP_ECORRUPT; }
    if (k < 0 || vp_parse_long(tok, v) < 0) {
        vp_seterr(err, errlen, "line %lu: bad integer for %s", (unsigned long)lx->line, what);
        return VP_ECORRUPT;
    }
    return VP_OK;
}

/* Triangle list that grows as polygons are fanned. */
typedef struct vp_trilist { uint32_t *t; size_t n, cap; } vp_trilist_t;

static int vp_trilist_add(vp_trilist_t *tl, uint32_t a, uint32_t b, uint32_t c)
{
    if (tl->n == tl->cap) {
        size_t cap = tl->cap ? 2 * tl->cap : 64;
        uint32_t *q;
        if (cap > SIZE_MAX / (3 * sizeof(uint32_t))) return VP_ENOMEM;
        q = realloc(tl->t, cap * 3 * sizeof(uint32_t));
        if (!q) return VP_ENOMEM;
        tl->t = q; tl->cap = cap;
    }
    tl->t[3 * tl->n] = a; tl->t[3 * tl->n + 1] = b; tl->t[3 * tl->n + 2] = c;
    tl->n++;
    return VP_OK;
}

/* Hands xyz and the triangles to out (freeing its old contents). */
static void vp_mesh_take(vp_mesh_t *out, double *xyz, size_t nv, vp_trilist_t *tl)
{
    vp_mesh_free(out);
    out->xyz = xyz ? xyz : malloc(1);
    out->nv = nv;
    out->tri = tl->t ? tl->t : malloc(1);
    out->nt = tl->n;
    tl->t = NULL;
}

/* ---------- OFF ---------- */

int vp_mesh_read_off_buf(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen)
{
    vp_lex_t lx;
    char tok[96];
    long long nv, nf, ne, i, j, n;
    double *xyz = NULL;
    vp_trilist_t tl = { NULL, 0, 0 };
    int st, k;
    unsigned long nul_line;
    if (!buf || !out) return VP_EINVAL;
    /* OFF is text: a NUL byte would end a number early ("-0.2986" read as "-0.") */
    if (vp_file_find_nul(buf, len, &nul_line)) {
        vp_seterr(err, errlen, "line %lu: a NUL byte inside the text (a damaged or binary file)", nul_line);
        return VP_ECORRUPT;
    }
    lx.p = buf; lx.len = len; lx.pos = 0; lx.line = 1; lx.hash_comments = 1;
    k = vp_lex_token(&lx, tok, sizeof tok);
    if (k <= 0 || (strcmp(tok, "OFF") && strcmp(tok, "COFF") && strcmp(tok, "NOFF") && strcmp(tok, "CNOFF"))) {
        vp_seterr(err, errlen, "line 1: not an OFF file (expected 'OFF')");
        return VP_ECORRUPT;
    }
    if ((st = vp_lex_long(&lx, &nv, "vertex count", err, errlen)) < 0) return st;
    if ((st = vp_lex_long(&lx, &nf, "face count", err, errlen)) < 0) return st;
    if ((st = vp_lex_long(&lx, &ne, "edge count", err, errlen)) < 0) return st;
    /* Each vertex needs at least 6 bytes ("0 0 0\n"), each face at least 8 ("3 0 0 0\n"). */
    if (nv < 0 || nf < 0 || (unsigned long long)nv > (len - lx.pos) / 6 + 1 ||
        (unsigned long long)nv > (unsigned long long)UINT32_MAX) {
        vp_seterr(err, errlen, "line %lu: vertex count %lld impossible for a file of %lu bytes",
                  (unsigned long)lx.line, nv, (unsigned long)len);
        return VP_ECORRUPT;
    }
    if ((unsigned long long)nf > (len - lx.pos) / 8 + 1) {
        vp_seterr(err, errlen, "line %lu: face count %lld impossible for a file of %lu bytes",
                  (unsigned long)lx.line, nf, (unsigned long)len);
        return VP_ECORRUPT;
    }
    vp_lex_skip_line(&lx);
    xyz = malloc(nv ? (size_t)nv * 3 * sizeof(double) : 1);
    if (!xyz) return VP_ENOMEM;
    for (i = 0; i < nv; i++) {
        for (j = 0; j < 3; j++)
            if ((st = vp_lex_double(&lx, &xyz[3 * i + j], "a vertex coordinate", err, errlen)) < 0) goto fail;
        vp_lex_skip_line(&lx);
    }
    for (i = 0; i < nf; i++) {
        long long first, prev, cur;
        if ((st = vp_lex_long(&lx, &n, "a face size", err, errlen)) < 0) goto fail;
        if (n < 3 || n > 1000000 || (unsigned long long)n > len - lx.pos) {
            vp_seterr(err, errlen, "line %lu: face %lld has %lld corners", (unsigned long)lx.line, i, n);
            st = VP_ECORRUPT; goto fail;
        }
        first = prev = -1;
        for (j = 0; j < n; j++) {
            if ((st = vp_lex_long(&lx, &cur, "a vertex index", err, errlen)) < 0) goto fail;
            if (cur < 0 || cur >= nv) {
                vp_seterr(err, errlen, "line %lu: vertex index %lld out of range [0,%lld)", (unsigned long)lx.line, cur, nv);
                st = VP_ECORRUPT; goto fail;
            }
            if (j == 0) first = cur;
            else if (j >= 2 && (st = vp_trilist_add(&tl, (uint32_t)first, (uint32_t)prev, (uint32_t)cur)) < 0) goto fail;
            prev = cur;
        }
        vp_lex_skip_line(&lx);
    }
    vp_mesh_take(out, xyz, (size_t)nv, &tl);
    return VP_OK;
fail:
    free(xyz); free(tl.t);
    return st;
}

/* ---------- PLY ---------- */

enum vp_ply_type { VP_PT_NONE, VP_PT_I8, VP_PT_U8, VP_PT_I16, VP_PT_U16, VP_PT_I32, VP_PT_U32, VP_PT_F32, VP_PT_F64 };

#define VP_PLY_MAX_ELEM 16
#define VP_PLY_MAX_PROP 64

typedef struct vp_ply_prop {
    char name[32];
    int type;        /* scalar type, or item type for lists */
    int count_type;  /* VP_PT_NONE for scalars */
} vp_ply_prop_t;

typedef struct vp_ply_elem {
    char name[32];
    unsigned long long count;
    int nprop;
    vp_ply_prop_t prop[VP_PLY_MAX_PROP];
} vp_ply_elem_t;

static int vp_ply_type_of(const char *s)
{
    static const struct { const char *name; int type; } names[] = {
        {"char", VP_PT_I8}, {"int8", VP_PT_I8}, {"uchar", VP_PT_U8}, {"uint8", VP_PT_U8},
        {"short", VP_PT_I16}, {"int16", VP_PT_I16}, {"ushort", VP_PT_U16}, {"uint16", VP_PT_U16},
        {"int", VP_PT_I32}, {"int32", VP_PT_I32}, {"uint", VP_PT_U32}, {"uint32", VP_PT_U32},
        {"float", VP_PT_F32}, {"float32", VP_PT_F32}, {"double", VP_PT_F64}, {"float64", VP_PT_F64}
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(s, names[i].name)) return names[i].type;
    return VP_PT_NONE;
}

static size_t vp_ply_size(int t)
{
    switch (t) {
    case VP_PT_I8: case VP_PT_U8: return 1;
    case VP_PT_I16: case VP_PT_U16: return 2;
    case VP_PT_I32: case VP_PT_U32: case VP_PT_F32: return 4;
    case VP_PT_F64: return 8;
    default: return 0;
    }
}

static int vp_ply_is_int(int t) { return t != VP_PT_F32 && t != VP_PT_F64 && t != VP_PT_NONE; }

/* Data reader for the body: ascii tokens or binary with a byte order. */
typedef struct vp_ply_in {
    const unsigned char *p;
    size_t len, pos;
    int ascii, big_endian;
    vp_lex_t lx;
} vp_ply_in_t;

/* Reads one value of type t as double. */
static int vp_ply_read(vp_ply_in_t *in, int t, double *v, char *err, size_t errlen)
{
    if (in->ascii) {
        char tok[96];
        int k = vp_lex_token(&in->lx, tok, sizeof tok);
        if (k == 0) { vp_seterr(err, errlen, "line %lu: unexpected end of file", (unsigned long)in->lx.line); return VP_ECORRUPT; }
        if (k < 0 || vp_parse_double(tok, v) < 0) {
            vp_seterr(err, errlen, "line %lu: bad number '%.20s'", (unsigned long)in->lx.line, k < 0 ? "(too long)" : tok);
            return VP_ECORRUPT;
        }
        if (vp_ply_is_int(t) && *v != floor(*v)) {
            vp_seterr(err, errlen, "line %lu: integer expected, got '%.20s'", (unsigned long)in->lx.line, tok);
            return VP_ECORRUPT;
        }
        return VP_OK;
    } else {
        size_t n = vp_ply_size(t), i;
        uint64_t u = 0;
        if (in->len - in->pos < n) {
            vp_seterr(err, errlen, "byte %lu: unexpected end of file (truncated binary data)", (unsigned long)in->pos);
            return VP_ECORRUPT;
        }
        for (i = 0; i < n; i++) {
            unsigned b = in->p[in->pos + (in->big_endian ? i : n - 1 - i)];
            u = (u << 8) | b;
        }
        in->pos += n;
        switch (t) {
        case VP_PT_I8: *v = (double)(int8_t)(uint8_t)u; break;
        case VP_PT_U8: *v = (double)(uint8_t)u; break;
        case VP_PT_I16: *v = (double)(int16_t)(uint16_t)u; break;
        case VP_PT_U16: *v = (double)(uint16_t)u; break;
        case VP_PT_I32: *v = (double)(int32_t)(uint32_t)u; break;
        case VP_PT_U32: *v = (double)(uint32_t)u; break;
        case VP_PT_F32: { uint32_t w = (uint32_t)u; float f; memcpy(&f, &w, 4); *v = f; break; }
        default: memcpy(v, &u, 8); break;
        }
        if (!isfinite(*v)) {
            vp_seterr(err, errlen, "byte %lu: non-finite value", (unsigned long)(in->pos - n));
            return VP_ECORRUPT;
        }
        return VP_OK;
    }
}

static const char *vp_ply_where(const vp_ply_in_t *in, char *buf, size_t n)
{
    if (in->ascii) snprintf(buf, n, "line %lu", (unsigned long)in->lx.line);
    else snprintf(buf, n, "byte %lu", (unsigned long)in->pos);
    return buf;
}

/* Reads one header line into line[] (without the newline); returns 0 at end of buffer, -1 for
 * a line too long, -2 for a NUL byte in it. */
static int vp_ply_header_line(const unsigned char *p, size_t len, size_t *pos, char *line, size_t linelen)
{
    size_t n = 0;
    if (*pos >= len) return 0;
    while (*pos < len && p[*pos] != '\n') {
        if (!p[*pos]) return -2;
        if (n + 1 < linelen) line[n++] = (char)p[*pos];
        else return -1;
        (*pos)++;
    }
    if (*pos >= len) return 0;  /* header lines must end with a newline */
    (*pos)++;
    if (n && line[n - 1] == '\r') n--;
    line[n] = 0;
    return 1;
}

/* The PLY header: its elements and properties into el[*nel], the format (0 ascii, 1 binary
 * little-endian, 2 big-endian), *pos and *line_no just after it; each element's count checked
 * against the bytes left, an ASCII body checked for NUL bytes. VP_OK or VP_ECORRUPT (err). */
static int vp_ply_header(const unsigned char *p, size_t len, size_t *pos_io, size_t *line_io, vp_ply_elem_t *el,
                         int *nel_out, int *format_out, char *err, size_t errlen)
{
    int nel = 0, format = -1, have_end = 0, e;
    size_t pos = *pos_io, line_no = *line_io;
    char line[512];
    for (;;) {
        char *words[8];
        int nw = 0, k;
        char *s;
        k = vp_ply_header_line(p, len, &pos, line, sizeof line);
        line_no++;
        if (k == 0) { vp_seterr(err, errlen, "line %lu: header ends before 'end_header'", (unsigned long)line_no); return VP_ECORRUPT; }
        if (k == -2) { vp_seterr(err, errlen, "line %lu: a NUL byte inside the header (a damaged file)", (unsigned long)line_no); return VP_ECORRUPT; }
        if (k < 0) { vp_seterr(err, errlen, "line %lu: header line too long", (unsigned long)line_no); return VP_ECORRUPT; }
        if (line_no == 1) {
            if (strcmp(line, "ply")) { vp_seterr(err, errlen, "line 1: not a PLY file (expected 'ply')"); return VP_ECORRUPT; }
            continue;
        }
        for (s = line; *s && nw < 8;) {
            while (*s == ' ' || *s == '\t') *s++ = 0;
            if (!*s) break;
            words[nw++] = s;
            while (*s && *s != ' ' && *s != '\t') s++;
        }
        if (nw == 0) continue;
        if (!strcmp(words[0], "comment") || !strcmp(words[0], "obj_info")) continue;
        if (!strcmp(words[0], "end_header")) { have_end = 1; break; }
        if (!strcmp(words[0], "format")) {
            if (nw != 3 || strcmp(words[2], "1.0")) { vp_seterr(err, errlen, "line %lu: bad format line", (unsigned long)line_no); return VP_ECORRUPT; }
            if (!strcmp(words[1], "ascii")) format = 0;
            else if (!strcmp(words[1], "binary_little_endian")) format = 1;
            else if (!strcmp(words[1], "binary_big_endian")) format = 2;
            else { vp_seterr(err, errlen, "line %lu: unknown format '%.40s'", (unsigned long)line_no, words[1]); return VP_ECORRUPT; }
            continue;
        }
        if (!strcmp(words[0], "element")) {
            long long cnt;
            if (nw != 3 || vp_parse_long(words[2], &cnt) < 0 || cnt < 0) {
                vp_seterr(err, errlen, "line %lu: bad element line", (unsigned long)line_no); return VP_ECORRUPT;
            }
            if (nel == VP_PLY_MAX_ELEM) { vp_seterr(err, errlen, "line %lu: too many elements", (unsigned long)line_no); return VP_ECORRUPT; }
            if (strlen(words[1]) >= sizeof el[0].name) { vp_seterr(err, errlen, "line %lu: element name too long", (unsigned long)line_no); return VP_ECORRUPT; }
            strcpy(el[nel].name, words[1]);
            el[nel].count = (unsigned long long)cnt;
            el[nel].nprop = 0;
            nel++;
            continue;
        }
        if (!strcmp(words[0], "property")) {
            vp_ply_prop_t *pr;
            if (nel == 0) { vp_seterr(err, errlen, "line %lu: property before any element", (unsigned long)line_no); return VP_ECORRUPT; }
            if (el[nel - 1].nprop == VP_PLY_MAX_PROP) { vp_seterr(err, errlen, "line %lu: too many properties", (unsigned long)line_no); return VP_ECORRUPT; }
            pr = &el[nel - 1].prop[el[nel - 1].nprop];
            if (nw == 5 && !strcmp(words[1], "list")) {
                pr->count_type = vp_ply_type_of(words[2]);
                pr->type = vp_ply_type_of(words[3]);
                if (!vp_ply_is_int(pr->count_type) || pr->type == VP_PT_NONE) {
                    vp_seterr(err, errlen, "line %lu: bad list types", (unsigned long)line_no); return VP_ECORRUPT;
                }
                s = words[4];
            } else if (nw == 3) {
                pr->count_type = VP_PT_NONE;
                pr->type = vp_ply_type_of(words[1]);
                if (pr->type == VP_PT_NONE) { vp_seterr(err, errlen, "line %lu: unknown type '%.20s'", (unsigned long)line_no, words[1]); return VP_ECORRUPT; }
                s = words[2];
            } else { vp_seterr(err, errlen, "line %lu: bad property line", (unsigned long)line_no); return VP_ECORRUPT; }
            if (strlen(s) >= sizeof pr->name) { vp_seterr(err, errlen, "line %lu: property name too long", (unsigned long)line_no); return VP_ECORRUPT; }
            strcpy(pr->name, s);
            el[nel - 1].nprop++;
            continue;
        }
        vp_seterr(err, errlen, "line %lu: unknown header keyword '%.20s'", (unsigned long)line_no, words[0]);
        return VP_ECORRUPT;
    }
    if (!have_end || format < 0) { vp_seterr(err, errlen, "line %lu: no format line in header", (unsigned long)line_no); return VP_ECORRUPT; }

    /* Counts against the remaining bytes: each instance needs its fixed-size part. */
    for (e = 0; e < nel; e++) {
        unsigned long long minsize = 0;
        int k;
        for (k = 0; k < el[e].nprop; k++)
            minsize += vp_ply_size(el[e].prop[k].count_type != VP_PT_NONE ? el[e].prop[k].count_type : el[e].prop[k].type);
        if (format == 0) minsize = 2ULL * (unsigned long long)el[e].nprop;   /* a digit and a separator */
        if (el[e].count && el[e].nprop == 0) {
            vp_seterr(err, errlen, "header: element '%s' has instances but no properties", el[e].name); return VP_ECORRUPT;
        }
        if (el[e].count && el[e].count > (len - pos + 1) / (minsize ? minsize : 1)) {
            vp_seterr(err, errlen, "header: element '%s' count %llu impossible for a file of %lu bytes",
                      el[e].name, el[e].count, (unsigned long)len);
            return VP_ECORRUPT;
        }
    }

    if (format == 0) {
        /* an ASCII body is text: a NUL byte would end a number early */
        unsigned long nul_line;
        if (vp_file_find_nul(p + pos, len - pos, &nul_line)) {
            vp_seterr(err, errlen, "line %lu: a NUL byte inside the text (a damaged or binary file)",
                      (unsigned long)line_no + nul_line);
            return VP_ECORRUPT;
        }
    }
    *pos_io = pos;
    *line_io = line_no;
    *nel_out = nel;
    *format_out = format;
    return VP_OK;
}

/* The PLY body: each element's instances read (in.ascii: as text), the vertex element's x, y, z
 * into *xyz (malloc'ed, *nv of them), the face element's polygons fanned into triangles (tl).
 * VP_OK, or an error (err) with *xyz still to be freed by the caller. */
static int vp_ply_body(vp_ply_in_t *in, const vp_ply_elem_t *el, int nel, size_t len, double **xyz_out, size_t *nv_out,
                       vp_trilist_t *tl, char *err, size_t errlen)
{
    double *xyz = NULL;
    size_t nv = 0;
    char where[64];
    int e, st = VP_ECORRUPT;
    unsigned long long i;
    for (e = 0; e < nel; e++) {
        int is_vertex = !strcmp(el[e].name, "vertex"), is_face = !strcmp(el[e].name, "face");
        int ix = -1, iy = -1, iz = -1, iface = -1, k;
        if (is_vertex) {
            if (xyz) { vp_seterr(err, errlen, "header: two vertex elements"); goto out; }
            for (k = 0; k < el[e].nprop; k++) {
                if (el[e].prop[k].count_type != VP_PT_NONE) continue;
                if (!strcmp(el[e].prop[k].name, "x")) ix = k;
                else if (!strcmp(el[e].prop[k].name, "y")) iy = k;
                else if (!strcmp(el[e].prop[k].name, "z")) iz = k;
            }
            if (ix < 0 || iy < 0 || iz < 0) { vp_seterr(err, errlen, "header: vertex element lacks x, y or z"); goto out; }
            if (el[e].count > UINT32_MAX) { vp_seterr(err, errlen, "header: too many vertices"); goto out; }
            nv = (size_t)el[e].count;
            xyz = malloc(nv ? nv * 3 * sizeof(double) : 1);
            if (!xyz) { st = VP_ENOMEM; goto out; }
        }
        if (is_face) {
            for (k = 0; k < el[e].nprop; k++)
                if (el[e].prop[k].count_type != VP_PT_NONE &&
                    (!strcmp(el[e].prop[k].name, "vertex_indices") || !strcmp(el[e].prop[k].name, "vertex_index")))
                    iface = k;
            if (iface < 0) { vp_seterr(err, errlen, "header: face element lacks a vertex_indices list"); goto out; }
            if (!vp_ply_is_int(el[e].prop[iface].type)) { vp_seterr(err, errlen, "header: face indices must be integers"); goto out; }
            if (!xyz && el[e].count) { vp_seterr(err, errlen, "header: face element before vertex element"); goto out; }
        }
        for (i = 0; i < el[e].count; i++) {
            for (k = 0; k < el[e].nprop; k++) {
                const vp_ply_prop_t *pr = &el[e].prop[k];
                double v;
                if ((st = vp_ply_read(in, pr->count_type != VP_PT_NONE ? pr->count_type : pr->type, &v, err, errlen)) < 0) goto out;
                st = VP_ECORRUPT;
                if (pr->count_type == VP_PT_NONE) {
                    if (is_vertex) {
                        if (k == ix) xyz[3 * i] = v;
                        else if (k == iy) xyz[3 * i + 1] = v;
                        else if (k == iz) xyz[3 * i + 2] = v;
                    }
                } else {
                    double n = v, first = -1, prev = -1;
                    unsigned long long j, cnt;
                    int use = is_face && k == iface;
                    if (n < 0 || n > (double)(len - (in->ascii ? in->lx.pos : in->pos))) {
                        vp_seterr(err, errlen, "%s: list of %g items is impossible", vp_ply_where(in, where, sizeof where), n);
                        goto out;
                    }
                    if (use && n < 3) {
                        vp_seterr(err, errlen, "%s: face %llu has %g corners", vp_ply_where(in, where, sizeof where), i, n);
                        goto out;
                    }
                    cnt = (unsigned long long)n;
                    for (j = 0; j < cnt; j++) {
                        double idx;
                        if ((st = vp_ply_read(in, pr->type, &idx, err, errlen)) < 0) goto out;
                        st = VP_ECORRUPT;
                        if (!use) continue;
                        if (idx < 0 || idx >= (double)nv) {
                            vp_seterr(err, errlen, "%s: vertex index %g out of range [0,%lu)",
                                      vp_ply_where(in, where, sizeof where), idx, (unsigned long)nv);
                            goto out;
                        }
                        if (j == 0) first = idx;
                        else if (j >= 2 && (st = vp_trilist_add(tl, (uint32_t)first, (uint32_t)prev, (uint32_t)idx)) < 0) goto out;
                        st = VP_ECORRUPT;
                        prev = idx;
                    }
                }
            }
        }
    }
    st = VP_OK;
out:
    *xyz_out = xyz;
    *nv_out = nv;
    return st;
}

int vp_mesh_read_ply_buf(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen)
{
    const unsigned char *p = buf;
    vp_ply_elem_t *el = NULL;
    int nel = 0, format = -1, st;
    size_t pos = 0, line_no = 0;
    double *xyz = NULL;
    size_t nv = 0;
    vp_trilist_t tl = { NULL, 0, 0 };
    vp_ply_in_t in;

    if (!buf || !out) return VP_EINVAL;
    el = calloc(VP_PLY_MAX_ELEM, sizeof *el);
    if (!el) return VP_ENOMEM;
    st = vp_ply_header(p, len, &pos, &line_no, el, &nel, &format, err, errlen);
    if (st != VP_OK) goto fail;
    in.p = p; in.len = len; in.pos = pos;
    in.ascii = format == 0; in.big_endian = format == 2;
    in.lx.p = (const char *)p; in.lx.len = len; in.lx.pos = pos; in.lx.line = line_no + 1; in.lx.hash_comments = 0;
    st = vp_ply_body(&in, el, nel, len, &xyz, &nv, &tl, err, errlen);
    if (st != VP_OK) goto fail;
    st = VP_ECORRUPT;
    if (!xyz) { vp_seterr(err, errlen, "header: no vertex element"); goto fail; }
    free(el);
    vp_mesh_take(out, xyz, nv, &tl);
    return VP_OK;
fail:
    free(el); free(xyz); free(tl.t);
    return st;
}

int vp_mesh_read_buf(const void *buf, size_t len, vp_mesh_t *out, char *err, size_t errlen)
{
    const char *c = buf;
    if (!buf) return VP_EINVAL;
    if (len >= 3 && !memcmp(c, "ply", 3)) return vp_mesh_read_ply_buf(buf, len, out, err, errlen);
    return vp_mesh_read_off_buf(buf, len, out, err, errlen);
}

/* The first bytes of a mesh file: "ply", or "OFF" (COFF, NOFF, CNOFF) after blanks and comments. */
static const char *vp_mesh_head(const unsigned char *p, size_t n)
{
    static const char *const kw[] = { "OFF", "COFF", "NOFF", "CNOFF" };
    size_t i = 0, k, t;
    if (n >= 3 && !memcmp(p, "ply", 3)) return NULL;
    while (i < n) {
        if (p[i] == '#') { while (i < n && p[i] != '\n') i++; }
        else if (vp_is_space((char)p[i])) i++;
        else break;
    }
    if (i == n) return NULL;   /* only blanks and comments so far: the reader decides */
    for (t = i; t < n && p[t] && !vp_is_space((char)p[t]) && p[t] != '#'; t++) {}
    if (t == n && n >= VP_FILE_HEAD) return NULL;   /* cut by the end of the head */
    for (k = 0; k < sizeof kw / sizeof kw[0]; k++)
        if (t - i == strlen(kw[k]) && !memcmp(p + i, kw[k], t - i)) return NULL;
    return "it starts with neither 'ply' nor 'OFF'";
}

int vp_mesh_read_file(const char *path, vp_mesh_t *out, char *err, size_t errlen)
{
    unsigned char *data = NULL;
    size_t n = 0;
    char sub[400];
    int st;
    st = vp_file_read(path, VP_MESH_MAX_FILE, "mesh file", vp_mesh_head, &data, &n, sub, sizeof sub);
    if (st < 0) { vp_seterr(err, errlen, "%s", sub); return st; }
    st = vp_mesh_read_buf(data, n, out, err, errlen);
    if (st < 0 && err && errlen) {
        char tmp[512];
        snprintf(tmp, sizeof tmp, "%s: %s", path, err);
        snprintf(err, errlen, "%s", tmp);
    }
    free(data);
    return st;
}
