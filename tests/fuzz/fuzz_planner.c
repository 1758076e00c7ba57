/* libFuzzer target: the planner driven by a rangefinder that errs as a real one can. The object
 * is a sphere, or two; built with FUZZ_OBJECT_BOXES (fuzz_planner_box.c), a box or two instead
 * (flat faces, edges and corners: coplanar samples, far Voronoi vertices, cuts at acute folds),
 * axis-aligned or turned; the input's first bytes choose the configuration (Omega a box or a ball, a
 * body, moves weighed by machine time, tubes, eps, noise tolerance, confirmed misses, a short
 * range, a distance bound, an angle bound, a line laser's more rays, the sight rule of a camera's
 * misses, a re-scan of the sphere moved after the first scan: from the start or where the device
 * stands, every sample or a sparse share), the rest decide, probe by probe and ray by ray,
 * whether the answer is the true one or a fault: a dropout (a miss), a too-close, a distance off
 * by up to 5 noise tolerances, a false hit anywhere on the ray, a hit past the range, an answer
 * that is not one (NaN, negative: it must be refused and change nothing), or a contact part way
 * along the last move. Whatever the device says, every call returns a status, every command is
 * well formed (a MOVE starts where the device stands, a PROBE has a unit direction and a finite
 * range within the rangefinder's), the planner never finds one of its own moves unproven
 * (VP_EUNSAFE), and the same input gives the same commands bit for bit; and until an answer
 * claims more free space than there is (a dropout on S, a hit read too far: a lie a move may
 * then act on), no MOVE enters the true object. Never a crash, never a sanitizer report. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_status.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#ifndef FUZZ_OBJECT_BOXES
#define FUZZ_OBJECT_BOXES 0
#endif
#define CONFIG_BYTES 4
#define MAX_COMMANDS 6000
#define LINE_RAYS 3u
#define ARENA_BYTES ((size_t)24 << 20)

typedef struct fuzz_dev {
    const uint8_t *p;
    size_t n, i;
    double centre[2][3], radius;  /* one sphere, or two apart (two components) */
    int spheres;
    double half[3], rot[3][3];    /* boxes: half sizes (corners just inside the sphere) and axes (rows) */
    double min_range, noise, tol; /* tol: the noise tolerance the planner trusts hits to */
    int lied;                     /* an answer claimed more free space than there is */
} fuzz_dev_t;

static unsigned next_byte(fuzz_dev_t *s)
{
    return s->i < s->n ? s->p[s->i++] : 0u; /* past the input: the truth */
}

static void fail(void) { __builtin_trap(); }

/* boxes: the part [*lo, *hi] of o + t d (t in [*lo, *hi] on entry) inside the box about
 * centre s shrunk by `in`; 0 when none */
static int box_clip(const fuzz_dev_t *D, int s, const double *o, const double *d, double in, double *lo, double *hi)
{
    int a, k;
    for (a = 0; a < 3; a++) {
        double ol = 0.0, dl = 0.0, h = D->half[a] - in, t1, t2;
        for (k = 0; k < 3; k++) {
            ol += D->rot[a][k] * (o[k] - D->centre[s][k]);
            dl += D->rot[a][k] * d[k];
        }
        if (dl == 0.0) {
            if (!(fabs(ol) < h)) return 0;
            continue;
        }
        t1 = (-h - ol) / dl;
        t2 = (h - ol) / dl;
        if (t1 > t2) { double x = t1; t1 = t2; t2 = x; }
        if (t1 > *lo) *lo = t1;
        if (t2 < *hi) *hi = t2;
        if (!(*lo < *hi)) return 0;
    }
    return 1;
}

/* the first point of the spheres (boxes) along the ray, or -1 */
static double object_ray(const fuzz_dev_t *D, const double *o, const double *d)
{
    double best = -1.0;
    int s;
    for (s = 0; FUZZ_OBJECT_BOXES && s < D->spheres; s++) {
        double lo = -HUGE_VAL, hi = HUGE_VAL;
        if (!box_clip(D, s, o, d, 0.0, &lo, &hi) || hi < 0.0) continue;
        if (lo <= 0.0) return 0.0; /* from inside: at once */
        if (best < 0.0 || lo < best) best = lo;
    }
    for (s = 0; !FUZZ_OBJECT_BOXES && s < D->spheres; s++) {
        double w[3], b, q, disc, t;
        int k;
        for (k = 0; k < 3; k++) w[k] = o[k] - D->centre[s][k];
        b = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
        q = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - D->radius * D->radius;
        if (q <= 0.0) return 0.0; /* from inside: at once */
        disc = b * b - q;
        if (disc < 0.0) continue;
        t = -b - sqrt(disc);
        if (t >= 0.0 && (best < 0.0 || t < best)) best = t;
    }
    return best;
}

/* What the rangefinder says along the ray into *r, the next byte choosing the truth or a fault
 * (for a non-answer: checks that it is refused, then *r is the truth). */
static void answer(vp_planner_t *pl, fuzz_dev_t *D, const double *o, const double *d, double range,
                   int ray, vp_probe_result_t *r)
{
    unsigned x = next_byte(D);
    double t = object_ray(D, o, d);
    if (t >= 0.0 && t < D->min_range) r->hit = VP_PROBE_TOO_CLOSE, r->dist = 0.0;
    else if (t >= 0.0 && t <= range) r->hit = 1, r->dist = t;
    else r->hit = 0, r->dist = 0.0;
    if (x >= 200u && x < 216u) r->hit = 0, r->dist = 0.0;                      /* dropout */
    else if (x >= 216u && x < 224u) r->hit = VP_PROBE_TOO_CLOSE, r->dist = 0.0; /* unreadable */
    else if (x >= 224u && x < 236u && r->hit == 1) {
        r->dist += D->noise * ((double)x - 230.0);
        if (r->dist < 0.0) r->dist = 0.0;
    } else if (x >= 236u && x < 246u) {
        r->hit = 1;                                                           /* false hit */
        r->dist = range * (double)next_byte(D) / 255.0;
    } else if (x >= 246u && x < 250u) {
        r->hit = 1;                                                           /* past the range */
        r->dist = range * (1.0 + (double)next_byte(D) / 64.0);
    } else if (x == 250u) {
        /* not an answer: refused, nothing changed; then the true one */
        vp_probe_result_t bad;
        double dd[3];
        bad.hit = (next_byte(D) & 1u) ? 1 : 3;
        bad.dist = bad.hit == 1 ? -1.0 : 0.5;
        if ((ray ? vp_planner_feed_ray(pl, d, &bad) : vp_planner_feed(pl, &bad)) != VP_EINVAL) fail();
        bad.hit = 1;
        bad.dist = NAN;
        if ((ray ? vp_planner_feed_ray(pl, d, &bad) : vp_planner_feed(pl, &bad)) != VP_EINVAL) fail();
        if (ray) {
            /* a ray's direction not of unit length: refused too */
            dd[0] = 2.0 * d[0]; dd[1] = 2.0 * d[1]; dd[2] = 2.0 * d[2];
            if (vp_planner_feed_ray(pl, dd, r) != VP_EINVAL) fail();
        }
    }
    if (!ray) {
        /* the most free space the answer can prove (a hit: up to its distance less the noise
         * tolerance, or the whole range past it; a miss: the range; a too-close: nothing)
         * against the space that is free: beyond it, the device lied (a dropout on S, a hit
         * read too far) and a move may go through the object on its word */
        double claim = r->hit == 1 ? (r->dist > range + D->tol ? range : r->dist - D->tol) : r->hit == 0 ? range : 0.0;
        if (t >= 0.0 && claim > t + 1e-12 * (1.0 + range)) D->lied = 1;
    }
}

/* 1 when segment [a, b] enters one of the spheres (boxes) deeper than rounding */
static int through_object(const fuzz_dev_t *D, const double *a, const double *b)
{
    int s, k;
    for (s = 0; FUZZ_OBJECT_BOXES && s < D->spheres; s++) {
        double ab[3], lo = 0.0, hi = 1.0;
        for (k = 0; k < 3; k++) ab[k] = b[k] - a[k];
        if (box_clip(D, s, a, ab, 1e-9 * (1.0 + D->radius), &lo, &hi)) return 1;
    }
    for (s = 0; !FUZZ_OBJECT_BOXES && s < D->spheres; s++) {
        double ab[3], ac[3], l2 = 0.0, u = 0.0, d2 = 0.0, r = D->radius - 1e-9 * (1.0 + D->radius);
        for (k = 0; k < 3; k++) {
            ab[k] = b[k] - a[k];
            ac[k] = D->centre[s][k] - a[k];
            l2 += ab[k] * ab[k];
            u += ab[k] * ac[k];
        }
        u = l2 > 0.0 ? u / l2 : 0.0;
        if (u < 0.0) u = 0.0;
        if (u > 1.0) u = 1.0;
        for (k = 0; k < 3; k++) d2 += (ac[k] - u * ab[k]) * (ac[k] - u * ab[k]);
        if (d2 < r * r) return 1;
    }
    return 0;
}

static int touch_ok(int st)
{
    return st == VP_OK || st == VP_EINVAL || st == VP_ERANGE || st == VP_ESTATE || st == VP_ENOMEM;
}

/* one run; the commands folded into *hash */
static void run(const uint8_t *data, size_t size, void *arena, vp_planner_t *pl, uint64_t *hash)
{
    vp_planner_config_t c;
    fuzz_dev_t D;
    double pos[3], move[3];
    uint64_t h = 1469598103934665603ull;
    vp_cmd_t cmd;
    int k, n, st, touched = 0, rescans = 0, sight;
    unsigned b0 = data[0], b1 = data[1], b2 = data[2], b3 = data[3];
    memset(&c, 0, sizeof c);
    memset(&D, 0, sizeof D);
    D.p = data + CONFIG_BYTES;
    D.n = size - CONFIG_BYTES;
    D.radius = 0.55 + 0.4 * (b2 & 15u) / 15.0;
    D.centre[0][0] = 0.05 * (double)((int)(b1 & 7u) - 3);
    D.centre[0][1] = 0.05 * (double)((int)((b1 >> 3) & 7u) - 3);
    D.centre[0][2] = FUZZ_OBJECT_BOXES ? 0.0 : 0.03 * (double)((int)((b1 >> 6) & 1u) - 1);
    sight = (b1 & 128u) != 0;
    {
        /* boxes: corners just inside the sphere of D.radius (set below); b1's bit 6 turns them about
         * (1, 2, 3)/sqrt(14) by 0.5 rad, else their faces face the axes */
        static const double turned[3][3] = {
            { 0.88632666461248877, -0.36690738911144422, 0.28249603787013322 },
            { 0.40188379999990925, 0.91255897277883746, -0.075667248519194735 },
            { -0.23003142153743572, 0.18059648118458971, 0.95627948638941873 } };
        int a;
        for (a = 0; a < 3; a++)
            for (k = 0; k < 3; k++) D.rot[a][k] = (b1 & 64u) ? turned[a][k] : (double)(a == k);
    }
    D.spheres = 1;
    if (b3 & 128u) {
        /* two parts: smaller spheres 1.9 apart, an interior point in each */
        D.spheres = 2;
        D.radius *= 0.7;
        memcpy(D.centre[1], D.centre[0], sizeof D.centre[1]);
        D.centre[0][0] -= 0.95;
        D.centre[1][0] += 0.95;
    }
    D.half[0] = 0.7 * D.radius;
    D.half[1] = 0.55 * D.radius;
    D.half[2] = 0.45 * D.radius;
    /* the re-scan's sphere: moved by up to 0.1 (b2's high bits), Omega still holding it */
    move[0] = 0.025 * (double)((b2 >> 4) & 3u);
    move[1] = 0.0;
    move[2] = -0.025 * (double)(b2 >> 6);
    if (b0 & 1u) {
        c.omega_kind = VP_OMEGA_BALL;
        c.omega_radius = 2.0;
    } else {
        c.omega_kind = VP_OMEGA_BOX;
        for (k = 0; k < 3; k++) { c.omega_lo[k] = -2.0; c.omega_hi[k] = 2.0; }
    }
    for (k = 0; k < 3; k++) {
        c.start[k] = 2.5;
        c.interior[0][k] = D.centre[0][k];
        c.interior[1][k] = D.centre[1][k];
    }
    c.ninterior = (uint32_t)D.spheres;
    {
        static const double eps[4] = { 0.5, 0.35, 0.7, 0.28 };
        c.eps = eps[(b0 >> 1) & 3u];
    }
    c.noise_tol = (b0 & 8u) ? 0.01 : 0.0;
    D.noise = c.noise_tol > 0.0 ? c.noise_tol : 0.002;
    D.tol = c.noise_tol;
    c.confirm_misses = (b0 >> 4) & 1u;
    c.clearance = (b0 & 32u) ? 0.2 : 0.0; /* a body: Omega keeps 0.2 from the sphere (r < 1.1) */
    c.max_range = (b0 & 64u) ? 1.6 : 0.0;
    if (b0 & 128u) c.max_distance = 0.06;
    if (b3 & 1u) c.min_angle = 20.0;
    if ((b3 & 2u) && c.clearance > 0.0) {
        /* tubes: the object must be rho-open up to eta (core/planner/tube.c), or a tube's proof
         * proves nothing. Every sphere holds balls of radius 0.3; a box holds balls no larger
         * than its smallest half size, and its corners lie (sqrt 3 - 1) rho from them */
        c.min_feature = 0.3;
        if (FUZZ_OBJECT_BOXES) {
            if (c.min_feature > 0.9 * D.half[2]) c.min_feature = 0.9 * D.half[2];
            c.feature_margin = 0.75 * c.min_feature;
        }
    }
    if ((b3 & 4u) && c.clearance > 0.0) c.flags |= VP_PLAN_FAR_READS; /* spots read past the edge */
    D.min_range = (b3 & 8u) ? 0.05 : 0.0;
    if ((b3 & 16u) && c.clearance > 0.0) {
        /* moves weighed by machine time: Z six times slower than X and Y, the pan's travel two turns */
        c.axis_time[0] = c.axis_time[1] = 1.0 / 300.0;
        c.axis_time[2] = 1.0 / 50.0;
        c.axis_time[3] = c.axis_time[4] = 1.0 / 3.0;
        c.pan_travel[0] = -6.283185307179586;
        c.pan_travel[1] = 6.283185307179586;
    }
    if (b3 & 32u) c.line_rays = LINE_RAYS;
    st = vp_planner_init(pl, arena, ARENA_BYTES, &c);
    if (st != VP_OK) { *hash = (uint64_t)(int64_t)st; return; }
    memcpy(pos, c.start, sizeof pos);
    for (n = 0; n < MAX_COMMANDS; n++) {
        st = vp_planner_next(pl, &cmd);
        if (st == VP_EUNSAFE) fail(); /* its own move unproven: never, whatever the device said */
        if (st != VP_OK) {
            if (st >= 0 || st < VP_ESTALL) fail(); /* a status from the list */
            if (vp_planner_next(pl, &cmd) != st) fail(); /* and it stays */
            break;
        }
        h = (h ^ (uint64_t)cmd.kind) * 1099511628211ull;
        for (k = 0; k < 3; k++) {
            double v[3];
            uint64_t u;
            v[0] = cmd.from[k]; v[1] = cmd.to[k]; v[2] = cmd.dir[k];
            memcpy(&u, &v[cmd.kind == VP_CMD_MOVE ? 1 : 0], sizeof u);
            h = (h ^ u) * 1099511628211ull;
        }
        if (cmd.kind == VP_CMD_DONE) {
            if (!(b3 & 64u) || rescans > 0) break;
            /* the sphere moved after the first scan: a re-scan (every old proof stale, every
             * sample measured again, or a sparse share of them) from the start, or from where
             * the device stands (the next byte says which) */
            unsigned how = next_byte(&D) & 3u;
            for (k = 0; k < 3; k++) D.centre[0][k] += move[k];
            /* a sphere that moved onto the device: the object, not the planner, went through */
            if (through_object(&D, pos, pos)) D.lied = 1;
            st = vp_planner_rescan_with(pl, how);
            if (st != VP_OK && st != VP_ENOMEM) fail();
            if (st != VP_OK) break;
            rescans++;
            if (!(how & VP_RESCAN_HERE)) memcpy(pos, c.start, sizeof pos);
            continue;
        }
        for (k = 0; k < 3; k++) {
            /* from where it stands (after a contact: the contact point, as the planner worked
             * it out along the move, to rounding) */
            if (touched && fabs(cmd.from[k] - pos[k]) <= 1e-12 * (1.0 + fabs(pos[k]))) pos[k] = cmd.from[k];
            if (cmd.from[k] != pos[k]) fail();
        }
        touched = 0;
        if (cmd.kind == VP_CMD_MOVE) {
            for (k = 0; k < 3; k++)
                if (!isfinite(cmd.to[k])) fail();
            /* the product's promise, checked against the true object: while the device has
             * told no lie that frees space, no move goes through the object */
            if (!D.lied && through_object(&D, cmd.from, cmd.to)) fail();
            memcpy(pos, cmd.to, sizeof pos);
            if (next_byte(&D) == 251u) {
                /* the contact switch part way along the move (a surface the camera missed,
                 * or a false alarm): the device stands there */
                double len = 0.0, at;
                vp_planner_stage_t stage = vp_planner_stage(pl);
                for (k = 0; k < 3; k++) len += (cmd.to[k] - cmd.from[k]) * (cmd.to[k] - cmd.from[k]);
                len = sqrt(len);
                at = len * (double)next_byte(&D) / 255.0;
                st = vp_planner_touch(pl, at);
                /* during the seeds a contact stops the scan (documented), else never */
                if (st == VP_EUNSAFE && stage == VP_STAGE_SEED) break;
                if (!touch_ok(st)) fail();
                if (st == VP_OK && len > 0.0) {
                    for (k = 0; k < 3; k++) pos[k] = cmd.from[k] + at / len * (cmd.to[k] - cmd.from[k]);
                    touched = 1;
                }
            }
            continue;
        }
        if (cmd.kind != VP_CMD_PROBE) fail();
        {
            double dd = cmd.dir[0] * cmd.dir[0] + cmd.dir[1] * cmd.dir[1] + cmd.dir[2] * cmd.dir[2];
            vp_probe_result_t r;
            unsigned i, fed = 0;
            if (!(fabs(dd - 1.0) < 1e-9) || !(cmd.range > 0.0) || !isfinite(cmd.range)) fail();
            if (c.max_range > 0.0 && cmd.range > c.max_range * (1.0 + 1e-12)) fail();
            answer(pl, &D, cmd.from, cmd.dir, cmd.range, 0, &r);
            if (sight && r.hit == 0) {
                /* the sight rule, as a camera port applies it: a miss where the mesh so far may
                 * hide the spot from the camera proves nothing */
                double cam[3];
                cam[0] = cmd.from[0] + 0.05; cam[1] = cmd.from[1] - 0.03; cam[2] = cmd.from[2] + 0.02;
                st = vp_planner_spot_hidden(pl, cmd.from, cmd.dir, cmd.range, cam);
                if (st != 0 && st != 1) fail();
                if (st == 1) r.hit = VP_PROBE_TOO_CLOSE;
            }
            st = vp_planner_feed(pl, &r);
            if (st == VP_EUNSAFE || (st != VP_OK && (st >= 0 || st < VP_ESTALL))) fail();
            if (st != VP_OK) {
                if (vp_planner_next(pl, &cmd) == VP_OK && cmd.kind != VP_CMD_DONE) fail(); /* an error stops it */
                break;
            }
            h = (h ^ (uint64_t)r.hit) * 1099511628211ull;
            for (i = 0; i < c.line_rays; i++) {
                /* a line laser's more rays, fanned about the probe's direction */
                double d[3], s = 0.05 * ((double)i - 1.0), len;
                d[0] = cmd.dir[0] + s * cmd.dir[1];
                d[1] = cmd.dir[1] - s * cmd.dir[0];
                d[2] = cmd.dir[2] + s;
                len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                for (k = 0; k < 3; k++) d[k] /= len;
                if (!(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1.0) <= 1e-9)) continue;
                answer(pl, &D, cmd.from, d, cmd.range, 1, &r);
                st = vp_planner_feed_ray(pl, d, &r);
                if (st != VP_OK) fail();
                fed++;
            }
            if (fed == c.line_rays && c.line_rays > 0 && vp_planner_feed_ray(pl, cmd.dir, &r) != VP_ESTATE)
                fail(); /* one ray too many: refused */
        }
    }
    *hash = h;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static vp_planner_t pl;
    static void *arena;
    uint64_t h1, h2;
    if (size < CONFIG_BYTES) return 0;
    if (!arena && !(arena = malloc(ARENA_BYTES))) return 0;
    run(data, size, arena, &pl, &h1);
    run(data, size, arena, &pl, &h2);
    if (h1 != h2) fail(); /* deterministic: the same answers, the same commands */
    return 0;
}
