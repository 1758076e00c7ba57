/* vp_cam — the camera boundary: a grayscale frame and a capture interface that V4L2, libcamera
 * and the host-sim renderer all fill the same way. Nothing above it knows which one it was. */
#ifndef VP_CAM_H
#define VP_CAM_H
#include <stddef.h>
#include <stdint.h>

typedef struct vp_frame {
    const uint8_t *data;     /* first luma byte of the top row */
    int width, height;
    int stride;              /* bytes from one row to the next */
    int step;                /* bytes from one pixel to the next: 1 GREY, 2 YUYV (luma bytes) */
    int64_t t_ns;            /* exposure time stamp (CLOCK_MONOTONIC; simulated clock in dry runs) */
    int index;               /* backend buffer index, for release */
    int64_t seq;             /* the camera's frame sequence number (-1: the backend gives none).
                                On entry to capture: the lowest one the caller will accept (a hint:
                                a backend may skip older frames; the caller checks again) */
} vp_frame_t;

#define VP_FRAME_PIX(f, x, y) ((f)->data[(size_t)(y) * (size_t)(f)->stride + (size_t)(x) * (size_t)(f)->step])

typedef struct vp_cam {
    void *ctx;
    /* A frame exposed at or after not_before_ns (older queued frames are dropped), within
     * timeout_ms: VP_OK, VP_ETIMEOUT, VP_EIO. The frame stays valid until release. */
    int  (*capture)(void *ctx, int64_t not_before_ns, int timeout_ms, vp_frame_t *f);
    void (*release)(void *ctx, vp_frame_t *f);
    void (*close)(void *ctx);                  /* releases everything, ctx included */
    const char *(*error)(void *ctx);           /* the last failure in words (may be NULL) */
    /* May be NULL. The sequence number of the next frame the camera will deliver, now: frames
     * already waiting in the queue are dropped (drained), so a frame carrying this number or a
     * later one left the sensor after the call (pipeline latency aside: see vp_machine). Called
     * right after the laser is switched. VP_OK or VP_EIO. */
    int  (*mark)(void *ctx, int64_t *next_seq);
    const char *name;        /* "v4l2", "libcamera", "camsim" */
} vp_cam_t;

#define VP_FOURCC(a, b, c, d) ((unsigned)(a) | ((unsigned)(b) << 8) | ((unsigned)(c) << 16) | ((unsigned)(d) << 24))

/* Opening by name, from a board file: the backends behind one call. */
typedef struct vp_cam_config {
    char backend[16];        /* "v4l2" (default when empty) or "libcamera" */
    char device[128];        /* v4l2: "/dev/video0"; libcamera: camera id or "" for the first */
    int width, height;       /* 0: the device's default */
    unsigned format;         /* v4l2 fourcc, 0: GREY else YUYV */
    int exposure_us;         /* > 0: manual exposure */
    int buffers;             /* 0: 4 */
} vp_cam_config_t;

/* VP_ENODEV also when the backend was not built (libcamera without the library). */
int vp_cam_open(const vp_cam_config_t *c, vp_cam_t *cam, char *err, size_t errlen);

#endif
