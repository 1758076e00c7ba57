/* vp_bvh — bounding-volume hierarchy over a triangle mesh (host side, heap allowed).
 * Built once (binned SAH, leaves of <= 4 triangles), then queried read-only:
 * first ray hit, parity inside test, closest point, and "segment within r" tests.
 * Triangle indices returned are those of the input array. */
#ifndef VP_BVH_H
#define VP_BVH_H
#include <stddef.h>
#include <stdint.h>

typedef struct vp_bvh vp_bvh_t;

/* xyz: 3*nv doubles, tri: 3*nt indices (all < nv; the caller checks). VP_OK or VP_ENOMEM/VP_EINVAL. */
int    vp_bvh_build(const double *xyz, size_t nv, const uint32_t *tri, size_t nt, vp_bvh_t **out);
void   vp_bvh_free(vp_bvh_t *b);
void   vp_bvh_bounds(const vp_bvh_t *b, double lo[3], double hi[3]);
size_t vp_bvh_triangles(const vp_bvh_t *b);

/* First triangle hit with t in (tmin, tmax] along o + t d; 1 hit (*t, *tri set), 0 miss.
 * Edges are inclusive (a tiny tolerance), so a ray cannot slip between two triangles. */
int    vp_bvh_ray(const vp_bvh_t *b, const double o[3], const double d[3], double tmin, double tmax,
                  double *t, size_t *tri);
/* 1 if p is inside the closed mesh (crossing parity along rays chosen to avoid edges). */
int    vp_bvh_inside(const vp_bvh_t *b, const double p[3]);
/* Distance from p to the mesh; q (optional) gets the closest point, tri (optional) its triangle. */
double vp_bvh_closest(const vp_bvh_t *b, const double p[3], double q[3], size_t *tri);
/* 1 if some point of segment [a,c] is within distance r (>= 0) of some triangle. */
int    vp_bvh_segment_near(const vp_bvh_t *b, const double a[3], const double c[3], double r);

/* Exact-arithmetic-free geometry helpers, also used by tests. */
double vp_tri_closest(const double p[3], const double v0[3], const double v1[3], const double v2[3], double q[3]);
double vp_seg_tri_dist2(const double a[3], const double c[3], const double v0[3], const double v1[3], const double v2[3]);

#endif
