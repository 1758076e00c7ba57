#!/usr/bin/python3
"""Writes the regression meshes of issue 12 (tests/t_safety.sh) into this folder.

usage: /usr/bin/python3 tests/meshes/make_meshes.py [DIR [APEX]]
With APEX (degrees) only the knife-edge wedge of that apex angle is written, as DIR/wedgeAPEX.off
(the 20 and 15 degree wedges of the README: APEX 20 and 15; 26 writes the committed wedge26.off).

Closed triangle meshes, faces oriented outward (counter-clockwise seen from outside), OFF with a
'#' comment header (voroprobe's reader skips '#' to the end of the line). Coordinates are
written with repr() (shortest exact form: they read back as the same doubles). Plain Python, no
numpy: the committed files are the reference, this script says how they were made.
Validated by tests/meshes/check_open3d.py.
"""
import math
import os
import sys
from fractions import Fraction

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
APEX = sys.argv[2] if len(sys.argv) > 2 else None


def num(x):
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def write(name, comment, V, F):
    check_closed(name, V, F)
    vol = signed_volume(V, F)
    assert vol > 0, (name, vol)
    with open(os.path.join(OUT, name), "w") as f:
        f.write("OFF\n")
        for line in comment.strip().split("\n"):
            f.write("# " + line + "\n")
        f.write("# %d vertices, %d triangles, volume %.6g\n" % (len(V), len(F), vol))
        f.write("%d %d 0\n" % (len(V), len(F)))
        for v in V:
            f.write(" ".join(num(c) for c in v) + "\n")
        for t in F:
            f.write("3 %d %d %d\n" % tuple(t))


def check_closed(name, V, F):
    """Every directed edge once, its reverse once: closed and consistently oriented."""
    seen = {}
    for t in F:
        assert len(set(t)) == 3, (name, t)
        for i in range(3):
            e = (t[i], t[(i + 1) % 3])
            seen[e] = seen.get(e, 0) + 1
    for (a, b), n in seen.items():
        assert n == 1 and seen.get((b, a)) == 1, (name, a, b, n, seen.get((b, a)))


def signed_volume(V, F):
    s = Fraction(0)
    for a, b, c in F:
        A, B, C = [[Fraction(x) for x in V[i]] for i in (a, b, c)]
        s += (A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0])
              + A[2] * (B[0] * C[1] - B[1] * C[0]))
    return float(s / 6)


def box(lo, hi, V=None, F=None):
    """An axis-aligned box, 8 vertices, 12 outward triangles (appended to V, F)."""
    V = [] if V is None else V
    F = [] if F is None else F
    o = len(V)
    for z in (lo[2], hi[2]):
        for y in (lo[1], hi[1]):
            for x in (lo[0], hi[0]):
                V.append((x, y, z))
    # vertex index = o + 4*zi + 2*yi + xi
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    for a, b, c, d in quads:
        F.append((o + a, o + b, o + c))
        F.append((o + a, o + c, o + d))
    return V, F


def cube():
    V, F = box((0, 0, 0), (1, 1, 1))
    write("cube.off", "unit cube [0,1]^3 (issue 12: 12 triangles)", V, F)


def box_half():
    V, F = box((0, 0, 0), (1, 0.5, 0.25))
    write("box.off", "box 1 x 0.5 x 0.25, corner at the origin", V, F)


def tetra():
    V = [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)]
    F = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
    write("tetra.off", "regular tetrahedron, edge 2*sqrt(2), centred at the origin", V, F)


def octa():
    V = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    F = []
    for sx, x in ((1, 0), (-1, 1)):
        for sy, y in ((1, 2), (-1, 3)):
            for sz, z in ((1, 4), (-1, 5)):
                t = (x, y, z)
                F.append(t if sx * sy * sz > 0 else (x, z, y))
    write("octa.off", "regular octahedron, vertices on the axes at distance 1", V, F)


def bowtie_edge():
    # Two unit cubes sharing the edge x = 1, y = 1 (0 <= z <= 1): that edge is in 4 triangles.
    V, F = box((0, 0, 0), (1, 1, 1))
    V, F = box((1, 1, 0), (2, 2, 1), V, F)
    V, F = merge(V, F)
    vol = signed_volume(V, F)
    assert vol > 0
    edges = {}
    for t in F:
        for i in range(3):
            e = tuple(sorted((t[i], t[(i + 1) % 3])))
            edges[e] = edges.get(e, 0) + 1
    assert sorted(edges.values()).count(4) == 1, "one non-manifold edge"
    with open(os.path.join(OUT, "bowtie.off"), "w") as f:
        f.write("OFF\n# bow-tie: unit cubes [0,1]^3 and [1,2]x[1,2]x[0,1] sharing the edge x=1, y=1\n")
        f.write("# NOT a manifold: that edge is in 4 triangles (closed: no boundary edge)\n")
        f.write("# %d vertices, %d triangles, volume %.6g\n" % (len(V), len(F), vol))
        f.write("%d %d 0\n" % (len(V), len(F)))
        for v in V:
            f.write(" ".join(num(c) for c in v) + "\n")
        for t in F:
            f.write("3 %d %d %d\n" % tuple(t))


def bowtie_vertex():
    # Two unit cubes sharing the vertex (1,1,1): closed, every edge in 2 triangles, but the
    # shared vertex's link is two cycles (a pinched vertex).
    V, F = box((0, 0, 0), (1, 1, 1))
    V, F = box((1, 1, 1), (2, 2, 2), V, F)
    V, F = merge(V, F)
    vol = signed_volume(V, F)
    assert vol > 0
    check_closed("bowtie-vertex.off", V, F)
    with open(os.path.join(OUT, "bowtie-vertex.off"), "w") as f:
        f.write("OFF\n# unit cubes [0,1]^3 and [1,2]^3 sharing the vertex (1,1,1)\n")
        f.write("# every edge in 2 triangles, but NOT a manifold at the shared vertex (pinched)\n")
        f.write("# %d vertices, %d triangles, volume %.6g\n" % (len(V), len(F), vol))
        f.write("%d %d 0\n" % (len(V), len(F)))
        for v in V:
            f.write(" ".join(num(c) for c in v) + "\n")
        for t in F:
            f.write("3 %d %d %d\n" % tuple(t))


def bowtie_gap():
    # The bow-tie pulled apart: the edges x=1,y=1 and x=1.02,y=1.02 are 0.02*sqrt(2) apart.
    V, F = box((0, 0, 0), (1, 1, 1))
    V, F = box((1.02, 1.02, 0), (2.02, 2.02, 1), V, F)
    write("bowtie-gap.off", "two unit cubes whose edges nearly touch: [0,1]^3 and [1.02,2.02]x[1.02,2.02]x[0,1]\n"
          "(two components, 0.028 apart along the diagonal)", V, F)


def merge(V, F):
    idx, NV = {}, []
    remap = []
    for v in V:
        if v not in idx:
            idx[v] = len(NV)
            NV.append(v)
        remap.append(idx[v])
    return NV, [tuple(remap[i] for i in t) for t in F]


def cylinder(n=32, r=0.5, h=1.0):
    V = []
    for k in range(n):
        a = 2 * math.pi * k / n
        V.append((r * math.cos(a), r * math.sin(a), 0.0))
    for k in range(n):
        a = 2 * math.pi * k / n
        V.append((r * math.cos(a), r * math.sin(a), h))
    cb, ct = 2 * n, 2 * n + 1
    V += [(0.0, 0.0, 0.0), (0.0, 0.0, h)]
    F = []
    for k in range(n):
        k1 = (k + 1) % n
        F.append((k, k1, n + k1))
        F.append((k, n + k1, n + k))
        F.append((cb, k1, k))
        F.append((ct, n + k, n + k1))
    write("cylinder32.off", "cylinder, 32 sides, radius 0.5, height 1 (z from 0 to 1), caps fanned from their centres", V, F)


def cone(n=32, r=0.5, h=1.0):
    V = []
    for k in range(n):
        a = 2 * math.pi * k / n
        V.append((r * math.cos(a), r * math.sin(a), 0.0))
    apex, cb = n, n + 1
    V += [(0.0, 0.0, h), (0.0, 0.0, 0.0)]
    F = []
    for k in range(n):
        k1 = (k + 1) % n
        F.append((k, k1, apex))
        F.append((cb, k1, k))
    write("cone32.off", "cone, 32 sides, base radius 0.5 at z = 0, apex (0,0,1), base fanned from its centre", V, F)


def icosphere(level):
    p = (1 + math.sqrt(5)) / 2
    V = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p), (0, -1, -p), (0, 1, -p),
         (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    V = [tuple(c / math.sqrt(x * x + y * y + z * z) for c in (x, y, z)) for x, y, z in V]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        mid = {}

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                x, y, z = [(V[a][k] + V[b][k]) / 2 for k in range(3)]
                n = math.sqrt(x * x + y * y + z * z)
                mid[key] = len(V)
                V.append((x / n, y / n, z / n))
            return mid[key]
        NF = []
        for a, b, c in F:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            NF += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = NF
    return V, F


def exact_midpoint(a, b):
    """The midpoint of a and b if it is exactly a double triple (then collinear exactly)."""
    m = []
    for k in range(3):
        q = (Fraction(a[k]) + Fraction(b[k])) / 2
        if Fraction(float(q)) != q:
            return None
        m.append(float(q))
    return tuple(m)


def sphere_degenerate():
    V, F = icosphere(2)
    assert len(V) == 162 and len(F) == 320
    write("icosphere2.off", "icosphere level 2 (icosahedron subdivided twice, on the unit sphere): the clean twin of\n"
          "icosphere2-degen.off", V, F)
    # Two zero-area faces: a face (a,b,c) is split at a point m exactly on its edge ab (an exact
    # midpoint: three collinear points) into (a,m,c) and (m,b,c); the zero-area face (m,a,b)
    # closes the mesh against the neighbour (b,a,d), which keeps the edge ab.
    used, done = set(), 0
    for fi in range(len(F)):
        if done == 2:
            break
        a, b, c = F[fi]
        if used & {a, b, c}:
            continue
        for (p, q, r) in ((a, b, c), (b, c, a), (c, a, b)):
            mpt = exact_midpoint(V[p], V[q])
            if mpt is None:
                continue
            # the neighbour across p-q must not be touched already
            nb = [t for t in F if (q, p) in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))]
            assert len(nb) == 1
            if used & set(nb[0]):
                continue
            m = len(V)
            V.append(mpt)
            F[fi] = (p, m, r)
            F.append((m, q, r))
            F.append((m, p, q))
            used |= {p, q, r} | set(nb[0])
            P, M, Q = [[Fraction(x) for x in V[i]] for i in (p, m, q)]
            u = [M[k] - P[k] for k in range(3)]
            w = [Q[k] - P[k] for k in range(3)]
            cross = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
            assert cross == (0, 0, 0), "exactly collinear"
            done += 1
            break
    assert done == 2, done
    write("icosphere2-degen.off", "icosphere level 2 (162 vertices) with two zero-area faces: two faces split at the\n"
          "exact midpoint m of an edge ab, the face (m,a,b) has three collinear corners (area 0)", V, F)


def wedge(apex="26"):
    # a knife edge: the triangle (0,0), (1,h), (1,-h) with h = tan(apex / 2) (26 degrees: dino's
    # sharpest fold), extruded from z = 0 to 0.5; faces turned outward by the centroid test below
    h = math.tan(math.radians(float(apex) / 2.0))
    V = [(0, 0, 0), (1, h, 0), (1, -h, 0), (0, 0, 0.5), (1, h, 0.5), (1, -h, 0.5)]
    T = [(0, 1, 2), (3, 5, 4), (0, 3, 4), (0, 4, 1), (0, 2, 5), (0, 5, 3), (1, 4, 5), (1, 5, 2)]
    c = [sum(v[k] for v in V) / len(V) for k in range(3)]
    F = []
    for a, b, d in T:
        u = [V[b][k] - V[a][k] for k in range(3)]
        w = [V[d][k] - V[a][k] for k in range(3)]
        n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        F.append((a, b, d) if sum(n[k] * (V[a][k] - c[k]) for k in range(3)) > 0 else (a, d, b))
    write("wedge%s.off" % apex, "a wedge with a knife edge: apex angle %s degrees along the z axis, 1 deep, 0.5 high" % apex,
          V, F)


if APEX is not None:
    os.makedirs(OUT, exist_ok=True)
    wedge(APEX)
    sys.exit(0)
cube()
box_half()
tetra()
octa()
bowtie_edge()
bowtie_vertex()
bowtie_gap()
cylinder()
cone()
sphere_degenerate()
wedge()
