/* vp_logverify — a proof check of a session log from the log alone (see vp_logverify.h).
 * Nothing here comes from core/vp_planner.c: the free space is rebuilt from the records. */
#include "vp_logverify.h"
#include "vp_vec3.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct vp_lv_probe {
    double o[3], d[3];   /* origin relative to Omega's centre, unit direction */
    double len;          /* the free part: o .. o + len d */
    uint32_t record;
    uint64_t born;       /* PROBE and MOVE records up to and with it (the header's proof life) */
};

struct vp_lv_entry {
    uint64_t key;        /* hash of the quantised line */
    uint32_t probe, next;
};

#define LV_NONE UINT32_MAX
/* Quantisation of a line: its unit direction in cells of LV_HU, the foot of the perpendicular
 * from Omega's centre in cells of LV_HC x diameter. A move's line is known to within a bound
 * that grows as the move gets shorter; a query visits every cell within that bound, and a
 * move so short that this would be more than LV_MAX_CELLS cells looks at every probe. */
#define LV_HU 1e-3
#define LV_HC 1e-3
#define LV_MAX_CELLS 4096
/* Probes are also hashed on their origin (cells of LV_HO x diameter): a short move looks first
 * at the probes fired from either of its ends, and scans them all only when those fall short. */
#define LV_HO 1e-6
#define LV_ORIGIN_SEED 0x6A09E667F3BCC909ull
/* A free part within eps (at least this many noise tolerances) of a contact proves nothing, as
 * in the planner (core/planner/contact.c) */
#define LV_CONTACT_REACH_NOISE 4.0
/* The tube rule looks at no more lattice points than this per move (the box about its capsule),
 * nor more cubes, the split ones too: a larger one is unproven (a body's move of that many
 * feature sizes is not a move a planner makes), and a free part longer than LV_TUBE_STEPS steps
 * of rho / 2 proves no tube */
#define LV_TUBE_LATTICE 1e9
#define LV_TUBE_STEPS 1e5
/* The planner proves a tube with a margin m = rho / 32 (vp_logverify.h): a cube of half diagonal
 * at most m that meets the capsule is always seen; a lattice cube (half side rho / 4, half
 * diagonal 0.433 rho) halved four times has a half diagonal of 0.027 rho */
#define LV_TUBE_MARGIN (1.0 / 32.0)
#define LV_TUBE_DEPTH 4
#define LV_SQRT3 1.7320508075688773


static double dist3(const double *a, const double *b)
{
    double d[3] = { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
    return sqrt(vp_dot3(d, d));
}

static int64_t cell(double x, double h)
{
    double c = floor(x / h);
    if (c > 1e15) c = 1e15;
    if (c < -1e15) c = -1e15;
    return (int64_t)c;
}

static uint64_t mix(uint64_t h, int64_t v)
{
    h ^= (uint64_t)v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 31);
}

static uint64_t key6(const int64_t *k)
{
    uint64_t h = 0x243F6A8885A308D3ull;
    int i;
    for (i = 0; i < 6; i++) h = mix(h, k[i]);
    return h;
}

static uint64_t key3(const int64_t *k)
{
    uint64_t h = LV_ORIGIN_SEED;
    int i;
    for (i = 0; i < 3; i++) h = mix(h, k[i]);
    return h;
}

/* the foot of the perpendicular from the origin onto the line through p along unit u */
static void foot(const double *p, const double *u, double *c)
{
    double s = vp_dot3(p, u);
    int k;
    for (k = 0; k < 3; k++) c[k] = p[k] - s * u[k];
}

static void line_cells(const vp_logverify_t *v, const double *u, const double *c, int64_t *k)
{
    int i;
    for (i = 0; i < 3; i++) {
        k[i] = cell(u[i], v->hu);
        k[3 + i] = cell(c[i], v->hc);
    }
}

static int rehash(vp_lv_hash_t *H, size_t slots)
{
    uint32_t *h = malloc(slots * sizeof *h);
    size_t i;
    if (!h) return VP_ENOMEM;
    for (i = 0; i < slots; i++) h[i] = LV_NONE;
    for (i = 0; i < H->n; i++) {
        size_t s = (size_t)(H->ent[i].key & (slots - 1));
        H->ent[i].next = h[s];
        h[s] = (uint32_t)i;
    }
    free(H->head);
    H->head = h;
    H->mask = slots - 1;
    return VP_OK;
}

static int grow(void **p, size_t *cap, size_t need, size_t size)
{
    size_t c = *cap ? *cap : 1024;
    void *q;
    if (need <= *cap) return VP_OK;
    while (c < need) c *= 2;
    q = realloc(*p, c * size);
    if (!q) return VP_ENOMEM;
    *p = q;
    *cap = c;
    return VP_OK;
}

static int add_entry(vp_lv_hash_t *H, uint64_t key, uint32_t probe)
{
    size_t s;
    int st;
    if ((st = grow((void **)&H->ent, &H->cap, H->n + 1, sizeof *H->ent)) != VP_OK) return st;
    if (!H->head || H->n + 1 > (H->mask + 1) / 2)
        if ((st = rehash(H, H->head ? 2 * (H->mask + 1) : 4096)) != VP_OK) return st;
    s = (size_t)(key & H->mask);
    H->ent[H->n].key = key;
    H->ent[H->n].probe = probe;
    H->ent[H->n].next = H->head[s];
    H->head[s] = (uint32_t)H->n;
    H->n++;
    return VP_OK;
}

static void hash_free(vp_lv_hash_t *H)
{
    free(H->ent);
    free(H->head);
}

int vp_logverify_begin(vp_logverify_t *v, const vp_logfmt_header_t *h)
{
    const vp_planner_config_t *c = &h->cfg;
    int k;
    memset(v, 0, sizeof *v);
    v->cfg = *c;
    if (c->omega_kind == VP_OMEGA_BALL) {
        if (!(c->omega_radius > 0.0) || !isfinite(c->omega_radius)) return VP_EINVAL;
        for (k = 0; k < 3; k++) {
            if (!isfinite(c->omega_center[k])) return VP_EINVAL;
            v->centre[k] = c->omega_center[k];
        }
        v->diam = 2.0 * c->omega_radius;
    } else if (c->omega_kind == VP_OMEGA_BOX) {
        double e[3];
        for (k = 0; k < 3; k++) {
            if (!isfinite(c->omega_lo[k]) || !isfinite(c->omega_hi[k]) || !(c->omega_lo[k] < c->omega_hi[k]))
                return VP_EINVAL;
            v->centre[k] = 0.5 * c->omega_lo[k] + 0.5 * c->omega_hi[k];
            e[k] = c->omega_hi[k] - c->omega_lo[k];
        }
        v->diam = sqrt(vp_dot3(e, e));
    } else {
        return VP_EINVAL;
    }
    if (!isfinite(v->diam) || !(v->diam > 0.0)) return VP_EINVAL;
    v->tol = VP_LOGVERIFY_TOL_REL * v->diam;
    v->hu = LV_HU;
    v->hc = LV_HC * v->diam;
    v->ho = LV_HO * v->diam;
    v->res.tol = v->tol;
    {
        /* the planner's contact reach: eps, at least CONTACT_REACH_NOISE noise tolerances */
        double e = isfinite(c->eps) && c->eps > 0.0 ? c->eps : 0.0;
        double nt = isfinite(c->noise_tol) && c->noise_tol > 0.0 ? LV_CONTACT_REACH_NOISE * c->noise_tol : 0.0;
        /* less the tolerance: never a probe the planner trusted refused for rounding */
        v->ct_reach = (e > nt ? e : nt) - v->tol;
        if (v->ct_reach < 0.0) v->ct_reach = 0.0;
    }
    memcpy(v->res.pos, c->start, sizeof v->res.pos);
    v->res.ok = 1;
    if (c->clearance > 0.0 && c->min_feature > 0.0) {
        if (!isfinite(c->min_feature) || !isfinite(c->feature_margin) || !(c->feature_margin >= 0.0) ||
            !isfinite(c->clearance))
            return VP_EINVAL;
        v->tubes = 1;
        v->tcell = 2.0 * c->min_feature;
    }
    return VP_OK;
}

/* ---------- intervals of the segment p + s (q - p), s in [0,1] ---------- */

static int push_iv(vp_logverify_t *v, size_t *n, double a, double b)
{
    if (a < 0.0) a = 0.0;
    if (b > 1.0) b = 1.0;
    if (!(a <= b)) return VP_OK;
    if (grow((void **)&v->iv, &v->cap_iv, *n + 1, sizeof *v->iv) != VP_OK) return VP_ENOMEM;
    v->iv[*n][0] = a;
    v->iv[*n][1] = b;
    (*n)++;
    return VP_OK;
}

/* The part of [p,q] outside the open Omega (dOmega included): at most two intervals. */
static int outside_part(vp_logverify_t *v, const double *p, const double *q, size_t *n)
{
    const vp_planner_config_t *c = &v->cfg;
    if (c->omega_kind == VP_OMEGA_BOX) {
        /* outside: some coordinate <= lo or >= hi; each such set is a prefix or a suffix */
        double pre = -1.0, suf = 2.0;  /* [0,pre] and [suf,1] */
        int k, b;
        for (k = 0; k < 3; k++) {
            for (b = 0; b < 2; b++) {
                double w = b ? c->omega_hi[k] : c->omega_lo[k];
                double a0 = b ? p[k] - w : w - p[k];   /* >= 0: p is on the outer side */
                double a1 = b ? q[k] - w : w - q[k];
                if (a0 >= 0.0 && a1 >= 0.0) { pre = 1.0; continue; }
                if (a0 < 0.0 && a1 < 0.0) continue;
                if (a0 >= 0.0) {               /* from p out to the crossing */
                    double s = a0 / (a0 - a1);
                    if (s > pre) pre = s;
                } else {
                    double s = -a0 / (a1 - a0);
                    if (s < suf) suf = s;
                }
            }
        }
        if (pre >= 0.0 && push_iv(v, n, 0.0, pre) != VP_OK) return VP_ENOMEM;
        if (suf <= 1.0 && push_iv(v, n, suf, 1.0) != VP_OK) return VP_ENOMEM;
    } else {
        /* |p - m + s w|^2 >= r^2, from the foot of the perpendicular from m (no cancellation
         * of the squares of far ends) */
        double w[3], a[3], e[3], A, t0, h2, r = c->omega_radius;
        int k;
        for (k = 0; k < 3; k++) {
            w[k] = q[k] - p[k];
            a[k] = p[k] - c->omega_center[k];
        }
        A = vp_dot3(w, w);
        if (A == 0.0) {
            if (vp_dot3(a, a) >= r * r) return push_iv(v, n, 0.0, 1.0);
            return VP_OK;
        }
        t0 = -vp_dot3(a, w) / A;
        for (k = 0; k < 3; k++) e[k] = a[k] + t0 * w[k];
        h2 = r * r - vp_dot3(e, e);
        if (!(h2 > 0.0)) return push_iv(v, n, 0.0, 1.0);
        {
            double dt = sqrt(h2 / A);
            if (push_iv(v, n, 0.0, t0 - dt) != VP_OK || push_iv(v, n, t0 + dt, 1.0) != VP_OK) return VP_ENOMEM;
        }
    }
    return VP_OK;
}

/* If the probe's line holds [p,q] (p, q relative to the centre), the interval its free part covers. */
static int probe_part(vp_logverify_t *v, const vp_lv_probe_t *pr, const double *p, const double *q, size_t *n,
                      uint32_t *on_line)
{
    double wp[3], wq[3], ap, aq, dp[3], dq[3], t2 = v->tol * v->tol;
    int k;
    for (k = 0; k < 3; k++) {
        wp[k] = p[k] - pr->o[k];
        wq[k] = q[k] - pr->o[k];
    }
    ap = vp_dot3(wp, pr->d);
    aq = vp_dot3(wq, pr->d);
    for (k = 0; k < 3; k++) {
        dp[k] = wp[k] - ap * pr->d[k];
        dq[k] = wq[k] - aq * pr->d[k];
    }
    if (!(pr->len >= 0.0)) return VP_OK; /* withdrawn by a contact */
    if (v->cfg.proof_life > 0 && v->commands - pr->born > v->cfg.proof_life) return VP_OK; /* too old */
    if (vp_dot3(dp, dp) > t2 || vp_dot3(dq, dq) > t2) return VP_OK;
    (*on_line)++;
    if (aq == ap) return ap >= 0.0 && ap <= pr->len ? push_iv(v, n, 0.0, 1.0) : VP_OK;
    {
        double s0 = (0.0 - ap) / (aq - ap), s1 = (pr->len - ap) / (aq - ap), x;
        if (s0 > s1) { x = s0; s0 = s1; s1 = x; }
        return push_iv(v, n, s0, s1);
    }
}

static int cmp_iv(const void *a, const void *b)
{
    const double *x = a, *y = b;
    return x[0] < y[0] ? -1 : x[0] > y[0] ? 1 : 0;
}

static int visit(vp_logverify_t *v, uint32_t i, const double *p, const double *q, size_t *n, uint32_t *on_line)
{
    if (v->seen[i] == v->stamp) return VP_OK;
    v->seen[i] = v->stamp;
    return probe_part(v, &v->pr[i], p, q, n, on_line);
}

/* Sorts the intervals; the measure of [0,1] they leave uncovered, the number of gaps and the first. */
static double uncovered(vp_logverify_t *v, size_t n, uint32_t *gaps, double *g0, double *g1)
{
    double at = 0.0, gap = 0.0;
    size_t i;
    qsort(v->iv, n, sizeof *v->iv, cmp_iv);
    *gaps = 0;
    for (i = 0; i <= n; i++) {
        double s = i < n ? v->iv[i][0] : 1.0;
        if (s > at) {
            if (!*gaps) { *g0 = at; *g1 = s; }
            (*gaps)++;
            gap += s - at;
        }
        if (i < n && v->iv[i][1] > at) at = v->iv[i][1];
    }
    return gap;
}

/* The probes fired from within tol of x (cells of the origin hash). */
static int origin_parts(vp_logverify_t *v, const double *x, const double *p, const double *q, size_t *n,
                        uint32_t *on_line)
{
    int64_t k0[3], k1[3], k[3];
    int i, st;
    for (i = 0; i < 3; i++) {
        k0[i] = cell(x[i] - v->tol, v->ho);
        k1[i] = cell(x[i] + v->tol, v->ho);
    }
    for (k[0] = k0[0]; k[0] <= k1[0]; k[0]++)
        for (k[1] = k0[1]; k[1] <= k1[1]; k[1]++)
            for (k[2] = k0[2]; k[2] <= k1[2]; k[2]++) {
                uint64_t key = key3(k);
                uint32_t e;
                for (e = v->lines.head[key & v->lines.mask]; e != LV_NONE; e = v->lines.ent[e].next)
                    if (v->lines.ent[e].key == key && (st = visit(v, v->lines.ent[e].probe, p, q, n, on_line)) != VP_OK) return st;
            }
    return VP_OK;
}

/* The earlier probes whose line may hold [p,q]: the cells within the bound of its line. */
static int probe_parts(vp_logverify_t *v, const double *p, const double *q, double len, size_t *n,
                       uint32_t *on_line)
{
    double u[3], c[3], eu, ec, lo[6], hi[6];
    int64_t k0[6], k1[6], k[6];
    double cells = 1.0;
    int i, st;
    if (v->npr == 0) return VP_OK;
    if (++v->stamp == 0) {
        memset(v->seen, 0, v->npr * sizeof *v->seen);
        v->stamp = 1;
    }
    /* both ends within tol of the probe's line: the directions differ by at most
     * 2 sin(theta/2) <= sqrt(2) sin(theta) <= sqrt(2) 2 tol / len (up to sign), the feet by at
     * most tol + 2 |p| (that difference); rounding on top */
    eu = 3.0 * v->tol / len + 1e-12;
    for (i = 0; i < 3; i++) u[i] = (q[i] - p[i]) / len;
    foot(p, u, c);
    ec = v->tol + 2.0 * sqrt(vp_dot3(p, p)) * eu + 1e-12 * (sqrt(vp_dot3(p, p)) + v->diam);
    for (i = 0; i < 3; i++) {
        lo[i] = u[i] - eu; hi[i] = u[i] + eu;
        lo[3 + i] = c[i] - ec; hi[3 + i] = c[i] + ec;
    }
    for (i = 0; i < 6; i++) {
        double h = i < 3 ? v->hu : v->hc;
        k0[i] = cell(lo[i], h);
        k1[i] = cell(hi[i], h);
        cells *= (double)(k1[i] - k0[i] + 1);
    }
    if (eu >= 0.5 || cells > LV_MAX_CELLS) {
        size_t j;
        uint32_t gaps;
        double g0, g1;
        if ((st = origin_parts(v, p, p, q, n, on_line)) != VP_OK || (st = origin_parts(v, q, p, q, n, on_line)) != VP_OK)
            return st;
        if (!(uncovered(v, *n, &gaps, &g0, &g1) * len > v->tol)) return VP_OK;
        v->res.scans++;
        for (j = 0; j < v->npr; j++)
            if ((st = visit(v, (uint32_t)j, p, q, n, on_line)) != VP_OK) return st;
        return VP_OK;
    }
    memcpy(k, k0, sizeof k);
    for (;;) {
        uint64_t key = key6(k);
        uint32_t e;
        for (e = v->lines.head[key & v->lines.mask]; e != LV_NONE; e = v->lines.ent[e].next)
            if (v->lines.ent[e].key == key && (st = visit(v, v->lines.ent[e].probe, p, q, n, on_line)) != VP_OK) return st;
        for (i = 0; i < 6 && k[i] == k1[i]; i++) k[i] = k0[i];
        if (i == 6) break;
        k[i]++;
    }
    return VP_OK;
}

static void lerp(const double *p, const double *q, double s, double *x)
{
    int k;
    for (k = 0; k < 3; k++) x[k] = p[k] + s * (q[k] - p[k]);
}

/* ---------- tubes: the free parts by cells of 2 rho ---------- */

static uint64_t tkey(const int64_t *k)
{
    uint64_t h = 0x13198A2E03707344ull;
    int i;
    for (i = 0; i < 3; i++) h = mix(h, k[i]);
    return h;
}

/* probe id into the cell with key; once per cell (its entries for id are the newest) */
static int tadd(vp_logverify_t *v, uint64_t key, uint32_t id)
{
    uint32_t e;
    if (v->cells.head)
        for (e = v->cells.head[key & v->cells.mask]; e != LV_NONE && v->cells.ent[e].probe == id; e = v->cells.ent[e].next)
            if (v->cells.ent[e].key == key) return VP_OK;
    return add_entry(&v->cells, key, id);
}

/* A free part into every cell within one cell of a point of it taken rho / 2 apart: a point
 * nearer than rho to the part lies within 1.25 rho < one cell of such a point, so its own cell
 * lists the part. */
static int tube_add(vp_logverify_t *v, uint32_t id)
{
    const vp_lv_probe_t *P = &v->pr[id];
    double step = 0.25 * v->tcell, n = ceil(P->len / step);
    double i;
    int st;
    if (n > LV_TUBE_STEPS) return VP_OK; /* left out: it proves no tube (never more than is true) */
    for (i = 0.0; i <= n; i += 1.0) {
        double s = n > 0.0 ? P->len * (i / n) : 0.0;
        int64_t c[3], k[3];
        int a;
        for (a = 0; a < 3; a++) c[a] = cell(P->o[a] + s * P->d[a], v->tcell);
        for (k[0] = c[0] - 1; k[0] <= c[0] + 1; k[0]++)
            for (k[1] = c[1] - 1; k[1] <= c[1] + 1; k[1]++)
                for (k[2] = c[2] - 1; k[2] <= c[2] + 1; k[2]++)
                    if ((st = tadd(v, tkey(k), id)) != VP_OK) return st;
    }
    return VP_OK;
}

/* squared distance from x to the segment o .. o + len u (unit u) */
static double seg_dist2(const double *o, const double *u, double len, const double *x)
{
    double w[3], s, e[3];
    int k;
    for (k = 0; k < 3; k++) w[k] = x[k] - o[k];
    s = vp_dot3(w, u);
    if (s < 0.0) s = 0.0;
    if (s > len) s = len;
    for (k = 0; k < 3; k++) e[k] = w[k] - s * u[k];
    return vp_dot3(e, e);
}

/* squared distance from x (relative to the centre) to a free part */
static double part_dist2(const vp_lv_probe_t *P, const double *x)
{
    return seg_dist2(P->o, P->d, P->len, x);
}

/* distance from x (relative to the centre, inside Omega) to the outside of Omega */
static double outside_dist(const vp_logverify_t *v, const double *x)
{
    const vp_planner_config_t *c = &v->cfg;
    double best = HUGE_VAL;
    int k;
    if (c->omega_kind == VP_OMEGA_BALL) return c->omega_radius - sqrt(vp_dot3(x, x));
    for (k = 0; k < 3; k++) {
        double lo = x[k] + v->centre[k] - c->omega_lo[k], hi = c->omega_hi[k] - x[k] - v->centre[k];
        if (lo < best) best = lo;
        if (hi < best) best = hi;
    }
    return best;
}

/* 1 if x (relative to the centre) lies nearer than r (at most rho) to free space */
static int near_free(vp_logverify_t *v, const double *x, double r)
{
    double lim = r + v->tol;
    int64_t k[3];
    uint64_t key;
    uint32_t e;
    int a;
    if (outside_dist(v, x) < lim) return 1;
    if (!v->cells.head) return 0;
    for (a = 0; a < 3; a++) k[a] = cell(x[a], v->tcell);
    key = tkey(k);
    for (e = v->cells.head[key & v->cells.mask]; e != LV_NONE; e = v->cells.ent[e].next) {
        const vp_lv_probe_t *P = &v->pr[v->cells.ent[e].probe];
        if (v->cells.ent[e].key != key || !(P->len >= 0.0)) continue;
        if (v->cfg.proof_life > 0 && v->commands - P->born > v->cfg.proof_life) continue;
        if (part_dist2(P, x) < lim * lim) return 1;
    }
    return 0;
}

/* The tube rule (vp_logverify.h) for the move p -> q (relative to the centre): 1 if it holds;
 * 0 and *bad the centre of the first cube found that is not seen to lie within rho of free
 * space; -1 when the lattice is too large to look at (LV_TUBE_LATTICE). The cubes of side
 * rho / 2 about the lattice's points fill the box about the capsule; a cube that meets the
 * capsule is within rho of free space when its centre is within rho less its half diagonal h;
 * otherwise its eight halves are looked at, down to h <= m rho (LV_TUBE_MARGIN), where a centre
 * farther than rho - h is a violation. More than LV_TUBE_LATTICE cubes in all: -1 too. */
static int tube_holds(vp_logverify_t *v, const double *p, const double *q, double *bad)
{
    double R = v->cfg.clearance + v->cfg.feature_margin + v->cfg.min_feature, sp = 0.5 * v->cfg.min_feature;
    double rho = v->cfg.min_feature, floor_h = LV_TUBE_MARGIN * rho;
    double lo[3], u[3], len, nd[3], pts = 1.0, budget;
    long n[3], i[3];
    int k;
    for (k = 0; k < 3; k++) {
        double a = (p[k] < q[k] ? p[k] : q[k]) - R, b = (p[k] < q[k] ? q[k] : p[k]) + R;
        lo[k] = p[k] - sp * ceil((p[k] - a) / sp);
        nd[k] = ceil((b - lo[k]) / sp);
        pts *= nd[k] + 1.0;
        u[k] = q[k] - p[k];
    }
    if (!(pts <= LV_TUBE_LATTICE)) return -1;
    budget = LV_TUBE_LATTICE; /* cubes, the split ones too */
    for (k = 0; k < 3; k++) n[k] = (long)nd[k];
    len = sqrt(vp_dot3(u, u));
    for (k = 0; k < 3; k++) u[k] = len > 0.0 ? u[k] / len : 0.0;
    for (i[0] = 0; i[0] <= n[0]; i[0]++)
        for (i[1] = 0; i[1] <= n[1]; i[1]++)
            for (i[2] = 0; i[2] <= n[2]; i[2]++) {
                /* a stack of cubes (centre, half side): each taken out is seen within rho of
                 * free space, missed by the capsule, or split in eight (depth at most
                 * LV_TUBE_DEPTH: 1 + 7 LV_TUBE_DEPTH entries) */
                double cube[1 + 7 * LV_TUBE_DEPTH][4];
                int top = 0;
                for (k = 0; k < 3; k++) cube[0][k] = lo[k] + sp * (double)i[k];
                cube[0][3] = 0.5 * sp;
                while (top >= 0) {
                    double x[3], a = cube[top][3], h = a * LV_SQRT3;
                    int c;
                    memcpy(x, cube[top], sizeof x);
                    top--;
                    if (seg_dist2(p, u, len, x) > (R + h) * (R + h)) continue; /* the cube misses the capsule */
                    v->res.tube_points++;
                    if (--budget < 0.0) return -1; /* bounded time: as a lattice too large */
                    if (near_free(v, x, rho - h)) continue;
                    if (h <= floor_h || top + 8 >= 1 + 7 * LV_TUBE_DEPTH) {
                        memcpy(bad, x, sizeof x);
                        return 0;
                    }
                    for (c = 0; c < 8; c++) {
                        top++;
                        for (k = 0; k < 3; k++) cube[top][k] = x[k] + ((c >> k) & 1 ? 0.5 * a : -0.5 * a);
                        cube[top][3] = 0.5 * a;
                    }
                }
            }
    return 1;
}

/* A move counted as unproven (`missing` of its length, the first gap s0..s1 of `gaps`); its
 * listing (NULL past VP_LOGVERIFY_LIST) */
static vp_logverify_move_t *unproven(vp_logverify_t *v, const vp_logfmt_record_t *r, const double *p,
                                     const double *q, double len, double missing, double s0, double s1,
                                     uint32_t gaps)
{
    vp_logverify_result_t *R = &v->res;
    vp_logverify_move_t *m;
    R->unproven_moves++;
    R->unproven_length += missing;
    if (R->nmoves_listed >= VP_LOGVERIFY_LIST) return NULL;
    m = &R->move[R->nmoves_listed++];
    memset(m, 0, sizeof *m);
    m->record = v->index;
    m->seq = r->seq;
    m->move = R->moves;
    memcpy(m->from, p, sizeof m->from);
    memcpy(m->to, q, sizeof m->to);
    m->length = len;
    m->unproven = missing;
    m->gap_s0 = s0;
    m->gap_s1 = s1;
    lerp(p, q, s0, m->gap_from);
    lerp(p, q, s1, m->gap_to);
    m->gaps = gaps;
    return m;
}

static int check_move(vp_logverify_t *v, const vp_logfmt_record_t *r)
{
    vp_logverify_move_t *m;
    vp_logverify_result_t *R = &v->res;
    double p[3], q[3], pr[3], qr[3], len, gap, g0 = 0.0, g1 = 0.0;
    size_t n = 0;
    uint32_t gaps = 0, on_line = 0;
    int k, st;
    memcpy(p, R->pos, sizeof p);
    memcpy(q, r->target, sizeof q);
    memcpy(v->from, p, sizeof v->from);
    memcpy(R->pos, q, sizeof R->pos);
    R->moves++;
    len = dist3(p, q);
    if (len <= v->tol) return VP_OK;   /* shorter than the tolerance: nothing to cover */
    if (v->omega_broken) {
        /* a contact outside Omega: Omega does not hold the object (A2 fails), nothing outside
         * it is free any more (the planner stops there) */
        unproven(v, r, p, q, len, len, 0.0, 1.0, 1u);
        return VP_OK;
    }
    if (!(dist3(p, v->centre) <= VP_LOGVERIFY_FAR * v->diam) || !(dist3(q, v->centre) <= VP_LOGVERIFY_FAR * v->diam)) {
        /* not a move this machine makes, and one whose arithmetic is not to be trusted */
        unproven(v, r, p, q, len, len, 0.0, 1.0, 1u);
        return VP_OK;
    }
    if ((st = outside_part(v, p, q, &n)) != VP_OK) return st;
    gap = n > 0 ? uncovered(v, n, &gaps, &g0, &g1) : 1.0; /* of the move, inside Omega */
    if (gap == 0.0) { R->moves_outside++; return VP_OK; }
    if (v->cfg.clearance > 0.0 && !v->tubes) {
        /* a body without tubes stays outside Omega: its part inside is unproven (a ray proves
         * no volume) unless it enters by no more than the tolerance */
        if (gap * len > v->tol) unproven(v, r, p, q, len, gap * len, g0, g1, gaps);
        return VP_OK;
    }
    if (v->tubes) {
        /* a body inside Omega: the tube rule alone (a ray proves no volume); a move that enters
         * Omega by no more than the tolerance (an end on dOmega, rounded) is outside */
        double bad[3];
        if (!isfinite(len)) return VP_EINVAL;
        if (!(gap * len > v->tol)) return VP_OK;
        for (k = 0; k < 3; k++) {
            pr[k] = p[k] - v->centre[k];
            qr[k] = q[k] - v->centre[k];
        }
        R->tube_moves++;
        st = tube_holds(v, pr, qr, bad);
        if (st == 1) return VP_OK;
        if (st < 0) {
            R->tube_too_large++;
            unproven(v, r, p, q, len, len, 0.0, 1.0, 1u);
            return VP_OK;
        }
        /* the whole move unproven; its gap named by the point found far from free space */
        m = unproven(v, r, p, q, len, len, 0.0, 1.0, 1u);
        if (m)
            for (k = 0; k < 3; k++) m->gap_from[k] = m->gap_to[k] = bad[k] + v->centre[k];
        return VP_OK;
    }
    if (isfinite(len)) {
        for (k = 0; k < 3; k++) {
            pr[k] = p[k] - v->centre[k];
            qr[k] = q[k] - v->centre[k];
        }
        if ((st = probe_parts(v, pr, qr, len, &n, &on_line)) != VP_OK) return st;
    }
    gap = uncovered(v, n, &gaps, &g0, &g1);
    if (!(gap * len > v->tol)) return VP_OK;
    m = unproven(v, r, p, q, len, gap * len, g0, g1, gaps);
    if (m) m->probes_on_line = on_line;
    return VP_OK;
}

static int add_free(vp_logverify_t *v, const double *origin, const double *u, double len);

/* 1 if the free part origin .. origin + len u (origin absolute) passes within the contact
 * reach of a contact logged so far: a miss there may be a surface the rangefinder cannot see */
static int near_contact(const vp_logverify_t *v, const double *origin, const double *u, double len)
{
    vp_lv_probe_t P;
    size_t i;
    int k;
    for (k = 0; k < 3; k++) {
        P.o[k] = origin[k] - v->centre[k];
        P.d[k] = u[k];
    }
    P.len = len;
    for (i = 0; i < v->nct; i++)
        if (part_dist2(&P, v->ct[i]) <= v->ct_reach * v->ct_reach) return 1;
    return 0;
}

static int add_probe(vp_logverify_t *v, const vp_logfmt_record_t *r)
{
    vp_logverify_result_t *R = &v->res;
    double off = dist3(r->origin, R->pos), dl, len, u[3];
    int i;
    R->probes++;
    if (!(off <= v->tol)) {
        R->probes_off_position++;
        if (R->nprobes_listed < VP_LOGVERIFY_LIST) {
            vp_logverify_probe_t *x = &R->probe[R->nprobes_listed++];
            x->record = v->index;
            x->seq = r->seq;
            memcpy(x->origin, r->origin, sizeof x->origin);
            memcpy(x->pos, R->pos, sizeof x->pos);
            x->off = off;
        }
        return VP_OK;   /* fired from where the device was not: proves nothing */
    }
    if (!(dist3(r->origin, v->centre) <= VP_LOGVERIFY_FAR * v->diam)) { R->probes_far++; return VP_OK; }
    dl = sqrt(vp_dot3(r->dir, r->dir));
    if (!(dl > 0.0) || !isfinite(dl)) { R->probes_bad++; return VP_OK; }
    if (r->hit == 1) {
        double nt = v->cfg.noise_tol > 0.0 ? v->cfg.noise_tol : 0.0;
        len = r->dist - nt;
        if (len > r->range) len = r->range;
    } else if (r->hit == 0) {
        len = r->range;
    } else {
        return VP_OK;   /* too close: nothing measured, nothing free */
    }
    if (v->cfg.max_range > 0.0 && len > v->cfg.max_range) len = v->cfg.max_range; /* the rangefinder's reach */
    if (!(len > 0.0) || !isfinite(len)) return VP_OK;
    for (i = 0; i < 3; i++) u[i] = r->dir[i] / dl;
    if (near_contact(v, r->origin, u, len)) { R->probes_near_contact++; return VP_OK; }
    return add_free(v, r->origin, u, len);
}

/* A free part o .. o + len u (u unit, o absolute) into the store and its three hash entries. */
static int add_free(vp_logverify_t *v, const double *origin, const double *u, double len)
{
    vp_lv_probe_t *P;
    double c[3], nu[3];
    int64_t k[6];
    uint32_t id;
    int i, st;
    if (v->npr + 1 > v->cap_pr) {
        /* the probes and their per-move stamps grow together */
        size_t cap = v->cap_pr;
        uint32_t *s;
        if ((st = grow((void **)&v->pr, &cap, v->npr + 1, sizeof *v->pr)) != VP_OK) return st;
        s = realloc(v->seen, cap * sizeof *s);
        if (!s) return VP_ENOMEM;   /* pr grew already: harmless, cap_pr still the old one */
        memset(s + v->cap_pr, 0, (cap - v->cap_pr) * sizeof *s);
        v->seen = s;
        v->cap_pr = cap;
    }
    id = (uint32_t)v->npr;
    P = &v->pr[id];
    for (i = 0; i < 3; i++) {
        nu[i] = -u[i];
        P->o[i] = origin[i] - v->centre[i];
        P->d[i] = u[i];
    }
    P->len = len;
    P->born = v->commands;
    P->record = v->index;
    foot(P->o, u, c);
    line_cells(v, u, c, k);
    if ((st = add_entry(&v->lines, key6(k), id)) != VP_OK) return st;
    line_cells(v, nu, c, k);
    if ((st = add_entry(&v->lines, key6(k), id)) != VP_OK) return st;
    for (i = 0; i < 3; i++) k[i] = cell(P->o[i], v->ho);
    if ((st = add_entry(&v->lines, key3(k), id)) != VP_OK) return st;
    v->npr++;
    return v->tubes ? tube_add(v, id) : VP_OK;
}

/* CONTACT: the MOVE before stopped at value[0] along it, where the surface is. */
static int add_contact(vp_logverify_t *v, const vp_logfmt_record_t *r)
{
    vp_logverify_result_t *R = &v->res;
    double d[3], u[3], c[3], cr[3], len, at = r->value[0];
    size_t i;
    int k;
    double wtol = v->tol + (v->cfg.noise_tol > 0.0 && isfinite(v->cfg.noise_tol) ? v->cfg.noise_tol : 0.0);
    if (!v->after_move) { R->contacts_misplaced++; return VP_OK; } /* stopped no move: nothing learnt */
    vp_sub3(d, R->pos, v->from);
    len = sqrt(vp_dot3(d, d));
    if (!(at >= 0.0) || !(at <= len + v->tol)) return VP_OK; /* not on the move: nothing learnt */
    for (k = 0; k < 3; k++) {
        u[k] = len > 0.0 ? d[k] / len : 0.0;
        c[k] = v->from[k] + at * u[k];
    }
    R->contacts++;
    for (k = 0; k < 3; k++) cr[k] = c[k] - v->centre[k];
    if (outside_dist(v, cr) <= 0.0) v->omega_broken = 1;
    /* every free part through the point (within the hits' tolerance) was wrong, and later
     * ones near it prove nothing */
    for (i = 0; i < v->npr; i++) {
        vp_lv_probe_t *P = &v->pr[i];
        if (P->len >= 0.0 && part_dist2(P, cr) <= wtol * wtol) { P->len = -1.0; R->withdrawn++; }
    }
    if (grow((void **)&v->ct, &v->cap_ct, v->nct + 1, sizeof *v->ct) != VP_OK) return VP_ENOMEM;
    memcpy(v->ct[v->nct++], cr, sizeof cr);
    memcpy(R->pos, c, sizeof R->pos);
    /* the head travelled up to the point */
    return at > 0.0 && len > 0.0 ? add_free(v, v->from, u, at) : VP_OK;
}

int vp_logverify_add(vp_logverify_t *v, const vp_logfmt_record_t *r)
{
    int st = VP_OK;
    if (r->type == VP_LOGFMT_MOVE) { st = check_move(v, r); v->commands++; }
    else if (r->type == VP_LOGFMT_PROBE) { v->commands++; st = add_probe(v, r); }
    else if (r->type == VP_LOGFMT_RAY) v->res.rays++; /* the planner moves on PROBE proofs alone */
    else if (r->event == VP_LOGFMT_EV_CONTACT) { v->res.events++; st = add_contact(v, r); }
    else if (r->event == VP_LOGFMT_EV_RESCAN) {
        /* a re-scan: the object may have changed, so nothing proven before proves anything now;
         * the device is at the start again */
        size_t i;
        if (r->code < 0 || ((unsigned)r->code & ~(VP_RESCAN_HERE | VP_RESCAN_SPARSE))) return VP_ECORRUPT; /* no such flags */
        for (i = 0; i < v->npr; i++) v->pr[i].len = -1.0;
        if (!(r->code & VP_RESCAN_HERE)) memcpy(v->res.pos, v->cfg.start, sizeof v->res.pos); /* the device stays */
        v->res.events++;
        v->res.rescans++;
    }
    else v->res.events++;   /* START, PAUSE, RESUME, FAULT, DONE, ...: the device stays */
    v->after_move = r->type == VP_LOGFMT_MOVE; /* what the next record follows */
    if (st != VP_OK) return st;
    v->index++;
    v->res.records++;
    return VP_OK;
}

void vp_logverify_end(vp_logverify_t *v, vp_logverify_result_t *res)
{
    v->res.ok = v->res.unproven_moves == 0 && v->res.probes_off_position == 0 && v->res.contacts_misplaced == 0;
    if (res) *res = v->res;
    free(v->pr);
    hash_free(&v->lines);
    free(v->iv);
    free(v->seen);
    free(v->ct);
    hash_free(&v->cells);
    memset(v, 0, sizeof *v);
}

int vp_logverify_run(const vp_logfmt_header_t *h, const vp_logfmt_record_t *records, size_t n,
                     vp_logverify_result_t *res)
{
    vp_logverify_t *v = malloc(sizeof *v);
    size_t i;
    int st;
    if (!v) return VP_ENOMEM;
    st = vp_logverify_begin(v, h);
    for (i = 0; st == VP_OK && i < n; i++) st = vp_logverify_add(v, &records[i]);
    vp_logverify_end(v, res);
    free(v);
    return st;
}
