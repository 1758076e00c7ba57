/* vp_iorec — see vp_iorec.h. */
#include <string.h>
#include "vp_iorec.h"
#include "vp_status.h"

void vp_iorec_init(vp_iorec_t *r, const vp_iorec_config_t *cfg)
{
    int i;
    memset(r, 0, sizeof *r);
    r->cfg = *cfg;
    if (r->cfg.naxes > VP_IO_MAX_AXES) r->cfg.naxes = VP_IO_MAX_AXES;
    for (i = 0; i < r->cfg.naxes; i++) r->motor[i] = r->carriage[i] = cfg->start[i];
}

uint32_t vp_iorec_inputs(const vp_iorec_t *r)
{
    uint32_t in = r->cfg.stuck_inputs;
    int i;
    for (i = 0; i < r->cfg.naxes; i++) {
        if (r->cfg.has_min[i] && r->carriage[i] <= r->cfg.min_sw[i]) in |= VP_IO_LIM_MIN(i);
        if (r->cfg.has_max[i] && r->carriage[i] >= r->cfg.max_sw[i]) in |= VP_IO_LIM_MAX(i);
    }
    if (r->cfg.estop_at >= 0 && r->now >= r->cfg.estop_at && r->now < r->cfg.estop_until) in |= VP_IO_ESTOP;
    return in;
}

static int64_t vp_iorec_now(void *ctx) { return ((vp_iorec_t *)ctx)->now; }

static int vp_iorec_wait(void *ctx, int64_t t)
{
    vp_iorec_t *r = ctx;
    if (t < r->now) r->late_writes++;
    else r->now = t;
    if (r->cfg.stall_ns > 0 && t >= r->cfg.stall_at) { r->now += r->cfg.stall_ns; r->cfg.stall_ns = 0; }
    return VP_OK;
}

/* One motor step: the carriage trails by up to `slack` behind the motor. */
static void vp_iorec_step(vp_iorec_t *r, int a)
{
    int up = ((r->out & VP_IO_DIR(a)) != 0) != (r->cfg.invert_dir[a] != 0);
    r->pulses[a]++;
    if (!(r->out & VP_IO_EN(a))) { r->steps_disabled++; return; }
    r->motor[a] += up ? 1 : -1;
    if (r->carriage[a] < r->motor[a] - r->cfg.slack[a]) r->carriage[a] = r->motor[a] - r->cfg.slack[a];
    if (r->carriage[a] > r->motor[a]) r->carriage[a] = r->motor[a];
}

static int vp_iorec_write(void *ctx, uint32_t mask, uint32_t values)
{
    vp_iorec_t *r = ctx;
    uint32_t change = (r->out ^ values) & mask;
    int b;
    for (b = 0; b < VP_IO_NOUT; b++) {
        uint32_t bit = 1u << b;
        if (!(change & bit)) continue;
        r->out ^= bit;
        r->edges++;
        if (r->n < r->cfg.cap && r->cfg.buf) {
            r->cfg.buf[r->n].t_ns = r->now;
            r->cfg.buf[r->n].line = (uint8_t)b;
            r->cfg.buf[r->n].value = (r->out & bit) != 0;
            r->n++;
        } else r->dropped++;
        if (b < r->cfg.naxes && (r->out & bit)) vp_iorec_step(r, b);
    }
    return VP_OK;
}

static int vp_iorec_read(void *ctx, uint32_t *in)
{
    *in = vp_iorec_inputs(ctx);
    return VP_OK;
}

vp_io_t vp_iorec_io(vp_iorec_t *r)
{
    vp_io_t io;
    io.ctx = r;
    io.now = vp_iorec_now;
    io.wait_until = vp_iorec_wait;
    io.write = vp_iorec_write;
    io.read = vp_iorec_read;
    return io;
}
