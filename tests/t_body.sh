#!/bin/sh
# A head with a body (body mode: it stays outside Omega and probes every Voronoi edge along its
# line from dOmega) reaches fine resolution on the rpi4 board's dry run: a line that meets S
# before its edge gives a sample seen from elsewhere (a point of S within eps of the unseen
# facet, inserted when no sample lies within eps/4), so the edges occluded from dOmega get
# resolved instead of left open. At eps 5 and 3 mm (the board's eps is 10): a closed 2-manifold,
# within 1 mm of the object at eps 3 (host-sim's Hausdorff), 0 moves through the object, 0 head
# collisions, the log proven free. (The build before this rule left 4 and 19 edges open at eps 5
# and 3: `git show 1e63c8a`.)
. tests/lib.sh
B=$BUILD
out=""
for e in 5 3; do
  o="$tmp/e$e"
  "$VP" scan --board boards/rpi4-gantry.ini --dry-run --eps $e --log "$o.vplog" --json --quiet >"$o.txt" 2>"$o.err"
  rc=$?
  [ $rc -eq 0 ] && [ "$(field "$o.txt" closed)" = true ] || bad "eps $e: exit $rc, not closed ($(tail -n 1 "$o.txt" | cut -c1-160))"
  [ "$(field "$o.txt" through)" = 0 ] && [ "$(field "$o.txt" head_collisions)" = 0 ] || bad "eps $e: moves through or head collisions"
  h=$(field "$o.txt" hausdorff)
  "$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "eps $e: log verify: $(tail -n 1 "$o.verify")"
  out="$out eps $e: $(field "$o.txt" vertices) vertices, $(field "$o.txt" probes) probes, within $h mm, $(field "$o.txt" machine_s) s of machine time;"
done
awk -v h="$(field "$tmp/e3.txt" hausdorff)" 'BEGIN { exit !(h > 0 && h <= 1.0) }' || bad "eps 3: Hausdorff $(field "$tmp/e3.txt" hausdorff) mm, above 1 mm"
# a miss must be seen: the 36 mm torus, its inner side lit through a hole the head cannot enter
# and often hidden from the camera; with the sight rule it closes at eps 5 with genus 1 (CGAL)
# (at eps 6 the build before the sight rule ended open, 8 edges, and so does the planner since
# the aim's tolerance is eps: 6 mm is above the tube's 5.4 mm radius; tests/t_backdrop.sh has a
# torus left open without walls)
. tests/cgal_object.sh
cgal_object_build "$B" || bad "$CG_WHY"
o="$tmp/torus"
"$VP" scan --board boards/rpi4-gantry.ini --dry-run --surface 'torus*18@200,150,150' --eps 5 --log "$o.vplog" \
  --json --quiet >"$o.txt" 2>"$o.err"
rc=$?
[ $rc -eq 0 ] && [ "$(field "$o.txt" unseen_misses)" -gt 0 ] 2>/dev/null || bad "torus eps 5: exit $rc, $(field "$o.txt" unseen_misses) unseen misses"
[ "$(field "$o.txt" through)" = 0 ] && [ "$(field "$o.txt" head_collisions)" = 0 ] || bad "torus eps 5: moves through or head collisions"
[ -x "${CO:-}" ] && { "$CO" topology "$o.off" | grep -q '"closed":true,"components":1,"genus":1' || bad "torus eps 5: CGAL: $("$CO" topology "$o.off")"; }
"$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "torus eps 5: log verify: $(tail -n 1 "$o.verify")"
out="$out the 36 mm torus at eps 5 genus 1 (CGAL), $(field "$o.txt" unseen_misses) misses not seen taken as unreadable;"
[ $fail = 0 ] || exit 1
echo "t_body: rpi4 body mode closed at$out 0 moves through, 0 head collisions, logs verified"
