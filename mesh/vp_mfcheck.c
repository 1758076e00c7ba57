/* vp_mfcheck — closed k-manifold check of a list of k-simplices (see vp_mfcheck.h). */
#include "vp_mfcheck.h"
#include <stdlib.h>
#include <string.h>
#include "vp_status.h"

#define NONE UINT32_MAX

/* A face: up to 4 sorted vertex indices (unused slots NONE), and where it came from. */
typedef struct face {
    uint32_t v[4];
    uint32_t simplex;   /* index of the k-simplex */
    uint32_t pos;       /* position (in the sorted simplex) of the vertex left out */
} face_t;

static int face_cmp(const void *a, const void *b)
{
    const face_t *x = a, *y = b;
    int i;
    for (i = 0; i < 4; i++)
        if (x->v[i] != y->v[i]) return x->v[i] < y->v[i] ? -1 : 1;
    return 0;
}

static int face_same(const face_t *x, const face_t *y)
{
    return !memcmp(x->v, y->v, sizeof x->v);
}

static void sort_small(uint32_t *v, int n)
{
    int i, j;
    for (i = 1; i < n; i++)
        for (j = i; j > 0 && v[j - 1] > v[j]; j--) { uint32_t t = v[j]; v[j] = v[j - 1]; v[j - 1] = t; }
}

static uint32_t uf_find(uint32_t *par, uint32_t x)
{
    while (par[x] != x) { par[x] = par[par[x]]; x = par[x]; }
    return x;
}

static void uf_join(uint32_t *par, uint32_t a, uint32_t b)
{
    a = uf_find(par, a); b = uf_find(par, b);
    if (a != b) par[a < b ? b : a] = a < b ? a : b;
}

/* m edges (pairs) form exactly one cycle: every vertex in two of them, all reached. */
static int one_cycle(const uint32_t (*e)[2], size_t m)
{
    size_t i, j, steps = 0, prev = 0;
    uint32_t start, cur;
    if (m < 3) return 0;
    for (i = 0; i < m; i++) {
        size_t deg[2] = { 0, 0 };
        int s;
        for (s = 0; s < 2; s++)
            for (j = 0; j < m; j++) deg[s] += (e[j][0] == e[i][s]) + (e[j][1] == e[i][s]);
        if (deg[0] != 2 || deg[1] != 2 || e[i][0] == e[i][1]) return 0;
    }
    start = e[0][0]; cur = e[0][1]; steps = 1;
    while (cur != start) {
        for (j = 0; j < m; j++)
            if (j != prev && (e[j][0] == cur || e[j][1] == cur)) break;
        if (j == m) return 0;
        cur = e[j][0] == cur ? e[j][1] : e[j][0];
        prev = j;
        if (++steps > m) return 0;
    }
    return steps == m;
}

/* m triangles form a 2-sphere: each edge in two, each vertex link one cycle, connected,
 * V - E + F = 2. scratch: room for 3m edges. */
static int is_sphere2(const uint32_t (*t)[3], size_t m, uint32_t (*scratch)[2])
{
    size_t i, j, nv = 0, ne = 0, cnt;
    uint32_t verts[512], par[512];
    if (m < 4 || 3 * m > 3 * 512) return 0;
    for (i = 0; i < m; i++) {
        int c;
        for (c = 0; c < 3; c++) {
            for (j = 0; j < nv; j++) if (verts[j] == t[i][c]) break;
            if (j == nv) { if (nv == 512) return 0; verts[nv++] = t[i][c]; }
        }
    }
    /* every edge in exactly two triangles */
    for (i = 0; i < m; i++) {
        int c;
        for (c = 0; c < 3; c++) {
            uint32_t a = t[i][c], b = t[i][(c + 1) % 3];
            size_t i2;
            cnt = 0;
            for (i2 = 0; i2 < m; i2++) {
                int has_a = t[i2][0] == a || t[i2][1] == a || t[i2][2] == a;
                int has_b = t[i2][0] == b || t[i2][1] == b || t[i2][2] == b;
                cnt += has_a && has_b;
            }
            if (cnt != 2) return 0;
        }
    }
    ne = 3 * m / 2;
    if ((long)nv - (long)ne + (long)m != 2) return 0;
    /* connected */
    for (j = 0; j < nv; j++) par[j] = (uint32_t)j;
    for (i = 0; i < m; i++) {
        uint32_t loc[3];
        int c;
        for (c = 0; c < 3; c++) { for (j = 0; verts[j] != t[i][c]; j++) {} loc[c] = (uint32_t)j; }
        uf_join(par, loc[0], loc[1]); uf_join(par, loc[0], loc[2]);
    }
    for (j = 0; j < nv; j++) if (uf_find(par, (uint32_t)j) != 0) return 0;
    /* each vertex link one cycle */
    for (j = 0; j < nv; j++) {
        size_t me = 0;
        for (i = 0; i < m; i++) {
            int c;
            for (c = 0; c < 3; c++)
                if (t[i][c] == verts[j]) {
                    scratch[me][0] = t[i][(c + 1) % 3];
                    scratch[me][1] = t[i][(c + 2) % 3];
                    me++;
                }
        }
        if (!one_cycle((const uint32_t (*)[2])scratch, me)) return 0;
    }
    return 1;
}

static size_t binom(int n, int r)
{
    size_t b = 1;
    int i;
    for (i = 1; i <= r; i++) b = b * (size_t)(n - r + i) / (size_t)i;
    return b;
}

/* All j-faces (j+1 of the k+1 sorted vertices s[]) of simplex si. */
static size_t add_faces(face_t *f, const uint32_t *s, int k, int j, uint32_t si)
{
    size_t n = 0;
    unsigned mask;
    for (mask = 0; mask < (1u << (k + 1)); mask++) {
        int c, bits = 0, left = 0;
        for (c = 0; c <= k; c++) bits += (mask >> c) & 1;
        if (bits != j + 1) continue;
        memset(f[n].v, 0xff, sizeof f[n].v);
        for (c = 0, bits = 0; c <= k; c++)
            if ((mask >> c) & 1) f[n].v[bits++] = s[c];
            else left = c;
        f[n].simplex = si;
        f[n].pos = (uint32_t)left;
        n++;
    }
    return n;
}

int vp_mfcheck_run(const uint32_t *simp, size_t ns, int k, size_t nv, vp_mfcheck_t *out, uint32_t *oriented)
{
    uint32_t *sorted = NULL, *par = NULL, *adj = NULL, *vstart = NULL, *vlist = NULL;
    signed char *sign = NULL;
    face_t *f = NULL;
    size_t i, j, nf, maxf;
    int dim, st = VP_ENOMEM;
    if (!out || k < 1 || k > VP_MFCHECK_KMAX || (ns && !simp) || ns >= NONE || nv >= NONE) return VP_EINVAL;
    for (i = 0; i < ns * (size_t)(k + 1); i++) if (simp[i] >= nv) return VP_EINVAL;
    memset(out, 0, sizeof *out);
    out->k = k;
    out->orientable = -1;
    sorted = malloc((ns ? ns : 1) * (size_t)(k + 1) * sizeof *sorted);
    par = malloc((ns ? ns : 1) * sizeof *par);
    adj = malloc((ns ? ns : 1) * (size_t)(k + 1) * sizeof *adj);
    sign = malloc(ns ? ns : 1);
    maxf = binom(k + 1, (k + 1) / 2);
    f = malloc((ns ? ns : 1) * maxf * sizeof *f);
    vstart = calloc(nv + 1, sizeof *vstart);
    vlist = malloc((ns ? ns : 1) * (size_t)(k + 1) * sizeof *vlist);
    if (!sorted || !par || !adj || !sign || !f || !vstart || !vlist) goto done;
    for (i = 0; i < ns; i++) {
        memcpy(sorted + i * (k + 1), simp + i * (k + 1), (size_t)(k + 1) * sizeof *sorted);
        sort_small(sorted + i * (k + 1), k + 1);
        for (j = 0; j < (size_t)k; j++)
            if (sorted[i * (k + 1) + j] == sorted[i * (k + 1) + j + 1]) out->duplicates++;
    }
    /* face counts of every dimension; duplicates among the k-simplices */
    for (dim = 0; dim <= k; dim++) {
        nf = 0;
        for (i = 0; i < ns; i++) nf += add_faces(f + nf, sorted + i * (k + 1), k, dim, (uint32_t)i);
        qsort(f, nf, sizeof *f, face_cmp);
        for (i = 0; i < nf; i++)
            if (i == 0 || !face_same(&f[i], &f[i - 1])) out->faces[dim]++;
            else if (dim == k) out->duplicates++;
        out->euler += (dim % 2 ? -1 : 1) * (long)out->faces[dim];
    }
    /* (k-1)-faces: each in exactly two k-simplices; adjacency through them */
    for (i = 0; i < ns * (size_t)(k + 1); i++) adj[i] = NONE;
    for (i = 0; i < ns; i++) par[i] = (uint32_t)i;
    nf = 0;
    for (i = 0; i < ns; i++) nf += add_faces(f + nf, sorted + i * (k + 1), k, k - 1, (uint32_t)i);
    qsort(f, nf, sizeof *f, face_cmp);
    for (i = 0; i < nf; i = j) {
        for (j = i + 1; j < nf && face_same(&f[i], &f[j]); j++) {}
        if (j - i != 2) { out->bad_facets++; continue; }
        adj[f[i].simplex * (k + 1) + f[i].pos] = f[i + 1].simplex;
        adj[f[i + 1].simplex * (k + 1) + f[i + 1].pos] = f[i].simplex;
        uf_join(par, f[i].simplex, f[i + 1].simplex);
    }
    for (i = 0; i < ns; i++) if (uf_find(par, (uint32_t)i) == i) out->components++;
    /* vertex links */
    for (i = 0; i < ns * (size_t)(k + 1); i++) vstart[sorted[i] + 1]++;
    for (i = 0; i < nv; i++) vstart[i + 1] += vstart[i];
    {
        uint32_t *fill = calloc(nv + 1, sizeof *fill);
        uint32_t (*lk)[3] = NULL, (*scr)[2] = NULL;
        size_t maxdeg = 0;
        if (!fill) goto done;
        for (i = 0; i < ns * (size_t)(k + 1); i++) {
            uint32_t v = sorted[i];
            vlist[vstart[v] + fill[v]++] = (uint32_t)(i / (size_t)(k + 1));
        }
        free(fill);
        for (i = 0; i < nv; i++) if (vstart[i + 1] - vstart[i] > maxdeg) maxdeg = vstart[i + 1] - vstart[i];
        lk = malloc((maxdeg + 1) * sizeof *lk);
        scr = malloc((3 * maxdeg + 1) * sizeof *scr);
        if (!lk || !scr) { free(lk); free(scr); goto done; }
        for (i = 0; i < nv; i++) {
            size_t deg = vstart[i + 1] - vstart[i], m = 0, a;
            int ok;
            if (!deg) continue;   /* not a vertex of the complex */
            for (a = 0; a < deg; a++) {
                const uint32_t *s = sorted + (size_t)vlist[vstart[i] + a] * (k + 1);
                int c, w = 0;
                for (c = 0; c <= k; c++) if (s[c] != i) lk[m][w++] = s[c];
                m++;
            }
            if (k == 1) ok = deg == 2 && lk[0][0] != lk[1][0];
            else if (k == 2) {
                for (a = 0; a < m; a++) { scr[a][0] = lk[a][0]; scr[a][1] = lk[a][1]; }
                ok = one_cycle((const uint32_t (*)[2])scr, m);
            } else ok = is_sphere2((const uint32_t (*)[3])lk, m, scr);
            if (!ok) out->bad_links++;
        }
        free(lk);
        free(scr);
    }
    out->manifold = ns > 0 && !out->duplicates && !out->bad_facets && !out->bad_links;
    /* orientations: breadth-first through the shared (k-1)-faces. Simplex i's sign s induces
     * s * (-1)^pos on the face without its pos-th (sorted) vertex; neighbours must disagree. */
    if (out->manifold) {
        uint32_t *queue = vlist;   /* reused: ns entries needed, ns * (k+1) held */
        size_t qh, qt;
        out->orientable = 1;
        memset(sign, 0, ns);
        for (i = 0; i < ns; i++) {
            if (sign[i]) continue;
            sign[i] = 1;
            qh = qt = 0;
            queue[qt++] = (uint32_t)i;
            while (qh < qt) {
                uint32_t s = queue[qh++];
                int c;
                for (c = 0; c <= k; c++) {
                    uint32_t nb = adj[(size_t)s * (k + 1) + c];
                    int c2, want;
                    if (nb == NONE) continue;
                    for (c2 = 0; c2 <= k && adj[(size_t)nb * (k + 1) + c2] != s; c2++) {}
                    if (c2 > k) continue;
                    want = -sign[s] * ((c + c2) % 2 ? -1 : 1);
                    if (!sign[nb]) { sign[nb] = (signed char)want; queue[qt++] = nb; }
                    else if (sign[nb] != want) out->orientable = 0;
                }
            }
        }
    }
    if (oriented) {
        memcpy(oriented, sorted, ns * (size_t)(k + 1) * sizeof *oriented);
        if (out->orientable == 1)
            for (i = 0; i < ns; i++)
                if (sign[i] < 0) {
                    uint32_t t = oriented[i * (k + 1)];
                    oriented[i * (k + 1)] = oriented[i * (k + 1) + 1];
                    oriented[i * (k + 1) + 1] = t;
                }
    }
    st = VP_OK;
done:
    free(sorted); free(par); free(adj); free(sign); free(f); free(vstart); free(vlist);
    return st;
}
