/* vp_meshcheck — see vp_meshcheck.h. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_meshcheck.h"
#include "vp_status.h"
#include "vp_vec3.h"

typedef struct vp_dedge { uint32_t lo, hi; uint32_t face; uint32_t forward; } vp_dedge_t;

static int vp_dedge_cmp(const void *pa, const void *pb)
{
    const vp_dedge_t *a = pa, *b = pb;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    if (a->face != b->face) return a->face < b->face ? -1 : 1;
    return 0;
}

int vp_edge_cmp(const void *x, const void *y)
{
    const vp_edge_rec_t *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return p->f < q->f ? -1 : p->f > q->f;
}

uint32_t vp_uf_find(uint32_t *par, uint32_t x)
{
    while (par[x] != x) { par[x] = par[par[x]]; x = par[x]; }
    return x;
}

void vp_uf_join(uint32_t *par, uint32_t a, uint32_t b)
{
    a = vp_uf_find(par, a); b = vp_uf_find(par, b);
    if (a != b) { if (a < b) par[b] = a; else par[a] = b; }
}

static void vp_tri_vec(const vp_mesh_t *m, size_t f, const double **a, const double **b, const double **c)
{
    *a = m->xyz + 3 * (size_t)m->tri[3 * f];
    *b = m->xyz + 3 * (size_t)m->tri[3 * f + 1];
    *c = m->xyz + 3 * (size_t)m->tri[3 * f + 2];
}

static double vp_angle(const double *p, const double *q, const double *r)
{
    double u[3], v[3], c[3];
    int k;
    for (k = 0; k < 3; k++) { u[k] = q[k] - p[k]; v[k] = r[k] - p[k]; }
    vp_cross3(c, u, v);
    return atan2(vp_norm3(c), vp_dot3(u, v));
}

void vp_meshcheck_free(vp_meshcheck_t *r)
{
    if (!r) return;
    free(r->comp_of_face);
    free(r->comp);
    r->comp_of_face = NULL;
    r->comp = NULL;
}

/* Is the link of vertex v (edges opposite v in its faces) one cycle, or one path? */
static int vp_link_ok(const uint32_t *link, size_t nlink, uint32_t *ids, uint32_t *deg, uint32_t *par)
{
    size_t n = 0, i, j, ends = 0, roots = 0;
    for (i = 0; i < 2 * nlink; i++) {
        for (j = 0; j < n; j++) if (ids[j] == link[i]) break;
        if (j == n) { ids[n] = link[i]; deg[n] = 0; par[n] = (uint32_t)n; n++; }
        deg[j]++;
    }
    for (i = 0; i < nlink; i++) {
        uint32_t a = 0, b = 0;
        for (j = 0; j < n; j++) { if (ids[j] == link[2 * i]) a = (uint32_t)j; if (ids[j] == link[2 * i + 1]) b = (uint32_t)j; }
        vp_uf_join(par, a, b);
    }
    for (j = 0; j < n; j++) {
        if (deg[j] > 2) return 0;
        if (deg[j] == 1) ends++;
        if (vp_uf_find(par, (uint32_t)j) == j) roots++;
    }
    return roots == 1 && (ends == 0 || ends == 2);
}

/* What vp_meshcheck_analyze's parts share: the mesh, directed edges sorted by vertex pair,
 * face and vertex union-find parents, vertex -> faces (CSR), and the faces and vertices found
 * degenerate or non-manifold. */
typedef struct vp_mc_ws {
    vp_dedge_t *de;
    uint32_t *fpar, *vstart, *vfaces, *vpar, *stamp, *compmap;
    unsigned char *bad_vertex, *bad_face;
} vp_mc_ws_t;

/* Faces: degenerate ones, the smallest angle, the directed edges (sorted); vertex degrees. */
static void vp_mc_faces(const vp_mesh_t *m, vp_mc_ws_t *w, vp_meshcheck_t *r)
{
    size_t nt = m->nt, f, j;
    for (f = 0; f < nt; f++) {
        const uint32_t *t = m->tri + 3 * f;
        const double *a, *b, *cc;
        w->fpar[f] = (uint32_t)f;
        vp_tri_vec(m, f, &a, &b, &cc);
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) w->bad_face[f] = 1;
        else {
            double u[3], v[3], n[3];
            int k;
            for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = cc[k] - a[k]; }
            vp_cross3(n, u, v);
            if (n[0] == 0 && n[1] == 0 && n[2] == 0) w->bad_face[f] = 1;
            else {
                double a0 = vp_angle(a, b, cc), a1 = vp_angle(b, cc, a), a2 = vp_angle(cc, a, b), mn;
                mn = a0 < a1 ? a0 : a1;
                if (a2 < mn) mn = a2;
                mn *= 180.0 / 3.141592653589793;
                if (mn < r->min_angle_deg) r->min_angle_deg = mn;
            }
        }
        if (w->bad_face[f]) r->degenerate_faces++;
        for (j = 0; j < 3; j++) {
            uint32_t u = t[j], v = t[(j + 1) % 3];
            vp_dedge_t *e = &w->de[3 * f + j];
            e->lo = u < v ? u : v; e->hi = u < v ? v : u;
            e->face = (uint32_t)f; e->forward = u < v;
            w->vstart[t[j]]++;
        }
    }
    if (nt == 0) r->min_angle_deg = 0;
    qsort(w->de, 3 * nt, sizeof *w->de, vp_dedge_cmp);

}

/* Edges (boundary, misoriented, non-manifold) and the components joined across them. */
static int vp_mc_edges(const vp_mesh_t *m, vp_mc_ws_t *w, vp_meshcheck_t *r)
{
    size_t nt = m->nt, f, i, j, ne;
    int c;
    for (i = 0; i < 3 * nt; i = j) {
        size_t cnt;
        for (j = i + 1; j < 3 * nt && w->de[j].lo == w->de[i].lo && w->de[j].hi == w->de[i].hi; j++) {}
        cnt = j - i;
        r->edges++;
        if (w->de[i].lo == w->de[i].hi) continue;   /* from a degenerate face */
        if (cnt == 1) r->boundary_edges++;
        else if (cnt == 2) { if (w->de[i].forward == w->de[i + 1].forward) r->misoriented_edges++; }
        else {
            r->nonmanifold_edges++;
            w->bad_vertex[w->de[i].lo] = w->bad_vertex[w->de[i].hi] = 1;
        }
        for (ne = i + 1; ne < j; ne++) vp_uf_join(w->fpar, w->de[i].face, w->de[ne].face);
    }

    /* Components, numbered in order of their first face. */
    for (f = 0; f < nt; f++) w->compmap[f] = UINT32_MAX;
    r->components = 0;
    for (f = 0; f < nt; f++) {
        uint32_t root = vp_uf_find(w->fpar, (uint32_t)f);
        if (w->compmap[root] == UINT32_MAX) w->compmap[root] = (uint32_t)r->components++;
        r->comp_of_face[f] = (int)w->compmap[root];
    }
    r->comp = calloc((size_t)r->components + 1, sizeof *r->comp);
    if (!r->comp) return VP_ENOMEM;
    for (c = 0; c < r->components; c++) r->comp[c].manifold = 1;

    return VP_OK;
}

/* Vertex -> faces (CSR) and each vertex's link: one cycle (or a path on the boundary). */
static int vp_mc_links(const vp_mesh_t *m, vp_mc_ws_t *w, vp_meshcheck_t *r)
{
    size_t nt = m->nt, nv = m->nv, f, i, j, maxdeg = 0;
    uint32_t *link = NULL, *scratch = NULL;
    {
        size_t acc = 0;
        for (i = 0; i < nv; i++) {
            size_t d = w->vstart[i];
            w->vstart[i] = (uint32_t)acc;
            acc += d;
            if (d > maxdeg) maxdeg = d;
        }
        w->vstart[nv] = (uint32_t)acc;
    }
    {
        uint32_t *fill = malloc((nv + 1) * sizeof *fill);
        if (!fill) return VP_ENOMEM;
        memcpy(fill, w->vstart, (nv + 1) * sizeof *fill);
        for (f = 0; f < nt; f++)
            for (j = 0; j < 3; j++) w->vfaces[fill[m->tri[3 * f + j]]++] = (uint32_t)f;
        free(fill);
    }
    link = malloc((2 * maxdeg + 2) * sizeof *link);
    scratch = malloc((6 * maxdeg + 6) * sizeof *scratch);
    if (!link || !scratch) { free(link); free(scratch); return VP_ENOMEM; }
    for (i = 0; i < nv; i++) {
        size_t nl = 0, k;
        if (w->vstart[i + 1] == w->vstart[i]) { r->unused_vertices++; continue; }
        for (k = w->vstart[i]; k < w->vstart[i + 1]; k++) {
            const uint32_t *t = m->tri + 3 * (size_t)w->vfaces[k];
            int at = t[0] == i ? 0 : t[1] == i ? 1 : 2;
            if (w->bad_face[w->vfaces[k]]) { w->bad_vertex[i] = 1; continue; }
            link[2 * nl] = t[(at + 1) % 3];
            link[2 * nl + 1] = t[(at + 2) % 3];
            nl++;
        }
        if (!w->bad_vertex[i] && !vp_link_ok(link, nl, scratch, scratch + 2 * maxdeg + 2, scratch + 4 * maxdeg + 4))
            w->bad_vertex[i] = 1;
        if (w->bad_vertex[i]) r->nonmanifold_vertices++;
    }
    free(link);
    free(scratch);
    return VP_OK;
}

/* Per component: faces, vertices, edges, boundary edges and loops, area, volume, manifoldness. */
static int vp_mc_components(const vp_mesh_t *m, vp_mc_ws_t *w, vp_meshcheck_t *r)
{
    size_t nt = m->nt, nv = m->nv, f, i, j;
    int c;
    for (f = 0; f < nt; f++) {
        vp_mesh_component_t *cp = &r->comp[r->comp_of_face[f]];
        const double *a, *b, *cc;
        double u[3], v[3], n[3];
        int k;
        vp_tri_vec(m, f, &a, &b, &cc);
        for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = cc[k] - a[k]; }
        vp_cross3(n, u, v);
        cp->faces++;
        cp->area += 0.5 * vp_norm3(n);
        cp->volume += (a[0] * (b[1] * cc[2] - b[2] * cc[1]) - a[1] * (b[0] * cc[2] - b[2] * cc[0]) +
                       a[2] * (b[0] * cc[1] - b[1] * cc[0])) / 6.0;
        if (w->bad_face[f]) cp->manifold = 0;
    }
    for (i = 0; i < nv; i++) { w->stamp[i] = UINT32_MAX; w->vpar[i] = (uint32_t)i; }
    for (f = 0; f < nt; f++) {
        uint32_t cid = (uint32_t)r->comp_of_face[f];
        for (j = 0; j < 3; j++) {
            uint32_t v = m->tri[3 * f + j];
            if (w->bad_vertex[v]) r->comp[cid].manifold = 0;
        }
    }
    /* vertices per component: a vertex counts once for each component it touches */
    {
        size_t *order = malloc((nt + 1) * sizeof *order), *cstart = calloc((size_t)r->components + 1, sizeof *cstart);
        if (!order || !cstart) { free(order); free(cstart); return VP_ENOMEM; }
        for (f = 0; f < nt; f++) cstart[r->comp_of_face[f] + 1]++;
        for (c = 0; c < r->components; c++) cstart[c + 1] += cstart[c];
        for (f = 0; f < nt; f++) order[cstart[r->comp_of_face[f]]++] = f;
        for (f = 0; f < nt; f++) {
            size_t ff = order[f];
            uint32_t cid = (uint32_t)r->comp_of_face[ff];
            for (j = 0; j < 3; j++) {
                uint32_t v = m->tri[3 * ff + j];
                if (w->stamp[v] != cid) { w->stamp[v] = cid; r->comp[cid].vertices++; }
            }
        }
        free(order); free(cstart);
    }
    for (i = 0; i < 3 * nt; i = j) {
        size_t cnt;
        vp_mesh_component_t *cp;
        for (j = i + 1; j < 3 * nt && w->de[j].lo == w->de[i].lo && w->de[j].hi == w->de[i].hi; j++) {}
        cnt = j - i;
        cp = &r->comp[r->comp_of_face[w->de[i].face]];
        cp->edges++;
        if (w->de[i].lo == w->de[i].hi) continue;
        if (cnt == 1) { cp->boundary_edges++; vp_uf_join(w->vpar, w->de[i].lo, w->de[i].hi); }
        else if (cnt > 2 || w->de[i].forward == w->de[i + 1].forward) cp->manifold = cnt > 2 ? 0 : cp->manifold;
        if (cnt == 2 && w->de[i].forward == w->de[i + 1].forward) cp->genus = -2;   /* marks "misoriented" for now */
    }
    /* boundary loops: components of the boundary-edge graph */
    for (i = 0; i < nv; i++) w->stamp[i] = 0;
    for (i = 0; i < 3 * nt; i = j) {
        for (j = i + 1; j < 3 * nt && w->de[j].lo == w->de[i].lo && w->de[j].hi == w->de[i].hi; j++) {}
        if (j - i == 1 && w->de[i].lo != w->de[i].hi) {
            uint32_t root = vp_uf_find(w->vpar, w->de[i].lo);
            if (!w->stamp[root]) { w->stamp[root] = 1; r->comp[r->comp_of_face[w->de[i].face]].boundary_loops++; }
        }
    }
    return VP_OK;
}

/* Euler characteristic, genus, closed / oriented / outward, over the components. */
static void vp_mc_totals(const vp_mesh_t *m, vp_meshcheck_t *r)
{
    size_t nt = m->nt, nv = m->nv;
    int c;
    r->euler = 0;
    r->genus = 0;
    for (c = 0; c < r->components; c++) {
        vp_mesh_component_t *cp = &r->comp[c];
        long twice;
        int misoriented = cp->genus == -2;
        cp->euler = (long)cp->vertices - (long)cp->edges + (long)cp->faces;
        cp->closed = cp->manifold && cp->boundary_edges == 0;
        twice = 2 - cp->euler - (long)cp->boundary_loops;
        cp->genus = (cp->manifold && !misoriented && twice >= 0 && twice % 2 == 0) ? (int)(twice / 2) : -1;
        r->euler += cp->euler;
        if (cp->genus < 0 || r->genus < 0) r->genus = -1; else r->genus += cp->genus;
    }
    /* a vertex shared by two components was counted twice above; the global count uses it once */
    {
        size_t used = nv - r->unused_vertices, sumv = 0;
        for (c = 0; c < r->components; c++) sumv += r->comp[c].vertices;
        r->euler -= (long)(sumv - used);
    }
    r->closed_manifold = nt > 0 && r->boundary_edges == 0 && r->nonmanifold_edges == 0 &&
                         r->nonmanifold_vertices == 0 && r->degenerate_faces == 0;
    r->oriented = r->misoriented_edges == 0 && r->nonmanifold_edges == 0;
    r->outward = r->closed_manifold && r->oriented;
    for (c = 0; c < r->components; c++) if (!(r->comp[c].volume > 0)) r->outward = 0;
}

int vp_meshcheck_analyze(const vp_mesh_t *m, vp_meshcheck_t *r)
{
    size_t nt = m->nt, nv = m->nv, i;
    vp_mc_ws_t ws, *w = &ws;
    int st = VP_ENOMEM;
    memset(r, 0, sizeof *r);
    memset(w, 0, sizeof *w);
    r->nv = nv; r->nt = nt;
    r->min_angle_deg = 180;
    for (i = 0; i < 3 * nt; i++) if (m->tri[i] >= nv) return VP_EINVAL;
    if (nv > UINT32_MAX - 1 || nt > UINT32_MAX / 3) return VP_ERANGE;
    w->de = malloc((3 * nt + 1) * sizeof *w->de);
    w->fpar = malloc((nt + 1) * sizeof *w->fpar);
    w->vstart = calloc(nv + 1, sizeof *w->vstart);
    w->vfaces = malloc((3 * nt + 1) * sizeof *w->vfaces);
    w->vpar = malloc((nv + 1) * sizeof *w->vpar);
    w->stamp = malloc((nv + 1) * sizeof *w->stamp);
    w->bad_vertex = calloc(nv + 1, 1);
    w->bad_face = calloc(nt + 1, 1);
    r->comp_of_face = malloc((nt + 1) * sizeof(int));
    w->compmap = malloc((nt + 1) * sizeof *w->compmap);
    if (w->de && w->fpar && w->vstart && w->vfaces && w->vpar && w->stamp && w->bad_vertex && w->bad_face &&
        r->comp_of_face && w->compmap) {
        vp_mc_faces(m, w, r);
        st = vp_mc_edges(m, w, r);
        if (st == VP_OK) st = vp_mc_links(m, w, r);
        if (st == VP_OK) st = vp_mc_components(m, w, r);
        if (st == VP_OK) vp_mc_totals(m, r);
    }
    free(w->de); free(w->fpar); free(w->vstart); free(w->vfaces); free(w->vpar); free(w->stamp);
    free(w->compmap); free(w->bad_vertex); free(w->bad_face);
    if (st < 0) vp_meshcheck_free(r);
    return st;
}

void vp_meshcheck_print(const vp_meshcheck_t *r, void *file)
{
    FILE *f = file;
    int c;
    fprintf(f, "vertices %lu (unused %lu), triangles %lu, edges %lu\n", (unsigned long)r->nv,
            (unsigned long)r->unused_vertices, (unsigned long)r->nt, (unsigned long)r->edges);
    fprintf(f, "closed 2-manifold %s, oriented %s, outward %s\n", r->closed_manifold ? "yes" : "no",
            r->oriented ? "yes" : "no", r->outward ? "yes" : "no");
    fprintf(f, "boundary edges %lu, non-manifold edges %lu, non-manifold vertices %lu, misoriented edges %lu, degenerate faces %lu\n",
            (unsigned long)r->boundary_edges, (unsigned long)r->nonmanifold_edges, (unsigned long)r->nonmanifold_vertices,
            (unsigned long)r->misoriented_edges, (unsigned long)r->degenerate_faces);
    fprintf(f, "components %d, euler %ld, genus %d, smallest angle %.3f deg\n", r->components, r->euler, r->genus, r->min_angle_deg);
    for (c = 0; c < r->components && c < 50; c++)
        fprintf(f, "  component %d: faces %lu euler %ld genus %d boundary loops %lu area %.6g volume %.6g\n", c,
                (unsigned long)r->comp[c].faces, r->comp[c].euler, r->comp[c].genus,
                (unsigned long)r->comp[c].boundary_loops, r->comp[c].area, r->comp[c].volume);
}

/* Orients every connected component consistently (breadth-first across shared edges) and
 * outward (positive volume). The planner orients each facet by the side its probe came from;
 * this makes the file right even where a probe came at a grazing angle. Returns the number of
 * facets flipped against the planner's choice through *flipped (may be NULL). */
int vp_mesh_orient(vp_mesh_t *m)
{
    size_t nt = m->nt, i, nh = 3 * nt;
    vp_edge_rec_t *h = malloc((nh + 1) * sizeof *h);
    uint32_t *queue = malloc((nt + 1) * sizeof *queue), *comp = malloc((nt + 1) * sizeof *comp);
    unsigned char *flip = calloc(nt + 1, 1);
    uint32_t ncomp = 0;
    if (!h || !queue || !comp || !flip) { free(h); free(queue); free(comp); free(flip); return VP_ENOMEM; }
    for (i = 0; i < nt; i++) {
        int e;
        for (e = 0; e < 3; e++) {
            uint32_t a = m->tri[3 * i + (size_t)e], b = m->tri[3 * i + (size_t)((e + 1) % 3)];
            h[3 * i + (size_t)e].a = a < b ? a : b;
            h[3 * i + (size_t)e].b = a < b ? b : a;
            h[3 * i + (size_t)e].f = (uint32_t)i;
        }
        comp[i] = UINT32_MAX;
    }
    qsort(h, nh, sizeof *h, vp_edge_cmp);
    for (i = 0; i < nt; i++) {
        size_t qh = 0, qt = 0;
        double vol = 0.0;
        size_t j;
        if (comp[i] != UINT32_MAX) continue;
        comp[i] = ncomp;
        queue[qt++] = (uint32_t)i;
        while (qh < qt) {
            uint32_t f = queue[qh++];
            int e;
            for (e = 0; e < 3; e++) {
                uint32_t a = m->tri[3 * (size_t)f + (size_t)e], b = m->tri[3 * (size_t)f + (size_t)((e + 1) % 3)];
                vp_edge_rec_t key;
                size_t lo = 0, hi = nh;
                if (flip[f]) { uint32_t t = a; a = b; b = t; }
                key.a = a < b ? a : b; key.b = a < b ? b : a; key.f = 0;
                while (lo < hi) { size_t mid = (lo + hi) / 2; if (vp_edge_cmp(&h[mid], &key) < 0) lo = mid + 1; else hi = mid; }
                /* only a manifold edge (exactly two faces) carries orientation across */
                if (lo + 1 < nh && h[lo].a == key.a && h[lo].b == key.b && h[lo + 1].a == key.a &&
                    h[lo + 1].b == key.b && !(lo + 2 < nh && h[lo + 2].a == key.a && h[lo + 2].b == key.b)) {
                    uint32_t g = h[lo].f == f ? h[lo + 1].f : h[lo].f;
                    int k, same = 0;
                    if (comp[g] != UINT32_MAX) continue;
                    /* g must traverse the edge b -> a */
                    for (k = 0; k < 3; k++)
                        if (m->tri[3 * (size_t)g + (size_t)k] == a && m->tri[3 * (size_t)g + (size_t)((k + 1) % 3)] == b) same = 1;
                    flip[g] = (unsigned char)same;
                    comp[g] = ncomp;
                    queue[qt++] = g;
                }
            }
        }
        for (j = 0; j < qt; j++) {
            const uint32_t *t = m->tri + 3 * (size_t)queue[j];
            const double *a = m->xyz + 3 * (size_t)t[0], *b = m->xyz + 3 * (size_t)t[flip[queue[j]] ? 2 : 1],
                         *c = m->xyz + 3 * (size_t)t[flip[queue[j]] ? 1 : 2];
            vol += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                   a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
        if (vol < 0.0)
            for (j = 0; j < qt; j++) flip[queue[j]] ^= 1;
        ncomp++;
    }
    for (i = 0; i < nt; i++)
        if (flip[i]) {
            uint32_t t = m->tri[3 * i + 1];
            m->tri[3 * i + 1] = m->tri[3 * i + 2];
            m->tri[3 * i + 2] = t;
        }
    free(h); free(queue); free(comp); free(flip);
    return VP_OK;
}
