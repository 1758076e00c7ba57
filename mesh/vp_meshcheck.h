/* vp_meshcheck — analysis of a triangle mesh on the PC side: topology (closed 2-manifold,
 * orientation, components, Euler characteristic, genus, boundary) and quality (smallest angle).
 * The Hausdorff distance to a simulated object is sim/vp_hausdorff.h. */
#ifndef VP_MESHCHECK_H
#define VP_MESHCHECK_H
#include <stddef.h>
#include <stdint.h>
#include "vp_meshio.h"

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

/* An undirected edge {a, b} (a < b) of face f; vp_edge_cmp sorts by a, then b, then f. */
typedef struct vp_edge_rec { uint32_t a, b, f; } vp_edge_rec_t;
int vp_edge_cmp(const void *x, const void *y);
/* Union-find over parents par[] (par[x] == x: a root; path halving; the smaller index is the root). */
uint32_t vp_uf_find(uint32_t *par, uint32_t x);
void     vp_uf_join(uint32_t *par, uint32_t a, uint32_t b);

/* Orients each connected component of m consistently and outward (positive volume). */
int vp_mesh_orient(vp_mesh_t *m);

#endif
