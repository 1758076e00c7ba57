/* vp_v4l2 — the V4L2 camera backend (Linux): the device named in the board file, GREY or YUYV
 * (luma used in place, no conversion), or for a coloured laser the channel of its colour (RGB24,
 * BGR24 in place; YUYV converted, vp_cam_channel), mmap streaming, poll timeouts, stale frames dropped by
 * their monotonic time stamps, optional manual exposure. Errors say what is wrong in one line:
 * missing device, not a capture device, busy (another program streams), permission, no usable
 * pixel format (the formats offered are listed). */
#ifndef VP_V4L2_H
#define VP_V4L2_H
#include <stddef.h>
#include "vp_cam.h"

typedef struct vp_v4l2_config {
    const char *device;      /* "/dev/video0" */
    int width, height;       /* 0: keep the device's current size */
    unsigned format;         /* 0: GREY if offered, else YUYV (a colour: RGB24, BGR24, else YUYV); or
                                VP_FOURCC('G','R','E','Y') / ('Y','U','Y','V') / ('R','G','B','3') / ('B','G','R','3') */
    int buffers;             /* mmap buffers (0: 4) */
    int exposure_us;         /* > 0: manual exposure (vp_v4l2_controls) */
    double gain;             /* > 0: this fixed gain (V4L2_CID_GAIN, the driver's units) */
    int colour;              /* VP_COLOUR_*: the laser's channel; a colour one needs YUYV, RGB24 or BGR24 */
} vp_v4l2_config_t;

/* The controls a scan relies on, set and each read back with VIDIOC_G_CTRL through ioc (the
 * device's ioctl; tests give a fake camera): with exposure_us > 0 V4L2_CID_EXPOSURE_AUTO =
 * manual, V4L2_CID_EXPOSURE_AUTO_PRIORITY = 0 and V4L2_CID_AUTOGAIN = 0 where the camera has
 * them, V4L2_CID_EXPOSURE_ABSOLUTE = exposure_us / 100 (its unit is 100 us); with gain > 0
 * V4L2_CID_GAIN = gain. VP_EIO when the camera lacks a control asked for, refuses it, or reads
 * back another value: err names the control and both values. */
typedef int (*vp_v4l2_ioctl_fn)(void *ctx, unsigned long request, void *arg);
int vp_v4l2_controls(vp_v4l2_ioctl_fn ioc, void *ctx, int exposure_us, double gain, char *err, size_t errlen);

/* Fills cam. VP_ENODEV (no such device, not V4L2, no capture), VP_EIO (busy, permission,
 * no GREY/YUYV, ioctl failures); err gets the reason. */
int vp_v4l2_open(const vp_v4l2_config_t *cfg, vp_cam_t *cam, char *err, size_t errlen);

#endif
