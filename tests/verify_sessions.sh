#!/bin/sh
# The proof check of every session the tests produced: tests/run.sh sets VP_AUDIT_DIR, so each
# sim and scan keeps a copy of its log there; here `voroprobe log verify` (which shares no code
# with the planner) checks that every MOVE in each lay in space proven free before it was made.
# Exit 0 when every log is proven; a log the tests damaged on purpose (unreadable: exit 3) is
# counted apart, never as proven.
DIR=${1:?usage: verify_sessions.sh DIR}
VP=${VP:-build/voroprobe}
n=0; ok=0; bad=0; unread=0; moves=0
for f in "$DIR"/*; do
  [ -f "$f" ] || continue
  n=$((n+1))
  out=$("$VP" log verify "$f" 2>&1); rc=$?
  case $rc in
    0) ok=$((ok+1))
       m=$(echo "$out" | sed -n 's/^verify: \([0-9]*\) moves.*/\1/p' | tail -n 1)
       moves=$((moves + ${m:-0}));;
    3) unread=$((unread+1));;
    *) bad=$((bad+1)); echo "NOT PROVEN: $f"; echo "$out" | tail -n 5 | sed 's/^/  /';;
  esac
done
[ "$n" -gt 0 ] || { echo "session proofs: no session log was kept in $DIR (is VP_AUDIT_DIR set?)"; exit 1; }
echo "session proofs: $ok of $n session logs proven free ($moves moves), $bad not proven, $unread unreadable"
[ "$bad" -eq 0 ]
