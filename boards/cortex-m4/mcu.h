/* The microcontroller scanner: the planner runs on the MCU; the host plays the object and the
 * rangefinder over a framed, CRC-checked UART link (doc/mcu-protocol.md). Shared by the
 * board-independent files (mcu_link.c, mcu_motion.c, mcu_scan.c) and the boards that run them
 * (board_an386.c: the MPS2 AN386 under qemu or on the FPGA board; board_hostpipe.c: the same
 * sources on the build machine over a pipe). Given to the compiler with -include, since a
 * boards/ file includes only core headers (tests/t_layers.sh). */
#ifndef VP_MCU_H
#define VP_MCU_H
#include <stddef.h>
#include <stdint.h>
#include "vp_planner.h"

/* ---- the link (doc/mcu-protocol.md) ---- */
#define MCU_PROTO_VERSION   1u
#define MCU_MAX_PAYLOAD     2112u   /* a log header (at most 2048 bytes) fits */
#define MCU_FRAME_OVERHEAD  10u     /* version, type, sequence (2), length (2), CRC-32 (4) */

enum mcu_frame_type {
    MCU_HELLO = 0x01, MCU_MOVE = 0x02, MCU_PROBE = 0x03, MCU_LOG = 0x04, MCU_DONE = 0x06,
    MCU_START = 0x81, MCU_ACK = 0x82, MCU_RESULT = 0x83, MCU_STOP = 0x84, MCU_NAK = 0x85
};

typedef struct mcu_link_stats {
    uint32_t frames_sent, frames_received;
    uint32_t crc_errors;     /* frames from the host that failed the CRC, length or version */
    uint32_t naks;           /* frames the host reported damaged (sent again) */
    uint32_t timeouts;       /* requests sent again because no reply came in time */
} mcu_link_stats_t;
extern mcu_link_stats_t mcu_link_stats;

/* Sends a request and waits for its reply (same sequence number), sending it again after a
 * NAK, a damaged reply or MCU_REPLY_TIMEOUT_MS without one. tries: sends at most (0: until a
 * reply). Returns the reply's type (payload in reply[], *reply_len) or VP_ETIMEOUT. */
#define MCU_REPLY_TIMEOUT_MS 500u
int mcu_link_request(uint8_t type, const uint8_t *payload, uint16_t len, uint32_t tries,
                     uint8_t *reply, uint16_t *reply_len);

/* little-endian fields */
void mcu_put32(uint8_t *p, uint32_t v);
void mcu_putf64(uint8_t *p, double v);
uint32_t mcu_get32(const uint8_t *p);
double mcu_getf64(const uint8_t *p);

/* ---- motion: step edges from a hardware timer, a trapezoid profile per move ---- */
typedef struct mcu_axes_config {
    uint32_t steps_per_unit;   /* the same on X, Y, Z */
    uint32_t max_rate;         /* steps/s of the axis with the most steps */
    uint32_t accel;            /* steps/s^2 */
    uint32_t pulse_ticks;      /* step pulse width, timer ticks */
    uint32_t tick_hz;          /* the step timer's clock */
} mcu_axes_config_t;
extern const mcu_axes_config_t mcu_axes;

typedef struct mcu_move_report {
    uint32_t edges[3];         /* step edges produced per axis (2 per step) */
    uint32_t steps;            /* steps of the axis with the most */
    uint32_t ticks_programmed; /* the timer's schedule: first edge's start to last edge */
    uint32_t ticks_measured;   /* the same span on the free-running clock, read in the ISR */
    uint32_t late_edges;       /* edges whose interrupt came after the next edge was due */
    uint32_t inputs;           /* endstops/e-stop seen (debounced), MCU_IN_* */
} mcu_move_report_t;

#define MCU_IN_ESTOP  0x1u
#define MCU_IN_LIMIT  0x2u
#define MCU_DEBOUNCE  3u       /* samples an input must hold before it counts */

/* Runs the move from -> to (units) on the step timer; returns when its last edge is out.
 * VP_EABORT when the e-stop or a limit stopped it (report->inputs says which). */
int mcu_motion_move(const double from[3], const double to[3], mcu_move_report_t *report);
/* The step timer's interrupt: one edge. */
void mcu_motion_edge(void);

/* ---- the images' shared start-up and receive ring (mcu_start.c) ---- */
void mcu_crt_init(void);        /* .data copied, .bss cleared, the FPU enabled */
void mcu_rx_put(uint8_t c);     /* a received byte, from the UART's interrupt (dropped when full) */
void vp_default_handler(void);

/* ---- the session: HELLO, START, the scan, DONE (mcu_scan.c) ---- */
void mcu_main(void);
extern const char mcu_board_name[];

/* ---- what a board provides ---- */
void mcu_hal_init(void);
uint32_t mcu_hal_now(void);                 /* free-running clock, mcu_axes.tick_hz */
int  mcu_hal_getc(void);                    /* a received byte, or -1 */
void mcu_hal_write(const uint8_t *p, size_t n);
void mcu_hal_idle(void);                    /* wait for an interrupt (or the 1 kHz tick) */
void mcu_hal_motion_idle(void);             /* while the step timer runs */
/* the step timer: the first edge after `first` ticks, the next `second` after it; then each
 * mcu_motion_edge() call sets the interval after the next one with mcu_hal_step_next */
void mcu_hal_step_start(uint32_t first, uint32_t second);
void mcu_hal_step_next(uint32_t ticks);
void mcu_hal_step_stop(void);
void mcu_hal_step_ack(void);                /* clears the timer's interrupt */
void mcu_hal_step_pins(uint32_t dir_bits, uint32_t step_bits); /* bit k: axis k */
uint32_t mcu_hal_inputs(void);              /* raw MCU_IN_* levels */
void mcu_hal_laser(int on);

#endif
