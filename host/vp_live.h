/* vp_live — the live view of a running scan: an HTTP server (libmicrohttpd, its own threads)
 * serving a page and a stream of server-sent events: the probed surface points as they come,
 * snapshots of the mesh, and the counts. The scan loop only appends to memory and publishes
 * with a try-lock: it never waits for the server or a browser. Samples are all kept (an
 * append-only array in fixed chunks, read by each connection at its own pace); mesh snapshots
 * are built only when a connection has sent the last one, so a slow browser gets fewer frames,
 * never fewer samples. */
#ifndef VP_LIVE_H
#define VP_LIVE_H
#include <stddef.h>
#include <stdint.h>
#include "vp_planner.h"
#include "vp_session.h"

typedef struct vp_live vp_live_t;

/* Starts serving page[0..len) at / and the events at /events on every address of the host.
 * VP_OK; VP_EIO (the port cannot be bound: err says); VP_ENODEV (built without libmicrohttpd). */
int  vp_live_start(vp_live_t **out, unsigned port, const char *page, size_t len, char *err, size_t errlen);
/* Watches pl and chains the scan's own hook (inner, may be NULL): give the scan *hooks. */
void vp_live_attach(vp_live_t *lv, const vp_planner_t *pl, const vp_session_hooks_t *inner, vp_session_hooks_t *hooks);
/* Waits up to seconds for a first page to connect (so it sees the scan from its start): 1 if one did. */
int  vp_live_wait_client(vp_live_t *lv, double seconds);
/* The scan ended: the final mesh and counts are published under state ("closed", "stopped",
 * ...); waits up to linger seconds for the pages connected to receive them. */
void vp_live_finish(vp_live_t *lv, const char *state, const vp_mesh_t *mesh, double linger);
/* Frames built and their cost (the time the scan loop spent on them). */
void vp_live_stats(const vp_live_t *lv, unsigned long *frames, double *max_frame_seconds, double *total_frame_seconds);
void vp_live_stop(vp_live_t *lv);

#endif
