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
#include "vp_hausdorff.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_vec3.h"
#include "vp_planner.h"
#include "vp_run.h"
#include "vp_session.h"
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

/* The farthest the laser origin gets from segment [a, b] while the joints go straight from pa
 * to pb: the kinematics' forward map at samples + 1 even points of the piece. */
static double piece_off_segment(const vp_kin_t *kin, const double *pa, const double *pb, const double *a,
                                const double *b, int samples)
{
    double worst = 0;
    int q, k;
    for (q = 0; q <= samples; q++) {
        double jj[VP_KIN_JOINTS], oo[3], dd[3], ab[3], s = 0, l2 = 0, foot[3];
        for (k = 0; k < VP_KIN_JOINTS; k++) jj[k] = pa[k] + q / (double)samples * (pb[k] - pa[k]);
        vp_kin_forward(kin, jj, oo, dd);
        for (k = 0; k < 3; k++) { ab[k] = b[k] - a[k]; s += (oo[k] - a[k]) * ab[k]; l2 += ab[k] * ab[k]; }
        s = s < 0 ? 0 : s > l2 ? 1 : s / l2;
        for (k = 0; k < 3; k++) foot[k] = a[k] + s * ab[k];
        if (vp_dist3(oo, foot) > worst) worst = vp_dist3(oo, foot);
    }
    return worst;
}

static void cmd_move(vp_cmd_t *c, const double from[3], const double to[3])
{
    memset(c, 0, sizeof *c);
    c->kind = VP_CMD_MOVE;
    memcpy(c->from, from, sizeof c->from);
    memcpy(c->to, to, sizeof c->to);
}

typedef struct scan_out {
    long commands, hits, misses, blind, occluded, falsehits;
    int done;
    double worst, rms;
    unsigned facets;
    int closed, genus;
    double hausdorff;
} scan_out_t;

/* The device of the scan below: the machine, and every probe checked against the true object. */
typedef struct scan_dev {
    vp_machine_t *m;
    vp_dryrun_t *d;
    const vp_board_t *b;
    scan_out_t *o;
    double se;
    long n;
    double move_floor;  /* what the MOVEs take at least: each axis at its top speed throughout */
} scan_dev_t;

static int scan_move(void *ctx, const vp_cmd_t *c, int *collided)
{
    scan_dev_t *s = ctx;
    int k, rc = vp_machine_exec(s->m, c, NULL);
    double t = 0;
    (void)collided;
    for (k = 0; k < 3; k++) {
        double tk = fabs(c->to[k] - c->from[k]) / s->b->axis[k].ax.max_speed;
        if (tk > t) t = tk;
    }
    s->move_floor += t;
    CHECKF(rc == VP_OK, "command %ld (move): %s", s->n, vp_strerror(rc));
    s->n++;
    return rc;
}

static int scan_probe(void *ctx, const vp_cmd_t *c, vp_probe_result_t *res)
{
    scan_dev_t *s = ctx;
    scan_out_t *o = s->o;
    double t;
    int truth, rc = vp_machine_exec(s->m, c, res);
    CHECKF(rc == VP_OK, "command %ld (probe): %s", s->n, vp_strerror(rc));
    s->n++;
    if (rc != VP_OK) return rc;
    truth = vp_surface_ray(s->d->surf, c->from, c->dir, c->range, &t);
    if (res->hit && truth) {
        double e = fabs(res->dist - t);
        o->hits++;
        s->se += e * e;
        if (e > o->worst) o->worst = e;
    } else if (res->hit) o->falsehits++;
    else {
        o->misses++;
        if (truth && t < s->b->tri.min_range) o->blind++;
        else if (truth) o->occluded++;
    }
    return VP_OK;
}

/* A planner scan on a board's dry run (until DONE or cap commands) through the core's run loop:
 * every probe against the true object; at DONE the mesh is checked. */
static void scan(const char *board, long cap, scan_out_t *o)
{
    vp_board_t b;
    vp_dryrun_t *d;
    vp_machine_t *m;
    vp_planner_t *pl = malloc(sizeof *pl);
    vp_planner_config_t cfg;
    size_t arena_bytes = (size_t)64 << 20;
    void *arena = malloc(arena_bytes);
    char err[300];
    scan_dev_t sd;
    vp_device_ops_t ops;
    vp_run_result_t run;
    long n;
    int64_t run0;
    clock_t t0 = clock();
    int rc = vp_board_load(board, &b, err, sizeof err);
    memset(o, 0, sizeof *o);
    CHECKF(rc == VP_OK, "%s", err);
    if (rc != VP_OK) return;
    CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
    m = vp_dryrun_machine(d);
    CHECK(vp_machine_home(m) == VP_OK);
    CHECK(vp_machine_goto(m, b.start) == VP_OK);
    vp_board_planner_config(&b, &cfg);
    cfg.noise_tol = 2;
    cfg.confirm_misses = 2;
    CHECK(vp_planner_init(pl, arena, arena_bytes, &cfg) == VP_OK);
    memset(&sd, 0, sizeof sd);
    sd.m = m; sd.d = d; sd.b = &b; sd.o = o;
    ops.ctx = &sd;
    ops.move = scan_move;
    ops.probe = scan_probe;
    ops.touched = NULL;
    ops.rays = NULL;
    ops.move_path = NULL;
    ops.sight = NULL;
    run0 = d->rec.now;
    rc = vp_run(pl, &ops, NULL, (unsigned long)cap, &run);
    CHECKF(rc == VP_OK, "scan: %s", vp_strerror(rc));
    {
        /* machine time by motion: the four parts add up to the clock over the run, the MOVEs take
         * at least what their longest axis needs at top speed, and every part is spent */
        const vp_machine_stats_t *t = &m->st;
        printf("  machine time by motion: moves %.1f s (at least %.1f), aims %.1f s, settling %.1f s, reading %.1f s; "
               "the clock %.1f s\n", t->move_ns * 1e-9, sd.move_floor, t->aim_ns * 1e-9, t->settle_ns * 1e-9, t->read_ns * 1e-9,
               (d->rec.now - run0) * 1e-9);
        CHECK(t->move_ns + t->aim_ns + t->settle_ns + t->read_ns == d->rec.now - run0);
        CHECK(t->move_ns * 1e-9 >= sd.move_floor && sd.move_floor > 0);
        CHECK(t->aim_ns > 0 && t->read_ns >= 0);
        CHECK(t->settle_ns == (int64_t)llround(b.settle_ms * 1e6) * (int64_t)t->probes);
        /* sim.ini's camera reaches beyond its clearance ball: it never turns the head on the way;
         * rpi4's head stays in its ball and turns on the way, its contact switch watched along the
         * pieces (its overtravel, contact_stop 10 mm, bounds each touch's stop) */
        if (m->cfg.contact)
            CHECK(m->cfg.turn_on_move == 1 && m->cfg.contact_stop == 10 && t->moves_turning > 0);
        else
            CHECK(m->cfg.turn_on_move == 0 && t->moves_turning == 0);
    }
    o->done = run.done;
    n = (long)run.commands;
    o->rms = o->hits ? sqrt(sd.se / o->hits) : 0;
    o->commands = n;
    o->facets = vp_planner_num_facets(pl);
    if (o->done) {
        vp_mesh_t mesh;
        vp_meshcheck_t mc;
        vp_hausdorff_t hd;
        memset(&mesh, 0, sizeof mesh);
        CHECK(vp_session_mesh(pl, &mesh) == VP_OK);
        CHECK(vp_meshcheck_analyze(&mesh, &mc) == VP_OK);
        o->closed = mc.closed_manifold;
        o->genus = mc.genus;
        CHECK(vp_hausdorff(&mesh, d->surf, 20000, 7, &hd) == VP_OK);
        o->hausdorff = hd.hausdorff;
        vp_meshcheck_free(&mc);
        vp_mesh_free(&mesh);
    }
    printf("%s: %ld commands (%s), %ld hits, %ld misses (%ld with the surface nearer than %.0f mm, %ld with the spot hidden), "
           "%ld false hits; %lu moves, origin travel %.0f mm, %llu GPIO edges, %.0f s of machine time, %.1f s CPU\n",
           board, n, o->done ? "DONE" : "cap", o->hits, o->misses, o->blind, b.tri.min_range, o->occluded, o->falsehits,
           m->st.moves, m->st.travel, (unsigned long long)d->rec.edges, d->rec.now * 1e-9,
           (double)(clock() - t0) / CLOCKS_PER_SEC);
    printf("  probe error against the true object: rms %.3f mm, worst %.3f mm", o->rms, o->worst);
    if (o->done) printf("; mesh: %u facets, %s, genus %d, Hausdorff to the object %.2f mm (eps %.0f)", o->facets,
                        o->closed ? "closed manifold" : "NOT closed", o->genus, o->hausdorff, b.eps);
    printf("\n");
    /* frames tied to the laser (the board's camera streams with latency on its dry run): no probe
     * was refused for its frames */
    printf("  frames: %lu taken, %lu dropped as older than the laser switch, %lu probes refused for their frames\n",
           m->st.frames, m->st.stale, m->st.refused);
    CHECK(m->st.refused == 0);
    vp_dryrun_close(d);
    free(arena);
    free(pl);
}

int main(void)
{
    vp_board_t b;
    vp_dryrun_t *d;
    vp_machine_t *m;
    vp_cmd_t c;
    vp_probe_result_t res;
    char err[300];
    double o[3], dir[3], p[3];
    int rc;

    rc = vp_board_load("boards/sim.ini", &b, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
    m = vp_dryrun_machine(d);
    CHECK(m->cfg.turn_on_move == 0); /* its camera reaches beyond the clearance ball: MOVEs straight */
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

    /* a MOVE the head's orientation cannot make: the head first turns about the laser origin, then
     * moves; the origin ends where commanded. The case is searched on the rpi4 board (its axes'
     * travel is tight about Omega): a point of dOmega, a direction the head can aim along there,
     * and a point 10 mm away that the carriage cannot reach in that orientation but can in another */
    {
        double from[3], to[3], u[3], jt[VP_KIN_JOINTS], j1[VP_KIN_JOINTS], j2[VP_KIN_JOINTS];
        int found = 0, a, bdir, e, k, other;
        rc = vp_board_load("boards/rpi4-gantry.ini", &b, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
        CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
        m = vp_dryrun_machine(d);
        CHECK(vp_machine_home(m) == VP_OK);
        for (a = 0; a < 26 * 26 && !found; a++)
            for (e = 0; e < 26 && !found; e++) {
                int i3 = a / 26 + (a / 26 >= 13), i4 = a % 26 + (a % 26 >= 13), i5 = e + (e >= 13);
                double p0[3] = { i3 % 3 - 1.0, (i3 / 3) % 3 - 1.0, i3 / 9 - 1.0 }, l0 = vp_norm3(p0);
                double w[3] = { i5 % 3 - 1.0, (i5 / 3) % 3 - 1.0, i5 / 9 - 1.0 }, lw = vp_norm3(w);
                for (k = 0; k < 3; k++) {
                    from[k] = b.omega_center[k] + b.omega_radius * p0[k] / l0;
                    u[k] = (double)((i4 / (k == 0 ? 1 : k == 1 ? 3 : 9)) % 3) - 1.0;
                    to[k] = from[k] + 10.0 * w[k] / lw;
                }
                if (vp_norm3(u) == 0.0) continue;
                vp_normalize3(u);
                if (vp_kin_aim(&m->kin, m->j, from, u, jt) != VP_OK || vp_kin_move(&m->kin, jt, from, j1) != VP_OK ||
                    vp_kin_move(&m->kin, jt, to, j1) != VP_ERANGE)
                    continue;
                for (bdir = 0, other = 0; bdir < 27 && !other; bdir++) {
                    double v[3] = { bdir % 3 - 1.0, (bdir / 3) % 3 - 1.0, bdir / 9 - 1.0 };
                    if (bdir == 13) continue;
                    vp_normalize3(v);
                    other = vp_kin_aim(&m->kin, jt, from, v, j2) == VP_OK && vp_kin_move(&m->kin, j2, to, j1) == VP_OK;
                }
                found = other;
            }
        CHECKF(found, "no MOVE on rpi4 that needs a turn first");
        if (found) {
            double tgt[3];
            int q;
            CHECK(vp_machine_goto(m, from) == VP_OK);
            for (q = 0; q < 3; q++) tgt[q] = from[q] + 50.0 * u[q];
            cmd_probe(&c, from, tgt, 10); /* the head aims along u */
            CHECK(vp_machine_exec(m, &c, &res) == VP_OK);
            CHECK(vp_kin_move(&m->kin, m->j, to, j1) == VP_ERANGE); /* what MOVE refused before */
            cmd_move(&c, from, to);
            CHECK(vp_machine_exec(m, &c, &res) == VP_OK && m->st.turns == 1 && m->turn_n > 0);
            vp_machine_beam(m, o, dir);
            CHECKF(vp_dist3(o, to) < 0.02, "after the turn and the move at %g %g %g", o[0], o[1], o[2]);
            /* a MOVE no orientation can make: refused, nothing moved, no turn */
            cmd_move(&c, to, (double[3]){ 900, 150, 150 });
            CHECK(vp_machine_exec(m, &c, &res) == VP_ERANGE && m->st.turns == 1);
            vp_machine_beam(m, o, dir);
            CHECK(vp_dist3(o, to) < 0.02);
            printf("a MOVE from (%g, %g, %g) to (%g, %g, %g) with the head along (%g, %g, %g): turned first, then moved\n",
                   from[0], from[1], from[2], to[0], to[1], to[2], u[0], u[1], u[2]);
        }
        vp_dryrun_close(d);
    }

    /* A MOVE that names its PROBE (boards/sim-enclosed.ini: the ball rule, so turn_on_move): the
     * head turns on the way, the laser origin kept on the line. Checked against the kinematics'
     * forward map, sampled along every piece of the joints' path: the origin within origin_tol
     * (plus a step) of the commanded line; at the end the beam along the PROBE's direction; the
     * PROBE's aim then takes no time. The same MOVE on the machine told not to turn (the swept
     * rule) keeps its orientation and the PROBE turns the head. */
    {
        double A[3] = { 90, 60, 120 }, B[3] = { 100, -40, 110 }, dirA[3], j0[VP_KIN_JOINTS], jh[VP_KIN_JOINTS];
        double tol, worst = 0, aim_on = 0, aim_off = 0, hit_on = 0, hit_off = 0;
        int pass, w, k;
        rc = vp_board_load("boards/sim-enclosed.ini", &b, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
        for (pass = 0; pass < 2; pass++) {
            vp_cmd_t mv;
            int64_t a0;
            CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
            m = vp_dryrun_machine(d);
            CHECK(m->cfg.turn_on_move == 1);
            if (pass == 1) m->cfg.turn_on_move = 0;
            tol = m->kin.cfg.origin_tol > 0 ? m->kin.cfg.origin_tol : 0.1;
            CHECK(vp_machine_home(m) == VP_OK && vp_machine_goto(m, b.start) == VP_OK);
            /* half the turn on the first MOVE (the way left after it as long as itself) */
            for (k = 0; k < 3; k++) dirA[k] = -A[k];
            vp_normalize3(dirA);
            cmd_move(&mv, b.start, A);
            memcpy(mv.dir, dirA, sizeof mv.dir);
            mv.range = vp_dist3(b.start, A);
            memcpy(j0, m->j, sizeof j0);
            CHECK(vp_kin_aim(&m->kin, j0, A, dirA, jh) == VP_OK);
            CHECK(vp_machine_exec(m, &mv, &res) == VP_OK);
            vp_machine_beam(m, o, dir);
            CHECKF(vp_dist3(o, A) < 0.02, "pass %d: at %g %g %g", pass, o[0], o[1], o[2]);
            if (pass == 0) {
                CHECKF(m->move_n > 1 && m->st.moves_turning == 1, "%d pieces, %lu", m->move_n, m->st.moves_turning);
                CHECKF(fabs(m->j[VP_J_PAN] - 0.5 * (j0[VP_J_PAN] + jh[VP_J_PAN])) < 0.05 &&
                       fabs(m->j[VP_J_TILT] - 0.5 * (j0[VP_J_TILT] + jh[VP_J_TILT])) < 0.05,
                       "pan %g tilt %g, half of %g %g", m->j[VP_J_PAN], m->j[VP_J_TILT], jh[VP_J_PAN], jh[VP_J_TILT]);
                for (w = 0; w < m->move_n; w++) {
                    double off = piece_off_segment(&m->kin, w ? m->way[w - 1] : j0, m->way[w], b.start, A, 40);
                    if (off > worst) worst = off;
                }
                CHECKF(worst <= tol + 0.02, "the origin %g mm off the line (origin_tol %g)", worst, tol);
            } else {
                CHECK(m->move_n == 0 && m->st.moves_turning == 0 && m->j[VP_J_PAN] == j0[VP_J_PAN] &&
                      m->j[VP_J_TILT] == j0[VP_J_TILT]);
            }
            /* the last MOVE (nothing left after it): the head ends along the PROBE's direction */
            cmd_move(&mv, A, B);
            for (k = 0; k < 3; k++) mv.dir[k] = b.interior[k] - B[k]; /* at the torus's tube */
            vp_normalize3(mv.dir);
            mv.range = 0;
            CHECK(vp_machine_exec(m, &mv, &res) == VP_OK);
            vp_machine_beam(m, o, dir);
            CHECKF(vp_dist3(o, B) < 0.02, "pass %d: at %g %g %g", pass, o[0], o[1], o[2]);
            if (pass == 0)
                CHECKF(vp_dot3(dir, mv.dir) > cos(0.05 * M_PI / 180) && m->st.moves_turning == 2, "beam %g %g %g", dir[0], dir[1], dir[2]);
            a0 = m->st.aim_ns;
            cmd_probe(&c, B, b.interior, 400);
            CHECK(vp_machine_exec(m, &c, &res) == VP_OK && res.hit == 1);
            if (pass == 0) { aim_on = 1e-9 * (double)(m->st.aim_ns - a0); hit_on = res.dist; }
            else { aim_off = 1e-9 * (double)(m->st.aim_ns - a0); hit_off = res.dist; }
            vp_dryrun_close(d);
        }
        CHECKF(aim_on < 0.01 && aim_off > 0.1, "the PROBE's aim: %g s after turning on the way, %g s after a straight MOVE", aim_on, aim_off);
        CHECKF(fabs(hit_on - hit_off) < 0.5, "the same probe reads %g and %g", hit_on, hit_off);
        printf("MOVEs turning towards their PROBE (sim-enclosed): the origin at most %.3f mm off the line, the PROBE's aim %.3f s (%.3f s after a straight MOVE)\n",
               worst, aim_on, aim_off);
    }

    /* MOVEs as one path (vp_machine_move_path, boards/sim-enclosed.ini): a route of 12 chords
     * round a circle (bends of 15 degrees), the head turning on the way towards the PROBE that
     * follows. Made one by one on one machine and as one path on another: the same joints after
     * every MOVE bit for bit, the same travel; the laser origin, by the forward map sampled along
     * every piece, within origin_tol of each MOVE's line; the path takes less time (it passes
     * the bends without stopping). An e-stop half way: the MOVEs before it made whole, counted,
     * the rest not. A head with a contact switch (rpi4) is refused, nothing moved. */
    {
        enum { NW = 12 };
        vp_cmd_t mv[NW];
        double P[NW + 1][3], jone[NW][VP_KIN_JOINTS], jstr[NW][VP_KIN_JOINTS], travel[2], tol, worst = 0, secs[2], left;
        int i, k, w, done = -1, pass, same = 1;
        unsigned long moves[2], turning[2];
        rc = vp_board_load("boards/sim-enclosed.ini", &b, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
        for (i = 0; i <= NW; i++) {
            double a = (double)i * 15.0 * M_PI / 180.0;
            P[i][0] = 170.0 * cos(a); P[i][1] = 170.0 * sin(a); P[i][2] = 100.0 + 2.0 * i;
        }
        left = 0;
        for (i = NW; i-- > 0;) {
            cmd_move(&mv[i], P[i], P[i + 1]);
            for (k = 0; k < 3; k++) mv[i].dir[k] = b.interior[k] - P[NW][k];
            vp_normalize3(mv[i].dir);
            mv[i].range = left;
            left += vp_dist3(P[i], P[i + 1]);
        }
        for (pass = 0; pass < 4; pass++) {
            int64_t t0;
            CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
            m = vp_dryrun_machine(d);
            if (pass >= 2) {
                /* the same MOVEs straight (the head told not to turn): each piece ends where the
                 * joints will be as stepped */
                m->cfg.turn_on_move = 0;
                if (pass == 3) {
                    CHECK(vp_machine_home(m) == VP_OK && vp_machine_goto(m, P[0]) == VP_OK);
                    CHECK(vp_machine_move_path(m, mv, NW, &done) == VP_OK && done == NW && m->st.moves_turning == 0);
                    for (i = 0; i < NW; i++)
                        CHECK(m->path[i].n == 1 && memcmp(m->path_way[m->path[i].first], jstr[i], sizeof jstr[i]) == 0 &&
                              memcmp(m->path[i].j1, jstr[i], sizeof jstr[i]) == 0);
                    vp_dryrun_close(d);
                    continue;
                }
            }
            tol = m->kin.cfg.origin_tol > 0 ? m->kin.cfg.origin_tol : 0.1;
            CHECK(vp_machine_home(m) == VP_OK && vp_machine_goto(m, P[0]) == VP_OK);
            t0 = m->st.move_ns;
            if (pass == 0 || pass == 2) {
                for (i = 0; i < NW; i++) {
                    CHECK(vp_machine_exec(m, &mv[i], &res) == VP_OK);
                    memcpy(pass == 0 ? jone[i] : jstr[i], m->j, sizeof jone[i]);
                }
                if (pass == 2) { vp_dryrun_close(d); continue; }
            } else {
                CHECK(vp_machine_move_path(m, mv, NW, &done) == VP_OK && done == NW);
                CHECK(m->st.paths == 1 && m->st.path_moves == NW);
                for (i = 0; i < NW; i++) {
                    const vp_machine_path_move_t *pm = &m->path[i];
                    if (memcmp(pm->j1, jone[i], sizeof jone[i]) != 0) same = 0;
                    for (w = 0; w < pm->n; w++) {
                        double off = piece_off_segment(&m->kin, w ? m->path_way[pm->first + w - 1] : pm->j0,
                                                       m->path_way[pm->first + w], P[i], P[i + 1], 20);
                        if (off > worst) worst = off;
                    }
                }
                CHECK(memcmp(m->j, jone[NW - 1], sizeof m->j) == 0);
            }
            secs[pass] = 1e-9 * (double)(m->st.move_ns - t0);
            travel[pass] = m->st.travel;
            moves[pass] = m->st.moves;
            turning[pass] = m->st.moves_turning;
            vp_dryrun_close(d);
        }
        CHECK(same);
        CHECK(travel[0] == travel[1] && moves[0] == moves[1] && turning[0] == turning[1] && turning[1] == NW);
        CHECKF(worst <= tol + 0.02, "the origin %g mm off a MOVE's line (origin_tol %g)", worst, tol);
        CHECKF(secs[1] < 0.9 * secs[0], "the path %g s, one by one %g s", secs[1], secs[0]);
        printf("12 MOVEs round a bend as one path (sim-enclosed): %.3f s against %.3f s one by one, the same joints; the origin at most %.3f mm off the lines\n",
               secs[1], secs[0], worst);

        /* an e-stop half way through the path */
        CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
        m = vp_dryrun_machine(d);
        CHECK(vp_machine_home(m) == VP_OK && vp_machine_goto(m, P[0]) == VP_OK);
        d->rec.cfg.estop_at = d->rec.now + (int64_t)(0.5e9 * secs[1]);
        d->rec.cfg.estop_until = INT64_MAX;
        CHECK(vp_machine_move_path(m, mv, NW, &done) == VP_EABORT);
        CHECKF(done > 0 && done < NW && m->st.moves == (unsigned long)done, "%d made, %lu counted", done, m->st.moves);
        CHECK(done > 0 && memcmp(m->path[done - 1].j1, jone[done - 1], sizeof jone[0]) == 0);
        vp_dryrun_close(d);

        /* a MOVE that needs the head turned first (vp_machine_turn_for: its orientation would put
         * the carriage outside travel at the end): on rpi4's gantry less its contact switch, found
         * by search from Omega's sphere. In a path of four it is made alone, the path resumed after
         * it; the joints after every MOVE and the turn's pieces are those of the MOVEs made one
         * by one, bit for bit, and the turn is recorded as a motion of its own. */
        {
            double from[3] = { 0, 0, 0 }, to[3] = { 0, 0, 0 }, mid[3], u[3] = { 0, 0, 0 }, jt[VP_KIN_JOINTS], jx[VP_KIN_JOINTS];
            double jref[4][VP_KIN_JOINTS], tref[VP_MACHINE_MAX_WAY][VP_KIN_JOINTS];
            vp_cmd_t tm[4];
            int found = 0, s, e, a, tn = 0, calls = 0, same_j = 1, same_turn = 0, off;
            vp_board_t r;
            rc = vp_board_load("boards/rpi4-gantry.ini", &r, err, sizeof err);
            CHECKF(rc == VP_OK, "%s", err);
            r.contact.chip[0] = 0;
            r.contact_sim = 0;
            CHECK(vp_dryrun_open(&r, NULL, &d, err, sizeof err) == VP_OK);
            m = vp_dryrun_machine(d);
            CHECK(m->cfg.contact == 0 && vp_machine_home(m) == VP_OK);
            for (s = 0; s < 27 && !found; s++)
                for (a = 0; a < 27 && !found; a++)
                    for (e = 0; e < 27 && !found; e++) {
                        double ps[3] = { s % 3 - 1.0, (s / 3) % 3 - 1.0, s / 9 - 1.0 };
                        double pa[3] = { a % 3 - 1.0, (a / 3) % 3 - 1.0, a / 9 - 1.0 };
                        double pe[3] = { e % 3 - 1.0, (e / 3) % 3 - 1.0, e / 9 - 1.0 };
                        if (s == 13 || a == 13 || e == 13) continue;
                        vp_normalize3(ps); vp_normalize3(pa); vp_normalize3(pe);
                        for (k = 0; k < 3; k++) {
                            from[k] = r.omega_center[k] + r.omega_radius * ps[k];
                            to[k] = from[k] + 10.0 * pe[k];
                            u[k] = pa[k];
                        }
                        found = vp_kin_aim(&m->kin, m->j, from, u, jt) == VP_OK && vp_kin_move(&m->kin, jt, from, jx) == VP_OK &&
                                vp_kin_move(&m->kin, jt, to, jx) == VP_ERANGE;
                    }
            vp_dryrun_close(d);
            CHECK(found);
            for (k = 0; k < 3; k++) mid[k] = 0.5 * (from[k] + to[k]);
            cmd_move(&tm[0], from, from);
            cmd_move(&tm[1], from, to);      /* the turn first */
            cmd_move(&tm[2], to, mid);
            cmd_move(&tm[3], mid, to);
            for (pass = 0; found && pass < 2; pass++) {
                double aim_to[3];
                CHECK(vp_dryrun_open(&r, NULL, &d, err, sizeof err) == VP_OK);
                m = vp_dryrun_machine(d);
                CHECK(vp_machine_home(m) == VP_OK && vp_machine_goto(m, from) == VP_OK);
                for (k = 0; k < 3; k++) aim_to[k] = from[k] + 50.0 * u[k];
                cmd_probe(&c, from, aim_to, 10);     /* the head aimed along u */
                CHECK(vp_machine_exec(m, &c, &res) == VP_OK);
                if (pass == 0) {
                    for (i = 0; i < 4; i++) {
                        unsigned long turns = m->st.turns;
                        CHECK(vp_machine_exec(m, &tm[i], &res) == VP_OK);
                        memcpy(jref[i], m->j, sizeof jref[i]);
                        if (m->st.turns != turns) { tn = m->turn_n; memcpy(tref, m->way, (size_t)tn * sizeof tref[0]); }
                    }
                } else {
                    for (off = 0; off < 4; off += done) {
                        CHECK(vp_machine_move_path(m, tm + off, 4 - off, &done) == VP_OK && done > 0);
                        if (done <= 0) break;
                        calls++;
                        for (i = 0; i < done; i++) {
                            const vp_machine_path_move_t *pm = &m->path[i];
                            if (memcmp(pm->j1, jref[off + i], sizeof pm->j1) != 0) same_j = 0;
                            if (pm->turn_n > 0)
                                same_turn = off + i == 1 && pm->turn_n == tn && pm->n == tn + 1 &&
                                            memcmp(m->path_way[pm->first], tref, (size_t)tn * sizeof tref[0]) == 0;
                        }
                    }
                    CHECK(memcmp(m->j, jref[3], sizeof m->j) == 0);
                }
                vp_dryrun_close(d);
            }
            CHECKF(tn > 0 && same_turn && same_j && calls == 3, "turn %d pieces, same turn %d, same joints %d, %d calls", tn, same_turn, same_j, calls);
        }

        /* refused: no MOVE, a PROBE among them, a head with a contact switch but no overtravel to
         * plan its stops for (contact_stop 0); with it, the path is made */
        CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
        m = vp_dryrun_machine(d);
        CHECK(m->cfg.contact == 0 && vp_machine_paths_allowed(m)); /* no switch: paths, whatever contact_stop */
        CHECK(vp_machine_home(m) == VP_OK && vp_machine_goto(m, P[0]) == VP_OK);
        cmd_probe(&c, P[0], b.interior, 400);
        CHECK(vp_machine_move_path(m, mv, 0, &done) == VP_EINVAL && done == 0);
        CHECK(vp_machine_move_path(m, &c, 1, &done) == VP_EINVAL && m->st.moves == 0);
        vp_dryrun_close(d);
        rc = vp_board_load("boards/rpi4-gantry.ini", &b, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
        CHECK(vp_dryrun_open(&b, NULL, &d, err, sizeof err) == VP_OK);
        m = vp_dryrun_machine(d);
        CHECK(m->cfg.contact == 1 && vp_machine_home(m) == VP_OK);
        m->cfg.contact_stop = 0;
        CHECK(!vp_machine_paths_allowed(m));
        CHECK(vp_machine_move_path(m, mv, 1, &done) == VP_EINVAL && done == 0 && m->st.moves == 0);
        m->cfg.contact_stop = 10;
        CHECK(vp_machine_paths_allowed(m));
        CHECK(vp_machine_move_path(m, mv, 1, &done) == VP_OK && done == 1 && m->st.moves == 1 && !vp_machine_contact(m, NULL));
        vp_dryrun_close(d);
    }

    /* calibration on the dry run: a flat target at x = 300, 20 stations from 200 to 15 mm */
    {
        vp_dryrun_options_t opt;
        vp_calib_plan_t cp;
        vp_tri_model_t fit;
        vp_tri_fit_report_t rep;
        double worst = 0, worst_mm = 0;
        int i;
        rc = vp_board_load("boards/rpi4-gantry.ini", &b, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
        memset(&opt, 0, sizeof opt);
        opt.flat_target = 1;
        opt.target_x = 300;
        CHECK(vp_dryrun_open(&b, &opt, &d, err, sizeof err) == VP_OK);
        m = vp_dryrun_machine(d);
        CHECK(vp_machine_home(m) == VP_OK);
        memset(&cp, 0, sizeof cp);
        cp.target_x = 300; cp.y = 150; cp.z = 150;
        cp.d_near = 15; cp.d_far = 200;
        cp.stations = 20;
        CHECK(vp_machine_calibrate(m, &cp, &fit, &rep) == VP_OK);
        /* the board's geometric model is the truth the renderer used */
        for (i = 0; i <= 100; i++) {
            double dd = 15 + 185 * i / 100.0, s_fit, s_true, slope;
            s_true = vp_tri_s(&b.tri, dd);
            vp_tri_eval(&b.tri, s_true, &slope);
            /* the same image point through both models */
            {
                double u = b.tri.p0[0] + s_true * b.tri.e[0], v = b.tri.p0[1] + s_true * b.tri.e[1], df;
                s_fit = (u - fit.p0[0]) * fit.e[0] + (v - fit.p0[1]) * fit.e[1];
                df = vp_tri_eval(&fit, s_fit, NULL);
                if (fabs(df - dd) / slope > worst) worst = fabs(df - dd) / slope;
                if (fabs(df - dd) > worst_mm) worst_mm = fabs(df - dd);
            }
        }
        printf("calibration on the dry run: %d spots at 20 stations, residual rms %.3f mm (max %.3f), line %.3f px; "
               "against the true model %.4f px = %.3f mm over 15..200 mm\n", rep.n, rep.rms_mm, rep.max_mm,
               rep.line_rms_px, worst, worst_mm);
        CHECK(rep.n == 60);
        /* spots of ~0.03 px each, 60 of them: the fit is good to a few hundredths of a pixel */
        CHECKF(worst < 0.05, "calibrated model off by %.4f px", worst);
        vp_dryrun_close(d);
    }

    /* the rpi4 board's dry run to DONE: a closed mesh of the object within eps */
    {
        scan_out_t so;
        scan("boards/rpi4-gantry.ini", 20000, &so);
        CHECK(so.done && so.closed && so.genus == 0);
        CHECK(so.falsehits == 0 && so.occluded == 0);
        /* the rangefinder's own error on rendered frames is well below 1 mm at these ranges */
        CHECKF(so.worst < 1, "worst probe error %.3f mm", so.worst);
        CHECKF(so.hausdorff < 15, "Hausdorff %.2f mm", so.hausdorff);
        /* the sim board, a while */
        scan("boards/sim.ini", 150, &so);
        CHECK(so.commands == 150 && so.falsehits == 0 && so.worst < 1);
    }
    return vp_test_done("test_port_machine");
}
