#!/bin/sh
# The contact safety net: a surface the rangefinder cannot see (host-sim --dark: a black or
# shiny patch, read as a miss, i.e. as free space) and a head with a contact switch (--contact).
# For a sphere, a cube, the CAD part fandisk, dino and a sphere with two patches,
# `voroprobe sim ... --contact` must
#   - stop on contact (contacts > 0) and report 0 collisions,
#   - have every move, up to where the switch closed, outside the object by the independent
#     exact checker tests/cgal_moves.cpp (CGAL; a CONTACT event ends its move at the touch),
#   - pass `voroprobe log verify` (a contact withdraws the free parts through its point),
#   - exit honestly: 0 only when the mesh is a closed manifold, else 4 (the unseen patch).
# The case the checkers must catch: the same cube without the switch drives through the
# object (host-sim counts collisions, CGAL counts the moves through and inside). The meshes of
# ../shared/meshes are used when present (a fresh clone has only tests/meshes).
# A session cut after its first contacts and resumed from its log ends with the same mesh.
# The checker itself: a move ending on a face is "through" unless a contact line ends it there.
# The machine: boards/sim.ini's dry run with clearance 0, a dark band and the switch at the laser
# origin: no move of the origin past the surface beyond contact_stop (without the switch: through).
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
D="$BUILD/contact"
SM=../shared/meshes
rm -rf "$D"; mkdir -p "$D" "$BUILD/safety"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
field() { sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" "$1" | tr -d '"'; }

. tests/cgal_moves.sh
cgal_moves_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }

# ---- the checker: a move ending on the top face of the unit cube, and the way back
printf 'start 0.5 0.5 2\nmove 0.5 0.5 1\nmove 0.5 0.5 2\n' >"$D/self1.moves"
got=$("$CG" tests/meshes/cube.off "$D/self1.moves" | tail -n 1)
[ "$got" = "moves 2, through 2, inside 0, first 1" ] || bad "cgal_moves: a move onto a face: '$got'"
printf 'start 0.5 0.5 2\nmove 0.5 0.5 0.5\ncontact 0.5 0.5 1\nmove 0.5 0.5 2\n' >"$D/self2.moves"
got=$("$CG" tests/meshes/cube.off "$D/self2.moves" | tail -n 1)
[ "$got" = "moves 2, through 0, inside 0, first none" ] || bad "cgal_moves: a move stopped on a face: '$got'"
printf 'start 0.5 0.5 2\nmove 0.5 0.5 0.5\ncontact 0.5 0.5 0.9\nmove 0.5 0.5 2\n' >"$D/self3.moves"
got=$("$CG" tests/meshes/cube.off "$D/self3.moves" | tail -n 1)
[ "$got" = "moves 2, through 2, inside 0, first 1" ] || bad "cgal_moves: a contact inside the object: '$got'"

# ---- one case: NAME MESH OPTIONS...
nrun=0
run() {
  name=$1; mesh=$2; shift 2
  o="$D/$name"
  [ -f "$mesh" ] || { echo "skip $name ($mesh not found)"; return; }
  "$VP" sim --surface "off:$mesh" "$@" --contact --json --quiet --hausdorff 0 --out "$o" --log "$o.vplog" >"$o.json" 2>"$o.err"
  rc=$?
  coll=$(field "$o.json" collisions); contacts=$(field "$o.json" contacts); closed=$(field "$o.json" closed_manifold)
  [ "$coll" = 0 ] || bad "$name: collisions $coll"
  [ -n "$contacts" ] && [ "$contacts" -gt 0 ] || bad "$name: no contact (the dark patch was never met?)"
  case "$rc:$closed" in 0:true|4:false) ;; *) bad "$name: exit $rc with closed_manifold $closed";; esac
  start=$("$VP" log dump "$o.vplog" | sed -n '/^# start /{s/^# start \([^ ]*\) \([^ ]*\) \([^ ,]*\),.*/\1,\2,\3/p;q;}')
  "$VP" log dump "$o.vplog" --csv >"$o.csv" || bad "$name: log dump"
  "$CG" "$mesh" "$o.csv" --start "$start" >"$o.cgal" 2>&1
  cg=$(tail -n 1 "$o.cgal"); cgc=$(sed -n 's/^contacts \([0-9]*\).*/\1/p' "$o.cgal")
  case "$cg" in "moves "*", through 0, inside 0, first none") ;; *) bad "$name: CGAL: $cg";; esac
  [ "${cgc:-0}" = "$contacts" ] || bad "$name: CGAL saw ${cgc:-0} contacts, the session $contacts"
  "$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "$name: log verify: $(tail -n 1 "$o.verify")"
  nrun=$((nrun + 1))
  printf '%-14s exit %s, %s vertices, %s probes, contacts %s, proofs withdrawn %s, misses not trusted %s, collisions %s; CGAL: %s\n' \
    "$name" "$rc" "$(field "$o.json" vertices)" "$(field "$o.json" probes)" "$contacts" "$(field "$o.json" revoked)" \
    "$(field "$o.json" dark_misses)" "$coll" "$cg"
}
run sphere966 $SM/sphere966.off --eps-rel 0.05 --dark 0,0,10,5
run sphere-2dark $SM/sphere966.off --eps-rel 0.04 --dark 10,0,0,4 --dark 0,-10,0,6
run cube tests/meshes/cube.off --eps-rel 0.05 --dark 0.5,0.5,1,0.3
run fandisk $SM/fandisk.off --eps-rel 0.05 --dark 0.2966,0.15655,0.2075,0.15
run dino $SM/dino.off --eps-rel 0.03 --dark 0.115434,-0.555923,1.60466,0.3

# ---- a patch where the seed's probe meets the sphere: the seed comes from another side (it used
# to stop there: "out of range", the interior point taken for outside the object)
o="$D/seedpatch"
"$VP" sim --surface sphere --eps-rel 0.05 --dark 0.6,0.6,0.53,0.1 --contact --json --quiet --hausdorff 0 \
  --log "$o.vplog" >"$o.json" 2>"$o.err"
rc=$?
ps=$(field "$o.json" planner_status); coll=$(field "$o.json" collisions)
[ "$ps" = ok ] && [ "$coll" = 0 ] && { [ $rc = 0 ] || [ $rc = 4 ]; } || bad "dark patch over the seed: exit $rc, planner $ps, collisions $coll"
"$VP" log verify "$o.vplog" >/dev/null 2>&1 || bad "dark patch over the seed: log verify"
echo "dark patch over the seed's way in: planner $ps, exit $rc, collisions $coll"

# ---- without the switch the head goes through the object: both checkers must see it
o="$D/nocontact"
"$VP" sim --surface off:tests/meshes/cube.off --eps-rel 0.05 --dark 0.5,0.5,1,0.3 --stop-after 3000 --json --quiet \
  --hausdorff 0 --log "$o.vplog" >"$o.json" 2>"$o.err"
coll=$(field "$o.json" collisions)
[ -n "$coll" ] && [ "$coll" -gt 0 ] || bad "without the contact switch: collisions '$coll' (expected > 0)"
start=$("$VP" log dump "$o.vplog" | sed -n '/^# start /{s/^# start \([^ ]*\) \([^ ]*\) \([^ ,]*\),.*/\1,\2,\3/p;q;}')
"$VP" log dump "$o.vplog" --csv >"$o.csv"
cg=$("$CG" tests/meshes/cube.off "$o.csv" --start "$start" | tail -n 1)
case "$cg" in *", through 0, inside 0, first none") bad "without the contact switch CGAL sees no move through: $cg";; esac
echo "without the switch: host-sim collisions $coll; CGAL: $cg"

# ---- cut after some contacts, resumed: the same mesh as the whole session
o="$D/cut"
"$VP" sim --surface off:tests/meshes/cube.off --eps-rel 0.05 --dark 0.5,0.5,1,0.3 --contact --stop-after 900 --quiet \
  --hausdorff 0 --out "$o" --log "$o.vplog" >/dev/null 2>&1
c1=$("$VP" log dump "$o.vplog" | grep -c "EVENT contact")
"$VP" sim --resume "$o.vplog" --quiet >/dev/null 2>&1
[ "$c1" -gt 0 ] || bad "the cut session had no contact before its cut"
cmp -s "$o.off" "$D/cube.off" || bad "resumed after $c1 contacts: the mesh differs from the whole session's"
"$VP" log verify "$o.vplog" >/dev/null 2>&1 || bad "the resumed log does not verify"
echo "cut at command 900 after $c1 contact(s), resumed: mesh identical to the whole session's"

# ---- the machine: boards/sim.ini's dry run with clearance 0 (the head enters Omega), a dark band
# the camera sees no spot on, and the contact switch at the laser origin (port/vp_machine, driven by
# host-sim's object): the origin never goes past the surface by more than contact_stop; without
# the switch the same run drives through the object
o="$D/machine"
sed -e 's/^clearance = 12/clearance = 0/' -e 's/^clear_by = swept.*/clear_by = swept\ncontact = sim\ncontact_stop = 25/' \
  boards/sim.ini >"$o.ini"
printf 'dark = 0.0007, -30, 30\n' >>"$o.ini"
sed -e '/^contact/d' "$o.ini" >"$o-off.ini"
"$VP" scan --board "$o.ini" --dry-run --log "$o.vplog" >"$o.out" 2>&1
grep -q 'dry run: .* 0 moves through the object' "$o.out" || bad "machine dry run with the switch: $(grep 'dry run: probe' "$o.out")"
mc=$(sed -n 's/^dry run: the contact switch stopped \([0-9]*\) move.*/\1/p' "$o.out")
md=$(sed -n 's/^dry run: the contact switch stopped .* at most \([0-9.]*\) mm past.*/\1/p' "$o.out")
[ -n "$mc" ] && [ "$mc" -gt 0 ] || bad "machine dry run: no contact"
"$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "machine dry run: log verify: $(tail -n 1 "$o.verify")"
"$VP" scan --board "$o-off.ini" --dry-run --stop-after 3000 --log "$o-off.vplog" >"$o-off.out" 2>&1
mt=$(sed -n 's/^dry run: .* \([0-9]*\) moves through the object$/\1/p' "$o-off.out")
[ -n "$mt" ] && [ "$mt" -gt 0 ] || bad "machine dry run without the switch: '$mt' moves through (expected > 0)"
# the head's body: the stylus's give past a touch (within contact_stop) and the way back over it
# are the touch, not collisions; without the switch the body goes into the object
hc=$(sed -n 's/^dry run: head: \([0-9]*\) head collisions.*/\1/p' "$o.out")
hoff=$(sed -n 's/^dry run: head: \([0-9]*\) head collisions.*/\1/p' "$o-off.out")
[ "$hc" = 0 ] || bad "machine dry run with the switch: $hc head collisions"
[ -n "$hoff" ] && [ "$hoff" -gt 0 ] || bad "machine dry run without the switch: '$hoff' head collisions (expected > 0)"
echo "machine dry run (sim.ini, clearance 0, a dark band): $mc contact(s), the laser origin at most $md mm past the surface (contact_stop 25), 0 moves through, $hc head collisions; without the switch $mt moves through and $hoff head collisions in 3000 commands"

[ $fail = 0 ] || exit 1
echo "contact safety net: $nrun object(s) with dark patches, 0 collisions, every move outside the object by CGAL up to its contact, logs verified; without the switch $coll collisions; machine dry run $mc contacts, 0 moves through ($mt without the switch)"
