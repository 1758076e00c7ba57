/* vp_scan — see vp_scan.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_cam.h"
#include "vp_rtclock.h"
#include "vp_rng.h"
#include "vp_scan.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_vec3.h"

volatile sig_atomic_t vp_scan_stop;

static void vp_scan_on_signal(int sig)
{
    (void)sig;
    vp_scan_stop = 1;
}

void vp_scan_catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = vp_scan_on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;    /* a second Ctrl-C ends the process at once */
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

/* ---------- the dry run's object ---------- */

int vp_scan_dry_surface(const vp_board_t *b, const char *spec, char *out, size_t outlen, char *err, size_t errlen)
{
    const char *s = spec && *spec ? spec : b->sim_surface[0] ? b->sim_surface : "ellipsoid";
    vp_surface_t *surf;
    double lo[3], hi[3], room = HUGE_VAL, margin, scale, off[3];
    int k, st, n;
    if (strchr(s, '*') || strchr(s, '@') || strchr(s, '+')) {
        if (strlen(s) >= outlen) { snprintf(err, errlen, "object spec too long"); return VP_EINVAL; }
        strcpy(out, s);
        return VP_OK;
    }
    /* a bare object: centred on the interior point, 60% of the room Omega leaves around it */
    st = vp_surface_open(s, &surf, err, errlen);
    if (st != VP_OK) return st;
    vp_surface_bbox(surf, lo, hi);
    vp_surface_close(surf);
    margin = b->clearance > b->min_range ? b->clearance : b->min_range;
    for (k = 0; k < 3; k++) {
        double h, e = 0.5 * (hi[k] - lo[k]);
        if (b->omega_kind == VP_OMEGA_BOX) {
            h = b->interior[k] - b->omega_lo[k];
            if (b->omega_hi[k] - b->interior[k] < h) h = b->omega_hi[k] - b->interior[k];
        } else {
            double dc = 0;
            int q;
            for (q = 0; q < 3; q++) dc += (b->interior[q] - b->omega_center[q]) * (b->interior[q] - b->omega_center[q]);
            h = b->omega_radius - sqrt(dc);
        }
        h -= margin;
        if (e > 0 && h / e < room) room = h / e;
    }
    if (!(room > 0) || !isfinite(room)) {
        snprintf(err, errlen, "%s: Omega leaves no room for an object around the interior point", b->path);
        return VP_EINVAL;
    }
    scale = 0.6 * room;
    for (k = 0; k < 3; k++) off[k] = b->interior[k] - scale * 0.5 * (lo[k] + hi[k]);
    n = snprintf(out, outlen, "%s*%.6g@%.6g,%.6g,%.6g", s, scale, off[0], off[1], off[2]);
    if (n < 0 || (size_t)n >= outlen) { snprintf(err, errlen, "object spec too long"); return VP_EINVAL; }
    return VP_OK;
}

/* ---------- opening, homing ---------- */

static const char *const vp_axis_name[VP_KIN_JOINTS] = { "x", "y", "z", "pan", "tilt" };

typedef struct vp_scan_ev { int kind, axis; const char *what; } vp_scan_ev_t;
static vp_scan_ev_t vp_scan_last_ev;

static void vp_scan_event(void *ctx, const vp_step_event_t *ev)
{
    (void)ctx;
    /* retimes are counted in the stepper's statistics (vp_scan_step_report) */
    if (ev->kind == VP_STEP_EV_HOMED || ev->kind == VP_STEP_EV_CLEARED || ev->kind == VP_STEP_EV_RETIME) return;
    vp_scan_last_ev.kind = ev->kind;
    vp_scan_last_ev.axis = ev->axis;
    vp_scan_last_ev.what = ev->what;
}

int vp_scan_open(vp_scan_dev_t *d, const vp_board_t *b, int dry, const char *surface, double target_x,
                 unsigned long long seed, char *err, size_t errlen)
{
    int st;
    memset(d, 0, sizeof *d);
    memset(&vp_scan_last_ev, 0, sizeof vp_scan_last_ev);
    d->board = *b;
    d->dry = dry;
    d->raw = NAN;
    d->seed = seed ? seed : (unsigned long long)b->sim_seed;
    d->head_tol = b->head_margin > VP_SCAN_HEAD_TOL ? b->head_margin : VP_SCAN_HEAD_TOL;
    if (dry) {
        vp_dryrun_options_t o;
        memset(&o, 0, sizeof o);
        o.surface = surface ? surface : "sphere";   /* a flat target needs no object */
        o.flat_target = surface == NULL;
        o.target_x = target_x;
        o.seed = d->seed;
        st = vp_dryrun_open(b, &o, &d->dr, err, errlen);
        if (st != VP_OK) return st;
        d->m = vp_dryrun_machine(d->dr);
    } else {
        vp_gpiod_config_t gc;
        vp_cam_config_t cc;
        vp_cam_t cam;
        vp_kin_config_t kc;
        vp_step_config_t sc;
        vp_machine_config_t mc;
        vp_io_t io;
        char e1[300] = "", e2[300] = "";
        int sg, sv;
        if (b->io != VP_BOARD_IO_GPIOD) {
            snprintf(err, errlen, "board '%s' (%s) has io = sim: it drives no hardware; use --dry-run", b->name, b->path);
            return VP_ENODEV;
        }
        vp_board_gpiod_config(b, &gc);
        sg = vp_gpiod_open(&gc, &d->gpio, e1, sizeof e1);
        cc = b->camera;
        cc.width = b->cam_model.width;
        cc.height = b->cam_model.height;
        memset(&cam, 0, sizeof cam);
        sv = vp_cam_open(&cc, &cam, e2, sizeof e2);
        if (sg != VP_OK || sv != VP_OK) {
            snprintf(err, errlen, "the hardware of board '%s' (%s) is not available:%s%s%s%s\n"
                     "  (--dry-run runs the board on host-sim instead)", b->name, b->path,
                     sg != VP_OK ? "\n  GPIO: " : "", sg != VP_OK ? e1 : "", sv != VP_OK ? "\n  camera: " : "",
                     sv != VP_OK ? e2 : "");
            if (sv == VP_OK && cam.close) cam.close(cam.ctx);
            if (d->gpio) vp_gpiod_close(d->gpio);
            d->gpio = NULL;
            return sg != VP_OK ? sg : sv;
        }
        vp_board_kin_config(b, &kc);
        vp_board_step_config(b, &sc);
        vp_board_machine_config(b, &mc);
        mc.diff_len = 2 * (size_t)b->cam_model.width * (size_t)b->cam_model.height;
        d->hw_frame = mc.diff_buf = malloc(mc.diff_len);
        if (!mc.diff_buf) {
            if (cam.close) cam.close(cam.ctx);
            vp_gpiod_close(d->gpio);
            d->gpio = NULL;
            return VP_ENOMEM;
        }
        io = vp_gpiod_io(d->gpio);
        st = vp_machine_init(&d->hw, &kc, &sc, &io, &cam, &b->tri, &mc);
        if (st != VP_OK) {
            snprintf(err, errlen, "%s: the machine configuration is refused", b->path);
            if (cam.close) cam.close(cam.ctx);
            vp_gpiod_close(d->gpio);
            d->gpio = NULL;
            return st;
        }
        d->hw_open = 1;
        d->m = &d->hw;
    }
    d->m->step.cfg.event = vp_scan_event;
    d->m->step.cfg.event_ctx = d;
    return VP_OK;
}

int vp_scan_depth_beyond(const vp_surface_t *surf, const double o[3], const double dir[3], double t0, double t1,
                         double tol)
{
    double p[3];
    long n, i;
    int k;
    if (!(tol > 0)) return 1;                 /* nothing is within no tolerance: say deep */
    if (!(t1 > t0)) t1 = t0;
    /* n equal parts no longer than tol / 4, both ends sampled: every point within tol / 8 */
    n = (long)ceil((t1 - t0) / (0.25 * tol));
    for (i = 0; i <= n; i++) {
        double s = n > 0 ? t0 + (t1 - t0) * (double)i / (double)n : t0;
        for (k = 0; k < 3; k++) p[k] = o[k] + s * dir[k];
        if (vp_surface_inside(surf, p) && vp_surface_distance(surf, p) > 0.875 * tol) return 1;
    }
    return 0;
}

/* the point dist along o + s dir within tol of the surface */
static int vp_scan_near_surface(const vp_surface_t *surf, const double o[3], const double dir[3], double dist, double tol)
{
    double q[3];
    int k;
    for (k = 0; k < 3; k++) q[k] = o[k] + dist * dir[k];
    return vp_surface_distance(surf, q) <= tol;
}

vp_hit_judged_t vp_scan_judge_hit(const vp_surface_t *surf, const double o[3], const double dir[3], double range,
                                  double dist, double tol, double *err)
{
    double t;
    *err = 0;
    /* the crossing is looked for up to tol past the range: a hit at the range's end whose
     * surface lies just beyond it is a measurement */
    if (!vp_surface_ray(surf, o, dir, range + tol, &t))
        /* no crossing along the ray: a beam grazing a limb reads it within tol (a measurement of
         * the surface beside the ray), anything farther is a false hit */
        return vp_scan_near_surface(surf, o, dir, dist, tol) ? VP_HIT_GRAZING : VP_HIT_FALSE;
    if (dist - t > tol)
        /* past the crossing: a thin edge the ray clips, its free part nowhere deeper inside than
         * tol, is a beam that passed beside the edge within the machine's aim; otherwise the
         * planner would take space inside the object for free */
        return vp_scan_depth_beyond(surf, o, dir, t, dist, tol) ? (*err = dist - t, VP_HIT_PAST) : VP_HIT_GRAZING;
    if (t - dist > tol)
        /* before the crossing: the beam, as wide as its spot, met an edge or a limb beside the
         * ray (its free part ends short of the crossing); a point within tol of the surface
         * measures it, anything else is a sample off the surface */
        return vp_scan_near_surface(surf, o, dir, dist, tol) ? VP_HIT_GRAZING : VP_HIT_FALSE;
    *err = fabs(dist - t);
    return VP_HIT_TRUE;
}

void vp_scan_unreadable_text(const vp_scan_dev_t *d, char *buf, size_t n)
{
    snprintf(buf, n, "%lu off the laser line, %lu blobs too big for a spot, %lu with several spots, %lu below the "
             "model's span", d->unread_why[0], d->unread_why[1], d->unread_why[2], d->unread_why[3]);
    if (d->unread_why[4] && strlen(buf) + 1 < n)
        snprintf(buf + strlen(buf), n - strlen(buf), ", %lu not the laser's spot (light there in the laser-off "
                 "frame, or not again there in a second laser-on frame)", d->unread_why[4]);
    if (d->unread_why[5] && strlen(buf) + 1 < n)
        snprintf(buf + strlen(buf), n - strlen(buf), ", %lu with no spot where the backdrop would show one (hidden "
                 "from the camera, or on a surface too dark)", d->unread_why[5]);
}

void vp_scan_step_report(const vp_scan_dev_t *d, char *buf, size_t n, double value[4])
{
    const vp_step_stats_t *st;
    size_t len;
    int i;
    value[0] = value[1] = value[2] = value[3] = 0;
    if (!d->m) { snprintf(buf, n, "step timing: no machine"); return; }
    st = &d->m->step.st;
    value[0] = (double)st->retimed;
    value[1] = (double)st->late_faults;
    value[2] = st->late_max_ns * 1e-3;
    value[3] = (double)st->limited;
    snprintf(buf, n, "step timing: %llu retimes, %llu late faults (max_late_us %g, on_late %s), worst %.1f us late; "
             "steps by lateness <1,2,4..1024,more us:", (unsigned long long)st->retimed,
             (unsigned long long)st->late_faults, d->board.max_late_us, d->board.late_fault ? "fault" : "reenter",
             st->late_max_ns * 1e-3);
    for (i = 0; i < VP_STEP_LATE_BUCKETS; i++) {
        len = strlen(buf);
        if (len + 1 >= n) break;
        snprintf(buf + len, n - len, "%s%llu", i ? "," : " ", (unsigned long long)st->late_hist[i]);
    }
}

void vp_scan_fault_text(const vp_scan_dev_t *d, char *buf, size_t n)
{
    const vp_scan_ev_t *e = &vp_scan_last_ev;
    const char *ax = e->axis >= 0 && e->axis < VP_KIN_JOINTS ? vp_axis_name[e->axis] : "?";
    int st = d->fault;
    switch (d->m ? d->m->step.fault : 0) {
    case VP_STEP_FAULT_ESTOP:
        snprintf(buf, n, "e-stop pressed: pulses stopped, drivers off");
        return;
    case VP_STEP_FAULT_LIMIT:
        snprintf(buf, n, "limit switch of axis %s closed during a move (a hard limit): drivers off", ax);
        return;
    case VP_STEP_FAULT_HOME:
        snprintf(buf, n, "homing axis %s failed: %s", ax, e->what ? e->what : "?");
        return;
    case VP_STEP_FAULT_LATE:
        snprintf(buf, n, "a step came %.0f us late (max_late_us %g, on_late = fault): pulses stopped, drivers off; "
                 "homing needed", d->m->step.st.late_max_ns * 1e-3, d->board.max_late_us);
        return;
    case VP_STEP_FAULT_CONTACT:
        snprintf(buf, n, "the contact switch stayed closed after the head backed off a touch (a stuck switch or a "
                 "broken wire): drivers off; check the probe, then home");
        return;
    default: break;
    }
    if (st == VP_EABORT && d->m && d->m->host_touched)
        snprintf(buf, n, "the contact switch closed %.1f mm into the move: something stands where free space was "
                 "assumed; the head backed off to where the move began (clear it, then resume)", d->m->host_touch_at);
    else if (st == VP_ESTATE && d->m && d->m->touched)
        snprintf(buf, n, "after a touch the next move must back off it, not go further in (refused, nothing moved)");
    else if (st == VP_ERANGE) snprintf(buf, n, "the command is outside the machine's travel (refused, nothing moved)");
    else if (st == VP_ETIMEOUT) snprintf(buf, n, "camera: no frame in time");
    else if (st == VP_EIO) snprintf(buf, n, "I/O error (GPIO or camera)%s%s", d->m && d->m->cam.error ? ": " : "",
                                    d->m && d->m->cam.error ? d->m->cam.error(d->m->cam.ctx) : "");
    else snprintf(buf, n, "%s", vp_strerror(st));
}

/* A machine fault (st) while d was homing or moving on its own: kept in d->fault and said in
 * err as "WHAT: the fault". Returns st. */
static int vp_scan_failed(vp_scan_dev_t *d, int st, const char *what, char *err, size_t errlen)
{
    char t[200];
    d->fault = st;
    vp_scan_fault_text(d, t, sizeof t);
    snprintf(err, errlen, "%s: %s", what, t);
    return st;
}

int vp_scan_home(vp_scan_dev_t *d, char *err, size_t errlen)
{
    vp_machine_t *m = d->m;
    double j[VP_KIN_JOINTS];
    int a, st = vp_machine_home(m);
    if (st != VP_OK) return vp_scan_failed(d, st, "homing failed", err, errlen);
    /* axes without a switch: take up the backlash in a fixed direction (down unless that leaves
     * travel), so the carriage sits the same way after every homing */
    for (a = 0; a < VP_KIN_JOINTS; a++) {
        const vp_step_axis_t *ax = &m->step.cfg.axis[a];
        double dz = 2 * ax->backlash + 2 / ax->steps_per_unit;
        if (ax->home_dir || ax->backlash <= 0) continue;
        vp_step_position(&m->step, j);
        j[a] -= j[a] - dz >= ax->travel_min ? dz : -dz;
        st = vp_step_move(&m->step, j);
        if (st == VP_OK) {
            vp_step_position(&m->step, j);
            j[a] = ax->home_pos;
            st = vp_step_move(&m->step, j);
        }
        vp_step_position(&m->step, m->j);
        if (st != VP_OK) {
            char what[80];
            snprintf(what, sizeof what, "taking up the backlash of axis %s failed", vp_axis_name[a]);
            return vp_scan_failed(d, st, what, err, errlen);
        }
    }
    return VP_OK;
}


double vp_scan_seconds(const vp_scan_dev_t *d)
{
    if (d->dry) return (double)d->dr->rec.now * 1e-9;
    return (double)vp_rt_now() * 1e-9;
}

void vp_scan_close(vp_scan_dev_t *d)
{
    if (d->dr) vp_dryrun_close(d->dr);
    if (d->hw_open) vp_machine_close(&d->hw);
    if (d->gpio) vp_gpiod_close(d->gpio);
    free(d->hw_frame);
    d->hw_frame = NULL;
    d->dr = NULL;
    d->gpio = NULL;
    d->hw_open = 0;
    d->m = NULL;
}

/* ---------- the head's body along a motion (dry run) ---------- */

/* The joint path j0 -> way[0] -> ... -> way[n-1] (linear joint pieces) against the object:
 * one motion, counted once for each part that came within head_tol of it. The joints are the
 * commanded ones: the true pose differs by at most the board's head_margin <= head_tol. */
static void vp_scan_head_path(vp_scan_dev_t *d, const double j0[VP_KIN_JOINTS], const double (*way)[VP_KIN_JOINTS], int n)
{
    vp_head_object_t obj;
    int any[VP_HEAD_MAX_PARTS], hit[VP_HEAD_MAX_PARTS], w, i, nany = 0;
    if (!d->dry || n < 1) return;
    obj = vp_dryrun_object(d->dr);
    memset(any, 0, sizeof any);
    for (w = 0; w < n; w++) {
        if (vp_head_sweep(&d->board.head, &obj, w ? way[w - 1] : j0, way[w], d->head_tol, hit, &d->head_evals) < 0)
            continue;
        for (i = 0; i < VP_HEAD_MAX_PARTS; i++) any[i] |= hit[i];
    }
    d->head_motions++;
    for (i = 0; i < VP_HEAD_MAX_PARTS; i++) {
        d->head_part[i] += (unsigned long)any[i];
        if (!(d->reach_out && vp_board_part_is_ball(&d->board, i)))
            nany += any[i];
    }
    if (nany) d->head_hits++;
}

/* Backing off a touch: 1 while the switch's zone is not yet clear at pose j: the laser origin
 * inside the object or within 2 head_tol of it (a stylus), a sensed part within 2 head_tol (a
 * mount's switch). */
static int vp_scan_in_touch(vp_scan_dev_t *d, const double j[VP_KIN_JOINTS])
{
    double o[3], dir[3], gap;
    if (d->board.contact_mount) {
        vp_head_object_t obj = vp_dryrun_object(d->dr);
        return vp_head_near(&d->board.head, &obj, d->dr->mount_mask, j, 2.0 * d->head_tol, &gap, &d->head_evals) != 0;
    }
    vp_kin_forward(&d->m->kin, j, o, dir);
    return vp_surface_inside(d->dr->surf, o) || vp_surface_distance(d->dr->surf, o) < 2.0 * d->head_tol;
}

/* A MOVE's joint path j0 -> way[0..n-1] (vp_scan_move_check has judged the laser origin's). One
 * the contact switch stopped is swept only while the origin, moving along cmd's line, is less than
 * d->touch_cut along it (the joints interpolated within the piece where it gets there): before
 * that a part within head_tol of the object met it before the stylus did, a crash the switch
 * could not stop; past it the head moves on by the stylus's give, checked against contact_stop.
 * The MOVE that backs off such a touch is swept from where the switch's zone is clear again
 * (vp_scan_in_touch, in steps of head_tol / 4 of the origin's way): the same give, retraced. */
static void vp_scan_head_move(vp_scan_dev_t *d, const vp_cmd_t *cmd, const double j0[VP_KIN_JOINTS],
                              const double (*way)[VP_KIN_JOINTS], int n)
{
    double cut[VP_MACHINE_MAX_WAY][VP_KIN_JOINTS], u[3], o[3], dir[3], s0 = 0.0, s1, len = vp_dist3(cmd->from, cmd->to);
    int w, k, a, m = 0;
    if (d->touching && d->board.contact_mount) {
        /* the mount's switch looked at every part at every step up to the touch (vp_dryrun), and
         * vp_scan_move_check bounds how far they went on */
        d->head_motions++;
        return;
    }
    if (d->backing && n >= 1 && n <= VP_MACHINE_MAX_WAY) {
        double from[VP_KIN_JOINTS];
        memcpy(from, j0, sizeof from);
        for (w = 0; w < n; w++) {
            double oa[3], ob[3], j[VP_KIN_JOINTS];
            long q, nq;
            vp_kin_forward(&d->m->kin, from, oa, dir);
            vp_kin_forward(&d->m->kin, way[w], ob, dir);
            nq = 1 + (long)(vp_dist3(oa, ob) / (0.25 * d->head_tol));
            for (q = 0; q <= nq; q++) {
                for (a = 0; a < VP_KIN_JOINTS; a++) j[a] = from[a] + (way[w][a] - from[a]) * (double)q / (double)nq;
                if (!vp_scan_in_touch(d, j)) break;
            }
            if (q <= nq) {
                /* clear from j on: the rest of this piece and the pieces after it */
                memcpy(cut[m++], way[w], sizeof cut[0]);
                for (k = w + 1; k < n; k++) memcpy(cut[m++], way[k], sizeof cut[0]);
                vp_scan_head_path(d, j, (const double (*)[VP_KIN_JOINTS])cut, m);
                return;
            }
            memcpy(from, way[w], sizeof from);
        }
        d->head_motions++;   /* never clear of the touch: the way back alone */
        return;
    }
    if (!d->touching || n < 1 || n > VP_MACHINE_MAX_WAY || !(len > 0.0)) { vp_scan_head_path(d, j0, way, n); return; }
    for (k = 0; k < 3; k++) u[k] = (cmd->to[k] - cmd->from[k]) / len;
    for (w = 0; w < n; w++) {
        vp_kin_forward(&d->m->kin, way[w], o, dir);
        s1 = 0.0;
        for (k = 0; k < 3; k++) s1 += (o[k] - cmd->from[k]) * u[k];
        if (s1 < d->touch_cut) { memcpy(cut[m++], way[w], sizeof cut[0]); s0 = s1; continue; }
        if (s1 > s0) {
            const double *p = w ? way[w - 1] : j0;
            double f = (d->touch_cut - s0) / (s1 - s0);
            for (a = 0; a < VP_KIN_JOINTS; a++) cut[m][a] = p[a] + f * (way[w][a] - p[a]);
            m++;
        }
        break;
    }
    if (m > 0) vp_scan_head_path(d, j0, (const double (*)[VP_KIN_JOINTS])cut, m);
}

/* A move the contact switch stopped `at` along it (unit direction u, length len; the laser
 * origin judged from a, s0 along it; a crossing of the surface counts up to ts_max from a): where
 * the head's sweep stops (touch_cut: 2 head_tol before the origin met the surface), how far past
 * it the switch closed (touch_lag), and how far the head went on: the origin past the surface with
 * its overtravel, or for a mount's switch the most a sensed part went on from where it closed to
 * joints rest (NULL: the carriages now). Counted as through, and 1 returned, when that is deeper
 * than contact_stop. */
static int vp_scan_touch_depth(vp_scan_dev_t *d, const double a[3], const double u[3], double s0, double len, double at,
                               double overtravel, double ts_max, const double *rest)
{
    double ts, depth = 0.0, past;
    d->contacts++;
    d->touch_lag = 0.0;
    d->touch_cut = at - 2.0 * d->head_tol;
    if (vp_surface_ray(d->dr->surf, a, u, len - s0, &ts) && ts < ts_max) {
        depth = s0 + at - (s0 + ts) + overtravel;
        d->touch_lag = at - ts > 0.0 ? at - ts : 0.0;
        d->touch_cut = s0 + ts - 2.0 * d->head_tol;
    }
    if (d->board.contact_mount && (past = vp_dryrun_mount_past(d->dr, rest)) > depth) depth = past;
    if (depth > d->touch_depth_max) d->touch_depth_max = depth;
    if (depth > d->board.contact_stop + 1e-6) { d->through++; return 1; }
    return 0;
}

/* A dry run's check of the host's own move from joints j0 (laser origin o0) towards p: the
 * origin's segment and the head along the joints' line, as for a MOVE; one the contact switch
 * stopped (vp_machine_goto backed off at once) only up to the touch, the head swept up to 1 mm
 * before the origin met the surface as for a touched MOVE (the way back retraces that). */
static void vp_scan_goto_check(vp_scan_dev_t *d, const double o0[3], const double j0[VP_KIN_JOINTS], const double p[3])
{
    vp_machine_t *m = d->m;
    vp_cmd_t cmd;
    double jt[VP_KIN_JOINTS], u[3], len = vp_dist3(o0, p), end[3];
    int k;
    if (vp_kin_move(&m->kin, j0, p, jt) != VP_OK) return;
    memset(&cmd, 0, sizeof cmd);
    cmd.kind = VP_CMD_MOVE;
    memcpy(cmd.from, o0, sizeof cmd.from);
    memcpy(cmd.to, p, sizeof cmd.to);
    if (!m->host_touched) {
        /* as far as it went (all the way, unless a fault stopped it) */
        double o1[3], dir[3];
        vp_machine_beam(m, o1, dir);
        if (vp_surface_segment_collides(d->dr->surf, o0, o1, 0)) d->through++;
        vp_scan_head_path(d, j0, (const double (*)[VP_KIN_JOINTS])m->j, 1);
        return;
    }
    for (k = 0; k < 3; k++) u[k] = len > 0.0 ? (p[k] - o0[k]) / len : 0.0;
    vp_scan_touch_depth(d, o0, u, 0.0, len, m->host_touch_at, m->host_overtravel, m->host_touch_at + d->head_tol,
                        m->host_rest);
    d->touch_lag = 0.0;   /* it backed off already */
    for (k = 0; k < 3; k++) end[k] = o0[k] + (d->touch_cut > 0.0 ? d->touch_cut : 0.0) * u[k];
    if (d->touch_cut > 0.0 && vp_surface_segment_collides(d->dr->surf, o0, end, 0)) d->through++;
    d->touching = 1;
    d->backing = 0;
    vp_scan_head_move(d, &cmd, j0, (const double (*)[VP_KIN_JOINTS])&jt, 1);
    d->touching = 0;
}

int vp_scan_goto(vp_scan_dev_t *d, const double p[3], char *err, size_t errlen)
{
    double o0[3], dir[3], j0[VP_KIN_JOINTS];
    int st;
    vp_machine_beam(d->m, o0, dir);
    memcpy(j0, d->m->j, sizeof j0);
    st = vp_machine_goto(d->m, p);
    if (d->dry) vp_scan_goto_check(d, o0, j0, p);
    if (st != VP_OK) {
        char what[100];
        snprintf(what, sizeof what, "moving to %.6g %.6g %.6g", p[0], p[1], p[2]);
        return vp_scan_failed(d, st, what, err, errlen);
    }
    return st;
}

void vp_scan_head_text(const vp_scan_dev_t *d, char *buf, size_t n)
{
    int i;
    size_t len;
    buf[0] = 0;
    for (i = 0; i < d->board.head.nparts; i++) {
        len = strlen(buf);
        if (len + 1 >= n) break;
        snprintf(buf + len, n - len, "%s%s %lu", i ? ", " : "", d->board.head.part[i].name, d->head_part[i]);
    }
}

/* ---------- executing the planner's commands ---------- */

static void vp_scan_trip(vp_scan_dev_t *d)
{
    d->commands++;
    if (d->dry && d->estop_at && d->commands == d->estop_at) {
        /* pressed 2 ms into this command, and kept pressed */
        d->dr->rec.cfg.estop_at = d->dr->rec.now + 2000000;
        d->dr->rec.cfg.estop_until = INT64_MAX;
    }
}

/* A dry run's check of a MOVE made: the laser origin's segment against the object. A move the
 * contact switch stopped went into the surface by the switch's lag and the overtravel: within
 * contact_stop that is the touch the switch is for, deeper a collision; the way back starts
 * inside by the lag (that stretch is the way in, retraced) */
static void vp_scan_move_check(vp_scan_dev_t *d, const vp_cmd_t *cmd, int last, int *collided)
{
    double a[3], u[3], at, len = vp_dist3(cmd->from, cmd->to), s0 = 0.0;
    int k, touched = last && vp_machine_contact(d->m, &at);
    for (k = 0; k < 3; k++) u[k] = len > 0.0 ? (cmd->to[k] - cmd->from[k]) / len : 0.0;
    if (d->touching && len > 0.0) s0 = d->touch_lag + 1e-9 * (1.0 + len);
    if (s0 > len) s0 = len;
    for (k = 0; k < 3; k++) a[k] = cmd->from[k] + s0 * u[k];
    d->backing = d->touching;
    d->touching = 0;
    if (touched) {
        if (vp_scan_touch_depth(d, a, u, s0, len, at, d->m->last.overtravel, HUGE_VAL, NULL)) *collided = 1;
        d->touching = 1;
    } else if (len > s0 && vp_surface_segment_collides(d->dr->surf, a, cmd->to, 0)) {
        d->through++;
        *collided = 1;
    }
}

static int vp_scan_dev_move_do(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    vp_scan_dev_t *d = ctx;
    double j0[VP_KIN_JOINTS];
    unsigned long turns = d->m->st.turns;
    int st;
    vp_scan_trip(d);
    memcpy(j0, d->m->j, sizeof j0);
    st = vp_machine_exec(d->m, cmd, NULL);
    *collided = 0;
    if (st != VP_OK) { d->fault = st; d->fault_cmd = *cmd; return st; }
    if (d->dry) {
        /* the laser origin's segment; then a MOVE is one straight line of all five joints: the
         * whole head along it, after the turn about the laser origin the machine made first, if
         * any (vp_machine_move) */
        unsigned long before = d->head_hits;
        vp_scan_move_check(d, cmd, 1, collided);
        if (d->m->st.turns != turns && d->m->turn_n > 0) {
            vp_scan_head_path(d, j0, (const double (*)[VP_KIN_JOINTS])d->m->way, d->m->turn_n);
            memcpy(j0, d->m->way[d->m->turn_n - 1], sizeof j0);
        }
        if (d->m->move_n > 0)   /* it turned on the way: the pieces it took */
            vp_scan_head_move(d, cmd, j0, (const double (*)[VP_KIN_JOINTS])d->m->way, d->m->move_n);
        else
            vp_scan_head_move(d, cmd, j0, (const double (*)[VP_KIN_JOINTS])d->m->j, 1);
        if (d->head_hits != before) *collided = 1;
    }
    return VP_OK;
}

static int vp_scan_dev_probe_do(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    vp_scan_dev_t *d = ctx;
    vp_machine_t *m = d->m;
    unsigned long near0 = m->st.near;
    vp_reading_t kind;
    double j0[VP_KIN_JOINTS], target[VP_KIN_JOINTS], way[VP_MACHINE_MAX_WAY][VP_KIN_JOINTS];
    int st, nway = 0;
    vp_scan_trip(d);
    d->last_false_miss = 0;
    if (d->dry) {
        /* the aim path the machine is about to take (vp_machine_probe plans the same one) */
        vp_camsim_seed(d->dr->cs, vp_mix64(d->seed ^ vp_mix64(d->probes)));
        memcpy(j0, m->j, sizeof j0);
        if (vp_kin_aim(&m->kin, j0, cmd->from, cmd->dir, target) == VP_OK)
            nway = vp_kin_aim_path(&m->kin, j0, target, way, VP_MACHINE_MAX_WAY);
    }
    st = vp_machine_exec(m, cmd, res);
    if (st != VP_OK) { d->fault = st; d->fault_cmd = *cmd; return st; }
    if (d->dry && nway > 0) {
        memcpy(way[nway - 1], m->j, sizeof way[0]);   /* where the steps ended */
        vp_scan_head_path(d, j0, (const double (*)[VP_KIN_JOINTS])way, nway);
    }
    d->probes++;
    kind = vp_machine_reading(m, cmd, m->st.near != near0, d->near_measure, res, &d->raw);
    if (kind == VP_READING_NEAR) d->near++;
    if (kind >= VP_READING_OFF_LINE) {
        d->unreadable++;
        d->unread_why[kind == VP_READING_NOT_LASER ? 4 : kind == VP_READING_NO_SPOT ? 5 : kind - VP_READING_OFF_LINE]++;
    }
    if (res->hit == VP_PROBE_TOO_CLOSE) d->too_close++;
    else if (res->hit) d->hits++;
    else d->misses++;
    if (d->dry && res->hit != VP_PROBE_TOO_CLOSE) {
        /* a hit is judged against the surface within the noise tolerance the planner trusts hits
         * to: a hit at the end of the range whose surface lies just beyond it is a measurement,
         * not a false hit; so is a miss whose surface lies within that tolerance of the range's
         * end (its spot read at the range or just past it): a miss is false only before that */
        double t, e;
        int truth;
        if (res->hit) {
            vp_hit_judged_t j = vp_scan_judge_hit(d->dr->surf, cmd->from, cmd->dir, cmd->range, res->dist, d->noise_tol, &e);
            if (j == VP_HIT_GRAZING) d->grazing++;
            else if (j == VP_HIT_FALSE) d->false_hits++;
            else {
                /* past the surface by more than the noise tolerance: the planner would take
                 * space inside the object for free (and the ray's error all the same) */
                if (j == VP_HIT_PAST) d->past++;
                d->true_n++;
                d->err2 += e * e;
                if (e > d->err_max) d->err_max = e;
            }
            return VP_OK;
        }
        truth = vp_surface_ray(d->dr->surf, cmd->from, cmd->dir, cmd->range, &t);
        if (truth && t >= (m->cfg.line ? m->cfg.line_model.min_range : m->tri.min_range) &&
                   t < cmd->range - d->noise_tol) {
            /* a surface on the ray: false unless the ray only clips a thin edge, nowhere deeper
             * inside than the tolerance (the beam passed beside it), as for a hit read past one */
            if (vp_scan_depth_beyond(d->dr->surf, cmd->from, cmd->dir, t, cmd->range, d->noise_tol)) {
                d->false_misses++;
                d->last_false_miss = 1;
            }
            else d->grazing++;
        }
    }
    return VP_OK;
}

/* Machine time by the planner's stage when it issued the command (seed, refinement, closing). */
static void vp_scan_stage_time(vp_scan_dev_t *d, double t0)
{
    int s = d->pl ? (int)vp_planner_stage(d->pl) : (int)VP_STAGE_REFINE;
    d->stage_s[s] += vp_scan_seconds(d) - t0;
    d->stage_cmds[s]++;
}

static int vp_scan_dev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    vp_scan_dev_t *d = ctx;
    double t0 = vp_scan_seconds(d);
    int st = vp_scan_dev_move_do(ctx, cmd, collided);
    vp_scan_stage_time(d, t0);
    return st;
}

/* MOVEs as one path (vp_machine_move_path), each checked in a dry run as when made alone: the
 * laser origin's segment, the head along the pieces it took. With --estop-at the MOVEs go one
 * by one, so the e-stop falls in the command it names. */
static int vp_scan_dev_move_path(void *ctx, const vp_cmd_t *cmds, int n, int *collided, int *done)
{
    vp_scan_dev_t *d = ctx;
    double t0 = vp_scan_seconds(d);
    int st, i, s = d->pl ? (int)vp_planner_stage(d->pl) : (int)VP_STAGE_REFINE;
    if (d->estop_at) {
        st = vp_scan_dev_move(ctx, cmds, collided);
        *done = st == VP_OK;
        return st;
    }
    st = vp_machine_move_path(d->m, cmds, n, done);
    d->stage_s[s] += vp_scan_seconds(d) - t0;
    d->stage_cmds[s] += (unsigned long)*done;
    for (i = 0; i < *done; i++) {
        const vp_machine_path_move_t *pm = &d->m->path[i];
        unsigned long before = d->head_hits;
        vp_scan_trip(d);
        collided[i] = 0;
        if (!d->dry) continue;
        vp_scan_move_check(d, &cmds[i], i + 1 == *done, &collided[i]);
        if (pm->turn_n > 0) {
            /* the turn it needed first, then the MOVE: two motions, as when made alone */
            vp_scan_head_path(d, pm->j0, (const double (*)[VP_KIN_JOINTS])d->m->path_way + pm->first, pm->turn_n);
            vp_scan_head_move(d, &cmds[i], d->m->path_way[pm->first + pm->turn_n - 1],
                              (const double (*)[VP_KIN_JOINTS])d->m->path_way + pm->first + pm->turn_n, pm->n - pm->turn_n);
        } else
            vp_scan_head_move(d, &cmds[i], pm->j0, (const double (*)[VP_KIN_JOINTS])d->m->path_way + pm->first, pm->n);
        if (d->head_hits != before) collided[i] = 1;
    }
    if (st != VP_OK) { d->fault = st; d->fault_cmd = cmds[*done < n ? *done : n - 1]; }
    return st;
}

static int vp_scan_dev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    vp_scan_dev_t *d = ctx;
    double t0 = vp_scan_seconds(d);
    int st = vp_scan_dev_probe_do(ctx, cmd, res);
    vp_scan_stage_time(d, t0);
    return st;
}

/* A line laser: the frame's other rays (port/vp_machine), judged in a dry run against the object
 * like the probes: a ray's point must lie within the noise tolerance of the surface. */
static int vp_scan_dev_rays(void *ctx, const vp_cmd_t *probe, unsigned i, vp_cmd_t *ray, vp_probe_result_t *res)
{
    vp_scan_dev_t *d = ctx;
    double dist;
    if (!vp_machine_ray(d->m, i, ray->dir, &dist)) return 0;
    ray->range = d->m->cfg.line_model.max_range;
    res->hit = 1;
    res->dist = dist;
    d->raw = dist;              /* the RAY record's raw reading: its own distance */
    d->rays++;
    if (d->dry) {
        /* the point against the object: its distance from the surface (a sample's error) */
        double q[3], e;
        int k;
        for (k = 0; k < 3; k++) q[k] = probe->from[k] + dist * ray->dir[k];
        e = vp_surface_distance(d->dr->surf, q);
        d->ray_err2 += e * e;
        if (e > d->ray_err_max) d->ray_err_max = e;
        if (e > d->noise_tol) d->ray_false++;
    }
    return 1;
}

/* The head's contact switch stopped the last MOVE: where (port/vp_machine). */
static int vp_scan_dev_touched(void *ctx, double *at)
{
    vp_scan_dev_t *d = ctx;
    return vp_machine_contact(d->m, at);
}

/* A miss must be seen: without walls round the machine (vp_scan_ops gives this device no sight
 * with them) a miss only says the camera found no spot, so its reading is judged against where
 * the camera stood (its centre: the calibrated one when the board has the full model, else
 * [camera] position, carried by the head's pan and tilt). In body mode only, where a side left
 * unseen is found from aside (a head that travels inside Omega has its contact switch for what
 * the rangefinder cannot see). */
static int vp_scan_dev_sight(void *ctx, const vp_cmd_t *probe, double cam[3])
{
    vp_scan_dev_t *d = ctx;
    double rot[9], pos[3], c[3];
    const double *in = d->board.have_rf ? d->board.rf.cam.pos : d->board.cam_model.pos;
    int k;
    (void)probe;
    if (!d->pl || !(d->pl->cfg.clearance > 0.0)) return 0;
    vp_kin_head(&d->m->kin, d->m->j, rot, pos);
    vp_kin_mul(rot, in, c);
    for (k = 0; k < 3; k++) cam[k] = pos[k] + c[k];
    return 1;
}

vp_device_ops_t vp_scan_ops(vp_scan_dev_t *d)
{
    vp_device_ops_t ops;
    ops.ctx = d;
    ops.move = vp_scan_dev_move;
    ops.probe = vp_scan_dev_probe;
    ops.touched = vp_board_has_contact(&d->board) ? vp_scan_dev_touched : NULL;
    ops.move_path = vp_machine_paths_allowed(d->m) ? vp_scan_dev_move_path : NULL;
    ops.rays = d->board.line_laser ? vp_scan_dev_rays : NULL;
    ops.sight = d->board.have_backdrop ? NULL : vp_scan_dev_sight;
    return ops;
}

/* ---------- resuming: back to where the log left the machine ---------- */

typedef struct { double p[3]; uint32_t i; } vp_pt_t;

static int vp_pt_cmp(const void *x, const void *y)
{
    const vp_pt_t *a = x, *b = y;
    int k;
    for (k = 0; k < 3; k++)
        if (a->p[k] != b->p[k]) return a->p[k] < b->p[k] ? -1 : 1;
    return a->i < b->i ? -1 : a->i > b->i;
}

static int vp_outside(const vp_planner_config_t *c, const double p[3])
{
    int k;
    if (c->omega_kind == VP_OMEGA_BALL) return vp_dist3(p, c->omega_center) >= c->omega_radius;
    for (k = 0; k < 3; k++)
        if (p[k] <= c->omega_lo[k] || p[k] >= c->omega_hi[k]) return 1;
    return 0;
}

static void vp_omega_sphere(const vp_planner_config_t *c, double o[3], double *r)
{
    int k;
    double q = 0;
    for (k = 0; k < 3; k++) {
        o[k] = c->omega_kind == VP_OMEGA_BALL ? c->omega_center[k] : 0.5 * (c->omega_lo[k] + c->omega_hi[k]);
        q += 0.25 * (c->omega_hi[k] - c->omega_lo[k]) * (c->omega_hi[k] - c->omega_lo[k]);
    }
    *r = 1.01 * (c->omega_kind == VP_OMEGA_BALL ? c->omega_radius : sqrt(q));
}

/* A way between two points outside the convex Omega that stays outside it: radially out to
 * the sphere of radius rs about o (a ray from the centre never re-enters a convex set), round
 * it in chords of at most 15 degrees (they stay outside Omega's circumsphere), radially in.
 * Appends the waypoints after a (b included) to W when W != NULL; returns the length. */
static double vp_sphere_way(const double o[3], double rs, const double a[3], const double b[3], double (*W)[3],
                            long *nw, long cap)
{
    double ua[3], ub[3], um[3], ra = 0, rb = 0, len = 0, prev[3], ang, dd = 0;
    int k, half, i, n;
    for (k = 0; k < 3; k++) { ua[k] = a[k] - o[k]; ub[k] = b[k] - o[k]; ra += ua[k] * ua[k]; rb += ub[k] * ub[k]; }
    ra = sqrt(ra);
    rb = sqrt(rb);
    if (!(ra > 0) || !(rb > 0)) return HUGE_VAL;
    for (k = 0; k < 3; k++) { ua[k] /= ra; ub[k] /= rb; um[k] = ua[k] + ub[k]; dd += um[k] * um[k]; }
    if (dd < 1e-12) {   /* opposite: turn through any perpendicular */
        double t[3] = { 1, 0, 0 };
        if (fabs(ua[0]) > 0.9) { t[0] = 0; t[1] = 1; }
        um[0] = ua[1] * t[2] - ua[2] * t[1];
        um[1] = ua[2] * t[0] - ua[0] * t[2];
        um[2] = ua[0] * t[1] - ua[1] * t[0];
        dd = vp_dot3(um, um);
    }
    for (k = 0; k < 3; k++) um[k] /= sqrt(dd);
    memcpy(prev, a, sizeof prev);
    if (ra < rs) ra = rs;
    if (rb < rs) rb = rs;
    for (half = 0; half < 2; half++) {
        const double *u0 = half ? um : ua, *u1 = half ? ub : um;
        double c0 = vp_dot3(u0, u1);
        ang = acos(c0 > 1 ? 1 : c0 < -1 ? -1 : c0);
        n = (int)ceil(ang / (15.0 * 3.14159265358979323846 / 180.0));
        if (n < 1) n = 1;
        for (i = half; i <= n; i++) {
            double t = (double)i / n, w[3], r = ra + (rb - ra) * 0.5 * (half + t), q = 0;
            for (k = 0; k < 3; k++) { w[k] = (1 - t) * u0[k] + t * u1[k]; q += w[k] * w[k]; }
            for (k = 0; k < 3; k++) w[k] = o[k] + r * w[k] / sqrt(q);
            len += vp_dist3(prev, w);
            if (W && *nw < cap) memcpy(W[(*nw)++], w, sizeof w);
            memcpy(prev, w, sizeof prev);
        }
    }
    len += vp_dist3(prev, b);
    if (W && *nw < cap) memcpy(W[(*nw)++], b, sizeof prev);
    return len;
}

/* The way back from P[0] (the start, outside Omega) to P[n-1] through proven-free space: round
 * Omega (everything outside it is free) to the logged position v outside Omega from which the
 * logged moves P[i-1]P[i] (equal points joined) lead to P[n-1] the shortest way, then along
 * them. Writes the waypoints after P[0] into W (capacity cap); returns their count (< 0: none)
 * and the length. */
static long vp_scan_route(const vp_planner_config_t *cfg, const double (*P)[3], uint32_t n, double (*W)[3], long cap,
                          double *route_len)
{
    vp_pt_t *s = malloc((size_t)n * sizeof *s);
    uint32_t *id = malloc((size_t)n * sizeof *id), *rep = malloc((size_t)n * sizeof *rep);
    uint32_t *deg = calloc((size_t)n + 1, sizeof *deg), *adj = malloc(2 * (size_t)n * sizeof *adj);
    uint32_t *prev = malloc((size_t)n * sizeof *prev), *heap = malloc(2 * (size_t)n * sizeof *heap);
    double *dist = malloc((size_t)n * sizeof *dist), *hkey = malloc(2 * (size_t)n * sizeof *hkey);
    double o[3], rs, best = HUGE_VAL;
    uint32_t i, nn = 0, nh = 0, src, v, bi = 0;
    long nw = -1;
    if (n == 0 || !s || !id || !rep || !deg || !adj || !prev || !heap || !dist || !hkey) goto out;
    for (i = 0; i < n; i++) { memcpy(s[i].p, P[i], sizeof s[i].p); s[i].i = i; }
    qsort(s, n, sizeof *s, vp_pt_cmp);
    for (i = 0; i < n; i++) {
        if (!(i > 0 && s[i].p[0] == s[i - 1].p[0] && s[i].p[1] == s[i - 1].p[1] && s[i].p[2] == s[i - 1].p[2]))
            rep[nn++] = s[i].i;
        id[s[i].i] = nn - 1;
    }
    /* adjacency (compressed rows) of the undirected segments */
    for (i = 1; i < n; i++) { deg[id[i - 1] + 1]++; deg[id[i] + 1]++; }
    for (i = 0; i < nn; i++) deg[i + 1] += deg[i];
    {
        uint32_t *fill = malloc(((size_t)nn + 1) * sizeof *fill);
        if (!fill) goto out;
        memcpy(fill, deg, ((size_t)nn + 1) * sizeof *fill);
        for (i = 1; i < n; i++) { adj[fill[id[i - 1]]++] = id[i]; adj[fill[id[i]]++] = id[i - 1]; }
        free(fill);
    }
    /* Dijkstra from the end, lazy binary heap: dist and prev lead every node to P[n-1] */
    src = id[n - 1];
    for (i = 0; i < nn; i++) { dist[i] = HUGE_VAL; prev[i] = UINT32_MAX; }
    dist[src] = 0;
    heap[nh] = src; hkey[nh++] = 0;
    while (nh) {
        double k0 = hkey[0];
        uint32_t u = heap[0], c, q;
        nh--;
        heap[0] = heap[nh]; hkey[0] = hkey[nh];
        for (c = 0;;) {   /* sift down */
            uint32_t l = 2 * c + 1, r = l + 1, b = c;
            if (l < nh && hkey[l] < hkey[b]) b = l;
            if (r < nh && hkey[r] < hkey[b]) b = r;
            if (b == c) break;
            { double tk = hkey[b]; uint32_t tv = heap[b]; hkey[b] = hkey[c]; heap[b] = heap[c]; hkey[c] = tk; heap[c] = tv; }
            c = b;
        }
        if (k0 > dist[u]) continue;
        for (q = deg[u]; q < deg[u + 1]; q++) {
            uint32_t w = adj[q];
            double nd = dist[u] + vp_dist3(P[rep[u]], P[rep[w]]);
            if (nd < dist[w] && nh < 2 * n) {
                dist[w] = nd;
                prev[w] = u;
                c = nh++;   /* sift up */
                heap[c] = w; hkey[c] = nd;
                while (c > 0 && hkey[(c - 1) / 2] > hkey[c]) {
                    uint32_t pa = (c - 1) / 2;
                    double tk = hkey[pa]; uint32_t tv = heap[pa];
                    hkey[pa] = hkey[c]; heap[pa] = heap[c]; hkey[c] = tk; heap[c] = tv;
                    c = pa;
                }
            }
        }
    }
    /* the best way in: round Omega to a logged position outside it, then the logged moves */
    vp_omega_sphere(cfg, o, &rs);
    for (i = 0; i < nn; i++) {
        double c;
        if (dist[i] == HUGE_VAL || (i != id[0] && !vp_outside(cfg, P[rep[i]]))) continue;
        c = dist[i] + (i == id[0] ? 0 : vp_sphere_way(o, rs, P[0], P[rep[i]], NULL, NULL, 0));
        if (c < best) { best = c; bi = i; }
    }
    if (best == HUGE_VAL) goto out;
    nw = 0;
    *route_len = best;
    if (bi != id[0]) vp_sphere_way(o, rs, P[0], P[rep[bi]], W, &nw, cap);
    for (v = prev[bi]; v != UINT32_MAX && nw < cap; v = prev[v]) memcpy(W[nw++], P[rep[v]], sizeof W[0]);
    if (nw >= cap) nw = -1;
out:
    free(s); free(id); free(rep); free(deg); free(adj); free(prev); free(heap); free(dist); free(hkey);
    return nw;
}

static void vp_units(const vp_step_t *s, const int32_t *pos, double *u)
{
    int i;
    for (i = 0; i < s->cfg.naxes; i++) u[i] = pos[i] / s->cfg.axis[i].steps_per_unit;
}

int vp_scan_return(vp_scan_dev_t *d, const vp_sessionlog_t *L, uint32_t n, const double start[3], FILE *msg,
                   char *err, size_t errlen)
{
    vp_machine_t *m = d->m;
    int32_t pos[VP_STEP_MAX_AXES];
    double u[VP_STEP_MAX_AXES], t[VP_STEP_MAX_AXES], (*P)[3] = NULL, (*W)[3] = NULL, travel = 0, route_len = 0;
    uint32_t np = 1, i;
    uint64_t probes = 0;
    long nr, cap;
    int st = VP_OK, a, w;
    P = malloc(((size_t)L->moves + 1) * sizeof *P);
    if (!P) { snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    memcpy(P[0], start, sizeof P[0]);
    memcpy(pos, m->step.pos, sizeof pos);
    /* the joints the session had after each logged command, as the step generator rounds them
     * (a MOVE that turned the head on its way, port/vp_machine.c, is taken as made straight: the
     * laser origin is where it was, the orientation the PROBE after it aims from again) */
    for (i = 0; i < n && i < L->n; i++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(L, i, &rec) != VP_OK) { st = VP_ECORRUPT; break; }
        if (rec.type == VP_LOGFMT_EVENT && rec.event == VP_LOGFMT_EV_RESCAN) {
            /* a re-scan started from the start: the way back begins there (the moves before it
             * were free for the object as it was) */
            np = 1;
            travel = 0;
            probes = 0;
            memcpy(pos, m->step.pos, sizeof pos);
            continue;
        }
        if (rec.type == VP_LOGFMT_EVENT || rec.type == VP_LOGFMT_RAY) continue; /* a RAY: the PROBE's frame */
        vp_units(&m->step, pos, u);
        if (rec.type == VP_LOGFMT_MOVE) {
            st = vp_kin_move(&m->kin, u, rec.target, t);
            if (st == VP_OK && np <= L->moves) {
                travel += vp_dist3(P[np - 1], rec.target);
                memcpy(P[np++], rec.target, sizeof P[0]);
            }
        } else {
            st = vp_kin_aim(&m->kin, u, rec.origin, rec.dir, t);
            probes++;
        }
        if (st != VP_OK) {
            snprintf(err, errlen, "record %u: the logged %s is out of this board's travel", i,
                     rec.type == VP_LOGFMT_MOVE ? "move" : "probe");
            break;
        }
        for (a = 0; a < VP_KIN_JOINTS; a++) pos[a] = vp_step_to_steps(&m->step, a, t[a]);
    }
    if (st == VP_ECORRUPT) snprintf(err, errlen, "the log cannot be read again");
    if (st != VP_OK) { free(P); return st; }
    d->probes = probes;
    /* back along the logged moves (and round Omega, where everything is free) */
    cap = (long)np + 64;
    W = malloc((size_t)cap * sizeof *W);
    nr = W ? vp_scan_route(&L->header.cfg, (const double (*)[3])P, np, W, cap, &route_len) : -1;
    if (nr < 0) { free(P); free(W); snprintf(err, errlen, "no route back through the logged moves"); return VP_EDEGEN; }
    if (msg) fprintf(msg, "resume: back to %.6g %.6g %.6g: %ld moves, %.0f mm (the session had travelled %.0f mm)\n",
                     P[np - 1][0], P[np - 1][1], P[np - 1][2], nr, route_len, travel);
    for (w = 0; w < nr && st == VP_OK; w++) {
        if (vp_scan_stop) { st = VP_EABORT; snprintf(err, errlen, "stopped (Ctrl-C) on the way back"); break; }
        st = vp_scan_goto(d, W[w], err, errlen);   /* a dry run checks each leg there */
    }
    if (msg && d->dry) fprintf(msg, "resume: dry run: %lu of those moves went through the object, %lu brought the head "
                               "within %g mm of it\n", d->through, d->head_hits, d->head_tol);
    free(P);
    free(W);
    if (st != VP_OK) return st;
    /* then the head as the log left it: turn about the laser origin to the same joints */
    vp_units(&m->step, pos, t);
    {
        double j0[VP_KIN_JOINTS];
        memcpy(j0, m->j, sizeof j0);
        w = vp_kin_aim_path(&m->kin, m->j, t, m->way, VP_MACHINE_MAX_WAY);
        st = w < 0 ? w : vp_step_move_path(&m->step, &m->way[0][0], w);
        vp_step_position(&m->step, m->j);
        if (st != VP_OK) return vp_scan_failed(d, st, "turning the head back", err, errlen);
        vp_scan_head_path(d, j0, (const double (*)[VP_KIN_JOINTS])m->way, w);
    }
    for (a = 0; a < VP_KIN_JOINTS; a++)
        if (m->step.pos[a] != pos[a]) {
            snprintf(err, errlen, "axis %s is at step %ld, not at step %ld where the log left it", vp_axis_name[a],
                     (long)m->step.pos[a], (long)pos[a]);
            return VP_EDEGEN;
        }
    return VP_OK;
}
