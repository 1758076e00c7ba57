/* vp_motion and the simulated device's clock: a sphere translated and inflated against the
 * exact formula (inside, ray, distance, closest point, normal at several times), a rotation, a
 * bump against its closed form and against a fine scan of the inside test (the march skips
 * nothing), the speed bound against finite differences, bad specs refused, the clock's
 * trapezoid, and moves against a moving sphere: collisions exactly where the closest approach
 * of device and sphere says (the static check misses them), none when the object stands still. */
#include <math.h>
#include <string.h>
#include "vp_motion.h"
#include "vp_rng.h"
#include "vp_simdev.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"
#include "vp_vec3.h"

/* first crossing of o + t d (t in (0, tmax]) with the sphere (c, R): 1 and *t, 0 for none;
 * *grazing when the ray is within 1e-6 of tangent */
static int sphere_ray(const double c[3], double R, const double o[3], const double d[3], double tmax, double *t,
                      int *grazing)
{
    double w[3], b, q, disc, h, t0, t1;
    vp_sub3(w, o, c);
    b = vp_dot3(w, d);
    q = vp_dot3(w, w) - R * R;
    disc = b * b - q;
    *grazing = fabs(disc) < 1e-6;
    if (disc <= 0) return 0;
    h = sqrt(disc);
    t0 = -b - h;
    t1 = -b + h;
    if (t0 > 0 && t0 <= tmax) { *t = t0; return 1; }
    if (t1 > 0 && t1 <= tmax) { *t = t1; return 1; }
    return 0;
}

static void rand_dir(vp_rng_t *r, double d[3])
{
    do {
        int k;
        for (k = 0; k < 3; k++) d[k] = 2 * vp_rng_uniform(r) - 1;
    } while (vp_dot3(d, d) > 1 || vp_dot3(d, d) < 1e-3);
    vp_normalize3(d);
}

static void check_similarity(const vp_surface_t *sph)
{
    static const double times[] = { 0, 0.5, 1.7, 3 };
    const double vel[3] = { 0.3, -0.2, 0.1 }, grow = 0.2;
    double lo[3], hi[3], cb[3];
    vp_motion_t *m;
    char err[256];
    vp_rng_t r;
    int i, k, n, nrays = 0, nhits = 0;
    vp_surface_bbox(sph, lo, hi);
    for (k = 0; k < 3; k++) cb[k] = 0.5 * (lo[k] + hi[k]);
    CHECK(vp_motion_open("translate:0.3,-0.2,0.1+inflate:0.2", sph, &m, err, sizeof err) == VP_OK);
    CHECK(vp_motion_is_similarity(m));
    vp_rng_seed(&r, 11);
    for (i = 0; i < 4; i++) {
        double t = times[i], s = exp(grow * t), c[3], R = s;
        /* the sphere's centre (the origin) scaled about the bbox centre, then translated */
        for (k = 0; k < 3; k++) c[k] = cb[k] + s * (0 - cb[k]) + vel[k] * t;
        for (n = 0; n < 400; n++) {
            double p[3], q[3], dir[3], nrm[3], dc, d, th = -1, tm, tr = -1;
            int hit, ref, graze;
            for (k = 0; k < 3; k++) p[k] = c[k] + 3 * R * (2 * vp_rng_uniform(&r) - 1);
            dc = vp_dist3(p, c);
            if (fabs(dc - R) > 1e-9) CHECKF(vp_motion_inside(m, t, p) == (dc < R), "t %g |p-c| %g R %g", t, dc, R);
            d = vp_motion_closest(m, t, p, q);
            CHECKF(fabs(d - fabs(dc - R)) < 1e-9 * (1 + R), "t %g distance %.12g, exact %.12g", t, d, fabs(dc - R));
            CHECK(fabs(vp_dist3(q, c) - R) < 1e-9 * R);
            vp_motion_normal(m, t, q, nrm);
            for (k = 0; k < 3; k++) CHECK(fabs(nrm[k] - (q[k] - c[k]) / R) < 1e-9);
            /* aimed near the sphere, half of them long enough to reach it */
            rand_dir(&r, dir);
            for (k = 0; k < 3; k++) dir[k] = c[k] + 1.2 * R * dir[k] * vp_rng_uniform(&r) - p[k];
            if (!vp_normalize3(dir)) continue;
            tm = 6 * R * vp_rng_uniform(&r);
            ref = sphere_ray(c, R, p, dir, tm, &tr, &graze);
            if (graze) continue;
            hit = vp_motion_ray(m, t, p, dir, tm, &th);
            nrays++;
            nhits += ref;
            CHECKF(hit == ref, "t %g ray hit %d, exact %d", t, hit, ref);
            if (hit && ref) CHECKF(fabs(th - tr) < 1e-9 * (1 + R), "t %g ray t %.12g, exact %.12g", t, th, tr);
        }
    }
    CHECKF(nrays > 1000 && nhits > 200, "rays %d hits %d", nrays, nhits);
    /* a pure translation and inflation: the speed bound is |v| + rate * (largest radius) */
    {
        double sb = vp_motion_speed_bound(m, 0, 2), rmax = exp(grow * 2) * 0.5 * vp_dist3(lo, hi);
        CHECKF(fabs(sb - (vp_norm3(vel) + grow * rmax)) < 1e-12, "speed bound %.12g", sb);
    }
    vp_motion_close(m);

    /* the sphere of radius 0.5 at (1,0,0), a quarter turn per second about the z axis at the origin */
    {
        vp_surface_t *off;
        double p[3] = { 0, 1, 0 }, x[3] = { 1, 0, 0 }, y[3], o[3] = { 0, 3, 0 }, dn[3] = { 0, -1, 0 }, th;
        CHECK(vp_surface_open("sphere*0.5@1,0,0", &off, err, sizeof err) == VP_OK);
        CHECK(vp_motion_open("rotate:0,0,1,90@0,0,0", off, &m, err, sizeof err) == VP_OK);
        CHECK(vp_motion_inside(m, 1, p) && !vp_motion_inside(m, 1, x) && vp_motion_inside(m, 0, x));
        vp_motion_to_world(m, 2, x, y);
        CHECK(fabs(y[0] + 1) < 1e-12 && fabs(y[1]) < 1e-12);
        CHECK(vp_motion_ray(m, 1, o, dn, 10, &th) && fabs(th - 1.5) < 1e-9);
        /* speed bound: omega times the farthest point (centre 1 + radius 0.5, bbox half-diagonal) */
        CHECK(vp_motion_speed_bound(m, 0, 1) >= asin(1.0) * 1.5);
        vp_motion_close(m);
        vp_surface_close(off);
    }
}

/* a bump of radius 0.5 on the unit sphere at (1,0,0), 0.1 high per second: its points move along x */
static void check_bump(const vp_surface_t *sph)
{
    vp_motion_t *m;
    char err[256];
    double o[3] = { 3, 0, 0 }, dn[3] = { -1, 0, 0 }, th, p[3], q[3];
    int i, k, n, skipped = 0, rays = 0;
    vp_rng_t r;
    CHECK(vp_motion_open("bump:2,0,0,0.5,0.1", sph, &m, err, sizeof err) == VP_OK);
    CHECK(!vp_motion_is_similarity(m));
    for (i = 0; i <= 4; i++) {
        /* the height stops at 0.5 RADIUS / max|phi'| = 0.1456 (t = 1.456) */
        double t = 0.5 * i, h = 0.1 * t < 0.25 / (6 / sqrt(5.0) * 0.64) ? 0.1 * t : 0.25 / (6 / sqrt(5.0) * 0.64);
        /* on the axis: the bump's top at 1 + h */
        CHECKF(vp_motion_ray(m, t, o, dn, 10, &th) && fabs(th - (2 - h)) < 1e-8, "t %g ray %.12g", t, th);
        /* off the axis at height y: the body point (x0, y, 0) moves to x0 + h (1 - rho^2)^3 */
        for (k = 1; k <= 4; k++) {
            double yy = 0.1 * k, oo[3] = { 3, 0, 0 }, x0 = sqrt(1 - yy * yy), rho2 = ((x0 - 1) * (x0 - 1) + yy * yy) / 0.25;
            double X = x0 + (rho2 < 1 ? h * (1 - rho2) * (1 - rho2) * (1 - rho2) : 0);
            oo[1] = yy;
            CHECKF(vp_motion_ray(m, t, oo, dn, 10, &th) && fabs(th - (3 - X)) < 1e-8, "t %g y %g ray %.12g exact %.12g", t, yy, th, 3 - X);
        }
        p[0] = 2; p[1] = p[2] = 0;
        CHECKF(fabs(vp_motion_closest(m, t, p, q) - (1 - h)) < 1e-7, "t %g distance %.12g", t, vp_motion_distance(m, t, p));
    }
    /* segments past the bump's top (at 1.1 when t = 1): through it, and clear of it by 0.05 */
    {
        double a1[3] = { 1.05, -1, 0 }, b1[3] = { 1.05, 1, 0 }, a2[3] = { 1.15, -1, 0 }, b2[3] = { 1.15, 1, 0 };
        CHECK(!vp_surface_segment_collides(sph, a1, b1, 0) && vp_motion_segment_collides(m, 1, a1, b1, 0));
        CHECK(!vp_motion_segment_collides(m, 1, a2, b2, 0) && !vp_motion_segment_collides(m, 1, a2, b2, 0.02));
        CHECK(vp_motion_segment_collides(m, 1, a2, b2, 0.06) && !vp_motion_segment_collides(m, 0, a1, b1, 0.04));
    }
    /* the march against a fine scan of the inside test along random rays through the bump */
    vp_rng_seed(&r, 5);
    for (n = 0; n < 60; n++) {
        double oo[3], dir[3], aim[3], tb = -1, prev, step = 1e-3, tm = 4;
        int s0, hit;
        for (k = 0; k < 3; k++) oo[k] = 1 + 1.5 * (2 * vp_rng_uniform(&r) - 1);
        for (k = 0; k < 3; k++) aim[k] = (k == 0 ? 1.05 : 0) + 0.4 * (2 * vp_rng_uniform(&r) - 1);
        vp_sub3(dir, aim, oo);
        if (!vp_normalize3(dir)) continue;
        s0 = vp_motion_inside(m, 1, oo);
        for (prev = 0; prev < tm; prev += step) {
            double x[3];
            for (k = 0; k < 3; k++) x[k] = oo[k] + (prev + step) * dir[k];
            if (vp_motion_inside(m, 1, x) != s0) { tb = prev + step; break; }
        }
        hit = vp_motion_ray(m, 1, oo, dir, tm, &th);
        if (tb < 0) { if (hit) skipped++; continue; } /* a crossing thinner than the scan's step */
        rays++;
        CHECKF(hit && th <= tb + 1e-9 && th >= tb - step - 1e-9, "march %d %.9g, scan %.9g", hit, hit ? th : -1, tb);
    }
    CHECK(rays > 30 && skipped <= 2);
    /* the speed bound holds for surface points (finite differences over [0, 2]) */
    {
        double pts[300 * 3], sb = vp_motion_speed_bound(m, 0, 2), worst = 0;
        size_t got = vp_surface_sample(sph, 300, 3, pts), j;
        for (j = 0; j < got; j++) {
            double ya[3], yb[3];
            vp_motion_to_world(m, 1.0, pts + 3 * j, ya);
            vp_motion_to_world(m, 1.01, pts + 3 * j, yb);
            if (vp_dist3(ya, yb) / 0.01 > worst) worst = vp_dist3(ya, yb) / 0.01;
        }
        CHECKF(worst <= sb && worst > 0.05, "speed %g bound %g", worst, sb);
        /* to_body undoes to_world */
        for (j = 0; j < got; j++) {
            double y[3], x[3];
            vp_motion_to_world(m, 2, pts + 3 * j, y);
            vp_motion_to_body(m, 2, y, x);
            CHECK(vp_dist3(x, pts + 3 * j) < 1e-12);
        }
    }
    vp_motion_close(m);
}

/* every motion at once: surface points never outrun the speed bound, and to_body undoes to_world */
static void check_combined(const vp_surface_t *sph)
{
    vp_motion_t *m;
    char err[256];
    double pts[400 * 3], sb, worst = 0;
    size_t got = vp_surface_sample(sph, 400, 9, pts), j;
    int i;
    CHECK(vp_motion_open("bend:1,0,0,0,1,0,0.05+bump:0,0,1,0.6,0.1+inflate:0.05+rotate:1,2,3,20@0.5,0,0+translate:0.1,0,0.2",
                         sph, &m, err, sizeof err) == VP_OK);
    sb = vp_motion_speed_bound(m, 0, 2);
    for (i = 0; i < 20; i++) {
        double t = 0.1 * i;
        for (j = 0; j < got; j++) {
            double ya[3], yb[3], x[3];
            vp_motion_to_world(m, t, pts + 3 * j, ya);
            vp_motion_to_world(m, t + 1e-4, pts + 3 * j, yb);
            if (vp_dist3(ya, yb) / 1e-4 > worst) worst = vp_dist3(ya, yb) / 1e-4;
            vp_motion_to_body(m, t, ya, x);
            CHECK(vp_dist3(x, pts + 3 * j) < 1e-9);
            /* a body surface point carried to time t is on the object then */
            CHECK(vp_motion_distance(m, t, ya) < 1e-9);
        }
    }
    CHECKF(worst <= sb && worst > 0.3 * sb, "fastest surface point %g, bound %g", worst, sb);
    vp_motion_close(m);
}

static void check_specs(const vp_surface_t *sph)
{
    static const char *bad[] = { "", "wiggle:1", "translate:1,2", "translate:1,2,3+", "translate:1,2,3x",
                                 "rotate:0,0,0,5", "bump:0,0,1,0,1", "translate:1,0,0+translate:1,0,0",
                                 "bend:1,0,0,2,0,0,1", "inflate:nan", "rotate:0,0,1,5@1,2" };
    char err[256];
    vp_motion_t *m = NULL;
    size_t i;
    for (i = 0; i < sizeof bad / sizeof *bad; i++) {
        err[0] = 0;
        CHECKF(vp_motion_check_spec(bad[i], err, sizeof err) == VP_EINVAL && err[0], "'%s' accepted", bad[i]);
        CHECK(vp_motion_open(bad[i], sph, &m, err, sizeof err) == VP_EINVAL);
    }
    CHECK(vp_motion_check_spec("translate:1e+2,0,-1e-3+rotate:1,1,0,30@0,0,1+inflate:-0.1+bend:1,0,0,0,0,1,0.1+bump:0,0,1,0.3,0.05",
                               err, sizeof err) == VP_OK);
}

/* the device moves along y at x = xd from y = -3 to 3 at speed 1 while the unit sphere moves along x
 * at speed 1: the closest approach of the two centres is |xd - 3| / sqrt(2) at tau = (xd + 3) / 2 */
static void check_device(const vp_surface_t *sph)
{
    vp_motion_t *m, *still;
    vp_simdev_config_t cfg;
    vp_simdev_t *d;
    vp_simdev_move_t mr;
    vp_simdev_probe_t pr;
    vp_simdev_stats_t st;
    char err[256];
    double xd, a[3], b[3], mx[3] = { -1, 0, 0 };
    int agree = 0, moving_only = 0;
    CHECK(vp_motion_open("translate:1,0,0", sph, &m, err, sizeof err) == VP_OK);
    CHECK(vp_motion_open("translate:0,0,0", sph, &still, err, sizeof err) == VP_OK);
    memset(&cfg, 0, sizeof cfg);
    cfg.motion = m;
    cfg.speed = 1;
    for (xd = 1.2; xd < 5; xd += 0.05) {
        int exact = fabs(xd - 3) / sqrt(2.0) < 1, stat;
        if (fabs(fabs(xd - 3) / sqrt(2.0) - 1) < 0.01) continue; /* within the tolerance of the boundary */
        a[0] = b[0] = xd; a[1] = -3; b[1] = 3; a[2] = b[2] = 0;
        CHECK(vp_simdev_create(sph, &cfg, a, &d) == VP_OK);
        CHECK(vp_simdev_move(d, b, &mr) == VP_OK);
        CHECKF(mr.collided == exact, "xd %g: collided %d, exact %d", xd, mr.collided, exact);
        agree += mr.collided == exact;
        stat = vp_surface_segment_collides(sph, a, b, 0);
        moving_only += exact && !stat;
        vp_simdev_stats(d, &st);
        CHECK(st.time == 6 && st.collisions == (unsigned long)exact);
        vp_simdev_destroy(d);
    }
    /* the static check (the device without a clock) misses these collisions */
    CHECKF(agree == 77 && moving_only == 57, "agree %d, missed by the static check %d", agree, moving_only);
    /* the same moves with the object standing still: only where the static check says */
    cfg.motion = still;
    for (xd = 0.5; xd < 5; xd += 0.25) {
        a[0] = b[0] = xd; a[1] = -3; b[1] = 3; a[2] = b[2] = 0;
        CHECK(vp_simdev_create(sph, &cfg, a, &d) == VP_OK);
        CHECK(vp_simdev_move(d, b, &mr) == VP_OK && mr.collided == vp_surface_segment_collides(sph, a, b, 0));
        CHECK(mr.collided == (xd <= 1)); /* touching at xd = 1 counts */
        vp_simdev_destroy(d);
    }
    /* a motion of another object is refused */
    {
        vp_surface_t *other;
        CHECK(vp_surface_open("sphere", &other, err, sizeof err) == VP_OK);
        a[0] = 5; a[1] = a[2] = 0;
        CHECK(vp_simdev_create(other, &cfg, a, &d) == VP_EINVAL);
        vp_surface_close(other);
    }
    /* the clock: trapezoid moves (speed 2, accel 4: 1 s to speed over 1 unit) and probe times;
     * the probe sees the sphere where it is when the exposure ends */
    cfg.motion = m;
    cfg.speed = 2;
    cfg.accel = 4;
    cfg.probe_time = 0.25;
    a[0] = 10; a[1] = 5; a[2] = 0;
    CHECK(vp_simdev_create(sph, &cfg, a, &d) == VP_OK);
    b[0] = 10; b[1] = 5 - 0.5; b[2] = 0;   /* short: a triangle, 2 sqrt(0.5 / 4) */
    CHECK(vp_simdev_move(d, b, &mr) == VP_OK && !mr.collided);
    vp_simdev_stats(d, &st);
    CHECK(fabs(st.time - 2 * sqrt(0.5 / 4)) < 1e-12);
    b[1] = 0;                             /* 4.5 units: 4.5 / 2 + 2 / 4 */
    CHECK(vp_simdev_move(d, b, &mr) == VP_OK && !mr.collided);
    vp_simdev_stats(d, &st);
    CHECK(fabs(st.time - (2 * sqrt(0.5 / 4) + 4.5 / 2 + 0.5)) < 1e-12);
    CHECK(vp_simdev_probe(d, mx, 20, &pr) == VP_OK && pr.hit);
    vp_simdev_stats(d, &st);
    CHECKF(fabs(pr.t - (10 - st.time - 1)) < 1e-9, "probe %.12g, sphere at %.12g", pr.t, st.time);
    vp_simdev_destroy(d);
    vp_motion_close(m);
    vp_motion_close(still);
}

/* A body shrunk far (inflate, with a bump of height 0 so the march is taken): in its frame the
 * ray starts 1e6 radii away, where adjacent doubles lie farther apart than the march's tolerance.
 * The bisection spun forever there; now the ray ends, hitting the sphere of radius exp(-t) where
 * the formula says (to the doubles' resolution at 5), and a segment through it collides. */
static void check_shrunk(const vp_surface_t *sph)
{
    vp_motion_t *m = NULL;
    char err[256];
    double o[3] = { 0, 0, 5 }, d[3] = { 0, 0, -1 }, b[3] = { 0, 0, -5 }, c[3] = { 3, 0, 5 }, e[3] = { 3, 0, -5 }, t;
    int i;
    CHECK(vp_motion_open("inflate:-1+bump:1,0,0,0.5,0", sph, &m, err, sizeof err) == VP_OK);
    if (!m) return;
    for (i = 12; i <= 17; i++) {
        double th = -1, r = exp(-(double)i);
        int hit = vp_motion_ray(m, (double)i, o, d, 100, &th);
        CHECKF(hit && fabs(th - (5 - r)) < 1e-9, "t %d: hit %d at %.17g, the sphere at %.17g", i, hit, th, 5 - r);
        CHECKF(vp_motion_segment_collides(m, (double)i, o, b, 0) == 1, "t %d: the segment through the centre", i);
        CHECKF(vp_motion_segment_collides(m, (double)i, c, e, 0) == 0, "t %d: a segment 3 away", i);
    }
    t = 20;
    CHECK(vp_motion_ray(m, t, c, d, 100, &t) == 0);
    vp_motion_close(m);
}

int main(void)
{
    vp_surface_t *sph;
    char err[256];
    CHECK(vp_surface_open("sphere", &sph, err, sizeof err) == VP_OK);
    check_similarity(sph);
    check_bump(sph);
    check_combined(sph);
    check_shrunk(sph);
    check_specs(sph);
    check_device(sph);
    vp_surface_close(sph);
    return vp_test_done("motion (moving sphere vs exact formula, bump, march, speed bound, clock, moving collisions)");
}
