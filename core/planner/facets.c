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

/* ---------- the sizing field (paper 002, section 6) ----------
 * g(x) = size_rel * min_p (dM(p) + |x - p|): size_rel times the 1-Lipschitz extension of dM from
 * the samples p; dM(p), the distance to the medial axis, is estimated by the distance to p's
 * poles: the farthest vertex of its Voronoi cell (at infinity on the hull), and the farthest
 * one on the other side. The min is taken over the facet's own vertices (the samples nearest
 * its ball centre), and g is held to [min_size, eps]: the floor ends refinement on sharp edges,
 * where dM goes to 0. A ball is bad when r > g(c), i.e. r > size_rel dM / (1 - size_rel). */
static double pole_distance(vp_planner_t *pl, uint32_t v)
{
    const double *p = vp_dt_point(&pl->dt, v);
    uint32_t *tets = pl->pool.astar, i;
    int n = vp_dt_incident_tets(&pl->dt, v, tets, (int)pl->pool.cap_astar), unbounded = 0;
    double far = -1.0, other = -1.0, u[3] = { 0, 0, 0 }, c[3], d[3], dist;
    if (n <= 0) return VP_PL_HUGE;
    for (i = 0; i < (uint32_t)n; i++) {
        if (vp_dt_is_ghost(&pl->dt, tets[i])) { unbounded = 1; continue; }
        if (vp_dt_circumcenter(&pl->dt, tets[i], c) != VP_OK) continue;
        vp_sub3(d, c, p);
        dist = vp_norm3(d);
        if (dist > far) { far = dist; memcpy(u, d, sizeof u); }
    }
    if (unbounded) {
        /* the first pole is at infinity, outward: away from the neighbours' centroid */
        double m[3] = { 0, 0, 0 };
        uint32_t cnt = 0, k;
        for (i = 0; i < (uint32_t)n; i++) {
            const uint32_t *w = vp_dt_tet(&pl->dt, tets[i]);
            for (k = 0; k < 4; k++)
                if (w[k] != v && w[k] != VP_DT_GHOST) {
                    const double *q = vp_dt_point(&pl->dt, w[k]);
                    m[0] += q[0]; m[1] += q[1]; m[2] += q[2];
                    cnt++;
                }
        }
        if (cnt == 0) return VP_PL_HUGE;
        for (k = 0; k < 3; k++) u[k] = p[k] - m[k] / (double)cnt;
    }
    for (i = 0; i < (uint32_t)n; i++) {
        if (vp_dt_is_ghost(&pl->dt, tets[i]) || vp_dt_circumcenter(&pl->dt, tets[i], c) != VP_OK) continue;
        vp_sub3(d, c, p);
        if (vp_dot3(d, u) < 0.0 && (dist = vp_norm3(d)) > other) other = dist;
    }
    if (unbounded) return other >= 0.0 ? other : VP_PL_HUGE;
    if (far < 0.0) return VP_PL_HUGE;
    return other >= 0.0 && other < far ? other : far;
}

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

/* The facet's place in the heap's order, and 1 if its ball is bad */
static int facet_rate(vp_planner_t *pl, vp_frec_t *f)
{
    double b = vp_pl_size_bound(pl, f->v, f->c);
    f->key = pl->cfg.size_rel > 0.0 ? f->r / b : f->r;
    return f->r > b;
}

/* With the sizing field: every facet rated again (dM estimates shrink as samples arrive); the
 * ones now bad are queued. Returns how many. */
VP_PL_API int vp_pl_size_pass(vp_planner_t *pl)
{
    uint32_t k, n = 0;
    for (k = 0; k < pl->pool.nfrec; k++) {
        vp_frec_t *f = &pl->pool.frec[k];
        if (f->v[0] == NONE || f->heap != NONE || (f->flags & FREC_STUCK)) continue;
        if (facet_rate(pl, f)) {
            VP_TRY(vp_pl_heap_push(pl, k));
            n++;
        }
    }
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

/* Adds facet fv (any order) with ball centre c; `outside` is a point on the probe's side, so
 * the facet is stored facing it. A facet already known keeps its first ball. */
VP_PL_API int vp_pl_frec_add(vp_planner_t *pl, const uint32_t *fv, const double *c, const double *outside,
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
    if (facet_rate(pl, f) || facet_too_sharp(pl, v)) return vp_pl_heap_push(pl, k);
    return VP_OK;
}

/* A second ball for facet record k (the edge crosses S twice): keep the larger, and mark the
 * record so that no free segment is inferred from it any more. */
VP_PL_API void vp_pl_frec_set_ball(vp_planner_t *pl, uint32_t k, const double *c)
{
    vp_frec_t *f = &pl->pool.frec[k];
    double r = vp_dist3(c, vp_dt_point(&pl->dt, f->v[0]));
    f->flags |= FREC_DOUBLE;
    if (!(r > f->r)) return;
    f->c[0] = c[0]; f->c[1] = c[1]; f->c[2] = c[2];
    f->r = r;
    if (f->heap != NONE) {
        (void)facet_rate(pl, f);
        heap_up(pl, f->heap);
    } else if (facet_rate(pl, f) && !(f->flags & FREC_STUCK)) {
        (void)vp_pl_heap_push(pl, k);
    }
}
