/* vp_dt — incremental 3D Delaunay triangulation (Bowyer-Watson) in a caller-given arena.
 *
 * Insertion of p: find one tet in conflict with p (visibility walk, or given by the caller),
 * dig the cavity (all tets whose circumsphere contains p, found breadth-first from it,
 * recording the boundary facets as they are met), then fill it with one new tet per cavity
 * boundary facet joined to p. The new tets are glued to each other through a table indexed by
 * local ids of the boundary vertices (half-edge a -> b meets b -> a), or an edge hash for very
 * large cavities. Only marks and local-id tags are written before the cavity is known and the
 * memory for the new tets is reserved, and every failure undoes them, so the triangulation is
 * left as it was.
 *
 * Marks live in spare bits of the vertex words: bit 31 of word 0 = "in the cavity", bit 31 of
 * word 1 = "tested, not in conflict". Local ids live in the vertex records' tet words (bit 31
 * set) until the fill rewrites those words. All are cleared before an insertion returns.
 *
 * Predicates: the inline filters of vp_pred.h with static bounds for the bounding box of all
 * vertex records (p included), so most tests cost a determinant and one comparison; the exact
 * stages run only when a filter cannot decide.
 *
 * Removal of a vertex (vp_dt_remove, at the end of the file) refills its star with tets of the
 * Delaunay triangulation of its link, built with the same code in a second vp_dt_t inside the
 * free space.
 */
#include <math.h>
#include <string.h>
#include "vp_dt.h"
#include "vp_pred.h"
#include "vp_sort.h"

#define MARK 0x80000000u
#define VMASK 0x7FFFFFFFu
#define DEAD 0xFFFFFFFFu
#define VDUP 0xFFFFFFFEu /* vertex record of a duplicate point: never inserted */
#define VPEND VP_DT_PENDING /* vertex record waiting while the set is flat (dim < 3) */

#if defined(__GNUC__) && !defined(VP_NO_PREFETCH)
#define PREFETCH(addr) __builtin_prefetch(addr)
#else
#define PREFETCH(addr) ((void)0)
#endif

#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define ALWAYS_INLINE static inline __attribute__((always_inline))
#define NOINLINE __attribute__((noinline))
#else
#define ALWAYS_INLINE static inline
#define NOINLINE
#endif

#define TET(dt, t) ((dt)->tets + (size_t)(t) * (dt)->stride)
/* The same through local copies (tets_, stride_) in the hot loops: a store through a
 * uint32_t pointer may alias dt->stride, so TET() would reload it after every store. */
#define TETS(t) (tets_ + (size_t)(t) * stride_)
#define PT(dt, v) ((dt)->vtop[-(ptrdiff_t)(v)].xyz)
#define VREC(dt, v) ((dt)->vtop[-(ptrdiff_t)(v)])

/* facet i = vertices FI[i][0..2], ordered so that orient3d(facet, v_i) > 0 */
const unsigned char vp_dt_facet_index[4][3] = { { 1, 3, 2 }, { 0, 2, 3 }, { 0, 3, 1 }, { 0, 1, 2 } };
#define FI vp_dt_facet_index

/* One boundary facet of the cavity, recorded while digging. */
typedef struct bfacet {
    uint32_t v[3];    /* oriented so that the cavity (and p) is on its positive side */
    uint32_t outside; /* 4 * tet + facet of the tet that stays */
    uint32_t from;    /* 4 * killed tet + facet */
    uint32_t lid;     /* gluing: local ids of v[0..2] (7 bits each), the ghost case (2 bits),
                       * which of v[0..2] got their id here (3 bits) */
    uint32_t old[3];  /* for those: the vertex record's tet word before the tag */
} bfacet_t;

#define LID_GHOST_SHIFT (3u * LID_BITS)
#define LID_NEW_SHIFT (3u * LID_BITS + 2u)

/* edge hash entry used to glue the new tets of a large cavity to each other */
typedef struct ehash {
    uint32_t a, b;    /* edge (a < b); a == VP_DT_NONE: empty */
    uint32_t ref;     /* 4 * new tet + facet opposite the edge's third vertex */
} ehash_t;

/* New tet (a,b,c,p) from boundary facet (a,b,c): slot of a, b, c, p. With the ghost among
 * a, b, c (case 1 + its index) an even permutation moves it to slot 3. */
static const unsigned char POS[4][4] = {
    { 0, 1, 2, 3 }, { 3, 2, 1, 0 }, { 2, 3, 0, 1 }, { 1, 0, 3, 2 }
};

#define LID_BITS 7u
#define LID_MAX (1u << LID_BITS) /* local vertex ids for the gluing table */
#define VTAG 0x80000000u         /* vertex record's tet word holds a local id (never a tet) */

static unsigned char *gap_lo(const vp_dt_t *dt)
{
    return (unsigned char *)(dt->tets + (size_t)dt->ntet_slots * dt->stride);
}

static unsigned char *gap_hi(const vp_dt_t *dt)
{
    return (unsigned char *)((dt->vtop + 1) - dt->nvert);
}

/* Records the arena use: tets + vertices + `scratch` bytes of scratch in use now. */
static void note_high_water(vp_dt_t *dt, size_t scratch)
{
    size_t used = (size_t)(dt->mem_hi - gap_hi(dt)) + (size_t)(gap_lo(dt) - dt->mem_lo) + scratch;
    if (used > dt->high_water) dt->high_water = used;
}

int vp_dt_init(vp_dt_t *dt, void *mem, size_t bytes, size_t payload_bytes)
{
    uintptr_t lo, hi;
    int k;
    if (!dt || !mem || payload_bytes > 1024) return VP_EINVAL;
    lo = ((uintptr_t)mem + 7u) & ~(uintptr_t)7u;
    hi = ((uintptr_t)mem + bytes) & ~(uintptr_t)7u;
    if (hi < lo || hi - lo < 1024) return VP_EINVAL;
    memset(dt, 0, sizeof *dt);
    dt->mem_lo = (unsigned char *)lo;
    dt->mem_hi = (unsigned char *)hi;
    dt->tets = (uint32_t *)lo;
    dt->vtop = (vp_dt_vertex_t *)hi - 1;
    dt->stride = 8u + (uint32_t)((payload_bytes + 3u) / 4u);
    dt->free_head = VP_DT_NONE;
    dt->last_tet = VP_DT_NONE;
    dt->dim = -1;
    dt->rng = 0x2545F491u;
    for (k = 0; k < 3; k++) {
        dt->box_lo[k] = HUGE_VAL;
        dt->box_hi[k] = -HUGE_VAL;
    }
    dt->sbound_o3 = dt->sbound_is = HUGE_VAL;
    dt->lowbit = VP_DT_LOWBIT_NONE;
    return VP_OK;
}

/* The static filter bounds for the box and lowbit: 0 while every coordinate is a multiple of
 * 2^lowbit and the box is small enough in those units for the filters' floating-point
 * determinants to be exact (integer grids). */
static void box_bounds(vp_dt_t *dt)
{
    int xo = 0, xi = 0;
    if (dt->lowbit != VP_DT_LOWBIT_OFF) {
        xo = vp_orient3d_box_exact(dt->box_lo, dt->box_hi, dt->lowbit);
        xi = vp_insphere_box_exact(dt->box_lo, dt->box_hi, dt->lowbit);
        if (!xo && !xi) dt->lowbit = VP_DT_LOWBIT_OFF;
    }
    dt->sbound_o3 = xo ? 0.0 : vp_orient3d_static_bound(dt->box_lo, dt->box_hi);
    dt->sbound_is = xi ? 0.0 : vp_insphere_static_bound(dt->box_lo, dt->box_hi);
}

/* Grows the bounding box to hold p (finite) and updates the static filter bounds. Extents
 * only grow and lowbit only drops, so once neither filter is exact, lowbit is no longer
 * tracked. */
static void box_add(vp_dt_t *dt, const double *p)
{
    int k, grown = 0;
    for (k = 0; k < 3; k++) {
        if (p[k] < dt->box_lo[k]) { dt->box_lo[k] = p[k]; grown = 1; }
        if (p[k] > dt->box_hi[k]) { dt->box_hi[k] = p[k]; grown = 1; }
        if (dt->lowbit != VP_DT_LOWBIT_OFF && p[k] != 0.0) {
            int b = vp_lowest_bit(p[k]);
            if (b < dt->lowbit) { dt->lowbit = b; grown = 1; }
        }
    }
    if (grown) box_bounds(dt);
}

int vp_dt_alive(const vp_dt_t *dt, uint32_t t)
{
    return t < dt->ntet_slots && TET(dt, t)[0] != DEAD;
}

uint32_t vp_dt_num_finite_tets(const vp_dt_t *dt)
{
    return dt->nalive - dt->nghost;
}

size_t vp_dt_bytes_used(const vp_dt_t *dt)
{
    return dt->high_water;
}

void vp_dt_facet(const vp_dt_t *dt, uint32_t t, int i, uint32_t f[3])
{
    const uint32_t *v = TET(dt, t);
    f[0] = v[FI[i][0]] & VMASK;
    f[1] = v[FI[i][1]] & VMASK;
    f[2] = v[FI[i][2]] & VMASK;
}

static int finite_point(const double p[3])
{
    /* x - x is 0 for finite x, NaN for Inf and NaN */
    return p[0] - p[0] == 0.0 && p[1] - p[1] == 0.0 && p[2] - p[2] == 0.0;
}

static int same_point(const double *a, const double *b)
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* The conflict test when insphere(a,b,c,d,p) is exactly 0: p on a vertex, or the
 * perturbation decides. */
static int conflict_zero(const uint32_t *v, const double *a, const double *b, const double *c,
                         const double *d, const double *p, uint32_t *dup, double sb_o3)
{
    if (same_point(a, p)) { *dup = v[0] & VMASK; return 0; }
    if (same_point(b, p)) { *dup = v[1] & VMASK; return 0; }
    if (same_point(c, p)) { *dup = v[2]; return 0; }
    if (same_point(d, p)) { *dup = v[3]; return 0; }
    return vp_insphere_sos_zero_b(a, b, c, d, p, sb_o3) > 0;
}

/* The rare part of the conflict test: the filter could not decide insphere(a,b,c,d,p). */
static int conflict_exact(const uint32_t *v, const double *a, const double *b, const double *c,
                          const double *d, const double *p, uint32_t *dup, double sb_o3)
{
    int s = vp_insphere_tail(a, b, c, d, p);
    if (s == 0) return conflict_zero(v, a, b, c, d, p, dup, sb_o3);
    return s > 0;
}

static int conflict_ghost(const vp_dt_t *dt, const uint32_t *v, const double *p, uint32_t *dup);

/* Conflict test of tet record v with p. For a finite tet: p inside the circumsphere under the
 * symbolic perturbation. For a ghost tet: p strictly beyond its hull facet, or on the facet's
 * plane and in conflict with the finite tet behind the facet (its circle test). When p lands
 * exactly on a vertex, *dup receives it and the answer is 0. in_box: p lies in the bounding
 * box, and sbound is dt->sbound_is (else HUGE_VAL; the orient3d bound follows). */
ALWAYS_INLINE int conflict_b(const vp_dt_t *dt, const uint32_t *v, const double *p,
                             uint32_t *dup, double sbound, int in_box)
{
    const double *a, *b, *c, *d;
    int s;
    if (v[3] == VP_DT_GHOST) return conflict_ghost(dt, v, p, dup);
    a = PT(dt, v[0] & VMASK);
    b = PT(dt, v[1] & VMASK);
    c = PT(dt, v[2]);
    d = PT(dt, v[3]);
    s = vp_insphere_filter_b(a, b, c, d, p, sbound);
    if (s != VP_PRED_UNSURE) return s > 0;
    if (sbound == 0.0) /* exact box: det is 0 */
        return conflict_zero(v, a, b, c, d, p, dup, in_box ? dt->sbound_o3 : HUGE_VAL);
    return conflict_exact(v, a, b, c, d, p, dup, in_box ? dt->sbound_o3 : HUGE_VAL);
}

static int conflict_ghost(const vp_dt_t *dt, const uint32_t *v, const double *p, uint32_t *dup)
{
    int s = vp_orient3d_fast(PT(dt, v[0] & VMASK), PT(dt, v[1] & VMASK), PT(dt, v[2]), p);
    if (s) return s > 0;
    return conflict_b(dt, TET(dt, v[7] >> 2), p, dup, HUGE_VAL, 0);
}

static int conflict(const vp_dt_t *dt, const uint32_t *v, const double *p, uint32_t *dup)
{
    return conflict_b(dt, v, p, dup, HUGE_VAL, 0);
}

#ifndef VP_CORE_MCU /* host tools and tests only (vp_status.h) */
int vp_dt_in_conflict(const vp_dt_t *dt, uint32_t t, const double p[3])
{
    uint32_t dup = VP_DT_NONE;
    if (!vp_dt_alive(dt, t) || !finite_point(p)) return 0;
    return conflict(dt, TET(dt, t), p, &dup);
}
#endif

/* ---- tet slots ---- */

static void tet_release(vp_dt_t *dt, uint32_t t)
{
    uint32_t *v = TET(dt, t);
    v[0] = DEAD;
    v[4] = dt->free_head;
    dt->free_head = t;
    dt->nfree++;
}

static uint32_t tet_take(vp_dt_t *dt)
{
    uint32_t t;
    if (dt->nfree) {
        t = dt->free_head;
        dt->free_head = TET(dt, t)[4];
        dt->nfree--;
        return t;
    }
    return dt->ntet_slots++;
}

/* ---- point location ---- */

static uint32_t lcg(vp_dt_t *dt)
{
    dt->rng = dt->rng * 1664525u + 1013904223u;
    return dt->rng >> 24;
}

/* Visibility walk: step through any facet that has p strictly on its far side. Ends in the
 * finite tet whose closure contains p, or in the ghost tet of a hull facet p is beyond.
 * Terminates in a Delaunay triangulation (acyclicity of the in-front relation); the step
 * budget only guards against a corrupted structure.
 *
 * The four facet orientations of a tet come from the differences d_k = v_k - p and two cross
 * products: with c01 = d0 x d1 and c23 = d2 x d3, orient3d(facet i, p) = -D_i for
 *   D_3 = c01 . d2, D_2 = -(c01 . d3), D_1 = c23 . d0, D_0 = -(c23 . d1)
 * (orient3d(a, b, c, p) = -det(a - p, b - p, c - p); facet i as in FI). Each D_i has the six
 * monomials of orient3d, products of one x, one y and one z difference, along paths of 8
 * roundings (3 differences, cross product and difference, dot product and 2 sums), so the
 * static orient3d bound (vp_pred.h) certifies its sign, and an exact box makes it exact
 * (values below 3 * 2^49 units, as in vp_orient3d_box_exact). Uncertain facets get the exact
 * predicate. */
static int walk(vp_dt_t *dt, const double *p, uint32_t t, uint32_t *out, double sbound)
{
    uint32_t prev = VP_DT_NONE, *const tets_ = dt->tets;
    const size_t stride_ = dt->stride;
    uint64_t budget = 16u + 4u * (uint64_t)dt->nalive;
    if (!vp_dt_alive(dt, t)) t = dt->last_tet;
    if (!vp_dt_alive(dt, t)) {
        for (t = 0; t < dt->ntet_slots && !vp_dt_alive(dt, t); t++) {}
        if (t == dt->ntet_slots) return VP_ESTATE;
    }
    if (TETS(t)[3] == VP_DT_GHOST) t = TETS(t)[7] >> 2;
    while (budget--) {
        const uint32_t *v = TETS(t);
        const double *q0, *q1, *q2, *q3;
        double D[4];
        uint32_t r, k;
        if (v[3] == VP_DT_GHOST) { *out = t; return VP_OK; }
        q0 = PT(dt, v[0]); q1 = PT(dt, v[1]); q2 = PT(dt, v[2]); q3 = PT(dt, v[3]);
#ifdef VP_PRED_HAVE_V2D
        {
            /* the same expressions, lanes (d0, d2) x (d1, d3): (c01, c23) at once */
            vp_pred_v2d_ px = { p[0], p[0] }, py = { p[1], p[1] }, pz = { p[2], p[2] };
            vp_pred_v2d_ ux = (vp_pred_v2d_){ q0[0], q2[0] } - px, vx = (vp_pred_v2d_){ q1[0], q3[0] } - px;
            vp_pred_v2d_ uy = (vp_pred_v2d_){ q0[1], q2[1] } - py, vy = (vp_pred_v2d_){ q1[1], q3[1] } - py;
            vp_pred_v2d_ uz = (vp_pred_v2d_){ q0[2], q2[2] } - pz, vz = (vp_pred_v2d_){ q1[2], q3[2] } - pz;
            vp_pred_v2d_ cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
            vp_pred_v2d_ e = (cx * VP_PRED_SWAP_(ux) + cy * VP_PRED_SWAP_(uy)) + cz * VP_PRED_SWAP_(uz);
            vp_pred_v2d_ f = (cx * VP_PRED_SWAP_(vx) + cy * VP_PRED_SWAP_(vy)) + cz * VP_PRED_SWAP_(vz);
            D[3] = e[0];
            D[1] = e[1];
            D[2] = -f[0];
            D[0] = -f[1];
        }
#else
        {
        double d0x, d0y, d0z, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z, ax, ay, az, bx, by, bz;
        d0x = q0[0] - p[0]; d0y = q0[1] - p[1]; d0z = q0[2] - p[2];
        d1x = q1[0] - p[0]; d1y = q1[1] - p[1]; d1z = q1[2] - p[2];
        d2x = q2[0] - p[0]; d2y = q2[1] - p[1]; d2z = q2[2] - p[2];
        d3x = q3[0] - p[0]; d3y = q3[1] - p[1]; d3z = q3[2] - p[2];
        ax = d0y * d1z - d0z * d1y; ay = d0z * d1x - d0x * d1z; az = d0x * d1y - d0y * d1x;
        bx = d2y * d3z - d2z * d3y; by = d2z * d3x - d2x * d3z; bz = d2x * d3y - d2y * d3x;
        D[3] = (ax * d2x + ay * d2y) + az * d2z;
        D[2] = -((ax * d3x + ay * d3y) + az * d3z);
        D[1] = (bx * d0x + by * d0y) + bz * d0z;
        D[0] = -((bx * d1x + by * d1y) + bz * d1z);
        }
#endif
        r = lcg(dt);
        for (k = 0; k < 4; k++) {
            uint32_t i = (r + k) & 3u;
            if ((v[4 + i] >> 2) == prev) continue;
            if (D[i] > sbound) break;                   /* p strictly beyond facet i */
            if (sbound != 0.0 && !(D[i] < -sbound) &&   /* uncertain (NaN: overflow) */
                vp_orient3d_fast(PT(dt, v[FI[i][0]]), PT(dt, v[FI[i][1]]), PT(dt, v[FI[i][2]]),
                                 p) < 0)
                break;
        }
        if (k == 4) { *out = t; return VP_OK; }
        prev = t;
        t = v[4 + ((r + k) & 3u)] >> 2;
        dt->walk_steps++;
    }
    return VP_EDEGEN;
}

#ifndef VP_CORE_MCU /* host tools and tests only (vp_status.h) */
int vp_dt_locate(vp_dt_t *dt, const double p[3], uint32_t hint, uint32_t *tet)
{
    double lo[3], hi[3];
    int k;
    if (!dt || !p || !tet || !finite_point(p)) return VP_EINVAL;
    if (dt->dim < 3) return VP_ESTATE;
    /* p may lie outside the bounding box: the static bound of a box that holds it too */
    for (k = 0; k < 3; k++) {
        lo[k] = p[k] < dt->box_lo[k] ? p[k] : dt->box_lo[k];
        hi[k] = p[k] > dt->box_hi[k] ? p[k] : dt->box_hi[k];
    }
    return walk(dt, p, hint, tet, vp_orient3d_static_bound(lo, hi));
}
#endif

/* ---- the cavity ---- */

/* Puts back the vertex records' tet words that local ids replaced (bf[0..nb)). */
static void untag_vertices(vp_dt_t *dt, const bfacet_t *bf, uint32_t nb)
{
    uint32_t q, k;
    for (q = 0; q < nb; q++) {
        uint32_t fresh = bf[q].lid >> LID_NEW_SHIFT;
        if (!fresh) continue;
        for (k = 0; k < 3; k++)
            if (fresh & (1u << k)) VREC(dt, bf[q].v[k]).tet = bf[q].old[k];
    }
}

/* Clears the marks of a cavity being abandoned: queue[0..nk) in the cavity, the outside tets
 * of the boundary facets bf[0..nb) tested not in conflict; and the local-id tags. */
static void unmark_cavity(vp_dt_t *dt, const uint32_t *queue, uint32_t nk, const bfacet_t *bf,
                          uint32_t nb)
{
    uint32_t q;
    for (q = 0; q < nk; q++) TET(dt, queue[q])[0] &= VMASK;
    for (q = 0; q < nb; q++) TET(dt, bf[q].outside >> 2)[1] &= VMASK;
    untag_vertices(dt, bf, nb);
}

/* Local id of vertex x (boundary facet b, slot k) for the gluing table: the ghost is 0, other
 * vertices are numbered from 1 in order of appearance; the id is kept as a tag in the vertex
 * record's tet word (the fill rewrites all of those words; failures put them back). Past
 * LID_MAX - 1 ids, *nid becomes LID_MAX + 1 and the edge hash glues instead. */
ALWAYS_INLINE uint32_t local_id(vp_dt_t *dt, uint32_t x, bfacet_t *b, unsigned k, uint32_t *nid,
                                int may_be_ghost)
{
    uint32_t w, id;
    if (may_be_ghost && x == VP_DT_GHOST) return (k + 1u) << LID_GHOST_SHIFT;
    w = VREC(dt, x).tet;
    if (w & VTAG) return (w & (LID_MAX - 1u)) << (LID_BITS * k);
    if (*nid >= LID_MAX) {
        *nid = LID_MAX + 1u;
        return 0;
    }
    id = (*nid)++;
    b->old[k] = w;
    VREC(dt, x).tet = VTAG | id;
    return (id << (LID_BITS * k)) | (1u << (LID_NEW_SHIFT + k));
}

/* One facet i of cavity tet t (record v) during the digging: the neighbour joins the cavity,
 * or the facet is recorded as a boundary facet. Returns 1 when p is a vertex (*dup). */
ALWAYS_INLINE int dig_facet(vp_dt_t *dt, const uint32_t *v, uint32_t t, unsigned i,
                            const double *p, double sbound, uint32_t *queue, uint32_t *nk,
                            bfacet_t *bftop, uint32_t *nb, uint32_t *nid, uint32_t *dup,
                            int ghost_tet, uint32_t *tets_, size_t stride_)
{
    uint32_t ref = v[4 + i], u = ref >> 2, x0, x1, x2;
    uint32_t *uv = TETS(u);
    bfacet_t *b;
    if (uv[0] & MARK) return 0; /* in the cavity: an inner facet */
    if (!(uv[1] & MARK)) {      /* not tested yet */
        if (conflict_b(dt, uv, p, dup, sbound, 1)) {
            uv[0] |= MARK;
            queue[(*nk)++] = u;
            PREFETCH(TETS(uv[4] >> 2));
            PREFETCH(TETS(uv[5] >> 2));
            PREFETCH(TETS(uv[6] >> 2));
            PREFETCH(TETS(uv[7] >> 2));
            return 0;
        }
        if (*dup != VP_DT_NONE) return 1;
        uv[1] |= MARK;
    }
    b = bftop - ++*nb;
    x0 = v[FI[i][0]] & VMASK;
    x1 = v[FI[i][1]] & VMASK;
    x2 = v[FI[i][2]] & VMASK;
    b->v[0] = x0;
    b->v[1] = x1;
    b->v[2] = x2;
    b->outside = ref;
    b->from = 4u * t + i;
    /* in a ghost tet the ghost is v[3]: only where FI[i][k] == 3 */
    b->lid = local_id(dt, x0, b, 0, nid, ghost_tet && FI[i][0] == 3) |
             local_id(dt, x1, b, 1, nid, ghost_tet && FI[i][1] == 3) |
             local_id(dt, x2, b, 2, nid, ghost_tet && FI[i][2] == 3);
    return 0;
}

static uint32_t ehash_slot(uint32_t a, uint32_t b, uint32_t mask)
{
    uint64_t k = ((uint64_t)a << 32) | b;
    return (uint32_t)((k * 0x9E3779B97F4A7C15ull) >> 40) & mask;
}

/* The fill with the gluing table: tet (a,b,c,p) on each boundary facet (a,b,c); vertex e goes
 * to slot e ^ x, with x = 0 without the ghost and x = 3, 2, 1 when the ghost is a, b, c (the
 * slots of POS). The facet opposite vertex e contains p and the half-edge (e+1 -> e+2): the
 * first pass files each new tet under its three half-edges, the second reads each tet's
 * neighbours from the half-edges the other way round (positions kept in old[], no longer
 * needed). Returns the number of new ghost tets. */
static NOINLINE uint32_t fill_glued(vp_dt_t *dt, uint32_t vid, bfacet_t *bf, uint32_t nb,
                                    const uint32_t *created, uint32_t *tbl, uint32_t dim)
{
    uint32_t q, nghost_new = 0, *const tets_ = dt->tets;
    const size_t stride_ = dt->stride;
    for (q = 0; q < nb; q++) {
        bfacet_t *b = bf + q;
        uint32_t t = created[q], lid = b->lid, out = b->outside, t4 = 4u * t;
        uint32_t x = (4u - ((lid >> LID_GHOST_SHIFT) & 3u)) & 3u, fresh = lid >> LID_NEW_SHIFT;
        uint32_t ra = (lid & (LID_MAX - 1u)) * dim, la = lid & (LID_MAX - 1u);
        uint32_t rb = ((lid >> LID_BITS) & (LID_MAX - 1u)) * dim, lb = (lid >> LID_BITS) & (LID_MAX - 1u);
        uint32_t lc = (lid >> (2 * LID_BITS)) & (LID_MAX - 1u), rc = lc * dim;
        uint32_t *w = TETS(t), *ow = TETS(out >> 2);
        nghost_new += x != 0;
        w[x] = b->v[0];
        w[1u ^ x] = b->v[1];
        w[2u ^ x] = b->v[2];
        w[3u ^ x] = vid;
        w[4u + (3u ^ x)] = out; /* facet opposite p: the outside neighbour */
        ow[4u + (out & 3u)] = t4 + (3u ^ x);
        ow[1] &= VMASK;         /* its "tested" mark goes */
        tbl[rb + lc] = t4 + x;
        tbl[rc + la] = t4 + (1u ^ x);
        tbl[ra + lb] = t4 + (2u ^ x);
        b->old[0] = rc + lb;
        b->old[1] = ra + lc;
        b->old[2] = rb + la;
        if (fresh) { /* each boundary vertex: the new tet on the facet that numbered it */
            if (fresh & 1u) VREC(dt, b->v[0]).tet = t;
            if (fresh & 2u) VREC(dt, b->v[1]).tet = t;
            if (fresh & 4u) VREC(dt, b->v[2]).tet = t;
        }
    }
    for (q = 0; q < nb; q++) {
        const bfacet_t *b = bf + q;
        uint32_t *w = TETS(created[q]), x = (4u - ((b->lid >> LID_GHOST_SHIFT) & 3u)) & 3u;
        w[4u + x] = tbl[b->old[0]];
        w[4u + (1u ^ x)] = tbl[b->old[1]];
        w[4u + (2u ^ x)] = tbl[b->old[2]];
    }
    return nghost_new;
}

/* Inserts vertex record vid (already appended, not yet in the triangulation) given a tet
 * `start` known to be in conflict with it.
 *
 * Scratch, in the free space between the tets (lo) and the vertex records (hi): while digging,
 * the queue of cavity tets grows up from lo and the boundary facets grow down from hi. Then,
 * below the boundary facets: the killed list, the killed tets' vertices, the created list,
 * created_from (the lists the planner reads after the insertion), and the gluing table (or an
 * edge hash for very large cavities). New tet slots beyond the old ones grow over the queue.
 * (159 lines, kept whole: digging and filling share the scratch layout and a dozen locals of
 * the hottest loop of the program; split, they would pass through memory.) */
static int dig_and_fill(vp_dt_t *dt, uint32_t vid, uint32_t start, uint32_t *dupv)
{
    const double *p = PT(dt, vid);
    unsigned char *lo = gap_lo(dt), *hi = gap_hi(dt);
    uint32_t *queue = (uint32_t *)lo;
    bfacet_t *bftop = (bfacet_t *)((uintptr_t)hi & ~(uintptr_t)7u), *bf;
    uint32_t nk, nb = 0, q, nghost_killed = 0, nghost_new = 0, dim, reuse, from_free, extra;
    uint32_t dup = VP_DT_NONE;
    uint32_t *created, *killed, *kverts, *cfrom, *tbl = NULL;
    double sbound = dt->sbound_is; /* p and every vertex lie in the box */
    uint32_t *const tets_ = dt->tets;
    const size_t stride_ = dt->stride;
    ehash_t *eh = NULL;
    uint32_t hmask = 0, nid = 1;
    unsigned char *scratch_lo, *need_lo;

    /* dig: breadth-first from start over tets in conflict, recording the boundary */
    if ((unsigned char *)(queue + 8) > (unsigned char *)(bftop - 8)) return VP_ENOMEM;
    TETS(start)[0] |= MARK;
    queue[0] = start;
    nk = 1;
    {
        const uint32_t *sv = TETS(start);
        PREFETCH(TETS(sv[4] >> 2));
        PREFETCH(TETS(sv[5] >> 2));
        PREFETCH(TETS(sv[6] >> 2));
        PREFETCH(TETS(sv[7] >> 2));
    }
    for (q = 0; q < nk; q++) {
        uint32_t t = queue[q];
        const uint32_t *v = TETS(t);
        if ((unsigned char *)(queue + nk + 4) > (unsigned char *)(bftop - nb - 4)) {
            unmark_cavity(dt, queue, nk, bftop - nb, nb);
            return VP_ENOMEM;
        }
        if (v[3] != VP_DT_GHOST ?
            dig_facet(dt, v, t, 0, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 0, tets_, stride_) ||
            dig_facet(dt, v, t, 1, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 0, tets_, stride_) ||
            dig_facet(dt, v, t, 2, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 0, tets_, stride_) ||
            dig_facet(dt, v, t, 3, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 0, tets_, stride_) :
            (nghost_killed++,
             dig_facet(dt, v, t, 0, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 1, tets_, stride_) ||
             dig_facet(dt, v, t, 1, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 1, tets_, stride_) ||
             dig_facet(dt, v, t, 2, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 1, tets_, stride_) ||
             dig_facet(dt, v, t, 3, p, sbound, queue, &nk, bftop, &nb, &nid, &dup, 1, tets_, stride_))) {
            unmark_cavity(dt, queue, nk, bftop - nb, nb);
            *dupv = dup;
            return VP_EDUP;
        }
    }
    bf = bftop - nb;

    /* reserve the lists and the gluing scratch below the boundary facets, new slots above lo */
    killed = (uint32_t *)bf - nk;
    kverts = killed - 4 * (size_t)nk;
    created = kverts - nb;
    cfrom = created - nb;
    dim = nb / 2 + 3; /* a cavity bounded by a sphere has nb / 2 + 2 boundary vertices */
    scratch_lo = NULL;
    if (nid <= LID_MAX && nid <= dim) { /* unless the cavity is huge (or not a ball) */
        tbl = cfrom - (size_t)dim * dim;
        scratch_lo = (unsigned char *)tbl;
    }
    reuse = nb < nk ? nb : nk;
    from_free = nb - reuse < dt->nfree ? nb - reuse : dt->nfree;
    extra = nb - reuse - from_free;
    need_lo = lo + (size_t)extra * dt->stride * sizeof(uint32_t);
    if (need_lo < (unsigned char *)(queue + nk)) need_lo = (unsigned char *)(queue + nk);
    if (!scratch_lo || (uintptr_t)scratch_lo < (uintptr_t)need_lo ||
        (uintptr_t)scratch_lo > (uintptr_t)bf) {
        uint32_t hbits;
        untag_vertices(dt, bf, nb);
        nid = 0;
        for (hbits = 4; (1u << hbits) < 3u * nb; hbits++) {}
        hmask = (1u << hbits) - 1u;
        tbl = NULL;
        eh = (ehash_t *)((uintptr_t)cfrom & ~(uintptr_t)7u) - (hmask + 1u);
        scratch_lo = (unsigned char *)eh;
        if ((uintptr_t)scratch_lo < (uintptr_t)need_lo || (uintptr_t)scratch_lo > (uintptr_t)bf) {
            unmark_cavity(dt, queue, nk, bf, nb); /* the tags are gone already */
            return VP_ENOMEM;
        }
    }
    /* nothing can fail from here on */

    /* the killed tets, as they were, before any slot is overwritten */
    for (q = 0; q < nk; q++) {
        uint32_t t = queue[q];
        const uint32_t *v = TETS(t);
        uint32_t *kv = kverts + 4 * (size_t)q;
        killed[q] = t;
        kv[0] = v[0] & VMASK;
        kv[1] = v[1] & VMASK;
        kv[2] = v[2];
        kv[3] = v[3];
    }
    if (eh) memset(eh, 0xFF, (size_t)(hmask + 1u) * sizeof *eh);

    /* slots for the new tets: the killed ones first */
    for (q = nb; q < nk; q++) tet_release(dt, killed[q]);

    /* fill: tet (a,b,c,p) on each boundary facet (a,b,c) */
    if (tbl) {
        for (q = 0; q < nb; q++) {
            created[q] = q < nk ? killed[q] : tet_take(dt);
            cfrom[q] = bf[q].from;
        }
        nghost_new = fill_glued(dt, vid, bf, nb, created, tbl, dim);
    } else {
        /* a very large cavity: glued through the edge hash */
        for (q = 0; q < nb; q++) {
            uint32_t t = q < nk ? killed[q] : tet_take(dt), *w = TETS(t), out = bf[q].outside;
            uint32_t *ow = TETS(out >> 2);
            uint32_t a = bf[q].v[0], b = bf[q].v[1], c = bf[q].v[2], g, e, vv[3];
            const unsigned char *pos;
            g = (bf[q].lid >> LID_GHOST_SHIFT) & 3u; /* set while digging, whatever the gluing */
            pos = POS[g];
            nghost_new += g != 0;
            w[pos[0]] = a;
            w[pos[1]] = b;
            w[pos[2]] = c;
            w[pos[3]] = vid;
            w[4 + pos[3]] = out;
            ow[4 + (out & 3u)] = 4u * t + pos[3];
            ow[1] &= VMASK;
            cfrom[q] = bf[q].from;
            created[q] = t;
            if (a != VP_DT_GHOST) VREC(dt, a).tet = t;
            if (b != VP_DT_GHOST) VREC(dt, b).tet = t;
            if (c != VP_DT_GHOST) VREC(dt, c).tet = t;
            vv[0] = a; vv[1] = b; vv[2] = c;
            for (e = 0; e < 3; e++) {
                uint32_t x = vv[(e + 1) % 3], y = vv[(e + 2) % 3], h;
                if (x > y) { uint32_t tmp = x; x = y; y = tmp; }
                h = ehash_slot(x, y, hmask);
                while (eh[h].a != VP_DT_NONE && (eh[h].a != x || eh[h].b != y)) h = (h + 1) & hmask;
                if (eh[h].a == VP_DT_NONE) {
                    eh[h].a = x; eh[h].b = y; eh[h].ref = 4u * t + pos[e];
                } else {
                    uint32_t o = eh[h].ref;
                    w[4 + pos[e]] = o;
                    TETS(o >> 2)[4 + (o & 3u)] = 4u * t + pos[e];
                }
            }
        }
    }
    VREC(dt, vid).tet = created[0];
    dt->nalive += nb - nk;
    dt->nghost += nghost_new - nghost_killed;
    dt->killed = killed;
    dt->killed_verts = kverts;
    dt->created = created;
    dt->created_from = cfrom;
    dt->nkilled = nk;
    dt->ncreated = nb;
    dt->last_tet = created[0];
    note_high_water(dt, (size_t)(gap_hi(dt) - scratch_lo));
    return VP_OK;
}

/* ---- building the first tet ---- */

static int collinear(const double *a, const double *b, const double *c)
{
    return !vp_orient2d_proj(a, b, c, 0) && !vp_orient2d_proj(a, b, c, 1) &&
           !vp_orient2d_proj(a, b, c, 2);
}

/* Glues the tets in list[0..n) to each other through facets with equal vertex sets (n <= 5). */
static void glue_small(vp_dt_t *dt, const uint32_t *list, int n)
{
    int a, b, i, j;
    for (a = 0; a < n; a++)
        for (i = 0; i < 4; i++) {
            uint32_t fa[3], *va = TET(dt, list[a]);
            vp_dt_facet(dt, list[a], i, fa);
            for (b = 0; b < n; b++) {
                if (b == a) continue;
                for (j = 0; j < 4; j++) {
                    uint32_t fb[3];
                    int m = 0, x, y;
                    vp_dt_facet(dt, list[b], j, fb);
                    for (x = 0; x < 3; x++)
                        for (y = 0; y < 3; y++) m += fa[x] == fb[y];
                    if (m == 3) va[4 + i] = 4u * list[b] + (uint32_t)j;
                }
            }
        }
}

/* Creates the first finite tet and its four ghosts from span[0..3] (span[3] is `last`, the
 * vertex being inserted), then inserts every other pending vertex. On failure everything
 * returns to the flat (pending) state. */
static int build_first(vp_dt_t *dt, uint32_t last)
{
    uint32_t s[4], list[5], v, dup;
    int i, k, st;
    unsigned char *lo = gap_lo(dt);
    memcpy(s, dt->span, sizeof s);
    if (vp_orient3d(PT(dt, s[0]), PT(dt, s[1]), PT(dt, s[2]), PT(dt, s[3])) < 0) {
        uint32_t tmp = s[0]; s[0] = s[1]; s[1] = tmp;
    }
    if ((size_t)(gap_hi(dt) - lo) < 5u * dt->stride * sizeof(uint32_t)) return VP_ENOMEM;
    for (k = 0; k < 5; k++) list[k] = dt->ntet_slots++;
    memcpy(TET(dt, list[0]), s, sizeof s);
    for (i = 0; i < 4; i++) {
        uint32_t *g = TET(dt, list[1 + i]);
        g[0] = s[FI[i][0]];
        g[1] = s[FI[i][2]];
        g[2] = s[FI[i][1]];
        g[3] = VP_DT_GHOST;
    }
    glue_small(dt, list, 5);
    for (k = 0; k < 4; k++) VREC(dt, s[k]).tet = list[0];
    dt->nalive = 5;
    dt->nghost = 4;
    dt->ninserted = 4;
    dt->dim = 3;
    dt->last_tet = list[0];
    note_high_water(dt, 0);
    for (v = 0; v <= last; v++) {
        uint32_t t;
        if (VREC(dt, v).tet != VPEND || v == s[0] || v == s[1] || v == s[2] || v == s[3])
            continue;
        st = walk(dt, PT(dt, v), dt->last_tet, &t, dt->sbound_o3);
        if (st == VP_OK) st = dig_and_fill(dt, v, t, &dup);
        if (st != VP_OK) {
            /* back to flat: no tets, every vertex pending (removed and duplicate records
             * stay as they are; `last` is given back by the caller) */
            uint32_t w;
            for (w = 0; w <= last; w++)
                if (VREC(dt, w).tet < VPEND) VREC(dt, w).tet = VPEND;
            dt->ntet_slots = dt->nfree = dt->nalive = dt->nghost = 0;
            dt->free_head = dt->last_tet = VP_DT_NONE;
            dt->ninserted = 0;
            dt->dim = 2;
            dt->nkilled = dt->ncreated = 0;
            return st == VP_EDUP ? VP_EDEGEN : st;
        }
        dt->ninserted++;
    }
    /* the first 3D triangulation is new as a whole: the lists are empty (scan all tets) */
    dt->nkilled = dt->ncreated = 0;
    return VP_OK;
}

/* Adds vertex vid while the set is still flat (dim < 3). */
static int insert_flat(vp_dt_t *dt, uint32_t vid, uint32_t *dupv)
{
    const double *p = PT(dt, vid);
    uint32_t v;
    for (v = 0; v < vid; v++)
        if (VREC(dt, v).tet == VPEND && same_point(PT(dt, v), p)) { *dupv = v; return VP_EDUP; }
    switch (dt->dim) {
    case -1: dt->span[0] = vid; dt->dim = 0; break;
    case 0: dt->span[1] = vid; dt->dim = 1; break;
    case 1:
        if (!collinear(PT(dt, dt->span[0]), PT(dt, dt->span[1]), p)) {
            dt->span[2] = vid;
            dt->dim = 2;
        }
        break;
    default:
        if (vp_orient3d(PT(dt, dt->span[0]), PT(dt, dt->span[1]), PT(dt, dt->span[2]), p)) {
            dt->span[3] = vid;
            return build_first(dt, vid);
        }
    }
    VREC(dt, vid).tet = VPEND;
    return VP_OK;
}

/* ---- public insertion ---- */

static int append_vertex(vp_dt_t *dt, const double p[3], uint32_t *vid)
{
    vp_dt_vertex_t *r;
    if (dt->nvert >= VP_DT_MAX_VERTICES) return VP_ENOMEM;
    if ((size_t)(gap_hi(dt) - gap_lo(dt)) < 2 * sizeof(vp_dt_vertex_t) + 64) return VP_ENOMEM;
    r = &VREC(dt, dt->nvert);
    r->xyz[0] = p[0]; r->xyz[1] = p[1]; r->xyz[2] = p[2];
    box_add(dt, p);
    r->tet = VP_DT_NONE;
    r->aux = 0;
    *vid = dt->nvert++;
    return VP_OK;
}

/* Puts the appended record vid into the triangulation, starting from tet `start` (walk from it
 * when `located` is 0, or dig from it directly). */
static int insert_record(vp_dt_t *dt, uint32_t vid, uint32_t start, int located, uint32_t *dupv)
{
    const double *p = PT(dt, vid);
    int st;
    if (dt->dim < 3) {
        int was = dt->dim;
        st = insert_flat(dt, vid, dupv);
        if (st != VP_OK && st != VP_EDUP) dt->dim = was;
        return st;
    }
    if (!located) {
        const uint32_t *v;
        st = walk(dt, p, start, &start, dt->sbound_o3);
        if (st != VP_OK) return st;
        v = TET(dt, start);
        if (v[3] != VP_DT_GHOST) {
            int k;
            for (k = 0; k < 4; k++)
                if (same_point(PT(dt, v[k]), p)) { *dupv = v[k]; return VP_EDUP; }
        }
    }
    st = dig_and_fill(dt, vid, start, dupv);
    if (st == VP_OK) dt->ninserted++;
    return st;
}

/* p becomes a new vertex and is inserted from `start` (a hint, or with in_conflict a tet in
 * conflict with p); on failure the vertex is taken back (a duplicate reports the old one). */
static int append_and_insert(vp_dt_t *dt, const double p[3], uint32_t start, int in_conflict,
                             uint32_t *vertex)
{
    uint32_t vid, dup = VP_DT_NONE;
    int st = append_vertex(dt, p, &vid);
    if (st != VP_OK) return st;
    st = insert_record(dt, vid, start, in_conflict, &dup);
    if (st != VP_OK) {
        dt->nvert--;
        if (st == VP_EDUP && vertex) *vertex = dup;
        return st;
    }
    if (vertex) *vertex = vid;
    return VP_OK;
}

int vp_dt_insert(vp_dt_t *dt, const double p[3], uint32_t hint, uint32_t *vertex)
{
    if (!dt || !p || !finite_point(p)) return VP_EINVAL;
    return append_and_insert(dt, p, hint, 0, vertex);
}

int vp_dt_insert_in_conflict(vp_dt_t *dt, const double p[3], uint32_t conflict_tet,
                             uint32_t *vertex)
{
    uint32_t dup = VP_DT_NONE;
    if (!dt || !p || !finite_point(p)) return VP_EINVAL;
    if (dt->dim < 3 || !vp_dt_alive(dt, conflict_tet)) return VP_EINVAL;
    if (!conflict(dt, TET(dt, conflict_tet), p, &dup)) {
        if (dup != VP_DT_NONE) { if (vertex) *vertex = dup; return VP_EDUP; }
        return VP_EINVAL;
    }
    return append_and_insert(dt, p, conflict_tet, 1, vertex);
}

#ifndef VP_CORE_MCU /* batch insertion: host tools only (vp_status.h) */
/* free space a batch of n points needs: records, order, sort scratch, a cavity's worth */
static size_t batch_bytes(uint32_t n)
{
    return (size_t)n * (sizeof(vp_dt_vertex_t) + sizeof(uint32_t)) + vp_sort_scratch_bytes(n) + 4096;
}

/* Sorts and inserts one chunk xyz[0..n) whose scratch fits in the free space. */
static int insert_chunk(vp_dt_t *dt, const double *xyz, uint32_t n, uint32_t *ids, uint32_t id0)
{
    uint32_t *order, base, k;
    int st = VP_OK;
    /* sort at the bottom of the free space, then lay the records out in insertion order */
    order = (uint32_t *)(((uintptr_t)gap_lo(dt) + 7u) & ~(uintptr_t)7u);
    vp_sort_brio(xyz, n, 0x5EEDu + dt->nvert, order,
                 (void *)(((uintptr_t)(order + n) + 7u) & ~(uintptr_t)7u));
    base = dt->nvert;
    for (k = 0; k < n; k++) {
        vp_dt_vertex_t *r = &VREC(dt, base + k);
        const double *p = xyz + 3 * (size_t)order[k];
        if (k + 16 < n) PREFETCH(xyz + 3 * (size_t)order[k + 16]);
        r->xyz[0] = p[0]; r->xyz[1] = p[1]; r->xyz[2] = p[2];
        r->tet = VP_DT_NONE;
        r->aux = id0 + order[k];
        box_add(dt, p);
        if (ids) ids[id0 + order[k]] = base + k;
    }
    dt->nvert = base + n;
    note_high_water(dt, batch_bytes(n) - (size_t)n * sizeof(vp_dt_vertex_t));
    /* the sort scratch is dead from here on: tets may grow over it */
    for (k = 0; k < n; k++) {
        uint32_t vid = base + k, dup = VP_DT_NONE;
        st = insert_record(dt, vid, dt->last_tet, 0, &dup);
        if (st == VP_EDUP) {
            VREC(dt, vid).tet = VDUP;
            if (ids) ids[VREC(dt, vid).aux] = dup;
            st = VP_OK;
        } else if (st != VP_OK) {
            break;
        }
    }
    if (st != VP_OK) {
        /* the records from k on were never inserted: give them back */
        uint32_t j;
        if (ids)
            for (j = k; j < n; j++) ids[VREC(dt, base + j).aux] = VP_DT_NONE;
        dt->nvert = base + k;
    }
    return st;
}

int vp_dt_insert_batch(vp_dt_t *dt, const double *xyz, uint32_t n, uint32_t *ids)
{
    uint32_t done = 0;
    size_t i;
    if (!dt || (!xyz && n)) return VP_EINVAL;
    for (i = 0; i < n; i++)
        if (!finite_point(xyz + 3 * i)) return VP_EINVAL;
    if (ids)
        for (i = 0; i < n; i++) ids[i] = VP_DT_NONE;
    if ((uint64_t)dt->nvert + n > VP_DT_MAX_VERTICES) return VP_ENOMEM;
    /* one sorted batch when its scratch fits, otherwise the largest chunks that fit */
    while (done < n) {
        size_t room = (size_t)(gap_hi(dt) - gap_lo(dt));
        uint32_t m = n - done;
        int st;
        while (m > 0 && batch_bytes(m) > room) m = m > 64 ? m / 2 : m - 1;
        if (m == 0) return VP_ENOMEM;
        st = insert_chunk(dt, xyz + 3 * (size_t)done, m, ids, done);
        if (st != VP_OK) return st;
        done += m;
    }
    return VP_OK;
}
#endif

/* ---- queries ---- */

int vp_dt_circumcenter(const vp_dt_t *dt, uint32_t t, double c[3])
{
    const uint32_t *v;
    const double *a, *b, *cc, *d;
    double bx, by, bz, cx, cy, cz, dx, dy, dz, b2, c2, d2, det, inv;
    if (!vp_dt_alive(dt, t)) return VP_EINVAL;
    v = TET(dt, t);
    if (v[3] == VP_DT_GHOST) return VP_EINVAL;
    a = PT(dt, v[0]); b = PT(dt, v[1]); cc = PT(dt, v[2]); d = PT(dt, v[3]);
    bx = b[0] - a[0]; by = b[1] - a[1]; bz = b[2] - a[2];
    cx = cc[0] - a[0]; cy = cc[1] - a[1]; cz = cc[2] - a[2];
    dx = d[0] - a[0]; dy = d[1] - a[1]; dz = d[2] - a[2];
    b2 = bx * bx + by * by + bz * bz;
    c2 = cx * cx + cy * cy + cz * cz;
    d2 = dx * dx + dy * dy + dz * dz;
    det = bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx);
    if (det == 0.0) return VP_EDEGEN;
    inv = 0.5 / det;
    c[0] = a[0] + inv * (b2 * (cy * dz - cz * dy) - c2 * (by * dz - bz * dy) + d2 * (by * cz - bz * cy));
    c[1] = a[1] + inv * (-b2 * (cx * dz - cz * dx) + c2 * (bx * dz - bz * dx) - d2 * (bx * cz - bz * cx));
    c[2] = a[2] + inv * (b2 * (cx * dy - cy * dx) - c2 * (bx * dy - by * dx) + d2 * (bx * cy - by * cx));
    return VP_OK;
}

int vp_dt_voronoi_edge(const vp_dt_t *dt, uint32_t t, int i, vp_dt_vedge_t *e)
{
    const uint32_t *v;
    uint32_t u, f[3];
    int st;
    if (!vp_dt_alive(dt, t) || i < 0 || i > 3 || !e) return VP_EINVAL;
    v = TET(dt, t);
    u = v[4 + i] >> 2;
    vp_dt_facet(dt, t, i, f);
    if (f[0] == VP_DT_GHOST || f[1] == VP_DT_GHOST || f[2] == VP_DT_GHOST) return VP_EINVAL;
    memset(e, 0, sizeof *e);
    if (v[3] != VP_DT_GHOST && TET(dt, u)[3] != VP_DT_GHOST) {
        double len2 = 0.0;
        int k;
        if ((st = vp_dt_circumcenter(dt, t, e->from)) != VP_OK) return st;
        if ((st = vp_dt_circumcenter(dt, u, e->to)) != VP_OK) return st;
        for (k = 0; k < 3; k++) {
            e->dir[k] = e->to[k] - e->from[k];
            len2 += e->dir[k] * e->dir[k];
        }
        if (len2 > 0.0) {
            double inv = 1.0 / sqrt(len2);
            for (k = 0; k < 3; k++) e->dir[k] *= inv;
        }
        return VP_OK;
    } else {
        /* hull facet: a ray from the finite tet's Voronoi vertex, outward along the facet
         * normal. Facet orientation: seen from the finite tet, outward is negative. */
        uint32_t fin = v[3] == VP_DT_GHOST ? u : t, g[3];
        int fi = v[3] == VP_DT_GHOST ? (int)(v[4 + i] & 3u) : i, k;
        const double *a, *b, *c;
        double n[3], len;
        if ((st = vp_dt_circumcenter(dt, fin, e->from)) != VP_OK) return st;
        vp_dt_facet(dt, fin, fi, g);
        a = PT(dt, g[0]); b = PT(dt, g[1]); c = PT(dt, g[2]);
        n[0] = (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
        n[1] = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]);
        n[2] = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0.0)) return VP_EDEGEN;
        /* the finite tet's own vertex is on the positive side: outward is -n */
        for (k = 0; k < 3; k++) e->dir[k] = -n[k] / len;
        e->is_ray = 1;
        return VP_OK;
    }
}

int vp_dt_incident_tets(const vp_dt_t *dt, uint32_t v, uint32_t *out, int cap)
{
    int n = 0, q;
    uint32_t t;
    if (!dt || v >= dt->nvert || cap < 0) return VP_EINVAL;
    t = VREC(dt, v).tet;
    if (t >= dt->ntet_slots) return VP_EINVAL;
    if (cap < 1) return VP_ENOMEM;
    out[n++] = t;
    for (q = 0; q < n; q++) {
        const uint32_t *w = TET(dt, out[q]);
        int i, k;
        for (i = 0; i < 4; i++) {
            uint32_t u;
            if (w[i] == v) continue; /* the facet opposite v does not contain v */
            u = w[4 + i] >> 2;
            for (k = 0; k < n && out[k] != u; k++) {}
            if (k < n) continue;
            if (n == cap) return VP_ENOMEM;
            out[n++] = u;
        }
    }
    return n;
}

#ifndef VP_CORE_MCU /* validation and vertex removal: host tools and tests only (vp_status.h) */

/* ---- validation ---- */

static int tet_has(const uint32_t *v, uint32_t x)
{
    return v[0] == x || v[1] == x || v[2] == x || v[3] == x;
}

/* Walks around edge (x,y) starting in tet t; returns the number of tets around it and the
 * smallest tet index met, or 0 if the ring does not close. */
static uint32_t edge_ring(const vp_dt_t *dt, uint32_t t, uint32_t x, uint32_t y, uint32_t *minid)
{
    uint32_t cur = t, n = 0, limit = dt->nalive + 1, enter_other;
    const uint32_t *v = TET(dt, t);
    int k, other[2], m = 0;
    for (k = 0; k < 4; k++)
        if (v[k] != x && v[k] != y) other[m++] = k;
    /* leave t through the facet opposite other[0]: it contains x, y and v[other[1]] */
    enter_other = v[other[1]];
    cur = v[4 + other[0]] >> 2;
    *minid = t;
    n = 1;
    while (cur != t) {
        const uint32_t *w = TET(dt, cur);
        int ex = -1;
        if (!tet_has(w, x) || !tet_has(w, y) || !tet_has(w, enter_other) || n > limit) return 0;
        if (cur < *minid) *minid = cur;
        /* exit through the facet opposite enter_other */
        for (k = 0; k < 4; k++)
            if (w[k] == enter_other) ex = k;
        cur = w[4 + ex] >> 2;
        for (k = 0; k < 4; k++)
            if (w[k] != x && w[k] != y && k != ex) break;
        enter_other = w[k];
        n++;
    }
    return n;
}

int vp_dt_check(const vp_dt_t *dt)
{
    uint32_t t, v, nalive = 0, nghost = 0, nfree = 0;
    uint64_t edges = 0;
    if (!dt) return VP_EINVAL;
    if (dt->dim < 3) {
        /* flat: no tets; records pending, removed or duplicate; span pending */
        int k;
        if (dt->ntet_slots || dt->nalive || dt->nfree || dt->ninserted || dt->dim < -1)
            return VP_EDEGEN;
        for (v = 0; v < dt->nvert; v++)
            if (VREC(dt, v).tet < VPEND) return VP_EDEGEN;
        for (k = 0; k <= dt->dim; k++)
            if (dt->span[k] >= dt->nvert || VREC(dt, dt->span[k]).tet != VPEND) return VP_EDEGEN;
        return VP_OK;
    }
    for (t = dt->free_head; t != VP_DT_NONE; t = TET(dt, t)[4]) {
        if (t >= dt->ntet_slots || TET(dt, t)[0] != DEAD || ++nfree > dt->nfree) return VP_EDEGEN;
    }
    if (nfree != dt->nfree) return VP_EDEGEN;
    for (t = 0; t < dt->ntet_slots; t++) {
        const uint32_t *w = TET(dt, t);
        int i, k;
        if (w[0] == DEAD) continue;
        nalive++;
        for (k = 0; k < 4; k++) {
            if (w[k] & MARK) return VP_EDEGEN;
            if (w[k] == VP_DT_GHOST ? k != 3 : (w[k] >= dt->nvert || VREC(dt, w[k]).tet >= VPEND))
                return VP_EDEGEN;
        }
        if (w[0] == w[1] || w[0] == w[2] || w[0] == w[3] || w[1] == w[2] || w[1] == w[3] ||
            w[2] == w[3])
            return VP_EDEGEN;
        if (w[3] == VP_DT_GHOST) nghost++;
        else if (vp_orient3d(PT(dt, w[0]), PT(dt, w[1]), PT(dt, w[2]), PT(dt, w[3])) <= 0)
            return VP_EDEGEN;
        for (i = 0; i < 4; i++) {
            uint32_t ref = w[4 + i], u = ref >> 2, j = ref & 3u, dup = VP_DT_NONE;
            const uint32_t *x;
            if (u >= dt->ntet_slots) return VP_EDEGEN;
            x = TET(dt, u);
            if (x[0] == DEAD || x[4 + j] != 4u * t + (uint32_t)i) return VP_EDEGEN;
            if (tet_has(w, x[j])) return VP_EDEGEN;
            for (k = 0; k < 4; k++)
                if (k != i && !tet_has(x, w[k])) return VP_EDEGEN;
            /* local Delaunay: the vertex across facet i is not in conflict with t */
            if (x[j] != VP_DT_GHOST && conflict(dt, w, PT(dt, x[j]), &dup)) return VP_EDEGEN;
        }
        /* edges: counted once, by the smallest tet index around them */
        for (i = 0; i < 4; i++)
            for (k = i + 1; k < 4; k++) {
                uint32_t minid;
                if (!edge_ring(dt, t, w[i], w[k], &minid)) return VP_EDEGEN;
                edges += minid == t;
            }
    }
    if (nalive != dt->nalive || nghost != dt->nghost || nalive + nfree != dt->ntet_slots)
        return VP_EDEGEN;
    {
        uint64_t nv = 1, nins = 0;
        for (v = 0; v < dt->nvert; v++) {
            uint32_t vt = VREC(dt, v).tet;
            if (vt == VDUP || vt == VP_DT_NONE) continue; /* never inserted, or removed */
            if (vt >= dt->ntet_slots || !tet_has(TET(dt, vt), v)) return VP_EDEGEN;
            nins++;
        }
        if (nins != dt->ninserted) return VP_EDEGEN;
        nv += nins;
        /* closed 3-manifold (S^3 with the ghost vertex): V - E + F - T = 0, F = 2T */
        if (nv + nalive != edges) return VP_EDEGEN;
    }
    return VP_OK;
}

/* ---- vertex removal ----
 *
 * The star of v (every tet containing v, ghost tets included) is the cavity; its boundary
 * facets (each star tet's facet opposite v) form the link of v, a triangulated sphere. The
 * Delaunay triangulation of the remaining points restricted to the cavity consists of tets
 * with vertices among the link vertices (and the ghost), each with an empty perturbed
 * circumsphere; with fewer points such a tet stays Delaunay, and the perturbation depends on
 * the points only, so these tets, and the boundary facets, are tets and facets of the small
 * triangulation of the link vertices. That one is built in the scratch space with the same
 * predicates (a second vp_dt_t on a block of the free space); the tet on the inner side of each
 * boundary facet is kept, then every tet reached from kept ones without crossing a boundary
 * facet. The kept tets replace the star: the star's slots first, then the free list, then new
 * slots; they are glued to the outside through the boundary facets.
 *
 * When the link vertices are coplanar (v on the hull, above a flat part of the rest), the
 * cavity is filled with ghost tets only; one more point behind that plane (the far vertex of
 * a tet outside a boundary facet) makes the small triangulation 3D without adding a tet to
 * the cavity. With no such point the rest is flat: the pending mode.
 *
 * Scratch, from the top of the free space down: the star's tets (the killed list), their
 * vertices, per star tet the outside reference and 4 * tet + index of v, the link vertices and
 * their saved tet words (local ids are tags in the vertex records' tet words, as in the
 * insertion), then the block of the small triangulation, above a reserve for new tet slots.
 * The created lists go over the top of that block once it has been read. Nothing of the
 * triangulation is written before every allocation has succeeded, except the tags, which a
 * failure puts back. */

#define RM_PAY 5u            /* payload words of the small triangulation's tets: */
                             /* the kept index (or NONE), then per facet its boundary facet */
#define RM_SEED 0xFFFFFFFEu  /* kept (a boundary facet is on it), not yet numbered */
#define RM_FLAT 1            /* internal: the rest of the set is flat */

typedef struct rm_star {
    uint32_t nk;          /* tets in the star */
    uint32_t nfin;        /* finite ones */
    uint32_t nlink;       /* finite link vertices (local ids 0 .. nlink-1) */
    uint32_t cap;         /* capacity of glob / oldw */
    uint32_t *killed;     /* the star's tets */
    uint32_t *kverts;     /* their 4 vertices each */
    uint32_t *outs;       /* per star tet: 4 * tet + facet across its facet opposite v */
    uint32_t *from;       /* per star tet: 4 * tet + index of v */
    uint32_t *glob;       /* local id -> vertex */
    uint32_t *oldw;       /* the link vertices' tet words before the tags */
} rm_star_t;

/* The flat state (dim, span) of the pending records as inserting them in index order leaves
 * it; the set is known to be flat. */
static void flat_replay(vp_dt_t *dt)
{
    uint32_t v;
    dt->dim = -1;
    for (v = 0; v < dt->nvert && dt->dim < 2; v++) {
        if (VREC(dt, v).tet != VPEND) continue;
        if (dt->dim == -1) {
            dt->span[0] = v;
            dt->dim = 0;
        } else if (dt->dim == 0) {
            dt->span[1] = v;
            dt->dim = 1;
        } else if (!collinear(PT(dt, dt->span[0]), PT(dt, dt->span[1]), PT(dt, v))) {
            dt->span[2] = v;
            dt->dim = 2;
        }
    }
    dt->nkilled = dt->ncreated = 0;
}

/* A removal that leaves the set flat: every tet goes, the other vertices become pending. */
static void drop_to_flat(vp_dt_t *dt, uint32_t v)
{
    uint32_t w;
    for (w = 0; w < dt->nvert; w++)
        if (VREC(dt, w).tet < VPEND) VREC(dt, w).tet = VPEND;
    VREC(dt, v).tet = VP_DT_NONE;
    dt->ntet_slots = dt->nfree = dt->nalive = dt->nghost = 0;
    dt->free_head = dt->last_tet = VP_DT_NONE;
    dt->ninserted = 0;
    flat_replay(dt);
}

static void rm_untag(vp_dt_t *dt, const rm_star_t *S)
{
    uint32_t i;
    for (i = 0; i < S->nlink; i++) VREC(dt, S->glob[i]).tet = S->oldw[i];
}

/* Collects the star of v (breadth-first from t0, marks in word 0 cleared again) at the top of
 * the free space, lays out the arrays of S below it and tags the link vertices with local ids.
 * VP_ENOMEM (nothing changed) when the free space cannot hold them with room to spare. */
static int rm_star(vp_dt_t *dt, uint32_t v, uint32_t t0, rm_star_t *S)
{
    unsigned char *lo = gap_lo(dt);
    uint32_t *top = (uint32_t *)((uintptr_t)gap_hi(dt) & ~(uintptr_t)7u);
    size_t room = (uintptr_t)top > (uintptr_t)lo ? (size_t)((unsigned char *)top - lo) / 4u : 0;
    uint32_t nk = 1, q;
    if (room < 256) return VP_ENOMEM;
    TET(dt, t0)[0] |= MARK;
    top[-1] = t0;
    for (q = 0; q < nk; q++) {
        const uint32_t *w = TET(dt, top[-1 - (ptrdiff_t)q]);
        int i;
        for (i = 0; i < 4; i++) {
            uint32_t u, *uw;
            if ((w[i] & VMASK) == v) continue; /* the facet opposite v: the boundary */
            u = w[4 + i] >> 2;
            uw = TET(dt, u);
            if (uw[0] & MARK) continue;
            if (16u * ((size_t)nk + 1u) + 64u > room) {
                for (q = 0; q < nk; q++) TET(dt, top[-1 - (ptrdiff_t)q])[0] &= VMASK;
                return VP_ENOMEM;
            }
            uw[0] |= MARK;
            top[-1 - (ptrdiff_t)nk++] = u;
        }
    }
    S->nk = nk;
    S->killed = top - nk;
    for (q = 0; q < nk; q++) TET(dt, S->killed[q])[0] &= VMASK;
    S->kverts = S->killed - 4 * (size_t)nk;
    S->outs = S->kverts - nk;
    S->from = S->outs - nk;
    S->cap = nk + 4u;
    S->glob = S->from - S->cap;
    S->oldw = S->glob - S->cap;
    S->nfin = 0;
    for (q = 0; q < nk; q++) {
        uint32_t t = S->killed[q], iv;
        const uint32_t *w = TET(dt, t);
        memcpy(S->kverts + 4 * (size_t)q, w, 4 * sizeof(uint32_t));
        for (iv = 0; w[iv] != v; iv++) {}
        S->outs[q] = w[4 + iv];
        S->from[q] = 4u * t + iv;
        S->nfin += w[3] != VP_DT_GHOST;
    }
    /* the link vertices, numbered in order of appearance */
    S->nlink = 0;
    for (q = 0; q < nk; q++) {
        uint32_t iv = S->from[q] & 3u, m;
        for (m = 0; m < 3; m++) {
            uint32_t x = S->kverts[4 * (size_t)q + FI[iv][m]];
            if (x == VP_DT_GHOST || (VREC(dt, x).tet & VTAG)) continue;
            if (S->nlink + 1u >= S->cap) { /* not a sphere: never in a valid triangulation */
                rm_untag(dt, S);
                return VP_EDEGEN;
            }
            S->glob[S->nlink] = x;
            S->oldw[S->nlink] = VREC(dt, x).tet;
            VREC(dt, x).tet = VTAG | S->nlink;
            S->nlink++;
        }
    }
    return VP_OK;
}

/* Builds the Delaunay triangulation of the link vertices in mem[0 .. S->oldw), vertex i of
 * it being link vertex i. A flat link gets one more vertex (*wid) behind its plane. RM_FLAT
 * when the remaining set is flat. */
static int rm_link_dt(const vp_dt_t *dt, rm_star_t *S, unsigned char *mem, vp_dt_t *sd,
                      uint32_t *wid)
{
    unsigned char *end = (unsigned char *)S->oldw;
    uint32_t i, sv, q, x = VP_DT_NONE;
    int k, st;
    *wid = VP_DT_NONE;
    if ((uintptr_t)end < (uintptr_t)mem + 2048u) return VP_ENOMEM;
    if (vp_dt_init(sd, mem, (size_t)(end - mem), RM_PAY * sizeof(uint32_t)) != VP_OK)
        return VP_ENOMEM;
    /* the filters' box: the link's, with the whole set's lowbit (valid for every point) */
    for (k = 0; k < 3; k++) sd->box_lo[k] = sd->box_hi[k] = PT(dt, S->glob[0])[k];
    for (i = 1; i < S->nlink; i++) {
        const double *p = PT(dt, S->glob[i]);
        for (k = 0; k < 3; k++) {
            if (p[k] < sd->box_lo[k]) sd->box_lo[k] = p[k];
            if (p[k] > sd->box_hi[k]) sd->box_hi[k] = p[k];
        }
    }
    sd->lowbit = dt->lowbit;
    box_bounds(sd);
    for (i = 0; i < S->nlink; i++) {
        st = vp_dt_insert(sd, PT(dt, S->glob[i]), VP_DT_NONE, &sv);
        if (st != VP_OK) return st == VP_ENOMEM ? VP_ENOMEM : VP_EDEGEN;
        if (sv != i) return VP_EDEGEN;
    }
    if (sd->dim == 3) return VP_OK;
    /* a flat link: the far vertex of a finite tet outside a finite boundary facet */
    for (q = 0; q < S->nk && x == VP_DT_NONE; q++) {
        uint32_t out = S->outs[q];
        if (S->kverts[4 * (size_t)q + 3] == VP_DT_GHOST) continue;
        x = TET(dt, out >> 2)[out & 3u];
        if (x == VP_DT_GHOST) x = VP_DT_NONE;
    }
    if (x == VP_DT_NONE) /* every finite tet contains v: the rest is the link, flat */
        return S->nfin == dt->nalive - dt->nghost ? RM_FLAT : VP_EDEGEN;
    S->glob[S->nlink] = x;
    st = vp_dt_insert(sd, PT(dt, x), VP_DT_NONE, &sv);
    if (st != VP_OK) return st == VP_ENOMEM ? VP_ENOMEM : VP_EDEGEN;
    if (sv != S->nlink || sd->dim != 3) return VP_EDEGEN;
    *wid = sv;
    return VP_OK;
}

/* The oriented local ids of boundary facet q (the ghost stays VP_DT_GHOST). */
static void rm_bface(const vp_dt_t *dt, const rm_star_t *S, uint32_t q, uint32_t f[3])
{
    uint32_t iv = S->from[q] & 3u, m;
    for (m = 0; m < 3; m++) {
        uint32_t x = S->kverts[4 * (size_t)q + FI[iv][m]];
        f[m] = x == VP_DT_GHOST ? x : VREC(dt, x).tet & VMASK;
    }
}

static void sort3(const uint32_t f[3], uint32_t s[3])
{
    uint32_t a = f[0], b = f[1], c = f[2], t;
    if (a > b) { t = a; a = b; b = t; }
    if (b > c) { t = b; b = c; c = t; }
    if (a > b) { t = a; a = b; b = t; }
    s[0] = a; s[1] = b; s[2] = c;
}

static uint32_t rm_hash(const uint32_t s[3], uint32_t mask)
{
    return ((s[0] * 0x9E3779B1u) ^ (s[1] * 0x85EBCA77u) ^ (s[2] * 0xC2B2AE3Du)) >> 7 & mask;
}

/* Selects the small triangulation's tets inside the cavity (payload marks, see RM_PAY): the
 * facet table of the boundary and a queue in its free space. *nkept, *ngk: kept tets, of
 * which ghost tets; *scratch_end: the end of the table and queue. VP_EDEGEN if a boundary
 * facet is missing or the fill leaks through one (never for a valid triangulation). */
static int rm_select(const vp_dt_t *dt, const rm_star_t *S, vp_dt_t *sd, uint32_t wid,
                     uint32_t *nkept, uint32_t *ngk, unsigned char **scratch_end)
{
    uint32_t hbits = 4, mask, q, t, K = 0, nmatch = 0, ng = 0, *tab, *queue;
    while ((1u << hbits) < 2u * S->nk) hbits++;
    mask = (1u << hbits) - 1u;
    tab = (uint32_t *)(((uintptr_t)gap_lo(sd) + 7u) & ~(uintptr_t)7u);
    queue = tab + 4 * ((size_t)mask + 1u);
    if ((uintptr_t)(queue + sd->nalive) > (uintptr_t)gap_hi(sd)) return VP_ENOMEM;
    *scratch_end = (unsigned char *)(queue + sd->nalive);
    for (q = 0; q <= mask; q++) tab[4 * q] = VP_DT_NONE;
    for (q = 0; q < S->nk; q++) {
        uint32_t f[3], s[3], h;
        rm_bface(dt, S, q, f);
        sort3(f, s);
        for (h = rm_hash(s, mask); tab[4 * h] != VP_DT_NONE; h = (h + 1u) & mask) {}
        tab[4 * h] = s[0]; tab[4 * h + 1] = s[1]; tab[4 * h + 2] = s[2]; tab[4 * h + 3] = q;
    }
    for (t = 0; t < sd->ntet_slots; t++) {
        uint32_t *w = TET(sd, t);
        if (w[0] != DEAD) memset(w + 8, 0xFF, RM_PAY * sizeof(uint32_t));
    }
    /* each facet once, from the tet with the smaller index */
    for (t = 0; t < sd->ntet_slots; t++) {
        uint32_t *w = TET(sd, t), j;
        if (w[0] == DEAD) continue;
        for (j = 0; j < 4; j++) {
            uint32_t u = w[4 + j] >> 2, f[3], s[3], h, b[3], bid;
            if (u < t) continue;
            f[0] = w[FI[j][0]]; f[1] = w[FI[j][1]]; f[2] = w[FI[j][2]];
            if (f[0] == wid || f[1] == wid || f[2] == wid) continue;
            sort3(f, s);
            for (h = rm_hash(s, mask); tab[4 * h] != VP_DT_NONE; h = (h + 1u) & mask)
                if (tab[4 * h] == s[0] && tab[4 * h + 1] == s[1] && tab[4 * h + 2] == s[2]) break;
            if (tab[4 * h] == VP_DT_NONE) continue;
            bid = tab[4 * h + 3];
            rm_bface(dt, S, bid, b);
            nmatch++;
            /* the same orientation: the cavity (where v was) is on t's side */
            if ((f[0] == b[0] && f[1] == b[1]) || (f[0] == b[1] && f[1] == b[2]) ||
                (f[0] == b[2] && f[1] == b[0])) {
                w[8 + 1 + j] = bid;
                w[8] = RM_SEED;
            } else {
                uint32_t *uw = TET(sd, u);
                uw[8 + 1 + (w[4 + j] & 3u)] = bid;
                uw[8] = RM_SEED;
            }
        }
    }
    if (nmatch != S->nk) return VP_EDEGEN;
    for (t = 0; t < sd->ntet_slots; t++) {
        uint32_t *w = TET(sd, t);
        if (w[0] != DEAD && w[8] == RM_SEED) {
            w[8] = K;
            queue[K++] = t;
        }
    }
    for (q = 0; q < K; q++) {
        const uint32_t *w = TET(sd, queue[q]);
        uint32_t j;
        if (w[0] == wid || w[1] == wid || w[2] == wid || w[3] == wid) return VP_EDEGEN;
        ng += w[3] == VP_DT_GHOST;
        for (j = 0; j < 4; j++) {
            uint32_t *uw;
            if (w[8 + 1 + j] != VP_DT_NONE) continue;
            uw = TET(sd, w[4 + j] >> 2);
            if (uw[8 + 1 + (w[4 + j] & 3u)] != VP_DT_NONE) return VP_EDEGEN;
            if (uw[8] != VP_DT_NONE) continue;
            if (K == sd->nalive) return VP_EDEGEN;
            uw[8] = K;
            queue[K++] = w[4 + j] >> 2;
        }
    }
    *nkept = K;
    *ngk = ng;
    return VP_OK;
}

/* Replaces the star by the kept tets (nothing can fail here). */
static void rm_commit(vp_dt_t *dt, const rm_star_t *S, const vp_dt_t *sd, uint32_t v,
                      uint32_t K, uint32_t ngk, uint32_t *created, uint32_t *cfrom)
{
    uint32_t k, t, q, ng_star = S->nk - S->nfin;
    for (k = 0; k < K; k++) created[k] = k < S->nk ? S->killed[k] : tet_take(dt);
    for (q = K; q < S->nk; q++) tet_release(dt, S->killed[q]);
    for (t = 0; t < sd->ntet_slots; t++) {
        const uint32_t *sw = TET(sd, t);
        uint32_t slot, *W, i, cf = VP_DT_NONE;
        if (sw[0] == DEAD || sw[8] == VP_DT_NONE) continue;
        slot = created[sw[8]];
        W = TET(dt, slot);
        for (i = 0; i < 4; i++) W[i] = sw[i] == VP_DT_GHOST ? VP_DT_GHOST : S->glob[sw[i]];
        for (i = 0; i < 4; i++) {
            uint32_t bid = sw[8 + 1 + i], r;
            if (bid != VP_DT_NONE) {
                r = S->outs[bid];
                W[4 + i] = r;
                TET(dt, r >> 2)[4 + (r & 3u)] = 4u * slot + i;
                if (cf == VP_DT_NONE) cf = S->from[bid];
            } else {
                r = sw[4 + i];
                W[4 + i] = 4u * created[TET(sd, r >> 2)[8]] + (r & 3u);
            }
        }
        cfrom[sw[8]] = cf;
        for (i = 0; i < 4; i++)
            if (W[i] != VP_DT_GHOST) VREC(dt, W[i]).tet = slot; /* the link's tags go too */
    }
    VREC(dt, v).tet = VP_DT_NONE;
    dt->ninserted--;
    dt->nalive = dt->nalive - S->nk + K;
    dt->nghost = dt->nghost - ng_star + ngk;
    dt->killed = S->killed;
    dt->killed_verts = S->kverts;
    dt->created = created;
    dt->created_from = cfrom;
    dt->nkilled = S->nk;
    dt->ncreated = K;
    dt->last_tet = created[0];
}

int vp_dt_remove(vp_dt_t *dt, uint32_t v)
{
    rm_star_t S;
    vp_dt_t sd;
    uint32_t t0, K = 0, ngk = 0, wid, extra, *created;
    size_t X = 0, need;
    unsigned char *scratch_end = NULL;
    int st, attempt;
    if (!dt || v >= dt->nvert) return VP_EINVAL;
    t0 = VREC(dt, v).tet;
    if (t0 == VPEND) { /* flat set: a pending vertex just leaves it */
        VREC(dt, v).tet = VP_DT_NONE;
        flat_replay(dt);
        return VP_OK;
    }
    if (dt->dim < 3 || !vp_dt_alive(dt, t0) || !tet_has(TET(dt, t0), v)) return VP_EINVAL;
    if (dt->ninserted <= 4) {
        drop_to_flat(dt, v);
        return VP_OK;
    }
    st = rm_star(dt, v, t0, &S);
    if (st != VP_OK) return st;
    /* new tet slots (beyond the star's and the free list's) grow from the bottom of the free
     * space: the small triangulation sits above a reserve for them, rebuilt once if short */
    for (attempt = 0;; attempt++) {
        st = rm_link_dt(dt, &S, gap_lo(dt) + X, &sd, &wid);
        if (st == RM_FLAT) {
            rm_untag(dt, &S);
            drop_to_flat(dt, v);
            return VP_OK;
        }
        if (st == VP_OK) st = rm_select(dt, &S, &sd, wid, &K, &ngk, &scratch_end);
        if (st != VP_OK) {
            rm_untag(dt, &S);
            return st;
        }
        extra = K > S.nk + dt->nfree ? K - S.nk - dt->nfree : 0;
        need = (size_t)extra * dt->stride * sizeof(uint32_t);
        if (need <= X) break;
        if (attempt) {
            rm_untag(dt, &S);
            return VP_ENOMEM;
        }
        X = (need + 7u) & ~(size_t)7u;
    }
    /* the created lists over the top of the small triangulation's block (its tets stay) */
    if ((size_t)((unsigned char *)S.oldw - gap_lo(&sd)) < 2u * (size_t)K * sizeof(uint32_t)) {
        rm_untag(dt, &S);
        return VP_ENOMEM;
    }
    created = S.oldw - K;
    rm_commit(dt, &S, &sd, v, K, ngk, created, created - K);
    {
        /* the scratch at its peak: S's arrays, and the small triangulation's block at the
         * most it held (its own high water, or its tets, table, queue and vertex records) */
        size_t blk = (size_t)(scratch_end - sd.mem_lo) + (size_t)sd.nvert * sizeof(vp_dt_vertex_t);
        if (sd.high_water > blk) blk = sd.high_water;
        note_high_water(dt, (size_t)(gap_hi(dt) - (unsigned char *)S.oldw) + blk);
    }
    return VP_OK;
}

#endif /* VP_CORE_MCU */
