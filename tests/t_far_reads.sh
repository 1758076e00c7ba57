#!/bin/sh
# Spots read past their edge (`scan --far-reads`, VP_PLAN_FAR_READS: body mode on a board with a
# backdrop). The beam of a probe goes on past its Voronoi edge and a triangulating head reads the
# spot wherever it lands, so the probe asks for its whole line through Omega: a reading past the
# edge's end proves the edge free, as a miss does, and becomes a sample where none lies within
# eps. boards/sim-enclosed.ini's dry run, the 100 mm torus at eps 6, with and without the rule
# (the same build). Checked, none of it by the planner's own code:
#   - host-sim's exact ray against the object: 0 false hits (every reading, a far one too, within
#     the noise of S), 0 hidden spots, 0 moves through the object, 0 head collisions;
#   - `log verify` proves every move free from the log alone (a reading frees its line up to it);
#   - CGAL (tests/cgal_object.cpp topology): closed 2-manifold of genus 1, both ways;
#   - far readings and samples counted, and fewer probes than without (2,647 against 3,137);
#   - a session cut short and resumed replays bit for bit and ends with the same mesh;
#   - the log's header is version 7 with the rule, 6 without;
#   - without the backdrop (the sight rule's boards) `--far-reads` is refused (exit 2), and so is
#     `sim --far-reads` without a body.
. tests/lib.sh
. tests/cgal_object.sh
cgal_object_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }
B=boards/sim-enclosed.ini
for v in far near; do
  x=""; [ $v = far ] && x=--far-reads
  "$VP" scan --board "$B" --dry-run --eps 6 --noise-tol 0.5 --log "$tmp/$v.vplog" --out "$tmp/$v" --quiet --json $x \
    >"$tmp/$v.out" 2>&1
  rc=$?
  [ $rc -eq 0 ] || bad "$v: exit $rc ($(grep '^mesh' "$tmp/$v.out"))"
  tail -n 1 "$tmp/$v.out" | grep -q '^{.*"probes":' || bad "$v: no JSON summary"
  for k in through head_collisions hidden_spots false_hits; do
    [ "$(field "$tmp/$v.out" $k)" = 0 ] || bad "$v: $k $(field "$tmp/$v.out" $k)"
  done
  grep -q ' 0 false hits, 0 hidden spots, 0 moves through the object' "$tmp/$v.out" || bad "$v: $(grep 'probe error' "$tmp/$v.out")"
  "$CO" topology "$tmp/$v.off" | grep -q '"manifold":true,"closed":true,"components":1,"genus":1}' ||
    bad "$v: CGAL topology: $("$CO" topology "$tmp/$v.off")"
  "$VP" log verify "$tmp/$v.vplog" >"$tmp/$v.verify" 2>&1 || bad "$v: log verify: $(tail -n 1 "$tmp/$v.verify")"
done
fr=$(field "$tmp/far.out" far_reads); fs=$(field "$tmp/far.out" far_samples)
[ "${fr:-0}" -gt 0 ] && [ "${fs:-0}" -gt 0 ] && [ "$fs" -le "$fr" ] || bad "far: ${fr:-no} far readings, ${fs:-no} samples"
grep -q "^body: $fr spots read past their edge's end (the edge free), $fs of them made samples" "$tmp/far.out" ||
  bad "far: the summary does not name them"
[ -z "$(field "$tmp/near.out" far_reads)" ] || bad "near: far readings without --far-reads"
"$VP" log dump "$tmp/far.vplog" 2>/dev/null | head -n 1 | grep -q 'format version 7,' || bad "far: the header is not version 7"
"$VP" log dump "$tmp/near.vplog" 2>/dev/null | head -n 1 | grep -q 'format version 6,' || bad "near: the header is not version 6"
pf=$(field "$tmp/far.out" probes); pn=$(field "$tmp/near.out" probes)
[ "${pf:-0}" -gt 0 ] && [ "$pf" -lt "$pn" ] || bad "far: $pf probes, not fewer than $pn without the rule"
# the far session's probes ask for more than their edge: their ranges run on through Omega
mr() { "$VP" log dump "$1" --csv 2>/dev/null | awk -F, '$3 == "probe" { n++; s += $10 } END { if (n) printf "%.1f", s / n }'; }
mf=$(mr "$tmp/far.vplog"); mn=$(mr "$tmp/near.vplog")
awk -v a="$mf" -v b="$mn" 'BEGIN { exit !(a > 1.2 * b && b > 0) }' || bad "far: mean range asked $mf mm, against $mn without the rule"
# cut short and resumed: the replay reissues the planner's commands bit for bit
"$VP" scan --board "$B" --dry-run --eps 6 --noise-tol 0.5 --log "$tmp/r.vplog" --out "$tmp/r" --quiet --stop-after 4000 \
  --far-reads >"$tmp/r1.out" 2>&1
[ $? -eq 3 ] || bad "cut short: not stopped (exit 3 expected)"
"$VP" scan --board "$B" --dry-run --log "$tmp/r.vplog" --out "$tmp/r" --quiet --resume --json >"$tmp/r2.out" 2>&1 ||
  bad "resume: exit $? ($(tail -n 2 "$tmp/r2.out" | head -n 1))"
cmp -s "$tmp/r.off" "$tmp/far.off" || bad "resume: the mesh differs from the session run at once"
"$VP" log check "$tmp/r.vplog" >"$tmp/r.check" 2>&1 && grep -q 'reissues all .* commands bit for bit' "$tmp/r.check" ||
  bad "resume: log check: $(grep replay "$tmp/r.check")"
# no backdrop, or no body: refused (a miss asked that far would meet the sight rule more often)
grep -v '^backdrop' "$B" >"$tmp/open.ini"
"$VP" scan --board "$tmp/open.ini" --dry-run --eps 12 --log "$tmp/o.vplog" --quiet --far-reads >"$tmp/o.out" 2>&1
orc=$?
[ $orc -eq 2 ] && grep -q -- '--far-reads needs a board in body mode (\[omega\] clearance) with a backdrop' "$tmp/o.out" ||
  bad "without the backdrop: exit $orc, not refused ($(head -n 1 "$tmp/o.out"))"
[ -e "$tmp/o.vplog" ] && bad "without the backdrop: a log was written"
# sim: only with a body
"$VP" sim --surface sphere --eps-rel 0.1 --far-reads --no-log --quiet >"$tmp/s.out" 2>&1
src=$?
[ $src -eq 2 ] && grep -q -- '--far-reads reads on past a body-mode probe.s edge: give --clearance too' "$tmp/s.out" ||
  bad "sim without --clearance: exit $src, not refused"
[ $fail = 0 ] || exit 1
echo "t_far_reads: 100 mm torus at eps 6 on the enclosed board: $pf probes ($fr read past their edge, $fs samples) against $pn without; both closed, genus 1 (CGAL), 0 false hits, logs verified; resumed bit for bit; refused without walls"
