#!/bin/sh
# Reconstruction (voroprobe reconstruct, the tangential Delaunay complex) side by side with
# GUDHI's TangentialComplex (Debian 12 python3-gudhi 3.7.1) on the same points, in the same run:
# torus, sphere, Clifford torus, Klein bottle at 10k, the torus and the Clifford torus at 100k,
# SO(3) at 5000 (seed 1).
# Both fix inconsistencies by perturbing points within the same bound (0.25 x the mean
# nearest-neighbour distance for GUDHI; 0.25 x each point's own for voroprobe), GUDHI for at
# most 120 s. Time: building the complex and fixing it (tangents, stars, fixing; GUDHI:
# constructor + compute_tangential_complex + fix_inconsistencies_using_perturbation), without
# reading points or writing output. Memory: each process's peak RSS (/usr/bin/time; GUDHI's
# includes the Python interpreter and numpy, ~30 MB). Euler characteristic: voroprobe's from its
# manifold check; GUDHI's from its simplex tree. Usage: sh bench/reconstruct.sh [BUILD]
# (REC_QUICK=1: the 10k sets only).
B=${1:-${BUILD:-build}}
VP=$B/voroprobe
PY=/usr/bin/python3
if ! [ -x "$VP" ]; then echo "reconstruct bench: $VP missing (make BUILD=$B)"; exit 1; fi
have_gudhi=1
"$PY" -c "import gudhi" >/dev/null 2>&1 || { have_gudhi=0; echo "reconstruct bench: python3-gudhi missing (sh tools/install-deps.sh bench): voroprobe only"; }
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/gudhi_tc.py" <<'PYEOF'
import json, resource, sys, time
import numpy as np
import gudhi
path, k, perturb, limit = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
pts = np.loadtxt(path)
t0 = time.monotonic()
tc = gudhi.TangentialComplex(intrisic_dim=k, points=pts)
tc.compute_tangential_complex()
t1 = time.monotonic()
before = tc.num_inconsistent_simplices()
r = tc.fix_inconsistencies_using_perturbation(max_perturb=perturb, time_limit=limit)
t2 = time.monotonic()
after = tc.num_inconsistent_simplices()
st = tc.create_simplex_tree()
euler = 0
for s, _ in st.get_simplices():
    euler += -1 if len(s) % 2 == 0 else 1
print(json.dumps({"seconds_build": t1 - t0, "seconds_fix": t2 - t1, "seconds": t2 - t0,
                  "inconsistent_before": before, "inconsistent": after, "euler": euler,
                  "peak_rss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}))
PYEOF
field() { sed -n "s/.*\"$1\": *\([^,}]*\).*/\1/p" "$2" | tr -d ' '; }
echo "reconstruct: voroprobe (tangential Delaunay complex) vs GUDHI TangentialComplex 3.7.1, same points, seed 1"
printf '%-16s | %-44s | %-40s | %s\n' "dataset" "voroprobe: s, MB, inconsistent before>after, Euler" "GUDHI: s, MB, inconsistent before>after, Euler" "GUDHI/voroprobe time, memory"
sets="torus:10000:0 sphere:10000:2 clifford:10000:0 klein:10000:0"
[ "${REC_QUICK:-0}" = 1 ] || sets="$sets torus:100000:0 clifford:100000:0 so3:5000:0"
for s in $sets; do
  name=${s%%:*}; rest=${s#*:}; n=${rest%%:*}; want=${rest#*:}
  "$VP" reconstruct --generate "$name" --n "$n" --seed 1 --out-points "$tmp/p.txt" --quiet || exit 1
  k=$( "$VP" reconstruct --help | sed -n "s/^  $name  *k=\([0-9]\).*/\1/p")
  /usr/bin/time -f "%U %S %M" -o "$tmp/vp.rss" "$VP" reconstruct "$tmp/p.txt" --dim "$k" --seed 1 --out "$tmp/out" --json --quiet --time-limit 120 >"$tmp/vp.json" 2>&1
  vs=$(field seconds "$tmp/vp.json"); vb=$(field inconsistent_before "$tmp/vp.json"); va=$(field inconsistent "$tmp/vp.json")
  ve=$(field euler "$tmp/vp.json"); vm=$(field manifold "$tmp/vp.json"); nn=$(field nn_mean "$tmp/vp.json")
  vr=$(tail -1 "$tmp/vp.rss" | awk '{print $3}'); vcpu=$(tail -1 "$tmp/vp.rss" | awk '{print $1 + $2}')
  vcol=$(awk -v s="$vs" -v r="$vr" -v b="$vb" -v a="$va" -v e="$ve" -v m="$vm" -v w="$want" 'BEGIN{printf "%.2f s, %.0f MB, %s > %s, Euler %s%s%s", s, r/1024, b, a, e, e==w?"":" (want " w ")", m=="true"?", manifold":", NOT manifold"}')
  if [ $have_gudhi = 1 ]; then
    pert=$(awk -v x="$nn" 'BEGIN{printf "%.6g", 0.25 * x}')
    /usr/bin/time -f "%U %S %M" -o "$tmp/g.rss" "$PY" "$tmp/gudhi_tc.py" "$tmp/p.txt" "$k" "$pert" 120 >"$tmp/g.json" 2>"$tmp/g.err"
    gs=$(field seconds "$tmp/g.json"); gb=$(field inconsistent_before "$tmp/g.json"); ga=$(field inconsistent "$tmp/g.json")
    ge=$(field euler "$tmp/g.json"); gr=$(tail -1 "$tmp/g.rss" | awk '{print $3}'); gcpu=$(tail -1 "$tmp/g.rss" | awk '{print $1 + $2}')
    if [ -n "$gs" ]; then
      gcol=$(awk -v s="$gs" -v r="$gr" -v b="$gb" -v a="$ga" -v e="$ge" 'BEGIN{printf "%.2f s, %.0f MB, %s > %s, Euler %s", s, r/1024, b, a, e}')
      ratio=$(awk -v g="$gs" -v v="$vs" -v gr="$gr" -v vr="$vr" -v gc="$gcpu" -v vc="$vcpu" 'BEGIN{printf "%.1fx time, %.1fx memory (process CPU s: %.1f vs %.1f)", g/v, gr/vr, gc, vc}')
    else
      gcol="failed: $(tail -1 "$tmp/g.err")"; ratio="-"
    fi
  else
    gcol="(not installed)"; ratio="-"
  fi
  printf '%-16s | %-44s | %-40s | %s\n' "$name $n" "$vcol" "$gcol" "$ratio"
done
[ "${REC_QUICK:-0}" = 1 ] && exit 0

# On the planner's own samples: `sim` scans the sphere (radius 1) and the torus (radii 1, 0.3) at
# several eps; its session log's hits are reconstructed and compared with the planner's
# restricted Delaunay mesh, both read by Open3D and measured against the exact surface: the
# largest distance to it over 12 points per triangle (corners, edge midpoints, interior) and the
# largest angle between a triangle's normal and the surface normal at its centroid. The
# papers: distance ~ eps^2, angle ~ eps (the log-log slopes below).
echo
echo "reconstruct on scan samples: the planner's mesh vs voroprobe reconstruct of its log's hits"
for surf in sphere torus; do
  for eps in 0.2 0.14 0.1 0.07 0.05; do
    "$VP" sim --surface "$surf" --eps "$eps" --out "$tmp/$surf-$eps" --quiet --hausdorff 0 >/dev/null 2>&1 || { echo "sim $surf $eps failed"; continue; }
    "$VP" reconstruct "$tmp/$surf-$eps.vplog" --dim 2 --out "$tmp/$surf-$eps-rec" --json --quiet >"$tmp/$surf-$eps-rec.json" 2>&1
  done
done
"$PY" - "$tmp" <<'PYEOF'
import json, math, sys
import numpy as np
import open3d as o3d
d = sys.argv[1]
def surface(name, x):
    if name == "sphere":
        r = np.linalg.norm(x, axis=1)
        return np.abs(r - 1), x / r[:, None]
    rho = np.hypot(x[:, 0], x[:, 1])
    q = np.stack([x[:, 0] - x[:, 0] / rho, x[:, 1] - x[:, 1] / rho, x[:, 2]], axis=1)
    l = np.linalg.norm(q, axis=1)
    return np.abs(l - 0.3), q / l[:, None]
B = np.array([[1,0,0],[0,1,0],[0,0,1],[.5,.5,0],[0,.5,.5],[.5,0,.5],[1/3,1/3,1/3],[.6,.2,.2],[.2,.6,.2],[.2,.2,.6],[.4,.4,.2],[.2,.4,.4]])
def measure(name, path):
    m = o3d.io.read_triangle_mesh(path)
    V, F = np.asarray(m.vertices), np.asarray(m.triangles)
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    pts = (B[:, 0, None, None] * a + B[:, 1, None, None] * b + B[:, 2, None, None] * c).reshape(-1, 3)
    dist, _ = surface(name, pts)
    n = np.cross(b - a, c - a); n /= np.linalg.norm(n, axis=1)[:, None]
    _, sn = surface(name, (a + b + c) / 3)
    ang = np.degrees(np.arccos(np.clip(np.abs((n * sn).sum(1)), 0, 1)))
    return len(V), len(F), dist.max(), ang.max(), m.is_watertight()
def slope(e, y):
    return np.polyfit(np.log(e), np.log(y), 1)[0]
for name in ("sphere", "torus"):
    rows = []
    for eps in ("0.2", "0.14", "0.1", "0.07", "0.05"):
        try:
            p = measure(name, "%s/%s-%s.ply" % (d, name, eps))
            r = measure(name, "%s/%s-%s-rec.ply" % (d, name, eps))
            j = json.loads(open("%s/%s-%s-rec.json" % (d, name, eps)).read().strip().splitlines()[-1])
        except Exception as ex:
            print("%s eps %s: %s" % (name, eps, ex)); continue
        rows.append((float(eps), p, r, j))
        print("%-6s eps %-4s | planner: %5d vertices, distance %.2e, normals %5.2f deg, %s | reconstruct: %5d points, inconsistent %d > %d, %s, Euler %d, distance %.2e, normals %5.2f deg"
              % (name, eps, p[0], p[2], p[3], "closed" if p[4] else "open", r[0], j["inconsistent_before"], j["inconsistent"],
                 "manifold" if j["manifold"] else "NOT manifold", j["euler"], r[2], r[3]))
    if len(rows) >= 3:
        e = [x[0] for x in rows]
        print("%-6s log-log slopes vs eps: distance planner %.2f, reconstruct %.2f (papers: 2); normals planner %.2f, reconstruct %.2f (papers: 1)"
              % (name, slope(e, [x[1][2] for x in rows]), slope(e, [x[2][2] for x in rows]),
                 slope(e, [x[1][3] for x in rows]), slope(e, [x[2][3] for x in rows])))
PYEOF
