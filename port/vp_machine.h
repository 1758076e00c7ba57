/* vp_machine — the scanner as one object: kinematics, step generator, GPIO backend, camera
 * backend and rangefinder model, executing the planner's commands:
 *   MOVE  -> vp_kin_move -> vp_step_move -> backend              (a straight line of the laser origin)
 *   PROBE -> vp_kin_aim (+ aim path) -> vp_step_move_path -> settle -> laser off -> mark -> capture
 *            (copied) -> laser on -> mark -> capture -> on minus off -> spot -> distance -> laser off
 *            -> vp_probe_result_t
 * so a scan loop is:  while (vp_planner_next(pl, &cmd) == VP_OK && cmd.kind != VP_CMD_DONE) {
 *                         if (vp_machine_exec(m, &cmd, &res) < 0) break;   // fault: stop, resumable
 *                         if (cmd.kind == VP_CMD_PROBE) vp_planner_feed(pl, &res); }
 * The backends are the caller's (vp_gpiod or vp_iorec; vp_v4l2, vp_libcamera or camsim): the
 * machine does not know which. A probe's distance is along the beam the joints actually give
 * (steps are quantised); `last` keeps that beam and the measured point. A spot seen nearer than
 * the rangefinder's min_range is reported as a hit (extrapolated): a surface that close is never
 * free space. A surface so near that its spot leaves the frame is not seen at all: keep the
 * planner's clearance above that distance (see the board's [rangefinder] min_range).
 *
 * A contact switch on the head (cfg.contact: a touch probe at the laser origin) is the safety
 * net for surfaces the rangefinder cannot see (black, shiny: no spot, read as free space). A
 * MOVE watches it: when it closes the joints at the trigger are latched, the head decelerates at
 * the axes' accelerations and stops, and the MOVE returns VP_OK with last.contact = 1, the
 * trigger's distance along the commanded segment (last.contact_at) and how far past it the head
 * stopped (last.overtravel). A contact already closed when a MOVE starts (touching at rest) is a
 * contact at 0: nothing moves. The MOVE after a contact must back off (not advance along the
 * touching move's direction; VP_ESTATE, nothing moved): the head first returns along the line to
 * the trigger point (where the planner believes it stands), then makes the move; the contact
 * must open on the way, else the machine faults (VP_EABORT, step.fault VP_STEP_FAULT_CONTACT:
 * a stuck switch or a broken wire reads closed forever; homing needed). */
#ifndef VP_MACHINE_H
#define VP_MACHINE_H
#include "vp_cam.h"
#include "vp_calib.h"
#include "vp_io.h"
#include "vp_kin.h"
#include "vp_laser.h"
#include "vp_line.h"
#include "vp_planner.h"
#include "vp_step.h"

#define VP_MACHINE_MAX_WAY 128
#define VP_MACHINE_PATH_MOVES 16      /* MOVEs one path takes at most (vp_machine_move_path) */
#define VP_MACHINE_PATH_WAY 256       /* and their pieces */
#define VP_MACHINE_BACK (VP_MACHINE_MAX_WAY + 2) /* a touch's way back: the pieces retraced */
#define VP_MACHINE_MAX_CALIB 256
#define VP_MACHINE_MAX_LINE 1024      /* a line laser's points per frame (columns looked at) */

typedef struct vp_machine_stats {
    unsigned long moves, probes, hits, misses, frames, camera_errors;
    unsigned long miss_reason[7];     /* by VP_SPOT_* + 3; [5]: spot found but out of range; [6]: not
                                         the laser's spot (VP_SPOT_NOT_LASER, VP_SPOT_MOVED) */
    unsigned long near;               /* spots nearer than min_range, reported as hits */
    double travel;                    /* laser origin path length, mm */
    unsigned long stale;              /* frames dropped as older than the laser switch (sequence) */
    unsigned long refused;            /* probes refused for their frames (vp_machine_last.fault) */
    unsigned long confirmed;          /* spots checked in a second laser-on frame (confirm) */
    unsigned long moved, off_lit;     /* refused: not again where they were; light in the laser-off frame */
    unsigned long line_points;        /* a line laser: points read (every column), and of them */
    unsigned long line_rays;          /* reported as rays (within the calibrated span) */
    unsigned long line_gaps;          /* probes whose axis fell in a gap of the line: unreadable */
    unsigned long turns;              /* MOVEs the head first turned for (its orientation put the
                                         carriage outside its travel at the MOVE's end) */
    unsigned long moves_turning;      /* MOVEs that turned the head towards their PROBE on the way
                                         (turn_on_move) */
    unsigned long paths, path_moves;  /* paths of two MOVEs or more (vp_machine_move_path), and
                                         their MOVEs */
    int64_t move_ns, aim_ns, settle_ns, read_ns; /* machine time by motion (the io clock): MOVEs;
                                         a PROBE's aim, its settle, its frames and their reading */
} vp_machine_stats_t;

/* Why a probe's frames were refused (VP_EIO, nothing read from them). */
enum { VP_FRAME_OK = 0,
       VP_FRAME_BACKWARDS = 1,        /* a frame numbered or stamped older than one already seen */
       VP_FRAME_UNPROVEN = 2,         /* the camera gives no sequence number / mark: a frame cannot be
                                         shown to be from after the laser switch */
       VP_FRAME_NO_BUFFER = 3,        /* no room for the laser-off frame (diff_buf) */
       VP_FRAME_SIZE = 4 };           /* the laser-on frame is not the size of the laser-off one */

typedef struct vp_machine_last {
    double origin[3], dir[3];         /* the beam of the last probe */
    double point[3];                  /* its hit point (if hit) */
    vp_spot_t spot;
    int64_t t_ns;                     /* frame time stamp (of the laser-on frame) */
    int64_t seq, seq_off;             /* sequence numbers of the laser-on and laser-off frames */
    int64_t seq_confirm;              /* and of the confirming laser-on frame (-1: none) */
    int64_t seq_mark;                 /* the camera's next sequence number right after the laser went on */
    int fault;                        /* VP_FRAME_* of the last probe */
    int contact;                      /* the last MOVE stopped on the contact switch */
    double contact_at;                /* its trigger: distance along the MOVE from cmd->from */
    double overtravel;                /* how far past the trigger the laser origin stopped (mm) */
    double contact_point[3];          /* the laser origin at the trigger (latched joints) */
    int rf_why;                       /* full model: VP_RF_* of the last spot (-1: no spot read) */
    double rf_dist, rf_gap_px;        /* its distance along the beam (also out of span) and miss of the beam */
} vp_machine_last_t;

typedef struct vp_machine_config {
    uint32_t settle_ns;               /* wait after the aim before the exposure */
    int timeout_ms;                   /* camera (0: 1000) */
    int use_laser_line;               /* 1: switch VP_IO_LASER on for each exposure; then each probe
                                         takes a laser-off and a laser-on frame and finds the spot in
                                         their difference (on - off, clamped at 0): light present in
                                         both (a highlight near the laser line) cancels */
    int latency_frames;               /* frames after the camera's mark that may still show the laser
                                         as it was before the switch: only a frame numbered at least
                                         mark + latency_frames is used (board [camera] latency_frames;
                                         measure it with vp_machine_measure_latency) */
    uint8_t *diff_buf;                /* the caller's room for the laser-off frame: width x height */
    size_t diff_len;
    int single_frame;                 /* tests only: no laser-off frame, no differencing */
    int contact;                      /* 1: the head has a contact switch (VP_IO_CONTACT); MOVEs
                                         watch it */
    double contact_stop;              /* mm the laser origin may travel past a touch (the stylus's
                                         overtravel): with contact, > 0 lets MOVEs turn on the way
                                         and run as paths, watched, their waypoints passed where
                                         the stop stays within it (vp_step_move_touch); 0: each
                                         MOVE alone and straight, its stop taken from rest */
    int turn_on_move;                 /* 1: a MOVE that names the PROBE it leads to (cmd dir, and
                                         in range the way left after it) turns the head towards
                                         that probe's direction on the way, its share of the turn
                                         by length, the laser origin kept on the line (within the
                                         kinematics' origin_tol): only for a head within its
                                         clearance ball in every pose (the ball rule) */
    int backdrop;                     /* 1: walls round the machine end every beam that meets
                                         nothing, within the range: a frame with no spot is
                                         unreadable (VP_READING_NO_SPOT), never free space */
    int confirm;                      /* 1: the spot must be the laser's: a second laser-on frame right
                                         after the first shows it where the first did (within
                                         confirm_px, or 0.4 of the spot's radius), and the laser-off frame is plain there (no light
                                         standing out): light that moves (a glint, the head still
                                         ringing) is not read as the spot (VP_SPOT_MOVED, _NOT_LASER);
                                         needs diff_len >= 2 frames */
    double confirm_px;                /* px (0: 1.0) */
    vp_spot_config_t spot;
    int use_rf;                       /* 1: distances from the full model rf (vp_calib), not tri */
    vp_rf_model_t rf;
    int line;                         /* 1: a line laser (needs use_laser_line and diff_len >= 2
                                         frames): each probe reads the line in a laser-off /
                                         laser-on pair (vp_line_detect) and the fan's point on its
                                         axis (the beam) answers the PROBE; every other point of the
                                         line is a ray of the frame (vp_machine_ray) */
    vp_line_model_t line_model;       /* camera and laser plane, tilt frame; axis = the beam */
    vp_line_config_t line_cfg;        /* detection (column_step: columns / VP_MACHINE_MAX_LINE at most) */
    double line_ray_half;             /* rays only from the points within this angle of the axis, rad
                                         (0: the whole fan): the fan's ends meet the object farther
                                         and more obliquely, where its points are less sure */
    double line_gap_cols;             /* with the line on one side of the axis only, the columns this
                                         many steps round where the beam's hit could show must be
                                         plainly empty, and the line must end farther (0: 3) */
} vp_machine_config_t;

/* One MOVE of a path: joints straight from j0 through its pieces (vp_machine_move_path). */
typedef struct vp_machine_path_move {
    double j0[VP_KIN_JOINTS];         /* the joints at its start, as stepped */
    double j1[VP_KIN_JOINTS];         /* at its end, as stepped */
    int first, n;                     /* its pieces: path_way[first .. first + n) */
    int turn_n;                       /* of them the first turn_n: a turn about the laser origin made
                                         before it (vp_machine_turn_for), a motion of its own */
    int turning;                      /* it turned the head towards its PROBE (turn_on_move) */
} vp_machine_path_move_t;

typedef struct vp_machine {
    vp_kin_t kin;
    vp_step_t step;
    vp_io_t io;
    vp_cam_t cam;
    vp_tri_model_t tri;
    vp_machine_config_t cfg;
    double j[VP_KIN_JOINTS];          /* joints as stepped (units) */
    double way[VP_MACHINE_MAX_WAY][VP_KIN_JOINTS];
    int turn_n;                       /* the last turn before a MOVE: its path, way[0 .. turn_n) */
    int move_n;                       /* the last MOVE turned on its way: its path, way[0 .. move_n)
                                         (0: one straight line of the joints) */
    double path_way[VP_MACHINE_PATH_WAY][VP_KIN_JOINTS];
    vp_machine_path_move_t path[VP_MACHINE_PATH_MOVES]; /* the last path's MOVEs made */
    vp_machine_stats_t st;
    vp_machine_last_t last;
    vp_spot_ws_t ws;
    int64_t seen_seq, seen_ts;        /* the newest frame taken (-1 / none: seen = 0) */
    int seen;
    int touched;                      /* a MOVE stopped on the contact: the next one backs off */
    double touch_point[3], touch_dir[3];  /* the trigger point and that MOVE's unit direction
                                             (0 for a contact at rest on a null MOVE) */
    double back_way[VP_MACHINE_BACK][VP_KIN_JOINTS]; /* a watched path's touch: the way back, its
                                             pieces retraced through the latched joints to
                                             where the touched MOVE started */
    int back_n, back_latch;           /* (0: straight back to touch_point); the latch's index */
    double touch_from[3];             /* the touched MOVE's start (cmd->from) */
    unsigned long contacts;           /* MOVEs stopped on the contact */
    int host_touched;                 /* the last vp_machine_goto stopped on the contact */
    double host_touch_at;             /* its trigger: the laser origin's distance along it */
    double host_overtravel;           /* how far the origin went on past the trigger */
    double host_rest[VP_KIN_JOINTS];  /* the joints where it came to rest, before backing off */
    /* a line laser: the last probe's frame (world points, from the PROBE's origin) */
    vp_line_ws_t lws;
    vp_line_point_t lpts[VP_MACHINE_MAX_LINE];
    int nline;                        /* points of the last frame */
    int nrays;                        /* of them rays (within the span) */
    double ray_dir[VP_MACHINE_MAX_LINE][3], ray_dist[VP_MACHINE_MAX_LINE];
    int16_t colmap[VP_LINE_MAX_W];    /* column index -> its point in lpts (-1: none) */
} vp_machine_t;

/* Checks and wires the parts (VP_EINVAL for a bad kinematics or stepper configuration). */
int vp_machine_init(vp_machine_t *m, const vp_kin_config_t *kc, const vp_step_config_t *sc, const vp_io_t *io,
                    const vp_cam_t *cam, const vp_tri_model_t *tri, const vp_machine_config_t *mc);
/* Homing cycle (vp_step_home), then the joints are known. */
int vp_machine_home(vp_machine_t *m);
/* Laser origin to p with pan/tilt unchanged (e.g. to the planner's start after homing, a
 * resume's way back); a pending back-off from a touch is dropped. A head with a contact switch
 * watches it: a touch stops the move (host_touched = 1, host_touch_at: the trigger's distance
 * from where the move began), the head backs off to there (the switch must open on the way, else
 * VP_STEP_FAULT_CONTACT) and the move returns VP_EABORT: something stands where only free space
 * was assumed, and the session stays resumable once it is cleared. */
int vp_machine_goto(vp_machine_t *m, const double p[3]);
/* The two halves of exec, for loops that keep them apart. */
int vp_machine_move(vp_machine_t *m, const vp_cmd_t *cmd);
/* Consecutive MOVEs (n of them, 1..VP_MACHINE_PATH_MOVES) as one path of the step generator:
 * each takes the pieces vp_machine_move would (the same joints, each MOVE starting where the one
 * before ends as stepped), and the waypoints between MOVEs are passed without stopping where
 * every axis moving on either side has a jerk (vp_step_move_path's junctions and look-ahead),
 * so the head stops only at the path's end. *done: the MOVEs made whole, from the first, and
 * path[0 .. *done) where each went. Fewer than n with VP_OK when the next one needs the head
 * turned first (vp_machine_turn_for: such a MOVE is made alone, first in a path) or its pieces
 * would not fit path_way: give the rest again. An error as vp_machine_move's, *done the MOVEs
 * reached before it. A head with a contact switch watches it along the path (cfg.contact_stop >
 * 0, else VP_EINVAL): a touch stops the path, the MOVE it fell in is the last made (*done
 * counts it) and vp_machine_contact() says where along it. */
int vp_machine_move_path(vp_machine_t *m, const vp_cmd_t *cmds, int n, int *done);
/* 1 when the machine may run a route as one path and turn the head on the way: a head without a
 * contact switch, or one whose stop past a touch is bounded (cfg.contact_stop > 0) */
int vp_machine_paths_allowed(const vp_machine_t *m);
/* 1 and *at (the trigger's distance along that MOVE, planner units) when the last MOVE stopped
 * on the contact switch; 0 otherwise (at may be NULL). */
int vp_machine_contact(const vp_machine_t *m, double *at);
int vp_machine_probe(vp_machine_t *m, const vp_cmd_t *cmd, vp_probe_result_t *res);
/* A line laser: ray i of the last PROBE's frame, as the planner takes it (vp_planner_feed_ray):
 * the unit direction from the PROBE's origin (cmd->from) to the point and its distance. 1, or 0
 * past the last (and without a line laser). */
int vp_machine_ray(const vp_machine_t *m, unsigned i, double dir[3], double *dist);
/* One planner command. VP_OK (a probe's miss is a result, not an error); VP_ERANGE (outside
 * travel: refused, nothing moved); VP_EABORT (e-stop, hard limit: stopped, fault set, homing
 * needed); VP_ETIMEOUT / VP_EIO (camera); VP_ESTATE (fault pending, not homed). */
int vp_machine_exec(vp_machine_t *m, const vp_cmd_t *cmd, vp_probe_result_t *res);
/* The planner's result of a probe, from the rangefinder's reading that vp_machine_probe just
 * made (m->last.spot; res as vp_machine_probe filled it; was_near: vp_machine_probe counted the
 * spot as nearer than min_range, i.e. m->st.near grew). Only "no spot", or a spot beyond the
 * range asked, is a miss: free space. A spot nearer than min_range is VP_PROBE_TOO_CLOSE, or with
 * near_measure a hit at the model's extrapolated distance. A frame that cannot be read (a blob
 * too big for a spot, as a surface at the lens gives; several spots; a spot off the laser line)
 * or a spot below the model's valid span proves nothing free: VP_PROBE_TOO_CLOSE too. res->dist
 * is 0 for VP_PROBE_TOO_CLOSE. With the full model (cfg.use_rf) a spot beyond the calibrated span,
 * or below it (unless near_measure), is VP_PROBE_TOO_CLOSE too, never a miss, and a spot whose
 * camera ray misses the beam is off the line. With cfg.backdrop a frame with no spot at all is
 * VP_PROBE_TOO_CLOSE (VP_READING_NO_SPOT): the beam would have lit a wall. *raw (may be NULL): the spot's position along the
 * image line, px (full model: its distance along the beam, mm)
 * (NaN: no spot). Returns what the reading was (VP_READING_*). */
typedef enum vp_reading {
    VP_READING_PLAIN = 0,          /* a hit or a miss as measured */
    VP_READING_NEAR = 1,           /* nearer than min_range (too close, or a hit with near_measure) */
    VP_READING_OFF_LINE = 2,       /* unreadable: a spot off the laser line */
    VP_READING_TOO_BIG = 3,        /* unreadable: a blob too big for a spot */
    VP_READING_SEVERAL = 4,        /* unreadable: several spots */
    VP_READING_BELOW_MODEL = 5,    /* unreadable: a spot below the model's valid span, or another failure */
    VP_READING_NOT_LASER = 6,      /* unreadable: too wide for the laser's spot, or it moved between two
                                      laser-on frames (VP_SPOT_NOT_LASER, VP_SPOT_MOVED) */
    VP_READING_NO_SPOT = 7         /* unreadable: no spot at all where the backdrop (cfg.backdrop) would
                                      show one: hidden from the camera, or on a surface too dark */
} vp_reading_t;
vp_reading_t vp_machine_reading(const vp_machine_t *m, const vp_cmd_t *cmd, int was_near, int near_measure,
                                vp_probe_result_t *res, double *raw);

/* Calibration against a flat target across machine +x at x = target_x: the head looks along +x
 * and steps towards the target through `stations` distances from d_far to d_near, evenly in 1/d
 * so the spot moves evenly across the image (distances known from the kinematics), `frames`
 * exposures each; the spots and distances are fitted (vp_tri_fit).
 * VP_EDEGEN with fewer than 4 spots; the model goes to *out (ranges: the calibrated span). */
typedef struct vp_calib_plan {
    double target_x, y, z;            /* the plane, and where the beam crosses it */
    double d_near, d_far;
    int stations, frames;             /* >= 4; 0: 3 frames */
} vp_calib_plan_t;
int vp_machine_calibrate(vp_machine_t *m, const vp_calib_plan_t *p, vp_tri_model_t *out, vp_tri_fit_report_t *rep);

/* The observations of the full calibration (vp_calib), the head looking along +x at the flat
 * target x = target_x that carries a mark (a bright dot) at `mark` (machine coordinates):
 *  - mark stations: for each of `depths` depths (evenly in 1/depth from mark_near to mark_far) and
 *    each point of a cols x rows grid over the image (margin_px from its edges), the gantry moves
 *    the head so that the nominal camera would see the mark there (stations out of travel, with the
 *    laser origin within 2 mm of the target, or with the nominal laser spot within 30 px of the mark
 *    are left out);
 *  - beam stations: `stations` distances from d_far to d_near along the beam through (y, z), as
 *    vp_machine_calibrate.
 * At each: a laser-off frame (the mark: VP_OBS_MARK with its tilt-frame position) and the on - off
 * difference (the laser spot: VP_OBS_SPOT with the target plane in the tilt frame), both with the
 * head pose the joints give. Beam stations also give (uv, distance along the nominal beam) for
 * the 1-D model (beam_uv, beam_d: room for `stations`). A line laser gives no spot observation
 * (its plane: vp_machine_calibrate_line). Needs the laser line (the mark is seen with
 * the laser off). VP_ENOMEM when obs (cap entries) is full. */
typedef struct vp_calib_full_plan {
    double target_x, y, z;
    double mark[3];
    double d_near, d_far;
    int stations;
    int depths, cols, rows;
    double mark_near, mark_far, margin_px;
    const vp_rf_model_t *nominal;     /* places the mark in the image */
} vp_calib_full_plan_t;
int vp_machine_calibrate_full(vp_machine_t *m, const vp_calib_full_plan_t *p, vp_calib_obs_t *obs, int cap, int *n,
                              double (*beam_uv)[2], double *beam_d, int *nbeam);
/* A line laser's plane (vp_line_fit_plane): at the head as it stands, facing the flat target
 * x = target_x, a laser-off / laser-on pair and the line in it (vp_line_detect, image points
 * only); each column found becomes a VP_OBS_SPOT (its centre and the target plane in the tilt
 * frame at the pose the joints give), appended at obs[*n] (*n grows). VP_ENOMEM when they do not
 * fit in cap (nothing appended); VP_ESTATE without a line laser. */
int vp_machine_line_obs(vp_machine_t *m, double target_x, vp_calib_obs_t *obs, int cap, int *n);
/* The line at each of p's beam stations (the distances vp_machine_calibrate_full steps through,
 * the head along +x through (y, z)): *n observations from *poses stations that showed the line. */
int vp_machine_calibrate_line(vp_machine_t *m, const vp_calib_full_plan_t *p, vp_calib_obs_t *obs, int cap, int *n,
                              int *poses);
/* At the head as it stands: the spot in the on - off difference and (mark, may be NULL) the
 * brightest spot of the laser-off frame; both from vp_spot_find without a model. */
int vp_machine_observe(vp_machine_t *m, vp_spot_t *mark, vp_spot_t *spot);

/* The camera's pipeline latency in frames, from the head as it stands (aimed at a matte surface
 * within range): `trials` times the laser is switched on, then off, and the frames from the mark
 * after the switch are counted until the spot appears (disappears), each frame against a laser-off
 * reference; *latency is the largest count. Needs a laser line, diff_buf and a camera with
 * sequence numbers and mark (VP_ESTATE otherwise); VP_ETIMEOUT when the spot never changes within
 * max_frames. On a real camera set latency_frames one above it (an exposure straddling the
 * switch shows a partial spot). */
int vp_machine_measure_latency(vp_machine_t *m, int trials, int max_frames, int *latency);

/* Laser origin and beam direction now. */
void vp_machine_beam(const vp_machine_t *m, double origin[3], double dir[3]);
/* Drivers off, camera closed (the backends' owners release the rest). */
void vp_machine_close(vp_machine_t *m);

#endif
