/* The scan loop's paths (vp_run with a device's move_path): consecutive MOVEs handed to the
 * device at once. Against the loop with each MOVE made alone, on a device written here from the
 * sphere's formula: the same commands in the same order reach the log (the after hook), every
 * path is a chain of MOVEs starting where the head stands, max_commands is kept exactly, a
 * device that makes part of a path is given the rest again, and when the hook stops the scan
 * or the device fails in a path, every MOVE the head made is logged and none it did not make.
 * A contact switch that stops a path's MOVE: the path ends there, that MOVE is logged with its
 * touch, and the planner, which has gone past it, stops the scan as a MOVE alone would (the
 * contact outside Omega: VP_ERANGE) or refuses the path (inside Omega: VP_ESTATE). */
#include <math.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_run.h"
#include "vp_test.h"

#define ARENA (16u << 20)

typedef struct path_dev {
    double pos[3];
    unsigned long executed;        /* MOVEs and PROBEs the head made */
    unsigned long logged;          /* commands the after hook saw */
    unsigned long paths, path_moves, longest;
    unsigned long breaks;          /* a path's MOVE not starting where the head stands */
    unsigned long collided;        /* MOVEs the device reported collided (every 7th) */
    unsigned long non_moves;       /* a path holding something else than a MOVE */
    int per_call;                  /* at most this many MOVEs made per move_path call (0: all) */
    unsigned long fail_at;         /* the device fails at the first MOVE from this command on
                                      (1-based; 0: never) */
    unsigned long stop_at;         /* the hook stops the scan after this command (0: never) */
    unsigned long touch_at;        /* the contact stops the first MOVE from this command on,
                                      half way (1-based; 0: never) */
    unsigned long nan_at;          /* from this PROBE on (1-based; 0: never) the device answers a
                                      miss at a NaN distance */
    unsigned long probes;
    int touched;                   /* the last MOVE stopped on the contact */
    double touch_dist, touch_point[3];
    unsigned long touch_logged;    /* MOVEs the hook saw with a touch, and their distance */
    double logged_dist;
    int touch_in_path;             /* the touched MOVE was one of a path, and not its last */
    uint64_t hash;                 /* of the logged commands and results, in order */
} path_dev_t;

static void mix(uint64_t *h, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++) { *h ^= b[i]; *h *= 1099511628211ull; }
}

static int move_one(path_dev_t *d, const vp_cmd_t *cmd, int *collided)
{
    int k;
    if (d->fail_at && d->executed + 1 >= d->fail_at) return VP_EIO;
    d->touched = 0;
    if (d->touch_at && d->executed + 1 >= d->touch_at && !d->touch_dist) {
        /* half way along: the head backs off to there */
        d->touched = 1;
        d->touch_dist = 0.5 * sqrt((cmd->to[0] - cmd->from[0]) * (cmd->to[0] - cmd->from[0]) +
                                   (cmd->to[1] - cmd->from[1]) * (cmd->to[1] - cmd->from[1]) +
                                   (cmd->to[2] - cmd->from[2]) * (cmd->to[2] - cmd->from[2]));
        for (k = 0; k < 3; k++) d->touch_point[k] = d->pos[k] = 0.5 * (cmd->from[k] + cmd->to[k]);
        d->executed++;
        *collided = 0;
        return VP_OK;
    }
    memcpy(d->pos, cmd->to, sizeof d->pos);
    d->executed++;
    *collided = d->executed % 7 == 0;
    d->collided += (unsigned long)*collided;
    return VP_OK;
}

static int dev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    return move_one(ctx, cmd, collided);
}

static int dev_move_path(void *ctx, const vp_cmd_t *cmds, int n, int *collided, int *done)
{
    path_dev_t *d = ctx;
    int i, st = VP_OK;
    if (n > 1) { d->paths++; d->path_moves += (unsigned long)n; }
    if ((unsigned long)n > d->longest) d->longest = (unsigned long)n;
    *done = 0;
    for (i = 0; i < n; i++) {
        if (cmds[i].kind != VP_CMD_MOVE) d->non_moves++;
        if (memcmp(cmds[i].from, i == 0 ? d->pos : cmds[i - 1].to, sizeof d->pos) != 0) d->breaks++;
    }
    for (i = 0; i < n && (!d->per_call || i < d->per_call); i++) {
        st = move_one(d, &cmds[i], &collided[i]);
        if (st != VP_OK) break;
        (*done)++;
        if (d->touched) { d->touch_in_path = i + 1 < n; break; }   /* the path ends at a touch */
    }
    return st;
}

static int dev_touched(void *ctx, double *at)
{
    path_dev_t *d = ctx;
    if (d->touched) *at = d->touch_dist;
    return d->touched;
}

/* the unit sphere: first hit along the ray */
static int dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    path_dev_t *d = ctx;
    const double *p = d->pos, *u = cmd->dir;
    double b = p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
    double c = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1.0, disc = b * b - c, s;
    d->executed++;
    res->hit = 0;
    res->dist = 0.0;
    if (d->nan_at && ++d->probes >= d->nan_at) {
        res->dist = NAN;
        return VP_OK;
    }
    if (disc > 0.0 && (s = -b - sqrt(disc)) > 0.0 && s <= cmd->range) {
        res->hit = 1;
        res->dist = s;
    }
    return VP_OK;
}

static int after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    path_dev_t *d = ctx;
    d->logged++;
    if (cmd->kind == VP_CMD_MOVE && res) { d->touch_logged++; d->logged_dist = res->dist; }
    mix(&d->hash, &cmd->kind, sizeof cmd->kind);
    mix(&d->hash, cmd->from, sizeof cmd->from);
    mix(&d->hash, cmd->to, sizeof cmd->to);
    if (res) { mix(&d->hash, &res->hit, sizeof res->hit); mix(&d->hash, &res->dist, sizeof res->dist); }
    if (d->stop_at && d->logged >= d->stop_at && cmd->kind != VP_CMD_DONE) return VP_EABORT;
    return VP_OK;
}

/* The unit sphere's scan: Omega [-1.5, 1.5]^3, eps 0.3, from (0, 0, 2). */
static void sphere_config(vp_planner_config_t *cfg)
{
    int k;
    memset(cfg, 0, sizeof *cfg);
    cfg->omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) { cfg->omega_lo[k] = -1.5; cfg->omega_hi[k] = 1.5; }
    cfg->ninterior = 1;
    cfg->eps = 0.3;
    cfg->start[2] = 2.0;
}

/* One scan of the unit sphere in Omega [-1.5, 1.5]^3; paths: the device takes them. */
static int scan(path_dev_t *d, int paths, unsigned long max_commands, vp_run_result_t *run, vp_planner_stats_t *st)
{
    static unsigned char arena[ARENA];
    static vp_planner_t pl;
    vp_planner_config_t cfg;
    vp_device_ops_t ops;
    vp_run_hooks_t hooks;
    int per = d->per_call;
    unsigned long fail = d->fail_at, stop = d->stop_at, touch = d->touch_at, nan_at = d->nan_at;
    sphere_config(&cfg);
    memset(d, 0, sizeof *d);
    d->per_call = per;
    d->fail_at = fail;
    d->stop_at = stop;
    d->touch_at = touch;
    d->nan_at = nan_at;
    d->hash = 1469598103934665603ull;
    memcpy(d->pos, cfg.start, sizeof d->pos);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    memset(&ops, 0, sizeof ops);
    ops.ctx = d;
    ops.move = dev_move;
    ops.probe = dev_probe;
    ops.move_path = paths ? dev_move_path : NULL;
    ops.touched = touch ? dev_touched : NULL;
    memset(&hooks, 0, sizeof hooks);
    hooks.ctx = d;
    hooks.after = after;
    vp_run(&pl, &ops, &hooks, max_commands, run);
    if (st) vp_planner_get_stats(&pl, st);
    return run->status;
}

/* vp_planner_touch_path itself: after the planner's first MOVE, a touch on that MOVE is its
 * ordinary touch (as vp_planner_touch); on a MOVE it has gone past, VP_ERANGE outside Omega and
 * VP_ESTATE inside (and the planner keeps that error). */
static int first_move(vp_planner_t *pl, path_dev_t *d, vp_cmd_t *cmd)
{
    static unsigned char arena[ARENA];
    vp_planner_config_t cfg;
    int i;
    sphere_config(&cfg);
    memset(d, 0, sizeof *d);
    memcpy(d->pos, cfg.start, sizeof d->pos);
    if (vp_planner_init(pl, arena, sizeof arena, &cfg) != VP_OK) return 0;
    for (i = 0; i < 10000; i++) {
        vp_probe_result_t res;
        if (vp_planner_next(pl, cmd) != VP_OK) return 0;
        if (cmd->kind == VP_CMD_MOVE) return 1;
        if (cmd->kind != VP_CMD_PROBE) return 0;
        dev_probe(d, cmd, &res);
        if (vp_planner_feed(pl, &res) != VP_OK) return 0;
    }
    return 0;
}

static void touch_path_api(void)
{
    static vp_planner_t pl, ref;
    path_dev_t d;
    vp_cmd_t mv, other;
    double half;
    CHECK(first_move(&pl, &d, &mv));
    memset(&other, 0, sizeof other);
    other.kind = VP_CMD_MOVE;
    other.from[0] = 0.5; other.to[0] = 0.7;            /* inside Omega */
    CHECK(vp_planner_touch_path(&pl, &other, 0.1) == VP_ESTATE);
    CHECK(vp_planner_touch_path(&pl, &mv, 0.0) == VP_ESTATE);   /* the error is kept */
    CHECK(first_move(&pl, &d, &mv));
    other.from[0] = other.to[0] = 0.0;
    other.from[2] = 2.4; other.to[2] = 2.2;             /* outside Omega */
    CHECK(vp_planner_touch_path(&pl, &other, 0.1) == VP_ERANGE);
    CHECK(vp_planner_touch_path(&pl, &other, 0.5) == VP_ERANGE);   /* kept, before `at` is looked at */
    CHECK(first_move(&pl, &d, &mv));
    CHECK(vp_planner_touch_path(&pl, &other, 0.5) == VP_EINVAL);   /* beyond that MOVE */
    /* the last MOVE given: vp_planner_touch's answer */
    half = 0.5 * sqrt((mv.to[0] - mv.from[0]) * (mv.to[0] - mv.from[0]) + (mv.to[1] - mv.from[1]) * (mv.to[1] - mv.from[1]) +
                      (mv.to[2] - mv.from[2]) * (mv.to[2] - mv.from[2]));
    CHECK(first_move(&ref, &d, &mv));
    {
        int a = vp_planner_touch_path(&pl, &mv, half), b = vp_planner_touch(&ref, half);
        vp_cmd_t na, nb;
        CHECKF(a == b, "the last MOVE: touch_path %d, touch %d", a, b);
        if (a == VP_OK) {
            CHECK(vp_planner_next(&pl, &na) == VP_OK && vp_planner_next(&ref, &nb) == VP_OK);
            CHECK(na.kind == nb.kind && memcmp(na.from, nb.from, sizeof na.from) == 0 && memcmp(na.to, nb.to, sizeof na.to) == 0);
        }
        printf("  vp_planner_touch_path: gone past inside Omega %d, outside %d, the last MOVE %d (vp_planner_touch %d)\n",
               VP_ESTATE, VP_ERANGE, a, b);
    }
}

int main(void)
{
    path_dev_t a, b;
    vp_run_result_t ra, rb;
    vp_planner_stats_t sa, sb;
    unsigned long k, cuts[] = { 1, 2, 3, 7, 40, 41, 42, 97, 500 };
    size_t i;

    /* the whole scan: the same log, made in paths */
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    CHECK(scan(&a, 0, 0, &ra, &sa) == VP_OK && ra.done);
    CHECK(scan(&b, 1, 0, &rb, &sb) == VP_OK && rb.done);
    CHECK(a.hash == b.hash);
    CHECK(a.logged == b.logged && ra.commands == rb.commands);
    CHECK(b.executed == a.executed && b.executed + 1 == b.logged);   /* + DONE */
    CHECK(sa.probes == sb.probes && sa.insertions == sb.insertions);
    CHECK(b.paths > 50 && b.longest >= 3 && b.longest <= VP_DEV_PATH);
    CHECK(b.breaks == 0 && b.non_moves == 0);
    CHECK(a.collided > 0 && rb.collisions == b.collided && ra.collisions == a.collided && a.collided == b.collided);
    printf("  %lu commands, %lu paths of %lu MOVEs (the longest %lu), same log\n", b.logged, b.paths, b.path_moves, b.longest);

    /* a device that answers a miss at a NaN distance: refused before it is logged (the log's
     * reader would refuse the record, and everything after it), the scan stops there */
    memset(&b, 0, sizeof b);
    b.nan_at = 5;
    CHECK(scan(&b, 1, 0, &rb, NULL) == VP_EINVAL);
    CHECK(b.probes == 5 && b.logged + 1 == b.executed);

    /* a device that makes at most two MOVEs a call: given the rest again */
    memset(&b, 0, sizeof b);
    b.per_call = 2;
    CHECK(scan(&b, 1, 0, &rb, NULL) == VP_OK && rb.done);
    CHECK(b.hash == a.hash && b.logged == a.logged && b.breaks == 0);

    /* max_commands kept exactly: no command asked of the planner past it */
    for (i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        memset(&b, 0, sizeof b);
        CHECK(scan(&b, 1, cuts[i], &rb, NULL) == VP_OK);
        CHECK(rb.commands == cuts[i] && b.executed == cuts[i] && b.logged == cuts[i]);
    }

    /* the hook stops the scan: every MOVE made is logged, none is made unlogged; the loop
     * stops at the end of the path the stop fell in */
    for (k = 1; k < 300; k += 13) {
        memset(&b, 0, sizeof b);
        b.stop_at = k;
        CHECK(scan(&b, 1, 0, &rb, NULL) == VP_EABORT);
        CHECK(b.logged == b.executed && b.logged >= k && b.logged < k + VP_DEV_PATH);
        CHECK(rb.commands == k - 1);
    }

    /* the device fails in a path: the MOVEs before it logged, the error returned */
    for (k = 5; k < 300; k += 17) {
        memset(&b, 0, sizeof b);
        b.fail_at = k;
        CHECK(scan(&b, 1, 0, &rb, NULL) == VP_EIO);
        CHECK(b.executed >= k - 1 && b.logged == b.executed);
    }
    /* the contact switch stops a MOVE: in a path, the path ends there; the MOVE is logged with
     * its touch and nothing after it is made; outside Omega the scan stops as with that MOVE
     * made alone (VP_ERANGE), inside it the planner refuses a path it has gone past */
    {
        unsigned long in_path = 0, outside = 0, inside = 0;
        for (k = 2; k < 1000; k += 7) {
            int sa_st, sb_st, out;
            memset(&a, 0, sizeof a);
            memset(&b, 0, sizeof b);
            a.touch_at = b.touch_at = k;
            sa_st = scan(&a, 0, 0, &ra, NULL);
            sb_st = scan(&b, 1, 0, &rb, NULL);
            if (!b.touched) continue;                      /* k fell on the last PROBEs */
            out = fabs(b.touch_point[0]) > 1.5 || fabs(b.touch_point[1]) > 1.5 || fabs(b.touch_point[2]) > 1.5;
            CHECK(b.touch_logged == 1 && b.logged_dist == b.touch_dist && rb.contacts == 1);
            CHECK(b.logged == b.executed);                 /* the touched MOVE is the last made */
            if (!b.touch_in_path) {
                /* the path's last MOVE (the run of MOVEs cut at VP_DEV_PATH): as alone */
                CHECKF(sa_st == sb_st, "touch at %lu on a path's last MOVE: alone %d, path %d", k, sa_st, sb_st);
                continue;
            }
            in_path++;
            CHECK(a.touched && a.touch_logged == 1 && a.executed >= b.executed);
            if (out) {
                outside++;
                CHECKF(sa_st == VP_ERANGE && sb_st == VP_ERANGE, "touch at %lu outside Omega: alone %d, path %d", k, sa_st, sb_st);
                CHECK(a.hash == b.hash && a.logged == b.logged);   /* the same log either way */
            } else {
                inside++;
                CHECKF(sb_st == VP_ESTATE, "touch at %lu inside Omega in a path: %d", k, sb_st);
            }
        }
        CHECK(in_path > 5 && outside > 0);
        printf("  touches in a path: %lu (%lu outside Omega, %lu inside)\n", in_path, outside, inside);
    }
    touch_path_api();
    return vp_test_done("test_run_path");
}
