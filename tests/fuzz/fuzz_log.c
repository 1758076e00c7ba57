/* libFuzzer target: the session log reader (core incremental reader in every chunking, the
 * host loader) and the replay of whatever it accepts. Never a crash, never a sanitizer report. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "vp_logfmt.h"
#include "vp_sessionlog.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static vp_logfmt_reader_t r;
    vp_logfmt_record_t rec;
    vp_sessionlog_t L;
    char err[600], stop[600];
    size_t pos = 0, chunk = size ? 1 + data[0] % 97 : 1;
    uint32_t n = 0;
    /* the core reader, fed in chunks */
    vp_logfmt_reader_init(&r);
    while (pos < size) {
        size_t used, c = size - pos < chunk ? size - pos : chunk;
        int st = vp_logfmt_reader_push(&r, data + pos, c, &used, &rec);
        pos += used;
        if (st < 0) break;
        if (st == VP_LOGFMT_GOT_RECORD) {
            unsigned char buf[VP_LOGFMT_MAX_RECORD];
            int k = vp_logfmt_record_encode(&rec, buf, sizeof buf);
            n++;
            /* what decodes re-encodes (same size) */
            if (k < 0) __builtin_trap();
        }
    }
    (void)vp_logfmt_reader_finish(&r);
    /* single records anywhere */
    if (size > 4) (void)vp_logfmt_record_decode(data + 1, size - 1, &rec, NULL);
    /* the host loader and a replay with a small arena */
    if (vp_sessionlog_load_buf(&L, data, size, err, sizeof err) == VP_OK) {
        vp_replay_t R;
        vp_sessionlog_stop_text(&L, stop, sizeof stop);
        if (L.n != n) __builtin_trap();
        if (vp_replay_open(&R, &L, (size_t)1 << 20, err, sizeof err) == VP_OK)
            (void)vp_replay_run(&R, &L, 64, err, sizeof err);
        vp_replay_close(&R);
    }
    vp_sessionlog_free(&L);
    return 0;
}
