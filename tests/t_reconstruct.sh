#!/bin/sh
# `voroprobe reconstruct` (the tangential Delaunay complex) end to end on seeded samples: sphere
# (noisy, non-uniform), torus (noisy), genus-2 in R^3, Clifford torus (non-uniform) and Klein
# bottle in R^4, a closed curve in R^10, SO(3) in R^9. Each must end with 0 inconsistent
# simplices, pass the manifold check, and have the manifold's Euler characteristic and
# orientability. The surfaces in R^3 are read back by an independent reader, Open3D: vertex and
# triangle counts as reported, edge- and vertex-manifold, watertight, orientable, Euler
# characteristic from its own edge count, outward orientation (positive volume). Also: the text
# reader (commas), the PLY and session-log inputs, and the usage and input errors.
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
. tests/need_python.sh
need_python open3d python3-open3d
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail=0
runs=0
# name points options expected-euler expected-orientable
while read -r name n opts euler orient; do
  runs=$((runs + 1))
  opts=$(echo "$opts" | tr , ' '); [ "$opts" = - ] && opts=
  # shellcheck disable=SC2086
  "$VP" reconstruct --generate "$name" --n "$n" $opts --seed 1 --out "$tmp/$name" --json --quiet >"$tmp/$name.json" 2>"$tmp/$name.err"
  rc=$?
  "$PY" - "$tmp/$name.json" "$euler" "$orient" "$rc" <<'PYEOF' || { echo "FAIL: $name $n $opts: $(cat "$tmp/$name.json" "$tmp/$name.err")"; fail=$((fail + 1)); }
import json, sys
j = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
euler, orient, rc = int(sys.argv[2]), sys.argv[3] == "yes", int(sys.argv[4])
assert rc == 0, rc
assert j["inconsistent"] == 0, j
assert j["manifold"] is True, j
assert j["euler"] == euler, j
assert j["orientable"] is orient, j
assert j["simplices"][0] == j["points"], j
PYEOF
done <<EOF
sphere 4000 --noise,0.003 2 yes
sphere 3000 --nonuniform 2 yes
torus 4000 --noise,0.002 0 yes
genus2 5000 - -2 yes
clifford 4000 --nonuniform 0 yes
klein 4000 - 0 no
curve 2000 - 0 yes
so3 5000 - 0 yes
EOF
# the checks above must fail without fixing (the torus keeps inconsistent simplices)
"$VP" reconstruct --generate torus --n 4000 --fix none --out "$tmp/nofix" --json --quiet >"$tmp/nofix.json" 2>&1; rc=$?
[ $rc = 1 ] && grep -q '"inconsistent":[1-9]' "$tmp/nofix.json" ||
  { echo "FAIL: --fix none should leave inconsistent simplices and exit 1 ($rc): $(cat "$tmp/nofix.json")"; fail=$((fail + 1)); }
# Open3D reads the surfaces in R^3
"$PY" - "$tmp" <<'PYEOF' || fail=$((fail + 1))
import json, sys
import numpy as np
import open3d as o3d
d = sys.argv[1]
for name, euler in (("sphere", 2), ("torus", 0), ("genus2", -2)):
    j = json.loads(open("%s/%s.json" % (d, name)).read().strip().splitlines()[-1])
    m = o3d.io.read_triangle_mesh("%s/%s.ply" % (d, name))
    V, F = np.asarray(m.vertices), np.asarray(m.triangles)
    assert len(V) == j["points"] and len(F) == j["simplices"][2], (name, len(V), len(F))
    assert m.is_edge_manifold(allow_boundary_edges=False), name
    assert m.is_vertex_manifold(), name
    assert m.is_watertight(), name
    assert m.is_orientable(), name
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    ne = len(np.unique(e, axis=0))
    assert len(V) - ne + len(F) == euler, (name, len(V), ne, len(F))
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    vol = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert vol > 0, (name, vol)
    # the OFF written alongside holds the same triangles
    w = open("%s/%s.off" % (d, name)).read().split()
    nv, nf = int(w[1]), int(w[2])
    off = np.array([int(x) for x in w[4 + 3 * nv:]]).reshape(nf, 4)[:, 1:]
    assert (off == F).all(), name
# and tells an open mesh (one triangle less) from a closed one
m = o3d.io.read_triangle_mesh("%s/torus.ply" % d)
m.triangles = o3d.utility.Vector3iVector(np.asarray(m.triangles)[1:])
assert not m.is_watertight()
PYEOF
# inputs: text with commas, PLY (its vertices), a session log (its hits)
"$VP" reconstruct --generate torus --n 3000 --out-points "$tmp/t.txt" --quiet || fail=$((fail + 1))
sed 's/ /, /g' "$tmp/t.txt" >"$tmp/tc.txt"
"$VP" reconstruct "$tmp/tc.txt" --dim 2 --out "$tmp/tc" --quiet || { echo "FAIL: text with commas"; fail=$((fail + 1)); }
"$VP" reconstruct "$tmp/torus.ply" --dim 2 --out "$tmp/fromply" --quiet || { echo "FAIL: PLY input"; fail=$((fail + 1)); }
"$VP" sim --surface sphere --eps 0.1 --out "$tmp/s" --quiet --hausdorff 0 >/dev/null 2>&1
if [ -f "$tmp/s.vplog" ]; then
  "$VP" reconstruct "$tmp/s.vplog" --dim 2 --out "$tmp/fromlog" --json --quiet >"$tmp/log.json" 2>&1
  grep -q '"manifold":true' "$tmp/log.json" && grep -q '"euler":2,' "$tmp/log.json" ||
    { echo "FAIL: session log input: $(cat "$tmp/log.json")"; fail=$((fail + 1)); }
else
  echo "FAIL: sim wrote no log"; fail=$((fail + 1))
fi
# degenerate input: a Clifford torus on a regular 40 x 40 grid (every cell's vertices cocircular),
# every point given twice: fixed deterministically to a closed manifold, Euler 0
"$PY" -c "
import math
s = 1 / math.sqrt(2)
with open('$tmp/grid.txt', 'w') as f:
    for i in range(40):
        for j in range(40):
            a, b = 2 * math.pi * i / 40, 2 * math.pi * j / 40
            line = '%.17g %.17g %.17g %.17g\\n' % (s * math.cos(a), s * math.sin(a), s * math.cos(b), s * math.sin(b))
            f.write(line + line)
"
"$VP" reconstruct "$tmp/grid.txt" --dim 2 --out "$tmp/grid" --json --quiet >"$tmp/grid.json" 2>&1
grep -q '"inconsistent":0,"euler":0,"manifold":true' "$tmp/grid.json" && grep -q '"points":3200' "$tmp/grid.json" ||
  { echo "FAIL: degenerate grid with duplicates: $(cat "$tmp/grid.json")"; fail=$((fail + 1)); }
# errors: usage 2, bad input 1 with a message naming the line
"$VP" reconstruct --help >/dev/null || { echo "FAIL: --help"; fail=$((fail + 1)); }
"$VP" reconstruct "$tmp/t.txt" --out "$tmp/x" >/dev/null 2>&1; [ $? = 2 ] || { echo "FAIL: missing --dim not usage"; fail=$((fail + 1)); }
"$VP" reconstruct --generate nonesuch --n 5 --out "$tmp/x" >/dev/null 2>&1; [ $? = 2 ] || { echo "FAIL: unknown manifold not usage"; fail=$((fail + 1)); }
printf '0 0 0\n1 0 0\n0 1 x\n' >"$tmp/bad.txt"
"$VP" reconstruct "$tmp/bad.txt" --dim 2 --out "$tmp/x" >/dev/null 2>"$tmp/bad.err"; rc=$?
[ $rc = 1 ] && grep -q "line 3" "$tmp/bad.err" || { echo "FAIL: bad text not refused by line ($rc)"; fail=$((fail + 1)); }
printf '0 0 0\n1 0\n' >"$tmp/bad2.txt"
"$VP" reconstruct "$tmp/bad2.txt" --dim 2 --out "$tmp/x" >/dev/null 2>"$tmp/bad2.err"; rc=$?
[ $rc = 1 ] && grep -q "line 2" "$tmp/bad2.err" || { echo "FAIL: ragged text not refused ($rc)"; fail=$((fail + 1)); }
if [ $fail = 0 ]; then
  echo "t_reconstruct: $runs samples (sphere, torus, genus2, clifford, klein, curve R^10, so3 5000): 0 inconsistent, closed manifold, right Euler and orientability; Open3D: watertight, oriented outward; degenerate grid with duplicates; text/PLY/log inputs; errors refused"
  exit 0
fi
echo "t_reconstruct: $fail failure(s)"
exit 1
