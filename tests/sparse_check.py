"""A sparse re-scan of an unchanged object, checked from outside the planner.

usage: sparse_check.py OLD.off DUMP.csv EDGES SKIPPED [must-fail]

OLD.off: the first scan's mesh (its vertices are the samples), DUMP.csv: `voroprobe log dump
--csv` of the re-scan's log, EDGES: the edges of CGAL's 3D Delaunay triangulation of those
vertices (`cgal_object edges OLD.off`), SKIPPED: the number of samples the re-scan reports not
measured. The samples measured are those a PROBE after the RESCAN event hit (within 1e-9 of the
object's size); the others were left out. A sample left out can still be hit by the line
measuring another (two samples on one line, where the first scan's probe crossed S twice): so
those never hit are at most as many as reported, and fewer by at most 2% of the samples.
Checked: that; no two never hit that are Delaunay neighbours; each with 3 neighbours at least.
must-fail: one measured sample next to a left-out one is taken as left out too: the check has
to find two neighbours left out (exit 0 when it does).
"""
import csv
import sys


def read_off(path):
    with open(path) as f:
        words = [w for line in f for w in line.split("#")[0].split()]
    assert words[0] == "OFF"
    nv = int(words[1])
    return [tuple(float(x) for x in words[4 + 3 * i:7 + 3 * i]) for i in range(nv)]


def main():
    off, dump, edges_path, reported = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    must_fail = len(sys.argv) > 5 and sys.argv[5] == "must-fail"
    V = read_off(off)
    lo = [min(p[k] for p in V) for k in range(3)]
    hi = [max(p[k] for p in V) for k in range(3)]
    tol = 1e-9 * max(1.0, max(h - l for h, l in zip(hi, lo)))
    cell = {}
    for i, p in enumerate(V):
        cell.setdefault(tuple(round(c / 1e-6) for c in p), []).append(i)

    def find(q):
        key = tuple(round(c / 1e-6) for c in q)
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for i in cell.get((key[0] + dx, key[1] + dy, key[2] + dz), []):
                        if max(abs(a - b) for a, b in zip(V[i], q)) <= tol:
                            return i
        return None

    measured = set()
    after = False
    with open(dump) as f:
        for row in csv.DictReader(f):
            if row["type"] == "event" and row["event"] == "rescan":
                after = True
            elif after and row["type"] == "probe" and row["hit"] == "1":
                i = find((float(row["point_x"]), float(row["point_y"]), float(row["point_z"])))
                if i is not None:
                    measured.add(i)
    nb = {i: set() for i in range(len(V))}
    with open(edges_path) as f:
        for line in f:
            a, b = (int(x) for x in line.split())
            nb[a].add(b)
            nb[b].add(a)
    if must_fail:
        for i in sorted(measured):
            if any(j not in measured for j in nb[i]):
                measured.discard(i)
                reported += 1
                break
    left = [i for i in range(len(V)) if i not in measured]
    bad = []
    if not (reported - 0.02 * len(V) <= len(left) <= reported):
        bad.append("%d samples never hit, the re-scan reports %d not measured" % (len(left), reported))
    pairs = [(i, j) for i in left for j in nb[i] if j > i and j not in measured]
    if pairs:
        bad.append("%d pairs of Delaunay neighbours both left out (first %d-%d)" % (len(pairs), pairs[0][0], pairs[0][1]))
    few = [i for i in left if len(nb[i]) < 3]
    if few:
        bad.append("%d left out with fewer than 3 neighbours" % len(few))
    print("%d samples, %d hit, %d never hit (reported not measured: %d), %d Delaunay edges; %s"
          % (len(V), len(measured), len(left), reported, sum(len(s) for s in nb.values()) // 2,
             "; ".join(bad) if bad else "no two neighbours both never hit"))
    if must_fail:
        sys.exit(0 if pairs else 1)
    sys.exit(1 if bad else 0)


main()
