/* vp_laser — the camera laser rangefinder: find the laser spot in a grayscale frame, turn its
 * image position into a distance along the beam.
 *
 * Spot: background from block percentiles (ambient light, gradients), refined to a plane fitted
 * to the ring around the spot before the centroid; noise from the median
 * absolute residual, peak of the 3x3 mean residual without its brightest pixel (a hot pixel
 * scores nothing), the spot's
 * connected region above a fraction of its peak, sub-pixel centroid weighted by the residual
 * above that threshold. A miss, never a guess: no peak above min_snr noise sigmas (no spot), a
 * second peak above second_ratio of the first outside the spot, standing out of its own
 * surroundings (several spots; a broad glare is not one), a region that
 * does not fit in max_radius (a lamp, a reflection, not a spot), or a spot off the laser line.
 *
 * Distance: the beam is a line, so its image is a line (the epipolar line) and, for a pinhole
 * camera, the distance along the beam is a linear-fractional function of the position s along
 * that line:  d = (a + b s) / (1 + c s),  s = (spot - p0) . e.  Three numbers and a line, fitted
 * from frames at known distances (vp_tri_fit) or computed from the camera geometry.
 * Pure C, no OS; the caller owns the workspace. */
#ifndef VP_LASER_H
#define VP_LASER_H
#include <stdint.h>
#include "vp_cam.h"

/* Camera on the tilt stage (the laser's frame, vp_kin): a pinhole with Brown-Conrady lens
 * distortion as OpenCV defines it (k3 = 0), on normalised coordinates x = X/Z, y = Y/Z:
 *   r2 = x^2 + y^2,  x' = x (1 + k1 r2 + k2 r2^2) + 2 p1 x y + p2 (r2 + 2 x^2),
 *                    y' = y (1 + k1 r2 + k2 r2^2) + p1 (r2 + 2 y^2) + 2 p2 x y,
 *   u = fx x' + cx,  v = fy y' + cy.  dist all 0: the plain pinhole. */
typedef struct vp_camera_model {
    int width, height;
    double fx, fy, cx, cy;   /* focal lengths and principal point, pixels */
    double dist[4];          /* k1, k2, p1, p2 */
    double pos[3];           /* centre in the tilt frame (mm) */
    double rot[9];           /* rows: camera x (right), y (down), z (forward) in the tilt frame */
} vp_camera_model_t;

/* rot from a point the optical axis passes through and an up direction (tilt frame). */
int vp_camera_look_at(vp_camera_model_t *c, const double look[3], const double up[3]);
/* Image of a point given in the tilt frame (through the lens distortion): 1 and (u,v) if in front
 * of the camera. */
int vp_camera_project(const vp_camera_model_t *c, const double p[3], double uv[2]);

typedef struct vp_tri_model {
    double p0[2], e[2];      /* epipolar line: p0 + s e, e unit, s grows with distance */
    double a, b, c;          /* d = (a + b s) / (1 + c s) */
    double line_tol;         /* px: spots farther from the line are not the laser (0: off) */
    double min_range, max_range;   /* mm, where the spot is in the frame and trusted */
} vp_tri_model_t;

/* Distance for image point uv; VP_ERANGE outside [min_range, max_range] or off the line. */
int    vp_tri_distance(const vp_tri_model_t *m, const double uv[2], double *d);
/* s for a distance (the inverse of the model). */
double vp_tri_s(const vp_tri_model_t *m, double d);
/* d(s) and |dd/ds| (mm per pixel along the line). */
double vp_tri_eval(const vp_tri_model_t *m, double s, double *dd_ds);
/* The exact model of a pinhole camera and a beam from laser_offset along +x (tilt frame); the
 * ranges are clipped to the frame and to [min_range, max_range] (max_range 0: unbounded). */
int vp_tri_from_geometry(const vp_camera_model_t *cam, const double laser_offset[3], double min_range,
                         double max_range, vp_tri_model_t *m);

typedef struct vp_tri_fit_report {
    int n;
    double rms_mm, max_mm;   /* distance residuals */
    double line_rms_px;      /* spots off the fitted line */
} vp_tri_fit_report_t;

/* Fits line and model to n >= 4 spots uv[i] seen at known distances d[i] (linear least squares,
 * then Gauss-Newton on the distance residuals). min/max_range become the calibrated span unless
 * the caller sets them after. VP_EINVAL (n < 4, NaN), VP_EDEGEN (degenerate spots). */
int vp_tri_fit(const double (*uv)[2], const double *d, int n, int width, int height,
               vp_tri_model_t *m, vp_tri_fit_report_t *rep);

/* ---- spot detection ---- */

#define VP_SPOT_MAX_BLOCKS 8192
#define VP_SPOT_MAX_W 4096
#define VP_SPOT_MAX_H 65536
#define VP_SPOT_MAX_R 32

typedef struct vp_spot_config {
    int block;               /* background block size, px (0: 16) */
    double percentile;       /* background level within a block (0: 0.3) */
    double min_snr;          /* smoothed peak above this many noise sigmas (0: 10) */
    double min_peak;         /* and above this many grey levels (0: 8) */
    double rel_thresh;       /* spot = pixels above this fraction of the peak (0: 0.3) */
    double second_ratio;     /* another peak this strong: several spots (0: 0.35) */
    int max_radius;          /* spot must fit in this half-size, px (0: 16, <= VP_SPOT_MAX_R) */
    double band;             /* with a model: search only this close to the line, px (0: all) */
} vp_spot_config_t;

enum { VP_SPOT_FOUND = 1, VP_SPOT_NONE = 0, VP_SPOT_SEVERAL = -1, VP_SPOT_TOO_BIG = -2,
       VP_SPOT_OFF_LINE = -3,
       VP_SPOT_NOT_LASER = -4,     /* vp_machine: light in the laser-off frame where the spot is */
       VP_SPOT_MOVED = -5 };       /* vp_machine: a second laser-on frame saw it elsewhere, or not at all */

typedef struct vp_spot {
    int result;              /* VP_SPOT_* */
    double u, v;             /* sub-pixel centre (x right, y down) */
    double peak, noise, snr; /* residual peak and noise (grey levels) */
    double second;           /* strongest other peak (above its ring) / peak */
    int u2, v2;              /* where it is */
    int area;                /* pixels in the spot */
} vp_spot_t;

typedef struct vp_spot_ws {  /* workspace, about 130 KB; reuse it frame after frame */
    float bg[VP_SPOT_MAX_BLOCKS];
    float rows[5][VP_SPOT_MAX_W];
    float tx[VP_SPOT_MAX_W];         /* background interpolation along a row */
    int16_t bx[VP_SPOT_MAX_W];
    uint8_t mark[(2 * VP_SPOT_MAX_R + 1) * (2 * VP_SPOT_MAX_R + 1)];
    int16_t stack[(2 * VP_SPOT_MAX_R + 1) * (2 * VP_SPOT_MAX_R + 1)][2];
} vp_spot_ws_t;

/* Returns VP_OK with out->result telling found or which miss; VP_EINVAL for a bad frame (8 x 8
 * up to VP_SPOT_MAX_W x VP_SPOT_MAX_H, 1-4 bytes a pixel) or a configuration out of range (block
 * 0-VP_SPOT_MAX_W, percentile and rel_thresh 0-1, the other numbers finite and not negative; a
 * max_radius above VP_SPOT_MAX_R is taken as that), out then unchanged. model may be NULL (no
 * line gating). */
int vp_spot_find(const vp_frame_t *f, const vp_spot_config_t *cfg, const vp_tri_model_t *model,
                 vp_spot_ws_t *ws, vp_spot_t *out);

/* Frame -> distance: the spot, then the model. 1 hit with *d, 0 a miss (out->result says
 * why; a spot out of range is a miss too), < 0 an error. */
int vp_laser_measure(const vp_frame_t *f, const vp_spot_config_t *cfg, const vp_tri_model_t *m,
                     vp_spot_ws_t *ws, vp_spot_t *spot, double *d);

#endif
