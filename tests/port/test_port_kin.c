/* vp_kin: forward/inverse round trips with laser and tilt-axis offsets, pan wrap and the
 * turned-round branch, travel limits, MOVE keeps the laser origin on the segment, aim paths keep
 * it within origin_tol. */
#include <math.h>
#include <string.h>
#include "vp_kin.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_test.h"

static double dist3(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* distance from p to segment [a,b] */
static double seg_dist(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], l2 = 0, s = 0, q[3];
    int i;
    for (i = 0; i < 3; i++) { ab[i] = b[i] - a[i]; ap[i] = p[i] - a[i]; l2 += ab[i] * ab[i]; s += ab[i] * ap[i]; }
    s = l2 > 0 ? s / l2 : 0;
    if (s < 0) s = 0;
    if (s > 1) s = 1;
    for (i = 0; i < 3; i++) q[i] = a[i] + s * ab[i];
    return dist3(p, q);
}

static void lerp5(const double a[5], const double b[5], double s, double out[5])
{
    int i;
    for (i = 0; i < 5; i++) out[i] = a[i] + s * (b[i] - a[i]);
}

int main(void)
{
    vp_kin_t k;
    vp_kin_config_t c;
    vp_rng_t r;
    double cur[5] = { 100, 100, 100, 0, 0 }, j[5], o[3], d[3], q[3], p[3], maxerr = 0, maxdev = 0;
    double way[256][5];
    int i, n, w, s, pieces = 0;

    memset(&c, 0, sizeof c);
    c.tilt_offset[2] = 40;                       /* tilt axis 40 mm above the pan bearing */
    c.laser_offset[0] = 25; c.laser_offset[1] = -12; c.laser_offset[2] = 8;
    c.origin_tol = 0.01;
    CHECK(vp_kin_init(&k, &c) == VP_OK);

    /* zero pose: beam along +x from G + tilt_offset + laser_offset */
    vp_kin_forward(&k, (double[5]){ 0, 0, 0, 0, 0 }, o, d);
    CHECK(fabs(o[0] - 25) < 1e-12 && fabs(o[1] + 12) < 1e-12 && fabs(o[2] - 48) < 1e-12);
    CHECK(fabs(d[0] - 1) < 1e-15 && fabs(d[1]) < 1e-15 && fabs(d[2]) < 1e-15);
    /* pan 90: beam along +y; tilt 90: beam up */
    vp_kin_forward(&k, (double[5]){ 0, 0, 0, 90, 0 }, o, d);
    CHECK(fabs(d[1] - 1) < 1e-12 && fabs(o[0] - 12) < 1e-12 && fabs(o[1] - 25) < 1e-12);
    vp_kin_forward(&k, (double[5]){ 0, 0, 0, 0, 90 }, o, d);
    CHECK(fabs(d[2] - 1) < 1e-12 && fabs(o[0] + 8) < 1e-12 && fabs(o[2] - 65) < 1e-12);
    vp_kin_point(&k, (double[5]){ 0, 0, 0, 0, 0 }, 100, p);
    CHECK(fabs(p[0] - 125) < 1e-12 && fabs(p[2] - 48) < 1e-12);

    /* round trips, unlimited travel */
    vp_rng_seed(&r, 7);
    for (i = 0; i < 20000; i++) {
        double org[3] = { 500 * vp_rng_uniform(&r), 500 * vp_rng_uniform(&r), 500 * vp_rng_uniform(&r) };
        vp_rng_unit3(&r, d);
        cur[3] = 720 * vp_rng_uniform(&r) - 360;
        cur[4] = 180 * vp_rng_uniform(&r) - 90;
        CHECK(vp_kin_aim(&k, cur, org, d, j) == VP_OK);
        vp_kin_forward(&k, j, o, q);
        if (dist3(o, org) > maxerr) maxerr = dist3(o, org);
        if (dist3(q, d) * 500 > maxerr) maxerr = dist3(q, d) * 500;
        CHECKF(fabs(j[3] - cur[3]) <= 180 + 1e-9 && fabs(j[4] - cur[4]) <= 270 + 1e-9, "pan %g from %g", j[3], cur[3]);
    }
    CHECKF(maxerr < 1e-9, "aim round trip error %g mm", maxerr);

    /* pan wraps to the nearest turn; with pan travel [-180,180] it cannot */
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 350, 0 }, (double[3]){ 0, 0, 0 },
                     (double[3]){ cos(10 * 3.14159265358979323846 / 180), sin(10 * 3.14159265358979323846 / 180), 0 }, j) == VP_OK);
    CHECKF(fabs(j[3] - 370) < 1e-9 && fabs(j[4]) < 1e-9, "pan %g tilt %g", j[3], j[4]);
    c.lo[3] = -180; c.hi[3] = 180; c.lo[4] = -90; c.hi[4] = 90;
    CHECK(vp_kin_init(&k, &c) == VP_OK);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 170, 0 }, (double[3]){ 0, 0, 0 },
                     (double[3]){ cos(10 * 3.14159265358979323846 / 180), sin(10 * 3.14159265358979323846 / 180), 0 }, j) == VP_OK);
    CHECKF(fabs(j[3] - 10) < 1e-9, "pan %g", j[3]);
    /* tilt travel lets the head look back over the top: the cheaper branch wins */
    c.lo[4] = -30; c.hi[4] = 150; c.lo[3] = 0; c.hi[3] = 90;
    CHECK(vp_kin_init(&k, &c) == VP_OK);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 0, 0 }, (double[3]){ 0, 0, 0 }, (double[3]){ -sqrt(0.75), 0, 0.5 }, j) == VP_OK);
    CHECKF(fabs(j[3]) < 1e-9 && fabs(j[4] - 150) < 1e-9, "pan %g tilt %g", j[3], j[4]);
    vp_kin_forward(&k, j, o, q);
    CHECKF(fabs(q[0] + sqrt(0.75)) < 1e-12 && fabs(q[2] - 0.5) < 1e-12, "dir %g %g %g", q[0], q[1], q[2]);
    /* no solution: backwards and down with tilt limited to [-30,150] and pan to [0,90] */
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 0, 0 }, (double[3]){ 0, 0, 0 }, (double[3]){ 0, -0.6, -0.8 }, j) == VP_ERANGE);
    /* straight down keeps the pan */
    c.lo[4] = -90; c.hi[4] = 90;
    CHECK(vp_kin_init(&k, &c) == VP_OK);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 33, 10 }, (double[3]){ 1, 2, 3 }, (double[3]){ 0, 0, -1 }, j) == VP_OK);
    CHECKF(fabs(j[3] - 33) < 1e-9 && fabs(j[4] + 90) < 1e-9, "pan %g tilt %g", j[3], j[4]);
    /* XYZ travel */
    c.lo[0] = c.lo[1] = c.lo[2] = 0; c.hi[0] = c.hi[1] = c.hi[2] = 300;
    CHECK(vp_kin_init(&k, &c) == VP_OK);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 0, 0 }, (double[3]){ 10, 10, 10 }, (double[3]){ 1, 0, 0 }, j) == VP_ERANGE);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 0, 0 }, (double[3]){ 100, 100, 100 }, (double[3]){ 1, 0, 0 }, j) == VP_OK);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 0, 0 }, (double[3]){ 100, 100, 100 }, (double[3]){ 1, 1, 0 }, j) == VP_EINVAL);
    CHECK(vp_kin_aim(&k, (double[5]){ 0, 0, 0, 0, 0 }, (double[3]){ NAN, 100, 100 }, (double[3]){ 1, 0, 0 }, j) == VP_EINVAL);
    c.lo[0] = 5; c.hi[0] = 4;
    CHECK(vp_kin_init(&k, &c) == VP_EINVAL);
    c.lo[0] = 0; c.hi[0] = 300;
    CHECK(vp_kin_init(&k, &c) == VP_OK);

    /* MOVE: pan/tilt kept, linear joints keep the origin on the segment */
    maxdev = 0;
    for (i = 0; i < 2000; i++) {
        double a[3] = { 80 + 140 * vp_rng_uniform(&r), 80 + 140 * vp_rng_uniform(&r), 80 + 140 * vp_rng_uniform(&r) };
        double b[3] = { 80 + 140 * vp_rng_uniform(&r), 80 + 140 * vp_rng_uniform(&r), 80 + 140 * vp_rng_uniform(&r) };
        double ja[5], jb[5], js[5];
        vp_rng_unit3(&r, d);
        if (vp_kin_aim(&k, (double[5]){ 150, 150, 150, 0, 0 }, a, d, ja) != VP_OK) continue;
        CHECK(vp_kin_move(&k, ja, b, jb) == VP_OK);
        CHECK(jb[3] == ja[3] && jb[4] == ja[4]);
        for (s = 0; s <= 50; s++) {
            lerp5(ja, jb, s / 50.0, js);
            vp_kin_forward(&k, js, o, q);
            if (seg_dist(o, a, b) > maxdev) maxdev = seg_dist(o, a, b);
        }
        vp_kin_forward(&k, jb, o, q);
        CHECK(dist3(o, b) < 1e-9);
    }
    CHECKF(maxdev < 1e-9, "move leaves the segment by %g mm", maxdev);
    CHECK(vp_kin_move(&k, (double[5]){ 150, 150, 150, 0, 0 }, (double[3]){ 400, 0, 0 }, j) == VP_ERANGE);

    /* aim paths: the origin stays within origin_tol of its start-end line */
    maxdev = 0;
    for (i = 0; i < 2000; i++) {
        double org[3] = { 80 + 140 * vp_rng_uniform(&r), 80 + 140 * vp_rng_uniform(&r), 80 + 140 * vp_rng_uniform(&r) };
        double ja[5], jb[5], js[5], prev[5], oa[3], ob[3];
        vp_rng_unit3(&r, d);
        if (vp_kin_aim(&k, (double[5]){ 150, 150, 150, 0, 0 }, org, d, ja) != VP_OK) continue;
        vp_rng_unit3(&r, d);
        if (vp_kin_aim(&k, ja, org, d, jb) != VP_OK) continue;
        n = vp_kin_aim_path(&k, ja, jb, way, 256);
        CHECK(n >= 1);
        if (n < 1) continue;
        pieces += n;
        CHECK(memcmp(way[n - 1], jb, sizeof jb) == 0);
        vp_kin_forward(&k, ja, oa, q);
        vp_kin_forward(&k, jb, ob, q);
        memcpy(prev, ja, sizeof prev);
        for (w = 0; w < n; w++) {
            for (s = 0; s <= 20; s++) {
                lerp5(prev, way[w], s / 20.0, js);
                vp_kin_forward(&k, js, o, q);
                if (seg_dist(o, oa, ob) > maxdev) maxdev = seg_dist(o, oa, ob);
            }
            memcpy(prev, way[w], sizeof prev);
        }
    }
    CHECKF(maxdev <= 0.01, "aim path leaves the origin by %g mm", maxdev);
    printf("aim paths: %d pieces for 2000 aims, origin kept within %.4f mm (tol 0.01)\n", pieces, maxdev);
    printf("kinematics round trip error %.2g mm, move deviation < 1e-9 mm\n", maxerr);
    return vp_test_done("test_port_kin");
}
