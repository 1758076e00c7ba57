#!/bin/sh
# Machine time on the board (simulated by the dry run): the body-mode issue's machine (rpi4-gantry
# with a 12 mm head, Omega a ball of 80 mm, the 100 x 70 x 50 mm ellipsoid; the head's parts off)
# and boards/sim.ini's 100 mm sphere, each with the head's moves weighed by the axes' speeds and,
# in the same run, ordered by length (scan --by-length: the anchor). Seconds of machine time per
# vertex and the ratio; the issue's figure at its filing (d9f7016: 16.2 s per vertex at eps 16,
# the one eps that closed then) for reference.
set -u
B=${1:-build}
VP="$B/voroprobe"
D="$B/bench/machine"
rm -rf "$D"; mkdir -p "$D"
field() { tail -n 1 "$1" | sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }
sh tools/small_head_board.sh "$D/old.ini" || exit 1
echo "Machine time per vertex, moves weighed by the axes' speeds against ordered by length (same run)"
printf '%-34s %5s %-8s %9s %9s %9s %-8s %9s %9s %9s %7s\n' board eps closed vertices "machine s" "s/vertex" \
  "length:" vertices "machine s" "s/vertex" ratio
row() { # NAME LABEL BOARD EPS [surface]
  n=$1; lab=$2; b=$3; e=$4; shift 4
  for k in timed length; do
    x=""; [ $k = length ] && x=--by-length
    "$VP" scan --board "$b" --dry-run --eps "$e" "$@" $x --log "$D/$n-$e-$k.vplog" --json --quiet >"$D/$n-$e-$k.json" 2>&1
  done
  t=$D/$n-$e-timed.json; l=$D/$n-$e-length.json
  awk -v n="$lab" -v e="$e" -v c="$(field "$t" closed)/$(field "$l" closed)" -v tv="$(field "$t" vertices)" \
      -v ts="$(field "$t" machine_s)" -v lv="$(field "$l" vertices)" -v ls="$(field "$l" machine_s)" 'BEGIN {
    tp = tv > 0 ? ts / tv : 0; lp = lv > 0 ? ls / lv : 0
    printf "%-34s %5s %-8s %9s %9.0f %9.2f %-8s %9s %9.0f %9.2f %6.2fx\n", n, e, c, tv, ts, tp, "", lv, ls, lp, (tp > 0 ? lp / tp : 0) }'
}
for e in 16 8 4; do row rpi4-old "rpi4, the issue's geometry" "$D/old.ini" $e; done
for e in 8 4; do row sim-sphere "sim.ini, sphere*50" boards/sim.ini $e --surface 'sphere*50'; done
t=$D/rpi4-old-16-timed.json
awk -v tv="$(field "$t" vertices)" -v ts="$(field "$t" machine_s)" 'BEGIN {
  printf "at eps 16 against the issue at its filing (d9f7016, 16.2 s per vertex): %.2fx less\n", (tv > 0 ? 16.2 / (ts / tv) : 0) }'
