/* vp_laser — see vp_laser.h. */
#include <math.h>
#include <string.h>
#include "vp_laser.h"
#include "vp_status.h"
#include "vp_vec3.h"

/* ---- camera ---- */

static int vp_unit(double v[3])
{
    double n = vp_norm3(v);
    if (!(n > 1e-12) || !isfinite(n)) return 0;
    v[0] /= n; v[1] /= n; v[2] /= n;
    return 1;
}

int vp_camera_look_at(vp_camera_model_t *c, const double look[3], const double up[3])
{
    double x[3], y[3], z[3];
    int i;
    for (i = 0; i < 3; i++) z[i] = look[i] - c->pos[i];
    if (!vp_unit(z)) return VP_EINVAL;
    vp_cross3(x, z, up);
    if (!vp_unit(x)) return VP_EINVAL;
    vp_cross3(y, z, x);
    for (i = 0; i < 3; i++) { c->rot[i] = x[i]; c->rot[3 + i] = y[i]; c->rot[6 + i] = z[i]; }
    return VP_OK;
}

int vp_camera_project(const vp_camera_model_t *c, const double p[3], double uv[2])
{
    double q[3], pc[3];
    int i;
    for (i = 0; i < 3; i++) q[i] = p[i] - c->pos[i];
    for (i = 0; i < 3; i++) pc[i] = c->rot[3 * i] * q[0] + c->rot[3 * i + 1] * q[1] + c->rot[3 * i + 2] * q[2];
    if (!(pc[2] > 1e-9)) return 0;
    if (c->dist[0] == 0 && c->dist[1] == 0 && c->dist[2] == 0 && c->dist[3] == 0) {
        uv[0] = c->fx * pc[0] / pc[2] + c->cx;
        uv[1] = c->fy * pc[1] / pc[2] + c->cy;
        return 1;
    }
    {
        const double *k = c->dist, x = pc[0] / pc[2], y = pc[1] / pc[2], r2 = x * x + y * y;
        double radial = 1 + k[0] * r2 + k[1] * r2 * r2;
        uv[0] = c->fx * (x * radial + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x)) + c->cx;
        uv[1] = c->fy * (y * radial + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y) + c->cy;
    }
    return 1;
}

/* ---- the triangulation model ---- */

double vp_tri_eval(const vp_tri_model_t *m, double s, double *dd_ds)
{
    double den = 1 + m->c * s;
    if (dd_ds) *dd_ds = fabs((m->b - m->c * m->a) / (den * den));
    return (m->a + m->b * s) / den;
}

double vp_tri_s(const vp_tri_model_t *m, double d) { return (m->a - d) / (d * m->c - m->b); }

int vp_tri_distance(const vp_tri_model_t *m, const double uv[2], double *d)
{
    double du = uv[0] - m->p0[0], dv = uv[1] - m->p0[1];
    double s = du * m->e[0] + dv * m->e[1], off = fabs(du * m->e[1] - dv * m->e[0]);
    double smin = vp_tri_s(m, m->min_range), dist;
    if (!isfinite(s)) return VP_EINVAL;
    if (m->line_tol > 0 && off > m->line_tol) return VP_ERANGE;
    /* the branch of the hyperbola the beam lives on: same side of the pole as min_range */
    if ((1 + m->c * s) * (1 + m->c * smin) <= 0) return VP_ERANGE;
    dist = vp_tri_eval(m, s, NULL);
    if (!isfinite(dist) || dist < m->min_range || (m->max_range > 0 && dist > m->max_range)) return VP_ERANGE;
    *d = dist;
    return VP_OK;
}

/* 3x3 linear solve with partial pivoting; VP_EDEGEN when singular. */
static int vp_solve3(double A[3][3], double b[3], double x[3])
{
    int i, j, k, p;
    for (k = 0; k < 3; k++) {
        p = k;
        for (i = k + 1; i < 3; i++) if (fabs(A[i][k]) > fabs(A[p][k])) p = i;
        if (!(fabs(A[p][k]) > 1e-300)) return VP_EDEGEN;
        if (p != k) {
            double t;
            for (j = 0; j < 3; j++) { t = A[k][j]; A[k][j] = A[p][j]; A[p][j] = t; }
            t = b[k]; b[k] = b[p]; b[p] = t;
        }
        for (i = k + 1; i < 3; i++) {
            double f = A[i][k] / A[k][k];
            for (j = k; j < 3; j++) A[i][j] -= f * A[k][j];
            b[i] -= f * b[k];
        }
    }
    for (i = 2; i >= 0; i--) {
        double s = b[i];
        for (j = i + 1; j < 3; j++) s -= A[i][j] * x[j];
        x[i] = s / A[i][i];
        if (!isfinite(x[i])) return VP_EDEGEN;
    }
    return VP_OK;
}

/* Visible span of s on the line inside the frame shrunk by margin px. */
static int vp_tri_span(const vp_tri_model_t *m, int w, int h, double margin, double *slo, double *shi)
{
    double lo = -HUGE_VAL, hi = HUGE_VAL, bmin[2] = { margin, margin }, bmax[2] = { w - 1 - margin, h - 1 - margin };
    int k;
    for (k = 0; k < 2; k++) {
        if (fabs(m->e[k]) < 1e-12) {
            if (m->p0[k] < bmin[k] || m->p0[k] > bmax[k]) return 0;
            continue;
        }
        {
            double s1 = (bmin[k] - m->p0[k]) / m->e[k], s2 = (bmax[k] - m->p0[k]) / m->e[k];
            if (s1 > s2) { double t = s1; s1 = s2; s2 = t; }
            if (s1 > lo) lo = s1;
            if (s2 < hi) hi = s2;
        }
    }
    *slo = lo;
    *shi = hi;
    return lo < hi;
}

/* Range limits from the frame: the distances where the spot enters and leaves it. */
static void vp_tri_clip_range(vp_tri_model_t *m, int w, int h, double min_range, double max_range)
{
    double slo, shi, dlo, dhi, pole;
    m->min_range = min_range;
    m->max_range = max_range;
    if (!vp_tri_span(m, w, h, 4, &slo, &shi)) return;
    pole = m->c != 0 ? -1 / m->c : HUGE_VAL;   /* s of the vanishing point (d -> infinity) */
    dlo = vp_tri_eval(m, slo, NULL);
    if (pole > slo && pole < shi) dhi = HUGE_VAL;
    else dhi = vp_tri_eval(m, shi, NULL);
    if (dlo > dhi) { double t = dlo; dlo = dhi; dhi = t; }
    if (dlo > m->min_range) m->min_range = dlo;
    if (isfinite(dhi) && (m->max_range <= 0 || dhi < m->max_range)) m->max_range = dhi;
}

int vp_tri_from_geometry(const vp_camera_model_t *cam, const double lo[3], double min_range, double max_range,
                         vp_tri_model_t *m)
{
    double d[3], uv[3][2], s[3], A[3][3], b[3], x[3], len, d0, d1;
    int i;
    if (!cam || !lo || !m || !(min_range > 0) || max_range < 0 || (max_range > 0 && max_range <= min_range)) return VP_EINVAL;
    memset(m, 0, sizeof *m);
    d0 = min_range;
    d1 = max_range > 0 ? max_range : 10 * min_range;
    d[0] = d0; d[1] = 0.5 * (d0 + d1); d[2] = d1;
    for (i = 0; i < 3; i++) {
        double p[3] = { lo[0] + d[i], lo[1], lo[2] };
        if (!vp_camera_project(cam, p, uv[i])) return VP_ERANGE;
    }
    m->p0[0] = uv[0][0];
    m->p0[1] = uv[0][1];
    m->e[0] = uv[2][0] - uv[0][0];
    m->e[1] = uv[2][1] - uv[0][1];
    len = sqrt(m->e[0] * m->e[0] + m->e[1] * m->e[1]);
    if (!(len > 1e-9)) return VP_EDEGEN;       /* the camera looks along the beam */
    m->e[0] /= len;
    m->e[1] /= len;
    for (i = 0; i < 3; i++) {
        s[i] = (uv[i][0] - m->p0[0]) * m->e[0] + (uv[i][1] - m->p0[1]) * m->e[1];
        A[i][0] = 1; A[i][1] = s[i]; A[i][2] = -s[i] * d[i];
        b[i] = d[i];
    }
    VP_TRY(vp_solve3(A, b, x));
    m->a = x[0]; m->b = x[1]; m->c = x[2];
    m->line_tol = 3;
    vp_tri_clip_range(m, cam->width, cam->height, min_range, max_range);
    return VP_OK;
}

int vp_tri_fit(const double (*uv)[2], const double *d, int n, int width, int height, vp_tri_model_t *m,
               vp_tri_fit_report_t *rep)
{
    double mu[2] = { 0, 0 }, sxx = 0, syy = 0, sxy = 0, th, lmin, cs = 0, S = 0, D = 0, p[3], lam = 1e-3;
    double dmin = HUGE_VAL, dmax = -HUGE_VAL, sse, rms, mx;
    int i, it;
    if (!uv || !d || !m || n < 4) return VP_EINVAL;
    for (i = 0; i < n; i++) {
        if (!isfinite(uv[i][0]) || !isfinite(uv[i][1]) || !(d[i] > 0) || !isfinite(d[i])) return VP_EINVAL;
        mu[0] += uv[i][0] / n;
        mu[1] += uv[i][1] / n;
    }
    for (i = 0; i < n; i++) {
        double x = uv[i][0] - mu[0], y = uv[i][1] - mu[1];
        sxx += x * x; syy += y * y; sxy += x * y;
        if (d[i] < dmin) dmin = d[i];
        if (d[i] > dmax) dmax = d[i];
    }
    if (!(sxx + syy > 1e-6)) return VP_EDEGEN;
    memset(m, 0, sizeof *m);
    th = 0.5 * atan2(2 * sxy, sxx - syy);
    m->e[0] = cos(th);
    m->e[1] = sin(th);
    m->p0[0] = mu[0];
    m->p0[1] = mu[1];
    lmin = 0.5 * (sxx + syy) - sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    /* s grows with d */
    for (i = 0; i < n; i++) cs += ((uv[i][0] - mu[0]) * m->e[0] + (uv[i][1] - mu[1]) * m->e[1]) * (d[i] - 0.5 * (dmin + dmax));
    if (cs < 0) { m->e[0] = -m->e[0]; m->e[1] = -m->e[1]; }
    for (i = 0; i < n; i++) {
        double s = (uv[i][0] - mu[0]) * m->e[0] + (uv[i][1] - mu[1]) * m->e[1];
        if (fabs(s) > S) S = fabs(s);
        if (d[i] > D) D = d[i];
    }
    /* linear start in scaled units: d/D = (a' + b' s/S) / (1 + c' s/S) */
    {
        double A[3][3], b[3];
        memset(A, 0, sizeof A);
        memset(b, 0, sizeof b);
        for (i = 0; i < n; i++) {
            double s = ((uv[i][0] - mu[0]) * m->e[0] + (uv[i][1] - mu[1]) * m->e[1]) / S, dd = d[i] / D;
            double r[3] = { 1, s, -s * dd };
            int j, k;
            for (j = 0; j < 3; j++) { for (k = 0; k < 3; k++) A[j][k] += r[j] * r[k]; b[j] += r[j] * dd; }
        }
        VP_TRY(vp_solve3(A, b, p));
    }
    /* Levenberg-Marquardt on the distance residuals */
    for (it = 0; it < 50; it++) {
        double A[3][3], g[3], q[3], e0 = 0, e1 = 0, Ad[3][3];
        int j, k;
        memset(A, 0, sizeof A);
        memset(g, 0, sizeof g);
        for (i = 0; i < n; i++) {
            double s = ((uv[i][0] - mu[0]) * m->e[0] + (uv[i][1] - mu[1]) * m->e[1]) / S, dd = d[i] / D;
            double den = 1 + p[2] * s, f = (p[0] + p[1] * s) / den, r = dd - f;
            double J[3] = { 1 / den, s / den, -s * f / den };
            e0 += r * r;
            for (j = 0; j < 3; j++) { for (k = 0; k < 3; k++) A[j][k] += J[j] * J[k]; g[j] += J[j] * r; }
        }
        memcpy(Ad, A, sizeof A);
        for (j = 0; j < 3; j++) Ad[j][j] *= 1 + lam;
        {
            double gg[3] = { g[0], g[1], g[2] };
            if (vp_solve3(Ad, gg, q) != VP_OK) break;
        }
        for (i = 0; i < n; i++) {
            double s = ((uv[i][0] - mu[0]) * m->e[0] + (uv[i][1] - mu[1]) * m->e[1]) / S, dd = d[i] / D;
            double r = dd - (p[0] + q[0] + (p[1] + q[1]) * s) / (1 + (p[2] + q[2]) * s);
            e1 += r * r;
        }
        if (e1 < e0) {
            for (j = 0; j < 3; j++) p[j] += q[j];
            lam *= 0.3;
            if (e0 - e1 < 1e-15 * e0) break;
        } else lam *= 10;
    }
    m->a = p[0] * D;
    m->b = p[1] * D / S;
    m->c = p[2] / S;
    sse = 0;
    mx = 0;
    for (i = 0; i < n; i++) {
        double s = (uv[i][0] - mu[0]) * m->e[0] + (uv[i][1] - mu[1]) * m->e[1], r = d[i] - vp_tri_eval(m, s, NULL);
        if (!isfinite(r)) return VP_EDEGEN;
        sse += r * r;
        if (fabs(r) > mx) mx = fabs(r);
    }
    rms = sqrt(sse / n);
    m->line_tol = 3 + 5 * sqrt(lmin > 0 ? lmin / n : 0);
    m->min_range = dmin;
    m->max_range = dmax;
    (void)width;
    (void)height;
    if (rep) {
        rep->n = n;
        rep->rms_mm = rms;
        rep->max_mm = mx;
        rep->line_rms_px = sqrt(lmin > 0 ? lmin / n : 0);
    }
    return VP_OK;
}

/* ---- spot detection ---- */

static double vp_spot_bg(const vp_spot_ws_t *ws, int nbx, int nby, int B, double x, double y)
{
    double fx = (x + 0.5) / B - 0.5, fy = (y + 0.5) / B - 0.5, tx, ty;
    int x0, y0, x1, y1;
    if (fx < 0) fx = 0;
    if (fy < 0) fy = 0;
    if (fx > nbx - 1) fx = nbx - 1;
    if (fy > nby - 1) fy = nby - 1;
    x0 = (int)fx; y0 = (int)fy;
    x1 = x0 + 1 < nbx ? x0 + 1 : x0;
    y1 = y0 + 1 < nby ? y0 + 1 : y0;
    tx = fx - x0; ty = fy - y0;
    return (1 - ty) * ((1 - tx) * ws->bg[y0 * nbx + x0] + tx * ws->bg[y0 * nbx + x1]) +
           ty * ((1 - tx) * ws->bg[y1 * nbx + x0] + tx * ws->bg[y1 * nbx + x1]);
}

/* residuals of row y, full width */
static void vp_spot_row(const vp_frame_t *f, const vp_spot_ws_t *ws, int nbx, int nby, int B, int y, float *out)
{
    double fy = (y + 0.5) / B - 0.5, ty;
    int y0, y1, x, bx;
    float rb[VP_SPOT_MAX_W / 8 + 3];
    if (fy < 0) fy = 0;
    if (fy > nby - 1) fy = nby - 1;
    y0 = (int)fy;
    y1 = y0 + 1 < nby ? y0 + 1 : y0;
    ty = fy - y0;
    (void)B;
    for (bx = 0; bx < nbx; bx++) rb[bx] = (float)((1 - ty) * ws->bg[y0 * nbx + bx] + ty * ws->bg[y1 * nbx + bx]);
    rb[nbx] = rb[nbx - 1];
    {
        const uint8_t *p = f->data + (size_t)y * (size_t)f->stride;
        const int st = f->step;
        for (x = 0; x < f->width; x++) {
            int x0 = ws->bx[x];
            out[x] = (float)p[(size_t)x * st] - (rb[x0] + ws->tx[x] * (rb[x0 + 1] - rb[x0]));
        }
    }
}

/* per-column interpolation between block centres, shared by every row */
static void vp_spot_cols(vp_spot_ws_t *ws, int w, int nbx, int B)
{
    int x;
    for (x = 0; x < w; x++) {
        double fx = (x + 0.5) / B - 0.5;
        int x0;
        if (fx < 0) fx = 0;
        if (fx > nbx - 1) fx = nbx - 1;
        x0 = (int)fx;
        ws->bx[x] = (int16_t)x0;
        ws->tx[x] = (float)(fx - x0);
    }
}

/* x interval of row y within `band` px of the model's line ([0, w-1] without a band). */
static int vp_spot_band(const vp_tri_model_t *m, double band, int w, int y, int *x0, int *x1)
{
    /* |(x - p0x) e_y - (y - p0y) e_x| <= band */
    double ex, ey, c, lo, hi;
    *x0 = 1;
    *x1 = w - 2;
    if (!m || band <= 0) return 1;
    ex = m->e[0]; ey = m->e[1];
    c = (y - m->p0[1]) * ex;
    if (fabs(ey) < 1e-9) return fabs(c) <= band;
    lo = m->p0[0] + (c - band) / ey;
    hi = m->p0[0] + (c + band) / ey;
    if (lo > hi) { double t = lo; lo = hi; hi = t; }
    /* a line nearly along the rows puts lo and hi far out: the band misses the row's pixels, or
     * the bounds land within them (never cast from out of an int's range) */
    if (!(lo <= *x1) || !(hi >= *x0)) return 0;
    if (lo > *x0) *x0 = (int)ceil(lo);
    if (hi < *x1) *x1 = (int)floor(hi);
    return *x0 <= *x1;
}

/* Largest score in the band, outside the box ex (ex[0] > ex[2]: no box). The score is the 3x3
 * mean residual without the brightest of the nine: a lone hot pixel scores like background. */
static double vp_spot_scan(const vp_frame_t *f, vp_spot_ws_t *ws, int nbx, int nby, int B, const vp_tri_model_t *m,
                           double band, const int ex[4], int *xm, int *ym)
{
    float *r[3], *col = ws->rows[3], *cmax = ws->rows[4];
    double best = -HUGE_VAL;
    int y, x, w = f->width, h = f->height;
    r[0] = ws->rows[0]; r[1] = ws->rows[1]; r[2] = ws->rows[2];
    vp_spot_row(f, ws, nbx, nby, B, 0, r[0]);
    vp_spot_row(f, ws, nbx, nby, B, 1, r[1]);
    for (y = 1; y < h - 1; y++) {
        int x0, x1;
        float *t;
        vp_spot_row(f, ws, nbx, nby, B, y + 1, r[2]);
        if (vp_spot_band(m, band, w, y, &x0, &x1)) {
            for (x = x0 - 1; x <= x1 + 1; x++) {
                float a = r[0][x] > r[1][x] ? r[0][x] : r[1][x];
                col[x] = r[0][x] + r[1][x] + r[2][x];
                cmax[x] = a > r[2][x] ? a : r[2][x];
            }
            for (x = x0; x <= x1; x++) {
                float mx = cmax[x - 1] > cmax[x] ? cmax[x - 1] : cmax[x];
                double s;
                if (cmax[x + 1] > mx) mx = cmax[x + 1];
                s = (col[x - 1] + col[x] + col[x + 1] - mx) * (1.0 / 8);
                if (s <= best) continue;
                if (x >= ex[0] && x <= ex[2] && y >= ex[1] && y <= ex[3]) continue;
                best = s;
                *xm = x;
                *ym = y;
            }
        }
        t = r[0]; r[0] = r[1]; r[1] = r[2]; r[2] = t;
    }
    return best;
}

typedef struct vp_resfn {
    const vp_frame_t *f;
    const vp_spot_ws_t *ws;
    int nbx, nby, B, plane;
    double p0, gx, gy, xc, yc;   /* plane background p0 + gx (x - xc) + gy (y - yc) */
} vp_resfn_t;

static double vp_res(const vp_resfn_t *r, int x, int y)
{
    double b = r->plane ? r->p0 + r->gx * (x - r->xc) + r->gy * (y - r->yc) : vp_spot_bg(r->ws, r->nbx, r->nby, r->B, x, y);
    return VP_FRAME_PIX(r->f, x, y) - b;
}

/* Region of residuals above thr connected to (x0,y0) inside the box of half-size R around
 * (xm,ym); centroid weighted by residual - thr. 1 if it reaches the box or the frame border. */
static int vp_spot_flood(const vp_resfn_t *rf, vp_spot_ws_t *ws, int xm, int ym, int R, int x0, int y0, double thr,
                         double *u, double *v, int *area, int bb[4])
{
    static const int nb[8][2] = { { 1, 0 }, { -1, 0 }, { 0, 1 }, { 0, -1 }, { 1, 1 }, { 1, -1 }, { -1, 1 }, { -1, -1 } };
    const int w = rf->f->width, h = rf->f->height, side = 2 * R + 1;
    double sw = 0, su = 0, sv = 0;
    int sp = 0;
    memset(ws->mark, 0, (size_t)side * side);
    *area = 0;
    bb[0] = bb[2] = x0;
    bb[1] = bb[3] = y0;
    ws->stack[sp][0] = (int16_t)x0;
    ws->stack[sp][1] = (int16_t)y0;
    sp++;
    ws->mark[(y0 - ym + R) * side + (x0 - xm + R)] = 1;
    while (sp > 0) {
        int px, py, k;
        double r;
        sp--;
        px = ws->stack[sp][0];
        py = ws->stack[sp][1];
        if (px - xm >= R || xm - px >= R || py - ym >= R || ym - py >= R || px == 0 || py == 0 || px == w - 1 || py == h - 1)
            return 1;
        r = vp_res(rf, px, py);
        (*area)++;
        sw += r - thr;
        su += (r - thr) * px;
        sv += (r - thr) * py;
        if (px < bb[0]) bb[0] = px;
        if (py < bb[1]) bb[1] = py;
        if (px > bb[2]) bb[2] = px;
        if (py > bb[3]) bb[3] = py;
        for (k = 0; k < 8; k++) {
            int qx = px + nb[k][0], qy = py + nb[k][1], mi = (qy - ym + R) * side + (qx - xm + R);
            if (ws->mark[mi]) continue;
            ws->mark[mi] = 1;
            if (vp_res(rf, qx, qy) > thr) {
                ws->stack[sp][0] = (int16_t)qx;
                ws->stack[sp][1] = (int16_t)qy;
                sp++;
            }
        }
    }
    if (!(sw > 0)) { *area = 0; return 0; }
    *u = su / sw;
    *v = sv / sw;
    return 0;
}

/* Least-squares plane through the ring 3..9 px outside the spot's box, one pass dropping
 * pixels more than 3 sigma off; sets rf to plane mode. */
static int vp_spot_plane(vp_resfn_t *rf, const int bb[4], double sigma)
{
    const vp_frame_t *f = rf->f;
    int pass, x, y, xa = bb[0] - 9, xb = bb[2] + 9, ya = bb[1] - 9, yb = bb[3] + 9;
    double p[3] = { 0, 0, 0 };
    if (xa < 0) xa = 0;
    if (ya < 0) ya = 0;
    if (xb > f->width - 1) xb = f->width - 1;
    if (yb > f->height - 1) yb = f->height - 1;
    rf->xc = 0.5 * (bb[0] + bb[2]);
    rf->yc = 0.5 * (bb[1] + bb[3]);
    for (pass = 0; pass < 2; pass++) {
        double A[3][3], b[3];
        int n = 0;
        memset(A, 0, sizeof A);
        memset(b, 0, sizeof b);
        for (y = ya; y <= yb; y++)
            for (x = xa; x <= xb; x++) {
                double r[3], val = VP_FRAME_PIX(f, x, y);
                int j, k;
                if (x >= bb[0] - 3 && x <= bb[2] + 3 && y >= bb[1] - 3 && y <= bb[3] + 3) continue;
                r[0] = 1; r[1] = x - rf->xc; r[2] = y - rf->yc;
                if (pass && fabs(val - (p[0] + p[1] * r[1] + p[2] * r[2])) > 3 * sigma) continue;
                for (j = 0; j < 3; j++) { for (k = 0; k < 3; k++) A[j][k] += r[j] * r[k]; b[j] += r[j] * val; }
                n++;
            }
        if (n < 12 || vp_solve3(A, b, p) != VP_OK) return VP_EDEGEN;
    }
    rf->p0 = p[0];
    rf->gx = p[1];
    rf->gy = p[2];
    rf->plane = 1;
    return VP_OK;
}

int vp_spot_find(const vp_frame_t *f, const vp_spot_config_t *cfg0, const vp_tri_model_t *model, vp_spot_ws_t *ws,
                 vp_spot_t *out)
{
    vp_spot_config_t c;
    int w, h, B, nbx, nby, bx, by, x, y, xm = 0, ym = 0, R, x0, y0, i;
    vp_resfn_t rf;
    int none[4] = { 1, 1, 0, 0 }, ex[4], bb[4];
    unsigned hist[2048];
    double sigma, S1, S2, peak, thr, thr_det, half;
    if (!f || !f->data || !ws || !out || f->width < 8 || f->height < 8 || f->width > VP_SPOT_MAX_W || f->step < 1 ||
        f->step > 4 || f->height > VP_SPOT_MAX_H || f->stride < f->width * f->step) return VP_EINVAL;
    memset(&c, 0, sizeof c);
    if (cfg0) c = *cfg0;
    /* a configuration out of its range is refused (0 is each field's default) */
    if (c.block < 0 || c.block > VP_SPOT_MAX_W || !(c.percentile >= 0 && c.percentile <= 1) ||
        !(c.rel_thresh >= 0 && c.rel_thresh <= 1) || !(c.min_snr >= 0) || !isfinite(c.min_snr) || !(c.min_peak >= 0) ||
        !isfinite(c.min_peak) || !(c.second_ratio >= 0) || !isfinite(c.second_ratio) || c.max_radius < 0 ||
        !(c.band >= 0) || !isfinite(c.band))
        return VP_EINVAL;
    memset(out, 0, sizeof *out);
    if (c.block == 0) c.block = 16;
    if (c.percentile == 0) c.percentile = 0.3;
    if (c.min_snr == 0) c.min_snr = 10;
    if (c.min_peak == 0) c.min_peak = 8;
    if (c.rel_thresh == 0) c.rel_thresh = 0.3;
    if (c.second_ratio == 0) c.second_ratio = 0.35;
    if (c.max_radius == 0) c.max_radius = 16;
    if (c.max_radius > VP_SPOT_MAX_R) c.max_radius = VP_SPOT_MAX_R;
    w = f->width;
    h = f->height;
    B = c.block;
    while ((size_t)((w + B - 1) / B) * (size_t)((h + B - 1) / B) > VP_SPOT_MAX_BLOCKS || (w + B - 1) / B > VP_SPOT_MAX_W / 8) B++;
    nbx = (w + B - 1) / B;
    nby = (h + B - 1) / B;

    /* background: a low percentile of each block (the spot is a small part of a block) */
    for (by = 0; by < nby; by++)
        for (bx = 0; bx < nbx; bx++) {
            unsigned hb[256], n = 0, need, acc = 0;
            int v = 0, xe = (bx + 1) * B < w ? (bx + 1) * B : w, ye = (by + 1) * B < h ? (by + 1) * B : h;
            memset(hb, 0, sizeof hb);
            for (y = by * B; y < ye; y++)
                for (x = bx * B; x < xe; x++) { hb[VP_FRAME_PIX(f, x, y)]++; n++; }
            need = (unsigned)(c.percentile * n);
            for (v = 0; v < 255; v++) { acc += hb[v]; if (acc > need) break; }
            ws->bg[by * nbx + bx] = (float)v;
        }
    vp_spot_cols(ws, w, nbx, B);
    /* noise: median absolute deviation of the residuals on a 3x3 sub-grid */
    memset(hist, 0, sizeof hist);
    {
        unsigned n = 0, need, acc = 0;
        int med = 0, k;
        for (y = 1; y < h; y += 3) {
            vp_spot_row(f, ws, nbx, nby, B, y, ws->rows[0]);
            for (x = 1; x < w; x += 3) {
                double r = ws->rows[0][x];
                int bin = (int)floor(r * 4) + 1024;
                if (bin < 0) bin = 0;
                if (bin > 2047) bin = 2047;
                hist[bin]++;
                n++;
            }
        }
        need = n / 2;
        for (med = 0; med < 2047; med++) { acc += hist[med]; if (acc > need) break; }
        acc = hist[med];
        for (k = 1; acc <= need && k < 2048; k++) {
            if (med - k >= 0) acc += hist[med - k];
            if (med + k < 2048) acc += hist[med + k];
        }
        sigma = 1.4826 * (k - 0.5) / 4;
        if (sigma < 0.5) sigma = 0.5;
    }
    out->noise = sigma;

    /* the strongest smoothed peak */
    S1 = vp_spot_scan(f, ws, nbx, nby, B, model, c.band, none, &xm, &ym);
    thr_det = c.min_snr * sigma / 3;      /* the score averages 8 pixels: about a third of the noise */
    if (thr_det < c.min_peak) thr_det = c.min_peak;
    out->snr = S1 / (sigma / 3);
    if (!(S1 >= thr_det)) { out->result = VP_SPOT_NONE; return VP_OK; }

    /* the raw peak next to it, and the region above a fraction of it (block background) */
    rf.f = f; rf.ws = ws; rf.nbx = nbx; rf.nby = nby; rf.B = B; rf.plane = 0;
    peak = -HUGE_VAL;
    x0 = xm; y0 = ym;
    for (y = ym - 1; y <= ym + 1; y++)
        for (x = xm - 1; x <= xm + 1; x++) {
            double r = vp_res(&rf, x, y);
            if (r > peak) { peak = r; x0 = x; y0 = y; }
        }
    thr = c.rel_thresh * peak;
    if (thr < 3 * sigma) thr = 3 * sigma;
    R = c.max_radius;
    if (vp_spot_flood(&rf, ws, xm, ym, R, x0, y0, thr, &out->u, &out->v, &out->area, bb)) {
        out->result = VP_SPOT_TOO_BIG;
        return VP_OK;
    }
    /* then the local background: a plane through the ring around the spot, and the region again */
    if (vp_spot_plane(&rf, bb, sigma) == VP_OK) {
        peak = -HUGE_VAL;
        for (y = bb[1]; y <= bb[3]; y++)
            for (x = bb[0]; x <= bb[2]; x++) {
                double r = vp_res(&rf, x, y);
                if (r > peak) { peak = r; x0 = x; y0 = y; }
            }
        thr = c.rel_thresh * peak;
        if (thr < 3 * sigma) thr = 3 * sigma;
        if (vp_spot_flood(&rf, ws, xm, ym, R, x0, y0, thr, &out->u, &out->v, &out->area, bb)) {
            out->result = VP_SPOT_TOO_BIG;
            return VP_OK;
        }
    }
    out->peak = peak;
    if (out->area == 0) { out->result = VP_SPOT_NONE; return VP_OK; }

    /* any other peak outside the spot and its halo */
    half = 0.5 * ((bb[2] - bb[0]) > (bb[3] - bb[1]) ? (bb[2] - bb[0]) : (bb[3] - bb[1]));
    i = (int)ceil(3 + half);
    ex[0] = bb[0] - i; ex[1] = bb[1] - i; ex[2] = bb[2] + i; ex[3] = bb[3] + i;
    S2 = vp_spot_scan(f, ws, nbx, nby, B, model, c.band, ex, &x, &y);
    out->second = S2 > 0 ? S2 / S1 : 0;
    out->u2 = x;
    out->v2 = y;
    if (S2 >= c.second_ratio * S1 && S2 >= thr_det) {
        /* a second spot stands out of its surroundings; a broad hump (glare) does not */
        int r = (int)ceil(half) + 4, k, nr = 0;
        double ring = 0;
        rf.plane = 0;
        for (k = -r; k <= r; k++) {
            int pts[4][2] = { { x + k, y - r }, { x + k, y + r }, { x - r, y + k }, { x + r, y + k } }, q;
            for (q = 0; q < 4; q++)
                if (pts[q][0] >= 0 && pts[q][0] < w && pts[q][1] >= 0 && pts[q][1] < h) { ring += vp_res(&rf, pts[q][0], pts[q][1]); nr++; }
        }
        if (nr) ring /= nr;
        out->second = (S2 - ring) / S1;
        if (S2 - ring >= c.second_ratio * S1 && S2 - ring >= thr_det) { out->result = VP_SPOT_SEVERAL; return VP_OK; }
    }
    if (model && model->line_tol > 0) {
        double du = out->u - model->p0[0], dv = out->v - model->p0[1];
        if (fabs(du * model->e[1] - dv * model->e[0]) > model->line_tol) { out->result = VP_SPOT_OFF_LINE; return VP_OK; }
    }
    out->result = VP_SPOT_FOUND;
    return VP_OK;
}

int vp_laser_measure(const vp_frame_t *f, const vp_spot_config_t *cfg, const vp_tri_model_t *m, vp_spot_ws_t *ws,
                     vp_spot_t *spot, double *d)
{
    double uv[2];
    VP_TRY(vp_spot_find(f, cfg, m, ws, spot));
    if (spot->result != VP_SPOT_FOUND) return 0;
    uv[0] = spot->u;
    uv[1] = spot->v;
    return vp_tri_distance(m, uv, d) == VP_OK ? 1 : 0;
}
