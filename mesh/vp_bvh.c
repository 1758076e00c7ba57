/* vp_bvh — see vp_bvh.h. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_bvh.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define VP_BVH_LEAF 4
#define VP_BVH_BINS 16
#define VP_BVH_MAXDEPTH 60

typedef struct vp_bvh_node {
    double lo[3], hi[3];
    uint32_t first;   /* leaf: first triangle slot; inner: index of the right child (left = this+1) */
    uint32_t count;   /* leaf: triangles; inner: 0 */
} vp_bvh_node_t;

struct vp_bvh {
    vp_bvh_node_t *node;
    size_t nnode;
    double *v;        /* 9 doubles per triangle slot, in leaf order */
    size_t *orig;     /* input index of each slot */
    size_t nt;
};

static double vp_clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

/* ---------- build ---------- */

typedef struct vp_bvh_build {
    const double *xyz;
    const uint32_t *tri;
    double *cen;       /* centroid per input triangle */
    double *blo, *bhi; /* box per input triangle */
    size_t *idx;       /* permutation being partitioned */
    vp_bvh_node_t *node;
    size_t nnode, cap;
} vp_bvh_build_t;

static void vp_box_empty(double lo[3], double hi[3])
{
    int k;
    for (k = 0; k < 3; k++) { lo[k] = DBL_MAX; hi[k] = -DBL_MAX; }
}
static void vp_box_grow(double lo[3], double hi[3], const double blo[3], const double bhi[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        if (blo[k] < lo[k]) lo[k] = blo[k];
        if (bhi[k] > hi[k]) hi[k] = bhi[k];
    }
}
static double vp_box_area(const double lo[3], const double hi[3])
{
    double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    if (dx < 0) return 0;
    return dx * dy + dy * dz + dz * dx;
}

static size_t vp_bvh_node_new(vp_bvh_build_t *B)
{
    return B->nnode++;   /* capacity 2*nt is enough for a binary tree with >= 1 triangle per leaf */
}

static void vp_bvh_split(vp_bvh_build_t *B, size_t ni, size_t begin, size_t end, int depth)
{
    vp_bvh_node_t *nd = &B->node[ni];
    double clo[3], chi[3];
    size_t n = end - begin, i, mid;
    int axis = -1, k, best_bin = -1;
    double best_cost = DBL_MAX;

    vp_box_empty(nd->lo, nd->hi);
    vp_box_empty(clo, chi);
    for (i = begin; i < end; i++) {
        size_t t = B->idx[i];
        vp_box_grow(nd->lo, nd->hi, B->blo + 3 * t, B->bhi + 3 * t);
        vp_box_grow(clo, chi, B->cen + 3 * t, B->cen + 3 * t);
    }
    if (n <= VP_BVH_LEAF || depth >= VP_BVH_MAXDEPTH) {
        nd->first = (uint32_t)begin; nd->count = (uint32_t)n;
        return;
    }
    /* Binned SAH over the three axes. */
    for (k = 0; k < 3; k++) {
        double ext = chi[k] - clo[k], scale;
        size_t cnt[VP_BVH_BINS];
        double lo[VP_BVH_BINS][3], hi[VP_BVH_BINS][3];
        double alo[3], ahi[3], area_left[VP_BVH_BINS];
        size_t nleft[VP_BVH_BINS], acc;
        int b;
        if (ext <= 0) continue;
        scale = VP_BVH_BINS / ext;
        for (b = 0; b < VP_BVH_BINS; b++) { cnt[b] = 0; vp_box_empty(lo[b], hi[b]); }
        for (i = begin; i < end; i++) {
            size_t t = B->idx[i];
            int bin = (int)((B->cen[3 * t + k] - clo[k]) * scale);
            if (bin >= VP_BVH_BINS) bin = VP_BVH_BINS - 1;
            if (bin < 0) bin = 0;
            cnt[bin]++;
            vp_box_grow(lo[bin], hi[bin], B->blo + 3 * t, B->bhi + 3 * t);
        }
        vp_box_empty(alo, ahi);
        acc = 0;
        for (b = 0; b < VP_BVH_BINS - 1; b++) {
            acc += cnt[b];
            vp_box_grow(alo, ahi, lo[b], hi[b]);
            area_left[b] = vp_box_area(alo, ahi);
            nleft[b] = acc;
        }
        vp_box_empty(alo, ahi);
        acc = 0;
        for (b = VP_BVH_BINS - 1; b > 0; b--) {
            double cost;
            acc += cnt[b];
            vp_box_grow(alo, ahi, lo[b], hi[b]);
            if (nleft[b - 1] == 0 || acc == 0) continue;
            cost = area_left[b - 1] * (double)nleft[b - 1] + vp_box_area(alo, ahi) * (double)acc;
            if (cost < best_cost) { best_cost = cost; axis = k; best_bin = b; }
        }
    }
    if (axis >= 0) {
        double scale = VP_BVH_BINS / (chi[axis] - clo[axis]);
        size_t lo_i = begin, hi_i = end;
        while (lo_i < hi_i) {
            size_t t = B->idx[lo_i];
            int bin = (int)((B->cen[3 * t + axis] - clo[axis]) * scale);
            if (bin >= VP_BVH_BINS) bin = VP_BVH_BINS - 1;
            if (bin < 0) bin = 0;
            if (bin < best_bin) lo_i++;
            else { hi_i--; B->idx[lo_i] = B->idx[hi_i]; B->idx[hi_i] = t; }
        }
        mid = lo_i;
    } else {
        mid = begin + n / 2;   /* all centroids equal: any split */
    }
    if (mid == begin || mid == end) mid = begin + n / 2;
    {
        size_t left = vp_bvh_node_new(B), right;
        vp_bvh_split(B, left, begin, mid, depth + 1);
        right = vp_bvh_node_new(B);
        vp_bvh_split(B, right, mid, end, depth + 1);
        B->node[ni].first = (uint32_t)right;
        B->node[ni].count = 0;
    }
}

int vp_bvh_build(const double *xyz, size_t nv, const uint32_t *tri, size_t nt, vp_bvh_t **out)
{
    vp_bvh_build_t B;
    vp_bvh_t *b;
    size_t i;
    int k, j;
    if (!xyz || !tri || !out || nt == 0 || nt > UINT32_MAX / 2) return VP_EINVAL;
    for (i = 0; i < 3 * nt; i++) if (tri[i] >= nv) return VP_EINVAL;
    memset(&B, 0, sizeof B);
    b = calloc(1, sizeof *b);
    B.cen = malloc(nt * 3 * sizeof(double));
    B.blo = malloc(nt * 3 * sizeof(double));
    B.bhi = malloc(nt * 3 * sizeof(double));
    B.idx = malloc(nt * sizeof(size_t));
    B.node = malloc(2 * nt * sizeof(vp_bvh_node_t));
    if (b) { b->v = malloc(nt * 9 * sizeof(double)); b->orig = malloc(nt * sizeof(size_t)); }
    if (!b || !B.cen || !B.blo || !B.bhi || !B.idx || !B.node || !b->v || !b->orig) {
        free(B.cen); free(B.blo); free(B.bhi); free(B.idx); free(B.node);
        if (b) { free(b->v); free(b->orig); free(b); }
        return VP_ENOMEM;
    }
    B.xyz = xyz; B.tri = tri;
    for (i = 0; i < nt; i++) {
        B.idx[i] = i;
        for (k = 0; k < 3; k++) {
            double a = xyz[3 * tri[3 * i] + k], c = xyz[3 * tri[3 * i + 1] + k], d = xyz[3 * tri[3 * i + 2] + k];
            B.cen[3 * i + k] = (a + c + d) / 3.0;
            B.blo[3 * i + k] = a < c ? (a < d ? a : d) : (c < d ? c : d);
            B.bhi[3 * i + k] = a > c ? (a > d ? a : d) : (c > d ? c : d);
        }
    }
    B.nnode = 0;
    vp_bvh_split(&B, vp_bvh_node_new(&B), 0, nt, 0);
    for (i = 0; i < nt; i++) {
        size_t t = B.idx[i];
        b->orig[i] = t;
        for (j = 0; j < 3; j++)
            for (k = 0; k < 3; k++) b->v[9 * i + 3 * j + k] = xyz[3 * tri[3 * t + j] + k];
    }
    b->node = B.node;
    b->nnode = B.nnode;
    b->nt = nt;
    free(B.cen); free(B.blo); free(B.bhi); free(B.idx);
    *out = b;
    return VP_OK;
}

void vp_bvh_free(vp_bvh_t *b)
{
    if (!b) return;
    free(b->node); free(b->v); free(b->orig); free(b);
}

void vp_bvh_bounds(const vp_bvh_t *b, double lo[3], double hi[3])
{
    memcpy(lo, b->node[0].lo, sizeof(double) * 3);
    memcpy(hi, b->node[0].hi, sizeof(double) * 3);
}

size_t vp_bvh_triangles(const vp_bvh_t *b) { return b->nt; }

/* ---------- rays ---------- */

/* Slab test: entry parameter of the ray in the box within [t0, t1], or +inf. */
static double vp_ray_box(const vp_bvh_node_t *nd, const double o[3], const double inv[3], double t0, double t1)
{
    int k;
    for (k = 0; k < 3; k++) {
        double a = (nd->lo[k] - o[k]) * inv[k], c = (nd->hi[k] - o[k]) * inv[k];
        if (a > c) { double s = a; a = c; c = s; }
        if (a != a) a = -DBL_MAX;   /* 0 * inf when the origin lies on a slab plane */
        if (c != c) c = DBL_MAX;
        if (a > t0) t0 = a;
        if (c < t1) t1 = c;
        if (t0 > t1) return DBL_MAX;
    }
    return t0;
}

#define VP_EDGE_TOL 1e-12

/* Moeller-Trumbore with inclusive edges; returns t or +inf. bary gets (u, v) when asked. */
static double vp_ray_tri(const double o[3], const double d[3], const double *v, double *bary, double *detp)
{
    double e1[3], e2[3], pv[3], tv[3], qv[3], det, inv, u, w;
    vp_sub3(e1, v + 3, v);
    vp_sub3(e2, v + 6, v);
    vp_cross3(pv, d, e2);
    det = vp_dot3(e1, pv);
    if (detp) *detp = det;
    if (det == 0) return DBL_MAX;
    inv = 1.0 / det;
    vp_sub3(tv, o, v);
    u = vp_dot3(tv, pv) * inv;
    if (u < -VP_EDGE_TOL || u > 1 + VP_EDGE_TOL) return DBL_MAX;
    vp_cross3(qv, tv, e1);
    w = vp_dot3(d, qv) * inv;
    if (w < -VP_EDGE_TOL || u + w > 1 + VP_EDGE_TOL) return DBL_MAX;
    if (bary) { bary[0] = u; bary[1] = w; }
    return vp_dot3(e2, qv) * inv;
}

int vp_bvh_ray(const vp_bvh_t *b, const double o[3], const double d[3], double tmin, double tmax,
               double *t, size_t *tri)
{
    uint32_t stack[VP_BVH_MAXDEPTH + 8];
    int sp = 0, k;
    double inv[3], best = tmax;
    size_t best_tri = (size_t)-1;
    for (k = 0; k < 3; k++) inv[k] = 1.0 / d[k];
    if (vp_ray_box(&b->node[0], o, inv, tmin, best) == DBL_MAX) return 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const vp_bvh_node_t *nd = &b->node[stack[--sp]];
        if (nd->count) {
            uint32_t i;
            for (i = nd->first; i < nd->first + nd->count; i++) {
                double th = vp_ray_tri(o, d, b->v + 9 * (size_t)i, NULL, NULL);
                if (th > tmin && th <= best) { best = th; best_tri = i; }
            }
        } else {
            uint32_t l = (uint32_t)(nd - b->node) + 1, r = nd->first;
            double tl = vp_ray_box(&b->node[l], o, inv, tmin, best);
            double tr = vp_ray_box(&b->node[r], o, inv, tmin, best);
            if (tl <= tr) {   /* push the farther first so the nearer is popped first */
                if (tr != DBL_MAX) stack[sp++] = r;
                if (tl != DBL_MAX) stack[sp++] = l;
            } else {
                if (tl != DBL_MAX) stack[sp++] = l;
                if (tr != DBL_MAX) stack[sp++] = r;
            }
        }
    }
    if (best_tri == (size_t)-1) return 0;
    *t = best;
    if (tri) *tri = b->orig[best_tri];
    return 1;
}

/* Counts crossings of the ray from p along d; -1 when a hit is too close to an edge to trust. */
static long vp_bvh_parity(const vp_bvh_t *b, const double p[3], const double d[3])
{
    uint32_t stack[VP_BVH_MAXDEPTH + 8];
    int sp = 0, k;
    double inv[3];
    long count = 0;
    for (k = 0; k < 3; k++) inv[k] = 1.0 / d[k];
    stack[sp++] = 0;
    while (sp > 0) {
        const vp_bvh_node_t *nd = &b->node[stack[--sp]];
        if (vp_ray_box(nd, p, inv, 0, DBL_MAX) == DBL_MAX) continue;
        if (nd->count) {
            uint32_t i;
            for (i = nd->first; i < nd->first + nd->count; i++) {
                double bary[2], det, th;
                const double *v = b->v + 9 * (size_t)i;
                th = vp_ray_tri(p, d, v, bary, &det);
                if (th == DBL_MAX) {
                    /* Near-parallel triangles close to the ray make parity unreliable. */
                    continue;
                }
                if (th < 0) continue;
                if (th < 1e-300 || bary[0] < 1e-9 || bary[1] < 1e-9 || bary[0] + bary[1] > 1 - 1e-9) return -1;
                {
                    double e1[3], e2[3], n[3], nn;
                    vp_sub3(e1, v + 3, v); vp_sub3(e2, v + 6, v); vp_cross3(n, e1, e2);
                    nn = sqrt(vp_dot3(n, n));
                    if (fabs(det) < 1e-9 * nn) return -1;   /* grazing */
                }
                count++;
            }
        } else {
            stack[sp++] = nd->first;
            stack[sp++] = (uint32_t)(nd - b->node) + 1;
        }
    }
    return count;
}

int vp_bvh_inside(const vp_bvh_t *b, const double p[3])
{
    static const double dirs[8][3] = {
        { 0.5773502691896258, 0.5773502691896258, 0.5773502691896258 },
        { 0.2672612419124244, -0.5345224838248488, 0.8017837257372732 },
        { -0.8164965809277261, 0.4082482904638631, 0.4082482904638631 },
        { 0.1230914909793327, 0.4923659639173309, -0.8616404368553291 },
        { -0.3015113445777636, -0.9045340337332909, 0.3015113445777636 },
        { 0.7071067811865476, 0.0, -0.7071067811865476 },
        { -0.2357022603955158, 0.9428090415820634, 0.2357022603955158 },
        { 0.9284766908852593, -0.1856953381770519, -0.3218714670404766 }
    };
    int i, votes = 0, n = 0;
    for (i = 0; i < 8; i++) {
        long c = vp_bvh_parity(b, p, dirs[i]);
        if (c < 0) continue;
        n++;
        votes += (int)(c & 1);
        if (n == 1) return (int)(c & 1);   /* one clean ray decides */
    }
    return n ? votes * 2 > n : 0;
}

/* ---------- closest point ---------- */

double vp_tri_closest(const double p[3], const double a[3], const double b[3], const double c[3], double q[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], d1, d2, d3, d4, d5, d6, va, vb, vc, v, w, den;
    int k;
    vp_sub3(ab, b, a); vp_sub3(ac, c, a); vp_sub3(ap, p, a);
    d1 = vp_dot3(ab, ap); d2 = vp_dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) { memcpy(q, a, 3 * sizeof(double)); goto done; }
    vp_sub3(bp, p, b);
    d3 = vp_dot3(ab, bp); d4 = vp_dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) { memcpy(q, b, 3 * sizeof(double)); goto done; }
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        v = d1 / (d1 - d3);
        for (k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
        goto done;
    }
    vp_sub3(cp, p, c);
    d5 = vp_dot3(ab, cp); d6 = vp_dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) { memcpy(q, c, 3 * sizeof(double)); goto done; }
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        w = d2 / (d2 - d6);
        for (k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
        goto done;
    }
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
        goto done;
    }
    den = va + vb + vc;
    if (den <= 0) {   /* degenerate triangle: fall back to its edges */
        double qa[3], best = DBL_MAX, dd;
        const double *e[3][2] = { { a, b }, { b, c }, { c, a } };
        for (k = 0; k < 3; k++) {
            double ed[3], pe[3], s, l2;
            int j;
            vp_sub3(ed, e[k][1], e[k][0]); vp_sub3(pe, p, e[k][0]);
            l2 = vp_dot3(ed, ed);
            s = l2 > 0 ? vp_clamp01(vp_dot3(pe, ed) / l2) : 0;
            for (j = 0; j < 3; j++) qa[j] = e[k][0][j] + s * ed[j];
            vp_sub3(pe, p, qa);
            dd = vp_dot3(pe, pe);
            if (dd < best) { best = dd; memcpy(q, qa, sizeof qa); }
        }
        return best;
    }
    v = vb / den; w = vc / den;
    for (k = 0; k < 3; k++) q[k] = a[k] + ab[k] * v + ac[k] * w;
done:
    {
        double dq[3];
        vp_sub3(dq, p, q);
        return vp_dot3(dq, dq);
    }
}

static double vp_point_box_dist2(const double p[3], const vp_bvh_node_t *nd)
{
    double s = 0;
    int k;
    for (k = 0; k < 3; k++) {
        double e = p[k] < nd->lo[k] ? nd->lo[k] - p[k] : p[k] > nd->hi[k] ? p[k] - nd->hi[k] : 0;
        s += e * e;
    }
    return s;
}

double vp_bvh_closest(const vp_bvh_t *b, const double p[3], double q[3], size_t *tri)
{
    uint32_t stack[VP_BVH_MAXDEPTH + 8];
    int sp = 0;
    double best = DBL_MAX, bq[3] = { 0, 0, 0 };
    size_t bt = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const vp_bvh_node_t *nd = &b->node[stack[--sp]];
        if (vp_point_box_dist2(p, nd) >= best) continue;
        if (nd->count) {
            uint32_t i;
            for (i = nd->first; i < nd->first + nd->count; i++) {
                const double *v = b->v + 9 * (size_t)i;
                double cq[3], d2 = vp_tri_closest(p, v, v + 3, v + 6, cq);
                if (d2 < best) { best = d2; memcpy(bq, cq, sizeof bq); bt = i; }
            }
        } else {
            uint32_t l = (uint32_t)(nd - b->node) + 1, r = nd->first;
            double dl = vp_point_box_dist2(p, &b->node[l]), dr = vp_point_box_dist2(p, &b->node[r]);
            if (dl <= dr) { stack[sp++] = r; stack[sp++] = l; }
            else { stack[sp++] = l; stack[sp++] = r; }
        }
    }
    if (q) memcpy(q, bq, sizeof bq);
    if (tri) *tri = b->orig[bt];
    return sqrt(best);
}

/* ---------- segments ---------- */

static double vp_seg_seg_dist2(const double p1[3], const double q1[3], const double p2[3], const double q2[3])
{
    double d1[3], d2[3], r[3], a, e, f, s, t, c1[3], c2[3], dd[3];
    int k;
    vp_sub3(d1, q1, p1); vp_sub3(d2, q2, p2); vp_sub3(r, p1, p2);
    a = vp_dot3(d1, d1); e = vp_dot3(d2, d2); f = vp_dot3(d2, r);
    if (a <= 0 && e <= 0) return vp_dot3(r, r);
    if (a <= 0) { s = 0; t = vp_clamp01(f / e); }
    else {
        double c = vp_dot3(d1, r);
        if (e <= 0) { t = 0; s = vp_clamp01(-c / a); }
        else {
            double bb = vp_dot3(d1, d2), den = a * e - bb * bb;
            s = den > 0 ? vp_clamp01((bb * f - c * e) / den) : 0;
            t = (bb * s + f) / e;
            if (t < 0) { t = 0; s = vp_clamp01(-c / a); }
            else if (t > 1) { t = 1; s = vp_clamp01((bb - c) / a); }
        }
    }
    for (k = 0; k < 3; k++) { c1[k] = p1[k] + d1[k] * s; c2[k] = p2[k] + d2[k] * t; }
    vp_sub3(dd, c1, c2);
    return vp_dot3(dd, dd);
}

double vp_seg_tri_dist2(const double a[3], const double c[3], const double v0[3], const double v1[3], const double v2[3])
{
    double d[3], tv[9], best, q[3], x;
    double th;
    vp_sub3(d, c, a);
    memcpy(tv, v0, 3 * sizeof(double)); memcpy(tv + 3, v1, 3 * sizeof(double)); memcpy(tv + 6, v2, 3 * sizeof(double));
    th = vp_ray_tri(a, d, tv, NULL, NULL);
    if (th >= 0 && th <= 1) return 0;
    best = vp_tri_closest(a, v0, v1, v2, q);
    x = vp_tri_closest(c, v0, v1, v2, q); if (x < best) best = x;
    x = vp_seg_seg_dist2(a, c, v0, v1); if (x < best) best = x;
    x = vp_seg_seg_dist2(a, c, v1, v2); if (x < best) best = x;
    x = vp_seg_seg_dist2(a, c, v2, v0); if (x < best) best = x;
    return best;
}

/* Segment [a, a+d] against a box inflated by r (slab test, conservative for the rounded box). */
static int vp_seg_box(const vp_bvh_node_t *nd, const double a[3], const double inv[3], double r)
{
    double t0 = 0, t1 = 1;
    int k;
    for (k = 0; k < 3; k++) {
        double lo = (nd->lo[k] - r - a[k]) * inv[k], hi = (nd->hi[k] + r - a[k]) * inv[k];
        if (lo > hi) { double s = lo; lo = hi; hi = s; }
        if (lo != lo) lo = -DBL_MAX;
        if (hi != hi) hi = DBL_MAX;
        if (lo > t0) t0 = lo;
        if (hi < t1) t1 = hi;
        if (t0 > t1) return 0;
    }
    return 1;
}

int vp_bvh_segment_near(const vp_bvh_t *b, const double a[3], const double c[3], double r)
{
    uint32_t stack[VP_BVH_MAXDEPTH + 8];
    int sp = 0, k;
    double d[3], inv[3], r2 = r * r;
    vp_sub3(d, c, a);
    for (k = 0; k < 3; k++) inv[k] = 1.0 / d[k];
    stack[sp++] = 0;
    while (sp > 0) {
        const vp_bvh_node_t *nd = &b->node[stack[--sp]];
        if (!vp_seg_box(nd, a, inv, r)) continue;
        if (nd->count) {
            uint32_t i;
            for (i = nd->first; i < nd->first + nd->count; i++) {
                const double *v = b->v + 9 * (size_t)i;
                if (vp_seg_tri_dist2(a, c, v, v + 3, v + 6) <= r2) return 1;
            }
        } else {
            stack[sp++] = nd->first;
            stack[sp++] = (uint32_t)(nd - b->node) + 1;
        }
    }
    return 0;
}
