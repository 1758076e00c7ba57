/* build/voroprobe: the command-line front end of the scanner. */
#include <stdio.h>
#include <string.h>
#include "vp_backends.h"
#include "vp_cli.h"

#define VP_VERSION "0.1.0"

static const struct vp_cli_cmd commands[] = {
    { "sim", vp_cli_sim, "scan a simulated object (host-sim) and write the mesh" },
    { "scan", vp_cli_scan, "scan an object on a board's machine (or --dry-run on host-sim), logged" },
    { "calibrate", vp_cli_calibrate, "fit the rangefinder model against a flat target; write the calibration" },
    { "track", vp_cli_track, "keep the mesh of a moving, deforming object over rounds of re-scans (host-sim)" },
    { "mcu", vp_cli_mcu, "scan with the planner on a microcontroller (qemu, serial, pipe), host-sim as the object" },
    { "replay", vp_cli_replay, "replay a session log through the planner, bit for bit, and mesh it" },
    { "mesh", vp_cli_mesh, "the mesh (and probed points) of a session log, complete or not" },
    { "report", vp_cli_report, "one self-contained HTML page of a session log: 3D viewer, summary, plots" },
    { "certify", vp_cli_certify, "check the papers' hypotheses H1-H3 on a log or mesh, facet by facet" },
    { "log", vp_cli_log, "session logs: dump the records, check CRCs and what is recoverable" },
    { "reconstruct", vp_cli_reconstruct, "a k-manifold from points in R^d: the tangential Delaunay complex" },
    { "bench-delaunay", vp_cli_bench_delaunay, "3D Delaunay of a point set (TetGen .node or generated)" },
};

static void usage(FILE *f)
{
    size_t i;
    fprintf(f, "usage: voroprobe COMMAND [options]   (voroprobe COMMAND --help for details)\n"
               "       voroprobe --version              (the version and the hardware backends built in)\n\n");
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-16s %s\n", commands[i].name, commands[i].summary);
}

int main(int argc, char **argv)
{
    size_t i;
    if (argc < 2) { usage(stderr); return 2; }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "-V") || !strcmp(argv[1], "version")) {
        char b[256];
        vp_backends_describe(b, sizeof b);
        printf("voroprobe %s\n%s\n", VP_VERSION, b);
        return 0;
    }
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (commands[i].run && !strcmp(argv[1], commands[i].name))
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "voroprobe: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
