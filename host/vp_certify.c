/* vp_certify — see vp_certify.h. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_certify.h"
#include "vp_meshcheck.h"
#include "vp_dt.h"
#include "vp_kdtree.h"
#include "vp_pred.h"
#include "vp_status.h"
#include "vp_vec3.h"

/* ---------- exact sums of products (Shewchuk's expansions; no FMA: -ffp-contract=off) ---------- */

static void two_sum(double a, double b, double *x, double *y)
{
    double bv, av;
    *x = a + b;
    bv = *x - a;
    av = *x - bv;
    *y = (a - av) + (b - bv);
}

static void two_diff(double a, double b, double *x, double *y)
{
    double bv, av;
    *x = a - b;
    bv = a - *x;
    av = *x + bv;
    *y = (a - av) + (bv - b);
}

static void split(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a, ab = c - a;
    *hi = c - ab;
    *lo = a - *hi;
}

static void two_product(double a, double b, double *x, double *y)
{
    double ahi, alo, bhi, blo, e1, e2, e3;
    *x = a * b;
    split(a, &ahi, &alo);
    split(b, &bhi, &blo);
    e1 = *x - ahi * bhi;
    e2 = e1 - alo * bhi;
    e3 = e2 - ahi * blo;
    *y = alo * blo - e3;
}

/* e (n nonoverlapping components, increasing magnitude) += b; returns the new length. */
static int grow(double *e, int n, double b)
{
    double q = b, h[64];
    int i, k = 0;
    for (i = 0; i < n; i++) {
        double s, t;
        two_sum(q, e[i], &s, &t);
        q = s;
        if (t != 0.0) h[k++] = t;
    }
    if (q != 0.0 || k == 0) h[k++] = q;
    memcpy(e, h, (size_t)k * sizeof *h);
    return k;
}

int vp_cert_cmp_radius(const double p[3], const double q[3], double r)
{
    double e[64], hi, lo, x, y;
    int n = 0, k;
    for (k = 0; k < 3; k++) {
        two_diff(p[k], q[k], &hi, &lo);
        two_product(hi, hi, &x, &y); n = grow(e, n, x); n = grow(e, n, y);
        two_product(hi, 2.0 * lo, &x, &y); n = grow(e, n, x); n = grow(e, n, y);
        two_product(lo, lo, &x, &y); n = grow(e, n, x); n = grow(e, n, y);
    }
    two_product(r, r, &x, &y);
    n = grow(e, n, -x);
    n = grow(e, n, -y);
    return e[n - 1] > 0.0 ? 1 : e[n - 1] < 0.0 ? -1 : 0;
}

/* ---------- H1 ---------- */

static int check_h1(const vp_mesh_t *m, vp_cert_t *c, size_t maxl, FILE *rep)
{
    size_t nt = m->nt, ne = 3 * nt, i, j, listed = 0;
    vp_edge_rec_t *e = malloc((ne + 1) * sizeof *e);
    uint32_t *par = malloc((nt + 1) * sizeof *par), *start = calloc(m->nv + 1, sizeof *start);
    uint32_t *link = malloc((2 * ne + 1) * sizeof *link), *fill;
    if (!e || !par || !start || !link) { free(e); free(par); free(start); free(link); return VP_ENOMEM; }
    for (i = 0; i < nt; i++) {
        const uint32_t *t = m->tri + 3 * i;
        int k;
        par[i] = (uint32_t)i;
        const double *pa = m->xyz + 3 * (size_t)t[0], *pb = m->xyz + 3 * (size_t)t[1], *pc = m->xyz + 3 * (size_t)t[2];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
            (vp_orient2d_proj(pa, pb, pc, 0) == 0 && vp_orient2d_proj(pa, pb, pc, 1) == 0 &&
             vp_orient2d_proj(pa, pb, pc, 2) == 0)) {
            if (c->degenerate_facets++ < maxl && rep)
                fprintf(rep, "H1 fails: facet %zu (%u %u %u) is degenerate (repeated or collinear vertices)\n",
                        i, t[0], t[1], t[2]);
        }
        for (k = 0; k < 3; k++) {
            uint32_t a = t[k], b = t[(k + 1) % 3];
            e[3 * i + (size_t)k].a = a < b ? a : b;
            e[3 * i + (size_t)k].b = a < b ? b : a;
            e[3 * i + (size_t)k].f = (uint32_t)i;
        }
    }
    qsort(e, ne, sizeof *e, vp_edge_cmp);
    for (i = 0; i < ne; i = j) {
        for (j = i + 1; j < ne && e[j].a == e[i].a && e[j].b == e[i].b; j++) {
            uint32_t x = vp_uf_find(par, e[i].f), y = vp_uf_find(par, e[j].f);
            if (x != y) par[x < y ? y : x] = x < y ? x : y;
        }
        c->edges++;
        if (j - i == 2) continue;
        if (j - i == 1) c->boundary_edges++;
        else c->nonmanifold_edges++;
        if (listed++ < maxl && rep) {
            size_t q;
            fprintf(rep, "H1 fails: edge (%u %u) is in %zu facet(s):", e[i].a, e[i].b, j - i);
            for (q = i; q < j; q++) fprintf(rep, " %u", e[q].f);
            fprintf(rep, "%s\n", j - i == 1 ? " (a boundary edge: a hole)" : " (non-manifold)");
        }
    }
    for (i = 0; i < nt; i++) if (par[i] == i) c->components++;
    /* vertex links: the opposite edges of a vertex's facets must form one cycle */
    for (i = 0; i < nt; i++) {
        int k;
        for (k = 0; k < 3; k++) start[m->tri[3 * i + (size_t)k]]++;
    }
    {
        uint32_t s = 0;
        for (i = 0; i <= m->nv; i++) { uint32_t n = i < m->nv ? start[i] : 0; start[i] = s; s += 2 * n; }
    }
    fill = calloc(m->nv + 1, sizeof *fill);
    if (!fill) { free(e); free(par); free(start); free(link); return VP_ENOMEM; }
    for (i = 0; i < nt; i++) {
        int k;
        for (k = 0; k < 3; k++) {
            uint32_t v = m->tri[3 * i + (size_t)k], *l = link + start[v] + 2 * fill[v]++;
            l[0] = m->tri[3 * i + (size_t)((k + 1) % 3)];
            l[1] = m->tri[3 * i + (size_t)((k + 2) % 3)];
        }
    }
    listed = 0;
    for (i = 0; i < m->nv; i++) {
        uint32_t n = fill[i], *l = link + start[i], cur, prev, steps = 0, q;
        int ok = 1;
        if (n == 0) continue;
        /* every link vertex appears exactly twice, and walking the link visits all n edges */
        for (q = 0; q < 2 * n && ok; q++) {
            uint32_t x = l[q], cnt = 0, r;
            for (r = 0; r < 2 * n; r++) cnt += l[r] == x;
            if (cnt != 2) ok = 0;
        }
        if (ok) {
            prev = l[0];
            cur = l[1];
            steps = 1;
            while (cur != l[0] && steps <= n) {
                uint32_t r, next = UINT32_MAX;
                for (r = 0; r < n; r++) {
                    if (l[2 * r] == cur && l[2 * r + 1] != prev) { next = l[2 * r + 1]; break; }
                    if (l[2 * r + 1] == cur && l[2 * r] != prev) { next = l[2 * r]; break; }
                }
                if (next == UINT32_MAX) break;
                prev = cur;
                cur = next;
                steps++;
            }
            ok = cur == l[0] && steps == n;
        }
        if (!ok) {
            c->bad_vertices++;
            if (listed++ < maxl && rep)
                fprintf(rep, "H1 fails: vertex %zu: the links of its %u facets are not one cycle (a boundary or pinched vertex)\n", i, n);
        }
    }
    c->h1 = c->boundary_edges == 0 && c->nonmanifold_edges == 0 && c->bad_vertices == 0 && c->degenerate_facets == 0 &&
            nt > 0;
    free(e); free(par); free(start); free(link); free(fill);
    return VP_OK;
}

/* ---------- H2 ---------- */

/* Parity of the crossings of segment [o, q] with the facets of component `comp` (labels),
 * exact; -1 when the segment meets an edge or vertex (try another direction). */
static int parity(const vp_mesh_t *m, const uint32_t *label, uint32_t comp, const double *o, const double *q)
{
    size_t i;
    int n = 0;
    for (i = 0; i < m->nt; i++) {
        const double *a = m->xyz + 3 * (size_t)m->tri[3 * i], *b = m->xyz + 3 * (size_t)m->tri[3 * i + 1],
                     *c = m->xyz + 3 * (size_t)m->tri[3 * i + 2];
        int s1, s2, t1, t2, t3;
        if (label[i] != comp) continue;
        s1 = vp_orient3d(a, b, c, o);
        s2 = vp_orient3d(a, b, c, q);
        if (s1 == 0 && s2 == 0) continue; /* coplanar with the segment: no crossing counted */
        if (s1 == 0 || s2 == 0) return -1;
        if (s1 == s2) continue;
        t1 = vp_orient3d(o, q, a, b);
        t2 = vp_orient3d(o, q, b, c);
        t3 = vp_orient3d(o, q, c, a);
        if (t1 == 0 || t2 == 0 || t3 == 0) {
            if ((t1 >= 0 && t2 >= 0 && t3 >= 0) || (t1 <= 0 && t2 <= 0 && t3 <= 0)) return -1;
            continue;
        }
        if (t1 == t2 && t2 == t3) n++;
    }
    return n & 1;
}

static int check_h2(const vp_mesh_t *m, const vp_cert_config_t *cfg, vp_cert_t *c, FILE *rep)
{
    uint32_t *label, *par, i;
    size_t f;
    double lo[3] = { DBL_MAX, DBL_MAX, DBL_MAX }, hi[3] = { -DBL_MAX, -DBL_MAX, -DBL_MAX }, size = 0;
    static const double dirs[6][3] = { { 0.4469983318002897, 0.5384104567341229, 0.7144217014264011 },
                                       { -0.6123, 0.2345, 0.7551 }, { 0.3311, -0.8812, 0.3374 },
                                       { -0.1, -0.2, -0.9747 }, { 0.9, 0.3, -0.3162 }, { -0.57, 0.577, -0.585 } };
    if (!cfg->interior || cfg->ninterior == 0) { c->h2 = -1; return VP_OK; }
    if (m->nt == 0) { c->h2 = 0; c->h2_missing = cfg->ninterior; return VP_OK; }
    label = malloc(m->nt * sizeof *label);
    par = malloc((m->nv + 1) * sizeof *par);
    if (!label || !par) { free(label); free(par); return VP_ENOMEM; }
    /* components by shared vertices */
    for (i = 0; i < m->nv; i++) par[i] = i;
    for (f = 0; f < m->nt; f++) {
        int k;
        for (k = 1; k < 3; k++) {
            uint32_t x = vp_uf_find(par, m->tri[3 * f]), y = vp_uf_find(par, m->tri[3 * f + (size_t)k]);
            if (x != y) par[x < y ? y : x] = x < y ? x : y;
        }
    }
    for (f = 0; f < m->nt; f++) label[f] = vp_uf_find(par, m->tri[3 * f]);
    for (i = 0; i < m->nv; i++) {
        int k;
        for (k = 0; k < 3; k++) {
            if (m->xyz[3 * i + (size_t)k] < lo[k]) lo[k] = m->xyz[3 * i + (size_t)k];
            if (m->xyz[3 * i + (size_t)k] > hi[k]) hi[k] = m->xyz[3 * i + (size_t)k];
        }
    }
    for (i = 0; i < 3; i++) size += hi[i] - lo[i];
    /* the distinct component labels: vertex roots marked in par (reused as flags) */
    for (i = 0; i < m->nv; i++) par[i] = 0;
    for (f = 0; f < m->nt; f++) par[label[f]] = 1;
    for (i = 0; i < cfg->ninterior; i++) {
        const double *o = cfg->interior[i];
        uint32_t comp = UINT32_MAX, g;
        for (g = 0; g < m->nv && comp == UINT32_MAX; g++) {
            int d, odd = 0, even = 0;
            if (!par[g]) continue;
            /* enclosed: an odd number of crossings in every direction (a component with a
             * hole gives different answers in different directions) */
            for (d = 0; d < 6; d++) {
                double q[3], len = 4.0 * size + fabs(o[0]) + fabs(o[1]) + fabs(o[2]) + 1.0;
                int k, p;
                for (k = 0; k < 3; k++) q[k] = o[k] + len * dirs[d][k];
                p = parity(m, label, g, o, q);
                odd += p == 1;
                even += p == 0;
            }
            if (odd > 0 && even == 0) comp = g;
        }
        if (comp == UINT32_MAX) {
            c->h2_missing++;
            if (rep) fprintf(rep, "H2 fails: interior point o_%u (%.9g %.9g %.9g) is enclosed by no mesh component: %s\n",
                             i, o[0], o[1], o[2],
                             c->boundary_edges > 0 ? "the mesh around it is still open (see the boundary edges)"
                                                   : "its component of S has no vertex");
        }
    }
    c->h2 = c->h2_missing == 0;
    free(label);
    free(par);
    return VP_OK;
}

/* ---------- H3 ---------- */

static double dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static int check_h3_balls(const vp_mesh_t *m, const vp_cert_config_t *cfg, vp_cert_t *c, size_t maxl, FILE *rep)
{
    const double *S = cfg->samples ? cfg->samples : m->xyz;
    size_t ns = cfg->samples ? cfg->nsamples : m->nv, f, lb = 0, lo = 0;
    vp_kdtree_t *kd = NULL;
    int st = vp_kdtree_build(S, ns, &kd);
    if (st != VP_OK) return st;
    for (f = 0; f < m->nt; f++) {
        const double *cc = cfg->centers + 3 * f;
        const double *v[3];
        double r[3], rmax, rmin;
        size_t idx[8], nn, q;
        double d2[8];
        int k, near = 0, big = 0;
        for (k = 0; k < 3; k++) {
            v[k] = m->xyz + 3 * (size_t)m->tri[3 * f + (size_t)k];
            r[k] = dist3(cc, v[k]);
            if (vp_cert_cmp_radius(cc, v[k], cfg->eps) > 0) big = 1;
        }
        rmax = r[0] > r[1] ? (r[0] > r[2] ? r[0] : r[2]) : (r[1] > r[2] ? r[1] : r[2]);
        rmin = r[0] < r[1] ? (r[0] < r[2] ? r[0] : r[2]) : (r[1] < r[2] ? r[1] : r[2]);
        for (k = 1; k < 3; k++) if (vp_cmp_dist(cc, v[k], v[near]) < 0) near = k;
        if (rmax > c->max_radius) { c->max_radius = rmax; c->max_radius_facet = f; }
        if (rmax > 0 && (rmax - rmin) / rmax > c->max_spread) c->max_spread = (rmax - rmin) / rmax;
        if (big) {
            c->big_balls++;
            if (lb++ < maxl && rep)
                fprintf(rep, "H3 fails: facet %zu (%u %u %u): its surface Delaunay ball (centre %.9g %.9g %.9g) has "
                        "radius %.9g > eps %.9g\n", f, m->tri[3 * f], m->tri[3 * f + 1], m->tri[3 * f + 2],
                        cc[0], cc[1], cc[2], rmax, cfg->eps);
        }
        /* empty: no sample strictly closer to the centre than the facet's nearest vertex */
        nn = vp_kdtree_knn(kd, cc, 8, idx, d2);
        for (q = 0; q < nn; q++) {
            const double *p = vp_kdtree_point(kd, idx[q]);
            if (p[0] == v[0][0] && p[1] == v[0][1] && p[2] == v[0][2]) continue;
            if (p[0] == v[1][0] && p[1] == v[1][1] && p[2] == v[1][2]) continue;
            if (p[0] == v[2][0] && p[1] == v[2][1] && p[2] == v[2][2]) continue;
            if (vp_cmp_dist(cc, p, v[near]) < 0) {
                c->open_balls++;
                if (lo++ < maxl && rep)
                    fprintf(rep, "H3 fails: facet %zu (%u %u %u): sample %.9g %.9g %.9g lies inside its ball "
                            "(not a Delaunay ball)\n", f, m->tri[3 * f], m->tri[3 * f + 1], m->tri[3 * f + 2],
                            p[0], p[1], p[2]);
                break;
            }
        }
    }
    vp_kdtree_free(kd);
    c->h3 = c->big_balls == 0 && c->open_balls == 0 && m->nt > 0;
    return VP_OK;
}

/* Bare mesh: circumradius <= eps (necessary) and Delaunay for the mesh's vertices (necessary). */
static int check_h3_bare(const vp_mesh_t *m, const vp_cert_config_t *cfg, vp_cert_t *c, size_t maxl, FILE *rep)
{
    size_t bytes = 1024 * (m->nv + 64) + ((size_t)1 << 20), f, lb = 0, ld = 0;
    void *mem = malloc(bytes);
    uint32_t *ids = malloc((m->nv + 1) * sizeof *ids), tets[4096];
    vp_dt_t dt;
    int st;
    if (!mem || !ids) { free(mem); free(ids); return VP_ENOMEM; }
    st = vp_dt_init(&dt, mem, bytes, 0);
    if (st == VP_OK) st = vp_dt_insert_batch(&dt, m->xyz, (uint32_t)m->nv, ids);
    if (st != VP_OK) { free(mem); free(ids); return st == VP_EINVAL ? VP_EINVAL : VP_ENOMEM; }
    for (f = 0; f < m->nt; f++) {
        const uint32_t *t = m->tri + 3 * f;
        const double *a = m->xyz + 3 * (size_t)t[0], *b = m->xyz + 3 * (size_t)t[1], *cc = m->xyz + 3 * (size_t)t[2];
        double ab = dist3(a, b), bc = dist3(b, cc), ca = dist3(cc, a), u[3], w[3], n[3], area2, R;
        int k, n_inc, found = 0;
        for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; w[k] = cc[k] - a[k]; }
        vp_cross3(n, u, w);
        area2 = vp_norm3(n);
        R = area2 > 0 ? ab * bc * ca / (2.0 * area2) : INFINITY;
        if (R > c->max_radius) { c->max_radius = R; c->max_radius_facet = f; }
        if (!(R <= cfg->eps * (1.0 + 1e-12))) {
            c->big_circumradius++;
            if (lb++ < maxl && rep)
                fprintf(rep, "H3 fails: facet %zu (%u %u %u): circumradius %.9g > eps %.9g, so no ball of radius <= eps "
                        "circumscribes it\n", f, t[0], t[1], t[2], R, cfg->eps);
        } else if (R > cfg->eps * (1.0 - 1e-12)) {
            c->undecided++;
        }
        /* a facet of Del(E) is a facet of some tet of the vertex's star */
        n_inc = vp_dt_incident_tets(&dt, ids[t[0]], tets, 4096);
        for (k = 0; k < n_inc && !found; k++) {
            const uint32_t *q = vp_dt_tet(&dt, tets[k]);
            int hb = 0, hc = 0, z;
            for (z = 0; z < 4; z++) { hb |= q[z] == ids[t[1]]; hc |= q[z] == ids[t[2]]; }
            found = hb && hc;
        }
        if (n_inc < 0 || !found) {
            c->not_delaunay++;
            if (ld++ < maxl && rep)
                fprintf(rep, "H3 fails: facet %zu (%u %u %u) is not a facet of the Delaunay triangulation of the mesh "
                        "vertices (symbolic perturbation), so it has no empty circumscribing ball\n", f, t[0], t[1], t[2]);
        }
    }
    free(mem);
    free(ids);
    c->h3 = (c->big_circumradius || c->not_delaunay || m->nt == 0) ? 0 : -1;
    return VP_OK;
}

/* The distance from mesh vertex v (dt vertex id) to its poles (paper 002, after Amenta and
 * Bern): the farthest Voronoi vertex of its cell (at infinity, outward, when the cell is
 * unbounded) and the farthest one on the other side; the nearer is taken as dM(v). */
static double pole_dm(const vp_dt_t *dt, uint32_t id, uint32_t *tets, int cap)
{
    const double *p = vp_dt_point(dt, id);
    int n = vp_dt_incident_tets(dt, id, tets, cap), i, k, unbounded = 0;
    double far = -1.0, other = -1.0, u[3] = { 0, 0, 0 }, c[3], d[3], m[3] = { 0, 0, 0 };
    unsigned cnt = 0;
    if (n <= 0) return INFINITY;
    for (i = 0; i < n; i++) {
        const uint32_t *w = vp_dt_tet(dt, tets[i]);
        if (vp_dt_is_ghost(dt, tets[i])) { unbounded = 1; continue; }
        for (k = 0; k < 4; k++)
            if (w[k] != id) {
                const double *q = vp_dt_point(dt, w[k]);
                m[0] += q[0]; m[1] += q[1]; m[2] += q[2];
                cnt++;
            }
        if (vp_dt_circumcenter(dt, tets[i], c) != VP_OK) continue;
        vp_sub3(d, c, p);
        if (vp_norm3(d) > far) { far = vp_norm3(d); memcpy(u, d, sizeof u); }
    }
    if (unbounded && cnt) for (k = 0; k < 3; k++) u[k] = p[k] - m[k] / (double)cnt;
    for (i = 0; i < n; i++) {
        if (vp_dt_is_ghost(dt, tets[i]) || vp_dt_circumcenter(dt, tets[i], c) != VP_OK) continue;
        vp_sub3(d, c, p);
        if (vp_dot3(d, u) < 0.0 && vp_norm3(d) > other) other = vp_norm3(d);
    }
    if (unbounded) return other >= 0.0 ? other : INFINITY;
    return other >= 0.0 && other < far ? other : far;
}

/* eps' = max over balls of r / dM(c), dM(c) = min over the facet's vertices (dM(v) + |c - v|) */
static int estimate_eps_prime(const vp_mesh_t *m, const vp_cert_config_t *cfg, vp_cert_t *c)
{
    size_t bytes = 1024 * (m->nv + 64) + ((size_t)1 << 20), f;
    void *mem = malloc(bytes);
    uint32_t *ids = malloc((m->nv + 1) * sizeof *ids), tets[4096];
    double *dm = malloc((m->nv + 1) * sizeof *dm);
    vp_dt_t dt;
    int st;
    c->eps_prime = -1.0;
    if (!mem || !ids || !dm) { free(mem); free(ids); free(dm); return VP_ENOMEM; }
    st = vp_dt_init(&dt, mem, bytes, 0);
    if (st == VP_OK) st = vp_dt_insert_batch(&dt, m->xyz, (uint32_t)m->nv, ids);
    if (st == VP_OK) {
        for (f = 0; f < m->nv; f++) dm[f] = pole_dm(&dt, ids[f], tets, 4096);
        for (f = 0; f < m->nt; f++) {
            const uint32_t *t = m->tri + 3 * f;
            const double *ctr = cfg->centers + 3 * f;
            double r = dist3(ctr, m->xyz + 3 * (size_t)t[0]), g = INFINITY, e;
            int k;
            for (k = 0; k < 3; k++) {
                double x = dm[t[k]] + dist3(ctr, m->xyz + 3 * (size_t)t[k]);
                if (x < g) g = x;
            }
            e = r / g;
            if (e > c->eps_prime) { c->eps_prime = e; c->eps_prime_facet = f; }
        }
    }
    free(mem);
    free(ids);
    free(dm);
    return st == VP_OK ? VP_OK : st == VP_EINVAL ? VP_EINVAL : VP_ENOMEM;
}

int vp_certify(const vp_mesh_t *m, const vp_cert_config_t *cfg, vp_cert_t *out, FILE *rep)
{
    size_t maxl;
    int st;
    memset(out, 0, sizeof *out);
    if (!m || !cfg || !(cfg->eps > 0) || !isfinite(cfg->eps)) return VP_EINVAL;
    maxl = cfg->max_list ? cfg->max_list : 20;
    if ((st = check_h1(m, out, maxl, rep)) != VP_OK) return st;
    if ((st = check_h2(m, cfg, out, rep)) != VP_OK) return st;
    st = cfg->centers ? check_h3_balls(m, cfg, out, maxl, rep) : check_h3_bare(m, cfg, out, maxl, rep);
    if (st != VP_OK) return st;
    out->eps_prime = -1.0;
    if (cfg->centers && m->nt > 0 && (st = estimate_eps_prime(m, cfg, out)) != VP_OK) return st;
    out->reach_ok = cfg->reach > 0 ? cfg->eps < 0.091 * cfg->reach : -1;
    if (cfg->reach > 0 && cfg->diam > 0)
        out->hausdorff_bound = 4.5 * cfg->diam / (cfg->reach * cfg->reach) * cfg->eps * cfg->eps;
    return VP_OK;
}
