/* tasks.c — detect_access as a stack of probe tasks instead of a recursion.
 * A task probes the Voronoi edge dual to one facet of a tet from its active end: a hit adds the
 * facet to Del_v|S(E) with its ball; a miss proves the edge free and makes the other end
 * active (its Voronoi vertex gets a record and its edges are queued in turn). */
#include "vp_planner_priv.h"

/* ---------- Voronoi edges, clipped to Omega ---------- */


#define FAR_AWAY 1e30 /* length of a Voronoi ray (an edge to an infinite vertex) */
/* the device steps back out of Omega along an edge at most this many times, doubling the step
 * from two ulps of the coordinates: 16 doublings cover any rounding of the entry point */
#define ENTRY_STEP_TRIES 16
#define ROUND_REL 4e-16 /* about two ulps (2.2e-16 each), relative */
/* a ball centre stays this share of the probe's range inside its Voronoi edge: a centre on a
 * Voronoi vertex would put a fourth sample on its sphere; far above rounding, far below eps */
#define HIT_INSET_REL 1e-9

/* a Voronoi vertex farther than this from Omega's centre (in Omega circumradii) is placed on
 * its facet's line instead: a flat tet's float circumcentre is off by more than Omega's size */
#define FAR_VERTEX_REL 1e4
/* a tet's fourth vertex this close to its facet's plane (relative to the distances involved)
 * makes the tet flat: its Voronoi vertex is at the far end of its side */
#define FLAT_REL 1e-9

/* The parameter of a tet's Voronoi vertex on the line m + s n through its facet's circumcentre
 * (rho2 the facet's squared circumradius, d the tet's fourth vertex on side `side` of n): the
 * point equidistant from d and the facet's vertices; a flat tet's goes to the far end. */
static double line_param(const double *m, const double *n, double rho2, const double *d, int side, double far)
{
    double dm[3], num, den, s;
    vp_sub3(dm, d, m);
    num = vp_dot3(dm, dm) - rho2;
    den = vp_dot3(dm, n);
    if (!((double)side * den > FLAT_REL * (sqrt(vp_dot3(dm, dm)) + sqrt(rho2))))
        return num >= 0.0 ? side * far : -side * far;
    s = num / (2.0 * den);
    return s > far ? far : s < -far ? -far : s;
}

/* The Voronoi edge dual to facet f of finite tet t as a part of the facet's line (through its
 * circumcentre along its normal): its direction is exact to rounding even when a Voronoi vertex
 * is far away — the flat tets of coplanar samples on a flat face, whose float circumcentres
 * (1e15 away) made the clipped edge noise and left faces of a cube unprobed. */
static int edge_geom_line(const vp_planner_t *pl, uint32_t t, int f, edgegeom_t *g)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    uint32_t fv[3], u = w[4 + f] >> 2, j = w[4 + f] & 3u;
    const double *a, *b, *c;
    double ab[3], ac[3], n[3], m[3], co[3], far, rho2, s_t, s_u;
    int k;
    vp_dt_facet(&pl->dt, t, f, fv);
    if (fv[0] == VP_DT_GHOST || fv[1] == VP_DT_GHOST || fv[2] == VP_DT_GHOST) return VP_EINVAL;
    a = vp_dt_point(&pl->dt, fv[0]); b = vp_dt_point(&pl->dt, fv[1]); c = vp_dt_point(&pl->dt, fv[2]);
    vp_sub3(ab, b, a); vp_sub3(ac, c, a); vp_cross3(n, ab, ac);
    if (!vp_normalize3(n) || !vp_pl_facet_circumcenter(pl, fv, m)) return VP_EDEGEN;
    rho2 = vp_dist3(m, a);
    rho2 *= rho2;
    vp_pl_omega_center(&pl->cfg, co);
    far = vp_dist3(m, co) + 4.0 * vp_pl_omega_circumradius(&pl->cfg) + 1.0;
    /* vp_dt_facet orders the facet so that the tet's own fourth vertex is on the +n side */
    s_t = line_param(m, n, rho2, vp_dt_point(&pl->dt, w[f]), 1, far);
    s_u = vp_dt_is_ghost(&pl->dt, u) ? -far
        : line_param(m, n, rho2, vp_dt_point(&pl->dt, vp_dt_tet(&pl->dt, u)[j]), -1, far);
    for (k = 0; k < 3; k++) { g->a[k] = m[k] + s_t * n[k]; g->dir[k] = s_u >= s_t ? n[k] : -n[k]; }
    g->len = fabs(s_u - s_t);
    if (!vp_finite3(g->a)) return VP_EDEGEN;
    if (!(g->len > 0.0) || !vp_pl_omega_clip(&pl->cfg, g->a, g->dir, g->len, &g->t0, &g->t1)) g->t0 = g->t1 = 0.0;
    g->a_inside = vp_pl_omega_inside(&pl->cfg, g->a);
    return VP_OK;
}

/* Geometry of the Voronoi edge dual to facet f of tet t, oriented from t's Voronoi vertex. */
VP_PL_API int vp_pl_edge_geom(const vp_planner_t *pl, uint32_t t, int f, edgegeom_t *g)
{
    vp_dt_vedge_t e;
    int st = vp_dt_voronoi_edge(&pl->dt, t, f, &e), k;
    int tg = vp_dt_is_ghost(&pl->dt, t);
    memset(g, 0, sizeof *g);
    /* VP_EDEGEN: a tet of the edge is flat to the last bit (no float circumcentre at all): as
     * a far one, its Voronoi vertex is at the far end of its side of the facet's line */
    if (st != VP_OK && st != VP_EDEGEN) return st;
    {
        double co[3], big = FAR_VERTEX_REL * (vp_pl_omega_circumradius(&pl->cfg) + 1.0);
        vp_pl_omega_center(&pl->cfg, co);
        if (st == VP_EDEGEN || vp_dist3(e.from, co) > big || (!e.is_ray && vp_dist3(e.to, co) > big)) {
            if (!tg) return edge_geom_line(pl, t, f, g);
            /* a ghost tet: the finite side's edge, walked the other way */
            {
                const uint32_t *w = vp_dt_tet(&pl->dt, t);
                edgegeom_t h;
                if ((st = edge_geom_line(pl, w[4 + f] >> 2, (int)(w[4 + f] & 3u), &h)) != VP_OK) return st;
                for (k = 0; k < 3; k++) { g->a[k] = h.a[k] + h.len * h.dir[k]; g->dir[k] = -h.dir[k]; }
                g->len = h.len;
                if (!vp_pl_omega_clip(&pl->cfg, g->a, g->dir, g->len, &g->t0, &g->t1)) g->t0 = g->t1 = 0.0;
                g->a_inside = 0;
                return VP_OK;
            }
        }
    }
    if (!e.is_ray) {
        for (k = 0; k < 3; k++) { g->a[k] = e.from[k]; g->dir[k] = e.to[k] - e.from[k]; }
        g->len = sqrt(vp_dot3(g->dir, g->dir));
        if (!(g->len > 0.0)) { g->t0 = g->t1 = 0.0; g->a_inside = vp_pl_omega_inside(&pl->cfg, g->a); return VP_OK; }
        for (k = 0; k < 3; k++) g->dir[k] /= g->len;
    } else if (!tg) {
        /* finite tet, ghost neighbour: from the Voronoi vertex outward to infinity */
        for (k = 0; k < 3; k++) { g->a[k] = e.from[k]; g->dir[k] = e.dir[k]; }
        g->len = FAR_AWAY;
    } else {
        /* ghost tet: from a point far out on the ray, back in to the finite vertex */
        double c[3], back;
        vp_pl_omega_center(&pl->cfg, c);
        back = vp_dist3(e.from, c) + 4.0 * vp_pl_omega_circumradius(&pl->cfg) + 1.0;
        for (k = 0; k < 3; k++) { g->a[k] = e.from[k] + back * e.dir[k]; g->dir[k] = -e.dir[k]; }
        g->len = back;
    }
    if (!vp_finite3(g->a) || !vp_finite3(g->dir)) return VP_EDEGEN;
    if (!vp_pl_omega_clip(&pl->cfg, g->a, g->dir, g->len, &g->t0, &g->t1)) g->t0 = g->t1 = 0.0;
    g->a_inside = !tg && vp_pl_omega_inside(&pl->cfg, g->a);
    return VP_OK;
}

/* A point of the Voronoi vertex of finite tet t (its circumcentre), for records. */
VP_PL_API int vp_pl_tet_point(const vp_planner_t *pl, uint32_t t, double *p)
{
    return vp_dt_circumcenter(&pl->dt, t, p);
}

/* ---------- detect_access as a stack of probe tasks ---------- */

/* Probing every edge of every active vertex (the paper's detect_access): always with
 * VP_PLAN_PAPER, otherwise only while a hole could not be closed locally. */
VP_PL_API int vp_pl_exhaustive(const vp_planner_t *pl)
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

VP_PL_API void vp_pl_task_compact(vp_planner_t *pl)
{
    uint32_t i, n = 0;
    for (i = 0; i < pl->pool.ntask; i++)
        if (task_live(pl, &pl->pool.task[i])) {
            if (pl->pool.small) pl->pool.small[n] = pl->pool.small[i]; /* the kept ball goes along */
            pl->pool.task[n++] = pl->pool.task[i];
        }
    pl->pool.ntask = n;
}

VP_PL_API int vp_pl_task_push(vp_planner_t *pl, uint32_t t, int f, int forced)
{
    unsigned s = side_get(pl, t, f);
    vp_task_t *k;
    if (s & SIDE_QUEUED) return VP_OK;
    if (pl->pool.ntask >= pl->pool.cap_task) vp_pl_task_compact(pl);
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

VP_PL_API int vp_pl_facet_has_ghost(const vp_planner_t *pl, uint32_t t, int f)
{
    uint32_t fv[3];
    vp_dt_facet(&pl->dt, t, f, fv);
    return fv[0] == VP_DT_GHOST || fv[1] == VP_DT_GHOST || fv[2] == VP_DT_GHOST;
}

/* detect_access(t): queue a probe of every Voronoi edge around active vertex t that still
 * needs one. Without VP_PLAN_PAPER, edges towards vertices already known free are left out. */
VP_PL_API int vp_pl_explore(vp_planner_t *pl, uint32_t t)
{
    int f;
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    for (f = 3; f >= 0; f--) {
        unsigned s = side_get(pl, t, f);
        if ((s & (SIDE_QUEUED | SIDE_BLOCKED)) || vp_pl_facet_has_ghost(pl, t, f)) continue;
        /* BEHIND seen from a free vertex: the edge crosses S twice; its other ball is probed
         * from here */
        if ((s & SIDE_MASK) != SIDE_UNKNOWN && (s & SIDE_MASK) != SIDE_BEHIND) continue;
        if ((s & SIDE_MASK) == SIDE_UNKNOWN && !vp_pl_exhaustive(pl) && tet_active(pl, w[4 + f] >> 2)) continue;
        VP_TRY(vp_pl_task_push(pl, t, f, 0));
    }
    return VP_OK;
}

/* Marks tet t active (reachable). rec: its record, or VREC_OUT. */
static int activate(vp_planner_t *pl, uint32_t t, uint32_t rec)
{
    pay(pl, t)[0] = rec;
    vp_pl_cut_reached(pl, t);
    return vp_pl_explore(pl, t);
}

/* the unique point of the facet's plane equidistant from its vertices; 0 for a flat facet */
VP_PL_API int vp_pl_facet_circumcenter(const vp_planner_t *pl, const uint32_t *fv, double *m)
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
    if (!vp_pl_facet_circumcenter(pl, fv, m)) return 0;
    vp_sub3(d, m, origin);
    s = vp_dot3(d, dir);
    return s > 0.0 && s < range;
}

/* A side that cannot be probed from this end (no usable edge: a degenerate tet, or no place to
 * probe from): marked so that no rule asks for it again, which bounds the work of closing. */
static int task_unprobeable(vp_planner_t *pl, uint32_t t, int f)
{
    side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED | SIDE_DEGEN);
    pl->st.stalls++;
    return 0;
}

/* Body mode: where the line of edge g leaves Omega behind its vertex (the probe's origin), and
 * how far behind (*standoff); 0 when the line misses Omega. */
static int body_origin(const vp_planner_t *pl, const edgegeom_t *g, double *o, double *standoff)
{
    double back[3], t0b;
    int q;
    for (q = 0; q < 3; q++) back[q] = -g->dir[q];
    if (!vp_pl_omega_clip(&pl->cfg, g->a, back, VP_PL_HUGE, &t0b, standoff)) return 0;
    for (q = 0; q < 3; q++) o[q] = g->a[q] - *standoff * g->dir[q];
    return 1;
}

/* Timed body mode: a probe's start o moved back along its line (unit dir, into Omega) onto the
 * route sphere (route.c), by at most on_edge and within the rangefinder's range with the
 * probe's `range`: how far. */
static double start_back(const vp_planner_t *pl, double *o, const double *dir, double range, double on_edge)
{
#if VP_PL_TIMED
    double most = on_edge, s;
    int q;
    if (pl->cfg.max_range > 0.0 && pl->cfg.max_range - range < most) most = pl->cfg.max_range - range;
    s = vp_pl_start_back(pl, o, dir, most);
    for (q = 0; q < 3; q++) o[q] -= s * dir[q];
    return s;
#else
    (void)pl; (void)o; (void)dir; (void)range; (void)on_edge;
    return 0.0;
#endif
}

#if VP_PL_TUBES
/* halvings of the search for the start nearest the edge whose way out is proven */
#define TUBE_START_HALVINGS 8

/* Body mode with tubes: how far a probe that would start at o on dOmega, along unit dir, may
 * start further in (at most `most`): a sub-capsule of a proven capsule is proven, so the starts
 * o + s dir whose tube back to o is proven (tube.c) are those up to some s_in, found by halving;
 * of those, the one nearest the device, if its tube from the device is proven too and going
 * there and back out to o is no longer than the way to o without it (so a start inside never
 * lengthens the travel). Returns that advance (0: start at o); tube.goal_exit keeps o. */
static double tube_start(vp_planner_t *pl, const double *o, const double *dir, double most)
{
    const double *p = pl->pool.vrec[pl->dev.at].p;
    double w[3], s, lo = 0.0, hi = most, x[3];
    int q, i;
    memcpy(pl->tube.goal_exit, o, sizeof pl->tube.goal_exit);
    if (!(most > 0.0)) return 0.0;
    for (q = 0; q < 3; q++) x[q] = o[q] + most * dir[q];
    if (!vp_pl_tube_free(pl, x, o)) {
        for (i = 0; i < TUBE_START_HALVINGS; i++) {
            double mid = 0.5 * (lo + hi);
            for (q = 0; q < 3; q++) x[q] = o[q] + mid * dir[q];
            if (vp_pl_tube_free(pl, x, o)) lo = mid;
            else hi = mid;
        }
        most = lo;
        if (!(most > 0.0)) return 0.0;
    }
    vp_sub3(w, p, o);
    s = vp_dot3(w, dir);
    if (s > most) s = most;
    if (!(s > 0.0)) return 0.0;
    for (q = 0; q < 3; q++) x[q] = o[q] + s * dir[q];
    /* worth it only if going there and back out to o is no longer than the way to o without it */
    if (vp_dist3(p, x) + s > vp_pl_tube_way_out(pl, o)) return 0.0;
    if (!vp_pl_tube_free(pl, p, x)) return 0.0;
    pl->st.tube_starts++;
    pl->tube.goal_in = 1;
    return s;
}
#endif

#ifndef VP_CORE_MCU
/* 1 when task k's Voronoi edge (the vertices of its tet and of the tet across its facet) is the
 * one kept in tv/uv beside its slot; else 0, and tv/uv keep it from now on. What a slot keeps of
 * its edge (a start, a ball) is a function of those vertices alone. */
static int edge_kept(const vp_planner_t *pl, const vp_task_t *k, uint32_t tv[4], uint32_t uv[4])
{
    const uint32_t *w = vp_dt_tet(&pl->dt, k->tet);
    const uint32_t *x = vp_dt_tet(&pl->dt, w[4 + k->facet] >> 2);
    if (memcmp(tv, w, 4 * sizeof *tv) == 0 && memcmp(uv, x, 4 * sizeof *uv) == 0) return 1;
    memcpy(tv, w, 4 * sizeof *tv);
    memcpy(uv, x, 4 * sizeof *uv);
    return 0;
}

/* body mode with tubes: the newest tasks looked at for the one whose probe starts nearest the
 * head (without tubes all of them are: the 1,024 newest left the torus at eps 3 open where all
 * close it, at twice the machine time; with tubes all ended the mug open, its tubes unproven) */
#define NEAR_WINDOW_TUBES 32u

/* Body mode: where the probe along the Voronoi edge dual to facet f of t would start (the
 * edge's line leaving Omega behind t's vertex); 0 when that cannot be said cheaply. A function
 * of the two tets' vertices alone. */
static int edge_origin(const vp_planner_t *pl, uint32_t t, int f, double *o, double *dir)
{
    edgegeom_t g;
    double standoff;
    int q;
    if (vp_pl_edge_geom(pl, t, f, &g) != VP_OK || !(g.t0 < g.t1)) return 0;
    if (dir) memcpy(dir, g.dir, sizeof g.dir);
    if (!g.a_inside) {
        for (q = 0; q < 3; q++) o[q] = g.a[q] + g.t0 * g.dir[q];
        start_back(pl, o, g.dir, g.t1 - g.t0, g.t0);
        return 1;
    }
    if (!body_origin(pl, &g, o, &standoff)) return 0;
    start_back(pl, o, g.dir, standoff + g.t1, VP_PL_HUGE);
    return 1;
}

/* A live task may be preferred for its start: its tet active, not a ray walked on */
static int task_startable(const vp_planner_t *pl, const vp_task_t *k)
{
    return tet_active(pl, k->tet) && !(k->off > 0.0);
}

/* Where task k's probe would start; 0 when it cannot be said cheaply (the task is then not
 * preferred). */
VP_PL_API int vp_pl_task_origin(const vp_planner_t *pl, const vp_task_t *k, double *o)
{
    if (!task_live(pl, k) || !task_startable(pl, k)) return 0;
    return edge_origin(pl, k->tet, k->facet, o, NULL);
}

/* timed: slot i's kept direction (a float each: an estimate's input) */
static void near_dir_put(vp_planner_t *pl, uint32_t i, const double *d)
{
    float *f = pl->pool.near_dir + 3 * (size_t)i;
    f[0] = (float)d[0];
    f[1] = (float)d[1];
    f[2] = (float)d[2];
}

/* vp_pl_task_origin of the live, startable task in slot i, worked out again only when its edge
 * is not the one kept in the slot's vp_task_near_t (an insertion replaced a tet of it, or the
 * slot holds another task; every time in an arena too small to keep them); with dir (timed) its
 * probe's direction too */
static int task_origin_kept(vp_planner_t *pl, uint32_t i, double *o, double *dir)
{
    const vp_task_t *k = &pl->pool.task[i];
    vp_task_near_t *c = pl->pool.near ? &pl->pool.near[i] : NULL;
    if (!c) {
        /* a small arena keeps no starts; the direction as a kept one would be (a float) */
        int ok = edge_origin(pl, k->tet, k->facet, o, dir), q;
        for (q = 0; ok && dir && q < 3; q++) dir[q] = (double)(float)dir[q];
        return ok;
    }
    if (!edge_kept(pl, k, c->tv, c->uv)) {
        double d[3] = { 0.0, 0.0, 0.0 };
        c->ok = (uint8_t)edge_origin(pl, k->tet, k->facet, c->o, d);
        if (pl->pool.near_dir) near_dir_put(pl, i, d);
    }
    if (c->ok) memcpy(o, c->o, sizeof c->o);
    if (c->ok && dir) {
        const float *f = pl->pool.near_dir + 3 * (size_t)i;
        dir[0] = f[0]; dir[1] = f[1]; dir[2] = f[2];
    }
    return c->ok;
}

/* Body mode: every probe starts on dOmega (timed round a ball: on the route sphere just beyond,
 * start_back) and the head travels round Omega to it. Of the waiting tasks (with tubes, of the
 * NEAR_WINDOW_TUBES newest), the one whose probe starts nearest the head (timed, route.c: whose
 * start and aim the head reaches soonest at the axes' top speeds) is put on top of the stack
 * (ties: the newer; none: the top stays). Without tubes the tasks whose tet an insertion killed
 * are dropped on the way, the order kept: they are most of the stack (the torus at eps-rel 0.01:
 * 17k of 18k), and each pick would read them all again. The stack may end empty. */
VP_PL_API void vp_pl_task_nearest_on_top(vp_planner_t *pl)
{
    uint32_t i, n, top, best = NONE;
    double bd = VP_PL_HUGE, o[3], dir[3];
    int tubes = pl->cfg.min_feature > 0.0, timed = vp_pl_timed(pl);
    for (i = n = tubes && pl->pool.ntask > NEAR_WINDOW_TUBES ? pl->pool.ntask - NEAR_WINDOW_TUBES : 0; i < pl->pool.ntask; i++) {
        int live = task_live(pl, &pl->pool.task[i]);
        if (!tubes) {
            if (!live) continue;
            if (n != i) {
                pl->pool.task[n] = pl->pool.task[i];
                if (pl->pool.near) pl->pool.near[n] = pl->pool.near[i];
                if (pl->pool.near_dir) memcpy(pl->pool.near_dir + 3 * (size_t)n, pl->pool.near_dir + 3 * (size_t)i, 3 * sizeof(float));
            }
        }
        if (live && task_startable(pl, &pl->pool.task[n]) && task_origin_kept(pl, n, o, timed ? dir : NULL)) {
            double d = timed ? vp_pl_way_time(pl, o, dir) : vp_dist3(o, pl->dev.pos);
            if (d <= bd) { bd = d; best = n; }
        }
        n++;
    }
    pl->pool.ntask = n;
    top = n - 1;
    if (best != NONE && best != top) {
        vp_task_t t = pl->pool.task[best];
        pl->pool.task[best] = pl->pool.task[top];
        pl->pool.task[top] = t;
        if (pl->pool.near) {
            vp_task_near_t c = pl->pool.near[best];
            pl->pool.near[best] = pl->pool.near[top];
            pl->pool.near[top] = c;
        }
        if (pl->pool.near_dir) {
            float *a = pl->pool.near_dir + 3 * (size_t)best, *b = pl->pool.near_dir + 3 * (size_t)top, x[3];
            memcpy(x, a, sizeof x);
            memcpy(a, b, sizeof x);
            memcpy(b, x, sizeof x);
        }
    }
}
#endif

#ifndef VP_CORE_MCU
/* VP_PLAN_SMALL_FIRST: the newest tasks looked at for the smallest ball */
#define SMALL_WINDOW 32u
/* ... but for facets at most this many floors (min_size) across: at a knife edge those are the
 * facets laid across the fold, which wait their turn */
#define SMALL_HOLD 1.0

/* The squared radius of the smallest surface Delaunay ball task k's probe can find: a ball
 * centred on the facet's Voronoi edge (its part in Omega) through the facet's vertices, of
 * radius^2 = R^2 + |c - m|^2 for the facet's circumcentre m and circumradius R; a function of
 * the two tets' vertices alone. -1 when the task is not a candidate (degenerate, or a facet
 * within the hold). */
static double small_key_of(const vp_planner_t *pl, const vp_task_t *k)
{
    uint32_t fv[3];
    double m[3], x[3], r2, s, d2;
    edgegeom_t g;
    int q;
    vp_dt_facet(&pl->dt, k->tet, k->facet, fv);
    if (fv[0] == VP_DT_GHOST || fv[1] == VP_DT_GHOST || fv[2] == VP_DT_GHOST || !vp_pl_facet_circumcenter(pl, fv, m))
        return -1.0;
    vp_sub3(x, m, vp_dt_point(&pl->dt, fv[0]));
    r2 = vp_dot3(x, x);
    if (pl->cfg.min_size > 0.0 && r2 <= SMALL_HOLD * SMALL_HOLD * pl->cfg.min_size * pl->cfg.min_size) return -1.0;
    if (vp_pl_edge_geom(pl, k->tet, k->facet, &g) != VP_OK || !(g.t0 < g.t1)) return -1.0;
    /* the point of the edge in Omega nearest m: m's foot on its line, clamped */
    vp_sub3(x, m, g.a);
    s = vp_dot3(x, g.dir);
    s = s < g.t0 ? g.t0 : s > g.t1 ? g.t1 : s;
    for (q = 0; q < 3; q++) x[q] = g.a[q] + s * g.dir[q] - m[q];
    d2 = vp_dot3(x, x);
    return r2 + d2;
}

/* small_key_of for the task in slot i, or -1 when it is no candidate now (gone, walked on, its
 * tet not reached): worked out again only when its edge is not the one kept beside the slot (a
 * function of the two tets' vertices alone; every time in an arena too small to keep them) */
static double task_small_key(vp_planner_t *pl, uint32_t i)
{
    const vp_task_t *k = &pl->pool.task[i];
    vp_task_small_t *c = pl->pool.small ? &pl->pool.small[i] : NULL;
    if (!task_live(pl, k) || k->off > 0.0 || !tet_active(pl, k->tet)) return -1.0;
    if (!c) return small_key_of(pl, k);
    if (!edge_kept(pl, k, c->tv, c->uv) || !c->ok) {
        c->key = small_key_of(pl, k);
        c->ok = 1;
    }
    return c->key;
}

/* Point mode with VP_PLAN_SMALL_FIRST: of the SMALL_WINDOW newest tasks, the one whose probe can
 * find the smallest ball is put on top of the stack, the others keeping their order (ties: the
 * newer). A small ball is a facet of the surface being sampled finely; the large ones mostly
 * reach into the pockets of the hull, where the insertions found meanwhile kill them unprobed.
 * Probes per vertex at --accuracy-rel 0.002, with the tilt waiting for the size pass (facets.c):
 * fandisk 8.23 -> 7.38, dino 9.66 -> 8.37, knot 8.86 -> 7.97 (README).
 * A ray being walked on stays on top. */
VP_PL_API void vp_pl_task_small_on_top(vp_planner_t *pl)
{
    uint32_t i, lo, best = NONE, top = pl->pool.ntask - 1;
    double bk = VP_PL_HUGE;
    if (pl->pool.task[top].off > 0.0) return;
    lo = pl->pool.ntask > SMALL_WINDOW ? pl->pool.ntask - SMALL_WINDOW : 0;
    for (i = pl->pool.ntask; i-- > lo;) {
        double key = task_small_key(pl, i);
        if (key >= 0.0 && key < bk) {
            bk = key;
            best = i;
        }
    }
    if (best != NONE && best != top) {
        vp_task_t k = pl->pool.task[best];
        memmove(&pl->pool.task[best], &pl->pool.task[best + 1], (size_t)(top - best) * sizeof k);
        pl->pool.task[top] = k;
        if (pl->pool.small) {
            vp_task_small_t c = pl->pool.small[best];
            memmove(&pl->pool.small[best], &pl->pool.small[best + 1], (size_t)(top - best) * sizeof c);
            pl->pool.small[top] = c;
        }
    }
}
#endif

/* VP_PLAN_FAR_READS (body mode): the beam goes on past the edge's end, and a triangulating head
 * reads the spot wherever it lands; so the range asked runs on to where the line leaves Omega
 * (within the rangefinder's reach), and a reading past the edge's end proves the whole edge free
 * (as a miss would) and is a point of S seen from elsewhere (vp_pl_task_finish). 0: nothing asked
 * beyond the edge (point mode, no such flag, or a line longer than the reach, walked on). */
static double far_reach(const vp_planner_t *pl, const double *o, const double *dir, double range)
{
#if VP_PL_CONTACTS
    double t0, t1;
    if (!(pl->cfg.flags & VP_PLAN_FAR_READS) || !(pl->cfg.clearance > 0.0) || vp_pl_probe_limited(pl)) return 0.0;
    if (!vp_pl_omega_clip(&pl->cfg, o, dir, range + 2.0 * vp_pl_omega_circumradius(&pl->cfg), &t0, &t1) ||
        !(t1 > range))
        return 0.0;
    return vp_pl_clamp_range(pl, t1);
#else
    (void)pl; (void)o; (void)dir; (void)range;
    return 0.0;
#endif
}

/* Prepares the probe of task k: the route to its origin and the ray. Returns 1 when a probe
 * is ready, 0 when the task resolved without probing. */
VP_PL_API int vp_pl_task_start(vp_planner_t *pl, vp_task_t *k)
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
    if ((s & SIDE_MASK) == SIDE_UNKNOWN && !vp_pl_exhaustive(pl) && !(s & SIDE_FORCED) && tet_active(pl, u))
        return 0;
    if (!tet_active(pl, t)) return 0;
    st = vp_pl_edge_geom(pl, t, f, &g);
    if (st != VP_OK) return task_unprobeable(pl, t, f); /* degenerate: no usable edge */
    if (!(g.t0 < g.t1) || k->off >= g.t1 - g.t0 - LEN_REL_EPS * (1.0 + g.t1)) {
        /* the edge lies outside Omega (or is already proven free by the walked ray): free */
        uint32_t pf = k->off > 0.0 ? k->proof : PROOF_OUTSIDE;
        side_set(pl, t, f, SIDE_UNKNOWN);
        side_free(pl, t, f, pf);
        side_free(pl, u, (int)j, pf);
        return 0;
    }
    pl->probe.standoff = 0.0;
    pl->probe.vantage = 0;
#if VP_PL_CONTACTS
    pl->aim.on = 0;
#endif
    if (g.a_inside && pl->cfg.clearance > 0.0) {
        /* a device with a body stays outside Omega: it probes the edge's line from where the
         * line leaves Omega behind the vertex; only a hit beyond the vertex is on the edge */
        double t1b, back_s;
        if (!body_origin(pl, &g, o, &t1b)) return task_unprobeable(pl, t, f);
#if VP_PL_TUBES
        if ((s & SIDE_RETRIED) && !pl->tube.on) {
            /* unseen at a hole: its line is what occluded it; from aside instead (aim.c) */
            st = vp_pl_aim_start(pl, k, o);
            if (st < 0) pl->error = st;
            return st > 0;
        }
        if (pl->tube.on) {
            /* start nearer the vertex (at least the clearance behind it) where tubes allow */
            double adv = tube_start(pl, o, g.dir, t1b - pl->cfg.clearance);
            int q;
            for (q = 0; q < 3; q++) o[q] += adv * g.dir[q];
            t1b -= adv;
        }
#endif
        range = t1b + g.t1;
        /* timed: from the route sphere, a little further back on the line */
        back_s = start_back(pl, o, g.dir, range, VP_PL_HUGE);
        range += back_s;
        pl->probe.standoff = t1b + back_s;
    } else if (g.a_inside) {
        goal = tet_rec(pl, t);
        if (goal == VREC_OUT || goal == NONE) return task_unprobeable(pl, t, f);
        /* from where the device will stand: the record's point (g.a is the same vertex, but
         * worked out along the facet's line when the other end is far, so not the same bits) */
        memcpy(o, pl->pool.vrec[goal].p, sizeof o);
        range = g.t1;
    } else {
        int q, tries;
        double back = 0.0;
        for (q = 0; q < 3; q++) o[q] = g.a[q] + g.t0 * g.dir[q];
        range = g.t1 - g.t0;
        /* where the edge enters Omega, from a far Voronoi vertex (a nearly flat tet): rounding
         * can put it inside Omega; the device waits outside, so step back along the line */
        for (tries = 0; vp_pl_omega_inside(&pl->cfg, o) && tries < ENTRY_STEP_TRIES; tries++) {
            double step = back > 0.0 ? back : ROUND_REL * (fabs(g.t0) + sqrt(vp_dot3(g.a, g.a))) + pl->ptol;
            for (q = 0; q < 3; q++) o[q] -= step * g.dir[q];
            range += step;
            back += step;
        }
        if (vp_pl_omega_inside(&pl->cfg, o)) return task_unprobeable(pl, t, f);
#if VP_PL_TUBES
        if (pl->tube.on && pl->cfg.clearance > 0.0 && k->off <= 0.0) {
            /* start further along the edge (up to the clearance before its end) where tubes allow */
            double adv = tube_start(pl, o, g.dir, range - pl->cfg.clearance);
            for (q = 0; q < 3; q++) o[q] += adv * g.dir[q];
            range -= adv;
        }
#endif
        /* timed: from the route sphere, still on the edge (g.a lies outside Omega) */
        if (k->off <= 0.0) range += start_back(pl, o, g.dir, range, g.t0 - back);
    }
    if (k->off > 0.0) {
        /* resume a range-limited probe from the end of its free part, where the device was left
         * (vp_pl_walk_on): from that record's point itself, the MOVE's end to the last bit (the
         * edge's start moved on by off rounds otherwise) */
        range -= k->off;
        goal = pl->dev.at;
        memcpy(o, pl->pool.vrec[goal].p, sizeof o);
    }
    pl->probe.full = range;
    range = vp_pl_clamp_range(pl, range);
    if (goal != NONE) st = vp_pl_plan_route(pl, goal, NULL);
    else st = vp_pl_plan_route(pl, NONE, o);
    if (VP_PL_CONTACTS && st == PL_UNREACHABLE) {
        /* a contact withdrew every known way there: unseen from this end */
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
        return 0;
    }
    if (st != VP_OK) { pl->error = st; return 0; }
    memcpy(pl->probe.origin, o, sizeof o);
    memcpy(pl->probe.dir, g.dir, sizeof g.dir);
    pl->probe.range = range;
    pl->probe.reach = far_reach(pl, o, g.dir, range);
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

#if VP_PL_CONTACTS
/* The prepared probe will not be made (its origin is out of reach): its side is unseen. */
VP_PL_API void vp_pl_probe_drop(vp_planner_t *pl)
{
    vp_task_t *k = &pl->probe.task;
    pl->probe.ready = 0;
    pl->aim.on = 0;
    if (vp_dt_alive(&pl->dt, k->tet))
        side_set(pl, k->tet, k->facet, (side_get(pl, k->tet, k->facet) & ~(SIDE_QUEUED | SIDE_FORCED)) | SIDE_BLOCKED);
}
#endif

#if VP_PL_CONTACTS || VP_PL_LINE_LASER
/* samples seen from elsewhere (body mode) and a line laser's samples */
#define OCCLUDED_SPACING 0.25
#define OCCLUDED_REACH 1.0
/* Inserts the point h of S when no sample lies within sp of it: the nearest sample is a vertex
 * of a tet whose circumsphere holds h (it becomes h's Delaunay neighbour), found by walking the
 * conflict region from the tet that holds it. 1: inserted (the new sample in *v when v is not
 * NULL); 0: not (a sample too near, outside Omega, a conflict region too large to walk, no
 * room); < 0 an error. */
VP_PL_API int vp_pl_sample_insert(vp_planner_t *pl, const double h[3], uint32_t hint, double sp, uint32_t *vout)
{
    double near2;
    uint32_t t0, v;
    int st;
    if (!vp_pl_omega_inside(&pl->cfg, h)) return 0;
    if (vp_dt_locate(&pl->dt, h, hint, &t0) != VP_OK) return 0;
    if (!vp_pl_nearest_sample(pl, h, t0, &near2) || !(near2 > sp * sp)) return 0;
    if (!vp_pl_pools_have_room(pl)) return 0;
    st = vp_dt_insert(&pl->dt, h, t0, &v);
    if (st == VP_EDUP) return 0;
    if (st != VP_OK) return st;
    pl->st.insertions++;
    pl->close.exhaustive = 0;
    if (vout) *vout = v;
    st = vp_pl_after_insert(pl, v);
    return st == VP_OK ? 1 : st;
}

/* A sample seen from elsewhere: where the line from dOmega met S before an occluded Voronoi edge
 * is a point of S (the "picking region" variant of Delaunay refinement takes such points near
 * the ball it refines). Inserted when no sample lies within OCCLUDED_SPACING eps of it, so the
 * samples keep a spacing and the refinement its bound. 1 when inserted. */
static int occluded_sample(vp_planner_t *pl, double dist)
{
    double h[3], sp = OCCLUDED_SPACING * pl->cfg.eps;
    uint32_t fv[3];
    double m[3];
    int q;
    if (pl->cfg.min_size > 0.0 && pl->cfg.min_size < sp) sp = pl->cfg.min_size;
    for (q = 0; q < 3; q++) h[q] = pl->probe.origin[q] + dist * pl->probe.dir[q];
    if (!vp_pl_omega_inside(&pl->cfg, h)) return VP_OK;
    /* only a point near the unseen facet (within eps of its circumcentre: the picking region
     * about the surface Delaunay ball it would have) */
    vp_dt_facet(&pl->dt, pl->probe.task.tet, pl->probe.task.facet, fv);
    if (fv[0] == VP_DT_GHOST || fv[1] == VP_DT_GHOST || fv[2] == VP_DT_GHOST || !vp_pl_facet_circumcenter(pl, fv, m) ||
        vp_dist3(m, h) > OCCLUDED_REACH * pl->cfg.eps)
        return VP_OK;
    return vp_pl_sample_insert(pl, h, pl->probe.task.tet, sp, NULL);
}

/* The oldest of a line laser's queued hits (planner.c, vp_planner_feed_ray) becomes a sample when
 * no sample lies within eps of it: the spacing the refinement itself keeps (a bad ball's centre
 * is farther than eps from every sample), so the samples' packing bound and the refinement's end
 * (every ball at most eps, the mesh closed) are those of paper 000. */
#if VP_PL_LINE_LASER
VP_PL_API int vp_pl_ray_sample(vp_planner_t *pl)
{
    double h[3];
    uint32_t hint = 0;
    int st;
    memcpy(h, pl->rays.pts[0], sizeof h);
    pl->rays.n--;
    memmove(pl->rays.pts[0], pl->rays.pts[1], pl->rays.n * sizeof pl->rays.pts[0]);
    /* a live tet to walk from: the last task's, or the first alive */
    if (pl->probe.task.tet < pl->dt.ntet_slots && vp_dt_alive(&pl->dt, pl->probe.task.tet)) hint = pl->probe.task.tet;
    else
        while (hint < pl->dt.ntet_slots && !vp_dt_alive(&pl->dt, hint)) hint++;
    st = vp_pl_sample_insert(pl, h, hint, pl->cfg.eps, NULL);
    pl->st.ray_samples += st == 1;
    return st;
}
#endif
#endif

#if VP_PL_TUBES
/* ways out looked at from a start past an occluder: the 26 directions of a cube's faces, edges
 * and corners (vantage_dir) */
static void vantage_dir(int j, double *u)
{
    int q, c[3];
    c[0] = j % 3 - 1; c[1] = (j / 3) % 3 - 1; c[2] = j / 9 - 1;
    for (q = 0; q < 3; q++) u[q] = (double)c[q];
    vp_normalize3(u);
}
#define VANTAGE_STARTS 24 /* starts looked at on a line at most, min_feature / 2 apart or more */
#define VANTAGE_KEEP 4 /* the best ways out (way_better) checked for a proven tube */
#define SURVEY_FAILS_FREE 8u /* surveys found blocked before the ratio to those that pass counts */

/* Body mode with tubes: the current probe again, from x (s further along its line), reached by a
 * tube from e on dOmega. Returns 1 when it is ready, 0 when no route, < 0 an error. */
VP_PL_API int vp_pl_vantage_go(vp_planner_t *pl, const double *x, double s, const double *e)
{
    vp_pl_probe_t *P = &pl->probe;
    int st;
    memcpy(pl->tube.goal_exit, e, sizeof pl->tube.goal_exit);
    pl->tube.goal_in = 1;
    st = vp_pl_plan_route(pl, NONE, x);
    if (st != VP_OK) { pl->tube.goal_in = 0; return st < 0 ? st : 0; }
    memcpy(P->origin, x, sizeof P->origin);
    P->standoff -= s;
    /* the rest of the line from x, within the rangefinder's reach again (the range kept was
     * the reach's from the old origin: s can lie beyond it) */
    P->full -= s;
    P->range = vp_pl_clamp_range(pl, P->full);
    P->reach = 0.0;
    P->origin_rec = pl->dev.at;
    P->chain_proof = PROOF_NONE;
    P->vantage = 1;
    P->ready = 1;
    side_set(pl, P->task.tet, P->task.facet, side_get(pl, P->task.tet, P->task.facet) | SIDE_QUEUED);
    pl->st.vantages++;
    return 1;
}

/* The probe waiting for a survey will not be made (no tube proven): its side is unseen. */
VP_PL_API int vp_pl_vantage_unseen(vp_planner_t *pl)
{
    vp_task_t *k = &pl->probe.task;
    if (vp_dt_alive(&pl->dt, k->tet))
        side_set(pl, k->tet, k->facet, side_get(pl, k->tet, k->facet) | SIDE_BLOCKED);
    return VP_OK;
}

/* the least distance from a sample to segment [a, b], or any value below `need` once one sample
 * is nearer than that (a guess at how clear a way is, cut short when it is not) */
static double sample_clearance(const vp_planner_t *pl, const double *a, const double *b, double need)
{
    double d[3], l2, best = VP_PL_HUGE, n2 = need * need;
    uint32_t v;
    vp_sub3(d, b, a);
    l2 = vp_dot3(d, d);
    for (v = 0; v < pl->dt.nvert; v++) {
        const vp_dt_vertex_t *p = vp_dt_vertex(&pl->dt, v);
        double dd;
        if (p->tet == VP_DT_NONE || p->tet > VP_DT_MAX_VERTICES) continue;
        dd = vp_pl_seg_dist2(a, d, l2, p->xyz);
        if (dd < best) best = dd;
        if (best < n2) break;
    }
    return sqrt(best);
}

/* A way out is better when less of it is unexplored (cells on its axis no free ray has marked:
 * the object's inside is never marked), then when it is clearer of the samples. */
static int way_better(uint32_t un, double c, uint32_t un_than, double c_than)
{
    return un < un_than || (un == un_than && c > c_than);
}

/* Body mode with tubes: the line met S at `dist`, before the edge's vertex (at the standoff).
 * The same line is probed again from past the occluder, between it and the vertex, when a
 * tube from there straight out of Omega (towards a face, an edge or a corner of a cube) is
 * proven: the device goes round Omega to that way out and in along it. Starts lie at least the
 * tube's reach from every sample; of their ways, clear of the samples by the body and the
 * margin, only the best few (way_better) are checked; when none is proven, the best is
 * surveyed first by parallel rays (tube.c), within the survey budget. Once per task. Returns 1
 * when the probe (or the survey) is under way. */
static int vantage_retry(vp_planner_t *pl, double dist)
{
    vp_pl_probe_t *P = &pl->probe;
    double lo = dist + pl->cfg.clearance, hi = P->standoff - pl->cfg.clearance, o[3], dir[3];
    double need = pl->cfg.clearance + pl->cfg.feature_margin + 0.5 * pl->cfg.min_feature;
    double need_x = pl->tube.reach + pl->tube.half;
    double cx[VANTAGE_KEEP][3], cu[VANTAGE_KEEP][3], ce[VANTAGE_KEEP][3], cc[VANTAGE_KEEP], cs[VANTAGE_KEEP];
    uint32_t cn[VANTAGE_KEEP];
    int i, j, q, n = 0, starts;
    memcpy(o, P->origin, sizeof o);
    memcpy(dir, P->dir, sizeof dir);
    if (!(lo < hi)) return 0;
    starts = (int)ceil((hi - lo) / (0.5 * pl->cfg.min_feature)) + 1;
    if (starts > VANTAGE_STARTS) starts = VANTAGE_STARTS;
    if (starts < 2) starts = 2;
    for (i = 0; i < starts; i++) {
        /* from the vertex's end of the stretch towards the occluder (the line may run through the
         * occluding part for a while past its first point) */
        double s = hi - (hi - lo) * i / (starts - 1), x[3];
        for (q = 0; q < 3; q++) x[q] = o[q] + s * dir[q];
        if (sample_clearance(pl, x, x, need_x) < need_x) continue;
        for (j = 0; j < 27; j++) {
            double e[3], u[3], T, c;
            uint32_t un;
            int at;
            if (j == 13) continue; /* the centre of the cube: no direction */
            vantage_dir(j, u);
            T = vp_pl_omega_exit(&pl->cfg, x, u);
            if (!(T > 0.0)) continue;
            for (q = 0; q < 3; q++) e[q] = x[q] + T * u[q];
            un = vp_pl_tube_unexplored(pl, x, e);
            if (n == VANTAGE_KEEP && un > cn[n - 1]) continue;
            c = sample_clearance(pl, x, e, need);
            if (c < need) continue;
            if (n == VANTAGE_KEEP && !way_better(un, c, cn[n - 1], cc[n - 1])) continue;
            /* kept in order, best first */
            for (at = n < VANTAGE_KEEP ? n++ : n - 1; at > 0 && way_better(un, c, cn[at - 1], cc[at - 1]); at--) {
                memcpy(cx[at], cx[at - 1], sizeof cx[at]);
                memcpy(cu[at], cu[at - 1], sizeof cu[at]);
                memcpy(ce[at], ce[at - 1], sizeof ce[at]);
                cc[at] = cc[at - 1];
                cn[at] = cn[at - 1];
                cs[at] = cs[at - 1];
            }
            memcpy(cx[at], x, sizeof x);
            memcpy(cu[at], u, sizeof u);
            memcpy(ce[at], e, sizeof e);
            cc[at] = c;
            cn[at] = un;
            cs[at] = s;
        }
    }
    for (i = 0; i < n; i++)
        if (vp_pl_tube_free(pl, cx[i], ce[i])) {
            int st = vp_pl_vantage_go(pl, cx[i], cs[i], ce[i]);
            if (st != 0) return st;
        }
    /* surveys take at most half of all probes, and stop where most are found blocked */
    if (n == 0 || pl->st.survey_probes > pl->st.probes - pl->st.survey_probes ||
        pl->st.surveys_failed >= SURVEY_FAILS_FREE + 2u * (pl->st.surveys - pl->st.surveys_failed))
        return 0;
    vp_pl_survey_start(pl, cx[0], cu[0], cs[0]);
    return 1;
}
#endif

/* Side f of t met S at h, a point of its Voronoi edge: the facet's record with its surface
 * Delaunay ball centred at h (`outside` a point on the probe's side; pf the proof of the free
 * part up to h, or none; the record's index into *rec unless NULL), the side hit, the other end
 * behind S unless it was hit too. */
VP_PL_API int vp_pl_side_hit(vp_planner_t *pl, uint32_t t, int f, const double *h, const double *outside, uint32_t pf,
                             uint32_t *rec)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    uint32_t u = w[4 + f] >> 2, j = w[4 + f] & 3u, fv[3], fr;
    unsigned su = side_get(pl, u, (int)j) & SIDE_MASK;
    int st;
    vp_dt_facet(&pl->dt, t, f, fv);
    st = vp_pl_frec_add(pl, fv, h, outside, t, pf, &fr);
    if (st != VP_OK) return st;
    side_set(pl, t, f, SIDE_HIT);
    if (su == SIDE_HIT) {
        /* seen from both ends: two balls; the larger one decides refinement */
        vp_pl_frec_set_ball(pl, fr, h);
    } else {
        side_set(pl, u, (int)j, (side_get(pl, u, (int)j) & ~SIDE_MASK) | SIDE_BEHIND);
    }
    if (rec) *rec = fr;
    return VP_OK;
}

/* The result of the probe of the current task. */
VP_PL_API int vp_pl_task_finish(vp_planner_t *pl, const vp_probe_result_t *res)
{
    vp_task_t *k = &pl->probe.task;
    uint32_t t = k->tet, u, j, fv[3], fr;
    int f = k->facet, q, far;
#if VP_PL_CONTACTS
    int st;
#endif
    const uint32_t *w;
    double tol = pl->cfg.noise_tol;
#if VP_PL_CONTACTS
    if (pl->aim.on) return vp_pl_aim_feed(pl, res);
#endif
    w = vp_dt_tet(&pl->dt, t);
    u = w[4 + f] >> 2;
    j = w[4 + f] & 3u;
    side_set(pl, t, f, side_get(pl, t, f) & ~(SIDE_QUEUED | SIDE_FORCED));
    if (res->hit == VP_PROBE_TOO_CLOSE) {
        /* nothing learnt: not free, no sample; not asked again from this end */
        unsigned was = side_get(pl, t, f);
        side_set(pl, t, f, was | SIDE_BLOCKED);
#if VP_PL_CONTACTS
        if ((was & SIDE_RETRIED) && pl->cfg.clearance > 0.0 && !pl->tube.on && !(pl->probe.standoff > 0.0)) {
            /* unseen at a hole, once more (its line enters Omega from a vertex outside: no
             * standoff; and its spot cannot be read): from aside (aim.c) */
            int st2 = vp_pl_aim_start(pl, k, pl->probe.origin);
            return st2 < 0 ? st2 : VP_OK;
        }
#endif
        return VP_OK;
    }
    if (res->hit && pl->probe.standoff > 0.0 && res->dist < pl->probe.standoff + tol) {
        /* from a standoff: the line met S before reaching the vertex; the edge is unseen */
        pl->st.occluded++;
#if VP_PL_TUBES
        if (pl->tube.on && !pl->probe.vantage) {
            /* from past the occluder, if a tube leads there */
            VP_TRY(vp_pl_probe_proof(pl, res, &fr)); /* the free part up to the occluder */
            st = vantage_retry(pl, res->dist);
            if (st != 0) return st < 0 ? st : VP_OK;
        }
#endif
#if VP_PL_CONTACTS
        {
            unsigned was = side_get(pl, t, f);
            side_set(pl, t, f, was | SIDE_BLOCKED);
            st = occluded_sample(pl, res->dist);
            if (st != 0 || !(was & SIDE_RETRIED)) return st < 0 ? st : VP_OK;
            /* unseen at a hole, once more: from aside (aim.c) */
            st = vp_pl_aim_start(pl, k, pl->probe.origin);
            return st < 0 ? st : VP_OK;
        }
#else
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
        return VP_OK;
#endif
    }
    if (res->hit && res->dist <= pl->probe.range + tol) {
        /* the ball centre stays strictly inside the edge: a centre on a Voronoi vertex (a hit
         * at 0 or past the end, within the noise) would put a fourth sample on its sphere */
        double h[3], d = res->dist, inset = HIT_INSET_REL * pl->probe.range;
        if (d > pl->probe.range - inset) d = pl->probe.range - inset;
        if (d < inset) d = inset;
        for (q = 0; q < 3; q++) h[q] = pl->probe.origin[q] + d * pl->probe.dir[q];
        {
            uint32_t pf;
            VP_TRY(vp_pl_probe_proof(pl, res, &pf));
            return vp_pl_side_hit(pl, t, f, h, pl->probe.origin, pf, NULL);
        }
    }
    /* a dropout must not open a way into the object: a miss is trusted only after
     * confirm_misses more misses on the same ray (twice that where a hit is expected); a
     * reading past the edge's end is no dropout (one past the range asked is no reading: a miss) */
    far = res->hit == 1 && pl->probe.reach > pl->probe.range && res->dist <= pl->dev.iss_range + tol;
    if (pl->cfg.confirm_misses > 0 && !far &&
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
        VP_TRY(vp_pl_probe_proof(pl, res, &pf));
        k->proof = pf;
    }
    if (VP_PL_CONTACTS && k->proof == PROOF_NONE && pl->contact.n > 0) {
        /* a miss near a contact proves nothing: the edge is unseen from here */
        side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
        return VP_OK;
    }
    if (vp_pl_probe_limited(pl)) {
        /* range-limited: the free part ends here; walk there and probe on */
        double e[3];
        if (pl->cfg.clearance > 0.0) {
            /* a device with a body stays outside Omega: the rest of the line is unseen */
            side_set(pl, t, f, side_get(pl, t, f) | SIDE_BLOCKED);
            pl->st.occluded++;
            return VP_OK;
        }
        VP_TRY(vp_pl_walk_on(pl, pl->probe.origin_rec, k->proof, e));
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
    if ((fr = vp_pl_frec_lookup(pl, fv)) != NONE) {
        vp_pl_frec_delete(pl, fr);
        pl->st.noise_drops++;
    }
    side_set(pl, t, f, SIDE_UNKNOWN);
    side_free(pl, t, f, k->proof);
    side_free(pl, u, (int)j, k->proof);
    VP_TRY(vp_pl_tet_reached(pl, u, k->proof));
#if VP_PL_CONTACTS
    if (far) {
        /* the beam met S past the edge: a sample where none lies within eps (the line laser's
         * spacing, vp_pl_ray_sample: every sample stays eps from the others, as a bad ball's
         * centre does, so the packing bound and the end of the refinement are paper 000's) */
        double h[3];
        for (q = 0; q < 3; q++) h[q] = pl->probe.origin[q] + res->dist * pl->probe.dir[q];
        pl->st.far_reads++;
        st = vp_pl_sample_insert(pl, h, t, pl->cfg.eps, NULL);
        if (st < 0) return st;
        pl->st.far_samples += st == 1;
    }
#endif
    return VP_OK;
}

/* Tet u's Voronoi vertex was seen free by the current probe (`proof` its free part, from the
 * probe's origin): u is reached (outside), linked to the origin's record. */
VP_PL_API int vp_pl_tet_reached(vp_planner_t *pl, uint32_t u, uint32_t proof)
{
    int st;
    if (!tet_active(pl, u)) {
        double c[3];
        uint32_t r;
        if (vp_dt_is_ghost(&pl->dt, u) || vp_pl_tet_point(pl, u, c) != VP_OK || !vp_pl_omega_inside(&pl->cfg, c))
            return activate(pl, u, VREC_OUT);
        st = vp_pl_rec_link(pl, c, pl->probe.origin_rec, 0, proof, &r);
        if (st != VP_OK || r == NONE) return st;
        return activate(pl, u, r);
    }
    if (tet_rec(pl, u) != VREC_OUT && pl->probe.origin_rec != NONE)
        return vp_pl_edge_add(pl, pl->probe.origin_rec, tet_rec(pl, u), proof);
    return VP_OK;
}
