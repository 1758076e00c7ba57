#!/bin/sh
# 3D Delaunay: voroprobe against the anchors of ../shared/ANCHORS.md, measured in the same run.
# Each figure is the median of 3 runs, one process per run. Where CGAL (libcgal-dev) is
# installed its time is re-measured here on the very same points; otherwise the anchor table's
# figure is used and marked "(table)".
set -u
B=${1:-build}
VP="$B/voroprobe"
D="$B/bench"; mkdir -p "$D"
RUNS=${VP_BENCH_RUNS:-3}
SETS=${VP_BENCH_SETS:-"uniform:100000 uniform:1000000 grid:50 sphere:100000"}

cgal=""
if [ -f /usr/include/CGAL/Delaunay_triangulation_3.h ]; then
  if [ ! -x "$D/cgal_delaunay" ] || [ bench/cgal_delaunay.cpp -nt "$D/cgal_delaunay" ]; then
    g++ -O2 -DNDEBUG -o "$D/cgal_delaunay" bench/cgal_delaunay.cpp -lgmp -lmpfr 2>"$D/cgal-build.log" || true
  fi
  [ -x "$D/cgal_delaunay" ] && cgal="$D/cgal_delaunay"
fi

# table anchors: CGAL sorted seconds
anchor_s() {
  case $1 in uniform:100000) echo 0.475;; uniform:1000000) echo 4.610;; grid:50) echo 1.080;;
    sphere:100000) echo 1.417;; *) echo "";; esac
}
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
field() { sed -n "s/.*\"$1\":\([^,}]*\).*/\1/p"; }

echo "3D Delaunay: voroprobe bench-delaunay vs CGAL Delaunay_triangulation_3 (sorted), median of $RUNS"
printf '%-16s %9s %9s %10s %9s %10s %8s %7s %6s\n' set points tets vp_s vp_pts/s cgal_s ratio B/pt valid
for s in $SETS; do
  kind=${s%%:*}; n=${s#*:}
  node="$D/$kind-$n.node"
  [ -f "$node" ] || "$VP" bench-delaunay --$kind "$n" --seed 1 --save-node "$node" >/dev/null
  : >"$D/vp.txt"
  i=0; while [ $i -lt "$RUNS" ]; do
    if [ $i -eq 0 ]; then "$VP" bench-delaunay --node "$node" --check >>"$D/vp.txt"
    else "$VP" bench-delaunay --node "$node" >>"$D/vp.txt"; fi
    i=$((i+1)); done
  vs=$(field seconds <"$D/vp.txt" | median)
  tets=$(head -1 "$D/vp.txt" | field tets)
  bpp=$(head -1 "$D/vp.txt" | field bytes_per_point)
  valid=$(head -1 "$D/vp.txt" | field valid)
  cs=""; src=""
  if [ -n "$cgal" ]; then
    : >"$D/cgal.txt"
    i=0; while [ $i -lt "$RUNS" ]; do "$cgal" "$node" >>"$D/cgal.txt"; i=$((i+1)); done
    cs=$(field seconds <"$D/cgal.txt" | median)
    ctets=$(head -1 "$D/cgal.txt" | field tets)
    [ "$ctets" = "$tets" ] || echo "  note: CGAL finite tets $ctets, voroprobe $tets"
  fi
  [ -n "$cs" ] || { cs=$(anchor_s "$s"); src="(table)"; }
  ratio=$(awk -v a="$cs" -v b="$vs" 'BEGIN { if (b > 0 && a != "") printf "%.2fx", a / b; else print "-" }')
  pps=$(awk -v n="$n" -v s="$vs" 'BEGIN { k = n; if ("'$kind'" == "grid") k = n*n*n; printf "%.0f", k / s }')
  printf '%-16s %9s %9s %10s %9s %10s %8s %7s %6s\n' "$s" "$( [ $kind = grid ] && echo $((n*n*n)) || echo $n)" "$tets" "$vs" "$pps" "$cs$src" "$ratio" "$bpp" "$valid"
done
echo "ratio = CGAL seconds / voroprobe seconds (above 1: voroprobe faster)"

# Vertex removal: vp_dt_remove against CGAL's Delaunay_triangulation_3::remove on the same points
# and the same subset, in the same run. Both build the triangulation of all points first (not
# timed), then remove a fixed random 10% of them (one after the other, in the same order), timed.
# The driver below (C, against the core and mesh libraries of $B) draws the subset (splitmix64,
# seed 1) and writes it for CGAL; with --check it also validates the result (vp_dt_check) and
# counts the finite tets of a from-scratch build of the remaining points.
RSETS=${VP_BENCH_REMOVE_SETS:-"uniform:100000 uniform:1000000 sphere:100000"}
RFRAC=${VP_BENCH_REMOVE_FRACTION:-0.1}
if [ -n "$RSETS" ]; then
cat >"$D/vp_remove.c" <<'CEOF'
/* written by bench/delaunay.sh: times vp_dt_remove on a .node file (see there) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_dt.h"
#include "vp_pointgen.h"
#include "vp_rng.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    double *xyz, frac, t0, t1, *rest;
    size_t n, m, i, bytes, nrest = 0;
    uint32_t *ids, *perm, slots_before, nfree_after, tets_after;
    uint64_t s = 1;
    void *arena;
    vp_dt_t dt;
    char err[256];
    int check = argc > 4 && !strcmp(argv[4], "--check"), valid = -1;
    long scratch_tets = -1, regrow = -1;
    FILE *f;
    if (argc < 4) { fprintf(stderr, "usage: vp_remove FILE.node FRACTION LIST [--check]\n"); return 2; }
    if (vp_pointgen_read_node(argv[1], &xyz, &n, err, sizeof err)) { fprintf(stderr, "%s\n", err); return 1; }
    frac = strtod(argv[2], NULL);
    m = (size_t)(frac * (double)n);
    bytes = 300 * n + (1u << 20);
    arena = malloc(bytes);
    ids = malloc(n * sizeof *ids);
    perm = malloc(n * sizeof *perm);
    if (!arena || !ids || !perm || vp_dt_init(&dt, arena, bytes, 0) != VP_OK) return 1;
    if (vp_dt_insert_batch(&dt, xyz, (uint32_t)n, ids) != VP_OK || dt.ninserted != n) {
        fprintf(stderr, "insertion failed (or duplicate points)\n");
        return 1;
    }
    for (i = 0; i < n; i++) perm[i] = (uint32_t)i;
    for (i = n; i > 1; i--) { /* Fisher-Yates: the first m are the subset, in removal order */
        size_t j = (size_t)(vp_splitmix_next(&s) % i);
        uint32_t x = perm[i - 1]; perm[i - 1] = perm[j]; perm[j] = x;
    }
    if (!(f = fopen(argv[3], "w"))) { perror(argv[3]); return 1; }
    for (i = 0; i < m; i++) fprintf(f, "%u\n", perm[i]);
    fclose(f);
    slots_before = dt.ntet_slots;
    t0 = now();
    for (i = 0; i < m; i++)
        if (vp_dt_remove(&dt, ids[perm[i]]) != VP_OK) { fprintf(stderr, "removal failed\n"); return 1; }
    t1 = now();
    nfree_after = dt.nfree;
    tets_after = vp_dt_num_finite_tets(&dt);
    if (check) {
        vp_dt_t sd;
        void *a2 = malloc(bytes);
        valid = vp_dt_check(&dt) == VP_OK && dt.ninserted == n - m;
        rest = malloc(3 * sizeof(double) * n);
        for (i = 0; i < dt.nvert; i++)
            if (vp_dt_vertex(&dt, (uint32_t)i)->tet != VP_DT_NONE)
                memcpy(rest + 3 * nrest++, vp_dt_point(&dt, (uint32_t)i), 3 * sizeof(double));
        if (a2 && rest && vp_dt_init(&sd, a2, bytes, 0) == VP_OK &&
            vp_dt_insert_batch(&sd, rest, (uint32_t)nrest, NULL) == VP_OK)
            scratch_tets = (long)vp_dt_num_finite_tets(&sd);
        free(a2);
        free(rest);
        /* the removed points again: the new tets go into the freed slots */
        for (i = 0; i < m; i++)
            if (vp_dt_insert(&dt, xyz + 3 * (size_t)perm[i], VP_DT_NONE, NULL) != VP_OK) break;
        regrow = i == m ? (long)dt.ntet_slots - (long)slots_before : -1;
    }
    printf("{\"points\":%zu,\"removed\":%zu,\"tets\":%u,\"seconds\":%.4f,\"free_slots\":%u,"
           "\"valid\":%s,\"scratch_tets\":%ld,\"reinsert_new_slots\":%ld}\n",
           n, m, tets_after, t1 - t0, nfree_after,
           valid < 0 ? "null" : valid ? "true" : "false", scratch_tets, regrow);
    return valid == 0;
}
CEOF
CC_=${CC:-gcc}
"$CC_" -std=c99 -O2 -ffp-contract=off -D_POSIX_C_SOURCE=200809L -Icore -Imesh -o "$D/vp_remove" "$D/vp_remove.c" \
  "$B/libvpmesh.a" "$B/libvpcore.a" -lm 2>"$D/vp_remove-build.log" || { echo "vp_remove: build failed ($D/vp_remove-build.log)"; exit 1; }
cgalr=""
[ -n "$cgal" ] && cgalr="$cgal" # the same program: with a list of indices it times removal
echo
echo "Vertex removal: vp_dt_remove vs CGAL Delaunay_triangulation_3::remove, a fixed random $RFRAC of the points, median of $RUNS"
printf '%-16s %8s %8s %9s %9s %8s %9s %9s %6s %6s %6s\n' set points removed vp_s cgal_s ratio tets cgal_tets equal valid slots+
for s in $RSETS; do
  kind=${s%%:*}; n=${s#*:}
  node="$D/$kind-$n.node"
  [ -f "$node" ] || "$VP" bench-delaunay --$kind "$n" --seed 1 --save-node "$node" >/dev/null
  list="$D/$kind-$n.remove"
  : >"$D/vpr.txt"
  i=0; while [ $i -lt "$RUNS" ]; do
    if [ $i -eq 0 ]; then "$D/vp_remove" "$node" "$RFRAC" "$list" --check >>"$D/vpr.txt"
    else "$D/vp_remove" "$node" "$RFRAC" "$list" >>"$D/vpr.txt"; fi
    i=$((i+1)); done
  vs=$(field seconds <"$D/vpr.txt" | median)
  m=$(head -1 "$D/vpr.txt" | field removed)
  tets=$(head -1 "$D/vpr.txt" | field tets)
  stets=$(head -1 "$D/vpr.txt" | field scratch_tets)
  valid=$(head -1 "$D/vpr.txt" | field valid)
  regrow=$(head -1 "$D/vpr.txt" | field reinsert_new_slots)
  [ "$stets" = "$tets" ] || { echo "  note: from-scratch build of the remaining points has $stets finite tets"; valid=false; }
  cs="-"; ctets="-"; equal="-"
  if [ -n "$cgalr" ]; then
    : >"$D/cgalr.txt"
    i=0; while [ $i -lt "$RUNS" ]; do "$cgalr" "$node" "$list" >>"$D/cgalr.txt"; i=$((i+1)); done
    cs=$(field seconds <"$D/cgalr.txt" | median)
    ctets=$(head -1 "$D/cgalr.txt" | field tets)
    if [ "$ctets" = "$tets" ]; then equal=yes; else equal=NO; fi
  fi
  ratio=$(awk -v a="$cs" -v b="$vs" 'BEGIN { if (b > 0 && a != "-") printf "%.2fx", a / b; else print "-" }')
  printf '%-16s %8s %8s %9s %9s %8s %9s %9s %6s %6s %6s\n' "$s" "$n" "$m" "$vs" "$cs" "$ratio" "$tets" "$ctets" "$equal" "$valid" "$regrow"
done
echo "ratio = CGAL seconds / voroprobe seconds (above 1: voroprobe faster); tets: finite tets after the"
echo "removals (voroprobe's equal to a from-scratch build of the remaining points, checked); equal: CGAL's"
echo "count is the same; slots+: new tet slots needed to insert the removed points again (0: all in freed ones)"
fi
