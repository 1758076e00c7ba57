/* libFuzzer target: the Delaunay triangulation (core/vp_dt.c) under any sequence of insertions
 * and removals of points on a small integer lattice (scaled by a power of two), so that four
 * coplanar and five cospherical points are the rule, in an arena the input sizes (3 to 51 KB:
 * VP_ENOMEM on most calls; or 1 MB), walks started from any tet slot, live or not. After every
 * call:
 *   - the status is VP_OK, VP_EDUP (a point already there, the vertex named), VP_EINVAL (a
 *     removal of what is not a vertex, a tet not in conflict) or VP_ENOMEM, and a call that
 *     fails changed nothing (the tets, ghosts included, as sets of points, and the counts); a
 *     point inserted is a new record;
 *   - vp_dt_check passes; every vertex record holds its point, a live vertex a live tet that has
 *     it (VP_DT_PENDING while flat), a removed one VP_DT_NONE;
 *   - checked with exact 128-bit integer determinants of this file's own (not vp_pred's, though
 *     agreeing with them on random cases: predicates_agree): every finite tet is positively
 *     oriented, no point of the set lies strictly inside a finite tet's circumsphere, every
 *     point lies on the inner side of (or on) every hull facet, the tets use exactly the points
 *     of the set, and with fewer than four points or all of them coplanar the set is pending
 *     (dim < 3), else tetrahedralised; a tet said to be in conflict with a point
 *     is refused only where the point lies on or outside its circumsphere (behind or on its hull
 *     facet) and taken only where on or inside;
 *   - the tets are those of the same points inserted from scratch in the reverse order (the
 *     symbolic perturbation makes the triangulation of a point set unique: vp_dt.h).
 * Never a crash, never a sanitizer report. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_dt.h"
#include "vp_pred.h"
#include "vp_status.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAXP 48          /* points in the set at most */
#define MAXOPS 96        /* calls per input at most */
#define BIG_ARENA ((size_t)1 << 20)

#define fail() __builtin_trap()

__extension__ typedef __int128 i128;

typedef struct { long x[3]; } ipt_t; /* lattice coordinates (the point is x * 2^scale) */

static int sgn(i128 v) { return (v > 0) - (v < 0); }

/* orient3d(a, b, c, d) as vp_pred.h states it: the sign of ((b - a) x (c - a)) . (d - a) */
static int iorient(const ipt_t *a, const ipt_t *b, const ipt_t *c, const ipt_t *d)
{
    i128 u[3], v[3], w[3];
    int k;
    for (k = 0; k < 3; k++) {
        u[k] = b->x[k] - a->x[k];
        v[k] = c->x[k] - a->x[k];
        w[k] = d->x[k] - a->x[k];
    }
    return sgn((u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] + (u[0] * v[1] - u[1] * v[0]) * w[2]);
}

/* the lifted 4x4 determinant det [p_i - e, |p_i - e|^2], expanded along its last column */
static int lifted(const ipt_t *const *p, const ipt_t *e)
{
    i128 m[4][4], det = 0;
    int i, k;
    for (i = 0; i < 4; i++) {
        i128 l = 0;
        for (k = 0; k < 3; k++) {
            m[i][k] = p[i]->x[k] - e->x[k];
            l += m[i][k] * m[i][k];
        }
        m[i][3] = l;
    }
    for (i = 0; i < 4; i++) {
        i128 r[3][3];
        int ri = 0, q;
        for (q = 0; q < 4; q++) {
            if (q == i) continue;
            for (k = 0; k < 3; k++) r[ri][k] = m[q][k];
            ri++;
        }
        det += (i % 2 ? 1 : -1) * m[i][3] *
               (r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]));
    }
    return sgn(det);
}

/* > 0 when e lies strictly inside the sphere through a, b, c, d (any orientation): the lifted
 * determinant's sign times the orientation's, times the sign that the corner tet (0,0,0),
 * (4,0,0), (0,4,0), (0,0,4) with e = (1,1,1), plainly inside, gives */
static int iinsphere(const ipt_t *a, const ipt_t *b, const ipt_t *c, const ipt_t *d, const ipt_t *e)
{
    static const ipt_t k0 = {{0, 0, 0}}, k1 = {{4, 0, 0}}, k2 = {{0, 4, 0}}, k3 = {{0, 0, 4}}, ke = {{1, 1, 1}};
    static int cal; /* worked out on the first call */
    const ipt_t *kp[4] = {&k0, &k1, &k2, &k3}, *p[4] = {a, b, c, d};
    if (!cal) cal = lifted(kp, &ke) * iorient(&k0, &k1, &k2, &k3);
    return lifted(p, e) * iorient(a, b, c, d) * cal;
}

/* Once per process: this file's determinants and vp_pred's give the same signs on 200,000 random
 * lattice cases (zeros included), so that where the two disagree below, the triangulation is at
 * fault and not the checker. */
static void predicates_agree(void)
{
    uint32_t r = 12345u;
    int it, i, k;
    for (it = 0; it < 200000; it++) {
        ipt_t p[5];
        double d[5][3];
        int o;
        for (i = 0; i < 5; i++)
            for (k = 0; k < 3; k++) {
                r = r * 1103515245u + 12345u;
                p[i].x[k] = (long)((r >> 16) % 7u) - 3;
                d[i][k] = (double)p[i].x[k];
            }
        o = iorient(&p[0], &p[1], &p[2], &p[3]);
        if (o != vp_orient3d(d[0], d[1], d[2], d[3])) fail();
        if (o > 0 && iinsphere(&p[0], &p[1], &p[2], &p[3], &p[4]) != vp_insphere(d[0], d[1], d[2], d[3], d[4])) fail();
    }
}

typedef struct {
    uint32_t id;   /* vertex record */
    ipt_t ip;      /* lattice point */
} member_t;

#define MAXGONE 256

typedef struct {
    member_t m[MAXP];
    int n;
    int scale;
    uint32_t gone[MAXGONE]; /* records removed */
    int ngone;
} set_t;

static double coord(const set_t *S, long v) { return ldexp((double)v, S->scale); }

static void to_coords(const set_t *S, const ipt_t *ip, double *p)
{
    int q;
    for (q = 0; q < 3; q++) p[q] = coord(S, ip->x[q]);
}

/* the member whose vertex is v, or -1 */
static int member_of(const set_t *S, uint32_t v)
{
    int i;
    for (i = 0; i < S->n; i++)
        if (S->m[i].id == v) return i;
    return -1;
}

/* the lattice point of bytes b[0..2] into ip, and as coordinates into p */
static void lattice(const set_t *S, const uint8_t *b, int range, ipt_t *ip, double *p)
{
    int q;
    for (q = 0; q < 3; q++) ip->x[q] = (long)(b[q] % (2 * range + 1)) - range;
    to_coords(S, ip, p);
}

static void add_member(set_t *S, uint32_t v, const ipt_t *ip)
{
    S->m[S->n].id = v;
    S->m[S->n].ip = *ip;
    S->n++;
}

/* a tet as its points' lattice coordinates, vertices sorted (ghost last), to compare
 * triangulations whose records are numbered differently */
typedef struct { long k[12]; int ghost; } tkey_t;

static int key_cmp(const void *a, const void *b)
{
    const tkey_t *p = a, *q = b;
    int i;
    if (p->ghost != q->ghost) return p->ghost < q->ghost ? -1 : 1;
    for (i = 0; i < 12; i++)
        if (p->k[i] != q->k[i]) return p->k[i] < q->k[i] ? -1 : 1;
    return 0;
}

static int pt_cmp(const long *a, const long *b)
{
    int i;
    for (i = 0; i < 3; i++)
        if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}

/* the member at lattice point x, or -1 */
static int member_at(const set_t *S, const long *x)
{
    int i;
    for (i = 0; i < S->n; i++)
        if (!pt_cmp(S->m[i].ip.x, x)) return i;
    return -1;
}

/* An insertion of ip answered st with vertex v (the records nvert0 before, nvert1 after): a new
 * record for a point not yet there, joining the set; the vertex already at ip for VP_EDUP */
static void insert_outcome(set_t *S, int st, uint32_t v, const ipt_t *ip, uint32_t nvert0, uint32_t nvert1)
{
    if (st == VP_OK) {
        if (v < nvert0 || nvert1 != nvert0 + 1) fail();  /* not a new record */
        if (member_at(S, ip->x) >= 0) fail();            /* a duplicate taken as new */
        add_member(S, v, ip);
    } else if (st == VP_EDUP) {
        int mi = member_at(S, ip->x);
        if (mi < 0 || S->m[mi].id != v) fail();          /* a duplicate of what? */
    } else if (st != VP_ENOMEM) {
        fail();
    }
}

/* the sorted tet keys of dt into keys (room for cap); returns the count, -1 on overflow or a
 * vertex not in the set */
static int tet_keys(const vp_dt_t *dt, const set_t *S, const uint32_t *ids, tkey_t *keys, int cap)
{
    uint32_t t;
    int n = 0;
    for (t = 0; t < dt->ntet_slots; t++) {
        const uint32_t *w;
        long pts[4][3];
        int i, j, np = 0;
        if (!vp_dt_alive(dt, t)) continue;
        if (n >= cap) return -1;
        w = vp_dt_tet(dt, t);
        memset(&keys[n], 0, sizeof keys[n]);
        for (i = 0; i < 4; i++) {
            int mi = -1;
            if (w[i] == VP_DT_GHOST) { keys[n].ghost = 1; continue; }
            for (j = 0; j < S->n; j++)
                if ((ids ? ids[j] : S->m[j].id) == w[i]) mi = j;
            if (mi < 0) return -1;
            memcpy(pts[np++], S->m[mi].ip.x, sizeof pts[0]);
        }
        /* insertion sort of the points */
        for (i = 1; i < np; i++)
            for (j = i; j > 0 && pt_cmp(pts[j - 1], pts[j]) > 0; j--) {
                long tmp[3];
                memcpy(tmp, pts[j], sizeof tmp);
                memcpy(pts[j], pts[j - 1], sizeof tmp);
                memcpy(pts[j - 1], tmp, sizeof tmp);
            }
        for (i = 0; i < np; i++) memcpy(&keys[n].k[3 * i], pts[i], sizeof pts[i]);
        n++;
    }
    qsort(keys, (size_t)n, sizeof keys[0], key_cmp);
    return n;
}

#define MAXTETS 2048

static int same_keys(const tkey_t *a, int na, const tkey_t *b, int nb)
{
    int i;
    if (na != nb) return 0;
    for (i = 0; i < na; i++)
        if (key_cmp(&a[i], &b[i])) return 0;
    return 1;
}

/* 1 when the points of S are all coplanar (or fewer than four) */
static int flat(const set_t *S)
{
    int i, j = -1, k = -1, l;
    if (S->n < 4) return 1;
    /* a second point apart from the first, a third off their line, then any off their plane */
    for (i = 1; i < S->n && j < 0; i++)
        if (pt_cmp(S->m[i].ip.x, S->m[0].ip.x)) j = i;
    if (j < 0) return 1;
    for (i = 1; i < S->n && k < 0; i++) {
        long u[3], v[3];
        int q;
        for (q = 0; q < 3; q++) {
            u[q] = S->m[j].ip.x[q] - S->m[0].ip.x[q];
            v[q] = S->m[i].ip.x[q] - S->m[0].ip.x[q];
        }
        if (u[1] * v[2] - u[2] * v[1] || u[2] * v[0] - u[0] * v[2] || u[0] * v[1] - u[1] * v[0]) k = i;
    }
    if (k < 0) return 1;
    for (l = 1; l < S->n; l++)
        if (iorient(&S->m[0].ip, &S->m[j].ip, &S->m[k].ip, &S->m[l].ip)) return 0;
    return 1;
}

/* every check of the header on dt holding exactly the points of S; dt's tet keys into now (the
 * next call's reference, should it fail), their count returned */
static int check_all(vp_dt_t *dt, const set_t *S, void *scratch_arena, tkey_t *now)
{
    static tkey_t b[MAXTETS];
    static vp_dt_t fresh;
    static uint32_t fid[MAXP];
    uint32_t t;
    int i, na, nb, used[MAXP];
#ifndef FUZZ_DT_NO_SELF_CHECK /* left out to show the checks below see a wrong triangulation alone */
    if (vp_dt_check(dt) != VP_OK) fail();
#endif
    if (flat(S) != (dt->dim < 3)) fail();
    for (i = 0; i < S->n; i++) {
        const vp_dt_vertex_t *r = vp_dt_vertex(dt, S->m[i].id);
        int q;
        for (q = 0; q < 3; q++)
            if (r->xyz[q] != coord(S, S->m[i].ip.x[q])) fail(); /* a record's point changed */
        if (dt->dim < 3) {
            if (r->tet != VP_DT_PENDING) fail();
        } else {
            const uint32_t *w;
            if (!vp_dt_alive(dt, r->tet)) fail();
            w = vp_dt_tet(dt, r->tet);
            if (w[0] != S->m[i].id && w[1] != S->m[i].id && w[2] != S->m[i].id && w[3] != S->m[i].id) fail();
        }
    }
    for (i = 0; i < S->ngone; i++)
        if (vp_dt_vertex(dt, S->gone[i])->tet != VP_DT_NONE) fail(); /* a removed record revived */
    memset(used, 0, sizeof used);
    if (dt->dim == 3) {
        for (t = 0; t < dt->ntet_slots; t++) {
            const uint32_t *w;
            int mi[4], q;
            if (!vp_dt_alive(dt, t)) continue;
            w = vp_dt_tet(dt, t);
            for (q = 0; q < 4; q++) {
                if (w[q] == VP_DT_GHOST && q < 3) fail(); /* the ghost only in slot 3 */
                mi[q] = w[q] == VP_DT_GHOST ? -1 : member_of(S, w[q]);
                if (w[q] != VP_DT_GHOST && mi[q] < 0) fail(); /* a vertex not in the set */
                if (mi[q] >= 0) used[mi[q]] = 1;
            }
            if (w[3] == VP_DT_GHOST) {
                /* a hull facet: every point on its inner (negative) side or on it */
                for (i = 0; i < S->n; i++)
                    if (iorient(&S->m[mi[0]].ip, &S->m[mi[1]].ip, &S->m[mi[2]].ip, &S->m[i].ip) > 0) fail();
                continue;
            }
            if (iorient(&S->m[mi[0]].ip, &S->m[mi[1]].ip, &S->m[mi[2]].ip, &S->m[mi[3]].ip) <= 0) fail();
            for (i = 0; i < S->n; i++)
                if (iinsphere(&S->m[mi[0]].ip, &S->m[mi[1]].ip, &S->m[mi[2]].ip, &S->m[mi[3]].ip, &S->m[i].ip) > 0)
                    fail(); /* a point strictly inside an empty sphere */
        }
        for (i = 0; i < S->n; i++)
            if (!used[i]) fail(); /* a point of the set in no tet */
    }
    /* the same points from scratch, in the reverse order */
    if (vp_dt_init(&fresh, scratch_arena, BIG_ARENA, 0) != VP_OK) fail();
    for (i = S->n - 1; i >= 0; i--) {
        double p[3];
        to_coords(S, &S->m[i].ip, p);
        if (vp_dt_insert(&fresh, p, VP_DT_NONE, &fid[i]) != VP_OK) fail();
    }
    na = tet_keys(dt, S, NULL, now, MAXTETS);
    nb = tet_keys(&fresh, S, fid, b, MAXTETS);
    if (na < 0 || nb < 0) fail();
    if (!same_keys(now, na, b, nb)) fail();
    return na;
}

/* a snapshot of everything a failed call must leave as it was */
typedef struct {
    uint32_t ntet_slots, nalive, nvert, ninserted;
    int dim;
} shape_t;

static void shape(const vp_dt_t *dt, shape_t *s)
{
    s->ntet_slots = dt->ntet_slots;
    s->nalive = dt->nalive;
    s->nvert = dt->nvert;
    s->ninserted = dt->ninserted;
    s->dim = dt->dim;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static unsigned char *arena, *big;
    static set_t S;
    static tkey_t before[MAXTETS], after[MAXTETS];
    vp_dt_t dt;
    size_t bytes, pos;
    int range, op, na = 0; /* the tets now, in before: none yet */
    if (!arena) {
        predicates_agree();
        if (!((arena = malloc(BIG_ARENA)) && (big = malloc(BIG_ARENA)))) return 0;
    }
    if (size < 2) return 0;
    /* the arena: 3 to 51 KB (VP_ENOMEM early), or 1 MB */
    bytes = data[0] >= 192 ? BIG_ARENA : (size_t)3072 + (size_t)data[0] * 256;
    /* the lattice: coordinates in [-R, R], R 1, 2, 3 or 40, times 2^scale, scale -3..4 */
    range = (int[]){1, 2, 3, 40}[data[1] & 3];
    memset(&S, 0, sizeof S);
    S.scale = ((data[1] >> 2) & 7) - 3;
    if (vp_dt_init(&dt, arena, bytes, (size_t)(data[1] >> 5) * 4) != VP_OK) return 0;
    for (pos = 2, op = 0; pos + 4 <= size && op < MAXOPS; pos += 4, op++) {
        const uint8_t *b = data + pos;
        shape_t s0, s1;
        int st;
        shape(&dt, &s0); /* with before: what a failed call must not change */
        switch (b[0] % 8) {
        case 5: { /* insert a lattice point into the circumsphere of a tet said to hold it */
            double p[3];
            uint32_t v = VP_DT_NONE, t = VP_DT_NONE, k = (uint32_t)(b[0] >> 3) * 251u + b[3], seen = 0, u;
            ipt_t ip;
            int want = -2; /* 1 accepted, 0 refused (VP_EINVAL), -1 either */
            lattice(&S, b + 1, range, &ip, p);
            for (u = 0; u < dt.ntet_slots && dt.dim == 3; u++)
                if (vp_dt_alive(&dt, u) && seen++ == k % dt.nalive) t = u;
            if (t == VP_DT_NONE || S.n >= MAXP) continue;
            {
                const uint32_t *w = vp_dt_tet(&dt, t);
                int mi[4], q, sgn_;
                for (q = 0; q < 4; q++) mi[q] = w[q] == VP_DT_GHOST ? -1 : member_of(&S, w[q]);
                if (mi[0] < 0 || mi[1] < 0 || mi[2] < 0 || (w[3] != VP_DT_GHOST && mi[3] < 0)) fail();
                if (w[3] == VP_DT_GHOST) /* beyond the hull facet: its positive side */
                    sgn_ = iorient(&S.m[mi[0]].ip, &S.m[mi[1]].ip, &S.m[mi[2]].ip, &ip);
                else
                    sgn_ = iinsphere(&S.m[mi[0]].ip, &S.m[mi[1]].ip, &S.m[mi[2]].ip, &S.m[mi[3]].ip, &ip);
                want = sgn_ > 0 ? 1 : sgn_ < 0 ? 0 : -1;
            }
            st = vp_dt_insert_in_conflict(&dt, p, t, &v);
            if (st == VP_OK && want == 0) fail();     /* accepted outside the circumsphere */
            if (st == VP_EINVAL) {
                if (want == 1) fail();                /* refused inside it */
            } else {
                insert_outcome(&S, st, v, &ip, s0.nvert, dt.nvert);
            }
            break;
        }
        case 6: case 7: { /* remove a member (or, now and then, something that is not one) */
            uint32_t v;
            int mi = -1;
            if (S.n > 0 && !(b[2] == 255)) {
                mi = b[1] % S.n;
                v = S.m[mi].id;
            } else {
                v = b[3] & 1 ? VP_DT_GHOST : (uint32_t)b[1] + dt.nvert;
            }
            st = vp_dt_remove(&dt, v);
            if (mi < 0) {
                if (st != VP_EINVAL) fail();
            } else if (st == VP_OK) {
                S.m[mi] = S.m[--S.n];
                if (S.ngone < MAXGONE) S.gone[S.ngone++] = v;
                if (vp_dt_remove(&dt, v) != VP_EINVAL) fail(); /* removed twice */
            } else if (st != VP_ENOMEM) {
                fail();
            }
            break;
        }
        case 4: { /* a batch: the next 1 to 6 points (three bytes each) at once */
            double xyz[3 * 6];
            uint32_t ids[6];
            ipt_t ips[6];
            int n = 1 + b[1] % 6, i;
            if (pos + 4 + 3 * (size_t)n > size || S.n + n > MAXP) continue;
            for (i = 0; i < n; i++) lattice(&S, data + pos + 4 + 3 * i, range, &ips[i], xyz + 3 * i);
            pos += 3 * (size_t)n;
            st = vp_dt_insert_batch(&dt, xyz, (uint32_t)n, ids);
            if (st != VP_OK && st != VP_ENOMEM) fail();
            for (i = 0; i < n; i++) {
                int mi;
                if (ids[i] == VP_DT_NONE) {
                    if (st == VP_OK) fail(); /* left out with no reason */
                    continue;
                }
                if (memcmp(vp_dt_point(&dt, ids[i]), xyz + 3 * i, 3 * sizeof(double))) fail();
                mi = member_of(&S, ids[i]);
                if (mi >= 0) {
                    if (pt_cmp(S.m[mi].ip.x, ips[i].x)) fail();
                    continue;
                }
                if (member_at(&S, ips[i].x) >= 0) fail(); /* a point already there made new */
                add_member(&S, ids[i], &ips[i]);
            }
            if (st == VP_ENOMEM) {
                /* what was inserted stays; the counts before are no reference */
                na = check_all(&dt, &S, big, before);
                continue;
            }
            break;
        }
        default: { /* insert a lattice point */
            double p[3];
            uint32_t v = VP_DT_NONE;
            ipt_t ip;
            lattice(&S, b + 1, range, &ip, p);
            if (S.n >= MAXP) continue;
            /* the walk from the last tet made, or from any slot (a dead one or past the end: the
             * walk starts elsewhere) */
            st = vp_dt_insert(&dt, p, (b[0] & 16) ? VP_DT_NONE : (uint32_t)(b[0] >> 5) * 97u % (dt.ntet_slots + 2u), &v);
            insert_outcome(&S, st, v, &ip, s0.nvert, dt.nvert);
        }
        }
        shape(&dt, &s1);
        if (st != VP_OK) {
            if (memcmp(&s0, &s1, sizeof s0)) fail(); /* a failed call changed the counts */
            if (!same_keys(before, na, after, tet_keys(&dt, &S, NULL, after, MAXTETS))) fail();
        }
        na = check_all(&dt, &S, big, before);
    }
    return 0;
}
