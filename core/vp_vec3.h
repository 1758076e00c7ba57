/* vp_vec3 — the one home of the small 3-vector helpers (like littlefs' lfs_util.h).
 *
 * A vector is `double v[3]`. One argument order everywhere: the output first, then the inputs
 * (vp_sub3(o, a, b) is o = a - b). Every helper is static inline: no symbol enters the core's
 * table, no libm call but sqrt. The arithmetic is written out term by term in a fixed order
 * (x, then y, then z), so results are bit-identical wherever these are used (-ffp-contract=off).
 *
 * VP_DASSERT(cond): an internal invariant, checked only in a debug build (-DVP_DEBUG_ASSERT),
 * compiled out otherwise. It never prints: a failed check calls __builtin_trap() on GCC/Clang,
 * or writes through a null pointer elsewhere. Errors a caller can cause are statuses (VP_EINVAL),
 * never asserts (STYLE.md: asserts only for internal invariants).
 */
#ifndef VP_VEC3_H
#define VP_VEC3_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#ifdef VP_DEBUG_ASSERT
#if defined(__GNUC__)
#define VP_DASSERT(cond) do { if (!(cond)) __builtin_trap(); } while (0)
#else
#define VP_DASSERT(cond) do { if (!(cond)) *(volatile int *)0 = 0; } while (0)
#endif
#else
#define VP_DASSERT(cond) ((void)0)
#endif

/* The largest length vp_normalize3 accepts: beyond it the square of a coordinate may overflow. */
#define VP_VEC3_HUGE 1e300

static inline double vp_dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* o = a - b (o may be a or b) */
static inline void vp_sub3(double *o, const double *a, const double *b)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

/* o = a + b (o may be a or b) */
static inline void vp_add3(double *o, const double *a, const double *b)
{
    o[0] = a[0] + b[0];
    o[1] = a[1] + b[1];
    o[2] = a[2] + b[2];
}

/* o = a x b (o must be neither a nor b) */
static inline void vp_cross3(double *o, const double *a, const double *b)
{
    VP_DASSERT(o != a && o != b);
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double vp_norm3(const double *v)
{
    return sqrt(vp_dot3(v, v));
}

/* |a - b| */
static inline double vp_dist3(const double *a, const double *b)
{
    double d[3];
    vp_sub3(d, a, b);
    return sqrt(vp_dot3(d, d));
}

/* d is finite (no NaN, no infinity): its exponent bits are not all ones. No libm call and no
 * floating-point arithmetic (a double subtraction is a library call on the Cortex-M4's FPU). */
static inline int vp_finite(double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    return ((u >> 52) & 0x7FFu) != 0x7FFu;
}

/* All three coordinates finite. */
static inline int vp_finite3(const double *p)
{
    uint64_t u[3];
    memcpy(u, p, sizeof u);
    return ((u[0] >> 52) & 0x7FFu) != 0x7FFu && ((u[1] >> 52) & 0x7FFu) != 0x7FFu &&
           ((u[2] >> 52) & 0x7FFu) != 0x7FFu;
}

/* Scales v to unit length in place. Returns 0 and leaves v unchanged when its length is zero,
 * not finite or beyond VP_VEC3_HUGE: a direction must never be made from nothing. */
static inline int vp_normalize3(double *v)
{
    double n = sqrt(vp_dot3(v, v));
    if (!(n > 0.0) || !(n < VP_VEC3_HUGE)) return 0;
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
    return 1;
}

/* The plane normal to unit u, spanned by unit w1 = u x t / |u x t| and w2 = u x w1 (t: any
 * direction not along u). */
static inline void vp_normal_frame3(const double *u, const double *t, double *w1, double *w2)
{
    vp_cross3(w1, u, t);
    vp_normalize3(w1);
    vp_cross3(w2, u, w1);
}

#endif
