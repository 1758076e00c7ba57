/* vp_dryrun — a board's machine with host-sim at the hardware boundary: the same vp_machine
 * (kinematics, step generator, rangefinder) on the recording GPIO backend (simulated clock,
 * switches where the board's homing expects them, carriages with the board's backlash as slack)
 * and on vp_camsim frames rendered at the carriages' true pose. Nothing sleeps. A board with a
 * contact switch ([head] contact) gets one that closes while the true laser origin (the probe
 * point) is inside the object. */
#ifndef VP_DRYRUN_H
#define VP_DRYRUN_H
#include <stddef.h>
#include "vp_board.h"
#include "vp_camsim.h"
#include "vp_head.h"
#include "vp_iorec.h"
#include "vp_machine.h"
#include "vp_surface.h"

typedef struct vp_dryrun {
    vp_machine_t m;
    vp_iorec_t rec;
    vp_camsim_t *cs;
    vp_surface_t *surf;
    vp_board_t board;
    uint8_t *frame;              /* the machine's diff_buf: 2 frames */
    /* the contact switch: the object (or the flat target x >= target_x) at the true origin */
    vp_kin_t touch_kin;
    int flat_target;
    double target_x;
    int32_t touch_carriage[VP_KIN_JOINTS];   /* where it was last evaluated */
    double touch_origin[3], touch_clear;     /* the origin there, and a ball around it in which
                                                the answer stays the same (its distance to the
                                                surface) */
    int touch_known, touch_in;
    unsigned long touch_evals;               /* surface queries made */
    /* contact_by = mount: the switch closes while a part of the head (the clearance ball left
     * out) is within VP_DRYRUN_MOUNT_NEED of the object, at the carriages' true pose */
    unsigned mount_mask;                     /* the parts it senses (bit i: board.head.part[i]) */
    double mount_j[VP_KIN_JOINTS], mount_gap;  /* the pose last evaluated, and a lower bound of the
                                                  parts' distance to the object there */
    double mount_first[VP_KIN_JOINTS];       /* the pose where it last closed */
    double fan_origin[3], fan_normal[3];     /* a line laser: its plane as mounted (tilt frame) */
} vp_dryrun_t;

typedef struct vp_dryrun_options {
    const char *surface;         /* NULL: the board's [sim] surface */
    vp_iorec_edge_t *edges;      /* keep edges here (NULL: count only) */
    size_t cap;
    unsigned long long seed;     /* 0: the board's [sim] seed */
    int flat_target;             /* 1: the scene is a flat target x = target_x, not the surface */
    double target_x;
} vp_dryrun_options_t;

/* contact_by = mount: how near the object a part comes before the switch closes (mm): the dry
 * run's stand-in for its first touch. */
#define VP_DRYRUN_MOUNT_NEED 0.25

/* The carriages start where the laser origin is at the board's start with pan = tilt = 0
 * (home_pos for axes without a switch). VP_EINVAL (bad surface spec; err says why). */
int  vp_dryrun_open(const vp_board_t *b, const vp_dryrun_options_t *o, vp_dryrun_t **out, char *err, size_t errlen);
vp_machine_t *vp_dryrun_machine(vp_dryrun_t *d);
/* The true laser origin and beam (from the carriages, not from the step counts). */
void vp_dryrun_true_beam(const vp_dryrun_t *d, double origin[3], double dir[3]);
/* A line laser: the plane the renderer draws the fan in (tilt frame; origin on it, unit normal),
 * the board's nominal plane turned with the mounted beam. 0 without a line laser. */
int  vp_dryrun_true_plane(const vp_dryrun_t *d, double origin[3], double normal[3]);
/* The simulated object as the head's body check takes it (vp_head.h). */
vp_head_object_t vp_dryrun_object(const vp_dryrun_t *d);
/* contact_by = mount: a bound on how far any part the switch senses has gone from the pose where
 * the switch last closed to joints j (NULL: the carriages now) (mm; 0 if it never closed). */
double vp_dryrun_mount_past(const vp_dryrun_t *d, const double *j);
void vp_dryrun_close(vp_dryrun_t *d);

#endif
