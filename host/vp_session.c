#include <stdlib.h>
#include <string.h>
#include "vp_rtclock.h"
#include "vp_run.h"
#include "vp_session.h"

static void progress_line(FILE *f, const vp_planner_t *pl, int final)
{
    vp_planner_stats_t st;
    vp_planner_get_stats(pl, &st);
    fprintf(f, "\r  probes %-9llu vertices %-7u facets %-7u bad balls %-6u largest ball %.4g (eps %.4g)%s",
            (unsigned long long)st.probes, vp_planner_dt(pl)->ninserted, vp_planner_num_facets(pl),
            st.bad_balls, st.bad_balls ? st.max_ball : 0.0, pl->cfg.eps, final ? "\n" : "");
    fflush(f);
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
    double next_report;
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
    if (c->progress && (commands & 1023u) == 0 && vp_progress_due(&c->next_report)) progress_line(c->progress, pl, 0);
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
    c.next_report = w0 + 0.5;
    rh.ctx = &c;
    rh.after = vp_session_after;
    rh.clock = vp_session_clock;
    rh.progress = vp_session_progress;
    vp_run(pl, dev, &rh, max_commands, &r);
    if (progress) progress_line(progress, pl, 1);
    memset(out, 0, sizeof *out);
    out->status = r.status;
    out->collisions = r.collisions;
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

/* Orients every connected component consistently (breadth-first across shared edges) and
 * outward (positive volume). The planner orients each facet by the side its probe came from;
 * this makes the file right even where a probe came at a grazing angle. Returns the number of
 * facets flipped against the planner's choice through *flipped (may be NULL). */
typedef struct { uint32_t a, b, f; } half_t;

static int cmp_half(const void *x, const void *y)
{
    const half_t *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return p->f < q->f ? -1 : p->f > q->f;
}

int vp_mesh_orient(vp_mesh_t *m)
{
    size_t nt = m->nt, i, nh = 3 * nt;
    half_t *h = malloc((nh + 1) * sizeof *h);
    uint32_t *queue = malloc((nt + 1) * sizeof *queue), *comp = malloc((nt + 1) * sizeof *comp);
    unsigned char *flip = calloc(nt + 1, 1);
    uint32_t ncomp = 0;
    if (!h || !queue || !comp || !flip) { free(h); free(queue); free(comp); free(flip); return VP_ENOMEM; }
    for (i = 0; i < nt; i++) {
        int e;
        for (e = 0; e < 3; e++) {
            uint32_t a = m->tri[3 * i + (size_t)e], b = m->tri[3 * i + (size_t)((e + 1) % 3)];
            h[3 * i + (size_t)e].a = a < b ? a : b;
            h[3 * i + (size_t)e].b = a < b ? b : a;
            h[3 * i + (size_t)e].f = (uint32_t)i;
        }
        comp[i] = UINT32_MAX;
    }
    qsort(h, nh, sizeof *h, cmp_half);
    for (i = 0; i < nt; i++) {
        size_t qh = 0, qt = 0;
        double vol = 0.0;
        size_t j;
        if (comp[i] != UINT32_MAX) continue;
        comp[i] = ncomp;
        queue[qt++] = (uint32_t)i;
        while (qh < qt) {
            uint32_t f = queue[qh++];
            int e;
            for (e = 0; e < 3; e++) {
                uint32_t a = m->tri[3 * (size_t)f + (size_t)e], b = m->tri[3 * (size_t)f + (size_t)((e + 1) % 3)];
                half_t key;
                size_t lo = 0, hi = nh;
                if (flip[f]) { uint32_t t = a; a = b; b = t; }
                key.a = a < b ? a : b; key.b = a < b ? b : a; key.f = 0;
                while (lo < hi) { size_t mid = (lo + hi) / 2; if (cmp_half(&h[mid], &key) < 0) lo = mid + 1; else hi = mid; }
                /* only a manifold edge (exactly two faces) carries orientation across */
                if (lo + 1 < nh && h[lo].a == key.a && h[lo].b == key.b && h[lo + 1].a == key.a &&
                    h[lo + 1].b == key.b && !(lo + 2 < nh && h[lo + 2].a == key.a && h[lo + 2].b == key.b)) {
                    uint32_t g = h[lo].f == f ? h[lo + 1].f : h[lo].f;
                    int k, same = 0;
                    if (comp[g] != UINT32_MAX) continue;
                    /* g must traverse the edge b -> a */
                    for (k = 0; k < 3; k++)
                        if (m->tri[3 * (size_t)g + (size_t)k] == a && m->tri[3 * (size_t)g + (size_t)((k + 1) % 3)] == b) same = 1;
                    flip[g] = (unsigned char)same;
                    comp[g] = ncomp;
                    queue[qt++] = g;
                }
            }
        }
        for (j = 0; j < qt; j++) {
            const uint32_t *t = m->tri + 3 * (size_t)queue[j];
            const double *a = m->xyz + 3 * (size_t)t[0], *b = m->xyz + 3 * (size_t)t[flip[queue[j]] ? 2 : 1],
                         *c = m->xyz + 3 * (size_t)t[flip[queue[j]] ? 1 : 2];
            vol += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                   a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
        if (vol < 0.0)
            for (j = 0; j < qt; j++) flip[queue[j]] ^= 1;
        ncomp++;
    }
    for (i = 0; i < nt; i++)
        if (flip[i]) {
            uint32_t t = m->tri[3 * i + 1];
            m->tri[3 * i + 1] = m->tri[3 * i + 2];
            m->tri[3 * i + 2] = t;
        }
    free(h); free(queue); free(comp); free(flip);
    return VP_OK;
}
