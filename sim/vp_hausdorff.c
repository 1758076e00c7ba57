/* vp_hausdorff — see vp_hausdorff.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_bvh.h"
#include "vp_hausdorff.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_vec3.h"

static void vp_tri_vec(const vp_mesh_t *m, size_t f, const double **a, const double **b, const double **c)
{
    *a = m->xyz + 3 * (size_t)m->tri[3 * f];
    *b = m->xyz + 3 * (size_t)m->tri[3 * f + 1];
    *c = m->xyz + 3 * (size_t)m->tri[3 * f + 2];
}

#define VP_HD_TOP 24
/* Moves of the local maximisation at one step length before it halves anyway. A step that
 * always gains a little (a ridge of the distance that longer steps overshoot) otherwise crept on
 * for hours: the bear's mesh on the enclosed board, 1e-10 mm a move, 5e-15 mm gained each. */
#define VP_HD_LEVEL_MOVES 1000

/* The pattern searches' step: on while it is above 1e-10 and finite (an infinite area's step
 * never halves); halved after a round that gained nothing, or after VP_HD_LEVEL_MOVES moves at
 * one length. */
static int vp_hd_stepping(double step) { return step > 1e-10 && step < HUGE_VAL; }

static void vp_hd_next_step(double *step, int *moves, int moved)
{
    if (!moved || ++*moves == VP_HD_LEVEL_MOVES) { *step *= 0.5; *moves = 0; }
}

typedef struct vp_hd_cand { double d; double p[3]; size_t face; double u, v; } vp_hd_cand_t;

static void vp_hd_keep(vp_hd_cand_t *top, int *ntop, const vp_hd_cand_t *c)
{
    int i;
    if (*ntop == VP_HD_TOP && c->d <= top[VP_HD_TOP - 1].d) return;
    i = *ntop < VP_HD_TOP ? (*ntop)++ : VP_HD_TOP - 1;
    while (i > 0 && top[i - 1].d < c->d) { top[i] = top[i - 1]; i--; }
    top[i] = *c;
}

static void vp_bary_point(const vp_mesh_t *m, size_t f, double u, double v, double p[3])
{
    const double *a, *b, *c;
    int k;
    vp_tri_vec(m, f, &a, &b, &c);
    for (k = 0; k < 3; k++) p[k] = a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]);
}

static double hd_surface_closest(const void *ctx, const double p[3], double q[3])
{
    return vp_surface_closest(ctx, p, q);
}
static void hd_surface_normal(const void *ctx, const double p[3], double n[3]) { vp_surface_normal(ctx, p, n); }
static size_t hd_surface_sample(const void *ctx, size_t n, uint64_t seed, double *xyz)
{
    return vp_surface_sample(ctx, n, seed, xyz);
}

static int hd_surface_creases(const void *ctx, double step, double **xyz, size_t *n)
{
    return vp_surface_creases(ctx, step, xyz, n);
}

void vp_hausdorff_surface_object(const vp_surface_t *s, vp_hd_object_t *obj)
{
    obj->ctx = s;
    obj->closest = hd_surface_closest;
    obj->normal = hd_surface_normal;
    obj->sample = hd_surface_sample;
    obj->creases = hd_surface_creases;
    obj->area = vp_surface_area(s);
}

int vp_hausdorff(const vp_mesh_t *m, const vp_surface_t *s, size_t n, uint64_t seed, vp_hausdorff_t *out)
{
    vp_hd_object_t obj;
    if (!s) return VP_EINVAL;
    vp_hausdorff_surface_object(s, &obj);
    return vp_hausdorff_object(m, &obj, n, seed, out);
}

int vp_hausdorff_object(const vp_mesh_t *m, const vp_hd_object_t *s, size_t n, uint64_t seed, vp_hausdorff_t *out)
{
    vp_bvh_t *bvh = NULL;
    double *cdf = NULL, *pts = NULL, acc = 0, sum, spacing;
    size_t f, i, *vface = NULL;
    vp_hd_cand_t top[VP_HD_TOP];
    int ntop = 0, st, t;
    vp_rng_t r;
    if (!m || !s || !out || m->nt == 0) return VP_EINVAL;
    memset(out, 0, sizeof *out);
    st = vp_bvh_build(m->xyz, m->nv, m->tri, m->nt, &bvh);
    if (st < 0) return st;
    cdf = malloc(m->nt * sizeof *cdf);
    vface = malloc((m->nv + 1) * sizeof *vface);
    pts = malloc((n + 1) * 3 * sizeof *pts);
    if (!cdf || !vface || !pts) { st = VP_ENOMEM; goto done; }
    for (i = 0; i < m->nv; i++) vface[i] = (size_t)-1;
    for (f = 0; f < m->nt; f++) {
        const double *a, *b, *c;
        double u[3], v[3], nn[3];
        int k;
        vp_tri_vec(m, f, &a, &b, &c);
        for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = c[k] - a[k]; }
        vp_cross3(nn, u, v);
        acc += 0.5 * vp_norm3(nn);
        cdf[f] = acc;
        for (k = 0; k < 3; k++) vface[m->tri[3 * f + k]] = f;
    }

    /* Mesh -> surface: every vertex, then n points uniform by area. */
    vp_rng_seed(&r, seed);
    sum = 0;
    for (i = 0; i < m->nv + n; i++) {
        vp_hd_cand_t c;
        if (i < m->nv) {
            if (vface[i] == (size_t)-1) continue;
            c.face = vface[i];
            c.u = m->tri[3 * c.face + 1] == i ? 1 : 0;
            c.v = m->tri[3 * c.face + 2] == i ? 1 : 0;
        } else {
            double target = vp_rng_uniform(&r) * acc;
            size_t lo = 0, hi = m->nt - 1;
            while (lo < hi) { size_t mid = (lo + hi) / 2; if (cdf[mid] > target) hi = mid; else lo = mid + 1; }
            c.face = lo;
            c.u = vp_rng_uniform(&r); c.v = vp_rng_uniform(&r);
            if (c.u + c.v > 1) { c.u = 1 - c.u; c.v = 1 - c.v; }
        }
        vp_bary_point(m, c.face, c.u, c.v, c.p);
        c.d = s->closest(s->ctx, c.p, NULL);
        if (i >= m->nv) sum += c.d;
        vp_hd_keep(top, &ntop, &c);
    }
    out->mean_mesh_to_surface = n ? sum / (double)n : 0;
    /* Local maximisation inside each candidate's triangle (pattern search on u, v). */
    for (t = 0; t < ntop; t++) {
        vp_hd_cand_t c = top[t];
        double step = 0.25;
        int moves = 0;
        static const double dirs[6][2] = { { 1, 0 }, { -1, 0 }, { 0, 1 }, { 0, -1 }, { 1, -1 }, { -1, 1 } };
        while (vp_hd_stepping(step)) {
            int k, moved = 0;
            for (k = 0; k < 6; k++) {
                vp_hd_cand_t e = c;
                e.u = c.u + step * dirs[k][0];
                e.v = c.v + step * dirs[k][1];
                if (e.u < 0) e.u = 0;
                if (e.v < 0) e.v = 0;
                if (e.u + e.v > 1) { double sc = 1 / (e.u + e.v); e.u *= sc; e.v *= sc; }
                vp_bary_point(m, e.face, e.u, e.v, e.p);
                e.d = s->closest(s->ctx, e.p, NULL);
                if (e.d > c.d) { c = e; moved = 1; }
            }
            vp_hd_next_step(&step, &moves, moved);
        }
        if (c.d > out->mesh_to_surface) out->mesh_to_surface = c.d;
    }

    /* Surface -> mesh. */
    if (s->sample(s->ctx, n, seed ^ 0x5a5a5a5a5a5a5a5aULL, pts) != n) { st = VP_ENOMEM; goto done; }
    ntop = 0;
    sum = 0;
    for (i = 0; i < n; i++) {
        vp_hd_cand_t c;
        memcpy(c.p, pts + 3 * i, sizeof c.p);
        c.d = vp_bvh_closest(bvh, c.p, NULL, NULL);
        c.face = 0; c.u = c.v = 0;
        sum += c.d;
        vp_hd_keep(top, &ntop, &c);
    }
    out->mean_surface_to_mesh = n ? sum / (double)n : 0;
    /* the area samples' spacing: the search's first step, and the creases' */
    spacing = sqrt(s->area / (double)(n + 1));
    if (s->creases && spacing > 0) {
        /* a part's sharp edges, which area samples reach only near: candidates too (not in the
         * mean), as far apart as the area samples */
        double *cp;
        size_t nc;
        if ((st = s->creases(s->ctx, spacing, &cp, &nc)) != VP_OK) goto done;
        for (i = 0; i < nc; i++) {
            vp_hd_cand_t c;
            memcpy(c.p, cp + 3 * i, sizeof c.p);
            c.d = vp_bvh_closest(bvh, c.p, NULL, NULL);
            c.face = 0; c.u = c.v = 0;
            vp_hd_keep(top, &ntop, &c);
        }
        free(cp);
    }
    for (t = 0; t < ntop; t++) {
        vp_hd_cand_t c = top[t];
        double step = spacing;
        int moves = 0;
        while (vp_hd_stepping(step)) {
            double nrm[3], t1[3], t2[3], len;
            int k, moved = 0, j;
            s->normal(s->ctx, c.p, nrm);
            /* tangent basis */
            if (fabs(nrm[0]) < 0.9) { t1[0] = 0; t1[1] = nrm[2]; t1[2] = -nrm[1]; }
            else { t1[0] = -nrm[2]; t1[1] = 0; t1[2] = nrm[0]; }
            len = vp_norm3(t1);
            for (j = 0; j < 3; j++) t1[j] /= len;
            vp_cross3(t2, nrm, t1);
            for (k = 0; k < 4; k++) {
                double y[3], q[3], d;
                double a = (k == 0) - (k == 1), b = (k == 2) - (k == 3);
                for (j = 0; j < 3; j++) y[j] = c.p[j] + step * (a * t1[j] + b * t2[j]);
                s->closest(s->ctx, y, q);
                d = vp_bvh_closest(bvh, q, NULL, NULL);
                if (d > c.d) { c.d = d; memcpy(c.p, q, sizeof q); moved = 1; }
            }
            vp_hd_next_step(&step, &moves, moved);
        }
        if (c.d > out->surface_to_mesh) out->surface_to_mesh = c.d;
    }
    out->hausdorff = out->mesh_to_surface > out->surface_to_mesh ? out->mesh_to_surface : out->surface_to_mesh;
    st = VP_OK;
done:
    vp_bvh_free(bvh);
    free(cdf); free(vface); free(pts);
    return st;
}
