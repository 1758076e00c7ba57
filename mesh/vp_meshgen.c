/* vp_meshgen — see vp_meshgen.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_meshgen.h"
#include "vp_status.h"
#include "vp_vec3.h"

/* Midpoint vertex of edge (a,b), created once: open addressing on the sorted pair. */
typedef struct vp_midmap { uint64_t *key; uint32_t *val; size_t cap; } vp_midmap_t;

static uint32_t vp_midpoint(vp_midmap_t *mm, vp_mesh_t *m, size_t *nv, uint32_t a, uint32_t b)
{
    uint64_t key = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
    size_t h = (size_t)((key * 0x9e3779b97f4a7c15ULL) >> 20) & (mm->cap - 1);
    double p[3], n;
    int k;
    while (mm->key[h] != UINT64_MAX) {
        if (mm->key[h] == key) return mm->val[h];
        h = (h + 1) & (mm->cap - 1);
    }
    for (k = 0; k < 3; k++) p[k] = 0.5 * (m->xyz[3 * a + k] + m->xyz[3 * b + k]);
    n = vp_norm3(p);
    for (k = 0; k < 3; k++) m->xyz[3 * *nv + k] = p[k] / n;
    mm->key[h] = key;
    mm->val[h] = (uint32_t)*nv;
    return (uint32_t)(*nv)++;
}

int vp_meshgen_icosphere(int level, vp_mesh_t *m)
{
    static const int faces[20][3] = {
        { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 }, { 1, 5, 9 }, { 5, 11, 4 },
        { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 },
        { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 }
    };
    const double g = (1 + sqrt(5.0)) / 2;
    const double v0[12][3] = {
        { -1, g, 0 }, { 1, g, 0 }, { -1, -g, 0 }, { 1, -g, 0 }, { 0, -1, g }, { 0, 1, g },
        { 0, -1, -g }, { 0, 1, -g }, { g, 0, -1 }, { g, 0, 1 }, { -g, 0, -1 }, { -g, 0, 1 }
    };
    size_t nt = 20, nvtot = 12, i, f;
    int l, k, st;
    if (level < 0 || level > 8) return VP_EINVAL;
    for (l = 0; l < level; l++) { nvtot += nt * 3 / 2; nt *= 4; }
    if ((st = vp_mesh_alloc(m, nvtot, nt)) < 0) return st;
    for (i = 0; i < 12; i++) {
        double n = sqrt(v0[i][0] * v0[i][0] + v0[i][1] * v0[i][1] + v0[i][2] * v0[i][2]);
        for (k = 0; k < 3; k++) m->xyz[3 * i + k] = v0[i][k] / n;
    }
    for (f = 0; f < 20; f++) for (k = 0; k < 3; k++) m->tri[3 * f + k] = (uint32_t)faces[f][k];
    {
        size_t cur_nt = 20, cur_nv = 12;
        uint32_t *tmp = malloc(nt * 3 * sizeof(uint32_t));
        vp_midmap_t mm;
        mm.cap = 1;
        while (mm.cap < 4 * nvtot) mm.cap *= 2;
        mm.key = malloc(mm.cap * sizeof(uint64_t));
        mm.val = malloc(mm.cap * sizeof(uint32_t));
        if (!tmp || !mm.key || !mm.val) { free(tmp); free(mm.key); free(mm.val); vp_mesh_free(m); return VP_ENOMEM; }
        memset(mm.key, 0xff, mm.cap * sizeof(uint64_t));
        for (l = 0; l < level; l++) {
            for (f = 0; f < cur_nt; f++) {
                uint32_t a = m->tri[3 * f], b = m->tri[3 * f + 1], c = m->tri[3 * f + 2];
                uint32_t ab = vp_midpoint(&mm, m, &cur_nv, a, b), bc = vp_midpoint(&mm, m, &cur_nv, b, c),
                         ca = vp_midpoint(&mm, m, &cur_nv, c, a);
                uint32_t *o = tmp + 12 * f;
                o[0] = a; o[1] = ab; o[2] = ca;
                o[3] = b; o[4] = bc; o[5] = ab;
                o[6] = c; o[7] = ca; o[8] = bc;
                o[9] = ab; o[10] = bc; o[11] = ca;
            }
            cur_nt *= 4;
            memcpy(m->tri, tmp, cur_nt * 3 * sizeof(uint32_t));
        }
        free(tmp); free(mm.key); free(mm.val);
    }
    /* Orient every face outward (vertices are on a sphere about the origin). */
    for (f = 0; f < nt; f++) {
        const double *a = m->xyz + 3 * m->tri[3 * f], *b = m->xyz + 3 * m->tri[3 * f + 1], *c = m->xyz + 3 * m->tri[3 * f + 2];
        double u[3], v[3], n[3];
        for (k = 0; k < 3; k++) { u[k] = b[k] - a[k]; v[k] = c[k] - a[k]; }
        vp_cross3(n, u, v);
        if (n[0] * (a[0] + b[0] + c[0]) + n[1] * (a[1] + b[1] + c[1]) + n[2] * (a[2] + b[2] + c[2]) < 0) {
            uint32_t s = m->tri[3 * f + 1]; m->tri[3 * f + 1] = m->tri[3 * f + 2]; m->tri[3 * f + 2] = s;
        }
    }
    return VP_OK;
}

int vp_meshgen_torus(double R, double r, int nu, int nv, vp_mesh_t *m)
{
    int i, j, st;
    if (nu < 3 || nv < 3 || !(R > r) || !(r > 0)) return VP_EINVAL;
    if ((st = vp_mesh_alloc(m, (size_t)nu * nv, 2 * (size_t)nu * nv)) < 0) return st;
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double th = 2 * 3.141592653589793 * i / nu, ph = 2 * 3.141592653589793 * j / nv;
            double *p = m->xyz + 3 * ((size_t)i * nv + j);
            p[0] = (R + r * cos(ph)) * cos(th);
            p[1] = (R + r * cos(ph)) * sin(th);
            p[2] = r * sin(ph);
        }
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            uint32_t a = (uint32_t)(i * nv + j), b = (uint32_t)(((i + 1) % nu) * nv + j);
            uint32_t c = (uint32_t)(((i + 1) % nu) * nv + (j + 1) % nv), d = (uint32_t)(i * nv + (j + 1) % nv);
            uint32_t *t = m->tri + 6 * ((size_t)i * nv + j);
            t[0] = a; t[1] = b; t[2] = c;
            t[3] = a; t[4] = c; t[5] = d;
        }
    return VP_OK;
}

int vp_meshgen_append(vp_mesh_t *a, const vp_mesh_t *b, const double offset[3])
{
    vp_mesh_t r;
    size_t i;
    int st;
    vp_mesh_init(&r);
    if ((st = vp_mesh_alloc(&r, a->nv + b->nv, a->nt + b->nt)) < 0) return st;
    if (a->nv) memcpy(r.xyz, a->xyz, a->nv * 3 * sizeof(double));
    if (a->nt) memcpy(r.tri, a->tri, a->nt * 3 * sizeof(uint32_t));
    for (i = 0; i < 3 * b->nv; i++) r.xyz[3 * a->nv + i] = b->xyz[i] + (offset ? offset[i % 3] : 0);
    for (i = 0; i < 3 * b->nt; i++) r.tri[3 * a->nt + i] = b->tri[i] + (uint32_t)a->nv;
    vp_mesh_free(a);
    *a = r;
    return VP_OK;
}
