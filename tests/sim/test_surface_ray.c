/* Ray casting of every simulated object against brute force: fine marching of the inside test
 * and bisection. The fast hit must be the first crossing (same t to 1e-9), never later than a
 * point known to be inside, including rays that graze the surface and pass through thin slivers.
 * Prints the measured time per ray. */
#include <math.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "vp_meshgen.h"
#include "vp_meshio.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

static double vp_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void at(const double o[3], const double d[3], double t, double p[3])
{
    int k;
    for (k = 0; k < 3; k++) p[k] = o[k] + t * d[k];
}

static int inside_at(const vp_surface_t *s, const double o[3], const double d[3], double t)
{
    double p[3];
    at(o, d, t, p);
    return vp_surface_inside(s, p);
}

/* First change of the inside state along the ray, marching with step h, then bisection. */
static int brute_ray(const vp_surface_t *s, const double o[3], const double d[3], double tmax, double h, double *t)
{
    int in0 = inside_at(s, o, d, 0);
    double prev = 0, cur;
    for (cur = h;; cur += h) {
        if (cur > tmax) cur = tmax;
        if (inside_at(s, o, d, cur) != in0) {
            double a = prev, b = cur;
            while (b - a > 1e-14 * (1 + b)) {
                double m = 0.5 * (a + b);
                if (m <= a || m >= b) break;
                if (inside_at(s, o, d, m) == in0) a = m; else b = m;
            }
            *t = 0.5 * (a + b);
            return 1;
        }
        if (cur >= tmax) return 0;
        prev = cur;
    }
}

/* Is there a crossing within 1e-9 of t? */
static int crossing_near(const vp_surface_t *s, const double o[3], const double d[3], double t)
{
    double e;
    for (e = 1e-11; e <= 1e-8; e *= 10)
        if (inside_at(s, o, d, t - e) != inside_at(s, o, d, t + e)) return 1;
    return 0;
}

static void check_surface(const char *spec, int nrays, int ngraze)
{
    vp_surface_t *s;
    char err[256];
    double lo[3], hi[3], c[3], R = 0;
    vp_rng_t r;
    int i, k, agree = 0, thin = 0, grazed = 0, st;
    st = vp_surface_open(spec, &s, err, sizeof err);
    CHECKF(st == VP_OK, "%s: %s", spec, err);
    if (st != VP_OK) return;
    vp_surface_bbox(s, lo, hi);
    for (k = 0; k < 3; k++) { c[k] = 0.5 * (lo[k] + hi[k]); R += (hi[k] - lo[k]) * (hi[k] - lo[k]); }
    R = 0.5 * sqrt(R);
    vp_rng_seed(&r, 12345);
    /* Random rays: from outside the box towards it, and from random points of the box. */
    for (i = 0; i < nrays; i++) {
        double o[3], d[3], u[3], tgt[3], n = 0, tf = 0, tb = 0, tmax;
        int hf, hb;
        if (i % 3 != 2) {
            vp_rng_unit3(&r, u);
            for (k = 0; k < 3; k++) { o[k] = c[k] + 1.1 * R * u[k]; tgt[k] = lo[k] + (hi[k] - lo[k]) * vp_rng_uniform(&r); }
            for (k = 0; k < 3; k++) { d[k] = tgt[k] - o[k]; n += d[k] * d[k]; }
            n = sqrt(n);
            for (k = 0; k < 3; k++) d[k] /= n;
        } else {
            for (k = 0; k < 3; k++) o[k] = lo[k] + (hi[k] - lo[k]) * vp_rng_uniform(&r);
            vp_rng_unit3(&r, d);
        }
        tmax = (i % 5 == 4) ? 0.7 * R : 2.5 * R;   /* some short ranges: misses beyond tmax */
        hf = vp_surface_ray(s, o, d, tmax, &tf);
        hb = brute_ray(s, o, d, tmax, 2e-3 * R, &tb);
        if (hf) CHECKF(tf > 0 && tf <= tmax, "%s ray %d: t %g outside (0,%g]", spec, i, tf, tmax);
        if ((!hb && !hf) || (hb && hf && fabs(tf - tb) <= 1e-9 * (1 + tb))) { agree++; continue; }
        if (hf && (!hb || tf < tb)) {
            /* a crossing the marching missed (a sliver thinner than its step)? */
            CHECKF(crossing_near(s, o, d, tf), "%s ray %d: fast hit %.17g is no crossing (brute %d %.17g)", spec, i, tf, hb, tb);
            thin++;
            continue;
        }
        CHECKF(0, "%s ray %d: fast %d t=%.17g, brute %d t=%.17g (o %g %g %g d %g %g %g)", spec, i, hf, tf, hb, tb,
               o[0], o[1], o[2], d[0], d[1], d[2]);
    }
    /* Grazing rays: the line passes just inside the surface (depth eps) along a tangent. The
     * first hit must come no later than that inside point. */
    {
        double *pts = malloc((size_t)ngraze * 3 * sizeof(double));
        vp_surface_sample(s, (size_t)ngraze, 99, pts);
        for (i = 0; i < ngraze; i++) {
            static const double depth[5] = { 1e-3, 1e-5, 1e-7, 1e-9, 1e-11 };
            double *q = pts + 3 * i, nrm[3], tg[3], pin[3], o[3], t, len = 0, L = 0.5 * R;
            int in;
            vp_surface_normal(s, q, nrm);
            vp_rng_unit3(&r, tg);
            t = tg[0] * nrm[0] + tg[1] * nrm[1] + tg[2] * nrm[2];
            for (k = 0; k < 3; k++) { tg[k] -= t * nrm[k]; len += tg[k] * tg[k]; }
            len = sqrt(len);
            for (k = 0; k < 3; k++) tg[k] /= len;
            for (k = 0; k < 3; k++) pin[k] = q[k] - depth[i % 5] * nrm[k];
            for (k = 0; k < 3; k++) o[k] = pin[k] - L * tg[k];
            in = vp_surface_inside(s, pin);
            if (!in || vp_surface_inside(s, o)) continue;
            grazed++;
            CHECKF(vp_surface_ray(s, o, tg, 2 * L, &t) && t <= L * (1 + 1e-15), "%s graze %d depth %g: first hit missing or late",
                   spec, i, depth[i % 5]);
            CHECKF(crossing_near(s, o, tg, t), "%s graze %d: hit is no crossing", spec, i);
        }
        free(pts);
    }
    /* Timing: probe-like rays from outside towards the object. */
    {
        int nt = 200000, hits = 0;
        double *O = malloc((size_t)nt * 6 * sizeof(double)), t0, t1;
        for (i = 0; i < nt; i++) {
            double u[3], tgt[3], n = 0, *o = O + 6 * i, *d = o + 3;
            vp_rng_unit3(&r, u);
            for (k = 0; k < 3; k++) { o[k] = c[k] + 1.1 * R * u[k]; tgt[k] = lo[k] + (hi[k] - lo[k]) * vp_rng_uniform(&r); }
            for (k = 0; k < 3; k++) { d[k] = tgt[k] - o[k]; n += d[k] * d[k]; }
            n = sqrt(n);
            for (k = 0; k < 3; k++) d[k] /= n;
        }
        t0 = vp_now();
        for (i = 0; i < nt; i++) { double t; hits += vp_surface_ray(s, O + 6 * i, O + 6 * i + 3, 3 * R, &t); }
        t1 = vp_now();
        printf("%-44s %7.3f us/ray (%d%% hits); %d rays agree with brute force, %d thin crossings only the fast caster saw, %d grazing rays\n",
               spec, (t1 - t0) / nt * 1e6, hits * 100 / nt, agree, thin, grazed);
        free(O);
    }
    vp_surface_close(s);
}

int main(void)
{
    check_surface("sphere", 2500, 600);
    check_surface("ellipsoid", 2500, 600);
    check_surface("torus", 2500, 600);
    check_surface("genus2", 2500, 600);
    check_surface("genus5", 2500, 600);
    check_surface("blobby", 2500, 600);
    check_surface("torus+sphere*0.4@0,0,1.5+genus5*0.3@4,0,0", 2500, 600);
    check_surface("torus*0.001@1000,2000,-3000", 300, 200);   /* small and far from the origin */
    {
        /* triangle meshes: a 32768-face torus grid and an icosphere, through the BVH */
        vp_mesh_t m, ico;
        char path[96], spec[256];
        double off[3] = { 0, 0, 2 };
        vp_mesh_init(&m); vp_mesh_init(&ico);
        snprintf(path, sizeof path, "/tmp/vp_test_ray_%ld.ply", (long)getpid());
        CHECK(vp_meshgen_torus(1.0, 0.3, 256, 64, &m) == VP_OK && vp_meshgen_icosphere(3, &ico) == VP_OK);
        CHECK(vp_meshgen_append(&m, &ico, off) == VP_OK);
        CHECK(vp_mesh_write_file(&m, path, VP_MESH_PLY_BIN) == VP_OK);
        snprintf(spec, sizeof spec, "ply:%s", path);
        check_surface(spec, 600, 300);
        remove(path);
        vp_mesh_free(&m); vp_mesh_free(&ico);
    }
    return vp_test_done("test_surface_ray");
}
