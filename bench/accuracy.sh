#!/bin/sh
# The accuracy target (sim --accuracy-rel R) against CGAL's surface mesher on the same objects, in
# the same run. Every mesh -- ours and CGAL's -- is measured by CGAL (tests/cgal_object.cpp:
# PMP::approximate_Hausdorff_distance both ways), never by voroprobe's own measure.
#   ours:  vertices, probes per vertex, whole simulated scan seconds, closed + genus, H/target
#   CGAL:  make_surface_mesh, angle 30 deg, radius bound diagonal/20, manifold tag, with the
#          distance bound H (the issue's setting) and then H/1.5, H/2, ... until its measured
#          Hausdorff is at most ours; its vertices and seconds at our measured Hausdorff are
#          interpolated (log-log) between the two runs that bracket it
#   uniform: the uniform-eps planner (sim --eps-rel) at eps-rel 0.02, 0.014, 0.01, 0.007, 0.005
#          until its measured Hausdorff is at most ours (or 300k vertices); the same interpolation
# Then the lower bound of paper 002 on the size of a loose eps-sample, |E| >= 2 + (2/(5 pi))
# area / eps^2, against uniform scans of the sphere and the torus.
set -u
B=${1:-build}
VP="$B/voroprobe"
D="$B/bench/accuracy"
mkdir -p "$D"
RATES=${VP_BENCH_ACCURACY_RATES:-"0.002 0.001"}
M=../shared/meshes
T=tests/meshes
OBJECTS=${VP_BENCH_ACCURACY:-"$M/fandisk.off $M/dino.off $M/bear.off $M/knot.off $M/blob-closed.off $M/ellipe0.003.off $M/sphere966.off $T/cube.off $T/box.off $T/cylinder32.off $T/cone32.off $T/octa.off $T/tetra.off"}
CG="$D/cgal_object"
if [ ! -f /usr/include/CGAL/Polygon_mesh_processing/distance.h ]; then
  echo "accuracy bench: CGAL (libcgal-dev) is not installed: nothing to measure against"; exit 0
fi
if [ ! -x "$CG" ] || [ tests/cgal_object.cpp -nt "$CG" ]; then
  g++ -O2 -DNDEBUG -o "$CG" tests/cgal_object.cpp -lgmp -lmpfr 2>"$D/build.log" || { echo "cgal_object does not build: $D/build.log"; exit 1; }
fi
field() { sed -n "s/.*\"$1\":\([^,}]*\).*/\1/p" | tr -d '"'; }
chaus() { "$CG" hausdorff "$1" "$2" | field hausdorff; }
# interp H_TARGET "h1 v1 s1" "h2 v2 s2": v and s at H_TARGET, log-log between (h1 > target >= h2)
interp() {
  awk -v t="$1" -v a="$2" -v b="$3" 'BEGIN {
    split(a, x, " "); split(b, y, " ");
    if (x[1] <= t || y[1] == x[1]) { printf "%d %.3f\n", y[2], y[3]; exit }
    f = (log(t) - log(x[1])) / (log(y[1]) - log(x[1]));
    printf "%d %.3f\n", exp(log(x[2]) + f * (log(y[2]) - log(x[2]))), exp(log(x[3]) + f * (log(y[3]) - log(x[3]))) }'
}
echo "Accuracy target vs CGAL's surface mesher (angle 30, distance bound, manifold tag); every Hausdorff measured by CGAL"
printf '%-12s %6s %7s %5s %7s %8s %5s | %7s %6s | %7s %5s %7s %5s | %7s %5s\n' \
  object R verts p/v sec closed H/T cgal@H H/T cgal_v= v/cgal cgal_s= c/ours uni_v= v/uni
for R in $RATES; do
  for obj in $OBJECTS; do
    [ -f "$obj" ] || { echo "skip $obj (not found)"; continue; }
    n=$(basename "$obj" .off)
    j=$("$VP" sim --surface "off:$obj" --accuracy-rel "$R" --quiet --json --no-log --out "$D/$n" | tail -1)
    v=$(echo "$j" | field vertices); p=$(echo "$j" | field probes); s=$(echo "$j" | field total_seconds)
    st=$(echo "$j" | field status); g=$(echo "$j" | field genus); t=$(echo "$j" | field accuracy_target)
    e=$(echo "$j" | field eps)
    h=$(chaus "$obj" "$D/$n.off")
    # CGAL: the distance bound H first (the issue's row), then finer until it reaches our H
    prev=""; cv=""; first=""
    for k in 1 1.5 2 3 4 6 8 12; do
      dist=$(awk -v t="$t" -v k="$k" 'BEGIN { printf "%.9g", t / k }')
      cj=$("$CG" mesh "$obj" "$dist" "$e" "$D/$n-cgal.off" 2>/dev/null) || break
      ch=$(chaus "$obj" "$D/$n-cgal.off"); cvv=$(echo "$cj" | field vertices); cs=$(echo "$cj" | field seconds)
      [ -n "$first" ] || first="$cvv $ch"
      cur="$ch $cvv $cs"
      if awk -v a="$ch" -v b="$h" 'BEGIN { exit !(a <= b) }'; then
        set -- $(interp "$h" "${prev:-$cur}" "$cur"); cv=$1; csec=$2; break
      fi
      prev="$cur"
    done
    set -- $first; fv=$1; fh=$2
    [ -n "$cv" ] || { cv=""; csec=""; }
    # the uniform-eps planner, the same way (when it never gets there: its finest run, ">")
    uprev=""; uv=""; ulast=""
    for er in 0.02 0.014 0.01 0.007 0.005; do
      uj=$("$VP" sim --surface "off:$obj" --eps-rel "$er" --quiet --json --no-log --hausdorff 0 --out "$D/$n-uni" | tail -1)
      uvv=$(echo "$uj" | field vertices); us=$(echo "$uj" | field total_seconds)
      [ "$(echo "$uj" | field status)" = closed ] || { uprev=""; continue; }
      uh=$(chaus "$obj" "$D/$n-uni.off")
      ucur="$uh $uvv $us"; ulast=">$uvv"
      if awk -v a="$uh" -v b="$h" 'BEGIN { exit !(a <= b) }'; then
        set -- $(interp "$h" "${uprev:-$ucur}" "$ucur"); uv=$1; break
      fi
      uprev="$ucur"
      [ "$uvv" -gt 300000 ] && break
    done
    awk -v n="$n" -v R="$R" -v v="$v" -v p="$p" -v s="$s" -v st="$st" -v g="$g" -v h="$h" -v t="$t" \
        -v fv="$fv" -v fh="$fh" -v cv="$cv" -v cs="${csec:-}" -v uv="$uv" -v ul="$ulast" 'BEGIN {
      printf "%-12s %6s %7d %5.1f %7.2f %8s %5.2f | %7d %6.2f | %7s %5s %7s %5s | %7s %5s\n", n, R, v, p / v, s,
        (st == "closed" ? "yes/" g : st), h / t, fv, fh / t,
        (cv == "" ? "-" : cv), (cv == "" ? "-" : sprintf("%.2f", v / cv)),
        (cs == "" ? "-" : sprintf("%.2f", cs)), (cs == "" ? "-" : sprintf("%.2f", cs / s)),
        (uv == "" ? (ul == "" ? "-" : ul) : uv), (uv == "" ? "-" : sprintf("%.2f", v / uv)) }'
  done
done
echo "H/T: Hausdorff / target (CGAL's measure); cgal@H: CGAL's mesher with distance bound H and its H/T;"
echo "cgal_v=, cgal_s=, uni_v=: vertices and seconds CGAL's mesher, and vertices the uniform-eps planner, need"
echo "for our measured Hausdorff (>N: the uniform planner's finest run, N vertices, is still farther);"
echo "v/cgal, v/uni: ours over theirs (below 1: fewer vertices than they need); c/ours: CGAL's mesher"
echo "seconds over our whole simulated scan's (above 1: the scan is faster than CGAL's mesher)."

echo
echo "Paper 002's lower bound on a loose eps-sample: |E| >= 2 + (2/(5 pi)) area / eps^2"
for c in sphere:0.1:12.566371 sphere:0.05:12.566371 torus:0.1:11.843525 torus:0.05:11.843525; do
  s=${c%%:*}; r=${c#*:}; e=${r%%:*}; a=${r#*:}
  v=$("$VP" sim --surface "$s" --eps "$e" --quiet --json --no-log --hausdorff 0 --out "$D/lb" | tail -1 | field vertices)
  awk -v s="$s" -v e="$e" -v a="$a" -v v="$v" 'BEGIN { lb = 2 + 2 / (5 * 3.14159265358979) * a / (e * e);
    printf "%-7s eps %-5s vertices %6d  bound %8.1f  %s\n", s, e, v, lb, (v >= lb ? "holds" : "VIOLATED") }'
done
