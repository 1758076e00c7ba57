/* vp_mfcheck — is a pure simplicial k-complex (k = 1, 2, 3) a closed k-manifold?
 *
 * Works from the list of k-simplices alone (vertex indices), with no knowledge of how they were
 * made: every (k-1)-simplex in exactly two k-simplices, every vertex link a (k-1)-sphere (k = 1:
 * two points; k = 2: one cycle; k = 3: a connected closed surface, each of its vertex links one
 * cycle, Euler characteristic 2), orientability by propagating orientations across shared
 * (k-1)-faces, the Euler characteristic from the face counts of every dimension, and the
 * connected components. */
#ifndef VP_MFCHECK_H
#define VP_MFCHECK_H
#include <stddef.h>
#include <stdint.h>

#define VP_MFCHECK_KMAX 3

typedef struct vp_mfcheck {
    int k;
    size_t faces[VP_MFCHECK_KMAX + 1]; /* distinct j-faces, j = 0..k */
    long euler;                     /* sum of (-1)^j faces[j] */
    size_t duplicates;              /* k-simplices given more than once (or with a repeated vertex) */
    size_t bad_facets;              /* (k-1)-faces not in exactly two k-simplices */
    size_t bad_links;               /* vertices whose link is not a (k-1)-sphere */
    size_t components;              /* connected through shared (k-1)-faces */
    int manifold;                   /* 1: closed k-manifold (none of the three counts above) */
    int orientable;                 /* 1 or 0; -1 when not decided (not a manifold) */
} vp_mfcheck_t;

/* simp: ns k-simplices, k+1 vertex indices each (< nv). oriented (may be NULL): receives the
 * same simplices, same order, each with its vertices ordered so that all induce opposite
 * orientations on every shared (k-1)-face (when orientable; otherwise sorted).
 * VP_OK, VP_EINVAL (k out of 1..3, an index >= nv), VP_ENOMEM. */
int vp_mfcheck_run(const uint32_t *simp, size_t ns, int k, size_t nv, vp_mfcheck_t *out, uint32_t *oriented);

#endif
