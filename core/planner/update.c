/* update.c — refinement: the centre of a bad ball is inserted (the paper's "insert c(f) into
 * E"), then Del_v|S and the free paths are updated around the insertion's cavity: facets that
 * died are removed, cavity-boundary sides keep a result their shortened Voronoi edge still
 * holds, new tets inherit activity. */
#include "vp_planner_priv.h"

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
    if (vp_pl_edge_geom(pl, t, f, &g) != VP_OK || !(g.t0 < g.t1)) return 0;
    for (k = 0; k < 3; k++) e[k] = g.a[k] + g.t1 * g.dir[k];
    return 1;
}

/* Facets inside the cavity (a killed tet's facet not on its boundary, kbound) are gone: so are
 * their balls. */
static void drop_cavity_facets(vp_planner_t *pl, const uint32_t *kverts, const uint32_t *kbound,
                               uint32_t nk)
{
    uint32_t ki;
    int i;
    for (ki = 0; ki < nk; ki++)
        for (i = 0; i < 4; i++) {
            uint32_t fv[3], r;
            int m = 0, x;
            if ((kbound[ki] >> i) & 1u) continue;
            for (x = 0; x < 4; x++)
                if (x != i) fv[m++] = kverts[4 * ki + (uint32_t)x];
            r = vp_pl_frec_lookup(pl, fv);
            if (r != NONE) vp_pl_frec_delete(pl, r);
        }
}

/* detect_access from every new active vertex, and from old active neighbours towards new
 * vertices not reached yet */
static int explore_cavity(vp_planner_t *pl, uint32_t pv, const uint32_t *created, uint32_t nc)
{
    uint32_t q;
    for (q = 0; q < nc; q++) {
        uint32_t n = created[q];
        const uint32_t *w = vp_dt_tet(&pl->dt, n);
        int jn = facet_index_of(w, pv);
        if (tet_active(pl, n)) {
            VP_TRY(vp_pl_explore(pl, n));
        } else {
            uint32_t U = w[4 + jn] >> 2, jj = w[4 + jn] & 3u;
            if (tet_active(pl, U) && (side_get(pl, U, (int)jj) & SIDE_MASK) == SIDE_UNKNOWN &&
                !vp_pl_facet_has_ghost(pl, n, jn))
                VP_TRY(vp_pl_task_push(pl, U, (int)jj, 0));
        }
    }
    return VP_OK;
}

/* The update of Del_v|S and of the free paths after vertex pv was inserted: the cavity's killed
 * tets (their payloads saved in the scratch, VP_PL_SCRATCH), its boundary facets and the new
 * tets. One pass over the boundary, in the order the inferences need it (125 lines: the
 * cases of a boundary side are one table and read best together). */
VP_PL_API int vp_pl_after_insert(vp_planner_t *pl, uint32_t pv)
{
    uint32_t nk, nc, q, ki;
    const uint32_t *killed = vp_dt_last_killed(&pl->dt, &nk);
    const uint32_t *kverts = vp_dt_last_killed_vertices(&pl->dt);
    const uint32_t *created = vp_dt_last_created(&pl->dt, &nc);
    const uint32_t *cfrom = vp_dt_last_created_from(&pl->dt);
    uint32_t *kpay, *kbound, *ckidx;
    const double *P = vp_dt_point(&pl->dt, pv);
    int st;

    if (KPAY * nk + nk + nc > pl->pool.cap_astar) return VP_ENOMEM;
    if (KPAY * nk + nk + nc > pl->peak.astar) pl->peak.astar = KPAY * nk + nk + nc;
    kpay = pl->pool.astar;
    kbound = kpay + KPAY * nk;
    ckidx = kbound + nk;
    /* the killed tets' payloads, before created tets overwrite their slots; their vertices'
     * stars changed (and the new sample's), so their normal estimates and ratings (facets.c)
     * are stale */
    vp_pl_sample_touch(pl, pv);
    for (q = 0; q < nk; q++) {
        memcpy(kpay + KPAY * q, pay(pl, killed[q]), KPAY * sizeof(uint32_t));
        kbound[q] = 0;
        for (ki = 0; ki < 4; ki++)
            if (kverts[4 * q + ki] < pl->pool.cap_nrm) {
                pl->dt.vtop[-(ptrdiff_t)kverts[4 * q + ki]].aux &= ~AUX_NRM;
                vp_pl_sample_touch(pl, kverts[4 * q + ki]);
            }
    }
    for (q = 0; q < nc; q++) {
        uint32_t ks = cfrom[q] >> 2;
        for (ki = 0; ki < nk && killed[ki] != ks; ki++) {}
        if (ki == nk) return VP_EDEGEN;
        ckidx[q] = ki;
        kbound[ki] |= 1u << (cfrom[q] & 3u);
    }
    drop_cavity_facets(pl, kverts, kbound, nk);
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
        } else if (vp_pl_tet_point(pl, n, c) != VP_OK || !vp_pl_omega_inside(&pl->cfg, c)) {
            pay(pl, n)[0] = VREC_OUT;
        } else {
            c_ok = 1;
        }
        if (vp_pl_facet_has_ghost(pl, n, jn)) continue;
        vp_dt_facet(&pl->dt, n, jn, fv);
        r = vp_pl_frec_lookup(pl, fv);
        if (r != NONE && (pl->pool.frec[r].flags & FREC_CUT)) {
            /* a cut tet's facet (close.c): made again below if U is the cut one */
            vp_pl_frec_delete(pl, r);
            r = NONE;
        }
        if (r != NONE) {
            int dbl = (pl->pool.frec[r].flags & FREC_DOUBLE) != 0;
            memcpy(oldc, pl->pool.frec[r].c, sizeof oldc);
            oldproof = pl->pool.frec[r].proof;
            valid = vp_cmp_dist(pl->pool.frec[r].c, P, vp_dt_point(&pl->dt, fv[0])) >= 0;
            if (!valid) vp_pl_frec_delete(pl, r);
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
                                                      : vp_pl_tet_point(pl, U, pu) == VP_OK;
            if (c_ok && from_u && vp_dist3(pu, c) <= vp_dist3(pu, oldc) - tol) {
                sn = sU = SIDE_FREE;
                edge_free = 1;
                pfree = oldproof;
            } else {
                sn = sU = SIDE_UNKNOWN;
            }
        } else if (r != NONE) {
            sn = sU = SIDE_UNKNOWN;
        } else if (sU == SIDE_HIT || sU == SIDE_BEHIND) {
            /* a hit whose record went with a cut (close.c), the cut tet now in the cavity: the
             * facet is between U and a new tet again and is probed again */
            sU = SIDE_UNKNOWN;
        }
        side_set(pl, n, jn, sn);
        side_set(pl, U, (int)jj, (side_get(pl, U, (int)jj) & ~SIDE_MASK) | sU);
        if ((side_get(pl, U, 0) & SIDE_CUT) && pay(pl, n)[0] == NONE && vp_pl_frec_lookup(pl, fv) == NONE) {
            /* a new inside tet against a cut one: the boundary runs between them */
            uint32_t cr;
            VP_TRY(vp_pl_frec_add_cut(pl, fv, vp_dt_point(&pl->dt, vp_dt_tet(&pl->dt, U)[jj]), n, &cr));
        }
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
                    st = vp_pl_rec_new(pl, e, NONE, REC_OUT, &er);
                    if (st != VP_OK) return st;
                    st = vp_pl_rec_link(pl, c, er, 0, pfree, &nr);
                } else {
                    st = vp_pl_rec_link(pl, c, urec, 0, pfree, &nr);
                }
                /* the rest of the old edge, towards the former vertex, is free too */
                if (st == VP_OK && k_ok && nr != NONE) st = vp_pl_edge_add(pl, nr, krec, pk);
                if (st != VP_OK) return st;
            }
            if (nr == NONE && k_ok) {
                st = vp_pl_rec_link(pl, c, krec, 0, pk, &nr);
                if (st != VP_OK) return st;
            }
            if (nr != NONE) pay(pl, n)[0] = nr;
        }
    }
    for (q = 0; q < nc; q++)
        if (pay(pl, created[q])[0] != NONE) vp_pl_cut_reached(pl, created[q]);
    return explore_cavity(pl, pv, created, nc);
}

/* ---------- refinement: insert the centre of a bad ball ---------- */


/* The tets around fv[0], listed in the scratch after the `held` words the caller keeps there
 * (VP_PL_SCRATCH): at most INCIDENT_MAX of them, a bound on the work (a vertex of a good mesh
 * has some 30). */
#define INCIDENT_MAX 65536u
VP_PL_API int vp_pl_incident(vp_planner_t *pl, uint32_t v, uint32_t held, uint32_t **inc)
{
    uint32_t room = pl->pool.cap_astar - held;
    *inc = pl->pool.astar + held;
    return vp_dt_incident_tets(&pl->dt, v, *inc, (int)(room > INCIDENT_MAX ? INCIDENT_MAX : room));
}

static uint32_t find_facet_slow(vp_planner_t *pl, const uint32_t *fv, int *fi, uint32_t held)
{
    uint32_t *inc;
    int n = vp_pl_incident(pl, fv[0], held, &inc), k;
    for (k = 0; k < n; k++) {
        const uint32_t *w = vp_dt_tet(&pl->dt, inc[k]);
        int a = facet_index_of(w, fv[1]), b = facet_index_of(w, fv[2]), c = facet_index_of(w, fv[0]);
        if (a >= 0 && b >= 0) {
            *fi = 6 - a - b - c;
            return inc[k];
        }
    }
    return NONE;
}

/* a live tet holding facet fv, and the facet's index in it; the caller keeps the first `held`
 * words of the scratch (VP_PL_SCRATCH) */
VP_PL_API uint32_t vp_pl_find_facet(vp_planner_t *pl, const uint32_t *fv, int *fi, uint32_t held)
{
    uint32_t k = vp_pl_frec_lookup(pl, fv);
    if (k != NONE && vp_dt_alive(&pl->dt, pl->pool.frec[k].hint)) {
        const uint32_t *w = vp_dt_tet(&pl->dt, pl->pool.frec[k].hint);
        int a = facet_index_of(w, fv[0]), b = facet_index_of(w, fv[1]), c = facet_index_of(w, fv[2]);
        if (a >= 0 && b >= 0 && c >= 0) {
            *fi = 6 - a - b - c;
            return pl->pool.frec[k].hint;
        }
    }
    return find_facet_slow(pl, fv, fi, held);
}


/* Room for one insertion's update in every pool, checked before inserting: the update then
 * never runs out halfway (VP_ENOMEM leaves the mesh whole and exportable). A cavity has some
 * tens of tets: records and free edges (up to 4 per new tet) get twice pool.room, the rest
 * pool.room (ROOM_SMALL; vp_planner_init). */
VP_PL_API int vp_pl_pools_have_room(const vp_planner_t *pl)
{
    uint32_t r = pl->pool.room;
    return pl->pool.nvrec + 2 * r <= pl->pool.cap_vrec && pl->pool.nfedge + 2 * r <= pl->pool.cap_fedge &&
           pl->pool.nfrec + r <= pl->pool.cap_frec && pl->pool.ntask + r <= pl->pool.cap_task &&
           pl->pool.nheap + r <= pl->pool.cap_heap && 4u * (pl->pool.nfacets + r) < pl->pool.hash_mask;
}

/* A ball within 30% of the largest is about as urgent (refining it shrinks the largest radius
 * as much, the order of insertions changes no guarantee); the nearest of those saves travel. */
#define NEAR_BALL_SHARE 0.7
static uint32_t choose_ball(const vp_planner_t *pl)
{
    uint32_t best = pl->pool.heap[0], i;
    double rmin, bestd;
    if ((pl->cfg.flags & VP_PLAN_LARGEST) || pl->pool.nheap < 2) return best;
    /* among the balls at least NEAR_BALL_SHARE of the largest, the nearest to the device */
    rmin = NEAR_BALL_SHARE * pl->pool.frec[best].key;
    bestd = vp_dist3(pl->dev.pos, pl->pool.frec[best].c);
    for (i = 1; i < pl->pool.nheap; i++) {
        const vp_frec_t *f = &pl->pool.frec[pl->pool.heap[i]];
        double d;
        if (f->key < rmin) continue;
        d = vp_dist3(pl->dev.pos, f->c);
        if (d < bestd) { bestd = d; best = pl->pool.heap[i]; }
    }
    return best;
}

#if VP_PL_CONTACTS
/* The squared distance from h to its nearest sample into *near2: that sample becomes h's
 * Delaunay neighbour, so it is a vertex of a tet whose circumsphere holds h; those tets are
 * walked breadth first from t0, the tet that holds h (pool.astar is scratch: nobody holds it
 * here). 1 when found; 0 when that region has NEAR_WALK tets or more. */
#define NEAR_WALK 512u
VP_PL_API int vp_pl_nearest_sample(vp_planner_t *pl, const double h[3], uint32_t t0, double *near2)
{
    uint32_t *stack = pl->pool.astar, n = 0, seen = 0;
    *near2 = VP_PL_HUGE;
    if (pl->pool.cap_astar < 2 * NEAR_WALK) return 0;
    stack[n++] = t0;
    while (seen < n && n < NEAR_WALK) {
        uint32_t t = stack[seen++], k, j;
        const uint32_t *w = vp_dt_tet(&pl->dt, t);
        for (k = 0; k < 4; k++) {
            uint32_t u = w[4 + k] >> 2;
            if (w[k] != VP_DT_GHOST) {
                double d2 = vp_dist3(h, vp_dt_point(&pl->dt, w[k]));
                d2 *= d2;
                if (d2 < *near2) *near2 = d2;
            }
            for (j = 0; j < n && stack[j] != u; j++) {}
            if (j == n && n < NEAR_WALK && vp_dt_in_conflict(&pl->dt, u, h)) stack[n++] = u;
        }
    }
    return n < NEAR_WALK;
}

/* A ball found from aside is refined at the point of S its line read, instead of its centre
 * taken onto the edge, when the two lie more than READ_OFF_REL of the ball's radius apart, or
 * more than the hits' tolerance (the centre would be a sample that far off S: the aim's
 * tolerance, up to eps, is wider than the hits'). A point read beyond READ_INSIDE_REL of the
 * radius is taken along the way to the centre until it lies that far inside the ball (where the
 * aim's tolerance exceeds the ball: a sample there still kills the facet, every ball through its
 * circle between the two tets' circumballs lying in their union). No sample may lie within
 * READ_NEAR_REL of the radius of that point (the insertions stay apart, so they end). A point
 * read nearer a sample than that is where the line met S beside a vertex of the facet, not where
 * S crosses the facet's Voronoi edge: the centre may lie as far off S as the tolerance, and the
 * ball is left unrefined (the facet kept, as one that cannot be refined). */
#define READ_OFF_REL (1.0 / 3.0)
#define READ_INSIDE_REL 0.95
#define READ_NEAR_REL 0.1
#endif

/* A ball that is not to be refined: its facet kept, the ball off the heap for good (FREC_STUCK:
 * the manifold criterion's pick skips it too) */
static void keep_unrefined(vp_planner_t *pl, uint32_t k)
{
    vp_pl_heap_remove(pl, k);
    pl->pool.frec[k].flags |= FREC_STUCK;
}

VP_PL_API int vp_pl_refine(vp_planner_t *pl)
{
    if (pl->pool.fhash_dirty) { vp_pl_fhash_rebuild(pl); pl->pool.fhash_dirty = 0; }
    uint32_t k = choose_ball(pl), t, v = NONE, fv[3], pf;
    int fi, st;
    double c[3];
    if (pl->pool.ntask + ROOM_SMALL > pl->pool.cap_task) vp_pl_task_compact(pl);
    if (!vp_pl_pools_have_room(pl)) return VP_ENOMEM;
    memcpy(fv, pl->pool.frec[k].v, sizeof fv);
    memcpy(c, pl->pool.frec[k].c, sizeof c);
    pf = pl->pool.frec[k].proof;
    t = vp_pl_find_facet(pl, fv, &fi, 0);
    if (t == NONE) {
        vp_pl_frec_delete(pl, k);
        pl->st.stale_balls++;
        return VP_OK;
    }
#if VP_PL_CONTACTS
    {
        /* a ball found from aside: its centre, the hit taken onto the edge, lies up to the
         * aim's tolerance off S. Where that is more than a fraction of the ball or than the
         * hits' tolerance, the point of S the line read is the sample (taken into the ball
         * when read beyond it, so the facet goes), if it keeps a spacing to every sample (a
         * picking region of Delaunay refinement: the insertions stay apart, so they end); read
         * right beside a sample, the ball stays as it is */
        double h[3], o[3], o2, n2, r = pl->pool.frec[k].r, sp = READ_OFF_REL * r, in = READ_INSIDE_REL * r;
        uint32_t th;
        if (sp > pl->cfg.noise_tol) sp = pl->cfg.noise_tol;
        if (vp_pl_aim_read(pl, k, h)) {
            vp_sub3(o, h, c);
            o2 = vp_dot3(o, o);
            if (o2 > sp * sp) {
                if (o2 >= in * in) {
                    /* read beyond the ball: the point of [c, h] nearest h inside it */
                    double s = in / sqrt(o2);
                    int q;
                    for (q = 0; q < 3; q++) h[q] = c[q] + s * o[q];
                }
                if (vp_dt_locate(&pl->dt, h, t, &th) == VP_OK && vp_pl_nearest_sample(pl, h, th, &n2)) {
                    if (n2 < READ_NEAR_REL * READ_NEAR_REL * r * r) {
                        keep_unrefined(pl, k);
                        pl->st.read_kept++;
                        return VP_OK;
                    }
                    memcpy(c, h, sizeof c);
                    pl->st.read_samples++;
                }
            }
        }
    }
#endif
    st = vp_dt_insert_in_conflict(&pl->dt, c, t, &v);
    if (st == VP_EINVAL)
        st = vp_dt_insert_in_conflict(&pl->dt, c, vp_dt_tet(&pl->dt, t)[4 + fi] >> 2, &v);
    if (st == VP_EINVAL) st = vp_dt_insert(&pl->dt, c, t, &v);
    if (st == VP_ENOMEM) return st;
    if (st != VP_OK) {
        /* cannot be refined (a duplicate within rounding) */
        keep_unrefined(pl, k);
        pl->st.stale_balls++;
        return VP_OK;
    }
    pl->st.insertions++;
    pl->close.exhaustive = 0;
    /* the sample remembers the probe that found it: a re-scan measures it along that line */
#if VP_PL_CONTACTS
    if (pf < AUX_PROOF) vp_dt_vertex(&pl->dt, v)->aux = (vp_dt_vertex(&pl->dt, v)->aux & AUX_NRM) | (pf + 1u);
#else
    (void)pf;
#endif
    st = vp_pl_after_insert(pl, v);
    vp_pl_note_peak(pl);
    return st;
}
