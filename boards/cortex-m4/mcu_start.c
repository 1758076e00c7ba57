/* mcu_start.c — what every Cortex-M4 image of the scanner shares, whatever its board: the
 * start-up before mcu_main (.data copied from flash, .bss cleared, the FPU enabled), the
 * default interrupt handler, and the ring the UART's receive interrupt fills and the link
 * reads (mcu_hal_getc). Not in the build machine's program (board_hostpipe.c reads a pipe). */
#include <stdint.h>

#define REG(a) (*(volatile uint32_t *)(a))
#define SCB_CPACR 0xE000ED88u   /* coprocessor access (ARMv7-M) */

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss;

static volatile uint8_t rx_ring[1024];
static volatile uint32_t rx_head, rx_tail;

void mcu_crt_init(void)
{
    uint32_t *src = &_sidata, *dst = &_sdata;
    while (dst < &_edata) *dst++ = *src++;
    for (dst = &_sbss; dst < &_ebss; dst++) *dst = 0;
    REG(SCB_CPACR) |= 0xFu << 20;      /* the FPU: CP10, CP11 full access */
    __asm__ volatile ("dsb\n\tisb");
}

void vp_default_handler(void)
{
    for (;;) {}
}

void mcu_rx_put(uint8_t c)
{
    if (rx_head - rx_tail < sizeof rx_ring) { rx_ring[rx_head % sizeof rx_ring] = c; rx_head++; }
}

int mcu_hal_getc(void)
{
    int c;
    if (rx_tail == rx_head) return -1;
    c = rx_ring[rx_tail % sizeof rx_ring];
    rx_tail++;
    return c;
}
