/* voroprobe scan: the device program. Home, then planner <-> machine until DONE, writing the
 * session log; Ctrl-C and the e-stop leave a resumable log; --resume continues one; --dry-run
 * runs the same loop with host-sim at the hardware boundary. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_backends.h"
#include "vp_cli.h"
#include "vp_log.h"
#include "vp_note.h"
#include "vp_logfile.h"
#include "vp_hausdorff.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_outcome.h"
#include "vp_audit.h"
#include "vp_scan.h"
#include "vp_session.h"
#include "vp_sim_opts.h"
#include "vp_sim_setup.h"
#include "vp_slog.h"
#include "vp_surface.h"

static void scan_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe scan --board FILE --log LOG [options]\n"
        "       voroprobe scan --log LOG --resume [options]\n"
        "Scans the object on a board's machine: homes, then moves and probes as the planner asks\n"
        "until it says DONE, writing the session log as it goes and the mesh at the end.\n"
        "  --board FILE     the machine (boards/*.ini); with --resume: the one in the log\n"
        "  --log LOG        the session log (replaced; with --resume: continued)\n"
        "  --resume         replay LOG, home, go back along the logged free route to where the\n"
        "                   scan stopped and continue it (the options come from the log)\n"
        "  --eps E          largest surface Delaunay ball radius, mm (default: the board's eps)\n"
        "  --calib FILE     rangefinder calibration file (default: the board's [rangefinder]\n"
        "                   calibration when that file exists, else the camera geometry)\n"
        "  --out PREFIX     mesh files PREFIX.ply and PREFIX.off (default: LOG without .vplog)\n"
        "  --sync POLICY    when the log is synced: record (each), N (records), Tms, N,Tms or\n"
        "                   close (default: the board's log_sync, else record)\n"
        "  --arena BYTES    planner memory (default 64M; K, M, G suffixes)\n"
        "  --noise-tol MM   hits are trusted to within this distance (default 2)\n"
        "  --confirm N      re-probes of a miss where a hit is expected (default 2)\n"
        "  --near-spots M   a spot nearer than the rangefinder's min_range: too-close (the planner\n"
        "                   gets VP_PROBE_TOO_CLOSE: never free, never sampled) or measure (a hit\n"
        "                   at the model's extrapolated distance); default: the board's near_spots\n"
        "  --quiet          no progress line\n"
        "Dry run (nothing moves, nothing sleeps):\n"
        "  --dry-run        the board's kinematics, step generator (recording GPIO backend on a\n"
        "                   simulated clock) and camera model (rendered frames) on host-sim\n"
        "  --surface SPEC   the simulated object: NAME (sphere, torus, genus2, ellipsoid, genus5,\n"
        "                   blobby), off:FILE or ply:FILE are sized to fit Omega around the board's\n"
        "                   interior point; a SPEC with '*' or '@' is taken as written, in mm\n"
        "                   (default: the board's [sim] surface, else an ellipsoid sized to Omega)\n"
        "  --seed N         seed of the frames' noise (default: the board's [sim] seed)\n"
        "Stopping: Ctrl-C stops after the current command (PAUSE event); a second Ctrl-C ends at\n"
        "once. The e-stop stops the pulses at once (FAULT event). Both leave the log resumable.\n"
        "Tests: --stop-after N (Ctrl-C after N commands), --estop-at N (dry run: e-stop during\n"
        "command N of this run).\n"
        "Exit status: 0 DONE (closed mesh), 1 failed or stopped by a fault, 2 usage, 3 paused, 4 DONE but\n"
        "the mesh is not closed (or misses a component), 5 a dry run moved through the object.\n");
    {
        char b[256];
        vp_backends_describe(b, sizeof b);
        fprintf(f, "Hardware backends built in: %s.\n", b);
    }
}

typedef struct scan_opts {
    const char *board, *log, *calib, *out, *surface;
    int near;                     /* -1: the board's near_spots; 0 too-close; 1 measure */
    double eps, noise_tol;
    int confirm, dry, resume, quiet, have_sync;
    size_t arena;
    unsigned long long seed;
    unsigned long stop_after, estop_at;
    unsigned long board_crc;
    int have_crc;
    vp_logfile_config_t sync;
} scan_opts_t;

static void scan_defaults(scan_opts_t *o)
{
    memset(o, 0, sizeof *o);
    o->noise_tol = 2;
    o->confirm = 2;
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
    if (!strcmp(a, "--resume") && !from_note) { o->resume = 1; return 0; }
    if (!strcmp(a, "--quiet") && !from_note) { o->quiet = 1; return 0; }
    if (strcmp(a, "--board") && strcmp(a, "--log") && strcmp(a, "--calib") && strcmp(a, "--out") &&
        strcmp(a, "--surface") && strcmp(a, "--eps") && strcmp(a, "--noise-tol") && strcmp(a, "--confirm") &&
        strcmp(a, "--arena") && strcmp(a, "--seed") && strcmp(a, "--sync") && strcmp(a, "--stop-after") &&
        strcmp(a, "--estop-at") && strcmp(a, "--near-spots") && (strcmp(a, "--board-crc") || !from_note))
        return 1;
    if (!val) { snprintf(err, n, "%s needs a value", a); return -1; }
    (*i)++;
    if (!strcmp(a, "--board")) o->board = val;
    else if (!strcmp(a, "--log")) o->log = val;
    else if (!strcmp(a, "--calib")) o->calib = val;
    else if (!strcmp(a, "--out")) o->out = val;
    else if (!strcmp(a, "--surface")) o->surface = val;
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
        if (vp_logfile_parse_sync(val, &o->sync)) {
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
    vp_note_put_opt(buf, n, &len, "--arena", "%zu", o->arena);
    vp_note_put_num(buf, n, &len, "--noise-tol", o->noise_tol);
    vp_note_put_opt(buf, n, &len, "--confirm", "%d", o->confirm);
    vp_note_put_str(buf, n, &len, "--near-spots", o->near ? "measure" : "too-close");
    if (o->calib) vp_note_put_str(buf, n, &len, "--calib", o->calib);
    if (o->dry) {
        vp_note_put(buf, n, &len, "--dry-run");
        vp_note_put_str(buf, n, &len, "--surface", surface);
        vp_note_put_opt(buf, n, &len, "--seed", "%llu", o->seed);
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
    while ((k = fread(buf, 1, sizeof buf, f)) > 0) c = vp_log_crc32(c, buf, k);
    fclose(f);
    *crc = c;
    return 0;
}

/* ---------- the run ---------- */

typedef struct scan_run {
    vp_slog_writer_t w;
    vp_scan_dev_t *dev;
    vp_planner_t *pl;
    unsigned long n, stop_after;
    int paused, quiet, hw;
    double next_report, wall0, t0;
    uint64_t probes0;
} scan_run_t;

static void scan_progress(scan_run_t *r, int final)
{
    vp_planner_stats_t st;
    double t = vp_scan_seconds(r->dev) - r->t0;
    vp_planner_get_stats(r->pl, &st);
    fprintf(stderr, "\r  commands %-7lu probes %-6llu (%llu hits, %llu too close)  facets %-6u bad balls %-5u "
            "largest ball %-7.3g  machine time %d:%02d:%02d%s",
            r->n, (unsigned long long)st.probes, (unsigned long long)st.hits, (unsigned long long)st.too_close,
            vp_planner_num_facets(r->pl), st.bad_balls, st.bad_balls ? st.max_ball : 0.0, (int)(t / 3600),
            (int)fmod(t / 60, 60), (int)fmod(t, 60), final ? "\n" : "");
    fflush(stderr);
}

static int scan_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    scan_run_t *r = ctx;
    int st = vp_slog_after(&r->w, cmd, res);
    if (st != VP_OK) return st;
    if (cmd->kind == VP_CMD_DONE) return VP_OK;
    r->n++;
    if (!r->quiet && (r->hw || vp_wall_seconds() > r->next_report)) {
        scan_progress(r, 0);
        r->next_report = vp_wall_seconds() + 0.5;
    }
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

int vp_cmd_scan(int argc, char **argv)
{
    scan_opts_t o, cl;
    vp_board_t b;
    vp_scan_dev_t dev;
    vp_slog_t L;
    vp_planner_config_t cfg;
    vp_planner_t *pl = NULL;
    void *arena = NULL;
    scan_run_t run;
    vp_session_result_t res;
    vp_mesh_t mesh;
    char err[1600], sub[600], note[VP_LOG_NOTE_MAX + 1], notebuf[VP_LOG_NOTE_MAX + 1], surface[VP_PATH_MAX] = "";
    char prefix[VP_PATH_MAX], text[VP_LOG_TEXT_MAX + 1], board_path[VP_PATH_MAX];
    int st, i, have_L = 0, dev_open = 0, log_open = 0, rc = 1, k, nint = 1;
    uint32_t replayed = 0;
    double wall0 = vp_wall_seconds();

    scan_defaults(&cl);
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) { scan_usage(stdout); return 0; }
        st = scan_option(&cl, argc, argv, &i, 0, err, sizeof err);
        if (st == 0) continue;
        if (st < 0) fprintf(stderr, "scan: %s\n", err);
        else fprintf(stderr, "scan: unknown option %s (see --help)\n", argv[i]);
        return 2;
    }
    if (!cl.log) { fprintf(stderr, "scan: give the session log: --log LOG (see --help)\n"); return 2; }
    if (!cl.resume && !cl.board) { fprintf(stderr, "scan: give the machine: --board FILE (see --help)\n"); return 2; }
    if (cl.estop_at && !cl.dry && !cl.resume) { fprintf(stderr, "scan: --estop-at simulates the e-stop: dry runs only\n"); return 2; }
    o = cl;
    vp_mesh_init(&mesh);
    memset(&run, 0, sizeof run);
    run.w.file.fd = -1;

    /* ---- the options: the command line, or the log's with --resume ---- */
    if (cl.resume) {
        char *tok[64];
        int nt;
        st = vp_slog_load(&L, cl.log, err, sizeof err);
        if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); return 1; }
        have_L = 1;
        memcpy(notebuf, L.header.note, sizeof notebuf);
        nt = vp_note_split(notebuf, tok, 64);
        if (nt < 1 || strcmp(tok[0], "scan") != 0) {
            fprintf(stderr, "scan: %s was not written by `scan`%s\n", cl.log,
                    nt >= 1 && !strcmp(tok[0], "sim") ? " but by `sim`: resume it with `voroprobe sim --resume`" : "");
            goto done;
        }
        scan_defaults(&o);
        for (i = 1; i < nt; i++)
            if (scan_option(&o, nt, tok, &i, 1, sub, sizeof sub) != 0) {
                fprintf(stderr, "scan: %s: the options recorded in the log are not understood ('%s')\n", cl.log, tok[i]);
                goto done;
            }
        if (cl.dry && !o.dry) { fprintf(stderr, "scan: %s is a scan of the real machine: it cannot go on as a dry run\n", cl.log); goto done; }
        if (!cl.dry && o.dry) cl.dry = 1;   /* a dry run's log goes on as a dry run */
        if ((cl.eps && cl.eps != o.eps) || (cl.surface && strcmp(cl.surface, o.surface ? o.surface : "")) ||
            (cl.near >= 0 && cl.near != o.near) ||
            (cl.seed && cl.seed != o.seed)) {
            fprintf(stderr, "scan: a resumed scan keeps the options in its log (%s)\n", L.header.note);
            goto done;
        }
        if (o.estop_at || cl.estop_at) o.estop_at = cl.estop_at;
        if (cl.board) o.board = cl.board;
        if (cl.calib) o.calib = cl.calib;
        o.log = cl.log;
        o.out = cl.out;
        o.quiet = cl.quiet;
        o.resume = 1;
        o.stop_after = cl.stop_after;
        o.sync = cl.sync;
        o.have_sync = cl.have_sync;
    }
    if (o.estop_at && !o.dry) { fprintf(stderr, "scan: --estop-at simulates the e-stop: dry runs only\n"); goto done; }

    /* ---- the board, its calibration, the object ---- */
    st = vp_board_load(o.board, &b, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); goto done; }
    if (o.calib && (st = vp_board_calibration_load(&b, o.calib, NULL, err, sizeof err)) != VP_OK) {
        fprintf(stderr, "scan: %s\n", err);
        goto done;
    }
    if (!(b.clearance > 0.0)) {
        /* a camera rangefinder's "no spot" is not a proof of free space: an occluded spot, a dark
         * or shiny surface read the same. Inside Omega the head would move on such misses. */
        if (!o.dry) {
            fprintf(stderr, "scan: %s: [omega] clearance = 0 lets the head into Omega, where it moves along rays its "
                    "rangefinder reported free; a camera rangefinder reports an occluded, dark or shiny spot as no spot, "
                    "which proves nothing (a dry run of a cube moved through it 1878 times): set clearance to the head's "
                    "radius, so that the head stays outside Omega\n", o.board);
            goto done;
        }
        fprintf(stderr, "scan: warning: clearance 0 (dry run only): the head enters Omega and trusts every \"no spot\" "
                "as free space; moves through the object are counted and end the run with exit 5\n");
    }
    {
        unsigned long crc = 0;
        file_crc(o.board, &crc);
        if (o.resume && o.have_crc && crc != o.board_crc)
            fprintf(stderr, "scan: note: %s changed since the log was started (the planner's configuration is "
                    "checked below; the machine's may differ)\n", o.board);
        o.board_crc = crc;
    }
    snprintf(board_path, sizeof board_path, "%s", o.board);
    if (!o.eps) o.eps = b.eps;
    if (o.near < 0) o.near = b.near_measure;
    if (o.dry) {
        if (o.resume) snprintf(surface, sizeof surface, "%s", o.surface ? o.surface : "");
        else if ((st = vp_scan_dry_surface(&b, o.surface, surface, sizeof surface, err, sizeof err)) != VP_OK) {
            fprintf(stderr, "scan: --surface: %s\n", err);
            goto done;
        }
        if (!o.seed) o.seed = (unsigned long long)b.sim_seed;
    }
    if (!o.have_sync) {
        vp_logfile_config_default(&o.sync);
        if (b.log_sync[0]) vp_logfile_parse_sync(b.log_sync, &o.sync);
    }
    /* the log and mesh paths are checked before anything is written */
    if (o.out) st = vp_path_cat(prefix, sizeof prefix, o.out, "", err, sizeof err);
    else {
        size_t len = strlen(o.log);
        if (len > 6 && !strcmp(o.log + len - 6, ".vplog")) {
            st = vp_path_cat(prefix, sizeof prefix, o.log, "", err, sizeof err);
            if (st == VP_OK) prefix[len - 6] = 0;
        } else
            st = vp_path_cat(prefix, sizeof prefix, o.log, ".mesh", err, sizeof err);
    }
    {
        char chk[VP_PATH_MAX];
        if (st == VP_OK) st = vp_path_cat(chk, sizeof chk, prefix, ".ply", err, sizeof err);
        if (st == VP_OK) st = vp_path_cat(chk, sizeof chk, o.log, "", err, sizeof err);
    }
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); rc = 2; goto done; }

    /* ---- the machine ---- */
    st = vp_scan_open(&dev, &b, o.dry, o.dry ? surface : NULL, 0, o.seed, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); goto done; }
    dev_open = 1;
    dev.estop_at = o.estop_at;
    dev.near_measure = o.near;

    /* ---- the planner's configuration: the board's scan volume, eps and rangefinder ---- */
    vp_board_planner_config(&b, &cfg);
    cfg.eps = o.eps;
    cfg.noise_tol = o.noise_tol;
    cfg.confirm_misses = (uint32_t)o.confirm;
    {
        /* eps within what the planner can resolve in double precision (as sim says it) */
        vp_sim_options_t none;
        memset(&none, 0, sizeof none);
        if (vp_sim_check_ranges(&cfg, 0.0, &none, err, sizeof err) != VP_OK) {
            fprintf(stderr, "scan: %s\n", err);
            goto done;
        }
    }
    if (o.dry) {
        /* the simulated object must lie in Omega; the board's interior point must be inside it
         * (else the object's own interior points stand in for it) */
        vp_surface_t *s = dev.dr->surf;
        double lo[3], hi[3], gap = b.clearance;   /* with a clearance the head stays outside Omega */
        int inside = 1;
        vp_surface_bbox(s, lo, hi);
        for (k = 0; k < 3; k++)
            if (b.omega_kind == VP_OMEGA_BOX && (lo[k] - gap <= b.omega_lo[k] || hi[k] + gap >= b.omega_hi[k])) inside = 0;
        if (b.omega_kind == VP_OMEGA_BALL) {
            /* the object's farthest point from the centre, from points sampled on its surface */
            size_t q, ns = 4000;
            double *xyz = malloc(3 * ns * sizeof *xyz), r2 = (b.omega_radius - gap) * (b.omega_radius - gap);
            if (xyz) {
                ns = vp_surface_sample(s, ns, 1, xyz);
                for (q = 0; q < ns; q++) {
                    double dd = 0;
                    for (k = 0; k < 3; k++) dd += (xyz[3 * q + k] - b.omega_center[k]) * (xyz[3 * q + k] - b.omega_center[k]);
                    if (dd >= r2) inside = 0;
                }
                free(xyz);
            }
        }
        if (!inside) {
            fprintf(stderr, "scan: the simulated object %s (box %.4g %.4g %.4g .. %.4g %.4g %.4g) is not inside the "
                    "board's Omega%s ([omega] in %s)\n", surface, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
                    gap > 0 ? " by the clearance (the head stays outside Omega)" : "", b.path);
            goto done;
        }
        if (vp_surface_components(s) > 1 || !vp_surface_inside(s, b.interior)) {
            nint = vp_surface_components(s);
            if (nint > VP_PLANNER_MAX_SEEDS) { fprintf(stderr, "scan: the object has %d components (at most %d)\n", nint, VP_PLANNER_MAX_SEEDS); goto done; }
            for (k = 0; k < nint; k++) vp_surface_interior_point(s, k, cfg.interior[k]);
            cfg.ninterior = (uint32_t)nint;
        }
    }
    pl = malloc(sizeof *pl);
    arena = malloc(o.arena);
    if (!pl || !arena) { fprintf(stderr, "scan: cannot allocate the %zu-byte arena\n", o.arena); goto done; }
    st = vp_planner_init(pl, arena, o.arena, &cfg);
    if (st != VP_OK) {
        fprintf(stderr, "scan: planner: %s (%s)\n", vp_strerror(st),
                st == VP_ENOMEM ? "the arena is too small: --arena" : "check [omega] in the board file");
        goto done;
    }
    {
        fprintf(stderr, "scan: board %s (%s)%s%s\n", b.name, b.path, o.dry ? ", dry run on host-sim: " : "",
                o.dry ? surface : "");
        fprintf(stderr, "scan: eps %g mm, rangefinder %g..%g mm from %s\n", o.eps, b.tri.min_range, b.tri.max_range,
                model_source(&b));
        if (b.calib_missing)
            fprintf(stderr, "scan: note: the calibration file %s does not exist yet (voroprobe calibrate writes it)\n", b.calib_path);
        if (o.dry && (vp_surface_components(dev.dr->surf) > 1 || !vp_surface_inside(dev.dr->surf, b.interior)))
            fprintf(stderr, "scan: note: the board's interior point is not inside the simulated object: its own %u "
                    "interior point(s) are used\n", cfg.ninterior);
    }

    /* ---- the log: new, or replayed and continued ---- */
    run.dev = &dev;
    run.pl = pl;
    run.quiet = o.quiet;
    run.hw = !o.dry;
    run.stop_after = o.stop_after;
    run.w.raw = &dev.raw;
    if (o.resume) {
        vp_replay_t R;
        char why[300];
        if (!vp_slog_same_config(&L.header.cfg, L.header.arena_bytes, &cfg, (uint64_t)o.arena, why, sizeof why)) {
            fprintf(stderr, "scan: %s: the scan configuration is not the logged one (%s): the board file or the "
                    "calibration changed since\n", o.log, why);
            goto done;
        }
        vp_slog_stop_text(&L, sub, sizeof sub);
        fprintf(stderr, "resume %s: %s\n", o.log, sub);
        vp_replay_init_state(&R, pl, &L);
        st = vp_replay_run(&R, &L, L.n, why, sizeof why);
        if (st != VP_OK) { fprintf(stderr, "scan: %s: replay failed: %s\n", o.log, why); goto done; }
        replayed = R.applied;
        fprintf(stderr, "resume: %u records replayed (%llu probes, %llu moves)%s\n", R.applied,
                (unsigned long long)R.probes, (unsigned long long)R.moves, L.done ? "; the session is already complete" : "");
        if (L.done) {
            st = write_mesh(pl, prefix, &mesh, err, sizeof err);
            if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); goto done; }
            printf("log: %s (complete; %u records replayed, nothing appended)\n", o.log, replayed);
            printf("mesh: %u vertices, %u facets\nwrote %s.ply and %s.off\n", (unsigned)mesh.nv, (unsigned)mesh.nt, prefix, prefix);
            rc = 0;
            goto done;
        }
        st = vp_logfile_open_append_read(&run.w.file, o.log, L.good_bytes, L.n, (uint64_t)L.size, &o.sync);
        if (st == VP_OK) {
            snprintf(text, sizeof text, "resumed after record %d", (int)L.n - 1);
            st = vp_logfile_event(&run.w.file, VP_LOG_EV_RESUME, 0, text);
        }
    } else {
        vp_log_header_t h;
        scan_note(&o, board_path, o.eps, surface, note, sizeof note);
        vp_log_header_init(&h, &cfg, (uint64_t)o.arena, VP_LOG_UNITS_MM, b.name, note);
        if (vp_mkdirs_for(o.log) != 0) { fprintf(stderr, "scan: cannot create the folder of %s: %s\n", o.log, strerror(errno)); goto done; }
        st = vp_logfile_create(&run.w.file, o.log, &h, &o.sync);
        if (st == VP_OK)
            st = vp_logfile_event(&run.w.file, VP_LOG_EV_START, 0, o.dry ? "voroprobe scan (dry run on host-sim)" : "voroprobe scan");
    }
    if (st == VP_OK) {
        /* the rangefinder model in use */
        vp_log_record_t ev;
        const vp_tri_model_t *t = &b.tri;
        snprintf(text, sizeof text, "rangefinder: %.150s; line %.9g %.9g %.9g %.9g", model_source(&b), t->p0[0], t->p0[1],
                 t->e[0], t->e[1]);
        vp_log_record_event(&ev, 0, VP_LOG_EV_CALIBRATION, b.calibrated, text);
        ev.value[0] = t->a; ev.value[1] = t->b; ev.value[2] = t->c; ev.value[3] = t->max_range;
        st = vp_logfile_append(&run.w.file, &ev);
    }
    if (st != VP_OK) {
        if (run.w.file.busy)
            fprintf(stderr, "scan: log %s is being written by another process: it is left as it is (wait for that "
                    "scan to end, or give another --log)\n", o.log);
        else if (run.w.file.changed)
            fprintf(stderr, "scan: log %s was written by another process while it was read: it is left as it is "
                    "(resume again)\n", o.log);
        else
            fprintf(stderr, "scan: cannot write the session log %s: %s\n", o.log, strerror(errno));
        goto done;
    }
    log_open = 1;

    /* ---- home, the start, back to where a resumed scan stopped ---- */
    vp_scan_catch_signals();
    st = vp_scan_home(&dev, err, sizeof err);
    if (st == VP_OK) st = vp_scan_goto(&dev, b.start, err, sizeof err);
    if (st == VP_OK && o.resume) st = vp_scan_return(&dev, &L, L.n, b.start, stderr, err, sizeof err);
    if (vp_scan_stop && (st == VP_OK || dev.m->step.fault == VP_STEP_FAULT_NONE)) { st = VP_EABORT; run.paused = 1; }
    if (st != VP_OK && !run.paused) {
        fprintf(stderr, "scan: %s\n", err);
        snprintf(text, sizeof text, "%.250s", err);
        vp_logfile_event(&run.w.file, VP_LOG_EV_FAULT, st, text);
        fprintf(stderr, "scan: stopped before the scan went on; the log %s is resumable: voroprobe scan --log %s --resume\n",
                o.log, o.log);
        goto done;
    }

    /* ---- the scan ---- */
    if (st == VP_OK) {
        vp_device_ops_t ops = vp_scan_ops(&dev);
        vp_session_hooks_t hooks;
        hooks.ctx = &run;
        hooks.after = scan_after;
        run.t0 = vp_scan_seconds(&dev);
        run.wall0 = vp_wall_seconds();
        run.probes0 = dev.probes;
        if (!o.quiet) fprintf(stderr, "scan: homed%s; scanning (Ctrl-C stops after the current command)\n", o.resume ? ", back where the log left off" : "");
        vp_session_run(pl, &ops, &hooks, 0, NULL, &res);
        st = res.status;
        if (!o.quiet) scan_progress(&run, 1);
    }
    if (run.w.failed) {
        fprintf(stderr, "scan: writing the session log %s failed: %s; the scan stopped\n", o.log, strerror(errno));
    } else if (run.paused) {
        snprintf(text, sizeof text, "paused after %lu commands (Ctrl-C)", run.n);
        vp_logfile_event(&run.w.file, VP_LOG_EV_PAUSE, 0, text);
        fprintf(stderr, "scan: %s; resume with: voroprobe scan --log %s --resume\n", text, o.log);
        rc = VP_EXIT_STOPPED;
    } else if (st == VP_OK) {
        rc = 0;
    } else if (dev.fault) {
        char why[300];
        const vp_cmd_t *c = &dev.fault_cmd;
        vp_scan_fault_text(&dev, why, sizeof why);
        if (c->kind == VP_CMD_MOVE)
            snprintf(text, sizeof text, "command %lu (move to %.6g %.6g %.6g): %.160s", run.n + 1, c->to[0], c->to[1], c->to[2], why);
        else
            snprintf(text, sizeof text, "command %lu (probe from %.6g %.6g %.6g along %.4f %.4f %.4f): %.120s", run.n + 1,
                     c->from[0], c->from[1], c->from[2], c->dir[0], c->dir[1], c->dir[2], why);
        vp_logfile_event(&run.w.file, VP_LOG_EV_FAULT, dev.fault, text);
        fprintf(stderr, "scan: stopped at %s\nscan: the log %s is resumable: voroprobe scan --log %s --resume%s\n", text,
                o.log, o.log, dev.m->step.fault == VP_STEP_FAULT_ESTOP ? " (after releasing the e-stop)" : "");
    } else {
        snprintf(text, sizeof text, "planner: %s", st == VP_ERANGE ? "the probe towards an interior point found no "
                 "surface: is [omega] interior inside the object?" : vp_strerror(st));
        vp_logfile_event(&run.w.file, VP_LOG_EV_FAULT, st, text);
        fprintf(stderr, "scan: the scan stopped: %s%s\n", text, st == VP_ENOMEM ? " (the arena is full: --arena)" : "");
        if (dev.unreadable) {
            char why[300];
            vp_scan_unreadable_text(&dev, why, sizeof why);
            fprintf(stderr, "scan: %lu frame(s) could not be read (%s)%s\n", dev.unreadable, why,
                    dev.unread_why[0] ? ": a spot off the laser line means the rangefinder model is off: calibrate" : "");
        }
    }
    vp_logfile_close(&run.w.file);
    log_open = 0;
    vp_audit_keep(o.log); /* for an independent proof check (VP_AUDIT_DIR) */

    /* ---- the mesh and the figures ---- */
    st = write_mesh(pl, prefix, &mesh, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "scan: %s\n", err); rc = 1; goto done; }
    {
        vp_planner_stats_t ps;
        vp_meshcheck_t mc;
        vp_machine_t *m = dev.m;
        int have_mc = vp_meshcheck_analyze(&mesh, &mc) == VP_OK;
        double mt = vp_scan_seconds(&dev) - run.t0;
        vp_planner_get_stats(pl, &ps);
        printf("scan: %s after %lu commands of this run%s\n", rc == 0 ? "DONE" : rc == 3 ? "paused" : "stopped", run.n,
               o.resume ? " (resumed)" : "");
        printf("log: %s (%u records replayed + %lu written, %lu syncs)\n", o.log, replayed, run.w.file.records,
               run.w.file.syncs);
        printf("mesh: %u vertices, %u facets; %s, %d component(s), genus %d\n", (unsigned)mesh.nv, (unsigned)mesh.nt,
               have_mc && mc.closed_manifold ? "closed 2-manifold" : "NOT closed (yet)", have_mc ? mc.components : -1,
               have_mc ? mc.genus : -1);
        {
            char nh[80] = "", tc[120] = "";
            if (o.near && dev.near) snprintf(nh, sizeof nh, " (%lu nearer than %g mm, measured)", dev.near, b.tri.min_range);
            if (dev.too_close)
                snprintf(tc, sizeof tc, " (%lu nearer than %g mm, %lu unreadable frames)", dev.too_close - dev.unreadable,
                         b.tri.min_range, dev.unreadable);
            printf("machine: %lu probes: %lu hits%s, %lu misses, %lu too close%s; %lu moves, laser origin travel %.0f mm, "
                   "%.0f s of machine time%s\n", dev.hits + dev.misses + dev.too_close, dev.hits, nh, dev.misses,
                   dev.too_close, tc, m->st.moves,
                   m->st.travel, mt, o.dry ? " (simulated)" : "");
        }
        printf("planner: %llu probes in all, largest ball %.4g mm (eps %g), arena peak %zu bytes\n",
               (unsigned long long)ps.probes, ps.max_ball, o.eps, ps.arena_peak);
        if (rc == 0 && have_mc && !mc.closed_manifold) {
            printf("warning: the planner said DONE but the mesh is not closed (%zu boundary edges): the planner leaves open "
                   "what its probes could not see (%llu too-close results%s, %llu Voronoi edges occluded from dOmega)\n",
                   mc.boundary_edges, (unsigned long long)ps.too_close,
                   o.near || !ps.too_close ? "" : ": --near-spots measure reports near spots as hits",
                   (unsigned long long)ps.occluded);
            rc = VP_EXIT_NOT_CLOSED;
        }
        if (rc == 0 && ps.missing_components > 0) {
            printf("warning: the planner said DONE but %u interior point(s) are not enclosed by the mesh (H2): "
                   "certify names them\n", ps.missing_components);
            rc = VP_EXIT_NOT_CLOSED;
        }
        if (o.dry && dev.through > 0) {
            printf("SAFETY: %lu moves of this dry run went through the object: on the machine that is a crash "
                   "into the part (voroprobe log verify %s names the first unproven move)\n", dev.through, o.log);
            rc = VP_EXIT_COLLISION;
        }
        if (o.dry) {
            vp_hausdorff_t hd;
            printf("dry run: probe error against the true object rms %.3f mm, worst %.3f mm (%lu hits); %lu false hits, "
                   "%lu hidden spots, %lu moves through the object\n",
                   dev.true_n ? sqrt(dev.err2 / (double)dev.true_n) : 0.0, dev.err_max, dev.true_n, dev.false_hits,
                   dev.false_misses, dev.through);
            if (rc == 0 && mesh.nt > 0 && vp_hausdorff(&mesh, dev.dr->surf, 20000, 7, &hd) == VP_OK)
                printf("dry run: the mesh is within %.2f mm of the object (Hausdorff), eps %g mm\n", hd.hausdorff, o.eps);
            printf("dry run: %d frames rendered, %.1f s wall\n", (int)m->st.frames, vp_wall_seconds() - wall0);
        }
        printf("wrote %s.ply and %s.off\n", prefix, prefix);
        if (have_mc) vp_meshcheck_free(&mc);
    }
done:
    if (log_open) vp_logfile_close(&run.w.file);
    if (dev_open) vp_scan_close(&dev);
    if (have_L) vp_slog_free(&L);
    vp_mesh_free(&mesh);
    free(pl);
    free(arena);
    return rc;
}
