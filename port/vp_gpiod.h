/* vp_gpiod — the Linux GPIO backend through libgpiod v1 (Debian 12: 1.6). Built for real when
 * VP_HAVE_GPIOD is defined (the Makefile sets it when pkg-config finds libgpiod); otherwise
 * vp_gpiod_open() answers VP_ENODEV.
 *
 * Pins are chip + line offset from the board file. Outputs on one chip with one polarity form
 * one bulk request, so a write is one ioctl per bulk touched; logical bits may share a pin
 * (a common enable line). Deadlines: vp_rtclock (clock_nanosleep TIMER_ABSTIME, then a short
 * spin), optional SCHED_FIFO. Inputs are read by value (one ioctl per input bulk). */
#ifndef VP_GPIOD_H
#define VP_GPIOD_H
#include <stddef.h>
#include "vp_io.h"
#include "vp_rtclock.h"

#define VP_GPIO_CHIP_LEN 32
enum { VP_PULL_NONE = 0, VP_PULL_UP, VP_PULL_DOWN };

typedef struct vp_gpio_pin {
    char chip[VP_GPIO_CHIP_LEN];  /* "gpiochip0", "/dev/gpiochip0", "0" or a chip label; "" = not wired */
    int offset;
    int active_low;
    int pull;                     /* VP_PULL_* (inputs) */
} vp_gpio_pin_t;

typedef struct vp_gpiod_config {
    vp_gpio_pin_t out[VP_IO_NOUT];  /* by output bit number */
    vp_gpio_pin_t in[VP_IO_NIN];    /* by input bit number */
    int rt_priority;                /* SCHED_FIFO priority, 0: normal scheduling */
    int64_t spin_ns;                /* busy wait before each deadline (0: 50 us) */
    const char *consumer;           /* shown by gpioinfo (NULL: "voroprobe") */
} vp_gpiod_config_t;

typedef struct vp_gpiod vp_gpiod_t;

/* VP_ENODEV (no such chip, or built without libgpiod), VP_EIO (line busy, request refused),
 * VP_EINVAL (bad offset, too many chips); err gets one line naming the pin. */
int     vp_gpiod_open(const vp_gpiod_config_t *cfg, vp_gpiod_t **out, char *err, size_t errlen);
vp_io_t vp_gpiod_io(vp_gpiod_t *g);
void    vp_gpiod_stats(const vp_gpiod_t *g, vp_rt_stats_t *st);
void    vp_gpiod_close(vp_gpiod_t *g);   /* outputs low, lines released */
/* The version of the libgpiod linked in, asked of the library ("1.6.3"); NULL when built without. */
const char *vp_gpiod_version(void);

#endif
