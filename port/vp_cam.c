/* vp_cam — see vp_cam.h: the backend chosen by name. */
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
