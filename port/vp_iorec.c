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
    r->rng = cfg->seed ^ 0x9e3779b97f4a7c15ull;
}

/* splitmix64 */
static uint64_t vp_iorec_rand(vp_iorec_t *r)
{
    uint64_t z = (r->rng += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Wake-up lateness of a stock Linux kernel: bins [lo, hi) us with their share in ppm, uniform
 * inside a bin. */
static const struct { uint32_t lo_us, hi_us, ppm; } vp_iorec_linux[] = {
    { 0, 2, 500000 }, { 2, 10, 300000 }, { 10, 30, 150000 }, { 30, 100, 40000 },
    { 100, 300, 8000 }, { 300, 1000, 1500 }, { 1000, 3000, 400 }, { 3000, 8000, 100 } };

static int64_t vp_iorec_draw(vp_iorec_t *r)
{
    uint64_t u = vp_iorec_rand(r), p = u % 1000000;
    unsigned i;
    for (i = 0; i + 1 < sizeof vp_iorec_linux / sizeof vp_iorec_linux[0] && p >= vp_iorec_linux[i].ppm; i++)
        p -= vp_iorec_linux[i].ppm;
    return (int64_t)vp_iorec_linux[i].lo_us * 1000 +
           (int64_t)((u >> 20) % ((vp_iorec_linux[i].hi_us - vp_iorec_linux[i].lo_us) * 1000u));
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
    if (r->cfg.contact && r->cfg.contact(r->cfg.contact_ctx, r->carriage)) in |= VP_IO_CONTACT;
    return in;
}

static int64_t vp_iorec_now(void *ctx) { return ((vp_iorec_t *)ctx)->now; }

static int vp_iorec_wait(void *ctx, int64_t t)
{
    vp_iorec_t *r = ctx;
    r->waits++;
    r->wait_t = t;
    if (t < r->now) r->late_writes++;
    else r->now = t;
    if (r->cfg.latency == VP_IOREC_LAT_LINUX) {
        int64_t l = vp_iorec_draw(r);
        r->now += l;
        if (l > 0) r->late_waits++;
        if (l > r->late_max_ns) r->late_max_ns = l;
    }
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
    int64_t late = r->now - r->wait_t;
    int b;
    /* a step rising: its lateness is measured at the start of the write */
    if (!(change & values & ((1u << r->cfg.naxes) - 1)) || late < 0) late = 0;
    if (late > INT32_MAX) late = INT32_MAX;
    r->now += r->cfg.write_ns;
    for (b = 0; b < VP_IO_NOUT; b++) {
        uint32_t bit = 1u << b;
        if (!(change & bit)) continue;
        r->out ^= bit;
        r->edges++;
        if (r->n < r->cfg.cap && r->cfg.buf) {
            r->cfg.buf[r->n].t_ns = r->now;
            r->cfg.buf[r->n].line = (uint8_t)b;
            r->cfg.buf[r->n].value = (r->out & bit) != 0;
            r->cfg.buf[r->n].late_ns = (r->out & bit) && b < r->cfg.naxes ? (int32_t)late : 0;
            r->n++;
        } else r->dropped++;
        if (b < r->cfg.naxes && (r->out & bit)) vp_iorec_step(r, b);
    }
    return VP_OK;
}

static int vp_iorec_read(void *ctx, uint32_t *in)
{
    vp_iorec_t *r = ctx;
    r->now += r->cfg.read_ns;
    r->reads++;
    *in = vp_iorec_inputs(r);
    if (r->cfg.glitch_reads && r->now >= r->cfg.glitch_at) {
        *in |= r->cfg.glitch_bits;
        r->cfg.glitch_reads--;
        r->glitched++;
    }
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
