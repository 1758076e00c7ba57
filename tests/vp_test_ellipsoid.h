/* vp_test_ellipsoid.h — an ellipsoid written from its formula alone, for the tests that check the
 * planner without host-sim (test_lineray, test_rescan, test_sight): its implicit value, a ray's
 * first entry from outside, whether a straight move enters it; a device that probes and moves
 * against it, the planner configuration those tests share, and the judge of the mesh they scan. */
#ifndef VP_TEST_ELLIPSOID_H
#define VP_TEST_ELLIPSOID_H
#include <math.h>
#include <string.h>
#include "vp_device.h"
#include "vp_planner.h"
#include "vp_test.h"

typedef struct vp_test_ell {
    double ax[3], c[3]; /* semi-axes, centre */
} vp_test_ell_t;

static double vp_test_ell_f(const vp_test_ell_t *e, const double *x)
{
    double y0 = x[0] - e->c[0], y1 = x[1] - e->c[1], y2 = x[2] - e->c[2];
    return y0 * y0 / (e->ax[0] * e->ax[0]) + y1 * y1 / (e->ax[1] * e->ax[1]) + y2 * y2 / (e->ax[2] * e->ax[2]) - 1.0;
}

/* first t in (0, len] where p + t u meets the ellipsoid from outside; 0 if none */
static int vp_test_ell_first(const vp_test_ell_t *e, const double *p, const double *u, double len, double *t)
{
    double a = 0, b = 0, c = vp_test_ell_f(e, p), disc, s;
    int k;
    for (k = 0; k < 3; k++) {
        a += u[k] * u[k] / (e->ax[k] * e->ax[k]);
        b += (p[k] - e->c[k]) * u[k] / (e->ax[k] * e->ax[k]);
    }
    disc = b * b - a * c;
    if (disc <= 0.0) return 0;
    s = (-b - sqrt(disc)) / a;
    if (s <= 1e-12 || s > len) return 0;
    *t = s;
    return 1;
}

/* 1 if the straight move from p to q enters the ellipsoid or ends inside it */
static int vp_test_ell_move_enters(const vp_test_ell_t *e, const double *p, const double *q)
{
    double u[3], len, t;
    int k;
    for (k = 0; k < 3; k++) u[k] = q[k] - p[k];
    len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (!(len > 0.0)) return 0;
    for (k = 0; k < 3; k++) u[k] /= len;
    return vp_test_ell_first(e, p, u, len, &t) || vp_test_ell_f(e, q) < 0.0;
}

/* A device at pos against ellipsoid e (a test's own device starts with one): its MOVEs count
 * those that enter e, its PROBEs meet e exactly. */
typedef struct vp_test_ell_dev {
    vp_test_ell_t e;
    double pos[3];
    unsigned long probes, moves, into;
} vp_test_ell_dev_t;

static inline int vp_test_ell_dev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    vp_test_ell_dev_t *d = ctx;
    d->moves++;
    *collided = vp_test_ell_move_enters(&d->e, d->pos, cmd->to);
    d->into += (unsigned long)*collided;
    memcpy(d->pos, cmd->to, sizeof d->pos);
    return VP_OK;
}

static inline int vp_test_ell_dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    vp_test_ell_dev_t *d = ctx;
    double t;
    d->probes++;
    res->hit = vp_test_ell_first(&d->e, d->pos, cmd->dir, cmd->range, &t);
    res->dist = res->hit ? t : 0.0;
    return VP_OK;
}

/* Omega: the box of semi-axes ax grown by 0.3, one interior point (the centre), the device
 * starting 0.5 above the top */
static inline void vp_test_ell_config(vp_planner_config_t *c, const double *ax, double eps)
{
    int k;
    memset(c, 0, sizeof *c);
    c->omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) {
        c->omega_lo[k] = -ax[k] - 0.3;
        c->omega_hi[k] = ax[k] + 0.3;
    }
    c->ninterior = 1;
    c->eps = eps;
    c->start[2] = ax[2] + 0.5;
}

/* The planner's mesh judged against e: closed and oriented (each directed edge once, its reverse
 * present), Euler characteristic 2, every ball centre and every vertex on e, every ball's radius
 * (its centre to its vertices, recomputed) at most eps. what names the case in a failure; returns
 * the mesh's vertices. */
static inline unsigned vp_test_ell_judge(const vp_planner_t *pl, const vp_test_ell_t *e, double eps, const char *what)
{
    enum { MAXV = 200000, MAXH = 600000 };
    static uint32_t used[MAXV];
    static uint64_t half[MAXH];
    const vp_dt_t *dt = vp_planner_dt(pl);
    uint32_t slots = vp_planner_facet_slots(pl), i, j, nf = 0, nv = 0, v[3];
    uint32_t nh = 0, lost = 0, bad_ball = 0, open = 0, off_surface = 0;
    double r, c[3], worst = 0.0;
    CHECKF(dt->nvert <= MAXV, "%s: %u samples, more than the judge holds", what, dt->nvert);
    if (dt->nvert > MAXV) return 0;
    memset(used, 0, sizeof used);
    for (i = 0; i < slots; i++) {
        int k;
        if (!vp_planner_facet(pl, i, v, &r, c)) continue;
        nf++;
        if (fabs(vp_test_ell_f(e, c)) > 1e-9) off_surface++;
        for (k = 0; k < 3; k++) {
            const double *p = vp_dt_point(dt, v[k]);
            double d = sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2]));
            if (d > worst) worst = d;
            if (d > eps * (1 + 1e-9)) bad_ball++;
            if (!used[v[k]]++) nv++;
            if (nh < MAXH) half[nh++] = ((uint64_t)v[k] << 32) | v[(k + 1) % 3];
            else lost++;
        }
    }
    for (i = 0; i < nh; i++) {
        uint64_t rev = (half[i] << 32) | (half[i] >> 32);
        uint32_t found = 0, same = 0;
        for (j = 0; j < nh; j++) {
            found += half[j] == rev;
            same += half[j] == half[i];
        }
        if (found != 1 || same != 1) open++;
    }
    for (i = 0; i < dt->nvert; i++)
        if (used[i] && fabs(vp_test_ell_f(e, vp_dt_point(dt, i))) > 1e-9) off_surface++;
    CHECKF(lost == 0, "%s: %u half-edges more than the judge holds", what, lost);
    CHECKF(nf > 0 && open == 0, "%s: %u of %u half-edges without a single reverse", what, open, nh);
    CHECKF((long)nv - (long)(nh / 2) + (long)nf == 2, "%s: Euler characteristic %ld", what,
           (long)nv - (long)(nh / 2) + (long)nf);
    CHECKF(bad_ball == 0, "%s: %u ball radii above eps (worst %.9g)", what, bad_ball, worst);
    CHECKF(off_surface == 0, "%s: %u points off the ellipsoid", what, off_surface);
    return nv;
}

#endif
