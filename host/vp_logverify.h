/* vp_logverify — a proof check of a session log, from the log alone: every MOVE must lie in
 * space proven free before it was made. It shares no code with the planner's free-space
 * bookkeeping (core/vp_planner.c): it replays the records only, never the planner.
 *
 * Rules of proof (doc/session-log.md, "Proof check"):
 * - the device starts at the header's cfg.start; a MOVE goes from the current position to its
 *   target; EVENTs (START, PAUSE, RESUME, ...) do not move it;
 * - a PROBE (origin o, unit direction d, range R, result h, distance t) proves free the segment
 *   o .. o + (t - noise_tol) d for a hit (nothing if t <= noise_tol; never beyond R), o .. o + R d
 *   for a miss, and nothing for a too-close result; only probes logged before a move count,
 *   and only probes fired from where the device stood (a probe whose origin is not the device
 *   position is counted as a violation and proves nothing);
 * - everything outside Omega (the header's box or ball) is free (assumption A2: Omega contains
 *   the object); a point on dOmega counts as outside;
 * - a PROBE proves nothing beyond the header's rangefinder range (max_range, when set), nor
 *   anything when its free part passes within the contact reach (the header's eps, at least 4
 *   noise tolerances, as the planner's) of an earlier contact: a miss there may be a surface
 *   the rangefinder cannot see;
 * - a CONTACT event (the head's contact switch stopped the MOVE right before it at value[0]
 *   along it) puts the device at that point; every earlier free part that passes within the
 *   noise tolerance of the point is withdrawn (the surface is there: the probe that showed it
 *   free was wrong), and the part of the move up to the point is free (the head travelled it).
 *   A CONTACT that does not follow a MOVE is a violation (misplaced) and teaches nothing; one
 *   outside Omega (or on dOmega) shows that Omega does not hold the object: no move after it is
 *   proven (the planner stops there);
 * - a device with a body (a header with a clearance) and no tubes never enters Omega: the part
 *   of a move inside Omega is unproven whatever probes lie along it (a ray proves no volume);
 * - a move or probe more than VP_LOGVERIFY_FAR diameters from Omega's centre is not a move
 *   this machine makes: the move is unproven, the probe proves nothing;
 * - a move is proven when the segment parameter interval [0,1] is covered by its part outside
 *   Omega and the free parts of earlier probes on its line (both its ends within tol of the
 *   probe's line), the uncovered length adding up to at most tol;
 * - with tubes (a header with a clearance C and a feature size rho > 0, margin eta; the object
 *   lies within eta of its balls of radius rho): a move not wholly outside Omega is proven when
 *   every point of the capsule of radius C + eta + rho about it lies nearer than rho to a free
 *   part or to the outside of Omega. The check covers the capsule with cubes, those of side
 *   rho / 2 about the points of a lattice anchored at the move's start, split in eight where
 *   need be: a cube whose centre lies nearer than rho less its half diagonal to free space is
 *   proven whole. A planner proves its tubes with a margin m = rho / 32 (every point within
 *   C + eta + rho + m of the move lies nearer than rho - m to free space: core/planner/tube.c),
 *   so cubes of half diagonal at most m are always proven; a cube that small not proven is a
 *   violation. (Distances are taken to the check's tolerance tol, 1e-9 of Omega's diameter.)
 *
 * Streaming: vp_logverify_begin, vp_logverify_add for each record in log order,
 * vp_logverify_end. Probes are kept in a hash on their quantised line (direction and foot
 * point), so a move looks at the few probes whose line can contain it: O(n) expected.
 */
#ifndef VP_LOGVERIFY_H
#define VP_LOGVERIFY_H

#include <stddef.h>
#include <stdint.h>
#include "vp_logfmt.h"

/* Geometric tolerance, relative to Omega's diameter: a move end within tol of a probe's line
 * is on it, and a move may leave up to tol of its length uncovered (rounding of the planner's
 * arithmetic is ~1e-16 relative; an unproven stretch the tests care about is >= 1e-6). */
#define VP_LOGVERIFY_TOL_REL 1e-9

/* Moves and probe origins farther than this many Omega diameters from its centre are refused
 * (their arithmetic could not be trusted to the tolerance). */
#define VP_LOGVERIFY_FAR 1e6

/* How many offending moves / probes the result lists (the counts are complete). */
#define VP_LOGVERIFY_LIST 20

typedef struct vp_logverify_move {
    uint32_t record;           /* its index among the log's records (0-based) */
    uint32_t seq;              /* its sequence number */
    uint64_t move;             /* its number among the MOVE records (1-based) */
    double from[3], to[3];
    double length;             /* |to - from| */
    double unproven;           /* total length of the parts not proven free */
    double gap_s0, gap_s1;     /* the first unproven part, as segment parameters in [0,1] */
    double gap_from[3], gap_to[3]; /* ... and as points */
    uint32_t gaps;             /* unproven parts (maximal intervals) */
    uint32_t probes_on_line;   /* earlier probes whose line contains the segment */
} vp_logverify_move_t;

typedef struct vp_logverify_probe {
    uint32_t record, seq;
    double origin[3];          /* where the log says it was fired from */
    double pos[3];             /* where the device was */
    double off;                /* |origin - pos| */
} vp_logverify_probe_t;

typedef struct vp_logverify_result {
    uint64_t records;          /* records verified */
    uint64_t moves, probes, events;
    uint64_t rays;             /* RAY records (a line laser's more rays): counted, never taken as proof */
    uint64_t unproven_moves;   /* moves not covered by proven-free space */
    uint64_t probes_off_position; /* probes fired from where the device was not */
    uint64_t probes_bad;       /* probes with a zero direction (prove nothing; also counted) */
    uint64_t moves_outside;    /* moves wholly outside Omega */
    uint64_t contacts;         /* CONTACT events */
    uint64_t withdrawn;        /* free parts a contact showed false */
    uint64_t rescans;          /* RESCAN events: every free part before one is stale after it */
    uint64_t scans;            /* moves too short for the line index that the probes fired
                                  from their ends did not prove (all probes scanned) */
    uint64_t tube_moves;       /* with tubes: moves not wholly outside Omega, checked by the tube rule */
    uint64_t tube_points;      /* cubes of their capsules looked at (their centres) */
    uint64_t tube_too_large;   /* tube moves whose lattice (or cubes) are too many to look at: unproven */
    uint64_t contacts_misplaced; /* CONTACT events not right after a MOVE (a violation) */
    uint64_t probes_near_contact; /* probes whose free part passes within the contact reach of
                                     an earlier contact: they prove nothing */
    uint64_t probes_far;       /* probes fired from beyond VP_LOGVERIFY_FAR: they prove nothing */
    double unproven_length;    /* summed over the unproven moves */
    double tol;                /* the tolerance used (VP_LOGVERIFY_TOL_REL x Omega's diameter) */
    double pos[3];             /* the device position after the last record */
    uint32_t nmoves_listed;    /* first unproven moves, in log order */
    vp_logverify_move_t move[VP_LOGVERIFY_LIST];
    uint32_t nprobes_listed;   /* first off-position probes, in log order */
    vp_logverify_probe_t probe[VP_LOGVERIFY_LIST];
    int ok;                    /* 1: every move proven, every probe from the device position and
                                  every CONTACT right after a MOVE */
} vp_logverify_result_t;

/* The verifier's state (fields are private). */
typedef struct vp_lv_probe vp_lv_probe_t;
typedef struct vp_lv_entry vp_lv_entry_t;
/* a hash of probe indices by 64-bit key (chained; heads UINT32_MAX: empty) */
typedef struct vp_lv_hash {
    vp_lv_entry_t *ent; size_t n, cap;
    uint32_t *head; size_t mask;
} vp_lv_hash_t;
typedef struct vp_logverify {
    vp_planner_config_t cfg;
    double centre[3], diam, tol, hu, hc, ho;
    vp_lv_probe_t *pr; size_t npr, cap_pr;      /* probes with a free part */
    vp_lv_hash_t lines;                         /* each probe on its line as +d and -d, and on
                                                   its origin */
    double (*iv)[2]; size_t cap_iv;             /* per-move interval scratch */
    uint32_t *seen; uint32_t stamp;             /* per-probe stamp: counted once per move */
    uint32_t index;                             /* next record index */
    uint64_t commands;                          /* PROBE and MOVE records so far */
    double from[3];                             /* where the last MOVE started */
    int after_move;                             /* the record before the current one was a MOVE */
    double (*ct)[3]; size_t nct, cap_ct;        /* contact points (relative to the centre) */
    double ct_reach;                            /* a free part this near a contact proves nothing */
    int omega_broken;                           /* a contact outside Omega: nothing after it is proven */
    int tubes;                                  /* the header has a clearance and min_feature */
    double tcell;                               /* the free parts' cells: 2 min_feature */
    vp_lv_hash_t cells;                         /* a free part in every cell it passes within
                                                   1.25 min_feature of */
    vp_logverify_result_t res;
} vp_logverify_t;

/* VP_OK; VP_EINVAL when the header's Omega is unusable (not finite, empty). */
int  vp_logverify_begin(vp_logverify_t *v, const vp_logfmt_header_t *h);
/* One record, in log order. VP_OK or VP_ENOMEM (the state stays valid; end still frees). */
int  vp_logverify_add(vp_logverify_t *v, const vp_logfmt_record_t *r);
/* The result; frees the state. */
void vp_logverify_end(vp_logverify_t *v, vp_logverify_result_t *res);

/* All at once: header and records[0..n). VP_OK, VP_EINVAL, VP_ENOMEM. */
int  vp_logverify_run(const vp_logfmt_header_t *h, const vp_logfmt_record_t *records, size_t n,
                      vp_logverify_result_t *res);

#endif
