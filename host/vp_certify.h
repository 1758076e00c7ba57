/* vp_certify — the hypotheses under which the papers guarantee a probed mesh, checked facet
 * by facet (000: Theorem 2.1 with H1-H3; 002: loose eps-samples):
 *   H1  the mesh is a 2-manifold without boundary: every edge in exactly two facets, every
 *       vertex link one cycle, no degenerate facet (combinatorial, exact);
 *   H2  a vertex on every component of S: each interior point o_i is enclosed by a mesh
 *       component (ray parity with exact orientation tests);
 *   H3  every facet has a surface Delaunay ball of radius <= eps: with the balls (from a log's
 *       replay) the radius of each ball is compared to eps exactly and the ball is checked
 *       empty of samples exactly; without them (a bare mesh) only necessary conditions can be
 *       checked: circumradius <= eps and the facet is Delaunay for the mesh's vertices;
 *   and eps < 0.091 reach when a reach bound is given.
 * Offending facets, edges and vertices are printed (indices are the PLY file's). */
#ifndef VP_CERTIFY_H
#define VP_CERTIFY_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "vp_meshio.h"

typedef struct vp_cert_config {
    double eps;                  /* > 0 */
    double reach;                /* a lower bound on reach(S); 0: unknown */
    double diam;                 /* an upper bound on diam(S); 0: unknown */
    const double (*interior)[3]; /* the o_i (NULL: H2 cannot be checked) */
    uint32_t ninterior;
    const double *centers;       /* per facet: its surface Delaunay ball's centre (NULL: bare mesh) */
    const double *samples;       /* the sample set E (3 per point); NULL: the mesh's vertices */
    size_t nsamples;
    size_t max_list;             /* offenders printed per kind (0: 20) */
} vp_cert_config_t;

typedef struct vp_cert {
    int h1, h2, h3, reach_ok;    /* 1 holds, 0 fails, -1 cannot be checked */
    /* H1 */
    size_t edges, boundary_edges, nonmanifold_edges, bad_vertices, degenerate_facets;
    int components;
    /* H2 */
    uint32_t h2_missing;         /* interior points not enclosed */
    /* H3 */
    size_t big_balls;            /* ball radius > eps (exact) */
    size_t open_balls;           /* a sample strictly inside the ball (exact) */
    size_t big_circumradius;     /* bare mesh: circumradius > eps */
    size_t not_delaunay;         /* bare mesh: not a facet of Del(vertices) */
    size_t undecided;            /* bare mesh: circumradius within rounding of eps */
    double max_radius;           /* largest ball radius (or circumradius for a bare mesh) */
    size_t max_radius_facet;
    double max_spread;           /* largest relative difference of a ball's three radii */
    double hausdorff_bound;      /* 4.5 diam / reach^2 * eps^2 when reach and diam are known */
    /* paper 002's non-uniform loose eps-sample: every ball has r <= eps' dM(c); dM estimated
     * from the mesh vertices' poles in Del(vertices) and extended 1-Lipschitz to the centres
     * (an estimate, not a bound: dM of the true surface is unknown). With balls only; -1: none */
    double eps_prime;
    size_t eps_prime_facet;
} vp_cert_t;

/* Checks everything it can; prints offenders (and nothing else) to report (may be NULL).
 * VP_OK (whatever the verdict), VP_EINVAL, VP_ENOMEM. */
int vp_certify(const vp_mesh_t *m, const vp_cert_config_t *cfg, vp_cert_t *out, FILE *report);

/* Exact sign of |p - q|^2 - r^2 (-1, 0, +1) for finite doubles of moderate size. */
int vp_cert_cmp_radius(const double p[3], const double q[3], double r);

#endif
