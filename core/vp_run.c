/* vp_run — see vp_run.h. */
#include <string.h>
#include "vp_run.h"

static double vp_run_clock(const vp_run_hooks_t *h)
{
    return h && h->clock ? h->clock(h->ctx) : 0.0;
}

int vp_run(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_run_hooks_t *hooks,
           unsigned long max_commands, vp_run_result_t *out)
{
    int (*after)(void *, const vp_cmd_t *, const vp_probe_result_t *) = hooks ? hooks->after : 0;
    void *hctx = hooks ? hooks->ctx : 0;
    int st = VP_OK;
    memset(out, 0, sizeof *out);
    for (;;) {
        vp_cmd_t cmd;
        vp_probe_result_t res;
        double c0 = vp_run_clock(hooks);
        int collided = 0;
        st = vp_planner_next(pl, &cmd);
        out->planner_seconds += vp_run_clock(hooks) - c0;
        if (st != VP_OK) break;
        if (cmd.kind == VP_CMD_DONE) {
            out->done = 1;
            if (after) st = after(hctx, &cmd, NULL);
            break;
        }
        if (cmd.kind == VP_CMD_MOVE) {
#ifndef VP_CORE_MCU
            double at = 0.0;
            int touched;
            st = dev->move(dev->ctx, &cmd, &collided);
            out->collisions += collided != 0;
            touched = st == VP_OK && dev->touched && dev->touched(dev->ctx, &at) == 1;
            res.hit = 1;
            res.dist = at;
            if (st == VP_OK && after) st = after(hctx, &cmd, touched ? &res : NULL);
            if (st == VP_OK && touched) {
                /* logged first; the planner learns where the head touched */
                out->contacts++;
                c0 = vp_run_clock(hooks);
                st = vp_planner_touch(pl, at);
                out->planner_seconds += vp_run_clock(hooks) - c0;
            }
#else /* a microcontroller core has no contact safety net (VP_PL_CONTACTS) */
            st = dev->move(dev->ctx, &cmd, &collided);
            out->collisions += collided != 0;
            if (st == VP_OK && after) st = after(hctx, &cmd, NULL);
#endif
            if (st != VP_OK) break;
        } else {
            int hst = VP_OK;
            st = dev->probe(dev->ctx, &cmd, &res);
            if (st != VP_OK) break;
            /* logged before the planner judges it */
            if (after) hst = after(hctx, &cmd, &res);
            c0 = vp_run_clock(hooks);
            st = vp_planner_feed(pl, &res);
            out->planner_seconds += vp_run_clock(hooks) - c0;
#ifndef VP_CORE_MCU
            if (st == VP_OK && dev->rays) {
                /* a line laser: the frame's other rays, each logged, then fed (also when the hook
                 * asked to pause after the PROBE: a frame is never split) */
                vp_cmd_t ray;
                unsigned i;
                int got;
                for (i = 0; st == VP_OK; i++) {
                    ray = cmd;
                    ray.kind = VP_CMD_RAY;
                    got = dev->rays(dev->ctx, &cmd, i, &ray, &res);
                    if (got < 0) { st = got; break; }   /* the device failed */
                    if (got != 1) break;                 /* the frame has no more */
                    if (after) st = after(hctx, &ray, &res);
                    if (st != VP_OK) break;
                    c0 = vp_run_clock(hooks);
                    st = vp_planner_feed_ray(pl, ray.dir, &res);
                    out->planner_seconds += vp_run_clock(hooks) - c0;
                }
            }
#endif
            if (st == VP_OK) st = hst;
            if (st != VP_OK) break;
        }
        out->commands++;
        if (hooks && hooks->progress) hooks->progress(hctx, pl, out->commands);
        if (max_commands && out->commands >= max_commands) break;
    }
    out->status = st;
    return st;
}
