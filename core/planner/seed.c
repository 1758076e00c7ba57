/* seed.c — the start: for each interior point o_i (A1) a probe from dOmega towards it finds
 * the surface; three more around it make the paper's persistent facet (a tiny triangle whose
 * ball, <= eps/3, keeps Del_v|S(E) non-empty) and a fourth point makes the first tetrahedron. */
#include "vp_planner_priv.h"

/* The persistent facet must not be a needle: twice its area at least SEED_FAT times its longer
 * leg squared (an angle above about 11.5 degrees between equal legs); otherwise other axes and
 * smaller angles are tried, SEED_RETRIES times, then the thin one is kept. */
#define SEED_FAT 0.2
#define SEED_RETRIES 12

/* ---------- seeds: the persistent facet and a fourth point per component ---------- */

VP_PL_API int vp_pl_seed_issue(vp_planner_t *pl, const double *dir, double range)
{
    memcpy(pl->probe.origin, pl->pool.vrec[pl->dev.at].p, sizeof pl->probe.origin);
    memcpy(pl->probe.dir, dir, sizeof pl->probe.dir);
    pl->probe.full = range;
    pl->probe.range = vp_pl_clamp_range(pl, range);
    pl->probe.reach = 0.0;
    pl->seed.miss = 0;
    pl->probe.ready = 1;
    pl->probe.chain_proof = PROOF_NONE;
    return VP_OK;
}

/* A seed probe towards o_i that met nothing. A hit is certain somewhere along the ray (o_i is
 * inside the object), so a miss is re-probed first (a dropout): confirm_misses times, twice that
 * where the probe reaches o_i. A confirmed miss within the rangefinder's reach proves its
 * segment free: the device walks to its end and probes on along the same ray (not with a body:
 * that device stays outside Omega). 1: re-probing or walking on; 0: the whole ray is free, so
 * o_i is not inside the object; < 0: an error. */
VP_PL_API int vp_pl_seed_miss_on(vp_planner_t *pl)
{
    double e[3];
    int limited = vp_pl_probe_limited(pl);
    /* twice where the surface must lie within this probe's range */
    if (pl->seed.miss < (limited ? 1u : 2u) * pl->cfg.confirm_misses) {
        pl->seed.miss++;
        pl->st.reprobes++;
        pl->probe.ready = 1;
        return 1;
    }
    if (!limited || pl->cfg.clearance > 0.0) return 0;
    {
        vp_probe_result_t miss = { 0, 0.0 };
        uint32_t pf;
        VP_TRY(vp_pl_probe_proof(pl, &miss, &pf));
        if (VP_PL_CONTACTS && pf == PROOF_NONE) return 0; /* a miss near a contact: no way on */
        VP_TRY(vp_pl_walk_on(pl, pl->dev.at, pf, e));
        pl->probe.chain_proof = pf;
    }
    memcpy(pl->probe.origin, e, sizeof e);
    memcpy(pl->seed.q, e, sizeof e);
    pl->probe.full -= pl->probe.range;
    pl->probe.range = vp_pl_clamp_range(pl, pl->probe.full);
    pl->seed.miss = 0;
    pl->probe.ready = 1;
    return 1;
}

/* exit distance from p along unit u out of Omega */
VP_PL_API double vp_pl_omega_exit(const vp_planner_config_t *c, const double *p, const double *u)
{
    double t0, t1;
    if (!vp_pl_omega_clip(c, p, u, VP_PL_HUGE, &t0, &t1)) return 0.0;
    return t1;
}

static void seed_axes(const double *u, int turn, double *w1, double *w2)
{
    double t[3] = { 0, 0, 1 }, a[3], b[3];
    int k;
    if (fabs(u[2]) > 0.8) { t[0] = 1; t[2] = 0; }
    vp_cross3(a, u, t);
    vp_normalize3(a);
    vp_cross3(b, u, a);
    /* turn the pair by 30 degrees per retry (cos, sin of 30 deg multiples by rotation) */
    for (k = 0; k < turn % 6; k++) {
        double c30 = 0.8660254037844386, s30 = 0.5, na[3], nb[3];
        int q;
        for (q = 0; q < 3; q++) {
            na[q] = c30 * a[q] + s30 * b[q];
            nb[q] = -s30 * a[q] + c30 * b[q];
        }
        memcpy(a, na, sizeof a);
        memcpy(b, nb, sizeof b);
    }
    memcpy(w1, a, sizeof a);
    memcpy(w2, b, sizeof b);
}

/* Where the seed of o_i comes from: the start's side, or after a seed that found nothing where
 * S must be (a dark or shiny surface on the way in: the contact safety net's case) the
 * reseeding directions, each once. */
#define SEED_DIRS 26u
static void seed_dir(const vp_planner_t *pl, const double *o, double *u)
{
#if VP_PL_CONTACTS
    if (pl->seed.dir > 0) { vp_pl_reseed_dir(pl->seed.dir - 1, u); return; }
#endif
    vp_sub3(u, pl->cfg.start, o);
    if (!vp_normalize3(u)) { u[0] = 0; u[1] = 0; u[2] = 1; }
}

/* The seed found no surface where there must be one: start it again from the next direction
 * (its points so far dropped), else VP_ERANGE (o_i is not inside the object). */
static int seed_other_dir(vp_planner_t *pl)
{
#if VP_PL_CONTACTS
    if (pl->seed.dir < SEED_DIRS) {
        pl->seed.dir++;
        pl->seed.npts = pl->seed.base;
        pl->seed.step = 0;
        pl->seed.attempt = 0;
        pl->seed.miss = 0;
        return VP_OK;
    }
#endif
    (void)pl;
    return VP_ERANGE;
}

VP_PL_API int vp_pl_seed_next(vp_planner_t *pl)
{
    const double *o;
    double u[3], d[3], w1[3], w2[3], te, th;
    int k;
    if (pl->seed.cur >= pl->cfg.ninterior) return 1; /* all seeds probed */
    o = pl->cfg.interior[pl->seed.cur];
    seed_dir(pl, o, u);
    switch (pl->seed.step) {
    case 0: /* from dOmega towards o */
        te = vp_pl_omega_exit(&pl->cfg, o, u);
        for (k = 0; k < 3; k++) pl->seed.q[k] = o[k] + te * u[k];
        VP_TRY(vp_pl_plan_route(pl, NONE, pl->seed.q));
        for (k = 0; k < 3; k++) d[k] = -u[k];
        return vp_pl_seed_issue(pl, d, te);
    case 1:
    case 2: /* two directions very close to [q, a): the persistent facet */
        th = pl->cfg.eps / (8.0 * vp_dist3(pl->seed.q, pl->seed.pts[pl->seed.npts - 1])) /
             (double)(1u << (2 * (pl->seed.attempt / 2)));
        if (!(th <= 1.0)) th = 1.0; /* a hit nearer than eps/8 (or at q itself): 45 degrees at most */
        seed_axes(u, (int)pl->seed.attempt, w1, w2);
        for (k = 0; k < 3; k++) d[k] = -u[k] + th * (pl->seed.step == 1 ? w1[k] : w2[k]);
        vp_normalize3(d);
        return vp_pl_seed_issue(pl, d, 2.0 * vp_dist3(pl->seed.q, o) + pl->cfg.eps);
    default: /* a fourth point, from the other side of Omega */
        for (k = 0; k < 3; k++) d[k] = -u[k];
        te = vp_pl_omega_exit(&pl->cfg, o, d);
        {
            double q2[3];
            for (k = 0; k < 3; k++) q2[k] = o[k] + te * d[k];
            VP_TRY(vp_pl_plan_route(pl, NONE, q2));
        }
        return vp_pl_seed_issue(pl, u, te);
    }
}

VP_PL_API int vp_pl_seed_feed(vp_planner_t *pl, const vp_probe_result_t *res_in)
{
    double h[3];
    int k;
    vp_probe_result_t r = *res_in;
    const vp_probe_result_t *res = &r;
    if (r.hit == 1) {
        for (k = 0; k < 3; k++) h[k] = pl->probe.origin[k] + r.dist * pl->probe.dir[k];
        /* S lies inside Omega (A2): a hit on dOmega or beyond it (at the probe's very origin,
         * a false hit) is no sample, and the facet's legs would have no length; as unreadable */
        if (!vp_pl_omega_inside(&pl->cfg, h)) r.hit = VP_PROBE_TOO_CLOSE;
    }
    if (r.hit == VP_PROBE_TOO_CLOSE) r.hit = 0; /* no usable sample: like a miss */
    if (!res->hit && pl->seed.step != 1 && pl->seed.step != 2) {
        /* towards o_i: a hit is certain unless o_i is outside the object */
        int w = res_in->hit != 0 ? 0 : vp_pl_seed_miss_on(pl);
        if (w < 0) return w;
        return w ? VP_OK : seed_other_dir(pl);
    }
    switch (pl->seed.step) {
    case 0:
        memcpy(pl->seed.pts[pl->seed.npts++], h, sizeof h);
#ifndef VP_CORE_MCU
        memcpy(pl->seed.ray[pl->seed.npts - 1], pl->probe.dir, sizeof pl->seed.ray[0]);
#endif
        pl->seed.step = 1;
        pl->seed.attempt = 0;
        return VP_OK;
    case 1:
    case 2:
        if (res->hit && vp_dist3(h, pl->seed.pts[pl->seed.npts - pl->seed.step]) <= pl->cfg.eps / 4.0) {
            memcpy(pl->seed.pts[pl->seed.npts++], h, sizeof h);
#ifndef VP_CORE_MCU
        memcpy(pl->seed.ray[pl->seed.npts - 1], pl->probe.dir, sizeof pl->seed.ray[0]);
#endif
            if (pl->seed.step == 2) {
                /* legs short and the triangle not flat, else try other axes, smaller angles */
                const double *a = pl->seed.pts[pl->seed.npts - 3], *b = pl->seed.pts[pl->seed.npts - 2];
                double ab[3], ac[3], n[3], area2, l2;
                vp_sub3(ab, b, a);
                vp_sub3(ac, h, a);
                vp_cross3(n, ab, ac);
                area2 = sqrt(vp_dot3(n, n));
                l2 = vp_dot3(ab, ab) > vp_dot3(ac, ac) ? vp_dot3(ab, ab) : vp_dot3(ac, ac);
                if (!(area2 > SEED_FAT * l2) && pl->seed.attempt < SEED_RETRIES) {
                    pl->seed.npts -= 2;
                    pl->seed.attempt++;
                    pl->seed.step = 1;
                    return VP_OK;
                }
                pl->seed.step = 3;
            } else {
                pl->seed.step = 2;
            }
            return VP_OK;
        }
        /* a miss or a far hit (near a silhouette the ray lands elsewhere): retry */
        if (pl->seed.attempt >= 12) return seed_other_dir(pl);
        if (pl->seed.step == 2) pl->seed.npts--;
        pl->seed.attempt++;
        pl->seed.step = 1;
        return VP_OK;
    default:
        memcpy(pl->seed.pts[pl->seed.npts++], h, sizeof h);
#ifndef VP_CORE_MCU
        memcpy(pl->seed.ray[pl->seed.npts - 1], pl->probe.dir, sizeof pl->seed.ray[0]);
#endif
        pl->seed.cur++;
        pl->seed.step = 0;
#if VP_PL_CONTACTS
        pl->seed.dir = 0;
        pl->seed.base = pl->seed.npts;
#endif
        return VP_OK;
    }
}

/* All seed points in the triangulation; every outside Voronoi vertex is active. */
VP_PL_API int vp_pl_start_run(vp_planner_t *pl)
{
    uint32_t i, t;
    int st;
    for (i = 0; i < pl->seed.npts; i++) {
        st = vp_dt_insert(&pl->dt, pl->seed.pts[i], VP_DT_NONE, NULL);
        if (st != VP_OK && st != VP_EDUP) return st;
    }
    if (pl->dt.dim < 3) return VP_EDEGEN;
    for (t = 0; t < pl->dt.ntet_slots; t++) {
        double c[3];
        if (!vp_dt_alive(&pl->dt, t)) continue;
        pay(pl, t)[1] = 0;
        pay(pl, t)[0] = (vp_dt_is_ghost(&pl->dt, t) || vp_pl_tet_point(pl, t, c) != VP_OK ||
                         !vp_pl_omega_inside(&pl->cfg, c)) ? VREC_OUT : NONE;
    }
    for (t = 0; t < pl->dt.ntet_slots; t++)
        if (vp_dt_alive(&pl->dt, t) && tet_active(pl, t))
            VP_TRY(vp_pl_explore(pl, t));
    vp_pl_note_peak(pl);
    return VP_OK;
}
