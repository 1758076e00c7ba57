/* vp_kin — see vp_kin.h. */
#include <math.h>
#include <string.h>
#include "vp_kin.h"
#include "vp_status.h"
#include "vp_vec3.h"

#define VP_DEG (3.14159265358979323846 / 180.0)

static int vp_kin_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return 0;
    return 1;
}

static double vp_kin_norm(const double v[3]) { return vp_norm3(v); }

int vp_kin_init(vp_kin_t *k, const vp_kin_config_t *cfg)
{
    int i;
    if (!k || !cfg) return VP_EINVAL;
    if (!vp_kin_finite(cfg->tilt_offset, 3) || !vp_kin_finite(cfg->laser_offset, 3) ||
        !vp_kin_finite(cfg->lo, VP_KIN_JOINTS) || !vp_kin_finite(cfg->hi, VP_KIN_JOINTS) ||
        !isfinite(cfg->origin_tol) || cfg->origin_tol < 0) return VP_EINVAL;
    for (i = 0; i < VP_KIN_JOINTS; i++) if (cfg->lo[i] > cfg->hi[i]) return VP_EINVAL;
    k->cfg = *cfg;
    if (k->cfg.origin_tol == 0) k->cfg.origin_tol = 0.1;
    k->tilted = 0;
    k->beam[0] = 1;
    k->beam[1] = k->beam[2] = 0;
    if (!vp_kin_finite(cfg->laser_dir, 3)) return VP_EINVAL;
    if (cfg->laser_dir[0] != 0 || cfg->laser_dir[1] != 0 || cfg->laser_dir[2] != 0) {
        double n = vp_kin_norm(cfg->laser_dir);
        if (!(n > 1e-9)) return VP_EINVAL;
        for (i = 0; i < 3; i++) k->beam[i] = cfg->laser_dir[i] / n;
        k->tilted = !(k->beam[0] == 1 && k->beam[1] == 0 && k->beam[2] == 0);
        if (k->beam[0] < 0.5) return VP_EINVAL;   /* within 60 degrees of +x */
    }
    k->reach = vp_kin_norm(cfg->tilt_offset) + vp_kin_norm(cfg->laser_offset);
    return VP_OK;
}

void vp_kin_rot(double pan, double tilt, double r[9])
{
    double cp = cos(pan * VP_DEG), sp = sin(pan * VP_DEG), ct = cos(tilt * VP_DEG), st = sin(tilt * VP_DEG);
    r[0] = cp * ct; r[1] = -sp; r[2] = -cp * st;
    r[3] = sp * ct; r[4] = cp;  r[5] = -sp * st;
    r[6] = st;      r[7] = 0;   r[8] = ct;
}

void vp_kin_mul(const double r[9], const double v[3], double out[3])
{
    out[0] = vp_dot3(r, v);
    out[1] = r[3] * v[0] + r[4] * v[1] + r[5] * v[2];
    out[2] = r[6] * v[0] + r[7] * v[1] + r[8] * v[2];
}

/* Laser origin relative to the pan pivot G. */
static void vp_kin_arm(const vp_kin_t *k, double pan, double tilt, double f[3])
{
    double r[9], rz[9], a[3], b[3];
    int i;
    vp_kin_rot(pan, tilt, r);
    vp_kin_rot(pan, 0, rz);
    vp_kin_mul(rz, k->cfg.tilt_offset, a);
    vp_kin_mul(r, k->cfg.laser_offset, b);
    for (i = 0; i < 3; i++) f[i] = a[i] + b[i];
}

void vp_kin_head(const vp_kin_t *k, const double j[VP_KIN_JOINTS], double rot[9], double pos[3])
{
    double rz[9], a[3];
    int i;
    vp_kin_rot(j[VP_J_PAN], j[VP_J_TILT], rot);
    vp_kin_rot(j[VP_J_PAN], 0, rz);
    vp_kin_mul(rz, k->cfg.tilt_offset, a);
    for (i = 0; i < 3; i++) pos[i] = j[i] + a[i];
}

void vp_kin_forward(const vp_kin_t *k, const double j[VP_KIN_JOINTS], double origin[3], double dir[3])
{
    double r[9], f[3];
    int i;
    vp_kin_arm(k, j[VP_J_PAN], j[VP_J_TILT], f);
    for (i = 0; i < 3; i++) origin[i] = j[i] + f[i];
    vp_kin_rot(j[VP_J_PAN], j[VP_J_TILT], r);
    if (k->tilted) { vp_kin_mul(r, k->beam, dir); return; }
    dir[0] = r[0]; dir[1] = r[3]; dir[2] = r[6];
}

void vp_kin_point(const vp_kin_t *k, const double j[VP_KIN_JOINTS], double dist, double p[3])
{
    double o[3], d[3];
    int i;
    vp_kin_forward(k, j, o, d);
    for (i = 0; i < 3; i++) p[i] = o[i] + dist * d[i];
}

static int vp_kin_joint_ok(const vp_kin_t *k, int i, double v)
{
    const double eps = 1e-9;
    if (k->cfg.lo[i] == 0 && k->cfg.hi[i] == 0) return 1;
    return v >= k->cfg.lo[i] - eps && v <= k->cfg.hi[i] + eps;
}

int vp_kin_in_travel(const vp_kin_t *k, const double j[VP_KIN_JOINTS])
{
    int i;
    for (i = 0; i < VP_KIN_JOINTS; i++) if (!vp_kin_joint_ok(k, i, j[i])) return 0;
    return 1;
}

/* Aim a beam calibrated off +x: the tilts with bx sin t + bz cos t = dz, each with its pan. Where
 * the beam cannot point exactly (near vertical, at the tilt's travel) it points as close as it
 * goes, off dir by at most its angle to +x. */
/* The pose that puts the laser origin at `origin` with pan near pn (and its neighbours by 360)
 * and this tilt, if it is in travel and turns the joints less than *best from cur. */
static void vp_kin_aim_pan(const vp_kin_t *k, const double cur[VP_KIN_JOINTS], const double origin[3], double pn,
                           double tilt, double *best, double out[VP_KIN_JOINTS], int *found)
{
    double cand[VP_KIN_JOINTS], f[3];
    int m, i;
    for (m = -2; m <= 2; m++) {
        double pan = pn + 360.0 * m, cost;
        if (!vp_kin_joint_ok(k, VP_J_PAN, pan)) continue;
        vp_kin_arm(k, pan, tilt, f);
        for (i = 0; i < 3; i++) cand[i] = origin[i] - f[i];
        cand[VP_J_PAN] = pan;
        cand[VP_J_TILT] = tilt;
        if (!vp_kin_in_travel(k, cand)) continue;
        cost = fabs(pan - cur[VP_J_PAN]) + fabs(tilt - cur[VP_J_TILT]);
        if (cost < *best) { *best = cost; memcpy(out, cand, sizeof cand); *found = 1; }
    }
}

static int vp_kin_aim_tilted(const vp_kin_t *k, const double cur[VP_KIN_JOINTS], const double origin[3],
                             const double dir[3], double out[VP_KIN_JOINTS])
{
    const double *b = k->beam;
    double amp = sqrt(b[0] * b[0] + b[2] * b[2]), phi = atan2(b[2], b[0]), s = dir[2] / amp, as, tilts[6], best = HUGE_VAL;
    int ti, found = 0;
    /* within asin|by| of vertical the beam cannot point: aim it as steep as it goes (it then
     * differs from dir by at most that angle) */
    as = asin(s > 1 ? 1 : s < -1 ? -1 : s);
    tilts[0] = (as - phi) / VP_DEG;
    tilts[1] = (3.14159265358979323846 - as - phi) / VP_DEG;
    for (ti = 0; ti < 2; ti++) { tilts[2 + 2 * ti] = tilts[ti] + 360; tilts[3 + 2 * ti] = tilts[ti] - 360; }
    for (ti = 0; ti < 6; ti++) {
        double tilt = tilts[ti], h0, pb, pn, off = acos(b[0]) / VP_DEG, lo = k->cfg.lo[VP_J_TILT], hi = k->cfg.hi[VP_J_TILT];
        /* past the tilt's travel by no more than the beam's own angle: as far as it goes */
        if (!(lo == 0 && hi == 0) && tilt < lo && tilt > lo - off) tilt = lo;
        if (!(lo == 0 && hi == 0) && tilt > hi && tilt < hi + off) tilt = hi;
        if (!vp_kin_joint_ok(k, VP_J_TILT, tilt)) continue;
        h0 = cos(tilt * VP_DEG) * b[0] - sin(tilt * VP_DEG) * b[2];
        pb = hypot(dir[0], dir[1]) < 1e-12 ? cur[VP_J_PAN] : (atan2(dir[1], dir[0]) - atan2(b[1], h0)) / VP_DEG;
        pn = pb + 360.0 * floor((cur[VP_J_PAN] - pb) / 360.0 + 0.5);
        vp_kin_aim_pan(k, cur, origin, pn, tilt, &best, out, &found);
    }
    return found ? VP_OK : VP_ERANGE;
}

int vp_kin_aim(const vp_kin_t *k, const double cur[VP_KIN_JOINTS], const double origin[3],
               const double dir[3], double out[VP_KIN_JOINTS])
{
    double p0, t0, tilts[3], best = HUGE_VAL;
    int nt, b, ti, found = 0;
    if (!k || !cur || !origin || !dir || !out) return VP_EINVAL;
    if (!vp_kin_finite(cur, VP_KIN_JOINTS) || !vp_kin_finite(origin, 3) || !vp_kin_finite(dir, 3) ||
        fabs(vp_kin_norm(dir) - 1) > 1e-9) return VP_EINVAL;
    if (k->tilted) return vp_kin_aim_tilted(k, cur, origin, dir, out);
    t0 = asin(dir[2] > 1 ? 1 : dir[2] < -1 ? -1 : dir[2]) / VP_DEG;
    /* straight up or down: pan is free, keep it */
    p0 = (fabs(dir[2]) > 1 - 1e-12) ? cur[VP_J_PAN] : atan2(dir[1], dir[0]) / VP_DEG;
    for (b = 0; b < 2; b++) {
        /* branch 1: the head turned round (pan + 180) and tilted over the top */
        if (b == 0) { tilts[0] = t0; nt = 1; }
        else { tilts[0] = 180 - t0; tilts[1] = -180 - t0; nt = 2; }
        for (ti = 0; ti < nt; ti++) {
            double pb = p0 + 180.0 * b, tilt = tilts[ti];
            /* pan candidates: the one nearest to cur, and its neighbours by 360 */
            double pn = pb + 360.0 * floor((cur[VP_J_PAN] - pb) / 360.0 + 0.5);
            if (!vp_kin_joint_ok(k, VP_J_TILT, tilt)) continue;
            vp_kin_aim_pan(k, cur, origin, pn, tilt, &best, out, &found);
        }
    }
    return found ? VP_OK : VP_ERANGE;
}

int vp_kin_move(const vp_kin_t *k, const double cur[VP_KIN_JOINTS], const double to[3],
                double out[VP_KIN_JOINTS])
{
    double f[3], j[VP_KIN_JOINTS];
    int i;
    if (!k || !cur || !to || !out || !vp_kin_finite(cur, VP_KIN_JOINTS) || !vp_kin_finite(to, 3))
        return VP_EINVAL;
    vp_kin_arm(k, cur[VP_J_PAN], cur[VP_J_TILT], f);
    for (i = 0; i < 3; i++) j[i] = to[i] - f[i];
    j[VP_J_PAN] = cur[VP_J_PAN];
    j[VP_J_TILT] = cur[VP_J_TILT];
    if (!vp_kin_in_travel(k, j)) return VP_ERANGE;
    memcpy(out, j, sizeof j);
    return VP_OK;
}

int vp_kin_aim_path(const vp_kin_t *k, const double cur[VP_KIN_JOINTS],
                    const double target[VP_KIN_JOINTS], double (*way)[VP_KIN_JOINTS], int max)
{
    double oa[3], ob[3], d[3], f[3], phi;
    int n, w, i;
    if (!k || !cur || !target || !way || max < 1) return VP_EINVAL;
    /* A linear joint piece turning the head by phi (rad) moves the arm end off its chord by at
     * most reach * phi^2 / 8 (second derivative bound); n pieces keep that below origin_tol. */
    phi = (fabs(target[VP_J_PAN] - cur[VP_J_PAN]) + fabs(target[VP_J_TILT] - cur[VP_J_TILT])) * VP_DEG;
    n = 1;
    if (k->reach > 0 && phi > 0) {
        double nn = ceil(phi * sqrt(k->reach / (8.0 * k->cfg.origin_tol)));
        if (nn > max) return VP_ENOMEM;
        if (nn > 1) n = (int)nn;
    }
    vp_kin_forward(k, cur, oa, d);
    vp_kin_forward(k, target, ob, d);
    for (w = 1; w <= n; w++) {
        double s = (double)w / n;
        double pan = cur[VP_J_PAN] + s * (target[VP_J_PAN] - cur[VP_J_PAN]);
        double tilt = cur[VP_J_TILT] + s * (target[VP_J_TILT] - cur[VP_J_TILT]);
        if (w == n) { memcpy(way[w - 1], target, sizeof way[0]); break; }
        vp_kin_arm(k, pan, tilt, f);
        for (i = 0; i < 3; i++) way[w - 1][i] = oa[i] + s * (ob[i] - oa[i]) - f[i];
        way[w - 1][VP_J_PAN] = pan;
        way[w - 1][VP_J_TILT] = tilt;
    }
    return n;
}
