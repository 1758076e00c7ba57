/* vp_run — the scan loop, once for every device: allocation-free, no clock, no stdio.
 *
 *     vp_planner_next -> MOVE:  dev->move  -> hooks->after(cmd, NULL)
 *                               stopped by contact: hooks->after(cmd, {hit 1, dist at})
 *                               -> vp_planner_touch
 *                     -> PROBE: dev->probe [-> dev->sight: a miss whose spot may be hidden
 *                               from the camera becomes unreadable] -> hooks->after(cmd, res)
 *                               -> vp_planner_feed
 *                     -> DONE:  hooks->after(cmd, NULL), stop
 *
 * A device with move_path (and no contact switch) gets a MOVE and the MOVEs the planner gives
 * after it (up to VP_DEV_PATH, never past max_commands) at once, to pass the waypoints between
 * them without stopping; each MOVE is then logged and counted as when made alone. The planner
 * needs nothing back from a MOVE made whole, so the commands and the log are the same.
 *
 * A probe's result goes to the hooks (the session log) before the planner judges it: nothing
 * measured is lost when the planner then stops (a replay stops at the same record). Timing
 * and progress come from optional hooks the host supplies (host/vp_session.c); the Cortex-M4
 * image and the tests run it bare. */
#ifndef VP_RUN_H
#define VP_RUN_H
#include "vp_device.h"
#include "vp_planner.h"

typedef struct vp_run_hooks {
    void *ctx;
    /* after each executed command (res NULL for MOVE and DONE; for a MOVE the contact switch
     * stopped, hit 1 and dist the distance along it): non-zero stops the scan with that
     * status. May be NULL. */
    int (*after)(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res);
    /* seconds on some monotonic clock, read around each planner call to add up the planner's
     * share (out->planner_seconds). May be NULL: not timed. */
    double (*clock)(void *ctx);
    /* after each executed MOVE or PROBE (commands: how many so far). May be NULL. */
    void (*progress)(void *ctx, const vp_planner_t *pl, unsigned long commands);
} vp_run_hooks_t;

typedef struct vp_run_result {
    int status;                 /* VP_OK: DONE or max_commands reached; else the error */
    int done;                   /* the planner said DONE */
    unsigned long commands;     /* MOVE and PROBE commands executed */
    unsigned long collisions;   /* moves the device reported as collided */
    unsigned long contacts;     /* moves the head's contact switch stopped */
    unsigned long unseen_misses; /* misses fed as unreadable: their spot may be hidden from the
                                    camera (vp_device_ops_t.sight, vp_planner_spot_hidden) */
    double planner_seconds;     /* inside vp_planner_next/feed (0 without hooks->clock) */
} vp_run_result_t;

/* Runs until DONE, an error, or max_commands executed (0: no limit). hooks may be NULL.
 * Returns out->status. */
int vp_run(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_run_hooks_t *hooks,
           unsigned long max_commands, vp_run_result_t *out);

#endif
