/* A miss must be seen (vp_planner_spot_hidden, and vp_run feeding such a miss as unreadable).
 *
 * The ellipsoid (1, 0.7, 0.5) is scanned by a device written here from its formula; then:
 * - the call's contract: NaN or a negative range, VP_EINVAL; nothing in the mesh yet, 0;
 * - the run loop: a device that reports its camera (vp_device_ops_t.sight) 1.5 below the laser,
 *   so that the ellipsoid stands between some spots and it: every result the log hook sees as
 *   unreadable is a miss the device read and the call calls hidden,
 *   the count is vp_run_result_t.unseen_misses, and the scan still ends with no move into the
 *   ellipsoid;
 * - every facet of the mesh is an occluder (vp_planner_sight_occluder);
 * - with --cases FILE: part way through the scan (much of space still unknown), the occluders and
 *   a set of sight triangles (random ones, ones like a scanner's, ones through an occluder's
 *   vertex or along its edge, the occluder itself) with the call's answer, for tests/t_sight.sh to
 *   check against CGAL's exact do_intersect. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_run.h"
#include "vp_test.h"
#include "vp_test_ellipsoid.h"

#define ARENA (32u << 20)
static const double AX[3] = { 1.0, 0.7, 0.5 }; /* the ellipsoid's semi-axes */

typedef struct ell_dev {
    vp_test_ell_dev_t b;     /* the ellipsoid, the device's place, its counts */
    double cam_off[3];       /* the camera from the laser origin (sight): far below it */
    int last_miss;           /* the last probe was read as a miss */
    unsigned long misses, unseen, unseen_checked;
} ell_dev_t;

static unsigned char arena[ARENA];
static vp_planner_t pl;

static int dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    ell_dev_t *d = ctx;
    int st = vp_test_ell_dev_probe(&d->b, cmd, res);
    d->last_miss = !res->hit;
    d->misses += (unsigned long)d->last_miss;
    return st;
}

static int dev_sight(void *ctx, const vp_cmd_t *cmd, double cam[3])
{
    ell_dev_t *d = ctx;
    int k;
    for (k = 0; k < 3; k++) cam[k] = cmd->from[k] + d->cam_off[k];
    return 1;
}

/* the log hook: an unreadable result must be a miss the call calls hidden, judged before the
 * planner is fed (the mesh as the call saw it) */
static int after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    ell_dev_t *d = ctx;
    double cam[3];
    if (cmd->kind != VP_CMD_PROBE || !res || res->hit != VP_PROBE_TOO_CLOSE) return VP_OK;
    d->unseen++;
    dev_sight(d, cmd, cam);
    if (d->last_miss && vp_planner_spot_hidden(&pl, cmd->from, cmd->dir, cmd->range, cam) == 1) d->unseen_checked++;
    return VP_OK;
}

static void scan(ell_dev_t *d, double eps, int sight, unsigned long max_commands, vp_run_result_t *r)
{
    vp_planner_config_t cfg;
    vp_device_ops_t ops;
    vp_run_hooks_t hooks;
    vp_test_ell_config(&cfg, AX, eps);
    memset(d, 0, sizeof *d);
    memcpy(d->b.e.ax, AX, sizeof d->b.e.ax);
    d->cam_off[0] = 0.2; d->cam_off[1] = -0.3; d->cam_off[2] = -1.5;
    memcpy(d->b.pos, cfg.start, sizeof d->b.pos);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    memset(&ops, 0, sizeof ops);
    ops.ctx = d;
    ops.move = vp_test_ell_dev_move;
    ops.probe = dev_probe;
    ops.sight = sight ? dev_sight : NULL;
    memset(&hooks, 0, sizeof hooks);
    hooks.ctx = d;
    hooks.after = after;
    vp_run(&pl, &ops, &hooks, max_commands, r);
}

static double urand(unsigned long *s)
{
    *s = *s * 6364136223846793005ul + 1442695040888963407ul;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static void put_tri(FILE *f, const double *a, const double *b, const double *c)
{
    fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g", a[0], a[1], a[2], b[0], b[1], b[2], c[0],
            c[1], c[2]);
}

/* a query: the sight triangle (cam, o, o + range d) as the call takes it */
static void query(FILE *f, const double *cam, const double *o, const double *end, unsigned *n)
{
    double d[3], range;
    int k, h;
    for (k = 0; k < 3; k++) d[k] = end[k] - o[k];
    range = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(range > 0.0)) return;
    for (k = 0; k < 3; k++) d[k] /= range;
    h = vp_planner_spot_hidden(&pl, o, d, range, cam);
    CHECK(h == 0 || h == 1);
    {
        double e[3];
        for (k = 0; k < 3; k++) e[k] = o[k] + range * d[k]; /* the end the call computes */
        put_tri(f, cam, o, e);
    }
    fprintf(f, " %d\n", h);
    (*n)++;
}

static void write_cases(const char *path)
{
    uint32_t i, nf = 0;
    unsigned long s = 12345;
    unsigned n = 0;
    double tri[3][3];
    int got;
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f) return;
    for (i = 0; (got = vp_planner_sight_occluder(&pl, i, tri)) >= 0; i++) nf += got == 1;
    fprintf(f, "facets %u\n", nf);
    for (i = 0; (got = vp_planner_sight_occluder(&pl, i, tri)) >= 0; i++) {
        if (got != 1) continue;
        put_tri(f, tri[0], tri[1], tri[2]);
        fprintf(f, "\n");
    }
    fprintf(f, "queries\n");
    for (i = 0; i < 400; i++) { /* anywhere in and round Omega */
        double p[3][3];
        int k, j;
        for (j = 0; j < 3; j++)
            for (k = 0; k < 3; k++) p[j][k] = 3.2 * urand(&s) - 1.6;
        query(f, p[0], p[1], p[2], &n);
    }
    for (i = 0; i < 400; i++) { /* a scanner's: from outside, towards the object, the camera beside */
        double o[3], t[3], e[3], cam[3], len;
        int k;
        for (k = 0; k < 3; k++) { o[k] = 2.0 * urand(&s) - 1.0; t[k] = 1.2 * urand(&s) - 0.6; }
        len = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        for (k = 0; k < 3; k++) {
            o[k] *= 1.6 / len;
            e[k] = o[k] + (1.0 + urand(&s)) * (t[k] - o[k]);
            cam[k] = o[k] + 0.3 * urand(&s) - 0.15;
        }
        query(f, cam, o, e, &n);
    }
    for (i = 0, s = 777; (got = vp_planner_sight_occluder(&pl, i, tri)) >= 0 && n < 1400; i++) {
        /* through an occluder's vertex, along its edge, itself */
        double far[3];
        const double *a = tri[0], *b = tri[1], *c = tri[2];
        int k;
        if (got != 1 || urand(&s) > 0.3) continue;
        for (k = 0; k < 3; k++) far[k] = 3.2 * urand(&s) - 1.6;
        query(f, far, a, far[0] > 0 ? b : c, &n); /* the beam from a vertex to another: along an edge */
        query(f, a, b, c, &n);                    /* the occluder itself (in its plane) */
        for (k = 0; k < 3; k++) far[k] = a[k] + 2.0 * (a[k] - c[k]) + 0.5 * urand(&s);
        query(f, c, far, a, &n);                   /* the cam at a vertex */
    }
    fclose(f);
    printf("wrote %u occluders and %u sight triangles to %s\n", nf, n, path);
}

int main(int argc, char **argv)
{
    static ell_dev_t d;
    vp_run_result_t r;
    const double o[3] = { 0.0, 0.0, 1.0 }, dir[3] = { 0.0, 0.0, -1.0 }, cam[3] = { 0.1, 0.0, 1.0 };
    double nan = strtod("nan", NULL);
    vp_planner_config_t cfg;

    /* nothing found yet: nothing hides a spot */
    vp_test_ell_config(&cfg, AX, 0.2);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    CHECK(vp_planner_spot_hidden(&pl, o, dir, 2.0, cam) == 0);

    if (argc == 3 && !strcmp(argv[1], "--cases")) {
        /* part way: much of space is still unknown (its boundary occludes), part of the mesh found */
        scan(&d, 0.2, 0, 400, &r);
        CHECK(r.status == VP_OK && !r.done && d.b.into == 0);
        write_cases(argv[2]);
        return vp_test_done("test_sight --cases");
    }
    scan(&d, 0.2, 0, 2000000, &r);
    CHECK(r.status == VP_OK && r.done && d.b.into == 0 && r.unseen_misses == 0 && d.unseen == 0);
    /* every facet of the mesh is an occluder */
    {
        uint32_t i, v[3], nf = 0, nocc = 0;
        double tri[3][3];
        for (i = 0; i < vp_planner_facet_slots(&pl); i++) {
            nf += vp_planner_facet(&pl, i, v, NULL, NULL) != 0;
            nocc += vp_planner_facet(&pl, i, v, NULL, NULL) != 0 && vp_planner_sight_occluder(&pl, i, tri) == 1;
        }
        CHECKF(nf > 0 && nocc == nf, "%u of %u facets of the mesh are occluders", nocc, nf);
        CHECK(vp_planner_sight_occluder(&pl, 0xFFFFFFF0u, tri) == -1);
    }
    /* the contract: bad input is refused and changes nothing */
    {
        const double bad[3] = { 0.0, nan, 0.0 };
        CHECK(vp_planner_spot_hidden(&pl, bad, dir, 2.0, cam) == VP_EINVAL);
        CHECK(vp_planner_spot_hidden(&pl, o, bad, 2.0, cam) == VP_EINVAL);
        CHECK(vp_planner_spot_hidden(&pl, o, dir, 2.0, bad) == VP_EINVAL);
        CHECK(vp_planner_spot_hidden(&pl, o, dir, nan, cam) == VP_EINVAL);
        CHECK(vp_planner_spot_hidden(&pl, o, dir, -1.0, cam) == VP_EINVAL);
    }
    /* straight down through the ellipsoid's top from above it, the camera beside: hidden past it;
     * a beam that stops short of it: nothing between */
    CHECK(vp_planner_spot_hidden(&pl, o, dir, 2.0, cam) == 1);
    CHECK(vp_planner_spot_hidden(&pl, o, dir, 0.3, cam) == 0);

    /* the run loop with the camera far below the laser */
    scan(&d, 0.2, 1, 2000000, &r);
    CHECKF(r.status == VP_OK && d.b.into == 0, "status %d, %lu moves into the ellipsoid", r.status, d.b.into);
    CHECKF(d.unseen == r.unseen_misses && d.unseen_checked == d.unseen && d.unseen > 0,
           "%lu results fed as unreadable, %lu counted, %lu of them misses the call calls hidden", d.unseen,
           r.unseen_misses, d.unseen_checked);
    printf("ellipsoid eps 0.2, the camera 1.5 below the laser: %lu misses, %lu fed as unreadable\n", d.misses, d.unseen);
    return vp_test_done("test_sight");
}
