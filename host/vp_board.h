/* vp_board — a machine described as data (grbl's cpu_map/defaults idea, as an INI file):
 * pins as chip:offset, per-axis steps, speeds, accelerations, travel, backlash and homing,
 * the e-stop, the pan/tilt head geometry, the camera (device and pinhole model), the
 * rangefinder (range, calibration), Omega and scan defaults, and what host-sim renders in dry
 * runs. Every complaint names the file, the line, the section and the key.
 *
 * Pins:  [!]CHIP:OFFSET [pull-up|pull-down]   ('!' = active low)   or  none
 * Axes:  [axis.x] [axis.y] [axis.z] (mm) [axis.pan] [axis.tilt] (degrees)
 * Head body ([head] laser_body, camera_body, bracket, hub): capsules X1,Y1,Z1,X2,Y2,Z2,R and a
 * box CX,CY,CZ,HX,HY,HZ; each part must stay within [omega] clearance of the laser origin in
 * every pose (the ball rule, vp_head.h), unless an io = sim board states clear_by = swept.
 * See boards/rpi4-gantry.ini for every key with a comment. */
#ifndef VP_BOARD_H
#define VP_BOARD_H
#include <limits.h>
#include <stddef.h>
#include <stdint.h>
#include "vp_cam.h"
#include "vp_calib.h"
#include "vp_gpiod.h"
#include "vp_head.h"
#include "vp_kin.h"
#include "vp_laser.h"
#include "vp_machine.h"
#include "vp_planner.h"
#include "vp_step.h"

#define VP_BOARD_AXES 5
#ifdef PATH_MAX
#define VP_BOARD_PATH_MAX PATH_MAX   /* bytes of a file's path, with the NUL */
#else
#define VP_BOARD_PATH_MAX 4096
#endif
enum { VP_BOARD_IO_SIM = 0, VP_BOARD_IO_GPIOD = 1 };

typedef struct vp_board_axis {
    vp_gpio_pin_t step, dir, enable, lim_min, lim_max;
    vp_step_axis_t ax;
} vp_board_axis_t;

typedef struct vp_board {
    char name[64];
    char path[VP_BOARD_PATH_MAX];        /* the board file (a longer path is refused) */
    int io;                              /* VP_BOARD_IO_*: gpiod needs pins and an e-stop */
    char log_sync[32];                   /* session log sync policy (vp_logwriter_parse_sync; "" default) */
    vp_board_axis_t axis[VP_BOARD_AXES]; /* x y z pan tilt (index = vp_kin joint) */
    vp_gpio_pin_t estop, laser;
    /* [timing] */
    double pulse_us, dir_setup_us, enable_ms, poll_ms, spin_us, max_step_rate;
    int rt_priority;
    int debounce;                        /* samples a switch or e-stop level must hold (3) */
    double max_late_us;                  /* a step later than this is a retime (100) */
    char on_late[16];                    /* "reenter" (default) or "fault" */
    int late_fault;                      /* on_late = fault */
    /* [head] */
    double tilt_offset[3], laser_offset[3], origin_tol;
    vp_gpio_pin_t contact;               /* the head's contact switch (a touch probe at the laser origin) */
    int contact_sim;                     /* contact = sim: the dry run's switch only (io = sim) */
    double contact_stop;                 /* mm the stylus can travel past its trigger (0: not given) */
    int contact_halt;                    /* no pulse after a touch is confirmed (no deceleration) */
    char contact_by[8];                  /* "stylus" (default): a touch probe at the laser origin;
                                            "mount": the head's breakaway mount, any part pushed */
    int contact_mount;                   /* contact_by = mount */
    double contact_reach;                /* the most a move travels from a touch to rest (mm, at load) */
    char body_laser[96], body_camera[96], body_bracket[96], body_hub[96];  /* parts as written */
    char clear_by[16];                   /* "ball" (default) or "swept" (io = sim only) */
    int clear_swept;                     /* clear_by = swept */
    vp_head_t head;                      /* the body: the clearance ball and the parts */
    double head_reach, head_margin;      /* the farthest part from the laser origin, and the error
                                            added for origin_tol, step rounding and backlash (mm) */
    /* [camera] */
    vp_cam_config_t camera;
    vp_camera_model_t cam_model;         /* intrinsics and pose in the tilt frame */
    double look_at[3], up[3];
    int timeout_ms;
    char laser_colour[16];               /* [camera] laser_colour: red, green, blue or luma (default) */
    int latency_frames;                  /* frames after a laser switch that may still show the old
                                            state (2); vp_machine_measure_latency measures it */
    /* [rangefinder] */
    double min_range, max_range, band, settle_ms;
    double line[4], model[3];
    int calibrated;                      /* 1: line and model in the board, 2: from a calibration
                                            file (else 0: from the geometry) */
    vp_tri_model_t tri;                  /* the model in use */
    char near_spots[16];                 /* "too-close" (default) or "measure" */
    int confirm_spot;                    /* [rangefinder] confirm_spot: a second laser-on frame must show the
                                            spot where the first did (vp_machine_config_t.confirm) */
    double backdrop[6];                  /* [rangefinder] backdrop = XLO, YLO, ZLO, XHI, YHI, ZHI: matte
                                            walls round the machine (a box, mm) on which every beam
                                            that meets nothing ends, within max_range */
    int have_backdrop;                   /* then a frame with no spot is unreadable, never free space
                                            (vp_machine_config_t.backdrop) */
    int near_measure;                    /* a spot nearer than min_range: 1 a hit at the model's
                                            extrapolated distance, 0 VP_PROBE_TOO_CLOSE */
    char laser_kind[8];                  /* [rangefinder] laser = dot (default) or line */
    int line_laser;                      /* laser = line: a fan of light, a point per image column */
    double line_fan;                     /* [rangefinder] fan = DEGREES: the fan's full width (30) */
    double line_fan_used;                /* [rangefinder] fan_used = DEGREES: the middle part of the
                                            fan whose points become rays (default: all of it) */
    double line_normal[3];               /* [rangefinder] line_normal: the laser plane's normal, tilt
                                            frame (0, 0, 1: the fan spreads across the beam level) */
    int line_step;                       /* [rangefinder] line_step: every this many columns (0: as
                                            many as the machine keeps, VP_MACHINE_MAX_LINE) */
    char calibration[256];               /* [rangefinder] calibration = FILE (as written) */
    char calib_path[VP_BOARD_PATH_MAX];  /* that file relative to the board's folder ("" none) */
    int calib_missing;                   /* the key names a file that does not exist (yet) */
    /* [calibrate]: the calibration fixture, a flat target across +x */
    int have_fixture;
    double cal_target[3];                /* the plane x = cal_target[0]; the beam meets it at y, z */
    double cal_near, cal_far;            /* closest and farthest station (mm from the target) */
    int cal_stations, cal_frames;
    /* [omega] and scan defaults */
    int omega_kind;                      /* VP_OMEGA_BOX / VP_OMEGA_BALL (vp_planner.h values) */
    double omega_lo[3], omega_hi[3], omega_center[3], omega_radius;
    double interior[3], start[3], eps, clearance;
    double min_feature, feature_margin;  /* tubes inside Omega (0: the head stays outside) */
    /* [sim]: dry runs */
    char sim_surface[256];
    double sim_blur, sim_noise, sim_ambient, sim_gradient, sim_texture, sim_energy;
    double sim_seed;
    double sim_frame_ms;                 /* > 0: the simulated camera streams at this period */
    int sim_latency;                     /* and hands frames over this many frames late */
    double sim_cam_pos[3], sim_cam_look[3];  /* camera_position / camera_look_at */
    double sim_speckle[2];               /* speckle = CONTRAST, F-NUMBER (the spot's grain) */
    double sim_vibration[4];             /* vibration = PX, HZ, DECAY_MS, DEGREES (after each move) */
    double sim_flicker[2];               /* flicker = DEPTH, HZ (the ambient light's mains ripple) */
    double sim_glint[6];                 /* glint = PEAK, SIGMA_PX, DIST_MM, ACROSS_PX, SWING_PX, PERIOD_MS */
    double sim_ghost[3];                 /* ghost = ENERGY, DU_PX, DV_PX: a reflection of the laser (a
                                            second spot or line of this relative energy, moved so) */
    double sim_dark[3];                  /* dark = ALBEDO, Z_LO, Z_HI (the object is dark between) */
    vp_camera_model_t sim_cam;           /* the camera as mounted on the simulated head (default:
                                            the [camera] model; a dry run renders with it) */
    double sim_dist[4];                  /* [sim] distortion: the simulated lens' k1, k2, p1, p2 */
    double sim_laser_origin[3];          /* [sim] laser_origin (default: [head] laser_offset) */
    double sim_laser_error[2];           /* [sim] laser_error: the beam turned ANGLE degrees from +x,
                                            towards AZIMUTH degrees about x from +y */
    /* the full rangefinder model (vp_calib) from a calibration file that has one */
    int have_rf;
    vp_rf_model_t rf;
    double cal_mark[2];                  /* [calibrate] mark = Y, Z: a bright dot on the target */
    int have_mark;
    /* a line laser's plane from a calibration file that has one (tilt frame) */
    int have_plane;
    double plane_origin[3], plane_normal[3];
} vp_board_t;

/* What a calibration file says about its fit (vp_board_calibration_*). */
typedef struct vp_board_calib {
    char board[64];                      /* the board it was made on */
    int spots, stations;
    double near, far;                    /* the calibrated span, mm */
    double rms_mm, max_mm, line_rms_px;  /* fit residuals */
    vp_tri_model_t tri;                  /* line, model (ranges: the span) */
    int have_rf;                         /* the full model too (camera, distortion, beam) */
    vp_rf_model_t rf;                    /* its ranges: the span the spots covered */
    double rf_rms_px;
    int have_plane;                      /* a line laser's plane (vp_line_fit_plane) */
    double plane_origin[3], plane_normal[3];   /* tilt frame, the normal unit */
    int plane_points, plane_poses;       /* columns and target poses it was fitted to */
    double plane_rms_mm, plane_max_mm;   /* their distances to it */
    double plane_tilt_deg;               /* from the board's nominal line_normal */
} vp_board_calib_t;

/* VP_OK; VP_EIO (cannot read); VP_EINVAL (syntax, unknown or missing key, bad value, an
 * inconsistent machine); err gets "file:line: [section] key: reason". */
int  vp_board_load(const char *path, vp_board_t *b, char *err, size_t errlen);
int  vp_board_parse(const char *text, const char *name, vp_board_t *b, char *err, size_t errlen);
/* 1 if the board has a contact switch on its head ([head] contact). */
int  vp_board_has_contact(const vp_board_t *b);
/* 1 if head part i is the clearance ball about the laser origin ([omega] clearance), the
 * planner's assumption rather than a part of the machine. */
int  vp_board_part_is_ball(const vp_board_t *b, int i);

/* A calibration file (INI: [calibration] about the fit, [rangefinder] line and model) replaces
 * the board's rangefinder model (b->calibrated = 2, b->calib_path = path; the board's
 * min_range/max_range stay). A board with `calibration = FILE` in [rangefinder] loads it by
 * itself when the file exists (relative to the board's folder). VP_EIO (cannot read),
 * VP_EINVAL ("file:line: [section] key: reason", or made on another board). info may be NULL. */
int  vp_board_calibration_load(vp_board_t *b, const char *path, vp_board_calib_t *info, char *err, size_t errlen);
/* Writes a calibration file for board b (VP_EIO with err). */
int  vp_board_calibration_write(const char *path, const vp_board_t *b, const vp_board_calib_t *c, char *err,
                                size_t errlen);

/* The module configurations a board implies. */
void vp_board_step_config(const vp_board_t *b, vp_step_config_t *c);
void vp_board_kin_config(const vp_board_t *b, vp_kin_config_t *k);
void vp_board_gpiod_config(const vp_board_t *b, vp_gpiod_config_t *g);
void vp_board_machine_config(const vp_board_t *b, vp_machine_config_t *m);
/* The planner's scan: Omega, the interior point, eps, the start, the rangefinder's range and the
 * device clearance from the board; noise_tol and confirm_misses 0 (the caller's to set). */
void vp_board_planner_config(const vp_board_t *b, vp_planner_config_t *c);

#endif
