#!/bin/sh
# The probing planner on host-sim against CGAL's surface mesher (radius criterion only, the
# seed-000 rule), re-measured here on the same surfaces and radii, and against the published
# rule run by voroprobe itself (--paper: every edge probed, prev-chain travel, largest ball
# first). Times: voroprobe's whole simulated scan (planner + simulated probes) vs CGAL's
# refinement. Medians of 3 runs for times; counts are deterministic.
set -u
B=${1:-build}
VP="$B/voroprobe"
D="$B/bench"; mkdir -p "$D"
RUNS=${VP_BENCH_RUNS:-3}
CASES=${VP_BENCH_PLANNER:-"sphere:0.1 sphere:0.05 sphere:0.02 torus:0.1 torus:0.05 torus:0.02 genus2:0.1 genus2:0.05 genus2:0.02"}
cgal=""
if [ -f /usr/include/CGAL/make_surface_mesh.h ]; then
  if [ ! -x "$D/cgal_mesher" ] || [ bench/cgal_mesher.cpp -nt "$D/cgal_mesher" ]; then
    g++ -O2 -DNDEBUG -o "$D/cgal_mesher" bench/cgal_mesher.cpp -lgmp -lmpfr 2>"$D/cgal-mesher-build.log" || true
  fi
  [ -x "$D/cgal_mesher" ] && cgal="$D/cgal_mesher"
fi
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
field() { sed -n "s/.*\"$1\":\([^,}]*\).*/\1/p" | tr -d '"'; }
# table anchors (ANCHORS.md): CGAL mesher seconds and vertices
anchor() {
  case $1 in
    sphere:0.1) echo "0.044 824";; sphere:0.05) echo "0.226 3327";; sphere:0.02) echo "1.897 20675";;
    torus:0.1) echo "0.080 794";; torus:0.05) echo "0.335 3115";; torus:0.02) echo "4.134 19607";;
    genus2:0.1) echo "0.173 1407";; genus2:0.05) echo "0.984 5627";; genus2:0.02) echo "7.063 35040";;
  esac
}
echo "Probing planner (voroprobe sim) vs CGAL surface mesher (radius only), median of $RUNS"
printf '%-12s %7s %7s %6s %8s %8s %6s %6s %6s %6s %9s %9s %5s %4s %6s %6s\n' case verts cgal_v dv% sim_s cgal_s ratio p/v p/v_pap hits% travel trav_pap tr_x coll B/vert cm+g
for c in $CASES; do
  s=${c%%:*}; e=${c#*:}
  : >"$D/sim.txt"
  i=0; while [ $i -lt "$RUNS" ]; do
    "$VP" sim --surface "$s" --eps "$e" --quiet --json --hausdorff 0 --no-log --out "$D/$s-$e" | tail -1 >>"$D/sim.txt"; i=$((i+1)); done
  line=$(head -1 "$D/sim.txt")
  vs=$(field total_seconds <"$D/sim.txt" | median)
  v=$(echo "$line" | field vertices); p=$(echo "$line" | field probes); h=$(echo "$line" | field hits)
  tr=$(echo "$line" | field travel); co=$(echo "$line" | field collisions); ab=$(echo "$line" | field arena_bytes_peak)
  cm=$(echo "$line" | field closed_manifold); g=$(echo "$line" | field genus)
  pap=$("$VP" sim --surface "$s" --eps "$e" --quiet --json --hausdorff 0 --no-log --paper --out "$D/$s-$e-paper" | tail -1)
  pp=$(echo "$pap" | field probes); pv=$(echo "$pap" | field vertices); pt=$(echo "$pap" | field travel)
  cs=""; cv=""; src=""
  if [ -n "$cgal" ]; then
    : >"$D/cgal.txt"
    i=0; while [ $i -lt "$RUNS" ]; do "$cgal" "$s" "$e" >>"$D/cgal.txt"; i=$((i+1)); done
    cs=$(field seconds <"$D/cgal.txt" | median); cv=$(head -1 "$D/cgal.txt" | field vertices)
  else
    set -- $(anchor "$c"); cs=$1; cv=$2; src="*"
  fi
  awk -v c="$c" -v v="$v" -v cv="$cv" -v vs="$vs" -v cs="$cs" -v p="$p" -v h="$h" -v pp="$pp" -v pv="$pv" \
      -v tr="$tr" -v pt="$pt" -v co="$co" -v ab="$ab" -v cm="$cm" -v g="$g" -v src="$src" 'BEGIN {
    printf "%-12s %7d %7d %+5.1f%% %8.3f %7.3f%s %5.2fx %6.2f %6.2f %5.0f%% %9.0f %9.0f %4.1fx %4d %6.0f %s/%d\n",
      c, v, cv, 100*(v-cv)/cv, vs, cs, src, cs/vs, p/v, pp/pv, 100*h/p, tr, pt, pt/tr, co, ab/v, (cm=="true"?"yes":"NO"), g }'
done
echo "ratio = CGAL mesher seconds / voroprobe scan seconds (above 1: the whole simulated scan is faster"
echo "than CGAL's mesher); p/v = probes per output vertex (ours, and the published rule's); tr_x = travel"
echo "of the published rule (prev chains) / ours; B/vert = arena peak per output vertex; cm+g = closed"
echo "manifold / genus. * = table figure (CGAL not installed)."

# Body mode (the head kept outside Omega, every probe started on dOmega): the planner takes, of
# all waiting tasks, the one whose probe starts nearest the head. Its planner seconds against
# CGAL's mesher on the same surface and radius, both measured here.
BODY=${VP_BENCH_BODY:-"torus:0.05 torus:0.03 torus:0.02"}
echo
echo "Body mode (voroprobe sim --clearance 0.05) vs CGAL surface mesher (radius only), median of $RUNS"
printf '%-12s %7s %8s %8s %8s %7s %7s %9s\n' case verts probes plan_s cgal_s ratio p/v travel
for c in $BODY; do
  s=${c%%:*}; e=${c#*:}
  : >"$D/body.txt"
  i=0; while [ $i -lt "$RUNS" ]; do
    "$VP" sim --surface "$s" --eps "$e" --clearance 0.05 --quiet --json --hausdorff 0 --no-log --out "$D/body-$s-$e" | tail -1 >>"$D/body.txt"; i=$((i+1)); done
  line=$(head -1 "$D/body.txt")
  ps=$(field planner_seconds <"$D/body.txt" | median)
  v=$(echo "$line" | field vertices); p=$(echo "$line" | field probes); tr=$(echo "$line" | field travel)
  cs="-"
  if [ -n "$cgal" ]; then
    : >"$D/cgal.txt"
    i=0; while [ $i -lt "$RUNS" ]; do "$cgal" "$s" "$e" >>"$D/cgal.txt"; i=$((i+1)); done
    cs=$(field seconds <"$D/cgal.txt" | median)
  fi
  awk -v c="$c" -v v="$v" -v p="$p" -v ps="$ps" -v cs="$cs" -v tr="$tr" 'BEGIN {
    printf "%-12s %7d %8d %8.3f %8s %6s %7.2f %9.0f\n", c, v, p, ps, cs, (cs=="-" ? "-" : sprintf("%.2fx", ps/cs)), p/v, tr }'
done
echo "plan_s = the planner's own seconds (no simulated probes); ratio = plan_s / CGAL mesher seconds."
