/* How a dry run judges a hit read past the surface (vp_scan_depth_beyond): against a sphere,
 * where the deepest point of a ray's stretch inside it has a closed form (the point of the
 * stretch nearest the centre, its depth the radius less that distance):
 *  - 2000 random stretches through and beside spheres of several radii: every stretch deeper
 *    than the tolerance is called deep, none shallower than 7/8 of it is;
 *  - a ray that clips a sphere's edge (0.5 mm deep, tolerance 2) is not, one through the centre
 *    is; a stretch from the entry point 1 mm in is not, 3 mm in is, and so is one whose deepest
 *    point (2.1 mm) is its very end; with no tolerance everything is deep. */
#include <math.h>
#include <stdio.h>
#include "vp_rng.h"
#include "vp_scan.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

/* the deepest point of o + s d, s in [t0, t1], inside the ball (c, r): r less its distance to c */
static double ball_depth(const double c[3], double r, const double o[3], const double d[3], double t0, double t1)
{
    double oc[3], s, p[3], l = 0;
    int k;
    for (k = 0; k < 3; k++) oc[k] = c[k] - o[k];
    s = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    if (s < t0) s = t0;
    if (s > t1) s = t1;
    for (k = 0; k < 3; k++) {
        p[k] = o[k] + s * d[k] - c[k];
        l += p[k] * p[k];
    }
    return r - sqrt(l);
}

int main(void)
{
    static const double radii[3] = { 5, 20, 60 };
    char err[200], spec[64];
    unsigned long deep = 0, shallow = 0, between = 0;
    vp_rng_t rng;
    int ri, i;
    vp_rng_seed(&rng, 7);
    for (ri = 0; ri < 3; ri++) {
        vp_surface_t *s = NULL;
        double c[3] = { 0, 0, 0 }, r = radii[ri];
        snprintf(spec, sizeof spec, "sphere*%g", r);
        CHECKF(vp_surface_open(spec, &s, err, sizeof err) == VP_OK, "%s", err);
        if (!s) continue;
        for (i = 0; i < 700; i++) {
            /* a ray from 2r away towards a point within 1.1 r of the centre; a stretch of it */
            double o[3], q[3], d[3], l = 0, t0, t1, tol = 0.5 + 2.5 * vp_rng_uniform(&rng), depth;
            int k, got;
            for (k = 0; k < 3; k++) o[k] = 4 * r * (vp_rng_uniform(&rng) - 0.5);
            o[2] = 2 * r;
            for (k = 0; k < 3; k++) q[k] = 1.1 * r * (vp_rng_uniform(&rng) - 0.5) * 2 / sqrt(3.0);
            for (k = 0; k < 3; k++) {
                d[k] = q[k] - o[k];
                l += d[k] * d[k];
            }
            l = sqrt(l);
            for (k = 0; k < 3; k++) d[k] /= l;
            t0 = l * vp_rng_uniform(&rng);
            t1 = t0 + 2 * r * vp_rng_uniform(&rng);
            depth = ball_depth(c, r, o, d, t0, t1);
            got = vp_scan_depth_beyond(s, o, d, t0, t1, tol);
            if (depth > tol) {
                deep++;
                CHECKF(got == 1, "r %g: a stretch %.3f deep called shallow (tol %.3f)", r, depth, tol);
            } else if (depth < 0.875 * tol) {
                shallow++;
                CHECKF(got == 0, "r %g: a stretch %.3f deep called deeper than %.3f", r, depth, tol);
            } else between++;
        }
        if (ri == 1) {
            /* r 20: a ray 19.5 from the centre clips 0.5 mm deep; one through the centre */
            double o[3] = { 19.5, 0, 40 }, d[3] = { 0, 0, -1 }, o2[3] = { 0, 0, 40 };
            CHECK(vp_scan_depth_beyond(s, o, d, 0, 80, 2) == 0);
            CHECK(vp_scan_depth_beyond(s, o2, d, 0, 80, 2) == 1);
            CHECK(vp_scan_depth_beyond(s, o2, d, 20, 21, 2) == 0);   /* the entry, 1 mm in */
            CHECK(vp_scan_depth_beyond(s, o2, d, 20, 23, 2) == 1);   /* 3 mm in */
            /* the deepest point at the stretch's very end (2.1 mm), the stretch not a whole
             * number of steps long */
            CHECK(vp_scan_depth_beyond(s, o2, d, 19.2, 22.1, 2) == 1);
            CHECK(vp_scan_depth_beyond(s, o2, d, 20, 20, 2) == 0);   /* a point on the surface */
            CHECK(vp_scan_depth_beyond(s, o2, d, 20, 22, 0) == 1);   /* no tolerance: deep */
        }
        vp_surface_close(s);
    }
    CHECK(deep > 500 && shallow > 500);
    {
        /* a hit judged (vp_scan_judge_hit): a sphere of 20 at the origin and one of 5 whose
         * surface passes 0.5 beside the ray o + s (1, 0, 0), o = (-50, 0, 0), before the big
         * one's crossing at 30 */
        vp_surface_t *s = NULL;
        double o[3] = { -50, 0, 0 }, d[3] = { 1, 0, 0 }, side[3] = { -50, 20.5, 0 }, e = -1;
        CHECKF(vp_surface_open("sphere*20+sphere*5@-30,5.5,0", &s, err, sizeof err) == VP_OK, "%s", err);
        if (s) {
            CHECK(vp_scan_judge_hit(s, o, d, 100, 30.5, 2, &e) == VP_HIT_TRUE && fabs(e - 0.5) < 1e-9);
            CHECK(vp_scan_judge_hit(s, o, d, 100, 28.5, 2, &e) == VP_HIT_TRUE && fabs(e - 1.5) < 1e-9);
            /* 10 past, through the big sphere: space inside taken for free */
            CHECK(vp_scan_judge_hit(s, o, d, 100, 40, 2, &e) == VP_HIT_PAST && fabs(e - 10) < 1e-9);
            /* the crossing just beyond the range asked for: a measurement at its end */
            CHECK(vp_scan_judge_hit(s, o, d, 29, 30, 2, &e) == VP_HIT_TRUE);
            /* read 10 short, at the small sphere beside the ray (0.5 off it): the beam met it */
            CHECK(vp_scan_judge_hit(s, o, d, 100, 20, 2, &e) == VP_HIT_GRAZING);
            /* the same with hits trusted to 0.25, and a point in the air 10 before the crossing */
            CHECK(vp_scan_judge_hit(s, o, d, 100, 20, 0.25, &e) == VP_HIT_FALSE);
            CHECK(vp_scan_judge_hit(s, o, d, 100, 5, 2, &e) == VP_HIT_FALSE);
            /* a ray 0.5 beside the big sphere, no crossing: read beside it, or in the air */
            CHECK(vp_scan_judge_hit(s, side, d, 100, 50, 2, &e) == VP_HIT_GRAZING);
            CHECK(vp_scan_judge_hit(s, side, d, 100, 30, 2, &e) == VP_HIT_FALSE);
            vp_surface_close(s);
        }
    }
    printf("test_scanjudge: %lu stretches deeper than the tolerance all caught, %lu shallower than 7/8 of it none "
           "(%lu between); a clipped edge is not deep; hits judged true, past, grazing (short of the crossing too) and false\n", deep, shallow, between);
    return vp_test_done("test_scanjudge");
}
