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

[ $fail = 0 ] || exit 1
echo "line laser (16 rays, 30 degrees): $nrun object(s) closed with their genus, 0 collisions, every move outside by CGAL, logs verified, replayed and resumed bit for bit; probes $sp -> $sl ($(awk "BEGIN{printf \"%+.1f\", 100*($sl-$sp)/$sp}")%), moves $mp -> $ml ($(awk "BEGIN{printf \"%+.1f\", 100*($ml-$mp)/$mp}")%); a forged RAY origin refused"
