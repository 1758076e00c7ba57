#!/bin/sh
# A line laser's plane calibrated on the machine, end to end, on the rpi4 board's dry run with
# `laser = line`, the simulated lens at k1 = -0.15 and the laser mounted 1 degree off +x (the
# rendered fan's plane turned with it): before calibration the scan's rays lie far off the object
# (the bound below must fail for them); `voroprobe calibrate` fits the camera from the mark and
# the plane from the line on the flat target, recovering the mounted plane (angle against the
# renderer's own plane); the file it writes drives a dry-run scan that closes with its rays within
# the bound, 0 moves through the object and 0 false hits. The same file without its plane (an
# older file: the camera calibrated, the plane nominal) still loads and fails the bound; a plane
# whose normal is not a unit vector is refused, and so is a line laser's calibration without a mark.
BUILD=${BUILD:-build}
VP=$BUILD/voroprobe
[ -x "$VP" ] || { echo "t_line_calib: $VP not built"; exit 1; }
TMP=$(mktemp -d) || exit 1
trap 'rm -rf "$TMP"' EXIT
fail() { echo "t_line_calib: FAIL: $*"; exit 1; }
field() { sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" "$1" | tr -d '"'; }
# the bound on the scan's rays (distance of each ray's point from the true surface): rms, worst (mm)
RMS_BOUND=0.2 WORST_BOUND=1.5
B=$TMP/rpi4-line.ini
# [sim] is the board file's last section: the lens and the laser as mounted
{ sed -e 's/^\[calibrate\]$/[calibrate]\nmark = 190, 150/' -e 's/^near_spots = too-close$/&\nlaser = line/' boards/rpi4-gantry.ini
  printf 'distortion = -0.15, 0, 0, 0\nlaser_error = 1, 30\n'; } > "$B"
grep -q '^laser = line' "$B" && grep -q '^mark = ' "$B" || fail "the board copy has no line laser or no mark"

# before: the nominal plane and camera (the scan never closes: its rays claim free space inside
# the object; 200 commands are enough to measure them)
"$VP" scan --board "$B" --dry-run --stop-after 200 --json --log "$TMP/u.vplog" > "$TMP/u.out" 2>&1
RC=$?
# uncalibrated, the line's points are millimetres off: probes read the surface beyond where it is,
# which the dry run reports as a SAFETY failure (exit 5: space inside the object taken for free)
[ $RC -eq 5 ] && grep -q '^SAFETY: .* read the surface more than' "$TMP/u.out" ||
  fail "the uncalibrated scan, stopped after 200 commands, exited $RC without the SAFETY report"
UR=$(field "$TMP/u.out" ray_rms) UW=$(field "$TMP/u.out" ray_worst) UN=$(field "$TMP/u.out" rays)
[ -n "$UR" ] && [ -n "$UW" ] && [ "${UN:-0}" -gt 0 ] || fail "the uncalibrated scan's rays not reported: $(tail -n 3 "$TMP/u.out")"
awk -v r="$UR" -v w="$UW" -v br=$RMS_BOUND -v bw=$WORST_BOUND 'BEGIN { exit !(r >= br && w >= bw) }' ||
  fail "the uncalibrated rays pass the bound (rms $UR mm, worst $UW mm): the check proves nothing"

# calibrate: the board's [calibrate] stations
"$VP" calibrate --board "$B" --dry-run --out "$TMP/line.calib" > "$TMP/cal.out" 2> "$TMP/cal.err" ||
  fail "calibrate exited $?: $(cat "$TMP/cal.err")"
set -- $(sed -n 's/^dry run truth: the plane as mounted, normal ([^)]*), \([0-9.e-]*\) deg from the board.s; fitted \([0-9.e-]*\) deg off it, its origin \([0-9.e-]*\) mm off it; k1 [-0-9.]* (fitted \([-0-9.e]*\))$/\1 \2 \3 \4/p' "$TMP/cal.out")
TT=$1 TE=$2 TO=$3 K1=$4
set -- $(sed -n 's/^line plane: \([0-9]*\) columns of the line on the target at \([0-9]*\) of [0-9]* stations;.* the columns \([0-9.e-]*\) mm rms.*/\1 \2 \3/p' "$TMP/cal.out")
NC=$1 NP=$2 PR=$3
[ -n "$TE" ] && [ -n "$K1" ] && [ -n "$PR" ] || fail "calibrate's report not understood: $(cat "$TMP/cal.out")"
awk -v t="$TT" 'BEGIN { exit !(t > 0.4) }' || fail "the mounted plane is only $TT deg from the nominal: nothing to recover"
awk -v e="$TE" -v o="$TO" 'BEGIN { exit !(e < 0.05 && o < 0.05) }' || fail "the fitted plane is $TE deg, its origin $TO mm off the true one"
awk -v k="$K1" 'BEGIN { exit !(k > -0.155 && k < -0.145) }' || fail "k1 $K1, not -0.15"
[ "$NP" -ge 5 ] || fail "the line was seen at $NP stations only"
grep -q '^plane = ' "$TMP/line.calib" && grep -q '^plane_tilt_deg = ' "$TMP/line.calib" && grep -q '^distortion = ' "$TMP/line.calib" ||
  fail "the calibration file has no plane or no camera"

# after: the scan with the file closes, its rays within the bound
"$VP" scan --board "$B" --dry-run --calib "$TMP/line.calib" --json --log "$TMP/c.vplog" > "$TMP/c.out" 2>&1 ||
  fail "the calibrated scan exited $? (0: closed): $(grep -E '^dry run: (probe|line)' "$TMP/c.out")"
CR=$(field "$TMP/c.out" ray_rms) CW=$(field "$TMP/c.out" ray_worst) CF=$(field "$TMP/c.out" ray_false) CN=$(field "$TMP/c.out" rays)
TH=$(field "$TMP/c.out" through)
FH=$(sed -n 's/^dry run: probe error .*; \([0-9]*\) false hits,.*/\1/p' "$TMP/c.out")
[ -n "$CR" ] && [ -n "$FH" ] && [ "${CN:-0}" -gt 0 ] || fail "the calibrated scan's report not understood: $(tail -n 3 "$TMP/c.out")"
awk -v r="$CR" -v w="$CW" -v br=$RMS_BOUND -v bw=$WORST_BOUND 'BEGIN { exit !(r < br && w < bw) }' ||
  fail "calibrated rays: rms $CR mm, worst $CW mm (bound $RMS_BOUND, $WORST_BOUND)"
[ "$CF" = 0 ] && [ "$TH" = 0 ] && [ "$FH" = 0 ] && ! grep -q '^SAFETY' "$TMP/c.out" ||
  fail "calibrated scan: $CF false rays, $TH moves through, $FH false hits $(grep '^SAFETY' "$TMP/c.out")"
"$VP" log verify "$TMP/c.vplog" > "$TMP/v.out" 2>&1 || fail "log verify: $(tail -n 1 "$TMP/v.out")"

# the file without its plane (as older files are) loads: the board's nominal normal turned to hold
# the calibrated beam (reported, not bounded: how near it comes depends on how the fan is mounted)
grep -v '^plane = ' "$TMP/line.calib" > "$TMP/noplane.calib"
"$VP" scan --board "$B" --dry-run --calib "$TMP/noplane.calib" --stop-after 200 --json --log "$TMP/n.vplog" > "$TMP/n.out" 2>&1
RC=$?
[ $RC -eq 3 ] || [ $RC -eq 5 ] || fail "the scan with the plane-less file, stopped after 200 commands, exited $RC: $(tail -n 2 "$TMP/n.out")"
NR=$(field "$TMP/n.out" ray_rms)
[ -n "$NR" ] || fail "the scan with the plane-less file reports no rays: $(tail -n 2 "$TMP/n.out")"

# a plane whose normal is not a unit vector
sed 's/^plane = \([^,]*\), \([^,]*\), \([^,]*\), \([^,]*\),/plane = \1, \2, \3, 0.5,/' "$TMP/line.calib" > "$TMP/bad.calib"
"$VP" scan --board "$B" --dry-run --calib "$TMP/bad.calib" --log "$TMP/b.vplog" > /dev/null 2> "$TMP/e1"; RC=$?
[ $RC -ne 0 ] && grep -q 'plane: the normal' "$TMP/e1" || fail "a plane normal that is not a unit vector: exit $RC, $(tail -n 1 "$TMP/e1")"

# a line laser without a mark: refused, saying why
"$VP" calibrate --board "$B" --dry-run --one-d --out "$TMP/x.calib" > /dev/null 2> "$TMP/e2"; RC=$?
[ $RC -eq 2 ] && grep -q 'line laser: it is calibrated with a mark' "$TMP/e2" && [ ! -e "$TMP/x.calib" ] ||
  fail "a line laser calibrated without a mark: exit $RC, $(tail -n 1 "$TMP/e2")"

echo "t_line_calib: ok: plane mounted $TT deg from the nominal, fitted $TE deg off it (origin $TO mm) from $NC columns at $NP stations (${PR} mm rms), k1 $K1; rays rms/worst: uncalibrated $UR/$UW mm, camera only $NR mm rms, calibrated $CR/$CW mm (bound $RMS_BOUND/$WORST_BOUND), scan closed, 0 through, 0 false hits"
