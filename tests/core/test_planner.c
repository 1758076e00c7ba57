/* The probe planner on host-sim: closed 2-manifolds of the right genus and component count,
 * every ball <= eps, Hausdorff within the paper's bound, zero collisions; vertex count growing
 * like 1/eps^2; noise and dropouts; every error path. VP_TEST_QUICK=1 (set under qemu) runs a
 * reduced set. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_sim_setup.h"
#include "vp_session.h"
#include "vp_vec3.h"
#include "vp_test.h"

static int quick;

/* Options of a quiet scan that writes nothing. */
static void quiet_options(vp_sim_options_t *o, const char *surface, double eps_rel)
{
    vp_sim_options_default(o);
    o->surface = surface;
    o->eps_rel = eps_rel;
    o->out = NULL;
    o->hausdorff = 0;
    o->quiet = 1;
}

typedef struct scan_result {
    int status, closed, components, genus;
    unsigned vertices, facets, collisions, missing;
    double max_ball, hausdorff, eps, min_angle;
    unsigned long long probes, hits;
} scan_result_t;

static void scan(const char *surface, double eps_rel, unsigned flags, double noise, double dropout,
                 size_t hausdorff, scan_result_t *r)
{
    vp_sim_options_t o;
    vp_sim_t s;
    vp_planner_stats_t st;
    vp_simdev_stats_t ds;
    char err[512];
    memset(r, 0, sizeof *r);
    quiet_options(&o, surface, eps_rel);
    o.flags = flags;
    o.noise = noise;
    o.dropout = dropout;
    o.hausdorff = hausdorff;
    o.arena = (size_t)64 << 20;
    r->status = vp_sim_open(&s, &o, err, sizeof err);
    if (r->status != VP_OK) {
        fprintf(stderr, "%s: %s\n", surface, err);
        vp_sim_close(&s);
        return;
    }
    r->status = vp_sim_run(&s, NULL);
    if (vp_sim_finish(&s, &o, err, sizeof err) != VP_OK) r->status = VP_EIO;
    vp_planner_get_stats(s.pl, &st);
    vp_simdev_stats(s.dev, &ds);
    /* the planner's counts of answers against the device's own (the seed's probes too) */
    CHECKF(st.probes == ds.probes && st.hits == ds.hits && st.misses == ds.misses && st.too_close == ds.too_close,
           "%s: planner %llu probes = %llu hits + %llu misses + %llu too close; device %lu = %lu + %lu + %lu",
           surface, (unsigned long long)st.probes, (unsigned long long)st.hits, (unsigned long long)st.misses,
           (unsigned long long)st.too_close, ds.probes, ds.hits, ds.misses, ds.too_close);
    r->eps = s.cfg.eps;
    r->vertices = (unsigned)s.mesh.nv;
    r->facets = (unsigned)s.mesh.nt;
    r->closed = s.have_check && s.check.closed_manifold && s.check.outward;
    r->components = s.have_check ? s.check.components : -1;
    r->genus = s.have_check ? s.check.genus : -1;
    r->min_angle = s.have_check ? s.check.min_angle_deg : 0.0;
    r->collisions = (unsigned)ds.collisions;
    r->max_ball = st.max_ball;
    r->missing = st.missing_components;
    r->hausdorff = s.have_haus ? s.haus.hausdorff : -1.0;
    r->probes = st.probes;
    r->hits = st.hits;
    printf("%-34s eps %.4f: %5u vertices, closed %d, comps %d, genus %d, ball %.4f, haus %.5f, "
           "coll %u, %.2f probes/vertex\n", surface, r->eps, r->vertices, r->closed, r->components,
           r->genus, r->max_ball, r->hausdorff, r->collisions,
           r->vertices ? (double)r->probes / r->vertices : 0.0);
    vp_sim_close(&s);
}

/* The object's guarantees: status, manifold, topology, balls, collisions, Hausdorff. */
static void check_scan(const scan_result_t *r, int comps, int genus, double haus_bound)
{
    CHECK(r->status == VP_OK);
    CHECK(r->closed);
    CHECKF(r->components == comps, "components %d, expected %d", r->components, comps);
    CHECKF(r->genus == genus, "genus %d, expected %d", r->genus, genus);
    CHECKF(r->max_ball <= r->eps, "largest ball %.6g > eps %.6g", r->max_ball, r->eps);
    CHECK(r->collisions == 0);
    CHECK(r->missing == 0);
    if (haus_bound > 0) CHECKF(r->hausdorff >= 0 && r->hausdorff <= haus_bound, "Hausdorff %.6g > %.6g", r->hausdorff, haus_bound);
}

/* Hausdorff bound of Theorem 2.1: 4.5 diam(S) / rch(S)^2 * eps^2 (reach of the sphere 1, of
 * the torus min(r, R - r) = 0.3). For genus2/genus5 we check the empirical O(eps^2) scale
 * against 2 eps instead (their reach is not known in closed form). */
static void test_surfaces(void)
{
    scan_result_t r, r2;
    scan("sphere", 0.05, 0, 0, 0, 4000, &r);
    check_scan(&r, 1, 0, 4.5 * 2.0 / 1.0 * r.eps * r.eps);
    scan("torus", 0.04, 0, 0, 0, 4000, &r);
    check_scan(&r, 1, 1, 4.5 * 2.6 / 0.09 * r.eps * r.eps);
    scan("genus2", 0.03, 0, 0, 0, 4000, &r);
    check_scan(&r, 1, 2, 2.0 * r.eps);
    if (!quick) {
        scan("genus5", 0.025, 0, 0, 0, 4000, &r);
        check_scan(&r, 1, 5, 2.0 * r.eps);
        scan("ellipsoid", 0.03, 0, 0, 0, 4000, &r);
        check_scan(&r, 1, 0, 2.0 * r.eps);
        scan("blobby", 0.03, 0, 0, 0, 4000, &r);
        check_scan(&r, 1, 0, 2.0 * r.eps);
        scan("torus", 0.02, 0, 0, 0, 4000, &r2);
        check_scan(&r2, 1, 1, 4.5 * 2.6 / 0.09 * r2.eps * r2.eps);
    }
    /* vertex count like 1/eps^2: halving eps multiplies it by about 4 */
    scan("sphere", 0.04, 0, 0, 0, 0, &r);
    scan("sphere", 0.02, 0, 0, 0, 0, &r2);
    CHECKF(r2.vertices > 3.2 * r.vertices && r2.vertices < 4.8 * r.vertices, "%u -> %u", r.vertices, r2.vertices);
    check_scan(&r2, 1, 0, 0);
    /* several components at once, with a seed missed on purpose by the geometry */
    scan("sphere*0.5@0,0,2+sphere*0.5@0,0,-2+torus", 0.02, 0, 0, 0, 3000, &r);
    check_scan(&r, 3, 1, 2.0 * r.eps);
    scan("sphere@3,0,0+torus", 0.02, 0, 0, 0, 3000, &r);
    check_scan(&r, 2, 1, 2.0 * r.eps);
}

/* The optional angle bound: no triangle angle below it at the end. */
static void test_angle_bound(void)
{
    vp_sim_options_t o;
    vp_sim_t s;
    char err[512];
    quiet_options(&o, "torus", 0.02);
    o.min_angle = 25.0;
    CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
    CHECK(vp_sim_run(&s, NULL) == VP_OK);
    CHECK(vp_sim_finish(&s, &o, err, sizeof err) == VP_OK);
    CHECK(s.have_check && s.check.closed_manifold && s.check.genus == 1);
    CHECKF(s.check.min_angle_deg >= 25.0 - 1e-6, "smallest angle %.3f", s.check.min_angle_deg);
    printf("torus with a 25 degree bound: %zu vertices, smallest angle %.2f\n", s.mesh.nv, s.check.min_angle_deg);
    vp_sim_close(&s);
}

/* The published rule (probe every edge, prev chains, largest ball first) gives the same
 * guarantees, with more probes. */
static void test_paper_mode(void)
{
    scan_result_t a, b;
    scan("torus", 0.04, VP_PLAN_PAPER | VP_PLAN_PREV_CHAINS | VP_PLAN_LARGEST, 0, 0, 3000, &a);
    check_scan(&a, 1, 1, 4.5 * 2.6 / 0.09 * a.eps * a.eps);
    scan("torus", 0.04, 0, 0, 0, 0, &b);
    CHECKF(b.probes < a.probes, "probes: ours %llu, paper %llu", b.probes, a.probes);
}

/* A rangefinder with a minimum range: what it cannot measure is never taken as free (zero
 * collisions); where it hides a facet the mesh is reported open, not patched. */
static void test_min_range(void)
{
    vp_sim_options_t o;
    vp_sim_t s;
    vp_planner_stats_t st;
    vp_simdev_stats_t ds;
    char err[512];
    quiet_options(&o, "torus", 0.02);
    o.min_range = 0.02;
    CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
    CHECK(vp_sim_run(&s, NULL) == VP_OK);
    CHECK(vp_sim_finish(&s, &o, err, sizeof err) == VP_OK);
    vp_planner_get_stats(s.pl, &st);
    vp_simdev_stats(s.dev, &ds);
    CHECK(ds.collisions == 0);
    CHECK(st.too_close > 0 && st.too_close == ds.too_close && st.hits + st.misses + st.too_close == st.probes);
    printf("torus with a 0.02 minimum range: %llu probes too close, %zu boundary edges, collisions %lu\n",
           (unsigned long long)st.too_close, s.check.boundary_edges, ds.collisions);
    vp_sim_close(&s);
}

/* Body mode: a MOVE that leads to a PROBE names it (cmd dir: the PROBE's direction; range: the
 * length of the MOVEs left after it), so that a machine may turn the head on the way. Checked
 * against the commands that follow: each MOVE's hint against the next PROBE, its range against
 * the MOVEs actually issued before that PROBE, the last one ending at the PROBE's origin. */
typedef struct hint_check {
    vp_cmd_t moves[256];
    unsigned n, overflow;
    unsigned long hinted, probes_after, bad_dir, bad_range, bad_end;
    double worst_range;
} hint_check_t;

static int hint_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    hint_check_t *h = ctx;
    unsigned i;
    (void)res;
    if (cmd->kind == VP_CMD_MOVE) {
        if (h->n < 256) h->moves[h->n++] = *cmd;
        else h->overflow++;
        return 0;
    }
    if (cmd->kind == VP_CMD_PROBE && h->n > 0) {
        double left = 0.0;
        int any = 0;
        for (i = h->n; i-- > 0;) {
            const vp_cmd_t *m = &h->moves[i];
            int hinted = m->dir[0] != 0.0 || m->dir[1] != 0.0 || m->dir[2] != 0.0;
            if (!hinted) { left += vp_dist3(m->from, m->to); continue; }
            any = 1;
            h->hinted++;
            if (!(vp_dot3(m->dir, cmd->dir) > 1.0 - 1e-12)) h->bad_dir++;
            if (fabs(m->range - left) > 1e-9 * (1.0 + left)) h->bad_range++;
            if (fabs(m->range - left) > h->worst_range) h->worst_range = fabs(m->range - left);
            if (i == h->n - 1 && vp_dist3(m->to, cmd->from) > 1e-12) h->bad_end++;
            left += vp_dist3(m->from, m->to);
        }
        h->probes_after += any;
    }
    h->n = 0;
    return 0;
}

static void test_move_hints(void)
{
    const char *objs[2] = { "torus", "blobby" };
    int i;
    for (i = 0; i < 2; i++) {
        vp_sim_options_t o;
        vp_sim_t s;
        vp_session_hooks_t hk;
        static hint_check_t h;
        char err[512];
        memset(&h, 0, sizeof h);
        quiet_options(&o, objs[i], 0.04);
        o.clearance = 0.05;
        CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
        hk.ctx = &h;
        hk.after = hint_after;
        s.hooks = &hk;
        CHECK(vp_sim_run(&s, NULL) == VP_OK);
        CHECKF(h.hinted > 100 && h.probes_after > 50 && h.overflow == 0, "%s: %lu hinted MOVEs before %lu PROBEs",
               objs[i], h.hinted, h.probes_after);
        CHECKF(h.bad_dir == 0 && h.bad_range == 0 && h.bad_end == 0, "%s: %lu directions, %lu ranges (worst %g), %lu ends wrong",
               objs[i], h.bad_dir, h.bad_range, h.worst_range, h.bad_end);
        printf("%s with a 0.05 clearance: %lu MOVEs named the PROBE they lead to (%lu PROBEs), every direction,"
               " way left and end right\n", objs[i], h.hinted, h.probes_after);
        vp_sim_close(&s);
    }
}

/* A device with a body (clearance radius): it stays outside Omega and probes along the Voronoi
 * lines from dOmega. Zero collisions always; objects seen whole from outside close. */
static void test_clearance(void)
{
    vp_sim_options_t o;
    vp_sim_t s;
    vp_simdev_stats_t ds;
    char err[512];
    const char *objs[3] = { "sphere", "blobby", "torus" };
    int i;
    for (i = 0; i < 3; i++) {
        quiet_options(&o, objs[i], 0.02);
        o.clearance = 0.05;
        CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
        CHECK(vp_sim_run(&s, NULL) == VP_OK);
        CHECK(vp_sim_finish(&s, &o, err, sizeof err) == VP_OK);
        vp_simdev_stats(s.dev, &ds);
        CHECK(ds.collisions == 0);
        if (i < 2) CHECK(s.check.closed_manifold && s.check.genus == 0);
        printf("%s with a 0.05 clearance: %zu vertices, closed %d, %zu boundary edges, collisions %lu\n",
               objs[i], s.mesh.nv, s.check.closed_manifold, s.check.boundary_edges, ds.collisions);
        vp_sim_close(&s);
    }
}

/* A rangefinder of short reach: no PROBE asks for more than max_range, a probe that ends
 * in free space is continued from its end (the seed probes from dOmega too), no shortcut is
 * taken on a probe that could not reach; the mesh closes with zero collisions. */
typedef struct reach_watch {
    double max_range, longest;
    unsigned long probes;
} reach_watch_t;

static int watch_reach(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    reach_watch_t *w = ctx;
    (void)res;
    if (cmd->kind == VP_CMD_PROBE) {
        w->probes++;
        if (cmd->range > w->longest) w->longest = cmd->range;
    }
    return 0;
}

static void test_max_range(void)
{
    /* a dropout on a walked ray must be confirmed like any miss; with noise, a hull ray's
     * old hit cut off by an insertion frees the ray only up to the noise tolerance before it
     * (seed 7 once moved onto the surface there) */
    static const struct { const char *surface; double reach, dropout, noise; unsigned seed; int genus; } c[4] = {
        { "torus", 0.4, 0.1, 0.0, 1, 1 }, { "torus", 0.4, 0.3, 0.002, 7, 1 },
        { "genus2", 1.0, 0.0, 0.0, 1, 2 }, { "genus2", 0.3, 0.0, 0.0, 1, 2 } };
    int i;
    for (i = 0; i < (quick ? 3 : 4); i++) {
        vp_sim_options_t o;
        vp_sim_t s;
        vp_simdev_stats_t ds;
        vp_session_hooks_t h;
        reach_watch_t w;
        char err[512];
        quiet_options(&o, c[i].surface, 0.03);
        o.max_range = c[i].reach;
        o.dropout = c[i].dropout;
        o.noise = c[i].noise;
        o.seed = c[i].seed;
        memset(&w, 0, sizeof w);
        memset(&h, 0, sizeof h);
        h.ctx = &w;
        h.after = watch_reach;
        CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
        s.hooks = &h;
        CHECK(vp_sim_run(&s, NULL) == VP_OK);
        CHECK(vp_sim_finish(&s, &o, err, sizeof err) == VP_OK);
        vp_simdev_stats(s.dev, &ds);
        CHECK(ds.collisions == 0);
        CHECK(w.probes > 0);
        CHECKF(w.longest <= c[i].reach, "a probe of range %.17g > max range %g", w.longest, c[i].reach);
        CHECK(s.have_check && s.check.closed_manifold && s.check.genus == c[i].genus && s.check.components == 1);
        printf("%s with a %.1f maximum range, dropout %.2f, noise %g: %zu vertices, %lu probes, longest %.3f, "
               "closed %d, collisions %lu\n", c[i].surface, c[i].reach, c[i].dropout, c[i].noise, s.mesh.nv, w.probes, w.longest,
               s.check.closed_manifold, ds.collisions);
        vp_sim_close(&s);
    }
}

/* Noise and dropouts well below eps: still closed, right topology, no collision. */
static void test_noise(void)
{
    scan_result_t r;
    scan("sphere", 0.04, 0, 1e-4, 0.0, 2000, &r);
    check_scan(&r, 1, 0, 0);
    scan("torus", 0.04, 0, 2e-4, 0.02, 2000, &r);
    check_scan(&r, 1, 1, 0);
    /* 1% of eps of noise with dropouts: a hit within the noise of an edge's end that a full
     * miss from that end contradicts is dropped (it once left a non-manifold edge here) */
    scan("torus", 0.0133, 0, 5e-4, 0.1, 0, &r);
    check_scan(&r, 1, 1, 0);
    /* here the very first probe, from dOmega towards o, drops out: re-probed, not an error */
    scan("blobby", 0.03, 0, 1e-3, 0.2, 2000, &r);
    check_scan(&r, 1, 0, 0);
    if (!quick) {
        scan("genus2", 0.03, 0, 2e-4, 0.05, 2000, &r);
        check_scan(&r, 1, 2, 0);
    }
}

/* ---- error paths ---- */

static void base_config(vp_planner_config_t *c)
{
    int k;
    memset(c, 0, sizeof *c);
    c->omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) { c->omega_lo[k] = -2; c->omega_hi[k] = 2; c->start[k] = 3; }
    c->ninterior = 1;
    c->eps = 0.1;
}

/* base_config with every length times f */
static void scaled_config(vp_planner_config_t *c, double f)
{
    int k;
    base_config(c);
    for (k = 0; k < 3; k++) { c->omega_lo[k] *= f; c->omega_hi[k] *= f; c->start[k] *= f; }
    c->eps *= f;
}

static void test_errors(void)
{
    vp_planner_t *pl = malloc(sizeof *pl);
    size_t bytes = (size_t)8 << 20;
    void *mem = malloc(bytes);
    vp_planner_config_t c;
    vp_cmd_t cmd;
    vp_probe_result_t res;
    base_config(&c);
    CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_OK);
    CHECK(vp_planner_init(NULL, mem, bytes, &c) == VP_EINVAL);
    CHECK(vp_planner_init(pl, NULL, bytes, &c) == VP_EINVAL);
    CHECK(vp_planner_init(pl, mem, bytes, NULL) == VP_EINVAL);
    base_config(&c); c.eps = 0;             CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.eps = -1;            CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.eps = NAN;           CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.eps = INFINITY;      CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.omega_hi[1] = -3;    CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.omega_lo[2] = NAN;   CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.omega_kind = 7;      CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.omega_kind = VP_OMEGA_BALL; c.omega_radius = 0;
    CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.interior[0][0] = 5;  CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.interior[0][2] = NAN; CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.ninterior = 0;       CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.ninterior = VP_PLANNER_MAX_SEEDS + 1; CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.start[0] = 0; c.start[1] = 0; c.start[2] = 0; /* start inside Omega */
    CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    base_config(&c); c.noise_tol = -1;      CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    /* Omega's size (its circumradius 3.46 f here): below 1e-4 or above 1e50 units refused (at
     * 1e-13 a scan ended DONE with no facet, the proofs' slack larger than Omega) */
    scaled_config(&c, 1e-5);                 CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    scaled_config(&c, 1e-13);                CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    scaled_config(&c, 1e50);                 CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_EINVAL);
    scaled_config(&c, 1e-4);                 CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_OK);
    scaled_config(&c, 1e49);                 CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_OK);
    base_config(&c);                         CHECK(vp_planner_init(pl, mem, 1000, &c) == VP_ENOMEM);
    /* a failed init on a planner at work: under the least arena it is left as it was (the
     * session goes on); over it but too small for the pools it is left holding the error
     * (the build before left it half made: the next call crashed) */
    base_config(&c);
    CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_OK);
    CHECK(vp_planner_next(pl, &cmd) == VP_OK);
    CHECK(vp_planner_init(pl, mem, 1000, &c) == VP_ENOMEM);
    {
        vp_cmd_t again;
        int st = vp_planner_next(pl, &again);
        CHECKF(st == VP_OK, "the session after a refused init: %d", st);
    }
    {
        size_t small = 0, b;
        for (b = 64u << 10; b <= (1u << 20) && !small; b += 4096)
            if (vp_planner_init(pl, mem, b, &c) == VP_ENOMEM) small = b;
            else break;
        CHECKF(small > 0, "an arena over the least size that the pools do not fit");
        if (small) {
            vp_probe_result_t r0 = { 0, 0.0 };
            CHECK(vp_planner_next(pl, &cmd) == VP_ENOMEM);
            CHECK(vp_planner_feed(pl, &r0) == VP_ESTATE || vp_planner_feed(pl, &r0) == VP_ENOMEM);
            CHECK(vp_planner_facet_slots(pl) == 0);
            CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_OK); /* and it starts again */
            CHECK(vp_planner_next(pl, &cmd) == VP_OK);
        }
    }
    /* protocol: feed before a probe, next before feeding, bad results */
    base_config(&c);
    CHECK(vp_planner_init(pl, mem, bytes, &c) == VP_OK);
    res.hit = 1; res.dist = 1.0;
    CHECK(vp_planner_feed(pl, &res) == VP_ESTATE);
    do CHECK(vp_planner_next(pl, &cmd) == VP_OK); while (cmd.kind == VP_CMD_MOVE);
    CHECK(cmd.kind == VP_CMD_PROBE);
    CHECK(vp_planner_next(pl, &cmd) == VP_ESTATE);
    res.hit = 1; res.dist = NAN;
    CHECK(vp_planner_feed(pl, &res) == VP_EINVAL);
    res.dist = -1.0;
    CHECK(vp_planner_feed(pl, &res) == VP_EINVAL);
    /* a miss's and a too-close result's distance too: the session log holds it (the build
     * before took a NaN there and wrote a record its reader refuses) */
    res.hit = 0; res.dist = NAN;
    CHECK(vp_planner_feed(pl, &res) == VP_EINVAL);
    res.dist = INFINITY;
    CHECK(vp_planner_feed(pl, &res) == VP_EINVAL);
    res.hit = VP_PROBE_TOO_CLOSE; res.dist = -INFINITY;
    CHECK(vp_planner_feed(pl, &res) == VP_EINVAL);
    CHECK(vp_planner_next(pl, &cmd) == VP_ESTATE); /* still owed: nothing changed */
    /* misses towards o from every side (the seed comes again from 26 other directions, a dark
     * surface on its way in being possible): o is not inside the object, VP_ERANGE */
    res.hit = 0; res.dist = 0;
    {
        int n, st = VP_OK;
        for (n = 0; n < 64; n++) {
            st = vp_planner_feed(pl, &res);
            if (st != VP_OK) break;
            do st = vp_planner_next(pl, &cmd); while (st == VP_OK && cmd.kind == VP_CMD_MOVE);
            if (st != VP_OK || cmd.kind != VP_CMD_PROBE) break;
        }
        CHECKF(st == VP_ERANGE && n == 26, "status %d after %d more seed probes", st, n);
    }
    CHECK(vp_planner_next(pl, &cmd) == VP_ERANGE);
    free(mem);
    free(pl);
}

/* Arena exhaustion: VP_ENOMEM, never a crash; the mesh so far stays exportable and the
 * triangulation valid. */
static void test_enomem(void)
{
    vp_sim_options_t o;
    vp_sim_t s;
    char err[512];
    size_t arena;
    int saw = 0;
    for (arena = 80u << 10; arena <= (2u << 20); arena *= 2) {
        quiet_options(&o, "torus", 0.01);
        o.arena = arena;
        if (vp_sim_open(&s, &o, err, sizeof err) != VP_OK) {
            CHECKF(strstr(err, "arena") != NULL, "%s", err);
            vp_sim_close(&s);
            continue;
        }
        if (vp_sim_run(&s, NULL) == VP_ENOMEM) {
            vp_cmd_t cmd;
            saw++;
            CHECK(vp_planner_next(s.pl, &cmd) == VP_ENOMEM); /* stays stopped */
            CHECK(vp_dt_check(vp_planner_dt(s.pl)) == VP_OK);
            CHECK(vp_sim_finish(&s, &o, err, sizeof err) == VP_OK);
            CHECK(s.mesh.nt > 0);
        }
        vp_sim_close(&s);
    }
    CHECK(saw > 0);
}

/* 2.5 KB of arena per output vertex is enough (the split of the arena follows the measured
 * peaks of each pool; the proofs of free space take about 360 B of it). */
static void test_arena_per_vertex(const char *surface, double eps_rel)
{
    vp_sim_options_t o;
    vp_sim_t s;
    char err[512];
    unsigned nv;
    quiet_options(&o, surface, eps_rel);
    CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
    CHECK(vp_sim_run(&s, NULL) == VP_OK);
    nv = vp_planner_dt(s.pl)->ninserted;
    vp_sim_close(&s);
    o.arena = (size_t)2560 * nv;
    CHECK(vp_sim_open(&s, &o, err, sizeof err) == VP_OK);
    CHECKF(vp_sim_run(&s, NULL) == VP_OK, "%s: %u vertices in %zu bytes", surface, nv, o.arena);
    CHECK(vp_planner_dt(s.pl)->ninserted == nv);
    printf("%s: %u vertices scanned in a %zu-byte arena (2.5 KB per vertex)\n", surface, nv, o.arena);
    vp_sim_close(&s);
}

int main(void)
{
    const char *q = getenv("VP_TEST_QUICK");
    quick = q && *q == '1';
    test_errors();
    test_enomem();
    test_surfaces();
    test_paper_mode();
    test_noise();
    test_arena_per_vertex("genus2", 0.012);
    if (!quick) {
        test_arena_per_vertex("torus", 0.012);
        test_arena_per_vertex("genus5", 0.02);
    }
    test_angle_bound();
    test_min_range();
    test_max_range();
    test_clearance();
    test_move_hints();
    return vp_test_done("test_planner");
}
