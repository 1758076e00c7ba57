/* vp_gpiod — see vp_gpiod.h. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_gpiod.h"
#include "vp_status.h"

#ifdef VP_HAVE_GPIOD
#include <gpiod.h>

#define VP_GPIOD_CHIPS 4
#define VP_GPIOD_BULKS 8

typedef struct vp_gpiod_bulk {
    int chip, active_low, pull, output, requested;
    struct gpiod_line_bulk lines;
    unsigned offsets[GPIOD_LINE_BULK_MAX_LINES];
    uint32_t bits[GPIOD_LINE_BULK_MAX_LINES];   /* logical bits on each line */
} vp_gpiod_bulk_t;

struct vp_gpiod {
    struct gpiod_chip *chip[VP_GPIOD_CHIPS];
    char name[VP_GPIOD_CHIPS][VP_GPIO_CHIP_LEN];
    int nchips, nbulks;
    vp_gpiod_bulk_t bulk[VP_GPIOD_BULKS];
    uint32_t out;
    vp_rtclock_t clk;
};

static int vp_gpiod_chip(vp_gpiod_t *g, const char *name, char *err, size_t errlen)
{
    int i;
    for (i = 0; i < g->nchips; i++) if (!strcmp(g->name[i], name)) return i;
    if (g->nchips == VP_GPIOD_CHIPS) { snprintf(err, errlen, "gpiod: more than %d chips", VP_GPIOD_CHIPS); return VP_EINVAL; }
    g->chip[g->nchips] = gpiod_chip_open_lookup(name);
    if (!g->chip[g->nchips]) {
        snprintf(err, errlen, "gpiod: cannot open chip '%s': %s", name, strerror(errno));
        return errno == EACCES || errno == EPERM ? VP_EIO : VP_ENODEV;
    }
    snprintf(g->name[g->nchips], VP_GPIO_CHIP_LEN, "%s", name);
    return g->nchips++;
}

/* Adds logical bit `bit` on pin p to the bulk of its chip, polarity and direction. */
static int vp_gpiod_add(vp_gpiod_t *g, const vp_gpio_pin_t *p, int output, uint32_t bit, char *err, size_t errlen)
{
    vp_gpiod_bulk_t *b = NULL;
    struct gpiod_line *line;
    int c = vp_gpiod_chip(g, p->chip, err, errlen), i, k;
    if (c < 0) return c;
    /* a pin may carry several bits of one direction, never both directions */
    for (i = 0; i < g->nbulks; i++) {
        vp_gpiod_bulk_t *o = &g->bulk[i];
        if (o->chip != c) continue;
        for (k = 0; k < (int)o->lines.num_lines; k++) {
            if (o->offsets[k] != (unsigned)p->offset) continue;
            if (o->output != output || o->active_low != p->active_low) {
                snprintf(err, errlen, "gpiod: %s:%d used twice with different direction or polarity", p->chip, p->offset);
                return VP_EINVAL;
            }
            o->bits[k] |= bit;
            return VP_OK;
        }
    }
    for (i = 0; i < g->nbulks; i++)
        if (g->bulk[i].chip == c && g->bulk[i].output == output && g->bulk[i].active_low == p->active_low &&
            (output || g->bulk[i].pull == p->pull)) { b = &g->bulk[i]; break; }
    if (!b) {
        if (g->nbulks == VP_GPIOD_BULKS) { snprintf(err, errlen, "gpiod: too many line groups"); return VP_EINVAL; }
        b = &g->bulk[g->nbulks++];
        memset(b, 0, sizeof *b);
        b->chip = c;
        b->output = output;
        b->active_low = p->active_low;
        b->pull = output ? 0 : p->pull;
        gpiod_line_bulk_init(&b->lines);
    }
    if (b->lines.num_lines == GPIOD_LINE_BULK_MAX_LINES) { snprintf(err, errlen, "gpiod: too many lines"); return VP_EINVAL; }
    line = p->offset < 0 ? NULL : gpiod_chip_get_line(g->chip[c], (unsigned)p->offset);
    if (!line) {
        snprintf(err, errlen, "gpiod: %s has no line %d (it has %u)", p->chip, p->offset, gpiod_chip_num_lines(g->chip[c]));
        return VP_EINVAL;
    }
    b->offsets[b->lines.num_lines] = (unsigned)p->offset;
    b->bits[b->lines.num_lines] = bit;
    gpiod_line_bulk_add(&b->lines, line);
    return VP_OK;
}

static int vp_gpiod_request(vp_gpiod_t *g, vp_gpiod_bulk_t *b, const char *consumer, char *err, size_t errlen)
{
    struct gpiod_line_request_config rc;
    int zeros[GPIOD_LINE_BULK_MAX_LINES];
    unsigned k;
    memset(zeros, 0, sizeof zeros);
    rc.consumer = consumer;
    rc.request_type = b->output ? GPIOD_LINE_REQUEST_DIRECTION_OUTPUT : GPIOD_LINE_REQUEST_DIRECTION_INPUT;
    rc.flags = (b->active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0) |
               (b->pull == VP_PULL_UP ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP : 0) |
               (b->pull == VP_PULL_DOWN ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN : 0);
    if (gpiod_line_request_bulk(&b->lines, &rc, b->output ? zeros : NULL) == 0) { b->requested = 1; return VP_OK; }
    for (k = 0; k < b->lines.num_lines; k++) {
        struct gpiod_line *l = b->lines.lines[k];
        gpiod_line_update(l);
        if (gpiod_line_is_used(l)) {
            const char *who = gpiod_line_consumer(l);
            snprintf(err, errlen, "gpiod: %s:%u is busy (used by '%s')", g->name[b->chip], b->offsets[k], who ? who : "the kernel");
            return VP_EIO;
        }
    }
    snprintf(err, errlen, "gpiod: request of %u lines on %s refused: %s", b->lines.num_lines, g->name[b->chip], strerror(errno));
    return VP_EIO;
}

int vp_gpiod_open(const vp_gpiod_config_t *cfg, vp_gpiod_t **out, char *err, size_t errlen)
{
    vp_gpiod_t *g;
    int i, rc = VP_OK;
    if (!cfg || !out) return VP_EINVAL;
    *out = NULL;
    g = calloc(1, sizeof *g);
    if (!g) return VP_ENOMEM;
    vp_rt_init(&g->clk, cfg->spin_ns);
    for (i = 0; i < VP_IO_NOUT && rc == VP_OK; i++)
        if (cfg->out[i].chip[0]) rc = vp_gpiod_add(g, &cfg->out[i], 1, 1u << i, err, errlen);
    for (i = 0; i < VP_IO_NIN && rc == VP_OK; i++)
        if (cfg->in[i].chip[0]) rc = vp_gpiod_add(g, &cfg->in[i], 0, 1u << i, err, errlen);
    for (i = 0; i < g->nbulks && rc == VP_OK; i++)
        rc = vp_gpiod_request(g, &g->bulk[i], cfg->consumer ? cfg->consumer : "voroprobe", err, errlen);
    if (rc == VP_OK && cfg->rt_priority) rc = vp_rt_realtime(cfg->rt_priority, err, errlen);
    if (rc != VP_OK) { vp_gpiod_close(g); return rc; }
    *out = g;
    return VP_OK;
}

static int64_t vp_gpiod_now(void *ctx) { (void)ctx; return vp_rt_now(); }
static int vp_gpiod_wait(void *ctx, int64_t t) { return vp_rt_wait_until(&((vp_gpiod_t *)ctx)->clk, t); }

static int vp_gpiod_write(void *ctx, uint32_t mask, uint32_t values)
{
    vp_gpiod_t *g = ctx;
    int vals[GPIOD_LINE_BULK_MAX_LINES], i;
    unsigned k;
    g->out = (g->out & ~mask) | (values & mask);
    for (i = 0; i < g->nbulks; i++) {
        vp_gpiod_bulk_t *b = &g->bulk[i];
        uint32_t any = 0;
        if (!b->output || !b->requested) continue;
        for (k = 0; k < b->lines.num_lines; k++) { any |= b->bits[k]; vals[k] = (g->out & b->bits[k]) != 0; }
        if (!(any & mask)) continue;
        if (gpiod_line_set_value_bulk(&b->lines, vals) != 0) return VP_EIO;
    }
    return VP_OK;
}

static int vp_gpiod_read(void *ctx, uint32_t *in)
{
    vp_gpiod_t *g = ctx;
    int vals[GPIOD_LINE_BULK_MAX_LINES], i;
    unsigned k;
    *in = 0;
    for (i = 0; i < g->nbulks; i++) {
        vp_gpiod_bulk_t *b = &g->bulk[i];
        if (b->output || !b->requested) continue;
        if (gpiod_line_get_value_bulk(&b->lines, vals) != 0) return VP_EIO;
        for (k = 0; k < b->lines.num_lines; k++) if (vals[k] > 0) *in |= b->bits[k];
    }
    return VP_OK;
}

vp_io_t vp_gpiod_io(vp_gpiod_t *g)
{
    vp_io_t io;
    io.ctx = g;
    io.now = vp_gpiod_now;
    io.wait_until = vp_gpiod_wait;
    io.write = vp_gpiod_write;
    io.read = vp_gpiod_read;
    return io;
}

void vp_gpiod_stats(const vp_gpiod_t *g, vp_rt_stats_t *st) { *st = g->clk.st; }

void vp_gpiod_close(vp_gpiod_t *g)
{
    int i;
    if (!g) return;
    vp_gpiod_write(g, ~0u, 0);
    for (i = 0; i < g->nbulks; i++) if (g->bulk[i].requested) gpiod_line_release_bulk(&g->bulk[i].lines);
    for (i = 0; i < g->nchips; i++) gpiod_chip_close(g->chip[i]);
    free(g);
}

const char *vp_gpiod_version(void) { return gpiod_version_string(); }

#else /* no libgpiod */

struct vp_gpiod { int unused; };

int vp_gpiod_open(const vp_gpiod_config_t *cfg, vp_gpiod_t **out, char *err, size_t errlen)
{
    (void)cfg;
    if (out) *out = NULL;
    snprintf(err, errlen, "gpiod: built without libgpiod (install libgpiod-dev and rebuild)");
    return VP_ENODEV;
}

vp_io_t vp_gpiod_io(vp_gpiod_t *g)
{
    vp_io_t io;
    memset(&io, 0, sizeof io);
    io.ctx = g;
    return io;
}

void vp_gpiod_stats(const vp_gpiod_t *g, vp_rt_stats_t *st) { (void)g; memset(st, 0, sizeof *st); }
void vp_gpiod_close(vp_gpiod_t *g) { free(g); }
const char *vp_gpiod_version(void) { return NULL; }

#endif
