/* vp_board — a machine described as data (grbl's cpu_map/defaults idea, as an INI file):
 * pins as chip:offset, per-axis steps, speeds, accelerations, travel, backlash and homing,
 * the e-stop, the pan/tilt head geometry, the camera (device and pinhole model), the
 * rangefinder (range, calibration), Omega and scan defaults, and what host-sim renders in dry
 * runs. Every complaint names the file, the line, the section and the key.
 *
 * Pins:  [!]CHIP:OFFSET [pull-up|pull-down]   ('!' = active low)   or  none
 * Axes:  [axis.x] [axis.y] [axis.z] (mm) [axis.pan] [axis.tilt] (degrees)
 * See boards/rpi4-gantry.ini for every key with a comment. */
#ifndef VP_BOARD_H
#define VP_BOARD_H
#include <stddef.h>
#include <stdint.h>
#include "vp_cam.h"
#include "vp_gpiod.h"
#include "vp_kin.h"
#include "vp_laser.h"
#include "vp_step.h"

#define VP_BOARD_AXES 5
enum { VP_BOARD_IO_SIM = 0, VP_BOARD_IO_GPIOD = 1 };

typedef struct vp_board_axis {
    vp_gpio_pin_t step, dir, enable, lim_min, lim_max;
    vp_step_axis_t ax;
} vp_board_axis_t;

typedef struct vp_board {
    char name[64];
    char path[256];
    int io;                              /* VP_BOARD_IO_*: gpiod needs pins and an e-stop */
    vp_board_axis_t axis[VP_BOARD_AXES]; /* x y z pan tilt (index = vp_kin joint) */
    vp_gpio_pin_t estop, laser;
    /* [timing] */
    double pulse_us, dir_setup_us, enable_ms, poll_ms, spin_us, max_step_rate;
    int rt_priority;
    /* [head] */
    double tilt_offset[3], laser_offset[3], origin_tol;
    /* [camera] */
    vp_cam_config_t camera;
    vp_camera_model_t cam_model;         /* intrinsics and pose in the tilt frame */
    double look_at[3], up[3];
    int timeout_ms;
    /* [rangefinder] */
    double min_range, max_range, band, settle_ms;
    double line[4], model[3];
    int calibrated;                      /* line and model given (else from the geometry) */
    vp_tri_model_t tri;                  /* the model in use */
    /* [omega] and scan defaults */
    int omega_kind;                      /* VP_OMEGA_BOX / VP_OMEGA_BALL (vp_planner.h values) */
    double omega_lo[3], omega_hi[3], omega_center[3], omega_radius;
    double interior[3], start[3], eps, clearance;
    /* [sim]: dry runs */
    char sim_surface[256];
    double sim_blur, sim_noise, sim_ambient, sim_gradient, sim_texture, sim_energy;
    double sim_seed;
} vp_board_t;

/* VP_OK; VP_EIO (cannot read); VP_EINVAL (syntax, unknown or missing key, bad value, an
 * inconsistent machine); err gets "file:line: [section] key: reason". */
int  vp_board_load(const char *path, vp_board_t *b, char *err, size_t errlen);
int  vp_board_parse(const char *text, const char *name, vp_board_t *b, char *err, size_t errlen);

/* The module configurations a board implies. */
void vp_board_step_config(const vp_board_t *b, vp_step_config_t *c);
void vp_board_kin_config(const vp_board_t *b, vp_kin_config_t *k);
void vp_board_gpiod_config(const vp_board_t *b, vp_gpiod_config_t *g);

#endif
