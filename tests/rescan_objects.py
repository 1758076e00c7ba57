#!/usr/bin/env python3
"""Objects for the re-scan tests: a unit icosphere (level 4: 2,562 vertices) and the same
sphere with a smooth bump on 5% of its area (a cap of 25.8 degrees about +x, raised by HEIGHT
at its centre, (1 - (a/A)^2)^2 in the angle a from the centre, A the cap's angle); a torus
(radii 1 and 0.3, 96 x 32 quads split in two) and the same torus with its tube swollen into the
hole on the +x side (by 0.3 at the inner equator, over 0.6 of its length: the hole narrows
from 0.7 to 0.4 there).
usage: rescan_objects.py OUTDIR [HEIGHT]"""
import math, os, sys

def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        mid = {}
        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                mid[k] = len(v) - 1
            return mid[k]
        g = []
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return v, f

def write_off(path, v, f):
    with open(path, "w") as o:
        o.write("OFF\n%d %d 0\n" % (len(v), len(f)))
        for p in v:
            o.write("%.17g %.17g %.17g\n" % p)
        for a, b, c in f:
            o.write("3 %d %d %d\n" % (a, b, c))

def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    height = float(sys.argv[2]) if len(sys.argv) > 2 else 0.1
    v, f = icosphere(4)
    write_off(out + "/sphere.off", v, f)
    cap = math.acos(0.9)  # a cap of 5% of the area: (1 - cos A) / 2 = 0.05
    w = []
    for p in v:
        a = math.acos(max(-1.0, min(1.0, p[0])))
        s = 1.0 + (height * (1 - (a / cap) ** 2) ** 2 if a < cap else 0.0)
        w.append(tuple(s * x for x in p))
    write_off(out + "/sphere_bump.off", w, f)
    for name, swell in (("torus", 0.0), ("torus_swollen", 0.3)):
        nu, nv, R, r = 96, 32, 1.0, 0.3
        v, f = [], []
        for i in range(nu):
            u = 2 * math.pi * i / nu
            for j in range(nv):
                t = 2 * math.pi * j / nv
                # the swelling: largest at u = 0 on the inner equator (t = pi)
                du = min(abs(u), 2 * math.pi - abs(u)) * (R - r)
                dt = abs(t - math.pi) * r
                q = (du * du + dt * dt) ** 0.5 / 0.3
                rr = r + (swell * (1 - q * q) ** 2 if q < 1 else 0.0)
                v.append(((R + rr * math.cos(t)) * math.cos(u), (R + rr * math.cos(t)) * math.sin(u), rr * math.sin(t)))
        for i in range(nu):
            for j in range(nv):
                a, b = i * nv + j, ((i + 1) % nu) * nv + j
                c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
                f += [(a, b, c), (a, c, d)]
        write_off(out + "/" + name + ".off", v, f)

if __name__ == "__main__":
    main()
