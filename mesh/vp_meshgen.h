/* vp_meshgen — reference meshes for tests and demos (outward-oriented, closed). */
#ifndef VP_MESHGEN_H
#define VP_MESHGEN_H
#include "vp_meshio.h"

/* Icosahedron subdivided `level` times (20 * 4^level faces), vertices on the unit sphere. */
int vp_meshgen_icosphere(int level, vp_mesh_t *m);
/* Torus of core radius R and tube radius r around the z axis: nu x nv grid, 2*nu*nv faces. */
int vp_meshgen_torus(double R, double r, int nu, int nv, vp_mesh_t *m);
/* Appends b to a (indices shifted), moved by offset. */
int vp_meshgen_append(vp_mesh_t *a, const vp_mesh_t *b, const double offset[3]);

#endif
