/* vp_session — the scan loop (core/vp_run) on a host: with a clock for the timing, a progress
 * line and the session log's hook. The device (core/vp_device.h) is anything that can execute
 * MOVE and PROBE (host-sim, a real machine through port/, or a logged session being replayed). */
#ifndef VP_SESSION_H
#define VP_SESSION_H
#include <stdio.h>
#include "vp_device.h"
#include "vp_meshio.h"
#include "vp_planner.h"

typedef struct vp_session_hooks {
    void *ctx;
    /* called after each command was executed (res NULL for MOVE/DONE); a non-zero return
     * stops the scan with that status */
    int (*after)(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res);
} vp_session_hooks_t;

typedef struct vp_session_result {
    int status;              /* VP_OK when the planner said DONE */
    unsigned long collisions;
    unsigned long unseen_misses; /* misses fed as unreadable: their spot maybe hidden (vp_run.h) */
    double planner_seconds;  /* CPU time inside vp_planner_next/feed */
    double total_seconds;    /* wall time of the loop */
} vp_session_result_t;

/* Runs until DONE, an error, or max_commands (0: no limit). progress: a FILE to print a
 * progress line to (NULL: quiet). */
int vp_session_run(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_session_hooks_t *hooks,
                   unsigned long max_commands, FILE *progress, vp_session_result_t *out);

/* Progress lines are printed at most twice a second: 1 when one is due (*next_report then moves
 * half a second on), else 0. *next_report starts at 0 (the first is due at once) or a time of
 * vp_rt_seconds(). */
int vp_progress_due(double *next_report);

/* The planner's restricted facets as a mesh (used vertices only, in triangulation order,
 * faces oriented outward). */
int vp_session_mesh(const vp_planner_t *pl, vp_mesh_t *m);

#endif
