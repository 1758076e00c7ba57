/* vp_kdtree — points stored in tree order: the median of each range is the node, split on the
 * widest axis of the range; the axis is kept per node. */
#include <float.h>
#include <stdlib.h>
#include <string.h>
#include "vp_kdtree.h"
#include "vp_status.h"

struct vp_kdtree {
    double *p;            /* 3*n, tree order */
    size_t *orig;         /* input index of each slot */
    unsigned char *axis;  /* split axis per slot */
    size_t n;
};

static void vp_kd_swap(vp_kdtree_t *t, size_t i, size_t j)
{
    double tmp[3];
    size_t o;
    memcpy(tmp, t->p + 3 * i, sizeof tmp);
    memcpy(t->p + 3 * i, t->p + 3 * j, sizeof tmp);
    memcpy(t->p + 3 * j, tmp, sizeof tmp);
    o = t->orig[i]; t->orig[i] = t->orig[j]; t->orig[j] = o;
}

/* Quickselect: puts the k-th smallest (by axis) of [lo,hi) at k. */
static void vp_kd_select(vp_kdtree_t *t, size_t lo, size_t hi, size_t k, int ax)
{
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2, i, store;
        double pivot;
        /* median of three as pivot */
        double a = t->p[3 * lo + ax], b = t->p[3 * mid + ax], c = t->p[3 * (hi - 1) + ax];
        size_t pi = (a < b) ? (b < c ? mid : (a < c ? hi - 1 : lo)) : (a < c ? lo : (b < c ? hi - 1 : mid));
        pivot = t->p[3 * pi + ax];
        vp_kd_swap(t, pi, hi - 1);
        store = lo;
        for (i = lo; i < hi - 1; i++)
            if (t->p[3 * i + ax] < pivot) vp_kd_swap(t, i, store++);
        vp_kd_swap(t, store, hi - 1);
        if (store == k) return;
        if (k < store) { hi = store; continue; }
        /* the pivot's equals next to it: many equal coordinates (a mesh's repeated vertices)
         * otherwise take one element a pass */
        lo = store + 1;
        for (i = lo; i < hi; i++)
            if (t->p[3 * i + ax] == pivot) vp_kd_swap(t, i, lo++);
        if (k < lo) return;
    }
}

static void vp_kd_build_range(vp_kdtree_t *t, size_t lo, size_t hi)
{
    while (hi > lo) {
        double mn[3] = { DBL_MAX, DBL_MAX, DBL_MAX }, mx[3] = { -DBL_MAX, -DBL_MAX, -DBL_MAX };
        size_t i, mid = lo + (hi - lo) / 2;
        int k, ax = 0;
        for (i = lo; i < hi; i++)
            for (k = 0; k < 3; k++) {
                double v = t->p[3 * i + k];
                if (v < mn[k]) mn[k] = v;
                if (v > mx[k]) mx[k] = v;
            }
        for (k = 1; k < 3; k++) if (mx[k] - mn[k] > mx[ax] - mn[ax]) ax = k;
        vp_kd_select(t, lo, hi, mid, ax);
        t->axis[mid] = (unsigned char)ax;
        vp_kd_build_range(t, lo, mid);
        lo = mid + 1;
    }
}

int vp_kdtree_build(const double *xyz, size_t n, vp_kdtree_t **out)
{
    vp_kdtree_t *t;
    size_t i;
    if (!xyz || !out || n == 0) return VP_EINVAL;
    t = calloc(1, sizeof *t);
    if (!t) return VP_ENOMEM;
    t->p = malloc(n * 3 * sizeof(double));
    t->orig = malloc(n * sizeof(size_t));
    t->axis = malloc(n);
    if (!t->p || !t->orig || !t->axis) { vp_kdtree_free(t); return VP_ENOMEM; }
    memcpy(t->p, xyz, n * 3 * sizeof(double));
    for (i = 0; i < n; i++) t->orig[i] = i;
    t->n = n;
    vp_kd_build_range(t, 0, n);
    *out = t;
    return VP_OK;
}

void vp_kdtree_free(vp_kdtree_t *t)
{
    if (!t) return;
    free(t->p); free(t->orig); free(t->axis); free(t);
}

typedef struct vp_kd_best { size_t k, n; size_t idx[32]; double d2[32]; } vp_kd_best_t;

static void vp_kd_offer(vp_kd_best_t *b, size_t slot, double d2)
{
    size_t i;
    if (b->n == b->k && d2 >= b->d2[b->n - 1]) return;
    i = b->n < b->k ? b->n++ : b->n - 1;
    while (i > 0 && b->d2[i - 1] > d2) { b->d2[i] = b->d2[i - 1]; b->idx[i] = b->idx[i - 1]; i--; }
    b->d2[i] = d2; b->idx[i] = slot;
}

static void vp_kd_search(const vp_kdtree_t *t, size_t lo, size_t hi, const double p[3], vp_kd_best_t *b)
{
    while (hi > lo) {
        size_t mid = lo + (hi - lo) / 2;
        const double *q = t->p + 3 * mid;
        int ax = t->axis[mid];
        double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2], diff = p[ax] - q[ax];
        vp_kd_offer(b, mid, dx * dx + dy * dy + dz * dz);
        if (diff < 0) {
            vp_kd_search(t, lo, mid, p, b);
            if (b->n == b->k && diff * diff >= b->d2[b->n - 1]) return;
            lo = mid + 1;
        } else {
            vp_kd_search(t, mid + 1, hi, p, b);
            if (b->n == b->k && diff * diff >= b->d2[b->n - 1]) return;
            hi = mid;
        }
    }
}

size_t vp_kdtree_knn(const vp_kdtree_t *t, const double p[3], size_t k, size_t *idx, double *d2)
{
    vp_kd_best_t b;
    size_t i;
    if (k > 32) k = 32;
    if (k == 0) return 0;
    b.k = k; b.n = 0;
    vp_kd_search(t, 0, t->n, p, &b);
    for (i = 0; i < b.n; i++) {
        if (idx) idx[i] = b.idx[i];
        if (d2) d2[i] = b.d2[i];
    }
    return b.n;
}

const double *vp_kdtree_point(const vp_kdtree_t *t, size_t slot) { return t->p + 3 * slot; }

size_t vp_kdtree_original(const vp_kdtree_t *t, size_t slot) { return t->orig[slot]; }
