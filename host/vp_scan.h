/* vp_scan — the machine side of `scan` and `calibrate`: a board's machine opened on its hardware
 * (libgpiod + V4L2/libcamera) or as a dry run (host-sim at the hardware boundary), homed, and
 * executing planner commands through vp_machine_exec with the results mapped for the planner
 * (a spot nearer than min_range: VP_PROBE_TOO_CLOSE; no spot: a miss). A resumed session is
 * brought back to where its log left the machine: home, the logged free route, the same joints.
 *
 * Dry runs are deterministic: probe k's frame noise is drawn from (seed, k) alone, axes without
 * a switch take up their backlash the same way after every homing, and the joints a log left
 * are recomputed step for step, so a resumed dry run sees exactly what the uncut one saw. */
#ifndef VP_SCAN_H
#define VP_SCAN_H
#include <signal.h>
#include <stddef.h>
#include "vp_board.h"
#include "vp_dryrun.h"
#include "vp_gpiod.h"
#include "vp_machine.h"
#include "vp_session.h"
#include "vp_sessionlog.h"
#include "vp_surface.h"

typedef struct vp_scan_dev {
    vp_board_t board;
    int dry;                      /* 1: host-sim stands in for the hardware */
    vp_dryrun_t *dr;              /* dry run */
    vp_gpiod_t *gpio;             /* hardware */
    vp_machine_t hw;              /* the machine on the hardware backends */
    int hw_open;
    uint8_t *hw_frame;            /* the machine's laser-off / difference frames (diff_buf) */
    vp_machine_t *m;              /* the machine in use */
    unsigned long long seed;      /* dry run: frames of probe k from (seed, k) */
    uint64_t probes;              /* probes executed (replayed ones included after a resume) */
    unsigned long commands;       /* commands executed by this run */
    unsigned long too_close, hits, misses, through; /* results as fed; dry run: moves through the object */
    unsigned long unreadable;     /* of too_close: a blob, several spots, a spot off the line or below the model */
    unsigned long unread_why[6];  /* off the line, too big, several spots, below the model, not the laser,
                                     no spot where the backdrop would show one */
    unsigned long near;           /* spots nearer than min_range (too close, or hits with near_measure) */
    int near_measure;             /* 1: a spot nearer than min_range is a hit at the extrapolated distance */
    double raw;                   /* last probe's raw reading: spot position along the line, px (NaN: none) */
    unsigned long estop_at;       /* dry run: press the e-stop during this run's command N (0: never) */
    int fault;                    /* the status that stopped a command (VP_OK: none) */
    unsigned long contacts;       /* moves the head's contact switch stopped */
    const vp_planner_t *pl;       /* the planner issuing the commands (for the time by stage), or NULL */
    double stage_s[4];            /* machine time of this run's commands by vp_planner_stage */
    unsigned long stage_cmds[4];
    double noise_tol;             /* dry run: hits are judged against the object within this (mm) */
    int touching;                 /* the last one did: the head stands on the surface */
    int backing;                  /* dry run: this MOVE backs off that touch */
    double touch_lag;             /* dry run: how far past the surface the switch closed (mm) */
    double touch_depth_max;       /* dry run: deepest a stopped move went past the surface (mm) */
    double touch_cut;             /* dry run, a move the switch stopped: how far along it the head's
                                     body is swept (to 2 head_tol before the laser origin meets the
                                     surface; the rest is the stylus's, within contact_stop) */
    int reach_out;                /* dry run (scan --reach-out): the object may reach out of Omega;
                                     the clearance ball in it is the assumption broken on purpose,
                                     counted by part but not as a head collision */
    vp_cmd_t fault_cmd;
    /* dry run: probes against the true object */
    unsigned long true_n, false_hits, false_misses;
    int last_false_miss;          /* the last probe was such a miss (a hidden spot) */
    unsigned long false_misses_unseen; /* of them fed as unreadable (vp_device_ops_t.sight) */
    unsigned long past;           /* hits farther than the surface by more than noise_tol (space
                                     inside the object read as free) */
    unsigned long grazing;        /* hits whose ray meets no surface but whose point lies within
                                     noise_tol of it (a beam grazing a limb), or read past a thin
                                     edge the ray clips, nowhere deeper inside than noise_tol */
    double err2, err_max;
    unsigned long rays, ray_false;       /* a line laser: rays fed, and (dry run) hits off the surface by more than noise_tol */
    double ray_err2, ray_err_max;        /* (dry run) their errors against the surface */
    /* dry run: the head's body (board [head]) swept along every motion against the object */
    unsigned long head_motions;   /* motions checked: MOVEs, aims, the legs of a resume's way back */
    unsigned long head_hits;      /* of those, motions that brought a part within head_tol */
    unsigned long head_part[VP_HEAD_MAX_PARTS];  /* such motions per part (board.head.part[i]) */
    unsigned long head_evals;     /* distance queries the check made */
    double head_tol;              /* a part nearer the surface than this is a head collision: 0.5 mm,
                                     or the board's head_margin (origin_tol, steps, backlash) if larger */
} vp_scan_dev_t;

/* Dry runs: 1 if some point of the ray o + s dir (dir a unit vector), s in [t0, t1], lies
 * deeper than tol inside the object; 0 if none lies deeper than 7/8 tol (between the two,
 * either). Depth, the distance to the surface inside, changes by at most the step between
 * samples, so samples tol / 4 apart catch any point deeper than tol. A hit read more than tol
 * past the surface whose free part is nowhere deeper is a beam that passed beside a thin edge
 * the ray clips (counted as grazing), not space inside the object taken for free. */
int vp_scan_depth_beyond(const vp_surface_t *surf, const double o[3], const double dir[3], double t0, double t1,
                         double tol);

/* Dry runs: a hit read dist along the commanded ray o + s dir (probed to range) against the
 * object, the planner trusting hits to tol. TRUE: within tol of the ray's first crossing (err
 * its distance from it); PAST: farther than tol past it and deeper inside than tol somewhere
 * on its free part (space inside the object taken for free: err how far past); GRAZING: a
 * beam beside the ray, past a thin edge it clips or short of the crossing or with no crossing,
 * its point within tol of the surface; FALSE: a point off the surface. */
typedef enum { VP_HIT_TRUE, VP_HIT_PAST, VP_HIT_GRAZING, VP_HIT_FALSE } vp_hit_judged_t;
vp_hit_judged_t vp_scan_judge_hit(const vp_surface_t *surf, const double o[3], const double dir[3], double range,
                                  double dist, double tol, double *err);

/* Dry runs: the smallest head_tol (mm). */
#define VP_SCAN_HEAD_TOL 0.5

/* Ctrl-C: set by the SIGINT/SIGTERM handler (vp_scan_catch_signals); the loop stops after the
 * current command. A second signal ends the process at once. */
extern volatile sig_atomic_t vp_scan_stop;
void vp_scan_catch_signals(void);

/* Dry runs: the object for a spec. NULL (or "") gives the board's [sim] surface, else an
 * ellipsoid sized to Omega; a bare NAME or off:/ply: FILE (no '*' or '@') is scaled and placed
 * to fit Omega around the board's interior point; anything else is taken as written (mm). */
int  vp_scan_dry_surface(const vp_board_t *b, const char *spec, char *out, size_t outlen, char *err, size_t errlen);

/* Opens the machine. Hardware: the GPIO lines and the camera the board names (VP_ENODEV with
 * every missing device named in err). Dry run: host-sim with the object `surface` (a resolved
 * spec) or a flat target x = target_x (surface NULL). */
int  vp_scan_open(vp_scan_dev_t *d, const vp_board_t *b, int dry, const char *surface, double target_x,
                  unsigned long long seed, char *err, size_t errlen);
/* Homing, then axes without a switch take up their backlash in a fixed direction. */
int  vp_scan_home(vp_scan_dev_t *d, char *err, size_t errlen);
/* The laser origin to p, pan/tilt unchanged. */
int  vp_scan_goto(vp_scan_dev_t *d, const double p[3], char *err, size_t errlen);
/* The device operations for vp_session_run (ctx = d). */
vp_device_ops_t vp_scan_ops(vp_scan_dev_t *d);
/* After a resume's replay (first n records of L), from the planner's start (the machine homed
 * and at cfg.start): back along the logged moves (shortest route through them: every segment
 * was proven free), then the joints the log left, step for step. msg: notes (may be NULL). */
int  vp_scan_return(vp_scan_dev_t *d, const vp_sessionlog_t *L, uint32_t n, const double start[3], FILE *msg,
                    char *err, size_t errlen);
/* The step timing report (EVENT VP_LOGFMT_EV_STEPPING, logged before the session's last event)
 * and the summary: text, and value[] = retimes, late faults,
 * worst lateness (us), steps held back by the re-entry limiter. */
void vp_scan_step_report(const vp_scan_dev_t *d, char *buf, size_t n, double value[4]);
/* Why the last command failed, in words (e-stop, limit switch, camera, travel). */
void vp_scan_fault_text(const vp_scan_dev_t *d, char *buf, size_t n);
/* The unreadable frames by reason, in words. */
void vp_scan_unreadable_text(const vp_scan_dev_t *d, char *buf, size_t n);
/* The head collisions by part, in words ("clearance ball 0, laser 0, camera 2, ..."). */
void vp_scan_head_text(const vp_scan_dev_t *d, char *buf, size_t n);
/* Machine time: simulated in a dry run, else the monotonic clock (s). */
double vp_scan_seconds(const vp_scan_dev_t *d);
void vp_scan_close(vp_scan_dev_t *d);

#endif
