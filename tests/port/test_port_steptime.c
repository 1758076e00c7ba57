/* Step timing under a stock-kernel latency model: vp_step with the settings of
 * boards/rpi4-gantry.ini (copied below: tests/port sees only the port layer) driving the
 * recording backend with a cost per GPIO write and read and late wake-ups drawn from its built-in
 * histogram (seeded, so every run is the same). Judged on the recorded edge timestamps (the
 * backend's virtual clock, never the wall clock):
 *   - every pulse is at least pulse_us wide between its actual rising and falling edges;
 *   - no two rising edges of one axis closer than 1 / max_step_rate, nor the dominant axis of a
 *     move faster than its max_speed;
 *   - no speed jump: the dominant axis' interval never shrinks faster than its acceleration
 *     allows (speeds at interval midpoints, 1 ns of rounding allowed per interval);
 *   - every retime counted: the steps the backend saw start later than max_late_us after their
 *     deadline are exactly st.retimed and the counts of the RETIME events, and the backend's
 *     lateness of every step bins to exactly st.late_hist;
 *   - late_fault: a late step faults before its pulse, and homing is needed again;
 *   - debouncing (debounce = 3 samples): a 1- or 2-sample glitch on a limit switch, the home
 *     switch or the e-stop is ignored, a 3-sample one is obeyed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_iorec.h"
#include "vp_status.h"
#include "vp_step.h"
#include "vp_test.h"

#define NAX 5
#define CAP 3000000
static vp_iorec_edge_t edges[CAP];
static int64_t ts[400000];
static int32_t lt[400000];       /* the backend's lateness of each of those edges */

static uint64_t nretime_ev, retime_sum;
static int nev, last_kind;
static void on_event(void *ctx, const vp_step_event_t *ev)
{
    (void)ctx;
    nev++;
    last_kind = ev->kind;
    if (ev->kind == VP_STEP_EV_RETIME) { nretime_ev++; retime_sum += ev->count; }
}

/* boards/rpi4-gantry.ini: [timing] and the five axes */
static void rpi4(vp_step_config_t *c)
{
    static const double spu[NAX] = { 80, 80, 400, 35.5556, 35.5556 }, vmax[NAX] = { 150, 120, 15, 90, 60 },
                        acc[NAX] = { 1500, 1200, 150, 360, 240 }, lo[NAX] = { 0, 0, 0, -190, -90 },
                        hi[NAX] = { 400, 300, 300, 190, 90 }, bl[NAX] = { 0.05, 0.05, 0.02, 0.1, 0.1 },
                        hpos[NAX] = { -2, -2, 302, -192, 0 }, seek[NAX] = { 30, 30, 8, 20, 0 },
                        feed[NAX] = { 3, 3, 1, 2, 0 }, pull[NAX] = { 3, 3, 3, 5, 0 };
    static const int hdir[NAX] = { -1, -1, 1, -1, 0 }, order[NAX] = { 2, 2, 1, 3, 0 };
    int i;
    memset(c, 0, sizeof *c);
    c->naxes = NAX;
    for (i = 0; i < NAX; i++) {
        vp_step_axis_t *a = &c->axis[i];
        a->steps_per_unit = spu[i];
        a->max_speed = vmax[i];
        a->accel = acc[i];
        a->travel_min = lo[i];
        a->travel_max = hi[i];
        a->backlash = bl[i];
        a->home_dir = hdir[i];
        a->home_pos = hpos[i];
        a->home_seek = seek[i];
        a->home_feed = feed[i];
        a->home_pulloff = pull[i];
        a->home_order = order[i];
    }
    c->axis[1].invert_dir = 1;
    c->pulse_ns = 4000;          /* pulse_us = 4 */
    c->dir_setup_ns = 2000;      /* dir_setup_us = 2 */
    c->enable_ns = 2000000;      /* enable_ms = 2 */
    c->poll_ns = 1000000;        /* poll_ms = 1 */
    c->max_step_rate = 20000;
    c->max_late_ns = 100000;     /* max_late_us = 100 */
    c->debounce = 3;             /* debounce = 3 */
    c->late_fault = 0;           /* late = reenter */
    c->event = on_event;
}

static void rec(vp_iorec_config_t *rc, int latency)
{
    memset(rc, 0, sizeof *rc);
    rc->buf = edges;
    rc->cap = CAP;
    rc->naxes = NAX;
    rc->estop_at = -1;
    rc->invert_dir[1] = 1;
    rc->start[0] = 9000; rc->start[1] = 7000; rc->start[2] = -20000; rc->start[3] = 2000;
    rc->has_min[0] = rc->has_min[1] = rc->has_min[3] = 1;
    rc->min_sw[0] = 37; rc->min_sw[1] = -11; rc->min_sw[3] = 500;
    rc->has_max[2] = 1; rc->max_sw[2] = 1234;
    if (latency) {
        rc->latency = VP_IOREC_LAT_LINUX;
        rc->seed = 17;
        rc->write_ns = 1500;     /* assumed cost of a GPIO line-set ioctl */
        rc->read_ns = 1500;
    }
}

/* Rising edges of axis a from edge i0 on into ts; returns their count. */
static int rises(const vp_iorec_t *r, size_t i0, int a)
{
    size_t i;
    int n = 0;
    for (i = i0; i < r->n; i++)
        if (r->cfg.buf[i].line == a && r->cfg.buf[i].value) { lt[n] = r->cfg.buf[i].late_ns; ts[n++] = r->cfg.buf[i].t_ns; }
    return n;
}

/* Worst speed-up over single steps as a fraction of amax (speeds at interval midpoints; the
 * slack is 1 ns of rounding on each interval). Slow-downs are the OS's and not counted. The
 * stated tolerance: an interval may give back the lateness (<= max_late, phase jitter) the OS
 * added to the one before it, as recorded by the backend; a later step gives back nothing. */
static double worst_speedup(int n, double amax, int32_t max_late)
{
    double worst = 0;
    int k;
    for (k = 0; k + 2 < n; k++) {
        int64_t j = lt[k + 1] <= max_late ? lt[k + 1] : 0;
        double h1 = (ts[k + 1] - ts[k] - j) * 1e-9, h2 = (ts[k + 2] - ts[k + 1]) * 1e-9;
        double v1 = 1 / h1, v2 = 1 / h2, dm = (h1 + h2) / 2;
        double acc = (v2 - v1 - (v1 * v1 + v2 * v2) * 1e-9 / dm) / dm;
        if (acc / amax > worst) worst = acc / amax;
    }
    return worst;
}

static double latency_run(int latency)
{
    static vp_iorec_t r;
    static const double way[][NAX] = {
        { 10, 150, 150, 0, 0 }, { 390, 150, 150, 0, 0 }, { 10, 150, 150, 0, 0 }, { 10, 290, 150, 0, 0 },
        { 10, 10, 150, 0, 0 }, { 10, 10, 120, 0, 0 }, { 10, 10, 120, 180, 0 }, { 10, 10, 120, -180, 80 },
        { 300, 250, 140, 40, -60 }, { 50, 20, 125, -90, 30 }, { 380, 280, 130, 120, 0 }, { 200, 150, 150, 0, 0 } };
    vp_iorec_config_t rc;
    vp_step_config_t c;
    vp_step_t s;
    vp_io_t io;
    int64_t min_pulse = INT64_MAX, min_gap[NAX], rise_t[NAX], prev_tick = -1;
    uint64_t hist[VP_STEP_LATE_BUCKETS], over = 0, ticks = 0;
    double worst_up = 0, worst_v = 0;
    unsigned w;
    size_t i;
    int a, bad_w = 0;
    rpi4(&c);
    rec(&rc, latency);
    memset(rc.has_min, 0, sizeof rc.has_min);   /* positions declared: no switches */
    memset(rc.has_max, 0, sizeof rc.has_max);
    vp_iorec_init(&r, &rc);
    io = vp_iorec_io(&r);
    CHECK(vp_step_init(&s, &c, &io) == VP_OK);
    CHECK(vp_step_set_position(&s, (double[NAX]){ 200, 150, 150, 0, 0 }) == VP_OK);
    nretime_ev = retime_sum = 0;
    for (w = 0; w < sizeof way / sizeof way[0]; w++) {
        size_t e0 = r.n;
        int32_t from[NAX], d, dmax = 0, dom = 0, n;
        memcpy(from, s.pos, sizeof from);
        CHECKF(vp_step_move(&s, way[w]) == VP_OK, "move %u", w);
        for (a = 0; a < NAX; a++) {
            d = abs(s.pos[a] - from[a]);
            CHECK(s.pos[a] == vp_step_to_steps(&s, a, way[w][a]));
            if (d > dmax) { dmax = d; dom = a; }
        }
        /* the dominant axis of the move: never a speed-up beyond its acceleration, never
         * faster than its max speed (backlash steps of that axis included) */
        n = rises(&r, e0, dom);
        {
            double up = worst_speedup(n, c.axis[dom].accel * c.axis[dom].steps_per_unit, (int32_t)c.max_late_ns);
            double vmax = c.axis[dom].max_speed * c.axis[dom].steps_per_unit;
            int k;
            if (up > worst_up) worst_up = up;
            for (k = 0; k + 1 < n; k++) {
                double v = 1e9 / (ts[k + 1] - ts[k] + 1) / vmax;
                if (v > worst_v) worst_v = v;
            }
        }
    }
    CHECKF(worst_up <= 1 + 1e-6, "speed-up %.6f of the acceleration", worst_up);
    CHECKF(worst_v <= 1 + 1e-9, "speed %.6f of max", worst_v);
    CHECK(r.dropped == 0 && r.steps_disabled == 0);
    /* pulses and rising-edge spacing, every axis, every edge */
    for (a = 0; a < NAX; a++) { min_gap[a] = INT64_MAX; rise_t[a] = -1; }
    memset(hist, 0, sizeof hist);
    for (i = 0; i < r.n; i++) {
        const vp_iorec_edge_t *e = &r.cfg.buf[i];
        if (e->line >= NAX) continue;
        a = e->line;
        if (e->value) {
            if (rise_t[a] >= 0 && e->t_ns - rise_t[a] < min_gap[a]) min_gap[a] = e->t_ns - rise_t[a];
            rise_t[a] = e->t_ns;
            if (e->t_ns != prev_tick) {   /* one write raises every axis of a tick */
                prev_tick = e->t_ns;
                ticks++;
                hist[vp_step_late_bucket(e->late_ns)]++;
                if (e->late_ns > (int32_t)c.max_late_ns) over++;
            }
        } else {
            if (e->t_ns - rise_t[a] < min_pulse) min_pulse = e->t_ns - rise_t[a];
            if (e->t_ns - rise_t[a] < (int64_t)c.pulse_ns) bad_w++;
        }
    }
    CHECKF(bad_w == 0 && min_pulse >= 4000, "%d pulses under 4 us, shortest %lld ns", bad_w, (long long)min_pulse);
    for (a = 0; a < NAX; a++) CHECKF(min_gap[a] >= 50000, "axis %d: rising edges %lld ns apart", a, (long long)min_gap[a]);
    /* every retime counted, and reported */
    CHECKF(over == s.st.retimed && (s.st.retimed > 0) == latency, "backend saw %llu late steps, stepper counted %llu",
           (unsigned long long)over, (unsigned long long)s.st.retimed);
    CHECK(retime_sum == s.st.retimed && (nretime_ev > 0) == latency);
    CHECK(memcmp(hist, s.st.late_hist, sizeof hist) == 0);
    CHECK(s.st.late_faults == 0 && (r.late_waits > 0) == latency);
    if (!latency) {   /* on time: every step on its deadline, the profile as planned */
        CHECK(s.st.late_hist[0] == ticks && s.st.limited == 0 && min_pulse == 4000);
        printf("on time: %llu ticks in %.2f s of machine time, shortest pulse %.3f us, closest rising edges %.1f us (x)\n",
               (unsigned long long)ticks, r.now * 1e-9, min_pulse * 1e-3, min_gap[0] * 1e-3);
        return r.now * 1e-9;
    }
    printf("latency model (seed 17, 1.5 us per write/read): %llu ticks in %.2f s of machine time, %llu late wake-ups "
           "(worst %.2f ms)\n", (unsigned long long)ticks, r.now * 1e-9, (unsigned long long)r.late_waits,
           r.late_max_ns * 1e-6);
    printf("  shortest pulse %.3f us (pulse_us 4); closest rising edges %.1f us (x) %.1f (y) %.1f (z) %.1f (pan) %.1f (tilt), "
           "1/max_step_rate = 50 us\n", min_pulse * 1e-3, min_gap[0] * 1e-3, min_gap[1] * 1e-3, min_gap[2] * 1e-3,
           min_gap[3] * 1e-3, min_gap[4] * 1e-3);
    printf("  worst speed-up %.4f of the acceleration, speed %.4f of max; %llu retimes (> 100 us late) in %llu "
           "events, %llu steps held back by the re-entry limiter, worst lateness %.2f ms\n  lateness histogram (us):",
           worst_up, worst_v, (unsigned long long)s.st.retimed, (unsigned long long)nretime_ev,
           (unsigned long long)s.st.limited, s.st.late_max_ns * 1e-6);
    for (a = 0; a < VP_STEP_LATE_BUCKETS; a++)
        printf(" %s%d:%llu", a == VP_STEP_LATE_BUCKETS - 1 ? ">=" : "<", a == VP_STEP_LATE_BUCKETS - 1 ? 1 << (a - 1) : 1 << a,
               (unsigned long long)s.st.late_hist[a]);
    printf("\n");
    return r.now * 1e-9;
}

/* late_fault: a 3 ms stall faults the move before the late pulse; homing needed again. */
static void late_fault(void)
{
    static vp_iorec_t r;
    vp_iorec_config_t rc;
    vp_step_config_t c;
    vp_step_t s;
    vp_io_t io;
    int64_t last_rise = -1, stall_end;
    size_t i, e0;
    rpi4(&c);
    c.late_fault = 1;
    rec(&rc, 0);
    vp_iorec_init(&r, &rc);
    io = vp_iorec_io(&r);
    CHECK(vp_step_init(&s, &c, &io) == VP_OK);
    CHECK(vp_step_home(&s) == VP_OK);
    r.cfg.stall_at = r.now + 300000000;
    r.cfg.stall_ns = 3000000;
    stall_end = r.cfg.stall_at + 3000000;
    e0 = r.n;
    nev = 0;
    CHECK(vp_step_move(&s, (double[NAX]){ 390, 1, 299, -187, 0 }) == VP_EABORT);
    CHECK(s.fault == VP_STEP_FAULT_LATE && s.st.late_faults == 1 && s.st.retimed == 0 && !s.homed && !s.enabled);
    CHECK(nev == 1 && last_kind == VP_STEP_EV_LATE);
    for (i = e0; i < r.n; i++) if (r.cfg.buf[i].line < NAX && r.cfg.buf[i].value) last_rise = r.cfg.buf[i].t_ns;
    CHECKF(last_rise >= 0 && last_rise < r.cfg.stall_at + 100000, "a pulse %lld ns after the stall began",
           (long long)(last_rise - r.cfg.stall_at));
    CHECK((r.out & (VP_IO_STEP(0) | VP_IO_EN(0))) == 0 && r.now >= stall_end);
    CHECK(vp_step_move(&s, (double[NAX]){ 10, 10, 10, 0, 0 }) == VP_ESTATE);
    CHECK(vp_step_clear_fault(&s) == VP_OK);
    CHECK(vp_step_move(&s, (double[NAX]){ 10, 10, 10, 0, 0 }) == VP_ESTATE);
    CHECK(vp_step_home(&s) == VP_OK);
    CHECK(vp_step_move(&s, (double[NAX]){ 10, 10, 10, 0, 0 }) == VP_OK);
}

/* A machine on the rpi4 settings over a recording backend that keeps no edges, with the
 * glitch of `len` reads on `bits` at `at` (ns; len 0: none): ready, not homed. */
static void glitch_machine(vp_step_t *s, vp_iorec_t *r, uint32_t bits, int64_t at, uint32_t len)
{
    vp_iorec_config_t rc;
    vp_step_config_t c;
    vp_io_t io;
    rpi4(&c);
    rec(&rc, 0);
    rc.buf = NULL;
    rc.cap = 0;
    rc.glitch_bits = bits;
    rc.glitch_at = at;
    rc.glitch_reads = len;
    vp_iorec_init(r, &rc);
    io = vp_iorec_io(r);
    CHECK(vp_step_init(s, &c, &io) == VP_OK);
}

/* One machine, homed; a move of x toward its min switch with a glitch of `len` reads on `bits`
 * 50 ms in. Returns the move's status. */
static int glitch_move(vp_step_t *s, vp_iorec_t *r, uint32_t bits, uint32_t len)
{
    glitch_machine(s, r, 0, 0, 0);
    CHECK(vp_step_home(s) == VP_OK);
    CHECK(vp_step_move(s, (double[NAX]){ 300, 10, 10, 0, 0 }) == VP_OK);
    r->cfg.glitch_bits = bits;
    r->cfg.glitch_at = r->now + 50000000;
    r->cfg.glitch_reads = len;
    nev = 0;
    return vp_step_move(s, (double[NAX]){ 20, 10, 10, 0, 0 });
}

static void debounce(void)
{
    static vp_iorec_t r;
    vp_step_t s;
    uint32_t len;
    int64_t off0 = 0;
    /* hard limit (x min) and e-stop: glitches of 1 and 2 samples ignored, 3 obeyed */
    for (len = 1; len <= 3; len++) {
        int rc = glitch_move(&s, &r, VP_IO_LIM_MIN(0), len);
        CHECK(r.glitched == len);
        if (len < 3) CHECKF(rc == VP_OK && s.fault == 0 && nev == 0 && s.pos[0] == 20 * 80, "limit glitch of %u: %d", len, rc);
        else CHECKF(rc == VP_EABORT && s.fault == VP_STEP_FAULT_LIMIT && last_kind == VP_STEP_EV_LIMIT && s.pos[0] > 20 * 80,
                    "limit held %u samples: %d", len, rc);
        rc = glitch_move(&s, &r, VP_IO_ESTOP, len);
        CHECK(r.glitched == len);
        if (len < 3) CHECKF(rc == VP_OK && s.fault == 0 && nev == 0, "e-stop glitch of %u: %d", len, rc);
        else CHECKF(rc == VP_EABORT && s.fault == VP_STEP_FAULT_ESTOP && last_kind == VP_STEP_EV_ESTOP,
                    "e-stop held %u samples: %d", len, rc);
    }
    /* the home switch, 12 s into homing (x seeking its switch, after z): a 1-sample glitch
     * changes nothing, the latch is the first of the 3 confirming samples (the same switch
     * position as without a glitch); a 3-sample one is taken for the switch, and the slow
     * approach then misses it */
    for (len = 0; len <= 3; len += len ? 2 : 1) {
        int st;
        glitch_machine(&s, &r, VP_IO_LIM_MIN(0), 12000000000, len);
        st = vp_step_home(&s);
        CHECK(r.glitched == len);
        if (len < 3) CHECK(st == VP_OK);
        if (!len) off0 = r.carriage[0] - s.pos[0];
        else if (len < 3) CHECKF(r.carriage[0] - s.pos[0] == off0, "homed %lld steps off after a glitch", (long long)(r.carriage[0] - s.pos[0] - off0));
        else CHECKF(st == VP_ETIMEOUT && s.fault == VP_STEP_FAULT_HOME, "homing with a 3-sample glitch: %d", st);
    }
    CHECKF(off0 == 37 - (-160) + 4, "switch offset %lld", (long long)off0);   /* + x's 4 backlash steps */
    printf("debounce 3: limit and e-stop glitches of 1 and 2 samples ignored, 3 samples obeyed; homing latch exact\n");
}

int main(void)
{
    double t0 = latency_run(0), t1 = latency_run(1);
    printf("the same moves took %.2f s of machine time on time, %.2f s under the latency model\n", t0, t1);
    late_fault();
    debounce();
    return vp_test_done("test_port_steptime");
}
