/* voroprobe bench-delaunay: time the 3D Delaunay triangulation of a point set. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_cli.h"
#include "vp_dt.h"
#include "vp_pointgen.h"
#include "vp_rtclock.h"
#include "vp_sim_opts.h"

static void bench_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe bench-delaunay (--node FILE | --uniform N [--seed S] | --grid K |\n"
        "                                 --sphere N [--seed S]) [--check] [--bytes-per-point B]\n"
        "                                [--save-node FILE]\n"
        "Triangulates the points (spatial sort + incremental insertion in one arena) and prints\n"
        "one JSON line: points, finite tets, seconds (sort + insertion), points_per_second,\n"
        "arena_bytes (arena actually used), bytes_per_point, valid (with --check: the full\n"
        "vp_dt_check; otherwise null).\n"
        "  --node FILE         TetGen .node file (first line: N 3 0 0; then: index x y z)\n"
        "  --uniform N         N points uniform in [0,1)^3\n"
        "  --grid K            the K^3 integer grid, shuffled\n"
        "  --sphere N          N points on the unit sphere\n"
        "  --seed S            generator seed (default 1)\n"
        "  --bytes-per-point B arena given to the triangulation (default 300)\n"
        "  --save-node FILE    also write the points as a .node file (for other tools)\n");
}

int vp_cli_bench_delaunay(int argc, char **argv)
{
    const char *node = NULL, *save = NULL;
    long uniform = -1, grid = -1, sphere = -1;
    unsigned long long seed = 1;
    double bpp = 300.0;
    int check = 0, i, st, valid = -1;
    double *xyz = NULL, t0, t1;
    size_t n = 0, bytes;
    void *arena;
    vp_dt_t dt;
    char err[256];

    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { bench_usage(stdout); return 0; }
        if (!strcmp(a, "--check")) { check = 1; continue; }
        if (strcmp(a, "--node") && strcmp(a, "--uniform") && strcmp(a, "--grid") && strcmp(a, "--sphere") &&
            strcmp(a, "--seed") && strcmp(a, "--bytes-per-point") && strcmp(a, "--save-node")) {
            fprintf(stderr, "bench-delaunay: unknown option %s\n", a);
            bench_usage(stderr);
            return 2;
        }
        if (!val) { fprintf(stderr, "bench-delaunay: %s needs a value\n", a); return 2; }
        if (!strcmp(a, "--node")) node = val;
        else if (!strcmp(a, "--save-node")) save = val;
        else if (!strcmp(a, "--bytes-per-point")) {
            char *e;
            bpp = strtod(val, &e);
            if (e == val || *e || !(bpp > 0.0) || !isfinite(bpp)) {
                fprintf(stderr, "bench-delaunay: --bytes-per-point takes a positive number, not '%s'\n", val);
                return 2;
            }
        } else {
            /* a count: the seed any, the points 1 to 1e8 */
            int is_seed = !strcmp(a, "--seed");
            unsigned long long cnt;
            if (vp_parse_count(val, is_seed ? ~0ull : 100000000ull, &cnt) || (!is_seed && cnt == 0)) {
                fprintf(stderr, "bench-delaunay: %s takes a whole number%s, not '%s'\n", a, is_seed ? "" : " from 1 to 1e8", val);
                return 2;
            }
            if (is_seed) seed = cnt;
            else if (!strcmp(a, "--uniform")) uniform = (long)cnt;
            else if (!strcmp(a, "--grid")) grid = (long)cnt;
            else sphere = (long)cnt;
        }
        i++;
    }
    if ((node != NULL) + (uniform >= 0) + (grid >= 0) + (sphere >= 0) != 1) {
        fprintf(stderr, "bench-delaunay: give exactly one of --node, --uniform, --grid, --sphere\n");
        bench_usage(stderr);
        return 2;
    }
    if (node) st = vp_pointgen_read_node(node, &xyz, &n, err, sizeof err);
    else if (uniform >= 0) st = vp_pointgen_uniform((size_t)uniform, seed, &xyz, &n, err, sizeof err);
    else if (grid >= 0) st = vp_pointgen_grid((size_t)grid, seed, &xyz, &n, err, sizeof err);
    else st = vp_pointgen_sphere((size_t)sphere, seed, &xyz, &n, err, sizeof err);
    if (st) { fprintf(stderr, "bench-delaunay: %s\n", err); return 1; }
    if (save && vp_pointgen_write_node(save, xyz, n, err, sizeof err)) {
        fprintf(stderr, "bench-delaunay: %s\n", err);
        free(xyz);
        return 1;
    }
    if (n > VP_DT_MAX_VERTICES) { fprintf(stderr, "bench-delaunay: too many points\n"); free(xyz); return 1; }
    if (!(bpp >= 64.0)) { fprintf(stderr, "bench-delaunay: --bytes-per-point must be >= 64\n"); free(xyz); return 2; }
    bytes = (size_t)(bpp * (double)n) + (1u << 20);
    arena = malloc(bytes);
    if (!arena) { fprintf(stderr, "bench-delaunay: cannot allocate %zu bytes\n", bytes); free(xyz); return 1; }
    if (vp_dt_init(&dt, arena, bytes, 0) != VP_OK) { fprintf(stderr, "bench-delaunay: init failed\n"); return 1; }
    t0 = vp_rt_seconds();
    st = vp_dt_insert_batch(&dt, xyz, (uint32_t)n, NULL);
    t1 = vp_rt_seconds();
    if (st != VP_OK) {
        fprintf(stderr, "bench-delaunay: insertion failed: %s (try a larger --bytes-per-point)\n",
                vp_strerror(st));
        free(arena); free(xyz);
        return 1;
    }
    if (check) valid = vp_dt_check(&dt) == VP_OK;
    printf("{\"points\":%zu,\"tets\":%u,\"seconds\":%.4f,\"points_per_second\":%.0f,"
           "\"arena_bytes\":%zu,\"bytes_per_point\":%.1f,\"valid\":%s}\n",
           n, vp_dt_num_finite_tets(&dt), t1 - t0, (double)n / (t1 - t0), vp_dt_bytes_used(&dt),
           n ? (double)vp_dt_bytes_used(&dt) / (double)n : 0.0,
           valid < 0 ? "null" : valid ? "true" : "false");
    free(arena);
    free(xyz);
    return valid == 0 ? 1 : 0;
}
