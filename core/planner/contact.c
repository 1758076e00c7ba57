/* contact.c — the contact safety net: a MOVE stopped by the head's contact switch.
 *
 * A miss is the planner's proof of free space, and a surface the rangefinder cannot see (black,
 * shiny, a spot lost in glare) also gives a miss. A head with a contact switch stops when it
 * touches; vp_planner_touch() is told where along the MOVE that happened. Then:
 *   - every proof whose ray passes through the contact point is false: withdrawn (its length
 *     set below 0, so no check accepts it again), with the free edges, prev links and free
 *     Voronoi edges that named it;
 *   - the records no longer joined to R^3 \ Omega by proven-free edges are lost: the prev
 *     chains are rebuilt over what is left (breadth first from the records outside Omega), and
 *     the Voronoi vertices of lost records become inactive again;
 *   - a probe whose free part passes within reach of a contact proves nothing from now on
 *     (proof.c): a miss there is read as "unseen" (the side is blocked, not free);
 *   - the contact point is a point of S: it is inserted as a sample;
 *   - the device backs off along the move to its start, over the part it has just travelled.
 * The head never travels a segment twice that a contact contradicted, so each contact closes
 * one false way; the mesh around a surface the rangefinder cannot see stays open and certify
 * names it. */
#include "vp_planner_priv.h"

/* a probe's free part passing this close to a contact proves nothing: eps, at least this many
 * times the noise tolerance */
#define CONTACT_REACH_NOISE 4.0

static int proof_revoked(const vp_planner_t *pl, uint32_t id)
{
    return id < pl->pool.nproof && pl->pool.proof[id].len < 0.0;
}

/* 1 if the free part of proof q (its own piece) passes within tol of x */
static int proof_near(const vp_proof_t *q, const double *x, double tol)
{
    double d[3], s, e2;
    int k;
    if (!(q->len >= 0.0)) return 0;
    vp_sub3(d, x, q->o);
    s = vp_dot3(d, q->d);
    if (s < 0.0) s = 0.0;
    if (s > q->len) s = q->len;
    e2 = 0.0;
    for (k = 0; k < 3; k++) {
        double r = x[k] - (q->o[k] + s * q->d[k]);
        e2 += r * r;
    }
    return e2 <= tol * tol;
}

/* 1 if the segment o + [0, len] d passes within reach of a contact: not a proof */
VP_PL_API int vp_pl_contact_distrusts(const vp_planner_t *pl, const double *o, const double *d, double len)
{
    vp_proof_t q;
    uint32_t i;
    memcpy(q.o, o, sizeof q.o);
    memcpy(q.d, d, sizeof q.d);
    q.len = len;
    for (i = 0; i < pl->contact.n; i++)
        if (proof_near(&q, pl->contact.at[i], pl->contact.reach[i])) return 1;
    return 0;
}

/* Keeps contact c with its reach; when the table is full, the nearest kept contact's reach
 * grows to cover c's (a larger zone distrusted: never a smaller one). */
static void contact_keep(vp_planner_t *pl, const double *c, double reach)
{
    vp_pl_contact_t *ct = &pl->contact;
    uint32_t i, best = 0;
    double bd = VP_PL_HUGE;
    if (ct->n < VP_PLANNER_MAX_CONTACTS) {
        memcpy(ct->at[ct->n], c, 3 * sizeof(double));
        ct->reach[ct->n++] = reach;
        return;
    }
    for (i = 0; i < ct->n; i++) {
        double d = vp_dist3(ct->at[i], c);
        if (d < bd) { bd = d; best = i; }
    }
    if (bd + reach > ct->reach[best]) ct->reach[best] = bd + reach;
}

/* Rebuilds the prev chains over the free edges whose proofs stand, breadth first from the
 * records outside Omega; records not reached are lost (REC_LOST). The queue is pool.astar
 * (VP_PL_SCRATCH: nobody holds it between commands). */
static int rebuild_chains(vp_planner_t *pl)
{
    uint32_t *q = pl->pool.astar, nq = 0, head = 0, i;
    for (i = 0; i < pl->pool.nvrec; i++) {
        vp_vrec_t *r = &pl->pool.vrec[i];
        if (r->flags & REC_OUT) {
            if (nq >= pl->pool.cap_astar) return VP_ENOMEM;
            r->flags &= ~REC_LOST;
            r->prev = i;
            r->depth = 0;
            r->proof = PROOF_NONE;
            q[nq++] = i;
        } else {
            r->flags |= REC_LOST;
        }
    }
    while (head < nq) {
        uint32_t cur = q[head++], e;
        for (e = pl->pool.vrec[cur].adj; e != NONE;) {
            const uint32_t *w = pl->pool.fedge + FEDGE_WORDS * e;
            int isa = w[0] == cur;
            uint32_t nb = isa ? w[1] : w[0];
            vp_vrec_t *r = &pl->pool.vrec[nb];
            if ((r->flags & REC_LOST) && !proof_revoked(pl, w[4])) {
                if (nq >= pl->pool.cap_astar) return VP_ENOMEM;
                r->flags &= ~REC_LOST;
                r->prev = cur;
                r->depth = pl->pool.vrec[cur].depth + 1;
                r->proof = w[4];
                q[nq++] = nb;
            }
            e = isa ? w[2] : w[3];
        }
    }
    return VP_OK;
}

/* Tets: a side proven free by a withdrawn proof is unknown again; a Voronoi vertex whose
 * record is lost is inactive again. */
static void reset_tets(vp_planner_t *pl)
{
    uint32_t t;
    int f;
    for (t = 0; t < pl->dt.ntet_slots; t++) {
        uint32_t rec;
        if (!vp_dt_alive(&pl->dt, t)) continue;
        for (f = 0; f < 4; f++) {
            unsigned s = side_get(pl, t, f);
            if ((s & SIDE_MASK) == SIDE_FREE && proof_revoked(pl, side_proof(pl, t, f)))
                side_set(pl, t, f, s & ~SIDE_MASK);
        }
        rec = tet_rec(pl, t);
        if (rec != NONE && rec != VREC_OUT && (pl->pool.vrec[rec].flags & REC_LOST)) pay(pl, t)[0] = NONE;
    }
}

/* the record standing at point p (exactly), else NONE */
VP_PL_API uint32_t vp_pl_rec_at(const vp_planner_t *pl, const double *p)
{
    uint32_t i;
    for (i = pl->pool.nvrec; i-- > 0;) {
        const double *q = pl->pool.vrec[i].p;
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2] && !(pl->pool.vrec[i].flags & REC_LOST)) return i;
    }
    return NONE;
}

/* Every proof through point c is false: withdrawn. */
static void revoke_through(vp_planner_t *pl, const double *c)
{
    double tol = pl->ptol + pl->cfg.noise_tol;
    uint32_t i;
    for (i = 0; i < pl->pool.nproof; i++)
        if (proof_near(&pl->pool.proof[i], c, tol)) {
            pl->pool.proof[i].len = -1.0;
            pl->st.revoked++;
            vp_pl_tube_off(pl); /* the marks of that proof stay in the grid */
        }
}

/* Proofs were withdrawn: what the device was about to do is dropped (its route; its probe back to
 * the queue, or a re-scan's measuring probe to be tried again), and the prev chains are rebuilt
 * over the proofs that stand. */
static int abandon_plan(vp_planner_t *pl)
{
    if (pl->phase == PH_VERIFY) {
        /* a re-scan's measuring probe: its line is tried again (another way there, or the next) */
        if (pl->probe.ready && pl->rescan.cur != NONE && pl->rescan.along > 0) pl->rescan.along--;
        pl->probe.ready = 0;
    } else if (pl->probe.ready && pl->probe.task.off > 0.0) {
        /* a walked ray goes on from where the device was to stand: not any more */
        vp_pl_probe_drop(pl);
    } else if (pl->probe.ready) {
        pl->probe.ready = 0;
        if (pl->phase == PH_RUN || pl->phase == PH_CLOSE) {
            if (pl->pool.ntask >= pl->pool.cap_task) vp_pl_task_compact(pl);
            if (pl->pool.ntask >= pl->pool.cap_task) return VP_ENOMEM;
            pl->pool.task[pl->pool.ntask++] = pl->probe.task;
        }
    }
    if (pl->phase == PH_RESEED) pl->phase = PH_COMPONENTS;
    pl->sc.pending = 0;
    pl->route.deferred = 0;
    pl->route.n = pl->route.i = 0;
    VP_TRY(rebuild_chains(pl));
    reset_tets(pl);
    return VP_OK;
}

/* The record standing at p, or a new one there (lost inside Omega: no proven chain yet). */
static int rec_here(vp_planner_t *pl, const double *p, uint32_t *r)
{
    *r = vp_pl_rec_at(pl, p);
    if (*r != NONE) return VP_OK;
    return vp_pl_rec_new(pl, p, NONE, vp_pl_omega_inside(&pl->cfg, p) ? REC_LOST : REC_OUT, r);
}

/* Point c of S (a contact, a blocked step's hit) becomes a sample. */
static int insert_point(vp_planner_t *pl, const double *c)
{
    uint32_t v;
    int st;
    if (!vp_pl_pools_have_room(pl)) return VP_ENOMEM;
    st = vp_dt_insert(&pl->dt, c, VP_DT_NONE, &v);
    if (st == VP_EDUP) return VP_OK;
    if (st != VP_OK) return st;
    pl->st.insertions++;
    pl->close.exhaustive = 0;
    if (pl->phase != PH_RUN && pl->phase != PH_VERIFY) pl->phase = PH_RUN; /* a re-scan's measuring goes on */
    st = vp_pl_after_insert(pl, v);
    vp_pl_note_peak(pl);
    return st;
}

/* The point `*at` along the MOVE from -> to: *at checked (VP_EINVAL beyond the MOVE by more than
 * the planner's tolerance) and clamped to it, u its unit direction (0 for a null MOVE), c the
 * point. */
static int point_along(const vp_planner_t *pl, const double *from, const double *to, double *at, double *u, double *c)
{
    double len;
    int k;
    vp_sub3(u, to, from);
    len = sqrt(vp_dot3(u, u));
    if (!(*at >= 0.0) || !(*at <= len + pl->ptol)) return VP_EINVAL;
    if (*at > len) *at = len;
    if (len > 0.0)
        for (k = 0; k < 3; k++) u[k] /= len;
    for (k = 0; k < 3; k++) c[k] = from[k] + *at * u[k];
    return VP_OK;
}

/* The contact at c, `at` along the last MOVE (unit direction u), as point_along gives them. */
static int touch_at(vp_planner_t *pl, double at, const double *u, const double *c)
{
    double back[3];
    uint32_t from_rec, touch = PROOF_NONE;
    /* Omega holds the object (A2): a contact outside it breaks the assumption every proof
     * outside Omega rests on */
    if (!vp_pl_omega_inside(&pl->cfg, c)) return VP_ERANGE;
    /* the seeds' probes start outside Omega: a contact before them is not expected */
    if (pl->phase == PH_SEED || pl->dt.dim < 3) return VP_EUNSAFE;
    pl->contact.moved = 0;
    pl->st.contacts++;
    revoke_through(pl, c);
    contact_keep(pl, c, pl->cfg.eps > CONTACT_REACH_NOISE * pl->cfg.noise_tol ? pl->cfg.eps
                                                                             : CONTACT_REACH_NOISE * pl->cfg.noise_tol);
    /* the part travelled up to the contact is free: the way back */
    memcpy(back, pl->contact.move_from, sizeof back);
    if (at > 0.0) VP_TRY(vp_pl_proof_add(pl, back, u, at, &touch));
    VP_TRY(abandon_plan(pl));
    /* the device stands at the contact; it backs off to the move's start */
    VP_TRY(rec_here(pl, back, &from_rec));
    memcpy(pl->dev.pos, c, sizeof pl->dev.pos);
    pl->dev.at = from_rec;
    if (at > 0.0) VP_TRY(vp_pl_route_push(pl, back, touch));
    /* the contact point is a sample of S */
    return insert_point(pl, c);
}

/* A re-scan's probe of a stale route step (rescan.c) found S on the step, at h (NULL: the step
 * could not be proven: near a contact): its proof `old` and every proof through h are false. What
 * the device was about to do is dropped, the prev chains are rebuilt, the device keeps its place
 * (a record there), and h becomes a sample. */
VP_PL_API int vp_pl_withdraw_at(vp_planner_t *pl, const double *h, uint32_t old)
{
    uint32_t r;
    if (h && !vp_pl_omega_inside(&pl->cfg, h)) return VP_ERANGE; /* Omega holds the object (A2) */
    if (old < pl->pool.nproof && pl->pool.proof[old].len >= 0.0) {
        pl->pool.proof[old].len = -1.0;
        pl->st.revoked++;
        vp_pl_tube_off(pl);
    }
    if (h) revoke_through(pl, h);
    VP_TRY(abandon_plan(pl));
    VP_TRY(rec_here(pl, pl->dev.pos, &r));
    pl->dev.at = r;
    /* while the seeds are placed there is no triangulation to take a sample yet */
    return h && pl->phase != PH_SEED && pl->dt.dim == 3 ? insert_point(pl, h) : VP_OK;
}

int vp_planner_touch(vp_planner_t *pl, double at)
{
    double u[3], c[3];
    int st;
    if (!pl) return VP_EINVAL;
    if (pl->error) return pl->error;
    if (!pl->contact.moved || pl->dev.awaiting) return VP_ESTATE;
    /* a bad `at` changes nothing (not even pl->error) */
    VP_TRY(point_along(pl, pl->contact.move_from, pl->dev.pos, &at, u, c));
    st = touch_at(pl, at, u, c);
    if (st < 0) pl->error = st;
    return st;
}

int vp_planner_touch_path(vp_planner_t *pl, const vp_cmd_t *move, double at)
{
    double u[3], c[3];
    int k, last = pl && pl->contact.moved && !pl->dev.awaiting;
    if (!pl || !move || move->kind != VP_CMD_MOVE) return VP_EINVAL;
    if (pl->error) return pl->error;
    for (k = 0; k < 3; k++)
        if (move->to[k] != pl->dev.pos[k] || move->from[k] != pl->contact.move_from[k]) last = 0;
    if (last) return vp_planner_touch(pl, at);   /* the last command given */
    VP_TRY(point_along(pl, move->from, move->to, &at, u, c));
    /* Omega holds the object (A2): a contact outside it breaks the assumption every proof
     * outside Omega rests on */
    pl->error = vp_pl_omega_inside(&pl->cfg, c) ? VP_ESTATE : VP_ERANGE;
    return pl->error;
}
