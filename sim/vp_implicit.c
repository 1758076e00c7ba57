/* vp_implicit — see vp_implicit.h. All coordinates are in the object's own frame. */
#include <float.h>
#include <math.h>
#include <string.h>
#include "vp_implicit.h"
#include "vp_vec3.h"

#define VP_TORUS_R2 0.09      /* tube radius 0.3, squared */
#define VP_G2_K 50.0          /* genus2 smooth-union sharpness */
#define VP_G5_C 11.8
#define VP_BLOB_T 0.5
#define VP_BLOB_N 4

static const double vp_ell_axes[3] = { 1.0, 0.7, 0.5 };
static const double vp_blob_c[VP_BLOB_N][3] = {
    { 0.0, 0.0, 0.0 }, { 1.0, 0.2, 0.1 }, { -0.5, 0.8, 0.2 }, { 0.2, -0.3, 0.9 }
};
static const double vp_blob_s[VP_BLOB_N] = { 1.0, 0.8, 0.7, 0.6 };

static const char *const vp_imp_names[VP_IMP_COUNT] = {
    "sphere", "torus", "genus2", "ellipsoid", "genus5", "blobby"
};

int vp_imp_from_name(const char *name, unsigned long len)
{
    int k;
    for (k = 0; k < VP_IMP_COUNT; k++)
        if (strlen(vp_imp_names[k]) == len && !strncmp(name, vp_imp_names[k], len)) return k;
    return -1;
}

const char *vp_imp_name(int kind) { return kind >= 0 && kind < VP_IMP_COUNT ? vp_imp_names[kind] : "?"; }

int vp_imp_genus(int kind)
{
    switch (kind) {
    case VP_IMP_TORUS: return 1;
    case VP_IMP_GENUS2: return 2;
    case VP_IMP_GENUS5: return 5;
    default: return 0;
    }
}

void vp_imp_bbox(int kind, double lo[3], double hi[3])
{
    int k, i;
    switch (kind) {
    case VP_IMP_SPHERE: for (k = 0; k < 3; k++) { lo[k] = -1.01; hi[k] = 1.01; } break;
    case VP_IMP_TORUS: lo[0] = lo[1] = -1.31; hi[0] = hi[1] = 1.31; lo[2] = -0.31; hi[2] = 0.31; break;
    case VP_IMP_GENUS2:
        /* f >= min(a,b) - log(2)/50, so the solid lies in tori of tube radius sqrt(0.09+0.01387). */
        lo[0] = -2.34; hi[0] = 2.34; lo[1] = -1.34; hi[1] = 1.34; lo[2] = -0.34; hi[2] = 0.34; break;
    case VP_IMP_ELLIPSOID: for (k = 0; k < 3; k++) { lo[k] = -vp_ell_axes[k] - 0.01; hi[k] = vp_ell_axes[k] + 0.01; } break;
    case VP_IMP_GENUS5: for (k = 0; k < 3; k++) { lo[k] = -2.28; hi[k] = 2.28; } break;   /* x^2 <= 5.1363 */
    default: {
        /* f < 0 needs some term > T/N, i.e. |p-c_i| < s_i sqrt(ln(N/T)). */
        double rad = sqrt(log(VP_BLOB_N / VP_BLOB_T)) + 0.01;
        for (k = 0; k < 3; k++) { lo[k] = DBL_MAX; hi[k] = -DBL_MAX; }
        for (i = 0; i < VP_BLOB_N; i++)
            for (k = 0; k < 3; k++) {
                double a = vp_blob_c[i][k] - rad * vp_blob_s[i], b = vp_blob_c[i][k] + rad * vp_blob_s[i];
                if (a < lo[k]) lo[k] = a;
                if (b > hi[k]) hi[k] = b;
            }
    }
    }
}

/* ---------- point values ---------- */

static double vp_torus_at(double x, double y, double z, double g[3])
{
    double rho = sqrt(x * x + y * y), f = (rho - 1) * (rho - 1) + z * z - VP_TORUS_R2;
    if (g) {
        double w = rho > 0 ? 2 * (rho - 1) / rho : 0;
        g[0] = w * x; g[1] = w * y; g[2] = 2 * z;
    }
    return f;
}

double vp_imp_grad(int kind, const double p[3], double g[3])
{
    double x = p[0], y = p[1], z = p[2];
    switch (kind) {
    case VP_IMP_SPHERE:
        if (g) { g[0] = 2 * x; g[1] = 2 * y; g[2] = 2 * z; }
        return x * x + y * y + z * z - 1;
    case VP_IMP_TORUS:
        return vp_torus_at(x, y, z, g);
    case VP_IMP_GENUS2: {
        double ga[3], gb[3], a, b, e, wa, f;
        a = vp_torus_at(x + 1, y, z, g ? ga : NULL);
        b = vp_torus_at(x - 1, y, z, g ? gb : NULL);
        e = exp(-VP_G2_K * fabs(a - b));
        f = (a < b ? a : b) - log1p(e) / VP_G2_K;
        if (g) {
            int k;
            wa = a <= b ? 1 / (1 + e) : e / (1 + e);
            for (k = 0; k < 3; k++) g[k] = wa * ga[k] + (1 - wa) * gb[k];
        }
        return f;
    }
    case VP_IMP_ELLIPSOID: {
        double ax = x / vp_ell_axes[0], ay = y / vp_ell_axes[1], az = z / vp_ell_axes[2];
        if (g) { g[0] = 2 * ax / vp_ell_axes[0]; g[1] = 2 * ay / vp_ell_axes[1]; g[2] = 2 * az / vp_ell_axes[2]; }
        return ax * ax + ay * ay + az * az - 1;
    }
    case VP_IMP_GENUS5: {
        double x2 = x * x, y2 = y * y, z2 = z * z;
        if (g) { g[0] = x * (4 * x2 - 10); g[1] = y * (4 * y2 - 10); g[2] = z * (4 * z2 - 10); }
        return x2 * (x2 - 5) + y2 * (y2 - 5) + z2 * (z2 - 5) + VP_G5_C;
    }
    default: {
        double f = VP_BLOB_T;
        int i;
        if (g) g[0] = g[1] = g[2] = 0;
        for (i = 0; i < VP_BLOB_N; i++) {
            double dx = x - vp_blob_c[i][0], dy = y - vp_blob_c[i][1], dz = z - vp_blob_c[i][2];
            double is2 = 1.0 / (vp_blob_s[i] * vp_blob_s[i]);
            double e = exp(-(dx * dx + dy * dy + dz * dz) * is2);
            f -= e;
            if (g) { g[0] += 2 * is2 * e * dx; g[1] += 2 * is2 * e * dy; g[2] += 2 * is2 * e * dz; }
        }
        return f;
    }
    }
}

double vp_imp_f(int kind, const double p[3]) { return vp_imp_grad(kind, p, NULL); }

/* ---------- interval arithmetic ---------- */

typedef struct vp_iv { double lo, hi; } vp_iv_t;

static vp_iv_t vp_iv(double lo, double hi) { vp_iv_t r; r.lo = lo; r.hi = hi; return r; }
static vp_iv_t vp_iv_add(vp_iv_t a, vp_iv_t b) { return vp_iv(a.lo + b.lo, a.hi + b.hi); }
static vp_iv_t vp_iv_sub(vp_iv_t a, vp_iv_t b) { return vp_iv(a.lo - b.hi, a.hi - b.lo); }
static vp_iv_t vp_iv_addc(vp_iv_t a, double c) { return vp_iv(a.lo + c, a.hi + c); }
static vp_iv_t vp_iv_scale(vp_iv_t a, double k) { return k >= 0 ? vp_iv(k * a.lo, k * a.hi) : vp_iv(k * a.hi, k * a.lo); }
static vp_iv_t vp_iv_mul(vp_iv_t a, vp_iv_t b)
{
    double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
    double lo = fmin(fmin(p1, p2), fmin(p3, p4)), hi = fmax(fmax(p1, p2), fmax(p3, p4));
    return vp_iv(lo, hi);
}
static vp_iv_t vp_iv_sq(vp_iv_t a)
{
    if (a.lo >= 0) return vp_iv(a.lo * a.lo, a.hi * a.hi);
    if (a.hi <= 0) return vp_iv(a.hi * a.hi, a.lo * a.lo);
    return vp_iv(0, a.lo * a.lo > a.hi * a.hi ? a.lo * a.lo : a.hi * a.hi);
}
static vp_iv_t vp_iv_sqrt(vp_iv_t a) { return vp_iv(sqrt(a.lo > 0 ? a.lo : 0), sqrt(a.hi > 0 ? a.hi : 0)); }
/* Pads for rounding: values of size ~mag lose ~1e-16*mag per operation. */
static vp_iv_t vp_iv_pad(vp_iv_t a, double mag)
{
    double e = 1e-13 * (mag + fabs(a.lo) + fabs(a.hi)) + 1e-300;
    return vp_iv(a.lo - e, a.hi + e);
}

static vp_iv_t vp_torus_iv(vp_iv_t X, vp_iv_t Y, vp_iv_t Z)
{
    vp_iv_t rho = vp_iv_sqrt(vp_iv_add(vp_iv_sq(X), vp_iv_sq(Y)));
    return vp_iv_addc(vp_iv_add(vp_iv_sq(vp_iv_addc(rho, -1.0)), vp_iv_sq(Z)), -VP_TORUS_R2);
}

/* d/dt of the torus function along d over the box. */
static vp_iv_t vp_torus_div(vp_iv_t X, vp_iv_t Y, vp_iv_t Z, const double d[3])
{
    vp_iv_t rho2 = vp_iv_add(vp_iv_sq(X), vp_iv_sq(Y)), rho, w, s;
    if (rho2.lo <= 1e-20) return vp_iv(-HUGE_VAL, HUGE_VAL);
    rho = vp_iv_sqrt(rho2);
    w = vp_iv(1 - 1 / rho.lo, 1 - 1 / rho.hi);
    s = vp_iv_add(vp_iv_scale(X, d[0]), vp_iv_scale(Y, d[1]));
    return vp_iv_add(vp_iv_scale(vp_iv_mul(w, s), 2.0), vp_iv_scale(Z, 2 * d[2]));
}

static double vp_smin(double a, double b)
{
    return (a < b ? a : b) - log1p(exp(-VP_G2_K * fabs(a - b))) / VP_G2_K;
}

static double vp_sigmoid(double x) { return x >= 0 ? 1 / (1 + exp(-x)) : exp(x) / (1 + exp(x)); }

void vp_imp_fbox(int kind, const double lo[3], const double hi[3], double out[2])
{
    vp_iv_t X = vp_iv(lo[0], hi[0]), Y = vp_iv(lo[1], hi[1]), Z = vp_iv(lo[2], hi[2]), r;
    double mag = 1;
    switch (kind) {
    case VP_IMP_SPHERE:
        r = vp_iv_addc(vp_iv_add(vp_iv_add(vp_iv_sq(X), vp_iv_sq(Y)), vp_iv_sq(Z)), -1.0);
        break;
    case VP_IMP_TORUS:
        r = vp_torus_iv(X, Y, Z);
        break;
    case VP_IMP_GENUS2: {
        vp_iv_t a = vp_torus_iv(vp_iv_addc(X, 1.0), Y, Z), b = vp_torus_iv(vp_iv_addc(X, -1.0), Y, Z);
        r = vp_iv(vp_smin(a.lo, b.lo), vp_smin(a.hi, b.hi));   /* smin is increasing in both */
        break;
    }
    case VP_IMP_ELLIPSOID:
        r = vp_iv_addc(vp_iv_add(vp_iv_add(vp_iv_sq(vp_iv_scale(X, 1 / vp_ell_axes[0])),
                                           vp_iv_sq(vp_iv_scale(Y, 1 / vp_ell_axes[1]))),
                                 vp_iv_sq(vp_iv_scale(Z, 1 / vp_ell_axes[2]))), -1.0);
        break;
    case VP_IMP_GENUS5: {
        /* u^4 - 5u^2 = (u^2 - 2.5)^2 - 6.25: exact range through the square. */
        vp_iv_t gx = vp_iv_sq(vp_iv_addc(vp_iv_sq(X), -2.5));
        vp_iv_t gy = vp_iv_sq(vp_iv_addc(vp_iv_sq(Y), -2.5));
        vp_iv_t gz = vp_iv_sq(vp_iv_addc(vp_iv_sq(Z), -2.5));
        r = vp_iv_addc(vp_iv_add(vp_iv_add(gx, gy), gz), VP_G5_C - 18.75);
        mag = 20;
        break;
    }
    default: {
        int i;
        r = vp_iv(VP_BLOB_T, VP_BLOB_T);
        for (i = 0; i < VP_BLOB_N; i++) {
            double is2 = 1.0 / (vp_blob_s[i] * vp_blob_s[i]);
            vp_iv_t r2 = vp_iv_add(vp_iv_add(vp_iv_sq(vp_iv_addc(X, -vp_blob_c[i][0])),
                                             vp_iv_sq(vp_iv_addc(Y, -vp_blob_c[i][1]))),
                                   vp_iv_sq(vp_iv_addc(Z, -vp_blob_c[i][2])));
            r.lo -= exp(-r2.lo * is2);
            r.hi -= exp(-r2.hi * is2);
        }
    }
    }
    r = vp_iv_pad(r, mag);
    out[0] = r.lo; out[1] = r.hi;
}

/* Encloses df/dt = grad f . d over the box (genus2 and blobby only). */
static vp_iv_t vp_imp_dbox(int kind, const double lo[3], const double hi[3], const double d[3])
{
    vp_iv_t X = vp_iv(lo[0], hi[0]), Y = vp_iv(lo[1], hi[1]), Z = vp_iv(lo[2], hi[2]), r;
    if (kind == VP_IMP_GENUS2) {
        vp_iv_t Xa = vp_iv_addc(X, 1.0), Xb = vp_iv_addc(X, -1.0);
        vp_iv_t a = vp_torus_iv(Xa, Y, Z), b = vp_torus_iv(Xb, Y, Z);
        vp_iv_t da = vp_torus_div(Xa, Y, Z, d), db = vp_torus_div(Xb, Y, Z, d);
        vp_iv_t bma = vp_iv_sub(b, a), wa;
        if (da.lo == -HUGE_VAL || db.lo == -HUGE_VAL) return vp_iv(-HUGE_VAL, HUGE_VAL);
        /* weight of torus a = sigmoid(k (b - a)), increasing in b - a */
        wa = vp_iv(vp_sigmoid(VP_G2_K * bma.lo), vp_sigmoid(VP_G2_K * bma.hi));
        r = vp_iv_add(db, vp_iv_mul(wa, vp_iv_sub(da, db)));
    } else {
        int i;
        r = vp_iv(0, 0);
        for (i = 0; i < VP_BLOB_N; i++) {
            double is2 = 1.0 / (vp_blob_s[i] * vp_blob_s[i]);
            vp_iv_t DX = vp_iv_addc(X, -vp_blob_c[i][0]), DY = vp_iv_addc(Y, -vp_blob_c[i][1]), DZ = vp_iv_addc(Z, -vp_blob_c[i][2]);
            vp_iv_t r2 = vp_iv_add(vp_iv_add(vp_iv_sq(DX), vp_iv_sq(DY)), vp_iv_sq(DZ));
            vp_iv_t e = vp_iv(exp(-r2.hi * is2), exp(-r2.lo * is2));
            vp_iv_t dot = vp_iv_add(vp_iv_add(vp_iv_scale(DX, d[0]), vp_iv_scale(DY, d[1])), vp_iv_scale(DZ, d[2]));
            r = vp_iv_add(r, vp_iv_mul(e, vp_iv_scale(dot, 2 * is2)));
        }
    }
    return vp_iv_pad(r, 1.0);
}

/* ---------- ray casting ---------- */

/* Safeguarded Newton on a function of one variable with a sign change in [lo, hi] (outside at
 * lo iff out_lo): Newton steps while they stay inside the shrinking bracket (the first 40),
 * bisection otherwise. f(ctx, x, &df) gives the value and the derivative. */
typedef double (*vp_fn1_t)(const void *ctx, double x, double *df);

static double vp_newton_bracket(vp_fn1_t fn, const void *ctx, double lo, double hi, int out_lo)
{
    double x = 0.5 * (lo + hi);
    int it;
    for (it = 0; it < 200; it++) {
        double df, f = fn(ctx, x, &df), xn;
        if ((f > 0) == out_lo) lo = x; else hi = x;
        if (hi - lo <= 4e-16 * (fabs(lo) + fabs(hi)) + 1e-300) break;
        xn = (df != 0 && it < 40) ? x - f / df : 0.5 * (lo + hi);
        if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
        if (fabs(xn - x) <= 2e-16 * (fabs(x) + 1e-30) || f == 0) break;
        x = xn;
    }
    return x;
}

/* f(o + t d) and its derivative along d, for vp_newton_bracket. */
typedef struct vp_ray_fn { int kind; const double *o, *d; } vp_ray_fn_t;

static double vp_ray_fn(const void *ctx, double x, double *df)
{
    const vp_ray_fn_t *r = ctx;
    double p[3], g[3], f;
    p[0] = r->o[0] + x * r->d[0]; p[1] = r->o[1] + x * r->d[1]; p[2] = r->o[2] + x * r->d[2];
    f = vp_imp_grad(r->kind, p, g);
    *df = g[0] * r->d[0] + g[1] * r->d[1] + g[2] * r->d[2];
    return f;
}

/* Safeguarded Newton on f(o + t d) in [lo, hi] where the sign changes (outside at lo iff out_lo). */
static double vp_refine_root(int kind, const double o[3], const double d[3], double lo, double hi, int out_lo)
{
    vp_ray_fn_t r;
    r.kind = kind; r.o = o; r.d = d;
    return vp_newton_bracket(vp_ray_fn, &r, lo, hi, out_lo);
}

/* First crossing by interval subdivision: natural bounds on f, monotonicity from bounds on f',
 * mean-value exclusion, leftmost interval first. */
static int vp_ray_interval(int kind, const double o[3], const double d[3], double t0, double t1, double *t)
{
    struct { double a, b, fa, fb; } st[160];
    int sp = 0, k;
    double p[3];
    for (k = 0; k < 3; k++) p[k] = o[k] + t0 * d[k];
    st[0].fa = vp_imp_f(kind, p);
    for (k = 0; k < 3; k++) p[k] = o[k] + t1 * d[k];
    st[0].fb = vp_imp_f(kind, p);
    st[0].a = t0; st[0].b = t1;
    sp = 1;
    while (sp > 0) {
        double a = st[sp - 1].a, b = st[sp - 1].b, fa = st[sp - 1].fa, fb = st[sp - 1].fb;
        double lo[3], hi[3], F[2], h, m, fm, dmax;
        vp_iv_t D;
        sp--;
        for (k = 0; k < 3; k++) {
            double u = o[k] + a * d[k], v = o[k] + b * d[k];
            lo[k] = u < v ? u : v; hi[k] = u < v ? v : u;
        }
        vp_imp_fbox(kind, lo, hi, F);
        if (F[0] > 0 || F[1] < 0) continue;
        D = vp_imp_dbox(kind, lo, hi, d);
        if (D.lo > 0 || D.hi < 0) {   /* monotone: one crossing at most */
            if ((fa > 0) != (fb > 0)) { *t = vp_refine_root(kind, o, d, a, b, fa > 0); return 1; }
            continue;
        }
        h = 0.5 * (b - a);
        m = a + h;
        for (k = 0; k < 3; k++) p[k] = o[k] + m * d[k];
        fm = vp_imp_f(kind, p);
        dmax = -D.lo > D.hi ? -D.lo : D.hi;
        if (fabs(fm) > dmax * h) continue;  /* |f(m)| exceeds any change within the interval */
        if (h < 1e-13 || sp >= 158) {
            if ((fa > 0) != (fb > 0)) { *t = vp_refine_root(kind, o, d, a, b, fa > 0); return 1; }
            continue;   /* a tangency or a pair of crossings closer than 1e-13: no transverse hit */
        }
        st[sp].a = m; st[sp].b = b; st[sp].fa = fm; st[sp].fb = fb; sp++;
        st[sp].a = a; st[sp].b = m; st[sp].fa = fa; st[sp].fb = fm; sp++;
    }
    return 0;
}

/* Quartic on [0,1] in power form a[0..4]: first root where the sign changes. */
static double vp_poly4(const double a[5], double u, double *du)
{
    *du = ((4 * a[4] * u + 3 * a[3]) * u + 2 * a[2]) * u + a[1];
    return (((a[4] * u + a[3]) * u + a[2]) * u + a[1]) * u + a[0];
}

static double vp_poly4_fn(const void *ctx, double u, double *du)
{
    return vp_poly4((const double *)ctx, u, du);
}

static double vp_poly4_refine(const double a[5], double lo, double hi, int out_lo)
{
    return vp_newton_bracket(vp_poly4_fn, a, lo, hi, out_lo);
}

/* Bernstein subdivision: sign changes of the control values bound the number of roots
 * (Descartes); one change isolates a single crossing. Zero counts as "inside" (<= 0). */
static int vp_bernstein_first(const double a[5], double *u)
{
    struct { double u0, u1, b[5]; } st[80];
    int sp = 1, k;
    st[0].u0 = 0; st[0].u1 = 1;
    st[0].b[0] = a[0];
    st[0].b[1] = a[0] + a[1] / 4;
    st[0].b[2] = a[0] + a[1] / 2 + a[2] / 6;
    st[0].b[3] = a[0] + 0.75 * a[1] + a[2] / 2 + a[3] / 4;
    st[0].b[4] = a[0] + a[1] + a[2] + a[3] + a[4];
    while (sp > 0) {
        double b[5], u0 = st[sp - 1].u0, u1 = st[sp - 1].u1, l[5], r[5], m;
        int changes = 0;
        sp--;
        memcpy(b, st[sp].b, sizeof b);
        for (k = 0; k < 4; k++) changes += (b[k] > 0) != (b[k + 1] > 0);
        if (changes == 0) continue;
        if (changes == 1 || u1 - u0 < 1e-14 || sp >= 78) {
            if ((b[0] > 0) == (b[4] > 0)) continue;
            *u = vp_poly4_refine(a, u0, u1, b[0] > 0);
            return 1;
        }
        /* de Casteljau at the midpoint */
        {
            double w[5];
            memcpy(w, b, sizeof w);
            l[0] = w[0]; r[4] = w[4];
            for (k = 1; k <= 4; k++) {
                int j;
                for (j = 0; j <= 4 - k; j++) w[j] = 0.5 * (w[j] + w[j + 1]);
                l[k] = w[0]; r[4 - k] = w[4 - k];
            }
        }
        m = 0.5 * (u0 + u1);
        st[sp].u0 = m; st[sp].u1 = u1; memcpy(st[sp].b, r, sizeof r); sp++;
        st[sp].u0 = u0; st[sp].u1 = m; memcpy(st[sp].b, l, sizeof l); sp++;
    }
    return 0;
}

/* Quartic coefficients in s of f(q + s d) for the torus and genus5. */
static void vp_quartic_coeffs(int kind, const double q[3], const double d[3], double c[5])
{
    if (kind == VP_IMP_TORUS) {
        double A = vp_dot3(d, d);
        double B = 2 * (vp_dot3(q, d));
        double C = vp_dot3(q, q) + (1.0 - VP_TORUS_R2);
        double Ap = d[0] * d[0] + d[1] * d[1];
        double Bp = 2 * (q[0] * d[0] + q[1] * d[1]);
        double Cp = q[0] * q[0] + q[1] * q[1];
        /* (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2), R = 1: same sign as the torus function */
        c[4] = A * A;
        c[3] = 2 * A * B;
        c[2] = B * B + 2 * A * C - 4 * Ap;
        c[1] = 2 * B * C - 4 * Bp;
        c[0] = C * C - 4 * Cp;
    } else {
        int k;
        c[0] = VP_G5_C; c[1] = c[2] = c[3] = c[4] = 0;
        for (k = 0; k < 3; k++) {
            double x = q[k], e = d[k], x2 = x * x, e2 = e * e;
            c[4] += e2 * e2;
            c[3] += 4 * e2 * e * x;
            c[2] += 6 * e2 * x2 - 5 * e2;
            c[1] += 4 * e * x2 * x - 10 * e * x;
            c[0] += x2 * x2 - 5 * x2;
        }
    }
}

/* Roots of |d|^2 t^2 + 2 b t + c with c = |o|^2 - 1 (after scaling): first crossing in (t0,t1]. */
static int vp_quadric_first(const double o[3], const double d[3], double t0, double t1, double *t)
{
    double A = vp_dot3(d, d);
    double B = vp_dot3(o, d);
    double C = vp_dot3(o, o) - 1;
    double disc = B * B - A * C, q, r1, r2;
    if (!(disc > 0) || A == 0) return 0;
    q = -(B + (B >= 0 ? sqrt(disc) : -sqrt(disc)));
    r1 = q / A;
    r2 = q != 0 ? C / q : r1;
    if (r1 > r2) { double s = r1; r1 = r2; r2 = s; }
    if (r1 > t0 && r1 <= t1) { *t = r1; return 1; }
    if (r1 <= t0 && r2 > t0 && r2 <= t1) { *t = r2; return 1; }
    return 0;
}

int vp_imp_ray(int kind, const double o[3], const double d[3], double t0, double t1, double *t)
{
    double lo[3], hi[3], a = t0, b = t1;
    int k;
    if (!(t1 > t0)) return 0;
    if (kind == VP_IMP_SPHERE) return vp_quadric_first(o, d, t0, t1, t);
    if (kind == VP_IMP_ELLIPSOID) {
        double os[3], ds[3];
        for (k = 0; k < 3; k++) { os[k] = o[k] / vp_ell_axes[k]; ds[k] = d[k] / vp_ell_axes[k]; }
        return vp_quadric_first(os, ds, t0, t1, t);
    }
    /* Clip to the bounding box: outside it f > 0. */
    vp_imp_bbox(kind, lo, hi);
    for (k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return 0;
        } else {
            double u = (lo[k] - o[k]) / d[k], v = (hi[k] - o[k]) / d[k];
            if (u > v) { double s = u; u = v; v = s; }
            if (u > a) a = u;
            if (v < b) b = v;
        }
    }
    if (!(b > a)) return 0;
    if (kind == VP_IMP_TORUS || kind == VP_IMP_GENUS5) {
        double q[3], c[5], L = b - a, u;
        for (k = 0; k < 3; k++) q[k] = o[k] + a * d[k];
        vp_quartic_coeffs(kind, q, d, c);
        c[1] *= L; c[2] *= L * L; c[3] *= L * L * L; c[4] *= (L * L) * (L * L);
        if (!vp_bernstein_first(c, &u)) return 0;
        *t = a + u * L;
        return *t > t0 && *t <= t1;
    }
    if (!vp_ray_interval(kind, o, d, a, b, t)) return 0;
    return *t > t0 && *t <= t1;
}

/* ---------- closest points ---------- */

/* Closest point on the ellipsoid with axes e[0] > e[1] > ... to y (all y >= 0), into x. */
static void vp_ell_closest(int n, const double *e, const double *y, double *x)
{
    int i, it;
    if (n == 1) { x[0] = e[0]; return; }
    if (y[n - 1] > 0) {
        double en = e[n - 1], sum = 0, s0, s1, s = 0;
        for (i = 0; i < n; i++) sum += (e[i] * y[i]) * (e[i] * y[i]);
        s0 = -en * en + en * y[n - 1];
        s1 = -en * en + sqrt(sum);
        for (it = 0; it < 400; it++) {
            double F = -1;
            s = 0.5 * (s0 + s1);
            if (s == s0 || s == s1) break;
            for (i = 0; i < n; i++) { double r = e[i] * y[i] / (s + e[i] * e[i]); F += r * r; }
            if (F > 0) s0 = s; else if (F < 0) s1 = s; else break;
        }
        for (i = 0; i < n; i++) x[i] = e[i] * e[i] * y[i] / (s + e[i] * e[i]);
        return;
    }
    {
        double en2 = e[n - 1] * e[n - 1], sum = 0, xs[3];
        int ok = 1;
        for (i = 0; i < n - 1; i++) {
            double den = e[i] * e[i] - en2;
            if (den <= 0) { ok = 0; break; }
            xs[i] = e[i] * e[i] * y[i] / den;
            sum += (xs[i] / e[i]) * (xs[i] / e[i]);
        }
        if (ok && sum < 1) {
            for (i = 0; i < n - 1; i++) x[i] = xs[i];
            x[n - 1] = e[n - 1] * sqrt(1 - sum);
            return;
        }
        x[n - 1] = 0;
        vp_ell_closest(n - 1, e, y, x);
    }
}

double vp_imp_closest_exact(int kind, const double p[3], double q[3])
{
    int k;
    if (kind == VP_IMP_SPHERE) {
        double n = vp_norm3(p);
        if (n == 0) { q[0] = 1; q[1] = q[2] = 0; return 1; }
        for (k = 0; k < 3; k++) q[k] = p[k] / n;
        return fabs(n - 1);
    }
    if (kind == VP_IMP_TORUS) {
        double rho = sqrt(p[0] * p[0] + p[1] * p[1]), c[3], v[3], dc;
        if (rho > 0) { c[0] = p[0] / rho; c[1] = p[1] / rho; } else { c[0] = 1; c[1] = 0; }
        c[2] = 0;
        for (k = 0; k < 3; k++) v[k] = p[k] - c[k];
        dc = vp_norm3(v);
        if (dc == 0) { v[0] = c[0]; v[1] = c[1]; v[2] = 0; dc = 1; for (k = 0; k < 3; k++) q[k] = c[k] + 0.3 * v[k]; return 0.3; }
        for (k = 0; k < 3; k++) q[k] = c[k] + 0.3 * v[k] / dc;
        return fabs(dc - 0.3);
    }
    if (kind == VP_IMP_ELLIPSOID) {
        double y[3], x[3];
        for (k = 0; k < 3; k++) y[k] = fabs(p[k]);
        vp_ell_closest(3, vp_ell_axes, y, x);
        for (k = 0; k < 3; k++) q[k] = p[k] < 0 ? -x[k] : x[k];
        return vp_dist3(p, q);
    }
    return -1;
}

int vp_imp_project(int kind, const double p[3], double q[3])
{
    int it, k;
    double x[3];
    memcpy(x, p, sizeof x);
    for (it = 0; it < 30; it++) {
        double g[3], f = vp_imp_grad(kind, x, g), gg = vp_dot3(g, g), s;
        if (!(gg > 0) || !isfinite(f)) return -1;
        s = f / gg;
        for (k = 0; k < 3; k++) x[k] -= s * g[k];
        if (fabs(f) <= 1e-14 * sqrt(gg)) { memcpy(q, x, sizeof x); return 0; }
    }
    memcpy(q, x, sizeof x);
    return fabs(vp_imp_f(kind, x)) < 1e-10 ? 0 : -1;
}

/* Solves the 4x4 system a x = b by Gaussian elimination with partial pivoting; -1 if singular. */
static int vp_solve4(double a[4][4], double b[4], double x[4])
{
    int i, j, k;
    for (i = 0; i < 4; i++) {
        int piv = i;
        for (j = i + 1; j < 4; j++) if (fabs(a[j][i]) > fabs(a[piv][i])) piv = j;
        if (!(fabs(a[piv][i]) > 1e-300)) return -1;
        if (piv != i) {
            double t;
            for (k = 0; k < 4; k++) { t = a[i][k]; a[i][k] = a[piv][k]; a[piv][k] = t; }
            t = b[i]; b[i] = b[piv]; b[piv] = t;
        }
        for (j = i + 1; j < 4; j++) {
            double m = a[j][i] / a[i][i];
            for (k = i; k < 4; k++) a[j][k] -= m * a[i][k];
            b[j] -= m * b[i];
        }
    }
    for (i = 3; i >= 0; i--) {
        double s = b[i];
        for (k = i + 1; k < 4; k++) s -= a[i][k] * x[k];
        x[i] = s / a[i][i];
    }
    return 0;
}

/* Newton step on the Lagrange conditions q - p + lambda grad f(q) = 0, f(q) = 0 (Hessian by
 * central differences of the gradient); y gets the proposed point. -1 if singular. */
static int vp_lagrange_step(int kind, const double p[3], const double q[3], double y[3])
{
    double g[3], f, gg, lam, a[4][4], b[4], x[4], h = 1e-6 * (1 + fabs(q[0]) + fabs(q[1]) + fabs(q[2]));
    int i, j;
    f = vp_imp_grad(kind, q, g);
    gg = vp_dot3(g, g);
    if (!(gg > 0)) return -1;
    lam = ((p[0] - q[0]) * g[0] + (p[1] - q[1]) * g[1] + (p[2] - q[2]) * g[2]) / gg;
    for (j = 0; j < 3; j++) {
        double qp[3], qm[3], gp[3], gm[3];
        memcpy(qp, q, sizeof qp); memcpy(qm, q, sizeof qm);
        qp[j] += h; qm[j] -= h;
        vp_imp_grad(kind, qp, gp);
        vp_imp_grad(kind, qm, gm);
        for (i = 0; i < 3; i++) a[i][j] = (i == j) + lam * (gp[i] - gm[i]) / (2 * h);
    }
    for (i = 0; i < 3; i++) { a[i][3] = g[i]; a[3][i] = g[i]; b[i] = -(q[i] - p[i] + lam * g[i]); }
    a[3][3] = 0;
    b[3] = -f;
    if (vp_solve4(a, b, x) < 0) return -1;
    for (i = 0; i < 3; i++) y[i] = q[i] + x[i];
    return 0;
}

double vp_imp_foot(int kind, const double p[3], const double start[3], double q[3])
{
    double cur[3], dcur;
    int it, k;
    if (vp_imp_project(kind, start, cur) < 0) memcpy(cur, start, sizeof cur);
    dcur = vp_dist3(p, cur);
    for (it = 0; it < 100; it++) {
        double g[3], gn, n[3], w, step[3], lam = 1, z[3], y[3], dz = 0, move;
        int tries, ok = 0;
        /* Newton on the Lagrange conditions first (quadratic convergence), accepted only if it
         * brings the surface point closer; else a damped step towards p's tangent-plane foot. */
        if (vp_lagrange_step(kind, p, cur, y) == 0 && vp_imp_project(kind, y, z) == 0) {
            dz = vp_dist3(p, z);
            if (dz <= dcur) ok = 1;
        }
        if (!ok) {
            vp_imp_grad(kind, cur, g);
            gn = vp_norm3(g);
            if (!(gn > 0)) break;
            for (k = 0; k < 3; k++) n[k] = g[k] / gn;
            w = (p[0] - cur[0]) * n[0] + (p[1] - cur[1]) * n[1] + (p[2] - cur[2]) * n[2];
            for (k = 0; k < 3; k++) step[k] = (p[k] - w * n[k]) - cur[k];
            for (tries = 0; tries < 12; tries++, lam *= 0.5) {
                for (k = 0; k < 3; k++) y[k] = cur[k] + lam * step[k];
                if (vp_imp_project(kind, y, z) < 0) continue;
                dz = vp_dist3(p, z);
                if (dz <= dcur) { ok = 1; break; }
            }
        }
        if (!ok) break;
        move = vp_dist3(z, cur);
        memcpy(cur, z, sizeof cur);
        dcur = dz;
        if (move <= 1e-15 * (1 + dcur)) break;
    }
    memcpy(q, cur, sizeof cur);
    return dcur;
}
