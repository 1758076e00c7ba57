#!/bin/sh
# `voroprobe mesh LOG` output read back by an independent reader, Open3D (Debian's
# python3-open3d, always /usr/bin/python3): the mesh (binary and ASCII PLY) has the vertex and
# face counts and the coordinates of the OFF file written alongside, and the probed-point
# cloud (--points) has one point per logged hit, at origin + dist * dir, with unit normals
# pointing back to the probe origin. Skips (77) only when open3d cannot be imported.
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
. tests/need_python.sh
need_python open3d python3-open3d
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
"$VP" sim --surface sphere@2.5,0,0+torus --eps-rel 0.04 --noise 0.0005 --dropout 0.05 --out "$tmp/s" \
  --quiet --hausdorff 0 --sync close >/dev/null || { echo "FAIL: sim"; exit 1; }
size=$(wc -c <"$tmp/s.vplog")
head -c $((size / 2)) "$tmp/s.vplog" >"$tmp/half.vplog"
for log in s half; do
  "$VP" mesh "$tmp/$log.vplog" --out "$tmp/$log" --off --points >/dev/null 2>&1 || { echo "FAIL: mesh $log"; exit 1; }
  "$VP" mesh "$tmp/$log.vplog" --out "$tmp/$log.ascii" --ascii --points >/dev/null 2>&1 || { echo "FAIL: mesh --ascii $log"; exit 1; }
  "$VP" log dump "$tmp/$log.vplog" --csv >"$tmp/$log.csv" 2>/dev/null
done
"$PY" - "$tmp" <<'PYEOF'
import csv, sys
import numpy as np
import open3d as o3d
d = sys.argv[1]
def read_off(path):
    with open(path) as f:
        words = f.read().split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    v = np.array([float(x) for x in words[4:4 + 3 * nv]]).reshape(nv, 3)
    f = np.array([int(x) for x in words[4 + 3 * nv:]]).reshape(nf, 4)
    assert (f[:, 0] == 3).all()
    return v, f[:, 1:]
for log in ("s", "half"):
    V, F = read_off("%s/%s.off" % (d, log))
    for ply in ("%s/%s.ply" % (d, log), "%s/%s.ascii.ply" % (d, log)):
        m = o3d.io.read_triangle_mesh(ply)
        mv, mf = np.asarray(m.vertices), np.asarray(m.triangles)
        assert mv.shape == V.shape, (ply, mv.shape, V.shape)
        assert mf.shape == F.shape, (ply, mf.shape, F.shape)
        assert np.array_equal(mv, V), ply          # exact: 17 digits in OFF, doubles in PLY
        assert (mf == F).all(), ply
    closed = m.is_watertight()
    assert closed == (log == "s"), (log, closed)
    # the probed points: one per logged hit
    hits = []
    with open("%s/%s.csv" % (d, log)) as f:
        for r in csv.DictReader(f):
            if r["type"] == "probe" and r["hit"] == "1":
                o = np.array([float(r["origin_x"]), float(r["origin_y"]), float(r["origin_z"])])
                u = np.array([float(r["dir_x"]), float(r["dir_y"]), float(r["dir_z"])])
                p = np.array([float(r["point_x"]), float(r["point_y"]), float(r["point_z"])])
                hits.append((o, u, p))
    for ply in ("%s/%s.points.ply" % (d, log), "%s/%s.ascii.points.ply" % (d, log)):
        pc = o3d.io.read_point_cloud(ply)
        P, N = np.asarray(pc.points), np.asarray(pc.normals)
        assert len(P) == len(hits) and N.shape == P.shape, (ply, len(P), len(hits))
        for (o, u, p), q, n in zip(hits, P, N):
            assert np.abs(q - p).max() < 1e-12, (ply, q, p)
            assert abs(np.linalg.norm(n) - 1) < 1e-12
            assert np.dot(n, o - q) > 0, "normal does not point to the probe origin"
    print("%s: mesh %d vertices, %d faces (%s); %d probed points with normals towards the origins: "
          "binary and ASCII read by open3d %s" % (log, len(V), len(F), "closed" if closed else "open: holes",
                                                  len(hits), o3d.__version__))
PYEOF
