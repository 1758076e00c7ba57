#!/bin/sh
# What the live view costs the scan: sim of genus2 at eps 0.02 (about 37k vertices) without and
# with --serve and a client reading the events to the end (in a network namespace of its own);
# total_seconds of sim --json, medians of 3, and the mesh frames the scan loop built.
# Usage: sh bench/live.sh [BUILD]
B=${1:-build}
VP=$(cd "$B" && pwd)/voroprobe
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
unshare -rn true 2>/dev/null || { echo "bench/live.sh: needs a network namespace (unshare -rn)"; exit 1; }
cat >"$T/client.py" <<'PY'
import time, urllib.request
for _ in range(200):
    try:
        r = urllib.request.urlopen('http://127.0.0.1:8780/events', timeout=120); break
    except OSError:
        time.sleep(0.05)
for line in r:
    if line.startswith(b'event: end'): break
PY
SIM="$VP sim --surface genus2 --eps 0.02 --no-log --hausdorff 0 --json --out $T/s"
cat >"$T/run.sh" <<RUN
ip link set lo up
for i in 1 2 3; do
  $SIM 2>/dev/null | tail -n 1 | sed -n 's/.*"total_seconds":\([0-9.]*\).*/plain \1/p'
  $SIM --serve 8780 --serve-wait 30 2>"$T/err" | tail -n 1 | sed -n 's/.*"total_seconds":\([0-9.]*\).*/served \1/p' &
  /usr/bin/python3 "$T/client.py"
  wait
  sed -n 's/.*live view: //p' "$T/err"
done
RUN
unshare -rn sh "$T/run.sh" >"$T/out"
med() { grep "^$1 " "$T/out" | cut -d' ' -f2 | sort -n | sed -n 2p; }
echo "genus2 eps 0.02: sim total $(med plain) s without --serve, $(med served) s with --serve and a client reading (medians of 3)"
echo "  scan loop, last run: $(grep 'mesh frames' "$T/out" | tail -n 1)"
