/* vp_backends — see vp_backends.h. */
#include <stdio.h>
#include <string.h>
#include "vp_backends.h"
#include "vp_gpiod.h"
#include "vp_libcamera.h"

void vp_backends_get(vp_backends_t *b)
{
    memset(b, 0, sizeof *b);
    b->gpiod_version = vp_gpiod_version();
    b->gpiod = b->gpiod_version != NULL;
    b->v4l2 = 1;
#ifdef VP_HAVE_LIBCAMERA
    b->libcamera = 1;
    b->libcamera_version = vp_libcamera_version();
#endif
}

int vp_backends_describe(char *buf, size_t len)
{
    vp_backends_t b;
    char g[64], c[64];
    vp_backends_get(&b);
    if (b.gpiod) snprintf(g, sizeof g, "yes (%s)", b.gpiod_version ? b.gpiod_version : "?");
    else snprintf(g, sizeof g, "no (built without libgpiod-dev)");
    if (b.libcamera) snprintf(c, sizeof c, "yes (%s)", b.libcamera_version ? b.libcamera_version : "?");
    else snprintf(c, sizeof c, "no (built without libcamera-dev)");
    return snprintf(buf, len, "GPIO: libgpiod %s; camera: V4L2 %s, libcamera %s", g, b.v4l2 ? "yes" : "no", c);
}
