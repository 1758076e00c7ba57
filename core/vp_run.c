/* vp_run — see vp_run.h. */
#include <string.h>
#include "vp_run.h"

static double vp_run_clock(const vp_run_hooks_t *h)
{
    return h && h->clock ? h->clock(h->ctx) : 0.0;
}

/* A miss must be seen: where the device's misses mean only that its camera found no spot, a miss
 * whose spot may be hidden from the camera by what is not known free (the mesh found so far, the
 * space still unknown: vp_planner_spot_hidden) proves nothing and is fed, and logged, as
 * unreadable (VP_PROBE_TOO_CLOSE). */
static void vp_run_sight(const vp_planner_t *pl, const vp_device_ops_t *dev, const vp_run_hooks_t *hooks,
                         vp_run_result_t *out, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    double cam[3], c0;
    if (res->hit != 0 || !dev->sight || dev->sight(dev->ctx, cmd, cam) != 1) return;
    c0 = vp_run_clock(hooks);
    if (vp_planner_spot_hidden(pl, cmd->from, cmd->dir, cmd->range, cam) == 1) {
        res->hit = VP_PROBE_TOO_CLOSE;
        res->dist = 0.0;
        out->unseen_misses++;
    }
    out->planner_seconds += vp_run_clock(hooks) - c0;
}

#ifndef VP_CORE_MCU
/* The head's contact switch stopped MOVE `move` at `at` (logged already): the planner learns
 * where (vp_planner_touch_path: an ordinary touch when it is the last command given). */
static int vp_run_touch(vp_planner_t *pl, const vp_run_hooks_t *hooks, vp_run_result_t *out, const vp_cmd_t *move,
                        double at)
{
    double c0 = vp_run_clock(hooks);
    int st;
    out->contacts++;
    st = vp_planner_touch_path(pl, move, at);
    out->planner_seconds += vp_run_clock(hooks) - c0;
    return st;
}

/* A MOVE and the MOVEs the planner gives after it, up to VP_DEV_PATH and never past
 * max_commands, made as one path (dev->move_path): the planner needs nothing back from a MOVE
 * made whole, so it can say the route ahead before the head moves. The command that ends the
 * run of MOVEs is kept in *next (*held 1) for the loop. Each MOVE made is logged (hooks->after)
 * and counted as when made alone; one the hook would stop after is followed by the others the
 * path made, logged too (the head went there). */
static int vp_run_path(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_run_hooks_t *hooks,
                       unsigned long max_commands, vp_run_result_t *out, const vp_cmd_t *first,
                       vp_cmd_t *next, int *held)
{
    vp_cmd_t path[VP_DEV_PATH];
    int collided[VP_DEV_PATH], n = 1, off = 0, done, i, st = VP_OK, pst = VP_OK, hst = VP_OK;
    path[0] = *first;
    while (n < VP_DEV_PATH && !(max_commands && out->commands + (unsigned long)n >= max_commands)) {
        double c0 = vp_run_clock(hooks);
        pst = vp_planner_next(pl, &path[n]);
        out->planner_seconds += vp_run_clock(hooks) - c0;
        if (pst != VP_OK) break;
        if (path[n].kind != VP_CMD_MOVE) {
            *next = path[n];
            *held = 1;
            break;
        }
        n++;
    }
    while (off < n && st == VP_OK) {
        vp_probe_result_t touch;
        int touched = 0;
        memset(collided + off, 0, (size_t)(n - off) * sizeof collided[0]);
        done = 0;
        st = dev->move_path(dev->ctx, path + off, n - off, collided + off, &done);
        if (done < 0 || done > n - off) done = 0;
        if (st == VP_OK && done == 0) st = VP_ESTATE;   /* a device that makes no progress */
        /* the head's contact switch stopped the last MOVE made: the path ends there */
        memset(&touch, 0, sizeof touch);
        touch.hit = 1;
        if (st == VP_OK && dev->touched) touched = dev->touched(dev->ctx, &touch.dist) == 1;
        for (i = off; i < off + done; i++) {
            int h = VP_OK, last = touched && i + 1 == off + done;
            out->collisions += collided[i] != 0;
            if (hooks && hooks->after) h = hooks->after(hooks->ctx, &path[i], last ? &touch : NULL);
            if (hst != VP_OK) continue;        /* logged, not counted: the run stops */
            hst = h;
            if (hst != VP_OK || last) continue; /* a touched MOVE counts once the planner took it */
            out->commands++;
            if (hooks && hooks->progress) hooks->progress(hooks->ctx, pl, out->commands);
        }
        off += done;
        if (touched) {
            /* as a MOVE made alone: logged first, then the planner learns where the head touched */
            *held = 0;
            if (hst != VP_OK) return hst;
            if ((st = vp_run_touch(pl, hooks, out, &path[off - 1], touch.dist)) != VP_OK) return st;
            out->commands++;
            if (hooks && hooks->progress) hooks->progress(hooks->ctx, pl, out->commands);
            return VP_OK;
        }
        if (hst != VP_OK && st == VP_OK) break;
    }
    if (st != VP_OK) return st;
    if (hst != VP_OK) return hst;
    if (off < n) return VP_ESTATE;
    return pst;
}
#endif

int vp_run(vp_planner_t *pl, const vp_device_ops_t *dev, const vp_run_hooks_t *hooks,
           unsigned long max_commands, vp_run_result_t *out)
{
    int (*after)(void *, const vp_cmd_t *, const vp_probe_result_t *) = hooks ? hooks->after : 0;
    void *hctx = hooks ? hooks->ctx : 0;
    int st = VP_OK;
#ifndef VP_CORE_MCU
    vp_cmd_t next;
    int held = 0;
#endif
    memset(out, 0, sizeof *out);
    for (;;) {
        vp_cmd_t cmd;
        vp_probe_result_t res;
        double c0 = vp_run_clock(hooks);
        int collided = 0;
#ifndef VP_CORE_MCU
        if (held) {
            cmd = next;      /* the command that ended a path */
            held = 0;
        } else
#endif
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
            if (dev->move_path) {
                st = vp_run_path(pl, dev, hooks, max_commands, out, &cmd, &next, &held);
                if (st != VP_OK || (max_commands && out->commands >= max_commands)) break;
                continue;
            }
            st = dev->move(dev->ctx, &cmd, &collided);
            out->collisions += collided != 0;
            touched = st == VP_OK && dev->touched && dev->touched(dev->ctx, &at) == 1;
            res.hit = 1;
            res.dist = at;
            if (st == VP_OK && after) st = after(hctx, &cmd, touched ? &res : NULL);
            if (st == VP_OK && touched) st = vp_run_touch(pl, hooks, out, &cmd, at);   /* logged first */
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
            if (!vp_probe_result_valid(&res)) { st = VP_EINVAL; break; } /* never logged: unreadable */
            vp_run_sight(pl, dev, hooks, out, &cmd, &res);
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
                    if (!vp_probe_result_valid(&res)) { st = VP_EINVAL; break; }
                    vp_run_sight(pl, dev, hooks, out, &ray, &res);
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
