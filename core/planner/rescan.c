/* rescan.c — a second scan of an object that may have changed since the session so far (paper
 * 001's setting, one step at a time): nothing learnt before is used without being measured again.
 *
 *   - Free space: every proof made before the re-scan is stale (the object may have moved into
 *     it). A MOVE along a stale proof is preceded by a PROBE of the same segment from where the
 *     device stands; the MOVE goes only when that PROBE finds the segment free (a fresh proof,
 *     which the free graph keeps). A hit there is a point of S where the old proofs said free:
 *     every proof through it is withdrawn, the records no longer reached are lost (as after a
 *     contact), and the point becomes a sample.
 *   - Samples: each is measured again from outside Omega, along the line of the probe that found
 *     it (the surface Delaunay ball whose centre it was) or, where that line is blocked or the
 *     sample has none (seeds, contacts, a line laser's points), along its normal; where both are
 *     blocked (a concavity), from that probe's own origin inside Omega, reached over the free
 *     graph with every stale step proven again. Found again
 *     within the tolerance: kept, with its facets. Otherwise (the surface moved, receded, or
 *     something covers it; or no line from outside reaches it) it is removed (vp_dt_remove):
 *     its star's facets, and the facets of its neighbours, are dropped with the knowledge of
 *     their Voronoi edges, and probed again from the active Voronoi vertices around them.
 *   - Then the scan goes on as any scan: refinement, holes, components.
 * So a change is seen where it moves a sample or crosses one of the lines measured; the surface
 * between samples that hold is taken as unchanged (a change smaller than the sample spacing,
 * between the lines, can be missed: say so). The device never moves on a stale proof. */
#include "vp_planner_priv.h"

#if VP_PL_CONTACTS

/* a sample found again within this share of (1 + Omega's circumradius) is where it was: far
 * above the rounding of a re-measured distance, far below any physical size */
#define KEEP_TOL_REL 1e-9
/* a sample found again farther than that but within MOVE_REACH eps of where it was, on the line
 * measured, moved there: the point measured takes its place when no sample lies within
 * MOVE_SPACING eps of it (paper 001 moves each vertex with the surface and keeps any two R/3
 * apart). Farther: removed, and the refinement finds the surface there. A surface of another
 * part nearer than that on the line is thinner than eps/2: outside paper 000's range. */
#define MOVE_REACH 0.5
#define MOVE_SPACING (1.0 / 3.0)

/* A proof is stale when it was made before a re-scan, or (cfg.proof_life) when it or a piece of
 * its chain is older than the proofs' life: the object may have moved into it since. */
#define CHAIN_LOOK 64u
static int stale(const vp_planner_t *pl, uint32_t id)
{
    uint32_t now, n = 0;
    if (id >= pl->pool.nproof) return 0; /* outside Omega (A2), or none */
    if (pl->rescan.mark > 0 && id < pl->rescan.mark) return 1;
    if (pl->cfg.proof_life == 0) return 0;
    now = (uint32_t)(pl->st.probes + pl->st.moves);
    /* the pieces vp_pl_proof_covers may use: a withdrawn one covers nothing and is not counted */
    for (; id < pl->pool.nproof && n < CHAIN_LOOK; id = pl->pool.proof[id].prev) {
        if (!(pl->pool.proof[id].len >= 0.0)) continue;
        n++;
        if (now - pl->pool.proof[id].born > pl->cfg.proof_life) return 1;
    }
    return 0;
}

/* 1 if the next MOVE of the route rests on a stale proof: it is probed first */
VP_PL_API int vp_pl_step_stale(const vp_planner_t *pl)
{
    return (pl->rescan.mark > 0 || pl->cfg.proof_life > 0) && pl->route.i < pl->route.n &&
           stale(pl, pl->route.proof[pl->route.i]);
}

/* vertex record v is a sample in the triangulation now */
static int in_set(const vp_planner_t *pl, uint32_t v)
{
    uint32_t t = vp_dt_vertex(&pl->dt, v)->tet, k;
    const uint32_t *w;
    if (t >= pl->dt.ntet_slots || !vp_dt_alive(&pl->dt, t)) return 0;
    w = vp_dt_tet(&pl->dt, t);
    for (k = 0; k < 4; k++)
        if (w[k] == v) return 1;
    return 0;
}

/* The outward normal of sample v: the sum of its oriented facets' normals (zero: none). The
 * tets around v go into the scratch (VP_PL_SCRATCH: nothing holds it between commands). */
static int outward_normal(vp_planner_t *pl, uint32_t v, double *nrm)
{
    uint32_t *inc;
    int n = vp_pl_incident(pl, v, 0, &inc), i, f;
    nrm[0] = nrm[1] = nrm[2] = 0.0;
    if (n < 0) return n == VP_ENOMEM ? VP_OK : n;
    for (i = 0; i < n; i++) {
        const uint32_t *w = vp_dt_tet(&pl->dt, inc[i]);
        for (f = 0; f < 4; f++) {
            uint32_t fv[3], r;
            double ab[3], ac[3], c[3];
            int k;
            if (w[f] == v || vp_pl_facet_has_ghost(pl, inc[i], f)) continue;
            vp_dt_facet(&pl->dt, inc[i], f, fv);
            if ((r = vp_pl_frec_lookup(pl, fv)) == NONE) continue;
            {
                const uint32_t *s = pl->pool.frec[r].v;
                const double *a = vp_dt_point(&pl->dt, s[0]);
                vp_sub3(ab, vp_dt_point(&pl->dt, s[1]), a);
                vp_sub3(ac, vp_dt_point(&pl->dt, s[2]), a);
                vp_cross3(c, ab, ac);
                if (pl->pool.frec[r].flags & FREC_FLIP) for (k = 0; k < 3; k++) c[k] = -c[k];
                for (k = 0; k < 3; k++) nrm[k] += c[k];
            }
        }
    }
    if (!vp_normalize3(nrm)) nrm[0] = nrm[1] = nrm[2] = 0.0;
    return VP_OK;
}

/* The line to measure sample v along: unit d towards the surface. 1: found; 0: none left. */
static int sample_line(vp_planner_t *pl, uint32_t v, uint32_t along, double *d)
{
    if (along == 0) {
        uint32_t id = (vp_dt_vertex(&pl->dt, v)->aux & AUX_PROOF);
        if (id == 0 && v < pl->seed.npts && !memcmp(vp_dt_point(&pl->dt, v), pl->seed.pts[v], sizeof pl->seed.pts[v])) {
            /* a seed (start_run inserts them first, in order): the ray it was found along */
            memcpy(d, pl->seed.ray[v], 3 * sizeof(double));
            return 1;
        }
        if (id == 0 || id - 1 >= pl->pool.nproof) return 0;
        memcpy(d, pl->pool.proof[id - 1].d, 3 * sizeof(double));
        return 1;
    }
    if (outward_normal(pl, v, d) != VP_OK || (d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0)) return 0;
    d[0] = -d[0]; d[1] = -d[1]; d[2] = -d[2];
    return 1;
}

/* A route with a shortcut proposed (vp_pl_plan_route): the straight way is probed first, as for
 * a task, and the route waits for its answer. */
static void hold_for_shortcut(vp_planner_t *pl)
{
    if (pl->sc.to == NONE) return;
    pl->sc.from = pl->route.from;
    pl->sc.tries = 0;
    pl->sc.pending = 1;
    pl->route.i = pl->route.n;
}

/* The route to a measuring point planned (st: its status): the PROBE along unit d, the sample
 * expected at distance e. 1: prepared; 0: no way there; < 0: an error. */
static int measure_along(vp_planner_t *pl, int st, const double *d, double e)
{
    if (st < 0) return st;
    if (st == PL_UNREACHABLE) return 0;
    pl->rescan.expect = e;
    pl->rescan.tries = 0;
    /* far enough past the sample to see a surface that receded (then not where it was) */
    VP_TRY(vp_pl_seed_issue(pl, d, e + pl->cfg.eps));
    hold_for_shortcut(pl);
    return 1;
}

/* Puts the device outside Omega on the line through sample v along d and prepares the PROBE
 * towards it. 1: prepared; 0: no way there. */
static int measure_from_outside(vp_planner_t *pl, uint32_t v, const double *d)
{
    const double *p = vp_dt_point(&pl->dt, v);
    double back[3], q[3], te;
    int k, st;
    for (k = 0; k < 3; k++) back[k] = -d[k];
    te = vp_pl_omega_exit(&pl->cfg, p, back);
    if (!(te > 0.0)) return 0;
    for (k = 0; k < 3; k++) q[k] = p[k] + te * back[k];
    if (pl->cfg.max_range > 0.0 && te > pl->cfg.max_range) return 0; /* out of the rangefinder's reach */
    /* round Omega, outside it; from inside (after measuring from an origin there) out over
     * the free graph first */
    st = vp_pl_omega_inside(&pl->cfg, pl->dev.pos) ? vp_pl_plan_route(pl, NONE, q) : vp_pl_route_outside(pl, q);
    return measure_along(pl, st, d, te);
}

/* From where the probe that found sample v stood (a record inside Omega: the device goes there
 * over the free graph, proving each stale step again on the way), along that probe's ray.
 * 1: prepared; 0: no record there or no way to it. */
static int measure_from_origin(vp_planner_t *pl, uint32_t v)
{
    uint32_t id = (vp_dt_vertex(&pl->dt, v)->aux & AUX_PROOF) - 1u, r;
    const vp_proof_t *q;
    double d[3], e;
    int st;
    if (id >= pl->pool.nproof) return 0;
    q = &pl->pool.proof[id];
    if (!vp_pl_omega_inside(&pl->cfg, q->o) || (r = vp_pl_rec_at(pl, q->o)) == NONE) return 0;
    memcpy(d, q->d, sizeof d);
    e = vp_dot3(d, vp_dt_point(&pl->dt, v)) - vp_dot3(d, q->o);
    if (!(e > 0.0)) return 0;
    st = vp_pl_plan_route(pl, r, NULL);
    return measure_along(pl, st, d, e);
}

/* No line of this pass reached sample v: from inside in the next pass, or removed (unseen). */
static int drop_sample(vp_planner_t *pl, uint32_t v);
static void unskip_neighbours(vp_planner_t *pl, uint32_t nr);
static int line_exhausted(vp_planner_t *pl, uint32_t v)
{
    vp_dt_vertex_t *r = vp_dt_vertex(&pl->dt, v);
    pl->rescan.cur = NONE;
    if (pl->rescan.pass == 0) {
        r->aux |= AUX_DEFER;
        return VP_OK;
    }
    r->aux &= ~AUX_DEFER;
    pl->st.rescan_unseen++;
    return drop_sample(pl, v);
}

/* The star of v, its neighbours' facets: dropped (facet records, side results) and probed
 * again from the active Voronoi vertices around them. Called before v leaves the triangulation;
 * the tets around v and then those around each neighbour go into the scratch. */
static void forget_facets_at(vp_planner_t *pl, uint32_t u, uint32_t held)
{
    uint32_t *inc;
    int n = vp_pl_incident(pl, u, held, &inc), i, f;
    for (i = 0; i < n; i++) {
        uint32_t t = inc[i];
        const uint32_t *w = vp_dt_tet(&pl->dt, t);
        for (f = 0; f < 4; f++) {
            uint32_t fv[3], r, nb = w[4 + f] >> 2, j = w[4 + f] & 3u;
            if (w[f] == u || vp_pl_facet_has_ghost(pl, t, f)) continue;
            vp_dt_facet(&pl->dt, t, f, fv);
            if ((r = vp_pl_frec_lookup(pl, fv)) != NONE) vp_pl_frec_delete(pl, r);
            side_set(pl, t, f, side_get(pl, t, f) & SIDE_QUEUED);
            side_set(pl, nb, (int)j, side_get(pl, nb, (int)j) & SIDE_QUEUED);
        }
    }
}

static int explore_around(vp_planner_t *pl, uint32_t u, uint32_t held)
{
    uint32_t *inc;
    int n = vp_pl_incident(pl, u, held, &inc), i, f;
    if (n < 0) return n;
    for (i = 0; i < n; i++) {
        uint32_t t = inc[i];
        const uint32_t *w = vp_dt_tet(&pl->dt, t);
        if (tet_active(pl, t)) { VP_TRY(vp_pl_explore(pl, t)); continue; }
        /* an inactive tet: its active neighbours probe towards it */
        for (f = 0; f < 4; f++) {
            uint32_t nb = w[4 + f] >> 2, j = w[4 + f] & 3u;
            if (tet_active(pl, nb) && (side_get(pl, nb, (int)j) & SIDE_MASK) == SIDE_UNKNOWN &&
                !vp_pl_facet_has_ghost(pl, t, f))
                VP_TRY(vp_pl_task_push(pl, nb, (int)j, 0));
        }
    }
    return VP_OK;
}

/* The neighbours of v (the vertices of its star) into the scratch's front: their count. */
static uint32_t neighbours(vp_planner_t *pl, uint32_t v, uint32_t cap)
{
    uint32_t *ring = pl->pool.astar, *inc, nr = 0, k;
    int n = vp_pl_incident(pl, v, cap, &inc), i;
    for (i = 0; i < n; i++) {
        const uint32_t *w = vp_dt_tet(&pl->dt, inc[i]);
        for (k = 0; k < 4; k++) {
            uint32_t x = w[k], j;
            if (x == v || x == VP_DT_GHOST) continue;
            for (j = 0; j < nr && ring[j] != x; j++) {}
            if (j == nr && nr < cap) ring[nr++] = x;
        }
    }
    return nr;
}

#define RING_CAP 512u /* neighbours of one sample kept (a good mesh's have some 15) */

/* Removes sample v from the triangulation: the tets filling its star are new (no record,
 * nothing known of their sides), and the active Voronoi vertices around probe towards them. */
static int remove_sample(vp_planner_t *pl, uint32_t v, uint32_t nr)
{
    uint32_t i, nc, q;
    const uint32_t *created;
    int st;
    for (i = 0; i < nr; i++) { /* their stars change */
        vp_dt_vertex(&pl->dt, pl->pool.astar[i])->aux &= ~AUX_NRM;
        vp_pl_sample_touch(pl, pl->pool.astar[i]);
    }
    st = vp_dt_remove(&pl->dt, v);
    if (st != VP_OK) return st;
    created = vp_dt_last_created(&pl->dt, &nc);
    for (q = 0; q < nc; q++) {
        uint32_t *w = pay(pl, created[q]), k;
        double c[3];
        w[0] = (vp_dt_is_ghost(&pl->dt, created[q]) || vp_pl_tet_point(pl, created[q], c) != VP_OK ||
                !vp_pl_omega_inside(&pl->cfg, c)) ? VREC_OUT : NONE;
        w[1] = 0;
        for (k = 0; k < 4; k++) w[2 + k] = PROOF_NONE;
    }
    pl->close.exhaustive = 0;
    for (i = 0; i < nr; i++)
        if (in_set(pl, pl->pool.astar[i])) VP_TRY(explore_around(pl, pl->pool.astar[i], nr));
    vp_pl_note_peak(pl);
    return VP_OK;
}

/* a triangulation keeps this many samples at least (vp_dt_remove drops to a flat set below) */
#define KEEP_MIN 5u

/* Before v's facets are forgotten: room for the update, the facet hash current, v's neighbours
 * listed at the scratch's front (*nr of them). */
static int ready_to_forget(vp_planner_t *pl, uint32_t v, uint32_t *nr)
{
    if (pl->pool.cap_astar < 4u * RING_CAP || !vp_pl_pools_have_room(pl)) return VP_ENOMEM;
    if (pl->pool.fhash_dirty) { vp_pl_fhash_rebuild(pl); pl->pool.fhash_dirty = 0; }
    *nr = neighbours(pl, v, RING_CAP);
    forget_facets_at(pl, v, *nr);
    return VP_OK;
}

/* Sample v is not where it was: its facets and its neighbours' are forgotten, and it is removed;
 * while too few samples are left for that (the whole object moved), it waits (doomed) until
 * new samples are in. */
static int drop_sample(vp_planner_t *pl, uint32_t v)
{
    uint32_t nr, i;
    pl->st.rescan_dropped++;
    VP_TRY(ready_to_forget(pl, v, &nr));
    if (pl->phase == PH_VERIFY) unskip_neighbours(pl, nr);
    for (i = 0; i < nr; i++) forget_facets_at(pl, pl->pool.astar[i], nr);
    if (pl->dt.ninserted <= KEEP_MIN) {
        if (pl->rescan.ndoomed >= sizeof pl->rescan.doomed / sizeof pl->rescan.doomed[0]) return VP_ENOMEM;
        pl->rescan.doomed[pl->rescan.ndoomed++] = v;
        return VP_OK;
    }
    return remove_sample(pl, v, nr);
}

/* The doomed samples go as soon as the triangulation keeps 3D without them (planner.c calls
 * this before each refinement step while any wait). */
VP_PL_API int vp_pl_remove_doomed(vp_planner_t *pl)
{
    while (pl->rescan.ndoomed > 0 && pl->dt.ninserted > KEEP_MIN) {
        uint32_t v = pl->rescan.doomed[--pl->rescan.ndoomed], nr;
        if (!in_set(pl, v)) continue;
        VP_TRY(ready_to_forget(pl, v, &nr)); /* its neighbours' were forgotten when it was doomed */
        VP_TRY(remove_sample(pl, v, nr));
    }
    return VP_OK;
}

/* samples looked at for the nearest next one: the head's travel between them is machine time
 * (with a body, round Omega); vertex order alone is already roughly local */
#define NEAR_SAMPLES 128u

/* pass 0: every sample not left out (AUX_SKIP); pass 1: those deferred to it (AUX_DEFER), with
 * AUX_SKIP too when a sparse re-scan left one out until a neighbour moved in pass 1 */
static int wanted(const vp_planner_t *pl, uint32_t v)
{
    uint32_t a = vp_dt_vertex(&pl->dt, v)->aux;
    return !(a & AUX_TAKEN) && in_set(pl, v) && (pl->rescan.pass == 0 ? !(a & AUX_SKIP) : (a & AUX_DEFER) != 0);
}

/* A sparse re-scan: the samples left out, greedily in vertex order, no two of them neighbours
 * (a maximal independent set of the Delaunay graph; hull samples too: their ghost neighbour is
 * not a sample). The scratch holds each one's neighbours in turn. */
static void choose_skipped(vp_planner_t *pl)
{
    uint32_t v, i, nr;
    for (v = 0; v < pl->dt.nvert; v++) {
        if (!in_set(pl, v)) continue;
        nr = neighbours(pl, v, RING_CAP);
        if (nr < 3) continue;
        for (i = 0; i < nr && !(vp_dt_vertex(&pl->dt, pl->pool.astar[i])->aux & AUX_SKIP); i++) {}
        if (i == nr) vp_dt_vertex(&pl->dt, v)->aux |= AUX_SKIP;
    }
}

/* The neighbours of a sample not where it was (the scratch's front, nr of them): those left out
 * are measured after all, in the current pass (the cursor goes back to them); in pass 1 from
 * outside first, as pass 0 would have (AUX_DEFER with AUX_SKIP kept: measure_next). */
static void unskip_neighbours(vp_planner_t *pl, uint32_t nr)
{
    uint32_t i;
    for (i = 0; i < nr; i++) {
        uint32_t u = pl->pool.astar[i];
        vp_dt_vertex_t *r = vp_dt_vertex(&pl->dt, u);
        if (!(r->aux & AUX_SKIP) || (r->aux & AUX_DEFER)) continue;
        if (pl->rescan.pass == 1) r->aux |= AUX_DEFER;
        else r->aux &= ~AUX_SKIP;
        if (u < pl->rescan.next) pl->rescan.next = u;
    }
}

/* Where sample v is measured from in pass 0 (on dOmega along its probe's line, into q), else
 * the sample itself. */
static const double *measuring_point(vp_planner_t *pl, uint32_t v, double *q)
{
    double d[3], te;
    const double *p = vp_dt_point(&pl->dt, v);
    int k;
    if (pl->rescan.pass != 0 || !sample_line(pl, v, 0, d)) return p;
    for (k = 0; k < 3; k++) d[k] = -d[k];
    te = vp_pl_omega_exit(&pl->cfg, p, d);
    for (k = 0; k < 3; k++) q[k] = p[k] + te * d[k];
    return q;
}

/* Of the next NEAR_SAMPLES samples this pass still wants (in vertex order), the one nearest the
 * head, taken; NONE when the cursor moved past samples not wanted (call again). */
static uint32_t next_sample(vp_planner_t *pl)
{
    uint32_t v, seen = 0, best = NONE;
    double bd = VP_PL_HUGE, q[3];
    while (pl->rescan.next < pl->rescan.nvert && !wanted(pl, pl->rescan.next)) pl->rescan.next++;
    for (v = pl->rescan.next; v < pl->rescan.nvert && seen < NEAR_SAMPLES; v++) {
        double d;
        if (!wanted(pl, v)) continue;
        seen++;
        d = vp_dist3(pl->dev.pos, measuring_point(pl, v, q));
        if (d < bd) { bd = d; best = v; }
    }
    if (best != NONE) vp_dt_vertex(&pl->dt, best)->aux |= AUX_TAKEN;
    return best;
}

/* The next sample to measure: the route there and its PROBE prepared (1), or none left (0).
 * Pass 0 measures every sample from outside Omega; those no line from outside reaches wait for
 * pass 1, which goes inside to their probes' origins (one trip through the free graph for all
 * of them, the stale steps proven once). */
static int measure_next(vp_planner_t *pl)
{
    double d[3];
    int st;
    for (;;) {
        uint32_t v, last = pl->rescan.pass == 0 ? 2u : 3u;
        if (pl->rescan.cur == NONE) {
            if (pl->rescan.next >= pl->rescan.nvert) {
                uint32_t u;
                if (pl->rescan.pass == 1) return 0;
                pl->rescan.pass = 1;
                pl->rescan.next = 0;
                for (u = 0; u < pl->rescan.nvert; u++) vp_dt_vertex(&pl->dt, u)->aux &= ~AUX_TAKEN;
                continue;
            }
            v = next_sample(pl);
            if (v == NONE) continue;
            pl->rescan.cur = v;
            /* pass 1 goes in to the probe's origin, but a sample a sparse re-scan left out until
             * then gets the lines from outside first */
            pl->rescan.along = pl->rescan.pass == 0 || (vp_dt_vertex(&pl->dt, v)->aux & AUX_SKIP) ? 0u : 2u;
            vp_dt_vertex(&pl->dt, v)->aux &= ~AUX_SKIP;
        }
        v = pl->rescan.cur;
        while (pl->rescan.along < last) {
            uint32_t along = pl->rescan.along++;
            if (!sample_line(pl, v, along == 2 ? 0 : along, d)) continue;
            if (along == 1) pl->st.rescan_normal++;
            st = along == 2 ? measure_from_origin(pl, v) : measure_from_outside(pl, v, d);
            if (st != 0) return st;
        }
        VP_TRY(line_exhausted(pl, v));
    }
}

/* Every sample measured: the scan goes on. Sides still queued lost their tasks at the start;
 * every active Voronoi vertex is explored again (a finished session's needs nothing). */
static int verify_done(vp_planner_t *pl)
{
    uint32_t t;
    pl->phase = PH_RUN;
    for (t = 0; t < pl->dt.nvert; t++) {
        vp_dt_vertex_t *r = vp_dt_vertex(&pl->dt, t);
        if ((r->aux & AUX_SKIP) && in_set(pl, t)) pl->st.rescan_skipped++;
        r->aux &= ~AUX_SKIP;
    }
    for (t = 0; t < pl->dt.ntet_slots; t++)
        if (vp_dt_alive(&pl->dt, t) && tet_active(pl, t) && !vp_dt_is_ghost(&pl->dt, t))
            VP_TRY(vp_pl_explore(pl, t));
    return VP_OK;
}

VP_PL_API int vp_pl_verify_next(vp_planner_t *pl)
{
    int st = measure_next(pl);
    if (st < 0) return st;
    if (st == 0) return verify_done(pl);
    return VP_OK;
}

/* The sample being measured, v, is done with: kept, or (drop) removed by the next
 * vp_planner_next (an error there, such as a full arena, leaves this PROBE's record replayable). */
static int measured(vp_planner_t *pl, uint32_t v, int drop)
{
    pl->rescan.cur = NONE;
    vp_dt_vertex(&pl->dt, v)->aux &= ~AUX_DEFER;
    if (drop) pl->rescan.drop = v;
    return VP_OK;
}

VP_PL_API int vp_pl_verify_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    uint32_t v = pl->rescan.cur;
    double tol = pl->rescan.tol, e = pl->rescan.expect;
    if (res->hit == 1 && fabs(res->dist - e) <= tol) {
        pl->st.rescan_kept++;
        return measured(pl, v, 0);
    }
    if (res->hit == 0 && pl->rescan.tries < pl->cfg.confirm_misses) {
        /* a miss where the sample should be: a dropout, or the surface gone; look again */
        pl->rescan.tries++;
        pl->st.reprobes++;
        pl->probe.ready = 1;
        return VP_OK;
    }
    if (res->hit == 1 && fabs(res->dist - e) <= MOVE_REACH * pl->cfg.eps) {
        /* near where it was, on the line measured: the sample moved there (its line goes with it
         * where it was measured along that line; along its normal, it keeps none) */
        int k;
        pl->rescan.move = 1;
        for (k = 0; k < 3; k++) pl->rescan.move_to[k] = pl->dev.iss_o[k] + res->dist * pl->dev.iss_d[k];
        pl->rescan.move_aux = pl->rescan.along == 2u ? 0u : (vp_dt_vertex(&pl->dt, v)->aux & AUX_PROOF);
        return measured(pl, v, 1);
    }
    if ((res->hit == 1 && res->dist < e - tol) || res->hit == VP_PROBE_TOO_CLOSE) {
        /* something nearer along this line: covered, or only blocked from here */
        if (pl->rescan.along < (pl->rescan.pass == 0 ? 2u : 3u)) return VP_OK; /* the next line */
        if (pl->rescan.pass == 0) return line_exhausted(pl, v);
        pl->st.rescan_unseen++;
        return measured(pl, v, 1);
    }
    /* not where it was */
    return measured(pl, v, 1);
}

/* The PROBE of a stale route step: from the device along the step (unit d), its length in
 * the rangefinder's reach (*range). 0: the step has no length (nothing to prove). */
VP_PL_API int vp_pl_reprove_dir(vp_planner_t *pl, double *d, double *range)
{
    const double *to = pl->route.pts + 3 * (size_t)pl->route.i;
    double len;
    vp_sub3(d, to, pl->dev.pos);
    len = sqrt(vp_dot3(d, d));
    if (!vp_normalize3(d)) {
        pl->route.proof[pl->route.i] = PROOF_OUTSIDE; /* a MOVE of no length */
        return 0;
    }
    *range = vp_pl_clamp_range(pl, len);
    pl->rescan.reprove = 1;
    return 1;
}

/* The free graph's edges between the step's two ends that named the stale proof take the
 * fresh one: later routes over them need no probe. */
static void renew_edges(vp_planner_t *pl, uint32_t old, uint32_t fresh, const double *a, const double *b)
{
    uint32_t e;
    for (e = 0; e < pl->pool.nfedge; e++) {
        uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
        const double *p, *q;
        if (w[4] != old) continue;
        p = pl->pool.vrec[w[0]].p;
        q = pl->pool.vrec[w[1]].p;
        if ((vp_dist3(p, a) <= pl->ptol && vp_dist3(q, b) <= pl->ptol) ||
            (vp_dist3(p, b) <= pl->ptol && vp_dist3(q, a) <= pl->ptol))
            w[4] = fresh;
    }
    /* the prev chains' links (travel along prev chains reads them) */
    for (e = 0; e < pl->pool.nvrec; e++) {
        vp_vrec_t *r = &pl->pool.vrec[e];
        const double *p, *q;
        if (r->proof != old || r->prev == e || r->prev >= pl->pool.nvrec) continue;
        p = r->p;
        q = pl->pool.vrec[r->prev].p;
        if ((vp_dist3(p, a) <= pl->ptol && vp_dist3(q, b) <= pl->ptol) ||
            (vp_dist3(p, b) <= pl->ptol && vp_dist3(q, a) <= pl->ptol))
            r->proof = fresh;
    }
}

/* Puts a waypoint on the current route step, `at` along it from the device, with proof `pf`:
 * the step's first part is free again, its rest is still stale (probed from there). */
static int split_step(vp_planner_t *pl, double at, uint32_t pf)
{
    uint32_t i = pl->route.i, j;
    const double *to = pl->route.pts + 3 * (size_t)i;
    double d[3], w[3];
    int k;
    if (pl->route.n >= pl->route.cap) return VP_ENOMEM;
    vp_sub3(d, to, pl->dev.pos);
    vp_normalize3(d);
    for (k = 0; k < 3; k++) w[k] = pl->dev.pos[k] + at * d[k];
    for (j = pl->route.n; j > i; j--) {
        memcpy(pl->route.pts + 3 * (size_t)j, pl->route.pts + 3 * (size_t)(j - 1), 3 * sizeof(double));
        pl->route.proof[j] = pl->route.proof[j - 1];
    }
    memcpy(pl->route.pts + 3 * (size_t)i, w, sizeof w);
    pl->route.proof[i] = pf;
    pl->route.n++;
    return VP_OK;
}

VP_PL_API int vp_pl_reprove_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    const double *to = pl->route.pts + 3 * (size_t)pl->route.i;
    double len = vp_dist3(pl->dev.pos, to), free_len;
    uint32_t old = pl->route.proof[pl->route.i], fresh;
    int k;
    pl->rescan.reprove = 0;
    if (res->hit == 0 && pl->rescan.tries < pl->cfg.confirm_misses) {
        pl->rescan.tries++;
        pl->st.reprobes++;
        return VP_OK; /* the step is still stale: probed again (a dropout hides a surface) */
    }
    pl->rescan.tries = 0;
    /* the free part this PROBE shows (a miss: its range; a hit: up to the noise before it);
     * near a contact it proves nothing (a surface the rangefinder cannot see), as any probe's
     * (vp_pl_probe_proof) */
    free_len = res->hit == 0 ? pl->dev.iss_range : res->hit == 1 ? res->dist - pl->cfg.noise_tol : 0.0;
    if (free_len > 0.0 && pl->contact.n > 0 && vp_pl_contact_distrusts(pl, pl->dev.iss_o, pl->dev.iss_d, free_len))
        free_len = 0.0;
    if (free_len >= len - pl->ptol) {
        /* free again: a fresh proof of the step */
        VP_TRY(vp_pl_proof_add(pl, pl->dev.iss_o, pl->dev.iss_d, len, &fresh));
        if (fresh == PROOF_NONE) return VP_EUNSAFE;
        renew_edges(pl, old, fresh, pl->dev.pos, to);
        pl->route.proof[pl->route.i] = fresh;
        pl->st.reproved++;
        return VP_OK;
    }
    if (res->hit == 0 && free_len > 0.0 && pl->dev.iss_range < len - pl->ptol) {
        /* a step longer than the rangefinder's reach: its first part is free again; the rest is
         * probed from there */
        VP_TRY(vp_pl_proof_add(pl, pl->dev.iss_o, pl->dev.iss_d, free_len, &fresh));
        if (fresh == PROOF_NONE) return VP_EUNSAFE;
        return split_step(pl, free_len, fresh);
    }
    /* blocked (or not provable: near a contact): the old proofs there are false; handled by the
     * next vp_planner_next (an error there leaves this PROBE's record replayable). A hit is the
     * point that blocks only when it lies before the step's end (one at its very end, not
     * provable near a contact, may lie past Omega) */
    pl->st.reprove_blocked++;
    pl->rescan.blocked = res->hit == 1 && res->dist - pl->cfg.noise_tol < len - pl->ptol ? 1 : 2;
    pl->rescan.blocked_proof = old;
    for (k = 0; k < 3; k++) pl->rescan.blocked_at[k] = pl->dev.iss_o[k] + res->dist * pl->dev.iss_d[k];
    return VP_OK;
}

/* What the last PROBE asked for (vp_planner_next, before anything else): a blocked route step's
 * withdrawal, or a moved sample's removal. */
VP_PL_API int vp_pl_rescan_pending(vp_planner_t *pl)
{
    if (pl->rescan.blocked) {
        int b = pl->rescan.blocked;
        pl->rescan.blocked = 0;
        VP_TRY(vp_pl_withdraw_at(pl, b == 1 ? pl->rescan.blocked_at : NULL, pl->rescan.blocked_proof));
    }
    if (pl->rescan.drop != NONE && pl->rescan.mark > 0) {
        uint32_t v = pl->rescan.drop, nv;
        int moved = pl->rescan.move, st;
        pl->rescan.drop = NONE;
        pl->rescan.move = 0;
        VP_TRY(drop_sample(pl, v));
        if (moved) {
            /* paper 001's vertex move: the point measured takes the sample's place, unless a
             * sample lies within R/3 of it (its spacing invariant; R, the balls' radius, is at
             * most eps); then the sample is only removed (its deletion) */
            double sp = MOVE_SPACING * pl->cfg.eps;
            if (pl->cfg.min_size > 0.0 && pl->cfg.min_size < sp) sp = pl->cfg.min_size;
            st = vp_pl_sample_insert(pl, pl->rescan.move_to, VP_DT_NONE, sp, &nv);
            if (st < 0) return st;
            if (st == 1) {
                vp_dt_vertex(&pl->dt, nv)->aux = (vp_dt_vertex(&pl->dt, nv)->aux & AUX_NRM) | pl->rescan.move_aux;
                pl->st.rescan_moved++;
                vp_pl_note_peak(pl);
            }
        }
    }
    return VP_OK;
}

static int rescan(vp_planner_t *pl, unsigned flags)
{
    uint32_t t;
    int f;
    if (!pl || (flags & ~(VP_RESCAN_HERE | VP_RESCAN_SPARSE))) return VP_EINVAL;
    if (pl->error) return pl->error;
    if (pl->dev.awaiting) return VP_ESTATE;
    if (pl->dt.dim < 3 || pl->phase == PH_SEED) return VP_ESTATE;
    if ((flags & VP_RESCAN_SPARSE) && pl->pool.cap_astar < 4u * RING_CAP) return VP_ENOMEM;
    /* what was under way is dropped: its probes and routes were for the old object */
    pl->route.n = pl->route.i = 0;
    pl->route.deferred = 0;
    pl->probe.ready = 0;
    pl->sc.pending = 0;
    pl->pool.ntask = 0;
    pl->rays.n = pl->rays.left = 0;
    for (t = 0; t < pl->dt.ntet_slots; t++)
        if (vp_dt_alive(&pl->dt, t))
            for (f = 0; f < 4; f++) side_set(pl, t, f, side_get(pl, t, f) & ~SIDE_QUEUED);
    if (!(flags & VP_RESCAN_HERE)) {
        memcpy(pl->dev.pos, pl->cfg.start, sizeof pl->dev.pos);
        pl->dev.at = 0; /* the start's record (vp_planner_init) */
    } else {
        /* the device stays, at its record (routes from it prove each stale step first) */
        uint32_t r = pl->dev.at;
        if (r >= pl->pool.nvrec || memcmp(pl->pool.vrec[r].p, pl->dev.pos, sizeof pl->dev.pos) != 0)
            r = vp_pl_rec_at(pl, pl->dev.pos);
        if (r == NONE) {
            int st = vp_pl_rec_new(pl, pl->dev.pos, NONE, vp_pl_omega_inside(&pl->cfg, pl->dev.pos) ? REC_LOST : REC_OUT, &r);
            if (st != VP_OK) return st;
        }
        pl->dev.at = r;
    }
    memset(&pl->close, 0, sizeof pl->close);
    pl->aim.past_share = 0; /* closing's last resort is the previous scan's */
    pl->rescan.mark = pl->pool.nproof > 0 ? pl->pool.nproof : 1;
    pl->rescan.nvert = pl->dt.nvert;
    pl->rescan.next = 0;
    pl->rescan.pass = 0;
    for (t = 0; t < pl->dt.nvert; t++) vp_dt_vertex(&pl->dt, t)->aux &= ~(AUX_TAKEN | AUX_DEFER | AUX_SKIP);
    if (flags & VP_RESCAN_SPARSE) choose_skipped(pl);
    pl->rescan.cur = NONE;
    pl->rescan.reprove = 0;
    pl->rescan.ndoomed = 0;
    pl->rescan.drop = NONE;
    pl->rescan.move = 0;
    pl->rescan.blocked = 0;
    pl->rescan.tol = pl->cfg.noise_tol > KEEP_TOL_REL * (1.0 + vp_pl_omega_circumradius(&pl->cfg))
                         ? pl->cfg.noise_tol : KEEP_TOL_REL * (1.0 + vp_pl_omega_circumradius(&pl->cfg));
    pl->phase = PH_VERIFY;
    vp_pl_tube_off(pl); /* the marks are of the object as it was */
    if (!(flags & VP_RESCAN_HERE)) pl->tube.inside = 0;
    return VP_OK;
}

int vp_planner_rescan(vp_planner_t *pl) { return rescan(pl, 0); }
int vp_planner_rescan_here(vp_planner_t *pl) { return rescan(pl, VP_RESCAN_HERE); }
int vp_planner_rescan_with(vp_planner_t *pl, unsigned flags) { return rescan(pl, flags); }

#endif
