#!/bin/sh
# The rpi4 board's dry run (voroprobe scan --board boards/rpi4-gantry.ini --dry-run) with host-sim's
# frame faults switched on in a copy of the board ([sim] speckle, vibration, flicker, glint, dark)
# and the spot confirmed ([rangefinder] confirm_spot = yes): against the true object (within the
# scan's noise tolerance, as the planner trusts hits) no false hit and no move through it. Without the glint and the dark band (speckle, a ringing head, mains
# flicker) the scan closes its mesh. A fault key out of its range is refused, naming it.
# (tests/host/test_camfaults judges every probe against the renderer's truth.)
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
board() {   # board NAME CONFIRM KEY-LINES...
  name=$1; conf=$2; shift 2
  sed "s/^\[rangefinder\]/[rangefinder]\nconfirm_spot = $conf/" boards/rpi4-gantry.ini >"$tmp/$name.ini"
  printf '%s\n' "$@" >>"$tmp/$name.ini"
}
board mild yes "speckle = 1, 8" "vibration = 8, 150, 40, 0" "flicker = 0.6, 100"
board all yes "speckle = 1, 8" "vibration = 8, 150, 40, 0" "flicker = 0.6, 100" "glint = 60, 2, 40, 10, 12, 700" \
  "dark = 0.0007, 144, 156"
"$VP" scan --board "$tmp/mild.ini" --dry-run --eps 12 --log "$tmp/mild.vplog" >"$tmp/mild.out" 2>&1
rc=$?
grep -q 'mesh: .*closed 2-manifold' "$tmp/mild.out" && [ $rc -eq 0 ] || { cat "$tmp/mild.out"; echo "FAIL: speckle, vibration, flicker: exit $rc, not closed"; exit 1; }
grep -q ' 0 false hits, 0 hidden spots, 0 moves through the object' "$tmp/mild.out" || { cat "$tmp/mild.out"; echo "FAIL: mild faults misread"; exit 1; }
"$VP" scan --board "$tmp/all.ini" --dry-run --log "$tmp/all.vplog" >"$tmp/all.out" 2>&1
rc=$?
# an open mesh (exit 4) is allowed: unreadable frames prove nothing and leave their facets open
[ $rc -eq 0 ] || [ $rc -eq 4 ] || { cat "$tmp/all.out"; echo "FAIL: all faults: exit $rc"; exit 1; }
grep -q 'scan: DONE' "$tmp/all.out" && grep -q ' 0 false hits, [0-9]* hidden spots, 0 moves through the object' "$tmp/all.out" ||
  { cat "$tmp/all.out"; echo "FAIL: all faults: a false hit or a move through the object"; exit 1; }
# bad fault keys: refused, named, nothing written
board bad1 yes "speckle = 2, 8"
board bad2 yes "dark = 0.1, 160, 150"
board bad3 maybe
for b in bad1 bad2 bad3; do
  "$VP" scan --board "$tmp/$b.ini" --dry-run --log "$tmp/$b.vplog" >"$tmp/$b.out" 2>&1
  rc=$?
  [ $rc -eq 1 ] && ! [ -e "$tmp/$b.vplog" ] || { cat "$tmp/$b.out"; echo "FAIL: $b accepted (exit $rc)"; exit 1; }
done
grep -q '\[sim\] speckle: expected CONTRAST' "$tmp/bad1.out" && grep -q '\[sim\] dark: expected ALBEDO' "$tmp/bad2.out" &&
  grep -q '\[rangefinder\] confirm_spot: expected yes or no' "$tmp/bad3.out" || { cat "$tmp"/bad*.out; echo "FAIL: error messages"; exit 1; }
m=$(grep '^dry run: probe' "$tmp/mild.out" | sed 's/^dry run: //')
a=$(grep '^dry run: probe' "$tmp/all.out" | sed 's/^dry run: //')
u=$(grep '^unreadable frames' "$tmp/all.out" | sed 's/^unreadable frames: //')
echo "t_camfaults: rpi4 dry run, speckle + ringing head + flicker (eps 12): closed, $m; with a moving glint and a dark band too: $a (unreadable: $u); bad fault keys refused"
