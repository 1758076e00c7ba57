/* vp_cam — the camera boundary: a grayscale frame and a capture interface that V4L2, libcamera
 * and the host-sim renderer all fill the same way. Nothing above it knows which one it was. */
#ifndef VP_CAM_H
#define VP_CAM_H
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

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
    int exposure_us;         /* > 0: manual exposure (refused if the camera does not take it) */
    double gain;             /* > 0: fixed analogue gain (V4L2: the driver's units; libcamera: x) */
    int colour;              /* VP_COLOUR_*: the channel the laser shows in (colour formats) */
    int buffers;             /* 0: 4 */
} vp_cam_config_t;

/* The laser's colour: which channel of a colour frame the spot is looked for in. */
enum { VP_COLOUR_LUMA = 0, VP_COLOUR_RED = 1, VP_COLOUR_GREEN = 2, VP_COLOUR_BLUE = 3 };
/* A frame's own report of its exposure (libcamera's request metadata) against the manual
 * settings: 1 when it has both and they match (the exposure within 2 % + 30 us: sensors set it
 * in whole lines; the gain within 3 %: their gain steps), else 0 and why names the control and
 * both values. have_*: the metadata holds it. */
int vp_cam_exposure_taken(int exposure_us, double gain, int have_exposure, long exposure_md, int have_gain, double gain_md,
                          char *why, size_t whylen);

/* "red", "green", "blue", "luma" -> VP_COLOUR_*; -1 otherwise. */
int vp_cam_colour_parse(const char *name);

/* Where one channel of a packed frame lies, when it is a byte of each pixel (no conversion):
 * GREY luma; YUYV luma (step 2); RGB24 / BGR24 red, green, blue (step 3). 1 and the byte
 * offset and step, or 0 when the channel must be computed (vp_cam_channel). */
int vp_cam_channel_view(unsigned fourcc, int colour, int *offset, int *step);
/* One channel of a packed frame into out (width x height, out_stride bytes a row): the bytes as
 * they are where vp_cam_channel_view says so; YUYV red, green or blue from Y and the pair's Cb,
 * Cr (ITU-R BT.601, limited range, as V4L2 sends YUYV by default); luma of RGB24 / BGR24 as
 * BT.601's Y' (0.299 R + 0.587 G + 0.114 B). Rounded, clamped to 0..255. VP_EINVAL for an odd
 * YUYV width, an unknown format or colour, or a stride too small. */
int vp_cam_channel(unsigned fourcc, const uint8_t *src, int width, int height, int stride, int colour, uint8_t *out,
                   int out_stride);

/* VP_ENODEV also when the backend was not built (libcamera without the library). */
int vp_cam_open(const vp_cam_config_t *c, vp_cam_t *cam, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
