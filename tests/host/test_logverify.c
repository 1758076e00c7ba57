/* vp_logverify, the proof check of a session log, on crafted logs written with core's encoder
 * and read back through the log reader: each kind of unproven move (through Omega with no
 * probe, 1% past a miss's range, past a hit, along a too-close probe, before its covering
 * probe, parallel to a probed line 1e-6 away, a chord of a ball Omega) and a probe from where
 * the device never moved are named with their record number; legitimate moves (outside Omega,
 * along dOmega, covered end to end by two collinear probes and the outside part, a tangent to a
 * ball Omega, across a PAUSE/RESUME) pass; with tubes, a move whose capsule misses 0.1 apart
 * cover passes, and one beyond them, between misses 0.3 apart or along a single ray is refused;
 * on 400 random logs of misses and a move into Omega no move is proven whose capsule holds a point
 * farther than rho from free space (a brute force written here: the lattice check before did); a body without tubes
 * is refused inside Omega; forged logs fail (test_forged: a CONTACT that stopped no move, a miss
 * fired again through a contact, a miss beside it within the noise tolerance, a miss past the
 * rangefinder's range, moves and probes from far away, a lattice too large); a torn tail is verified up to its last good record;
 * a synthetic 500k-record log runs in seconds.
 *
 *   test_logverify              the checks above
 *   test_logverify DIR          also writes each crafted log as DIR/NAME.vplog and the
 *                               expectations as DIR/expect.txt ("NAME EXIT FIRST_UNPROVEN
 *                               FIRST_OFF_POSITION", -1 for none) for tests/t_log_verify.sh
 *   test_logverify --mutate IN OUT   copies the log IN to OUT with one MOVE's target (the first
 *                               MOVE inside Omega after the middle of the log) moved to the
 *                               header's first interior point, CRC re-encoded; prints the record
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_logfmt.h"
#include "vp_logverify.h"
#include "vp_sessionlog.h"
#include "vp_test.h"

#define MAXREC 256

typedef struct crafted {
    vp_logfmt_header_t h;
    vp_logfmt_record_t r[MAXREC];
    size_t n;
} crafted_t;

static void box_header(crafted_t *c, double noise_tol, double sx, double sy, double sz)
{
    vp_planner_config_t cfg;
    int k;
    memset(&cfg, 0, sizeof cfg);
    cfg.omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) { cfg.omega_lo[k] = -1.0; cfg.omega_hi[k] = 1.0; }
    cfg.ninterior = 1;
    cfg.eps = 0.1;
    cfg.start[0] = sx; cfg.start[1] = sy; cfg.start[2] = sz;
    cfg.noise_tol = noise_tol;
    memset(c, 0, sizeof *c);
    vp_logfmt_header_init(&c->h, &cfg, 1u << 20, VP_LOGFMT_UNITS_NONE, "test", "crafted by test_logverify");
}

static void ball_header(crafted_t *c)
{
    vp_planner_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.omega_kind = VP_OMEGA_BALL;
    cfg.omega_radius = 1.0;
    cfg.ninterior = 1;
    cfg.eps = 0.1;
    cfg.start[2] = 2.0;
    memset(c, 0, sizeof *c);
    vp_logfmt_header_init(&c->h, &cfg, 1u << 20, VP_LOGFMT_UNITS_NONE, "test", "crafted by test_logverify (ball)");
}

/* the box header with a body of 0.1 and tubes of feature size rho (0: none), margin 0 */
static void tube_header(crafted_t *c, double rho)
{
    vp_planner_config_t tc;
    box_header(c, 0, 2, 0, 0);
    tc = c->h.cfg;
    tc.clearance = 0.1;
    tc.min_feature = rho;
    vp_logfmt_header_init(&c->h, &tc, 1u << 20, VP_LOGFMT_UNITS_NONE, "test", "crafted by test_logverify (tubes)");
}

static uint32_t ev(crafted_t *c, uint32_t event)
{
    vp_logfmt_record_event(&c->r[c->n], (uint32_t)c->n, event, 0, "crafted");
    return (uint32_t)c->n++;
}

static uint32_t mv(crafted_t *c, double x, double y, double z)
{
    vp_cmd_t cmd;
    memset(&cmd, 0, sizeof cmd);
    cmd.kind = VP_CMD_MOVE;
    cmd.to[0] = x; cmd.to[1] = y; cmd.to[2] = z;
    vp_logfmt_record_move(&c->r[c->n], (uint32_t)c->n, &cmd);
    return (uint32_t)c->n++;
}

/* a probe from o along d (normalised here) */
static uint32_t pb(crafted_t *c, double ox, double oy, double oz, double dx, double dy, double dz, double range,
                   int hit, double dist)
{
    vp_cmd_t cmd;
    vp_probe_result_t res;
    double l = sqrt(dx * dx + dy * dy + dz * dz);
    memset(&cmd, 0, sizeof cmd);
    cmd.kind = VP_CMD_PROBE;
    cmd.from[0] = ox; cmd.from[1] = oy; cmd.from[2] = oz;
    cmd.dir[0] = dx / l; cmd.dir[1] = dy / l; cmd.dir[2] = dz / l;
    cmd.range = range;
    res.hit = hit;
    res.dist = dist;
    vp_logfmt_record_probe(&c->r[c->n], (uint32_t)c->n, &cmd, &res, dist);
    return (uint32_t)c->n++;
}

/* Encodes the log into a buffer (header + records). */
static unsigned char *encode(const crafted_t *c, size_t *len)
{
    size_t cap = VP_LOGFMT_MAX_HEADER + (c->n + 1) * VP_LOGFMT_MAX_RECORD, n;
    unsigned char *b = malloc(cap);
    size_t i;
    int k;
    if (!b) return NULL;
    k = vp_logfmt_header_encode(&c->h, b, cap);
    CHECK(k > 0);
    if (k <= 0) { free(b); return NULL; }
    n = (size_t)k;
    for (i = 0; i < c->n; i++) {
        k = vp_logfmt_record_encode(&c->r[i], b + n, cap - n);
        CHECK(k > 0);
        if (k <= 0) { free(b); return NULL; }
        n += (size_t)k;
    }
    *len = n;
    return b;
}

/* Verifies c's encoded bytes (cut to `cut` bytes when cut != 0) through the reader; the same
 * as verifying the records directly when nothing is cut. */
static int verify_bytes(const crafted_t *c, size_t cut, vp_logverify_result_t *res, uint32_t *valid)
{
    vp_sessionlog_t L;
    vp_logverify_t *v = malloc(sizeof *v);
    char err[400];
    size_t len = 0;
    unsigned char *b = encode(c, &len);
    uint32_t i;
    int st;
    if (!b || !v) { free(b); free(v); return VP_ENOMEM; }
    st = vp_sessionlog_load_buf(&L, b, cut ? cut : len, err, sizeof err);
    free(b);
    if (st != VP_OK) { free(v); return st; }
    *valid = L.n;
    st = vp_logverify_begin(v, &L.header);
    for (i = 0; st == VP_OK && i < L.n; i++) {
        vp_logfmt_record_t r;
        st = vp_sessionlog_record(&L, i, &r);
        if (st == VP_OK) st = vp_logverify_add(v, &r);
    }
    vp_logverify_end(v, res);
    free(v);
    vp_sessionlog_free(&L);
    return st;
}

static FILE *expect_file;
static const char *out_dir;

static void write_log(const crafted_t *c, const char *name, int exit_code, long first, long off)
{
    char path[1024];
    size_t len = 0;
    unsigned char *b;
    FILE *f;
    if (!out_dir) return;
    b = encode(c, &len);
    if (!b) return;
    snprintf(path, sizeof path, "%s/%s.vplog", out_dir, name);
    f = fopen(path, "wb");
    CHECKF(f != NULL, "cannot write %s", path);
    if (f) { CHECK(fwrite(b, 1, len, f) == len); fclose(f); }
    free(b);
    if (expect_file) fprintf(expect_file, "%s %d %ld %ld\n", name, exit_code, first, off);
}

/* Verifies c both ways and checks: the number of unproven moves, the first one's record (-1:
 * none), the number of off-position probes and the first one's record. */
static void expect(const crafted_t *c, const char *name, uint64_t unproven, long first, uint64_t off, long first_off)
{
    vp_logverify_result_t a, b;
    uint32_t valid = 0;
    int st = vp_logverify_run(&c->h, c->r, c->n, &a);
    CHECKF(st == VP_OK, "%s: run %d", name, st);
    st = verify_bytes(c, 0, &b, &valid);
    CHECKF(st == VP_OK, "%s: through the reader %d", name, st);
    CHECKF(valid == c->n, "%s: %u of %zu records read back", name, valid, c->n);
    CHECKF(a.unproven_moves == unproven, "%s: %llu unproven moves, expected %llu", name,
           (unsigned long long)a.unproven_moves, (unsigned long long)unproven);
    CHECKF(first < 0 ? a.nmoves_listed == 0 : a.nmoves_listed > 0 && a.move[0].record == (uint32_t)first,
           "%s: first unproven record %ld expected, got %ld", name, first,
           a.nmoves_listed ? (long)a.move[0].record : -1L);
    CHECKF(a.probes_off_position == off, "%s: %llu probes off position, expected %llu", name,
           (unsigned long long)a.probes_off_position, (unsigned long long)off);
    CHECKF(first_off < 0 ? a.nprobes_listed == 0 : a.nprobes_listed > 0 && a.probe[0].record == (uint32_t)first_off,
           "%s: first off-position probe %ld expected", name, first_off);
    CHECKF(a.ok == (unproven == 0 && off == 0), "%s: ok %d", name, a.ok);
    CHECKF(a.records == c->n, "%s: %llu records verified", name, (unsigned long long)a.records);
    /* the encoded and read-back log gives the same verdict */
    CHECKF(b.unproven_moves == a.unproven_moves && b.probes_off_position == a.probes_off_position &&
           b.moves == a.moves && b.probes == a.probes && b.ok == a.ok, "%s: reader round trip differs", name);
    if (a.nmoves_listed && b.nmoves_listed)
        CHECKF(a.move[0].record == b.move[0].record && a.move[0].gap_s0 == b.move[0].gap_s0 &&
               a.move[0].gap_s1 == b.move[0].gap_s1, "%s: reader round trip: first move differs", name);
    write_log(c, name, a.ok ? 0 : 1, first, first_off);
}

/* CONTACT: the MOVE before it stopped `at` along it */
static uint32_t ct(crafted_t *c, double at)
{
    vp_logfmt_record_event(&c->r[c->n], (uint32_t)c->n, VP_LOGFMT_EV_CONTACT, 0, "crafted contact");
    c->r[c->n].value[0] = at;
    return (uint32_t)c->n++;
}

static void test_crafted(void)
{
    crafted_t c;
    vp_logverify_result_t r;
    uint32_t bad, valid;

    /* a contact: the miss that showed the way free is withdrawn; the travelled stretch stays */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, 0, 0);   /* a miss through Omega (a dark surface at x = 0.2) */
    mv(&c, -0.5, 0, 0);
    ct(&c, 0.8);                          /* the switch closed at x = 0.2 */
    mv(&c, 0.6, 0, 0);                    /* back along the travelled stretch: free */
    bad = mv(&c, 0.1, 0, 0);              /* on through the contact: the miss no longer proves it */
    expect(&c, "contact", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.contacts == 1 && r.withdrawn == 1 && r.nmoves_listed == 1);
    CHECK(fabs(r.move[0].gap_s0 - 0.4 / 0.5) < 1e-9 && r.move[0].gap_s1 == 1.0);
    /* the same log without its CONTACT event: every move proven (what the event changes) */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, 0, 0);
    mv(&c, -0.5, 0, 0);
    mv(&c, 0.6, 0, 0);
    mv(&c, 0.1, 0, 0);
    expect(&c, "contact_unlogged", 0, -1, 0, -1);

    /* a re-scan: the object may have changed, so a miss logged before the RESCAN event proves
     * nothing after it (the device is at the start again); the same way probed again does */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, 0, 0);   /* a miss through Omega */
    mv(&c, 0, 0, 0);                      /* proven */
    mv(&c, 1, 0, 0);
    ev(&c, VP_LOGFMT_EV_RESCAN);
    mv(&c, 1, 0, 0);                      /* from the start (2,0,0) onto dOmega: outside */
    bad = mv(&c, 0, 0, 0);                /* the old miss no longer proves it */
    expect(&c, "rescan_stale", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.rescans == 1 && r.nmoves_listed == 1 && r.move[0].seq == bad);
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, 0, 0);
    mv(&c, 0, 0, 0);
    mv(&c, 1, 0, 0);
    ev(&c, VP_LOGFMT_EV_RESCAN);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 1, 0, 0);   /* probed again after the re-scan: free to the centre */
    mv(&c, 0, 0, 0);
    expect(&c, "rescan_reproved", 0, -1, 0, -1);
    /* the header's proof life (an object that moves): a free part proves moves for that many
     * commands (PROBEs and MOVEs) after it, no longer */
    box_header(&c, 0, 2, 0, 0);
    c.h.cfg.proof_life = 2;
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, 0, 0);   /* a miss through Omega */
    mv(&c, 0.5, 0, 0);                    /* 0 commands old */
    mv(&c, 0.6, 0, 0);                    /* 1 */
    mv(&c, 0.4, 0, 0);                    /* 2 */
    bad = mv(&c, 0.3, 0, 0);              /* 3: too old */
    expect(&c, "proof_life", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.nmoves_listed == 1 && r.move[0].seq == bad);
    c.h.cfg.proof_life = 0;               /* the same log without a life: proven */
    expect(&c, "proof_life_none", 0, -1, 0, -1);

    /* a probe after the RESCAN event from where the device stood before it: off its position */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    ev(&c, VP_LOGFMT_EV_RESCAN);
    bad = pb(&c, 1, 0, 0, -1, 0, 0, 1, 0, 0);
    expect(&c, "rescan_restart", 0, -1, 1, bad);
    /* the RESCAN event's code holds flags (bit 0: the device stays, bit 1: a sparse re-scan);
     * other bits are not a log voroprobe writes (replay refuses them too) */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    bad = ev(&c, VP_LOGFMT_EV_RESCAN);
    c.r[bad].code = VP_RESCAN_HERE | VP_RESCAN_SPARSE;
    pb(&c, 1, 0, 0, -1, 0, 0, 1, 0, 0);   /* from where it stood: on its position */
    expect(&c, "rescan_here_sparse", 0, -1, 0, -1);
    c.r[bad].code = 4;
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_ECORRUPT);

    /* a move through Omega with no probe */
    box_header(&c, 0, 2, 0, 0);
    ev(&c, VP_LOGFMT_EV_START);
    mv(&c, 1, 0, 0);                      /* outside, onto dOmega: free */
    bad = mv(&c, 0, 0, 0);
    expect(&c, "no_probe", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.moves == 2 && r.moves_outside == 1 && r.nmoves_listed == 1);
    CHECK(r.move[0].seq == bad && r.move[0].move == 2 && r.move[0].gap_s0 == 0.0 && r.move[0].gap_s1 == 1.0);
    CHECK(fabs(r.move[0].unproven - 1.0) < 1e-12 && r.move[0].probes_on_line == 0);

    /* a torn tail: verified up to the last good record (the bad move is in the torn part) */
    {
        size_t len = 0;
        unsigned char *b = encode(&c, &len);
        free(b);
        CHECK(verify_bytes(&c, len - 10, &r, &valid) == VP_OK);
        CHECK(valid == c.n - 1 && r.records == c.n - 1 && r.ok && r.moves == 1);
    }

    /* a move 1% past a miss's range */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 0.5, 0, 0);
    mv(&c, 0.5, 0, 0);                    /* exactly the miss's range: free */
    mv(&c, 1, 0, 0);
    bad = mv(&c, 1 - 0.505, 0, 0);        /* 1% further */
    expect(&c, "past_miss", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.nmoves_listed == 1 && fabs(r.move[0].unproven - 0.005) < 1e-9 && r.move[0].probes_on_line == 1);
    CHECK(fabs(r.move[0].gap_s0 - 0.5 / 0.505) < 1e-12 && r.move[0].gap_s1 == 1.0);

    /* a move past a hit point (noise tolerance 0.01: free up to 0.59 of a hit at 0.6) */
    box_header(&c, 0.01, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, 1, 0.6);
    mv(&c, 0.42, 0, 0);                   /* 0.58 along: free */
    mv(&c, 1, 0, 0);
    bad = mv(&c, 0.4, 0, 0);              /* onto the hit point: the last 0.01 is not proven */
    mv(&c, 1, 0, 0);                      /* and back: its first 0.01 is not either */
    mv(&c, 0.2, 0, 0);                    /* past it */
    expect(&c, "past_hit", 3, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.nmoves_listed == 3 && fabs(r.move[0].unproven - 0.01) < 1e-9 && fabs(r.move[1].unproven - 0.01) < 1e-9 &&
          fabs(r.move[2].unproven - 0.21) < 1e-9);
    CHECK(fabs(r.move[0].gap_s0 - 0.59 / 0.6) < 1e-12 && r.move[0].gap_s1 == 1.0 && r.move[1].gap_s0 == 0.0);

    /* a move along a probe that was too close: nothing proven */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 2, VP_PROBE_TOO_CLOSE, 0);
    bad = mv(&c, 0.9, 0, 0);
    expect(&c, "too_close", 1, bad, 0, -1);

    /* a move before its covering probe (the probe after it covers the move back) */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    bad = mv(&c, 0.5, 0, 0);
    pb(&c, 0.5, 0, 0, 1, 0, 0, 0.5, 0, 0);
    mv(&c, 1, 0, 0);
    mv(&c, 0.5, 0, 0);
    expect(&c, "before_probe", 1, bad, 0, -1);

    /* a move parallel to a probed line, 1e-6 away */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 1, 0, 0);
    mv(&c, 1, 1e-6, 0);                   /* along dOmega (x = 1): free */
    bad = mv(&c, 0.5, 1e-6, 0);
    mv(&c, 1, 1e-6, 0);
    mv(&c, 1, 0, 0);
    mv(&c, 0.5, 0, 0);                    /* on the line itself: free */
    expect(&c, "offset_1e-6", 2, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.nmoves_listed == 2 && r.move[0].probes_on_line == 0 && r.move[1].record == bad + 1);

    /* a probe from a position never moved to: counted, and it proves nothing */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    bad = pb(&c, 1, 0.2, 0, -1, 0, 0, 1, 0, 0);
    mv(&c, 1, 0.2, 0);                    /* along dOmega: free */
    mv(&c, 0.5, 0.2, 0);                  /* would be covered by that probe */
    expect(&c, "probe_elsewhere", 1, bad + 2, 1, bad);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.nprobes_listed == 1 && fabs(r.probe[0].off - 0.2) < 1e-12 && r.probe[0].pos[0] == 1.0);

    /* the same probe where the device stood: no violation, and the move is proven */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1, 0, 0);
    mv(&c, 1, 0.2, 0);
    pb(&c, 1, 0.2, 0, -1, 0, 0, 1, 0, 0);
    mv(&c, 0.5, 0.2, 0);
    expect(&c, "probe_here", 0, -1, 0, -1);

    /* legitimate: one move covered by the outside part, two collinear probes end to end, and
     * the outside part again; across a PAUSE and a RESUME (the position carries over) */
    box_header(&c, 0.01, 2, 0, 0);
    ev(&c, VP_LOGFMT_EV_START);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 0.8, 0, 0);        /* free x in [0.2, 1] */
    mv(&c, 0.2, 0, 0);
    ev(&c, VP_LOGFMT_EV_PAUSE);
    ev(&c, VP_LOGFMT_EV_RESUME);
    pb(&c, 0.2, 0, 0, -1, 0, 0, 2, 1, 1.21);     /* hit at x = -1.01: free to x = -1.0 */
    mv(&c, 1.5, 0, 0);                           /* back along both, out of Omega */
    mv(&c, -1.5, 0, 0);                          /* outside, probe 1, probe 2, outside */
    mv(&c, -1.5, 3, 0);                          /* outside */
    mv(&c, 1.5, 3, 0);
    mv(&c, 1, 0.999, 1);                         /* along dOmega */
    mv(&c, 1, -1, -1);                           /* along a face of Omega */
    mv(&c, 1, -1, -1);                           /* zero length */
    ev(&c, VP_LOGFMT_EV_DONE);
    expect(&c, "legit", 0, -1, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.ok && r.moves == 9 && r.probes == 2 && r.events == 4);
    CHECK(r.pos[0] == 1.0 && r.pos[1] == -1.0 && r.pos[2] == -1.0);

    /* the same, but the two probes leave a gap of 1e-4 between them */
    box_header(&c, 0.01, 2, 0, 0);
    mv(&c, 1, 0, 0);
    pb(&c, 1, 0, 0, -1, 0, 0, 0.8, 0, 0);
    mv(&c, 0.2, 0, 0);
    mv(&c, 0.1999, 0, 0);                        /* the gap itself */
    bad = c.n - 1;
    expect(&c, "gap_1e-4", 1, (long)bad, 0, -1);

    /* a ball Omega: a tangent is outside, a chord is not */
    ball_header(&c);
    mv(&c, 0, 0, 1);                             /* from the start (0,0,2) onto dOmega */
    mv(&c, 1, 0, 1);                             /* tangent at (0,0,1): outside */
    mv(&c, 0, 0, 1);
    bad = mv(&c, 1, 0, 0);                       /* a chord: inside */
    pb(&c, 1, 0, 0, -1, 0, 1, sqrt(2.0), 0, 0);  /* back along the chord: free */
    mv(&c, 0, 0, 1);
    mv(&c, 1, 0, 0);
    mv(&c, 2, 0, 0);                             /* out */
    expect(&c, "ball_chord", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
    CHECK(r.nmoves_listed == 1 && fabs(r.move[0].unproven - sqrt(2.0)) < 1e-9);

    /* tubes (clearance 0.1, feature 0.2, margin 0: the capsule of 0.3 about a move must lie
     * within 0.2 of free space): 81 misses along -x from x = 1.5, 0.1 apart across, reaching
     * x = 0, prove the tube to (0.6,0,0) and back; a move on to (-0.2,0,0) reaches 0.5 beyond
     * the misses' ends and is refused */
    {
        int a, b;
        tube_header(&c, 0.2);
        for (a = -4; a <= 4; a++)
            for (b = -4; b <= 4; b++) {
                mv(&c, 1.5, 0.1 * a, 0.1 * b); /* outside Omega (x <= 1) */
                pb(&c, 1.5, 0.1 * a, 0.1 * b, -1, 0, 0, 1.5, 0, 0);
            }
        mv(&c, 1, 0, 0);
        mv(&c, 0.6, 0, 0);
        mv(&c, 1, 0, 0);
        bad = mv(&c, -0.2, 0, 0);
        expect(&c, "tube_rays", 1, bad, 0, -1);
        CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
        CHECK(r.tube_moves == 3 && r.tube_points > 100 && r.move[0].gap_from[0] < -0.2);
        /* misses 0.3 apart across, at 0.1 + 0.3 i: every point of the lattice of 0.1 the rule
         * starts from lies within 0.15 of one, yet the line (x, -0.05, -0.05), 0.07 from the
         * move's axis, lies 0.21 from all: a ball of the object of radius 0.2 there meets no
         * miss and the head's body (the build before passed this move) */
        tube_header(&c, 0.2);
        for (a = -2; a <= 2; a++)
            for (b = -2; b <= 2; b++) {
                mv(&c, 1.5, 0.1 + 0.3 * a, 0.1 + 0.3 * b);
                pb(&c, 1.5, 0.1 + 0.3 * a, 0.1 + 0.3 * b, -1, 0, 0, 1.5, 0, 0);
            }
        mv(&c, 1, 0, 0);
        bad = mv(&c, 0.6, 0, 0);
        expect(&c, "tube_between_lattice_points", 1, bad, 0, -1);
        /* one probe along the move proves its line, not its tube ... */
        tube_header(&c, 0.2);
        mv(&c, 1, 0, 0);
        pb(&c, 1, 0, 0, -1, 0, 0, 1.0, 0, 0);
        bad = mv(&c, 0.6, 0, 0);
        expect(&c, "tube_one_ray", 1, bad, 0, -1);
        /* ... and without a feature size nothing proves it: a body without tubes stays
         * outside Omega (the build before took the line rule here) */
        c.h.cfg.min_feature = 0.0;
        expect(&c, "body_one_ray_no_tubes", 1, bad, 0, -1);
        CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK);
        CHECK(r.nmoves_listed == 1 && fabs(r.move[0].unproven - 0.4) < 1e-9 && r.tube_moves == 0);
        /* a point device (no clearance) takes the line rule */
        c.h.cfg.clearance = 0.0;
        expect(&c, "point_one_ray_line_rule", 0, -1, 0, -1);
        /* a lattice too large to look at (feature 1e-6 against a move of 3): unproven, at once */
        tube_header(&c, 1e-6);
        c.h.cfg.start[0] = -3.0;
        bad = mv(&c, 0, 0, 0);
        expect(&c, "tube_lattice_too_large", 1, bad, 0, -1);
        CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.tube_too_large == 1 && r.tube_points == 0);
    }
}

/* What a log cannot make the check believe: a CONTACT that stopped no MOVE, a miss through an
 * earlier contact, a miss beside the contact within the hits' tolerance, a miss beyond the
 * rangefinder's range, moves from far away (rounding), a ball Omega's chord from far away. */
static void test_forged(void)
{
    crafted_t c;
    vp_logverify_result_t r;
    uint32_t bad;
    /* a CONTACT first: it stopped no move, so it puts the device nowhere and frees nothing */
    box_header(&c, 0, 2, 0, 0);
    ct(&c, 1.5);
    bad = mv(&c, 0, 0, 0);
    expect(&c, "contact_misplaced", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.contacts_misplaced == 1 && r.contacts == 0 && !r.ok);
    /* ... nor after a RESCAN (the move before it is not the one stopped; the build before took
     * the stretch from that move's start to the start position as travelled) */
    box_header(&c, 0, 2, 0, 0);
    pb(&c, 2, 0, 0, -1, 0, 0, 2.5, 0, 0);
    mv(&c, 0, 0, 0);
    pb(&c, 0, 0, 0, 0, 1, 0, 0.5, 0, 0);
    mv(&c, 0, 0.5, 0);
    ev(&c, VP_LOGFMT_EV_RESCAN);
    ct(&c, 2);
    bad = mv(&c, 0, 0, 0);
    expect(&c, "contact_after_rescan", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.contacts_misplaced == 1);
    /* the same wrong miss fired again after the contact proves nothing near it */
    box_header(&c, 0, 2, 0, 0);
    pb(&c, 2, 0, 0, -1, 0, 0, 4, 0, 0);
    mv(&c, -0.5, 0, 0);
    ct(&c, 2);                            /* stopped at the centre */
    mv(&c, 2, 0, 0);                      /* back along the travelled stretch */
    pb(&c, 2, 0, 0, -1, 0, 0, 4, 0, 0);
    bad = mv(&c, -0.5, 0, 0);
    expect(&c, "contact_miss_again", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.probes_near_contact == 1 && r.withdrawn == 1);
    /* a miss 1e-6 beside the contact point, noise tolerance 0.001: withdrawn with the other */
    box_header(&c, 0.001, 2, 0, 0);
    mv(&c, 2, 1e-6, 0);
    pb(&c, 2, 1e-6, 0, -1, 0, 0, 4, 0, 0);
    mv(&c, 2, 0, 0);
    pb(&c, 2, 0, 0, -1, 0, 0, 4, 0, 0);
    mv(&c, -0.5, 0, 0);
    ct(&c, 2);
    mv(&c, 2, 0, 0);
    mv(&c, 2, 1e-6, 0);
    bad = mv(&c, -0.5, 1e-6, 0);
    expect(&c, "contact_beside", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.withdrawn == 2);
    /* a miss is free no farther than the rangefinder reaches */
    box_header(&c, 0, 2, 0, 0);
    c.h.cfg.max_range = 1.0;
    pb(&c, 2, 0, 0, -1, 0, 0, 4, 0, 0);
    bad = mv(&c, -0.5, 0, 0);
    expect(&c, "beyond_max_range", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && fabs(r.move[0].unproven - 1.5) < 1e-9);
    c.h.cfg.max_range = 0.0;
    expect(&c, "within_range", 0, -1, 0, -1);
    /* a move from 1e16 away to the centre (its inside part rounds away): refused as far */
    box_header(&c, 0, 2, 0, 0);
    bad = mv(&c, 1e16, 0, 0);
    mv(&c, 0, 0, 0);
    expect(&c, "far_move", 2, bad, 0, -1);
    /* a ball Omega's chord 0.5 from its centre, from 1e5 radii on either side: the inside
     * part (sqrt 3) measured from the foot of the perpendicular, not from squares of 1e5 */
    ball_header(&c);
    mv(&c, 1e5, 0.5, 0);
    bad = mv(&c, -1e5, 0.5, 0);
    expect(&c, "ball_far_chord", 1, bad, 0, -1);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && fabs(r.move[0].unproven - sqrt(3.0)) < 1e-8);
    /* a contact outside Omega: Omega does not hold the object, so its outside proves nothing
     * after it (the build before took the way back through the touched point as outside) */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 2, 2, 0);
    mv(&c, 2, -2, 0);
    ct(&c, 1.0);                          /* touched at (2, 1, 0), outside Omega */
    bad = mv(&c, 2, 2, 0);
    mv(&c, 2, -2, 0);
    expect(&c, "contact_outside", 2, bad, 0, -1);
    /* a probe fired from far away proves nothing */
    box_header(&c, 0, 2, 0, 0);
    mv(&c, 1e7, 0, 0);
    pb(&c, 1e7, 0, 0, -1, 0, 0, 2e7, 0, 0);
    CHECK(vp_logverify_run(&c.h, c.r, c.n, &r) == VP_OK && r.probes_far == 1);
}

/* A synthetic log of 250k probes and 250k moves, each move along the probe before it (all
 * proven), then one not (offset 1e-6): linear-time, in seconds. */
/* The tube rule against a brute force written here, on random logs: misses from outside the box
 * Omega along about -x (random spacing, tilt and range), then a move into Omega. Whenever the
 * check proves the move, 3,000 random points of its capsule (radius C + eta + rho = 0.3) must each
 * lie within rho (0.2, to the check's tolerance) of a miss or of Omega's outside, measured here
 * from the probes as logged. The check on lattice points alone (the build before) proves some
 * moves with points 0.2-0.22 from all free space. A deterministic generator (xorshift). */
static uint64_t lv_rng = 0x9E3779B97F4A7C15ull;
static double lv_rand(void)
{
    lv_rng ^= lv_rng << 13;
    lv_rng ^= lv_rng >> 7;
    lv_rng ^= lv_rng << 17;
    return (double)(lv_rng >> 11) * (1.0 / 9007199254740992.0);
}

static double seg_dist(const double *o, const double *d, double len, const double *x)
{
    double w[3], s, e[3];
    int k;
    for (k = 0; k < 3; k++) w[k] = x[k] - o[k];
    s = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
    if (s < 0.0) s = 0.0;
    if (s > len) s = len;
    for (k = 0; k < 3; k++) e[k] = w[k] - s * d[k];
    return sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
}

static void test_tube_random(void)
{
    static crafted_t c;
    double ray[120][7]; /* origin, unit direction, range */
    int trial, proven = 0, refused = 0, far_pts = 0, far_moves = 0;
    for (trial = 0; trial < 400; trial++) {
        double sp = 0.1 + 0.25 * lv_rand(), a[3], b[3], R = 0.3, rho = 0.2;
        int nr = 0, i, j, k, bad_here = 0;
        vp_logverify_result_t res;
        tube_header(&c, rho);
        for (i = -4; i <= 4 && nr < 120; i++)
            for (j = -4; j <= 4 && nr < 120; j++) {
                double *r = ray[nr], l;
                if (fabs(i * sp) > 0.75 || fabs(j * sp) > 0.75) continue;
                r[0] = 1.5; r[1] = i * sp + 0.3 * sp * (lv_rand() - 0.5); r[2] = j * sp + 0.3 * sp * (lv_rand() - 0.5);
                r[3] = -1.0; r[4] = 0.1 * (lv_rand() - 0.5); r[5] = 0.1 * (lv_rand() - 0.5);
                l = sqrt(r[3] * r[3] + r[4] * r[4] + r[5] * r[5]);
                for (k = 3; k < 6; k++) r[k] /= l;
                r[6] = 1.2 + 1.0 * lv_rand();
                mv(&c, r[0], r[1], r[2]);
                pb(&c, r[0], r[1], r[2], r[3], r[4], r[5], r[6], 0, 0);
                nr++;
            }
        a[0] = 1.0; a[1] = 0.2 * (lv_rand() - 0.5); a[2] = 0.2 * (lv_rand() - 0.5);
        b[0] = 0.3 + 0.5 * lv_rand(); b[1] = 0.4 * (lv_rand() - 0.5); b[2] = 0.4 * (lv_rand() - 0.5);
        mv(&c, 2.0, a[1], a[2]);
        mv(&c, a[0], a[1], a[2]); /* onto dOmega: outside */
        mv(&c, b[0], b[1], b[2]);
        if (vp_logverify_run(&c.h, c.r, c.n, &res) != VP_OK) { CHECK(0); continue; }
        if (res.unproven_moves > 0) { refused++; continue; }
        proven++;
        for (i = 0; i < 3000; i++) {
            double x[3], t = lv_rand(), best, e[3], dd;
            for (k = 0; k < 3; k++) x[k] = a[k] + t * (b[k] - a[k]) + R * (2.0 * lv_rand() - 1.0);
            for (k = 0; k < 3; k++) e[k] = b[k] - a[k];
            dd = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
            for (k = 0; k < 3; k++) e[k] /= dd;
            if (seg_dist(a, e, dd, x) > R) { i--; continue; }
            best = 1.0 - fabs(x[0]); /* Omega's outside: the box [-1,1]^3 */
            for (k = 1; k < 3; k++)
                if (1.0 - fabs(x[k]) < best) best = 1.0 - fabs(x[k]);
            for (j = 0; j < nr; j++) {
                double dj = seg_dist(ray[j], ray[j] + 3, ray[j][6], x);
                if (dj < best) best = dj;
            }
            if (best > rho + 1e-8) { far_pts++; bad_here = 1; }
        }
        far_moves += bad_here;
    }
    printf("tube rule, random: %d moves proven, %d refused; %d proven with capsule points farther than rho (%d points)\n",
           proven, refused, far_moves, far_pts);
    CHECKF(proven > 40 && refused > 40, "%d proven, %d refused: the cases do not span the rule", proven, refused);
    CHECKF(far_moves == 0, "%d moves proven with %d capsule points farther than rho from free space", far_moves, far_pts);
}

static void test_big(void)
{
    enum { N = 250000 };
    vp_logfmt_header_t h;
    vp_planner_config_t cfg;
    vp_logverify_t *v = malloc(sizeof *v);
    vp_logverify_result_t r;
    vp_logfmt_record_t rec;
    double pos[3] = { 1, 0, 0 }, t0, secs;
    uint64_t s = 88172645463325252ull;
    uint32_t seq = 0;
    int i, k, st;
    if (!v) { CHECK(0); return; }
    memset(&cfg, 0, sizeof cfg);
    cfg.omega_kind = VP_OMEGA_BOX;
    for (k = 0; k < 3; k++) { cfg.omega_lo[k] = -1; cfg.omega_hi[k] = 1; }
    cfg.ninterior = 1;
    cfg.eps = 0.01;
    cfg.start[0] = 1;
    vp_logfmt_header_init(&h, &cfg, 1u << 20, VP_LOGFMT_UNITS_NONE, "test", "big");
    t0 = (double)clock() / CLOCKS_PER_SEC;
    st = vp_logverify_begin(v, &h);
    CHECK(st == VP_OK);
    for (i = 0; i < N && st == VP_OK; i++) {
        vp_cmd_t cmd;
        vp_probe_result_t res;
        double d[3], l, len;
        memset(&cmd, 0, sizeof cmd);
        for (k = 0; k < 3; k++) {
            s ^= s << 13; s ^= s >> 7; s ^= s << 17;
            d[k] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
        }
        l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (d[0] * pos[0] + d[1] * pos[1] + d[2] * pos[2] > 0) l = -l;   /* towards the centre */
        cmd.kind = VP_CMD_PROBE;
        for (k = 0; k < 3; k++) { cmd.from[k] = pos[k]; cmd.dir[k] = d[k] / l; }
        cmd.range = 0.05;
        res.hit = i % 2;
        res.dist = 0.04;
        len = res.hit ? 0.04 : 0.05;
        vp_logfmt_record_probe(&rec, seq++, &cmd, &res, res.dist);
        st = vp_logverify_add(v, &rec);
        cmd.kind = VP_CMD_MOVE;
        /* half way along the free part; one move in 1000 only 1e-7 long (too short for the
         * line index: the probe fired from its start proves it) */
        for (k = 0; k < 3; k++) cmd.to[k] = pos[k] + (i % 1000 == 499 ? 1e-7 : 0.5 * len) * cmd.dir[k];
        vp_logfmt_record_move(&rec, seq++, &cmd);
        if (st == VP_OK) st = vp_logverify_add(v, &rec);
        if (i % 1000 == 999) {
            /* then 1e-7 further: no probe was fired from either end, all probes are looked at */
            for (k = 0; k < 3; k++) cmd.to[k] += 1e-7 * cmd.dir[k];
            vp_logfmt_record_move(&rec, seq++, &cmd);
            if (st == VP_OK) st = vp_logverify_add(v, &rec);
        }
        memcpy(pos, cmd.to, sizeof pos);
    }
    /* one move 1e-6 off the last probe's line */
    {
        vp_cmd_t cmd;
        memset(&cmd, 0, sizeof cmd);
        cmd.kind = VP_CMD_MOVE;
        memcpy(cmd.to, pos, sizeof pos);
        cmd.to[0] += 0.01;
        cmd.to[1] += 1e-6;
        vp_logfmt_record_move(&rec, seq++, &cmd);
        if (st == VP_OK) st = vp_logverify_add(v, &rec);
    }
    vp_logverify_end(v, &r);
    free(v);
    secs = (double)clock() / CLOCKS_PER_SEC - t0;
    CHECK(st == VP_OK);
    CHECKF(r.records == 2u * N + N / 1000 + 1 && r.unproven_moves == 1 && r.nmoves_listed == 1 &&
           r.move[0].record == 2u * N + N / 1000,
           "%llu unproven, first %ld", (unsigned long long)r.unproven_moves, r.nmoves_listed ? (long)r.move[0].record : -1L);
    CHECKF(secs < 20.0, "%.2f s", secs);
    CHECKF(r.scans == N / 1000, "%llu index fallbacks", (unsigned long long)r.scans);
    printf("synthetic log: %u records verified in %.2f s CPU (%llu index fallbacks)\n", seq, secs,
           (unsigned long long)r.scans);
}

/* --mutate IN OUT */
static int mutate(const char *in, const char *out)
{
    vp_sessionlog_t L;
    char err[1400];
    uint32_t i, pick = UINT32_MAX;
    FILE *f;
    int st = vp_sessionlog_load(&L, in, err, sizeof err), k;
    if (st != VP_OK) { fprintf(stderr, "%s\n", err); return 2; }
    for (i = L.n / 2; i < L.n && pick == UINT32_MAX; i++) {
        vp_logfmt_record_t r;
        const vp_planner_config_t *c = &L.header.cfg;
        int inside = 1;
        if (vp_sessionlog_record(&L, i, &r) != VP_OK || r.type != VP_LOGFMT_MOVE) continue;
        for (k = 0; k < 3; k++) {
            if (c->omega_kind == VP_OMEGA_BOX && !(r.target[k] > c->omega_lo[k] && r.target[k] < c->omega_hi[k])) inside = 0;
        }
        if (c->omega_kind == VP_OMEGA_BALL) {
            double d2 = 0;
            for (k = 0; k < 3; k++) d2 += (r.target[k] - c->omega_center[k]) * (r.target[k] - c->omega_center[k]);
            inside = d2 < c->omega_radius * c->omega_radius;
        }
        if (inside) pick = i;
    }
    if (pick == UINT32_MAX) { fprintf(stderr, "no MOVE inside Omega in the second half\n"); vp_sessionlog_free(&L); return 2; }
    f = fopen(out, "wb");
    if (!f) { vp_sessionlog_free(&L); return 2; }
    fwrite(L.data, 1, L.off[pick], f);       /* the header and every record before it */
    for (i = pick; i < L.n; i++) {
        vp_logfmt_record_t r;
        unsigned char b[VP_LOGFMT_MAX_RECORD];
        int n;
        if (vp_sessionlog_record(&L, i, &r) != VP_OK) break;
        if (i == pick) memcpy(r.target, L.header.cfg.interior[0], sizeof r.target);
        n = vp_logfmt_record_encode(&r, b, sizeof b);
        if (n > 0) fwrite(b, 1, (size_t)n, f);
    }
    st = ferror(f);
    fclose(f);
    vp_sessionlog_free(&L);
    if (st) return 2;
    printf("%u\n", pick);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "--mutate")) return mutate(argv[2], argv[3]);
    if (argc == 2) {
        char path[1024];
        out_dir = argv[1];
        snprintf(path, sizeof path, "%s/expect.txt", out_dir);
        expect_file = fopen(path, "w");
        if (!expect_file) { fprintf(stderr, "cannot write %s\n", path); return 2; }
    }
    test_crafted();
    test_forged();
    if (!out_dir) test_tube_random();
    if (expect_file) fclose(expect_file);
    if (!out_dir) test_big();
    return vp_test_done("test_logverify");
}
