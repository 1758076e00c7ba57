/* vp_calib — see vp_calib.h. */
#include <math.h>
#include <string.h>
#include "vp_calib.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define NP 18   /* fx fy cx cy | k1 k2 p1 p2 | rotation vector (3) | position (3) | beam offset (2) | beam tilt (2) */

void vp_lens_distort(const double k[4], const double xy[2], double out[2])
{
    const double x = xy[0], y = xy[1], r2 = x * x + y * y, radial = 1 + k[0] * r2 + k[1] * r2 * r2;
    out[0] = x * radial + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
    out[1] = y * radial + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
}

int vp_lens_undistort(const double k[4], const double xyd[2], double out[2])
{
    double x = xyd[0], y = xyd[1];
    int it;
    if (!isfinite(x) || !isfinite(y)) return VP_EINVAL;
    for (it = 0; it < 50; it++) {
        const double r2 = x * x + y * y, radial = 1 + k[0] * r2 + k[1] * r2 * r2;
        const double dr = 2 * k[0] + 4 * k[1] * r2;   /* d radial / d(r2) * 2 */
        double f[2], xy[2] = { x, y }, a, b, c, d, det, dx, dy;
        vp_lens_distort(k, xy, f);
        f[0] -= xyd[0];
        f[1] -= xyd[1];
        a = radial + x * dr * x + 2 * k[2] * y + 6 * k[3] * x;
        b = x * dr * y + 2 * k[2] * x + 2 * k[3] * y;
        c = y * dr * x + 2 * k[2] * x + 2 * k[3] * y;
        d = radial + y * dr * y + 6 * k[2] * y + 2 * k[3] * x;
        det = a * d - b * c;
        if (!(fabs(det) > 1e-12)) return VP_EDEGEN;
        dx = (d * f[0] - b * f[1]) / det;
        dy = (a * f[1] - c * f[0]) / det;
        x -= dx;
        y -= dy;
        if (!isfinite(x) || !isfinite(y) || x * x + y * y > 100) return VP_EDEGEN;
        if (fabs(dx) + fabs(dy) < 1e-14) break;
    }
    {
        double chk[2], xy[2] = { x, y };
        vp_lens_distort(k, xy, chk);
        if (fabs(chk[0] - xyd[0]) + fabs(chk[1] - xyd[1]) > 1e-9) return VP_EDEGEN;
    }
    out[0] = x;
    out[1] = y;
    return VP_OK;
}

int vp_camera_ray(const vp_camera_model_t *cam, const double uv[2], double dir[3])
{
    double xd[2], x[2];
    int i;
    if (!cam || !uv || !dir || !(cam->fx > 0) || !(cam->fy > 0)) return VP_EINVAL;
    xd[0] = (uv[0] - cam->cx) / cam->fx;
    xd[1] = (uv[1] - cam->cy) / cam->fy;
    VP_TRY(vp_lens_undistort(cam->dist, xd, x));
    for (i = 0; i < 3; i++) dir[i] = cam->rot[i] * x[0] + cam->rot[3 + i] * x[1] + cam->rot[6 + i];
    return VP_OK;
}

/* Closest approach of the beam o + t d (d unit) and the ray c + s r: t, s and the gap (mm). */
static int vp_rf_closest(const double o[3], const double d[3], const double c[3], const double r[3], double *t, double *s,
                         double *gap)
{
    double w[3], b = vp_dot3(d, r), rr = vp_dot3(r, r), dw, rw, den, p[3], q[3];
    int i;
    for (i = 0; i < 3; i++) w[i] = o[i] - c[i];
    dw = vp_dot3(d, w);
    rw = vp_dot3(r, w);
    den = rr - b * b;
    if (!(den > 1e-12 * rr)) return VP_EDEGEN;   /* the ray runs along the beam */
    *t = (b * rw - rr * dw) / den;
    *s = (rw - b * dw) / den;
    for (i = 0; i < 3; i++) { p[i] = o[i] + *t * d[i]; q[i] = c[i] + *s * r[i]; }
    *gap = vp_dist3(p, q);
    return VP_OK;
}

int vp_rf_distance(const vp_rf_model_t *m, const double uv[2], double *d, int *why, double *gap_px)
{
    double r[3], t, s, gap, tol;
    int rc;
    if (!m || !uv || !d || !why || !isfinite(uv[0]) || !isfinite(uv[1]) || !(m->max_range > m->min_range)) return VP_EINVAL;
    *why = VP_RF_OFF_BEAM;
    if (gap_px) *gap_px = HUGE_VAL;
    rc = vp_camera_ray(&m->cam, uv, r);
    if (rc == VP_EDEGEN) return VP_OK;           /* outside the lens' model: not a reading */
    if (rc != VP_OK) return rc;
    if (vp_rf_closest(m->origin, m->dir, m->cam.pos, r, &t, &s, &gap) != VP_OK || !(s > 0)) return VP_OK;
    /* the gap as the image sees it at the spot's depth s */
    gap = gap * 0.5 * (m->cam.fx + m->cam.fy) / s;
    if (gap_px) *gap_px = gap;
    tol = m->ray_tol_px > 0 ? m->ray_tol_px : 3;
    *d = t;
    if (gap > tol) return VP_OK;
    *why = t < m->min_range || t > m->max_range ? VP_RF_OUT_OF_SPAN : VP_RF_OK;
    return VP_OK;
}

int vp_rf_spot(const vp_rf_model_t *m, double d, double uv[2])
{
    double p[3];
    int i;
    for (i = 0; i < 3; i++) p[i] = m->origin[i] + d * m->dir[i];
    return vp_camera_project(&m->cam, p, uv);
}

int vp_rf_nominal(const vp_camera_model_t *cam, const double laser_offset[3], double min_range, double max_range,
                  vp_rf_model_t *m)
{
    if (!cam || !laser_offset || !m || !(min_range > 0) || !(max_range > min_range)) return VP_EINVAL;
    memset(m, 0, sizeof *m);
    m->cam = *cam;
    memcpy(m->origin, laser_offset, sizeof m->origin);
    m->dir[0] = 1;
    m->min_range = min_range;
    m->max_range = max_range;
    m->ray_tol_px = 3;
    return VP_OK;
}

/* ---- the fit ---- */

typedef struct vp_rf_frame {
    const vp_rf_model_t *start;
    double u1[3], u2[3];         /* across the nominal beam */
    int phase;                   /* 0: Huber's loss; 1: residuals beyond 3 VP_CALIB_HUBER_PX left out */
    int camera_only;             /* the beam held at start's (no spots: a line laser) */
} vp_rf_frame_t;

#define VP_CALIB_CUT_PX (3 * VP_CALIB_HUBER_PX)

/* rotation matrix of rotation vector w (Rodrigues) */
static void vp_rodrigues(const double w[3], double R[9])
{
    double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), a, b, K[9], K2[9];
    int i, j, k;
    if (th < 1e-12) { a = 1; b = 0.5; } else { a = sin(th) / th; b = (1 - cos(th)) / (th * th); }
    K[0] = 0; K[1] = -w[2]; K[2] = w[1];
    K[3] = w[2]; K[4] = 0; K[5] = -w[0];
    K[6] = -w[1]; K[7] = w[0]; K[8] = 0;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            K2[3 * i + j] = 0;
            for (k = 0; k < 3; k++) K2[3 * i + j] += K[3 * i + k] * K[3 * k + j];
        }
    for (i = 0; i < 9; i++) R[i] = (i % 4 == 0 ? 1 : 0) + a * K[i] + b * K2[i];
}

static void vp_rf_build(const vp_rf_frame_t *f, const double q[NP], vp_rf_model_t *m)
{
    double R[9], n;
    int i, j, k;
    *m = *f->start;
    m->cam.fx = q[0]; m->cam.fy = q[1]; m->cam.cx = q[2]; m->cam.cy = q[3];
    for (i = 0; i < 4; i++) m->cam.dist[i] = q[4 + i];
    vp_rodrigues(q + 8, R);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            m->cam.rot[3 * i + j] = 0;
            for (k = 0; k < 3; k++) m->cam.rot[3 * i + j] += R[3 * i + k] * f->start->cam.rot[3 * k + j];
        }
    for (i = 0; i < 3; i++) {
        m->cam.pos[i] = q[11 + i];
        m->origin[i] = f->start->origin[i] + q[14] * f->u1[i] + q[15] * f->u2[i];
        m->dir[i] = f->start->dir[i] + q[16] * f->u1[i] + q[17] * f->u2[i];
    }
    n = vp_norm3(m->dir);
    for (i = 0; i < 3; i++) m->dir[i] /= n;
}

/* The observation's predicted image point; 0 when it has none (behind the camera, beam along the plane). */
static int vp_rf_predict(const vp_rf_model_t *m, const vp_calib_obs_t *o, double uv[2], double *t_out)
{
    if (o->kind == VP_OBS_MARK) return vp_camera_project(&m->cam, o->p, uv);
    {
        double den = vp_dot3(o->n, m->dir), t, p[3];
        int i;
        if (!(fabs(den) > 1e-9)) return 0;
        t = (o->h - vp_dot3(o->n, m->origin)) / den;
        if (t_out) *t_out = t;
        for (i = 0; i < 3; i++) p[i] = m->origin[i] + t * m->dir[i];
        return vp_camera_project(&m->cam, p, uv);
    }
}

/* Huber's loss on an image residual of squared length e2: quadratic up to VP_CALIB_HUBER_PX, then
 * linear (a stray detection, a reflection taken for the mark, pulls no harder than that) */
static double vp_rf_loss(int phase, double e2)
{
    const double c = VP_CALIB_HUBER_PX;
    if (phase) return e2 <= VP_CALIB_CUT_PX * VP_CALIB_CUT_PX ? e2 : VP_CALIB_CUT_PX * VP_CALIB_CUT_PX;
    return e2 <= c * c ? e2 : 2 * c * sqrt(e2) - c * c;
}

/* the weight (square root) of a residual of length e in the normal equations */
static double vp_rf_weight(int phase, double e)
{
    if (phase) return e <= VP_CALIB_CUT_PX ? 1 : 0;
    return e <= VP_CALIB_HUBER_PX ? 1 : sqrt(VP_CALIB_HUBER_PX / e);
}

static double vp_rf_cost(const vp_rf_frame_t *f, const double q[NP], const vp_calib_obs_t *obs, int n)
{
    vp_rf_model_t m;
    double c = 0, uv[2];
    int i;
    vp_rf_build(f, q, &m);
    for (i = 0; i < n; i++) {
        if (!vp_rf_predict(&m, &obs[i], uv, NULL)) return HUGE_VAL;
        c += vp_rf_loss(f->phase, (uv[0] - obs[i].uv[0]) * (uv[0] - obs[i].uv[0]) + (uv[1] - obs[i].uv[1]) * (uv[1] - obs[i].uv[1]));
    }
    return isfinite(c) ? c : HUGE_VAL;
}

/* Cholesky solve of A x = b (A symmetric positive definite, n x n); VP_EDEGEN on a pivot below
 * rel times its diagonal entry. */
static int vp_chol(double A[NP][NP], const double b[NP], double x[NP], double rel)
{
    double L[NP][NP], y[NP];
    int i, j, k;
    for (j = 0; j < NP; j++) {
        double s = A[j][j];
        for (k = 0; k < j; k++) s -= L[j][k] * L[j][k];
        if (!(s > rel * A[j][j]) || !(A[j][j] > 0)) return VP_EDEGEN;
        L[j][j] = sqrt(s);
        for (i = j + 1; i < NP; i++) {
            double t = A[i][j];
            for (k = 0; k < j; k++) t -= L[i][k] * L[j][k];
            L[i][j] = t / L[j][j];
        }
    }
    for (i = 0; i < NP; i++) {
        double s = b[i];
        for (k = 0; k < i; k++) s -= L[i][k] * y[k];
        y[i] = s / L[i][i];
    }
    for (i = NP - 1; i >= 0; i--) {
        double s = y[i];
        for (k = i + 1; k < NP; k++) s -= L[k][i] * x[k];
        x[i] = s / L[i][i];
    }
    return VP_OK;
}

/* J^T J and J^T r by central differences, one observation at a time (no storage for J). */
static int vp_rf_normal(const vp_rf_frame_t *f, const double q[NP], const vp_calib_obs_t *obs, int n, double A[NP][NP],
                        double g[NP])
{
    static const double step[NP] = { 1e-4, 1e-4, 1e-4, 1e-4, 1e-7, 1e-7, 1e-7, 1e-7, 1e-8, 1e-8, 1e-8,
                                     1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-8, 1e-8 };
    vp_rf_model_t m0, mp[NP], mm[NP];
    double qq[NP];
    int i, j, k;
    memset(A, 0, sizeof(double) * NP * NP);
    memset(g, 0, sizeof(double) * NP);
    vp_rf_build(f, q, &m0);
    for (k = 0; k < NP; k++) {
        memcpy(qq, q, sizeof qq);
        qq[k] = q[k] + step[k];
        vp_rf_build(f, qq, &mp[k]);
        qq[k] = q[k] - step[k];
        vp_rf_build(f, qq, &mm[k]);
    }
    for (i = 0; i < n; i++) {
        double uv[2], r[2], J[2][NP], a[2], b[2], e, w;
        if (!vp_rf_predict(&m0, &obs[i], uv, NULL)) return VP_EDEGEN;
        r[0] = uv[0] - obs[i].uv[0];
        r[1] = uv[1] - obs[i].uv[1];
        /* the loss as weighted least squares */
        e = sqrt(r[0] * r[0] + r[1] * r[1]);
        w = vp_rf_weight(f->phase, e);
        for (k = 0; k < NP; k++) {
            if (!vp_rf_predict(&mp[k], &obs[i], a, NULL) || !vp_rf_predict(&mm[k], &obs[i], b, NULL)) return VP_EDEGEN;
            J[0][k] = w * (a[0] - b[0]) / (2 * step[k]);
            J[1][k] = w * (a[1] - b[1]) / (2 * step[k]);
        }
        r[0] *= w;
        r[1] *= w;
        for (j = 0; j < NP; j++) {
            g[j] += J[0][j] * r[0] + J[1][j] * r[1];
            for (k = 0; k <= j; k++) A[j][k] += J[0][j] * J[0][k] + J[1][j] * J[1][k];
        }
    }
    for (j = 0; j < NP; j++)
        for (k = j + 1; k < NP; k++) A[j][k] = A[k][j];
    if (f->camera_only)
        for (j = 14; j < NP; j++) {
            /* the beam's parameters held: no step, a regular system */
            for (k = 0; k < NP; k++) A[j][k] = A[k][j] = 0;
            A[j][j] = 1;
            g[j] = 0;
        }
    return VP_OK;
}

static int vp_rf_fit_do(const vp_calib_obs_t *obs, int n, const vp_rf_model_t *start, vp_rf_model_t *out,
                        vp_rf_fit_report_t *rep, int camera_only)
{
    vp_rf_frame_t f;
    vp_rf_fit_report_t r;
    double q[NP], A[NP][NP], g[NP], dq[NP], qt[NP], cost, lam = 1e-3, a[3] = { 0, 0, 1 };
    int i, k, it, marks = 0, spots = 0, rc;
    if (!obs || !start || !out || n < 1) return VP_EINVAL;
    for (i = 0; i < n; i++) {
        const vp_calib_obs_t *o = &obs[i];
        if (!isfinite(o->uv[0]) || !isfinite(o->uv[1])) return VP_EINVAL;
        if (o->kind == VP_OBS_MARK) {
            if (!isfinite(o->p[0]) || !isfinite(o->p[1]) || !isfinite(o->p[2])) return VP_EINVAL;
            marks++;
        } else if (o->kind == VP_OBS_SPOT) {
            if (!isfinite(o->h) || !(fabs(vp_norm3(o->n) - 1) < 1e-6)) return VP_EINVAL;
            spots++;
        } else return VP_EINVAL;
    }
    if (marks < VP_CALIB_MIN_MARKS || (camera_only ? spots != 0 : spots < VP_CALIB_MIN_SPOTS)) return VP_EINVAL;
    if (!(start->cam.fx > 0) || !(start->cam.fy > 0) || !(fabs(vp_norm3(start->dir) - 1) < 1e-9)) return VP_EINVAL;
    memset(&r, 0, sizeof r);
    r.marks = marks;
    r.spots = spots;
    f.start = start;
    f.camera_only = camera_only;
    if (fabs(start->dir[2]) > 0.9) { a[0] = 1; a[2] = 0; }
    vp_cross3(f.u1, start->dir, a);
    {
        double l = vp_norm3(f.u1);
        for (k = 0; k < 3; k++) f.u1[k] /= l;
    }
    vp_cross3(f.u2, start->dir, f.u1);
    memset(q, 0, sizeof q);
    q[0] = start->cam.fx; q[1] = start->cam.fy; q[2] = start->cam.cx; q[3] = start->cam.cy;
    for (k = 0; k < 4; k++) q[4 + k] = start->cam.dist[k];
    for (k = 0; k < 3; k++) q[11 + k] = start->cam.pos[k];
    cost = vp_rf_cost(&f, q, obs, n);
    if (!isfinite(cost)) return VP_EDEGEN;
    {
        /* the nominal model's plain rms */
        vp_rf_model_t m0;
        double s2 = 0, uv[2];
        vp_rf_build(&f, q, &m0);
        for (i = 0; i < n; i++) {
            vp_rf_predict(&m0, &obs[i], uv, NULL);
            s2 += (uv[0] - obs[i].uv[0]) * (uv[0] - obs[i].uv[0]) + (uv[1] - obs[i].uv[1]) * (uv[1] - obs[i].uv[1]);
        }
        r.start_rms_px = sqrt(s2 / n);
    }
    f.phase = 0;
    for (it = 0; it < 400; it++) {
        double S[NP][NP], gs[NP], d[NP], newcost = HUGE_VAL;
        VP_TRY(vp_rf_normal(&f, q, obs, n, A, g));
        for (k = 0; k < NP; k++) d[k] = A[k][k] > 0 ? sqrt(A[k][k]) : 0;
        /* every parameter must be fixed by the observations: the scaled normal matrix is regular */
        for (i = 0; i < NP; i++) {
            if (!(d[i] > 0)) return VP_EDEGEN;
            for (k = 0; k < NP; k++) S[i][k] = A[i][k] / (d[i] * d[k]);
            gs[i] = -g[i] / d[i];
        }
        rc = vp_chol(S, gs, dq, 1e-13);
        if (rc != VP_OK) return VP_EDEGEN;
        for (;;) {
            for (i = 0; i < NP; i++) {
                for (k = 0; k < NP; k++) S[i][k] = A[i][k] / (d[i] * d[k]);
                S[i][i] *= 1 + lam;
            }
            if (vp_chol(S, gs, dq, 0) == VP_OK) {
                for (k = 0; k < NP; k++) qt[k] = q[k] + dq[k] / d[k];
                newcost = vp_rf_cost(&f, qt, obs, n);
            }
            if (newcost < cost) break;
            lam *= 10;
            if (lam > 1e12) break;
        }
        r.iterations = it + 1;
        if (newcost < cost) {
            double rel = (cost - newcost) / cost, stepn = 0;
            for (k = 0; k < NP; k++) stepn += dq[k] * dq[k];
            memcpy(q, qt, sizeof q);
            cost = newcost;
            lam = lam > 1e-9 ? lam / 10 : lam;
            if (!(rel < 1e-12 || stepn < 1e-20)) continue;
        }
        /* converged; with Huber's loss any residual beyond the cut: again without those */
        if (f.phase == 0) {
            vp_rf_model_t m1;
            double uv[2];
            int far = 0;
            vp_rf_build(&f, q, &m1);
            for (i = 0; i < n && !far; i++)
                far = vp_rf_predict(&m1, &obs[i], uv, NULL) &&
                      hypot(uv[0] - obs[i].uv[0], uv[1] - obs[i].uv[1]) > VP_CALIB_CUT_PX;
            if (far) {
                f.phase = 1;
                lam = 1e-3;
                cost = vp_rf_cost(&f, q, obs, n);
                continue;
            }
        }
        break;
    }
    vp_rf_build(&f, q, out);
    {
        /* origin: the beam's point nearest the nominal origin (the kinematics' laser origin) */
        double w[3], t;
        for (k = 0; k < 3; k++) w[k] = start->origin[k] - out->origin[k];
        t = vp_dot3(w, out->dir);
        for (k = 0; k < 3; k++) out->origin[k] += t * out->dir[k];
    }
    /* residuals; the span the spots cover */
    {
        double s2 = 0, m2 = 0, sp2 = 0, mm2 = 0, lo = HUGE_VAL, hi = -HUGE_VAL;
        for (i = 0; i < n; i++) {
            double uv[2], t = 0, e2, e;
            vp_rf_predict(out, &obs[i], uv, &t);
            e2 = (uv[0] - obs[i].uv[0]) * (uv[0] - obs[i].uv[0]) + (uv[1] - obs[i].uv[1]) * (uv[1] - obs[i].uv[1]);
            e = sqrt(e2);
            s2 += e2;
            if (e > r.max_px) r.max_px = e;
            if (e > VP_CALIB_HUBER_PX) r.outliers++;
            if (e > VP_CALIB_CUT_PX) r.strays++;
            if (obs[i].kind == VP_OBS_MARK) m2 += e2;
            else {
                double dm = 0;
                int why;
                vp_rf_model_t wide = *out;
                sp2 += e2;
                if (t < lo) lo = t;
                if (t > hi) hi = t;
                wide.min_range = -1e9;
                wide.max_range = 1e9;
                wide.ray_tol_px = 1e9;
                if (vp_rf_distance(&wide, obs[i].uv, &dm, &why, NULL) == VP_OK && why == VP_RF_OK) {
                    mm2 += (dm - t) * (dm - t);
                    if (fabs(dm - t) > r.spot_max_mm) r.spot_max_mm = fabs(dm - t);
                }
            }
        }
        r.rms_px = sqrt(s2 / n);
        r.mark_rms_px = sqrt(m2 / marks);
        r.spot_rms_px = spots ? sqrt(sp2 / spots) : 0;
        r.spot_rms_mm = spots ? sqrt(mm2 / spots) : 0;
        r.span[0] = spots ? lo : 0;
        r.span[1] = spots ? hi : 0;
    }
    /* a fit that did not converge leaves large residuals everywhere; a few gross ones (a mark or
     * a spot detected far from where it was: left out of the last round, VP_CALIB_CUT_PX) do not
     * make it one, as long as they are at most 1 in 10 of the observations (the report says how
     * far it got) */
    if (!isfinite(r.rms_px) || (!(r.rms_px < 10) && 10 * r.strays > n)) {
        if (rep) *rep = r;
        return VP_EDEGEN;
    }
    if (camera_only) {
        /* the beam and its span as given */
        if (rep) *rep = r;
        return VP_OK;
    }
    if (!(r.span[1] > r.span[0]) || !(r.span[0] > 0)) return VP_EDEGEN;
    /* the span, widened by the spot's noise (0.5 mm and 0.2 %): the farthest station reads on
     * either side of its distance */
    out->min_range = r.span[0] - 0.5 - 0.002 * r.span[0];
    out->max_range = r.span[1] + 0.5 + 0.002 * r.span[1];
    if (out->min_range < 0.5 * r.span[0]) out->min_range = 0.5 * r.span[0];
    if (!(out->ray_tol_px > 0)) out->ray_tol_px = 3;
    if (rep) *rep = r;
    return VP_OK;
}

int vp_rf_fit(const vp_calib_obs_t *obs, int n, const vp_rf_model_t *start, vp_rf_model_t *out, vp_rf_fit_report_t *rep)
{
    return vp_rf_fit_do(obs, n, start, out, rep, 0);
}

int vp_rf_fit_camera(const vp_calib_obs_t *obs, int n, const vp_rf_model_t *start, vp_rf_model_t *out,
                     vp_rf_fit_report_t *rep)
{
    return vp_rf_fit_do(obs, n, start, out, rep, 1);
}
