/* voroprobe mcu: the microcontroller scanner. The planner runs on the MCU (the MPS2 AN386
 * image under qemu-system-arm, a real board on a serial port, or the same sources built for
 * this machine); this end plays the object and the rangefinder (host-sim), writes the session
 * log the MCU streams, and at DONE meshes the log as `voroprobe mesh` does. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_audit.h"
#include "vp_cli.h"
#include "vp_logfmt.h"
#include "vp_mcu.h"
#include "vp_note.h"
#include "vp_outcome.h"
#include "vp_sessionlog.h"
#include "vp_sim_opts.h"
#include "vp_sim_session.h"
#include "vp_sim_setup.h"

static volatile int mcu_stop;
static void mcu_on_signal(int sig)
{
    (void)sig;
    mcu_stop = 1;
}

static void mcu_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe mcu (--qemu IMAGE | --serial DEVICE | --socket PATH | --exec PROGRAM)\n"
        "                     --surface SPEC (--eps E | --eps-rel R) [options]\n"
        "Scans a simulated object with the planner running on a microcontroller: the MCU plans,\n"
        "drives its axes and streams its session log over a framed, CRC-checked UART link\n"
        "(doc/mcu-protocol.md); this end answers its probes from the simulated object, writes the\n"
        "log and, at DONE, the mesh of the log (as `voroprobe mesh` does).\n"
        "  --qemu IMAGE       run IMAGE (BUILD/m4/voroprobe-an386.elf, from\n"
        "                     sh boards/cortex-m4/build.sh) on qemu-system-arm -M mps2-an386\n"
        "  --machine M        qemu's machine (default mps2-an386; netduinoplus2, an STM32F405, for\n"
        "                     BUILD/m4/voroprobe-stm32f405.elf)\n"
        "  --qemu-bin PATH    the qemu-system-arm program (default: from PATH)\n"
        "  --icount N         qemu's -icount shift=N (default 3: 8 ns per instruction): the\n"
        "                     board's time follows its instructions, so step edges are timed the\n"
        "                     same on a busy host; --no-icount: qemu's clock follows the host's\n"
        "  --serial DEVICE    a board on a serial port (e.g. /dev/ttyUSB0); --baud B (115200)\n"
        "  --socket PATH      a board behind a unix socket (e.g. qemu -serial unix:PATH,server=on)\n"
        "  --exec PROGRAM     the MCU's sources built for this machine (BUILD/m4/voroprobe-m4-host),\n"
        "                     on a pipe\n"
        "  --out PREFIX       PREFIX.vplog (the MCU's log), PREFIX.ply, PREFIX.off (default out/mcu)\n"
        "  --corrupt N        damage N frames on the link (one bit each, received and sent by\n"
        "                     turns): each must be caught and asked for again\n"
        "  --timeout S        the board is silent after S seconds without a valid frame (default 20)\n"
        "  --quiet            no progress lines\n"
        "  sim's object and rangefinder options: --surface, --eps, --eps-rel, --noise, --dropout,\n"
        "  --max-range, --min-range, --omega, --seed, --hausdorff, ... (voroprobe sim --help)\n"
        "Ctrl-C or SIGTERM: the MCU is told STOP (a PAUSE event ends its log).\n"
        "Exit status as sim's: 0 closed, 1 error (link, board silent, log refused), 2 usage,\n"
        "3 stopped, 4 not_closed, 5 collision.\n");
}

typedef struct mcu_dev {
    vp_sim_t *sim;
} mcu_dev_t;

static int dev_move(void *ctx, const double from[3], const double to[3], int *collided)
{
    mcu_dev_t *d = ctx;
    vp_simdev_move_t r;
    int st;
    (void)from;
    st = vp_simdev_move(d->sim->dev, to, &r);
    *collided = r.collided;
    return st == VP_OK || st == VP_EABORT ? VP_OK : st;
}

static int dev_probe(void *ctx, const double from[3], const double dir[3], double range, int *hit,
                     double *dist, double *raw)
{
    mcu_dev_t *d = ctx;
    vp_simdev_probe_t r;
    int st;
    (void)from;
    st = vp_simdev_probe(d->sim->dev, dir, range, &r);
    if (st != VP_OK) return st;
    *raw = r.hit ? r.t : NAN;
    *hit = r.too_close ? VP_PROBE_TOO_CLOSE : r.hit;
    *dist = r.hit ? (r.t < 0 ? 0.0 : r.t) : 0.0;
    return VP_OK;
}

static int parse_num(const char *s, double *v)
{
    char *e;
    *v = strtod(s, &e);
    return e != s && *e == '\0' && isfinite(*v);
}

int vp_cli_mcu(int argc, char **argv)
{
    vp_sim_options_t o;
    vp_sim_t sim;
    vp_mcu_link_t link;
    vp_mcu_options_t mo;
    vp_mcu_result_t res;
    vp_mcu_device_t dev;
    mcu_dev_t md;
    vp_logfmt_header_t h;
    vp_sessionlog_t L;
    vp_replay_t R;
    const char *qemu_image = NULL, *serial = NULL, *sock = NULL, *exec = NULL, *qemu_bin = NULL, *machine = NULL;
    char err[1400], note[VP_LOGFMT_NOTE_MAX + 1], logpath[VP_PATH_MAX];
    unsigned char *hbuf = NULL;
    double corrupt = 0, timeout = 20, baud = 115200, icount = 3;
    int st, i, hn, links = 0, ex;
    vp_sim_options_default(&o);
    o.out = "out/mcu";
    o.arena = (size_t)1 << 20;      /* host-sim's own planner is not used: the MCU plans */
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double *num = NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { mcu_usage(stdout); return 0; }
        if (!strcmp(a, "--qemu") || !strcmp(a, "--serial") || !strcmp(a, "--socket") || !strcmp(a, "--exec") ||
            !strcmp(a, "--qemu-bin") || !strcmp(a, "--machine")) {
            if (!v) { fprintf(stderr, "mcu: %s needs a value\n", a); return 2; }
            if (!strcmp(a, "--qemu")) qemu_image = v, links++;
            else if (!strcmp(a, "--serial")) serial = v, links++;
            else if (!strcmp(a, "--socket")) sock = v, links++;
            else if (!strcmp(a, "--exec")) exec = v, links++;
            else if (!strcmp(a, "--machine")) machine = v;
            else qemu_bin = v;
            i++;
            continue;
        }
        if (!strcmp(a, "--no-icount")) { icount = -1; continue; }
        if (!strcmp(a, "--corrupt")) num = &corrupt;
        else if (!strcmp(a, "--timeout")) num = &timeout;
        else if (!strcmp(a, "--baud")) num = &baud;
        else if (!strcmp(a, "--icount")) num = &icount;
        if (num) {
            if (!v || !parse_num(v, num) || *num < 0 || *num > 1e7 || (num != &timeout && *num != floor(*num)) ||
                (num == &timeout && *num <= 0)) {
                fprintf(stderr, "mcu: %s needs a %s\n", a, num == &timeout ? "positive number of seconds" : "whole number >= 0");
                return 2;
            }
            i++;
            continue;
        }
        if (!strcmp(a, "--arena")) { fprintf(stderr, "mcu: the MCU's arena is its own (its HELLO says how large)\n"); return 2; }
        if (!strcmp(a, "--line-laser")) { fprintf(stderr, "mcu: a microcontroller core takes one ray per probe (a dot laser): no --line-laser\n"); return 2; }
        if (!strcmp(a, "--far-reads")) { fprintf(stderr, "mcu: a microcontroller core asks for its edges only: no --far-reads\n"); return 2; }
        if (!strcmp(a, "--clearance") || !strcmp(a, "--min-feature")) {
            /* its core plans a body in its own order (the newest task first, no lines aimed from
             * aside, no tubes: its flash), so this build's planner could not replay its log */
            fprintf(stderr, "mcu: a microcontroller core keeps the probe a point (no %s): its body-mode order is not "
                    "this build's, whose replay checks its log\n", a);
            return 2;
        }
        if (!strcmp(a, "--proof-life")) { fprintf(stderr, "mcu: a microcontroller core's proofs do not expire (an object standing still): no --proof-life\n"); return 2; }
        st = vp_sim_parse_option(&o, argc, argv, &i, err, sizeof err);
        if (st == 0) continue;
        if (st < 0) fprintf(stderr, "mcu: %s\n", err);
        else fprintf(stderr, "mcu: unknown option %s (see --help)\n", a);
        return 2;
    }
    if (links != 1) { fprintf(stderr, "mcu: give one of --qemu, --serial, --socket, --exec (see --help)\n"); return 2; }
    if (!o.surface) { fprintf(stderr, "mcu: --surface is required (see --help)\n"); return 2; }
    if (!(o.eps > 0.0) && !(o.eps_rel > 0.0)) { fprintf(stderr, "mcu: give --eps or --eps-rel (see --help)\n"); return 2; }
    if (vp_sim_check_out(&o, err, sizeof err) != VP_OK ||
        vp_path_cat(logpath, sizeof logpath, o.out, ".vplog", err, sizeof err) != VP_OK) {
        fprintf(stderr, "mcu: %s\n", err);
        return 2;
    }
    if (vp_mkdirs_for(o.out) != 0) { fprintf(stderr, "mcu: cannot create the folder of %s\n", o.out); return 1; }
    st = vp_sim_open(&sim, &o, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "mcu: %s\n", err); vp_sim_close(&sim); return 1; }
    /* START: the session's header (the planner configuration, the object in the note) */
    vp_sim_session_note(&o, note, sizeof note);
    vp_logfmt_header_init(&h, &sim.cfg, 0, VP_LOGFMT_UNITS_NONE, "host-sim", note);
    hbuf = malloc(VP_LOGFMT_MAX_HEADER);
    hn = hbuf ? vp_logfmt_header_encode(&h, hbuf, VP_LOGFMT_MAX_HEADER) : VP_ENOMEM;
    if (hn < 0) { fprintf(stderr, "mcu: the session header: %s\n", vp_strerror(hn)); free(hbuf); vp_sim_close(&sim); return 1; }
    if (qemu_image) st = vp_mcu_open_qemu(&link, qemu_bin, machine, qemu_image, (int)icount, err, sizeof err);
    else if (exec) st = vp_mcu_open_exec(&link, exec, err, sizeof err);
    else if (serial) st = vp_mcu_open_serial(&link, serial, (long)baud, err, sizeof err);
    else st = vp_mcu_open_socket(&link, sock, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "mcu: %s\n", err); free(hbuf); vp_sim_close(&sim); return 1; }
    {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = mcu_on_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESETHAND;
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
        signal(SIGPIPE, SIG_IGN);
    }
    if (!o.quiet)
        fprintf(stderr, "voroprobe mcu: %s, eps %.6g, link %s%s%s%s\n", o.surface, sim.cfg.eps,
                qemu_image ? "qemu " : serial ? "serial " : sock ? "socket " : "pipe to ",
                qemu_image ? (machine ? machine : "mps2-an386") : "", qemu_image ? " " : "",
                qemu_image ? qemu_image : serial ? serial : sock ? sock : exec);
    memset(&mo, 0, sizeof mo);
    mo.header = hbuf;
    mo.header_len = (size_t)hn;
    mo.log_path = logpath;
    mo.corrupt = (unsigned)corrupt;
    mo.silent_seconds = timeout;
    mo.progress = o.quiet ? NULL : stderr;
    mo.stop_flag = &mcu_stop;
    md.sim = &sim;
    dev.ctx = &md;
    dev.move = dev_move;
    dev.probe = dev_probe;
    st = vp_mcu_serve(&link, &dev, &mo, &res, err, sizeof err);
    vp_mcu_close(&link);
    free(hbuf);
    if (st != VP_OK) {
        fprintf(stderr, "mcu: %s\n", err);
        fprintf(stderr, "mcu: %lu damaged frames caught here, %lu moves, %lu probes before it stopped\n",
                res.crc_errors, res.moves, res.probes_answered);
        if (res.log_bytes > 0)
            fprintf(stderr, "mcu: the log so far is %s (voroprobe mesh and log verify read it)\n", logpath);
        vp_sim_close(&sim);
        return 1;
    }
    vp_audit_keep(logpath);
    printf("link: %lu frames in, %lu out; damaged frames caught: %lu here, %u on the MCU (%lu + %lu injected); "
           "%lu requests repeated, %u NAKs, %u timeouts on the MCU\n",
           res.frames_in, res.frames_out, res.crc_errors, res.mcu_crc_errors, res.injected_in, res.injected_out,
           res.repeats, res.mcu_naks, res.mcu_timeouts);
    printf("steps: %lu moves checked against the ideal trapezoid: %lu with wrong edge counts, %lu off schedule "
           "(largest %.1f ticks); last edge %.1f us after its time at most (mean %.1f us); %lu edges, %lu served "
           "after the next was due\n",
           res.moves_checked, res.edge_mismatches, res.schedule_mismatches, res.max_schedule_dev_ticks,
           res.max_latency_us, res.mean_latency_us, res.edges, res.late_edges);
    printf("mcu: board %s, status %s, %u commands, %u probes, %u vertices, %u facets, arena peak %u of %u bytes, %.1f s\n",
           res.hello.board, vp_strerror(res.status), res.commands, res.probes, res.vertices, res.facets,
           res.arena_peak, res.hello.arena_bytes, res.seconds);
    /* the mesh of the log, as `voroprobe mesh` makes it */
    st = vp_sessionlog_load(&L, logpath, err, sizeof err);
    if (st == VP_OK) {
        st = vp_replay_open(&R, &L, 0, err, sizeof err);
        if (st == VP_OK) st = vp_replay_run(&R, &L, L.n, err, sizeof err);
        if (st == VP_OK) {
            free(sim.pl);
            free(sim.arena);
            sim.pl = R.pl;
            sim.arena = R.arena;
            R.pl = NULL;
            R.arena = NULL;
        }
        vp_replay_close(&R);
        vp_sessionlog_free(&L);
    }
    if (st != VP_OK) { fprintf(stderr, "mcu: %s: %s\n", logpath, err); vp_sim_close(&sim); return 1; }
    sim.run.status = res.status;
    sim.run.total_seconds = res.seconds;
    sim.paused = res.status == VP_EABORT;
    if (vp_sim_finish(&sim, &o, err, sizeof err) != VP_OK) { fprintf(stderr, "mcu: %s\n", err); vp_sim_close(&sim); return 1; }
    printf("log: %s (%lu records, %llu bytes, streamed by the MCU)\n", logpath, res.log_records,
           (unsigned long long)res.log_bytes);
    vp_sim_report(&sim, &o, stdout);
    ex = vp_sim_exit(&sim);
    if (res.edge_mismatches || res.schedule_mismatches) {
        fprintf(stderr, "mcu: the step edges of %lu move(s) differ from the ideal trapezoid: exit %d\n",
                res.edge_mismatches + res.schedule_mismatches, ex ? ex : VP_EXIT_ERROR);
        ex = ex ? ex : VP_EXIT_ERROR;
    }
    vp_sim_close(&sim);
    return ex;
}
