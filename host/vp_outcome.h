/* vp_outcome — what a scan came to, said the same way by sim and scan: the exit status, the
 * JSON "status" and the summary line agree.
 *
 *   0  closed     the planner said DONE; the mesh is a closed 2-manifold around every o_i
 *   1  error      the scan stopped on an error (planner, device, I/O): the mesh so far is written
 *   2  usage      bad options (nothing scanned)
 *   3  stopped    paused on purpose (--stop-after, Ctrl-C, SIGTERM): resumable from the log
 *   4  not_closed DONE, but the mesh is not closed or misses a component (certify says where)
 *   5  collision  a move touched the object (simulator or dry run: the laser origin's path, or
 *                 the head's body swept along a move or an aim): the one promise broken
 *   6  not_within_target  closed, but the measured Hausdorff distance is above the accuracy
 *                         target (sim --accuracy: only a simulation can measure it)
 *   7  wrong_topology     closed, but its genus or number of components is not the object's
 *                         (only a simulation or a dry run knows the object's)
 */
#ifndef VP_OUTCOME_H
#define VP_OUTCOME_H

enum vp_exit {
    VP_EXIT_CLOSED = 0, VP_EXIT_ERROR = 1, VP_EXIT_USAGE = 2, VP_EXIT_STOPPED = 3,
    VP_EXIT_NOT_CLOSED = 4, VP_EXIT_COLLISION = 5, VP_EXIT_NOT_WITHIN_TARGET = 6,
    VP_EXIT_WRONG_TOPOLOGY = 7
};

typedef struct vp_outcome_in {
    int run_status;         /* the session loop's status (VP_OK after DONE) */
    int paused;             /* stopped on purpose */
    unsigned long collisions;
    int closed_manifold;    /* the mesh, checked */
    unsigned missing_components;
    int beyond_target;      /* the measured Hausdorff distance exceeds the accuracy target */
    int wrong_topology;     /* closed, but not with the object's genus and components (known) */
} vp_outcome_in_t;

int vp_outcome(const vp_outcome_in_t *in);   /* the exit status */
const char *vp_outcome_name(int exit_status); /* "closed", "error", ... */

#endif
