/* libFuzzer target: the board file parser (INI, host/vp_board.c) and what a board it accepts
 * implies: the planner's, the kinematics', the step generator's and the machine's configuration,
 * and the planner started on it. A file refused says why (a reason in err, VP_EINVAL or VP_EIO);
 * a file accepted gives configurations the modules take or refuse with a status. Never a crash,
 * never a sanitizer report. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "vp_board.h"
#include "vp_planner.h"
#include "vp_status.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define ARENA_BYTES ((size_t)4 << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static vp_board_t b;
    static vp_planner_t pl;
    static void *arena;
    char *text, err[1024];
    int st;
    if (!arena && !(arena = malloc(ARENA_BYTES))) return 0;
    text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0; /* a NUL inside the data ends the text there, as a file's would be refused */
    err[0] = 0;
    st = vp_board_parse(text, "fuzz.ini", &b, err, sizeof err);
    if (st != VP_OK) {
        if ((st != VP_EINVAL && st != VP_EIO) || !err[0]) __builtin_trap(); /* refused, and why */
    } else {
        vp_planner_config_t c;
        vp_kin_config_t kc;
        vp_kin_t k;
        vp_step_config_t sc;
        vp_machine_config_t mc;
        vp_board_planner_config(&b, &c);
        c.noise_tol = 0.5;
        st = vp_planner_init(&pl, arena, ARENA_BYTES, &c);
        if (st != VP_OK && st != VP_EINVAL && st != VP_ENOMEM) __builtin_trap();
        if (st == VP_OK) {
            vp_cmd_t cmd;
            int n;
            /* the first commands: the way to the first probe */
            for (n = 0; n < 8 && vp_planner_next(&pl, &cmd) == VP_OK && cmd.kind == VP_CMD_MOVE; n++)
                ;
        }
        vp_board_kin_config(&b, &kc);
        st = vp_kin_init(&k, &kc);
        if (st != VP_OK && st != VP_EINVAL) __builtin_trap();
        vp_board_step_config(&b, &sc);
        vp_board_machine_config(&b, &mc);
    }
    free(text);
    return 0;
}
