/* vp_logfmt — see vp_logfmt.h; the byte layout is in doc/session-log.md. */
#include <string.h>
#include "vp_logfmt.h"
#include "vp_vec3.h"

const unsigned char vp_logfmt_magic[VP_LOGFMT_MAGIC_LEN] = { 'V', 'P', 'L', 'O', 'G', '\r', '\n', 0x1a };

/* header: magic 8, version 2, flags 2, length 4, then fixed fields up to the interior points */
#define HDR_FIXED 188u
#define REC_FRAME 16u   /* length 4, sequence 4, type 2, flags 2 ... CRC 4 */

/* ---------- CRC-32, four bits at a time from a constant table ---------- */

static const uint32_t crc_nibble[16] = {
    0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
    0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
    0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu
};

uint32_t vp_logfmt_crc32(uint32_t crc, const void *data, size_t len)
{
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    crc = ~crc;
    for (i = 0; i < len; i++) {
        crc ^= p[i];
        crc = (crc >> 4) ^ crc_nibble[crc & 15u];
        crc = (crc >> 4) ^ crc_nibble[crc & 15u];
    }
    return ~crc;
}

/* ---------- little-endian fields ---------- */

static void put16(unsigned char *p, uint32_t v) { p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8); }
static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24);
}
static void put64(unsigned char *p, uint64_t v) { put32(p, (uint32_t)v); put32(p + 4, (uint32_t)(v >> 32)); }
static uint64_t dbits(double d) { uint64_t u; memcpy(&u, &d, 8); return u; }
static void putd(unsigned char *p, double d) { put64(p, dbits(d)); }
static void putd3(unsigned char *p, const double *v) { putd(p, v[0]); putd(p + 8, v[1]); putd(p + 16, v[2]); }

static uint32_t get16(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8; }
static uint32_t get32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t get64(const unsigned char *p) { return (uint64_t)get32(p) | (uint64_t)get32(p + 4) << 32; }
static double getd(const unsigned char *p) { uint64_t u = get64(p); double d; memcpy(&d, &u, 8); return d; }
static void getd3(const unsigned char *p, double *v) { v[0] = getd(p); v[1] = getd(p + 8); v[2] = getd(p + 16); }




static size_t bounded_len(const char *s, size_t max)
{
    size_t n = 0;
    if (!s) return 0;
    while (n < max && s[n]) n++;
    return n;
}

/* after the note, version 2: the sizing field's two numbers (size_rel, min_size); version 3:
 * those and the distance bound; a version 1 header has none. The oldest version that holds
 * the configuration is written. */
static int sizing(const vp_planner_config_t *c) { return c->size_rel != 0.0 || c->min_size != 0.0; }
#ifndef VP_CORE_MCU
/* version 4: those three, a line laser's rays per frame and the proofs' life (two uint32);
 * version 5: those and the tubes' feature size and margin (two doubles); version 6: those, the
 * axes' times per unit (five doubles) and the pan's travel (two); version 7: the same bytes, and
 * the planner flag VP_PLAN_FAR_READS may be set (only there); version 8: the same bytes, and the
 * flag VP_PLAN_SMALL_FIRST is set (only there) */
static int timed(const vp_planner_config_t *c)
{
    int k;
    for (k = 0; k < VP_PLANNER_AXES; k++)
        if (c->axis_time[k] != 0.0) return 1;
    return c->pan_travel[0] != 0.0 || c->pan_travel[1] != 0.0;
}
static uint32_t header_version(const vp_planner_config_t *c)
{
    return (c->flags & VP_PLAN_SMALL_FIRST) ? 8u : (c->flags & VP_PLAN_FAR_READS) ? 7u : timed(c) ? 6u : c->min_feature != 0.0 || c->feature_margin != 0.0 ? 5u
           : c->line_rays != 0u || c->proof_life != 0u ? 4u : c->max_distance != 0.0 ? 3u : sizing(c) ? 2u : 1u;
}
static uint32_t ext_bytes(uint32_t version)
{
    return version >= 6u ? 104u : version == 5u ? 48u : version == 4u ? 32u : version == 3u ? 24u : version == 2u ? 16u : 0u;
}
#define PROBE_LIKE(t) ((t) == VP_LOGFMT_PROBE || (t) == VP_LOGFMT_RAY)
#else
static uint32_t header_version(const vp_planner_config_t *c)
{
    return c->max_distance != 0.0 ? 3u : sizing(c) ? 2u : 1u;
}
static uint32_t ext_bytes(uint32_t version) { return version >= 3u ? 24u : version == 2u ? 16u : 0u; }
#define PROBE_LIKE(t) ((t) == VP_LOGFMT_PROBE)
#endif

/* ---------- header ---------- */

void vp_logfmt_header_init(vp_logfmt_header_t *h, const vp_planner_config_t *cfg, uint64_t arena_bytes,
                        uint32_t units, const char *board, const char *note)
{
    size_t n;
    memset(h, 0, sizeof *h);
    h->version = cfg ? header_version(cfg) : 1u; /* as encoded */
    h->units = units;
    if (cfg) h->cfg = *cfg;
    h->arena_bytes = arena_bytes;
    n = bounded_len(board, VP_LOGFMT_BOARD_MAX);
    memcpy(h->board, board ? board : "", n);
    h->board[n] = 0;
    n = bounded_len(note, VP_LOGFMT_NOTE_MAX);
    memcpy(h->note, note ? note : "", n);
    h->note[n] = 0;
}

/* The configuration fields a header's reader takes, shared by the encoder and the decoder (the
 * fields a version does not hold are zero): a known Omega, 1 .. VP_PLANNER_MAX_SEEDS interior
 * points, and every number the planner reads finite. */
static int cfg_ok(const vp_planner_config_t *c)
{
    uint32_t i;
    if (c->ninterior < 1 || c->ninterior > VP_PLANNER_MAX_SEEDS) return 0;
    if (c->omega_kind != VP_OMEGA_BOX && c->omega_kind != VP_OMEGA_BALL) return 0;
    if (!vp_finite(c->eps) || !vp_finite3(c->omega_lo) || !vp_finite3(c->omega_hi) ||
        !vp_finite3(c->omega_center) || !vp_finite(c->omega_radius) || !vp_finite3(c->start) ||
        !vp_finite(c->max_range) || !vp_finite(c->noise_tol) || !vp_finite(c->clearance) ||
        !vp_finite(c->min_angle) || !vp_finite(c->size_rel) || !vp_finite(c->min_size) ||
        !vp_finite(c->max_distance))
        return 0;
    for (i = 0; i < c->ninterior; i++)
        if (!vp_finite3(c->interior[i])) return 0;
#ifndef VP_CORE_MCU
    if (c->line_rays > VP_PLANNER_MAX_LINE_RAYS || !vp_finite(c->min_feature) || !vp_finite(c->feature_margin) ||
        !vp_finite(c->pan_travel[0]) || !vp_finite(c->pan_travel[1]))
        return 0;
    for (i = 0; i < VP_PLANNER_AXES; i++)
        if (!vp_finite(c->axis_time[i])) return 0;
#endif
    return 1;
}

int vp_logfmt_header_size(const vp_logfmt_header_t *h)
{
    size_t bl, nl;
    if (!h || !cfg_ok(&h->cfg)) return VP_EINVAL; /* never a header the reader refuses */
    bl = bounded_len(h->board, VP_LOGFMT_BOARD_MAX + 1);
    nl = bounded_len(h->note, VP_LOGFMT_NOTE_MAX + 1);
    if (bl > VP_LOGFMT_BOARD_MAX || nl > VP_LOGFMT_NOTE_MAX) return VP_EINVAL;
    return (int)(HDR_FIXED + 24u * h->cfg.ninterior + 2u + bl + 2u + nl + ext_bytes(header_version(&h->cfg)) + 4u);
}

int vp_logfmt_header_encode(const vp_logfmt_header_t *h, void *buf, size_t cap)
{
    unsigned char *p = (unsigned char *)buf, *q;
    const vp_planner_config_t *c;
    int size = vp_logfmt_header_size(h);
    size_t bl, nl;
    uint32_t i;
    if (size < 0) return size;
    if (!buf || cap < (size_t)size) return VP_ENOMEM;
    c = &h->cfg;
    memcpy(p, vp_logfmt_magic, VP_LOGFMT_MAGIC_LEN);
    put16(p + 8, header_version(c));
    put16(p + 10, 0);
    put32(p + 12, (uint32_t)size);
    put32(p + 16, h->units);
    put32(p + 20, (uint32_t)c->omega_kind);
    putd(p + 24, c->eps);
    putd3(p + 32, c->omega_lo);
    putd3(p + 56, c->omega_hi);
    putd3(p + 80, c->omega_center);
    putd(p + 104, c->omega_radius);
    putd3(p + 112, c->start);
    putd(p + 136, c->max_range);
    putd(p + 144, c->noise_tol);
    putd(p + 152, c->clearance);
    putd(p + 160, c->min_angle);
    put32(p + 168, c->confirm_misses);
    put32(p + 172, c->flags);
    put64(p + 176, h->arena_bytes);
    put32(p + 184, c->ninterior);
    q = p + HDR_FIXED;
    for (i = 0; i < c->ninterior; i++, q += 24) putd3(q, c->interior[i]);
    bl = bounded_len(h->board, VP_LOGFMT_BOARD_MAX);
    put16(q, (uint32_t)bl);
    memcpy(q + 2, h->board, bl);
    q += 2 + bl;
    nl = bounded_len(h->note, VP_LOGFMT_NOTE_MAX);
    put16(q, (uint32_t)nl);
    memcpy(q + 2, h->note, nl);
    q += 2 + nl;
    if (header_version(c) >= 2u) {
        putd(q, c->size_rel);
        putd(q + 8, c->min_size);
        if (header_version(c) >= 3u) putd(q + 16, c->max_distance);
#ifndef VP_CORE_MCU
        if (header_version(c) >= 4u) {
            put32(q + 24, c->line_rays);
            put32(q + 28, c->proof_life);
        }
        if (header_version(c) >= 5u) {
            putd(q + 32, c->min_feature);
            putd(q + 40, c->feature_margin);
        }
        if (header_version(c) >= 6u) {
            for (i = 0; i < VP_PLANNER_AXES; i++) putd(q + 48 + 8 * i, c->axis_time[i]);
            putd(q + 88, c->pan_travel[0]);
            putd(q + 96, c->pan_travel[1]);
        }
#endif
        q += ext_bytes(header_version(c));
    }
    put32(q, vp_logfmt_crc32(0, p, (size_t)(q - p)));
    return size;
}

/* Decodes a complete header of n bytes (length and CRC already checked). */
static int header_decode(const unsigned char *p, uint32_t n, vp_logfmt_header_t *h)
{
    vp_planner_config_t *c = &h->cfg;
    const unsigned char *q, *end = p + n - 4;
    uint32_t i, bl, nl;
    memset(h, 0, sizeof *h);
    h->version = get16(p + 8);
    h->units = get32(p + 16);
    c->omega_kind = (int)get32(p + 20);
    c->eps = getd(p + 24);
    getd3(p + 32, c->omega_lo);
    getd3(p + 56, c->omega_hi);
    getd3(p + 80, c->omega_center);
    c->omega_radius = getd(p + 104);
    getd3(p + 112, c->start);
    c->max_range = getd(p + 136);
    c->noise_tol = getd(p + 144);
    c->clearance = getd(p + 152);
    c->min_angle = getd(p + 160);
    c->confirm_misses = get32(p + 168);
    c->flags = get32(p + 172);
    h->arena_bytes = get64(p + 176);
    c->ninterior = get32(p + 184);
    if (get16(p + 10) != 0) return 0;
    if (c->ninterior < 1 || c->ninterior > VP_PLANNER_MAX_SEEDS) return 0; /* before reading them */
    q = p + HDR_FIXED;
    if ((size_t)(end - q) < 24u * c->ninterior + 2u) return 0;
    for (i = 0; i < c->ninterior; i++, q += 24) getd3(q, c->interior[i]);
    bl = get16(q);
    q += 2;
    if (bl > VP_LOGFMT_BOARD_MAX || (size_t)(end - q) < bl + 2u) return 0;
    memcpy(h->board, q, bl);
    h->board[bl] = 0;
    q += bl;
    nl = get16(q);
    q += 2;
    if (h->version < 1u || h->version > VP_LOGFMT_VERSION) return 0;
    if (nl > VP_LOGFMT_NOTE_MAX || (size_t)(end - q) != nl + ext_bytes(h->version)) return 0;
    memcpy(h->note, q, nl);
    h->note[nl] = 0;
    if (h->version >= 2u) {
        c->size_rel = getd(q + nl);
        c->min_size = getd(q + nl + 8);
        if (h->version >= 3u) c->max_distance = getd(q + nl + 16);
#ifndef VP_CORE_MCU
        if (h->version >= 4u) {
            c->line_rays = get32(q + nl + 24);
            c->proof_life = get32(q + nl + 28);
        }
        if (h->version >= 5u) {
            c->min_feature = getd(q + nl + 32);
            c->feature_margin = getd(q + nl + 40);
        }
        if (h->version >= 6u) {
            for (i = 0; i < VP_PLANNER_AXES; i++) c->axis_time[i] = getd(q + nl + 48 + 8 * i);
            c->pan_travel[0] = getd(q + nl + 88);
            c->pan_travel[1] = getd(q + nl + 96);
        }
#endif
    }
    /* what the header holds names its version (a version 1 with far reads is damaged too) */
    if (header_version(c) != h->version || !cfg_ok(c)) return 0;
    /* embedded NULs are not text */
    return bounded_len(h->board, bl) == bl && bounded_len(h->note, nl) == nl;
}

/* The length a header's first 16 bytes give, 0 when impossible. The length and the CRC at its
 * end keep their places in every version: a version above ours is believed only once the CRC
 * says the header is intact (a damaged version byte is a damaged header, not a newer format). */
static uint32_t header_length(const unsigned char *p)
{
    uint32_t ver = get16(p + 8), n = get32(p + 12);
    return ver == 0 || n < HDR_FIXED + 24u + 8u || n > VP_LOGFMT_MAX_HEADER ? 0 : n;
}

/* A whole header of n bytes (n from header_length): VP_LOGFMT_R_OK with *h, or the reason. */
static int header_whole(const unsigned char *p, uint32_t n, vp_logfmt_header_t *h)
{
    if (vp_logfmt_crc32(0, p, n - 4) != get32(p + n - 4)) return VP_LOGFMT_R_HEADER_CRC;
    if (get16(p + 8) > VP_LOGFMT_VERSION) return VP_LOGFMT_R_VERSION;
    return header_decode(p, n, h) ? VP_LOGFMT_R_OK : VP_LOGFMT_R_HEADER;
}

int vp_logfmt_header_decode(const void *buf, size_t len, vp_logfmt_header_t *h, int *reason)
{
    const unsigned char *p = (const unsigned char *)buf;
    uint32_t n = 0;
    int why;
    if (!buf || !h) return VP_EINVAL;
    if (len < 16) why = len >= VP_LOGFMT_MAGIC_LEN && memcmp(p, vp_logfmt_magic, VP_LOGFMT_MAGIC_LEN) != 0
                            ? VP_LOGFMT_R_MAGIC : VP_LOGFMT_R_TRUNCATED;
    else if (memcmp(p, vp_logfmt_magic, VP_LOGFMT_MAGIC_LEN) != 0) why = VP_LOGFMT_R_MAGIC;
    else if ((n = header_length(p)) == 0) why = VP_LOGFMT_R_HEADER;
    else if (len < n) why = VP_LOGFMT_R_TRUNCATED;
    else why = header_whole(p, n, h);
    if (reason) *reason = why;
    return why == VP_LOGFMT_R_OK ? (int)n : why == VP_LOGFMT_R_VERSION ? VP_EVERSION : VP_ECORRUPT;
}

/* ---------- records ---------- */

static void record_clear(vp_logfmt_record_t *r, uint32_t seq, int type)
{
    memset(r, 0, sizeof *r);
    r->seq = seq;
    r->type = type;
}

void vp_logfmt_record_probe(vp_logfmt_record_t *r, uint32_t seq, const vp_cmd_t *cmd,
                         const vp_probe_result_t *res, double raw)
{
#ifndef VP_CORE_MCU
    record_clear(r, seq, cmd->kind == VP_CMD_RAY ? VP_LOGFMT_RAY : VP_LOGFMT_PROBE);
#else
    record_clear(r, seq, VP_LOGFMT_PROBE);
#endif
    memcpy(r->origin, cmd->from, sizeof r->origin);
    memcpy(r->dir, cmd->dir, sizeof r->dir);
    r->range = cmd->range;
    r->hit = res->hit == VP_PROBE_TOO_CLOSE ? VP_PROBE_TOO_CLOSE : res->hit ? 1 : 0;
    r->dist = res->dist;
    r->raw = raw;
}

void vp_logfmt_record_move(vp_logfmt_record_t *r, uint32_t seq, const vp_cmd_t *cmd)
{
    record_clear(r, seq, VP_LOGFMT_MOVE);
    memcpy(r->target, cmd->to, sizeof r->target);
}

void vp_logfmt_record_event(vp_logfmt_record_t *r, uint32_t seq, uint32_t event, int32_t code,
                         const char *text)
{
    size_t n = bounded_len(text, VP_LOGFMT_TEXT_MAX);
    record_clear(r, seq, VP_LOGFMT_EVENT);
    r->event = event;
    r->code = code;
    memcpy(r->text, text ? text : "", n);
    r->text[n] = 0;
    r->text_len = (uint32_t)n;
}

int vp_logfmt_record_size(const vp_logfmt_record_t *r)
{
    if (!r) return VP_EINVAL;
    switch (r->type) {
    case VP_LOGFMT_PROBE: return VP_LOGFMT_PROBE_SIZE;
#ifndef VP_CORE_MCU
    case VP_LOGFMT_RAY: return VP_LOGFMT_PROBE_SIZE;
#endif
    case VP_LOGFMT_MOVE: return VP_LOGFMT_MOVE_SIZE;
    case VP_LOGFMT_EVENT:
        if (r->text_len > VP_LOGFMT_TEXT_MAX || bounded_len(r->text, r->text_len) != r->text_len)
            return VP_EINVAL;
        return (int)(VP_LOGFMT_EVENT_BASE + r->text_len);
    default: return VP_EINVAL;
    }
}

/* A PROBE's, RAY's or MOVE's fields as the reader takes them: hit 0..2, every number finite */
static int fields_ok(const vp_logfmt_record_t *r)
{
    if (PROBE_LIKE(r->type))
        return r->hit >= 0 && r->hit <= 2 && vp_finite3(r->origin) && vp_finite3(r->dir) && vp_finite(r->range) &&
               vp_finite(r->dist);
    return r->type != VP_LOGFMT_MOVE || vp_finite3(r->target);
}

int vp_logfmt_record_encode(const vp_logfmt_record_t *r, void *buf, size_t cap)
{
    unsigned char *p = (unsigned char *)buf;
    int size = vp_logfmt_record_size(r), k;
    if (size < 0) return size;
    if (!fields_ok(r)) return VP_EINVAL; /* never a record the reader refuses */
    if (!buf || cap < (size_t)size) return VP_ENOMEM;
    put32(p, (uint32_t)size);
    put32(p + 4, r->seq);
    put16(p + 8, (uint32_t)r->type);
    put16(p + 10, 0);
    if (PROBE_LIKE(r->type)) {
        putd3(p + 12, r->origin);
        putd3(p + 36, r->dir);
        putd(p + 60, r->range);
        putd(p + 68, r->dist);
        putd(p + 76, r->raw);
        put32(p + 84, (uint32_t)r->hit);
    } else if (r->type == VP_LOGFMT_MOVE) {
        putd3(p + 12, r->target);
    } else {
        put32(p + 12, r->event);
        put32(p + 16, (uint32_t)r->code);
        for (k = 0; k < 4; k++) putd(p + 20 + 8 * k, r->value[k]);
        put16(p + 52, r->text_len);
        memcpy(p + 54, r->text, r->text_len);
    }
    put32(p + size - 4, vp_logfmt_crc32(0, p, (size_t)size - 4));
    return size;
}

/* Decodes a complete record (length and CRC checked): a VP_LOGFMT_R_* reason. */
static int record_decode(const unsigned char *p, uint32_t n, vp_logfmt_record_t *r)
{
    uint32_t type = get16(p + 8), k;
    record_clear(r, get32(p + 4), (int)type);
    if (PROBE_LIKE(type)) {
        uint32_t hit;
        if (n != VP_LOGFMT_PROBE_SIZE) return VP_LOGFMT_R_LENGTH;
        getd3(p + 12, r->origin);
        getd3(p + 36, r->dir);
        r->range = getd(p + 60);
        r->dist = getd(p + 68);
        r->raw = getd(p + 76);
        hit = get32(p + 84);
        if (hit > 2) return VP_LOGFMT_R_FIELD;
        r->hit = (int)hit;
        if (!fields_ok(r)) return VP_LOGFMT_R_FIELD;
    } else if (type == VP_LOGFMT_MOVE) {
        if (n != VP_LOGFMT_MOVE_SIZE) return VP_LOGFMT_R_LENGTH;
        getd3(p + 12, r->target);
        if (!fields_ok(r)) return VP_LOGFMT_R_FIELD;
    } else if (type == VP_LOGFMT_EVENT) {
        if (n < VP_LOGFMT_EVENT_BASE) return VP_LOGFMT_R_LENGTH;
        r->event = get32(p + 12);
        r->code = (int32_t)get32(p + 16);
        for (k = 0; k < 4; k++) r->value[k] = getd(p + 20 + 8 * k);
        r->text_len = get16(p + 52);
        if (r->text_len > VP_LOGFMT_TEXT_MAX || n != VP_LOGFMT_EVENT_BASE + r->text_len) return VP_LOGFMT_R_LENGTH;
        memcpy(r->text, p + 54, r->text_len);
        r->text[r->text_len] = 0;
        if (bounded_len(r->text, r->text_len) != r->text_len) return VP_LOGFMT_R_FIELD;
    } else {
        return VP_LOGFMT_R_TYPE;
    }
    if (get16(p + 10) != 0) return VP_LOGFMT_R_FIELD;
    return VP_LOGFMT_R_OK;
}

int vp_logfmt_record_decode(const void *buf, size_t len, vp_logfmt_record_t *rec, int *reason)
{
    const unsigned char *p = (const unsigned char *)buf;
    uint32_t n;
    int why = VP_LOGFMT_R_OK;
    if (!buf || !rec) return VP_EINVAL;
    if (len < 4) why = VP_LOGFMT_R_TRUNCATED;
    else if ((n = get32(p)) < REC_FRAME || n > VP_LOGFMT_MAX_RECORD) why = VP_LOGFMT_R_LENGTH;
    else if (len < n) why = VP_LOGFMT_R_TRUNCATED;
    else if (vp_logfmt_crc32(0, p, n - 4) != get32(p + n - 4)) why = VP_LOGFMT_R_CRC;
    else why = record_decode(p, n, rec);
    if (reason) *reason = why;
    return why == VP_LOGFMT_R_OK ? (int)n : VP_ECORRUPT;
}

/* ---------- reader ---------- */

#ifndef VP_CORE_MCU /* texts for people: host only (vp_status.h) */
const char *vp_logfmt_reason_text(int reason)
{
    switch (reason) {
    case VP_LOGFMT_R_OK: return "ok";
    case VP_LOGFMT_R_TRUNCATED: return "truncated (the data ends inside it: a torn write)";
    case VP_LOGFMT_R_MAGIC: return "not a voroprobe session log (bad magic)";
    case VP_LOGFMT_R_VERSION: return "written by a newer log format version";
    case VP_LOGFMT_R_HEADER: return "invalid header";
    case VP_LOGFMT_R_HEADER_CRC: return "header CRC mismatch";
    case VP_LOGFMT_R_LENGTH: return "impossible record length";
    case VP_LOGFMT_R_CRC: return "CRC mismatch";
    case VP_LOGFMT_R_SEQUENCE: return "wrong sequence number";
    case VP_LOGFMT_R_TYPE: return "unknown record type";
    case VP_LOGFMT_R_FIELD: return "invalid field value";
    default: return "unknown reason";
    }
}
#endif

#ifndef VP_CORE_MCU /* the incremental reader: host only (vp_status.h) */
void vp_logfmt_reader_init(vp_logfmt_reader_t *r)
{
    memset(r, 0, sizeof *r);
    r->status = VP_OK;
    r->need = VP_LOGFMT_MAGIC_LEN;   /* the magic first, then version, flags and length */
}

static int reader_fail(vp_logfmt_reader_t *r, int status, int reason)
{
    r->status = status;
    r->reason = reason;
    r->bad_in_header = !r->have_header;
    r->bad_record = r->records;
    r->bad_offset = r->offset;
    return status;
}

/* The first `need` bytes of the current item are in buf: check them, maybe ask for more. */
static int reader_step(vp_logfmt_reader_t *r, vp_logfmt_record_t *rec)
{
    const unsigned char *p = r->buf;
    uint32_t n;
    int why;
    if (!r->have_header) {
        if (r->have == VP_LOGFMT_MAGIC_LEN) {
            if (memcmp(p, vp_logfmt_magic, VP_LOGFMT_MAGIC_LEN) != 0) return reader_fail(r, VP_ECORRUPT, VP_LOGFMT_R_MAGIC);
            r->need = 16;
            return VP_LOGFMT_NEED_MORE;
        }
        if (r->have == 16) {
            n = header_length(p);
            if (n == 0) return reader_fail(r, VP_ECORRUPT, VP_LOGFMT_R_HEADER);
            r->need = n;
            return VP_LOGFMT_NEED_MORE;
        }
        n = r->need;
        why = header_whole(p, n, &r->header);
        if (why != VP_LOGFMT_R_OK) return reader_fail(r, why == VP_LOGFMT_R_VERSION ? VP_EVERSION : VP_ECORRUPT, why);
        r->have_header = 1;
        r->offset += n;
        r->have = 0;
        r->need = 4;
        return VP_LOGFMT_GOT_HEADER;
    }
    if (r->have == 4) {
        n = get32(p);
        if (n < REC_FRAME || n > VP_LOGFMT_MAX_RECORD) return reader_fail(r, VP_ECORRUPT, VP_LOGFMT_R_LENGTH);
        r->need = n;
        return VP_LOGFMT_NEED_MORE;
    }
    n = r->need;
    if (vp_logfmt_crc32(0, p, n - 4) != get32(p + n - 4)) return reader_fail(r, VP_ECORRUPT, VP_LOGFMT_R_CRC);
    if (get32(p + 4) != r->records) return reader_fail(r, VP_ECORRUPT, VP_LOGFMT_R_SEQUENCE);
    why = record_decode(p, n, rec);
    if (why != VP_LOGFMT_R_OK) return reader_fail(r, VP_ECORRUPT, why);
    r->records++;
    r->offset += n;
    r->have = 0;
    r->need = 4;
    return VP_LOGFMT_GOT_RECORD;
}

int vp_logfmt_reader_push(vp_logfmt_reader_t *r, const void *data, size_t len, size_t *used,
                       vp_logfmt_record_t *rec)
{
    const unsigned char *d = (const unsigned char *)data;
    size_t pos = 0;
    int st = VP_LOGFMT_NEED_MORE;
    if (used) *used = 0;
    if (r->status != VP_OK) return r->status;
    if (!rec || (!d && len)) return VP_EINVAL;
    while (pos < len) {
        size_t take = r->need - r->have;
        if (take > len - pos) take = len - pos;
        memcpy(r->buf + r->have, d + pos, take);
        r->have += (uint32_t)take;
        pos += take;
        if (r->have < r->need) break;
        st = reader_step(r, rec);
        if (st != VP_LOGFMT_NEED_MORE) break;
    }
    if (used) *used = pos;
    return st;
}

int vp_logfmt_reader_finish(vp_logfmt_reader_t *r)
{
    if (r->status != VP_OK) return r->status;
    if (!r->have_header || r->have > 0) return reader_fail(r, VP_ECORRUPT, VP_LOGFMT_R_TRUNCATED);
    return VP_OK;
}
#endif

/* ---------- replay ---------- */

#ifndef VP_CORE_MCU /* replay: host only (vp_status.h) */

static int same_bits(const double *a, const double *b, int n)
{
    int k;
    for (k = 0; k < n; k++)
        if (dbits(a[k]) != dbits(b[k])) return 0;
    return 1;
}

int vp_logfmt_replay(vp_planner_t *pl, const vp_logfmt_record_t *rec, vp_logfmt_mismatch_t *mm)
{
    vp_cmd_t cmd;
    vp_probe_result_t res;
    const char *bad = NULL;
    int st;
    if (!pl || !rec) return VP_EINVAL;
    if (rec->type == VP_LOGFMT_EVENT) return VP_OK;
    if (rec->type == VP_LOGFMT_RAY) {
        /* one more ray of the frame of the PROBE just fed: from its origin */
        if (!same_bits(pl->dev.iss_o, rec->origin, 3)) {
            if (mm) {
                memset(&mm->got, 0, sizeof mm->got);
                mm->expected_type = rec->type;
                mm->got_kind = VP_CMD_RAY;
                mm->field = "origin";
                memcpy(mm->got.from, pl->dev.iss_o, sizeof mm->got.from);
            }
            return VP_ECORRUPT;
        }
        res.hit = rec->hit;
        res.dist = rec->dist;
        return vp_planner_feed_ray(pl, rec->dir, &res);
    }
    st = vp_planner_next(pl, &cmd);
    if (st != VP_OK) return st;
    if (rec->type == VP_LOGFMT_MOVE) {
        if (cmd.kind != VP_CMD_MOVE) bad = "kind";
        else if (!same_bits(cmd.to, rec->target, 3)) bad = "target";
    } else if (rec->type == VP_LOGFMT_PROBE) {
        if (cmd.kind != VP_CMD_PROBE) bad = "kind";
        else if (!same_bits(cmd.from, rec->origin, 3)) bad = "origin";
        else if (!same_bits(cmd.dir, rec->dir, 3)) bad = "dir";
        else if (!same_bits(&cmd.range, &rec->range, 1)) bad = "range";
    } else {
        bad = "kind";
    }
    if (bad) {
        if (mm) {
            mm->expected_type = rec->type;
            mm->got_kind = cmd.kind;
            mm->field = bad;
            mm->got = cmd;
        }
        return VP_ECORRUPT;
    }
    if (rec->type == VP_LOGFMT_PROBE) {
        res.hit = rec->hit;
        res.dist = rec->dist;
        return vp_planner_feed(pl, &res);
    }
    return VP_OK;
}
#endif
