#!/bin/sh
# The full rangefinder calibration end to end on the rpi4 board's dry run with the simulated
# lens at k1 = -0.15 and the beam 1 degree off +x (origin 0.5 mm aside): `voroprobe calibrate`
# recovers k1 and the beam, its model reads frames over 10..400 mm within 1 mm of the renderer's
# true distance (worst, and at 400 mm), where the 1-D model on the same frames does not (the
# bound must fail for it); the file it writes drives a dry-run scan to a closed mesh (the beam
# aimed as fitted); bad input is refused.
BUILD=${BUILD:-build}
VP=$BUILD/voroprobe
[ -x "$VP" ] || { echo "t_calib_full: $VP not built"; exit 1; }
TMP=$(mktemp -d) || exit 1
trap 'rm -rf "$TMP"' EXIT
fail() { echo "t_calib_full: FAIL: $*"; exit 1; }
B=$TMP/rpi4-lens.ini
# [sim] is the board file's last section: the lens and the beam as mounted
{ sed 's/^\[calibrate\]$/[calibrate]\nmark = 190, 150                # a bright dot on the target (y, z)/' boards/rpi4-gantry.ini
  printf 'distortion = -0.15, 0, 0, 0\nlaser_error = 1, 30\nlaser_origin = 20, 0.4, -0.3\n'; } > "$B"
"$VP" calibrate --board "$B" --dry-run --target 425,150,150 --near 10 --far 400 --out "$TMP/full.calib" > "$TMP/cal.out" 2> "$TMP/cal.err" ||
  fail "calibrate exited $?: $(cat "$TMP/cal.err")"
K1=$(sed -n 's/^  distortion: k1 \([-0-9.e]*\),.*/\1/p' "$TMP/cal.out")
BEAM=$(sed -n 's/.*(fitted: \([0-9.e-]*\) deg off it).*/\1/p' "$TMP/cal.out")
set -- $(sed -n 's/^  full model: worst \([0-9.e-]*\) mm, rms \([0-9.e-]*\) mm, at 400 mm \([0-9.a-z-]*\)\( mm\)*; refused \([0-9]*\)$/\1 \2 \3 \5/p' "$TMP/cal.out")
FW=$1 FR=$2 FF=$3 FN=$4
set -- $(sed -n 's/^  1-D model:  worst \([0-9.e-]*\) mm, rms \([0-9.e-]*\) mm, at 400 mm \([0-9.e-]*\) mm.*/\1 \2 \3/p' "$TMP/cal.out")
OW=$1 OR=$2 OF=$3
[ -n "$K1" ] && [ -n "$BEAM" ] && [ -n "$FN" ] && [ -n "$OW" ] || fail "calibrate's report not understood: $(cat "$TMP/cal.out")"
awk -v k="$K1" 'BEGIN { exit !(k > -0.155 && k < -0.145) }' || fail "k1 $K1, not -0.15"
awk -v a="$BEAM" 'BEGIN { exit !(a < 0.05) }' || fail "the fitted beam is $BEAM deg off the true one"
case $FF in ''|*[!0-9.e-]*) fail "full model: the frame at 400 mm was $FF";; esac
awk -v w="$FW" -v f="$FF" -v n="$FN" 'BEGIN { exit !(w < 1 && f < 1 && n == 0) }' ||
  fail "full model: worst $FW mm, at 400 mm $FF mm, $FN refused (bound 1 mm)"
awk -v w="$OW" 'BEGIN { exit !(w >= 1) }' || fail "the 1-D model passes the 1 mm bound too (worst $OW mm): the check proves nothing"
grep -q '^beam = ' "$TMP/full.calib" && grep -q '^distortion = ' "$TMP/full.calib" || fail "the calibration file has no full model"
# calibrated over the board's own 15..200 mm: the 1-D model is far off at 400 mm, the full model
# refuses what lies beyond its span instead of reading it wrong
"$VP" calibrate --board "$B" --dry-run --target 425,150,150 --near 15 --far 200 --out "$TMP/short.calib" > "$TMP/cal2.out" 2> "$TMP/cal2.err" ||
  fail "calibrate over 15..200 mm exited $?: $(cat "$TMP/cal2.err")"
set -- $(sed -n 's/^  full model: worst \([0-9.e-]*\) mm, rms \([0-9.e-]*\) mm, at 400 mm \([0-9.a-z-]*\)\( mm\)*; refused \([0-9]*\)$/\1 \2 \3 \5/p' "$TMP/cal2.out")
SW2=$1 SN2=$4
set -- $(sed -n 's/^  1-D model:  worst \([0-9.e-]*\) mm, rms \([0-9.e-]*\) mm, at 400 mm \([0-9.e-]*\) mm.*/\1 \2 \3/p' "$TMP/cal2.out")
OF2=$3
[ -n "$SN2" ] && [ -n "$OF2" ] || fail "calibrate's report over 15..200 mm not understood: $(cat "$TMP/cal2.out")"
awk -v w="$SW2" -v n="$SN2" -v f="$OF2" 'BEGIN { exit !(w < 1 && n > 0 && f > 1) }' ||
  fail "over 15..200 mm: full model worst $SW2 mm with $SN2 refused, 1-D model at 400 mm $OF2 mm"
# the scan measures with it and aims the fitted beam: a closed mesh (exit 0), probes on the object
"$VP" scan --board "$B" --dry-run --calib "$TMP/full.calib" --log "$TMP/s.vplog" > "$TMP/scan.out" 2>&1 ||
  fail "scan with the full model exited $? (0: closed): $(grep -E '^(mesh|dry run: probe)' "$TMP/scan.out")"
set -- $(sed -n 's/^dry run: probe error against the true object rms \([0-9.]*\) mm, worst \([0-9.]*\) mm ([0-9]* hits); \([0-9]*\) false hits.*/\1 \2 \3/p' "$TMP/scan.out")
SR=$1 SW=$2 SF=$3
[ -n "$SF" ] && awk -v r="$SR" -v w="$SW" -v f="$SF" 'BEGIN { exit !(r < 0.05 && w < 0.2 && f == 0) }' ||
  fail "scan with the full model: probe error rms $SR mm, worst $SW mm, $SF false hits"
# bad input: a mark that is not a number, a mark out of view, a broken full model
"$VP" calibrate --board "$B" --dry-run --mark nan,150 --out "$TMP/x.calib" > /dev/null 2> "$TMP/e1" ; RC=$?
[ $RC -eq 2 ] && grep -q 'mark takes Y,Z' "$TMP/e1" || fail "--mark nan,150: exit $RC, $(cat "$TMP/e1")"
"$VP" calibrate --board "$B" --dry-run --target 425,150,150 --near 10 --far 400 --mark 5000,150 --out "$TMP/x.calib" > /dev/null 2> "$TMP/e2"; RC=$?
[ $RC -eq 1 ] && grep -q 'too few observations: 0 of the mark' "$TMP/e2" && [ ! -e "$TMP/x.calib" ] || fail "a mark out of view: exit $RC, $(tail -1 "$TMP/e2")"
sed 's/^beam = \([^,]*\), \([^,]*\), \([^,]*\), \([^,]*\),/beam = \1, \2, \3, 0.5,/' "$TMP/full.calib" > "$TMP/bad.calib"
"$VP" scan --board "$B" --dry-run --calib "$TMP/bad.calib" --log "$TMP/b.vplog" > /dev/null 2> "$TMP/e3"; RC=$?
[ $RC -ne 0 ] && grep -q 'beam: the direction' "$TMP/e3" || fail "a beam direction that is not a unit vector: exit $RC, $(tail -1 "$TMP/e3")"
echo "t_calib_full: ok: k1 $K1, beam $BEAM deg off; over 10..400 mm full model worst $FW mm rms $FR mm at 400 mm $FF mm, 1-D model worst $OW mm rms $OR mm (fails 1 mm); calibrated over 15..200 mm the 1-D model is $OF2 mm off at 400 mm, the full model refuses $SN2 frames beyond its span; scan closed, probe error rms $SR mm worst $SW mm; bad input refused"
