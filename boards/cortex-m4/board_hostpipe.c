/* The MCU's sources on the build machine: the link on stdin/stdout (a pipe to `voroprobe mcu
 * --exec`), the step timer simulated on a virtual clock (each idle call is the next timer
 * expiry: the interval in the timer runs out, the next one is reloaded, the interrupt
 * handler runs). The same session, byte for byte, as the board's: x86-64 against the M4.
 * (mcu.h is given with -include.) */
#include <poll.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

const char mcu_board_name[] = "host-pipe";
const mcu_axes_config_t mcu_axes = { 100u, 10000u, 1000000u, 300u, 25000000u };

static unsigned char inbuf[4096];
static size_t in_n, in_i;
static uint32_t virtual_ticks;     /* the time the simulated step timer has run */
static int step_running;
static uint32_t step_count, step_reload;
/* VP_M4_ESTOP=FROM,COUNT: the e-stop input reads pressed on input reads FROM .. FROM+COUNT-1
 * (one read after each step pulse): a glitch shorter than MCU_DEBOUNCE must be ignored */
static unsigned long estop_from, estop_count, input_reads;

void mcu_hal_init(void)
{
    const char *e = getenv("VP_M4_ESTOP");
    char *end;
    if (e) {
        estop_from = strtoul(e, &end, 10);
        estop_count = *end == ',' ? strtoul(end + 1, NULL, 10) : 1;
    }
}

static uint32_t real_ticks(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint32_t)((uint64_t)ts.tv_sec * mcu_axes.tick_hz + (uint64_t)ts.tv_nsec * mcu_axes.tick_hz / 1000000000u);
}

/* the build machine's clock, stopped while the simulated step timer runs (its edges are then
 * served exactly on time: the ideal the board is compared with) */
static uint32_t real_at_start;
uint32_t mcu_hal_now(void)
{
    return (step_running ? real_at_start : real_ticks()) + virtual_ticks;
}

int mcu_hal_getc(void)
{
    if (in_i == in_n) {
        struct pollfd p;
        ssize_t r;
        p.fd = 0;
        p.events = POLLIN;
        if (poll(&p, 1, 1) <= 0) return -1;
        r = read(0, inbuf, sizeof inbuf);
        if (r <= 0) exit(0);           /* the host closed the link */
        in_n = (size_t)r;
        in_i = 0;
    }
    return inbuf[in_i++];
}

void mcu_hal_write(const uint8_t *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(1, p, n);
        if (w <= 0) exit(1);
        p += w;
        n -= (size_t)w;
    }
}

void mcu_hal_idle(void)
{
}

void mcu_hal_motion_idle(void)
{
    if (!step_running) return;
    virtual_ticks += step_count;
    step_count = step_reload;
    mcu_motion_edge();
}

void mcu_hal_step_start(uint32_t first, uint32_t second)
{
    step_count = first;
    step_reload = second;
    real_at_start = real_ticks();
    step_running = 1;
}

void mcu_hal_step_next(uint32_t ticks)
{
    step_reload = ticks;
}

void mcu_hal_step_stop(void)
{
    step_running = 0;
    virtual_ticks += real_at_start - real_ticks();   /* the clock goes on from where it stopped */
}

void mcu_hal_step_ack(void)
{
}

void mcu_hal_step_pins(uint32_t dir_bits, uint32_t step_bits)
{
    (void)dir_bits;
    (void)step_bits;
}

uint32_t mcu_hal_inputs(void)
{
    unsigned long k = input_reads++;
    return estop_count && k >= estop_from && k - estop_from < estop_count ? MCU_IN_ESTOP : 0u;
}

void mcu_hal_laser(int on)
{
    (void)on;
}

int main(void);
int main(void)
{
    mcu_main();
    return 0;
}
