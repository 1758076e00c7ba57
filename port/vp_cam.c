/* vp_cam — see vp_cam.h: the backend chosen by name. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "vp_cam.h"
#include "vp_libcamera.h"
#include "vp_status.h"
#include "vp_v4l2.h"

int vp_cam_open(const vp_cam_config_t *c, vp_cam_t *cam, char *err, size_t errlen)
{
    if (!c || !cam) return VP_EINVAL;
    memset(cam, 0, sizeof *cam);
    if (!c->backend[0] || !strcmp(c->backend, "v4l2")) {
        vp_v4l2_config_t v;
        memset(&v, 0, sizeof v);
        v.device = c->device[0] ? c->device : "/dev/video0";
        v.width = c->width;
        v.height = c->height;
        v.format = c->format;
        v.exposure_us = c->exposure_us;
        v.gain = c->gain;
        v.colour = c->colour;
        v.buffers = c->buffers;
        return vp_v4l2_open(&v, cam, err, errlen);
    }
    if (!strcmp(c->backend, "libcamera")) {
#ifdef VP_HAVE_LIBCAMERA
        vp_libcamera_config_t l;
        memset(&l, 0, sizeof l);
        l.camera = c->device;
        l.width = c->width;
        l.height = c->height;
        l.exposure_us = c->exposure_us;
        l.gain = c->gain;
        l.buffers = c->buffers;
        return vp_libcamera_open(&l, cam, err, errlen);
#else
        snprintf(err, errlen, "camera: built without libcamera (install libcamera-dev and rebuild, or use v4l2)");
        return VP_ENODEV;
#endif
    }
    snprintf(err, errlen, "camera: unknown backend '%s' (v4l2 or libcamera)", c->backend);
    return VP_EINVAL;
}

int vp_cam_colour_parse(const char *name)
{
    static const char *const names[4] = { "luma", "red", "green", "blue" };
    int i;
    for (i = 0; name && i < 4; i++) if (!strcmp(name, names[i])) return i;
    return -1;
}

#define VP_FCC_GREY VP_FOURCC('G', 'R', 'E', 'Y')
#define VP_FCC_YUYV VP_FOURCC('Y', 'U', 'Y', 'V')
#define VP_FCC_RGB3 VP_FOURCC('R', 'G', 'B', '3')
#define VP_FCC_BGR3 VP_FOURCC('B', 'G', 'R', '3')

int vp_cam_channel_view(unsigned fourcc, int colour, int *offset, int *step)
{
    if (colour == VP_COLOUR_LUMA && (fourcc == VP_FCC_GREY || fourcc == VP_FCC_YUYV)) {
        *offset = 0;
        *step = fourcc == VP_FCC_GREY ? 1 : 2;
        return 1;
    }
    if (colour >= VP_COLOUR_RED && colour <= VP_COLOUR_BLUE && (fourcc == VP_FCC_RGB3 || fourcc == VP_FCC_BGR3)) {
        *offset = fourcc == VP_FCC_RGB3 ? colour - VP_COLOUR_RED : VP_COLOUR_BLUE - colour;
        *step = 3;
        return 1;
    }
    return 0;
}

static uint8_t vp_cam_clamp(double v)
{
    long q = lround(v);
    return (uint8_t)(q < 0 ? 0 : q > 255 ? 255 : q);
}

int vp_cam_channel(unsigned fourcc, const uint8_t *src, int width, int height, int stride, int colour, uint8_t *out,
                   int out_stride)
{
    int off, step, x, y;
    if (!src || !out || width < 1 || height < 1 || out_stride < width || colour < VP_COLOUR_LUMA || colour > VP_COLOUR_BLUE)
        return VP_EINVAL;
    if (vp_cam_channel_view(fourcc, colour, &off, &step)) {
        if (stride < width * step) return VP_EINVAL;
        for (y = 0; y < height; y++)
            for (x = 0; x < width; x++) out[(size_t)y * out_stride + x] = src[(size_t)y * stride + (size_t)x * step + off];
        return VP_OK;
    }
    if (fourcc == VP_FCC_YUYV) {
        /* Y Cb Y Cr for each pair; limited range: Y 16..235, Cb Cr 16..240 about 128 */
        if (width % 2 || stride < 2 * width) return VP_EINVAL;
        for (y = 0; y < height; y++) {
            const uint8_t *p = src + (size_t)y * stride;
            for (x = 0; x < width; x++) {
                const uint8_t *q = p + 4 * (x / 2);
                double Y = 1.164383561643836 * (p[2 * x] - 16), cb = q[1] - 128.0, cr = q[3] - 128.0, v;
                if (colour == VP_COLOUR_RED) v = Y + 1.596026785714286 * cr;
                else if (colour == VP_COLOUR_GREEN) v = Y - 0.391762290094914 * cb - 0.812967647237771 * cr;
                else v = Y + 2.017232142857143 * cb;
                out[(size_t)y * out_stride + x] = vp_cam_clamp(v);
            }
        }
        return VP_OK;
    }
    if ((fourcc == VP_FCC_RGB3 || fourcc == VP_FCC_BGR3) && colour == VP_COLOUR_LUMA) {
        int r = fourcc == VP_FCC_RGB3 ? 0 : 2, b = 2 - r;
        if (stride < 3 * width) return VP_EINVAL;
        for (y = 0; y < height; y++)
            for (x = 0; x < width; x++) {
                const uint8_t *q = src + (size_t)y * stride + 3 * (size_t)x;
                out[(size_t)y * out_stride + x] = vp_cam_clamp(0.299 * q[r] + 0.587 * q[1] + 0.114 * q[b]);
            }
        return VP_OK;
    }
    return VP_EINVAL;
}

int vp_cam_exposure_taken(int exposure_us, double gain, int have_exposure, long exposure_md, int have_gain, double gain_md,
                          char *why, size_t whylen)
{
    if (!have_exposure) { snprintf(why, whylen, "ExposureTime: not in the frame's metadata (cannot be confirmed)"); return 0; }
    if (!have_gain) { snprintf(why, whylen, "AnalogueGain: not in the frame's metadata (cannot be confirmed)"); return 0; }
    if (!(fabs((double)exposure_md - exposure_us) <= 0.02 * exposure_us + 30)) {
        snprintf(why, whylen, "ExposureTime: set %d us, the frame says %ld us", exposure_us, exposure_md);
        return 0;
    }
    if (!(fabs(gain_md - gain) <= 0.03 * gain)) {
        snprintf(why, whylen, "AnalogueGain: set %.3f, the frame says %.3f", gain, gain_md);
        return 0;
    }
    return 1;
}
