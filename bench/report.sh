#!/bin/sh
# The report's size and load time for a large mesh: a sim of the sphere at eps 0.0093 (about
# 100k vertices), its report, and chromium (headless, no network) opening it: the page measures
# the time to its first drawn frame (performance.now() after the first draw and a read-back of
# the canvas, from the start of navigation) and prints it in the page, read with --dump-dom.
# Medians of 3, WebGL (SwiftShader, the CPU) and the 2D canvas. Also the time of report --png.
# Usage: sh bench/report.sh [BUILD] [EPS]
B=${1:-build}
EPS=${2:-0.0093}
VP=$B/voroprobe
command -v chromium >/dev/null 2>&1 || { echo "bench/report.sh: chromium is not installed"; exit 1; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
NONET=""
unshare -rn true 2>/dev/null && NONET="unshare -rn"
"$VP" sim --surface sphere --eps "$EPS" --out "$T/s" --hausdorff 0 --quiet --json >"$T/sim.json" || exit 1
nv=$(sed -n 's/.*"vertices":\([0-9]*\).*/\1/p' "$T/sim.json")
nf=$(sed -n 's/.*"facets":\([0-9]*\).*/\1/p' "$T/sim.json")
np=$(sed -n 's/.*"probes":\([0-9]*\).*/\1/p' "$T/sim.json")
t0=$(date +%s%N)
"$VP" report "$T/s.vplog" --out "$T/r.html" --quiet || exit 1
t1=$(date +%s%N)
"$VP" report "$T/s.vplog" --png "$T/r.png" --quiet || exit 1
t2=$(date +%s%N)
size=$(wc -c <"$T/r.html")
gz=$(gzip -c "$T/r.html" | wc -c)
median() { sort -n | sed -n 2p; }
load() { # FLAGS: first_frame_ms of 3 runs, median
  for i in 1 2 3; do
    HOME=$T timeout 300 $NONET chromium --headless --no-sandbox --proxy-server=127.0.0.1:9 --window-size=1280,900 \
      $1 --dump-dom "file://$T/r.html" 2>/dev/null | sed -n 's/.*<pre id="vp-probe">[^<]*first_frame_ms=\([0-9.]*\).*/\1/p'
  done | median
}
gl=$(load "--use-angle=swiftshader --enable-unsafe-swiftshader")
cv=$(load "--disable-webgl")
echo "report of sphere eps $EPS: $nv vertices, $nf facets, $np probes"
echo "  report --out: $(( (t1 - t0) / 1000000 )) ms, $size bytes ($gz gzipped)"
echo "  first drawn frame in chromium: WebGL (SwiftShader) $gl ms, 2D canvas $cv ms (medians of 3)"
echo "  report --png (4 views of 480x360, software): $(( (t2 - t1) / 1000000 )) ms, $(wc -c <"$T/r.png") bytes"
