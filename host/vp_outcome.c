/* vp_outcome — see vp_outcome.h. */
#include "vp_outcome.h"
#include "vp_status.h"

int vp_outcome(const vp_outcome_in_t *in)
{
    if (in->collisions > 0) return VP_EXIT_COLLISION;
    if (in->paused) return VP_EXIT_STOPPED;
    if (in->run_status != VP_OK) return VP_EXIT_ERROR;
    if (!in->closed_manifold || in->missing_components > 0) return VP_EXIT_NOT_CLOSED;
    if (in->wrong_topology) return VP_EXIT_WRONG_TOPOLOGY;
    if (in->beyond_target) return VP_EXIT_NOT_WITHIN_TARGET;
    return VP_EXIT_CLOSED;
}

const char *vp_outcome_name(int exit_status)
{
    switch (exit_status) {
    case VP_EXIT_CLOSED: return "closed";
    case VP_EXIT_ERROR: return "error";
    case VP_EXIT_USAGE: return "usage";
    case VP_EXIT_STOPPED: return "stopped";
    case VP_EXIT_NOT_CLOSED: return "not_closed";
    case VP_EXIT_COLLISION: return "collision";
    case VP_EXIT_NOT_WITHIN_TARGET: return "not_within_target";
    case VP_EXIT_WRONG_TOPOLOGY: return "wrong_topology";
    default: return "unknown";
    }
}
