/* vp_board — see vp_board.h. Keys are described by tables; values are checked where they are
 * read, the machine as a whole after the file is read. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "vp_board.h"
#include "vp_ini.h"
#include "vp_logwriter.h"
#include "vp_planner.h"
#include "vp_status.h"
#include "vp_vec3.h"

enum { K_NUM, K_NUMS, K_INT, K_BOOL, K_PIN, K_STR, K_HOME, K_IO, K_FMT, K_RANGE, K_BOX, K_BALL };
enum { R_NO = 0, R_YES = 1, R_GPIO = 2 };   /* required: never, always, for io = gpiod */

typedef struct vp_bkey {
    const char *name;
    int type;
    size_t off;          /* in vp_board_t, or in vp_board_axis_t for axis keys */
    int n;               /* K_NUMS: count; K_STR: buffer size */
    double lo, hi;       /* accepted numbers (lo > hi: any) */
    int req;
} vp_bkey_t;

#define B(f) offsetof(vp_board_t, f)
#define A(f) offsetof(vp_board_axis_t, f)
#define POS 1e-300
#define ANY 1, -1

static const vp_bkey_t k_board[] = {
    { "name", K_STR, B(name), 64, ANY, R_YES },
    { "io", K_IO, B(io), 0, ANY, R_YES },
    { "log_sync", K_STR, B(log_sync), 32, ANY, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_timing[] = {
    { "pulse_us", K_NUM, B(pulse_us), 1, 0.5, 1000, R_NO },
    { "dir_setup_us", K_NUM, B(dir_setup_us), 1, 0, 1000, R_NO },
    { "enable_ms", K_NUM, B(enable_ms), 1, 0, 1000, R_NO },
    { "poll_ms", K_NUM, B(poll_ms), 1, 0.05, 100, R_NO },
    { "spin_us", K_NUM, B(spin_us), 1, 0, 1000, R_NO },
    { "max_step_rate", K_NUM, B(max_step_rate), 1, 1, 500000, R_NO },
    { "rt_priority", K_INT, B(rt_priority), 1, 0, 99, R_NO },
    { "debounce", K_INT, B(debounce), 1, 1, 64, R_NO },
    { "max_late_us", K_NUM, B(max_late_us), 1, 1, 1e6, R_NO },
    { "on_late", K_STR, B(on_late), 16, ANY, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_axis[] = {
    { "step", K_PIN, A(step), 0, ANY, R_GPIO },
    { "dir", K_PIN, A(dir), 0, ANY, R_GPIO },
    { "enable", K_PIN, A(enable), 0, ANY, R_NO },
    { "limit_min", K_PIN, A(lim_min), 0, ANY, R_NO },
    { "limit_max", K_PIN, A(lim_max), 0, ANY, R_NO },
    { "steps_per_unit", K_NUM, A(ax.steps_per_unit), 1, POS, 1e6, R_YES },
    { "max_speed", K_NUM, A(ax.max_speed), 1, POS, 1e5, R_YES },
    { "accel", K_NUM, A(ax.accel), 1, POS, 1e7, R_YES },
    { "travel", K_RANGE, A(ax.travel_min), 2, -1e6, 1e6, R_YES },
    { "backlash", K_NUM, A(ax.backlash), 1, 0, 100, R_NO },
    { "jerk", K_NUM, A(ax.jerk), 1, 0, 1e5, R_NO },
    { "invert", K_BOOL, A(ax.invert_dir), 0, ANY, R_NO },
    { "home", K_HOME, A(ax.home_dir), 0, ANY, R_NO },
    { "home_pos", K_NUM, A(ax.home_pos), 1, -1e6, 1e6, R_NO },
    { "home_seek", K_NUM, A(ax.home_seek), 1, 0, 1e5, R_NO },
    { "home_feed", K_NUM, A(ax.home_feed), 1, 0, 1e5, R_NO },
    { "home_pulloff", K_NUM, A(ax.home_pulloff), 1, 0, 1000, R_NO },
    { "home_order", K_INT, A(ax.home_order), 1, 0, 9, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_estop[] = {
    { "pin", K_PIN, B(estop), 0, ANY, R_GPIO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_laser[] = {
    { "pin", K_PIN, B(laser), 0, ANY, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_head[] = {
    { "tilt_offset", K_NUMS, B(tilt_offset), 3, -1e4, 1e4, R_NO },
    { "laser_offset", K_NUMS, B(laser_offset), 3, -1e4, 1e4, R_YES },
    { "origin_tol", K_NUM, B(origin_tol), 1, POS, 10, R_NO },
    { "contact", K_PIN, B(contact), 0, ANY, R_NO },
    { "contact_stop", K_NUM, B(contact_stop), 1, POS, 1000, R_NO },
    { "contact_halt", K_BOOL, B(contact_halt), 0, ANY, R_NO },
    { "contact_by", K_STR, B(contact_by), 8, ANY, R_NO },
    { "laser_body", K_STR, B(body_laser), 96, ANY, R_NO },
    { "camera_body", K_STR, B(body_camera), 96, ANY, R_NO },
    { "bracket", K_STR, B(body_bracket), 96, ANY, R_NO },
    { "hub", K_STR, B(body_hub), 96, ANY, R_NO },
    { "clear_by", K_STR, B(clear_by), 16, ANY, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_camera[] = {
    { "backend", K_STR, B(camera.backend), 16, ANY, R_NO },
    { "device", K_STR, B(camera.device), 128, ANY, R_NO },
    { "width", K_INT, B(cam_model.width), 1, 8, 4096, R_YES },
    { "height", K_INT, B(cam_model.height), 1, 8, 4096, R_YES },
    { "format", K_FMT, B(camera.format), 0, ANY, R_NO },
    { "exposure_us", K_INT, B(camera.exposure_us), 1, 0, 1e7, R_NO },
    { "buffers", K_INT, B(camera.buffers), 1, 0, 8, R_NO },
    { "focal_px", K_NUMS, B(cam_model.fx), 1, POS, 1e5, R_NO },
    { "fx", K_NUM, B(cam_model.fx), 1, POS, 1e5, R_NO },
    { "fy", K_NUM, B(cam_model.fy), 1, POS, 1e5, R_NO },
    { "center", K_NUMS, B(cam_model.cx), 2, -1e4, 1e4, R_NO },
    { "distortion", K_NUMS, B(cam_model.dist), 4, -10, 10, R_NO },
    { "position", K_NUMS, B(cam_model.pos), 3, -1e4, 1e4, R_YES },
    { "look_at", K_NUMS, B(look_at), 3, -1e5, 1e5, R_YES },
    { "up", K_NUMS, B(up), 3, -1e5, 1e5, R_NO },
    { "timeout_ms", K_INT, B(timeout_ms), 1, 1, 60000, R_NO },
    { "latency_frames", K_INT, B(latency_frames), 1, 0, 64, R_NO },
    { "gain", K_NUM, B(camera.gain), 1, 0, 1e4, R_NO },
    { "laser_colour", K_STR, B(laser_colour), 16, ANY, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_range[] = {
    { "min_range", K_NUM, B(min_range), 1, POS, 1e5, R_YES },
    { "max_range", K_NUM, B(max_range), 1, POS, 1e5, R_YES },
    { "band", K_NUM, B(band), 1, 0, 1000, R_NO },
    { "settle_ms", K_NUM, B(settle_ms), 1, 0, 10000, R_NO },
    { "line", K_NUMS, B(line), 4, -1e5, 1e5, R_NO },
    { "model", K_NUMS, B(model), 3, -1e9, 1e9, R_NO },
    { "calibration", K_STR, B(calibration), 256, ANY, R_NO },
    { "near_spots", K_STR, B(near_spots), 16, ANY, R_NO },
    { "confirm_spot", K_BOOL, B(confirm_spot), 0, ANY, R_NO },
    { "backdrop", K_NUMS, B(backdrop), 6, -1e6, 1e6, R_NO },
    { "laser", K_STR, B(laser_kind), 8, ANY, R_NO },
    { "fan", K_NUM, B(line_fan), 1, 1, 120, R_NO },
    { "fan_used", K_NUM, B(line_fan_used), 1, 1, 120, R_NO },
    { "line_normal", K_NUMS, B(line_normal), 3, -1e3, 1e3, R_NO },
    { "line_step", K_INT, B(line_step), 1, 1, 64, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_omega[] = {
    { "box", K_BOX, B(omega_lo), 6, -1e6, 1e6, R_NO },
    { "ball", K_BALL, B(omega_center), 4, -1e6, 1e6, R_NO },
    { "interior", K_NUMS, B(interior), 3, -1e6, 1e6, R_NO },
    { "eps", K_NUM, B(eps), 1, POS, 1e5, R_YES },
    { "start", K_NUMS, B(start), 3, -1e6, 1e6, R_YES },
    { "clearance", K_NUM, B(clearance), 1, 0, 1e4, R_NO },
    { "min_feature", K_NUM, B(min_feature), 1, 0, 1e4, R_NO },
    { "feature_margin", K_NUM, B(feature_margin), 1, 0, 1e4, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_sim[] = {
    { "surface", K_STR, B(sim_surface), 256, ANY, R_NO },
    { "blur_px", K_NUM, B(sim_blur), 1, 0.3, 50, R_NO },
    { "noise", K_NUM, B(sim_noise), 1, 0, 100, R_NO },
    { "ambient", K_NUM, B(sim_ambient), 1, 0, 255, R_NO },
    { "gradient", K_NUM, B(sim_gradient), 1, -255, 255, R_NO },
    { "texture", K_NUM, B(sim_texture), 1, 0, 255, R_NO },
    { "spot_energy", K_NUM, B(sim_energy), 1, POS, 1e9, R_NO },
    { "seed", K_NUM, B(sim_seed), 1, 0, 9e15, R_NO },
    { "frame_ms", K_NUM, B(sim_frame_ms), 1, 0, 1000, R_NO },
    { "latency_frames", K_INT, B(sim_latency), 1, 0, 64, R_NO },
    { "camera_position", K_NUMS, B(sim_cam_pos), 3, -1e4, 1e4, R_NO },
    { "camera_look_at", K_NUMS, B(sim_cam_look), 3, -1e5, 1e5, R_NO },
    { "speckle", K_NUMS, B(sim_speckle), 2, 0, 1e3, R_NO },
    { "vibration", K_NUMS, B(sim_vibration), 4, -1e5, 1e5, R_NO },
    { "flicker", K_NUMS, B(sim_flicker), 2, 0, 1e4, R_NO },
    { "glint", K_NUMS, B(sim_glint), 6, -1e5, 1e5, R_NO },
    { "ghost", K_NUMS, B(sim_ghost), 3, -1e4, 1e4, R_NO },
    { "dark", K_NUMS, B(sim_dark), 3, -1e6, 1e6, R_NO },
    { "distortion", K_NUMS, B(sim_dist), 4, -10, 10, R_NO },
    { "laser_origin", K_NUMS, B(sim_laser_origin), 3, -1e4, 1e4, R_NO },
    { "laser_error", K_NUMS, B(sim_laser_error), 2, -90, 360, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };
static const vp_bkey_t k_calib[] = {
    { "target", K_NUMS, B(cal_target), 3, -1e6, 1e6, R_YES },
    { "near", K_NUM, B(cal_near), 1, POS, 1e5, R_NO },
    { "far", K_NUM, B(cal_far), 1, POS, 1e5, R_NO },
    { "stations", K_INT, B(cal_stations), 1, 4, 256, R_NO },
    { "frames", K_INT, B(cal_frames), 1, 1, 64, R_NO },
    { "mark", K_NUMS, B(cal_mark), 2, -1e6, 1e6, R_NO },
    { NULL, 0, 0, 0, 0, 0, 0 } };

enum { S_BOARD, S_TIMING, S_AX0, S_AX4 = S_AX0 + 4, S_ESTOP, S_LASER, S_HEAD, S_CAMERA, S_RANGE, S_OMEGA, S_SIM, S_CALIB,
       NSEC };
#define NKEY 24

static const char *const sec_name[NSEC] = { "board", "timing", "axis.x", "axis.y", "axis.z", "axis.pan", "axis.tilt",
                                            "estop", "laser", "head", "camera", "rangefinder", "omega", "sim",
                                            "calibrate" };
static const int sec_required[NSEC] = { 1, 0, 1, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1, 0, 0 };
static const char *const axis_unit[VP_BOARD_AXES] = { "mm", "mm", "mm", "deg", "deg" };

static const vp_bkey_t *vp_sec_keys(int s)
{
    if (s >= S_AX0 && s <= S_AX4) return k_axis;
    switch (s) {
    case S_BOARD: return k_board;
    case S_TIMING: return k_timing;
    case S_ESTOP: return k_estop;
    case S_LASER: return k_laser;
    case S_HEAD: return k_head;
    case S_CAMERA: return k_camera;
    case S_RANGE: return k_range;
    case S_OMEGA: return k_omega;
    case S_CALIB: return k_calib;
    default: return k_sim;
    }
}

typedef struct vp_bctx {
    vp_board_t *b;
    const char *name;
    int sec;                      /* current section, -1 before the first */
    int secline[NSEC];            /* 0: section absent */
    int line[NSEC][NKEY];         /* line each key was set on, 0: not set */
} vp_bctx_t;

static unsigned char *vp_key_ptr(vp_bctx_t *c, int s, const vp_bkey_t *k)
{
    unsigned char *base = (unsigned char *)c->b;
    if (s >= S_AX0 && s <= S_AX4) base = (unsigned char *)&c->b->axis[s - S_AX0];
    return base + k->off;
}

/* n numbers separated by commas (or blanks), all of them, each in [lo, hi] */
static int vp_numbers(const char *v, double *out, int n, double lo, double hi, char *msg, size_t ml)
{
    const char *p = v;
    int i;
    for (i = 0; i < n; i++) {
        char *e;
        while (*p == ' ' || *p == '\t' || (i > 0 && *p == ',')) p++;
        out[i] = strtod(p, &e);
        if (e == p || !isfinite(out[i])) {
            if (n == 1) snprintf(msg, ml, "expected a number, got '%s'", v);
            else snprintf(msg, ml, "expected %d numbers separated by commas, got '%s'", n, v);
            return VP_EINVAL;
        }
        if (lo <= hi && (out[i] < lo || out[i] > hi)) {
            if (lo == POS) snprintf(msg, ml, "%g must be positive (at most %g)", out[i], hi);
            else snprintf(msg, ml, "%g is outside %g..%g", out[i], lo, hi);
            return VP_EINVAL;
        }
        p = e;
        while (*p == ' ' || *p == '\t') p++;
        if (i + 1 < n && *p == ',') p++;
    }
    if (*p) {
        if (n == 1) snprintf(msg, ml, "expected a number, got '%s'", v);
        else snprintf(msg, ml, "expected %d numbers, got '%s'", n, v);
        return VP_EINVAL;
    }
    return VP_OK;
}

static int vp_pin(const char *v, vp_gpio_pin_t *pin, char *msg, size_t ml)
{
    char chip[VP_GPIO_CHIP_LEN], word[32];
    const char *p = v, *colon;
    char *e;
    long off;
    size_t n;
    memset(pin, 0, sizeof *pin);
    pin->offset = -1;
    if (!strcmp(v, "none") || !*v) return VP_OK;
    if (*p == '!') { pin->active_low = 1; p++; }
    colon = strchr(p, ':');
    if (!colon || colon == p) { snprintf(msg, ml, "expected [!]CHIP:OFFSET [pull-up|pull-down] or none, got '%s'", v); return VP_EINVAL; }
    n = (size_t)(colon - p);
    if (n >= sizeof chip) { snprintf(msg, ml, "chip name too long in '%s'", v); return VP_EINVAL; }
    memcpy(chip, p, n);
    chip[n] = 0;
    off = strtol(colon + 1, &e, 10);
    if (e == colon + 1 || off < 0 || off > 4095) { snprintf(msg, ml, "bad line offset in '%s'", v); return VP_EINVAL; }
    while (*e == ' ' || *e == '\t') e++;
    if (*e) {
        if (strlen(e) >= sizeof word) { snprintf(msg, ml, "unknown pin option '%s'", e); return VP_EINVAL; }
        strcpy(word, e);
        if (!strcmp(word, "pull-up")) pin->pull = VP_PULL_UP;
        else if (!strcmp(word, "pull-down")) pin->pull = VP_PULL_DOWN;
        else { snprintf(msg, ml, "unknown pin option '%s' (pull-up or pull-down)", word); return VP_EINVAL; }
    }
    strcpy(pin->chip, chip);
    pin->offset = (int)off;
    return VP_OK;
}

static int vp_board_key(void *user, const char *section, const char *key, const char *val, int line, char *msg, size_t ml)
{
    vp_bctx_t *c = user;
    const vp_bkey_t *keys, *k;
    unsigned char *ptr;
    double v[6];
    int s, ki;
    if (!*key) { /* a section header */
        for (s = 0; s < NSEC; s++) if (!strcmp(section, sec_name[s])) break;
        if (s == NSEC) { snprintf(msg, ml, "unknown section (board, timing, axis.x|y|z|pan|tilt, estop, laser, head, camera, rangefinder, omega, sim, calibrate)"); return VP_EINVAL; }
        if (c->secline[s]) { snprintf(msg, ml, "section repeated (first at line %d)", c->secline[s]); return VP_EINVAL; }
        c->sec = s;
        c->secline[s] = line;
        return VP_OK;
    }
    if (c->sec < 0) { snprintf(msg, ml, "key outside any section"); return VP_EINVAL; }
    s = c->sec;
    keys = vp_sec_keys(s);
    for (ki = 0; keys[ki].name; ki++) if (!strcmp(keys[ki].name, key)) break;
    if (!keys[ki].name) { snprintf(msg, ml, "unknown key"); return VP_EINVAL; }
    k = &keys[ki];
    if (c->line[s][ki]) { snprintf(msg, ml, "set twice (first at line %d)", c->line[s][ki]); return VP_EINVAL; }
    c->line[s][ki] = line;
    ptr = vp_key_ptr(c, s, k);
    switch (k->type) {
    case K_NUM:
        VP_TRY(vp_numbers(val, v, 1, k->lo, k->hi, msg, ml));
        memcpy(ptr, v, sizeof(double));
        break;
    case K_NUMS:
        VP_TRY(vp_numbers(val, v, k->n, k->lo, k->hi, msg, ml));
        memcpy(ptr, v, (size_t)k->n * sizeof(double));
        if (!strcmp(key, "focal_px")) c->b->cam_model.fy = v[0];
        break;
    case K_RANGE:
        VP_TRY(vp_numbers(val, v, 2, k->lo, k->hi, msg, ml));
        if (!(v[0] < v[1])) { snprintf(msg, ml, "expected MIN, MAX with MIN below MAX, got '%s'", val); return VP_EINVAL; }
        memcpy(ptr, v, 2 * sizeof(double));
        break;
    case K_BOX:
        VP_TRY(vp_numbers(val, v, 6, k->lo, k->hi, msg, ml));
        if (!(v[0] < v[3] && v[1] < v[4] && v[2] < v[5])) { snprintf(msg, ml, "expected XLO, YLO, ZLO, XHI, YHI, ZHI with each LO below its HI"); return VP_EINVAL; }
        memcpy(c->b->omega_lo, v, 3 * sizeof(double));
        memcpy(c->b->omega_hi, v + 3, 3 * sizeof(double));
        c->b->omega_kind = VP_OMEGA_BOX;
        break;
    case K_BALL:
        VP_TRY(vp_numbers(val, v, 4, k->lo, k->hi, msg, ml));
        if (!(v[3] > 0)) { snprintf(msg, ml, "expected X, Y, Z, RADIUS with a positive radius"); return VP_EINVAL; }
        memcpy(c->b->omega_center, v, 3 * sizeof(double));
        c->b->omega_radius = v[3];
        c->b->omega_kind = VP_OMEGA_BALL;
        break;
    case K_INT: {
        int iv;
        VP_TRY(vp_numbers(val, v, 1, k->lo, k->hi, msg, ml));
        if (v[0] != floor(v[0])) { snprintf(msg, ml, "expected a whole number, got '%s'", val); return VP_EINVAL; }
        iv = (int)v[0];
        memcpy(ptr, &iv, sizeof iv);
        break;
    }
    case K_BOOL: {
        int iv;
        if (!strcmp(val, "yes") || !strcmp(val, "true") || !strcmp(val, "1")) iv = 1;
        else if (!strcmp(val, "no") || !strcmp(val, "false") || !strcmp(val, "0")) iv = 0;
        else { snprintf(msg, ml, "expected yes or no, got '%s'", val); return VP_EINVAL; }
        memcpy(ptr, &iv, sizeof iv);
        break;
    }
    case K_HOME: {
        int iv;
        if (!strcmp(val, "min")) iv = -1;
        else if (!strcmp(val, "max")) iv = 1;
        else if (!strcmp(val, "none")) iv = 0;
        else { snprintf(msg, ml, "expected min, max or none, got '%s'", val); return VP_EINVAL; }
        memcpy(ptr, &iv, sizeof iv);
        break;
    }
    case K_IO: {
        int iv;
        if (!strcmp(val, "gpiod")) iv = VP_BOARD_IO_GPIOD;
        else if (!strcmp(val, "sim")) iv = VP_BOARD_IO_SIM;
        else { snprintf(msg, ml, "expected gpiod or sim, got '%s'", val); return VP_EINVAL; }
        memcpy(ptr, &iv, sizeof iv);
        break;
    }
    case K_FMT: {
        unsigned f;
        if (!strcmp(val, "GREY")) f = VP_FOURCC('G', 'R', 'E', 'Y');
        else if (!strcmp(val, "YUYV")) f = VP_FOURCC('Y', 'U', 'Y', 'V');
        else if (!strcmp(val, "RGB24")) f = VP_FOURCC('R', 'G', 'B', '3');
        else if (!strcmp(val, "BGR24")) f = VP_FOURCC('B', 'G', 'R', '3');
        else if (!strcmp(val, "auto")) f = 0;
        else { snprintf(msg, ml, "expected GREY, YUYV, RGB24, BGR24 or auto, got '%s'", val); return VP_EINVAL; }
        memcpy(ptr, &f, sizeof f);
        break;
    }
    case K_PIN:
        if (!strcmp(key, "contact") && !strcmp(val, "sim")) { c->b->contact_sim = 1; break; }
        VP_TRY(vp_pin(val, (vp_gpio_pin_t *)(void *)ptr, msg, ml));
        break;
    case K_STR:
        if (strlen(val) >= (size_t)k->n) { snprintf(msg, ml, "longer than %d characters", k->n - 1); return VP_EINVAL; }
        strcpy((char *)ptr, val);
        if (!strcmp(key, "backend") && strcmp(val, "v4l2") && strcmp(val, "libcamera")) {
            snprintf(msg, ml, "expected v4l2 or libcamera, got '%s'", val);
            return VP_EINVAL;
        }
        if (!strcmp(key, "log_sync")) {
            vp_logwriter_config_t lc;
            if (vp_logwriter_parse_sync(val, &lc)) {
                snprintf(msg, ml, "expected record, close, N (records), Tms or N,Tms; got '%s'", val);
                return VP_EINVAL;
            }
        }
        if (!strcmp(key, "calibration") && !*val) { snprintf(msg, ml, "expected a file name"); return VP_EINVAL; }
        if (!strcmp(key, "on_late")) {
            if (strcmp(val, "reenter") && strcmp(val, "fault")) {
                snprintf(msg, ml, "expected reenter or fault, got '%s'", val);
                return VP_EINVAL;
            }
            c->b->late_fault = !strcmp(val, "fault");
        }
        if (!strcmp(key, "laser_colour")) {
            int ch = vp_cam_colour_parse(val);
            if (ch < 0) { snprintf(msg, ml, "expected red, green, blue or luma, got '%s'", val); return VP_EINVAL; }
            c->b->camera.colour = ch;
        }
        if (!strcmp(key, "clear_by")) {
            if (strcmp(val, "ball") && strcmp(val, "swept")) {
                snprintf(msg, ml, "expected ball or swept, got '%s'", val);
                return VP_EINVAL;
            }
            c->b->clear_swept = !strcmp(val, "swept");
        }
        if (!strcmp(key, "contact_by")) {
            if (strcmp(val, "stylus") && strcmp(val, "mount")) {
                snprintf(msg, ml, "expected stylus or mount, got '%s'", val);
                return VP_EINVAL;
            }
            c->b->contact_mount = !strcmp(val, "mount");
        }
        if (!strcmp(key, "laser")) {
            if (strcmp(val, "dot") && strcmp(val, "line")) {
                snprintf(msg, ml, "expected dot or line, got '%s'", val);
                return VP_EINVAL;
            }
            c->b->line_laser = !strcmp(val, "line");
        }
        if (!strcmp(key, "near_spots")) {
            if (strcmp(val, "too-close") && strcmp(val, "measure")) {
                snprintf(msg, ml, "expected too-close or measure, got '%s'", val);
                return VP_EINVAL;
            }
            c->b->near_measure = !strcmp(val, "measure");
        }
        break;
    }
    return VP_OK;
}

/* ---- the machine as a whole ---- */

static int vp_key_index(int s, const char *key)
{
    const vp_bkey_t *k = vp_sec_keys(s);
    int i;
    for (i = 0; k[i].name; i++) if (!strcmp(k[i].name, key)) return i;
    return -1;
}

static int vp_seen(const vp_bctx_t *c, int s, const char *key) { return c->line[s][vp_key_index(s, key)]; }

/* "file:line: [section] key: reason" for a key (its line, or the section's when unset) */
static int vp_bad(const vp_bctx_t *c, int s, const char *key, char *err, size_t el, const char *fmt, ...)
{
    char msg[700];
    va_list ap;
    int line = key ? vp_seen(c, s, key) : 0;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (!line) line = c->secline[s];
    if (key) snprintf(err, el, "%s:%d: [%s] %s: %s", c->name, line, sec_name[s], key, msg);
    else snprintf(err, el, "%s:%d: [%s]: %s", c->name, line, sec_name[s], msg);
    return VP_EINVAL;
}

typedef struct vp_pinuse { const vp_gpio_pin_t *pin; int sec; const char *key; int out; } vp_pinuse_t;

static int vp_board_pins(const vp_bctx_t *c, char *err, size_t el)
{
    static const char *const pk[5] = { "step", "dir", "enable", "limit_min", "limit_max" };
    vp_pinuse_t u[32];
    const vp_board_t *b = c->b;
    int n = 0, i, j, a;
    for (a = 0; a < VP_BOARD_AXES; a++) {
        const vp_gpio_pin_t *p[5] = { &b->axis[a].step, &b->axis[a].dir, &b->axis[a].enable, &b->axis[a].lim_min, &b->axis[a].lim_max };
        for (i = 0; i < 5; i++) {
            if (!p[i]->chip[0]) continue;
            u[n].pin = p[i]; u[n].sec = S_AX0 + a; u[n].key = pk[i]; u[n].out = i < 3; n++;
        }
    }
    if (b->estop.chip[0]) { u[n].pin = &b->estop; u[n].sec = S_ESTOP; u[n].key = "pin"; u[n].out = 0; n++; }
    if (b->laser.chip[0]) { u[n].pin = &b->laser; u[n].sec = S_LASER; u[n].key = "pin"; u[n].out = 1; n++; }
    if (b->contact.chip[0]) { u[n].pin = &b->contact; u[n].sec = S_HEAD; u[n].key = "contact"; u[n].out = 0; n++; }
    for (i = 0; i < n; i++)
        for (j = 0; j < i; j++) {
            if (strcmp(u[i].pin->chip, u[j].pin->chip) || u[i].pin->offset != u[j].pin->offset) continue;
            /* one enable line for several drivers is normal */
            if (!strcmp(u[i].key, "enable") && !strcmp(u[j].key, "enable") && u[i].pin->active_low == u[j].pin->active_low) continue;
            return vp_bad(c, u[i].sec, u[i].key, err, el, "%s:%d is already [%s] %s (line %d)", u[i].pin->chip, u[i].pin->offset,
                          sec_name[u[j].sec], u[j].key, vp_seen(c, u[j].sec, u[j].key));
        }
    return VP_OK;
}

/* Every required section and key is there (with io = gpiod: the pins and the e-stop too). */
static int vp_board_check_keys(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    const vp_bkey_t *k;
    int s, ki;
    for (s = 0; s < NSEC; s++) {
        k = vp_sec_keys(s);
        if (!c->secline[s]) {
            if (sec_required[s]) { snprintf(err, el, "%s: missing section [%s]", c->name, sec_name[s]); return VP_EINVAL; }
            if (s == S_ESTOP && b->io == VP_BOARD_IO_GPIOD) {
                snprintf(err, el, "%s: missing section [estop]: a board that drives motors needs an e-stop input", c->name);
                return VP_EINVAL;
            }
            continue;
        }
        for (ki = 0; k[ki].name; ki++)
            if (!c->line[s][ki] && (k[ki].req == R_YES || (k[ki].req == R_GPIO && b->io == VP_BOARD_IO_GPIOD))) {
                snprintf(err, el, "%s:%d: [%s] missing key '%s'%s", c->name, c->secline[s], sec_name[s], k[ki].name,
                         k[ki].req == R_GPIO ? " (needed with io = gpiod)" : "");
                return VP_EINVAL;
            }
    }
    return VP_OK;
}

/* The axes: homing speeds and positions, step rates, the pins a driven axis needs. */
static int vp_board_check_axes(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    int s, a;
    for (a = 0; a < VP_BOARD_AXES; a++) {
        vp_board_axis_t *x = &b->axis[a];
        vp_step_axis_t *ax = &x->ax;
        double rest, seek;
        s = S_AX0 + a;
        if (!ax->home_pulloff) ax->home_pulloff = 1;
        seek = ax->home_seek ? ax->home_seek : ax->max_speed / 4;
        if (ax->home_seek > ax->max_speed) return vp_bad(c, s, "home_seek", err, el, "faster than max_speed (%g %s/s)", ax->max_speed, axis_unit[a]);
        if (ax->home_feed > seek) return vp_bad(c, s, "home_feed", err, el, "faster than home_seek (%g %s/s)", seek, axis_unit[a]);
        if (ax->home_dir && !vp_seen(c, s, "home_pos")) return vp_bad(c, s, "home", err, el, "needs home_pos (where the switch closes)");
        rest = ax->home_pos - ax->home_dir * ax->home_pulloff;
        if (rest < ax->travel_min || rest > ax->travel_max)
            return vp_bad(c, s, "home_pos", err, el, "%s the axis rests at %g %s, outside travel %g..%g",
                          ax->home_dir ? "after the pull-off" : "at power-on", rest, axis_unit[a], ax->travel_min, ax->travel_max);
        if (b->max_step_rate > 0 && ax->max_speed * ax->steps_per_unit > b->max_step_rate)
            return vp_bad(c, s, "max_speed", err, el, "%g %s/s is %g steps/s, above [timing] max_step_rate %g", ax->max_speed,
                          axis_unit[a], ax->max_speed * ax->steps_per_unit, b->max_step_rate);
        if (b->io == VP_BOARD_IO_GPIOD && ax->home_dir < 0 && !x->lim_min.chip[0])
            return vp_bad(c, s, "home", err, el, "homing to min needs a limit_min pin");
        if (b->io == VP_BOARD_IO_GPIOD && ax->home_dir > 0 && !x->lim_max.chip[0])
            return vp_bad(c, s, "home", err, el, "homing to max needs a limit_max pin");
        if (b->io == VP_BOARD_IO_GPIOD && (!x->step.chip[0] || !x->dir.chip[0]))
            return vp_bad(c, s, x->step.chip[0] ? "dir" : "step", err, el, "a driven axis needs this pin");
    }
    if (b->io == VP_BOARD_IO_GPIOD) {
        if (!b->estop.chip[0]) return vp_bad(c, S_ESTOP, "pin", err, el, "a board that drives motors needs an e-stop input");
        VP_TRY(vp_board_pins(c, err, el));
    }
    return VP_OK;
}

/* The camera: focal length, centre and aim; the camera as mounted on the simulated head. */
static int vp_board_check_camera(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    if (!b->cam_model.fx || !b->cam_model.fy) return vp_bad(c, S_CAMERA, NULL, err, el, "missing key 'focal_px' (or fx and fy)");
    if (!vp_seen(c, S_CAMERA, "center")) {
        b->cam_model.cx = (b->cam_model.width - 1) / 2.0;
        b->cam_model.cy = (b->cam_model.height - 1) / 2.0;
    }
    if (vp_camera_look_at(&b->cam_model, b->look_at, b->up) != VP_OK)
        return vp_bad(c, S_CAMERA, "look_at", err, el, "must differ from position and not lie along 'up' from it");
    /* host-sim's faults: contrast, depth and albedo are fractions */
    if (b->sim_speckle[0] > 1 || (b->sim_speckle[0] > 0 && !(b->sim_speckle[1] > 0)))
        return vp_bad(c, S_SIM, "speckle", err, el, "expected CONTRAST (0..1), F-NUMBER (positive)");
    if (vp_seen(c, S_SIM, "vibration") && (b->sim_vibration[0] < 0 || !(b->sim_vibration[1] > 0) || !(b->sim_vibration[2] > 0)))
        return vp_bad(c, S_SIM, "vibration", err, el, "expected PX (>= 0), HZ (positive), DECAY_MS (positive), DEGREES");
    if (b->sim_flicker[0] > 1 || (b->sim_flicker[0] > 0 && !(b->sim_flicker[1] > 0)))
        return vp_bad(c, S_SIM, "flicker", err, el, "expected DEPTH (0..1), HZ (positive)");
    if (vp_seen(c, S_SIM, "glint") && (b->sim_glint[0] < 0 || b->sim_glint[0] > 255 || !(b->sim_glint[1] > 0) ||
                                       !(b->sim_glint[2] > 0) || !(b->sim_glint[5] > 0)))
        return vp_bad(c, S_SIM, "glint", err, el, "expected PEAK (0..255), SIGMA_PX, DIST_MM, ACROSS_PX, SWING_PX, PERIOD_MS");
    if (vp_seen(c, S_SIM, "dark") && !(b->sim_dark[0] > 0 && b->sim_dark[0] <= 1 && b->sim_dark[1] < b->sim_dark[2]))
        return vp_bad(c, S_SIM, "dark", err, el, "expected ALBEDO (above 0, at most 1), Z_LO, Z_HI (the object is dark between)");
    /* the camera as mounted on the simulated head: the model unless [sim] moves it */
    b->sim_cam = b->cam_model;
    if (vp_seen(c, S_SIM, "camera_position")) memcpy(b->sim_cam.pos, b->sim_cam_pos, sizeof b->sim_cam.pos);
    else memcpy(b->sim_cam_pos, b->cam_model.pos, sizeof b->sim_cam_pos);
    if (!vp_seen(c, S_SIM, "camera_look_at")) memcpy(b->sim_cam_look, b->look_at, sizeof b->sim_cam_look);
    if (vp_seen(c, S_SIM, "distortion")) memcpy(b->sim_cam.dist, b->sim_dist, sizeof b->sim_cam.dist);
    else memcpy(b->sim_dist, b->cam_model.dist, sizeof b->sim_dist);
    if (!vp_seen(c, S_SIM, "laser_origin")) memcpy(b->sim_laser_origin, b->laser_offset, sizeof b->sim_laser_origin);
    if (!(b->sim_laser_error[0] >= 0 && b->sim_laser_error[0] <= 30))
        return vp_bad(c, S_SIM, "laser_error", err, el, "the angle (first number) must be 0..30 degrees");
    if (vp_camera_look_at(&b->sim_cam, b->sim_cam_look, b->up) != VP_OK)
        return vp_bad(c, S_SIM, vp_seen(c, S_SIM, "camera_look_at") ? "camera_look_at" : "camera_position", err, el,
                      "the camera must not look along 'up' nor at its own position");
    return VP_OK;
}

/* The rangefinder: its range, and its model from a calibration or from the camera geometry. */
static int vp_board_check_range(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    int rc;
    if (!(b->min_range < b->max_range)) return vp_bad(c, S_RANGE, "max_range", err, el, "must be above min_range (%g)", b->min_range);
    if (!vp_seen(c, S_RANGE, "fan")) b->line_fan = 30.0;
    if (!vp_seen(c, S_RANGE, "fan_used")) b->line_fan_used = b->line_fan;
    if (b->line_fan_used > b->line_fan) return vp_bad(c, S_RANGE, "fan_used", err, el, "must be at most fan (%g degrees)", b->line_fan);
    if (!vp_seen(c, S_RANGE, "line_normal")) { b->line_normal[0] = b->line_normal[1] = 0.0; b->line_normal[2] = 1.0; }
    if (b->line_laser) {
        double nl = sqrt(vp_dot3(b->line_normal, b->line_normal));
        if (!(nl > 0)) return vp_bad(c, S_RANGE, "line_normal", err, el, "must not be 0, 0, 0");
        if (b->confirm_spot)
            return vp_bad(c, S_RANGE, "confirm_spot", err, el, "a line laser has no spot to confirm (its detector refuses "
                          "columns lit with the laser off)");
        if (fabs(b->line_normal[0]) > 1e-3 * nl)
            return vp_bad(c, S_RANGE, "line_normal", err, el, "must be at right angles to the beam (+x): the fan holds the beam");
        if (!b->laser.chip[0])
            return vp_bad(c, S_RANGE, "laser", err, el, "a line laser is read from a laser-off / laser-on frame pair: "
                          "the board needs [laser] pin");
    }
    if (!!vp_seen(c, S_RANGE, "line") != !!vp_seen(c, S_RANGE, "model"))
        return vp_bad(c, S_RANGE, vp_seen(c, S_RANGE, "line") ? "line" : "model", err, el, "a calibration needs both line and model");
    if (vp_seen(c, S_RANGE, "line")) {
        double len = sqrt(b->line[2] * b->line[2] + b->line[3] * b->line[3]);
        if (!(len > 0.5 && len < 2)) return vp_bad(c, S_RANGE, "line", err, el, "the direction (3rd, 4th numbers) must be a unit vector");
        memset(&b->tri, 0, sizeof b->tri);
        b->tri.p0[0] = b->line[0]; b->tri.p0[1] = b->line[1];
        b->tri.e[0] = b->line[2] / len; b->tri.e[1] = b->line[3] / len;
        b->tri.a = b->model[0]; b->tri.b = b->model[1]; b->tri.c = b->model[2];
        b->tri.line_tol = 3;
        b->tri.min_range = b->min_range;
        b->tri.max_range = b->max_range;
        b->calibrated = 1;
    } else {
        rc = vp_tri_from_geometry(&b->cam_model, b->laser_offset, b->min_range, b->max_range, &b->tri);
        if (rc != VP_OK) return vp_bad(c, S_CAMERA, "look_at", err, el, "the camera does not see the beam between min_range and max_range");
        if (b->tri.max_range - b->tri.min_range < 0.2 * (b->max_range - b->min_range))
            return vp_bad(c, S_CAMERA, "look_at", err, el, "the beam is in view only from %.0f to %.0f mm", b->tri.min_range, b->tri.max_range);
        b->calibrated = 0;
    }
    return VP_OK;
}

/* The calibration fixture ([calibrate]): stations within the rangefinder's range. */
static int vp_board_check_fixture(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    if (c->secline[S_CALIB]) {
        b->have_fixture = 1;
        if (!vp_seen(c, S_CALIB, "near")) b->cal_near = 1.5 * b->min_range;
        if (!vp_seen(c, S_CALIB, "far")) b->cal_far = b->max_range < 200 ? b->max_range : 200;
        if (!vp_seen(c, S_CALIB, "stations")) b->cal_stations = 20;
        if (!vp_seen(c, S_CALIB, "frames")) b->cal_frames = 3;
        b->have_mark = vp_seen(c, S_CALIB, "mark") != 0;
        if (!(b->cal_near < b->cal_far)) return vp_bad(c, S_CALIB, "far", err, el, "must be above near (%g mm)", b->cal_near);
        if (b->cal_near < b->min_range || b->cal_far > b->max_range)
            return vp_bad(c, S_CALIB, b->cal_near < b->min_range ? "near" : "far", err, el,
                          "the stations must lie within the rangefinder's range %g..%g mm", b->min_range, b->max_range);
        if (b->cal_stations * b->cal_frames > 256)
            return vp_bad(c, S_CALIB, "frames", err, el, "stations x frames is %d, at most 256", b->cal_stations * b->cal_frames);
    }
    return VP_OK;
}

/* The ball about Omega's centre oc within which the laser origin stays: the planner's detours
 * outside Omega may go round its circumsphere (1.01 times its radius, hugging dOmega 1% of it
 * away; 1.02 allowed), or at the start's distance. Returns 1 when the start's distance decides. */
static int vp_board_origin_ball(const vp_board_t *b, double oc[3], double *lim)
{
    double rcirc = 0, rs = 0;
    int k;
    for (k = 0; k < 3; k++) {
        double lo = b->omega_kind == VP_OMEGA_BOX ? b->omega_lo[k] : b->omega_center[k] - b->omega_radius;
        double hi = b->omega_kind == VP_OMEGA_BOX ? b->omega_hi[k] : b->omega_center[k] + b->omega_radius;
        oc[k] = 0.5 * (lo + hi);
        rcirc += 0.25 * (hi - lo) * (hi - lo);
        rs += (b->start[k] - oc[k]) * (b->start[k] - oc[k]);
    }
    rcirc = b->omega_kind == VP_OMEGA_BALL ? b->omega_radius : sqrt(rcirc);
    rs = sqrt(rs);
    *lim = 1.02 * rcirc > rs ? 1.02 * rcirc : rs;
    return !(1.02 * rcirc >= rs);
}

/* Omega and the start, within reach of the head in any orientation (the planner's detours round
 * Omega included). */
static int vp_board_check_omega(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    vp_kin_t kin;
    vp_kin_config_t kc;
    if (!vp_seen(c, S_OMEGA, "box") == !vp_seen(c, S_OMEGA, "ball"))
        return vp_bad(c, S_OMEGA, vp_seen(c, S_OMEGA, "box") ? "ball" : NULL, err, el, "give exactly one of box and ball");
    vp_board_kin_config(b, &kc);
    if (vp_kin_init(&kin, &kc) != VP_OK) return vp_bad(c, S_HEAD, NULL, err, el, "bad head geometry");
    {
        double lo[3], hi[3], reach = kin.reach;
        int k;
        const char *key = b->omega_kind == VP_OMEGA_BOX ? "box" : "ball";
        for (k = 0; k < 3; k++) {
            lo[k] = b->omega_kind == VP_OMEGA_BOX ? b->omega_lo[k] : b->omega_center[k] - b->omega_radius;
            hi[k] = b->omega_kind == VP_OMEGA_BOX ? b->omega_hi[k] : b->omega_center[k] + b->omega_radius;
            if (lo[k] - reach < b->axis[k].ax.travel_min || hi[k] + reach > b->axis[k].ax.travel_max)
                return vp_bad(c, S_OMEGA, key, err, el, "%c from %g to %g is not within %s travel %g..%g less the head's reach %.1f mm",
                              "xyz"[k], lo[k], hi[k], sec_name[S_AX0 + k], b->axis[k].ax.travel_min, b->axis[k].ax.travel_max, reach);
        }
        if (!vp_seen(c, S_OMEGA, "interior"))
            for (k = 0; k < 3; k++) b->interior[k] = 0.5 * (lo[k] + hi[k]);
        {
            int inside_s = 1, inside_i = 1;
            double ds = 0, di = 0;
            for (k = 0; k < 3; k++) {
                if (b->omega_kind == VP_OMEGA_BOX) {
                    if (b->start[k] <= lo[k] || b->start[k] >= hi[k]) inside_s = 0;
                    if (b->interior[k] <= lo[k] || b->interior[k] >= hi[k]) inside_i = 0;
                }
                ds += (b->start[k] - b->omega_center[k]) * (b->start[k] - b->omega_center[k]);
                di += (b->interior[k] - b->omega_center[k]) * (b->interior[k] - b->omega_center[k]);
            }
            if (b->omega_kind == VP_OMEGA_BALL) { inside_s = ds < b->omega_radius * b->omega_radius; inside_i = di < b->omega_radius * b->omega_radius; }
            if (inside_s) return vp_bad(c, S_OMEGA, "start", err, el, "the device must start outside Omega");
            if (!inside_i) return vp_bad(c, S_OMEGA, "interior", err, el, "must lie inside Omega");
            for (k = 0; k < 3; k++)
                if (b->start[k] - reach < b->axis[k].ax.travel_min || b->start[k] + reach > b->axis[k].ax.travel_max)
                    return vp_bad(c, S_OMEGA, "start", err, el, "%c = %g is beyond %s travel less the head's reach", "xyz"[k], b->start[k], sec_name[S_AX0 + k]);
        }
        {
            /* the planner's detours round Omega: all of them must be within reach */
            double oc[3], lim;
            int by_start = vp_board_origin_ball(b, oc, &lim);
            for (k = 0; k < 3; k++)
                if (oc[k] - lim - reach < b->axis[k].ax.travel_min || oc[k] + lim + reach > b->axis[k].ax.travel_max)
                    return vp_bad(c, S_OMEGA, key, err, el, "the planner's detours round Omega reach %.1f mm from its centre "
                                  "(%s): %c from %.1f to %.1f is not within %s travel %g..%g less the head's reach %.1f mm; "
                                  "use a smaller %s", lim, by_start ? "the start's distance" : "1.02 x its circumradius",
                                  "xyz"[k], oc[k] - lim, oc[k] + lim, sec_name[S_AX0 + k], b->axis[k].ax.travel_min,
                                  b->axis[k].ax.travel_max, reach, b->omega_kind == VP_OMEGA_BOX ? "box, or a ball" : "ball");
        }
    }
    return VP_OK;
}

/* The backdrop: the walls must lie beyond everywhere the head can go (each axis's travel, plus
 * the laser origin's distance from the carriage and the body's from the origin: homing runs to
 * the travel's ends) and within the rangefinder's range of every place the laser origin probes
 * from (Omega and the detours round it, the start), so that a beam meeting nothing shows its
 * spot on a wall; a frame with no spot then means the spot was hidden or the surface it fell on
 * returned too little light, never empty space. */
static int vp_board_check_backdrop(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    vp_kin_config_t kc;
    vp_kin_t kin;
    double oc[3], lim, far = 0;
    int k;
    b->have_backdrop = vp_seen(c, S_RANGE, "backdrop") != 0;
    if (!b->have_backdrop) return VP_OK;
    vp_board_kin_config(b, &kc);
    if (vp_kin_init(&kin, &kc) != VP_OK) return vp_bad(c, S_HEAD, NULL, err, el, "bad head geometry");
    for (k = 0; k < 3; k++)
        if (!(b->backdrop[k] < b->backdrop[3 + k]))
            return vp_bad(c, S_RANGE, "backdrop", err, el, "expected XLO, YLO, ZLO, XHI, YHI, ZHI with each LO below its HI");
    for (k = 0; k < 3; k++) {
        /* the head: the carriage anywhere in its travel, the body round it */
        double body = kin.reach + b->head_reach;
        if (b->backdrop[k] > b->axis[k].ax.travel_min - body || b->backdrop[3 + k] < b->axis[k].ax.travel_max + body)
            return vp_bad(c, S_RANGE, "backdrop", err, el, "%c from %g to %g: the walls must lie beyond %s travel %g..%g "
                          "plus the head (%.1f mm: the laser origin %.1f from the carriage, the body %.1f from it)",
                          "xyz"[k], b->backdrop[k], b->backdrop[3 + k], sec_name[S_AX0 + k], b->axis[k].ax.travel_min,
                          b->axis[k].ax.travel_max, body, kin.reach, b->head_reach);
    }
    vp_board_origin_ball(b, oc, &lim);
    for (k = 0; k < 3; k++) {
        double a = oc[k] - b->backdrop[k], z = b->backdrop[3 + k] - oc[k];
        far += (a > z ? a : z) * (a > z ? a : z);
    }
    /* the laser origin within lim of Omega's centre, a wall point within the far corner's distance */
    far = sqrt(far) + lim;
    if (far > b->tri.max_range)
        return vp_bad(c, S_RANGE, "backdrop", err, el, "its far corner can lie %.1f mm from the laser origin, beyond "
                      "the rangefinder's range (%g mm): a beam meeting nothing would show no spot there", far,
                      b->tri.max_range);
    return VP_OK;
}

int vp_board_has_contact(const vp_board_t *b) { return b && (b->contact.chip[0] || b->contact_sim); }

#define VP_BOARD_BALL_PART "clearance ball"
int vp_board_part_is_ball(const vp_board_t *b, int i)
{
    return b && i >= 0 && i < b->head.nparts && !strcmp(b->head.part[i].name, VP_BOARD_BALL_PART);
}

/* The contact switch: the head must stop within the stylus's overtravel (contact_stop). A MOVE
 * translates x, y, z together; its stop from a touch is at most vp_step_contact_reach over them
 * (the deceleration from the fastest coordinated speed, |V| max_i(V_i / A_i) / 2, plus the
 * debounce samples' steps). */
static int vp_board_check_contact(vp_bctx_t *c, char *err, size_t el)
{
    static const int xyz[3] = { 0, 1, 2 };
    vp_board_t *b = c->b;
    vp_step_config_t sc;
    double speed;
    if (b->contact_sim && b->io != VP_BOARD_IO_SIM)
        return vp_bad(c, S_HEAD, "contact", err, el, "'sim' is the dry run's switch: a board with io = gpiod needs a pin");
    if (!vp_board_has_contact(b)) {
        const char *k = vp_seen(c, S_HEAD, "contact_stop") ? "contact_stop" : vp_seen(c, S_HEAD, "contact_halt") ?
                        "contact_halt" : vp_seen(c, S_HEAD, "contact_by") ? "contact_by" : NULL;
        if (k) return vp_bad(c, S_HEAD, k, err, el, "needs a contact switch ([head] contact = PIN)");
        return VP_OK;
    }
    /* a mount's switch says that some part touched, not where: only a head kept outside Omega,
     * where any touch stops the scan, can take it (the planner reads a stylus's touch as a point
     * of the surface at the laser origin) */
    if (b->contact_mount && (!(b->clearance > 0) || b->min_feature > 0))
        return vp_bad(c, S_HEAD, "contact_by", err, el, "a mount's switch does not tell where the head touched: it needs "
                      "the head kept outside Omega ([omega] clearance > 0%s), where a touch stops the scan",
                      b->min_feature > 0 ? " and no tubes inside it: min_feature = 0" : "");
    vp_board_step_config(b, &sc);
    b->contact_reach = vp_step_contact_reach(&sc, xyz, 3, &speed);
    if (b->contact_stop > 0 && b->contact_stop < b->contact_reach)
        return vp_bad(c, S_HEAD, "contact_stop", err, el,
                      "%g mm is below the head's stop from a touch, %.3f mm: a MOVE at full speed on x, y and z "
                      "(%.1f mm/s) decelerates over |V| max(V_i/A_i)/2%s, and %d debounce samples add up to a step "
                      "each; lower max_speed, raise accel%s", b->contact_stop, b->contact_reach, speed,
                      b->contact_halt ? " (0: contact_halt)" : "", b->debounce,
                      b->contact_halt ? "" : " or set contact_halt = yes");
    return VP_OK;
}

/* One body part as written: a capsule X1, Y1, Z1, X2, Y2, Z2, R or a box CX, CY, CZ, HX, HY, HZ
 * (centre and half-sizes along the frame's axes), or none. The default when unset: def (NULL:
 * no part). Returns VP_OK with *have = 0 for none. */
static int vp_board_part(vp_bctx_t *c, const char *key, const char *val, int kind, const double *def, int *have,
                         double v[7], char *err, size_t el)
{
    char msg[200];
    int n = kind == VP_HEAD_BOX ? 6 : 7, k;
    *have = 0;
    if (!vp_seen(c, S_HEAD, key)) {
        if (!def) return VP_OK;
        memcpy(v, def, (size_t)n * sizeof *v);
        *have = 1;
        return VP_OK;
    }
    if (!strcmp(val, "none")) return VP_OK;
    if (vp_numbers(val, v, n, -1e4, 1e4, msg, sizeof msg) != VP_OK)
        return vp_bad(c, S_HEAD, key, err, el, "%s (%s, or none)", msg,
                      kind == VP_HEAD_BOX ? "a box: CX, CY, CZ, HX, HY, HZ in the tilt frame" : "a capsule: X1, Y1, Z1, X2, Y2, Z2, R");
    if (kind == VP_HEAD_BOX) {
        for (k = 3; k < 6; k++)
            if (!(v[k] > 0)) return vp_bad(c, S_HEAD, key, err, el, "the half-sizes HX, HY, HZ must be positive");
    } else if (!(v[6] > 0)) return vp_bad(c, S_HEAD, key, err, el, "the radius R must be positive");
    *have = 1;
    return VP_OK;
}

/* The head's body, and the ball rule: every part within the clearance ball about the laser
 * origin in every pose (the planner keeps that origin outside Omega and the board puts the
 * object at least the clearance inside it), unless an io = sim board checks every motion
 * against its simulated object instead (clear_by = swept). */
static int vp_board_check_head(vp_bctx_t *c, char *err, size_t el)
{
    static const char *const key[4] = { "laser_body", "camera_body", "bracket", "hub" };
    static const char *const part[4] = { "laser", "camera", "bracket", "tilt hub" };
    vp_board_t *b = c->b;
    const char *val[4];
    double def[4][7], v[7], zero[3] = { 0, 0, 0 }, dxyz = 0, dang = 0, far[VP_HEAD_MAX_PARTS];
    int i, k, have, a, worst;
    val[0] = b->body_laser; val[1] = b->body_camera; val[2] = b->body_bracket; val[3] = b->body_hub;
    /* the defaults: a 12 mm laser module 32 mm long behind its exit, a 25 mm board camera 20 mm
     * deep about its centre, a bracket from the tilt axis to the camera; no pan-frame part */
    for (k = 0; k < 3; k++) {
        def[0][k] = b->laser_offset[k] - (k == 0 ? 26 : 0);
        def[0][3 + k] = b->laser_offset[k] - (k == 0 ? 6 : 0);
        def[1][k] = b->cam_model.pos[k];
        def[1][3 + k] = k == 0 ? 10 : 12.5;
        def[2][k] = 0;
        def[2][3 + k] = b->cam_model.pos[k];
    }
    def[0][6] = 6;
    def[2][6] = 4;
    if (vp_head_init(&b->head, b->tilt_offset, b->laser_offset) != VP_OK) return vp_bad(c, S_HEAD, NULL, err, el, "bad head geometry");
    if (b->clearance > 0)
        vp_head_add(&b->head, VP_BOARD_BALL_PART, VP_HEAD_TILT, VP_HEAD_CAPSULE, b->laser_offset, b->laser_offset, b->clearance);
    for (i = 0; i < 4; i++) {
        int kind = i == 1 ? VP_HEAD_BOX : VP_HEAD_CAPSULE;
        VP_TRY(vp_board_part(c, key[i], val[i], kind, i < 3 ? def[i] : NULL, &have, v, err, el));
        if (!have) continue;
        vp_head_add(&b->head, part[i], i == 3 ? VP_HEAD_PAN : VP_HEAD_TILT, kind, v, v + 3, kind == VP_HEAD_BOX ? 0 : v[6]);
    }
    /* how far the true laser origin may be from the planner's: origin_tol while aiming, half a
     * step and the backlash of every axis (pan and tilt swing it by their angle times the reach) */
    for (a = 0; a < 3; a++) {
        double q = 0.5 / b->axis[a].ax.steps_per_unit + b->axis[a].ax.backlash;
        dxyz += q * q;
    }
    for (a = 3; a < 5; a++) dang += 0.5 / b->axis[a].ax.steps_per_unit + b->axis[a].ax.backlash;
    b->head_margin = b->origin_tol + sqrt(dxyz) + dang * (3.14159265358979323846 / 180.0) *
                     (vp_dist3(zero, b->tilt_offset) + vp_dist3(zero, b->laser_offset));
    /* the part reaching farthest decides; the others beyond the ball are named with it */
    b->head_reach = 0;
    worst = -1;
    for (i = 0; i < b->head.nparts; i++) {
        if (vp_board_part_is_ball(b, i)) continue;
        far[i] = vp_head_reach(&b->head, i, b->axis[4].ax.travel_min, b->axis[4].ax.travel_max);
        if (far[i] > b->head_reach) { b->head_reach = far[i]; worst = i; }
    }
    if (worst >= 0 && b->clearance > 0 && !b->clear_swept && b->head_reach + b->head_margin > b->clearance) {
        const vp_head_part_t *p = &b->head.part[worst];
        char also[200] = "";
        for (i = 0; i < b->head.nparts; i++) {
            size_t len = strlen(also);
            if (i == worst || vp_board_part_is_ball(b, i) || far[i] + b->head_margin <= b->clearance)
                continue;
            snprintf(also + len, sizeof also - len, "%s%s %.1f", len ? ", " : "; also beyond it: ", b->head.part[i].name,
                     far[i] + b->head_margin);
        }
        for (k = 0; k < 4; k++) if (!strcmp(part[k], p->name)) break;
        return vp_bad(c, S_HEAD, vp_seen(c, S_HEAD, key[k]) ? key[k] : NULL, err, el,
                      "the %s reaches %.1f mm from the laser origin (%.1f, plus %.2f for origin_tol, half a step and "
                      "the backlash), %.1f mm beyond the clearance ball ([omega] clearance %g)%s: nothing proves it clear of "
                      "the object; raise clearance to %.1f or more (the object must then lie that far inside Omega)%s%s%s",
                      p->name, b->head_reach + b->head_margin, b->head_reach, b->head_margin,
                      b->head_reach + b->head_margin - b->clearance, b->clearance, also, b->head_reach + b->head_margin,
                      b->io == VP_BOARD_IO_SIM ? ", or state clear_by = swept (io = sim: every motion checked against "
                      "the simulated object)" : "", vp_seen(c, S_HEAD, key[k]) ? "" : "; this is the default ",
                      vp_seen(c, S_HEAD, key[k]) ? "" : key[k]);
    }
    if (b->min_feature > 0) {
        /* tubes prove the clearance ball's way, nothing beyond it: the whole head inside it */
        if (!(b->clearance > 0))
            return vp_bad(c, S_OMEGA, "min_feature", err, el, "tubes inside Omega are for a head with a body: set "
                          "clearance (the ball about the laser origin that holds the whole head)");
        if (worst >= 0 && b->head_reach + b->head_margin > b->clearance)
            return vp_bad(c, S_OMEGA, "min_feature", err, el, "tubes inside Omega prove the clearance ball's way only, "
                          "and the %s reaches %.1f mm from the laser origin, beyond the clearance %g (clear_by = swept "
                          "does not help inside Omega: a dry run of a torus brought the camera into it): raise "
                          "clearance to %.1f or more, or set min_feature = 0", b->head.part[worst].name,
                          b->head_reach + b->head_margin, b->clearance, b->head_reach + b->head_margin);
        /* a tube is proven by misses round the head's way; a surface too dark for the camera reads
         * as a miss, and no switch guards the body (a mount's needs min_feature = 0, a stylus
         * guards the beam only): a miss must be a spot seen on the walls */
        if (!vp_seen(c, S_RANGE, "backdrop"))
            return vp_bad(c, S_OMEGA, "min_feature", err, el, "tubes inside Omega need [rangefinder] backdrop: they "
                          "are proven by misses round the head's way, and without the walls a surface too dark for "
                          "the camera reads as a miss where the head's body then goes (no switch guards the body); "
                          "declare the walls, or set min_feature = 0");
        if (!vp_seen(c, S_OMEGA, "feature_margin")) b->feature_margin = VP_FEATURE_MARGIN_DEFAULT * b->min_feature;
    }
    if (b->clear_swept && b->io != VP_BOARD_IO_SIM)
        return vp_bad(c, S_HEAD, "clear_by", err, el, "swept checks the simulated object only: a board that drives motors "
                      "(io = gpiod) needs the ball rule (clear_by = ball)");
    return VP_OK;
}

/* A loaded board, checked part by part; defaults filled in. */
static int vp_board_check(vp_bctx_t *c, char *err, size_t el)
{
    VP_TRY(vp_board_check_keys(c, err, el));
    VP_TRY(vp_board_check_axes(c, err, el));
    VP_TRY(vp_board_check_camera(c, err, el));
    VP_TRY(vp_board_check_range(c, err, el));
    VP_TRY(vp_board_check_fixture(c, err, el));
    VP_TRY(vp_board_check_contact(c, err, el));
    VP_TRY(vp_board_check_omega(c, err, el));
    VP_TRY(vp_board_check_head(c, err, el));
    return vp_board_check_backdrop(c, err, el);
}

static void vp_board_defaults(vp_board_t *b)
{
    int a;
    memset(b, 0, sizeof *b);
    for (a = 0; a < VP_BOARD_AXES; a++) {
        b->axis[a].step.offset = b->axis[a].dir.offset = b->axis[a].enable.offset = -1;
        b->axis[a].lim_min.offset = b->axis[a].lim_max.offset = -1;
    }
    b->estop.offset = b->laser.offset = b->contact.offset = -1;
    b->pulse_us = 4;
    b->dir_setup_us = 2;
    b->enable_ms = 2;
    b->poll_ms = 1;
    b->spin_us = 50;
    b->debounce = 3;
    b->max_late_us = 100;
    strcpy(b->on_late, "reenter");
    b->origin_tol = 0.1;
    strcpy(b->camera.backend, "v4l2");
    strcpy(b->camera.device, "/dev/video0");
    b->up[2] = 1;
    b->timeout_ms = 1000;
    b->latency_frames = 2;
    b->settle_ms = 20;
    b->sim_blur = 1.2;
    b->sim_noise = 2;
    b->sim_ambient = 30;
    b->sim_gradient = 20;
    b->sim_texture = 3;
    b->sim_energy = 6000;
    b->sim_seed = 1;
}

/* [rangefinder] calibration = FILE: relative to the board's folder; used when it exists */
static int vp_board_calib_key(vp_bctx_t *c, char *err, size_t el)
{
    vp_board_t *b = c->b;
    const char *slash = strrchr(c->name, '/');
    char path[VP_BOARD_PATH_MAX], sub[400];
    int rc, n;
    if (!b->calibration[0]) return VP_OK;
    if (b->calibration[0] == '/' || !slash) n = snprintf(path, sizeof path, "%s", b->calibration);
    else n = snprintf(path, sizeof path, "%.*s/%s", (int)(slash - c->name), c->name, b->calibration);
    if (n < 0 || (size_t)n >= sizeof path) return vp_bad(c, S_RANGE, "calibration", err, el, "path too long");
    if (access(path, F_OK) != 0) {   /* not opened to look: a pipe would wait for a writer */
        b->calib_missing = 1;
        snprintf(b->calib_path, sizeof b->calib_path, "%s", path);
        return VP_OK;
    }
    rc = vp_board_calibration_load(b, path, NULL, sub, sizeof sub);
    if (rc != VP_OK) return vp_bad(c, S_RANGE, "calibration", err, el, "%s", sub);
    return VP_OK;
}

static int vp_board_finish(vp_bctx_t *c, int rc, char *err, size_t el)
{
    if (rc != VP_OK) return rc;
    rc = vp_board_check(c, err, el);
    if (rc != VP_OK) return rc;
    return vp_board_calib_key(c, err, el);
}

int vp_board_parse(const char *text, const char *name, vp_board_t *b, char *err, size_t errlen)
{
    vp_bctx_t c;
    if (!text || !b) return VP_EINVAL;
    vp_board_defaults(b);
    memset(&c, 0, sizeof c);
    c.b = b;
    c.name = name ? name : "(board)";
    c.sec = -1;
    snprintf(b->path, sizeof b->path, "%s", c.name);
    return vp_board_finish(&c, vp_ini_parse_text(text, c.name, vp_board_key, &c, err, errlen), err, errlen);
}

int vp_board_load(const char *path, vp_board_t *b, char *err, size_t errlen)
{
    vp_bctx_t c;
    if (!path || !b) return VP_EINVAL;
    vp_board_defaults(b);
    memset(&c, 0, sizeof c);
    c.b = b;
    c.name = path;
    c.sec = -1;
    if (strlen(path) >= sizeof b->path) {
        snprintf(err, errlen, "the board path %.48s... is too long (%lu bytes, at most %lu)", path,
                 (unsigned long)strlen(path), (unsigned long)sizeof b->path - 1);
        return VP_EINVAL;
    }
    snprintf(b->path, sizeof b->path, "%s", path);
    return vp_board_finish(&c, vp_ini_parse_file(path, vp_board_key, &c, err, errlen), err, errlen);
}

/* ---- calibration files ---- */

typedef struct vp_cctx {
    vp_board_calib_t *info;
    int line_at, model_at, board_at;
    double line[4], model[3];
    int sec;                     /* 0 none, 1 [calibration], 2 [rangefinder] */
    /* the full model: camera (fx fy cx cy), distortion, camera_position, camera_rotation, beam
     * (origin, direction), beam_span, ray_tol_px; at[k] the line each was set on */
    double rf[4 + 4 + 3 + 9 + 6 + 2 + 1];
    int rf_at[7];
    double plane[6];             /* a line laser's plane: origin, normal */
    int plane_at;
} vp_cctx_t;

static const char *const rf_keys[7] = { "camera", "distortion", "camera_position", "camera_rotation", "beam", "beam_span",
                                        "ray_tol_px" };
static const int rf_count[7] = { 4, 4, 3, 9, 6, 2, 1 };

static int vp_calib_key(void *user, const char *section, const char *key, const char *val, int line, char *msg, size_t ml)
{
    vp_cctx_t *c = user;
    vp_board_calib_t *in = c->info;
    double v[4];
    (void)line;
    if (!*key) {
        if (!strcmp(section, "calibration")) c->sec = 1;
        else if (!strcmp(section, "rangefinder")) c->sec = 2;
        else { snprintf(msg, ml, "unknown section (calibration or rangefinder)"); return VP_EINVAL; }
        return VP_OK;
    }
    if (c->sec == 2) {
        if (!strcmp(key, "line")) { VP_TRY(vp_numbers(val, c->line, 4, -1e5, 1e5, msg, ml)); c->line_at = line; return VP_OK; }
        if (!strcmp(key, "model")) { VP_TRY(vp_numbers(val, c->model, 3, -1e9, 1e9, msg, ml)); c->model_at = line; return VP_OK; }
        if (!strcmp(key, "plane")) { VP_TRY(vp_numbers(val, c->plane, 6, -1e6, 1e6, msg, ml)); c->plane_at = line; return VP_OK; }
        {
            int k, off = 0;
            for (k = 0; k < 7; k++) {
                if (!strcmp(key, rf_keys[k])) {
                    VP_TRY(vp_numbers(val, c->rf + off, rf_count[k], -1e6, 1e6, msg, ml));
                    c->rf_at[k] = line;
                    return VP_OK;
                }
                off += rf_count[k];
            }
        }
        snprintf(msg, ml, "unknown key (a calibration file sets line and model, and for the full model camera, "
                          "distortion, camera_position, camera_rotation, beam, beam_span, ray_tol_px; a line laser's plane)");
        return VP_EINVAL;
    }
    if (c->sec != 1) { snprintf(msg, ml, "key outside any section"); return VP_EINVAL; }
    if (!strcmp(key, "board")) {
        if (strlen(val) >= sizeof in->board) { snprintf(msg, ml, "longer than %d characters", (int)sizeof in->board - 1); return VP_EINVAL; }
        strcpy(in->board, val);
        c->board_at = line;
        return VP_OK;
    }
    if (!strcmp(key, "span")) {
        VP_TRY(vp_numbers(val, v, 2, POS, 1e5, msg, ml));
        in->near = v[0];
        in->far = v[1];
        return VP_OK;
    }
    if (!strcmp(key, "spots") || !strcmp(key, "stations")) {
        VP_TRY(vp_numbers(val, v, 1, 0, 1e6, msg, ml));
        if (!strcmp(key, "spots")) in->spots = (int)v[0]; else in->stations = (int)v[0];
        return VP_OK;
    }
    if (!strcmp(key, "plane_points") || !strcmp(key, "plane_poses")) {
        VP_TRY(vp_numbers(val, v, 1, 0, 1e9, msg, ml));
        if (!strcmp(key, "plane_points")) in->plane_points = (int)v[0]; else in->plane_poses = (int)v[0];
        return VP_OK;
    }
    if (!strcmp(key, "plane_rms_mm") || !strcmp(key, "plane_max_mm") || !strcmp(key, "plane_tilt_deg")) {
        VP_TRY(vp_numbers(val, v, 1, 0, 1e9, msg, ml));
        if (!strcmp(key, "plane_rms_mm")) in->plane_rms_mm = v[0];
        else if (!strcmp(key, "plane_max_mm")) in->plane_max_mm = v[0];
        else in->plane_tilt_deg = v[0];
        return VP_OK;
    }
    if (!strcmp(key, "residual_rms_mm") || !strcmp(key, "residual_max_mm") || !strcmp(key, "line_rms_px")) {
        VP_TRY(vp_numbers(val, v, 1, 0, 1e9, msg, ml));
        if (key[0] == 'l') in->line_rms_px = v[0];
        else if (key[9] == 'r') in->rms_mm = v[0];
        else in->max_mm = v[0];
        return VP_OK;
    }
    snprintf(msg, ml, "unknown key");
    return VP_EINVAL;
}

int vp_board_calibration_load(vp_board_t *b, const char *path, vp_board_calib_t *info, char *err, size_t errlen)
{
    vp_board_calib_t scratch;
    vp_cctx_t c;
    double len;
    int rc;
    if (!b || !path) return VP_EINVAL;
    if (strlen(path) >= sizeof b->calib_path) {
        snprintf(err, errlen, "the calibration path %.48s... is too long (%lu bytes, at most %lu)", path,
                 (unsigned long)strlen(path), (unsigned long)sizeof b->calib_path - 1);
        return VP_EINVAL;
    }
    memset(&c, 0, sizeof c);
    memset(&scratch, 0, sizeof scratch);
    c.info = info ? info : &scratch;
    memset(c.info, 0, sizeof *c.info);
    rc = vp_ini_parse_file(path, vp_calib_key, &c, err, errlen);
    if (rc != VP_OK) return rc;
    if (!c.line_at || !c.model_at) {
        snprintf(err, errlen, "%s: [rangefinder] missing key '%s'", path, c.line_at ? "model" : "line");
        return VP_EINVAL;
    }
    if (!c.board_at) { snprintf(err, errlen, "%s: [calibration] missing key 'board'", path); return VP_EINVAL; }
    if (strcmp(c.info->board, b->name)) {
        snprintf(err, errlen, "%s:%d: [calibration] board: made on board '%s', not on '%s'", path, c.board_at,
                 c.info->board, b->name);
        return VP_EINVAL;
    }
    len = sqrt(c.line[2] * c.line[2] + c.line[3] * c.line[3]);
    if (!(len > 0.5 && len < 2)) {
        snprintf(err, errlen, "%s:%d: [rangefinder] line: the direction (3rd, 4th numbers) must be a unit vector", path, c.line_at);
        return VP_EINVAL;
    }
    memset(&b->tri, 0, sizeof b->tri);
    b->tri.p0[0] = c.line[0]; b->tri.p0[1] = c.line[1];
    b->tri.e[0] = c.line[2] / len; b->tri.e[1] = c.line[3] / len;
    b->tri.a = c.model[0]; b->tri.b = c.model[1]; b->tri.c = c.model[2];
    b->tri.line_tol = 3;
    b->tri.min_range = b->min_range;
    b->tri.max_range = b->max_range;
    memcpy(b->line, c.line, sizeof b->line);
    memcpy(b->model, c.model, sizeof b->model);
    b->have_rf = 0;
    if (c.rf_at[0] || c.rf_at[4]) {
        /* the full model: every key, a rotation, a unit beam, a span within the board's range */
        vp_rf_model_t rf;
        const double *q = c.rf;
        double dn, ortho = 0;
        int k, i, j;
        for (k = 0; k < 7; k++)
            if (!c.rf_at[k] && k != 6) {
                snprintf(err, errlen, "%s: [rangefinder] missing key '%s' (a full model needs camera, distortion, "
                                      "camera_position, camera_rotation, beam and beam_span)", path, rf_keys[k]);
                return VP_EINVAL;
            }
        memset(&rf, 0, sizeof rf);
        rf.cam = b->cam_model;
        rf.cam.fx = q[0]; rf.cam.fy = q[1]; rf.cam.cx = q[2]; rf.cam.cy = q[3];
        memcpy(rf.cam.dist, q + 4, sizeof rf.cam.dist);
        memcpy(rf.cam.pos, q + 8, sizeof rf.cam.pos);
        memcpy(rf.cam.rot, q + 11, sizeof rf.cam.rot);
        memcpy(rf.origin, q + 20, sizeof rf.origin);
        memcpy(rf.dir, q + 23, sizeof rf.dir);
        rf.min_range = q[26] > b->min_range ? q[26] : b->min_range;
        rf.max_range = q[27] < b->max_range ? q[27] : b->max_range;
        rf.ray_tol_px = c.rf_at[6] ? q[28] : 3;
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                double dot = rf.cam.rot[3 * i] * rf.cam.rot[3 * j] + rf.cam.rot[3 * i + 1] * rf.cam.rot[3 * j + 1] +
                             rf.cam.rot[3 * i + 2] * rf.cam.rot[3 * j + 2];
                ortho += fabs(dot - (i == j));
            }
        dn = sqrt(rf.dir[0] * rf.dir[0] + rf.dir[1] * rf.dir[1] + rf.dir[2] * rf.dir[2]);
        if (!(rf.cam.fx > 0) || !(rf.cam.fy > 0)) { snprintf(err, errlen, "%s:%d: [rangefinder] camera: the focal lengths must be positive", path, c.rf_at[0]); return VP_EINVAL; }
        if (!(ortho < 1e-6)) { snprintf(err, errlen, "%s:%d: [rangefinder] camera_rotation: not a rotation (rows must be orthonormal)", path, c.rf_at[3]); return VP_EINVAL; }
        if (!(fabs(dn - 1) < 1e-6)) { snprintf(err, errlen, "%s:%d: [rangefinder] beam: the direction (4th-6th numbers) must be a unit vector", path, c.rf_at[4]); return VP_EINVAL; }
        if (!(rf.max_range > rf.min_range)) { snprintf(err, errlen, "%s:%d: [rangefinder] beam_span: %g..%g mm leaves nothing of the board's range %g..%g", path, c.rf_at[5], q[26], q[27], b->min_range, b->max_range); return VP_EINVAL; }
        if (!(rf.ray_tol_px > 0)) { snprintf(err, errlen, "%s:%d: [rangefinder] ray_tol_px: must be positive", path, c.rf_at[6]); return VP_EINVAL; }
        b->rf = rf;
        b->have_rf = 1;
        /* the planner asks for no more than the model can read */
        if (b->tri.max_range > rf.max_range) b->tri.max_range = rf.max_range;
        c.info->have_rf = 1;
        c.info->rf = rf;
    }
    b->have_plane = 0;
    if (c.plane_at) {
        /* a line laser's plane: a unit normal */
        double nl = sqrt(c.plane[3] * c.plane[3] + c.plane[4] * c.plane[4] + c.plane[5] * c.plane[5]);
        if (!(fabs(nl - 1) < 1e-6)) {
            snprintf(err, errlen, "%s:%d: [rangefinder] plane: the normal (4th-6th numbers) must be a unit vector", path, c.plane_at);
            return VP_EINVAL;
        }
        memcpy(b->plane_origin, c.plane, sizeof b->plane_origin);
        memcpy(b->plane_normal, c.plane + 3, sizeof b->plane_normal);
        b->have_plane = 1;
        c.info->have_plane = 1;
        memcpy(c.info->plane_origin, c.plane, sizeof c.info->plane_origin);
        memcpy(c.info->plane_normal, c.plane + 3, sizeof c.info->plane_normal);
    }
    b->calibrated = 2;
    b->calib_missing = 0;
    snprintf(b->calib_path, sizeof b->calib_path, "%s", path);
    c.info->tri = b->tri;
    return VP_OK;
}

int vp_board_calibration_write(const char *path, const vp_board_t *b, const vp_board_calib_t *c, char *err,
                               size_t errlen)
{
    FILE *f = fopen(path, "w");
    int ok;
    if (!f) { snprintf(err, errlen, "cannot write %s", path); return VP_EIO; }
    fprintf(f, "# voroprobe calibration of board '%s' (%s), written by `voroprobe calibrate`.\n"
               "# Use it with `calibration = FILE` in the board's [rangefinder] or `voroprobe scan --calib FILE`.\n\n",
            b->name, b->path);
    fprintf(f, "[calibration]\nboard = %s\nspots = %d\nstations = %d\nspan = %.17g, %.17g    # mm from the target\n"
               "residual_rms_mm = %.6g\nresidual_max_mm = %.6g\nline_rms_px = %.6g\n\n",
            b->name, c->spots, c->stations, c->near, c->far, c->rms_mm, c->max_mm, c->line_rms_px);
    if (c->have_plane)
        fprintf(f, "# the line laser's plane: fitted to %d columns of the line on the target at %d poses, their\n"
                   "# distances to it (mm); its normal's angle from the board's line_normal (degrees)\n"
                   "plane_points = %d\nplane_poses = %d\nplane_rms_mm = %.6g\nplane_max_mm = %.6g\nplane_tilt_deg = %.6g\n\n",
                c->plane_points, c->plane_poses, c->plane_points, c->plane_poses, c->plane_rms_mm, c->plane_max_mm,
                c->plane_tilt_deg);
    fprintf(f, "# the spot at image point P0 + s E (px) is d = (A + B s) / (1 + C s) mm along the beam\n"
               "[rangefinder]\nline = %.17g, %.17g, %.17g, %.17g\nmodel = %.17g, %.17g, %.17g\n",
            c->tri.p0[0], c->tri.p0[1], c->tri.e[0], c->tri.e[1], c->tri.a, c->tri.b, c->tri.c);
    if (c->have_rf) {
        const vp_rf_model_t *r = &c->rf;
        fprintf(f, "# the full model (used when present): the camera (fx, fy, cx, cy px; distortion k1, k2, p1, p2;\n"
                   "# its centre and rotation rows in the tilt frame), the beam (origin, unit direction, tilt frame),\n"
                   "# the span the calibration covered (mm along the beam), residual %.4f px rms\n", c->rf_rms_px);
        fprintf(f, "camera = %.17g, %.17g, %.17g, %.17g\ndistortion = %.17g, %.17g, %.17g, %.17g\n", r->cam.fx, r->cam.fy,
                r->cam.cx, r->cam.cy, r->cam.dist[0], r->cam.dist[1], r->cam.dist[2], r->cam.dist[3]);
        fprintf(f, "camera_position = %.17g, %.17g, %.17g\ncamera_rotation = %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, "
                   "%.17g, %.17g\n", r->cam.pos[0], r->cam.pos[1], r->cam.pos[2], r->cam.rot[0], r->cam.rot[1], r->cam.rot[2],
                r->cam.rot[3], r->cam.rot[4], r->cam.rot[5], r->cam.rot[6], r->cam.rot[7], r->cam.rot[8]);
        fprintf(f, "beam = %.17g, %.17g, %.17g, %.17g, %.17g, %.17g\nbeam_span = %.17g, %.17g\nray_tol_px = %.17g\n",
                r->origin[0], r->origin[1], r->origin[2], r->dir[0], r->dir[1], r->dir[2], r->min_range, r->max_range,
                r->ray_tol_px);
    }
    if (c->have_plane)
        fprintf(f, "# the line laser's plane (used when present): a point on it (the laser's exit) and its unit normal,\n"
                   "# tilt frame\nplane = %.17g, %.17g, %.17g, %.17g, %.17g, %.17g\n", c->plane_origin[0], c->plane_origin[1],
                c->plane_origin[2], c->plane_normal[0], c->plane_normal[1], c->plane_normal[2]);
    ok = !ferror(f);
    if (fclose(f) != 0) ok = 0;
    if (!ok) { snprintf(err, errlen, "cannot write %s", path); return VP_EIO; }
    return VP_OK;
}

/* ---- configurations for the modules ---- */

void vp_board_step_config(const vp_board_t *b, vp_step_config_t *c)
{
    int a;
    memset(c, 0, sizeof *c);
    c->naxes = VP_BOARD_AXES;
    for (a = 0; a < VP_BOARD_AXES; a++) c->axis[a] = b->axis[a].ax;
    c->pulse_ns = (uint32_t)llround(b->pulse_us * 1000);
    c->dir_setup_ns = (uint32_t)llround(b->dir_setup_us * 1000);
    c->enable_ns = (uint32_t)llround(b->enable_ms * 1e6);
    c->poll_ns = (uint32_t)llround(b->poll_ms * 1e6);
    c->max_step_rate = b->max_step_rate;
    c->debounce = (uint32_t)b->debounce;
    c->max_late_ns = (uint32_t)llround(b->max_late_us * 1000);
    c->late_fault = b->late_fault;
    c->contact_halt = b->contact_halt;
}

/* A line laser's fan: its axis (the beam the kinematics aim, along which a PROBE is read) and its
 * plane's normal. A calibrated plane is kept as measured and the beam brought into it (the
 * kinematics then aim that axis); the board's nominal normal is turned to hold the beam. */
static void vp_board_line_axis(const vp_board_t *b, double axis[3], double normal[3])
{
    double beam[3] = { 1, 0, 0 }, nn[3], d;
    int k;
    if (b->have_rf) memcpy(beam, b->rf.dir, sizeof beam);
    memcpy(nn, b->have_plane ? b->plane_normal : b->line_normal, sizeof nn);
    d = sqrt(vp_dot3(nn, nn));
    for (k = 0; k < 3; k++) nn[k] /= d;
    if (b->have_plane) {
        d = vp_dot3(beam, nn);
        for (k = 0; k < 3; k++) axis[k] = beam[k] - d * nn[k];
        memcpy(normal, nn, sizeof nn);
    } else {
        memcpy(axis, beam, sizeof beam);
        d = vp_dot3(nn, beam) / vp_dot3(beam, beam);
        for (k = 0; k < 3; k++) normal[k] = nn[k] - d * beam[k];
    }
    d = sqrt(vp_dot3(axis, axis));
    for (k = 0; k < 3; k++) axis[k] /= d;
    d = sqrt(vp_dot3(normal, normal));
    for (k = 0; k < 3; k++) normal[k] /= d;
}

void vp_board_kin_config(const vp_board_t *b, vp_kin_config_t *k)
{
    int a;
    memset(k, 0, sizeof *k);
    memcpy(k->tilt_offset, b->tilt_offset, sizeof k->tilt_offset);
    memcpy(k->laser_offset, b->laser_offset, sizeof k->laser_offset);
    if (b->have_rf) {
        /* the beam as calibrated: the kinematics aim it and place its points */
        memcpy(k->laser_offset, b->rf.origin, sizeof k->laser_offset);
        memcpy(k->laser_dir, b->rf.dir, sizeof k->laser_dir);
    }
    if (b->line_laser && b->have_plane) {
        /* a line laser with a calibrated plane: the beam in that plane, the fan's axis */
        double nrm[3];
        vp_board_line_axis(b, k->laser_dir, nrm);
    }
    for (a = 0; a < VP_BOARD_AXES; a++) { k->lo[a] = b->axis[a].ax.travel_min; k->hi[a] = b->axis[a].ax.travel_max; }
    k->origin_tol = b->origin_tol;
}

void vp_board_machine_config(const vp_board_t *b, vp_machine_config_t *m)
{
    memset(m, 0, sizeof *m);
    m->settle_ns = (uint32_t)llround(b->settle_ms * 1e6);
    m->timeout_ms = b->timeout_ms;
    m->use_laser_line = b->laser.chip[0] != 0;
    m->latency_frames = b->latency_frames;
    m->spot.band = b->band;
    m->contact = vp_board_has_contact(b);
    m->confirm = b->confirm_spot;
    m->backdrop = b->have_backdrop;
    /* the head turns on the way to a probe only where every pose is safe (the ball rule); with a
     * contact switch its MOVEs are watched along their pieces and paths, each waypoint passed
     * where a touch stops within the stylus's overtravel (contact_stop, or the stop of the worst
     * straight MOVE) */
    m->turn_on_move = b->clearance > 0 && !(b->head_reach + b->head_margin > b->clearance);
    if (m->contact && m->turn_on_move) m->contact_stop = b->contact_stop > 0 ? b->contact_stop : b->contact_reach;
    m->use_rf = b->have_rf;
    if (b->have_rf) m->rf = b->rf;
    if (b->line_laser) {
        /* the fan: the plane through the laser's exit point with the board's normal (or as
         * calibrated) holding the beam, its axis; the camera as calibrated (or as the board
         * describes it) */
        vp_line_model_t *l = &m->line_model;
        m->line = 1;
        l->cam = b->have_rf ? b->rf.cam : b->cam_model;
        memcpy(l->origin, b->have_rf ? b->rf.origin : b->laser_offset, sizeof l->origin);
        if (b->have_plane) memcpy(l->origin, b->plane_origin, sizeof l->origin);
        vp_board_line_axis(b, l->axis, l->normal);
        l->half_angle = 0.5 * b->line_fan * (M_PI / 180.0);
        l->min_range = b->have_rf ? b->rf.min_range : b->min_range;
        l->max_range = b->have_rf ? b->rf.max_range : b->max_range;
        m->line_cfg.column_step = b->line_step;
        if (b->line_fan_used < b->line_fan) m->line_ray_half = 0.5 * b->line_fan_used * (M_PI / 180.0);
    }
}

void vp_board_planner_config(const vp_board_t *b, vp_planner_config_t *c)
{
    int a;
    memset(c, 0, sizeof *c);
    c->omega_kind = b->omega_kind;
    memcpy(c->omega_lo, b->omega_lo, sizeof c->omega_lo);
    memcpy(c->omega_hi, b->omega_hi, sizeof c->omega_hi);
    memcpy(c->omega_center, b->omega_center, sizeof c->omega_center);
    c->omega_radius = b->omega_radius;
    memcpy(c->interior[0], b->interior, sizeof c->interior[0]);
    c->ninterior = 1;
    c->eps = b->eps;
    memcpy(c->start, b->start, sizeof c->start);
    c->max_range = b->tri.max_range;
    c->clearance = b->clearance;
    /* lines aimed from aside turn the head in ways no other probe does: only for a head that
     * lies within the clearance ball in every pose (the ball rule), never for clear_by = swept */
    if (b->clearance > 0 && b->head_reach + b->head_margin > b->clearance) c->flags |= VP_PLAN_NO_AIM;
    c->min_feature = b->min_feature;
    c->feature_margin = b->feature_margin;
    if (b->clearance > 0) {
        /* body mode: moves weighed by the axes' top speeds (pan and tilt per radian) */
        for (a = 0; a < VP_PLANNER_AXES; a++)
            c->axis_time[a] = (a < 3 ? 1.0 : 180.0 / M_PI) / b->axis[a].ax.max_speed;
        c->pan_travel[0] = b->axis[VP_J_PAN].ax.travel_min * (M_PI / 180.0);
        c->pan_travel[1] = b->axis[VP_J_PAN].ax.travel_max * (M_PI / 180.0);
        if (c->pan_travel[1] - c->pan_travel[0] >= 4.0 * M_PI || fabs(c->pan_travel[0]) > 100.0 ||
            fabs(c->pan_travel[1]) > 100.0)
            c->pan_travel[0] = c->pan_travel[1] = 0.0; /* two turns and more: as if it turned freely */
    }
    if (b->line_laser) {
        /* the rays a frame can give: one per column looked at */
        int step = b->line_step > 0 ? b->line_step : (b->cam_model.width + VP_MACHINE_MAX_LINE - 1) / VP_MACHINE_MAX_LINE;
        c->line_rays = (uint32_t)((b->cam_model.width + step - 1) / step);
    }
}

void vp_board_gpiod_config(const vp_board_t *b, vp_gpiod_config_t *g)
{
    int a;
    memset(g, 0, sizeof *g);
    for (a = 0; a < VP_BOARD_AXES; a++) {
        const vp_board_axis_t *x = &b->axis[a];
        if (x->step.chip[0]) g->out[a] = x->step;
        if (x->dir.chip[0]) g->out[8 + a] = x->dir;
        if (x->enable.chip[0]) g->out[16 + a] = x->enable;
        if (x->lim_min.chip[0]) g->in[a] = x->lim_min;
        if (x->lim_max.chip[0]) g->in[8 + a] = x->lim_max;
    }
    if (b->laser.chip[0]) g->out[24] = b->laser;
    if (b->estop.chip[0]) g->in[16] = b->estop;
    if (b->contact.chip[0]) g->in[17] = b->contact;
    g->rt_priority = b->rt_priority;
    g->spin_ns = (int64_t)llround(b->spin_us * 1000);
    g->consumer = "voroprobe";
}
