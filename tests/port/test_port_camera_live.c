/* A real V4L2 camera, where one exists (skipped elsewhere): format, frames within a timeout,
 * time stamps not older than asked, the luma plane readable, the spot detector run on it. */
#include <glob.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "vp_cam.h"
#include "vp_laser.h"
#include "vp_status.h"
#include "vp_test.h"

static vp_spot_ws_t ws;

int main(void)
{
    glob_t g;
    vp_cam_config_t c;
    vp_cam_t cam;
    char err[300];
    size_t i;
    int opened = 0, k;
    int64_t last_seq;
    if (glob("/dev/video*", 0, NULL, &g) != 0) TEST_SKIP("no /dev/video* on this machine");
    for (i = 0; i < g.gl_pathc && !opened; i++) {
        memset(&c, 0, sizeof c);
        snprintf(c.device, sizeof c.device, "%s", g.gl_pathv[i]);
        if (vp_cam_open(&c, &cam, err, sizeof err) == VP_OK) opened = 1;
        else printf("%s\n", err);
    }
    globfree(&g);
    if (!opened) TEST_SKIP("no usable capture device among /dev/video*");
    last_seq = -1;
    for (k = 0; k < 5; k++) {
        vp_frame_t f;
        vp_spot_t sp;
        struct timespec ts;
        int64_t now;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        now = (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
        memset(&f, 0, sizeof f);
        f.seq = -1;                      /* any sequence number */
        CHECKF(cam.capture(cam.ctx, now, 3000, &f) == VP_OK, "%s", cam.error ? cam.error(cam.ctx) : "");
        if (!f.data) break;
        CHECK(f.width > 0 && f.height > 0 && f.stride >= f.width * f.step);
        CHECK(f.t_ns >= now || f.t_ns == 0);
        /* frames come numbered upwards */
        CHECKF(f.seq > last_seq, "frame %lld after %lld", (long long)f.seq, (long long)last_seq);
        last_seq = f.seq;
        CHECK(vp_spot_find(&f, NULL, NULL, &ws, &sp) == VP_OK);
        printf("%s frame %dx%d step %d: spot result %d noise %.1f\n", cam.name, f.width, f.height, f.step, sp.result, sp.noise);
        cam.release(cam.ctx, &f);
    }
    cam.close(cam.ctx);
    return vp_test_done("test_port_camera_live");
}
