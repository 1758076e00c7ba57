/* vp_progress — a bar on a terminal, plain periodic lines elsewhere. */
#include <stdlib.h>
#include <unistd.h>
#include "vp_progress.h"
#include "vp_rtclock.h"

#define BAR_WIDTH 24

void vp_progress_init(vp_progress_t *p, FILE *f)
{
    const char *env = getenv("VP_PROGRESS_SECONDS");
    double s = env ? strtod(env, NULL) : 0.0;
    p->f = f;
    p->tty = f && isatty(fileno(f));
    p->period = p->tty ? 0.5 : s > 0 ? s : 10.0;
    p->next = vp_rt_seconds() + p->period;
    p->drawn = 0;
}

int vp_progress_tick(vp_progress_t *p)
{
    double now;
    if (!p->f) return 0;
    now = vp_rt_seconds();
    if (now < p->next) return 0;
    p->next = now + p->period;
    return 1;
}

void vp_progress_print(vp_progress_t *p, double fraction, const char *text, int final)
{
    if (!p->f) return;
    if (p->tty) {
        fputs("\r\033[K", p->f);
        if (fraction >= 0) {
            int i, full = (int)(fraction * BAR_WIDTH + 0.5);
            if (full > BAR_WIDTH) full = BAR_WIDTH;
            fputc('[', p->f);
            for (i = 0; i < BAR_WIDTH; i++) fputc(i < full ? '#' : '.', p->f);
            fprintf(p->f, "] %3d%% ", (int)(100 * (fraction > 1 ? 1 : fraction) + 0.5));
        }
        fputs(text, p->f);
        if (final) fputc('\n', p->f);
        p->drawn = !final;
    } else {
        fprintf(p->f, "%s\n", text);
    }
    fflush(p->f);
}
