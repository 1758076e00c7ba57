/* vp_rtclock — see vp_rtclock.h. */
#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif
#include <time.h>
#include "vp_rtclock.h"
#include "vp_status.h"

int64_t vp_rt_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

double vp_rt_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void vp_rt_init(vp_rtclock_t *c, int64_t spin_ns)
{
    memset(c, 0, sizeof *c);
    c->spin_ns = spin_ns > 0 ? spin_ns : 50000;
#ifdef __linux__
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
#endif
}

static const int64_t vp_rt_bounds[VP_RT_HIST - 1] = { 1000, 2000, 5000, 10000, 20000, 50000, 100000, 200000,
                                                      500000, 1000000, 2000000 };

int vp_rt_wait_until(vp_rtclock_t *c, int64_t t)
{
    int64_t now = vp_rt_now(), late;
    int b;
    if (t - now > c->spin_ns) {
        struct timespec ts;
        int64_t wake = t - c->spin_ns;
        ts.tv_sec = (time_t)(wake / 1000000000);
        ts.tv_nsec = (long)(wake % 1000000000);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) { }
    }
    do now = vp_rt_now(); while (now < t);
    late = now - t;
    c->st.waits++;
    if (late < 0) c->st.early++;
    if (late > c->st.late_max_ns) c->st.late_max_ns = late;
    c->st.late_sum_ns += (double)late;
    for (b = 0; b < VP_RT_HIST - 1 && late >= vp_rt_bounds[b]; b++) { }
    c->st.hist[b]++;
    return VP_OK;
}

int vp_rt_realtime(int prio, char *err, size_t errlen)
{
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = prio;
    if (prio < 1 || prio > 99) { snprintf(err, errlen, "real-time priority %d not in 1..99", prio); return VP_EINVAL; }
    if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0) {
        snprintf(err, errlen, "SCHED_FIFO %d refused: %s (needs root or CAP_SYS_NICE)", prio, strerror(errno));
        return VP_EIO;
    }
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
        snprintf(err, errlen, "mlockall: %s", strerror(errno));
        return VP_EIO;
    }
    return VP_OK;
}

double vp_rt_quantile_us(const vp_rt_stats_t *st, double q)
{
    uint64_t need = (uint64_t)(q * (double)st->waits + 0.5), acc = 0;
    int b;
    for (b = 0; b < VP_RT_HIST - 1; b++) {
        acc += st->hist[b];
        if (acc >= need) return vp_rt_bounds[b] * 1e-3;
    }
    return st->late_max_ns * 1e-3;
}

static int64_t vp_rt_io_now(void *ctx) { (void)ctx; return vp_rt_now(); }
static int vp_rt_io_wait(void *ctx, int64_t t) { return vp_rt_wait_until(ctx, t); }
static int vp_rt_io_write(void *ctx, uint32_t mask, uint32_t values)
{
    vp_rtclock_t *c = ctx;
    c->out = (c->out & ~mask) | (values & mask);
    c->writes++;
    return VP_OK;
}
static int vp_rt_io_read(void *ctx, uint32_t *in) { (void)ctx; *in = 0; return VP_OK; }

vp_io_t vp_rt_null_io(vp_rtclock_t *c)
{
    vp_io_t io;
    io.ctx = c;
    io.now = vp_rt_io_now;
    io.wait_until = vp_rt_io_wait;
    io.write = vp_rt_io_write;
    io.read = vp_rt_io_read;
    return io;
}
