/* --serve and its companions, around a scan. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_live_cli.h"

extern const unsigned char vp_live_page[];
extern const size_t vp_live_page_len;

void vp_live_cli_init(vp_live_cli_t *c)
{
    memset(c, 0, sizeof *c);
    c->linger = 5.0;
}

int vp_live_cli_option(vp_live_cli_t *c, int argc, char **argv, int *i, const char *cmd)
{
    const char *a = argv[*i], *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    char *e;
    double v;
    if (strcmp(a, "--serve") && strcmp(a, "--serve-wait") && strcmp(a, "--serve-linger")) return 1;
    if (!val) { fprintf(stderr, "%s: %s needs a value\n", cmd, a); return -1; }
    (*i)++;
    v = strtod(val, &e);
    if (e == val || *e || !(v >= 0) || !isfinite(v)) { fprintf(stderr, "%s: %s takes a number, not '%s'\n", cmd, a, val); return -1; }
    if (!strcmp(a, "--serve")) {
        if (v < 1 || v > 65535 || v != floor(v)) { fprintf(stderr, "%s: --serve takes a port 1..65535, not '%s'\n", cmd, val); return -1; }
        c->port = (unsigned)v;
    } else if (!strcmp(a, "--serve-wait")) c->wait = v;
    else c->linger = v;
    return 0;
}

int vp_live_cli_begin(vp_live_cli_t *c, const vp_planner_t *pl, const vp_session_hooks_t **hooks, FILE *msg, const char *cmd)
{
    char err[300];
    if (!c->port) return 0;
    if (vp_live_start(&c->lv, c->port, (const char *)vp_live_page, vp_live_page_len, err, sizeof err) != VP_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err);
        return 1;
    }
    vp_live_attach(c->lv, pl, *hooks, &c->hooks);
    *hooks = &c->hooks;
    if (msg) fprintf(msg, "%s: live view at http://<this machine>:%u/\n", cmd, c->port);
    if (c->wait > 0 && !vp_live_wait_client(c->lv, c->wait) && msg)
        fprintf(msg, "%s: no page connected within %g s: scanning\n", cmd, c->wait);
    return 0;
}

void vp_live_cli_end(vp_live_cli_t *c, const char *state, const vp_mesh_t *mesh, FILE *msg, const char *cmd)
{
    unsigned long frames;
    double fmax, ftotal;
    if (!c->lv) return;
    vp_live_finish(c->lv, state, mesh, c->linger);
    vp_live_stats(c->lv, &frames, &fmax, &ftotal);
    if (msg) fprintf(msg, "%s: live view: %lu mesh frames built in the scan loop (%.3f s in all, longest %.4f s)\n",
                     cmd, frames, ftotal, fmax);
    vp_live_stop(c->lv);
    c->lv = NULL;
}
