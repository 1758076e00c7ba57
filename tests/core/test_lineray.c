/* A line laser's frames in the planner (vp_planner_feed_ray), against a device written here from
 * the formula of an ellipsoid alone (no host-sim): each PROBE's frame carries N more rays in
 * the plane of the probe's ray and a fixed direction across it. Checked from the formula and the
 * mesh, not from the planner's own word: every sample lies on the ellipsoid, the mesh is a
 * closed oriented 2-manifold of Euler characteristic 2, every surface Delaunay ball (its centre
 * on the ellipsoid, recomputed here) is at most eps and empty of the other samples' ... at
 * its vertices, the samples keep the spacing the refinement keeps (no two farther than the seed
 * triangle's apart closer than eps), and the line laser probes less than the dot laser. Then
 * the call's contract and the log format's RAY record and version-4 header. */
#include <math.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_run.h"
#include "vp_logfmt.h"
#include "vp_test.h"
#include "vp_test_ellipsoid.h"

#define ARENA (32u << 20)
static const double AX[3] = { 1.0, 0.7, 0.5 }; /* semi-axes */

typedef struct ell_dev {
    vp_test_ell_dev_t b;     /* the ellipsoid, the device's place, its counts */
    unsigned nrays;          /* more rays per frame */
    double half;             /* half fan angle, rad */
    unsigned long rays, ray_hits;
} ell_dev_t;

static const vp_test_ell_t ELL = { { 1.0, 0.7, 0.5 }, { 0, 0, 0 } };
static int ell_first(const double *p, const double *u, double len, double *t) { return vp_test_ell_first(&ELL, p, u, len, t); }

/* ray i: the fan in the plane of the probe's ray and the axis least along it */
static int dev_rays(void *ctx, const vp_cmd_t *probe, unsigned i, vp_cmd_t *ray, vp_probe_result_t *res)
{
    ell_dev_t *d = ctx;
    double a[3] = { 0, 0, 0 }, h[3], n, th, t;
    int k, m = 0;
    if (i >= d->nrays) return 0;
    for (k = 1; k < 3; k++)
        if (fabs(probe->dir[k]) < fabs(probe->dir[m])) m = k;
    a[m] = 1.0;
    h[0] = probe->dir[1] * a[2] - probe->dir[2] * a[1];
    h[1] = probe->dir[2] * a[0] - probe->dir[0] * a[2];
    h[2] = probe->dir[0] * a[1] - probe->dir[1] * a[0];
    n = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    th = d->half * (2.0 * ((double)i + 0.5) / (double)d->nrays - 1.0);
    for (k = 0; k < 3; k++) ray->dir[k] = cos(th) * probe->dir[k] + sin(th) * h[k] / n;
    n = sqrt(ray->dir[0] * ray->dir[0] + ray->dir[1] * ray->dir[1] + ray->dir[2] * ray->dir[2]);
    for (k = 0; k < 3; k++) ray->dir[k] /= n;
    ray->range = 10.0;
    d->rays++;
    res->hit = ell_first(probe->from, ray->dir, ray->range, &t);
    res->dist = res->hit ? t : 0.0;
    d->ray_hits += (unsigned long)res->hit;
    return 1;
}

/* Omega: the ellipsoid's box grown by 0.3; the head starts above it, the interior point is its centre */
static void config(vp_planner_config_t *c, double eps, unsigned nrays)
{
    vp_test_ell_config(c, AX, eps);
    c->line_rays = nrays;
}

static unsigned char arena[ARENA];
static vp_planner_t pl;

/* no two samples closer than eps but the seeds' (the persistent facet's tiny triangle and the
 * points found with it, the first inserted) */
static double min_spacing(uint32_t skip)
{
    const vp_dt_t *dt = vp_planner_dt(&pl);
    uint32_t i, j;
    double m = 1e300;
    for (i = skip; i < dt->nvert; i++)
        for (j = i + 1; j < dt->nvert; j++) {
            const double *p = vp_dt_point(dt, i), *q = vp_dt_point(dt, j);
            double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
            if (d < m) m = d;
        }
    return m;
}

static void scan(double eps, unsigned nrays, ell_dev_t *d, vp_planner_stats_t *st, vp_run_result_t *run)
{
    vp_planner_config_t cfg;
    vp_device_ops_t ops;
    config(&cfg, eps, nrays);
    memset(d, 0, sizeof *d);
    d->b.e = ELL;
    memcpy(d->b.pos, cfg.start, sizeof d->b.pos);
    d->nrays = nrays;
    d->half = 15.0 * M_PI / 180.0;
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    ops.ctx = d;
    ops.move = vp_test_ell_dev_move;
    ops.probe = vp_test_ell_dev_probe;
    ops.touched = NULL;
    ops.rays = nrays ? dev_rays : NULL;
    ops.move_path = NULL;
    ops.sight = NULL;
    vp_run(&pl, &ops, NULL, 2000000, run);
    vp_planner_get_stats(&pl, st);
}

static void test_scans(void)
{
    static const double epss[] = { 0.2, 0.1 };
    int e;
    for (e = 0; e < 2; e++) {
        ell_dev_t d0, d1;
        vp_planner_stats_t s0, s1;
        vp_run_result_t r0, r1;
        unsigned nv0, nv1;
        double sp;
        scan(epss[e], 0, &d0, &s0, &r0);
        CHECK(r0.status == VP_OK && r0.done && d0.b.into == 0);
        nv0 = vp_test_ell_judge(&pl, &ELL, epss[e], "dot laser");
        scan(epss[e], 16, &d1, &s1, &r1);
        CHECK(r1.status == VP_OK && r1.done && d1.b.into == 0);
        nv1 = vp_test_ell_judge(&pl, &ELL, epss[e], "line laser");
        /* every ray fed, its hits counted alike; some became samples */
        CHECK(s1.rays == d1.rays && s1.ray_hits == d1.ray_hits && s1.ray_samples > 0);
        /* the seeds are the first samples inserted; after them the spacing is eps */
        sp = min_spacing(pl.seed.npts);
        CHECKF(sp > epss[e] * (1 - 1e-9) || s1.ray_samples == 0, "samples %.9g apart at eps %g", sp, epss[e]);
        CHECKF(d1.b.probes < d0.b.probes, "line laser %lu probes, dot laser %lu", d1.b.probes, d0.b.probes);
        printf("ellipsoid eps %g: dot laser %lu probes, %u vertices; line laser (16 rays) %lu probes, %u vertices, "
               "%llu samples from %lu ray hits; no moves into it\n", epss[e], d0.b.probes, nv0, d1.b.probes, nv1,
               (unsigned long long)s1.ray_samples, d1.ray_hits);
    }
}

static void test_contract(void)
{
    vp_planner_config_t cfg;
    vp_planner_stats_t a, b;
    vp_cmd_t cmd;
    vp_probe_result_t res = { 1, 0.5 }, bad;
    double x[3] = { 1, 0, 0 }, nanv[3] = { NAN, 0, 0 }, two[3] = { 2, 0, 0 };
    unsigned i;
    config(&cfg, 0.2, VP_PLANNER_MAX_LINE_RAYS + 1);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_EINVAL);
    /* a dot laser takes no rays */
    config(&cfg, 0.2, 0);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    CHECK(vp_planner_next(&pl, &cmd) == VP_OK);
    CHECK(vp_planner_feed_ray(&pl, x, &res) == VP_ESTATE);
    /* a line laser: not before a PROBE is fed, not while one is owed, not beyond line_rays */
    config(&cfg, 0.2, 3);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    CHECK(vp_planner_feed_ray(&pl, x, &res) == VP_ESTATE);
    do CHECK(vp_planner_next(&pl, &cmd) == VP_OK); while (cmd.kind == VP_CMD_MOVE);
    CHECK(cmd.kind == VP_CMD_PROBE);
    CHECK(vp_planner_feed_ray(&pl, x, &res) == VP_ESTATE);
    CHECK(vp_planner_feed(&pl, &res) == VP_OK);
    vp_planner_get_stats(&pl, &a);
    CHECK(vp_planner_feed_ray(NULL, x, &res) == VP_EINVAL);
    CHECK(vp_planner_feed_ray(&pl, NULL, &res) == VP_EINVAL);
    CHECK(vp_planner_feed_ray(&pl, x, NULL) == VP_EINVAL);
    CHECK(vp_planner_feed_ray(&pl, nanv, &res) == VP_EINVAL);
    CHECK(vp_planner_feed_ray(&pl, two, &res) == VP_EINVAL);
    bad = res; bad.hit = 3;
    CHECK(vp_planner_feed_ray(&pl, x, &bad) == VP_EINVAL);
    bad = res; bad.dist = -1.0;
    CHECK(vp_planner_feed_ray(&pl, x, &bad) == VP_EINVAL);
    bad = res; bad.dist = NAN;
    CHECK(vp_planner_feed_ray(&pl, x, &bad) == VP_EINVAL);
    vp_planner_get_stats(&pl, &b);
    CHECK(memcmp(&a, &b, sizeof a) == 0); /* refused: nothing changed */
    for (i = 0; i < 3; i++) CHECK(vp_planner_feed_ray(&pl, x, &res) == VP_OK);
    CHECK(vp_planner_feed_ray(&pl, x, &res) == VP_ESTATE);
    vp_planner_get_stats(&pl, &b);
    CHECK(b.rays == 3 && b.ray_hits == 3);
    CHECK(vp_planner_next(&pl, &cmd) == VP_OK); /* the planner goes on */
    /* the frame is over once the next command is issued: no ray after it (a MOVE, or a PROBE owed) */
    vp_planner_get_stats(&pl, &a);
    CHECK(vp_planner_feed_ray(&pl, x, &res) == VP_ESTATE);
    vp_planner_get_stats(&pl, &b);
    CHECK(memcmp(&a, &b, sizeof a) == 0);
}

static void test_log(void)
{
    vp_planner_config_t cfg;
    vp_logfmt_header_t h, g;
    vp_logfmt_record_t r, q;
    vp_cmd_t cmd;
    vp_probe_result_t res = { 1, 0.25 };
    unsigned char buf[VP_LOGFMT_MAX_HEADER];
    int n, why;
    /* a dot laser's header stays in the oldest version; a line laser's is version 4 */
    config(&cfg, 0.2, 0);
    vp_logfmt_header_init(&h, &cfg, 1u << 20, VP_LOGFMT_UNITS_MM, "b", "n");
    CHECK(h.version == 1);
    config(&cfg, 0.2, 24);
    vp_logfmt_header_init(&h, &cfg, 1u << 20, VP_LOGFMT_UNITS_MM, "b", "n");
    CHECK(h.version == 4);
    n = vp_logfmt_header_encode(&h, buf, sizeof buf);
    CHECK(n > 0 && vp_logfmt_header_decode(buf, (size_t)n, &g, &why) == n && g.version == 4 && g.cfg.line_rays == 24);
    /* a RAY has the PROBE's layout and its own type */
    memset(&cmd, 0, sizeof cmd);
    cmd.kind = VP_CMD_RAY;
    cmd.from[0] = 0.5; cmd.dir[1] = 1.0; cmd.range = 3.0;
    vp_logfmt_record_probe(&r, 7, &cmd, &res, 0.25);
    CHECK(r.type == VP_LOGFMT_RAY);
    n = vp_logfmt_record_encode(&r, buf, sizeof buf);
    CHECK(n == VP_LOGFMT_PROBE_SIZE && vp_logfmt_record_decode(buf, (size_t)n, &q, &why) == n);
    CHECK(q.type == VP_LOGFMT_RAY && q.seq == 7 && q.dir[1] == 1.0 && q.dist == 0.25 && q.hit == 1 && q.origin[0] == 0.5);
}

int main(void)
{
    test_contract();
    test_log();
    test_scans();
    return vp_test_done("test_lineray");
}
