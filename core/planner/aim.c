/* aim.c — body mode: a hidden facet's surface Delaunay ball found from aside (beyond paper 000,
 * which probes each Voronoi edge along itself).
 *
 * A head that stays outside Omega probes a Voronoi edge along its line from dOmega; where the
 * object occludes that line (a torus's inner side, a cup's wall) the edge is unseen, and a hole
 * at such a facet stays open. But S can be met on the edge itself by lines from other
 * directions. The first line along a direction passes the edge's far vertex b (when b lies in
 * Omega): seen free, b is outside the object, its tet is reached (its sides probed like any) and
 * the facet lies between two outside tets. Otherwise, along a direction d tilted from the edge e,
 * a line through a point q(t) of the edge [a, a + len e] either passes q(t) free (q(t) lies outside the object: S crosses the edge
 * further on), or meets S just before q(t) (within len / cos of the tilt, as a surface crossing
 * the edge before q(t) would be met), or meets something farther from q(t) (occluded: the next
 * direction). Narrowing [lo, hi] between a point seen free and one met just before, the line
 * meets S within `tol` of q(t). Where S runs slanted to the edge, the lines on either side of a
 * narrowed stretch can each meet S more than tol before or after q(t) and still within tol of
 * the edge (a line tilted by a from e, up to tol / sin a from q(t)): once the stretch left is
 * below what a line tells apart, the hit of the direction nearest the edge, if within tol of
 * it, is taken onto it as the crossing. The next q(t) is where the last hit puts the crossing (S taken as
 * a plane square to e there, as near a good facet: a hit d before or after q(t) along the line
 * is d cos(tilt) along the edge), else the middle: where the line through the middle of a long
 * edge meets S at a spot the camera cannot see (the bear's 10.7 mm edge on the enclosed board:
 * every such line unreadable), the line near the crossing is read. That point of S, taken onto
 * the edge, is the centre of the
 * facet's surface Delaunay ball (every point of a Voronoi edge is equidistant to the facet's
 * three samples and farther from the others), as the probe along the edge would have found it,
 * up to tol along S's normal (the larger of the hits' noise and eps: a line that meets S within
 * eps of the edge has found the ball, as closely as the refinement resolves S there; a tolerance
 * of the hits' noise alone left the rpi4 torus's inner equator open at 7 of 24 eps from 1.8 to
 * 6 mm, against 5 of 24). What the refinement guarantees is unchanged (every ball at most eps,
 * checked exactly at the end); the centre may lie tol off S, so its refinement takes the point
 * of S the line read instead where the two lie farther apart than the hits are trusted
 * (update.c). The head never enters Omega: each line starts on dOmega, reached round Omega like
 * every probe in body mode.
 *
 * Lines for b alone (the last resort of closing, close.far_lines): b seen free needs no crossing
 * of S read near the edge, and the tilts above all come from behind the facet, through the
 * object when the edge runs away from S into a hole (the torus's inner side). These come from
 * beyond b, 135 degrees from e, each one line through b: where such a line meets S near the facet
 * it does so about as obliquely as the 45-degree tilts (lines square to e read a line laser's
 * frame at a grazing angle: one ray 2.02 mm off on the rpi4 board, beyond what hits are trusted
 * to).
 *
 * Used for the sides left unseen at a hole while closing (SIDE_RETRIED: once per side), while
 * aims are at most a quarter of all probes (AIM_SHARE). */
#include "vp_planner_priv.h"

#if VP_PL_CONTACTS

#define AIM_DIRS 8u       /* directions tried per hidden side: two tilts, four turns each */
#define AIM_VERTEX_DIRS 8u /* then, with close.far_lines and b in Omega, lines through b alone */
#define AIM_STEPS 24u     /* lines along one direction at most (halvings of the edge) */
#define AIM_TOL_REL 1.0   /* of eps: a line meeting S this near q(t) has found the ball */
#define AIM_MID_T 0.5     /* halving starts at the edge's midpoint */
#define AIM_GUARD 0.1     /* an estimated crossing is tried at least this share of [lo, hi] in */
#define AIM_SHARE 3u      /* aims start while they are at most 1 in AIM_SHARE + 1 of all probes */

/* direction i: tilted 30 degrees from e (four turns a quarter apart), then 45 degrees (four
 * turns between those); u, v span the plane normal to e. The line meets S about as obliquely as
 * it is tilted from e (a Voronoi edge of a good facet runs near S's normal): a steeper tilt reads
 * the spot at a grazing angle, where a triangulating rangefinder errs most. Past AIM_DIRS, for b
 * alone: 135 degrees from e (coming from beyond b), in the eight turns */
static void aim_dir(uint32_t i, const double *e, double *d)
{
    static const double tilt_cos[3] = {0.86602540378443865, 0.70710678118654752, -0.70710678118654752},
                        tilt_sin[3] = {0.5, 0.70710678118654752, 0.70710678118654752};
    static const double turn[8][2] = {{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.0, -1.0},
                                      {0.70710678118654752, 0.70710678118654752}, {-0.70710678118654752, 0.70710678118654752},
                                      {-0.70710678118654752, -0.70710678118654752}, {0.70710678118654752, -0.70710678118654752}};
    double u[3], v[3], ax[3] = {0.0, 0.0, 0.0};
    int q, k = 0, tl = i < AIM_DIRS ? (int)(i / 4u) : 2;
    /* the axis least along e, crossed with e */
    for (q = 1; q < 3; q++)
        if (fabs(e[q]) < fabs(e[k])) k = q;
    ax[k] = 1.0;
    vp_normal_frame3(e, ax, u, v);
    for (q = 0; q < 3; q++)
        d[q] = tilt_cos[tl] * e[q] + tilt_sin[tl] * (turn[i % 8u][0] * u[q] + turn[i % 8u][1] * v[q]);
}

static double aim_tol(const vp_planner_t *pl)
{
    double tol = AIM_TOL_REL * pl->cfg.eps;
    return pl->cfg.noise_tol > tol ? pl->cfg.noise_tol : tol;
}

/* 1 while the direction tried is one for the far vertex b alone */
static int aim_vertex_only(const vp_pl_aim_t *A)
{
    return A->dir_i >= AIM_DIRS;
}

/* how far before q(t) a line along this direction may meet S and still be taken as the edge's
 * own crossing: the edge's length over the cosine of the tilt, plus the tolerance (a line for b
 * alone reads nothing before it) */
static double aim_near(const vp_planner_t *pl)
{
    const vp_pl_aim_t *A = &pl->aim;
    if (aim_vertex_only(A)) return aim_tol(pl);
    return A->len / vp_dot3(A->d, A->e) + aim_tol(pl);
}

/* Where a hit `dist` along the issued line puts S's crossing of the edge (as t): S taken as a
 * plane square to e, a hit before or after q(t) along the line is that times cos(tilt) along
 * the edge */
static double aim_crossing(const vp_pl_aim_t *A, double dist)
{
    return A->t + (dist - A->sq) * vp_dot3(A->d, A->e) / A->len;
}

/* The side is left unseen: no aimed line found its ball. */
static int aim_give_up(vp_planner_t *pl)
{
    vp_task_t *k = &pl->probe.task;
    pl->aim.on = 0;
    if (vp_dt_alive(&pl->dt, k->tet))
        side_set(pl, k->tet, k->facet, (side_get(pl, k->tet, k->facet) & ~(SIDE_QUEUED | SIDE_FORCED)) | SIDE_BLOCKED);
    return VP_OK;
}

/* The stretch [lo, hi] left is below what a line can tell apart (the tolerance along the edge,
 * as a line square to S would see it) */
static int aim_narrowed(const vp_planner_t *pl, const vp_pl_aim_t *A)
{
    return (A->hi - A->lo) * A->len * vp_dot3(A->d, A->e) < aim_tol(pl);
}

/* The hit `dist` along the issued line from o into h, and taken onto the edge (kept a hair
 * inside its ends) into c; returns the hit's distance from c */
static double aim_onto_edge(const vp_pl_aim_t *A, const double *o, double dist, double *h, double *c)
{
    double x[3], s, inset = 1e-9 * A->len;
    int q;
    for (q = 0; q < 3; q++) h[q] = o[q] + dist * A->d[q];
    vp_sub3(x, h, A->a);
    s = vp_dot3(x, A->e);
    if (s > A->len - inset) s = A->len - inset;
    if (s < inset) s = inset;
    for (q = 0; q < 3; q++) c[q] = A->a[q] + s * A->e[q];
    return vp_dist3(h, c);
}

/* The hit `dist` into near_c when, taken onto the edge, it lies within tol of it and nearer
 * than the direction's hits before */
static void aim_keep_near(vp_pl_aim_t *A, const double *o, double dist, double tol)
{
    double h[3], c[3], dd = aim_onto_edge(A, o, dist, h, c);
    if (dd <= tol && (A->near_d < 0.0 || dd < A->near_d)) {
        memcpy(A->near_c, c, sizeof A->near_c);
        memcpy(A->near_h, h, sizeof A->near_h);
        A->near_d = dd;
    }
}

#define AIM_READS (sizeof ((vp_pl_aim_t *)0)->read / sizeof ((vp_pl_aim_t *)0)->read[0])

/* The aim ends with the facet's surface Delaunay ball centred at c, on the edge, taken there from
 * the point h of S the line read; when the ball is its record's own, a ring of the latest such
 * balls keeps h with the record and the centre, for its refinement */
static int aim_ball(vp_planner_t *pl, const double *c, const double *h)
{
    const vp_task_t *k = &pl->probe.task;
    vp_pl_aim_t *A = &pl->aim;
    uint32_t r;
    A->on = 0;
    pl->st.aim_balls++;
    VP_TRY(vp_pl_side_hit(pl, k->tet, k->facet, c, A->out, PROOF_NONE, &r));
    if (!memcmp(pl->pool.frec[r].c, c, sizeof pl->pool.frec[r].c)) {
        struct vp_pl_aim_read *e = &A->read[A->nread++ % AIM_READS];
        e->k = r;
        memcpy(e->c, c, sizeof e->c);
        memcpy(e->h, h, sizeof e->h);
    }
    return VP_OK;
}

/* The point of S read for record k's ball found from aside, into h: 1 when the ring still holds
 * it (the same record with the same centre: a record made again, or given a larger ball, has
 * another), else 0 */
VP_PL_API int vp_pl_aim_read(const vp_planner_t *pl, uint32_t k, double *h)
{
    uint32_t i, n = pl->aim.nread < AIM_READS ? pl->aim.nread : (uint32_t)AIM_READS;
    for (i = 0; i < n; i++) {
        const struct vp_pl_aim_read *e = &pl->aim.read[i];
        if (e->k == k && !memcmp(e->c, pl->pool.frec[k].c, sizeof e->c)) {
            memcpy(h, e->h, sizeof e->h);
            return 1;
        }
    }
    return 0;
}

/* Prepares the line through q(t) along the current direction, trying the next directions
 * while one cannot be issued (its line leaves Omega too soon, or is out of the rangefinder's
 * reach, or no route to its origin). Returns 1 when a probe is ready, 0 when the side stays
 * unseen, < 0 an error. */
static int aim_issue(vp_planner_t *pl)
{
    vp_pl_aim_t *A = &pl->aim;
    vp_pl_probe_t *P = &pl->probe;
    uint32_t ndirs = AIM_DIRS + (A->to_vertex && pl->close.far_lines ? AIM_VERTEX_DIRS : 0u);
    for (; A->dir_i < ndirs; A->dir_i++, A->steps = 0, A->lo = 0.0, A->hi = 1.0, A->near_d = -1.0) {
        double q[3], back[3], t0, t1, o[3], range;
        int k, st;
        if (A->steps == 0) aim_dir(A->dir_i, A->e, A->d);
        /* this direction is done after AIM_STEPS lines, or once the stretch left is below what
         * a line can tell apart (the tolerance along the edge); one line for b alone */
        if (A->steps >= AIM_STEPS || (A->steps > 0 && (aim_vertex_only(A) || aim_narrowed(pl, A))))
            continue;
        /* the first line of a direction passes the far vertex, when it lies in Omega */
        A->t = A->steps == 0 ? (A->to_vertex ? 1.0 : AIM_MID_T) : 0.5 * (A->lo + A->hi);
        if (A->steps > 0 && A->next_t > A->lo && A->next_t < A->hi) {
            /* where the last hit puts the crossing, kept a tenth of the stretch off its ends */
            double m = AIM_GUARD * (A->hi - A->lo);
            A->t = A->next_t < A->lo + m ? A->lo + m : A->next_t > A->hi - m ? A->hi - m : A->next_t;
        }
        A->next_t = -1.0;
        for (k = 0; k < 3; k++) {
            q[k] = A->a[k] + A->t * A->len * A->e[k];
            back[k] = -A->d[k];
        }
        if (!vp_pl_omega_clip(&pl->cfg, q, back, VP_PL_HUGE, &t0, &t1) || !(t1 > 0.0)) continue;
        for (k = 0; k < 3; k++) o[k] = q[k] - t1 * A->d[k];
        range = vp_pl_clamp_range(pl, t1 + aim_near(pl));
        if (range < t1 + aim_tol(pl)) continue; /* q(t) out of reach */
        st = vp_pl_plan_route(pl, NONE, o);
        if (st == PL_UNREACHABLE) continue;
        if (st != VP_OK) return st < 0 ? st : 0;
        A->sq = t1;
        A->steps++;
        A->tries = 0;
        memcpy(P->origin, o, sizeof o);
        memcpy(P->dir, A->d, sizeof P->dir);
        P->range = P->full = range;
        P->reach = 0.0;
        P->standoff = 0.0;
        P->vantage = 0;
        P->origin_rec = pl->dev.at;
        P->chain_proof = PROOF_NONE;
        P->ready = 1;
        pl->st.aims++;
        return 1;
    }
    return 0;
}

/* Side k of the current probe (body mode) was unseen along its edge's line, whose origin was
 * `out` (on the facet's outer side). Aims at the edge from aside: at its part in Omega, from its
 * vertex a or, where a lies outside Omega, from where it enters (outside Omega is free, as a
 * reached vertex is). Returns 1 when the first line is under way, 0 when none could be (the side
 * is left unseen), < 0 an error. */
VP_PL_API int vp_pl_aim_start(vp_planner_t *pl, const vp_task_t *k, const double *out)
{
    vp_pl_aim_t *A = &pl->aim;
    edgegeom_t g;
    int st, q;
    if (k != &pl->probe.task) pl->probe.task = *k;
    /* a budget: where most hidden facets cannot be seen from aside either (a cavity deeper than
     * the tilts reach), the lines would cost more than the rest of the scan */
    if ((pl->cfg.flags & VP_PLAN_NO_AIM) ||
        (AIM_SHARE * pl->st.aims > pl->st.probes - pl->st.aims && pl->st.aims >= pl->aim.past_share))
        return aim_give_up(pl);
    if (vp_pl_edge_geom(pl, k->tet, k->facet, &g) != VP_OK || !(g.t0 < g.t1)) return aim_give_up(pl);
    /* the edge's part in Omega, [t0, t1] (t0 is 0 when a lies inside) */
    for (q = 0; q < 3; q++) A->a[q] = g.a[q] + g.t0 * g.dir[q];
    A->len = g.t1 - g.t0;
    memcpy(A->e, g.dir, sizeof A->e);
    memcpy(A->out, out, sizeof A->out);
    A->to_vertex = !(g.t1 < g.len);
    A->dir_i = A->steps = 0;
    A->next_t = -1.0;
    A->near_d = -1.0;
    A->lo = 0.0;
    A->hi = 1.0;
    A->on = 1;
    st = aim_issue(pl);
    if (st <= 0) {
        VP_TRY(aim_give_up(pl));
        return st;
    }
    side_set(pl, k->tet, k->facet, side_get(pl, k->tet, k->facet) | SIDE_QUEUED);
    return 1;
}

/* Closing's last resort (close.c) has queued `sides` sides: from now on aims pass far vertices
 * alone too, and the lines those sides need start past the budget (each side once, so they are
 * bounded: what the budget guards against is aims on every new side of a deep cavity), at most
 * a quarter of the probes so far (the mug's cavity on the enclosed board took all of them and
 * more, and stayed open). */
VP_PL_API void vp_pl_aim_last_resort(vp_planner_t *pl, uint32_t sides)
{
    uint64_t lines = (uint64_t)sides * (AIM_DIRS + AIM_VERTEX_DIRS), cap = pl->st.probes / (AIM_SHARE + 1u);
    pl->close.far_lines = 1;
    pl->aim.past_share = pl->st.aims + (lines < cap ? lines : cap);
}

/* The answer to an aimed line. */
VP_PL_API int vp_pl_aim_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    vp_pl_aim_t *A = &pl->aim;
    vp_task_t *k = &pl->probe.task;
    double tol = aim_tol(pl);
    uint32_t pf = PROOF_NONE;
    int st, redo;
    /* a dropout must not show b or q(t) free: a miss is trusted after confirm_misses more
     * misses on the same line, as along an edge (tasks.c); its free part is recorded then */
    redo = res->hit == 0 && A->tries < pl->cfg.confirm_misses;
    if (res->hit != VP_PROBE_TOO_CLOSE && !redo) VP_TRY(vp_pl_probe_proof(pl, res, &pf)); /* its free part */
    if (!vp_dt_alive(&pl->dt, k->tet)) { A->on = 0; return VP_OK; } /* the facet has gone */
    if (redo) {
        A->tries++;
        pl->st.reprobes++;
        pl->probe.ready = 1;
        return VP_OK; /* the side stays queued */
    }
    side_set(pl, k->tet, k->facet, side_get(pl, k->tet, k->facet) & ~SIDE_QUEUED);
    if (res->hit == VP_PROBE_TOO_CLOSE) {
        A->steps = AIM_STEPS; /* nothing learnt along this direction */
    } else if (res->hit == 0 || res->dist > A->sq + tol) {
        if (A->t == 1.0) {
            /* the far vertex seen free: its tet is reached (outside), and its own sides are
             * probed like any; this facet lies between two outside tets, not on S (or on S
             * twice) */
            const uint32_t *w = vp_dt_tet(&pl->dt, k->tet);
            A->on = 0;
            pl->st.aim_reached++;
            /* the edge itself is not proven free: never probed again */
            side_set(pl, k->tet, k->facet, side_get(pl, k->tet, k->facet) | SIDE_BLOCKED);
            return vp_pl_tet_reached(pl, w[4 + k->facet] >> 2, pf);
        }
        A->lo = A->t; /* q(t) seen free: S crosses the edge further on */
        if (res->hit == 1) A->next_t = aim_crossing(A, res->dist);
    } else if (aim_vertex_only(A)) {
        A->steps = AIM_STEPS; /* b not seen free along this direction */
    } else if (res->dist >= A->sq - tol) {
        /* S met within tol of q(t): the ball's centre, on the edge */
        double h[3], c[3];
        (void)aim_onto_edge(A, pl->probe.origin, res->dist, h, c);
        return aim_ball(pl, c, h);
    } else if (res->dist >= A->sq - aim_near(pl)) {
        A->hi = A->t; /* met just before q(t): S crosses the edge before it */
        A->next_t = aim_crossing(A, res->dist);
    } else {
        A->steps = AIM_STEPS; /* occluded along this direction too */
    }
    if (res->hit == 1 && A->steps < AIM_STEPS && !aim_vertex_only(A)) {
        aim_keep_near(A, pl->probe.origin, res->dist, tol);
        if (A->near_d >= 0.0 && aim_narrowed(pl, A)) {
            /* narrowed with no line within tol of q(t): the hit nearest the edge */
            pl->st.aim_near++;
            return aim_ball(pl, A->near_c, A->near_h);
        }
    }
    st = aim_issue(pl);
    if (st > 0) {
        side_set(pl, k->tet, k->facet, side_get(pl, k->tet, k->facet) | SIDE_QUEUED);
        return VP_OK;
    }
    VP_TRY(aim_give_up(pl));
    return st;
}

#endif
