#!/bin/sh
# Re-scan (sim --rescan) against a fresh scan, both measured in this run: the object unchanged
# (the mesh must come back byte for byte), a bump on 5% of a sphere's area, a torus swollen into
# its hole, one part of two moved by 2 eps. Probes of the re-scan (after the RESCAN event) over
# the probes of the first scan, and over a fresh scan of the object as it is now; the same for a
# sparse re-scan (--rescan-sparse). Then tracking rounds (sim --track) of a sphere translating and
# of a bump growing on it: probes per round against the first scan, with and without
# --rescan-sparse.
set -u
B=${1:-build}
VP="$B/voroprobe"
D="$B/bench/rescan"
rm -rf "$D"; mkdir -p "$D/obj"
python3 tests/rescan_objects.py "$D/obj" 0.15
field() { tail -n 1 "$1" | sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }
rfield() { tail -n 1 "$1" | sed -n "s/.*\"rescan\":{[^}]*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }
echo "Re-scan vs a fresh scan (probes; the re-scan's share of the first scan's and of a fresh scan of the object now)"
printf '%-34s %-26s %9s %9s %7s %9s %7s %6s %7s %6s %9s %7s %s\n' "first scan" "object now" first rescan share fresh "share" kept removed moved \
  sparse share "same mesh"
row() { # NAME FIRST_SPEC EPSREL NOW_SPEC [extra]
  n=$1; a=$2; e=$3; now=$4; shift 4
  "$VP" sim --surface "$a" --eps-rel "$e" "$@" --out "$D/$n" --quiet --hausdorff 0 >/dev/null 2>&1
  "$VP" sim --rescan "$D/$n.vplog" --surface "$now" --out "$D/$n-r" --quiet --json --hausdorff 0 >"$D/$n-r.json" 2>&1
  "$VP" sim --rescan "$D/$n.vplog" --rescan-sparse --surface "$now" --out "$D/$n-s" --quiet --json --hausdorff 0 \
    >"$D/$n-s.json" 2>&1
  "$VP" sim --surface "$now" --eps-rel "$e" "$@" --out "$D/$n-f" --quiet --json --hausdorff 0 >"$D/$n-f.json" 2>&1
  p=$(rfield "$D/$n-r.json" probes); o=$(rfield "$D/$n-r.json" old_probes); f=$(field "$D/$n-f.json" probes)
  ps=$(rfield "$D/$n-s.json" probes)
  same=-; [ "$a" = "$now" ] && { cmp -s "$D/$n.ply" "$D/$n-r.ply" && cmp -s "$D/$n.ply" "$D/$n-s.ply" && same=yes || same=NO; }
  printf '%-34s %-26s %9s %9s %6.1f%% %9s %6.1f%% %6s %7s %6s %9s %6.1f%% %s\n' "$(basename "$a") $e $*" "$(basename "$now")" \
    "$o" "$p" "$(awk -v p="$p" -v o="$o" 'BEGIN { print 100 * p / o }')" "$f" "$(awk -v p="$p" -v f="$f" 'BEGIN { print 100 * p / f }')" \
    "$(rfield "$D/$n-r.json" kept)" "$(rfield "$D/$n-r.json" dropped)" "$(rfield "$D/$n-r.json" moved)" "$ps" \
    "$(awk -v p="$ps" -v o="$o" 'BEGIN { print 100 * p / o }')" "$same"
}
for s in sphere torus genus2 ellipsoid blobby; do
  row "$s" "$s" 0.03 "$s"
  row "$s-fine" "$s" 0.015 "$s"
done
row body ellipsoid 0.04 ellipsoid --clearance 0.1
row bump "off:$D/obj/sphere.off" 0.02 "off:$D/obj/sphere_bump.off"
row swollen "off:$D/obj/torus.off" 0.03 "off:$D/obj/torus_swollen.off"
row moved "sphere@3,0,0+torus" 0.02 "sphere@3.25,0,0+torus"

echo
echo "Tracking (sim --surface sphere --eps 0.2 --track 3): probes per round (the first scan's in brackets), samples moved"
for m in translate:0.0005,0,0 bump:1,0,0,0.5,0.001; do
  for sp in "" --rescan-sparse; do
    "$VP" sim --surface sphere --eps 0.2 --motion "$m" --track 3 $sp --no-log --quiet --json --out "$D/track" >"$D/track.json" 2>&1
    python3 - "$D/track.json" "$m" "$sp" <<'PY'
import json, sys
r = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])["rounds"]
print("%-24s %-16s [%d] %s" % (sys.argv[2], sys.argv[3] or "every sample", r[0]["probes"],
      ", ".join("%d probes, %d moved, %s" % (x["probes"], x["moved"], "closed" if x["closed"] else "NOT closed") for x in r[1:])))
PY
  done
done
