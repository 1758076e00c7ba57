#!/bin/sh
# Body mode (the head stays outside Omega): a facet whose Voronoi edge's own line is occluded
# from dOmega is found from aside (core/planner/aim.c): lines tilted from the edge, through
# points of it, narrow the stretch where S crosses it, or see its far vertex free. Without it
# the torus and genus2 stayed open in body mode (their inner sides face each other across the
# holes). Each next line goes where the last hit puts the crossing of the edge (else the
# middle). genus5 at 0.025 closes only by closing's last resort (core/planner/close.c): the
# sides still unseen at its last holes are aimed at again, with lines through their far vertex
# alone; at 0.028 it is taken twice (again with at most half as many edges odd; which eps takes
# it twice moves with the aims: 0.022 while the aim's tolerance was the hits' own). Without the
# last resort 0.025 ended open when it was measured. On the enclosed board's dry run a side
# whose line enters Omega from outside and whose spot the camera cannot read is aimed at too.
# With dropouts (a real hit read as a miss, 5%) an aimed line's miss is trusted only once
# confirmed, as a task's is: trusted at once, such misses took far vertices inside genus5 for
# outside (311-359 of some 850 per scan) and the scan ended open.
# Checked, none of it by voroprobe's own code:
#   - CGAL (tests/cgal_object.cpp topology) says each mesh is a closed 2-manifold of the
#     object's genus (torus 1, genus2 2) and measures it against the object's own mesh (the
#     Hausdorff distance within eps);
#   - host-sim's exact check: 0 moves through the object; `log verify` proves every move free;
#   - the checker must fail: the torus's mesh less one triangle is not closed.
. tests/lib.sh
. tests/cgal_object.sh
cgal_object_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }
# what every run must show: a line aimed from aside, CGAL's closed 2-manifold of the object's
# genus ($2), every move proven free by `log verify`
aimed_closed() {
  a=$(field "$tmp/$1.json" aims)
  [ "${a:-0}" -gt 0 ] || bad "$1: no line aimed from aside"
  "$CO" topology "$tmp/$1.off" | grep -q "\"manifold\":true,\"closed\":true,\"components\":1,\"genus\":$2}" ||
    bad "$1: CGAL topology: $("$CO" topology "$tmp/$1.off")"
  "$VP" log verify "$tmp/$1.vplog" >"$tmp/$1.verify" 2>&1 || bad "$1: log verify: $(tail -n 1 "$tmp/$1.verify")"
}
out=""
for c in "torus 0.03 1" "torus 0.02 1" "genus2 0.03 2" "genus5 0.04 5" "genus5 0.025 5" "genus5 0.028 5" "genus5 0.04 5 0.05"; do
  set -- $c
  n="$1-$2${4:+-dropout$4}"
  "$VP" sim --surface "$1" --clearance 0.05 --eps-rel "$2" ${4:+--dropout $4} --out "$tmp/$n" --json >"$tmp/$n.json" 2>"$tmp/$n.err"
  rc=$?
  [ $rc -eq 0 ] || bad "$n: exit $rc ($(tail -n 1 "$tmp/$n.err"))"
  [ "$(field "$tmp/$n.json" collisions)" = 0 ] || bad "$n: $(field "$tmp/$n.json" collisions) moves through the object"
  [ "$(field "$tmp/$n.json" tube_moves)" = 0 ] || bad "$n: the head entered Omega"
  aimed_closed "$n" "$3"
  fl=$(field "$tmp/$n.json" far_line_sides)
  lr=$(field "$tmp/$n.json" last_resorts)
  case $n in genus5-0.025|genus5-0.028) [ "${fl:-0}" -gt 0 ] || bad "$n: closing's last resort not taken";; esac
  if [ "$n" = genus5-0.028 ]; then [ "${lr:-0}" -ge 2 ] || bad "$n: closing's last resort taken ${lr:-0} times, not again"; fi
  out="$out $n: $(field "$tmp/$n.json" vertices) vertices, $(field "$tmp/$n.json" probes) probes ($a aimed, $(field "$tmp/$n.json" aim_balls) balls, $(field "$tmp/$n.json" aim_reached) far vertices, ${fl:-0} sides again in ${lr:-0} last resorts);"
done
# a dry run on the enclosed board (a camera that cannot read every spot): fandisk at eps 6 kept one
# facet open whose Voronoi edge enters Omega from a vertex outside it and whose spot the camera
# cannot see from that line; at the hole it is now aimed at from aside too, and the mesh closes
M=../shared/meshes/fandisk.off
if [ -r "$M" ]; then
  n=enclosed-fandisk-6
  "$VP" scan --board boards/sim-enclosed.ini --dry-run --surface "off:$M*100" --eps 6 --log "$tmp/$n.vplog" --json --quiet \
    >"$tmp/$n.json" 2>"$tmp/$n.err"
  rc=$?
  [ $rc -eq 0 ] && [ "$(field "$tmp/$n.json" closed)" = true ] || bad "$n: exit $rc, not closed ($(tail -n 1 "$tmp/$n.err"))"
  [ "$(field "$tmp/$n.json" through)" = 0 ] && [ "$(field "$tmp/$n.json" head_collisions)" = 0 ] ||
    bad "$n: $(field "$tmp/$n.json" through) moves through, $(field "$tmp/$n.json" head_collisions) head collisions"
  aimed_closed "$n" 0
  out="$out $n: $(field "$tmp/$n.json" vertices) vertices, $(field "$tmp/$n.json" probes) probes ($a aimed, $(field "$tmp/$n.json" aim_balls) balls);"
else
  echo "t_aim: $M not found: the enclosed board's case skipped"
fi
# the checker must fail: the torus's mesh less its last triangle
awk '/^#/ || NF == 0 { next } !h { print; h = 1; next } !c { print $1, $2 - 1, $3; c = 1; n = $1 + $2 - 1; next }
     n-- > 0 { print }' "$tmp/torus-0.03.off" >"$tmp/open.off"
"$CO" topology "$tmp/open.off" | grep -q '"closed":false' || bad "CGAL topology: a torus less a triangle taken for closed"
[ $fail = 0 ] || exit 1
echo "t_aim: closed with the object's genus, 0 moves through, logs verified:$out"
