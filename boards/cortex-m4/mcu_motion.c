/* Step edges from a hardware timer. A move is a straight line in steps: the axis with the
 * most steps (N) follows a trapezoid profile (accelerate at mcu_axes.accel up to max_rate,
 * cruise, decelerate; a triangle when N is too short to reach the rate), the other axes
 * step with it by Bresenham. Step k (1..N) rises at s^-1(k), the time the profile reaches k
 * steps, and falls pulse_ticks later; the timer interrupt makes one edge each and programs
 * the interval after the next one (the timer reloads in hardware, so an interrupt served
 * late does not move the edges). Inputs (e-stop, limits) are read after each falling edge
 * and debounced over MCU_DEBOUNCE samples. (mcu.h is given with -include.) */
#include <string.h>
#include "vp_status.h"

static volatile struct {
    uint32_t n;                /* steps of the leading axis */
    uint32_t edge;             /* the next edge to make: 2k rises step k+1, 2k+1 falls it */
    uint32_t total[3];         /* steps per axis */
    uint32_t err[3];           /* Bresenham accumulators */
    uint32_t dir_bits, step_bits;
    uint32_t edges[3];
    uint32_t t_start, t_first, t_last;
    uint32_t late;
    uint32_t hold[2], inputs; /* debouncing: samples held per input, inputs latched */
    int busy, abort;
    /* the profile, in seconds and steps */
    float accel, rate, n_acc, t_acc, t_total;
} mv;

/* Time in ticks of edge e from the start of the move. */
static uint32_t edge_ticks(uint32_t e)
{
    float k = (float)(e / 2u + 1u), t, n = (float)mv.n;
    if (k <= mv.n_acc) t = __builtin_sqrtf(2.0f * k / mv.accel);
    else if (k <= n - mv.n_acc) t = mv.t_acc + (k - mv.n_acc) / mv.rate;
    else t = mv.t_total - __builtin_sqrtf(2.0f * (n - k) / mv.accel);
    return (uint32_t)(t * (float)mcu_axes.tick_hz + 0.5f) + (e & 1u ? mcu_axes.pulse_ticks : 0u);
}

static uint32_t interval(uint32_t e)
{
    return edge_ticks(e) - (e ? edge_ticks(e - 1u) : 0u);
}

static int32_t to_steps(double x)
{
    double s = x * (double)mcu_axes.steps_per_unit;
    return (int32_t)(s < 0 ? s - 0.5 : s + 0.5);
}

void mcu_motion_edge(void)
{
    uint32_t e = mv.edge, now = mcu_hal_now(), k, in;
    mcu_hal_step_ack();
    if (!mv.busy) return;
    if (e == 0) mv.t_first = now;
    if (e + 1u < 2u * mv.n) {
        /* the timer already runs the interval to edge e + 1: program the one after it */
        if (e + 2u < 2u * mv.n) mcu_hal_step_next(interval(e + 2u));
        /* late: edge e + 1 was due before this interrupt was served */
        if (now - mv.t_start > edge_ticks(e + 1u)) mv.late++;
    }
    mv.t_last = now;
    if ((e & 1u) == 0) {
        mv.step_bits = 0;
        for (k = 0; k < 3; k++) {
            mv.err[k] += mv.total[k];
            if (mv.err[k] >= mv.n) { mv.err[k] -= mv.n; mv.step_bits |= 1u << k; mv.edges[k]++; }
        }
        mcu_hal_step_pins(mv.dir_bits, mv.step_bits);
    } else {
        for (k = 0; k < 3; k++) if (mv.step_bits >> k & 1u) mv.edges[k]++;
        mcu_hal_step_pins(mv.dir_bits, 0);
        in = mcu_hal_inputs();
        for (k = 0; k < 2; k++) {
            if (in >> k & 1u) { if (++mv.hold[k] >= MCU_DEBOUNCE) mv.inputs |= 1u << k; }
            else mv.hold[k] = 0;
        }
        if (mv.inputs) mv.abort = 1;
    }
    mv.edge = e + 1u;
    if (mv.edge == 2u * mv.n || (mv.abort && (mv.edge & 1u) == 0)) {
        mcu_hal_step_stop();
        mv.busy = 0;
    }
}

int mcu_motion_move(const double from[3], const double to[3], mcu_move_report_t *r)
{
    uint32_t k, n = 0;
    float nf;
    memset((void *)&mv, 0, sizeof mv);
    for (k = 0; k < 3; k++) {
        int32_t d = to_steps(to[k]) - to_steps(from[k]);
        if (d < 0) { mv.dir_bits |= 1u << k; d = -d; }
        mv.total[k] = (uint32_t)d;
        if ((uint32_t)d > n) n = (uint32_t)d;
    }
    memset(r, 0, sizeof *r);
    r->steps = n;
    if (n == 0) return VP_OK;
    mv.n = n;
    for (k = 0; k < 3; k++) mv.err[k] = n / 2u;
    nf = (float)n;
    mv.accel = (float)mcu_axes.accel;
    mv.rate = (float)mcu_axes.max_rate;
    mv.n_acc = mv.rate * mv.rate / (2.0f * mv.accel);
    if (2.0f * mv.n_acc >= nf) {          /* a triangle: turn at half way */
        mv.n_acc = nf / 2.0f;
        mv.t_acc = __builtin_sqrtf(nf / mv.accel);
        mv.t_total = 2.0f * mv.t_acc;
    } else {
        mv.t_acc = mv.rate / mv.accel;
        mv.t_total = 2.0f * mv.t_acc + (nf - 2.0f * mv.n_acc) / mv.rate;
    }
    mv.busy = 1;
    mv.t_start = mcu_hal_now();
    mcu_hal_step_pins(mv.dir_bits, 0);
    mcu_hal_step_start(interval(0), interval(1));
    while (mv.busy) mcu_hal_motion_idle();
    for (k = 0; k < 3; k++) r->edges[k] = mv.edges[k];
    r->ticks_programmed = edge_ticks(mv.edge - 1u);
    r->ticks_measured = mv.t_last - mv.t_start;
    r->late_edges = mv.late;
    r->inputs = mv.inputs;
    return mv.abort ? VP_EABORT : VP_OK;
}
