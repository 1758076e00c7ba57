#!/bin/sh
# PLY files written by vp_meshio, read back by an independent reader: Open3D from Debian's
# python3-open3d (always /usr/bin/python3, not a python3 found on PATH). Binary and ASCII.
# Skips (77) only when /usr/bin/python3 cannot import open3d.
BUILD=${BUILD:-build}
. tests/need_python.sh
need_python open3d python3-open3d
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
"$BUILD/tests/mesh/test_meshio" --write-ply "$tmp/torus.ply" || { echo "FAIL: test_meshio --write-ply"; exit 1; }
"$PY" - "$tmp/torus.ply" "$tmp/torus.ply.ascii.ply" <<'PYEOF'
import math, sys
import numpy as np
import open3d as o3d
nu, nv, R, r = 12, 8, 1.0, 0.3
V = []
for i in range(nu):
    for j in range(nv):
        th, ph = 2 * math.pi * i / nu, 2 * math.pi * j / nv
        V.append(((R + r * math.cos(ph)) * math.cos(th), (R + r * math.cos(ph)) * math.sin(th), r * math.sin(ph)))
F = []
for i in range(nu):
    for j in range(nv):
        a, b = i * nv + j, ((i + 1) % nu) * nv + j
        c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
        F += [(a, b, c), (a, c, d)]
V, F = np.array(V), np.array(F)
for path in sys.argv[1:]:
    m = o3d.io.read_triangle_mesh(path)
    mv, mf = np.asarray(m.vertices), np.asarray(m.triangles)
    assert mv.shape == V.shape, (path, mv.shape)
    assert mf.shape == F.shape, (path, mf.shape)
    err = float(np.abs(mv - V).max())
    assert err < 1e-12, (path, err)
    assert (mf == F).all(), path
    assert m.is_edge_manifold() and m.is_vertex_manifold() and m.is_watertight(), path
    print("%s: %d vertices, %d triangles, max coordinate error %.3g, watertight" % (path.split("/")[-1], len(mv), len(mf), err))
print("t_ply_open3d: open3d %s read both files correctly" % o3d.__version__)
PYEOF
