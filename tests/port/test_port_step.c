/* vp_step with the recording backend: step counts and directions, pulse width and DIR setup,
 * speed and acceleration limits checked from the recorded edge timestamps, every axis within
 * half a step of the straight line (they start and end together), soft limits refuse before any
 * edge, homing against switches (order, latch, failures), backlash take-up against a carriage
 * with slack, direction inversion, e-stop (no pulse after the read that sees it, drivers off
 * within poll_ns, fault, resumable after release and homing), hard limits, an OS stall (no
 * bunching, no speed-up beyond the acceleration), and the generator's own step throughput. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_iorec.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_step.h"
#include "vp_test.h"

#define CAP 2000000
static vp_iorec_edge_t edges[CAP];
static int64_t ts[5][400000];     /* rising STEP edges per axis */
static int dirs[5][400000];
static int nts[5];

static int nev, last_ev_kind, last_ev_axis;
static void on_event(void *ctx, const vp_step_event_t *ev)
{
    (void)ctx;
    nev++;
    last_ev_kind = ev->kind;
    last_ev_axis = ev->axis;
}

static void config(vp_step_config_t *c)
{
    static const double spu[5] = { 80, 80, 400, 40, 40 }, vmax[5] = { 150, 100, 20, 90, 60 },
                        acc[5] = { 1500, 1000, 200, 360, 240 }, lo[5] = { 0, 0, 0, -180, -90 },
                        hi[5] = { 400, 300, 200, 180, 90 };
    int i;
    memset(c, 0, sizeof *c);
    c->naxes = 5;
    for (i = 0; i < 5; i++) {
        c->axis[i].steps_per_unit = spu[i];
        c->axis[i].max_speed = vmax[i];
        c->axis[i].accel = acc[i];
        c->axis[i].travel_min = lo[i];
        c->axis[i].travel_max = hi[i];
        c->axis[i].home_pulloff = 3;
        c->axis[i].home_order = 1;
    }
    c->axis[0].home_dir = -1; c->axis[0].home_pos = -2;
    c->axis[1].home_dir = -1; c->axis[1].home_pos = -2;
    c->axis[2].home_dir = 1;  c->axis[2].home_pos = 202; c->axis[2].home_order = 0;  /* z first */
    c->axis[3].home_dir = -1; c->axis[3].home_pos = -182;
    c->axis[4].home_dir = 0;  c->axis[4].home_pos = 0;
    c->event = on_event;
}

static void rec_config(vp_iorec_config_t *rc)
{
    memset(rc, 0, sizeof *rc);
    rc->buf = edges;
    rc->cap = CAP;
    rc->naxes = 5;
    rc->estop_at = -1;
    rc->start[0] = 9000; rc->start[1] = 7000; rc->start[2] = -30000; rc->start[3] = 2000; rc->start[4] = 0;
    rc->has_min[0] = rc->has_min[1] = rc->has_min[3] = 1;
    rc->min_sw[0] = 37; rc->min_sw[1] = -11; rc->min_sw[3] = 500;
    rc->has_max[2] = 1; rc->max_sw[2] = 1234;
}

/* Rising STEP edges of each axis from edge i0 on, with the direction from the DIR level. */
static void collect(const vp_iorec_t *r, size_t i0, const int *invert)
{
    size_t i;
    int a, dirlv[5] = { 0, 0, 0, 0, 0 };
    memset(nts, 0, sizeof nts);
    /* DIR levels before i0 */
    for (i = 0; i < i0; i++) {
        int ln = r->cfg.buf[i].line;
        if (ln >= 8 && ln < 13) dirlv[ln - 8] = r->cfg.buf[i].value;
    }
    for (i = i0; i < r->n; i++) {
        int ln = r->cfg.buf[i].line;
        if (ln >= 8 && ln < 13) dirlv[ln - 8] = r->cfg.buf[i].value;
        if (ln < 5 && r->cfg.buf[i].value) {
            a = ln;
            ts[a][nts[a]] = r->cfg.buf[i].t_ns;
            dirs[a][nts[a]] = (dirlv[a] != 0) != (invert && invert[a]) ? 1 : -1;
            nts[a]++;
        }
    }
}

/* Speed over every window of m <= 40 steps: the ideal motion advanced at least m-1 steps
 * (Bresenham keeps each axis within half a step), the dominant axis exactly m. */
static double worst_speed(int a, double vmax, int dominant)
{
    double worst = 0;
    int k, m;
    for (k = 0; k < nts[a]; k++)
        for (m = 1; m <= 40 && k + m < nts[a]; m++) {
            double dt = (ts[a][k + m] - ts[a][k] + 1) * 1e-9;  /* 1 ns: rounding of two deadlines */
            double v = (dominant ? m : m - 1) / dt;
            if (v / vmax > worst) worst = v / vmax;
        }
    return worst;
}

/* Acceleration of axis a from midpoint speeds of single steps (exact for constant acceleration);
 * the slack covers ns rounding of the deadlines. Returns the worst ratio to amax: of speed-ups
 * and slow-downs, or with speedups_only of speed-ups alone (a late wake-up stretches an
 * interval, which only the OS decides). */
static double worst_accel(int a, double amax, int speedups_only)
{
    double worst = 0;
    int k;
    for (k = 0; k + 2 < nts[a]; k++) {
        double h1 = (ts[a][k + 1] - ts[a][k]) * 1e-9, h2 = (ts[a][k + 2] - ts[a][k + 1]) * 1e-9;
        double v1 = 1 / h1, v2 = 1 / h2, dm = (h1 + h2) / 2;
        double slack = (v1 * v1 + v2 * v2) * 1e-9 / dm;
        double acc = ((speedups_only ? v2 - v1 : fabs(v2 - v1)) - slack) / dm;
        if (acc / amax > worst) worst = acc / amax;
    }
    return worst;
}

/* The block iterator alone: Bresenham along the line, the trapezoid's timing, a stop halfway. */
static void test_block_iterator(void)
{
    vp_step_block_t b;
    double t;
    uint32_t mask;
    int k, a;
    int32_t d[5] = { 1000, 600, -300, 0, 7 };
    double rt[5] = { 1e4, 1e4, 1e4, 1e4, 1e4 }, ac[5] = { 1e5, 1e5, 1e5, 1e5, 1e5 };
    int32_t p[5] = { 0, 0, 0, 0, 0 };
    double worst = 0, tprev = 0;
    CHECK(vp_step_block_init(&b, 5, d, rt, ac, 0) == VP_OK);
    CHECK(b.n == 1000);
    for (k = 1; vp_step_block_next(&b, &t, &mask); k++) {
        CHECK(t > tprev);
        tprev = t;
        CHECK(mask & 1);
        for (a = 0; a < 5; a++) {
            if (mask & (1u << a)) p[a] += d[a] > 0 ? 1 : -1;
            if (fabs(p[a] - (double)k * d[a] / 1000) > worst) worst = fabs(p[a] - (double)k * d[a] / 1000);
        }
    }
    CHECK(k - 1 == 1000);
    for (a = 0; a < 5; a++) CHECK(p[a] == d[a]);
    CHECKF(worst <= 0.5 + 1e-12, "Bresenham off the line by %g steps", worst);
    CHECKF(fabs(tprev - b.T) < 1e-12, "end %g vs %g", tprev, b.T);
    /* 1000 steps at 1e4/s, 1e5/s^2: 0.1 s ramps over 500 steps -> a triangle of 0.2 s */
    CHECKF(fabs(b.T - 0.2) < 1e-12 && fabs(b.vp - 1e4) < 1e-9, "T %g vp %g", b.T, b.vp);
    /* a stop halfway decelerates over v^2/2a steps */
    CHECK(vp_step_block_init(&b, 5, d, rt, ac, 0) == VP_OK);
    for (k = 0; k < 250; k++) vp_step_block_next(&b, &t, &mask);
    vp_step_block_stop(&b);
    CHECKF(b.end == 250 + (uint32_t)floor(2 * 1e5 * 250 / (2 * 1e5)), "stop at %u", b.end);
    {
        int32_t bad[5] = { 5, 0, 0, 0, 0 };
        double zr[5] = { 0, 1, 1, 1, 1 };
        CHECK(vp_step_block_init(&b, 5, bad, zr, ac, 0) == VP_EINVAL);
    }
}

/* One scenario on one recorded machine: each part below starts from the state the one before
 * left (homed, moved, faulted), so they stay one function. */
int main(void)
{
    static vp_iorec_t rec;
    vp_iorec_config_t rc;
    vp_step_config_t c;
    vp_step_t s;
    vp_io_t io;
    double pos[5];
    int i, k, a;

    test_block_iterator();

    /* ---- config checks ---- */
    rec_config(&rc);
    vp_iorec_init(&rec, &rc);
    io = vp_iorec_io(&rec);
    config(&c);
    CHECK(vp_step_init(&s, &c, &io) == VP_OK);
    c.axis[0].max_speed = 0;
    CHECK(vp_step_init(&s, &c, &io) == VP_EINVAL);
    config(&c);
    c.axis[0].home_pos = 5;     /* rests at 2 after pull-off: fine */
    CHECK(vp_step_init(&s, &c, &io) == VP_OK);
    c.axis[0].home_pos = -5;    /* rests at -2: outside travel */
    CHECK(vp_step_init(&s, &c, &io) == VP_EINVAL);
    config(&c);
    c.max_step_rate = 400000;   /* faster than 2 us pulses allow */
    CHECK(vp_step_init(&s, &c, &io) == VP_EINVAL);

    /* ---- homing ---- */
    config(&c);
    CHECK(vp_step_init(&s, &c, &io) == VP_OK);
    CHECK(vp_step_move(&s, (double[5]){ 10, 10, 10, 0, 0 }) == VP_ESTATE);   /* not homed */
    nev = 0;
    CHECK(vp_step_home(&s) == VP_OK);
    CHECK(nev == 4 && last_ev_kind == VP_STEP_EV_HOMED);
    vp_step_position(&s, pos);
    CHECKF(fabs(pos[0] - 1) < 1e-12 && fabs(pos[1] - 1) < 1e-12 && fabs(pos[2] - 199) < 1e-12 &&
           fabs(pos[3] + 179) < 1e-12 && pos[4] == 0, "home rest %g %g %g %g %g", pos[0], pos[1], pos[2], pos[3], pos[4]);
    /* the switch point is home_pos: carriage - logical is the switch offset */
    CHECK(rec.carriage[0] - s.pos[0] == 37 - (-160));
    CHECK(rec.carriage[1] - s.pos[1] == -11 - (-160));
    CHECK(rec.carriage[2] - s.pos[2] == 1234 - 202 * 400);
    CHECK(rec.carriage[3] - s.pos[3] == 500 - (-182 * 40));
    /* z homed first: its first pulse precedes every other axis's */
    collect(&rec, 0, NULL);
    CHECK(nts[2] > 0 && nts[0] > 0 && ts[2][0] < ts[0][0] && ts[2][nts[2] - 1] < ts[0][0]);
    CHECK(nts[4] == 0);
    CHECK(rec.steps_disabled == 0 && rec.late_writes == 0);

    /* ---- a coordinated move, checked edge by edge ---- */
    {
        double target[5] = { 301.3, 77.7, 123.45, 35.5, -20.25 };
        double rate[5], accm[5], ratio;
        int32_t from[5], delta[5], dom = 0;
        size_t e0 = rec.n;
        int64_t t_first = -1, t_last = 0;
        memcpy(from, s.pos, sizeof from);
        CHECK(vp_step_move(&s, target) == VP_OK);
        collect(&rec, e0, NULL);
        for (a = 0; a < 5; a++) {
            delta[a] = (int32_t)llround(target[a] * c.axis[a].steps_per_unit) - from[a];
            CHECKF(nts[a] == abs(delta[a]), "axis %d: %d steps, want %d", a, nts[a], abs(delta[a]));
            for (k = 0; k < nts[a]; k++) CHECK(dirs[a][k] == (delta[a] > 0 ? 1 : -1));
            CHECK(s.pos[a] == from[a] + delta[a]);
            CHECK(rec.carriage[a] - s.pos[a] == (a == 0 ? 197 : a == 1 ? 149 : a == 2 ? 1234 - 80800 : a == 3 ? 7780 : 0));
            if (abs(delta[a]) > abs(delta[dom])) dom = a;
            rate[a] = c.axis[a].max_speed * c.axis[a].steps_per_unit;
            accm[a] = c.axis[a].accel * c.axis[a].steps_per_unit;
            if (nts[a]) {
                if (t_first < 0 || ts[a][0] < t_first) t_first = ts[a][0];
                if (ts[a][nts[a] - 1] > t_last) t_last = ts[a][nts[a] - 1];
            }
        }
        /* speed limits per axis over windows */
        for (a = 0; a < 5; a++) {
            double w = worst_speed(a, rate[a], a == dom);
            CHECKF(w <= 1 + 1e-9, "axis %d speed %.4f of max", a, w);
        }
        /* dominant acceleration; the others follow it scaled by |d_a|/n */
        ratio = worst_accel(dom, accm[dom], 0);
        CHECKF(ratio <= 1 + 1e-6, "dominant axis %d acceleration %.6f of max", dom, ratio);
        {
            double amost = 0, vmost = 0, vdom = worst_speed(dom, rate[dom], 1);
            int alim = -1, vlim = -1;
            for (a = 0; a < 5; a++) {
                double sc = (double)abs(delta[a]) / abs(delta[dom]);
                double ar = ratio * accm[dom] * sc / accm[a], vr = vdom * rate[dom] * sc / rate[a];
                CHECKF(ar <= 1 + 1e-6, "axis %d accel %.6f of max", a, ar);
                CHECKF(vr <= 1 + 1e-6, "axis %d speed %.6f of max", a, vr);
                if (ar > amost) { amost = ar; alim = a; }
                if (vr > vmost) { vmost = vr; vlim = a; }
            }
            /* the most constrained axis rules: it reaches its limit */
            CHECKF(amost > 0.99 && vmost > 0.99, "limits not reached: accel %.4f speed %.4f", amost, vmost);
            printf("move: dominant axis %d, %d steps in %.3f s; speed limited by axis %d (%.4f of max), "
                   "acceleration by axis %d (%.4f of max)\n", dom, nts[dom], (t_last - t_first) * 1e-9, vlim, vmost,
                   alim, amost);
        }
        /* on the line: replay all edges in time order, every axis within half a step of the
         * dominant's progress along the segment */
        {
            int32_t p[5] = { 0, 0, 0, 0, 0 };
            double worst = 0;
            size_t i2;
            for (i2 = e0; i2 < rec.n; i2++) {
                int ln = rec.cfg.buf[i2].line;
                if (ln >= 5 || !rec.cfg.buf[i2].value) continue;
                p[ln] += delta[ln] > 0 ? 1 : -1;
                if (i2 + 1 < rec.n && rec.cfg.buf[i2 + 1].t_ns == rec.cfg.buf[i2].t_ns && rec.cfg.buf[i2 + 1].line < 5 &&
                    rec.cfg.buf[i2 + 1].value) continue;   /* same tick: judge after the tick */
                for (a = 0; a < 5; a++) {
                    double lam = (double)abs(p[dom]) / abs(delta[dom]);
                    double dev = fabs(p[a] - lam * delta[a]);
                    if (dev > worst) worst = dev;
                }
            }
            CHECKF(worst <= 0.5 + 1e-9, "path leaves the line by %g steps", worst);
            printf("path: every axis within %.3f steps of the segment\n", worst);
        }
        /* every axis starts in the first and ends in the last ticks of the dominant */
        for (a = 0; a < 5; a++) {
            double span = (double)abs(delta[dom]) / abs(delta[a]);   /* dominant ticks per step of a */
            int first_tick = 0, last_tick = 0;
            for (k = 0; k < nts[dom]; k++) { if (ts[dom][k] == ts[a][0]) first_tick = k + 1; if (ts[dom][k] == ts[a][nts[a] - 1]) last_tick = k + 1; }
            CHECKF(first_tick >= 1 && first_tick <= span / 2 + 1, "axis %d starts at tick %d (span %g)", a, first_tick, span);
            CHECKF(last_tick >= nts[dom] - span / 2 - 1, "axis %d ends at tick %d of %d", a, last_tick, nts[dom]);
        }
        /* pulses: width pulse_ns, DIR settled dir_setup_ns before */
        {
            int64_t rise[5] = { -1, -1, -1, -1, -1 }, dirt[5] = { -1000000, -1000000, -1000000, -1000000, -1000000 };
            int bad_w = 0, bad_d = 0;
            size_t i2;
            for (i2 = 0; i2 < rec.n; i2++) {
                const vp_iorec_edge_t *ed = &rec.cfg.buf[i2];
                if (ed->line >= 8 && ed->line < 13) dirt[ed->line - 8] = ed->t_ns;
                if (ed->line < 5 && ed->value) { rise[ed->line] = ed->t_ns; if (ed->t_ns - dirt[ed->line] < 1000) bad_d++; }
                if (ed->line < 5 && !ed->value && ed->t_ns - rise[ed->line] != 2000) bad_w++;
            }
            CHECKF(bad_w == 0, "%d pulses not 2 us wide", bad_w);
            CHECKF(bad_d == 0, "%d steps within 1 us of a DIR change", bad_d);
        }
    }

    /* ---- soft limits refuse before any edge ---- */
    {
        size_t e0 = rec.n;
        int32_t p0[5];
        memcpy(p0, s.pos, sizeof p0);
        CHECK(vp_step_move(&s, (double[5]){ 401, 10, 10, 0, 0 }) == VP_ERANGE);
        CHECK(vp_step_move(&s, (double[5]){ 10, 10, 10, 0, -91 }) == VP_ERANGE);
        CHECK(vp_step_move_path(&s, (double[10]){ 10, 10, 10, 0, 0, 10, 10, 10, 0, 95 }, 2) == VP_ERANGE);
        CHECK(vp_step_move(&s, (double[5]){ NAN, 10, 10, 0, 0 }) == VP_EINVAL);
        CHECK(rec.n == e0 && memcmp(p0, s.pos, sizeof p0) == 0);
        CHECK(vp_step_move(&s, (double[5]){ 400, 300, 200, 180, 90 }) == VP_OK);   /* the corner is allowed */
    }

    /* ---- backlash: carriage with 24 steps of slack on x ---- */
    {
        static vp_iorec_t r2;
        vp_step_t s2;
        int pass;
        for (pass = 0; pass < 2; pass++) {
            int32_t off;
            rec_config(&rc);
            rc.slack[0] = 24;
            rc.buf = NULL; rc.cap = 0;
            vp_iorec_init(&r2, &rc);
            io = vp_iorec_io(&r2);
            config(&c);
            c.axis[0].backlash = pass ? 24 / 80.0 : 0;
            CHECK(vp_step_init(&s2, &c, &io) == VP_OK);
            CHECK(vp_step_home(&s2) == VP_OK);
            off = r2.carriage[0] - s2.pos[0];
            for (i = 0; i < 6; i++) {
                CHECK(vp_step_move(&s2, (double[5]){ i % 2 ? 50 : 120, 50, 50, 0, 0 }) == VP_OK);
                if (pass) CHECKF(r2.carriage[0] - s2.pos[0] == off, "move %d: carriage off by %d", i, r2.carriage[0] - s2.pos[0] - off);
            }
            if (!pass) CHECK(abs(r2.carriage[0] - s2.pos[0] - off) == 24);   /* uncompensated: lags */
            else CHECKF(s2.st.backlash_steps[0] == 24 * 8, "backlash steps %llu", (unsigned long long)s2.st.backlash_steps[0]);
        }
    }

    /* ---- direction inversion ---- */
    {
        static vp_iorec_t r3;
        vp_step_t s3;
        int inv[5] = { 0, 1, 0, 0, 0 };
        rec_config(&rc);
        rc.invert_dir[1] = 1;
        vp_iorec_init(&r3, &rc);
        io = vp_iorec_io(&r3);
        config(&c);
        c.axis[1].invert_dir = 1;
        CHECK(vp_step_init(&s3, &c, &io) == VP_OK);
        CHECK(vp_step_home(&s3) == VP_OK);      /* homing works through the inverted wiring */
        {
            size_t e0 = r3.n;
            CHECK(vp_step_move(&s3, (double[5]){ 1, 50, 199, -179, 0 }) == VP_OK);
            collect(&r3, e0, inv);
            CHECK(nts[1] == 49 * 80);
            for (k = 0; k < nts[1]; k++) CHECK(dirs[1][k] == 1);
            CHECK((r3.out & VP_IO_DIR(1)) == 0);   /* the DIR line is low for + */
            CHECK(r3.carriage[1] - s3.pos[1] == -11 - (-160));
        }
    }

    /* ---- e-stop ---- */
    {
        static vp_iorec_t r4;
        vp_step_t s4;
        int64_t T, en_off = -1, last_rise = -1;
        int32_t p0[5];
        size_t e0, i2;
        rec_config(&rc);
        vp_iorec_init(&r4, &rc);
        io = vp_iorec_io(&r4);
        config(&c);
        CHECK(vp_step_init(&s4, &c, &io) == VP_OK);
        CHECK(vp_step_home(&s4) == VP_OK);
        memcpy(p0, s4.pos, sizeof p0);
        T = r4.now + 300000000;               /* 0.3 s into a 2.5 s move */
        r4.cfg.estop_at = T;
        r4.cfg.estop_until = T + 2000000000;
        e0 = r4.n;
        nev = 0;
        CHECK(vp_step_move(&s4, (double[5]){ 350, 250, 150, 90, 45 }) == VP_EABORT);
        CHECK(s4.fault == VP_STEP_FAULT_ESTOP && !s4.enabled && !s4.homed);
        CHECK(nev == 1 && last_ev_kind == VP_STEP_EV_ESTOP);
        for (i2 = e0; i2 < r4.n; i2++) {
            const vp_iorec_edge_t *ed = &r4.cfg.buf[i2];
            if (ed->line < 5 && ed->value) last_rise = ed->t_ns;
            if (ed->line >= 16 && ed->line < 21 && !ed->value && en_off < 0) en_off = ed->t_ns;
        }
        /* inputs are read after each falling edge: a pulse already due may still go out, none
         * after the next read (the move's fastest axis steps every 83 us) */
        CHECKF(last_rise >= 0 && last_rise < T + 84000, "last pulse %lld, e-stop %lld", (long long)last_rise, (long long)T);
        CHECKF(en_off >= T && en_off <= T + 1000000, "drivers off %lld ns after the e-stop", (long long)(en_off - T));
        printf("e-stop: last pulse %.1f us after it, drivers off %.1f us after it (poll 1 ms)\n",
               (last_rise - T) * 1e-3, (en_off - T) * 1e-3);
        /* the position is what was issued; no pulse went out after */
        CHECK((r4.out & (VP_IO_STEP(0) | VP_IO_STEP(1) | VP_IO_EN(0))) == 0);
        CHECK(r4.carriage[0] - s4.pos[0] == 197);
        /* resumable: refused while pressed, cleared after, homing again, then moves */
        CHECK(vp_step_move(&s4, (double[5]){ 10, 10, 10, 0, 0 }) == VP_ESTATE);
        CHECK(vp_step_clear_fault(&s4) == VP_EABORT);
        r4.now = T + 2000000000;
        CHECK(vp_step_clear_fault(&s4) == VP_OK && s4.fault == 0);
        CHECK(vp_step_move(&s4, (double[5]){ 10, 10, 10, 0, 0 }) == VP_ESTATE);
        CHECK(vp_step_home(&s4) == VP_OK);
        CHECK(vp_step_move(&s4, (double[5]){ 10, 10, 10, 0, 0 }) == VP_OK);
        /* e-stop while waiting for a slow first step: the drivers still go off within poll_ns */
        c.axis[2].accel = 0.5;        /* first z step after sqrt(2/(0.5*400)) = 100 ms */
        CHECK(vp_step_init(&s4, &c, &io) == VP_OK);
        CHECK(vp_step_set_position(&s4, (double[5]){ 10, 10, 10, 0, 0 }) == VP_OK);
        T = r4.now + 30000000;
        r4.cfg.estop_at = T;
        r4.cfg.estop_until = T + 1000;
        e0 = r4.n;
        CHECK(vp_step_move(&s4, (double[5]){ 10, 10, 20, 0, 0 }) == VP_EABORT);
        en_off = -1;
        last_rise = -1;
        for (i2 = e0; i2 < r4.n; i2++) {
            const vp_iorec_edge_t *ed = &r4.cfg.buf[i2];
            if (ed->line < 5 && ed->value) last_rise = ed->t_ns;
            if (ed->line >= 16 && ed->line < 21 && !ed->value && en_off < 0) en_off = ed->t_ns;
        }
        CHECK(last_rise < 0);
        CHECKF(en_off >= T && en_off <= T + 1000000, "slow move: drivers off %lld ns after", (long long)(en_off - T));
    }

    /* ---- hard limit during a move, homing failures ---- */
    {
        static vp_iorec_t r5;
        vp_step_t s5;
        rec_config(&rc);
        rc.has_max[0] = 1;
        rc.max_sw[0] = 37 + 160 + 200 * 80;   /* a max switch at x = 200 */
        rc.buf = NULL; rc.cap = 0;
        vp_iorec_init(&r5, &rc);
        io = vp_iorec_io(&r5);
        config(&c);
        CHECK(vp_step_init(&s5, &c, &io) == VP_OK);
        CHECK(vp_step_home(&s5) == VP_OK);
        CHECK(vp_step_move(&s5, (double[5]){ 150, 10, 150, 0, 0 }) == VP_OK);
        nev = 0;
        CHECK(vp_step_move(&s5, (double[5]){ 300, 10, 150, 0, 0 }) == VP_EABORT);
        CHECK(s5.fault == VP_STEP_FAULT_LIMIT && nev == 1 && last_ev_kind == VP_STEP_EV_LIMIT && last_ev_axis == 0);
        vp_step_position(&s5, pos);
        CHECKF(fabs(pos[0] - 200) < 0.02, "stopped at x = %g", pos[0]);
        /* a missing switch: not found within 1.5x travel */
        rec_config(&rc);
        rc.has_min[1] = 0;
        rc.buf = NULL; rc.cap = 0;
        vp_iorec_init(&r5, &rc);
        io = vp_iorec_io(&r5);
        config(&c);
        CHECK(vp_step_init(&s5, &c, &io) == VP_OK);
        CHECK(vp_step_home(&s5) == VP_ETIMEOUT);
        CHECK(s5.fault == VP_STEP_FAULT_HOME && last_ev_kind == VP_STEP_EV_HOME_FAIL && last_ev_axis == 1);
        CHECK(abs(r5.carriage[1] - 7000) >= (int)(1.5 * 300 * 80));
        /* a switch stuck closed */
        rec_config(&rc);
        rc.stuck_inputs = VP_IO_LIM_MAX(2);
        rc.buf = NULL; rc.cap = 0;
        vp_iorec_init(&r5, &rc);
        io = vp_iorec_io(&r5);
        CHECK(vp_step_init(&s5, &c, &io) == VP_OK);
        CHECK(vp_step_home(&s5) == VP_EIO && s5.fault == VP_STEP_FAULT_HOME && last_ev_axis == 2);
    }

    /* ---- rate cap and enable ---- */
    {
        static vp_iorec_t r6;
        vp_step_t s6;
        size_t e0;
        int64_t en_on = -1;
        rec_config(&rc);
        vp_iorec_init(&r6, &rc);
        io = vp_iorec_io(&r6);
        config(&c);
        c.max_step_rate = 5000;       /* x could do 12000 steps/s */
        c.allow_unhomed = 1;
        CHECK(vp_step_init(&s6, &c, &io) == VP_OK);
        e0 = r6.n;
        CHECK(vp_step_move(&s6, (double[5]){ 200, 0, 0, 0, 0 }) == VP_OK);
        collect(&r6, e0, NULL);
        CHECK(nts[0] == 16000);
        CHECKF(worst_speed(0, 5000, 1) <= 1 + 1e-9, "capped speed %.4f", worst_speed(0, 5000, 1));
        for (i = (int)e0; i < (int)r6.n; i++) if (r6.cfg.buf[i].line == 16 && r6.cfg.buf[i].value) { en_on = r6.cfg.buf[i].t_ns; break; }
        CHECK(en_on >= 0 && ts[0][0] - en_on >= 1000000);
        CHECK(vp_step_enable(&s6, 0) == VP_OK && (r6.out & VP_IO_EN(0)) == 0);
    }

    /* ---- an OS stall in the middle of a move: the rest is shifted, never bunched, and the
     * motor re-accelerates into the cruise at the axis' acceleration (no speed jump) ---- */
    {
        static vp_iorec_t r8;
        vp_step_t s8;
        size_t e0;
        int64_t minint = INT64_MAX, t0s, t1s;
        rec_config(&rc);
        memset(rc.has_min, 0, sizeof rc.has_min);
        memset(rc.has_max, 0, sizeof rc.has_max);
        vp_iorec_init(&r8, &rc);
        io = vp_iorec_io(&r8);
        config(&c);
        c.allow_unhomed = 1;
        CHECK(vp_step_init(&s8, &c, &io) == VP_OK);
        e0 = r8.n;
        CHECK(vp_step_move(&s8, (double[5]){ 100, 0, 0, 0, 0 }) == VP_OK);
        collect(&r8, e0, NULL);
        t0s = ts[0][nts[0] - 1] - ts[0][0];
        CHECK(s8.st.limited == 0 && s8.st.retimed == 0);   /* on time: the profile as planned */
        r8.cfg.stall_at = r8.now + 400000000;     /* in the cruise of the next move */
        r8.cfg.stall_ns = 3000000;
        e0 = r8.n;
        CHECK(vp_step_move(&s8, (double[5]){ 200, 0, 0, 0, 0 }) == VP_OK);
        collect(&r8, e0, NULL);
        t1s = ts[0][nts[0] - 1] - ts[0][0];
        for (k = 0; k + 1 < nts[0]; k++) if (ts[0][k + 1] - ts[0][k] < minint) minint = ts[0][k + 1] - ts[0][k];
        CHECK(nts[0] == 8000 && s8.st.retimed == 1);
        CHECKF(minint >= (int64_t)(1e9 / 12000) - 1, "steps bunched: %lld ns apart", (long long)minint);
        /* the stall, plus at most the ramp's lost time v / 2a = 50 ms */
        CHECKF(t1s - t0s >= 3000000 && t1s - t0s <= 3000000 + 50000000, "stall added %lld ns", (long long)(t1s - t0s));
        CHECKF(worst_speed(0, 12000, 1) <= 1 + 1e-9, "speed %.4f after a stall", worst_speed(0, 12000, 1));
        CHECKF(worst_accel(0, 1500 * 80, 1) <= 1 + 1e-6, "speed-up %.4f of max after a stall", worst_accel(0, 1500 * 80, 1));
        printf("stall: 3 ms at 12000 steps/s added %.1f ms (re-entry ramp at the axis' acceleration), %llu steps held back\n",
               (t1s - t0s) * 1e-6, (unsigned long long)s8.st.limited);
    }

    /* ---- throughput of the generator itself (count-only recording backend) ---- */
    {
        static vp_iorec_t r7;
        vp_step_t s7;
        struct timespec t0, t1;
        double sec;
        uint64_t steps = 0;
        memset(&rc, 0, sizeof rc);
        rc.naxes = 5;
        rc.estop_at = -1;
        vp_iorec_init(&r7, &rc);
        io = vp_iorec_io(&r7);
        config(&c);
        c.allow_unhomed = 1;
        CHECK(vp_step_init(&s7, &c, &io) == VP_OK);
        clock_gettime(CLOCK_MONOTONIC, &t0);
        for (i = 0; i < 20; i++)
            CHECK(vp_step_move(&s7, i % 2 ? (double[5]){ 0, 0, 0, 0, 0 } : (double[5]){ 400, 300, 200, 180, 90 }) == VP_OK);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        for (a = 0; a < 5; a++) steps += s7.st.steps[a];
        sec = (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
        printf("generator: %.1f M steps (%.1f M dominant ticks) in %.3f s: %.1f M steps/s of CPU\n", steps * 1e-6,
               s7.st.steps[2] * 1e-6, sec, steps * 1e-6 / sec);
    }
    return vp_test_done("test_port_step");
}
