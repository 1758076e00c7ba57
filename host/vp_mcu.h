/* vp_mcu — the host's end of the microcontroller scanner's link (doc/mcu-protocol.md): the
 * planner runs on the MCU (boards/cortex-m4/mcu_*.c); the host answers its requests, playing
 * the object and the rangefinder (a device given as callbacks: host-sim, or anything else),
 * checks every MOVE's step edges against the ideal trapezoid, and writes the session log the
 * MCU streams. The link is qemu-system-arm running the image, a program on a pipe, a serial
 * device (a real board) or a unix socket. */
#ifndef VP_MCU_H_HOST
#define VP_MCU_H_HOST
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#define VP_MCU_PROTO_VERSION 1u
#define VP_MCU_MAX_PAYLOAD   2112u

typedef struct vp_mcu_link {
    int fd;                    /* the link (both directions) */
    pid_t child;               /* qemu or the --exec program (0: none) */
    unsigned char rx[2 * VP_MCU_MAX_PAYLOAD + 64];
    size_t rx_n;
    int rx_overflow;
    unsigned char inbuf[4096];
    size_t in_n, in_i;
} vp_mcu_link_t;

/* Opens the link. VP_OK, or an error with a message in err. qemu: the qemu-system-arm
 * program (NULL: from PATH); machine: its -M (NULL: mps2-an386; netduinoplus2 for the
 * STM32F405 image), whose first UART is the link; icount >= 0 gives -icount shift=icount. */
int  vp_mcu_open_qemu(vp_mcu_link_t *l, const char *qemu, const char *machine, const char *image, int icount,
                      char *err, size_t errlen);
int  vp_mcu_open_exec(vp_mcu_link_t *l, const char *program, char *err, size_t errlen);
int  vp_mcu_open_serial(vp_mcu_link_t *l, const char *device, long baud, char *err, size_t errlen);
int  vp_mcu_open_socket(vp_mcu_link_t *l, const char *path, char *err, size_t errlen);
void vp_mcu_close(vp_mcu_link_t *l);

/* What the MCU says of itself (HELLO). */
typedef struct vp_mcu_hello {
    uint32_t version, arena_bytes, tick_hz, steps_per_unit, max_rate, accel, pulse_ticks;
    char board[36];
} vp_mcu_hello_t;

/* The object and the rangefinder. move: the device moves; *collided. probe: from the device's
 * position; hit is 0, 1 or VP_PROBE_TOO_CLOSE, raw the sensor's reading (NaN: none). */
typedef struct vp_mcu_device {
    void *ctx;
    int (*move)(void *ctx, const double from[3], const double to[3], int *collided);
    int (*probe)(void *ctx, const double from[3], const double dir[3], double range, int *hit,
                 double *dist, double *raw);
} vp_mcu_device_t;

typedef struct vp_mcu_options {
    const unsigned char *header;   /* the START payload: a session log header (vp_logfmt) */
    size_t header_len;
    const char *log_path;          /* where the streamed log goes */
    unsigned corrupt;              /* damage this many frames (one bit each), in and out by turns */
    double silent_seconds;         /* no valid frame for this long: the board is silent */
    FILE *progress;                /* progress lines (NULL: quiet) */
    volatile int *stop_flag;       /* set: answer the next request with STOP */
} vp_mcu_options_t;

typedef struct vp_mcu_result {
    vp_mcu_hello_t hello;
    int done;                      /* DONE received */
    int32_t status;                /* the MCU's scan status (VP_OK: the planner said DONE) */
    uint32_t commands, probes, vertices, facets, arena_peak;
    uint32_t mcu_crc_errors, mcu_naks, mcu_timeouts;   /* the MCU's counters */
    unsigned long frames_in, frames_out, crc_errors;    /* the host's: damaged frames received */
    unsigned long repeats;         /* requests received again (a reply lost or damaged) */
    unsigned long injected_in, injected_out;            /* frames damaged on purpose */
    unsigned long moves, probes_answered, collisions, log_records;
    uint64_t log_bytes;
    /* the step edges against the ideal trapezoid */
    unsigned long moves_checked, edge_mismatches, schedule_mismatches, late_edges, edges;
    double max_schedule_dev_ticks; /* programmed schedule against the ideal duration */
    double max_latency_us, mean_latency_us; /* measured last edge after the programmed one */
    double seconds;
} vp_mcu_result_t;

/* The ideal trapezoid (or triangle) duration of n steps, seconds: the last step's rise. */
double vp_mcu_trapezoid_seconds(uint32_t n, double max_rate, double accel);

/* Serves one session: HELLO -> START ... DONE. VP_OK when DONE came (res->status says how the
 * scan ended); VP_ETIMEOUT (the board silent), VP_EIO (link closed, log not writable),
 * VP_ECORRUPT (a log record the core's reader refuses, or a protocol version mismatch); err
 * says which. */
int vp_mcu_serve(vp_mcu_link_t *l, const vp_mcu_device_t *dev, const vp_mcu_options_t *o,
                 vp_mcu_result_t *res, char *err, size_t errlen);

#endif
