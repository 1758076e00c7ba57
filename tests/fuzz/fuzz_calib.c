/* libFuzzer target: the rangefinder's calibration fits (port/vp_calib.c vp_rf_fit and
 * vp_rf_fit_camera, port/vp_laser.c vp_tri_fit). Their input is what a user's calibration session
 * saw: marks of a target at known places and laser spots on target planes, with whatever the
 * detection got wrong. The target makes a true head (the board files' camera and beam, moved by
 * up to a few pixels, a degree and a millimetre as the input says), images marks at 1-5 depths and
 * spots at 0-31 distances through it (plus noise of up to 0.3 px), then spoils them as the rest of
 * the input says (a NaN, a kind that is none, an outlier, a copy, a spot's plane moved or not
 * unit, marks or spots taken away).
 *
 * Input: b0-b7 the true head; b8 the depths, b9 the spots, b10 the noise, b11 bit 0 the camera
 * alone; then (what, which, how much) triples, each one spoiling.
 *
 * What must hold: a status of VP_OK, VP_EINVAL or VP_EDEGEN, VP_EINVAL whenever a NaN or a bad
 * kind is among the observations; on VP_OK a model of finite numbers, a unit beam, a span with
 * min < max, a report whose rms, worst residual and strays (beyond 6 px) agree with the ones
 * worked out here from the model returned (a projection of this file's own, written from
 * vp_laser.h's formula), and not both an rms above 10 px and over 1 in 10 astray; on exact, unspoiled observations from 3 depths and 8 distances or more, VP_OK with residuals
 * below 0.01 px (a fit that stops short, or says it cannot, on what fixes every parameter, is a
 * finding). vp_tri_fit on the spots alone (before the spoiling): a status, VP_OK or VP_EDEGEN from
 * 4 spots up, and on VP_OK finite numbers whose worst distance error is the one reported. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "vp_calib.h"
#include "vp_laser.h"
#include "vp_status.h"
#include "../port/ref_camera.h"
#ifdef FUZZ_CALIB_SHOW /* what an input gives, to check that the seeds reach the fitted cases */
#include <stdio.h>
#define SHOW(...) fprintf(stderr, __VA_ARGS__)
#else
#define SHOW(...) ((void)0)
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAXOBS 256
#define PI 3.14159265358979323846

/* a reproducible normal deviate from a counter (the noise) */
static double noise_at(uint32_t k)
{
    uint32_t a = k * 2654435761u ^ 0x9E3779B9u, b;
    double u1, u2;
    a ^= a >> 15; a *= 0x2C1B3C6Du; a ^= a >> 12;
    b = a * 0x297A2D39u; b ^= b >> 15;
    u1 = ((a >> 8) + 0.5) / 16777216.0;
    u2 = ((b >> 8) + 0.5) / 16777216.0;
    return sqrt(-2 * log(u1)) * cos(2 * PI * u2);
}

/* the residual of one observation under model m, px (-1 when it has none: behind the camera) */
static double residual(const vp_rf_model_t *m, const vp_calib_obs_t *o)
{
    double p[3], uv[2], den;
    int k;
    if (o->kind == VP_OBS_MARK) {
        if (!ref_project(&m->cam, o->p, uv)) return -1;
    } else {
        /* the beam's crossing of the target plane n.x = h */
        den = o->n[0] * m->dir[0] + o->n[1] * m->dir[1] + o->n[2] * m->dir[2];
        if (!(fabs(den) > 1e-12)) return -1;
        for (k = 0; k < 3; k++)
            p[k] = m->origin[k] + (o->h - (o->n[0] * m->origin[0] + o->n[1] * m->origin[1] + o->n[2] * m->origin[2])) / den * m->dir[k];
        if (!ref_project(&m->cam, p, uv)) return -1;
    }
    return hypot(uv[0] - o->uv[0], uv[1] - o->uv[1]);
}

static int all_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static vp_calib_obs_t obs[MAXOBS];
    static double tuv[MAXOBS][2], td[MAXOBS];
    static const double zs[5] = { 40, 70, 120, 200, 300 };
    uint8_t h[12] = { 0 };
    vp_camera_model_t cam;
    vp_rf_model_t nominal, truth, out;
    vp_rf_fit_report_t rep;
    int n = 0, nmark = 0, nspot = 0, depths, spots, i, j, k, st, spoiled = 0, bad = 0, camera_only;
    double noise, a, axis[3] = { 0.6, 0.48, 0.64 };
    size_t at;
    memcpy(h, data, size < sizeof h ? size : sizeof h);
    /* the board files' camera (640 x 480, focal 350 px, 30 mm beside the laser, looking 100 mm out) */
    memset(&cam, 0, sizeof cam);
    cam.width = 640;
    cam.height = 480;
    cam.fx = cam.fy = 350;
    cam.cx = 319.5;
    cam.cy = 239.5;
    cam.pos[1] = 30;
    cam.pos[2] = 10;
    if (vp_camera_look_at(&cam, (double[3]){ 100, 0, 0 }, (double[3]){ 0, 0, 1 }) != VP_OK) __builtin_trap();
    if (vp_rf_nominal(&cam, (double[3]){ 20, 0, 0 }, 10, 400, &nominal) != VP_OK) __builtin_trap();
    /* the true head: the nominal one moved as b0-b7 say */
    truth = nominal;
    truth.cam.fx = 350 + (h[0] - 128) / 10.0;
    truth.cam.fy = truth.cam.fx * (1 + (h[1] - 128) / 12800.0);
    truth.cam.cx = 319.5 + (h[2] - 128) / 16.0;
    truth.cam.cy = 239.5 + (h[3] - 128) / 16.0;
    truth.cam.dist[0] = -0.3 + h[4] / 640.0;
    truth.cam.dist[1] = (h[5] - 128) / 2560.0;
    truth.cam.dist[2] = (h[6] & 15) / 5000.0 - 0.0015;
    truth.cam.dist[3] = (h[6] >> 4) / 5000.0 - 0.0015;
    for (k = 0; k < 3; k++) axis[k] /= sqrt(0.6 * 0.6 + 0.48 * 0.48 + 0.64 * 0.64);
    ref_turn(truth.cam.rot, axis, (h[7] - 128) / 128.0 * PI / 180);
    truth.cam.pos[0] += (h[7] & 7) / 7.0 - 0.5;
    truth.origin[1] += (h[1] & 7) / 7.0 - 0.5;
    truth.origin[2] -= (h[2] & 7) / 7.0 - 0.5;
    a = (h[5] & 15) / 10.0 * PI / 180;
    truth.dir[0] = cos(a);
    truth.dir[1] = sin(a) * cos(h[4] * PI / 128);
    truth.dir[2] = sin(a) * sin(h[4] * PI / 128);
    depths = 1 + h[8] % 5;
    spots = h[9] % 32;
    noise = (h[10] % 4) * 0.1;
    camera_only = h[11] & 1;
    /* marks over the image at the depths, spots at distances from 400 mm down to 10 mm */
    for (i = 0; i < depths; i++)
        for (j = 0; j < 40 && n < MAXOBS; j++) {
            double want[2] = { 30 + 580.0 * (j % 8) / 7, 30 + 420.0 * (j / 8) / 4 }, r[3], uv[2];
            if (vp_camera_ray(&nominal.cam, want, r) != VP_OK) continue;
            memset(&obs[n], 0, sizeof obs[n]);
            for (k = 0; k < 3; k++) obs[n].p[k] = nominal.cam.pos[k] + zs[depths == 1 ? 2 : i] * r[k];
            if (!ref_project(&truth.cam, obs[n].p, uv) || uv[0] < 0 || uv[1] < 0 || uv[0] > 639 || uv[1] > 479) continue;
            obs[n].kind = VP_OBS_MARK;
            obs[n].uv[0] = uv[0] + noise * noise_at(2u * (uint32_t)n);
            obs[n].uv[1] = uv[1] + noise * noise_at(2u * (uint32_t)n + 1u);
            n++;
            nmark++;
        }
    if (!camera_only)
        for (i = 0; i < spots && n < MAXOBS; i++) {
            double d = spots == 1 ? 150 : 1 / (1 / 400.0 + (1 / 10.0 - 1 / 400.0) * i / (spots - 1)), tilt = i % 2 ? 0.05 : 0;
            double p[3], uv[2];
            memset(&obs[n], 0, sizeof obs[n]);
            obs[n].kind = VP_OBS_SPOT;
            obs[n].n[0] = cos(tilt);
            obs[n].n[1] = sin(tilt);
            for (k = 0; k < 3; k++) p[k] = truth.origin[k] + d * truth.dir[k];
            obs[n].h = obs[n].n[0] * p[0] + obs[n].n[1] * p[1];
            if (!ref_project(&truth.cam, p, uv)) continue;
            obs[n].uv[0] = uv[0] + noise * noise_at(2u * (uint32_t)n);
            obs[n].uv[1] = uv[1] + noise * noise_at(2u * (uint32_t)n + 1u);
            tuv[nspot][0] = obs[n].uv[0];
            tuv[nspot][1] = obs[n].uv[1];
            td[nspot] = d;
            n++;
            nspot++;
        }
    /* the spoiling: (what, which, how much) */
    for (at = sizeof h; at + 3 <= size && n > 0; at += 3) {
        vp_calib_obs_t *o = &obs[data[at + 1] % n];
        int v = data[at + 2];
        switch (data[at] % 8) {
        case 0: break;
        case 1: o->uv[v & 1] = NAN; bad = 1; break;                      /* a NaN */
        case 2: o->kind = v % 4 == 0 ? 0 : 3 + v; bad = 1; break;        /* no kind */
        case 3: o->uv[v & 1] += (v - 128) * 2.0; break;                  /* an outlier */
        case 4: if (n < MAXOBS) { obs[n] = *o; n++; } break;            /* a copy */
        case 5: o->h += (v - 128) * 0.5; break;                          /* the plane elsewhere */
        case 6: o->n[0] *= 1 + v / 64.0; break;                          /* not unit */
        default: n = n > v % 16 ? n - v % 16 : 0; break;                 /* the last ones lost */
        }
        spoiled = 1;
    }
    memset(&out, 0xA5, sizeof out);
    memset(&rep, 0, sizeof rep);
    st = camera_only ? vp_rf_fit_camera(obs, n, &nominal, &out, &rep) : vp_rf_fit(obs, n, &nominal, &out, &rep);
    SHOW("fit status %d\n", st);
    if (st != VP_OK && st != VP_EINVAL && st != VP_EDEGEN) __builtin_trap();
    if (bad && st != VP_EINVAL) {
        /* a NaN or a bad kind among those the fit was given must be refused */
        for (i = 0; i < n; i++)
            if ((obs[i].kind != VP_OBS_MARK && obs[i].kind != VP_OBS_SPOT) || !all_finite(obs[i].uv, 2)) __builtin_trap();
    }
    if (!spoiled && noise == 0 && depths >= 3 && (camera_only || spots >= 8) && st != VP_OK) __builtin_trap();
    if (st == VP_OK) {
        double ss = 0, worst = 0, len;
        int m = 0, strays = 0;
        if (!all_finite(&out.cam.fx, 4) || !all_finite(out.cam.dist, 4) || !all_finite(out.cam.pos, 3) ||
            !all_finite(out.cam.rot, 9) || !all_finite(out.origin, 3) || !all_finite(out.dir, 3) ||
            !isfinite(out.min_range) || !isfinite(out.max_range) || !(out.min_range < out.max_range))
            __builtin_trap();
        len = sqrt(out.dir[0] * out.dir[0] + out.dir[1] * out.dir[1] + out.dir[2] * out.dir[2]);
        if (!(fabs(len - 1) < 1e-9)) __builtin_trap();
        if (!isfinite(rep.rms_px) || !isfinite(rep.max_px) || rep.rms_px < 0 || rep.max_px < rep.rms_px * (1 - 1e-9))
            __builtin_trap();
        /* the report against the residuals worked out here */
        for (i = 0; i < n; i++) {
            double r;
            if (camera_only && obs[i].kind != VP_OBS_MARK) continue;
            r = residual(&out, &obs[i]);
            if (r < 0) continue;
            ss += r * r;
            if (r > worst) worst = r;
            strays += r > 3 * VP_CALIB_HUBER_PX;
            m++;
        }
        if (m > 0 && (fabs(sqrt(ss / m) - rep.rms_px) > 1e-6 * (1 + rep.rms_px) || fabs(worst - rep.max_px) > 1e-6 * (1 + worst)))
            __builtin_trap();
        /* the strays it names, and its own rule: no fit with an rms above 10 px and over 1 in 10 astray */
        if (m == n && rep.strays != strays) __builtin_trap();
        if (m == n && !(sqrt(ss / m) < 10) && 10 * strays > n) __builtin_trap();
        SHOW("fit: %d obs (%d marks, %d spots), rms %.6f px (here %.6f over %d), worst %.6f (here %.6f)\n", n, nmark, nspot,
             rep.rms_px, m > 0 ? sqrt(ss / m) : -1.0, m, rep.max_px, worst);
        if (!spoiled && noise == 0 && (worst > 0.01 || !(rep.rms_px < 0.01))) __builtin_trap();
    }
    /* the spots alone through the epipolar model */
    if (nspot > 0) {
        vp_tri_model_t tm;
        vp_tri_fit_report_t tr;
        st = vp_tri_fit((const double(*)[2])tuv, td, nspot, 640, 480, &tm, &tr);
        if (st != VP_OK && st != VP_EINVAL && st != VP_EDEGEN) __builtin_trap();
        if (nspot >= 4 && st == VP_EINVAL) __builtin_trap();
        if (st == VP_OK) {
            double worst = 0;
            if (!all_finite(tm.p0, 2) || !all_finite(tm.e, 2) || !isfinite(tm.a) || !isfinite(tm.b) || !isfinite(tm.c) ||
                !isfinite(tr.rms_mm) || !isfinite(tr.max_mm))
                __builtin_trap();
            for (i = 0; i < nspot; i++) {
                /* d = (a + b s) / (1 + c s), s along the line from p0 */
                double s = (tuv[i][0] - tm.p0[0]) * tm.e[0] + (tuv[i][1] - tm.p0[1]) * tm.e[1];
                double d = (tm.a + tm.b * s) / (1 + tm.c * s);
                if (fabs(d - td[i]) > worst) worst = fabs(d - td[i]);
            }
            /* the report against the distances worked out here (the lens bends the spots' line, so
             * the model is not exact even on exact spots) */
            SHOW("tri: %d spots, max %.6f mm (here %.6f)\n", nspot, tr.max_mm, worst);
            if (fabs(worst - tr.max_mm) > 1e-6 * (1 + worst)) __builtin_trap();
        }
    }
    return 0;
}
