/* vp_device — what the run loop (vp_run) needs of a scanner: execute the planner's MOVE and
 * PROBE. A device is host-sim, a real machine through port/ (vp_machine), a logged session
 * being replayed, or the Cortex-M4 image's built-in probe; the loop does not know which. */
#ifndef VP_DEVICE_H
#define VP_DEVICE_H
#include "vp_planner.h"

#define VP_DEV_PATH 16   /* MOVEs the scan loop gives a device's move_path at once */

typedef struct vp_device_ops {
    void *ctx;
    /* executes a straight move; *collided (may be ignored) reports a collision seen by a
     * simulator. Returns VP_OK or an error (the scan stops). */
    int (*move)(void *ctx, const vp_cmd_t *cmd, int *collided);
    /* executes consecutive MOVEs (cmds[0 .. n), n <= VP_DEV_PATH) as one path: the same lines,
     * the waypoints between them passed without stopping where the machine can; collided[i] as
     * move's; *done the MOVEs made whole, from the first (fewer than n with VP_OK: the rest are
     * given again). NULL: each MOVE alone. With touched: a contact stops the path, the MOVE
     * it stopped is the last of *done, and touched says where along it. */
    int (*move_path)(void *ctx, const vp_cmd_t *cmds, int n, int *collided, int *done);
    /* executes a probe; fills res. */
    int (*probe)(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res);
    /* after a MOVE: 1 when the head's contact switch stopped it, *at the distance from the
     * move's start to where the switch closed (the head has backed off to that point); 0 for a
     * move made whole. NULL: the head has no contact switch. */
    int (*touched)(void *ctx, double *at);
    /* after a PROBE, with a line laser: the i-th more ray of the same frame (i = 0, 1, ...): 1
     * with *ray (a copy of the PROBE, kind VP_CMD_RAY) given its unit direction and the range it
     * was read over, and its result; 0 when the frame has no more; < 0 an error (the scan stops).
     * NULL: a dot laser. */
    int (*rays)(void *ctx, const vp_cmd_t *probe, unsigned i, vp_cmd_t *ray, vp_probe_result_t *res);
    /* after a PROBE (or a ray of its frame) the device read as a miss: 1 with *cam the camera's
     * centre at that reading when a miss means only that the camera found no spot (a spot hidden
     * from it reads the same); 0 when a miss is seen for what it is (walls round the machine show
     * the spot past the range). NULL: misses are trusted. */
    int (*sight)(void *ctx, const vp_cmd_t *probe, double cam[3]);
} vp_device_ops_t;

#endif
