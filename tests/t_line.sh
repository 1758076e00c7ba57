#!/bin/sh
# A line laser (sim --line-laser N[,DEG]): each probe's frame gives N more rays, whose hits become
# samples where no sample lies within eps. For each object the same scan is run with a dot laser
# and with a 16-ray line laser; the line laser's session must
#   - close with the object's genus (exit 0) and report 0 collisions,
#   - have every move outside the object by the independent exact checker tests/cgal_moves.cpp
#     (CGAL; objects given as meshes), and pass `voroprobe log verify`,
#   - log every ray (as many RAY records as the JSON's rays; the header in format version 4),
#   - replay bit for bit to the same mesh bytes, and resume after a cut to the same mesh,
#   - probe less than the dot laser (the figure printed: probes, moves and travel saved).
# The cases the checks must catch: a RAY record moved to another origin (CRC made good again)
# is refused by replay, and a resume with another --line-laser is refused.
# The machine (port/vp_machine reading the line in rendered laser-off / laser-on frames,
# port/vp_line): boards/rpi4-gantry.ini's dry run with [rangefinder] laser = line closes with 0
# moves through the object, 0 head collisions, 0 false hits, every ray's point within the noise
# tolerance of the object, its log verified, in less machine time than the dot laser; a cut and
# resumed session ends with the same mesh.
# The meshes of ../shared/meshes are used when present (a fresh clone has only tests/meshes).
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
D="$BUILD/line"
SM=../shared/meshes
rm -rf "$D"; mkdir -p "$D" "$BUILD/safety"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
field() { sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" "$1" | tr -d '"'; }

. tests/cgal_moves.sh
cgal_moves_build "$BUILD" || { echo "FAIL: $CG_WHY"; exit 1; }

nrun=0; sp=0; sl=0; mp=0; ml=0
# one case: NAME SURFACE MESH(or -) GENUS OPTIONS...
run() {
  name=$1; surf=$2; mesh=$3; genus=$4; shift 4
  case "$surf" in off:*) [ -f "${surf#off:}" ] || { echo "skip $name (${surf#off:} not found)"; return; };; esac
  o="$D/$name"
  "$VP" sim --surface "$surf" "$@" --json --quiet --hausdorff 0 --out "$o-dot" --log "$o-dot.vplog" >"$o-dot.json" 2>"$o-dot.err"
  rd=$?
  "$VP" sim --surface "$surf" "$@" --line-laser 16 --json --quiet --hausdorff 0 --out "$o" --log "$o.vplog" >"$o.json" 2>"$o.err"
  rc=$?
  [ $rd = 0 ] || bad "$name: the dot laser's scan exits $rd"
  [ $rc = 0 ] || bad "$name: the line laser's scan exits $rc"
  [ "$(field "$o.json" genus)" = "$genus" ] || bad "$name: genus $(field "$o.json" genus), expected $genus"
  [ "$(field "$o.json" collisions)" = 0 ] || bad "$name: collisions $(field "$o.json" collisions)"
  pd=$(field "$o-dot.json" probes); pl=$(field "$o.json" probes)
  md=$(field "$o-dot.json" moves); mv=$(field "$o.json" moves)
  rays=$(field "$o.json" rays); rs=$(field "$o.json" ray_samples)
  [ -n "$rs" ] && [ "$rs" -gt 0 ] || bad "$name: no ray became a sample"
  [ "$pl" -lt "$pd" ] || bad "$name: the line laser probes $pl times, the dot laser $pd"
  "$VP" log dump "$o.vplog" --csv >"$o.csv" || bad "$name: log dump"
  nr=$(awk -F, '$3 == "ray"' "$o.csv" | wc -l)
  [ "$nr" = "$rays" ] || bad "$name: $nr RAY records, the session fed $rays rays"
  "$VP" log check "$o.vplog" | grep -q 'format version 4' || bad "$name: the header is not format version 4"
  "$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "$name: log verify: $(tail -n 1 "$o.verify")"
  if [ "$mesh" != - ]; then
    start=$("$VP" log dump "$o.vplog" | sed -n '/^# start /{s/^# start \([^ ]*\) \([^ ]*\) \([^ ,]*\),.*/\1,\2,\3/p;q;}')
    cg=$("$CG" "$mesh" "$o.csv" --start "$start" 2>&1 | tail -n 1)
    case "$cg" in "moves "*", through 0, inside 0, first none") ;; *) bad "$name: CGAL: $cg";; esac
  else cg="(analytic surface)"; fi
  "$VP" replay "$o.vplog" --out "$o-replay" >"$o-replay.out" 2>&1 || bad "$name: replay: $(tail -n 1 "$o-replay.out")"
  cmp -s "$o.off" "$o-replay.off" || bad "$name: the replayed mesh differs"
  nrun=$((nrun + 1)); sp=$((sp + pd)); sl=$((sl + pl)); mp=$((mp + md)); ml=$((ml + mv))
  printf '%-10s dot laser %6s probes %6s moves travel %-8s | line laser %6s probes (%s%%) %6s moves (%s%%) travel %-8s, %s vertices, %s samples from %s rays; CGAL: %s\n' \
    "$name" "$pd" "$md" "$(field "$o-dot.json" travel)" "$pl" "$(awk "BEGIN{printf \"%+.0f\", 100*($pl-$pd)/$pd}")" \
    "$mv" "$(awk "BEGIN{printf \"%+.0f\", 100*($mv-$md)/$md}")" "$(field "$o.json" travel)" "$(field "$o.json" vertices)" "$rs" "$rays" "$cg"
}
run sphere sphere - 0 --eps 0.05
run torus torus - 1 --eps 0.05
run cube off:tests/meshes/cube.off tests/meshes/cube.off 0 --eps-rel 0.02
run tetra off:tests/meshes/tetra.off tests/meshes/tetra.off 0 --eps-rel 0.02
run fandisk off:$SM/fandisk.off $SM/fandisk.off 0 --eps-rel 0.01
run knot off:$SM/knot.off $SM/knot.off 1 --eps-rel 0.01
run noisy sphere - 0 --eps 0.05 --noise 0.001 --dropout 0.05

# ---- cut, resumed: the same mesh as the whole session (a frame is never split by the cut)
for n in 700 701; do
  o="$D/cut$n"
  "$VP" sim --surface torus --eps 0.05 --line-laser 16 --stop-after $n --quiet --hausdorff 0 --out "$o" >/dev/null 2>&1
  "$VP" sim --resume "$o.vplog" --quiet >/dev/null 2>&1 || bad "resume after $n commands"
  cmp -s "$o.off" "$D/torus.off" || bad "resumed after $n commands: the mesh differs from the whole session's"
done
"$VP" sim --resume "$D/cut700.vplog" --line-laser 8 --quiet --out "$D/cut-other" >"$D/cut-other.out" 2>&1 &&
  bad "a resume with another --line-laser was accepted"
grep -q "line laser" "$D/cut-other.out" || bad "a resume with another --line-laser: '$(tail -n 1 "$D/cut-other.out")'"

# ---- a RAY moved to another origin (its CRC made good again): replay must refuse it
python3 - "$D/torus.vplog" "$D/forged.vplog" <<'EOF' || bad "could not forge a RAY record"
import struct, sys, zlib
b = bytearray(open(sys.argv[1], 'rb').read())
p = struct.unpack_from('<I', b, 12)[0]          # the header's length
while p < len(b):
    n, seq, typ = struct.unpack_from('<IIH', b, p)
    if typ == 4:                                  # the first RAY: its origin x moved by 1e-3
        x = struct.unpack_from('<d', b, p + 12)[0]
        struct.pack_into('<d', b, p + 12, x + 1e-3)
        struct.pack_into('<I', b, p + n - 4, zlib.crc32(bytes(b[p:p + n - 4])) & 0xffffffff)
        break
    p += n
open(sys.argv[2], 'wb').write(b)
EOF
"$VP" log check "$D/forged.vplog" --no-replay >/dev/null 2>&1 || bad "the forged log's CRCs are not good (the forgery, not the replay, would be caught)"
"$VP" replay "$D/forged.vplog" --out "$D/forged" >"$D/forged.out" 2>&1 && bad "replay accepted a RAY from another origin"
grep -q "RAY differs in its origin" "$D/forged.out" || bad "replay of the forged RAY: '$(tail -n 1 "$D/forged.out")'"

# ---- the machine: the rpi4 gantry's dry run, dot and line laser
o="$D/rpi4"
sed 's/^near_spots = too-close$/near_spots = too-close\nlaser = line\nfan = 30/' boards/rpi4-gantry.ini >"$o-line.ini"
grep -q '^laser = line' "$o-line.ini" || bad "the rpi4 board's line-laser copy was not made"
"$VP" scan --board boards/rpi4-gantry.ini --dry-run --eps 10 --json --log "$o-dot.vplog" --out "$o-dot" >"$o-dot.out" 2>&1
"$VP" scan --board "$o-line.ini" --dry-run --eps 10 --json --log "$o.vplog" --out "$o" >"$o.out" 2>&1
rc=$?
tail -n 1 "$o.out" >"$o.json"; tail -n 1 "$o-dot.out" >"$o-dot.json"
[ $rc = 0 ] && [ "$(field "$o.json" closed)" = true ] || bad "rpi4 line laser: exit $rc, closed $(field "$o.json" closed)"
[ "$(field "$o.json" through)" = 0 ] && [ "$(field "$o.json" head_collisions)" = 0 ] || bad "rpi4 line laser: through $(field "$o.json" through), head collisions $(field "$o.json" head_collisions)"
grep -q ' 0 false hits' "$o.out" || bad "rpi4 line laser: $(grep 'dry run: probe error' "$o.out")"
[ "$(field "$o.json" ray_false)" = 0 ] && [ "$(field "$o.json" rays)" -gt 0 ] || bad "rpi4 line laser: rays $(field "$o.json" rays), false $(field "$o.json" ray_false)"
"$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "rpi4 line laser: log verify: $(tail -n 1 "$o.verify")"
td=$(field "$o-dot.json" machine_s); tl=$(field "$o.json" machine_s)
awk "BEGIN{exit !($tl < $td)}" || bad "rpi4: the line laser takes $tl s of machine time, the dot laser $td s"
"$VP" scan --board "$o-line.ini" --dry-run --eps 10 --log "$o-cut.vplog" --stop-after 150 --out "$o-cut" >/dev/null 2>&1
"$VP" scan --log "$o-cut.vplog" --resume --dry-run --out "$o-cut" >"$o-cut.out" 2>&1 || bad "rpi4 line laser: resume: $(tail -n 1 "$o-cut.out")"
cmp -s "$o-cut.off" "$o.off" || bad "rpi4 line laser: cut after 150 commands and resumed, the mesh differs"
echo "rpi4 dry run, eps 10: dot laser $(field "$o-dot.json" probes) probes, $td s of machine time; line laser $(field "$o.json" probes) probes, $tl s ($(awk "BEGIN{printf \"%+.0f\", 100*($tl-$td)/$td}")%), $(field "$o.json" vertices) vertices, $(field "$o.json" rays) rays (worst $(field "$o.json" ray_worst) mm off the object, 0 false), 0 through, 0 head collisions; cut and resumed: same mesh"

# ---- two spheres 2 mm apart: the beam between two surfaces, at a limb, in a gap of the line is
# unreadable, never a hit in the air (a hit beside a limb within the noise tolerance is a grazing
# reading). The neck is 2 mm across at eps 12, far outside paper 000's range: lines aimed from
# aside at its sides closed the mesh across it, one part where the object has two, and host-sim
# said so (wrong topology, exit 7, as for the stacked boxes below); before sides whose line enters
# Omega from outside were aimed at, and again since an aimed direction takes its hit nearest the
# edge (core/planner/aim.c), it ends open (exit 4, 2 edges). Either is an honest answer there.
o="$D/rpi4-two"
"$VP" scan --board "$D/rpi4-line.ini" --dry-run --eps 12 --surface "sphere*10@200,150,141+sphere*7@200,150,160" \
  --json --log "$o.vplog" --out "$o" >"$o.out" 2>&1
rc=$?
tail -n 1 "$o.out" >"$o.json"
gaps=$(sed -n 's/.* \([0-9]*\) probes with the beam in a gap of the line$/\1/p' "$o.out")
case $rc in
  7) grep -q "wrong topology" "$o.out" || bad "two spheres, line laser: exit 7 without 'wrong topology'";;
  4) grep -q "the mesh is not closed" "$o.out" || bad "two spheres, line laser: exit 4 without 'the mesh is not closed'";;
  *) bad "two spheres, line laser: exit $rc (expected 4, open, or 7, closed across the neck with the wrong topology)";;
esac
grep -q ' 0 false hits, [0-9]* hidden spots, 0 moves through the object' "$o.out" || bad "two spheres, line laser: $(grep 'dry run: probe error' "$o.out")"
[ "$(field "$o.json" ray_false)" = 0 ] && [ "$(field "$o.json" head_collisions)" = 0 ] || bad "two spheres: ray_false $(field "$o.json" ray_false), head collisions $(field "$o.json" head_collisions)"
[ -n "$gaps" ] && [ "$gaps" -gt 0 ] || bad "two spheres: no probe read as a gap of the line ('$gaps')"
"$VP" log verify "$o.vplog" >/dev/null 2>&1 || bad "two spheres, line laser: log verify"
echo "two spheres 2 mm apart, line laser: exit $rc (open, or closed across the 2 mm neck at eps 12 with the wrong topology: said so), 0 false hits, $gaps probes unreadable (the beam in a gap of the line, at its end or between two surfaces), 0 false rays"

# ---- three stacked boxes: convex edges and concave steps; the beam at an edge is read on one face
# or not at all, never past the surface (a SAFETY line in the dry run's report), never in the air
o="$D/rpi4-boxes"
B3="off:tests/meshes/box.off*36@182,141,138+off:tests/meshes/box.off*20@190,145,147.4+off:tests/meshes/box.off*10@195,147,152.6"
"$VP" scan --board "$D/rpi4-line.ini" --dry-run --eps 6 --surface "$B3" --json --log "$o.vplog" --out "$o" >"$o.out" 2>&1
rc=$?
tail -n 1 "$o.out" >"$o.json"
# (the boxes lie 0.4 and 0.2 mm apart, 15-30 times below eps: where the mesh closes it joins them
# into one surface of genus 0, and host-sim says so, wrong topology, exit 7, as for two spheres
# closer than eps in README)
[ $rc = 0 ] || [ $rc = 4 ] || { [ $rc = 7 ] && grep -q 'the mesh has genus 0 in 1 component(s), the object genus 0 in 3' "$o.out"; } ||
  bad "stacked boxes, line laser: exit $rc ($(grep -E 'SAFETY|topology' "$o.out"))"
grep -q '^SAFETY' "$o.out" && bad "stacked boxes, line laser: $(grep SAFETY "$o.out")"
grep -q ' 0 false hits, [0-9]* hidden spots, 0 moves through the object' "$o.out" || bad "stacked boxes, line laser: $(grep 'dry run: probe error' "$o.out")"
"$VP" log verify "$o.vplog" >/dev/null 2>&1 || bad "stacked boxes, line laser: log verify"
echo "stacked boxes, line laser: exit $rc, $(sed -n 's/^dry run: probe error against the true object \(.*\); 0 false hits.*/probe error \1/p' "$o.out"), 0 false hits, none past the surface; $(field "$o.json" rays) rays, worst $(field "$o.json" ray_worst) mm off the object ($(field "$o.json" ray_false) beyond the noise tolerance)"

# ---- a reflection doubling the line (an equal second line 14 px away): every column has two
# candidates, so every probe is unreadable, none a miss (a miss would be taken for free space)
o="$D/rpi4-ghost"
(cat "$D/rpi4-line.ini"; printf 'ghost = 1, 0, 14\n') >"$o.ini"
"$VP" scan --board "$o.ini" --dry-run --eps 10 --log "$o.vplog" --out "$o" >"$o.out" 2>&1
gm=$(sed -n 's/^machine: \([0-9]*\) probes: \([0-9]*\) hits, \([0-9]*\) misses, .*/\1 \2 \3/p' "$o.out")
set -- $gm
[ -n "$gm" ] && [ "$1" -gt 0 ] && [ "$2" = 0 ] && [ "$3" = 0 ] || bad "a doubled line: probes/hits/misses '$gm' (expected no hit and no miss)"
echo "a doubled line (a reflection as bright as the laser): ${1:-?} probes, ${2:-?} hits, ${3:-?} misses: every one unreadable"

[ $fail = 0 ] || exit 1
echo "line laser (16 rays, 30 degrees): $nrun object(s) closed with their genus, 0 collisions, every move outside by CGAL, logs verified, replayed and resumed bit for bit; probes $sp -> $sl ($(awk "BEGIN{printf \"%+.1f\", 100*($sl-$sp)/$sp}")%), moves $mp -> $ml ($(awk "BEGIN{printf \"%+.1f\", 100*($ml-$mp)/$mp}")%); a forged RAY origin refused"
