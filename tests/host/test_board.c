/* Board files: boards/rpi4-gantry.ini and boards/sim.ini parse into the expected machine;
 * broken variants are refused with the file, the right line, the section, the key and the
 * reason; the module configurations derived from a board are accepted by those modules; a NUL
 * byte in a line, a device and a folder are refused; long board paths are kept whole. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "vp_board.h"
#include "vp_iorec.h"
#include "vp_planner.h"
#include "vp_status.h"
#include "vp_test.h"
#include "vp_vec3.h"

static char text[65536];

static int load_text(const char *path)
{
    FILE *f = fopen(path, "r");
    size_t n;
    if (!f) return 0;
    n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
    return 1;
}

/* line number (1-based) of the first occurrence of s in t */
static int line_of(const char *t, const char *s)
{
    const char *p = strstr(t, s), *q;
    int line = 1;
    if (!p) return -1;
    for (q = t; q < p; q++) if (*q == '\n') line++;
    return line;
}

/* text with the first `from` replaced by `to` */
static char *edit(const char *from, const char *to)
{
    static char out[65536];
    const char *p = strstr(text, from);
    if (!p) { fprintf(stderr, "edit: '%s' not found\n", from); exit(2); }
    snprintf(out, sizeof out, "%.*s%s%s", (int)(p - text), text, to, p + strlen(from));
    return out;
}

/* the edited text t becomes the text later edits start from */
static void keep(const char *t)
{
    static char two[65536];
    snprintf(two, sizeof two, "%s", t);
    memcpy(text, two, sizeof text);
}

/* removes a whole section: from its header to the next '[' at a line start */
static char *cut_section(const char *hdr)
{
    static char out[65536];
    const char *p = strstr(text, hdr), *e;
    if (!p) exit(2);
    e = strstr(p + 1, "\n[");
    snprintf(out, sizeof out, "%.*s%s", (int)(p - text), text, e ? e + 1 : "");
    return out;
}

static int nbad;
static void bad(const char *t, const char *want_loc, const char *want_msg)
{
    vp_board_t b;
    char err[400];
    int rc = vp_board_parse(t, "rpi4.ini", &b, err, sizeof err);
    nbad++;
    CHECKF(rc == VP_EINVAL, "accepted; wanted '%s'", want_msg);
    CHECKF(strstr(err, want_loc) && strstr(err, want_msg), "got '%s', wanted '%s' ... '%s'", err, want_loc, want_msg);
    if (getenv("VP_VERBOSE")) printf("  %s\n", err);
}

/* The two boards of boards/, read field by field, and the configs made from them. */
static void test_two_boards(void)
{
    vp_board_t b;
    char err[400];
    int rc;
    int a;
    /* ---- the two boards ---- */
    rc = vp_board_load("boards/rpi4-gantry.ini", &b, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    CHECK(!strcmp(b.name, "rpi4-gantry") && b.io == VP_BOARD_IO_GPIOD);
    CHECK(b.axis[0].ax.steps_per_unit == 80 && b.axis[0].ax.max_speed == 150 && b.axis[0].ax.accel == 1500);
    CHECK(b.axis[0].ax.travel_min == 0 && b.axis[0].ax.travel_max == 400 && b.axis[0].ax.home_dir == -1);
    CHECK(b.axis[1].ax.invert_dir == 1 && b.axis[2].ax.home_dir == 1 && b.axis[4].ax.home_dir == 0);
    CHECK(!strcmp(b.axis[0].step.chip, "gpiochip0") && b.axis[0].step.offset == 17 && !b.axis[0].step.active_low);
    CHECK(b.axis[0].enable.offset == 16 && b.axis[0].enable.active_low == 1);
    CHECK(b.axis[0].lim_min.offset == 19 && b.axis[0].lim_min.pull == VP_PULL_UP && b.axis[0].lim_max.offset == -1);
    CHECK(b.estop.offset == 4 && b.estop.pull == VP_PULL_UP && b.laser.offset == 18);
    CHECK(b.tilt_offset[2] == 45 && b.laser_offset[0] == 20);
    CHECK(!strcmp(b.camera.backend, "v4l2") && !strcmp(b.camera.device, "/dev/video0") && b.camera.exposure_us == 1000);
    CHECK(b.camera.format == VP_FOURCC('G', 'R', 'E', 'Y') && b.cam_model.fx == 350 && b.cam_model.fy == 350);
    CHECK(b.min_range == 10 && b.max_range == 400 && !b.calibrated && b.tri.max_range > b.tri.min_range);
    CHECK(b.omega_kind == VP_OMEGA_BALL && b.omega_radius == 83 && b.eps == 10 && b.start[2] == 234);
    CHECK(!strcmp(b.sim_surface, "ellipsoid*24@200,150,150"));
    /* the head's body: the clearance ball and four parts; the camera's far corner decides */
    CHECK(b.head.nparts == 5 && !strcmp(b.head.part[2].name, "camera") && b.head.part[4].frame == VP_HEAD_PAN);
    CHECK(fabs(b.head_reach - sqrt(30.0 * 30 + 42.5 * 42.5 + 22.5 * 22.5)) < 1e-9 && !b.clear_swept);
    CHECK(b.head_reach + b.head_margin <= b.clearance && b.head_margin > b.origin_tol && b.head_margin < 1);
    CHECK(b.near_measure == 0 && !b.calibration[0] && b.have_fixture && b.cal_target[0] == 300 && b.cal_stations == 20);
    CHECK(b.sim_cam.pos[1] == b.cam_model.pos[1] && b.sim_cam.rot[0] == b.cam_model.rot[0]);
    {
        vp_step_config_t sc;
        vp_kin_config_t kc;
        vp_gpiod_config_t gc;
        vp_kin_t kin;
        vp_step_t st;
        vp_iorec_t rec;
        vp_iorec_config_t rcf;
        vp_io_t io;
        vp_board_step_config(&b, &sc);
        CHECK(sc.naxes == 5 && sc.pulse_ns == 4000 && sc.dir_setup_ns == 2000 && sc.enable_ns == 2000000 && sc.max_step_rate == 20000);
        CHECK(sc.debounce == 3 && sc.max_late_ns == 100000 && sc.late_fault == 0);
        memset(&rcf, 0, sizeof rcf);
        rcf.naxes = 5;
        rcf.estop_at = -1;
        vp_iorec_init(&rec, &rcf);
        io = vp_iorec_io(&rec);
        CHECK(vp_step_init(&st, &sc, &io) == VP_OK);
        vp_board_kin_config(&b, &kc);
        CHECK(vp_kin_init(&kin, &kc) == VP_OK && kc.hi[3] == 190 && kc.lo[4] == -90);
        vp_board_gpiod_config(&b, &gc);
        CHECK(gc.out[0].offset == 17 && gc.out[8].offset == 27 && gc.out[12].offset == 13);
        for (a = 0; a < 5; a++) CHECK(gc.out[16 + a].offset == 16 && gc.out[16 + a].active_low);
        CHECK(gc.in[0].offset == 19 && gc.in[8 + 2].offset == 21 && gc.in[16].offset == 4 && gc.out[24].offset == 18);
        CHECK(gc.rt_priority == 50 && gc.spin_ns == 50000);
    }
    rc = vp_board_load("boards/sim.ini", &b, err, sizeof err);
    CHECKF(rc == VP_OK, "%s", err);
    CHECK(!strcmp(b.name, "sim") && b.io == VP_BOARD_IO_SIM && !b.axis[0].step.chip[0] && !b.estop.chip[0]);
    CHECK(!strcmp(b.sim_surface, "sphere*80") && b.interior[0] == 0 && b.sim_energy == 6000);
    CHECK(b.clear_swept && b.head.nparts == 4 && b.head_reach > b.clearance);   /* the default body, swept */
    CHECK(b.cam_model.cx == 319.5 && b.cam_model.cy == 239.5);   /* centre defaults to the middle */
}

/* Broken boards: each error names the file, the line, the section and the key. */
static void test_broken_boards(void)
{
    vp_board_t b;
    char err[400];
    char loc[64];
    int rc;
    const char *t;
    /* ---- broken boards ---- */
    CHECK(load_text("boards/rpi4-gantry.ini"));
    CHECK(vp_board_load("boards/no-such-board.ini", &b, err, sizeof err) == VP_EIO && strstr(err, "boards/no-such-board.ini"));
#define LOC(s) (snprintf(loc, sizeof loc, "rpi4.ini:%d: ", line_of(t, s)), loc)
    t = edit("steps_per_unit = 80\nmax_speed = 150", "stesp_per_unit = 80\nmax_speed = 150");
    bad(t, LOC("stesp_per_unit"), "[axis.x] stesp_per_unit: unknown key");
    t = edit("steps_per_unit = 400", "steps_per_unit = 4OO");
    bad(t, LOC("4OO"), "[axis.z] steps_per_unit: expected a number, got '4OO'");
    t = edit("max_speed = 120", "max_speed = -120");
    bad(t, LOC("-120"), "[axis.y] max_speed: -120 must be positive");
    t = edit("accel = 1200\n", "");
    bad(t, LOC("[axis.y]"), "[axis.y] missing key 'accel'");
    t = cut_section("[axis.tilt]");
    bad(t, "rpi4.ini: ", "missing section [axis.tilt]");
    /* the contact switch's kind: a stylus (the default) or the head's mount (this board's); a
     * mount needs the head kept outside Omega, and either needs a switch */
    t = edit("contact_by = mount ", "contact_by = tip ");
    bad(t, LOC("contact_by"), "[head] contact_by: expected stylus or mount, got 'tip'");
    CHECK(vp_board_parse(text, "rpi4.ini", &b, err, sizeof err) == VP_OK && b.contact_mount == 1);
    t = edit("clearance = 58", "clearance = 0 ");
    bad(t, LOC("contact_by"), "[head] contact_by: a mount's switch does not tell where the head touched");
    t = edit("clearance = 58", "clearance = 58\nmin_feature = 10");
    bad(t, LOC("contact_by"), "and no tubes inside it: min_feature = 0");
    {
        keep(edit("contact = gpiochip0:7 pull-up", "#"));
        t = edit("contact_stop = 10 ", "# ");
        bad(t, LOC("contact_by"), "[head] contact_by: needs a contact switch");
        CHECK(load_text("boards/rpi4-gantry.ini"));
    }
    /* tubes need the walls: with a stylus (the mount's switch refuses tubes) and no backdrop a
     * dark surface would read free round the body's way; sim-enclosed.ini has walls and takes
     * them, and refuses them with its walls taken out */
    {
        keep(edit("contact_by = mount ", "contact_by = stylus "));
        t = edit("clearance = 58", "clearance = 58\nmin_feature = 10");
        bad(t, LOC("min_feature"), "[omega] min_feature: tubes inside Omega need [rangefinder] backdrop");
        CHECK(load_text("boards/sim-enclosed.ini"));
        t = edit("clearance = 58", "clearance = 58\nmin_feature = 10");
        CHECK(vp_board_parse(t, "rpi4.ini", &b, err, sizeof err) == VP_OK && b.min_feature == 10.0);
        keep(t);
        t = edit("backdrop = ", "# backdrop = ");
        bad(t, LOC("min_feature"), "need [rangefinder] backdrop");
        CHECK(load_text("boards/rpi4-gantry.ini"));
    }
    /* without the key: a stylus */
    t = edit("contact_by = mount ", "# contact_by = mount ");
    CHECK(vp_board_parse(t, "rpi4.ini", &b, err, sizeof err) == VP_OK && b.contact_mount == 0);
    t = cut_section("[estop]");
    bad(t, "rpi4.ini: ", "missing section [estop]: a board that drives motors needs an e-stop input");
    t = edit("dir = gpiochip0:23", "dir = gpiochip0:27");
    snprintf(loc, sizeof loc, "rpi4.ini:%d: ", line_of(t, "[axis.y]") + 2);
    bad(t, loc, "[axis.y] dir: gpiochip0:27 is already [axis.x] dir (line 29)");
    t = edit("limit_max = gpiochip0:21 pull-up", "limit_max = gpiochip0:17 pull-up");
    bad(t, LOC("limit_max = gpiochip0:17"), "[axis.z] limit_max: gpiochip0:17 is already [axis.x] step");
    t = edit("step = gpiochip0:5", "step = gpio5");
    bad(t, LOC("gpio5"), "[axis.pan] step: expected [!]CHIP:OFFSET [pull-up|pull-down] or none, got 'gpio5'");
    t = edit("pin = gpiochip0:4 pull-up", "pin = gpiochip0:4 pullup");
    bad(t, LOC("pullup"), "[estop] pin: unknown pin option 'pullup'");
    t = edit("travel = 0, 400", "travel = 400, 0");
    bad(t, LOC("400, 0"), "[axis.x] travel: expected MIN, MAX with MIN below MAX");
    t = edit("travel = 0, 400", "travel = 0");
    bad(t, LOC("travel = 0 "), "[axis.x] travel: expected 2 numbers separated by commas, got '0'");
    t = edit("home_pos = -2", "home_pos = -5");
    bad(t, LOC("home_pos = -5"), "[axis.x] home_pos: after the pull-off the axis rests at -2 mm, outside travel 0..400");
    t = edit("home = max", "home = top");
    bad(t, LOC("home = top"), "[axis.z] home: expected min, max or none, got 'top'");
    t = edit("limit_max = gpiochip0:21 pull-up\n", "");
    bad(t, LOC("home = max"), "[axis.z] home: homing to max needs a limit_max pin");
    t = edit("[axis.tilt]", "[axis.w]");
    bad(t, LOC("[axis.w]"), "[axis.w]: unknown section");
    t = edit("backlash = 0.02", "backlash = 0.02\nmax_speed = 10");
    bad(t, LOC("max_speed = 10\n"), "[axis.z] max_speed: set twice (first at line");
    t = edit("max_speed = 150", "max_speed = 300");
    bad(t, LOC("max_speed = 300"), "[axis.x] max_speed: 300 mm/s is 24000 steps/s, above [timing] max_step_rate 20000");
    t = edit("ball = 200, 150, 150, 83", "ball = 200, 150, 150, 130");
    bad(t, LOC("ball = 200"), "[omega] ball: y from 20 to 280 is not within axis.y travel 0..300 less the head's reach 65.0 mm");
    t = edit("ball = 200, 150, 150, 83", "box = 130, 90, 90, 270, 210, 210");
    bad(t, LOC("box = 130"), "[omega] box: the planner's detours round Omega reach 112.2 mm from its centre (1.02 x its "
        "circumradius): y from 37.8 to 262.2 is not within axis.y travel 0..300 less the head's reach 65.0 mm; use a smaller box, or a ball");
    t = edit("start = 200, 150, 234", "start = 200, 150, 150");
    bad(t, LOC("start = 200"), "[omega] start: the device must start outside Omega");
    t = edit("on_late = reenter", "on_late = ignore");
    bad(t, LOC("on_late = ignore"), "[timing] on_late: expected reenter or fault, got 'ignore'");
    t = edit("debounce = 3", "debounce = 0");
    bad(t, LOC("debounce = 0"), "[timing] debounce: 0 is outside 1..64");
    t = edit("near_spots = too-close", "near_spots = guess");
    bad(t, LOC("near_spots = guess"), "[rangefinder] near_spots: expected too-close or measure, got 'guess'");
    t = edit("name = rpi4-gantry", "name = rpi4-gantry\nlog_sync = often");
    bad(t, LOC("log_sync = often"), "[board] log_sync: expected record, close, N (records), Tms or N,Tms; got 'often'");
    t = edit("far = 200", "far = 12");
    bad(t, LOC("far = 12"), "[calibrate] far: must be above near (15 mm)");
    t = edit("camera_look_at = 100, 0, 0", "camera_look_at = 0, 30, 10");
    bad(t, LOC("camera_look_at = 0"), "[sim] camera_look_at: the camera must not look along 'up' nor at its own position");
    t = edit("interior = 200, 150, 150", "interior = 20, 150, 150");
    bad(t, LOC("interior = 20,"), "[omega] interior: must lie inside Omega");
    t = edit("# line = P0X, P0Y, EX, EY", "line = 557, 277, -0.988, -0.155");
    bad(t, LOC("line = 557"), "[rangefinder] line: a calibration needs both line and model");
    t = edit("look_at = 100, 0, 0", "look_at = -100, 0, 0");
    bad(t, LOC("look_at = -100"), "[camera] look_at: the camera does not see the beam between min_range and max_range");
    t = edit("format = GREY", "format = MJPG");
    bad(t, LOC("MJPG"), "[camera] format: expected GREY, YUYV, RGB24, BGR24 or auto, got 'MJPG'");
    t = edit("backend = v4l2", "backend = opencv");
    bad(t, LOC("opencv"), "[camera] backend: expected v4l2 or libcamera, got 'opencv'");
    t = edit("io = gpiod", "io = gpio");
    bad(t, LOC("io = gpio "), "[board] io: expected gpiod or sim, got 'gpio'");
    t = edit("invert = yes", "invert = maybe");
    bad(t, LOC("maybe"), "[axis.y] invert: expected yes or no, got 'maybe'");
    t = edit("pulse_us = 4 ", "pulse_us 4 ");
    bad(t, LOC("pulse_us 4"), "expected 'key = value' or '[section]', got 'pulse_us 4");
    t = edit("[head]", "[head");
    bad(t, LOC("[head"), "section header without ']'");
    t = edit("[board]", "[board]\n[board]");
    snprintf(loc, sizeof loc, "rpi4.ini:%d: ", line_of(t, "[board]") + 1);
    bad(t, loc, "[board]: section repeated (first at line 7)");
    t = edit("eps = 10 ", "eps = 0 ");
    bad(t, LOC("eps = 0"), "[omega] eps: 0 must be positive");
    /* with io = sim the pins and the e-stop are not needed */
    t = edit("io = gpiod", "io = sim");
    {
        static char t2[65536];
        strcpy(t2, t);
        strcpy(text, t2);
        t = cut_section("[estop]");
        rc = vp_board_parse(t, "rpi4.ini", &b, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
    }
}

/* Calibration files: written, read back by the board, broken ones named. */
static void test_calibration_files(void)
{
    vp_board_t b;
    char err[400];
    int rc;
    const char *t;
    /* ---- calibration files: written, read back by the board, broken ones named ---- */
    {
        char dir[] = "/tmp/vp_calib_XXXXXX", bpath[128], cpath[128], bt[65536];
        vp_board_t b2;
        vp_board_calib_t ci, back;
        FILE *f;
        CHECK(mkdtemp(dir) != NULL);
        snprintf(bpath, sizeof bpath, "%s/board.ini", dir);
        snprintf(cpath, sizeof cpath, "%s/board.calib", dir);
        CHECK(load_text("boards/rpi4-gantry.ini"));
        t = edit("# calibration = rpi4-gantry.calib", "calibration = board.calib");
        snprintf(bt, sizeof bt, "%s", t);
        f = fopen(bpath, "w");
        CHECK(f && fputs(bt, f) >= 0 && fclose(f) == 0);
        rc = vp_board_load(bpath, &b, err, sizeof err);
        CHECKF(rc == VP_OK && b.calib_missing && !b.calibrated && !strcmp(b.calib_path, cpath), "%s", err);
        memset(&ci, 0, sizeof ci);
        ci.tri = b.tri;
        ci.tri.a += 1.5;       /* not the geometry: the file's model must win */
        ci.spots = 60; ci.stations = 20; ci.near = 15; ci.far = 200; ci.rms_mm = 0.01;
        CHECK(vp_board_calibration_write(cpath, &b, &ci, err, sizeof err) == VP_OK);
        rc = vp_board_load(bpath, &b2, err, sizeof err);
        CHECKF(rc == VP_OK && b2.calibrated == 2 && !b2.calib_missing && b2.tri.a == ci.tri.a && b2.tri.b == ci.tri.b &&
               b2.tri.c == ci.tri.c && b2.tri.p0[0] == ci.tri.p0[0] && b2.tri.min_range == 10, "%s", err);
        CHECK(vp_board_calibration_load(&b, cpath, &back, err, sizeof err) == VP_OK && back.spots == 60 && back.far == 200);
        CHECK(!b2.have_plane && !back.have_plane);    /* a file without a line laser's plane */
        {
            /* a line laser's plane: written, read back bit for bit, used by a line board's machine */
            vp_machine_config_t mc;
            double l = sqrt(0.01 * 0.01 + 1);
            ci.have_plane = 1;
            ci.plane_origin[0] = 20; ci.plane_origin[1] = 0.25; ci.plane_origin[2] = 0.5;
            ci.plane_normal[0] = 0.01 / l; ci.plane_normal[1] = 0; ci.plane_normal[2] = 1 / l;
            ci.plane_points = 1859; ci.plane_poses = 20; ci.plane_rms_mm = 0.0097; ci.plane_max_mm = 0.07; ci.plane_tilt_deg = 0.5;
            CHECK(vp_board_calibration_write(cpath, &b, &ci, err, sizeof err) == VP_OK);
            CHECKF(vp_board_calibration_load(&b, cpath, &back, err, sizeof err) == VP_OK, "%s", err);
            CHECK(b.have_plane && back.have_plane && !memcmp(b.plane_origin, ci.plane_origin, sizeof b.plane_origin) &&
                  !memcmp(b.plane_normal, ci.plane_normal, sizeof b.plane_normal) && back.plane_points == 1859 &&
                  back.plane_poses == 20 && back.plane_rms_mm == 0.0097 && back.plane_tilt_deg == 0.5);
            b.line_laser = 1;
            b.line_fan = 30;
            vp_board_machine_config(&b, &mc);
            CHECK(mc.line && !memcmp(mc.line_model.origin, ci.plane_origin, sizeof mc.line_model.origin) &&
                  fabs(mc.line_model.normal[0] - ci.plane_normal[0]) < 1e-15 && fabs(mc.line_model.normal[2] - ci.plane_normal[2]) < 1e-15 &&
                  fabs(vp_dot3(mc.line_model.axis, mc.line_model.normal)) < 1e-15);
            b.line_laser = 0;
            /* a normal that is not a unit vector: refused, naming the line */
            f = fopen(cpath, "w");
            CHECK(f && fputs("[calibration]\nboard = rpi4-gantry\n[rangefinder]\nline = 1, 2, 1, 0\nmodel = 1, 2, 3\n"
                             "plane = 20, 0, 0, 0, 0, 2\n", f) >= 0 && fclose(f) == 0);
            rc = vp_board_calibration_load(&b, cpath, NULL, err, sizeof err);
            CHECKF(rc == VP_EINVAL && strstr(err, "board.calib:6: [rangefinder] plane: the normal"), "%s", err);
            ci.have_plane = 0;
        }
        /* broken: the error names the calibration file, its line, section and key, via the board's key */
        f = fopen(cpath, "w");
        CHECK(f && fputs("[calibration]\nboard = rpi4-gantry\n[rangefinder]\nline = 1, 2, 1, 0\nmodel = 1, 2\n", f) >= 0 && fclose(f) == 0);
        rc = vp_board_load(bpath, &b2, err, sizeof err);
        CHECKF(rc == VP_EINVAL && strstr(err, "board.ini:") && strstr(err, "[rangefinder] calibration: ") &&
               strstr(err, "board.calib:5: [rangefinder] model: expected 3 numbers"), "%s", err);
        f = fopen(cpath, "w");
        CHECK(f && fputs("[calibration]\nboard = sim\n[rangefinder]\nline = 1, 2, 1, 0\nmodel = 1, 2, 3\n", f) >= 0 && fclose(f) == 0);
        rc = vp_board_calibration_load(&b, cpath, NULL, err, sizeof err);
        CHECKF(rc == VP_EINVAL && strstr(err, "board.calib:2: [calibration] board: made on board 'sim', not on 'rpi4-gantry'"), "%s", err);
        f = fopen(cpath, "w");
        CHECK(f && fputs("[calibration]\nboard = rpi4-gantry\n[rangefinder]\nline = 1, 2, 1, 0\n", f) >= 0 && fclose(f) == 0);
        rc = vp_board_calibration_load(&b, cpath, NULL, err, sizeof err);
        CHECKF(rc == VP_EINVAL && strstr(err, "board.calib: [rangefinder] missing key 'model'"), "%s", err);
        remove(cpath);
        remove(bpath);
        rmdir(dir);
    }
}

/* A NUL byte inside a value, a device, a folder, a long path: refused, naming them. */
static void test_nul_bytes(void)
{
    vp_board_t b;
    char err[400];
    int rc;
    /* ---- a NUL byte inside a value is refused naming the line (it was read as the part before
     * it: "steps_per_unit = 8<NUL>0" gave 8); a device or a folder is refused at once (a board
     * at /dev/zero was read for ever); a board path of any length is kept whole ---- */
    {
        char dir[] = "/tmp/vp_nul_XXXXXX", bpath[1200], want[64];
        const char *at;
        FILE *f;
        size_t n, k;
        CHECK(mkdtemp(dir) != NULL);
        CHECK(load_text("boards/rpi4-gantry.ini"));
        at = strstr(text, "steps_per_unit = 80\n");
        CHECK(at != NULL);
        snprintf(bpath, sizeof bpath, "%s/board.ini", dir);
        f = fopen(bpath, "wb");
        n = strlen(text);
        k = (size_t)(at - text) + strlen("steps_per_unit = 8");
        CHECK(f && fwrite(text, 1, k, f) == k && fputc(0, f) == 0 && fwrite(text + k, 1, n - k, f) == n - k && fclose(f) == 0);
        rc = vp_board_load(bpath, &b, err, sizeof err);
        snprintf(want, sizeof want, "board.ini:%d: ", line_of(text, "steps_per_unit = 80\n"));
        CHECKF(rc == VP_EINVAL && strstr(err, want) && strstr(err, "NUL"), "%s (wanted %s)", err, want);
        remove(bpath);
        rc = vp_board_load("/dev/zero", &b, err, sizeof err);
        CHECKF(rc == VP_EIO && strstr(err, "/dev/zero is not a regular file"), "%s", err);
        rc = vp_board_load(dir, &b, err, sizeof err);
        CHECKF(rc == VP_EIO && strstr(err, "not a regular file (a folder)"), "%s", err);
        /* a long path: 4 folders of 200 characters */
        n = strlen(dir);
        for (k = 0; k < 4; k++) {
            memset(bpath + n, 'b', 201);
            bpath[n] = '/';
            n += 201;
            bpath[n] = 0;
            CHECK(mkdir(bpath, 0700) == 0);
        }
        strcpy(bpath + n, "/board.ini");
        f = fopen(bpath, "w");
        CHECK(f && fputs(text, f) >= 0 && fclose(f) == 0);
        rc = vp_board_load(bpath, &b, err, sizeof err);
        CHECKF(rc == VP_OK && !strcmp(b.path, bpath), "%s", err);
        remove(bpath);
        for (k = 0; k < 4; k++) {
            bpath[n] = 0;
            rmdir(bpath);
            n -= 201;
        }
        rmdir(dir);
    }
    printf("2 boards parsed; %d broken variants refused with file, line, section, key and reason; calibration files "
           "written, read back, broken ones named; NUL bytes, devices and folders refused\n", nbad);
}

/* A line laser: the keys, the configs made from them, and a board without a laser pin refused. */
static void test_line_laser(void)
{
    static char t2[65536];
    vp_board_t b;
    vp_machine_config_t mc;
    vp_planner_config_t pc;
    char err[400], loc[64];
    const char *t, *p;
    t = edit("near_spots = too-close", "near_spots = too-close\nlaser = spot");
    bad(t, LOC("laser = spot"), "[rangefinder] laser: expected dot or line, got 'spot'");
    t = edit("near_spots = too-close", "near_spots = too-close\nfan = 200");
    bad(t, LOC("fan = 200"), "[rangefinder] fan: 200 is outside 1..120");
    t = edit("near_spots = too-close", "near_spots = too-close\nlaser = line\nfan = 20\nfan_used = 25");
    bad(t, LOC("fan_used = 25"), "[rangefinder] fan_used: must be at most fan (20 degrees)");
    t = edit("near_spots = too-close", "near_spots = too-close\nlaser = line\nline_normal = 0, 0, 0");
    bad(t, LOC("line_normal = 0"), "[rangefinder] line_normal: must not be 0, 0, 0");
    t = edit("near_spots = too-close", "near_spots = too-close\nlaser = line\nfan = 40\nline_step = 2");
    CHECK(vp_board_parse(t, "rpi4.ini", &b, err, sizeof err) == VP_OK && b.line_laser);
    vp_board_machine_config(&b, &mc);
    vp_board_planner_config(&b, &pc);
    CHECK(mc.line == 1 && mc.line_cfg.column_step == 2 && pc.line_rays == (uint32_t)((b.cam_model.width + 1) / 2));
    CHECK(fabs(mc.line_model.half_angle - 20.0 * M_PI / 180.0) < 1e-12 && mc.line_ray_half == 0.0);
    CHECK(fabs(vp_dot3(mc.line_model.axis, mc.line_model.normal)) < 1e-12 && fabs(vp_dot3(mc.line_model.axis, mc.line_model.axis) - 1) < 1e-12);
    /* a dot laser: no rays */
    CHECK(vp_board_parse(text, "rpi4.ini", &b, err, sizeof err) == VP_OK && !b.line_laser);
    vp_board_planner_config(&b, &pc);
    CHECK(pc.line_rays == 0);
    /* no laser pin: a line cannot be read from a laser-off / laser-on pair */
    t = cut_section("[laser]");
    p = strstr(t, "near_spots = too-close");
    CHECK(p != NULL);
    if (!p) return;
    snprintf(t2, sizeof t2, "%.*snear_spots = too-close\nlaser = line%s", (int)(p - t), t, p + strlen("near_spots = too-close"));
    t = t2;
    bad(t, LOC("laser = line"), "[rangefinder] laser: a line laser is read from a laser-off / laser-on frame pair: the board needs [laser] pin");
}

int main(void)
{
    test_two_boards();
    test_broken_boards();
    test_line_laser();
    test_calibration_files();
    test_nul_bytes();
    return vp_test_done("test_board");
}
