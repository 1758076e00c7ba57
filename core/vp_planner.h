/* vp_planner — where to move and where to probe, after Boissonnat, Guibas and Oudot,
 * "Learning smooth objects by probing" (SoCG 2005).
 *
 * The planner keeps a 3D Delaunay triangulation of the surface samples found so far. Its dual
 * Voronoi graph is the roadmap: the probe device only moves along Voronoi edges (current or
 * former) already proven free, and probes along Voronoi edges from their free end. A probe that
 * hits the surface S on the edge dual to facet f makes f a facet of Del_v|S(E), the visible
 * restricted Delaunay triangulation, with a surface Delaunay ball centred at the hit. Every
 * ball larger than eps (a bad ball) is refined by inserting its centre. When no ball is bad and
 * the restricted facets close up, the mesh is a closed surface isotopic to S within O(eps^2).
 *
 * Step-driven, allocation-free, no callbacks: vp_planner_next() yields one command (MOVE along
 * a proven-free segment, PROBE along a ray from the current position, or DONE); after a PROBE
 * the caller reports the result with vp_planner_feed(). The same loop runs on a
 * microcontroller, a Linux board and the simulator. All memory is the caller's arena.
 */
#ifndef VP_PLANNER_H
#define VP_PLANNER_H

#include <stddef.h>
#include <stdint.h>
#include "vp_dt.h"
#include "vp_status.h"

#define VP_OMEGA_BOX 0
#define VP_OMEGA_BALL 1
#define VP_PLANNER_MAX_SEEDS 16
#define VP_PLANNER_MAX_CONTACTS 16 /* contacts kept apart; more widen the nearest one's reach */
#define VP_PLANNER_MAX_LINE_RAYS 4096 /* a line laser's rays per frame (image columns) */
#define VP_PLANNER_AXES 5          /* x, y, z, pan, tilt (axis_time) */
#define VP_PLANNER_RAY_QUEUE 64    /* line-laser points waiting to become samples */
/* the tubes' feature margin when none is given, per unit of min_feature: a right-angled corner
 * of a box reaches (sqrt 3 - 1) = 0.732 of it beyond its inner balls, an edge of 60 degrees 1 */
#define VP_FEATURE_MARGIN_DEFAULT 0.75

/* planner options (flags) */
#define VP_PLAN_PAPER        0x1u /* detect_access as published: probe every edge of every
                                     newly active Voronoi vertex */
#define VP_PLAN_PREV_CHAINS  0x2u /* travel along prev chains (tree paths) only */
#define VP_PLAN_LARGEST      0x4u /* always refine the largest bad ball (paper); otherwise the
                                     largest one near the device among the big ones */
#define VP_PLAN_NO_AIM       0x8u /* body mode: no lines aimed from aside at hidden facets (aim.c):
                                     for a head that reaches beyond the clearance ball, whose
                                     body only a dry run's sweep checks */
#define VP_PLAN_FAR_READS   0x10u /* body mode: a probe asks for its line up to where it leaves
                                     Omega, not only to its edge's end; a reading past the end
                                     proves the edge free and is a point of S seen from
                                     elsewhere, a sample where none lies within eps (tasks.c) */
#define VP_PLAN_SMALL_FIRST 0x20u /* point mode: of the newest probe tasks, the one whose facet
                                     can have the smallest surface Delaunay ball goes first
                                     (tasks.c; sim sets it with a distance bound), and a facet's
                                     tilt waits for the size pass where it does not bend
                                     (facets.c); otherwise the newest first */

typedef struct vp_planner_config {
    int omega_kind;              /* VP_OMEGA_BOX or VP_OMEGA_BALL */
    double omega_lo[3], omega_hi[3];      /* box */
    double omega_center[3], omega_radius; /* ball */
    double interior[VP_PLANNER_MAX_SEEDS][3]; /* o_i: one point inside each component (A1) */
    uint32_t ninterior;
    double eps;                  /* bound on surface Delaunay ball radii */
    double start[3];             /* device position at the start: outside Omega */
    double max_range;            /* rangefinder range; 0 = unlimited */
    double noise_tol;            /* hits are trusted to within this distance (0: exact) */
    uint32_t confirm_misses;     /* re-probes of a miss where a hit is expected (dropouts) */
    double clearance;            /* device radius: > 0 keeps the device outside Omega (Omega must
                                    keep this distance from the object); it probes every
                                    Voronoi edge along its line from dOmega */
    double min_angle;            /* optional angle bound in degrees (0: off, at most 30): a
                                    facet with a smaller angle is refined like a bad ball */
    double size_rel;             /* > 0: the sizing field of paper 002, a ball is bad when its
                                    radius exceeds g(c) = size_rel min_p (dM(p) + |c - p|),
                                    held to [min_size, eps]; 0: eps everywhere (below 1) */
    double min_size;             /* the sizing field's floor (> 0 and <= eps with size_rel) */
    double max_distance;         /* > 0: a ball is also bad when its centre (on the surface) is
                                    farther than this from its facet's circumcentre, i.e. the
                                    facet strays that far from the surface there (the distance
                                    bound of Boissonnat-Oudot and CGAL's mesher), or leaves
                                    the tangent planes at its vertices that far (a sharp
                                    edge cut off); never below noise_tol; 0: off */
    uint32_t flags;              /* VP_PLAN_* */
    uint32_t line_rays;          /* a line laser: up to this many more rays per PROBE, from the
                                    probe's origin in the same frame (vp_planner_feed_ray); their
                                    hits become samples where no sample lies within eps. 0: a
                                    dot laser (one ray per PROBE) */
    uint32_t proof_life;         /* an object that moves: a proof of free space older than this
                                    many commands (PROBEs and MOVEs) is stale, probed again before
                                    the device moves along it; 0: proofs never expire */
    double min_feature;          /* with a clearance (body mode): > 0 lets the device travel inside
                                    Omega through tubes proven free (tube.c), on the assumption
                                    that every point of the object lies within feature_margin of
                                    a ball of this radius inside the object; 0: never inside */
    double feature_margin;       /* how far the object may reach beyond its balls of radius
                                    min_feature (sharp convex edges and corners: a dihedral angle
                                    theta needs min_feature (1/sin(theta/2) - 1), a cube's corner
                                    0.74 min_feature) */
    double axis_time[VP_PLANNER_AXES]; /* with a clearance (body mode): the time one unit of
                                    travel takes at each axis's top speed (1/max_speed): x, y, z
                                    per unit of length, the head's pan (about z: the azimuth of
                                    the probe's direction) and tilt (its elevation) per radian.
                                    The ways round Omega and the order of the probes are then
                                    chosen for machine time, not length. All 0: length */
    double pan_travel[2];        /* the pan's travel in radians (lo < hi, each within 1000): a
                                    turn across its ends goes the long way round. Both 0: the pan
                                    turns freely. Timed needs the x, y and z times; pan and tilt
                                    may be 0 (not weighed) */
} vp_planner_config_t;

/* VP_CMD_RAY is never issued by vp_planner_next: it names one more ray of the last PROBE's frame
 * (a line laser) for the run loop's hooks (vp_run) and the log. */
enum vp_cmd_kind { VP_CMD_MOVE = 1, VP_CMD_PROBE = 2, VP_CMD_DONE = 3, VP_CMD_RAY = 4 };

typedef struct vp_cmd {
    int kind;
    double from[3];   /* MOVE: start (the current position); PROBE: the origin */
    double to[3];     /* MOVE: target */
    double dir[3];    /* PROBE: unit direction */
    double range;     /* PROBE: maximum distance */
} vp_cmd_t;

#define VP_PROBE_TOO_CLOSE 2 /* a surface nearer than the rangefinder can measure */

typedef struct vp_probe_result {
    int hit;          /* 1: surface at `dist` along the ray; 0: nothing within range;
                         VP_PROBE_TOO_CLOSE: something nearer than the minimum range (no
                         distance: nothing on this ray is proven free or sampled) */
    double dist;
} vp_probe_result_t;

typedef struct vp_planner_stats {
    /* hits, misses and too_close count the answers as the device gave them (every probe fed,
     * the seed's too), whatever the planner made of each: they sum to the probes answered */
    uint64_t probes, hits, misses, moves, reprobes;
    uint64_t insertions, stale_balls, routes, astar_fallbacks, astar_expansions;
    uint64_t shortcut_probes;  /* probes of a straight way to save a detour */
    uint64_t far_reads, far_samples; /* VP_PLAN_FAR_READS: readings past a probed edge's end,
                                        and the samples made of them (tasks.c) */
    uint64_t direct_routes;
    uint64_t escalations;      /* holes closed by probing every edge of every active vertex */
    uint64_t too_close;        /* probes that saw a surface nearer than the minimum range */
    uint64_t occluded;         /* body mode: the line met S before the edge */
    uint64_t tube_moves;       /* body mode: moves inside Omega along tubes proven free */
    uint64_t level_routes;     /* body mode: ways round a ball Omega taken level (route.c): the
                                  slowest axis moved least */
    uint64_t tube_starts;      /* body mode: probes started inside Omega (nearer their edge) */
    uint64_t vantages;         /* body mode: lines probed again from past what occluded them */
    uint64_t surveys, survey_probes, surveys_failed; /* tubes surveyed by parallel rays first */
    uint64_t aims;             /* body mode: probes aimed from aside at a hidden facet's edge */
    uint64_t aim_balls;        /* hidden facets whose surface Delaunay ball those found */
    uint64_t aim_near;         /* ... of them by the hit nearest the edge of a narrowed stretch */
    uint64_t aim_reached;      /* hidden facets whose far vertex those saw free (reached) */
    uint64_t read_samples;     /* balls found from aside refined at the point of S the line read
                                  instead of their centre (update.c) */
    uint64_t read_kept;        /* ... left unrefined: the point read lies beside a sample, where
                                  the centre may be as far off S as the tolerance */
    uint64_t far_line_sides;   /* sides aimed at once more with lines through the far vertex alone
                                  (the last resort of closing, close.c) */
    uint64_t last_resorts;     /* closing's last resort taken (again only with at most half as
                                  many odd edges) */
    uint64_t reseeds;          /* samples added on components the seeds had missed */
    uint64_t noise_drops;      /* hits that a full miss from the edge's other end contradicted
                                  (S within the noise of that end): the facet dropped */
    uint64_t unproven;         /* segments an inference took for free that no probe covers:
                                  never added to the free graph */
    uint64_t manifold_refinements; /* facets refined because an edge had not two facets */
    uint64_t unseen_refinements; /* ... of them at an edge whose ring holds a side left unseen (body
                                  mode, after closing's last resort, while the odd edges fall) */
    uint64_t fins_cut;         /* tets of the inside cut off where it touched itself (at an edge
                                  or a vertex) below the manifold floor (a fin's tip; close.c) */
    uint64_t stalls;           /* steps that made no progress (bounded: see VP_ESTALL) */
    uint64_t contacts;         /* moves the head's contact switch stopped (vp_planner_touch) */
    uint64_t revoked;          /* proofs of free space a contact showed false */
    uint64_t dark_misses;      /* misses not taken as proof: the ray passed near a contact */
    uint64_t rays, ray_hits;   /* a line laser's more rays fed (vp_planner_feed_ray), and hits */
    uint64_t ray_samples;      /* their hits inserted as samples */
    uint64_t rescan_kept;      /* a re-scan (vp_planner_rescan): samples measured again and kept */
    uint64_t rescan_dropped;   /* samples not where they were (moved, gone, covered): removed */
    uint64_t rescan_unseen;    /* of those, samples no line reached (covered, or out of reach) */
    uint64_t rescan_moved;     /* of those, samples found again near where they were: the point
                                  measured takes the sample's place (paper 001's vertex move) */
    uint64_t rescan_skipped;   /* kept unmeasured (VP_RESCAN_SPARSE): every neighbour held */
    uint64_t rescan_normal;    /* samples measured along their normal (their probe's line blocked
                                  or unknown) */
    uint64_t reproved;         /* route steps on proofs from before the re-scan, probed again and
                                  found free before the MOVE */
    uint64_t reprove_blocked;  /* ... and found blocked: the proofs through that point withdrawn */
    double travel;             /* length of all MOVEs */
    double travel_prev_chains; /* what the same moves cost along prev chains (the paper's
                                  paths); equal to travel with VP_PLAN_PREV_CHAINS */
    double max_ball;           /* largest surface Delaunay ball now */
    uint32_t bad_balls;        /* in the queue now */
    uint32_t missing_components; /* o_i not enclosed by the mesh (H2 fails for them) */
    uint32_t records, free_edges, facet_records;
    size_t arena_peak;
} vp_planner_stats_t;

/* Internal records, declared for sizing only (core/planner/vp_planner_priv.h has the rest). */
typedef struct vp_vrec vp_vrec_t;
typedef struct vp_frec vp_frec_t;
typedef struct vp_task {
    uint32_t tet;
    uint8_t facet;
    uint16_t tries;
    uint32_t proof;    /* with off > 0: the proof of the ray's last free piece */
    double off;        /* already proven free from the origin (a range-limited probe) */
} vp_task_t;

/* Body mode, per task slot: where the task's probe would start (o; ok 0 where it cannot), kept
 * with the Voronoi edge it was worked out for: the two tets' vertices as stored, which name the
 * facet between them and the edge to the last bit (vertex records are never reused). tasks.c */
typedef struct vp_task_near {
    uint32_t tv[4], uv[4];
    double o[3];
    uint8_t ok;
} vp_task_near_t;

/* Point mode with VP_PLAN_SMALL_FIRST: beside each task slot, the squared radius of the smallest
 * ball its probe can find (-1: not a candidate), with the two tets' vertices it was worked out
 * for (as vp_task_near_t's: they name the facet and its Voronoi edge). tasks.c */
typedef struct vp_task_small {
    uint32_t tv[4], uv[4];
    double key;
    uint8_t ok;
} vp_task_small_t;

/* A proof of free space: the free part of one probe, [o, o + len * d] (d unit), and the proof
 * of the piece before it on the same ray (a range-limited probe walked on), or none. */
typedef struct vp_proof {
    double o[3], d[3], len;
    uint32_t prev;
    uint32_t born;     /* commands issued when it was made (cfg.proof_life) */
} vp_proof_t;

/* The planner's state, in parts by role (like grbl's stepper.c). Each part says who writes it;
 * the files are those of core/planner/. Nothing here is for the caller to read or write: use
 * the functions below (cfg may be read). */

/* The pools, carved from the arena once by vp_planner_init (planner.c) and never moved. */
typedef struct vp_pl_pools {
    vp_vrec_t *vrec; uint32_t nvrec, cap_vrec;        /* records: route.c (rec_new) */
    uint32_t *fedge; uint32_t nfedge, cap_fedge;      /* free graph: route.c (edge_add) */
    vp_frec_t *frec; uint32_t nfrec, cap_frec, frec_free, nfacets; /* facets.c */
    uint32_t *fhash; uint32_t hash_mask, ntomb;       /* facet key -> frec index: facets.c */
    uint32_t room;                                    /* headroom of one update (update.c) */
    int fhash_dirty;                                  /* facets.c: rebuild before a lookup */
    uint32_t *heap; uint32_t nheap, cap_heap;         /* bad balls, max-heap on radius: facets.c */
    vp_task_t *task; uint32_t ntask, cap_task;        /* pending probes (a stack): tasks.c */
    vp_task_near_t *near;                             /* per task slot in body mode (an arena
                                                         of some 2.6 MB up, 3 MB timed), else NULL: tasks.c
                                                         (the nearest task) */
    vp_task_small_t *small;                           /* per task slot with the smallest ball
                                                         first (point mode; an arena of some
                                                         3 MB up), else NULL: tasks.c */
    float *near_dir;                                  /* timed body mode: beside each kept
                                                         start, its probe's direction (3 per
                                                         slot, a cost's estimate: route.c) */
    vp_proof_t *proof; uint32_t nproof, cap_proof;    /* free parts of probes: proof.c */
    uint32_t *astar; uint32_t cap_astar;              /* scratch, see VP_PL_SCRATCH in the
                                                         private header for who owns it when */
    uint32_t *vstamp;                                 /* per sample (cap_nrm of them): the size
                                                         pass's epoch of its last change (facets.c) */
    double *nrm; uint32_t cap_nrm;                    /* per sample: its normal estimate, valid
                                                         while the sample record's aux is 1
                                                         (facets.c; update.c clears it) */
} vp_pl_pools_t;

/* The current route: written by route.c (plan_route, route_push), consumed one MOVE at a time
 * by vp_planner_next (planner.c). Done when i == n. */
typedef struct vp_pl_route {
    uint32_t *path; uint32_t cap_path;     /* waypoint records of a path search (route.c) */
    double *pts; uint32_t n, i, cap;       /* the route as points; i: the next one to move to */
    uint32_t *proof;                       /* each step's proof of freedom */
    uint32_t from;                         /* the record the route starts at */
    int deferred;                          /* the route waits for the shortcut probe's answer */
} vp_pl_route_t;

/* Where the device is and what it was last told: planner.c (next/feed). */
typedef struct vp_pl_device {
    double pos[3];
    uint32_t at;                           /* record it stands at (VP_DT_NONE between) */
    int awaiting;                          /* 1: a PROBE was issued, feed() expected */
    double iss_o[3], iss_d[3], iss_range;  /* the PROBE issued last */
    double pan;                            /* the pan it was aimed with last (radians; timed
                                              body mode: route.c), before the first probe 0
                                              or the nearest end of pan_travel */
} vp_pl_device_t;

/* The probe being carried out: prepared by task_start (tasks.c) or the seed/reseed steps
 * (seed.c, close.c), issued by vp_planner_next, closed by task_finish. */
typedef struct vp_pl_probe {
    vp_task_t task;                        /* the task it carries out */
    double origin[3], dir[3], range, full;
    double reach;                          /* body mode: the beam asked for past the edge's end,
                                              to where its line leaves Omega (0: range) */
    double standoff;                       /* origin to the edge's vertex (body mode) */
    int vantage;                           /* body mode with tubes: started past an occluder */
    int ready;                             /* prepared: issue it once the route is done */
    uint32_t origin_rec;
    uint32_t cur_proof;                    /* the proof made from its result (or none): proof.c */
    uint32_t chain_proof;                  /* it continues this proof's ray (or none) */
} vp_pl_probe_t;

/* A straight shortcut being probed instead of a detour: route.c proposes, planner.c issues
 * and takes the answer. */
typedef struct vp_pl_shortcut {
    uint32_t to, from, tries;
    int pending;                           /* 1: to issue, 2: issued */
} vp_pl_shortcut_t;

/* The seeds: seed.c only. */
typedef struct vp_pl_seed {
    uint32_t cur, step, attempt;
    uint32_t miss;                         /* misses of the current seed probe (dropouts) */
    uint32_t dir;                          /* the seed's direction: 0 from the start, then the
                                              reseeding directions (a surface not seen on the way) */
    uint32_t base;                         /* npts when the current seed began */
    double pts[4 * VP_PLANNER_MAX_SEEDS][3];
#ifndef VP_CORE_MCU
    double ray[4 * VP_PLANNER_MAX_SEEDS][3];  /* the ray each was found along (a re-scan's line) */
#endif
    uint32_t npts;
    double q[3];
} vp_pl_seed_t;

/* Closing holes and H2: close.c (and the exhaustive flag read by tasks.c). */
typedef struct vp_pl_close {
    uint64_t mark;           /* probes + insertions + 1 when holes were last closed */
    uint64_t size_mark;      /* insertions + 1 at the last pass of the sizing field */
    uint32_t size_epoch;     /* the size passes so far, plus 1 (facets.c: what changed since) */
    int exhaustive;          /* detect_access in full until the next insertion */
    int far_lines;           /* aims also pass the far vertex alone (aim.c): set the first time
                                closing finds nothing left to probe at a hole (close.c) */
    uint32_t resort_odd;     /* the odd edges when closing's last resort was last taken: taken
                                again only with at most half as many (close.c) */
    uint32_t unseen_odd;     /* body mode: the odd edges when the manifold criterion last refined
                                round a side left unseen (0: never); again only with fewer (close.c) */
    uint32_t h2_done;        /* bit i: o_i is enclosed by the mesh */
    uint8_t h2_tries[VP_PLANNER_MAX_SEEDS];
} vp_pl_close_t;

/* Contacts (contact.c): where the head touched S during a MOVE that a miss had shown free (a
 * dark or shiny surface that returned no spot). A miss whose ray passes within reach of one is
 * not taken as proof of free space. */
typedef struct vp_pl_contact {
    double at[VP_PLANNER_MAX_CONTACTS][3];
    double reach[VP_PLANNER_MAX_CONTACTS];
    uint32_t n;
    int moved;                             /* the last command was a MOVE: a touch may follow */
    double move_from[3];                   /* that MOVE's start */
} vp_pl_contact_t;

#ifndef VP_CORE_MCU
/* A line laser's hits waiting to become samples (planner.c: feed_ray queues, the refinement step
 * inserts). left: rays the current frame may still give. */
typedef struct vp_pl_rays {
    double pts[VP_PLANNER_RAY_QUEUE][3];
    uint32_t n, left;
} vp_pl_rays_t;
#endif

#ifndef VP_CORE_MCU
/* A re-scan (rescan.c): what is left to measure again, and a route step being proven again. */
typedef struct vp_pl_rescan {
    uint32_t mark;                         /* proofs below this id are stale (0: no re-scan) */
    uint32_t nvert;                        /* samples (vertex records) before the re-scan */
    uint32_t next;                         /* the next of them to measure */
    int pass;                              /* 0: from outside Omega; 1: the samples that needs
                                              from their probe's origin inside (deferred) */
    uint32_t cur;                          /* the one being measured (NONE: none) */
    uint32_t along;                        /* 0: its probe's line, 1: its normal */
    uint32_t tries;                        /* misses of the current PROBE re-probed */
    double expect;                         /* the sample's distance along the PROBE */
    double tol;                            /* kept when found within this of it */
    int reprove;                           /* 1: the PROBE out is a route step's proof */
    uint32_t doomed[8], ndoomed;           /* samples to remove once the triangulation keeps 3D
                                              without them (a few samples left: the object moved) */
    uint32_t drop;                         /* a sample the last PROBE showed moved: removed by the
                                              next vp_planner_next (NONE: none) */
    int move;                              /* 1: ... and the point that PROBE met takes its place
                                              (move_to; the line it keeps: move_aux) */
    double move_to[3];
    uint32_t move_aux;
    int blocked;                           /* the last route-step PROBE found the step blocked:
                                              1 at blocked_at, 2 with no point; handled by the
                                              next vp_planner_next */
    double blocked_at[3];
    uint32_t blocked_proof;
} vp_pl_rescan_t;
#endif

#ifndef VP_CORE_MCU
/* Tubes proven free inside Omega (tube.c): a bit per cell of a grid over Omega's bounding box,
 * set when the cell lies within min_feature of free space. on: 0 when off (no min_feature, or a
 * contact or a re-scan made the marks stale). The device's way out: where it is inside Omega
 * (inside) and the point outside from which a proven tube reaches it (exit). */
typedef struct vp_pl_tube {
    uint8_t *bits;
    uint32_t n[3];
    double lo[3], cell, half;  /* the grid: its corner, cell side, half a cell's diagonal */
    double mark;               /* a cell is marked within this distance of a free ray */
    double reach;              /* clearance + feature_margin + min_feature: the checked capsule */
    int on, inside, goal_in;   /* goal_in: the next route's goal is a start inside Omega */
    double exit[3], goal_exit[3];
    /* a survey: parallel rays from outside Omega that prove a tube from sx out along su, fired
     * one by one (i of n, on an m x m grid d apart across it), then the probe pend from sx */
    uint32_t survey_i, survey_n, survey_m;
    int survey_ready, survey_wait;
    double sx[3], su[3], sw1[3], sw2[3], sd, ss, ray_range;
    vp_pl_probe_t pend;
} vp_pl_tube_t;
#endif

#ifndef VP_CORE_MCU
/* Body mode: a hidden facet's Voronoi edge [a, a + len e] found from aside (aim.c). Lines
 * along direction d through points q(t) of the edge, t in (lo, hi), halve the stretch where S
 * crosses it: q(lo) was seen free, the line through q(hi) met S just before it. */
typedef struct vp_pl_aim {
    int on;                    /* 1: the probe prepared or issued is an aimed one */
    uint32_t dir_i, steps;     /* the direction tried (aim.c), the lines along it so far */
    uint32_t tries;            /* re-probes of the issued line after a miss (a dropout?) */
    int to_vertex;             /* the edge ends at its far vertex in Omega (else at dOmega) */
    double a[3], e[3], len;    /* the edge */
    double out[3];             /* a point on the edge's line outside S: the facet's outer side */
    double d[3], t, lo, hi;    /* this direction; the point q(t) the issued line passes through */
    double sq;                 /* the line's origin to q(t) */
    double next_t;             /* where the last hit puts S's crossing of the edge, or -1 */
    double near_c[3], near_d;  /* of this direction's hits, the one nearest the edge: taken onto
                                  it, and its distance (near_d < 0: none within tol) */
    double near_h[3];          /* that hit as read */
    struct vp_pl_aim_read {    /* the balls found lately (a ring): record k's centre c, on the edge, */
        uint32_t k;            /* and h, the point of S the line read, up to the tolerance aside */
        double c[3], h[3];     /* (refining the ball may insert h instead: update.c) */
    } read[256];
    uint32_t nread;            /* balls found from aside so far; the next goes to
                                  read[nread % 256]: a run on the rpi4's 36 mm torus at eps 1.85 to
                                  3 finds 68 to 430 */
    uint64_t past_share;       /* aims up to this count start past AIM_SHARE: those closing's last
                                  resort queued (close.c, vp_pl_aim_last_resort); 0 again on a
                                  re-scan */
} vp_pl_aim_t;
#endif

/* High-water marks of the pools whose use goes up and down (for stats.arena_peak). */
typedef struct vp_pl_peak {
    uint32_t task, heap, route, astar, path;
} vp_pl_peak_t;

typedef struct vp_planner {
    vp_planner_config_t cfg; /* the caller's, copied by init; read everywhere */
    vp_dt_t dt;              /* the Delaunay triangulation of the samples (vp_dt) */
    int phase;               /* PH_*: the phase machine of planner.c */
    int error;               /* sticky: once < 0, next/feed return it */
    uint32_t stamp;          /* path search generation (route.c) */
    double ptol;             /* slack of a proof check (rounding of constructed points) */
    double sin_angle;        /* sin of the angle bound (0: none) */
    vp_pl_pools_t pool;
    vp_pl_route_t route;
    vp_pl_device_t dev;
    vp_pl_probe_t probe;
    vp_pl_shortcut_t sc;
    vp_pl_seed_t seed;
    vp_pl_close_t close;
    vp_pl_contact_t contact;
#ifndef VP_CORE_MCU
    vp_pl_rays_t rays;
    vp_pl_rescan_t rescan;
    vp_pl_tube_t tube;
    vp_pl_aim_t aim;
#endif
    vp_pl_peak_t peak;
    vp_planner_stats_t st;   /* counters, written where things happen */
} vp_planner_t;

/* Checks the configuration (VP_EINVAL: bad Omega (also one whose circumradius is below 1e-4 or
 * above 1e50 units: choose the units so, mm for a desktop scanner), eps <= 0 or NaN, no interior point, an
 * interior point or the start outside its place; VP_ENOMEM: arena too small) and prepares a
 * session. Nothing is probed before the first vp_planner_next(). A bad configuration or an
 * arena under the least size leaves pl as it was; an arena too small for the pools once laid
 * out leaves pl cleared and holding the error: vp_planner_next and every call that acts answer
 * VP_ENOMEM (vp_planner_feed VP_ESTATE: no probe is owed); the arena is the new session's, an
 * earlier session in it is gone. */
int vp_planner_init(vp_planner_t *pl, void *arena, size_t bytes, const vp_planner_config_t *cfg);

#ifndef VP_CORE_MCU
/* 1 when the configuration has the planner weigh its moves by machine time: a body (clearance)
 * and the x, y and z axis times (axis_time) */
int vp_planner_timed(const vp_planner_config_t *c);
#endif

/* The next command. VP_OK with cmd filled; VP_ESTATE if a PROBE result is still owed;
 * VP_ENOMEM when the arena is full (the mesh so far stays exportable); VP_ERANGE when an
 * interior point turned out not to be inside the object. */
int vp_planner_next(vp_planner_t *pl, vp_cmd_t *cmd);

/* 1 when a device's result is one the planner (and a session log) takes: hit 0, 1 or
 * VP_PROBE_TOO_CLOSE, the distance finite, a hit's not negative. */
int vp_probe_result_valid(const vp_probe_result_t *res);

/* The result of the last PROBE. VP_EINVAL for a distance that is NaN or infinite (whatever the
 * result: the session log holds it) or a hit at a negative one (nothing changes). */
int vp_planner_feed(vp_planner_t *pl, const vp_probe_result_t *res);

/* A miss must be seen: 1 when an occluder (below) crosses the triangle swept by the sight lines
 * from the camera's centre `cam` to the beam from `origin` along unit `dir` up to `range` (a spot
 * there may have been hidden from the camera, so a miss read there proves nothing: feed it as
 * VP_PROBE_TOO_CLOSE); 0 when none does; VP_EINVAL for NaN or a negative range. Changes nothing.
 * Exact (orient3d on the points given); touching counts, and so does an occluder lying in the
 * triangle's plane. */
int vp_planner_spot_hidden(const vp_planner_t *pl, const double origin[3], const double dir[3], double range,
                           const double cam[3]);
/* The occluders, where S may stand: the facets of the mesh found so far, and the facets between a
 * tet whose Voronoi vertex no probe has reached and one whose vertex was reached or lies outside
 * Omega. Slot i: 1 with its corners in tri, 0 when slot i holds none, -1 past the last slot. */
int vp_planner_sight_occluder(const vp_planner_t *pl, uint32_t i, double tri[3][3]);

/* The last MOVE stopped at distance `at` from its start: the head's contact switch closed, so S
 * is there although the probes had shown the segment free (a surface the rangefinder cannot
 * see: black, shiny). Call it before the next vp_planner_next(). The planner withdraws every
 * proof of free space whose ray passes through the contact point, distrusts misses near it from
 * now on, takes the point as a sample, and routes the device back along the move to its start
 * (the next MOVE goes from the contact point there). VP_EINVAL for NaN or `at` outside the
 * move; VP_ESTATE when the last command was not a MOVE or a touch was already reported for it;
 * VP_ERANGE when the contact lies outside Omega (Omega must hold the object: assumption A2);
 * VP_EUNSAFE when it comes while the seeds are placed (a seed's ray walked on into Omega met S
 * where its probe had shown it free: there is no triangulation yet to take the point, and the
 * scan stops). */
#ifndef VP_CORE_MCU /* a microcontroller core leaves the contact safety net out (vp_status.h) */
int vp_planner_touch(vp_planner_t *pl, double at);
/* The same for `move`, a MOVE of a path the device made as one (vp_run): the MOVEs given after it,
 * and the PROBE that may follow them, were not made. The last command given: vp_planner_touch.
 * Else the planner has gone past it: VP_ERANGE when the contact lies outside Omega (as
 * vp_planner_touch: a head kept outside Omega met the object there, and the scan stops),
 * otherwise VP_ESTATE (a device must not run such a path inside Omega). */
int vp_planner_touch_path(vp_planner_t *pl, const vp_cmd_t *move, double at);

/* A line laser: one more ray of the last PROBE's frame, from that PROBE's origin along unit `dir`,
 * and what it saw (as for vp_planner_feed). Call after vp_planner_feed, up to cfg.line_rays
 * times per PROBE. A hit is a point of S: it is inserted as a sample before the next refinement
 * step when no sample lies within eps of it (the samples keep their spacing, so the refinement
 * keeps its bound and its end: every ball at most eps); misses and rays fed while the seeds are
 * found or holes are closed add nothing. VP_EINVAL for NaN, a direction not of unit length or a
 * bad result (nothing changes); VP_ESTATE without cfg.line_rays, before a PROBE was fed, while a
 * PROBE result is owed, or for more rays than cfg.line_rays. */
int vp_planner_feed_ray(vp_planner_t *pl, const double dir[3], const vp_probe_result_t *res);

/* A re-scan: the object may have changed since the session so far (replayed into pl); the device
 * stands at cfg.start again. Every proof of free space made so far is stale: before the device
 * moves along one, a PROBE of that segment must find it free again (a hit withdraws the proofs
 * through that point, and the point becomes a sample). Then every sample is measured again from
 * outside Omega, along the line of the probe that found it or along its normal: one found again
 * within the noise tolerance (at least a billionth of Omega's size) is kept with its facets; any
 * other is removed (vp_dt_remove) with the facets and free Voronoi edges around it (its star and
 * its neighbours' facets), and the scan goes on from there as any scan does. So a change is seen
 * where it moves a sample or crosses one of the lines measured; elsewhere the surface between
 * samples that hold is taken as unchanged. VP_ESTATE while a PROBE result is owed or before the
 * session has samples (dim < 3). Call it again for another re-scan. */
int vp_planner_rescan(vp_planner_t *pl);
/* The same with the device where it stands (the next round of tracking a moving object: it
 * leaves over stale steps, each proven again first). */
int vp_planner_rescan_here(vp_planner_t *pl);
/* Either, by flags (a RESCAN event's code carries them): VP_RESCAN_HERE, the device stays;
 * VP_RESCAN_SPARSE, a sample all of whose Delaunay neighbours are measured is not measured itself
 * (no two neighbours both left out) unless one of them is not where it was: about 70% of the
 * samples are measured on an unchanged object, and a change narrower than the sample spacing
 * that moves only samples left out goes unseen. Other bits: VP_EINVAL. */
#define VP_RESCAN_HERE 1u
#define VP_RESCAN_SPARSE 2u
int vp_planner_rescan_with(vp_planner_t *pl, unsigned flags);
#endif

/* The mesh: restricted facets with their vertices (indices into vp_planner_dt()), oriented with
 * the normal (b-a)x(c-a) pointing out of the object. vp_planner_facet returns the ball radius
 * through *radius (may be NULL). Iterate i < vp_planner_facet_slots(). Returns 1 for a facet,
 * 2 for a facet of a tet cut off at a pinch below the manifold floor (its ball is its circumball,
 * not a probed surface point; stats.fins_cut), 0 for an empty slot. */
uint32_t vp_planner_facet_slots(const vp_planner_t *pl);
int vp_planner_facet(const vp_planner_t *pl, uint32_t i, uint32_t v[3], double *radius,
                     double center[3]);
uint32_t vp_planner_num_facets(const vp_planner_t *pl);
/* What the planner is doing (for reports): finding the first samples (paper 000's seed; in a
 * re-scan, measuring the old ones again), Delaunay
 * refinement, closing (holes, the manifold criterion, every component enclosed), done. Refining
 * again after a closing round counts as refinement. */
typedef enum { VP_STAGE_SEED = 0, VP_STAGE_REFINE = 1, VP_STAGE_CLOSE = 2, VP_STAGE_DONE = 3 } vp_planner_stage_t;
vp_planner_stage_t vp_planner_stage(const vp_planner_t *pl);
const vp_dt_t *vp_planner_dt(const vp_planner_t *pl);
void vp_planner_get_stats(const vp_planner_t *pl, vp_planner_stats_t *st);

#endif
