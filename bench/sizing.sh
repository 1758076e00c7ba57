#!/bin/sh
# The sizing field of paper 002 (sim --size-rel E) against the uniform-eps planner at equal
# certified eps' (certify's non-uniform eps' = max r / dM, dM from the samples' poles): on the
# sphere and the torus (dM constant: adaptive should equal uniform) and on the ellipsoid
# (1, 0.7, 0.5), where paper 002 bounds the saving at 3.6x. The adaptive run's E is chosen so
# that its eps' comes out at the uniform run's.
set -u
B=${1:-build}
VP="$B/voroprobe"
D="$B/bench/sizing"
mkdir -p "$D"
field() { sed -n "s/.*\"$1\":\([^,}]*\).*/\1/p" | tr -d '"'; }
run() { # run NAME ARGS...: vertices and certified eps'
  n=$1; shift
  v=$("$VP" sim "$@" --quiet --json --hausdorff 0 --out "$D/$n" | tail -1 | field vertices)
  e=$("$VP" certify "$D/$n.vplog" 2>&1 | sed -n "s/.*eps' = \([0-9.]*\).*/\1/p" | head -1)
  echo "$v $e"
}
echo "Sizing field (paper 002) vs uniform eps at equal certified eps'"
printf '%-10s %-34s %7s %8s   %-44s %7s %8s %7s\n' surface uniform verts "eps'" adaptive verts "eps'" saving
for c in "sphere 0.1 0.091" "torus 0.03 0.091" "ellipsoid 0.05 0.158" "ellipsoid 0.045 0.145"; do
  set -- $c; s=$1; e=$2; E=$3
  set -- $(run "$s-u" --surface "$s" --eps "$e"); uv=$1; ue=$2
  set -- $(run "$s-a" --surface "$s" --eps 0.3 --size-rel "$E" --min-size 0.005); av=$1; ae=$2
  printf '%-10s %-34s %7d %8s   %-44s %7d %8s %6.2fx\n' "$s" "--eps $e" "$uv" "$ue" \
    "--eps 0.3 --size-rel $E --min-size 0.005" "$av" "$ae" "$(awk -v a="$uv" -v b="$av" 'BEGIN { print a / b }')"
done
