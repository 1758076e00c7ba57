/* libFuzzer target: camera frames as the rangefinder reads them (port/vp_laser.c, port/vp_line.c).
 * A frame is bytes a driver hands over, and anything may be in it: the spot finder
 * (vp_spot_find, vp_laser_measure) and the line finder (vp_line_detect, a laser-on / laser-off
 * pair) read frames of any size from 8 x 8 up, grey or YUYV, rows padded or not, each held in a
 * buffer of exactly its size (a read past it is an ASan report), with and without the
 * triangulation model, a spot or a line drawn over whatever texture the input gives.
 *
 * Input: b0, b1 the size (8-135 px each way); b2 flags (bit 0 YUYV, bit 1 padded rows, bit 2 a
 * model, bit 3 a spot drawn, bit 4 a second one, bit 5 a line drawn, bit 6 the drawing clipped at
 * 255, bit 7 the laser-off frame its own bytes rather than the texture); b3 the padding, the
 * spot's band and the line's column step; b4-b9 where the spot and the line lie, how bright and
 * how wide; b10 a field of the spot finder's configuration set in or out of its range (0: the
 * defaults); b11 the beam's image line in the model turned, down to nearly along the rows (0: as
 * the camera gives it); the rest the texture, repeated over the frame.
 *
 * What must hold (besides no crash and no sanitizer report): a configuration out of range is
 * refused (VP_EINVAL) with nothing written; with one in range a valid frame is never refused; a
 * spot found lies on the sensor (pixel centres 0 .. size - 1, each pixel reaching half a pixel
 * either way: a centre fitted between rows 0 and 1 may lie a little above row 0) with a finite
 * centre and an area the spot's box can hold; a hit's distance lies within the model's range; a
 * line point lies in its column, on the sensor, one per column looked at, and with a model at a
 * distance within its range along a unit direction; every column is counted once by its
 * outcome; and the answers do not depend on what the workspace held before (each call is made
 * twice, the workspace scribbled over in between). */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_laser.h"
#include "vp_line.h"
#include "vp_status.h"
#ifdef FUZZ_FRAME_SHOW /* what an input finds, to check that the seeds reach the found cases */
#include <stdio.h>
#define SHOW(...) fprintf(stderr, __VA_ARGS__)
#else
#define SHOW(...) ((void)0)
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define HDR 12

static vp_spot_ws_t sws;
static vp_line_ws_t lws;

/* a frame of w x h of `step` bytes per pixel and `pad` more per row, in a buffer of exactly its
 * size; the luma from the texture, plus the spot and the line */
static uint8_t *make_frame(vp_frame_t *f, int w, int h, int step, int pad, const uint8_t *tex, size_t ntex,
                           const uint8_t *hdr, int spots, int line, int clip)
{
    size_t stride = (size_t)w * (size_t)step + (size_t)pad, n = stride * (size_t)h, i;
    uint8_t *buf = malloc(n);
    int x, y, k;
    if (!buf) return NULL;
    for (i = 0; i < n; i++) buf[i] = ntex ? tex[i % ntex] : (uint8_t)40;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double add = 0.0;
            for (k = 0; k < spots; k++) {
                /* a Gaussian spot: centre, peak and width from the header (the second one mirrored) */
                double cu = (k ? 255 - hdr[4] : hdr[4]) * (w - 1) / 255.0, cv = (k ? 255 - hdr[5] : hdr[5]) * (h - 1) / 255.0;
                double s = 0.6 + (hdr[7] & 15) * 0.5, a = 20.0 + hdr[6];
                add += a * exp(-((x - cu) * (x - cu) + (y - cv) * (y - cv)) / (2 * s * s));
            }
            if (line) {
                /* a line across the frame: v = v0 + slope (u - w/2) */
                double v0 = hdr[8] * (h - 1) / 255.0, slope = ((int)hdr[9] - 128) / 64.0, s = 0.8 + (hdr[7] >> 4) * 0.4;
                double dv = y - (v0 + slope * (x - w / 2.0));
                add += (20.0 + hdr[6]) * exp(-dv * dv / (2 * s * s));
            }
            if (add > 0.0) {
                uint8_t *p = buf + (size_t)y * stride + (size_t)x * (size_t)step;
                double v = *p + add;
                *p = (uint8_t)(v > 255.0 ? (clip ? 255.0 : fmod(v, 256.0)) : v);
            }
        }
    memset(f, 0, sizeof *f);
    f->data = buf;
    f->width = w;
    f->height = h;
    f->stride = (int)stride;
    f->step = step;
    return buf;
}

/* the head of the board files, scaled to the frame: the laser at (20, 0, 0) along +x, the camera
 * 30 mm beside it looking 100 mm out */
static void camera(vp_camera_model_t *c, int w, int h)
{
    memset(c, 0, sizeof *c);
    c->width = w;
    c->height = h;
    c->fx = c->fy = 0.55 * w;
    c->cx = (w - 1) / 2.0;
    c->cy = (h - 1) / 2.0;
    c->pos[1] = 30;
    c->pos[2] = 10;
    vp_camera_look_at(c, (double[3]){ 100, 0, 0 }, (double[3]){ 0, 0, 1 });
}

/* b10: one field of the spot finder's configuration set to a value in or out of its range (0:
 * the defaults); 1 if the result is in range (block 0-4096, percentile and rel_thresh 0-1, the
 * others finite and not negative) */
static int spoil_config(vp_spot_config_t *c, int b)
{
    static const double val[8] = { -1, NAN, INFINITY, 1e300, 0.5, 2, 4096, 5000 };
    double v = val[(b >> 3) & 7];
    int iv = (b >> 3) & 7;
    static const int ival[8] = { -1, 0, 2147483647, 1000000000, 1, 2, 4096, 5000 };
    if (!b) return 1;
    switch (b & 7) {
    case 0: c->block = ival[iv]; return c->block >= 0 && c->block <= VP_SPOT_MAX_W;
    case 1: c->percentile = v; return v >= 0 && v <= 1;
    case 2: c->min_snr = v; return v >= 0 && isfinite(v);
    case 3: c->min_peak = v; return v >= 0 && isfinite(v);
    case 4: c->rel_thresh = v; return v >= 0 && v <= 1;
    case 5: c->second_ratio = v; return v >= 0 && isfinite(v);
    case 6: c->max_radius = ival[iv]; return c->max_radius >= 0;
    default: c->band = v; return v >= 0 && isfinite(v);
    }
}

static void check_spot(const vp_frame_t *f, const vp_spot_config_t *cfg, const vp_tri_model_t *m, int valid)
{
    vp_spot_t a, b, s;
    double d = NAN;
    int st, hit, R = cfg->max_radius > 0 ? (cfg->max_radius < VP_SPOT_MAX_R ? cfg->max_radius : VP_SPOT_MAX_R) : 16;
    memset(&sws, 0, sizeof sws);
    if (!valid) {
        /* a configuration out of range: refused, nothing written */
        memset(&a, 0x5A, sizeof a);
        memcpy(&b, &a, sizeof b);
        if (vp_spot_find(f, cfg, m, &sws, &a) != VP_EINVAL || memcmp(&a, &b, sizeof a) != 0) __builtin_trap();
        if (m && vp_laser_measure(f, cfg, m, &sws, &s, &d) != VP_EINVAL) __builtin_trap();
        return;
    }
    st = vp_spot_find(f, cfg, m, &sws, &a);
    if (st != VP_OK) __builtin_trap(); /* a valid frame is never refused */
    if (a.result < VP_SPOT_OFF_LINE || a.result > VP_SPOT_FOUND) __builtin_trap();
    if (a.result == VP_SPOT_OFF_LINE && !m) __builtin_trap();
    if (a.result == VP_SPOT_FOUND &&
        (!isfinite(a.u) || !isfinite(a.v) || a.u < -0.5 || a.u > f->width - 0.5 || a.v < -0.5 || a.v > f->height - 0.5 ||
         a.area < 1 || a.area > (2 * R + 1) * (2 * R + 1) || !(a.peak > 0)))
        __builtin_trap();
    memset(&sws, 0xA5, sizeof sws);
    if (vp_spot_find(f, cfg, m, &sws, &b) != VP_OK || memcmp(&a, &b, sizeof a) != 0) __builtin_trap();
    SHOW("spot: result %d at (%.2f, %.2f), area %d, peak %.1f, snr %.1f\n", a.result, a.u, a.v, a.area, a.peak, a.snr);
    if (!m) return;
    hit = vp_laser_measure(f, cfg, m, &sws, &s, &d);
    if (hit < 0 || memcmp(&a, &s, sizeof a) != 0) __builtin_trap();
    if (hit == 1 && (a.result != VP_SPOT_FOUND || !isfinite(d) || d < m->min_range || d > m->max_range))
        __builtin_trap();
    SHOW("measure: %d, d %.2f (range %.1f-%.1f)\n", hit, d, m->min_range, m->max_range);
}

#define MAXCOL 136

static void check_line(const vp_frame_t *on, const vp_frame_t *off, const vp_line_config_t *cfg, const vp_line_model_t *m)
{
    static vp_line_point_t a[MAXCOL], b[MAXCOL];
    vp_line_stats_t sa, sb;
    int na = -1, nb = -1, st, k, sum = 0, step = cfg->column_step > 0 ? cfg->column_step : 1;
    int cols = (on->width + step - 1) / step;
    memset(&lws, 0, sizeof lws);
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    st = vp_line_detect(on, off, cfg, m, &lws, a, MAXCOL, &na, &sa);
    if (st != VP_OK) __builtin_trap();
    if (na < 0 || na > cols || sa.found != na || sa.columns != cols) __builtin_trap();
    for (k = 0; k < VP_LINE_NREASONS; k++) {
        if (sa.why[k] < 0) __builtin_trap();
        sum += sa.why[k];
    }
    if (sum != cols || sa.why[VP_LINE_FOUND] != na) __builtin_trap();
    for (k = 0; k < na; k++) {
        const vp_line_point_t *p = &a[k];
        SHOW("  point col %d u %.3f v %.4f peak %.2f snr %.2f width %.3f sat %d dist %.2f\n", p->col, p->u, p->v, p->peak, p->snr,
             p->width, p->saturated, p->dist);
        if (p->col < 0 || p->col >= on->width || p->col % step || (k && p->col <= a[k - 1].col) || p->u != p->col ||
            !isfinite(p->v) || p->v < -0.5 || p->v > on->height - 0.5 || !isfinite(p->peak) || !isfinite(p->width))
            __builtin_trap();
        if (m) {
            double n2 = p->dir[0] * p->dir[0] + p->dir[1] * p->dir[1] + p->dir[2] * p->dir[2];
            if (!isfinite(p->dist) || p->dist < m->min_range || p->dist > m->max_range || !(fabs(n2 - 1) < 1e-9))
                __builtin_trap();
        }
    }
    SHOW("line: %d of %d columns, why %d %d %d %d %d %d %d %d\n", na, cols, sa.why[0], sa.why[1], sa.why[2], sa.why[3],
         sa.why[4], sa.why[5], sa.why[6], sa.why[7]);
    memset(&lws, 0x5A, sizeof lws);
    if (vp_line_detect(on, off, cfg, m, &lws, b, MAXCOL, &nb, &sb) != VP_OK || nb != na ||
        memcmp(a, b, sizeof a) != 0 || memcmp(&sa, &sb, sizeof sa) != 0)
        __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t hdr[HDR] = { 0 };
    const uint8_t *tex, *offtex;
    size_t ntex, noff;
    int w, h, step, pad, flags, spots, valid;
    vp_frame_t on, off;
    uint8_t *bon, *boff;
    vp_camera_model_t cam;
    vp_tri_model_t tm;
    vp_line_model_t lm;
    vp_spot_config_t sc;
    vp_line_config_t lc;
    memcpy(hdr, data, size < HDR ? size : HDR);
    tex = data + (size < HDR ? size : HDR);
    ntex = size < HDR ? 0 : size - HDR;
    w = 8 + hdr[0] % 128;
    h = 8 + hdr[1] % 128;
    flags = hdr[2];
    step = flags & 1 ? 2 : 1;
    pad = flags & 2 ? hdr[3] % 17 : 0;
    spots = flags & 8 ? (flags & 16 ? 2 : 1) : 0;
    /* the laser-off frame: the texture's second half when bit 7 is set, else the same texture */
    offtex = tex;
    noff = ntex;
    if ((flags & 128) && ntex >= 2) {
        ntex /= 2;
        offtex = tex + ntex;
        noff = ntex;
    }
    bon = make_frame(&on, w, h, step, pad, tex, ntex, hdr, spots, flags & 32, flags & 64);
    boff = make_frame(&off, w, h, step, pad, offtex, noff, hdr, 0, 0, 0);
    if (!bon || !boff) {
        free(bon);
        free(boff);
        return 0;
    }
    camera(&cam, w, h);
    memset(&sc, 0, sizeof sc);
    sc.band = hdr[3] % 5 == 0 ? 0.0 : 1.0 + hdr[3] % 40;
    valid = spoil_config(&sc, hdr[10]);
    if (!(flags & 4) || vp_tri_from_geometry(&cam, (double[3]){ 20, 0, 0 }, 10, 800, &tm) != VP_OK)
        check_spot(&on, &sc, NULL, valid);
    else {
        if (hdr[11]) {
            /* the beam's image line turned towards the rows, down to nearly along them */
            static const double tilt[8] = { 0, 1e-12, 1e-10, 1.5e-9, 1e-6, 1e-3, 0.1, 1.2 };
            double a = atan2(tm.e[1], tm.e[0]) + (hdr[11] & 128 ? -1 : 1) * tilt[hdr[11] & 7];
            if (hdr[11] & 8) a = (hdr[11] & 128 ? -1 : 1) * tilt[hdr[11] & 7]; /* from along the rows */
            tm.e[0] = cos(a);
            tm.e[1] = sin(a);
        }
        check_spot(&on, &sc, &tm, valid);
    }
    memset(&lc, 0, sizeof lc);
    lc.column_step = 1 + hdr[3] % 3;
    memset(&lm, 0, sizeof lm);
    lm.cam = cam;
    lm.origin[0] = 20;
    lm.normal[2] = 1;
    lm.axis[0] = 1;
    lm.half_angle = 29.5 * 3.14159265358979323846 / 180;
    lm.min_range = 10;
    lm.max_range = 800;
    check_line(&on, &off, &lc, flags & 4 ? &lm : NULL);
    free(bon);
    free(boff);
    return 0;
}
