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
