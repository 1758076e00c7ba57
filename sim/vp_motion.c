/* vp_motion — see vp_motion.h. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_motion.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define VP_MOTION_MAX_DEFORM 8
#define DEG_TO_RAD 0.017453292519943295
/* the bump profile phi(rho) = (1 - rho^2)^3: max |phi'| = 6/sqrt(5) (4/5)^2 at rho = 1/sqrt(5) */
#define BUMP_DPHI_MAX (6.0 / 2.23606797749978970 * 0.64)
/* a bump stops growing when its gradient reaches this: the map stays one-to-one, its inverse
 * 2-Lipschitz and the fixed point that inverts it a contraction by 1/2 */
#define BUMP_GRAD_MAX 0.5
/* the marches stop refining below this fraction of the object's radius */
#define MARCH_TOL_REL 1e-9
#define MARCH_STEPS_MAX 4000000L
/* a march's step is at least this many units in the last place of where it is: far from a shrunk
 * body (its frame scaled by 1e-6 and less) the tolerance is finer than the doubles there */
#define MARCH_ULPS 4.0

/* a march's step from u, at least MARCH_ULPS units in the last place of u (u + step != u) */
static double march_step(double step, double u)
{
    double least = MARCH_ULPS * DBL_EPSILON * fabs(u);
    return step < least ? least : step;
}

enum { DEFORM_BEND, DEFORM_BUMP };

/* one deformation x + g(x) n of the body frame */
typedef struct vp_deform {
    int kind;
    double n[3];        /* displacement direction (unit): B for a bend, the normal for a bump */
    double a[3];        /* bend: the bent axis (unit) */
    double p[3];        /* bump: its centre on the surface; bend: the body's centre */
    double rate;        /* bend: curvature per second; bump: height per second */
    double radius;      /* bump: support radius */
    double tcap;        /* bump: |t| beyond which the height stays */
} vp_deform_t;

struct vp_motion {
    const vp_surface_t *body;
    double centre[3];   /* the body's bounding-box centre */
    double radius0;     /* half the body's bounding-box diagonal: the body lies within it of centre */
    double vel[3];      /* translate */
    double axis[3], omega, rcentre[3]; /* rotate: unit axis, rad/s, point on the axis */
    double grow;        /* inflate: scale exp(grow t) */
    int ndef;
    vp_deform_t def[VP_MOTION_MAX_DEFORM];
};

static const char vp_motion_help_text[] =
    "Motion spec (--motion): terms joined by '+'\n"
    "  translate:VX,VY,VZ                   velocity (units per second)\n"
    "  rotate:AX,AY,AZ,DEG_PER_S[@CX,CY,CZ] spin about the axis through C (default the object's centre)\n"
    "  inflate:RATE                         scale about the centre by exp(RATE t)\n"
    "  bend:AX,AY,AZ,BX,BY,BZ,K_PER_S        bend axis A towards B: x + (k/2)((x-centre).A)^2 B, k = K t\n"
    "  bump:X,Y,Z,RADIUS,HEIGHT_PER_S       a smooth bump growing at the surface point nearest X,Y,Z\n"
    "                                       (its height stops at 0.29 RADIUS)\n"
    "At most one each of translate, rotate, inflate; up to 8 bends and bumps.\n"
    "Example: translate:0.01,0,0+rotate:0,0,1,5   bump:1,0,0,0.3,0.02+inflate:0.001";

const char *vp_motion_help(void) { return vp_motion_help_text; }

/* ---------- the spec ---------- */

static const char *const term_names[] = { "translate", "rotate", "inflate", "bend", "bump" };
static const int term_nums[] = { 3, 4, 1, 7, 5 };

/* the term kind named at s (followed by ':'), or -1 */
static int term_at(const char *s, size_t *len)
{
    int k;
    for (k = 0; k < 5; k++) {
        size_t n = strlen(term_names[k]);
        if (!strncmp(s, term_names[k], n) && s[n] == ':') { *len = n + 1; return k; }
    }
    return -1;
}

typedef struct term {
    int kind;
    double v[7];
    int has_at;
    double at[3];
} term_t;

/* Reads up to `want` comma-separated numbers; *s moves past them. */
static int read_numbers(const char **s, double *v, int want, char *err, size_t errlen, const char *name)
{
    int i;
    for (i = 0; i < want; i++) {
        char *e;
        if (i > 0) {
            if (**s != ',') { snprintf(err, errlen, "motion '%s' takes %d numbers, found %d", name, want, i); return VP_EINVAL; }
            (*s)++;
        }
        v[i] = strtod(*s, &e);
        if (e == *s || !isfinite(v[i])) { snprintf(err, errlen, "motion '%s': not a number at '%.20s'", name, *s); return VP_EINVAL; }
        *s = e;
    }
    return VP_OK;
}

static int parse_spec(const char *spec, term_t *terms, int *nterms, char *err, size_t errlen)
{
    const char *s = spec;
    int n = 0, seen[3] = { 0, 0, 0 }, ndef = 0;
    if (!spec || !*spec) { snprintf(err, errlen, "empty motion spec (see --help)"); return VP_EINVAL; }
    for (;;) {
        size_t len;
        int kind = term_at(s, &len), st;
        term_t T;
        memset(&T, 0, sizeof T);
        if (kind < 0) {
            snprintf(err, errlen, "motion: unknown term at '%.20s' (translate:, rotate:, inflate:, bend:, bump:)", s);
            return VP_EINVAL;
        }
        s += len;
        T.kind = kind;
        if ((st = read_numbers(&s, T.v, term_nums[kind], err, errlen, term_names[kind])) != VP_OK) return st;
        if (kind == 1 && *s == '@') {
            s++;
            T.has_at = 1;
            if ((st = read_numbers(&s, T.at, 3, err, errlen, "rotate ...@")) != VP_OK) return st;
        }
        if (kind <= 2) {
            if (seen[kind]) { snprintf(err, errlen, "motion: '%s' given twice (give it once)", term_names[kind]); return VP_EINVAL; }
            seen[kind] = 1;
        } else if (++ndef > VP_MOTION_MAX_DEFORM) {
            snprintf(err, errlen, "motion: more than %d bends and bumps", VP_MOTION_MAX_DEFORM);
            return VP_EINVAL;
        }
        if (kind == 1 && !(vp_norm3(T.v) > 0)) { snprintf(err, errlen, "motion 'rotate': the axis is zero"); return VP_EINVAL; }
        if (kind == 3) {
            double a[3], b[3], c[3];
            memcpy(a, T.v, sizeof a);
            memcpy(b, T.v + 3, sizeof b);
            vp_cross3(c, a, b);
            if (!(vp_norm3(a) > 0) || !(vp_norm3(c) > 1e-9 * vp_norm3(a) * vp_norm3(b))) {
                snprintf(err, errlen, "motion 'bend': A and B must be nonzero and not parallel");
                return VP_EINVAL;
            }
        }
        if (kind == 4 && !(T.v[3] > 0)) { snprintf(err, errlen, "motion 'bump': RADIUS must be > 0"); return VP_EINVAL; }
        if (terms) terms[n] = T;
        n++;
        if (!*s) break;
        if (*s != '+') {
            snprintf(err, errlen, "motion: unexpected '%.20s' after '%s' (terms are joined by '+')", s, term_names[kind]);
            return VP_EINVAL;
        }
        s++;
    }
    *nterms = n;
    return VP_OK;
}

int vp_motion_check_spec(const char *spec, char *err, size_t errlen)
{
    int n;
    return parse_spec(spec, NULL, &n, err, errlen);
}

int vp_motion_open(const char *spec, const vp_surface_t *body, vp_motion_t **out, char *err, size_t errlen)
{
    term_t terms[3 + VP_MOTION_MAX_DEFORM];
    vp_motion_t *m;
    double lo[3], hi[3], d2 = 0;
    int n, i, k, st;
    if (!body || !out) return VP_EINVAL;
    if ((st = parse_spec(spec, terms, &n, err, errlen)) != VP_OK) return st;
    m = calloc(1, sizeof *m);
    if (!m) return VP_ENOMEM;
    m->body = body;
    vp_surface_bbox(body, lo, hi);
    for (k = 0; k < 3; k++) {
        m->centre[k] = 0.5 * (lo[k] + hi[k]);
        d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    m->radius0 = 0.5 * sqrt(d2);
    memcpy(m->rcentre, m->centre, sizeof m->rcentre);
    m->axis[2] = 1;
    for (i = 0; i < n; i++) {
        const term_t *T = &terms[i];
        if (T->kind == 0) memcpy(m->vel, T->v, sizeof m->vel);
        else if (T->kind == 1) {
            memcpy(m->axis, T->v, sizeof m->axis);
            vp_normalize3(m->axis);
            m->omega = T->v[3] * DEG_TO_RAD;
            if (T->has_at) memcpy(m->rcentre, T->at, sizeof m->rcentre);
        } else if (T->kind == 2) m->grow = T->v[0];
        else {
            vp_deform_t *D = &m->def[m->ndef++];
            D->kind = T->kind == 3 ? DEFORM_BEND : DEFORM_BUMP;
            if (D->kind == DEFORM_BEND) {
                double ab;
                memcpy(D->p, m->centre, sizeof D->p);
                memcpy(D->a, T->v, sizeof D->a);
                vp_normalize3(D->a);
                memcpy(D->n, T->v + 3, sizeof D->n);
                ab = vp_dot3(D->a, D->n);
                for (k = 0; k < 3; k++) D->n[k] -= ab * D->a[k];
                vp_normalize3(D->n);
                D->rate = T->v[6];
            } else {
                /* the bump sits on the body at t = 0 (earlier deformations are zero then) */
                vp_surface_closest(body, T->v, D->p);
                vp_surface_normal(body, D->p, D->n);
                D->radius = T->v[3];
                D->rate = T->v[4];
                D->tcap = D->rate != 0 ? BUMP_GRAD_MAX * D->radius / (BUMP_DPHI_MAX * fabs(D->rate)) : 0;
            }
        }
    }
    *out = m;
    return VP_OK;
}

void vp_motion_close(vp_motion_t *m) { free(m); }
const vp_surface_t *vp_motion_body(const vp_motion_t *m) { return m->body; }
int vp_motion_is_similarity(const vp_motion_t *m) { return m->ndef == 0; }

/* ---------- the deformations (body frame) ---------- */

/* the bend's curvature or the bump's height at time t */
static double deform_amount(const vp_deform_t *D, double t)
{
    if (D->kind == DEFORM_BUMP) {
        if (t > D->tcap) t = D->tcap;
        if (t < -D->tcap) t = -D->tcap;
    }
    return D->rate * t;
}

/* g(x) and, when grad is given, its gradient */
static double deform_g(const vp_deform_t *D, double amount, const double x[3], double grad[3])
{
    double r[3], g;
    int k;
    if (D->kind == DEFORM_BEND) {
        double u;
        vp_sub3(r, x, D->p);
        u = vp_dot3(r, D->a);
        g = 0.5 * amount * u * u;
        if (grad) for (k = 0; k < 3; k++) grad[k] = amount * u * D->a[k];
    } else {
        double rho2, w;
        vp_sub3(r, x, D->p);
        rho2 = vp_dot3(r, r) / (D->radius * D->radius);
        if (rho2 >= 1) {
            if (grad) grad[0] = grad[1] = grad[2] = 0;
            return 0;
        }
        w = 1 - rho2;
        g = amount * w * w * w;
        if (grad) for (k = 0; k < 3; k++) grad[k] = -6.0 * amount * w * w * r[k] / (D->radius * D->radius);
    }
    return g;
}

static void deform_apply(const vp_deform_t *D, double amount, const double x[3], double y[3])
{
    double g = deform_g(D, amount, x, NULL);
    int k;
    for (k = 0; k < 3; k++) y[k] = x[k] + g * D->n[k];
}

/* x with x + g(x) n = y: exact for a bend (g is constant along n), a contraction for a bump */
static void deform_invert(const vp_deform_t *D, double amount, const double yin[3], double x[3])
{
    double g, y[3];
    int k, it;
    memcpy(y, yin, sizeof y); /* x may be yin */
    if (D->kind == DEFORM_BEND || amount == 0) {
        g = deform_g(D, amount, y, NULL);
        for (k = 0; k < 3; k++) x[k] = y[k] - g * D->n[k];
        return;
    }
    memcpy(x, y, sizeof y);
    for (it = 0; it < 200; it++) {
        double nx[3], dx = 0;
        g = deform_g(D, amount, x, NULL);
        for (k = 0; k < 3; k++) {
            nx[k] = y[k] - g * D->n[k];
            dx += fabs(nx[k] - x[k]);
        }
        memcpy(x, nx, sizeof nx);
        if (dx <= 1e-15 * (1 + fabs(y[0]) + fabs(y[1]) + fabs(y[2]))) break;
    }
}

/* ---------- the similarity (inflate, rotate, translate) ---------- */

typedef struct frame {
    double s;          /* scale */
    double R[3][3];    /* rotation */
    double amount[VP_MOTION_MAX_DEFORM];
    double t;
} frame_t;

static void frame_at(const vp_motion_t *m, double t, frame_t *F)
{
    double c = cos(m->omega * t), s = sin(m->omega * t), C = 1 - c;
    const double *u = m->axis;
    int i;
    F->t = t;
    F->s = exp(m->grow * t);
    F->R[0][0] = c + u[0] * u[0] * C;        F->R[0][1] = u[0] * u[1] * C - u[2] * s; F->R[0][2] = u[0] * u[2] * C + u[1] * s;
    F->R[1][0] = u[1] * u[0] * C + u[2] * s; F->R[1][1] = c + u[1] * u[1] * C;        F->R[1][2] = u[1] * u[2] * C - u[0] * s;
    F->R[2][0] = u[2] * u[0] * C - u[1] * s; F->R[2][1] = u[2] * u[1] * C + u[0] * s; F->R[2][2] = c + u[2] * u[2] * C;
    for (i = 0; i < m->ndef; i++) F->amount[i] = deform_amount(&m->def[i], t);
}

static void rot(const frame_t *F, const double v[3], double o[3])
{
    int i;
    for (i = 0; i < 3; i++) o[i] = F->R[i][0] * v[0] + F->R[i][1] * v[1] + F->R[i][2] * v[2];
}
static void rot_t(const frame_t *F, const double v[3], double o[3])
{
    int i;
    for (i = 0; i < 3; i++) o[i] = F->R[0][i] * v[0] + F->R[1][i] * v[1] + F->R[2][i] * v[2];
}

/* deformed body frame -> world */
static void sim_fwd(const vp_motion_t *m, const frame_t *F, const double x[3], double y[3])
{
    double z[3], w[3];
    int k;
    for (k = 0; k < 3; k++) z[k] = m->centre[k] + F->s * (x[k] - m->centre[k]) - m->rcentre[k];
    rot(F, z, w);
    for (k = 0; k < 3; k++) y[k] = w[k] + m->rcentre[k] + m->vel[k] * F->t;
}
/* world -> deformed body frame */
static void sim_inv(const vp_motion_t *m, const frame_t *F, const double y[3], double x[3])
{
    double z[3], w[3];
    int k;
    for (k = 0; k < 3; k++) z[k] = y[k] - m->vel[k] * F->t - m->rcentre[k];
    rot_t(F, z, w);
    for (k = 0; k < 3; k++) x[k] = m->centre[k] + (w[k] + m->rcentre[k] - m->centre[k]) / F->s;
}

/* body -> deformed body frame, and back */
static void def_fwd(const vp_motion_t *m, const frame_t *F, const double x[3], double y[3])
{
    double p[3];
    int i;
    memcpy(p, x, sizeof p);
    for (i = 0; i < m->ndef; i++) deform_apply(&m->def[i], F->amount[i], p, p);
    memcpy(y, p, sizeof p);
}
static void def_inv(const vp_motion_t *m, const frame_t *F, const double y[3], double x[3])
{
    double p[3];
    int i;
    memcpy(p, y, sizeof p);
    for (i = m->ndef - 1; i >= 0; i--) deform_invert(&m->def[i], F->amount[i], p, p);
    memcpy(x, p, sizeof p);
}

/* The radius about the centre that holds the deformed body. */
static double def_radius(const vp_motion_t *m, const frame_t *F)
{
    double r = m->radius0;
    int i;
    for (i = 0; i < m->ndef; i++)
        r += m->def[i].kind == DEFORM_BUMP ? fabs(F->amount[i]) : 0.5 * fabs(F->amount[i]) * r * r;
    return r;
}

/* A Lipschitz bound of the inverse deformation over the ball of radius R about the centre (in
 * the deformed frame): each bump's inverse is 1/(1 - |grad g|)-Lipschitz, a bend's inverse
 * 1 + |k| A on the slab |(y - centre).A| <= A. */
static double def_inv_lipschitz(const vp_motion_t *m, const frame_t *F, double R)
{
    double L = 1;
    int i;
    for (i = m->ndef - 1; i >= 0; i--) {
        const vp_deform_t *D = &m->def[i];
        double amt = fabs(F->amount[i]);
        if (D->kind == DEFORM_BUMP) {
            L /= 1 - amt * BUMP_DPHI_MAX / D->radius;
            R += amt;
        } else {
            L *= 1 + amt * R;
            R += 0.5 * amt * R * R;
        }
    }
    return L;
}

void vp_motion_to_world(const vp_motion_t *m, double t, const double x[3], double y[3])
{
    frame_t F;
    double p[3];
    frame_at(m, t, &F);
    def_fwd(m, &F, x, p);
    sim_fwd(m, &F, p, y);
}

void vp_motion_to_body(const vp_motion_t *m, double t, const double y[3], double x[3])
{
    frame_t F;
    double p[3];
    frame_at(m, t, &F);
    sim_inv(m, &F, y, p);
    def_inv(m, &F, p, x);
}

int vp_motion_inside(const vp_motion_t *m, double t, const double p[3])
{
    double x[3];
    vp_motion_to_body(m, t, p, x);
    return vp_surface_inside(m->body, x);
}

/* [u0, u1] of the line o + u d (d unit) inside the ball (c, R), clipped to [0, umax]; 0 if empty */
static int clip_ball(const double c[3], double R, const double o[3], const double d[3], double umax, double *u0,
                     double *u1)
{
    double w[3], b, q, disc, h;
    vp_sub3(w, o, c);
    b = vp_dot3(w, d);
    q = vp_dot3(w, w) - R * R;
    disc = b * b - q;
    if (disc <= 0) return 0;
    h = sqrt(disc);
    *u0 = -b - h > 0 ? -b - h : 0;
    *u1 = -b + h < umax ? -b + h : umax;
    return *u0 < *u1;
}

/* side and distance lower bound at a point of the deformed frame */
static int def_side(const vp_motion_t *m, const frame_t *F, const double p[3])
{
    double x[3];
    def_inv(m, F, p, x);
    return vp_surface_inside(m->body, x);
}

int vp_motion_ray(const vp_motion_t *m, double t, const double o[3], const double dir[3], double tmax, double *t_hit)
{
    frame_t F;
    double of[3], df[3], umax, u, u1, R, L, tol;
    long steps;
    int side, k;
    if (!(tmax > 0)) return 0;
    frame_at(m, t, &F);
    sim_inv(m, &F, o, of);
    rot_t(&F, dir, df);
    umax = tmax / F.s;
    if (m->ndef == 0) {
        if (!vp_surface_ray(m->body, of, df, umax, &u)) return 0;
        *t_hit = u * F.s;
        return 1;
    }
    /* the march: steps no longer than the body distance over the inverse's Lipschitz bound
     * cross no surface; a side change between two steps is bisected */
    R = def_radius(m, &F) * (1 + 1e-6);
    L = def_inv_lipschitz(m, &F, R);
    tol = MARCH_TOL_REL * R;
    if (!clip_ball(m->centre, R, of, df, umax, &u, &u1)) return 0;
    {
        double p[3];
        for (k = 0; k < 3; k++) p[k] = of[k] + u * df[k];
        side = def_side(m, &F, p);
    }
    for (steps = 0; steps < MARCH_STEPS_MAX && u < u1; steps++) {
        double p[3], x[3], step, un;
        for (k = 0; k < 3; k++) p[k] = of[k] + u * df[k];
        def_inv(m, &F, p, x);
        step = vp_surface_distance(m->body, x) / L;
        step = march_step(step < tol ? tol : step, u);
        un = u + step < u1 ? u + step : u1;
        for (k = 0; k < 3; k++) p[k] = of[k] + un * df[k];
        if (def_side(m, &F, p) != side) {
            double a = u, b = un;
            while (b - a > 0.25 * tol) {
                double mid = 0.5 * (a + b);
                /* a and b adjacent doubles (a far ray in a shrunk body's frame): as fine as it gets */
                if (!(mid > a && mid < b)) break;
                for (k = 0; k < 3; k++) p[k] = of[k] + mid * df[k];
                if (def_side(m, &F, p) == side) a = mid; else b = mid;
            }
            if (!(b > 0)) return 0;
            *t_hit = b * F.s;
            return 1;
        }
        u = un;
    }
    return 0;
}

/* distance from p (deformed frame) to the deformed body, by a true surface point: the body's
 * closest point to the preimage, refined by projected Gauss-Newton steps on |D(x) - p|^2 */
static double def_closest(const vp_motion_t *m, const frame_t *F, const double p[3], double q[3])
{
    double x[3], bx[3], best, bq[3];
    int it, k, i;
    def_inv(m, F, p, x);
    vp_surface_closest(m->body, x, bx);
    def_fwd(m, F, bx, bq);
    best = vp_dist3(bq, p);
    for (it = 0; it < 8 && m->ndef > 0; it++) {
        double pts[VP_MOTION_MAX_DEFORM + 1][3], r[3], y[3], nx[3], nq[3], d;
        memcpy(pts[0], bx, sizeof bx);
        for (i = 0; i < m->ndef; i++) deform_apply(&m->def[i], F->amount[i], pts[i], pts[i + 1]);
        vp_sub3(r, pts[m->ndef], p);
        /* J^T r, J = J_k ... J_1 with J_i = I + n_i grad g_i^T */
        memcpy(y, r, sizeof y);
        for (i = m->ndef - 1; i >= 0; i--) {
            double gr[3], nv;
            deform_g(&m->def[i], F->amount[i], pts[i], gr);
            nv = vp_dot3(m->def[i].n, y);
            for (k = 0; k < 3; k++) y[k] += gr[k] * nv;
        }
        for (k = 0; k < 3; k++) nx[k] = bx[k] - y[k];
        vp_surface_closest(m->body, nx, nx);
        def_fwd(m, F, nx, nq);
        d = vp_dist3(nq, p);
        if (!(d < best)) break;
        best = d;
        memcpy(bx, nx, sizeof bx);
        memcpy(bq, nq, sizeof bq);
    }
    if (q) memcpy(q, bq, sizeof bq);
    return best;
}

int vp_motion_segment_collides(const vp_motion_t *m, double t, const double a[3], const double b[3], double clearance)
{
    frame_t F;
    double af[3], bf[3], d[3], len, clr, R, L, tol, u, u1;
    long steps;
    int k;
    if (clearance < 0) clearance = 0;
    frame_at(m, t, &F);
    sim_inv(m, &F, a, af);
    sim_inv(m, &F, b, bf);
    clr = clearance / F.s;
    if (m->ndef == 0) return vp_surface_segment_collides(m->body, af, bf, clr);
    R = def_radius(m, &F) * (1 + 1e-6) + clr;
    L = def_inv_lipschitz(m, &F, R);
    tol = MARCH_TOL_REL * R;
    vp_sub3(d, bf, af);
    len = vp_norm3(d);
    if (len > 0) for (k = 0; k < 3; k++) d[k] /= len;
    else d[0] = 1, d[1] = d[2] = 0;
    if (!clip_ball(m->centre, R, af, d, len, &u, &u1)) {
        /* the whole segment lies outside the ball: only a zero-length one inside can matter */
        if (len > 0) return 0;
        u = u1 = 0;
    }
    for (steps = 0; steps < MARCH_STEPS_MAX; steps++) {
        double p[3], x[3], lower;
        for (k = 0; k < 3; k++) p[k] = af[k] + u * d[k];
        def_inv(m, &F, p, x);
        if (vp_surface_inside(m->body, x)) return 1;
        lower = vp_surface_distance(m->body, x) / L;
        /* within the clearance by the lower bound: counted (conservative: the true gap may be
         * up to L times larger) */
        if (lower <= clr) return 1;
        if (u >= u1) return 0;
        u += march_step(lower - clr > tol ? lower - clr : tol, u);
        if (u > u1) u = u1;
    }
    return 1;
}

double vp_motion_closest(const vp_motion_t *m, double t, const double p[3], double q[3])
{
    frame_t F;
    double pf[3], qf[3], d;
    frame_at(m, t, &F);
    sim_inv(m, &F, p, pf);
    d = m->ndef == 0 ? vp_surface_closest(m->body, pf, qf) : def_closest(m, &F, pf, qf);
    if (q) sim_fwd(m, &F, qf, q);
    return d * F.s;
}

double vp_motion_distance(const vp_motion_t *m, double t, const double p[3]) { return vp_motion_closest(m, t, p, NULL); }

void vp_motion_normal(const vp_motion_t *m, double t, const double p[3], double n[3])
{
    frame_t F;
    double pf[3], pts[VP_MOTION_MAX_DEFORM + 1][3], v[3];
    int i, k;
    frame_at(m, t, &F);
    sim_inv(m, &F, p, pf);
    def_inv(m, &F, pf, pts[0]);
    vp_surface_normal(m->body, pts[0], v);
    /* the normal goes by J^-T = J_k^-T ... J_1^-T, J_i^-T v = v - grad g (n.v) / (1 + grad g.n) */
    for (i = 0; i < m->ndef; i++) {
        double gr[3], den, nv;
        deform_g(&m->def[i], F.amount[i], pts[i], gr);
        deform_apply(&m->def[i], F.amount[i], pts[i], pts[i + 1]);
        den = 1 + vp_dot3(gr, m->def[i].n);
        nv = vp_dot3(m->def[i].n, v);
        for (k = 0; k < 3; k++) v[k] -= gr[k] * nv / den;
    }
    rot(&F, v, n);
    vp_normalize3(n);
}

double vp_motion_speed_bound(const vp_motion_t *m, double t0, double t1)
{
    frame_t F;
    double ta = fabs(t0) > fabs(t1) ? fabs(t0) : fabs(t1), smax, rho, vdef = 0, r = m->radius0, cr[3];
    int i;
    /* the deformations' amounts grow with |t|: their largest over [t0, t1] is at ta */
    frame_at(m, ta, &F);
    for (i = 0; i < m->ndef; i++) {
        const vp_deform_t *D = &m->def[i];
        double amt = fabs(F.amount[i]), rate = fabs(D->rate);
        if (D->kind == DEFORM_BUMP) {
            /* moving points are carried through the bump: grad <= BUMP_GRAD_MAX */
            vdef = vdef * (1 + amt * BUMP_DPHI_MAX / D->radius) + rate;
            r += amt;
        } else {
            vdef = vdef * (1 + amt * r) + 0.5 * rate * r * r;
            r += 0.5 * amt * r * r;
        }
    }
    rho = r;
    smax = exp(m->grow * t0) > exp(m->grow * t1) ? exp(m->grow * t0) : exp(m->grow * t1);
    vp_sub3(cr, m->centre, m->rcentre);
    return fabs(m->omega) * (smax * rho + vp_norm3(cr)) + fabs(m->grow) * smax * rho + smax * vdef + vp_norm3(m->vel);
}

/* ---------- the Hausdorff measure at one time ---------- */

typedef struct hd_ctx { const vp_motion_t *m; double t; } hd_ctx_t;

static double hd_closest(const void *ctx, const double p[3], double q[3])
{
    const hd_ctx_t *c = ctx;
    return vp_motion_closest(c->m, c->t, p, q);
}
static void hd_normal(const void *ctx, const double p[3], double n[3])
{
    const hd_ctx_t *c = ctx;
    vp_motion_normal(c->m, c->t, p, n);
}
/* the body's samples carried to time t (uniform by the body's area, not the deformed one's) */
static size_t hd_sample(const void *ctx, size_t n, uint64_t seed, double *xyz)
{
    const hd_ctx_t *c = ctx;
    size_t i, got = vp_surface_sample(c->m->body, n, seed, xyz);
    for (i = 0; i < got; i++) {
        double x[3];
        memcpy(x, xyz + 3 * i, sizeof x);
        vp_motion_to_world(c->m, c->t, x, xyz + 3 * i);
    }
    return got;
}

int vp_motion_hausdorff(const vp_mesh_t *mesh, const vp_motion_t *m, double t, size_t n, uint64_t seed,
                        vp_hausdorff_t *out)
{
    hd_ctx_t c;
    vp_hd_object_t obj;
    double s;
    if (!m || !vp_finite(t)) return VP_EINVAL;
    c.m = m;
    c.t = t;
    s = exp(m->grow * t);
    obj.ctx = &c;
    obj.closest = hd_closest;
    obj.normal = hd_normal;
    obj.sample = hd_sample;
    obj.creases = NULL;   /* the moving body: area samples alone */
    obj.area = vp_surface_area(m->body) * s * s;
    return vp_hausdorff_object(mesh, &obj, n, seed, out);
}
