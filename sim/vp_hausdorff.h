/* vp_hausdorff — the two-sided Hausdorff distance between a mesh and a simulated object
 * (vp_surface): how far the scan's mesh is from the truth. */
#ifndef VP_HAUSDORFF_H
#define VP_HAUSDORFF_H
#include <stddef.h>
#include <stdint.h>
#include "vp_meshio.h"
#include "vp_surface.h"

typedef struct vp_hausdorff {
    double mesh_to_surface;   /* max over mesh points of the distance to the true surface */
    double surface_to_mesh;   /* max over surface points of the distance to the mesh */
    double hausdorff;         /* the larger of the two */
    double mean_mesh_to_surface;
    double mean_surface_to_mesh;
} vp_hausdorff_t;

/* Two-sided Hausdorff distance by dense sampling (n points on each side, roughly uniform by
 * area, plus every vertex of the mesh and points along the object's creases), then local
 * maximisation around the worst samples (a pattern search, its steps halving, a bounded number
 * of moves at each length: it always ends). The mesh side uses a BVH for closest points. */
int vp_hausdorff(const vp_mesh_t *m, const vp_surface_t *s, size_t n, uint64_t seed, vp_hausdorff_t *out);

/* The same measure against any object given by its queries (a moving object at one time). */
typedef struct vp_hd_object {
    const void *ctx;
    double (*closest)(const void *ctx, const double p[3], double q[3]);  /* q may be NULL */
    void   (*normal)(const void *ctx, const double p[3], double n[3]);
    size_t (*sample)(const void *ctx, size_t n, uint64_t seed, double *xyz);
    /* points along the object's creases at most step apart (vp_surface_creases: a malloc'ed
     * array), where it is farthest from a mesh that cuts its sharp edges; NULL: none */
    int (*creases)(const void *ctx, double step, double **xyz, size_t *n);
    double area;
} vp_hd_object_t;
int vp_hausdorff_object(const vp_mesh_t *m, const vp_hd_object_t *obj, size_t n, uint64_t seed, vp_hausdorff_t *out);
/* The queries of a simulated object, as vp_hausdorff takes them (creases included). */
void vp_hausdorff_surface_object(const vp_surface_t *s, vp_hd_object_t *obj);

#endif
