/* The contact safety net in the planner (vp_planner_touch), against a device written here from
 * the sphere's formula alone (no host-sim): the unit sphere at the origin with a dark cap
 * (x > ZCAP: no spot, the rangefinder reads a miss) and a head whose contact switch stops a
 * move where its segment first meets the sphere. Every executed move (up to its contact) is
 * checked against the formula: no point before the touch inside the sphere. Without the switch
 * the same planner drives the head through the cap (the case the check must catch). Then the
 * call's contract: bad arguments and states change nothing. */
#include <math.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_run.h"
#include "vp_test.h"

#define ZCAP 0.55
static int cap_axis = 0; /* the dark cap: coordinate cap_axis above ZCAP */
#define ARENA (16u << 20)

typedef struct sphere_dev {
    double pos[3];
    int contact;             /* the head has a contact switch */
    int touched;             /* the last move stopped */
    double at;
    unsigned long moves, contacts, into, probes, dark;
    double deepest;          /* deepest point reached below the surface (no switch) */
} sphere_dev_t;

/* first t in (0, len] where p + t u meets the unit sphere from outside; 0 if none */
static int sphere_first(const double *p, const double *u, double len, double *t)
{
    double b = p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
    double c = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1.0, disc = b * b - c, s;
    if (disc <= 0.0) return 0;
    s = -b - sqrt(disc);
    if (s <= 1e-12 || s > len) {
        if (c < 0.0) { *t = 0.0; return 1; } /* starts inside */
        return 0;
    }
    *t = s;
    return 1;
}

/* smallest |x| along [p, p + len u] */
static double seg_min_norm(const double *p, const double *u, double len)
{
    double s = -(p[0] * u[0] + p[1] * u[1] + p[2] * u[2]), x[3];
    int k;
    if (s < 0.0) s = 0.0;
    if (s > len) s = len;
    for (k = 0; k < 3; k++) x[k] = p[k] + s * u[k];
    return sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
}

static int dev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    sphere_dev_t *d = ctx;
    double u[3], len, t, skip;
    int k;
    for (k = 0; k < 3; k++) u[k] = cmd->to[k] - d->pos[k];
    len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    d->touched = 0;
    d->moves++;
    *collided = 0;
    if (!(len > 0.0)) return VP_OK;
    for (k = 0; k < 3; k++) u[k] /= len;
    /* the head may stand on the sphere after a contact: check from just off it */
    skip = 1e-9;
    if (d->contact && len > skip && sphere_first((double[3]){ d->pos[0] + skip * u[0], d->pos[1] + skip * u[1], d->pos[2] + skip * u[2] }, u, len - skip, &t)) {
        d->touched = 1;
        d->at = skip + t;
        d->contacts++;
        for (k = 0; k < 3; k++) d->pos[k] += d->at * u[k];
        return VP_OK;
    }
    if (seg_min_norm((double[3]){ d->pos[0] + skip * u[0], d->pos[1] + skip * u[1], d->pos[2] + skip * u[2] }, u, len - skip) < 1.0 - 1e-9) {
        double m = seg_min_norm(d->pos, u, len);
        d->into++;
        *collided = 1;
        if (1.0 - m > d->deepest) d->deepest = 1.0 - m;
    }
    memcpy(d->pos, cmd->to, sizeof d->pos);
    return VP_OK;
}

static int dev_touched(void *ctx, double *at)
{
    sphere_dev_t *d = ctx;
    *at = d->at;
    return d->touched;
}

static int dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    sphere_dev_t *d = ctx;
    double t;
    d->probes++;
    res->hit = 0;
    res->dist = 0.0;
    if (sphere_first(d->pos, cmd->dir, cmd->range, &t)) {
        if (d->pos[cap_axis] + t * cmd->dir[cap_axis] > ZCAP) { d->dark++; return VP_OK; } /* no spot */
        res->hit = 1;
        res->dist = t;
    }
    return VP_OK;
}

static void config(vp_planner_config_t *c, double eps)
{
    int k;
    memset(c, 0, sizeof *c);
    c->omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) { c->omega_lo[k] = -1.5; c->omega_hi[k] = 1.5; }
    c->ninterior = 1;
    c->eps = eps;
    c->start[2] = 2.0;
}

static void scan(int contact, double eps, sphere_dev_t *d, vp_planner_stats_t *st, vp_run_result_t *run)
{
    static unsigned char arena[ARENA];
    static vp_planner_t pl;
    vp_planner_config_t cfg;
    vp_device_ops_t ops;
    config(&cfg, eps);
    memset(d, 0, sizeof *d);
    memcpy(d->pos, cfg.start, sizeof d->pos);
    d->contact = contact;
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    ops.ctx = d;
    ops.move = dev_move;
    ops.probe = dev_probe;
    ops.touched = contact ? dev_touched : NULL;
    ops.rays = NULL;
    ops.move_path = NULL;
    ops.sight = NULL;
    vp_run(&pl, &ops, NULL, 200000, run);
    vp_planner_get_stats(&pl, st);
}

static void test_dark_cap(void)
{
    sphere_dev_t d;
    vp_planner_stats_t st;
    vp_run_result_t run;
    double eps;
    for (eps = 0.2; eps >= 0.09; eps /= 1.5) {
        scan(1, eps, &d, &st, &run);
        CHECKF(run.status == VP_OK && run.done, "eps %.3f: status %d, done %d", eps, run.status, run.done);
        CHECKF(d.into == 0, "eps %.3f: %lu moves into the sphere", eps, d.into);
        CHECKF(d.contacts > 0 && d.contacts == st.contacts && run.contacts == d.contacts,
               "eps %.3f: contacts %lu, planner %llu", eps, d.contacts, (unsigned long long)st.contacts);
        CHECK(st.revoked >= st.contacts);
        printf("dark cap x > %.2f, eps %.3f, contact switch: %lu moves, %lu probes (%lu dark), %lu contacts, "
               "%llu proofs withdrawn, %llu misses not trusted, 0 moves into the sphere\n", ZCAP, eps, d.moves, d.probes,
               d.dark, d.contacts, (unsigned long long)st.revoked, (unsigned long long)st.dark_misses);
        /* the same scan without the switch goes into the sphere: what the check must see */
        scan(0, eps, &d, &st, &run);
        CHECKF(d.into > 0, "eps %.3f: without a contact switch no move entered the sphere", eps);
        printf("  without the switch: %lu moves into the sphere (down to %.3f below its surface)\n", d.into, d.deepest);
    }
}

static void test_contract(void)
{
    static unsigned char arena[ARENA];
    static vp_planner_t pl;
    vp_planner_config_t cfg;
    vp_cmd_t cmd;
    vp_probe_result_t res;
    vp_planner_stats_t a, b;
    sphere_dev_t d;
    int n, collided, touched = 0;
    config(&cfg, 0.2);
    memset(&d, 0, sizeof d);
    memcpy(d.pos, cfg.start, sizeof d.pos);
    d.contact = 1;
    CHECK(vp_planner_touch(NULL, 0.0) == VP_EINVAL);
    CHECK(vp_planner_init(&pl, arena, sizeof arena, &cfg) == VP_OK);
    CHECK(vp_planner_touch(&pl, 0.0) == VP_ESTATE);       /* no move yet */
    /* run the dark-cap sphere to its first contact */
    for (n = 0; n < 100000 && !touched; n++) {
        CHECK(vp_planner_next(&pl, &cmd) == VP_OK);
        if (cmd.kind == VP_CMD_DONE) break;
        if (cmd.kind == VP_CMD_PROBE) {
            dev_probe(&d, &cmd, &res);
            CHECK(vp_planner_touch(&pl, 0.0) == VP_ESTATE); /* a PROBE is owed */
            CHECK(vp_planner_feed(&pl, &res) == VP_OK);
            CHECK(vp_planner_touch(&pl, 0.0) == VP_ESTATE); /* the last command was a PROBE */
            continue;
        }
        dev_move(&d, &cmd, &collided);
        touched = d.touched;
    }
    CHECKF(touched, "no contact in %d commands", n);
    if (!touched) return;
    vp_planner_get_stats(&pl, &a);
    {
        double len = sqrt((cmd.to[0] - cmd.from[0]) * (cmd.to[0] - cmd.from[0]) + (cmd.to[1] - cmd.from[1]) * (cmd.to[1] - cmd.from[1]) +
                          (cmd.to[2] - cmd.from[2]) * (cmd.to[2] - cmd.from[2]));
        CHECK(vp_planner_touch(&pl, NAN) == VP_EINVAL);
        CHECK(vp_planner_touch(&pl, -1e-3) == VP_EINVAL);
        CHECK(vp_planner_touch(&pl, len * 1.01 + 1e-6) == VP_EINVAL);
        vp_planner_get_stats(&pl, &b);
        CHECK(memcmp(&a, &b, sizeof a) == 0);            /* refused: nothing changed */
        CHECK(vp_planner_touch(&pl, d.at) == VP_OK);
        CHECK(vp_planner_touch(&pl, d.at) == VP_ESTATE); /* once per move */
        vp_planner_get_stats(&pl, &b);
        CHECK(b.contacts == 1 && b.insertions == a.insertions + 1 && b.revoked >= 1);
        /* the next command backs off along the move to its start */
        CHECK(vp_planner_next(&pl, &cmd) == VP_OK);
        CHECK(cmd.kind == VP_CMD_MOVE && memcmp(cmd.from, d.pos, sizeof d.pos) == 0);
    }
    printf("vp_planner_touch: refuses NaN, negative, beyond the move, no move, a probe owed, twice; state "
           "unchanged; a contact after %d commands: sample inserted, the head backs off along the move\n", n);
}

/* The cap on the side the seed comes from (the start is above the sphere): the seed's probe
 * finds no surface where there must be one, and the seed comes from another direction instead
 * of stopping (VP_ERANGE before). */
static void test_dark_seed(void)
{
    sphere_dev_t d;
    vp_planner_stats_t st;
    vp_run_result_t run;
    cap_axis = 2;
    scan(1, 0.2, &d, &st, &run);
    CHECKF(run.status == VP_OK && run.done, "dark cap over the seed: status %d, done %d", run.status, run.done);
    CHECKF(d.into == 0, "dark cap over the seed: %lu moves into the sphere", d.into);
    printf("dark cap z > %.2f over the seed's way in: %s, %lu contacts, 0 moves into the sphere\n", ZCAP,
           run.done ? "DONE" : "stopped", d.contacts);
    cap_axis = 0;
}

int main(void)
{
    test_contract();
    test_dark_cap();
    test_dark_seed();
    return vp_test_done("test_contact");
}
