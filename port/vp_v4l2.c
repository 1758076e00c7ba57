/* vp_v4l2 — see vp_v4l2.h. */
#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
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
        f->data = v->mem[b.index];
        f->width = v->width;
        f->height = v->height;
        f->stride = v->stride;
        f->step = v->step;
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
    int have_grey = 0, have_yuyv = 0, i;
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
        vp_fourcc_str(fd.pixelformat, fc);
        if (strlen(offered) + 6 < sizeof offered) { strcat(offered, " "); strcat(offered, fc); }
    }
    if (cfg->format == V4L2_PIX_FMT_GREY && have_grey) want = V4L2_PIX_FMT_GREY;
    else if (cfg->format == V4L2_PIX_FMT_YUYV && have_yuyv) want = V4L2_PIX_FMT_YUYV;
    else if (!cfg->format) want = have_grey ? V4L2_PIX_FMT_GREY : have_yuyv ? V4L2_PIX_FMT_YUYV : 0;
    if (!want) {
        char msg[200];
        snprintf(msg, sizeof msg, "offers no %s format (has:%s)", cfg->format ? "such" : "GREY or YUYV", offered[0] ? offered : " none");
        return vp_v4l2_fail(v, VP_EIO, err, errlen, "%s", msg);
    }
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
    v->step = want == V4L2_PIX_FMT_GREY ? 1 : 2;
    v->width = (int)fmt.fmt.pix.width;
    v->height = (int)fmt.fmt.pix.height;
    v->stride = fmt.fmt.pix.bytesperline ? (int)fmt.fmt.pix.bytesperline : v->width * v->step;
    if (cfg->exposure_us > 0) {
        struct v4l2_control ctl;
        ctl.id = V4L2_CID_EXPOSURE_AUTO;
        ctl.value = V4L2_EXPOSURE_MANUAL;
        if (vp_xioctl(v->fd, VIDIOC_S_CTRL, &ctl) == 0) {
            ctl.id = V4L2_CID_EXPOSURE_ABSOLUTE;
            ctl.value = cfg->exposure_us / 100;     /* units of 100 us */
            if (ctl.value < 1) ctl.value = 1;
        }
        if (vp_xioctl(v->fd, VIDIOC_S_CTRL, &ctl) != 0)
            snprintf(v->err, sizeof v->err, "camera %s: manual exposure not set: %s", v->dev, strerror(errno));
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
