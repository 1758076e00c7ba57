/* A re-scan (vp_planner_rescan) against a device written here from the formula of an ellipsoid
 * alone (no host-sim): the object of the re-scan may be another ellipsoid (stretched, moved).
 * Judged from the formula and the mesh, not from the planner's word: the object unchanged, the
 * re-scan measures each sample once and gives the same facets with the same balls; the object
 * changed, the mesh is a closed oriented 2-manifold of Euler characteristic 2 whose vertices and
 * ball centres all lie on the new ellipsoid, every ball at most eps; and in every case no move
 * enters the ellipsoid of the moment. Then the call's contract. */
#include <math.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_run.h"
#include "vp_test.h"
#include "vp_test_ellipsoid.h"

#define ARENA (32u << 20)

typedef vp_test_ell_dev_t ell_dev_t; /* e: the object now */

/* Omega: the first ellipsoid's box grown by 0.3; the head starts above it */
static void config(vp_planner_config_t *c, double eps)
{
    static const double ax[3] = { 1.0, 0.7, 0.5 };
    vp_test_ell_config(c, ax, eps);
}

static unsigned char arena[ARENA];
static vp_planner_t pl;

static void run(ell_dev_t *d, vp_run_result_t *r)
{
    vp_device_ops_t ops;
    memset(&ops, 0, sizeof ops);
    ops.ctx = d;
    ops.move = vp_test_ell_dev_move;
    ops.probe = vp_test_ell_dev_probe;
    vp_run(&pl, &ops, NULL, 2000000, r);
}

/* the facets as (sorted vertex triple, centre, radius) in slot order: a fingerprint */
static uint32_t facets(double *out, uint32_t cap)
{
    uint32_t slots = vp_planner_facet_slots(&pl), i, n = 0, v[3];
    double r, c[3];
    for (i = 0; i < slots && n < cap; i++) {
        if (!vp_planner_facet(&pl, i, v, &r, c)) continue;
        out[7 * n] = v[0]; out[7 * n + 1] = v[1]; out[7 * n + 2] = v[2];
        out[7 * n + 3] = c[0]; out[7 * n + 4] = c[1]; out[7 * n + 5] = c[2]; out[7 * n + 6] = r;
        n++;
    }
    return n;
}

static void fresh(ell_dev_t *d, double eps)
{
    vp_planner_config_t cfg;
    vp_run_result_t r;
    config(&cfg, eps);
    memset(d, 0, sizeof *d);
    d->e.ax[0] = 1.0; d->e.ax[1] = 0.7; d->e.ax[2] = 0.5;
    memcpy(d->pos, cfg.start, sizeof d->pos);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    run(d, &r);
    CHECK(r.status == VP_OK && r.done && d->into == 0);
}

static void test_unchanged(double eps, unsigned flags)
{
    static double before[7 * 20000], after[7 * 20000];
    ell_dev_t d;
    vp_run_result_t r;
    vp_planner_stats_t s;
    uint32_t n0, n1, samples;
    fresh(&d, eps);
    n0 = facets(before, 20000);
    samples = vp_planner_dt(&pl)->ninserted;
    d.probes = d.moves = 0;
    memcpy(d.pos, pl.cfg.start, sizeof d.pos);
    CHECK(vp_planner_rescan_with(&pl, flags) == VP_OK);
    run(&d, &r);
    CHECK(r.status == VP_OK && r.done && d.into == 0);
    vp_planner_get_stats(&pl, &s);
    n1 = facets(after, 20000);
    CHECKF(n0 == n1 && !memcmp(before, after, 7 * sizeof(double) * n0), "unchanged: %u facets before, %u after", n0, n1);
    /* sparse: the samples left out are an independent set of the Delaunay graph (a sample has
     * some 6 neighbours: at most a quarter or so, and a maximal set at least a tenth) */
    CHECKF(d.probes == s.rescan_kept && s.rescan_kept + s.rescan_skipped == samples && s.rescan_dropped == 0 &&
           (flags & VP_RESCAN_SPARSE ? s.rescan_skipped >= samples / 10 && s.rescan_skipped <= samples / 3
                                     : s.rescan_skipped == 0),
           "unchanged: %lu probes for %u samples (%llu kept, %llu not measured)", d.probes, samples,
           (unsigned long long)s.rescan_kept, (unsigned long long)s.rescan_skipped);
    vp_test_ell_judge(&pl, &d.e, eps, "unchanged");
    printf("ellipsoid eps %g, unchanged%s: %u samples, %lu probes (%llu not measured), the same %u facets\n", eps,
           flags & VP_RESCAN_SPARSE ? ", sparse" : "", samples, d.probes, (unsigned long long)s.rescan_skipped, n1);
}

static void test_changed(double eps, const double *ax, const double *c, const char *what, unsigned flags)
{
    ell_dev_t d;
    vp_run_result_t r;
    vp_planner_stats_t s;
    unsigned long p0;
    unsigned nv;
    fresh(&d, eps);
    p0 = d.probes;
    d.probes = d.moves = 0;
    memcpy(d.e.ax, ax, sizeof d.e.ax);
    memcpy(d.e.c, c, sizeof d.e.c);
    memcpy(d.pos, pl.cfg.start, sizeof d.pos);
    CHECK(vp_planner_rescan_with(&pl, flags) == VP_OK);
    run(&d, &r);
    CHECKF(r.status == VP_OK && r.done, "%s: status %d", what, r.status);
    CHECKF(d.into == 0, "%s: %lu moves into the ellipsoid", what, d.into);
    vp_planner_get_stats(&pl, &s);
    CHECK(s.rescan_dropped > 0);
    nv = vp_test_ell_judge(&pl, &d.e, eps, what);
    printf("ellipsoid eps %g, %s%s: %lu probes (the first scan %lu), %llu samples kept, %llu not measured, %llu removed "
           "(%llu moved), %u vertices, %llu route steps proven again (%llu blocked), no move into it\n", eps, what,
           flags & VP_RESCAN_SPARSE ? ", sparse" : "", d.probes, p0, (unsigned long long)s.rescan_kept,
           (unsigned long long)s.rescan_skipped, (unsigned long long)s.rescan_dropped,
           (unsigned long long)s.rescan_moved, nv,
           (unsigned long long)s.reproved, (unsigned long long)s.reprove_blocked);
}

/* A route step proven again (its proof grown old) by a PROBE that hits at the step's very end (within the noise: the
 * step is free) proves it again; the same PROBE passing a contact's point proves nothing (a
 * surface the rangefinder cannot see may stand there, as for any probe): the step is blocked and
 * withdrawn, the hit taken as no point. The contact is put into the planner's table by hand,
 * beside the ray. */
static void test_reprove_near_contact(void)
{
    int with;
    for (with = 0; with < 2; with++) {
        ell_dev_t d;
        vp_cmd_t cmd;
        vp_planner_stats_t a, b;
        int n, got = 0;
        vp_planner_config_t cfg;
        config(&cfg, 0.2);
        cfg.proof_life = 30; /* proofs older than 30 probes are stale: route steps proven again */
        memset(&d, 0, sizeof d);
        d.e.ax[0] = 1.0; d.e.ax[1] = 0.7; d.e.ax[2] = 0.5;
        memcpy(d.pos, cfg.start, sizeof d.pos);
        CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
        for (n = 0; n < 100000 && !got; n++) {
            vp_probe_result_t res;
            int collided = 0;
            if (vp_planner_next(&pl, &cmd) != VP_OK || cmd.kind == VP_CMD_DONE) break;
            if (cmd.kind == VP_CMD_MOVE) {
                CHECK(vp_test_ell_dev_move(&d, &cmd, &collided) == VP_OK);
                continue;
            }
            if (cmd.kind == VP_CMD_PROBE && pl.rescan.reprove && cmd.range > 0.05) {
                int k;
                memset(&res, 0, sizeof res);
                res.hit = 1;
                res.dist = cmd.range; /* at the step's end */
                if (with) {
                    pl.contact.n = 1;
                    pl.contact.reach[0] = 0.01;
                    for (k = 0; k < 3; k++) pl.contact.at[0][k] = cmd.from[k] + 0.5 * cmd.range * cmd.dir[k];
                    pl.contact.at[0][0] += 0.005; /* within reach of the ray, not on it */
                }
                vp_planner_get_stats(&pl, &a);
                CHECK(vp_planner_feed(&pl, &res) == VP_OK);
                vp_planner_get_stats(&pl, &b);
                got = 1;
                if (with)
                    /* blocked with no point: the hit, distrusted, is not taken as a sample (it may
                     * lie at the step's end, past Omega) */
                    CHECKF(b.reproved == a.reproved && b.reprove_blocked == a.reprove_blocked + 1 && pl.rescan.blocked == 2,
                           "a step proven again past a contact (%llu proven, %llu blocked)",
                           (unsigned long long)(b.reproved - a.reproved), (unsigned long long)(b.reprove_blocked - a.reprove_blocked));
                else
                    CHECKF(b.reproved == a.reproved + 1 && b.reprove_blocked == a.reprove_blocked,
                           "a step hit at its end not proven again (%llu proven, %llu blocked)",
                           (unsigned long long)(b.reproved - a.reproved), (unsigned long long)(b.reprove_blocked - a.reprove_blocked));
                break;
            }
            CHECK(vp_test_ell_dev_probe(&d, &cmd, &res) == VP_OK);
            CHECK(vp_planner_feed(&pl, &res) == VP_OK);
        }
        CHECKF(got, "no route step proven again after %d commands", n);
    }
}

static void test_contract(void)
{
    vp_planner_config_t cfg;
    vp_planner_stats_t a, b;
    vp_cmd_t cmd;
    CHECK(vp_planner_rescan(NULL) == VP_EINVAL);
    CHECK(vp_planner_rescan_with(NULL, 0) == VP_EINVAL);
    config(&cfg, 0.2);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    CHECK(vp_planner_rescan(&pl) == VP_ESTATE); /* no samples yet */
    do CHECK(vp_planner_next(&pl, &cmd) == VP_OK); while (cmd.kind == VP_CMD_MOVE);
    CHECK(cmd.kind == VP_CMD_PROBE);
    vp_planner_get_stats(&pl, &a);
    CHECK(vp_planner_rescan(&pl) == VP_ESTATE); /* a PROBE result is owed */
    CHECK(vp_planner_rescan_with(&pl, 4u) == VP_EINVAL); /* no such flag */
    vp_planner_get_stats(&pl, &b);
    CHECK(memcmp(&a, &b, sizeof a) == 0);
}

int main(void)
{
    static const double stretched[3] = { 1.08, 0.7, 0.5 }, same[3] = { 1.0, 0.7, 0.5 };
    static const double origin[3] = { 0, 0, 0 }, moved[3] = { 0.04, -0.03, 0.02 };
    test_contract();
    test_reprove_near_contact();
    test_unchanged(0.2, 0);
    test_unchanged(0.1, 0);
    test_unchanged(0.1, VP_RESCAN_SPARSE);
    test_changed(0.15, stretched, origin, "stretched along x by 8%", 0);
    test_changed(0.15, same, moved, "moved by 0.054", 0);
    test_changed(0.15, stretched, origin, "stretched along x by 8%", VP_RESCAN_SPARSE);
    test_changed(0.15, same, moved, "moved by 0.054", VP_RESCAN_SPARSE);
    return vp_test_done("test_rescan");
}
