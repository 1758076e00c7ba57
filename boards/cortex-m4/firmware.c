/* Cortex-M4 image: the voroprobe core and planner with a static arena, linked freestanding.
 * Proves the core and the planner need no OS, no heap and no stdio, and measures their flash
 * and RAM use. The main loop is a whole scan through the core's run loop (vp_run): a built-in
 * simulated probe (a ray cast against an analytic sphere, standing in for the rangefinder) is
 * the device, until DONE; the figures are parked where a debugger can read them (vp_m4_result).
 * Built with -DVP_M4_HOST the same loop runs on the build machine and prints them
 * (tests/t_cortex_m4.sh), so the arena is known to be large enough for the scan. */
#include <stdint.h>
#include <string.h>
#include "vp_planner.h"
#include "vp_run.h"

#ifndef VP_M4_ARENA_BYTES
#define VP_M4_ARENA_BYTES (448u * 1024u)   /* see link.ld: this scan needs 272 KB */
#endif
#ifndef VP_M4_EPS
#define VP_M4_EPS 0.35             /* on a unit sphere: about 80 vertices */
#endif
#define VP_M4_MAX_COMMANDS 200000u

static uint64_t arena[VP_M4_ARENA_BYTES / 8];
static vp_planner_t pl;

typedef struct vp_m4_result {
    int32_t status;                /* VP_OK when the planner said DONE */
    uint32_t commands, probes, hits, facets, vertices;
    uint32_t arena_peak;           /* bytes of the arena the planner used */
} vp_m4_result_t;
volatile vp_m4_result_t vp_m4_result;

/* The simulated probe: the unit sphere at the origin. First crossing of the ray o + t d with
 * 0 < t <= range (range 0: unlimited). */
static int vp_m4_sphere(const double o[3], const double d[3], double range, double *t)
{
    double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
    double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - 1.0;
    double disc = b * b - c, s, t0;
    if (disc <= 0.0) return 0;
    s = __builtin_sqrt(disc);
    t0 = -b - s;
    if (t0 <= 0.0) t0 = -b + s;    /* from inside: the way out */
    if (t0 <= 0.0 || (range > 0.0 && t0 > range)) return 0;
    *t = t0;
    return 1;
}

/* The device: a MOVE is where it is told; a PROBE casts the ray against the sphere. */
static int vp_m4_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    (void)ctx; (void)cmd; (void)collided;
    return VP_OK;
}

static int vp_m4_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    (void)ctx;
    res->dist = 0.0;
    res->hit = vp_m4_sphere(cmd->from, cmd->dir, cmd->range, &res->dist);
    return VP_OK;
}

int vp_m4_scan(void);
int vp_m4_scan(void)
{
    vp_planner_config_t cfg;
    vp_planner_stats_t st;
    vp_device_ops_t dev;
    vp_run_result_t run;
    int rc, k;
    memset(&cfg, 0, sizeof cfg);
    memset(&run, 0, sizeof run);
    cfg.omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) { cfg.omega_lo[k] = -1.5; cfg.omega_hi[k] = 1.5; }
    cfg.ninterior = 1;             /* interior[0] = the origin */
    cfg.eps = VP_M4_EPS;
    cfg.start[2] = 2.0;
    dev.ctx = 0;
    dev.move = vp_m4_move;
    dev.probe = vp_m4_probe;
    dev.touched = 0;
    dev.rays = 0;
    dev.move_path = 0;
    dev.sight = 0;
    rc = vp_planner_init(&pl, arena, sizeof arena, &cfg);
    if (rc == VP_OK) rc = vp_run(&pl, &dev, 0, VP_M4_MAX_COMMANDS, &run);
    vp_planner_get_stats(&pl, &st);
    vp_m4_result.status = rc;
    vp_m4_result.commands = (uint32_t)run.commands;
    vp_m4_result.probes = (uint32_t)st.probes;
    vp_m4_result.hits = (uint32_t)st.hits;
    vp_m4_result.facets = vp_planner_num_facets(&pl);
    vp_m4_result.vertices = vp_planner_dt(&pl)->ninserted;
    vp_m4_result.arena_peak = (uint32_t)st.arena_peak;
    return rc;
}

#ifdef VP_M4_HOST
#include <stdio.h>
int main(void)
{
    int rc = vp_m4_scan();
    printf("firmware loop on the host: status %d%s, %u commands, %u probes (%u hits), %u vertices, %u facets, "
           "arena peak %u of %u bytes\n", (int)vp_m4_result.status, rc == VP_OK ? " (DONE)" : "",
           (unsigned)vp_m4_result.commands, (unsigned)vp_m4_result.probes, (unsigned)vp_m4_result.hits,
           (unsigned)vp_m4_result.vertices, (unsigned)vp_m4_result.facets, (unsigned)vp_m4_result.arena_peak,
           (unsigned)sizeof arena);
    return rc == VP_OK && vp_m4_result.facets > 0 ? 0 : 1;
}
#else
extern uint32_t _sdata, _edata, _etext, _sbss, _ebss, _estack;
int main(void);
void vp_reset_handler(void);
void vp_default_handler(void);

void vp_default_handler(void)
{
    for (;;) {}
}

void vp_reset_handler(void)
{
    uint32_t *src = &_etext, *dst = &_sdata;
    while (dst < &_edata) *dst++ = *src++;
    for (dst = &_sbss; dst < &_ebss; dst++) *dst = 0;
    /* enable the FPU (CP10, CP11 full access) */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    main();
    vp_default_handler();
}

__attribute__((section(".isr_vector"), used))
static void (*const vector_table[16])(void) = {
    (void (*)(void))&_estack, vp_reset_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, 0, 0, 0, 0,
    vp_default_handler, vp_default_handler, 0, vp_default_handler, vp_default_handler,
};

int main(void)
{
    vp_m4_scan();
    return 0;
}
#endif
