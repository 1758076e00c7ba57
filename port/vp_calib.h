/* vp_calib — the rangefinder's full geometric model and its calibration.
 *
 * Model: the camera (intrinsics fx, fy, cx, cy; Brown-Conrady distortion k1, k2, p1, p2; pose in
 * the tilt frame, vp_camera_model_t) and the laser beam (a line in the tilt frame: origin and unit
 * direction). A spot is measured by undistorting it, back-projecting the camera ray and taking
 * the point of the beam closest to that ray: its distance along the beam from the origin. A ray
 * that passes farther from the beam than ray_tol_px (as seen in the image at that depth) is not
 * the laser; a distance outside the calibrated span is refused, never extrapolated.
 *
 * Calibration: observations the machine makes with known head poses (vp_kin), all in the tilt
 * frame: the image of a known point (a mark printed on the flat target) and the image of the
 * laser spot where the beam meets a known plane (the target). Levenberg-Marquardt over all 18
 * parameters (4 intrinsics, 4 distortion, 6 camera pose, 2 beam offset across the beam, 2 beam
 * direction) from the board's nominal values, minimising image residuals (px; Huber's loss beyond
 * VP_CALIB_HUBER_PX, then, if some are left beyond 3 times that, again without them: a stray
 * detection, a reflection taken for the mark, does not bend the model). The laser spot
 * alone cannot calibrate the camera: it always lies on the beam, so its image only ever samples
 * one curve of the image; the mark seen over the image and over depth does.
 * Pure C, no OS, no allocation. */
#ifndef VP_CALIB_H
#define VP_CALIB_H
#include "vp_laser.h"

/* Distortion of normalised coordinates xy (dist: k1, k2, p1, p2). */
void vp_lens_distort(const double dist[4], const double xy[2], double out[2]);
/* Its inverse by Newton's method; VP_EDEGEN when it does not converge (far outside the lens). */
int  vp_lens_undistort(const double dist[4], const double xyd[2], double out[2]);
/* The camera ray of image point uv in the tilt frame: from cam->pos along dir, scaled so that
 * its component along the optical axis is 1 (a point at depth z is pos + z dir). */
int  vp_camera_ray(const vp_camera_model_t *cam, const double uv[2], double dir[3]);

typedef struct vp_rf_model {
    vp_camera_model_t cam;       /* intrinsics, distortion, pose in the tilt frame */
    double origin[3], dir[3];    /* the beam in the tilt frame (dir unit) */
    double min_range, max_range; /* the calibrated span, mm along the beam */
    double ray_tol_px;           /* farther from the beam than this (px at the spot's depth): not the laser */
} vp_rf_model_t;

enum { VP_RF_OK = 0, VP_RF_OFF_BEAM = 1, VP_RF_OUT_OF_SPAN = 2 };

/* The spot at uv: VP_OK and *why (VP_RF_*); *d the distance along the beam (also when out of
 * span; undefined when off the beam), gap_px (may be NULL) the ray's miss of the beam in px.
 * VP_EINVAL for NaN or a model without a span. */
int  vp_rf_distance(const vp_rf_model_t *m, const double uv[2], double *d, int *why, double *gap_px);
/* Image of the beam's point at distance d (0 when behind the camera). */
int  vp_rf_spot(const vp_rf_model_t *m, double d, double uv[2]);
/* The nominal model: camera as given, beam from laser_offset along +x. */
int  vp_rf_nominal(const vp_camera_model_t *cam, const double laser_offset[3], double min_range, double max_range,
                   vp_rf_model_t *m);

enum { VP_OBS_MARK = 1, VP_OBS_SPOT = 2 };

typedef struct vp_calib_obs {
    int kind;                    /* VP_OBS_* */
    double uv[2];                /* detected image point, px */
    double p[3];                 /* MARK: the point in the tilt frame */
    double n[3], h;              /* SPOT: the target plane n.x = h in the tilt frame (n unit) */
} vp_calib_obs_t;

typedef struct vp_rf_fit_report {
    int marks, spots, iterations;
    double rms_px, max_px;               /* all observations */
    double mark_rms_px, spot_rms_px;
    double spot_rms_mm, spot_max_mm;     /* spots measured by the fitted model against the
                                            fitted beam's crossing of the target plane */
    double start_rms_px;                 /* the nominal model's */
    int outliers;                        /* observations left farther than VP_CALIB_HUBER_PX */
    int strays;                          /* farther than 3 VP_CALIB_HUBER_PX (the last round leaves such out) */
    double span[2];                      /* distances the spots cover, mm */
} vp_rf_fit_report_t;

#define VP_CALIB_MIN_MARKS 20
#define VP_CALIB_HUBER_PX 2.0            /* residuals beyond this count linearly (Huber's loss) */
#define VP_CALIB_MIN_SPOTS 6

/* Fits the model to n observations from start (the nominal). VP_EINVAL: a NaN or a bad kind, or
 * fewer than VP_CALIB_MIN_MARKS marks / VP_CALIB_MIN_SPOTS spots; VP_EDEGEN: the observations
 * cannot fix every parameter (marks all at one depth, spots all at one distance, ...) or the fit
 * diverges (an rms of 10 px or more, or not a number, with more than 1 in 10 observations off by
 * over 3 Huber cuts: a few observations detected far from where they were are left out and
 * counted, not a failure; rep, when not NULL, is written then too: rms_px and strays say how
 * far). out's span: the distances the spots cover, widened by 0.5 mm + 0.2 %. */
int  vp_rf_fit(const vp_calib_obs_t *obs, int n, const vp_rf_model_t *start, vp_rf_model_t *out,
               vp_rf_fit_report_t *rep);

/* The camera alone (a line laser: no spot on a beam): intrinsics, distortion and pose fitted to
 * marks only, as vp_rf_fit does; out's beam and span are start's. VP_EINVAL: a spot among the
 * observations, fewer than VP_CALIB_MIN_MARKS marks, a NaN; VP_EDEGEN as vp_rf_fit. */
int  vp_rf_fit_camera(const vp_calib_obs_t *obs, int n, const vp_rf_model_t *start, vp_rf_model_t *out,
                      vp_rf_fit_report_t *rep);

#endif
