#!/bin/sh
# The live view (sim --serve, host/vp_live) in a real browser: in a network namespace of its
# own (loopback only), sim serves a genus-2 scan and waits for a page (--serve-wait); Debian's
# chromium, headless, opens http://127.0.0.1:PORT/ and follows the scan to its end, paused and
# resumed once on the page's button while the scan runs (tests/cdp_wait.py drives the page
# through the DevTools protocol until it shows the final state, then takes its DOM). The
# page must have updated while the scan ran, received every sample sent, and end with the state
# and counts of sim --json (tests/report_check.py live). A stalled client (connects to the
# events and never reads) must not change the scan: same counts, and sim ends after
# --serve-linger. scan --serve (a dry run) streams to its final state. The checker must reject a
# page that lost a sample.
# Skips (77) without chromium, without a network namespace, or in a build without libmicrohttpd.
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
PY=/usr/bin/python3
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v chromium >/dev/null 2>&1 || { echo "chromium is not installed (tools/install-deps.sh check)"; exit 77; }
unshare -rn ip link set lo up 2>/dev/null || { echo "no network namespace here (unshare -rn)"; exit 77; }
"$VP" sim --help | grep -q -- '--serve PORT' || fail "sim --help says nothing of --serve"
"$VP" sim --surface sphere --eps 0.3 --no-log --quiet --serve 0 >/dev/null 2>&1; [ $? -eq 2 ] || fail "--serve 0 is not a usage error"

SIM="$VP sim --surface genus2 --eps 0.035 --no-log --json --hausdorff 0"
cat >"$T/run.sh" <<EOF
ip link set lo up || exit 3
$SIM --out "$T/a" --serve 8765 --serve-wait 60 --serve-linger 60 >"$T/live.json" 2>"$T/live.err" &
pid=\$!
HOME="$T" timeout 180 chromium --headless --no-sandbox --no-first-run --window-size=1280,900 \
  --remote-debugging-port=9222 http://127.0.0.1:8765/ 2>"$T/chromium.err" &
cpid=\$!
$PY tests/cdp_wait.py 9222 120 "wait=+document.getElementById('l-updates').textContent >= 1" \\
  "eval=document.getElementById('pause').click()" "sleep=0.3" "eval=document.getElementById('pause').click()" \\
  "wait=document.getElementById('l-final').textContent === 'yes'" >"$T/dom.html"
kill \$cpid
wait \$pid || exit 4
# a client that asks for the events and never reads them
$PY -c "
import socket, subprocess, sys, time
p = subprocess.Popen(sys.argv[1:])
for _ in range(100):
    try:
        s = socket.create_connection(('127.0.0.1', 8766)); break
    except OSError:
        time.sleep(0.05)
s.sendall(b'GET /events HTTP/1.1\r\nHost: x\r\n\r\n')
sys.exit(p.wait())
" $SIM --out "$T/b" --serve 8766 --serve-wait 60 --serve-linger 2 >"$T/stalled.json" 2>"$T/stalled.err" || exit 5
# scan --serve: a dry run on host-sim, its events read to the end by a plain HTTP client
$VP scan --board boards/rpi4-gantry.ini --dry-run --log "$T/scan.vplog" --serve 8767 --serve-wait 60 >"$T/scan.out" 2>"$T/scan.err" &
pid=\$!
$PY -c "
import time, urllib.request
for _ in range(200):
    try:
        r = urllib.request.urlopen('http://127.0.0.1:8767/events', timeout=120); break
    except OSError:
        time.sleep(0.1)
last = ''
for line in r:
    line = line.decode()
    if line.startswith('data: {\\"state\\"'): last = line
    if line.startswith('event: end'): break
print(last.strip())
" >"$T/scan.events" || exit 6
wait \$pid || exit 7
EOF
timeout 300 unshare -rn sh "$T/run.sh"; rc=$?
[ $rc -eq 77 ] && exit 77
[ $rc -eq 0 ] || { tail -n 5 "$T/live.err" "$T/stalled.err" 2>/dev/null; fail "the live run exited $rc"; }
grep -q '"status":"unusable"' "$T/live.json" && fail "sim said unusable"
case $(cat "$T/live.err") in *"built without libmicrohttpd"*) echo "built without libmicrohttpd"; exit 77;; esac

live=$($PY tests/report_check.py live "$T/dom.html" "$T/live.json") || fail "live page: $live"
echo "live: $live"
grep -q 'id="l-connections">2 / 0<' "$T/dom.html" || fail "the page was not paused and resumed once: $(grep -o 'l-connections">[^<]*' "$T/dom.html")"
# the stalled client changed nothing
$SIM --out "$T/c" >"$T/plain.json" 2>/dev/null || fail "plain sim exited $?"
for k in vertices facets probes hits moves; do
  a=$(sed -n "s/.*\"$k\":\([0-9]*\).*/\1/p" "$T/plain.json"); b=$(sed -n "s/.*\"$k\":\([0-9]*\).*/\1/p" "$T/stalled.json")
  [ -n "$a" ] && [ "$a" = "$b" ] || fail "$k: $b with a stalled client, $a without"
done
grep -q '"state":"done","final":true' "$T/scan.events" || fail "scan --serve: no final state: $(cat "$T/scan.events")"
scan_probes=$(sed -n 's/.*"probes":\([0-9]*\).*/\1/p' "$T/scan.events")
grep -q "probes $scan_probes " "$T/scan.err" || fail "scan --serve: $scan_probes probes in the events, not in scan's progress"
# the checker rejects a page that lost a sample
$PY - "$T/dom.html" "$T/lost.html" <<'EOF'
import re, sys
s = open(sys.argv[1], encoding='utf-8').read()
t = re.sub(r'(<td id="l-received">)(\d+)', lambda m: m.group(1) + str(int(m.group(2)) - 1), s)
assert t != s
open(sys.argv[2], 'w', encoding='utf-8').write(t)
EOF
res=$($PY tests/report_check.py live "$T/lost.html" "$T/live.json") && fail "the live check passed a lost sample: $res"
echo "lost sample rejected: $res"
frames=$(sed -n 's/.*live view: \([0-9]*\) mesh frames.*(\(.*\)).*/\1 frames (\2)/p' "$T/live.err")
echo "t_live: chromium followed sim --serve to its end, paused and resumed (${live#ok }); scan loop: $frames; a stalled client changed no count; scan --serve ended with its $scan_probes probes; a lost sample rejected"
