#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_sim_setup.h"
#include "vp_bodyreport.h"
#include "vp_vec3.h"
#include "vp_kdtree.h"
#include "vp_outcome.h"
#include "vp_meshio.h"
#include "vp_note.h"

void vp_sim_options_default(vp_sim_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->out = "out/scan";
    o->confirm = -1;
    o->arena = (size_t)512 << 20;
    o->omega_margin = 0.1;
    o->seed = 1;
    o->hausdorff = 20000;
    o->speed = VP_SIM_SPEED;
    o->accel = VP_SIM_ACCEL;
    o->probe_time = VP_SIM_PROBE_TIME;
    o->proof_life = -1;
    o->feature_margin = -1;
}

/* --motion without --proof-life: a proof expires once the object may have moved this share of
 * eps since it was made, the speed bound taken over this horizon (s) */
#define PROOF_LIFE_EPS_SHARE (1.0 / 64.0)
#define PROOF_LIFE_HORIZON 3600.0

static double omega_diameter(const vp_planner_config_t *c)
{
    double d[3];
    vp_sub3(d, c->omega_hi, c->omega_lo);
    return c->omega_kind == VP_OMEGA_BALL ? 2.0 * c->omega_radius : sqrt(vp_dot3(d, d));
}

int vp_sim_config(const vp_surface_t *surf, double eps, int ball, double margin,
                  vp_planner_config_t *cfg, char *err, size_t errlen)
{
    double lo[3], hi[3], diag = 0.0, m;
    int k, c, n = vp_surface_components(surf);
    memset(cfg, 0, sizeof *cfg);
    vp_surface_bbox(surf, lo, hi);
    for (k = 0; k < 3; k++) diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    diag = sqrt(diag);
    m = margin * diag;
    if (n < 1 || n > VP_PLANNER_MAX_SEEDS) {
        snprintf(err, errlen, "the object has %d components (1..%d supported)", n, VP_PLANNER_MAX_SEEDS);
        return VP_EINVAL;
    }
    if (ball) {
        cfg->omega_kind = VP_OMEGA_BALL;
        for (k = 0; k < 3; k++) cfg->omega_center[k] = 0.5 * (lo[k] + hi[k]);
        cfg->omega_radius = 0.5 * diag + m;
        for (k = 0; k < 3; k++) cfg->start[k] = cfg->omega_center[k] + (cfg->omega_radius + m) / sqrt(3.0);
    } else {
        cfg->omega_kind = VP_OMEGA_BOX;
        for (k = 0; k < 3; k++) {
            cfg->omega_lo[k] = lo[k] - m;
            cfg->omega_hi[k] = hi[k] + m;
            cfg->start[k] = hi[k] + 1.5 * m;
        }
    }
    cfg->ninterior = (uint32_t)n;
    for (c = 0; c < n; c++) vp_surface_interior_point(surf, c, cfg->interior[c]);
    cfg->eps = eps;
    return VP_OK;
}

/* Up to 3 significant digits, rounded up (a value printed as the smallest accepted one must be
 * accepted when given back). */
static double up3(double v)
{
    double p;
    if (!(v > 0) || !isfinite(v)) return v;
    p = pow(10.0, floor(log10(v)) - 2.0);
    return ceil(v / p * (1.0 - 1e-12)) * p;
}

int vp_sim_check_ranges(const vp_planner_config_t *cfg, double diag, const vp_sim_options_t *o, char *err,
                        size_t errlen)
{
    double od = 0.0, big = 0.0, min_eps, nmax;
    int k;
    /* eps against Omega: the planner's constructions (Voronoi vertices, probe hits, ball radii)
     * are rounded to double; far below the size of Omega and the magnitude of its coordinates
     * they are noise, and the scan stops on a consistency check */
    if (cfg->omega_kind == VP_OMEGA_BALL) {
        od = 2.0 * cfg->omega_radius;
        for (k = 0; k < 3; k++) big = fmax(big, fabs(cfg->omega_center[k]) + cfg->omega_radius);
    } else {
        for (k = 0; k < 3; k++) {
            od += (cfg->omega_hi[k] - cfg->omega_lo[k]) * (cfg->omega_hi[k] - cfg->omega_lo[k]);
            big = fmax(big, fmax(fabs(cfg->omega_lo[k]), fabs(cfg->omega_hi[k])));
        }
        od = sqrt(od);
    }
    min_eps = up3(fmax(VP_SIM_EPS_MIN_OMEGA * od, VP_SIM_EPS_MIN_COORD * big));
    if (!(cfg->eps >= min_eps * (1.0 - 1e-9))) {
        char rel[48] = "";
        if (diag > 0) snprintf(rel, sizeof rel, " (--eps-rel %.3g)", up3(min_eps / diag));
        snprintf(err, errlen, "eps %.6g is too small for this object: the planner computes in double precision, "
                 "so eps must be at least %g of Omega's diagonal (%.6g) and %g of its largest coordinate (%.6g); "
                 "the smallest accepted is --eps %.3g%s", cfg->eps, VP_SIM_EPS_MIN_OMEGA, od,
                 VP_SIM_EPS_MIN_COORD, big, min_eps, rel);
        return VP_EINVAL;
    }
    /* the rangefinder: the planner trusts a hit to 4 sigma and makes its first facet of hits
     * within eps/4 of each other; a miss is trusted after repeated misses on the ray */
    nmax = cfg->eps * VP_SIM_NOISE_MAX_REL;
    if (o->noise > nmax) {
        snprintf(err, errlen, "--noise %.6g is out of the range the planner supports: 0 to eps/%g (%.3g at eps %.6g): "
                 "it trusts a hit to 4 standard deviations and builds its first facet from hits within eps/4",
                 o->noise, 1.0 / VP_SIM_NOISE_MAX_REL, nmax, cfg->eps);
        return VP_EINVAL;
    }
    if (o->dropout > VP_SIM_DROPOUT_MAX) {
        snprintf(err, errlen, "--dropout %.6g is out of the range the planner supports: 0 to %g (a miss is "
                 "trusted only after repeated misses on the same ray; above %g the seed probes fail)",
                 o->dropout, VP_SIM_DROPOUT_MAX, VP_SIM_DROPOUT_MAX);
        return VP_EINVAL;
    }
    return VP_OK;
}

int vp_sim_check_out(const vp_sim_options_t *o, char *err, size_t errlen)
{
    char path[VP_PATH_MAX];
    int st;
    if (!o->out) return VP_OK;
    if ((st = vp_path_cat(path, sizeof path, o->out, ".ply", err, errlen)) != VP_OK) return st;
    return vp_path_cat(path, sizeof path, o->out, ".off", err, errlen);
}

/* An accuracy target H sets the distance bound to H / ACCURACY_SHARE and its floor to
 * H / ACCURACY_FLOOR (measured: see the README's accuracy table) */
#ifndef ACCURACY_SHARE
#define ACCURACY_SHARE 3.0
#endif
#ifndef ACCURACY_FLOOR
#define ACCURACY_FLOOR 4.0
#endif

void vp_accuracy_config(vp_planner_config_t *cfg, double target)
{
    cfg->max_distance = target / ACCURACY_SHARE;
    cfg->min_size = target / ACCURACY_FLOOR < cfg->eps ? target / ACCURACY_FLOOR : cfg->eps;
}

int vp_sim_open(vp_sim_t *s, const vp_sim_options_t *o, char *err, size_t errlen)
{
    vp_simdev_config_t dc;
    double lo[3], hi[3], eps;
    int st, k;
    memset(s, 0, sizeof *s);
    vp_mesh_init(&s->mesh);
    st = vp_surface_open(o->surface, &s->surf, err, errlen);
    if (st != VP_OK) return st;
    vp_surface_bbox(s->surf, lo, hi);
    for (k = 0; k < 3; k++) s->diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    s->diag = sqrt(s->diag);
    s->components = vp_surface_components(s->surf);
    s->contact = o->contact;
    s->target = o->accuracy > 0 ? o->accuracy : o->accuracy_rel * s->diag;
    /* an accuracy target H: a facet is refined where it strays more than H / ACCURACY_SHARE from
     * the surface at its ball centre, or (across a sharp edge, from the tangent planes at its
     * vertices) along an edge; eps diag / 20; the result is measured against the target,
     * never assumed */
    eps = s->target > 0 ? s->diag / 20.0 : o->eps > 0 ? o->eps : o->eps_rel * s->diag;
    /* a device with a body stays outside Omega: Omega keeps twice its radius from the object */
    st = vp_sim_config(s->surf, eps, o->omega_ball,
                       o->clearance > 0 && 2.0 * o->clearance > o->omega_margin * s->diag
                           ? 2.0 * o->clearance / s->diag : o->omega_margin,
                       &s->cfg, err, errlen);
    if (st != VP_OK) return st;
    if ((st = vp_sim_check_ranges(&s->cfg, s->diag, o, err, errlen)) != VP_OK) return st;
    s->cfg.noise_tol = 4.0 * o->noise;
    /* with dropouts, trust a miss once a false one is unlikely: p^(c+1) <= 1e-6 */
    s->cfg.confirm_misses = (uint32_t)(o->confirm >= 0 ? o->confirm
                                       : o->dropout > 0 ? (int)ceil(log(1e-6) / log(o->dropout)) - 1 : 0);
    s->cfg.clearance = o->clearance;
    s->cfg.min_feature = o->min_feature;
    s->cfg.feature_margin = o->min_feature > 0 ? (o->feature_margin >= 0 ? o->feature_margin : VP_FEATURE_MARGIN_DEFAULT * o->min_feature) : 0.0;
    if (o->min_feature > 0 && !(o->clearance > 0)) {
        snprintf(err, errlen, "--min-feature lets a device with a body into Omega: give --clearance too");
        return VP_EINVAL;
    }
    if (o->min_feature > 0 && o->ndark > 0) {
        /* as a board's loader: tubes need walls that tell a dark surface from empty space */
        snprintf(err, errlen, "--min-feature with --dark: tubes are proven by misses round the body's way, and a "
                 "dark patch reads as a miss where the body then goes; host-sim has no walls to tell them apart "
                 "(a board's [rangefinder] backdrop does: scan --board boards/sim-enclosed.ini --dry-run)");
        return VP_EINVAL;
    }
    if ((o->flags & VP_PLAN_FAR_READS) && !(o->clearance > 0)) {
        snprintf(err, errlen, "--far-reads reads on past a body-mode probe's edge: give --clearance too");
        return VP_EINVAL;
    }
    s->cfg.min_angle = o->min_angle;
    if (s->target > 0) {
        vp_accuracy_config(&s->cfg, s->target);
    } else if (o->size_rel > 0) {
        s->cfg.size_rel = o->size_rel;
        s->cfg.min_size = o->min_size > 0 ? o->min_size : s->cfg.eps / 10.0;
        if (s->cfg.min_size > s->cfg.eps) {
            snprintf(err, errlen, "--min-size %.6g is above eps %.6g (the sizing field lies between them)",
                     s->cfg.min_size, s->cfg.eps);
            return VP_EINVAL;
        }
    } else if (o->min_size > 0 && !(o->max_distance > 0)) {
        snprintf(err, errlen, "--min-size is the floor of the sizing field or the distance bound: give --size-rel or --max-distance too");
        return VP_EINVAL;
    } else if (o->min_size > 0) {
        s->cfg.min_size = o->min_size;
    }
    if (o->max_distance > 0) s->cfg.max_distance = o->max_distance;
    s->cfg.max_range = o->max_range;
    s->cfg.flags = o->flags;
    /* with a distance bound, in point mode: the task that can find the smallest ball first (the
     * published order, --paper, keeps its own) */
    if (s->cfg.max_distance > 0 && !(o->clearance > 0) && !o->newest_first && !(o->flags & VP_PLAN_PAPER))
        s->cfg.flags |= VP_PLAN_SMALL_FIRST;
    s->cfg.line_rays = o->line_rays;
    if (o->proof_life >= 0) s->cfg.proof_life = (uint32_t)o->proof_life;
    s->line_half = 0.5 * o->line_deg * (M_PI / 180.0);
    memset(&dc, 0, sizeof dc);
    dc.clearance = o->clearance;
    dc.noise_sigma = o->noise;
    dc.dropout = o->dropout;
    dc.max_range = o->max_range;
    dc.min_range = o->min_range;
    dc.seed = o->seed;
    dc.ndark = o->ndark;
    memcpy(dc.dark, o->dark, sizeof dc.dark);
    dc.contact = o->contact;
    if (o->motion) {
        if ((st = vp_motion_open(o->motion, s->surf, &s->motion, err, errlen)) != VP_OK) return st;
        dc.motion = s->motion;
    }
    if (s->motion && o->proof_life < 0) {
        /* proofs expire once the object may have moved PROOF_LIFE_EPS_SHARE eps since: the
         * longest command (a move across Omega, or a probe) bounds the time per command */
        double lam = vp_motion_speed_bound(s->motion, 0.0, PROOF_LIFE_HORIZON), r = omega_diameter(&s->cfg);
        double c[3], far, tmax;
        for (k = 0; k < 3; k++)
            c[k] = s->cfg.omega_kind == VP_OMEGA_BALL ? s->cfg.omega_center[k] : 0.5 * (s->cfg.omega_lo[k] + s->cfg.omega_hi[k]);
        far = 2.0 * vp_dist3(s->cfg.start, c) + r; /* the first move, from the start, may be longer */
        if (far > r) r = far;
        tmax = r / o->speed + (o->accel > 0 ? o->speed / o->accel : 0.0);
        double n;
        if (o->probe_time > tmax) tmax = o->probe_time;
        n = lam > 0 && tmax > 0 ? floor(s->cfg.eps * PROOF_LIFE_EPS_SHARE / (lam * tmax)) : 0.0;
        s->cfg.proof_life = lam > 0 ? (n < 1 ? 1u : n > 1e9 ? 1000000000u : (uint32_t)n) : 0u;
    }
    dc.speed = o->speed;
    dc.accel = o->accel;
    dc.probe_time = o->probe_time;
    s->dc = dc;
    st = vp_simdev_create(s->surf, &dc, s->cfg.start, &s->dev);
    if (st != VP_OK) { snprintf(err, errlen, "cannot create the simulated device: %s", vp_strerror(st)); return st; }
    s->pl = malloc(sizeof *s->pl);
    s->arena = malloc(o->arena ? o->arena : 1);
    if (!s->pl || !s->arena) { snprintf(err, errlen, "cannot allocate the %zu-byte arena", o->arena); return VP_ENOMEM; }
    st = vp_planner_init(s->pl, s->arena, o->arena, &s->cfg);
    if (st != VP_OK) {
        snprintf(err, errlen, "planner: %s%s", vp_strerror(st),
                 st == VP_ENOMEM ? " (the arena is too small: --arena)" : "");
        return st;
    }
    return VP_OK;
}

int vp_sim_swap_surface(vp_sim_t *s, const char *spec, char *err, size_t errlen)
{
    vp_surface_t *ns;
    vp_simdev_t *nd;
    double lo[3], hi[3], c[3], m = s->cfg.clearance, r2 = 0.0;
    int st, k;
    st = vp_surface_open(spec, &ns, err, errlen);
    if (st != VP_OK) return st;
    vp_surface_bbox(ns, lo, hi);
    for (k = 0; k < 3; k++) {
        c[k] = s->cfg.omega_center[k];
        r2 += (fabs(lo[k] - c[k]) > fabs(hi[k] - c[k]) ? (lo[k] - c[k]) * (lo[k] - c[k]) : (hi[k] - c[k]) * (hi[k] - c[k]));
    }
    if (s->cfg.omega_kind == VP_OMEGA_BOX ? !(lo[0] >= s->cfg.omega_lo[0] + m && lo[1] >= s->cfg.omega_lo[1] + m &&
                                              lo[2] >= s->cfg.omega_lo[2] + m && hi[0] <= s->cfg.omega_hi[0] - m &&
                                              hi[1] <= s->cfg.omega_hi[1] - m && hi[2] <= s->cfg.omega_hi[2] - m)
                                          : !(sqrt(r2) <= s->cfg.omega_radius - m)) {
        snprintf(err, errlen, "the object %s does not lie in the logged session's Omega%s: a re-scan keeps "
                 "the session's Omega (scan it afresh instead)", spec, m > 0 ? " with the head's clearance" : "");
        vp_surface_close(ns);
        return VP_EINVAL;
    }
    st = vp_simdev_create(ns, &s->dc, s->cfg.start, &nd);
    if (st != VP_OK) {
        snprintf(err, errlen, "cannot create the simulated device: %s", vp_strerror(st));
        vp_surface_close(ns);
        return st;
    }
    vp_simdev_destroy(s->dev);
    vp_surface_close(s->surf);
    s->dev = nd;
    s->surf = ns;
    s->components = vp_surface_components(ns);
    s->rescan = 1;
    s->rescan_spec = spec;
    vp_planner_get_stats(s->pl, &s->before);
    return VP_OK;
}

static int dev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    vp_sim_t *s = ctx;
    vp_simdev_move_t r;
    int st = vp_simdev_move(s->dev, cmd->to, &r);
    *collided = r.collided;
    s->touched = r.touched;
    s->touch_at = r.at;
    return st == VP_OK || st == VP_EABORT ? VP_OK : st;
}

static int dev_touched(void *ctx, double *at)
{
    vp_sim_t *s = ctx;
    *at = s->touch_at;
    return s->touched;
}

static int dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    vp_sim_t *s = ctx;
    vp_simdev_probe_t r;
    int st = vp_simdev_probe(s->dev, cmd->dir, cmd->range, &r);
    if (st != VP_OK) return st;
    s->raw = r.hit ? r.t : NAN;
    res->hit = r.too_close ? VP_PROBE_TOO_CLOSE : r.hit;
    res->dist = r.hit ? (r.t < 0 ? 0.0 : r.t) : 0.0;
    return VP_OK;
}

/* A line laser on the head: its plane holds the probe's ray and the horizontal across it (the
 * line lies level in the camera's view); ray i of n spreads evenly over the fan, the centre ray
 * being the probe itself. */
static int dev_rays(void *ctx, const vp_cmd_t *probe, unsigned i, vp_cmd_t *ray, vp_probe_result_t *res)
{
    vp_sim_t *s = ctx;
    vp_simdev_probe_t r;
    double h[3], n, th;
    unsigned m = s->cfg.line_rays, j;
    int k;
    if (i >= m) return 0;
    h[0] = -probe->dir[1];
    h[1] = probe->dir[0];
    h[2] = 0.0;
    n = sqrt(h[0] * h[0] + h[1] * h[1]);
    if (!(n > 1e-9)) { h[0] = 1.0; h[1] = 0.0; n = 1.0; } /* straight up or down: along x */
    /* m + 1 even steps across the fan, the one at the centre (the probe's own ray) skipped */
    j = i < m / 2 ? i : i + 1;
    th = s->line_half * (2.0 * (double)j / (double)m - 1.0);
    for (k = 0; k < 3; k++) ray->dir[k] = cos(th) * probe->dir[k] + sin(th) * h[k] / n;
    n = sqrt(ray->dir[0] * ray->dir[0] + ray->dir[1] * ray->dir[1] + ray->dir[2] * ray->dir[2]);
    for (k = 0; k < 3; k++) ray->dir[k] /= n;
    /* the rangefinder's whole range, not the probe's edge */
    ray->range = s->cfg.max_range > 0.0 ? s->cfg.max_range : 2.0 * s->diag + 1.0;
    if (vp_simdev_ray(s->dev, ray->dir, ray->range, i, &r) != VP_OK) return r.status < 0 ? r.status : VP_EINVAL;
    s->raw = r.hit ? r.t : NAN;
    res->hit = r.too_close ? VP_PROBE_TOO_CLOSE : r.hit;
    res->dist = r.hit ? (r.t < 0 ? 0.0 : r.t) : 0.0;
    return 1;
}

int vp_sim_run(vp_sim_t *s, FILE *progress)
{
    vp_device_ops_t ops;
    ops.ctx = s;
    ops.move = dev_move;
    ops.probe = dev_probe;
    ops.touched = s->contact ? dev_touched : NULL;
    ops.rays = s->cfg.line_rays ? dev_rays : NULL;
    ops.move_path = NULL;
    ops.sight = NULL;
    return vp_session_run(s->pl, &ops, s->hooks, 0, progress, &s->run);
}

/* what the planner did since its counters were b (a re-scan's, a round's): into r's counts */
static void counts_since(const vp_planner_stats_t *st, const vp_planner_stats_t *b, vp_sim_round_t *r)
{
    r->probes = st->probes - b->probes;
    r->moves = st->moves - b->moves;
    r->kept = st->rescan_kept - b->rescan_kept;
    r->skipped = st->rescan_skipped - b->rescan_skipped;
    r->dropped = st->rescan_dropped - b->rescan_dropped;
    r->moved = st->rescan_moved - b->rescan_moved;
    r->unseen = st->rescan_unseen - b->rescan_unseen;
    r->normal = st->rescan_normal - b->rescan_normal;
    r->reproved = st->reproved - b->reproved;
    r->blocked = st->reprove_blocked - b->reprove_blocked;
}

/* each round's mesh as OUT.roundK.ply (--out): what a tracking session hands over per round */
static int round_mesh(const vp_mesh_t *m, const vp_sim_options_t *o, int k, FILE *progress)
{
    char path[VP_PATH_MAX], ext[32], err[256];
    int st;
    if (!o->out) return VP_OK;
    snprintf(ext, sizeof ext, ".round%d.ply", k);
    if ((st = vp_path_cat(path, sizeof path, o->out, ext, err, sizeof err)) != VP_OK) {
        if (progress) fprintf(progress, "sim: %s\n", err);
        return st;
    }
    if (vp_mkdirs_for(o->out) != 0) {
        if (progress) fprintf(progress, "sim: cannot create the folder of %s: %s\n", o->out, strerror(errno));
        return VP_EIO;
    }
    if ((st = vp_mesh_write_file(m, path, VP_MESH_PLY_BIN)) != VP_OK && progress)
        fprintf(progress, "sim: cannot write %s: %s\n", path, strerror(errno));
    return st;
}

/* Round k just ended (its counters since b, c0 collisions before it): its figures into r and its
 * mesh to OUT.roundK.ply. */
static int round_figures(vp_sim_t *s, const vp_sim_options_t *o, const vp_planner_stats_t *b, unsigned long c0,
                         double t0, int k, FILE *progress, vp_sim_round_t *r)
{
    vp_planner_stats_t st;
    vp_simdev_stats_t ds;
    vp_mesh_t m;
    vp_meshcheck_t mc;
    size_t i;
    int err;
    vp_planner_get_stats(s->pl, &st);
    vp_simdev_stats(s->dev, &ds);
    memset(r, 0, sizeof *r);
    r->t0 = t0;
    r->t1 = ds.time;
    counts_since(&st, b, r);
    r->collisions = ds.collisions - c0;
    r->status = s->run.status;
    r->hausdorff = -1.0;
    r->min_spacing = -1.0;
    vp_mesh_init(&m);
    if ((err = vp_session_mesh(s->pl, &m)) != VP_OK) { vp_mesh_free(&m); return err; }
    r->vertices = (unsigned)m.nv;
    if (vp_meshcheck_analyze(&m, &mc) == VP_OK) {
        r->closed = mc.closed_manifold;
        r->genus = mc.genus;
        r->components = mc.components;
        vp_meshcheck_free(&mc);
    }
    if (o->hausdorff > 0 && m.nt > 0) {
        vp_hausdorff_t h;
        if (s->motion ? vp_motion_hausdorff(&m, s->motion, ds.time, o->hausdorff, 7, &h) == VP_OK
                      : vp_hausdorff(&m, s->surf, o->hausdorff, 7, &h) == VP_OK)
            r->hausdorff = h.hausdorff;
    }
    {
        /* the closest two vertices: each one's nearest other (a kd-tree) */
        vp_kdtree_t *kt = NULL;
        if (m.nv >= 2 && vp_kdtree_build(m.xyz, m.nv, &kt) == VP_OK) {
            for (i = 0; i < m.nv; i++) {
                size_t idx[2];
                double d2[2];
                if (vp_kdtree_knn(kt, m.xyz + 3 * i, 2, idx, d2) == 2 && (r->min_spacing < 0 || sqrt(d2[1]) < r->min_spacing))
                    r->min_spacing = sqrt(d2[1]);
            }
            vp_kdtree_free(kt);
        }
    }
    err = round_mesh(&m, o, k, progress);
    vp_mesh_free(&m);
    return err;
}

int vp_sim_track(vp_sim_t *s, const vp_sim_options_t *o, int n, unsigned flags, int (*rescan_event)(void *ctx, int round),
                 void *ctx, FILE *progress)
{
    int k, st = VP_OK;
    vp_sim_round_t *r = calloc((size_t)n + 1, sizeof *r);
    vp_planner_stats_t zero;
    if (!r) return VP_ENOMEM;
    free(s->rounds);
    s->rounds = r;
    memset(&zero, 0, sizeof zero);
    st = round_figures(s, o, &zero, 0, 0.0, 0, progress, &r[0]);
    s->nrounds = 1;
    if (st != VP_OK) return st;
    for (k = 1; k <= n && s->run.status == VP_OK; k++) {
        vp_planner_stats_t b;
        vp_simdev_stats_t ds;
        vp_planner_get_stats(s->pl, &b);
        vp_simdev_stats(s->dev, &ds);
        if (rescan_event && (st = rescan_event(ctx, k)) != VP_OK) break;
        if ((st = vp_planner_rescan_with(s->pl, VP_RESCAN_HERE | flags)) != VP_OK) break;
        vp_sim_run(s, progress);
        st = round_figures(s, o, &b, ds.collisions, ds.time, k, progress, &r[k]);
        s->nrounds = k + 1;
        if (st != VP_OK) break;
    }
    return st;
}

int vp_sim_finish(vp_sim_t *s, const vp_sim_options_t *o, char *err, size_t errlen)
{
    int st = vp_session_mesh(s->pl, &s->mesh);
    if (st != VP_OK) { snprintf(err, errlen, "mesh: %s", vp_strerror(st)); return st; }
    if (vp_meshcheck_analyze(&s->mesh, &s->check) == VP_OK) s->have_check = 1;
    if (o->hausdorff > 0 && s->mesh.nt > 0 &&
        vp_hausdorff(&s->mesh, s->surf, o->hausdorff, 7, &s->haus) == VP_OK)
        s->have_haus = 1;
    if (s->motion && o->hausdorff > 0 && s->mesh.nt > 0) {
        vp_simdev_stats_t ds;
        vp_simdev_stats(s->dev, &ds);
        if (vp_motion_hausdorff(&s->mesh, s->motion, ds.time, o->hausdorff, 7, &s->haus_end) == VP_OK)
            s->have_haus_end = 1;
    }
    if (o->out) {
        char path[VP_PATH_MAX];
        if ((st = vp_sim_check_out(o, err, errlen)) != VP_OK) return st;
        if (vp_mkdirs_for(o->out) != 0) {
            snprintf(err, errlen, "cannot create the folder of %s: %s", o->out, strerror(errno));
            return VP_EIO;
        }
        vp_path_cat(path, sizeof path, o->out, ".ply", err, errlen);
        if ((st = vp_mesh_write_file(&s->mesh, path, VP_MESH_PLY_BIN)) != VP_OK) {
            snprintf(err, errlen, "cannot write %s: %s", path, strerror(errno));
            return st;
        }
        vp_path_cat(path, sizeof path, o->out, ".off", err, errlen);
        if ((st = vp_mesh_write_file(&s->mesh, path, VP_MESH_OFF)) != VP_OK) {
            snprintf(err, errlen, "cannot write %s: %s", path, strerror(errno));
            return st;
        }
        s->written = 1;
    }
    return VP_OK;
}

int vp_topology_differs(const vp_meshcheck_t *mc, const vp_surface_t *surf)
{
    int g = vp_surface_genus(surf);
    if (!mc->closed_manifold || g < 0) return 0;
    return mc->genus != g || mc->components != vp_surface_components(surf);
}

int vp_sim_wrong_topology(const vp_sim_t *s)
{
    return s->have_check && !s->motion && vp_topology_differs(&s->check, s->surf);
}

int vp_sim_exit(const vp_sim_t *s)
{
    vp_outcome_in_t in;
    vp_planner_stats_t st;
    vp_simdev_stats_t ds;
    vp_planner_get_stats(s->pl, &st);
    vp_simdev_stats(s->dev, &ds);
    in.run_status = s->run.status;
    in.paused = s->paused;
    in.collisions = ds.collisions;
    in.closed_manifold = s->have_check && s->check.closed_manifold;
    in.missing_components = st.missing_components;
    /* a re-scan keeps the old interior points: a part of the object now that the mesh does not
     * hold is missed (a new part the re-scan never met) */
    if (s->rescan && s->have_check && s->check.components < s->components)
        in.missing_components += (unsigned)(s->components - s->check.components);
    in.beyond_target = s->target > 0 && s->have_haus && s->haus.hausdorff > s->target;
    in.wrong_topology = vp_sim_wrong_topology(s);
    return vp_outcome(&in);
}

void vp_sim_report(const vp_sim_t *s, const vp_sim_options_t *o, FILE *f)
{
    int ex = vp_sim_exit(s), closed = s->have_check && s->check.closed_manifold;
    char genus[16];
    vp_planner_stats_t st;
    vp_simdev_stats_t ds;
    unsigned nv = (unsigned)s->mesh.nv;
    vp_planner_get_stats(s->pl, &st);
    vp_simdev_stats(s->dev, &ds);
    if (closed) snprintf(genus, sizeof genus, "%d", s->check.genus);
    else snprintf(genus, sizeof genus, "null");
    if (!o->quiet || !o->json) {
        fprintf(f, "mesh: %u vertices, %u facets; %s, %d component(s), genus %d, smallest angle %.1f deg\n",
                nv, (unsigned)s->mesh.nt,
                s->have_check && s->check.closed_manifold ? "closed 2-manifold" : "NOT a closed manifold",
                s->have_check ? s->check.components : -1, s->have_check ? s->check.genus : -1,
                s->have_check ? s->check.min_angle_deg : 0.0);
        fprintf(f, "probes: %llu (%.2f per vertex, %.0f%% hits), moves %llu, travel %.4g (along prev chains: %.4g), collisions %lu\n",
                (unsigned long long)st.probes, nv ? (double)st.probes / nv : 0.0,
                st.probes ? 100.0 * (double)st.hits / (double)st.probes : 0.0,
                (unsigned long long)st.moves, st.travel, st.travel_prev_chains, ds.collisions);
        fprintf(f, "largest ball %.6g (eps %.6g)", st.max_ball, s->cfg.eps);
        if (s->have_haus) fprintf(f, ", Hausdorff %.6g", s->haus.hausdorff);
        fprintf(f, "; planner %.3f s, total %.3f s, arena peak %zu bytes (%.0f per vertex)\n",
                s->run.planner_seconds, s->run.total_seconds, st.arena_peak,
                nv ? (double)st.arena_peak / nv : 0.0);
        if (o->out && s->written) fprintf(f, "wrote %s.ply and %s.off\n", o->out, o->out);
        if (s->target > 0 && s->have_haus)
        {
            fprintf(f, "accuracy: target %.6g, measured Hausdorff %.6g: %s (distance bound %.6g, floor %.6g, "
                    "eps %.6g)\n", s->target, s->haus.hausdorff, s->haus.hausdorff <= s->target ? "within" : "NOT within",
                    s->cfg.max_distance, s->cfg.min_size, s->cfg.eps);
            if (s->cfg.noise_tol > s->cfg.max_distance)
                fprintf(f, "accuracy: the hits are trusted to %.6g only (4 x the noise): the distance bound is "
                        "that, above the target's share\n", s->cfg.noise_tol);
        }
        if (o->contact || o->ndark)
            fprintf(f, "contact: %llu move(s) stopped by the contact switch, %llu proof(s) of free space withdrawn, "
                    "%llu miss(es) near a contact not trusted; dark patches read %lu probe(s) as misses\n",
                    (unsigned long long)st.contacts, (unsigned long long)st.revoked,
                    (unsigned long long)st.dark_misses, ds.dark_misses);
        if (s->cfg.clearance > 0)
            fprintf(f, "body: clearance %.6g; %llu Voronoi edges occluded from where they were probed; ",
                    s->cfg.clearance, (unsigned long long)st.occluded);
        if (s->cfg.clearance > 0 && s->cfg.min_feature > 0)
            fprintf(f, "tubes (min feature %.6g, margin %.6g): %llu moves inside Omega, %llu probes started "
                    "inside it, %llu of them past what occluded their line; %llu tubes surveyed first (%llu probes, "
                    "%llu found blocked)\n", s->cfg.min_feature, s->cfg.feature_margin,
                    (unsigned long long)st.tube_moves, (unsigned long long)(st.tube_starts + st.vantages),
                    (unsigned long long)st.vantages, (unsigned long long)st.surveys,
                    (unsigned long long)st.survey_probes, (unsigned long long)st.surveys_failed);
        else if (s->cfg.clearance > 0)
            fprintf(f, "the device stays outside Omega\n");
        if (s->cfg.clearance > 0) vp_bodyreport_aims(f, &st);
        if (s->cfg.flags & VP_PLAN_FAR_READS) vp_bodyreport_far(f, &st); /* vp_sim_open: only with a body */
        if (s->cfg.line_rays)
            fprintf(f, "line laser: %u more rays per probe over %.3g degrees: %llu rays, %llu hits, %llu of them "
                    "made samples\n", s->cfg.line_rays, o->line_deg, (unsigned long long)st.rays,
                    (unsigned long long)st.ray_hits, (unsigned long long)st.ray_samples);
        if (s->motion) {
            double vmax = vp_motion_speed_bound(s->motion, 0, ds.time);
            fprintf(f, "motion: %s; simulated time %.6g s (speed bound %.6g: surface points moved up to %.6g); "
                    "collisions with the moving object %lu", o->motion, ds.time, vmax, vmax * ds.time, ds.collisions);
            if (s->have_haus && s->have_haus_end)
                fprintf(f, "; Hausdorff at the start %.6g, at the end %.6g", s->haus.hausdorff, s->haus_end.hausdorff);
            fprintf(f, "\n");
        }
        if (s->rescan) {
            vp_sim_round_t d;
            counts_since(&st, &s->before, &d);
            fprintf(f, "rescan of %s: %llu probes, %llu moves (the session re-scanned took %llu probes); samples: %llu "
                    "kept, %llu not measured (their neighbours held), %llu removed (%llu moved: the point measured "
                    "took their place; %llu covered or out of reach of every line), %llu measured along their normal; "
                    "%llu route steps proven again (%llu blocked)\n", s->rescan_spec, (unsigned long long)d.probes,
                    (unsigned long long)d.moves, (unsigned long long)s->before.probes, (unsigned long long)d.kept,
                    (unsigned long long)d.skipped, (unsigned long long)d.dropped, (unsigned long long)d.moved,
                    (unsigned long long)d.unseen, (unsigned long long)d.normal, (unsigned long long)d.reproved,
                    (unsigned long long)d.blocked);
        }
        if (s->rescan && s->have_check && s->check.components < s->components)
            fprintf(f, "rescan: the object now has %d component(s), the mesh %d: a part the re-scan never met (it "
                    "keeps the old interior points): scan afresh\n", s->components, s->check.components);
        if (s->nrounds > 0) {
            int k;
            fprintf(f, "tracking: %d round(s) after the first scan (a re-scan each, from where the device stood)", s->nrounds - 1);
            if (o->out) fprintf(f, "; each round's mesh in %s.round0.ply .. %s.round%d.ply", o->out, o->out, s->nrounds - 1);
            fprintf(f, "\n");
            for (k = 0; k < s->nrounds; k++) {
                const vp_sim_round_t *r = &s->rounds[k];
                fprintf(f, "  round %d: t %.4g..%.4g s, %llu probes, %llu moves, samples kept %llu (not measured %llu) removed %llu (moved "
                        "%llu), steps proven again %llu (%llu blocked); %u vertices, %s, genus %d; collisions %lu; Hausdorff at its end %.6g; "
                        "closest vertices %.6g\n", k, r->t0, r->t1, (unsigned long long)r->probes, (unsigned long long)r->moves,
                        (unsigned long long)r->kept, (unsigned long long)r->skipped, (unsigned long long)r->dropped,
                        (unsigned long long)r->moved, (unsigned long long)r->reproved, (unsigned long long)r->blocked,
                        r->vertices, r->closed ? "closed" : "NOT closed", r->genus,
                        r->collisions, r->hausdorff, r->min_spacing);
            }
        }
        if (st.fins_cut)
            fprintf(f, "closing: %llu tet(s) of the inside cut off where it touched itself thinner than the manifold "
                    "floor (the tip of a fin or an acute fold; their facets' balls at most 4 times that floor)\n",
                    (unsigned long long)st.fins_cut);
        if (st.unproven || st.stalls)
            fprintf(f, "safety: %llu segments an inference proposed were not proven free (never travelled); "
                    "%llu sides could not be probed\n", (unsigned long long)st.unproven, (unsigned long long)st.stalls);
        fprintf(f, "result: %s (exit %d)%s\n", vp_outcome_name(ex), ex,
                ex == VP_EXIT_NOT_CLOSED ? ": the mesh is not closed around every component; certify names where" :
                ex == VP_EXIT_COLLISION ? ": a move touched the object" :
                ex == VP_EXIT_NOT_WITHIN_TARGET ? ": the mesh is farther from the object than the accuracy target" :
                ex == VP_EXIT_WRONG_TOPOLOGY ? ": the mesh is closed, but its genus or components are not the object's (a "
                                               "handle through a part thinner than the samples' spacing, or parts joined or split)" :
                ex == VP_EXIT_ERROR ? ": the scan stopped on an error; the mesh so far is written" : "");
    }
    if (o->json) {
        char touch[1280] = "";
        if (o->contact || o->ndark)
            snprintf(touch, sizeof touch, ",\"contacts\":%llu,\"revoked\":%llu,\"dark_misses\":%llu,\"dark_probes\":%lu",
                     (unsigned long long)st.contacts, (unsigned long long)st.revoked,
                     (unsigned long long)st.dark_misses, ds.dark_misses);
        if (s->cfg.line_rays)
            snprintf(touch + strlen(touch), sizeof touch - strlen(touch),
                     ",\"line_rays\":%u,\"line_deg\":%.6g,\"rays\":%llu,\"ray_hits\":%llu,\"ray_samples\":%llu",
                     s->cfg.line_rays, o->line_deg, (unsigned long long)st.rays, (unsigned long long)st.ray_hits,
                     (unsigned long long)st.ray_samples);
        if (s->cfg.clearance > 0)
            snprintf(touch + strlen(touch), sizeof touch - strlen(touch),
                     ",\"clearance\":%.6g,\"occluded\":%llu,\"min_feature\":%.6g,\"feature_margin\":%.6g,"
                     "\"tube_moves\":%llu,\"tube_starts\":%llu,\"vantages\":%llu,\"surveys\":%llu,"
                     "\"survey_probes\":%llu,\"surveys_failed\":%llu", s->cfg.clearance,
                     (unsigned long long)st.occluded, s->cfg.min_feature, s->cfg.feature_margin,
                     (unsigned long long)st.tube_moves, (unsigned long long)st.tube_starts,
                     (unsigned long long)st.vantages, (unsigned long long)st.surveys,
                     (unsigned long long)st.survey_probes, (unsigned long long)st.surveys_failed);
        if (s->cfg.clearance > 0) vp_bodyreport_aims_json(touch, sizeof touch, &st);
        if (s->cfg.flags & VP_PLAN_FAR_READS) /* vp_sim_open: only with a body */
            vp_bodyreport_far_json(touch, sizeof touch, &st);
        fprintf(f, "{\"surface\":\"%s\",\"eps\":%.9g,\"status\":\"%s\",\"exit\":%d,\"planner_status\":\"%s\","
                "\"vertices\":%u,\"facets\":%u,"
                "\"probes\":%llu,\"hits\":%llu,\"misses\":%llu,\"too_close\":%llu,\"reprobes\":%llu,\"moves\":%llu,"
                "\"travel\":%.6g,\"travel_prev_chains\":%.6g,\"collisions\":%lu,"
                "\"closed_manifold\":%s,\"components\":%d,\"genus\":%s,\"max_ball_radius\":%.9g,"
                "\"hausdorff\":%.6g,\"min_angle_deg\":%.3f,\"planner_seconds\":%.4f,"
                "\"total_seconds\":%.4f,\"arena_bytes_peak\":%zu,\"insertions\":%llu,\"routes\":%llu,"
                "\"astar_expansions\":%llu,\"astar_fallbacks\":%llu,\"shortcut_probes\":%llu,"
                "\"escalations\":%llu,\"reseeds\":%llu,\"missing_components\":%u,\"unproven\":%llu,"
                "\"stalls\":%llu,\"fins_cut\":%llu,\"accuracy_target\":%.6g,\"size_rel\":%.6g,\"min_size\":%.6g,\"max_distance\":%.6g%s",
                s->rescan ? s->rescan_spec : o->surface, s->cfg.eps, vp_outcome_name(ex), ex, vp_strerror(s->run.status), nv, (unsigned)s->mesh.nt,
                (unsigned long long)st.probes, (unsigned long long)st.hits,
                (unsigned long long)st.misses, (unsigned long long)st.too_close, (unsigned long long)st.reprobes,
                (unsigned long long)st.moves, st.travel, st.travel_prev_chains, ds.collisions,
                s->have_check && s->check.closed_manifold ? "true" : "false",
                s->have_check ? s->check.components : -1, genus,
                st.max_ball, s->have_haus ? s->haus.hausdorff : -1.0,
                s->have_check ? s->check.min_angle_deg : 0.0, s->run.planner_seconds,
                s->run.total_seconds, st.arena_peak, (unsigned long long)st.insertions,
                (unsigned long long)st.routes, (unsigned long long)st.astar_expansions,
                (unsigned long long)st.astar_fallbacks, (unsigned long long)st.shortcut_probes,
                (unsigned long long)st.escalations, (unsigned long long)st.reseeds, st.missing_components,
                (unsigned long long)st.unproven, (unsigned long long)st.stalls, (unsigned long long)st.fins_cut, s->target, s->cfg.size_rel,
                s->cfg.min_size, s->cfg.max_distance, touch);
        if (s->rescan) {
            vp_sim_round_t d;
            counts_since(&st, &s->before, &d);
            fprintf(f, ",\"rescan\":{\"surface\":\"%s\",\"probes\":%llu,\"moves\":%llu,\"old_probes\":%llu,"
                    "\"kept\":%llu,\"skipped\":%llu,\"dropped\":%llu,\"moved\":%llu,\"unseen\":%llu,\"normal\":%llu,"
                    "\"reproved\":%llu,\"blocked\":%llu}", s->rescan_spec, (unsigned long long)d.probes,
                    (unsigned long long)d.moves, (unsigned long long)s->before.probes, (unsigned long long)d.kept,
                    (unsigned long long)d.skipped, (unsigned long long)d.dropped, (unsigned long long)d.moved,
                    (unsigned long long)d.unseen, (unsigned long long)d.normal, (unsigned long long)d.reproved,
                    (unsigned long long)d.blocked);
        }
        if (s->nrounds > 0) {
            int k;
            fprintf(f, ",\"rounds\":[");
            for (k = 0; k < s->nrounds; k++) {
                const vp_sim_round_t *r = &s->rounds[k];
                fprintf(f, "%s{\"t0\":%.6g,\"t1\":%.6g,\"probes\":%llu,\"moves\":%llu,\"kept\":%llu,\"skipped\":%llu,"
                        "\"dropped\":%llu,\"moved\":%llu,\"reproved\":%llu,\"blocked\":%llu,\"collisions\":%lu,\"status\":\"%s\",\"closed\":%s,"
                        "\"genus\":%d,\"components\":%d,\"vertices\":%u,\"hausdorff\":%.6g,\"min_spacing\":%.6g}",
                        k ? "," : "", r->t0, r->t1, (unsigned long long)r->probes, (unsigned long long)r->moves,
                        (unsigned long long)r->kept, (unsigned long long)r->skipped, (unsigned long long)r->dropped,
                        (unsigned long long)r->moved, (unsigned long long)r->reproved, (unsigned long long)r->blocked,
                        r->collisions, vp_strerror(r->status), r->closed ? "true" : "false",
                        r->genus, r->components, r->vertices, r->hausdorff, r->min_spacing);
            }
            fprintf(f, "]");
        }
        if (s->motion)
            fprintf(f, ",\"motion\":\"%s\",\"sim_time\":%.6g,\"speed_bound\":%.6g,\"speed\":%.6g,\"accel\":%.6g,"
                    "\"probe_time\":%.6g,\"hausdorff_start\":%.6g,\"hausdorff_end\":%.6g",
                    o->motion, ds.time, vp_motion_speed_bound(s->motion, 0, ds.time), o->speed, o->accel, o->probe_time,
                    s->have_haus ? s->haus.hausdorff : -1.0, s->have_haus_end ? s->haus_end.hausdorff : -1.0);
        fprintf(f, "}\n");
    }
}

void vp_sim_close(vp_sim_t *s)
{
    if (s->have_check) vp_meshcheck_free(&s->check);
    vp_mesh_free(&s->mesh);
    free(s->rounds);
    if (s->dev) vp_simdev_destroy(s->dev);
    if (s->motion) vp_motion_close(s->motion);
    if (s->surf) vp_surface_close(s->surf);
    free(s->pl);
    free(s->arena);
    memset(s, 0, sizeof *s);
}
