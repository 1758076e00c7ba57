#!/bin/sh
# A mug-like object (tools/make_mug.py: a cup with a deep cavity and a handle) as a scanner's
# user would bring one: the generated mesh is read back by an independent reader (Open3D) and
# must be closed, edge- and vertex-manifold, oriented outward (positive signed volume) and of
# genus 1 (Euler characteristic 0); the reader must refuse the same mesh with one triangle
# taken out (open) and turned inside out (negative volume). Then a point-probe scan of it
# (`sim`, eps 2% of the diagonal) closes with genus 1, 0 moves through it, its log verified, and
# its mesh, read by Open3D, is a closed genus-1 surface. Skips (77) only when open3d cannot be
# imported. With a body of 1 mm, tubes and the hidden facets found from aside it closes too
# (below); with the machine's head, boards/sim.ini, the mug stays open (README, the machine's
# resolution).
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
. tests/need_python.sh
need_python open3d python3-open3d
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
bad() { echo "FAIL: $*"; exit 1; }
"$PY" tools/make_mug.py "$tmp/mug.off" --step 2.5 >/dev/null || bad "tools/make_mug.py"
"$PY" - "$tmp" <<'PYEOF' || exit 1
import sys
import numpy as np
import open3d as o3d
d = sys.argv[1]

def judge(V, T):
    """(closed, manifold, genus, signed volume) by Open3D's manifold tests and its edge list."""
    m = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(V), o3d.utility.Vector3iVector(T))
    closed = len(m.get_non_manifold_edges(allow_boundary_edges=False)) == 0
    manifold = m.is_edge_manifold(allow_boundary_edges=True) and m.is_vertex_manifold() and m.is_orientable()
    e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    ne = len(np.unique(e, axis=0))
    chi = len(V) - ne + len(T)
    vol = np.einsum("ij,ij->i", V[T[:, 0]], np.cross(V[T[:, 1]], V[T[:, 2]])).sum() / 6.0
    return closed, manifold, (2 - chi) / 2.0, vol

m = o3d.io.read_triangle_mesh(d + "/mug.off")
V, T = np.asarray(m.vertices), np.asarray(m.triangles)
closed, manifold, g, vol = judge(V, T)
if not (closed and manifold and g == 1 and vol > 0):
    sys.exit("FAIL: the mug: closed %s, manifold %s, genus %g, volume %g" % (closed, manifold, g, vol))
# the checker must fail: one triangle out, and the mesh inside out
c2 = judge(V, T[1:])
c3 = judge(V, T[:, ::-1].copy())
if c2[0] or c3[3] > 0:
    sys.exit("FAIL: the checker passed a mug with a hole (%s) or turned inside out (volume %g)" % (c2[0], c3[3]))
print("mug: %d vertices, %d triangles, genus 1, volume %.0f mm^3 (a triangle out: open; inside out: %.0f)" % (len(V), len(T), vol, c3[3]))
PYEOF
"$VP" sim --surface "off:$tmp/mug.off" --eps-rel 0.02 --out "$tmp/s" --quiet --json >"$tmp/s.json" 2>/dev/null
grep -q '"status":"closed"' "$tmp/s.json" && grep -q '"genus":1' "$tmp/s.json" && grep -q '"collisions":0' "$tmp/s.json" ||
  bad "point-probe scan of the mug: $(cut -c1-300 "$tmp/s.json")"
"$VP" log verify "$tmp/s.vplog" >"$tmp/v.txt" 2>&1 || bad "log verify: $(tail -1 "$tmp/v.txt")"
"$PY" - "$tmp/s.off" <<'PYEOF' || exit 1
import sys
import numpy as np
import open3d as o3d
m = o3d.io.read_triangle_mesh(sys.argv[1])
V, T = np.asarray(m.vertices), np.asarray(m.triangles)
e = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1), axis=0)
chi = len(V) - len(e) + len(T)
closed = len(m.get_non_manifold_edges(allow_boundary_edges=False)) == 0 and m.is_vertex_manifold()
if not closed or chi != 0:
    sys.exit("FAIL: the scanned mug read by Open3D: closed %s, Euler characteristic %d" % (closed, chi))
PYEOF
# With a body of 1 mm (sim --clearance 1) and tubes (--min-feature 2): the cavity and the outside
# close through tubes, and the handle's hole (whose corners are narrower than the tube the body
# needs) through the facets found from aside (core/planner/aim.c): the mesh Open3D reads is closed,
# manifold, Euler characteristic 0. The open-edge checker must find an open edge far from the
# handle once a triangle of the cavity's floor is taken out. 0 collisions (host-sim), the log
# verified. (At eps 0.04 4 edges at the handle's hole stay open since tubes are proven with a
# margin the log check can see: README, tubes.)
"$VP" sim --surface "off:$tmp/mug.off" --eps-rel 0.035 --clearance 1 --min-feature 2 --out "$tmp/b" --quiet --json \
  >"$tmp/b.json" 2>/dev/null
grep -q '"collisions":0' "$tmp/b.json" || bad "the mug with a body: $(cut -c1-300 "$tmp/b.json")"
"$VP" log verify "$tmp/b.vplog" >"$tmp/bv.txt" 2>&1 || bad "log verify, the mug with a body: $(tail -1 "$tmp/bv.txt")"
bo=$("$PY" - "$tmp/b.off" <<'PYEOF'
import sys
import numpy as np
import open3d as o3d
m = o3d.io.read_triangle_mesh(sys.argv[1])
V, T = np.asarray(m.vertices), np.asarray(m.triangles)

def open_far(T):
    """open edges (on fewer or more than two triangles), and how many lie farther than 19 mm from
    the handle ring's core circle (centre x 44, z 50, radius 22, in the plane y = 0)"""
    e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    u, c = np.unique(e, axis=0, return_counts=True)
    mid = 0.5 * (V[u[c != 2, 0]] + V[u[c != 2, 1]])
    q = np.hypot(mid[:, 0] - 44.0, mid[:, 2] - 50.0) - 22.0
    return len(mid), int(np.sum(np.hypot(q, mid[:, 1]) > 19.0))

n, far = open_far(T)
chi = len(V) - len(np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1), axis=0)) + len(T)
if n or not m.is_vertex_manifold() or chi != 0:
    sys.exit("FAIL: the mug with a body: %d open edges (%d away from the handle's hole), Euler characteristic %d"
             % (n, far, chi))
# the checker must fail: a triangle of the cavity's floor (z near 10, within 25 mm of the axis) out
c = V[T].mean(axis=1)
floor = np.where((np.abs(c[:, 2] - 10.0) < 2.0) & (np.hypot(c[:, 0], c[:, 1]) < 25.0))[0]
if len(floor) == 0 or open_far(np.delete(T, floor[0], axis=0))[1] == 0:
    sys.exit("FAIL: the open-edge checker missed a hole in the cavity's floor")
print(n)
PYEOF
) || bad "$bo"
v=$(sed 's/.*"vertices":\([0-9]*\).*/\1/' "$tmp/s.json"); p=$(sed 's/.*"probes":\([0-9]*\).*/\1/' "$tmp/s.json")
h=$(sed 's/.*"hausdorff":\([0-9.e-]*\).*/\1/' "$tmp/s.json")
echo "t_mug: the mug closed, genus 1 (Open3D), scanned by point probes: $v vertices, $p probes, within $h mm, 0 moves through, log verified; with a body of 1 mm, tubes and facets found from aside closed too (genus 1, $bo open edges), 0 collisions, log verified"
