/* The Linux timing loop without GPIO: vp_step driven by vp_rt_null_io (absolute deadlines with
 * clock_nanosleep TIMER_ABSTIME and a short spin, pins not driven). No deadline may be met
 * early; lateness is measured and printed per step rate, not judged (this machine is shared and
 * virtual, so a pass/fail on latency would only measure the neighbours). The GPIO ioctl cost is
 * not included: see test_port_gpiod on a board. VP_TEST_RT=1 adds a SCHED_FIFO run. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_rtclock.h"
#include "vp_status.h"
#include "vp_step.h"
#include "vp_test.h"

static void run(double rate, int rt)
{
    vp_rtclock_t clk;
    vp_io_t io;
    vp_step_config_t c;
    vp_step_t s;
    double target, sec = 0.25;
    int64_t t0, t1;
    memset(&c, 0, sizeof c);
    c.naxes = 1;
    c.axis[0].steps_per_unit = 100;
    c.axis[0].max_speed = rate / 100;
    c.axis[0].accel = rate / 100 * 200;      /* 5 ms ramps: nearly all at full rate */
    c.axis[0].travel_min = 0;
    c.axis[0].travel_max = 1e6;
    c.allow_unhomed = 1;
    c.enable_ns = 1000;
    vp_rt_init(&clk, 50000);
    io = vp_rt_null_io(&clk);
    CHECK(vp_step_init(&s, &c, &io) == VP_OK);
    target = rate * sec / 100;
    t0 = vp_rt_now();
    CHECK(vp_step_move(&s, &target) == VP_OK);
    t1 = vp_rt_now();
    CHECK(s.pos[0] == (int32_t)(rate * sec));
    CHECK(clk.st.early == 0);
    CHECK((clk.out & VP_IO_STEP(0)) == 0);
    printf("%s %7.0f steps/s: %6llu deadlines in %.3f s (plan %.3f), late mean %5.1f us, <=%g us for 99%%, max %6.1f us\n",
           rt ? "fifo" : "    ", rate, (unsigned long long)clk.st.waits, (t1 - t0) * 1e-9,
           rate * sec / rate + 0.01, clk.st.late_sum_ns / clk.st.waits * 1e-3, vp_rt_quantile_us(&clk.st, 0.99),
           clk.st.late_max_ns * 1e-3);
}

int main(void)
{
    static const double rates[] = { 2000, 5000, 10000, 20000, 50000, 100000 };
    vp_rtclock_t clk;
    int64_t t;
    unsigned i;
    char err[200];
    /* never early, even for deadlines already past or closer than the spin */
    vp_rt_init(&clk, 0);
    for (i = 0; i < 2000; i++) {
        t = vp_rt_now() + (int64_t)(i % 7) * 20000 - 10000;
        vp_rt_wait_until(&clk, t);
        CHECK(vp_rt_now() >= t);
    }
    CHECK(clk.st.early == 0 && clk.st.waits == 2000);
    CHECK(vp_rt_realtime(0, err, sizeof err) == VP_EINVAL);
    printf("timing loop only (no GPIO ioctl), 2 deadlines per step (rise, fall), spin 50 us:\n");
    for (i = 0; i < sizeof rates / sizeof rates[0]; i++) run(rates[i], 0);
    if (getenv("VP_TEST_RT") && !strcmp(getenv("VP_TEST_RT"), "1")) {
        if (vp_rt_realtime(50, err, sizeof err) == VP_OK)
            for (i = 0; i < sizeof rates / sizeof rates[0]; i++) run(rates[i], 1);
        else printf("SCHED_FIFO not available: %s\n", err);
    }
    return vp_test_done("test_port_rt");
}
