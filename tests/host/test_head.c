/* The head's body swept along joint motions (vp_head):
 *  - a mount's switch (vp_head_near) at random poses near a sphere: closed only where the brute
 *    force puts a sensed part within the distance, open with a gap no larger than the true one;
 *    the clearance ball left out of the mask; every point of every part moves no farther than
 *    vp_head_moved between two random poses;
 *  - a MOVE whose laser origin passes 23.6 mm clear of a sphere while the camera box goes
 *    through it is caught, naming the camera (and the bracket's end at it); the old check (the origin's segment, radius 0, and
 *    radius 12) misses it;
 *  - a pan turn that swings the camera through a sphere is caught; a check of the two end
 *    poses alone misses it;
 *  - random motions of the rpi4-like head near a sphere against a brute force written here:
 *    the motion sampled densely (no body point moves more than 0.05 mm between samples), the
 *    exact distance from the sphere to each part at every sample, the pose from R = Rz(pan)
 *    Ry(-tilt) written out again. Every motion the brute force finds touching is caught, and
 *    every motion caught comes within the tolerance; the old origin-only check misses some;
 *  - the reach of a tilt-frame part is its farthest corner, of a pan-frame part the largest over
 *    tilt by dense sampling; bad parts are refused and change nothing. */
#include <math.h>
#include <string.h>
#include "vp_head.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

#define DEG (3.14159265358979323846 / 180.0)
#define TOL 0.5

static const double tilt_offset[3] = { 0, 0, 45 }, laser_offset[3] = { 20, 0, 0 };

static double surf_distance(void *ctx, const double p[3]) { return vp_surface_distance(ctx, p); }
static int surf_inside(void *ctx, const double p[3]) { return vp_surface_inside(ctx, p); }

/* the rpi4 head: 0 ball, 1 laser, 2 camera, 3 bracket (tilt frame), 4 tilt hub (pan frame) */
static void rpi4_head(vp_head_t *h, double ball)
{
    static const double cam_c[3] = { 0, 30, 10 }, cam_h[3] = { 10, 12.5, 12.5 };
    static const double la[3] = { -6, 0, 0 }, lb[3] = { 14, 0, 0 };
    static const double ba[3] = { 0, 0, 0 }, bb[3] = { 0, 30, 10 };
    static const double ha[3] = { 0, -30, 45 }, hb[3] = { 0, -14, 45 };
    CHECK(vp_head_init(h, tilt_offset, laser_offset) == VP_OK);
    CHECK(vp_head_add(h, "clearance ball", VP_HEAD_TILT, VP_HEAD_CAPSULE, laser_offset, laser_offset, ball) == VP_OK);
    CHECK(vp_head_add(h, "laser", VP_HEAD_TILT, VP_HEAD_CAPSULE, la, lb, 6) == VP_OK);
    CHECK(vp_head_add(h, "camera", VP_HEAD_TILT, VP_HEAD_BOX, cam_c, cam_h, 0) == VP_OK);
    CHECK(vp_head_add(h, "bracket", VP_HEAD_TILT, VP_HEAD_CAPSULE, ba, bb, 4) == VP_OK);
    CHECK(vp_head_add(h, "tilt hub", VP_HEAD_PAN, VP_HEAD_CAPSULE, ha, hb, 14) == VP_OK);
}

static vp_surface_t *sphere(double r, const double c[3])
{
    char spec[128], err[200];
    vp_surface_t *s = NULL;
    snprintf(spec, sizeof spec, "sphere*%.17g@%.17g,%.17g,%.17g", r, c[0], c[1], c[2]);
    CHECK(vp_surface_open(spec, &s, err, sizeof err) == VP_OK);
    return s;
}

/* ---- the brute force: its own pose and exact sphere-to-part distances ---- */

static void bf_point(const double j[5], int frame, const double p[3], double w[3])
{
    double cp = cos(j[3] * DEG), sp = sin(j[3] * DEG), ct = cos(j[4] * DEG), st = sin(j[4] * DEG), q[3];
    if (frame == VP_HEAD_TILT) {
        /* Ry(-tilt) p (tilt > 0 raises +x), then the tilt axis above the pan pivot */
        q[0] = ct * p[0] - st * p[2] + tilt_offset[0];
        q[1] = p[1] + tilt_offset[1];
        q[2] = st * p[0] + ct * p[2] + tilt_offset[2];
    } else memcpy(q, p, sizeof q);
    w[0] = j[0] + cp * q[0] - sp * q[1];
    w[1] = j[1] + sp * q[0] + cp * q[1];
    w[2] = j[2] + q[2];
}

/* signed distance from the sphere (centre c, radius R) to the part in pose j */
static double bf_gap(const vp_head_part_t *p, const double j[5], const double c[3], double R)
{
    double d;
    int k;
    if (p->kind == VP_HEAD_CAPSULE) {
        double a[3], b[3], ab[3], t = 0, dd = 0, q;
        bf_point(j, p->frame, p->a, a);
        bf_point(j, p->frame, p->b, b);
        for (k = 0; k < 3; k++) { ab[k] = b[k] - a[k]; dd += ab[k] * ab[k]; t += (c[k] - a[k]) * ab[k]; }
        t = dd > 0 ? t / dd : 0;
        if (t < 0) t = 0;
        if (t > 1) t = 1;
        for (d = 0, k = 0; k < 3; k++) { q = a[k] + t * ab[k] - c[k]; d += q * q; }
        return sqrt(d) - p->r - R;
    }
    {
        /* the sphere's centre in the box's frame: world = pose(local); local axes from three
         * posed points */
        double o[3], ax[3][3], l[3], e, s = 0;
        int q;
        bf_point(j, p->frame, p->a, o);
        for (q = 0; q < 3; q++) {
            double u[3];
            memcpy(u, p->a, sizeof u);
            u[q] += 1;
            bf_point(j, p->frame, u, ax[q]);
            for (k = 0; k < 3; k++) ax[q][k] -= o[k];
        }
        for (q = 0; q < 3; q++) {
            for (l[q] = 0, k = 0; k < 3; k++) l[q] += (c[k] - o[k]) * ax[q][k];
            e = fabs(l[q]) - p->b[q];
            if (e > 0) s += e * e;
        }
        if (s > 0) return sqrt(s) - R;
        /* the centre inside the box */
        return -R;
    }
}

/* smallest gap per part along ja -> jb sampled in n steps */
static void bf_sweep(const vp_head_t *h, const double ja[5], const double jb[5], const double c[3], double R, long n,
                     double gap[VP_HEAD_MAX_PARTS])
{
    long s;
    int i, k;
    for (i = 0; i < h->nparts; i++) gap[i] = HUGE_VAL;
    for (s = 0; s <= n; s++) {
        double j[5];
        for (k = 0; k < 5; k++) j[k] = ja[k] + (jb[k] - ja[k]) * (double)s / (double)n;
        for (i = 0; i < h->nparts; i++) {
            double g = bf_gap(&h->part[i], j, c, R);
            if (g < gap[i]) gap[i] = g;
        }
    }
}

/* the laser origin in pose j */
static void origin(const double j[5], double o[3]) { bf_point(j, VP_HEAD_TILT, laser_offset, o); }

int main(void)
{
    vp_head_t h;
    vp_head_object_t obj;
    int hit[VP_HEAD_MAX_PARTS], i;
    unsigned long evals = 0;
    rpi4_head(&h, 2);
    obj.distance = surf_distance;
    obj.inside = surf_inside;

    /* 1. a MOVE: the camera box through a sphere, the laser origin 23.6 mm clear of it */
    {
        double c[3] = { 50, 30, 55 }, ja[5] = { 0, 0, 0, 0, 0 }, jb[5] = { 100, 0, 0, 0, 0 }, oa[3], ob[3];
        vp_surface_t *s = sphere(8, c);
        obj.ctx = s;
        origin(ja, oa);
        origin(jb, ob);
        CHECK(!vp_surface_segment_collides(s, oa, ob, 0));    /* the old check: the origin's segment */
        CHECK(!vp_surface_segment_collides(s, oa, ob, 12));   /* ... with the old clearance */
        CHECK(vp_head_sweep(&h, &obj, ja, jb, TOL, hit, &evals) == 2);
        /* the camera and the bracket's end at it; not the clearance ball, the laser, the hub */
        CHECK(hit[2] == 1 && hit[3] == 1 && hit[0] == 0 && hit[1] == 0 && hit[4] == 0);
        /* the same move 30 mm lower passes under the sphere: clear */
        ja[2] = jb[2] = -40;
        CHECK(vp_head_sweep(&h, &obj, ja, jb, TOL, hit, &evals) == 0);
        vp_surface_close(s);
        printf("move: camera box through a sphere of 8 mm caught, the laser origin 23.6 mm clear (old check: missed)\n");
    }
    /* 2. a pan turn 0 -> 90 swings the camera through a sphere at pan 45; both end poses clear */
    {
        double c[3] = { -30 * sin(45 * DEG), 30 * cos(45 * DEG), 55 }, ja[5] = { 0, 0, 0, 0, 0 }, jb[5] = { 0, 0, 0, 90, 0 };
        vp_surface_t *s = sphere(6, c);
        obj.ctx = s;
        CHECK(vp_head_sweep(&h, &obj, ja, ja, TOL, hit, &evals) == 0);   /* the end poses alone */
        CHECK(vp_head_sweep(&h, &obj, jb, jb, TOL, hit, &evals) == 0);
        CHECK(vp_head_sweep(&h, &obj, ja, jb, TOL, hit, &evals) >= 1 && hit[2] == 1 && hit[0] == 0);
        vp_surface_close(s);
        printf("pan turn: camera swung through a sphere of 6 mm caught; the end poses alone: clear\n");
    }
    /* 3. random motions near a sphere against the brute force */
    {
        vp_rng_t r;
        int n = 200, m, both = 0, clear = 0, band = 0, missed = 0, false_hit = 0, old_missed = 0, bf_hits = 0, wrong_missed = 0;
        vp_head_t wrong = h;
        /* a wrong input the comparison must fail: the tilt hub declared in the tilt frame */
        wrong.part[4].frame = VP_HEAD_TILT;
        double worst_caught = -HUGE_VAL;
        vp_rng_seed(&r, 20261202);
        for (m = 0; m < n; m++) {
            double c[3], R = 5 + 15 * vp_rng_uniform(&r), ja[5], jb[5], gap[VP_HEAD_MAX_PARTS], speed, oa[3], ob[3];
            vp_surface_t *s;
            long steps;
            int k, nh, any_bf = 0;
            for (k = 0; k < 3; k++) { ja[k] = 60 * (vp_rng_uniform(&r) - 0.5); jb[k] = ja[k] + 60 * (vp_rng_uniform(&r) - 0.5); }
            ja[3] = 360 * (vp_rng_uniform(&r) - 0.5);
            jb[3] = ja[3] + 120 * (vp_rng_uniform(&r) - 0.5);
            ja[4] = 180 * (vp_rng_uniform(&r) - 0.5);
            jb[4] = ja[4] + 90 * (vp_rng_uniform(&r) - 0.5);
            /* the sphere near the head's path: about a random point of it */
            {
                double mid[5], w[3], u = vp_rng_uniform(&r), p[3] = { 30 * vp_rng_uniform(&r) - 10, 60 * vp_rng_uniform(&r) - 30,
                                                                    20 * vp_rng_uniform(&r) - 10 };
                for (k = 0; k < 5; k++) mid[k] = ja[k] + u * (jb[k] - ja[k]);
                bf_point(mid, VP_HEAD_TILT, p, w);
                for (k = 0; k < 3; k++) c[k] = w[k] + (R + 25) * (vp_rng_uniform(&r) - 0.5) * 2;
            }
            s = sphere(R, c);
            obj.ctx = s;
            {
                int hw[VP_HEAD_MAX_PARTS];
                vp_head_sweep(&wrong, &obj, ja, jb, TOL, hw, NULL);
                nh = vp_head_sweep(&h, &obj, ja, jb, TOL, hit, &evals);
                CHECK(nh >= 0);
                bf_sweep(&h, ja, jb, c, R, 2000, gap);
                if (gap[4] <= 0 && !hw[4]) wrong_missed++;
            }
            /* the brute force: no body point moves more than 0.05 mm between samples */
            speed = 0;
            for (k = 0; k < 3; k++) speed += (jb[k] - ja[k]) * (jb[k] - ja[k]);
            speed = sqrt(speed) + (fabs(jb[3] - ja[3]) + fabs(jb[4] - ja[4])) * DEG * 150;
            steps = (long)ceil(speed / 0.05) + 1;
            bf_sweep(&h, ja, jb, c, R, steps, gap);
            for (i = 0; i < h.nparts; i++) {
                if (gap[i] <= 0) any_bf = 1;
                if (gap[i] <= 0 && !hit[i]) missed++;                  /* must never happen */
                if (hit[i] && gap[i] > TOL + 0.05) false_hit++;         /* caught, yet never within TOL */
                if (hit[i] && gap[i] > worst_caught) worst_caught = gap[i];
                if (hit[i] && gap[i] <= 0) both++;
                else if (!hit[i] && gap[i] > TOL) clear++;
                else band++;
            }
            bf_hits += any_bf;
            origin(ja, oa);
            origin(jb, ob);
            if (any_bf && !vp_surface_segment_collides(s, oa, ob, 0)) old_missed++;
            vp_surface_close(s);
        }
        CHECKF(missed == 0, "%d parts touching by the brute force were not caught", missed);
        CHECKF(false_hit == 0, "%d parts caught stayed farther than %g mm", false_hit, TOL);
        CHECK(bf_hits > 30 && bf_hits < n - 30);   /* both kinds of motion were drawn */
        CHECK(old_missed > 0);                     /* the origin-only check is not enough */
        CHECK(wrong_missed > 0);                   /* the comparison sees a wrong body */
        printf("random motions: %d, %d touching by the brute force; parts: %d touching caught, %d clear passed, %d within "
               "the %g mm band; 0 missed, 0 caught beyond it (farthest caught %.3f mm); the old origin check missed %d of "
               "the touching motions, the hub put in the tilt frame missed %d; %lu distance queries\n", n, bf_hits, both, clear,
               band, TOL, worst_caught, old_missed, wrong_missed, evals);
    }
    /* 4. reach from the laser origin: tilt part = farthest corner; pan part = over tilt */
    {
        double cam = sqrt(30.0 * 30 + 42.5 * 42.5 + 22.5 * 22.5), bf = 0, t;
        CHECK(fabs(vp_head_reach(&h, 2, -90, 90) - cam) < 1e-9);
        CHECK(fabs(vp_head_reach(&h, 1, -90, 90) - 32) < 1e-9);
        for (t = -90; t <= 90; t += 0.001) {
            double o[3] = { 20 * cos(t * DEG), 0, 45 + 20 * sin(t * DEG) }, e[2][3] = { { 0, -30, 45 }, { 0, -14, 45 } };
            int q, k;
            for (q = 0; q < 2; q++) {
                double d = 0;
                for (k = 0; k < 3; k++) d += (e[q][k] - o[k]) * (e[q][k] - o[k]);
                if (sqrt(d) + 14 > bf) bf = sqrt(d) + 14;
            }
        }
        t = vp_head_reach(&h, 4, -90, 90);
        CHECKF(t >= bf - 1e-9 && t < bf + 0.1, "hub reach %.6f, brute force %.6f", t, bf);
        printf("reach: camera %.2f mm (its far corner), tilt hub %.3f mm (brute force over tilt %.3f)\n", cam, t, bf);
    }
    /* 5. bad parts are refused and change nothing */
    {
        double a[3] = { 0, 0, 0 }, b[3] = { 1, -1, 1 }, nan3[3] = { NAN, 0, 0 };
        int n0 = h.nparts;
        CHECK(vp_head_add(&h, "x", VP_HEAD_TILT, VP_HEAD_BOX, a, b, 0) == VP_EINVAL);
        CHECK(vp_head_add(&h, "x", VP_HEAD_TILT, VP_HEAD_CAPSULE, nan3, a, 1) == VP_EINVAL);
        CHECK(vp_head_add(&h, "x", VP_HEAD_TILT, VP_HEAD_CAPSULE, a, a, -1) == VP_EINVAL);
        CHECK(vp_head_add(&h, "x", 7, VP_HEAD_CAPSULE, a, a, 1) == VP_EINVAL);
        CHECK(h.nparts == n0);
        {
            double j5[5] = { 0, 0, 0, 0, 0 };
            CHECK(vp_head_sweep(&h, &obj, j5, j5, 0, hit, NULL) == VP_EINVAL);
        }
    }
    /* 6. a mount's switch (vp_head_near) and the parts' travel (vp_head_moved) against the
     * brute force: random poses near a sphere, the clearance ball left out of the mask */
    {
        vp_rng_t r;
        const double need = 0.25;
        const unsigned mask = 0x1eu;           /* laser, camera, bracket, tilt hub */
        int m, closed = 0, open = 0, k, pi;
        double worst_lb = 0, moved_ratio = 0;
        vp_rng_seed(&r, 20261205);
        for (m = 0; m < 400; m++) {
            double c[3], R = 3 + 15 * vp_rng_uniform(&r), j[5], jb[5], g = -1, bf = HUGE_VAL;
            vp_surface_t *s;
            int in;
            for (k = 0; k < 3; k++) j[k] = 60 * (vp_rng_uniform(&r) - 0.5);
            j[3] = 360 * (vp_rng_uniform(&r) - 0.5);
            j[4] = 180 * (vp_rng_uniform(&r) - 0.5);
            {
                /* the sphere's surface near a random point of the head: from 1 mm inside to 7 mm out */
                double p[3] = { 30 * vp_rng_uniform(&r) - 10, 60 * vp_rng_uniform(&r) - 30, 20 * vp_rng_uniform(&r) - 10 }, w[3], u[3], l = 0;
                bf_point(j, VP_HEAD_TILT, p, w);
                for (k = 0; k < 3; k++) { u[k] = vp_rng_uniform(&r) - 0.5; l += u[k] * u[k]; }
                l = sqrt(l);
                for (k = 0; k < 3; k++) c[k] = w[k] + (R + 8 * vp_rng_uniform(&r) - 1) * u[k] / l;
            }
            s = sphere(R, c);
            obj.ctx = s;
            for (pi = 1; pi < h.nparts; pi++) { double q = bf_gap(&h.part[pi], j, c, R); if (q < bf) bf = q; }
            in = vp_head_near(&h, &obj, mask, j, need, &g, NULL);
            CHECK(in == 0 || in == 1);
            if (in) {
                closed++;
                CHECKF(bf < need + 1e-9, "closed with the parts %.6f mm from the sphere (need %g)", bf, need);
            } else {
                open++;
                CHECKF(g <= bf + 1e-9 && g >= 0.75 * need - 1e-12, "open: gap %.6f, brute force %.6f", g, bf);
                if (g / bf > worst_lb) worst_lb = g / bf;
            }
            /* every point of every part moves no farther than vp_head_moved says, whatever the way */
            for (k = 0; k < 5; k++) jb[k] = j[k] + (k < 3 ? 20 : 40) * (vp_rng_uniform(&r) - 0.5);
            for (pi = 0; pi < h.nparts; pi++) {
                const vp_head_part_t *pt = &h.part[pi];
                double bound = vp_head_moved(&h, pi, j, jb), far = 0;
                int q;
                for (q = 0; q < 64; q++) {
                    double loc[3], wa[3], wb[3], d = 0, t = vp_rng_uniform(&r);
                    for (k = 0; k < 3; k++)
                        loc[k] = pt->kind == VP_HEAD_CAPSULE ? pt->a[k] + t * (pt->b[k] - pt->a[k]) + pt->r * (2 * vp_rng_uniform(&r) - 1) / sqrt(3.0)
                                                             : pt->a[k] + pt->b[k] * (2 * vp_rng_uniform(&r) - 1);
                    bf_point(j, pt->frame, loc, wa);
                    bf_point(jb, pt->frame, loc, wb);
                    for (k = 0; k < 3; k++) d += (wb[k] - wa[k]) * (wb[k] - wa[k]);
                    if (sqrt(d) > far) far = sqrt(d);
                }
                CHECKF(far <= bound + 1e-9, "part %d moved %.6f mm, bound %.6f", pi, far, bound);
                if (far / bound > moved_ratio) moved_ratio = far / bound;
            }
            vp_surface_close(s);
        }
        CHECKF(closed > 50 && open > 50, "closed %d, open %d: too few of a kind", closed, open);
        /* the checker: with the ball in the mask, a pose where only the ball meets the sphere closes */
        {
            double c[3], j5[5] = { 0, 0, 0, 0, 0 }, g;
            vp_surface_t *s;
            origin(j5, c);
            c[0] += 2.5;                  /* a 1 mm sphere 1.5 mm ahead of the laser's exit, in the 2 mm ball */
            s = sphere(1, c);
            obj.ctx = s;
            CHECK(vp_head_near(&h, &obj, mask, j5, need, &g, NULL) == 0);
            CHECK(vp_head_near(&h, &obj, mask | 1u, j5, need, &g, NULL) == 1);
            vp_surface_close(s);
        }
        printf("mount switch: %d poses closed, %d open, every one as the brute force says (the clearance ball left out: "
               "a sphere in it alone leaves the switch open); gap bound up to %.2f of the true gap; parts moved up to %.2f "
               "of vp_head_moved\n", closed, open, worst_lb, moved_ratio);
    }
    return vp_test_done("test_head");
}
