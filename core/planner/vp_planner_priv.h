/* vp_planner_priv.h — the planner's private header: shared by the files of core/planner/ and
 * by tests/test_planner_parts.c, not for use outside (like lwIP's tcp_priv.h). The public API
 * is core/vp_planner.h.
 *
 * The probe planner of "Learning smooth objects by probing" (Boissonnat, Guibas, Oudot, SoCG
 * 2005; ../shared/papers/000_probing_smooth_objects.txt), made step-driven.
 *
 * Vocabulary (the paper's):
 *   Voronoi vertex    the circumcentre of a Delaunay tet (its dual); ghost tets stand for the
 *                     infinite vertices.
 *   active vertex     one the device can reach: it has a free path (prev links) to R^3 \ Omega.
 *                     Active vertices inside Omega get a record (vrec) that is kept after the
 *                     tet dies ("former Voronoi vertices"), so every stored path stays valid.
 *   detect_access     probing the Voronoi edges around an active vertex: a hit adds the dual
 *                     facet to Del_v|S(E) with its ball; a miss proves the edge free and makes
 *                     the other end active. Here it is a stack of probe tasks, not a recursion.
 *   bad ball          a surface Delaunay ball of radius > eps; the largest is refined first
 *                     (VP_PLAN_LARGEST) or the largest near the device.
 *   persistent facet  the tiny seed triangle: its ball (<= eps/3) keeps Del_v|S non-empty.
 *
 * Beyond the paper: a probe result belongs to the side it was probed from (one status per
 * (tet, facet) side); a facet on the boundary of an insertion's cavity keeps its result when its
 * shortened Voronoi edge still holds it; without VP_PLAN_PAPER an edge between two vertices
 * already known free is not probed (it cannot be a facet of the final mesh, whose dual edges
 * cross S once); holes left at the end are closed by probing around them; motion follows
 * shortest known-free paths (A*) instead of prev chains.
 */
#ifndef VP_PLANNER_PRIV_H
#define VP_PLANNER_PRIV_H

#include <math.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_pred.h"
#include "vp_vec3.h"

#define NONE VP_DT_NONE
#define VREC_OUT 0xFFFFFFFEu /* active, outside Omega or infinite: no record needed */

/* side status of a (tet, facet) pair, low 2 bits */
#define SIDE_UNKNOWN 0u
#define SIDE_FREE    1u  /* the whole dual edge is free */
#define SIDE_HIT     2u  /* probed from this side: free up to the ball centre (facet record) */
#define SIDE_BEHIND  3u  /* probed from the other side and hit: this end is beyond S */
#define SIDE_MASK    3u
#define SIDE_QUEUED  4u  /* a probe task is pending */
#define SIDE_FORCED  8u  /* probed although both ends are known free (closing a hole) */
#define SIDE_BLOCKED 16u /* not probed again from this end: too close to measure, occluded from
                           dOmega (a device with a body), or degenerate (with SIDE_DEGEN) */
#define SIDE_DEGEN   32u /* blocked because the edge is degenerate, not because it is unseen */
#define SIDE_CUT     64u /* on all four sides: an inside tet cut off at a pinch (close.c) */
#define SIDE_RETRIED 128u /* with tubes: a side left unseen, probed once more while closing holes */

/* record flags */
#define REC_OUT 1u       /* on or outside dOmega: joins every other such record outside */
#define REC_LOST 2u      /* no longer joined to the outside by proofs that stand (contact.c):
                            its prev chain is not a way */

/* a sample's aux word (its vp_dt vertex record): bit 31, its normal estimate in pool.nrm is
 * valid (facets.c); bit 30, a re-scan measures it from inside Omega, in its second pass; bit 29,
 * the re-scan's current pass has taken it; bit 28, a sparse re-scan leaves it unmeasured while
 * its neighbours hold; bits 0-27, 1 + the proof of the probe that found it (0: none; rescan.c) */
#define AUX_NRM 0x80000000u
#define AUX_DEFER 0x40000000u
#define AUX_TAKEN 0x20000000u
#define AUX_SKIP 0x10000000u
#define AUX_PROOF 0x0FFFFFFFu

/* facet record flags */
#define FREC_FLIP 1u     /* (v0,v1,v2) is oriented inward: swap two for output */
#define FREC_STUCK 2u    /* its centre could not be inserted: not refined again */
#define FREC_DOUBLE 4u   /* hit from both ends: the dual edge crosses S twice */
#define FREC_CUT 8u      /* no probed ball: a facet of a tet cut off at a pinch (close.c); its
                            ball is its circumball, never refined */
#define FREC_OUTOUT 16u  /* both its tets outside at the last closing pass (close.c) */
#define FREC_NOTMESH (FREC_DOUBLE | FREC_OUTOUT) /* between two outside tets: not in the mesh */

/* VP_PL_PHASES — the planner's state machine, in one place (planner.c runs it).
 *
 * Each vp_planner_next() issues the first of these that applies (the "issue order"):
 *
 *   1. route.i < route.n     MOVE to the next route point; its proof is checked again first
 *   2. sc.pending == 1       PROBE the straight way sc.from -> sc.to    (sc.pending = 2)
 *   3. probe.ready           PROBE the prepared probe                   (probe.ready = 0)
 *   4. otherwise             one step of the phase machine below; loop (bounded: VP_ESTALL)
 *
 * A PROBE sets dev.awaiting; vp_planner_feed() takes its answer, routed by the same state:
 * sc.pending == 2 -> shortcut_feed, PH_SEED -> seed_feed, PH_RESEED -> reseed_feed, else
 * task_finish. While a shortcut is pending the route is held (route.i = route.n); with
 * route.deferred its search runs only if the straight probe hits.
 *
 *   PH_SEED        seed_next: per o_i, the persistent facet and a fourth point;
 *                  all found: start_run (insert them, explore the outside) ------> PH_RUN
 *   PH_RUN         a bad ball (not exhaustive, no walked ray in progress): refine
 *                  else a task: task_start prepares its probe (or settles the side)
 *                  else a bad ball: refine
 *                  else ------------------------------------------------------> PH_CLOSE
 *   PH_CLOSE       close_holes queued probes ----------------------------------> PH_RUN
 *                  none, or nothing probed or inserted since the last try ----> PH_COMPONENTS
 *   PH_COMPONENTS  every o_i enclosed by the mesh (H2) ------------------------> PH_DONE
 *                  o_i missed: route to dOmega, probe towards o_i ------------> PH_RESEED
 *   PH_RESEED      (feed) a hit, inserted -------------------------------------> PH_RUN
 *                  a miss the rangefinder's reach cut short: walk on ---------> PH_RESEED
 *                  otherwise ---------------------------------------------------> PH_COMPONENTS
 *   PH_DONE        DONE at every call
 *   PH_VERIFY      a re-scan (vp_planner_rescan): each sample of the session so far measured
 *                  again from outside Omega, kept or removed ---------------------> PH_RUN
 * With a re-scan, a route step on a proof from before it is probed first (issue order 1 is
 * then a PROBE; vp_planner_feed -> reprove_feed before anything else).
 *
 * close.exhaustive: set by close_holes when no active vertex borders a hole; cleared by the
 * next insertion. close.mark: probes + insertions + 1 when holes were last closed. */
enum { PH_SEED = 0, PH_RUN, PH_CLOSE, PH_COMPONENTS, PH_RESEED, PH_DONE, PH_VERIFY };

struct vp_vrec {
    double p[3];
    double g, f;       /* path search: cost so far, and plus the straight distance left */
    uint32_t prev;     /* previous record on the free path (itself: a root, outside Omega) */
    uint32_t adj;      /* first free edge at this record */
    uint32_t depth;    /* hops to the root */
    uint32_t flags;
    uint32_t stamp, from; /* path search bookkeeping */
    uint32_t hpos;        /* place in the search's open heap, NONE when closed */
    uint32_t proof;       /* the proof that the segment from prev to here is free */
};

struct vp_frec {
    uint32_t v[3];     /* sorted; v[0] == NONE: free slot, v[1] = next free */
    uint32_t heap;     /* index in the bad-ball heap or NONE */
    uint32_t flags;
    uint32_t hint;     /* a tet that had the facet (checked before use) */
    double c[3];       /* ball centre (the hit) */
    double r;          /* ball radius */
    double key;        /* the heap's order: r, or r / g(c) with the sizing field (bad above 1) */
    uint32_t proof;    /* the probe that found the ball: free up to its centre, less the noise */
    uint32_t rated;    /* the size pass's epoch when it was last rated (facets.c) */
};

/* VP_PL_API marks a function shared by the files of core/planner/: external by default (each
 * file is compiled and testable alone); a build that compiles the planner as one unit
 * (core/planner/unity/vp_planner_unity.c, like SQLite's amalgamation and its SQLITE_PRIVATE)
 * defines it as static so the compiler may inline a function into its only caller. */
#ifndef VP_PL_API
#define VP_PL_API
#endif

/* ---------- shared constants and types ---------- */

/* VP_PL_SCRATCH: pool.astar (cap_astar words) is scratch with one owner at a time, never kept
 * across a command:
 *   astar_path (route.c)      the search's open heap, for one route;
 *   after_insert (update.c)   the killed tets' payloads, for one insertion's update;
 *   find_facet (update.c)     the tets around a vertex, after the words its caller holds;
 *   nearest_sample (update.c) the tets whose circumspheres hold a point, for the refinement of
 *                             a ball found from aside or a sample seen from elsewhere;
 *   close_holes (close.c)     the edge-count table (3 words a slot) at the front, held while
 *                             it calls find_facet, which then lists after it (held = 3 slots).
 * None of them calls another of them but close_holes -> find_facet. */

/* Tolerances, relative. LEN_REL_EPS: two lengths closer than this times (1 + the length) are
 * one (a dozen roundings of 2.2e-16 each, with a wide margin); a segment inside Omega for less
 * than that only touches it. DIR_COS_EPS: unit directions whose dot product is above 1 - this
 * are one ray (the pieces of a walked ray, rounded). VP_PL_HUGE: a length or cost nothing
 * reaches (unbounded, without infinities). */
#define LEN_REL_EPS 1e-12
#define DIR_COS_EPS 1e-12
#define VP_PL_HUGE 1e300

/* VP_PL_CONTACTS: the contact safety net (contact.c) is built. A microcontroller core
 * (VP_CORE_MCU) leaves it out, and with it every test for a withdrawn proof or a lost record:
 * none can occur there (its scanner has no contact switch). */
#ifndef VP_CORE_MCU
#define VP_PL_CONTACTS 1
#else
#define VP_PL_CONTACTS 0
#endif
/* VP_PL_LINE_LASER: a line laser's more rays per frame are taken (vp_planner_feed_ray); a
 * microcontroller core leaves them out (its flash budget). */
#define VP_PL_LINE_LASER VP_PL_CONTACTS

/* VP_PL_TUBES: travel inside Omega with a body through tubes proven free (tube.c); a
 * microcontroller core leaves it out (its RAM: the grid of marks). */
#define VP_PL_TUBES VP_PL_CONTACTS

/* VP_PL_TIMED: body mode weighs the head's moves by the axes' speeds (axis_time: route.c's way
 * round Omega, the nearest task); a microcontroller core leaves it out (its flash budget). */
#define VP_PL_TIMED VP_PL_CONTACTS

/* plan_route: no way known to the goal (a contact withdrew the proofs of every way there) */
#define PL_UNREACHABLE 1
#define PROOF_NONE      0xFFFFFFFFu
#define PROOF_OUTSIDE   0xFFFFFFFDu
#define PROOF_TUBE      0xFFFFFFFCu /* a tube proven free inside Omega (tube.c) */
#define FEDGE_WORDS 5u
#define KPAY 6u /* payload words of a tet: record, sides, four side proofs */
/* Headroom of one insertion's update (vp_pl_pools_have_room): pool.room entries of facets,
 * tasks, heap and hash, twice that of records and free edges. ROOM_SMALL from SMALL_ARENA up;
 * below it one per ROOM_BYTES of arena (32 at the least arena, 50 at 100 KiB), as a small arena
 * never has 256 to spare. One update is bounded by its cavity (at most one record and one facet,
 * four tasks and free edges per new tet). Measured per refinement step: up to 102 tasks, 52
 * records, 88 free edges in sessions of thousands of vertices (fandisk at accuracy 0.005, a
 * cavity of 214 tets); in the 15 scans of up to 150 vertices a small arena holds (spheres, tori,
 * blobs, cube, tetra, fandisk, knot, with noise and dropouts) up to 26 tasks, 15 records and 20
 * free edges (cavities of at most 56 tets): at 100 KiB pool.room is nearly twice the largest. */
#define ROOM_SMALL 256u
#define SMALL_ARENA (512u * 1024u)
#define ROOM_BYTES 2048u
/* The manifold criterion's floor with a distance bound (close.c), and how far a facet whose
 * Voronoi edge crosses S twice is refined (facets.c): this share of the bound's floor min_size,
 * so that a fin or a gap thinner than the floor is still resolved. */
#define MANIFOLD_FLOOR_MIN 0.05
#define PROOF_SHARE 16u /* of the arena's 100 units: the proofs (one per probe that proved something) */
#define HASH_EMPTY 0xFFFFFFFFu
typedef struct edgegeom {
    double a[3], dir[3]; /* from the tet's end towards the neighbour's end */
    double len;          /* to the neighbour's end (huge for an infinite end) */
    double t0, t1;       /* the part inside Omega; t0 >= t1: none */
    int a_inside;        /* the tet's own end lies inside Omega */
} edgegeom_t;

/* ---------- tet payload: word 0 = record, word 1 = four side bytes, words 2-5 the proof of
 * each free side ---------- */

static inline uint32_t *pay(const vp_planner_t *pl, uint32_t t) { return (uint32_t *)vp_dt_payload(&pl->dt, t); }

/* ---------- the tets around an edge of Del(E) ---------- */

#define RING_MAX 4096u /* tets turned around one edge at most: a ring has some 5; this only
                         stops a walk on a broken ring */

/* Turning around edge (x, y) of Del(E), tet by tet: ring_start puts the walk at t0 (0: t0 does
 * not hold the edge); ring_step moves to the next tet of the ring, 0 when back at t0 or when the
 * ring is broken (*broken then set). */
typedef struct ring { uint32_t t0, cur, other, x, y, left; } ring_t;

static inline int ring_start(const vp_planner_t *pl, ring_t *r, uint32_t t0, uint32_t x, uint32_t y)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t0);
    int k;
    r->t0 = r->cur = t0;
    r->x = x;
    r->y = y;
    r->left = RING_MAX;
    for (k = 0; k < 4; k++)
        if (w[k] != x && w[k] != y) { r->other = w[k]; return 1; }
    return 0;
}

static inline int ring_step(const vp_planner_t *pl, ring_t *r, int *broken)
{
    const uint32_t *c = vp_dt_tet(&pl->dt, r->cur);
    int k, ix = -1;
    for (k = 0; k < 4; k++)
        if (c[k] == r->other) ix = k;
    if (ix < 0) { *broken = 1; return 0; }
    for (k = 0; k < 4; k++)
        if (c[k] != r->x && c[k] != r->y && c[k] != r->other) break;
    r->cur = c[4 + ix] >> 2;
    r->other = c[k];
    return r->cur != r->t0 && --r->left;
}

static inline uint32_t tet_rec(const vp_planner_t *pl, uint32_t t) { return pay(pl, t)[0]; }
static inline unsigned side_get(const vp_planner_t *pl, uint32_t t, int f)
{ return (pay(pl, t)[1] >> (8 * f)) & 0xFFu; }
static inline void side_set(vp_planner_t *pl, uint32_t t, int f, unsigned s)
{
    uint32_t *w = pay(pl, t) + 1;
    *w = (*w & ~(0xFFu << (8 * f))) | ((uint32_t)(s & 0xFFu) << (8 * f));
}
static inline int tet_active(const vp_planner_t *pl, uint32_t t) { return tet_rec(pl, t) != NONE; }
/* 1 if facet record f is a facet of the mesh: live, and between the outside and the inside */
static inline int frec_in_mesh(const vp_frec_t *f) { return f->v[0] != NONE && !(f->flags & FREC_NOTMESH); }
/* side f of t (its whole Voronoi edge) proven free by `proof`; other flags kept */
static inline void side_free(vp_planner_t *pl, uint32_t t, int f, uint32_t proof)
{
    side_set(pl, t, f, (side_get(pl, t, f) & ~SIDE_MASK) | SIDE_FREE);
    pay(pl, t)[2 + f] = proof;
}
static inline uint32_t side_proof(const vp_planner_t *pl, uint32_t t, int f) { return pay(pl, t)[2 + f]; }

/* contact.c */
#if VP_PL_CONTACTS
VP_PL_API int vp_pl_contact_distrusts(const vp_planner_t *pl, const double *o, const double *d, double len);
#endif

#if VP_PL_CONTACTS
VP_PL_API int vp_pl_withdraw_at(vp_planner_t *pl, const double *h, uint32_t old);
VP_PL_API uint32_t vp_pl_rec_at(const vp_planner_t *pl, const double *p);
#endif

/* rescan.c */
#if VP_PL_CONTACTS
VP_PL_API int vp_pl_step_stale(const vp_planner_t *pl);
VP_PL_API int vp_pl_reprove_dir(vp_planner_t *pl, double *d, double *range);
VP_PL_API int vp_pl_reprove_feed(vp_planner_t *pl, const vp_probe_result_t *res);
VP_PL_API int vp_pl_verify_next(vp_planner_t *pl);
VP_PL_API int vp_pl_verify_feed(vp_planner_t *pl, const vp_probe_result_t *res);
VP_PL_API int vp_pl_remove_doomed(vp_planner_t *pl);
VP_PL_API int vp_pl_rescan_pending(vp_planner_t *pl);
#endif

/* proof.c */
#if VP_PL_CONTACTS
VP_PL_API int vp_pl_proof_add(vp_planner_t *pl, const double *o, const double *d, double len, uint32_t *out);
#endif
VP_PL_API int vp_pl_probe_proof(vp_planner_t *pl, const vp_probe_result_t *res, uint32_t *out);
VP_PL_API int vp_pl_proof_covers(const vp_planner_t *pl, uint32_t id, const double *a, const double *b);

/* route.c */
VP_PL_API double vp_pl_clamp_range(const vp_planner_t *pl, double range);
VP_PL_API int vp_pl_edge_add(vp_planner_t *pl, uint32_t a, uint32_t b, uint32_t proof);
VP_PL_API void vp_pl_omega_center(const vp_planner_config_t *c, double *o);
VP_PL_API double vp_pl_omega_circumradius(const vp_planner_config_t *c);
VP_PL_API int vp_pl_omega_clip(const vp_planner_config_t *c, const double *a, const double *dir, double len,
                               double *t0, double *t1);
VP_PL_API int vp_pl_omega_inside(const vp_planner_config_t *c, const double *p);
VP_PL_API int vp_pl_plan_route(vp_planner_t *pl, uint32_t b, const double *gp);
VP_PL_API int vp_pl_probe_limited(const vp_planner_t *pl);
VP_PL_API int vp_pl_rec_link(vp_planner_t *pl, const double *p, uint32_t prev, uint32_t flags, uint32_t proof,
                             uint32_t *out);
VP_PL_API int vp_pl_rec_new(vp_planner_t *pl, const double *p, uint32_t prev, uint32_t flags, uint32_t *out);
VP_PL_API int vp_pl_route_full(vp_planner_t *pl, uint32_t a, uint32_t b);
VP_PL_API int vp_pl_route_push(vp_planner_t *pl, const double *p, uint32_t proof);
#if VP_PL_TIMED
VP_PL_API int vp_pl_timed(const vp_planner_t *pl);
VP_PL_API double vp_pl_move_time(const vp_planner_t *pl, const double *a, const double *b);
VP_PL_API double vp_pl_pan_for(const vp_planner_t *pl, const double *dir);
VP_PL_API void vp_pl_pan_aim(vp_planner_t *pl, const double *dir);
VP_PL_API double vp_pl_way_time(const vp_planner_t *pl, const double *o, const double *dir);
VP_PL_API double vp_pl_start_back(const vp_planner_t *pl, const double *o, const double *dir, double most);
#endif
#if VP_PL_CONTACTS
VP_PL_API int vp_pl_route_outside(vp_planner_t *pl, const double *q);
#endif
VP_PL_API int vp_pl_seg_enters_omega(const vp_planner_config_t *c, const double *a, const double *b);
#if VP_PL_TUBES
VP_PL_API double vp_pl_tube_way_out(vp_planner_t *pl, const double *to);
#endif
VP_PL_API int vp_pl_walk_on(vp_planner_t *pl, uint32_t from, uint32_t proof, double e[3]);

/* facets.c */
VP_PL_API void vp_pl_fhash_rebuild(vp_planner_t *pl);
VP_PL_API int vp_pl_frec_add(vp_planner_t *pl, const uint32_t *fv, const double *c, const double *outside,
                             uint32_t tet, uint32_t proof, uint32_t *out);
VP_PL_API void vp_pl_frec_delete(vp_planner_t *pl, uint32_t k);
VP_PL_API uint32_t vp_pl_frec_lookup(const vp_planner_t *pl, const uint32_t *fv);
VP_PL_API int vp_pl_facet_circumcenter(const vp_planner_t *pl, const uint32_t *fv, double *m);
VP_PL_API void vp_pl_cut_reached(vp_planner_t *pl, uint32_t t);
VP_PL_API int vp_pl_frec_add_cut(vp_planner_t *pl, const uint32_t *fv, const double *outside, uint32_t tet, uint32_t *out);
VP_PL_API void vp_pl_frec_set_ball(vp_planner_t *pl, uint32_t k, const double *c);
VP_PL_API void vp_pl_heap_remove(vp_planner_t *pl, uint32_t k);
VP_PL_API int vp_pl_heap_push(vp_planner_t *pl, uint32_t k);
VP_PL_API double vp_pl_size_bound(vp_planner_t *pl, const uint32_t *v, const double *c);
VP_PL_API int vp_pl_facet_rate(vp_planner_t *pl, vp_frec_t *f, int at_pass);
VP_PL_API int vp_pl_size_pass(vp_planner_t *pl);
VP_PL_API void vp_pl_sample_touch(vp_planner_t *pl, uint32_t v);

/* tasks.c */
VP_PL_API int vp_pl_edge_geom(const vp_planner_t *pl, uint32_t t, int f, edgegeom_t *g);
VP_PL_API int vp_pl_exhaustive(const vp_planner_t *pl);
VP_PL_API int vp_pl_explore(vp_planner_t *pl, uint32_t t);
VP_PL_API int vp_pl_facet_has_ghost(const vp_planner_t *pl, uint32_t t, int f);
VP_PL_API void vp_pl_task_compact(vp_planner_t *pl);
#if VP_PL_CONTACTS
VP_PL_API void vp_pl_probe_drop(vp_planner_t *pl);
#endif
VP_PL_API int vp_pl_side_hit(vp_planner_t *pl, uint32_t t, int f, const double *h, const double *outside, uint32_t pf,
                             uint32_t *rec);
VP_PL_API int vp_pl_task_finish(vp_planner_t *pl, const vp_probe_result_t *res);
VP_PL_API int vp_pl_tet_reached(vp_planner_t *pl, uint32_t u, uint32_t proof);
VP_PL_API int vp_pl_task_push(vp_planner_t *pl, uint32_t t, int f, int forced);
VP_PL_API int vp_pl_task_start(vp_planner_t *pl, vp_task_t *k);
#ifndef VP_CORE_MCU
VP_PL_API int vp_pl_task_origin(const vp_planner_t *pl, const vp_task_t *k, double *o);
VP_PL_API void vp_pl_task_nearest_on_top(vp_planner_t *pl);
VP_PL_API void vp_pl_task_small_on_top(vp_planner_t *pl);
#endif
VP_PL_API int vp_pl_tet_point(const vp_planner_t *pl, uint32_t t, double *p);
#if VP_PL_CONTACTS || VP_PL_LINE_LASER
VP_PL_API int vp_pl_sample_insert(vp_planner_t *pl, const double h[3], uint32_t hint, double sp, uint32_t *vout);
#endif

/* update.c */
VP_PL_API int vp_pl_after_insert(vp_planner_t *pl, uint32_t pv);
#if VP_PL_LINE_LASER
VP_PL_API int vp_pl_ray_sample(vp_planner_t *pl);
#endif
VP_PL_API uint32_t vp_pl_find_facet(vp_planner_t *pl, const uint32_t *fv, int *fi, uint32_t held);
VP_PL_API int vp_pl_incident(vp_planner_t *pl, uint32_t v, uint32_t held, uint32_t **inc);
VP_PL_API int vp_pl_pools_have_room(const vp_planner_t *pl);
VP_PL_API int vp_pl_refine(vp_planner_t *pl);
#if VP_PL_CONTACTS
VP_PL_API int vp_pl_nearest_sample(vp_planner_t *pl, const double h[3], uint32_t t0, double *near2);
#endif

/* close.c */
VP_PL_API int vp_pl_check_components(vp_planner_t *pl);
VP_PL_API void vp_pl_reseed_dir(uint32_t attempt, double *d);
VP_PL_API int vp_pl_close_holes(vp_planner_t *pl, int refine_only);
VP_PL_API int vp_pl_reseed_feed(vp_planner_t *pl, const vp_probe_result_t *res);
VP_PL_API int vp_pl_cut_keeps_topology(const vp_planner_t *pl, uint32_t t);
/* 1 when tet t has a vertex in the sorted list vs[0 .. n) */
VP_PL_API int vp_pl_has_vertex_in(const vp_planner_t *pl, uint32_t t, const uint32_t *vs, uint32_t n);
#if VP_PL_TUBES
/* Body mode's detect_access from the holes alone: the vertices of the edge table's odd edges
 * (3 words per slot: a, b, facets; NONE empty), sorted, once each, into the scratch past the
 * table (pool.astar + 3 slots); their number, or NONE past HOLE_VERTICES_MAX or the scratch */
#define HOLE_VERTICES_MAX 4096u
VP_PL_API uint32_t vp_pl_hole_vertices(const vp_planner_t *pl, const uint32_t *tab, uint32_t slots);
/* Closing's last resort: the sides round the table's odd edges left unseen after one more try
 * (BLOCKED and RETRIED), whose edge ends at its far vertex in Omega, queued again with lines
 * through that vertex too; the number queued, or a negative status */
VP_PL_API int vp_pl_aim_far_vertices(vp_planner_t *pl, const uint32_t *tab, uint32_t slots);
#endif

/* seed.c */
VP_PL_API double vp_pl_omega_exit(const vp_planner_config_t *c, const double *p, const double *u);
VP_PL_API int vp_pl_seed_feed(vp_planner_t *pl, const vp_probe_result_t *res_in);
VP_PL_API int vp_pl_seed_issue(vp_planner_t *pl, const double *dir, double range);
VP_PL_API int vp_pl_seed_miss_on(vp_planner_t *pl);
VP_PL_API int vp_pl_seed_next(vp_planner_t *pl);
VP_PL_API int vp_pl_start_run(vp_planner_t *pl);

/* tube.c */
#if VP_PL_TUBES
VP_PL_API double vp_pl_seg_dist2(const double *a, const double *d, double len2, const double *p);
VP_PL_API size_t vp_pl_tube_plan(const vp_planner_config_t *c, double ptol, size_t budget, vp_pl_tube_t *T);
VP_PL_API void vp_pl_tube_mark(vp_planner_t *pl, const double *o, const double *d, double len);
VP_PL_API int vp_pl_tube_free(const vp_planner_t *pl, const double *a, const double *b);
VP_PL_API uint32_t vp_pl_tube_unexplored(const vp_planner_t *pl, const double *a, const double *b);
VP_PL_API void vp_pl_tube_off(vp_planner_t *pl);
VP_PL_API void vp_pl_survey_start(vp_planner_t *pl, const double *x, const double *u, double s);
VP_PL_API int vp_pl_survey_next(vp_planner_t *pl);
VP_PL_API int vp_pl_survey_feed(vp_planner_t *pl, const vp_probe_result_t *res);
VP_PL_API int vp_pl_vantage_go(vp_planner_t *pl, const double *x, double s, const double *e);
VP_PL_API int vp_pl_vantage_unseen(vp_planner_t *pl);
#endif

/* aim.c */
#if VP_PL_CONTACTS
VP_PL_API int vp_pl_aim_start(vp_planner_t *pl, const vp_task_t *k, const double *out);
VP_PL_API int vp_pl_aim_feed(vp_planner_t *pl, const vp_probe_result_t *res);
VP_PL_API void vp_pl_aim_last_resort(vp_planner_t *pl, uint32_t sides);
VP_PL_API int vp_pl_aim_read(const vp_planner_t *pl, uint32_t k, double *h);
#endif

/* planner.c */
VP_PL_API void vp_pl_note_peak(vp_planner_t *pl);

#endif
