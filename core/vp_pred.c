/* vp_pred.c — exact geometric predicates (see vp_pred.h for the conventions).
 *
 * Each predicate is the sign of a polynomial in coordinate differences. Stages, in order:
 *   F  (vp_pred.h, inline) static filter (bound from a bounding box, for vp_dt) and
 *      semi-static filter (bound from the largest differences); for an integer grid whose
 *      box makes the evaluation exact, the static bound is 0 (vp_*_box_exact).
 *   A' exactness certificate (small integer differences at a common power-of-two scale): the
 *      floating-point value is exact, zero included. Tried first by the tails.
 *   A  floating-point evaluation; the answer stands when |det| exceeds c * permanent, c a
 *      compile-time constant derived below for each predicate (rounding-error count).
 *   B  orient3d and insphere: double-double evaluation on the exact differences (each one a
 *      two-diff pair hi + lo), error below c * eps^2 * permanent (bound derived at dd_mul).
 *      Decides nearly every non-degenerate input that A could not, e.g. rounded points of a
 *      sphere.
 *   C  the differences p - q were exact (all two-diff tails zero, as on integer grids or for
 *      nearby points): the determinant of those doubles, exactly, with floating-point
 *      expansions (two-sum, Dekker product, compression).
 *   X  exact integers: every coordinate is m * 2^e; divided by 2^E (E = lowest set bit of all
 *      inputs) it is an integer below 2^2099, and the determinant is evaluated in fixed-size
 *      two's complement arrays (32-bit limbs) whose length follows the actual bit span.
 * A zero permanent means every monomial has a factor p - q that is exactly 0 (a nonzero
 * difference rounds to nonzero, and nonzero products cannot underflow, see below): the answer
 * is 0 at once, as for coplanar points sharing a coordinate.
 * Built with VP_CORE_MCU (vp_status.h: a microcontroller image) the tails leave out A', A, B
 * and C and go from F straight to X (orient2d and cmp_dist, which have no inline filter: from
 * A to X); the signs are the same.
 * A-C assume no overflow and no precision lost to underflow. A cheap magnitude check guards
 * them: every nonzero |coordinate| must lie in [2^lo, 2^hi) (per-degree window below). Inputs
 * whose exponents spread less than the window are first multiplied by an exact power of two
 * (the sign of a homogeneous polynomial does not change); the rest go straight to X.
 *
 * Why the window suffices: a double with |x| >= 2^lo is a multiple of 2^(lo-52), so every
 * difference, product and sum of degree <= k formed from the inputs (computed or exact) is a
 * multiple of 2^(k(lo-52)) >= 2^-900. A rounded result that would be subnormal is then exact,
 * so every operation obeys |fl(x) - x| <= eps |x| (eps = 2^-53), two-product tails are exact,
 * and the error bounds (which multiply permanents by >= 2^-100) never underflow. The upper end
 * keeps every value, including Veltkamp's 2^27 * a, below 2^1020.
 *
 * Worst-case stack, gcc 12 -fstack-usage summed along the deepest call chain (vp_insphere_sos
 * -> vp_insphere_tail -> insphere_tail -> insphere_big -> big_det3 -> big_minor -> big_diff ->
 * big_load): x86-64 -O2: 4360 bytes; Cortex-M4 -mthumb -Os: 3944 bytes (+ libgcc soft-float
 * helpers).
 * insphere_big's limb arrays (790 x 4 bytes, sized for the widest possible input) dominate;
 * orient3d alone: 2.9 KB / 2.5 KB. No recursion, no heap, no writable static data.
 */
#include "vp_pred.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#define EPS 0x1p-53
#define UNDECIDED 2

/* the error-free transformations and double-double steps are small: inline them into the
 * stages (not when optimising for size) */
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define EFT_INLINE static inline __attribute__((always_inline))
#else
#define EFT_INLINE static inline
#endif

#define COUNT(st, field) do { if (st) (st)->field++; } while (0)

/* Filter constants: c >= (n eps + O(eps^2)) / (1 - eps), n = roundings along the longest path
 * of one monomial (counted at each stage below), the same count bounding how much the computed
 * permanent may undershoot the exact one. The eps^2 terms are taken generously. */
#define O2_ERR_A ((4.0 + 256.0 * EPS) * EPS)
#define CD_ERR_A ((6.0 + 256.0 * EPS) * EPS)
#define O3_ERR_A ((8.0 + 512.0 * EPS) * EPS)
#define IS_ERR_A ((16.0 + 1024.0 * EPS) * EPS)
#define O3_ERR_B (32.0 * EPS * EPS)
#define IS_ERR_B (64.0 * EPS * EPS)

/* Safe windows [2^lo, 2^hi) for nonzero |coordinates|, by polynomial degree k:
 * k (lo - 52) >= -900 and k (hi + 1) + log2(#monomials) + 28 < 1020. */
#define W2_LO (-398)
#define W2_HI 480
#define W3_LO (-248)
#define W3_HI 320
#define W5_LO (-128)
#define W5_HI 190

#ifndef VP_CORE_MCU /* stages A', A, B, C: left out with VP_CORE_MCU (see the top) */
/* ------------------------------------------------------------------------------------------
 * Error-free transformations (round-to-nearest-even doubles, no FMA).
 */

/* x = fl(a + b), x + y = a + b exactly. */
EFT_INLINE void two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    double bv = s - a;
    double av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* x = fl(a - b), x + y = a - b exactly. */
EFT_INLINE void two_diff(double a, double b, double *x, double *y)
{
    double s = a - b;
    double bv = a - s;
    double av = s + bv;
    *x = s;
    *y = (a - av) + (bv - b);
}

/* Veltkamp: a = hi + lo, each half fits in 26 bits. */
EFT_INLINE void split(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a; /* 2^27 + 1 */
    double big = c - a;
    *hi = c - big;
    *lo = a - *hi;
}

/* Dekker: x = fl(a * b), x + y = a * b exactly. */
EFT_INLINE void two_prod(double a, double b, double *x, double *y)
{
    double ah, al, bh, bl, p = a * b;
    split(a, &ah, &al);
    split(b, &bh, &bl);
    *x = p;
    *y = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
}

static void two_square(double a, double *x, double *y)
{
    double ah, al, p = a * a;
    split(a, &ah, &al);
    *x = p;
    *y = al * al - ((p - ah * ah) - (ah + ah) * al);
}

/* ------------------------------------------------------------------------------------------
 * Expansions: arrays of nonoverlapping doubles in increasing magnitude, zeros removed (the
 * value 0 has length 0). The sign is the sign of the last component.
 */

static int exp_sign(const double *e, int n)
{
    return n == 0 ? 0 : (e[n - 1] > 0.0 ? 1 : -1);
}

/* h = e + f: merge by magnitude, then one chain of two-sums. Returns the length. */
static int exp_sum(const double *e, int ne, const double *f, int nf, double *h)
{
    double q, g, err;
    int i = 0, j = 0, k = 0;
    if (ne + nf == 0) return 0;
    if (j >= nf || (i < ne && fabs(e[i]) < fabs(f[j]))) q = e[i++];
    else q = f[j++];
    while (i < ne || j < nf) {
        if (j >= nf || (i < ne && fabs(e[i]) < fabs(f[j]))) g = e[i++];
        else g = f[j++];
        two_sum(q, g, &q, &err);
        if (err != 0.0) h[k++] = err;
    }
    if (q != 0.0) h[k++] = q;
    return k;
}

/* h = e * b. Returns the length (<= 2n). */
static int exp_scale(const double *e, int n, double b, double *h)
{
    double q, err, p1, p0, s;
    int i, k = 0;
    if (n == 0 || b == 0.0) return 0;
    two_prod(e[0], b, &q, &err);
    if (err != 0.0) h[k++] = err;
    for (i = 1; i < n; i++) {
        two_prod(e[i], b, &p1, &p0);
        two_sum(q, p0, &s, &err);
        if (err != 0.0) h[k++] = err;
        two_sum(p1, s, &q, &err);
        if (err != 0.0) h[k++] = err;
    }
    if (q != 0.0) h[k++] = q;
    return k;
}

/* Same value in (usually far) fewer components, in place: a top-down then a bottom-up sweep. */
static int exp_compress(double *e, int n)
{
    double q, s, err;
    int i, bottom, top = 0;
    if (n <= 1) return n;
    bottom = n - 1;
    q = e[n - 1];
    for (i = n - 2; i >= 0; i--) {
        two_sum(q, e[i], &s, &err);
        if (err != 0.0) {
            e[bottom--] = s;
            q = err;
        } else {
            q = s;
        }
    }
    e[bottom] = q;
    q = e[bottom];
    for (i = bottom + 1; i < n; i++) {
        two_sum(e[i], q, &s, &err);
        if (err != 0.0) e[top++] = err;
        q = s;
    }
    if (q != 0.0) e[top++] = q;
    return top;
}

/* h = a*b - c*d exactly. Returns the length (<= 4). */
static int prod_diff(double a, double b, double c, double d, double *h)
{
    double x, y, e1[2], e2[2];
    int n1 = 0, n2 = 0;
    two_prod(a, b, &x, &y);
    if (y != 0.0) e1[n1++] = y;
    if (x != 0.0) e1[n1++] = x;
    two_prod(c, d, &x, &y);
    if (y != 0.0) e2[n2++] = -y;
    if (x != 0.0) e2[n2++] = -x;
    return exp_sum(e1, n1, e2, n2, h);
}

/* h = |v|^2 exactly (v three doubles). Returns the length (<= 6). */
static int exp_norm2(const double *v, double *h)
{
    double s[3][2], t[4];
    int n[3], k, nt;
    for (k = 0; k < 3; k++) {
        double x, y;
        two_square(v[k], &x, &y);
        n[k] = 0;
        if (y != 0.0) s[k][n[k]++] = y;
        if (x != 0.0) s[k][n[k]++] = x;
    }
    nt = exp_sum(s[0], n[0], s[1], n[1], t);
    return exp_sum(t, nt, s[2], n[2], h);
}

/* ------------------------------------------------------------------------------------------
 * Double-double: hi + lo with |lo| <= eps |hi| (two-sum / two-diff / two-prod outputs are).
 * Write H = |x.hi| |y.hi| for a product, A = |x.hi| + |y.hi| for a sum.
 * dd_mul: the error is xl*yl (<= eps^2 H) + rounding of the two cross products and their sum
 *   (<= 4 eps^2 H + 2 eps^3 H) + rounding of pl + c, |pl + c| <= 3 eps H (1+eps)^2; total
 *   <= 8.001 eps^2 H, i.e. <= 8.002 eps^2 |x| |y|.
 * dd_add: rounding of xl + yl (<= eps^2 A) and of sl + t, |sl + t| <= 2 eps A (1+eps); total
 *   <= 3.001 eps^2 A, i.e. <= 3.002 eps^2 (|x| + |y|).
 * By induction over the expression, a value whose monomials each pass m products and s sums
 * is off by at most ((1 + 8.002 eps^2)^m (1 + 3.002 eps^2)^s - 1) times its permanent.
 */
struct dd {
    double hi, lo;
};

EFT_INLINE struct dd dd_diff(double a, double b)
{
    struct dd z;
    two_diff(a, b, &z.hi, &z.lo);
    return z;
}

EFT_INLINE struct dd dd_mul(struct dd x, struct dd y)
{
    double ph, pl, c;
    struct dd z;
    two_prod(x.hi, y.hi, &ph, &pl);
    c = x.hi * y.lo + x.lo * y.hi;
    two_sum(ph, pl + c, &z.hi, &z.lo);
    return z;
}

EFT_INLINE struct dd dd_add(struct dd x, struct dd y)
{
    double sh, sl;
    struct dd z;
    two_sum(x.hi, y.hi, &sh, &sl);
    two_sum(sh, sl + (x.lo + y.lo), &z.hi, &z.lo);
    return z;
}

EFT_INLINE struct dd dd_sub(struct dd x, struct dd y)
{
    y.hi = -y.hi;
    y.lo = -y.lo;
    return dd_add(x, y);
}

/* [xy] minor of two dd 3-vectors: x0 y1 - x1 y0 */
EFT_INLINE struct dd dd_minor(const struct dd *x, const struct dd *y)
{
    return dd_sub(dd_mul(x[0], y[1]), dd_mul(x[1], y[0]));
}

#endif /* VP_CORE_MCU */

/* ------------------------------------------------------------------------------------------
 * Input magnitude checks and exact power-of-two rescaling.
 */

static int in_window(const double *const *p, int np, double lo, double hi)
{
    int i, k, ok = 1;
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++) {
            double t = fabs(p[i][k]);
            ok &= (t < hi) & ((t >= lo) | (t == 0.0));
        }
    return ok;
}

static int all_finite(const double *const *p, int np)
{
    int i, k;
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++)
            if (!(fabs(p[i][k]) <= 0x1.fffffffffffffp1023)) return 0;
    return 1;
}

/* floor(log2 |x|) for finite nonzero x. */
static int exponent_of(double x)
{
    uint64_t u;
    int be, k;
    memcpy(&u, &x, sizeof u);
    be = (int)((u >> 52) & 0x7ff);
    if (be) return be - 1023;
    u &= (UINT64_C(1) << 52) - 1;
    for (k = -1075; u; u >>= 1) k++;
    return k;
}

static double pow2(int s) /* 2^s, -1022 <= s <= 1023 */
{
    uint64_t u = (uint64_t)(s + 1023) << 52;
    double r;
    memcpy(&r, &u, sizeof r);
    return r;
}

#ifndef VP_CORE_MCU /* stages A', A, B, C: left out with VP_CORE_MCU (see the top) */
/* Copies the points times 2^s into out[] so that every nonzero |coordinate| lies in
 * [2^lo, 2^hi) (exact: the results are normal). Returns 0 when the spread is too wide. */
static int rescale(const double *const *p, int np, int lo, int hi, double (*out)[3])
{
    int i, k, mn = 4096, mx = -4096, s;
    double f;
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++)
            if (p[i][k] != 0.0) {
                int ex = exponent_of(p[i][k]);
                if (ex < mn) mn = ex;
                if (ex > mx) mx = ex;
            }
    if (mn > mx) mn = mx = 0;
    if (mx - mn >= hi - lo) return 0;
    /* feasible s: lo - mn <= s <= hi - 1 - mx; that interval meets [-1022, 1023] */
    s = lo - mn;
    if (s < -1022) s = -1022;
    f = pow2(s);
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++) out[i][k] = p[i][k] * f;
    return 1;
}

/* ------------------------------------------------------------------------------------------
 * Exactness certificate (stage A', tried first by the tails): when every coordinate is an
 * integer multiple of 2^s and every computed difference p_i - o is below 2^(s + bits) in
 * magnitude, the differences are exact (an exact difference is a multiple of 2^s, and it is
 * below 2^(s + bits) because rounding is monotone), and every product and sum of a
 * floating-point evaluation of a degree-k polynomial in them is an integer multiple of
 * 2^(j s), j <= k, whose magnitude the caller's choice of `bits` keeps below 2^(53 + j s):
 * no rounding anywhere, so the sign is exact, zero included. Typical of integer grids, where
 * filters cannot decide exact zeros. 2^(s + bits) is the power of two just above the largest
 * |difference|. Only s <= 0 is tried (grids with unit or finer spacing relative to their
 * extent): then q / 2^s cannot underflow, and k s >= -1074 keeps subnormals out; no overflow,
 * as 2^(k bits + 7) is small.
 */
/* largest |q - o| so far */
static inline double si_span(double m, const double *q, const double *o)
{
    double dx = fabs(q[0] - o[0]), dy = fabs(q[1] - o[1]), dz = fabs(q[2] - o[2]);
    m = m > dx ? m : dx;
    m = m > dy ? m : dy;
    return m > dz ? m : dz;
}

/* q / 2^s: accumulates the distance to the nearest integers (for |t| < 2^51,
 * (t + 1.5 * 2^52) - 1.5 * 2^52 is t rounded to an integer; no cancellation in the sum) and
 * the largest |t| */
static inline void si_check(const double *q, double inv, double *err, double *big)
{
    double t0 = q[0] * inv, t1 = q[1] * inv, t2 = q[2] * inv;
    double r0 = (t0 + 0x1.8p52) - 0x1.8p52, r1 = (t1 + 0x1.8p52) - 0x1.8p52;
    double r2 = (t2 + 0x1.8p52) - 0x1.8p52, a0 = fabs(t0), a1 = fabs(t1), a2 = fabs(t2), m;
    *err += (fabs(t0 - r0) + fabs(t1 - r1)) + fabs(t2 - r2);
    m = a0 > a1 ? a0 : a1;
    m = m > a2 ? m : a2;
    *big = *big > m ? *big : m;
}

/* inv = 2^-s for the largest difference m, or 0 when s would be positive or too small */
static double si_scale(double m, int bits, int k)
{
    int s;
    if (!(m > 0.0 && m <= 0x1.fffffffffffffp1023)) return 0.0;
    s = exponent_of(m) + 1 - bits;
    if (s > 0 || k * s < -1074) return 0.0;
    return pow2(-s); /* >= 1: q * inv is exact or overflows */
}

/* the certificate for insphere(a, b, c, d, e): differences from e, 9 bits, degree 5 */
static int small_integers5(const double *a, const double *b, const double *c, const double *d,
                           const double *e)
{
    double err = 0.0, big = 0.0;
    double inv = si_scale(si_span(si_span(si_span(si_span(0.0, a, e), b, e), c, e), d, e), 9, 5);
    if (inv == 0.0) return 0;
    si_check(e, inv, &err, &big); /* most inputs that fail, fail here */
    if (err != 0.0) return 0;
    si_check(a, inv, &err, &big);
    si_check(b, inv, &err, &big);
    si_check(c, inv, &err, &big);
    si_check(d, inv, &err, &big);
    return big < 0x1p51 && err == 0.0;
}

/* the certificate for orient3d(a, b, c, d): differences from a, 16 bits, degree 3 */
static int small_integers4(const double *a, const double *b, const double *c, const double *d)
{
    double err = 0.0, big = 0.0;
    double inv = si_scale(si_span(si_span(si_span(0.0, b, a), c, a), d, a), 16, 3);
    if (inv == 0.0) return 0;
    si_check(a, inv, &err, &big);
    if (err != 0.0) return 0;
    si_check(b, inv, &err, &big);
    si_check(c, inv, &err, &big);
    si_check(d, inv, &err, &big);
    return big < 0x1p51 && err == 0.0;
}

#endif /* VP_CORE_MCU */

/* ------------------------------------------------------------------------------------------
 * Stage X: exact integers. Value = limbs (32 bits, little-endian); accumulators are two's
 * complement modulo 2^(32n), multiplicands are magnitudes with a separate sign. Only the final
 * value of an accumulator must fit, so intermediate wrap-around is harmless.
 */

#define LIMBS(bits) ((bits) / 32 + 1) /* 32 * LIMBS(b) >= b + 1: room for a sign bit */
#define BIG_SPAN_MAX 2098             /* |x| < 2^1024 and lowest bit >= 2^-1074 */
#define N1_MAX LIMBS(BIG_SPAN_MAX + 1)           /* difference: < 2^(S+1) */
#define N2_MAX LIMBS(2 * (BIG_SPAN_MAX + 1) + 2) /* 2x2 minor or |v|^2 */
#define N3_MAX LIMBS(3 * (BIG_SPAN_MAX + 1) + 3) /* 3x3 determinant */
#define N5_MAX LIMBS(5 * (BIG_SPAN_MAX + 1) + 7) /* insphere */

struct big_frame {
    int low;            /* every coordinate is an integer multiple of 2^low */
    int n1, n2, n3, n5; /* limbs needed at each degree for this input */
};

/* x = (-1)^sign * m * 2^e. Returns the sign bit; m == 0 for zero. */
static int dbl_parts(double x, uint64_t *m, int *e)
{
    uint64_t u;
    int be;
    memcpy(&u, &x, sizeof u);
    be = (int)((u >> 52) & 0x7ff);
    *m = u & ((UINT64_C(1) << 52) - 1);
    if (be) {
        *m |= UINT64_C(1) << 52;
        *e = be - 1075;
    } else {
        *e = -1074;
    }
    return (int)(u >> 63);
}

/* Sizes the arrays for the np points. Returns 0 when every coordinate is zero. */
static int big_setup(struct big_frame *f, const double *const *p, int np)
{
    int i, k, low = 1 << 20, high = -(1 << 20), span;
    for (i = 0; i < np; i++)
        for (k = 0; k < 3; k++) {
            uint64_t m;
            int e, len = 0;
            dbl_parts(p[i][k], &m, &e);
            if (m == 0) continue;
            while (!(m & 1)) {
                m >>= 1;
                e++;
            }
            if (e < low) low = e;
            while (m >> len) len++;
            if (e + len > high) high = e + len;
        }
    if (low > high) return 0;
    span = high - low; /* |coordinate| / 2^low < 2^span, span <= BIG_SPAN_MAX */
    f->low = low;
    f->n1 = LIMBS(span + 1);
    f->n2 = LIMBS(2 * (span + 1) + 2);
    f->n3 = LIMBS(3 * (span + 1) + 3);
    f->n5 = LIMBS(5 * (span + 1) + 7);
    return 1;
}

/* acc += (neg ? -1 : 1) * m * 2^sh  (mod 2^(32n)). */
static void big_add_mant(uint32_t *acc, int n, uint64_t m, int sh, int neg)
{
    uint32_t v[3];
    int q = sh >> 5, r = sh & 31, k;
    uint64_t carry = 0;
    v[0] = (uint32_t)(m << r);
    v[1] = (uint32_t)(r ? m >> (32 - r) : m >> 32);
    v[2] = (uint32_t)(r ? m >> (64 - r) : 0);
    for (k = q; k < n; k++) {
        uint64_t add = (k - q < 3 ? v[k - q] : 0) + carry;
        if (!neg) {
            uint64_t t = (uint64_t)acc[k] + add;
            acc[k] = (uint32_t)t;
            carry = t >> 32;
        } else {
            carry = (uint64_t)acc[k] < add;
            acc[k] = (uint32_t)((uint64_t)acc[k] - add);
        }
        if (k - q >= 2 && !carry) break;
    }
}

static void big_negate(uint32_t *x, int n)
{
    uint64_t c = 1;
    int k;
    for (k = 0; k < n; k++) {
        uint64_t t = (uint64_t)(uint32_t)~x[k] + c;
        x[k] = (uint32_t)t;
        c = t >> 32;
    }
}

/* Two's complement to magnitude in place; *neg gets the sign. Returns the trimmed length. */
static int big_to_mag(uint32_t *x, int n, int *neg)
{
    *neg = (int)(x[n - 1] >> 31);
    if (*neg) big_negate(x, n);
    while (n > 0 && x[n - 1] == 0) n--;
    return n;
}

static int big_sign(const uint32_t *x, int n)
{
    int k;
    if (x[n - 1] >> 31) return -1;
    for (k = 0; k < n; k++)
        if (x[k]) return 1;
    return 0;
}

/* acc += (neg ? -1 : 1) * a * b  (mod 2^(32n)); a, b magnitudes. */
static void big_madd(uint32_t *acc, int n, const uint32_t *a, int la, const uint32_t *b, int lb,
                     int neg)
{
    int i, j, k;
    if (la == 0 || lb == 0) return;
    if (neg) big_negate(acc, n);
    for (i = 0; i < la && i < n; i++) {
        uint64_t c = 0, ai = a[i];
        if (!ai) continue;
        for (j = 0; j < lb && i + j < n; j++) {
            uint64_t t = (uint64_t)acc[i + j] + ai * b[j] + c;
            acc[i + j] = (uint32_t)t;
            c = t >> 32;
        }
        for (k = i + j; c && k < n; k++) {
            uint64_t t = (uint64_t)acc[k] + c;
            acc[k] = (uint32_t)t;
            c = t >> 32;
        }
    }
    if (neg) big_negate(acc, n);
}

static void big_load(uint32_t *acc, int n, const struct big_frame *f, double x, int neg)
{
    uint64_t m;
    int e, sh;
    neg ^= dbl_parts(x, &m, &e);
    if (m == 0) return;
    sh = e - f->low;
    if (sh < 0) { /* the low bits are zero: see big_setup */
        m >>= -sh;
        sh = 0;
    }
    big_add_mant(acc, n, m, sh, neg);
}

/* d = |x - y| / 2^low, *neg its sign. Returns the length. */
static int big_diff(uint32_t *d, const struct big_frame *f, double x, double y, int *neg)
{
    memset(d, 0, (size_t)f->n1 * sizeof *d);
    big_load(d, f->n1, f, x, 0);
    big_load(d, f->n1, f, y, 1);
    return big_to_mag(d, f->n1, neg);
}

/* acc (n2 limbs) = (p-o)_i (q-o)_j - (p-o)_j (q-o)_i. */
static void big_minor(uint32_t *acc, const struct big_frame *f, const double *p, const double *q,
                      const double *o, int i, int j, uint32_t *d1, uint32_t *d2)
{
    int l1, l2, s1, s2;
    memset(acc, 0, (size_t)f->n2 * sizeof *acc);
    l1 = big_diff(d1, f, p[i], o[i], &s1);
    l2 = big_diff(d2, f, q[j], o[j], &s2);
    big_madd(acc, f->n2, d1, l1, d2, l2, s1 ^ s2);
    l1 = big_diff(d1, f, p[j], o[j], &s1);
    l2 = big_diff(d2, f, q[i], o[i], &s2);
    big_madd(acc, f->n2, d1, l1, d2, l2, !(s1 ^ s2));
}

/* acc3 (n3 limbs) = det[p-o; q-o; r-o], expanded along z. m: n2 limbs scratch. */
static void big_det3(uint32_t *acc3, const struct big_frame *f, const double *p, const double *q,
                     const double *r, const double *o, uint32_t *m, uint32_t *d1, uint32_t *d2)
{
    const double *row[3];
    int k;
    row[0] = p;
    row[1] = q;
    row[2] = r;
    memset(acc3, 0, (size_t)f->n3 * sizeof *acc3);
    for (k = 0; k < 3; k++) {
        int lm, sm, ld, sd;
        big_minor(m, f, row[k == 0 ? 1 : 0], row[k == 2 ? 1 : 2], o, 0, 1, d1, d2);
        lm = big_to_mag(m, f->n2, &sm);
        ld = big_diff(d1, f, row[k][2], o[2], &sd);
        big_madd(acc3, f->n3, d1, ld, m, lm, sd ^ sm ^ (k == 1));
    }
}

static int orient3d_big(const double *a, const double *b, const double *c, const double *d)
{
    uint32_t acc3[N3_MAX], m[N2_MAX], d1[N1_MAX], d2[N1_MAX];
    const double *p[4];
    struct big_frame f;
    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    if (!all_finite(p, 4) || !big_setup(&f, p, 4)) return 0;
    big_det3(acc3, &f, b, c, d, a, m, d1, d2);
    return big_sign(acc3, f.n3);
}

/* sign of w_a bcd - w_b acd + w_c abd - w_d abc, all relative to e (see insphere_fp). */
static int insphere_big(const double *a, const double *b, const double *c, const double *d,
                        const double *e)
{
    uint32_t acc5[N5_MAX], acc3[N3_MAX], m[N2_MAX], d1[N1_MAX], d2[N1_MAX];
    const double *p[5];
    struct big_frame f;
    int i;
    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    p[4] = e;
    if (!all_finite(p, 5) || !big_setup(&f, p, 5)) return 0;
    memset(acc5, 0, (size_t)f.n5 * sizeof *acc5);
    for (i = 0; i < 4; i++) {
        const double *o[3];
        int j, n = 0, l3, s3, lw, sw, k;
        for (j = 0; j < 4; j++)
            if (j != i) o[n++] = p[j];
        big_det3(acc3, &f, o[0], o[1], o[2], e, m, d1, d2);
        l3 = big_to_mag(acc3, f.n3, &s3);
        memset(m, 0, (size_t)f.n2 * sizeof *m);
        for (k = 0; k < 3; k++) {
            int ld, sd;
            ld = big_diff(d1, &f, p[i][k], e[k], &sd);
            big_madd(m, f.n2, d1, ld, d1, ld, 0);
        }
        lw = big_to_mag(m, f.n2, &sw);
        big_madd(acc5, f.n5, m, lw, acc3, l3, s3 ^ (i & 1));
    }
    return big_sign(acc5, f.n5);
}

static int orient2d_big(const double *a, const double *b, const double *c, int i, int j)
{
    uint32_t m[N2_MAX], d1[N1_MAX], d2[N1_MAX];
    const double *p[3];
    struct big_frame f;
    p[0] = a;
    p[1] = b;
    p[2] = c;
    if (!all_finite(p, 3) || !big_setup(&f, p, 3)) return 0;
    big_minor(m, &f, b, c, a, i, j, d1, d2);
    return big_sign(m, f.n2);
}

static int cmp_dist_big(const double *p, const double *q, const double *r)
{
    uint32_t acc[N2_MAX], d1[N1_MAX];
    const double *pt[3];
    struct big_frame f;
    int k;
    pt[0] = p;
    pt[1] = q;
    pt[2] = r;
    if (!all_finite(pt, 3) || !big_setup(&f, pt, 3)) return 0;
    memset(acc, 0, (size_t)f.n2 * sizeof *acc);
    for (k = 0; k < 3; k++) {
        int l, s;
        l = big_diff(d1, &f, q[k], p[k], &s);
        big_madd(acc, f.n2, d1, l, d1, l, 0);
        l = big_diff(d1, &f, r[k], p[k], &s);
        big_madd(acc, f.n2, d1, l, d1, l, 1);
    }
    return big_sign(acc, f.n2);
}

/* ------------------------------------------------------------------------------------------
 * orient3d = det[b-a; c-a; d-a]
 *          = Wz (Ux Vy - Uy Vx) + Vz (Uy Wx - Ux Wy) + Uz (Vx Wy - Vy Wx),  U,V,W = b-a, c-a, d-a.
 * Stage A roundings per monomial: 3 differences, product, minor, scale, 2 sums = 8.
 */

#ifndef VP_CORE_MCU /* stages A', A, B, C: left out with VP_CORE_MCU (see the top) */
/* Stage B: path of a monomial: minor product and difference, scale, 2 sums: m = 2, s = 3,
 * error <= 25.02 eps^2 P_abs; P_abs (exact differences) <= (1+eps)^3 P_h and the permanent of
 * the rounded differences P_h <= P / (1-eps)^5 (P as computed in stage A): < 25.1 eps^2 P.
 * Deciding on |hi| > fl(32 eps^2 P) leaves |det| >= |hi| (1-eps) above that. */
static int orient3d_dd(const double *a, const double *b, const double *c, const double *d,
                       double perm)
{
    struct dd u[3], v[3], w[3], det;
    double bound = O3_ERR_B * perm;
    int k;
    for (k = 0; k < 3; k++) {
        u[k] = dd_diff(b[k], a[k]);
        v[k] = dd_diff(c[k], a[k]);
        w[k] = dd_diff(d[k], a[k]);
    }
    det = dd_add(dd_add(dd_mul(w[2], dd_minor(u, v)), dd_mul(v[2], dd_minor(w, u))),
                 dd_mul(u[2], dd_minor(v, w)));
    if (det.hi > bound) return 1;
    if (-det.hi > bound) return -1;
    return UNDECIDED;
}

/* Stage C. */
static int orient3d_exact_diff(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3], t, m[4], s1[8], s2[8], s3[8], s12[16], det[24];
    int k, n1, n2, n3, n12, n, inexact = 0;
    for (k = 0; k < 3; k++) {
        two_diff(b[k], a[k], &u[k], &t);
        inexact |= t != 0.0;
        two_diff(c[k], a[k], &v[k], &t);
        inexact |= t != 0.0;
        two_diff(d[k], a[k], &w[k], &t);
        inexact |= t != 0.0;
    }
    if (inexact) return UNDECIDED;
    n = prod_diff(u[0], v[1], u[1], v[0], m);
    n1 = exp_scale(m, n, w[2], s1);
    n = prod_diff(u[1], w[0], u[0], w[1], m);
    n2 = exp_scale(m, n, v[2], s2);
    n = prod_diff(v[0], w[1], v[1], w[0], m);
    n3 = exp_scale(m, n, u[2], s3);
    n12 = exp_sum(s1, n1, s2, n2, s12);
    n = exp_sum(s12, n12, s3, n3, det);
    return exp_sign(det, n);
}

static int orient3d_fp(const double *a, const double *b, const double *c, const double *d,
                       struct vp_pred_stats *st)
{
    double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    double uvx = ux * vy, vux = uy * vx, uwy = uy * wx, wuy = ux * wy, vwx = vx * wy, wvx = vy * wx;
    double det = (wz * (uvx - vux) + vz * (uwy - wuy)) + uz * (vwx - wvx);
    double perm = (fabs(wz) * (fabs(uvx) + fabs(vux)) + fabs(vz) * (fabs(uwy) + fabs(wuy)))
                  + fabs(uz) * (fabs(vwx) + fabs(wvx));
    double bound = O3_ERR_A * perm;
    int r;
    if (det > bound || -det > bound || perm == 0.0) {
        COUNT(st, stage[VP_STAGE_FILTER]);
        return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
    }
    r = orient3d_dd(a, b, c, d, perm);
    if (r != UNDECIDED) {
        COUNT(st, stage[VP_STAGE_DD]);
        return r;
    }
    r = orient3d_exact_diff(a, b, c, d);
    if (r != UNDECIDED) {
        COUNT(st, stage[VP_STAGE_EXACTDIFF]);
        return r;
    }
    COUNT(st, stage[VP_STAGE_BIGINT]);
    return orient3d_big(a, b, c, d);
}

#endif /* VP_CORE_MCU */

static int orient3d_tail(const double *a, const double *b, const double *c, const double *d,
                         struct vp_pred_stats *st)
{
#ifdef VP_CORE_MCU
    COUNT(st, stage[VP_STAGE_BIGINT]);
    return orient3d_big(a, b, c, d);
#else
    const double *p[4];
    double sc[4][3];
    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    /* 16 bits: minors < 2^33, terms < 2^49, det < 3 * 2^49 */
    if (small_integers4(a, b, c, d)) {
        double det = vp_orient3d_det_(a, b, c, d);
        COUNT(st, stage[VP_STAGE_EXACTDIFF]);
        return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
    }
    if (!in_window(p, 4, 0x1p-248, 0x1p320)) {
        if (!all_finite(p, 4)) return 0;
        if (!rescale(p, 4, W3_LO, W3_HI, sc)) {
            COUNT(st, stage[VP_STAGE_BIGINT]);
            return orient3d_big(a, b, c, d);
        }
        COUNT(st, rescaled);
        return orient3d_fp(sc[0], sc[1], sc[2], sc[3], st);
    }
    return orient3d_fp(a, b, c, d, st);
#endif
}

int vp_orient3d_stats(const double *a, const double *b, const double *c, const double *d,
                      struct vp_pred_stats *st)
{
    int r = vp_orient3d_filter(a, b, c, d);
    if (r != VP_PRED_UNSURE) {
        COUNT(st, stage[VP_STAGE_FILTER]);
        return r;
    }
    return orient3d_tail(a, b, c, d, st);
}

int vp_orient3d_tail(const double *a, const double *b, const double *c, const double *d)
{
    return orient3d_tail(a, b, c, d, 0);
}

int vp_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    return vp_orient3d_stats(a, b, c, d, 0);
}

/* ------------------------------------------------------------------------------------------
 * insphere. With A..D = a-e .. d-e, w_X = |X|^2 and [XY] = Xx Yy - Xy Yx:
 *   XYZ = det[X; Y; Z] = Xz [YZ] - Yz [XZ] + Zz [XY]
 *   D'  = w_A BCD - w_B ACD + w_C ABD - w_D ABC,
 * which is minus the 4x4 determinant of the rows (X, w_X) (expansion along the lift column).
 * For a positive tetrahedron D' > 0 when e is inside (check: unit corner tetrahedron, e its
 * circumcentre: D' = 0.75 * orient3d = 0.75). 72 monomials of degree 5.
 * Stage A roundings per monomial: differences 5, lift 3 (square + 2 sums), minor 2, det3 3
 * (scale + 2 sums), final 3 (product + 2 sums) = 16; the permanent takes the same path.
 */

#ifndef VP_CORE_MCU /* stages A', A, B, C: left out with VP_CORE_MCU (see the top) */
static const int other3[4][3] = { { 1, 2, 3 }, { 0, 2, 3 }, { 0, 1, 3 }, { 0, 1, 2 } };

/* Stage B. Path of a monomial: lift (square, 2 sums), minor (product, difference), det3
 * (scale, 2 sums), final (product, 2 sums): m = 4, s = 7, error <= 53.03 eps^2 P_abs, with
 * P_abs <= (1+eps)^5 P_h <= (1+eps)^5 P / (1-eps)^11 (P as computed in stage A): < 53.1 eps^2 P.
 * Deciding on |hi| > fl(64 eps^2 P) leaves |det| >= |hi| (1-eps) above that. */
static int insphere_dd(const double *a, const double *b, const double *c, const double *d,
                       const double *e, double perm)
{
    struct dd h[4][3], mnr[4][4], det3, lift, term[4], det;
    const double *p[4];
    double bound = IS_ERR_B * perm;
    int i, j, k;
    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    for (i = 0; i < 4; i++)
        for (k = 0; k < 3; k++) h[i][k] = dd_diff(p[i][k], e[k]);
    for (i = 0; i < 4; i++)
        for (j = i + 1; j < 4; j++) mnr[i][j] = dd_minor(h[i], h[j]);
    for (i = 0; i < 4; i++) {
        int x = other3[i][0], y = other3[i][1], z = other3[i][2];
        det3 = dd_add(dd_sub(dd_mul(h[x][2], mnr[y][z]), dd_mul(h[y][2], mnr[x][z])),
                      dd_mul(h[z][2], mnr[x][y]));
        lift = dd_add(dd_add(dd_mul(h[i][0], h[i][0]), dd_mul(h[i][1], h[i][1])),
                      dd_mul(h[i][2], h[i][2]));
        term[i] = dd_mul(lift, det3);
    }
    det = dd_add(dd_sub(term[0], term[1]), dd_sub(term[2], term[3]));
    if (det.hi > bound) return 1;
    if (-det.hi > bound) return -1;
    return UNDECIDED;
}

#define ACC_CAP 64 /* stage C accumulator; longer (rare) means go to stage X */

/* Stage C: the differences are exact doubles; D' exactly with expansions. */
static int insphere_exact_diff(const double *a, const double *b, const double *c,
                               const double *d, const double *e)
{
    const double *p[4];
    double h[4][3];
    double mnr[4][4][4]; /* exact [XY] minors, mnr[i][j] for i < j */
    int mlen[4][4];
    double acc[2][ACC_CAP], d3[24], s1[8], s2[8], s3[8], s12[16], w[6], term[48];
    int i, j, k, alen = 0, cur = 0;

    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    for (i = 0; i < 4; i++)
        for (k = 0; k < 3; k++) {
            double t;
            two_diff(p[i][k], e[k], &h[i][k], &t);
            if (t != 0.0) return UNDECIDED;
        }
    for (i = 0; i < 4; i++)
        for (j = i + 1; j < 4; j++)
            mlen[i][j] = prod_diff(h[i][0], h[j][1], h[j][0], h[i][1], mnr[i][j]);
    for (i = 0; i < 4; i++) {
        int x = other3[i][0], y = other3[i][1], z = other3[i][2];
        int n1, n2, n3, n12, n, nw, q;
        n1 = exp_scale(mnr[y][z], mlen[y][z], h[x][2], s1);
        n2 = exp_scale(mnr[x][z], mlen[x][z], -h[y][2], s2);
        n3 = exp_scale(mnr[x][y], mlen[x][y], h[z][2], s3);
        n12 = exp_sum(s1, n1, s2, n2, s12);
        n = exp_compress(d3, exp_sum(s12, n12, s3, n3, d3));
        nw = exp_compress(w, exp_norm2(h[i], w));
        for (q = 0; q < nw; q++) {
            int nt = exp_scale(d3, n, (i & 1) ? -w[q] : w[q], term);
            if (alen + nt > ACC_CAP) {
                alen = exp_compress(acc[cur], alen);
                if (alen + nt > ACC_CAP) return UNDECIDED;
            }
            alen = exp_sum(acc[cur], alen, term, nt, acc[cur ^ 1]);
            cur ^= 1;
        }
        alen = exp_compress(acc[cur], alen);
    }
    return exp_sign(acc[cur], alen);
}

static int insphere_fp(const double *a, const double *b, const double *c, const double *d,
                       const double *e, struct vp_pred_stats *st)
{
    double aex = a[0] - e[0], aey = a[1] - e[1], aez = a[2] - e[2];
    double bex = b[0] - e[0], bey = b[1] - e[1], bez = b[2] - e[2];
    double cex = c[0] - e[0], cey = c[1] - e[1], cez = c[2] - e[2];
    double dex = d[0] - e[0], dey = d[1] - e[1], dez = d[2] - e[2];
    double abx = aex * bey, bax = bex * aey, acx = aex * cey, cax = cex * aey;
    double adx = aex * dey, dax = dex * aey, bcx = bex * cey, cbx = cex * bey;
    double bdx = bex * dey, dbx = dex * bey, cdx = cex * dey, dcx = dex * cey;
    double ab = abx - bax, ac = acx - cax, ad = adx - dax;
    double bc = bcx - cbx, bd = bdx - dbx, cd = cdx - dcx;
    double abp = fabs(abx) + fabs(bax), acp = fabs(acx) + fabs(cax), adp = fabs(adx) + fabs(dax);
    double bcp = fabs(bcx) + fabs(cbx), bdp = fabs(bdx) + fabs(dbx), cdp = fabs(cdx) + fabs(dcx);
    double bcd = (bez * cd - cez * bd) + dez * bc;
    double acd = (aez * cd - cez * ad) + dez * ac;
    double abd = (aez * bd - bez * ad) + dez * ab;
    double abc = (aez * bc - bez * ac) + cez * ab;
    double bcdp = (fabs(bez) * cdp + fabs(cez) * bdp) + fabs(dez) * bcp;
    double acdp = (fabs(aez) * cdp + fabs(cez) * adp) + fabs(dez) * acp;
    double abdp = (fabs(aez) * bdp + fabs(bez) * adp) + fabs(dez) * abp;
    double abcp = (fabs(aez) * bcp + fabs(bez) * acp) + fabs(cez) * abp;
    double al = (aex * aex + aey * aey) + aez * aez;
    double bl = (bex * bex + bey * bey) + bez * bez;
    double cl = (cex * cex + cey * cey) + cez * cez;
    double dl = (dex * dex + dey * dey) + dez * dez;
    double det = (al * bcd - bl * acd) + (cl * abd - dl * abc);
    double perm = (al * bcdp + bl * acdp) + (cl * abdp + dl * abcp);
    double bound = IS_ERR_A * perm;
    int r;
    if (det > bound || -det > bound || perm == 0.0) {
        COUNT(st, stage[VP_STAGE_FILTER]);
        return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
    }
    r = insphere_dd(a, b, c, d, e, perm);
    if (r != UNDECIDED) {
        COUNT(st, stage[VP_STAGE_DD]);
        return r;
    }
    r = insphere_exact_diff(a, b, c, d, e);
    if (r != UNDECIDED) {
        COUNT(st, stage[VP_STAGE_EXACTDIFF]);
        return r;
    }
    COUNT(st, stage[VP_STAGE_BIGINT]);
    return insphere_big(a, b, c, d, e);
}

#endif /* VP_CORE_MCU */

static int insphere_tail(const double *a, const double *b, const double *c, const double *d,
                         const double *e, struct vp_pred_stats *st)
{
#ifdef VP_CORE_MCU
    COUNT(st, stage[VP_STAGE_BIGINT]);
    return insphere_big(a, b, c, d, e);
#else
    const double *p[5];
    double sc[5][3];
    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    p[4] = e;
    /* 9 bits: minors < 2^19, det3 < 6 * 2^27, lifts < 3 * 2^18, det < 72 * 2^45 */
    if (small_integers5(a, b, c, d, e)) {
        double det = vp_insphere_det_(a, b, c, d, e);
        COUNT(st, stage[VP_STAGE_EXACTDIFF]);
        return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
    }
    if (!in_window(p, 5, 0x1p-128, 0x1p190)) {
        if (!all_finite(p, 5)) return 0;
        if (!rescale(p, 5, W5_LO, W5_HI, sc)) {
            COUNT(st, stage[VP_STAGE_BIGINT]);
            return insphere_big(a, b, c, d, e);
        }
        COUNT(st, rescaled);
        return insphere_fp(sc[0], sc[1], sc[2], sc[3], sc[4], st);
    }
    return insphere_fp(a, b, c, d, e, st);
#endif
}

int vp_insphere_stats(const double *a, const double *b, const double *c, const double *d,
                      const double *e, struct vp_pred_stats *st)
{
    int r = vp_insphere_filter(a, b, c, d, e);
    if (r != VP_PRED_UNSURE) {
        COUNT(st, stage[VP_STAGE_FILTER]);
        return r;
    }
    return insphere_tail(a, b, c, d, e, st);
}

int vp_insphere_tail(const double *a, const double *b, const double *c, const double *d,
                     const double *e)
{
    return insphere_tail(a, b, c, d, e, 0);
}

int vp_insphere(const double *a, const double *b, const double *c, const double *d,
                const double *e)
{
    return vp_insphere_stats(a, b, c, d, e, 0);
}

double vp_insphere_det(const double *a, const double *b, const double *c, const double *d,
                       const double *e)
{
    return vp_insphere_det_(a, b, c, d, e);
}

double vp_orient3d_det(const double *a, const double *b, const double *c, const double *d)
{
    return vp_orient3d_det_(a, b, c, d);
}

int vp_orient3d_filter_ss(const double *a, const double *b, const double *c, const double *d)
{
    return vp_orient3d_filter(a, b, c, d);
}

int vp_insphere_filter_ss(const double *a, const double *b, const double *c, const double *d,
                          const double *e)
{
    return vp_insphere_filter(a, b, c, d, e);
}

/* ------------------------------------------------------------------------------------------
 * Static filter bounds (see vp_pred.h): the semi-static bounds with the box extents as the
 * maxima. A computed extent is at least (1 - eps) times the exact one, as a computed maximum
 * of differences is, so the derivation is unchanged.
 */
static int box_extents(const double lo[3], const double hi[3], double s[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        s[k] = hi[k] - lo[k];
        if (!(s[k] >= VP_PRED_FILTER_LO && s[k] <= VP_PRED_FILTER_HI)) return 0;
    }
    return 1;
}

double vp_orient3d_static_bound(const double lo[3], const double hi[3])
{
    double s[3];
    if (!box_extents(lo, hi, s)) return HUGE_VAL;
    return VP_PRED_FILTER_O3 * ((s[0] * s[1]) * s[2]);
}

double vp_insphere_static_bound(const double lo[3], const double hi[3])
{
    double s[3];
    if (!box_extents(lo, hi, s)) return HUGE_VAL;
    return VP_PRED_FILTER_IS * ((((s[0] * s[0] + s[1] * s[1]) + s[2] * s[2]) *
                                 ((s[0] * s[1]) * s[2])));
}

int vp_lowest_bit(double x)
{
    uint64_t m;
    int e;
    dbl_parts(x, &m, &e);
    return e + exponent_of((double)(m & (~m + 1u))); /* the lowest set bit, exactly */
}

/* Extents below 2^(lowbit + bits) with 2^lowbit a unit every coordinate is a multiple of:
 * the differences are integers below 2^bits units, computed exactly (their exact values are
 * representable). orient3d (bits 16): minors < 2^33, scaled < 2^49, det < 3 * 2^49 units.
 * insphere (bits 9), scalar form: minors < 2^19, det3 < 3 * 2^28, lifts < 3 * 2^18,
 * det < 36 * 2^46; two-lane form: m < 2^19, n < 3 * 2^28, m n < 3 * 2^47, det < 18 * 2^47.
 * All below 2^53 units, units (2^(k lowbit), k <= degree) are >= 2^-1074, and values stay
 * below 2^(degree (lowbit + bits) + 7) <= 2^1023: no rounding, no overflow. */
static int box_exact(const double lo[3], const double hi[3], int lowbit, int bits, int degree)
{
    int k;
    if (degree * lowbit < -1074 || degree * (lowbit + bits) + 7 > 1023) return 0;
    for (k = 0; k < 3; k++)
        if (!(hi[k] - lo[k] < pow2(lowbit + bits))) return 0;
    return 1;
}

int vp_orient3d_box_exact(const double lo[3], const double hi[3], int lowbit)
{
    return box_exact(lo, hi, lowbit, 16, 3);
}

int vp_insphere_box_exact(const double lo[3], const double hi[3], int lowbit)
{
    return box_exact(lo, hi, lowbit, 9, 5);
}

/* ------------------------------------------------------------------------------------------
 * Symbolic perturbation. Let M be the 5x5 matrix with rows (x, y, z, |q|^2, 1) for q = a..e.
 * Subtracting e's row and then 2 e_x (resp. y, z) times the x (y, z) column from the lift
 * column leaves rows (q - e, |q - e|^2, 0) and (e, |e|^2, 1): det M = det4(rows (X, w_X)) = -D'.
 * So insphere = -sign(det M). Lifting q by delta_q adds delta_q times the cofactor of its lift
 * entry; the deltas sit in one column, so det M is exactly linear in them:
 *   det M(delta) = det M + sum_q delta_q C_q,  C_q = (-1)^(i+4) det4(rows (p, 1), p != q),
 * with i the row of q (1..5). Since det4(rows (p1..p4, 1)) = -orient3d(p1, p2, p3, p4)
 * (subtract row 1, expand along the ones column), C_q = (-1)^(i+1) orient3d(others in order):
 *   C_a = +o(b,c,d,e), C_b = -o(a,c,d,e), C_c = +o(a,b,d,e), C_d = -o(a,b,c,e), C_e = +o(a,b,c,d).
 * With delta_q = eps^rank(q), the lexicographically largest point dominating, the perturbed
 * insphere is -sign(C_q) of the first point q (lexicographically decreasing) with C_q != 0.
 * For a positive tetrahedron C_e = orient3d(a,b,c,d) > 0, so the answer is never 0 unless two
 * points coincide (then det M(delta) is identically 0: two equal rows).
 */

static int lex_cmp(const double *a, const double *b)
{
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
    if (a[2] != b[2]) return a[2] < b[2] ? -1 : 1;
    return 0;
}

static int insphere_perturbed(const double *a, const double *b, const double *c,
                              const double *d, const double *e, struct vp_pred_stats *st,
                              double o3b)
{
    static const unsigned char others[5][4] = {
        { 1, 2, 3, 4 }, { 0, 2, 3, 4 }, { 0, 1, 3, 4 }, { 0, 1, 2, 4 }, { 0, 1, 2, 3 }
    };
    const double *p[5];
    unsigned used = 0;
    int i, j;
    p[0] = a;
    p[1] = b;
    p[2] = c;
    p[3] = d;
    p[4] = e;
    /* points by decreasing lexicographic order, selected one at a time: usually the first
     * decides. Coincident points give 0 (the perturbation cannot separate them): while the
     * largest remaining point q has a twin, C_q' = 0 for every q' before it (the twins are
     * both among the other four), and selecting q compares it with its twin. */
    for (i = 0; i < 5; i++) {
        int q = -1, o;
        const unsigned char *r;
        for (j = 0; j < 5; j++) {
            int cmp;
            if (used & (1u << j)) continue;
            if (q < 0) { q = j; continue; }
            cmp = lex_cmp(p[j], p[q]);
            if (cmp == 0) return 0; /* coincident points */
            if (cmp > 0) q = j;
        }
        used |= 1u << q;
        r = others[q];
        if (o3b == HUGE_VAL) {
            o = vp_orient3d_fast(p[r[0]], p[r[1]], p[r[2]], p[r[3]]);
        } else {
            o = vp_orient3d_filter_b(p[r[0]], p[r[1]], p[r[2]], p[r[3]], o3b);
            if (o == VP_PRED_UNSURE)
                o = o3b == 0.0 ? 0 : vp_orient3d_tail(p[r[0]], p[r[1]], p[r[2]], p[r[3]]);
        }
        if (q & 1) o = -o; /* rows 2 and 4 (b, d) take a minus sign */
        if (o != 0) {
            COUNT(st, sos);
            return -o;
        }
    }
    return 0;
}

int vp_insphere_sos_stats(const double *a, const double *b, const double *c, const double *d,
                          const double *e, struct vp_pred_stats *st)
{
    int s = vp_insphere_stats(a, b, c, d, e, st);
    return s != 0 ? s : insphere_perturbed(a, b, c, d, e, st, HUGE_VAL);
}

int vp_insphere_sos_zero(const double *a, const double *b, const double *c, const double *d,
                         const double *e)
{
    return insphere_perturbed(a, b, c, d, e, 0, HUGE_VAL);
}

int vp_insphere_sos_zero_b(const double *a, const double *b, const double *c, const double *d,
                           const double *e, double o3_static_bound)
{
    return insphere_perturbed(a, b, c, d, e, 0, o3_static_bound);
}

int vp_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                    const double *e)
{
    return vp_insphere_sos_stats(a, b, c, d, e, 0);
}

/* ------------------------------------------------------------------------------------------
 * orient2d on a coordinate plane: (b-a)_i (c-a)_j - (b-a)_j (c-a)_i, i, j = drop+1, drop+2 (mod 3).
 * Stage A roundings: 2 differences, product, difference = 4.
 */

static int orient2d_fp(const double *a, const double *b, const double *c, int i, int j,
                       struct vp_pred_stats *st)
{
    double ui = b[i] - a[i], uj = b[j] - a[j], vi = c[i] - a[i], vj = c[j] - a[j];
    double l = ui * vj, r = uj * vi;
    double det = l - r, bound = O2_ERR_A * (fabs(l) + fabs(r));
#ifndef VP_CORE_MCU
    double t1, t2, t3, t4, m[4];
#endif
    if (det > bound || -det > bound || bound == 0.0) {
        COUNT(st, stage[VP_STAGE_FILTER]);
        return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
    }
#ifndef VP_CORE_MCU
    two_diff(b[i], a[i], &ui, &t1);
    two_diff(b[j], a[j], &uj, &t2);
    two_diff(c[i], a[i], &vi, &t3);
    two_diff(c[j], a[j], &vj, &t4);
    if (t1 == 0.0 && t2 == 0.0 && t3 == 0.0 && t4 == 0.0) {
        COUNT(st, stage[VP_STAGE_EXACTDIFF]);
        return exp_sign(m, prod_diff(ui, vj, uj, vi, m));
    }
#endif
    COUNT(st, stage[VP_STAGE_BIGINT]);
    return orient2d_big(a, b, c, i, j);
}

int vp_orient2d_proj_stats(const double *a, const double *b, const double *c, int drop,
                           struct vp_pred_stats *st)
{
    const double *p[3];
#ifndef VP_CORE_MCU
    double sc[3][3];
#endif
    int i = drop == 0 ? 1 : (drop == 1 ? 2 : 0);
    int j = drop == 0 ? 2 : (drop == 1 ? 0 : 1);
    p[0] = a;
    p[1] = b;
    p[2] = c;
    if (!in_window(p, 3, 0x1p-398, 0x1p480)) {
        if (!all_finite(p, 3)) return 0;
#ifndef VP_CORE_MCU
        if (rescale(p, 3, W2_LO, W2_HI, sc)) {
            COUNT(st, rescaled);
            return orient2d_fp(sc[0], sc[1], sc[2], i, j, st);
        }
#endif
        COUNT(st, stage[VP_STAGE_BIGINT]);
        return orient2d_big(a, b, c, i, j);
    }
    return orient2d_fp(a, b, c, i, j, st);
}

int vp_orient2d_proj(const double *a, const double *b, const double *c, int drop)
{
    return vp_orient2d_proj_stats(a, b, c, drop, 0);
}

/* ------------------------------------------------------------------------------------------
 * cmp_dist: |q-p|^2 - |r-p|^2. Stage A roundings: 2 differences, square, 2 sums, final
 * difference = 6; the permanent is the sum of the two squared norms.
 */

static int cmp_dist_fp(const double *p, const double *q, const double *r,
                       struct vp_pred_stats *st)
{
    double qx = q[0] - p[0], qy = q[1] - p[1], qz = q[2] - p[2];
    double rx = r[0] - p[0], ry = r[1] - p[1], rz = r[2] - p[2];
    double sq = (qx * qx + qy * qy) + qz * qz, sr = (rx * rx + ry * ry) + rz * rz;
    double det = sq - sr, bound = CD_ERR_A * (sq + sr);
#ifndef VP_CORE_MCU
    double dq[3], dr[3], hq[6], hr[6], h[12];
    int k, inexact = 0, nq, nr;
#endif
    if (det > bound || -det > bound || bound == 0.0) {
        COUNT(st, stage[VP_STAGE_FILTER]);
        return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
    }
#ifndef VP_CORE_MCU
    for (k = 0; k < 3; k++) {
        double t;
        two_diff(q[k], p[k], &dq[k], &t);
        inexact |= t != 0.0;
        two_diff(r[k], p[k], &dr[k], &t);
        inexact |= t != 0.0;
    }
    if (!inexact) {
        COUNT(st, stage[VP_STAGE_EXACTDIFF]);
        nq = exp_norm2(dq, hq);
        nr = exp_norm2(dr, hr);
        for (k = 0; k < nr; k++) hr[k] = -hr[k];
        return exp_sign(h, exp_sum(hq, nq, hr, nr, h));
    }
#endif
    COUNT(st, stage[VP_STAGE_BIGINT]);
    return cmp_dist_big(p, q, r);
}

int vp_cmp_dist_stats(const double *p, const double *q, const double *r,
                      struct vp_pred_stats *st)
{
    const double *pt[3];
#ifndef VP_CORE_MCU
    double sc[3][3];
#endif
    pt[0] = p;
    pt[1] = q;
    pt[2] = r;
    if (!in_window(pt, 3, 0x1p-398, 0x1p480)) {
        if (!all_finite(pt, 3)) return 0;
#ifndef VP_CORE_MCU
        if (rescale(pt, 3, W2_LO, W2_HI, sc)) {
            COUNT(st, rescaled);
            return cmp_dist_fp(sc[0], sc[1], sc[2], st);
        }
#endif
        COUNT(st, stage[VP_STAGE_BIGINT]);
        return cmp_dist_big(p, q, r);
    }
    return cmp_dist_fp(p, q, r, st);
}

int vp_cmp_dist(const double *p, const double *q, const double *r)
{
    return vp_cmp_dist_stats(p, q, r, 0);
}

int vp_lex_cmp(const double *a, const double *b)
{
    int k;
    for (k = 0; k < 3; k++) {
        if (a[k] < b[k]) return -1;
        if (a[k] > b[k]) return 1;
    }
    return 0;
}
