/* The scanner on the MCU: the planner in a static arena, the core's run loop (vp_run), the
 * axes on the step timer (mcu_motion.c) and the host over the link (mcu_link.c).
 *
 *   HELLO (board, arena, axes)      -> START (a session log header: the planner configuration)
 *   the header again, as the MCU logs it, and a START event   -> ACK each
 *   per command: MOVE (after the steps are out: edges, ticks) -> ACK
 *                PROBE (laser on)                             -> RESULT (hit, distance, raw)
 *                its log record                               -> ACK
 *   DONE (status, figures, link counters)                     -> ACK; then HELLO again
 *
 * A STOP in place of any reply ends the session with a PAUSE event. The log the host writes is
 * the bytes the MCU encoded (core/vp_logfmt.h), so it is the MCU's record of the session.
 * (mcu.h is given with -include.) */
#include <string.h>
#include "vp_logfmt.h"
#include "vp_planner.h"
#include "vp_run.h"

#ifndef VP_MCU_ARENA_BYTES
#define VP_MCU_ARENA_BYTES (448u * 1024u)
#endif
#define MCU_TRIES 20u             /* a request sent this often without a reply: the host is gone */
#define MCU_LOG_BOARD "voroprobe-m4"

static uint64_t arena[VP_MCU_ARENA_BYTES / 8];
static vp_planner_t pl;
static vp_logfmt_header_t header;
static uint8_t out[MCU_MAX_PAYLOAD], reply[MCU_MAX_PAYLOAD];
static uint32_t log_seq;
static double last_raw;
static int stopped;               /* the host said STOP */

/* A request whose reply must be ACK (STOP ends the session). */
static int request_ack(uint8_t type, const uint8_t *p, uint16_t n)
{
    uint16_t rlen;
    int t = mcu_link_request(type, p, n, MCU_TRIES, reply, &rlen);
    if (t < 0) return t;
    if (t == MCU_STOP) { stopped = 1; return VP_EABORT; }
    return t == MCU_ACK ? VP_OK : VP_ECORRUPT;
}

static int log_record(vp_logfmt_record_t *r)
{
    int n;
    r->seq = log_seq++;
    n = vp_logfmt_record_encode(r, out, sizeof out);
    if (n < 0) return n;
    return request_ack(MCU_LOG, out, (uint16_t)n);
}

static int log_event(uint32_t event, int32_t code, const char *text)
{
    vp_logfmt_record_t r;
    vp_logfmt_record_event(&r, 0, event, code, text);
    return log_record(&r);
}

static int dev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    mcu_move_report_t rep;
    uint8_t p[84];
    int k, st;
    (void)ctx;
    *collided = 0;
    st = mcu_motion_move(cmd->from, cmd->to, &rep);
    for (k = 0; k < 3; k++) {
        mcu_putf64(p + 8 * k, cmd->from[k]);
        mcu_putf64(p + 24 + 8 * k, cmd->to[k]);
        mcu_put32(p + 48 + 4 * k, rep.edges[k]);
    }
    mcu_put32(p + 60, rep.steps);
    mcu_put32(p + 64, rep.ticks_programmed);
    mcu_put32(p + 68, rep.ticks_measured);
    mcu_put32(p + 72, rep.late_edges);
    mcu_put32(p + 76, rep.inputs);
    mcu_put32(p + 80, (uint32_t)st);
    k = request_ack(MCU_MOVE, p, sizeof p);
    return st != VP_OK ? st : k;
}

static int dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    uint8_t p[56];
    uint16_t rlen;
    int k, t;
    (void)ctx;
    for (k = 0; k < 3; k++) {
        mcu_putf64(p + 8 * k, cmd->from[k]);
        mcu_putf64(p + 24 + 8 * k, cmd->dir[k]);
    }
    mcu_putf64(p + 48, cmd->range);
    mcu_hal_laser(1);
    t = mcu_link_request(MCU_PROBE, p, sizeof p, MCU_TRIES, reply, &rlen);
    mcu_hal_laser(0);
    if (t < 0) return t;
    if (t == MCU_STOP) { stopped = 1; return VP_EABORT; }
    if (t != MCU_RESULT || rlen != 17 || reply[0] > VP_PROBE_TOO_CLOSE) return VP_ECORRUPT;
    res->hit = reply[0];
    res->dist = mcu_getf64(reply + 1);
    last_raw = mcu_getf64(reply + 9);
    return VP_OK;
}

static int after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    vp_logfmt_record_t r;
    (void)ctx;
    if (cmd->kind == VP_CMD_DONE) vp_logfmt_record_event(&r, 0, VP_LOGFMT_EV_DONE, 0, "the planner says DONE");
    else if (cmd->kind == VP_CMD_MOVE) vp_logfmt_record_move(&r, 0, cmd);
    else vp_logfmt_record_probe(&r, 0, cmd, res, last_raw);
    return log_record(&r);
}

/* HELLO until the host answers START with a header it can use. */
static int await_start(void)
{
    uint8_t p[64];
    uint16_t rlen;
    size_t nb = strlen(mcu_board_name);
    int t;
    memset(p, 0, sizeof p);
    p[0] = (uint8_t)MCU_PROTO_VERSION;
    mcu_put32(p + 4, (uint32_t)sizeof arena);
    mcu_put32(p + 8, mcu_axes.tick_hz);
    mcu_put32(p + 12, mcu_axes.steps_per_unit);
    mcu_put32(p + 16, mcu_axes.max_rate);
    mcu_put32(p + 20, mcu_axes.accel);
    mcu_put32(p + 24, mcu_axes.pulse_ticks);
    memcpy(p + 28, mcu_board_name, nb < 35 ? nb : 35);
    for (;;) {
        t = mcu_link_request(MCU_HELLO, p, sizeof p, 0, reply, &rlen);
        if (t != MCU_START) continue;
        return vp_logfmt_header_decode(reply, rlen, &header, NULL) == (int)rlen ? VP_OK : VP_ECORRUPT;
    }
}

static void send_done(int status, const vp_run_result_t *run)
{
    vp_planner_stats_t st;
    uint8_t p[40];
    vp_planner_get_stats(&pl, &st);
    mcu_put32(p, (uint32_t)status);
    mcu_put32(p + 4, (uint32_t)run->commands);
    mcu_put32(p + 8, (uint32_t)st.probes);
    mcu_put32(p + 12, vp_planner_dt(&pl)->ninserted);
    mcu_put32(p + 16, vp_planner_num_facets(&pl));
    mcu_put32(p + 20, (uint32_t)st.arena_peak);
    mcu_put32(p + 24, mcu_link_stats.crc_errors);
    mcu_put32(p + 28, mcu_link_stats.naks);
    mcu_put32(p + 32, mcu_link_stats.timeouts);
    mcu_put32(p + 36, (uint32_t)run->done);
    request_ack(MCU_DONE, p, sizeof p);
}

void mcu_main(void)
{
    mcu_hal_init();
    for (;;) {
        vp_logfmt_header_t h;
        vp_device_ops_t dev;
        vp_run_hooks_t hooks;
        vp_run_result_t run;
        int st, n;
        memset(&run, 0, sizeof run);
        memset(&mcu_link_stats, 0, sizeof mcu_link_stats);
        stopped = 0;
        log_seq = 0;
        st = await_start();
        if (st == VP_OK) st = vp_planner_init(&pl, arena, sizeof arena, &header.cfg);
        if (st != VP_OK) { send_done(st, &run); continue; }
        vp_logfmt_header_init(&h, &header.cfg, sizeof arena, header.units, MCU_LOG_BOARD, header.note);
        n = vp_logfmt_header_encode(&h, out, sizeof out);
        st = n < 0 ? n : request_ack(MCU_LOG, out, (uint16_t)n);
        if (st == VP_OK) st = log_event(VP_LOGFMT_EV_START, 0, "voroprobe mcu");
        if (st == VP_OK) {
            dev.ctx = 0;
            dev.move = dev_move;
            dev.probe = dev_probe;
            dev.touched = 0;
            dev.rays = 0;
            dev.move_path = 0;
            dev.sight = 0;
            memset(&hooks, 0, sizeof hooks);
            hooks.after = after;
            st = vp_run(&pl, &dev, &hooks, 0, &run);
            if (st == VP_EABORT) log_event(VP_LOGFMT_EV_PAUSE, st, stopped ? "stopped by the host" : "e-stop or limit");
            else if (st != VP_OK && st != VP_ETIMEOUT) log_event(VP_LOGFMT_EV_FAULT, st, "the scan stopped");
        }
        mcu_hal_laser(0);
        send_done(st, &run);
    }
}
