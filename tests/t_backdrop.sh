#!/bin/sh
# A backdrop ([rangefinder] backdrop: matte walls round the machine on which every beam that
# meets nothing ends, within max_range): a frame with no spot is then unreadable, never free
# space. Without it a spot the camera cannot see (hidden behind the object, as on a torus's far
# inner side seen through its hole, or on a surface too dark to return the laser) reads as a
# miss, and the planner takes space inside the object for free. boards/sim-enclosed.ini's dry
# run (a 100 mm object, the head in its clearance ball). Checked, none of it by voroprobe's own
# code:
#   - host-sim's exact ray against the object counts the misses that had a surface on them
#     (hidden spots), and the moves through the object;
#   - CGAL (tests/cgal_object.cpp topology) says the torus's mesh is a closed 2-manifold of
#     genus 1; `log verify` proves every move free;
#   - CGAL says fandisk's mesh at eps 8 is a closed 2-manifold of genus 0 (the manifold
#     criterion refines at an edge of four facets);
#   - a line laser with the walls: the sphere closed (CGAL), every ray within the noise
#     tolerance of the object (host-sim), the dark band never read as free;
#   - the same runs without the backdrop read hidden spots (host-sim counts them: the check sees
#     them); there the sight rule (a miss whose spot the mesh found so far or the space still
#     unknown may hide from the camera is unreadable) takes some of them as unreadable, and the
#     torus closes with genus 1 (CGAL) that way too.
. tests/lib.sh
. tests/cgal_object.sh
cgal_object_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }
B=boards/sim-enclosed.ini
grep -v '^backdrop' "$B" >"$tmp/open.ini"

# ---- the 100 mm torus at eps 6: its far inner side is seen through the hole
"$VP" scan --board "$B" --dry-run --eps 6 --log "$tmp/t.vplog" --quiet --json >"$tmp/t.out" 2>&1
rc=$?
[ $rc -eq 0 ] || bad "torus: exit $rc ($(grep '^mesh' "$tmp/t.out"))"
[ "$(field "$tmp/t.out" hidden_spots)" = 0 ] || bad "torus: $(field "$tmp/t.out" hidden_spots) misses with a surface on them"
[ "$(field "$tmp/t.out" through)" = 0 ] || bad "torus: moves through the object"
[ "$(field "$tmp/t.out" head_collisions)" = 0 ] || bad "torus: head collisions"
# the head turned on the way to its probes (the ball rule): the aims took next to nothing, and
# the dry run's sweep of the head along the pieces the machine took found no collision (above)
mt=$(field "$tmp/t.out" moves_turning)
[ "${mt:-0}" -gt 1000 ] || bad "torus: ${mt:-no} MOVEs turned the head on the way"
awk -v a="$(field "$tmp/t.out" machine_s_aims)" -v t="$(field "$tmp/t.out" machine_s)" 'BEGIN { exit !(t > 0 && a < 0.01 * t) }' ||
  bad "torus: aims $(field "$tmp/t.out" machine_s_aims) s of $(field "$tmp/t.out" machine_s) s"
# each probe's route made as one path (the waypoints between MOVEs passed without stopping); the
# log's proof of every MOVE (log verify, below) is the same as for MOVEs made one by one
np=$(field "$tmp/t.out" paths)
pm=$(field "$tmp/t.out" path_moves)
[ "${np:-0}" -gt 500 ] && [ "${pm:-0}" -ge $((2 * ${np:-0})) ] || bad "torus: ${np:-no} paths of ${pm:-no} MOVEs"
ns=$(field "$tmp/t.out" unreadable_no_spot)
[ "${ns:-0}" -gt 0 ] || bad "torus: no frame without a spot (the hidden spots were not met)"
"$CO" topology "$tmp/t.off" | grep -q '"manifold":true,"closed":true,"components":1,"genus":1}' ||
  bad "torus: CGAL topology: $("$CO" topology "$tmp/t.off")"
"$VP" log verify "$tmp/t.vplog" >"$tmp/t.verify" 2>&1 || bad "torus: log verify: $(tail -n 1 "$tmp/t.verify")"
# a miss is a spot seen past the range: not repeated with the walls (the log's header says so)
"$VP" log dump "$tmp/t.vplog" 2>/dev/null | grep -q 'confirm misses 0,' || bad "torus: misses still confirmed with a backdrop"
# without the walls: hidden spots, some taken as unreadable by the sight rule; the torus closes
"$VP" scan --board "$tmp/open.ini" --dry-run --eps 6 --log "$tmp/o.vplog" --quiet --json >"$tmp/o.out" 2>&1
orc=$?
oh=$(field "$tmp/o.out" hidden_spots)
[ "${oh:-0}" -gt 0 ] || bad "torus without the backdrop: no hidden spot counted (the check cannot see them)"
[ "$(field "$tmp/o.out" unseen_misses)" -gt 0 ] 2>/dev/null || bad "torus without the backdrop: no miss taken as unseen"
[ $orc -eq 0 ] || bad "torus without the backdrop: exit $orc, expected 0 (closed by the sight rule)"
"$CO" topology "$tmp/o.off" | grep -q '"closed":true,"components":1,"genus":1' ||
  bad "torus without the backdrop: CGAL: $("$CO" topology "$tmp/o.off")"
"$VP" log dump "$tmp/o.vplog" 2>/dev/null | grep -q 'confirm misses 2,' || bad "torus without the backdrop: misses not confirmed"

# ---- a CAD part (fandisk, 100 mm) at eps 8: its sharp edges leave an edge of four facets (an
# outside tet between two inside ones) whose ring had a side once unseen and since probed; the
# manifold criterion must refine there (it stopped at any side ever marked unseen, and the mesh
# ended non-manifold, exit 4)
"$VP" scan --board "$B" --dry-run --surface 'off:../shared/meshes/fandisk.off*100' --eps 8 \
  --log "$tmp/f8.vplog" --quiet --json >"$tmp/f8.out" 2>&1
frc=$?
[ $frc -eq 0 ] || bad "fandisk: exit $frc ($(grep '^mesh' "$tmp/f8.out"))"
[ "$(field "$tmp/f8.out" through)" = 0 ] || bad "fandisk: moves through the object"
[ "$(field "$tmp/f8.out" head_collisions)" = 0 ] || bad "fandisk: head collisions"
[ "$(field "$tmp/f8.out" hidden_spots)" = 0 ] || bad "fandisk: hidden spots"
"$CO" topology "$tmp/f8.off" | grep -q '"manifold":true,"closed":true,"components":1,"genus":0}' ||
  bad "fandisk: CGAL topology: $("$CO" topology "$tmp/f8.off")"
"$VP" log verify "$tmp/f8.vplog" >"$tmp/f8.verify" 2>&1 || bad "fandisk: log verify: $(tail -n 1 "$tmp/f8.verify")"

# ---- a dark band (albedo 0.0007) round the 100 mm sphere at eps 12: the spot is too faint
grep -q '^\[sim\]' "$B" && [ "$(grep '^\[' "$B" | tail -n 1)" = "[sim]" ] || bad "the board's last section is not [sim]"
(cat "$B"; printf 'dark = 0.0007, -10, 10\n') >"$tmp/dark.ini"
grep -v '^backdrop' "$tmp/dark.ini" >"$tmp/dark-open.ini"
"$VP" scan --board "$tmp/dark.ini" --dry-run --surface 'sphere*50' --eps 12 --log "$tmp/d.vplog" --quiet --json >"$tmp/d.out" 2>&1
drc=$?
[ "$(field "$tmp/d.out" hidden_spots)" = 0 ] || bad "dark band: $(field "$tmp/d.out" hidden_spots) misses with a surface on them"
[ "$(field "$tmp/d.out" through)" = 0 ] || bad "dark band: moves through the object"
dn=$(field "$tmp/d.out" unreadable_no_spot)
[ "${dn:-0}" -gt 0 ] || bad "dark band: no frame without a spot"
[ $drc -eq 4 ] && grep -q 'with no spot where the backdrop would show one' "$tmp/d.out" &&
  grep -q 'frames showed no spot where the backdrop would: a surface too dark' "$tmp/d.out" ||
  bad "dark band: exit $drc, expected 4 (the band cannot be seen) with the frames named"
"$VP" log verify "$tmp/d.vplog" >"$tmp/d.verify" 2>&1 || bad "dark band: log verify: $(tail -n 1 "$tmp/d.verify")"
"$VP" scan --board "$tmp/dark-open.ini" --dry-run --surface 'sphere*50' --eps 12 --log "$tmp/do.vplog" --quiet --json \
  --stop-after 1500 >"$tmp/do.out" 2>&1
dh=$(sed -n 's/^dry run: probe error.* \([0-9]*\) hidden spots.*/\1/p' "$tmp/do.out")
[ "${dh:-0}" -gt 0 ] || bad "dark band without the backdrop: ${dh:-no} hidden spots in 1500 commands (expected some)"

# ---- a line laser with the walls: a beam with no point of the line on either side is unreadable
# (the line drawn on the walls too); the sphere at eps 12 closes (CGAL) with every ray on the object
# (the dry run counts a ray farther than the noise tolerance from it as false), the dark band is
# never free
sed 's/^\[rangefinder\]/[laser]\npin = gpiochip0:18\n[rangefinder]\nlaser = line\nfan = 30/' "$B" >"$tmp/l.ini"
grep -q '^laser = line' "$tmp/l.ini" || bad "the line-laser copy of the board was not made"
"$VP" scan --board "$tmp/l.ini" --dry-run --surface 'sphere*50' --eps 12 --log "$tmp/ls.vplog" --quiet --json >"$tmp/ls.out" 2>&1
lrc=$?
[ $lrc -eq 0 ] || bad "line laser, sphere: exit $lrc ($(grep '^mesh' "$tmp/ls.out"))"
lr=$(field "$tmp/ls.out" rays)
[ "${lr:-0}" -gt 10000 ] && [ "$(field "$tmp/ls.out" ray_false)" = 0 ] ||
  bad "line laser, sphere: ${lr:-no} rays, $(field "$tmp/ls.out" ray_false) off the object"
[ "$(field "$tmp/ls.out" hidden_spots)" = 0 ] && [ "$(field "$tmp/ls.out" through)" = 0 ] || bad "line laser, sphere: hidden spots or moves through"
"$CO" topology "$tmp/ls.off" | grep -q '"manifold":true,"closed":true,"components":1,"genus":0}' ||
  bad "line laser, sphere: CGAL topology: $("$CO" topology "$tmp/ls.off")"
(cat "$tmp/l.ini"; printf 'dark = 0.0007, -10, 10\n') >"$tmp/ld.ini"
grep -v '^backdrop' "$tmp/ld.ini" >"$tmp/ld-open.ini"
for v in ld ld-open; do
  "$VP" scan --board "$tmp/$v.ini" --dry-run --surface 'sphere*50' --eps 12 --log "$tmp/$v.vplog" --quiet --json \
    --stop-after 1500 >"$tmp/$v.out" 2>&1
done
ln=$(field "$tmp/ld.out" unreadable_no_spot)
[ "$(field "$tmp/ld.out" hidden_spots)" = 0 ] && [ "${ln:-0}" -gt 0 ] ||
  bad "line laser, dark band: $(field "$tmp/ld.out" hidden_spots) hidden spots, ${ln:-no} frames without the line unreadable"
lh=$(field "$tmp/ld-open.out" hidden_spots)
[ "${lh:-0}" -gt 0 ] || bad "line laser, dark band without the backdrop: ${lh:-no} hidden spots in 1500 commands (expected some)"

# ---- the loader
sed 's/^backdrop = .*/backdrop = -330, -350, -350, 350, 350, 350/' "$B" >"$tmp/n.ini"
"$VP" scan --board "$tmp/n.ini" --dry-run --log "$tmp/n.vplog" --stop-after 1 >"$tmp/n.out" 2>&1
grep -q 'backdrop: x from -330 to 350: the walls must lie beyond axis.x travel -230..230 plus the head (116.7 mm' "$tmp/n.out" ||
  bad "walls within the head's reach: $(head -n 1 "$tmp/n.out")"
sed 's/^max_range = .*/max_range = 700/' "$B" >"$tmp/f.ini"
"$VP" scan --board "$tmp/f.ini" --dry-run --log "$tmp/f.vplog" --stop-after 1 >"$tmp/f.out" 2>&1
grep -q 'backdrop: its far corner can lie 766.2 mm from the laser origin, beyond the rangefinder.s range (700 mm)' "$tmp/f.out" ||
  bad "walls beyond the range: $(head -n 1 "$tmp/f.out")"
[ $fail = 0 ] || exit 1
echo "t_backdrop: 100 mm torus at eps 6 closed with genus 1 (CGAL), 0 hidden spots, $ns frames without a spot unreadable," \
  "$(field "$tmp/t.out" machine_s) s; fandisk at eps 8 closed, genus 0 (CGAL), $(field "$tmp/f8.out" machine_s) s; without the backdrop $oh hidden spots ($(field "$tmp/o.out" hidden_spots_free) taken for free), closed by the sight rule, $(field "$tmp/o.out" machine_s) s;" \
  "a dark band: 0 hidden spots, $dn unreadable, exit 4 (without: $dh hidden spots in 1500 commands);" \
  "a line laser: the sphere closed, $lr rays, 0 off the object; its dark band 0 hidden spots, $ln unreadable (without: $lh hidden); bad walls refused"
