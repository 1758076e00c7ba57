/* Camera settings a scan can rely on, without a camera.
 *
 * Controls (port/vp_v4l2.c, vp_v4l2_controls) through a fake camera's ioctl: manual exposure,
 * exposure_auto_priority and auto gain off, the exposure time and a fixed gain, each read back.
 * A camera that takes them passes; one that clamps the exposure to its range, keeps its auto
 * exposure on while saying yes, lacks a gain control, or refuses a write is refused, and the error
 * names the control. The checker's case to fail: the clamping and the ignoring cameras accept
 * every VIDIOC_S_CTRL, so a check of the write alone (the old code) would pass them.
 *
 * libcamera's read-back (vp_cam_exposure_taken): the exposure and gain a frame's metadata report,
 * within a sensor line and a gain step, or the control named.
 *
 * Colour (port/vp_cam.c): the laser's channel of YUYV, RGB24 and BGR24 frames. Here against the
 * formulas' values at chosen pixels; with a folder argument the frames and channels are written
 * there for tests/t_camcolour.sh, which checks every pixel against numpy's own conversion. */
#include <errno.h>
#include <linux/videodev2.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_cam.h"
#include "vp_rng.h"
#include "vp_status.h"
#include "vp_test.h"
#include "vp_v4l2.h"

/* ---- a fake camera: a few controls, each with a range and a behaviour ---- */

enum { TAKES = 0, CLAMPS = 1, IGNORES = 2, REFUSES = 3 };

typedef struct fake_ctrl {
    unsigned id;
    int present, min, max, value, behaviour;
} fake_ctrl_t;

typedef struct fake_cam {
    fake_ctrl_t c[5];
    int writes, reads;
} fake_cam_t;

static fake_ctrl_t *fake_find(fake_cam_t *f, unsigned id)
{
    int i;
    for (i = 0; i < 5; i++) if (f->c[i].id == id && f->c[i].present) return &f->c[i];
    return NULL;
}

static int fake_ioctl(void *ctx, unsigned long req, void *arg)
{
    fake_cam_t *f = ctx;
    if (req == VIDIOC_QUERYCTRL) {
        struct v4l2_queryctrl *q = arg;
        fake_ctrl_t *c = fake_find(f, q->id);
        if (!c) { errno = EINVAL; return -1; }
        q->minimum = c->min;
        q->maximum = c->max;
        q->step = 1;
        return 0;
    }
    if (req == VIDIOC_S_CTRL || req == VIDIOC_G_CTRL) {
        struct v4l2_control *v = arg;
        fake_ctrl_t *c = fake_find(f, v->id);
        if (!c) { errno = EINVAL; return -1; }
        if (req == VIDIOC_G_CTRL) { f->reads++; v->value = c->value; return 0; }
        f->writes++;
        if (c->behaviour == REFUSES) { errno = EBUSY; return -1; }
        if (c->behaviour == IGNORES) return 0;          /* says yes, keeps its own */
        if (c->behaviour == CLAMPS) c->value = v->value < c->min ? c->min : v->value > c->max ? c->max : v->value;
        else c->value = v->value;
        return 0;
    }
    errno = ENOTTY;
    return -1;
}

/* a UVC webcam as it starts: aperture-priority auto exposure, auto gain on */
static void fake_webcam(fake_cam_t *f)
{
    memset(f, 0, sizeof *f);
    f->c[0] = (fake_ctrl_t){ V4L2_CID_EXPOSURE_AUTO, 1, 0, 3, V4L2_EXPOSURE_APERTURE_PRIORITY, CLAMPS };
    f->c[1] = (fake_ctrl_t){ V4L2_CID_EXPOSURE_AUTO_PRIORITY, 1, 0, 1, 1, CLAMPS };
    f->c[2] = (fake_ctrl_t){ V4L2_CID_EXPOSURE_ABSOLUTE, 1, 3, 2047, 156, CLAMPS };
    f->c[3] = (fake_ctrl_t){ V4L2_CID_AUTOGAIN, 1, 0, 1, 1, CLAMPS };
    f->c[4] = (fake_ctrl_t){ V4L2_CID_GAIN, 1, 0, 255, 64, CLAMPS };
}

static void controls(void)
{
    fake_cam_t f;
    char err[300];
    int rc;
    /* a camera that takes everything */
    fake_webcam(&f);
    rc = vp_v4l2_controls(fake_ioctl, &f, 1000, 32, err, sizeof err);
    CHECKF(rc == VP_OK, "%d %s", rc, err);
    CHECK(f.c[0].value == V4L2_EXPOSURE_MANUAL && f.c[1].value == 0 && f.c[2].value == 10 && f.c[3].value == 0 &&
          f.c[4].value == 32);
    CHECKF(f.reads == 5 && f.writes == 5, "%d reads, %d writes", f.reads, f.writes);
    printf("controls taken: exposure manual, priority off, 10 x 100 us, auto gain off, gain 32 (5 read back)\n");
    /* no exposure_auto_priority, no auto gain (a global-shutter camera): fine, they are optional */
    fake_webcam(&f);
    f.c[1].present = f.c[3].present = 0;
    CHECK(vp_v4l2_controls(fake_ioctl, &f, 1000, 0, err, sizeof err) == VP_OK && f.c[2].value == 10);
    /* an exposure beyond the camera's range: clamped, read back 2047, refused */
    fake_webcam(&f);
    rc = vp_v4l2_controls(fake_ioctl, &f, 500000, 0, err, sizeof err);
    CHECKF(rc == VP_EIO && strstr(err, "V4L2_CID_EXPOSURE_ABSOLUTE") && strstr(err, "5000") && strstr(err, "2047"), "%d %s",
           rc, err);
    printf("clamped: %s\n", err);
    /* says yes to manual exposure and stays in aperture priority */
    fake_webcam(&f);
    f.c[0].behaviour = IGNORES;
    rc = vp_v4l2_controls(fake_ioctl, &f, 1000, 0, err, sizeof err);
    CHECKF(rc == VP_EIO && strstr(err, "V4L2_CID_EXPOSURE_AUTO ") && strstr(err, "reads back 3"), "%d %s", rc, err);
    printf("ignored: %s\n", err);
    CHECK(f.writes == 1);         /* the write itself succeeded: only the read-back tells */
    /* a gain asked of a camera without one */
    fake_webcam(&f);
    f.c[4].present = 0;
    rc = vp_v4l2_controls(fake_ioctl, &f, 1000, 16, err, sizeof err);
    CHECKF(rc == VP_EIO && strstr(err, "V4L2_CID_GAIN") && strstr(err, "no such control"), "%d %s", rc, err);
    printf("missing: %s\n", err);
    /* a write refused (busy) */
    fake_webcam(&f);
    f.c[4].behaviour = REFUSES;
    rc = vp_v4l2_controls(fake_ioctl, &f, 1000, 16, err, sizeof err);
    CHECKF(rc == VP_EIO && strstr(err, "V4L2_CID_GAIN") && strstr(err, "refused"), "%d %s", rc, err);
    /* nothing asked: nothing touched */
    fake_webcam(&f);
    CHECK(vp_v4l2_controls(fake_ioctl, &f, 0, 0, err, sizeof err) == VP_OK && f.writes == 0 && f.reads == 0);
    CHECK(vp_v4l2_controls(fake_ioctl, &f, -1, 0, err, sizeof err) == VP_EINVAL);
    CHECK(vp_v4l2_controls(fake_ioctl, &f, 1000, NAN, err, sizeof err) == VP_EINVAL);
}

/* libcamera's read-back: a completed request's metadata against the manual settings */
static void metadata(void)
{
    char why[200];
    CHECK(vp_cam_exposure_taken(1000, 2.0, 1, 1000, 1, 2.0, why, sizeof why));
    CHECK(vp_cam_exposure_taken(1000, 2.0, 1, 1040, 1, 2.05, why, sizeof why));      /* a line, a gain step */
    CHECK(!vp_cam_exposure_taken(1000, 2.0, 1, 16600, 1, 2.0, why, sizeof why) && strstr(why, "ExposureTime") &&
          strstr(why, "16600"));
    printf("metadata: %s\n", why);
    CHECK(!vp_cam_exposure_taken(1000, 2.0, 1, 1000, 1, 8.0, why, sizeof why) && strstr(why, "AnalogueGain"));
    CHECK(!vp_cam_exposure_taken(1000, 2.0, 0, 0, 1, 2.0, why, sizeof why) && strstr(why, "ExposureTime: not in"));
    CHECK(!vp_cam_exposure_taken(1000, 2.0, 1, 1000, 0, 0, why, sizeof why) && strstr(why, "AnalogueGain: not in"));
}

/* ---- colour ---- */

#define W 64
#define H 24

static uint8_t yuyv[H][2 * W], rgb[H][3 * W], bgr[H][3 * W], out[H][W];

static int clamp255(double v) { long q = lround(v); return q < 0 ? 0 : q > 255 ? 255 : (int)q; }

static void colour(const char *dir)
{
    static const char *const name[4] = { "luma", "red", "green", "blue" };
    vp_rng_t r;
    int x, y, ch, off, step;
    vp_rng_seed(&r, 7);
    for (y = 0; y < H; y++)
        for (x = 0; x < 2 * W; x++) yuyv[y][x] = (uint8_t)(16 + vp_rng_below(&r, 225));
    for (y = 0; y < H; y++)
        for (x = 0; x < 3 * W; x++) rgb[y][x] = (uint8_t)vp_rng_below(&r, 256);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) { bgr[y][3 * x] = rgb[y][3 * x + 2]; bgr[y][3 * x + 1] = rgb[y][3 * x + 1]; bgr[y][3 * x + 2] = rgb[y][3 * x]; }
    CHECK(vp_cam_colour_parse("red") == VP_COLOUR_RED && vp_cam_colour_parse("luma") == VP_COLOUR_LUMA &&
          vp_cam_colour_parse("infrared") < 0 && vp_cam_colour_parse(NULL) < 0);
    /* in place where the channel is a byte of the pixel */
    CHECK(vp_cam_channel_view(VP_FOURCC('R', 'G', 'B', '3'), VP_COLOUR_RED, &off, &step) && off == 0 && step == 3);
    CHECK(vp_cam_channel_view(VP_FOURCC('B', 'G', 'R', '3'), VP_COLOUR_RED, &off, &step) && off == 2 && step == 3);
    CHECK(vp_cam_channel_view(VP_FOURCC('Y', 'U', 'Y', 'V'), VP_COLOUR_LUMA, &off, &step) && off == 0 && step == 2);
    CHECK(!vp_cam_channel_view(VP_FOURCC('Y', 'U', 'Y', 'V'), VP_COLOUR_RED, &off, &step));
    CHECK(!vp_cam_channel_view(VP_FOURCC('G', 'R', 'E', 'Y'), VP_COLOUR_GREEN, &off, &step));
    for (ch = 0; ch < 4; ch++) {
        int worst = 0;
        CHECK(vp_cam_channel(VP_FOURCC('R', 'G', 'B', '3'), &rgb[0][0], W, H, 3 * W, ch, &out[0][0], W) == VP_OK);
        for (y = 0; y < H; y++)
            for (x = 0; x < W; x++) {
                const uint8_t *p = &rgb[y][3 * x];
                int want = ch ? p[ch - 1] : clamp255(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]);
                if (abs(out[y][x] - want) > worst) worst = abs(out[y][x] - want);
            }
        CHECKF(worst == 0, "RGB24 %s off by %d", name[ch], worst);
        /* BGR24 gives the same channel */
        {
            static uint8_t o2[H][W];
            CHECK(vp_cam_channel(VP_FOURCC('B', 'G', 'R', '3'), &bgr[0][0], W, H, 3 * W, ch, &o2[0][0], W) == VP_OK);
            CHECK(!memcmp(o2, out, sizeof out));
        }
    }
    /* YUYV: pixel (5, 3) by hand, BT.601 limited range */
    {
        const uint8_t *q = &yuyv[3][4 * 2];
        double Y = q[2] - 16.0, cb = q[1] - 128.0, cr = q[3] - 128.0;
        CHECK(vp_cam_channel(VP_FOURCC('Y', 'U', 'Y', 'V'), &yuyv[0][0], W, H, 2 * W, VP_COLOUR_RED, &out[0][0], W) == VP_OK);
        CHECKF(out[3][5] == clamp255(255.0 / 219 * Y + 255.0 / 224 * 1.402 * cr), "red %d", out[3][5]);
        CHECK(vp_cam_channel(VP_FOURCC('Y', 'U', 'Y', 'V'), &yuyv[0][0], W, H, 2 * W, VP_COLOUR_BLUE, &out[0][0], W) == VP_OK);
        CHECKF(out[3][5] == clamp255(255.0 / 219 * Y + 255.0 / 224 * 1.772 * cb), "blue %d", out[3][5]);
    }
    /* bad input: nothing written */
    memset(out, 0xAB, sizeof out);
    CHECK(vp_cam_channel(VP_FOURCC('Y', 'U', 'Y', 'V'), &yuyv[0][0], W - 1, H, 2 * W, VP_COLOUR_RED, &out[0][0], W) == VP_EINVAL);
    CHECK(vp_cam_channel(VP_FOURCC('G', 'R', 'E', 'Y'), &yuyv[0][0], W, H, W, VP_COLOUR_RED, &out[0][0], W) == VP_EINVAL);
    CHECK(vp_cam_channel(VP_FOURCC('R', 'G', 'B', '3'), &rgb[0][0], W, H, 2 * W, VP_COLOUR_RED, &out[0][0], W) == VP_EINVAL);
    CHECK(vp_cam_channel(VP_FOURCC('R', 'G', 'B', '3'), &rgb[0][0], W, H, 3 * W, 7, &out[0][0], W) == VP_EINVAL);
    CHECK(out[0][0] == 0xAB && out[H - 1][W - 1] == 0xAB);
    if (dir) {
        /* the frames and every channel, for numpy */
        char path[512];
        FILE *fp;
        snprintf(path, sizeof path, "%s/yuyv.raw", dir);
        fp = fopen(path, "wb");
        CHECK(fp && fwrite(yuyv, 1, sizeof yuyv, fp) == sizeof yuyv);
        if (fp) fclose(fp);
        snprintf(path, sizeof path, "%s/rgb24.raw", dir);
        fp = fopen(path, "wb");
        CHECK(fp && fwrite(rgb, 1, sizeof rgb, fp) == sizeof rgb);
        if (fp) fclose(fp);
        for (ch = 0; ch < 4; ch++) {
            int k;
            for (k = 0; k < 2; k++) {
                unsigned fmt = k ? VP_FOURCC('R', 'G', 'B', '3') : VP_FOURCC('Y', 'U', 'Y', 'V');
                CHECK(vp_cam_channel(fmt, k ? &rgb[0][0] : &yuyv[0][0], W, H, k ? 3 * W : 2 * W, ch, &out[0][0], W) == VP_OK);
                snprintf(path, sizeof path, "%s/%s-%s.raw", dir, k ? "rgb24" : "yuyv", name[ch]);
                fp = fopen(path, "wb");
                CHECK(fp && fwrite(out, 1, sizeof out, fp) == sizeof out);
                if (fp) fclose(fp);
            }
        }
        printf("frames %dx%d and their channels written to %s\n", W, H, dir);
    }
}

int main(int argc, char **argv)
{
    controls();
    metadata();
    colour(argc > 1 ? argv[1] : NULL);
    return vp_test_done("test_port_camctl");
}
