// vp_libcamera — see vp_libcamera.h. Completed requests arrive on libcamera's thread and are
// handed to the caller's thread through a queue; a frame's buffer stays mapped for its life.
#include <sys/mman.h>
#include <time.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <libcamera/libcamera.h>
#include <libcamera/version.h>

// libcamera 0.5 replaced AeEnable by ExposureTimeMode / AnalogueGainMode
#if LIBCAMERA_VERSION_MAJOR > 0 || LIBCAMERA_VERSION_MINOR >= 5
#define VP_LIBCAMERA_EXPOSURE_MODE 1
#endif

#include "vp_libcamera.h"
#include "vp_status.h"

using namespace libcamera;

namespace {

struct Mapped {
    void *base = MAP_FAILED;
    size_t len = 0;
    const uint8_t *luma = nullptr;
};

struct Libcam {
    std::unique_ptr<CameraManager> cm;
    std::shared_ptr<Camera> cam;
    std::unique_ptr<CameraConfiguration> config;
    std::unique_ptr<FrameBufferAllocator> alloc;
    std::vector<std::unique_ptr<Request>> requests;
    std::vector<Mapped> maps;
    Stream *stream = nullptr;
    int width = 0, height = 0, stride = 0, step = 1;
    bool acquired = false, started = false;
    std::mutex mu;
    std::condition_variable cv;
    std::deque<Request *> done;
    std::string err;
    int64_t last_seq = -1, last_ts = -1;   // newest frame taken from the queue
    int exposure_us = 0;                   // > 0: manual, with gain
    float gain = 0;
    int unsettled = 0;                     // frames in a row whose metadata differ from the controls

    // the manual exposure into a request's controls
    void fix(ControlList &c) const
    {
        if (exposure_us <= 0) return;
#ifdef VP_LIBCAMERA_EXPOSURE_MODE
        c.set(controls::ExposureTimeMode, controls::ExposureTimeModeManual);
        c.set(controls::AnalogueGainMode, controls::AnalogueGainModeManual);
#else
        c.set(controls::AeEnable, false);
#endif
        c.set(controls::ExposureTime, (int32_t)exposure_us);
        c.set(controls::AnalogueGain, gain);
    }

    // "" when the request's metadata show the exposure and gain asked for, else what differs
    std::string check(Request *r) const
    {
        if (exposure_us <= 0) return "";
        const ControlList &md = r->metadata();
        auto e = md.get(controls::ExposureTime);
        auto g = md.get(controls::AnalogueGain);
        char why[200];
        if (vp_cam_exposure_taken(exposure_us, gain, e ? 1 : 0, e ? (long)*e : 0, g ? 1 : 0, g ? (double)*g : 0.0, why,
                                  sizeof why))
            return "";
        return why;
    }

    void completed(Request *r)
    {
        if (r->status() == Request::RequestCancelled) return;
        std::lock_guard<std::mutex> lk(mu);
        done.push_back(r);
        cv.notify_one();
    }

    ~Libcam()
    {
        if (started) cam->stop();
        if (cam) cam->requestCompleted.disconnect(this, &Libcam::completed);
        requests.clear();
        for (auto &m : maps) if (m.base != MAP_FAILED) munmap(m.base, m.len);
        alloc.reset();
        if (acquired) cam->release();
        cam.reset();
        if (cm) cm->stop();
    }
};

int capture(void *ctx, int64_t not_before, int timeout_ms, vp_frame_t *f)
{
    Libcam *lc = static_cast<Libcam *>(ctx);
    auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
        Request *r;
        {
            std::unique_lock<std::mutex> lk(lc->mu);
            if (!lc->cv.wait_until(lk, until, [lc] { return !lc->done.empty(); })) {
                lc->err = "libcamera: no frame within " + std::to_string(timeout_ms) + " ms";
                return VP_ETIMEOUT;
            }
            r = lc->done.front();
            lc->done.pop_front();
        }
        FrameBuffer *b = r->buffers().begin()->second;
        const FrameMetadata &md = b->metadata();
        int64_t ts = (int64_t)md.timestamp, seq = (int64_t)md.sequence;
        // a frame older than one already seen cannot be placed against the laser: refused
        if (lc->last_seq >= 0 && (seq <= lc->last_seq || ts < lc->last_ts)) {
            lc->err = "libcamera: frame " + std::to_string(seq) + " is not after frame " + std::to_string(lc->last_seq) +
                      " (sequence number or time stamp went back): refused";
            r->reuse(Request::ReuseBuffers);
            lc->cam->queueRequest(r);
            return VP_EIO;
        }
        lc->last_seq = seq;
        lc->last_ts = ts;
        bool stale = ts < not_before || seq < f->seq;
        std::string off = md.status == FrameMetadata::FrameSuccess ? lc->check(r) : "";
        if (!off.empty() && ++lc->unsettled >= 30) {
            lc->err = "libcamera: the camera did not take the manual exposure: " + off;
            r->reuse(Request::ReuseBuffers);
            lc->fix(r->controls());
            lc->cam->queueRequest(r);
            return VP_EIO;
        }
        if (md.status != FrameMetadata::FrameSuccess || stale || !off.empty()) {
            r->reuse(Request::ReuseBuffers);
            lc->fix(r->controls());
            lc->cam->queueRequest(r);
            continue;
        }
        lc->unsettled = 0;
        size_t idx = (size_t)r->cookie();
        f->data = lc->maps[idx].luma;
        f->width = lc->width;
        f->height = lc->height;
        f->stride = lc->stride;
        f->step = lc->step;
        f->t_ns = ts;
        f->index = (int)idx;
        f->seq = seq;
        return VP_OK;
    }
}

// Drains the completed requests (back to the camera) and gives the next sequence number.
int mark(void *ctx, int64_t *next_seq)
{
    Libcam *lc = static_cast<Libcam *>(ctx);
    for (;;) {
        Request *r;
        {
            std::lock_guard<std::mutex> lk(lc->mu);
            if (lc->done.empty()) break;
            r = lc->done.front();
            lc->done.pop_front();
        }
        const FrameMetadata &md = r->buffers().begin()->second->metadata();
        int64_t ts = (int64_t)md.timestamp, seq = (int64_t)md.sequence;
        bool back = lc->last_seq >= 0 && (seq <= lc->last_seq || ts < lc->last_ts);
        if (!back) { lc->last_seq = seq; lc->last_ts = ts; }
        r->reuse(Request::ReuseBuffers);
        lc->fix(r->controls());
        lc->cam->queueRequest(r);
        if (back) {
            lc->err = "libcamera: frame " + std::to_string(seq) + " is not after frame " + std::to_string(lc->last_seq) + ": refused";
            return VP_EIO;
        }
    }
    *next_seq = lc->last_seq + 1;
    return VP_OK;
}

void release(void *ctx, vp_frame_t *f)
{
    Libcam *lc = static_cast<Libcam *>(ctx);
    Request *r = lc->requests[(size_t)f->index].get();
    r->reuse(Request::ReuseBuffers);
    lc->fix(r->controls());
    if (lc->cam->queueRequest(r) < 0) lc->err = "libcamera: requeue failed";
    f->data = nullptr;
}

void close_cam(void *ctx) { delete static_cast<Libcam *>(ctx); }
const char *error(void *ctx) { return static_cast<Libcam *>(ctx)->err.c_str(); }

int fail(Libcam *lc, int rc, char *err, size_t errlen, const std::string &msg)
{
    std::snprintf(err, errlen, "libcamera: %s", msg.c_str());
    delete lc;
    return rc;
}

bool luma_format(const PixelFormat &p, int *step)
{
    if (p == formats::R8 || p == formats::YUV420 || p == formats::NV12 || p == formats::NV21) { *step = 1; return true; }
    if (p == formats::YUYV) { *step = 2; return true; }
    return false;
}

} // namespace

extern "C" int vp_libcamera_open(const vp_libcamera_config_t *cfg, vp_cam_t *out, char *err, size_t errlen)
{
    if (!cfg || !out) return VP_EINVAL;
    Libcam *lc = new (std::nothrow) Libcam;
    if (!lc) return VP_ENOMEM;
    lc->cm = std::make_unique<CameraManager>();
    if (lc->cm->start() < 0) return fail(lc, VP_EIO, err, errlen, "camera manager did not start");
    auto cams = lc->cm->cameras();
    if (cams.empty()) return fail(lc, VP_ENODEV, err, errlen, "no camera found (is it connected and enabled?)");
    if (cfg->camera && *cfg->camera) {
        lc->cam = lc->cm->get(cfg->camera);
        if (!lc->cam) {
            std::string ids;
            for (auto &c : cams) ids += " " + c->id();
            return fail(lc, VP_ENODEV, err, errlen, std::string("no camera '") + cfg->camera + "' (have:" + ids + ")");
        }
    } else lc->cam = cams[0];
    if (lc->cam->acquire() < 0) return fail(lc, VP_EIO, err, errlen, "camera " + lc->cam->id() + " is busy (another program uses it)");
    lc->acquired = true;
    lc->config = lc->cam->generateConfiguration({ StreamRole::Viewfinder });
    if (!lc->config || lc->config->size() < 1) return fail(lc, VP_EIO, err, errlen, "no stream configuration");
    StreamConfiguration &sc = lc->config->at(0);
    const PixelFormat want[] = { formats::R8, formats::YUV420, formats::NV12, formats::NV21, formats::YUYV };
    bool ok = false;
    for (const PixelFormat &p : want) {
        sc.pixelFormat = p;
        if (cfg->width > 0 && cfg->height > 0) sc.size = Size((unsigned)cfg->width, (unsigned)cfg->height);
        sc.bufferCount = (unsigned)(cfg->buffers > 0 ? cfg->buffers : 4);
        if (lc->config->validate() != CameraConfiguration::Invalid && luma_format(sc.pixelFormat, &lc->step)) { ok = true; break; }
    }
    if (!ok) return fail(lc, VP_EIO, err, errlen, "no R8/YUV420/NV12/YUYV stream (offered " + sc.toString() + ")");
    if (lc->cam->configure(lc->config.get()) < 0) return fail(lc, VP_EIO, err, errlen, "configure failed");
    lc->stream = sc.stream();
    lc->width = (int)sc.size.width;
    lc->height = (int)sc.size.height;
    lc->stride = (int)sc.stride;
    lc->alloc = std::make_unique<FrameBufferAllocator>(lc->cam);
    if (lc->alloc->allocate(lc->stream) < 0) return fail(lc, VP_EIO, err, errlen, "buffer allocation failed");
    const auto &bufs = lc->alloc->buffers(lc->stream);
    for (size_t i = 0; i < bufs.size(); i++) {
        const FrameBuffer::Plane &pl = bufs[i]->planes()[0];
        Mapped m;
        m.len = (size_t)pl.offset + pl.length;
        m.base = mmap(nullptr, m.len, PROT_READ, MAP_SHARED, pl.fd.get(), 0);
        if (m.base == MAP_FAILED) return fail(lc, VP_EIO, err, errlen, "mmap of a frame buffer failed");
        m.luma = static_cast<const uint8_t *>(m.base) + pl.offset;
        lc->maps.push_back(m);
        std::unique_ptr<Request> r = lc->cam->createRequest(i);
        if (!r || r->addBuffer(lc->stream, bufs[i].get()) < 0) return fail(lc, VP_EIO, err, errlen, "request setup failed");
        lc->requests.push_back(std::move(r));
    }
    lc->cam->requestCompleted.connect(lc, &Libcam::completed);
    if (cfg->exposure_us < 0 || !(cfg->gain >= 0)) return fail(lc, VP_EINVAL, err, errlen, "bad exposure or gain");
    lc->exposure_us = cfg->exposure_us;
    lc->gain = cfg->gain > 0 ? (float)cfg->gain : 1.0f;
    if (cfg->gain > 0 && cfg->exposure_us <= 0) return fail(lc, VP_EINVAL, err, errlen, "a fixed gain needs exposure_us too");
    if (lc->exposure_us > 0) {
        // the camera must offer the controls at all
        const ControlInfoMap &ci = lc->cam->controls();
#ifdef VP_LIBCAMERA_EXPOSURE_MODE
        if (!ci.count(&controls::ExposureTimeMode)) return fail(lc, VP_EIO, err, errlen, "the camera has no ExposureTimeMode control");
#else
        if (!ci.count(&controls::AeEnable)) return fail(lc, VP_EIO, err, errlen, "the camera has no AeEnable control");
#endif
        if (!ci.count(&controls::ExposureTime)) return fail(lc, VP_EIO, err, errlen, "the camera has no ExposureTime control");
        if (!ci.count(&controls::AnalogueGain)) return fail(lc, VP_EIO, err, errlen, "the camera has no AnalogueGain control");
    }
    ControlList ctl;
    lc->fix(ctl);
    if (lc->cam->start(&ctl) < 0) return fail(lc, VP_EIO, err, errlen, "start failed");
    lc->started = true;
    for (auto &r : lc->requests) {
        lc->fix(r->controls());
        if (lc->cam->queueRequest(r.get()) < 0) return fail(lc, VP_EIO, err, errlen, "queueing a request failed");
    }
    out->ctx = lc;
    out->capture = capture;
    out->release = release;
    out->close = close_cam;
    out->error = error;
    out->mark = mark;
    out->name = "libcamera";
    return VP_OK;
}

extern "C" const char *vp_libcamera_version(void)
{
    return CameraManager::version().c_str();
}
