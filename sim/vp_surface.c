/* vp_surface — see vp_surface.h. Each term is an implicit object (vp_implicit) or a closed
 * triangle mesh (vp_bvh), placed by a uniform scale and a translation. */
#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_bvh.h"
#include "vp_implicit.h"
#include "vp_kdtree.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_rng.h"
#include "vp_file.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_vec3.h"

#define VP_TERM_MESH 100
#define VP_TERM_TEXT 256
#define VP_CELL_GRID 40
#define VP_SEED_COUNT 16384
#define VP_SEED_K 3

typedef struct vp_term {
    int kind;                  /* VP_IMP_* or VP_TERM_MESH */
    double scale, c[3];        /* world = c + scale * local */
    double llo[3], lhi[3];     /* local box holding the solid */
    double lo[3], hi[3];       /* world box */
    char text[VP_TERM_TEXT + 32]; /* "term N '...'", for messages */
    int first_comp, ncomp, genus;
    double area;               /* world units */
    /* implicit terms */
    double interior[3];                 /* local, f < 0 */
    vp_kdtree_t *seeds;                 /* surface points starting closest-point searches */
    uint32_t *cells; size_t ncells;     /* grid cells near the surface (sampling) */
    double cell[3], shell;
    /* mesh terms */
    vp_mesh_t mesh;
    vp_bvh_t *bvh;
    double *cdf;                        /* cumulative face area */
    double *comp_interior;              /* 3 per component, local */
    double orient;                      /* +1 if the faces point outward, -1 if inward */
} vp_term_t;

struct vp_surface {
    vp_term_t *term;
    int nterm, ncomp, genus;
    double lo[3], hi[3], area;
};

static const char vp_help_text[] =
"Object specs (the simulated object; --surface SPEC):\n"
"  SPEC  = TERM ( '+' TERM )*            several terms = several components\n"
"  TERM  = NAME [ '*' SCALE ] [ '@' X ',' Y ',' Z ]   (modifiers in either order)\n"
"  NAME  = sphere      unit sphere\n"
"          torus       (sqrt(x^2+y^2)-1)^2 + z^2 - 0.3^2\n"
"          genus2      smooth union of two tori centred at (+-1,0,0) (ANCHORS.md)\n"
"          ellipsoid   semi-axes 1, 0.7, 0.5\n"
"          genus5      x^4-5x^2+y^4-5y^2+z^4-5z^2+11.8 = 0 (a cube frame)\n"
"          blobby      metaball of four Gaussian balls, one smooth component\n"
"          off:PATH    closed triangle mesh in OFF format\n"
"          ply:PATH    closed triangle mesh in PLY format (ascii or binary)\n"
"  A term is centre + SCALE * object (SCALE > 0, default 1; centre default 0,0,0).\n"
"  '+' starts a new term only before a NAME, so 1e+2 and paths with '+' are safe;\n"
"  in a PATH, '*' and '@' count as modifiers only in a final suffix.\n"
"  Terms must be disjoint: surfaces at least 1% of the smaller term's box diagonal apart.\n"
"  Examples: sphere@3,0,0+torus   sphere*0.5@2,0,0+genus2   off:part.off*2@0,0,1\n";

const char *vp_surface_help(void) { return vp_help_text; }

static void vp_to_local(const vp_term_t *T, const double w[3], double l[3])
{
    int k;
    for (k = 0; k < 3; k++) l[k] = (w[k] - T->c[k]) / T->scale;
}

static void vp_to_world(const vp_term_t *T, const double l[3], double w[3])
{
    int k;
    for (k = 0; k < 3; k++) w[k] = T->c[k] + T->scale * l[k];
}

/* ---------- spec parsing ---------- */

/* Length of the NAME at s (0 if none); *kind = VP_IMP_* or -1 for off:, -2 for ply:. */
static size_t vp_name_at(const char *s, int *kind)
{
    size_t n = 0;
    int k;
    if (!strncmp(s, "off:", 4)) { *kind = -1; return 4; }
    if (!strncmp(s, "ply:", 4)) { *kind = -2; return 4; }
    while (isalnum((unsigned char)s[n])) n++;
    if (n == 0) return 0;
    if (s[n] && s[n] != '*' && s[n] != '@' && s[n] != '+') return 0;
    k = vp_imp_from_name(s, (unsigned long)n);
    if (k < 0) return 0;
    *kind = k;
    return n;
}

static int vp_parse_number(const char *s, const char **end, double *v)
{
    char *e;
    if (!*s || isspace((unsigned char)*s)) return -1;
    *v = strtod(s, &e);
    if (e == s || !isfinite(*v)) return -1;
    *end = e;
    return 0;
}

/* Parses a complete modifier string ("*S", "@x,y,z", both in either order); 0 or -1. */
static int vp_parse_mods(const char *s, double *scale, double c[3])
{
    int have_scale = 0, have_at = 0, k;
    while (*s) {
        const char *e;
        if (*s == '*' && !have_scale) {
            if (vp_parse_number(s + 1, &e, scale) < 0 || !(*scale > 0)) return -1;
            have_scale = 1; s = e;
        } else if (*s == '@' && !have_at) {
            s++;
            for (k = 0; k < 3; k++) {
                if (vp_parse_number(s, &e, &c[k]) < 0) return -1;
                s = e;
                if (k < 2) { if (*s != ',') return -1; s++; }
            }
            have_at = 1;
        } else return -1;
    }
    return 0;
}

/* ---------- implicit terms ---------- */

static void vp_cell_box(const vp_term_t *T, uint32_t id, double lo[3], double hi[3])
{
    uint32_t i = id % VP_CELL_GRID, j = (id / VP_CELL_GRID) % VP_CELL_GRID, k = id / (VP_CELL_GRID * VP_CELL_GRID);
    lo[0] = T->llo[0] + i * T->cell[0]; hi[0] = lo[0] + T->cell[0];
    lo[1] = T->llo[1] + j * T->cell[1]; hi[1] = lo[1] + T->cell[1];
    lo[2] = T->llo[2] + k * T->cell[2]; hi[2] = lo[2] + T->cell[2];
}

/* One shell sample: uniform in the cells near the surface, kept when |f|/|grad f| < shell,
 * then projected. Returns 1 on success (q set), 0 if this try was rejected. */
static int vp_shell_try(const vp_term_t *T, vp_rng_t *r, double q[3], int *in_shell)
{
    double lo[3], hi[3], x[3], g[3], f, gn;
    int k;
    vp_cell_box(T, T->cells[vp_rng_below(r, T->ncells)], lo, hi);
    for (k = 0; k < 3; k++) x[k] = lo[k] + vp_rng_uniform(r) * (hi[k] - lo[k]);
    f = vp_imp_grad(T->kind, x, g);
    gn = vp_norm3(g);
    *in_shell = fabs(f) < T->shell * gn;
    if (!*in_shell) return 0;
    if (vp_imp_project(T->kind, x, q) < 0) return 0;
    return vp_dist3(q, x) <= 2 * T->shell;
}

static void vp_sample_local(const vp_term_t *T, vp_rng_t *r, double q[3])
{
    int k;
    switch (T->kind) {
    case VP_IMP_SPHERE:
        vp_rng_unit3(r, q);
        return;
    case VP_IMP_TORUS:
        for (;;) {
            double th = 6.283185307179586 * vp_rng_uniform(r), ph = 6.283185307179586 * vp_rng_uniform(r);
            double w = 1 + 0.3 * cos(ph);
            if (vp_rng_uniform(r) * 1.3 >= w) continue;   /* area element is proportional to w */
            q[0] = w * cos(th); q[1] = w * sin(th); q[2] = 0.3 * sin(ph);
            return;
        }
    case VP_IMP_ELLIPSOID:
        for (;;) {
            static const double ax[3] = { 1.0, 0.7, 0.5 };
            double u[3], fac = 0;
            vp_rng_unit3(r, u);
            for (k = 0; k < 3; k++) fac += (u[k] / ax[k]) * (u[k] / ax[k]);
            if (vp_rng_uniform(r) * 2.0 >= sqrt(fac)) continue;   /* area element ~ |A^-T u| */
            for (k = 0; k < 3; k++) q[k] = ax[k] * u[k];
            return;
        }
    case VP_TERM_MESH: {
        size_t lo = 0, hi = T->mesh.nt - 1;
        double target = vp_rng_uniform(r) * T->cdf[T->mesh.nt - 1], a = vp_rng_uniform(r), b = vp_rng_uniform(r);
        const double *v0, *v1, *v2;
        while (lo < hi) { size_t mid = (lo + hi) / 2; if (T->cdf[mid] > target) hi = mid; else lo = mid + 1; }
        if (a + b > 1) { a = 1 - a; b = 1 - b; }
        v0 = T->mesh.xyz + 3 * T->mesh.tri[3 * lo];
        v1 = T->mesh.xyz + 3 * T->mesh.tri[3 * lo + 1];
        v2 = T->mesh.xyz + 3 * T->mesh.tri[3 * lo + 2];
        for (k = 0; k < 3; k++) q[k] = v0[k] + a * (v1[k] - v0[k]) + b * (v2[k] - v0[k]);
        return;
    }
    default: {
        int in_shell, tries;
        for (tries = 0; tries < 1000000; tries++)
            if (vp_shell_try(T, r, q, &in_shell)) return;
        memcpy(q, T->interior, 3 * sizeof(double));   /* not reached for the built-in objects */
    }
    }
}

static int vp_imp_term_init(vp_term_t *T, char *err, size_t errlen)
{
    int i, j, k;
    double best = DBL_MAX;
    vp_imp_bbox(T->kind, T->llo, T->lhi);
    T->ncomp = 1;
    T->genus = vp_imp_genus(T->kind);
    /* Interior point: the lowest f on a grid. */
    for (i = 0; i <= 30; i++)
        for (j = 0; j <= 30; j++)
            for (k = 0; k <= 30; k++) {
                double p[3], f;
                p[0] = T->llo[0] + (T->lhi[0] - T->llo[0]) * i / 30.0;
                p[1] = T->llo[1] + (T->lhi[1] - T->llo[1]) * j / 30.0;
                p[2] = T->llo[2] + (T->lhi[2] - T->llo[2]) * k / 30.0;
                f = vp_imp_f(T->kind, p);
                if (f < best) { best = f; memcpy(T->interior, p, sizeof T->interior); }
            }
    if (!(best < 0)) { vp_seterr(err, errlen, "%s: no interior point found", T->text); return VP_EDEGEN; }
    if (T->kind == VP_IMP_SPHERE) { T->area = 4 * 3.141592653589793; return VP_OK; }
    if (T->kind == VP_IMP_TORUS) { T->area = 4 * 3.141592653589793 * 3.141592653589793 * 0.3; return VP_OK; }
    /* Cells near the surface, for sampling and the area estimate. */
    {
        size_t n = (size_t)VP_CELL_GRID * VP_CELL_GRID * VP_CELL_GRID, id;
        double mincell;
        for (k = 0; k < 3; k++) T->cell[k] = (T->lhi[k] - T->llo[k]) / VP_CELL_GRID;
        mincell = T->cell[0] < T->cell[1] ? T->cell[0] : T->cell[1];
        if (T->cell[2] < mincell) mincell = T->cell[2];
        T->shell = 0.25 * mincell;
        T->cells = malloc(n * sizeof(uint32_t));
        if (!T->cells) return VP_ENOMEM;
        T->ncells = 0;
        for (id = 0; id < n; id++) {
            double lo[3], hi[3], F[2];
            vp_cell_box(T, (uint32_t)id, lo, hi);
            for (k = 0; k < 3; k++) { lo[k] -= T->shell; hi[k] += T->shell; }
            vp_imp_fbox(T->kind, lo, hi, F);
            if (F[0] <= 0 && F[1] >= 0) T->cells[T->ncells++] = (uint32_t)id;
        }
        if (T->ncells == 0) { vp_seterr(err, errlen, "%s: surface not found", T->text); return VP_EDEGEN; }
    }
    {
        vp_rng_t r;
        size_t tries = 400000, t, hits = 0;
        double q[3];
        int in_shell;
        vp_rng_seed(&r, 0x5eed0001u + (uint64_t)T->kind);
        for (t = 0; t < tries; t++) { vp_shell_try(T, &r, q, &in_shell); hits += (size_t)in_shell; }
        T->area = (double)hits / (double)tries * (double)T->ncells * T->cell[0] * T->cell[1] * T->cell[2] / (2 * T->shell);
    }
    if (T->kind != VP_IMP_ELLIPSOID) {
        double *pts = malloc(VP_SEED_COUNT * 3 * sizeof(double));
        vp_rng_t r;
        size_t s;
        int st;
        if (!pts) return VP_ENOMEM;
        vp_rng_seed(&r, 0x5eed0002u + (uint64_t)T->kind);
        for (s = 0; s < VP_SEED_COUNT; s++) vp_sample_local(T, &r, pts + 3 * s);
        st = vp_kdtree_build(pts, VP_SEED_COUNT, &T->seeds);
        free(pts);
        if (st < 0) return st;
    }
    return VP_OK;
}

/* ---------- mesh terms ---------- */

static int vp_mesh_term_init(vp_term_t *T, const char *path, char *err, size_t errlen)
{
    vp_meshcheck_t mc;
    char msg[400];
    int st, c, k;
    size_t f;
    double vol = 0;
    st = vp_mesh_read_file(path, &T->mesh, msg, sizeof msg);
    if (st < 0) { vp_seterr(err, errlen, "%s: %s", T->text, msg); return st; }
    if (T->mesh.nt == 0) { vp_seterr(err, errlen, "%s: mesh has no faces", T->text); return VP_EINVAL; }
    st = vp_meshcheck_analyze(&T->mesh, &mc);
    if (st < 0) { vp_seterr(err, errlen, "%s: mesh analysis failed: %s", T->text, vp_strerror(st)); return st; }
    if (mc.boundary_edges) {
        vp_seterr(err, errlen, "%s: mesh is not closed (%lu boundary edges)", T->text, (unsigned long)mc.boundary_edges);
        vp_meshcheck_free(&mc);
        return VP_EINVAL;
    }
    T->ncomp = mc.components;
    T->genus = mc.closed_manifold && mc.oriented ? mc.genus : -1;
    for (c = 0; c < mc.components; c++) vol += mc.comp[c].volume;
    T->orient = vol >= 0 ? 1.0 : -1.0;
    st = vp_bvh_build(T->mesh.xyz, T->mesh.nv, T->mesh.tri, T->mesh.nt, &T->bvh);
    T->cdf = malloc(T->mesh.nt * sizeof(double));
    T->comp_interior = malloc((size_t)mc.components * 3 * sizeof(double));
    if (st < 0 || !T->cdf || !T->comp_interior) { vp_meshcheck_free(&mc); return st < 0 ? st : VP_ENOMEM; }
    vp_bvh_bounds(T->bvh, T->llo, T->lhi);
    {
        double acc = 0, *bestarea = calloc((size_t)mc.components, sizeof(double));
        size_t *bestface = calloc((size_t)mc.components, sizeof(size_t));
        if (!bestarea || !bestface) { free(bestarea); free(bestface); vp_meshcheck_free(&mc); return VP_ENOMEM; }
        for (f = 0; f < T->mesh.nt; f++) {
            const double *a = T->mesh.xyz + 3 * T->mesh.tri[3 * f], *b = T->mesh.xyz + 3 * T->mesh.tri[3 * f + 1],
                         *d = T->mesh.xyz + 3 * T->mesh.tri[3 * f + 2];
            double u[3], v[3], n[3], ar;
            for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = d[k] - a[k]; }
            vp_cross3(n, u, v);
            ar = 0.5 * vp_norm3(n);
            acc += ar;
            T->cdf[f] = acc;
            c = mc.comp_of_face[f];
            if (ar > bestarea[c]) { bestarea[c] = ar; bestface[c] = f; }
        }
        T->area = acc;
        /* Interior point of each component: from the centroid of its largest face, halfway to
         * the next crossing on the inner side (checked by parity). */
        for (c = 0; c < mc.components; c++) {
            size_t ff = bestface[c];
            const double *a = T->mesh.xyz + 3 * T->mesh.tri[3 * ff], *b = T->mesh.xyz + 3 * T->mesh.tri[3 * ff + 1],
                         *d = T->mesh.xyz + 3 * T->mesh.tri[3 * ff + 2];
            double g[3], u[3], v[3], n[3], th, m[3];
            int side, found = 0;
            for (k = 0; k < 3; k++) { g[k] = (a[k] + b[k] + d[k]) / 3; u[k] = b[k] - a[k]; v[k] = d[k] - a[k]; }
            vp_cross3(n, u, v);
            /* a component of zero-area faces only: no direction, no interior point */
            for (side = vp_normalize3(n) ? -1 : 3; side <= 1 && !found; side += 2) {
                double dir[3];
                for (k = 0; k < 3; k++) dir[k] = side * n[k];
                if (!vp_bvh_ray(T->bvh, g, dir, 1e-12 * (1 + fabs(g[0]) + fabs(g[1]) + fabs(g[2])), DBL_MAX, &th, NULL)) continue;
                for (k = 0; k < 3; k++) m[k] = g[k] + 0.5 * th * dir[k];
                if (vp_bvh_inside(T->bvh, m)) { found = 1; memcpy(T->comp_interior + 3 * c, m, sizeof m); }
            }
            if (!found) {
                free(bestarea); free(bestface); vp_meshcheck_free(&mc);
                vp_seterr(err, errlen, "%s: no interior point found for component %d", T->text, c);
                return VP_EDEGEN;
            }
        }
        free(bestarea); free(bestface);
    }
    vp_meshcheck_free(&mc);
    for (k = 0; k < 3; k++) {   /* small margin */
        double pad = 1e-9 * (T->lhi[k] - T->llo[k]) + 1e-12;
        T->llo[k] -= pad; T->lhi[k] += pad;
    }
    return VP_OK;
}

static void vp_term_free(vp_term_t *T)
{
    vp_kdtree_free(T->seeds);
    free(T->cells);
    vp_mesh_free(&T->mesh);
    vp_bvh_free(T->bvh);
    free(T->cdf);
    free(T->comp_interior);
}

/* ---------- per-term queries (world coordinates in, world out) ---------- */

static int vp_term_inside(const vp_term_t *T, const double w[3])
{
    double l[3];
    int k;
    for (k = 0; k < 3; k++) if (w[k] < T->lo[k] || w[k] > T->hi[k]) return 0;
    vp_to_local(T, w, l);
    if (T->kind == VP_TERM_MESH) return vp_bvh_inside(T->bvh, l);
    return vp_imp_f(T->kind, l) < 0;
}

/* Closest point in the local frame. */
static double vp_term_closest_local(const vp_term_t *T, const double p[3], double q[3])
{
    double d;
    if (T->kind == VP_TERM_MESH) return vp_bvh_closest(T->bvh, p, q, NULL);
    d = vp_imp_closest_exact(T->kind, p, q);
    if (d >= 0) return d;
    {
        size_t idx[VP_SEED_K], n, i;
        double d2[VP_SEED_K], best = DBL_MAX, cand[3];
        n = vp_kdtree_knn(T->seeds, p, VP_SEED_K, idx, d2);
        for (i = 0; i < n; i++) {
            /* a start farther than twice the best distance cannot lead closer in practice */
            if (i > 0 && sqrt(d2[i]) > 2 * best + T->shell) break;
            d = vp_imp_foot(T->kind, p, vp_kdtree_point(T->seeds, idx[i]), cand);
            if (d < best) { best = d; memcpy(q, cand, sizeof cand); }
        }
        return best;
    }
}

static double vp_box_dist(const double lo[3], const double hi[3], const double p[3])
{
    double s = 0;
    int k;
    for (k = 0; k < 3; k++) {
        double e = p[k] < lo[k] ? lo[k] - p[k] : p[k] > hi[k] ? p[k] - hi[k] : 0;
        s += e * e;
    }
    return sqrt(s);
}

/* Entry parameter of the ray into the box within [t0,t1], or -1. */
static double vp_ray_box_enter(const double lo[3], const double hi[3], const double o[3], const double d[3], double t0, double t1)
{
    int k;
    for (k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return -1;
        } else {
            double u = (lo[k] - o[k]) / d[k], v = (hi[k] - o[k]) / d[k];
            if (u > v) { double s = u; u = v; v = s; }
            if (u > t0) t0 = u;
            if (v < t1) t1 = v;
            if (t0 > t1) return -1;
        }
    }
    return t0;
}

/* Does a segment (local frame, clearance r) come within r of an implicit term's surface or
 * enter it? Subdivision: interval bounds on f over the swept box, then distance bounds
 * (distance to the surface is 1-Lipschitz). */
static int vp_imp_segment_collides(const vp_term_t *T, const double a[3], const double b[3], double r)
{
    struct { double t0, t1; } st[128];
    int sp = 1, k;
    double len = vp_dist3(a, b);
    if (T->kind == VP_IMP_SPHERE) {
        double d[3], dd = 0, s = 0, c[3];
        for (k = 0; k < 3; k++) { d[k] = b[k] - a[k]; dd += d[k] * d[k]; s -= a[k] * d[k]; }
        s = dd > 0 ? s / dd : 0;
        if (s < 0) s = 0;
        if (s > 1) s = 1;
        for (k = 0; k < 3; k++) c[k] = a[k] + s * d[k];
        return vp_norm3(c) <= 1 + r;
    }
    st[0].t0 = 0; st[0].t1 = 1;
    while (sp > 0) {
        double t0 = st[sp - 1].t0, t1 = st[sp - 1].t1, lo[3], hi[3], F[2], m[3], q[3], h, dm, tm;
        sp--;
        for (k = 0; k < 3; k++) {
            double u = a[k] + t0 * (b[k] - a[k]), v = a[k] + t1 * (b[k] - a[k]);
            lo[k] = (u < v ? u : v) - r; hi[k] = (u < v ? v : u) + r;
        }
        vp_imp_fbox(T->kind, lo, hi, F);
        if (F[0] > 0) continue;              /* the whole swept box is outside */
        tm = 0.5 * (t0 + t1);
        for (k = 0; k < 3; k++) m[k] = a[k] + tm * (b[k] - a[k]);
        if (vp_imp_f(T->kind, m) <= 0) return 1;
        if (F[1] < 0) return 1;
        h = 0.5 * (t1 - t0) * len;
        dm = vp_term_closest_local(T, m, q);
        if (dm <= r) return 1;
        if (dm - h > r) continue;
        if (h < 1e-12 || sp >= 126) return 1;   /* within r + 1e-12: count as touching */
        st[sp].t0 = tm; st[sp].t1 = t1; sp++;
        st[sp].t0 = t0; st[sp].t1 = tm; sp++;
    }
    return 0;
}

/* ---------- open / close ---------- */

static int vp_boxes_near(const double alo[3], const double ahi[3], const double blo[3], const double bhi[3], double gap)
{
    int k;
    for (k = 0; k < 3; k++)
        if (alo[k] > bhi[k] + gap || blo[k] > ahi[k] + gap) return 0;
    return 1;
}

static double vp_term_diag(const vp_term_t *T)
{
    double s = 0;
    int k;
    for (k = 0; k < 3; k++) s += (T->hi[k] - T->lo[k]) * (T->hi[k] - T->lo[k]);
    return sqrt(s);
}

/* Checks that no sample of term A's surface lies inside B or closer than gap to it. */
static int vp_terms_apart(const vp_term_t *A, const vp_term_t *B, double gap)
{
    vp_rng_t r;
    int i;
    vp_rng_seed(&r, 0x0ec1a9u);
    for (i = 0; i < 3000; i++) {
        double l[3], w[3], lb[3], q[3];
        vp_sample_local(A, &r, l);
        vp_to_world(A, l, w);
        if (vp_box_dist(B->lo, B->hi, w) >= gap) continue;
        if (vp_term_inside(B, w)) return 0;
        vp_to_local(B, w, lb);
        if (vp_term_closest_local(B, lb, q) * B->scale < gap) return 0;
    }
    return 1;
}

int vp_surface_open(const char *spec, vp_surface_t **out, char *err, size_t errlen)
{
    vp_surface_t *s;
    size_t len, start, i;
    int st = VP_OK, t, k;
    if (err && errlen) err[0] = 0;
    if (!spec || !out) { vp_seterr(err, errlen, "no object spec"); return VP_EINVAL; }
    len = strlen(spec);
    if (len == 0) { vp_seterr(err, errlen, "empty object spec (try 'sphere', or see --help)"); return VP_EINVAL; }
    s = calloc(1, sizeof *s);
    if (!s) return VP_ENOMEM;
    /* Split at '+' followed by a NAME. */
    start = 0;
    for (i = 0; i <= len; i++) {
        int kind;
        if (i < len && !(spec[i] == '+' && i > start && vp_name_at(spec + i + 1, &kind))) continue;
        {
            vp_term_t *T, *nt = realloc(s->term, (size_t)(s->nterm + 1) * sizeof *nt);
            char text[VP_TERM_TEXT];
            size_t n = i - start, nl;
            if (!nt) { st = VP_ENOMEM; goto fail; }
            s->term = nt;
            T = &s->term[s->nterm++];
            memset(T, 0, sizeof *T);
            T->scale = 1;
            if (n >= VP_TERM_TEXT) {
                vp_seterr(err, errlen, "term %d of the spec is too long: %lu characters, at most %d (a mesh in a "
                          "deep folder: give a shorter path or a link to it)", s->nterm, (unsigned long)n, VP_TERM_TEXT - 1);
                st = VP_EINVAL;
                goto fail;
            }
            memcpy(text, spec + start, n); text[n] = 0;
            snprintf(T->text, sizeof T->text, "term %d '%s'", s->nterm, text);
            nl = vp_name_at(text, &kind);
            if (!nl) {
                vp_seterr(err, errlen, "%s: unknown object (known: sphere torus genus2 ellipsoid genus5 blobby off:PATH ply:PATH)", T->text);
                st = VP_EINVAL; goto fail;
            }
            if (kind >= 0) {
                T->kind = kind;
                if (text[nl] == '+' && vp_parse_mods(text + nl, &T->scale, T->c) < 0) {
                    vp_seterr(err, errlen, "%s: unknown object '%s' after '+' (known: sphere torus genus2 ellipsoid genus5 blobby off:PATH ply:PATH)",
                              T->text, text + nl + 1);
                    st = VP_EINVAL; goto fail;
                }
                if (vp_parse_mods(text + nl, &T->scale, T->c) < 0) {
                    vp_seterr(err, errlen, "%s: bad modifiers '%s' (expected *SCALE with SCALE > 0 and/or @X,Y,Z)", T->text, text + nl);
                    st = VP_EINVAL; goto fail;
                }
                if ((st = vp_imp_term_init(T, err, errlen)) < 0) goto fail;
            } else {
                size_t j, pend = n;
                for (j = nl + 1; j < n; j++) {
                    double sc = 1, cc[3] = { 0, 0, 0 };
                    if ((text[j] == '*' || text[j] == '@') && vp_parse_mods(text + j, &sc, cc) == 0) {
                        pend = j; T->scale = sc; memcpy(T->c, cc, sizeof cc);
                        break;
                    }
                }
                text[pend] = 0;
                if (pend == nl) { vp_seterr(err, errlen, "%s: missing file path", T->text); st = VP_EINVAL; goto fail; }
                T->kind = VP_TERM_MESH;
                if ((st = vp_mesh_term_init(T, text + nl, err, errlen)) < 0) goto fail;
            }
            for (k = 0; k < 3; k++) {
                T->lo[k] = T->c[k] + T->scale * T->llo[k];
                T->hi[k] = T->c[k] + T->scale * T->lhi[k];
            }
            T->area *= T->scale * T->scale;
            T->first_comp = s->ncomp;
            s->ncomp += T->ncomp;
            start = i + 1;
        }
    }
    /* Terms must be apart. */
    for (t = 0; t < s->nterm; t++) {
        int u;
        for (u = 0; u < t; u++) {
            vp_term_t *A = &s->term[u], *B = &s->term[t];
            double da = vp_term_diag(A), db = vp_term_diag(B), gap = 0.01 * (da < db ? da : db);
            if (!vp_boxes_near(A->lo, A->hi, B->lo, B->hi, gap)) continue;
            if (!vp_terms_apart(A, B, gap) || !vp_terms_apart(B, A, gap)) {
                vp_seterr(err, errlen, "%s overlaps or nearly touches %s (components must be at least %g apart)",
                          B->text, A->text, gap);
                st = VP_ERANGE; goto fail;
            }
        }
    }
    s->genus = 0;
    for (k = 0; k < 3; k++) { s->lo[k] = DBL_MAX; s->hi[k] = -DBL_MAX; }
    for (t = 0; t < s->nterm; t++) {
        vp_term_t *T = &s->term[t];
        if (T->genus < 0 || s->genus < 0) s->genus = -1; else s->genus += T->genus;
        s->area += T->area;
        for (k = 0; k < 3; k++) {
            if (T->lo[k] < s->lo[k]) s->lo[k] = T->lo[k];
            if (T->hi[k] > s->hi[k]) s->hi[k] = T->hi[k];
        }
    }
    *out = s;
    return VP_OK;
fail:
    vp_surface_close(s);
    return st;
}

void vp_surface_close(vp_surface_t *s)
{
    int t;
    if (!s) return;
    for (t = 0; t < s->nterm; t++) vp_term_free(&s->term[t]);
    free(s->term);
    free(s);
}

/* ---------- public queries ---------- */

void vp_surface_bbox(const vp_surface_t *s, double lo[3], double hi[3])
{
    memcpy(lo, s->lo, sizeof s->lo);
    memcpy(hi, s->hi, sizeof s->hi);
}

int vp_surface_components(const vp_surface_t *s) { return s->ncomp; }
int vp_surface_genus(const vp_surface_t *s) { return s->genus; }
double vp_surface_area(const vp_surface_t *s) { return s->area; }

void vp_surface_interior_point(const vp_surface_t *s, int comp, double p[3])
{
    int t;
    for (t = 0; t < s->nterm; t++) {
        const vp_term_t *T = &s->term[t];
        if (comp >= T->first_comp && comp < T->first_comp + T->ncomp) {
            vp_to_world(T, T->kind == VP_TERM_MESH ? T->comp_interior + 3 * (comp - T->first_comp) : T->interior, p);
            return;
        }
    }
    p[0] = p[1] = p[2] = NAN;
}

int vp_surface_inside(const vp_surface_t *s, const double p[3])
{
    int t;
    for (t = 0; t < s->nterm; t++)
        if (vp_term_inside(&s->term[t], p)) return 1;
    return 0;
}

int vp_surface_ray(const vp_surface_t *s, const double o[3], const double dir[3], double tmax, double *t_hit)
{
    double best = tmax;
    int t, hit = 0;
    if (!(tmax > 0)) return 0;
    for (t = 0; t < s->nterm; t++) {
        const vp_term_t *T = &s->term[t];
        double l[3], lt, enter = vp_ray_box_enter(T->lo, T->hi, o, dir, 0, best);
        int ok;
        if (enter < 0) continue;
        vp_to_local(T, o, l);
        if (T->kind == VP_TERM_MESH) ok = vp_bvh_ray(T->bvh, l, dir, 0, best / T->scale, &lt, NULL);
        else ok = vp_imp_ray(T->kind, l, dir, 0, best / T->scale, &lt);
        if (ok && lt * T->scale <= best) { best = lt * T->scale; hit = 1; }
    }
    if (hit) *t_hit = best;
    return hit;
}

int vp_surface_segment_collides(const vp_surface_t *s, const double a[3], const double b[3], double clearance)
{
    int t, k;
    if (clearance < 0) clearance = 0;
    for (t = 0; t < s->nterm; t++) {
        const vp_term_t *T = &s->term[t];
        double la[3], lb[3], r = clearance / T->scale;
        int near = 1;
        for (k = 0; k < 3; k++) {
            double lo = a[k] < b[k] ? a[k] : b[k], hi = a[k] < b[k] ? b[k] : a[k];
            if (lo > T->hi[k] + clearance || hi < T->lo[k] - clearance) near = 0;
        }
        if (!near) continue;
        vp_to_local(T, a, la);
        vp_to_local(T, b, lb);
        if (T->kind == VP_TERM_MESH) {
            if (vp_bvh_inside(T->bvh, la) || vp_bvh_segment_near(T->bvh, la, lb, r)) return 1;
        } else if (vp_imp_segment_collides(T, la, lb, r)) return 1;
    }
    return 0;
}

/* The term nearest p (*term), its distance and, when q is given, its nearest point (world). */
static double nearest_term(const vp_surface_t *s, const double p[3], double q[3], int *term)
{
    double best = DBL_MAX, bq[3] = { 0, 0, 0 };
    int t, bt = 0;
    for (t = 0; t < s->nterm; t++) {
        const vp_term_t *T = &s->term[t];
        double l[3], lq[3], d;
        if (vp_box_dist(T->lo, T->hi, p) >= best) continue;
        vp_to_local(T, p, l);
        d = vp_term_closest_local(T, l, lq) * T->scale;
        if (d < best) { best = d; bt = t; if (q) vp_to_world(T, lq, bq); }
    }
    if (q) memcpy(q, bq, sizeof bq);
    if (term) *term = bt;
    return best;
}

double vp_surface_closest(const vp_surface_t *s, const double p[3], double q[3])
{
    return nearest_term(s, p, q, NULL);
}

double vp_surface_distance(const vp_surface_t *s, const double p[3]) { return vp_surface_closest(s, p, NULL); }

void vp_surface_normal(const vp_surface_t *s, const double p[3], double n[3])
{
    double nn;
    int k, bt;
    nearest_term(s, p, NULL, &bt);
    {
        const vp_term_t *T = &s->term[bt];
        double l[3];
        vp_to_local(T, p, l);
        if (T->kind == VP_TERM_MESH) {
            size_t f;
            double q[3], u[3], v[3];
            const double *a, *b, *c;
            vp_bvh_closest(T->bvh, l, q, &f);
            a = T->mesh.xyz + 3 * T->mesh.tri[3 * f]; b = T->mesh.xyz + 3 * T->mesh.tri[3 * f + 1]; c = T->mesh.xyz + 3 * T->mesh.tri[3 * f + 2];
            for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = c[k] - a[k]; }
            vp_cross3(n, u, v);
            for (k = 0; k < 3; k++) n[k] *= T->orient;
        } else {
            vp_imp_grad(T->kind, l, n);
        }
    }
    nn = vp_norm3(n);
    if (nn > 0) for (k = 0; k < 3; k++) n[k] /= nn;
}

static void vp_face_normal(const vp_mesh_t *m, size_t f, double n[3])
{
    const double *a = m->xyz + 3 * (size_t)m->tri[3 * f], *b = m->xyz + 3 * (size_t)m->tri[3 * f + 1],
                 *c = m->xyz + 3 * (size_t)m->tri[3 * f + 2];
    double u[3], v[3], l;
    int k;
    for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = c[k] - a[k]; }
    vp_cross3(n, u, v);
    l = vp_norm3(n);
    for (k = 0; k < 3; k++) n[k] = l > 0 ? n[k] / l : 0;
}

#define VP_CREASE_COS 0.93969262078590838   /* cos 20 degrees */

/* the points of the crease between pa and pb: both ends and points at most step apart between */
static long vp_crease_points(const double pa[3], const double pb[3], double step)
{
    double len = 0;
    long np;
    int k;
    for (k = 0; k < 3; k++) len += (pb[k] - pa[k]) * (pb[k] - pa[k]);
    np = (long)ceil(sqrt(len) / step);
    return np < 1 ? 1 : np;
}

int vp_surface_creases(const vp_surface_t *s, double step, double **xyz, size_t *n)
{
    double *out = NULL;
    size_t count = 0;
    int t;
    if (!s || !xyz || !n) return VP_EINVAL;
    *xyz = NULL;
    *n = 0;
    if (!(step > 0)) return VP_EINVAL;
    for (t = 0; t < s->nterm; t++) {
        const vp_term_t *T = &s->term[t];
        const vp_mesh_t *m = &T->mesh;
        vp_edge_rec_t *e;
        size_t f, i, j, ne = 3 * m->nt, more = 0;
        int pass;
        if (T->kind != VP_TERM_MESH || m->nt == 0) continue;
        e = malloc(ne * sizeof *e);
        if (!e) { free(out); return VP_ENOMEM; }
        for (f = 0; f < m->nt; f++)
            for (j = 0; j < 3; j++) {
                uint32_t a = m->tri[3 * f + j], b = m->tri[3 * f + (j + 1) % 3];
                e[3 * f + j].a = a < b ? a : b;
                e[3 * f + j].b = a < b ? b : a;
                e[3 * f + j].f = (uint32_t)f;
            }
        qsort(e, ne, sizeof *e, vp_edge_cmp);
        /* the edges in two faces or more, those two turning by more than 20 degrees: counted,
         * then written */
        for (pass = 0; pass < 2; pass++) {
            size_t at = count;
            if (pass == 1) {
                double *grown = more ? realloc(out, (count + more) * 3 * sizeof *out) : out;
                if (more && !grown) { free(e); free(out); return VP_ENOMEM; }
                out = grown;
            }
            for (i = 0; i + 1 < ne; i = j) {
                double n0[3], n1[3], pa[3], pb[3];
                long np, q;
                int k;
                for (j = i + 1; j < ne && e[j].a == e[i].a && e[j].b == e[i].b; j++) {}
                if (j - i < 2) continue;
                vp_face_normal(m, e[i].f, n0);
                vp_face_normal(m, e[i + 1].f, n1);
                if (vp_dot3(n0, n1) > VP_CREASE_COS) continue;
                vp_to_world(T, m->xyz + 3 * (size_t)e[i].a, pa);
                vp_to_world(T, m->xyz + 3 * (size_t)e[i].b, pb);
                np = vp_crease_points(pa, pb, step);
                if (pass == 0) { more += (size_t)np + 1; continue; }
                for (q = 0; q <= np; q++, at++)
                    for (k = 0; k < 3; k++) out[3 * at + k] = pa[k] + (pb[k] - pa[k]) * (double)q / (double)np;
            }
        }
        count += more;
        free(e);
    }
    *xyz = out;
    *n = count;
    return VP_OK;
}

size_t vp_surface_sample(const vp_surface_t *s, size_t n, uint64_t seed, double *xyz)
{
    size_t *cnt, done = 0, i;
    int t;
    double *frac;
    if (n == 0) return 0;
    cnt = calloc((size_t)s->nterm, sizeof *cnt);
    frac = calloc((size_t)s->nterm, sizeof *frac);
    if (!cnt || !frac) { free(cnt); free(frac); return 0; }
    /* Largest-remainder split of n by area. */
    for (t = 0; t < s->nterm; t++) {
        double want = (double)n * s->term[t].area / s->area;
        cnt[t] = (size_t)floor(want);
        frac[t] = want - floor(want);
        done += cnt[t];
    }
    while (done < n) {
        int bt = 0;
        for (t = 1; t < s->nterm; t++) if (frac[t] > frac[bt]) bt = t;
        cnt[bt]++; frac[bt] = -1; done++;
    }
    done = 0;
    for (t = 0; t < s->nterm; t++) {
        vp_rng_t r;
        vp_rng_seed(&r, seed ^ (0x9e3779b97f4a7c15ULL * (uint64_t)(t + 1)));
        for (i = 0; i < cnt[t] && done < n; i++, done++) {
            double l[3];
            vp_sample_local(&s->term[t], &r, l);
            vp_to_world(&s->term[t], l, xyz + 3 * done);
        }
    }
    free(cnt); free(frac);
    return done;
}
