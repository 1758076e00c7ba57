#!/bin/sh
# The device program on a dry run (host-sim at the hardware boundary: the board's kinematics,
# step generator on the recording GPIO backend, rendered camera frames): boards/rpi4-gantry.ini
# scanned to DONE with a closed mesh and a log, in under a minute; the log replays to the same
# mesh bytes; a scan stopped by --stop-after (a Ctrl-C raised on purpose), by a real SIGINT,
# by the e-stop, and twice in a row, resumes to the same mesh bytes; too-close results are
# logged; calibration on a mis-mounted simulated camera recovers its true model within bound
# and scan then uses the file; bad boards and missing hardware fail with clear messages; a mesh
# that closes with another topology than the simulated object's exits 7.
. tests/lib.sh
B=$BUILD
BOARD=boards/rpi4-gantry.ini
S="--quiet --sync close"

for c in scan calibrate; do
  "$VP" $c --help >"$tmp/help.txt" 2>&1 || bad "$c --help"
  grep -q "dry-run" "$tmp/help.txt" || bad "$c --help says nothing about --dry-run"
done

# ---- the board's dry run to DONE: closed mesh, log, time (default log sync: every record)
t0=$(date +%s%N)
"$VP" scan --board $BOARD --dry-run --log "$tmp/full.vplog" >"$tmp/full.txt" 2>"$tmp/full.err"; rc=$?
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
secs=$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))
[ $rc -eq 0 ] || { bad "dry run of $BOARD: exit $rc"; tail -5 "$tmp/full.err"; }
grep -q "^scan: DONE" "$tmp/full.txt" || bad "dry run did not say DONE"
grep -q "closed 2-manifold, 1 component(s), genus 0" "$tmp/full.txt" || { bad "dry run mesh not closed genus 0"; grep mesh "$tmp/full.txt"; }
grep -q "0 false hits, 0 hidden spots, 0 moves through the object" "$tmp/full.txt" || { bad "dry run: false readings"; grep "dry run" "$tmp/full.txt"; }
[ -s "$tmp/full.ply" ] && [ -s "$tmp/full.off" ] || bad "no mesh files beside the log"
[ "$ms" -lt 60000 ] || bad "dry run took $secs s (limit 60)"
"$VP" log check "$tmp/full.vplog" >"$tmp/check.txt" || bad "log check of the dry run"
grep -q "complete (DONE)" "$tmp/check.txt" || bad "log not complete"
"$VP" log dump "$tmp/full.vplog" | grep -q "EVENT calibration code 0 values" || bad "no rangefinder model event in the log"
echo "dry run of $BOARD: $(grep '^scan: DONE' "$tmp/full.txt" | sed 's/scan: //'), $(grep '^mesh' "$tmp/full.txt" | cut -d';' -f1 | sed 's/mesh: //'), $secs s wall"
grep "dry run: the mesh" "$tmp/full.txt"

# ---- the log replays to the same bytes
"$VP" replay "$tmp/full.vplog" --out "$tmp/re" --quiet || bad "replay of the dry-run log"
cmp -s "$tmp/re.ply" "$tmp/full.ply" && cmp -s "$tmp/re.off" "$tmp/full.off" || bad "replay: mesh differs"

same() { # $1: log prefix, $2: what
  cmp -s "$tmp/$1.ply" "$tmp/full.ply" && cmp -s "$tmp/$1.off" "$tmp/full.off" || { bad "$2: resumed mesh differs"; return; }
  "$VP" log check "$tmp/$1.vplog" >"$tmp/c.txt" && grep -q "complete (DONE)" "$tmp/c.txt" || bad "$2: resumed log not complete"
  "$VP" replay "$tmp/$1.vplog" --out "$tmp/$1.re" --quiet && cmp -s "$tmp/$1.re.ply" "$tmp/full.ply" || bad "$2: replay of the resumed log differs"
  echo "$2: resumed to the same mesh bytes"
}

# ---- paused after N commands (a Ctrl-C raised on purpose), resumed
for n in 300 600; do
  "$VP" scan --board $BOARD --dry-run --log "$tmp/p$n.vplog" $S --stop-after $n >"$tmp/p.txt" 2>"$tmp/p.err"; rc=$?
  [ $rc -eq 3 ] || bad "--stop-after $n: exit $rc, not 3 (paused)"
  # a Ctrl-C in a path (the MOVEs of a route made as one) pauses at the path's end: within 16 commands
  pn=$("$VP" log dump "$tmp/p$n.vplog" | sed -n "s/.*EVENT pause code 0 'paused after \([0-9]*\) commands (Ctrl-C)'.*/\1/p")
  [ -n "$pn" ] && [ "$pn" -ge $n ] && [ "$pn" -lt $((n + 16)) ] || bad "--stop-after $n: no PAUSE event within 16 commands (${pn:-none})"
  "$VP" log check "$tmp/p$n.vplog" | grep -q "scan --log $tmp/p$n.vplog --resume" || bad "log check does not say how to resume"
  "$VP" scan --log "$tmp/p$n.vplog" --resume $S >"$tmp/r.txt" 2>"$tmp/r.err" || { bad "resume after $n: exit $?"; tail -3 "$tmp/r.err"; }
  grep -q "moves, .* mm (the session had travelled" "$tmp/r.err" || bad "resume after $n: no route back"
  grep -q "dry run: 0 of those moves went through the object" "$tmp/r.err" || bad "resume after $n: the route back crossed the object"
  same p$n "stopped after $n commands"
done
# a complete log resumed again: nothing to do
"$VP" scan --log "$tmp/p300.vplog" --resume $S >"$tmp/r.txt" 2>&1 && grep -q "complete; .* nothing appended" "$tmp/r.txt" ||
  bad "resume of a complete log"

# ---- stopped twice, resumed twice
"$VP" scan --board $BOARD --dry-run --log "$tmp/tw.vplog" $S --stop-after 200 >/dev/null 2>&1
"$VP" scan --log "$tmp/tw.vplog" --resume $S --stop-after 300 >/dev/null 2>&1; rc=$?
[ $rc -eq 3 ] || bad "second pause: exit $rc"
"$VP" scan --log "$tmp/tw.vplog" --resume $S >/dev/null 2>&1 || bad "second resume"
same tw "paused twice"

# ---- a real SIGINT while it runs
"$VP" scan --board $BOARD --dry-run --log "$tmp/sig.vplog" --sync record >"$tmp/sig.txt" 2>&1 &
pid=$!
sleep 0.5
kill -INT $pid 2>/dev/null
wait $pid; rc=$?
if [ $rc -eq 3 ]; then
  "$VP" log dump "$tmp/sig.vplog" | grep -q "EVENT pause .*(Ctrl-C)" || bad "SIGINT: no PAUSE event"
  "$VP" scan --log "$tmp/sig.vplog" --resume $S >/dev/null 2>&1 || bad "resume after SIGINT"
  same sig "SIGINT after 0.5 s"
elif [ $rc -eq 0 ]; then
  echo "SIGINT: the scan had finished before the signal (not checked)"
else
  bad "SIGINT: exit $rc"; tail -3 "$tmp/sig.txt"
fi

# ---- the e-stop pressed during command N (the first MOVE from command 577 on in the full run's
# log, commands counted from 1): FAULT event, resumable
N=$("$VP" log dump "$tmp/full.vplog" | awk '$3 == "MOVE" || $3 == "PROBE" { n++; if (n >= 577 && $3 == "MOVE") { print n; exit } }')
[ -n "$N" ] || { bad "no MOVE from command 577 on in the full run"; N=577; }
"$VP" scan --board $BOARD --dry-run --log "$tmp/es.vplog" $S --estop-at $N >"$tmp/es.txt" 2>"$tmp/es.err"; rc=$?
[ $rc -eq 1 ] || bad "e-stop: exit $rc, not 1"
grep -q "stopped at command $N (move to .*): e-stop pressed: pulses stopped, drivers off" "$tmp/es.err" || { bad "e-stop not reported"; cat "$tmp/es.err"; }
"$VP" log dump "$tmp/es.vplog" | grep -q "EVENT fault code -12 'command $N " || bad "e-stop: no FAULT event"
"$VP" log check "$tmp/es.vplog" | grep -q "incomplete (last event: fault)" || bad "e-stop: log check"
"$VP" scan --log "$tmp/es.vplog" --resume $S >/dev/null 2>&1 || bad "resume after the e-stop"
same es "e-stop during command $N"

# ---- without a clearance the head enters Omega and probes from Voronoi vertices, some nearer
# than min_range: VP_PROBE_TOO_CLOSE, logged as too close, never as hits
sed 's/^clearance = 58 /clearance = 0 /; s/^contact_by = mount /contact_by = stylus /' $BOARD >"$tmp/noclear.ini"
"$VP" scan --board "$tmp/noclear.ini" --dry-run --log "$tmp/tc.vplog" $S --eps 15 --near-spots too-close >"$tmp/tc.txt" 2>&1; rc=$?
# (exit 5 when the head's body, swept along the motions, touches the object: inside Omega the
# laser's own segment stays free but the camera and the tilt hub need not)
[ $rc -eq 0 ] || [ $rc -eq 4 ] || [ $rc -eq 5 ] || bad "--near-spots too-close: exit $rc"
n=$("$VP" log dump "$tmp/tc.vplog" | grep -c "too close (nothing measured, nothing free)")
[ "$n" -gt 0 ] || bad "--near-spots too-close: no too-close probe in the log"
"$VP" replay "$tmp/tc.vplog" --out "$tmp/tc.re" --quiet && cmp -s "$tmp/tc.re.ply" "$tmp/tc.ply" || bad "too-close log: replay differs"
echo "near spots as too close: $n too-close probes logged; $(grep '^mesh' "$tmp/tc.txt" | cut -d';' -f2)"

# ---- calibration: a mis-mounted camera on the simulated head
sed 's/^camera_position = 0, 30, 10 /camera_position = 0, 31.5, 10.5 /; s/^camera_look_at = 100, 0, 0 /camera_look_at = 100, 1.5, -1 /' \
  $BOARD >"$tmp/mis.ini"
grep -q "camera_look_at = 100, 1.5, -1" "$tmp/mis.ini" || bad "could not edit the board"
"$VP" scan --board "$tmp/mis.ini" --dry-run --log "$tmp/mis0.vplog" $S >"$tmp/m0.txt" 2>"$tmp/m0.err"; rc=$?
[ $rc -ne 0 ] && grep -q "calibrate" "$tmp/m0.err" || { bad "uncalibrated mis-mounted camera: no advice to calibrate (exit $rc)"; tail -3 "$tmp/m0.err"; }
"$VP" calibrate --board "$tmp/mis.ini" --dry-run --out "$tmp/mis.calib" >"$tmp/cal.txt" 2>&1 || { bad "calibrate --dry-run"; cat "$tmp/cal.txt"; }
grep -q "^\[rangefinder\]" "$tmp/mis.calib" && grep -q "^model = " "$tmp/mis.calib" || bad "calibration file"
# the bound: 60 spots of ~0.03 px noise each fit the line and model to about 0.03 px; 0.1 px
# leaves room for the sub-step pose error of the stations
px=$(sed -n 's/.*against the true model of the mounted camera .*: worst [0-9.]* mm (\([0-9.]*\) px).*/\1/p' "$tmp/cal.txt")
mm=$(sed -n 's/.*against the true model of the mounted camera .*: worst \([0-9.]*\) mm.*/\1/p' "$tmp/cal.txt")
off=$(sed -n 's/.*alone is off by up to \([0-9.]*\) mm.*/\1/p' "$tmp/cal.txt")
[ -n "$px" ] && awk -v p="$px" 'BEGIN { exit !(p + 0 < 0.1) }' || { bad "calibrated model off by ${px:-?} px (bound 0.1)"; cat "$tmp/cal.txt"; }
echo "calibration: fitted model within $px px ($mm mm) of the true one over 15..200 mm; the uncalibrated model was off by $off mm"
# the camera's pipeline latency (the simulated camera hands frames over 2 frames late): measured,
# and a camera later than the board allows is caught (the second latency_frames line is [sim]'s)
grep -q "camera latency: 2 frame(s) measured after a laser switch (board: latency_frames = 2)\$" "$tmp/cal.txt" ||
  { bad "calibrate: camera latency not measured as 2 frames"; grep latency "$tmp/cal.txt"; }
awk '/^latency_frames = 2 / && ++n == 2 { sub(/= 2 /, "= 3 ") } { print }' "$tmp/mis.ini" >"$tmp/lat3.ini"
"$VP" calibrate --board "$tmp/lat3.ini" --dry-run --out "$tmp/lat3.calib" >"$tmp/lat3.txt" 2>&1 &&
  bad "calibrate: a camera 3 frames late on a board allowing 2 calibrated (its frames are all laser-off)"
grep -q "lag the laser by more than \[camera\] latency_frames = 2" "$tmp/lat3.txt" ||
  { bad "calibrate: a camera 3 frames late on a board allowing 2: the message does not name latency_frames"; tail -2 "$tmp/lat3.txt"; }
echo "camera latency: 2 frames measured by calibrate; a camera 3 frames late on a board allowing 2 refused, naming latency_frames"
grep "^fit:" "$tmp/cal.txt"
"$VP" scan --board "$tmp/mis.ini" --dry-run --log "$tmp/mis1.vplog" $S --calib "$tmp/mis.calib" >"$tmp/m1.txt" 2>"$tmp/m1.err" ||
  { bad "scan with the calibration: exit $?"; tail -3 "$tmp/m1.err"; }
grep -q "rangefinder 10..400 mm from $tmp/mis.calib" "$tmp/m1.err" || bad "scan does not say it uses the calibration"
grep -q "closed 2-manifold" "$tmp/m1.txt" || bad "calibrated scan: mesh not closed"
a=$(sed -n 's/^model = \([^,]*\),.*/\1/p' "$tmp/mis.calib")
"$VP" log dump "$tmp/mis1.vplog" | grep -q "EVENT calibration code 2 values $a .*$tmp/mis.calib" || bad "the log does not record the calibration's model"
grep "probe error" "$tmp/m1.txt"
# the same through the board's key (relative to the board file)
sed 's|^# calibration = rpi4-gantry.calib|calibration = mis.calib|' "$tmp/mis.ini" >"$tmp/mis2.ini"
"$VP" scan --board "$tmp/mis2.ini" --dry-run --log "$tmp/mis2.vplog" $S --stop-after 50 >/dev/null 2>"$tmp/m2.err"
grep -q "from $tmp/mis.calib" "$tmp/m2.err" || bad "[rangefinder] calibration = FILE not used"

# ---- clear errors
sed 's/^steps_per_unit = 400/steps_per_unit = 4OO/' $BOARD >"$tmp/typo.ini"
"$VP" scan --board "$tmp/typo.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "typo.ini:[0-9]*: \[axis.z\] steps_per_unit: expected a number, got '4OO'" "$tmp/e.txt" || { bad "bad board file"; cat "$tmp/e.txt"; }
"$VP" scan --board "$tmp/nonexistent.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e.txt" && bad "missing board accepted"
grep -q "nonexistent.ini" "$tmp/e.txt" || bad "missing board not named"
# no GPIO chip and no camera here (or a build without libgpiod): both named, nothing written
if [ ! -e /dev/gpiochip0 ] && [ ! -e /dev/video0 ]; then
  "$VP" scan --board $BOARD --log "$tmp/hw.vplog" >/dev/null 2>"$tmp/e.txt"; rc=$?
  [ $rc -eq 1 ] || bad "scan without hardware: exit $rc"
  grep -q "GPIO: gpiod: .*gpiochip0\|GPIO: gpiod: built without libgpiod" "$tmp/e.txt" || { bad "missing GPIO not named"; cat "$tmp/e.txt"; }
  grep -q "camera: camera /dev/video0: \|camera: .*libcamera" "$tmp/e.txt" || { bad "missing camera not named"; cat "$tmp/e.txt"; }
  [ ! -e "$tmp/hw.vplog" ] || bad "a log was written without hardware"
  "$VP" calibrate --board $BOARD >/dev/null 2>"$tmp/e2.txt" && bad "calibrate without hardware succeeded"
  grep -q "GPIO: gpiod" "$tmp/e2.txt" || bad "calibrate: missing GPIO not named"
  echo "without hardware: $(sed -n 2p "$tmp/e.txt" | sed 's/^ *//')"
else
  echo "this machine has a GPIO chip or a camera: the missing-hardware message is not checked"
fi
"$VP" scan --board boards/sim.ini --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e.txt"
grep -q "has io = sim: it drives no hardware; use --dry-run" "$tmp/e.txt" || bad "io = sim without --dry-run"
"$VP" scan --board $BOARD --log "$tmp/x.vplog" --estop-at 5 >/dev/null 2>&1; [ $? -eq 2 ] || bad "--estop-at without --dry-run accepted"
sed 's/^surface = sphere\*80/surface = sphere*140/' boards/sim.ini >"$tmp/big.ini"
"$VP" scan --board "$tmp/big.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e.txt"
grep -q "is not inside the board's Omega by the clearance" "$tmp/e.txt" || { bad "an object too near dOmega accepted"; cat "$tmp/e.txt"; }
"$VP" sim --surface sphere --eps-rel 0.1 --out "$tmp/simlog" --quiet --hausdorff 0 >/dev/null 2>&1
"$VP" scan --log "$tmp/simlog.vplog" --resume >/dev/null 2>"$tmp/e.txt"
grep -q "not written by \`scan\` but by \`sim\`" "$tmp/e.txt" || bad "resume of a sim log"
"$VP" scan --log "$tmp/p300.vplog" --resume --eps 9 >/dev/null 2>"$tmp/e.txt"
grep -q "a resumed scan keeps the options in its log" "$tmp/e.txt" || bad "resume with other options accepted"

# ---- a bare object sized to Omega, whose centre is not inside it (torus): its own interior point
sed '/^surface = /d' boards/sim.ini >"$tmp/nosurf.ini"
"$VP" scan --board "$tmp/nosurf.ini" --dry-run --log "$tmp/ns.vplog" $S --stop-after 30 >/dev/null 2>"$tmp/ns.err"
grep -q "dry run on host-sim: ellipsoid\*" "$tmp/ns.err" || bad "default object not sized to Omega"
"$VP" scan --board boards/sim.ini --dry-run --surface torus --log "$tmp/to.vplog" $S --stop-after 30 >/dev/null 2>"$tmp/to.err"; rc=$?
[ $rc -eq 3 ] && grep -q "torus\*" "$tmp/to.err" && grep -q "interior point is not inside the simulated object" "$tmp/to.err" ||
  { bad "--surface torus on sim.ini (exit $rc)"; cat "$tmp/to.err"; }

# ---- a dry run knows the object: two spheres 0.5 mm apart joined into one closed mesh at eps 10
# is a wrong answer, said so (exit 7, wrong_topology), not "closed"
"$VP" scan --board $BOARD --dry-run --surface "sphere*10@190,150,150+sphere*10@210.5,150,150" --eps 10 \
  --log "$tmp/two.vplog" --out "$tmp/two" $S --json >"$tmp/two.txt" 2>"$tmp/two.err"; rc=$?
[ $rc -eq 7 ] && grep -q '"status":"wrong_topology"' "$tmp/two.txt" &&
  grep -q "genus 0 in 1 component(s), the object genus 0 in 2: wrong topology" "$tmp/two.txt" ||
  { bad "two spheres joined on the dry run: exit $rc"; grep -E "^mesh|wrong" "$tmp/two.txt"; }

[ $fail -eq 0 ] && echo "scan dry runs: DONE, replay, 2 pauses, a double pause, SIGINT, e-stop resumed byte-identical; calibration within bound; two spheres joined caught (exit 7); errors clear"
exit $fail
