"""Paper 001's invariants after every tracking round, checked against the object's own formula.

usage: track_invariants.py OUT JSON EPS MOTION [selftest]

OUT.roundK.ply are the rounds' meshes (read with Open3D), JSON the session's --json line (each
round's t0, t1), MOTION the --motion spec of the unit sphere: translate:VX,VY,VZ or
bump:X,Y,Z,RADIUS,HEIGHT_PER_S (the bump written from host-sim's documented model, not its code:
the surface point p nearest X moves along the normal n at p by h(t) (1 - |x-p|^2/R^2)^3 inside
radius R; h = rate * t, held once its gradient reaches 1/2).  For round K, with Sigma = the object
at t1 and v the object's speed bound:

 (i)   sampling: every point of Sigma within eps + v (t1 - t0) of a vertex (the surface Delaunay
       balls have radius at most eps; the samples were measured during the round)
 (ii)  spacing: a vertex new in this round (moved or inserted) is at least R/3 from every other,
       R the largest circumradius of the round's triangles
 (iii) closed: an edge-manifold, vertex-manifold, orientable, watertight mesh (Open3D), Euler
       characteristic 2
 (iv)  the nearest-point map of the mesh onto Sigma is one-to-one: the mesh within the distance
       of (i) of Sigma, each triangle's normal within 90 degrees of Sigma's at the point nearest
       its centroid, and the triangles' areas projected onto Sigma's normals add up to Sigma's
       area (degree 1: a fold or a double cover adds or takes away area)

selftest: the checker's must-fail cases (a round's mesh moved by 2 eps; one vertex pushed inside
through the surface) are reported and exit 1 if the checker passes them.
"""
import json
import sys

import numpy as np
import open3d as o3d


def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    V = [np.array(p, float) / np.linalg.norm(p) for p in v]
    F = f
    for _ in range(level):
        mid = {}
        nf = []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = V[a] + V[b]
                V.append(p / np.linalg.norm(p))
                mid[k] = len(V) - 1
            return mid[k]
        for a, b, c in F:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = nf
    return np.array(V), np.array(F)


class Object:
    """the unit sphere under one motion term, at time t"""

    def __init__(self, spec):
        kind, args = spec.split(":")
        a = [float(x) for x in args.split(",")]
        self.kind = kind
        if kind == "translate":
            self.vel = np.array(a[:3])
            self.speed = float(np.linalg.norm(self.vel))
        elif kind == "bump":
            self.p = np.array(a[:3]) / np.linalg.norm(a[:3])
            self.R, self.rate = a[3], a[4]
            dphi = 6.0 / 5 ** 0.5 * 0.64  # max |d/drho (1 - rho^2)^3|
            self.tcap = 0.5 * self.R / (dphi * abs(self.rate))
            self.speed = abs(self.rate)
        else:
            raise SystemExit("track_invariants: motion %s not known here" % spec)

    def surface(self, t, V):
        if self.kind == "translate":
            return V + self.vel * t
        h = self.rate * min(t, self.tcap)
        r2 = np.sum((V - self.p) ** 2, axis=1) / self.R ** 2
        g = np.where(r2 < 1, h * np.clip(1 - r2, 0, None) ** 3, 0.0)
        return V + g[:, None] * self.p[None, :]


def nearest(P, Q, chunk=256):
    """index of the nearest row of Q for each row of P, and the distance"""
    idx = np.empty(len(P), int)
    dist = np.empty(len(P))
    q2 = np.sum(Q * Q, axis=1)
    for i in range(0, len(P), chunk):
        p = P[i:i + chunk]
        d2 = np.sum(p * p, axis=1)[:, None] - 2 * p @ Q.T + q2[None, :]
        j = np.argmin(d2, axis=1)
        idx[i:i + chunk] = j
        dist[i:i + chunk] = np.sqrt(np.maximum(d2[np.arange(len(p)), j], 0))
    return idx, dist


def check(V, F, sigma, eps, slack, prev=None):
    """the four invariants of a mesh (V, F) against sigma = (points, face centroids, face normals,
    area); a list of failures (empty: all hold) and the figures"""
    bad = []
    SV, SC, SN, area = sigma
    mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(V), o3d.utility.Vector3iVector(F))
    if not (mesh.is_edge_manifold(allow_boundary_edges=False) and mesh.is_vertex_manifold() and mesh.is_orientable()
            and mesh.is_watertight()):
        bad.append("(iii) not a closed 2-manifold")
    E = set()
    for a, b, c in F:
        for x, y in ((a, b), (b, c), (c, a)):
            E.add((min(x, y), max(x, y)))
    chi = len(V) - len(E) + len(F)
    if chi != 2:
        bad.append("(iii) Euler characteristic %d" % chi)
    # (i) sampling
    _, dv = nearest(SV, V)
    if dv.max() > eps + slack:
        bad.append("(i) a point of the object %.4g from every vertex (bound %.4g)" % (dv.max(), eps + slack))
    # (ii) spacing of the round's new vertices
    A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    a, b, c = np.linalg.norm(B - C, axis=1), np.linalg.norm(C - A, axis=1), np.linalg.norm(A - B, axis=1)
    cr = np.cross(B - A, C - A)
    twice = np.linalg.norm(cr, axis=1)
    R = float(np.max(a * b * c / np.maximum(2 * twice, 1e-300)))
    spacing = None
    if prev is not None:
        _, dprev = nearest(V, prev)
        new = np.where(dprev > 1e-12)[0]
        if len(new):
            D = np.linalg.norm(V[new][:, None, :] - V[None, :, :], axis=2)
            D[np.arange(len(new)), new] = np.inf
            spacing = float(D.min())
            if spacing < R / 3:
                bad.append("(ii) a new vertex %.4g from another (R/3 = %.4g)" % (spacing, R / 3))
    # (iv) the nearest-point map
    cen = (A + B + C) / 3
    j, dc = nearest(cen, SC)
    _, dvert = nearest(V, SV)
    far = max(dc.max(), dvert.max())
    if far > eps + slack:
        bad.append("(iv) the mesh %.4g from the object" % far)
    nrm = cr / np.maximum(twice, 1e-300)[:, None]
    cosang = np.sum(nrm * SN[j], axis=1)
    if cosang.min() <= 0:
        bad.append("(iv) %d triangles turned away from the object's normal" % int(np.sum(cosang <= 0)))
    proj = float(np.sum(0.5 * twice * cosang))
    if abs(proj / area - 1) > 0.05:
        bad.append("(iv) projected area %.4g of the object's %.4g (degree not 1)" % (proj, area))
    return bad, dict(chi=chi, dens=float(dv.max()), R=R, spacing=spacing, cosmin=float(cosang.min()),
                     degree=proj / area, dist=float(far))


def sigma_at(obj, t, IV, IF):
    SV = obj.surface(t, IV)
    A, B, C = SV[IF[:, 0]], SV[IF[:, 1]], SV[IF[:, 2]]
    cr = np.cross(B - A, C - A)
    tw = np.linalg.norm(cr, axis=1)
    return SV, (A + B + C) / 3, cr / tw[:, None], float(np.sum(tw) / 2)


def read(path):
    m = o3d.io.read_triangle_mesh(path)
    return np.asarray(m.vertices, float), np.asarray(m.triangles, int)


def main():
    out, jpath, eps, spec = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
    selftest = len(sys.argv) > 5 and sys.argv[5] == "selftest"
    d = json.loads(open(jpath).read().strip().splitlines()[-1])
    rounds = d["rounds"]
    obj = Object(spec)
    IV, IF = icosphere(6)
    ok = True
    prev = None
    for k, r in enumerate(rounds):
        V, F = read("%s.round%d.ply" % (out, k))
        if len(F) == 0:
            print("FAIL: round %d: no mesh" % k)
            ok = False
            prev = V
            continue
        sigma = sigma_at(obj, r["t1"], IV, IF)
        slack = obj.speed * (r["t1"] - r["t0"])
        bad, fig = check(V, F, sigma, eps, slack, prev if k > 0 else None)
        print("round %d: (i) farthest point of the object from a vertex %.4f (bound %.4f); (ii) new vertices %s apart, "
              "R/3 %.4f; (iii) closed, Euler %d; (iv) mesh within %.4f, normals' least cosine %.3f, degree %.4f"
              % (k, fig["dens"], eps + slack, "%.4f" % fig["spacing"] if fig["spacing"] is not None else "-",
                 fig["R"] / 3, fig["chi"], fig["dist"], fig["cosmin"], fig["degree"]))
        for b in bad:
            print("FAIL: round %d: %s" % (k, b))
            ok = False
        if selftest and k == 1:
            moved = V + np.array([2 * eps, 0, 0])
            b1, _ = check(moved, F, sigma, eps, slack)
            pushed = V.copy()
            i = int(np.argmax(pushed[:, 0]))
            pushed[i] *= 0.2  # through the surface, far inside: its triangles fold over
            b2, _ = check(pushed, F, sigma, eps, slack)
            print("must fail: moved by 2 eps: %s; a vertex pushed inside: %s" % ("; ".join(b1) or "PASSED",
                                                                                  "; ".join(b2) or "PASSED"))
            if not b1 or not any("(iv)" in x for x in b2):
                print("FAIL: the checker passes a mesh it must fail")
                ok = False
        prev = V
    sys.exit(0 if ok else 1)


main()
