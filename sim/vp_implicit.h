/* vp_implicit — the analytic test objects in their own frame: f(p) < 0 inside, f = 0 on the
 * surface. Point values, gradients, interval bounds over boxes, first ray crossings, and exact
 * closest points where a closed form exists. Used by vp_surface (which adds placement).
 *
 *   sphere     x^2+y^2+z^2-1
 *   torus      (sqrt(x^2+y^2)-1)^2+z^2-0.3^2
 *   genus2     smooth union of two such tori centred at (-1,0,0) and (1,0,0):
 *              min(a,b) - log(1+exp(-50|a-b|))/50
 *   ellipsoid  (x/1)^2+(y/0.7)^2+(z/0.5)^2-1
 *   genus5     x^4-5x^2+y^4-5y^2+z^4-5z^2+11.8 (a cube frame: 8 corners, 12 tubes)
 *   blobby     0.5 - sum_i exp(-|p-c_i|^2/s_i^2) over four balls (one smooth component)
 */
#ifndef VP_IMPLICIT_H
#define VP_IMPLICIT_H

enum vp_imp_kind {
    VP_IMP_SPHERE, VP_IMP_TORUS, VP_IMP_GENUS2, VP_IMP_ELLIPSOID, VP_IMP_GENUS5, VP_IMP_BLOBBY,
    VP_IMP_COUNT
};

int         vp_imp_from_name(const char *name, unsigned long len);  /* kind, or -1 */
const char *vp_imp_name(int kind);
int         vp_imp_genus(int kind);
/* Box that holds the solid (f < 0), with a small margin. */
void        vp_imp_bbox(int kind, double lo[3], double hi[3]);
double      vp_imp_f(int kind, const double p[3]);
double      vp_imp_grad(int kind, const double p[3], double g[3]);       /* returns f; g = grad f */
/* Encloses f over the box [lo,hi] (padded for rounding): out[0] <= f <= out[1]. */
void        vp_imp_fbox(int kind, const double lo[3], const double hi[3], double out[2]);
/* First transverse crossing of f along o + t d with t in (t0, t1]; 1 and *t, or 0.
 * sphere/ellipsoid: closed form; torus/genus5: the quartic in t, roots isolated by Bernstein
 * subdivision (Descartes' rule) then Newton-bisection; genus2/blobby: interval bounds on f and
 * on df/dt with the mean-value test, subdividing leftmost-first, then Newton-bisection. */
int         vp_imp_ray(int kind, const double o[3], const double d[3], double t0, double t1, double *t);
/* Exact closest surface point when a closed form exists (sphere, torus, ellipsoid): returns the
 * distance and fills q; returns -1 for the other kinds. */
double      vp_imp_closest_exact(int kind, const double p[3], double q[3]);
/* Newton projection along the gradient; 0 on success (|f|/|grad f| < 1e-14), -1 otherwise. */
int         vp_imp_project(int kind, const double p[3], double q[3]);
/* Local closest point by descent on |p - q| over the surface, starting at surface point start. */
double      vp_imp_foot(int kind, const double p[3], const double start[3], double q[3]);

#endif
