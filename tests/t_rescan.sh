#!/bin/sh
# `sim --rescan`: a second scan of an object scanned before (issue: objects that change).
# (1) the object unchanged (sphere, torus, genus2, ellipsoid, blobby, a tessellated sphere; a
#     body-mode run): the mesh is the old one byte for byte, with at most 35% of the old
#     session's probes (the figures are printed; the README's table comes from here); with
#     --rescan-sparse the same mesh with at most 30% of them, and the samples it left out (those
#     no PROBE after the RESCAN event hit) no two neighbours in CGAL's Delaunay triangulation of
#     the samples (tests/sparse_check.py, which must fail when one more is taken as left out);
# (2) a bump on 5% of the sphere's area, 0.15 high (tests/rescan_objects.py): closed, genus 0, as close to
#     the bumped object as a fresh scan of it (host-sim's measure and CGAL's), the probes beyond
#     the re-measuring at most a quarter of a fresh scan's; CGAL measures the old mesh far from
#     the bumped object (the measure's case that must fail); the same with --rescan-sparse: as
#     close as a fresh scan (the change is seen through the samples measured around it); the
#     log says which old samples were kept (replay --samples): CGAL finds each kept one on the
#     bumped object and each removed one off it (also for the swollen torus, sparse);
# (2b) a torus whose tube swells into the hole: closed, genus 1; CGAL (tests/cgal_moves.cpp)
#     finds no move after the RESCAN event through the swollen torus, and finds the old
#     session's moves through it (the checker's case that must fail: trusting the old proofs
#     would have driven the head through the swelling);
# (3) one part of two moved by about 2 eps: closed, 2 components, genus 1, 0 collisions;
# (4) a re-scan paused and resumed ends with the same mesh; every log verified (log verify) and
#     replayed to the same mesh;
# (5) refusals: an object outside the session's Omega, --resume with --rescan, the old log as
#     the new one (also by another name), a session option (--seed) with --rescan; --no-log
#     writes no log; --rescan-sparse without a re-scan; a new part far from the old object,
#     which the re-scan never meets, ends not closed (exit 4) and says so;
# (6) `scan --rescan` on the rpi4 gantry's dry run: the same object gives the old mesh byte for
#     byte (also with --rescan-sparse); a smaller one closes with 0 moves through it and 0 head
#     collisions, its log verified;
#     paused and resumed, the same mesh.
. tests/lib.sh
B=$BUILD
S="--quiet --sync close"
rfield() { tail -n 1 "$1" | sed -n "s/.*\"rescan\":{[^}]*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }
. tests/cgal_moves.sh
cgal_moves_build "$B" || bad "$CG_WHY"
. tests/cgal_object.sh
cgal_object_build "$B" || bad "$CG_WHY"
mkdir -p "$tmp/obj" && python3 tests/rescan_objects.py "$tmp/obj" 0.15 || bad "tests/rescan_objects.py"

# which old samples a re-scan kept, from its log (replay --samples), against the object now (CGAL):
# every one kept lies on it, every one removed does not
kept_on() { # LOG OBJECT.off WHAT KEPT REMOVED (the figures the re-scan reported)
  "$VP" replay "$1" --out "$tmp/ks" --samples --quiet || { bad "$3: replay --samples"; return; }
  awk -F, 'NR > 1 && $5 == 0 { print $2, $3, $4 }' "$tmp/ks.samples.csv" >"$tmp/ks.pts"
  awk -F, 'NR > 1 && $5 == 0 { print ($6 == "" ? "kept" : "removed") }' "$tmp/ks.samples.csv" >"$tmp/ks.what"
  "$CO" distance "$2" "$tmp/ks.pts" >"$tmp/ks.d" || { bad "$3: CGAL's distances"; return; }
  r=$(paste -d' ' "$tmp/ks.d" "$tmp/ks.what" | awk -v tol=1e-9 '
    $2 == "kept" { k++; if ($1 > km) km = $1; if ($1 > tol) kb++ }
    $2 == "removed" { r++; if ($1 <= tol) rb++; if (rm == "" || $1 < rm) rm = $1 }
    END { printf "%d %d %d %d %g %g", k, r, kb, rb, km, rm }')
  set -- "$@" $r
  echo "$3, the log's samples (replay --samples): $6 kept, farthest ${10} from the object now (CGAL); $7 removed, nearest ${11}"
  [ "$6" = "$4" ] && [ "$7" = "$5" ] || bad "$3: replay --samples counts $6 kept, $7 removed; the re-scan said $4, $5"
  [ "$8" = 0 ] || bad "$3: $8 samples kept off the object now"
  [ "$9" = 0 ] || bad "$3: $9 samples removed that lie on the object now"
}

verified() { # LOG WHAT: log verify proves every move; replay gives the same mesh as PLY
  "$VP" log verify "$1" >"$tmp/v.txt" 2>&1 || { bad "$2: log verify: $(tail -n 1 "$tmp/v.txt")"; return; }
  "$VP" replay "$1" --out "$tmp/rep" >"$tmp/rep.txt" 2>&1 || { bad "$2: replay: $(tail -n 2 "$tmp/rep.txt")"; return; }
  cmp -s "$tmp/rep.ply" "$3" || bad "$2: the replayed mesh differs"
}

# moves after the RESCAN event (or before it: BEFORE) as a cgal_moves list, from the dump
moves() { # LOG after|before
  "$VP" log dump "$1" >"$tmp/d.txt" 2>/dev/null
  start=$(sed -n 's/^# start \([^,]*\),.*/\1/p' "$tmp/d.txt")
  "$VP" log dump "$1" --csv 2>/dev/null | awk -F, -v want="$2" -v start="$start" '
    NR == 1 { print "start " start; next }
    $3 == "event" && $20 == "rescan" { r = 1; if (want == "after") print "start " start; next }
    $3 == "move" && ((want == "after") == (r == 1)) { print "move " $1, $17, $18, $19 }'
}

# ---- (1) unchanged
for spec in sphere:0.03 torus:0.03 genus2:0.03 ellipsoid:0.03 blobby:0.03 "off:$tmp/obj/sphere.off:0.02" ellipsoid:0.04:body; do
  obj=$(echo "$spec" | sed 's/:[0-9.]*\(:body\)\{0,1\}$//'); e=$(echo "$spec" | sed 's/.*:\([0-9.]*\)\(:body\)\{0,1\}$/\1/')
  extra=""; name=$(basename "$obj" | tr -c 'a-z0-9\n' _)
  case $spec in *:body) extra="--clearance 0.1"; name="$name-body";; esac
  "$VP" sim --surface "$obj" --eps-rel "$e" $extra --out "$tmp/$name" $S >/dev/null 2>&1 || { bad "$name: fresh scan"; continue; }
  "$VP" sim --rescan "$tmp/$name.vplog" --json $S >"$tmp/$name-r.json" 2>&1; rc=$?
  [ $rc -eq 0 ] || { bad "$name: re-scan exit $rc"; tail -3 "$tmp/$name-r.json"; continue; }
  cmp -s "$tmp/$name.ply" "$tmp/$name.rescan.ply" || bad "$name: the re-scan's mesh is not the old one"
  p=$(rfield "$tmp/$name-r.json" probes); o=$(rfield "$tmp/$name-r.json" old_probes); k=$(rfield "$tmp/$name-r.json" kept)
  d=$(rfield "$tmp/$name-r.json" dropped); rp=$(rfield "$tmp/$name-r.json" reproved)
  ratio=$(awk -v p="$p" -v o="$o" 'BEGIN { printf "%.3f", p / o }')
  echo "unchanged $name (eps-rel $e): $p probes of the old $o ($ratio), samples kept $k, removed $d, steps proven again $rp"
  awk -v r="$ratio" 'BEGIN { exit !(r <= 0.35) }' || bad "$name: the re-scan took $ratio of the old probes"
  [ "$d" = 0 ] || bad "$name: $d samples removed from an unchanged object"
  verified "$tmp/$name.rescan.vplog" "$name" "$tmp/$name.rescan.ply"
  "$VP" sim --rescan "$tmp/$name.vplog" --rescan-sparse --out "$tmp/$name-sp" --json $S >"$tmp/$name-sp.json" 2>&1; rc=$?
  [ $rc -eq 0 ] || { bad "$name: sparse re-scan exit $rc"; tail -3 "$tmp/$name-sp.json"; continue; }
  cmp -s "$tmp/$name.ply" "$tmp/$name-sp.ply" || bad "$name: the sparse re-scan's mesh is not the old one"
  p=$(rfield "$tmp/$name-sp.json" probes); sk=$(rfield "$tmp/$name-sp.json" skipped)
  ratio=$(awk -v p="$p" -v o="$o" 'BEGIN { printf "%.3f", p / o }')
  echo "  --rescan-sparse: $p probes ($ratio), $sk samples not measured"
  awk -v r="$ratio" 'BEGIN { exit !(r <= 0.30) }' || bad "$name: the sparse re-scan took $ratio of the old probes"
  if [ -x "$CO" ]; then
    # which samples it left out, from its log, against CGAL's Delaunay triangulation of them
    "$VP" log dump "$tmp/$name-sp.vplog" --csv >"$tmp/sp.csv" 2>/dev/null
    "$CO" edges "$tmp/$name.off" >"$tmp/edges.txt" || bad "$name: CGAL's Delaunay edges"
    python3 tests/sparse_check.py "$tmp/$name.off" "$tmp/sp.csv" "$tmp/edges.txt" "$sk" >"$tmp/spc.txt" ||
      bad "$name: sparse: $(cat "$tmp/spc.txt")"
    python3 tests/sparse_check.py "$tmp/$name.off" "$tmp/sp.csv" "$tmp/edges.txt" "$sk" must-fail >/dev/null ||
      bad "$name: the sparse check passes two neighbours left out"
    echo "    $(cat "$tmp/spc.txt")"
  fi
  verified "$tmp/$name-sp.vplog" "$name sparse" "$tmp/$name-sp.ply"
done

# ---- (2) a bump on 5% of the area
"$VP" sim --rescan "$tmp/sphere_off.vplog" --surface "off:$tmp/obj/sphere_bump.off" --out "$tmp/bump" --json $S >"$tmp/bump.json" 2>&1
rc=$?
"$VP" sim --surface "off:$tmp/obj/sphere_bump.off" --eps-rel 0.02 --out "$tmp/fresh-bump" --json $S >"$tmp/fresh-bump.json" 2>&1
if [ $rc -ne 0 ]; then bad "bump: re-scan exit $rc"; tail -3 "$tmp/bump.json"; else
  [ "$(field "$tmp/bump.json" genus)" = 0 ] || bad "bump: genus $(field "$tmp/bump.json" genus)"
  p=$(rfield "$tmp/bump.json" probes); k=$(rfield "$tmp/bump.json" kept); d=$(rfield "$tmp/bump.json" dropped)
  fp=$(field "$tmp/fresh-bump.json" probes); h=$(field "$tmp/bump.json" hausdorff); fh=$(field "$tmp/fresh-bump.json" hausdorff)
  col=$(field "$tmp/bump.json" collisions)
  ch=$(chaus "$tmp/bump.off" "$tmp/obj/sphere_bump.off"); cfh=$(chaus "$tmp/fresh-bump.off" "$tmp/obj/sphere_bump.off")
  cold=$(chaus "$tmp/sphere_off.off" "$tmp/obj/sphere_bump.off")
  echo "bump on 5% of the area: $p probes ($k samples measured and kept, $d removed; a fresh scan of the bumped sphere $fp);" \
       "Hausdorff $h (fresh $fh), by CGAL $ch (fresh $cfh; the old mesh $cold); collisions $col"
  awk -v p="$p" -v k="$k" -v d="$d" -v f="$fp" 'BEGIN { exit !(p - k - d <= 0.25 * f) }' ||
    bad "bump: $p probes: more than a quarter of a fresh scan beyond the re-measuring"
  awk -v d="$d" -v k="$k" 'BEGIN { exit !(d >= 1 && d <= 0.15 * (k + d)) }' || bad "bump: $d samples removed of $((k + d))"
  awk -v h="$h" -v f="$fh" -v c="$ch" -v cf="$cfh" 'BEGIN { exit !(h <= 1.5 * f && c <= 1.5 * cf) }' ||
    bad "bump: Hausdorff $h / CGAL $ch against a fresh scan's $fh / $cfh"
  awk -v c="$cold" 'BEGIN { exit !(c >= 0.13) }' || bad "bump: CGAL measures the old mesh only $cold from the bumped sphere"
  [ "$col" = 0 ] || bad "bump: $col collisions"
  verified "$tmp/bump.vplog" bump "$tmp/bump.ply"
  if [ -x "$CO" ]; then
    kept_on "$tmp/bump.vplog" "$tmp/obj/sphere_bump.off" bump "$k" "$d"
    # the checker's case that must fail: the same samples against the sphere before the bump
    "$CO" distance "$tmp/obj/sphere.off" "$tmp/ks.pts" | paste -d' ' - "$tmp/ks.what" |
      awk '$2 == "removed" && $1 <= 1e-9 { n++ } END { exit !(n > 0) }' ||
      bad "bump: against the sphere before the bump, no removed sample lies on it (the check must fail there)"
  fi
fi
"$VP" sim --rescan "$tmp/sphere_off.vplog" --rescan-sparse --surface "off:$tmp/obj/sphere_bump.off" --out "$tmp/bsp" --json $S \
  >"$tmp/bsp.json" 2>&1 || bad "bump, sparse: exit $?"
h=$(field "$tmp/bsp.json" hausdorff); ch=$(chaus "$tmp/bsp.off" "$tmp/obj/sphere_bump.off")
echo "bump, --rescan-sparse: $(rfield "$tmp/bsp.json" probes) probes, $(rfield "$tmp/bsp.json" skipped) samples not measured," \
     "$(rfield "$tmp/bsp.json" dropped) removed ($(rfield "$tmp/bsp.json" moved) moved); genus $(field "$tmp/bsp.json" genus)," \
     "Hausdorff $h, by CGAL $ch"
[ "$(field "$tmp/bsp.json" genus)" = 0 ] && [ "$(field "$tmp/bsp.json" collisions)" = 0 ] || bad "bump, sparse: genus or collisions"
awk -v h="$ch" -v f="${cfh:-0}" 'BEGIN { exit !(h <= 1.5 * f + 1e-9) }' || bad "bump, sparse: CGAL's Hausdorff $ch (fresh $cfh)"
verified "$tmp/bsp.vplog" "bump sparse" "$tmp/bsp.ply"

# ---- (2b) a torus whose tube swells into its hole, where the old session's head went
"$VP" sim --surface "off:$tmp/obj/torus.off" --eps-rel 0.03 --out "$tmp/torus_off" $S >/dev/null 2>&1 || bad "torus.off: fresh scan"
"$VP" sim --rescan "$tmp/torus_off.vplog" --surface "off:$tmp/obj/torus_swollen.off" --out "$tmp/swollen" --json $S \
  >"$tmp/swollen.json" 2>&1 || bad "swollen torus: re-scan exit $?"
[ "$(field "$tmp/swollen.json" genus)" = 1 ] && [ "$(field "$tmp/swollen.json" collisions)" = 0 ] ||
  bad "swollen torus: genus $(field "$tmp/swollen.json" genus), collisions $(field "$tmp/swollen.json" collisions)"
echo "swollen torus: $(rfield "$tmp/swollen.json" probes) probes (the old session $(rfield "$tmp/swollen.json" old_probes))," \
     "kept $(rfield "$tmp/swollen.json" kept), removed $(rfield "$tmp/swollen.json" dropped), route steps proven again" \
     "$(rfield "$tmp/swollen.json" reproved) ($(rfield "$tmp/swollen.json" blocked) blocked), Hausdorff $(field "$tmp/swollen.json" hausdorff)"
verified "$tmp/swollen.vplog" "swollen torus" "$tmp/swollen.ply"
if [ -x "${CG:-}" ]; then
  moves "$tmp/swollen.vplog" after >"$tmp/after.txt"
  "$CG" "$tmp/obj/torus_swollen.off" "$tmp/after.txt" >"$tmp/cga.txt" 2>&1 || bad "swollen torus: CGAL: $(tail -n 1 "$tmp/cga.txt")"
  moves "$tmp/torus_off.vplog" before >"$tmp/before.txt"
  "$CG" "$tmp/obj/torus_swollen.off" "$tmp/before.txt" >"$tmp/cgb.txt" 2>&1 &&
    bad "swollen torus: CGAL finds none of the old session's moves through it (the check must fail there)"
  echo "CGAL, the swollen torus: the re-scan's moves: $(tail -n 1 "$tmp/cga.txt"); the old session's: $(tail -n 1 "$tmp/cgb.txt")"
fi
# the same sparse: samples left out that a changed neighbour frees in the pass from inside are
# measured from outside first, as without --rescan-sparse (no more probes than that)
"$VP" sim --rescan "$tmp/torus_off.vplog" --rescan-sparse --surface "off:$tmp/obj/torus_swollen.off" --out "$tmp/swsp" --json $S \
  >"$tmp/swsp.json" 2>&1 || bad "swollen torus, sparse: exit $?"
[ "$(field "$tmp/swsp.json" genus)" = 1 ] && [ "$(field "$tmp/swsp.json" collisions)" = 0 ] || bad "swollen torus, sparse: genus or collisions"
p=$(rfield "$tmp/swsp.json" probes); pn=$(rfield "$tmp/swollen.json" probes)
echo "swollen torus, --rescan-sparse: $p probes ($pn measuring every sample), $(rfield "$tmp/swsp.json" skipped) not measured," \
     "removed $(rfield "$tmp/swsp.json" dropped) ($(rfield "$tmp/swollen.json" dropped))"
[ "$p" -le "$pn" ] || bad "swollen torus, sparse: $p probes, more than measuring every sample ($pn)"
verified "$tmp/swsp.vplog" "swollen torus sparse" "$tmp/swsp.ply"
[ -x "$CO" ] && kept_on "$tmp/swsp.vplog" "$tmp/obj/torus_swollen.off" "swollen torus sparse" \
  "$(( $(rfield "$tmp/swsp.json" kept) + $(rfield "$tmp/swsp.json" skipped) ))" "$(rfield "$tmp/swsp.json" dropped)"
if [ -x "${CG:-}" ]; then
  moves "$tmp/swsp.vplog" after >"$tmp/after.txt"
  "$CG" "$tmp/obj/torus_swollen.off" "$tmp/after.txt" >"$tmp/cga.txt" 2>&1 || bad "swollen torus, sparse: CGAL: $(tail -n 1 "$tmp/cga.txt")"
fi

# ---- (3) one part of two moved by about 2 eps
"$VP" sim --surface "sphere@3,0,0+torus" --eps-rel 0.02 --out "$tmp/two" $S >/dev/null 2>&1 || bad "two: fresh scan"
"$VP" sim --rescan "$tmp/two.vplog" --surface "sphere@3.25,0,0+torus" --json $S >"$tmp/two-r.json" 2>&1; rc=$?
[ $rc -eq 0 ] || bad "moved part: exit $rc"
[ "$(field "$tmp/two-r.json" components)" = 2 ] && [ "$(field "$tmp/two-r.json" genus)" = 1 ] ||
  bad "moved part: $(field "$tmp/two-r.json" components) components, genus $(field "$tmp/two-r.json" genus)"
[ "$(field "$tmp/two-r.json" collisions)" = 0 ] || bad "moved part: collisions"
echo "one part of two moved by 0.25 (eps $(field "$tmp/two-r.json" eps)): $(rfield "$tmp/two-r.json" probes) probes" \
     "(the old session $(rfield "$tmp/two-r.json" old_probes)), kept $(rfield "$tmp/two-r.json" kept)," \
     "removed $(rfield "$tmp/two-r.json" dropped), Hausdorff $(field "$tmp/two-r.json" hausdorff)"
verified "$tmp/two.rescan.vplog" "moved part" "$tmp/two.rescan.ply"

# ---- (4) paused and resumed
"$VP" sim --rescan "$tmp/sphere_off.vplog" --surface "off:$tmp/obj/sphere_bump.off" --out "$tmp/cut" --stop-after 700 $S >/dev/null 2>&1
rc=$?
[ $rc -eq 3 ] || bad "paused re-scan: exit $rc (3 expected)"
"$VP" sim --resume "$tmp/cut.vplog" $S >/dev/null 2>&1 || bad "resumed re-scan: exit $?"
cmp -s "$tmp/cut.ply" "$tmp/bump.ply" || bad "a re-scan paused and resumed ends with another mesh"
verified "$tmp/cut.vplog" "paused re-scan" "$tmp/cut.ply"

# ---- (6) on a machine: the rpi4 gantry's dry run (its kinematics, steps, rendered frames)
R="scan --board boards/rpi4-gantry.ini --dry-run --eps 6 --quiet"
"$VP" $R --log "$tmp/m.vplog" >/dev/null 2>&1 || bad "rpi4 dry run: exit $?"
"$VP" scan --rescan "$tmp/m.vplog" --log "$tmp/mr.vplog" --quiet --json >"$tmp/mr.json" 2>&1 || bad "rpi4 re-scan: exit $?"
cmp -s "$tmp/m.ply" "$tmp/mr.ply" || bad "rpi4 re-scan: not the old mesh"
echo "rpi4 dry run, the same object: $(rfield "$tmp/mr.json" probes) probes (the first scan $(rfield "$tmp/mr.json" old_probes))," \
     "$(field "$tmp/mr.json" machine_s) s of machine time, the old mesh byte for byte"
"$VP" scan --rescan "$tmp/m.vplog" --rescan-sparse --log "$tmp/ms.vplog" --quiet --json >"$tmp/ms.json" 2>&1 ||
  bad "rpi4 sparse re-scan: exit $?"
cmp -s "$tmp/m.ply" "$tmp/ms.ply" || bad "rpi4 sparse re-scan: not the old mesh"
"$VP" log verify "$tmp/ms.vplog" >/dev/null 2>&1 || bad "rpi4 sparse re-scan: log verify"
echo "rpi4 dry run, the same object, --rescan-sparse: $(rfield "$tmp/ms.json" probes) probes," \
     "$(rfield "$tmp/ms.json" skipped) samples not measured, $(field "$tmp/ms.json" machine_s) s of machine time, the old mesh"
"$VP" scan --rescan "$tmp/m.vplog" --log "$tmp/mc.vplog" --surface "ellipsoid*20@202,150,150" --quiet --json >"$tmp/mc.json" 2>&1 ||
  bad "rpi4 re-scan of a smaller object: exit $?"
[ "$(field "$tmp/mc.json" closed)" = true ] && [ "$(field "$tmp/mc.json" through)" = 0 ] && [ "$(field "$tmp/mc.json" head_collisions)" = 0 ] ||
  bad "rpi4 re-scan of a smaller object: closed $(field "$tmp/mc.json" closed), through $(field "$tmp/mc.json" through), head $(field "$tmp/mc.json" head_collisions)"
"$VP" log verify "$tmp/mc.vplog" >/dev/null 2>&1 || bad "rpi4 re-scan: log verify"
echo "rpi4 dry run, a smaller object (ellipsoid*20 for *24): $(rfield "$tmp/mc.json" probes) probes, kept $(rfield "$tmp/mc.json" kept)," \
     "removed $(rfield "$tmp/mc.json" dropped), within $(field "$tmp/mc.json" hausdorff) mm, 0 moves through, 0 head collisions"
"$VP" scan --rescan "$tmp/m.vplog" --log "$tmp/mp.vplog" --surface "ellipsoid*20@202,150,150" --quiet --stop-after 300 >/dev/null 2>&1
[ $? -eq 3 ] || bad "rpi4 re-scan paused: exit status"
"$VP" scan --log "$tmp/mp.vplog" --resume --quiet >/dev/null 2>&1 || bad "rpi4 re-scan resumed: exit $?"
cmp -s "$tmp/mp.ply" "$tmp/mc.ply" || bad "rpi4 re-scan paused and resumed: another mesh"

# ---- (5) refusals
"$VP" sim --rescan "$tmp/sphere.vplog" --surface "sphere*3" $S >"$tmp/o.txt" 2>&1
[ $? -eq 2 ] && grep -q "does not lie in the logged session's Omega" "$tmp/o.txt" || bad "an object outside Omega: $(cat "$tmp/o.txt")"
"$VP" sim --rescan "$tmp/sphere.vplog" --resume "$tmp/sphere.vplog" $S >"$tmp/o.txt" 2>&1
[ $? -ne 0 ] && grep -q "cannot go together" "$tmp/o.txt" || bad "--resume with --rescan: $(cat "$tmp/o.txt")"
"$VP" sim --rescan "$tmp/sphere.vplog" --log "$tmp/sphere.vplog" $S >"$tmp/o.txt" 2>&1
[ $? -ne 0 ] && grep -q "writes a new log" "$tmp/o.txt" || bad "the old log as the new one: $(cat "$tmp/o.txt")"

"$VP" sim --rescan "$tmp/sphere.vplog" --log "$tmp/./sphere.vplog" $S >"$tmp/o.txt" 2>&1
[ $? -ne 0 ] && grep -q "writes a new log" "$tmp/o.txt" || bad "the old log under another name: $(cat "$tmp/o.txt")"
"$VP" sim --rescan "$tmp/sphere.vplog" --seed 5 $S >"$tmp/o.txt" 2>&1
[ $? -ne 0 ] && grep -q "keeps the options of the session" "$tmp/o.txt" || bad "--seed with --rescan: $(cat "$tmp/o.txt")"
"$VP" sim --rescan "$tmp/sphere.vplog" --no-log --out "$tmp/nolog" $S >/dev/null 2>&1 || bad "--no-log with --rescan: exit $?"
[ -e "$tmp/nolog.vplog" ] && bad "--no-log with --rescan wrote a log"
# a new part the re-scan never meets (it keeps the old interior points): not closed around it, said
"$VP" sim --rescan "$tmp/sphere.vplog" --surface "sphere+sphere*0.05@1.2,1.2,-1.2" --out "$tmp/newpart" $S >"$tmp/o.txt" 2>&1
[ $? -eq 4 ] && grep -q "a part the re-scan never met" "$tmp/o.txt" || bad "a new part far away: $(tail -3 "$tmp/o.txt")"
"$VP" scan --rescan "$tmp/m.vplog" --log "$tmp/m.vplog" --quiet >"$tmp/o.txt" 2>&1
[ $? -eq 2 ] && grep -q "writes a new log" "$tmp/o.txt" || bad "scan: the old log as the new one: $(cat "$tmp/o.txt")"
"$VP" sim --surface sphere --eps 0.2 --rescan-sparse --no-log $S >"$tmp/o.txt" 2>&1
[ $? -eq 2 ] && grep -q "is for a re-scan" "$tmp/o.txt" || bad "sim --rescan-sparse alone: $(cat "$tmp/o.txt")"
"$VP" scan --board boards/rpi4-gantry.ini --dry-run --eps 6 --rescan-sparse --log "$tmp/x.vplog" --quiet >"$tmp/o.txt" 2>&1
[ $? -eq 2 ] && grep -q "goes with --rescan" "$tmp/o.txt" || bad "scan --rescan-sparse alone: $(cat "$tmp/o.txt")"

[ $fail -eq 0 ] && echo "rescan: unchanged objects give their mesh again, a bump and a moved part are scanned again where they changed"
exit $fail
