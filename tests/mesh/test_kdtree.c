/* vp_kdtree: k nearest points against brute force, on random points and on point sets with many
 * equal coordinates (a mesh's repeated vertices, a grid): 60,000 copies of one point took the
 * quickselect one element a pass (some 1e9 swaps) before the equal keys were gathered. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_kdtree.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_test.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* the k smallest squared distances from q, by brute force, ascending */
static void brute_knn(const double *p, size_t n, const double *q, size_t k, double *out)
{
    double *d = malloc(n * sizeof *d);
    size_t i;
    if (!d) return;
    for (i = 0; i < n; i++) {
        double dx = p[3 * i] - q[0], dy = p[3 * i + 1] - q[1], dz = p[3 * i + 2] - q[2];
        d[i] = dx * dx + dy * dy + dz * dz;
    }
    qsort(d, n, sizeof *d, cmp_double);
    memcpy(out, d, k * sizeof *d);
    free(d);
}

static void check_set(const char *name, const double *p, size_t n, vp_rng_t *r, int queries)
{
    vp_kdtree_t *t = NULL;
    int qi, bad = 0;
    CHECK(vp_kdtree_build(p, n, &t) == VP_OK);
    if (!t) return;
    for (qi = 0; qi < queries; qi++) {
        double q[3], d2[8], want[8];
        size_t idx[8], got, k = 1 + (size_t)qi % 8, j;
        if (qi % 3 == 0) memcpy(q, p + 3 * (size_t)(vp_rng_uniform(r) * (double)n), sizeof q); /* on a point */
        else for (j = 0; j < 3; j++) q[j] = -0.2 + 1.4 * vp_rng_uniform(r);
        got = vp_kdtree_knn(t, q, k, idx, d2);
        brute_knn(p, n, q, k, want);
        if (got != (k < n ? k : n)) bad++;
        for (j = 0; j < got; j++) {
            const double *x = vp_kdtree_point(t, idx[j]), *y = p + 3 * vp_kdtree_original(t, idx[j]);
            double dx = x[0] - q[0], dy = x[1] - q[1], dz = x[2] - q[2];
            if (d2[j] != want[j] || dx * dx + dy * dy + dz * dz != d2[j] || memcmp(x, y, 3 * sizeof *x) != 0) bad++;
        }
    }
    CHECKF(bad == 0, "%s: %d answers differ from brute force", name, bad);
    vp_kdtree_free(t);
}

int main(void)
{
    vp_rng_t r;
    size_t n = 60000 + 2000, i;
    double *p = malloc(3 * n * sizeof *p);
    vp_rng_seed(&r, 5);
    if (!p) return 1;
    /* random points */
    for (i = 0; i < 3 * 2000; i++) p[i] = vp_rng_uniform(&r);
    check_set("random", p, 2000, &r, 3000);
    /* 60,000 copies of one point among 2,000 random ones */
    for (i = 2000; i < n; i++) { p[3 * i] = 0.5; p[3 * i + 1] = 0.25; p[3 * i + 2] = 0.75; }
    check_set("repeated", p, n, &r, 600);
    /* 16,000 points of a 40^3 grid, each twice: every coordinate shared by hundreds */
    for (i = 0; i < 32000; i++) {
        size_t c = i % 64000 / 2;
        p[3 * i] = (double)(c % 40) / 39.0;
        p[3 * i + 1] = (double)(c / 40 % 40) / 39.0;
        p[3 * i + 2] = (double)(c / 1600) / 39.0;
    }
    check_set("grid", p, 32000, &r, 600);
    /* one point alone, and all points equal */
    check_set("one", p, 1, &r, 20);
    for (i = 0; i < 3 * 5000; i++) p[i] = 1.0;
    check_set("all equal", p, 5000, &r, 50);
    free(p);
    return vp_test_done("test_kdtree (k nearest against brute force; random, repeated, grid, equal points)");
}
