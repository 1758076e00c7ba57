#!/bin/sh
# A moving object in host-sim (sim --motion): a bad spec or a clock option without --motion is a
# usage error (exit 2); a sphere standing still (translate:0,0,0) scans as without --motion (same
# mesh, 0 collisions, Hausdorff the same at start and end); a slow scan of a translating sphere
# (3 eps over the scan's time) collides with today's planner, which does not know about motion,
# and every move's collision and every probe's reading agree with the exact sphere rebuilt from
# the log alone (tests/motion_check.py), which must fail when told the wrong velocity; a
# deforming sphere (bump, bend, rotation) runs to the end and reports its figures.
. tests/lib.sh
B=$BUILD
command -v python3 >/dev/null || { echo "skipped: python3 is needed for the exact check"; exit 77; }
field() { python3 -c "import json,sys; print(json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])[sys.argv[2]])" "$@"; }

"$VP" sim --help | grep -q -- "--motion SPEC" || bad "sim --help does not name --motion"
S="--surface sphere --eps 0.2 --quiet"
for spec in "wiggle:1" "translate:1,2" "translate:1,0,0+translate:0,1,0" "bump:1,0,0,0,1" "rotate:0,0,0,5" ""; do
  "$VP" sim $S --out "$tmp/bad" --motion "$spec" >"$tmp/out" 2>"$tmp/err"; rc=$?
  [ $rc -eq 2 ] || bad "--motion '$spec': exit $rc, not 2"
  grep -q "motion" "$tmp/err" || bad "--motion '$spec': the error does not say what is wrong: $(cat "$tmp/err")"
  [ -e "$tmp/bad.ply" ] && bad "--motion '$spec' wrote a mesh"
done
"$VP" sim $S --out "$tmp/bad" --speed 5 >/dev/null 2>&1; [ $? -eq 2 ] || bad "--speed without --motion is not exit 2"
"$VP" sim $S --out "$tmp/bad" --motion translate:0,0,0 --probe-time -1 >/dev/null 2>&1; [ $? -eq 2 ] || bad "--probe-time -1 is not exit 2"

# standing still: the same scan as the static object
"$VP" sim $S --out "$tmp/static" --json >"$tmp/static.json"; rc0=$?
"$VP" sim $S --out "$tmp/still" --motion translate:0,0,0 --json >"$tmp/still.json"; rc1=$?
[ $rc0 -eq 0 ] && [ $rc1 -eq 0 ] || bad "sphere static exit $rc0, standing still exit $rc1"
cmp -s "$tmp/static.ply" "$tmp/still.ply" || bad "standing still: the mesh differs from the static scan"
[ "$(field "$tmp/still.json" collisions)" = 0 ] || bad "standing still: collisions"
h0=$(field "$tmp/still.json" hausdorff_start); h1=$(field "$tmp/still.json" hausdorff_end); hs=$(field "$tmp/static.json" hausdorff)
[ "$h0" = "$h1" ] && [ "$h0" = "$hs" ] || bad "standing still: Hausdorff start $h0, end $h1, static $hs"
T0=$(field "$tmp/still.json" sim_time)

# moving: 3 eps over the scan's time (0.6 / T0), and 0.3 eps
check() { # velocity, prefix: the simulator against the exact sphere
  "$VP" log dump "$2.vplog" --jsonl >"$2.jsonl" || { bad "log dump $2"; return 1; }
  python3 tests/motion_check.py "$2.jsonl" --vel "$1,0,0" --speed 300 --accel 3000 --probe-time 0.053 \
    --tol 0.00347 --collisions "$(field "$2.json" collisions)" >"$2.check" || { cat "$2.check"; return 1; }
}
v=$(python3 -c "print('%.6g' % (0.6 / $T0))")
"$VP" sim $S --out "$tmp/slow" --motion "translate:$v,0,0" --json >"$tmp/slow.json"; rc=$?
c=$(field "$tmp/slow.json" collisions)
[ "$rc" -eq 5 ] && [ "$c" -gt 0 ] || bad "translating at $v (3 eps per scan): exit $rc, collisions $c (expected > 0, exit 5)"
check "$v" "$tmp/slow" || bad "translating at $v: the simulator disagrees with the exact sphere"
exact=$(sed 's/.*exact \([0-9]*\) sure.*/\1/' "$tmp/slow.check")
# the object taken as standing still (velocity 0): the check must fail
check 0 "$tmp/slow" >"$tmp/wrong" && bad "the exact check passed a log with the wrong velocity"
grep -q MISMATCH "$tmp/wrong" || bad "the exact check did not name the mismatch"
v2=$(python3 -c "print('%.6g' % (0.06 / $T0))")
"$VP" sim $S --out "$tmp/slower" --motion "translate:$v2,0,0" --json >"$tmp/slower.json"
check "$v2" "$tmp/slower" || bad "translating at $v2: the simulator disagrees with the exact sphere"
c2=$(field "$tmp/slower.json" collisions)

# deforming: runs to the end with its figures
for m in "bump:1,0,0,0.5,0.001+rotate:0,0,1,2" "bend:1,0,0,0,0,1,0.0005+inflate:0.0005"; do
  "$VP" sim $S --out "$tmp/def" --motion "$m" --json >"$tmp/def.json"; rc=$?
  [ $rc -eq 0 ] || [ $rc -eq 5 ] || bad "--motion $m: exit $rc"
  he=$(field "$tmp/def.json" hausdorff_end)
  python3 -c "import sys; sys.exit(0 if 0 < float('$he') < 0.5 else 1)" || bad "--motion $m: Hausdorff at the end $he"
done

echo "motion: bad specs exit 2; standing still = static (Hausdorff $h0, ${T0} s simulated); translating at $v/s (3 eps per scan): $c collisions (exact: $exact), at $v2/s: $c2, every move and probe as the exact sphere; deforming runs report"
exit $fail
