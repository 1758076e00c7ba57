/* vp_v4l2 — the V4L2 camera backend (Linux): the device named in the board file, GREY or YUYV
 * (luma used in place, no conversion), mmap streaming, poll timeouts, stale frames dropped by
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
    unsigned format;         /* 0: GREY if offered, else YUYV; or VP_FOURCC('G','R','E','Y') / ('Y','U','Y','V') */
    int buffers;             /* mmap buffers (0: 4) */
    int exposure_us;         /* > 0: manual exposure (a failure to set it is not fatal) */
} vp_v4l2_config_t;

/* Fills cam. VP_ENODEV (no such device, not V4L2, no capture), VP_EIO (busy, permission,
 * no GREY/YUYV, ioctl failures); err gets the reason. */
int vp_v4l2_open(const vp_v4l2_config_t *cfg, vp_cam_t *cam, char *err, size_t errlen);

#endif
