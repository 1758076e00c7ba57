/* vp_kin — kinematics of an XYZ gantry carrying a pan/tilt head with a laser.
 *
 * Joints (VP_KIN_JOINTS): x, y, z in mm (the pan pivot), pan and tilt in degrees.
 * Head frame at pan = tilt = 0: the world axes; the beam leaves along +x.
 *   R(pan, tilt) = Rz(pan) * Ry(-tilt)          (tilt > 0 raises the beam)
 *   tilt frame:   origin  T = G + Rz(pan) * tilt_offset,  axes R
 *   laser origin  O = T + R * laser_offset,  beam direction d = R * (1,0,0)
 * so pan = atan2(dy, dx), tilt = asin(dz). The world frame is the machine frame (mm). A beam
 * calibrated off +x (laser_dir = b): d = R b, and aiming solves bx sin(tilt) + bz cos(tilt) = dz,
 * then pan turns (bx cos(tilt) - bz sin(tilt), by) onto (dx, dy); within asin|by| of vertical
 * such a beam cannot point, and is aimed as steep as it goes (off dir by at most that angle).
 *
 * MOVE keeps pan and tilt and translates the gantry: every joint moves linearly and the laser
 * origin (the planner's device point) stays exactly on the segment. Aiming (PROBE) turns the
 * head about the laser origin: a few linear joint segments keep the origin within origin_tol.
 * Pure C, no OS, no allocation. */
#ifndef VP_KIN_H
#define VP_KIN_H

#define VP_KIN_JOINTS 5
enum { VP_J_X, VP_J_Y, VP_J_Z, VP_J_PAN, VP_J_TILT };

typedef struct vp_kin_config {
    double tilt_offset[3];   /* tilt axis centre from the pan pivot, pan frame (mm) */
    double laser_offset[3];  /* laser origin from the tilt axis centre, tilt frame (mm) */
    double lo[VP_KIN_JOINTS], hi[VP_KIN_JOINTS]; /* joint travel; lo == hi == 0: unlimited */
    double origin_tol;       /* aim: laser origin stays this close to its line (0: 0.1 mm) */
    double laser_dir[3];     /* the beam in the tilt frame as calibrated (0, 0, 0: +x); then
                                d = R * laser_dir and aiming solves for it */
} vp_kin_config_t;

typedef struct vp_kin {
    vp_kin_config_t cfg;
    double reach;
    int tilted;              /* the beam is not +x */
    double beam[3];          /* unit beam direction in the tilt frame */
} vp_kin_t;

/* VP_EINVAL for NaN or lo > hi. */
int vp_kin_init(vp_kin_t *k, const vp_kin_config_t *cfg);

/* The head's rotation for pan and tilt (degrees): Rz(pan) Ry(-tilt), row-major (tilt frame ->
 * world); and r v. */
void vp_kin_rot(double pan, double tilt, double r[9]);
void vp_kin_mul(const double r[9], const double v[3], double out[3]);
/* Head pose: rot (row-major 3x3, tilt frame -> world), pos = tilt frame origin. */
void vp_kin_head(const vp_kin_t *k, const double j[VP_KIN_JOINTS], double rot[9], double pos[3]);
/* Laser origin and unit beam direction for joints j. */
void vp_kin_forward(const vp_kin_t *k, const double j[VP_KIN_JOINTS], double origin[3], double dir[3]);
/* World point of a hit measured dist along the beam. */
void vp_kin_point(const vp_kin_t *k, const double j[VP_KIN_JOINTS], double dist, double p[3]);

/* Joints that put the laser origin at `origin` aiming along unit `dir`, the pan/tilt solution
 * in travel nearest to `cur` (pan may wrap by 360). VP_EINVAL (NaN, dir not unit),
 * VP_ERANGE (no solution within travel). */
int vp_kin_aim(const vp_kin_t *k, const double cur[VP_KIN_JOINTS], const double origin[3],
               const double dir[3], double out[VP_KIN_JOINTS]);
/* Joints that move the laser origin to `to` with pan/tilt unchanged (a straight line of the
 * origin when interpolated linearly). VP_ERANGE outside travel. */
int vp_kin_move(const vp_kin_t *k, const double cur[VP_KIN_JOINTS], const double to[3],
                double out[VP_KIN_JOINTS]);
/* Waypoints from cur to target (an aim result) that keep the laser origin within origin_tol
 * of the line from its start to its end when each piece is run as a linear joint move.
 * Writes n <= max waypoints (the last one is target) and returns n, or VP_ENOMEM. */
int vp_kin_aim_path(const vp_kin_t *k, const double cur[VP_KIN_JOINTS],
                    const double target[VP_KIN_JOINTS], double (*way)[VP_KIN_JOINTS], int max);
/* 1 if j lies within the joint travel. */
int vp_kin_in_travel(const vp_kin_t *k, const double j[VP_KIN_JOINTS]);

#endif
