#!/bin/sh
# voroprobe report in a real browser: Debian's chromium, headless, without a network, opens the
# report of a small sim session and
#   (a) its canvas drew the mesh: chromium's screenshot is not background where the mesh (read
#       from the PLY sim wrote, projected and rasterised by tests/report_check.py) projects and
#       background elsewhere; with WebGL (SwiftShader) and with WebGL disabled (the 2D canvas);
#   (b) the numbers on the page (vertices, facets, probes, hits, genus, status) equal sim --json;
#   the page holds no URL (no src/href to a network, no "http" at all); a click (through the
#   DevTools protocol, tests/cdp_wait.py) where the test's own ray cast meets facet F names F.
#   (c) report, sim, replay and mesh --png: each of the four software-rendered views is drawn
#       where the mesh projects with that view's camera and background elsewhere (no browser).
# Each checker must reject a page made wrong on purpose: no triangles (blank canvas), a wrong
# vertex count, a picture compared with another object's mesh. Skips (77) when chromium is not
# installed.
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
PY=/usr/bin/python3
CHECK="$PY tests/report_check.py"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# chromium without a network: its own network namespace when the kernel allows, else a dead proxy
NONET=""
unshare -rn true 2>/dev/null && NONET="unshare -rn"
browse() { # browse EXTRA_FLAGS URL ARG...
  flags=$1; url=$2; shift 2
  HOME=$T timeout 120 $NONET chromium --headless --no-sandbox --no-first-run --disable-background-networking \
    --proxy-server=127.0.0.1:9 --window-size=1280,900 $flags "$@" "$url" 2>>"$T/chromium.err"
}
GL="--use-angle=swiftshader --enable-unsafe-swiftshader"

"$VP" sim --surface torus --eps 0.1 --out "$T/s" --json --quiet --png "$T/sim.png" >"$T/sim.json" || fail "sim exited $?"
"$VP" replay "$T/s.vplog" --out "$T/rep" --quiet --png "$T/replay.png" || fail "replay --png exited $?"
"$VP" mesh "$T/s.vplog" --out "$T/m" --quiet --png "$T/mesh.png" || fail "mesh --png exited $?"
# (c) the picture, checked before the browser (it needs none)
"$VP" report "$T/s.vplog" --png "$T/pic.png" --quiet || fail "report --png exited $?"
res=$($CHECK png "$T/pic.png" "$T/s.ply") || fail "png: $res"
for p in sim replay mesh; do
  res=$($CHECK png "$T/$p.png" "$T/s.ply") || fail "$p --png: $res"
done
echo "png: $res"
"$VP" sim --surface sphere --eps 0.3 --out "$T/other" --quiet >/dev/null || fail "sim sphere"
res=$($CHECK png "$T/pic.png" "$T/other.ply") && fail "the picture check passed a torus picture as a sphere: $res"
echo "torus picture against a sphere rejected: $res"
command -v chromium >/dev/null 2>&1 || { echo "chromium is not installed (tools/install-deps.sh check)"; exit 77; }
"$VP" report "$T/s.vplog" --out "$T/r.html" --quiet || fail "report exited $?"
"$VP" report --help >/dev/null || fail "report --help"
"$VP" report "$T/s.vplog" >/dev/null 2>&1; [ $? -eq 2 ] || fail "report without --out: not a usage error"
"$VP" report "$T/none.vplog" --out "$T/x.html" >/dev/null 2>&1; [ $? -eq 1 ] || fail "report of a missing log: not exit 1"

# self-contained: no URL anywhere
grep -Eiq '(src|href)[[:space:]]*=[[:space:]]*["'\'']?[a-z]*:?//' "$T/r.html" && fail "a src/href names a network resource"
grep -qi 'http' "$T/r.html" && fail "the page holds 'http'"
size=$(wc -c <"$T/r.html")

probe_of() { sed -n 's/.*<pre id="vp-probe">\([^<]*\)<.*/\1/p' "$1"; }
for mode in webgl 2d; do
  flags=$GL
  [ $mode = 2d ] && flags="--disable-webgl"
  browse "$flags" "file://$T/r.html" --dump-dom >"$T/dom-$mode.html"
  probe=$(probe_of "$T/dom-$mode.html")
  case $probe in renderer=$mode\ *) ;; *) fail "$mode: the page drew with '$probe'";; esac
  browse "$flags" "file://$T/r.html" --screenshot="$T/shot-$mode.png" >/dev/null
  [ -s "$T/shot-$mode.png" ] || fail "$mode: no screenshot"
  res=$($CHECK pixels "$T/shot-$mode.png" "$T/s.ply" "$probe") || fail "$mode pixels: $res"
  echo "$mode: $res ($probe)"
  res=$($CHECK numbers "$T/dom-$mode.html" "$T/sim.json") || fail "$mode numbers: $res"
  echo "$mode: $res"
done

# pick: a click where the test's own ray cast finds facet F must name facet F on the page
set -- $($CHECK pick "$T/s.ply" 720 540)
px=$1 py=$2 want=$3
cat >"$T/pick.sh" <<PICK
HOME="$T" timeout 120 chromium --headless --no-sandbox --no-first-run --proxy-server=127.0.0.1:9 \
  --window-size=1280,900 $GL --remote-debugging-port=9223 "file://$T/r.html" 2>>"$T/chromium.err" &
cpid=\$!
$PY tests/cdp_wait.py 9223 60 "wait=/renderer=/.test(document.getElementById('vp-probe').textContent)" \
  "eval=(function () { var c = document.getElementById('view'), b = c.getBoundingClientRect(), o = { clientX: b.left + $px, clientY: b.top + $py, bubbles: true }; c.dispatchEvent(new MouseEvent('mousedown', o)); window.dispatchEvent(new MouseEvent('mouseup', o)); })()" \
  "wait=/^facet /.test(document.getElementById('pick').textContent)" >"$T/dom-pick.html"
rc=\$?
kill \$cpid
exit \$rc
PICK
if [ -n "$NONET" ]; then unshare -rn sh -c "ip link set lo up && sh $T/pick.sh"; else sh "$T/pick.sh"; fi ||
  fail "pick: no facet named after a click"
got=$(sed -n 's/.*<div id="pick">facet \([0-9]*\):.*/\1/p' "$T/dom-pick.html")
[ "$got" = "$want" ] || fail "pick: the page names facet '$got' at ($px, $py), the ray cast facet $want"
grep -q 'H1 and H3 hold here' "$T/dom-pick.html" || fail "pick: facet $got of a closed torus said to break H1 or H3"
echo "pick: a click at ($px, $py) names facet $got, as the test's ray cast"

# the checkers reject a blank canvas and a wrong number
$PY - "$T/r.html" "$T/blank.html" "$T/wrong.html" <<'EOF'
import re, sys
s = open(sys.argv[1], encoding='utf-8').read()
blank = re.sub(r'"tri":"[^"]*"', '"tri":""', s, count=1)
m = re.search(r'"summary":\{[^}]*?"vertices":(\d+)', s)
wrong = s[:m.start(1)] + str(int(m.group(1)) + 1) + s[m.end(1):]
assert blank != s and wrong != s
open(sys.argv[2], 'w', encoding='utf-8').write(blank)
open(sys.argv[3], 'w', encoding='utf-8').write(wrong)
EOF
browse "$GL" "file://$T/blank.html" --dump-dom >"$T/dom-blank.html"
browse "$GL" "file://$T/blank.html" --screenshot="$T/shot-blank.png" >/dev/null
res=$($CHECK pixels "$T/shot-blank.png" "$T/s.ply" "$(probe_of "$T/dom-blank.html")") && fail "the pixel check passed a blank canvas: $res"
echo "blank canvas rejected: $res"
browse "$GL" "file://$T/wrong.html" --dump-dom >"$T/dom-wrong.html"
res=$($CHECK numbers "$T/dom-wrong.html" "$T/sim.json") && fail "the number check passed a wrong vertex count: $res"
echo "wrong number rejected: $res"

nums=$(sed -n 's/.*"vertices":\([0-9]*\),"facets":\([0-9]*\),"probes":\([0-9]*\).*/\1 vertices, \2 facets, \3 probes/p' "$T/sim.json")
echo "t_report: torus ($nums), $size-byte page: mesh drawn by WebGL and by the 2D canvas where projected and nowhere else, 6 numbers equal sim --json, pick names the facet ray-cast here, --png's 4 views (report, sim, replay, mesh) drawn where projected; a blank canvas, a wrong count, another object's picture rejected"
