/* route.c — Omega, the free graph and the device's routes.
 * Omega is the known region holding the object (A2: R^3 \ Omega is free). The records are the
 * paper's active Voronoi vertices (current or former) with their prev links ("prev chains",
 * the paper's paths back to R^3 \ Omega); the free graph joins records by proven-free
 * segments. Routes: around Omega outside it, along prev chains (VP_PLAN_PREV_CHAINS, the
 * paper), or by A* over the free graph with a straight shortcut probed when the search runs
 * long. Body mode with the axes' speeds (timed): the way round a ball Omega that takes the
 * least machine time, and the machine time of the way to a probe (the nearest task, tasks.c). */
#include "vp_planner_priv.h"

/* ---------- Omega ---------- */

VP_PL_API void vp_pl_omega_center(const vp_planner_config_t *c, double *o)
{
    int k;
    for (k = 0; k < 3; k++)
        o[k] = c->omega_kind == VP_OMEGA_BALL ? c->omega_center[k] : 0.5 * (c->omega_lo[k] + c->omega_hi[k]);
}

VP_PL_API double vp_pl_omega_circumradius(const vp_planner_config_t *c)
{
    if (c->omega_kind == VP_OMEGA_BALL) return c->omega_radius;
    return 0.5 * sqrt((c->omega_hi[0] - c->omega_lo[0]) * (c->omega_hi[0] - c->omega_lo[0]) +
                      (c->omega_hi[1] - c->omega_lo[1]) * (c->omega_hi[1] - c->omega_lo[1]) +
                      (c->omega_hi[2] - c->omega_lo[2]) * (c->omega_hi[2] - c->omega_lo[2]));
}

/* strictly inside Omega */
VP_PL_API int vp_pl_omega_inside(const vp_planner_config_t *c, const double *p)
{
    if (c->omega_kind == VP_OMEGA_BALL) {
        double d[3];
        vp_sub3(d, p, c->omega_center);
        return vp_dot3(d, d) < c->omega_radius * c->omega_radius;
    }
    return p[0] > c->omega_lo[0] && p[0] < c->omega_hi[0] && p[1] > c->omega_lo[1] &&
           p[1] < c->omega_hi[1] && p[2] > c->omega_lo[2] && p[2] < c->omega_hi[2];
}

/* The parameter interval [*t0, *t1] of a + s*dir (unit dir, s in [0, len]) inside Omega.
 * Returns 0 when the line misses Omega there. */
VP_PL_API int vp_pl_omega_clip(const vp_planner_config_t *c, const double *a, const double *dir, double len,
                               double *t0, double *t1)
{
    double lo = 0.0, hi = len;
    if (c->omega_kind == VP_OMEGA_BALL) {
        double d[3], b, cc, disc, sq;
        vp_sub3(d, a, c->omega_center);
        b = vp_dot3(d, dir);
        cc = vp_dot3(d, d) - c->omega_radius * c->omega_radius;
        disc = b * b - cc;
        if (!(disc > 0.0)) return 0;
        sq = sqrt(disc);
        if (-b - sq > lo) lo = -b - sq;
        if (-b + sq < hi) hi = -b + sq;
    } else {
        int k;
        for (k = 0; k < 3; k++) {
            if (dir[k] == 0.0) {
                if (!(a[k] > c->omega_lo[k] && a[k] < c->omega_hi[k])) return 0;
            } else {
                double s0 = (c->omega_lo[k] - a[k]) / dir[k], s1 = (c->omega_hi[k] - a[k]) / dir[k];
                if (s0 > s1) { double t = s0; s0 = s1; s1 = t; }
                if (s0 > lo) lo = s0;
                if (s1 < hi) hi = s1;
            }
        }
    }
    if (!(lo < hi)) return 0;
    *t0 = lo;
    *t1 = hi;
    return 1;
}

/* 1 if segment [a, b] enters Omega (more than rounding) */
VP_PL_API int vp_pl_seg_enters_omega(const vp_planner_config_t *c, const double *a, const double *b)
{
    double d[3], len, t0, t1;
    vp_sub3(d, b, a);
    len = sqrt(vp_dot3(d, d));
    if (!(len > 0.0)) return vp_pl_omega_inside(c, a);
    d[0] /= len; d[1] /= len; d[2] /= len;
    return vp_pl_omega_clip(c, a, d, len, &t0, &t1) && t1 - t0 > LEN_REL_EPS * (1.0 + len);
}

/* ---------- records and the free graph ---------- */

VP_PL_API int vp_pl_rec_new(vp_planner_t *pl, const double *p, uint32_t prev, uint32_t flags, uint32_t *out)
{
    vp_vrec_t *r;
    if (pl->pool.nvrec >= pl->pool.cap_vrec) return VP_ENOMEM;
    r = &pl->pool.vrec[pl->pool.nvrec];
    r->p[0] = p[0]; r->p[1] = p[1]; r->p[2] = p[2];
    r->prev = prev == NONE ? pl->pool.nvrec : prev;
    r->adj = NONE;
    r->depth = prev == NONE ? 0 : pl->pool.vrec[prev].depth + 1;
    r->flags = flags;
    r->stamp = 0;
    r->from = NONE;
    r->g = 0.0;
    r->proof = PROOF_NONE;
    *out = pl->pool.nvrec++;
    return VP_OK;
}


/* Joins records a and b by a free edge when `proof` covers the segment between them; a
 * segment it does not cover is counted and left out (never travelled). */
VP_PL_API int vp_pl_edge_add(vp_planner_t *pl, uint32_t a, uint32_t b, uint32_t proof)
{
    uint32_t e, *w;
    if (a == b) return VP_OK;
    if (!vp_pl_proof_covers(pl, proof, pl->pool.vrec[a].p, pl->pool.vrec[b].p)) {
        pl->st.unproven++;
        return VP_OK;
    }
    if (pl->pool.nfedge >= pl->pool.cap_fedge) return VP_ENOMEM;
    e = pl->pool.nfedge++;
    w = pl->pool.fedge + FEDGE_WORDS * e;
    w[0] = a;
    w[1] = b;
    w[2] = pl->pool.vrec[a].adj;
    w[3] = pl->pool.vrec[b].adj;
    w[4] = proof;
    pl->pool.vrec[a].adj = e;
    pl->pool.vrec[b].adj = e;
    if (VP_PL_CONTACTS && ((pl->pool.vrec[a].flags ^ pl->pool.vrec[b].flags) & REC_LOST)) {
        /* a lost record joined again (contact.c): its prev chain goes through this edge */
        uint32_t x = (pl->pool.vrec[a].flags & REC_LOST) ? a : b, y = x == a ? b : a;
        pl->pool.vrec[x].flags &= ~REC_LOST;
        pl->pool.vrec[x].prev = y;
        pl->pool.vrec[x].depth = pl->pool.vrec[y].depth + 1;
        pl->pool.vrec[x].proof = proof;
    }
    return VP_OK;
}

/* A record reached from `prev` along the segment `proof` shows free. *out = NONE (and nothing
 * made) when the proof does not cover it. */
VP_PL_API int vp_pl_rec_link(vp_planner_t *pl, const double *p, uint32_t prev, uint32_t flags, uint32_t proof,
                             uint32_t *out)
{
    int st;
    *out = NONE;
    if (prev != NONE && !vp_pl_proof_covers(pl, proof, pl->pool.vrec[prev].p, p)) {
        pl->st.unproven++;
        return VP_OK;
    }
    st = vp_pl_rec_new(pl, p, prev, flags, out);
    if (st != VP_OK) return st;
    if (prev != NONE) {
        pl->pool.vrec[*out].proof = proof;
        st = vp_pl_edge_add(pl, prev, *out, proof);
        if (st != VP_OK) { pl->pool.nvrec--; *out = NONE; return st; }
    }
    return VP_OK;
}

/* 1 for a proof a contact withdrew (contact.c) */
static int proof_withdrawn(const vp_planner_t *pl, uint32_t id)
{
    return VP_PL_CONTACTS && id < pl->pool.nproof && !(pl->pool.proof[id].len >= 0.0);
}

/* 1 for a record a contact cut off from the outside (contact.c) */
static int rec_lost(const vp_planner_t *pl, uint32_t r)
{
    return VP_PL_CONTACTS && (pl->pool.vrec[r].flags & REC_LOST);
}

/* the proof of a free edge between records a and b that covers them, or PROOF_NONE */
static uint32_t edge_proof(const vp_planner_t *pl, uint32_t a, uint32_t b)
{
    uint32_t e;
    for (e = pl->pool.vrec[a].adj; e != NONE;) {
        const uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
        int isa = w[0] == a;
        if ((isa ? w[1] : w[0]) == b && !proof_withdrawn(pl, w[4])) return w[4];
        e = isa ? w[2] : w[3];
    }
    return PROOF_NONE;
}

/* ---------- routes outside Omega ---------- */

/* Appends a step to the route, with its proof of freedom. */
VP_PL_API int vp_pl_route_push(vp_planner_t *pl, const double *p, uint32_t proof)
{
    double *q;
    if (pl->route.n >= pl->route.cap) return VP_ENOMEM;
    q = pl->route.pts + 3 * (size_t)pl->route.n;
    if (pl->route.n > 0 && q[-3] == p[0] && q[-2] == p[1] && q[-1] == p[2]) return VP_OK;
    q[0] = p[0]; q[1] = p[1]; q[2] = p[2];
    pl->route.proof[pl->route.n] = proof;
    pl->route.n++;
    return VP_OK;
}

/* A probe's range within the rangefinder's reach. */
VP_PL_API double vp_pl_clamp_range(const vp_planner_t *pl, double range)
{
    return pl->cfg.max_range > 0.0 && range > pl->cfg.max_range ? pl->cfg.max_range : range;
}

/* 1 if the current probe was cut short by the rangefinder's reach */
VP_PL_API int vp_pl_probe_limited(const vp_planner_t *pl)
{
    return pl->probe.range < pl->probe.full - LEN_REL_EPS * (1.0 + pl->probe.full);
}

/* A range-limited probe missed: its segment is free (proof). The device walks from record
 * `from` to the segment's end (a new record, pl->dev.at) to probe on; the step costs the same
 * under either rule. */
VP_PL_API int vp_pl_walk_on(vp_planner_t *pl, uint32_t from, uint32_t proof, double e[3])
{
    uint32_t r;
    int k;
    for (k = 0; k < 3; k++) e[k] = pl->probe.origin[k] + pl->probe.range * pl->probe.dir[k];
    VP_TRY(vp_pl_rec_link(pl, e, from, 0, proof, &r));
    if (r == NONE) return VP_EUNSAFE; /* the probe's own end: never */
    pl->st.travel_prev_chains += pl->probe.range;
    pl->route.n = pl->route.i = 0;
    VP_TRY(vp_pl_route_push(pl, e, proof));
    pl->dev.at = r;
    return VP_OK;
}

/* the fallback sphere is 1% beyond Omega's circumsphere: a chord of <= 15 degrees dips to
 * cos(7.5 deg) = 0.9914 of the radius, still outside the circumsphere (1.01 x 0.9914 > 1) */
#define SPHERE_ROUTE_GROW 1.01
#define SPHERE_ROUTE_CHORDS 8 /* per quarter turn at most: <= 11.25 degrees each */
/* a pushed-out midpoint lands this share of Omega's circumradius beyond dOmega: clear of
 * rounding, a short detour */
#define PUSH_OUT_REL 0.01

/* Moves m (the midpoint of a chord with unit direction u) out of Omega: along the part of
 * (m - centre) perpendicular to the chord, to delta beyond dOmega. */
static void push_out(const vp_planner_config_t *c, double *m, const double *u, double delta)
{
    double o[3], d[3], t0, t1, s;
    int k;
    vp_pl_omega_center(c, o);
    vp_sub3(d, m, o);
    s = vp_dot3(d, u);
    for (k = 0; k < 3; k++) d[k] -= s * u[k];
    if (!vp_normalize3(d)) {
        double t[3] = { 0, 0, 1 };
        if (fabs(u[2]) > 0.8) { t[0] = 1; t[2] = 0; }
        vp_cross3(d, u, t);
        vp_normalize3(d);
    }
    if (!vp_pl_omega_clip(c, m, d, VP_PL_HUGE, &t0, &t1)) return;
    for (k = 0; k < 3; k++) m[k] += (t1 + delta) * d[k];
}

/* The fallback: out to a sphere around Omega's circumsphere, along the great circle in chords
 * of at most 15 degrees (they stay outside the circumsphere), and back in. */
static int sphere_route(vp_planner_t *pl, const double *a, const double *b, int dry, double *len)
{
    double c[3], ra, rb, rs, ua[3], ub[3], um[3], prev[3];
    int i, k, st, half;
    vp_pl_omega_center(&pl->cfg, c);
    rs = SPHERE_ROUTE_GROW * vp_pl_omega_circumradius(&pl->cfg);
    vp_sub3(ua, a, c);
    vp_sub3(ub, b, c);
    ra = sqrt(vp_dot3(ua, ua));
    rb = sqrt(vp_dot3(ub, ub));
    if (!vp_normalize3(ua) || !vp_normalize3(ub)) return VP_EDEGEN;
    if (ra < rs) ra = rs;
    if (rb < rs) rb = rs;
    for (k = 0; k < 3; k++) um[k] = ua[k] + ub[k];
    if (!vp_normalize3(um)) {
        double t[3] = { 1, 0, 0 };
        if (fabs(ua[0]) > 0.9) { t[0] = 0; t[1] = 1; }
        vp_cross3(um, ua, t);
        vp_normalize3(um);
    }
    prev[0] = a[0]; prev[1] = a[1]; prev[2] = a[2];
    for (half = 0; half < 2; half++) {
        const double *u0 = half ? um : ua, *u1 = half ? ub : um;
        for (i = half; i <= SPHERE_ROUTE_CHORDS; i++) {
            double s = i / (double)SPHERE_ROUTE_CHORDS, w[3], r = ra + (rb - ra) * 0.5 * (half + s);
            for (k = 0; k < 3; k++) w[k] = (1.0 - s) * u0[k] + s * u1[k];
            vp_normalize3(w);
            for (k = 0; k < 3; k++) w[k] = c[k] + r * w[k];
            *len += vp_dist3(prev, w);
            if (!dry && (st = vp_pl_route_push(pl, w, PROOF_OUTSIDE)) != VP_OK) return st;
            prev[0] = w[0]; prev[1] = w[1]; prev[2] = w[2];
        }
    }
    *len += vp_dist3(prev, b);
    return dry ? VP_OK : vp_pl_route_push(pl, b, PROOF_OUTSIDE);
}

/* Appends a path between two points on or outside dOmega that stays outside Omega: the
 * straight segment where it does not enter Omega, otherwise its midpoint pushed out of Omega
 * (sideways to the chord), recursively with an explicit stack of bounded depth, so the path
 * hugs dOmega. If that does not settle, the way round Omega's circumsphere. *len gets its
 * length; with dry != 0 it only measures. */
#define ROUTE_DEPTH 10 /* midpoint pushes per segment: 2^10 pieces hug any convex dOmega */
static int outside_route(vp_planner_t *pl, const double *a, const double *b, int dry, double *len)
{
    double stack[ROUTE_DEPTH + 2][3], cur[3], delta = PUSH_OUT_REL * vp_pl_omega_circumradius(&pl->cfg);
    int depth[ROUTE_DEPTH + 2], n = 0, st;
    uint32_t nroute0 = pl->route.n;
    *len = 0.0;
    memcpy(cur, a, sizeof cur);
    memcpy(stack[n], b, sizeof stack[n]);
    depth[n++] = 0;
    while (n > 0) {
        double *y = stack[n - 1], m[3], u[3];
        int d = depth[n - 1], k;
        if (!vp_pl_seg_enters_omega(&pl->cfg, cur, y)) {
            *len += vp_dist3(cur, y);
            if (!dry && (st = vp_pl_route_push(pl, y, PROOF_OUTSIDE)) != VP_OK) return st;
            memcpy(cur, y, sizeof cur);
            n--;
            continue;
        }
        if (d >= ROUTE_DEPTH) {
            pl->route.n = nroute0;
            *len = 0.0;
            return sphere_route(pl, a, b, dry, len);
        }
        vp_sub3(u, y, cur);
        vp_normalize3(u);
        for (k = 0; k < 3; k++) m[k] = 0.5 * (cur[k] + y[k]);
        push_out(&pl->cfg, m, u, delta);
        depth[n - 1] = d + 1;
        memcpy(stack[n], m, sizeof m);
        depth[n++] = d + 1;
    }
    return VP_OK;
}

#if VP_PL_TIMED
/* timed: a body, and the times of x, y and z (pan and tilt may be left out) */
int vp_planner_timed(const vp_planner_config_t *c)
{
    return c->clearance > 0.0 && c->axis_time[0] > 0.0 && c->axis_time[1] > 0.0 && c->axis_time[2] > 0.0;
}

VP_PL_API int vp_pl_timed(const vp_planner_t *pl) { return vp_planner_timed(&pl->cfg); }

/* the pan has no travel given: it turns freely */
static int pan_free(const vp_planner_t *pl) { return pl->cfg.pan_travel[0] == 0.0 && pl->cfg.pan_travel[1] == 0.0; }

/* The time of the straight move from a to b at the axes' top speeds: the slowest axis's. */
VP_PL_API double vp_pl_move_time(const vp_planner_t *pl, const double *a, const double *b)
{
    double t = 0.0, u;
    int k;
    for (k = 0; k < 3; k++) {
        u = pl->cfg.axis_time[k] * fabs(b[k] - a[k]);
        if (u > t) t = u;
    }
    return t;
}

#define TURN_PI 3.14159265358979324
/* atan2(y, x) to within 2e-6 radians, by + - * / alone (the same bits on every machine): an
 * odd polynomial for atan on [0, 1] (Abramowitz and Stegun 4.4.49's kind), the octant folded
 * in. A cost is all it is used for. */
static double turn_angle(double y, double x)
{
    double ax = fabs(x), ay = fabs(y), t, t2, a;
    if (!(ax > 0.0) && !(ay > 0.0)) return 0.0;
    t = ax >= ay ? ay / ax : ax / ay;
    t2 = t * t;
    a = t * (0.99997726 + t2 * (-0.33262347 + t2 * (0.19354346 + t2 * (-0.11643287 + t2 * (0.05265332 - 0.01172120 * t2)))));
    if (ay > ax) a = 0.5 * TURN_PI - a;
    if (x < 0.0) a = TURN_PI - a;
    return y < 0.0 ? -a : a;
}

/* q turned by whole turns to the nearest to cur (floor: exact) */
static double turn_near(double q, double cur)
{
    return q + 2.0 * TURN_PI * floor((cur - q) / (2.0 * TURN_PI) + 0.5);
}

/* The pan that aims along dir from where the head is aimed now (dev.pan): the direction's
 * azimuth turned by whole turns to the nearest within the pan's travel (a machine's aim does
 * the same), or, a pan that turns freely, the one at most half a turn away. Straight up or
 * down any pan aims: the head keeps its own. */
VP_PL_API double vp_pl_pan_for(const vp_planner_t *pl, const double *dir)
{
    double cur = pl->dev.pan, lo = pl->cfg.pan_travel[0], hi = pl->cfg.pan_travel[1], p, q, best, bd = VP_PL_HUGE;
    int k;
    if (!(dir[0] * dir[0] + dir[1] * dir[1] > 1e-18)) return cur;
    p = turn_near(turn_angle(dir[1], dir[0]), cur);
    if (pan_free(pl)) return p;
    best = p < lo ? lo : p > hi ? hi : p; /* none within travel: as near as it goes */
    for (k = -1; k <= 1; k++) {
        q = p + k * 2.0 * TURN_PI;
        if (q >= lo && q <= hi && fabs(q - cur) < bd) {
            bd = fabs(q - cur);
            best = q;
        }
    }
    return best;
}

/* A PROBE along dir goes out: the pan it is aimed with (a pan that turns freely kept within
 * half a turn of 0: only its turns count) */
VP_PL_API void vp_pl_pan_aim(vp_planner_t *pl, const double *dir)
{
    double p = vp_pl_pan_for(pl, dir);
    pl->dev.pan = pan_free(pl) ? turn_near(p, 0.0) : p;
}

/* The least machine time of the way to a probe from o along dir: the straight move's, or
 * the head's turn (pan and tilt), whichever is longer (the axes move together). */
VP_PL_API double vp_pl_way_time(const vp_planner_t *pl, const double *o, const double *dir)
{
    const double *d0 = pl->dev.iss_d;
    double t = vp_pl_move_time(pl, pl->dev.pos, o), u;
    u = pl->cfg.axis_time[3] * fabs(vp_pl_pan_for(pl, dir) - pl->dev.pan);
    if (u > t) t = u;
    u = pl->cfg.axis_time[4] * fabs(turn_angle(dir[2], sqrt(dir[0] * dir[0] + dir[1] * dir[1])) -
                                    turn_angle(d0[2], sqrt(d0[0] * d0[0] + d0[1] * d0[1])));
    return u > t ? u : t;
}

/* The level way round a ball Omega: about the axis through the centre along the slowest of
 * x, y, z (k), the head's coordinate h on that axis and its distance r from the centre go
 * linearly from a's to b's, its direction about the axis turns from a's to b's (in two halves
 * of under a half turn each), on or beyond the route sphere. The slowest axis thus travels
 * |h_b - h_a| only, where the great circle may climb over the ball and back down (two starts
 * at one height on either side: over the top). */
typedef struct level {
    double c[3], ha, hb, ra, rb, ea[2], em[2], eb[2];
    int k, i, j;
} level_t;

#define LEVEL_CHORDS_MIN 4
#define LEVEL_CHORDS_MAX 1024
/* consecutive points at most 10 degrees apart seen from the centre: a chord between points at
 * 1.01 R dips to 1.01 cos(5 deg) R = 1.006 R, outside Omega */
#define LEVEL_CHORD_COS 0.98480775301220796

static void level_point(const level_t *L, double s, double *w)
{
    double h = L->ha + s * (L->hb - L->ha), r = L->ra + s * (L->rb - L->ra), rho2 = r * r - h * h;
    double rho = rho2 > 0.0 ? sqrt(rho2) : 0.0, u = s < 0.5 ? 2.0 * s : 2.0 * s - 1.0, e[2], n;
    const double *e0 = s < 0.5 ? L->ea : L->em, *e1 = s < 0.5 ? L->em : L->eb;
    e[0] = (1.0 - u) * e0[0] + u * e1[0];
    e[1] = (1.0 - u) * e0[1] + u * e1[1];
    n = sqrt(e[0] * e[0] + e[1] * e[1]);
    w[L->k] = L->c[L->k] + h;
    w[L->i] = L->c[L->i] + rho * e[0] / n;
    w[L->j] = L->c[L->j] + rho * e[1] / n;
}

/* Sets up the level way from a to b and the number of its chords; 0 when there is none (both
 * ends on the axis, or no number of chords keeps it outside Omega). */
static int level_setup(const vp_planner_t *pl, const double *a, const double *b, level_t *L, int *nch)
{
    double ua[3], ub[3], la, lb, rs = SPHERE_ROUTE_GROW * pl->cfg.omega_radius, rhoa, rhob, tiny, n;
    int q, k = 2;
    for (q = 0; q < 2; q++)
        if (pl->cfg.axis_time[q] > pl->cfg.axis_time[k]) k = q;
    L->k = k;
    L->i = (k + 1) % 3;
    L->j = (k + 2) % 3;
    memcpy(L->c, pl->cfg.omega_center, sizeof L->c);
    vp_sub3(ua, a, L->c);
    vp_sub3(ub, b, L->c);
    la = sqrt(vp_dot3(ua, ua));
    lb = sqrt(vp_dot3(ub, ub));
    if (!(la > 0.0) || !(lb > 0.0)) return 0;
    /* each end as seen from the centre, on the route sphere where it lies inside it */
    L->ra = la < rs ? rs : la;
    L->rb = lb < rs ? rs : lb;
    L->ha = ua[k] * (L->ra / la);
    L->hb = ub[k] * (L->rb / lb);
    rhoa = sqrt(ua[L->i] * ua[L->i] + ua[L->j] * ua[L->j]);
    rhob = sqrt(ub[L->i] * ub[L->i] + ub[L->j] * ub[L->j]);
    tiny = LEN_REL_EPS * (la + lb);
    if (!(rhoa > tiny) && !(rhob > tiny)) return 0; /* both on the axis: the great circle */
    if (!(rhoa > tiny)) { ua[L->i] = ub[L->i]; ua[L->j] = ub[L->j]; rhoa = rhob; }
    if (!(rhob > tiny)) { ub[L->i] = ua[L->i]; ub[L->j] = ua[L->j]; rhob = rhoa; }
    L->ea[0] = ua[L->i] / rhoa; L->ea[1] = ua[L->j] / rhoa;
    L->eb[0] = ub[L->i] / rhob; L->eb[1] = ub[L->j] / rhob;
    L->em[0] = L->ea[0] + L->eb[0];
    L->em[1] = L->ea[1] + L->eb[1];
    n = sqrt(L->em[0] * L->em[0] + L->em[1] * L->em[1]);
    if (n > 1e-6) {
        L->em[0] /= n;
        L->em[1] /= n;
    } else {
        /* half a turn: round by the left of a */
        L->em[0] = -L->ea[1];
        L->em[1] = L->ea[0];
    }
    for (q = LEVEL_CHORDS_MIN; q <= LEVEL_CHORDS_MAX; q *= 2) {
        double p[3], w[3], dp[3], dw[3];
        int ok = 1, x;
        level_point(L, 0.0, p);
        for (x = 1; x <= q && ok; x++) {
            level_point(L, x / (double)q, w);
            vp_sub3(dp, p, L->c);
            vp_sub3(dw, w, L->c);
            ok = vp_dot3(dp, dw) >= LEVEL_CHORD_COS * sqrt(vp_dot3(dp, dp) * vp_dot3(dw, dw));
            memcpy(p, w, sizeof p);
        }
        if (ok) {
            *nch = q;
            return 1;
        }
    }
    return 0;
}

/* Measures (route == 0) or appends the level way from a to b; its machine time in *t. Returns
 * 0 when there is none, a piece of it would enter Omega, or (route != 0) the route has no room
 * for it (nothing appended then). */
static int level_route(vp_planner_t *pl, const double *a, const double *b, int route, double *t)
{
    level_t L;
    double prev[3], w[3];
    int n, q;
    if (!level_setup(pl, a, b, &L, &n)) return 0;
    if (route && (uint64_t)pl->route.n + (uint64_t)n + 2u > pl->route.cap) return 0;
    memcpy(prev, a, sizeof prev);
    *t = 0.0;
    for (q = 0; q <= n + 1; q++) {
        if (q <= n) level_point(&L, q / (double)n, w);
        else memcpy(w, b, sizeof w);
        if (vp_pl_seg_enters_omega(&pl->cfg, prev, w)) return 0;
        *t += vp_pl_move_time(pl, prev, w);
        if (route && vp_pl_route_push(pl, w, PROOF_OUTSIDE) != VP_OK) return 0;
        memcpy(prev, w, sizeof prev);
    }
    return 1;
}

/* Timed body mode round a ball Omega (no tubes): how far back along its line (unit dir, o on
 * dOmega, the line entering Omega there) a probe starts so that it stands on the route sphere
 * (1% beyond dOmega, where the level way and the great circle run): the head then joins its
 * way round Omega where it starts and leaves it where it ends, with no step out at the start
 * and back in at the end (a reversal of every moving axis: a stop at each, backlash taken up).
 * At most `most` (the range left), 0 when o is on that sphere already. */
VP_PL_API double vp_pl_start_back(const vp_planner_t *pl, const double *o, const double *dir, double most)
{
    double v[3], vd, v2, rt, disc, s;
    if (!vp_pl_timed(pl) || pl->cfg.omega_kind != VP_OMEGA_BALL || pl->cfg.min_feature > 0.0 || !(most > 0.0))
        return 0.0;
    rt = SPHERE_ROUTE_GROW * pl->cfg.omega_radius * (1.0 + 1e-9);
    vp_sub3(v, o, pl->cfg.omega_center);
    vd = vp_dot3(v, dir);
    v2 = vp_dot3(v, v);
    if (v2 >= rt * rt) return 0.0;
    /* |v - s dir| = rt: the root beyond o (v2 < rt^2, so the other is behind) */
    disc = vd * vd + (rt * rt - v2);
    s = vd + sqrt(disc);
    if (!(s > 0.0)) return 0.0;
    return s < most ? s : most;
}

/* The route's points from n0 on, after a: their machine time at top speed (timed != 0) or
 * their length */
static double route_sum(const vp_planner_t *pl, const double *a, uint32_t n0, int timed)
{
    double s = 0.0;
    uint32_t q;
    for (q = n0; q < pl->route.n; q++) {
        const double *w = pl->route.pts + 3 * (size_t)q;
        s += timed ? vp_pl_move_time(pl, a, w) : vp_dist3(a, w);
        a = w;
    }
    return s;
}

/* Body mode: the way round Omega outside it from a to b. Timed, of outside_route's (along
 * dOmega) and, for a ball, the level way, the one of less machine time (the level way on a
 * tie: it moves the slowest axis least). */
static int body_route(vp_planner_t *pl, const double *a, const double *b, double *len)
{
    uint32_t n0 = pl->route.n;
    double tl;
    VP_TRY(outside_route(pl, a, b, 0, len));
    if (!vp_pl_timed(pl) || pl->cfg.omega_kind != VP_OMEGA_BALL) return VP_OK;
    if (!level_route(pl, a, b, 0, &tl) || tl > route_sum(pl, a, n0, 1)) return VP_OK;
    pl->route.n = n0;
    if (!level_route(pl, a, b, 1, &tl)) {
        /* no room for the level way's points: the great circle's again */
        pl->route.n = n0;
        return outside_route(pl, a, b, 0, len);
    }
    pl->st.level_routes++;
    *len = route_sum(pl, a, n0, 0);
    return VP_OK;
}
#else
#define body_route(pl, a, b, len) outside_route(pl, a, b, 0, len)
#endif

#if VP_PL_CONTACTS
/* The device goes round Omega, outside it, to q on or outside dOmega (a re-scan's measuring
 * points, rescan.c): the route, and a record at q (pl->dev.at). The device stands on or outside
 * dOmega. */
VP_PL_API int vp_pl_route_outside(vp_planner_t *pl, const double *q)
{
    double len;
    uint32_t b;
    pl->route.n = pl->route.i = 0;
    pl->st.routes++;
    pl->route.from = pl->dev.at;
    pl->route.deferred = 0;
    pl->sc.to = NONE;
    VP_TRY(body_route(pl, pl->dev.pos, q, &len));
    VP_TRY(vp_pl_rec_new(pl, q, NONE, REC_OUT, &b));
    pl->dev.at = b;
    return VP_OK;
}
#endif

/* ---------- paths for the device ---------- */

/* first record on the prev chain of r that lies outside Omega (the chain's root) */
static uint32_t chain_root(const vp_planner_t *pl, uint32_t r)
{
    while (pl->pool.vrec[r].prev != r) r = pl->pool.vrec[r].prev;
    return r;
}

/* One step up the prev chain from record *x: its length added to *l, and with route != 0 its
 * upper end appended to the route. */
static int chain_step(vp_planner_t *pl, uint32_t *x, double *l, int route)
{
    uint32_t p = pl->pool.vrec[*x].prev;
    int st;
    if (rec_lost(pl, *x) || proof_withdrawn(pl, pl->pool.vrec[*x].proof)) return PL_UNREACHABLE;
    *l += vp_dist3(pl->pool.vrec[*x].p, pl->pool.vrec[p].p);
    if (route && (st = vp_pl_route_push(pl, pl->pool.vrec[p].p, pl->pool.vrec[*x].proof)) != VP_OK) return st;
    *x = p;
    return VP_OK;
}

/* Length of the prev-chain (tree) path from record a to record b, or to the outside point gp
 * when b == NONE. The paper's device travels these. With route != 0 the path is appended to
 * the route. */
static int tree_path(vp_planner_t *pl, uint32_t a, uint32_t b, const double *gp, int route,
                     double *len)
{
    uint32_t x = a, y = b, ny = 0, i;
    double l = 0.0, ol;
    const double *last;
    int st;
    *len = 0.0;
    if (rec_lost(pl, a) || (b != NONE && rec_lost(pl, b))) return PL_UNREACHABLE;
    if (b == NONE) {
        while (pl->pool.vrec[x].prev != x)
            if ((st = chain_step(pl, &x, &l, route)) != VP_OK) return st;
        st = outside_route(pl, pl->pool.vrec[x].p, gp, !route, &ol);
        *len = l + ol;
        return st;
    }
    /* climb to the common ancestor; y's half is kept to be walked downwards */
    while (pl->pool.vrec[x].depth > pl->pool.vrec[y].depth)
        if ((st = chain_step(pl, &x, &l, route)) != VP_OK) return st;
    while (pl->pool.vrec[y].depth > pl->pool.vrec[x].depth) {
        if (ny >= pl->route.cap_path) return VP_ENOMEM;
        if (rec_lost(pl, y) || proof_withdrawn(pl, pl->pool.vrec[y].proof)) return PL_UNREACHABLE;
        pl->route.path[ny++] = y;
        y = pl->pool.vrec[y].prev;
    }
    while (x != y && !(pl->pool.vrec[x].prev == x && pl->pool.vrec[y].prev == y)) {
        if ((st = chain_step(pl, &x, &l, route)) != VP_OK) return st;
        if (ny >= pl->route.cap_path) return VP_ENOMEM;
        if (rec_lost(pl, y) || proof_withdrawn(pl, pl->pool.vrec[y].proof)) return PL_UNREACHABLE;
        pl->route.path[ny++] = y;
        y = pl->pool.vrec[y].prev;
    }
    last = pl->pool.vrec[x].p;
    if (x != y) {
        st = outside_route(pl, pl->pool.vrec[x].p, pl->pool.vrec[y].p, !route, &ol);
        if (st != VP_OK) return st;
        l += ol;
        last = pl->pool.vrec[y].p;
    }
    for (i = ny; i-- > 0;) {
        l += vp_dist3(last, pl->pool.vrec[pl->route.path[i]].p);
        last = pl->pool.vrec[pl->route.path[i]].p;
        if (route && (st = vp_pl_route_push(pl, last, pl->pool.vrec[pl->route.path[i]].proof)) != VP_OK) return st;
    }
    *len = l;
    return VP_OK;
}

/* A* over the free graph (records joined by proven-free segments; records outside Omega joined
 * to each other around Omega). Goal: record b, or the outside point gp when b == NONE.
 * Returns VP_ENOMEM when the search budget runs out (the caller falls back to prev chains). */
#define VIRTUAL 0x80000000u

typedef struct astar {
    vp_planner_t *pl;
    uint32_t *open, nopen, stamp;
    const double *goal;
} astar_t;

static void astar_place(astar_t *s, uint32_t i, uint32_t n)
{
    s->open[i] = n;
    s->pl->pool.vrec[n].hpos = i;
}

static void astar_sift_up(astar_t *s, uint32_t i)
{
    uint32_t n = s->open[i];
    double f = s->pl->pool.vrec[n].f;
    while (i > 0) {
        uint32_t p = (i - 1) / 2;
        if (!(f < s->pl->pool.vrec[s->open[p]].f)) break;
        astar_place(s, i, s->open[p]);
        i = p;
    }
    astar_place(s, i, n);
}

static uint32_t astar_pop(astar_t *s)
{
    uint32_t top = s->open[0], i = 0, last;
    s->pl->pool.vrec[top].hpos = NONE;
    if (--s->nopen == 0) return top;
    last = s->open[s->nopen];
    for (;;) {
        uint32_t l = 2 * i + 1, r = l + 1, m;
        double fm = s->pl->pool.vrec[last].f;
        m = NONE;
        if (l < s->nopen && s->pl->pool.vrec[s->open[l]].f < fm) { m = l; fm = s->pl->pool.vrec[s->open[l]].f; }
        if (r < s->nopen && s->pl->pool.vrec[s->open[r]].f < fm) m = r;
        if (m == NONE) break;
        astar_place(s, i, s->open[m]);
        i = m;
    }
    astar_place(s, i, last);
    return top;
}

static int astar_relax(astar_t *s, uint32_t from, uint32_t nb, double g, uint32_t virt)
{
    vp_vrec_t *r = &s->pl->pool.vrec[nb];
    if (r->stamp == s->stamp && !(g < r->g)) return VP_OK;
    if (r->stamp != s->stamp) {
        r->stamp = s->stamp;
        r->hpos = NONE;
    }
    r->g = g;
    r->f = g + vp_dist3(r->p, s->goal);
    r->from = from | virt;
    if (r->hpos == NONE) {
        if (s->nopen >= s->pl->pool.cap_astar) return VP_ENOMEM;
        r->hpos = s->nopen++;
        s->open[r->hpos] = nb;
        if (s->nopen > s->pl->peak.astar) s->pl->peak.astar = s->nopen;
    }
    astar_sift_up(s, r->hpos);
    return VP_OK;
}

static int astar_path(vp_planner_t *pl, uint32_t a, uint32_t b, const double *gp, double *len,
                      uint32_t max_expansions)
{
    astar_t s;
    uint32_t broot = b != NONE ? chain_root(pl, b) : NONE, best_out = NONE, node = NONE, i;
    uint32_t expansions = 0, budget = pl->pool.cap_astar > max_expansions ? max_expansions : pl->pool.cap_astar;
    double best_out_cost = VP_PL_HUGE, ol;
    int st;
    s.pl = pl;
    s.open = pl->pool.astar;
    s.nopen = 0;
    s.stamp = ++pl->stamp;
    s.goal = b != NONE ? pl->pool.vrec[b].p : gp;
    pl->pool.vrec[a].stamp = s.stamp;
    pl->pool.vrec[a].g = 0.0;
    pl->pool.vrec[a].f = vp_dist3(pl->pool.vrec[a].p, s.goal);
    pl->pool.vrec[a].from = NONE;
    pl->pool.vrec[a].hpos = 0;
    s.open[s.nopen++] = a;
    while (s.nopen > 0) {
        uint32_t e, cur;
        if (best_out != NONE && best_out_cost <= pl->pool.vrec[s.open[0]].f) break;
        cur = astar_pop(&s);
        pl->st.astar_expansions++;
        if (cur == b) { node = b; break; }
        if (++expansions > budget) return VP_ENOMEM;
        for (e = pl->pool.vrec[cur].adj; e != NONE;) {
            const uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
            int isa = w[0] == cur;
            uint32_t nb = isa ? w[1] : w[0];
            if (!proof_withdrawn(pl, w[4])) {
                st = astar_relax(&s, cur, nb, pl->pool.vrec[cur].g + vp_dist3(pl->pool.vrec[cur].p, pl->pool.vrec[nb].p), 0);
                if (st != VP_OK) return st;
            }
            e = isa ? w[2] : w[3];
        }
        if (pl->pool.vrec[cur].flags & REC_OUT) {
            if (b == NONE) {
                if (outside_route(pl, pl->pool.vrec[cur].p, gp, 1, &ol) == VP_OK &&
                    pl->pool.vrec[cur].g + ol < best_out_cost) {
                    best_out_cost = pl->pool.vrec[cur].g + ol;
                    best_out = cur;
                }
            } else if (broot != cur && outside_route(pl, pl->pool.vrec[cur].p, pl->pool.vrec[broot].p, 1, &ol) == VP_OK) {
                st = astar_relax(&s, cur, broot, pl->pool.vrec[cur].g + ol, VIRTUAL);
                if (st != VP_OK) return st;
            }
        }
    }
    if (node == NONE && best_out == NONE) return VP_ENOMEM;
    /* walk back from the end, collecting the records, then emit them forwards */
    {
        uint32_t n = node != NONE ? node : best_out, np = 0;
        double l = 0.0;
        const double *last = pl->pool.vrec[a].p;
        while (n != NONE) {
            if (np >= pl->route.cap_path) return VP_ENOMEM;
            pl->route.path[np++] = n;
            if (np > pl->peak.path) pl->peak.path = np;
            n = pl->pool.vrec[n].from == NONE ? NONE : (pl->pool.vrec[n].from & ~VIRTUAL);
        }
        for (i = np - 1; i-- > 0;) {
            uint32_t r = pl->route.path[i];
            if (pl->pool.vrec[r].from & VIRTUAL) {
                st = outside_route(pl, last, pl->pool.vrec[r].p, 0, &ol);
                l += ol;
            } else {
                st = vp_pl_route_push(pl, pl->pool.vrec[r].p, edge_proof(pl, pl->route.path[i + 1], r));
                l += vp_dist3(last, pl->pool.vrec[r].p);
            }
            if (st != VP_OK) return st;
            last = pl->pool.vrec[r].p;
        }
        if (node == NONE) {
            st = outside_route(pl, last, gp, 0, &ol);
            if (st != VP_OK) return st;
            l += ol;
        }
        *len = l;
    }
    return VP_OK;
}

/* A* budgets, in expanded records: a search within the rangefinder's reach that needs more than
 * SEARCH_LOCAL is a detour, and one straight probe is cheaper; SEARCH_FULL bounds the work of
 * one route (the prev chains are always a way). */
#define SEARCH_LOCAL 256u
#define SEARCH_FULL 4096u
/* a found route longer than this many times the straight distance (plus 2 eps) to a target
 * within reach is a detour worth one probe of the straight way */
#define SHORTCUT_DETOUR 3.0

/* The full route from record a to record b (search, else prev chains), into the route buffer. */
VP_PL_API int vp_pl_route_full(vp_planner_t *pl, uint32_t a, uint32_t b)
{
    double l;
    int st;
    pl->route.n = pl->route.i = 0;
    st = astar_path(pl, a, b, NULL, &l, SEARCH_FULL);
    if (st == VP_OK) return VP_OK;
    pl->route.n = 0;
    pl->st.astar_fallbacks++;
    return tree_path(pl, a, b, NULL, 1, &l);
}

/* 1 if one probe from a reaches b: no farther than the rangefinder's maximum range */
static int in_reach(const vp_planner_t *pl, const double *a, const double *b)
{
    return !(pl->cfg.max_range > 0.0) || vp_dist3(a, b) <= pl->cfg.max_range;
}

#if VP_PL_TUBES
/* Body mode with tubes: the length of the way from the device to `to` (on dOmega) without a
 * new tube: out along the tube it came in by, then round Omega outside it. */
VP_PL_API double vp_pl_tube_way_out(vp_planner_t *pl, const double *to)
{
    const double *p = pl->pool.vrec[pl->dev.at].p;
    double l = 0.0, out = 0.0;
    if (pl->tube.inside) {
        out = vp_dist3(p, pl->tube.exit);
        p = pl->tube.exit;
    }
    if (outside_route(pl, p, to, 1, &l) != VP_OK) return VP_PL_HUGE;
    return out + l;
}

/* Body mode with tubes (tube.c): from `from` to `to` straight when that tube is proven;
 * otherwise out of Omega (back along the tube the device came in by), round Omega outside it,
 * and in along the goal's own tube (tube.goal_exit, proven by task_start) when the goal is
 * inside Omega. */
static int tube_route(vp_planner_t *pl, const double *from, const double *to, double *len)
{
    vp_pl_tube_t *T = &pl->tube;
    double cur[3], ol = 0.0;
    int to_in = T->goal_in;
    T->goal_in = 0;
    *len = 0.0;
    if (T->on && vp_pl_tube_free(pl, from, to)) {
        VP_TRY(vp_pl_route_push(pl, to, PROOF_TUBE));
        *len = vp_dist3(from, to);
    } else {
        memcpy(cur, from, sizeof cur);
        if (T->inside) {
            VP_TRY(vp_pl_route_push(pl, T->exit, PROOF_TUBE));
            *len += vp_dist3(cur, T->exit);
            memcpy(cur, T->exit, sizeof cur);
        }
        VP_TRY(body_route(pl, cur, to_in ? T->goal_exit : to, &ol));
        *len += ol;
        if (to_in) {
            VP_TRY(vp_pl_route_push(pl, to, PROOF_TUBE));
            *len += vp_dist3(T->goal_exit, to);
        }
    }
    T->inside = to_in;
    if (to_in) memcpy(T->exit, T->goal_exit, sizeof T->exit);
    return VP_OK;
}
#endif

/* Plans the device's route from where it stands to record b, or to the outside point gp when
 * b == NONE (a record is then made there). Sets pl->dev.at to the destination record. */
VP_PL_API int vp_pl_plan_route(vp_planner_t *pl, uint32_t b, const double *gp)
{
    double tl = 0.0, al = 0.0;
    int st;
    pl->route.n = pl->route.i = 0;
    pl->st.routes++;
    pl->route.from = pl->dev.at;
    pl->sc.to = NONE;
    pl->route.deferred = 0;
    if (b != NONE && b == pl->dev.at) return VP_OK;
    if (pl->cfg.clearance > 0.0) {
        /* a device with a body never enters Omega: every probe starts on or beyond dOmega */
        if (b != NONE && !(pl->pool.vrec[b].flags & REC_OUT)) return VP_EDEGEN;
#if VP_PL_TUBES
        if (pl->tube.on || pl->tube.inside) {
            /* a device with a body enters Omega only along tubes proven free */
            const double *to = b != NONE ? pl->pool.vrec[b].p : gp;
            int in = pl->tube.goal_in;
            VP_TRY(tube_route(pl, pl->pool.vrec[pl->dev.at].p, to, &tl));
            if (b == NONE && (st = vp_pl_rec_new(pl, gp, NONE, in ? 0u : REC_OUT, &b)) != VP_OK) return st;
            pl->dev.at = b;
            return VP_OK;
        }
#endif
        st = body_route(pl, pl->pool.vrec[pl->dev.at].p, b != NONE ? pl->pool.vrec[b].p : gp, &tl);
        if (st != VP_OK) return st;
        if (b == NONE && (st = vp_pl_rec_new(pl, gp, NONE, REC_OUT, &b)) != VP_OK) return st;
        pl->dev.at = b;
        return VP_OK;
    }
    if (!(pl->cfg.flags & VP_PLAN_PREV_CHAINS)) {
        /* what the same move costs along prev chains (reported beside the travel) */
        st = tree_path(pl, pl->dev.at, b, gp, 0, &tl);
        if (st < 0) return st;
        pl->st.travel_prev_chains += tl;
    }
    if (!(pl->cfg.flags & VP_PLAN_PREV_CHAINS) && b != NONE) {
        /* the goal one free edge away: no search */
        uint32_t e, cur = pl->dev.at;
        for (e = pl->pool.vrec[cur].adj; e != NONE;) {
            const uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
            int isa = w[0] == cur;
            if ((isa ? w[1] : w[0]) == b && !proof_withdrawn(pl, w[4])) {
                pl->dev.at = b;
                pl->st.direct_routes++;
                return vp_pl_route_push(pl, pl->pool.vrec[b].p, w[4]);
            }
            e = isa ? w[2] : w[3];
        }
    }
    if (!(pl->cfg.flags & VP_PLAN_PREV_CHAINS)) {
        /* a shortcut is one probe along the straight way: only within the rangefinder's reach */
        int cheap = b != NONE && !(pl->cfg.flags & VP_PLAN_PAPER) && in_reach(pl, pl->pool.vrec[pl->dev.at].p, pl->pool.vrec[b].p);
        st = astar_path(pl, pl->dev.at, b, gp, &al, cheap ? SEARCH_LOCAL : SEARCH_FULL);
        if (st != VP_OK && cheap) {
            /* no short way in the free graph: probe the straight line first; the full search
             * runs only if that probe hits */
            pl->route.n = 0;
            pl->sc.to = b;
            pl->route.deferred = 1;
            pl->dev.at = b;
            return VP_OK;
        }
        if (st != VP_OK) { pl->route.n = 0; pl->st.astar_fallbacks++; }
    } else {
        st = VP_ENOMEM;
    }
    if (!(pl->cfg.flags & (VP_PLAN_PREV_CHAINS | VP_PLAN_PAPER)) && b != NONE) {
        /* a long detour to a near target: first probe the straight way (one probe can save
         * many moves); the route found stays the plan if the probe hits */
        double d = vp_dist3(pl->pool.vrec[pl->dev.at].p, pl->pool.vrec[b].p);
        double known = st == VP_OK ? al : VP_PL_HUGE;
        if (known > SHORTCUT_DETOUR * d + 2.0 * pl->cfg.eps && d > 0.0 && in_reach(pl, pl->pool.vrec[pl->dev.at].p, pl->pool.vrec[b].p))
            pl->sc.to = b;
    }
    if (st != VP_OK) {
        /* the prev chains: always a way (and the only one with VP_PLAN_PREV_CHAINS) */
        st = tree_path(pl, pl->dev.at, b, gp, 1, &tl);
        if (st == PL_UNREACHABLE) {
            /* a contact withdrew the proofs of every known way there */
            pl->route.n = 0;
            pl->sc.to = NONE;
            return st;
        }
        if (st != VP_OK) return st;
        if (pl->cfg.flags & VP_PLAN_PREV_CHAINS) pl->st.travel_prev_chains += tl;
    }
    if (b == NONE) {
        st = vp_pl_rec_new(pl, gp, NONE, REC_OUT, &b);
        if (st != VP_OK) return st;
    }
    pl->dev.at = b;
    return VP_OK;
}
