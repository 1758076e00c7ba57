/* The tangential Delaunay complex (host/vp_tdc) and the manifold check (mesh/vp_mfcheck):
 * the check on hand-made complexes it must accept or reject; stars against a brute-force
 * computation of the same restricted power diagram; tangent spaces; the generators; a small
 * reconstruction end to end. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_manifoldgen.h"
#include "vp_mfcheck.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_tdc.h"
#include "../vp_test.h"

/* ---- hand-made complexes ---- */
static const uint32_t octa[8][3] = {
    { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 }, { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 }
};

/* n x n grid of squares, two triangles each; the rows wrap with x -> -x for a Klein bottle. */
static size_t grid(uint32_t *t, int n, int klein)
{
    size_t m = 0;
    int x, y, c;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            uint32_t v[4];
            int cx[4] = { x, x + 1, x, x + 1 }, cy[4] = { y, y, y + 1, y + 1 };
            for (c = 0; c < 4; c++) {
                int px = cx[c] % n, py = cy[c];
                if (py == n) { py = 0; if (klein) px = (n - px) % n; }
                v[c] = (uint32_t)(py * n + px);
            }
            t[m++] = v[0]; t[m++] = v[1]; t[m++] = v[3];
            t[m++] = v[0]; t[m++] = v[3]; t[m++] = v[2];
        }
    return m / 3;
}

/* Every edge of an oriented closed surface appears once in each direction. */
static int oriented_ok(const uint32_t *t, size_t nt)
{
    size_t i, j;
    int a, b;
    for (i = 0; i < nt; i++)
        for (a = 0; a < 3; a++) {
            uint32_t u = t[3 * i + a], v = t[3 * i + (a + 1) % 3];
            int back = 0;
            for (j = 0; j < nt; j++)
                for (b = 0; b < 3; b++)
                    if (t[3 * j + b] == v && t[3 * j + (b + 1) % 3] == u) back++;
            if (back != 1) return 0;
        }
    return 1;
}

static void test_mfcheck(void)
{
    vp_mfcheck_t r;
    uint32_t t[3 * 2 * 36 * 2], o[3 * 2 * 36 * 2];
    size_t nt;
    uint32_t cyc[2 * 5], eight[2 * 6], s3[5 * 4], two[2 * 5 * 4];
    int i, j, c;

    CHECK(vp_mfcheck_run(&octa[0][0], 8, 2, 6, &r, o) == VP_OK);
    CHECK(r.manifold == 1 && r.orientable == 1 && r.euler == 2 && r.components == 1);
    CHECK(r.faces[0] == 6 && r.faces[1] == 12 && r.faces[2] == 8);
    CHECK(oriented_ok(o, 8));
    /* must fail: a missing triangle */
    CHECK(vp_mfcheck_run(&octa[0][0], 7, 2, 6, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.bad_facets == 3 && r.euler == 1);
    /* must fail: two octahedra pinched at a vertex */
    memcpy(t, octa, sizeof octa);
    for (i = 0; i < 24; i++) t[24 + i] = octa[i / 3][i % 3] == 0 ? 0 : octa[i / 3][i % 3] + 5;
    CHECK(vp_mfcheck_run(t, 16, 2, 11, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.bad_facets == 0 && r.bad_links == 1 && r.euler == 3);
    /* must fail: a triangle given twice */
    memcpy(t, octa, sizeof octa);
    t[24] = 4; t[25] = 2; t[26] = 0;
    CHECK(vp_mfcheck_run(t, 9, 2, 6, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.duplicates == 1);
    /* torus, Klein bottle (must be found non-orientable), Moebius strip (open) */
    nt = grid(t, 6, 0);
    CHECK(vp_mfcheck_run(t, nt, 2, 36, &r, o) == VP_OK);
    CHECK(r.manifold == 1 && r.orientable == 1 && r.euler == 0 && oriented_ok(o, nt));
    nt = grid(t, 6, 1);
    CHECK(vp_mfcheck_run(t, nt, 2, 36, &r, o) == VP_OK);
    CHECK(r.manifold == 1 && r.orientable == 0 && r.euler == 0);
    CHECK(!oriented_ok(o, nt));
    nt = grid(t, 6, 1) - 2 * 6;   /* one row of squares less: a Moebius strip, open */
    CHECK(vp_mfcheck_run(t, nt, 2, 36, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.bad_facets > 0 && r.orientable == -1);
    /* k = 1: a cycle; a figure eight must fail */
    for (i = 0; i < 5; i++) { cyc[2 * i] = (uint32_t)i; cyc[2 * i + 1] = (uint32_t)((i + 1) % 5); }
    CHECK(vp_mfcheck_run(cyc, 5, 1, 5, &r, NULL) == VP_OK);
    CHECK(r.manifold == 1 && r.euler == 0 && r.orientable == 1);
    {
        static const uint32_t e8[12] = { 0, 1, 1, 2, 2, 0, 0, 3, 3, 4, 4, 0 };
        memcpy(eight, e8, sizeof e8);
    }
    CHECK(vp_mfcheck_run(eight, 6, 1, 5, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.bad_facets == 1);
    /* k = 3: the boundary of a 4-simplex (a 3-sphere); one tet less; two pinched at a vertex */
    for (i = 0; i < 5; i++)
        for (j = 0, c = 0; j < 5; j++) if (j != i) s3[4 * i + c++] = (uint32_t)j;
    CHECK(vp_mfcheck_run(s3, 5, 3, 5, &r, NULL) == VP_OK);
    CHECK(r.manifold == 1 && r.euler == 0 && r.orientable == 1 && r.faces[1] == 10 && r.faces[2] == 10);
    CHECK(vp_mfcheck_run(s3, 4, 3, 5, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.bad_facets == 4);
    memcpy(two, s3, sizeof s3);
    for (i = 0; i < 20; i++) two[20 + i] = s3[i] == 0 ? 0 : s3[i] + 4;
    CHECK(vp_mfcheck_run(two, 10, 3, 9, &r, NULL) == VP_OK);
    CHECK(r.manifold == 0 && r.bad_facets == 0 && r.bad_links == 1);
    /* bad input */
    CHECK(vp_mfcheck_run(s3, 5, 3, 4, &r, NULL) == VP_EINVAL);
    CHECK(vp_mfcheck_run(s3, 5, 4, 5, &r, NULL) == VP_EINVAL);
}

/* ---- stars against brute force ---- */

/* Solves the k x k system A x = b (Gaussian elimination with pivoting); 0 when singular. */
static int solve(double A[3][3], double *b, int k, double *x)
{
    int i, j, r;
    for (i = 0; i < k; i++) {
        int piv = i;
        for (r = i + 1; r < k; r++) if (fabs(A[r][i]) > fabs(A[piv][i])) piv = r;
        if (fabs(A[piv][i]) < 1e-12) return 0;
        if (piv != i) {
            double tb = b[i];
            for (j = 0; j < k; j++) { double tt = A[i][j]; A[i][j] = A[piv][j]; A[piv][j] = tt; }
            b[i] = b[piv]; b[piv] = tb;
        }
        for (r = i + 1; r < k; r++) {
            double f = A[r][i] / A[i][i];
            for (j = i; j < k; j++) A[r][j] -= f * A[i][j];
            b[r] -= f * b[i];
        }
    }
    for (i = k - 1; i >= 0; i--) {
        double s = b[i];
        for (j = i + 1; j < k; j++) s -= A[i][j] * x[j];
        x[i] = s / A[i][i];
    }
    return 1;
}

static int cmp_simplex(const void *a, const void *b) { return memcmp(a, b, 4 * sizeof(uint32_t)); }

/* Every k-subset {q} of the other points whose power-equidistant point t of T_p is nearer (in
 * power, weights w) to p than every other point: the simplices of star(p), as 4-slot rows (unused slots
 * UINT32_MAX, sorted). O(n^(k+1)). */
static size_t brute_star(const double *pts, const double *w, size_t n, int d, int k, const double *basis, size_t p,
                         uint32_t (*out)[4], size_t cap)
{
    size_t m = 0, q[3], r;
    const double *pp = pts + p * d;
    double *y = malloc(n * 3 * sizeof *y), *h = malloc(n * sizeof *h);
    for (r = 0; r < n; r++) {
        int c, j;
        double len2 = 0, proj2 = 0;
        for (j = 0; j < d; j++) len2 += (pts[r * d + j] - pp[j]) * (pts[r * d + j] - pp[j]);
        for (c = 0; c < k; c++) {
            double s = 0;
            for (j = 0; j < d; j++) s += basis[c * d + j] * (pts[r * d + j] - pp[j]);
            y[r * 3 + c] = s;
            proj2 += s * s;
        }
        h[r] = len2 - proj2 - w[r] + w[p];   /* power: |x - r|^2 - w_r against |x - p|^2 - w_p */
    }
    for (q[0] = 0; q[0] < n; q[0]++)
        for (q[1] = k > 1 ? q[0] + 1 : 0; q[1] < (k > 1 ? n : 1); q[1]++)
            for (q[2] = k > 2 ? q[1] + 1 : 0; q[2] < (k > 2 ? n : 1); q[2]++) {
                double A[3][3], b[3], t[3];
                int i, c, ok = 1;
                for (i = 0; i < k; i++) if (q[i] == p) ok = 0;
                if (!ok) continue;
                /* |t|^2 - w_p = |t - y_q|^2 + |q - T_p|^2 - w_q  <=>  2 y_q . t = |y_q|^2 + h_q */
                for (i = 0; i < k; i++) {
                    b[i] = h[q[i]];
                    for (c = 0; c < k; c++) { A[i][c] = 2 * y[q[i] * 3 + c]; b[i] += y[q[i] * 3 + c] * y[q[i] * 3 + c]; }
                }
                if (!solve(A, b, k, t)) continue;
                for (r = 0; r < n && ok; r++) {
                    double lhs = 0, rhs = h[r];
                    if (r == p || r == q[0] || (k > 1 && r == q[1]) || (k > 2 && r == q[2])) continue;
                    for (c = 0; c < k; c++) { lhs += 2 * y[r * 3 + c] * t[c]; rhs += y[r * 3 + c] * y[r * 3 + c]; }
                    if (lhs > rhs) ok = 0;
                }
                if (!ok || m >= cap) continue;
                out[m][0] = (uint32_t)p;
                for (i = 0; i < k; i++) out[m][i + 1] = (uint32_t)q[i];
                for (i = k + 1; i < 4; i++) out[m][i] = UINT32_MAX;
                {   /* sort the k+1 ids */
                    int a2, b2;
                    for (a2 = 1; a2 <= k; a2++)
                        for (b2 = a2; b2 > 0 && out[m][b2 - 1] > out[m][b2]; b2--) {
                            uint32_t tt = out[m][b2]; out[m][b2] = out[m][b2 - 1]; out[m][b2 - 1] = tt;
                        }
                }
                m++;
            }
    free(y); free(h);
    qsort(out, m, sizeof out[0], cmp_simplex);
    return m;
}

/* Random orthonormal k-frame of R^d (Gram-Schmidt). */
static void random_frame(vp_rng_t *r, int k, int d, double *B)
{
    int a, b, j;
    for (a = 0; a < k; a++) {
        double s;
        for (;;) {
            for (j = 0; j < d; j++) B[a * d + j] = vp_rng_normal(r);
            for (b = 0; b < a; b++) {
                double dot = 0;
                for (j = 0; j < d; j++) dot += B[a * d + j] * B[b * d + j];
                for (j = 0; j < d; j++) B[a * d + j] -= dot * B[b * d + j];
            }
            s = 0;
            for (j = 0; j < d; j++) s += B[a * d + j] * B[a * d + j];
            if (s > 1e-6) break;
        }
        for (j = 0; j < d; j++) B[a * d + j] /= sqrt(s);
    }
}

/* The two sets equal: 1, else 0. */
static int same_sets(uint32_t (*a)[4], size_t na, uint32_t (*b)[4], size_t nb)
{
    return na == nb && !memcmp(a, b, na * sizeof a[0]);
}

static void test_stars(void)
{
    static const int dims[][3] = { { 1, 2, 30 }, { 1, 5, 30 }, { 2, 3, 60 }, { 2, 4, 60 }, { 3, 4, 40 }, { 3, 9, 40 } };
    size_t trial, compared = 0, mismatches = 0;
    uint32_t (*bs)[4] = malloc(20000 * sizeof *bs), (*ts)[4] = malloc(20000 * sizeof *ts);
    for (trial = 0; trial < 2 * sizeof dims / sizeof dims[0]; trial++) {
        int k = dims[trial / 2][0], d = dims[trial / 2][1], j;
        size_t n = (size_t)dims[trial / 2][2], p, i;
        vp_rng_t r;
        double *pts = malloc(n * d * sizeof *pts), *T = malloc(n * k * d * sizeof *T), *w = calloc(n, sizeof *w);
        vp_tdc_params_t prm;
        vp_tdc_t *t = NULL;
        char err[200];
        vp_rng_seed(&r, 77 + trial);
        for (i = 0; i < n * d; i++) pts[i] = vp_rng_uniform(&r);
        for (p = 0; p < n; p++) random_frame(&r, k, d, T + p * k * d);
        if (trial % 2) for (p = 0; p < n; p++) w[p] = 0.05 * vp_rng_uniform(&r);   /* weighted */
        memset(&prm, 0, sizeof prm);
        prm.k = k; prm.tangents = T; prm.max_rounds = -1;
        if (trial % 2) prm.weights = w;
        CHECK(vp_tdc_create(&t, pts, n, d, &prm, err, sizeof err) == VP_OK);
        CHECK(vp_tdc_build(t) == VP_OK);
        for (p = 0; p < n; p++) {
            size_t cnt, nb = brute_star(pts, w, n, d, k, T + p * k * d, p, bs, 20000);
            const uint32_t *s = vp_tdc_star(t, p, &cnt);
            for (i = 0; i < cnt; i++) {
                for (j = 0; j < 4; j++) ts[i][j] = j <= k ? s[i * (k + 1) + j] : UINT32_MAX;
            }
            qsort(ts, cnt, sizeof ts[0], cmp_simplex);
            compared++;
            if (!same_sets(bs, nb, ts, cnt)) {
                mismatches++;
                if (mismatches < 5) fprintf(stderr, "k=%d d=%d %s point %zu: star %zu simplices, brute force %zu\n", k, d,
                                            trial % 2 ? "weighted" : "unweighted", p, cnt, nb);
            }
            /* the comparison must see a star with one simplex less */
            if (p == 0 && cnt > 0) CHECK(!same_sets(bs, nb, ts, cnt - 1));
        }
        vp_tdc_free(t);
        free(pts); free(T); free(w);
    }
    CHECKF(mismatches == 0, "%zu of %zu stars differ from the brute-force restricted power diagram", mismatches, compared);
    free(bs); free(ts);
}

/* ---- tangent spaces, generators, a reconstruction ---- */
static void test_generators_and_tangents(void)
{
    size_t n = 2000, i;
    double *p = malloc(n * 10 * sizeof *p), worst = 0;
    vp_tdc_params_t prm;
    vp_tdc_t *t = NULL;
    char err[200];
    int j, a;
    CHECK(vp_manifold_sample("sphere", n, 3, 0, 0, p) == VP_OK);
    for (i = 0; i < n; i++) worst = fmax(worst, fabs(sqrt(p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1] + p[3 * i + 2] * p[3 * i + 2]) - 1));
    CHECK(worst < 1e-12);
    /* PCA tangent planes of the sphere: orthogonal to the radius */
    memset(&prm, 0, sizeof prm);
    prm.k = 2; prm.max_rounds = -1;
    CHECK(vp_tdc_create(&t, p, n, 3, &prm, err, sizeof err) == VP_OK);
    CHECK(vp_tdc_build(t) == VP_OK);
    worst = 0;
    {
        double sum = 0;
        for (i = 0; i < n; i++) {
            const double *B = vp_tdc_tangent(t, i);
            for (a = 0; a < 2; a++) {
                double off = fabs(B[3 * a] * p[3 * i] + B[3 * a + 1] * p[3 * i + 1] + B[3 * a + 2] * p[3 * i + 2]);
                worst = fmax(worst, off);
                sum += off;
            }
        }
        CHECKF(worst < 0.15 && sum / (2 * n) < 0.02, "sphere tangent planes off the radius by %g (mean %g)", worst, sum / (2 * n));
    }
    vp_tdc_free(t);
    /* SO(3): orthogonal with determinant 1 */
    CHECK(vp_manifold_sample("so3", n, 3, 0, 0, p) == VP_OK);
    worst = 0;
    for (i = 0; i < n; i++) {
        const double *R = p + 9 * i;
        int x, y;
        for (x = 0; x < 3; x++)
            for (y = 0; y < 3; y++) {
                double s = 0;
                for (j = 0; j < 3; j++) s += R[3 * x + j] * R[3 * y + j];
                worst = fmax(worst, fabs(s - (x == y)));
            }
        worst = fmax(worst, fabs(R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]) - 1));
    }
    CHECK(worst < 1e-12);
    /* Klein bottle: (sqrt(x^2+y^2) - 2)^2 + z^2 + w^2 = 1; Clifford torus: x^2+y^2 = z^2+w^2 = 1/2 */
    CHECK(vp_manifold_sample("klein", n, 3, 0, 0, p) == VP_OK);
    worst = 0;
    for (i = 0; i < n; i++) {
        const double *q = p + 4 * i;
        double rr = sqrt(q[0] * q[0] + q[1] * q[1]) - 2;
        worst = fmax(worst, fabs(rr * rr + q[2] * q[2] + q[3] * q[3] - 1));
    }
    CHECK(worst < 1e-12);
    CHECK(vp_manifold_sample("clifford", n, 3, 0, 0, p) == VP_OK);
    worst = 0;
    for (i = 0; i < n; i++) worst = fmax(worst, fabs(p[4 * i] * p[4 * i] + p[4 * i + 1] * p[4 * i + 1] - 0.5));
    CHECK(worst < 1e-12);
    /* noise moves points off; the same seed gives the same points */
    {
        double *q = malloc(n * 3 * sizeof *q);
        CHECK(vp_manifold_sample("torus", n, 9, 0.01, 1, p) == VP_OK);
        CHECK(vp_manifold_sample("torus", n, 9, 0.01, 1, q) == VP_OK);
        CHECK(!memcmp(p, q, n * 3 * sizeof *q));
        CHECK(vp_manifold_sample("torus", n, 10, 0.01, 1, q) == VP_OK);
        CHECK(memcmp(p, q, n * 3 * sizeof *q) != 0);
        free(q);
    }
    CHECK(vp_manifold_sample("nonesuch", n, 1, 0, 0, p) == VP_EINVAL);
    CHECK(vp_manifold_sample("torus", n, 1, -1, 0, p) == VP_EINVAL);
    free(p);
}

static void test_reconstruction(void)
{
    static const char *names[] = { "torus", "klein" };
    size_t n = 3000, ns[2] = { 0, 0 }, run, which;
    for (which = 0; which < 2; which++) {
        uint32_t *first = NULL;
        for (run = 0; run < 2; run++) {
            const vp_manifold_info_t *info = vp_manifold_find(names[which]);
            double *p = malloc(n * info->d * sizeof *p);
            vp_tdc_params_t prm;
            vp_tdc_t *t = NULL;
            vp_tdc_stats_t S;
            vp_mfcheck_t mc;
            uint32_t *simp = NULL;
            char err[200];
            vp_manifold_sample(names[which], n, 5, 0, 0, p);
            memset(&prm, 0, sizeof prm);
            prm.k = 2; prm.seed = 5;
            CHECK(vp_tdc_create(&t, p, n, info->d, &prm, err, sizeof err) == VP_OK);
            CHECK(vp_tdc_build(t) == VP_OK);
            CHECK(vp_tdc_fix(t) == VP_OK);
            vp_tdc_get_stats(t, &S);
            CHECK(S.inconsistent_before > 0 && S.inconsistent == 0);
            CHECK(S.max_shift_rel <= 0.25 + 1e-9);
            CHECK(vp_tdc_simplices(t, &simp, &ns[run]) == VP_OK);
            CHECK(vp_mfcheck_run(simp, ns[run], 2, n, &mc, NULL) == VP_OK);
            CHECK(mc.manifold == 1 && mc.euler == info->euler && mc.orientable == info->orientable);
            if (!run) first = simp;
            else {
                CHECK(ns[0] == ns[1] && !memcmp(first, simp, ns[0] * 3 * sizeof *simp));   /* deterministic */
                free(simp);
            }
            vp_tdc_free(t);
            free(p);
        }
        free(first);
    }
    {   /* bad input: a clear refusal */
        double bad[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, NAN };
        vp_tdc_params_t prm;
        vp_tdc_t *t = NULL;
        char err[200] = "";
        memset(&prm, 0, sizeof prm);
        prm.k = 2;
        CHECK(vp_tdc_create(&t, bad, 4, 3, &prm, err, sizeof err) == VP_EINVAL && strstr(err, "not finite"));
        prm.k = 3;
        CHECK(vp_tdc_create(&t, bad, 4, 3, &prm, err, sizeof err) == VP_EINVAL);
        {
            double w[5] = { 0, 0, 0, -1, 0 }, ok[15] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1 };
            prm.k = 2; prm.weights = w;
            CHECK(vp_tdc_create(&t, ok, 5, 3, &prm, err, sizeof err) == VP_EINVAL && strstr(err, "weight"));
        }
    }
}

int main(void)
{
    test_mfcheck();
    test_stars();
    test_generators_and_tangents();
    test_reconstruction();
    return vp_test_done("test_tdc (manifold check accepts/rejects, stars = brute force, tangents, generators, torus/klein fixed)");
}
