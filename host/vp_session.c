#include <stdlib.h>
#include <string.h>
#include "vp_progress.h"
#include "vp_rtclock.h"
#include "vp_meshcheck.h"
#include "vp_run.h"
#include "vp_session.h"

/* One progress line. The bar is how near the mesh is to closing: its facets over the 2V - 4 a
 * closed mesh of genus 0 on the same V samples has (full when closed; a torus reads full at
 * 2V facets too). There is no total to count to: the object's size is unknown. */
static void progress_line(vp_progress_t *p, const vp_planner_t *pl, int final)
{
    vp_planner_stats_t st;
    char text[200];
    uint32_t nv = vp_planner_dt(pl)->ninserted, nf = vp_planner_num_facets(pl);
    double frac = nv > 3 ? (double)nf / (2.0 * nv - 4.0) : 0.0;
    vp_planner_get_stats(pl, &st);
    snprintf(text, sizeof text, "%sprobes %-9llu vertices %-7u facets %-7u bad balls %-6u largest ball %.4g (eps %.4g)",
             p->tty ? "closed " : "  progress: ", (unsigned long long)st.probes, nv, nf, st.bad_balls,
             st.bad_balls ? st.max_ball : 0.0, pl->cfg.eps);
    vp_progress_print(p, frac > 1.0 ? 1.0 : frac, text, final);
}

int vp_progress_due(double *next_report)
{
    double now = vp_rt_seconds();
    if (now <= *next_report) return 0;
    *next_report = now + 0.5;
    return 1;
}

typedef struct vp_session_run_ctx {
    const vp_session_hooks_t *hooks;
    FILE *progress;
    vp_progress_t prog;
} vp_session_run_ctx_t;

static int vp_session_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    const vp_session_hooks_t *h = ((vp_session_run_ctx_t *)ctx)->hooks;
    return h && h->after ? h->after(h->ctx, cmd, res) : VP_OK;
}

/* the scan is one thread that never sleeps: monotonic time inside the planner calls is its
 * CPU time, and reading it costs no system call */
static double vp_session_clock(void *ctx)
{
    (void)ctx;
    return vp_rt_seconds();
}

static void vp_session_progress(void *ctx, const vp_planner_t *pl, unsigned long commands)
{
    vp_session_run_ctx_t *c = ctx;
    if (c->progress && (commands & 1023u) == 0 && vp_progress_tick(&c->prog)) progress_line(&c->prog, pl, 0);
}

int vp_session_run(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_session_hooks_t *hooks,
                   unsigned long max_commands, FILE *progress, vp_session_result_t *out)
{
    double w0 = vp_rt_seconds();
    vp_session_run_ctx_t c;
    vp_run_hooks_t rh;
    vp_run_result_t r;
    c.hooks = hooks;
    c.progress = progress;
    vp_progress_init(&c.prog, progress);
    rh.ctx = &c;
    rh.after = vp_session_after;
    rh.clock = vp_session_clock;
    rh.progress = vp_session_progress;
    vp_run(pl, dev, &rh, max_commands, &r);
    if (progress) progress_line(&c.prog, pl, 1);
    memset(out, 0, sizeof *out);
    out->status = r.status;
    out->collisions = r.collisions;
    out->unseen_misses = r.unseen_misses;
    out->planner_seconds = r.planner_seconds;
    out->total_seconds = vp_rt_seconds() - w0;
    return r.status;
}

int vp_session_mesh(const vp_planner_t *pl, vp_mesh_t *m)
{
    const vp_dt_t *dt = vp_planner_dt(pl);
    uint32_t slots = vp_planner_facet_slots(pl), i, *map, nv = 0, nt = 0;
    int st;
    map = malloc(((size_t)dt->nvert + 1) * sizeof *map);
    if (!map) return VP_ENOMEM;
    for (i = 0; i < dt->nvert; i++) map[i] = VP_DT_NONE;
    for (i = 0; i < slots; i++) {
        uint32_t v[3];
        int k;
        if (!vp_planner_facet(pl, i, v, NULL, NULL)) continue;
        for (k = 0; k < 3; k++) map[v[k]] = 0;
        nt++;
    }
    for (i = 0; i < dt->nvert; i++)
        if (map[i] == 0) map[i] = nv++;
    st = vp_mesh_alloc(m, nv, nt);
    if (st != VP_OK) { free(map); return st; }
    for (i = 0; i < dt->nvert; i++)
        if (map[i] != VP_DT_NONE) memcpy(m->xyz + 3 * (size_t)map[i], vp_dt_point(dt, i), 3 * sizeof(double));
    nt = 0;
    for (i = 0; i < slots; i++) {
        uint32_t v[3];
        int k;
        if (!vp_planner_facet(pl, i, v, NULL, NULL)) continue;
        for (k = 0; k < 3; k++) m->tri[3 * (size_t)nt + (size_t)k] = map[v[k]];
        nt++;
    }
    free(map);
    return vp_mesh_orient(m);
}
