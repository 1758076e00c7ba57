/* vp_libcamera — the libcamera camera backend (C++ inside, C interface). Built only when
 * pkg-config finds libcamera (VP_HAVE_LIBCAMERA); Debian 12 ships 0.0.3. Takes the luma plane
 * of R8, YUV420, NV12/NV21 (step 1) or YUYV (step 2) in place; frames older than the
 * caller's moment are requeued. Manual exposure: AeEnable off (ExposureTimeMode and
 * AnalogueGainMode manual from libcamera 0.5), ExposureTime and AnalogueGain fixed in every
 * request and read back from each completed request's metadata: a frame whose metadata says
 * otherwise (the sensor's controls take a few frames to apply) is requeued, and 30 such frames
 * in a row fail the capture with the control named. */
#ifndef VP_LIBCAMERA_H
#define VP_LIBCAMERA_H
#include <stddef.h>
#include "vp_cam.h"

typedef struct vp_libcamera_config {
    const char *camera;      /* camera id, NULL or "" for the first one */
    int width, height;       /* 0: the pipeline's default */
    int buffers;             /* 0: 4 */
    int exposure_us;         /* > 0: auto exposure off, this exposure (us) */
    double gain;             /* > 0: this analogue gain (x; 0 with exposure_us: 1.0) */
} vp_libcamera_config_t;

#ifdef __cplusplus
extern "C" {
#endif
/* VP_ENODEV (no camera, unknown id), VP_EIO (busy, no usable format, start failed). */
int vp_libcamera_open(const vp_libcamera_config_t *cfg, vp_cam_t *cam, char *err, size_t errlen);
/* The version of the libcamera linked in, asked of the library ("v0.0.3"). */
const char *vp_libcamera_version(void);
#ifdef __cplusplus
}
#endif

#endif
