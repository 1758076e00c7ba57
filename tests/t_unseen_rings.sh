#!/bin/sh
# The manifold criterion at a hole whose rings hold an unseen side (core/planner/close.c). When
# probing round the edges with one facet finds nothing more, the largest facet at each is refined;
# that was skipped wherever a side of the edge's ring of tets was left unseen (its Voronoi edge
# occluded from dOmega and not found from aside either). At the rpi4 board's 36 mm torus those
# sides run along the axis through the hole, where no line's miss can be read (the camera looks
# through the hole), and the hole at the inner equator stayed open (at eps 3 its 9 boundary edges
# all skipped so; at eps 2.1, tested here, it ended open with 680 vertices). In body mode such an edge is now refined too, once closing's last
# resort (lines through far vertices alone) is spent, while each pass that does so finds fewer odd
# edges than the last.
# Checked, none of it by voroprobe's own code:
#   - CGAL (tests/cgal_object.cpp topology): a closed 2-manifold of genus 1;
#   - the checker must fail: the same mesh with one facet taken out is not closed;
#   - every vertex within 1 mm of the torus by its formula (Python: the dry run's own figure is
#     0.80 mm at worst, a sample refined where its ball was found from aside); `log verify` proves
#     every move free.
. tests/lib.sh
. tests/need_python.sh
need_python math python3-minimal
. tests/cgal_object.sh
cgal_object_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }

"$VP" scan --board boards/rpi4-gantry.ini --dry-run --surface 'torus*18@200,150,150' --eps 2.1 --log "$tmp/t.vplog" \
  --quiet --json >"$tmp/t.out" 2>&1
rc=$?
[ $rc -eq 0 ] || bad "torus at eps 2.1: exit $rc ($(grep '^mesh' "$tmp/t.out"))"
# the path under test was taken
ur=$(tail -n 1 "$tmp/t.out" | sed -n 's/.*"unseen_refinements":\([0-9]*\).*/\1/p')
[ "${ur:-0}" -gt 0 ] || bad "torus: no facet refined round a side left unseen (${ur:-none})"
grep -q ' 0 moves through the object' "$tmp/t.out" || bad "torus: moves through the object"
grep -q ' 0 head collisions' "$tmp/t.out" || bad "torus: head collisions"
topo=$("$CO" topology "$tmp/t.off")
echo "$topo" | grep -q '"manifold":true,"closed":true,"components":1,"genus":1}' || bad "torus: CGAL topology: $topo"
"$VP" log verify "$tmp/t.vplog" >"$tmp/t.verify" 2>&1 || bad "torus: log verify: $(tail -n 1 "$tmp/t.verify")"

# every vertex on S, within the 1 mm the machine is asked for
res=$("$PY" - "$tmp/t.off" <<'EOF'
import math, sys
w = [l for l in open(sys.argv[1]).read().split('\n') if l.strip() and not l.startswith('#')]
nv = int(w[1].split()[0])
worst = max(abs(math.hypot(math.hypot(x - 200, y - 150) - 18, z - 150) - 5.4)
            for x, y, z in ((float(t) for t in l.split()[:3]) for l in w[2:2 + nv]))
print(nv, '%.3f' % worst)
EOF
)
set -- $res
awk -v d="${2:-9}" 'BEGIN { exit !(d <= 1.0) }' || bad "torus: a vertex ${2:-?} mm off S (more than 1)"

# the checker must fail: the last facet taken out leaves a hole
"$PY" - "$tmp/t.off" "$tmp/holed.off" <<'EOF'
import sys
w = [l for l in open(sys.argv[1]).read().split('\n') if l.strip() and not l.startswith('#')]
nv, nf = (int(t) for t in w[1].split()[:2])
w[1] = '%d %d 0' % (nv, nf - 1)
open(sys.argv[2], 'w').write('\n'.join(w[:2 + nv + nf - 1]) + '\n')
EOF
"$CO" topology "$tmp/holed.off" | grep -q '"closed":true' && bad "the checker: a mesh with a facet taken out is called closed"

[ $fail -eq 0 ] || exit 1
echo "t_unseen_rings: rpi4 dry run, 36 mm torus at eps 2.1: $ur facets refined round unseen sides; closed, genus 1 (CGAL), ${1:-?} vertices, the farthest ${2:-?} mm off S; the mesh with a facet out is not closed"
