/* vp_step — see vp_step.h. */
#include <math.h>
#include <string.h>
#include "vp_status.h"
#include "vp_step.h"

/* ---- the block iterator (pure) ---- */

int vp_step_block_init(vp_step_block_t *b, int naxes, const int32_t *delta, const double *rate,
                       const double *acc, double rate_cap)
{
    uint32_t n = 0, d;
    double v = HUGE_VAL, a = HUGE_VAL;
    int i;
    if (!b || !delta || !rate || !acc || naxes < 1 || naxes > VP_STEP_MAX_AXES || rate_cap < 0) return VP_EINVAL;
    memset(b, 0, sizeof *b);
    b->naxes = naxes;
    for (i = 0; i < naxes; i++) {
        if (delta[i] == INT32_MIN) return VP_EINVAL;
        d = (uint32_t)(delta[i] < 0 ? -delta[i] : delta[i]);
        if (d > n) n = d;
    }
    for (i = 0; i < naxes; i++) {
        b->delta[i] = delta[i];
        if (!delta[i]) continue;
        d = (uint32_t)(delta[i] < 0 ? -delta[i] : delta[i]);
        if (!(rate[i] > 0) || !(acc[i] > 0) || !isfinite(rate[i]) || !isfinite(acc[i])) return VP_EINVAL;
        /* axis i runs at |d_i| / n of the dominant rate */
        if (rate[i] * n / d < v) v = rate[i] * n / d;
        if (acc[i] * n / d < a) a = acc[i] * n / d;
        b->acc[i] = n / 2;
    }
    b->n = b->end = n;
    if (!n) return VP_OK;
    if (rate_cap > 0 && v > rate_cap) v = rate_cap;
    b->v = v;
    b->a = a;
    b->sa = v * v / (2 * a);
    if (2 * b->sa >= n) { /* triangle */
        b->sa = n / 2.0;
        b->vp = sqrt(a * n);
        b->ta = b->vp / a;
        b->T = 2 * b->ta;
    } else {
        b->vp = v;
        b->ta = v / a;
        b->T = 2 * b->ta + (n - 2 * b->sa) / v;
    }
    return VP_OK;
}

int vp_step_block_ends(vp_step_block_t *b, double vi, double vo)
{
    double a, n, vp2, lim;
    if (!b || !(vi >= 0) || !(vo >= 0) || !isfinite(vi) || !isfinite(vo)) return VP_EINVAL;
    if (!b->n || (vi == 0 && vo == 0)) return VP_OK;
    a = b->a;
    n = b->n;
    if (vi > b->v) vi = b->v;
    if (vo > b->v) vo = b->v;
    /* what the block's acceleration can change over its n steps */
    lim = sqrt(vi * vi + 2 * a * n);
    if (vo > lim) vo = lim;
    lim = sqrt(vo * vo + 2 * a * n);
    if (vi > lim) vi = lim;
    b->ends = 1;
    b->vi = vi;
    b->vo = vo;
    vp2 = b->v * b->v;
    b->sa = (vp2 - vi * vi) / (2 * a);
    b->sd = (vp2 - vo * vo) / (2 * a);
    if (b->sa + b->sd >= n) { /* no cruise: the peak where the two ramps meet */
        vp2 = a * n + 0.5 * (vi * vi + vo * vo);
        b->vp = sqrt(vp2);
        if (b->vp < vi) b->vp = vi;
        if (b->vp < vo) b->vp = vo;
        b->sa = (b->vp * b->vp - vi * vi) / (2 * a);
        if (b->sa > n) b->sa = n;
        b->sd = n - b->sa;
    } else
        b->vp = b->v;
    b->ta = (b->vp - vi) / a;
    b->td = (b->vp - vo) / a;
    b->T = b->ta + (n - b->sa - b->sd) / b->vp + b->td;
    return VP_OK;
}

static double vp_step_block_time(const vp_step_block_t *b, double s)
{
    if (b->stopping) {
        double q = b->v0 * b->v0 - 2 * b->a * (s - b->s0);
        return b->t0 + (b->v0 - sqrt(q > 0 ? q : 0)) / b->a;
    }
    if (b->ends) {
        /* 2s / (sqrt(vi^2 + 2as) + vi): (sqrt(..) - vi) / a without the cancellation */
        double r = b->n - s > 0 ? b->n - s : 0;
        if (s <= b->sa) return 2 * s / (sqrt(b->vi * b->vi + 2 * b->a * s) + b->vi);
        if (s <= b->n - b->sd) return b->ta + (s - b->sa) / b->vp;
        return r > 0 ? b->T - 2 * r / (sqrt(b->vo * b->vo + 2 * b->a * r) + b->vo) : b->T;
    }
    if (s <= b->sa) return sqrt(2 * s / b->a);
    if (s <= b->n - b->sa) return b->ta + (s - b->sa) / b->vp;
    return b->T - sqrt(2 * (b->n - s > 0 ? b->n - s : 0) / b->a);
}

double vp_step_block_rate(const vp_step_block_t *b)
{
    double s = b->k;
    if (b->stopping) {
        double q = b->v0 * b->v0 - 2 * b->a * (s - b->s0);
        return sqrt(q > 0 ? q : 0);
    }
    if (b->ends) {
        if (s <= b->sa) return sqrt(b->vi * b->vi + 2 * b->a * s);
        if (s <= b->n - b->sd) return b->vp;
        return sqrt(b->vo * b->vo + 2 * b->a * (b->n - s > 0 ? b->n - s : 0));
    }
    if (s <= b->sa) return sqrt(2 * b->a * s);
    if (s <= b->n - b->sa) return b->vp;
    return sqrt(2 * b->a * (b->n - s > 0 ? b->n - s : 0));
}

int vp_step_block_next(vp_step_block_t *b, double *t, uint32_t *mask)
{
    uint32_t m = 0;
    int i;
    if (b->k >= b->end) return 0;
    b->k++;
    *t = vp_step_block_time(b, b->k);
    for (i = 0; i < b->naxes; i++) {
        if (!b->delta[i]) continue;
        b->acc[i] += (uint32_t)(b->delta[i] < 0 ? -b->delta[i] : b->delta[i]);
        if (b->acc[i] >= b->n) { b->acc[i] -= b->n; m |= 1u << i; }
    }
    *mask = m;
    return 1;
}

void vp_step_block_stop(vp_step_block_t *b)
{
    double v0, t0;
    uint32_t m;
    if (b->k >= b->end) return;
    v0 = vp_step_block_rate(b);
    t0 = b->k ? vp_step_block_time(b, b->k) : 0;
    m = (uint32_t)floor(v0 * v0 / (2 * b->a));
    b->s0 = b->k;
    b->t0 = t0;
    b->v0 = v0;
    b->stopping = 1;
    if (b->k + m < b->end) b->end = b->k + m;
}

/* ---- the stepper ---- */

enum { VP_RUN_MOVE, VP_RUN_BACKLASH, VP_RUN_HOME };

typedef struct vp_run {
    int mode;
    int axis;            /* VP_RUN_HOME: the axis homed */
    uint32_t watch;      /* VP_RUN_HOME: input bit that stops the block (0: none) */
    int triggered;
    int32_t latch;       /* position of `axis` when `watch` was first seen */
    int contact;         /* VP_RUN_MOVE: VP_STEP_WATCH_* */
    int armed;           /* the contact was seen open: its closing stops the move */
    vp_step_contact_t *c;
    /* VP_RUN_MOVE through a waypoint without stopping: the last block ended at rate vlast
     * (steps/s of its dominant axis), its last tick due at t_last, woken at prev, the motor's
     * interval hmot (0: none yet) */
    int join, retimed;   /* retimed: the last tick was a retime (the motor slower than planned) */
    int carry;           /* a touch's stop goes on along the path's next piece */
    int64_t t_last, prev, hmot;
    double vlast;
} vp_run_t;

static void vp_step_emit_late(vp_step_t *s, int kind, int axis, const char *what, int64_t late_ns, uint64_t count)
{
    vp_step_event_t ev;
    if (!s->cfg.event) return;
    ev.kind = kind;
    ev.axis = axis;
    ev.t_ns = s->io.now(s->io.ctx);
    ev.what = what;
    ev.late_ns = late_ns;
    ev.count = count;
    s->cfg.event(s->cfg.event_ctx, &ev);
}

static void vp_step_emit(vp_step_t *s, int kind, int axis, const char *what)
{
    vp_step_emit_late(s, kind, axis, what, 0, 0);
}

int vp_step_late_bucket(int64_t late_ns)
{
    int64_t us = late_ns / 1000;
    int i = 0;
    while (us > 0 && i < VP_STEP_LATE_BUCKETS - 1) { us >>= 1; i++; }
    return i;
}

static uint32_t vp_step_all(int naxes, uint32_t (*bit)(int))
{
    uint32_t m = 0;
    int i;
    for (i = 0; i < naxes; i++) m |= bit(i);
    return m;
}
static uint32_t vp_bit_step(int a) { return VP_IO_STEP(a); }
static uint32_t vp_bit_en(int a) { return VP_IO_EN(a); }

static int vp_step_write(vp_step_t *s, uint32_t mask, uint32_t values)
{
    int r = s->io.write(s->io.ctx, mask, values);
    if (r >= 0) s->out = (s->out & ~mask) | (values & mask);
    return r;
}

/* Stop everything: step lines low, drivers off, fault latched. */
static int vp_step_trip(vp_step_t *s, int fault, int kind, int axis, const char *what)
{
    uint32_t m = vp_step_all(s->cfg.naxes, vp_bit_step) | vp_step_all(s->cfg.naxes, vp_bit_en);
    vp_step_write(s, m, 0);
    s->enabled = 0;
    s->homed = 0;
    s->fault = fault;
    s->fault_t = s->io.now(s->io.ctx);
    vp_step_emit(s, kind, axis, what);
    return fault == VP_STEP_FAULT_IO ? VP_EIO : VP_EABORT;
}

/* One input sample through the debouncer: a bit changes level after cfg.debounce consecutive
 * samples at the new level; deb_at keeps the axis position at the first of them. */
static int vp_step_sample(vp_step_t *s, uint32_t *deb)
{
    uint32_t in = 0, diff;
    int b;
    if (s->io.read(s->io.ctx, &in) < 0) return VP_EIO;
    s->st.polls++;
    diff = (in ^ s->deb) & ((1u << VP_IO_NIN) - 1);
    for (b = 0; b < VP_IO_NIN; b++) {
        if (!(diff & (1u << b))) { s->deb_n[b] = 0; continue; }
        if (!s->deb_n[b] && b < 16 && (b & 7) < s->cfg.naxes) s->deb_at[b] = s->pos[b & 7];
        if (!s->deb_n[b] && (1u << b) == VP_IO_CONTACT) memcpy(s->contact_at, s->pos, sizeof s->contact_at);
        if (++s->deb_n[b] >= s->cfg.debounce) { s->deb ^= 1u << b; s->deb_n[b] = 0; }
    }
    *deb = s->deb;
    return VP_OK;
}

/* 1 while an input change is being confirmed. */
static int vp_step_deb_busy(const vp_step_t *s)
{
    int b;
    for (b = 0; b < VP_IO_NIN; b++) if (s->deb_n[b]) return 1;
    return 0;
}

/* cfg.debounce samples back to back: the debounced levels of inputs that hold still. */
static int vp_step_settle(vp_step_t *s, uint32_t *deb)
{
    uint32_t k;
    for (k = 0; k < s->cfg.debounce; k++) VP_TRY(vp_step_sample(s, deb));
    return VP_OK;
}

/* Debounced inputs seen between steps: VP_OK to go on, or VP_EABORT after tripping. */
static int vp_step_check(vp_step_t *s, const vp_step_block_t *b, vp_run_t *r, uint32_t in)
{
    int i;
    if (in & VP_IO_ESTOP) return vp_step_trip(s, VP_STEP_FAULT_ESTOP, VP_STEP_EV_ESTOP, -1, "e-stop");
    if (r->contact) {
        /* the touch latch: every axis at the first of the confirming samples */
        if (!(in & VP_IO_CONTACT)) r->armed = 1;
        else if (r->armed && !r->triggered) {
            r->triggered = 1;
            memcpy(r->c->latch, s->contact_at, sizeof r->c->latch);
        }
    }
    if (r->mode == VP_RUN_HOME && r->watch && (in & r->watch) && !r->triggered) {
        r->triggered = 1;
        r->latch = s->deb_at[r->watch & VP_IO_LIM_MIN(r->axis) ? r->axis : 8 + r->axis];
    }
    if (s->cfg.no_hard_limits) return VP_OK;
    for (i = 0; i < b->naxes; i++) {
        if (r->mode == VP_RUN_HOME && i == r->axis && r->watch) continue;
        if ((b->delta[i] < 0 && (in & VP_IO_LIM_MIN(i))) || (b->delta[i] > 0 && (in & VP_IO_LIM_MAX(i))))
            return vp_step_trip(s, VP_STEP_FAULT_LIMIT, VP_STEP_EV_LIMIT, i, "hard limit");
    }
    return VP_OK;
}

/* n samples (1 between steps; cfg.debounce before a block: a switch already closed is seen
 * before the first step), then the checks. */
static int vp_step_poll_n(vp_step_t *s, const vp_step_block_t *b, vp_run_t *r, uint32_t n)
{
    uint32_t in = 0, k;
    for (k = 0; k < n; k++)
        if (vp_step_sample(s, &in) < 0)
            return vp_step_trip(s, VP_STEP_FAULT_IO, VP_STEP_EV_ESTOP, -1, "input read failed");
    return vp_step_check(s, b, r, in);
}

static int vp_step_poll(vp_step_t *s, const vp_step_block_t *b, vp_run_t *r) { return vp_step_poll_n(s, b, r, 1); }

/* Shortest interval (ns) after one of h1 ns that keeps the speed-up within a (steps/s^2),
 * speeds taken at interval midpoints: (1/h2 - 1/h1) / ((h1 + h2) / 2) <= a. */
static int64_t vp_step_min_next(int64_t h1_ns, double a)
{
    double h1 = h1_ns * 1e-9, B = a * h1 / 2 + 1 / h1;
    return (int64_t)ceil(2 / (B + sqrt(B * B + 2 * a)) * 1e9);
}

/* Runs one block through the backend: direction, enable, then timed pulses. */
static int vp_step_run_block(vp_step_t *s, vp_step_block_t *b, vp_run_t *r)
{
    uint32_t dmask = 0, dval = 0, mask, smask;
    int64_t start, t_ns, wake = 0, now, shift = 0, prev = -1, hmot = 0, hcap, late, rise, worst = 0, first = 0;
    int join = r->join && b->ends && b->vi > 0 && r->vlast > 0;
    uint64_t nretime = 0;
    double t;
    int i, rc;
    const int64_t poll = s->cfg.poll_ns;
    if (b->n == 0) return VP_OK;
    for (i = 0; i < b->naxes; i++) {
        if (!b->delta[i]) continue;
        dmask |= VP_IO_DIR(i);
        if ((b->delta[i] > 0) != (s->cfg.axis[i].invert_dir != 0)) dval |= VP_IO_DIR(i);
        if (r->mode != VP_RUN_BACKLASH) s->last_dir[i] = (int8_t)(b->delta[i] > 0 ? 1 : -1);
    }
    /* read before anything moves */
    VP_TRY(vp_step_poll_n(s, b, r, s->cfg.debounce));
    if (r->contact && r->triggered && !r->carry) return VP_OK;
    if ((s->out & dmask) != dval) {
        if (vp_step_write(s, dmask, dval) < 0) return vp_step_trip(s, VP_STEP_FAULT_IO, VP_STEP_EV_ESTOP, -1, "write failed");
        wake = s->cfg.dir_setup_ns;
    }
    r->join = 0;
    if (join && s->enabled) {
        /* on through the waypoint: the first tick follows the last one at the entry rate, the
         * limiter goes on from the motor's interval (scaled to this block's dominant axis) and
         * a direction just written still gets its setup time */
        if (wake) first = s->io.now(s->io.ctx) + wake;
        start = r->t_last;
        prev = r->prev;
        /* on time, the plan is trusted as at a start (its first interval is the junction's);
         * after a retime the motor's interval goes on, scaled to this block's dominant axis */
        if (r->retimed && r->hmot > 0) hmot = (int64_t)llround((double)r->hmot * r->vlast / b->vi);
        goto run;
    }
    if (!s->enabled) {
        uint32_t em = vp_step_all(s->cfg.naxes, vp_bit_en);
        if (vp_step_write(s, em, em) < 0) return vp_step_trip(s, VP_STEP_FAULT_IO, VP_STEP_EV_ESTOP, -1, "write failed");
        s->enabled = 1;
        if (s->cfg.enable_ns > wake) wake = s->cfg.enable_ns;
    }
    if (s->cfg.lead_ns > wake) wake = s->cfg.lead_ns;
    start = s->io.now(s->io.ctx) + wake;
run:
    s->st.blocks++;
    /* the rate cap as an interval (1 ns of deadline rounding allowed) */
    hcap = (int64_t)floor(1e9 / b->v);
    while (vp_step_block_next(b, &t, &mask)) {
        t_ns = start + shift + (int64_t)llround(t * 1e9);
        /* the limiter: never sooner after the last wake-up than the rate cap or the acceleration
         * allow from the motor's interval (after a retime: the re-entry ramp) */
        if (prev >= 0) {
            int64_t early = prev + hcap;
            if (hmot > 0) { int64_t e2 = prev + vp_step_min_next(hmot, b->a); if (e2 > early) early = e2; }
            if (t_ns < early) { if (early - t_ns > 1000) s->st.limited++; shift += early - t_ns; t_ns = early; }
        }
        if (t_ns < first) { shift += first - t_ns; t_ns = first; }
        /* long waits are cut into polls so the e-stop is seen within poll_ns (shorter while a
         * change is being confirmed by the debouncer) */
        for (;;) {
            int64_t p = vp_step_deb_busy(s) ? poll / s->cfg.debounce : poll;
            now = s->io.now(s->io.ctx);
            if (t_ns - now <= p) break;
            s->io.wait_until(s->io.ctx, now + p);
            VP_TRY(vp_step_poll(s, b, r));
        }
        if (r->contact && r->triggered && s->cfg.contact_halt) {   /* touched while waiting: no pulse */
            b->k--;
            b->end = b->k;
            break;
        }
        s->io.wait_until(s->io.ctx, t_ns);
        now = s->io.now(s->io.ctx);
        late = now > t_ns ? now - t_ns : 0;
        s->st.late_hist[vp_step_late_bucket(late)]++;
        if (late > s->st.late_max_ns) s->st.late_max_ns = late;
        if (late > (int64_t)s->cfg.max_late_ns) {
            if (s->cfg.late_fault) {   /* no pulse: stop, homing needed */
                s->st.late_faults++;
                vp_step_write(s, vp_step_all(s->cfg.naxes, vp_bit_step) | vp_step_all(s->cfg.naxes, vp_bit_en), 0);
                s->enabled = 0;
                s->homed = 0;
                s->fault = VP_STEP_FAULT_LATE;
                s->fault_t = now;
                vp_step_emit_late(s, VP_STEP_EV_LATE, -1, "late step", late, 1);
                return VP_EABORT;
            }
            s->st.retimed++;
            nretime++;
            if (late > worst) worst = late;
        }
        smask = 0;
        for (i = 0; i < b->naxes; i++) {
            if (!(mask & (1u << i))) continue;
            smask |= VP_IO_STEP(i);
            s->st.steps[i]++;
            if (r->mode == VP_RUN_BACKLASH) s->st.backlash_steps[i]++;
            else s->pos[i] += b->delta[i] > 0 ? 1 : -1;
        }
        rc = vp_step_write(s, smask, smask);
        /* the pulse is timed from the actual rising edge (read after the write) */
        rise = s->io.now(s->io.ctx);
        /* the schedule goes on from the wake-up: lateness shifts the rest of the move (never a
         * catch-up burst). Up to max_late_ns it is phase jitter (the motor keeps the commanded
         * interval); beyond, a real slow-down the limiter ramps up from. */
        shift += late;
        r->retimed = late > (int64_t)s->cfg.max_late_ns;
        if (prev >= 0) hmot = r->retimed ? now - prev : t_ns - prev;
        prev = now;
        s->io.wait_until(s->io.ctx, rise + s->cfg.pulse_ns);
        if (vp_step_write(s, smask, 0) < 0 || rc < 0)
            return vp_step_trip(s, VP_STEP_FAULT_IO, VP_STEP_EV_ESTOP, -1, "write failed");
        /* inputs after the falling edge; homing or a touch: the switch closed, decelerate to a
         * stop (a touch with contact_halt: stop here) */
        VP_TRY(vp_step_poll(s, b, r));
        if (r->triggered && !b->stopping) {
            if (r->contact && s->cfg.contact_halt) b->end = b->k;
            else vp_step_block_stop(b);
        }
    }
    s->st.move_time += vp_step_block_time(b, b->end);
    if (nretime) vp_step_emit_late(s, VP_STEP_EV_RETIME, -1, "late steps: profile re-entered", worst, nretime);
    if (r->mode == VP_RUN_MOVE && b->ends && b->end == b->n && prev >= 0) {
        /* through the waypoint at speed: planned (vo), or a stop the block could not finish */
        double ve = b->stopping ? vp_step_block_rate(b) : b->vo;
        if (ve > 0) {
            r->join = 1;
            r->t_last = start + shift + (int64_t)llround((b->stopping ? vp_step_block_time(b, b->n) : b->T) * 1e9);
            r->prev = prev;
            r->hmot = hmot;
            r->vlast = ve;
        }
    }
    return VP_OK;
}

static void vp_step_limits(const vp_step_t *s, double *rate, double *acc)
{
    int i;
    for (i = 0; i < s->cfg.naxes; i++) {
        rate[i] = s->cfg.axis[i].max_speed * s->cfg.axis[i].steps_per_unit;
        acc[i] = s->cfg.axis[i].accel * s->cfg.axis[i].steps_per_unit;
    }
}

/* Backlash take-up for reversing axes (at rest: a path's planner stops there), then the block
 * itself between the dominant rates vin and vout. */
static int vp_step_exec(vp_step_t *s, const int32_t *delta, const double *rate, const double *acc, double vin,
                        double vout, vp_run_t *r)
{
    int32_t bd[VP_STEP_MAX_AXES];
    double brate[VP_STEP_MAX_AXES], bacc[VP_STEP_MAX_AXES];
    vp_step_block_t b;
    int i, any = 0;
    vp_run_t br;
    memset(&br, 0, sizeof br);
    br.mode = VP_RUN_BACKLASH;
    vp_step_limits(s, brate, bacc);
    for (i = 0; i < s->cfg.naxes; i++) {
        int dir = delta[i] > 0 ? 1 : delta[i] < 0 ? -1 : 0;
        bd[i] = 0;
        if (dir && s->backlash[i] && s->last_dir[i] && s->last_dir[i] != dir) { bd[i] = dir * s->backlash[i]; any = 1; }
    }
    if (any) {
        VP_TRY(vp_step_block_init(&b, s->cfg.naxes, bd, brate, bacc, s->cfg.max_step_rate));
        VP_TRY(vp_step_run_block(s, &b, &br));
        r->join = 0;
    }
    if (!r->join) vin = 0;     /* the last block stopped (or there was none, or backlash): from rest */
    VP_TRY(vp_step_block_init(&b, s->cfg.naxes, delta, rate, acc, s->cfg.max_step_rate));
    VP_TRY(vp_step_block_ends(&b, vin, vout));
    return vp_step_run_block(s, &b, r);
}

/* A junction's rho: the entry rate of block d1 (steps/s of its dominant axis, n1 steps) over the
 * exit rate of block d0 (n0) that best matches the axes' velocities, weighted by their jerk J. */
static double vp_step_rho(int na, const int32_t *d0, const int32_t *d1, double n0, double n1, const double *J)
{
    double num = 0, den = 0;
    int i;
    for (i = 0; i < na; i++) {
        double ai = d0[i] / n0, bi = d1[i] / n1;
        if (!d0[i] && !d1[i]) continue;
        num += ai * bi / (J[i] * J[i]);
        den += bi * bi / (J[i] * J[i]);
    }
    return den > 0 && num > 0 ? num / den : 0;
}

static void vp_step_jerks(const vp_step_t *s, double *J)
{
    int i;
    for (i = 0; i < s->cfg.naxes; i++) J[i] = s->cfg.axis[i].jerk * s->cfg.axis[i].steps_per_unit;
}

/* How far a touch's stop carries the touching point within a block of n dominant steps whose
 * piece is len long (the caller's bound of the point's travel along it): from its top rate v at
 * acceleration a, or to the block's end (the rest is the next block's); plus the confirming
 * samples (debounce), a step each, at the path's longest step lmax (they can fall on either side
 * of a waypoint). */
static double vp_step_touch_stop(const vp_step_t *s, double len, double n, double v, double a, double lmax)
{
    double run = v * v / (2 * a);
    return (n > 0 ? len / n * (run < n ? run : n) : 0) + 2.0 * s->cfg.debounce * lmax;
}

/* The junction rates of a path's blocks d[0..nb-1] (steps; lastdir: each axis's direction before
 * the first; v0: the first block's entry rate, as the plan before gave it): vin[w], vout[w] in
 * steps/s of block w's dominant axis, the last block ending at rest. A junction is passed at a
 * rate only where every axis moving on either side has a jerk, none reverses with backlash to
 * take up, and the blocks turn by less than 90 degrees in jerk-scaled step space; its exit rate
 * x and entry rate rho * x keep each axis's jump
 * |x a_i - rho x b_i| (a, b: the axis's steps per dominant step before and after) within its
 * jerk, rho the least-squares match of the two velocities. Then grbl's two passes: backward
 * from rest (each block can slow down to its exit), forward from rest (each can speed up). */
static void vp_step_plan(const vp_step_t *s, const int32_t (*d)[VP_STEP_MAX_AXES], int nb, const int8_t *lastdir,
                         const double *rate, const double *acc, double v0, const double *len, double lmax,
                         double stop_max, double *vin, double *vout)
{
    double n[VP_STEP_PLAN], a[VP_STEP_PLAN], v[VP_STEP_PLAN], rho[VP_STEP_PLAN], xmax[VP_STEP_PLAN];
    double J[VP_STEP_MAX_AXES];   /* jerk in steps/s */
    int8_t dir[VP_STEP_MAX_AXES];
    int w, i, na = s->cfg.naxes;
    memcpy(dir, lastdir, sizeof dir);
    vp_step_jerks(s, J);
    for (w = 0; w < nb; w++) {
        vp_step_block_t b;
        n[w] = a[w] = v[w] = 0;
        if (vp_step_block_init(&b, na, d[w], rate, acc, s->cfg.max_step_rate) == VP_OK && b.n) {
            n[w] = b.n; a[w] = b.a; v[w] = b.v;
        }
        vin[w] = vout[w] = rho[w] = xmax[w] = 0;
    }
    for (w = 0; w + 1 < nb; w++) {
        double x;
        int ok = n[w] > 0 && n[w + 1] > 0;
        for (i = 0; i < na; i++) if (d[w][i]) dir[i] = (int8_t)(d[w][i] > 0 ? 1 : -1);
        for (i = 0; ok && i < na; i++) {
            if (!d[w][i] && !d[w + 1][i]) continue;
            if (!(J[i] > 0)) ok = 0;
            else if (d[w + 1][i] && dir[i] && (d[w + 1][i] > 0 ? 1 : -1) != dir[i] && s->backlash[i]) ok = 0;
        }
        if (!ok || !((rho[w] = vp_step_rho(na, d[w], d[w + 1], n[w], n[w + 1], J)) > 0)) continue;
        x = v[w] < v[w + 1] / rho[w] ? v[w] : v[w + 1] / rho[w];
        for (i = 0; i < na; i++) {
            double jump = fabs(d[w][i] / n[w] - rho[w] * d[w + 1][i] / n[w + 1]);
            if (jump > 0 && J[i] / jump < x) x = J[i] / jump;
        }
        if (len) {
            /* watched for a touch: the stop from the entry into block w + 1 ends within that
             * block, and with block w's own stop within stop_max */
            double room = stop_max - vp_step_touch_stop(s, len[w], n[w], v[w], a[w], lmax);
            double l1 = len[w + 1] / n[w + 1], reach = room > 0 ? (l1 > 0 ? room / l1 : n[w + 1]) : 0, vmax;
            if (reach > n[w + 1]) reach = n[w + 1];
            vmax = sqrt(2 * a[w + 1] * reach) / rho[w];
            if (vmax < x) x = vmax;
        }
        xmax[w] = x;
    }
    /* backward: block w+1 slows from its entry rho x to its exit over its steps */
    for (w = nb - 2; w >= 0; w--) {
        double y;
        if (!(xmax[w] > 0)) continue;
        y = sqrt(vout[w + 1] * vout[w + 1] + 2 * a[w + 1] * n[w + 1]) / rho[w];
        vout[w] = xmax[w] < y ? xmax[w] : y;
    }
    /* forward: block w speeds up from its entry over its steps */
    vin[0] = v0;
    for (w = 0; w < nb; w++) {
        double y = sqrt(vin[w] * vin[w] + 2 * a[w] * n[w]);
        if (vout[w] > y) vout[w] = y;
        if (w + 1 < nb) vin[w + 1] = rho[w] * vout[w];
    }
}

int32_t vp_step_to_steps(const vp_step_t *s, int axis, double units)
{
    return (int32_t)llround(units * s->cfg.axis[axis].steps_per_unit);
}

int vp_step_init(vp_step_t *s, const vp_step_config_t *cfg, const vp_io_t *io)
{
    int i;
    if (!s || !cfg || !io || !io->now || !io->wait_until || !io->write || !io->read) return VP_EINVAL;
    if (cfg->naxes < 1 || cfg->naxes > VP_STEP_MAX_AXES) return VP_EINVAL;
    memset(s, 0, sizeof *s);
    s->cfg = *cfg;
    s->io = *io;
    if (!s->cfg.pulse_ns) s->cfg.pulse_ns = 2000;
    if (!s->cfg.dir_setup_ns) s->cfg.dir_setup_ns = 1000;
    if (!s->cfg.enable_ns) s->cfg.enable_ns = 1000000;
    if (!s->cfg.lead_ns) s->cfg.lead_ns = 200000;
    if (!s->cfg.poll_ns) s->cfg.poll_ns = 1000000;
    if (!s->cfg.max_late_ns) s->cfg.max_late_ns = 100000;
    if (!s->cfg.debounce) s->cfg.debounce = 1;
    if (s->cfg.debounce > 64) return VP_EINVAL;
    if (!(s->cfg.max_step_rate >= 0) || s->cfg.max_step_rate > 1e9 / (2.0 * s->cfg.pulse_ns)) return VP_EINVAL;
    if (!s->cfg.max_step_rate) s->cfg.max_step_rate = 1e9 / (2.0 * s->cfg.pulse_ns);
    for (i = 0; i < cfg->naxes; i++) {
        vp_step_axis_t *a = &s->cfg.axis[i];
        double rest;
        if (!(a->steps_per_unit > 0) || !(a->max_speed > 0) || !(a->accel > 0) || !isfinite(a->steps_per_unit) ||
            !isfinite(a->max_speed) || !isfinite(a->accel) || !isfinite(a->travel_min) || !isfinite(a->travel_max) ||
            a->travel_min > a->travel_max || !(a->backlash >= 0) || !isfinite(a->backlash) ||
            a->home_dir < -1 || a->home_dir > 1 || !isfinite(a->home_pos) || !(a->home_seek >= 0) ||
            !(a->home_feed >= 0) || !(a->home_pulloff >= 0) || !isfinite(a->home_seek) ||
            !isfinite(a->home_feed) || !isfinite(a->home_pulloff) || !(a->jerk >= 0) || !isfinite(a->jerk)) return VP_EINVAL;
        if (fabs(a->travel_min) * a->steps_per_unit > 2e9 || fabs(a->travel_max) * a->steps_per_unit > 2e9) return VP_EINVAL;
        if (!a->home_seek) a->home_seek = a->max_speed / 4;
        if (!a->home_feed) a->home_feed = a->home_seek / 10;
        if (!a->home_pulloff) a->home_pulloff = 1;
        if (a->home_seek > a->max_speed || a->home_feed > a->home_seek) return VP_EINVAL;
        rest = a->home_dir ? a->home_pos - a->home_dir * a->home_pulloff : a->home_pos;
        if (rest < a->travel_min || rest > a->travel_max) return VP_EINVAL;
        s->backlash[i] = (int32_t)llround(a->backlash * a->steps_per_unit);
    }
    if (io->write(io->ctx, (1u << VP_IO_NOUT) - 1, 0) < 0) return VP_EIO;
    return VP_OK;
}

int vp_step_enable(vp_step_t *s, int on)
{
    uint32_t em;
    if (!s) return VP_EINVAL;
    if (on && s->fault) return VP_ESTATE;
    em = vp_step_all(s->cfg.naxes, vp_bit_en);
    VP_TRY(vp_step_write(s, em, on ? em : 0));
    if (on && !s->enabled) s->io.wait_until(s->io.ctx, s->io.now(s->io.ctx) + s->cfg.enable_ns);
    s->enabled = on != 0;
    return VP_OK;
}

void vp_step_position(const vp_step_t *s, double *units)
{
    int i;
    for (i = 0; i < s->cfg.naxes; i++) units[i] = s->pos[i] / s->cfg.axis[i].steps_per_unit;
}

int vp_step_set_position(vp_step_t *s, const double *units)
{
    int i;
    if (!s || !units) return VP_EINVAL;
    if (s->fault) return VP_ESTATE;
    for (i = 0; i < s->cfg.naxes; i++) if (!isfinite(units[i])) return VP_EINVAL;
    for (i = 0; i < s->cfg.naxes; i++) s->pos[i] = vp_step_to_steps(s, i, units[i]);
    s->homed = 1;
    return VP_OK;
}

int vp_step_clear_fault(vp_step_t *s)
{
    uint32_t in = 0;
    if (!s) return VP_EINVAL;
    if (vp_step_settle(s, &in) < 0) return VP_EIO;
    if (in & VP_IO_ESTOP) return VP_EABORT;
    if (s->fault) vp_step_emit(s, VP_STEP_EV_CLEARED, -1, "fault cleared");
    s->fault = VP_STEP_FAULT_NONE;
    return VP_OK;
}

/* Checks a target against travel (half a step of slack) and turns it into step deltas. */
static int vp_step_target(const vp_step_t *s, const double *target, const int32_t *from, int32_t *delta)
{
    int i;
    for (i = 0; i < s->cfg.naxes; i++) {
        const vp_step_axis_t *a = &s->cfg.axis[i];
        double h = 0.5 / a->steps_per_unit;
        if (!isfinite(target[i])) return VP_EINVAL;
        if (target[i] < a->travel_min - h || target[i] > a->travel_max + h) return VP_ERANGE;
        delta[i] = vp_step_to_steps(s, i, target[i]) - from[i];
    }
    return VP_OK;
}

int vp_step_move_path(vp_step_t *s, const double *way, int n)
{
    return vp_step_move_watch(s, way, n, VP_STEP_WATCH_NONE, NULL);
}

/* The steps of block w of a path that starts at p0. */
static void vp_step_piece(const vp_step_t *s, const double *way, int w, const int32_t *p0, int32_t *d)
{
    int32_t from[VP_STEP_MAX_AXES];
    int i, na = s->cfg.naxes;
    for (i = 0; i < na; i++) from[i] = w > 0 ? vp_step_to_steps(s, i, way[(size_t)(w - 1) * na + i]) : p0[i];
    for (i = 0; i < na; i++) d[i] = vp_step_to_steps(s, i, way[(size_t)w * na + i]) - from[i];
}

/* The path's longest step (len over the dominant steps of its piece) from p0, in *lmax; and 1
 * when every piece's own touch stop (vp_step_touch_stop) is within stop_max. */
static int vp_step_touch_check(const vp_step_t *s, const int32_t *p0, const double *way, int n, const double *len,
                               double stop_max, double *lmax)
{
    double rate[VP_STEP_MAX_AXES], acc[VP_STEP_MAX_AXES];
    int w, pass;
    *lmax = 0;
    vp_step_limits(s, rate, acc);
    for (pass = 0; pass < 2; pass++)
        for (w = 0; w < n; w++) {
            int32_t d[VP_STEP_MAX_AXES];
            vp_step_block_t b;
            vp_step_piece(s, way, w, p0, d);
            if (!(len[w] >= 0) || vp_step_block_init(&b, s->cfg.naxes, d, rate, acc, s->cfg.max_step_rate) != VP_OK) return 0;
            if (!b.n) continue;
            if (pass == 0 && len[w] / b.n > *lmax) *lmax = len[w] / b.n;
            if (pass == 1 && vp_step_touch_stop(s, len[w], b.n, b.v, b.a, *lmax) > stop_max) return 0;
        }
    return 1;
}

int vp_step_touch_fits(const vp_step_t *s, const double *from, const double *way, int n, const double *len,
                       double stop_max)
{
    int32_t p0[VP_STEP_MAX_AXES];
    double lmax;
    int i;
    if (!s || !way || !len || n < 0 || !(stop_max >= 0)) return 0;
    for (i = 0; i < s->cfg.naxes; i++) p0[i] = from ? vp_step_to_steps(s, i, from[i]) : s->pos[i];
    return vp_step_touch_check(s, p0, way, n, len, stop_max, &lmax);
}

/* The piece the latched position lies on: the touch was confirmed in block w, `debounce`
 * samples (a step each) after the first that saw it, which may lie on a piece before. */
static int vp_step_latch_piece(const vp_step_t *s, const double *way, int w, const int32_t *p0, const int32_t *latch)
{
    int na = s->cfg.naxes;
    while (w > 0) {
        int32_t d[VP_STEP_MAX_AXES], from;
        int i, k = 0;
        vp_step_piece(s, way, w, p0, d);
        for (i = 1; i < na; i++) if ((d[i] < 0 ? -(int64_t)d[i] : d[i]) > (d[k] < 0 ? -(int64_t)d[k] : d[k])) k = i;
        from = vp_step_to_steps(s, k, way[(size_t)(w - 1) * na + k]);
        /* progress along the piece's dominant axis: none yet, an earlier piece's */
        if (d[k] != 0 && (latch[k] - from) * (d[k] > 0 ? 1 : -1) > 0) break;
        w--;
    }
    return w;
}

/* A touch's stop that block w could not finish: the head still moving at r->vlast when it
 * reached its waypoint (or as it was about to start: the touch seen before its first step) goes
 * on along the next piece, entered at the junction's rate (rho) and decelerating from its first
 * step. The plan's watched junctions let it end there; c->rest_way says where it did. */
static int vp_step_stop_on(vp_step_t *s, const double *way, int n, int w, const int32_t *p0, const double *rate,
                           const double *acc, vp_run_t *r, vp_step_contact_t *c)
{
    double J[VP_STEP_MAX_AXES];
    int na = s->cfg.naxes;
    vp_step_jerks(s, J);
    while (r->join && !s->cfg.contact_halt) {
        int32_t d0[VP_STEP_MAX_AXES], d1[VP_STEP_MAX_AXES];
        vp_step_block_t b0, b1;
        double rho;
        int i, j = w + 1;
        /* block w at its waypoint: the stop goes on from w + 1; not yet started: from w */
        for (i = 0; i < na; i++)
            if (vp_step_to_steps(s, i, way[(size_t)w * na + i]) != s->pos[i]) j = w;
        if (j >= n || j == 0) break;
        vp_step_piece(s, way, j - 1, p0, d0);
        vp_step_piece(s, way, j, p0, d1);
        if (vp_step_block_init(&b0, na, d0, rate, acc, s->cfg.max_step_rate) != VP_OK || !b0.n ||
            vp_step_block_init(&b1, na, d1, rate, acc, s->cfg.max_step_rate) != VP_OK || !b1.n)
            break;
        rho = vp_step_rho(na, d0, d1, b0.n, b1.n, J);
        if (!(rho > 0)) break;
        VP_TRY(vp_step_block_ends(&b1, rho * r->vlast, 0));
        vp_step_block_stop(&b1);
        r->carry = 1;
        VP_TRY(vp_step_run_block(s, &b1, r));
        r->carry = 0;
        c->rest_way = w = j;
    }
    return VP_OK;
}

int vp_step_move_watch(vp_step_t *s, const double *way, int n, int watch, vp_step_contact_t *c)
{
    return vp_step_move_touch(s, way, n, watch, NULL, 0, c);
}

int vp_step_move_touch(vp_step_t *s, const double *way, int n, int watch, const double *len, double stop_max,
                       vp_step_contact_t *c)
{
    int32_t delta[VP_STEP_MAX_AXES], at[VP_STEP_MAX_AXES];
    double rate[VP_STEP_MAX_AXES], acc[VP_STEP_MAX_AXES];
    vp_step_contact_t unused;
    vp_run_t r;
    uint32_t in = 0;
    double vin[VP_STEP_PLAN], vout[VP_STEP_PLAN];
    int w, rc, na, i, base = 0, nplan = 0;
    double lmax = 0;
    if (!s || !way || n < 0 || watch < VP_STEP_WATCH_NONE || watch > VP_STEP_WATCH_RELEASE || (watch && !c) ||
        (len && watch != VP_STEP_WATCH_STOP))
        return VP_EINVAL;
    if (!c) c = &unused;
    memset(c, 0, sizeof *c);
    s->path_done = 0;
    if (s->fault || (!s->homed && !s->cfg.allow_unhomed)) return VP_ESTATE;
    na = s->cfg.naxes;
    /* every waypoint first: refuse before anything moves */
    memcpy(at, s->pos, sizeof at);
    for (w = 0; w < n; w++) {
        rc = vp_step_target(s, way + (size_t)w * na, at, delta);
        if (rc < 0) { s->st.refused++; return rc; }
    }
    if (len && !vp_step_touch_check(s, at, way, n, len, stop_max, &lmax)) { s->st.refused++; return VP_ERANGE; }
    vp_step_limits(s, rate, acc);
    memset(&r, 0, sizeof r);
    r.mode = VP_RUN_MOVE;
    r.contact = watch;
    r.c = c;
    if (watch) {
        /* the contact as it stands: closed before a move that may touch is a touch at its start */
        if (vp_step_settle(s, &in) < 0) return vp_step_trip(s, VP_STEP_FAULT_IO, VP_STEP_EV_ESTOP, -1, "input read failed");
        if (in & VP_IO_ESTOP) return vp_step_trip(s, VP_STEP_FAULT_ESTOP, VP_STEP_EV_ESTOP, -1, "e-stop");
        if (!(in & VP_IO_CONTACT)) r.armed = 1;
        else if (watch == VP_STEP_WATCH_STOP) {
            c->hit = c->at_start = 1;
            memcpy(c->latch, s->pos, sizeof c->latch);
            s->st.contacts++;
            s->st.moves++;
            vp_step_emit(s, VP_STEP_EV_CONTACT, -1, "contact closed before the move");
            return VP_OK;
        }
    }
    for (w = 0; w < n; w++) {
        int q = w - base;
        if (w == 0 || (q >= VP_STEP_PLAN / 2 && base + nplan < n)) {
            /* the junctions of the next VP_STEP_PLAN blocks, re-planned halfway through so the
             * path ends at rest only at its end (none when a contact is watched without the
             * pieces' lengths: a stop there is taken from rest); the first block enters at the
             * rate the last plan gave it */
            int32_t d[VP_STEP_PLAN][VP_STEP_MAX_AXES], p[VP_STEP_MAX_AXES];
            int nb = n - w < VP_STEP_PLAN ? n - w : VP_STEP_PLAN, k;
            double v0 = w > 0 && r.join ? vin[q] : 0;
            memset(vin, 0, sizeof vin);
            memset(vout, 0, sizeof vout);
            base = w;
            nplan = nb;
            q = 0;
            if ((!watch || len) && nb > 1) {
                memcpy(p, s->pos, sizeof p);
                for (k = 0; k < nb; k++) {
                    vp_step_target(s, way + (size_t)(w + k) * na, p, d[k]);
                    for (i = 0; i < na; i++) p[i] += d[k][i];
                }
                vp_step_plan(s, (const int32_t (*)[VP_STEP_MAX_AXES])d, nb, s->last_dir, rate, acc, v0,
                             len ? len + w : NULL, lmax, stop_max, vin, vout);
            }
        }
        vp_step_target(s, way + (size_t)w * na, s->pos, delta);
        VP_TRY(vp_step_exec(s, delta, rate, acc, vin[q], vout[q], &r));
        if (r.contact && r.triggered) {
            c->hit = 1;
            c->way = c->rest_way = w;
            s->st.contacts++;
            vp_step_emit(s, VP_STEP_EV_CONTACT, -1, "contact: stopped");
            if (len) {
                VP_TRY(vp_step_stop_on(s, way, n, w, at, rate, acc, &r, c));
                c->way = vp_step_latch_piece(s, way, w, at, c->latch);
            }
            s->path_done = c->rest_way;
            break;
        }
        s->path_done = w + 1;
    }
    if (watch == VP_STEP_WATCH_RELEASE && !r.armed) {
        /* backed off and still closed: the switch cannot be trusted */
        if (vp_step_settle(s, &in) < 0) return vp_step_trip(s, VP_STEP_FAULT_IO, VP_STEP_EV_ESTOP, -1, "input read failed");
        if (in & VP_IO_CONTACT)
            return vp_step_trip(s, VP_STEP_FAULT_CONTACT, VP_STEP_EV_CONTACT, -1,
                                "contact stays closed after backing off (a stuck switch or a broken wire)");
    }
    s->st.moves++;
    return VP_OK;
}

double vp_step_contact_reach(const vp_step_config_t *c, const int *axes, int naxes, double *speed)
{
    double cap, v2 = 0, ratio = 0, h2 = 0, v;
    uint32_t pulse, deb;
    int k;
    if (!c || !axes || naxes < 1) return NAN;
    pulse = c->pulse_ns ? c->pulse_ns : 2000;
    cap = c->max_step_rate > 0 ? c->max_step_rate : 1e9 / (2.0 * pulse);
    deb = c->debounce ? c->debounce : 1;
    for (k = 0; k < naxes; k++) {
        const vp_step_axis_t *a = &c->axis[axes[k]];
        v = a->max_speed;
        if (v * a->steps_per_unit > cap) v = cap / a->steps_per_unit;
        v2 += v * v;
        if (v / a->accel > ratio) ratio = v / a->accel;
        h2 += 1 / (a->steps_per_unit * a->steps_per_unit);
    }
    if (speed) *speed = sqrt(v2);
    return (c->contact_halt ? 0 : 0.5 * sqrt(v2) * ratio) + deb * sqrt(h2);
}

int vp_step_move(vp_step_t *s, const double *target) { return vp_step_move_path(s, target, 1); }

/* Single-axis homing move of `steps` (signed) at `rate` steps/s, stopping when `watch` closes. */
static int vp_step_home_move(vp_step_t *s, int axis, int32_t steps, double rate, uint32_t watch, vp_run_t *r)
{
    int32_t delta[VP_STEP_MAX_AXES];
    double rt[VP_STEP_MAX_AXES], acc[VP_STEP_MAX_AXES];
    memset(delta, 0, sizeof delta);
    vp_step_limits(s, rt, acc);
    delta[axis] = steps;
    rt[axis] = rate;
    memset(r, 0, sizeof *r);
    r->mode = VP_RUN_HOME;
    r->axis = axis;
    r->watch = watch;
    return vp_step_exec(s, delta, rt, acc, 0, 0, r);
}

static int vp_step_home_fail(vp_step_t *s, int axis, int rc, const char *what)
{
    uint32_t m = vp_step_all(s->cfg.naxes, vp_bit_en);
    vp_step_write(s, m | vp_step_all(s->cfg.naxes, vp_bit_step), 0);
    s->enabled = 0;
    s->fault = VP_STEP_FAULT_HOME;
    s->fault_t = s->io.now(s->io.ctx);
    vp_step_emit(s, VP_STEP_EV_HOME_FAIL, axis, what);
    return rc;
}

static int vp_step_home_axis(vp_step_t *s, int i)
{
    const vp_step_axis_t *a = &s->cfg.axis[i];
    const int dir = a->home_dir;
    const double spu = a->steps_per_unit;
    const uint32_t sw = dir < 0 ? VP_IO_LIM_MIN(i) : VP_IO_LIM_MAX(i);
    int32_t pull = (int32_t)llround(a->home_pulloff * spu), seek;
    uint32_t in = 0;
    vp_run_t r;
    if (pull < 1) pull = 1;
    seek = (int32_t)ceil(1.5 * (a->travel_max - a->travel_min) * spu) + 2 * pull;
    if (vp_step_settle(s, &in) < 0) return vp_step_home_fail(s, i, VP_EIO, "input read failed");
    if (in & sw) { /* already on the switch: leave it first */
        VP_TRY(vp_step_home_move(s, i, -dir * pull, a->home_seek * spu, 0, &r));
        if (vp_step_settle(s, &in) < 0 || (in & sw)) return vp_step_home_fail(s, i, VP_EIO, "limit switch stays closed");
    }
    VP_TRY(vp_step_home_move(s, i, dir * seek, a->home_seek * spu, sw, &r));
    if (!r.triggered) return vp_step_home_fail(s, i, VP_ETIMEOUT, "limit switch not found");
    VP_TRY(vp_step_home_move(s, i, -dir * pull, a->home_seek * spu, 0, &r));
    if (vp_step_settle(s, &in) < 0 || (in & sw)) return vp_step_home_fail(s, i, VP_EIO, "limit switch stays closed");
    VP_TRY(vp_step_home_move(s, i, dir * 2 * pull, a->home_feed * spu, sw, &r));
    if (!r.triggered) return vp_step_home_fail(s, i, VP_ETIMEOUT, "limit switch lost on slow approach");
    /* the latched step is where the switch closes: home_pos */
    s->pos[i] = vp_step_to_steps(s, i, a->home_pos) + (s->pos[i] - r.latch);
    VP_TRY(vp_step_home_move(s, i, vp_step_to_steps(s, i, a->home_pos - dir * a->home_pulloff) - s->pos[i],
                             a->home_seek * spu, 0, &r));
    if (vp_step_settle(s, &in) < 0 || (in & sw)) return vp_step_home_fail(s, i, VP_EIO, "limit switch stays closed");
    vp_step_emit(s, VP_STEP_EV_HOMED, i, "axis homed");
    return VP_OK;
}

int vp_step_home(vp_step_t *s)
{
    int order[VP_STEP_MAX_AXES], n = 0, i, j;
    if (!s) return VP_EINVAL;
    if (s->fault) return VP_ESTATE;
    s->homed = 0;
    for (i = 0; i < s->cfg.naxes; i++) {
        if (!s->cfg.axis[i].home_dir) { s->pos[i] = vp_step_to_steps(s, i, s->cfg.axis[i].home_pos); continue; }
        /* insertion by (home_order, index) */
        for (j = n; j > 0 && s->cfg.axis[order[j - 1]].home_order > s->cfg.axis[i].home_order; j--) order[j] = order[j - 1];
        order[j] = i;
        n++;
    }
    for (j = 0; j < n; j++) VP_TRY(vp_step_home_axis(s, order[j]));
    s->homed = 1;
    return VP_OK;
}
