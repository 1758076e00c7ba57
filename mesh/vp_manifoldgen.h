/* vp_manifoldgen — seeded samples of k-manifolds in R^d, for reconstruction tests and benchmarks.
 *
 *   name      k  d   the manifold                                           Euler  orientable
 *   sphere    2  3   unit sphere                                             2     yes
 *   torus     2  3   torus, radii 1 and 0.4 (area-uniform)                   0     yes
 *   genus2    2  3   two tori (radii 0.8, 0.3, centres x = +-1) joined     -2     yes
 *                    by a smooth minimum (samples projected onto it)
 *   clifford  2  4   flat torus (cos a, sin a, cos b, sin b) / sqrt 2        0     yes
 *   klein     2  4   Klein bottle ((2+cos v)cos u, (2+cos v)sin u,           0     no
 *                    sin v cos(u/2), sin v sin(u/2))
 *   so3       3  9   rotation matrices (Haar-uniform), row by row            0     yes
 *   curve     1  10  closed curve (cos jt, sin jt)/j, j = 1..5              0     yes
 *
 * Same name, n, seed and options: the same points on every machine (vp_rng). noise adds a
 * Gaussian of that standard deviation to every coordinate; nonuniform thins the sample so the
 * density grows fivefold along the first coordinate (rejection, still n points). */
#ifndef VP_MANIFOLDGEN_H
#define VP_MANIFOLDGEN_H
#include <stddef.h>
#include <stdint.h>

typedef struct vp_manifold_info {
    const char *name;
    int k, d;
    long euler;
    int orientable;
    const char *what;
} vp_manifold_info_t;

/* The table above: NULL past the end (i from 0). */
const vp_manifold_info_t *vp_manifold_info(size_t i);
const vp_manifold_info_t *vp_manifold_find(const char *name);

/* n points (d coordinates each, d from the table) into out (n*d doubles).
 * VP_OK, VP_EINVAL (unknown name, n == 0, negative or non-finite noise). */
int vp_manifold_sample(const char *name, size_t n, uint64_t seed, double noise, int nonuniform, double *out);

#endif
