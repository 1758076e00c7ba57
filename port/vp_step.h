/* vp_step — step generation for up to VP_IO_MAX_AXES stepper axes (grbl's stepper idea, no
 * timers: a stream of timed edges through a vp_io backend).
 *
 * A move is one block: the joints travel on a straight line in step space. The axis with the
 * most steps (dominant) follows a trapezoidal velocity profile from rest to rest; the others
 * step by Bresenham on the dominant ticks, so every axis starts and ends together and each stays
 * within half a step of the line. The profile's speed and acceleration are the largest that
 * keep every axis within its own max speed and acceleration (the most constrained axis rules).
 * Step times come from the exact profile (no accumulated drift), as absolute ns deadlines.
 *
 * Timing guarantees (whatever the OS does): each pulse ends pulse_ns after its actual rising
 * edge (the time read after the write); inputs are read after the falling edge, never between
 * a deadline and its rising edge; no rising edge follows the one before sooner than the block's
 * rate cap (<= max_step_rate) or sooner than the acceleration allows from the interval the motor
 * really had (a limiter on the wake-up times). A late wake-up thus only ever stretches one
 * interval and shifts the rest of the move (never a catch-up burst). Lateness up to max_late_ns
 * is phase jitter: the next interval is the planned one. A step later than that is a retime:
 * the motor is taken to have slowed to that interval and re-accelerates into the profile at the
 * block's acceleration (counted; VP_STEP_EV_RETIME after the block), or with late_fault a fault
 * before the pulse (homing needed). Every step's lateness goes into a log2 histogram.
 * Inputs are debounced: a level change is taken after `debounce` consecutive equal samples
 * (the homing latch is the position at the first of them).
 *
 * Also: steps per unit, direction inversion, enable lines, backlash take-up before a reversing
 * move (extra steps not counted in the position), soft travel limits (a move leaving travel is
 * refused before any step), homing against limit switches (seek, pull off, slow locate, pull
 * off; the switch position is latched), and an e-stop input polled after every step pulse and
 * at least every poll_ns: no pulse after it is seen, drivers disabled, a fault reported through
 * the event callback. A fault blocks moves until vp_step_clear_fault() and a new homing; the
 * caller's session is untouched.
 *
 * A contact input (a touch probe on the head, VP_IO_CONTACT) is watched only by the moves that
 * ask for it (vp_step_move_watch): it is read after every step pulse like the e-stop and
 * debounced the same way; when it closes the positions of all axes at the first confirming
 * sample are latched (as the homing latch) and the move decelerates to rest at the block's
 * acceleration (or, with contact_halt, issues no further pulse), and the rest of the path is
 * dropped. The stop is a result, not a fault: no homing is needed.
 *
 * The block iterator (vp_step_block_*) is pure arithmetic, usable from a timer interrupt. */
#ifndef VP_STEP_H
#define VP_STEP_H
#include <stdint.h>
#include "vp_io.h"

#define VP_STEP_MAX_AXES VP_IO_MAX_AXES

typedef struct vp_step_axis {
    double steps_per_unit;   /* steps per mm (or per degree) */
    double max_speed;        /* units/s */
    double accel;            /* units/s^2 */
    double travel_min, travel_max;  /* soft limits, machine coordinates */
    double backlash;         /* units taken up before a reversal */
    int invert_dir;          /* 1: DIR line low for positive motion */
    int home_dir;            /* -1: switch at the min end, +1: at the max end, 0: no homing */
    double home_pos;         /* coordinate where the switch closes (home_dir != 0), or the
                                position taken as known at homing (home_dir == 0) */
    double home_seek;        /* units/s (0: max_speed / 4) */
    double home_feed;        /* units/s (0: home_seek / 10) */
    double home_pulloff;     /* units (0: 1 unit) */
    int home_order;          /* homing goes by increasing order, then by axis index */
    double jerk;             /* units/s: the speed change the axis takes at once where a path
                                bends at a waypoint (Marlin's classic jerk); 0: a path's
                                waypoints are passed at rest */
} vp_step_axis_t;

enum { VP_STEP_EV_ESTOP = 1, VP_STEP_EV_LIMIT, VP_STEP_EV_HOME_FAIL, VP_STEP_EV_HOMED,
       VP_STEP_EV_CLEARED, VP_STEP_EV_RETIME, VP_STEP_EV_LATE, VP_STEP_EV_CONTACT };

typedef struct vp_step_event {
    int kind;                /* VP_STEP_EV_* */
    int axis;                /* -1 if none */
    int64_t t_ns;
    const char *what;        /* short constant text */
    int64_t late_ns;         /* VP_STEP_EV_RETIME, VP_STEP_EV_LATE: worst lateness */
    uint64_t count;          /* VP_STEP_EV_RETIME: retimes in the block just run */
} vp_step_event_t;

typedef struct vp_step_config {
    int naxes;               /* 1..VP_STEP_MAX_AXES */
    vp_step_axis_t axis[VP_STEP_MAX_AXES];
    uint32_t pulse_ns;       /* step pulse width (0: 2000) */
    uint32_t dir_setup_ns;   /* DIR settles this long before a step (0: 1000) */
    uint32_t enable_ns;      /* drivers wake this long after enable (0: 1 ms) */
    uint32_t lead_ns;        /* first deadline of a block this far ahead (0: 200 us) */
    uint32_t poll_ns;        /* inputs read at least this often while waiting (0: 1 ms) */
    uint32_t max_late_ns;    /* a step later than this is a retime, or a fault with late_fault
                                (0: 100 us); less is phase jitter; never a burst either way */
    uint32_t debounce;       /* samples an input level must hold to be taken (0: 1) */
    int late_fault;          /* 1: a retime faults instead (VP_STEP_FAULT_LATE, homing needed) */
    double max_step_rate;    /* backend limit in steps/s per axis (0: 1e9 / (2 pulse_ns)) */
    int allow_unhomed;       /* 1: moves allowed before homing */
    int no_hard_limits;      /* 1: a switch closing during a move is not a fault */
    int contact_halt;        /* 1: a contact stop issues no pulse after the confirming sample
                                (the stylus cannot take the deceleration); 0: decelerate */
    void (*event)(void *ctx, const vp_step_event_t *ev);   /* faults, homing and retimes (once
                                                              after a block), may be NULL */
    void *event_ctx;
} vp_step_config_t;

enum { VP_STEP_FAULT_NONE = 0, VP_STEP_FAULT_ESTOP, VP_STEP_FAULT_LIMIT, VP_STEP_FAULT_HOME,
       VP_STEP_FAULT_IO, VP_STEP_FAULT_LATE,
       VP_STEP_FAULT_CONTACT };  /* the contact stayed closed after a move that backed off it */

/* One block: Bresenham over `delta` with a trapezoid on the dominant axis, from rest to rest or
 * between the entry and exit rates a path's junctions allow (vp_step_block_ends). */
typedef struct vp_step_block {
    int naxes;
    int32_t delta[VP_STEP_MAX_AXES];
    uint32_t n, k, end;      /* dominant steps: total, done, last one (a stop moves it) */
    double v, a;             /* dominant step rate cap and acceleration */
    double sa, ta, vp, T;    /* accel steps and time, peak rate, total time */
    int ends;                /* entry or exit rate not 0 */
    double vi, vo, sd, td;   /* entry and exit rates, decel steps and time */
    int stopping;
    double s0, t0, v0;       /* decelerating stop from step s0 at t0 with rate v0 */
    uint64_t acc[VP_STEP_MAX_AXES];
} vp_step_block_t;

/* rate[i], acc[i]: axis i limits in steps/s and steps/s^2 (> 0 for every moving axis);
 * rate_cap caps every axis's step rate (0: none). VP_EINVAL for a bad limit. */
int  vp_step_block_init(vp_step_block_t *b, int naxes, const int32_t *delta, const double *rate,
                        const double *acc, double rate_cap);
/* Entry and exit dominant rates (steps/s, at most the block's cap; a change the block's
 * acceleration cannot make over its steps is cut to what it can): the trapezoid becomes
 * vi -> peak -> vo. VP_EINVAL for a negative or NaN rate. */
int  vp_step_block_ends(vp_step_block_t *b, double vi, double vo);
/* Next dominant tick: 1 with its time (s from the block start) and the axes that step (bit i,
 * direction from the sign of delta[i]); 0 when the block is done. */
int  vp_step_block_next(vp_step_block_t *b, double *t, uint32_t *mask);
/* Decelerate to rest from the last tick at the block's acceleration (the path is kept). */
void vp_step_block_stop(vp_step_block_t *b);
/* Dominant step rate at the last tick (steps/s, the profile's value). */
double vp_step_block_rate(const vp_step_block_t *b);

#define VP_STEP_LATE_BUCKETS 12               /* ... [10] < 1.024 ms, [11] >= 1.024 ms */

typedef struct vp_step_stats {
    uint64_t steps[VP_STEP_MAX_AXES];        /* pulses issued (backlash included) */
    uint64_t backlash_steps[VP_STEP_MAX_AXES];
    uint64_t moves, blocks, refused, polls;
    uint64_t retimed;                        /* steps later than max_late_ns (profile re-entered) */
    uint64_t late_faults;                    /* the same with late_fault: moves stopped */
    uint64_t limited;                        /* steps the re-entry limiter held back > 1 us */
    uint64_t contacts;                       /* moves stopped by the contact input */
    uint64_t late_hist[VP_STEP_LATE_BUCKETS];/* step lateness: [0] < 1 us, [i] < 2^i us, last: more */
    int64_t late_max_ns;
    double move_time;                        /* s of motion (profile time) */
} vp_step_stats_t;

typedef struct vp_step {
    vp_step_config_t cfg;
    vp_io_t io;
    int32_t pos[VP_STEP_MAX_AXES];           /* logical position in steps */
    int8_t last_dir[VP_STEP_MAX_AXES];       /* +1/-1 of the last motion, 0 unknown */
    int32_t backlash[VP_STEP_MAX_AXES];      /* steps */
    uint32_t out;                            /* current output levels */
    int enabled, homed, fault;
    int64_t fault_t;
    uint32_t deb;                            /* debounced input levels */
    uint8_t deb_n[VP_IO_NIN];                /* consecutive samples differing from deb */
    int32_t deb_at[VP_IO_NIN];               /* limit bits: axis position at the first of them */
    int32_t contact_at[VP_STEP_MAX_AXES];    /* the contact bit: every axis at the first of them */
    int path_done;                           /* waypoints the last path reached (a fault stops
                                                it short: the ones before it were reached) */
    vp_step_stats_t st;
} vp_step_t;

/* Checks the configuration (VP_EINVAL: bad counts, speeds, travel, home position outside travel
 * after the pull-off) and sets all outputs low (drivers disabled). */
int  vp_step_init(vp_step_t *s, const vp_step_config_t *cfg, const vp_io_t *io);
int  vp_step_enable(vp_step_t *s, int on);
/* Homing cycle. VP_OK; VP_EABORT (e-stop); VP_ETIMEOUT (a switch never closed within 1.5x the
 * travel); VP_EIO (a switch stays closed after pulling off). Failures set a fault. */
int  vp_step_home(vp_step_t *s);
/* Coordinated move to target (units, naxes values). VP_OK; VP_ERANGE (outside travel, nothing
 * moved); VP_ESTATE (fault pending or not homed); VP_EABORT (e-stop or hard limit during the
 * move: stopped at once, position = the steps issued, fault set); VP_EINVAL (NaN). */
int  vp_step_move(vp_step_t *s, const double *target);
#define VP_STEP_PLAN 32   /* blocks a path's look-ahead plans at once (re-planned halfway) */
/* n moves through waypoints (n * naxes values); all are checked against travel first. Where
 * every axis moving on either side of a waypoint has a jerk, the waypoint is passed without
 * stopping: the junction's rate keeps each axis's speed change within its jerk (none reverses
 * where it has backlash), and a look-ahead over VP_STEP_PLAN blocks keeps each block's
 * acceleration, so the path ends at rest (grbl's planner idea, Marlin's jerk rule). The joints
 * keep to the same straight pieces between waypoints either way. */
int  vp_step_move_path(vp_step_t *s, const double *way, int n);

/* How a move watches the contact input. STOP: a contact that closes (or is closed before the
 * first step) stops the move. RELEASE: the move backs off a contact; the contact may be closed
 * at the start and is taken as a stop only after it has been seen open; if it is still closed
 * when the path ends, the machine faults (VP_STEP_FAULT_CONTACT: a stuck switch or a broken
 * wire; VP_EABORT, drivers off, homing needed). */
enum { VP_STEP_WATCH_NONE = 0, VP_STEP_WATCH_STOP = 1, VP_STEP_WATCH_RELEASE = 2 };
typedef struct vp_step_contact {
    int hit;                                 /* the move stopped on the contact */
    int at_start;                            /* it was closed before the first step (no step made) */
    int way;                                 /* the waypoint being travelled to when it closed
                                                (vp_step_move_touch: at the latched position) */
    int rest_way;                            /* ... and when the head came to rest (vp_step_move_touch:
                                                the stop may carry on past waypoints) */
    int32_t latch[VP_STEP_MAX_AXES];         /* steps of every axis at the first confirming sample */
} vp_step_contact_t;
/* vp_step_move_path watching the contact (watch VP_STEP_WATCH_*); *c filled (may be NULL with
 * VP_STEP_WATCH_NONE). Returns as vp_step_move_path. */
int  vp_step_move_watch(vp_step_t *s, const double *way, int n, int watch, vp_step_contact_t *c);
/* vp_step_move_watch that also passes the waypoints of a path watched for a touch (STOP) without
 * stopping: len[w] bounds how far the touching point travels along piece w (any unit, e.g. mm of
 * the laser origin), stop_max how far it may go past the trigger. A piece whose own stop (its
 * top rate, 2 * debounce steps) goes farther refuses the path (VP_ERANGE, nothing moved:
 * vp_step_touch_fits); a junction is passed at a rate from which the stop carries the point no
 * farther than stop_max with the piece before's worst and ends within the next piece, where the
 * touched path's stop decelerates on (c->rest_way). len NULL: vp_step_move_watch. */
int  vp_step_move_touch(vp_step_t *s, const double *way, int n, int watch, const double *len, double stop_max,
                        vp_step_contact_t *c);
/* 1 when every piece of the path from `from` (units; NULL: the current position) keeps its own
 * touch's stop within stop_max (as vp_step_move_touch checks) */
int  vp_step_touch_fits(const vp_step_t *s, const double *from, const double *way, int n, const double *len,
                        double stop_max);
/* The most a coordinated move of the listed axes travels (units along its path) between the
 * first sample that sees a contact and rest: the deceleration from the fastest coordinated speed
 * plus `debounce` steps (the confirming samples, and the step the trigger falls within).
 * A move along direction w (|w| = 1) runs at v = min_i V_i / |w_i| and accelerates at
 * a = min_i A_i / |w_i| (V_i: max_speed capped by max_step_rate, A_i: accel), so it stops in
 * v^2 / (2 a); over all directions the largest is |V| max_i (V_i / A_i) / 2, reached with every
 * axis at its max speed (0 with contact_halt). One step along the path is at most
 * sqrt(sum_i 1 / steps_per_unit_i^2). *speed (may be NULL): |V|. */
double vp_step_contact_reach(const vp_step_config_t *c, const int *axes, int naxes, double *speed);
/* Position in units (logical, steps / steps_per_unit). */
void vp_step_position(const vp_step_t *s, double *units);
/* Declare the current position (boards without switches). Sets homed. */
int  vp_step_set_position(vp_step_t *s, const double *units);
/* Clears a fault once the e-stop is released (VP_EABORT while it is pressed); homing needed. */
int  vp_step_clear_fault(vp_step_t *s);
/* Bucket of a lateness in the histogram. */
int  vp_step_late_bucket(int64_t late_ns);
/* Unit value -> steps (rounded), as the stepper does. */
int32_t vp_step_to_steps(const vp_step_t *s, int axis, double units);

#endif
