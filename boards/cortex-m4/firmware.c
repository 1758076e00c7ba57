/* Cortex-M4 image: the voroprobe core with a static arena, linked freestanding.
 * Proves the core needs no OS, no heap and no stdio, and measures its flash and RAM use.
 * The main loop triangulates points from a local generator, the way the device triangulates
 * its probe hits, and parks the result where a debugger can read it. */
#include <stdint.h>
#include <string.h>
#include "vp_dt.h"

#ifndef VP_M4_ARENA_BYTES
#define VP_M4_ARENA_BYTES (96u * 1024u)
#endif

static uint64_t arena[VP_M4_ARENA_BYTES / 8];
static vp_dt_t dt;
volatile uint32_t vp_m4_result;

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
    uint32_t s = 12345u, i;
    int st = vp_dt_init(&dt, arena, sizeof arena, 4);
    for (i = 0; st == VP_OK && i < 1000u; i++) {
        double p[3];
        int k;
        for (k = 0; k < 3; k++) {
            s = s * 1664525u + 1013904223u;
            p[k] = (double)(s >> 8) * (1.0 / 16777216.0);
        }
        st = vp_dt_insert(&dt, p, VP_DT_NONE, 0);
    }
    vp_m4_result = (uint32_t)vp_dt_check(&dt) ^ vp_dt_num_finite_tets(&dt);
    return 0;
}
