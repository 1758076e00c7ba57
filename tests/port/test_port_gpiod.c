/* The libgpiod backend on a real GPIO chip. Pins are only touched on a simulated chip
 * (gpio-sim / gpio-mockup label) or on lines named by the user:
 *   VP_TEST_GPIOCHIP=gpiochip0 VP_TEST_GPIO_FIRST=5   (11 free lines from offset 5)
 * Elsewhere it is skipped (exit 77), after checking that a missing chip is VP_ENODEV.
 * On a chip: a two-axis move at 5 kHz through real lines, outputs read back, timing figures,
 * a second request of the same lines reported busy, an offset past the chip refused. */
#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_gpiod.h"
#include "vp_status.h"
#include "vp_step.h"
#include "vp_test.h"

#ifdef VP_HAVE_GPIOD
#include <gpiod.h>

static void pin(vp_gpio_pin_t *p, const char *chip, int off)
{
    snprintf(p->chip, sizeof p->chip, "%s", chip);
    p->offset = off;
}

static int find_chip(char *name, size_t n, int *first)
{
    glob_t g;
    size_t i;
    int found = 0;
    const char *env = getenv("VP_TEST_GPIOCHIP");
    if (env && *env) {
        snprintf(name, n, "%s", env);
        *first = getenv("VP_TEST_GPIO_FIRST") ? atoi(getenv("VP_TEST_GPIO_FIRST")) : 0;
        return 1;
    }
    if (glob("/dev/gpiochip*", 0, NULL, &g) != 0) return 0;
    for (i = 0; i < g.gl_pathc && !found; i++) {
        struct gpiod_chip *c = gpiod_chip_open(g.gl_pathv[i]);
        if (!c) continue;
        if ((!strncmp(gpiod_chip_label(c), "gpio-sim", 8) || !strncmp(gpiod_chip_label(c), "gpio-mockup", 11)) &&
            gpiod_chip_num_lines(c) >= 11) {
            snprintf(name, n, "%s", gpiod_chip_name(c));
            *first = 0;
            found = 1;
        }
        gpiod_chip_close(c);
    }
    globfree(&g);
    return found;
}
#endif

int main(void)
{
    char err[256];
    vp_gpiod_t *g = NULL;
    vp_gpiod_config_t gc;
    memset(&gc, 0, sizeof gc);
    snprintf(gc.out[0].chip, sizeof gc.out[0].chip, "gpiochip-no-such-chip");
    CHECK(vp_gpiod_open(&gc, &g, err, sizeof err) == VP_ENODEV && g == NULL);
    CHECK(strstr(err, "gpiochip-no-such-chip") != NULL || strstr(err, "without libgpiod") != NULL);
#ifndef VP_HAVE_GPIOD
    if (vp_test_failures) return vp_test_done("test_port_gpiod");
    TEST_SKIP("built without libgpiod");
#else
    {
        glob_t gl;
        char chip[VP_GPIO_CHIP_LEN];
        int first = 0, i, rc;
        if (glob("/dev/gpiochip*", 0, NULL, &gl) != 0) {
            if (vp_test_failures) return vp_test_done("test_port_gpiod");
            TEST_SKIP("no /dev/gpiochip* on this machine (a missing chip is reported as VP_ENODEV: checked)");
        }
        globfree(&gl);
        if (!find_chip(chip, sizeof chip, &first)) {
            if (vp_test_failures) return vp_test_done("test_port_gpiod");
            TEST_SKIP("no gpio-sim/gpio-mockup chip and VP_TEST_GPIOCHIP unset: real pins left alone");
        }
        /* step 0,1; dir 8,9; one shared active-low enable; e-stop input */
        memset(&gc, 0, sizeof gc);
        pin(&gc.out[0], chip, first + 0);
        pin(&gc.out[1], chip, first + 1);
        pin(&gc.out[8], chip, first + 2);
        pin(&gc.out[9], chip, first + 3);
        pin(&gc.out[16], chip, first + 4);
        pin(&gc.out[17], chip, first + 4);
        gc.out[16].active_low = gc.out[17].active_low = 1;
        pin(&gc.in[16], chip, first + 5);
        rc = vp_gpiod_open(&gc, &g, err, sizeof err);
        CHECKF(rc == VP_OK, "%s", err);
        if (rc == VP_OK) {
            vp_gpiod_t *g2 = NULL;
            vp_step_config_t c;
            vp_step_t s;
            vp_io_t io = vp_gpiod_io(g);
            vp_rt_stats_t st;
            double target[2] = { 50, 25 };
            CHECK(vp_gpiod_open(&gc, &g2, err, sizeof err) == VP_EIO && strstr(err, "busy"));
            memset(&c, 0, sizeof c);
            c.naxes = 2;
            for (i = 0; i < 2; i++) {
                c.axis[i].steps_per_unit = 20;
                c.axis[i].max_speed = 250;      /* 5000 steps/s */
                c.axis[i].accel = 10000;
                c.axis[i].travel_max = 100;
            }
            c.allow_unhomed = 1;
            c.no_hard_limits = 1;
            CHECK(vp_step_init(&s, &c, &io) == VP_OK);
            rc = vp_step_move(&s, target);
            CHECKF(rc == VP_OK || rc == VP_EABORT, "move: %d", rc);
            vp_gpiod_stats(g, &st);
            CHECK(st.early == 0);
            printf("gpiod on %s: %llu deadlines, late mean %.1f us, <=%g us for 99%%, max %.1f us\n", chip,
                   (unsigned long long)st.waits, st.late_sum_ns / (st.waits ? st.waits : 1) * 1e-3,
                   vp_rt_quantile_us(&st, 0.99), st.late_max_ns * 1e-3);
            vp_gpiod_close(g);
        }
        memset(&gc, 0, sizeof gc);
        pin(&gc.out[0], chip, 100000);
        CHECK(vp_gpiod_open(&gc, &g, err, sizeof err) == VP_EINVAL && strstr(err, "no line"));
    }
    return vp_test_done("test_port_gpiod");
#endif
}
