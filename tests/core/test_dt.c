/* The 3D Delaunay triangulation: validity (vp_dt_check, exact) after random, degenerate and
 * adversarial sequences and after every error path; uniqueness under the symbolic
 * perturbation; the planner's queries; arena exhaustion. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_dt.h"
#include "vp_pred.h"
#include "vp_pointgen.h"
#include "vp_rng.h"
#include "vp_test.h"

static void *xmalloc(size_t n)
{
    void *p = malloc(n);
    if (!p) { fprintf(stderr, "out of memory\n"); exit(2); }
    return p;
}

/* A finite tet as its 4 vertex coordinates, sorted, for comparing triangulations whose
 * vertex numbering differs. */
typedef struct { double c[12]; } tetkey_t;

static int cmp_pt(const void *a, const void *b)
{
    return vp_lex_cmp((const double *)a, (const double *)b);
}

static int cmp_key(const void *a, const void *b)
{
    return memcmp(a, b, sizeof(tetkey_t)) < 0 ? -1 : memcmp(a, b, sizeof(tetkey_t)) > 0;
}

/* sorted list of finite tets; returns count */
static size_t tet_keys(const vp_dt_t *dt, tetkey_t **out)
{
    size_t n = 0;
    uint32_t t;
    tetkey_t *k = xmalloc(sizeof *k * (vp_dt_num_finite_tets(dt) + 1));
    for (t = 0; t < dt->ntet_slots; t++) {
        const uint32_t *v;
        int i;
        if (!vp_dt_alive(dt, t) || vp_dt_is_ghost(dt, t)) continue;
        v = vp_dt_tet(dt, t);
        for (i = 0; i < 4; i++) memcpy(k[n].c + 3 * i, vp_dt_point(dt, v[i]), 3 * sizeof(double));
        qsort(k[n].c, 4, 3 * sizeof(double), cmp_pt);
        n++;
    }
    qsort(k, n, sizeof *k, cmp_key);
    *out = k;
    return n;
}

static int same_triangulation(const vp_dt_t *a, const vp_dt_t *b)
{
    tetkey_t *ka, *kb;
    size_t na = tet_keys(a, &ka), nb = tet_keys(b, &kb);
    int same = na == nb && memcmp(ka, kb, na * sizeof *ka) == 0;
    free(ka); free(kb);
    return same;
}

typedef struct {
    vp_dt_t dt;
    void *mem;
    size_t bytes;
} tri_t;

static void tri_open(tri_t *t, size_t bytes, size_t payload)
{
    t->mem = xmalloc(bytes);
    t->bytes = bytes;
    CHECK(vp_dt_init(&t->dt, t->mem, bytes, payload) == VP_OK);
}

static void tri_close(tri_t *t) { free(t->mem); }

/* Snapshot of everything that defines the triangulation, to prove "unchanged". */
typedef struct {
    vp_dt_t dt;
    unsigned char *tets;
    size_t tet_bytes;
    unsigned char *verts;
    size_t vert_bytes;
} snap_t;

static void snap_take(snap_t *s, const vp_dt_t *dt)
{
    s->dt = *dt;
    s->tet_bytes = (size_t)dt->ntet_slots * dt->stride * 4;
    s->tets = xmalloc(s->tet_bytes + 1);
    memcpy(s->tets, dt->tets, s->tet_bytes);
    s->vert_bytes = (size_t)dt->nvert * sizeof(vp_dt_vertex_t);
    s->verts = xmalloc(s->vert_bytes + 1);
    memcpy(s->verts, (const unsigned char *)(dt->vtop + 1) - s->vert_bytes, s->vert_bytes);
}

static int snap_same(const snap_t *s, const vp_dt_t *dt)
{
    int same = s->dt.ntet_slots == dt->ntet_slots && s->dt.nvert == dt->nvert &&
               s->dt.nalive == dt->nalive && s->dt.nghost == dt->nghost &&
               s->dt.nfree == dt->nfree && s->dt.free_head == dt->free_head &&
               s->dt.ninserted == dt->ninserted && s->dt.dim == dt->dim;
    if (same) same = memcmp(s->tets, dt->tets, s->tet_bytes) == 0;
    if (same) same = memcmp(s->verts, (const unsigned char *)(dt->vtop + 1) - s->vert_bytes,
                            s->vert_bytes) == 0;
    return same;
}

static void snap_free(snap_t *s) { free(s->tets); free(s->verts); }

static uint32_t count_finite_brute(const vp_dt_t *dt)
{
    uint32_t t, n = 0;
    for (t = 0; t < dt->ntet_slots; t++) n += vp_dt_alive(dt, t) && !vp_dt_is_ghost(dt, t);
    return n;
}

/* ---- tests ---- */

static void test_random_sequential_vs_batch(void)
{
    size_t n, i;
    double *xyz;
    char err[128];
    tri_t a, b;
    uint32_t *ids;
    vp_pointgen_uniform(3000, 7, &xyz, &n, err, sizeof err);
    tri_open(&a, 4u << 20, 0);
    for (i = 0; i < n; i++) {
        uint32_t v;
        CHECK(vp_dt_insert(&a.dt, xyz + 3 * i, VP_DT_NONE, &v) == VP_OK);
        CHECK(v == i);
        if (i % 500 == 0 || i < 12) CHECKF(vp_dt_check(&a.dt) == VP_OK, "after %zu", i);
    }
    CHECK(vp_dt_check(&a.dt) == VP_OK);
    CHECK(vp_dt_num_finite_tets(&a.dt) == count_finite_brute(&a.dt));
    tri_open(&b, 4u << 20, 0);
    ids = xmalloc(n * sizeof *ids);
    CHECK(vp_dt_insert_batch(&b.dt, xyz, (uint32_t)n, ids) == VP_OK);
    CHECK(vp_dt_check(&b.dt) == VP_OK);
    CHECK(same_triangulation(&a.dt, &b.dt));
    for (i = 0; i < n; i++) CHECK(memcmp(vp_dt_point(&b.dt, ids[i]), xyz + 3 * i, 24) == 0);
    free(ids);
    tri_close(&a); tri_close(&b);
    free(xyz);
}

static void shuffle(double *xyz, size_t n, uint64_t seed)
{
    size_t i, c;
    for (i = n; i > 1; i--) {
        size_t j = (size_t)(vp_splitmix_next(&seed) % i);
        for (c = 0; c < 3; c++) {
            double t = xyz[3 * (i - 1) + c];
            xyz[3 * (i - 1) + c] = xyz[3 * j + c];
            xyz[3 * j + c] = t;
        }
    }
}

/* The integer grid is massively cospherical and coplanar. Under the symbolic perturbation the
 * triangulation is unique: every insertion order must give the very same tets. */
static void test_grid_unique(void)
{
    size_t n, i;
    double *xyz;
    char err[128];
    tri_t ref;
    int order;
    vp_pointgen_grid(7, 3, &xyz, &n, err, sizeof err);
    tri_open(&ref, 4u << 20, 0);
    CHECK(vp_dt_insert_batch(&ref.dt, xyz, (uint32_t)n, NULL) == VP_OK);
    CHECK(vp_dt_check(&ref.dt) == VP_OK);
    /* a grid of k^3 points has 6 (k-1)^3 ... tets only in some cases; the hull volume must
     * match: sum of finite tet volumes = (k-1)^3 */
    {
        double vol = 0.0;
        uint32_t t;
        for (t = 0; t < ref.dt.ntet_slots; t++) {
            const uint32_t *v;
            const double *a, *b, *c, *d;
            if (!vp_dt_alive(&ref.dt, t) || vp_dt_is_ghost(&ref.dt, t)) continue;
            v = vp_dt_tet(&ref.dt, t);
            a = vp_dt_point(&ref.dt, v[0]); b = vp_dt_point(&ref.dt, v[1]);
            c = vp_dt_point(&ref.dt, v[2]); d = vp_dt_point(&ref.dt, v[3]);
            vol += ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1])) * (d[0] - a[0]) +
                   ((b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2])) * (d[1] - a[1]) +
                   ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) * (d[2] - a[2]);
        }
        CHECKF(fabs(vol / 6.0 - 216.0) < 1e-9, "grid hull volume %.12g", vol / 6.0);
    }
    for (order = 0; order < 4; order++) {
        tri_t t;
        shuffle(xyz, n, 100 + (uint64_t)order);
        tri_open(&t, 4u << 20, 0);
        if (order & 1) {
            CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, NULL) == VP_OK);
        } else {
            for (i = 0; i < n; i++) CHECK(vp_dt_insert(&t.dt, xyz + 3 * i, VP_DT_NONE, NULL) == VP_OK);
        }
        CHECK(vp_dt_check(&t.dt) == VP_OK);
        CHECKF(same_triangulation(&ref.dt, &t.dt), "order %d", order);
        tri_close(&t);
    }
    tri_close(&ref);
    free(xyz);
}

/* The same grid scaled by powers of two (exactly) and translated: the filters' exact-box
 * shortcut applies to some of these and not to others; all give the same triangulation. */
static void test_grid_scaled(void)
{
    static const double scales[] = { 1.0, 0x1p-30, 0x1p150, 0x1p600, 0x1p-600 };
    static const double shifts[] = { 0.0, 1e9, -3.5 };
    size_t n, i, m, j;
    double *xyz, *q;
    char err[128];
    uint32_t ref_tets = 0;
    vp_pointgen_grid(6, 5, &xyz, &n, err, sizeof err);
    q = xmalloc(3 * n * sizeof *q);
    for (m = 0; m < sizeof scales / sizeof scales[0]; m++)
        for (j = 0; j < sizeof shifts / sizeof shifts[0]; j++) {
            tri_t t;
            for (i = 0; i < 3 * n; i++) q[i] = xyz[i] * scales[m] + shifts[j] * scales[m];
            tri_open(&t, 4u << 20, 0);
            CHECK(vp_dt_insert_batch(&t.dt, q, (uint32_t)n, NULL) == VP_OK);
            CHECKF(vp_dt_check(&t.dt) == VP_OK, "scale %g shift %g", scales[m], shifts[j]);
            if (!ref_tets) ref_tets = vp_dt_num_finite_tets(&t.dt);
            CHECKF(vp_dt_num_finite_tets(&t.dt) == ref_tets, "scale %g shift %g: %u tets, want %u",
                   scales[m], shifts[j], vp_dt_num_finite_tets(&t.dt), ref_tets);
            tri_close(&t);
        }
    free(q);
    free(xyz);
}

/* All integer points on the sphere of radius 15: exactly cospherical, plus the centre. */
static void test_cospherical(void)
{
    double pts[3 * 4096];
    size_t n = 0;
    int x, y, z, order;
    tri_t ref;
    for (x = -15; x <= 15; x++)
        for (y = -15; y <= 15; y++)
            for (z = -15; z <= 15; z++)
                if (x * x + y * y + z * z == 225) {
                    pts[3 * n] = x; pts[3 * n + 1] = y; pts[3 * n + 2] = z;
                    n++;
                }
    CHECK(n > 100);
    tri_open(&ref, 4u << 20, 0);
    CHECK(vp_dt_insert_batch(&ref.dt, pts, (uint32_t)n, NULL) == VP_OK);
    CHECK(vp_dt_check(&ref.dt) == VP_OK);
    for (order = 0; order < 3; order++) {
        tri_t t;
        size_t i;
        shuffle(pts, n, 7 + (uint64_t)order);
        tri_open(&t, 4u << 20, 0);
        for (i = 0; i < n; i++) CHECK(vp_dt_insert(&t.dt, pts + 3 * i, VP_DT_NONE, NULL) == VP_OK);
        CHECK(vp_dt_check(&t.dt) == VP_OK);
        CHECK(same_triangulation(&ref.dt, &t.dt));
        tri_close(&t);
    }
    {
        double c[3] = { 0, 0, 0 };
        CHECK(vp_dt_insert(&ref.dt, c, VP_DT_NONE, NULL) == VP_OK);
        CHECK(vp_dt_check(&ref.dt) == VP_OK);
    }
    tri_close(&ref);
}

/* Flat starts: coplanar, collinear and repeated points before the first tet exists. */
static void test_flat_start(void)
{
    tri_t t;
    double p[3];
    int i, j;
    uint32_t v;
    tri_open(&t, 1u << 20, 0);
    p[0] = 1; p[1] = 2; p[2] = 3;
    CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &v) == VP_OK && v == 0);
    CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &v) == VP_EDUP && v == 0);
    for (i = 1; i < 20; i++) { /* collinear */
        p[0] = 1 + i; p[1] = 2 + 2 * i; p[2] = 3 + 3 * i;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL) == VP_OK);
    }
    CHECK(t.dt.dim == 1);
    for (i = 0; i < 10; i++) /* coplanar: the plane z = 3 ... through the line? use x+y-z plane */
        for (j = 0; j < 10; j++) {
            int st;
            p[0] = i; p[1] = j; p[2] = i + j;
            st = vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL);
            /* (k, 2k, 3k) for k = 1..4 lies on the line inserted above */
            CHECK(st == ((j == 2 * i && i >= 1 && i <= 4) ? VP_EDUP : VP_OK));
        }
    CHECK(t.dt.dim == 2);
    CHECK(vp_dt_num_finite_tets(&t.dt) == 0);
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    p[0] = 0.5; p[1] = 0.25; p[2] = 7;
    CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL) == VP_OK);
    CHECK(t.dt.dim == 3);
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    CHECK(t.dt.ninserted == t.dt.nvert);
    p[0] = 5; p[1] = 5; p[2] = 10; /* a coplanar point already present */
    CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &v) == VP_EDUP);
    CHECK(memcmp(vp_dt_point(&t.dt, v), p, 24) == 0);
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    tri_close(&t);
}

static void test_bad_input(void)
{
    tri_t t;
    size_t n, i;
    double *xyz, bad[3] = { 0, 0, 0 };
    char err[128];
    snap_t s;
    uint32_t v;
    vp_pointgen_uniform(200, 9, &xyz, &n, err, sizeof err);
    tri_open(&t, 1u << 20, 0);
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, NULL) == VP_OK);
    snap_take(&s, &t.dt);
    bad[1] = NAN;
    CHECK(vp_dt_insert(&t.dt, bad, VP_DT_NONE, NULL) == VP_EINVAL);
    bad[1] = INFINITY;
    CHECK(vp_dt_insert(&t.dt, bad, VP_DT_NONE, NULL) == VP_EINVAL);
    bad[1] = -INFINITY;
    CHECK(vp_dt_insert_in_conflict(&t.dt, bad, 0, NULL) == VP_EINVAL);
    CHECK(vp_dt_insert(&t.dt, NULL, VP_DT_NONE, NULL) == VP_EINVAL);
    xyz[3 * 50 + 2] = NAN;
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, NULL) == VP_EINVAL);
    xyz[3 * 50 + 2] = 0.5;
    CHECK(snap_same(&s, &t.dt));
    /* duplicates: every existing point, through both entry points */
    for (i = 0; i < n; i += 7) {
        double p[3];
        memcpy(p, xyz + 3 * i, sizeof p);
        if (i == 50) continue;
        CHECK(vp_dt_insert(&t.dt, p, (uint32_t)i, &v) == VP_EDUP);
        CHECK(memcmp(vp_dt_point(&t.dt, v), p, 24) == 0);
        {
            uint32_t tets[256];
            int k = vp_dt_incident_tets(&t.dt, v, tets, 256), r;
            CHECK(k > 0);
            r = vp_dt_insert_in_conflict(&t.dt, p, tets[0], &v);
            CHECK(r == VP_EDUP || r == VP_EINVAL);
        }
    }
    CHECK(snap_same(&s, &t.dt));
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    /* a batch with duplicates inside and of existing points */
    {
        double dups[3 * 4];
        uint32_t ids[4];
        memcpy(dups, xyz, 24); memcpy(dups + 3, xyz, 24);
        dups[6] = 2; dups[7] = 2; dups[8] = 2;
        memcpy(dups + 9, dups + 6, 24);
        CHECK(vp_dt_insert_batch(&t.dt, dups, 4, ids) == VP_OK);
        CHECK(ids[0] == ids[1] && ids[2] == ids[3] && ids[0] != ids[2]);
        CHECK(memcmp(vp_dt_point(&t.dt, ids[0]), xyz, 24) == 0);
        CHECK(vp_dt_check(&t.dt) == VP_OK);
    }
    snap_free(&s);
    tri_close(&t);
    free(xyz);
}

/* Arena exhaustion at every size from tiny to enough: the failing call changes nothing. */
static void test_enomem(void)
{
    size_t n, i, bytes;
    double *xyz;
    char err[128];
    int failures_seen = 0;
    vp_pointgen_uniform(400, 11, &xyz, &n, err, sizeof err);
    for (bytes = 1024; bytes < 140000; bytes = bytes * 9 / 8 + 8) {
        tri_t t;
        snap_t s;
        int st = VP_OK;
        tri_open(&t, bytes, 4);
        for (i = 0; i < n; i++) {
            snap_take(&s, &t.dt);
            st = vp_dt_insert(&t.dt, xyz + 3 * i, VP_DT_NONE, NULL);
            if (st != VP_OK) {
                CHECKF(st == VP_ENOMEM, "status %d", st);
                CHECKF(snap_same(&s, &t.dt), "changed by a failed insert, arena %zu", bytes);
                CHECK(vp_dt_check(&t.dt) == VP_OK);
                snap_free(&s);
                failures_seen++;
                break;
            }
            snap_free(&s);
        }
        if (st == VP_OK) CHECK(vp_dt_check(&t.dt) == VP_OK);
        tri_close(&t);
        /* the batch stops cleanly too */
        tri_open(&t, bytes, 0);
        {
            uint32_t *ids = xmalloc(n * sizeof *ids);
            st = vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, ids);
            CHECK(st == VP_OK || st == VP_ENOMEM);
            CHECK(vp_dt_check(&t.dt) == VP_OK);
            if (st == VP_ENOMEM) {
                uint32_t inserted = 0;
                for (i = 0; i < n; i++) inserted += ids[i] != VP_DT_NONE;
                CHECKF(inserted == t.dt.ninserted, "ids %u inserted %u nvert %u dim %d", inserted, t.dt.ninserted, t.dt.nvert, t.dt.dim);
            }
            free(ids);
        }
        tri_close(&t);
    }
    CHECK(failures_seen > 10);
    free(xyz);
}

static double dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The planner's queries: Voronoi vertices and edges, vertex stars, created/killed lists,
 * insertion from a known conflicting tet. */
static void test_queries(void)
{
    size_t n, i;
    double *xyz;
    char err[128];
    tri_t t;
    uint32_t tt, rays = 0, segs = 0;
    vp_pointgen_uniform(500, 13, &xyz, &n, err, sizeof err);
    tri_open(&t, 2u << 20, 8);
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, NULL) == VP_OK);
    for (tt = 0; tt < t.dt.ntet_slots; tt++) {
        const uint32_t *v = vp_dt_tet(&t.dt, tt);
        double c[3];
        int f;
        if (!vp_dt_alive(&t.dt, tt)) continue;
        if (vp_dt_is_ghost(&t.dt, tt)) {
            CHECK(vp_dt_circumcenter(&t.dt, tt, c) == VP_EINVAL);
        } else {
            double r0;
            CHECK(vp_dt_circumcenter(&t.dt, tt, c) == VP_OK);
            r0 = dist(c, vp_dt_point(&t.dt, v[0]));
            for (f = 1; f < 4; f++) CHECK(fabs(dist(c, vp_dt_point(&t.dt, v[f])) - r0) < 1e-9 * (1 + r0));
        }
        for (f = 0; f < 4; f++) {
            vp_dt_vedge_t e;
            uint32_t fv[3];
            int st = vp_dt_voronoi_edge(&t.dt, tt, f, &e);
            vp_dt_facet(&t.dt, tt, f, fv);
            if (fv[0] == VP_DT_GHOST || fv[1] == VP_DT_GHOST || fv[2] == VP_DT_GHOST) {
                CHECK(st == VP_EINVAL);
                continue;
            }
            CHECK(st == VP_OK);
            if (e.is_ray) {
                /* from the Voronoi vertex, away from the hull: the facet's far side */
                const uint32_t *w = vp_dt_tet(&t.dt, tt);
                uint32_t fin = vp_dt_is_ghost(&t.dt, tt) ? w[4 + f] >> 2 : tt, k;
                const uint32_t *fw = vp_dt_tet(&t.dt, fin);
                double far[3], q[3];
                for (k = 0; k < 3; k++) far[k] = e.from[k] + 1e3 * e.dir[k];
                /* far along the ray, the facet's vertices are nearer than any other vertex of
                 * the finite tet */
                for (k = 0; k < 4; k++) {
                    if (fw[k] == fv[0] || fw[k] == fv[1] || fw[k] == fv[2]) continue;
                    memcpy(q, vp_dt_point(&t.dt, fw[k]), sizeof q);
                    CHECK(dist(far, q) > dist(far, vp_dt_point(&t.dt, fv[0])));
                }
                rays++;
            } else {
                double d0 = dist(e.from, vp_dt_point(&t.dt, fv[0])), d1 = dist(e.to, vp_dt_point(&t.dt, fv[0]));
                CHECK(fabs(dist(e.from, vp_dt_point(&t.dt, fv[1])) - d0) < 1e-9 * (1 + d0));
                CHECK(fabs(dist(e.to, vp_dt_point(&t.dt, fv[2])) - d1) < 1e-9 * (1 + d1));
                segs++;
            }
        }
    }
    CHECK(rays > 0 && segs > 0);
    /* vertex stars against a brute-force scan */
    for (i = 0; i < n; i += 13) {
        uint32_t star[512], brute = 0;
        int k = vp_dt_incident_tets(&t.dt, (uint32_t)i, star, 512), j;
        CHECK(k > 0);
        for (tt = 0; tt < t.dt.ntet_slots; tt++) {
            const uint32_t *v = vp_dt_tet(&t.dt, tt);
            if (vp_dt_alive(&t.dt, tt) &&
                (v[0] == i || v[1] == i || v[2] == i || v[3] == i)) brute++;
        }
        CHECK((uint32_t)k == brute);
        for (j = 0; j < k; j++) {
            const uint32_t *v = vp_dt_tet(&t.dt, star[j]);
            CHECK(v[0] == i || v[1] == i || v[2] == i || v[3] == i);
        }
        CHECK(vp_dt_incident_tets(&t.dt, (uint32_t)i, star, 2) == VP_ENOMEM);
    }
    /* insertion from a conflicting tet; killed = exactly the tets in conflict before */
    {
        uint64_t s = 99;
        int round;
        for (round = 0; round < 200; round++) {
            double p[3];
            uint32_t conflicting[512], nconf = 0, start = VP_DT_NONE, nk, nc, k, v;
            const uint32_t *killed, *created;
            p[0] = 1.4 * vp_splitmix_uniform(&s) - 0.2;
            p[1] = 1.4 * vp_splitmix_uniform(&s) - 0.2;
            p[2] = 1.4 * vp_splitmix_uniform(&s) - 0.2;
            for (tt = 0; tt < t.dt.ntet_slots; tt++)
                if (vp_dt_alive(&t.dt, tt) && vp_dt_in_conflict(&t.dt, tt, p)) {
                    if (nconf < 512) conflicting[nconf++] = tt;
                } else if (vp_dt_alive(&t.dt, tt) && start == VP_DT_NONE && round % 10 == 0) {
                    snap_t sn;
                    snap_take(&sn, &t.dt);
                    CHECK(vp_dt_insert_in_conflict(&t.dt, p, tt, NULL) == VP_EINVAL);
                    CHECK(snap_same(&sn, &t.dt));
                    snap_free(&sn);
                    start = 0;
                }
            CHECK(nconf > 0);
            start = conflicting[(uint32_t)round % nconf];
            /* payloads of the killed tets survive for the caller to read */
            for (k = 0; k < nconf; k++) {
                uint32_t *pl = vp_dt_payload(&t.dt, conflicting[k]);
                pl[0] = 0xC0DE0000u + conflicting[k];
            }
            CHECK(vp_dt_insert_in_conflict(&t.dt, p, start, &v) == VP_OK);
            killed = vp_dt_last_killed(&t.dt, &nk);
            created = vp_dt_last_created(&t.dt, &nc);
            CHECK(nk == nconf);
            for (k = 0; k < nk; k++) {
                uint32_t j, found = 0;
                for (j = 0; j < nconf; j++) found += conflicting[j] == killed[k];
                CHECK(found == 1);
                CHECK(((uint32_t *)vp_dt_payload(&t.dt, killed[k]))[0] == 0xC0DE0000u + killed[k]);
            }
            for (k = 0; k < nc; k++) {
                const uint32_t *w = vp_dt_tet(&t.dt, created[k]);
                CHECK(vp_dt_alive(&t.dt, created[k]));
                CHECK(w[0] == v || w[1] == v || w[2] == v || w[3] == v);
            }
            if (round % 40 == 0) CHECK(vp_dt_check(&t.dt) == VP_OK);
        }
        CHECK(vp_dt_check(&t.dt) == VP_OK);
    }
    tri_close(&t);
    free(xyz);
}

/* Adversarial sets: the moment curve and two skew lines (quadratic size), nearly coplanar
 * layers, points far from the origin with tiny separations. */
static void test_adversarial(void)
{
    tri_t t;
    int i, j;
    double p[3];
    tri_open(&t, 8u << 20, 0);
    for (i = 0; i < 150; i++) {
        double s = i / 150.0;
        p[0] = s; p[1] = s * s; p[2] = s * s * s;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL) == VP_OK);
    }
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    tri_close(&t);
    tri_open(&t, 16u << 20, 0);
    for (i = 0; i < 120; i++) {
        p[0] = i; p[1] = 0; p[2] = 0;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL) == VP_OK);
        p[0] = 0; p[1] = i; p[2] = 1;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL) == VP_OK);
    }
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    CHECK(vp_dt_num_finite_tets(&t.dt) > 119 * 119 / 2);
    tri_close(&t);
    /* nearly coplanar layers: z = one ulp apart around 1 */
    tri_open(&t, 8u << 20, 0);
    for (i = 0; i < 20; i++)
        for (j = 0; j < 20; j++) {
            p[0] = i * 0.1; p[1] = j * 0.1;
            p[2] = ((i * 7 + j * 3) % 3 == 0) ? nextafter(1.0, 2.0) : 1.0;
            CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL) == VP_OK);
        }
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    tri_close(&t);
    /* far from the origin, separated by a few ulps */
    tri_open(&t, 8u << 20, 0);
    {
        uint64_t s = 5;
        for (i = 0; i < 300; i++) {
            int k;
            for (k = 0; k < 3; k++) {
                double base = 1e9;
                int steps = (int)(vp_splitmix_next(&s) % 64);
                p[k] = base;
                while (steps--) p[k] = nextafter(p[k], 2e9);
            }
            {
                int st = vp_dt_insert(&t.dt, p, VP_DT_NONE, NULL);
                CHECK(st == VP_OK || st == VP_EDUP);
            }
        }
        CHECK(vp_dt_check(&t.dt) == VP_OK);
    }
    tri_close(&t);
}

/* The inline filters the insertion uses (two-lane on x86-64 and aarch64) against the exact
 * stages, on random, nearly cospherical and grid inputs: runs on every target, including
 * under qemu where the GMP reference is not built. */
static void test_filters(void)
{
    uint64_t s = 4242;
    int n, bad = 0, decided = 0;
    for (n = 0; n < 300000; n++) {
        double P[5][3], lo[3], hi[3], sb;
        int i, k, f, want, mode = n % 3;
        for (i = 0; i < 5; i++) {
            double v[3], r = 0.0;
            for (k = 0; k < 3; k++) {
                v[k] = 2.0 * vp_splitmix_uniform(&s) - 1.0;
                r += v[k] * v[k];
            }
            r = sqrt(r);
            for (k = 0; k < 3; k++) {
                if (mode == 0) P[i][k] = v[k] * 1e3 + 7.0;
                else if (mode == 1) P[i][k] = v[k] / r + 0.25; /* nearly cospherical */
                else P[i][k] = floor(v[k] * 3.0);            /* small grid */
            }
        }
        for (k = 0; k < 3; k++) {
            lo[k] = hi[k] = P[0][k];
            for (i = 1; i < 5; i++) {
                if (P[i][k] < lo[k]) lo[k] = P[i][k];
                if (P[i][k] > hi[k]) hi[k] = P[i][k];
            }
        }
        want = vp_insphere_tail(P[0], P[1], P[2], P[3], P[4]);
        sb = vp_insphere_static_bound(lo, hi);
        f = vp_insphere_filter_b(P[0], P[1], P[2], P[3], P[4], sb);
        if (f != VP_PRED_UNSURE) {
            decided++;
            bad += f != want;
        }
        f = vp_insphere_filter_b(P[0], P[1], P[2], P[3], P[4], HUGE_VAL);
        bad += f != VP_PRED_UNSURE && f != want;
        want = vp_orient3d_tail(P[4], P[1], P[0], P[3]);
        f = vp_orient3d_filter_b(P[4], P[1], P[0], P[3], vp_orient3d_static_bound(lo, hi));
        bad += f != VP_PRED_UNSURE && f != want;
    }
    CHECKF(bad == 0, "%d filter answers differ from the exact ones", bad);
    CHECKF(decided > 150000, "the static filter decided only %d of 300000", decided);
}


/* ---- vertex removal ---- */

/* Every tet, ghost tets included, as its 4 vertices' coordinates sorted (the ghost as
 * (+inf, +inf, +inf), last): the triangulation as a set, whatever the vertex and tet numbers. */
static size_t all_keys(const vp_dt_t *dt, tetkey_t **out)
{
    size_t n = 0;
    uint32_t t;
    tetkey_t *k = xmalloc(sizeof *k * (dt->nalive + 1));
    for (t = 0; t < dt->ntet_slots; t++) {
        const uint32_t *v;
        int i;
        if (!vp_dt_alive(dt, t)) continue;
        v = vp_dt_tet(dt, t);
        for (i = 0; i < 4; i++) {
            if (v[i] == VP_DT_GHOST) {
                k[n].c[3 * i] = k[n].c[3 * i + 1] = k[n].c[3 * i + 2] = INFINITY;
            } else {
                memcpy(k[n].c + 3 * i, vp_dt_point(dt, v[i]), 3 * sizeof(double));
            }
        }
        qsort(k[n].c, 4, 3 * sizeof(double), cmp_pt);
        n++;
    }
    qsort(k, n, sizeof *k, cmp_key);
    *out = k;
    return n;
}

/* a vertex record that is part of the set: in a tet, or pending while the set is flat */
static int present(const vp_dt_t *dt, uint32_t v)
{
    uint32_t t = vp_dt_vertex(dt, v)->tet;
    return t == VP_DT_PENDING || t < dt->ntet_slots;
}

/* The triangulation equals the one built from scratch from the points still present (in a
 * shuffled order, one by one or as a batch): the same tets, ghost tets included, tet for tet,
 * or for a flat set the same dimension and pending points. */
static int equals_scratch(const vp_dt_t *dt, uint64_t seed)
{
    size_t n = 0, i;
    uint32_t v, npend = 0;
    double *pts = xmalloc(3 * sizeof(double) * (dt->nvert + 1));
    tri_t t;
    int ok;
    for (v = 0; v < dt->nvert; v++)
        if (present(dt, v)) memcpy(pts + 3 * n++, vp_dt_point(dt, v), 3 * sizeof(double));
    shuffle(pts, n, seed);
    tri_open(&t, (1u << 16) + n * 600, 0);
    if (seed & 1) {
        CHECK(vp_dt_insert_batch(&t.dt, pts, (uint32_t)n, NULL) == VP_OK);
    } else {
        for (i = 0; i < n; i++) CHECK(vp_dt_insert(&t.dt, pts + 3 * i, VP_DT_NONE, NULL) == VP_OK);
    }
    ok = t.dt.dim == dt->dim && t.dt.ninserted == dt->ninserted &&
         t.dt.nalive == dt->nalive && t.dt.nghost == dt->nghost;
    if (ok && dt->dim == 3) {
        tetkey_t *ka, *kb;
        size_t na = all_keys(dt, &ka), nb = all_keys(&t.dt, &kb);
        ok = na == nb && memcmp(ka, kb, na * sizeof *ka) == 0;
        free(ka); free(kb);
    } else if (ok) {
        for (v = 0; v < dt->nvert; v++) npend += vp_dt_vertex(dt, v)->tet == VP_DT_PENDING;
        ok = npend == n;
    }
    tri_close(&t);
    free(pts);
    return ok;
}

static int tet_holds(const uint32_t *w, uint32_t x)
{
    return w[0] == x || w[1] == x || w[2] == x || w[3] == x;
}

typedef struct {
    long removals, with_ghosts, grew, shrank, drops;
} rmstats_t;

/* Removes v (a vertex in a 3D triangulation with >= 4 payload bytes) and checks what a
 * removal promises besides validity: killed = exactly the tets that held v, as they were;
 * created = live tets without v; every other tet keeps its slot, vertices and payload (its
 * neighbours change only towards the cavity); the slots: star first, then the free list,
 * then new ones; each created tet's created_from names a killed tet's facet opposite v that
 * the created tet holds. */
static void remove_checked(tri_t *tr, uint32_t v, rmstats_t *rs)
{
    vp_dt_t *dt = &tr->dt;
    uint32_t T = dt->ntet_slots, t, k, nk, nc, star = 0, nfree0 = dt->nfree, nalive0 = dt->nalive;
    uint32_t stride = dt->stride, ghosts = 0, dim0 = (uint32_t)dt->dim;
    uint32_t *before, *mark;
    const uint32_t *killed, *created, *kverts, *cfrom;
    int st;
    for (t = 0; t < T; t++)
        if (vp_dt_alive(dt, t)) *(uint32_t *)vp_dt_payload(dt, t) = 0xA0000000u ^ t;
    before = xmalloc((size_t)T * stride * 4 + 4);
    memcpy(before, dt->tets, (size_t)T * stride * 4);
    for (t = 0; t < T; t++)
        if (vp_dt_alive(dt, t) && tet_holds(before + (size_t)t * stride, v)) {
            star++;
            ghosts += vp_dt_is_ghost(dt, t);
        }
    st = vp_dt_remove(dt, v);
    CHECKF(st == VP_OK, "remove %u: status %d", v, st);
    mark = calloc((size_t)(T > dt->ntet_slots ? T : dt->ntet_slots) + 8, sizeof *mark);
    if (!mark) exit(2);
    rs->removals++;
    rs->with_ghosts += ghosts > 0;
    CHECK(vp_dt_vertex(dt, v)->tet == VP_DT_NONE);
    if (st != VP_OK || dt->dim < 3) {
        rs->drops += dt->dim < 3 && dim0 == 3;
        free(before); free(mark);
        return;
    }
    killed = vp_dt_last_killed(dt, &nk);
    created = vp_dt_last_created(dt, &nc);
    kverts = vp_dt_last_killed_vertices(dt);
    cfrom = vp_dt_last_created_from(dt);
    CHECKF(nk == star, "killed %u, star %u", nk, star);
    {
        long bad_killed = 0, bad_created = 0, bad_from = 0, bad_other = 0, with_from = 0;
        for (k = 0; k < nk; k++) {
            const uint32_t *b = before + (size_t)killed[k] * stride;
            bad_killed += !(killed[k] < T && tet_holds(b, v) && mark[killed[k]] == 0) ||
                          memcmp(kverts + 4 * k, b, 16) != 0;
            mark[killed[k]] = 1;
        }
        for (k = 0; k < nc; k++) {
            bad_created += !(created[k] < dt->ntet_slots && vp_dt_alive(dt, created[k])) ||
                           tet_holds(vp_dt_tet(dt, created[k]), v) || (mark[created[k]] & 2);
            mark[created[k]] |= 2;
            if (cfrom[k] != VP_DT_NONE) {
                uint32_t kt = cfrom[k] >> 2, i = cfrom[k] & 3u, j, found = 0, m;
                with_from++;
                for (j = 0; j < nk && killed[j] != kt; j++) {}
                for (m = 0; j < nk && m < 4; m++)
                    if (m != i) found += tet_holds(vp_dt_tet(dt, created[k]), kverts[4 * j + m]);
                bad_from += !(j < nk && kverts[4 * j + i] == v && found == 3);
            }
        }
        for (t = 0; t < dt->ntet_slots; t++) {
            const uint32_t *w;
            if (!vp_dt_alive(dt, t)) continue;
            w = vp_dt_tet(dt, t);
            if (tet_holds(w, v)) { bad_other++; continue; }
            if (mark[t] & 2) continue; /* created */
            if (t >= T || (mark[t] & 1)) { bad_other++; continue; } /* neither created nor kept */
            bad_other += memcmp(w, before + (size_t)t * stride, 16) != 0 ||
                         *(const uint32_t *)vp_dt_payload(dt, t) != (0xA0000000u ^ t);
            for (k = 0; k < 4; k++) {
                uint32_t was = before[(size_t)t * stride + 4 + k];
                if (!(mark[was >> 2] & 1)) bad_other += w[4 + k] != was;
            }
        }
        CHECKF(bad_killed == 0, "remove %u: %ld killed tets wrong", v, bad_killed);
        CHECKF(bad_created == 0, "remove %u: %ld created tets wrong", v, bad_created);
        CHECKF(bad_from == 0 && with_from > 0, "remove %u: %ld created_from wrong", v, bad_from);
        CHECKF(bad_other == 0, "remove %u: %ld other tets changed", v, bad_other);
    }
    /* the star's slots first, then the free list, then new slots */
    {
        uint32_t more = nc > nk ? nc - nk : 0, from_free = more < nfree0 ? more : nfree0;
        CHECK(dt->ntet_slots == T + (more - from_free));
        CHECK(dt->nfree == nfree0 - from_free + (nk > nc ? nk - nc : 0));
        CHECK(dt->nalive == nalive0 - nk + nc);
        for (k = 0; k < nc && k < nk && mark[created[k]] == 3; k++) {} /* star slots first */
        CHECK(k == (nc < nk ? nc : nk));
        rs->grew += dt->ntet_slots > T;
        rs->shrank += nc < nk;
    }
    free(before);
    free(mark);
}

/* Random points: random subsets removed one at a time down to 3 points (the pending mode);
 * every list and slot promise and vp_dt_check after each removal, from-scratch equality at
 * checkpoints; then a larger set at checkpoints only. */
static void test_remove_random(void)
{
    size_t n, i;
    double *xyz;
    char err[128];
    tri_t t;
    uint32_t *ids, *order;
    rmstats_t rs = { 0, 0, 0, 0, 0 };
    vp_pointgen_uniform(400, 31, &xyz, &n, err, sizeof err);
    tri_open(&t, 4u << 20, 4);
    ids = xmalloc(n * sizeof *ids);
    order = xmalloc(n * sizeof *order);
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, ids) == VP_OK);
    for (i = 0; i < n; i++) order[i] = ids[i];
    {
        uint64_t s = 77;
        for (i = n; i > 1; i--) {
            size_t j = (size_t)(vp_splitmix_next(&s) % i);
            uint32_t x = order[i - 1]; order[i - 1] = order[j]; order[j] = x;
        }
    }
    for (i = 0; i + 3 < n; i++) {
        remove_checked(&t, order[i], &rs);
        CHECKF(vp_dt_check(&t.dt) == VP_OK, "after removing %zu", i + 1);
        CHECK(t.dt.ninserted == (t.dt.dim == 3 ? n - i - 1 : 0));
        if (i % 25 == 0 || i + 40 > n) CHECKF(equals_scratch(&t.dt, i), "after removing %zu", i + 1);
    }
    CHECK(t.dt.dim == 2 && t.dt.ntet_slots == 0 && rs.drops == 1);
    printf("random: removals %ld with ghosts %ld grew %ld shrank %ld drops %ld\n", rs.removals, rs.with_ghosts, rs.grew, rs.shrank, rs.drops);
    CHECK(rs.with_ghosts > 20 && rs.shrank > 300);
    free(ids); free(order);
    tri_close(&t);
    free(xyz);

    /* 20000 points, 90% removed: checkpoints */
    vp_pointgen_uniform(20000, 32, &xyz, &n, err, sizeof err);
    tri_open(&t, 16u << 20, 0);
    ids = xmalloc(n * sizeof *ids);
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, ids) == VP_OK);
    {
        uint64_t s = 78;
        size_t removed = 0;
        for (i = n; i > 1; i--) {
            size_t j = (size_t)(vp_splitmix_next(&s) % i);
            uint32_t x = ids[i - 1]; ids[i - 1] = ids[j]; ids[j] = x;
        }
        for (i = 0; i < n * 9 / 10; i++) {
            CHECK(vp_dt_remove(&t.dt, ids[i]) == VP_OK);
            removed++;
            if (removed % 6000 == 0 || removed == n * 9 / 10) {
                CHECK(vp_dt_check(&t.dt) == VP_OK);
                CHECKF(equals_scratch(&t.dt, removed), "after %zu removals", removed);
            }
        }
        /* the freed slots hold the next insertions: no new slot until the free list is used */
        {
            uint32_t slots = t.dt.ntet_slots, nfree = t.dt.nfree;
            CHECK(nfree > 50000);
            for (i = 0; i < 1000; i++) { /* removed points again: new records */
                double p[3];
                uint32_t v;
                memcpy(p, vp_dt_point(&t.dt, ids[i]), sizeof p);
                CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &v) == VP_OK && v >= n);
            }
            CHECK(t.dt.ntet_slots == slots && t.dt.nfree < nfree);
            CHECK(vp_dt_check(&t.dt) == VP_OK);
        }
    }
    free(ids);
    tri_close(&t);
    free(xyz);
}

/* vertices of ghost tets (on the hull), smallest index first */
static uint32_t hull_vertex(const vp_dt_t *dt)
{
    uint32_t t, best = VP_DT_NONE;
    for (t = 0; t < dt->ntet_slots; t++) {
        const uint32_t *w = vp_dt_tet(dt, t);
        int i;
        if (!vp_dt_alive(dt, t) || w[3] != VP_DT_GHOST) continue;
        for (i = 0; i < 3; i++) if (w[i] < best) best = w[i];
    }
    return best;
}

/* Adversarial orders on one set: insertion order, reverse, hull vertices first; each all the
 * way down to the empty set (through the pending mode), then everything inserted again. */
static void test_remove_orders(void)
{
    size_t n, i;
    double *xyz;
    char err[128];
    int mode;
    vp_pointgen_uniform(300, 41, &xyz, &n, err, sizeof err);
    for (mode = 0; mode < 3; mode++) {
        tri_t t;
        rmstats_t rs = { 0, 0, 0, 0, 0 };
        uint32_t v;
        tri_open(&t, 4u << 20, 4);
        for (i = 0; i < n; i++) {
            CHECK(vp_dt_insert(&t.dt, xyz + 3 * i, VP_DT_NONE, &v) == VP_OK);
            CHECK(v == i);
        }
        for (i = 0; i < n; i++) {
            if (mode == 0) v = (uint32_t)i;
            else if (mode == 1) v = (uint32_t)(n - 1 - i);
            else {
                v = t.dt.dim == 3 ? hull_vertex(&t.dt) : VP_DT_NONE;
                if (v == VP_DT_NONE) /* flat: the first pending one */
                    for (v = 0; v < t.dt.nvert && vp_dt_vertex(&t.dt, v)->tet != VP_DT_PENDING; v++) {}
            }
            if (t.dt.dim == 3) {
                remove_checked(&t, v, &rs);
            } else {
                CHECK(vp_dt_vertex(&t.dt, v)->tet == VP_DT_PENDING);
                CHECK(vp_dt_remove(&t.dt, v) == VP_OK);
            }
            CHECKF(vp_dt_check(&t.dt) == VP_OK, "mode %d step %zu", mode, i);
            if (i % 20 == 0 || i + 10 > n) CHECKF(equals_scratch(&t.dt, 3 * i + (uint64_t)mode), "mode %d step %zu", mode, i);
        }
        CHECK(t.dt.dim == -1 && t.dt.ninserted == 0 && t.dt.ntet_slots == 0);
        if (mode == 2) CHECK(rs.with_ghosts == rs.removals);
        /* everything again: new records, the same triangulation as at the start */
        for (i = 0; i < n; i++) {
            CHECK(vp_dt_insert(&t.dt, xyz + 3 * i, VP_DT_NONE, &v) == VP_OK);
            CHECK(v == n + i);
        }
        CHECK(vp_dt_check(&t.dt) == VP_OK);
        CHECK(equals_scratch(&t.dt, 5));
        tri_close(&t);
    }
    free(xyz);
}

/* Removes every vertex of pts[0..n) but `keep`, in a shuffled order, with the full checks and
 * from-scratch equality after every `every` removals. */
static void remove_all_but(const double *pts, size_t n, size_t keep, uint64_t seed, int every,
                           const char *what)
{
    tri_t t;
    uint32_t *ids = xmalloc(n * sizeof *ids);
    rmstats_t rs = { 0, 0, 0, 0, 0 };
    size_t i;
    tri_open(&t, 8u << 20, 4);
    CHECK(vp_dt_insert_batch(&t.dt, pts, (uint32_t)n, ids) == VP_OK);
    for (i = n; i > 1; i--) {
        size_t j = (size_t)(vp_splitmix_next(&seed) % i);
        uint32_t x = ids[i - 1]; ids[i - 1] = ids[j]; ids[j] = x;
    }
    for (i = 0; i + keep < n; i++) {
        if (t.dt.dim == 3) remove_checked(&t, ids[i], &rs);
        else CHECK(vp_dt_remove(&t.dt, ids[i]) == VP_OK);
        CHECKF(vp_dt_check(&t.dt) == VP_OK, "%s: step %zu", what, i);
        if ((int)(i % (size_t)every) == 0 || i + keep + 8 > n)
            CHECKF(equals_scratch(&t.dt, seed + i), "%s: step %zu", what, i);
    }
    printf("%s: removals %ld with ghosts %ld grew %ld shrank %ld drops %ld\n", what, rs.removals, rs.with_ghosts, rs.grew, rs.shrank, rs.drops);
    free(ids);
    tri_close(&t);
}


/* Two skew lines of 40 points and one point between them, as one batch: removing that point
 * brings back the quadratic triangulation (8 times the tets of its star: new slots beyond the
 * free list). */
static void skew_with_centre(double *p)
{
    int i;
    p[0] = 20.25; p[1] = 20.1; p[2] = 0.5;
    for (i = 0; i < 40; i++) {
        double *q = p + 3 + 6 * i;
        q[0] = i; q[1] = 0; q[2] = 0;
        q[3] = 0; q[4] = i + 0.5; q[5] = 1;
    }
}

/* Degenerate sets: the integer grid (cospherical and coplanar everywhere), the integer points
 * of a sphere and its centre (the centre's link is the whole sphere), the surface of a cube
 * grid (coplanar hull faces, every vertex on the hull), two skew lines (quadratic size, stars
 * of linear size), nearly coplanar layers; and flat links (a pyramid's apex). */
static void test_remove_degenerate(void)
{
    size_t n, i;
    double *xyz, pts[3 * 4096];
    char err[128];
    int x, y, z;
    vp_pointgen_grid(6, 51, &xyz, &n, err, sizeof err);
    remove_all_but(xyz, n, 2, 1, 1, "grid 6");
    free(xyz);
    /* sphere of radius 15: the centre first, then the rest */
    n = 0;
    pts[0] = pts[1] = pts[2] = 0.0;
    n = 1;
    for (x = -15; x <= 15; x++)
        for (y = -15; y <= 15; y++)
            for (z = -15; z <= 15; z++)
                if (x * x + y * y + z * z == 225) {
                    pts[3 * n] = x; pts[3 * n + 1] = y; pts[3 * n + 2] = z;
                    n++;
                }
    {
        tri_t t;
        rmstats_t rs = { 0, 0, 0, 0, 0 };
        uint32_t v0;
        tri_open(&t, 8u << 20, 4);
        CHECK(vp_dt_insert(&t.dt, pts, VP_DT_NONE, &v0) == VP_OK);
        CHECK(vp_dt_insert_batch(&t.dt, pts + 3, (uint32_t)(n - 1), NULL) == VP_OK);
        CHECK(vp_dt_check(&t.dt) == VP_OK);
        remove_checked(&t, v0, &rs);
        CHECK(vp_dt_check(&t.dt) == VP_OK);
        CHECK(equals_scratch(&t.dt, 2));
        CHECK(equals_scratch(&t.dt, 3));
        tri_close(&t);
    }
    remove_all_but(pts, n, 0, 2, 5, "sphere 15");
    /* the surface of the 7^3 grid */
    n = 0;
    for (x = 0; x < 7; x++)
        for (y = 0; y < 7; y++)
            for (z = 0; z < 7; z++)
                if (x == 0 || x == 6 || y == 0 || y == 6 || z == 0 || z == 6) {
                    pts[3 * n] = x; pts[3 * n + 1] = y; pts[3 * n + 2] = z;
                    n++;
                }
    remove_all_but(pts, n, 0, 3, 3, "cube surface");
    /* two skew lines */
    n = 0;
    for (i = 0; i < 40; i++) {
        pts[3 * n] = (double)i; pts[3 * n + 1] = 0; pts[3 * n + 2] = 0; n++;
        pts[3 * n] = 0; pts[3 * n + 1] = (double)i + 0.5; pts[3 * n + 2] = 1; n++;
    }
    remove_all_but(pts, n, 0, 4, 2, "skew lines");
    {
        tri_t t;
        rmstats_t rs = { 0, 0, 0, 0, 0 };
        uint32_t ids[81], nk, nc;
        skew_with_centre(pts);
        tri_open(&t, 4u << 20, 4);
        CHECK(vp_dt_insert_batch(&t.dt, pts, 81, ids) == VP_OK);
        remove_checked(&t, ids[0], &rs);
        vp_dt_last_killed(&t.dt, &nk);
        vp_dt_last_created(&t.dt, &nc);
        CHECKF(rs.grew == 1 && nc > 4 * nk, "killed %u created %u", nk, nc);
        CHECK(vp_dt_check(&t.dt) == VP_OK && equals_scratch(&t.dt, 9));
        tri_close(&t);
    }
    /* nearly coplanar layers, one ulp apart */
    n = 0;
    for (x = 0; x < 12; x++)
        for (y = 0; y < 12; y++) {
            pts[3 * n] = x * 0.1; pts[3 * n + 1] = y * 0.1;
            pts[3 * n + 2] = ((x * 7 + y * 3) % 3 == 0) ? nextafter(1.0, 2.0) : 1.0;
            n++;
        }
    remove_all_but(pts, n, 0, 5, 4, "layers");
    /* a pyramid: a 5 x 5 planar grid, an apex above it and one point below */
    {
        tri_t t;
        rmstats_t rs = { 0, 0, 0, 0, 0 };
        uint32_t apex, below, v, base0;
        double p[3];
        tri_open(&t, 4u << 20, 4);
        for (x = 0; x < 5; x++)
            for (y = 0; y < 5; y++) {
                p[0] = x; p[1] = y; p[2] = 0;
                CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &v) == VP_OK);
            }
        base0 = 0;
        CHECK(t.dt.dim == 2);
        p[0] = 2; p[1] = 2; p[2] = 3;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &apex) == VP_OK);
        p[0] = 1; p[1] = 3; p[2] = -1;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &below) == VP_OK);
        CHECK(t.dt.dim == 3 && vp_dt_check(&t.dt) == VP_OK);
        remove_checked(&t, apex, &rs); /* its link is the flat base: ghost tets fill the cavity */
        CHECK(t.dt.dim == 3 && vp_dt_check(&t.dt) == VP_OK && equals_scratch(&t.dt, 1));
        remove_checked(&t, below, &rs); /* the rest is flat: the pending mode */
        CHECK(t.dt.dim == 2 && t.dt.ntet_slots == 0 && t.dt.ninserted == 0);
        CHECK(vp_dt_check(&t.dt) == VP_OK && equals_scratch(&t.dt, 2));
        CHECK(vp_dt_vertex(&t.dt, base0)->tet == VP_DT_PENDING);
        CHECK(vp_dt_remove(&t.dt, apex) == VP_EINVAL); /* already removed */
        /* the apex again: a new record, 3D again, as from scratch */
        p[0] = 2; p[1] = 2; p[2] = 3;
        CHECK(vp_dt_insert(&t.dt, p, VP_DT_NONE, &v) == VP_OK);
        CHECK(v == t.dt.nvert - 1 && v != apex);
        CHECK(t.dt.dim == 3 && vp_dt_check(&t.dt) == VP_OK && equals_scratch(&t.dt, 3));
        /* base points go until the rest is flat (the apex over collinear points, or 3 points) */
        for (v = 0; v < 25 && t.dt.dim == 3; v++) {
            remove_checked(&t, v, &rs);
            CHECKF(vp_dt_check(&t.dt) == VP_OK, "pyramid base %u", v);
            CHECKF(equals_scratch(&t.dt, v), "pyramid base %u", v);
        }
        CHECK(t.dt.dim < 3 && t.dt.ninserted == 0 && rs.drops == 2);
        /* pending vertices go one by one: dim and span follow */
        while (t.dt.dim >= 0) {
            for (v = 0; v < t.dt.nvert && vp_dt_vertex(&t.dt, v)->tet != VP_DT_PENDING; v++) {}
            CHECK(vp_dt_remove(&t.dt, v) == VP_OK);
            CHECK(vp_dt_check(&t.dt) == VP_OK && equals_scratch(&t.dt, v));
        }
        tri_close(&t);
    }
}

/* Insertions (new points and removed points again) and removals interleaved: validity after
 * every step, equality with a from-scratch build every 40 steps, dead tets reused. */
static void test_remove_interleaved(void)
{
    tri_t t;
    uint64_t s = 61;
    double *pool;
    uint32_t *vid, npool = 900, live = 0, step, reused = 0;
    rmstats_t rs = { 0, 0, 0, 0, 0 };
    size_t i;
    pool = xmalloc(3 * sizeof(double) * npool);
    vid = xmalloc(sizeof *vid * npool);
    for (i = 0; i < 3 * (size_t)npool; i++) pool[i] = vp_splitmix_uniform(&s);
    for (i = 0; i < npool; i++) vid[i] = VP_DT_NONE;
    tri_open(&t, 8u << 20, 4);
    for (step = 0; step < 2000; step++) {
        uint32_t k = (uint32_t)(vp_splitmix_next(&s) % npool);
        int want_insert = live < 20 || (live < 250 && vp_splitmix_next(&s) % 2);
        if (want_insert) {
            while (vid[k] != VP_DT_NONE) k = (k + 1) % npool;
            {
                uint32_t v, slots = t.dt.ntet_slots, nfree = t.dt.nfree, old = t.dt.nvert, nk, nc;
                CHECK(vp_dt_insert(&t.dt, pool + 3 * k, VP_DT_NONE, &v) == VP_OK);
                CHECK(v == old);
                vp_dt_last_killed(&t.dt, &nk);
                vp_dt_last_created(&t.dt, &nc);
                if (t.dt.dim == 3 && nk > 0 && nc - nk <= nfree) {
                    CHECK(t.dt.ntet_slots == slots);
                    reused += nfree > 0;
                }
                vid[k] = v;
                live++;
            }
        } else {
            while (vid[k] == VP_DT_NONE) k = (k + 1) % npool;
            if (t.dt.dim == 3) remove_checked(&t, vid[k], &rs);
            else CHECK(vp_dt_remove(&t.dt, vid[k]) == VP_OK);
            CHECK(vp_dt_remove(&t.dt, vid[k]) == VP_EINVAL);
            vid[k] = VP_DT_NONE;
            live--;
        }
        CHECKF(vp_dt_check(&t.dt) == VP_OK, "step %u", step);
        if (step % 40 == 0) CHECKF(equals_scratch(&t.dt, step), "step %u", step);
    }
    printf("interleaved: reused %u removals %ld grew %ld\n", reused, rs.removals, rs.grew);
    CHECK(reused > 100 && rs.removals > 800);
    tri_close(&t);
    free(pool);
    free(vid);
}

/* Bad input: refused, nothing changed. */
static void test_remove_bad_input(void)
{
    tri_t t;
    size_t n;
    double *xyz, dups[6];
    char err[128];
    snap_t sn;
    uint32_t v, dup_rec = VP_DT_NONE;
    vp_pointgen_uniform(100, 71, &xyz, &n, err, sizeof err);
    tri_open(&t, 1u << 20, 0);
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, NULL) == VP_OK);
    memcpy(dups, xyz, 24);
    dups[3] = 0.25; dups[4] = 0.5; dups[5] = 0.75;
    CHECK(vp_dt_insert_batch(&t.dt, dups, 2, NULL) == VP_OK); /* one duplicate record */
    for (v = 0; v < t.dt.nvert; v++)
        if (!present(&t.dt, v)) dup_rec = v;
    CHECK(dup_rec != VP_DT_NONE);
    CHECK(vp_dt_remove(&t.dt, 7) == VP_OK);
    snap_take(&sn, &t.dt);
    CHECK(vp_dt_remove(NULL, 0) == VP_EINVAL);
    CHECK(vp_dt_remove(&t.dt, t.dt.nvert) == VP_EINVAL);
    CHECK(vp_dt_remove(&t.dt, t.dt.nvert + 1000) == VP_EINVAL);
    CHECK(vp_dt_remove(&t.dt, VP_DT_GHOST) == VP_EINVAL);
    CHECK(vp_dt_remove(&t.dt, VP_DT_NONE) == VP_EINVAL);
    CHECK(vp_dt_remove(&t.dt, 7) == VP_EINVAL);       /* removed already */
    CHECK(vp_dt_remove(&t.dt, dup_rec) == VP_EINVAL); /* a duplicate record */
    CHECK(snap_same(&sn, &t.dt));
    CHECK(vp_dt_check(&t.dt) == VP_OK);
    snap_free(&sn);
    tri_close(&t);
    free(xyz);
}

/* A tight arena: a removal that cannot get its scratch returns VP_ENOMEM and leaves the
 * triangulation exactly as it was; with more room the same removals go through. */
static void test_remove_enomem(void)
{
    size_t n, i, bytes;
    double *xyz;
    char err[128];
    int failed = 0, done = 0, failed_then_done = 0;
    vp_pointgen_uniform(300, 81, &xyz, &n, err, sizeof err);
    for (bytes = 24000; bytes < 120000; bytes = bytes * 9 / 8 + 8) {
        tri_t t;
        uint32_t v;
        int last_failed = 0;
        tri_open(&t, bytes, 4);
        for (i = 0; i < n; i++)
            if (vp_dt_insert(&t.dt, xyz + 3 * i, VP_DT_NONE, NULL) != VP_OK) break;
        if (t.dt.dim < 3) { tri_close(&t); continue; }
        for (v = 0; v < t.dt.nvert; v += 3) {
            snap_t sn;
            int st;
            if (!present(&t.dt, v) || t.dt.dim < 3) continue;
            snap_take(&sn, &t.dt);
            st = vp_dt_remove(&t.dt, v);
            CHECKF(st == VP_OK || st == VP_ENOMEM, "status %d", st);
            if (st == VP_ENOMEM) {
                CHECKF(snap_same(&sn, &t.dt), "changed by a failed removal, arena %zu", bytes);
                failed++;
                last_failed = 1;
            } else {
                done++;
                failed_then_done += last_failed;
                last_failed = 0;
            }
            if (st == VP_ENOMEM || done % 16 == 0) CHECK(vp_dt_check(&t.dt) == VP_OK);
            snap_free(&sn);
        }
        CHECK(vp_dt_check(&t.dt) == VP_OK);
        tri_close(&t);
    }
    printf("enomem: failed %d done %d failed_then_done %d\n", failed, done, failed_then_done);
    CHECKF(failed > 10 && done > 100, "failed %d done %d", failed, done);
    /* a removal that needs new tet slots (the skew lines' centre) in arenas too small for it */
    {
        double pts[3 * 81];
        int f2 = 0, d2 = 0;
        skew_with_centre(pts);
        for (bytes = 40000; bytes < 400000; bytes = bytes * 9 / 8) {
            tri_t t;
            uint32_t ids[81];
            snap_t sn;
            int st;
            tri_open(&t, bytes, 4);
            if (vp_dt_insert_batch(&t.dt, pts, 81, ids) != VP_OK) { tri_close(&t); continue; }
            snap_take(&sn, &t.dt);
            st = vp_dt_remove(&t.dt, ids[0]);
            CHECKF(st == VP_OK || st == VP_ENOMEM, "status %d", st);
            if (st == VP_ENOMEM) {
                CHECKF(snap_same(&sn, &t.dt), "changed by a failed removal, arena %zu", bytes);
                f2++;
            } else {
                CHECK(equals_scratch(&t.dt, 1));
                d2++;
            }
            CHECK(vp_dt_check(&t.dt) == VP_OK);
            snap_free(&sn);
            tri_close(&t);
        }
        CHECKF(f2 > 2 && d2 > 2, "failed %d done %d", f2, d2);
    }
    free(xyz);
}

/* A fingerprint of a fixed triangulation: compared across x86-64 and aarch64 by t_cross. */
static void print_fingerprint(void)
{
    size_t n;
    double *xyz;
    char err[128];
    tri_t t;
    uint64_t h = 1469598103934665603ull;
    uint32_t tt;
    vp_pointgen_uniform(20000, 2024, &xyz, &n, err, sizeof err);
    tri_open(&t, 16u << 20, 0);
    CHECK(vp_dt_insert_batch(&t.dt, xyz, (uint32_t)n, NULL) == VP_OK);
    for (tt = 0; tt < t.dt.ntet_slots; tt++) {
        const unsigned char *b = (const unsigned char *)vp_dt_tet(&t.dt, tt);
        int k;
        for (k = 0; k < 32; k++) h = (h ^ b[k]) * 1099511628211ull;
    }
    printf("fingerprint uniform20000: %016llx tets %u\n", (unsigned long long)h,
           vp_dt_num_finite_tets(&t.dt));
    tri_close(&t);
    free(xyz);
}

int main(void)
{
    test_random_sequential_vs_batch();
    test_grid_unique();
    test_grid_scaled();
    test_cospherical();
    test_flat_start();
    test_bad_input();
    test_enomem();
    test_queries();
    test_adversarial();
    test_filters();
    test_remove_bad_input();
    test_remove_random();
    test_remove_orders();
    test_remove_degenerate();
    test_remove_interleaved();
    test_remove_enomem();
    print_fingerprint();
    return vp_test_done("test_dt");
}
