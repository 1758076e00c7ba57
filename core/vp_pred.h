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

int vp_orient3d(const double *a, const double *b, const double *c, const double *d);
int vp_insphere(const double *a, const double *b, const double *c, const double *d,
                const double *e);
int vp_insphere_sos(const double *a, const double *b, const double *c, const double *d,
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

#endif
