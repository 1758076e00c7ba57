/* vp_bodyreport — the body-mode lines of a scan's summary (vp_bodyreport.h). */
#include <string.h>
#include "vp_bodyreport.h"

typedef unsigned long long ull;

void vp_bodyreport_aims(FILE *f, const vp_planner_stats_t *st)
{
    fprintf(f, "body: hidden facets at holes aimed at from aside: %llu probes, %llu balls found (%llu by the hit "
               "nearest the edge), %llu far vertices seen free; %llu sides aimed at again through their far vertex "
               "alone (closing's last resort, taken %llu times); %llu facets refined at open edges round sides left "
               "unseen; %llu balls refined at the point read, %llu left as they were (read beside a sample)\n",
            (ull)st->aims, (ull)st->aim_balls, (ull)st->aim_near, (ull)st->aim_reached, (ull)st->far_line_sides,
            (ull)st->last_resorts, (ull)st->unseen_refinements, (ull)st->read_samples, (ull)st->read_kept);
}

void vp_bodyreport_far(FILE *f, const vp_planner_stats_t *st)
{
    fprintf(f, "body: %llu spots read past their edge's end (the edge free), %llu of them made samples (no sample "
               "within eps)\n", (ull)st->far_reads, (ull)st->far_samples);
}

void vp_bodyreport_aims_json(char *buf, size_t n, const vp_planner_stats_t *st)
{
    size_t at = strlen(buf);
    if (at >= n) return;
    snprintf(buf + at, n - at,
             ",\"aims\":%llu,\"aim_balls\":%llu,\"aim_near\":%llu,\"aim_reached\":%llu,\"far_line_sides\":%llu,"
             "\"last_resorts\":%llu,\"unseen_refinements\":%llu,\"read_samples\":%llu,\"read_kept\":%llu",
             (ull)st->aims, (ull)st->aim_balls, (ull)st->aim_near, (ull)st->aim_reached, (ull)st->far_line_sides,
             (ull)st->last_resorts, (ull)st->unseen_refinements, (ull)st->read_samples, (ull)st->read_kept);
}

void vp_bodyreport_far_json(char *buf, size_t n, const vp_planner_stats_t *st)
{
    size_t at = strlen(buf);
    if (at >= n) return;
    snprintf(buf + at, n - at, ",\"far_reads\":%llu,\"far_samples\":%llu", (ull)st->far_reads,
             (ull)st->far_samples);
}
