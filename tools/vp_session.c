#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_session.h"

double vp_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double vp_wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress_line(FILE *f, const vp_planner_t *pl, int final)
{
    vp_planner_stats_t st;
    vp_planner_get_stats(pl, &st);
    fprintf(f, "\r  probes %-9llu vertices %-7u facets %-7u bad balls %-6u largest ball %.4g (eps %.4g)%s",
            (unsigned long long)st.probes, vp_planner_dt(pl)->ninserted, vp_planner_num_facets(pl),
            st.bad_balls, st.bad_balls ? st.max_ball : 0.0, pl->cfg.eps, final ? "\n" : "");
    fflush(f);
}

int vp_session_run(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_session_hooks_t *hooks,
                   unsigned long max_commands, FILE *progress, vp_session_result_t *out)
{
    double w0 = vp_wall_seconds(), next_report = w0 + 0.5, cpu = 0.0;
    unsigned long n = 0;
    int st = VP_OK;
    memset(out, 0, sizeof *out);
    for (;;) {
        vp_cmd_t cmd;
        vp_probe_result_t res;
        double c0 = vp_cpu_seconds();
        int collided = 0;
        st = vp_planner_next(pl, &cmd);
        cpu += vp_cpu_seconds() - c0;
        if (st != VP_OK) break;
        if (cmd.kind == VP_CMD_DONE) {
            if (hooks && hooks->after) st = hooks->after(hooks->ctx, &cmd, NULL);
            break;
        }
        if (cmd.kind == VP_CMD_MOVE) {
            st = dev->move(dev->ctx, &cmd, &collided);
            out->collisions += collided != 0;
            if (st == VP_OK && hooks && hooks->after) st = hooks->after(hooks->ctx, &cmd, NULL);
            if (st != VP_OK) break;
        } else {
            st = dev->probe(dev->ctx, &cmd, &res);
            if (st != VP_OK) break;
            c0 = vp_cpu_seconds();
            st = vp_planner_feed(pl, &res);
            cpu += vp_cpu_seconds() - c0;
            if (st != VP_OK) break;
            if (hooks && hooks->after && (st = hooks->after(hooks->ctx, &cmd, &res)) != VP_OK) break;
        }
        if (max_commands && ++n >= max_commands) break;
        if (progress && (n & 1023u) == 0 && vp_wall_seconds() > next_report) {
            progress_line(progress, pl, 0);
            next_report = vp_wall_seconds() + 0.5;
        }
    }
    if (progress) progress_line(progress, pl, 1);
    out->status = st;
    out->planner_seconds = cpu;
    out->total_seconds = vp_wall_seconds() - w0;
    return st;
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
    return VP_OK;
}
