/* vp_head — see vp_head.h. */
#include <math.h>
#include <string.h>
#include "vp_head.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define VP_HEAD_DEG (3.14159265358979323846 / 180.0)
#define VP_HEAD_STACK 128
#define VP_HEAD_MAX_STEPS 1000000L   /* advancement steps per part and motion before giving up */

static int vp_head_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return 0;
    return 1;
}

int vp_head_init(vp_head_t *h, const double tilt_offset[3], const double laser_offset[3])
{
    if (!h || !tilt_offset || !laser_offset || !vp_head_finite(tilt_offset, 3) || !vp_head_finite(laser_offset, 3))
        return VP_EINVAL;
    memset(h, 0, sizeof *h);
    memcpy(h->tilt_offset, tilt_offset, sizeof h->tilt_offset);
    memcpy(h->laser_offset, laser_offset, sizeof h->laser_offset);
    return VP_OK;
}

int vp_head_add(vp_head_t *h, const char *name, int frame, int kind, const double a[3], const double b[3], double r)
{
    vp_head_part_t *p;
    int k;
    if (!h || !name || !a || !b || !vp_head_finite(a, 3) || !vp_head_finite(b, 3) || !isfinite(r) || r < 0 ||
        (frame != VP_HEAD_TILT && frame != VP_HEAD_PAN) || (kind != VP_HEAD_CAPSULE && kind != VP_HEAD_BOX))
        return VP_EINVAL;
    if (kind == VP_HEAD_BOX)
        for (k = 0; k < 3; k++) if (b[k] < 0) return VP_EINVAL;
    if (h->nparts >= VP_HEAD_MAX_PARTS) return VP_ENOMEM;
    p = &h->part[h->nparts++];
    memset(p, 0, sizeof *p);
    strncpy(p->name, name, sizeof p->name - 1);
    p->frame = frame;
    p->kind = kind;
    memcpy(p->a, a, sizeof p->a);
    memcpy(p->b, b, sizeof p->b);
    p->r = r;
    return VP_OK;
}

/* The core in its own frame: centre and three orthogonal half-axes (zero ones allowed). */
static void vp_head_core(const vp_head_part_t *p, double c[3], double e[3][3])
{
    int k;
    memset(e, 0, 9 * sizeof(double));
    if (p->kind == VP_HEAD_BOX) {
        memcpy(c, p->a, 3 * sizeof(double));
        for (k = 0; k < 3; k++) e[k][k] = p->b[k];
        return;
    }
    for (k = 0; k < 3; k++) {
        c[k] = 0.5 * (p->a[k] + p->b[k]);
        e[0][k] = 0.5 * (p->b[k] - p->a[k]);
    }
}

/* The core's vertices (a segment's 2 ends, a box's 8 corners); returns their count. */
static int vp_head_vertices(const vp_head_part_t *p, double v[8][3])
{
    double c[3], e[3][3];
    int n, i, k;
    vp_head_core(p, c, e);
    n = p->kind == VP_HEAD_BOX ? 8 : 2;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) {
            double s0 = (i & 1) ? 1 : -1, s1 = (i & 2) ? 1 : -1, s2 = (i & 4) ? 1 : -1;
            v[i][k] = c[k] + s0 * e[0][k] + s1 * e[1][k] + s2 * e[2][k];
        }
    return n;
}

double vp_head_reach(const vp_head_t *h, int i, double tilt_lo, double tilt_hi)
{
    const vp_head_part_t *p;
    double v[8][3], far = 0, step = 0.25, arm;
    int n, q, m, ns;
    if (!h || i < 0 || i >= h->nparts) return NAN;
    p = &h->part[i];
    n = vp_head_vertices(p, v);
    if (p->frame == VP_HEAD_TILT) {
        for (q = 0; q < n; q++) {
            double d = vp_dist3(v[q], h->laser_offset);
            if (d > far) far = d;
        }
        return far + p->r;
    }
    /* pan frame: the laser origin is at tilt_offset + Ry(-tilt) laser_offset there, on a circle
     * of radius arm about the tilt axis; the distance to a point is convex along the core, so its
     * largest value is at a vertex; tilt sampled every 0.25 degrees, plus the arc between */
    if (tilt_hi < tilt_lo) { double t = tilt_lo; tilt_lo = tilt_hi; tilt_hi = t; }
    arm = sqrt(h->laser_offset[0] * h->laser_offset[0] + h->laser_offset[2] * h->laser_offset[2]);
    ns = (int)ceil((tilt_hi - tilt_lo) / step);
    if (ns < 1) ns = 1;
    for (m = 0; m <= ns; m++) {
        double t = tilt_lo + (tilt_hi - tilt_lo) * m / ns, r[9], o[3], lo[3];
        vp_kin_rot(0, t, r);
        vp_kin_mul(r, h->laser_offset, lo);
        for (q = 0; q < 3; q++) o[q] = h->tilt_offset[q] + lo[q];
        for (q = 0; q < n; q++) {
            double d = vp_dist3(v[q], o);
            if (d > far) far = d;
        }
    }
    return far + arm * 0.5 * ((tilt_hi - tilt_lo) / ns) * VP_HEAD_DEG + p->r;
}

void vp_head_pose(const vp_head_t *h, int i, const double j[VP_KIN_JOINTS], double c[3], double e[3][3])
{
    const vp_head_part_t *p = &h->part[i];
    double r[9], rz[9], cl[3], el[3][3], t[3], w[3];
    int k, q;
    vp_head_core(p, cl, el);
    vp_kin_rot(j[VP_J_PAN], 0, rz);
    vp_kin_mul(rz, h->tilt_offset, t);
    for (k = 0; k < 3; k++) t[k] += j[k];          /* the tilt axis centre T */
    if (p->frame == VP_HEAD_TILT) vp_kin_rot(j[VP_J_PAN], j[VP_J_TILT], r);
    else memcpy(r, rz, sizeof r);
    vp_kin_mul(r, cl, w);
    for (k = 0; k < 3; k++) c[k] = (p->frame == VP_HEAD_TILT ? t[k] : j[k]) + w[k];
    for (q = 0; q < 3; q++) vp_kin_mul(r, el[q], e[q]);
}

/* A lower bound (>= 0.75 need) on the distance from the core (c, e) grown by r to the object,
 * or -1 when a point of the part is within need of the surface (or the bisection cannot tell). */
static double vp_head_gap(const vp_head_object_t *obj, const double c0[3], const double e0[3][3], double r, double need,
                          unsigned long *evals)
{
    double sc[VP_HEAD_STACK][3], se[VP_HEAD_STACK][3][3], best = HUGE_VAL;
    int n = 1;
    memcpy(sc[0], c0, sizeof sc[0]);
    memcpy(se[0], e0, sizeof se[0]);
    while (n > 0) {
        double c[3], e[3][3], d, rho2 = 0, rho, lb, len[3];
        int k, q, big = 0;
        n--;
        memcpy(c, sc[n], sizeof c);
        memcpy(e, se[n], sizeof e);
        d = obj->distance(obj->ctx, c);
        if (evals) (*evals)++;
        /* the ball of radius r about c is part of the body: it comes within d - r */
        if (d - r < need) return -1;
        for (q = 0; q < 3; q++) { len[q] = vp_dot3(e[q], e[q]); rho2 += len[q]; }
        rho = sqrt(rho2);
        lb = d - rho - r;
        if (lb >= need || rho <= 0.25 * need) { if (lb < best) best = lb; continue; }
        if (n + 2 > VP_HEAD_STACK) return -1;
        for (q = 1; q < 3; q++) if (len[q] > len[big]) big = q;
        for (k = 0; k < 3; k++) e[big][k] *= 0.5;
        for (q = 0; q < 2; q++) {
            double s = q ? -1.0 : 1.0;
            for (k = 0; k < 3; k++) sc[n][k] = c[k] + s * e[big][k];
            memcpy(se[n], e, sizeof se[n]);
            n++;
        }
    }
    return best;
}

double vp_head_moved(const vp_head_t *h, int i, const double ja[VP_KIN_JOINTS], const double jb[VP_KIN_JOINTS])
{
    const vp_head_part_t *p = &h->part[i];
    double dj[VP_KIN_JOINTS], cl[3], el[3][3], dg, dp, dt, rho;
    int k;
    for (k = 0; k < VP_KIN_JOINTS; k++) dj[k] = jb[k] - ja[k];
    dg = vp_norm3(dj);
    dp = fabs(dj[VP_J_PAN]) * VP_HEAD_DEG;
    dt = fabs(dj[VP_J_TILT]) * VP_HEAD_DEG;
    vp_head_core(p, cl, el);
    /* every core point lies within rho of the frame's origin (the tilt axis centre, or the pan
     * pivot), and a turn by a moves a point at r by at most a r */
    rho = vp_norm3(cl) + sqrt(vp_dot3(el[0], el[0]) + vp_dot3(el[1], el[1]) + vp_dot3(el[2], el[2]));
    return p->frame == VP_HEAD_TILT ? dg + dp * (vp_norm3(h->tilt_offset) + rho) + dt * rho : dg + dp * rho;
}

int vp_head_near(const vp_head_t *h, const vp_head_object_t *obj, unsigned mask, const double j[VP_KIN_JOINTS],
                 double need, double *gap, unsigned long *evals)
{
    double best = HUGE_VAL;
    int i;
    if (!h || !obj || !obj->distance || !obj->inside || !j || !gap || !(need > 0) || !isfinite(need) ||
        !vp_head_finite(j, VP_KIN_JOINTS))
        return VP_EINVAL;
    for (i = 0; i < h->nparts; i++) {
        double c[3], e[3][3], g;
        if (!(mask >> i & 1u)) continue;
        vp_head_pose(h, i, j, c, e);
        if (obj->inside(obj->ctx, c)) return 1;
        g = vp_head_gap(obj, c, (const double (*)[3])e, h->part[i].r, need, evals);
        if (g < 0) return 1;
        if (g < best) best = g;
    }
    *gap = best;
    return 0;
}

int vp_head_sweep(const vp_head_t *h, const vp_head_object_t *obj, const double ja[VP_KIN_JOINTS],
                  const double jb[VP_KIN_JOINTS], double tol, int hit[VP_HEAD_MAX_PARTS], unsigned long *evals)
{
    double dj[VP_KIN_JOINTS];
    int i, k, nhit = 0;
    if (!h || !obj || !obj->distance || !obj->inside || !ja || !jb || !hit || !(tol > 0) || !isfinite(tol) ||
        !vp_head_finite(ja, VP_KIN_JOINTS) || !vp_head_finite(jb, VP_KIN_JOINTS))
        return VP_EINVAL;
    for (k = 0; k < VP_KIN_JOINTS; k++) dj[k] = jb[k] - ja[k];
    for (i = 0; i < VP_HEAD_MAX_PARTS; i++) hit[i] = 0;
    for (i = 0; i < h->nparts; i++) {
        const vp_head_part_t *p = &h->part[i];
        double speed = vp_head_moved(h, i, ja, jb), s = 0;   /* the fastest a point moves per unit of s */
        long steps = 0;
        for (;;) {
            double j[VP_KIN_JOINTS], c[3], e[3][3], gap;
            for (k = 0; k < VP_KIN_JOINTS; k++) j[k] = s >= 1 ? jb[k] : ja[k] + s * dj[k];
            vp_head_pose(h, i, j, c, e);
            /* a part clear of the surface all along stays on the side it started on */
            if (steps == 0 && obj->inside(obj->ctx, c)) { hit[i] = 1; break; }
            gap = vp_head_gap(obj, c, (const double (*)[3])e, p->r, tol, evals);
            if (gap < 0 || ++steps > VP_HEAD_MAX_STEPS) { hit[i] = 1; break; }
            if (s >= 1 || !(speed > 0)) break;
            s += gap / speed;
            if (s > 1) s = 1;
        }
        nhit += hit[i];
    }
    return nhit;
}
