#!/bin/sh
# `voroprobe log verify`: the proof check of a session log from the log alone (no planner).
# (1) logs of real sessions pass: sim on sphere, torus, genus2, a body-mode run (--clearance),
#     a short-reach run (--max-range), a noisy one with dropouts, a session cut by a power cut
#     and resumed, one paused and resumed, and a scan dry run of boards/sim.ini (also paused and
#     resumed: a ball Omega); a torn log is verified up to its last good record and says so;
# (2) crafted logs (written by tests/test_logverify with core's encoder) fail with the right
#     record: a move through Omega with no probe, 1% past a miss's range, past a hit, along a
#     too-close probe, before its covering probe, 1e-6 off a probed line, a gap between two
#     probes, a chord of a ball Omega, a probe from where the device never was; legitimate
#     moves (two collinear probes end to end plus the outside part, across PAUSE/RESUME) pass;
# (3) a real log with one MOVE's target changed (CRC re-encoded) is caught at that record;
# exit statuses (0 proven, 1 not, 2 usage, 3 unreadable), --json, --help; and at the end every
# *.vplog this test wrote is verified again (the other tests keep their logs in their own
# temporary directories, removed on exit).
. tests/lib.sh
B=$BUILD
T=$B/tests/host/test_logverify
[ -x "$T" ] || { echo "FAIL: $T not built"; exit 1; }
S="--quiet --sync close --hausdorff 0"

# verify LOG: must exit 0 and say all moves are proven
proven() { # $1 log, $2 what
  "$VP" log verify "$1" >"$tmp/v.txt" 2>&1; rc=$?
  if [ $rc -ne 0 ] || ! grep -q "^verify: .* moves, .* probes: all moves proven free$" "$tmp/v.txt"; then
    bad "$2: log verify exit $rc"; tail -5 "$tmp/v.txt"
  else
    echo "$2: $(tail -n 1 "$tmp/v.txt" | sed 's/^verify: //')"
  fi
}

# ---- (1) real sessions
for s in sphere torus genus2; do
  "$VP" sim --surface $s --eps 0.1 --out "$tmp/$s" $S >/dev/null 2>&1 || bad "sim $s"
  proven "$tmp/$s.vplog" "sim $s eps 0.1"
done
"$VP" sim --surface sphere --eps 0.1 --clearance 0.05 --out "$tmp/body" $S >/dev/null 2>&1 || bad "sim body mode"
proven "$tmp/body.vplog" "sim sphere body mode (clearance 0.05)"
# a torus in body mode: its inner ring, unseen along its own Voronoi edges from outside Omega,
# is found from aside (core/planner/aim.c): closed, exit 0
"$VP" sim --surface torus --eps 0.1 --clearance 0.05 --out "$tmp/bodyt" $S >/dev/null 2>&1; rc=$?
[ $rc -eq 0 ] || bad "sim torus body mode: exit $rc (0 expected: closed)"
proven "$tmp/bodyt.vplog" "sim torus body mode (clearance 0.05)"
"$VP" sim --surface torus --eps 0.1 --max-range 0.5 --out "$tmp/reach" $S >/dev/null 2>&1 || bad "sim short reach"
proven "$tmp/reach.vplog" "sim torus max range 0.5"
"$VP" sim --surface torus --eps-rel 0.05 --noise 0.0005 --dropout 0.1 --out "$tmp/noisy" $S >/dev/null 2>&1 || bad "sim noisy"
proven "$tmp/noisy.vplog" "sim torus noise 0.0005 dropout 0.1"

# a power cut, then resumed: the torn log verifies up to its last good record
"$VP" sim --surface torus --eps-rel 0.05 --out "$tmp/cut" $S --power-cut 150000 >/dev/null 2>&1
"$VP" log verify "$tmp/cut.vplog" >"$tmp/v.txt" 2>&1 || bad "torn log: exit $?"
grep -q "truncated.*verified records 0\.\." "$tmp/v.txt" || { bad "torn log: not said"; cat "$tmp/v.txt"; }
grep -q "all moves proven free" "$tmp/v.txt" || bad "torn log: verdict"
"$VP" log verify "$tmp/cut.vplog" --json | tail -n 1 | grep -q '"log_complete":false,"ok":true}' || bad "torn log: json"
"$VP" sim --resume "$tmp/cut.vplog" $S >/dev/null 2>&1 || bad "resume after the power cut"
"$VP" log dump "$tmp/cut.vplog" | grep -q "EVENT resume" || bad "no RESUME event after the power cut"
proven "$tmp/cut.vplog" "sim torus cut by a power cut, resumed"
"$VP" sim --surface genus2 --eps 0.1 --out "$tmp/pause" $S --stop-after 2000 >/dev/null 2>&1
"$VP" sim --resume "$tmp/pause.vplog" $S >/dev/null 2>&1 || bad "resume after a pause"
"$VP" log dump "$tmp/pause.vplog" | grep -q "EVENT pause" || bad "no PAUSE event"
proven "$tmp/pause.vplog" "sim genus2 paused after 2000 commands, resumed"

# the scan dry run (the board's kinematics, steps and rendered frames), whole and paused
"$VP" scan --board boards/sim.ini --dry-run --log "$tmp/scan.vplog" --quiet --sync close >/dev/null 2>&1 || bad "scan dry run"
proven "$tmp/scan.vplog" "scan boards/sim.ini dry run"
"$VP" scan --board boards/sim.ini --dry-run --log "$tmp/scanp.vplog" --quiet --sync close --stop-after 300 >/dev/null 2>&1
"$VP" scan --log "$tmp/scanp.vplog" --resume --quiet --sync close >/dev/null 2>&1 || bad "scan resume"
proven "$tmp/scanp.vplog" "scan boards/sim.ini paused after 300 commands, resumed"

# ---- (2) crafted logs
mkdir -p "$tmp/crafted"
"$T" "$tmp/crafted" >"$tmp/t.txt" 2>&1 || { bad "test_logverify on the crafted logs"; tail -5 "$tmp/t.txt"; }
n=0
while read -r name code first off; do
  n=$((n + 1))
  log="$tmp/crafted/$name.vplog"
  "$VP" log verify "$log" --json >"$tmp/v.txt" 2>&1; rc=$?
  [ $rc -eq "$code" ] || { bad "crafted $name: exit $rc, expected $code"; cat "$tmp/v.txt"; continue; }
  j=$(tail -n 1 "$tmp/v.txt")
  if [ "$first" -ge 0 ]; then
    echo "$j" | grep -q "\"first_unproven_record\":$first," || bad "crafted $name: first unproven record not $first: $j"
    grep -q "^record $first (seq $first, move [0-9]*): MOVE from .* NOT proven free; first unproven part s " "$tmp/v.txt" ||
      bad "crafted $name: no line naming record $first"
    grep -q "^verify: [0-9]* of [0-9]* moves NOT proven free (first: record $first," "$tmp/v.txt" || bad "crafted $name: summary"
  else
    echo "$j" | grep -q '"first_unproven_record":null' || bad "crafted $name: $j"
  fi
  if [ "$off" -ge 0 ]; then
    echo "$j" | grep -q "\"first_off_position_record\":$off," || bad "crafted $name: off-position probe not $off: $j"
    grep -q "^record $off (seq $off): PROBE from .*, but the device was at " "$tmp/v.txt" || bad "crafted $name: no probe line"
  fi
  [ "$code" -ne 0 ] || echo "$j" | grep -q '"ok":true}$' || bad "crafted $name: not ok in json"
  [ "$code" -eq 0 ] || echo "$j" | grep -q '"ok":false}$' || bad "crafted $name: ok in json"
done <"$tmp/crafted/expect.txt"
[ $n -ge 11 ] || bad "only $n crafted logs"
echo "crafted logs: $n checked ($(awk '$2 != 0' "$tmp/crafted/expect.txt" | wc -l) must fail, each at its record)"
# the torn tail of a crafted log: its last (unproven) move is cut off
size=$(wc -c <"$tmp/crafted/no_probe.vplog")
head -c $((size - 10)) "$tmp/crafted/no_probe.vplog" >"$tmp/torn.vplog"
"$VP" log verify "$tmp/torn.vplog" >"$tmp/v.txt" 2>&1 || bad "torn crafted log: exit $?"
grep -q "verified records 0\.\.1 only" "$tmp/v.txt" || { bad "torn crafted log"; cat "$tmp/v.txt"; }

# ---- (3) a real log with one MOVE's target moved to the object's interior point
rec=$("$T" --mutate "$tmp/genus2.vplog" "$tmp/mut.vplog") || bad "mutate"
"$VP" log check "$tmp/mut.vplog" --no-replay >/dev/null || bad "mutated log: CRCs not re-encoded"
"$VP" log verify "$tmp/mut.vplog" --json >"$tmp/v.txt" 2>&1; rc=$?
[ $rc -eq 1 ] || bad "mutated log: exit $rc"
grep -q "^verify: [0-9]* of [0-9]* moves NOT proven free (first: record $rec, seq $rec," "$tmp/v.txt" ||
  { bad "mutated log: record $rec not named first"; tail -3 "$tmp/v.txt"; }
tail -n 1 "$tmp/v.txt" | grep -q "\"first_unproven_record\":$rec," || bad "mutated log: json"
echo "mutated genus2 log: record $rec named ($(grep '^verify:' "$tmp/v.txt" | sed 's/^verify: //'))"

# ---- exit statuses, --help
"$VP" log verify "$tmp/nonexistent.vplog" >/dev/null 2>&1; rc=$?
[ $rc -eq 3 ] || bad "missing log: exit $rc, not 3"
printf 'not a log at all\n' >"$tmp/junk.vplog"
"$VP" log verify "$tmp/junk.vplog" >/dev/null 2>&1; rc=$?
[ $rc -eq 3 ] || bad "junk: exit $rc, not 3"
"$VP" log verify "$tmp/sphere.vplog" --bogus >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || bad "unknown option: exit $rc, not 2"
"$VP" log verify >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || bad "no log: exit $rc, not 2"
"$VP" log --help | grep -q "log verify LOG \[--json\]" || bad "--help does not show verify"
"$VP" log --help | grep -q "1: not" || bad "--help does not give the exit statuses"
"$VP" log verify "$tmp/sphere.vplog" --json | tail -n 1 |
  grep -q '^{"moves":[0-9]*,"probes":[0-9]*,"unproven_moves":0,"first_unproven_record":null,"probes_off_position":0,.*"records":[0-9]*,.*"ok":true}$' ||
  bad "--json object"

# ---- every log this test wrote, once more (the crafted ones by their expectations above)
total=0; nok=0
for f in "$tmp"/*.vplog; do
  case $f in */junk.vplog|*/mut.vplog|*/nonexistent.vplog) continue;; esac
  total=$((total + 1))
  "$VP" log verify "$f" >/dev/null 2>&1 && nok=$((nok + 1)) || bad "final pass: $f"
done
echo "final pass: $nok of $total session logs proven"

[ $fail -eq 0 ] && echo "log verify: real sessions proven, crafted and mutated logs caught at their records"
exit $fail
