/* Camera backends without a camera: clear errors for a missing device, a file that is not a
 * V4L2 device, an unknown backend, libcamera not built or no such camera. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_cam.h"
#include "vp_status.h"
#include "vp_test.h"
#include "vp_v4l2.h"

int main(void)
{
    vp_cam_config_t c;
    vp_cam_t cam;
    char err[300];
    int rc;
    setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 1);
    memset(&c, 0, sizeof c);
    snprintf(c.device, sizeof c.device, "/dev/video-vp-no-such");
    rc = vp_cam_open(&c, &cam, err, sizeof err);
    CHECKF(rc == VP_ENODEV && strstr(err, "/dev/video-vp-no-such") && strstr(err, "No such file"), "%d %s", rc, err);
    printf("missing: %s\n", err);
    snprintf(c.device, sizeof c.device, "/dev/null");
    rc = vp_cam_open(&c, &cam, err, sizeof err);
    CHECKF(rc == VP_ENODEV && strstr(err, "not a V4L2 device"), "%d %s", rc, err);
    printf("not v4l2: %s\n", err);
    snprintf(c.device, sizeof c.device, "tests/vp_test.h");
    rc = vp_cam_open(&c, &cam, err, sizeof err);
    CHECKF(rc == VP_ENODEV && strstr(err, "not a character device"), "%d %s", rc, err);
    snprintf(c.backend, sizeof c.backend, "webcam");
    rc = vp_cam_open(&c, &cam, err, sizeof err);
    CHECKF(rc == VP_EINVAL && strstr(err, "unknown backend 'webcam'"), "%d %s", rc, err);
    snprintf(c.backend, sizeof c.backend, "libcamera");
    snprintf(c.device, sizeof c.device, "vp-no-such-camera");
    rc = vp_cam_open(&c, &cam, err, sizeof err);
    CHECKF(rc == VP_ENODEV, "%d %s", rc, err);
#ifdef VP_HAVE_LIBCAMERA
    CHECKF(strstr(err, "no camera"), "%s", err);
    printf("libcamera (built): %s\n", err);
#else
    CHECKF(strstr(err, "built without libcamera"), "%s", err);
    printf("libcamera (not built): %s\n", err);
#endif
    return vp_test_done("test_port_camera");
}
