/* Paths passed without stopping at their waypoints (vp_step's jerk), with the settings of
 * boards/rpi4-gantry.ini, judged on the recording backend's edges alone: the step positions are
 * rebuilt from the STEP and DIR edges, the speeds from the rising-edge times.
 *   - jerk 0: a path gives exactly the edges of its waypoints run as separate moves;
 *   - with jerk: every position after every tick lies within a step of the polyline through the
 *     waypoints (in step space), every waypoint is reached exactly and in order;
 *   - no axis faster than its max speed over any 8 of its steps;
 *   - where one axis dominates both pieces at a waypoint, its last interval before and first
 *     after change its speed by at most its jerk (plus the acceleration over those two
 *     intervals); planned with twice the jerk, this check fails;
 *   - an axis without a jerk (y): every waypoint where it moves is passed at rest, edge for edge
 *     as with no jerk at all;
 *   - at each waypoint passed, each axis's speed changes by at most its jerk (speeds over 8 steps
 *     either side, with the acceleration over those windows and Bresenham's one tick allowed; an
 *     axis starting or stopping there against its speed on the other side);
 *     the same check fails on a run planned with 20 times the jerk (the checker can fail);
 *   - an axis reversing where it has backlash: the head comes to rest there (the backlash is
 *     taken up at rest), and without backlash it does not stop;
 *   - the same with a stock kernel's late wake-ups: on the path, never over a max speed;
 *   - an aim path (vp_kin, the rpi4 head turning 160 degrees) and an arc take less time than
 *     stopping at every waypoint (the ratios are printed). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_iorec.h"
#include "vp_kin.h"
#include "vp_status.h"
#include "vp_step.h"
#include "vp_test.h"

#define NAX 5
#define CAP 2000000
#define MAXW 160
static vp_iorec_edge_t edges[CAP], edges2[CAP];
static const double spu[NAX] = { 80, 80, 400, 35.5556, 35.5556 }, vmax[NAX] = { 150, 120, 15, 90, 60 },
                    acc[NAX] = { 1500, 1200, 150, 360, 240 }, jerk[NAX] = { 10, 10, 1, 5, 5 };

static void config(vp_step_config_t *c, double jscale, int backlash)
{
    static const double bl[NAX] = { 0.05, 0.05, 0.02, 0.1, 0.1 };
    int i;
    memset(c, 0, sizeof *c);
    c->naxes = NAX;
    for (i = 0; i < NAX; i++) {
        vp_step_axis_t *a = &c->axis[i];
        a->steps_per_unit = spu[i];
        a->max_speed = vmax[i];
        a->accel = acc[i];
        a->travel_min = i < 3 ? 0 : i == 3 ? -190 : -90;
        a->travel_max = i < 2 ? 400 : i == 2 ? 300 : i == 3 ? 190 : 90;
        a->backlash = backlash ? bl[i] : 0;
        a->jerk = jerk[i] * jscale;
    }
    c->pulse_ns = 4000;
    c->dir_setup_ns = 2000;
    c->enable_ns = 2000000;
    c->poll_ns = 1000000;
    c->max_step_rate = 20000;
    c->debounce = 3;
    c->allow_unhomed = 1;
}

typedef struct run {
    vp_iorec_t r;
    double t;             /* s from the first edge to the last */
    uint64_t backlash_steps[NAX];
    uint64_t limited;     /* steps the stepper's limiter held back (none on time) */
} run_t;

/* Runs the path (as one path, or waypoint by waypoint with sep) from start. */
static int latency;   /* the stock kernel's late wake-ups (vp_iorec's model) */
static int mixed;     /* y has no jerk */
static int run_path(run_t *out, vp_iorec_edge_t *buf, const double *start, const double (*way)[NAX], int n,
                    double jscale, int backlash, int sep)
{
    vp_iorec_config_t rc;
    vp_step_config_t c;
    vp_step_t s;
    vp_io_t io;
    int w, i;
    memset(&rc, 0, sizeof rc);
    rc.buf = buf;
    rc.cap = CAP;
    rc.naxes = NAX;
    rc.estop_at = -1;
    if (latency) {
        rc.latency = VP_IOREC_LAT_LINUX;
        rc.seed = 5;
        rc.write_ns = rc.read_ns = 1500;
    }
    for (i = 0; i < NAX; i++) rc.start[i] = (int32_t)llround(start[i] * spu[i]);
    config(&c, jscale, backlash);
    if (mixed) c.axis[1].jerk = 0;
    vp_iorec_init(&out->r, &rc);
    io = vp_iorec_io(&out->r);
    if (vp_step_init(&s, &c, &io) != VP_OK || vp_step_set_position(&s, start) != VP_OK) return -1;
    if (sep) {
        for (w = 0; w < n; w++) if (vp_step_move(&s, way[w]) != VP_OK) return -1;
    } else if (vp_step_move_path(&s, &way[0][0], n) != VP_OK)
        return -1;
    out->t = out->r.n ? (out->r.cfg.buf[out->r.n - 1].t_ns - out->r.cfg.buf[0].t_ns) * 1e-9 : 0;
    for (i = 0; i < NAX; i++) out->backlash_steps[i] = s.st.backlash_steps[i];
    out->limited = s.st.limited;
    return out->r.dropped ? -1 : 0;
}

/* ---- the judge: positions and speeds from the edges ---- */

typedef struct tick { int64_t t; int32_t p[NAX]; uint32_t mask; } tick_t;
static tick_t ticks[CAP / 2];

/* Ticks (one write raises every axis that steps) with the position after each; returns count. */
static int rebuild(const vp_iorec_t *r, const double *start)
{
    int32_t p[NAX];
    uint32_t out = 0;
    size_t i;
    int n = 0, a;
    for (a = 0; a < NAX; a++) p[a] = (int32_t)llround(start[a] * spu[a]);
    for (i = 0; i < r->n; i++) {
        const vp_iorec_edge_t *e = &r->cfg.buf[i];
        if (e->value) out |= 1u << e->line; else out &= ~(1u << e->line);
        if (e->line < NAX && e->value) {
            a = e->line;
            p[a] += (out & VP_IO_DIR(a)) ? 1 : -1;
            if (n == 0 || ticks[n - 1].t != e->t_ns) { ticks[n].t = e->t_ns; ticks[n].mask = 0; n++; }
            memcpy(ticks[n - 1].p, p, sizeof p);
            ticks[n - 1].mask |= 1u << a;
        }
    }
    return n;
}

static double seg_dist(const int32_t *p, const double *a, const double *b)
{
    double ab[NAX], ap[NAX], l2 = 0, t = 0, d2 = 0;
    int i;
    for (i = 0; i < NAX; i++) { ab[i] = b[i] - a[i]; ap[i] = p[i] - a[i]; l2 += ab[i] * ab[i]; t += ab[i] * ap[i]; }
    t = l2 > 0 ? t / l2 : 0;
    if (t < 0) t = 0;
    if (t > 1) t = 1;
    for (i = 0; i < NAX; i++) { double q = ap[i] - t * ab[i]; d2 += q * q; }
    return sqrt(d2);
}

/* Every tick within a step of its segment, every waypoint reached in order; returns the worst
 * distance (steps), or -1 when a waypoint is skipped. wt[k]: index of the tick at waypoint k. */
static double judge_path(int nt, const double *start, const double (*way)[NAX], int n, int *wt)
{
    double w[MAXW + 1][NAX], worst = 0;
    int k = 0, j, i;
    for (i = 0; i < NAX; i++) w[0][i] = llround(start[i] * spu[i]);
    for (j = 0; j < n; j++) for (i = 0; i < NAX; i++) w[j + 1][i] = llround(way[j][i] * spu[i]);
    for (j = 0; j < nt && k < n; j++) {
        double d = seg_dist(ticks[j].p, w[k], w[k + 1]);
        int at = 1;
        if (d > worst) worst = d;
        for (i = 0; i < NAX; i++) if (ticks[j].p[i] != (int32_t)w[k + 1][i]) at = 0;
        if (at) { wt[k] = j; k++; while (k < n && !memcmp(w[k], w[k + 1], sizeof w[k])) { wt[k] = j; k++; } }
    }
    return k == n && j == nt ? worst : -1;
}

/* Rising-edge times of axis a among ticks [j0, j1). */
static int axis_times(int j0, int j1, int a, int64_t *t, int max)
{
    int j, n = 0;
    for (j = j0; j < j1 && n < max; j++) if (ticks[j].mask & (1u << a)) t[n++] = ticks[j].t;
    return n;
}

/* Worst speed over any 8 steps of an axis, as a fraction of its max speed. */
static double judge_speed(int nt)
{
    static int64_t t[CAP / 2];
    double worst = 0;
    int a, k, n;
    for (a = 0; a < NAX; a++) {
        n = axis_times(0, nt, a, t, CAP / 2);
        for (k = 0; k + 8 < n; k++) {
            double v = 8e9 / (double)(t[k + 8] - t[k] + 1) / (vmax[a] * spu[a]);
            if (v > worst) worst = v;
        }
    }
    return worst;
}

/* Speed (units/s, signed) of axis a over the 8 steps before (side -1) or after (+1) tick j, and
 * the span in s; 0 with *span 0 when the axis does not move on that side of the waypoint
 * (between j and the waypoint tick `other`); NAN when it has too few steps there to judge. */
static double speed_near(int nt, int j, int other, int a, int side, double *span)
{
    int64_t t[9];
    int n = 0, q, dir = 0;
    *span = 0;
    if (ticks[other].p[a] == ticks[j].p[a]) return 0;   /* still on that side: a start or a stop */
    if (side < 0) {
        for (q = j; q >= 0 && n < 9; q--) if (ticks[q].mask & (1u << a)) t[n++] = ticks[q].t;
    } else {
        for (q = j + 1; q < nt && n < 8; q++) if (ticks[q].mask & (1u << a)) t[n++] = ticks[q].t;
        if (n == 8) { memmove(t + 1, t, 8 * sizeof *t); t[0] = ticks[j].t; n = 9; }
    }
    if (n < 9) return NAN;
    *span = fabs((double)(t[8] - t[0])) * 1e-9;
    if (*span > 0.05) return NAN;
    /* the direction from the position change over the window */
    {
        int j2 = side < 0 ? j - 1 : j + 1;
        while (j2 > 0 && j2 < nt - 1 && ticks[j2].p[a] == ticks[j].p[a]) j2 += side;
        dir = ticks[j2].p[a] > ticks[j].p[a] ? side : -side;
    }
    return dir * 8 / *span / spu[a];
}

/* Worst speed change at a waypoint over (jerk + what the windows allow), over all passed ones;
 * an axis starting or stopping there is judged against its speed on the other side. */
static double judge_jumps(int nt, const int *wt, int n)
{
    double worst = 0;
    int k, a;
    for (k = 0; k + 1 < n; k++) {
        for (a = 0; a < NAX; a++) {
            double sb = 0, sa = 0, vb = speed_near(nt, wt[k], k ? wt[k - 1] : 0, a, -1, &sb),
                   va = speed_near(nt, wt[k], wt[k + 1], a, 1, &sa), allow;
            if (isnan(vb) || isnan(va) || (vb == 0 && va == 0)) continue;
            /* the acceleration over both windows, one tick of Bresenham in 8 steps either side */
            allow = jerk[a] + acc[a] * (sb + sa) + 0.15 * (fabs(va) > fabs(vb) ? fabs(va) : fabs(vb));
            if (fabs(va - vb) / allow > worst) worst = fabs(va - vb) / allow;
        }
    }
    return worst;
}

/* The tight check: at each waypoint where one axis dominates both pieces (the most steps), its
 * last interval before against its first after: the speed change over (jerk + the acceleration
 * over those two intervals + 1 ns of rounding on each), worst over the waypoints. */
static double judge_dominant(const double *start, const double (*way)[NAX], int n, const int *wt)
{
    double worst = 0;
    int k, a;
    for (k = 0; k + 1 < n; k++) {
        int32_t d0[NAX], d1[NAX];
        int dom0 = 0, dom1 = 0, q;
        int64_t tb = -1, ta = -1, t0 = ticks[wt[k]].t;
        for (a = 0; a < NAX; a++) {
            double p0 = k ? way[k - 1][a] : start[a];
            d0[a] = abs((int)(llround(way[k][a] * spu[a]) - llround(p0 * spu[a])));
            d1[a] = abs((int)(llround(way[k + 1][a] * spu[a]) - llround(way[k][a] * spu[a])));
            if (d0[a] > d0[dom0]) dom0 = a;
            if (d1[a] > d1[dom1]) dom1 = a;
        }
        a = dom0;
        if (dom0 != dom1 || !(ticks[wt[k]].mask & (1u << a))) continue;
        for (q = wt[k] - 1; q >= 0; q--) if (ticks[q].mask & (1u << a)) { tb = ticks[q].t; break; }
        for (q = wt[k] + 1; q < wt[k + 1] + 1; q++) if (ticks[q].mask & (1u << a)) { ta = ticks[q].t; break; }
        if (tb < 0 || ta < 0) continue;
        {
            double hb = (t0 - tb) * 1e-9, ha = (ta - t0) * 1e-9, vb = 1 / hb / spu[a], va = 1 / ha / spu[a];
            double allow = jerk[a] + acc[a] * (hb + ha) + (vb * vb / hb + va * va / ha) * 1e-9 * spu[a];
            if (fabs(va - vb) / allow > worst) worst = fabs(va - vb) / allow;
        }
    }
    return worst;
}

/* Speed of the fastest axis at arrival at tick j (from its last interval), units/s over the
 * speed a rest-to-rest profile has one step before its end, sqrt(2a / spu). */
static double arrival(int j)
{
    double worst = 0;
    int a;
    for (a = 0; a < NAX; a++) {
        int q, m = 0;
        int64_t t[2];
        if (!(ticks[j].mask & (1u << a))) continue;
        for (q = j; q >= 0 && m < 2; q--) if (ticks[q].mask & (1u << a)) t[m++] = ticks[q].t;
        if (m == 2) {
            double v = 1e9 / (double)(t[0] - t[1]) / spu[a], rest = sqrt(2 * acc[a] / spu[a]);
            if (v / rest > worst) worst = v / rest;
        }
    }
    return worst;
}

int main(void)
{
    static run_t A, B;
    static double way[MAXW][NAX];
    static int wt[MAXW];
    double start[NAX] = { 200, 150, 200, 10, -20 }, ratio_aim, ratio_arc;
    int n, k, nt, i;

    /* an aim path of the rpi4 head: turning about the laser origin, 150 degrees of pan */
    {
        vp_kin_config_t kc;
        vp_kin_t kin;
        double target[NAX], o[3], d[3], dir[3] = { -0.8, -0.5, -0.3 };
        double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        memset(&kc, 0, sizeof kc);
        kc.tilt_offset[2] = 45;
        kc.laser_offset[0] = 20;
        kc.origin_tol = 0.1;
        kc.lo[VP_J_PAN] = -190; kc.hi[VP_J_PAN] = 190;
        kc.lo[VP_J_TILT] = -90; kc.hi[VP_J_TILT] = 90;
        for (i = 0; i < 3; i++) dir[i] /= l;
        CHECK(vp_kin_init(&kin, &kc) == VP_OK);
        vp_kin_forward(&kin, start, o, d);
        CHECK(vp_kin_aim(&kin, start, o, dir, target) == VP_OK);
        n = vp_kin_aim_path(&kin, start, target, way, MAXW);
        CHECKF(n > 8 && n <= MAXW, "aim path of %d waypoints", n);
    }
    /* jerk 0: the path's edges are exactly those of its waypoints run one by one */
    CHECK(run_path(&A, edges, start, (const double (*)[NAX])way, n, 0, 1, 0) == 0);
    CHECK(run_path(&B, edges2, start, (const double (*)[NAX])way, n, 0, 1, 1) == 0);
    CHECK(A.r.n == B.r.n && !memcmp(edges, edges2, A.r.n * sizeof *edges));
    /* with jerk */
    CHECK(run_path(&B, edges2, start, (const double (*)[NAX])way, n, 1, 0, 0) == 0);
    nt = rebuild(&B.r, start);
    {
        double d = judge_path(nt, start, (const double (*)[NAX])way, n, wt), v = judge_speed(nt), jmp = judge_jumps(nt, wt, n);
        CHECKF(d >= 0 && d <= 1.0, "aim path: a tick %.3f steps off the polyline", d);
        CHECKF(v <= 1.0 + 1e-6, "aim path: an axis at %.4f of its max speed", v);
        CHECKF(B.limited == 0, "aim path on time: the limiter held back %llu steps", (unsigned long long)B.limited);
        CHECKF(jmp <= 1.0, "aim path: a speed change %.3f of the allowed", jmp);
        CHECKF(judge_dominant(start, (const double (*)[NAX])way, n, wt) <= 1.0, "aim path: the dominant axis changes speed by %.3f of the allowed",
               judge_dominant(start, (const double (*)[NAX])way, n, wt));
        CHECK(run_path(&A, edges, start, (const double (*)[NAX])way, n, 0, 0, 0) == 0);
        ratio_aim = B.t / A.t;
        CHECKF(ratio_aim < 0.6, "aim path: %.3f of the time with stops", ratio_aim);
        printf("aim path, %d waypoints: %.3f s without stops, %.3f s with (%.2f); within %.3f steps of the path, "
               "speed %.3f of max, speed changes %.2f of the jerk's allowance\n", n, B.t, A.t, ratio_aim, d, v, jmp);
        /* late wake-ups: never a catch-up burst across a waypoint either */
        latency = 1;
        CHECK(run_path(&B, edges2, start, (const double (*)[NAX])way, n, 1, 0, 0) == 0);
        latency = 0;
        nt = rebuild(&B.r, start);
        CHECKF(judge_path(nt, start, (const double (*)[NAX])way, n, wt) >= 0, "aim path, late wake-ups: off the path");
        CHECKF(judge_speed(nt) <= 1.0 + 1e-6, "aim path, late wake-ups: an axis at %.4f of its max speed", judge_speed(nt));
    }

    /* an arc in XY of 24 chords turning 30 degrees each (two turns), then a square corner and a
     * straight line back; Z and the head still */
    for (k = 0; k < 24; k++) {
        double ang = (k + 1) * M_PI / 6;
        way[k][0] = 200 + 60 * sin(ang);
        way[k][1] = 150 - 60 + 60 * cos(ang);
        way[k][2] = start[2]; way[k][3] = start[3]; way[k][4] = start[4];
    }
    memcpy(way[24], way[23], sizeof way[24]);
    way[24][0] += 80;
    memcpy(way[25], way[24], sizeof way[25]);
    way[25][1] += 80;
    n = 26;
    {
        double s2[NAX];
        memcpy(s2, start, sizeof s2);
        s2[1] = 150;
        s2[0] = 200;
        CHECK(run_path(&B, edges2, s2, (const double (*)[NAX])way, n, 1, 0, 0) == 0);
        nt = rebuild(&B.r, s2);
        {
            double d = judge_path(nt, s2, (const double (*)[NAX])way, n, wt), v = judge_speed(nt), jmp = judge_jumps(nt, wt, n);
            double corner = arrival(wt[24]), chord = arrival(wt[10]);
            CHECKF(d >= 0 && d <= 1.0, "arc: a tick %.3f steps off the polyline", d);
            CHECKF(v <= 1.0 + 1e-6, "arc: an axis at %.4f of its max speed", v);
            CHECKF(B.limited == 0, "arc on time: the limiter held back %llu steps", (unsigned long long)B.limited);
            double dj = judge_dominant(s2, (const double (*)[NAX])way, n, wt);
            CHECKF(jmp <= 1.0, "arc: a speed change %.3f of the allowed", jmp);
            CHECKF(dj <= 1.0, "arc: the dominant axis changes speed by %.3f of the allowed", dj);
            /* the square corner: at rest there (no axis keeps its speed through 90 degrees) */
            CHECKF(corner <= 1.5, "arc: the square corner passed at %.2f of the rest speed", corner);
            CHECKF(chord > 2, "arc: a 30 degree bend passed at only %.2f of the rest speed", chord);
            CHECK(run_path(&A, edges, s2, (const double (*)[NAX])way, n, 0, 0, 0) == 0);
            ratio_arc = B.t / A.t;
            CHECKF(ratio_arc < 0.95, "arc: %.3f of the time with stops", ratio_arc);
            printf("arc, %d waypoints: %.3f s without stops, %.3f s with (%.2f); within %.3f steps, speed %.3f of max, "
                   "speed changes %.2f of the allowance, the dominant axis's %.2f\n", n, B.t, A.t, ratio_arc, d, v, jmp, dj);
        }
        /* the checker can fail: planned with twice the jerk, the dominant axis's speed changes
         * break the tight allowance; with 20 x the jerk, the windows' too */
        CHECK(run_path(&B, edges2, s2, (const double (*)[NAX])way, n, 2, 0, 0) == 0);
        nt = rebuild(&B.r, s2);
        {
            double dj = (judge_path(nt, s2, (const double (*)[NAX])way, n, wt), judge_dominant(s2, (const double (*)[NAX])way, n, wt));
            CHECKF(dj > 1.0, "the tight check passed a run planned with 2 x the jerk (%.2f)", dj);
            printf("the same arc planned with 2 x the jerk: the dominant axis's speed changes %.2f of the allowance (caught)\n", dj);
        }
        /* y without a jerk: every waypoint where y moves is passed at rest, edge for edge as
         * with no jerk at all */
        mixed = 1;
        CHECK(run_path(&B, edges2, s2, (const double (*)[NAX])way, n, 1, 0, 0) == 0);
        mixed = 0;
        CHECK(B.r.n == A.r.n && !memcmp(edges, edges2, A.r.n * sizeof *edges));
        CHECK(run_path(&B, edges2, s2, (const double (*)[NAX])way, n, 20, 0, 0) == 0);
        nt = rebuild(&B.r, s2);
        {
            double jmp = (judge_path(nt, s2, (const double (*)[NAX])way, n, wt), judge_jumps(nt, wt, n));
            CHECKF(jmp > 1.0, "the jump check passed a run planned with 20 x the jerk (%.2f)", jmp);
            printf("the same arc planned with 20 x the jerk: speed changes %.2f of the allowance (caught)\n", jmp);
        }
    }

    /* Z reverses (a shallow V in x-z): at rest there with backlash, passed without */
    n = 0;
    for (k = 0; k < 8; k++, n++) { memcpy(way[n], start, sizeof way[n]); way[n][0] = start[0] + 10 * (k + 1); way[n][2] = start[2] + 0.5 * (k + 1); }
    for (k = 0; k < 8; k++, n++) { memcpy(way[n], start, sizeof way[n]); way[n][0] = start[0] + 80 + 10 * (k + 1); way[n][2] = start[2] + 4 - 0.5 * (k + 1); }
    CHECK(run_path(&B, edges2, start, (const double (*)[NAX])way, n, 1, 1, 0) == 0);
    nt = rebuild(&B.r, start);
    {
        /* with backlash the carriage lags the motor: only the arrival at the reversal is judged */
        int j, at = -1;
        int32_t zr = (int32_t)llround(way[7][2] * spu[2]), xr = (int32_t)llround(way[7][0] * spu[0]);
        for (j = 0; j < nt; j++) if (ticks[j].p[2] == zr && ticks[j].p[0] == xr) { at = j; break; }
        CHECK(at >= 0);
        CHECK(B.backlash_steps[2] > 0);
        if (at >= 0) CHECKF(arrival(at) <= 1.5, "z reverses with backlash at %.2f of the rest speed", arrival(at));
        printf("z reversing with backlash: arrives at %.2f of the rest speed, %llu backlash steps at rest\n",
               at >= 0 ? arrival(at) : -1.0, (unsigned long long)B.backlash_steps[2]);
    }
    CHECK(run_path(&B, edges2, start, (const double (*)[NAX])way, n, 1, 0, 0) == 0);
    nt = rebuild(&B.r, start);
    {
        double d = judge_path(nt, start, (const double (*)[NAX])way, n, wt);
        CHECKF(d >= 0 && d <= 1.0, "V: %.3f steps off", d);
        CHECKF(arrival(wt[7]) > 1.5, "z reversing without backlash stopped (%.2f of the rest speed)", arrival(wt[7]));
        CHECKF(judge_jumps(nt, wt, n) <= 1.0, "V: speed change %.2f of the allowance", judge_jumps(nt, wt, n));
    }
    return vp_test_done("test_port_blend");
}
