/* The rangefinder's full model (port/vp_calib): the lens model (its inverse; OpenCV's
 * projectPoints / undistortPoints with --opencv FILE, written by tests/t_lens_opencv.sh), the
 * fit against observations made by this file's own projection (seeded noise), the refusal of
 * spots off the beam or outside the calibrated span, bad input; then the rpi4 board's dry run
 * (lens k1 = -0.15, beam 1 degree off +x): the machine's calibration, probes read by the fitted
 * model against the renderer's truth, and a spot beyond the span refused as too close where the
 * 1-D model's path reads it as free space. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "vp_test.h"
#include "vp_board.h"
#include "vp_calib.h"
#include "vp_dryrun.h"
#include "vp_machine.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "ref_camera.h"
#include "vp_vec3.h"

#define PI 3.14159265358979323846

static vp_board_t board;

/* ---- the lens model against OpenCV (values written by python3-opencv) ---- */
static int opencv_compare(const char *path)
{
    FILE *f = fopen(path, "r");
    char kind[8];
    int n_p = 0, n_u = 0, n_swapped = 0;
    double worst_p = 0, worst_u = 0, worst_sw = HUGE_VAL;
    CHECKF(f != NULL, "cannot read %s", path);
    if (!f) return vp_test_done("test_port_calib --opencv");
    while (fscanf(f, "%7s", kind) == 1) {
        vp_camera_model_t c;
        double v[25];
        int i, k, need = !strcmp(kind, "P") ? 25 : 10;
        memset(&c, 0, sizeof c);
        for (i = 0; i < need; i++) CHECK(fscanf(f, "%lf", &v[i]) == 1);
        c.fx = v[0]; c.fy = v[1]; c.cx = v[2]; c.cy = v[3];
        for (k = 0; k < 4; k++) c.dist[k] = v[4 + k];
        if (!strcmp(kind, "P")) {
            /* P fx fy cx cy k1 k2 p1 p2 R(9) t(3) X Y Z u v: x_cam = R X + t */
            double uv[2], e, sw[2];
            const double *R = v + 8, *t = v + 17, *X = v + 20;
            vp_camera_model_t s;
            for (k = 0; k < 9; k++) c.rot[k] = R[k];
            for (k = 0; k < 3; k++) c.pos[k] = -(R[k] * t[0] + R[3 + k] * t[1] + R[6 + k] * t[2]);
            CHECK(vp_camera_project(&c, X, uv) == 1);
            e = hypot(uv[0] - v[23], uv[1] - v[24]);
            if (e > worst_p) worst_p = e;
            n_p++;
            /* a model with p1 and p2 swapped must disagree (the comparison can fail) */
            s = c;
            s.dist[2] = c.dist[3];
            s.dist[3] = c.dist[2];
            if (fabs(c.dist[2] - c.dist[3]) > 1e-4 && vp_camera_project(&s, X, sw)) {
                double es = hypot(sw[0] - v[23], sw[1] - v[24]);
                if (es < worst_sw) worst_sw = es;
                n_swapped++;
            }
        } else {
            /* U fx fy cx cy k1 k2 p1 p2 u v x y: normalised undistorted point */
            double uv[2] = { v[8], v[9] }, d[3], e;
            for (k = 0; k < 9; k++) c.rot[k] = k % 4 == 0;
            CHECK(fscanf(f, "%lf %lf", &v[10], &v[11]) == 2);
            CHECK(vp_camera_ray(&c, uv, d) == VP_OK);
            e = hypot(d[0] - v[10], d[1] - v[11]);
            if (e > worst_u) worst_u = e;
            n_u++;
        }
    }
    fclose(f);
    CHECKF(n_p >= 100 && n_u >= 100, "%d projections, %d undistortions read", n_p, n_u);
    CHECKF(worst_p < 1e-6, "projection differs from cv2.projectPoints by %.3g px", worst_p);
    CHECKF(worst_u < 1e-9, "undistortion differs from cv2.undistortPointsIter by %.3g", worst_u);
    CHECKF(n_swapped > 10 && worst_sw > 1e-3, "p1 and p2 swapped still agree within %.3g px", worst_sw);
    printf("opencv: %d projections within %.2e px of cv2.projectPoints, %d undistortions within %.2e of "
           "cv2.undistortPointsIter; p1/p2 swapped differs by >= %.3f px\n", n_p, worst_p, n_u, worst_u, worst_sw);
    return vp_test_done("test_port_calib --opencv");
}

/* ---- the lens model alone ---- */
static void lens(void)
{
    static const double ks[3][4] = { { -0.15, 0, 0, 0 }, { -0.3, 0.08, 0.002, -0.001 }, { 0.1, -0.02, -0.003, 0.002 } };
    double worst = 0, x[2], y[2], z[2], nan2[2] = { NAN, 0 };
    int s, i, j;
    for (s = 0; s < 3; s++)
        for (i = -10; i <= 10; i++)
            for (j = -8; j <= 8; j++) {
                x[0] = i * 0.09;
                x[1] = j * 0.085;
                vp_lens_distort(ks[s], x, y);
                CHECK(vp_lens_undistort(ks[s], y, z) == VP_OK);
                if (hypot(z[0] - x[0], z[1] - x[1]) > worst) worst = hypot(z[0] - x[0], z[1] - x[1]);
            }
    CHECKF(worst < 1e-12, "undistort(distort(x)) off by %.3g", worst);
    CHECK(vp_lens_undistort(ks[0], nan2, z) == VP_EINVAL);
    {
        /* no distortion: the plain pinhole, as before */
        vp_camera_model_t c = board.cam_model;
        double p[3] = { 120, -14, 33 }, uv[2], q[3];
        int k;
        memset(c.dist, 0, sizeof c.dist);
        CHECK(vp_camera_project(&c, p, uv));
        for (k = 0; k < 3; k++) q[k] = c.rot[3 * k] * (p[0] - c.pos[0]) + c.rot[3 * k + 1] * (p[1] - c.pos[1]) + c.rot[3 * k + 2] * (p[2] - c.pos[2]);
        CHECK(fabs(uv[0] - (c.fx * q[0] / q[2] + c.cx)) < 1e-9 && fabs(uv[1] - (c.fy * q[1] / q[2] + c.cy)) < 1e-9);
    }
}

/* ---- the fit on observations of a known model ---- */
typedef struct truth {
    vp_rf_model_t m;
} truth_t;

static void make_truth(truth_t *t, const vp_rf_model_t *nominal)
{
    static const double axis[3] = { 0.6, 0.48, 0.64 };
    double a = 1.0 * PI / 180, az = 30 * PI / 180;
    t->m = *nominal;
    t->m.cam.fx = 352.5; t->m.cam.fy = 348.9; t->m.cam.cx = 322.1; t->m.cam.cy = 236.4;
    t->m.cam.dist[0] = -0.15; t->m.cam.dist[1] = 0.02; t->m.cam.dist[2] = 0.001; t->m.cam.dist[3] = -0.0005;
    ref_turn(t->m.cam.rot, axis, 0.5 * PI / 180);
    t->m.cam.pos[0] += 0.3; t->m.cam.pos[1] -= 0.2; t->m.cam.pos[2] += 0.5;
    t->m.origin[1] += 0.4; t->m.origin[2] -= 0.3;
    t->m.dir[0] = cos(a); t->m.dir[1] = sin(a) * cos(az); t->m.dir[2] = sin(a) * sin(az);
}

/* marks over the image at `depths` depths, spots on target planes at `nspot` distances (all at
 * 150 mm with flat_spots) */
static int make_obs(const truth_t *t, const vp_rf_model_t *nominal, vp_calib_obs_t *obs, int depths, int nspot, int flat_spots,
                    double noise)
{
    static const double zs[5] = { 30, 60, 120, 200, 300 };
    vp_rng_t rng;
    int n = 0, dz, i, j, k;
    vp_rng_seed(&rng, 7);
    for (dz = 0; dz < depths; dz++)
        for (i = 0; i < 7; i++)
            for (j = 0; j < 5; j++) {
                double want[2], r[3], uv[2];
                want[0] = 30 + 579.0 * i / 6;
                want[1] = 30 + 419.0 * j / 4;
                if (vp_camera_ray(&nominal->cam, want, r) != VP_OK) continue;
                memset(&obs[n], 0, sizeof obs[n]);
                for (k = 0; k < 3; k++) obs[n].p[k] = nominal->cam.pos[k] + zs[depths == 1 ? 2 : dz] * r[k];
                if (!ref_project(&t->m.cam, obs[n].p, uv) || uv[0] < 0 || uv[1] < 0 || uv[0] > 639 || uv[1] > 479) continue;
                obs[n].kind = VP_OBS_MARK;
                obs[n].uv[0] = uv[0] + noise * vp_rng_normal(&rng);
                obs[n].uv[1] = uv[1] + noise * vp_rng_normal(&rng);
                n++;
            }
    for (i = 0; i < nspot; i++) {
        /* the target across the beam at distance d, tilted a little at every other station */
        double d = flat_spots ? 150 : 1 / (1 / 400.0 + (1 / 10.0 - 1 / 400.0) * i / (nspot - 1)), tilt = i % 2 ? 0.05 : 0;
        double p[3], uv[2];
        memset(&obs[n], 0, sizeof obs[n]);
        obs[n].kind = VP_OBS_SPOT;
        obs[n].n[0] = cos(tilt);
        obs[n].n[1] = sin(tilt);
        for (k = 0; k < 3; k++) p[k] = t->m.origin[k] + d * t->m.dir[k];
        obs[n].h = obs[n].n[0] * p[0] + obs[n].n[1] * p[1] + obs[n].n[2] * p[2];
        if (!ref_project(&t->m.cam, p, uv)) continue;
        obs[n].uv[0] = uv[0] + noise * vp_rng_normal(&rng);
        obs[n].uv[1] = uv[1] + noise * vp_rng_normal(&rng);
        n++;
    }
    return n;
}

/* worst distance error of model m over 11..399 mm and at 399 mm, spots imaged by truth */
static void dist_error(const vp_rf_model_t *m, const truth_t *t, double *worst, double *at_far, int *refused)
{
    int i;
    *worst = 0;
    *at_far = HUGE_VAL;
    *refused = 0;
    for (i = 0; i <= 40; i++) {
        double d = 11 + (399 - 11) * i / 40.0, p[3], uv[2], got, e;
        int why, k;
        for (k = 0; k < 3; k++) p[k] = t->m.origin[k] + d * t->m.dir[k];
        ref_project(&t->m.cam, p, uv);
        if (vp_rf_distance(m, uv, &got, &why, NULL) != VP_OK || why != VP_RF_OK) { (*refused)++; continue; }
        e = fabs(got - d);
        if (e > *worst) *worst = e;
        if (i == 40) *at_far = e;
    }
}

static void fit(void)
{
    static vp_calib_obs_t obs[512];
    vp_rf_model_t nominal, out, wide;
    vp_rf_fit_report_t rep;
    truth_t t;
    double worst, far, ang, p[3], uv[2], d, gap;
    int n, refused, why, k;
    CHECK(vp_rf_nominal(&board.cam_model, board.laser_offset, 10, 400, &nominal) == VP_OK);
    make_truth(&t, &nominal);
    n = make_obs(&t, &nominal, obs, 5, 24, 0, 0.05);
    CHECK(vp_rf_fit(obs, n, &nominal, &out, &rep) == VP_OK);
    ang = acos(out.dir[0] * t.m.dir[0] + out.dir[1] * t.m.dir[1] + out.dir[2] * t.m.dir[2]) * 180 / PI;
    CHECKF(fabs(out.cam.dist[0] + 0.15) < 0.003, "k1 %.5f", out.cam.dist[0]);
    CHECKF(ang < 0.01, "beam %.4f deg off", ang);
    CHECKF(fabs(out.cam.fx - 352.5) < 0.5 && fabs(out.cam.cy - 236.4) < 0.5, "fx %.3f cy %.3f", out.cam.fx, out.cam.cy);
    CHECKF(rep.rms_px < 0.08 && rep.start_rms_px > 5, "residual %.4f px (start %.3f)", rep.rms_px, rep.start_rms_px);
    dist_error(&out, &t, &worst, &far, &refused);
    CHECKF(worst < 0.5 && far < 0.5 && refused == 0, "fitted: worst %.4f mm, at 399 mm %.4f mm, %d refused", worst, far, refused);
    printf("fit on synthetic observations (%d, noise 0.05 px): k1 %.5f (true -0.15), beam %.4f deg off the true one, "
           "residual %.4f px; distance error worst %.4f mm, at 399 mm %.4f mm\n", n, out.cam.dist[0], ang, rep.rms_px, worst, far);
    /* three marks taken from a reflection 25 px away: the fit holds and names them */
    {
        vp_rf_model_t o2;
        vp_rf_fit_report_t r2;
        double w2, f2;
        int ref2;
        obs[5].uv[0] += 25; obs[40].uv[1] -= 25; obs[90].uv[0] += 18;
        CHECK(vp_rf_fit(obs, n, &nominal, &o2, &r2) == VP_OK);
        dist_error(&o2, &t, &w2, &f2, &ref2);
        CHECKF(r2.outliers == 3 && fabs(o2.cam.dist[0] + 0.15) < 0.003 && w2 < 0.5 && ref2 == 0,
               "with 3 stray marks: %d outliers, k1 %.5f, worst %.4f mm", r2.outliers, o2.cam.dist[0], w2);
        printf("with 3 stray marks (18-25 px): %d outliers found, k1 %.5f, distance error worst %.4f mm\n", r2.outliers,
               o2.cam.dist[0], w2);
        obs[5].uv[0] -= 25; obs[40].uv[1] += 25; obs[90].uv[0] -= 18;
    }
    /* a mark and a spot taken from something 250 px away (the rms over all of them is then far
     * above 10 px): the fit holds, names them, and gives the same distances; with such gross ones
     * on more than 1 in 10 of the observations it is refused */
    {
        static vp_calib_obs_t bad[512];
        vp_rf_model_t o3;
        vp_rf_fit_report_t r3;
        double w3, f3;
        int ref3, i, spot = -1, gross = 0;
        memcpy(bad, obs, sizeof bad);
        for (i = 0; i < n && spot < 0; i++)
            if (bad[i].kind == VP_OBS_SPOT) spot = i;
        bad[7].uv[1] += 250;
        bad[spot + 5].uv[0] -= 250;   /* a spot in the middle of the span: losing the farthest
                                          one costs the far end its accuracy */
        CHECK(vp_rf_fit(bad, n, &nominal, &o3, &r3) == VP_OK);
        dist_error(&o3, &t, &w3, &f3, &ref3);
        CHECKF(r3.rms_px > 10 && r3.outliers == 2 && r3.strays == 2 && r3.max_px > 200 &&
               fabs(o3.cam.dist[0] + 0.15) < 0.003 && w3 < 0.5 && ref3 == 0, "with 2 gross strays: rms %.2f px, %d outliers, k1 %.5f, worst %.4f mm", r3.rms_px, r3.outliers,
               o3.cam.dist[0], w3);
        printf("with a mark and a spot 250 px astray: rms %.1f px over all, %d outliers, distance error worst %.4f mm\n",
               r3.rms_px, r3.outliers, w3);
        for (i = 0; i < n; i += 8) {
            bad[i].uv[0] += 250;
            gross++;
        }
        memset(&r3, 0, sizeof r3);
        CHECKF(10 * gross > n && vp_rf_fit(bad, n, &nominal, &o3, &r3) == VP_EDEGEN, "%d of %d gross strays accepted", gross, n);
        CHECKF(r3.strays >= gross && r3.rms_px > 10 && r3.iterations > 0, "refused, but the report says %d strays, rms %.2f px",
               r3.strays, r3.rms_px);
    }
    /* the nominal model fails the same bound (what the check must catch) */
    wide = nominal;
    wide.ray_tol_px = 1e9;
    wide.min_range = -1e9;
    wide.max_range = 1e9;
    dist_error(&wide, &t, &worst, &far, &refused);
    CHECKF(far > 1, "the nominal model at 399 mm is off by only %.4f mm", far);
    printf("nominal model on the same spots: worst %.3f mm, at 399 mm %.3f mm (%d refused)\n", worst, far, refused);

    /* refusals: beyond the span, off the beam */
    out.max_range = 300;
    for (k = 0; k < 3; k++) p[k] = t.m.origin[k] + 350 * t.m.dir[k];
    ref_project(&t.m.cam, p, uv);
    CHECK(vp_rf_distance(&out, uv, &d, &why, NULL) == VP_OK && why == VP_RF_OUT_OF_SPAN && fabs(d - 350) < 1);
    for (k = 0; k < 3; k++) p[k] = t.m.origin[k] + 5 * t.m.dir[k];
    ref_project(&t.m.cam, p, uv);
    out.min_range = 10;
    CHECK(vp_rf_distance(&out, uv, &d, &why, NULL) == VP_OK && why == VP_RF_OUT_OF_SPAN && fabs(d - 5) < 0.5);
    for (k = 0; k < 3; k++) p[k] = t.m.origin[k] + 200 * t.m.dir[k];
    p[2] += 6;   /* 6 mm beside the beam: not the laser */
    ref_project(&t.m.cam, p, uv);
    CHECK(vp_rf_distance(&out, uv, &d, &why, &gap) == VP_OK && why == VP_RF_OFF_BEAM && gap > 3);
    uv[0] = NAN;
    CHECK(vp_rf_distance(&out, uv, &d, &why, NULL) == VP_EINVAL);

    /* bad input: NaN, a bad kind, too few marks, spots all at one distance */
    n = make_obs(&t, &nominal, obs, 5, 24, 0, 0.05);
    obs[3].uv[1] = NAN;
    CHECK(vp_rf_fit(obs, n, &nominal, &out, &rep) == VP_EINVAL);
    obs[3].uv[1] = 100;
    obs[4].kind = 7;
    CHECK(vp_rf_fit(obs, n, &nominal, &out, &rep) == VP_EINVAL);
    CHECK(vp_rf_fit(NULL, n, &nominal, &out, &rep) == VP_EINVAL);
    n = make_obs(&t, &nominal, obs, 5, 24, 0, 0.05);
    for (k = 0; k < n && obs[k].kind == VP_OBS_MARK; k++) {}
    CHECK(k > 30 && vp_rf_fit(obs + k - 10, n - k + 10, &nominal, &out, &rep) == VP_EINVAL);   /* 10 marks only */
    CHECK(vp_rf_fit(obs + k - 25, n - k + 25, &nominal, &out, &rep) == VP_EDEGEN);   /* 25, all at one depth */
    n = make_obs(&t, &nominal, obs, 5, 24, 1, 0.05);
    CHECK(vp_rf_fit(obs, n, &nominal, &out, &rep) == VP_EDEGEN);                /* one distance: the beam is free */

    /* the camera alone (a line laser: the mark only): recovered, the beam and span left as given */
    n = make_obs(&t, &nominal, obs, 5, 24, 0, 0.05);
    for (k = 0; k < n && obs[k].kind == VP_OBS_MARK; k++) {}
    CHECK(vp_rf_fit_camera(obs, n, &nominal, &out, &rep) == VP_EINVAL);         /* spots among them */
    CHECK(vp_rf_fit_camera(obs, k, &nominal, &out, &rep) == VP_OK);
    CHECKF(fabs(out.cam.dist[0] + 0.15) < 0.003 && fabs(out.cam.fx - 352.5) < 0.5 && fabs(out.cam.cy - 236.4) < 0.5 &&
           vp_dist3(out.cam.pos, t.m.cam.pos) < 0.5 && rep.mark_rms_px < 0.08 && rep.spots == 0,
           "camera alone: k1 %.5f fx %.3f cy %.3f, centre %.3f mm off, %.4f px", out.cam.dist[0], out.cam.fx, out.cam.cy,
           vp_dist3(out.cam.pos, t.m.cam.pos), rep.mark_rms_px);
    CHECK(!memcmp(out.origin, nominal.origin, sizeof out.origin) && !memcmp(out.dir, nominal.dir, sizeof out.dir) &&
          out.min_range == nominal.min_range && out.max_range == nominal.max_range);
    printf("camera alone from %d marks: k1 %.5f, centre %.3f mm off the true one, %.4f px rms\n", k, out.cam.dist[0],
           vp_dist3(out.cam.pos, t.m.cam.pos), rep.mark_rms_px);
    CHECK(vp_rf_fit_camera(obs + k - 10, 10, &nominal, &out, &rep) == VP_EINVAL);   /* 10 marks only */
    CHECK(vp_rf_fit_camera(obs + k - 25, 25, &nominal, &out, &rep) == VP_EDEGEN);   /* 25, all at one depth */
}

/* ---- the kinematics aiming a beam calibrated 1 degree off +x ---- */
static void kin(void)
{
    vp_kin_config_t c;
    vp_kin_t k, plain;
    vp_rng_t rng;
    double cur[5] = { 100, 100, 100, 0, 0 }, j[5], o[3], d[3], worst = 0, worst_plain = 0, near_v = 0;
    int i, k_ok = 0;
    memset(&c, 0, sizeof c);
    c.tilt_offset[2] = 45;
    c.laser_offset[0] = 20; c.laser_offset[1] = 0.4; c.laser_offset[2] = -0.3;
    c.lo[3] = -190; c.hi[3] = 190; c.lo[4] = -90; c.hi[4] = 90;
    CHECK(vp_kin_init(&plain, &c) == VP_OK && !plain.tilted);
    c.laser_dir[0] = cos(PI / 180); c.laser_dir[1] = sin(PI / 180) * cos(PI / 6); c.laser_dir[2] = sin(PI / 180) * sin(PI / 6);
    CHECK(vp_kin_init(&k, &c) == VP_OK && k.tilted);
    vp_rng_seed(&rng, 3);
    for (i = 0; i < 2000; i++) {
        double w[3], n, e[3], want[3] = { 150, 120, 90 };
        int a;
        for (a = 0; a < 3; a++) w[a] = vp_rng_normal(&rng);
        n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        for (a = 0; a < 3; a++) w[a] /= n;
        if (fabs(w[2]) > 0.999) continue;
        if (vp_kin_aim(&k, cur, want, w, j) != VP_OK) continue;
        k_ok++;
        vp_kin_forward(&k, j, o, d);
        for (a = 0; a < 3; a++) e[a] = d[a] - w[a];
        if (sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) > worst) worst = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        for (a = 0; a < 3; a++) if (fabs(o[a] - want[a]) > worst) worst = fabs(o[a] - want[a]);
        /* the plain kinematics aim +x there: the beam as mounted misses the asked direction by ~1 degree */
        if (vp_kin_aim(&plain, cur, want, w, j) == VP_OK) {
            double r[9], p[3];
            vp_kin_head(&k, j, r, p);
            e[0] = r[0] * k.beam[0] + r[1] * k.beam[1] + r[2] * k.beam[2];
            e[1] = r[3] * k.beam[0] + r[4] * k.beam[1] + r[5] * k.beam[2];
            e[2] = r[6] * k.beam[0] + r[7] * k.beam[1] + r[8] * k.beam[2];
            n = acos(e[0] * w[0] + e[1] * w[1] + e[2] * w[2]) * 180 / PI;
            if (n > worst_plain) worst_plain = n;
        }
    }
    CHECKF(k_ok > 1500 && worst < 1e-9, "%d aimed, worst %.3g", k_ok, worst);
    CHECKF(worst_plain > 0.99, "the +x kinematics miss by %.4f deg only", worst_plain);
    {
        /* straight down: as steep as the beam goes, within its 1 degree */
        double down[3] = { 0, 0, -1 }, want[3] = { 150, 120, 90 };
        CHECK(vp_kin_aim(&k, cur, want, down, j) == VP_OK);
        vp_kin_forward(&k, j, o, d);
        near_v = acos(-d[2]) * 180 / PI;
        CHECKF(near_v <= 1.0001 && fabs(o[0] - 150) < 1e-9, "straight down: %.4f deg off", near_v);
    }
    printf("kinematics with the beam 1 deg off +x: %d directions aimed within %.1e (the +x kinematics: %.3f deg off); "
           "straight down %.3f deg off\n", k_ok, worst, worst_plain, near_v);
}

/* ---- the machine on the rpi4 board's dry run, lens and beam as mounted differ ---- */
#define TARGET_X 425.0

static void probe_at(vp_machine_t *m, double dist_to_target, vp_probe_result_t *res, vp_reading_t *kind)
{
    vp_cmd_t c;
    memset(&c, 0, sizeof c);
    c.kind = VP_CMD_PROBE;
    c.from[0] = TARGET_X - dist_to_target;
    c.from[1] = 150;
    c.from[2] = 150;
    c.dir[0] = 1;
    c.range = 400;
    CHECK(vp_machine_exec(m, &c, res) == VP_OK);
    *kind = vp_machine_reading(m, &c, 0, 0, res, NULL);
}

static void machine(void)
{
    static vp_calib_obs_t obs[2048];
    static double buv[VP_MACHINE_MAX_CALIB][2], bd[VP_MACHINE_MAX_CALIB];
    vp_board_t b = board;
    vp_dryrun_options_t o;
    vp_dryrun_t *dr = NULL;
    vp_machine_t *m;
    vp_calib_full_plan_t fp;
    vp_rf_model_t nominal, fitm;
    vp_rf_fit_report_t rep;
    vp_probe_result_t res;
    vp_reading_t kind;
    char err[300];
    double worst = 0;
    int n = 0, nb = 0, i;
    b.sim_cam.dist[0] = -0.15;
    b.sim_laser_error[0] = 1;
    b.sim_laser_error[1] = 30;
    b.have_mark = 1;
    b.cal_mark[0] = 190;
    b.cal_mark[1] = 150;
    memset(&o, 0, sizeof o);
    o.flat_target = 1;
    o.target_x = TARGET_X;
    CHECK(vp_dryrun_open(&b, &o, &dr, err, sizeof err) == VP_OK);
    if (!dr) return;
    m = vp_dryrun_machine(dr);
    CHECK(vp_machine_home(m) == VP_OK);
    CHECK(vp_rf_nominal(&b.cam_model, b.laser_offset, b.min_range, b.max_range, &nominal) == VP_OK);
    memset(&fp, 0, sizeof fp);
    fp.target_x = TARGET_X; fp.y = 150; fp.z = 150;
    fp.mark[0] = TARGET_X; fp.mark[1] = 190; fp.mark[2] = 150;
    fp.d_near = 10; fp.d_far = 400; fp.stations = 20;
    fp.depths = 6; fp.cols = 7; fp.rows = 5;
    fp.mark_near = 30; fp.mark_far = 300; fp.margin_px = 30;
    fp.nominal = &nominal;
    CHECK(vp_machine_calibrate_full(m, &fp, obs, 2048, &n, buv, bd, &nb) == VP_OK);
    CHECK(vp_rf_fit(obs, n, &nominal, &fitm, &rep) == VP_OK);
    CHECKF(fabs(fitm.cam.dist[0] + 0.15) < 0.005, "k1 %.5f", fitm.cam.dist[0]);
    /* probes read by the fitted model, against the renderer's truth */
    m->cfg.use_rf = 1;
    m->cfg.rf = fitm;
    for (i = 0; i < 8; i++) {
        double dd = 20 + 370.0 * i / 7;
        probe_at(m, dd, &res, &kind);
        CHECK(res.hit == 1 && kind == VP_READING_PLAIN);
        if (res.hit == 1) {
            double e = fabs(res.dist - vp_camsim_last(dr->cs)->dist);
            if (e > worst) worst = e;
        }
    }
    CHECKF(worst < 1, "probe error %.4f mm", worst);
    /* a span ending at 300 mm: a spot at 350 mm is refused as too close, never free */
    m->cfg.rf.max_range = 300;
    probe_at(m, 350, &res, &kind);
    CHECKF(res.hit == VP_PROBE_TOO_CLOSE && kind == VP_READING_BELOW_MODEL, "hit %d kind %d", res.hit, (int)kind);
    probe_at(m, 250, &res, &kind);
    CHECK(res.hit == 1);
    /* the 1-D model's path with its span ending at 300 mm reads the same spot as a miss (free
     * space): the behaviour the full model's refusal replaces */
    m->cfg.use_rf = 0;
    m->tri.max_range = 300;
    probe_at(m, 350, &res, &kind);
    CHECKF(res.hit == 0, "1-D path: hit %d", res.hit);
    printf("dry run (k1 -0.15, beam 1 deg off): %d observations, k1 %.5f, 8 probes 20..390 mm within %.4f mm of the "
           "renderer's truth; a spot at 350 mm beyond a 300 mm span: too close (the 1-D path: a miss)\n", n, fitm.cam.dist[0], worst);
    vp_dryrun_close(dr);
}

int main(int argc, char **argv)
{
    char err[300];
    int rc;
    if (argc == 3 && !strcmp(argv[1], "--opencv")) return opencv_compare(argv[2]);
    rc = vp_board_load("boards/rpi4-gantry.ini", &board, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    if (rc != VP_OK) return vp_test_done("test_port_calib");
    lens();
    fit();
    kin();
    machine();
    return vp_test_done("test_port_calib");
}
