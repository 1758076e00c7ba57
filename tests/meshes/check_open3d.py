#!/usr/bin/python3
"""Validates the regression meshes with an independent reader: Debian's Open3D.

usage: /usr/bin/python3 tests/meshes/check_open3d.py [FILE.off ...]   (default: every *.off here)

Open3D's OFF reader does not skip '#' comment lines, so the comments are stripped into a
temporary copy first; its OFF reader parses coordinates as float32, so the volume and the
zero-area faces are computed here from the file's exact doubles, and Open3D gives the
topology. For each mesh: is_watertight (edge- and vertex-manifold, no boundary, no
self-intersection), is_orientable, and the signed volume > 0 (faces outward: Open3D's
get_volume needs a watertight mesh, so the volume is summed here from the triangles, which
works for every closed mesh). The meshes meant to break a rule say so in EXPECT and must break
exactly that rule; the zero-area faces (three exactly collinear corners) are counted. Exit status 0 when every mesh is as expected.
"""
import glob
import os
import sys
import tempfile
from fractions import Fraction

import numpy as np
import open3d as o3d

HERE = os.path.dirname(os.path.abspath(__file__))
# name -> what Open3D must report; anything not listed must be watertight, orientable, volume > 0
EXPECT = {
    # two cubes on one edge: that edge is in 4 triangles
    # (Open3D's is_orientable also says no there: it walks edges with two triangles only)
    "bowtie.off": dict(edge_manifold=False, vertex_manifold=True, watertight=False, orientable=False),
    # two cubes on one vertex: the vertex's link is two cycles
    "bowtie-vertex.off": dict(edge_manifold=True, vertex_manifold=False, watertight=False),
    # ../shared/meshes/ellipe0.003.off: faces oriented inward (its README says so)
    "ellipe0.003.off": dict(volume_sign=-1),
}


def collinear(p, q, r):
    """Exactly (rational arithmetic on the doubles): three collinear corners, a zero-area face."""
    P, Q, R = [[Fraction(float(x)) for x in v] for v in (p, q, r)]
    u = [Q[k] - P[k] for k in range(3)]
    w = [R[k] - P[k] for k in range(3)]
    return u[1] * w[2] == u[2] * w[1] and u[2] * w[0] == u[0] * w[2] and u[0] * w[1] == u[1] * w[0]


def strip_comments(path):
    """A copy without '#' lines, and the vertices and triangles parsed here as exact doubles."""
    with open(path) as f:
        lines = [l for l in f if not l.lstrip().startswith("#")]
    fd, tmp = tempfile.mkstemp(suffix=".off")
    with os.fdopen(fd, "w") as f:
        f.writelines(lines)
    rows = [l.split() for l in lines if l.split()]   # one vertex or face a line; extra values (colours) ignored
    assert rows[0][0] in ("OFF", "COFF", "NOFF", "CNOFF"), path
    head = rows[0][1:] or rows.pop(1)
    rows = rows[1:]
    nv, nf = int(head[0]), int(head[1])
    V = [tuple(float(x) for x in r[:3]) for r in rows[:nv]]
    F = []
    for r in rows[nv:nv + nf]:
        n = int(r[0])
        idx = [int(x) for x in r[1:1 + n]]
        F += [(idx[0], idx[j - 1], idx[j]) for j in range(2, n)]
    return tmp, np.array(V, dtype=np.float64), np.array(F, dtype=np.int64)


def check(path):
    name = os.path.basename(path)
    tmp, V, F = strip_comments(path)
    try:
        m = o3d.io.read_triangle_mesh(tmp)
    finally:
        os.unlink(tmp)
    if len(m.triangles) != len(F) or len(m.vertices) != len(V):
        return False, "%s: Open3D read %d vertices, %d triangles (expected %d, %d)" % (
            name, len(m.vertices), len(m.triangles), len(V), len(F))
    if (np.asarray(m.triangles) != F).any():
        return False, "%s: Open3D read other triangles" % name
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    vol = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)
    zero = sum(1 for t in F if collinear(V[t[0]], V[t[1]], V[t[2]]))
    got = dict(edge_manifold=m.is_edge_manifold(allow_boundary_edges=False),
               vertex_manifold=m.is_vertex_manifold(), self_intersecting=m.is_self_intersecting(),
               watertight=m.is_watertight(), orientable=m.is_orientable())
    want = dict(edge_manifold=True, vertex_manifold=True, self_intersecting=False, watertight=True, orientable=True)
    want.update(EXPECT.get(name, {}))
    sign = want.pop("volume_sign", 1)
    bad = [k for k in want if got[k] != want[k]]
    ok = not bad and vol * sign > 0
    flags = " ".join("%s=%s" % (k, "yes" if v else "no") for k, v in got.items())
    msg = "%-22s %5d v %5d t  volume %.6g  zero-area %d  %s%s" % (
        name, len(V), len(F), vol, zero, flags,
        "" if ok else "  UNEXPECTED: " + (", ".join(bad) if bad else "volume sign"))
    return ok, msg


def main():
    files = sys.argv[1:] or sorted(glob.glob(os.path.join(HERE, "*.off")))
    nbad = 0
    for p in files:
        ok, msg = check(p)
        print(msg)
        nbad += not ok
    print("%d mesh(es), %d as expected, %d not" % (len(files), len(files) - nbad, nbad))
    return 1 if nbad else 0


if __name__ == "__main__":
    sys.exit(main())
