/* voroprobe calibrate: the rangefinder model from a flat target at known distances, written to
 * a calibration file that the board loader reads (scan --calib FILE, or `calibration = FILE`). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_cli.h"
#include "vp_dryrun.h"
#include "vp_note.h"
#include "vp_scan.h"
#include "vp_vec3.h"

static void calibrate_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe calibrate --board FILE [--dry-run] [--out CALIB] [options]\n"
        "Fits the camera laser rangefinder. The head looks along machine +x at a flat matte target\n"
        "standing across x, steps towards it through stations evenly spaced in 1/distance (the\n"
        "distances come from the kinematics), finds the spot in each frame and fits the image line\n"
        "and the model d = (a + b s) / (1 + c s); the fit residual is reported and the model is\n"
        "written to CALIB (INI), which `scan --calib CALIB` or `calibration = CALIB` in the board's\n"
        "[rangefinder] uses.\n"
        "  --board FILE       the machine (boards/*.ini)\n"
        "  --out CALIB        the calibration file (default: the board's [rangefinder] calibration,\n"
        "                     else BOARD.calib beside the board file)\n"
        "  --target X,Y,Z     the target is the plane x = X; the beam meets it at y = Y, z = Z\n"
        "                     (default: the board's [calibrate] target)\n"
        "  --near D, --far D  nearest and farthest station, mm from the target\n"
        "  --stations N       distances (default 20), --frames N: exposures at each (default 3)\n"
        "  --dry-run          host-sim: the target rendered by the camera as mounted on the\n"
        "                     simulated head (the board's [sim] camera_position / camera_look_at);\n"
        "                     the fit is compared with that camera's true model\n"
        "  --seed N           dry run: seed of the frames' noise\n"
        "  --mark Y,Z         the full calibration (default when the board's [calibrate] has mark = Y, Z):\n"
        "                     a bright dot printed on the target at (X, Y, Z); the gantry shows it to the\n"
        "                     camera over the image at several depths (laser off) besides the beam stations\n"
        "                     (laser on), and Levenberg-Marquardt fits the camera's intrinsics, lens\n"
        "                     distortion (k1, k2, p1, p2) and pose in the tilt frame and the beam's origin\n"
        "                     and direction; scans then measure with that model and refuse spots outside\n"
        "                     the span it covered. The dry run compares it and the 1-D model with the\n"
        "                     renderer's true distances over the board's range. One frame pair per\n"
        "                     station (--frames applies to the 1-D calibration).\n"
        "                     A line laser ([rangefinder] laser = line): the camera from the mark alone, and\n"
        "                     the laser plane from the line seen on the target at the beam stations; the\n"
        "                     beam is the nominal one brought into that plane (the file records the plane).\n"
        "  --one-d            only the 1-D model, even with a mark\n"
        "Exit status: 0 written, 1 failed, 2 usage.\n");
}

static int nums(const char *s, double *v, int n)
{
    char *e;
    int i;
    for (i = 0; i < n; i++) {
        v[i] = strtod(s, &e);
        if (e == s || !isfinite(v[i])) return -1;
        s = e;
        if (i + 1 < n) { if (*s != ',') return -1; s++; }
    }
    return *s ? -1 : 0;
}

/* Largest distance error (mm, and px along the line) of model m against truth over [lo, hi]. */
static void model_error(const vp_tri_model_t *m, const vp_tri_model_t *truth, double lo, double hi, double *mm, double *px)
{
    int i;
    *mm = *px = 0;
    for (i = 0; i <= 200; i++) {
        double d = lo + (hi - lo) * i / 200.0, slope, s_t = vp_tri_s(truth, d), u, v, s_m, dm;
        vp_tri_eval(truth, s_t, &slope);
        u = truth->p0[0] + s_t * truth->e[0];
        v = truth->p0[1] + s_t * truth->e[1];
        s_m = (u - m->p0[0]) * m->e[0] + (v - m->p0[1]) * m->e[1];
        dm = vp_tri_eval(m, s_m, NULL);
        if (fabs(dm - d) > *mm) *mm = fabs(dm - d);
        if (slope > 0 && fabs(dm - d) / slope > *px) *px = fabs(dm - d) / slope;
    }
}

#define CAL_MAX_OBS 2048
#define CAL_VERIFY 40

static vp_calib_obs_t cal_obs[CAL_MAX_OBS];

static double deg_between(const double a[3], const double b[3])
{
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (vp_norm3(a) * vp_norm3(b));
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180 / 3.14159265358979323846;
}

/* Dry run: frames along the beam over the board's range, each read by the full model and the 1-D
 * model, against the renderer's true distance. */
static void calibrate_verify(vp_scan_dev_t *dev, const vp_board_t *b, const vp_calib_plan_t *plan, const vp_rf_model_t *rf,
                             const vp_tri_model_t *tri)
{
    double e_rf[2] = { 0, 0 }, e_1d[2] = { 0, 0 }, far_rf = NAN, far_1d = NAN, lo = b->min_range, hi = b->max_range;
    int i, n_rf = 0, n_1d = 0, ref_rf = 0, ref_1d = 0, seen = 0;
    vp_tri_model_t open1d = *tri;
    /* the 1-D model read without its span limits (the beam's 1 / cos of a misalignment takes the
     * farthest frame just past them): its error, not its refusal, is compared */
    open1d.min_range = 0.5 * lo;
    open1d.max_range = 2 * hi;
    for (i = 0; i < CAL_VERIFY; i++) {
        double dd = lo + (hi - lo) * i / (CAL_VERIFY - 1), o[3], uv[2], d, truth, gap;
        const vp_camsim_truth_t *tr;
        vp_spot_t spot;
        int why, st;
        o[0] = plan->target_x - dd; o[1] = plan->y; o[2] = plan->z;
        if (vp_machine_goto(dev->m, o) != VP_OK) continue;
        if (vp_machine_observe(dev->m, NULL, &spot) != VP_OK || spot.result != VP_SPOT_FOUND) continue;
        tr = vp_camsim_last(dev->dr->cs);
        if (!tr->hit) continue;
        truth = tr->dist;
        seen++;
        uv[0] = spot.u;
        uv[1] = spot.v;
        if (vp_rf_distance(rf, uv, &d, &why, &gap) == VP_OK && why == VP_RF_OK) {
            double e = fabs(d - truth);
            n_rf++;
            e_rf[0] += e * e;
            if (e > e_rf[1]) e_rf[1] = e;
            if (i == CAL_VERIFY - 1) far_rf = e;
        } else ref_rf++;
        st = vp_tri_distance(&open1d, uv, &d);
        if (st == VP_OK) {
            double e = fabs(d - truth);
            n_1d++;
            e_1d[0] += e * e;
            if (e > e_1d[1]) e_1d[1] = e;
            if (i == CAL_VERIFY - 1) far_1d = e;
        } else ref_1d++;
    }
    printf("dry run: %d frames along the true beam over %g..%g mm, distances against the renderer's truth:\n", seen, lo, hi);
    {
        char f1[32], f2[32];
        if (isnan(far_rf)) snprintf(f1, sizeof f1, "refused"); else snprintf(f1, sizeof f1, "%.4f mm", far_rf);
        if (isnan(far_1d)) snprintf(f2, sizeof f2, "refused"); else snprintf(f2, sizeof f2, "%.4f mm", far_1d);
        printf("  full model: worst %.4f mm, rms %.4f mm, at %g mm %s; refused %d\n", e_rf[1], n_rf ? sqrt(e_rf[0] / n_rf) : 0,
               hi, f1, ref_rf);
        printf("  1-D model:  worst %.4f mm, rms %.4f mm, at %g mm %s; refused %d (off its line)\n", e_1d[1],
               n_1d ? sqrt(e_1d[0] / n_1d) : 0, hi, f2, ref_1d);
    }
}

/* A line laser's nominal fan (the board's line_normal, the beam +x brought into it), seen by cam. */
static void line_nominal(const vp_board_t *b, const vp_camera_model_t *cam, vp_line_model_t *l)
{
    static vp_board_t nb;
    static vp_machine_config_t mc;
    nb = *b;
    nb.have_rf = nb.have_plane = 0;
    vp_board_machine_config(&nb, &mc);
    *l = mc.line_model;
    l->cam = *cam;
}

/* A line laser: its plane fitted to the line seen at the beam stations with the camera just
 * calibrated from the mark; the beam becomes the nominal one brought into that plane (where the
 * fan's centre lies within its plane no flat target shows), the span the columns' distances
 * from its origin; the 1-D model follows from that beam. */
static int calibrate_plane(vp_scan_dev_t *dev, const vp_board_t *b, const vp_calib_full_plan_t *fp, int dry,
                           vp_rf_model_t *fit, vp_board_calib_t *info, double (*beam_uv)[2], double *beam_d, int *nbeam)
{
    vp_calib_obs_t *lobs;
    vp_line_model_t nom, plane;
    vp_line_fit_report_t lrep;
    int cap = fp->stations * VP_MACHINE_MAX_LINE, nl = 0, poses = 0, st, i, k;
    lobs = malloc((size_t)cap * sizeof *lobs);
    if (!lobs) { fprintf(stderr, "calibrate: out of memory for the line's observations\n"); return 1; }
    st = vp_machine_calibrate_line(dev->m, fp, lobs, cap, &nl, &poses);
    if (st != VP_OK) {
        char why[300];
        free(lobs);
        dev->fault = st;
        vp_scan_fault_text(dev, why, sizeof why);
        fprintf(stderr, "calibrate: the line at the beam stations: %s\n", why);
        return 1;
    }
    line_nominal(b, &fit->cam, &nom);
    st = vp_line_fit_plane(&fit->cam, lobs, nl, &nom, &plane, &lrep);
    free(lobs);
    if (st != VP_OK) {
        fprintf(stderr, "calibrate: the laser plane cannot be fitted from %d columns of the line at %d of %d stations%s\n", nl,
                poses, fp->stations, st == VP_EDEGEN ? " (one target distance only, or a ray that misses the target)"
                                                     : " (too few: is the line on the target and in view?)");
        return 1;
    }
    memcpy(fit->origin, plane.origin, sizeof fit->origin);
    memcpy(fit->dir, plane.axis, sizeof fit->dir);
    fit->min_range = lrep.span[0] - 0.5 - 0.002 * lrep.span[0];
    fit->max_range = lrep.span[1] + 0.5 + 0.002 * lrep.span[1];
    if (fit->min_range < 0.5 * lrep.span[0]) fit->min_range = 0.5 * lrep.span[0];
    printf("line plane: %d columns of the line on the target at %d of %d stations; normal (%.6f, %.6f, %.6f), %.4f deg from "
           "the board's line_normal; the columns %.4f mm rms (max %.4f mm) off it, %.1f..%.1f mm from its origin\n", nl, poses,
           fp->stations, plane.normal[0], plane.normal[1], plane.normal[2], lrep.tilt_deg, lrep.rms_mm, lrep.max_mm,
           lrep.span[0], lrep.span[1]);
    printf("  beam: the nominal one in that plane: origin (%.3f, %.3f, %.3f) mm, direction (%.6f, %.6f, %.6f), %.4f deg from +x; "
           "calibrated span %.1f..%.1f mm\n", fit->origin[0], fit->origin[1], fit->origin[2], fit->dir[0], fit->dir[1],
           fit->dir[2], acos(fit->dir[0] > 1 ? 1 : fit->dir[0]) * 180 / 3.14159265358979323846, fit->min_range, fit->max_range);
    if (dry) {
        double to[3], tn[3], q[3], c;
        if (vp_dryrun_true_plane(dev->dr, to, tn)) {
            for (k = 0; k < 3; k++) q[k] = fit->origin[k] - to[k];
            c = fabs(vp_dot3(plane.normal, tn));
            printf("dry run truth: the plane as mounted, normal (%.6f, %.6f, %.6f), %.4f deg from the board's; fitted %.4f deg "
                   "off it, its origin %.4f mm off it; k1 %.5f (fitted %.5f)\n", tn[0], tn[1], tn[2],
                   acos(fmin(1.0, fabs(vp_dot3(nom.normal, tn)))) * 180 / 3.14159265358979323846,
                   acos(fmin(1.0, c)) * 180 / 3.14159265358979323846, fabs(vp_dot3(q, tn)), b->sim_cam.dist[0],
                   fit->cam.dist[0]);
        }
    }
    /* the 1-D model: the fitted beam's points at the stations' distances, as the camera sees them */
    *nbeam = 0;
    for (i = 0; i < fp->stations; i++) {
        double dd = 1 / (1 / fp->d_far + (1 / fp->d_near - 1 / fp->d_far) * i / (fp->stations - 1)), uv[2];
        if (vp_rf_spot(fit, dd, uv) && uv[0] >= 0 && uv[0] < fit->cam.width && uv[1] >= 0 && uv[1] < fit->cam.height) {
            beam_uv[*nbeam][0] = uv[0];
            beam_uv[*nbeam][1] = uv[1];
            beam_d[(*nbeam)++] = dd;
        }
    }
    info->have_plane = 1;
    memcpy(info->plane_origin, plane.origin, sizeof info->plane_origin);
    memcpy(info->plane_normal, plane.normal, sizeof info->plane_normal);
    info->plane_points = lrep.n;
    info->plane_poses = poses;
    info->plane_rms_mm = lrep.rms_mm;
    info->plane_max_mm = lrep.max_mm;
    info->plane_tilt_deg = lrep.tilt_deg;
    return 0;
}

/* The full calibration: observations, the fit, the report, the file. */
static int calibrate_full(vp_scan_dev_t *dev, const vp_board_t *b, const vp_calib_plan_t *plan, const double mark[2],
                          int dry, const char *path)
{
    static double beam_uv[VP_MACHINE_MAX_CALIB][2], beam_d[VP_MACHINE_MAX_CALIB];
    vp_calib_full_plan_t fp;
    vp_rf_model_t nominal, fit;
    vp_rf_fit_report_t rep;
    vp_tri_model_t tri;
    vp_tri_fit_report_t trep;
    vp_board_calib_t info;
    char err[1200];
    int n = 0, nbeam = 0, st, k, line = b->line_laser;
    st = vp_rf_nominal(&b->cam_model, b->laser_offset, b->min_range, b->max_range, &nominal);
    if (st != VP_OK) { fprintf(stderr, "calibrate: the board's camera and laser give no nominal model\n"); return 1; }
    memset(&fp, 0, sizeof fp);
    fp.target_x = plan->target_x;
    fp.y = plan->y;
    fp.z = plan->z;
    fp.mark[0] = plan->target_x;
    fp.mark[1] = mark[0];
    fp.mark[2] = mark[1];
    fp.d_near = plan->d_near;
    fp.d_far = plan->d_far;
    fp.stations = plan->stations;
    fp.depths = 6;
    fp.cols = 7;
    fp.rows = 5;
    fp.mark_near = 30;
    fp.mark_far = plan->d_far < 300 ? plan->d_far : 300;
    fp.margin_px = 30;
    fp.nominal = &nominal;
    if (fp.mark_far < fp.mark_near) fp.mark_far = fp.mark_near;
    st = vp_machine_calibrate_full(dev->m, &fp, cal_obs, CAL_MAX_OBS, &n, beam_uv, beam_d, &nbeam);
    if (st == VP_ESTATE) {
        fprintf(stderr, "calibrate: the full calibration sees the mark with the laser off: the board needs a [laser] pin\n");
        return 1;
    }
    if (st == VP_ERANGE) {
        fprintf(stderr, "calibrate: the beam stations (x = %g .. %g, y = %g, z = %g) are outside the machine's travel\n",
                plan->target_x - plan->d_far, plan->target_x - plan->d_near, plan->y, plan->z);
        return 1;
    }
    if (st != VP_OK) {
        char why[300];
        dev->fault = st;
        vp_scan_fault_text(dev, why, sizeof why);
        fprintf(stderr, "calibrate: %s\n", why);
        return 1;
    }
    /* a line laser has no spot: the camera from the mark alone, then its plane */
    memset(&rep, 0, sizeof rep);
    st = line ? vp_rf_fit_camera(cal_obs, n, &nominal, &fit, &rep) : vp_rf_fit(cal_obs, n, &nominal, &fit, &rep);
    {
        int marks = 0, spots = 0;
        for (k = 0; k < n; k++) { if (cal_obs[k].kind == VP_OBS_MARK) marks++; else spots++; }
        if (st == VP_EINVAL && line) {
            fprintf(stderr, "calibrate: too few observations: %d of the mark (at least %d): is the mark at y = %g, z = %g "
                            "on the target, lit, and in view?\n", marks, VP_CALIB_MIN_MARKS, mark[0], mark[1]);
            return 1;
        }
        if (st == VP_EINVAL) {
            fprintf(stderr, "calibrate: too few observations: %d of the mark (at least %d) and %d laser spots (at least %d): "
                            "is the mark at y = %g, z = %g on the target, lit, and in view?\n", marks, VP_CALIB_MIN_MARKS, spots,
                    VP_CALIB_MIN_SPOTS, mark[0], mark[1]);
            return 1;
        }
        if (st == VP_EDEGEN && rep.iterations > 0) {
            fprintf(stderr, "calibrate: the fit does not converge: residual rms %.2f px over all %d observations, %d of them "
                            "farther than %g px (more than 1 in 10): are the mark (y = %g, z = %g; the brightest thing in view "
                            "with the laser off) and the spots read where they are, and the board's camera and laser near "
                            "the real ones?\n",
                    rep.rms_px, n, rep.strays, 3 * VP_CALIB_HUBER_PX, mark[0], mark[1]);
            return 1;
        }
        if (st != VP_OK) {
            fprintf(stderr, "calibrate: the observations (%d of the mark, %d spots) do not fix every parameter of the model "
                            "(the mark seen at one depth only, the spots at one distance?) or the fit does not converge\n",
                    marks, spots);
            return 1;
        }
    }
    fit.ray_tol_px = 3;
    if (line)
        printf("camera fit (the mark alone: a line laser has no spot): %d observations, %d iterations; residual rms %.4f px "
               "(nominal model %.3f px), max %.4f px, %d beyond %g px, %d of them beyond %g px\n", n, rep.iterations,
               rep.rms_px, rep.start_rms_px, rep.max_px, rep.outliers, VP_CALIB_HUBER_PX, rep.strays, 3 * VP_CALIB_HUBER_PX);
    else
    printf("full fit: %d observations (%d of the mark, %d laser spots), %d iterations; residual rms %.4f px "
           "(nominal model %.3f px), max %.4f px, %d beyond %g px, %d of them beyond %g px; mark %.4f px rms, spots "
           "%.4f px rms, %.4f mm rms (max %.4f mm) along the beam\n", n, rep.marks, rep.spots, rep.iterations, rep.rms_px,
           rep.start_rms_px, rep.max_px, rep.outliers, VP_CALIB_HUBER_PX, rep.strays, 3 * VP_CALIB_HUBER_PX, rep.mark_rms_px,
           rep.spot_rms_px, rep.spot_rms_mm, rep.spot_max_mm);
    printf("  intrinsics: fx %.3f (%+.3f), fy %.3f (%+.3f), cx %.3f (%+.3f), cy %.3f (%+.3f) px\n", fit.cam.fx,
           fit.cam.fx - nominal.cam.fx, fit.cam.fy, fit.cam.fy - nominal.cam.fy, fit.cam.cx, fit.cam.cx - nominal.cam.cx,
           fit.cam.cy, fit.cam.cy - nominal.cam.cy);
    printf("  distortion: k1 %.5f, k2 %.5f, p1 %.6f, p2 %.6f (nominal %g, %g, %g, %g)\n", fit.cam.dist[0], fit.cam.dist[1],
           fit.cam.dist[2], fit.cam.dist[3], nominal.cam.dist[0], nominal.cam.dist[1], nominal.cam.dist[2], nominal.cam.dist[3]);
    printf("  camera: centre (%.3f, %.3f, %.3f) mm (moved %.3f mm), axis turned %.4f deg from the nominal\n", fit.cam.pos[0],
           fit.cam.pos[1], fit.cam.pos[2], vp_dist3(fit.cam.pos, nominal.cam.pos), deg_between(fit.cam.rot + 6, nominal.cam.rot + 6));
    if (!line)
    printf("  beam: origin (%.3f, %.3f, %.3f) mm (moved %.3f mm), direction (%.6f, %.6f, %.6f), %.4f deg from +x; "
           "calibrated span %.1f..%.1f mm\n", fit.origin[0], fit.origin[1], fit.origin[2], vp_dist3(fit.origin, nominal.origin),
           fit.dir[0], fit.dir[1], fit.dir[2], deg_between(fit.dir, nominal.dir), fit.min_range, fit.max_range);
    memset(&info, 0, sizeof info);
    if (line && calibrate_plane(dev, b, &fp, dry, &fit, &info, beam_uv, beam_d, &nbeam)) return 1;
    if (nbeam < 4 || vp_tri_fit((const double (*)[2])beam_uv, beam_d, nbeam, 0, 0, &tri, &trep) != VP_OK) {
        fprintf(stderr, "calibrate: fewer than 4 spots at the beam stations\n");
        return 1;
    }
    printf("1-D model from the beam stations: %d %s, residual rms %.4f mm, max %.4f mm; spots off its line %.3f px rms\n",
           trep.n, line ? "points of the fitted beam" : "spots", trep.rms_mm, trep.max_mm, trep.line_rms_px);
    if (dry && !line) {
        double td[3], ang = b->sim_laser_error[0] * 3.14159265358979323846 / 180, az = b->sim_laser_error[1] * 3.14159265358979323846 / 180;
        td[0] = cos(ang); td[1] = sin(ang) * cos(az); td[2] = sin(ang) * sin(az);
        printf("dry run truth: k1 %.5f, k2 %.5f, p1 %.6f, p2 %.6f; beam %.4f deg from +x (fitted: %.4f deg off it), "
               "camera centre off by %.3f mm\n", b->sim_cam.dist[0], b->sim_cam.dist[1], b->sim_cam.dist[2], b->sim_cam.dist[3],
               b->sim_laser_error[0], deg_between(fit.dir, td), vp_dist3(fit.cam.pos, b->sim_cam.pos));
        calibrate_verify(dev, b, plan, &fit, &tri);
    }
    info.spots = trep.n;
    info.stations = plan->stations;
    info.near = plan->d_near;
    info.far = plan->d_far;
    info.rms_mm = trep.rms_mm;
    info.max_mm = trep.max_mm;
    info.line_rms_px = trep.line_rms_px;
    info.tri = tri;
    info.have_rf = 1;
    info.rf = fit;
    info.rf_rms_px = rep.rms_px;
    st = vp_board_calibration_write(path, b, &info, err, sizeof err);
    if (st == VP_OK) {
        vp_board_t check = *b;
        st = vp_board_calibration_load(&check, path, NULL, err, sizeof err);   /* reads back */
    }
    if (st != VP_OK) { fprintf(stderr, "calibrate: %s\n", err); return 1; }
    printf("wrote %s (use it: scan --calib %s, or `calibration = FILE` in [rangefinder] of %s)\n", path, path, b->path);
    return 0;
}

int vp_cli_calibrate(int argc, char **argv)
{
    const char *board = NULL, *out = NULL;
    double target[3], v, near = 0, far = 0;
    int have_target = 0, stations = 0, frames = 0, dry = 0, i, st, rc = 1, dev_open = 0, have_mark = 0, one_d = 0;
    double mark[2] = { 0, 0 };
    unsigned long long seed = 0;
    vp_board_t b;
    vp_scan_dev_t dev;
    vp_calib_plan_t plan;
    vp_tri_model_t fit;
    vp_tri_fit_report_t rep;
    vp_board_calib_t info;
    char err[1200], path[VP_PATH_MAX];
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        char *e;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { calibrate_usage(stdout); return 0; }
        if (!strcmp(a, "--dry-run")) { dry = 1; continue; }
        if (!strcmp(a, "--one-d")) { one_d = 1; continue; }
        if (strcmp(a, "--board") && strcmp(a, "--out") && strcmp(a, "--target") && strcmp(a, "--near") && strcmp(a, "--mark") &&
            strcmp(a, "--far") && strcmp(a, "--stations") && strcmp(a, "--frames") && strcmp(a, "--seed")) {
            fprintf(stderr, "calibrate: unknown option %s (see --help)\n", a);
            return 2;
        }
        if (!val) { fprintf(stderr, "calibrate: %s needs a value\n", a); return 2; }
        i++;
        if (!strcmp(a, "--board")) { board = val; continue; }
        if (!strcmp(a, "--out")) { out = val; continue; }
        if (!strcmp(a, "--target")) {
            if (nums(val, target, 3)) { fprintf(stderr, "calibrate: --target takes X,Y,Z, not '%s'\n", val); return 2; }
            have_target = 1;
            continue;
        }
        if (!strcmp(a, "--mark")) {
            if (nums(val, mark, 2)) { fprintf(stderr, "calibrate: --mark takes Y,Z, not '%s'\n", val); return 2; }
            have_mark = 1;
            continue;
        }
        v = strtod(val, &e);
        if (e == val || *e || !(v > 0) || !isfinite(v)) { fprintf(stderr, "calibrate: %s takes a positive number, not '%s'\n", a, val); return 2; }
        if (!strcmp(a, "--near")) near = v;
        else if (!strcmp(a, "--far")) far = v;
        else if (!strcmp(a, "--seed")) seed = (unsigned long long)v;
        else if (v != floor(v)) { fprintf(stderr, "calibrate: %s takes a whole number\n", a); return 2; }
        else if (!strcmp(a, "--stations")) stations = (int)v;
        else frames = (int)v;
    }
    if (!board) { fprintf(stderr, "calibrate: give the machine: --board FILE (see --help)\n"); return 2; }
    st = vp_board_load(board, &b, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "calibrate: %s\n", err); return 1; }

    /* the fixture: options, else the board's [calibrate], else (dry runs) Omega's far side */
    memset(&plan, 0, sizeof plan);
    if (!have_target && b.have_fixture) { memcpy(target, b.cal_target, sizeof target); have_target = 1; }
    if (!have_target && dry) {
        int k;
        for (k = 0; k < 3; k++) target[k] = b.omega_kind == VP_OMEGA_BOX ? 0.5 * (b.omega_lo[k] + b.omega_hi[k]) : b.omega_center[k];
        target[0] = b.omega_kind == VP_OMEGA_BOX ? b.omega_hi[0] : b.omega_center[0] + b.omega_radius;
        have_target = 1;
    }
    if (!have_target) {
        fprintf(stderr, "calibrate: %s has no [calibrate] section: say where the flat target stands with --target X,Y,Z\n", b.path);
        return 2;
    }
    plan.target_x = target[0];
    plan.y = target[1];
    plan.z = target[2];
    plan.d_near = near ? near : b.have_fixture ? b.cal_near : 1.5 * b.min_range;
    plan.d_far = far ? far : b.have_fixture ? b.cal_far : (b.max_range < 200 ? b.max_range : 200);
    plan.stations = stations ? stations : b.have_fixture ? b.cal_stations : 20;
    plan.frames = frames ? frames : b.have_fixture ? b.cal_frames : 3;
    if (!have_mark && b.have_mark) { mark[0] = b.cal_mark[0]; mark[1] = b.cal_mark[1]; have_mark = 1; }
    if (one_d) have_mark = 0;
    if (have_mark) {
        /* the dry run draws it */
        b.have_mark = 1;
        b.cal_mark[0] = mark[0];
        b.cal_mark[1] = mark[1];
    }
    if (b.line_laser && !have_mark) {
        fprintf(stderr, "calibrate: %s has a line laser: it is calibrated with a mark on the target (the camera) and its line "
                        "(the plane), not with the 1-D model; give [calibrate] mark = Y, Z or --mark Y,Z\n", b.path);
        return 2;
    }
    if (!(plan.d_near < plan.d_far)) { fprintf(stderr, "calibrate: --near (%g) must be below --far (%g)\n", plan.d_near, plan.d_far); return 2; }
    if (plan.stations < 4 || plan.stations * plan.frames > VP_MACHINE_MAX_CALIB) {
        fprintf(stderr, "calibrate: stations (at least 4) x frames must be at most %d\n", VP_MACHINE_MAX_CALIB);
        return 2;
    }
    if (out) st = vp_path_cat(path, sizeof path, out, "", err, sizeof err);
    else if (b.calib_path[0]) st = vp_path_cat(path, sizeof path, b.calib_path, "", err, sizeof err);
    else {
        /* BOARD.ini -> BOARD.calib */
        size_t len = strlen(board);
        char stem[VP_PATH_MAX];
        st = vp_path_cat(stem, sizeof stem, board, "", err, sizeof err);
        if (st == VP_OK && len > 4 && !strcmp(stem + len - 4, ".ini")) stem[len - 4] = 0;
        if (st == VP_OK) st = vp_path_cat(path, sizeof path, stem, ".calib", err, sizeof err);
    }
    if (st != VP_OK) { fprintf(stderr, "calibrate: %s\n", err); return 2; }

    st = vp_scan_open(&dev, &b, dry, NULL, plan.target_x, seed, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "calibrate: %s\n", err); return 1; }
    dev_open = 1;
    fprintf(stderr, "calibrate: board %s (%s)%s; flat target at x = %g mm, beam crossing it at y = %g, z = %g\n", b.name,
            b.path, dry ? ", dry run on host-sim" : "", plan.target_x, plan.y, plan.z);
    st = vp_scan_home(&dev, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "calibrate: %s\n", err); goto done; }
    if (have_mark) {
        fprintf(stderr, "calibrate: homed; full calibration: %d beam stations from %g to %g mm from the target and the mark "
                        "at y = %g, z = %g shown over the image at 6 depths\n", plan.stations, plan.d_far, plan.d_near, mark[0], mark[1]);
        rc = calibrate_full(&dev, &b, &plan, mark, dry, path);
        goto done;
    }
    fprintf(stderr, "calibrate: homed; %d stations from %g to %g mm from the target, %d frame(s) each\n", plan.stations,
            plan.d_far, plan.d_near, plan.frames);
    st = vp_machine_calibrate(dev.m, &plan, &fit, &rep);
    if (st != VP_OK) {
        char why[300];
        dev.fault = st;
        vp_scan_fault_text(&dev, why, sizeof why);
        if (st == VP_EDEGEN)
            fprintf(stderr, "calibrate: fewer than 4 spots found: is the target there, lit by the laser and in view? "
                            "Or do the camera's frames lag the laser by more than [camera] latency_frames = %d?\n",
                    b.latency_frames);
        else if (st == VP_ERANGE) fprintf(stderr, "calibrate: the stations (x = %g .. %g, y = %g, z = %g) are outside the machine's travel\n",
                                          plan.target_x - plan.d_far, plan.target_x - plan.d_near, plan.y, plan.z);
        else fprintf(stderr, "calibrate: %s\n", why);
        goto done;
    }
    {
        /* the camera's pipeline latency, with the target in view (the spot looked for along the
         * line just fitted): frames that may still show the laser as it was before a switch; the
         * board's [camera] latency_frames must cover it */
        vp_tri_model_t keep = dev.m->tri;
        int lat = -1, lst;
        dev.m->tri = fit;
        lst = vp_machine_measure_latency(dev.m, 5, 16, &lat);
        dev.m->tri = keep;
        if (lst == VP_OK)
            printf("camera latency: %d frame(s) measured after a laser switch (board: latency_frames = %d)%s\n", lat,
                   b.latency_frames, lat > b.latency_frames ? ": RAISE latency_frames above it" : "");
        else
            printf("camera latency: not measured (%s)\n", lst == VP_ESTATE ? "no laser line or no frame sequence numbers"
                                                                          : vp_strerror(lst));
    }
    {
        /* back away from the target along the stations' line (the way the head came) */
        double away[3];
        away[0] = plan.target_x - plan.d_far;
        away[1] = plan.y;
        away[2] = plan.z;
        if (vp_scan_goto(&dev, away, err, sizeof err) != VP_OK) fprintf(stderr, "calibrate: %s\n", err);
    }
    printf("fit: %d spots at %d stations (%g..%g mm), residual rms %.4f mm, max %.4f mm; spots off the fitted line %.3f px rms\n",
           rep.n, plan.stations, plan.d_near, plan.d_far, rep.rms_mm, rep.max_mm, rep.line_rms_px);
    printf("model: line P0 = (%.4f, %.4f) px, E = (%.6f, %.6f); d = (%.6g + %.6g s) / (1 + %.6g s) mm\n", fit.p0[0], fit.p0[1],
           fit.e[0], fit.e[1], fit.a, fit.b, fit.c);
    if (dry) {
        vp_tri_model_t truth, nominal;
        double mm, px, mm0, px0;
        if (vp_tri_from_geometry(&b.sim_cam, b.laser_offset, b.min_range, b.max_range, &truth) == VP_OK &&
            vp_tri_from_geometry(&b.cam_model, b.laser_offset, b.min_range, b.max_range, &nominal) == VP_OK) {
            model_error(&fit, &truth, plan.d_near, plan.d_far, &mm, &px);
            model_error(&nominal, &truth, plan.d_near, plan.d_far, &mm0, &px0);
            printf("dry run: against the true model of the mounted camera over %g..%g mm: worst %.4f mm (%.4f px); "
                   "the camera geometry of [camera] alone is off by up to %.3f mm (%.2f px)\n", plan.d_near, plan.d_far, mm,
                   px, mm0, px0);
        }
    }
    memset(&info, 0, sizeof info);
    info.spots = rep.n;
    info.stations = plan.stations;
    info.near = plan.d_near;
    info.far = plan.d_far;
    info.rms_mm = rep.rms_mm;
    info.max_mm = rep.max_mm;
    info.line_rms_px = rep.line_rms_px;
    info.tri = fit;
    st = vp_board_calibration_write(path, &b, &info, err, sizeof err);
    if (st == VP_OK) {
        vp_board_t check = b;
        st = vp_board_calibration_load(&check, path, NULL, err, sizeof err);   /* reads back */
    }
    if (st != VP_OK) { fprintf(stderr, "calibrate: %s\n", err); goto done; }
    printf("wrote %s (use it: scan --calib %s, or `calibration = FILE` in [rangefinder] of %s)\n", path, path, b.path);
    if (rep.rms_mm > 1) fprintf(stderr, "calibrate: warning: the residual is large (%.2f mm): check the target and the focus\n", rep.rms_mm);
    rc = 0;
done:
    if (dev_open) vp_scan_close(&dev);
    return rc;
}
