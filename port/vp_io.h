/* vp_io — the GPIO boundary between the step generator and a backend (recording, libgpiod).
 *
 * Lines are logical bits; the backend maps them to pins and applies electrical polarity
 * (active-low enables, normally-closed switches). Outputs: STEP/DIR/EN per axis and the laser.
 * Inputs: a min and a max limit switch per axis, the e-stop and the head's contact switch (a
 * touch probe's stylus: closed when the probe point touches the object). 1 = active (asserted). */
#ifndef VP_IO_H
#define VP_IO_H
#include <stdint.h>

#define VP_IO_MAX_AXES 8
#define VP_IO_STEP(a)    (1u << (a))
#define VP_IO_DIR(a)     (1u << (8 + (a)))
#define VP_IO_EN(a)      (1u << (16 + (a)))
#define VP_IO_LASER      (1u << 24)
#define VP_IO_NOUT       25          /* output bit numbers are 0..24 */

#define VP_IO_LIM_MIN(a) (1u << (a))
#define VP_IO_LIM_MAX(a) (1u << (8 + (a)))
#define VP_IO_ESTOP      (1u << 16)
#define VP_IO_CONTACT    (1u << 17)
#define VP_IO_NIN        18

/* Filled by a backend; ctx is the backend's own state. All return VP_OK or a VP_E* code. */
typedef struct vp_io {
    void *ctx;
    int64_t (*now)(void *ctx);                           /* ns on the backend's clock */
    int (*wait_until)(void *ctx, int64_t t_ns);          /* returns at t_ns, never before */
    int (*write)(void *ctx, uint32_t mask, uint32_t values); /* set the lines in mask, now */
    int (*read)(void *ctx, uint32_t *inputs);            /* all inputs, now */
} vp_io_t;

#endif
