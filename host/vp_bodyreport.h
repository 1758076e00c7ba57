/* vp_bodyreport — the body-mode lines of a scan's summary, written the same way by sim and
 * scan: hidden facets aimed at from aside (core/planner/aim.c) and spots read past their edge's
 * end (VP_PLAN_FAR_READS), as a text line and as JSON fields. */
#ifndef VP_BODYREPORT_H
#define VP_BODYREPORT_H

#include <stddef.h>
#include <stdio.h>
#include "vp_planner.h"

/* the summary lines, each ending in a newline */
void vp_bodyreport_aims(FILE *f, const vp_planner_stats_t *st);
void vp_bodyreport_far(FILE *f, const vp_planner_stats_t *st);

/* the same counts as JSON fields (",\"aims\":N,..."), appended to the string in buf (size n;
 * cut short, still terminated, when it is full) */
void vp_bodyreport_aims_json(char *buf, size_t n, const vp_planner_stats_t *st);
void vp_bodyreport_far_json(char *buf, size_t n, const vp_planner_stats_t *st);

#endif
