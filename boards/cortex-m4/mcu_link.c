/* The MCU's end of the link (doc/mcu-protocol.md): frames COBS-stuffed between 0x00 bytes,
 * each [version, type, sequence, length, payload, CRC-32]. The MCU asks, the host answers:
 * a request is sent again until a reply with its sequence number arrives intact, so a damaged
 * frame in either direction is never acted on. (mcu.h is given with -include.) */
#include <string.h>
#include "vp_logfmt.h"

mcu_link_stats_t mcu_link_stats;

static uint16_t tx_seq;
static uint8_t body[MCU_MAX_PAYLOAD + MCU_FRAME_OVERHEAD];
static uint8_t wire[MCU_MAX_PAYLOAD + MCU_FRAME_OVERHEAD + MCU_MAX_PAYLOAD / 254 + 8];
/* the receiver: COBS-stuffed bytes since the last 0x00 */
static uint8_t rx[MCU_MAX_PAYLOAD + MCU_FRAME_OVERHEAD + MCU_MAX_PAYLOAD / 254 + 8];
static size_t rx_n;
static int rx_overflow;

void mcu_put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24);
}

uint32_t mcu_get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

void mcu_putf64(uint8_t *p, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    mcu_put32(p, (uint32_t)u);
    mcu_put32(p + 4, (uint32_t)(u >> 32));
}

double mcu_getf64(const uint8_t *p)
{
    uint64_t u = (uint64_t)mcu_get32(p) | (uint64_t)mcu_get32(p + 4) << 32;
    double v;
    memcpy(&v, &u, 8);
    return v;
}

/* COBS: every 0x00 of in[] replaced; out gets at most n + n/254 + 1 bytes. */
static size_t cobs_encode(const uint8_t *in, size_t n, uint8_t *out)
{
    size_t code_at = 0, o = 1, i;
    uint8_t code = 1;
    for (i = 0; i < n; i++) {
        if (in[i] == 0) {
            out[code_at] = code; code_at = o++; code = 1;
        } else {
            out[o++] = in[i];
            if (++code == 0xFF) { out[code_at] = code; code_at = o++; code = 1; }
        }
    }
    out[code_at] = code;
    return o;
}

/* Decodes into out[cap]; the decoded length, or -1 for a malformed block or one too long. */
static long cobs_decode(const uint8_t *in, size_t n, uint8_t *out, size_t cap)
{
    size_t i = 0, o = 0;
    while (i < n) {
        uint8_t code = in[i++], k;
        if (code == 0 || i + code - 1u > n || o + code > cap) return -1;
        for (k = 1; k < code; k++) out[o++] = in[i++];
        if (code != 0xFF && i < n) out[o++] = 0;
    }
    return (long)o;
}

static void send_frame(uint8_t type, uint16_t seq, const uint8_t *payload, uint16_t len)
{
    size_t n;
    uint8_t zero = 0;
    body[0] = (uint8_t)MCU_PROTO_VERSION;
    body[1] = type;
    body[2] = (uint8_t)seq; body[3] = (uint8_t)(seq >> 8);
    body[4] = (uint8_t)len; body[5] = (uint8_t)(len >> 8);
    if (len) memcpy(body + 6, payload, len);
    mcu_put32(body + 6 + len, vp_logfmt_crc32(0, body, 6u + len));
    n = cobs_encode(body, 10u + len, wire);
    mcu_hal_write(&zero, 1);
    mcu_hal_write(wire, n);
    mcu_hal_write(&zero, 1);
    mcu_link_stats.frames_sent++;
}

/* A complete block in rx[]: 1 and the frame's fields for a good frame, 0 for none (empty),
 * -1 for a damaged one. */
static int take_frame(uint8_t *type, uint16_t *seq, uint8_t *payload, uint16_t *len)
{
    long n;
    uint16_t plen;
    if (rx_n == 0 && !rx_overflow) return 0;
    n = rx_overflow ? -1 : cobs_decode(rx, rx_n, body, sizeof body);
    rx_n = 0;
    rx_overflow = 0;
    if (n < (long)MCU_FRAME_OVERHEAD) return -1;
    plen = (uint16_t)(body[4] | body[5] << 8);
    if ((long)plen + (long)MCU_FRAME_OVERHEAD != n || body[0] != MCU_PROTO_VERSION) return -1;
    if (vp_logfmt_crc32(0, body, 6u + plen) != mcu_get32(body + 6 + plen)) return -1;
    *type = body[1];
    *seq = (uint16_t)(body[2] | body[3] << 8);
    if (plen) memcpy(payload, body + 6, plen);
    *len = plen;
    return 1;
}

int mcu_link_request(uint8_t type, const uint8_t *payload, uint16_t len, uint32_t tries,
                     uint8_t *reply, uint16_t *reply_len)
{
    uint32_t sent = 0, hz_ms = mcu_axes.tick_hz / 1000u;
    uint16_t seq = ++tx_seq;
    for (;;) {
        uint32_t t0;
        int resend = 0;
        if (tries && sent == tries) return VP_ETIMEOUT;
        send_frame(type, seq, payload, len);
        sent++;
        t0 = mcu_hal_now();
        while (!resend) {
            int c = mcu_hal_getc();
            if (c < 0) {
                mcu_hal_idle();
                if (mcu_hal_now() - t0 > MCU_REPLY_TIMEOUT_MS * hz_ms) { mcu_link_stats.timeouts++; resend = 1; }
                continue;
            }
            if (c != 0) {
                if (rx_n < sizeof rx) rx[rx_n++] = (uint8_t)c;
                else rx_overflow = 1;
                continue;
            }
            {
                uint8_t rtype;
                uint16_t rseq, rlen;
                int got = take_frame(&rtype, &rseq, reply, &rlen);
                if (got == 0) continue;
                if (got < 0) { mcu_link_stats.crc_errors++; resend = 1; continue; }
                mcu_link_stats.frames_received++;
                if (rtype == MCU_NAK) { mcu_link_stats.naks++; resend = 1; continue; }
                if (rseq != seq) continue;          /* a late reply to an earlier request */
                *reply_len = rlen;
                return rtype;
            }
        }
    }
}
