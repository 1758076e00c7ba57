/* vp_line — see vp_line.h. */
#include <math.h>
#include <string.h>
#include "vp_line.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define VP_LINE_PARALLEL 0.01   /* |sin| of a ray's angle to the plane below this: refused */
#define VP_LINE_ROW_SPIKE 1.6   /* a peak's pixel above this times both row neighbours (+ 4 sigma): a
                                   spike (a line sloping up to 1.2 px a column stays below it) */

static int vp_line_model_ok(const vp_line_model_t *m)
{
    return m && vp_finite3(m->origin) && vp_finite3(m->normal) && vp_finite3(m->axis) &&
           fabs(vp_norm3(m->normal) - 1) < 1e-6 && fabs(vp_norm3(m->axis) - 1) < 1e-6 &&
           fabs(vp_dot3(m->normal, m->axis)) < 1e-6 && m->half_angle > 0 && m->half_angle < 3.14159 &&
           m->min_range >= 0 && m->max_range > m->min_range && isfinite(m->max_range) && m->cam.fx > 0 &&
           m->cam.fy > 0 && vp_finite3(m->cam.pos);
}

int vp_line_point3d(const vp_line_model_t *m, const double uv[2], double *dist, double dir[3], double p[3])
{
    double r[3], rn, den, s, q[3], v[3], d, c[3], ang;
    int i, rc;
    if (!vp_line_model_ok(m) || !uv || !dist || !dir || !isfinite(uv[0]) || !isfinite(uv[1])) return VP_EINVAL;
    rc = vp_camera_ray(&m->cam, uv, r);
    if (rc == VP_EDEGEN) return VP_ERANGE;               /* outside the lens' model */
    if (rc != VP_OK) return rc;
    rn = vp_norm3(r);
    den = vp_dot3(m->normal, r);
    if (!(fabs(den) > VP_LINE_PARALLEL * rn)) return VP_ERANGE;   /* the ray runs along the plane */
    for (i = 0; i < 3; i++) v[i] = m->origin[i] - m->cam.pos[i];
    s = vp_dot3(m->normal, v) / den;
    if (!(s > 0)) return VP_ERANGE;                     /* behind the camera */
    for (i = 0; i < 3; i++) {
        q[i] = m->cam.pos[i] + s * r[i];
        v[i] = q[i] - m->origin[i];
    }
    d = vp_norm3(v);
    if (!(d >= m->min_range && d <= m->max_range) || !(d > 0)) return VP_ERANGE;
    vp_cross3(c, v, m->axis);
    ang = atan2(vp_norm3(c), vp_dot3(v, m->axis));
    if (!(ang <= m->half_angle)) return VP_ERANGE;      /* outside the fan */
    *dist = d;
    for (i = 0; i < 3; i++) dir[i] = v[i] / d;
    if (p) for (i = 0; i < 3; i++) p[i] = q[i];
    return VP_OK;
}

/* ---- detection ---- */

static int vp_line_frame_ok(const vp_frame_t *f)
{
    return f && f->data && f->width >= 3 && f->height >= 3 && f->width <= VP_LINE_MAX_W && f->height <= VP_LINE_MAX_H &&
           f->step >= 1 && f->stride >= (f->width - 1) * f->step + 1;
}

/* The median of a histogram of n values (bin k: value k - 255), and the median absolute
 * deviation from it, interpolated within the integer bins. */
static void vp_line_median_mad(const int32_t *hist, long n, int *med, double *mad)
{
    long half = (n + 1) / 2, cum = 0;
    int k, m = 0;
    for (k = 0; k < 511; k++) {
        cum += hist[k];
        if (cum >= half) { m = k; break; }
    }
    *med = m - 255;
    cum = 0;
    for (k = 0; k <= 510; k++) {
        long c = k == 0 ? hist[m] : (m + k <= 510 ? hist[m + k] : 0) + (m - k >= 0 ? hist[m - k] : 0);
        if (cum + c >= 0.5 * n && c > 0) {
            double frac = (0.5 * n - cum) / c;
            *mad = k == 0 ? 0.5 * frac : k - 0.5 + frac;
            return;
        }
        cum += c;
    }
    *mad = 0;
}

/* Gaussian centre by weighted least squares of ln d on a parabola over rows [a, b] (weights d^2:
 * ln d's variance is sigma^2 / d^2); rows below lo are left out. 1 and *c, *sg on success. */
static int vp_line_gauss(const float *d, int a, int b, int yc, double lo, double *c, double *sg)
{
    double S[3][3] = { { 0 } }, g[3] = { 0 }, det, x1, x2;
    int y, used = 0;
    for (y = a; y <= b; y++) {
        double v = d[y], w, t, l;
        if (!(v > lo)) continue;
        w = v * v;
        t = y - yc;
        l = log(v);
        S[0][0] += w; S[0][1] += w * t; S[0][2] += w * t * t;
        S[1][2] += w * t * t * t; S[2][2] += w * t * t * t * t;
        g[0] += w * l; g[1] += w * t * l; g[2] += w * t * t * l;
        used++;
    }
    if (used < 3) return 0;
    S[1][0] = S[0][1]; S[1][1] = S[0][2]; S[2][0] = S[0][2]; S[2][1] = S[1][2];
    /* Cramer's rule on the 3x3 normal equations: c1 and c2 */
    det = S[0][0] * (S[1][1] * S[2][2] - S[1][2] * S[2][1]) - S[0][1] * (S[1][0] * S[2][2] - S[1][2] * S[2][0]) +
          S[0][2] * (S[1][0] * S[2][1] - S[1][1] * S[2][0]);
    if (!(fabs(det) > 0)) return 0;
    x1 = (S[0][0] * (g[1] * S[2][2] - S[1][2] * g[2]) - g[0] * (S[1][0] * S[2][2] - S[1][2] * S[2][0]) +
          S[0][2] * (S[1][0] * g[2] - g[1] * S[2][0])) / det;
    x2 = (S[0][0] * (S[1][1] * g[2] - g[1] * S[2][1]) - S[0][1] * (S[1][0] * g[2] - g[1] * S[2][0]) +
          g[0] * (S[1][0] * S[2][1] - S[1][1] * S[2][0])) / det;
    if (!(x2 < 0)) return 0;
    *c = yc - x1 / (2 * x2);
    *sg = sqrt(-1 / (2 * x2));
    return isfinite(*c);
}

/* One column: its outcome (VP_LINE_*), and the peak in *pt when found. */
static int vp_line_column(const vp_line_ws_t *ws, int h, double sigma, double thr, const vp_line_config_t *c,
                          vp_line_point_t *pt, int *ra, int *rb)
{
    const float *d = ws->d, *s = ws->s;
    double P, top, half, yl, yr, width, centre, sg, excl;
    int y, ys = 1, a, b, yt, sat = 0;
    for (y = 2; y < h - 1; y++) if (s[y] > s[ys]) ys = y;
    P = s[ys];
    if (!(P >= thr)) return VP_LINE_NONE;
    /* the peak's rows at half its score; a lone spike in or beside them (a hot pixel on the line) */
    a = b = ys;
    while (a > 0 && d[a - 1] > 0.5 * P) a--;
    while (b < h - 1 && d[b + 1] > 0.5 * P) b++;
    for (y = a > 1 ? a - 1 : 1; y <= b + 1 && y < h - 1; y++) {
        double nb = d[y - 1] > d[y + 1] ? d[y - 1] : d[y + 1];
        if (nb < 0) nb = 0;
        if (d[y] > c->spike_ratio * nb + 4 * sigma && d[y] >= thr) return VP_LINE_SPIKE;
    }
    yt = a;
    for (y = a; y <= b; y++) {
        if (d[y] > d[yt]) yt = y;
        if (ws->sat[y]) sat = 1;
    }
    top = d[yt];
    half = 0.5 * top;
    a = b = yt;
    while (a > 0 && d[a - 1] > half) a--;
    while (b < h - 1 && d[b + 1] > half) b++;
    if (a == 0 || b == h - 1) return VP_LINE_NONE;      /* cut by the frame's edge */
    yl = a - (d[a] - half) / (d[a] - d[a - 1]);
    yr = b + (d[b] - half) / (d[b] - d[b + 1]);
    width = yr - yl;
    {
        /* a clipped top widens the peak by its clipped run: only the rest must fit */
        int run = 0;
        for (y = a; y <= b; y++) run += ws->sat[y];
        if (!(width - run <= c->max_width)) return VP_LINE_WIDE;
    }
    /* another separated peak in the column: two candidates */
    excl = width + 1;
    for (y = 1; y < h - 1; y++)
        if ((y < yl - excl || y > yr + excl) && s[y] > c->second_ratio * P) return VP_LINE_SEVERAL;
    if (sat) centre = 0.5 * (yl + yr);   /* clipped top: the middle of its edges */
    else {
        double lo = 0.15 * top > 2 * sigma ? 0.15 * top : 2 * sigma;
        int ga = a - 2 > 0 ? a - 2 : 0, gb = b + 2 < h - 1 ? b + 2 : h - 1;
        if (!vp_line_gauss(d, ga, gb, yt, lo, &centre, &sg) || !(centre > yl - 0.5 && centre < yr + 0.5))
            return VP_LINE_BAD_FIT;
    }
    *ra = a > 1 ? a - 1 : 1;
    *rb = b + 1 < h - 1 ? b + 1 : h - 2;
    pt->v = centre;
    pt->peak = top;
    pt->snr = top / sigma;
    pt->width = width;
    pt->saturated = sat;
    return VP_LINE_FOUND;
}

int vp_line_detect(const vp_frame_t *on, const vp_frame_t *off, const vp_line_config_t *cfg, const vp_line_model_t *model,
                   vp_line_ws_t *ws, vp_line_point_t *pts, int cap, int *n, vp_line_stats_t *st)
{
    vp_line_config_t c;
    vp_line_stats_t sx;
    const int w = on ? on->width : 0, h = on ? on->height : 0;
    int x, y, cols, med, found = 0;
    long cnt;
    double mad, sigma, thr;
    if (!vp_line_frame_ok(on) || !vp_line_frame_ok(off) || off->width != w || off->height != h || !ws || !pts || !n)
        return VP_EINVAL;
    memset(&c, 0, sizeof c);
    if (cfg) c = *cfg;
    if (c.column_step < 0 || !(c.min_snr >= 0) || !(c.min_peak >= 0) || !(c.second_ratio >= 0) || !(c.max_width >= 0) ||
        !(c.spike_ratio >= 0) || !(c.max_skew_px >= 0) || !isfinite(c.min_snr) || !isfinite(c.min_peak) ||
        !isfinite(c.second_ratio) || !isfinite(c.max_width) || !isfinite(c.spike_ratio) || !isfinite(c.max_skew_px))
        return VP_EINVAL;
    if (c.column_step == 0) c.column_step = 1;
    if (c.min_snr == 0) c.min_snr = 8;
    if (c.min_peak == 0) c.min_peak = 6;
    if (c.second_ratio == 0) c.second_ratio = 0.35;
    if (c.max_width == 0) c.max_width = 7;
    if (c.spike_ratio == 0) c.spike_ratio = 2;
    if (c.max_skew_px == 0) c.max_skew_px = 0.1;
    cols = (w + c.column_step - 1) / c.column_step;
    if (cap < cols || (model && !vp_line_model_ok(model))) return VP_EINVAL;
    memset(&sx, 0, sizeof sx);
    sx.columns = cols;
    /* noise: the median absolute deviation of the difference over the columns looked at */
    memset(ws->hist, 0, sizeof ws->hist);
    for (y = 0; y < h; y++) {
        const uint8_t *po = on->data + (size_t)y * on->stride, *pf = off->data + (size_t)y * off->stride;
        for (x = 0; x < w; x += c.column_step) ws->hist[(int)po[(size_t)x * on->step] - (int)pf[(size_t)x * off->step] + 255]++;
    }
    cnt = (long)h * cols;
    vp_line_median_mad(ws->hist, cnt, &med, &mad);
    sigma = 1.4826 * mad;
    if (sigma < 0.5) sigma = 0.5;                         /* 8-bit steps: never below half a level */
    sx.noise = sigma;
    thr = c.min_snr * sigma > c.min_peak ? c.min_snr * sigma : c.min_peak;
    for (x = 0; x < w; x += c.column_step) {
        vp_line_point_t pt;
        int why, ra = 0, rb = -1;
        double dmed, dip;
        /* the column's difference above its own median (the ambient light's change between the
         * frames, a flicker, cancels too) */
        memset(ws->chist, 0, sizeof ws->chist);
        for (y = 0; y < h; y++) {
            int vo = VP_FRAME_PIX(on, x, y), df = vo - (int)VP_FRAME_PIX(off, x, y);
            ws->chist[df + 255]++;
            ws->d[y] = (float)df;
            ws->sat[y] = vo == 255;
        }
        vp_line_median_mad(ws->chist, h, &med, &dmed);
        for (y = 0; y < h; y++) ws->d[y] -= (float)med;
        /* a peak's score: its second brightest pixel of three (a lone hot pixel scores nothing) */
        ws->s[0] = ws->s[h - 1] = -1e30f;
        dip = 0;
        for (y = 1; y < h - 1; y++) {
            float nb = ws->d[y - 1] > ws->d[y + 1] ? ws->d[y - 1] : ws->d[y + 1], nd;
            ws->s[y] = ws->d[y] < nb ? ws->d[y] : nb;
            /* the same, downwards: light in the laser-off frame */
            nd = ws->d[y - 1] < ws->d[y + 1] ? ws->d[y - 1] : ws->d[y + 1];
            nd = ws->d[y] > nd ? ws->d[y] : nd;
            if (nd < dip) dip = nd;
        }
        if (dip <= -thr) sx.off_lit++;
        ws->off_lit[x / c.column_step] = dip <= -thr;
        memset(&pt, 0, sizeof pt);
        why = vp_line_column(ws, h, sigma, thr, &c, &pt, &ra, &rb);
        if (why == VP_LINE_FOUND) {
            /* a pixel of the peak standing out of its neighbours in the row (the line varies
             * slowly along itself: a hot pixel in one frame, not the laser), or near saturation
             * with the laser off (it shows nothing of the laser): refused */
            for (y = ra; y <= rb && why == VP_LINE_FOUND; y++) {
                double hi = 0, lo = 1e30, side;
                int k, both = 1;
                if (VP_FRAME_PIX(off, x, y) >= 250) why = VP_LINE_SPIKE;
                for (k = -1; k <= 1; k += 2) {
                    if (x + k < 0 || x + k >= w) { both = 0; continue; }
                    side = (double)VP_FRAME_PIX(on, x + k, y) - (double)VP_FRAME_PIX(off, x + k, y) - med;
                    if (side > hi) hi = side;
                    if (side < lo) lo = side;
                }
                /* above both row neighbours (a hot pixel with the laser on), or below both (one
                 * with the laser off) */
                if (ws->d[y] > VP_LINE_ROW_SPIKE * hi + 4 * sigma) why = VP_LINE_SPIKE;
                if (both && ws->d[y] < lo / VP_LINE_ROW_SPIKE - 4 * sigma) why = VP_LINE_SPIKE;
            }
        }
        ws->at[x / c.column_step] = -1;
        ws->why[x / c.column_step] = (uint8_t)why;
        if (why == VP_LINE_FOUND) {
            pt.col = x;
            pt.u = x;
            ws->at[x / c.column_step] = (int16_t)found;
            pts[found++] = pt;
        } else sx.why[why]++;
    }
    /* the neighbouring columns: the line's slope and how fast it fades along the columns; then
     * the 3D point */
    {
        int i, kept = 0;
        for (i = 0; i < found; i++) {
            const int k = pts[i].col / c.column_step;
            int lo = k, hi = k, why = VP_LINE_FOUND;
            double slope, g, sg2, skew;
            if (k - 1 >= 0 && ws->at[k - 1] >= 0) lo = k - 1;
            if (k + 1 < cols && ws->at[k + 1] >= 0) hi = k + 1;
            if (hi > lo) {
                const vp_line_point_t *a = &pts[ws->at[lo]], *b = &pts[ws->at[hi]];
                int l2 = lo, h2 = hi;
                slope = (b->v - a->v) / (b->u - a->u);
                /* the fading over up to 2 columns either side (a steadier figure than 1) */
                if (lo == k - 1 && k - 2 >= 0 && ws->at[k - 2] >= 0) l2 = k - 2;
                if (hi == k + 1 && k + 2 < cols && ws->at[k + 2] >= 0) h2 = k + 2;
                g = (log(pts[ws->at[h2]].peak) - log(pts[ws->at[l2]].peak)) / (pts[ws->at[h2]].u - pts[ws->at[l2]].u);
                sg2 = pts[i].width / 2.3548;
                sg2 *= sg2;
                skew = sg2 * slope * g / (1 + slope * slope);
                if (!(fabs(skew) <= c.max_skew_px) || !(fabs(slope) <= 2)) why = VP_LINE_SLANT;
            }
            if (why == VP_LINE_FOUND && model) {
                double uv[2];
                uv[0] = pts[i].u;
                uv[1] = pts[i].v;
                if (vp_line_point3d(model, uv, &pts[i].dist, pts[i].dir, pts[i].p) != VP_OK) why = VP_LINE_OFF_MODEL;
            }
            sx.why[why]++;
            ws->why[k] = (uint8_t)why;
            if (why == VP_LINE_FOUND) {
                if (kept != i) {
                    /* a later neighbour still reads this one's figures: swap, not overwrite */
                    vp_line_point_t t = pts[kept];
                    pts[kept] = pts[i];
                    pts[i] = t;
                    ws->at[pts[i].col / c.column_step] = (int16_t)i;
                }
                ws->at[k] = (int16_t)kept;
                kept++;
            }
        }
        found = kept;
    }
    sx.found = found;
    *n = found;
    if (st) *st = sx;
    return VP_OK;
}

/* ---- the laser plane's calibration ---- */

/* Eigenvalues (descending) and unit eigenvectors (columns of V) of symmetric A, cyclic Jacobi. */
static void vp_line_eig3(const double A0[3][3], double ev[3], double V[3][3])
{
    double A[3][3];
    int i, j, k, sweep, p, q;
    memcpy(A, A0, sizeof A);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) V[i][j] = i == j;
    for (sweep = 0; sweep < 50; sweep++) {
        double off = fabs(A[0][1]) + fabs(A[0][2]) + fabs(A[1][2]), scale = fabs(A[0][0]) + fabs(A[1][1]) + fabs(A[2][2]);
        if (!(off > 1e-15 * scale)) break;
        for (p = 0; p < 2; p++)
            for (q = p + 1; q < 3; q++) {
                double th, t, cs, sn;
                if (A[p][q] == 0) continue;
                th = (A[q][q] - A[p][p]) / (2 * A[p][q]);
                t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
                cs = 1 / sqrt(t * t + 1);
                sn = t * cs;
                for (k = 0; k < 3; k++) {   /* A = J^T A J, columns then rows */
                    double akp = A[k][p], akq = A[k][q];
                    A[k][p] = cs * akp - sn * akq;
                    A[k][q] = sn * akp + cs * akq;
                }
                for (k = 0; k < 3; k++) {
                    double apk = A[p][k], aqk = A[q][k];
                    A[p][k] = cs * apk - sn * aqk;
                    A[q][k] = sn * apk + cs * aqk;
                }
                for (k = 0; k < 3; k++) {
                    double vkp = V[k][p], vkq = V[k][q];
                    V[k][p] = cs * vkp - sn * vkq;
                    V[k][q] = sn * vkp + cs * vkq;
                }
            }
    }
    for (i = 0; i < 3; i++) ev[i] = A[i][i];
    /* sort descending, columns of V along */
    for (i = 0; i < 2; i++)
        for (j = i + 1; j < 3; j++)
            if (ev[j] > ev[i]) {
                double t = ev[i];
                ev[i] = ev[j];
                ev[j] = t;
                for (k = 0; k < 3; k++) { t = V[k][i]; V[k][i] = V[k][j]; V[k][j] = t; }
            }
}

/* Observation o's point: its camera ray meeting its target plane. */
static int vp_line_obs_point(const vp_camera_model_t *cam, const vp_calib_obs_t *o, double p[3])
{
    double r[3], den, s;
    int i;
    if (vp_camera_ray(cam, o->uv, r) != VP_OK) return VP_EDEGEN;
    den = vp_dot3(o->n, r);
    if (!(fabs(den) > 1e-6 * vp_norm3(r))) return VP_EDEGEN;
    s = (o->h - vp_dot3(o->n, cam->pos)) / den;
    if (!(s > 0)) return VP_EDEGEN;
    for (i = 0; i < 3; i++) p[i] = cam->pos[i] + s * r[i];
    return VP_OK;
}

int vp_line_fit_plane(const vp_camera_model_t *cam, const vp_calib_obs_t *obs, int n, const vp_line_model_t *nominal,
                      vp_line_model_t *out, vp_line_fit_report_t *rep)
{
    vp_line_model_t m;
    vp_line_fit_report_t r;
    double mean[3] = { 0, 0, 0 }, S[3][3] = { { 0 } }, ev[3], V[3][3], nrm[3], t, ax[3], p[3], e2 = 0;
    int i, j, k;
    if (!cam || !obs || !nominal || !out || n < VP_LINE_FIT_MIN || !vp_line_model_ok(nominal) || !(cam->fx > 0) ||
        !(cam->fy > 0))
        return VP_EINVAL;
    for (i = 0; i < n; i++) {
        const vp_calib_obs_t *o = &obs[i];
        if (o->kind != VP_OBS_SPOT || !isfinite(o->uv[0]) || !isfinite(o->uv[1]) || !isfinite(o->h) ||
            !vp_finite3(o->n) || !(fabs(vp_norm3(o->n) - 1) < 1e-6))
            return VP_EINVAL;
    }
    /* the points: their mean, then their scatter about it */
    for (i = 0; i < n; i++) {
        VP_TRY(vp_line_obs_point(cam, &obs[i], p));
        for (k = 0; k < 3; k++) mean[k] += p[k];
    }
    for (k = 0; k < 3; k++) mean[k] /= n;
    for (i = 0; i < n; i++) {
        double q[3];
        VP_TRY(vp_line_obs_point(cam, &obs[i], p));
        for (k = 0; k < 3; k++) q[k] = p[k] - mean[k];
        for (j = 0; j < 3; j++)
            for (k = 0; k < 3; k++) S[j][k] += q[j] * q[k];
    }
    vp_line_eig3((const double(*)[3])S, ev, V);
    memset(&r, 0, sizeof r);
    r.n = n;
    r.spread_mm = sqrt(ev[1] > 0 ? ev[1] / n : 0);
    /* one line of points (one target pose) leaves the plane's turn about it free */
    if (!(r.spread_mm >= 1.0) || !(ev[2] < 0.01 * ev[1])) return VP_EDEGEN;
    for (k = 0; k < 3; k++) nrm[k] = V[k][2];
    if (vp_dot3(nrm, nominal->normal) < 0)
        for (k = 0; k < 3; k++) nrm[k] = -nrm[k];
    m = *nominal;
    m.cam = *cam;
    for (k = 0; k < 3; k++) m.normal[k] = nrm[k] / vp_norm3(nrm);
    /* origin: the plane's point nearest the nominal origin; axis: the nominal one in the plane */
    for (k = 0; k < 3; k++) p[k] = nominal->origin[k] - mean[k];
    t = vp_dot3(p, m.normal);
    for (k = 0; k < 3; k++) m.origin[k] = nominal->origin[k] - t * m.normal[k];
    t = vp_dot3(nominal->axis, m.normal);
    for (k = 0; k < 3; k++) ax[k] = nominal->axis[k] - t * m.normal[k];
    if (!(vp_norm3(ax) > 0.5)) return VP_EDEGEN;
    t = vp_norm3(ax);
    for (k = 0; k < 3; k++) m.axis[k] = ax[k] / t;
    r.tilt_deg = acos(fmin(1.0, fabs(vp_dot3(m.normal, nominal->normal)))) * 180 / 3.14159265358979323846;
    r.span[0] = HUGE_VAL;
    r.span[1] = -HUGE_VAL;
    for (i = 0; i < n; i++) {
        double q[3], e, d;
        VP_TRY(vp_line_obs_point(cam, &obs[i], p));
        for (k = 0; k < 3; k++) q[k] = p[k] - m.origin[k];
        e = fabs(vp_dot3(q, m.normal));
        d = vp_norm3(q);
        e2 += e * e;
        if (e > r.max_mm) r.max_mm = e;
        if (d < r.span[0]) r.span[0] = d;
        if (d > r.span[1]) r.span[1] = d;
    }
    r.rms_mm = sqrt(e2 / n);
    *out = m;
    if (rep) *rep = r;
    return VP_OK;
}
