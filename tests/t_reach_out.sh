#!/bin/sh
# A misplaced object on the real board: rpi4-gantry's dry run (the head kept outside Omega, its
# routes round Omega made as watched paths, its contact switch in the head's mount; a copy with
# a stylus at the laser origin instead, contact_by = stylus, for the first cases) on an object
# that reaches out of Omega (`scan --dry-run --reach-out`): a ball of 24 mm in the middle and a
# knob of 6 mm reaching 3 mm out of Omega (both tests/meshes/icosphere2.off, so that the
# independent checker reads the same object).
#   - without --reach-out the dry run refuses the object and says why; without --dry-run the
#     option is refused; a knob holding the head's start is refused;
#   - knob below and to the -x side: the head meets it on a route round Omega, laser origin
#     first: the switch stops the path's MOVE, the scan ends with exit 1 and the reason (the
#     object reaches out of [omega]), no part of the head's body within 0.5 mm of the object
#     before the touch, the origin at most contact_stop past the surface; every move up to the
#     touch outside the object by CGAL (tests/cgal_moves.cpp, the switch's lag and backlash
#     within 0.5 mm), the log proven free (`log verify`); no scan goes on from that log (--resume
#     and --rescan say why), but it replays and makes a report;
#   - knob on the +x side: the head comes at it sideways with the laser pointing at Omega's
#     centre, and the laser module's side meets it before the origin does: the switch cannot
#     stop that; the dry run must say so (exit 5, the laser part counted) while CGAL on the
#     origin's path alone sees nothing wrong;
#   - the same sideways knob with the switch in the head's mount (contact_by = mount): stopped
#     (exit 1), no part within 0.5 mm before the switch closed, the parts at most contact_stop past;
#   - a knob in the way from homing to the start: the switch stops the host's own move too (the
#     head backs off, --json says why); with the mount exit 1 and no collision, with the stylus
#     the laser module meets it first (exit 5);
#   - the checkers' failing case: the same run without the switch drives through the knob
#     (the dry run counts moves through, exit 5; CGAL counts them too).
. tests/lib.sh
D="$BUILD/reach_out"
B=boards/rpi4-gantry.ini
rm -rf "$D"; mkdir -p "$D"
part() { tail -n 1 "$1" | sed -n "s/.*\"head_parts\":{[^}]*\"$2\":\([0-9]*\).*/\1/p"; }

# the board's switch sits in the head's mount; the stylus at the laser origin is this copy's
sed -e 's/^contact_by = mount /contact_by = stylus /' "$B" >"$D/stylus.ini"
grep -q "^contact_by = stylus" "$D/stylus.ini" || { echo "FAIL: the stylus copy of $B has no contact_by = stylus"; exit 1; }

. tests/cgal_moves.sh
cgal_moves_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }

# the object as one OFF for the checker: icosphere2 scaled by S and moved to X,Y,Z, twice
obj_off() {   # OUT S1,X1,Y1,Z1 S2,X2,Y2,Z2
  awk -v spec="$2 $3" '
    BEGIN { split(spec, specs, " ") }
    FNR == 1 { f++; nv = 0; nf = 0; hdr = 0; split(specs[f], t, ",") }
    /^#/ || /^OFF/ || NF == 0 { next }
    hdr == 0 { NV[f] = $1; NFC[f] = $2; hdr = 1; next }
    nv < NV[f] { V[++tv] = sprintf("%.17g %.17g %.17g", t[2] + t[1] * $1, t[3] + t[1] * $2, t[4] + t[1] * $3); nv++; next }
    nf < NFC[f] { line = $1; for (k = 2; k <= $1 + 1; k++) line = line " " ($k + base); F[++tf] = line; nf++
                  if (nf == NFC[f]) base += NV[f]; next }
    END { print "OFF"; print tv, tf, 0; for (i = 1; i <= tv; i++) print V[i]; for (i = 1; i <= tf; i++) print F[i] }
  ' tests/meshes/icosphere2.off tests/meshes/icosphere2.off >"$1"
}
ICO=tests/meshes/icosphere2.off
BODY="24,200,150,150"
spec() { echo "off:$ICO*24@200,150,150+off:$ICO*6@$1"; }

# ---- refused without --reach-out, and outside a dry run
"$VP" scan --board "$B" --dry-run --eps 16 --surface "$(spec 143.431,150,93.431)" --log "$D/refused.vplog" \
  >"$D/refused.out" 2>&1
rc=$?
[ $rc = 1 ] && grep -q "is not inside the board's Omega.*--reach-out" "$D/refused.out" ||
  bad "an object reaching out of Omega: exit $rc, $(grep 'scan:' "$D/refused.out" | tail -n 1)"
"$VP" scan --board "$B" --reach-out --log "$D/hw.vplog" >"$D/hw.out" 2>&1
rc=$?
[ $rc != 0 ] && grep -q "reach-out.*dry runs only" "$D/hw.out" || bad "--reach-out without --dry-run: exit $rc"

"$VP" scan --board "$B" --dry-run --reach-out --eps 16 --surface "$(spec 200,150,232)" --log "$D/start.vplog" \
  >"$D/start.out" 2>&1
rc=$?
[ $rc = 1 ] && grep -q "holds the laser origin's start" "$D/start.out" || bad "a knob holding the head's start: exit $rc"

# ---- one run: NAME KNOB BOARD
run() {
  name=$1; knob=$2; board=$3
  o="$D/$name"
  "$VP" scan --board "$board" --dry-run --reach-out --eps 16 --surface "$(spec "$knob")" --log "$o.vplog" --json --quiet \
    >"$o.json" 2>"$o.err"
  rc=$?
  obj_off "$o.off" "$BODY" "6,$knob"
  "$VP" log dump "$o.vplog" --csv >"$o.csv" || bad "$name: log dump"
  start=$("$VP" log dump "$o.vplog" | sed -n '/^# start /{s/^# start \([^ ]*\) \([^ ]*\) \([^ ,]*\),.*/\1,\2,\3/p;q;}')
  "$CG" "$o.off" "$o.csv" --start "$start" --lag 0.5 >"$o.cgal" 2>&1
  cg=$(tail -n 1 "$o.cgal")
  printf '%-10s exit %s, contacts %s (%s mm past the touch), moves through %s, head collisions %s (laser %s, camera %s, tilt hub %s, clearance ball %s); CGAL: %s\n' \
    "$name" "$rc" "$(field "$o.json" contacts)" "$(field "$o.json" touch_depth_max)" "$(field "$o.json" through)" \
    "$(field "$o.json" head_collisions)" "$(part "$o.json" laser)" "$(part "$o.json" camera)" "$(part "$o.json" 'tilt hub')" \
    "$(part "$o.json" 'clearance ball')" "$cg"
}

# ---- the origin meets the knob first: stopped on the path, exit 1
run first 143.431,150,93.431 "$D/stylus.ini"
o="$D/first"
[ $rc = 1 ] || bad "first: exit $rc (expected 1: stopped by the touch)"
grep -q "contact switch closed outside Omega: the object reaches out" "$o.err" || bad "first: the reason is not given"
# --json says why it stopped (read by Python's json, not by a pattern)
tail -n 1 "$o.json" | /usr/bin/python3 -c 'import json, sys; j = json.load(sys.stdin); sys.exit(0 if "reaches out of [omega]" in j.get("stop_reason", "") and j["exit"] == 1 else 1)' ||
  bad "first: --json has no stop_reason naming the touch"
[ "$(field "$o.json" contacts)" = 1 ] || bad "first: contacts $(field "$o.json" contacts)"
[ "$(field "$o.json" head_collisions)" = 0 ] || bad "first: head collisions $(field "$o.json" head_collisions)"
for p in laser camera bracket 'tilt hub'; do [ "$(part "$o.json" "$p")" = 0 ] || bad "first: $p $(part "$o.json" "$p")"; done
[ "$(part "$o.json" 'clearance ball')" -gt 0 ] || bad "first: the clearance ball never met the knob (the case tests nothing)"
depth=$(field "$o.json" touch_depth_max)
awk -v d="$depth" 'BEGIN { exit !(d > 0 && d <= 10) }' || bad "first: the origin went $depth mm past the surface (contact_stop 10)"
case "$cg" in "moves "*", through 0, inside 0, first none") ;; *) bad "first: CGAL: $cg";; esac
grep -q "^contacts 1 " "$o.cgal" || bad "first: CGAL did not see the contact"
# the touch came on a route of several MOVEs made as one path, not at its end
"$VP" log dump "$o.vplog" >"$o.dump"
prev=$(grep -B 4 "EVENT contact" "$o.dump" | grep -c " MOVE to ")
[ "$prev" = 4 ] || bad "first: the touched MOVE does not end a run of MOVEs ($prev of the 4 records before it)"
paths=$(field "$o.json" paths)
[ -n "$paths" ] && [ "$paths" -gt 0 ] || bad "first: no MOVEs made as one path ($paths)"
"$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "first: log verify: $(tail -n 1 "$o.verify")"
grep -q "1 contact(s)" "$o.verify" || bad "first: log verify did not take the contact: $(tail -n 1 "$o.verify")"
# the log afterwards: no scan goes on from it (--resume, --rescan refuse and say why), but it
# replays to the mesh it had and makes a report (they used to stop at the contact)
"$VP" scan --log "$o.vplog" --resume --quiet >"$o.resume" 2>&1
rc=$?
[ $rc = 1 ] && grep -q "touched outside Omega (the object reaches out of \[omega\]); no scan goes on" "$o.resume" ||
  bad "first: --resume after the touch: exit $rc, $(tail -n 1 "$o.resume")"
"$VP" scan --rescan "$o.vplog" --log "$o-re.vplog" --surface "off:$ICO*24@200,150,150" --quiet >"$o.rescan" 2>&1
rc=$?
[ $rc = 1 ] && grep -q "no scan goes on from this log" "$o.rescan" || bad "first: --rescan after the touch: exit $rc"
"$VP" replay "$o.vplog" --out "$o-replay" >"$o.replay" 2>&1 || bad "first: replay: $(tail -n 1 "$o.replay")"
grep -q "every command equal to the logged one" "$o.replay" || bad "first: replay: $(head -n 1 "$o.replay")"
"$VP" report "$o.vplog" --out "$o.html" --json >"$o.report" 2>&1 || bad "first: report: $(tail -n 1 "$o.report")"
tail -n 1 "$o.report" | /usr/bin/python3 -c 'import json, sys; j = json.load(sys.stdin); sys.exit(0 if j.get("status") == "error" else 1)' ||
  bad "first: the report's summary: $(tail -n 1 "$o.report" | cut -c1-200)"
[ -s "$o.html" ] || bad "first: no report page"
"$VP" certify "$o.vplog" >"$o.certify" 2>&1
rc=$?
[ $rc = 1 ] && grep -q "nothing to certify: the session has no facet yet" "$o.certify" || bad "first: certify: exit $rc, $(tail -n 1 "$o.certify")"

# ---- sideways: the laser module meets the knob before the origin: exit 5, the part named
run side 280,150,150 "$D/stylus.ini"
o="$D/side"
[ $rc = 5 ] || bad "side: exit $rc (expected 5: the laser module hit the knob)"
[ "$(part "$o.json" laser)" -gt 0 ] || bad "side: the laser part not counted"
grep -q "^SAFETY: .*laser 1" "$o.json" || bad "side: no SAFETY line naming the laser"
case "$cg" in "moves "*", through 0, inside 0, first none") ;; *) bad "side: CGAL on the origin's path: $cg";; esac

# ---- the same knob with the switch in the head's mount (contact_by = mount): any part pushed
# opens it, so the laser module's side stops the head too: exit 1, no collision, the parts at
# most contact_stop past where the switch closed
cp "$B" "$D/mount.ini"
grep -q "^contact_by = mount" "$D/mount.ini" || bad "mount: the board has no contact_by = mount"
run mount 280,150,150 "$D/mount.ini"
o="$D/mount"
[ $rc = 1 ] || bad "mount: exit $rc (expected 1: stopped by the touch)"
grep -q "contact switch closed outside Omega: the object reaches out" "$o.err" || bad "mount: the reason is not given"
[ "$(field "$o.json" contacts)" = 1 ] || bad "mount: contacts $(field "$o.json" contacts)"
[ "$(field "$o.json" head_collisions)" = 0 ] || bad "mount: head collisions $(field "$o.json" head_collisions)"
depth=$(field "$o.json" touch_depth_max)
awk -v d="$depth" 'BEGIN { exit !(d > 0 && d <= 10) }' || bad "mount: the head went $depth mm past the touch (contact_stop 10)"
case "$cg" in "moves "*", through 0, inside 0, first none") ;; *) bad "mount: CGAL: $cg";; esac
grep -q "the head (a bound over the parts its mount senses) at most" "$o.json" || bad "mount: the summary does not say what was bounded"
"$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "mount: log verify: $(tail -n 1 "$o.verify")"

# ---- a knob in the way from homing to the start (the host's own move, not the planner's): the
# switch stops that move too and the head backs off; with the mount: exit 1, no collision, the
# reason in --json; with the stylus the laser module and the tilt hub meet the knob first (exit 5)
for kind in mount stylus; do
  bd="$D/mount.ini"; [ $kind = stylus ] && bd="$D/stylus.ini"
  o="$D/start-$kind"
  "$VP" scan --board "$bd" --dry-run --reach-out --eps 16 --surface "sphere*24@200,150,150+sphere*20@180,137,228" \
    --log "$o.vplog" --json --quiet >"$o.json" 2>"$o.err"
  rc=$?
  reason=$(tail -n 1 "$o.json" | /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin).get("stop_reason", ""))')
  case "$reason" in "moving to 200 150 234: the contact switch closed "*" into the move"*) ;;
    *) bad "start-$kind: the way to the start not stopped by the switch: '$reason'";; esac
  [ "$(field "$o.json" contacts)" = 1 ] || bad "start-$kind: contacts $(field "$o.json" contacts)"
  if [ $kind = mount ]; then
    [ $rc = 1 ] && [ "$(field "$o.json" head_collisions)" = 0 ] || bad "start-mount: exit $rc, head collisions $(field "$o.json" head_collisions)"
  else
    [ $rc = 5 ] && [ "$(part "$o.json" laser)" -gt 0 ] || bad "start-stylus: exit $rc, laser $(part "$o.json" laser)"
  fi
  printf 'start-%-6s exit %s, %s; head collisions %s\n' "$kind" "$rc" "$reason" "$(field "$o.json" head_collisions)"
done

# ---- without the switch: through the knob, and both checkers see it
sed -e '/^contact/d' "$B" >"$D/noswitch.ini"
run noswitch 143.431,150,93.431 "$D/noswitch.ini"
o="$D/noswitch"
[ $rc = 5 ] || bad "noswitch: exit $rc (expected 5)"
t=$(field "$o.json" through)
[ -n "$t" ] && [ "$t" -gt 0 ] || bad "noswitch: the dry run counts no move through the knob ($t)"
case "$cg" in "moves "*", through 0, inside 0, first none") bad "noswitch: CGAL sees no move through: $cg";; esac

[ $fail = 0 ] && echo "reach-out: touched on a path and stopped (exit 1); sideways crash named (exit 5), stopped by a mount's switch (exit 1); without the switch through (exit 5)"
exit $fail
