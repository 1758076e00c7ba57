/* facets.c — Del_v|S(E): the restricted facets found by probing, each with its surface
 * Delaunay ball (centre = the hit, radius = distance to the facet's vertices); a hash on the
 * sorted vertex triple, and the bad-ball heap (balls of radius > eps, max on radius). */
#include "vp_planner_priv.h"

/* ---------- restricted facets: hash on the sorted vertex triple ---------- */

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

VP_PL_API uint32_t vp_pl_frec_lookup(const vp_planner_t *pl, const uint32_t *fv)
{
    uint32_t v[3];
    int found;
    uint32_t h;
    v[0] = fv[0]; v[1] = fv[1]; v[2] = fv[2];
    sort3(v);
    h = fhash_find(pl, v, &found);
    return found ? pl->pool.fhash[h] : NONE;
}

/* ---------- the samples' poles (Amenta and Bern): normals, distances to the medial axis ---------- */

/* The centroid of v's Delaunay neighbours (inside their hull); 0 if v has none. */
static int star_centroid(const vp_planner_t *pl, uint32_t v, const uint32_t *tets, int n, double *m)
{
    uint32_t cnt = 0, k;
    int i;
    m[0] = m[1] = m[2] = 0.0;
    for (i = 0; i < n; i++) {
        const uint32_t *w = vp_dt_tet(&pl->dt, tets[i]);
        for (k = 0; k < 4; k++)
            if (w[k] != v && w[k] != VP_DT_GHOST) {
                const double *q = vp_dt_point(&pl->dt, w[k]);
                m[0] += q[0]; m[1] += q[1]; m[2] += q[2];
                cnt++;
            }
    }
    if (cnt == 0) return 0;
    for (k = 0; k < 3; k++) m[k] /= (double)cnt;
    return 1;
}

/* The tets around sample v (in the scratch) and the direction u to its first pole: the
 * farthest vertex of its Voronoi cell, or on the hull (the cell unbounded, *unbounded = 1)
 * away from the neighbours' centroid. Returns the number of tets, 0 if no direction. */
static int first_pole(vp_planner_t *pl, uint32_t v, double *u, int *unbounded)
{
    const double *p = vp_dt_point(&pl->dt, v);
    uint32_t *tets = pl->pool.astar;
    int n = vp_dt_incident_tets(&pl->dt, v, tets, (int)pl->pool.cap_astar), i;
    double far = -1.0, c[3], d[3], dist;
    *unbounded = 0;
    u[0] = u[1] = u[2] = 0.0;
    if (n <= 0) return 0;
    for (i = 0; i < n; i++) {
        if (vp_dt_is_ghost(&pl->dt, tets[i])) { *unbounded = 1; continue; }
        if (vp_dt_circumcenter(&pl->dt, tets[i], c) != VP_OK) continue;
        vp_sub3(d, c, p);
        dist = vp_norm3(d);
        if (dist > far) { far = dist; memcpy(u, d, sizeof d); }
    }
    if (*unbounded) {
        double m[3];
        if (!star_centroid(pl, v, tets, n, m)) return 0;
        vp_sub3(u, p, m);
        return n;
    }
    return far < 0.0 ? 0 : n;
}

static double pole_distance(vp_planner_t *pl, uint32_t v)
{
    const double *p = vp_dt_point(&pl->dt, v);
    const uint32_t *tets = pl->pool.astar;
    double u[3], c[3], d[3], dist, far = -1.0, other = -1.0;
    int unbounded, n = first_pole(pl, v, u, &unbounded), i;
    if (n == 0) return VP_PL_HUGE;
    for (i = 0; i < n; i++) {
        if (vp_dt_is_ghost(&pl->dt, tets[i]) || vp_dt_circumcenter(&pl->dt, tets[i], c) != VP_OK) continue;
        vp_sub3(d, c, p);
        dist = vp_norm3(d);
        if (dist > far) far = dist;
        if (vp_dot3(d, u) < 0.0 && dist > other) other = dist;
    }
    if (unbounded) return other >= 0.0 ? other : VP_PL_HUGE;
    if (far < 0.0) return VP_PL_HUGE;
    return other >= 0.0 && other < far ? other : far;
}

/* The pole vector at sample v (not unit; zero if none), the normal estimate of Amenta and Bern;
 * on the hull (the first pole at infinity) the second pole, the farthest Voronoi vertex on
 * the inner side, whose side is told by the sum of the outward normals of the hull facets at v
 * (the neighbours' centroid says which side of those is out). The tets around v stay in the
 * scratch; returns how many. */
static int pole_vector(vp_planner_t *pl, uint32_t v, double *nrm)
{
    const uint32_t *tets = pl->pool.astar;
    const double *p = vp_dt_point(&pl->dt, v);
    double m[3], e1[3], e2[3], h[3], c[3], s, dist, other = -1.0, best[3] = { 0, 0, 0 };
    int unbounded, n = first_pole(pl, v, nrm, &unbounded), i;
    if (n == 0 || !unbounded) return n;
    vp_sub3(m, p, nrm); /* the centroid */
    nrm[0] = nrm[1] = nrm[2] = 0.0;
    for (i = 0; i < n; i++) {
        const uint32_t *w = vp_dt_tet(&pl->dt, tets[i]);
        if (!vp_dt_is_ghost(&pl->dt, tets[i])) continue;
        vp_sub3(e1, vp_dt_point(&pl->dt, w[1]), vp_dt_point(&pl->dt, w[0]));
        vp_sub3(e2, vp_dt_point(&pl->dt, w[2]), vp_dt_point(&pl->dt, w[0]));
        vp_cross3(h, e1, e2);
        vp_sub3(e1, vp_dt_point(&pl->dt, w[0]), m);
        s = vp_dot3(h, e1);
        if (s < 0.0) vp_sub3(nrm, nrm, h);
        else if (s > 0.0) vp_add3(nrm, nrm, h);
    }
    if (!(vp_dot3(nrm, nrm) > 0.0)) vp_sub3(nrm, p, m);
    for (i = 0; i < n; i++) {
        if (vp_dt_is_ghost(&pl->dt, tets[i]) || vp_dt_circumcenter(&pl->dt, tets[i], c) != VP_OK) continue;
        vp_sub3(e1, c, p);
        if (vp_dot3(e1, nrm) < 0.0 && (dist = vp_norm3(e1)) > other) { other = dist; memcpy(best, e1, sizeof best); }
    }
    if (other > 0.0) { nrm[0] = -best[0]; nrm[1] = -best[1]; nrm[2] = -best[2]; }
    return n;
}

/* The unit normal estimate at sample v (zero if none): its pole vector. It depends on v's star
 * only, so it is kept (pool.nrm) until an insertion changes that star (vp_pl_after_insert
 * clears the record's AUX_NRM). */
static void sample_normal(vp_planner_t *pl, uint32_t v, double *nrm)
{
    vp_dt_vertex_t *rec = &pl->dt.vtop[-(ptrdiff_t)v];
    if (v < pl->pool.cap_nrm && (rec->aux & AUX_NRM)) {
        memcpy(nrm, pl->pool.nrm + 3 * (size_t)v, 3 * sizeof(double));
        return;
    }
    if (pole_vector(pl, v, nrm) == 0 || !vp_normalize3(nrm)) nrm[0] = nrm[1] = nrm[2] = 0.0;
    if (v < pl->pool.cap_nrm) {
        memcpy(pl->pool.nrm + 3 * (size_t)v, nrm, 3 * sizeof(double));
        rec->aux |= AUX_NRM;
    }
}

/* ---------- the sizing field (paper 002, section 6) ----------
 * g(x) = size_rel * min_p (dM(p) + |x - p|): size_rel times the 1-Lipschitz extension of dM from
 * the samples p; dM(p), the distance to the medial axis, is estimated by the distance to p's
 * poles: the farthest vertex of its Voronoi cell (at infinity on the hull), and the farthest
 * one on the other side. The min is taken over the facet's own vertices (the samples nearest
 * its ball centre), and g is held to [min_size, eps]: the floor ends refinement on sharp edges,
 * where dM goes to 0. A ball is bad when r > g(c), i.e. r > size_rel dM / (1 - size_rel). */

/* The largest ball radius allowed at ball centre c of facet v: eps, or the sizing field. */
VP_PL_API double vp_pl_size_bound(vp_planner_t *pl, const uint32_t *v, const double *c)
{
    double g = VP_PL_HUGE;
    int k;
    if (!(pl->cfg.size_rel > 0.0)) return pl->cfg.eps;
    for (k = 0; k < 3; k++) {
        double x = pl->cfg.size_rel * (pole_distance(pl, v[k]) + vp_dist3(c, vp_dt_point(&pl->dt, v[k])));
        if (x < g) g = x;
    }
    if (g < pl->cfg.min_size) g = pl->cfg.min_size;
    return g < pl->cfg.eps ? g : pl->cfg.eps;
}

/* ---------- the distance bound: how far a facet strays from the surface ---------- */

/* The unit normal of facet record f, oriented out (zero if degenerate) */
static void frec_normal(const vp_planner_t *pl, const vp_frec_t *f, double *nrm)
{
    double e1[3], e2[3];
    vp_sub3(e1, vp_dt_point(&pl->dt, f->v[1]), vp_dt_point(&pl->dt, f->v[0]));
    vp_sub3(e2, vp_dt_point(&pl->dt, f->v[2]), vp_dt_point(&pl->dt, f->v[0]));
    vp_cross3(nrm, e1, e2);
    if (f->flags & FREC_FLIP) { nrm[0] = -nrm[0]; nrm[1] = -nrm[1]; nrm[2] = -nrm[2]; }
    if (!vp_normalize3(nrm)) nrm[0] = nrm[1] = nrm[2] = 0.0;
}

/* How sharply the restricted surface bends at facet f: the largest angle theta between its
 * normal and a neighbour's across one of its edges (the restricted facets around the edge, in
 * the Delaunay tets around it). A cap of radius r on a tip or a sharp edge whose faces' normals
 * differ by theta cuts off about r tan(theta / 2) (a cone of half-angle beta has
 * theta = pi - 2 beta and its tip r / tan beta above the cap); on a smooth part of curvature
 * radius rho it is about r^2 / rho, twice the facet's sagitta. Returns tan(theta / 2), at most
 * BEND_MAX. */
#define BEND_MAX 12.0
#ifndef BEND_SHARE
#define BEND_SHARE 1.5
#endif
/* The largest tan(theta / 2) between unit normal fn and the restricted facets (a, b, o) */
static double bend_at(vp_planner_t *pl, const double *fn, uint32_t a, uint32_t b, uint32_t o, double worst)
{
    uint32_t fv[3], g;
    double gn[3], c, t;
    if (o == VP_DT_GHOST) return worst;
    fv[0] = a; fv[1] = b; fv[2] = o;
    g = vp_pl_frec_lookup(pl, fv);
    if (g == NONE) return worst;
    frec_normal(pl, &pl->pool.frec[g], gn);
    if (vp_dot3(gn, gn) == 0.0) return worst;
    /* tan(theta / 2) = sqrt((1 - cos theta) / (1 + cos theta)) for unit normals */
    c = vp_dot3(fn, gn);
    t = 1.0 + c > 0.0 ? sqrt((1.0 - c) / (1.0 + c)) : BEND_MAX;
    return t > worst ? t : worst;
}

static double facet_bend(vp_planner_t *pl, const vp_frec_t *f)
{
    double fn[3], worst = 0.0;
    int e, held = 0, broken = 0, k;
    uint32_t t = f->hint;
    frec_normal(pl, f, fn);
    if (vp_dot3(fn, fn) == 0.0) return 0.0;
    if (vp_dt_alive(&pl->dt, t)) {
        const uint32_t *w = vp_dt_tet(&pl->dt, t);
        for (k = 0; k < 4; k++) held += w[k] == f->v[0] || w[k] == f->v[1] || w[k] == f->v[2];
    }
    if (held != 3) {
        /* the record's tet is gone: a tet that has the facet now (one walk round a sample, not
         * one per edge; the rings round its edges hold the same facets) */
        int fi;
        t = vp_pl_find_facet(pl, f->v, &fi, 0);
        held = t != NONE ? 3 : 0;
    }
    for (e = 0; e < 3; e++) {
        uint32_t a = f->v[e], b = f->v[(e + 1) % 3], x = f->v[(e + 2) % 3];
        if (held == 3) {
            /* around the edge from the facet's tet: each facet (a, b, o) of the ring once */
            ring_t r;
            if (ring_start(pl, &r, t, a, b))
                do {
                    if (r.other != x) worst = bend_at(pl, fn, a, b, r.other, worst);
                } while (ring_step(pl, &r, &broken));
        } else {
            /* no tet has the facet: the tets around a that hold b */
            uint32_t *tets = pl->pool.astar;
            int n = vp_dt_incident_tets(&pl->dt, a, tets, (int)pl->pool.cap_astar), i, j;
            for (i = 0; i < n; i++) {
                const uint32_t *w = vp_dt_tet(&pl->dt, tets[i]);
                int hasb = 0;
                for (j = 0; j < 4; j++) hasb |= w[j] == b;
                if (!hasb) continue;
                for (j = 0; j < 4; j++)
                    if (w[j] != a && w[j] != b && w[j] != x) worst = bend_at(pl, fn, a, b, w[j], worst);
            }
        }
    }
    return worst < BEND_MAX ? worst : BEND_MAX;
}

/* The distance from ball centre c to the circumcentre of facet v: c lies on the facet's dual
 * Voronoi edge, the line through the circumcentre normal to the facet, so it is
 * sqrt(r^2 - R^2) for the ball radius r and the facet's circumradius R. */
static double facet_distance(const vp_planner_t *pl, const vp_frec_t *f)
{
    const double *a = vp_dt_point(&pl->dt, f->v[0]), *b = vp_dt_point(&pl->dt, f->v[1]),
                 *c = vp_dt_point(&pl->dt, f->v[2]);
    double ab[3], ac[3], bc[3], n[3], n2, rr2, d2;
    vp_sub3(ab, b, a); vp_sub3(ac, c, a); vp_sub3(bc, c, b);
    vp_cross3(n, ab, ac);
    n2 = vp_dot3(n, n);
    if (!(n2 > 0.0)) return f->r;
    rr2 = vp_dot3(ab, ab) * vp_dot3(ac, ac) * vp_dot3(bc, bc) / (4.0 * n2);
    d2 = f->r * f->r - rr2;
    return d2 > 0.0 ? sqrt(d2) : 0.0;
}

/* How deep the facet lies under (or over) the surface, from the tangent planes T_i at its
 * vertices v_i (normals n_i: the poles, sample_normal): near the facet the surface is about the
 * envelope of the three planes, so a point x of the facet lies about min_i |n_i . (x - v_i)|
 * from it, on the side where all three agree. The largest of that over the facet is at a point
 * where two or three of the planes are equally far (on an edge, or inside). On a smooth part it
 * is twice the sagitta; at a sharp edge or corner cut off by the facet it is 1-2 times the cut,
 * where the facet's own ball centre may lie close to the facet. */
#ifndef TILT_SHARE
#define TILT_SHARE 2.0
#endif

static double envelope_depth(const double (*v)[3], const double (*n)[3], double sgn)
{
    double m[3][3], best = 0.0, t, a, b, det, lam[3];
    int i, j, k;
    /* m[i][j]: how far v_j lies beyond plane i, on the side sgn (depth at vertex j of plane i) */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double d[3];
            vp_sub3(d, v[j], v[i]);
            m[i][j] = -sgn * vp_dot3(n[i], d);
        }
    /* on edge ij, at x = (1 - t) v_i + t v_j: plane i is t m[i][j] away, plane j (1 - t) m[j][i] */
    for (i = 0; i < 3; i++) {
        j = (i + 1) % 3;
        k = (i + 2) % 3;
        a = m[i][j];
        b = m[j][i];
        if (!(a > 0.0 && b > 0.0)) continue;
        t = b / (a + b);
        a *= t;
        /* the third plane at that point */
        b = (1.0 - t) * m[k][i] + t * m[k][j];
        if (b < a) a = b;
        if (a > best) best = a;
    }
    /* inside: the point where the three planes are equally far, x = sum lam_j v_j with
     * sum_j lam_j m[i][j] = h for every i and sum lam = 1 (eliminate h: two equations) */
    {
        double r0[3], r1[3];
        for (j = 0; j < 3; j++) {
            r0[j] = m[0][j] - m[1][j];
            r1[j] = m[1][j] - m[2][j];
        }
        /* lam_2 = 1 - lam_0 - lam_1: r.lam = 0 becomes a 2x2 system */
        a = r0[0] - r0[2]; b = r0[1] - r0[2];
        t = r1[0] - r1[2]; det = a * (r1[1] - r1[2]) - b * t;
        if (det != 0.0) {
            lam[0] = (-r0[2] * (r1[1] - r1[2]) + b * r1[2]) / det;
            lam[1] = (-a * r1[2] + t * r0[2]) / det;
            lam[2] = 1.0 - lam[0] - lam[1];
            if (lam[0] >= 0.0 && lam[1] >= 0.0 && lam[2] >= 0.0) {
                double h = lam[0] * m[0][0] + lam[1] * m[0][1] + lam[2] * m[0][2];
                if (h > best) best = h;
            }
        }
    }
    return best;
}

static double facet_tilt(vp_planner_t *pl, const vp_frec_t *f)
{
    double n[3][3], v[3][3], e1[3], e2[3], fn[3], up, down;
    int i;
    for (i = 0; i < 3; i++) memcpy(v[i], vp_dt_point(&pl->dt, f->v[i]), sizeof v[i]);
    vp_sub3(e1, v[1], v[0]);
    vp_sub3(e2, v[2], v[0]);
    vp_cross3(fn, e1, e2);
    for (i = 0; i < 3; i++) {
        sample_normal(pl, f->v[i], n[i]); /* unit, or zero */
        if (vp_dot3(n[i], n[i]) == 0.0) return 0.0;
        if (vp_dot3(n[i], fn) < 0.0) { n[i][0] = -n[i][0]; n[i][1] = -n[i][1]; n[i][2] = -n[i][2]; } /* on the facet's side */
    }
    /* the surface above the facet (a convex part) or below it (a concave one) */
    up = envelope_depth((const double (*)[3])v, (const double (*)[3])n, -1.0);
    down = envelope_depth((const double (*)[3])v, (const double (*)[3])n, 1.0);
    if (down > up) up = down;
    for (i = 0; i < 3; i++) {
        /* each edge alone, whichever side each plane puts the other end (noisy normals) */
        int j = (i + 1) % 3;
        double a, b;
        vp_sub3(e1, v[j], v[i]);
        a = fabs(vp_dot3(e1, n[i]));
        b = fabs(vp_dot3(e1, n[j]));
        if (a + b > 0.0 && a * b / (a + b) > up) up = a * b / (a + b);
    }
    return up;
}

/* 1 if facet f lies at a corner: its vertices' normals point three ways (their determinant is
 * large; along a sharp edge two of them agree, on a smooth part all three do). A cap on a corner
 * or tip rounds it off with several facets, each bending only part of the way, so the bend
 * there is held to a smaller share of the bound. */
#ifndef CORNER_DET
#define CORNER_DET 0.25
#endif
#ifndef CORNER_BEND_SHARE
#define CORNER_BEND_SHARE 0.75
#endif
static int facet_at_corner(vp_planner_t *pl, const vp_frec_t *f)
{
    double n[3][3], x[3];
    int i;
    for (i = 0; i < 3; i++) sample_normal(pl, f->v[i], n[i]);
    vp_cross3(x, n[1], n[2]);
    return fabs(vp_dot3(n[0], x)) > CORNER_DET;
}

/* With VP_PLAN_SMALL_FIRST the tilt is rated when a facet is found only where it bends more
 * than this (tan of half the angle to a neighbour, about 17 degrees: a sharp edge or corner,
 * where a cut-off cap cannot wait); elsewhere at the size pass (at_pass), once the poles have
 * settled: poles taken from stars still growing refined smooth parts that needed nothing (the
 * ellipsoid at --accuracy-rel 0.002, the smallest ball first: 3,054 vertices, 2,162 so). */
#define TILT_BEND_AT 0.15

/* The facet's place in the heap's order, and 1 if its ball is bad: its radius above the size
 * bound, or (with a distance bound) its centre too far from the facet, unless the ball is
 * already at the floor min_size; or its dual edge crosses S twice, down to MANIFOLD_FLOOR_MIN of
 * that floor (the manifold criterion's). The key is how far over its bounds the ball is.
 * at_pass: rated by the size pass (vp_pl_size_pass), else as it is found or changes. */
VP_PL_API int vp_pl_facet_rate(vp_planner_t *pl, vp_frec_t *f, int at_pass)
{
    double b = vp_pl_size_bound(pl, f->v, f->c), d;
    int bad = f->r > b;
    f->rated = pl->close.size_epoch;
    f->key = pl->cfg.size_rel > 0.0 || pl->cfg.max_distance > 0.0 ? f->r / b : f->r;
    /* its dual Voronoi edge crosses S twice (a fin or a gap thinner than the samples are apart:
     * the topological ball property fails there); the farther crossing is the ball kept */
    if (pl->cfg.max_distance > 0.0 && (f->flags & FREC_DOUBLE) && f->r > MANIFOLD_FLOOR_MIN * pl->cfg.min_size &&
        f->r > pl->cfg.noise_tol)
        bad = 1;
    if (pl->cfg.max_distance > 0.0 && f->r > pl->cfg.min_size) {
        /* hits are trusted to noise_tol: no bound below it can be seen, nor met */
        double bound = pl->cfg.max_distance > pl->cfg.noise_tol ? pl->cfg.max_distance : pl->cfg.noise_tol;
        d = facet_distance(pl, f) / bound;
        if (d > 1.0) bad = 1;
        if (d > f->key) f->key = d;
        double bend = facet_bend(pl, f);
        if (at_pass || bend > TILT_BEND_AT || !(pl->cfg.flags & VP_PLAN_SMALL_FIRST)) {
            d = facet_tilt(pl, f) / (TILT_SHARE * bound);
            if (d > 1.0) bad = 1;
            if (d > f->key) f->key = d;
        }
        d = f->r * bend / ((facet_at_corner(pl, f) ? CORNER_BEND_SHARE : BEND_SHARE) * bound);
        if (d > 1.0) bad = 1;
        if (d > f->key) f->key = d;
    }
    return bad;
}

/* What a rating reads: the stars of the facet's samples (their poles and normals) and the
 * records at its samples (the neighbours across its edges, for the bend). Each sample keeps the
 * size pass's epoch in which one of those last changed (pool.vstamp: an insertion or removal
 * touches the samples of the tets it kills, a record's birth, second ball or death its three).
 * A record whose samples last changed before the epoch it was rated in would rate the same: the
 * pass skips it (tests/core/test_planner_parts.c rates such records afresh on a whole scan). */
VP_PL_API void vp_pl_sample_touch(vp_planner_t *pl, uint32_t v)
{
    if (v < pl->pool.cap_nrm) pl->pool.vstamp[v] = pl->close.size_epoch;
}

static void frec_touch(vp_planner_t *pl, const vp_frec_t *f)
{
    int i;
    for (i = 0; i < 3; i++) vp_pl_sample_touch(pl, f->v[i]);
}

static int frec_unchanged(const vp_planner_t *pl, const vp_frec_t *f)
{
    int i;
    for (i = 0; i < 3; i++)
        if (f->v[i] >= pl->pool.cap_nrm || pl->pool.vstamp[f->v[i]] >= f->rated) return 0;
    return 1;
}

/* With the sizing field: every facet rated again (dM estimates shrink as samples arrive), but
 * for those whose samples saw no change since they were rated; the ones now bad are queued.
 * Returns how many. */
VP_PL_API int vp_pl_size_pass(vp_planner_t *pl)
{
    uint32_t k, n = 0;
    for (k = 0; k < pl->pool.nfrec; k++) {
        vp_frec_t *f = &pl->pool.frec[k];
        if (f->v[0] == NONE || f->heap != NONE || (f->flags & FREC_STUCK) || frec_unchanged(pl, f)) continue;
        if (vp_pl_facet_rate(pl, f, 1)) {
            VP_TRY(vp_pl_heap_push(pl, k));
            n++;
        }
    }
    pl->close.size_epoch++;
    return (int)n;
}

/* ---------- the bad-ball heap (max on key: the radius, or radius over size bound) ---------- */

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
        if (!(pl->pool.frec[pl->pool.heap[p]].key < pl->pool.frec[pl->pool.heap[i]].key)) break;
        heap_swap(pl, i, p);
        i = p;
    }
}

static void heap_down(vp_planner_t *pl, uint32_t i)
{
    for (;;) {
        uint32_t l = 2 * i + 1, r = l + 1, m = i;
        if (l < pl->pool.nheap && pl->pool.frec[pl->pool.heap[l]].key > pl->pool.frec[pl->pool.heap[m]].key) m = l;
        if (r < pl->pool.nheap && pl->pool.frec[pl->pool.heap[r]].key > pl->pool.frec[pl->pool.heap[m]].key) m = r;
        if (m == i) break;
        heap_swap(pl, i, m);
        i = m;
    }
}

VP_PL_API int vp_pl_heap_push(vp_planner_t *pl, uint32_t k)
{
    if (pl->pool.nheap >= pl->pool.cap_heap) return VP_ENOMEM;
    pl->pool.heap[pl->pool.nheap] = k;
    pl->pool.frec[k].heap = pl->pool.nheap++;
    heap_up(pl, pl->pool.nheap - 1);
    return VP_OK;
}

VP_PL_API void vp_pl_heap_remove(vp_planner_t *pl, uint32_t k)
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
VP_PL_API void vp_pl_fhash_rebuild(vp_planner_t *pl)
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

VP_PL_API void vp_pl_frec_delete(vp_planner_t *pl, uint32_t k)
{
    int found;
    uint32_t h = fhash_find(pl, pl->pool.frec[k].v, &found);
    frec_touch(pl, &pl->pool.frec[k]);
    if (found) {
        pl->pool.fhash[h] = HASH_TOMB;
        if (++pl->pool.ntomb > (pl->pool.hash_mask + 1u) / 4u) pl->pool.fhash_dirty = 1;
    }
    vp_pl_heap_remove(pl, k);
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

/* The record of facet fv (any order) with ball centre c, stored facing `outside`, not rated;
 * *found = 1 when the facet has one already (it keeps its first ball). */
static int frec_insert(vp_planner_t *pl, const uint32_t *fv, const double *c, const double *outside,
                       uint32_t tet, uint32_t proof, uint32_t *out, int *found)
{
    uint32_t v[3], k, h;
    vp_frec_t *f;
    const double *a;
    v[0] = fv[0]; v[1] = fv[1]; v[2] = fv[2];
    sort3(v);
    h = fhash_find(pl, v, found);
    if (*found) { *out = pl->pool.fhash[h]; return VP_OK; }
    if (pl->pool.frec_free != NONE) {
        k = pl->pool.frec_free;
        pl->pool.frec_free = pl->pool.frec[k].v[1];
    } else {
        if (pl->pool.nfrec >= pl->pool.cap_frec) return VP_ENOMEM;
        k = pl->pool.nfrec++;
    }
    f = &pl->pool.frec[k];
    memcpy(f->v, v, sizeof v);
    frec_touch(pl, f);
    f->heap = NONE;
    f->flags = 0;
    f->rated = 0;
    f->hint = tet;
    f->proof = proof;
    f->c[0] = c[0]; f->c[1] = c[1]; f->c[2] = c[2];
    a = vp_dt_point(&pl->dt, v[0]);
    f->r = vp_dist3(c, a);
    f->key = f->r;
    if (vp_orient3d(a, vp_dt_point(&pl->dt, v[1]), vp_dt_point(&pl->dt, v[2]), outside) < 0)
        f->flags |= FREC_FLIP;
    if (pl->pool.fhash[h] == HASH_TOMB && pl->pool.ntomb > 0) pl->pool.ntomb--;
    pl->pool.fhash[h] = k;
    pl->pool.nfacets++;
    *out = k;
    return VP_OK;
}

/* Adds facet fv (any order) with ball centre c; `outside` is a point on the probe's side, so
 * the facet is stored facing it. A facet already known keeps its first ball. */
VP_PL_API int vp_pl_frec_add(vp_planner_t *pl, const uint32_t *fv, const double *c, const double *outside,
                             uint32_t tet, uint32_t proof, uint32_t *out)
{
    int found, st = frec_insert(pl, fv, c, outside, tet, proof, out, &found);
    if (st != VP_OK || found) return st;
    if (vp_pl_facet_rate(pl, &pl->pool.frec[*out], 0) || facet_too_sharp(pl, pl->pool.frec[*out].v)) return vp_pl_heap_push(pl, *out);
    return VP_OK;
}

/* A facet of a tet cut off at a pinch (close.c): its ball is its circumball (no probe found
 * it), and it is never rated nor refined: its centre is not a point of S. The scratch
 * (pool.astar) is left alone: the closing pass holds its edge table there. */
VP_PL_API int vp_pl_frec_add_cut(vp_planner_t *pl, const uint32_t *fv, const double *outside, uint32_t tet, uint32_t *out)
{
    double m[3];
    int k, st;
    if (!vp_pl_facet_circumcenter(pl, fv, m))
        for (k = 0; k < 3; k++)
            m[k] = (vp_dt_point(&pl->dt, fv[0])[k] + vp_dt_point(&pl->dt, fv[1])[k] + vp_dt_point(&pl->dt, fv[2])[k]) / 3.0;
    st = frec_insert(pl, fv, m, outside, tet, PROOF_NONE, out, &k);
    if (st != VP_OK) return st;
    vp_pl_heap_remove(pl, *out);
    pl->pool.frec[*out].flags |= FREC_CUT | FREC_STUCK;
    return VP_OK;
}

/* A second ball for facet record k (the edge crosses S twice): keep the larger, and mark the
 * record so that no free segment is inferred from it any more. */
VP_PL_API void vp_pl_frec_set_ball(vp_planner_t *pl, uint32_t k, const double *c)
{
    vp_frec_t *f = &pl->pool.frec[k];
    double r = vp_dist3(c, vp_dt_point(&pl->dt, f->v[0]));
    f->flags |= FREC_DOUBLE;
    frec_touch(pl, f);
    if (!(r > f->r)) return;
    f->c[0] = c[0]; f->c[1] = c[1]; f->c[2] = c[2];
    f->r = r;
    if (f->heap != NONE) {
        (void)vp_pl_facet_rate(pl, f, 0);
        heap_up(pl, f->heap);
    } else if (vp_pl_facet_rate(pl, f, 0) && !(f->flags & FREC_STUCK)) {
        (void)vp_pl_heap_push(pl, k);
    }
}
