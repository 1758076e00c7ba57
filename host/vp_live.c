/* vp_live — the live view: libmicrohttpd, server-sent events, a scan loop that never waits. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_live.h"
#include "vp_rtclock.h"
#include "vp_status.h"

#ifdef VP_HAVE_MHD
#include <errno.h>
#include <pthread.h>
#include <sys/types.h>
#include <time.h>
#include <microhttpd.h>

#define CHUNK 4096                 /* samples per chunk */
#define MAX_CHUNKS 65536           /* 268M samples */
#define SAMPLES_PER_EVENT 8192
#define PUBLISH_EVERY 64           /* commands between looks at the clock */
#define PUBLISH_PERIOD 0.05        /* seconds between publications */
#define POLL_PERIOD 0.05           /* a connection with nothing new looks again after this */
#define STATUS_PERIOD 0.2          /* seconds between status events of one connection */

typedef struct frame {
    float *tri;                    /* 9 floats per facet: the facet's three corners */
    uint32_t nt;
} frame_t;

typedef struct status {
    char state[32];
    unsigned long commands;
    uint64_t probes, hits, samples;
    uint32_t vertices, facets;
} status_t;

struct vp_live {
    struct MHD_Daemon *d;
    const char *page;
    size_t page_len;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    /* the scan thread's own */
    const vp_planner_t *pl;
    vp_session_hooks_t inner;
    float *chunk[MAX_CHUNKS];
    uint64_t wcount;
    unsigned long commands;
    frame_t *pending;
    unsigned long frames;
    double frame_max, frame_total, next_publish;
    /* shared, under mu */
    uint64_t pcount;
    frame_t *frame;
    uint32_t frame_seq;
    status_t status;
    uint32_t status_seq;
    int want_frame, final, quitting;
    int clients, behind;           /* connections open; of which have not ended their stream */
    unsigned long finals;          /* connections whose stream reached its end (the final state) */
    unsigned long connections;     /* ever */
};

typedef struct conn {
    vp_live_t *lv;
    char *buf;
    size_t len, off, cap;
    uint64_t cursor;
    uint32_t frame_seq, status_seq;
    double last_status;
    int final_sent, ended;
} conn_t;

/* ---------- the scan thread ---------- */

static void frame_free(frame_t *f)
{
    if (f) { free(f->tri); free(f); }
}

static frame_t *frame_build(const vp_planner_t *pl)
{
    const vp_dt_t *dt = vp_planner_dt(pl);
    uint32_t s, n = 0, slots = vp_planner_facet_slots(pl), nf = vp_planner_num_facets(pl);
    frame_t *f = malloc(sizeof *f);
    if (!f) return NULL;
    f->tri = malloc(((size_t)nf + 1) * 9 * sizeof *f->tri);
    if (!f->tri) { free(f); return NULL; }
    for (s = 0; s < slots && n < nf; s++) {
        uint32_t v[3];
        int k, q;
        if (!vp_planner_facet(pl, s, v, NULL, NULL)) continue;
        for (k = 0; k < 3; k++)
            for (q = 0; q < 3; q++) f->tri[9 * (size_t)n + 3 * k + q] = (float)vp_dt_point(dt, v[k])[q];
        n++;
    }
    f->nt = n;
    return f;
}

static void fill_status(vp_live_t *lv, status_t *s, const char *state)
{
    vp_planner_stats_t st;
    vp_planner_get_stats(lv->pl, &st);
    snprintf(s->state, sizeof s->state, "%s", state);
    s->commands = lv->commands;
    s->probes = st.probes;
    s->hits = st.hits;
    s->samples = lv->wcount;
    s->vertices = vp_planner_dt(lv->pl)->ninserted;
    s->facets = vp_planner_num_facets(lv->pl);
}

/* Publishes what the scan has, if the lock is free at once; else next time. No signal to the
 * connections (a system call in the scan loop): they look again every POLL_PERIOD. */
static void publish(vp_live_t *lv)
{
    if (pthread_mutex_trylock(&lv->mu) != 0) return;
    lv->pcount = lv->wcount;
    fill_status(lv, &lv->status, "running");
    lv->status_seq++;
    if (lv->pending) {
        frame_t *old = lv->frame;
        lv->frame = lv->pending;
        lv->pending = NULL;
        lv->frame_seq++;
        lv->want_frame = 0;
        frame_free(old);
    }
    pthread_mutex_unlock(&lv->mu);
}

static int live_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    vp_live_t *lv = ctx;
    int st = lv->inner.after ? lv->inner.after(lv->inner.ctx, cmd, res) : VP_OK;
    if ((cmd->kind == VP_CMD_PROBE || cmd->kind == VP_CMD_RAY) && res && res->hit == 1 && lv->wcount < (uint64_t)CHUNK * MAX_CHUNKS) {
        uint64_t i = lv->wcount;
        float *c = lv->chunk[i / CHUNK];
        int k;
        if (!c) c = lv->chunk[i / CHUNK] = malloc(CHUNK * 3 * sizeof *c);
        if (c) {
            for (k = 0; k < 3; k++) c[3 * (i % CHUNK) + (uint64_t)k] = (float)(cmd->from[k] + res->dist * cmd->dir[k]);
            lv->wcount++;
        }
    }
    lv->commands++;
    if ((lv->commands % PUBLISH_EVERY) == 0 && vp_rt_seconds() >= lv->next_publish) {
        lv->next_publish = vp_rt_seconds() + PUBLISH_PERIOD;
        /* a frame only when a page has taken the last one (read without the lock: a stale
         * answer costs one frame more or one later) */
        if (!lv->pending && lv->want_frame) {
            double t0 = vp_rt_seconds(), dt;
            lv->pending = frame_build(lv->pl);
            dt = vp_rt_seconds() - t0;
            lv->frames++;
            lv->frame_total += dt;
            if (dt > lv->frame_max) lv->frame_max = dt;
        }
        publish(lv);
    }
    return st;
}

/* ---------- the server's threads ---------- */

static void wait_a_little(vp_live_t *lv, double seconds)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    ts.tv_nsec += (long)(seconds * 1e9);
    ts.tv_sec += ts.tv_nsec / 1000000000L;
    ts.tv_nsec %= 1000000000L;
    pthread_cond_timedwait(&lv->cv, &lv->mu, &ts);
}

static int reserve(conn_t *c, size_t n)
{
    if (c->len + n + 1 > c->cap) {
        size_t cap = (c->len + n + 1) * 2;
        char *b = realloc(c->buf, cap);
        if (!b) return -1;
        c->buf = b;
        c->cap = cap;
    }
    return 0;
}

static int put(conn_t *c, const char *s, size_t n)
{
    if (reserve(c, n)) return -1;
    memcpy(c->buf + c->len, s, n);
    c->len += n;
    c->buf[c->len] = 0;
    return 0;
}

static int putf_status(conn_t *c, const status_t *s, int final)
{
    char t[400];
    int n = snprintf(t, sizeof t, "event: status\ndata: {\"state\":\"%s\",\"final\":%s,\"commands\":%lu,\"probes\":%llu,"
                     "\"hits\":%llu,\"samples\":%llu,\"vertices\":%u,\"facets\":%u}\n\n", s->state, final ? "true" : "false",
                     s->commands, (unsigned long long)s->probes, (unsigned long long)s->hits,
                     (unsigned long long)s->samples, s->vertices, s->facets);
    return put(c, t, (size_t)n);
}

/* floats as base64 of their little-endian bytes */
static int put_floats(conn_t *c, const float *v, size_t n)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t nb = 4 * n, i, o = 0, need = (nb + 2) / 3 * 4;
    const unsigned char *b;
    unsigned char *le;
    char *dst;
    if (reserve(c, need)) return -1;
    le = malloc(nb + 3);
    if (!le) return -1;
    for (i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &v[i], 4);
        le[4 * i] = (unsigned char)u; le[4 * i + 1] = (unsigned char)(u >> 8);
        le[4 * i + 2] = (unsigned char)(u >> 16); le[4 * i + 3] = (unsigned char)(u >> 24);
    }
    le[nb] = le[nb + 1] = le[nb + 2] = 0;
    b = le;
    dst = c->buf + c->len;
    for (i = 0; i < nb; i += 3) {
        dst[o++] = tab[b[i] >> 2];
        dst[o++] = tab[((b[i] & 3) << 4) | (b[i + 1] >> 4)];
        dst[o++] = i + 1 < nb ? tab[((b[i + 1] & 15) << 2) | (b[i + 2] >> 6)] : '=';
        dst[o++] = i + 2 < nb ? tab[b[i + 2] & 63] : '=';
    }
    c->len += o;
    c->buf[c->len] = 0;
    free(le);
    return 0;
}

/* The next event of one connection into c->buf: 0, or -1 at the end of the stream. */
static int next_event(conn_t *c)
{
    vp_live_t *lv = c->lv;
    double now = vp_rt_seconds();
    c->len = c->off = 0;
    pthread_mutex_lock(&lv->mu);
    if (!lv->quitting && c->cursor == lv->pcount && c->frame_seq == lv->frame_seq &&
        (c->status_seq == lv->status_seq || now - c->last_status < STATUS_PERIOD) && !lv->final)
        wait_a_little(lv, POLL_PERIOD);
    if (lv->quitting || c->ended) { pthread_mutex_unlock(&lv->mu); return -1; }
    if (c->cursor < lv->pcount) {
        /* samples below pcount never change: copied after the lock */
        uint64_t from = c->cursor, to = lv->pcount;
        char head[80];
        int n;
        pthread_mutex_unlock(&lv->mu);
        if (to - from > SAMPLES_PER_EVENT) to = from + SAMPLES_PER_EVENT;
        n = snprintf(head, sizeof head, "event: samples\ndata: {\"from\":%llu,\"n\":%llu,\"p\":\"",
                     (unsigned long long)from, (unsigned long long)(to - from));
        if (put(c, head, (size_t)n)) return -1;
        while (from < to) {
            uint64_t end = (from / CHUNK + 1) * CHUNK;
            if (end > to) end = to;
            if (put_floats(c, lv->chunk[from / CHUNK] + 3 * (from % CHUNK), 3 * (size_t)(end - from))) return -1;
            from = end;
        }
        c->cursor = to;
        return put(c, "\"}\n\n", 4);
    }
    if (c->frame_seq != lv->frame_seq && lv->frame) {
        char head[80];
        int n = snprintf(head, sizeof head, "event: mesh\ndata: {\"seq\":%u,\"nt\":%u,\"tri\":\"", lv->frame_seq, lv->frame->nt);
        int bad = put(c, head, (size_t)n) || put_floats(c, lv->frame->tri, 9 * (size_t)lv->frame->nt);
        c->frame_seq = lv->frame_seq;
        pthread_mutex_unlock(&lv->mu);
        return bad || put(c, "\"}\n\n", 4) ? -1 : 0;
    }
    if (c->frame_seq == lv->frame_seq) lv->want_frame = 1;
    if (lv->final) {
        /* everything sent: the final counts, then the end */
        status_t s = lv->status;
        if (c->final_sent) { c->ended = 1; pthread_mutex_unlock(&lv->mu); return put(c, "event: end\ndata: {}\n\n", 21); }
        c->final_sent = 1;
        pthread_mutex_unlock(&lv->mu);
        return putf_status(c, &s, 1);
    }
    if (c->status_seq != lv->status_seq && now - c->last_status >= STATUS_PERIOD) {
        status_t s = lv->status;
        c->status_seq = lv->status_seq;
        c->last_status = now;
        pthread_mutex_unlock(&lv->mu);
        return putf_status(c, &s, 0);
    }
    pthread_mutex_unlock(&lv->mu);
    return put(c, ": waiting\n\n", 11);
}

static ssize_t sse_read(void *cls, uint64_t pos, char *out, size_t max)
{
    conn_t *c = cls;
    size_t n;
    (void)pos;
    if (c->off == c->len && next_event(c) < 0) return MHD_CONTENT_READER_END_OF_STREAM;
    n = c->len - c->off;
    if (n > max) n = max;
    memcpy(out, c->buf + c->off, n);
    c->off += n;
    return (ssize_t)n;
}

static void sse_free(void *cls)
{
    conn_t *c = cls;
    vp_live_t *lv = c->lv;
    pthread_mutex_lock(&lv->mu);
    lv->clients--;
    lv->behind--;
    if (c->ended) lv->finals++;   /* the stream was handed over to its end */
    pthread_cond_broadcast(&lv->cv);
    pthread_mutex_unlock(&lv->mu);
    free(c->buf);
    free(c);
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *con, const char *url, const char *method,
                                  const char *version, const char *upload, size_t *upload_size, void **con_cls)
{
    vp_live_t *lv = cls;
    struct MHD_Response *r;
    enum MHD_Result ret;
    (void)version; (void)upload; (void)upload_size; (void)con_cls;
    if (strcmp(method, "GET") && strcmp(method, "HEAD")) return MHD_NO;
    if (!strcmp(url, "/events")) {
        conn_t *c = calloc(1, sizeof *c);
        if (!c) return MHD_NO;
        c->lv = lv;
        c->frame_seq = 0;
        pthread_mutex_lock(&lv->mu);
        lv->clients++;
        lv->behind++;
        lv->connections++;
        lv->want_frame = 1;
        c->status_seq = lv->status_seq - 1;
        pthread_cond_broadcast(&lv->cv);
        pthread_mutex_unlock(&lv->mu);
        r = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 64 * 1024, sse_read, c, sse_free);
        if (!r) { sse_free(c); return MHD_NO; }
        MHD_add_response_header(r, "Content-Type", "text/event-stream");
        MHD_add_response_header(r, "Cache-Control", "no-cache");
    } else if (!strcmp(url, "/")) {
        r = MHD_create_response_from_buffer(lv->page_len, (void *)lv->page, MHD_RESPMEM_PERSISTENT);
        if (!r) return MHD_NO;
        MHD_add_response_header(r, "Content-Type", "text/html; charset=utf-8");
    } else {
        static const char nf[] = "not found\n";
        r = MHD_create_response_from_buffer(sizeof nf - 1, (void *)nf, MHD_RESPMEM_PERSISTENT);
        if (!r) return MHD_NO;
        ret = MHD_queue_response(con, MHD_HTTP_NOT_FOUND, r);
        MHD_destroy_response(r);
        return ret;
    }
    ret = MHD_queue_response(con, MHD_HTTP_OK, r);
    MHD_destroy_response(r);
    return ret;
}

int vp_live_start(vp_live_t **out, unsigned port, const char *page, size_t len, char *err, size_t errlen)
{
    vp_live_t *lv = calloc(1, sizeof *lv);
    *out = NULL;
    if (!lv) { snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    if (port == 0 || port > 65535) { free(lv); snprintf(err, errlen, "--serve: port %u is not 1..65535", port); return VP_EINVAL; }
    lv->page = page;
    lv->page_len = len;
    pthread_mutex_init(&lv->mu, NULL);
    pthread_cond_init(&lv->cv, NULL);
    lv->d = MHD_start_daemon(MHD_USE_THREAD_PER_CONNECTION | MHD_USE_INTERNAL_POLLING_THREAD, (uint16_t)port, NULL, NULL,
                             on_request, lv, MHD_OPTION_CONNECTION_LIMIT, 32u, MHD_OPTION_END);
    if (!lv->d) {
        snprintf(err, errlen, "--serve: cannot serve on port %u (in use, or not allowed)", port);
        pthread_cond_destroy(&lv->cv);
        pthread_mutex_destroy(&lv->mu);
        free(lv);
        return VP_EIO;
    }
    *out = lv;
    return VP_OK;
}

void vp_live_attach(vp_live_t *lv, const vp_planner_t *pl, const vp_session_hooks_t *inner, vp_session_hooks_t *hooks)
{
    lv->pl = pl;
    if (inner) lv->inner = *inner;
    else memset(&lv->inner, 0, sizeof lv->inner);
    hooks->ctx = lv;
    hooks->after = live_after;
}

int vp_live_wait_client(vp_live_t *lv, double seconds)
{
    double end = vp_rt_seconds() + seconds;
    int got;
    pthread_mutex_lock(&lv->mu);
    while (lv->connections == 0 && vp_rt_seconds() < end) wait_a_little(lv, 0.1);
    got = lv->connections > 0;
    pthread_mutex_unlock(&lv->mu);
    return got;
}

void vp_live_finish(vp_live_t *lv, const char *state, const vp_mesh_t *mesh, double linger)
{
    frame_t *f = malloc(sizeof *f);
    double end = vp_rt_seconds() + linger;
    size_t i;
    if (f) {
        f->tri = malloc((mesh->nt + 1) * 9 * sizeof *f->tri);
        if (!f->tri) { free(f); f = NULL; }
    }
    if (f) {
        for (i = 0; i < 9 * mesh->nt; i++) f->tri[i] = (float)mesh->xyz[3 * (size_t)mesh->tri[i / 3] + i % 3];
        f->nt = (uint32_t)mesh->nt;
    }
    pthread_mutex_lock(&lv->mu);
    frame_free(lv->pending);
    lv->pending = NULL;
    if (f) { frame_free(lv->frame); lv->frame = f; lv->frame_seq++; }
    lv->pcount = lv->wcount;
    fill_status(lv, &lv->status, state);
    lv->status.vertices = (uint32_t)mesh->nv;   /* the final mesh's, as sim prints them */
    lv->status.facets = (uint32_t)mesh->nt;
    lv->status_seq++;
    lv->final = 1;
    pthread_cond_broadcast(&lv->cv);
    /* a page that connected once gets the end, even across a reconnection */
    while (vp_rt_seconds() < end && (lv->behind > 0 || (lv->connections > 0 && lv->finals == 0))) wait_a_little(lv, 0.1);
    pthread_mutex_unlock(&lv->mu);
}

void vp_live_stats(const vp_live_t *lv, unsigned long *frames, double *max_frame_seconds, double *total_frame_seconds)
{
    *frames = lv->frames;
    *max_frame_seconds = lv->frame_max;
    *total_frame_seconds = lv->frame_total;
}

void vp_live_stop(vp_live_t *lv)
{
    uint64_t i;
    if (!lv) return;
    pthread_mutex_lock(&lv->mu);
    lv->quitting = 1;
    pthread_cond_broadcast(&lv->cv);
    pthread_mutex_unlock(&lv->mu);
    MHD_stop_daemon(lv->d);
    for (i = 0; i < MAX_CHUNKS && lv->chunk[i]; i++) free(lv->chunk[i]);
    frame_free(lv->frame);
    frame_free(lv->pending);
    pthread_cond_destroy(&lv->cv);
    pthread_mutex_destroy(&lv->mu);
    free(lv);
}

#else /* built without libmicrohttpd */

struct vp_live { int unused; };

int vp_live_start(vp_live_t **out, unsigned port, const char *page, size_t len, char *err, size_t errlen)
{
    (void)port; (void)page; (void)len;
    *out = NULL;
    snprintf(err, errlen, "--serve: this voroprobe was built without libmicrohttpd (libmicrohttpd-dev)");
    return VP_ENODEV;
}
void vp_live_attach(vp_live_t *lv, const vp_planner_t *pl, const vp_session_hooks_t *inner, vp_session_hooks_t *hooks)
{
    (void)lv; (void)pl; (void)inner; (void)hooks;
}
int vp_live_wait_client(vp_live_t *lv, double seconds) { (void)lv; (void)seconds; return 0; }
void vp_live_finish(vp_live_t *lv, const char *state, const vp_mesh_t *mesh, double linger)
{
    (void)lv; (void)state; (void)mesh; (void)linger;
}
void vp_live_stats(const vp_live_t *lv, unsigned long *frames, double *max_frame_seconds, double *total_frame_seconds)
{
    (void)lv;
    *frames = 0;
    *max_frame_seconds = *total_frame_seconds = 0.0;
}
void vp_live_stop(vp_live_t *lv) { (void)lv; }

#endif
