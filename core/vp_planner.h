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

/* planner options (flags) */
#define VP_PLAN_PAPER        0x1u /* detect_access as published: probe every edge of every
                                     newly active Voronoi vertex */
#define VP_PLAN_PREV_CHAINS  0x2u /* travel along prev chains (tree paths) only */
#define VP_PLAN_LARGEST      0x4u /* always refine the largest bad ball (paper); otherwise the
                                     largest one near the device among the big ones */

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
    uint32_t flags;              /* VP_PLAN_* */
} vp_planner_config_t;

enum vp_cmd_kind { VP_CMD_MOVE = 1, VP_CMD_PROBE = 2, VP_CMD_DONE = 3 };

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
    uint64_t probes, hits, misses, moves, reprobes;
    uint64_t insertions, stale_balls, routes, astar_fallbacks, astar_expansions;
    uint64_t shortcut_probes;  /* probes of a straight way to save a detour */
    uint64_t direct_routes;
    uint64_t escalations;      /* holes closed by probing every edge of every active vertex */
    uint64_t too_close;        /* probes that saw a surface nearer than the minimum range */
    uint64_t occluded;         /* body mode: the line met S before the edge */
    uint64_t reseeds;          /* samples added on components the seeds had missed */
    uint64_t noise_drops;      /* hits that a full miss from the edge's other end contradicted
                                  (S within the noise of that end): the facet dropped */
    uint64_t unproven;         /* segments an inference took for free that no probe covers:
                                  never added to the free graph */
    uint64_t stalls;           /* steps that made no progress (bounded: see VP_ESTALL) */
    double travel;             /* length of all MOVEs */
    double travel_prev_chains; /* what the same moves cost along prev chains (the paper's
                                  paths); equal to travel with VP_PLAN_PREV_CHAINS */
    double max_ball;           /* largest surface Delaunay ball now */
    uint32_t bad_balls;        /* in the queue now */
    uint32_t missing_components; /* o_i not enclosed by the mesh (H2 fails for them) */
    uint32_t records, free_edges, facet_records;
    size_t arena_peak;
} vp_planner_stats_t;

/* Internal records, declared for sizing only. */
typedef struct vp_vrec vp_vrec_t;
typedef struct vp_frec vp_frec_t;
typedef struct vp_task {
    uint32_t tet;
    uint8_t facet, kind;
    uint16_t tries;
    uint32_t proof;    /* with off > 0: the proof of the ray's last free piece */
    double off;        /* already proven free from the origin (a range-limited probe) */
} vp_task_t;

/* A proof of free space: the free part of one probe, [o, o + len * d] (d unit), and the proof
 * of the piece before it on the same ray (a range-limited probe walked on), or none. */
typedef struct vp_proof {
    double o[3], d[3], len;
    uint32_t prev;
} vp_proof_t;

typedef struct vp_planner {
    vp_planner_config_t cfg;
    vp_dt_t dt;
    unsigned char *arena;
    size_t arena_bytes;
    /* pools carved from the arena */
    vp_vrec_t *vrec; uint32_t nvrec, cap_vrec;
    uint32_t *fedge; uint32_t nfedge, cap_fedge;     /* 4 words: a, b, next_a, next_b */
    vp_frec_t *frec; uint32_t nfrec, cap_frec, frec_free, nfacets;
    uint32_t *fhash; uint32_t hash_mask, ntomb;       /* facet key -> frec index */
    int fhash_dirty;
    uint32_t *heap; uint32_t nheap, cap_heap;         /* bad balls, max-heap on radius */
    vp_task_t *task; uint32_t ntask, cap_task;        /* pending probes (a stack) */
    uint32_t *path; uint32_t npath, cap_path, ipath;  /* current route: waypoint records */
    double *route; uint32_t nroute, iroute, cap_route;/* current route as points */
    uint32_t *route_proof;                            /* each route step's proof of freedom */
    vp_proof_t *proof; uint32_t nproof, cap_proof;    /* free parts of probes, as proven */
    uint32_t cur_proof;      /* the proof made from the current probe's result (or none) */
    uint32_t chain_proof;    /* the current probe continues this proof's ray (or none) */
    double iss_o[3], iss_d[3], iss_range; /* the PROBE issued last */
    double ptol;             /* slack of a proof check (rounding of constructed points) */
    uint64_t close_mark;     /* probes + insertions + 1 when holes were last closed */
    uint32_t *astar; uint32_t cap_astar;              /* scratch of the path search */
    /* state machine */
    int phase;
    int awaiting;            /* 1: a PROBE was issued, feed() expected */
    uint32_t at;             /* record the device stands at (VP_DT_NONE between) */
    double pos[3];
    uint32_t seed, seed_step, seed_try;
    uint32_t seed_miss;      /* misses of the current seed probe (dropouts are re-probed) */
    double seed_pts[4 * VP_PLANNER_MAX_SEEDS][3];
    uint32_t nseed_pts;
    double seed_q[3], seed_dir[3];
    double probe_origin[3], probe_dir[3], probe_range, probe_full;
    double standoff;         /* distance from the probe origin to the edge's vertex (body mode) */
    int probe_ready;         /* a probe is prepared: issue it once the route is done */
    uint32_t probe_origin_rec, misses_in_row;
    uint32_t route_from;     /* where the current route starts */
    uint32_t shortcut, sc_from, sc_tries; /* a straight shortcut being probed */
    int sc_pending;          /* 1: to issue, 2: issued */
    int route_deferred;      /* the route waits for the shortcut probe's answer */
    uint32_t stamp;
    uint32_t last_vertex;
    uint32_t peak_task, peak_heap, peak_route, peak_astar, peak_path; /* high-water marks */
    int error;
    int exhaustive;          /* detect_access in full until the next insertion (closing) */
    double sin_angle;        /* sin of the angle bound (0: none) */
    uint32_t h2_done;        /* bit i: o_i is enclosed by the mesh */
    uint8_t h2_tries[VP_PLANNER_MAX_SEEDS];
    uint32_t reseed;
    vp_task_t curtask;       /* the probe being carried out */
    vp_planner_stats_t st;
} vp_planner_t;

/* Checks the configuration (VP_EINVAL: bad Omega, eps <= 0 or NaN, no interior point, an
 * interior point or the start outside its place; VP_ENOMEM: arena too small) and prepares a
 * session. Nothing is probed before the first vp_planner_next(). */
int vp_planner_init(vp_planner_t *pl, void *arena, size_t bytes, const vp_planner_config_t *cfg);

/* The next command. VP_OK with cmd filled; VP_ESTATE if a PROBE result is still owed;
 * VP_ENOMEM when the arena is full (the mesh so far stays exportable); VP_ERANGE when an
 * interior point turned out not to be inside the object. */
int vp_planner_next(vp_planner_t *pl, vp_cmd_t *cmd);

/* The result of the last PROBE. VP_EINVAL for NaN or a negative distance (nothing changes). */
int vp_planner_feed(vp_planner_t *pl, const vp_probe_result_t *res);

/* The mesh: restricted facets with their vertices (indices into vp_planner_dt()), oriented with
 * the normal (b-a)x(c-a) pointing out of the object. vp_planner_facet returns the ball radius
 * through *radius (may be NULL). Iterate i < vp_planner_facet_slots(). Returns 1 for a facet,
 * 0 for an empty slot. */
uint32_t vp_planner_facet_slots(const vp_planner_t *pl);
int vp_planner_facet(const vp_planner_t *pl, uint32_t i, uint32_t v[3], double *radius,
                     double center[3]);
uint32_t vp_planner_num_facets(const vp_planner_t *pl);
const vp_dt_t *vp_planner_dt(const vp_planner_t *pl);
void vp_planner_get_stats(const vp_planner_t *pl, vp_planner_stats_t *st);

#endif
