/* vp_manifoldgen — seeded samples of k-manifolds (see vp_manifoldgen.h). */
#include "vp_manifoldgen.h"
#include <math.h>
#include <string.h>
#include "vp_rng.h"
#include "vp_status.h"

#define PI 3.14159265358979323846

static const vp_manifold_info_t table[] = {
    { "sphere",   2, 3,  2, 1, "unit sphere in R^3" },
    { "torus",    2, 3,  0, 1, "torus in R^3, radii 1 and 0.4" },
    { "genus2",   2, 3, -2, 1, "two tori (radii 0.8, 0.3, centres x = +-1) smoothly joined, in R^3" },
    { "clifford", 2, 4,  0, 1, "flat Clifford torus in R^4" },
    { "klein",    2, 4,  0, 0, "Klein bottle in R^4" },
    { "so3",      3, 9,  0, 1, "SO(3): 3x3 rotation matrices in R^9" },
    { "curve",    1, 10, 0, 1, "closed curve (cos jt, sin jt)/j, j = 1..5, in R^10" },
};
/* half extent of the first coordinate, for the non-uniform density */
static const double first_extent[] = { 1.0, 1.4, 2.1, 0.7072, 3.0, 1.0, 1.0 };

const vp_manifold_info_t *vp_manifold_info(size_t i)
{
    return i < sizeof table / sizeof table[0] ? &table[i] : NULL;
}

const vp_manifold_info_t *vp_manifold_find(const char *name)
{
    size_t i;
    for (i = 0; name && i < sizeof table / sizeof table[0]; i++)
        if (!strcmp(table[i].name, name)) return &table[i];
    return NULL;
}

/* Signed distance (approximately) to the genus-2 surface: the smooth union of two tori. */
static double tor_dist(double x, double y, double z, double cx)
{
    double rho = sqrt((x - cx) * (x - cx) + y * y) - 0.8;
    return sqrt(rho * rho + z * z) - 0.3;
}

static double genus2_f(const double p[3])
{
    double a = tor_dist(p[0], p[1], p[2], 1.0), b = tor_dist(p[0], p[1], p[2], -1.0);
    const double K = 12.0;
    double m = a < b ? a : b;
    return m - log(exp(-K * (a - m)) + exp(-K * (b - m))) / K;
}

static void genus2_point(vp_rng_t *r, double *p)
{
    for (;;) {
        double q[3], f;
        int it;
        q[0] = -2.2 + 4.4 * vp_rng_uniform(r);
        q[1] = -1.2 + 2.4 * vp_rng_uniform(r);
        q[2] = -0.4 + 0.8 * vp_rng_uniform(r);
        f = genus2_f(q);
        if (fabs(f) > 0.02) continue;
        /* Newton steps onto f = 0 along the gradient (central differences) */
        for (it = 0; it < 8; it++) {
            double g[3], g2 = 0, h = 1e-6;
            int c;
            for (c = 0; c < 3; c++) {
                double a[3], b[3];
                memcpy(a, q, sizeof a); memcpy(b, q, sizeof b);
                a[c] += h; b[c] -= h;
                g[c] = (genus2_f(a) - genus2_f(b)) / (2 * h);
                g2 += g[c] * g[c];
            }
            if (g2 < 1e-12) break;
            for (c = 0; c < 3; c++) q[c] -= f * g[c] / g2;
            f = genus2_f(q);
            if (fabs(f) < 1e-13) break;
        }
        if (fabs(f) > 1e-9) continue;
        memcpy(p, q, sizeof q);
        return;
    }
}

static void one_point(int which, vp_rng_t *r, double *p)
{
    double u, v, s;
    int j;
    switch (which) {
    case 0:
        do {
            s = 0;
            for (j = 0; j < 3; j++) { p[j] = vp_rng_normal(r); s += p[j] * p[j]; }
        } while (s < 1e-12);
        s = sqrt(s);
        for (j = 0; j < 3; j++) p[j] /= s;
        break;
    case 1:   /* area element (1 + 0.4 cos v): rejection */
        do {
            u = 2 * PI * vp_rng_uniform(r);
            v = 2 * PI * vp_rng_uniform(r);
        } while (vp_rng_uniform(r) * 1.4 > 1.0 + 0.4 * cos(v));
        p[0] = (1.0 + 0.4 * cos(v)) * cos(u);
        p[1] = (1.0 + 0.4 * cos(v)) * sin(u);
        p[2] = 0.4 * sin(v);
        break;
    case 2:
        genus2_point(r, p);
        break;
    case 3:
        u = 2 * PI * vp_rng_uniform(r);
        v = 2 * PI * vp_rng_uniform(r);
        s = 1.0 / sqrt(2.0);
        p[0] = s * cos(u); p[1] = s * sin(u); p[2] = s * cos(v); p[3] = s * sin(v);
        break;
    case 4:
        u = 2 * PI * vp_rng_uniform(r);
        v = 2 * PI * vp_rng_uniform(r);
        p[0] = (2.0 + cos(v)) * cos(u);
        p[1] = (2.0 + cos(v)) * sin(u);
        p[2] = sin(v) * cos(u / 2);
        p[3] = sin(v) * sin(u / 2);
        break;
    case 5: {   /* a uniform unit quaternion gives a Haar-uniform rotation */
        double q[4], w, x, y, z;
        do {
            s = 0;
            for (j = 0; j < 4; j++) { q[j] = vp_rng_normal(r); s += q[j] * q[j]; }
        } while (s < 1e-12);
        s = sqrt(s);
        w = q[0] / s; x = q[1] / s; y = q[2] / s; z = q[3] / s;
        p[0] = 1 - 2 * (y * y + z * z); p[1] = 2 * (x * y - z * w);     p[2] = 2 * (x * z + y * w);
        p[3] = 2 * (x * y + z * w);     p[4] = 1 - 2 * (x * x + z * z); p[5] = 2 * (y * z - x * w);
        p[6] = 2 * (x * z - y * w);     p[7] = 2 * (y * z + x * w);     p[8] = 1 - 2 * (x * x + y * y);
        break;
    }
    default:
        u = 2 * PI * vp_rng_uniform(r);
        for (j = 1; j <= 5; j++) {
            p[2 * j - 2] = cos(j * u) / j;
            p[2 * j - 1] = sin(j * u) / j;
        }
        break;
    }
}

int vp_manifold_sample(const char *name, size_t n, uint64_t seed, double noise, int nonuniform, double *out)
{
    const vp_manifold_info_t *info = vp_manifold_find(name);
    vp_rng_t r;
    size_t i;
    int which, j;
    if (!info || !n || !out || !(noise >= 0) || !isfinite(noise)) return VP_EINVAL;
    which = (int)(info - table);
    vp_rng_seed(&r, seed ^ (0x9e3779b97f4a7c15ULL * (uint64_t)(which + 1)));
    for (i = 0; i < n; i++) {
        double *p = out + i * (size_t)info->d;
        for (;;) {
            one_point(which, &r, p);
            if (nonuniform) {
                double s = (p[0] / first_extent[which] + 1) / 2;
                s = s < 0 ? 0 : s > 1 ? 1 : s;
                if (vp_rng_uniform(&r) * 5.0 > 1.0 + 4.0 * s) continue;
            }
            break;
        }
        if (noise > 0)
            for (j = 0; j < info->d; j++) p[j] += noise * vp_rng_normal(&r);
    }
    return VP_OK;
}
