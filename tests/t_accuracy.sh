#!/bin/sh
# sim --accuracy / --accuracy-rel: the target chooses eps, the sizing field and its floor, and the
# simulator measures the mesh against it (two-sided Hausdorff): exit 0 within it, 6 beyond it
# (a case that must be caught: the coarse icosphere at 0.5% of its diagonal, where the rule's
# floor is too coarse for its edges), 2 when combined with the settings it chooses.
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
field() { tail -n 1 "$1" | sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }

"$VP" sim --surface sphere --accuracy-rel 0.01 --out "$tmp/s" --json --quiet >"$tmp/s.txt" 2>&1; rc=$?
h=$(field "$tmp/s.txt" hausdorff); t=$(field "$tmp/s.txt" accuracy_target)
[ $rc -eq 0 ] && [ "$(field "$tmp/s.txt" status)" = closed ] || bad "sphere --accuracy-rel 0.01: exit $rc"
awk -v h="$h" -v t="$t" 'BEGIN { exit !(h > 0 && t > 0 && h <= t) }' || bad "sphere: Hausdorff $h above the target $t"
"$VP" log dump "$tmp/s.vplog" | head -5 | grep -q -- "--accuracy-rel 0.01" || bad "the target is not in the log's note"

"$VP" sim --surface off:tests/meshes/icosphere2.off --accuracy-rel 0.005 --out "$tmp/i" --json --quiet >"$tmp/i.txt" 2>&1; rc=$?
hi=$(field "$tmp/i.txt" hausdorff); ti=$(field "$tmp/i.txt" accuracy_target)
[ $rc -eq 6 ] && [ "$(field "$tmp/i.txt" status)" = not_within_target ] || bad "icosphere beyond its target: exit $rc (6 expected)"
awk -v h="$hi" -v t="$ti" 'BEGIN { exit !(h > t) }' || bad "icosphere: exit 6 but Hausdorff $hi within $ti"

"$VP" sim --surface sphere --accuracy 0.01 --eps 0.1 --out "$tmp/x" >/dev/null 2>"$tmp/e.txt"; rc=$?
[ $rc -eq 2 ] && grep -q "give it alone" "$tmp/e.txt" || bad "--accuracy with --eps: exit $rc"
"$VP" sim --surface sphere --accuracy 0.01 --hausdorff 0 --out "$tmp/x" >/dev/null 2>&1 && bad "--accuracy with --hausdorff 0 accepted"

[ $fail -eq 0 ] && echo "accuracy: sphere within its target (Hausdorff $h <= $t), the coarse icosphere caught beyond it ($hi > $ti, exit 6), misuse refused"
exit $fail
