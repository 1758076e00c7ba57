/* vp_motion — a simulated object that moves and deforms in time: a static vp_surface_t (the
 * body, as it is at t = 0) carried by a motion. The motion model is that of paper 001
 * (deforming surface meshes): a closed surface deforms over time without changing topology, and
 * every point of it moves no faster than a known bound lambda (vp_motion_speed_bound).
 *
 * A spec joins terms by '+':   TERM ( '+' TERM )*      (a '+' inside a number stays in it)
 *   translate:VX,VY,VZ                  velocity, units per second
 *   rotate:AX,AY,AZ,DEG_PER_S[@CX,CY,CZ] spin about the axis through C (default: the centre
 *                                       of the body's bounding box), right-handed
 *   inflate:RATE                        scale about the centre by exp(RATE t) (RATE < 0 shrinks)
 *   bend:AX,AY,AZ,BX,BY,BZ,K_PER_S       bend the body's A axis towards B (made perpendicular
 *                                       to A): x + (k/2) ((x - centre).A)^2 B, k = K_PER_S t
 *   bump:X,Y,Z,RADIUS,HEIGHT_PER_S      a smooth bump (height h (1 - rho^2)^3 at rho = distance
 *                                       / RADIUS < 1, along the surface normal) that grows at the
 *                                       surface point nearest X,Y,Z; its height stops growing at
 *                                       0.29 RADIUS (the map stays one-to-one, gradient <= 1/2)
 * At most one each of translate, rotate and inflate; up to 8 bends and bumps. The body point x
 * goes to the world as: bends and bumps in the order given (body frame), then inflate, rotate,
 * translate. At t = 0 every motion is the identity.
 *
 * What is exact: with translate, rotate and inflate only (a similarity), every query maps into
 * the body frame and asks vp_surface, so it is as exact as the static object. With bends or
 * bumps the ray and segment queries march conservatively (steps bounded by the body distance
 * over a Lipschitz bound of the inverse map): they never skip a part thicker than 1e-9 of the
 * object's size; a segment counts as colliding when it may come within the clearance (it may
 * report a near miss whose gap is below the clearance times the Lipschitz bound); the
 * distance is that of a true surface point (an upper bound, refined by projection).
 * All queries are read-only; times are seconds. */
#ifndef VP_MOTION_H
#define VP_MOTION_H
#include <stddef.h>
#include "vp_hausdorff.h"
#include "vp_surface.h"

typedef struct vp_motion vp_motion_t;

const char *vp_motion_help(void);
/* Checks the spec's syntax without an object: VP_OK, or VP_EINVAL and one clear line. */
int    vp_motion_check_spec(const char *spec, char *err, size_t errlen);
/* body must outlive the motion. VP_OK, VP_EINVAL (bad spec, err says why) or VP_ENOMEM. */
int    vp_motion_open(const char *spec, const vp_surface_t *body, vp_motion_t **out, char *err, size_t errlen);
void   vp_motion_close(vp_motion_t *m);
const vp_surface_t *vp_motion_body(const vp_motion_t *m);
/* 1 when the motion is a similarity (no bend, no bump): every query is exact. */
int    vp_motion_is_similarity(const vp_motion_t *m);

/* The body point x (t = 0) where it is at time t, and back. */
void   vp_motion_to_world(const vp_motion_t *m, double t, const double x[3], double y[3]);
void   vp_motion_to_body(const vp_motion_t *m, double t, const double y[3], double x[3]);

int    vp_motion_inside(const vp_motion_t *m, double t, const double p[3]);
/* As vp_surface_ray, against the object at time t. */
int    vp_motion_ray(const vp_motion_t *m, double t, const double o[3], const double dir_unit[3], double tmax,
                     double *t_hit);
/* As vp_surface_segment_collides, against the object frozen at time t. */
int    vp_motion_segment_collides(const vp_motion_t *m, double t, const double a[3], const double b[3],
                                  double clearance);
double vp_motion_closest(const vp_motion_t *m, double t, const double p[3], double q[3]);
double vp_motion_distance(const vp_motion_t *m, double t, const double p[3]);
void   vp_motion_normal(const vp_motion_t *m, double t, const double p[3], double n[3]);
/* The largest speed of any surface point at any time in [t0, t1] (units per second): over a
 * span dt of that interval no surface point moves farther than the bound times dt. */
double vp_motion_speed_bound(const vp_motion_t *m, double t0, double t1);
/* The two-sided Hausdorff distance of a mesh to the object at time t (as vp_hausdorff). */
int    vp_motion_hausdorff(const vp_mesh_t *mesh, const vp_motion_t *m, double t, size_t n, uint64_t seed,
                           vp_hausdorff_t *out);

#endif
