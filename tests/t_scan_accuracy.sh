#!/bin/sh
# `scan --accuracy H` on the machine (the rpi4 board's dry run, its head kept outside Omega): the
# object is a 642-vertex polyhedral sphere of radius 24 mm, so CGAL can measure the mesh against
# it independently (tests/cgal_object.cpp hausdorff, built by tests/cgal_object.sh):
#   - --accuracy 1 with hits trusted to 0.15 mm: closed, exit 0, the summary says within, and
#     CGAL's two-sided Hausdorff distance is at most 1 mm;
#   - --accuracy 0.5 with the default --noise-tol 2: the note says the bound cannot be met, and
#     the scan ends with exit 6 (not within the target), CGAL agreeing that it is not;
#   - cut after 1500 commands and resumed: the log keeps --accuracy, and the mesh is the same
#     bytes as the scan's run in one go.
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
bad() { echo "FAIL: $*"; exit 1; }
field() { tail -n 1 "$1" | sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }
. tests/cgal_object.sh
cgal_object_build "$B" || bad "$CG_WHY"
# the object: an icosahedron subdivided three times onto a sphere of radius 24 mm at (200, 150,
# 150), 642 vertices (tests/rescan_objects.py's icosphere, numbers to 17 digits: the dry run and
# CGAL read the same)
python3 -c 'import sys; sys.path.insert(0, "tests")
from rescan_objects import icosphere, write_off
v, f = icosphere(3)
write_off(sys.argv[1], [(200 + 24 * x, 150 + 24 * y, 150 + 24 * z) for x, y, z in v], f)' "$tmp/object.off" || bad "writing the object"
OBJ="off:$tmp/object.off*1@0,0,0"

# within the target
"$VP" scan --board boards/rpi4-gantry.ini --dry-run --surface "$OBJ" --accuracy 1 --noise-tol 0.15 --log "$tmp/a.vplog" \
  --quiet --json >"$tmp/a.txt" 2>"$tmp/a.err"
rc=$?
[ $rc = 0 ] || bad "--accuracy 1: exit $rc ($(tail -n 3 "$tmp/a.txt" | cut -c1-300))"
grep -q "^accuracy: target 1 mm, measured .*: within" "$tmp/a.txt" || bad "--accuracy 1: no 'within' line"
[ "$(field "$tmp/a.txt" accuracy_target)" = 1 ] || bad "--accuracy 1: the JSON has no accuracy_target"
h=$(chaus "$tmp/a.off" "$tmp/object.off")
awk "BEGIN{exit !($h > 0 && $h <= 1)}" || bad "--accuracy 1: CGAL measures $h mm"
# not within: the note, exit 6, and CGAL agrees
"$VP" scan --board boards/rpi4-gantry.ini --dry-run --surface "$OBJ" --accuracy 0.5 --log "$tmp/b.vplog" \
  --quiet --json >"$tmp/b.txt" 2>"$tmp/b.err"
rc=$?
[ $rc = 6 ] || bad "--accuracy 0.5 with hits trusted to 2 mm: exit $rc, not 6"
grep -q "hits are trusted only to 2 mm" "$tmp/b.err" || bad "--accuracy 0.5: no note about --noise-tol"
hb=$(chaus "$tmp/b.off" "$tmp/object.off")
awk "BEGIN{exit !($hb > 0.5)}" || bad "exit 6 but CGAL measures $hb mm (within 0.5)"
# cut and resumed: the same mesh
"$VP" scan --board boards/rpi4-gantry.ini --dry-run --surface "$OBJ" --accuracy 1 --noise-tol 0.15 --log "$tmp/c.vplog" \
  --quiet --stop-after 1500 >/dev/null 2>&1
[ $? = 3 ] || bad "--stop-after 1500: not paused"
"$VP" scan --log "$tmp/c.vplog" --resume --quiet >/dev/null 2>&1 || bad "resume: exit $?"
"$VP" log dump "$tmp/c.vplog" 2>/dev/null | head -5 | grep -q -- "--accuracy 1" || bad "the log's note lost --accuracy"
cmp -s "$tmp/a.off" "$tmp/c.off" || bad "cut and resumed: the mesh differs from the scan in one go"
echo "t_scan_accuracy: rpi4 dry run, --accuracy 1 (hits trusted to 0.15 mm): $(field "$tmp/a.txt" vertices) vertices, $(field "$tmp/a.txt" probes) probes, $(field "$tmp/a.txt" machine_s) s of machine time, CGAL Hausdorff $h mm; --accuracy 0.5 with hits trusted to 2 mm: exit 6, CGAL $hb mm; cut and resumed: the same mesh"
