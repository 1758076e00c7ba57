/* vp_kdtree — static k-d tree over 3D points for k-nearest queries (host side). */
#ifndef VP_KDTREE_H
#define VP_KDTREE_H
#include <stddef.h>

typedef struct vp_kdtree vp_kdtree_t;

/* Copies the n points (3*n doubles). VP_OK / VP_ENOMEM / VP_EINVAL. */
int    vp_kdtree_build(const double *xyz, size_t n, vp_kdtree_t **out);
void   vp_kdtree_free(vp_kdtree_t *t);
/* Up to k (<= 32) nearest points to p, nearest first: their slots (for vp_kdtree_point) and
 * squared distances.
 * Returns how many were found (min(k, n)). */
size_t vp_kdtree_knn(const vp_kdtree_t *t, const double p[3], size_t k, size_t *idx, double *d2);
const double *vp_kdtree_point(const vp_kdtree_t *t, size_t slot);
size_t vp_kdtree_original(const vp_kdtree_t *t, size_t slot);   /* input index of a slot */

#endif
