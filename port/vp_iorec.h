/* vp_iorec — the recording GPIO backend: a simulated clock (wait_until jumps, nothing sleeps),
 * every output edge captured with its timestamp, and a small machine behind the pins so inputs
 * answer like hardware: each axis has a motor (counts STEP rising edges while enabled, in the
 * direction of its DIR line), a carriage coupled to it with mechanical slack (backlash), limit
 * switches that close when the carriage reaches them, a scripted e-stop, and the head's contact
 * switch as the caller's function of the carriages (a wall in a test, the object in a dry run).
 * Used by the tests and by dry runs (cap 0: count and simulate, keep no edges).
 *
 * A latency model (off unless asked for): each write and read costs write_ns / read_ns of the
 * clock (an edge is stamped when its write completes), and with latency = VP_IOREC_LAT_LINUX
 * every wait returns late by a draw from a built-in histogram of a stock (non-PREEMPT_RT) Linux
 * kernel: half under 2 us, a tail of 0.05% beyond 1 ms up to 8 ms. The draws come from a seeded
 * generator: the same seed gives the same run. Glitches: the first glitch_reads reads at or
 * after glitch_at see glitch_bits active (a sample-long spike on a switch line). */
#ifndef VP_IOREC_H
#define VP_IOREC_H
#include <stddef.h>
#include <stdint.h>
#include "vp_io.h"

typedef struct vp_iorec_edge {
    int64_t t_ns;
    uint8_t line;            /* output bit number (VP_IO_* bit index) */
    uint8_t value;
    int32_t late_ns;         /* rising STEP edges: how long after the last wait's deadline the
                                write began (the step's lateness); 0 otherwise */
} vp_iorec_edge_t;

enum { VP_IOREC_LAT_NONE = 0, VP_IOREC_LAT_LINUX = 1 };

typedef struct vp_iorec_config {
    vp_iorec_edge_t *buf;    /* caller's edge buffer; NULL/0: keep none */
    size_t cap;
    int naxes;
    int invert_dir[VP_IO_MAX_AXES];   /* wiring: DIR high turns the motor negative */
    int32_t start[VP_IO_MAX_AXES];    /* carriage position at power-on (steps) */
    int has_min[VP_IO_MAX_AXES], has_max[VP_IO_MAX_AXES];
    int32_t min_sw[VP_IO_MAX_AXES];   /* min switch closed while carriage <= min_sw */
    int32_t max_sw[VP_IO_MAX_AXES];   /* max switch closed while carriage >= max_sw */
    int32_t slack[VP_IO_MAX_AXES];    /* mechanical backlash in steps */
    int64_t estop_at, estop_until;    /* e-stop pressed for t in [at, until); at < 0: never */
    uint32_t stuck_inputs;            /* inputs forced active (broken switch tests) */
    int64_t stall_at, stall_ns;       /* the first wait past stall_at returns stall_ns late (an OS stall) */
    uint32_t write_ns, read_ns;       /* cost of one write / read on the clock */
    int latency;                      /* VP_IOREC_LAT_*: late wake-ups */
    uint64_t seed;                    /* of the latency draws */
    uint32_t glitch_bits;             /* inputs forced active for glitch_reads reads from glitch_at */
    int64_t glitch_at;
    uint32_t glitch_reads;
    /* the contact input (VP_IO_CONTACT): 1 while the carriages (steps) put the probe on the
     * object; NULL: never closed */
    int (*contact)(void *ctx, const int32_t *carriage);
    void *contact_ctx;
} vp_iorec_config_t;

typedef struct vp_iorec {
    vp_iorec_config_t cfg;
    int64_t now;
    uint32_t out;
    size_t n;                          /* edges stored */
    uint64_t edges, dropped;           /* all edges seen; edges not stored (buffer full) */
    uint64_t late_writes;              /* waits for a time already past */
    uint64_t steps_disabled;           /* pulses while the driver was disabled (lost) */
    int32_t motor[VP_IO_MAX_AXES], carriage[VP_IO_MAX_AXES];
    uint64_t pulses[VP_IO_MAX_AXES];
    uint64_t rng;                      /* latency model state */
    int64_t wait_t;                    /* deadline of the last wait */
    uint64_t waits, late_waits;        /* waits; those the model made late */
    int64_t late_max_ns;               /* worst drawn lateness */
    uint64_t reads, glitched;          /* reads; reads the glitch touched */
} vp_iorec_t;

void     vp_iorec_init(vp_iorec_t *r, const vp_iorec_config_t *cfg);
vp_io_t  vp_iorec_io(vp_iorec_t *r);
uint32_t vp_iorec_inputs(const vp_iorec_t *r);

#endif
