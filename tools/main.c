/* build/voroprobe: the command-line front end of the scanner. */
#include <stdio.h>
#include <string.h>
#include "vp_cli.h"

static const struct vp_cli_cmd commands[] = {
    { "sim", vp_cmd_sim, "scan a simulated object (host-sim) and write the mesh" },
    { "bench-delaunay", vp_cmd_bench_delaunay, "3D Delaunay of a point set (TetGen .node or generated)" },
};

static void usage(FILE *f)
{
    size_t i;
    fprintf(f, "usage: voroprobe COMMAND [options]   (voroprobe COMMAND --help for details)\n\n");
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
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (commands[i].run && !strcmp(argv[1], commands[i].name))
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "voroprobe: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
