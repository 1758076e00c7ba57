/* vp_meshcheck — analysis of a triangle mesh on the PC side: topology (closed 2-manifold,
 * orientation, components, Euler characteristic, genus, boundary), quality (smallest angle)
 * and the two-sided Hausdorff distance to a simulated object (vp_surface). */
#ifndef VP_MESHCHECK_H
#define VP_MESHCHECK_H
#include <stddef.h>
#include <stdint.h>
#include "vp_meshio.h"

struct vp_surface;

typedef struct vp_mesh_component {
    size_t faces, vertices, edges;
    size_t boundary_edges, boundary_loops;
    long   euler;          /* V - E + F of the component */
    int    manifold;       /* every edge in 1 or 2 faces, every vertex link one cycle or path */
    int    closed;         /* manifold and no boundary edge */
    int    genus;          /* (2 - euler - boundary_loops) / 2 when manifold and oriented, else -1 */
    double area;
    double volume;         /* signed, by the divergence theorem (> 0: outward normals) */
} vp_mesh_component_t;

typedef struct vp_meshcheck {
    size_t nv, nt;
    size_t edges;                 /* distinct undirected edges */
    size_t boundary_edges;        /* edges in exactly one face */
    size_t nonmanifold_edges;     /* edges in more than two faces */
    size_t misoriented_edges;     /* two-face edges traversed the same way by both faces */
    size_t nonmanifold_vertices;  /* vertices whose link is not a single cycle (or path on the boundary) */
    size_t degenerate_faces;      /* a repeated vertex index, or zero area */
    size_t unused_vertices;
    int    closed_manifold;       /* no boundary, no non-manifold edge or vertex, no degenerate face */
    int    oriented;              /* consistently oriented (no misoriented edge) */
    int    outward;               /* closed, oriented and every component has volume > 0 */
    int    components;            /* connected through shared edges */
    long   euler;                 /* V (used) - E + F */
    int    genus;                 /* sum over components, -1 if any is unknown */
    double min_angle_deg;         /* smallest triangle angle, degrees */
    int   *comp_of_face;          /* nt component labels, 0..components-1 */
    vp_mesh_component_t *comp;    /* per component */
} vp_meshcheck_t;

/* Fills r (free with vp_meshcheck_free). VP_OK, VP_EINVAL (bad index), VP_ENOMEM. */
int  vp_meshcheck_analyze(const vp_mesh_t *m, vp_meshcheck_t *r);
void vp_meshcheck_free(vp_meshcheck_t *r);
/* One line per fact, for logs and the CLI. */
void vp_meshcheck_print(const vp_meshcheck_t *r, void *file /* FILE* */);

typedef struct vp_hausdorff {
    double mesh_to_surface;   /* max over mesh points of the distance to the true surface */
    double surface_to_mesh;   /* max over surface points of the distance to the mesh */
    double hausdorff;         /* the larger of the two */
    double mean_mesh_to_surface;
    double mean_surface_to_mesh;
} vp_hausdorff_t;

/* Two-sided Hausdorff distance by dense sampling (n points on each side, roughly uniform by
 * area, plus every vertex of the mesh), then local maximisation around the worst samples.
 * The mesh side uses a BVH for closest points. */
int  vp_meshcheck_hausdorff(const vp_mesh_t *m, const struct vp_surface *s, size_t n, uint64_t seed,
                            vp_hausdorff_t *out);

#endif
