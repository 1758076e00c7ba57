/* vp_logfmt: CRC-32 against known values, exact round trips of header and records (bits, not
 * values: -0.0, NaN payloads, denormals), incremental decoding in every chunking, a torn tail
 * at every byte offset, a flipped bit in every byte, sequence errors, newer versions. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_logfmt.h"
#include "vp_test.h"

static void test_crc(void)
{
    unsigned char z[32];
    memset(z, 0, sizeof z);
    CHECK(vp_logfmt_crc32(0, "123456789", 9) == 0xCBF43926u);
    CHECK(vp_logfmt_crc32(0, "", 0) == 0);
    CHECK(vp_logfmt_crc32(0, "The quick brown fox jumps over the lazy dog", 43) == 0x414FA339u);
    CHECK(vp_logfmt_crc32(0, z, 32) == 0x190A55ADu);
    /* incremental = one shot */
    CHECK(vp_logfmt_crc32(vp_logfmt_crc32(0, "12345", 5), "6789", 4) == 0xCBF43926u);
}

static double bits_double(uint64_t u) { double d; memcpy(&d, &u, 8); return d; }
static int same(double a, double b) { return memcmp(&a, &b, 8) == 0; }

static void make_header(vp_logfmt_header_t *h, uint32_t ninterior)
{
    vp_planner_config_t c;
    uint32_t i;
    memset(&c, 0, sizeof c);
    c.omega_kind = VP_OMEGA_BALL;
    c.omega_center[0] = 0.1; c.omega_center[1] = -0.0; c.omega_center[2] = 1e-310;
    c.omega_radius = 3.0000000000000004;
    c.omega_lo[0] = -1; c.omega_hi[2] = 1;
    c.ninterior = ninterior;
    for (i = 0; i < ninterior; i++) { c.interior[i][0] = i * 0.1; c.interior[i][1] = 1.0 / 3.0; c.interior[i][2] = -(double)i; }
    c.eps = 0.17493710530423543;
    c.start[0] = 2.5; c.start[1] = 2.5; c.start[2] = 2.5;
    c.max_range = 5; c.noise_tol = 4e-4; c.confirm_misses = 7; c.clearance = 0.01; c.min_angle = 20.5;
    c.flags = VP_PLAN_PAPER | VP_PLAN_LARGEST;
    vp_logfmt_header_init(h, &c, (uint64_t)256 << 20, VP_LOGFMT_UNITS_MM, "host-sim", "sim --surface torus --eps-rel 0.05");
}

static int header_equal(const vp_logfmt_header_t *a, const vp_logfmt_header_t *b)
{
    const vp_planner_config_t *x = &a->cfg, *y = &b->cfg;
    uint32_t i;
    int k, ok = a->version == b->version && a->units == b->units && a->arena_bytes == b->arena_bytes &&
                !strcmp(a->board, b->board) && !strcmp(a->note, b->note) &&
                x->omega_kind == y->omega_kind && x->ninterior == y->ninterior &&
                x->confirm_misses == y->confirm_misses && x->flags == y->flags &&
                same(x->eps, y->eps) && same(x->omega_radius, y->omega_radius) &&
                same(x->max_range, y->max_range) && same(x->noise_tol, y->noise_tol) &&
                same(x->clearance, y->clearance) && same(x->min_angle, y->min_angle) &&
                same(x->size_rel, y->size_rel) && same(x->min_size, y->min_size) &&
                same(x->max_distance, y->max_distance) && same(x->min_feature, y->min_feature) &&
                same(x->feature_margin, y->feature_margin);
    for (k = 0; k < VP_PLANNER_AXES; k++) ok = ok && same(x->axis_time[k], y->axis_time[k]);
    ok = ok && same(x->pan_travel[0], y->pan_travel[0]) && same(x->pan_travel[1], y->pan_travel[1]);
    for (k = 0; k < 3; k++)
        ok = ok && same(x->omega_lo[k], y->omega_lo[k]) && same(x->omega_hi[k], y->omega_hi[k]) &&
             same(x->omega_center[k], y->omega_center[k]) && same(x->start[k], y->start[k]);
    for (i = 0; i < x->ninterior && i < VP_PLANNER_MAX_SEEDS; i++)
        for (k = 0; k < 3; k++) ok = ok && same(x->interior[i][k], y->interior[i][k]);
    return ok;
}

static int record_equal(const vp_logfmt_record_t *a, const vp_logfmt_record_t *b)
{
    int k, ok = a->seq == b->seq && a->type == b->type;
    if (!ok) return 0;
    if (a->type == VP_LOGFMT_PROBE) {
        for (k = 0; k < 3; k++) ok = ok && same(a->origin[k], b->origin[k]) && same(a->dir[k], b->dir[k]);
        return ok && same(a->range, b->range) && a->hit == b->hit && same(a->dist, b->dist) && same(a->raw, b->raw);
    }
    if (a->type == VP_LOGFMT_MOVE) {
        for (k = 0; k < 3; k++) ok = ok && same(a->target[k], b->target[k]);
        return ok;
    }
    for (k = 0; k < 4; k++) ok = ok && same(a->value[k], b->value[k]);
    return ok && a->event == b->event && a->code == b->code && a->text_len == b->text_len &&
           !memcmp(a->text, b->text, a->text_len + 1);
}

/* A log of n records in buf; recs gets them; returns the byte count; offs[i] = record i's offset. */
static size_t make_log(unsigned char *buf, size_t cap, vp_logfmt_header_t *h, vp_logfmt_record_t *recs,
                       size_t *offs, uint32_t n)
{
    size_t len;
    uint32_t i;
    int w;
    make_header(h, 3);
    w = vp_logfmt_header_encode(h, buf, cap);
    CHECK(w > 0);
    len = (size_t)w;
    for (i = 0; i < n; i++) {
        vp_cmd_t cmd;
        vp_probe_result_t res;
        memset(&cmd, 0, sizeof cmd);
        cmd.from[0] = i * 0.25; cmd.from[1] = -0.0; cmd.from[2] = bits_double(1);
        cmd.to[0] = 1.0 / (i + 1); cmd.to[1] = 2; cmd.to[2] = -3;
        cmd.dir[0] = 0.6; cmd.dir[1] = 0.8; cmd.dir[2] = 0;
        cmd.range = 1e300;
        res.hit = (int)(i & 1); res.dist = res.hit ? 0.1 * i : 0;
        if (i % 7 == 0) vp_logfmt_record_event(&recs[i], i, 1 + i % 6, -(int32_t)i, i % 14 ? "resume after a power cut" : "");
        else if (i % 3 == 0) vp_logfmt_record_move(&recs[i], i, &cmd);
        else vp_logfmt_record_probe(&recs[i], i, &cmd, &res, i % 2 ? bits_double(0x7FF8000000000123ull) : -0.5);
        if (i % 7 == 0) { recs[i].value[0] = M_PI; recs[i].value[3] = -INFINITY; }
        offs[i] = len;
        w = vp_logfmt_record_encode(&recs[i], buf + len, cap - len);
        CHECK(w == vp_logfmt_record_size(&recs[i]));
        len += (size_t)w;
    }
    return len;
}

/* Reads buf[0..len) in chunks of `chunk` bytes (0: random sizes); returns records read. */
static uint32_t read_log(const unsigned char *buf, size_t len, size_t chunk, vp_logfmt_reader_t *r,
                         vp_logfmt_record_t *out, uint32_t cap, int *final)
{
    size_t pos = 0;
    uint32_t n = 0;
    int st = VP_OK;
    unsigned seed = 12345;
    vp_logfmt_reader_init(r);
    while (pos < len) {
        size_t used, c = chunk;
        vp_logfmt_record_t rec;
        if (!c) { seed = seed * 1103515245u + 12345u; c = 1 + (seed >> 16) % 200; }
        if (c > len - pos) c = len - pos;
        st = vp_logfmt_reader_push(r, buf + pos, c, &used, &rec);
        pos += used;
        if (st == VP_LOGFMT_GOT_RECORD) { if (n < cap) out[n] = rec; n++; }
        if (st < 0) break;
    }
    *final = st < 0 ? st : vp_logfmt_reader_finish(r);
    return n;
}

#define NREC 60

static void test_roundtrip(void)
{
    static unsigned char buf[65536];
    static vp_logfmt_record_t recs[NREC], got[NREC];
    size_t offs[NREC], len, chunks[] = { 0, 1, 2, 3, 7, 64, 65536 };
    vp_logfmt_header_t h, h2;
    vp_logfmt_reader_t r;
    unsigned i, c;
    int fin;
    len = make_log(buf, sizeof buf, &h, recs, offs, NREC);
    for (c = 0; c < sizeof chunks / sizeof chunks[0]; c++) {
        uint32_t n = read_log(buf, len, chunks[c], &r, got, NREC, &fin);
        int ok = n == NREC && fin == VP_OK && r.have_header && header_equal(&h, &r.header) && r.offset == len;
        for (i = 0; ok && i < NREC; i++) ok = record_equal(&recs[i], &got[i]);
        CHECKF(ok, "chunk %zu: %u records, status %d", chunks[c], n, fin);
    }
    /* header with 16 interior points and the longest strings */
    make_header(&h, VP_PLANNER_MAX_SEEDS);
    memset(h.note, 'n', VP_LOGFMT_NOTE_MAX); h.note[VP_LOGFMT_NOTE_MAX] = 0;
    memset(h.board, 'b', VP_LOGFMT_BOARD_MAX); h.board[VP_LOGFMT_BOARD_MAX] = 0;
    CHECK(vp_logfmt_header_encode(&h, buf, sizeof buf) == vp_logfmt_header_size(&h));
    CHECK(vp_logfmt_header_size(&h) <= VP_LOGFMT_MAX_HEADER);
    vp_logfmt_reader_init(&r);
    {
        size_t used;
        vp_logfmt_record_t rec;
        CHECK(vp_logfmt_reader_push(&r, buf, (size_t)vp_logfmt_header_size(&h), &used, &rec) == VP_LOGFMT_GOT_HEADER);
        CHECK(header_equal(&h, &r.header) && vp_logfmt_reader_finish(&r) == VP_OK);
    }
    /* encoder refusals */
    h2 = h; h2.cfg.ninterior = 0;
    CHECK(vp_logfmt_header_encode(&h2, buf, sizeof buf) == VP_EINVAL);
    CHECK(vp_logfmt_header_encode(&h, buf, 100) == VP_ENOMEM);
    {
        vp_logfmt_record_t rec;
        vp_logfmt_record_event(&rec, 0, VP_LOGFMT_EV_DONE, 0, "x");
        CHECK(vp_logfmt_record_encode(&rec, buf, 10) == VP_ENOMEM);
        rec.type = 9;
        CHECK(vp_logfmt_record_encode(&rec, buf, sizeof buf) == VP_EINVAL);
        /* nothing the reader refuses is written (the build before wrote these, and the reader
         * then stopped at them: the rest of a session lost) */
        {
            vp_cmd_t cmd;
            vp_probe_result_t res;
            static const double bad[] = { NAN, INFINITY, -INFINITY };
            int j, ok;
            memset(&cmd, 0, sizeof cmd);
            cmd.kind = VP_CMD_PROBE;
            cmd.dir[2] = 1.0;
            cmd.range = 1.0;
            res.hit = 0;
            res.dist = 0.0;
            for (j = 0; j < 3; j++) {
                unsigned char tmp[256];
                memset(tmp, 0xA5, sizeof tmp);
                vp_logfmt_record_probe(&rec, 1, &cmd, &res, NAN); /* a NaN raw reading is fine */
                ok = vp_logfmt_record_encode(&rec, tmp, sizeof tmp);
                CHECK(ok == VP_LOGFMT_PROBE_SIZE);
                rec.dist = bad[j];
                CHECK(vp_logfmt_record_encode(&rec, tmp, sizeof tmp) == VP_EINVAL);
                vp_logfmt_record_probe(&rec, 1, &cmd, &res, 0.0);
                rec.origin[1] = bad[j];
                CHECK(vp_logfmt_record_encode(&rec, tmp, sizeof tmp) == VP_EINVAL);
                vp_logfmt_record_probe(&rec, 1, &cmd, &res, 0.0);
                rec.range = bad[j];
                CHECK(vp_logfmt_record_encode(&rec, tmp, sizeof tmp) == VP_EINVAL);
                cmd.kind = VP_CMD_MOVE;
                cmd.to[0] = bad[j];
                vp_logfmt_record_move(&rec, 2, &cmd);
                memset(tmp, 0xA5, sizeof tmp);
                CHECK(vp_logfmt_record_encode(&rec, tmp, sizeof tmp) == VP_EINVAL);
                CHECK(tmp[0] == 0xA5 && tmp[11] == 0xA5); /* nothing written */
                cmd.kind = VP_CMD_PROBE;
                cmd.to[0] = 0.0;
            }
            vp_logfmt_record_probe(&rec, 1, &cmd, &res, 0.0);
            rec.hit = 3;
            CHECK(vp_logfmt_record_encode(&rec, buf, sizeof buf) == VP_EINVAL);
        }
        /* long texts are cut at the limit */
        {
            char t[400];
            memset(t, 'x', sizeof t); t[399] = 0;
            vp_logfmt_record_event(&rec, 0, VP_LOGFMT_EV_FAULT, VP_EIO, t);
            CHECK(rec.text_len == VP_LOGFMT_TEXT_MAX && vp_logfmt_record_size(&rec) <= VP_LOGFMT_MAX_RECORD);
        }
    }
    /* the planner configuration the format covers: a new field needs a new format version */
    CHECKF(sizeof(vp_planner_config_t) == 664,
           "vp_planner_config_t changed (%zu bytes): update core/vp_logfmt.c, doc/session-log.md, VP_LOGFMT_VERSION",
           sizeof(vp_planner_config_t));
}

static void test_truncation(void)
{
    static unsigned char buf[65536];
    static vp_logfmt_record_t recs[NREC], got[NREC];
    size_t offs[NREC], len, cut;
    vp_logfmt_header_t h;
    vp_logfmt_reader_t r;
    int fin, bad = 0;
    len = make_log(buf, sizeof buf, &h, recs, offs, NREC);
    for (cut = 0; cut < len; cut++) {
        uint32_t n = read_log(buf, cut, 0, &r, got, NREC, &fin), whole = 0;
        while (whole < NREC && offs[whole] + (size_t)vp_logfmt_record_size(&recs[whole]) <= cut) whole++;
        if (cut < offs[0]) {
            if (!(fin == VP_ECORRUPT && r.reason == VP_LOGFMT_R_TRUNCATED && r.bad_in_header && n == 0)) bad++;
        } else if (whole < NREC && cut == offs[whole]) {
            /* a cut between records is a clean end */
            if (!(fin == VP_OK && n == whole && r.offset == cut)) bad++;
        } else if (!(fin == VP_ECORRUPT && r.reason == VP_LOGFMT_R_TRUNCATED && n == whole &&
                     r.bad_record == whole && r.bad_offset == offs[whole] && r.offset == offs[whole])) {
            bad++;
        }
    }
    CHECKF(bad == 0, "%d cut positions misreported", bad);
}

static void test_bitflips(void)
{
    static unsigned char buf[65536];
    static vp_logfmt_record_t recs[NREC], got[NREC];
    size_t offs[NREC], len, at;
    vp_logfmt_header_t h;
    vp_logfmt_reader_t r;
    int fin, bad = 0, bit;
    len = make_log(buf, sizeof buf, &h, recs, offs, NREC);
    for (at = 0; at < len; at++)
        for (bit = 0; bit < 8; bit += 3) {
            uint32_t n, k = 0;
            buf[at] ^= (unsigned char)(1u << bit);
            n = read_log(buf, len, 0, &r, got, NREC, &fin);
            buf[at] ^= (unsigned char)(1u << bit);
            while (k < NREC && offs[k] + (size_t)vp_logfmt_record_size(&recs[k]) <= at) k++;
            if (at < offs[0]) {
                /* header damage: never a record, never a crash, never taken for a newer version */
                if (!(fin == VP_ECORRUPT && n == 0 && r.bad_in_header)) bad++;
            } else {
                /* the damaged record and nothing after it is rejected; all before are kept */
                uint32_t i;
                int ok = fin < 0 && n == k && r.bad_record == k && r.bad_offset == offs[k];
                for (i = 0; ok && i < n; i++) ok = record_equal(&recs[i], &got[i]);
                if (!ok) {
                    if (bad < 5) fprintf(stderr, "flip at %zu bit %d: %u records, reason %s, record %u\n",
                                         at, bit, n, vp_logfmt_reason_text(r.reason), r.bad_record);
                    bad++;
                }
            }
        }
    CHECKF(bad == 0, "%d flips misreported", bad);
}

/* The header's CRC (its last 4 bytes) recomputed after an edit. */
static void put_crc(unsigned char *buf, size_t hl)
{
    uint32_t c = vp_logfmt_crc32(0, buf, hl - 4);
    int k;
    for (k = 0; k < 4; k++) buf[hl - 4 + (size_t)k] = (unsigned char)(c >> (8 * k));
}

static void test_errors(void)
{
    static unsigned char buf[4096];
    vp_logfmt_header_t h;
    vp_logfmt_record_t rec;
    vp_logfmt_reader_t r;
    size_t used, hl;
    int w;
    vp_cmd_t cmd;
    vp_probe_result_t res;
    make_header(&h, 1);
    hl = (size_t)vp_logfmt_header_encode(&h, buf, sizeof buf);
    /* a newer version with a valid CRC is refused as newer */
    buf[8] = VP_LOGFMT_VERSION + 1;
    put_crc(buf, hl);
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, buf, hl, &used, &rec) == VP_EVERSION && r.reason == VP_LOGFMT_R_VERSION);
    CHECK(vp_logfmt_reader_push(&r, buf, hl, &used, &rec) == VP_EVERSION && used == 0);
    /* a damaged version byte (version 257, the CRC no longer matches) is a damaged header, not a
     * newer format; so is version 2 without the CRC fixed */
    buf[8] = 1;
    put_crc(buf, hl);
    buf[9] = 1;
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, buf, hl, &used, &rec) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_HEADER_CRC && r.bad_in_header);
    buf[9] = 0;
    buf[8] = 2;
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, buf, hl, &used, &rec) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_HEADER_CRC);
    buf[8] = 1;
    /* not a log */
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, "ply\nformat ascii 1.0\n....", 24, &used, &rec) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_MAGIC);
    /* an empty file is a truncated header */
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_finish(&r) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_TRUNCATED && r.bad_in_header);
    /* sequence: record 0 then record 2 */
    memset(&cmd, 0, sizeof cmd);
    cmd.dir[0] = 1; cmd.range = 1;
    res.hit = 1; res.dist = 0.5;
    vp_logfmt_record_probe(&rec, 0, &cmd, &res, 0.5);
    w = vp_logfmt_record_encode(&rec, buf + hl, sizeof buf - hl);
    vp_logfmt_record_probe(&rec, 2, &cmd, &res, 0.5);
    w += vp_logfmt_record_encode(&rec, buf + hl + (size_t)w, sizeof buf - hl - (size_t)w);
    {
        vp_logfmt_record_t out[4];
        int fin;
        uint32_t n = read_log(buf, hl + (size_t)w, 5, &r, out, 4, &fin);
        CHECK(n == 1 && fin == VP_ECORRUPT && r.reason == VP_LOGFMT_R_SEQUENCE && r.bad_record == 1 &&
              r.bad_offset == hl + VP_LOGFMT_PROBE_SIZE);
    }
    /* a NaN coordinate with a valid CRC is an invalid field; hit must be 0 or 1 (the encoder
     * writes no such record: the NaN is put into the origin's y, bytes 20-27 little-endian,
     * and the CRC made again) */
    vp_logfmt_record_probe(&rec, 0, &cmd, &res, 0.5);
    w = vp_logfmt_record_encode(&rec, buf + hl, sizeof buf - hl);
    {
        double nan = NAN;
        uint64_t u;
        int k;
        memcpy(&u, &nan, sizeof u);
        for (k = 0; k < 8; k++) buf[hl + 20 + (size_t)k] = (unsigned char)(u >> (8 * k));
        put_crc(buf + hl, (size_t)w);
    }
    {
        vp_logfmt_record_t out[2];
        int fin;
        read_log(buf, hl + (size_t)w, 0, &r, out, 2, &fin);
        CHECK(fin == VP_ECORRUPT && r.reason == VP_LOGFMT_R_FIELD && r.bad_record == 0);
    }
    CHECK(strlen(vp_logfmt_reason_text(VP_LOGFMT_R_CRC)) > 0 && strlen(vp_logfmt_reason_text(99)) > 0);
}

/* The header's encoder writes no header its reader refuses: each field the reader checks, made
 * bad, is refused by vp_logfmt_header_size and _encode (the buffer untouched); and the same field
 * put into a good header by hand (its bytes found by a marker value, the CRC made again) is
 * refused by the reader. */
enum { HF_EPS, HF_RADIUS, HF_INTERIOR, HF_START, HF_MAXDIST, HF_SIZEREL,
#ifndef VP_CORE_MCU
       HF_FEATURE, HF_AXIS, HF_PAN,
#endif
       HF_COUNT };
static double *header_field(vp_planner_config_t *c, int f)
{
    switch (f) {
    case HF_EPS: return &c->eps;
    case HF_RADIUS: return &c->omega_radius;
    case HF_INTERIOR: return &c->interior[1][2];
    case HF_START: return &c->start[1];
    case HF_MAXDIST: return &c->max_distance;
    case HF_SIZEREL: return &c->size_rel;
#ifndef VP_CORE_MCU
    case HF_FEATURE: return &c->min_feature;
    case HF_AXIS: return &c->axis_time[2];
    case HF_PAN: return &c->pan_travel[1];
#endif
    default: return &c->min_angle;
    }
}

static void test_header_fields(void)
{
    static unsigned char buf[4096];
    static const double marker = 1234.5678912345;
    vp_logfmt_header_t h, g;
    vp_logfmt_record_t rec;
    vp_logfmt_reader_t r;
    size_t used;
    int f, k, w, found, bad_enc = 0, bad_dec = 0;
    for (f = 0; f < HF_COUNT; f++)
        for (k = 0; k < 2; k++) {
            double *x;
            make_header(&h, 3);
            h.cfg.min_size = 0.01; /* the sizing field's two numbers and the distance bound: version 3 */
            h.cfg.size_rel = 0.5;
            h.cfg.max_distance = 0.02;
#ifndef VP_CORE_MCU
            h.cfg.min_feature = 0.5; h.cfg.feature_margin = 0.1; /* and the tubes' and axes': version 6 */
            h.cfg.axis_time[0] = 0.1; h.cfg.pan_travel[0] = -1; h.cfg.pan_travel[1] = 1;
#endif
            g = h;
            x = header_field(&h.cfg, f);
            *x = k ? -INFINITY : NAN;
            memset(buf, 0xa5, 64);
            if (vp_logfmt_header_size(&h) != VP_EINVAL || vp_logfmt_header_encode(&h, buf, sizeof buf) != VP_EINVAL ||
                buf[0] != 0xa5 || buf[63] != 0xa5)
                bad_enc++;
            /* by hand: the marker where the bad value goes */
            *header_field(&g.cfg, f) = marker;
            w = vp_logfmt_header_encode(&g, buf, sizeof buf);
            found = 0;
            if (w > 0) {
                int i;
                for (i = 0; i + 8 <= w; i++)
                    if (memcmp(buf + i, &marker, 8) == 0) { memcpy(buf + i, x, 8); found++; }
                put_crc(buf, (size_t)w);
                vp_logfmt_reader_init(&r);
            }
            if (w <= 0 || found != 1 || vp_logfmt_reader_push(&r, buf, (size_t)w, &used, &rec) != VP_ECORRUPT ||
                r.reason != VP_LOGFMT_R_HEADER)
                bad_dec++;
        }
    CHECKF(bad_enc == 0, "%d bad header fields encoded", bad_enc);
    CHECKF(bad_dec == 0, "%d bad header fields read", bad_dec);
    /* a kind of Omega neither box nor ball; no interior point; more rays per frame than a frame has */
    for (f = 0; f < 3; f++) {
        make_header(&h, 2);
        if (f == 0) h.cfg.omega_kind = 7;
        else if (f == 1) h.cfg.ninterior = 0;
#ifndef VP_CORE_MCU
        else h.cfg.line_rays = VP_PLANNER_MAX_LINE_RAYS + 1;
#else
        else h.cfg.omega_kind = -1;
#endif
        CHECKF(vp_logfmt_header_encode(&h, buf, sizeof buf) == VP_EINVAL, "bad header field %d encoded", f);
    }
    make_header(&h, 2);
    w = vp_logfmt_header_encode(&h, buf, sizeof buf);
    buf[20] = 7; /* omega_kind, bytes 20-23 */
    put_crc(buf, (size_t)w);
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, buf, (size_t)w, &used, &rec) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_HEADER);
}

/* The sizing field's two numbers: a header with them is version 2 and 16 bytes longer, read
 * back bit for bit; without them the header stays version 1, byte for byte as before (so
 * uniform sessions log exactly what they did); a version 2 header missing them is refused as
 * damaged, and one with a non-finite number is not written. */
static void test_sizing_header(void)
{
    vp_logfmt_header_t h, g;
    vp_logfmt_reader_t r;
    vp_logfmt_record_t rec;
    unsigned char a[VP_LOGFMT_MAX_HEADER], b[VP_LOGFMT_MAX_HEADER];
    size_t used;
    int na, nb;
    make_header(&h, 2);
    na = vp_logfmt_header_encode(&h, a, sizeof a);
    CHECK(na > 0 && a[8] == 1 && h.version == 1);
    h.cfg.size_rel = 0.25;
    h.cfg.min_size = bits_double(0x3F847AE147AE147Bull); /* 0.01 */
    nb = vp_logfmt_header_encode(&h, b, sizeof b);
    CHECK(nb == na + 16 && b[8] == 2);
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER && used == (size_t)nb);
    g = r.header;
    h.version = 2;
    CHECK(header_equal(&g, &h));
    /* version 2 without its numbers: the bytes before the CRC are the note's end */
    memcpy(b, a, (size_t)na);
    b[8] = 2;
    put_crc(b, (size_t)na);
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, b, (size_t)na, &used, &rec) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_HEADER);
    /* a NaN size_rel is not written (one put in by hand is not read: test_header_fields) */
    h.cfg.size_rel = bits_double(0x7FF8000000000000ull);
    CHECK(vp_logfmt_header_encode(&h, b, sizeof b) == VP_EINVAL);
    /* the distance bound: version 3, 24 bytes, with or without the sizing field */
    h.cfg.size_rel = 0.0;
    h.cfg.min_size = bits_double(0x3F50624DD2F1A9FCull); /* 0.001 */
    h.cfg.max_distance = bits_double(0x3F5A36E2EB1C432Dull); /* 0.0004 */
    nb = vp_logfmt_header_encode(&h, b, sizeof b);
    CHECK(nb == na + 24 && b[8] == 3);
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER && used == (size_t)nb);
    g = r.header;
    h.version = 3;
    CHECK(header_equal(&g, &h) && g.cfg.max_distance == h.cfg.max_distance);
    /* version 3 whose distance bound is 0 is not what an encoder writes: damaged */
    {
        vp_logfmt_header_t z = h;
        unsigned char c[VP_LOGFMT_MAX_HEADER];
        int nc;
        z.cfg.max_distance = 0.0;
        nc = vp_logfmt_header_encode(&z, c, sizeof c);
        CHECK(nc == na + 16 && c[8] == 2);
        memcpy(c, b, (size_t)nb);
        memset(c + nb - 12, 0, 8); /* the distance bound's bytes */
        put_crc(c, (size_t)nb);
        vp_logfmt_reader_init(&r);
        CHECK(vp_logfmt_reader_push(&r, c, (size_t)nb, &used, &rec) == VP_ECORRUPT && r.reason == VP_LOGFMT_R_HEADER);
        /* nor a version 2 header with 24 bytes after the note */
        memcpy(c, b, (size_t)nb);
        c[8] = 2;
        put_crc(c, (size_t)nb);
        vp_logfmt_reader_init(&r);
        CHECK(vp_logfmt_reader_push(&r, c, (size_t)nb, &used, &rec) == VP_ECORRUPT);
    }
    /* the planner takes the bound and refuses a negative or infinite one */
    {
        static unsigned char arena[4 << 20];
        static vp_planner_t pl;
        vp_planner_config_t cfg = h.cfg;
        CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
        cfg.max_distance = -1.0;
        CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_EINVAL);
        cfg.max_distance = bits_double(0x7FF0000000000000ull);
        CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_EINVAL);
        cfg.max_distance = 0.0004;
        cfg.min_size = 2.0 * cfg.eps; /* a floor above eps */
        CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_EINVAL);
    }
    /* tubes: version 5, 48 bytes; a NaN feature size is damage */
    h.cfg.max_distance = 0.0;
    h.cfg.min_size = 0.0;
    h.cfg.min_feature = bits_double(0x3FB999999999999Aull); /* 0.1 */
    h.cfg.feature_margin = 0.075;
    nb = vp_logfmt_header_encode(&h, b, sizeof b);
    CHECK(nb == na + 48 && b[8] == 5);
    vp_logfmt_reader_init(&r);
    CHECK(vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER && used == (size_t)nb);
    g = r.header;
    h.version = 5;
    CHECK(header_equal(&g, &h) && g.cfg.min_feature == h.cfg.min_feature && g.cfg.feature_margin == 0.075);
    h.cfg.min_feature = bits_double(0x7FF8000000000000ull);
    CHECK(vp_logfmt_header_encode(&h, b, sizeof b) == VP_EINVAL);
    h.cfg.min_feature = h.cfg.feature_margin = 0.0;
    /* moves weighed by machine time: version 6, 104 bytes, every axis's time and the pan's travel
     * read back bit for bit; any one of them alone makes it version 6; a NaN is damage */
    {
        static const double at[VP_PLANNER_AXES] = { 1.0 / 150, 1.0 / 120, 1.0 / 15, 0.63661977236758138, 0.95492965855137202 };
        int q;
        for (q = 0; q < VP_PLANNER_AXES + 1; q++) {
            memset(h.cfg.axis_time, 0, sizeof h.cfg.axis_time);
            h.cfg.pan_travel[0] = q == VP_PLANNER_AXES ? -3.3161255787892263 : 0.0;
            h.cfg.pan_travel[1] = q == VP_PLANNER_AXES ? 3.3161255787892263 : 0.0;
            if (q < VP_PLANNER_AXES) h.cfg.axis_time[q] = at[q];
            nb = vp_logfmt_header_encode(&h, b, sizeof b);
            vp_logfmt_reader_init(&r);
            CHECK(nb == na + 104 && b[8] == 6 &&
                  vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER);
            h.version = 6;
            CHECK(header_equal(&r.header, &h));
        }
        memcpy(h.cfg.axis_time, at, sizeof at);
        nb = vp_logfmt_header_encode(&h, b, sizeof b);
        vp_logfmt_reader_init(&r);
        CHECK(vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER && header_equal(&r.header, &h));
        h.cfg.axis_time[2] = bits_double(0x7FF8000000000000ull);
        CHECK(vp_logfmt_header_encode(&h, b, sizeof b) == VP_EINVAL);
        h.cfg.axis_time[2] = at[2];
        h.cfg.pan_travel[1] = bits_double(0xFFF0000000000000ull);
        CHECK(vp_logfmt_header_encode(&h, b, sizeof b) == VP_EINVAL);
        memset(h.cfg.axis_time, 0, sizeof h.cfg.axis_time);
        memset(h.cfg.pan_travel, 0, sizeof h.cfg.pan_travel);
    }
    /* spots read past the edge: version 7, the same 104 bytes, the flag read back; the flag in a
     * header of any other version (the CRC made good) is damage */
    {
        int v;
        h.cfg.flags |= VP_PLAN_FAR_READS;
        h.cfg.axis_time[2] = 1.0 / 15;
        nb = vp_logfmt_header_encode(&h, b, sizeof b);
        vp_logfmt_reader_init(&r);
        CHECK(nb == na + 104 && b[8] == 7 && vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER);
        h.version = 7;
        CHECK(header_equal(&r.header, &h) && (r.header.cfg.flags & VP_PLAN_FAR_READS));
        h.cfg.axis_time[2] = 0.0;
        nb = vp_logfmt_header_encode(&h, b, sizeof b);
        vp_logfmt_reader_init(&r);
        CHECK(nb == na + 104 && b[8] == 7 && vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER &&
              header_equal(&r.header, &h));
        for (v = 1; v <= 6; v++) {
            unsigned char c2[sizeof b];
            size_t m = (size_t)vp_logfmt_header_encode(&h, c2, sizeof c2);
            c2[8] = (unsigned char)v;
            put_crc(c2, m);
            vp_logfmt_reader_init(&r);
            CHECK(vp_logfmt_reader_push(&r, c2, m, &used, &rec) == VP_ECORRUPT);
        }
        h.cfg.flags &= ~VP_PLAN_FAR_READS;
    }
    /* the smallest ball first: version 8, the same 104 bytes, the flag read back (a distance bound
     * beside it, as sim sets it); the flag in a header of any other version is damage, and a
     * version 8 header without it too */
    {
        int v;
        unsigned char c2[sizeof b];
        size_t m;
        h.cfg.flags |= VP_PLAN_SMALL_FIRST;
        h.cfg.min_size = 0.001;
        h.cfg.max_distance = 0.0004;
        nb = vp_logfmt_header_encode(&h, b, sizeof b);
        vp_logfmt_reader_init(&r);
        CHECK(nb == na + 104 && b[8] == 8 && vp_logfmt_reader_push(&r, b, (size_t)nb, &used, &rec) == VP_LOGFMT_GOT_HEADER);
        h.version = 8;
        CHECK(header_equal(&r.header, &h) && (r.header.cfg.flags & VP_PLAN_SMALL_FIRST) &&
              r.header.cfg.max_distance == 0.0004 && r.header.cfg.min_size == 0.001);
        for (v = 1; v <= 7; v++) {
            m = (size_t)vp_logfmt_header_encode(&h, c2, sizeof c2);
            c2[8] = (unsigned char)v;
            put_crc(c2, m);
            vp_logfmt_reader_init(&r);
            CHECK(vp_logfmt_reader_push(&r, c2, m, &used, &rec) == VP_ECORRUPT);
        }
        /* the flag's bit cleared in a version 8 header (the flags word at byte 172) */
        m = (size_t)vp_logfmt_header_encode(&h, c2, sizeof c2);
        c2[172] &= (unsigned char)~VP_PLAN_SMALL_FIRST;
        put_crc(c2, m);
        vp_logfmt_reader_init(&r);
        CHECK(vp_logfmt_reader_push(&r, c2, m, &used, &rec) == VP_ECORRUPT);
        h.cfg.flags &= ~VP_PLAN_SMALL_FIRST;
        h.cfg.min_size = h.cfg.max_distance = 0.0;
    }
}

int main(void)
{
    test_crc();
    test_sizing_header();
    test_roundtrip();
    test_truncation();
    test_bitflips();
    test_errors();
    test_header_fields();
    return vp_test_done("test_log");
}
