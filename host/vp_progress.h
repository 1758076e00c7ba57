/* vp_progress — progress that suits where it goes. On a terminal: one line redrawn in place
 * (carriage return, erase to the end) with a bar, at most twice a second. In a pipe or a file:
 * plain lines, one every period (VP_PROGRESS_SECONDS in the environment, default 10 s), and
 * the last one when the run ends, so a log file reads line by line. */
#ifndef VP_PROGRESS_H
#define VP_PROGRESS_H
#include <stdio.h>

typedef struct vp_progress {
    FILE *f;
    int tty;          /* f is a terminal */
    double period;    /* seconds between lines */
    double next;      /* when the next line is due (vp_rt_seconds) */
    int drawn;        /* a line is on the terminal, not yet ended */
} vp_progress_t;

void vp_progress_init(vp_progress_t *p, FILE *f);
/* 1 when a line is due (the next then moves one period on), else 0. */
int  vp_progress_tick(vp_progress_t *p);
/* Prints text; on a terminal after a bar of fraction (0..1; < 0: no bar). final ends the line. */
void vp_progress_print(vp_progress_t *p, double fraction, const char *text, int final);

#endif
