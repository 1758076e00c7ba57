/* vp_planner — the probe planner of "Learning smooth objects by probing", made step-driven.
 *
 * Vocabulary (the paper's):
 *   Voronoi vertex    the circumcentre of a Delaunay tet (its dual); ghost tets stand for the
 *                     infinite vertices.
 *   active vertex     one the device can reach: it has a free path (prev links) to R^3 \ Omega.
 *                     Active vertices inside Omega get a record (vrec) that is kept after the
 *                     tet dies ("former Voronoi vertices"), so every stored path stays valid.
 *   detect_access     probing the Voronoi edges around an active vertex: a hit adds the dual
 *                     facet to Del_v|S(E) with its ball; a miss proves the edge free and makes
 *                     the other end active. Here it is a stack of probe tasks, not a recursion.
 *   bad ball          a surface Delaunay ball of radius > eps; the largest is refined first
 *                     (VP_PLAN_LARGEST) or the largest near the device.
 *   persistent facet  the tiny seed triangle: its ball (<= eps/3) keeps Del_v|S non-empty.
 *
 * Beyond the paper: a probe result belongs to the side it was probed from (one status per
 * (tet, facet) side); a facet on the boundary of an insertion's cavity keeps its result when its
 * shortened Voronoi edge still holds it; without VP_PLAN_PAPER an edge between two vertices
 * already known free is not probed (it cannot be a facet of the final mesh, whose dual edges
 * cross S once); holes left at the end are closed by probing around them; motion follows
 * shortest known-free paths (A*) instead of prev chains.
 */
#include <math.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_pred.h"
#include "vp_vec3.h"

#define NONE VP_DT_NONE
#define VREC_OUT 0xFFFFFFFEu /* active, outside Omega or infinite: no record needed */

/* side status of a (tet, facet) pair, low 2 bits */
#define SIDE_UNKNOWN 0u
#define SIDE_FREE    1u  /* the whole dual edge is free */
#define SIDE_HIT     2u  /* probed from this side: free up to the ball centre (facet record) */
#define SIDE_BEHIND  3u  /* probed from the other side and hit: this end is beyond S */
#define SIDE_MASK    3u
#define SIDE_QUEUED  4u  /* a probe task is pending */
#define SIDE_FORCED  8u  /* probed although both ends are known free (closing a hole) */
#define SIDE_BLOCKED 16u /* the probe from this end saw something too close to measure */

/* record flags */
#define REC_OUT 1u       /* on or outside dOmega: joins every other such record outside */

/* facet record flags */
#define FREC_FLIP 1u     /* (v0,v1,v2) is oriented inward: swap two for output */
#define FREC_STUCK 2u    /* its centre could not be inserted: not refined again */
#define FREC_DOUBLE 4u   /* hit from both ends: the dual edge crosses S twice */

/* phases */
enum { PH_SEED = 0, PH_START, PH_RUN, PH_CLOSE, PH_COMPONENTS, PH_RESEED, PH_DONE };


struct vp_vrec {
    double p[3];
    double g, f;       /* path search: cost so far, and plus the straight distance left */
    uint32_t prev;     /* previous record on the free path (itself: a root, outside Omega) */
    uint32_t adj;      /* first free edge at this record */
    uint32_t depth;    /* hops to the root */
    uint32_t flags;
    uint32_t stamp, from; /* path search bookkeeping */
    uint32_t hpos;        /* place in the search's open heap, NONE when closed */
    uint32_t proof;       /* the proof that the segment from prev to here is free */
};

struct vp_frec {
    uint32_t v[3];     /* sorted; v[0] == NONE: free slot, v[1] = next free */
    uint32_t heap;     /* index in the bad-ball heap or NONE */
    uint32_t flags;
    uint32_t hint;     /* a tet that had the facet (checked before use) */
    double c[3];       /* ball centre (the hit) */
    double r;          /* ball radius */
    uint32_t proof;    /* the probe that found the ball: free up to its centre, less the noise */
};


/* ---------- Omega ---------- */

static void omega_center(const vp_planner_config_t *c, double *o)
{
    int k;
    for (k = 0; k < 3; k++)
        o[k] = c->omega_kind == VP_OMEGA_BALL ? c->omega_center[k] : 0.5 * (c->omega_lo[k] + c->omega_hi[k]);
}

static double omega_circumradius(const vp_planner_config_t *c)
{
    if (c->omega_kind == VP_OMEGA_BALL) return c->omega_radius;
    return 0.5 * sqrt((c->omega_hi[0] - c->omega_lo[0]) * (c->omega_hi[0] - c->omega_lo[0]) +
                      (c->omega_hi[1] - c->omega_lo[1]) * (c->omega_hi[1] - c->omega_lo[1]) +
                      (c->omega_hi[2] - c->omega_lo[2]) * (c->omega_hi[2] - c->omega_lo[2]));
}

/* strictly inside Omega */
static int omega_inside(const vp_planner_config_t *c, const double *p)
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
static int omega_clip(const vp_planner_config_t *c, const double *a, const double *dir, double len,
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
static int seg_enters_omega(const vp_planner_config_t *c, const double *a, const double *b)
{
    double d[3], len, t0, t1;
    vp_sub3(d, b, a);
    len = sqrt(vp_dot3(d, d));
    if (!(len > 0.0)) return omega_inside(c, a);
    d[0] /= len; d[1] /= len; d[2] /= len;
    return omega_clip(c, a, d, len, &t0, &t1) && t1 - t0 > 1e-12 * (1.0 + len);
}

/* ---------- proofs of free space ----------
 * The device moves only along a segment that names its proof: the free part of a probe (a
 * chain of probes along one ray, for a range-limited rangefinder), or PROOF_OUTSIDE (outside
 * Omega, assumption A2). Every free-graph edge and every route step carries one, checked
 * geometrically when the edge is made and again when the MOVE is issued. The paper's
 * inferences (a shrunken Voronoi edge stays free, a kept ball) only propose a proof: on
 * objects where they fail (flat faces, sharp edges: one crossing per edge no longer holds)
 * the check refuses the segment, and it is never travelled. */
#define PROOF_NONE      0xFFFFFFFFu
#define PROOF_OUTSIDE   0xFFFFFFFDu
#define PROOF_CHAIN_MAX 64u /* pieces of one walked ray looked at */
/* free-graph edges: FEDGE_WORDS words each: a, b, next at a, next at b, proof */
#define FEDGE_WORDS 5u
#define KPAY 6u /* payload words of a tet: record, sides, four side proofs */
#define PROOF_SHARE 16u /* of the arena's 100 units: the proofs (one per probe that proved something) */

static int proof_new(vp_planner_t *pl, const double *o, const double *d, double len, uint32_t prev,
                     uint32_t *out)
{
    vp_proof_t *q;
    *out = PROOF_NONE;
    if (!(len > 0.0)) return VP_OK;
    if (pl->pool.nproof >= pl->pool.cap_proof) return VP_ENOMEM;
    q = &pl->pool.proof[pl->pool.nproof];
    memcpy(q->o, o, sizeof q->o);
    memcpy(q->d, d, sizeof q->d);
    q->len = len;
    q->prev = prev;
    *out = pl->pool.nproof++;
    return VP_OK;
}

/* 1 if proof id shows every point of [a, b] free: within pl->ptol of the ray and of its free
 * part (the union of the pieces of its chain), or the whole segment outside Omega. */
static int proof_covers(const vp_planner_t *pl, uint32_t id, const double *a, const double *b)
{
    double lo[PROOF_CHAIN_MAX], hi[PROOF_CHAIN_MAX], sa, sb, need0, need1, cur, x[3], tol = pl->ptol;
    const vp_proof_t *p;
    uint32_t n = 0, i, j;
    int k;
    if (id == PROOF_OUTSIDE) return !seg_enters_omega(&pl->cfg, a, b);
    if (id >= pl->pool.nproof) return 0;
    p = &pl->pool.proof[id];
    /* both ends on the ray's line */
    vp_sub3(x, a, p->o);
    sa = vp_dot3(x, p->d);
    for (k = 0; k < 3; k++) x[k] -= sa * p->d[k];
    if (!(vp_dot3(x, x) <= tol * tol)) return 0;
    vp_sub3(x, b, p->o);
    sb = vp_dot3(x, p->d);
    for (k = 0; k < 3; k++) x[k] -= sb * p->d[k];
    if (!(vp_dot3(x, x) <= tol * tol)) return 0;
    need0 = sa < sb ? sa : sb;
    need1 = sa < sb ? sb : sa;
    /* the free intervals of the chain on that line */
    for (i = id; i != PROOF_NONE && i < pl->pool.nproof && n < PROOF_CHAIN_MAX; i = pl->pool.proof[i].prev) {
        const vp_proof_t *q = &pl->pool.proof[i];
        double s0;
        if (!(vp_dot3(q->d, p->d) > 1.0 - 1e-12)) break;
        vp_sub3(x, q->o, p->o);
        s0 = vp_dot3(x, p->d);
        for (k = 0; k < 3; k++) x[k] -= s0 * p->d[k];
        if (!(vp_dot3(x, x) <= tol * tol)) break;
        /* insertion by start */
        for (j = n; j > 0 && lo[j - 1] > s0; j--) { lo[j] = lo[j - 1]; hi[j] = hi[j - 1]; }
        lo[j] = s0;
        hi[j] = s0 + q->len;
        n++;
    }
    cur = need0;
    for (i = 0; i < n; i++) {
        if (lo[i] > cur + tol) break;
        if (hi[i] > cur) cur = hi[i];
    }
    return n > 0 && lo[0] <= need0 + tol && cur >= need1 - tol;
}

/* The proof made by the current probe's result (once per probe): the free part of its ray. */
static int probe_proof(vp_planner_t *pl, const vp_probe_result_t *res, uint32_t *out)
{
    double len;
    int st;
    if (pl->probe.cur_proof != PROOF_NONE) { *out = pl->probe.cur_proof; return VP_OK; }
    *out = PROOF_NONE;
    if (res->hit == VP_PROBE_TOO_CLOSE) return VP_OK;
    len = res->hit ? res->dist - pl->cfg.noise_tol : pl->dev.iss_range;
    if (res->hit && len > pl->dev.iss_range) len = pl->dev.iss_range;
    st = proof_new(pl, pl->dev.iss_o, pl->dev.iss_d, len, pl->probe.chain_proof, out);
    if (st == VP_OK) pl->probe.cur_proof = *out;
    return st;
}

/* ---------- tet payload: word 0 = record, word 1 = four side bytes, words 2-5 the proof of
 * each free side ---------- */

static uint32_t *pay(const vp_planner_t *pl, uint32_t t) { return (uint32_t *)vp_dt_payload(&pl->dt, t); }
static uint32_t tet_rec(const vp_planner_t *pl, uint32_t t) { return pay(pl, t)[0]; }
static unsigned side_get(const vp_planner_t *pl, uint32_t t, int f)
{ return (pay(pl, t)[1] >> (8 * f)) & 0xFFu; }
static void side_set(vp_planner_t *pl, uint32_t t, int f, unsigned s)
{
    uint32_t *w = pay(pl, t) + 1;
    *w = (*w & ~(0xFFu << (8 * f))) | ((uint32_t)(s & 0xFFu) << (8 * f));
}
static int tet_active(const vp_planner_t *pl, uint32_t t) { return tet_rec(pl, t) != NONE; }
/* side f of t (its whole Voronoi edge) proven free by `proof`; other flags kept */
static void side_free(vp_planner_t *pl, uint32_t t, int f, uint32_t proof)
{
    side_set(pl, t, f, (side_get(pl, t, f) & ~SIDE_MASK) | SIDE_FREE);
    pay(pl, t)[2 + f] = proof;
}
static uint32_t side_proof(const vp_planner_t *pl, uint32_t t, int f) { return pay(pl, t)[2 + f]; }

/* ---------- arena ---------- */

static void *carve(unsigned char **cur, unsigned char *end, size_t bytes)
{
    uintptr_t p = ((uintptr_t)*cur + 7u) & ~(uintptr_t)7u;
    if (p + bytes > (uintptr_t)end || p + bytes < p) return NULL;
    *cur = (unsigned char *)(p + bytes);
    return (void *)p;
}

/* Arena in use at most: the triangulation's high-water mark plus every pool's. The planner's
 * split of the arena is fixed, so a session needs each pool's peak to fit its share. */
static void note_peak(vp_planner_t *pl)
{
    size_t used;
    uint32_t hash_need = 1;
    if (pl->pool.ntask > pl->peak.task) pl->peak.task = pl->pool.ntask;
    if (pl->pool.nheap > pl->peak.heap) pl->peak.heap = pl->pool.nheap;
    if (pl->route.n > pl->peak.route) pl->peak.route = pl->route.n;
    while (hash_need < 2u * pl->pool.nfacets + 16u) hash_need <<= 1;
    used = vp_dt_bytes_used(&pl->dt) + (size_t)pl->pool.nvrec * sizeof(vp_vrec_t) +
           (size_t)pl->pool.nfedge * 4u * FEDGE_WORDS + (size_t)pl->pool.nproof * sizeof(vp_proof_t) + (size_t)pl->pool.nfrec * sizeof(vp_frec_t) + (size_t)hash_need * 4u +
           (size_t)pl->peak.heap * 4u + (size_t)pl->peak.task * sizeof(vp_task_t) +
           (size_t)pl->peak.route * 24u + (size_t)pl->peak.astar * 4u + (size_t)pl->peak.path * 4u;
    if (used > pl->st.arena_peak) pl->st.arena_peak = used;
}

/* ---------- records and the free graph ---------- */

static int rec_new(vp_planner_t *pl, const double *p, uint32_t prev, uint32_t flags, uint32_t *out)
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
static int edge_add(vp_planner_t *pl, uint32_t a, uint32_t b, uint32_t proof)
{
    uint32_t e, *w;
    if (a == b) return VP_OK;
    if (!proof_covers(pl, proof, pl->pool.vrec[a].p, pl->pool.vrec[b].p)) {
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
    return VP_OK;
}

/* A record reached from `prev` along the segment `proof` shows free. *out = NONE (and nothing
 * made) when the proof does not cover it. */
static int rec_link(vp_planner_t *pl, const double *p, uint32_t prev, uint32_t flags, uint32_t proof,
                    uint32_t *out)
{
    int st;
    *out = NONE;
    if (prev != NONE && !proof_covers(pl, proof, pl->pool.vrec[prev].p, p)) {
        pl->st.unproven++;
        return VP_OK;
    }
    st = rec_new(pl, p, prev, flags, out);
    if (st != VP_OK) return st;
    if (prev != NONE) {
        pl->pool.vrec[*out].proof = proof;
        st = edge_add(pl, prev, *out, proof);
        if (st != VP_OK) { pl->pool.nvrec--; *out = NONE; return st; }
    }
    return VP_OK;
}

/* the proof of a free edge between records a and b that covers them, or PROOF_NONE */
static uint32_t edge_proof(const vp_planner_t *pl, uint32_t a, uint32_t b)
{
    uint32_t e;
    for (e = pl->pool.vrec[a].adj; e != NONE;) {
        const uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
        int isa = w[0] == a;
        if ((isa ? w[1] : w[0]) == b) return w[4];
        e = isa ? w[2] : w[3];
    }
    return PROOF_NONE;
}

/* ---------- routes outside Omega ---------- */

/* Appends a step to the route, with its proof of freedom. */
static int route_push(vp_planner_t *pl, const double *p, uint32_t proof)
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
static double clamp_range(const vp_planner_t *pl, double range)
{
    return pl->cfg.max_range > 0.0 && range > pl->cfg.max_range ? pl->cfg.max_range : range;
}

/* 1 if the current probe was cut short by the rangefinder's reach */
static int probe_limited(const vp_planner_t *pl)
{
    return pl->probe.range < pl->probe.full - 1e-12 * (1.0 + pl->probe.full);
}

/* A range-limited probe missed: its segment is free (proof). The device walks from record
 * `from` to the segment's end (a new record, pl->dev.at) to probe on; the step costs the same
 * under either rule. */
static int walk_on(vp_planner_t *pl, uint32_t from, uint32_t proof, double e[3])
{
    uint32_t r;
    int k, st;
    for (k = 0; k < 3; k++) e[k] = pl->probe.origin[k] + pl->probe.range * pl->probe.dir[k];
    if ((st = rec_link(pl, e, from, 0, proof, &r)) != VP_OK) return st;
    if (r == NONE) return VP_EUNSAFE; /* the probe's own end: never */
    pl->st.travel_prev_chains += pl->probe.range;
    pl->route.n = pl->route.i = 0;
    if ((st = route_push(pl, e, proof)) != VP_OK) return st;
    pl->dev.at = r;
    return VP_OK;
}

/* Moves m (the midpoint of a chord with unit direction u) out of Omega: along the part of
 * (m - centre) perpendicular to the chord, to delta beyond dOmega. */
static void push_out(const vp_planner_config_t *c, double *m, const double *u, double delta)
{
    double o[3], d[3], t0, t1, s;
    int k;
    omega_center(c, o);
    vp_sub3(d, m, o);
    s = vp_dot3(d, u);
    for (k = 0; k < 3; k++) d[k] -= s * u[k];
    if (!vp_normalize3(d)) {
        double t[3] = { 0, 0, 1 };
        if (fabs(u[2]) > 0.8) { t[0] = 1; t[2] = 0; }
        vp_cross3(d, u, t);
        vp_normalize3(d);
    }
    if (!omega_clip(c, m, d, 1e300, &t0, &t1)) return;
    for (k = 0; k < 3; k++) m[k] += (t1 + delta) * d[k];
}

/* The fallback: out to a sphere around Omega's circumsphere, along the great circle in chords
 * of at most 15 degrees (they stay outside the circumsphere), and back in. */
static int sphere_route(vp_planner_t *pl, const double *a, const double *b, int dry, double *len)
{
    double c[3], ra, rb, rs, ua[3], ub[3], um[3], prev[3];
    int i, k, st, half;
    omega_center(&pl->cfg, c);
    rs = 1.01 * omega_circumradius(&pl->cfg);
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
        for (i = half; i <= 8; i++) {
            double s = i / 8.0, w[3], r = ra + (rb - ra) * 0.5 * (half + s);
            for (k = 0; k < 3; k++) w[k] = (1.0 - s) * u0[k] + s * u1[k];
            vp_normalize3(w);
            for (k = 0; k < 3; k++) w[k] = c[k] + r * w[k];
            *len += vp_dist3(prev, w);
            if (!dry && (st = route_push(pl, w, PROOF_OUTSIDE)) != VP_OK) return st;
            prev[0] = w[0]; prev[1] = w[1]; prev[2] = w[2];
        }
    }
    *len += vp_dist3(prev, b);
    return dry ? VP_OK : route_push(pl, b, PROOF_OUTSIDE);
}

/* Appends a path between two points on or outside dOmega that stays outside Omega: the
 * straight segment where it does not enter Omega, otherwise its midpoint pushed out of Omega
 * (sideways to the chord), recursively with an explicit stack of bounded depth, so the path
 * hugs dOmega. If that does not settle, the way round Omega's circumsphere. *len gets its
 * length; with dry != 0 it only measures. */
#define ROUTE_DEPTH 10
static int outside_route(vp_planner_t *pl, const double *a, const double *b, int dry, double *len)
{
    double stack[ROUTE_DEPTH + 2][3], cur[3], delta = 0.01 * omega_circumradius(&pl->cfg);
    int depth[ROUTE_DEPTH + 2], n = 0, st;
    uint32_t nroute0 = pl->route.n;
    *len = 0.0;
    memcpy(cur, a, sizeof cur);
    memcpy(stack[n], b, sizeof stack[n]);
    depth[n++] = 0;
    while (n > 0) {
        double *y = stack[n - 1], m[3], u[3];
        int d = depth[n - 1], k;
        if (!seg_enters_omega(&pl->cfg, cur, y)) {
            *len += vp_dist3(cur, y);
            if (!dry && (st = route_push(pl, y, PROOF_OUTSIDE)) != VP_OK) return st;
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

/* ---------- restricted facets: hash on the sorted vertex triple ---------- */

#define HASH_EMPTY 0xFFFFFFFFu
#define HASH_TOMB  0xFFFFFFFEu

static void sort3(uint32_t *v)
{
    uint32_t t;
    if (v[0] > v[1]) { t = v[0]; v[0] = v[1]; v[1] = t; }
    if (v[1] > v[2]) { t = v[1]; v[1] = v[2]; v[2] = t; }
    if (v[0] > v[1]) { t = v[0]; v[0] = v[1]; v[1] = t; }
}

static uint32_t key_hash(const uint32_t *v)
{
    uint64_t h = (uint64_t)v[0] * 0x9E3779B97F4A7C15ull ^ (uint64_t)v[1] * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)v[2] * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    return (uint32_t)(h * 0xBF58476D1CE4E5B9ull >> 32);
}

/* slot of key v (sorted) in the hash, or of the first free place when absent (*found = 0) */
static uint32_t fhash_find(const vp_planner_t *pl, const uint32_t *v, int *found)
{
    uint32_t h = key_hash(v) & pl->pool.hash_mask, first_free = NONE;
    for (;;) {
        uint32_t e = pl->pool.fhash[h];
        if (e == HASH_EMPTY) {
            *found = 0;
            return first_free != NONE ? first_free : h;
        }
        if (e == HASH_TOMB) {
            if (first_free == NONE) first_free = h;
        } else if (pl->pool.frec[e].v[0] == v[0] && pl->pool.frec[e].v[1] == v[1] && pl->pool.frec[e].v[2] == v[2]) {
            *found = 1;
            return h;
        }
        h = (h + 1) & pl->pool.hash_mask;
    }
}

static uint32_t frec_lookup(const vp_planner_t *pl, const uint32_t *fv)
{
    uint32_t v[3];
    int found;
    uint32_t h;
    v[0] = fv[0]; v[1] = fv[1]; v[2] = fv[2];
    sort3(v);
    h = fhash_find(pl, v, &found);
    return found ? pl->pool.fhash[h] : NONE;
}

/* ---------- the bad-ball heap (max on radius) ---------- */

static void heap_swap(vp_planner_t *pl, uint32_t i, uint32_t j)
{
    uint32_t a = pl->pool.heap[i], b = pl->pool.heap[j];
    pl->pool.heap[i] = b; pl->pool.heap[j] = a;
    pl->pool.frec[b].heap = i;
    pl->pool.frec[a].heap = j;
}

static void heap_up(vp_planner_t *pl, uint32_t i)
{
    while (i > 0) {
        uint32_t p = (i - 1) / 2;
        if (!(pl->pool.frec[pl->pool.heap[p]].r < pl->pool.frec[pl->pool.heap[i]].r)) break;
        heap_swap(pl, i, p);
        i = p;
    }
}

static void heap_down(vp_planner_t *pl, uint32_t i)
{
    for (;;) {
        uint32_t l = 2 * i + 1, r = l + 1, m = i;
        if (l < pl->pool.nheap && pl->pool.frec[pl->pool.heap[l]].r > pl->pool.frec[pl->pool.heap[m]].r) m = l;
        if (r < pl->pool.nheap && pl->pool.frec[pl->pool.heap[r]].r > pl->pool.frec[pl->pool.heap[m]].r) m = r;
        if (m == i) break;
        heap_swap(pl, i, m);
        i = m;
    }
}

static int heap_push(vp_planner_t *pl, uint32_t k)
{
    if (pl->pool.nheap >= pl->pool.cap_heap) return VP_ENOMEM;
    pl->pool.heap[pl->pool.nheap] = k;
    pl->pool.frec[k].heap = pl->pool.nheap++;
    heap_up(pl, pl->pool.nheap - 1);
    return VP_OK;
}

static void heap_remove(vp_planner_t *pl, uint32_t k)
{
    uint32_t i = pl->pool.frec[k].heap;
    if (i == NONE) return;
    pl->pool.nheap--;
    if (i != pl->pool.nheap) {
        heap_swap(pl, i, pl->pool.nheap);
        heap_down(pl, i);
        heap_up(pl, i);
    }
    pl->pool.frec[k].heap = NONE;
}

/* ---------- facet records ---------- */

/* Rebuilds the hash from the live records when deleted slots pile up (they lengthen every
 * probe sequence). */
static void fhash_rebuild(vp_planner_t *pl)
{
    uint32_t i;
    for (i = 0; i <= pl->pool.hash_mask; i++) pl->pool.fhash[i] = HASH_EMPTY;
    for (i = 0; i < pl->pool.nfrec; i++) {
        int found;
        if (pl->pool.frec[i].v[0] == NONE) continue;
        pl->pool.fhash[fhash_find(pl, pl->pool.frec[i].v, &found)] = i;
    }
    pl->pool.ntomb = 0;
}

static void frec_delete(vp_planner_t *pl, uint32_t k)
{
    int found;
    uint32_t h = fhash_find(pl, pl->pool.frec[k].v, &found);
    if (found) {
        pl->pool.fhash[h] = HASH_TOMB;
        if (++pl->pool.ntomb > (pl->pool.hash_mask + 1u) / 4u) pl->pool.fhash_dirty = 1;
    }
    heap_remove(pl, k);
    pl->pool.frec[k].v[0] = NONE;
    pl->pool.frec[k].v[1] = pl->pool.frec_free;
    pl->pool.frec_free = k;
    pl->pool.nfacets--;
}

/* With an angle bound: the smallest angle of the triangle is below it, i.e. its shortest edge
 * is shorter than 2 R sin(bound), R its circumradius (Chew's criterion, as CGAL's mesher has). */
static int facet_too_sharp(const vp_planner_t *pl, const uint32_t *v)
{
    const double *a, *b, *c;
    double ab[3], ac[3], bc[3], n[3], la, lb, lc, lmin, area2, r;
    if (!(pl->sin_angle > 0.0)) return 0;
    a = vp_dt_point(&pl->dt, v[0]); b = vp_dt_point(&pl->dt, v[1]); c = vp_dt_point(&pl->dt, v[2]);
    vp_sub3(ab, b, a); vp_sub3(ac, c, a); vp_sub3(bc, c, b);
    la = sqrt(vp_dot3(bc, bc)); lb = sqrt(vp_dot3(ac, ac)); lc = sqrt(vp_dot3(ab, ab));
    vp_cross3(n, ab, ac);
    area2 = sqrt(vp_dot3(n, n));
    if (!(area2 > 0.0)) return 1;
    r = la * lb * lc / (2.0 * area2);
    lmin = la < lb ? la : lb;
    if (lc < lmin) lmin = lc;
    return lmin < 2.0 * r * pl->sin_angle;
}

/* Adds facet fv (any order) with ball centre c; `outside` is a point on the probe's side, so
 * the facet is stored facing it. A facet already known keeps its first ball. */
static int frec_add(vp_planner_t *pl, const uint32_t *fv, const double *c, const double *outside,
                    uint32_t tet, uint32_t proof, uint32_t *out)
{
    uint32_t v[3], k, h;
    int found;
    vp_frec_t *f;
    const double *a;
    v[0] = fv[0]; v[1] = fv[1]; v[2] = fv[2];
    sort3(v);
    h = fhash_find(pl, v, &found);
    if (found) { *out = pl->pool.fhash[h]; return VP_OK; }
    if (pl->pool.frec_free != NONE) {
        k = pl->pool.frec_free;
        pl->pool.frec_free = pl->pool.frec[k].v[1];
    } else {
        if (pl->pool.nfrec >= pl->pool.cap_frec) return VP_ENOMEM;
        k = pl->pool.nfrec++;
    }
    f = &pl->pool.frec[k];
    memcpy(f->v, v, sizeof v);
    f->heap = NONE;
    f->flags = 0;
    f->hint = tet;
    f->proof = proof;
    f->c[0] = c[0]; f->c[1] = c[1]; f->c[2] = c[2];
    a = vp_dt_point(&pl->dt, v[0]);
    f->r = vp_dist3(c, a);
    if (vp_orient3d(a, vp_dt_point(&pl->dt, v[1]), vp_dt_point(&pl->dt, v[2]), outside) < 0)
        f->flags |= FREC_FLIP;
    if (pl->pool.fhash[h] == HASH_TOMB && pl->pool.ntomb > 0) pl->pool.ntomb--;
    pl->pool.fhash[h] = k;
    pl->pool.nfacets++;
    *out = k;
    if (f->r > pl->cfg.eps || facet_too_sharp(pl, v)) return heap_push(pl, k);
    return VP_OK;
}

/* A second ball for facet record k (the edge crosses S twice): keep the larger, and mark the
 * record so that no free segment is inferred from it any more. */
static void frec_set_ball(vp_planner_t *pl, uint32_t k, const double *c)
{
    vp_frec_t *f = &pl->pool.frec[k];
    double r = vp_dist3(c, vp_dt_point(&pl->dt, f->v[0]));
    f->flags |= FREC_DOUBLE;
    if (!(r > f->r)) return;
    f->c[0] = c[0]; f->c[1] = c[1]; f->c[2] = c[2];
    f->r = r;
    if (f->heap != NONE) {
        heap_up(pl, f->heap);
    } else if (r > pl->cfg.eps && !(f->flags & FREC_STUCK)) {
        (void)heap_push(pl, k);
    }
}

/* ---------- Voronoi edges, clipped to Omega ---------- */

typedef struct edgegeom {
    double a[3], dir[3]; /* from the tet's end towards the neighbour's end */
    double len;          /* to the neighbour's end (huge for an infinite end) */
    double t0, t1;       /* the part inside Omega; t0 >= t1: none */
    int a_inside;        /* the tet's own end lies inside Omega */
} edgegeom_t;

#define FAR_AWAY 1e30

/* Geometry of the Voronoi edge dual to facet f of tet t, oriented from t's Voronoi vertex. */
static int edge_geom(const vp_planner_t *pl, uint32_t t, int f, edgegeom_t *g)
{
    vp_dt_vedge_t e;
    int st = vp_dt_voronoi_edge(&pl->dt, t, f, &e), k;
    int tg = vp_dt_is_ghost(&pl->dt, t);
    memset(g, 0, sizeof *g);
    if (st != VP_OK) return st;
    if (!e.is_ray) {
        for (k = 0; k < 3; k++) { g->a[k] = e.from[k]; g->dir[k] = e.to[k] - e.from[k]; }
        g->len = sqrt(vp_dot3(g->dir, g->dir));
        if (!(g->len > 0.0)) { g->t0 = g->t1 = 0.0; g->a_inside = omega_inside(&pl->cfg, g->a); return VP_OK; }
        for (k = 0; k < 3; k++) g->dir[k] /= g->len;
    } else if (!tg) {
        /* finite tet, ghost neighbour: from the Voronoi vertex outward to infinity */
        for (k = 0; k < 3; k++) { g->a[k] = e.from[k]; g->dir[k] = e.dir[k]; }
        g->len = FAR_AWAY;
    } else {
        /* ghost tet: from a point far out on the ray, back in to the finite vertex */
        double c[3], back;
        omega_center(&pl->cfg, c);
        back = vp_dist3(e.from, c) + 4.0 * omega_circumradius(&pl->cfg) + 1.0;
        for (k = 0; k < 3; k++) { g->a[k] = e.from[k] + back * e.dir[k]; g->dir[k] = -e.dir[k]; }
        g->len = back;
    }
    if (!vp_finite3(g->a) || !vp_finite3(g->dir)) return VP_EDEGEN;
    if (!omega_clip(&pl->cfg, g->a, g->dir, g->len, &g->t0, &g->t1)) g->t0 = g->t1 = 0.0;
    g->a_inside = !tg && omega_inside(&pl->cfg, g->a);
    return VP_OK;
}

/* A point of the Voronoi vertex of finite tet t (its circumcentre), for records. */
static int tet_point(const vp_planner_t *pl, uint32_t t, double *p)
{
    return vp_dt_circumcenter(&pl->dt, t, p);
}

/* ---------- paths for the device ---------- */

/* first record on the prev chain of r that lies outside Omega (the chain's root) */
static uint32_t chain_root(const vp_planner_t *pl, uint32_t r)
{
    while (pl->pool.vrec[r].prev != r) r = pl->pool.vrec[r].prev;
    return r;
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
    if (b == NONE) {
        while (pl->pool.vrec[x].prev != x) {
            uint32_t p = pl->pool.vrec[x].prev;
            l += vp_dist3(pl->pool.vrec[x].p, pl->pool.vrec[p].p);
            if (route && (st = route_push(pl, pl->pool.vrec[p].p, pl->pool.vrec[x].proof)) != VP_OK) return st;
            x = p;
        }
        st = outside_route(pl, pl->pool.vrec[x].p, gp, !route, &ol);
        *len = l + ol;
        return st;
    }
    /* climb to the common ancestor; y's half is kept to be walked downwards */
    while (pl->pool.vrec[x].depth > pl->pool.vrec[y].depth) {
        uint32_t p = pl->pool.vrec[x].prev;
        l += vp_dist3(pl->pool.vrec[x].p, pl->pool.vrec[p].p);
        if (route && (st = route_push(pl, pl->pool.vrec[p].p, pl->pool.vrec[x].proof)) != VP_OK) return st;
        x = p;
    }
    while (pl->pool.vrec[y].depth > pl->pool.vrec[x].depth) {
        if (ny >= pl->route.cap_path) return VP_ENOMEM;
        pl->route.path[ny++] = y;
        y = pl->pool.vrec[y].prev;
    }
    while (x != y && !(pl->pool.vrec[x].prev == x && pl->pool.vrec[y].prev == y)) {
        uint32_t p = pl->pool.vrec[x].prev;
        l += vp_dist3(pl->pool.vrec[x].p, pl->pool.vrec[p].p);
        if (route && (st = route_push(pl, pl->pool.vrec[p].p, pl->pool.vrec[x].proof)) != VP_OK) return st;
        x = p;
        if (ny >= pl->route.cap_path) return VP_ENOMEM;
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
        if (route && (st = route_push(pl, last, pl->pool.vrec[pl->route.path[i]].proof)) != VP_OK) return st;
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
    double best_out_cost = 1e300, ol;
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
            st = astar_relax(&s, cur, nb, pl->pool.vrec[cur].g + vp_dist3(pl->pool.vrec[cur].p, pl->pool.vrec[nb].p), 0);
            if (st != VP_OK) return st;
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
                st = route_push(pl, pl->pool.vrec[r].p, edge_proof(pl, pl->route.path[i + 1], r));
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

#define SEARCH_LOCAL 256u  /* expansions before a straight shortcut is probed */
#define SEARCH_FULL 4096u  /* expansions before falling back to the prev chains */

/* The full route from record a to record b (search, else prev chains), into the route buffer. */
static int route_full(vp_planner_t *pl, uint32_t a, uint32_t b)
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

/* Plans the device's route from where it stands to record b, or to the outside point gp when
 * b == NONE (a record is then made there). Sets pl->dev.at to the destination record. */
static int plan_route(vp_planner_t *pl, uint32_t b, const double *gp)
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
        /* a device with a body never enters Omega: every probe starts on dOmega */
        if (b != NONE && !(pl->pool.vrec[b].flags & REC_OUT)) return VP_EDEGEN;
        st = outside_route(pl, pl->pool.vrec[pl->dev.at].p, b != NONE ? pl->pool.vrec[b].p : gp, 0, &tl);
        if (st != VP_OK) return st;
        if (b == NONE && (st = rec_new(pl, gp, NONE, REC_OUT, &b)) != VP_OK) return st;
        pl->dev.at = b;
        return VP_OK;
    }
    if (!(pl->cfg.flags & VP_PLAN_PREV_CHAINS)) {
        /* what the same move costs along prev chains (reported beside the travel) */
        st = tree_path(pl, pl->dev.at, b, gp, 0, &tl);
        if (st != VP_OK) return st;
        pl->st.travel_prev_chains += tl;
    }
    if (!(pl->cfg.flags & VP_PLAN_PREV_CHAINS) && b != NONE) {
        /* the goal one free edge away: no search */
        uint32_t e, cur = pl->dev.at;
        for (e = pl->pool.vrec[cur].adj; e != NONE;) {
            const uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
            int isa = w[0] == cur;
            if ((isa ? w[1] : w[0]) == b) {
                pl->dev.at = b;
                pl->st.direct_routes++;
                return route_push(pl, pl->pool.vrec[b].p, w[4]);
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
        double known = st == VP_OK ? al : 1e300;
        if (known > 3.0 * d + 2.0 * pl->cfg.eps && d > 0.0 && in_reach(pl, pl->pool.vrec[pl->dev.at].p, pl->pool.vrec[b].p))
            pl->sc.to = b;
    }
    if (st != VP_OK) {
        /* the prev chains: always a way (and the only one with VP_PLAN_PREV_CHAINS) */
        st = tree_path(pl, pl->dev.at, b, gp, 1, &tl);
        if (st != VP_OK) return st;
        if (pl->cfg.flags & VP_PLAN_PREV_CHAINS) pl->st.travel_prev_chains += tl;
    }
    if (b == NONE) {
        st = rec_new(pl, gp, NONE, REC_OUT, &b);
        if (st != VP_OK) return st;
    }
    pl->dev.at = b;
    return VP_OK;
}

/* ---------- detect_access as a stack of probe tasks ---------- */

/* Probing every edge of every active vertex (the paper's detect_access): always with
 * VP_PLAN_PAPER, otherwise only while a hole could not be closed locally. */
static int exhaustive(const vp_planner_t *pl)
{
    return (pl->cfg.flags & VP_PLAN_PAPER) || pl->close.exhaustive;
}

/* A task is live while its tet is and its side is marked queued. A tet killed by an
 * insertion leaves its tasks behind (its slot may hold a new tet, whose sides start
 * unqueued, and any task pushed for that new tet lies above the old ones on the stack and is
 * popped first, clearing the mark): dropped here when the stack is full, skipped when popped. */
static int task_live(const vp_planner_t *pl, const vp_task_t *k)
{
    return vp_dt_alive(&pl->dt, k->tet) && (side_get(pl, k->tet, k->facet) & SIDE_QUEUED);
}

static void task_compact(vp_planner_t *pl)
{
    uint32_t i, n = 0;
    for (i = 0; i < pl->pool.ntask; i++)
        if (task_live(pl, &pl->pool.task[i])) pl->pool.task[n++] = pl->pool.task[i];
    pl->pool.ntask = n;
}

static int task_push(vp_planner_t *pl, uint32_t t, int f, int forced)
{
    unsigned s = side_get(pl, t, f);
    vp_task_t *k;
    if (s & SIDE_QUEUED) return VP_OK;
    if (pl->pool.ntask >= pl->pool.cap_task) task_compact(pl);
    if (pl->pool.ntask >= pl->pool.cap_task) return VP_ENOMEM;
    k = &pl->pool.task[pl->pool.ntask++];
    k->tet = t;
    k->facet = (uint8_t)f;
    k->tries = 0;
    k->proof = PROOF_NONE;
    k->off = 0.0;
    side_set(pl, t, f, s | SIDE_QUEUED | (forced ? SIDE_FORCED : 0u));
    return VP_OK;
}

static int facet_has_ghost(const vp_planner_t *pl, uint32_t t, int f)
{
    uint32_t fv[3];
    vp_dt_facet(&pl->dt, t, f, fv);
    return fv[0] == VP_DT_GHOST || fv[1] == VP_DT_GHOST || fv[2] == VP_DT_GHOST;
}

/* detect_access(t): queue a probe of every Voronoi edge around active vertex t that still
 * needs one. Without VP_PLAN_PAPER, edges towards vertices already known free are left out. */
static int explore(vp_planner_t *pl, uint32_t t)
{
    int f, st;
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    for (f = 3; f >= 0; f--) {
        unsigned s = side_get(pl, t, f);
        if ((s & (SIDE_QUEUED | SIDE_BLOCKED)) || facet_has_ghost(pl, t, f)) continue;
        /* BEHIND seen from a free vertex: the edge crosses S twice; its other ball is probed
         * from here */
        if ((s & SIDE_MASK) != SIDE_UNKNOWN && (s & SIDE_MASK) != SIDE_BEHIND) continue;
        if ((s & SIDE_MASK) == SIDE_UNKNOWN && !exhaustive(pl) && tet_active(pl, w[4 + f] >> 2)) continue;
        if ((st = task_push(pl, t, f, 0)) != VP_OK) return st;
    }
    return VP_OK;
}

/* Marks tet t active (reachable). rec: its record, or VREC_OUT. */
static int activate(vp_planner_t *pl, uint32_t t, uint32_t rec)
{
    pay(pl, t)[0] = rec;
    return explore(pl, t);
}

/* the unique point of the facet's plane equidistant from its vertices */
static int facet_circumcenter(const vp_planner_t *pl, const uint32_t *fv, double *m)
{
    const double *a = vp_dt_point(&pl->dt, fv[0]), *b = vp_dt_point(&pl->dt, fv[1]),
                 *c = vp_dt_point(&pl->dt, fv[2]);
    double ab[3], ac[3], n[3], t1[3], t2[3], d;
    int k;
    vp_sub3(ab, b, a);
    vp_sub3(ac, c, a);
    vp_cross3(n, ab, ac);
    d = 2.0 * vp_dot3(n, n);
    if (!(d > 0.0)) return 0;
    vp_cross3(t1, n, ab);
    vp_cross3(t2, ac, n);
    for (k = 0; k < 3; k++) m[k] = a[k] + (vp_dot3(ac, ac) * t1[k] + vp_dot3(ab, ab) * t2[k]) / d;
    return vp_finite3(m);
}

/* A miss is suspicious when the edge passes through its own facet's circumcentre: the facet is
 * then a plausible surface facet and the probe crosses the sampled surface there. */
static int expect_hit(const vp_planner_t *pl, uint32_t t, int f, const double *origin,
                      const double *dir, double range)
{
    uint32_t fv[3];
    double m[3], d[3], s;
    vp_dt_facet(&pl->dt, t, f, fv);
    if (!facet_circumcenter(pl, fv, m)) return 0;
    vp_sub3(d, m, origin);
    s = vp_dot3(d, dir);
    return s > 0.0 && s < range;
}

/* A side that cannot be probed from this end (no usable edge: a degenerate tet, or no place to
 * probe from): marked so that no rule asks for it again, which bounds the work of closing. */
static int task_unprobeable(vp_planner_t *pl, uint32_t t, int f)
{
    side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
    pl->st.stalls++;
    return 0;
}

/* Prepares the probe of task k: the route to its origin and the ray. Returns 1 when a probe
 * is ready, 0 when the task resolved without probing. */
static int task_start(vp_planner_t *pl, vp_task_t *k)
{
    uint32_t t = k->tet, u, j;
    int f = k->facet, st;
    unsigned s = side_get(pl, t, f);
    const uint32_t *w;
    edgegeom_t g;
    double o[3], range;
    uint32_t goal = NONE;
    if (!task_live(pl, k)) return 0;
    side_set(pl, t, f, s & ~(SIDE_QUEUED | SIDE_FORCED));
    if ((s & SIDE_MASK) != SIDE_UNKNOWN && (s & SIDE_MASK) != SIDE_BEHIND) return 0;
    w = vp_dt_tet(&pl->dt, t);
    u = w[4 + f] >> 2;
    j = w[4 + f] & 3u;
    if ((s & SIDE_MASK) == SIDE_UNKNOWN && !exhaustive(pl) && !(s & SIDE_FORCED) && tet_active(pl, u))
        return 0;
    if (!tet_active(pl, t)) return 0;
    st = edge_geom(pl, t, f, &g);
    if (st != VP_OK) return task_unprobeable(pl, t, f); /* degenerate: no usable edge */
    if (!(g.t0 < g.t1) || k->off >= g.t1 - g.t0 - 1e-12 * (1.0 + g.t1)) {
        /* the edge lies outside Omega (or is already proven free by the walked ray): free */
        uint32_t pf = k->off > 0.0 ? k->proof : PROOF_OUTSIDE;
        side_set(pl, t, f, SIDE_UNKNOWN);
        side_free(pl, t, f, pf);
        side_free(pl, u, (int)j, pf);
        return 0;
    }
    pl->probe.standoff = 0.0;
    if (g.a_inside && pl->cfg.clearance > 0.0) {
        /* a device with a body stays outside Omega: it probes the edge's line from where the
         * line leaves Omega behind the vertex; only a hit beyond the vertex is on the edge */
        double back[3], t0b, t1b;
        int q;
        for (q = 0; q < 3; q++) back[q] = -g.dir[q];
        if (!omega_clip(&pl->cfg, g.a, back, 1e300, &t0b, &t1b)) return task_unprobeable(pl, t, f);
        for (q = 0; q < 3; q++) o[q] = g.a[q] - t1b * g.dir[q];
        range = t1b + g.t1;
        pl->probe.standoff = t1b;
    } else if (g.a_inside) {
        goal = tet_rec(pl, t);
        if (goal == VREC_OUT || goal == NONE) return task_unprobeable(pl, t, f);
        o[0] = g.a[0]; o[1] = g.a[1]; o[2] = g.a[2];
        range = g.t1;
    } else {
        int q, tries;
        double back = 0.0;
        for (q = 0; q < 3; q++) o[q] = g.a[q] + g.t0 * g.dir[q];
        range = g.t1 - g.t0;
        /* where the edge enters Omega, from a far Voronoi vertex (a nearly flat tet): rounding
         * can put it inside Omega; the device waits outside, so step back along the line */
        for (tries = 0; omega_inside(&pl->cfg, o) && tries < 16; tries++) {
            double step = back > 0.0 ? back : 4e-16 * (fabs(g.t0) + sqrt(vp_dot3(g.a, g.a))) + pl->ptol;
            for (q = 0; q < 3; q++) o[q] -= step * g.dir[q];
            range += step;
            back += step;
        }
        if (omega_inside(&pl->cfg, o)) return task_unprobeable(pl, t, f);
    }
    if (k->off > 0.0) {
        /* resume a range-limited probe from the end of its free part */
        int q;
        for (q = 0; q < 3; q++) o[q] += k->off * g.dir[q];
        range -= k->off;
        goal = pl->dev.at; /* the device was left there */
    }
    pl->probe.full = range;
    range = clamp_range(pl, range);
    if (goal != NONE) st = plan_route(pl, goal, NULL);
    else st = plan_route(pl, NONE, o);
    if (st != VP_OK) { pl->error = st; return 0; }
    memcpy(pl->probe.origin, o, sizeof o);
    memcpy(pl->probe.dir, g.dir, sizeof g.dir);
    pl->probe.range = range;
    pl->probe.origin_rec = pl->dev.at;
    pl->probe.chain_proof = k->off > 0.0 ? k->proof : PROOF_NONE;
    pl->probe.task = *k;
    side_set(pl, t, f, side_get(pl, t, f) | SIDE_QUEUED);
    if (pl->sc.to != NONE) {
        /* the shortcut probe goes first, from where the device stands now */
        pl->sc.from = pl->route.from;
        pl->sc.tries = 0;
        pl->sc.pending = 1;
        return 2;
    }
    return 1;
}

/* The result of the probe of the current task. */
static int task_finish(vp_planner_t *pl, const vp_probe_result_t *res)
{
    vp_task_t *k = &pl->probe.task;
    uint32_t t = k->tet, u, j, fv[3], fr;
    int f = k->facet, st, q;
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    double tol = pl->cfg.noise_tol;
    u = w[4 + f] >> 2;
    j = w[4 + f] & 3u;
    side_set(pl, t, f, side_get(pl, t, f) & ~(SIDE_QUEUED | SIDE_FORCED));
    if (res->hit == VP_PROBE_TOO_CLOSE) {
        /* nothing learnt: not free, no sample; not asked again from this end */
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
        pl->st.too_close++;
        return VP_OK;
    }
    if (res->hit && pl->probe.standoff > 0.0 && res->dist < pl->probe.standoff + tol) {
        /* from a standoff: the line met S before reaching the vertex; the edge is unseen */
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
        pl->st.hits++;
        pl->st.occluded++;
        return VP_OK;
    }
    if (res->hit && res->dist <= pl->probe.range + tol) {
        /* the ball centre stays strictly inside the edge: a centre on a Voronoi vertex (a hit
         * at 0 or past the end, within the noise) would put a fourth sample on its sphere */
        double h[3], d = res->dist, inset = 1e-9 * pl->probe.range;
        if (d > pl->probe.range - inset) d = pl->probe.range - inset;
        if (d < inset) d = inset;
        for (q = 0; q < 3; q++) h[q] = pl->probe.origin[q] + d * pl->probe.dir[q];
        pl->st.hits++;
        vp_dt_facet(&pl->dt, t, f, fv);
        {
            unsigned su = side_get(pl, u, (int)j) & SIDE_MASK;
            uint32_t pf;
            if ((st = probe_proof(pl, res, &pf)) != VP_OK) return st;
            st = frec_add(pl, fv, h, pl->probe.origin, t, pf, &fr);
            if (st != VP_OK) return st;
            side_set(pl, t, f, SIDE_HIT);
            if (su == SIDE_HIT) {
                /* seen from both ends: two balls; the larger one decides refinement */
                frec_set_ball(pl, fr, h);
            } else {
                side_set(pl, u, (int)j, (side_get(pl, u, (int)j) & ~SIDE_MASK) | SIDE_BEHIND);
            }
        }
        return VP_OK;
    }
    pl->st.misses++;
    /* a dropout must not open a way into the object: a miss is trusted only after
     * confirm_misses more misses on the same ray (twice that where a hit is expected) */
    if (pl->cfg.confirm_misses > 0 &&
        k->tries < pl->cfg.confirm_misses *
                       (expect_hit(pl, t, f, pl->probe.origin, pl->probe.dir, pl->probe.range) ? 2u : 1u)) {
        k->tries++;
        pl->st.reprobes++;
        pl->probe.ready = 1;
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_QUEUED);
        return VP_OK;
    }
    {
        uint32_t pf;
        if ((st = probe_proof(pl, res, &pf)) != VP_OK) return st;
        k->proof = pf;
    }
    if (probe_limited(pl)) {
        /* range-limited: the free part ends here; walk there and probe on */
        double e[3];
        if (pl->cfg.clearance > 0.0) {
            /* a device with a body stays outside Omega: the rest of the line is unseen */
            side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
            pl->st.occluded++;
            return VP_OK;
        }
        if ((st = walk_on(pl, pl->probe.origin_rec, k->proof, e)) != VP_OK) return st;
        k->off += pl->probe.range;
        k->tries = 0; /* the next part of the ray is a new probe: its misses are confirmed anew */
        if (pl->pool.ntask >= pl->pool.cap_task) return VP_ENOMEM;
        pl->pool.task[pl->pool.ntask++] = *k;
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_QUEUED);
        return VP_OK;
    }
    /* the whole edge is free: a hit seen from the other end lay within the noise of this end
     * (S passes by the vertex here): the edge does not cross S once, its facet goes */
    vp_dt_facet(&pl->dt, t, f, fv);
    if ((fr = frec_lookup(pl, fv)) != NONE) {
        frec_delete(pl, fr);
        pl->st.noise_drops++;
    }
    side_set(pl, t, f, SIDE_UNKNOWN);
    side_free(pl, t, f, k->proof);
    side_free(pl, u, (int)j, k->proof);
    if (!tet_active(pl, u)) {
        double c[3];
        uint32_t r;
        if (vp_dt_is_ghost(&pl->dt, u) || tet_point(pl, u, c) != VP_OK || !omega_inside(&pl->cfg, c))
            return activate(pl, u, VREC_OUT);
        st = rec_link(pl, c, pl->probe.origin_rec, 0, k->proof, &r);
        if (st != VP_OK || r == NONE) return st;
        return activate(pl, u, r);
    }
    if (tet_rec(pl, u) != VREC_OUT && pl->probe.origin_rec != NONE)
        return edge_add(pl, pl->probe.origin_rec, tet_rec(pl, u), k->proof);
    return VP_OK;
}

/* ---------- after an insertion: the update of Del_v|S and of the free paths ---------- */

static int facet_index_of(const uint32_t *w, uint32_t v)
{
    int k;
    for (k = 0; k < 4; k++)
        if (w[k] == v) return k;
    return -1;
}

/* Entry point on dOmega of the Voronoi edge dual to facet f of t, walking from the far
 * (neighbour's) end towards t's vertex; t's vertex is inside Omega. */
static int entry_point(const vp_planner_t *pl, uint32_t t, int f, double *e)
{
    edgegeom_t g;
    int k;
    if (edge_geom(pl, t, f, &g) != VP_OK || !(g.t0 < g.t1)) return 0;
    for (k = 0; k < 3; k++) e[k] = g.a[k] + g.t1 * g.dir[k];
    return 1;
}

static int after_insert(vp_planner_t *pl, uint32_t pv)
{
    uint32_t nk, nc, q, ki;
    const uint32_t *killed = vp_dt_last_killed(&pl->dt, &nk);
    const uint32_t *kverts = vp_dt_last_killed_vertices(&pl->dt);
    const uint32_t *created = vp_dt_last_created(&pl->dt, &nc);
    const uint32_t *cfrom = vp_dt_last_created_from(&pl->dt);
    uint32_t *kpay, *kbound, *ckidx;
    const double *P = vp_dt_point(&pl->dt, pv);
    int st, i;

    if (KPAY * nk + nk + nc > pl->pool.cap_astar) return VP_ENOMEM;
    if (KPAY * nk + nk + nc > pl->peak.astar) pl->peak.astar = KPAY * nk + nk + nc;
    kpay = pl->pool.astar;
    kbound = kpay + KPAY * nk;
    ckidx = kbound + nk;
    /* the killed tets' payloads, before created tets overwrite their slots */
    for (q = 0; q < nk; q++) {
        memcpy(kpay + KPAY * q, pay(pl, killed[q]), KPAY * sizeof(uint32_t));
        kbound[q] = 0;
    }
    for (q = 0; q < nc; q++) {
        uint32_t ks = cfrom[q] >> 2;
        for (ki = 0; ki < nk && killed[ki] != ks; ki++) {}
        if (ki == nk) return VP_EDEGEN;
        ckidx[q] = ki;
        kbound[ki] |= 1u << (cfrom[q] & 3u);
    }
    /* facets inside the cavity are gone: so are their balls */
    for (ki = 0; ki < nk; ki++)
        for (i = 0; i < 4; i++) {
            uint32_t fv[3], r;
            int m = 0, x;
            if ((kbound[ki] >> i) & 1u) continue;
            for (x = 0; x < 4; x++)
                if (x != i) fv[m++] = kverts[4 * ki + (uint32_t)x];
            r = frec_lookup(pl, fv);
            if (r != NONE) frec_delete(pl, r);
        }
    for (q = 0; q < nc; q++) {
        pay(pl, created[q])[0] = NONE;
        pay(pl, created[q])[1] = 0;
    }
    /* cavity boundary facets: the Voronoi edge keeps its line and shrinks to [P_n, P_U] */
    for (q = 0; q < nc; q++) {
        uint32_t n = created[q], U, jj, fv[3], r, krec;
        const uint32_t *w = vp_dt_tet(&pl->dt, n);
        int jn = facet_index_of(w, pv), fi = (int)(cfrom[q] & 3u);
        unsigned sU, sK, sn;
        int valid = 0, reach_from_k = 0, edge_free = 0, c_ok = 0;
        double c[3], oldc[3], pu[3], tol = pl->cfg.noise_tol;
        uint32_t pfree = PROOF_NONE, pk = PROOF_NONE; /* proofs proposed: of the edge, of [P_k, P_n] */
        uint32_t oldproof = PROOF_NONE;
        ki = ckidx[q];
        U = w[4 + jn] >> 2;
        jj = w[4 + jn] & 3u;
        sU = side_get(pl, U, (int)jj) & SIDE_MASK;
        sK = (kpay[KPAY * ki + 1] >> (8 * fi)) & SIDE_MASK;
        krec = kpay[KPAY * ki];
        if (vp_dt_is_ghost(&pl->dt, n)) {
            pay(pl, n)[0] = VREC_OUT;
        } else if (tet_point(pl, n, c) != VP_OK || !omega_inside(&pl->cfg, c)) {
            pay(pl, n)[0] = VREC_OUT;
        } else {
            c_ok = 1;
        }
        if (facet_has_ghost(pl, n, jn)) continue;
        vp_dt_facet(&pl->dt, n, jn, fv);
        r = frec_lookup(pl, fv);
        if (r != NONE) {
            int dbl = (pl->pool.frec[r].flags & FREC_DOUBLE) != 0;
            memcpy(oldc, pl->pool.frec[r].c, sizeof oldc);
            oldproof = pl->pool.frec[r].proof;
            valid = vp_cmp_dist(pl->pool.frec[r].c, P, vp_dt_point(&pl->dt, fv[0])) >= 0;
            if (!valid) frec_delete(pl, r);
            if (dbl) {
                /* two crossings: nothing about free parts can be inferred; look again */
                side_set(pl, n, jn, SIDE_UNKNOWN);
                side_set(pl, U, (int)jj, side_get(pl, U, (int)jj) & ~SIDE_MASK);
                continue;
            }
        }
        sn = SIDE_UNKNOWN;
        if (r != NONE && valid) {
            if (sU == SIDE_HIT) sn = SIDE_BEHIND;
            else if (sK == SIDE_HIT) {
                sn = SIDE_HIT;
                sU = SIDE_BEHIND;
                /* [P_kold, c) was free; P_n lies on it, clear of c by the noise tolerance */
                reach_from_k = krec != NONE && krec != VREC_OUT && c_ok &&
                               vp_dist3(pl->pool.vrec[krec].p, c) <= vp_dist3(pl->pool.vrec[krec].p, pl->pool.frec[r].c) - tol;
                pk = pl->pool.frec[r].proof;
            }
            else { sn = SIDE_UNKNOWN; }
        } else if (sU == SIDE_FREE || sK == SIDE_FREE) {
            sn = sU = SIDE_FREE;
            edge_free = 1;
            reach_from_k = 1;
            pfree = pk = sK == SIDE_FREE ? kpay[KPAY * ki + 2 + fi] : side_proof(pl, U, (int)jj);
        } else if (r != NONE && sU == SIDE_HIT) {
            /* the old hit seen from U is cut off: U's side is free up to past P_n, with the
             * noise tolerance to spare (measured from U's vertex, or for a hull ray from where
             * the probe entered Omega: the hit may be off by the noise either way) */
            int from_u = vp_dt_is_ghost(&pl->dt, U) ? entry_point(pl, n, jn, pu)
                                                      : tet_point(pl, U, pu) == VP_OK;
            if (c_ok && from_u && vp_dist3(pu, c) <= vp_dist3(pu, oldc) - tol) {
                sn = sU = SIDE_FREE;
                edge_free = 1;
                pfree = oldproof;
            } else {
                sn = sU = SIDE_UNKNOWN;
            }
        } else if (r != NONE) {
            sn = sU = SIDE_UNKNOWN;
        }
        side_set(pl, n, jn, sn);
        side_set(pl, U, (int)jj, (side_get(pl, U, (int)jj) & ~SIDE_MASK) | sU);
        if (sn == SIDE_FREE) {
            side_free(pl, n, jn, pfree);
            side_free(pl, U, (int)jj, pfree);
        }
        /* activation through the free boundary edge (the paper's v' rule), or along the
         * former edge from the killed tet's record */
        if (pay(pl, n)[0] != NONE) continue;
        {
            uint32_t nr = NONE, urec = tet_rec(pl, U);
            int k_ok = reach_from_k && krec != NONE && krec != VREC_OUT;
            if (edge_free && urec != NONE) {
                if (urec == VREC_OUT) {
                    double e[3];
                    uint32_t er;
                    if (!entry_point(pl, n, jn, e)) continue;
                    st = rec_new(pl, e, NONE, REC_OUT, &er);
                    if (st != VP_OK) return st;
                    st = rec_link(pl, c, er, 0, pfree, &nr);
                } else {
                    st = rec_link(pl, c, urec, 0, pfree, &nr);
                }
                /* the rest of the old edge, towards the former vertex, is free too */
                if (st == VP_OK && k_ok && nr != NONE) st = edge_add(pl, nr, krec, pk);
                if (st != VP_OK) return st;
            }
            if (nr == NONE && k_ok) {
                st = rec_link(pl, c, krec, 0, pk, &nr);
                if (st != VP_OK) return st;
            }
            if (nr != NONE) pay(pl, n)[0] = nr;
        }
    }
    /* detect_access from every new active vertex, and from old active neighbours towards
     * new vertices not reached yet */
    for (q = 0; q < nc; q++) {
        uint32_t n = created[q];
        const uint32_t *w = vp_dt_tet(&pl->dt, n);
        int jn = facet_index_of(w, pv);
        if (tet_active(pl, n)) {
            if ((st = explore(pl, n)) != VP_OK) return st;
        } else {
            uint32_t U = w[4 + jn] >> 2, jj = w[4 + jn] & 3u;
            if (tet_active(pl, U) && (side_get(pl, U, (int)jj) & SIDE_MASK) == SIDE_UNKNOWN &&
                !facet_has_ghost(pl, n, jn))
                if ((st = task_push(pl, U, (int)jj, 0)) != VP_OK) return st;
        }
    }
    return VP_OK;
}

/* ---------- refinement: insert the centre of a bad ball ---------- */

static uint32_t find_facet_slow(vp_planner_t *pl, const uint32_t *fv, int *fi);

/* a live tet holding facet fv, and the facet's index in it */
static uint32_t find_facet(vp_planner_t *pl, const uint32_t *fv, int *fi)
{
    uint32_t k = frec_lookup(pl, fv);
    if (k != NONE && vp_dt_alive(&pl->dt, pl->pool.frec[k].hint)) {
        const uint32_t *w = vp_dt_tet(&pl->dt, pl->pool.frec[k].hint);
        int a = facet_index_of(w, fv[0]), b = facet_index_of(w, fv[1]), c = facet_index_of(w, fv[2]);
        if (a >= 0 && b >= 0 && c >= 0) {
            *fi = 6 - a - b - c;
            return pl->pool.frec[k].hint;
        }
    }
    return find_facet_slow(pl, fv, fi);
}

static uint32_t find_facet_slow(vp_planner_t *pl, const uint32_t *fv, int *fi)
{
    int n = vp_dt_incident_tets(&pl->dt, fv[0], pl->pool.astar, (int)(pl->pool.cap_astar > 65536 ? 65536 : pl->pool.cap_astar)), k;
    for (k = 0; k < n; k++) {
        const uint32_t *w = vp_dt_tet(&pl->dt, pl->pool.astar[k]);
        int a = facet_index_of(w, fv[1]), b = facet_index_of(w, fv[2]), c = facet_index_of(w, fv[0]);
        if (a >= 0 && b >= 0) {
            *fi = 6 - a - b - c;
            return pl->pool.astar[k];
        }
    }
    return NONE;
}

static int pools_have_room(const vp_planner_t *pl)
{
    return pl->pool.nvrec + 512 <= pl->pool.cap_vrec && pl->pool.nfedge + 512 <= pl->pool.cap_fedge &&
           pl->pool.nfrec + 256 <= pl->pool.cap_frec && pl->pool.ntask + 256 <= pl->pool.cap_task &&
           pl->pool.nheap + 256 <= pl->pool.cap_heap && 4u * (pl->pool.nfacets + 256) < pl->pool.hash_mask;
}

static uint32_t choose_ball(const vp_planner_t *pl)
{
    uint32_t best = pl->pool.heap[0], i;
    double rmin, bestd;
    if ((pl->cfg.flags & VP_PLAN_LARGEST) || pl->pool.nheap < 2) return best;
    /* among the balls at least 70% of the largest, the nearest to the device */
    rmin = 0.7 * pl->pool.frec[best].r;
    bestd = vp_dist3(pl->dev.pos, pl->pool.frec[best].c);
    for (i = 1; i < pl->pool.nheap; i++) {
        const vp_frec_t *f = &pl->pool.frec[pl->pool.heap[i]];
        double d;
        if (f->r < rmin) continue;
        d = vp_dist3(pl->dev.pos, f->c);
        if (d < bestd) { bestd = d; best = pl->pool.heap[i]; }
    }
    return best;
}

static int refine(vp_planner_t *pl)
{
    if (pl->pool.fhash_dirty) { fhash_rebuild(pl); pl->pool.fhash_dirty = 0; }
    uint32_t k = choose_ball(pl), t, v = NONE, fv[3];
    int fi, st;
    double c[3];
    if (pl->pool.ntask + 256 > pl->pool.cap_task) task_compact(pl);
    if (!pools_have_room(pl)) return VP_ENOMEM;
    memcpy(fv, pl->pool.frec[k].v, sizeof fv);
    memcpy(c, pl->pool.frec[k].c, sizeof c);
    t = find_facet(pl, fv, &fi);
    if (t == NONE) {
        frec_delete(pl, k);
        pl->st.stale_balls++;
        return VP_OK;
    }
    st = vp_dt_insert_in_conflict(&pl->dt, c, t, &v);
    if (st == VP_EINVAL)
        st = vp_dt_insert_in_conflict(&pl->dt, c, vp_dt_tet(&pl->dt, t)[4 + fi] >> 2, &v);
    if (st == VP_EINVAL) st = vp_dt_insert(&pl->dt, c, t, &v);
    if (st == VP_ENOMEM) return st;
    if (st != VP_OK) {
        /* cannot be refined (a duplicate within rounding): keep the facet, drop the ball */
        heap_remove(pl, k);
        pl->pool.frec[k].flags |= FREC_STUCK;
        pl->st.stale_balls++;
        return VP_OK;
    }
    pl->st.insertions++;
    pl->close.exhaustive = 0;
    st = after_insert(pl, v);
    note_peak(pl);
    return st;
}

/* ---------- closing: every edge of the mesh must have exactly two facets ---------- */

/* Queues forced probes around edge (x, y) of Del(E): from every active tet of the ring, each
 * unknown facet. Returns the number of probes queued, or a negative status. */
static int probe_around_edge(vp_planner_t *pl, uint32_t t0, uint32_t x, uint32_t y)
{
    uint32_t cur = t0, other, limit = 4096, pushed = 0;
    const uint32_t *w = vp_dt_tet(&pl->dt, t0);
    int k, ex = -1;
    for (k = 0; k < 4; k++)
        if (w[k] != x && w[k] != y) { ex = k; break; }
    if (ex < 0) return 0;
    other = w[ex];
    do {
        const uint32_t *c = vp_dt_tet(&pl->dt, cur);
        int f, st, ix = -1;
        if (tet_active(pl, cur))
            for (f = 0; f < 4; f++) {
                unsigned s = side_get(pl, cur, f);
                if ((s & SIDE_MASK) != SIDE_UNKNOWN || (s & (SIDE_QUEUED | SIDE_BLOCKED)) ||
                    facet_has_ghost(pl, cur, f))
                    continue;
                if ((st = task_push(pl, cur, f, 1)) != VP_OK) return st;
                pushed++;
            }
        for (k = 0; k < 4; k++)
            if (c[k] == other) ix = k;
        if (ix < 0) break;
        for (k = 0; k < 4; k++)
            if (c[k] != x && c[k] != y && c[k] != other) break;
        cur = c[4 + ix] >> 2;
        other = c[k];
    } while (cur != t0 && --limit);
    return (int)pushed;
}

static int close_holes(vp_planner_t *pl)
{
    /* edge counts in a scratch hash: 3 words per slot (a, b, count) */
    uint32_t slots = 1, i, *tab = pl->pool.astar, pushed = 0, holes = 0;
    while (slots < 4u * pl->pool.nfacets + 16u) slots <<= 1;
    if (3u * slots > pl->pool.cap_astar) return 0; /* too big to check here: left to certify */
    for (i = 0; i < 3u * slots; i++) tab[i] = NONE;
    for (i = 0; i < pl->pool.nfrec; i++) {
        const vp_frec_t *f = &pl->pool.frec[i];
        int e;
        if (f->v[0] == NONE) continue;
        for (e = 0; e < 3; e++) {
            uint32_t a = f->v[e], b = f->v[(e + 1) % 3], h;
            if (a > b) { uint32_t t = a; a = b; b = t; }
            h = (uint32_t)(((uint64_t)a * 0x9E3779B97F4A7C15ull ^ b) * 0xBF58476D1CE4E5B9ull >> 40) & (slots - 1);
            while (tab[3 * h] != NONE && (tab[3 * h] != a || tab[3 * h + 1] != b)) h = (h + 1) & (slots - 1);
            if (tab[3 * h] == NONE) { tab[3 * h] = a; tab[3 * h + 1] = b; tab[3 * h + 2] = 0; }
            tab[3 * h + 2]++;
        }
    }
    for (i = 0; i < slots; i++) {
        uint32_t fv[3], a = tab[3 * i], b = tab[3 * i + 1], t, k;
        int fi, n;
        if (a == NONE || tab[3 * i + 2] == 2) continue;
        /* a facet record with this edge gives a tet to turn around it from */
        t = NONE;
        for (k = 0; k < pl->pool.nfrec && t == NONE; k++) {
            const vp_frec_t *f = &pl->pool.frec[k];
            int ha, hb;
            if (f->v[0] == NONE) continue;
            ha = f->v[0] == a || f->v[1] == a || f->v[2] == a;
            hb = f->v[0] == b || f->v[1] == b || f->v[2] == b;
            if (ha && hb) { memcpy(fv, f->v, sizeof fv); t = k; }
        }
        if (t == NONE) continue;
        t = find_facet(pl, fv, &fi);
        if (t == NONE) continue;
        n = probe_around_edge(pl, t, a, b);
        if (n < 0) return n;
        pushed += (uint32_t)n;
        holes++;
    }
    if (holes > 0 && pushed == 0 && !pl->close.exhaustive) {
        /* no active vertex next to the holes: detect_access in full from every active vertex
         * until the next insertion */
        uint32_t tt;
        int st;
        pl->close.exhaustive = 1;
        pl->st.escalations++;
        for (tt = 0; tt < pl->dt.ntet_slots; tt++)
            if (vp_dt_alive(&pl->dt, tt) && tet_active(pl, tt)) {
                if ((st = explore(pl, tt)) != VP_OK) return st;
            }
        return (int)pl->pool.ntask;
    }
    return (int)pushed;
}

static int seed_issue(vp_planner_t *pl, const double *dir, double range);
static int seed_miss_on(vp_planner_t *pl);
static double omega_exit(const vp_planner_config_t *c, const double *p, const double *u);
static int pools_have_room(const vp_planner_t *pl);

/* ---------- H2: a vertex on every component ---------- */

/* 1 if point o is enclosed by the mesh: odd number of facets crossed by a ray from o. The
 * ray's direction is fixed and irrational-looking so that it meets no edge in practice. */
static int mesh_encloses(const vp_planner_t *pl, const double *o)
{
    static const double dir[3] = { 0.4469983318002897, 0.5384104567341229, 0.7144217014264011 };
    uint32_t i, crossings = 0;
    for (i = 0; i < pl->pool.nfrec; i++) {
        const vp_frec_t *f = &pl->pool.frec[i];
        const double *a, *b, *c;
        double e1[3], e2[3], p[3], q[3], t[3], det, u, v, w;
        if (f->v[0] == NONE) continue;
        a = vp_dt_point(&pl->dt, f->v[0]);
        b = vp_dt_point(&pl->dt, f->v[1]);
        c = vp_dt_point(&pl->dt, f->v[2]);
        vp_sub3(e1, b, a);
        vp_sub3(e2, c, a);
        vp_cross3(p, dir, e2);
        det = vp_dot3(e1, p);
        if (det == 0.0) continue;
        vp_sub3(t, o, a);
        u = vp_dot3(t, p) / det;
        if (u < 0.0 || u > 1.0) continue;
        vp_cross3(q, t, e1);
        v = vp_dot3(dir, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        w = vp_dot3(e2, q) / det;
        if (w > 0.0) crossings++;
    }
    return (int)(crossings & 1u);
}

/* Directions tried, one after the other, to find a component the seeds missed. */
static void reseed_dir(uint32_t attempt, double *d)
{
    static const signed char D[26][3] = {
        { 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 },
        { 1, 1, 1 }, { -1, -1, -1 }, { 1, -1, 1 }, { -1, 1, -1 }, { 1, 1, -1 }, { -1, -1, 1 },
        { -1, 1, 1 }, { 1, -1, -1 }, { 1, 1, 0 }, { -1, -1, 0 }, { 1, -1, 0 }, { -1, 1, 0 },
        { 1, 0, 1 }, { -1, 0, -1 }, { 1, 0, -1 }, { -1, 0, 1 }, { 0, 1, 1 }, { 0, -1, -1 },
        { 0, 1, -1 }, { 0, -1, 1 } };
    d[0] = D[attempt % 26][0]; d[1] = D[attempt % 26][1]; d[2] = D[attempt % 26][2];
    vp_normalize3(d);
}

#define RESEED_TRIES 26u

/* After the mesh closed: every o_i must be enclosed by it (H2). A missed component gets a new
 * sample: a probe towards o_i from another side of Omega, inserted like a ball centre. */
static int check_components(vp_planner_t *pl)
{
    uint32_t i;
    for (i = 0; i < pl->cfg.ninterior; i++) {
        const double *o = pl->cfg.interior[i];
        double d[3], q[3], te;
        int k, st;
        if (pl->close.h2_done & (1u << i)) continue;
        if (mesh_encloses(pl, o)) { pl->close.h2_done |= 1u << i; continue; }
        if (pl->close.h2_tries[i] >= RESEED_TRIES) continue; /* reported: not found */
        reseed_dir(pl->close.h2_tries[i]++, d);
        te = omega_exit(&pl->cfg, o, d);
        for (k = 0; k < 3; k++) q[k] = o[k] + te * d[k];
        if ((st = plan_route(pl, NONE, q)) != VP_OK) return st;
        for (k = 0; k < 3; k++) d[k] = -d[k];
        pl->phase = PH_RESEED;
        return seed_issue(pl, d, te);
    }
    pl->phase = PH_DONE;
    return VP_OK;
}

static int reseed_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    double h[3];
    uint32_t v;
    int k, st;
    pl->phase = PH_COMPONENTS;
    if (res->hit != 1) {
        /* a dropout or the end of the rangefinder's reach: probe again, or walk on */
        int w = res->hit == VP_PROBE_TOO_CLOSE ? 0 : seed_miss_on(pl);
        if (w < 0) return w;
        if (w) pl->phase = PH_RESEED;
        return VP_OK;
    }
    for (k = 0; k < 3; k++) h[k] = pl->probe.origin[k] + res->dist * pl->probe.dir[k];
    if (!pools_have_room(pl)) return VP_ENOMEM;
    st = vp_dt_insert(&pl->dt, h, VP_DT_NONE, &v);
    if (st == VP_EDUP) return VP_OK;
    if (st != VP_OK) return st;
    pl->st.insertions++;
    pl->st.reseeds++;
    pl->close.exhaustive = 0;
    st = after_insert(pl, v);
    pl->phase = PH_RUN;
    return st;
}

/* ---------- seeds: the persistent facet and a fourth point per component ---------- */

static int seed_issue(vp_planner_t *pl, const double *dir, double range)
{
    memcpy(pl->probe.origin, pl->pool.vrec[pl->dev.at].p, sizeof pl->probe.origin);
    memcpy(pl->probe.dir, dir, sizeof pl->probe.dir);
    pl->probe.full = range;
    pl->probe.range = clamp_range(pl, range);
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
static int seed_miss_on(vp_planner_t *pl)
{
    double e[3];
    int st, limited = probe_limited(pl);
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
        if ((st = probe_proof(pl, &miss, &pf)) != VP_OK) return st;
        if ((st = walk_on(pl, pl->dev.at, pf, e)) != VP_OK) return st;
        pl->probe.chain_proof = pf;
    }
    memcpy(pl->probe.origin, e, sizeof e);
    memcpy(pl->seed.q, e, sizeof e);
    pl->probe.full -= pl->probe.range;
    pl->probe.range = clamp_range(pl, pl->probe.full);
    pl->seed.miss = 0;
    pl->probe.ready = 1;
    return 1;
}

/* exit distance from p along unit u out of Omega */
static double omega_exit(const vp_planner_config_t *c, const double *p, const double *u)
{
    double t0, t1;
    if (!omega_clip(c, p, u, 1e300, &t0, &t1)) return 0.0;
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

static int seed_next(vp_planner_t *pl)
{
    const double *o;
    double u[3], d[3], w1[3], w2[3], te, th;
    int k, st;
    if (pl->seed.cur >= pl->cfg.ninterior) return 1; /* all seeds probed */
    o = pl->cfg.interior[pl->seed.cur];
    vp_sub3(u, pl->cfg.start, o);
    if (!vp_normalize3(u)) { u[0] = 0; u[1] = 0; u[2] = 1; }
    switch (pl->seed.step) {
    case 0: /* from dOmega towards o */
        te = omega_exit(&pl->cfg, o, u);
        for (k = 0; k < 3; k++) pl->seed.q[k] = o[k] + te * u[k];
        if ((st = plan_route(pl, NONE, pl->seed.q)) != VP_OK) return st;
        for (k = 0; k < 3; k++) d[k] = -u[k];
        return seed_issue(pl, d, te);
    case 1:
    case 2: /* two directions very close to [q, a): the persistent facet */
        th = pl->cfg.eps / (8.0 * vp_dist3(pl->seed.q, pl->seed.pts[pl->seed.npts - 1])) /
             (double)(1u << (2 * (pl->seed.attempt / 2)));
        seed_axes(u, (int)pl->seed.attempt, w1, w2);
        for (k = 0; k < 3; k++) d[k] = -u[k] + th * (pl->seed.step == 1 ? w1[k] : w2[k]);
        vp_normalize3(d);
        return seed_issue(pl, d, 2.0 * vp_dist3(pl->seed.q, o) + pl->cfg.eps);
    default: /* a fourth point, from the other side of Omega */
        for (k = 0; k < 3; k++) d[k] = -u[k];
        te = omega_exit(&pl->cfg, o, d);
        {
            double q2[3];
            for (k = 0; k < 3; k++) q2[k] = o[k] + te * d[k];
            if ((st = plan_route(pl, NONE, q2)) != VP_OK) return st;
        }
        return seed_issue(pl, u, te);
    }
}

static int seed_feed(vp_planner_t *pl, const vp_probe_result_t *res_in)
{
    double h[3];
    int k;
    vp_probe_result_t r = *res_in;
    const vp_probe_result_t *res = &r;
    if (r.hit == VP_PROBE_TOO_CLOSE) r.hit = 0; /* no usable sample: like a miss */
    if (res->hit)
        for (k = 0; k < 3; k++) h[k] = pl->probe.origin[k] + res->dist * pl->probe.dir[k];
    if (!res->hit && pl->seed.step != 1 && pl->seed.step != 2) {
        /* towards o_i: a hit is certain unless o_i is outside the object */
        int w = res_in->hit == VP_PROBE_TOO_CLOSE ? 0 : seed_miss_on(pl);
        if (w < 0) return w;
        return w ? VP_OK : VP_ERANGE;
    }
    switch (pl->seed.step) {
    case 0:
        memcpy(pl->seed.pts[pl->seed.npts++], h, sizeof h);
        pl->seed.step = 1;
        pl->seed.attempt = 0;
        return VP_OK;
    case 1:
    case 2:
        if (res->hit && vp_dist3(h, pl->seed.pts[pl->seed.npts - pl->seed.step]) <= pl->cfg.eps / 4.0) {
            memcpy(pl->seed.pts[pl->seed.npts++], h, sizeof h);
            if (pl->seed.step == 2) {
                /* legs short and the triangle not flat, else try other axes, smaller angles */
                const double *a = pl->seed.pts[pl->seed.npts - 3], *b = pl->seed.pts[pl->seed.npts - 2];
                double ab[3], ac[3], n[3], area2, l2;
                vp_sub3(ab, b, a);
                vp_sub3(ac, h, a);
                vp_cross3(n, ab, ac);
                area2 = sqrt(vp_dot3(n, n));
                l2 = vp_dot3(ab, ab) > vp_dot3(ac, ac) ? vp_dot3(ab, ab) : vp_dot3(ac, ac);
                if (!(area2 > 0.2 * l2) && pl->seed.attempt < 12) {
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
        if (pl->seed.attempt >= 12) return VP_ERANGE;
        if (pl->seed.step == 2) pl->seed.npts--;
        pl->seed.attempt++;
        pl->seed.step = 1;
        return VP_OK;
    default:
        memcpy(pl->seed.pts[pl->seed.npts++], h, sizeof h);
        pl->seed.cur++;
        pl->seed.step = 0;
        return VP_OK;
    }
}

/* All seed points in the triangulation; every outside Voronoi vertex is active. */
static int start_run(vp_planner_t *pl)
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
        pay(pl, t)[0] = (vp_dt_is_ghost(&pl->dt, t) || tet_point(pl, t, c) != VP_OK ||
                         !omega_inside(&pl->cfg, c)) ? VREC_OUT : NONE;
    }
    for (t = 0; t < pl->dt.ntet_slots; t++)
        if (vp_dt_alive(&pl->dt, t) && tet_active(pl, t))
            if ((st = explore(pl, t)) != VP_OK) return st;
    note_peak(pl);
    return VP_OK;
}

/* ---------- public ---------- */

int vp_planner_init(vp_planner_t *pl, void *arena, size_t bytes, const vp_planner_config_t *cfg)
{
    unsigned char *cur, *end;
    size_t dtb, unit;
    uint32_t i, hwords;
    int k, st;
    if (!pl || !arena || !cfg) return VP_EINVAL;
    if (cfg->omega_kind == VP_OMEGA_BALL) {
        if (!vp_finite3(cfg->omega_center) || !(cfg->omega_radius > 0.0) || !(cfg->omega_radius < 1e150))
            return VP_EINVAL;
    } else if (cfg->omega_kind == VP_OMEGA_BOX) {
        if (!vp_finite3(cfg->omega_lo) || !vp_finite3(cfg->omega_hi)) return VP_EINVAL;
        for (k = 0; k < 3; k++)
            if (!(cfg->omega_lo[k] < cfg->omega_hi[k])) return VP_EINVAL;
    } else {
        return VP_EINVAL;
    }
    if (!(cfg->eps > 0.0) || !(cfg->eps < 1e150)) return VP_EINVAL;
    if (cfg->ninterior < 1 || cfg->ninterior > VP_PLANNER_MAX_SEEDS) return VP_EINVAL;
    for (i = 0; i < cfg->ninterior; i++)
        if (!vp_finite3(cfg->interior[i]) || !omega_inside(cfg, cfg->interior[i])) return VP_EINVAL;
    if (!vp_finite3(cfg->start) || omega_inside(cfg, cfg->start)) return VP_EINVAL;
    if (!(cfg->min_angle >= 0.0) || cfg->min_angle > 30.0) return VP_EINVAL;
    if (!(cfg->max_range >= 0.0) || !(cfg->noise_tol >= 0.0) || !(cfg->clearance >= 0.0) ||
        cfg->max_range > 1e150 || cfg->noise_tol > 1e150 || cfg->clearance > 1e150)
        return VP_EINVAL;
    memset(pl, 0, sizeof *pl);
    pl->cfg = *cfg;
    cur = (unsigned char *)arena;
    end = cur + bytes;
    /* the split, per 100 units, from the peaks measured per output vertex (README): the
     * triangulation at least 29, records 20, proofs 16, free edges 6, facets 7, tasks 7, hash
     * 2-4, path search and hole scratch 8, paths 1, heap 1, route 1 */
    unit = bytes / 100;
    if (bytes < 64 * 1024) return VP_ENOMEM;
    pl->pool.cap_vrec = (uint32_t)(20 * unit / sizeof(vp_vrec_t));
    pl->pool.cap_frec = (uint32_t)(7 * unit / sizeof(vp_frec_t));
    pl->pool.cap_fedge = (uint32_t)(6 * unit / (4 * FEDGE_WORDS));
    for (hwords = 1; (size_t)hwords * 2 * 4 <= 4 * unit; hwords <<= 1) {}
    pl->pool.cap_astar = (uint32_t)(8 * unit / 4);
    pl->route.cap_path = (uint32_t)(unit / 4);
    pl->pool.cap_task = (uint32_t)(7 * unit / sizeof(vp_task_t));
    pl->pool.cap_heap = (uint32_t)(unit / 4);
    pl->route.cap = (uint32_t)(unit / 24);
    if (pl->route.cap > 4096) pl->route.cap = 4096;
    pl->pool.vrec = carve(&cur, end, (size_t)pl->pool.cap_vrec * sizeof(vp_vrec_t));
    pl->pool.frec = carve(&cur, end, (size_t)pl->pool.cap_frec * sizeof(vp_frec_t));
    pl->pool.fedge = carve(&cur, end, (size_t)pl->pool.cap_fedge * 4 * FEDGE_WORDS);
    pl->pool.fhash = carve(&cur, end, (size_t)hwords * 4);
    pl->pool.astar = carve(&cur, end, (size_t)pl->pool.cap_astar * 4);
    pl->route.path = carve(&cur, end, (size_t)pl->route.cap_path * 4);
    pl->pool.task = carve(&cur, end, (size_t)pl->pool.cap_task * sizeof(vp_task_t));
    pl->pool.heap = carve(&cur, end, (size_t)pl->pool.cap_heap * 4);
    pl->route.pts = carve(&cur, end, (size_t)pl->route.cap * 24);
    pl->route.proof = carve(&cur, end, (size_t)pl->route.cap * 4);
    pl->pool.cap_proof = (uint32_t)(PROOF_SHARE * unit / sizeof(vp_proof_t));
    pl->pool.proof = carve(&cur, end, (size_t)pl->pool.cap_proof * sizeof(vp_proof_t));
    if (!pl->route.proof || !pl->pool.proof || pl->pool.cap_proof < 64) return VP_ENOMEM;
    if (!pl->pool.vrec || !pl->pool.frec || !pl->pool.fedge || !pl->pool.fhash || !pl->pool.astar || !pl->route.path ||
        !pl->pool.task || !pl->pool.heap || !pl->route.pts || pl->pool.cap_vrec < 64 || pl->pool.cap_frec < 64 ||
        pl->pool.cap_task < 64 || pl->route.cap < 64 || pl->pool.cap_astar < 1024)
        return VP_ENOMEM;
    dtb = (size_t)(end - cur);
    if (dtb < 29 * unit) return VP_ENOMEM;
    st = vp_dt_init(&pl->dt, cur, dtb, KPAY * 4);
    if (st != VP_OK) return st == VP_EINVAL ? VP_ENOMEM : st;
    pl->pool.hash_mask = hwords - 1;
    for (i = 0; i < hwords; i++) pl->pool.fhash[i] = HASH_EMPTY;
    pl->pool.frec_free = NONE;
    pl->probe.cur_proof = pl->probe.chain_proof = PROOF_NONE;
    /* the slack of a proof: rounding of constructed points, far below any physical size */
    pl->ptol = 1e-10 * (1.0 + omega_circumradius(cfg));
    pl->phase = PH_SEED;
    {
        /* sin of the angle bound by its Taylor series (|x| <= pi/6: error below 1e-9) */
        double x = cfg->min_angle * 0.017453292519943295, x2 = x * x;
        pl->sin_angle = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))));
    }
    memcpy(pl->dev.pos, cfg->start, sizeof pl->dev.pos);
    st = rec_new(pl, cfg->start, NONE, REC_OUT, &pl->dev.at);
    if (st != VP_OK) return st;
    note_peak(pl);
    return VP_OK;
}

/* A PROBE goes out: what its result will prove is measured from this ray. */
static void issue_probe(vp_planner_t *pl, const vp_cmd_t *cmd)
{
    memcpy(pl->dev.iss_o, cmd->from, sizeof pl->dev.iss_o);
    memcpy(pl->dev.iss_d, cmd->dir, sizeof pl->dev.iss_d);
    pl->dev.iss_range = cmd->range;
    pl->probe.cur_proof = PROOF_NONE;
}

/* internal steps one vp_planner_next call may take without a command (plus 4 per task slot):
 * far above any real need, so hitting it means a rule loops */
#define STEP_BUDGET (1u << 20)

int vp_planner_next(vp_planner_t *pl, vp_cmd_t *cmd)
{
    int st;
    uint64_t budget;
    if (!pl || !cmd) return VP_EINVAL;
    if (pl->dev.awaiting) return VP_ESTATE;
    if (pl->error) return pl->error;
    memset(cmd, 0, sizeof *cmd);
    for (budget = STEP_BUDGET + 4u * (uint64_t)pl->pool.cap_task;; budget--) {
        if (budget == 0) {
            /* bounded work per call: a loop that issues nothing is reported, never spun */
            pl->st.stalls++;
            pl->error = VP_ESTALL;
            return VP_ESTALL;
        }
        if (pl->route.i < pl->route.n) {
            const double *to = pl->route.pts + 3 * (size_t)pl->route.i;
            /* the one promise: a MOVE only along a segment with a proof of freedom */
            if (!proof_covers(pl, pl->route.proof[pl->route.i], pl->dev.pos, to)) {
                pl->error = VP_EUNSAFE;
                return VP_EUNSAFE;
            }
            pl->route.i++;
            cmd->kind = VP_CMD_MOVE;
            memcpy(cmd->from, pl->dev.pos, sizeof cmd->from);
            memcpy(cmd->to, to, sizeof cmd->to);
            pl->st.travel += vp_dist3(pl->dev.pos, to);
            pl->st.moves++;
            memcpy(pl->dev.pos, to, sizeof pl->dev.pos);
            return VP_OK;
        }
        if (pl->sc.pending == 1) {
            const vp_vrec_t *a = &pl->pool.vrec[pl->sc.from], *b = &pl->pool.vrec[pl->sc.to];
            double d[3], len;
            vp_sub3(d, b->p, a->p);
            len = sqrt(vp_dot3(d, d));
            d[0] /= len; d[1] /= len; d[2] /= len;
            pl->sc.pending = 2;
            pl->dev.awaiting = 1;
            cmd->kind = VP_CMD_PROBE;
            memcpy(cmd->from, a->p, sizeof cmd->from);
            memcpy(cmd->dir, d, sizeof cmd->dir);
            cmd->range = len;
            pl->probe.chain_proof = PROOF_NONE;
            issue_probe(pl, cmd);
            pl->st.probes++;
            pl->st.shortcut_probes++;
            return VP_OK;
        }
        if (pl->probe.ready) {
            pl->probe.ready = 0;
            pl->dev.awaiting = 1;
            cmd->kind = VP_CMD_PROBE;
            memcpy(cmd->from, pl->probe.origin, sizeof cmd->from);
            memcpy(cmd->dir, pl->probe.dir, sizeof cmd->dir);
            cmd->range = pl->probe.range;
            issue_probe(pl, cmd);
            pl->st.probes++;
            return VP_OK;
        }
        switch (pl->phase) {
        case PH_SEED:
            st = seed_next(pl);
            if (st == 1) {
                st = start_run(pl);
                pl->phase = PH_RUN;
            }
            break;
        case PH_RUN:
            st = VP_OK;
            if (pl->pool.nheap > 0 && !exhaustive(pl) &&
                !(pl->pool.ntask > 0 && pl->pool.task[pl->pool.ntask - 1].off > 0.0)) {
                /* a known bad ball is refined at once: the probes still queued around it
                 * would mostly test facets that its insertion kills (the published rule
                 * finishes detect_access first). A range-limited probe in progress goes on
                 * first: the device stands at the end of its free part. */
                st = refine(pl);
            } else if (pl->pool.ntask > 0) {
                vp_task_t k = pl->pool.task[--pl->pool.ntask];
                if (task_start(pl, &k)) pl->probe.ready = 1;
                if (pl->sc.pending) pl->route.i = pl->route.n; /* hold the route: shortcut first */
                st = pl->error;
            } else if (pl->pool.nheap > 0) {
                st = refine(pl);
            } else {
                pl->phase = PH_CLOSE;
            }
            break;
        case PH_CLOSE:
            /* closing again with nothing probed or inserted since the last try cannot do
             * better: the holes stay (certify names them) */
            if (pl->close.mark == pl->st.probes + pl->st.insertions + 1) {
                pl->st.stalls++;
                pl->phase = PH_COMPONENTS;
                st = VP_OK;
                break;
            }
            pl->close.mark = pl->st.probes + pl->st.insertions + 1;
            st = close_holes(pl);
            pl->phase = st > 0 ? PH_RUN : PH_COMPONENTS;
            if (st > 0) st = VP_OK;
            break;
        case PH_COMPONENTS:
            st = check_components(pl);
            break;
        default:
            cmd->kind = VP_CMD_DONE;
            note_peak(pl);
            return VP_OK;
        }
        if (st < 0) {
            pl->error = st;
            return st;
        }
    }
}

int vp_planner_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    int st;
    if (!pl || !res) return VP_EINVAL;
    if (!pl->dev.awaiting) return VP_ESTATE;
    if (res->hit < 0 || res->hit > VP_PROBE_TOO_CLOSE) return VP_EINVAL;
    if (res->hit == 1 && (!(res->dist >= 0.0) || !(res->dist < 1e300))) return VP_EINVAL;
    pl->dev.awaiting = 0;
    if (pl->sc.pending == 2) {
        pl->sc.pending = 0;
        if (res->hit) {
            pl->st.hits++;
            if (pl->route.deferred) {
                pl->route.deferred = 0;
                st = route_full(pl, pl->sc.from, pl->sc.to);
                if (st != VP_OK) { pl->error = st; return st; }
            }
            pl->route.i = 0; /* the searched route stands */
            return VP_OK;
        }
        pl->st.misses++;
        if (pl->sc.tries < pl->cfg.confirm_misses) {
            pl->sc.tries++;
            pl->st.reprobes++;
            pl->sc.pending = 1;
            return VP_OK;
        }
        /* the straight way is free: take it */
        {
            uint32_t pf;
            pl->route.deferred = 0;
            st = probe_proof(pl, res, &pf);
            if (st == VP_OK) st = edge_add(pl, pl->sc.from, pl->sc.to, pf);
            if (st != VP_OK) { pl->error = st; return st; }
            pl->route.n = pl->route.i = 0;
            st = route_push(pl, pl->pool.vrec[pl->sc.to].p, pf);
            if (st != VP_OK) { pl->error = st; return st; }
        }
        return VP_OK;
    }
    if (pl->phase == PH_SEED) st = seed_feed(pl, res);
    else if (pl->phase == PH_RESEED) st = reseed_feed(pl, res);
    else st = task_finish(pl, res);
    if (st < 0) pl->error = st;
    return st;
}

uint32_t vp_planner_facet_slots(const vp_planner_t *pl) { return pl->pool.nfrec; }
uint32_t vp_planner_num_facets(const vp_planner_t *pl) { return pl->pool.nfacets; }
const vp_dt_t *vp_planner_dt(const vp_planner_t *pl) { return &pl->dt; }

int vp_planner_facet(const vp_planner_t *pl, uint32_t i, uint32_t v[3], double *radius, double center[3])
{
    const vp_frec_t *f;
    if (i >= pl->pool.nfrec) return 0;
    f = &pl->pool.frec[i];
    if (f->v[0] == NONE) return 0;
    v[0] = f->v[0];
    v[1] = (f->flags & FREC_FLIP) ? f->v[2] : f->v[1];
    v[2] = (f->flags & FREC_FLIP) ? f->v[1] : f->v[2];
    if (radius) *radius = f->r;
    if (center) memcpy(center, f->c, sizeof f->c);
    return 1;
}

void vp_planner_get_stats(const vp_planner_t *pl, vp_planner_stats_t *st)
{
    uint32_t i;
    *st = pl->st;
    st->bad_balls = pl->pool.nheap;
    st->missing_components = 0;
    for (i = 0; i < pl->cfg.ninterior; i++)
        st->missing_components += !(pl->close.h2_done & (1u << i));
    st->records = pl->pool.nvrec;
    st->free_edges = pl->pool.nfedge;
    st->facet_records = pl->pool.nfacets;
    st->max_ball = 0.0;
    for (i = 0; i < pl->pool.nfrec; i++)
        if (pl->pool.frec[i].v[0] != NONE && pl->pool.frec[i].r > st->max_ball) st->max_ball = pl->pool.frec[i].r;
}
