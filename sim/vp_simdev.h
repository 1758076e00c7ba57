/* vp_simdev — the simulated scanning device: does what it is commanded, exactly as a machine
 * would, and checks safety on its own against the true object (vp_surface).
 *   move:  straight segment from the current position; checked with the device's clearance
 *          radius; collisions counted; travel accumulated; optional travel box (refused).
 *   probe: from the current position along a unit direction up to a range: first surface
 *          crossing, with optional Gaussian noise along the ray, dropouts and a minimum range,
 *          drawn from a PRNG seeded by (seed, probe number): the k-th probe's noise and dropout
 *          depend on nothing else, so a session resumed from its log sees the same results.
 *   clock: every move advances it by the move's time (a trapezoid: accel up to speed, cruise,
 *          decelerate), every probe by the probe time; with a motion (vp_motion.h) each probe
 *          sees the object at the clock's time after it, and each move is checked against the
 *          object as it moves during the move (the move cut in time until the object's motion
 *          over one piece, by its speed bound, is below motion_tol; conservative by that much).
 * Plain double arrays in, result structs out: no planner types. */
#ifndef VP_SIMDEV_H
#define VP_SIMDEV_H
#include <stdint.h>
#include "vp_motion.h"
#include "vp_surface.h"

typedef struct vp_simdev vp_simdev_t;

#define VP_SIMDEV_MAX_DARK 8

typedef struct vp_simdev_config {
    double   clearance;          /* device body radius for move checks (0 = a point) */
    int      has_limits;         /* travel box on: moves ending or passing outside are refused */
    double   limit_lo[3], limit_hi[3];
    int      stop_on_collision;  /* 1: a colliding move is refused (VP_EABORT) and the device stays */
    double   noise_sigma;        /* standard deviation of the hit distance (along the ray) */
    double   dropout;            /* probability that a real hit reports a miss */
    double   min_range;          /* a surface nearer than this is reported as too close (no distance) */
    double   max_range;          /* probe range cap (0: only the per-probe range) */
    uint64_t seed;               /* PRNG seed for noise and dropouts */
    /* Dark patches: parts of the surface the rangefinder cannot see (black, shiny). A probe
     * whose first crossing lies in one of these balls (centre x, y, z, radius) reads a miss. */
    int      ndark;
    double   dark[VP_SIMDEV_MAX_DARK][4];
    /* The head's contact switch: a move stops where the device first touches the object (the
     * point, or the clearance ball) and the device stands there (a machine's overtravel past
     * the trigger and its back-off are the port's business: port/vp_machine). */
    int      contact;
    const vp_motion_t *motion;   /* the object moving (its body must be s); NULL: s, static */
    double speed, accel;         /* travel speed (units/s; 0: moves take no time), acceleration (0: none) */
    double probe_time;           /* one probe's settle + exposure (s) */
    double motion_tol;           /* moving checks over-count by at most this (0: 1e-3 of the bbox diagonal) */
} vp_simdev_config_t;            /* all-zero = exact point device without limits */

typedef struct vp_simdev_stats {
    unsigned long moves, refused_moves, collisions;
    unsigned long probes, hits, misses, dropouts, too_close; /* hits ... too_close: of probes and rays */
    unsigned long rays;          /* a line laser's more rays (vp_simdev_ray) */
    unsigned long dark_misses;   /* probes that met S on a dark patch: read as misses */
    unsigned long contacts;      /* moves the contact switch stopped */
    double travel;               /* total length moved */
    double time;                 /* the clock (s) */
} vp_simdev_stats_t;

typedef struct vp_simdev_move {
    int    status;     /* VP_OK, VP_ERANGE (outside the travel box), VP_EABORT (collision refused), VP_EINVAL */
    int    collided;   /* the segment met the object or came within the clearance */
    int    touched;    /* the contact switch stopped the move */
    double at;         /* ... this far along it (where the device now stands) */
    double length;     /* length moved (0 if refused) */
} vp_simdev_move_t;

typedef struct vp_simdev_probe {
    int    status;     /* VP_OK or VP_EINVAL (direction not unit length, bad range) */
    int    hit;        /* 1: a surface point was reported */
    int    too_close;  /* 1: a surface nearer than min_range (no distance, not a miss) */
    double t;          /* reported distance along the ray (noise included) */
    double point[3];   /* reported point: origin + t * dir */
    double true_t;     /* noiseless first crossing, -1 if none in range (evaluation only) */
} vp_simdev_probe_t;

/* s must outlive the device. start: initial position (collisions there are not counted). */
int  vp_simdev_create(const vp_surface_t *s, const vp_simdev_config_t *cfg, const double start[3],
                      vp_simdev_t **out);
void vp_simdev_destroy(vp_simdev_t *d);
int  vp_simdev_move(vp_simdev_t *d, const double target[3], vp_simdev_move_t *res);
int  vp_simdev_probe(vp_simdev_t *d, const double dir_unit[3], double range, vp_simdev_probe_t *res);
/* A line laser: ray i of the last probe's frame (from the same position, at the same time),
 * read like a probe (hits, misses, dark patches, noise and dropouts drawn from the seed, the
 * probe's number and i); counted in rays, not in probes. VP_EINVAL before any probe. */
int  vp_simdev_ray(vp_simdev_t *d, const double dir_unit[3], double range, unsigned i, vp_simdev_probe_t *res);
void vp_simdev_position(const vp_simdev_t *d, double p[3]);
/* Puts the device back where a logged session left it: at p, with `probes` probes done (the
 * next probe is number `probes`). Statistics are kept. */
void vp_simdev_restore(vp_simdev_t *d, const double p[3], uint64_t probes);
void vp_simdev_stats(const vp_simdev_t *d, vp_simdev_stats_t *st);

#endif
