/* vp_head — the scanner head's body and the swept-volume check of its motions.
 *
 * The body is a few parts, each a solid core (a segment or an axis-aligned box) grown by a
 * radius, fixed in the tilt frame (turns with pan and tilt: the clearance ball at the laser
 * origin, the laser module, the camera, the bracket) or in the pan frame (turns with pan only:
 * the tilt motor on the yoke). Frames as in vp_kin.h: a tilt-frame point p is at
 * T + R(pan, tilt) p, a pan-frame point q at G + Rz(pan) q (G = joints x, y, z).
 *
 * The check of one linear joint motion ja -> jb (a MOVE, or one piece of an aim path) is
 * conservative advancement: at s the distance from a part to the object has a lower bound L
 * (the part cut into pieces, each piece's centre distance less its half-diagonal and radius);
 * no point of the part moves faster than M per unit s (M = |dG| + |dpan| (|tilt_offset| + rho)
 * + |dtilt| rho, rho the core's reach from the tilt axis centre), so s advances by L / M and the
 * part cannot touch the object in between. A part is reported when a point of it comes within
 * `tol` of the object's surface or lies inside it; a motion passed is proven clear.
 *
 * The ball rule (vp_head_reach): the planner keeps the laser origin outside Omega, and the board
 * puts the object at least `clearance` inside Omega, so no object point is nearer the laser
 * origin than the clearance. A part that stays within that ball in every pose cannot touch any
 * object: the proof needs neither the object nor the motion. */
#ifndef VP_HEAD_H
#define VP_HEAD_H
#include "vp_kin.h"

#define VP_HEAD_MAX_PARTS 8
enum { VP_HEAD_TILT = 0, VP_HEAD_PAN = 1 };          /* the frame a part is fixed in */
enum { VP_HEAD_CAPSULE = 0, VP_HEAD_BOX = 1 };

typedef struct vp_head_part {
    char name[24];
    int frame, kind;
    double a[3], b[3];   /* capsule: segment a-b; box: centre a, half-sizes b (frame axes) */
    double r;            /* radius grown round the core (capsule; 0 for a box) */
} vp_head_part_t;

typedef struct vp_head {
    double tilt_offset[3], laser_offset[3];
    int nparts;
    vp_head_part_t part[VP_HEAD_MAX_PARTS];
} vp_head_t;

/* The object as distances: the unsigned distance to its surface and "inside". */
typedef struct vp_head_object {
    double (*distance)(void *ctx, const double p[3]);
    int (*inside)(void *ctx, const double p[3]);
    void *ctx;
} vp_head_object_t;

/* An empty body on this kinematics. VP_EINVAL for NaN. */
int vp_head_init(vp_head_t *h, const double tilt_offset[3], const double laser_offset[3]);
/* Adds a part (name copied, cut to 23 bytes). VP_EINVAL (NaN, negative radius or size, unknown
 * frame or kind), VP_ENOMEM (VP_HEAD_MAX_PARTS parts already). */
int vp_head_add(vp_head_t *h, const char *name, int frame, int kind, const double a[3], const double b[3], double r);

/* How far part i reaches from the laser origin in any pose with tilt in [tilt_lo, tilt_hi]
 * degrees (a tilt-frame part: in every pose; a pan-frame part: the largest over that tilt). */
double vp_head_reach(const vp_head_t *h, int i, double tilt_lo, double tilt_hi);

/* The world core of part i in pose j: centre c and half-axes e[3][3] (a capsule: one axis). */
void vp_head_pose(const vp_head_t *h, int i, const double j[VP_KIN_JOINTS], double c[3], double e[3][3]);

/* A bound on how far any point of part i is from where it was when the joints go from ja to jb,
 * whatever the way between: |dG| + |dpan| (|tilt_offset| + rho) + |dtilt| rho (rho: the core's
 * reach from its frame's origin; angles in radians). */
double vp_head_moved(const vp_head_t *h, int i, const double ja[VP_KIN_JOINTS], const double jb[VP_KIN_JOINTS]);

/* Pose j against the object, for the parts whose bit is set in mask (bit i: part i): 1 when a
 * point of one lies within need (> 0) of the surface or inside the object (or the bisection
 * cannot tell: a switch that closes early); else 0, and *gap a lower bound (>= 0.75 need) on
 * their distance to the object. VP_EINVAL for bad arguments. */
int vp_head_near(const vp_head_t *h, const vp_head_object_t *obj, unsigned mask, const double j[VP_KIN_JOINTS],
                 double need, double *gap, unsigned long *evals);

/* The linear joint motion ja -> jb against the object: for each part, 1 in hit[i] when a point
 * of it comes within tol (> 0) of the surface or lies inside the object, else 0 (proven clear).
 * Returns the number of parts hit (>= 0), or VP_EINVAL. evals (may be NULL) grows by the
 * distance queries made. */
int vp_head_sweep(const vp_head_t *h, const vp_head_object_t *obj, const double ja[VP_KIN_JOINTS],
                  const double jb[VP_KIN_JOINTS], double tol, int hit[VP_HEAD_MAX_PARTS], unsigned long *evals);

#endif
