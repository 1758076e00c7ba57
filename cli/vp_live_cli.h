/* The live view's options on the command line (--serve PORT, --serve-wait S, --serve-linger S)
 * and its start and end around a scan (host/vp_live). */
#ifndef VP_LIVE_CLI_H
#define VP_LIVE_CLI_H
#include <stdio.h>
#include "vp_live.h"

typedef struct vp_live_cli {
    unsigned port;         /* 0: no live view */
    double wait;           /* seconds to wait for a first page before scanning */
    double linger;         /* seconds to wait at the end for the pages to get the final state */
    vp_live_t *lv;
    vp_session_hooks_t hooks;
} vp_live_cli_t;

#define VP_LIVE_CLI_HELP \
    "  --serve PORT       serve a live view of the scan at http://HOST:PORT/ (every address of\n" \
    "                     this machine): the samples and the mesh as they grow, server-sent events\n" \
    "  --serve-wait S     wait up to S seconds for a page to connect before scanning\n" \
    "  --serve-linger S   at the end, wait up to S seconds for the pages to get the final state\n" \
    "                     (default 5)\n"

void vp_live_cli_init(vp_live_cli_t *c);
/* One option at argv[*i]: 0 taken, 1 not ours, -1 bad (said on stderr). */
int  vp_live_cli_option(vp_live_cli_t *c, int argc, char **argv, int *i, const char *cmd);
/* With --serve: starts the server and puts the live hook before *hooks. 0 ok, 1 failure (said). */
int  vp_live_cli_begin(vp_live_cli_t *c, const vp_planner_t *pl, const vp_session_hooks_t **hooks, FILE *msg, const char *cmd);
/* Publishes the final state and mesh, waits for the pages (--serve-linger), stops the server. */
void vp_live_cli_end(vp_live_cli_t *c, const char *state, const vp_mesh_t *mesh, FILE *msg, const char *cmd);

#endif
