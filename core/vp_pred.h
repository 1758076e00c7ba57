/* vp_pred — exact geometric predicates for voroprobe.
 *
 * Every function returns the exact sign (-1, 0, +1) of a polynomial in its double inputs, for all
 * finite doubles: a floating-point filter answers the easy cases, exact arithmetic the rest.
 * No state, no globals, no heap; stack use is bounded (see vp_pred.c).
 *
 * Conventions (points are const double[3]):
 *   vp_orient3d(a,b,c,d) = sign of ((b-a) x (c-a)) . (d-a).
 *       > 0: d lies on the side of plane (a,b,c) that the right-hand normal of (a,b,c) points to.
 *       A tetrahedron (a,b,c,d) is "positive" when vp_orient3d(a,b,c,d) > 0.
 *   vp_insphere(a,b,c,d,e), for a positive (a,b,c,d):
 *       > 0: e strictly inside the circumsphere, < 0 strictly outside, 0 on it.
 *   vp_insphere_sos(a,b,c,d,e): the same test under a symbolic perturbation (simulation of
 *       simplicity) of the lifting: each point q is lifted to |q|^2 + eps^rank(q) where the
 *       lexicographically larger point (x, then y, then z) gets the larger perturbation. A larger
 *       lift moves a point outward, so among cospherical points the lexicographically largest
 *       one is "outside". Never returns 0 when (a,b,c,d) is non-degenerate and e differs from
 *       a,b,c,d. Independent of the order points were inserted in, so the triangulation of a set
 *       is unique.
 */
#ifndef VP_PRED_H
#define VP_PRED_H

#include <math.h>

int vp_orient3d(const double *a, const double *b, const double *c, const double *d);
int vp_insphere(const double *a, const double *b, const double *c, const double *d,
                const double *e);
int vp_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                    const double *e);

/* vp_insphere_sos for inputs already known to give vp_insphere(a,b,c,d,e) == 0: only the
 * perturbation is evaluated (0 when two of the points coincide). */
int vp_insphere_sos_zero(const double *a, const double *b, const double *c, const double *d,
                         const double *e);
/* The same with the orient3d static bound for a box holding the five points (see
 * vp_orient3d_filter_b; 0 for a box where vp_orient3d_box_exact holds; HUGE_VAL: none). */
int vp_insphere_sos_zero_b(const double *a, const double *b, const double *c, const double *d,
                           const double *e, double o3_static_bound);

/* The exact stages that follow the inline filters below: same results as vp_orient3d and
 * vp_insphere, for callers that already ran vp_*_filter and got VP_PRED_UNSURE. */
int vp_orient3d_tail(const double *a, const double *b, const double *c, const double *d);
int vp_insphere_tail(const double *a, const double *b, const double *c, const double *d,
                     const double *e);

/* Sign of orient2d of the projections of a,b,c on the coordinate plane that drops axis `drop`
 * (0 = x, 1 = y, 2 = z): ((b-a) x (c-a)) component along the dropped axis. */
int vp_orient2d_proj(const double *a, const double *b, const double *c, int drop);

/* Sign of |p-q|^2 - |p-r|^2: < 0 when q is strictly closer to p than r. */
int vp_cmp_dist(const double *p, const double *q, const double *r);

/* Lexicographic comparison (x, then y, then z): -1, 0 (equal points), +1. */
int vp_lex_cmp(const double *a, const double *b);

/* Which stage answered a call, for tests and benchmarks. The caller owns the struct (zero it
 * first); the plain functions above keep no counts. */
enum vp_pred_stage {
    VP_STAGE_FILTER,     /* floating-point evaluation with a static error bound */
    VP_STAGE_DD,         /* double-double evaluation with an eps^2 error bound */
    VP_STAGE_EXACTDIFF,  /* differences were exact: expansion arithmetic on them */
    VP_STAGE_BIGINT,     /* exact integer arithmetic on the scaled coordinates */
    VP_STAGE_COUNT
};
struct vp_pred_stats {
    unsigned long stage[VP_STAGE_COUNT];
    unsigned long rescaled;  /* inputs first scaled by a power of two into the safe range */
    unsigned long sos;       /* vp_insphere_sos_stats: answered by the perturbation */
};
int vp_orient3d_stats(const double *a, const double *b, const double *c, const double *d,
                      struct vp_pred_stats *st);
int vp_insphere_stats(const double *a, const double *b, const double *c, const double *d,
                      const double *e, struct vp_pred_stats *st);
int vp_insphere_sos_stats(const double *a, const double *b, const double *c, const double *d,
                          const double *e, struct vp_pred_stats *st);
int vp_orient2d_proj_stats(const double *a, const double *b, const double *c, int drop,
                           struct vp_pred_stats *st);
int vp_cmp_dist_stats(const double *p, const double *q, const double *r,
                      struct vp_pred_stats *st);

/* ------------------------------------------------------------------------------------------
 * Inline semi-static filters: the exact sign (+1 or -1) when a floating-point evaluation
 * certifies it, VP_PRED_UNSURE otherwise (never 0). Cheap enough for inner loops; follow an
 * UNSURE with vp_orient3d_tail / vp_insphere_tail (or use vp_orient3d_fast / vp_insphere_fast).
 *
 * Error bound. Let m_x, m_y, m_z be the largest |x|, |y|, |z| of the computed differences.
 * Each of the N monomials of the polynomial is a product of exact differences, one or two per
 * axis; the evaluation below multiplies each by at most (1 + eps)^r (r roundings along its
 * path, the rounding of the differences included; eps = 2^-53), so
 *   |det_computed - det| <= ((1 + eps)^r - 1) * sum |monomials|,
 * and sum |monomials| is bounded through the maxima (exact differences are at most
 * (1 - eps)^-1 times the computed ones):
 *   orient3d: N = 6, each |u_x v_y w_z| <= m_x m_y m_z, r = 8 (3 differences, product, minor,
 *     scale, 2 sums): error <= 48 eps (1 + 20 eps) m_x m_y m_z.
 *   insphere: N = 72 = 4 lifts (3 squares, sum <= L = m_x^2 + m_y^2 + m_z^2) x 6 monomials of
 *     a 3x3 determinant (each <= m_x m_y m_z), r = 16 (5 differences, lift 3, minor 2, det3 3,
 *     final product and 2 sums 3): error <= 384 eps (1 + 40 eps) L m_x m_y m_z.
 * The bound is computed with a few more roundings (each down by at most a factor 1 - eps) and
 * uses the constants 48.5 eps and 385 eps, leaving a relative margin of 1/100 and 1/400.
 * Underflow: with every maximum in [2^-190, 2^190] no value overflows (insphere values stay
 * below 72 * 2^950), the bounds are normal numbers, and a product that underflows adds an
 * absolute error below 2^-1074 that the later factors (each below the corresponding maximum)
 * scale to at most 2^-1074 * max(1, m_z L, L, m_x m_y m_z) per product; summed over all
 * products this stays below 2^-60 of the margin (whose size is at least 2^-1011 for insphere,
 * 2^-624 for orient3d). Sums and differences whose result is
 * subnormal are exact. A maximum outside the window (a zero one included: then every
 * monomial vanishes), NaN or Inf gives UNSURE.
 */
#define VP_PRED_UNSURE 2
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define VP_PRED_INLINE static inline __attribute__((always_inline))
#else
#define VP_PRED_INLINE static inline
#endif
#define VP_PRED_FILTER_O3 (48.5 * 0x1p-53)
#define VP_PRED_FILTER_IS (385.0 * 0x1p-53)
#define VP_PRED_FILTER_LO 0x1p-190
#define VP_PRED_FILTER_HI 0x1p190

VP_PRED_INLINE double vp_pred_max3_(double a, double b, double c)
{
    double m = a > b ? a : b;
    return m > c ? m : c;
}

VP_PRED_INLINE int vp_pred_in_filter_window_(double mx, double my, double mz)
{
    double lo = mx < my ? mx : my, hi = mx > my ? mx : my;
    lo = lo < mz ? lo : mz;
    hi = hi > mz ? hi : mz;
    return lo >= VP_PRED_FILTER_LO && hi <= VP_PRED_FILTER_HI;
}

/* The orient3d determinant of a, b, c, d in doubles, relative to a, in the fixed order of
 * operations the filters' bounds are derived for. */
static inline double vp_orient3d_det_(const double *a, const double *b, const double *c,
                                      const double *d)
{
    double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    return (wz * (ux * vy - uy * vx) + vz * (uy * wx - ux * wy)) + uz * (vx * wy - vy * wx);
}

/* The same determinant out of line, for a size-optimised build (see vp_insphere_det). */
double vp_orient3d_det(const double *a, const double *b, const double *c, const double *d);
#ifdef __OPTIMIZE_SIZE__
#define VP_ORIENT3D_DET_ vp_orient3d_det
#else
#define VP_ORIENT3D_DET_ vp_orient3d_det_
#endif

static inline int vp_orient3d_filter(const double *a, const double *b, const double *c,
                                     const double *d)
{
    double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    double det = VP_ORIENT3D_DET_(a, b, c, d);
    double mx = vp_pred_max3_(fabs(ux), fabs(vx), fabs(wx));
    double my = vp_pred_max3_(fabs(uy), fabs(vy), fabs(wy));
    double mz = vp_pred_max3_(fabs(uz), fabs(vz), fabs(wz));
    double bound;
    if (!vp_pred_in_filter_window_(mx, my, mz)) return VP_PRED_UNSURE;
    bound = VP_PRED_FILTER_O3 * ((mx * my) * mz);
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return VP_PRED_UNSURE;
}

/* The insphere determinant of a, b, c, d, e in doubles, relative to e, in one fixed order of
 * operations (the filters' bounds and the exact small-integer stage rely on that order). */
static inline double vp_insphere_det_(const double *a, const double *b, const double *c,
                                      const double *d, const double *e)
{
    double aex = a[0] - e[0], aey = a[1] - e[1], aez = a[2] - e[2];
    double bex = b[0] - e[0], bey = b[1] - e[1], bez = b[2] - e[2];
    double cex = c[0] - e[0], cey = c[1] - e[1], cez = c[2] - e[2];
    double dex = d[0] - e[0], dey = d[1] - e[1], dez = d[2] - e[2];
    double ab = aex * bey - bex * aey, ac = aex * cey - cex * aey, ad = aex * dey - dex * aey;
    double bc = bex * cey - cex * bey, bd = bex * dey - dex * bey, cd = cex * dey - dex * cey;
    double bcd = (bez * cd - cez * bd) + dez * bc;
    double acd = (aez * cd - cez * ad) + dez * ac;
    double abd = (aez * bd - bez * ad) + dez * ab;
    double abc = (aez * bc - bez * ac) + cez * ab;
    double al = (aex * aex + aey * aey) + aez * aez;
    double bl = (bex * bex + bey * bey) + bez * bez;
    double cl = (cex * cex + cey * cey) + cez * cez;
    double dl = (dex * dex + dey * dey) + dez * dez;
    double det = (al * bcd - bl * acd) + (cl * abd - dl * abc);
    return det;
}

/* The same determinant out of line. A size-optimised build (-Os) has the inline filters below
 * call it: one copy of its 40 operations (software calls on a core without a double FPU)
 * instead of one in every caller. */
double vp_insphere_det(const double *a, const double *b, const double *c, const double *d,
                       const double *e);
#ifdef __OPTIMIZE_SIZE__
#define VP_INSPHERE_DET_ vp_insphere_det
#else
#define VP_INSPHERE_DET_ vp_insphere_det_
#endif

static inline int vp_insphere_filter(const double *a, const double *b, const double *c,
                                     const double *d, const double *e)
{
    double det = VP_INSPHERE_DET_(a, b, c, d, e), m[3];
    int k;
    for (k = 0; k < 3; k++) /* the largest coordinate difference to e, per axis */
        m[k] = vp_pred_max3_(vp_pred_max3_(fabs(a[k] - e[k]), fabs(b[k] - e[k]), fabs(c[k] - e[k])),
                             fabs(d[k] - e[k]), 0.0);
    double bound;
    if (!vp_pred_in_filter_window_(m[0], m[1], m[2])) return VP_PRED_UNSURE;
    bound = VP_PRED_FILTER_IS * ((((m[0] * m[0] + m[1] * m[1]) + m[2] * m[2]) * ((m[0] * m[1]) * m[2])));
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return VP_PRED_UNSURE;
}

/* The semi-static filters out of line (for the static ones below, when they cannot decide). */
int vp_orient3d_filter_ss(const double *a, const double *b, const double *c, const double *d);
int vp_insphere_filter_ss(const double *a, const double *b, const double *c, const double *d,
                          const double *e);

/* Static filters: `static_bound` = vp_orient3d_static_bound / vp_insphere_static_bound of a
 * box that holds every input point (HUGE_VAL: none). That bound is the semi-static one with
 * the box extents in place of the maxima (every difference is at most the extent), so it
 * costs one comparison; when it cannot decide, the semi-static filter (tighter for small
 * simplices) runs out of line. Same answers as vp_*_filter. */
VP_PRED_INLINE int vp_orient3d_filter_b(const double *a, const double *b, const double *c,
                                        const double *d, double static_bound)
{
    double det = VP_ORIENT3D_DET_(a, b, c, d);
    if (det > static_bound) return 1;
    if (-det > static_bound) return -1;
    if (det == 0.0) return VP_PRED_UNSURE; /* the semi-static bound cannot decide it either */
    return vp_orient3d_filter_ss(a, b, c, d);
}

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__aarch64__)) && \
    !defined(__OPTIMIZE_SIZE__) && !defined(VP_PRED_NO_SIMD)
/* Two-lane evaluation of the same determinant, Laplace-expanded along the (x, y) and
 * (z, lift) column pairs: D' = sum over the 3 splits {ij, kl} of the 4 points of
 * +-(m_ij n_kl + m_kl n_ij), m_ij = x_i y_j - x_j y_i, n_ij = l_i z_j - l_j z_i (relative to
 * e). Lanes hold (a, c) and (b, d). The 72 monomials and their bound are those of the scalar
 * form; a monomial's path has 5 differences, a lift (3), its n (product, difference), its m
 * (product, difference), the product m n and 3 sums: 16 roundings, as in the scalar form, so
 * the same bounds hold. Vector operations round each lane like the scalar ones (no FMA). */
typedef double vp_pred_v2d_ __attribute__((vector_size(16)));
#define VP_PRED_HAVE_V2D 1 /* vp_pred_v2d_ and the shuffles below are available */
#define VP_PRED_SWAP_(v) __builtin_shufflevector((v), (v), 1, 0)
#define VP_PRED_LO_(u, w) __builtin_shufflevector((u), (w), 0, 2)
#define VP_PRED_HI_(u, w) __builtin_shufflevector((u), (w), 1, 3)

VP_PRED_INLINE int vp_insphere_filter_b(const double *a, const double *b, const double *c,
                                        const double *d, const double *e, double static_bound)
{
    vp_pred_v2d_ ex = { e[0], e[0] }, ey = { e[1], e[1] }, ez = { e[2], e[2] };
    vp_pred_v2d_ ux = (vp_pred_v2d_){ a[0], c[0] } - ex, wx = (vp_pred_v2d_){ b[0], d[0] } - ex;
    vp_pred_v2d_ uy = (vp_pred_v2d_){ a[1], c[1] } - ey, wy = (vp_pred_v2d_){ b[1], d[1] } - ey;
    vp_pred_v2d_ uz = (vp_pred_v2d_){ a[2], c[2] } - ez, wz = (vp_pred_v2d_){ b[2], d[2] } - ez;
    vp_pred_v2d_ ul = (ux * ux + uy * uy) + uz * uz, wl = (wx * wx + wy * wy) + wz * wz;
    /* splits {ab, cd}: lanes (a, c) x (b, d) */
    vp_pred_v2d_ m1 = ux * wy - wx * uy, n1 = ul * wz - wl * uz;
    /* splits {ad, cb}: lanes (a, c) x (d, b) */
    vp_pred_v2d_ sx = VP_PRED_SWAP_(wx), sy = VP_PRED_SWAP_(wy), sz = VP_PRED_SWAP_(wz);
    vp_pred_v2d_ sl = VP_PRED_SWAP_(wl);
    vp_pred_v2d_ m2 = ux * sy - sx * uy, n2 = ul * sz - sl * uz;
    /* splits {ac, bd}: lanes (a, b) x (c, d) */
    vp_pred_v2d_ lx = VP_PRED_LO_(ux, wx), hx = VP_PRED_HI_(ux, wx);
    vp_pred_v2d_ ly = VP_PRED_LO_(uy, wy), hy = VP_PRED_HI_(uy, wy);
    vp_pred_v2d_ lz = VP_PRED_LO_(uz, wz), hz = VP_PRED_HI_(uz, wz);
    vp_pred_v2d_ ll = VP_PRED_LO_(ul, wl), hl = VP_PRED_HI_(ul, wl);
    vp_pred_v2d_ m3 = lx * hy - hx * ly, n3 = ll * hz - hl * lz;
    /* (m_ab n_cd + m_cd n_ab) - (m_ad n_cb + m_cb n_ad) - (m_ac n_bd + m_bd n_ac) */
    vp_pred_v2d_ t = (m1 * VP_PRED_SWAP_(n1) - m2 * VP_PRED_SWAP_(n2)) - m3 * VP_PRED_SWAP_(n3);
    double det = t[0] + t[1];
    if (det > static_bound) return 1;
    if (-det > static_bound) return -1;
    if (det == 0.0) return VP_PRED_UNSURE; /* the semi-static bound cannot decide it either */
    return vp_insphere_filter_ss(a, b, c, d, e);
}
#else
VP_PRED_INLINE int vp_insphere_filter_b(const double *a, const double *b, const double *c,
                                        const double *d, const double *e, double static_bound)
{
    double det = VP_INSPHERE_DET_(a, b, c, d, e);
    if (det > static_bound) return 1;
    if (-det > static_bound) return -1;
    if (det == 0.0) return VP_PRED_UNSURE; /* the semi-static bound cannot decide it either */
    return vp_insphere_filter_ss(a, b, c, d, e);
}
#endif

/* Static bounds for the points of the box lo[k] <= x_k <= hi[k]; HUGE_VAL when an extent
 * hi - lo is outside [2^-190, 2^190] (or the box is empty or not finite). */
double vp_orient3d_static_bound(const double lo[3], const double hi[3]);
double vp_insphere_static_bound(const double lo[3], const double hi[3]);

/* Exponent of the lowest set bit of x (x = odd * 2^result), for finite nonzero x. */
int vp_lowest_bit(double x);

/* 1 when the determinants vp_orient3d_filter_b / vp_insphere_filter_b compute are exact for
 * all points in the box whose coordinates are integer multiples of 2^lowbit (an integer
 * grid, say): every extent is below 2^(lowbit + 16) (orient3d) or 2^(lowbit + 9) (insphere),
 * so every difference is an exact integer number of units below that and every intermediate
 * value stays an integer below 2^53 units (see vp_pred.c). A static bound of 0 is then valid:
 * the filters decide every nonzero case, and VP_PRED_UNSURE means an exact zero. */
int vp_orient3d_box_exact(const double lo[3], const double hi[3], int lowbit);
int vp_insphere_box_exact(const double lo[3], const double hi[3], int lowbit);

/* Exact signs: the inline filter, then the out-of-line stages (a size-optimised build calls
 * vp_orient3d / vp_insphere instead: the same filter and stages, one copy). */
static inline int vp_orient3d_fast(const double *a, const double *b, const double *c,
                                   const double *d)
{
#ifdef __OPTIMIZE_SIZE__
    return vp_orient3d(a, b, c, d);
#else
    int s = vp_orient3d_filter(a, b, c, d);
    return s != VP_PRED_UNSURE ? s : vp_orient3d_tail(a, b, c, d);
#endif
}

static inline int vp_insphere_fast(const double *a, const double *b, const double *c,
                                   const double *d, const double *e)
{
#ifdef __OPTIMIZE_SIZE__
    return vp_insphere(a, b, c, d, e);
#else
    int s = vp_insphere_filter(a, b, c, d, e);
    return s != VP_PRED_UNSURE ? s : vp_insphere_tail(a, b, c, d, e);
#endif
}

#endif
