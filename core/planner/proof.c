/* proof.c — proofs of free space (the planner's safety rule; beyond the paper).
 * The paper moves the probe only along "current or former Voronoi edges" it knows to be free;
 * here every such segment names the free part of a probe that proves it (or "outside Omega",
 * assumption A2), checked when a free-graph edge is made and again before each MOVE. */
#include "vp_planner_priv.h"

/* ---------- proofs of free space ----------
 * The device moves only along a segment that names its proof: the free part of a probe (a
 * chain of probes along one ray, for a range-limited rangefinder), or PROOF_OUTSIDE (outside
 * Omega, assumption A2). Every free-graph edge and every route step carries one, checked
 * geometrically when the edge is made and again when the MOVE is issued. The paper's
 * inferences (a shrunken Voronoi edge stays free, a kept ball) only propose a proof: on
 * objects where they fail (flat faces, sharp edges: one crossing per edge no longer holds)
 * the check refuses the segment, and it is never travelled. */
#define PROOF_CHAIN_MAX 64u /* pieces of one walked ray looked at */

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
#if VP_PL_CONTACTS /* a microcontroller core's proofs never expire (cfg.proof_life is not read) */
    q->born = (uint32_t)(pl->st.probes + pl->st.moves);
#endif
    *out = pl->pool.nproof++;
#if VP_PL_TUBES
    vp_pl_tube_mark(pl, o, d, len);
#endif
    return VP_OK;
}

#if VP_PL_CONTACTS
/* A proof of its own (no chain): a segment the head has travelled (contact.c). */
VP_PL_API int vp_pl_proof_add(vp_planner_t *pl, const double *o, const double *d, double len, uint32_t *out)
{
    return proof_new(pl, o, d, len, PROOF_NONE, out);
}
#endif

/* 1 if x lies within tol of the line through p's origin along p's direction; *s its parameter */
static int on_line(const vp_proof_t *p, const double *x, double tol, double *s)
{
    double d[3];
    int k;
    vp_sub3(d, x, p->o);
    *s = vp_dot3(d, p->d);
    for (k = 0; k < 3; k++) d[k] -= *s * p->d[k];
    return vp_dot3(d, d) <= tol * tol;
}

/* 1 if proof id shows every point of [a, b] free: within pl->ptol of the ray and of its free
 * part (the union of the pieces of its chain), or the whole segment outside Omega. */
VP_PL_API int vp_pl_proof_covers(const vp_planner_t *pl, uint32_t id, const double *a, const double *b)
{
    double lo[PROOF_CHAIN_MAX], hi[PROOF_CHAIN_MAX], sa, sb, need0, need1, cur, tol = pl->ptol;
    const vp_proof_t *p;
    uint32_t n = 0, i, j;
    if (id == PROOF_OUTSIDE) return !vp_pl_seg_enters_omega(&pl->cfg, a, b);
#if VP_PL_TUBES
    if (id == PROOF_TUBE) return !vp_pl_seg_enters_omega(&pl->cfg, a, b) || vp_pl_tube_free(pl, a, b);
#endif
    if (id >= pl->pool.nproof) return 0;
    p = &pl->pool.proof[id];
    if (VP_PL_CONTACTS && !(p->len >= 0.0)) return 0; /* withdrawn by a contact */
    /* both ends on the ray's line */
    if (!on_line(p, a, tol, &sa) || !on_line(p, b, tol, &sb)) return 0;
    need0 = sa < sb ? sa : sb;
    need1 = sa < sb ? sb : sa;
    /* the free intervals of the chain on that line */
    for (i = id; i != PROOF_NONE && i < pl->pool.nproof && n < PROOF_CHAIN_MAX; i = pl->pool.proof[i].prev) {
        const vp_proof_t *q = &pl->pool.proof[i];
        double s0;
        if (!(vp_dot3(q->d, p->d) > 1.0 - DIR_COS_EPS) || !on_line(p, q->o, tol, &s0)) break;
        if (VP_PL_CONTACTS && !(q->len >= 0.0)) continue; /* a withdrawn piece covers nothing */
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
VP_PL_API int vp_pl_probe_proof(vp_planner_t *pl, const vp_probe_result_t *res, uint32_t *out)
{
    double len;
    int st;
    if (pl->probe.cur_proof != PROOF_NONE) { *out = pl->probe.cur_proof; return VP_OK; }
    *out = PROOF_NONE;
    if (res->hit == VP_PROBE_TOO_CLOSE) return VP_OK;
    len = res->hit ? res->dist - pl->cfg.noise_tol : pl->dev.iss_range;
    if (res->hit && len > pl->dev.iss_range) len = pl->dev.iss_range;
#if VP_PL_CONTACTS
    /* near a contact a miss may be a surface the rangefinder cannot see: no proof */
    if (pl->contact.n > 0 && len > 0.0 && vp_pl_contact_distrusts(pl, pl->dev.iss_o, pl->dev.iss_d, len)) {
        if (!res->hit) pl->st.dark_misses++;
        return VP_OK;
    }
#endif
    st = proof_new(pl, pl->dev.iss_o, pl->dev.iss_d, len, pl->probe.chain_proof, out);
    if (st == VP_OK) pl->probe.cur_proof = *out;
    return st;
}

/* ---------- a miss must be seen: the spot's sight line ----------
 * A triangulating rangefinder reads a miss when its camera finds no spot; it reads the same when
 * the spot is there but hidden from the camera (the far inner side of a torus lit through its
 * hole). Every spot the beam could make lies in the triangle (camera, origin, end of the range),
 * swept by its sight lines. Where S may stand in that triangle, a spot there may have been
 * hidden, and the miss proves nothing. S may stand wherever no probe has shown space free: the
 * occluders are the facets of the mesh found so far and the facets between a tet whose Voronoi
 * vertex no probe has reached (a part of space still unknown, the object's inside among it) and
 * one whose vertex was reached or lies outside Omega. Decided with exact orient3d on the points
 * given (touching counts as crossing; an occluder in the triangle's plane too). */

/* 1 when segment [s, t] meets triangle (a, b, c) that it does not lie in the plane of */
static int segment_meets_tri(const double *s, const double *t, const double *a, const double *b, const double *c)
{
    int os = vp_orient3d(a, b, c, s), ot = vp_orient3d(a, b, c, t), u, v, w;
    if ((os > 0 && ot > 0) || (os < 0 && ot < 0) || (os == 0 && ot == 0)) return 0;
    u = vp_orient3d(s, t, a, b);
    v = vp_orient3d(s, t, b, c);
    w = vp_orient3d(s, t, c, a);
    return (u >= 0 && v >= 0 && w >= 0) || (u <= 0 && v <= 0 && w <= 0);
}

/* 1 when triangles p and q meet (or lie in one plane: taken as meeting) */
static int tri_meets_tri(const double (*p)[3], const double (*q)[3])
{
    int i, sp = 0, sq = 0, zp = 0, zq = 0;
    for (i = 0; i < 3; i++) {
        int o = vp_orient3d(p[0], p[1], p[2], q[i]);
        sp += o;
        zp += o == 0;
        o = vp_orient3d(q[0], q[1], q[2], p[i]);
        sq += o;
        zq += o == 0;
    }
    if (sp == 3 || sp == -3 || sq == 3 || sq == -3) return 0; /* one wholly on one side of the other */
    if (zp == 3 || zq == 3) return 1;
    for (i = 0; i < 3; i++)
        if (segment_meets_tri(p[i], p[(i + 1) % 3], q[0], q[1], q[2]) ||
            segment_meets_tri(q[i], q[(i + 1) % 3], p[0], p[1], p[2]))
            return 1;
    return 0;
}

int vp_planner_sight_occluder(const vp_planner_t *pl, uint32_t i, double tri[3][3])
{
    int k;
    if (i < pl->pool.nfrec) {
        const vp_frec_t *f = &pl->pool.frec[i];
        if (!frec_in_mesh(f)) return 0;
        for (k = 0; k < 3; k++) memcpy(tri[k], vp_dt_point(&pl->dt, f->v[k]), sizeof tri[k]);
        return 1;
    }
    i -= pl->pool.nfrec;
    if (i / 4u >= pl->dt.ntet_slots) return -1;
    {
        uint32_t t = i / 4u, u;
        const uint32_t *w;
        int f = (int)(i % 4u);
        if (!vp_dt_alive(&pl->dt, t) || vp_dt_is_ghost(&pl->dt, t) || tet_active(pl, t)) return 0;
        w = vp_dt_tet(&pl->dt, t);
        u = w[4 + f] >> 2;
        if (!vp_dt_is_ghost(&pl->dt, u) && !tet_active(pl, u)) return 0;
        for (k = 0; k < 3; k++) memcpy(tri[k], vp_dt_point(&pl->dt, w[(f + 1 + k) & 3]), sizeof tri[k]);
        return 1;
    }
}

int vp_planner_spot_hidden(const vp_planner_t *pl, const double origin[3], const double dir[3], double range,
                           const double cam[3])
{
    double sweep[3][3], lo[3], hi[3], tri[3][3];
    uint32_t i;
    int q, got;
    if (!pl || !origin || !dir || !cam || !vp_finite3(origin) || !vp_finite3(dir) || !vp_finite3(cam) ||
        !vp_finite(range) || !(range >= 0.0))
        return VP_EINVAL;
    for (q = 0; q < 3; q++) {
        sweep[0][q] = cam[q];
        sweep[1][q] = origin[q];
        sweep[2][q] = origin[q] + range * dir[q];
        lo[q] = sweep[0][q] < sweep[1][q] ? sweep[0][q] : sweep[1][q];
        hi[q] = sweep[0][q] < sweep[1][q] ? sweep[1][q] : sweep[0][q];
        if (sweep[2][q] < lo[q]) lo[q] = sweep[2][q];
        if (sweep[2][q] > hi[q]) hi[q] = sweep[2][q];
    }
    for (i = 0; (got = vp_planner_sight_occluder(pl, i, tri)) >= 0; i++) {
        int out = 0;
        if (!got) continue;
        for (q = 0; q < 3 && !out; q++)
            out = (tri[0][q] < lo[q] && tri[1][q] < lo[q] && tri[2][q] < lo[q]) ||
                  (tri[0][q] > hi[q] && tri[1][q] > hi[q] && tri[2][q] > hi[q]);
        if (!out && tri_meets_tri((const double (*)[3])sweep, (const double (*)[3])tri)) return 1;
    }
    return 0;
}
