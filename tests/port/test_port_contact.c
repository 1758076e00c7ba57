/* The head's contact switch (a touch probe at the laser origin) on the recording GPIO backend,
 * through the real machine (kinematics, step generator) of a board like boards/sim.ini with
 * [head] contact = sim. Judged on the recorded edges, replayed here into carriage positions,
 * and on profiles computed here from the axes' limits by formula:
 *   - a MOVE towards a wall that closes the contact at a known x step: the latch is the carriages
 *     at the first read that saw the wall (every axis, a diagonal move too); the head decelerates
 *     (not an instant stop) and stops exactly debounce - 1 + floor(v^2 / (2 a)) dominant steps past
 *     the latch (v: the trapezoid's rate at the confirming step), within contact_stop and within
 *     v^2/(2a) + debounce steps; no step after the stop; `at` is the wall's distance to one step;
 *   - the MOVE back to the move's start returns along the line and ends exactly there; a MOVE that
 *     would go further in is refused before any step;
 *   - contact_halt: no pulse after the confirming sample;
 *   - glitches of 1 and 2 samples are ignored, 3 are a touch;
 *   - a contact closed at rest is a contact at 0 (no step); a stuck contact faults on backing off;
 *   - a board whose contact_stop is below its stopping distance is refused with the message; the
 *     rule (|V| max(V_i/A_i)/2 over x, y, z) is checked against the worst of 2091 directions'
 *     own block profiles (vp_step_block_init) and by hand on boards/rpi4-gantry.ini, whose probe
 *     pin may not be another input's;
 *   - the dry run's switch closes on host-sim's object: `at` against the true ray distance;
 *   - a watched path (contact_stop given, the axes with a jerk): three MOVEs run as one, a wall
 *     just before the first waypoint: the stop carries on past the waypoint along the next piece
 *     (the y steps start only at the waypoint's x; x's intervals only grow from the confirming
 *     step to rest, through the waypoint: no jump), ends within contact_stop and within the
 *     junction's bound, the touch is the first MOVE's (*done 1), and the way back retraces the
 *     pieces (y home before x leaves the waypoint) to the start exactly; with a stop too short
 *     for any piece the step generator refuses the path, nothing moved, and the machine makes
 *     the first MOVE alone; a MOVE turning on its way is watched along its pieces;
 *   - the host's own move (vp_machine_goto) into a wall: stopped, the trigger to one step, backed
 *     off to where it began, VP_EABORT; clear of the wall an ordinary move. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_board.h"
#include "vp_dryrun.h"
#include "vp_iorec.h"
#include "vp_machine.h"
#include "vp_status.h"
#include "vp_step.h"
#include "vp_surface.h"
#include "vp_test.h"

#define CAP 4000000
static vp_iorec_edge_t edges[CAP];

/* boards/sim.ini with a contact switch on the head */
static void board_text(char *buf, size_t n, const char *head_extra)
{
    snprintf(buf, n,
             "[board]\nname = touch\nio = sim\n[timing]\npulse_us = 2\nmax_step_rate = 100000\n"
             "[axis.x]\nsteps_per_unit = 80\nmax_speed = 300\naccel = 3000\ntravel = -300, 300\nhome = min\nhome_pos = -302\nhome_pulloff = 2\n"
             "[axis.y]\nsteps_per_unit = 80\nmax_speed = 300\naccel = 3000\ntravel = -300, 300\nhome = min\nhome_pos = -302\nhome_pulloff = 2\n"
             "[axis.z]\nsteps_per_unit = 400\nmax_speed = 50\naccel = 500\ntravel = -300, 300\nhome = max\nhome_pos = 302\nhome_pulloff = 2\nhome_order = 0\n"
             "[axis.pan]\nsteps_per_unit = 40\nmax_speed = 180\naccel = 720\ntravel = -360, 360\nhome = none\nhome_pos = 0\n"
             "[axis.tilt]\nsteps_per_unit = 40\nmax_speed = 180\naccel = 720\ntravel = -120, 120\nhome = none\nhome_pos = 0\n"
             "[head]\ntilt_offset = 0, 0, 40\nlaser_offset = 20, 0, 0\ncontact = sim\nclear_by = swept\n%s\n"
             "[camera]\nwidth = 640\nheight = 480\nfocal_px = 350\nposition = 0, 30, 10\nlook_at = 100, 0, 0\n"
             "[rangefinder]\nmin_range = 10\nmax_range = 400\nband = 12\n"
             "[omega]\nball = 0, 0, 0, 150\ninterior = 0, 0, 0\neps = 20\nstart = 0, 0, 200\nclearance = 12\n"
             "[sim]\nsurface = sphere*80\n", head_extra);
}

/* The test's wall: closed while x's carriage is at or beyond `at` (or always with `closed`);
 * the carriages at the first read that saw it closed. */
typedef struct wall {
    int32_t at;
    int closed, seen;
    int32_t first[VP_KIN_JOINTS];
} wall_t;

static int wall_contact(void *ctx, const int32_t *carriage)
{
    wall_t *w = ctx;
    int in = w->closed || carriage[0] >= w->at;
    if (in && !w->seen) { w->seen = 1; memcpy(w->first, carriage, sizeof w->first); }
    return in;
}

typedef struct rig {
    vp_board_t b;
    vp_dryrun_t *d;
    vp_machine_t *m;
    wall_t wall;
} rig_t;

static int rig_open(rig_t *r, const char *head_extra, int use_wall)
{
    static char text[4096];
    char err[400];
    vp_dryrun_options_t o;
    int rc;
    memset(r, 0, sizeof *r);
    board_text(text, sizeof text, head_extra);
    rc = vp_board_parse(text, "touch.ini", &r->b, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    if (rc != VP_OK) return rc;
    memset(&o, 0, sizeof o);
    o.edges = edges;
    o.cap = CAP;
    CHECK(vp_dryrun_open(&r->b, &o, &r->d, err, sizeof err) == VP_OK);
    r->m = vp_dryrun_machine(r->d);
    CHECK(r->m->cfg.contact == 1);
    r->wall.at = INT32_MAX;
    if (use_wall) { r->d->rec.cfg.contact = wall_contact; r->d->rec.cfg.contact_ctx = &r->wall; }
    CHECK(vp_machine_home(r->m) == VP_OK);
    CHECK(vp_machine_goto(r->m, r->b.start) == VP_OK);
    return VP_OK;
}

static void move_cmd(vp_cmd_t *c, const double from[3], const double to[3])
{
    memset(c, 0, sizeof *c);
    c->kind = VP_CMD_MOVE;
    memcpy(c->from, from, sizeof c->from);
    memcpy(c->to, to, sizeof c->to);
}

/* Replays the edges from index i0 into carriage positions (motor counts, no slack on this board)
 * given the positions and output levels there; rising STEP edges per axis into *steps; the times
 * of the rising edges of axis `axis` into t (up to nt). Returns that count. */
static long replay(const vp_iorec_t *rec, size_t i0, uint32_t out0, int32_t pos[VP_KIN_JOINTS], long steps[VP_KIN_JOINTS],
                   int axis, int64_t *t, long nt)
{
    uint32_t out = out0;
    size_t i;
    long n = 0;
    int a;
    for (a = 0; a < VP_KIN_JOINTS; a++) steps[a] = 0;
    for (i = i0; i < rec->n; i++) {
        const vp_iorec_edge_t *e = &rec->cfg.buf[i];
        uint32_t bit = 1u << e->line;
        out = e->value ? out | bit : out & ~bit;
        if (e->line < VP_KIN_JOINTS && e->value) {
            a = e->line;
            if (!(out & VP_IO_EN(a))) continue;
            pos[a] += ((out & VP_IO_DIR(a)) != 0) != (rec->cfg.invert_dir[a] != 0) ? 1 : -1;
            steps[a]++;
            if (a == axis && n < nt) t[n++] = e->t_ns;
        }
    }
    return n;
}

/* The trapezoid's dominant rate at step s of n (rest to rest), rate cap v, acceleration a. */
static double trap_rate(double s, double n, double v, double a)
{
    double up = sqrt(2 * a * s), down = sqrt(2 * a * (n - s > 0 ? n - s : 0)), r = up < v ? up : v;
    return down < r ? down : r;
}

static int64_t times[200000];

/* A MOVE along x from the start towards a wall `wall_mm` in; then the MOVE back to the start,
 * or (back_y != 0) from the trigger to the start moved back_y along y: the head first returns to
 * the trigger (x alone), then takes the planner's segment. Returns the overtravel in steps. */
static long touch_x(double wall_mm, const char *head_extra, int halt, double back_y)
{
    rig_t r;
    vp_cmd_t c;
    const double spu = 80, V = 300 * spu, A = 3000 * spu;
    double to[3], at, k_rate;
    int32_t pos[VP_KIN_JOINTS], x0, y0, W;
    long steps[VP_KIN_JOINTS], nt, over, expect, k, n;
    size_t i0;
    uint32_t out0;
    int a;
    if (rig_open(&r, head_extra, 1) != VP_OK) return -1;
    x0 = r.m->step.pos[0];
    y0 = r.m->step.pos[1];
    W = x0 + (int32_t)llround(wall_mm * spu);
    r.wall.at = W;
    memcpy(to, r.b.start, sizeof to);
    to[0] += 100;
    move_cmd(&c, r.b.start, to);
    i0 = r.d->rec.n;
    out0 = r.d->rec.out;
    memcpy(pos, r.d->rec.carriage, sizeof pos);
    CHECK(vp_machine_move(r.m, &c) == VP_OK);
    CHECK(vp_machine_contact(r.m, &at) == 1 && r.m->last.contact && r.m->step.fault == 0);
    nt = replay(&r.d->rec, i0, out0, pos, steps, 0, times, 200000);
    /* the latch: every axis at the first read that saw the wall */
    CHECK(r.wall.seen);
    for (a = 1; a < VP_KIN_JOINTS; a++) CHECKF(r.wall.first[a] == pos[a], "axis %d moved", a);
    CHECKF(r.wall.first[0] == W, "wall at %d, first seen at %d", W, r.wall.first[0]);
    CHECKF(r.m->last.contact_point[0] == W / spu + 20, "trigger at x %.6f, the wall at %.6f", r.m->last.contact_point[0],
           W / spu + 20);
    /* the replayed edges end where the machine says it stands: no step after the stop */
    CHECK(pos[0] == r.m->step.pos[0] && pos[0] == r.d->rec.carriage[0]);
    for (a = 1; a < VP_KIN_JOINTS; a++) CHECK(steps[a] == 0);
    /* the stop: confirmed debounce - 1 steps after the latch, then floor(v^2/(2a)) steps at the
     * trapezoid's rate there (0 with contact_halt) */
    n = (long)llround(100 * spu);
    k = (long)(W - x0) + (long)r.b.debounce - 1;
    k_rate = trap_rate((double)k, (double)n, V, A);
    over = pos[0] - W;
    expect = (long)r.b.debounce - 1 + (halt ? 0 : (long)floor(k_rate * k_rate / (2 * A)));
    CHECKF(over == expect, "stopped %ld steps past the wall, expected %ld", over, expect);
    CHECKF(over <= (halt ? 0 : k_rate * k_rate / (2 * A)) + r.b.debounce, "overtravel %ld steps", over);
    CHECKF(over / spu <= r.b.contact_reach && (r.b.contact_stop == 0 || over / spu <= r.b.contact_stop),
           "overtravel %.3f mm, reach %.3f, contact_stop %g", over / spu, r.b.contact_reach, r.b.contact_stop);
    CHECKF(fabs(r.m->last.overtravel - over / spu) < 1e-9, "machine says %.6f mm", r.m->last.overtravel);
    /* a deceleration: intervals grow after the confirming step, the last step slow */
    if (!halt && nt > 3) {
        long j, grow = 1;
        for (j = k + 1; j < nt; j++) if (times[j] - times[j - 1] < times[j - 1] - times[j - 2] - 1) grow = 0;
        CHECK(grow);
        CHECKF(1e9 / (double)(times[nt - 1] - times[nt - 2]) < 0.1 * k_rate, "last step at %.0f steps/s",
               1e9 / (double)(times[nt - 1] - times[nt - 2]));
    }
    /* at: the wall's distance along the move, to one step */
    CHECKF(fabs(at - wall_mm) <= 1 / spu + 1e-9, "at %.6f mm, the wall %.6f", at, wall_mm);
    /* a MOVE further in is refused, nothing moves */
    {
        double further[3], trig[3];
        size_t e0 = r.d->rec.n;
        memcpy(trig, r.b.start, sizeof trig);
        trig[0] += at;
        memcpy(further, trig, sizeof further);
        further[0] += 5;
        move_cmd(&c, trig, further);
        CHECK(vp_machine_move(r.m, &c) == VP_ESTATE && r.d->rec.n == e0);
        /* back to the move's start: along the line, ending exactly there */
        double back[3];
        memcpy(back, r.b.start, sizeof back);
        back[1] += back_y;
        move_cmd(&c, trig, back);
        i0 = r.d->rec.n;
        out0 = r.d->rec.out;
        memcpy(pos, r.d->rec.carriage, sizeof pos);
        CHECK(vp_machine_move(r.m, &c) == VP_OK && !vp_machine_contact(r.m, NULL) && r.m->step.fault == 0);
        replay(&r.d->rec, i0, out0, pos, steps, 0, NULL, 0);
        CHECKF(pos[0] == x0 && r.m->step.pos[0] == x0, "back at %d, started at %d", pos[0], x0);
        CHECK(pos[1] == y0 + (int32_t)llround(back_y * spu) && pos[1] == r.m->step.pos[1]);
        for (a = 2; a < VP_KIN_JOINTS; a++) CHECK(steps[a] == 0 && pos[a] == r.d->rec.carriage[a]);
        CHECK(steps[0] == over + (W - x0));   /* the overtravel back to the trigger, then the rest */
        if (back_y != 0) {
            /* the overtravel is undone on x alone before y moves: the planner's segment starts
             * at the trigger */
            long xs = 0;
            size_t i;
            for (i = i0; i < r.d->rec.n; i++) {
                const vp_iorec_edge_t *e = &r.d->rec.cfg.buf[i];
                if (e->line == 1 && e->value) break;
                if (e->line == 0 && e->value) xs++;
            }
            CHECKF(xs >= over, "y moved after %ld of the %ld steps back to the trigger", xs, over);
        }
    }
    vp_dryrun_close(r.d);
    return over;
}

/* A diagonal MOVE (z dominant) into a wall on x: every axis latched at the first read that saw
 * it; the stop within the coordinated profile's v^2/(2a) + debounce steps along the path. */
static void touch_diagonal(void)
{
    rig_t r;
    vp_cmd_t c;
    double to[3], d[3] = { 60, 40, -30 }, at, len, rate, acc, v, a, path_step, over_mm;
    static const double spu[3] = { 80, 80, 400 }, vmax[3] = { 300, 300, 50 }, amax[3] = { 3000, 3000, 500 };
    int32_t pos[VP_KIN_JOINTS], x0, z0, W;
    long steps[VP_KIN_JOINTS], n = 0, k, nd;
    size_t i0;
    uint32_t out0;
    int ax;
    if (rig_open(&r, "", 1) != VP_OK) return;
    x0 = r.m->step.pos[0];
    z0 = r.m->step.pos[2];
    W = x0 + 2000;                     /* 25 mm of x: 5/12 of the way */
    r.wall.at = W;
    for (ax = 0; ax < 3; ax++) to[ax] = r.b.start[ax] + d[ax];
    move_cmd(&c, r.b.start, to);
    i0 = r.d->rec.n;
    out0 = r.d->rec.out;
    memcpy(pos, r.d->rec.carriage, sizeof pos);
    CHECK(vp_machine_move(r.m, &c) == VP_OK && vp_machine_contact(r.m, &at));
    replay(&r.d->rec, i0, out0, pos, steps, -1, NULL, 0);
    for (ax = 0; ax < VP_KIN_JOINTS; ax++) CHECK(pos[ax] == r.m->step.pos[ax]);
    /* the machine's latch is the carriages at that read: the trigger point through the kinematics */
    CHECKF(fabs(r.m->last.contact_point[0] - (r.wall.first[0] / 80.0 + 20)) < 1e-9 &&
           fabs(r.m->last.contact_point[1] - r.wall.first[1] / 80.0) < 1e-9 &&
           fabs(r.m->last.contact_point[2] - (r.wall.first[2] / 400.0 + 40)) < 1e-9,
           "trigger %g %g %g", r.m->last.contact_point[0], r.m->last.contact_point[1], r.m->last.contact_point[2]);
    /* the coordinated profile by formula: z dominant (12000 steps) */
    for (ax = 0; ax < 3; ax++) { long s = labs((long)llround(d[ax] * spu[ax])); if (s > n) n = s; }
    v = a = HUGE_VAL;
    len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (ax = 0; ax < 3; ax++) {
        double di = fabs(d[ax] * spu[ax]);
        rate = vmax[ax] * spu[ax] * n / di;
        acc = amax[ax] * spu[ax] * n / di;
        if (rate < v) v = rate;
        if (acc < a) a = acc;
    }
    path_step = len / n;
    /* the dominant tick at the first read that saw the wall: x's Bresenham position */
    nd = labs((long)(r.wall.first[2] - z0));
    k = nd + r.b.debounce - 1;
    v = trap_rate((double)k, (double)n, v, a);
    over_mm = sqrt(pow((pos[0] - r.wall.first[0]) / 80.0, 2) + pow((pos[1] - r.wall.first[1]) / 80.0, 2) +
                   pow((pos[2] - r.wall.first[2]) / 400.0, 2));
    CHECKF(over_mm <= (v * v / (2 * a) + r.b.debounce) * path_step + 1e-9 && over_mm <= r.b.contact_reach,
           "diagonal overtravel %.4f mm, bound %.4f", over_mm, (v * v / (2 * a) + r.b.debounce) * path_step);
    CHECKF(fabs(over_mm - r.m->last.overtravel) < 1e-9, "%.6f vs %.6f", over_mm, r.m->last.overtravel);
    /* at: along the commanded line, the trigger's projection (to a step) */
    CHECKF(fabs(at - 25 * len / 60) <= 1 / 80.0 * len / 60 + 0.5 / 80 + 0.5 / 400 + 1e-9, "at %.4f, wall at %.4f", at, 25 * len / 60);
    printf("diagonal (60, 40, -30) mm into a wall 25 mm along x: latched at x %d y %d z %d steps (the carriages at the "
           "first closed read), stopped %.3f mm past it (bound %.3f mm), at %.4f mm\n",
           r.wall.first[0], r.wall.first[1], r.wall.first[2], over_mm, (v * v / (2 * a) + r.b.debounce) * path_step, at);
    /* back to the start exactly */
    {
        double trig[3];
        int k2;
        for (k2 = 0; k2 < 3; k2++) trig[k2] = r.b.start[k2] + at * d[k2] / len;
        move_cmd(&c, trig, r.b.start);
        CHECK(vp_machine_move(r.m, &c) == VP_OK && !vp_machine_contact(r.m, NULL));
        CHECK(r.m->step.pos[0] == x0 && r.d->rec.carriage[0] == x0);
    }
    vp_dryrun_close(r.d);
}

/* Glitches on the contact during a MOVE: `len` reads 30 ms in. Returns 1 if it was a touch. */
static int glitch(uint32_t len)
{
    rig_t r;
    vp_cmd_t c;
    double to[3];
    int hit;
    if (rig_open(&r, "", 0) != VP_OK) return -1;
    r.d->rec.cfg.contact = NULL;
    memcpy(to, r.b.start, sizeof to);
    to[0] += 100;
    r.d->rec.cfg.glitch_bits = VP_IO_CONTACT;
    r.d->rec.cfg.glitch_at = r.d->rec.now + 30000000;
    r.d->rec.cfg.glitch_reads = len;
    move_cmd(&c, r.b.start, to);
    CHECK(vp_machine_move(r.m, &c) == VP_OK);
    CHECK(r.d->rec.glitched == len);
    hit = vp_machine_contact(r.m, NULL);
    if (!hit) CHECK(r.m->step.pos[0] == (int32_t)llround((to[0] - 20) * 80));
    vp_dryrun_close(r.d);
    return hit;
}

/* A contact closed at rest: a contact at 0, no step; then released (a real touch) or stuck. */
static void at_rest(int stuck)
{
    rig_t r;
    vp_cmd_t c;
    double to[3], at = -1, away[3];
    size_t e0;
    int32_t p0;
    if (rig_open(&r, "", 1) != VP_OK) return;
    r.wall.closed = 1;
    memcpy(to, r.b.start, sizeof to);
    to[0] += 50;
    move_cmd(&c, r.b.start, to);
    e0 = r.d->rec.n;
    p0 = r.m->step.pos[0];
    CHECK(vp_machine_move(r.m, &c) == VP_OK && vp_machine_contact(r.m, &at) && at == 0);
    CHECK(r.d->rec.n == e0 && r.m->step.pos[0] == p0 && r.m->last.overtravel == 0);
    /* the next MOVE backs away 10 mm */
    memcpy(away, r.b.start, sizeof away);
    away[0] -= 10;
    move_cmd(&c, r.b.start, away);
    if (!stuck) {
        r.wall.closed = 0;
        CHECK(vp_machine_move(r.m, &c) == VP_OK && !vp_machine_contact(r.m, NULL) && r.m->step.fault == 0);
        CHECK(r.m->step.pos[0] == p0 - 800);
    } else {
        int rc = vp_machine_move(r.m, &c);
        CHECKF(rc == VP_EABORT && r.m->step.fault == VP_STEP_FAULT_CONTACT && !r.m->step.homed && !r.m->step.enabled,
               "stuck contact: %s, fault %d", vp_strerror(rc), r.m->step.fault);
        CHECK(r.m->step.pos[0] == p0 - 800);   /* it backed off, and the contact stayed closed */
        move_cmd(&c, away, r.b.start);
        CHECK(vp_machine_move(r.m, &c) == VP_ESTATE);
    }
    vp_dryrun_close(r.d);
}

/* A stuck switch (the input forced active): contact at 0, then the MOVE back to the move's start
 * (a null move) faults. */
static void stuck_input(void)
{
    rig_t r;
    vp_cmd_t c;
    double to[3], at = -1;
    if (rig_open(&r, "", 0) != VP_OK) return;
    r.d->rec.cfg.contact = NULL;
    r.d->rec.cfg.stuck_inputs = VP_IO_CONTACT;
    memcpy(to, r.b.start, sizeof to);
    to[2] -= 30;
    move_cmd(&c, r.b.start, to);
    CHECK(vp_machine_move(r.m, &c) == VP_OK && vp_machine_contact(r.m, &at) && at == 0);
    move_cmd(&c, r.b.start, r.b.start);
    CHECK(vp_machine_move(r.m, &c) == VP_EABORT && r.m->step.fault == VP_STEP_FAULT_CONTACT);
    vp_dryrun_close(r.d);
}

/* The rule against each direction's own block profile: worst of many directions. */
static double worst_direction_stop(const vp_step_config_t *sc)
{
    double worst = 0;
    int i, j;
    for (i = 0; i <= 40; i++)
        for (j = 0; j <= 50; j++) {
            double th = 1.5707963267948966 * i / 40, ph = 1.5707963267948966 * j / 50;
            double w[3] = { cos(th) * cos(ph), cos(th) * sin(ph), sin(th) }, rate[5], acc[5], len, per;
            int32_t delta[5] = { 0, 0, 0, 0, 0 };
            vp_step_block_t b;
            int ax;
            for (ax = 0; ax < 3; ax++) delta[ax] = (int32_t)llround(1000 * w[ax] * sc->axis[ax].steps_per_unit);
            for (ax = 0; ax < 5; ax++) {
                rate[ax] = sc->axis[ax].max_speed * sc->axis[ax].steps_per_unit;
                acc[ax] = sc->axis[ax].accel * sc->axis[ax].steps_per_unit;
            }
            if (vp_step_block_init(&b, 5, delta, rate, acc, sc->max_step_rate) != VP_OK || !b.n) continue;
            len = 0;
            for (ax = 0; ax < 3; ax++) len += pow(delta[ax] / sc->axis[ax].steps_per_unit, 2);
            per = sqrt(len) / b.n;            /* mm along the path per dominant step */
            if (b.v * b.v / (2 * b.a) * per > worst) worst = b.v * b.v / (2 * b.a) * per;
        }
    return worst;
}

static void board_rule(void)
{
    static char text[4096];
    char err[400];
    vp_board_t b;
    vp_step_config_t sc;
    static const int xyz[3] = { 0, 1, 2 };
    double reach, speed, decel, worst, steps_part;
    int rc;
    board_text(text, sizeof text, "");
    CHECK(vp_board_parse(text, "touch.ini", &b, err, sizeof err) == VP_OK);
    vp_board_step_config(&b, &sc);
    reach = vp_step_contact_reach(&sc, xyz, 3, &speed);
    /* by hand: |V| = sqrt(300^2 + 300^2 + 50^2), V_i/A_i = 0.1 on every axis */
    decel = 0.5 * sqrt(300.0 * 300 + 300.0 * 300 + 50.0 * 50) * 0.1;
    steps_part = 3 * sqrt(2 / 6400.0 + 1 / 160000.0);
    CHECKF(fabs(reach - decel - steps_part) < 1e-9 && fabs(b.contact_reach - reach) < 1e-12, "reach %.6f, by hand %.6f",
           reach, decel + steps_part);
    worst = worst_direction_stop(&sc);
    CHECKF(worst <= decel * (1 + 1e-9) && worst >= 0.995 * decel, "worst of the directions %.4f mm, rule %.4f", worst, decel);
    /* below it: refused with the rule in the message; at it: accepted */
    board_text(text, sizeof text, "contact_stop = 20");
    rc = vp_board_parse(text, "touch.ini", &b, err, sizeof err);
    {
        char want[120];
        snprintf(want, sizeof want, "[head] contact_stop: 20 mm is below the head's stop from a touch, %.3f mm", reach);
        CHECKF(rc == VP_EINVAL && strstr(err, want), "%s", err);
    }
    printf("contact_stop 20 refused: %s\n", err);
    board_text(text, sizeof text, "contact_stop = 21.5");
    CHECK(vp_board_parse(text, "touch.ini", &b, err, sizeof err) == VP_OK && b.contact_stop == 21.5);
    /* contact_halt: only the debounce steps remain */
    board_text(text, sizeof text, "contact_stop = 1\ncontact_halt = yes");
    CHECKF(vp_board_parse(text, "touch.ini", &b, err, sizeof err) == VP_OK && fabs(b.contact_reach - steps_part) < 1e-12, "%s", err);
    /* a contact_stop without a contact, and 'sim' on a gpiod board */
    board_text(text, sizeof text, "contact_stop = 30");
    {
        char *p = strstr(text, "contact = sim\n");
        memmove(p, p + 14, strlen(p + 14) + 1);
    }
    CHECK(vp_board_parse(text, "touch.ini", &b, err, sizeof err) == VP_EINVAL && strstr(err, "needs a contact switch"));
    /* boards/rpi4-gantry.ini: its probe on gpiochip0:7, stopping within contact_stop 10 */
    CHECKF(vp_board_load("boards/rpi4-gantry.ini", &b, err, sizeof err) == VP_OK, "%s", err);
    {
        vp_gpiod_config_t g;
        double by_hand = 0.5 * sqrt(150.0 * 150 + 120.0 * 120 + 15.0 * 15) * 0.1 + 3 * sqrt(2 / 6400.0 + 1 / 160000.0);
        vp_machine_config_t mc;
        vp_board_gpiod_config(&b, &g);
        vp_board_machine_config(&b, &mc);
        CHECK(vp_board_has_contact(&b) && mc.contact && b.contact_stop == 10 && !strcmp(g.in[17].chip, "gpiochip0") &&
              g.in[17].offset == 7 && g.in[17].pull == VP_PULL_UP);
        CHECKF(fabs(b.contact_reach - by_hand) < 1e-9, "rpi4: %.6f mm, by hand %.6f", b.contact_reach, by_hand);
        printf("rpi4-gantry: stop from a touch %.3f mm (contact_stop 10)\n", b.contact_reach);
    }
    /* the rpi4 file with the probe on the e-stop's pin, or with the dry run's switch: refused */
    {
        static char rpi[16384], mod[16384];
        FILE *f = fopen("boards/rpi4-gantry.ini", "r");
        size_t n = f ? fread(rpi, 1, sizeof rpi - 1, f) : 0;
        char *p;
        if (f) fclose(f);
        rpi[n] = 0;
        p = strstr(rpi, "contact = gpiochip0:7 pull-up");
        CHECK(p != NULL);
        if (p) {
            snprintf(mod, sizeof mod, "%.*scontact = gpiochip0:4 pull-up%s", (int)(p - rpi), rpi, p + 29);
            CHECKF(vp_board_parse(mod, "rpi4.ini", &b, err, sizeof err) == VP_EINVAL &&
                   strstr(err, "[head] contact: gpiochip0:4 is already [estop] pin"), "%s", err);
            snprintf(mod, sizeof mod, "%.*scontact = sim%s", (int)(p - rpi), rpi, p + 29);
            CHECKF(vp_board_parse(mod, "rpi4.ini", &b, err, sizeof err) == VP_EINVAL &&
                   strstr(err, "[head] contact: 'sim' is the dry run's switch"), "%s", err);
        }
    }
    printf("rule: %.3f mm (|V| %.1f mm/s x 0.1 / 2 + 3 steps of %.4f mm); worst of 2091 directions' block profiles "
           "%.3f mm\n", reach, speed, steps_part / 3, worst);
}

/* The dry run: the switch closes when the laser origin reaches host-sim's sphere (radius 80). */
static void dry_object(void)
{
    rig_t r;
    vp_cmd_t c;
    double to[3] = { 0, 0, 50 }, at = 0.0, t, dn[3] = { 0, 0, -1 }, o[3], dir[3];
    if (rig_open(&r, "contact_stop = 25", 0) != VP_OK) return;
    CHECK(vp_surface_ray(r.d->surf, r.b.start, dn, 400, &t) == 1);
    move_cmd(&c, r.b.start, to);
    CHECK(vp_machine_move(r.m, &c) == VP_OK && vp_machine_contact(r.m, &at));
    CHECKF(fabs(at - t) <= 1 / 400.0 + 1e-9, "at %.5f mm, the object at %.5f", at, t);
    vp_dryrun_true_beam(r.d, o, dir);
    CHECKF(o[2] < 80 && 80 - o[2] <= r.b.contact_stop && fabs(r.m->last.overtravel - (r.m->last.contact_point[2] - o[2])) < 1e-9,
           "stopped at z %.4f, overtravel %.4f", o[2], r.m->last.overtravel);
    printf("dry run: down onto the sphere from z 200: contact at %.4f mm (the object %.4f mm along the ray), stopped "
           "%.4f mm past it (contact_stop 25, %lu surface queries)\n", at, t, r.m->last.overtravel, r.d->touch_evals);
    to[2] = 200 - at;
    move_cmd(&c, to, r.b.start);
    CHECK(vp_machine_move(r.m, &c) == VP_OK && !vp_machine_contact(r.m, NULL));
    vp_dryrun_true_beam(r.d, o, dir);
    CHECKF(o[0] == 0 && o[1] == 0 && o[2] == 200, "back at %g %g %g", o[0], o[1], o[2]);
    vp_dryrun_close(r.d);
}

/* Step intervals of the x edges from index i0: x's position at each rising edge into xs, time
 * into ts; y's rising edges counted up to each x edge into ys. Returns the count of x edges. */
static long x_edges(const vp_iorec_t *rec, size_t i0, uint32_t out0, int32_t x0, int32_t y0, int32_t *xs, int32_t *ys,
                    int64_t *ts, long cap)
{
    uint32_t out = out0;
    int32_t x = x0, y = y0;
    size_t i;
    long n = 0;
    for (i = i0; i < rec->n; i++) {
        const vp_iorec_edge_t *e = &rec->cfg.buf[i];
        uint32_t bit = 1u << e->line;
        out = e->value ? out | bit : out & ~bit;
        if (e->line > 1 || !e->value || !(out & VP_IO_EN(e->line))) continue;
        if (e->line == 1) { y += ((out & VP_IO_DIR(1)) != 0) != (rec->cfg.invert_dir[1] != 0) ? 1 : -1; continue; }
        x += ((out & VP_IO_DIR(0)) != 0) != (rec->cfg.invert_dir[0] != 0) ? 1 : -1;
        if (n < cap) { xs[n] = x; ys[n] = y; ts[n] = e->t_ns; n++; }
    }
    return n;
}

static int32_t pxs[200000], pys[200000];

/* The rig with a jerk on x, y, z (waypoints passed at speed) and its paths watched with
 * contact_stop `stop`; the start in p0 */
static int watched_rig(rig_t *r, double jerk, double stop, double p0[3])
{
    int a;
    if (rig_open(r, "contact_stop = 21.5", 1) != VP_OK) return 0;
    for (a = 0; a < 3; a++) r->m->step.cfg.axis[a].jerk = jerk;
    r->m->cfg.contact_stop = stop;
    memcpy(p0, r->b.start, 3 * sizeof p0[0]);
    return 1;
}

static void touch_path(void)
{
    rig_t r;
    vp_cmd_t c[3];
    double p0[3], p1[3], p2[3], p3[3], at = 0, way[2][VP_KIN_JOINTS], lens[2];
    int32_t x0, y0, W, xw;
    long n, j, trig = -1, grow = 1, yfirst = -1;
    size_t i0;
    uint32_t out0;
    int done = -1;
    if (!watched_rig(&r, 20, 21.5, p0)) return;
    x0 = r.m->step.pos[0];
    y0 = r.m->step.pos[1];
    /* the route: 40 mm along x, then 40 x and 5 y, then 40 y; the wall 0.2 mm before the first
     * waypoint */
    memcpy(p1, p0, sizeof p1);
    p1[0] += 40;
    memcpy(p2, p1, sizeof p2);
    p2[0] += 40;
    p2[1] += 5;
    memcpy(p3, p2, sizeof p3);
    p3[1] += 40;
    move_cmd(&c[0], p0, p1);
    move_cmd(&c[1], p1, p2);
    move_cmd(&c[2], p2, p3);
    xw = x0 + 40 * 80;
    W = xw - 16;
    r.wall.at = W;
    i0 = r.d->rec.n;
    out0 = r.d->rec.out;
    CHECK(vp_machine_move_path(r.m, c, 3, &done) == VP_OK);
    CHECKF(done == 1 && vp_machine_contact(r.m, &at) == 1, "done %d", done);
    CHECKF(fabs(at - 39.8) <= 1 / 80.0 + 1e-9, "at %.4f", at);
    n = x_edges(&r.d->rec, i0, out0, x0, y0, pxs, pys, times, 200000);
    CHECK(n > 0 && pxs[n - 1] == r.m->step.pos[0] && r.m->step.pos[0] == r.d->rec.carriage[0]);
    /* past the waypoint, on the next piece: y moved, and only once x had reached the waypoint */
    CHECKF(r.m->step.pos[0] > xw && r.m->step.pos[1] > y0, "rest at x %d y %d, the waypoint at x %d", r.m->step.pos[0],
           r.m->step.pos[1], xw);
    for (j = 0; j < n; j++) {
        if (trig < 0 && pxs[j] >= W) trig = j;
        if (yfirst < 0 && pys[j] != y0) yfirst = j;
    }
    CHECKF(yfirst >= 0 && pxs[yfirst] >= xw - 1, "y moved first at x %d (waypoint %d)", yfirst >= 0 ? pxs[yfirst] : 0, xw);
    /* the stop decelerates through the waypoint: x's intervals only grow from the confirming
     * step to rest (1 us of rounding), and the last one is slow */
    for (j = trig + (long)r.b.debounce + 1; j < n; j++)
        if (times[j] - times[j - 1] < times[j - 1] - times[j - 2] - 1000) grow = 0;
    CHECKF(grow, "an interval shrank after the trigger");
    CHECKF(n > 3 && 1e9 / (double)(times[n - 1] - times[n - 2]) < 1000, "last x step at %.0f steps/s",
           1e9 / (double)(times[n - 1] - times[n - 2]));
    /* within contact_stop, and within the bound the junction was planned for: block 0's worst
     * stop and the next block's from its entry rate */
    CHECKF(r.m->last.overtravel <= 21.5 && r.m->last.overtravel > 0.2, "overtravel %.4f mm", r.m->last.overtravel);
    printf("a path of 3 MOVEs, the wall 0.2 mm before the first waypoint: touched at %.4f mm, stopped %.3f mm past it on "
           "the next piece (x %+d, y %+d steps past the waypoint), contact_stop 21.5\n", at, r.m->last.overtravel,
           r.m->step.pos[0] - xw, r.m->step.pos[1] - y0);
    /* the way back retraces: y home before x leaves the waypoint, then along x to the start */
    {
        double trig_pt[3];
        memcpy(trig_pt, p0, sizeof trig_pt);
        trig_pt[0] += at;
        move_cmd(&c[0], trig_pt, p0);
        i0 = r.d->rec.n;
        out0 = r.d->rec.out;
        {
            int32_t xr = r.m->step.pos[0], yr = r.m->step.pos[1];
            long back, yhome = -1;
            CHECK(vp_machine_move(r.m, &c[0]) == VP_OK && !vp_machine_contact(r.m, NULL) && r.m->step.fault == 0);
            back = x_edges(&r.d->rec, i0, out0, xr, yr, pxs, pys, times, 200000);
            for (j = 0; j < back; j++) if (yhome < 0 && pys[j] == y0) yhome = j;
            CHECKF(yr == y0 || (yhome >= 0 && pxs[yhome] >= xw - 1), "y home at x %d", yhome >= 0 ? pxs[yhome] : 0);
            CHECKF(r.m->step.pos[0] == x0 && r.m->step.pos[1] == y0, "back at %d %d", r.m->step.pos[0], r.m->step.pos[1]);
        }
    }
    /* the wall a step before the waypoint: seen on the first piece, confirmed (debounce reads, a
     * step each) on the second: the touch is still the first MOVE's, at its end */
    {
        vp_cmd_t b;
        memcpy(p0, r.b.start, sizeof p0);
        move_cmd(&c[0], p0, p1);
        move_cmd(&c[1], p1, p2);
        move_cmd(&c[2], p2, p3);
        r.wall.at = xw - 1;
        r.wall.seen = 0;
        CHECK(vp_machine_move_path(r.m, c, 3, &done) == VP_OK);
        CHECKF(done == 1 && vp_machine_contact(r.m, &at) == 1 && fabs(at - (40 - 1 / 80.0)) <= 1e-9,
               "a step before the waypoint: done %d, at %.5f", done, at);
        CHECK(r.wall.first[0] == xw - 1 && r.m->step.pos[0] > xw);
        {
            double trig_pt[3];
            memcpy(trig_pt, p0, sizeof trig_pt);
            trig_pt[0] += at;
            move_cmd(&b, trig_pt, p0);
        }
        r.wall.at = INT32_MAX;
        CHECK(vp_machine_move(r.m, &b) == VP_OK && r.m->step.pos[0] == x0 && r.m->step.pos[1] == y0);
    }
    /* a stop too long for any piece: the step generator refuses before a step, the machine makes
     * the first MOVE alone */
    r.wall.at = INT32_MAX;
    r.wall.seen = 0;
    memcpy(way[0], r.m->j, sizeof way[0]);
    way[0][0] += 40;
    memcpy(way[1], way[0], sizeof way[1]);
    way[1][0] += 40;
    lens[0] = lens[1] = 40;
    i0 = r.d->rec.n;
    CHECK(!vp_step_touch_fits(&r.m->step, NULL, &way[0][0], 2, lens, 1.0));
    CHECK(vp_step_touch_fits(&r.m->step, NULL, &way[0][0], 2, lens, 21.5));
    {
        vp_step_contact_t sc;
        CHECK(vp_step_move_touch(&r.m->step, &way[0][0], 2, VP_STEP_WATCH_STOP, lens, 1.0, &sc) == VP_ERANGE &&
              r.d->rec.n == i0);
    }
    r.m->cfg.contact_stop = 1.0;
    move_cmd(&c[0], p0, p1);
    move_cmd(&c[1], p1, p2);
    CHECK(vp_machine_move_path(r.m, c, 2, &done) == VP_OK && done == 1 && r.m->step.pos[0] == xw);
    r.m->cfg.contact_stop = 21.5;
    /* a MOVE turning on its way towards its PROBE, watched along its pieces: the wall stops it */
    r.m->cfg.turn_on_move = 1;
    move_cmd(&c[0], p1, p0);
    CHECK(vp_machine_move(r.m, &c[0]) == VP_OK && !vp_machine_contact(r.m, NULL));   /* back to the start, alone */
    move_cmd(&c[0], p0, p1);
    c[0].dir[1] = 1;
    c[0].range = 40;
    r.wall.at = x0 + 20 * 80;
    CHECK(vp_machine_move(r.m, &c[0]) == VP_OK && r.m->move_n > 1 && vp_machine_contact(r.m, &at) == 1);
    /* the pieces it took (the dry run sweeps the head along them) end where it stopped */
    CHECK(memcmp(r.m->way[r.m->move_n - 1], r.m->j, sizeof r.m->j) == 0);
    /* the wall is the carriage's x; the trigger is the laser origin there, on the MOVE's line (the
     * origin kept within origin_tol while the head turns), `at` along it */
    CHECK(r.wall.first[0] == x0 + 20 * 80);
    CHECKF(fabs(r.m->last.contact_point[0] - (p0[0] + at)) < 1e-9 &&
           fabs(r.m->last.contact_point[1] - p0[1]) <= r.m->kin.cfg.origin_tol + 0.02 &&
           fabs(r.m->last.contact_point[2] - p0[2]) <= r.m->kin.cfg.origin_tol + 0.02 && r.m->last.overtravel <= 21.5,
           "turning: at %.4f, trigger %.4f %.4f %.4f, overtravel %.4f", at, r.m->last.contact_point[0],
           r.m->last.contact_point[1], r.m->last.contact_point[2], r.m->last.overtravel);
    printf("a MOVE turning on its way (%d pieces) into the wall: touched at %.3f mm, stopped %.3f mm past it\n", r.m->move_n,
           at, r.m->last.overtravel);
    vp_dryrun_close(r.d);
}

/* A short piece along x, then a long one mostly down z (its own acceleration 6 times lower),
 * every axis with a high jerk so that the junction would be passed fast, contact_stop 4 mm: the
 * wall swept along the first piece, every stop within contact_stop (the junction planned for the
 * stop carried into the slow piece). Returns the worst overtravel. */
static double touch_sweep(void)
{
    rig_t r;
    vp_cmd_t c[2];
    double p0[3], p1[3], p2[3], worst = 0, at = 0;
    int32_t x0, k;
    int done, carried = 0;
    if (!watched_rig(&r, 1000, 4, p0)) return -1;
    x0 = r.m->step.pos[0];
    memcpy(p1, p0, sizeof p1);
    p1[0] += 3;
    memcpy(p2, p1, sizeof p2);
    p2[0] += 4;
    p2[2] -= 12;
    move_cmd(&c[0], p0, p1);
    move_cmd(&c[1], p1, p2);
    for (k = 40; k < 240; k += 4) {
        r.wall.at = x0 + k;
        r.wall.seen = 0;
        CHECK(vp_machine_move_path(r.m, c, 2, &done) == VP_OK && done == 1 && vp_machine_contact(r.m, &at) == 1);
        if (r.m->last.overtravel > worst) worst = r.m->last.overtravel;
        if (r.m->step.pos[2] != vp_step_to_steps(&r.m->step, 2, p0[2] - 40)) carried++;
        CHECKF(r.m->last.overtravel <= 4, "wall at %d steps: overtravel %.4f mm", k, r.m->last.overtravel);
        /* back to the start, along the pieces */
        r.wall.at = INT32_MAX;
        {
            vp_cmd_t b;
            double trig[3];
            memcpy(trig, p0, sizeof trig);
            trig[0] += at;
            move_cmd(&b, trig, p0);
            CHECK(vp_machine_move(r.m, &b) == VP_OK && !vp_machine_contact(r.m, NULL) && r.m->step.pos[0] == x0);
        }
    }
    CHECK(carried > 0);
    printf("a 3 mm piece then a slow one down z, contact_stop 4: the wall at 50 places along the first, every stop within "
           "it (worst %.3f mm; %d carried into the slow piece)\n", worst, carried);
    vp_dryrun_close(r.d);
    return worst;
}

/* The host's own move (vp_machine_goto: to the start, a resume's way back) watches the switch
 * too: towards a wall 40 mm along x it stops within the board's stopping distance of the wall,
 * says where (host_touch_at, to one step), backs off to where it began exactly, no step after,
 * and returns VP_EABORT; the next goto clear of the wall is an ordinary move. Without the switch
 * (a board with no contact) the same move goes through the wall's place: the check fails. */
static void host_goto(void)
{
    rig_t r;
    double to[3];
    const double spu = 80;
    int32_t pos[VP_KIN_JOINTS], x0, W;
    long steps[VP_KIN_JOINTS];
    size_t i0;
    uint32_t out0;
    int a, rc;
    if (rig_open(&r, "", 1) != VP_OK) return;
    x0 = r.m->step.pos[0];
    W = x0 + (int32_t)llround(40 * spu);
    r.wall.at = W;
    memcpy(to, r.b.start, sizeof to);
    to[0] += 100;
    i0 = r.d->rec.n;
    out0 = r.d->rec.out;
    memcpy(pos, r.d->rec.carriage, sizeof pos);
    rc = vp_machine_goto(r.m, to);
    CHECKF(rc == VP_EABORT && r.m->host_touched && r.m->step.fault == 0, "goto into a wall: %s, touched %d, fault %d",
           vp_strerror(rc), r.m->host_touched, r.m->step.fault);
    CHECKF(r.wall.seen && r.wall.first[0] == W, "wall at %d, first seen at %d", W, r.wall.first[0]);
    CHECKF(fabs(r.m->host_touch_at - 40) <= 1 / spu + 1e-9, "host_touch_at %.6f mm, the wall at 40", r.m->host_touch_at);
    /* back where it began, exactly, every step replayed from the edges */
    replay(&r.d->rec, i0, out0, pos, steps, 0, NULL, 0);
    CHECKF(pos[0] == x0 && r.m->step.pos[0] == x0, "back at %d, began at %d", pos[0], x0);
    for (a = 1; a < VP_KIN_JOINTS; a++) CHECK(steps[a] == 0 && pos[a] == r.d->rec.carriage[a]);
    /* out to the wall and past it by the stop, then back: at most twice the way to the stop */
    CHECKF(steps[0] <= 2 * ((long)(W - x0) + (long)llround(r.b.contact_reach * spu)) && steps[0] >= 2 * (long)(W - x0),
           "%ld x steps out and back, the wall %ld steps in, the stop at most %.0f", steps[0], (long)(W - x0),
           r.b.contact_reach * spu);
    /* clear of the wall: an ordinary move */
    r.wall.at = INT32_MAX;
    r.wall.seen = 0;
    {
        double at = r.m->host_touch_at;
        CHECK(vp_machine_goto(r.m, to) == VP_OK && !r.m->host_touched);
        printf("the host's own move into a wall 40 mm on: stopped, %.4f mm at the trigger, backed off to where it "
               "began; clear of it, an ordinary move\n", at);
    }
    vp_dryrun_close(r.d);
}

int main(void)
{
    long cruise, accel, halt;
    int g1, g2, g3;
    cruise = touch_x(50, "contact_stop = 21.5", 0, 0);
    accel = touch_x(3.125, "", 0, 10);
    halt = touch_x(50, "contact_halt = yes", 1, 0);
    printf("wall at 50 mm (cruise, 300 mm/s): stopped %ld steps (%.3f mm) past it; at 3.125 mm (accelerating): %ld steps; "
           "contact_halt: %ld steps; latch, at and the way back (via the trigger) exact\n", cruise, cruise / 80.0, accel, halt);
    touch_diagonal();
    g1 = glitch(1);
    g2 = glitch(2);
    g3 = glitch(3);
    CHECKF(!g1 && !g2 && g3 == 1, "glitches of 1, 2, 3 reads: contact %d %d %d", g1, g2, g3);
    at_rest(0);
    at_rest(1);
    stuck_input();
    board_rule();
    dry_object();
    touch_path();
    touch_sweep();
    host_goto();
    printf("glitches of 1 and 2 reads ignored, 3 a touch; a contact at rest is a contact at 0; a stuck contact faults "
           "after backing off\n");
    return vp_test_done("test_port_contact");
}
