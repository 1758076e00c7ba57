/* vp_v4l2 — see vp_v4l2.h. */
#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include "vp_rtclock.h"
#include "vp_status.h"
#include "vp_v4l2.h"

#define VP_V4L2_MAXBUF 8

typedef struct vp_v4l2 {
    int fd, nbuf, streaming, step;
    unsigned format;
    int width, height, stride;
    void *mem[VP_V4L2_MAXBUF];
    size_t len[VP_V4L2_MAXBUF];
    char dev[128];
    char err[256];
    unsigned long dropped;
    int64_t last_seq, last_ts;   /* newest frame dequeued (-1: none yet) */
    int colour, offset;          /* the laser's channel (VP_COLOUR_*) and its byte in a pixel */
    uint8_t *chan[VP_V4L2_MAXBUF];   /* that channel computed (YUYV colour), one per buffer */
} vp_v4l2_t;

static int vp_xioctl(int fd, unsigned long req, void *arg)
{
    int r;
    do r = ioctl(fd, req, arg); while (r < 0 && errno == EINTR);
    return r;
}

static void vp_fourcc_str(unsigned f, char out[5])
{
    int i;
    for (i = 0; i < 4; i++) { char ch = (char)((f >> (8 * i)) & 0xff); out[i] = ch >= 32 && ch < 127 ? ch : '?'; }
    out[4] = 0;
}

static void vp_v4l2_free(vp_v4l2_t *v)
{
    int i;
    if (v->streaming) {
        enum v4l2_buf_type t = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        vp_xioctl(v->fd, VIDIOC_STREAMOFF, &t);
    }
    for (i = 0; i < v->nbuf; i++) if (v->mem[i] && v->mem[i] != MAP_FAILED) munmap(v->mem[i], v->len[i]);
    for (i = 0; i < VP_V4L2_MAXBUF; i++) free(v->chan[i]);
    if (v->fd >= 0) close(v->fd);
    free(v);
}

static int vp_v4l2_fail(vp_v4l2_t *v, int rc, char *err, size_t errlen, const char *fmt, const char *what)
{
    char msg[256];
    snprintf(msg, sizeof msg, fmt, what);
    snprintf(err, errlen, "camera %s: %s", v->dev, msg);
    vp_v4l2_free(v);
    return rc;
}

static int64_t vp_v4l2_ts(const struct v4l2_buffer *b)
{
    return (int64_t)b->timestamp.tv_sec * 1000000000 + (int64_t)b->timestamp.tv_usec * 1000;
}

static int vp_v4l2_capture(void *ctx, int64_t not_before, int timeout_ms, vp_frame_t *f)
{
    vp_v4l2_t *v = ctx;
    int64_t deadline = vp_rt_now() + (int64_t)timeout_ms * 1000000;
    for (;;) {
        struct pollfd p;
        struct v4l2_buffer b;
        int64_t left = (deadline - vp_rt_now()) / 1000000;
        int r;
        p.fd = v->fd;
        p.events = POLLIN;
        p.revents = 0;
        r = poll(&p, 1, left > 0 ? (int)left : 0);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) { snprintf(v->err, sizeof v->err, "camera %s: poll: %s", v->dev, strerror(errno)); return VP_EIO; }
        if (r == 0) { snprintf(v->err, sizeof v->err, "camera %s: no frame within %d ms", v->dev, timeout_ms); return VP_ETIMEOUT; }
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        if (vp_xioctl(v->fd, VIDIOC_DQBUF, &b) < 0) {
            if (errno == EAGAIN) continue;
            snprintf(v->err, sizeof v->err, "camera %s: VIDIOC_DQBUF: %s", v->dev, strerror(errno));
            return errno == ENODEV ? VP_ENODEV : VP_EIO;
        }
        /* a frame older than one already seen (time stamp or sequence number going back), or a
         * clock that is not CLOCK_MONOTONIC, cannot be placed against the laser: refused, never
         * passed over (the stale-frame check would be skipped) */
        if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) != V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC ||
            (v->last_seq >= 0 && ((int64_t)b.sequence <= v->last_seq || vp_v4l2_ts(&b) < v->last_ts))) {
            snprintf(v->err, sizeof v->err, "camera %s: frame %u at %lld ns is not after frame %lld at %lld ns "
                     "(or its clock is not monotonic): refused", v->dev, b.sequence, (long long)vp_v4l2_ts(&b),
                     (long long)v->last_seq, (long long)v->last_ts);
            vp_xioctl(v->fd, VIDIOC_QBUF, &b);
            return VP_EIO;
        }
        v->last_seq = (int64_t)b.sequence;
        v->last_ts = vp_v4l2_ts(&b);
        /* broken frames and frames exposed before the caller's moment (or below the sequence
         * number asked for) go back to the driver */
        if ((b.flags & V4L2_BUF_FLAG_ERROR) || vp_v4l2_ts(&b) < not_before || (int64_t)b.sequence < f->seq) {
            v->dropped++;
            vp_xioctl(v->fd, VIDIOC_QBUF, &b);
            continue;
        }
        f->data = (const uint8_t *)v->mem[b.index] + v->offset;
        f->width = v->width;
        f->height = v->height;
        f->stride = v->stride;
        f->step = v->step;
        if (v->chan[b.index]) {
            /* the laser's colour from Y, Cb, Cr */
            if (vp_cam_channel(v->format, v->mem[b.index], v->width, v->height, v->stride, v->colour, v->chan[b.index],
                               v->width) != VP_OK) {
                snprintf(v->err, sizeof v->err, "camera %s: frame not convertible", v->dev);
                vp_xioctl(v->fd, VIDIOC_QBUF, &b);
                return VP_EIO;
            }
            f->data = v->chan[b.index];
            f->stride = v->width;
            f->step = 1;
        }
        f->t_ns = vp_v4l2_ts(&b);
        f->index = (int)b.index;
        f->seq = (int64_t)b.sequence;
        return VP_OK;
    }
}

static void vp_v4l2_release(void *ctx, vp_frame_t *f)
{
    vp_v4l2_t *v = ctx;
    struct v4l2_buffer b;
    memset(&b, 0, sizeof b);
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = (unsigned)f->index;
    if (vp_xioctl(v->fd, VIDIOC_QBUF, &b) < 0)
        snprintf(v->err, sizeof v->err, "camera %s: VIDIOC_QBUF: %s", v->dev, strerror(errno));
    f->data = NULL;
}

/* Drains the frames already waiting (back to the driver) and gives the next sequence number. */
static int vp_v4l2_mark(void *ctx, int64_t *next_seq)
{
    vp_v4l2_t *v = ctx;
    for (;;) {
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        if (vp_xioctl(v->fd, VIDIOC_DQBUF, &b) < 0) {
            if (errno == EAGAIN) break;
            snprintf(v->err, sizeof v->err, "camera %s: VIDIOC_DQBUF: %s", v->dev, strerror(errno));
            return VP_EIO;
        }
        if (v->last_seq >= 0 && ((int64_t)b.sequence <= v->last_seq || vp_v4l2_ts(&b) < v->last_ts)) {
            snprintf(v->err, sizeof v->err, "camera %s: frame %u is not after frame %lld: refused", v->dev, b.sequence,
                     (long long)v->last_seq);
            vp_xioctl(v->fd, VIDIOC_QBUF, &b);
            return VP_EIO;
        }
        v->last_seq = (int64_t)b.sequence;
        v->last_ts = vp_v4l2_ts(&b);
        v->dropped++;
        if (vp_xioctl(v->fd, VIDIOC_QBUF, &b) < 0) {
            snprintf(v->err, sizeof v->err, "camera %s: VIDIOC_QBUF: %s", v->dev, strerror(errno));
            return VP_EIO;
        }
    }
    *next_seq = v->last_seq + 1;
    return VP_OK;
}

static const char *vp_v4l2_ctrl_name(unsigned id)
{
    switch (id) {
    case V4L2_CID_EXPOSURE_AUTO: return "V4L2_CID_EXPOSURE_AUTO (exposure, auto)";
    case V4L2_CID_EXPOSURE_AUTO_PRIORITY: return "V4L2_CID_EXPOSURE_AUTO_PRIORITY (exposure_auto_priority)";
    case V4L2_CID_EXPOSURE_ABSOLUTE: return "V4L2_CID_EXPOSURE_ABSOLUTE (exposure time, 100 us)";
    case V4L2_CID_AUTOGAIN: return "V4L2_CID_AUTOGAIN (gain, auto)";
    case V4L2_CID_GAIN: return "V4L2_CID_GAIN (gain)";
    default: return "control";
    }
}

/* One control set and read back. optional: a camera without it passes. */
static int vp_v4l2_ctrl(vp_v4l2_ioctl_fn ioc, void *ctx, unsigned id, int value, int optional, char *err, size_t errlen)
{
    struct v4l2_queryctrl q;
    struct v4l2_control c;
    memset(&q, 0, sizeof q);
    q.id = id;
    if (ioc(ctx, VIDIOC_QUERYCTRL, &q) < 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED)) {
        if (optional) return VP_OK;
        snprintf(err, errlen, "%s: the camera has no such control", vp_v4l2_ctrl_name(id));
        return VP_EIO;
    }
    memset(&c, 0, sizeof c);
    c.id = id;
    c.value = value;
    if (ioc(ctx, VIDIOC_S_CTRL, &c) < 0) {
        snprintf(err, errlen, "%s: setting %d refused: %s", vp_v4l2_ctrl_name(id), value, strerror(errno));
        return VP_EIO;
    }
    memset(&c, 0, sizeof c);
    c.id = id;
    if (ioc(ctx, VIDIOC_G_CTRL, &c) < 0) {
        snprintf(err, errlen, "%s: cannot be read back: %s", vp_v4l2_ctrl_name(id), strerror(errno));
        return VP_EIO;
    }
    if (c.value != value) {
        snprintf(err, errlen, "%s: set to %d, the camera reads back %d (not taken)", vp_v4l2_ctrl_name(id), value, c.value);
        return VP_EIO;
    }
    return VP_OK;
}

int vp_v4l2_controls(vp_v4l2_ioctl_fn ioc, void *ctx, int exposure_us, double gain, char *err, size_t errlen)
{
    if (!ioc || exposure_us < 0 || !(gain >= 0) || gain > 2147483647.0) {
        if (err && errlen) snprintf(err, errlen, "camera controls: exposure %d us, gain %g: out of range", exposure_us, gain);
        return VP_EINVAL;
    }
    if (exposure_us > 0) {
        int units = (exposure_us + 50) / 100;
        if (units < 1) units = 1;
        VP_TRY(vp_v4l2_ctrl(ioc, ctx, V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, 0, err, errlen));
        /* UVC: with priority on, the camera may lower the frame rate instead of keeping the exposure */
        VP_TRY(vp_v4l2_ctrl(ioc, ctx, V4L2_CID_EXPOSURE_AUTO_PRIORITY, 0, 1, err, errlen));
        VP_TRY(vp_v4l2_ctrl(ioc, ctx, V4L2_CID_AUTOGAIN, 0, 1, err, errlen));
        VP_TRY(vp_v4l2_ctrl(ioc, ctx, V4L2_CID_EXPOSURE_ABSOLUTE, units, 0, err, errlen));
    }
    if (gain > 0) VP_TRY(vp_v4l2_ctrl(ioc, ctx, V4L2_CID_GAIN, (int)lround(gain), 0, err, errlen));
    return VP_OK;
}

static int vp_v4l2_fd_ioctl(void *ctx, unsigned long req, void *arg) { return vp_xioctl(*(int *)ctx, req, arg); }

static void vp_v4l2_close(void *ctx) { vp_v4l2_free(ctx); }
static const char *vp_v4l2_error(void *ctx) { return ((vp_v4l2_t *)ctx)->err; }

int vp_v4l2_open(const vp_v4l2_config_t *cfg, vp_cam_t *cam, char *err, size_t errlen)
{
    vp_v4l2_t *v;
    struct stat st;
    struct v4l2_capability cap;
    struct v4l2_fmtdesc fd;
    struct v4l2_format fmt;
    struct v4l2_requestbuffers rb;
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    unsigned caps, want = 0;
    char offered[160] = "", fc[5];
    int have_grey = 0, have_yuyv = 0, have_rgb = 0, have_bgr = 0, i, off = 0, step = 1;
    if (!cfg || !cfg->device || !cam) return VP_EINVAL;
    v = calloc(1, sizeof *v);
    if (!v) return VP_ENOMEM;
    v->fd = -1;
    v->last_seq = v->last_ts = -1;
    snprintf(v->dev, sizeof v->dev, "%s", cfg->device);
    v->fd = open(cfg->device, O_RDWR | O_NONBLOCK);
    if (v->fd < 0) {
        int e = errno;
        if (e == ENOENT || e == ENXIO || e == ENODEV) return vp_v4l2_fail(v, VP_ENODEV, err, errlen, "%s (is it plugged in and enabled?)", strerror(e));
        if (e == EACCES || e == EPERM) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s (add the user to group 'video')", strerror(e));
        if (e == EBUSY) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "busy: another program holds it");
        return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", strerror(e));
    }
    if (fstat(v->fd, &st) != 0 || !S_ISCHR(st.st_mode)) return vp_v4l2_fail(v, VP_ENODEV, err, errlen, "%s", "not a character device");
    memset(&cap, 0, sizeof cap);
    if (vp_xioctl(v->fd, VIDIOC_QUERYCAP, &cap) < 0) return vp_v4l2_fail(v, VP_ENODEV, err, errlen, "%s", "not a V4L2 device");
    caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) return vp_v4l2_fail(v, VP_ENODEV, err, errlen, "%s", "not a video capture device (a metadata or output node?)");
    if (!(caps & V4L2_CAP_STREAMING)) return vp_v4l2_fail(v, VP_ENODEV, err, errlen, "%s", "no streaming I/O");
    /* pixel formats offered */
    for (i = 0; i < 64; i++) {
        memset(&fd, 0, sizeof fd);
        fd.index = (unsigned)i;
        fd.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        if (vp_xioctl(v->fd, VIDIOC_ENUM_FMT, &fd) < 0) break;
        if (fd.pixelformat == V4L2_PIX_FMT_GREY) have_grey = 1;
        if (fd.pixelformat == V4L2_PIX_FMT_YUYV) have_yuyv = 1;
        if (fd.pixelformat == V4L2_PIX_FMT_RGB24) have_rgb = 1;
        if (fd.pixelformat == V4L2_PIX_FMT_BGR24) have_bgr = 1;
        vp_fourcc_str(fd.pixelformat, fc);
        if (strlen(offered) + 6 < sizeof offered) { strcat(offered, " "); strcat(offered, fc); }
    }
    if (cfg->colour < VP_COLOUR_LUMA || cfg->colour > VP_COLOUR_BLUE) return vp_v4l2_fail(v, VP_EINVAL, err, errlen, "%s", "unknown laser colour");
    if (cfg->format == V4L2_PIX_FMT_GREY && have_grey) want = V4L2_PIX_FMT_GREY;
    else if (cfg->format == V4L2_PIX_FMT_YUYV && have_yuyv) want = V4L2_PIX_FMT_YUYV;
    else if (cfg->format == V4L2_PIX_FMT_RGB24 && have_rgb) want = V4L2_PIX_FMT_RGB24;
    else if (cfg->format == V4L2_PIX_FMT_BGR24 && have_bgr) want = V4L2_PIX_FMT_BGR24;
    else if (!cfg->format && cfg->colour == VP_COLOUR_LUMA) want = have_grey ? V4L2_PIX_FMT_GREY : have_yuyv ? V4L2_PIX_FMT_YUYV : 0;
    else if (!cfg->format)
        want = have_rgb ? V4L2_PIX_FMT_RGB24 : have_bgr ? V4L2_PIX_FMT_BGR24 : have_yuyv ? V4L2_PIX_FMT_YUYV : 0;
    if (!want) {
        char msg[200];
        snprintf(msg, sizeof msg, "offers no %s format (has:%s)",
                 cfg->format ? "such" : cfg->colour ? "colour (RGB24, BGR24 or YUYV)" : "GREY or YUYV", offered[0] ? offered : " none");
        return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", msg);
    }
    if (want == V4L2_PIX_FMT_GREY && cfg->colour != VP_COLOUR_LUMA)
        return vp_v4l2_fail(v, VP_EINVAL, err, errlen, "%s", "a GREY camera has no colour: set [camera] laser_colour = luma or a colour format");
    memset(&fmt, 0, sizeof fmt);
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (vp_xioctl(v->fd, VIDIOC_G_FMT, &fmt) < 0) return vp_v4l2_fail(v, VP_EIO, err, errlen, "VIDIOC_G_FMT: %s", strerror(errno));
    if (cfg->width > 0 && cfg->height > 0) { fmt.fmt.pix.width = (unsigned)cfg->width; fmt.fmt.pix.height = (unsigned)cfg->height; }
    fmt.fmt.pix.pixelformat = want;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (vp_xioctl(v->fd, VIDIOC_S_FMT, &fmt) < 0) {
        if (errno == EBUSY) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "busy: another program streams from it");
        return vp_v4l2_fail(v, VP_EIO, err, errlen, "VIDIOC_S_FMT: %s", strerror(errno));
    }
    if (fmt.fmt.pix.pixelformat != want) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "driver refused the pixel format");
    v->format = want;
    v->colour = cfg->colour;
    v->width = (int)fmt.fmt.pix.width;
    v->height = (int)fmt.fmt.pix.height;
    {
        int bpp = want == V4L2_PIX_FMT_GREY ? 1 : want == V4L2_PIX_FMT_YUYV ? 2 : 3;
        v->stride = fmt.fmt.pix.bytesperline ? (int)fmt.fmt.pix.bytesperline : v->width * bpp;
        if (v->stride < v->width * bpp) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "rows shorter than the width");
    }
    if (vp_cam_channel_view(want, cfg->colour, &off, &step)) {
        v->offset = off;
        v->step = step;
    } else {
        /* computed per frame (YUYV colour, luma of RGB) into a buffer of its own */
        if (want == V4L2_PIX_FMT_YUYV && v->width % 2) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "YUYV of odd width");
        v->step = 1;
        v->offset = 0;
    }
    {
        char cerr[200];
        int rc = vp_v4l2_controls(vp_v4l2_fd_ioctl, &v->fd, cfg->exposure_us, cfg->gain, cerr, sizeof cerr);
        if (rc != VP_OK) return vp_v4l2_fail(v, rc == VP_EINVAL ? VP_EINVAL : VP_EIO, err, errlen, "%s", cerr);
    }
    memset(&rb, 0, sizeof rb);
    rb.count = (unsigned)(cfg->buffers > 0 ? cfg->buffers : 4);
    if (rb.count > VP_V4L2_MAXBUF) rb.count = VP_V4L2_MAXBUF;
    rb.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    rb.memory = V4L2_MEMORY_MMAP;
    if (vp_xioctl(v->fd, VIDIOC_REQBUFS, &rb) < 0) {
        if (errno == EBUSY) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "busy: another program streams from it");
        return vp_v4l2_fail(v, VP_EIO, err, errlen, "VIDIOC_REQBUFS: %s", strerror(errno));
    }
    if (rb.count < 2) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "too few capture buffers");
    v->nbuf = (int)rb.count;
    for (i = 0; i < v->nbuf; i++) {
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = (unsigned)i;
        if (vp_xioctl(v->fd, VIDIOC_QUERYBUF, &b) < 0) return vp_v4l2_fail(v, VP_EIO, err, errlen, "VIDIOC_QUERYBUF: %s", strerror(errno));
        v->len[i] = b.length;
        v->mem[i] = mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, v->fd, b.m.offset);
        if (v->mem[i] == MAP_FAILED) return vp_v4l2_fail(v, VP_EIO, err, errlen, "mmap: %s", strerror(errno));
        if ((size_t)v->stride * (size_t)v->height > b.length) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "buffer smaller than a frame");
        if (!vp_cam_channel_view(want, cfg->colour, &off, &step)) {
            v->chan[i] = malloc((size_t)v->width * (size_t)v->height);
            if (!v->chan[i]) return vp_v4l2_fail(v, VP_ENOMEM, err, errlen, "%s", "out of memory");
        }
        if (vp_xioctl(v->fd, VIDIOC_QBUF, &b) < 0) return vp_v4l2_fail(v, VP_EIO, err, errlen, "VIDIOC_QBUF: %s", strerror(errno));
    }
    if (vp_xioctl(v->fd, VIDIOC_STREAMON, &type) < 0) {
        if (errno == EBUSY) return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", "busy: another program streams from it");
        return vp_v4l2_fail(v, VP_EIO, err, errlen, "VIDIOC_STREAMON: %s", strerror(errno));
    }
    v->streaming = 1;
    cam->ctx = v;
    cam->capture = vp_v4l2_capture;
    cam->release = vp_v4l2_release;
    cam->close = vp_v4l2_close;
    cam->error = vp_v4l2_error;
    cam->mark = vp_v4l2_mark;
    cam->name = "v4l2";
    return VP_OK;
}
