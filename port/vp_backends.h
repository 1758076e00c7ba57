/* vp_backends — which hardware backends this build holds (libgpiod step/dir GPIO, V4L2 and
 * libcamera cameras), with the versions of the libraries linked in, asked of the libraries
 * themselves. `voroprobe --version` and `scan --help` print it. */
#ifndef VP_BACKENDS_H
#define VP_BACKENDS_H
#include <stddef.h>

typedef struct vp_backends {
    int gpiod;                       /* GPIO through libgpiod (VP_HAVE_GPIOD) */
    const char *gpiod_version;       /* "1.6.3"; NULL when not built */
    int v4l2;                        /* camera through V4L2 (always on Linux) */
    int libcamera;                   /* camera through libcamera (VP_HAVE_LIBCAMERA) */
    const char *libcamera_version;   /* "v0.0.3"; NULL when not built */
} vp_backends_t;

void vp_backends_get(vp_backends_t *b);

/* One line, e.g. "GPIO: libgpiod yes (1.6.3); camera: V4L2 yes, libcamera yes (v0.0.3)";
 * a backend left out says "no (built without libgpiod-dev)". Returns what snprintf returns. */
int vp_backends_describe(char *buf, size_t len);

#endif
