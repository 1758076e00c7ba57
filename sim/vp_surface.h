/* vp_surface — the simulated objects the scanner probes (host side, heap allowed).
 *
 * A spec names one or more components:  TERM ( '+' TERM )*
 *   TERM  = NAME [ '*' SCALE ] [ '@' X ',' Y ',' Z ]    (the two modifiers in either order)
 *   NAME  = sphere | torus | genus2 | ellipsoid | genus5 | blobby | off:PATH | ply:PATH
 * A term's points are  centre + SCALE * (the object's own points); SCALE > 0, default 1,
 * centre default 0,0,0. Numbers are C decimal numbers (1e-3 is fine).
 * A '+' starts a new term only when a NAME follows it, so '+' inside numbers (1e+2) and file
 * paths stays part of the term. In a PATH the modifiers are recognised only as a final suffix.
 * Terms must not overlap: their surfaces must stay apart by at least 1% of the smaller term's
 * bounding-box diagonal (checked on surface samples), else vp_surface_open fails.
 * Examples:  sphere@3,0,0+torus     sphere*0.5@2,0,0+genus2     off:bunny.off*2@0,0,1
 * vp_surface_help() returns this description for --help texts.
 *
 * All queries are read-only and thread-compatible; inside means f < 0 (closed meshes: parity).
 */
#ifndef VP_SURFACE_H
#define VP_SURFACE_H
#include <stddef.h>
#include <stdint.h>

typedef struct vp_surface vp_surface_t;

const char *vp_surface_help(void);

/* VP_OK, or VP_EINVAL (bad spec), VP_ECORRUPT/VP_EIO (mesh file), VP_ERANGE (overlap),
 * VP_ENOMEM; err gets one clear line. */
int    vp_surface_open(const char *spec, vp_surface_t **out, char *err, size_t errlen);
void   vp_surface_close(vp_surface_t *s);

void   vp_surface_bbox(const vp_surface_t *s, double lo[3], double hi[3]);
int    vp_surface_components(const vp_surface_t *s);
int    vp_surface_genus(const vp_surface_t *s);     /* sum over components; -1 when unknown */
double vp_surface_area(const vp_surface_t *s);      /* exact or estimated (about 1%) */
/* A point strictly inside component comp (0-based), found automatically. */
void   vp_surface_interior_point(const vp_surface_t *s, int comp, double p[3]);
int    vp_surface_inside(const vp_surface_t *s, const double p[3]);
/* First transverse crossing of the ray o + t dir (dir of unit length) with t in (0, tmax]:
 * 1 and *t_hit, or 0 for a miss. Never skips a thin part; grazing touches are misses. */
int    vp_surface_ray(const vp_surface_t *s, const double o[3], const double dir_unit[3], double tmax,
                      double *t_hit);
/* 1 if some point of segment [a,b] is inside the object or within `clearance` of its surface. */
int    vp_surface_segment_collides(const vp_surface_t *s, const double a[3], const double b[3],
                                   double clearance);
/* Unsigned distance to the surface; q (may be NULL) gets the closest surface point. */
double vp_surface_closest(const vp_surface_t *s, const double p[3], double q[3]);
double vp_surface_distance(const vp_surface_t *s, const double p[3]);
/* Outward unit normal at (or near) surface point p. */
void   vp_surface_normal(const vp_surface_t *s, const double p[3], double n[3]);
/* n points on the surface, roughly uniform by area, reproducible from seed; returns n. */
size_t vp_surface_sample(const vp_surface_t *s, size_t n, uint64_t seed, double *xyz);
/* Points along the creases of the mesh terms (edges whose two faces turn by more than 20
 * degrees: a part's sharp edges and corners, where the surface is farthest from a mesh that cuts
 * them), each crease's ends and points at most `step` apart between (world units): *xyz a
 * malloc'ed array of *n points (the caller frees it), NULL and 0 for smooth (implicit) terms.
 * VP_EINVAL (step not > 0), VP_ENOMEM. */
int vp_surface_creases(const vp_surface_t *s, double step, double **xyz, size_t *n);

#endif
