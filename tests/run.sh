#!/bin/sh
# Runs every test: the C test programs in $BUILD/tests and the scripts tests/t_*.sh.
# A test passes with exit status 0, is skipped with 77, fails otherwise.
# Ends with one line: "N passed, N failed, N skipped". Needs only POSIX sh and coreutils.
BUILD=${1:-build}
export VP_TEST_QUICK=${VP_TEST_QUICK:-0} BUILD VP="$BUILD/voroprobe"
pass=0; fail=0; skip=0; failed=""
logdir="$BUILD/test-logs"; mkdir -p "$logdir"
# every sim and scan keeps a copy of its session log here; all are proof-checked at the end
VP_AUDIT_DIR="$(pwd)/$BUILD/sessions"; export VP_AUDIT_DIR
rm -rf "$VP_AUDIT_DIR"; mkdir -p "$VP_AUDIT_DIR"
run_one() {
  name=$1; shift
  t0=$(date +%s%N)
  timeout "${VP_TEST_TIMEOUT:-900}" "$@" >"$logdir/$name.log" 2>&1
  rc=$?
  ds=$(( ($(date +%s%N) - t0 + 50000000) / 100000000 ))   # tenths of a second, rounded
  dt="$((ds / 10)).$((ds % 10))"
  case $rc in
    0) pass=$((pass+1)); printf 'PASS  %-28s %6ss  %s\n' "$name" "$dt" "$(tail -n 1 "$logdir/$name.log")";;
    77) skip=$((skip+1)); printf 'SKIP  %-28s         %s\n' "$name" "$(tail -n 1 "$logdir/$name.log")";;
    *) fail=$((fail+1)); failed="$failed $name"
       printf 'FAIL  %-28s (exit %d) log: %s\n' "$name" "$rc" "$logdir/$name.log"
       tail -n 15 "$logdir/$name.log" | sed 's/^/      /';;
  esac
}
for t in "$BUILD"/tests/*/test_*; do
  [ -x "$t" ] || continue
  run_one "$(basename "$t")" "$t"
done
for s in tests/t_*.sh; do
  [ -f "$s" ] || continue
  run_one "$(basename "$s" .sh)" sh "$s"
done
run_one session_proofs sh tests/verify_sessions.sh "$VP_AUDIT_DIR"
[ -n "$failed" ] && echo "failed:$failed"
echo "$pass passed, $fail failed, $skip skipped"
[ "$fail" -eq 0 ]
