/* vp_simdev — see vp_simdev.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_rng.h"
#include "vp_simdev.h"
#include "vp_status.h"
#include "vp_vec3.h"

struct vp_simdev {
    const vp_surface_t *surf;
    vp_simdev_config_t cfg;
    double pos[3];
    uint64_t nprobe;     /* probes done: the next probe's number */
    vp_simdev_stats_t st;
    double motion_tol;   /* cfg.motion_tol or its default */
};

static int vp_in_box(const vp_simdev_config_t *c, const double p[3])
{
    int k;
    for (k = 0; k < 3; k++) if (p[k] < c->limit_lo[k] || p[k] > c->limit_hi[k]) return 0;
    return 1;
}

/* The time a move of length len takes: a trapezoid of speed and acceleration (a triangle when
 * too short to reach the speed). */
static double vp_move_time(const vp_simdev_config_t *c, double len)
{
    if (!(c->speed > 0) || !(len > 0)) return 0;
    if (!(c->accel > 0)) return len / c->speed;
    if (len >= c->speed * c->speed / c->accel) return len / c->speed + c->speed / c->accel;
    return 2 * sqrt(len / c->accel);
}

/* The distance along a move of length len (taking T) at time tau after its start. */
static double vp_move_at(const vp_simdev_config_t *c, double len, double T, double tau)
{
    double ramp, peak;
    if (!(T > 0) || tau >= T) return len;
    if (!(c->accel > 0)) return len * tau / T;
    ramp = len >= c->speed * c->speed / c->accel ? c->speed / c->accel : 0.5 * T;
    peak = c->accel * ramp;
    if (tau < ramp) return 0.5 * c->accel * tau * tau;
    if (tau > T - ramp) return len - 0.5 * c->accel * (T - tau) * (T - tau);
    return 0.5 * c->accel * ramp * ramp + peak * (tau - ramp);
}

/* The part [ta, tb] of a move from a along dir (taking T from the clock's time) against the
 * moving object: checked against the object frozen at ta with the clearance grown by how far
 * any surface point can move in tb - ta; split in time while that growth exceeds the tolerance. */
static int vp_moving_collides(const vp_simdev_t *d, const double a[3], const double dir[3], double len, double T,
                              double ta, double tb, int depth)
{
    double pa[3], pb[3], sa = vp_move_at(&d->cfg, len, T, ta), sb = vp_move_at(&d->cfg, len, T, tb), grow;
    double t0 = d->st.time + ta;
    int k;
    for (k = 0; k < 3; k++) { pa[k] = a[k] + sa * dir[k]; pb[k] = a[k] + sb * dir[k]; }
    grow = tb > ta ? vp_motion_speed_bound(d->cfg.motion, t0, d->st.time + tb) * (tb - ta) : 0;
    if (!vp_motion_segment_collides(d->cfg.motion, t0, pa, pb, d->cfg.clearance + grow)) return 0;
    if (grow <= d->motion_tol || depth >= 60) return 1;
    return vp_moving_collides(d, a, dir, len, T, ta, 0.5 * (ta + tb), depth + 1) ||
           vp_moving_collides(d, a, dir, len, T, 0.5 * (ta + tb), tb, depth + 1);
}

static int vp_moving_move_collides(const vp_simdev_t *d, const double target[3], double len)
{
    double dir[3] = { 0, 0, 0 };
    int k;
    if (len > 0) for (k = 0; k < 3; k++) dir[k] = (target[k] - d->pos[k]) / len;
    return vp_moving_collides(d, d->pos, dir, len, vp_move_time(&d->cfg, len), 0, vp_move_time(&d->cfg, len), 0);
}

int vp_simdev_create(const vp_surface_t *s, const vp_simdev_config_t *cfg, const double start[3], vp_simdev_t **out)
{
    vp_simdev_t *d;
    if (!s || !start || !out || !vp_finite3(start)) return VP_EINVAL;
    if (cfg && (cfg->clearance < 0 || cfg->noise_sigma < 0 || cfg->dropout < 0 || cfg->dropout > 1 ||
                cfg->min_range < 0 || cfg->max_range < 0 || cfg->ndark < 0 || cfg->ndark > VP_SIMDEV_MAX_DARK))
        return VP_EINVAL;
    if (cfg && (!(cfg->speed >= 0 && cfg->accel >= 0 && cfg->probe_time >= 0 && cfg->motion_tol >= 0) ||
                !isfinite(cfg->speed + cfg->accel + cfg->probe_time + cfg->motion_tol) ||
                (cfg->motion && vp_motion_body(cfg->motion) != s))) return VP_EINVAL;
    /* the contact switch is checked against the object standing still */
    if (cfg && cfg->contact && cfg->motion) return VP_EINVAL;
    d = calloc(1, sizeof *d);
    if (!d) return VP_ENOMEM;
    d->surf = s;
    if (cfg) d->cfg = *cfg;
    memcpy(d->pos, start, sizeof d->pos);
    {
        double lo[3], hi[3];
        vp_surface_bbox(s, lo, hi);
        d->motion_tol = d->cfg.motion_tol > 0 ? d->cfg.motion_tol : 1e-3 * vp_dist3(lo, hi);
    }
    *out = d;
    return VP_OK;
}

void vp_simdev_destroy(vp_simdev_t *d) { free(d); }

/* Where along [p, p + len u] the device first touches the object: the point's first crossing,
 * or for a ball of radius c the first place within c of the surface (sphere tracing: each step
 * is the distance to the surface less c, so no contact is stepped over). 1 and *t, or 0. */
#define TOUCH_TOL_REL 1e-12
static int first_touch(const vp_simdev_t *d, const double p[3], const double u[3], double len, double *t)
{
    double c = d->cfg.clearance, s = 0.0, tol = TOUCH_TOL_REL * (1.0 + len + sqrt(vp_dot3(p, p)));
    int k, steps;
    if (!(c > 0.0)) return vp_surface_ray(d->surf, p, u, len, t);
    for (steps = 0; steps < 100000 && s <= len; steps++) {
        double q[3], gap;
        for (k = 0; k < 3; k++) q[k] = p[k] + s * u[k];
        if (vp_surface_inside(d->surf, q)) { *t = s; return 1; }
        gap = vp_surface_distance(d->surf, q) - c;
        if (gap <= tol) { *t = s; return 1; }
        s += gap;
    }
    return 0;
}

int vp_simdev_move(vp_simdev_t *d, const double target[3], vp_simdev_move_t *res)
{
    vp_simdev_move_t r = { VP_OK, 0, 0, 0.0, 0 };
    double len;
    if (!d || !target || !vp_finite3(target)) { r.status = VP_EINVAL; goto out; }
    /* The travel box is convex: a segment stays inside iff its end does (start is inside). */
    if (d->cfg.has_limits && !vp_in_box(&d->cfg, target)) {
        d->st.refused_moves++;
        r.status = VP_ERANGE;
        goto out;
    }
    len = sqrt((target[0] - d->pos[0]) * (target[0] - d->pos[0]) + (target[1] - d->pos[1]) * (target[1] - d->pos[1]) +
               (target[2] - d->pos[2]) * (target[2] - d->pos[2]));
    if (d->cfg.contact) {
        /* the device may stand on S (it touched there): the way back is checked from just off it */
        double u[3], p0[3], skip = 0.0, t;
        int k;
        for (k = 0; k < 3; k++) u[k] = len > 0.0 ? (target[k] - d->pos[k]) / len : 0.0;
        skip = 1e-9 * (1.0 + len + sqrt(vp_dot3(d->pos, d->pos)));
        if (skip > len) skip = len;
        for (k = 0; k < 3; k++) p0[k] = d->pos[k] + skip * u[k];
        if (len > skip && first_touch(d, p0, u, len - skip, &t)) {
            /* the switch closes at the touch: the device stops there */
            double at = skip + t;
            d->st.contacts++;
            d->st.moves++;
            d->st.travel += at;
            r.touched = 1;
            r.at = at;
            r.length = at;
            d->st.time += vp_move_time(&d->cfg, at);
            for (k = 0; k < 3; k++) d->pos[k] += at * u[k];
            goto out;
        }
        r.collided = len > skip && vp_surface_segment_collides(d->surf, p0, target, d->cfg.clearance);
    } else {
        r.collided = d->cfg.motion ? vp_moving_move_collides(d, target, len)
                                   : vp_surface_segment_collides(d->surf, d->pos, target, d->cfg.clearance);
    }
    if (r.collided) {
        d->st.collisions++;
        if (d->cfg.stop_on_collision) { d->st.refused_moves++; r.status = VP_EABORT; goto out; }
    }
    d->st.moves++;
    d->st.travel += len;
    d->st.time += vp_move_time(&d->cfg, len);
    r.length = len;
    memcpy(d->pos, target, sizeof d->pos);
out:
    if (res) *res = r;
    return r.status;
}

/* A reading's arguments: a device, a unit direction, a positive range. */
static int vp_ray_ok(const vp_simdev_t *d, const double dir[3], double range)
{
    return d && dir && vp_finite3(dir) && range > 0 && fabs(vp_dot3(dir, dir) - 1) <= 1e-9;
}

/* One reading along dir from the device: the object (as it is at the device's clock), dark
 * patches, the minimum range, dropouts and noise drawn from rng. */
static void vp_read(vp_simdev_t *d, const double dir[3], double range, vp_rng_t *rng, int probe, vp_simdev_probe_t *r)
{
    double t, noise, u;
    int k;
    if (d->cfg.max_range > 0 && range > d->cfg.max_range) range = d->cfg.max_range;
    noise = d->cfg.noise_sigma > 0 ? d->cfg.noise_sigma * vp_rng_normal(rng) : 0;
    u = vp_rng_uniform(rng);
    if (!(d->cfg.motion ? vp_motion_ray(d->cfg.motion, d->st.time, d->pos, dir, range, &t)
                        : vp_surface_ray(d->surf, d->pos, dir, range, &t))) { d->st.misses++; return; }
    r->true_t = t;
    for (k = 0; k < d->cfg.ndark; k++) {
        double q[3], e[3];
        int j;
        for (j = 0; j < 3; j++) { q[j] = d->pos[j] + t * dir[j]; e[j] = q[j] - d->cfg.dark[k][j]; }
        if (vp_dot3(e, e) <= d->cfg.dark[k][3] * d->cfg.dark[k][3]) {
            /* a dark patch: no spot, the rangefinder reads nothing */
            d->st.dark_misses += (unsigned long)probe;
            d->st.misses++;
            return;
        }
    }
    if (t < d->cfg.min_range) { d->st.too_close++; r->too_close = 1; return; }
    if (u < d->cfg.dropout) { d->st.dropouts++; d->st.misses++; return; }
    t += noise;
    if (t < 0) t = 0;
    r->hit = 1;
    r->t = t;
    for (k = 0; k < 3; k++) r->point[k] = d->pos[k] + t * dir[k];
    d->st.hits++;
}

int vp_simdev_probe(vp_simdev_t *d, const double dir[3], double range, vp_simdev_probe_t *res)
{
    vp_simdev_probe_t r;
    vp_rng_t rng;
    memset(&r, 0, sizeof r);
    r.true_t = -1;
    if (!vp_ray_ok(d, dir, range)) {
        r.status = VP_EINVAL;
    } else {
        /* The draws of probe k come from a generator seeded by (seed, k) alone. */
        vp_rng_seed(&rng, d->cfg.seed ^ (0x9E3779B97F4A7C15ULL * (d->nprobe + 1)));
        d->nprobe++;
        d->st.probes++;
        d->st.time += d->cfg.probe_time;  /* the reading is of the object as the exposure ends */
        vp_read(d, dir, range, &rng, 1, &r);
    }
    if (res) *res = r;
    return r.status;
}

int vp_simdev_ray(vp_simdev_t *d, const double dir[3], double range, unsigned i, vp_simdev_probe_t *res)
{
    vp_simdev_probe_t r;
    vp_rng_t rng;
    memset(&r, 0, sizeof r);
    r.true_t = -1;
    if (!vp_ray_ok(d, dir, range) || d->nprobe == 0) {
        r.status = VP_EINVAL;
    } else {
        /* ray i of the frame of probe k: drawn from (seed, k, i); the frame's time, no probe counted */
        vp_rng_seed(&rng, d->cfg.seed ^ (0x9E3779B97F4A7C15ULL * d->nprobe) ^ (0xD1B54A32D192ED03ULL * ((uint64_t)i + 1)));
        d->st.rays++;
        vp_read(d, dir, range, &rng, 0, &r);
    }
    if (res) *res = r;
    return r.status;
}

void vp_simdev_position(const vp_simdev_t *d, double p[3]) { memcpy(p, d->pos, sizeof d->pos); }
void vp_simdev_restore(vp_simdev_t *d, const double p[3], uint64_t probes)
{
    memcpy(d->pos, p, sizeof d->pos);
    d->nprobe = probes;
}

void vp_simdev_stats(const vp_simdev_t *d, vp_simdev_stats_t *st) { *st = d->st; }
