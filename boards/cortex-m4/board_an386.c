/* Arm MPS2 with the AN386 FPGA image (Cortex-M4F, 25 MHz peripheral clock), as qemu-system-arm
 * -M mps2-an386 models it and as the board runs it: vector table and start-up (.data copied,
 * .bss cleared, FPU on), UART0 (CMSDK APB UART, 115200 baud, receive interrupt into a ring),
 * the CMSDK dual timer (timer 1: the step edges, periodic with a background reload so each
 * edge's interval is already in the hardware when it starts; timer 2: the free-running clock),
 * step/dir outputs on GPIO0 and the laser on GPIO0 and LED0 of the FPGA I/O, e-stop and limit
 * on the FPGA I/O push buttons. (mcu.h is given with -include.) */
#include <stdint.h>
#include <string.h>

#define REG(a) (*(volatile uint32_t *)(a))
#define UART0        0x40004000u
#define UART_DATA    (UART0 + 0x00u)
#define UART_STATE   (UART0 + 0x04u)   /* bit 0 TX full, bit 1 RX full */
#define UART_CTRL    (UART0 + 0x08u)   /* TX en, RX en, TX int, RX int */
#define UART_INT     (UART0 + 0x0Cu)   /* write 1 to clear */
#define UART_BAUDDIV (UART0 + 0x10u)
#define DT1          0x40002000u       /* dual timer, module 1 (+0x20: module 2) */
#define DT_LOAD(m)   ((m) + 0x00u)
#define DT_VALUE(m)  ((m) + 0x04u)
#define DT_CTRL(m)   ((m) + 0x08u)     /* bit 1 32-bit, 5 int enable, 6 periodic, 7 enable */
#define DT_INTCLR(m) ((m) + 0x0Cu)
#define DT_BGLOAD(m) ((m) + 0x18u)
#define DT2          (DT1 + 0x20u)
#define GPIO0_DATAOUT 0x40010004u
#define GPIO0_OUTEN   0x40010010u
#define FPGAIO_LED0   0x40028000u
#define FPGAIO_BUTTON 0x40028008u
#define NVIC_ISER0    0xE000E100u
#define NVIC_IPR(n)   (0xE000E400u + (n))
#define SCB_SHPR3     0xE000ED20u
#define SYST_CSR      0xE000E010u
#define SYST_RVR      0xE000E014u
#define SYST_CVR      0xE000E018u
#define IRQ_UART0_RX  0
#define IRQ_DUALTIMER 10

#define SYSCLK_HZ 25000000u
const char mcu_board_name[] = "mps2-an386";
/* 100 steps per unit, 10,000 steps/s, 1,000,000 steps/s^2, 12 us pulses (the 10 us floor of
 * qemu's timers without -icount and the 1.9 us a DRV8825 needs) */
const mcu_axes_config_t mcu_axes = { 100u, 10000u, 1000000u, 300u, SYSCLK_HZ };

static uint32_t gpio_out;

void mcu_hal_init(void)
{
    REG(UART_BAUDDIV) = SYSCLK_HZ / 115200u;
    REG(UART_CTRL) = 0x1u | 0x2u | 0x8u;
    /* the free-running clock: counts down from 2^32 - 1 */
    REG(DT_CTRL(DT2)) = 0x2u;
    REG(DT_LOAD(DT2)) = 0xFFFFFFFFu;
    REG(DT_CTRL(DT2)) = 0x2u | 0x80u;
    REG(DT_CTRL(DT1)) = 0x2u | 0x20u | 0x40u;
    REG(GPIO0_OUTEN) = 0x7Fu;
    REG(SYST_RVR) = SYSCLK_HZ / 1000u - 1u;   /* a 1 kHz tick: wakes the idle loop */
    REG(SYST_CVR) = 0;
    REG(SYST_CSR) = 0x7u;                     /* processor clock, interrupt, enable */
    REG(SCB_SHPR3) = 0x80u << 24;             /* the tick below the step edges */
    *(volatile uint8_t *)NVIC_IPR(IRQ_DUALTIMER) = 0x00u;   /* the step edges first */
    *(volatile uint8_t *)NVIC_IPR(IRQ_UART0_RX) = 0x40u;
    REG(NVIC_ISER0) = 1u << IRQ_UART0_RX | 1u << IRQ_DUALTIMER;
}

uint32_t mcu_hal_now(void)
{
    return 0xFFFFFFFFu - REG(DT_VALUE(DT2));
}

void mcu_hal_write(const uint8_t *p, size_t n)
{
    while (n--) {
        while (REG(UART_STATE) & 1u) {}
        REG(UART_DATA) = *p++;
    }
}

void mcu_hal_idle(void)
{
    /* the 1 kHz tick bounds the sleep when the awaited interrupt came just before the WFI */
    __asm__ volatile ("wfi");
}

void mcu_hal_motion_idle(void)
{
    /* awake: the edge interrupts are served at once (under qemu -icount, a sleeping core's
     * time follows the host's clock and the edges would be served late) */
}

void mcu_hal_step_start(uint32_t first, uint32_t second)
{
    REG(DT_CTRL(DT1)) = 0x2u | 0x20u | 0x40u;
    REG(DT_LOAD(DT1)) = first;
    REG(DT_BGLOAD(DT1)) = second - 1u;
    REG(DT_INTCLR(DT1)) = 1u;
    REG(DT_CTRL(DT1)) = 0x2u | 0x20u | 0x40u | 0x80u;
}

void mcu_hal_step_next(uint32_t ticks)
{
    /* a reloaded period lasts BGLOAD + 1 ticks (it counts down through 0) */
    REG(DT_BGLOAD(DT1)) = ticks - 1u;
}

void mcu_hal_step_stop(void)
{
    REG(DT_CTRL(DT1)) = 0x2u | 0x20u | 0x40u;
}

void mcu_hal_step_ack(void)
{
    REG(DT_INTCLR(DT1)) = 1u;
}

void mcu_hal_step_pins(uint32_t dir_bits, uint32_t step_bits)
{
    gpio_out = (gpio_out & 0x40u) | (dir_bits & 7u) << 3 | (step_bits & 7u);
    REG(GPIO0_DATAOUT) = gpio_out;
}

uint32_t mcu_hal_inputs(void)
{
    uint32_t b = REG(FPGAIO_BUTTON);
    return (b & 1u ? MCU_IN_ESTOP : 0u) | (b & 2u ? MCU_IN_LIMIT : 0u);
}

void mcu_hal_laser(int on)
{
    gpio_out = on ? gpio_out | 0x40u : gpio_out & ~0x40u;
    REG(GPIO0_DATAOUT) = gpio_out;
    REG(FPGAIO_LED0) = on ? 1u : 0u;
}

/* ---- interrupts and start-up ---- */
void vp_uart0_rx_handler(void);
void vp_dualtimer_handler(void);
void vp_reset_handler(void);
void vp_systick_handler(void);
extern uint32_t _estack;

void vp_uart0_rx_handler(void)
{
    /* cleared first: a byte arriving after the drain below raises the interrupt again */
    REG(UART_INT) = 2u;
    while (REG(UART_STATE) & 2u) {
        uint8_t c = (uint8_t)REG(UART_DATA);
        mcu_rx_put(c);
    }
}

void vp_dualtimer_handler(void)
{
    mcu_motion_edge();
}

void vp_systick_handler(void)
{
}

void vp_reset_handler(void)
{
    mcu_crt_init();
    mcu_main();
    vp_default_handler();
}

typedef void (*vp_vector_t)(void);
__attribute__((section(".isr_vector"), used))
static const vp_vector_t vector_table[16 + 32] = {
    (vp_vector_t)(uintptr_t)&_estack, vp_reset_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, 0, 0, 0, 0,
    vp_default_handler, vp_default_handler, 0, vp_default_handler, vp_systick_handler,
    /* IRQ 0: UART0 receive ... IRQ 10: the dual timer */
    vp_uart0_rx_handler, vp_default_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_dualtimer_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, vp_default_handler,
    vp_default_handler, vp_default_handler, vp_default_handler, vp_default_handler,
};
