/* vp_rtclock — absolute-deadline waits on CLOCK_MONOTONIC for the Linux backends (POSIX).
 * A wait sleeps with clock_nanosleep(TIMER_ABSTIME) until spin_ns before the deadline, then
 * spins on clock_gettime: it never returns early and its lateness is recorded. Optional
 * SCHED_FIFO priority and locked memory for the stepping thread; the timer slack of the calling
 * thread is set to 1 ns (Linux), else a normal thread wakes up to 50 us late.
 * vp_rt_null_io() is a vp_io backend that keeps real time but drives no pins: it measures what
 * the timing loop alone sustains on a machine without GPIO. */
#ifndef VP_RTCLOCK_H
#define VP_RTCLOCK_H
#include <stddef.h>
#include <stdint.h>
#include "vp_io.h"

#define VP_RT_HIST 12  /* lateness buckets: <1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, >=2000 us */

typedef struct vp_rt_stats {
    uint64_t waits, early;           /* early must stay 0 */
    int64_t late_max_ns;
    double late_sum_ns;
    uint64_t hist[VP_RT_HIST];
} vp_rt_stats_t;

typedef struct vp_rtclock {
    int64_t spin_ns;                 /* 0: 50 us */
    vp_rt_stats_t st;
    uint32_t out;                    /* vp_rt_null_io: the output state */
    uint64_t writes;
} vp_rtclock_t;

/* CLOCK_MONOTONIC: nanoseconds, and seconds (the one monotonic clock of port, host and cli) */
int64_t vp_rt_now(void);
double  vp_rt_seconds(void);
void    vp_rt_init(vp_rtclock_t *c, int64_t spin_ns);
int     vp_rt_wait_until(vp_rtclock_t *c, int64_t t_ns);
/* SCHED_FIFO at prio (1..99) and mlockall; VP_EIO with a reason in err when not permitted. */
int     vp_rt_realtime(int prio, char *err, size_t errlen);
/* Lateness below which a fraction q of the waits fell (from the histogram, bucket bound). */
double  vp_rt_quantile_us(const vp_rt_stats_t *st, double q);
vp_io_t vp_rt_null_io(vp_rtclock_t *c);

#endif
