/* vp_line — the line laser: a fan of light in a plane; the camera sees a curve, and every image
 * column crossing it gives one 3D point, the camera ray of the curve's sub-pixel centre in that
 * column meeting the calibrated laser plane.
 *
 * Detection works on a laser-on / laser-off frame pair: their difference (on minus off) keeps the
 * laser and cancels what is lit in both frames (ambient light, gradients, highlights, a lamp).
 * Noise is the median absolute deviation of the difference; each column's baseline its median.
 * Per column the strongest peak of two bright pixels side by side (a lone hot pixel scores
 * nothing) is a measurement only when it stands min_snr noise sigmas above the baseline, has no
 * second separated peak above second_ratio of it, holds no spike (a pixel standing out of its
 * four neighbours: a hot pixel in one frame) nor a pixel saturated with the laser off (blind to
 * the laser), and its width fits
 * max_width, and the line there is not steep while its brightness changes fast along it (the
 * column would see its centre moved towards the brighter side: a limb, a fan's end, speckle).
 * Its centre: a Gaussian fit (weighted least squares on the log of the profile), or,
 * when the laser saturated the pixels, the middle of the half-level crossings. A column failing
 * a test reports nothing: a miss, never a guess.
 *
 * 3D: undistort (vp_lens_undistort), back-project (vp_camera_ray), meet the plane. Refused: rays
 * nearly parallel to the plane, points behind the camera, outside the fan (angle from the fan's
 * axis beyond half_angle) or outside [min_range, max_range] from the laser's origin.
 *
 * Calibration of the plane (vp_line_fit_plane): the camera already calibrated (vp_calib); the
 * line seen on a flat target at known planes; each column's ray meets the target's plane at a
 * point; the laser plane is the total least squares plane through all of them.
 * Pure C, no OS, no allocation: the caller owns the workspace. */
#ifndef VP_LINE_H
#define VP_LINE_H
#include <stdint.h>
#include "vp_cam.h"
#include "vp_calib.h"

#define VP_LINE_MAX_W 4096
#define VP_LINE_MAX_H 4096

typedef struct vp_line_model {
    vp_camera_model_t cam;       /* the calibrated camera, tilt frame */
    double origin[3], normal[3]; /* laser plane: through origin (the laser's exit point), unit normal, tilt frame */
    double axis[3];              /* the fan's centre direction, unit, in the plane */
    double half_angle;           /* the fan's half width, rad */
    double min_range, max_range; /* trusted span along each ray from origin, mm */
} vp_line_model_t;

typedef struct vp_line_config {
    int column_step;             /* every this many columns (0: 1) */
    double min_snr;              /* peak above this many noise sigmas (0: 8) */
    double min_peak;             /* and above this many grey levels (0: 6) */
    double second_ratio;         /* another separated peak this strong: two candidates (0: 0.35) */
    double max_width;            /* peak width at half its height, px (0: 7) */
    double spike_ratio;          /* a pixel above this times both neighbours (+ 4 sigma): a spike (0: 2) */
    double max_skew_px;          /* a steep line fading along itself moves a column's centre by about
                                    sigma^2 slope dln(peak)/du (from the neighbouring columns):
                                    beyond this, refused (0: 0.1 px) */
} vp_line_config_t;

/* Why a column reports nothing (vp_line_stats_t counts them). */
enum { VP_LINE_FOUND = 0, VP_LINE_NONE = 1, VP_LINE_SEVERAL = 2, VP_LINE_WIDE = 3, VP_LINE_SPIKE = 4,
       VP_LINE_BAD_FIT = 5, VP_LINE_SLANT = 6, VP_LINE_OFF_MODEL = 7, VP_LINE_NREASONS = 8 };

typedef struct vp_line_point {
    int col;                     /* image column */
    double u, v;                 /* sub-pixel centre (u = col) */
    double peak, snr, width;     /* difference above the baseline (grey levels), / noise, FWHM px */
    int saturated;               /* the laser clipped the on frame there (centre from the edges) */
    /* with a model: */
    double dist;                 /* from the laser's origin, mm */
    double dir[3];               /* unit direction from the origin to the point (tilt frame) */
    double p[3];                 /* the point, tilt frame */
} vp_line_point_t;

typedef struct vp_line_stats {
    int columns;                 /* columns looked at */
    int found;                   /* points reported */
    int why[VP_LINE_NREASONS];   /* columns by outcome (VP_LINE_*) */
    double noise;                /* sigma of the difference, grey levels */
    int off_lit;                 /* columns with a line in the laser-off frame (the difference's
                                    dip of two pixels below -min_snr sigma): the laser was on, or
                                    the scene moved between the frames; many: distrust the pair */
} vp_line_stats_t;

typedef struct vp_line_ws {      /* workspace, about 48 KB; reuse it frame after frame */
    int32_t hist[512];
    int32_t chist[512];
    float d[VP_LINE_MAX_H];      /* one column's difference */
    float s[VP_LINE_MAX_H];      /* its peak score */
    uint8_t sat[VP_LINE_MAX_H];  /* on frame at 255 */
    int16_t at[VP_LINE_MAX_W];   /* column index -> its peak among the found ones (-1: none) */
    uint8_t why[VP_LINE_MAX_W];  /* after vp_line_detect: column index (col / column_step) -> its
                                    outcome, VP_LINE_FOUND or why it reports nothing */
    uint8_t off_lit[VP_LINE_MAX_W]; /* and 1 where the column shows a line in the laser-off frame */
} vp_line_ws_t;

/* The 3D point of image point uv: VP_OK with *dist, dir (unit, from origin) and p (may be NULL);
 * VP_ERANGE when refused (parallel ray, behind the camera, outside the fan or the span, outside
 * the lens' model); VP_EINVAL for NaN, NULL or a bad model. Outputs unchanged unless VP_OK. */
int vp_line_point3d(const vp_line_model_t *m, const double uv[2], double *dist, double dir[3], double p[3]);

/* The line in a laser-on / laser-off pair (same size, GREY or YUYV luma). Points go to pts
 * (cap >= the columns looked at: width / column_step rounded up), *n their count; model may be
 * NULL (image points only, dist / dir / p zero). st may be NULL. VP_EINVAL for a bad frame,
 * config or capacity, with outputs unchanged. */
int vp_line_detect(const vp_frame_t *on, const vp_frame_t *off, const vp_line_config_t *cfg, const vp_line_model_t *model,
                   vp_line_ws_t *ws, vp_line_point_t *pts, int cap, int *n, vp_line_stats_t *st);

typedef struct vp_line_fit_report {
    int n;                       /* points used */
    double rms_mm, max_mm;       /* point distances to the fitted plane */
    double spread_mm;            /* rms extent across the points' main direction, in the plane */
    double tilt_deg;             /* angle between the fitted and the nominal normal */
    double span[2];              /* distances from the fitted origin the points cover, mm */
} vp_line_fit_report_t;

#define VP_LINE_FIT_MIN 10

/* Fits the laser plane to n observations (kind VP_OBS_SPOT: uv the line's centre in a column,
 * the target plane n.x = h, tilt frame) seen by cam (calibrated). nominal gives the fan (axis,
 * half angle, span) and the origin's nominal place: out's origin is the fitted plane's point
 * nearest it, its axis the nominal axis brought into the plane, its normal on the nominal's side.
 * VP_EINVAL: NULL, NaN, a bad kind, fewer than VP_LINE_FIT_MIN; VP_EDEGEN: a ray misses its
 * target, or the points lie on one line (one target pose). out unchanged unless VP_OK. */
int vp_line_fit_plane(const vp_camera_model_t *cam, const vp_calib_obs_t *obs, int n, const vp_line_model_t *nominal,
                      vp_line_model_t *out, vp_line_fit_report_t *rep);

#endif
