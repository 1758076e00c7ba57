#!/bin/sh
# The head's body on the board's dry run: boards/rpi4-gantry.ini (its head within its clearance
# ball) scans to a closed mesh with 0 head collisions, also across a pause and resume, and its
# log shows the ball rule's premise (the laser origin never inside Omega; clearance 0 fails
# that check); the same
# head on the board's former Omega (clearance 12, the 100 mm ellipsoid), run as an io = sim board
# that states clear_by = swept, sweeps its camera and tilt hub into the object: exit 5, the
# parts named, while the laser origin's own check sees 0 moves through the object; a board whose
# clearance is smaller than its head is refused at load, naming the part, how far it reaches and
# the line; clear_by = swept on a board that drives motors is refused.
. tests/lib.sh
B=$BUILD
BOARD=boards/rpi4-gantry.ini
S="--quiet --sync close"

# ---- 1. the board's dry run: closed, 0 head collisions
"$VP" scan --board $BOARD --dry-run --log "$tmp/r.vplog" $S --json >"$tmp/r.txt" 2>"$tmp/r.err"; rc=$?
[ $rc -eq 0 ] || { bad "dry run of $BOARD: exit $rc"; tail -5 "$tmp/r.txt" "$tmp/r.err"; }
grep -q "closed 2-manifold" "$tmp/r.txt" || bad "dry run: mesh not closed"
grep -q "^dry run: head: 0 head collisions in [0-9]* motions (clearance ball 0, laser 0, camera 0, bracket 0, tilt hub 0" "$tmp/r.txt" ||
  { bad "dry run: head collisions"; grep "head" "$tmp/r.txt"; }
[ "$(field "$tmp/r.txt" head_collisions)" = 0 ] && [ "$(field "$tmp/r.txt" status)" = closed ] || bad "dry run: --json"
# machine time by planner stage adds up to the run's machine time, and per vertex is that over the vertices
awk -v t="$(field "$tmp/r.txt" machine_s)" -v a="$(field "$tmp/r.txt" machine_s_seed)" -v b="$(field "$tmp/r.txt" machine_s_refine)" \
    -v c="$(field "$tmp/r.txt" machine_s_close)" -v p="$(field "$tmp/r.txt" machine_s_per_vertex)" -v n="$(field "$tmp/r.txt" vertices)" \
    'BEGIN { d = a + b + c - t; q = t / n - p; exit !(t > 0 && d < 0.25 && d > -0.25 && q < 0.01 && q > -0.01) }' ||
  bad "dry run: machine time by stage does not add up ($(tail -n 1 "$tmp/r.txt" | cut -c1-200))"
# and by motion: moves, aims, settling and reading add up to it too, every part spent but the
# settling, which is the board's settle_ms per probe
awk -v t="$(field "$tmp/r.txt" machine_s)" -v a="$(field "$tmp/r.txt" machine_s_moves)" -v b="$(field "$tmp/r.txt" machine_s_aims)" \
    -v c="$(field "$tmp/r.txt" machine_s_settle)" -v r="$(field "$tmp/r.txt" machine_s_read)" -v n="$(field "$tmp/r.txt" probes)" \
    -v ms="$(sed -n 's/^settle_ms *= *\([0-9.]*\).*/\1/p' $BOARD)" \
    'BEGIN { d = a + b + c + r - t; e = c - n * ms / 1000; exit !(a > 0 && b > 0 && r > 0 && d < 0.25 && d > -0.25 && e < 0.06 && e > -0.06) }' ||
  bad "dry run: machine time by motion does not add up ($(tail -n 1 "$tmp/r.txt" | cut -c1-300))"
motions=$(field "$tmp/r.txt" head_motions)
[ "${motions:-0}" -gt 500 ] || bad "dry run: only ${motions:-0} motions checked"
# the ball rule's premise, from the log alone: no move and no probe puts the laser origin inside
# Omega (closest approach of every logged MOVE segment, and every probe's origin, to the centre)
inside() { # $1: log; prints the closest approach to Omega's centre and its radius
  "$VP" log dump "$1" | awk '
    /^# eps .* Omega ball centre/ { cx = $7; cy = $8; cz = $9; R = $11 }
    /^# start / { px = $3; py = $4; pz = $5; min = 1e300 }
    / MOVE to / { x = $5; y = $6; z = $7; dx = x - px; dy = y - py; dz = z - pz; L = dx*dx + dy*dy + dz*dz; t = 0
                  if (L > 0) { t = ((cx-px)*dx + (cy-py)*dy + (cz-pz)*dz) / L; if (t < 0) t = 0; if (t > 1) t = 1 }
                  qx = px + t*dx - cx; qy = py + t*dy - cy; qz = pz + t*dz - cz; d = sqrt(qx*qx + qy*qy + qz*qz)
                  if (d < min) min = d; px = x; py = y; pz = z }
    / PROBE from / { d = sqrt(($5-cx)^2 + ($6-cy)^2 + ($7-cz)^2); if (d < min) min = d }
    END { printf "%.6f %g\n", min, R }'
}
set -- $(inside "$tmp/r.vplog")
awk -v m="$1" -v R="$2" 'BEGIN { exit !(m >= R - 1e-6) }' || bad "the laser origin entered Omega: $1 from its centre (radius $2)"
premise="$1"
# the check's own failing case: without a clearance the head enters Omega
sed 's/^clearance = 58 /clearance = 0 /; s/^contact_by = mount /contact_by = stylus /' $BOARD >"$tmp/nc.ini"
"$VP" scan --board "$tmp/nc.ini" --dry-run --log "$tmp/nc.vplog" $S --eps 15 >/dev/null 2>&1
set -- $(inside "$tmp/nc.vplog")
awk -v m="$1" -v R="$2" 'BEGIN { exit !(m < R - 1) }' || bad "clearance 0: the premise check did not see the origin inside Omega ($1, radius $2)"
echo "the premise from the log: the laser origin keeps $premise mm from Omega's centre (radius $2); with clearance 0 it came to $1"
# across a pause and a resume: the way back is checked too
"$VP" scan --board $BOARD --dry-run --log "$tmp/p.vplog" $S --stop-after 300 >/dev/null 2>&1; rc=$?
[ $rc -eq 3 ] || bad "--stop-after 300: exit $rc"
"$VP" scan --log "$tmp/p.vplog" --resume $S >"$tmp/pr.txt" 2>"$tmp/pr.err" || bad "resume: exit $?"
grep -q "dry run: 0 of those moves went through the object, 0 brought the head within 0.5 mm of it" "$tmp/pr.err" ||
  { bad "resume: the way back"; grep resume "$tmp/pr.err"; }
grep -q "^dry run: head: 0 head collisions" "$tmp/pr.txt" || bad "resumed run: head collisions"
echo "$BOARD dry run: $(grep '^mesh' "$tmp/r.txt" | cut -d';' -f1 | sed 's/mesh: //'), $(field "$tmp/r.txt" probes) probes, 0 head collisions in $motions motions; paused and resumed: 0"

# ---- 2. the same head on the former Omega (clearance 12, ellipsoid*50): the camera hits
sed -e 's/^io = gpiod /io = sim /' -e 's/^contact_by = mount /contact_by = stylus /' -e 's/^clearance = 58 /clearance = 12 /' -e 's/^ball = 200, 150, 150, 83 /ball = 200, 150, 150, 80 /' \
    -e 's/^start = 200, 150, 234 /start = 200, 150, 232 /' -e 's/^surface = ellipsoid\*24@/surface = ellipsoid*50@/' \
    -e 's/^eps = 10 /eps = 16 /' -e 's/^origin_tol = 0.1 /clear_by = swept\norigin_tol = 0.1 /' $BOARD >"$tmp/old.ini"
grep -q "^clear_by = swept" "$tmp/old.ini" && grep -q "^surface = ellipsoid\*50@" "$tmp/old.ini" || bad "could not edit the board"
"$VP" scan --board "$tmp/old.ini" --dry-run --log "$tmp/o.vplog" $S --json >"$tmp/o.txt" 2>"$tmp/o.err"; rc=$?
[ $rc -eq 5 ] || { bad "former Omega: exit $rc, not 5 (collision)"; tail -3 "$tmp/o.err"; }
grep -q "0 moves through the object" "$tmp/o.txt" || bad "former Omega: the origin's check should see nothing"
hits=$(field "$tmp/o.txt" head_collisions)
cam=$(tail -n 1 "$tmp/o.txt" | sed -n 's/.*"camera":\([0-9]*\).*/\1/p')
[ "${hits:-0}" -gt 0 ] && [ "${cam:-0}" -gt 0 ] || bad "former Omega: no head collision named the camera"
grep -q "^SAFETY: $hits motions of this dry run brought the head's body within 0.5 mm of the object" "$tmp/o.txt" || bad "former Omega: no SAFETY line"
echo "former Omega (clearance 12, ellipsoid*50): exit 5, $hits of $(field "$tmp/o.txt" head_motions) motions hit ($(grep '^dry run: head' "$tmp/o.txt" | sed 's/.*(\(.*\); swept.*/\1/')); the laser origin's check: 0"

# ---- 3. refused at load: a clearance smaller than the head
sed 's/^clearance = 58 /clearance = 20 /' $BOARD >"$tmp/small.ini"
"$VP" scan --board "$tmp/small.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e.txt"; rc=$?
line=$(grep -n '^camera_body' "$tmp/small.ini" | cut -d: -f1)
[ $rc -eq 1 ] && grep -q "small.ini:$line: \[head\] camera_body: the camera reaches 57.1 mm from the laser origin (56.7, plus 0.44 for origin_tol, half a step and the backlash), 37.1 mm beyond the clearance ball (\[omega\] clearance 20); also beyond it: laser 32.4, bracket 41.9, tilt hub 50.5" "$tmp/e.txt" ||
  { bad "clearance 20: not refused as it should be (exit $rc)"; cat "$tmp/e.txt"; }
[ ! -e "$tmp/x.vplog" ] || bad "a refused board wrote a log"
# the default body (no part keys) is the camera at [camera] position too
sed '/^laser_body\|^camera_body\|^bracket\|^hub/d; s/^clearance = 58 /clearance = 20 /' $BOARD >"$tmp/def.ini"
"$VP" scan --board "$tmp/def.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e2.txt"
grep -q "\[head\]: the camera reaches 57.1 mm .*this is the default camera_body" "$tmp/e2.txt" || { bad "default body"; cat "$tmp/e2.txt"; }
# swept is for io = sim boards only
sed 's/^origin_tol = 0.1 /clear_by = swept\norigin_tol = 0.1 /; s/^clearance = 58 /clearance = 20 /' $BOARD >"$tmp/sw.ini"
"$VP" scan --board "$tmp/sw.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e3.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "\[head\] clear_by: swept checks the simulated object only" "$tmp/e3.txt" || { bad "clear_by = swept on gpiod"; cat "$tmp/e3.txt"; }
# the part keys' own errors name the key
sed 's/^camera_body = 0, 30, 10, 10, 12.5, 12.5 /camera_body = 0, 30, 10, 10, 0, 12.5 /' $BOARD >"$tmp/flat.ini"
"$VP" scan --board "$tmp/flat.ini" --dry-run --log "$tmp/x.vplog" >/dev/null 2>"$tmp/e4.txt"
grep -q "\[head\] camera_body: the half-sizes HX, HY, HZ must be positive" "$tmp/e4.txt" || { bad "a flat camera box"; cat "$tmp/e4.txt"; }
echo "refused: $(sed 's/.*\[head\] camera_body: //; s/: nothing proves.*//' "$tmp/e.txt")"

[ $fail -eq 0 ] && echo "t_head: rpi4 dry run 0 head collisions, laser origin never inside Omega; former Omega caught by part (exit 5); small clearance, swept on gpiod, bad parts refused"
exit $fail
