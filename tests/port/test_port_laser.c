/* The rangefinder on rendered frames: vp_camsim draws the laser spot on simulated objects seen
 * by a board-like camera (blur, footprint, noise, ambient light); vp_laser finds the spot and
 * turns it into a distance. Measured against the renderer's truth over many frames. Also: the
 * exact geometric model, misses (no spot, several spots, glare, hot pixels, out of range), and
 * calibration from a flat target at known distances against the known true model. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_camsim.h"
#include "vp_kin.h"
#include "vp_laser.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

#define W 640
#define H 480
static uint8_t img[W * H];
static vp_spot_ws_t ws;

static void camera(vp_camsim_config_t *c)
{
    memset(c, 0, sizeof *c);
    c->cam.width = W;
    c->cam.height = H;
    c->cam.fx = c->cam.fy = 700;
    c->cam.cx = (W - 1) / 2.0;
    c->cam.cy = (H - 1) / 2.0;
    c->cam.pos[0] = 0; c->cam.pos[1] = 60; c->cam.pos[2] = 10;     /* 60 mm baseline */
    vp_camera_look_at(&c->cam, (double[3]){ 370, 0, 0 }, (double[3]){ 0, 0, 1 });
    c->laser_offset[0] = 20;
    c->blur_px = 1.2;
    c->spot_energy = 6000;
    c->noise = 2;
    c->ambient = 30;
}

static vp_frame_t frame(void)
{
    vp_frame_t f;
    memset(&f, 0, sizeof f);
    f.data = img; f.width = W; f.height = H; f.stride = W; f.step = 1;
    return f;
}

/* one frame of a flat target across the beam at distance dist (head at rest, beam along +x) */
static int flat(vp_camsim_config_t *c, double dist, vp_rng_t *rng, vp_camsim_truth_t *tr)
{
    static const double rot[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, pos[3] = { 0, 0, 40 };
    vp_camsim_scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.plane_n[0] = 1;
    sc.plane_d = c->laser_offset[0] + dist;
    return vp_camsim_render(c, &sc, rot, pos, rng, img, W, tr);
}

/* Misses, never guesses: ghosts, glare, hot pixels, out of range. */
static void misses(const vp_camsim_config_t *c0, const vp_tri_model_t *m)
{
    vp_camsim_config_t c = *c0;
    vp_camsim_truth_t tr;
    vp_spot_config_t sc;
    vp_tri_model_t mb = *m;
    vp_spot_t sp;
    vp_rng_t rng;
    vp_frame_t f = frame();
    double d;
    int n = 0;
    vp_rng_seed(&rng, 77);
    memset(&sc, 0, sizeof sc);
    c.blur_px = 1.5; c.noise = 2; c.ambient = 40; c.gradient = 30; c.texture = 3;
    /* clean */
    CHECK(flat(&c, 400, &rng, &tr) == VP_OK && tr.visible);
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 1 && fabs(d - 400) < 0.5);
    /* a reflection on the laser line: two spots */
    c.ghost = 0.7; c.ghost_offset[0] = 40 * m->e[0]; c.ghost_offset[1] = 40 * m->e[1];
    CHECK(flat(&c, 400, &rng, &tr) == VP_OK);
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_SEVERAL); n++;
    /* off the line: several without a band; with a 12 px band around the line it is not the laser */
    c.ghost_offset[0] = -30 * m->e[1]; c.ghost_offset[1] = 30 * m->e[0];
    CHECK(flat(&c, 400, &rng, &tr) == VP_OK);
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_SEVERAL); n++;
    sc.band = 12;
    CHECK(vp_laser_measure(&f, &sc, m, &ws, &sp, &d) == 1 && fabs(d - 400) < 0.5);
    c.ghost = 0;
    sc.band = 0;
    /* a lone spot off the line (the beam misses: target beyond its range): not the laser */
    c.max_range = 1000;
    c.lamp_peak = 120; c.lamp_sigma = 1.5;
    c.lamp_uv[0] = m->p0[0] + 200 * m->e[0] - 30 * m->e[1];
    c.lamp_uv[1] = m->p0[1] + 200 * m->e[1] + 30 * m->e[0];
    CHECK(flat(&c, 2000, &rng, &tr) == VP_OK && !tr.hit);
    CHECKF(vp_laser_measure(&f, &sc, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_OFF_LINE, "lone: %d at %.1f %.1f peak %.1f snr %.1f", sp.result, sp.u, sp.v, sp.peak, sp.snr); n++;
    sc.band = 12;
    CHECK(vp_laser_measure(&f, &sc, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_NONE); n++;
    sc.band = 0;
    c.max_range = 0;
    /* broad glare (sigma 25 px) is background: the spot is still measured */
    c.lamp_peak = 150; c.lamp_sigma = 25; c.lamp_uv[0] = 200; c.lamp_uv[1] = 330;
    CHECK(flat(&c, 600, &rng, &tr) == VP_OK && tr.visible);
    CHECKF(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 1 && fabs(d - 600) < 2, "glare: %d d %g at %.1f %.1f second %.2f at %d %d", sp.result, d, sp.u, sp.v, sp.second, sp.u2, sp.v2);
    /* a bright blob of 12 px next to the spot: a miss, never a guess */
    c.lamp_peak = 220; c.lamp_sigma = 12;
    CHECK(flat(&c, 600, &rng, &tr) == VP_OK);
    CHECKF(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 0 && (sp.result == VP_SPOT_TOO_BIG || sp.result == VP_SPOT_SEVERAL),
           "blob: %d", sp.result); n++;
    c.lamp_peak = 0;
    /* hot pixels: ignored next to a spot, not taken for one alone */
    c.hot_pixels = 40;
    CHECK(flat(&c, 300, &rng, &tr) == VP_OK);
    CHECKF(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 1 && fabs(d - 300) < 0.5, "hot pixels: %d %g", sp.result, d);
    c.max_range = 1000;
    CHECK(flat(&c, 2000, &rng, &tr) == VP_OK && !tr.hit);
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_NONE); n++;
    c.hot_pixels = 0;
    c.max_range = 0;
    /* out of the calibrated range: the spot is there, the distance is refused */
    mb.min_range = 200;
    mb.max_range = 700;
    CHECK(flat(&c, 150, &rng, &tr) == VP_OK && tr.visible);
    CHECK(vp_laser_measure(&f, NULL, &mb, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_FOUND); n++;
    CHECK(flat(&c, 800, &rng, &tr) == VP_OK && tr.visible);
    CHECK(vp_laser_measure(&f, NULL, &mb, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_FOUND); n++;
    /* dark frame, saturated frame */
    memset(img, 0, sizeof img);
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_NONE); n++;
    memset(img, 255, sizeof img);
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == 0 && sp.result == VP_SPOT_NONE); n++;
    f.width = 3;
    CHECK(vp_laser_measure(&f, NULL, m, &ws, &sp, &d) == VP_EINVAL);
    f.width = W;
    printf("misses: %d frames with ghosts, a stray spot, a glare blob, hot pixels, out of range, blank: all refused\n", n);
    /* the model's image line within 1e-8 rad of the rows (a camera level beside the laser): the
     * band's ends lie some 1e10 px out along the rows, and the search stays in the frame (it
     * started at INT_MIN before: a cast from beyond an int) */
    {
        vp_spot_config_t band = sc;
        int k;
        band.band = 12;
        CHECK(flat(&c, 400, &rng, &tr) == VP_OK && tr.visible);
        for (k = -1; k <= 1; k += 2) {
            mb = *m;
            mb.e[0] = cos(k * 1e-8);
            mb.e[1] = sin(k * 1e-8);
            mb.p0[1] = tr.uv[1] + 0.5 * k;          /* the line half a pixel off the spot */
            CHECK(vp_spot_find(&f, &band, &mb, &ws, &sp) == VP_OK && sp.result == VP_SPOT_FOUND);
            mb.p0[1] = tr.uv[1] + 40 * k;           /* 40 px off: outside the band */
            CHECK(vp_spot_find(&f, &band, &mb, &ws, &sp) == VP_OK && sp.result != VP_SPOT_FOUND);
        }
    }
    /* a configuration out of range is refused, nothing written */
    {
        vp_spot_config_t bad;
        vp_spot_t keep;
        int k;
        for (k = 0; k < 6; k++) {
            memset(&bad, 0, sizeof bad);
            if (k == 0) bad.percentile = NAN;
            if (k == 1) bad.percentile = 1.5;
            if (k == 2) bad.block = -1;
            if (k == 3) bad.min_snr = INFINITY;
            if (k == 4) bad.band = -2;
            if (k == 5) bad.rel_thresh = -0.1;
            memset(&sp, 0x5A, sizeof sp);
            keep = sp;
            CHECK(vp_spot_find(&f, &bad, m, &ws, &sp) == VP_EINVAL && memcmp(&sp, &keep, sizeof sp) == 0);
        }
    }
}

/* Calibration: a flat target at 25 known distances, 3 frames each; the fitted model against
 * the true (geometric) one over the calibrated span. */
static void calibration(const vp_camsim_config_t *c0, const vp_tri_model_t *truth)
{
    vp_camsim_config_t c = *c0;
    vp_camsim_truth_t tr;
    vp_tri_model_t fit;
    vp_tri_fit_report_t rep;
    vp_spot_t sp;
    vp_rng_t rng;
    vp_frame_t f = frame();
    double uv[75][2], dist[75], worst = 0, worst_mm = 0;
    int i, n = 0;
    vp_rng_seed(&rng, 5);
    c.blur_px = 1.4; c.noise = 2; c.ambient = 40; c.gradient = 20; c.texture = 2;
    for (i = 0; i < 75; i++) {
        double dd = 150 + (850 - 150) * (i / 3) / 24.0;
        CHECK(flat(&c, dd, &rng, &tr) == VP_OK && tr.visible);
        CHECK(vp_spot_find(&f, NULL, NULL, &ws, &sp) == VP_OK);
        if (sp.result != VP_SPOT_FOUND) continue;
        uv[n][0] = sp.u; uv[n][1] = sp.v; dist[n] = dd; n++;
    }
    CHECK(n == 75);
    CHECK(vp_tri_fit((const double (*)[2])uv, dist, n, W, H, &fit, &rep) == VP_OK);
    for (i = 0; i <= 200; i++) {
        double dd = 150 + 700 * i / 200.0, p[3] = { 20 + dd, 0, 0 }, q[2], dfit, ddds;
        vp_camera_project(&c.cam, p, q);
        dfit = vp_tri_eval(&fit, (q[0] - fit.p0[0]) * fit.e[0] + (q[1] - fit.p0[1]) * fit.e[1], NULL);
        vp_tri_eval(truth, vp_tri_s(truth, dd), &ddds);
        if (fabs(dfit - dd) / ddds > worst) worst = fabs(dfit - dd) / ddds;
        if (fabs(dfit - dd) > worst_mm) worst_mm = fabs(dfit - dd);
    }
    printf("calibration: %d spots, fit residual rms %.3f mm (max %.3f), line rms %.3f px; against the true model: "
           "max %.4f px = %.3f mm over 150..850 mm\n", rep.n, rep.rms_mm, rep.max_mm, rep.line_rms_px, worst, worst_mm);
    /* 75 spots with ~0.03 px each: the fitted curve is good to a fraction of that; 0.03 px allowed */
    CHECKF(worst <= 0.03, "calibrated model off by %.4f px", worst);
    CHECK(fabs(fit.min_range - 150) < 1e-9 && fabs(fit.max_range - 850) < 1e-9);
    /* exact spots give the exact model */
    for (i = 0; i < 10; i++) {
        double p[3] = { 20 + 150 + 70 * i, 0, 0 };
        vp_camera_project(&c.cam, p, uv[i]);
        dist[i] = 150 + 70 * i;
    }
    CHECK(vp_tri_fit((const double (*)[2])uv, dist, 10, W, H, &fit, &rep) == VP_OK && rep.rms_mm < 1e-6 && rep.line_rms_px < 1e-6);
    CHECK(vp_tri_fit((const double (*)[2])uv, dist, 3, W, H, &fit, &rep) == VP_EINVAL);
    for (i = 0; i < 10; i++) { uv[i][0] = 100; uv[i][1] = 100; }
    CHECK(vp_tri_fit((const double (*)[2])uv, dist, 10, W, H, &fit, &rep) == VP_EDEGEN);
}

int main(void)
{
    vp_camsim_config_t c;
    vp_tri_model_t m;
    vp_kin_t kin;
    vp_kin_config_t kc;
    vp_rng_t rng;
    vp_spot_t sp;
    vp_frame_t f = frame();
    double rot[9], pos[3], d;
    int i;
    camera(&c);
    memset(&kc, 0, sizeof kc);
    kc.tilt_offset[2] = 40;
    kc.laser_offset[0] = 20;
    CHECK(vp_kin_init(&kin, &kc) == VP_OK);
    CHECK(vp_tri_from_geometry(&c.cam, c.laser_offset, 120, 900, &m) == VP_OK);
    printf("geometric model: range %.1f..%.1f mm, line through (%.1f,%.1f) dir (%.3f,%.3f)\n", m.min_range, m.max_range,
           m.p0[0], m.p0[1], m.e[0], m.e[1]);
    /* exact for a pinhole camera */
    {
        double worst = 0;
        for (i = 0; i <= 1000; i++) {
            double dd = m.min_range + (m.max_range - m.min_range) * i / 1000.0, uv[2];
            CHECK(vp_camera_project(&c.cam, (double[3]){ 20 + dd, 0, 0 }, uv));
            CHECK(vp_tri_distance(&m, uv, &d) == VP_OK);
            if (fabs(d - dd) > worst) worst = fabs(d - dd);
        }
        CHECKF(worst < 1e-6, "geometric model off by %g mm", worst);
    }

    /* ---- many frames on objects ---- */
    {
        static const char *objs[] = { "sphere*100", "torus*120", "genus2*70", "ellipsoid*120" };
        int nvis = 0, nhit = 0, nfalse = 0, nmiss[6] = { 0, 0, 0, 0, 0, 0 }, nout = 0, ninv = 0, k;
        double se = 0, emax = 0, semm = 0, emaxmm = 0, zmax = 0, se20 = 0, emax20 = 0;
        int n20 = 0;
        clock_t t0 = clock(), tdet = 0;
        vp_rng_seed(&rng, 1234);
        for (k = 0; k < 4; k++) {
            vp_surface_t *s;
            vp_camsim_scene_t sc;
            char err[200];
            double samp[3 * 150];
            CHECK(vp_surface_open(objs[k], &s, err, sizeof err) == VP_OK);
            vp_surface_sample(s, 150, 99 + k, samp);
            memset(&sc, 0, sizeof sc);
            sc.surf = s;
            for (i = 0; i < 150; i++) {
                double org[3], dir[3], j[5], tgt[3], len = 0, dd_ds, uv[2];
                vp_camsim_truth_t tr;
                int q, hit;
                vp_rng_unit3(&rng, dir);
                for (q = 0; q < 3; q++) org[q] = dir[q] * (250 + 450 * vp_rng_uniform(&rng));
                if (vp_surface_inside(s, org) || vp_surface_distance(s, org) < 120) { i--; continue; }
                for (q = 0; q < 3; q++) { tgt[q] = samp[3 * i + q] + 8 * (vp_rng_uniform(&rng) - 0.5); dir[q] = tgt[q] - org[q]; len += dir[q] * dir[q]; }
                for (q = 0; q < 3; q++) dir[q] /= sqrt(len);
                if (vp_kin_aim(&kin, (double[5]){ 0, 0, 0, 0, 0 }, org, dir, j) != VP_OK) continue;
                vp_kin_head(&kin, j, rot, pos);
                c.blur_px = 0.8 + 1.7 * vp_rng_uniform(&rng);
                c.noise = 1 + 2 * vp_rng_uniform(&rng);
                c.ambient = 10 + 110 * vp_rng_uniform(&rng);
                c.gradient = 60 * vp_rng_uniform(&rng);
                c.texture = 8 * vp_rng_uniform(&rng);
                CHECK(vp_camsim_render(&c, &sc, rot, pos, &rng, img, W, &tr) == VP_OK);
                {
                    clock_t td = clock();
                    hit = vp_laser_measure(&f, NULL, &m, &ws, &sp, &d);
                    tdet += clock() - td;
                }
                CHECK(hit >= 0);
                if (!tr.hit || !tr.visible) { ninv++; if (hit) nfalse++; continue; }
                if (tr.dist < m.min_range || tr.dist > m.max_range) { nout++; if (hit) nfalse++; continue; }
                nvis++;
                if (!hit) { nmiss[sp.result + 3]++; if (getenv("VP_DEBUG")) { printf("miss %d: peak %.1f noise %.1f sigma %.2f dist %.0f snr %.1f second %.2f area %d at %.1f,%.1f true %.1f,%.1f\n", sp.result, tr.peak, c.noise, tr.sigma_px, tr.dist, sp.snr, sp.second, sp.area, sp.u, sp.v, tr.uv[0], tr.uv[1]); if (sp.result == -1) { FILE *pf = fopen("/tmp/miss.pgm", "wb"); fprintf(pf, "P5 %d %d 255\n", W, H); fwrite(img, 1, sizeof img, pf); fclose(pf); } } continue; }
                nhit++;
                uv[0] = tr.uv[0]; uv[1] = tr.uv[1];
                {
                    double s_true = (uv[0] - m.p0[0]) * m.e[0] + (uv[1] - m.p0[1]) * m.e[1];
                    double epx, crb, e = d - tr.dist;
                    vp_tri_eval(&m, s_true, &dd_ds);
                    epx = e / dd_ds;
                    /* Cramer-Rao bound of a Gaussian spot's centre: 0.8 sigma_noise / peak */
                    crb = 0.8 * c.noise / (tr.peak < 255 ? tr.peak : 255);
                    se += epx * epx;
                    semm += e * e;
                    if (fabs(epx) > emax) emax = fabs(epx);
                    if (fabs(e) > emaxmm) emaxmm = fabs(e);
                    if (fabs(epx) / (0.03 + crb) > zmax) zmax = fabs(epx) / (0.03 + crb);
                    /* per frame: 0.1 px of systematic error (pixel sampling of narrow spots, clipped
                     * saturated spots, the footprint's perspective asymmetry) plus 8 Cramer-Rao
                     * bounds (a thresholded centroid is about half as efficient as the optimal fit,
                     * so 8 CRB is about 4 sigma) */
                    CHECKF(fabs(epx) <= 0.1 + 8 * crb, "error %.3f px, bound %.3f px (peak %.1f)", epx, 0.1 + 8 * crb, tr.peak);
                    if ((tr.peak < 255 ? tr.peak : 255) >= 20 * c.noise) {
                        n20++;
                        se20 += epx * epx;
                        if (fabs(epx) > emax20) emax20 = fabs(epx);
                    }
                }
            }
            vp_surface_close(s);
        }
        printf("%d frames: %d spots visible in range, %d measured, misses none %d several %d too-big %d off-line %d; "
               "%d hidden/no hit, %d out of range, %d false hits; %.1f ms per frame, detection %.2f ms\n",
               600, nvis, nhit, nmiss[3], nmiss[2], nmiss[1], nmiss[0], ninv, nout, nfalse,
               (double)(clock() - t0) / CLOCKS_PER_SEC * 1000 / 600, (double)tdet / CLOCKS_PER_SEC * 1000 / 600);
        printf("error: rms %.4f px (%.3f mm), max %.4f px (%.3f mm), max / (0.03 px + CRB) %.2f\n", sqrt(se / nhit),
               sqrt(semm / nhit), emax, emaxmm, zmax);
        printf("spots with peak >= 20 noise sigmas: %d, rms %.4f px, max %.4f px\n", n20, sqrt(se20 / n20), emax20);
        /* no hit without a visible spot in range */
        CHECK(nfalse == 0);
        /* well-exposed spots (peak >= 20 sigma): rms within the CRB at the weakest of them (0.8/20 =
         * 0.04 px) combined with 0.03 px of pixel-sampling bias: sqrt(0.04^2 + 0.03^2) = 0.05 px */
        CHECKF(sqrt(se20 / n20) <= 0.05, "rms %.4f px", sqrt(se20 / n20));
        CHECK(n20 > 300 && nhit > 0.95 * nvis);
    }
    misses(&c, &m);
    calibration(&c, &m);
    return vp_test_done("test_port_laser");
}
