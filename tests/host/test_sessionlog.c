/* Session logs end to end, in-process: a scan of an analytic two-component object (torus +
 * sphere, exact distance functions, sphere tracing with + - * / sqrt only, noise and dropouts
 * from an integer hash of the probe number) logged through port/vp_logwriter; the log replayed
 * through a fresh planner gives the same mesh bytes; the session cut at record boundaries and
 * at byte offsets (torn records), resumed, gives the same final mesh; damaged logs keep their
 * valid prefix (a damaged header is not taken for a newer version); a log being written is
 * locked against a second writer; a changed configuration is caught by the replay; the host-sim device's noise
 * is a function of (seed, probe number).
 * The printed fingerprints (log bytes, mesh bytes) must be the same on x86-64 and aarch64
 * (tests/t_aarch64.sh compares them): nothing here depends on libm. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "vp_logfmt.h"
#include "vp_logwriter.h"
#include "vp_meshio.h"
#include "vp_planner.h"
#include "vp_session.h"
#include "vp_simdev.h"
#include "vp_sessionlog.h"
#include "vp_surface.h"
#include "vp_rng.h"
#include "vp_test.h"

static int quick;
static char dir[256];
static const vp_logwriter_config_t nosync = { 0, 0, 0 };  /* sync on close only: tests run fast */

/* ---------- the analytic device ---------- */

typedef struct adev {
    double pos[3];
    uint64_t nprobe;
    double raw;
} adev_t;

static double sdf(const double *p)
{
    double q = sqrt(p[0] * p[0] + p[1] * p[1]) - 1.0, d1 = sqrt(q * q + p[2] * p[2]) - 0.35;
    double dx = p[0] - 2.3, d2 = sqrt(dx * dx + p[1] * p[1] + p[2] * p[2]) - 0.5;
    return d1 < d2 ? d1 : d2;
}


static double unit(uint64_t *s) { *s = vp_mix64(*s); return (double)(*s >> 11) * (1.0 / 9007199254740992.0); }

static int adev_move(void *ctx, const vp_cmd_t *cmd, int *collided)
{
    adev_t *d = ctx;
    memcpy(d->pos, cmd->to, sizeof d->pos);
    *collided = 0;
    return VP_OK;
}

static int adev_probe(void *ctx, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    adev_t *d = ctx;
    uint64_t s = 12345u + d->nprobe++ * 0xD1B54A32D192ED03ULL;
    double t = 0.0, noise = (unit(&s) + unit(&s) + unit(&s) + unit(&s) - 2.0) * 1.7320508075688772 * 1e-4;
    double drop = unit(&s);
    int i;
    res->hit = 0;
    res->dist = 0.0;
    d->raw = NAN;
    for (i = 0; i < 20000 && t <= cmd->range; i++) {
        double p[3], f;
        p[0] = d->pos[0] + t * cmd->dir[0];
        p[1] = d->pos[1] + t * cmd->dir[1];
        p[2] = d->pos[2] + t * cmd->dir[2];
        f = sdf(p);
        if (f < 1e-12) {
            if (drop < 0.05) return VP_OK;        /* a dropout */
            t += noise;
            res->hit = 1;
            res->dist = t < 0 ? 0 : t;
            d->raw = t;
            return VP_OK;
        }
        t += f;
    }
    return VP_OK;
}

static void config(vp_planner_config_t *c)
{
    memset(c, 0, sizeof *c);
    c->omega_kind = VP_OMEGA_BOX;
    c->omega_lo[0] = -1.7; c->omega_lo[1] = -1.7; c->omega_lo[2] = -0.9;
    c->omega_hi[0] = 3.2; c->omega_hi[1] = 1.7; c->omega_hi[2] = 0.9;
    c->start[0] = 3.5; c->start[1] = 2.0; c->start[2] = 1.2;
    c->ninterior = 2;
    c->interior[0][0] = 1.0;
    c->interior[1][0] = 2.3;
    c->eps = 0.15;
    c->noise_tol = 4e-4;
    c->confirm_misses = 5;
}

#define ARENA ((size_t)16 << 20)

static uint64_t fnv(const unsigned char *p, size_t n)
{
    uint64_t h = 1469598103934665603ULL;
    size_t i;
    for (i = 0; i < n; i++) { h ^= p[i]; h *= 1099511628211ULL; }
    return h;
}

static int read_file(const char *path, unsigned char **data, size_t *n)
{
    FILE *f = fopen(path, "rb");
    long len;
    if (!f) return -1;
    fseek(f, 0, SEEK_END);
    len = ftell(f);
    fseek(f, 0, SEEK_SET);
    *data = malloc((size_t)len + 1);
    *n = fread(*data, 1, (size_t)len, f);
    fclose(f);
    return *n == (size_t)len ? 0 : -1;
}

static int write_file(const char *path, const unsigned char *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    if (fwrite(data, 1, n, f) != n) { fclose(f); return -1; }
    return fclose(f);
}

/* The planner's mesh as PLY bytes. */
static void mesh_bytes(const vp_planner_t *pl, unsigned char **out, size_t *len)
{
    vp_mesh_t m;
    vp_mesh_init(&m);
    CHECK(vp_session_mesh(pl, &m) == VP_OK);
    CHECK(vp_mesh_write_buf(&m, VP_MESH_PLY_BIN, out, len) == VP_OK);
    vp_mesh_free(&m);
}

/* Runs the scan from the planner's state with the device at (pos, nprobe), logging to w
 * (NULL: no log). */
static int run(vp_planner_t *pl, adev_t *d, vp_sessionlog_writer_t *w)
{
    vp_device_ops_t ops;
    vp_session_hooks_t hooks;
    vp_session_result_t res;
    ops.ctx = d; ops.move = adev_move; ops.probe = adev_probe; ops.touched = NULL; ops.rays = NULL; ops.move_path = NULL; ops.sight = NULL;
    hooks.ctx = w; hooks.after = vp_sessionlog_after;
    if (w) w->raw = &d->raw;
    return vp_session_run(pl, &ops, w ? &hooks : NULL, 0, NULL, &res);
}

/* ---------- the uncut session ---------- */

static unsigned char *log0, *mesh0;
static size_t nlog0, nmesh0;

static void test_session(void)
{
    vp_planner_config_t c;
    vp_planner_t *pl = malloc(sizeof *pl);
    void *arena = malloc(ARENA);
    vp_logfmt_header_t h;
    vp_sessionlog_writer_t w;
    adev_t d;
    char path[300];
    int st;
    config(&c);
    CHECK(vp_planner_init(pl, arena, ARENA, &c) == VP_OK);
    memset(&d, 0, sizeof d);
    memcpy(d.pos, c.start, sizeof d.pos);
    memset(&w, 0, sizeof w);
    vp_logfmt_header_init(&h, &c, ARENA, VP_LOGFMT_UNITS_MM, "test", "test_sessionlog: torus + sphere");
    snprintf(path, sizeof path, "%s/uncut.vplog", dir);
    CHECK(vp_logwriter_create(&w.file, path, &h, &nosync) == VP_OK);
    CHECK(vp_logwriter_event(&w.file, VP_LOGFMT_EV_START, 0, "test") == VP_OK);
    st = run(pl, &d, &w);
    CHECKF(st == VP_OK, "scan: %s", vp_strerror(st));
    CHECK(vp_logwriter_close(&w.file) == VP_OK);
    mesh_bytes(pl, &mesh0, &nmesh0);
    CHECK(read_file(path, &log0, &nlog0) == 0);
    {
        vp_planner_stats_t s;
        vp_planner_get_stats(pl, &s);
        CHECKF(s.missing_components == 0 && s.bad_balls == 0, "missing %u, bad %u", s.missing_components, s.bad_balls);
        printf("session: %llu probes (%llu hits), %llu moves, %u facets, log %zu bytes, %lu syncs\n",
               (unsigned long long)s.probes, (unsigned long long)s.hits, (unsigned long long)s.moves,
               vp_planner_num_facets(pl), nlog0, w.file.syncs);
    }
    printf("fingerprint session log %016llx mesh %016llx\n", (unsigned long long)fnv(log0, nlog0),
           (unsigned long long)fnv(mesh0, nmesh0));
    free(pl);
    free(arena);
}

/* ---------- replay ---------- */

static void test_replay(void)
{
    vp_sessionlog_t L;
    vp_replay_t R;
    char err[600];
    unsigned char *m, *re;
    size_t n, k, len = 0;
    uint32_t i;
    CHECK(vp_sessionlog_load_buf(&L, log0, nlog0, err, sizeof err) == VP_OK);
    CHECK(L.status == VP_OK && L.done && L.good_bytes == nlog0);
    CHECK(vp_replay_open(&R, &L, 0, err, sizeof err) == VP_OK);
    CHECKF(vp_replay_run(&R, &L, L.n, err, sizeof err) == VP_OK, "%s", err);
    CHECK(R.done && R.applied == L.n);
    mesh_bytes(R.pl, &m, &n);
    CHECK(n == nmesh0 && memcmp(m, mesh0, n) == 0);
    free(m);
    vp_replay_close(&R);
    /* the core encoder rebuilds the file byte for byte from the decoded records */
    re = malloc(nlog0);
    k = (size_t)vp_logfmt_header_encode(&L.header, re, nlog0);
    CHECK(k == L.off[0]);
    for (i = 0; i < L.n; i++) {
        vp_logfmt_record_t r;
        CHECK(vp_sessionlog_record(&L, i, &r) == VP_OK);
        len = (size_t)vp_logfmt_record_encode(&r, re + k, nlog0 - k);
        k += len;
    }
    CHECK(k == nlog0 && memcmp(re, log0, nlog0) == 0);
    free(re);
    vp_sessionlog_free(&L);
}

/* ---------- cut and resume ---------- */

/* Resumes from the first `bytes` of the uncut log; the final mesh must be mesh0. With `append`
 * the continuation is appended to the cut file, which must then replay to mesh0 too. */
static int resume_from(size_t bytes, int append)
{
    vp_sessionlog_t L;
    vp_replay_t R;
    char err[600], path[300];
    adev_t d;
    unsigned char *m;
    size_t n;
    int ok = 1, st;
    if (vp_sessionlog_load_buf(&L, log0, bytes, err, sizeof err) != VP_OK) {
        /* a cut inside the header: nothing to resume from (a new session starts over) */
        return bytes < 400;
    }
    if (vp_replay_open(&R, &L, 0, err, sizeof err) != VP_OK || vp_replay_run(&R, &L, L.n, err, sizeof err) != VP_OK) {
        fprintf(stderr, "cut at %zu: %s\n", bytes, err);
        vp_sessionlog_free(&L);
        return 0;
    }
    memset(&d, 0, sizeof d);
    memcpy(d.pos, R.pos, sizeof d.pos);
    d.nprobe = R.probes;
    if (append) {
        vp_sessionlog_writer_t w;
        memset(&w, 0, sizeof w);
        snprintf(path, sizeof path, "%s/cut.vplog", dir);
        ok = write_file(path, log0, bytes) == 0 &&
             vp_logwriter_open_append(&w.file, path, L.good_bytes, L.n, &nosync) == VP_OK &&
             vp_logwriter_event(&w.file, VP_LOGFMT_EV_RESUME, 0, "test") == VP_OK;
        st = R.done ? VP_OK : run(R.pl, &d, &w);
        ok = ok && st == VP_OK && vp_logwriter_close(&w.file) == VP_OK;
    } else {
        st = R.done ? VP_OK : run(R.pl, &d, NULL);
        ok = st == VP_OK;
    }
    mesh_bytes(R.pl, &m, &n);
    ok = ok && n == nmesh0 && memcmp(m, mesh0, n) == 0;
    free(m);
    vp_replay_close(&R);
    vp_sessionlog_free(&L);
    if (ok && append) {
        /* the appended log: valid to its end, complete, and it replays to the same mesh */
        unsigned char *data;
        size_t len;
        ok = read_file(path, &data, &len) == 0 && vp_sessionlog_load_buf(&L, data, len, err, sizeof err) == VP_OK;
        free(data);
        if (ok) {
            ok = L.status == VP_OK && L.done && vp_replay_open(&R, &L, 0, err, sizeof err) == VP_OK &&
                 vp_replay_run(&R, &L, L.n, err, sizeof err) == VP_OK;
            if (ok) {
                mesh_bytes(R.pl, &m, &n);
                ok = n == nmesh0 && memcmp(m, mesh0, n) == 0;
                free(m);
            }
            vp_replay_close(&R);
            vp_sessionlog_free(&L);
        }
    }
    if (!ok) fprintf(stderr, "resume from %zu bytes%s: different final mesh or failure\n", bytes, append ? " (appending)" : "");
    return ok;
}

static void test_resume(void)
{
    vp_sessionlog_t L;
    char err[600];
    uint64_t s = 777;
    int i, bad = 0, cuts = quick ? 12 : 60;
    CHECK(vp_sessionlog_load_buf(&L, log0, nlog0, err, sizeof err) == VP_OK);
    /* record boundaries: the first, the last, random ones */
    bad += !resume_from(L.off[0], 1);
    bad += !resume_from(nlog0, 0);
    bad += !resume_from(L.off[L.n - 1], 1);
    for (i = 0; i < cuts; i++) {
        uint32_t k = (uint32_t)(unit(&s) * L.n);
        bad += !resume_from(L.off[k], i % 4 == 0);
    }
    /* torn records: random byte offsets */
    for (i = 0; i < cuts; i++) {
        size_t at = L.off[0] + (size_t)(unit(&s) * (double)(nlog0 - L.off[0]));
        bad += !resume_from(at, i % 4 == 1);
    }
    /* cuts inside the header leave nothing to resume: reported, not misread */
    bad += !resume_from(10, 0);
    CHECKF(bad == 0, "%d of %d resumed sessions differ", bad, 2 * cuts + 4);
    printf("resume: %d cuts (record boundaries and torn records) give the uncut mesh\n", 2 * cuts + 4);
    vp_sessionlog_free(&L);
}

/* ---------- damage ---------- */

static void test_damage(void)
{
    vp_sessionlog_t L, L0;
    vp_replay_t R;
    char err[600], stop[600];
    unsigned char *bad = malloc(nlog0);
    uint32_t k;
    CHECK(vp_sessionlog_load_buf(&L0, log0, nlog0, err, sizeof err) == VP_OK);
    k = L0.n / 2;
    /* one flipped bit in record k: records 0..k-1 kept and replayable */
    memcpy(bad, log0, nlog0);
    bad[L0.off[k] + 20] ^= 0x10;
    CHECK(vp_sessionlog_load_buf(&L, bad, nlog0, err, sizeof err) == VP_OK);
    CHECK(L.status == VP_ECORRUPT && L.reason == VP_LOGFMT_R_CRC && L.n == k && L.good_bytes == L0.off[k]);
    vp_sessionlog_stop_text(&L, stop, sizeof stop);
    {
        char want[64];
        snprintf(want, sizeof want, "record %u (byte offset %zu)", k, L0.off[k]);
        CHECKF(strstr(stop, want) != NULL, "message: %s", stop);
    }
    CHECK(vp_replay_open(&R, &L, 0, err, sizeof err) == VP_OK && vp_replay_run(&R, &L, L.n, err, sizeof err) == VP_OK);
    CHECK(R.applied == k && !R.done);
    vp_replay_close(&R);
    vp_sessionlog_free(&L);
    /* a newer version (its header intact) is refused with a clear message; a damaged version
     * byte is a damaged header (it said "newer format version (257)") */
    memcpy(bad, log0, nlog0);
    bad[8] = VP_LOGFMT_VERSION + 1;
    {
        size_t hl = (size_t)bad[12] | (size_t)bad[13] << 8 | (size_t)bad[14] << 16 | (size_t)bad[15] << 24;
        uint32_t c = vp_logfmt_crc32(0, bad, hl - 4);
        int b;
        for (b = 0; b < 4; b++) bad[hl - 4 + (size_t)b] = (unsigned char)(c >> (8 * b));
    }
    {
        char want[48];
        snprintf(want, sizeof want, "newer format version (%u;", VP_LOGFMT_VERSION + 1u);
        CHECKF(vp_sessionlog_load_buf(&L, bad, nlog0, err, sizeof err) == VP_EVERSION && strstr(err, want), "%s", err);
    }
    vp_sessionlog_free(&L);
    memcpy(bad, log0, nlog0);
    bad[9] = 1;
    CHECKF(vp_sessionlog_load_buf(&L, bad, nlog0, err, sizeof err) == VP_ECORRUPT && strstr(err, "header is damaged") &&
           strstr(err, "CRC") && strstr(err, "reads 257, not a newer format") && !strstr(err, "newer format version"),
           "%s", err);
    vp_sessionlog_free(&L);
    /* not a log at all */
    CHECK(vp_sessionlog_load_buf(&L, "OFF\n3 1 0\n", 10, err, sizeof err) == VP_ECORRUPT && strstr(err, "magic") != NULL);
    vp_sessionlog_free(&L);
    /* another configuration (eps one ulp larger): the replay names the first differing record */
    {
        vp_logfmt_header_t h = L0.header;
        size_t hl;
        int n;
        h.cfg.eps = nextafter(h.cfg.eps, 1.0);
        n = vp_logfmt_header_encode(&h, bad, nlog0);
        hl = L0.off[0];
        CHECK(n == (int)hl);
        memcpy(bad + hl, log0 + hl, nlog0 - hl);
        CHECK(vp_sessionlog_load_buf(&L, bad, nlog0, err, sizeof err) == VP_OK && L.status == VP_OK);
        CHECK(vp_replay_open(&R, &L, 0, err, sizeof err) == VP_OK);
        CHECK(vp_replay_run(&R, &L, L.n, err, sizeof err) == VP_ECORRUPT);
        CHECKF(strstr(err, "record ") != NULL && strstr(err, "differs") != NULL, "%s", err);
        printf("changed eps: %s\n", err);
        vp_replay_close(&R);
        vp_sessionlog_free(&L);
    }
    vp_sessionlog_free(&L0);
    free(bad);
}

/* ---------- the writer's lock ---------- */

/* A log being written is locked: a second writer (here another open file of this process,
 * which flock treats like another process) is refused with busy set and the file keeps every
 * byte; once the first writer closes, the log can be written again. Two runs writing the same
 * log both reported success and corrupted it. */
static void test_lock(void)
{
    vp_planner_config_t c;
    vp_logfmt_header_t h;
    vp_logwriter_t a, b;
    char path[300], other[300];
    unsigned char *before, *after;
    size_t nb, na;
    config(&c);
    vp_logfmt_header_init(&h, &c, ARENA, VP_LOGFMT_UNITS_MM, "test", "test_sessionlog: lock");
    snprintf(path, sizeof path, "%s/lock.vplog", dir);
    snprintf(other, sizeof other, "%s/lock2.vplog", dir);
    CHECK(vp_logwriter_create(&a, path, &h, &nosync) == VP_OK && !a.busy);
    CHECK(vp_logwriter_event(&a, VP_LOGFMT_EV_START, 0, "first writer") == VP_OK && vp_logwriter_sync(&a) == VP_OK);
    CHECK(read_file(path, &before, &nb) == 0);
    CHECK(vp_logwriter_create(&b, path, &h, &nosync) == VP_EIO && b.busy && b.fd < 0);
    CHECK(vp_logwriter_open_append(&b, path, nb, 1, &nosync) == VP_EIO && b.busy && b.fd < 0);
    CHECK(vp_logwriter_create_copy(&b, path, before, 16, 0, &nosync) == VP_EIO && b.busy && b.fd < 0);
    CHECK(read_file(path, &after, &na) == 0 && na == nb && memcmp(before, after, nb) == 0);
    free(after);
    /* the first writer goes on undisturbed */
    CHECK(vp_logwriter_event(&a, VP_LOGFMT_EV_PAUSE, 0, "still mine") == VP_OK && vp_logwriter_close(&a) == VP_OK);
    /* closed: the lock is gone; but a log that grew after it was read (nb bytes) is not cut back */
    CHECK(read_file(path, &after, &na) == 0 && na > nb);
    free(after);
    CHECK(vp_logwriter_open_append_read(&b, path, nb, 1, nb, &nosync) == VP_EIO && b.changed && !b.busy && b.fd < 0);
    CHECK(read_file(path, &after, &na) == 0 && na > nb && memcmp(before, after, nb) == 0);
    free(after);
    CHECK(vp_logwriter_open_append_read(&b, path, nb, 1, na, &nosync) == VP_OK && !b.busy && !b.changed);
    CHECK(vp_logwriter_close(&b) == VP_OK);
    /* a copy to another file is locked the same way, and appends after the copied bytes */
    CHECK(vp_logwriter_create_copy(&a, other, before, nb, 1, &nosync) == VP_OK && a.bytes == nb && a.seq == 1);
    CHECK(vp_logwriter_create(&b, other, &h, &nosync) == VP_EIO && b.busy);
    CHECK(vp_logwriter_event(&a, VP_LOGFMT_EV_RESUME, 0, "copied") == VP_OK && vp_logwriter_close(&a) == VP_OK);
    CHECK(read_file(other, &after, &na) == 0 && na > nb && memcmp(before, after, nb) == 0);
    {
        vp_sessionlog_t L;
        char err[300];
        CHECKF(vp_sessionlog_load_buf(&L, after, na, err, sizeof err) == VP_OK && L.status == VP_OK && L.n == 2 &&
               L.events == 2, "%s", err);
        vp_sessionlog_free(&L);
    }
    free(after);
    free(before);
    unlink(path);
    unlink(other);
}

/* ---------- the writer's power cut and sync policy ---------- */

static void test_powercut(void)
{
    vp_planner_config_t c;
    vp_logfmt_header_t h;
    vp_sessionlog_writer_t w;
    vp_logwriter_config_t fc;
    vp_planner_t *pl = malloc(sizeof *pl);
    void *arena = malloc(ARENA);
    adev_t d;
    char path[300];
    unsigned char *data;
    size_t n;
    int st;
    config(&c);
    CHECK(vp_planner_init(pl, arena, ARENA, &c) == VP_OK);
    memset(&d, 0, sizeof d);
    memcpy(d.pos, c.start, sizeof d.pos);
    memset(&w, 0, sizeof w);
    vp_logwriter_config_default(&fc);
    CHECK(fc.sync_records == 1);
    CHECK(vp_logwriter_parse_sync("25,50ms", &fc) == 0 && fc.sync_records == 25 && fc.sync_ms == 50);
    CHECK(vp_logwriter_parse_sync("x", &fc) < 0 && vp_logwriter_parse_sync("0", &fc) < 0);
    CHECK(vp_logwriter_parse_sync("close", &fc) == 0 && fc.sync_records == 0 && fc.sync_ms == 0);
    fc.die_after_bytes = nlog0 / 3 + 17;
    vp_logfmt_header_init(&h, &c, ARENA, VP_LOGFMT_UNITS_MM, "test", "test_sessionlog: torus + sphere");
    snprintf(path, sizeof path, "%s/cut.vplog", dir);
    CHECK(vp_logwriter_create(&w.file, path, &h, &fc) == VP_OK);
    CHECK(vp_logwriter_event(&w.file, VP_LOGFMT_EV_START, 0, "test") == VP_OK);
    st = run(pl, &d, &w);
    CHECK(st == VP_EIO && w.file.dead && w.file.bytes == fc.die_after_bytes);
    CHECK(vp_logwriter_append(&w.file, &(vp_logfmt_record_t){ .type = VP_LOGFMT_MOVE }) == VP_EIO);
    vp_logwriter_close(&w.file);
    /* the file is the uncut log's first bytes: a torn record at the end */
    CHECK(read_file(path, &data, &n) == 0 && n == fc.die_after_bytes && memcmp(data, log0, n) == 0);
    free(data);
    CHECK(resume_from(n, 1));
    free(pl);
    free(arena);
}

/* ---------- host-sim device: noise by probe number ---------- */

static void test_simdev_restore(void)
{
    vp_surface_t *s;
    vp_simdev_t *a = NULL, *b = NULL;
    vp_simdev_config_t cfg;
    char err[200];
    double start[3] = { 3, 0.1, 0.2 }, ray[3] = { -1, 0, 0 };
    int i, same = 1;
    if (vp_surface_open("sphere", &s, err, sizeof err) != VP_OK) { CHECK(0); return; }
    memset(&cfg, 0, sizeof cfg);
    cfg.noise_sigma = 0.01;
    cfg.dropout = 0.3;
    cfg.seed = 9;
    CHECK(vp_simdev_create(s, &cfg, start, &a) == VP_OK && vp_simdev_create(s, &cfg, start, &b) == VP_OK);
    vp_simdev_restore(b, start, 50);
    for (i = 0; i < 100; i++) {
        vp_simdev_probe_t pa, pb;
        vp_simdev_probe(a, ray, 10, &pa);
        if (i < 50) continue;
        vp_simdev_probe(b, ray, 10, &pb);
        if (pa.hit != pb.hit || memcmp(&pa.t, &pb.t, sizeof pa.t) != 0) same = 0;
    }
    CHECK(same);
    vp_simdev_destroy(a);
    vp_simdev_destroy(b);
    vp_surface_close(s);
}

/* A writer whose write failed takes no further record (the scan loop logs a path's MOVEs one
 * after the other): the next would follow a lost sequence number. */
static void test_after_failed(void)
{
    vp_sessionlog_writer_t w;
    vp_cmd_t c;
    memset(&w, 0, sizeof w);
    memset(&c, 0, sizeof c);
    c.kind = VP_CMD_MOVE;
    w.failed = 1;
    CHECK(vp_sessionlog_after(&w, &c, NULL) == VP_EIO && w.commands == 0);
}

int main(void)
{
    const char *q = getenv("VP_TEST_QUICK");
    const char *tmp = getenv("TMPDIR");
    quick = q && *q && strcmp(q, "0") != 0;
    snprintf(dir, sizeof dir, "%s/vp_sessionlog_XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir)) { perror("mkdtemp"); return 1; }
    test_after_failed();
    test_session();
    test_replay();
    test_resume();
    test_damage();
    test_powercut();
    test_lock();
    test_simdev_restore();
    {
        char p[300];
        snprintf(p, sizeof p, "%s/uncut.vplog", dir); unlink(p);
        snprintf(p, sizeof p, "%s/cut.vplog", dir); unlink(p);
        rmdir(dir);
    }
    free(log0);
    free(mesh0);
    return vp_test_done("test_sessionlog");
}
