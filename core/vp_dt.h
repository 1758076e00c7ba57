/* vp_dt — incremental 3D Delaunay triangulation in a caller-given arena.
 *
 * Memory: one block (pointer + size) handed over by vp_dt_init. Tetrahedra are flat records
 * growing up from the bottom of the block: 4 vertex indices, 4 neighbour references
 * (4 * tet + facet), then `payload` bytes the caller owns (the planner keeps its Voronoi-vertex
 * state there; the triangulation never reads or writes them). Vertex records (x, y, z, one
 * incident tet) grow down from the top. The free space between the two is the scratch of the
 * current insertion. No pointers are stored, only indices, so the block can be saved and moved.
 *
 * The convex hull is closed by one infinite vertex VP_DT_GHOST, always in slot 3 of a hull
 * ("ghost") tet, so every tet has four neighbours and the hull needs no special cases.
 *
 * Conventions: facet i of a tet is the triangle opposite vertex i. For a finite tet
 * (v0,v1,v2,v3), vp_orient3d(v0,v1,v2,v3) > 0. A ghost tet (a,b,c,GHOST) has its hull facet
 * (a,b,c) oriented so that the inside of the hull is on its negative side.
 * Geometry decisions are exact (vp_pred); cospherical and coplanar input is resolved by the
 * symbolic perturbation of vp_insphere_sos, so every point set has one triangulation.
 *
 * Errors: every fallible call returns VP_OK (0) or a negative VP_E* status and leaves the
 * triangulation unchanged and valid.
 *
 * Vertex records are never renumbered: a removed vertex (vp_dt_remove) keeps its record, with
 * `tet` VP_DT_NONE, and a point inserted later gets a new record.
 */
#ifndef VP_DT_H
#define VP_DT_H

#include <stddef.h>
#include <stdint.h>
#include "vp_status.h"

#define VP_DT_GHOST 0x3FFFFFFFu /* the infinite vertex */
#define VP_DT_NONE  0xFFFFFFFFu /* no tet / no vertex */
#define VP_DT_PENDING 0xFFFFFFFDu /* vertex record's tet while the set is flat (dim < 3) */
#define VP_DT_MAX_VERTICES 0x3FFFFFF0u
#define VP_DT_LOWBIT_NONE 100000   /* lowbit before any nonzero coordinate */
#define VP_DT_LOWBIT_OFF (-100000) /* lowbit no longer tracked */

/* One vertex record: 32 bytes. */
typedef struct vp_dt_vertex {
    double xyz[3];
    uint32_t tet;   /* one tet containing the vertex; VP_DT_PENDING while the set is still flat
                     * (dim < 3: the vertex waits for the first tet); VP_DT_NONE when it is not
                     * in the set (removed, or a record being inserted); other values above
                     * VP_DT_MAX_VERTICES: a duplicate record of a batch, never inserted */
    uint32_t aux;   /* free for the caller (the triangulation never reads it) */
} vp_dt_vertex_t;

typedef struct vp_dt {
    unsigned char *mem_lo, *mem_hi;  /* the arena */
    uint32_t *tets;                  /* tet records from mem_lo upward */
    vp_dt_vertex_t *vtop;            /* vertex i is vtop[-(ptrdiff_t)i] */
    uint32_t stride;                 /* words per tet record: 8 + payload words */
    uint32_t ntet_slots;             /* tet records ever used (alive + free) */
    uint32_t nfree, free_head;       /* dead tets, chained through word 4 */
    uint32_t nalive, nghost;         /* alive tets, of which ghost tets */
    uint32_t nvert;                  /* vertex records (inserted, pending, removed or duplicate) */
    uint32_t ninserted;              /* vertices that are in the triangulation */
    uint32_t last_tet;               /* a recently created tet: default start of walks */
    uint32_t nkilled, ncreated;      /* the last insertion's or removal's lists, vp_dt_last_* */
    uint32_t *killed, *created;      /* point into the scratch space */
    uint32_t *killed_verts;          /* 4 vertices of each killed tet, as they were */
    uint32_t *created_from;          /* per created tet: 4 * killed tet + facet of its boundary facet */
    uint32_t rng;                    /* walk randomisation (a local LCG, deterministic) */
    int dim;                         /* -1 empty, 0..2 pending (flat so far), 3 tetrahedralised */
    uint32_t span[4];                /* pending mode: vertices spanning the current dimension */
    double box_lo[3], box_hi[3];     /* bounding box of every vertex record ever appended */
    double sbound_o3, sbound_is;     /* static filter bounds for that box (vp_pred.h); 0 when
                                      * the box and lowbit make the filters exact */
    int lowbit;                      /* every coordinate so far is a multiple of 2^lowbit;
                                      * VP_DT_LOWBIT_OFF once that can no longer help */
    size_t high_water;               /* most bytes of the arena ever in use */
    uint64_t walk_steps;             /* statistics: tets visited by walks */
} vp_dt_t;

/* Prepares an empty triangulation in mem[0..bytes). payload_bytes per tet (rounded up to 4)
 * are reserved for the caller. VP_EINVAL if mem is NULL or too small for anything. */
int vp_dt_init(vp_dt_t *dt, void *mem, size_t bytes, size_t payload_bytes);

/* Inserts p. Walks from tet `hint` (VP_DT_NONE: the last created tet) to the tet containing p.
 * *vertex receives the new vertex index, or for VP_EDUP the existing vertex at p.
 * VP_EINVAL for NaN/Inf, VP_ENOMEM when the arena is full. */
int vp_dt_insert(vp_dt_t *dt, const double p[3], uint32_t hint, uint32_t *vertex);

/* Inserts p, known to lie in the circumsphere of tet `conflict_tet` (the planner always knows
 * such a tet: an endpoint of the Voronoi edge whose probe produced p). No walk.
 * VP_EINVAL if the tet is not in conflict with p (nothing changes). */
int vp_dt_insert_in_conflict(vp_dt_t *dt, const double p[3], uint32_t conflict_tet,
                             uint32_t *vertex);

#ifndef VP_CORE_MCU /* left out of a microcontroller build (vp_status.h): host tools and tests */
/* Inserts n points (xyz[3*i..]) in a spatial order (Hilbert curve, BRIO rounds), sorting inside
 * the arena. ids (may be NULL) receives each point's vertex index (a duplicate gets the vertex
 * already there). Non-finite input is refused before anything changes (VP_EINVAL). On
 * VP_ENOMEM the triangulation is valid and holds the points inserted so far; ids of the points
 * left out are VP_DT_NONE. */
int vp_dt_insert_batch(vp_dt_t *dt, const double *xyz, uint32_t n, uint32_t *ids);

/* Removes vertex v: afterwards the triangulation is exactly the one of the remaining points
 * (vp_insphere_sos perturbs by the points' lexicographic order, never by index or insertion
 * order, so the Delaunay triangulation of a point set is unique: the same tets, ghost tets
 * included, as inserting the remaining points from scratch in any order). Method: the star of
 * v is the cavity; the Delaunay triangulation of its link vertices is built in the scratch
 * space with the same predicates, and its tets on the inner side of the cavity's boundary
 * facets replace the star. The new tets take the star's slots first, then free-list slots,
 * then new ones; star slots left over go to the free list for later insertions. v's record
 * stays, its tet set to VP_DT_NONE, so no other index changes; re-inserting the same point
 * makes a new record (a new index). A removal that leaves the set flat (fewer than 4 points,
 * or all coplanar) drops every tet and returns to the pending mode, as if the remaining points
 * had been inserted from scratch (dim and span as for them in index order; their records
 * VP_DT_PENDING); in the pending mode a pending vertex can be removed too (dim and span are
 * recomputed in one pass over the records).
 * Needs free space only as scratch (36 bytes per tet of v's star and the small triangulation,
 * 52 bytes per tet of it: 6 KB on average, 22 KB at most, for uniform points), and new tet
 * slots only where the cavity's new tets outnumber the star and the free list:
 * VP_ENOMEM when the free space is too small, VP_EINVAL for an index that is not a vertex of
 * the set (out of range, VP_DT_GHOST, removed, a duplicate record); both change nothing.
 * Lists (vp_dt_last_*): killed = the star of v; created = the tets that fill it. A removal
 * that drops to the pending mode kills every tet and leaves both lists empty. */
int vp_dt_remove(vp_dt_t *dt, uint32_t v);

/* The tet containing p (a ghost tet if p is outside the hull), walking from hint. */
int vp_dt_locate(vp_dt_t *dt, const double p[3], uint32_t hint, uint32_t *tet);

/* 1 if p is inside the circumsphere of tet t (exact, perturbed; for ghost tets: beyond the
 * hull facet). */
int vp_dt_in_conflict(const vp_dt_t *dt, uint32_t t, const double p[3]);

/* Validates everything: adjacency symmetry, ghost placement, positive orientation, the local
 * Delaunay property on every facet (exact), the vertex-to-tet map, the Euler relation of the
 * closed triangulation (V - E + F - T = 0 with the ghost vertex). VP_OK or VP_EDEGEN. */
int vp_dt_check(const vp_dt_t *dt);
#endif

/* --- access --- */
static inline const uint32_t *vp_dt_tet(const vp_dt_t *dt, uint32_t t)
{ return dt->tets + (size_t)t * dt->stride; }
static inline void *vp_dt_payload(const vp_dt_t *dt, uint32_t t)
{ return dt->tets + (size_t)t * dt->stride + 8; }
static inline const double *vp_dt_point(const vp_dt_t *dt, uint32_t v)
{ return dt->vtop[-(ptrdiff_t)v].xyz; }
static inline vp_dt_vertex_t *vp_dt_vertex(const vp_dt_t *dt, uint32_t v)
{ return &dt->vtop[-(ptrdiff_t)v]; }
static inline int vp_dt_is_ghost(const vp_dt_t *dt, uint32_t t)
{ return vp_dt_tet(dt, t)[3] == VP_DT_GHOST; }
/* 1 for a live tet slot, 0 for a free one (iterate t < dt->ntet_slots). */
int vp_dt_alive(const vp_dt_t *dt, uint32_t t);
uint32_t vp_dt_num_finite_tets(const vp_dt_t *dt);
/* Bytes of the arena in use now / at most so far. */
size_t vp_dt_bytes_used(const vp_dt_t *dt);

/* The vertices of facet i of tet t, ordered so that vp_orient3d(f0,f1,f2, v_i) > 0. */
void vp_dt_facet(const vp_dt_t *dt, uint32_t t, int i, uint32_t f[3]);
extern const unsigned char vp_dt_facet_index[4][3];

/* --- queries for the planner --- */

/* Circumcentre of finite tet t (its Voronoi vertex), in floating point. VP_EINVAL for ghosts. */
int vp_dt_circumcenter(const vp_dt_t *dt, uint32_t t, double c[3]);

/* The Voronoi edge dual to facet i of tet t. */
typedef struct vp_dt_vedge {
    int is_ray;        /* 0: segment from -> to; 1: ray from `from` along unit `dir` */
    double from[3], to[3], dir[3];
} vp_dt_vedge_t;
/* `from` is the Voronoi vertex of t when t is finite. For a hull facet the edge is a ray
 * leaving the hull outward. VP_EINVAL when the facet contains the ghost (no finite dual). */
int vp_dt_voronoi_edge(const vp_dt_t *dt, uint32_t t, int i, vp_dt_vedge_t *e);

/* Tets incident to vertex v (ghost tets included) into out[cap]. Returns the count, or
 * VP_ENOMEM if cap is too small, VP_EINVAL for a vertex not in the triangulation. */
int vp_dt_incident_tets(const vp_dt_t *dt, uint32_t v, uint32_t *out, int cap);

/* The tets the last successful insertion (or removal) created and killed. Valid until the next
 * call that modifies the triangulation. Both are empty after the insertion that made the set 3D for the
 * first time (every tet is new then). Killed slots are reused for created tets; their payload bytes
 * are left exactly as they were, so read a killed tet's payload before writing the payload of
 * a created one. */
static inline const uint32_t *vp_dt_last_created(const vp_dt_t *dt, uint32_t *n)
{ *n = dt->ncreated; return dt->created; }
static inline const uint32_t *vp_dt_last_killed(const vp_dt_t *dt, uint32_t *n)
{ *n = dt->nkilled; return dt->killed; }
/* The vertices killed tet k had (4 per tet, in the order of vp_dt_last_killed). */
static inline const uint32_t *vp_dt_last_killed_vertices(const vp_dt_t *dt)
{ return dt->killed_verts; }
/* For created tet q (order of vp_dt_last_created): 4 * t + i where facet i of killed tet t
 * was the cavity boundary facet this tet is built on. The new tet's copy of that facet is the
 * one opposite the new vertex; its Voronoi edge lies on the same line as before, shortened.
 * After a removal: one cavity boundary facet the created tet holds (its lowest facet index
 * among them), or VP_DT_NONE for a created tet with no facet on the cavity boundary. */
static inline const uint32_t *vp_dt_last_created_from(const vp_dt_t *dt)
{ return dt->created_from; }

#endif
