/* The machine object on a dry run (recording GPIO backend + host-sim frames): homing, planner
 * commands executed through the real kinematics, step generator and rangefinder, probe
 * distances against the true object, refusals outside travel, e-stop during a command, and a
 * whole planner scan driven by vp_machine_exec on boards/sim.ini. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_board.h"
#include "vp_dryrun.h"
#include "vp_planner.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

static void cmd_probe(vp_cmd_t *c, const double o[3], const double to[3], double range)
{
    double l = 0;
    int k;
    memset(c, 0, sizeof *c);
    c->kind = VP_CMD_PROBE;
    for (k = 0; k < 3; k++) { c->from[k] = o[k]; c->dir[k] = to[k] - o[k]; l += c->dir[k] * c->dir[k]; }
    for (k = 0; k < 3; k++) c->dir[k] /= sqrt(l);
    c->range = range;
}

static void cmd_move(vp_cmd_t *c, const double from[3], const double to[3])
{
    memset(c, 0, sizeof *c);
    c->kind = VP_CMD_MOVE;
    memcpy(c->from, from, sizeof c->from);
    memcpy(c->to, to, sizeof c->to);
}

/* A planner scan on a board's dry run; returns the number of commands. */
static long scan(const char *board, long cap, double *worst_err, double *rms_err, long *blind)
{
    vp_board_t b;
    vp_dryrun_t *d;
    vp_machine_t *m;
    vp_planner_t *pl = malloc(sizeof *pl);
    vp_planner_config_t cfg;
    size_t arena_bytes = (size_t)64 << 20;
    void *arena = malloc(arena_bytes);
    char err[300];
    long n = 0, hits = 0, misses = 0, falsehits = 0;
    double se = 0;
    clock_t t0 = clock();
    int rc = vp_board_load(board, &b, err, sizeof err);
    *worst_err = 0;
    *blind = 0;
    CHECKF(rc == VP_OK, "%s", err);
    if (rc != VP_OK) return 0;
    CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
    m = vp_dryrun_machine(d);
    CHECK(vp_machine_home(m) == VP_OK);
    CHECK(vp_machine_goto(m, b.start) == VP_OK);
    memset(&cfg, 0, sizeof cfg);
    cfg.omega_kind = b.omega_kind;
    memcpy(cfg.omega_lo, b.omega_lo, sizeof cfg.omega_lo);
    memcpy(cfg.omega_hi, b.omega_hi, sizeof cfg.omega_hi);
    memcpy(cfg.omega_center, b.omega_center, sizeof cfg.omega_center);
    cfg.omega_radius = b.omega_radius;
    memcpy(cfg.interior[0], b.interior, sizeof cfg.interior[0]);
    cfg.ninterior = 1;
    cfg.eps = b.eps;
    memcpy(cfg.start, b.start, sizeof cfg.start);
    cfg.max_range = b.tri.max_range;
    cfg.noise_tol = 2;
    cfg.confirm_misses = 2;
    cfg.clearance = b.clearance;
    CHECK(vp_planner_init(pl, arena, arena_bytes, &cfg) == VP_OK);
    for (n = 0; n < cap; n++) {
        vp_cmd_t c;
        vp_probe_result_t res;
        rc = vp_planner_next(pl, &c);
        CHECKF(rc == VP_OK, "planner: %s", vp_strerror(rc));
        if (rc != VP_OK || c.kind == VP_CMD_DONE) break;
        rc = vp_machine_exec(m, &c, &res);
        if (getenv("VP_TRACE")) printf("cmd %ld kind %d from %.1f %.1f %.1f to %.1f %.1f %.1f dir %.3f %.3f %.3f range %.1f -> rc %d hit %d dist %.3f spot %d\n", n, c.kind, c.from[0], c.from[1], c.from[2], c.to[0], c.to[1], c.to[2], c.dir[0], c.dir[1], c.dir[2], c.range, rc, res.hit, res.dist, m->last.spot.result);
        CHECKF(rc == VP_OK, "command %ld (%s): %s", n, c.kind == VP_CMD_MOVE ? "move" : "probe", vp_strerror(rc));
        if (rc != VP_OK) break;
        if (c.kind == VP_CMD_PROBE) {
            double t;
            int truth = vp_surface_ray(d->surf, c.from, c.dir, c.range, &t);
            if (res.hit && truth) {
                double e = fabs(res.dist - t);
                hits++;
                se += e * e;
                if (e > *worst_err) *worst_err = e;
            } else if (res.hit) falsehits++;
            else {
                misses++;
                if (truth && t < b.tri.min_range) (*blind)++;
            }
            CHECK(vp_planner_feed(pl, &res) == VP_OK);
        }
    }
    *rms_err = hits ? sqrt(se / hits) : 0;
    printf("%s: %ld commands (%s), %ld hits, %ld misses (%ld in the blind zone below %.0f mm), %ld false hits; "
           "%lu moves, travel %.0f mm, %.1f s simulated, %.1f s CPU; facets %u\n",
           board, n, n < cap ? "DONE" : "cap", hits, misses, *blind, b.tri.min_range, falsehits, m->st.moves, m->st.travel,
           d->rec.now * 1e-9, (double)(clock() - t0) / CLOCKS_PER_SEC, vp_planner_num_facets(pl));
    CHECK(falsehits == 0);
    vp_dryrun_close(d);
    free(arena);
    free(pl);
    return n;
}

int main(void)
{
    vp_board_t b;
    vp_dryrun_t *d;
    vp_machine_t *m;
    vp_cmd_t c;
    vp_probe_result_t res;
    char err[300];
    double o[3], dir[3], p[3], worst = 0, rms = 0;
    long blind, n;
    int rc;

    rc = vp_board_load("boards/sim.ini", &b, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
    m = vp_dryrun_machine(d);
    /* nothing moves before homing */
    cmd_move(&c, b.start, (double[3]){ 0, 0, 190 });
    CHECK(vp_machine_exec(m, &c, &res) == VP_ESTATE);
    CHECK(vp_machine_home(m) == VP_OK && m->step.homed);
    CHECK(vp_machine_goto(m, b.start) == VP_OK);
    vp_machine_beam(m, o, dir);
    CHECKF(fabs(o[0] - b.start[0]) < 0.02 && fabs(o[1] - b.start[1]) < 0.02 && fabs(o[2] - b.start[2]) < 0.01, "at %g %g %g", o[0], o[1], o[2]);
    /* probe straight down at the sphere (radius 80 at the origin): 120 mm */
    cmd_probe(&c, b.start, (double[3]){ 0, 0, 0 }, 400);
    CHECK(vp_machine_exec(m, &c, &res) == VP_OK);
    CHECKF(res.hit && fabs(res.dist - 120) < 0.5, "hit %d dist %g", res.hit, res.dist);
    vp_machine_beam(m, o, dir);
    CHECK(fabs(dir[2] + 1) < 1e-6 && fabs(o[2] - 200) < 0.01);
    vp_dryrun_true_beam(d, p, dir);
    CHECK(fabs(p[2] - 200) < 0.01);
    /* the same probe with a range short of the surface: a miss */
    cmd_probe(&c, b.start, (double[3]){ 0, 0, 0 }, 100);
    CHECK(vp_machine_exec(m, &c, &res) == VP_OK && !res.hit);
    /* a straight move, then probes from the side and past the object */
    cmd_move(&c, b.start, (double[3]){ 140, 30, 60 });
    CHECK(vp_machine_exec(m, &c, &res) == VP_OK);
    vp_machine_beam(m, o, dir);
    CHECK(fabs(o[0] - 140) < 0.02 && fabs(o[1] - 30) < 0.02 && fabs(o[2] - 60) < 0.01);
    {
        double t, target[3] = { 0, 10, 20 };
        cmd_probe(&c, (double[3]){ 140, 30, 60 }, target, 400);
        CHECK(vp_machine_exec(m, &c, &res) == VP_OK);
        CHECK(vp_surface_ray(d->surf, c.from, c.dir, 400, &t));
        CHECKF(res.hit && fabs(res.dist - t) < 0.5, "side probe %d %g vs %g", res.hit, res.dist, t);
        cmd_probe(&c, (double[3]){ 140, 30, 60 }, (double[3]){ 140, 300, 60 }, 400);
        CHECK(vp_machine_exec(m, &c, &res) == VP_OK && !res.hit);
    }
    /* outside travel: refused, nothing moved */
    cmd_move(&c, (double[3]){ 140, 30, 60 }, (double[3]){ 400, 0, 0 });
    CHECK(vp_machine_exec(m, &c, &res) == VP_ERANGE);
    vp_machine_beam(m, o, dir);
    CHECK(fabs(o[0] - 140) < 0.02);
    /* e-stop in the middle of a move: stopped, fault, homing needed, then it goes on */
    d->rec.cfg.estop_at = d->rec.now + 100000000;
    d->rec.cfg.estop_until = d->rec.now + 200000000;
    cmd_move(&c, (double[3]){ 140, 30, 60 }, (double[3]){ 140, -100, 150 });
    CHECK(vp_machine_exec(m, &c, &res) == VP_EABORT && m->step.fault == VP_STEP_FAULT_ESTOP);
    CHECK(vp_machine_exec(m, &c, &res) == VP_ESTATE);
    d->rec.now += 300000000;
    CHECK(vp_step_clear_fault(&m->step) == VP_OK);
    CHECK(vp_machine_home(m) == VP_OK);
    CHECK(vp_machine_goto(m, (double[3]){ 140, -100, 150 }) == VP_OK);
    printf("dry run on %s: %lu probes (%lu hits), %lu moves, %llu GPIO edges, %.2f s simulated\n", b.name, m->st.probes,
           m->st.hits, m->st.moves, (unsigned long long)d->rec.edges, d->rec.now * 1e-9);
    vp_dryrun_close(d);

    /* planner scans on both boards (capped: the planner's routes are its own business) */
    n = scan("boards/sim.ini", 4000, &worst, &rms, &blind);
    printf("  probe distance error against the true object: rms %.3f mm, worst %.3f mm\n", rms, worst);
    CHECK(n > 100);
    CHECKF(worst < 2, "worst probe error %.3f mm", worst);
    n = scan("boards/rpi4-gantry.ini", 4000, &worst, &rms, &blind);
    printf("  probe distance error against the true object: rms %.3f mm, worst %.3f mm\n", rms, worst);
    CHECK(n > 100);
    CHECKF(worst < 2, "worst probe error %.3f mm", worst);
    return vp_test_done("test_port_machine");
}
