/* The line laser (port/vp_line) against the renderer's own ray casting (host/vp_camsim): the
 * geometry alone (points on the plane projected and measured back); the laser plane calibrated
 * from a flat target at 5 distances (50-400 mm) through a board-like camera (f 350 px, 640 x 480,
 * lens k1 = -0.15) with the plane as mounted 1 degree off the nominal one, then the flat target
 * and a sphere measured against the truth per column; the faults of a real room (0 false points);
 * a dark band (misses, not points); a shifted line the checker must flag; two equal lines in a
 * column (nothing reported); the contract (NaN, NULL, bad sizes). Prints the figures. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_calib.h"
#include "vp_camsim.h"
#include "vp_line.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"
#include "vp_vec3.h"

#define PI 3.14159265358979323846
#define W 640
#define H 480
#define NDIST 5

static uint8_t img_on[W * H], img_off[W * H];
static vp_line_ws_t ws;
static vp_line_point_t pts[W];
static vp_camsim_line_truth_t truth;
static const double ident[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, zero3[3] = { 0, 0, 0 };
static const double dists[NDIST] = { 50, 137.5, 225, 312.5, 400 };

/* The head: the laser at (20, 0, 0) in the tilt frame, its fan nominally in the plane z = 0 about
 * +x, +-30 degrees; the camera 30 mm above it (the baseline across the plane), looking at the
 * fan 100 mm out; the line runs across the image, one point per column. */
static void config(vp_camsim_config_t *c, const double normal[3])
{
    memset(c, 0, sizeof *c);
    c->cam.width = W;
    c->cam.height = H;
    c->cam.fx = c->cam.fy = 350;
    c->cam.cx = 319.5;
    c->cam.cy = 239.5;
    c->cam.dist[0] = -0.15;
    c->cam.pos[2] = 30;
    vp_camera_look_at(&c->cam, (double[3]){ 100, 0, 0 }, (double[3]){ 0, 0, 1 });
    c->laser_offset[0] = 20;
    c->laser_kind = VP_CAMSIM_LINE;
    c->fan_half_angle = 30 * PI / 180;
    memcpy(c->line_normal, normal, sizeof c->line_normal);
    c->line_energy = 400000;
    c->blur_px = 1.3;
    c->noise = 2;
    c->ambient = 30;
}

static vp_frame_t frame(const uint8_t *p)
{
    vp_frame_t f;
    memset(&f, 0, sizeof f);
    f.data = p; f.width = W; f.height = H; f.stride = W; f.step = 1;
    return f;
}

/* a laser-on / laser-off pair, 33 ms apart, and the line's truth */
static int pair(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, vp_rng_t *rng)
{
    vp_camsim_truth_t tr;
    VP_TRY(vp_camsim_render_ex(c, sc, ident, zero3, rng, img_on, W, 1, 0, &tr, &truth));
    return vp_camsim_render_ex(c, sc, ident, zero3, rng, img_off, W, 0, 33333333, &tr, NULL);
}

static void target(vp_camsim_scene_t *sc, double d)
{
    memset(sc, 0, sizeof *sc);
    sc->plane_n[0] = 1;
    sc->plane_d = 20 + d;
}

/* the nominal model: the plane z = 0 through the laser, the fan about +x */
static void nominal(const vp_camera_model_t *cam, vp_line_model_t *m)
{
    memset(m, 0, sizeof *m);
    m->cam = *cam;
    m->origin[0] = 20;
    m->normal[2] = 1;
    m->axis[0] = 1;
    m->half_angle = 29.5 * PI / 180;   /* the fan's trusted part (its ends fade) */
    m->min_range = 20;
    m->max_range = 500;
}

/* mm per px along the column at a point: the tolerance's scale (the error a given centre error
 * makes there) */
static double mm_per_px(const vp_line_model_t *m, double u, double v)
{
    double a[2] = { u, v - 0.5 }, b[2] = { u, v + 0.5 }, da, db, dir[3], pa[3], pb[3];
    if (vp_line_point3d(m, a, &da, dir, pa) != VP_OK || vp_line_point3d(m, b, &db, dir, pb) != VP_OK) return 50;
    return hypot(hypot(pa[0] - pb[0], pa[1] - pb[1]), pa[2] - pb[2]);
}

typedef struct score {
    int n, false_pts, compared;
    double rms, worst, sum2;
} score_t;

/* Every reported point against the truth of its column: the error, and a false point when the
 * column has no true point or the error exceeds 3 x the expected: a centre error of 0.1 px (noise)
 * and, under laser speckle of contrast C, C x 0.6 px more (in quadrature: grains of 4.2 px across
 * a line 1.3-1.9 px wide move its centre by 0.17-0.26 px rms at C = 0.5, measured below), at the
 * mm per px of that place; and 0.05 mm. */
static double speckle_px;

static void grade(const vp_line_model_t *m, int n, score_t *s)
{
    int i;
    memset(s, 0, sizeof *s);
    s->n = n;
    for (i = 0; i < n; i++) {
        const vp_line_point_t *p = &pts[i];
        double e, tol;
        if (truth.count[p->col] != 1) { s->false_pts++; continue; }
        e = hypot(hypot(p->p[0] - truth.p[p->col][0], p->p[1] - truth.p[p->col][1]), p->p[2] - truth.p[p->col][2]);
        tol = 3 * (hypot(0.1, speckle_px) * mm_per_px(m, p->u, p->v) + 0.05);
        if (e > tol) s->false_pts++;
        s->sum2 += e * e;
        s->compared++;
        if (e > s->worst) s->worst = e;
    }
    s->rms = s->compared ? sqrt(s->sum2 / s->compared) : 0;
}

/* the centre's error in px against the truth's image row: rms and worst */
static void px_error(int n, double *rms, double *worst)
{
    double s2 = 0;
    int i, k = 0;
    *worst = 0;
    for (i = 0; i < n; i++) {
        double dv;
        if (truth.count[pts[i].col] != 1) continue;
        dv = fabs(pts[i].v - truth.v[pts[i].col]);
        s2 += dv * dv;
        k++;
        if (dv > *worst) *worst = dv;
    }
    *rms = k ? sqrt(s2 / k) : 0;
}

static int true_columns(void)
{
    int x, k = 0;
    for (x = 0; x < W; x++) k += truth.count[x] == 1;
    return k;
}

/* ---- the geometry alone ---- */
static void geometry(void)
{
    vp_camsim_config_t c;
    vp_line_model_t m;
    double nrm[3] = { 0, 0.0123, 1 }, worst = 0, l;
    int i, k, n = 0;
    config(&c, nrm);
    nominal(&c.cam, &m);
    l = vp_norm3(nrm);
    for (k = 0; k < 3; k++) m.normal[k] = nrm[k] / l;
    m.axis[0] = 1; m.axis[1] = 0; m.axis[2] = -m.normal[0] / m.normal[2];
    l = vp_norm3(m.axis);
    for (k = 0; k < 3; k++) m.axis[k] /= l;
    for (i = 0; i < 400; i++) {
        /* a point of the plane within the fan, projected by the camera, measured back */
        double a = (-29 + 58.0 * (i % 20) / 19) * PI / 180, d = 30 + 400.0 * (i / 20) / 19, b[3], q[3], uv[2], dist, dir[3], p[3];
        vp_cross3(b, m.normal, m.axis);
        for (k = 0; k < 3; k++) q[k] = m.origin[k] + d * (cos(a) * m.axis[k] + sin(a) * b[k]);
        if (!vp_camera_project(&m.cam, q, uv) || uv[0] < 0 || uv[0] > W - 1 || uv[1] < 0 || uv[1] > H - 1) continue;
        CHECK(vp_line_point3d(&m, uv, &dist, dir, p) == VP_OK);
        CHECK(fabs(dist - d) < 1e-6);
        if (hypot(hypot(p[0] - q[0], p[1] - q[1]), p[2] - q[2]) > worst) worst = hypot(hypot(p[0] - q[0], p[1] - q[1]), p[2] - q[2]);
        n++;
    }
    CHECKF(n > 150 && worst < 1e-6, "%d points, worst %.3g mm", n, worst);
    {
        /* refused: outside the span, outside the fan, a ray along the plane */
        double uv[2], dist = -1, dir[3], q[3], b[3];
        vp_cross3(b, m.normal, m.axis);
        for (k = 0; k < 3; k++) q[k] = m.origin[k] + 10 * m.axis[k];
        CHECK(vp_camera_project(&m.cam, q, uv) && vp_line_point3d(&m, uv, &dist, dir, NULL) == VP_ERANGE && dist == -1);
        for (k = 0; k < 3; k++) q[k] = m.origin[k] + 200 * (cos(0.6) * m.axis[k] + sin(0.6) * b[k]);
        CHECK(vp_camera_project(&m.cam, q, uv) && vp_line_point3d(&m, uv, &dist, dir, NULL) == VP_ERANGE);
        uv[0] = 319.5; uv[1] = 239.5 - 350 * tan(16.7 * PI / 180);   /* the camera's ray along z = 30: parallel */
        CHECK(vp_line_point3d(&m, uv, &dist, dir, NULL) == VP_ERANGE);
    }
    printf("geometry: %d points of the plane projected and measured back within %.2g mm\n", n, worst);
}

/* the plane as mounted: 1 degree off the nominal one, about the axis (1, 1, 0) */
static void true_normal(double nrm[3])
{
    const double a = 1 * PI / 180, k[3] = { 0.70710678118654752, 0.70710678118654752, 0 }, v[3] = { 0, 0, 1 };
    double kv[3], kd = vp_dot3(k, v);
    int i;
    vp_cross3(kv, k, v);
    for (i = 0; i < 3; i++) nrm[i] = v[i] * cos(a) + kv[i] * sin(a) + k[i] * kd * (1 - cos(a));
}

static vp_line_model_t fitted;

/* ---- calibration from the flat target, then the target and a sphere measured ---- */
static void accuracy(void)
{
    static vp_calib_obs_t obs[NDIST * W];
    vp_camsim_config_t c;
    vp_camsim_scene_t sc;
    vp_line_model_t nom;
    vp_line_fit_report_t rep;
    vp_line_stats_t st;
    vp_rng_t rng;
    double nrm[3];
    int i, j, n, nobs = 0, first = 0;
    true_normal(nrm);
    config(&c, nrm);
    nominal(&c.cam, &nom);
    vp_rng_seed(&rng, 11);
    for (i = 0; i < NDIST; i++) {
        vp_frame_t on = frame(img_on), off = frame(img_off);
        target(&sc, dists[i]);
        CHECK(pair(&c, &sc, &rng) == VP_OK);
        CHECK(vp_line_detect(&on, &off, NULL, NULL, &ws, pts, W, &n, &st) == VP_OK);
        for (j = 0; j < n; j++) {
            vp_calib_obs_t *o = &obs[nobs++];
            memset(o, 0, sizeof *o);
            o->kind = VP_OBS_SPOT;
            o->uv[0] = pts[j].u;
            o->uv[1] = pts[j].v;
            o->n[0] = 1;
            o->h = sc.plane_d;
        }
        if (i == 0) first = nobs;
    }
    {
        /* one target pose alone: the plane's turn about the line is free */
        vp_line_model_t keep;
        memset(&keep, 0x5a, sizeof keep);
        fitted = keep;
        CHECK(vp_line_fit_plane(&c.cam, obs, first, &nom, &fitted, &rep) == VP_EDEGEN);
        CHECK(!memcmp(&keep, &fitted, sizeof keep));
    }
    CHECK(vp_line_fit_plane(&c.cam, obs, nobs, &nom, &fitted, &rep) == VP_OK);
    {
        double dn = acos(fmin(1, vp_dot3(fitted.normal, nrm))) * 180 / PI, off = fitted.normal[0] * (fitted.origin[0] - 20) +
                                                                                 fitted.normal[1] * fitted.origin[1] + fitted.normal[2] * fitted.origin[2];
        CHECKF(dn < 0.02 && fabs(off) < 0.05, "fitted plane %.4f deg off, origin %.4f mm off the true plane", dn, off);
        printf("plane fit: %d columns from %d target poses, rms %.4f mm, worst %.4f mm to the plane; tilt %.3f deg from the "
               "nominal (true 1), %.4f deg from the true plane, true origin %.4f mm off it\n",
               rep.n, NDIST, rep.rms_mm, rep.max_mm, rep.tilt_deg, dn, off);
    }
    /* the target at the 5 distances again (new noise), measured by the fitted model */
    for (i = 0; i < NDIST; i++) {
        vp_frame_t on = frame(img_on), off = frame(img_off);
        score_t s;
        target(&sc, dists[i]);
        CHECK(pair(&c, &sc, &rng) == VP_OK);
        CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
        grade(&fitted, n, &s);
        CHECKF(s.false_pts == 0 && s.n > 0.9 * true_columns() && s.rms < (dists[i] < 300 ? 0.3 : 0.6) && s.worst < 2.5,
               "target %.1f mm: %d points of %d columns, %d false, rms %.3f worst %.3f", dists[i], s.n, true_columns(),
               s.false_pts, s.rms, s.worst);
        printf("flat target %5.1f mm: %3d points (%3d true columns), error rms %.3f mm, worst %.3f mm, noise %.2f, %d false\n",
               dists[i], s.n, true_columns(), s.rms, s.worst, st.noise, s.false_pts);
    }
    {
        vp_surface_t *sp = NULL;
        char err[200];
        vp_frame_t on = frame(img_on), off = frame(img_off);
        score_t s;
        CHECK(vp_surface_open("sphere*40@220,10,5", &sp, err, sizeof err) == VP_OK);
        memset(&sc, 0, sizeof sc);
        sc.surf = sp;
        CHECK(pair(&c, &sc, &rng) == VP_OK);
        CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
        grade(&fitted, n, &s);
        CHECKF(s.false_pts == 0 && s.n > 0.8 * true_columns() && s.rms < 0.2 && s.worst < 0.6,
               "sphere: %d points of %d columns, %d false, rms %.3f worst %.3f", s.n, true_columns(), s.false_pts, s.rms, s.worst);
        printf("sphere r 40 mm, 200 mm out: %3d points (%3d true columns), error rms %.3f mm, worst %.3f mm, %d false\n", s.n,
               true_columns(), s.rms, s.worst, s.false_pts);
        vp_surface_close(sp);
    }
}

/* the image of the plane's point at distance d along the fan's axis, moved across the line by dy px */
static void line_image(const vp_camsim_config_t *c, double d, double uv[2])
{
    double q[3] = { 20 + d, 0, 0 };
    vp_camera_project(&c->cam, q, uv);
}

/* ---- the faults of a real room: no false points; a dark band: misses ---- */
static void faults_at(double speckle, vp_surface_t *sp, const double nrm[3])
{
    vp_camsim_config_t c;
    vp_camsim_scene_t sc;
    vp_rng_t rng;
    vp_line_stats_t st;
    int i, k, n, total = 0, false_pts = 0, cols = 0, spikes = 0, several = 0, lit = 0;
    vp_rng_seed(&rng, 23);
    speckle_px = speckle * 0.6;
    printf("faults (ambient 60, gradient, texture, noise 2, %s, 40 hot pixels, a highlight 6 px and a moving glint 9 px "
           "from the line, a lamp's glare; tolerance 3 x %.2f px):\n", speckle > 0 ? "speckle 0.5 in grains of 4.2 px" : "no speckle",
           hypot(0.1, speckle_px));
    for (i = 0; i <= NDIST; i++) {
        double d = i < NDIST ? dists[i] : 180, s2 = 0, worst = 0, prms = 0, pworst = 0;
        int np = 0;
        for (k = 0; k < 3; k++) {
            /* the target at each distance and the sphere, three pairs each at other moments (the
             * glint swings between a pair's two frames) */
            vp_frame_t on = frame(img_on), off = frame(img_off);
            vp_camsim_truth_t tr;
            double uv[2], r, wv;
            int64_t t0 = (int64_t)k * 170000000;
            score_t s;
            config(&c, nrm);
            c.ambient = 60;
            c.gradient = 30;
            c.texture = 4;
            c.noise = 2;
            c.speckle = speckle;
            c.hot_pixels = 40;
            line_image(&c, d, uv);
            c.highlight_peak = 80;
            c.highlight_dist = d;
            c.highlight_off_px = 6;
            c.glint_peak = 60;
            c.glint_dist = d;
            c.glint_off_px = -9;
            c.glint_move_px = 12;
            c.glint_period_ms = 700;
            c.lamp_peak = 120;
            c.lamp_sigma = 25;
            c.lamp_uv[0] = uv[0] + 120;
            c.lamp_uv[1] = uv[1] - 10;
            if (i < NDIST) target(&sc, d);
            else { memset(&sc, 0, sizeof sc); sc.surf = sp; }
            CHECK(vp_camsim_render_ex(&c, &sc, ident, zero3, &rng, img_on, W, 1, t0, &tr, &truth) == VP_OK);
            CHECK(vp_camsim_render_ex(&c, &sc, ident, zero3, &rng, img_off, W, 0, t0 + 33333333, &tr, NULL) == VP_OK);
            CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
            grade(&fitted, n, &s);
            px_error(n, &r, &wv);
            total += n;
            false_pts += s.false_pts;
            cols += true_columns();
            spikes += st.why[VP_LINE_SPIKE];
            several += st.why[VP_LINE_SEVERAL];
            lit += st.off_lit;
            s2 += s.sum2;
            np += s.compared;
            if (s.worst > worst) worst = s.worst;
            prms += r * r / 3;
            if (wv > pworst) pworst = wv;
            CHECKF(s.false_pts == 0 && n > 0.6 * true_columns(), "faults, speckle %.1f, %s %.1f mm, pair %d: %d points of %d columns, %d false, worst %.3f",
                   speckle, i < NDIST ? "target" : "sphere", d, k, n, true_columns(), s.false_pts, s.worst);
        }
        if (i < NDIST) printf("  target %5.1f mm:", d);
        else printf("  sphere r 40 mm:");
        printf(" error rms %.3f mm, worst %.3f mm (centre %.3f px rms, %.3f px worst)\n", np ? sqrt(s2 / np) : 0, worst,
               sqrt(prms), pworst);
    }
    printf("  %d points of %d true columns in 18 pairs, %d false; refused: %d columns with a spike, %d with two peaks; "
           "%d columns with light in the laser-off frame (the glint)\n", total, cols, false_pts, spikes, several, lit);
}

static void faults(void)
{
    vp_camsim_config_t c;
    vp_camsim_scene_t sc;
    vp_rng_t rng;
    vp_line_stats_t st;
    vp_surface_t *sp = NULL;
    char err[200];
    double nrm[3];
    int i, n;
    true_normal(nrm);
    vp_rng_seed(&rng, 29);
    CHECK(vp_surface_open("sphere*40@220,10,5", &sp, err, sizeof err) == VP_OK);
    faults_at(0, sp, nrm);       /* every fault but speckle: the clean tolerance */
    faults_at(0.5, sp, nrm);
    speckle_px = 0;
    {
        /* a dark band (albedo 0.02) across the line on the target at 300 mm: misses there */
        vp_frame_t on = frame(img_on), off = frame(img_off);
        vp_camsim_truth_t tr;
        double zlo = HUGE_VAL, zhi = -HUGE_VAL;
        int x, dark = 0, in_dark = 0, edge = 0;
        score_t s;
        config(&c, nrm);
        c.ambient = 60;
        c.noise = 2;
        target(&sc, 300);
        CHECK(vp_camsim_render_ex(&c, &sc, ident, zero3, &rng, img_on, W, 0, 0, &tr, &truth) == VP_OK);
        for (x = 0; x < W; x++)
            if (truth.count[x] == 1) {
                if (truth.p[x][2] < zlo) zlo = truth.p[x][2];
                if (truth.p[x][2] > zhi) zhi = truth.p[x][2];
            }
        c.dark_albedo = 0.02;
        c.dark_z[0] = zlo + 0.35 * (zhi - zlo);
        c.dark_z[1] = zlo + 0.65 * (zhi - zlo);
        CHECK(pair(&c, &sc, &rng) == VP_OK);
        CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
        grade(&fitted, n, &s);
        for (x = 0; x < W; x++) dark += truth.count[x] == 1 && truth.albedo[x] < 1;
        for (i = 0; i < n; i++) {
            /* a point in a dark column: the blur's light from a lit one beside it, or a reading */
            const int x0 = pts[i].col;
            int lit = 0;
            for (x = x0 - 2; x <= x0 + 2; x++) lit |= x >= 0 && x < W && truth.count[x] == 1 && truth.albedo[x] == 1;
            in_dark += truth.albedo[x0] < 1 && !lit;
            edge += truth.albedo[x0] < 1 && lit;
        }
        CHECKF(dark > 50 && in_dark == 0 && s.false_pts == 0 && n > 0.5 * true_columns(),
               "dark band: %d dark columns, %d points in them, %d false, %d points", dark, in_dark, s.false_pts, n);
        printf("dark band (albedo 0.02) on the target at 300 mm: %d columns dark, %d points in them (%d more within 2 columns "
               "of its edges, lit by the blur from beside), %d points in all, %d false\n", dark, in_dark, edge, n, s.false_pts);
    }
    vp_surface_close(sp);
}

/* ---- cases the checks must catch ---- */
static void must_fail(void)
{
    vp_camsim_config_t c;
    vp_camsim_scene_t sc;
    vp_rng_t rng;
    vp_line_stats_t st;
    vp_frame_t on = frame(img_on), off = frame(img_off);
    double nrm[3];
    int n, y;
    score_t s;
    true_normal(nrm);
    config(&c, nrm);
    vp_rng_seed(&rng, 31);
    target(&sc, 225);
    /* the line moved by 5 px (the on frame shifted down): the checker flags the points */
    CHECK(pair(&c, &sc, &rng) == VP_OK);
    for (y = H - 1; y >= 5; y--) memcpy(img_on + (size_t)y * W, img_on + (size_t)(y - 5) * W, W);
    CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
    grade(&fitted, n, &s);
    CHECKF(n > 200 && s.false_pts > 0.95 * n, "line shifted 5 px: %d points, only %d flagged", n, s.false_pts);
    printf("checker: the line shifted by 5 px: %d of %d points flagged false", s.false_pts, n);
    {
        /* the on frame of another pose (the target 10 mm farther) against this pose's truth */
        vp_camsim_truth_t tr;
        vp_camsim_line_truth_t *keep = malloc(sizeof *keep);
        CHECK(keep != NULL);
        if (keep) {
            CHECK(pair(&c, &sc, &rng) == VP_OK);
            *keep = truth;
            target(&sc, 235);
            CHECK(vp_camsim_render_ex(&c, &sc, ident, zero3, &rng, img_on, W, 1, 0, &tr, &truth) == VP_OK);
            truth = *keep;
            CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
            grade(&fitted, n, &s);
            CHECKF(n > 200 && s.false_pts > 0.95 * n, "another pose's on frame: %d points, only %d flagged", n, s.false_pts);
            printf("; the on frame of a pose 10 mm farther: %d of %d flagged\n", s.false_pts, n);
            free(keep);
        }
    }
    {
        /* the laser-off frame replaced by a laser-on frame of another pose (the target 10 mm
         * farther): the pair is flagged (a line in the off frame), and the points, graded as
         * that pose's, are all false */
        vp_camsim_truth_t tr;
        vp_camsim_line_truth_t *keep = malloc(sizeof *keep);
        int clean_lit;
        CHECK(keep != NULL);
        if (keep) {
            target(&sc, 225);
            CHECK(pair(&c, &sc, &rng) == VP_OK);
            CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
            clean_lit = st.off_lit;
            target(&sc, 235);
            CHECK(vp_camsim_render_ex(&c, &sc, ident, zero3, &rng, img_off, W, 1, 0, &tr, keep) == VP_OK);
            CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
            truth = *keep;
            grade(&fitted, n, &s);
            CHECKF(clean_lit == 0 && st.off_lit > 300 && s.false_pts > 0.95 * n,
                   "off frame lit: %d columns flagged (clean pair %d), %d of %d points false", st.off_lit, clean_lit, s.false_pts, n);
            printf("the laser-off frame replaced by a laser-on frame of a pose 10 mm farther: %d columns show a line in it "
                   "(a clean pair: %d); graded as that pose, %d of %d points false\n", st.off_lit, clean_lit, s.false_pts, n);
            free(keep);
        }
    }
    /* a reflection: a second line as bright, 12 px below, in every column: nothing reported */
    c.ghost = 1;
    c.ghost_offset[0] = 0;
    c.ghost_offset[1] = 12;
    target(&sc, 225);
    CHECK(pair(&c, &sc, &rng) == VP_OK);
    CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, &st) == VP_OK);
    CHECKF(n == 0 && st.why[VP_LINE_SEVERAL] > 300, "two equal lines: %d points, %d columns refused as two", n,
           st.why[VP_LINE_SEVERAL]);
    printf("two equal lines 12 px apart (a reflection): %d points, %d columns refused as two candidates\n", n,
           st.why[VP_LINE_SEVERAL]);
}

/* ---- the contract: bad input is refused and changes nothing ---- */
static void contract(void)
{
    static vp_line_point_t keep[W];
    static vp_calib_obs_t obs[40];
    vp_frame_t on = frame(img_on), off = frame(img_off), bad;
    vp_line_config_t cfg;
    vp_line_model_t m = fitted, out, out0;
    vp_line_stats_t st, st0;
    vp_line_fit_report_t rep;
    double uv[2] = { NAN, 200 }, d = -3, dir[3] = { 7, 7, 7 };
    int n = -7, i;
    memset(pts, 0x33, sizeof pts);
    memcpy(keep, pts, sizeof keep);
    memset(&st, 0x44, sizeof st);
    st0 = st;
    CHECK(vp_line_detect(NULL, &off, NULL, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    bad = off; bad.width = W - 2;
    CHECK(vp_line_detect(&on, &bad, NULL, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    bad = off; bad.data = NULL;
    CHECK(vp_line_detect(&on, &bad, NULL, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    bad = off; bad.stride = W - 1;
    CHECK(vp_line_detect(&on, &bad, NULL, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    bad = on; bad.width = VP_LINE_MAX_W + 1; bad.stride = VP_LINE_MAX_W + 1;
    CHECK(vp_line_detect(&bad, &bad, NULL, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    CHECK(vp_line_detect(&on, &off, NULL, NULL, &ws, pts, W - 1, &n, &st) == VP_EINVAL);   /* too small for the columns */
    CHECK(vp_line_detect(&on, &off, NULL, NULL, NULL, pts, W, &n, &st) == VP_EINVAL);
    memset(&cfg, 0, sizeof cfg);
    cfg.min_snr = NAN;
    CHECK(vp_line_detect(&on, &off, &cfg, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    cfg.min_snr = 0;
    cfg.column_step = -1;
    CHECK(vp_line_detect(&on, &off, &cfg, NULL, &ws, pts, W, &n, &st) == VP_EINVAL);
    m.normal[1] = NAN;
    CHECK(vp_line_detect(&on, &off, NULL, &m, &ws, pts, W, &n, &st) == VP_EINVAL);
    CHECK(n == -7 && !memcmp(keep, pts, sizeof keep) && !memcmp(&st, &st0, sizeof st));
    /* the 3D point */
    CHECK(vp_line_point3d(&fitted, uv, &d, dir, NULL) == VP_EINVAL);
    uv[0] = 300;
    CHECK(vp_line_point3d(&m, uv, &d, dir, NULL) == VP_EINVAL);
    CHECK(vp_line_point3d(NULL, uv, &d, dir, NULL) == VP_EINVAL);
    CHECK(d == -3 && dir[0] == 7 && dir[1] == 7 && dir[2] == 7);
    /* the plane's fit */
    for (i = 0; i < 40; i++) {
        memset(&obs[i], 0, sizeof obs[i]);
        obs[i].kind = VP_OBS_SPOT;
        obs[i].uv[0] = 100 + 10 * i;
        obs[i].uv[1] = 200 + (i % 2) * 30;
        obs[i].n[0] = 1;
        obs[i].h = i % 2 ? 300 : 150;
    }
    memset(&out, 0x55, sizeof out);
    out0 = out;
    CHECK(vp_line_fit_plane(&fitted.cam, obs, VP_LINE_FIT_MIN - 1, &fitted, &out, &rep) == VP_EINVAL);
    CHECK(vp_line_fit_plane(NULL, obs, 40, &fitted, &out, &rep) == VP_EINVAL);
    CHECK(vp_line_fit_plane(&fitted.cam, obs, 40, NULL, &out, &rep) == VP_EINVAL);
    obs[7].uv[1] = NAN;
    CHECK(vp_line_fit_plane(&fitted.cam, obs, 40, &fitted, &out, &rep) == VP_EINVAL);
    obs[7].uv[1] = 200;
    obs[9].kind = VP_OBS_MARK;
    CHECK(vp_line_fit_plane(&fitted.cam, obs, 40, &fitted, &out, &rep) == VP_EINVAL);
    obs[9].kind = VP_OBS_SPOT;
    obs[3].n[0] = 2;
    CHECK(vp_line_fit_plane(&fitted.cam, obs, 40, &fitted, &out, &rep) == VP_EINVAL);
    obs[3].n[0] = 1;
    obs[5].h = -1000;        /* a target behind the camera: its ray cannot meet it */
    CHECK(vp_line_fit_plane(&fitted.cam, obs, 40, &fitted, &out, &rep) == VP_EDEGEN);
    CHECK(!memcmp(&out, &out0, sizeof out));
    printf("contract: NaN, NULL, bad sizes and capacities refused (VP_EINVAL), outputs unchanged\n");
}

/* ---- the detector's time per frame pair ---- */
static void timing(void)
{
    vp_camsim_config_t c;
    vp_camsim_scene_t sc;
    vp_rng_t rng;
    vp_frame_t on = frame(img_on), off = frame(img_off);
    struct timespec t0, t1;
    double nrm[3], ms;
    int i, n = 0, reps = 40;
    true_normal(nrm);
    config(&c, nrm);
    vp_rng_seed(&rng, 41);
    target(&sc, 225);
    CHECK(pair(&c, &sc, &rng) == VP_OK);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (i = 0; i < reps; i++) CHECK(vp_line_detect(&on, &off, NULL, &fitted, &ws, pts, W, &n, NULL) == VP_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    ms = ((t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) * 1e-6) / reps;
    printf("detector: %.2f ms per 640 x 480 pair on this machine (%d points with 3D)", ms, n);
    {
        /* every third column */
        vp_line_config_t cfg;
        score_t s;
        int n3 = 0;
        memset(&cfg, 0, sizeof cfg);
        cfg.column_step = 3;
        CHECK(vp_line_detect(&on, &off, &cfg, &fitted, &ws, pts, W / 3 + 1, &n3, NULL) == VP_OK);
        grade(&fitted, n3, &s);
        for (i = 0; i < n3; i++) CHECK(pts[i].col % 3 == 0);
        CHECKF(abs(3 * n3 - n) < 12 && s.false_pts == 0, "every third column: %d points (all: %d), %d false", n3, n, s.false_pts);
        printf("; every third column: %d points, %d false\n", n3, s.false_pts);
    }
}

int main(void)
{
    geometry();
    accuracy();
    faults();
    must_fail();
    contract();
    timing();
    return vp_test_done("test_line");
}
