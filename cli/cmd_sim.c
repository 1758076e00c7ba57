/* voroprobe sim: a full scan of a simulated object (host-sim device), mesh out, figures out. */
#include <errno.h>
#include <signal.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "vp_audit.h"
#include "vp_cli.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_motion.h"
#include "vp_note.h"
#include "vp_outcome.h"
#include "vp_live_cli.h"
#include "vp_render.h"
#include "vp_session.h"
#include "vp_simdev.h"
#include "vp_surface.h"
#include "vp_sim_opts.h"
#include "vp_sim_setup.h"
#include "vp_sim_session.h"

/* Ctrl-C or SIGTERM: the scan pauses after the current command (a PAUSE event in the log) */
static volatile sig_atomic_t sim_stop;
static void sim_on_signal(int sig)
{
    (void)sig;
    sim_stop = 1;
}

static void sim_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe sim --surface SPEC (--eps E | --eps-rel R) [options]\n"
        "Scans a simulated object with the probing planner and writes the mesh.\n"
        "  --surface SPEC     sphere, torus, genus2, ellipsoid, genus5, blobby, off:FILE, ply:FILE,\n"
        "                     or several joined by '+' (see below)\n"
        "  --eps E            largest surface Delaunay ball radius (same units as the object)\n"
        "  --eps-rel R        eps as a fraction of the object's bounding-box diagonal (not with --eps)\n"
        "  --out PREFIX       write PREFIX.ply, PREFIX.off and the session log PREFIX.vplog\n"
        "                     (default: out/scan)\n"
        "  --log FILE         write the session log to FILE instead of PREFIX.vplog\n"
        "  --no-log           write no session log\n"
        "  --resume LOG       replay LOG, then continue the scan and append to it (the options\n"
        "                     recorded in LOG are used; the mesh goes beside LOG unless --out)\n"
        "  --sync POLICY      when the log is synced: record (each, default), N (every N\n"
        "                     records), Tms (every T ms), N,Tms, close (only at the end)\n"
        "  --rescan LOG       scan again an object scanned before (LOG's session, with its options):\n"
        "                     every sample is measured again from outside Omega and kept, moved\n"
        "                     (found within eps/2 on its line: the point measured takes its place)\n"
        "                     or removed,\n"
        "                     the device re-proves old free space before it moves through it, and\n"
        "                     the scan goes on where something changed; --surface names the object\n"
        "                     now (default: the logged one). Writes a new log (LOG's records, a\n"
        "                     RESCAN event, the new ones; default LOG minus .vplog plus .rescan)\n"
        "  --track N          after the scan, N rounds of tracking: each a re-scan from where the\n"
        "                     device stands (with --motion the object moves on); every round's\n"
        "                     figures (probes, samples kept and removed, closed, genus, collisions,\n"
        "                     Hausdorff at its end) in the summary and --json (\"rounds\"); each\n"
        "                     round's mesh in PREFIX.roundK.ply\n"
        "  --rescan-sparse    with --rescan or --track: a sample is not measured when all its\n"
        "                     neighbours are and hold (no two neighbours both left out; some 20%%\n"
        "                     fewer probes); a change narrower than the sample spacing that moves\n"
        "                     only such samples goes unseen\n"
        );
    fprintf(f,
        "  --stop-after N     pause the session after N commands (a PAUSE event; resumable)\n"
        "  --power-cut BYTES  simulate a power cut once the log reaches BYTES bytes (torn write)\n"
        "  --noise S          Gaussian noise of each hit distance (standard deviation; at most eps/16)\n"
        "  --dropout P        probability that a real hit reports a miss (at most 0.5)\n"
        "  --confirm N        re-probes of a miss where a hit is expected (default 2 with\n"
        "                     --dropout, else 0)\n"
        "  --clearance C      device radius: the device then stays outside Omega (grown to keep 2C from\n"
        "                     the object) and probes each Voronoi edge along its line from dOmega;\n"
        "                     what it cannot see that way is left open (reported); any move closer\n"
        "                     than C to the object counts as a collision\n"
        "  --far-reads        with --clearance: a probe's spot is read wherever it lands on its line\n"
        "                     through Omega; past the edge's end it proves the edge free and becomes\n"
        "                     a sample where none lies within eps (scan --far-reads: on a body-mode\n"
        "                     board with a backdrop)\n"
        "  --min-feature R    with --clearance: the device may travel inside Omega through tubes\n"
        "                     proven free, assuming every point of the object lies within\n"
        "                     --feature-margin of a ball of radius R inside the object (no part\n"
        "                     thinner than 2R) and every miss true (no --dark); 0 (default): it\n"
        "                     stays outside Omega\n"
        "  --feature-margin M how far sharp convex edges and corners reach beyond those balls\n"
        "                     (default 0.75 R: a box's corners; an edge of angle A needs\n"
        "                     R (1/sin(A/2) - 1))\n"
        "  --max-range R      rangefinder range (0: unlimited)\n"
        "  --min-range R      the rangefinder cannot measure nearer than R (reported as too close)\n"
        "  --angle DEG        also refine facets with an angle below DEG (at most 30)\n"
        "  --size-rel E       adaptive sizing (paper 002): a ball is refined when its radius is above\n"
        "                     g(c) = E min_p (dM(p) + |c - p|), dM from the samples' poles, held\n"
        "                     between --min-size and eps (then the largest ball); 0.1-0.5 is usual\n"
        "  --min-size F       the floor of the sizing field (object units; default eps/10) or of\n"
        "                     the distance bound (default none): no ball smaller is refined\n"
        "  --max-distance D   the distance bound: a facet is refined where it strays farther than\n"
        "                     D from the surface, at its ball centre (the bound of CGAL's mesher)\n"
        "                     or, from the tangent planes at its vertices, across a sharp edge\n"
        "  --accuracy H       the target: the mesh within H of the object (two-sided Hausdorff);\n"
        "                     chooses eps (diagonal/20), the distance bound (H/3) and its floor\n"
        "                     (H/4); the simulator measures the result against H (exit 6 when it\n"
        "                     is farther). Not with --eps, --size-rel, --min-size, --max-distance\n"
        "  --accuracy-rel R   the same with H = R times the bounding-box diagonal\n"
        "  --newest-first     with a distance bound: probe the newest task first, as the planner does\n"
        "                     without one (default there: of the 32 newest, the one that can find\n"
        "                     the smallest ball; fewer probes per vertex)\n");
    fprintf(f,
        "  --arena BYTES      memory given to the planner (default 512M; K, M, G suffixes)\n"
        "  --omega box|ball   the known region containing the object (default box: the bounding box\n"
        "                     grown by 10%% of its diagonal)\n"
        "  --paper            the published algorithm: probe every edge, prev-chain travel,\n"
        "                     largest ball first\n"
        "  --largest          refine the largest bad ball first (default: the largest near the probe)\n"
        "  --prev-chains      travel along prev chains only\n"
        "  --line-laser N[,DEG] a line laser: each probe's frame gives N more rays, spread over a\n"
        "                     fan of DEG degrees (default 30) in the plane of the probe's ray and\n"
        "                     the horizontal; their hits become samples where no sample lies\n"
        "                     within eps (fewer probes; the same end: every ball at most eps)\n"
        "  --dark X,Y,Z,R     the surface inside this ball returns no spot (black, shiny): the\n"
        "                     rangefinder reads a miss there (repeat for up to 8 patches)\n"
        "  --contact          the head has a contact switch: a move stops where it touches, the\n"
        "                     planner withdraws the proofs through that point and goes on\n"
        "  --seed N           seed of the simulated noise and dropouts (default 1)\n"
"  --hausdorff N      surface samples for the Hausdorff measurement (default 20000, 0: skip)\n"
        "  --motion SPEC      the object moves and deforms (see below); the device then has a clock:\n"
        "                     each move takes its trapezoid's time, each probe --probe-time, and moves\n"
        "                     are checked against the object as it moves; the summary gives the\n"
        "                     simulated time and the Hausdorff distance at the start and at the end.\n"
        "                     The planner does not know about motion (its proofs carry no time)\n"
        "  --proof-life N     a proof of free space older than N commands is probed again before\n"
        "                     the device moves along it (default with --motion: the object may\n"
        "                     have moved eps/64 since; else 0: never)\n"
        "  --speed V          travel speed, units/s (default 300, boards/sim.ini)   [with --motion]\n"
        "  --accel A          travel acceleration, units/s^2 (default 3000; 0: none) [with --motion]\n"
        "  --probe-time T     one probe's settle + exposure, s (default 0.053)       [with --motion]\n"
        "  --json             print one JSON object as the last line\n"
        "  --png FILE         also a picture of the mesh (four views, drawn in software)\n"
        VP_LIVE_CLI_HELP
        "  --quiet            no progress line\n\n"
        "Exit status (the JSON's \"status\" says the same): 0 closed (DONE, a closed 2-manifold\n"
        "around every component), 1 error (the scan stopped; the mesh so far is written), 2 usage,\n"
        "3 stopped (--stop-after, Ctrl-C or SIGTERM: a PAUSE event, resumable), 4 not_closed (DONE but\n"
        "the mesh is open or misses a component: run certify), 5 collision (a move touched the object),\n"
        "6 not_within_target (closed, but farther from the object than --accuracy), 7 wrong_topology\n"
        "(closed, but not with the object's genus or number of components).\n\n"
        "%s\n\n%s\n", vp_surface_help(), vp_motion_help());
}

/* --track: a round begins: the RESCAN event (code: the re-scan's flags; VP_RESCAN_HERE, the
 * device stays where it stands) */
static int track_event(void *ctx, int round)
{
    vp_sim_session_t *g = ctx;
    char text[64];
    snprintf(text, sizeof text, "tracking round %d", round);
    return vp_logwriter_event(&g->w.file, VP_LOGFMT_EV_RESCAN, VP_RESCAN_HERE | (g->sparse ? VP_RESCAN_SPARSE : 0u), text);
}

/* The rounds of --track (track's --rounds): 1 to 1000, else 0 */
static int track_rounds(const char *s)
{
    unsigned long long n;
    return vp_parse_count(s, 1000ull, &n) || n == 0 ? 0 : (int)n;
}

int vp_cli_sim(int argc, char **argv)
{
    vp_sim_options_t o;
    vp_sim_t sim;
    vp_sim_session_t g;
    char err[1400];
    const char *png = NULL;
    int track = 0;
    vp_live_cli_t live;
    int st, i;
    vp_live_cli_init(&live);
    vp_sim_options_default(&o);
    vp_sim_session_init(&g);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { sim_usage(stdout); return 0; }
        if (!strcmp(a, "--png") && i + 1 < argc) { png = argv[++i]; continue; }
        if (!strcmp(a, "--track") && i + 1 < argc) {
            if (!(track = track_rounds(argv[++i]))) {
                fprintf(stderr, "sim: --track takes a number of rounds, 1..1000, not '%s'\n", argv[i]);
                return 2;
            }
            continue;
        }
        if ((st = vp_live_cli_option(&live, argc, argv, &i, "sim")) <= 0) { if (st < 0) return 2; continue; }
        st = vp_sim_session_parse_option(&g, argc, argv, &i, err, sizeof err);
        if (st == 1) st = vp_sim_parse_option(&o, argc, argv, &i, err, sizeof err);
        if (st == 1) st = vp_sim_parse_motion_option(&o, argc, argv, &i, err, sizeof err);
        if (st == 0) continue;
        if (st < 0) fprintf(stderr, "sim: %s\n", err);
        else fprintf(stderr, "sim: unknown option %s (see --help)\n", a);
        return 2;
    }
    st = vp_sim_session_options(&g, &o, argc, argv, err, sizeof err);
    if (st != VP_OK) {
        /* options that clash with the log's are usage; a log that cannot be read, a failure */
        fprintf(stderr, "sim: %s\n", err);
        vp_sim_session_free(&g);
        return st == VP_EINVAL ? 2 : 1;
    }
    if (!o.surface) { fprintf(stderr, "sim: --surface is required (see --help)\n"); return 2; }
    if (g.sparse && !g.rescan && !track) {
        fprintf(stderr, "sim: --rescan-sparse is for a re-scan (--rescan) or tracking (--track)\n");
        vp_sim_session_free(&g);
        return 2;
    }
    for (i = 1; i < argc && !o.motion; i++)
        if (!strcmp(argv[i], "--speed") || !strcmp(argv[i], "--accel") || !strcmp(argv[i], "--probe-time")) {
            fprintf(stderr, "sim: %s sets the clock of a moving object: give --motion too\n", argv[i]);
            return 2;
        }
    if (o.motion && o.contact) {
        fprintf(stderr, "sim: --contact is simulated against an object standing still: not with --motion\n");
        return 2;
    }
    if (o.accuracy > 0.0 || o.accuracy_rel > 0.0) {
        /* the target chooses eps, the sizing field and its floor, and is measured */
        if (o.eps > 0.0 || o.eps_rel > 0.0 || o.size_rel > 0.0 || o.min_size > 0.0 || o.max_distance > 0.0) {
            fprintf(stderr, "sim: --accuracy chooses eps, the distance bound and its floor: give it alone\n");
            return 2;
        }
        if (o.hausdorff == 0) { fprintf(stderr, "sim: --accuracy is measured: --hausdorff 0 would skip that\n"); return 2; }
    } else if (!(o.eps > 0.0) && !(o.eps_rel > 0.0)) {
        fprintf(stderr, "sim: give --eps, --eps-rel or --accuracy (see --help)\n");
        return 2;
    }
    /* every output path is checked before anything is scanned or written */
    if (vp_sim_check_out(&o, err, sizeof err) != VP_OK || vp_sim_session_set_path(&g, &o, err, sizeof err) != VP_OK) {
        fprintf(stderr, "sim: %s\n", err);
        vp_sim_session_free(&g);
        return 2;
    }
    if (png && vp_mkdirs_for(png) != 0) {
        fprintf(stderr, "sim: cannot create the folder of %s: %s\n", png, strerror(errno));
        vp_sim_session_free(&g);
        return 2;
    }
    st = vp_sim_open(&sim, &o, err, sizeof err);
    if (st == VP_OK) st = vp_sim_session_begin(&g, &sim, &o, o.quiet ? NULL : stderr, err, sizeof err);
    if (st != VP_OK) {
        /* a setting out of what the planner supports is a usage error, as a bad value is */
        fprintf(stderr, "sim: %s\n", err);
        vp_sim_close(&sim);
        vp_sim_session_free(&g);
        return st == VP_EINVAL ? 2 : 1;
    }
    if (!o.quiet)
        fprintf(stderr, "voroprobe sim: %s, eps %.6g, %d component(s), arena %zu bytes\n",
                o.surface, sim.cfg.eps, sim.components, o.arena);
    {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = sim_on_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESETHAND; /* a second one ends the process at once */
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
        g.w.stop_flag = &sim_stop;
    }
    if (vp_live_cli_begin(&live, sim.pl, &sim.hooks, o.quiet ? NULL : stderr, "sim")) {
        vp_sim_close(&sim);
        vp_sim_session_free(&g);
        return 1;
    }
    st = g.complete ? VP_OK : vp_sim_run(&sim, o.quiet ? NULL : stderr);
    if (track > 0 && !g.complete && st == VP_OK) {
        st = vp_sim_track(&sim, &o, track, g.sparse ? VP_RESCAN_SPARSE : 0u, g.active ? track_event : NULL, &g,
                          o.quiet ? NULL : stderr);
        if (st == VP_OK) st = sim.run.status;
    }
    i = vp_sim_session_end(&g, &sim, stderr);
    if (g.active) vp_audit_keep(g.path); /* for an independent proof check (VP_AUDIT_DIR) */
    if (i) { vp_sim_close(&sim); vp_sim_session_free(&g); return 1; }
    sim.paused = st == VP_EABORT && g.w.stopped;
    if (sim.paused)
        ; /* paused on purpose: said by vp_sim_session_end */
    else if (st != VP_OK && st != VP_ENOMEM)
        fprintf(stderr, "sim: the scan stopped: %s\n",
                st != VP_ERANGE ? vp_strerror(st)
                : o.clearance > 0 && o.max_range > 0
                    ? "the probe from dOmega towards an interior point found no surface within the rangefinder's "
                      "reach (a device with a body does not enter Omega: raise --max-range)"
                    : "the probe towards an interior point found no surface along its whole ray "
                      "(the point is not inside the object)");
    else if (st == VP_ENOMEM)
        fprintf(stderr, "sim: the arena is full (--arena): the mesh so far is written\n");
    st = vp_sim_finish(&sim, &o, err, sizeof err);
    if (st != VP_OK) fprintf(stderr, "sim: %s\n", err);
    vp_live_cli_end(&live, vp_outcome_name(vp_sim_exit(&sim)), &sim.mesh, o.quiet ? NULL : stderr, "sim");
    if (st == VP_OK && png && (st = vp_render_png(&sim.mesh, NULL, png, err, sizeof err)) != VP_OK) fprintf(stderr, "sim: %s\n", err);
    if (!o.quiet || !o.json) vp_sim_session_report(&g, stdout);
    vp_sim_report(&sim, &o, stdout);
    i = st != VP_OK ? VP_EXIT_ERROR : vp_sim_exit(&sim);
    vp_sim_close(&sim);
    vp_sim_session_free(&g);
    return i;
}

/* `voroprobe track`: `sim --track N` under its own name (--rounds N, default 5). */
int vp_cli_track(int argc, char **argv)
{
    char **av = malloc(((size_t)argc + 3) * sizeof *av);
    const char *rounds = "5";
    int i, n = 0, st;
    if (!av) { fprintf(stderr, "track: out of memory\n"); return 1; }
    av[n++] = argv[0];
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            printf("usage: voroprobe track --surface SPEC (--eps E | --eps-rel R) [--motion SPEC] [--rounds N] [options]\n"
                   "Keeps the mesh of an object that moves and deforms (host-sim's --motion) over N rounds\n"
                   "(default 5) after a first scan: each round is a re-scan from where the device stands,\n"
                   "every sample measured again, the moved ones removed and their surroundings scanned\n"
                   "again, every old proof of free space probed again before the device moves along it.\n"
                   "Every round's figures (time, probes, samples kept and removed, closed, genus,\n"
                   "collisions with the moving object, Hausdorff to it at the round's end) go to the\n"
                   "summary and --json (\"rounds\"). The options are those of `voroprobe sim` (see\n"
                   "voroprobe sim --help); `track` is `sim --track N`.\n");
            free(av);
            return 0;
        }
        if (!strcmp(argv[i], "--rounds") && i + 1 < argc) {
            if (!track_rounds(argv[++i])) {
                fprintf(stderr, "track: --rounds takes a number of rounds, 1..1000, not '%s'\n", argv[i]);
                free(av);
                return 2;
            }
            rounds = argv[i];
            continue;
        }
        av[n++] = argv[i];
    }
    av[n++] = (char *)"--track";
    av[n++] = (char *)rounds;
    av[n] = NULL;
    st = vp_cli_sim(n, av);
    free(av);
    return st;
}
