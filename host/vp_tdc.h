/* vp_tdc — the tangential Delaunay complex (paper 004, A. Ghosh's thesis, ch. 3): reconstruction
 * of a k-manifold (k = 1..3) from points in R^d at a cost that grows with k, not with d.
 *
 * Tangent space T_p: local PCA of p's nearest neighbours (or given by the caller).
 * star(p): the k-simplices incident to p whose weighted Voronoi face meets T_p. T_p cuts the
 * ambient power diagram in the k-dimensional power diagram of the neighbours projected onto
 * T_p, each with weight w_q - dist(q, T_p)^2; p's cell there is an intersection of halfspaces
 * of R^k, and each of its vertices, where p and q_1..q_k are equally near, is the simplex
 * {p, q_1..q_k} of star(p). Neighbours come from a k-d tree in R^d, nearest first, and the set
 * grows until the cell is certified: every cell vertex t is nearer to p (in power) than any
 * point outside the set can be (|t| + sqrt(|t|^2 - w_p + w_max) below the set's radius).
 * Inconsistent simplex: in star(u) but not in star(v) for a vertex v. Fixing is a local search
 * by perturbation: in turn, each point whose star holds one moves to a random spot of its
 * tangent space within perturb_rel times its nearest-neighbour distance of where it was given
 * (or takes a random weight up to that distance squared); only the stars the move can change
 * (those whose certified ball held the point before or holds it now) are computed again, and the
 * move is undone if the number of inconsistent simplices grew. Sweeps over the points repeat
 * until none is left or a bound is hit (what is left is reported). Every random draw is seeded
 * by (seed, point, trial): the same input gives the same complex. */
#ifndef VP_TDC_H
#define VP_TDC_H
#include <stddef.h>
#include <stdint.h>

#define VP_TDC_KMAX 3
#define VP_TDC_DMAX 64

enum vp_tdc_fix { VP_TDC_FIX_POSITION = 0, VP_TDC_FIX_WEIGHT = 1 };

/* Zero is the default of every field. */
typedef struct vp_tdc_params {
    int k;                  /* intrinsic dimension, 1..VP_TDC_KMAX (required) */
    int pca_neighbours;     /* points in each PCA (p included); default 8, 25, 60 for k = 1, 2, 3 */
    int max_neighbours;     /* largest neighbour set of a star; default 1024 */
    double perturb_rel;     /* perturbation bound / nearest-neighbour distance; default 0.25 */
    int fix_mode;           /* VP_TDC_FIX_POSITION (default) or VP_TDC_FIX_WEIGHT */
    int max_rounds;         /* fixing sweeps; default 1000; negative: no fixing */
    double time_limit;      /* seconds of fixing; default 120 */
    uint64_t seed;
    const double *tangents; /* optional: n*k*d, k orthonormal vectors of R^d per point */
    const double *weights;  /* optional: n weights w_p >= 0 (power distance |x-p|^2 - w_p) */
} vp_tdc_params_t;

typedef struct vp_tdc_stats {
    size_t inconsistent_before;   /* after the first stars, before fixing */
    size_t inconsistent;          /* now */
    size_t simplices;             /* distinct k-simplices in some star */
    size_t uncertified;           /* stars whose cell could not be certified (bound reached) */
    size_t rounds, moves, star_builds;   /* sweeps, trial moves, star computations */
    size_t max_neighbours_used;
    double max_shift;             /* largest distance of a point from where it was given */
    double max_shift_rel;         /* ... over its nearest-neighbour distance */
    double nn_mean;               /* mean nearest-neighbour distance of the given points */
    double seconds_tangents, seconds_stars, seconds_fix;
} vp_tdc_stats_t;

typedef struct vp_tdc vp_tdc_t;

/* Copies the n points of R^d (n*d doubles, finite). VP_EINVAL with err for bad input (k out of
 * range, d < k+1 or > VP_TDC_DMAX, n <= k+1, a non-finite coordinate), VP_ENOMEM. */
int  vp_tdc_create(vp_tdc_t **out, const double *pts, size_t n, int d, const vp_tdc_params_t *prm,
                   char *err, size_t errlen);
void vp_tdc_free(vp_tdc_t *t);
/* Tangent spaces and every star. VP_OK / VP_ENOMEM / VP_EDEGEN (a cell with too many vertices). */
int  vp_tdc_build(vp_tdc_t *t);
/* Fixing sweeps (see above) until no inconsistent simplex, max_rounds or time_limit. */
int  vp_tdc_fix(vp_tdc_t *t);
void vp_tdc_get_stats(const vp_tdc_t *t, vp_tdc_stats_t *s);
/* star(p): *count k-simplices of k+1 sorted indices each, valid until the next change. */
const uint32_t *vp_tdc_star(const vp_tdc_t *t, size_t p, size_t *count);
/* The complex: every k-simplex in some star, once (malloc'ed, k+1 sorted indices each). */
int  vp_tdc_simplices(const vp_tdc_t *t, uint32_t **simp, size_t *count);
/* Current positions (n*d; moved by a position fix) and the tangent basis of p (k*d). */
const double *vp_tdc_points(const vp_tdc_t *t);
const double *vp_tdc_tangent(const vp_tdc_t *t, size_t p);

#endif
