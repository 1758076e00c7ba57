#!/usr/bin/env python3
"""Writes a mug-like test object as a closed triangle mesh (OFF): a cup 80 mm across and 95 mm
tall with a cavity 66 mm across and 85 mm deep, and a handle (a ring of 7 mm tube) on its side:
genus 1, a deep concavity, a hole a head can see through only from the side.

The surface is the zero set of a distance-like function (smooth-union of the cup's shell and the
handle), meshed by marching tetrahedra on a grid (six tetrahedra per cube sharing its diagonal,
so neighbouring cubes agree on every face): vertices on grid edges are shared by key, so the mesh
is closed; each triangle faces the positive side (outside).

usage: make_mug.py OUT.off [--step MM]"""
import argparse
import numpy as np


def smooth_max(a, b, k):
    h = np.clip(0.5 - 0.5 * (b - a) / k, 0.0, 1.0)
    return b + (a - b) * h + k * h * (1.0 - h)


def smooth_min(a, b, k):
    return -smooth_max(-a, -b, k)


def mug(x, y, z):
    # the cup: a rounded solid cylinder r 40, z 0..95, minus the cavity r 33, z 10..(open)
    r = np.sqrt(x * x + y * y)
    outer = smooth_max(smooth_max(r - 40.0, -z, 3.0), z - 95.0, 3.0)
    cavity = smooth_max(r - 33.0, 10.0 - z, 3.0)
    cup = smooth_max(outer, -cavity, 2.0)
    # the handle: a ring in the x-z plane centred at x = 44, z = 50, radius 22, tube 7
    hx, hz = x - 44.0, z - 50.0
    q = np.sqrt(hx * hx + hz * hz) - 22.0
    ring = np.sqrt(q * q + y * y) - 7.0
    ring = smooth_max(ring, 38.0 - x, 2.0)          # only the part outside the cup
    return smooth_min(cup, ring, 3.0)


# the six tetrahedra of a cube (corner bits x=1, y=2, z=4) sharing the diagonal 0-7
TETS = [(0, 1, 3, 7), (0, 3, 2, 7), (0, 2, 6, 7), (0, 6, 4, 7), (0, 4, 5, 7), (0, 5, 1, 7)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--step", type=float, default=2.0)
    a = ap.parse_args()
    h = a.step
    xs = np.arange(-52.0, 78.0 + h, h) + 0.1234 * h
    ys = np.arange(-52.0, 52.0 + h, h) + 0.0567 * h
    zs = np.arange(-12.0, 107.0 + h, h) + 0.0311 * h
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    F = mug(X, Y, Z)
    F[np.abs(F) < 1e-9] = 1e-9
    nx, ny, nz = F.shape
    P = np.stack([X, Y, Z], axis=-1).reshape(-1, 3)
    f = F.reshape(-1)
    idx = np.arange(nx * ny * nz).reshape(nx, ny, nz)
    base = idx[:-1, :-1, :-1].reshape(-1)
    off = [0, ny * nz, nz, ny * nz + nz, 1, ny * nz + 1, nz + 1, ny * nz + nz + 1]
    # corner c: bit0 -> +x (ny*nz), bit1 -> +y (nz), bit2 -> +z (1)
    corner = lambda c: base + (ny * nz if c & 1 else 0) + (nz if c & 2 else 0) + (1 if c & 4 else 0)
    verts, vid, tris = [], {}, []

    def vert(p, q):
        key = (min(p, q), max(p, q))
        v = vid.get(key)
        if v is None:
            t = f[p] / (f[p] - f[q])
            verts.append(P[p] + t * (P[q] - P[p]))
            v = vid[key] = len(verts) - 1
        return v

    for tet in TETS:
        C = np.stack([corner(c) for c in tet], axis=1)       # (ncubes, 4) point ids
        neg = f[C] < 0
        nneg = neg.sum(axis=1)
        for row in np.nonzero((nneg > 0) & (nneg < 4))[0]:
            ids = C[row]
            ins = [i for i in ids if f[i] < 0]
            outs = [i for i in ids if f[i] >= 0]
            if len(ins) == 1 or len(outs) == 1:
                lone, rest = (ins[0], outs) if len(ins) == 1 else (outs[0], ins)
                poly = [vert(lone, r) for r in rest]
            else:
                a0, a1 = ins
                b0, b1 = outs
                poly = [vert(a0, b0), vert(a0, b1), vert(a1, b1), vert(a1, b0)]
            # face the outside: the normal along (mean of outside corners - mean of inside ones)
            dirn = P[outs].mean(axis=0) - P[ins].mean(axis=0)
            for k in range(1, len(poly) - 1):
                t = [poly[0], poly[k], poly[k + 1]]
                n = np.cross(verts[t[1]] - verts[t[0]], verts[t[2]] - verts[t[0]])
                if np.dot(n, dirn) < 0:
                    t = [t[0], t[2], t[1]]
                tris.append(t)
    V = np.array(verts)
    with open(a.out, "w") as fh:
        fh.write("OFF\n%d %d 0\n" % (len(V), len(tris)))
        for p in V:
            fh.write("%.17g %.17g %.17g\n" % tuple(p))
        for t in tris:
            fh.write("3 %d %d %d\n" % tuple(t))
    print("%s: %d vertices, %d triangles (grid step %g mm)" % (a.out, len(V), len(tris), h))


if __name__ == "__main__":
    main()
