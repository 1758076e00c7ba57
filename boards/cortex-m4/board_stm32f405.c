/* STM32F405 (Cortex-M4F, 1 MiB flash, 128 KiB SRAM; the Netduino Plus 2, qemu-system-arm
 * -M netduinoplus2): vector table and start-up (.data copied, .bss cleared, FPU on), the PLL at
 * 168 MHz from the 16 MHz HSI (APB1 42 MHz, APB2 84 MHz), USART1 (PA9/PA10, 115200 baud, receive
 * interrupt into a ring), TIM2 for the step edges (21 MHz: auto-reload preloaded, ARPE, so the
 * interval after the next is already in the hardware when the next starts and a late interrupt
 * moves no edge), TIM5 as the free-running clock (32 bits, 21 MHz), SysTick as a 1 kHz tick
 * that wakes the idle loop, step X/Y/Z on PC0-PC2, direction on PC3-PC5, the laser on PC6,
 * e-stop on PA0 and limit on PA1 (active high, pulled down).
 *
 * Under qemu 7.2's netduinoplus2 the RCC and the GPIO ports are unimplemented devices (writes
 * ignored, reads 0): the pins are not observable there, and the RCC reads as zero, which is how
 * this file tells the emulator from the part (a real RCC_CR has HSIRDY set after reset). qemu's
 * timers (hw/timer/stm32f2xx_timer.c) count 1 GHz ticks whatever the prescaler, have no preload,
 * restart the period at every ARR write, and every PSC, CNT or EGR write adds an offset to all
 * later periods; so there none of those is written: TIM5's count is the emulated time in ns
 * (extended past 32 bits at each reading, SysTick's tick reads it every ms) scaled to 21 MHz,
 * and the edges are scheduled on that clock, each ARR written at an interrupt as the time from
 * now to the next edge's due time, so a late interrupt still moves no edge. (SysTick's count is
 * no clock there: qemu shows it reloaded before the wrap's interrupt is pending.) (mcu.h is
 * given with -include.) */
#include <stdint.h>
#include <string.h>

#define REG(a) (*(volatile uint32_t *)(a))
#define RCC_CR       0x40023800u       /* bit 0 HSION, 1 HSIRDY, 24 PLLON, 25 PLLRDY */
#define RCC_PLLCFGR  0x40023804u
#define RCC_CFGR     0x40023808u
#define RCC_AHB1ENR  0x40023830u
#define RCC_APB1ENR  0x40023840u
#define RCC_APB2ENR  0x40023844u
#define FLASH_ACR    0x40023C00u
#define GPIOA        0x40020000u
#define GPIOC        0x40020800u
#define GPIO_MODER(p) ((p) + 0x00u)
#define GPIO_PUPDR(p) ((p) + 0x0Cu)
#define GPIO_IDR(p)   ((p) + 0x10u)
#define GPIO_BSRR(p)  ((p) + 0x18u)
#define GPIO_AFRH(p)  ((p) + 0x24u)
#define USART1       0x40011000u
#define USART_SR     (USART1 + 0x00u)  /* bit 5 RXNE, bit 7 TXE */
#define USART_DR     (USART1 + 0x04u)
#define USART_BRR    (USART1 + 0x08u)
#define USART_CR1    (USART1 + 0x0Cu)  /* bit 13 UE, 5 RXNEIE, 3 TE, 2 RE */
#define TIM2         0x40000000u
#define TIM5         0x40000C00u
#define TIM_CR1      (TIM2 + 0x00u)    /* bit 0 CEN, 2 URS, 7 ARPE */
#define TIM_DIER     (TIM2 + 0x0Cu)
#define TIM_SR       (TIM2 + 0x10u)
#define TIM_EGR      (TIM2 + 0x14u)
#define TIM_PSC      (TIM2 + 0x28u)
#define TIM_ARR      (TIM2 + 0x2Cu)
#define TIM5_CR1     (TIM5 + 0x00u)
#define TIM5_EGR     (TIM5 + 0x14u)
#define TIM5_CNT     (TIM5 + 0x24u)
#define TIM5_PSC     (TIM5 + 0x28u)
#define TIM5_ARR     (TIM5 + 0x2Cu)
#define NVIC_ISER0   0xE000E100u
#define NVIC_ISER1   0xE000E104u
#define NVIC_IPR(n)  (0xE000E400u + (n))
#define SCB_SHPR3    0xE000ED20u
#define SYST_CSR     0xE000E010u
#define SYST_RVR     0xE000E014u
#define SYST_CVR     0xE000E018u
#define IRQ_TIM2     28
#define IRQ_USART1   37

#define TICK_HZ 21000000u              /* TIM2 and TIM5: 84 MHz / 4 */
const char mcu_board_name[] = "stm32f405";
/* 100 steps per unit, 10,000 steps/s, 1,000,000 steps/s^2, 12 us pulses (as on the AN386) */
const mcu_axes_config_t mcu_axes = { 100u, 10000u, 1000000u, 252u, TICK_HZ };

static uint32_t ns_lo, ns_hi;          /* qemu: TIM5's last count, its wraps */
static int on_qemu;                    /* the RCC reads as zero: qemu's model (see above) */
static uint32_t due, after;            /* qemu: the next edge's time, the interval after it */

static void clocks_init(void)
{
    REG(FLASH_ACR) = 5u | 1u << 8 | 1u << 9 | 1u << 10;     /* 5 wait states, caches, prefetch */
    /* PLL from HSI: /16 -> 1 MHz, x336, /2 -> 168 MHz (/7 -> 48 MHz for USB) */
    REG(RCC_PLLCFGR) = 16u | 336u << 6 | 0u << 16 | 7u << 24;
    REG(RCC_CR) |= 1u << 24;
    while (!(REG(RCC_CR) & 1u << 25)) {}
    REG(RCC_CFGR) = 5u << 10 | 4u << 13;                     /* APB1 /4, APB2 /2 */
    REG(RCC_CFGR) = 5u << 10 | 4u << 13 | 2u;                /* SYSCLK from the PLL */
    while ((REG(RCC_CFGR) & 0xCu) != 0x8u) {}
}

void mcu_hal_init(void)
{
    on_qemu = (REG(RCC_CR) & 2u) == 0u;
    if (!on_qemu) clocks_init();
    REG(RCC_AHB1ENR) |= 1u << 0 | 1u << 2;                   /* GPIOA, GPIOC */
    REG(RCC_APB1ENR) |= 1u << 0 | 1u << 3;                   /* TIM2, TIM5 */
    REG(RCC_APB2ENR) |= 1u << 4;                             /* USART1 */
    /* PA9/PA10: USART1 (AF7); PA0/PA1 inputs pulled down; PC0-PC6 outputs */
    REG(GPIO_MODER(GPIOA)) = (REG(GPIO_MODER(GPIOA)) & ~(0xFu << 18 | 0xFu)) | 0xAu << 18;
    REG(GPIO_AFRH(GPIOA)) = (REG(GPIO_AFRH(GPIOA)) & ~0xFF0u) | 0x770u;
    REG(GPIO_PUPDR(GPIOA)) = (REG(GPIO_PUPDR(GPIOA)) & ~0xFu) | 0xAu;
    REG(GPIO_MODER(GPIOC)) = (REG(GPIO_MODER(GPIOC)) & ~0x3FFFu) | 0x1555u;
    REG(GPIO_BSRR(GPIOC)) = 0x7Fu << 16;
    REG(USART_BRR) = 84000000u / 115200u;                    /* APB2 84 MHz */
    REG(USART_CR1) = 1u << 13 | 1u << 5 | 1u << 3 | 1u << 2;
    /* on the part: TIM2 stopped, TIM5 running, both 84 MHz / 4 = 21 MHz; TIM2 preloaded,
     * updating only at overflow */
    if (!on_qemu) {
        REG(TIM_PSC) = 3u;
        REG(TIM_CR1) = 1u << 7 | 1u << 2;
        REG(TIM5_PSC) = 3u;
        REG(TIM5_ARR) = 0xFFFFFFFFu;
        REG(TIM5_EGR) = 1u;
        REG(TIM5_CR1) = 1u;
    }
    REG(TIM_DIER) = 1u;
    /* SysTick: HCLK/8 (21 MHz on the part and in qemu), 1 ms, interrupt */
    REG(SYST_RVR) = TICK_HZ / 1000u - 1u;
    REG(SYST_CVR) = 0;
    REG(SYST_CSR) = 0x3u;
    REG(SCB_SHPR3) = 0x80u << 24;                            /* the tick below the step edges */
    *(volatile uint8_t *)NVIC_IPR(IRQ_TIM2) = 0x00u;         /* the step edges first */
    *(volatile uint8_t *)NVIC_IPR(IRQ_USART1) = 0x40u;
    REG(NVIC_ISER0) = 1u << IRQ_TIM2;
    REG(NVIC_ISER1) = 1u << (IRQ_USART1 - 32);
}

uint32_t mcu_hal_now(void)
{
    uint32_t pm, lo;
    uint64_t t;
    if (!on_qemu) return REG(TIM5_CNT);
    __asm__ volatile ("mrs %0, primask\n\tcpsid i" : "=r"(pm) :: "memory");
    lo = REG(TIM5_CNT);
    if (lo < ns_lo) ns_hi++;
    ns_lo = lo;
    t = ((uint64_t)ns_hi << 32 | lo) * (TICK_HZ / 1000000u) / 1000u;
    __asm__ volatile ("msr primask, %0" :: "r"(pm) : "memory");
    return (uint32_t)t;
}

void mcu_hal_write(const uint8_t *p, size_t n)
{
    while (n--) {
        while (!(REG(USART_SR) & 1u << 7)) {}
        REG(USART_DR) = *p++;
    }
}

void mcu_hal_idle(void)
{
    /* the 1 kHz tick bounds the sleep when the awaited interrupt came just before the WFI */
    __asm__ volatile ("wfi");
}

void mcu_hal_motion_idle(void)
{
    /* awake: the edge interrupts are served at once (under qemu -icount a sleeping core's
     * time follows the host's clock) */
}

/* qemu: TIM2's next interrupt at time t of the free-running clock (the timer counts ns; an
 * edge already due gets the shortest period) */
static void arm_at(uint32_t t)
{
    int32_t d = (int32_t)(t - mcu_hal_now());
    uint32_t ns = d > 0 ? (uint32_t)d * 47u + ((uint32_t)d * 13u + 10u) / 21u : 0u;   /* 1000/21 ns */
    REG(TIM_ARR) = ns > 0u ? ns : 1u;
}

void mcu_hal_step_start(uint32_t first, uint32_t second)
{
    if (on_qemu) {
        REG(TIM_CR1) = 0u;
        due = mcu_hal_now() + first;
        after = second;
        REG(TIM_SR) = 0u;
        REG(TIM_CR1) = 1u;
        arm_at(due);
        return;
    }
    REG(TIM_CR1) = 1u << 7 | 1u << 2;
    REG(TIM_ARR) = first - 1u;
    REG(TIM_EGR) = 1u;                 /* loads ARR and PSC, counter 0; URS: no interrupt */
    REG(TIM_ARR) = second - 1u;        /* preloaded: the period after the first */
    REG(TIM_SR) = 0u;
    REG(TIM_CR1) = 1u << 7 | 1u << 2 | 1u;
}

void mcu_hal_step_next(uint32_t ticks)
{
    if (on_qemu) after = ticks;
    else REG(TIM_ARR) = ticks - 1u;    /* takes effect at the next update */
}

void mcu_hal_step_stop(void)
{
    REG(TIM_CR1) = on_qemu ? 0u : 1u << 7 | 1u << 2;
}

void mcu_hal_step_ack(void)
{
    REG(TIM_SR) = 0u;
    if (on_qemu) {
        /* the edge just served was due at `due`: the next one `after` later */
        due += after;
        arm_at(due);
    }
}

void mcu_hal_step_pins(uint32_t dir_bits, uint32_t step_bits)
{
    uint32_t set = (dir_bits & 7u) << 3 | (step_bits & 7u);
    REG(GPIO_BSRR(GPIOC)) = set | (~set & 0x3Fu) << 16;
}

uint32_t mcu_hal_inputs(void)
{
    uint32_t b = REG(GPIO_IDR(GPIOA));
    return (b & 1u ? MCU_IN_ESTOP : 0u) | (b & 2u ? MCU_IN_LIMIT : 0u);
}

void mcu_hal_laser(int on)
{
    REG(GPIO_BSRR(GPIOC)) = on ? 1u << 6 : 1u << 22;
}

/* ---- interrupts and start-up ---- */
void vp_usart1_handler(void);
void vp_tim2_handler(void);
void vp_reset_handler(void);
void vp_systick_handler(void);
extern uint32_t _ebss, _estack;

void vp_usart1_handler(void)
{
    while (REG(USART_SR) & 1u << 5) {
        uint8_t c = (uint8_t)REG(USART_DR);   /* the read clears RXNE */
        mcu_rx_put(c);
    }
}

void vp_tim2_handler(void)
{
    mcu_motion_edge();
}

void vp_systick_handler(void)
{
    /* qemu: TIM5's ns count wraps every 4.3 s; reading it every ms sees each wrap */
    if (on_qemu) (void)mcu_hal_now();
}

void vp_reset_handler(void)
{
    uint32_t *src, *dst = &_ebss;
    mcu_crt_init();
    /* the free RAM below the stack painted, so a debugger sees how deep the stack went */
    __asm__ volatile ("mov %0, sp" : "=r"(src));
    for (src -= 16; dst < src; dst++) *dst = 0xA5A5A5A5u;
    mcu_main();
    vp_default_handler();
}

typedef void (*vp_vector_t)(void);
#define D vp_default_handler
__attribute__((section(".isr_vector"), used))
static const vp_vector_t vector_table[16 + 38] = {
    (vp_vector_t)(uintptr_t)&_estack, vp_reset_handler, D, D, D, D, D, 0, 0, 0, 0, D, D, 0, D,
    vp_systick_handler,
    /* IRQ 0-27 */
    D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D,
    /* IRQ 28: TIM2, 29-36, 37: USART1 */
    vp_tim2_handler, D, D, D, D, D, D, D, D, vp_usart1_handler,
};
