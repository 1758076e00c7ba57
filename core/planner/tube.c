/* tube.c — travel inside Omega with a body: tubes proven free (beyond the paper).
 *
 * A probe proves its ray free, not a volume, and the device with a body (a ball of radius
 * C = cfg.clearance about its origin) needs a volume. The assumption that turns rays into
 * volumes (cfg.min_feature rho, cfg.feature_margin eta): every point of the object lies within
 * eta of a ball of radius rho inside the object (the object is rho-open up to eta; eta covers
 * sharp convex edges and corners, which no ball reaches).
 *
 * Let F be the proven-free space: the free parts of the probes, and R^3 \ Omega (A2). A ball
 * B(c, rho) inside the object meets no free ray and lies in Omega, so dist(c, F) >= rho. Hence
 * the capsule of radius C about a segment holds no point of the object when every point of the
 * capsule of radius C + eta + rho about it lies nearer than rho to F: an object point y in the
 * first has a ball B(c, rho) inside the object within eta of it, and c lies in the second.
 *
 * The check is kept on a grid of cubic cells over Omega's bounding box (cell side s <= rho / 4,
 * h = half its diagonal) with a margin m = rho / 32: a cell is marked when its centre lies
 * within rho - m - h of a free ray, so every point of a marked cell lies within rho - m of F; a
 * cell whose centre lies within rho - m - h of Omega's outside needs no mark. A segment is a
 * proven tube when every cell that meets its capsule of radius C + eta + rho + m is marked or
 * near the outside. The margin lets a check on cells of its own see the proof: a cell of half
 * diagonal at most m that meets the capsule of C + eta + rho has its centre within rho - m of F
 * (host/vp_logverify). Marks only grow (rays are only added); a contact or a re-scan makes them
 * stale and turns tubes off for good. */
#include "vp_planner_priv.h"

#if VP_PL_TUBES

#define HALF_DIAG 0.86602540378443871 /* sqrt(3) / 2, rounded up */
#define CELLS_PER_RHO 4.0             /* finest cells: rho / 4 */
#define CELLS_PER_RHO_MIN 2.0         /* coarsest cells that still leave a useful mark (rho / 2) */
#define CELL_GROW 1.25
#define TUBE_MARGIN (1.0 / 32.0)      /* m in rho: what a proven tube keeps in hand (see the top) */

/* The grid for cfg within `budget` bytes: sets T's geometry, returns the bytes of its bits, or
 * 0 when even the coarsest grid does not fit. */
VP_PL_API size_t vp_pl_tube_plan(const vp_planner_config_t *c, double ptol, size_t budget, vp_pl_tube_t *T)
{
    double lo[3], hi[3], rho = c->min_feature, s = rho / CELLS_PER_RHO;
    int k;
    memset(T, 0, sizeof *T);
    if (c->omega_kind == VP_OMEGA_BALL) {
        for (k = 0; k < 3; k++) {
            lo[k] = c->omega_center[k] - c->omega_radius;
            hi[k] = c->omega_center[k] + c->omega_radius;
        }
    } else {
        memcpy(lo, c->omega_lo, sizeof lo);
        memcpy(hi, c->omega_hi, sizeof hi);
    }
    for (; s <= rho / CELLS_PER_RHO_MIN; s *= CELL_GROW) {
        double cells = 1.0;
        for (k = 0; k < 3; k++) cells *= floor((hi[k] - lo[k]) / s) + 1.0;
        if (cells / 8.0 + 1.0 <= (double)budget && cells < 4e9) {
            for (k = 0; k < 3; k++) T->n[k] = (uint32_t)(floor((hi[k] - lo[k]) / s) + 1.0);
            memcpy(T->lo, lo, sizeof lo);
            T->cell = s;
            T->half = HALF_DIAG * s;
            T->mark = rho - TUBE_MARGIN * rho - T->half - ptol;
            T->reach = c->clearance + c->feature_margin + rho + TUBE_MARGIN * rho;
            return (size_t)(cells / 8.0) + 1u;
        }
    }
    return 0;
}

/* the squared distance from p to segment a .. a + d (len2 = |d|^2; 0: the point a) */
VP_PL_API double vp_pl_seg_dist2(const double *a, const double *d, double len2, const double *p)
{
    double w[3], t = 0.0, e[3];
    int k;
    vp_sub3(w, p, a);
    if (len2 > 0.0) {
        t = vp_dot3(w, d) / len2;
        if (t < 0.0) t = 0.0;
        if (t > 1.0) t = 1.0;
    }
    for (k = 0; k < 3; k++) e[k] = w[k] - t * d[k];
    return vp_dot3(e, e);
}

/* the cell index of coordinate x on axis k, clamped to the grid (-1 / n: beyond it) */
static long cell_of(const vp_pl_tube_t *T, int k, double x)
{
    double i = floor((x - T->lo[k]) / T->cell);
    if (i < -1.0) return -1;
    if (i > (double)T->n[k]) return (long)T->n[k];
    return (long)i;
}

/* a cell centre within the mark of Omega's outside (it needs no ray) */
static int near_outside(const vp_planner_t *pl, const double *c)
{
    const vp_planner_config_t *g = &pl->cfg;
    double m = pl->tube.mark;
    int k;
    if (g->omega_kind == VP_OMEGA_BALL) {
        double d[3], r = g->omega_radius - m;
        vp_sub3(d, c, g->omega_center);
        return r <= 0.0 || vp_dot3(d, d) >= r * r;
    }
    for (k = 0; k < 3; k++)
        if (c[k] <= g->omega_lo[k] + m || c[k] >= g->omega_hi[k] - m) return 1;
    return 0;
}

/* the bit of the cell with indices idx */
static size_t cell_bit(const vp_pl_tube_t *T, const size_t *idx)
{
    return (idx[2] * T->n[1] + idx[1]) * T->n[0] + idx[0];
}

/* 1 when the cell (bit, centre c) is neither marked nor near Omega's outside: no tube through it
 * is proven yet */
static int cell_open(const vp_planner_t *pl, size_t bit, const double *c)
{
    return !(pl->tube.bits[bit >> 3] & (1u << (bit & 7u))) && !near_outside(pl, c);
}

/* The cells whose centre lies within r of segment [a, b]: with set (the grid's bits) marks
 * them; otherwise returns 0
 * at the first that is neither marked nor near the outside (1: all are). Slab by slab across
 * the segment's main axis, each slab's cells within the box of the segment's piece there. */
static int tube_cells(const vp_planner_t *pl, const double *a, const double *b, double r, uint8_t *set)
{
    const vp_pl_tube_t *T = &pl->tube;
    double d[3], len2, r2 = r * r, ad = 0.0;
    long i0, i1, i;
    int k = 0, q, u, v;
    vp_sub3(d, b, a);
    len2 = vp_dot3(d, d);
    for (q = 0; q < 3; q++)
        if (fabs(d[q]) > ad) { ad = fabs(d[q]); k = q; }
    u = (k + 1) % 3;
    v = (k + 2) % 3;
    i0 = cell_of(T, k, (a[k] < b[k] ? a[k] : b[k]) - r);
    i1 = cell_of(T, k, (a[k] < b[k] ? b[k] : a[k]) + r);
    if (i0 < 0) i0 = 0;
    if (i1 >= (long)T->n[k]) i1 = (long)T->n[k] - 1;
    for (i = i0; i <= i1; i++) {
        double x = T->lo[k] + ((double)i + 0.5) * T->cell, t0 = 0.0, t1 = 1.0, plo[3], phi[3];
        long j, j0, j1, l0, l1, l;
        if (ad > 0.0) {
            t0 = (x - r - a[k]) / d[k];
            t1 = (x + r - a[k]) / d[k];
            if (t0 > t1) { double s = t0; t0 = t1; t1 = s; }
            if (t0 < 0.0) t0 = 0.0;
            if (t1 > 1.0) t1 = 1.0;
            if (t0 > t1) continue;
        }
        for (q = 0; q < 3; q++) {
            double e0 = a[q] + t0 * d[q], e1 = a[q] + t1 * d[q];
            plo[q] = (e0 < e1 ? e0 : e1) - r;
            phi[q] = (e0 < e1 ? e1 : e0) + r;
        }
        j0 = cell_of(T, u, plo[u]); j1 = cell_of(T, u, phi[u]);
        l0 = cell_of(T, v, plo[v]); l1 = cell_of(T, v, phi[v]);
        if (j0 < 0) j0 = 0;
        if (l0 < 0) l0 = 0;
        if (j1 >= (long)T->n[u]) j1 = (long)T->n[u] - 1;
        if (l1 >= (long)T->n[v]) l1 = (long)T->n[v] - 1;
        for (j = j0; j <= j1; j++)
            for (l = l0; l <= l1; l++) {
                double c[3];
                size_t idx[3], bit;
                c[k] = x;
                c[u] = T->lo[u] + ((double)j + 0.5) * T->cell;
                c[v] = T->lo[v] + ((double)l + 0.5) * T->cell;
                if (vp_pl_seg_dist2(a, d, len2, c) > r2) continue;
                idx[k] = (size_t)i; idx[u] = (size_t)j; idx[v] = (size_t)l;
                bit = cell_bit(T, idx);
                if (set) set[bit >> 3] |= (uint8_t)(1u << (bit & 7u));
                else if (cell_open(pl, bit, c)) return 0;
            }
    }
    return 1;
}

/* A free part of a probe, o .. o + len d: the cells within the mark of it. */
VP_PL_API void vp_pl_tube_mark(vp_planner_t *pl, const double *o, const double *d, double len)
{
    double e[3];
    int k;
    if (!pl->tube.on || !(len > 0.0) || !(pl->tube.mark > 0.0)) return;
    for (k = 0; k < 3; k++) e[k] = o[k] + len * d[k];
    (void)tube_cells(pl, o, e, pl->tube.mark, pl->tube.bits);
}

/* 1 if the capsule of radius cfg.clearance about [a, b] is proven free (see the top). */
VP_PL_API int vp_pl_tube_free(const vp_planner_t *pl, const double *a, const double *b)
{
    if (!pl->tube.on) return 0;
    /* every cell meeting the capsule: its centre within reach + half a diagonal (and the slack) */
    return tube_cells(pl, a, b, pl->tube.reach + pl->tube.half + pl->ptol, NULL);
}

/* How much of the way [a, b] is unexplored: the cells on its axis (points a cell's side apart)
 * neither marked nor near Omega's outside. Cells inside the object are never marked, so a way
 * through explored free space counts few; the vantage ranks its ways out by it. */
VP_PL_API uint32_t vp_pl_tube_unexplored(const vp_planner_t *pl, const double *a, const double *b)
{
    const vp_pl_tube_t *T = &pl->tube;
    double d[3], len, c[3];
    uint32_t n = 0, i, steps;
    size_t last = (size_t)-1;
    int k;
    vp_sub3(d, b, a);
    len = sqrt(vp_dot3(d, d));
    steps = (uint32_t)ceil(len / T->cell);
    for (i = 0; i <= steps; i++) {
        double t = steps ? (double)i / (double)steps : 0.0;
        size_t idx[3], bit;
        int in = 1;
        for (k = 0; k < 3; k++) {
            long j;
            j = cell_of(T, k, a[k] + t * d[k]);
            if (j < 0 || j >= (long)T->n[k]) { in = 0; break; }
            idx[k] = (size_t)j;
            c[k] = T->lo[k] + ((double)j + 0.5) * T->cell;
        }
        if (!in) continue;
        bit = cell_bit(T, idx);
        if (bit == last) continue;
        last = bit;
        n += (uint32_t)cell_open(pl, bit, c);
    }
    return n;
}

/* ---------- surveys: the planner proves a tube before it enters it ----------
 * Parallel rays along -u from outside Omega, on a square grid across the tube d apart: every
 * point of the capsule's cross-section lies within d / sqrt 2 of a ray, and d / sqrt 2 is below
 * the mark, so the cells of a capsule whose rays all miss are all marked. The device goes round
 * Omega outside it from one ray's origin to the next, the grid's centre first; a ray that meets
 * S within the body's radius of the way ends the survey (vp_pl_survey_feed). */
#define SURVEY_SPACING 1.35 /* d in marks: below sqrt 2 */

/* A survey of the tube from x out of Omega along unit u, for the current probe moved s along its
 * line to x once the tube is proven (vp_pl_vantage_go). */
VP_PL_API void vp_pl_survey_start(vp_planner_t *pl, const double *x, const double *u, double s)
{
    vp_pl_tube_t *T = &pl->tube;
    double t[3] = { 0, 0, 1 }, r = T->reach + T->half;
    if (fabs(u[2]) > 0.8) { t[0] = 1; t[2] = 0; }
    memcpy(T->sx, x, sizeof T->sx);
    memcpy(T->su, u, sizeof T->su);
    vp_normal_frame3(u, t, T->sw1, T->sw2);
    T->sd = SURVEY_SPACING * T->mark;
    T->survey_m = 2u * (uint32_t)ceil(r / T->sd) + 1u;
    T->survey_n = T->survey_m * T->survey_m;
    T->survey_i = 0;
    T->ss = s;
    T->pend = pl->probe;
    pl->probe.chain_proof = PROOF_NONE;
    pl->st.surveys++;
}

/* After the survey's last ray: the probe waiting for it goes ahead if the tube is now proven, or
 * its side is left unseen. */
static int survey_finish(vp_planner_t *pl)
{
    vp_pl_tube_t *T = &pl->tube;
    double e[3], tx;
    int q, st;
    pl->probe = T->pend;
    tx = vp_pl_omega_exit(&pl->cfg, T->sx, T->su);
    for (q = 0; q < 3; q++) e[q] = T->sx[q] + tx * T->su[q];
    if (vp_pl_tube_free(pl, T->sx, e)) {
        st = vp_pl_vantage_go(pl, T->sx, T->ss, e);
        if (st != 0) return st < 0 ? st : VP_OK;
    }
    pl->st.surveys_failed++;
    return vp_pl_vantage_unseen(pl);
}

/* Where survey ray i crosses the plane across the tube at its start: the grid's centre first,
 * then square rings about it outwards (ring k holds the 8k points at k steps), so that a tube
 * the object blocks near its axis shows it after a few rays. */
static void survey_point(const vp_pl_tube_t *T, uint32_t i, double *p)
{
    uint32_t k = 0, j, side, t;
    long a = 0, b = 0;
    int q;
    if (i > 0) {
        while ((2u * k + 1u) * (2u * k + 1u) <= i) k++;
        j = i - (2u * k - 1u) * (2u * k - 1u);
        side = j / (2u * k);
        t = j % (2u * k);
        switch (side) {
        case 0: a = -(long)k + (long)t; b = -(long)k; break;
        case 1: a = (long)k; b = -(long)k + (long)t; break;
        case 2: a = (long)k - (long)t; b = (long)k; break;
        default: a = -(long)k; b = (long)k - (long)t; break;
        }
    }
    for (q = 0; q < 3; q++) p[q] = T->sx[q] + T->sd * ((double)a * T->sw1[q] + (double)b * T->sw2[q]);
}

/* The route to the next survey ray's origin (outside Omega); its probe follows the route. */
VP_PL_API int vp_pl_survey_next(vp_planner_t *pl)
{
    vp_pl_tube_t *T = &pl->tube;
    double p[3], o[3], t, back = T->reach + T->half;
    int q;
    survey_point(T, T->survey_i, p);
    /* out along u until outside Omega, a rounding's breadth beyond dOmega */
    t = vp_pl_omega_exit(&pl->cfg, p, T->su) + pl->ptol;
    for (q = 0; q < 3; q++) o[q] = p[q] + t * T->su[q];
    if (vp_pl_omega_inside(&pl->cfg, o)) /* rounding: skip it */
        return ++T->survey_i < T->survey_n ? VP_OK : survey_finish(pl);
    T->ray_range = t + back;
    T->goal_in = 0;
    VP_TRY(vp_pl_plan_route(pl, NONE, o));
    T->survey_ready = 1;
    return VP_OK;
}

/* A survey ray's result: its free part marks the grid. */
VP_PL_API int vp_pl_survey_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    vp_pl_tube_t *T = &pl->tube;
    uint32_t pf;
    T->survey_wait = 0;
    VP_TRY(vp_pl_probe_proof(pl, res, &pf));
    pl->st.survey_probes++;
    if (res->hit == 1) {
        /* a point of S within the body's radius C of the way: the ball B(c, rho) inside the
         * object that the assumption puts within eta of it has c within C + eta + rho of the
         * way, and c's cell can never be marked (c is rho from every free point), so the tube
         * cannot be proven; the survey ends here */
        double h[3], d[3], e[3], tx, r = pl->cfg.clearance;
        int q;
        for (q = 0; q < 3; q++) h[q] = pl->dev.iss_o[q] + res->dist * pl->dev.iss_d[q];
        tx = vp_pl_omega_exit(&pl->cfg, T->sx, T->su);
        for (q = 0; q < 3; q++) e[q] = T->sx[q] + tx * T->su[q];
        vp_sub3(d, e, T->sx);
        if (vp_pl_seg_dist2(T->sx, d, vp_dot3(d, d), h) < r * r) T->survey_i = T->survey_n - 1u;
    }
    return ++T->survey_i < T->survey_n ? VP_OK : survey_finish(pl);
}

/* The marks no longer prove anything (a contact withdrew a proof, a re-scan): tubes off. */
VP_PL_API void vp_pl_tube_off(vp_planner_t *pl)
{
    pl->tube.on = 0;
}

#endif
