/* vp_dryrun — see vp_dryrun.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_dryrun.h"
#include "vp_status.h"
#include "vp_vec3.h"

/* joints from the carriages (the physical truth, backlash included) */
static void vp_dryrun_joints(const vp_dryrun_t *d, double j[VP_KIN_JOINTS])
{
    int a;
    for (a = 0; a < VP_KIN_JOINTS; a++) j[a] = d->rec.carriage[a] / d->board.axis[a].ax.steps_per_unit;
}

static void vp_dryrun_pose(void *ctx, double rot[9], double pos[3])
{
    const vp_dryrun_t *d = ctx;
    double j[VP_KIN_JOINTS];
    vp_dryrun_joints(d, j);
    vp_kin_head(&d->m.kin, j, rot, pos);
}

static int64_t vp_dryrun_clock(void *ctx) { return ((vp_dryrun_t *)ctx)->rec.now; }
static int vp_dryrun_laser(void *ctx) { return (((vp_dryrun_t *)ctx)->rec.out & VP_IO_LASER) != 0; }
static int vp_dryrun_wait(void *ctx, int64_t t)
{
    vp_dryrun_t *d = ctx;
    vp_io_t io = vp_iorec_io(&d->rec);
    return io.wait_until(io.ctx, t);
}

/* the GPIO as the machine sees it: the recording backend, and the camera told of laser switches */
static int64_t vp_dryrun_io_now(void *ctx) { vp_dryrun_t *d = ctx; vp_io_t io = vp_iorec_io(&d->rec); return io.now(io.ctx); }
static int vp_dryrun_io_read(void *ctx, uint32_t *in) { vp_dryrun_t *d = ctx; vp_io_t io = vp_iorec_io(&d->rec); return io.read(io.ctx, in); }
static int vp_dryrun_io_write(void *ctx, uint32_t mask, uint32_t values)
{
    vp_dryrun_t *d = ctx;
    vp_io_t io = vp_iorec_io(&d->rec);
    int rc = io.write(io.ctx, mask, values);
    if ((mask & VP_IO_LASER) && d->cs) vp_camsim_laser_switched(d->cs);
    if ((mask & values & 0xffu) && d->cs) vp_camsim_moved(d->cs);   /* a step edge: the head rings from now */
    return rc;
}

static double vp_dryrun_obj_distance(void *ctx, const double p[3]) { return vp_surface_distance(ctx, p); }
static int vp_dryrun_obj_inside(void *ctx, const double p[3]) { return vp_surface_inside(ctx, p); }

vp_head_object_t vp_dryrun_object(const vp_dryrun_t *d)
{
    vp_head_object_t obj;
    obj.distance = vp_dryrun_obj_distance;
    obj.inside = vp_dryrun_obj_inside;
    obj.ctx = d->surf;
    return obj;
}

/* the most any sensed part moved between two poses */
static double vp_dryrun_mount_moved(const vp_dryrun_t *d, const double ja[VP_KIN_JOINTS], const double jb[VP_KIN_JOINTS])
{
    double m = 0.0, v;
    int i;
    for (i = 0; i < d->board.head.nparts; i++)
        if ((d->mount_mask >> i & 1u) && (v = vp_head_moved(&d->board.head, i, ja, jb)) > m) m = v;
    return m;
}

/* contact_by = mount: a part of the head within VP_DRYRUN_MOUNT_NEED of the object at pose j. The
 * parts are looked at again only when they may have moved by more than their last gap less that
 * distance; while the switch is closed, at every pose. */
static int vp_dryrun_mount(vp_dryrun_t *d, const double j[VP_KIN_JOINTS])
{
    vp_head_object_t obj = vp_dryrun_object(d);
    double gap = 0.0;
    int in;
    if (d->touch_known && !d->touch_in && vp_dryrun_mount_moved(d, d->mount_j, j) < d->mount_gap - VP_DRYRUN_MOUNT_NEED)
        return 0;
    in = vp_head_near(&d->board.head, &obj, d->mount_mask, j, VP_DRYRUN_MOUNT_NEED, &gap, &d->touch_evals);
    if (in != 0) in = 1;        /* cannot tell: closed, as a switch that closes early */
    if (in && !(d->touch_known && d->touch_in)) memcpy(d->mount_first, j, sizeof d->mount_first);
    memcpy(d->mount_j, j, sizeof d->mount_j);
    d->mount_gap = gap;
    d->touch_in = in;
    d->touch_known = 1;
    return in;
}

double vp_dryrun_mount_past(const vp_dryrun_t *d, const double *j)
{
    double now[VP_KIN_JOINTS];
    if (!d->touch_known || !d->board.contact_mount) return 0.0;
    if (!j) { vp_dryrun_joints(d, now); j = now; }
    return vp_dryrun_mount_moved(d, d->mount_first, j);
}

/* The contact input: the true laser origin inside the object. The surface is asked again only
 * when the origin leaves the ball (radius: its distance to the surface) around the point it was
 * last asked at. */
static int vp_dryrun_contact(void *ctx, const int32_t *carriage)
{
    vp_dryrun_t *d = ctx;
    double j[VP_KIN_JOINTS], o[3], dir[3];
    int a;
    if (d->touch_known && !memcmp(carriage, d->touch_carriage, sizeof d->touch_carriage)) return d->touch_in;
    for (a = 0; a < VP_KIN_JOINTS; a++) j[a] = carriage[a] / d->board.axis[a].ax.steps_per_unit;
    memcpy(d->touch_carriage, carriage, sizeof d->touch_carriage);
    if (d->board.contact_mount && !d->flat_target) return vp_dryrun_mount(d, j);
    vp_kin_forward(&d->touch_kin, j, o, dir);
    if (d->touch_known && vp_dist3(o, d->touch_origin) < d->touch_clear) return d->touch_in;
    if (d->flat_target) {
        d->touch_in = o[0] >= d->target_x;
        d->touch_clear = fabs(o[0] - d->target_x);
    } else {
        d->touch_in = vp_surface_inside(d->surf, o);
        d->touch_clear = vp_surface_distance(d->surf, o);
    }
    memcpy(d->touch_origin, o, sizeof d->touch_origin);
    d->touch_known = 1;
    d->touch_evals++;
    return d->touch_in;
}

/* The laser as mounted turns the nominal beam (+x) onto dir: the same turn (about +x cross dir)
 * applied to the nominal plane's normal n gives the mounted plane's (unit). */
static void vp_dryrun_turn(const double n[3], const double dir[3], double out[3])
{
    static const double ex[3] = { 1, 0, 0 };
    double a[3], d[3], c, s, l, ka[3], k = 0;
    int i;
    l = vp_norm3(dir);
    for (i = 0; i < 3; i++) d[i] = dir[i] / l;
    vp_cross3(a, ex, d);
    s = vp_norm3(a);
    c = vp_dot3(ex, d);
    l = vp_norm3(n);
    if (!(s > 1e-15)) {
        for (i = 0; i < 3; i++) out[i] = n[i] / l;
        return;
    }
    for (i = 0; i < 3; i++) { a[i] /= s; k += a[i] * n[i]; }
    /* Rodrigues: n cos + (a x n) sin + a (a.n)(1 - cos) */
    vp_cross3(ka, a, n);
    for (i = 0; i < 3; i++) out[i] = (n[i] * c + ka[i] * s + a[i] * k * (1 - c)) / l;
}

int vp_dryrun_true_plane(const vp_dryrun_t *d, double origin[3], double normal[3])
{
    if (!d || !d->board.line_laser) return 0;
    memcpy(origin, d->fan_origin, 3 * sizeof *origin);
    memcpy(normal, d->fan_normal, 3 * sizeof *normal);
    return 1;
}

void vp_dryrun_true_beam(const vp_dryrun_t *d, double origin[3], double dir[3])
{
    double j[VP_KIN_JOINTS];
    vp_dryrun_joints(d, j);
    vp_kin_forward(&d->m.kin, j, origin, dir);
}

int vp_dryrun_open(const vp_board_t *b, const vp_dryrun_options_t *o, vp_dryrun_t **out, char *err, size_t errlen)
{
    vp_dryrun_t *d;
    vp_dryrun_options_t opt;
    vp_iorec_config_t rc;
    vp_kin_config_t kc;
    vp_step_config_t sc;
    vp_camsim_config_t cc;
    vp_camsim_scene_t scene;
    vp_machine_config_t mc;
    vp_cam_t cam;
    vp_io_t io;
    vp_kin_t kin;
    double j0[VP_KIN_JOINTS] = { 0, 0, 0, 0, 0 }, start_j[VP_KIN_JOINTS];
    int a, st;
    if (!b || !out) return VP_EINVAL;
    memset(&opt, 0, sizeof opt);
    if (o) opt = *o;
    d = calloc(1, sizeof *d);
    if (!d) return VP_ENOMEM;
    d->board = *b;
    st = vp_surface_open(opt.surface ? opt.surface : b->sim_surface, &d->surf, err, errlen);
    if (st != VP_OK) { free(d); return st; }
    /* where the machine powers on: laser origin at the start, head at rest */
    vp_board_kin_config(b, &kc);
    if (vp_kin_init(&kin, &kc) != VP_OK) { vp_surface_close(d->surf); free(d); return VP_EINVAL; }
    for (a = 0; a < VP_KIN_JOINTS; a++) j0[a] = b->axis[a].ax.home_dir ? 0 : b->axis[a].ax.home_pos;
    if (vp_kin_move(&kin, j0, b->start, start_j) != VP_OK) {
        snprintf(err, errlen, "%s: the start is out of reach", b->path);
        vp_surface_close(d->surf);
        free(d);
        return VP_ERANGE;
    }
    /* the recording backend's machine: carriage coordinates are machine steps */
    memset(&rc, 0, sizeof rc);
    rc.buf = opt.edges;
    rc.cap = opt.cap;
    rc.naxes = VP_KIN_JOINTS;
    rc.estop_at = -1;
    for (a = 0; a < VP_KIN_JOINTS; a++) {
        const vp_step_axis_t *ax = &b->axis[a].ax;
        rc.start[a] = (int32_t)llround(start_j[a] * ax->steps_per_unit);
        rc.invert_dir[a] = ax->invert_dir;
        rc.slack[a] = (int32_t)llround(ax->backlash * ax->steps_per_unit);
        if (ax->home_dir < 0) { rc.has_min[a] = 1; rc.min_sw[a] = (int32_t)llround(ax->home_pos * ax->steps_per_unit); }
        if (ax->home_dir > 0) { rc.has_max[a] = 1; rc.max_sw[a] = (int32_t)llround(ax->home_pos * ax->steps_per_unit); }
    }
    if (vp_board_has_contact(b)) {
        d->touch_kin = kin;
        d->flat_target = opt.flat_target;
        d->target_x = opt.target_x;
        rc.contact = vp_dryrun_contact;
        rc.contact_ctx = d;
        for (a = 0; a < b->head.nparts; a++)
            if (!vp_board_part_is_ball(b, a)) d->mount_mask |= 1u << a;
    }
    vp_iorec_init(&d->rec, &rc);
    io.ctx = d;
    io.now = vp_dryrun_io_now;
    io.wait_until = vp_dryrun_wait;
    io.write = vp_dryrun_io_write;
    io.read = vp_dryrun_io_read;
    /* the camera: host-sim frames at the carriages' pose */
    memset(&cc, 0, sizeof cc);
    cc.cam = b->sim_cam.width ? b->sim_cam : b->cam_model;   /* as mounted ([sim] may move it) */
    memcpy(cc.laser_offset, b->sim_laser_origin, sizeof cc.laser_offset);
    {
        /* the beam as mounted: turned laser_error[0] degrees from +x towards azimuth laser_error[1] */
        double ang = b->sim_laser_error[0] * 3.14159265358979323846 / 180, az = b->sim_laser_error[1] * 3.14159265358979323846 / 180;
        cc.laser_dir[0] = cos(ang);
        cc.laser_dir[1] = sin(ang) * cos(az);
        cc.laser_dir[2] = sin(ang) * sin(az);
    }
    cc.blur_px = b->sim_blur;
    cc.noise = b->sim_noise;
    cc.ambient = b->sim_ambient;
    cc.gradient = b->sim_gradient;
    cc.texture = b->sim_texture;
    cc.spot_energy = b->sim_energy;
    cc.max_range = 10 * b->max_range;
    /* the faults of a real world ([sim] speckle, vibration, flicker, glint, dark) */
    cc.speckle = b->sim_speckle[0];
    cc.fnumber = b->sim_speckle[1];
    cc.vib_px = b->sim_vibration[0];
    cc.vib_hz = b->sim_vibration[1];
    cc.vib_ms = b->sim_vibration[2];
    cc.vib_deg = b->sim_vibration[3];
    cc.exposure_ms = b->camera.exposure_us > 0 ? b->camera.exposure_us * 1e-3 : 0;
    cc.flicker = b->sim_flicker[0];
    cc.flicker_hz = b->sim_flicker[1];
    cc.glint_peak = b->sim_glint[0];
    cc.glint_sigma = b->sim_glint[1];
    cc.glint_dist = b->sim_glint[2];
    cc.glint_off_px = b->sim_glint[3];
    cc.glint_move_px = b->sim_glint[4];
    cc.glint_period_ms = b->sim_glint[5];
    cc.dark_albedo = b->sim_dark[0];
    cc.dark_z[0] = b->sim_dark[1];
    cc.dark_z[1] = b->sim_dark[2];
    cc.ghost = b->sim_ghost[0];
    cc.ghost_offset[0] = b->sim_ghost[1];
    cc.ghost_offset[1] = b->sim_ghost[2];
    if (b->line_laser) {
        /* a line laser: the fan as the board mounts it */
        cc.laser_kind = VP_CAMSIM_LINE;
        cc.fan_half_angle = 0.5 * b->line_fan * 3.14159265358979323846 / 180;
        vp_dryrun_turn(b->line_normal, cc.laser_dir, cc.line_normal);
        memcpy(d->fan_normal, cc.line_normal, sizeof d->fan_normal);
        memcpy(d->fan_origin, cc.laser_offset, sizeof d->fan_origin);
    }
    memset(&scene, 0, sizeof scene);
    scene.surf = d->surf;
    if (b->have_backdrop) {
        /* the walls round the machine */
        scene.backdrop = 1;
        memcpy(scene.backdrop_lo, b->backdrop, sizeof scene.backdrop_lo);
        memcpy(scene.backdrop_hi, b->backdrop + 3, sizeof scene.backdrop_hi);
    }
    if (opt.flat_target) {
        scene.surf = NULL;
        scene.plane_n[0] = 1;
        scene.plane_d = opt.target_x;
        if (b->have_mark) {
            /* the calibration mark printed on the target */
            scene.mark_peak = 120;
            scene.mark[0] = opt.target_x;
            scene.mark[1] = b->cal_mark[0];
            scene.mark[2] = b->cal_mark[1];
        }
    }
    st = vp_camsim_create(&cc, &scene, opt.seed ? opt.seed : (unsigned long long)b->sim_seed, vp_dryrun_pose,
                          vp_dryrun_clock, d, &d->cs);
    if (st != VP_OK) { vp_surface_close(d->surf); free(d); return st; }
    cam = vp_camsim_cam(d->cs);
    {
        /* the laser line seen by the camera, streaming as the board's [sim] says */
        vp_camsim_stream_t cst;
        memset(&cst, 0, sizeof cst);
        cst.period_ns = (int64_t)llround(b->sim_frame_ms * 1e6);
        cst.latency = b->sim_latency;
        cst.laser = b->laser.chip[0] ? vp_dryrun_laser : NULL;
        cst.wait_until = vp_dryrun_wait;
        st = vp_camsim_set_stream(d->cs, &cst);
        d->frame = malloc(2 * (size_t)cc.cam.width * (size_t)cc.cam.height);
        if (st != VP_OK || !d->frame) {
            vp_camsim_destroy(d->cs);
            vp_surface_close(d->surf);
            free(d->frame);
            free(d);
            return st != VP_OK ? st : VP_ENOMEM;
        }
    }
    vp_board_step_config(b, &sc);
    vp_board_machine_config(b, &mc);
    mc.diff_buf = d->frame;
    mc.diff_len = 2 * (size_t)cc.cam.width * (size_t)cc.cam.height;
    st = vp_machine_init(&d->m, &kc, &sc, &io, &cam, &b->tri, &mc);
    if (st != VP_OK) {
        snprintf(err, errlen, "%s: the machine configuration is refused", b->path);
        vp_camsim_destroy(d->cs);
        free(d->frame);
        vp_surface_close(d->surf);
        free(d);
        return st;
    }
    *out = d;
    return VP_OK;
}

vp_machine_t *vp_dryrun_machine(vp_dryrun_t *d) { return &d->m; }

void vp_dryrun_close(vp_dryrun_t *d)
{
    if (!d) return;
    vp_machine_close(&d->m);      /* closes (destroys) the renderer too */
    vp_surface_close(d->surf);
    free(d->frame);
    free(d);
}
