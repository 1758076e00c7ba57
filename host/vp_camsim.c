/* vp_camsim — see vp_camsim.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_camsim.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define VP_PI 3.14159265358979323846

static void vp_mulT(const double r[9], const double v[3], double out[3])
{
    int i;
    for (i = 0; i < 3; i++) out[i] = r[i] * v[0] + r[3 + i] * v[1] + r[6 + i] * v[2];
}

static void vp_mul(const double r[9], const double v[3], double out[3])
{
    int i;
    for (i = 0; i < 3; i++) out[i] = r[3 * i] * v[0] + r[3 * i + 1] * v[1] + r[3 * i + 2] * v[2];
}

/* tilt-frame point -> image: the camera's frame, the pinhole, then the lens (radial k1 k2,
 * decentring p1 p2) bending the true ray */
static int vp_camsim_image(const vp_camera_model_t *cam, const double t[3], double uv[2])
{
    double q[3], c[3], x, y, rr, bend, tx, ty;
    int i;
    for (i = 0; i < 3; i++) q[i] = t[i] - cam->pos[i];
    vp_mul(cam->rot, q, c);
    if (!(c[2] > 1e-9)) return 0;
    if (cam->dist[0] == 0 && cam->dist[1] == 0 && cam->dist[2] == 0 && cam->dist[3] == 0) {
        uv[0] = cam->fx * c[0] / c[2] + cam->cx;   /* a perfect lens */
        uv[1] = cam->fy * c[1] / c[2] + cam->cy;
        return 1;
    }
    x = c[0] / c[2];
    y = c[1] / c[2];
    rr = x * x + y * y;
    bend = 1 + rr * (cam->dist[0] + rr * cam->dist[1]);
    tx = 2 * cam->dist[2] * x * y + cam->dist[3] * (rr + 2 * x * x);
    ty = cam->dist[2] * (rr + 2 * y * y) + 2 * cam->dist[3] * x * y;
    uv[0] = cam->cx + cam->fx * (bend * x + tx);
    uv[1] = cam->cy + cam->fy * (bend * y + ty);
    return 1;
}

/* world point -> image */
static int vp_camsim_proj(const vp_camsim_config_t *c, const double rot[9], const double pos[3], const double p[3],
                          double uv[2])
{
    double q[3], t[3];
    int i;
    for (i = 0; i < 3; i++) q[i] = p[i] - pos[i];
    vp_mulT(rot, q, t);
    return vp_camsim_image(&c->cam, t, uv);
}

/* the beam's direction in the tilt frame */
static void vp_camsim_beam(const vp_camsim_config_t *c, double d[3])
{
    double n = sqrt(c->laser_dir[0] * c->laser_dir[0] + c->laser_dir[1] * c->laser_dir[1] + c->laser_dir[2] * c->laser_dir[2]);
    int i;
    if (!(n > 0)) { d[0] = 1; d[1] = d[2] = 0; return; }
    for (i = 0; i < 3; i++) d[i] = c->laser_dir[i] / n;
}

/* Where a beam from o (inside the backdrop's box) along d leaves the box, within maxr: the
 * distance and the wall's inward normal. 0 when o is not inside or the wall is beyond maxr. */
static int vp_camsim_backdrop(const vp_camsim_scene_t *sc, const double o[3], const double d[3], double maxr,
                              double *t, double n[3])
{
    double best = maxr;
    int k, face = -1;
    for (k = 0; k < 3; k++) {
        double tk;
        if (!(o[k] > sc->backdrop_lo[k] && o[k] < sc->backdrop_hi[k])) return 0;
        if (d[k] == 0) continue;
        tk = ((d[k] > 0 ? sc->backdrop_hi[k] : sc->backdrop_lo[k]) - o[k]) / d[k];
        if (tk <= best) { best = tk; face = k; }
    }
    if (face < 0) return 0;
    n[0] = n[1] = n[2] = 0;
    n[face] = d[face] > 0 ? -1 : 1;
    *t = best;
    return 1;
}

/* Approximately normal deviate from one 64-bit draw (sum of four 16-bit uniforms). */
static double vp_camsim_gauss(vp_rng_t *r)
{
    uint64_t x = vp_rng_u64(r);
    double s = (double)(x & 0xffff) + (double)((x >> 16) & 0xffff) + (double)((x >> 32) & 0xffff) + (double)(x >> 48);
    return (s / 65536.0 - 2.0) * 1.7320508075688772;
}

/* Adds a Gaussian spot of energy e and covariance (sxx, sxy, syy) at (u, v). */
static void vp_camsim_spot(float *acc, int w, int h, double u, double v, double e, double sxx, double sxy, double syy)
{
    double det = sxx * syy - sxy * sxy, ixx, ixy, iyy, rad, norm;
    int x0, x1, y0, y1, x, y;
    if (!(det > 0)) return;
    ixx = syy / det; ixy = -sxy / det; iyy = sxx / det;
    norm = e / (2 * VP_PI * sqrt(det));
    rad = 4.5 * sqrt(sxx > syy ? sxx : syy) + 1;
    x0 = (int)floor(u - rad); x1 = (int)ceil(u + rad);
    y0 = (int)floor(v - rad); y1 = (int)ceil(v + rad);
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > w - 1) x1 = w - 1;
    if (y1 > h - 1) y1 = h - 1;
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++) {
            double dx = x - u, dy = y - v, q = ixx * dx * dx + 2 * ixy * dx * dy + iyy * dy * dy;
            if (q < 40) acc[(size_t)y * w + x] += (float)(norm * exp(-0.5 * q));
        }
}

/* Mean of 1 + m cos(2 pi f t) over the exposure [t, t + T] (s): mains flicker of the ambient light. */
static double vp_camsim_flicker(const vp_camsim_config_t *c, double t)
{
    double f = c->flicker_hz > 0 ? c->flicker_hz : 100, T = (c->exposure_ms > 0 ? c->exposure_ms : 1) * 1e-3;
    return 1 + c->flicker * (sin(2 * VP_PI * f * (t + T)) - sin(2 * VP_PI * f * t)) / (2 * VP_PI * f * T);
}

/* Laser speckle on the laser's layer lay (row length w) within [x0, x1] x [y0, y1]: the pixels
 * times |z|^2 of a complex Gaussian field with grains of 2.44 lambda N on the sensor, drawn from
 * key, contrast c->speckle; the layer's sum before and after added to *before, *after. */
static int vp_camsim_speckle(const vp_camsim_config_t *c, float *lay, int w, int x0, int x1, int y0, int y1, uint64_t key,
                             double *before, double *after)
{
    double N = c->fnumber > 0 ? c->fnumber : 8, lam = (c->laser_nm > 0 ? c->laser_nm : 650) * 1e-3;
    double g = 2.44 * lam * N / (c->pixel_um > 0 ? c->pixel_um : 3);   /* grain, px */
    int gx0, gy0, nx, ny, i, x, y;
    float *z;
    vp_rng_t sr;
    if (g < 0.25) g = 0.25;
    gx0 = (int)floor(x0 / g);
    gy0 = (int)floor(y0 / g);
    nx = (int)floor(x1 / g) - gx0 + 2;
    ny = (int)floor(y1 / g) - gy0 + 2;
    z = malloc(2 * (size_t)nx * ny * sizeof *z);
    if (!z) return VP_ENOMEM;
    vp_rng_seed(&sr, key);
    for (i = 0; i < 2 * nx * ny; i++) z[i] = (float)(vp_camsim_gauss(&sr) * 0.70710678118654752);
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++) {
            double fx = x / g - gx0, fy = y / g - gy0, tx, ty, wq[4], re = 0, im = 0, ww = 0, I;
            int ix = (int)floor(fx), iy = (int)floor(fy), q, n[4];
            size_t p = (size_t)y * w + x;
            tx = fx - ix; ty = fy - iy;
            if (ix > nx - 2) ix = nx - 2;
            if (iy > ny - 2) iy = ny - 2;
            wq[0] = (1 - tx) * (1 - ty); wq[1] = tx * (1 - ty); wq[2] = (1 - tx) * ty; wq[3] = tx * ty;
            n[0] = iy * nx + ix; n[1] = n[0] + 1; n[2] = n[0] + nx; n[3] = n[2] + 1;
            for (q = 0; q < 4; q++) { re += wq[q] * z[2 * n[q]]; im += wq[q] * z[2 * n[q] + 1]; ww += wq[q] * wq[q]; }
            I = (re * re + im * im) / ww;      /* exponential, mean 1, at every pixel */
            *before += lay[p];
            lay[p] = (float)(lay[p] * (1 + c->speckle * (I - 1)));
            *after += lay[p];
        }
    free(z);
    return VP_OK;
}

/* The spot (and its ghost) through the faults: the head's vibration during the exposure (the
 * spot drawn at sub-exposure instants along a damped ringing, dt_ms after the last step) and laser
 * speckle (the pixels times |z|^2 of a complex Gaussian field with grains of 2.44 lambda N on the
 * sensor, contrast c->speckle), into lay (zeroed, w x h); the truth's peak, speckle gain and
 * vibration amplitude. */
static int vp_camsim_spot_faults(const vp_camsim_config_t *c, float *lay, int w, int h, double dt_ms,
                                 double sxx, double sxy, double syy, vp_camsim_truth_t *tr)
{
    const int K = c->vib_px > 0 ? 24 : 1;
    double th = c->vib_deg * VP_PI / 180, ev[2], T = c->exposure_ms > 0 ? c->exposure_ms : 1;
    double hz = c->vib_hz > 0 ? c->vib_hz : 150, tau = c->vib_ms > 0 ? c->vib_ms : 40, reach = 0, before = 0, after = 0, pk = 0;
    int k, x, y, x0, x1, y0, y1;
    ev[0] = cos(th);
    ev[1] = sin(th);
    if (dt_ms < 0) dt_ms = 0;
    tr->vib_px = c->vib_px > 0 ? c->vib_px * exp(-dt_ms / tau) : 0;
    for (k = 0; k < K; k++) {
        double t = dt_ms + (k + 0.5) * T / K, off = c->vib_px > 0 ? c->vib_px * exp(-t / tau) * sin(2 * VP_PI * hz * t * 1e-3) : 0;
        if (fabs(off) > reach) reach = fabs(off);
        vp_camsim_spot(lay, w, h, tr->uv[0] + off * ev[0], tr->uv[1] + off * ev[1], tr->energy / K, sxx, sxy, syy);
        if (c->ghost > 0)
            vp_camsim_spot(lay, w, h, tr->uv[0] + c->ghost_offset[0] + off * ev[0], tr->uv[1] + c->ghost_offset[1] + off * ev[1],
                           tr->energy * c->ghost / K, sxx, sxy, syy);
    }
    /* the window the spot can reach */
    {
        double rad = 4.5 * sqrt(sxx > syy ? sxx : syy) + 2 + reach;
        x0 = (int)floor(tr->uv[0] - rad); x1 = (int)ceil(tr->uv[0] + rad);
        y0 = (int)floor(tr->uv[1] - rad); y1 = (int)ceil(tr->uv[1] + rad);
        if (x0 < 0) x0 = 0;
        if (y0 < 0) y0 = 0;
        if (x1 > w - 1) x1 = w - 1;
        if (y1 > h - 1) y1 = h - 1;
    }
    if (c->speckle > 0 && x0 <= x1 && y0 <= y1) {
        /* the surface's roughness under the beam: the same spot gives the same grains frame
         * after frame, a spot moved by 0.05 mm others (the renderer's seed picks the surface) */
        uint64_t key = c->speckle_seed;
        int i;
        for (i = 0; i < 3; i++) key = vp_mix64(key ^ (uint64_t)(int64_t)llround(tr->point[i] * 20));
        VP_TRY(vp_camsim_speckle(c, lay, w, x0, x1, y0, y1, key, &before, &after));
    }
    tr->speckle_gain = before > 0 ? after / before : 1;
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++) if (lay[(size_t)y * w + x] > pk) pk = lay[(size_t)y * w + x];
    tr->peak = pk;
    return VP_OK;
}

/* ---- the line laser ---- */

/* The fan's frame in the tilt frame: its plane's normal nl, its centre direction ax (the beam's
 * direction brought into the plane) and bx = nl x ax across the fan. */
static int vp_camsim_fan(const vp_camsim_config_t *c, double nl[3], double ax[3], double bx[3])
{
    double b[3], l, t;
    int i;
    if (!vp_finite3(c->line_normal) || !(c->fan_half_angle >= 0) || !(c->fan_half_angle < 1.5) || c->line_rays < 0 ||
        c->line_rays > 1000000 || !(c->line_energy >= 0) || !(c->line_width >= 0))
        return VP_EINVAL;
    l = vp_norm3(c->line_normal);
    if (l > 0) for (i = 0; i < 3; i++) nl[i] = c->line_normal[i] / l;
    else { nl[0] = nl[1] = 0; nl[2] = 1; }
    vp_camsim_beam(c, b);
    t = vp_dot3(b, nl);
    for (i = 0; i < 3; i++) ax[i] = b[i] - t * nl[i];
    l = vp_norm3(ax);
    if (!(l > 1e-6)) return VP_EINVAL;
    for (i = 0; i < 3; i++) ax[i] /= l;
    vp_cross3(bx, nl, ax);
    return VP_OK;
}

/* One ray of the fan at angle a (rad from the axis): where it meets the scene and what the camera
 * sees of it. */
typedef struct vp_camsim_fray {
    int vis;                     /* hit, lit side, in front, in frame, not hidden */
    double uv[2];                /* its image (through the lens) */
    double tp[3], dist;          /* the point in the tilt frame, distance from the laser origin */
    double albedo;
    double e;                    /* energy per radian of fan reaching the camera */
    double sxx, sxy, syy;        /* its spot's covariance, px^2 */
} vp_camsim_fray_t;

typedef struct vp_camsim_fan_ctx {
    const vp_camsim_config_t *c;
    const vp_camsim_scene_t *sc;
    const double *rot, *pos;
    double nl[3], ax[3], bx[3];  /* tilt frame */
    double o[3], cpos[3], nlw[3];/* world: laser origin, camera centre, the plane's normal */
    double maxr, blur, sheet, energy;
} vp_camsim_fan_ctx_t;

static void vp_camsim_fan_ray(const vp_camsim_fan_ctx_t *f, double a, vp_camsim_fray_t *r)
{
    const vp_camsim_config_t *c = f->c;
    const vp_camsim_scene_t *sc = f->sc;
    double dt[3], d[3], t = 0, n[3], wp[3], vc[3], lc, cos_i, cos_e, tv[3], tl, sg, q[3], uv1[2], j[2], wall_n[3];
    int i, hit = 0, wall = 0;
    memset(r, 0, sizeof *r);
    for (i = 0; i < 3; i++) dt[i] = cos(a) * f->ax[i] + sin(a) * f->bx[i];
    vp_mul(f->rot, dt, d);
    if (sc->surf) hit = vp_surface_ray(sc->surf, f->o, d, f->maxr, &t);
    else {
        double den = vp_dot3(sc->plane_n, d), num = sc->plane_d - vp_dot3(sc->plane_n, f->o);
        if (fabs(den) > 1e-12) { t = num / den; hit = t > 0 && t <= f->maxr; }
    }
    /* no object on this ray of the fan: the line on the backdrop, if there is one */
    if (!hit && sc->backdrop) hit = wall = vp_camsim_backdrop(sc, f->o, d, f->maxr, &t, wall_n);
    if (!hit) return;
    for (i = 0; i < 3; i++) {
        wp[i] = f->o[i] + t * d[i];
        r->tp[i] = c->laser_offset[i] + t * dt[i];
    }
    r->dist = t;
    if (wall) memcpy(n, wall_n, sizeof n);
    else if (sc->surf) vp_surface_normal(sc->surf, wp, n);
    else for (i = 0; i < 3; i++) n[i] = sc->plane_n[i];
    cos_i = vp_dot3(n, d);
    if (cos_i > 0) for (i = 0; i < 3; i++) n[i] = -n[i];   /* the lit side */
    for (i = 0; i < 3; i++) vc[i] = f->cpos[i] - wp[i];
    lc = vp_norm3(vc);
    cos_e = vp_dot3(n, vc) / lc;
    if (!(cos_e > 0.02) || !vp_camsim_proj(c, f->rot, f->pos, wp, r->uv) || r->uv[0] < 0 || r->uv[0] > c->cam.width - 1 ||
        r->uv[1] < 0 || r->uv[1] > c->cam.height - 1)
        return;
    if (sc->surf) {
        double th, u[3];
        for (i = 0; i < 3; i++) u[i] = -vc[i] / lc;
        /* hidden if the object crosses the line of sight before the point */
        if (vp_surface_ray(sc->surf, f->cpos, u, lc * (1 - 1e-6) - 1e-6, &th)) return;
    }
    r->vis = 1;
    r->albedo = !wall && c->dark_albedo > 0 && wp[2] >= c->dark_z[0] && wp[2] <= c->dark_z[1] ? c->dark_albedo : 1;
    r->e = f->energy * r->albedo * cos_e * (300.0 / lc) * (300.0 / lc);
    /* the sheet's thickness on the surface: along the surface's direction that leaves the plane
     * fastest, sheet / |its rate|; through the camera's local projection */
    tl = vp_dot3(f->nlw, n);
    for (i = 0; i < 3; i++) tv[i] = f->nlw[i] - tl * n[i];
    tl = vp_norm3(tv);
    if (tl < 1e-9) { r->sxx = r->syy = f->blur * f->blur; return; }
    for (i = 0; i < 3; i++) tv[i] /= tl;
    sg = f->sheet / (tl > 0.15 ? tl : 0.15);
    for (i = 0; i < 3; i++) q[i] = wp[i] + 0.01 * tv[i];
    vp_camsim_proj(c, f->rot, f->pos, q, uv1);
    j[0] = (uv1[0] - r->uv[0]) / 0.01 * sg;
    j[1] = (uv1[1] - r->uv[1]) / 0.01 * sg;
    r->sxx = f->blur * f->blur + j[0] * j[0];
    r->syy = f->blur * f->blur + j[1] * j[1];
    r->sxy = j[0] * j[1];
}

/* The line: rays cast across the fan, the hits the camera sees drawn into acc (laser on), and the
 * truth per column by bisection between neighbouring rays (line may be NULL). The spot truth tr
 * says whether any of it was seen and the line's peak. */
static int vp_camsim_line(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, const double rot[9], const double pos[3],
                          float *acc, int laser, double blur, vp_camsim_truth_t *tr, vp_camsim_line_truth_t *line)
{
    const int w = c->cam.width, h = c->cam.height, N = c->line_rays > 1 ? c->line_rays : 4096;
    const double H = c->fan_half_angle > 0 ? c->fan_half_angle : 30 * VP_PI / 180, da = 2 * H / (N - 1);
    vp_camsim_fan_ctx_t f;
    vp_camsim_fray_t prev, cur;
    float *lay = NULL;
    int i, k, seen = 0, bx0 = w, bx1 = -1, by0 = h, by1 = -1;
    memset(&f, 0, sizeof f);
    f.c = c; f.sc = sc; f.rot = rot; f.pos = pos;
    VP_TRY(vp_camsim_fan(c, f.nl, f.ax, f.bx));
    vp_mul(rot, c->laser_offset, f.o);
    vp_mul(rot, c->cam.pos, f.cpos);
    vp_mul(rot, f.nl, f.nlw);
    for (i = 0; i < 3; i++) { f.o[i] += pos[i]; f.cpos[i] += pos[i]; }
    f.maxr = c->max_range > 0 ? c->max_range : 5000;
    f.blur = blur;
    f.sheet = c->line_width > 0 ? c->line_width : c->beam_radius > 0 ? c->beam_radius : 0.25;
    f.energy = c->line_energy > 0 ? c->line_energy : 60000;
    if (line) {
        if (w > VP_CAMSIM_MAX_W) return VP_EINVAL;
        memset(line, 0, sizeof *line);
        line->width = w;
        line->rays = N;
    }
    if (laser) {
        lay = calloc((size_t)w * h, sizeof *lay);
        if (!lay) return VP_ENOMEM;
    }
    memset(&prev, 0, sizeof prev);
    for (k = 0; k < N; k++) {
        const double a = -H + da * k;
        vp_camsim_fan_ray(&f, a, &cur);
        if (cur.vis) {
            seen++;
            if (laser) {
                double rad = 4.5 * sqrt(cur.sxx > cur.syy ? cur.sxx : cur.syy) + 2;
                int gx = c->ghost > 0 ? (int)ceil(fabs(c->ghost_offset[0])) : 0;
                int gy = c->ghost > 0 ? (int)ceil(fabs(c->ghost_offset[1])) : 0;
                vp_camsim_spot(lay, w, h, cur.uv[0], cur.uv[1], cur.e * da, cur.sxx, cur.sxy, cur.syy);
                if (c->ghost > 0)
                    vp_camsim_spot(lay, w, h, cur.uv[0] + c->ghost_offset[0], cur.uv[1] + c->ghost_offset[1],
                                   cur.e * da * c->ghost, cur.sxx, cur.sxy, cur.syy);
                if (cur.uv[0] - rad - gx < bx0) bx0 = (int)floor(cur.uv[0] - rad - gx);
                if (cur.uv[0] + rad + gx > bx1) bx1 = (int)ceil(cur.uv[0] + rad + gx);
                if (cur.uv[1] - rad - gy < by0) by0 = (int)floor(cur.uv[1] - rad - gy);
                if (cur.uv[1] + rad + gy > by1) by1 = (int)ceil(cur.uv[1] + rad + gy);
            }
            if (line && k > 0 && prev.vis && hypot(cur.uv[0] - prev.uv[0], cur.uv[1] - prev.uv[1]) < 3) {
                /* the columns between this ray's image and the last one's (no jump between them:
                 * an occlusion's edge) */
                const double u0 = prev.uv[0], u1 = cur.uv[0], lo = u0 < u1 ? u0 : u1, hi = u0 < u1 ? u1 : u0;
                int x;
                for (x = (int)ceil(lo); x < hi && x < w; x++) {
                    double a0 = a - da, a1 = a, am = a;
                    vp_camsim_fray_t r;
                    int it, ok = 1;
                    if (x < 0 || (double)x < lo) continue;
                    memset(&r, 0, sizeof r);
                    for (it = 0; it < 40; it++) {
                        am = 0.5 * (a0 + a1);
                        vp_camsim_fan_ray(&f, am, &r);
                        if (!r.vis) { ok = 0; break; }
                        if ((r.uv[0] < x) == (u0 < x)) a0 = am; else a1 = am;
                    }
                    if (!ok) continue;
                    if (line->count[x] == 0) {
                        line->v[x] = r.uv[1];
                        memcpy(line->p[x], r.tp, sizeof r.tp);
                        line->dist[x] = r.dist;
                        line->albedo[x] = r.albedo;
                    }
                    if (line->count[x] < 255) line->count[x]++;
                }
            }
        }
        prev = cur;
    }
    if (line) line->rays_visible = seen;
    tr->hit = tr->visible = seen > 0;
    if (laser) {
        double before = 0, after = 0, pk = 0;
        int st = VP_OK, x, y;
        if (bx0 < 0) bx0 = 0;
        if (by0 < 0) by0 = 0;
        if (bx1 > w - 1) bx1 = w - 1;
        if (by1 > h - 1) by1 = h - 1;
        if (c->speckle > 0 && bx0 <= bx1 && by0 <= by1) {
            /* the surface's roughness under the fan: grains drawn from the seed and the laser's place */
            uint64_t key = vp_mix64(c->speckle_seed ^ 0x6c696e65u);
            for (i = 0; i < 3; i++) key = vp_mix64(key ^ (uint64_t)(int64_t)llround(f.o[i] * 20));
            st = vp_camsim_speckle(c, lay, w, bx0, bx1, by0, by1, key, &before, &after);
        }
        tr->speckle_gain = before > 0 ? after / before : 1;
        for (y = by0; y <= by1; y++)
            for (x = bx0; x <= bx1; x++) {
                size_t p = (size_t)y * w + x;
                acc[p] += lay[p];
                if (lay[p] > pk) pk = lay[p];
            }
        tr->peak = pk;
        free(lay);
        VP_TRY(st);
    }
    return VP_OK;
}

static int vp_camsim_draw(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, const double rot[9], const double pos[3],
                          vp_rng_t *rng, uint8_t *img, int stride, vp_camsim_truth_t *truth, int laser, int64_t t_exp,
                          int64_t t_move, vp_camsim_line_truth_t *line)
{
    const int w = c->cam.width, h = c->cam.height;
    double ex[3], o[3], d[3], cpos[3], t = 0, blur, beam, energy, maxr, tx, ty, phx, phy, wall_n[3];
    vp_camsim_truth_t tr;
    float *acc;
    int i, x, y;
    const int faults = c->speckle > 0 || c->vib_px > 0;
    const double dt_ms = t_move == INT64_MIN ? 1e9 : (double)(t_exp - t_move) * 1e-6;
    if (!c || !sc || !rot || !pos || !rng || !img || w < 8 || h < 8 || stride < w ||
        (c->laser_kind != VP_CAMSIM_DOT && c->laser_kind != VP_CAMSIM_LINE))
        return VP_EINVAL;
    if (c->laser_kind == VP_CAMSIM_LINE) {
        double nl[3], ax[3], bx[3];
        VP_TRY(vp_camsim_fan(c, nl, ax, bx));
    }
    memset(&tr, 0, sizeof tr);
    tr.laser = laser;
    tr.albedo = tr.speckle_gain = tr.ambient_gain = 1;
    if (c->flicker > 0) tr.ambient_gain = vp_camsim_flicker(c, (double)t_exp * 1e-9);
    blur = c->blur_px > 0 ? c->blur_px : 1.2;
    beam = c->beam_radius > 0 ? c->beam_radius : 0.25;
    energy = c->spot_energy > 0 ? c->spot_energy : 3000;
    maxr = c->max_range > 0 ? c->max_range : 5000;
    vp_camsim_beam(c, ex);
    acc = malloc((size_t)w * h * sizeof *acc);
    if (!acc) return VP_ENOMEM;
    /* ambient light: level, gradient, a smooth pattern with a random phase */
    phx = 2 * VP_PI * vp_rng_uniform(rng);
    phy = 2 * VP_PI * vp_rng_uniform(rng);
    for (x = 0; x < w; x++) acc[x] = (float)cos(2 * VP_PI * x / 97.0 + phx);   /* row 0 as scratch */
    for (y = h - 1; y >= 0; y--) {
        ty = c->texture * cos(2 * VP_PI * y / 71.0 + phy);
        for (x = 0; x < w; x++) {
            tx = acc[x];
            acc[(size_t)y * w + x] = (float)(c->ambient + c->gradient * ((double)x / w + (double)y / h - 1) * 0.5 + ty * tx);
            if (c->flicker > 0) acc[(size_t)y * w + x] *= (float)tr.ambient_gain;
        }
    }
    /* the beam in the world */
    if (c->laser_kind == VP_CAMSIM_LINE) {
        int st = vp_camsim_line(c, sc, rot, pos, acc, laser, blur, &tr, line);
        if (st != VP_OK) { free(acc); return st; }
    }
    vp_mul(rot, c->laser_offset, o);
    vp_mul(rot, c->cam.pos, cpos);
    for (i = 0; i < 3; i++) { o[i] += pos[i]; cpos[i] += pos[i]; }
    vp_mul(rot, ex, d);
    if (c->laser_kind == VP_CAMSIM_LINE) {
        /* the line drew itself above */
    } else if (sc->surf) tr.hit = vp_surface_ray(sc->surf, o, d, maxr, &t);
    else {
        double den = sc->plane_n[0] * d[0] + sc->plane_n[1] * d[1] + sc->plane_n[2] * d[2];
        double num = sc->plane_d - (sc->plane_n[0] * o[0] + sc->plane_n[1] * o[1] + sc->plane_n[2] * o[2]);
        if (fabs(den) > 1e-12) { t = num / den; tr.hit = t > 0 && t <= maxr; }
    }
    /* no object on the beam: its spot on the backdrop, if there is one */
    if (!tr.hit && sc->backdrop && c->laser_kind != VP_CAMSIM_LINE) tr.backdrop = vp_camsim_backdrop(sc, o, d, maxr, &t, wall_n);
    if ((tr.hit || tr.backdrop) && c->laser_kind != VP_CAMSIM_LINE) {
        double n[3], vc[3], lc, cos_i, cos_e, t1[3], t2[3], j1[2], j2[2], uv1[2], q[3], r1, sxx, sxy, syy;
        tr.dist = t;
        for (i = 0; i < 3; i++) tr.point[i] = o[i] + t * d[i];
        if (tr.backdrop) memcpy(n, wall_n, sizeof n);
        else if (sc->surf) vp_surface_normal(sc->surf, tr.point, n);
        else for (i = 0; i < 3; i++) n[i] = sc->plane_n[i];
        cos_i = vp_dot3(n, d);
        if (cos_i > 0) { for (i = 0; i < 3; i++) n[i] = -n[i]; cos_i = -cos_i; }   /* the lit side */
        cos_i = -cos_i;
        for (i = 0; i < 3; i++) vc[i] = cpos[i] - tr.point[i];
        lc = vp_norm3(vc);
        cos_e = (vp_dot3(n, vc)) / lc;
        tr.visible = cos_e > 0.02 && vp_camsim_proj(c, rot, pos, tr.point, tr.uv) && tr.uv[0] >= 0 &&
                     tr.uv[0] <= w - 1 && tr.uv[1] >= 0 && tr.uv[1] <= h - 1;
        if (tr.visible && sc->surf) {
            double u[3], th;
            for (i = 0; i < 3; i++) u[i] = vc[i] / lc;
            /* hidden if the object crosses the line of sight before the spot */
            if (vp_surface_ray(sc->surf, cpos, (double[3]){ -u[0], -u[1], -u[2] }, lc * (1 - 1e-6) - 1e-6, &th)) tr.visible = 0;
        }
        if (tr.visible && laser) {
            /* footprint: beam radius across, stretched by 1/cos along the slant */
            for (i = 0; i < 3; i++) t1[i] = d[i] + cos_i * n[i];
            {
                double l1 = vp_norm3(t1);
                if (l1 < 1e-9) { double a[3] = { 1, 0, 0 }; if (fabs(n[0]) > 0.9) { a[0] = 0; a[1] = 1; }
                                 vp_cross3(t1, a, n);
                                 l1 = vp_norm3(t1); }
                for (i = 0; i < 3; i++) t1[i] /= l1;
            }
            t2[0] = n[1] * t1[2] - n[2] * t1[1];
            t2[1] = n[2] * t1[0] - n[0] * t1[2];
            t2[2] = n[0] * t1[1] - n[1] * t1[0];
            r1 = beam / (cos_i > 0.15 ? cos_i : 0.15);
            for (i = 0; i < 3; i++) q[i] = tr.point[i] + 0.01 * t1[i];
            vp_camsim_proj(c, rot, pos, q, uv1);
            j1[0] = (uv1[0] - tr.uv[0]) / 0.01 * r1; j1[1] = (uv1[1] - tr.uv[1]) / 0.01 * r1;
            for (i = 0; i < 3; i++) q[i] = tr.point[i] + 0.01 * t2[i];
            vp_camsim_proj(c, rot, pos, q, uv1);
            j2[0] = (uv1[0] - tr.uv[0]) / 0.01 * beam; j2[1] = (uv1[1] - tr.uv[1]) / 0.01 * beam;
            sxx = blur * blur + j1[0] * j1[0] + j2[0] * j2[0];
            syy = blur * blur + j1[1] * j1[1] + j2[1] * j2[1];
            sxy = j1[0] * j1[1] + j2[0] * j2[1];
            if (tr.hit && c->dark_albedo > 0 && tr.point[2] >= c->dark_z[0] && tr.point[2] <= c->dark_z[1]) tr.albedo = c->dark_albedo;
            tr.energy = energy * tr.albedo * cos_e * (300.0 / lc) * (300.0 / lc);
            tr.sigma_px = sqrt(sqrt(sxx * syy - sxy * sxy));
            tr.peak = tr.energy / (2 * VP_PI * tr.sigma_px * tr.sigma_px);
            if (faults) {
                float *lay = calloc((size_t)w * h, sizeof *lay);
                int st;
                if (!lay) { free(acc); return VP_ENOMEM; }
                st = vp_camsim_spot_faults(c, lay, w, h, dt_ms, sxx, sxy, syy, &tr);
                for (i = 0; i < w * h; i++) acc[i] += lay[i];
                free(lay);
                if (st != VP_OK) { free(acc); return st; }
            } else {
                vp_camsim_spot(acc, w, h, tr.uv[0], tr.uv[1], tr.energy, sxx, sxy, syy);
                if (c->ghost > 0)
                    vp_camsim_spot(acc, w, h, tr.uv[0] + c->ghost_offset[0], tr.uv[1] + c->ghost_offset[1],
                                   tr.energy * c->ghost, sxx, sxy, syy);
            }
        }
    }
    if (!sc->surf && sc->mark_peak > 0) {
        /* the printed mark: a dot of radius mark_sigma on the plane, seen whatever the laser does;
         * its footprint through the camera's local projection (as the beam's) */
        double mc[3], vc[3], a[3] = { 0, 0, 1 }, t1[3], t2[3], uv0[2], uv1[2], j1[2], j2[2], q[3], sxx, sxy, syy;
        double ms = sc->mark_sigma > 0 ? sc->mark_sigma : 0.4, step = 0.01, l;
        vp_mul(rot, c->cam.pos, mc);
        for (i = 0; i < 3; i++) { mc[i] += pos[i]; vc[i] = mc[i] - sc->mark[i]; }
        if (fabs(sc->plane_n[2]) > 0.9 * vp_norm3(sc->plane_n)) { a[0] = 1; a[2] = 0; }
        vp_cross3(t1, sc->plane_n, a);
        l = vp_norm3(t1);
        for (i = 0; i < 3; i++) t1[i] /= l;
        vp_cross3(t2, sc->plane_n, t1);
        l = vp_norm3(t2);
        for (i = 0; i < 3; i++) t2[i] /= l;
        if (fabs(vp_dot3(sc->plane_n, vc)) > 1e-6 && vp_camsim_proj(c, rot, pos, sc->mark, uv0) && uv0[0] > -20 &&
            uv0[0] < w + 20 && uv0[1] > -20 && uv0[1] < h + 20) {
            for (i = 0; i < 3; i++) q[i] = sc->mark[i] + step * t1[i];
            vp_camsim_proj(c, rot, pos, q, uv1);
            j1[0] = (uv1[0] - uv0[0]) / step * ms; j1[1] = (uv1[1] - uv0[1]) / step * ms;
            for (i = 0; i < 3; i++) q[i] = sc->mark[i] + step * t2[i];
            vp_camsim_proj(c, rot, pos, q, uv1);
            j2[0] = (uv1[0] - uv0[0]) / step * ms; j2[1] = (uv1[1] - uv0[1]) / step * ms;
            sxx = blur * blur + j1[0] * j1[0] + j2[0] * j2[0];
            syy = blur * blur + j1[1] * j1[1] + j2[1] * j2[1];
            sxy = j1[0] * j1[1] + j2[0] * j2[1];
            vp_camsim_spot(acc, w, h, uv0[0], uv0[1], sc->mark_peak * 2 * VP_PI * sqrt(sxx * syy - sxy * sxy), sxx, sxy, syy);
        }
    }
    if (c->lamp_peak > 0 && c->lamp_sigma > 0)
        vp_camsim_spot(acc, w, h, c->lamp_uv[0], c->lamp_uv[1], tr.ambient_gain * c->lamp_peak * 2 * VP_PI * c->lamp_sigma * c->lamp_sigma,
                       c->lamp_sigma * c->lamp_sigma, 0, c->lamp_sigma * c->lamp_sigma);
    if (c->highlight_peak > 0) {
        /* an ambient highlight beside the laser line: where the beam's image would be for a
         * surface at highlight_dist, moved across the line; lit whatever the laser does */
        double p1[3], p2[3], u1[2], u2[2], e[2], l, sg = c->highlight_sigma > 0 ? c->highlight_sigma : 1.5;
        double bd[3];
        vp_camsim_beam(c, bd);
        for (i = 0; i < 3; i++) {
            p1[i] = c->laser_offset[i] + c->highlight_dist * bd[i];
            p2[i] = c->laser_offset[i] + (c->highlight_dist + 1) * bd[i];
        }
        if (vp_camsim_image(&c->cam, p1, u1) && vp_camsim_image(&c->cam, p2, u2)) {
            e[0] = u2[0] - u1[0]; e[1] = u2[1] - u1[1];
            l = sqrt(e[0] * e[0] + e[1] * e[1]);
            if (l > 1e-12) { e[0] /= l; e[1] /= l; } else { e[0] = 1; e[1] = 0; }
            double ox = -c->highlight_off_px * e[1], oy = c->highlight_off_px * e[0];
            if (c->laser_kind == VP_CAMSIM_LINE) { ox = c->highlight_off_px * e[0]; oy = c->highlight_off_px * e[1]; }
            vp_camsim_spot(acc, w, h, u1[0] + ox, u1[1] + oy,
                           tr.ambient_gain * c->highlight_peak * 2 * VP_PI * sg * sg, sg * sg, 0, sg * sg);
        }
    }
    if (c->glint_peak > 0) {
        /* a glint of a lamp on a shiny part, lit by the ambient light alone, swinging across the
         * laser line (something in the room moves): it is where it was in neither frame of a pair */
        double p1[3], p2[3], u1[2], u2[2], e[2], l, sg = c->glint_sigma > 0 ? c->glint_sigma : 3;
        double per = (c->glint_period_ms > 0 ? c->glint_period_ms : 500) * 1e6, mv;
        mv = c->glint_move_px * sin(2 * VP_PI * fmod((double)t_exp, per) / per);
        for (i = 0; i < 3; i++) p1[i] = p2[i] = c->laser_offset[i];
        p1[0] += c->glint_dist;
        p2[0] += c->glint_dist + 1;
        if (vp_camera_project(&c->cam, p1, u1) && vp_camera_project(&c->cam, p2, u2)) {
            e[0] = u2[0] - u1[0]; e[1] = u2[1] - u1[1];
            l = sqrt(e[0] * e[0] + e[1] * e[1]);
            if (l > 1e-12) { e[0] /= l; e[1] /= l; } else { e[0] = 1; e[1] = 0; }
            double ox = -(c->glint_off_px + mv) * e[1], oy = (c->glint_off_px + mv) * e[0];
            if (c->laser_kind == VP_CAMSIM_LINE) { ox = (c->glint_off_px + mv) * e[0]; oy = (c->glint_off_px + mv) * e[1]; }
            vp_camsim_spot(acc, w, h, u1[0] + ox, u1[1] + oy,
                           tr.ambient_gain * c->glint_peak * 2 * VP_PI * sg * sg, sg * sg, 0, sg * sg);
        }
    }
    for (i = 0; i < c->hot_pixels; i++) acc[vp_rng_below(rng, (uint64_t)w * h)] = 255;
    /* noise, quantisation, saturation */
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double v = acc[(size_t)y * w + x] + (c->noise > 0 ? c->noise * vp_camsim_gauss(rng) : 0);
            long q = lround(v);
            img[(size_t)y * stride + x] = (uint8_t)(q < 0 ? 0 : q > 255 ? 255 : q);
        }
    free(acc);
    if (truth) *truth = tr;
    return VP_OK;
}

int vp_camsim_render(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, const double rot[9], const double pos[3],
                     vp_rng_t *rng, uint8_t *img, int stride, vp_camsim_truth_t *truth)
{
    return vp_camsim_draw(c, sc, rot, pos, rng, img, stride, truth, 1, 0, INT64_MIN, NULL);
}

int vp_camsim_render_ex(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, const double rot[9], const double pos[3],
                        vp_rng_t *rng, uint8_t *img, int stride, int laser, int64_t t_ns, vp_camsim_truth_t *truth,
                        vp_camsim_line_truth_t *line)
{
    return vp_camsim_draw(c, sc, rot, pos, rng, img, stride, truth, laser != 0, t_ns, INT64_MIN, line);
}

/* ---- the camera backend ---- */

#define VP_CAMSIM_HIST 32

struct vp_camsim {
    vp_camsim_config_t cfg;
    vp_camsim_scene_t scene;
    vp_rng_t rng;
    void (*pose)(void *ctx, double rot[9], double pos[3]);
    int64_t (*clock)(void *ctx);
    void *ctx;
    uint8_t *buf;
    int busy;
    vp_camsim_truth_t last, prev;
    vp_camsim_stream_t st;
    int64_t next;                          /* sequence number of the next frame to hand out */
    int64_t last_seq, last_ts;             /* of the frame handed out last (-1: none) */
    int64_t handed;                        /* frames handed out */
    int64_t hist_t[VP_CAMSIM_HIST];        /* the laser line as seen at mark/capture times */
    int hist_on[VP_CAMSIM_HIST], nhist;
    int64_t moved_at;                      /* the last step written (INT64_MIN: none yet) */
    vp_camsim_truth_t kept[VP_CAMSIM_HIST];    /* the truths of the frames handed out last */
    int nkept;
};

int vp_camsim_create(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, uint64_t seed,
                     void (*pose)(void *ctx, double rot[9], double pos[3]), int64_t (*clock)(void *ctx), void *ctx,
                     vp_camsim_t **out)
{
    vp_camsim_t *cs;
    if (!c || !sc || !pose || !out || c->cam.width < 8 || c->cam.height < 8) return VP_EINVAL;
    cs = calloc(1, sizeof *cs);
    if (!cs) return VP_ENOMEM;
    cs->buf = malloc((size_t)c->cam.width * c->cam.height);
    if (!cs->buf) { free(cs); return VP_ENOMEM; }
    cs->cfg = *c;
    cs->scene = *sc;
    vp_rng_seed(&cs->rng, seed);
    cs->pose = pose;
    cs->clock = clock;
    cs->ctx = ctx;
    cs->last_seq = cs->last_ts = -1;
    cs->moved_at = INT64_MIN;
    cs->cfg.speckle_seed = cs->cfg.speckle_seed ? cs->cfg.speckle_seed : vp_mix64(seed);
    *out = cs;
    return VP_OK;
}

static int vp_camsim_laser_now(const vp_camsim_t *cs) { return cs->st.laser ? cs->st.laser(cs->ctx) != 0 : 1; }
static int64_t vp_camsim_now(const vp_camsim_t *cs) { return cs->clock ? cs->clock(cs->ctx) : 0; }

/* the laser line now, into the history (kept in time order) */
static void vp_camsim_note(vp_camsim_t *cs)
{
    int64_t t = vp_camsim_now(cs);
    int on = vp_camsim_laser_now(cs);
    if (cs->nhist > 0 && cs->hist_t[(cs->nhist - 1) % VP_CAMSIM_HIST] == t) {
        cs->hist_on[(cs->nhist - 1) % VP_CAMSIM_HIST] = on;
        return;
    }
    cs->hist_t[cs->nhist % VP_CAMSIM_HIST] = t;
    cs->hist_on[cs->nhist % VP_CAMSIM_HIST] = on;
    cs->nhist++;
}

/* the laser line at time t: the last state noted at or before t (off before the history) */
static int vp_camsim_laser_at(const vp_camsim_t *cs, int64_t t)
{
    int k, n = cs->nhist < VP_CAMSIM_HIST ? cs->nhist : VP_CAMSIM_HIST;
    for (k = 1; k <= n; k++) {
        int i = (cs->nhist - k) % VP_CAMSIM_HIST;
        if (cs->hist_t[i] <= t) return cs->hist_on[i];
    }
    return 0;
}

/* Stream mode: frame s is exposed from s P (the laser as it was then), and handed over
 * `latency` frames later, stamped then: at (s + latency) P + 1 ns. So after a mark at T the
 * first `latency` frames handed out were exposed before T, though some are stamped after it. */
static int64_t vp_camsim_at(const vp_camsim_t *cs, int64_t s) { return (s + cs->st.latency) * cs->st.period_ns + 1; }

/* newest frame handed over by time t */
static int64_t vp_camsim_newest(const vp_camsim_t *cs, int64_t t)
{
    return (t + cs->st.period_ns - 1) / cs->st.period_ns - 1 - cs->st.latency;
}

static int vp_camsim_mark(void *ctx, int64_t *next_seq)
{
    vp_camsim_t *cs = ctx;
    vp_camsim_note(cs);
    if (cs->st.period_ns > 0) {
        int64_t d = vp_camsim_newest(cs, vp_camsim_now(cs));
        if (d + 1 > cs->next) cs->next = d + 1;
    }
    *next_seq = cs->next;
    return VP_OK;
}

static int vp_camsim_capture(void *ctx, int64_t not_before, int timeout_ms, vp_frame_t *f)
{
    vp_camsim_t *cs = ctx;
    double rot[9], pos[3];
    int64_t s, ts, want = f->seq, t_exp;
    int laser, q;
    if (cs->busy) return VP_ESTATE;
    vp_camsim_note(cs);
    if (cs->st.period_ns <= 0) {
        /* at once: the frame of now (frames below the sequence number asked for are skipped) */
        s = want > cs->next ? want : cs->next;
        ts = t_exp = vp_camsim_now(cs);
        laser = vp_camsim_laser_now(cs);
    } else {
        const int64_t P = cs->st.period_ns;
        int64_t now = vp_camsim_now(cs), d = vp_camsim_newest(cs, now), deadline = now + (int64_t)timeout_ms * 1000000;
        q = cs->st.queue > 0 ? cs->st.queue : 4;
        s = cs->next;
        if (s < d - q + 1) s = d - q + 1;          /* the queue keeps the newest q */
        if (not_before > deadline) return VP_ETIMEOUT; /* any frame it could take is later still */
        for (;;) {
            int64_t at = vp_camsim_at(cs, s);
            /* waiting frames below the number asked for, and those stamped before not_before, go
             * back unseen; then wait for the one wanted */
            if (s < want && !cs->st.every_frame) { s = want; continue; }
            if (at < not_before) {
                /* straight to the first frame stamped at or after not_before (one at a time from
                 * a stamp far ahead took ~1e10 turns) */
                int64_t j = (not_before - 1) / P + ((not_before - 1) % P != 0) - cs->st.latency; /* not_before > at >= 1 */
                s = j > s ? j : s + 1;
                continue;
            }
            if (at > now) {
                if (at > deadline || !cs->st.wait_until) return VP_ETIMEOUT;
                VP_TRY(cs->st.wait_until(cs->ctx, at));
                now = vp_camsim_now(cs);
            }
            break;
        }
        ts = vp_camsim_at(cs, s);
        t_exp = s * P;
        laser = vp_camsim_laser_at(cs, t_exp);
    }
    /* an injected fault: this frame numbered or stamped older than the one before */
    cs->handed++;
    if (cs->st.back_at > 0 && cs->handed == cs->st.back_at && cs->last_seq >= 0) {
        if (cs->st.back_kind == 2) s = cs->last_seq - 1;
        else ts = cs->last_ts - 1;
    }
    cs->pose(cs->ctx, rot, pos);
    cs->prev = cs->last;
    VP_TRY(vp_camsim_draw(&cs->cfg, &cs->scene, rot, pos, &cs->rng, cs->buf, cs->cfg.cam.width, &cs->last, laser, t_exp,
                          cs->moved_at, NULL));
    cs->last.seq = s;
    cs->last.t_ns = ts;
    cs->kept[cs->nkept++ % VP_CAMSIM_HIST] = cs->last;
    if (s + 1 > cs->next) cs->next = s + 1;
    cs->last_seq = s;
    cs->last_ts = ts;
    f->data = cs->buf;
    f->width = cs->cfg.cam.width;
    f->height = cs->cfg.cam.height;
    f->stride = cs->cfg.cam.width;
    f->step = 1;
    f->t_ns = ts;
    f->index = 0;
    f->seq = s;
    cs->busy = 1;
    return VP_OK;
}

static void vp_camsim_release(void *ctx, vp_frame_t *f) { (void)f; ((vp_camsim_t *)ctx)->busy = 0; }
static void vp_camsim_close_cb(void *ctx) { vp_camsim_destroy(ctx); }

vp_cam_t vp_camsim_cam(vp_camsim_t *cs)
{
    vp_cam_t c;
    c.ctx = cs;
    c.capture = vp_camsim_capture;
    c.release = vp_camsim_release;
    c.close = vp_camsim_close_cb;
    c.error = NULL;
    c.mark = vp_camsim_mark;
    c.name = "camsim";
    return c;
}

void vp_camsim_seed(vp_camsim_t *cs, uint64_t seed) { vp_rng_seed(&cs->rng, seed); }

const vp_camsim_truth_t *vp_camsim_last(const vp_camsim_t *cs) { return &cs->last; }
const vp_camsim_truth_t *vp_camsim_prev(const vp_camsim_t *cs) { return &cs->prev; }
vp_camsim_config_t *vp_camsim_config(vp_camsim_t *cs) { return &cs->cfg; }

const vp_camsim_truth_t *vp_camsim_truth_of(const vp_camsim_t *cs, int64_t seq)
{
    int k, n = cs->nkept < VP_CAMSIM_HIST ? cs->nkept : VP_CAMSIM_HIST;
    for (k = 1; k <= n; k++) {
        const vp_camsim_truth_t *t = &cs->kept[(cs->nkept - k) % VP_CAMSIM_HIST];
        if (t->seq == seq) return t;
    }
    return NULL;
}

void vp_camsim_laser_switched(vp_camsim_t *cs) { if (cs) vp_camsim_note(cs); }
void vp_camsim_moved(vp_camsim_t *cs) { if (cs) cs->moved_at = vp_camsim_now(cs); }

vp_camsim_stream_t *vp_camsim_stream(vp_camsim_t *cs) { return &cs->st; }

int vp_camsim_fault(vp_camsim_t *cs, int64_t at, int kind)
{
    if (!cs || at < 1 || kind < 1 || kind > 2) return VP_EINVAL;
    cs->st.back_at = cs->handed + at;
    cs->st.back_kind = kind;
    return VP_OK;
}

int vp_camsim_set_stream(vp_camsim_t *cs, const vp_camsim_stream_t *s)
{
    if (!cs || !s || s->period_ns < 0 || s->latency < 0 || s->queue < 0 || (s->period_ns > 0 && !s->wait_until)) return VP_EINVAL;
    cs->st = *s;
    return VP_OK;
}

void vp_camsim_destroy(vp_camsim_t *cs)
{
    if (!cs) return;
    free(cs->buf);
    free(cs);
}
