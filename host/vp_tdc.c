/* vp_tdc — the tangential Delaunay complex (see vp_tdc.h). */
#include "vp_tdc.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_file.h"
#include "vp_rng.h"
#include "vp_status.h"

#define NONE UINT32_MAX
#define LEAF 8
#define CELL_VMAX 8192   /* vertices of one restricted power cell */

/* ---- k-d tree over points of R^d (indices into a caller's array, which may move between
 * builds: the tree is rebuilt after each fixing round) ---- */
typedef struct kd_node { uint32_t lo, hi; int dim; double split; int32_t left, right; } kd_node_t;
typedef struct kd_tree {
    const double *pts;
    int d;
    size_t n, nn, cap;
    uint32_t *idx;
    kd_node_t *node;
} kd_tree_t;

static double coord(const kd_tree_t *T, uint32_t i, int c) { return T->pts[(size_t)i * T->d + c]; }

static int32_t kd_make(kd_tree_t *T, uint32_t lo, uint32_t hi)
{
    int32_t me = (int32_t)T->nn++;
    kd_node_t *nd = &T->node[me];
    nd->lo = lo; nd->hi = hi; nd->left = nd->right = -1; nd->dim = 0; nd->split = 0;
    if (hi - lo > LEAF) {
        double lo_c[VP_TDC_DMAX], hi_c[VP_TDC_DMAX], best = -1;
        uint32_t i, mid = lo + (hi - lo) / 2, a = lo, b = hi - 1;
        int c, dim = 0;
        for (c = 0; c < T->d; c++) { lo_c[c] = INFINITY; hi_c[c] = -INFINITY; }
        for (i = lo; i < hi; i++)
            for (c = 0; c < T->d; c++) {
                double v = coord(T, T->idx[i], c);
                if (v < lo_c[c]) lo_c[c] = v;
                if (v > hi_c[c]) hi_c[c] = v;
            }
        for (c = 0; c < T->d; c++) if (hi_c[c] - lo_c[c] > best) { best = hi_c[c] - lo_c[c]; dim = c; }
        /* quickselect: idx[mid] at its place along dim */
        while (a < b) {
            double piv = coord(T, T->idx[a + (b - a) / 2], dim);
            uint32_t x = a, y = b;
            while (x <= y) {
                while (coord(T, T->idx[x], dim) < piv) x++;
                while (coord(T, T->idx[y], dim) > piv) y--;
                if (x <= y) {
                    uint32_t t = T->idx[x]; T->idx[x] = T->idx[y]; T->idx[y] = t;
                    x++;
                    if (y == 0) break;
                    y--;
                }
            }
            if (mid <= y) b = y;
            else if (mid >= x) a = x;
            else break;
        }
        nd->dim = dim;
        nd->split = coord(T, T->idx[mid], dim);
        {
            int32_t l = kd_make(T, lo, mid), r = kd_make(T, mid, hi);
            T->node[me].left = l;
            T->node[me].right = r;
        }
    }
    return me;
}

static int kd_build(kd_tree_t *T, const double *pts, size_t n, int d)
{
    size_t i;
    T->pts = pts; T->d = d; T->n = n; T->nn = 0;
    if (!T->idx) {
        T->cap = 2 * (n / (LEAF / 2) + 1) + 8;
        T->idx = malloc(n * sizeof *T->idx);
        T->node = malloc(T->cap * sizeof *T->node);
        if (!T->idx || !T->node) return VP_ENOMEM;
    }
    for (i = 0; i < n; i++) T->idx[i] = (uint32_t)i;
    kd_make(T, 0, (uint32_t)n);
    return VP_OK;
}

static void kd_free(kd_tree_t *T) { free(T->idx); free(T->node); T->idx = NULL; T->node = NULL; }

static double dist2(const double *a, const double *b, int d)
{
    double s = 0;
    int c;
    for (c = 0; c < d; c++) { double t = a[c] - b[c]; s += t * t; }
    return s;
}

/* K nearest: a max-heap on d2 (hd, hi), m filled. */
typedef struct knn { size_t K, m; double *hd; uint32_t *hi; } knn_t;

static void heap_push(knn_t *h, double d2, uint32_t i)
{
    size_t c, p;
    if (h->m < h->K) {
        c = h->m++;
        while (c > 0 && h->hd[p = (c - 1) / 2] < d2) { h->hd[c] = h->hd[p]; h->hi[c] = h->hi[p]; c = p; }
        h->hd[c] = d2; h->hi[c] = i;
    } else if (d2 < h->hd[0]) {
        c = 0;
        for (;;) {
            size_t l = 2 * c + 1, r = l + 1, big = c;
            double bd = d2;
            if (l < h->m && h->hd[l] > bd) { big = l; bd = h->hd[l]; }
            if (r < h->m && h->hd[r] > bd) { big = r; }
            if (big == c) break;
            h->hd[c] = h->hd[big]; h->hi[c] = h->hi[big]; c = big;
        }
        h->hd[c] = d2; h->hi[c] = i;
    }
}

static void kd_knn_rec(const kd_tree_t *T, int32_t ni, const double *q, knn_t *h)
{
    const kd_node_t *nd = &T->node[ni];
    if (nd->left < 0) {
        uint32_t i;
        for (i = nd->lo; i < nd->hi; i++) {
            uint32_t id = T->idx[i];
            heap_push(h, dist2(q, T->pts + (size_t)id * T->d, T->d), id);
        }
        return;
    } else {
        double diff = q[nd->dim] - nd->split;
        int32_t near = diff < 0 ? nd->left : nd->right, far = diff < 0 ? nd->right : nd->left;
        kd_knn_rec(T, near, q, h);
        if (h->m < h->K || diff * diff < h->hd[0]) kd_knn_rec(T, far, q, h);
    }
}

/* The K nearest points to q, nearest first (sorted out of the heap). */
static size_t kd_knn(const kd_tree_t *T, const double *q, size_t K, double *d2, uint32_t *id)
{
    knn_t h;
    size_t m, i;
    h.K = K < T->n ? K : T->n; h.m = 0; h.hd = d2; h.hi = id;
    kd_knn_rec(T, 0, q, &h);
    m = h.m;
    for (i = m; i > 1; i--) {   /* heap sort: largest to the end */
        double td = h.hd[0]; uint32_t ti = h.hi[0];
        double dlast = h.hd[i - 1]; uint32_t ilast = h.hi[i - 1];
        h.hd[i - 1] = td; h.hi[i - 1] = ti;
        h.m = i - 1;
        h.hd[0] = dlast; h.hi[0] = ilast;
        {   /* sift down */
            size_t c = 0;
            for (;;) {
                size_t l = 2 * c + 1, r = l + 1, big = c;
                if (l < h.m && h.hd[l] > h.hd[big]) big = l;
                if (r < h.m && h.hd[r] > h.hd[big]) big = r;
                if (big == c) break;
                td = h.hd[c]; h.hd[c] = h.hd[big]; h.hd[big] = td;
                ti = h.hi[c]; h.hi[c] = h.hi[big]; h.hi[big] = ti;
                c = big;
            }
        }
    }
    return m;
}

typedef struct idlist { uint32_t *v; size_t n, cap; } idlist_t;

static int idlist_push(idlist_t *l, uint32_t x)
{
    if (l->n == l->cap) {
        size_t nc = l->cap ? 2 * l->cap : 256;
        uint32_t *nv = realloc(l->v, nc * sizeof *nv);
        if (!nv) return VP_ENOMEM;
        l->v = nv; l->cap = nc;
    }
    l->v[l->n++] = x;
    return VP_OK;
}

static int kd_ball_rec(const kd_tree_t *T, int32_t ni, const double *q, double r2, idlist_t *out)
{
    const kd_node_t *nd = &T->node[ni];
    if (nd->left < 0) {
        uint32_t i;
        for (i = nd->lo; i < nd->hi; i++)
            if (dist2(q, T->pts + (size_t)T->idx[i] * T->d, T->d) <= r2) VP_TRY(idlist_push(out, T->idx[i]));
        return VP_OK;
    } else {
        double diff = q[nd->dim] - nd->split;
        if (diff < 0 || diff * diff <= r2) VP_TRY(kd_ball_rec(T, nd->left, q, r2, out));
        if (diff >= 0 || diff * diff <= r2) VP_TRY(kd_ball_rec(T, nd->right, q, r2, out));
        return VP_OK;
    }
}

/* ---- the simplices of all stars: how many stars hold each (open addressing) ---- */
typedef struct sx_entry { uint32_t v[VP_TDC_KMAX + 1]; uint32_t count; } sx_entry_t;
typedef struct sx_table { sx_entry_t *e; size_t cap, used; int k; } sx_table_t;

static uint64_t sx_hash(const uint32_t *v, int k)
{
    uint64_t h = 0x243f6a8885a308d3ULL;
    int c;
    for (c = 0; c <= k; c++) h = vp_mix64(h ^ v[c]);
    return h;
}

static int sx_grow(sx_table_t *S)
{
    size_t nc = S->cap ? 2 * S->cap : 1024, i, live = 0;
    sx_entry_t *ne, *old = S->e;
    for (i = 0; i < S->cap; i++) live += old[i].count > 0;
    while (4 * (live + 1) > nc) nc *= 2;   /* at most a quarter full after growing */
    ne = malloc(nc * sizeof *ne);
    if (!ne) return VP_ENOMEM;
    for (i = 0; i < nc; i++) { ne[i].v[0] = NONE; ne[i].count = 0; }
    for (i = 0; i < S->cap; i++)
        if (old[i].count > 0) {
            size_t h = (size_t)sx_hash(old[i].v, S->k) & (nc - 1);
            while (ne[h].v[0] != NONE) h = (h + 1) & (nc - 1);
            ne[h] = old[i];
        }
    free(old);
    S->e = ne; S->cap = nc; S->used = live;
    return VP_OK;
}

/* The entry of simplex v (created with count 0 when absent). */
static int sx_find(sx_table_t *S, const uint32_t *v, sx_entry_t **out)
{
    size_t h;
    if ((S->used + 1) * 2 > S->cap) VP_TRY(sx_grow(S));
    h = (size_t)sx_hash(v, S->k) & (S->cap - 1);
    while (S->e[h].v[0] != NONE) {
        if (!memcmp(S->e[h].v, v, (size_t)(S->k + 1) * sizeof *v)) { *out = &S->e[h]; return VP_OK; }
        h = (h + 1) & (S->cap - 1);
    }
    memset(S->e[h].v, 0, sizeof S->e[h].v);
    memcpy(S->e[h].v, v, (size_t)(S->k + 1) * sizeof *v);
    S->e[h].count = 0;
    S->used++;
    *out = &S->e[h];
    return VP_OK;
}

/* ---- the object ---- */
struct vp_tdc {
    size_t n;
    int d, k;
    vp_tdc_params_t prm;
    double *orig, *pts, *w, *basis, *nn;
    double *radius;               /* of star(p): no point farther from p can change it */
    double w_max;                 /* bound on every weight (certification) */
    double shift_max;             /* bound on any point's distance from where it was given */
    double need_max;              /* an upper bound of radius[] over the certified stars */
    int given_tangents;           /* the caller's tangent spaces, no PCA */
    uint32_t **star;
    uint32_t *star_n;
    uint32_t **nb_id;             /* per point: its nearest points by given position, cached */
    double **nb_d2;
    uint32_t *nb_n;
    unsigned char *uncert;
    kd_tree_t kd;
    sx_table_t sx;
    size_t inconsistent, simplices;
    vp_tdc_stats_t st;
    /* scratch of one star */
    double *cv, *cv2;              /* cell vertices (k coordinates) */
    int32_t *cl, *cl2;             /* their labels (k each: the point whose bisector, or < 0: the box) */
};

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int vp_tdc_create(vp_tdc_t **out, const double *pts, size_t n, int d, const vp_tdc_params_t *prm,
                  char *err, size_t errlen)
{
    vp_tdc_t *t;
    size_t i;
    int k;
    if (!out || !pts || !prm) { vp_seterr(err, errlen, "no points"); return VP_EINVAL; }
    k = prm->k;
    if (k < 1 || k > VP_TDC_KMAX) { vp_seterr(err, errlen, "intrinsic dimension %d: must be 1..%d", k, VP_TDC_KMAX); return VP_EINVAL; }
    if (d <= k || d > VP_TDC_DMAX) {
        vp_seterr(err, errlen, "ambient dimension %d: must be above k = %d and at most %d", d, k, VP_TDC_DMAX);
        return VP_EINVAL;
    }
    if (n <= (size_t)k + 1 || n >= NONE / 2) { vp_seterr(err, errlen, "%zu points: need more than k+1 = %d", n, k + 1); return VP_EINVAL; }
    for (i = 0; i < n * (size_t)d; i++)
        if (!isfinite(pts[i])) { vp_seterr(err, errlen, "point %zu: coordinate %zu is not finite", i / (size_t)d, i % (size_t)d); return VP_EINVAL; }
    t = calloc(1, sizeof *t);
    if (!t) return VP_ENOMEM;
    t->n = n; t->d = d; t->k = k; t->prm = *prm;
    if (!t->prm.pca_neighbours) t->prm.pca_neighbours = k == 1 ? 8 : k == 2 ? 25 : 60;
    if (!t->prm.max_neighbours) t->prm.max_neighbours = 1024;
    if (!(t->prm.perturb_rel > 0)) t->prm.perturb_rel = 0.25;
    if (!t->prm.max_rounds) t->prm.max_rounds = 1000;
    if (!(t->prm.time_limit > 0)) t->prm.time_limit = 120;
    t->prm.tangents = NULL;
    t->orig = malloc(n * d * sizeof *t->orig);
    t->pts = malloc(n * d * sizeof *t->pts);
    t->w = calloc(n, sizeof *t->w);
    t->basis = malloc(n * (size_t)k * d * sizeof *t->basis);
    t->nn = malloc(n * sizeof *t->nn);
    t->radius = calloc(n, sizeof *t->radius);
    t->star = calloc(n, sizeof *t->star);
    t->star_n = calloc(n, sizeof *t->star_n);
    t->uncert = calloc(n, 1);
    t->nb_id = calloc(n, sizeof *t->nb_id);
    t->nb_d2 = calloc(n, sizeof *t->nb_d2);
    t->nb_n = calloc(n, sizeof *t->nb_n);
    t->cv = malloc((size_t)CELL_VMAX * k * sizeof *t->cv);
    t->cv2 = malloc((size_t)CELL_VMAX * k * sizeof *t->cv2);
    t->cl = malloc((size_t)CELL_VMAX * k * sizeof *t->cl);
    t->cl2 = malloc((size_t)CELL_VMAX * k * sizeof *t->cl2);
    t->sx.k = k;
    if (!t->orig || !t->pts || !t->w || !t->basis || !t->nn || !t->radius || !t->star || !t->star_n || !t->uncert || !t->nb_id || !t->nb_d2 || !t->nb_n
        || !t->cv || !t->cv2 || !t->cl || !t->cl2) {
        vp_tdc_free(t);
        return VP_ENOMEM;
    }
    memcpy(t->orig, pts, n * d * sizeof *pts);
    memcpy(t->pts, pts, n * d * sizeof *pts);
    if (prm->tangents) memcpy(t->basis, prm->tangents, n * (size_t)k * d * sizeof *t->basis);
    t->given_tangents = prm->tangents != NULL;
    t->prm.weights = NULL;
    if (prm->weights)
        for (i = 0; i < n; i++) {
            if (!isfinite(prm->weights[i]) || prm->weights[i] < 0) {
                vp_seterr(err, errlen, "point %zu: weight %g: must be finite and >= 0", i, prm->weights[i]);
                vp_tdc_free(t);
                return VP_EINVAL;
            }
            t->w[i] = prm->weights[i];
            if (t->w[i] > t->w_max) t->w_max = t->w[i];
        }
    *out = t;
    return VP_OK;
}

void vp_tdc_free(vp_tdc_t *t)
{
    size_t i;
    if (!t) return;
    if (t->star) for (i = 0; i < t->n; i++) free(t->star[i]);
    if (t->nb_id) for (i = 0; i < t->n; i++) free(t->nb_id[i]);
    if (t->nb_d2) for (i = 0; i < t->n; i++) free(t->nb_d2[i]);
    free(t->nb_id); free(t->nb_d2); free(t->nb_n);
    free(t->orig); free(t->pts); free(t->w); free(t->basis); free(t->nn); free(t->radius);
    free(t->star); free(t->star_n); free(t->uncert);
    free(t->cv); free(t->cv2); free(t->cl); free(t->cl2);
    kd_free(&t->kd);
    free(t->sx.e);
    free(t);
}

/* ---- tangent spaces: local PCA, eigenvectors by cyclic Jacobi rotations ---- */
static void jacobi_eigen(double *A, int d, double *V, double *ev)
{
    int i, j, r, sweep;
    for (i = 0; i < d; i++) for (j = 0; j < d; j++) V[i * d + j] = i == j;
    for (sweep = 0; sweep < 60; sweep++) {
        double off = 0, tot = 0;
        for (i = 0; i < d; i++) for (j = 0; j < d; j++) { tot += A[i * d + j] * A[i * d + j]; if (i != j) off += A[i * d + j] * A[i * d + j]; }
        if (off <= 1e-30 * tot || off == 0) break;
        for (i = 0; i < d - 1; i++)
            for (j = i + 1; j < d; j++) {
                double apq = A[i * d + j], theta, tn, c, s;
                if (fabs(apq) < 1e-300) continue;
                theta = (A[j * d + j] - A[i * d + i]) / (2 * apq);
                tn = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                c = 1 / sqrt(tn * tn + 1); s = tn * c;
                for (r = 0; r < d; r++) {   /* A <- A J (columns i, j) */
                    double ari = A[r * d + i], arj = A[r * d + j];
                    A[r * d + i] = c * ari - s * arj;
                    A[r * d + j] = s * ari + c * arj;
                }
                for (r = 0; r < d; r++) {   /* A <- J^T A (rows i, j) */
                    double air = A[i * d + r], ajr = A[j * d + r];
                    A[i * d + r] = c * air - s * ajr;
                    A[j * d + r] = s * air + c * ajr;
                }
                for (r = 0; r < d; r++) {   /* V <- V J */
                    double vri = V[r * d + i], vrj = V[r * d + j];
                    V[r * d + i] = c * vri - s * vrj;
                    V[r * d + j] = s * vri + c * vrj;
                }
            }
    }
    for (i = 0; i < d; i++) ev[i] = A[i * d + i];
}

static void tangent_pca(vp_tdc_t *t, size_t p, const uint32_t *id, size_t m)
{
    int d = t->d, k = t->k, a, b, j;
    double mean[VP_TDC_DMAX] = { 0 }, C[VP_TDC_DMAX * VP_TDC_DMAX], V[VP_TDC_DMAX * VP_TDC_DMAX], ev[VP_TDC_DMAX];
    unsigned char used[VP_TDC_DMAX] = { 0 };
    size_t i;
    for (i = 0; i < m; i++) for (a = 0; a < d; a++) mean[a] += t->orig[(size_t)id[i] * d + a] / (double)m;
    memset(C, 0, sizeof C);
    for (i = 0; i < m; i++) {
        const double *q = t->orig + (size_t)id[i] * d;
        for (a = 0; a < d; a++) for (b = a; b < d; b++) C[a * d + b] += (q[a] - mean[a]) * (q[b] - mean[b]);
    }
    for (a = 0; a < d; a++) for (b = 0; b < a; b++) C[a * d + b] = C[b * d + a];
    jacobi_eigen(C, d, V, ev);
    for (j = 0; j < k; j++) {   /* the k largest eigenvalues, their eigenvectors (columns of V) */
        int best = -1;
        for (a = 0; a < d; a++) if (!used[a] && (best < 0 || ev[a] > ev[best])) best = a;
        used[best] = 1;
        for (a = 0; a < d; a++) t->basis[(p * k + j) * d + a] = V[a * d + best];
    }
}

/* ---- one star: p's cell in the power diagram restricted to T_p ---- */

/* Clips the cell (nv vertices) by a.t <= b, labelled lab. Returns the new vertex count, or -1
 * when the cell would exceed CELL_VMAX. General position: a vertex on the plane is kept. */
static int clip_cell(vp_tdc_t *t, int nv, const double *a, double b, int32_t lab)
{
    int k = t->k, i, j, c, m = 0, out = 0;
    double f[CELL_VMAX];
    for (i = 0; i < nv; i++) {
        double s = -b;
        for (c = 0; c < k; c++) s += a[c] * t->cv[i * k + c];
        f[i] = s;
        out += s > 0;
    }
    if (!out) return nv;
    if (out == nv) return 0;
    for (i = 0; i < nv; i++) {    /* kept vertices, then the new ones on kept-removed edges */
        if (f[i] > 0) continue;
        if (m >= CELL_VMAX) return -1;
        memcpy(t->cv2 + m * k, t->cv + i * k, k * sizeof *t->cv);
        memcpy(t->cl2 + m * k, t->cl + i * k, k * sizeof *t->cl);
        m++;
    }
    for (i = 0; i < nv; i++) {
        if (f[i] > 0) continue;
        for (j = 0; j < nv; j++) {
            int common = 0, x, y;
            int32_t shared[VP_TDC_KMAX];
            double s;
            if (f[j] <= 0) continue;
            for (x = 0; x < k; x++)
                for (y = 0; y < k; y++)
                    if (t->cl[i * k + x] == t->cl[j * k + y]) { if (common < VP_TDC_KMAX) shared[common] = t->cl[i * k + x]; common++; }
            if (common != k - 1) continue;
            if (m >= CELL_VMAX) return -1;
            s = f[i] / (f[i] - f[j]);
            for (c = 0; c < k; c++) t->cv2[m * k + c] = t->cv[i * k + c] + s * (t->cv[j * k + c] - t->cv[i * k + c]);
            for (c = 0; c < k - 1; c++) t->cl2[m * k + c] = shared[c];
            t->cl2[m * k + k - 1] = lab;
            m++;
        }
    }
    {   /* swap buffers */
        double *tv = t->cv; int32_t *tl = t->cl;
        t->cv = t->cv2; t->cv2 = tv;
        t->cl = t->cl2; t->cl2 = tl;
    }
    return m;
}

static void sort_ids(uint32_t *v, int n)
{
    int i, j;
    for (i = 1; i < n; i++)
        for (j = i; j > 0 && v[j - 1] > v[j]; j--) { uint32_t x = v[j]; v[j] = v[j - 1]; v[j - 1] = x; }
}

static int sx_adjust(vp_tdc_t *t, const uint32_t *v, int delta)
{
    sx_entry_t *e;
    uint32_t full = (uint32_t)t->k + 1, before;
    VP_TRY(sx_find(&t->sx, v, &e));
    before = e->count;
    e->count = (uint32_t)((int)e->count + delta);
    t->inconsistent += (e->count > 0 && e->count < full) - (before > 0 && before < full);
    t->simplices += (e->count > 0) - (before > 0);
    return VP_OK;
}

/* The K nearest points to p by given position, nearest first: from p's cache, filled by the
 * k-d tree when it holds fewer (given positions never change). */
static int neighbours(vp_tdc_t *t, size_t p, size_t K, const uint32_t **id, const double **d2, size_t *got)
{
    if (t->nb_n[p] < K && t->nb_n[p] < t->n) {
        uint32_t *ni = realloc(t->nb_id[p], K * sizeof *ni);
        double *nd;
        if (!ni) return VP_ENOMEM;
        t->nb_id[p] = ni;
        nd = realloc(t->nb_d2[p], K * sizeof *nd);
        if (!nd) return VP_ENOMEM;
        t->nb_d2[p] = nd;
        t->nb_n[p] = (uint32_t)kd_knn(&t->kd, t->orig + p * t->d, K, nd, ni);
    }
    *id = t->nb_id[p];
    *d2 = t->nb_d2[p];
    *got = t->nb_n[p] < K ? t->nb_n[p] : K;
    return VP_OK;
}

/* The largest need(t) = |t| + sqrt(|t|^2 - w_p + w_max) over the cell's vertices: no point
 * farther from p than that can cut the cell. INFINITY while a vertex is one of the box's. */
static double cell_need(const vp_tdc_t *t, size_t p, int nv)
{
    int i, c, k = t->k;
    double need = 0;
    for (i = 0; i < nv; i++) {
        double r2 = 0, pw, nd;
        for (c = 0; c < k; c++) {
            r2 += t->cv[i * k + c] * t->cv[i * k + c];
            if (t->cl[i * k + c] < 0) return INFINITY;
        }
        pw = r2 - t->w[p] + t->w_max;
        nd = sqrt(r2) + sqrt(pw > 0 ? pw : 0);
        if (nd > need) need = nd;
    }
    return need;
}

/* Computes star(p) again and updates the simplex counts. */
static int star_compute(vp_tdc_t *t, size_t p)
{
    int k = t->k, d = t->d, c, nv = 0;
    const double *pp = t->pts + p * d, *B = t->basis + p * (size_t)k * d;
    size_t K = t->nb_n[p] ? t->nb_n[p] : (size_t)(k == 1 ? 8 : k == 2 ? 16 : 40);
    size_t cap = (size_t)t->prm.max_neighbours + 1, got = 0, i, ns = 0;
    double shift_p = sqrt(dist2(pp, t->orig + p * d, d)), need = INFINITY;
    int certified = 0;
    uint32_t *st;
    if (cap > t->n) cap = t->n;
    if (K > cap) K = cap;
    for (;;) {
        const uint32_t *nid;
        const double *nd2;
        double D, L;
        int all_in;
        VP_TRY(neighbours(t, p, K, &nid, &nd2, &got));
        all_in = got >= t->n;
        /* every point outside the set is at least D from p now (the points were given at
         * least sqrt(nd2[got-1]) apart and each moved at most shift_max since) */
        D = all_in ? INFINITY : sqrt(nd2[got - 1]) - shift_p - t->shift_max;
        /* start from a box of half width D (a vertex outside it could not be certified anyway) */
        L = all_in || D <= 0 ? 1e6 * (sqrt(nd2[got - 1]) + 1) : D;
        nv = 1 << k;
        for (i = 0; i < (size_t)nv; i++)
            for (c = 0; c < k; c++) {
                t->cv[i * k + c] = ((i >> c) & 1) ? L : -L;
                t->cl[i * k + c] = -1 - (int32_t)(2 * c + ((i >> c) & 1));
            }
        certified = 0;
        for (i = 0; i < got && nv > 0; i++) {
            const double *q = t->pts + (size_t)nid[i] * d;
            double a[VP_TDC_KMAX], b = 0, diff[VP_TDC_DMAX];
            int j;
            if (i >= 8 && !(i & 3)) {   /* the rest are too far to cut the cell: done */
                need = cell_need(t, p, nv);
                if (need < sqrt(nd2[i]) - shift_p - t->shift_max) { certified = 1; break; }
            }
            if (nid[i] == p) continue;
            for (j = 0; j < d; j++) { diff[j] = q[j] - pp[j]; b += diff[j] * diff[j]; }
            for (c = 0; c < k; c++) {
                double s = 0;
                for (j = 0; j < d; j++) s += B[c * d + j] * diff[j];
                a[c] = 2 * s;
            }
            b += t->w[p] - t->w[nid[i]];
            nv = clip_cell(t, nv, a, b, (int32_t)nid[i]);
            if (nv < 0) return VP_EDEGEN;
        }
        if (!certified) {
            need = cell_need(t, p, nv);
            certified = nv > 0 && (all_in ? isfinite(need) : need < D);
        }
        if (got > t->st.max_neighbours_used) t->st.max_neighbours_used = got;
        if (certified || K >= cap) break;
        K = 2 * K < cap ? 2 * K : cap;
    }
    t->radius[p] = certified ? need : INFINITY;
    if (certified && need > t->need_max) t->need_max = need;
    /* drop the old star's counts, store and count the new one */
    for (i = 0; i < t->star_n[p]; i++) VP_TRY(sx_adjust(t, t->star[p] + i * (k + 1), -1));
    st = realloc(t->star[p], ((size_t)nv + 1) * (k + 1) * sizeof *st);
    if (!st) return VP_ENOMEM;
    t->star[p] = st;
    for (i = 0; i < (size_t)nv; i++) {
        uint32_t *s = st + ns * (k + 1);
        int box = 0;
        s[0] = (uint32_t)p;
        for (c = 0; c < k; c++) {
            if (t->cl[i * k + c] < 0) box = 1;
            else s[c + 1] = (uint32_t)t->cl[i * k + c];
        }
        if (box) continue;
        sort_ids(s, k + 1);
        ns++;
    }
    t->star_n[p] = (uint32_t)ns;
    for (i = 0; i < ns; i++) VP_TRY(sx_adjust(t, st + i * (k + 1), +1));
    t->uncert[p] = !certified;
    t->st.star_builds++;
    return VP_OK;
}

int vp_tdc_build(vp_tdc_t *t)
{
    size_t p, i, m = (size_t)t->prm.pca_neighbours;
    double t0 = now_seconds(), t1;
    if (!t) return VP_EINVAL;
    if (m > t->n) m = t->n;
    if (m < 2) m = 2;
    VP_TRY(kd_build(&t->kd, t->orig, t->n, t->d));
    {
        double *d2 = malloc(m * sizeof *d2);
        uint32_t *id = malloc(m * sizeof *id);
        if (!d2 || !id) { free(d2); free(id); return VP_ENOMEM; }
        for (p = 0; p < t->n; p++) {
            size_t got = kd_knn(&t->kd, t->orig + p * t->d, m, d2, id);
            t->nn[p] = 0;
            for (i = 0; i < got; i++) if (d2[i] > 0) { t->nn[p] = sqrt(d2[i]); break; }
            if (!t->given_tangents) tangent_pca(t, p, id, got);
        }
        free(d2); free(id);
    }
    t1 = now_seconds();
    t->st.seconds_tangents = t1 - t0;
    if (t->prm.fix_mode == VP_TDC_FIX_WEIGHT)
        for (p = 0; p < t->n; p++) {
            double wb = t->prm.perturb_rel * t->nn[p];
            if (wb * wb > t->w_max) t->w_max = wb * wb;
        }
    for (p = 0; p < t->n; p++) VP_TRY(star_compute(t, p));
    t->st.inconsistent_before = t->inconsistent;
    t->st.seconds_stars = now_seconds() - t1;
    return VP_OK;
}

static uint32_t sx_count(const sx_table_t *S, const uint32_t *v)
{
    size_t h;
    if (!S->cap) return 0;
    h = (size_t)sx_hash(v, S->k) & (S->cap - 1);
    while (S->e[h].v[0] != NONE) {
        if (!memcmp(S->e[h].v, v, (size_t)(S->k + 1) * sizeof *v)) return S->e[h].count;
        h = (h + 1) & (S->cap - 1);
    }
    return 0;
}

/* A random point of the unit ball of R^k. */
static void unit_ball(vp_rng_t *r, int k, double *u)
{
    double s = 0, rad;
    int c;
    do {
        s = 0;
        for (c = 0; c < k; c++) { u[c] = vp_rng_normal(r); s += u[c] * u[c]; }
    } while (s < 1e-24);
    rad = pow(vp_rng_uniform(r), 1.0 / k) / sqrt(s);
    for (c = 0; c < k; c++) u[c] *= rad;
}

/* Stars whose certified ball holds `at` (a position of m): q with |q - at| < radius[q]. The
 * tree holds given positions, each point within shift_max of its own. */
static int stars_near(vp_tdc_t *t, size_t m, const double *at, unsigned char *mark, idlist_t *near, idlist_t *redo)
{
    size_t j;
    int d = t->d;
    double r = t->need_max + 2 * t->shift_max;
    near->n = 0;
    VP_TRY(kd_ball_rec(&t->kd, 0, t->orig + m * d, r * r, near));
    for (j = 0; j < near->n; j++) {
        uint32_t q = near->v[j];
        double rq = t->radius[q];
        if (mark[q]) continue;
        if (!isfinite(rq) || dist2(t->pts + (size_t)q * d, at, d) < rq * rq) {
            mark[q] = 1;
            VP_TRY(idlist_push(redo, q));
        }
    }
    return VP_OK;
}

static int star_inconsistent(const vp_tdc_t *t, size_t p)
{
    size_t i, full = (size_t)t->k + 1;
    for (i = 0; i < t->star_n[p]; i++)
        if (sx_count(&t->sx, t->star[p] + i * full) < full) return 1;
    return 0;
}

/* One trial: p moves to a random spot of its tangent space within the bound of where it was
 * given (or takes a random weight); the stars it can change are computed again; kept when the
 * number of inconsistent simplices did not grow, else undone. 1 kept, 0 undone, or < 0. */
static int try_move(vp_tdc_t *t, size_t p, uint64_t trial, unsigned char *mark, idlist_t *near, idlist_t *redo)
{
    int k = t->k, d = t->d, c, a;
    double oldpos[VP_TDC_DMAX], oldw = t->w[p], u[VP_TDC_KMAX], bound = t->prm.perturb_rel * t->nn[p];
    size_t before = t->inconsistent, i;
    vp_rng_t r;
    memcpy(oldpos, t->pts + p * d, d * sizeof *oldpos);
    vp_rng_seed(&r, t->prm.seed ^ vp_mix64(p + 1) ^ vp_mix64(~trial));
    if (t->prm.fix_mode == VP_TDC_FIX_WEIGHT) {
        t->w[p] = vp_rng_uniform(&r) * bound * bound;
    } else {
        unit_ball(&r, k, u);
        for (c = 0; c < d; c++) {
            double s = t->orig[p * d + c];
            for (a = 0; a < k; a++) s += bound * u[a] * t->basis[(p * k + a) * d + c];
            t->pts[p * d + c] = s;
        }
        if (bound > t->shift_max) t->shift_max = bound;
    }
    redo->n = 0;
    mark[p] = 1;
    VP_TRY(idlist_push(redo, (uint32_t)p));
    VP_TRY(stars_near(t, p, oldpos, mark, near, redo));
    VP_TRY(stars_near(t, p, t->pts + p * d, mark, near, redo));
    for (i = 0; i < redo->n; i++) mark[redo->v[i]] = 0;
    for (i = 0; i < redo->n; i++) VP_TRY(star_compute(t, redo->v[i]));
    t->st.moves++;
    if (t->inconsistent <= before) return 1;
    memcpy(t->pts + p * d, oldpos, d * sizeof *oldpos);
    t->w[p] = oldw;
    for (i = 0; i < redo->n; i++) VP_TRY(star_compute(t, redo->v[i]));
    return 0;
}

int vp_tdc_fix(vp_tdc_t *t)
{
    double t0 = now_seconds();
    unsigned char *mark;
    idlist_t todo = { 0, 0, 0 }, near = { 0, 0, 0 }, redo = { 0, 0, 0 };
    uint64_t trial = 0;
    int st = VP_OK;
    if (!t) return VP_EINVAL;
    mark = calloc(t->n, 1);
    if (!mark) return VP_ENOMEM;
    /* sweeps: every point whose star holds an inconsistent simplex, in turn */
    while (t->inconsistent && t->prm.max_rounds > 0 && t->st.rounds < (size_t)t->prm.max_rounds
           && now_seconds() - t0 < t->prm.time_limit) {
        size_t p, i;
        todo.n = 0;
        for (p = 0; p < t->n; p++)
            if (star_inconsistent(t, p) && (st = idlist_push(&todo, (uint32_t)p)) < 0) break;
        for (i = 0; st >= 0 && i < todo.n && t->inconsistent; i++) {
            if (!star_inconsistent(t, todo.v[i])) continue;
            st = try_move(t, todo.v[i], trial++, mark, &near, &redo);
            if ((i & 63) == 63 && now_seconds() - t0 >= t->prm.time_limit) break;
        }
        if (st < 0) break;
        t->st.rounds++;
    }
    free(mark); free(todo.v); free(near.v); free(redo.v);
    t->st.seconds_fix += now_seconds() - t0;
    return st < 0 ? st : VP_OK;
}

void vp_tdc_get_stats(const vp_tdc_t *t, vp_tdc_stats_t *s)
{
    size_t p;
    *s = t->st;
    s->inconsistent = t->inconsistent;
    s->simplices = t->simplices;
    s->uncertified = 0;
    s->max_shift = s->max_shift_rel = s->nn_mean = 0;
    for (p = 0; p < t->n; p++) {
        s->nn_mean += t->nn[p] / (double)t->n;
        double sh = sqrt(dist2(t->pts + p * t->d, t->orig + p * t->d, t->d));
        s->uncertified += t->uncert[p];
        if (sh > s->max_shift) s->max_shift = sh;
        if (t->nn[p] > 0 && sh / t->nn[p] > s->max_shift_rel) s->max_shift_rel = sh / t->nn[p];
    }
}

const uint32_t *vp_tdc_star(const vp_tdc_t *t, size_t p, size_t *count)
{
    if (!t || p >= t->n) { if (count) *count = 0; return NULL; }
    if (count) *count = t->star_n[p];
    return t->star[p];
}

int vp_tdc_simplices(const vp_tdc_t *t, uint32_t **simp, size_t *count)
{
    size_t i, m = 0, full = (size_t)t->k + 1;
    uint32_t *out = malloc((t->simplices + 1) * full * sizeof *out);
    if (!out) return VP_ENOMEM;
    for (i = 0; i < t->sx.cap; i++)
        if (t->sx.e[i].v[0] != NONE && t->sx.e[i].count > 0) {
            memcpy(out + m * full, t->sx.e[i].v, full * sizeof *out);
            m++;
        }
    *simp = out;
    *count = m;
    return VP_OK;
}

const double *vp_tdc_points(const vp_tdc_t *t) { return t->pts; }
const double *vp_tdc_tangent(const vp_tdc_t *t, size_t p) { return t->basis + p * (size_t)t->k * t->d; }
