/* test_gmp_pred: every predicate in vp_pred against an independent exact reference in GMP.
 *
 * Reference: each double converts exactly to a rational (mpq_set_d); all denominators are
 * powers of two, so multiplying by the largest one gives integers (mpz), on which the
 * determinants are evaluated by fraction-free Gaussian elimination (Bareiss), straight from the
 * definitions: orient3d = det[b-a; c-a; d-a]; insphere = -sign det of the 5x5 rows
 * (x, y, z, x^2+y^2+z^2, 1) (the convention is pinned by the fixed cases in check_semantics);
 * insphere_sos = the same 5x5 determinant with each lift raised by eps^(r+1), r = number of
 * points lexicographically larger, eps = 2^-k with k large enough that the leading term decides.
 * Also: SOS properties, stage counts, and an informational micro benchmark. */
#include <gmp.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#include "vp_pred.h"
#include "vp_rng.h"
#include "vp_test.h"

/* ---------------------------------------------------------------- random numbers */

static uint64_t rng_state = 0x243F6A8885A308D3u;

static uint64_t rnd(void)
{
    return vp_splitmix_next(&rng_state);
}

static int rint_in(int lo, int hi) /* uniform in [lo, hi] */
{
    return lo + (int)(rnd() % (uint64_t)(hi - lo + 1));
}

static double urand(void) /* [0, 1) */
{
    return (double)(rnd() >> 11) * 0x1p-53;
}

static double srand1(void) /* [-1, 1) */
{
    return 2.0 * urand() - 1.0;
}

/* A random direction, uniform: a point of the unit ball (not too near its centre) scaled to length 1. */
static void random_dir(double u[3])
{
    double v[3], n2;
    int k;
    do {
        for (k = 0; k < 3; k++) v[k] = srand1();
        n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (n2 < 0.01 || n2 > 1.0);
    n2 = sqrt(n2);
    for (k = 0; k < 3; k++) u[k] = v[k] / n2;
}

static double nudge(double x, int steps)
{
    while (steps > 0) { x = nextafter(x, INFINITY); steps--; }
    while (steps < 0) { x = nextafter(x, -INFINITY); steps++; }
    return x;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------------------------------------------------------- GMP reference */

static mpz_t M[5][5], Z[5][3], zt, zprev, zden;
static mpq_t Q[5][3];

static void ref_init(void)
{
    int i, j;
    for (i = 0; i < 5; i++) {
        for (j = 0; j < 5; j++) mpz_init(M[i][j]);
        for (j = 0; j < 3; j++) {
            mpz_init(Z[i][j]);
            mpq_init(Q[i][j]);
        }
    }
    mpz_init(zt);
    mpz_init(zprev);
    mpz_init(zden);
}

/* Z[i][k] = P[i][k] * D for one common power of two D making them all integers. */
static void to_integers(const double (*P)[3], int np)
{
    int i, k;
    mpz_set_ui(zden, 1);
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++) {
            mpq_set_d(Q[i][k], P[i][k]);
            if (mpz_cmp(mpq_denref(Q[i][k]), zden) > 0) mpz_set(zden, mpq_denref(Q[i][k]));
        }
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++) {
            mpz_divexact(zt, zden, mpq_denref(Q[i][k]));
            mpz_mul(Z[i][k], mpq_numref(Q[i][k]), zt);
        }
}

/* Sign of det M[0..n-1][0..n-1] (destroys M), Bareiss elimination. */
static int bareiss_sign(int n)
{
    int k, i, j, sign = 1;
    mpz_set_ui(zprev, 1);
    for (k = 0; k < n - 1; k++) {
        if (mpz_sgn(M[k][k]) == 0) {
            for (i = k + 1; i < n && mpz_sgn(M[i][k]) == 0; i++) continue;
            if (i == n) return 0;
            for (j = 0; j < n; j++) mpz_swap(M[k][j], M[i][j]);
            sign = -sign;
        }
        for (i = k + 1; i < n; i++) {
            for (j = k + 1; j < n; j++) {
                mpz_mul(zt, M[i][j], M[k][k]);
                mpz_submul(zt, M[i][k], M[k][j]);
                mpz_divexact(M[i][j], zt, zprev);
            }
        }
        mpz_set(zprev, M[k][k]);
    }
    return sign * mpz_sgn(M[n - 1][n - 1]);
}

/* Points already in Z. */
static int ref_orient3d_z(int a, int b, int c, int d)
{
    int k;
    for (k = 0; k < 3; k++) {
        mpz_sub(M[0][k], Z[b][k], Z[a][k]);
        mpz_sub(M[1][k], Z[c][k], Z[a][k]);
        mpz_sub(M[2][k], Z[d][k], Z[a][k]);
    }
    return bareiss_sign(3);
}

static void lift_rows(void)
{
    int i, k;
    for (i = 0; i < 5; i++) {
        mpz_set_ui(M[i][3], 0);
        for (k = 0; k < 3; k++) {
            mpz_set(M[i][k], Z[i][k]);
            mpz_addmul(M[i][3], Z[i][k], Z[i][k]);
        }
        mpz_set_ui(M[i][4], 1);
    }
}

static int ref_insphere(const double (*P)[3])
{
    to_integers(P, 5);
    lift_rows();
    return -bareiss_sign(5);
}

static int lex(const double *a, const double *b)
{
    int k;
    for (k = 0; k < 3; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int ref_insphere_sos(const double (*P)[3])
{
    int i, j, k, rank[5];
    size_t bits = 1, eps_bits;
    to_integers(P, 5);
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) {
            size_t s = mpz_sizeinbase(Z[i][k], 2);
            if (s > bits) bits = s;
        }
    /* lift cofactors are 4x4 determinants of entries below 2^bits: below 2^(3 bits + 5) */
    eps_bits = 3 * bits + 10;
    for (i = 0; i < 5; i++) {
        rank[i] = 0;
        for (j = 0; j < 5; j++)
            if (lex(P[j], P[i]) > 0) rank[i]++;
    }
    lift_rows();
    /* scale the lift column by 2^(5 k): lift * 2^(5k) + 2^(k (4 - rank)) */
    for (i = 0; i < 5; i++) {
        mpz_mul_2exp(M[i][3], M[i][3], 5 * eps_bits);
        mpz_set_ui(zt, 1);
        mpz_mul_2exp(zt, zt, eps_bits * (size_t)(4 - rank[i]));
        mpz_add(M[i][3], M[i][3], zt);
    }
    return -bareiss_sign(5);
}

static int ref_orient3d(const double (*P)[3], int a, int b, int c, int d)
{
    to_integers(P, 5);
    return ref_orient3d_z(a, b, c, d);
}

static int ref_orient2d(const double (*P)[3], int drop)
{
    int i = (drop + 1) % 3, j = (drop + 2) % 3;
    to_integers(P, 3);
    /* cross product component along the dropped axis */
    mpz_sub(M[0][0], Z[1][i], Z[0][i]);
    mpz_sub(M[0][1], Z[2][j], Z[0][j]);
    mpz_sub(M[1][0], Z[1][j], Z[0][j]);
    mpz_sub(M[1][1], Z[2][i], Z[0][i]);
    mpz_mul(zt, M[0][0], M[0][1]);
    mpz_submul(zt, M[1][0], M[1][1]);
    return mpz_sgn(zt);
}

static int ref_cmp_dist(const double (*P)[3])
{
    int k;
    to_integers(P, 3);
    mpz_set_ui(zt, 0);
    for (k = 0; k < 3; k++) {
        mpz_sub(M[0][0], Z[0][k], Z[1][k]);
        mpz_addmul(zt, M[0][0], M[0][0]);
        mpz_sub(M[0][0], Z[0][k], Z[2][k]);
        mpz_submul(zt, M[0][0], M[0][0]);
    }
    return mpz_sgn(zt);
}

/* ---------------------------------------------------------------- case generators */

typedef void (*gen_fn)(double (*P)[3]);

static double pow2i(int e)
{
    return ldexp(1.0, e);
}

static void gen_random(double (*P)[3])
{
    int i, k;
    double s = pow2i(rint_in(-30, 30)), t = (rnd() & 1) ? 0.0 : srand1() * pow2i(rint_in(-5, 30));
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) P[i][k] = t + s * srand1();
}

static void gen_grid(double (*P)[3])
{
    int i, k, r = rint_in(1, 3);
    double s = pow2i(rint_in(-40, 40)), t = (rnd() % 4 == 0) ? pow2i(rint_in(0, 40)) * s : 0.0;
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) P[i][k] = t + s * rint_in(-r, r);
}

/* a grid configuration mapped by an inexact affine map, then nudged by a few ulps */
static void gen_grid_perturbed(double (*P)[3])
{
    int i, k, n;
    double s = 0.5 + urand(), t[3];
    for (k = 0; k < 3; k++) t[k] = (rnd() & 1) ? srand1() * pow2i(rint_in(-3, 10)) : 0.0;
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) P[i][k] = t[k] + s * rint_in(-2, 2);
    for (n = rint_in(0, 3); n > 0; n--) {
        i = rint_in(0, 4);
        k = rint_in(0, 2);
        P[i][k] = nudge(P[i][k], rint_in(-2, 2));
    }
}

/* points on a sphere rounded to doubles */
static void gen_sphere(double (*P)[3])
{
    int i, k;
    double c[3], r = pow2i(rint_in(-8, 8)) * (0.5 + urand());
    int centred = rnd() % 3 == 0;
    for (k = 0; k < 3; k++) c[k] = centred ? 0.0 : srand1() * pow2i(rint_in(-4, 12));
    for (i = 0; i < 5; i++) {
        double u[3];
        random_dir(u);
        for (k = 0; k < 3; k++) P[i][k] = c[k] + r * u[k];
    }
}

/* points nearly on a plane (for orient3d) and nearly on a sphere with one nudged */
static void gen_sphere_nudged(double (*P)[3])
{
    int i = rint_in(0, 4), k = rint_in(0, 2);
    gen_sphere(P);
    P[i][k] = nudge(P[i][k], rint_in(-1, 1));
}

/* points differing only in the last bits */
static void gen_ulps(double (*P)[3])
{
    int i, k;
    double b[3];
    for (k = 0; k < 3; k++) b[k] = srand1() * pow2i(rint_in(-20, 20));
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) P[i][k] = nudge(b[k], rint_in(-4, 4));
}

/* large translations: 1e15 + small (exact or rounded) offsets */
static void gen_translated(double (*P)[3])
{
    int i, k, exact = rnd() & 1;
    double t = (rnd() & 1) ? 1e15 : -3.7e14;
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++)
            P[i][k] = t + (exact ? 0.125 * rint_in(-16, 16) : srand1() * 4.0);
}

static double wide_double(void)
{
    double m = (double)((rnd() >> 11) | 1);
    int e;
    if (rnd() % 8 == 0) return 0.0;
    e = rint_in(-1074 - 52, 1023 - 52);
    m = ldexp(m, e); /* may round to a subnormal or zero at the bottom */
    return (rnd() & 1) ? -m : m;
}

/* magnitudes anywhere in 1e-320 .. 1e308, mixed in one call */
static void gen_wide(double (*P)[3])
{
    int i, k, mode = rint_in(0, 2);
    for (i = 0; i < 5; i++) {
        double s = pow2i(rint_in(-1000, 950));
        for (k = 0; k < 3; k++) {
            if (mode == 0) P[i][k] = wide_double();
            else if (mode == 1) P[i][k] = s * srand1(); /* one scale per point */
            else P[i][k] = pow2i(rint_in(-1074, 1000)) * rint_in(-3, 3); /* wide grid */
        }
    }
}

/* exactly degenerate configurations with inexact differences and huge spreads */
static void gen_wide_degenerate(double (*P)[3])
{
    int i, k, mode = rint_in(0, 4);
    double z = wide_double(), w = wide_double();
    for (i = 0; i < 5; i++) {
        double t = wide_double(), u = wide_double();
        switch (mode) {
        case 0: /* collinear: (t, 2t, -t) */
            P[i][0] = t;
            P[i][1] = 2.0 * t;
            P[i][2] = -t;
            if (fabs(t) > 1e307) P[i][1] = t;
            break;
        case 1: /* coplanar z = const */
            P[i][0] = t;
            P[i][1] = u;
            P[i][2] = z;
            break;
        case 2: /* cocircular in a plane: (+-z, 0, w), (0, +-z, w), fifth point anywhere */
            P[i][0] = (i == 0) ? z : (i == 1) ? -z : (i == 4) ? t : 0.0;
            P[i][1] = (i == 2) ? z : (i == 3) ? -z : (i == 4) ? u : 0.0;
            P[i][2] = (i == 4) ? wide_double() : w;
            break;
        default: /* random wide points, then duplicates */
            for (k = 0; k < 3; k++) P[i][k] = wide_double();
            break;
        }
    }
    if (mode >= 3) {
        int a = rint_in(0, 4), b = rint_in(0, 4);
        for (k = 0; k < 3; k++) P[b][k] = P[a][k];
    }
}

/* tiny and huge: a grid scaled to subnormals or to the top of the range */
static void gen_extreme_grid(double (*P)[3])
{
    int i, k;
    double s = (rnd() & 1) ? pow2i(rint_in(-1074, -1000)) : pow2i(rint_in(900, 1018));
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) P[i][k] = s * rint_in(-3, 3);
    if (rnd() & 1) {
        i = rint_in(0, 4);
        k = rint_in(0, 2);
        P[i][k] = nudge(P[i][k], rint_in(-2, 2));
    }
}


/* at the edges of the safe exponent windows (widths 318, 568, 878 binades): x, y on a grid
 * at scale 2^b, z on a grid at 2^(b - span), so tiny terms decide near-degenerate cases */
static void gen_window_edge(double (*P)[3])
{
    static const int widths[3] = { 318, 568, 878 };
    int i, span = widths[rint_in(0, 2)] + rint_in(-2, 2), b = rint_in(-1074 + span, 1015);
    double big = pow2i(b), tiny = pow2i(b - span);
    for (i = 0; i < 5; i++) {
        P[i][0] = big * rint_in(-2, 2);
        P[i][1] = big * rint_in(-2, 2);
        P[i][2] = tiny * rint_in(-2, 2);
    }
    if (rnd() & 1) { /* rotate the axes */
        for (i = 0; i < 5; i++) {
            double t = P[i][0];
            P[i][0] = P[i][2];
            P[i][2] = P[i][1];
            P[i][1] = t;
        }
    }
}

/* at the edges of the inline filters' window (maxima of the differences near 2^-190 and
 * 2^190), with some differences tiny enough that their products underflow, near-degenerate
 * (grid points nudged by an ulp) */
static void gen_filter_edge(double (*P)[3])
{
    int i, k, e = (rnd() & 1) ? rint_in(-196, -184) : rint_in(184, 196);
    double s = pow2i(e), tiny = pow2i(rint_in(-1074, -900));
    for (i = 0; i < 5; i++)
        for (k = 0; k < 3; k++) {
            int mode = rint_in(0, 5);
            if (mode == 0) P[i][k] = tiny * rint_in(-3, 3);
            else if (mode == 1) P[i][k] = s * srand1();
            else P[i][k] = nudge(s * rint_in(-2, 2), rint_in(-1, 1));
        }
}

/* ---------------------------------------------------------------- checks */

struct gen_class {
    const char *name;
    gen_fn gen;
    long cases;
};

static struct vp_pred_stats st_o3, st_is, st_o2, st_cd;
static long exact_boxes;

static void dump_case(const double (*P)[3])
{
    int i;
    for (i = 0; i < 5; i++)
        fprintf(stderr, "  {%a, %a, %a}\n", P[i][0], P[i][1], P[i][2]);
}

static long run_class(const struct gen_class *g)
{
    long n, checks = 0;
    double P[5][3];
    for (n = 0; n < g->cases; n++) {
        int got, want, drop = (int)(n % 3);
        g->gen(P);
        got = vp_orient3d_stats(P[0], P[1], P[2], P[3], &st_o3);
        want = ref_orient3d((const double (*)[3])P, 0, 1, 2, 3);
        CHECKF(got == want, "%s orient3d got %d want %d", g->name, got, want);
        if (got != want) dump_case((const double (*)[3])P);
        {
            int f = vp_orient3d_filter(P[0], P[1], P[2], P[3]);
            CHECKF(f == VP_PRED_UNSURE || f == want, "%s orient3d filter %d want %d", g->name, f, want);
            CHECKF(vp_orient3d_tail(P[0], P[1], P[2], P[3]) == want, "%s orient3d tail", g->name);
            checks += 2;
        }
        got = vp_orient3d_stats(P[4], P[2], P[1], P[3], &st_o3);
        want = ref_orient3d((const double (*)[3])P, 4, 2, 1, 3);
        CHECKF(got == want, "%s orient3d(4213) got %d want %d", g->name, got, want);
        got = vp_insphere_stats(P[0], P[1], P[2], P[3], P[4], &st_is);
        want = ref_insphere((const double (*)[3])P);
        CHECKF(got == want, "%s insphere got %d want %d", g->name, got, want);
        if (got != want) dump_case((const double (*)[3])P);
        {
            /* the inline filter answers right or not at all; the tail is exact */
            int f = vp_insphere_filter(P[0], P[1], P[2], P[3], P[4]);
            CHECKF(f == VP_PRED_UNSURE || f == want, "%s insphere filter %d want %d", g->name, f, want);
            if (f != VP_PRED_UNSURE && f != want) dump_case((const double (*)[3])P);
            CHECKF(vp_insphere_tail(P[0], P[1], P[2], P[3], P[4]) == want, "%s insphere tail", g->name);
            checks += 2;
        }
        {
            /* static bounds from the box of the five points (sometimes a larger box) */
            double lo[3], hi[3], sb;
            int i, k, f;
            for (k = 0; k < 3; k++) {
                lo[k] = hi[k] = P[0][k];
                for (i = 1; i < 5; i++) {
                    if (P[i][k] < lo[k]) lo[k] = P[i][k];
                    if (P[i][k] > hi[k]) hi[k] = P[i][k];
                }
                if (n % 4 == 3) hi[k] += (hi[k] - lo[k]) * 0.5;
            }
            sb = vp_insphere_static_bound(lo, hi);
            f = vp_insphere_filter_b(P[0], P[1], P[2], P[3], P[4], sb);
            CHECKF(f == VP_PRED_UNSURE || f == want, "%s insphere static filter %d want %d", g->name, f, want);
            if (f != VP_PRED_UNSURE && f != want) dump_case((const double (*)[3])P);
            {
                /* exact boxes (grids): bound 0, UNSURE exactly for zeros */
                int lb = 100000, xi, xo;
                for (i = 0; i < 5; i++)
                    for (k = 0; k < 3; k++)
                        if (P[i][k] != 0.0 && vp_lowest_bit(P[i][k]) < lb) lb = vp_lowest_bit(P[i][k]);
                xi = lb < 100000 && vp_insphere_box_exact(lo, hi, lb);
                xo = lb < 100000 && vp_orient3d_box_exact(lo, hi, lb);
                if (xi) {
                    f = vp_insphere_filter_b(P[0], P[1], P[2], P[3], P[4], 0.0);
                    CHECKF(f == (want ? want : VP_PRED_UNSURE), "%s insphere exact box %d want %d",
                           g->name, f, want);
                    exact_boxes++;
                }
                want = ref_orient3d((const double (*)[3])P, 4, 2, 1, 3);
                if (xo) {
                    f = vp_orient3d_filter_b(P[4], P[2], P[1], P[3], 0.0);
                    CHECKF(f == (want ? want : VP_PRED_UNSURE), "%s orient3d exact box %d want %d",
                           g->name, f, want);
                }
            }
            sb = vp_orient3d_static_bound(lo, hi);
            f = vp_orient3d_filter_b(P[4], P[2], P[1], P[3], sb);
            CHECKF(f == VP_PRED_UNSURE || f == want, "%s orient3d static filter %d want %d", g->name, f, want);
            checks += 4;
        }
        got = vp_orient2d_proj_stats(P[0], P[1], P[2], drop, &st_o2);
        want = ref_orient2d((const double (*)[3])P, drop);
        CHECKF(got == want, "%s orient2d got %d want %d", g->name, got, want);
        if (got != want) dump_case((const double (*)[3])P);
        got = vp_cmp_dist_stats(P[0], P[1], P[2], &st_cd);
        want = ref_cmp_dist((const double (*)[3])P);
        CHECKF(got == want, "%s cmp_dist got %d want %d", g->name, got, want);
        if (got != want) dump_case((const double (*)[3])P);
        checks += 5;
    }
    return checks;
}

static void print_stats(const char *what, const struct vp_pred_stats *s)
{
    unsigned long tot = s->stage[0] + s->stage[1] + s->stage[2] + s->stage[3];
    printf("  %-10s %9lu calls: filter %.2f%%, dd %.2f%%, exact-diff %.2f%%, bigint %.3f%%, "
           "rescaled %.3f%%", what, tot, 100.0 * s->stage[0] / tot, 100.0 * s->stage[1] / tot,
           100.0 * s->stage[2] / tot, 100.0 * s->stage[3] / tot, 100.0 * s->rescaled / tot);
    if (s->sos) printf(", sos %lu", s->sos);
    printf("\n");
}

static void check_semantics(void)
{
    static const double o[3] = { 0, 0, 0 }, x[3] = { 1, 0, 0 }, y[3] = { 0, 1, 0 },
                        z[3] = { 0, 0, 1 }, mid[3] = { 0.5, 0.5, 0.5 }, far[3] = { 2, 2, 2 },
                        on[3] = { 1, 1, 0 }, x2[3] = { 2, 0, 0 };
    double P[5][3];
    CHECK(vp_orient3d(o, x, y, z) == 1);
    CHECK(vp_orient3d(x, o, y, z) == -1);
    CHECK(vp_orient3d(o, x, y, mid) == 1);
    CHECK(vp_orient3d(o, x, y, x2) == 0);
    CHECK(vp_insphere(o, x, y, z, mid) == 1);
    CHECK(vp_insphere(o, x, y, z, far) == -1);
    CHECK(vp_insphere(o, x, y, z, on) == 0);
    CHECK(vp_insphere_sos(o, x, y, z, on) == -1); /* (1,1,0) is the lexicographic maximum */
    CHECK(vp_insphere_sos(o, x, y, z, mid) == 1);
    CHECK(vp_orient2d_proj(o, x, y, 2) == 1);
    CHECK(vp_orient2d_proj(o, y, z, 0) == 1);
    CHECK(vp_orient2d_proj(o, z, x, 1) == 1);
    CHECK(vp_orient2d_proj(o, x, z, 1) == -1);
    CHECK(vp_cmp_dist(o, x, x2) == -1);
    CHECK(vp_cmp_dist(o, x, y) == 0);
    CHECK(vp_cmp_dist(o, x2, y) == 1);
    CHECK(vp_lex_cmp(x, y) == 1 && vp_lex_cmp(y, x) == -1 && vp_lex_cmp(x, x) == 0);
    /* the reference agrees with the fixed answers */
    memcpy(P[0], o, sizeof o);
    memcpy(P[1], x, sizeof o);
    memcpy(P[2], y, sizeof o);
    memcpy(P[3], z, sizeof o);
    memcpy(P[4], mid, sizeof o);
    CHECK(ref_insphere((const double (*)[3])P) == 1);
    CHECK(ref_orient3d((const double (*)[3])P, 0, 1, 2, 3) == 1);
    memcpy(P[4], on, sizeof o);
    CHECK(ref_insphere_sos((const double (*)[3])P) == -1);
    /* extreme magnitudes and non-finite input do not crash */
    {
        const double big[3] = { 0x1.fffffffffffffp1023, -0x1.fffffffffffffp1023, 0 },
                     tiny[3] = { 0x1p-1074, 0, -0x1p-1074 }, inf[3] = { INFINITY, 0, 0 };
        CHECK(vp_orient3d(big, tiny, o, x) == -vp_orient3d(tiny, big, o, x));
        (void)vp_insphere(inf, o, x, y, z);
        (void)vp_orient3d(inf, o, x, y);
    }
}

/* SOS: against the perturbed GMP determinant, plus the properties a Delaunay code uses. */
static long check_sos(long cases, gen_fn gen, const char *name, struct vp_pred_stats *st)
{
    static const int odd[6][5] = { { 1, 0, 2, 3, 4 }, { 0, 2, 1, 3, 4 }, { 0, 1, 3, 2, 4 },
                                   { 3, 1, 2, 0, 4 }, { 2, 1, 0, 3, 4 }, { 0, 3, 2, 1, 4 } };
    static const int even[3][5] = { { 1, 2, 0, 3, 4 }, { 3, 2, 1, 0, 4 }, { 1, 0, 3, 2, 4 } };
    long n, checks = 0;
    double P[5][3];
    for (n = 0; n < cases; n++) {
        int s, want, o, i, k, dup = 0;
        gen(P);
        for (i = 0; i < 5; i++)
            for (k = i + 1; k < 5; k++) dup |= lex(P[i], P[k]) == 0;
        s = vp_insphere_sos_stats(P[0], P[1], P[2], P[3], P[4], st);
        want = ref_insphere_sos((const double (*)[3])P);
        if (dup) want = 0;
        CHECKF(s == want, "%s sos got %d want %d", name, s, want);
        if (s != want) dump_case((const double (*)[3])P);
        if (vp_insphere(P[0], P[1], P[2], P[3], P[4]) == 0) {
            double lo[3], hi[3];
            int lb = 100000;
            CHECKF(vp_insphere_sos_zero(P[0], P[1], P[2], P[3], P[4]) == want,
                   "%s sos_zero differs", name);
            for (k = 0; k < 3; k++) {
                lo[k] = hi[k] = P[0][k];
                for (i = 0; i < 5; i++) {
                    if (P[i][k] < lo[k]) lo[k] = P[i][k];
                    if (P[i][k] > hi[k]) hi[k] = P[i][k];
                    if (P[i][k] != 0.0 && vp_lowest_bit(P[i][k]) < lb) lb = vp_lowest_bit(P[i][k]);
                }
            }
            CHECKF(vp_insphere_sos_zero_b(P[0], P[1], P[2], P[3], P[4],
                                          vp_orient3d_static_bound(lo, hi)) == want,
                   "%s sos_zero_b (static) differs", name);
            if (lb < 100000 && vp_orient3d_box_exact(lo, hi, lb))
                CHECKF(vp_insphere_sos_zero_b(P[0], P[1], P[2], P[3], P[4], 0.0) == want,
                       "%s sos_zero_b (exact box) differs", name);
        }
        o = vp_orient3d(P[0], P[1], P[2], P[3]);
        if (o != 0 && !dup) CHECKF(s != 0, "%s sos returned 0 for a proper tetrahedron", name);
        for (i = 0; i < 6; i++) {
            const int *q = odd[i];
            CHECK(vp_insphere_sos(P[q[0]], P[q[1]], P[q[2]], P[q[3]], P[q[4]]) == -s);
        }
        for (i = 0; i < 3; i++) {
            const int *q = even[i];
            CHECK(vp_insphere_sos(P[q[0]], P[q[1]], P[q[2]], P[q[3]], P[q[4]]) == s);
        }
        checks += 11;
    }
    return checks;
}

/* Two tetrahedra sharing facet (a, b, c) from both sides; e coplanar with the facet must get
 * the same answer from both. Grid points on the plane z = 0 or on x + y + z = 0. */
static long check_facets(long cases)
{
    long n, checks = 0;
    for (n = 0; n < cases; n++) {
        double a[3], b[3], c[3], e[3], d[3], f[3], s = pow2i(rint_in(-20, 20));
        double *pl[4];
        int i, plane = rint_in(0, 1), s1, s2;
        double *t1[4], *t2[4];
        pl[0] = a;
        pl[1] = b;
        pl[2] = c;
        pl[3] = e;
        for (i = 0; i < 4; i++) {
            pl[i][0] = s * rint_in(-2, 2);
            pl[i][1] = s * rint_in(-2, 2);
            pl[i][2] = plane ? -(pl[i][0] + pl[i][1]) : 0.0;
        }
        if (vp_orient2d_proj(a, b, c, 2) == 0) continue; /* facet must be a triangle */
        if (!lex(e, a) || !lex(e, b) || !lex(e, c)) continue;
        for (i = 0; i < 3; i++) {
            d[i] = s * rint_in(-2, 2);
            f[i] = s * rint_in(-2, 2);
        }
        {
            int od = vp_orient3d(a, b, c, d), of = vp_orient3d(a, b, c, f);
            if (od == 0 || of == 0 || od == of) continue;
            t1[0] = od > 0 ? a : b;
            t1[1] = od > 0 ? b : a;
            t1[2] = c;
            t1[3] = d;
            t2[0] = of > 0 ? a : b;
            t2[1] = of > 0 ? b : a;
            t2[2] = c;
            t2[3] = f;
        }
        s1 = vp_insphere_sos(t1[0], t1[1], t1[2], t1[3], e);
        s2 = vp_insphere_sos(t2[0], t2[1], t2[2], t2[3], e);
        CHECKF(s1 == s2 && s1 != 0, "facet consistency %d %d", s1, s2);
        checks++;
    }
    return checks;
}

/* ---------------------------------------------------------------- benchmark */

#define BENCH_N 4096
static double bench_pts[BENCH_N][5][3];

static double bench_ns(int which, int reps)
{
    volatile int sink = 0;
    double t0 = now();
    int r, i;
    for (r = 0; r < reps; r++)
        for (i = 0; i < BENCH_N; i++) {
            double (*p)[3] = bench_pts[i];
            if (which == 0) sink += vp_orient3d(p[0], p[1], p[2], p[3]);
            else if (which == 1) sink += vp_insphere(p[0], p[1], p[2], p[3], p[4]);
            else sink += vp_insphere_sos(p[0], p[1], p[2], p[3], p[4]);
        }
    (void)sink;
    return (now() - t0) * 1e9 / ((double)reps * BENCH_N);
}

static void benchmark(void)
{
    int i;
    struct vp_pred_stats s;
    for (i = 0; i < BENCH_N; i++) gen_random(bench_pts[i]);
    printf("bench (ns/call, informational): random: orient3d %.1f, insphere %.1f\n",
           bench_ns(0, 200), bench_ns(1, 200));
    memset(&s, 0, sizeof s);
    for (i = 0; i < BENCH_N; i++) {
        double (*p)[3] = bench_pts[i];
        int k, j;
        double r = 1.0;
        for (j = 0; j < 5; j++) { /* unit sphere, centred at the origin: worst case for B */
            double u[3];
            random_dir(u);
            for (k = 0; k < 3; k++) p[j][k] = r * u[k];
        }
        if (vp_orient3d(p[0], p[1], p[2], p[3]) < 0) {
            double t[3];
            memcpy(t, p[0], sizeof t);
            memcpy(p[0], p[1], sizeof t);
            memcpy(p[1], t, sizeof t);
        }
        vp_insphere_stats(p[0], p[1], p[2], p[3], p[4], &s);
    }
    printf("bench: unit-sphere points: insphere %.1f, insphere_sos %.1f\n", bench_ns(1, 20),
           bench_ns(2, 20));
    print_stats("sphere", &s);
    memset(&s, 0, sizeof s);
    for (i = 0; i < BENCH_N; i++) {
        double (*p)[3] = bench_pts[i];
        int j, k;
        double c[3] = { 10.3, -4.1, 7.7 };
        for (j = 0; j < 5; j++) { /* a small sphere away from the origin: exact differences */
            double v[3], n2;
            do {
                for (k = 0; k < 3; k++) v[k] = srand1();
                n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            } while (n2 < 0.01 || n2 > 1.0);
            n2 = sqrt(n2);
            for (k = 0; k < 3; k++) p[j][k] = c[k] + 0.01 * v[k] / n2;
        }
        vp_insphere_stats(p[0], p[1], p[2], p[3], p[4], &s);
    }
    printf("bench: small sphere off the origin: insphere %.1f\n", bench_ns(1, 20));
    print_stats("small-sph", &s);
    memset(&s, 0, sizeof s);
    for (i = 0; i < BENCH_N; i++) {
        gen_grid(bench_pts[i]);
        vp_insphere_stats(bench_pts[i][0], bench_pts[i][1], bench_pts[i][2], bench_pts[i][3],
                          bench_pts[i][4], &s);
    }
    printf("bench: integer grid: insphere %.1f, insphere_sos %.1f\n", bench_ns(1, 50),
           bench_ns(2, 50));
    print_stats("grid", &s);
}

/* ---------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    static const struct gen_class classes[] = {
        { "random", gen_random, 200000 },
        { "grid", gen_grid, 300000 },
        { "grid-perturbed", gen_grid_perturbed, 300000 },
        { "sphere", gen_sphere, 200000 },
        { "sphere-nudged", gen_sphere_nudged, 100000 },
        { "ulps", gen_ulps, 200000 },
        { "translated", gen_translated, 150000 },
        { "wide", gen_wide, 20000 },
        { "wide-degenerate", gen_wide_degenerate, 20000 },
        { "extreme-grid", gen_extreme_grid, 50000 },
        { "window-edge", gen_window_edge, 50000 },
        { "filter-edge", gen_filter_edge, 30000 },
    };
    double scale = 1.0, t0 = now();
    long total = 0;
    size_t c;
    struct vp_pred_stats st_sos;
    if (argc > 1) scale = atof(argv[1]);
    ref_init();
    check_semantics();
    for (c = 0; c < sizeof classes / sizeof classes[0]; c++) {
        struct gen_class g = classes[c];
        double t1 = now();
        long k;
        g.cases = (long)(g.cases * scale);
        k = run_class(&g);
        total += k;
        printf("%-16s %8ld cases %9ld checks %6.2fs\n", g.name, g.cases, k, now() - t1);
    }
    printf("exact-box cases: %ld\n", exact_boxes);
    CHECK(exact_boxes > 1000);
    print_stats("orient3d", &st_o3);
    print_stats("insphere", &st_is);
    print_stats("orient2d", &st_o2);
    print_stats("cmp_dist", &st_cd);
    memset(&st_sos, 0, sizeof st_sos);
    {
        double t1 = now();
        long k = check_sos((long)(200000 * scale), gen_grid, "grid", &st_sos);
        k += check_sos((long)(30000 * scale), gen_grid_perturbed, "grid-perturbed", &st_sos);
        k += check_sos((long)(20000 * scale), gen_extreme_grid, "extreme-grid", &st_sos);
        k += check_sos((long)(20000 * scale), gen_window_edge, "window-edge", &st_sos);
        k += check_sos((long)(20000 * scale), gen_sphere, "sphere", &st_sos);
        k += check_sos((long)(20000 * scale), gen_filter_edge, "filter-edge", &st_sos);
        long kf = check_facets((long)(200000 * scale));
        total += k + kf;
        printf("%-16s %8s       %9ld checks %6.2fs (+ %ld shared-facet checks)\n", "sos", "", k,
               now() - t1, kf);
        print_stats("sos", &st_sos);
    }
    printf("total: %ld checks in %.1fs\n", total, now() - t0);
    benchmark();
    return vp_test_done("test_gmp_pred");
}
