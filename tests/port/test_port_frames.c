/* Frames tied to the laser (issue 18, first part), on the rpi4 board's dry run against a flat
 * target: the simulated camera streams (33.3 ms frames) with a pipeline latency of 0..3 frames
 * and stamps frames when it hands them over, so a frame stamped after the laser switch can still
 * have been exposed before it. Measured here:
 *   - with the board's latency_frames equal to the camera's, no probe uses a frame exposed
 *     before its switch (the renderer's truth says which frames had the laser), every probe reads
 *     the true distance; the latency routine measures the camera's latency exactly;
 *   - with latency_frames one short (or a camera without sequence numbers, judged by time stamps
 *     alone) a laser-off frame is used and read as a miss: the checker above fails on it; without
 *     a mark the probe is refused instead;
 *   - an ambient highlight brighter than a dim spot, beside the laser line and lit in both frames,
 *     leaves the differenced distance as it was; the single-frame path reads the highlight;
 *   - a frame numbered or stamped older than the one before is refused with VP_FRAME_BACKWARDS. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_board.h"
#include "vp_camsim.h"
#include "vp_dryrun.h"
#include "vp_machine.h"
#include "vp_status.h"
#include "vp_test.h"

#define TARGET_X 300.0
#define PERIOD 33333333

static vp_board_t board;

static void cmd_at(vp_cmd_t *c, double dist, double range)
{
    memset(c, 0, sizeof *c);
    c->kind = VP_CMD_PROBE;
    c->from[0] = TARGET_X - dist;
    c->from[1] = 150;
    c->from[2] = 150;
    c->dir[0] = 1;
    c->range = range;
}

/* the dry run of the board at a flat target, its camera streaming with latency `lat` */
static vp_dryrun_t *open_run(int lat, int machine_lat)
{
    vp_dryrun_options_t o;
    vp_dryrun_t *d = NULL;
    char err[300];
    vp_board_t b = board;
    memset(&o, 0, sizeof o);
    o.flat_target = 1;
    o.target_x = TARGET_X;
    b.sim_frame_ms = PERIOD * 1e-6;
    b.sim_latency = lat;
    b.latency_frames = machine_lat;
    CHECK(vp_dryrun_open(&b, &o, &d, err, sizeof err) == VP_OK);
    if (!d) return NULL;
    CHECK(vp_machine_home(vp_dryrun_machine(d)) == VP_OK);
    return d;
}

/* The probe's two frames against the renderer's truth: 1 if either was exposed with the laser
 * in the wrong state (a frame from before its switch). */
static int pre_switch(const vp_dryrun_t *d)
{
    const vp_camsim_truth_t *on = vp_camsim_last(d->cs), *off = vp_camsim_prev(d->cs);
    return !on->laser || off->laser;
}

typedef struct run_out {
    int probes, ok, hits, misses, pre, refused;
    double worst;
} run_out_t;

/* probes at 12 distances from 40 to 260 mm; ok: a hit within 0.5 mm of the true distance */
static void probes(vp_dryrun_t *d, run_out_t *o)
{
    vp_machine_t *m = vp_dryrun_machine(d);
    int i;
    memset(o, 0, sizeof *o);
    for (i = 0; i < 12; i++) {
        vp_cmd_t c;
        vp_probe_result_t r;
        double dist = 40 + 20 * i, o3[3], dir[3], truth;
        int rc;
        cmd_at(&c, dist, 400);
        rc = vp_machine_probe(m, &c, &r);
        o->probes++;
        if (rc != VP_OK) { o->refused++; continue; }
        vp_dryrun_true_beam(d, o3, dir);
        truth = (TARGET_X - o3[0]) / dir[0];
        if (pre_switch(d)) o->pre++;
        if (r.hit) {
            o->hits++;
            if (fabs(r.dist - truth) > o->worst) o->worst = fabs(r.dist - truth);
            if (fabs(r.dist - truth) < 0.5) o->ok++;
        } else o->misses++;
    }
}

static void latency(void)
{
    int lat;
    for (lat = 0; lat <= 3; lat++) {
        vp_dryrun_t *d = open_run(lat, lat);
        vp_machine_t *m;
        run_out_t o;
        int meas = -1;
        if (!d) continue;
        m = vp_dryrun_machine(d);
        probes(d, &o);
        printf("camera latency %d frames, latency_frames %d: %d probes, %d hits within 0.5 mm (worst %.3f mm), "
               "%d misses, %d frames from before the switch used, %lu frames dropped as stale\n", lat, lat, o.probes,
               o.ok, o.worst, o.misses, o.pre, m->st.stale);
        CHECKF(o.pre == 0, "latency %d: %d pre-switch frames used", lat, o.pre);
        CHECKF(o.ok == o.probes && o.misses == 0 && o.refused == 0, "latency %d: %d of %d right", lat, o.ok, o.probes);
        /* the routine measures it (head aimed at the target 150 mm away) */
        {
            vp_cmd_t c;
            vp_probe_result_t r;
            cmd_at(&c, 150, 400);
            CHECK(vp_machine_probe(m, &c, &r) == VP_OK && r.hit);
            CHECK(vp_machine_measure_latency(m, 3, 10, &meas) == VP_OK);
            printf("  measured latency: %d frames\n", meas);
            CHECKF(meas == lat, "measured %d, camera %d", meas, lat);
        }
        vp_dryrun_close(d);
        /* a camera that hands over every frame (V4L2): the machine drops the stale ones itself */
        d = open_run(lat, lat);
        vp_camsim_stream(d->cs)->every_frame = 1;
        m = vp_dryrun_machine(d);
        probes(d, &o);
        printf("  every frame handed over: %d hits within 0.5 mm, %d frames from before the switch used, %lu dropped as "
               "stale by the machine\n", o.ok, o.pre, m->st.stale);
        CHECK(o.pre == 0 && o.ok == o.probes);
        CHECKF(m->st.stale >= (unsigned long)(2 * lat * o.probes), "stale %lu", m->st.stale);
        vp_dryrun_close(d);
        /* one frame short: a laser-off frame is used and read as a miss: the check above fails */
        if (lat > 0) {
            d = open_run(lat, lat - 1);
            probes(d, &o);
            printf("  latency_frames %d (one short): %d frames from before the switch used, %d misses, %d right\n",
                   lat - 1, o.pre, o.misses, o.ok);
            CHECKF(o.pre == o.probes && o.misses == o.probes, "one short: %d pre, %d misses", o.pre, o.misses);
            vp_dryrun_close(d);
        }
    }
    /* time stamps alone (not_before after the switch, latency_frames 0, single frame as before):
     * the camera's latency 2 hands over laser-off frames stamped after the switch, read as misses */
    {
        vp_dryrun_t *d = open_run(2, 0);
        run_out_t o;
        vp_machine_t *m = vp_dryrun_machine(d);
        int pre_on = 0, i;
        m->cfg.single_frame = 1;
        memset(&o, 0, sizeof o);
        for (i = 0; i < 12; i++) {
            vp_cmd_t c;
            vp_probe_result_t r;
            cmd_at(&c, 40 + 20 * i, 400);
            if (vp_machine_probe(m, &c, &r) != VP_OK) continue;
            o.probes++;
            if (!vp_camsim_last(d->cs)->laser) pre_on++;
            if (!r.hit) o.misses++;
        }
        printf("time stamps only (latency_frames 0: a frame stamped after the switch is taken; single frame), camera "
               "latency 2: %d of %d probes read a laser-off frame, %d misses\n", pre_on, o.probes, o.misses);
        CHECK(pre_on == o.probes && o.misses == o.probes && o.probes == 12);
        /* a camera that cannot say where its frames are (no mark): refused, never a miss */
        m->cfg.single_frame = 0;
        m->cfg.latency_frames = 2;
        m->cam.mark = NULL;
        {
            vp_cmd_t c;
            vp_probe_result_t r;
            unsigned long ref = m->st.refused, miss = m->st.misses;
            cmd_at(&c, 100, 400);
            CHECK(vp_machine_probe(m, &c, &r) == VP_EIO && m->last.fault == VP_FRAME_UNPROVEN && !r.hit);
            CHECK(m->st.refused == ref + 1 && m->st.misses == miss);
        }
        vp_dryrun_close(d);
    }
}

/* An ambient highlight beside the laser line, brighter than the (dim) spot, lit in both frames. */
static void highlight(void)
{
    vp_dryrun_t *d = open_run(1, 1);
    vp_machine_t *m = vp_dryrun_machine(d);
    vp_camsim_config_t *cc = vp_camsim_config(d->cs);
    vp_cmd_t c;
    vp_probe_result_t r;
    double clean, withh, single, peak;
    int rc;
    cc->spot_energy = 200;        /* a dim spot (a dark surface) */
    cmd_at(&c, 150, 400);
    CHECK(vp_machine_probe(m, &c, &r) == VP_OK && r.hit);
    clean = r.dist;
    peak = vp_camsim_last(d->cs)->peak;
    /* where the spot of a surface 260 mm away would be, 2 px across the line */
    cc->highlight_peak = 200;
    cc->highlight_sigma = 1.5;
    cc->highlight_dist = 260;
    cc->highlight_off_px = 2;
    CHECK(vp_machine_probe(m, &c, &r) == VP_OK);
    withh = r.hit ? r.dist : NAN;
    printf("highlight (peak %.0f, the spot's %.0f) beside the line: differenced %.3f mm, without it %.3f mm\n",
           cc->highlight_peak, peak, withh, clean);
    CHECKF(cc->highlight_peak > 2 * peak, "the highlight is not brighter than the spot (%.0f)", peak);
    CHECKF(r.hit && fabs(withh - clean) < 0.5, "differenced: %d %.3f vs %.3f", r.hit, withh, clean);
    /* the single laser-on frame: the highlight wins, a false farther hit */
    m->cfg.single_frame = 1;
    rc = vp_machine_probe(m, &c, &r);
    single = r.hit ? r.dist : NAN;
    printf("  single frame (no differencing): hit %d at %.3f mm (spot %d)\n", r.hit, single, m->last.spot.result);
    CHECK(rc == VP_OK && vp_camsim_last(d->cs)->laser);
    CHECKF(!(r.hit && fabs(single - clean) < 0.5), "the single frame read right: %.3f", single);
    CHECKF(r.hit && single > clean + 50, "single frame: %d %.3f", r.hit, single);
    m->cfg.single_frame = 0;
    vp_dryrun_close(d);
}

/* A frame numbered or stamped older than the one before: refused, never read. */
static void backwards(void)
{
    int kind;
    for (kind = 1; kind <= 2; kind++) {
        vp_dryrun_t *d = open_run(1, 1);
        vp_machine_t *m = vp_dryrun_machine(d);
        vp_cmd_t c;
        vp_probe_result_t r;
        int i, rc = VP_OK, n = 0;
        unsigned long miss;
        miss = m->st.misses;
        CHECK(vp_camsim_fault(d->cs, 5, kind) == VP_OK);
        for (i = 0; i < 4 && rc == VP_OK; i++) {
            cmd_at(&c, 100, 400);
            rc = vp_machine_probe(m, &c, &r);
            n++;
        }
        printf("frame %s older than the one before: probe %d -> %s, fault %d\n", kind == 1 ? "stamped" : "numbered", n,
               vp_strerror(rc), m->last.fault);
        CHECKF(rc == VP_EIO && m->last.fault == VP_FRAME_BACKWARDS && n == 3, "rc %d fault %d after %d", rc, m->last.fault, n);
        CHECK(m->st.misses == miss && m->st.refused == 1);
        vp_dryrun_close(d);
    }
}

int main(void)
{
    char err[300];
    int rc = vp_board_load("boards/rpi4-gantry.ini", &board, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    if (rc != VP_OK) return vp_test_done("test_port_frames");
    CHECK(board.laser.chip[0] && board.latency_frames >= 0);
    latency();
    highlight();
    backwards();
    return vp_test_done("test_port_frames");
}
