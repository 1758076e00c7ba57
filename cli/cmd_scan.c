/* voroprobe scan: the device program. Home, then planner <-> machine until DONE, writing the
 * session log; Ctrl-C and the e-stop leave a resumable log; --resume continues one; --dry-run
 * runs the same loop with host-sim at the hardware boundary. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_backends.h"
#include "vp_bodyreport.h"
#include "vp_cli.h"
#include "vp_logfmt.h"
#include "vp_note.h"
#include "vp_logwriter.h"
#include "vp_hausdorff.h"
#include "vp_live_cli.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_outcome.h"
#include "vp_progress.h"
#include "vp_audit.h"
#include "vp_json.h"
#include "vp_rtclock.h"
#include "vp_scan.h"
#include "vp_session.h"
#include "vp_sim_opts.h"
#include "vp_sim_setup.h"
#include "vp_sessionlog.h"
#include "vp_surface.h"

static void scan_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe scan --board FILE --log LOG [options]\n"
        "       voroprobe scan --log LOG --resume [options]\n"
        "       voroprobe scan --rescan OLD --log LOG [options]\n"
        "Scans the object on a board's machine: homes, then moves and probes as the planner asks\n"
        "until it says DONE, writing the session log as it goes and the mesh at the end.\n"
        "  --board FILE     the machine (boards/*.ini); with --resume: the one in the log\n"
        "  --log LOG        the session log (replaced; with --resume: continued)\n"
        "  --rescan OLD     scan again the object of session OLD (its options): every sample is\n"
        "                   measured again, moved ones are removed, old free space is proven again\n"
        "                   before the head moves through it, and the scan goes on where something\n"
        "                   changed; LOG gets OLD's records, a RESCAN event and the new ones (dry run:\n"
        "                   --surface names the object now)\n");
    fprintf(f,
        "  --rescan-sparse  with --rescan: a sample is not measured when all its neighbours are and\n"
        "                   hold (no two neighbours both left out; about 20%% fewer probes); a change\n"
        "                   narrower than the sample spacing that moves only such samples goes unseen\n"
        "  --resume         replay LOG, home, go back along the logged free route to where the\n"
        "                   scan stopped and continue it (the options come from the log)\n"
        "  --eps E          largest surface Delaunay ball radius, mm (default: the board's eps)\n"
        "  --accuracy H     the target, mm: facets are refined where they stray more than H/3 from\n"
        "                   the surface (down to balls of H/4), so the mesh can follow the object\n"
        "                   within H with fewer samples where it is flat; a dry run measures it\n"
        "                   (exit 6 when the mesh is farther); eps stays the largest ball\n"
        "  --calib FILE     rangefinder calibration file (default: the board's [rangefinder]\n"
        "                   calibration when that file exists, else the camera geometry)\n"
        "  --out PREFIX     mesh files PREFIX.ply and PREFIX.off (default: LOG without .vplog)\n"
        "  --sync POLICY    when the log is synced: record (each), N (records), Tms, N,Tms or\n"
        "                   close (default: the board's log_sync, else record)\n"
        "  --arena BYTES    planner memory (default 64M; K, M, G suffixes)\n"
        "  --noise-tol MM   hits are trusted to within this distance (default 2)\n"
        "  --confirm N      re-probes of a miss where a hit is expected (default 2; 0 on a board\n"
        "                   with a backdrop, where a spot that drops out reads as unreadable)\n"
        "  --near-spots M   a spot nearer than the rangefinder's min_range: too-close (the planner\n"
        "                   gets VP_PROBE_TOO_CLOSE: never free, never sampled) or measure (a hit\n"
        "                   at the model's extrapolated distance); default: the board's near_spots\n"
        "  --by-length      body mode: the head's moves ordered by length, as before they were weighed\n"
        "                   by the axes' speeds (the next probe the nearest, the ways round Omega\n"
        "                   along its surface): to compare machine times\n"
        "  --far-reads      body mode on a board with a backdrop: a probe asks for its whole line\n"
        "                   through Omega; a spot read past its edge's end proves the edge free and\n"
        "                   becomes a sample where none lies within eps (fewer probes; see README)\n"
        "  --quiet          no progress line\n"
        "  --json           end with one JSON object (status, probes, mesh, moves, stop_reason when it\n"
        "                   stopped short; dry run: moves through the object, head collisions by\n"
        "                   part, contacts, Hausdorff distance)\n"
        VP_LIVE_CLI_HELP
        "Dry run (nothing moves, nothing sleeps):\n"
        "  --dry-run        the board's kinematics, step generator (recording GPIO backend on a\n"
        "                   simulated clock) and camera model (rendered frames) on host-sim\n"
        "  --surface SPEC   the simulated object: NAME (sphere, torus, genus2, ellipsoid, genus5,\n"
        "                   blobby), off:FILE or ply:FILE are sized to fit Omega around the board's\n"
        "                   interior point; a SPEC with '*' or '@' is taken as written, in mm\n"
        "                   (default: the board's [sim] surface, else an ellipsoid sized to Omega)\n"
        "  --seed N         seed of the frames' noise (default: the board's [sim] seed)\n"
        "  --reach-out      keep an object that reaches out of Omega (refused otherwise), to rehearse\n"
        "                   a misplaced part: the head's contact switch must stop it where it meets\n"
        "                   the part; the clearance ball in the object is then reported by part but\n"
        "                   not as a head collision (every other part is)\n"
        );
    fprintf(f,
        "Stopping: Ctrl-C stops after the current command (PAUSE event; MOVEs made as one path:\n"
        "after the path, each logged); a second Ctrl-C ends at once. The e-stop stops the pulses\n"
        "at once (FAULT event). Both leave the log resumable.\n"
        "Tests: --stop-after N (Ctrl-C after N commands, or at the end of the path command N is in),\n"
        "--estop-at N (dry run: e-stop during command N of this run; MOVEs then made one by one).\n"
        "Exit status: 0 DONE (closed mesh), 1 failed or stopped by a fault, 2 usage, 3 paused, 4 DONE but\n"
        "the mesh is not closed (or misses a component), 5 a dry run moved through the object (the laser\n"
        "origin's path, or any part of the head's body swept along a move or an aim: board [head]), 6 a\n"
        "dry run's mesh farther from the object than --accuracy, 7 a dry run's mesh closed with another\n"
        "genus or number of components than the object's.\n");
    {
        char b[256];
        vp_backends_describe(b, sizeof b);
        fprintf(f, "Hardware backends built in: %s.\n", b);
    }
}

typedef struct scan_opts {
    const char *board, *log, *calib, *out, *surface;
    const char *rescan;           /* --rescan OLD: the session to scan again */
    int near;                     /* -1: the board's near_spots; 0 too-close; 1 measure */
    double eps, noise_tol;
    double accuracy;              /* --accuracy H (mm): the distance bound and its floor */
    int confirm, dry, resume, quiet, have_sync, json;
    int sparse;                   /* --rescan-sparse (VP_RESCAN_SPARSE) */
    int reach_out;                /* --reach-out: a dry run's object may reach out of Omega */
    int by_length;                /* --by-length: body mode's moves not weighed by machine time */
    int far;                      /* --far-reads: VP_PLAN_FAR_READS */
    size_t arena;
    unsigned long long seed;
    unsigned long stop_after, estop_at;
    unsigned long board_crc;
    int have_crc;
    vp_logwriter_config_t sync;
} scan_opts_t;

static void scan_defaults(scan_opts_t *o)
{
    memset(o, 0, sizeof *o);
    o->noise_tol = 2;
    o->confirm = -1;          /* 2, or 0 on a board with a backdrop */
    o->arena = (size_t)64 << 20;
    o->near = -1;
}

static int num(const char *s, double *v)
{
    char *e;
    *v = strtod(s, &e);
    return e != s && !*e && isfinite(*v);
}

/* 0 taken, 1 unknown, -1 bad value (err). from_note: the log's own options. */
static int scan_option(scan_opts_t *o, int argc, char **argv, int *i, int from_note, char *err, size_t n)
{
    const char *a = argv[*i], *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    double v;
    if (!strcmp(a, "--dry-run")) { o->dry = 1; return 0; }
    if (!strcmp(a, "--reach-out")) { o->reach_out = 1; return 0; }
    if (!strcmp(a, "--by-length")) { o->by_length = 1; return 0; }
    if (!strcmp(a, "--far-reads")) { o->far = 1; return 0; }
    if (!strcmp(a, "--resume") && !from_note) { o->resume = 1; return 0; }
    if (!strcmp(a, "--quiet") && !from_note) { o->quiet = 1; return 0; }
    if (!strcmp(a, "--json") && !from_note) { o->json = 1; return 0; }
    if (!strcmp(a, "--rescan-sparse") && !from_note) { o->sparse = 1; return 0; }
    if (strcmp(a, "--board") && strcmp(a, "--log") && strcmp(a, "--calib") && strcmp(a, "--out") &&
        strcmp(a, "--surface") && strcmp(a, "--eps") && strcmp(a, "--accuracy") && strcmp(a, "--noise-tol") && strcmp(a, "--confirm") &&
        strcmp(a, "--arena") && strcmp(a, "--seed") && strcmp(a, "--sync") && strcmp(a, "--stop-after") &&
        strcmp(a, "--estop-at") && strcmp(a, "--near-spots") && (strcmp(a, "--board-crc") || !from_note) &&
        (strcmp(a, "--rescan") || from_note))
        return 1;
    if (!val) { snprintf(err, n, "%s needs a value", a); return -1; }
    (*i)++;
    if (!strcmp(a, "--board")) o->board = val;
    else if (!strcmp(a, "--log")) o->log = val;
    else if (!strcmp(a, "--calib")) o->calib = val;
    else if (!strcmp(a, "--out")) o->out = val;
    else if (!strcmp(a, "--surface")) o->surface = val;
    else if (!strcmp(a, "--rescan")) o->rescan = val;
    else if (!strcmp(a, "--near-spots")) {
        if (strcmp(val, "too-close") && strcmp(val, "measure")) {
            snprintf(err, n, "--near-spots takes too-close or measure, not '%s'", val);
            return -1;
        }
        o->near = !strcmp(val, "measure");
    }
    else if (!strcmp(a, "--arena")) {
        if (vp_parse_size(val, &o->arena) || o->arena < 4096) { snprintf(err, n, "--arena: bad size '%s'", val); return -1; }
    } else if (!strcmp(a, "--sync")) {
        if (vp_logwriter_parse_sync(val, &o->sync)) {
            snprintf(err, n, "--sync takes record, close, N (records), Tms or N,Tms; not '%s'", val);
            return -1;
        }
        o->have_sync = 1;
    } else if (!strcmp(a, "--board-crc")) {
        char *e;
        o->board_crc = strtoul(val, &e, 16);
        o->have_crc = e != val && !*e;
    } else if (!num(val, &v)) {
        snprintf(err, n, "%s: not a number: '%s'", a, val);
        return -1;
    } else if (!strcmp(a, "--eps")) {
        if (!(v > 0)) { snprintf(err, n, "--eps must be > 0"); return -1; }
        o->eps = v;
    } else if (!strcmp(a, "--accuracy")) {
        if (!(v > 0)) { snprintf(err, n, "--accuracy must be > 0 (mm)"); return -1; }
        o->accuracy = v;
    } else if (!strcmp(a, "--noise-tol")) {
        if (!(v >= 0)) { snprintf(err, n, "--noise-tol must be >= 0"); return -1; }
        o->noise_tol = v;
    } else if (!strcmp(a, "--confirm")) {
        if (!(v >= 0 && v <= 16 && v == floor(v))) { snprintf(err, n, "--confirm must be in 0..16"); return -1; }
        o->confirm = (int)v;
    } else if (!strcmp(a, "--seed")) {
        if (!(v >= 0 && v == floor(v))) { snprintf(err, n, "--seed must be a whole number >= 0"); return -1; }
        o->seed = (unsigned long long)v;
    } else {
        if (!(v >= 1 && v == floor(v))) { snprintf(err, n, "%s takes a positive whole number, not '%s'", a, val); return -1; }
        if (!strcmp(a, "--stop-after")) o->stop_after = (unsigned long)v;
        else o->estop_at = (unsigned long)v;
    }
    return 0;
}

/* ---------- the log's note: the options that make the scan ---------- */

static void scan_note(const scan_opts_t *o, const char *board, double eps, const char *surface, char *buf, size_t n)
{
    size_t len = 0;
    buf[0] = 0;
    vp_note_put(buf, n, &len, "scan");
    vp_note_put_str(buf, n, &len, "--board", board);
    vp_note_put_num(buf, n, &len, "--eps", eps);
    if (o->accuracy > 0) vp_note_put_num(buf, n, &len, "--accuracy", o->accuracy);
    vp_note_put_opt(buf, n, &len, "--arena", "%zu", o->arena);
    vp_note_put_num(buf, n, &len, "--noise-tol", o->noise_tol);
    vp_note_put_opt(buf, n, &len, "--confirm", "%d", o->confirm);
    vp_note_put_str(buf, n, &len, "--near-spots", o->near ? "measure" : "too-close");
    if (o->by_length) vp_note_put(buf, n, &len, "--by-length");
    if (o->far) vp_note_put(buf, n, &len, "--far-reads");
    if (o->calib) vp_note_put_str(buf, n, &len, "--calib", o->calib);
    if (o->dry) {
        vp_note_put(buf, n, &len, "--dry-run");
        vp_note_put_str(buf, n, &len, "--surface", surface);
        vp_note_put_opt(buf, n, &len, "--seed", "%llu", o->seed);
        if (o->reach_out) vp_note_put(buf, n, &len, "--reach-out");
    }
    vp_note_put_opt(buf, n, &len, "--board-crc", "%08lx", o->board_crc);
}

static int file_crc(const char *path, unsigned long *crc)
{
    unsigned char buf[4096];
    uint32_t c = 0;
    size_t k;
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    while ((k = fread(buf, 1, sizeof buf, f)) > 0) c = vp_logfmt_crc32(c, buf, k);
    fclose(f);
    *crc = c;
    return 0;
}

/* ---------- the run ---------- */

typedef struct scan_run {
    vp_sessionlog_writer_t w;
    vp_scan_dev_t *dev;
    vp_planner_t *pl;
    unsigned long n, stop_after;
    int paused, quiet, hw;
    double wall0, t0;
    uint64_t probes0;
    vp_progress_t prog;    /* a bar on a terminal, periodic lines in a pipe or file */
} scan_run_t;

static void scan_progress(scan_run_t *r, int final)
{
    vp_planner_stats_t st;
    double t = vp_scan_seconds(r->dev) - r->t0;
    uint32_t nv = vp_planner_dt(r->pl)->ninserted, nf = vp_planner_num_facets(r->pl);
    char text[300];
    vp_planner_get_stats(r->pl, &st);
    snprintf(text, sizeof text, "  commands %-7lu probes %-6llu (%llu hits, %llu too close)  facets %-6u bad balls %-5u "
             "largest ball %-7.3g  machine time %d:%02d:%02d",
             r->n, (unsigned long long)st.probes, (unsigned long long)st.hits, (unsigned long long)st.too_close,
             nf, st.bad_balls, st.bad_balls ? st.max_ball : 0.0, (int)(t / 3600), (int)fmod(t / 60, 60), (int)fmod(t, 60));
    /* the bar: facets over the 2V - 4 of a closed mesh on the same samples (vp_session.c) */
    vp_progress_print(&r->prog, nv > 3 ? fmin(1.0, nf / (2.0 * nv - 4.0)) : 0.0, text, final);
}

/* The step timing report (retimes, late faults, lateness histogram) as an EVENT record: logged
 * before the session's last event (DONE, PAUSE or FAULT stays last). */
static int scan_log_stepping(scan_run_t *r)
{
    vp_logfmt_record_t ev;
    char text[VP_LOGFMT_TEXT_MAX + 1];
    double v[4];
    int st;
    vp_scan_step_report(r->dev, text, sizeof text, v);
    vp_logfmt_record_event(&ev, 0, VP_LOGFMT_EV_STEPPING, 0, text);
    memcpy(ev.value, v, sizeof v);
    st = vp_logwriter_append(&r->w.file, &ev);
    if (st != VP_OK) r->w.failed = 1;
    return st;
}

static int scan_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    scan_run_t *r = ctx;
    int st = cmd->kind == VP_CMD_DONE ? scan_log_stepping(r) : VP_OK;
    if (st != VP_OK) return st;
    st = vp_sessionlog_after(&r->w, cmd, res);
    if (st != VP_OK) return st;
    if (cmd->kind == VP_CMD_DONE || cmd->kind == VP_CMD_RAY) return VP_OK; /* a RAY: part of its PROBE's frame */
    if (cmd->kind == VP_CMD_PROBE && res && res->hit == VP_PROBE_TOO_CLOSE && r->dev->last_false_miss)
        r->dev->false_misses_unseen++; /* a hidden spot the sight rule caught (dry run) */
    r->n++;
    if (!r->quiet && (vp_progress_tick(&r->prog) || (r->hw && r->prog.tty))) scan_progress(r, 0);
    if (r->stop_after && r->n == r->stop_after) raise(SIGINT);   /* a Ctrl-C, on purpose */
    if (vp_scan_stop) { r->paused = 1; return VP_EABORT; }
    return VP_OK;
}

static int write_mesh(const vp_planner_t *pl, const char *prefix, vp_mesh_t *mesh, char *err, size_t n)
{
    char path[VP_PATH_MAX];
    int st = vp_session_mesh(pl, mesh);
    if (st != VP_OK) { snprintf(err, n, "mesh: %s", vp_strerror(st)); return st; }
    if ((st = vp_path_cat(path, sizeof path, prefix, ".ply", err, n)) != VP_OK) return st;
    if (vp_mkdirs_for(prefix) != 0) { snprintf(err, n, "cannot create the folder of %s: %s", prefix, strerror(errno)); return VP_EIO; }
    if ((st = vp_mesh_write_file(mesh, path, VP_MESH_PLY_BIN)) != VP_OK) { snprintf(err, n, "cannot write %.1400s: %s", path, strerror(errno)); return st; }
    if ((st = vp_path_cat(path, sizeof path, prefix, ".off", err, n)) != VP_OK) return st;
    if ((st = vp_mesh_write_file(mesh, path, VP_MESH_OFF)) != VP_OK) { snprintf(err, n, "cannot write %.1400s: %s", path, strerror(errno)); return st; }
    return VP_OK;
}

static const char *model_source(const vp_board_t *b)
{
    return b->calibrated == 2 ? b->calib_path : b->calibrated == 1 ? "the board's [rangefinder] line and model"
                                                                   : "the camera geometry (not calibrated)";
}

/* One run of `scan`: what its phases share (vp_cli_scan calls them in order). */
typedef struct scan_job {
    scan_opts_t o, cl;              /* the options in force; the command line's */
    vp_board_t b;
    vp_scan_dev_t dev;
    vp_sessionlog_t L;              /* the resumed log (have_L) */
    vp_planner_config_t cfg;
    vp_planner_t *pl;
    void *arena;
    scan_run_t run;
    vp_mesh_t mesh;
    char surface[VP_PATH_MAX], prefix[VP_PATH_MAX], board_path[VP_PATH_MAX];
    int have_L, dev_open, log_open;
    int rescans;                    /* RESCAN events in the loaded log (a re-scan resumed) */
    vp_planner_stats_t before;      /* the planner's counters when this run's re-scan began */
    int rc;                         /* the exit status so far */
    int st_home;                    /* what homing left: VP_OK, or VP_EABORT when paused */
    uint32_t replayed;
    double wall0;
    vp_live_cli_t live;             /* --serve: the live view */
    char stop_text[VP_LOGFMT_TEXT_MAX + 1];  /* why the scan stopped short of DONE ("": it did not) */
    int home_failed;                /* homing or the way to the start (or back) stopped: no scan */
    unsigned long unseen_misses;    /* misses of this run fed as unreadable (vp_run.h) */
} scan_job_t;

/* The command line into j->cl.
 * -1: go on; else the exit status. */
static int scan_parse(scan_job_t *j, int argc, char **argv)
{
    char err[1600];
    int st;
    int i;

    scan_defaults(&j->cl);
    vp_live_cli_init(&j->live);
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) { scan_usage(stdout); return 0; }
        if ((st = vp_live_cli_option(&j->live, argc, argv, &i, "scan")) <= 0) { if (st < 0) return 2; continue; }
        st = scan_option(&j->cl, argc, argv, &i, 0, err, sizeof err);
        if (st == 0) continue;
        if (st < 0) fprintf(stderr, "scan: %s\n", err);
        else fprintf(stderr, "scan: unknown option %s (see --help)\n", argv[i]);
        return 2;
    }
    if (!j->cl.log) { fprintf(stderr, "scan: give the session log: --log LOG (see --help)\n"); return 2; }
    if (j->cl.rescan && j->cl.resume) {
        fprintf(stderr, "scan: --rescan and --resume cannot go together (resume a paused re-scan with --resume alone)\n");
        return 2;
    }
    if (j->cl.sparse && !j->cl.rescan) { fprintf(stderr, "scan: --rescan-sparse goes with --rescan OLD\n"); return 2; }
    if (j->cl.rescan && !strcmp(j->cl.rescan, j->cl.log)) {
        fprintf(stderr, "scan: a re-scan writes a new log: give --log other than %s\n", j->cl.rescan);
        return 2;
    }
    if (!j->cl.resume && !j->cl.rescan && !j->cl.board) { fprintf(stderr, "scan: give the machine: --board FILE (see --help)\n"); return 2; }
    if (j->cl.estop_at && !j->cl.dry && !j->cl.resume) { fprintf(stderr, "scan: --estop-at simulates the e-stop: dry runs only\n"); return 2; }
    j->o = j->cl;
    vp_mesh_init(&j->mesh);
    memset(&j->run, 0, sizeof j->run);
    j->run.w.file.fd = -1;
    return -1;
}

/* The RESCAN events of a loaded log; the last one's object (its text "--surface SPEC", a dry
 * run's) into surface when it names one. */
static int count_rescans(const vp_sessionlog_t *L, char *surface, size_t n)
{
    uint32_t i;
    int c = 0;
    for (i = 0; i < L->n; i++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_EVENT || rec.event != VP_LOGFMT_EV_RESCAN) continue;
        c++;
        if (!strncmp(rec.text, "--surface ", 10)) snprintf(surface, n, "%s", rec.text + 10);
    }
    return c;
}

/* The options: the command line, or those in the log with --resume.
 * -1: go on; else the exit status. */
static int scan_options(scan_job_t *j)
{
    char err[1600];
    char sub[600];
    char notebuf[VP_LOGFMT_NOTE_MAX + 1];
    int st;
    int i;

    if (j->cl.resume || j->cl.rescan) {
        char *tok[64];
        const char *src = j->cl.rescan ? j->cl.rescan : j->cl.log;
        int nt;
        st = vp_sessionlog_load(&j->L, src, err, sizeof err);
        if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); return 1; }
        j->have_L = 1;
        memcpy(notebuf, j->L.header.note, sizeof notebuf);
        nt = vp_note_split(notebuf, tok, 64);
        if (nt < 1 || strcmp(tok[0], "scan") != 0) {
            fprintf(stderr, "scan: %s was not written by `scan`%s\n", src,
                    nt >= 1 && !strcmp(tok[0], "sim") ? " but by `sim`: resume it with `voroprobe sim --resume`" : "");
            return j->rc;
        }
        scan_defaults(&j->o);
        for (i = 1; i < nt; i++)
            if (scan_option(&j->o, nt, tok, &i, 1, sub, sizeof sub) != 0) {
                fprintf(stderr, "scan: %s: the options recorded in the log are not understood ('%s')\n", src, tok[i]);
                return j->rc;
            }
        if (j->cl.dry && !j->o.dry) { fprintf(stderr, "scan: %s is a scan of the real machine: it cannot go on as a dry run\n", src); return j->rc; }
        if (!j->cl.dry && j->o.dry) j->cl.dry = 1;   /* a dry run's log goes on as a dry run */
        if ((j->cl.eps && j->cl.eps != j->o.eps) || (j->cl.accuracy && j->cl.accuracy != j->o.accuracy) ||
            (!j->cl.rescan && j->cl.surface && strcmp(j->cl.surface, j->o.surface ? j->o.surface : "")) ||
            (j->cl.near >= 0 && j->cl.near != j->o.near) ||
            (j->cl.seed && j->cl.seed != j->o.seed)) {
            fprintf(stderr, "scan: a resumed scan keeps the options in its log (%s)\n", j->L.header.note);
            return j->rc;
        }
        if (j->o.estop_at || j->cl.estop_at) j->o.estop_at = j->cl.estop_at;
        if (j->cl.board) j->o.board = j->cl.board;
        if (j->cl.calib) j->o.calib = j->cl.calib;
        j->o.log = j->cl.log;
        j->o.out = j->cl.out;
        j->o.quiet = j->cl.quiet;
        j->o.json = j->cl.json;
        j->o.resume = j->cl.resume;
        j->o.rescan = j->cl.rescan;
        j->o.stop_after = j->cl.stop_after;
        j->o.sync = j->cl.sync;
        j->o.have_sync = j->cl.have_sync;
    }
    if (j->o.reach_out && !j->o.dry) { fprintf(stderr, "scan: --reach-out rehearses a misplaced object: dry runs only\n"); return j->rc; }
    if (j->o.estop_at && !j->o.dry) { fprintf(stderr, "scan: --estop-at simulates the e-stop: dry runs only\n"); return j->rc; }
    if (j->have_L) j->rescans = count_rescans(&j->L, j->surface, sizeof j->surface);
    return -1;
}

/* The board, its calibration, the object; the log and mesh paths checked.
 * -1: go on; else the exit status. */
static int scan_board(scan_job_t *j)
{
    char err[1600];
    int st;

    st = vp_board_load(j->o.board, &j->b, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); return j->rc; }
    if (j->o.calib && (st = vp_board_calibration_load(&j->b, j->o.calib, NULL, err, sizeof err)) != VP_OK) {
        fprintf(stderr, "scan: %s\n", err);
        return j->rc;
    }
    if (!(j->b.clearance > 0.0)) {
        /* a camera rangefinder's "no spot" is not a proof of free space: an occluded spot, a dark
         * or shiny surface read the same. Inside Omega the head would move on such misses. */
        if (!j->o.dry) {
            fprintf(stderr, "scan: %s: [omega] clearance = 0 lets the head into Omega, where it moves along rays its "
                    "rangefinder reported free; a camera rangefinder reports an occluded, dark or shiny spot as no spot, "
                    "which proves nothing (a dry run of a cube moved through it 1878 times): set clearance to the head's "
                    "radius, so that the head stays outside Omega\n", j->o.board);
            return j->rc;
        }
        fprintf(stderr, "scan: warning: clearance 0 (dry run only): the head enters Omega and trusts every \"no spot\" "
                "as free space; moves through the object are counted and end the run with exit 5\n");
    }
    {
        unsigned long crc = 0;
        file_crc(j->o.board, &crc);
        if (j->o.resume && j->o.have_crc && crc != j->o.board_crc)
            fprintf(stderr, "scan: note: %s changed since the log was started (the planner's configuration is "
                    "checked below; the machine's may differ)\n", j->o.board);
        j->o.board_crc = crc;
    }
    snprintf(j->board_path, sizeof j->board_path, "%s", j->o.board);
    if (!j->o.eps) j->o.eps = j->b.eps;
    if (j->o.near < 0) j->o.near = j->b.near_measure;
    /* a miss is re-probed in case the spot dropped out; with a backdrop a spot that drops out
     * leaves the frame unreadable, and a miss is a spot seen past the range: nothing to repeat */
    if (j->o.confirm < 0) j->o.confirm = j->b.have_backdrop ? 0 : 2;
    if (j->o.dry) {
        if (j->o.resume && j->rescans > 0) ; /* a re-scan resumed: the object its last RESCAN event names */
        else if (j->o.resume || (j->o.rescan && !j->cl.surface))
            snprintf(j->surface, sizeof j->surface, "%s", j->o.surface ? j->o.surface : "");
        else if ((st = vp_scan_dry_surface(&j->b, j->o.rescan ? j->cl.surface : j->o.surface, j->surface, sizeof j->surface,
                                           err, sizeof err)) != VP_OK) {
            fprintf(stderr, "scan: --surface: %s\n", err);
            return j->rc;
        }
        if (!j->o.seed) j->o.seed = (unsigned long long)j->b.sim_seed;
    }
    if (!j->o.have_sync) {
        vp_logwriter_config_default(&j->o.sync);
        if (j->b.log_sync[0]) vp_logwriter_parse_sync(j->b.log_sync, &j->o.sync);
    }
    /* the log and mesh paths are checked before anything is written */
    if (j->o.out) st = vp_path_cat(j->prefix, sizeof j->prefix, j->o.out, "", err, sizeof err);
    else {
        size_t len = strlen(j->o.log);
        if (len > 6 && !strcmp(j->o.log + len - 6, ".vplog")) {
            st = vp_path_cat(j->prefix, sizeof j->prefix, j->o.log, "", err, sizeof err);
            if (st == VP_OK) j->prefix[len - 6] = 0;
        } else
            st = vp_path_cat(j->prefix, sizeof j->prefix, j->o.log, ".mesh", err, sizeof err);
    }
    {
        char chk[VP_PATH_MAX];
        if (st == VP_OK) st = vp_path_cat(chk, sizeof chk, j->prefix, ".ply", err, sizeof err);
        if (st == VP_OK) st = vp_path_cat(chk, sizeof chk, j->o.log, "", err, sizeof err);
    }
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); j->rc = 2; return j->rc; }
    return -1;
}

/* The machine, the planner's configuration (a dry run's object inside Omega), the planner.
 * -1: go on; else the exit status. */
static int scan_prepare(scan_job_t *j)
{
    char err[1600];
    int st;
    int k;
    int nint = 1;

    st = vp_scan_open(&j->dev, &j->b, j->o.dry, j->o.dry ? j->surface : NULL, 0, j->o.seed, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); return j->rc; }
    j->dev_open = 1;
    j->dev.estop_at = j->o.estop_at;
    j->dev.near_measure = j->o.near;

    /* ---- the planner's configuration: the board's scan volume, eps and rangefinder ---- */
    vp_board_planner_config(&j->b, &j->cfg);
    j->cfg.eps = j->o.eps;
    /* an accuracy target: facets refined where they stray from the surface (paper 002's sizing
     * by the distance bound), down to a floor */
    if (j->o.accuracy > 0) vp_accuracy_config(&j->cfg, j->o.accuracy);
    j->cfg.noise_tol = j->o.noise_tol;
    j->dev.noise_tol = j->o.noise_tol;
    j->dev.reach_out = j->o.reach_out;
    j->cfg.confirm_misses = (uint32_t)j->o.confirm;
    {
        /* eps within what the planner can resolve in double precision (as sim says it) */
        vp_sim_options_t none;
        memset(&none, 0, sizeof none);
        if (vp_sim_check_ranges(&j->cfg, 0.0, &none, err, sizeof err) != VP_OK) {
            fprintf(stderr, "scan: %s\n", err);
            return j->rc;
        }
    }
    if (j->o.dry) {
        /* the simulated object must lie in Omega; the board's interior point must be inside it
         * (else the object's own interior points stand in for it) */
        vp_surface_t *s = j->dev.dr->surf;
        double lo[3], hi[3], gap = j->b.clearance;   /* with a clearance the head stays outside Omega */
        int inside = 1;
        vp_surface_bbox(s, lo, hi);
        for (k = 0; k < 3; k++)
            if (j->b.omega_kind == VP_OMEGA_BOX && (lo[k] - gap <= j->b.omega_lo[k] || hi[k] + gap >= j->b.omega_hi[k])) inside = 0;
        if (j->b.omega_kind == VP_OMEGA_BALL) {
            /* the object's farthest point from the centre, from points sampled on its surface */
            size_t q, ns = 4000;
            double *xyz = malloc(3 * ns * sizeof *xyz), r2 = (j->b.omega_radius - gap) * (j->b.omega_radius - gap);
            if (xyz) {
                ns = vp_surface_sample(s, ns, 1, xyz);
                for (q = 0; q < ns; q++) {
                    double dd = 0;
                    for (k = 0; k < 3; k++) dd += (xyz[3 * q + k] - j->b.omega_center[k]) * (xyz[3 * q + k] - j->b.omega_center[k]);
                    if (dd >= r2) inside = 0;
                }
                free(xyz);
            }
        }
        if (j->o.reach_out && (vp_surface_inside(s, j->b.start) || vp_surface_distance(s, j->b.start) < 1.0)) {
            fprintf(stderr, "scan: the simulated object %s holds the laser origin's start %g %g %g (or comes within 1 mm "
                    "of it; [omega] start in %s): the head would stand in it at power-on\n", j->surface, j->b.start[0],
                    j->b.start[1], j->b.start[2], j->b.path);
            return j->rc;
        }
        if (!inside && !j->o.reach_out) {
            fprintf(stderr, "scan: the simulated object %s (box %.4g %.4g %.4g .. %.4g %.4g %.4g) is not inside the "
                    "board's Omega%s ([omega] in %s; --reach-out rehearses such a misplaced object)\n", j->surface,
                    lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
                    gap > 0 ? " by the clearance (the head stays outside Omega)" : "", j->b.path);
            return j->rc;
        }
        if (vp_surface_components(s) > 1 || !vp_surface_inside(s, j->b.interior)) {
            nint = vp_surface_components(s);
            if (nint > VP_PLANNER_MAX_SEEDS) { fprintf(stderr, "scan: the object has %d components (at most %d)\n", nint, VP_PLANNER_MAX_SEEDS); return j->rc; }
            for (k = 0; k < nint; k++) vp_surface_interior_point(s, k, j->cfg.interior[k]);
            j->cfg.ninterior = (uint32_t)nint;
        }
    }
    if (j->have_L && (j->o.rescan || j->rescans > 0)) {
        /* a re-scan keeps the session's configuration: its interior points too (the object now
         * may differ from the one they were taken from) */
        memcpy(j->cfg.interior, j->L.header.cfg.interior, sizeof j->cfg.interior);
        j->cfg.ninterior = j->L.header.cfg.ninterior;
    }
    if (j->o.far) {
        /* a miss asked that far is trusted only where every beam ends on a spot: without walls
         * the sight rule (vp_planner_spot_hidden) would find an occluder in far more of them */
        if (!(j->b.clearance > 0) || !j->b.have_backdrop) {
            fprintf(stderr, "scan: --far-reads needs a board in body mode ([omega] clearance) with a backdrop "
                    "([rangefinder] backdrop)\n");
            j->rc = 2;
            return j->rc;
        }
        j->cfg.flags |= VP_PLAN_FAR_READS;
    }
    if (j->o.by_length || (j->have_L && (j->o.resume || j->o.rescan) && j->L.header.version < 6u)) {
        /* moves by length: asked for, or a session logged before its moves were weighed by the
         * axes' speeds (it goes on as begun) */
        memset(j->cfg.axis_time, 0, sizeof j->cfg.axis_time);
        memset(j->cfg.pan_travel, 0, sizeof j->cfg.pan_travel);
    }
    j->pl = malloc(sizeof *j->pl);
    j->arena = malloc(j->o.arena);
    if (!j->pl || !j->arena) { fprintf(stderr, "scan: cannot allocate the %zu-byte arena\n", j->o.arena); return j->rc; }
    st = vp_planner_init(j->pl, j->arena, j->o.arena, &j->cfg);
    if (st != VP_OK) {
        fprintf(stderr, "scan: planner: %s (%s)\n", vp_strerror(st),
                st == VP_ENOMEM ? "the arena is too small: --arena" : "check [omega] in the board file");
        return j->rc;
    }
    {
        fprintf(stderr, "scan: board %s (%s)%s%s\n", j->b.name, j->b.path, j->o.dry ? ", dry run on host-sim: " : "",
                j->o.dry ? j->surface : "");
        fprintf(stderr, "scan: eps %g mm, rangefinder %g..%g mm from %s\n", j->o.eps, j->b.tri.min_range, j->b.tri.max_range,
                model_source(&j->b));
        if (j->b.calib_missing)
            fprintf(stderr, "scan: note: the calibration file %s does not exist yet (voroprobe calibrate writes it)\n", j->b.calib_path);
        if (j->o.accuracy > 0 && j->cfg.noise_tol > j->cfg.max_distance)
            fprintf(stderr, "scan: note: --accuracy %g refines facets that stray more than %.3g mm from the surface, but the "
                    "hits are trusted only to %g mm (--noise-tol): that is the bound used, and the target may not be met; "
                    "lower --noise-tol to what the rangefinder shows (a dry run prints the probe error)\n",
                    j->o.accuracy, j->cfg.max_distance, j->cfg.noise_tol);
        if (j->o.dry && vp_surface_components(j->dev.dr->surf) > 1)
            fprintf(stderr, "scan: note: the simulated object has %u components: a point inside each is used\n",
                    j->cfg.ninterior);
        else if (j->o.dry && !vp_surface_inside(j->dev.dr->surf, j->b.interior))
            fprintf(stderr, "scan: note: the board's interior point is not inside the simulated object: its own %u "
                    "interior point(s) are used\n", j->cfg.ninterior);
    }
    return -1;
}

/* The log: new, or replayed and continued (a complete one only gives its mesh).
 * -1: go on; else the exit status. */
static int scan_log_open(scan_job_t *j)
{
    char err[1600];
    char sub[600];
    char note[VP_LOGFMT_NOTE_MAX + 1];
    char text[VP_LOGFMT_TEXT_MAX + 1];
    int st;

    j->run.dev = &j->dev;
    j->run.pl = j->pl;
    j->run.quiet = j->o.quiet;
    vp_progress_init(&j->run.prog, stderr);
    j->run.hw = !j->o.dry;
    j->run.stop_after = j->o.stop_after;
    j->run.w.raw = &j->dev.raw;
    if (j->o.resume) {
        vp_replay_t R;
        char why[420];
        if (!vp_sessionlog_same_config(&j->L.header.cfg, j->L.header.arena_bytes, &j->cfg, (uint64_t)j->o.arena, why, sizeof why)) {
            fprintf(stderr, "scan: %s: the scan configuration is not the logged one (%s): the board file or the "
                    "calibration changed since\n", j->o.log, why);
            return j->rc;
        }
        vp_sessionlog_stop_text(&j->L, sub, sizeof sub);
        fprintf(stderr, "resume %s: %s\n", j->o.log, sub);
        vp_replay_init_state(&R, j->pl, &j->L);
        st = vp_replay_run(&R, &j->L, j->L.n, why, sizeof why);
        if (st != VP_OK) { fprintf(stderr, "scan: %s: replay failed: %s\n", j->o.log, why); return j->rc; }
        if (R.touched_outside) { fprintf(stderr, "scan: %s: %s\n", j->o.log, VP_REPLAY_TOUCHED_OUTSIDE_TEXT); return j->rc; }
        j->replayed = R.applied;
        fprintf(stderr, "resume: %u records replayed (%llu probes, %llu moves)%s\n", R.applied,
                (unsigned long long)R.probes, (unsigned long long)R.moves, j->L.done ? "; the session is already complete" : "");
        if (j->L.done) {
            st = write_mesh(j->pl, j->prefix, &j->mesh, err, sizeof err);
            if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); return j->rc; }
            printf("log: %s (complete; %u records replayed, nothing appended)\n", j->o.log, j->replayed);
            printf("mesh: %u vertices, %u facets\nwrote %s.ply and %s.off\n", (unsigned)j->mesh.nv, (unsigned)j->mesh.nt, j->prefix, j->prefix);
            j->rc = 0;
            return j->rc;
        }
        st = vp_logwriter_open_append_read(&j->run.w.file, j->o.log, j->L.good_bytes, j->L.n, (uint64_t)j->L.size, &j->o.sync);
        if (st == VP_OK) {
            snprintf(text, sizeof text, "resumed after record %d", (int)j->L.n - 1);
            st = vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_RESUME, 0, text);
        }
        if (R.rescans > 0) j->before = R.at_rescan;
    } else if (j->o.rescan) {
        /* a re-scan: the old session replayed, copied to the new log, a RESCAN event */
        vp_replay_t R;
        char why[420];
        if (!vp_sessionlog_same_config(&j->L.header.cfg, j->L.header.arena_bytes, &j->cfg, (uint64_t)j->o.arena, why, sizeof why)) {
            fprintf(stderr, "scan: %s: the scan configuration is not the logged one (%s): the board file or the "
                    "calibration changed since; a re-scan needs the session's\n", j->o.rescan, why);
            return j->rc;
        }
        vp_replay_init_state(&R, j->pl, &j->L);
        st = vp_replay_run(&R, &j->L, j->L.n, why, sizeof why);
        if (st != VP_OK) { fprintf(stderr, "scan: %s: replay failed: %s\n", j->o.rescan, why); return j->rc; }
        if (R.touched_outside) { fprintf(stderr, "scan: %s: %s\n", j->o.rescan, VP_REPLAY_TOUCHED_OUTSIDE_TEXT); return j->rc; }
        j->replayed = R.applied;
        st = vp_planner_rescan_with(j->pl, j->cl.sparse ? VP_RESCAN_SPARSE : 0u);
        if (st != VP_OK) { fprintf(stderr, "scan: %s: the planner cannot re-scan this session: %s\n", j->o.rescan, vp_strerror(st)); return j->rc; }
        vp_planner_get_stats(j->pl, &j->before);
        fprintf(stderr, "rescan %s: %u records replayed (%llu probes); %u samples to measure again\n", j->o.rescan, R.applied,
                (unsigned long long)R.probes, j->pl->dt.ninserted);
        if (vp_mkdirs_for(j->o.log) != 0) { fprintf(stderr, "scan: cannot create the folder of %s: %s\n", j->o.log, strerror(errno)); return j->rc; }
        st = vp_logwriter_create_copy(&j->run.w.file, j->o.log, j->L.data, j->L.good_bytes, j->L.n, &j->o.sync);
        if (j->o.dry) snprintf(text, sizeof text, "--surface %.240s", j->surface);
        else snprintf(text, sizeof text, "the object on the machine now");
        if (st == VP_OK) st = vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_RESCAN, j->cl.sparse ? VP_RESCAN_SPARSE : 0u, text);
    } else {
        vp_logfmt_header_t h;
        scan_note(&j->o, j->board_path, j->o.eps, j->surface, note, sizeof note);
        vp_logfmt_header_init(&h, &j->cfg, (uint64_t)j->o.arena, VP_LOGFMT_UNITS_MM, j->b.name, note);
        if (vp_mkdirs_for(j->o.log) != 0) { fprintf(stderr, "scan: cannot create the folder of %s: %s\n", j->o.log, strerror(errno)); return j->rc; }
        st = vp_logwriter_create(&j->run.w.file, j->o.log, &h, &j->o.sync);
        if (st == VP_OK)
            st = vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_START, 0, j->o.dry ? "voroprobe scan (dry run on host-sim)" : "voroprobe scan");
    }
    if (st == VP_OK) {
        /* the rangefinder model in use */
        vp_logfmt_record_t ev;
        const vp_tri_model_t *t = &j->b.tri;
        snprintf(text, sizeof text, "rangefinder: %.150s; line %.9g %.9g %.9g %.9g", model_source(&j->b), t->p0[0], t->p0[1],
                 t->e[0], t->e[1]);
        vp_logfmt_record_event(&ev, 0, VP_LOGFMT_EV_CALIBRATION, j->b.calibrated, text);
        ev.value[0] = t->a; ev.value[1] = t->b; ev.value[2] = t->c; ev.value[3] = t->max_range;
        st = vp_logwriter_append(&j->run.w.file, &ev);
    }
    if (st != VP_OK) {
        if (j->run.w.file.busy)
            fprintf(stderr, "scan: log %s is being written by another process: it is left as it is (wait for that "
                    "scan to end, or give another --log)\n", j->o.log);
        else if (j->run.w.file.changed)
            fprintf(stderr, "scan: log %s was written by another process while it was read: it is left as it is "
                    "(resume again)\n", j->o.log);
        else
            fprintf(stderr, "scan: cannot write the session log %s: %s\n", j->o.log, strerror(errno));
        return j->rc;
    }
    j->log_open = 1;
    return -1;
}

/* Home, the start, back to where a resumed scan stopped.
 * -1: go on; else the exit status. */
static int scan_home(scan_job_t *j)
{
    char err[1600];
    char text[VP_LOGFMT_TEXT_MAX + 1];
    int st;

    vp_scan_catch_signals();
    st = vp_scan_home(&j->dev, err, sizeof err);
    if (st == VP_OK) st = vp_scan_goto(&j->dev, j->b.start, err, sizeof err);
    if (st == VP_OK && j->o.resume) st = vp_scan_return(&j->dev, &j->L, j->L.n, j->b.start, stderr, err, sizeof err);
    if (vp_scan_stop && (st == VP_OK || j->dev.m->step.fault == VP_STEP_FAULT_NONE)) { st = VP_EABORT; j->run.paused = 1; }
    if (st != VP_OK && !j->run.paused) {
        fprintf(stderr, "scan: %s\n", err);
        snprintf(text, sizeof text, "%.250s", err);
        scan_log_stepping(&j->run);
        vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_FAULT, st, text);
        fprintf(stderr, "scan: stopped before the scan went on; the log %s is resumable: voroprobe scan --log %s --resume\n",
                j->o.log, j->o.log);
        /* the summary (and --json) still follow: what the machine did, the mesh as the log has it */
        snprintf(j->stop_text, sizeof j->stop_text, "%s", text);
        j->home_failed = 1;
        return -1;
    }
    j->st_home = st;
    return -1;
}

/* The scan, and the event it ends with (j->rc: its exit status so far).
 * -1: go on; else the exit status. */
static int scan_go(scan_job_t *j)
{
    char text[VP_LOGFMT_TEXT_MAX + 1];
    int st = j->st_home;
    vp_session_result_t res;

    if (j->home_failed) return -1;   /* said and logged by scan_home; the summary follows */
    if (st == VP_OK) {
        vp_device_ops_t ops = vp_scan_ops(&j->dev);
        vp_session_hooks_t hooks;
        j->dev.pl = j->pl;
        const vp_session_hooks_t *hp = &hooks;
        hooks.ctx = &j->run;
        hooks.after = scan_after;
        if (vp_live_cli_begin(&j->live, j->pl, &hp, j->o.quiet ? NULL : stderr, "scan")) return 1;
        j->run.t0 = vp_scan_seconds(&j->dev);
        j->run.wall0 = vp_rt_seconds();
        j->run.probes0 = j->dev.probes;
        if (!j->o.quiet) fprintf(stderr, "scan: homed%s; scanning (Ctrl-C stops after the current command)\n", j->o.resume ? ", back where the log left off" : "");
        vp_session_run(j->pl, &ops, hp, 0, NULL, &res);
        st = res.status;
        j->unseen_misses = res.unseen_misses;
        if (!j->o.quiet) scan_progress(&j->run, 1);
        if (j->live.lv) { /* the live view's last frame: the mesh as the scan left it */
            vp_mesh_t m;
            vp_mesh_init(&m);
            vp_session_mesh(j->pl, &m);
            vp_live_cli_end(&j->live, st == VP_OK ? "done" : j->run.paused ? "stopped" : "error", &m,
                            j->o.quiet ? NULL : stderr, "scan");
            vp_mesh_free(&m);
        }
    }
    if (j->run.w.failed) {
        fprintf(stderr, "scan: writing the session log %s failed: %s; the scan stopped\n", j->o.log, strerror(errno));
    } else if (j->run.paused) {
        snprintf(text, sizeof text, "paused after %lu commands (Ctrl-C)", j->run.n);
        scan_log_stepping(&j->run);
        vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_PAUSE, 0, text);
        fprintf(stderr, "scan: %s; resume with: voroprobe scan --log %s --resume\n", text, j->o.log);
        snprintf(j->stop_text, sizeof j->stop_text, "%s", text);
        j->rc = VP_EXIT_STOPPED;
    } else if (st == VP_OK) {
        j->rc = 0;
    } else if (j->dev.fault) {
        char why[420];
        const vp_cmd_t *c = &j->dev.fault_cmd;
        vp_scan_fault_text(&j->dev, why, sizeof why);
        if (c->kind == VP_CMD_MOVE)
            snprintf(text, sizeof text, "command %lu (move to %.6g %.6g %.6g): %.160s", j->run.n + 1, c->to[0], c->to[1], c->to[2], why);
        else
            snprintf(text, sizeof text, "command %lu (probe from %.6g %.6g %.6g along %.4f %.4f %.4f): %.120s", j->run.n + 1,
                     c->from[0], c->from[1], c->from[2], c->dir[0], c->dir[1], c->dir[2], why);
        scan_log_stepping(&j->run);
        vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_FAULT, j->dev.fault, text);
        snprintf(j->stop_text, sizeof j->stop_text, "%s", text);
        fprintf(stderr, "scan: stopped at %s\nscan: the log %s is resumable: voroprobe scan --log %s --resume%s\n", text,
                j->o.log, j->o.log, j->dev.m->step.fault == VP_STEP_FAULT_ESTOP ? " (after releasing the e-stop)" : "");
    } else {
        if (st == VP_ERANGE && j->dev.contacts > 0)
            snprintf(text, sizeof text, "planner: the head's contact switch closed outside Omega: the object reaches out "
                     "of [omega] (it must lie the clearance inside it); the head stopped and backed off");
        else
            snprintf(text, sizeof text, "planner: %s", st == VP_ERANGE ? "the probe towards an interior point found no "
                     "surface: is [omega] interior inside the object?" : vp_strerror(st));
        scan_log_stepping(&j->run);
        vp_logwriter_event(&j->run.w.file, VP_LOGFMT_EV_FAULT, st, text);
        snprintf(j->stop_text, sizeof j->stop_text, "%s", text);
        fprintf(stderr, "scan: the scan stopped: %s%s\n", text, st == VP_ENOMEM ? " (the arena is full: --arena)" : "");
        if (j->dev.unreadable) {
            char why[420];
            vp_scan_unreadable_text(&j->dev, why, sizeof why);
            fprintf(stderr, "scan: %lu frame(s) could not be read (%s)%s\n", j->dev.unreadable, why,
                    j->dev.unread_why[0] ? ": a spot off the laser line means the rangefinder model is off: calibrate" : "");
        }
    }
    vp_logwriter_close(&j->run.w.file);
    j->log_open = 0;
    vp_audit_keep(j->o.log); /* for an independent proof check (VP_AUDIT_DIR) */
    return -1;
}

/* The mesh and the figures. Returns the exit status. */
static int scan_report(scan_job_t *j)
{
    char err[1600];
    int st;

    st = write_mesh(j->pl, j->prefix, &j->mesh, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); j->rc = 1; return j->rc; }
    {
        vp_planner_stats_t ps;
        vp_meshcheck_t mc;
        vp_machine_t *m = j->dev.m;
        double hausdorff = -1;
        int have_mc = vp_meshcheck_analyze(&j->mesh, &mc) == VP_OK;
        double mt = vp_scan_seconds(&j->dev) - j->run.t0;
        vp_planner_get_stats(j->pl, &ps);
        printf("scan: %s after %lu commands of this run%s\n", j->rc == 0 ? "DONE" : j->rc == 3 ? "paused" : "stopped", j->run.n,
               j->o.resume ? " (resumed)" : "");
        printf("log: %s (%u records replayed + %lu written, %lu syncs)\n", j->o.log, j->replayed, j->run.w.file.records,
               j->run.w.file.syncs);
        if (j->o.rescan || j->rescans > 0)
            printf("rescan of %s: %llu probes since the re-scan began (the session re-scanned took %llu); samples: %llu "
                   "kept, %llu not measured (their neighbours held), %llu removed (%llu moved: the point measured took their place; %llu covered or out of reach of "
                   "every line), %llu measured along their normal; %llu route steps proven again (%llu blocked)\n", j->o.rescan ? j->o.rescan : j->o.log,
                   (unsigned long long)(ps.probes - j->before.probes), (unsigned long long)j->before.probes,
                   (unsigned long long)ps.rescan_kept, (unsigned long long)ps.rescan_skipped,
                   (unsigned long long)ps.rescan_dropped, (unsigned long long)ps.rescan_moved, (unsigned long long)ps.rescan_unseen, (unsigned long long)ps.rescan_normal,
                   (unsigned long long)ps.reproved, (unsigned long long)ps.reprove_blocked);
        printf("mesh: %u vertices, %u facets; %s, %d component(s), genus %d\n", (unsigned)j->mesh.nv, (unsigned)j->mesh.nt,
               have_mc && mc.closed_manifold ? "closed 2-manifold" : "NOT closed (yet)", have_mc ? mc.components : -1,
               have_mc ? mc.genus : -1);
        {
            char nh[80] = "", tc[120] = "";
            if (j->o.near && j->dev.near) snprintf(nh, sizeof nh, " (%lu nearer than %g mm, measured)", j->dev.near, j->b.tri.min_range);
            if (j->dev.too_close)
                snprintf(tc, sizeof tc, " (%lu nearer than %g mm, %lu unreadable frames)", j->dev.too_close - j->dev.unreadable,
                         j->b.tri.min_range, j->dev.unreadable);
            printf("machine: %lu probes: %lu hits%s, %lu misses, %lu too close%s; %lu moves, laser origin travel %.0f mm, "
                   "%.0f s of machine time%s\n", j->dev.hits + j->dev.misses + j->dev.too_close, j->dev.hits, nh, j->dev.misses,
                   j->dev.too_close, tc, m->st.moves,
                   m->st.travel, mt, j->o.dry ? " (simulated)" : "");
            printf("machine time of this run by planner stage: seed %.0f s (%lu commands), refinement %.0f s (%lu), "
                   "closing %.0f s (%lu); %.1f s per vertex%s\n", j->dev.stage_s[VP_STAGE_SEED], j->dev.stage_cmds[VP_STAGE_SEED],
                   j->dev.stage_s[VP_STAGE_REFINE], j->dev.stage_cmds[VP_STAGE_REFINE], j->dev.stage_s[VP_STAGE_CLOSE],
                   j->dev.stage_cmds[VP_STAGE_CLOSE], j->mesh.nv ? mt / (double)j->mesh.nv : 0.0, j->o.dry ? " (simulated)" : "");
            printf("machine time by motion: moves %.0f s (%lu, %.2f s each), aims %.0f s, settling %.0f s, frames and "
                   "reading %.0f s (%.2f s per probe for the three)%s\n", 1e-9 * (double)m->st.move_ns, m->st.moves,
                   m->st.moves ? 1e-9 * (double)m->st.move_ns / (double)m->st.moves : 0.0, 1e-9 * (double)m->st.aim_ns,
                   1e-9 * (double)m->st.settle_ns, 1e-9 * (double)m->st.read_ns,
                   m->st.probes ? 1e-9 * (double)(m->st.aim_ns + m->st.settle_ns + m->st.read_ns) / (double)m->st.probes : 0.0,
                   j->o.dry ? " (simulated)" : "");
            if (m->st.moves_turning)
                printf("machine: %lu MOVEs turned the head towards their PROBE on the way (the laser origin on the "
                       "line: the ball rule)\n", m->st.moves_turning);
            if (m->st.paths)
                printf("machine: %lu paths of %lu MOVEs in all, each made at once (the waypoints between passed "
                       "without stopping where the axes' jerk allows)\n", m->st.paths, m->st.path_moves);
            if (m->st.turns)
                printf("machine: %lu MOVEs turned the head about the laser origin first (its orientation put the "
                       "carriage outside its travel at the MOVE's end)\n", m->st.turns);
            if (j->dev.unreadable) {
                char why[420];
                vp_scan_unreadable_text(&j->dev, why, sizeof why);
                printf("unreadable frames: %s\n", why);
            }
            if (j->unseen_misses)
                printf("unseen misses: %lu frames with no spot where the mesh found so far or the space still unknown "
                       "may hide the spot from the camera (no walls round the machine show a miss for what it is: "
                       "[rangefinder] backdrop); taken as unreadable, never free space\n", j->unseen_misses);
        }
        {
            char rep[VP_LOGFMT_TEXT_MAX + 1];
            double v[4];
            vp_scan_step_report(&j->dev, rep, sizeof rep, v);
            printf("%s%s\n", rep, j->o.dry ? " (simulated)" : "");
        }
        printf("planner: %llu probes in all, largest ball %.4g mm (eps %g), arena peak %zu bytes\n",
               (unsigned long long)ps.probes, ps.max_ball, j->o.eps, ps.arena_peak);
        if (vp_planner_timed(&j->cfg))
            printf("planner: moves weighed by the axes' top speeds (body mode): the next probe the one the head reaches "
                   "soonest; %llu of %llu routes taken level round Omega (the slowest axis moved least)\n",
                   (unsigned long long)ps.level_routes, (unsigned long long)ps.routes);
        if (j->b.clearance > 0 && j->b.min_feature > 0)
            printf("tubes: min feature %g mm, margin %g mm ([omega]): %llu moves inside Omega, %llu probes started "
                   "inside it, %llu of them past what occluded their line; %llu tubes surveyed first (%llu probes, "
                   "%llu found blocked)\n", j->b.min_feature, j->b.feature_margin,
                   (unsigned long long)ps.tube_moves, (unsigned long long)(ps.tube_starts + ps.vantages),
                   (unsigned long long)ps.vantages, (unsigned long long)ps.surveys,
                   (unsigned long long)ps.survey_probes, (unsigned long long)ps.surveys_failed);
        if (j->cfg.flags & VP_PLAN_FAR_READS) vp_bodyreport_far(stdout, &ps);
        if (j->b.clearance > 0 && ps.aims > 0) vp_bodyreport_aims(stdout, &ps);
        if (j->rc == 0 && have_mc && !mc.closed_manifold) {
            printf("warning: the planner said DONE but the mesh is not closed (%zu boundary edges): the planner leaves open "
                   "what its probes could not see (%llu too-close results%s, %llu Voronoi edges occluded from dOmega)\n",
                   mc.boundary_edges, (unsigned long long)ps.too_close,
                   j->o.near || !ps.too_close || !j->dev.near ? "" : ": --near-spots measure reports near spots as hits",
                   (unsigned long long)ps.occluded);
            if (j->dev.unread_why[5])
                printf("warning: %lu frames showed no spot where the backdrop would: a surface too dark for the "
                       "exposure ([camera] exposure_us, gain) or spots hidden from the camera; neither is taken for "
                       "free space\n", j->dev.unread_why[5]);
            j->rc = VP_EXIT_NOT_CLOSED;
        }
        if (j->rc == 0 && ps.missing_components > 0) {
            printf("warning: the planner said DONE but %u interior point(s) are not enclosed by the mesh (H2): "
                   "certify names them\n", ps.missing_components);
            j->rc = VP_EXIT_NOT_CLOSED;
        }
        if (j->o.dry && j->dev.through > 0) {
            printf("SAFETY: %lu moves of this dry run went through the object: on the machine that is a crash "
                   "into the part (voroprobe log verify %s names the first unproven move)\n", j->dev.through, j->o.log);
            j->rc = VP_EXIT_COLLISION;
        }
        if (j->o.dry && j->dev.past > 0) {
            printf("SAFETY: %lu probes of this dry run read the surface more than %g mm beyond where it is: the "
                   "planner took space inside the object for free\n", j->dev.past, j->dev.noise_tol);
            j->rc = VP_EXIT_COLLISION;
        }
        if (j->o.dry && j->dev.head_hits > 0) {
            char parts[400];
            vp_scan_head_text(&j->dev, parts, sizeof parts);
            printf("SAFETY: %lu motions of this dry run brought the head's body within %g mm of the object (%s): on "
                   "the machine that is a crash into the part\n", j->dev.head_hits, j->dev.head_tol, parts);
            j->rc = VP_EXIT_COLLISION;
        }
        if (j->o.dry) {
            vp_hausdorff_t hd;
            printf("dry run: probe error against the true object rms %.3f mm, worst %.3f mm (%lu hits); %lu false hits, "
                   "%lu hidden spots, %lu moves through the object\n",
                   j->dev.true_n ? sqrt(j->dev.err2 / (double)j->dev.true_n) : 0.0, j->dev.err_max, j->dev.true_n, j->dev.false_hits,
                   j->dev.false_misses, j->dev.through);
            if (j->unseen_misses && j->dev.false_misses)
                printf("dry run: %lu of the hidden spots taken for free space (%lu fed as unreadable by the sight rule)\n",
                       j->dev.false_misses - j->dev.false_misses_unseen, j->dev.false_misses_unseen);
            if (j->dev.grazing)
                printf("dry run: %lu hits where the beam grazes a limb or clips a thin edge (the point, and the ray's "
                       "free part, within %g mm of the surface)\n", j->dev.grazing, j->dev.noise_tol);
            if (j->dev.board.line_laser)
                printf("dry run: line laser: %lu rays from the probes' frames, error against the true object rms "
                       "%.3f mm, worst %.3f mm; %lu false (off the surface by more than %g mm); %lu probes with the "
                       "beam in a gap of the line\n", j->dev.rays,
                       j->dev.rays ? sqrt(j->dev.ray_err2 / (double)j->dev.rays) : 0.0, j->dev.ray_err_max,
                       j->dev.ray_false, j->dev.noise_tol, m->st.line_gaps);
            if (j->dev.contacts) {
                char past[80];
                snprintf(past, sizeof past, "where the switch closed, within %g mm of the object", VP_DRYRUN_MOUNT_NEED);
                printf("dry run: the contact switch stopped %lu move(s), %s at most %.3f mm past %s (contact_stop %g mm)\n",
                       j->dev.contacts, j->dev.board.contact_mount ? "the head (a bound over the parts its mount senses)" :
                       "the laser origin", j->dev.touch_depth_max, j->dev.board.contact_mount ? past : "the surface",
                       j->dev.board.contact_stop);
            }
            {
                char parts[400];
                vp_scan_head_text(&j->dev, parts, sizeof parts);
                printf("dry run: head: %lu head collisions in %lu motions (%s; swept, %g mm tolerance, %lu distance "
                       "queries)\n", j->dev.head_hits, j->dev.head_motions, parts, j->dev.head_tol, j->dev.head_evals);
            }
            if (j->rc == 0 && j->mesh.nt > 0 && vp_hausdorff(&j->mesh, j->dev.dr->surf, 20000, 7, &hd) == VP_OK) {
                printf("dry run: the mesh is within %.2f mm of the object (Hausdorff), eps %g mm\n", hd.hausdorff, j->o.eps);
                hausdorff = hd.hausdorff;
                if (j->o.accuracy > 0) {
                    printf("accuracy: target %g mm, measured %.3f mm: %s (distance bound %.3g mm, floor %.3g mm)\n",
                           j->o.accuracy, hd.hausdorff, hd.hausdorff <= j->o.accuracy ? "within" : "NOT within",
                           j->cfg.max_distance, j->cfg.min_size);
                    if (hd.hausdorff > j->o.accuracy) j->rc = VP_EXIT_NOT_WITHIN_TARGET;
                }
            }
            {
                /* the object is known here: a closed mesh of another genus or with other parts is
                 * a wrong answer, said so (before a missed target, as vp_outcome orders them) */
                const vp_surface_t *surf = j->dev.dr->surf;
                if ((j->rc == 0 || j->rc == VP_EXIT_NOT_WITHIN_TARGET) && have_mc && vp_topology_differs(&mc, surf)) {
                    printf("dry run: the mesh has genus %d in %d component(s), the object genus %d in %d: wrong topology\n",
                           mc.genus, mc.components, vp_surface_genus(surf), vp_surface_components(surf));
                    j->rc = VP_EXIT_WRONG_TOPOLOGY;
                }
            }
            printf("dry run: %d frames rendered, %.1f s wall\n", (int)m->st.frames, vp_rt_seconds() - j->wall0);
        }
        printf("wrote %s.ply and %s.off\n", j->prefix, j->prefix);
        if (j->o.json) {
            int i;
            printf("{\"status\":\"%s\",\"exit\":%d,\"probes\":%lu,\"vertices\":%u,\"facets\":%u,\"closed\":%s,"
                   "\"moves\":%lu,\"machine_s\":%.1f", vp_outcome_name(j->rc), j->rc,
                   j->dev.hits + j->dev.misses + j->dev.too_close, (unsigned)j->mesh.nv, (unsigned)j->mesh.nt,
                   have_mc && mc.closed_manifold ? "true" : "false", m->st.moves, mt);
            if (j->stop_text[0]) {
                printf(",\"stop_reason\":");
                vp_json_str(stdout, j->stop_text, 0);
            }
            printf(",\"machine_s_seed\":%.1f,\"machine_s_refine\":%.1f,\"machine_s_close\":%.1f,\"machine_s_per_vertex\":%.2f",
                   j->dev.stage_s[VP_STAGE_SEED], j->dev.stage_s[VP_STAGE_REFINE], j->dev.stage_s[VP_STAGE_CLOSE],
                   j->mesh.nv ? mt / (double)j->mesh.nv : 0.0);
            printf(",\"machine_s_moves\":%.1f,\"machine_s_aims\":%.1f,\"machine_s_settle\":%.1f,\"machine_s_read\":%.1f",
                   1e-9 * (double)m->st.move_ns, 1e-9 * (double)m->st.aim_ns, 1e-9 * (double)m->st.settle_ns,
                   1e-9 * (double)m->st.read_ns);
            printf(",\"turns\":%lu,\"moves_turning\":%lu,\"paths\":%lu,\"path_moves\":%lu", m->st.turns,
                   m->st.moves_turning, m->st.paths, m->st.path_moves);
            printf(",\"unreadable\":%lu,\"unreadable_no_spot\":%lu,\"unseen_misses\":%lu", j->dev.unreadable,
                   j->dev.unread_why[5], j->unseen_misses);
            if (j->o.rescan || j->rescans > 0)
                printf(",\"rescan\":{\"probes\":%llu,\"old_probes\":%llu,\"kept\":%llu,\"skipped\":%llu,\"dropped\":%llu,"
                       "\"moved\":%llu,\"unseen\":%llu,\"normal\":%llu,\"reproved\":%llu,\"blocked\":%llu}", (unsigned long long)(ps.probes - j->before.probes),
                       (unsigned long long)j->before.probes, (unsigned long long)ps.rescan_kept,
                       (unsigned long long)ps.rescan_skipped, (unsigned long long)ps.rescan_dropped, (unsigned long long)ps.rescan_moved,
                       (unsigned long long)ps.rescan_unseen,
                       (unsigned long long)ps.rescan_normal, (unsigned long long)ps.reproved,
                       (unsigned long long)ps.reprove_blocked);
            if (vp_planner_timed(&j->cfg))
                printf(",\"level_routes\":%llu,\"routes\":%llu", (unsigned long long)ps.level_routes,
                       (unsigned long long)ps.routes);
            {
                char body[512] = "";
                if (j->b.clearance > 0) vp_bodyreport_aims_json(body, sizeof body, &ps);
                if (j->cfg.flags & VP_PLAN_FAR_READS) vp_bodyreport_far_json(body, sizeof body, &ps);
                fputs(body, stdout);
            }
            if (j->b.clearance > 0 && j->b.min_feature > 0)
                printf(",\"min_feature\":%g,\"feature_margin\":%g,\"tube_moves\":%llu,\"tube_starts\":%llu,"
                       "\"vantages\":%llu,\"surveys\":%llu,\"survey_probes\":%llu", j->b.min_feature, j->b.feature_margin,
                       (unsigned long long)ps.tube_moves, (unsigned long long)ps.tube_starts,
                       (unsigned long long)ps.vantages, (unsigned long long)ps.surveys,
                       (unsigned long long)ps.survey_probes);
            if (j->o.dry) {
                printf(",\"through\":%lu,\"head_collisions\":%lu,\"head_motions\":%lu,\"head_parts\":{", j->dev.through,
                       j->dev.head_hits, j->dev.head_motions);
                for (i = 0; i < j->dev.board.head.nparts; i++)
                    printf("%s\"%s\":%lu", i ? "," : "", j->dev.board.head.part[i].name, j->dev.head_part[i]);
                printf("}");
                if (vp_board_has_contact(&j->b))
                    printf(",\"contacts\":%lu,\"touch_depth_max\":%.4f", j->dev.contacts, j->dev.touch_depth_max);
                if (j->o.reach_out) printf(",\"reach_out\":true");
                printf(",\"false_hits\":%lu,\"hidden_spots\":%lu,\"hidden_spots_free\":%lu", j->dev.false_hits,
                       j->dev.false_misses, j->dev.false_misses - j->dev.false_misses_unseen);
                if (hausdorff >= 0) printf(",\"hausdorff\":%.4f", hausdorff);
                if (j->o.accuracy > 0) printf(",\"accuracy_target\":%g", j->o.accuracy);
                if (j->dev.board.line_laser)
                    printf(",\"rays\":%lu,\"ray_rms\":%.4f,\"ray_worst\":%.4f,\"ray_false\":%lu", j->dev.rays,
                           j->dev.rays ? sqrt(j->dev.ray_err2 / (double)j->dev.rays) : 0.0, j->dev.ray_err_max, j->dev.ray_false);
            }
            printf("}\n");
        }
        if (have_mc) vp_meshcheck_free(&mc);
    }
    return j->rc;
}

int vp_cli_scan(int argc, char **argv)
{
    scan_job_t job, *j = &job;
    int rc;
    memset(j, 0, sizeof *j);
    j->rc = 1;
    j->wall0 = vp_rt_seconds();
    if ((rc = scan_parse(j, argc, argv)) >= 0) return rc;
    rc = scan_options(j);
    if (rc < 0) rc = scan_board(j);
    if (rc < 0) rc = scan_prepare(j);
    if (rc < 0) rc = scan_log_open(j);
    if (rc < 0) rc = scan_home(j);
    if (rc < 0) rc = scan_go(j);
    if (rc < 0) rc = scan_report(j);
    if (j->log_open) vp_logwriter_close(&j->run.w.file);
    if (j->dev_open) vp_scan_close(&j->dev);
    if (j->have_L) vp_sessionlog_free(&j->L);
    vp_mesh_free(&j->mesh);
    free(j->pl);
    free(j->arena);
    return rc;
}
