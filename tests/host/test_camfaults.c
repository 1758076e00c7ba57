/* A real world's frame faults on the rpi4 board's dry run, probe by probe against the renderer's
 * truth: laser speckle, the head still ringing after a move, mains flicker between the laser-off
 * and laser-on frames, a glint that moves, a dark surface. For each fault alone and all together
 * a whole scan of the board's object, every probe judged against what the renderer drew:
 *   - a hit: within TOL_MM of the true distance along the true beam, else a false hit (a hit
 *     where the truth is a miss, or farther or nearer than the tolerance);
 *   - a miss where the truth is a hit whose spot the renderer drew well above the noise (peak at
 *     least BRIGHT x the noise): a false miss (unsafe: the planner takes it for free space);
 *     a miss where the drawn spot is below that: a dark miss, counted;
 *   - frames exposed with the laser in the wrong state: 0; moves through the object: 0.
 * The machine's check that these faults need ([rangefinder] confirm_spot, port/vp_machine.c: a second
 * laser-on frame shows the spot where the first did, and the laser-off frame is plain there) is
 * switched off once to show that the faults defeat the detector without it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_board.h"
#include "vp_camsim.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_rng.h"
#include "vp_scan.h"
#include "vp_session.h"
#include "vp_status.h"
#include "vp_test.h"

/* the noise tolerance a scan trusts hits to (scan --noise-tol, default 2 mm): a hit farther off
 * than that would make the planner take a piece of the object for free space */
#define TOL_MM 2.0
#define BRIGHT 10.0

typedef struct tally {
    vp_scan_dev_t *d;
    double noise;
    unsigned long probes, hits, misses, unreadable, false_hits, false_misses, dark_misses, pre, dark_probes;
    double err2, worst, worst_false;
    double dark_peak;             /* the brightest spot drawn among the dark misses */
} tally_t;

static int judge(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    tally_t *t = ctx;
    const vp_camsim_truth_t *on, *off;
    int truth_hit;
    if (!res || cmd->kind != VP_CMD_PROBE) return 0;
    {
        /* the frames the machine read, by their numbers: laser off, laser on (and its confirmation) */
        const vp_machine_last_t *l = &t->d->m->last;
        const vp_camsim_truth_t *c2 = l->seq_confirm >= 0 ? vp_camsim_truth_of(t->d->dr->cs, l->seq_confirm) : NULL;
        on = vp_camsim_truth_of(t->d->dr->cs, l->seq);
        off = vp_camsim_truth_of(t->d->dr->cs, l->seq_off);
        t->probes++;
        if (!on || !off || !on->laser || off->laser || (l->seq_confirm >= 0 && (!c2 || !c2->laser))) {
            t->pre++;
            return 0;
        }
    }
    truth_hit = on->hit && on->dist <= cmd->range + TOL_MM;
    if (getenv("VP_CAMFAULTS_VERBOSE"))
        printf("probe %lu: result %d dist %.3f spot %d (%.1f, %.1f) peak %.1f | truth hit %d vis %d dist %.3f peak %.1f "
               "albedo %.3g speckle %.2f vib %.2f px | range %.1f\n", t->probes, res->hit, res->dist,
               t->d->m->last.spot.result, t->d->m->last.spot.u, t->d->m->last.spot.v, t->d->m->last.spot.peak, on->hit,
               on->visible, on->dist, on->peak, on->albedo, on->speckle_gain, on->vib_px, cmd->range);
    if (on->hit && on->albedo < 1) t->dark_probes++;
    if (res->hit == VP_PROBE_TOO_CLOSE) { t->unreadable++; return 0; }
    if (res->hit) {
        double e = truth_hit ? fabs(res->dist - on->dist) : HUGE_VAL;
        t->hits++;
        if (e > TOL_MM) {
            t->false_hits++;
            if (truth_hit && e > t->worst_false) t->worst_false = e;
            return 0;
        }
        t->err2 += e * e;
        if (e > t->worst) t->worst = e;
        return 0;
    }
    t->misses++;
    if (on->hit && on->dist <= cmd->range - TOL_MM && on->visible && on->dist >= t->d->m->tri.min_range) {
        if (on->peak >= BRIGHT * t->noise) t->false_misses++;
        else {
            t->dark_misses++;
            if (on->peak > t->dark_peak) t->dark_peak = on->peak;
        }
    }
    return 0;
}

typedef struct fault {
    const char *name;
    int no_settle;                /* 1: settle_ms 0 (the board waits 30 ms) */
    double speckle[2], vibration[4], flicker[2], glint[6], dark[3];
} fault_t;

static const fault_t faults[] = {
    { "none", 0, { 0, 0 }, { 0, 0, 0, 0 }, { 0, 0 }, { 0, 0, 0, 0, 0, 0 }, { 0, 0, 0 } },
    { "speckle", 0, { 1, 8 }, { 0, 0, 0, 0 }, { 0, 0 }, { 0, 0, 0, 0, 0, 0 }, { 0, 0, 0 } },
    { "vibration", 0, { 0, 0 }, { 8, 150, 40, 0 }, { 0, 0 }, { 0, 0, 0, 0, 0, 0 }, { 0, 0, 0 } },
    { "vib+nosettle", 1, { 0, 0 }, { 8, 150, 40, 0 }, { 0, 0 }, { 0, 0, 0, 0, 0, 0 }, { 0, 0, 0 } },
    { "flicker", 0, { 0, 0 }, { 0, 0, 0, 0 }, { 0.6, 100 }, { 0, 0, 0, 0, 0, 0 }, { 0, 0, 0 } },
    { "speckle+vib+flicker", 0, { 1, 8 }, { 8, 150, 40, 0 }, { 0.6, 100 }, { 0, 0, 0, 0, 0, 0 }, { 0, 0, 0 } },
    { "dark", 0, { 0, 0 }, { 0, 0, 0, 0 }, { 0, 0 }, { 0, 0, 0, 0, 0, 0 }, { 0.0007, 144, 156 } },
    { "glint+dark", 0, { 0, 0 }, { 0, 0, 0, 0 }, { 0, 0 }, { 60, 2, 40, 10, 12, 700 }, { 0.0007, 144, 156 } },
    { "all", 0, { 1, 8 }, { 8, 150, 40, 0 }, { 0.6, 100 }, { 60, 2, 40, 10, 12, 700 }, { 0.0007, 144, 156 } },
};

static vp_board_t board;
static unsigned long moved_n, off_lit_n;      /* the last scan's refusals by the confirmation */

/* One dry-run scan of the board's object with fault f; settle_ms as given (< 0: the board's). */
static int scan(const fault_t *f, double settle_ms, int hardened, tally_t *t, vp_session_result_t *sr, int *closed)
{
    vp_board_t b = board;
    vp_scan_dev_t d;
    vp_planner_config_t cfg;
    vp_planner_t *pl;
    vp_session_hooks_t hooks;
    vp_device_ops_t ops;
    void *arena;
    char err[400], surf[300];
    size_t bytes = (size_t)32 << 20;
    int st;
    memcpy(b.sim_speckle, f->speckle, sizeof b.sim_speckle);
    memcpy(b.sim_vibration, f->vibration, sizeof b.sim_vibration);
    memcpy(b.sim_flicker, f->flicker, sizeof b.sim_flicker);
    memcpy(b.sim_glint, f->glint, sizeof b.sim_glint);
    memcpy(b.sim_dark, f->dark, sizeof b.sim_dark);
    if (settle_ms >= 0) b.settle_ms = settle_ms;
    b.confirm_spot = hardened;
    memset(t, 0, sizeof *t);
    memset(sr, 0, sizeof *sr);
    *closed = 0;
    CHECK(vp_scan_dry_surface(&b, NULL, surf, sizeof surf, err, sizeof err) == VP_OK);
    st = vp_scan_open(&d, &b, 1, surf, 0, 0, err, sizeof err);
    CHECKF(st == VP_OK, "%s", err);
    if (st != VP_OK) return st;
    t->d = &d;
    t->noise = b.sim_noise;
    vp_board_planner_config(&b, &cfg);
    pl = malloc(sizeof *pl);
    arena = malloc(bytes);
    CHECK(pl && arena);
    st = vp_planner_init(pl, arena, bytes, &cfg);
    CHECKF(st == VP_OK, "planner %d", st);
    if (st == VP_OK) st = vp_scan_home(&d, err, sizeof err);
    if (st == VP_OK) st = vp_scan_goto(&d, b.start, err, sizeof err);
    CHECKF(st == VP_OK, "%s", err);
    if (st == VP_OK) {
        vp_mesh_t mesh;
        vp_meshcheck_t mc;
        ops = vp_scan_ops(&d);
        hooks.ctx = t;
        hooks.after = judge;
        st = vp_session_run(pl, &ops, &hooks, 20000, NULL, sr);
        vp_mesh_init(&mesh);
        if (st == VP_OK && vp_session_mesh(pl, &mesh) == VP_OK) {
            if (vp_meshcheck_analyze(&mesh, &mc) == VP_OK) {
                *closed = mc.closed_manifold;
                vp_meshcheck_free(&mc);
            }
        }
        vp_mesh_free(&mesh);
        sr->collisions = d.through;
        moved_n = d.m->st.moved;
        off_lit_n = d.m->st.off_lit;
    }
    free(arena);
    free(pl);
    vp_scan_close(&d);
    return st;
}

static void report(const char *name, const char *how, int st, const tally_t *t, const vp_session_result_t *sr, int closed)
{
    unsigned long good = t->hits - t->false_hits;
    printf("%-19s %s: %s, %lu probes: %lu hits (error rms %.3f mm, worst %.3f mm), %lu false hits (worst %.1f mm), "
           "%lu misses of which %lu false and %lu dark (%lu probes on the dark part; drawn peak at most %.1f, noise %g), "
           "%lu unreadable (%lu moved, %lu lit without the laser), %lu frames from before the laser, %lu collisions, mesh "
           "%s\n",
           name, how, st == VP_OK ? "DONE" : vp_strerror(st), t->probes, t->hits, good ? sqrt(t->err2 / good) : 0.0,
           t->worst, t->false_hits, t->false_hits ? t->worst_false : 0.0, t->misses, t->false_misses, t->dark_misses,
           t->dark_probes, t->dark_peak, t->noise, t->unreadable, moved_n, off_lit_n, t->pre, sr->collisions, closed ? "closed" : "open");
}

static int quick;

int main(int argc, char **argv)
{
    char err[300];
    size_t i;
    int rc = vp_board_load("boards/rpi4-gantry.ini", &board, err, sizeof err), st, closed, only = -1;
    tally_t t;
    vp_session_result_t sr;
    double rms_settled = 0, rms_unsettled = 0;
    CHECKF(rc == VP_OK, "%s", err);
    if (rc != VP_OK) return vp_test_done("test_camfaults");
    if (argc > 1) only = atoi(argv[1]);
    {
        /* VP_TEST_QUICK=1 (under qemu): speckle, ringing and flicker together; every case
         * natively */
        const char *q = getenv("VP_TEST_QUICK");
        quick = q && *q == '1';
    }
    for (i = 0; i < sizeof faults / sizeof faults[0]; i++) {
        const char *name = faults[i].name;
        unsigned long good;
        if (only >= 0 && (size_t)only != i) continue;
        if (quick && only < 0 && strcmp(name, "speckle+vib+flicker")) continue;
        st = scan(&faults[i], faults[i].no_settle ? 0 : -1, 1, &t, &sr, &closed);
        report(name, "confirmed", st, &t, &sr, closed);
        good = t.hits - t.false_hits;
        CHECKF(st == VP_OK, "%s: %s", name, vp_strerror(st));
        CHECKF(t.false_hits == 0, "%s: %lu false hits", name, t.false_hits);
        CHECKF(t.false_misses == 0, "%s: %lu false misses", name, t.false_misses);
        CHECKF(t.pre == 0 && sr.collisions == 0, "%s: %lu pre-switch frames, %lu collisions", name, t.pre, sr.collisions);
        CHECKF(t.worst <= TOL_MM && good > 20, "%s: worst %.3f over %lu hits", name, t.worst, good);
        if (faults[i].dark[0] > 0) {
            /* the dark band's spots under the noise are misses (judged with every drawn spot as
             * bright, each of them would be a false miss: the check sees them) */
            CHECKF(t.dark_misses > 0, "%s: no miss on the dark band", name);
        }
        if (!strcmp(name, "vibration")) rms_settled = sqrt(t.err2 / (double)good);
        if (!strcmp(name, "vib+nosettle")) {
            rms_unsettled = sqrt(t.err2 / (double)good);
            /* the board's settle_ms (30) lets the ringing decay: half the error of no wait */
            CHECKF(rms_settled > 0 && rms_unsettled > 1.5 * rms_settled, "settled %.3f, not %.3f", rms_settled, rms_unsettled);
        }
        if (!strcmp(name, "glint+dark")) {
            /* without the confirmation the moving glint is read as the spot: false hits */
            st = scan(&faults[i], faults[i].no_settle ? 0 : -1, 0, &t, &sr, &closed);
            report(name, "unconfirmed", st, &t, &sr, closed);
            CHECKF(t.false_hits > 0, "%s without confirmation: no false hit", name);
        }
    }
    return vp_test_done("test_camfaults");
}
