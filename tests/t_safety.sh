#!/bin/sh
# Issue 12 regression: the probe moves only through space proven free, on any closed mesh.
# For every mesh in tests/meshes/ (cube, box, tetrahedron, octahedron, bow-ties, cylinder, cone, a wedge,
# an icosphere with zero-area faces: tests/meshes/make_meshes.py) and ../shared/meshes/*.off,
# at eps-rel 0.1, 0.05 and 0.03, and at 0.05 with the sizing field (a0.05: --size-rel 0.25),
# `voroprobe sim --surface off:MESH --json` must
#   - finish (no hang: a run gets VP_SAFETY_TIMEOUT seconds, default 30; most take under 2 s
#     here, the edge-sharing bow-tie at 0.03 about 10 s),
#   - report "collisions":0 (host-sim checks every move against the object),
#   - have 0 moves through or inside the object by the independent exact checker
#     tests/cgal_moves.cpp (CGAL, built here into $BUILD/safety/; skipped without libcgal-dev),
#     which must also agree with host-sim's count,
#   - pass `voroprobe log verify LOG` (only when `voroprobe log --help` mentions verify),
#   - exit honestly: status 0 only when the JSON says closed_manifold true (and 7 when it closed
#     with another genus or number of components than the object's).
# First the checker itself must count hand-written moves right (through a face, along an edge,
# through a vertex, ending on a face, sliding in a face, inside, a zero-length move; and not a
# segment outside, one 1e-300 off a face, one in a face's plane beside it).
# VP_TEST_QUICK=1: eps 0.1 and 0.05 only, 15 s per run. VP_SAFETY_JOBS: parallel runs (2).
# The results table is printed and kept in $BUILD/safety/results.txt with every run's files
# (moves: the JSON's count, or for a hung run the moves its log holds; first: the first move
# through or inside the object by the CGAL checker). An open mesh must exit 4, never 0; the
# polyhedra, the zero-area faces and the smooth meshes that the planner closes (flat faces on
# their facet lines, the manifold criterion) must stay closed at every eps (must-close), and with
# the sizing field every mesh but the edge-sharing bow-tie must close with the object's topology.
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
export BUILD VP
D="$BUILD/safety"
CG="$D/cgal_moves"

# ---------- one case (called through xargs): MESH EPS -> $D/runs/NAME-EPS.result ----------
if [ "${1:-}" = "--one" ]; then
  mesh=$2; eps=$3
  name=$(basename "$mesh" .off); out="$D/runs/$name-$eps"
  # a0.05: eps-rel 0.05 with the adaptive sizing field (--size-rel 0.25, floor eps/10)
  case $eps in a*) epsv=${eps#a}; sizing="--size-rel 0.25";; *) epsv=$eps; sizing="";; esac
  rm -f "$out".*
  t0=$(date +%s%N)
  timeout -k 5 "$SAFETY_TIMEOUT" "$VP" sim --surface "off:$mesh" --eps-rel "$epsv" $sizing --out "$out" --json --quiet \
    --hausdorff 0 >"$out.stdout" 2>"$out.stderr"
  rc=$?
  ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  secs=$(printf '%d.%02d' $((ms / 1000)) $((ms % 1000 / 10)))
  json=$(tail -n 1 "$out.stdout" | grep '^{' || true)
  field() { echo "$json" | sed -n "s/.*\"$1\":\([^,}]*\).*/\1/p" | tr -d '"'; }
  coll=$(field collisions); closed=$(field closed_manifold); status=$(field status); moves=$(field moves)
  [ -n "$coll" ] || coll="-"; [ -n "$closed" ] || closed="-"; [ -n "$status" ] || status="-"
  verdict=""
  case $rc in
    124|137) verdict="$verdict hang(>${SAFETY_TIMEOUT}s)";;
    0|1|2|3|4|5|6|7|8|9|10) ;;
    *) verdict="$verdict exit-$rc";;
  esac
  if [ -z "$json" ]; then
    case $rc in 124|137) ;; *) verdict="$verdict no-json";; esac
  else
    [ "$coll" = 0 ] || verdict="$verdict collisions"
    if [ "$rc" = 0 ] && [ "$closed" != true ]; then verdict="$verdict exit-0-not-closed"; fi
    # the exit status and the JSON's status agree (0 closed, 4 not_closed, 1 error, 7 wrong_topology)
    case "$rc:$status" in
      0:closed|4:not_closed|1:error|7:wrong_topology) ;;
      *) verdict="$verdict exit-$rc-says-$status";;
    esac
    # closed: exit 0, or 7 when the object's genus or parts differ (the simulator knows them)
    if [ "$closed" = true ] && [ "$rc" != 0 ] && [ "$rc" != 7 ]; then verdict="$verdict closed-but-exit-$rc"; fi
    # objects the planner closes (flat faces, sharp edges, zero-area faces): a regression if not
    case "$name:$eps" in
      bowtie:a*) ;; # two cubes sharing an edge: not a manifold
      *:a*) # the sizing field's runs: every other mesh closes with its topology
        [ "$closed" = true ] && [ "$rc" = 0 ] || verdict="$verdict must-close";;
      cube:*|box:*|tetra:*|octa:*|cylinder32:*|cone32:*|wedge26:*|icosphere2:*|icosphere2-degen:*|bear:*|ellipe0.003:*|sphere966:*)
        [ "$closed" = true ] && [ "$rc" = 0 ] || verdict="$verdict must-close";;
    esac
  fi
  # the independent check, on whatever the log holds (a hung run's log too)
  cthrough="-"; cinside="-"; cfirst="-"; cmoves="-"
  if [ -x "$CG" ] && [ -s "$out.vplog" ]; then
    start=$("$VP" log dump "$out.vplog" 2>/dev/null | sed -n '/^# start /{s/^# start \([^ ]*\) \([^ ]*\) \([^ ,]*\),.*/\1,\2,\3/p;q;}')
    if [ -n "$start" ] && "$VP" log dump "$out.vplog" --csv >"$out.csv" 2>"$out.csv.err"; then
      "$CG" "$mesh" "$out.csv" --start "$start" --list 5 >"$out.cgal" 2>&1
      crc=$?
      line=$(tail -n 1 "$out.cgal")
      cmoves=$(echo "$line" | sed -n 's/^moves \([0-9]*\),.*/\1/p')
      cthrough=$(echo "$line" | sed -n 's/.* through \([0-9]*\),.*/\1/p')
      cinside=$(echo "$line" | sed -n 's/.* inside \([0-9]*\),.*/\1/p')
      cfirst=$(echo "$line" | sed -n 's/.* first \([0-9]*\).*/\1/p')
      [ -n "$cfirst" ] || cfirst="none"
      if [ "$crc" -gt 1 ] || [ -z "$cthrough" ] || [ -z "$cinside" ]; then
        verdict="$verdict cgal-error"; cthrough="?"; cinside="?"
      else
        [ "$cthrough" = 0 ] && [ "$cinside" = 0 ] || verdict="$verdict cgal-through/inside"
        # the two exact counts must agree (host-sim counts a move touching or inside the object)
        if [ -n "$json" ] && [ "$coll" != $((cthrough + cinside)) ]; then verdict="$verdict cgal!=host-sim"; fi
        if [ -n "$json" ] && [ -n "$moves" ] && [ "$moves" != "$cmoves" ]; then verdict="$verdict moves-differ"; fi
      fi
      rm -f "$out.csv"
    else
      verdict="$verdict log-dump-failed"
    fi
  fi
  [ -n "$moves" ] || moves="$cmoves"   # a hung run: the moves its log holds
  [ -n "$moves" ] || moves="-"; [ -n "$cmoves" ] || cmoves="-"
  ver="-"
  if [ "$HAVE_VERIFY" = 1 ] && [ -s "$out.vplog" ]; then
    "$VP" log verify "$out.vplog" >"$out.verify" 2>&1 && ver=ok || { ver="FAIL"; verdict="$verdict log-verify"; }
  fi
  [ -n "$verdict" ] || verdict=" pass"
  printf '%s %s %s %s %s %s %s %s %s %s %s %s %s\n' "$name" "$eps" "$rc" "$secs" "$moves" "$coll" \
    "$cthrough" "$cinside" "$cfirst" "$closed" "$status" "$ver" "$(echo $verdict | tr ' ' ',')" >"$out.result"
  exit 0
fi

# ---------- the main run ----------
[ -x "$VP" ] || { echo "FAIL: $VP is not built"; exit 1; }
QUICK=${VP_TEST_QUICK:-0}
EPS=${VP_SAFETY_EPS:-"0.1 0.05 0.03 a0.05"}
SAFETY_TIMEOUT=${VP_SAFETY_TIMEOUT:-30}
if [ "$QUICK" != 0 ]; then EPS=${VP_SAFETY_EPS:-"0.1 0.05"}; SAFETY_TIMEOUT=${VP_SAFETY_TIMEOUT:-15}; fi
JOBS=${VP_SAFETY_JOBS:-2}
SHARED=${VP_SHARED_MESHES:-../shared/meshes}
export SAFETY_TIMEOUT
mkdir -p "$D/runs" "$D/selftest" || exit 1
rm -f "$D"/runs/*
fail=0
bad() { echo "FAIL: $*"; fail=1; }
T0=$(date +%s)

# ---- the independent checker: build it (like bench/planner.sh builds its CGAL programs)
cgal_note=""
. tests/cgal_moves.sh
cgal_moves_build "$BUILD" || bad "$CG_WHY"

# ---- the checker must count hand-written moves right (unit cube [0,1]^3)
selftest() {   # NAME MESH 'EXPECTED LAST LINE' [checker options] <<move list
  cat >"$D/selftest/$1.moves"
  got=$("$CG" "$2" "$D/selftest/$1.moves" ${4:-} 2>&1 | tail -n 1)
  [ "$got" = "$3" ] || bad "cgal_moves self-test '$1': got '$got', expected '$3'"
  nself=$((nself + 1))
}
nself=0
if [ -x "$CG" ]; then
  C=tests/meshes/cube.off
  selftest face $C "moves 1, through 1, inside 0, first 1" <<'EOF'
# straight through the faces x = 0 and x = 1
start -0.5 0.5 0.5
move 1.5 0.5 0.5
EOF
  selftest edge $C "moves 1, through 1, inside 0, first 1" <<'EOF'
# touches only the edge x = 0, z = 0 at (0, 0.5, 0): outside the cube everywhere else
start -1 0.5 1
move 1 0.5 -1
EOF
  selftest vertex $C "moves 1, through 1, inside 0, first 1" <<'EOF'
# touches only the corner (0,0,0)
start -1 -1 1
move 1 1 -1
EOF
  selftest ends-on-face $C "moves 1, through 1, inside 0, first 1" <<'EOF'
start -1 0.5 0.5
move 0 0.5 0.5
EOF
  selftest in-face $C "moves 1, through 1, inside 0, first 1" <<'EOF'
# slides along the face z = 0
start 0.2 -1 0
move 0.2 2 0
EOF
  selftest inside $C "moves 1, through 0, inside 1, first 1" <<'EOF'
# wholly inside: meets no face
start 0.25 0.25 0.25
move 0.75 0.75 0.75
EOF
  selftest zero-length $C "moves 2, through 1, inside 1, first 1" <<'EOF'
# a move to where the device is: inside, then onto a corner
start 0.5 0.5 0.5
move 0.5 0.5 0.5
move 1 1 1
EOF
  selftest outside $C "moves 2, through 0, inside 0, first none" <<'EOF'
# outside, clear of the cube
start 2 2 2
move 3 -1 2
move 3 3 -1
EOF
  selftest near-miss $C "moves 1, through 0, inside 0, first none" <<'EOF'
# in the plane of the face z = 0 but beside it; then parallel to the face x = 0, 1e-300 off it
start -0.5 -1 0
move -0.5 2 0
EOF
  selftest near-miss2 $C "moves 1, through 0, inside 0, first none" <<'EOF'
start -1e-300 -1 0.5
move -1e-300 2 0.5
EOF
  # the CSV of `log dump --csv` (event, probe and move rows; the start from --start)
  selftest csv $C "moves 4, through 1, inside 1, first 3 (record 4)" "--start -0.5,0.5,0.5" <<'EOF'
seq,offset,type,origin_x,origin_y,origin_z,dir_x,dir_y,dir_z,range,hit,dist,raw,point_x,point_y,point_z,target_x,target_y,target_z,event,code,text
0,370,event,,,,,,,,,,,,,,,,,start,0,"a text, with a comma"
1,441,move,,,,,,,,,,,,,,-0.5,3,0.5,,,
2,481,probe,-0.5,3,0.5,0,-1,0,4,1,2,2,-0.5,1,0.5,,,,,,
3,573,move,,,,,,,,,,,,,,1.5,0.5,0.5,,,
4,613,move,,,,,,,,,,,,,,0.5,0.5,0.5,,,
5,653,move,,,,,,,,,,,,,,0.5,0.6,0.5,,,
EOF
  # zero-area faces: m (vertex 162) is the exact midpoint of the edge of vertices 0 and 42,
  # the face (162 0 42) has no area; a segment through m, from m/2 to 2m, meets the surface
  selftest degenerate tests/meshes/icosphere2-degen.off "moves 3, through 2, inside 1, first 1" <<'EOF'
start 0 0 0
move -0.3048778974198957 0.38817431328205076 0.040155508910005785
move -1.2195115896795827 1.552697253128203 0.16062203564002314
move 0 0 0
EOF
  "$CG" tests/meshes/icosphere2-degen.off "$D/selftest/degenerate.moves" | grep -q "324 triangles (2 zero-area)" ||
    bad "cgal_moves does not see the 2 zero-area faces of icosphere2-degen.off"
  echo "cgal_moves self-test: $nself hand-written cases checked"
fi

# ---- log verify, when it exists
HAVE_VERIFY=0
"$VP" log --help 2>&1 | grep -q verify && HAVE_VERIFY=1
export HAVE_VERIFY
[ "$HAVE_VERIFY" = 1 ] || bad "\`voroprobe log --help\` has no verify"

# ---- the scans
meshes=$(ls tests/meshes/*.off)
if [ -d "$SHARED" ]; then meshes="$meshes $(ls "$SHARED"/*.off)"
else echo "note: $SHARED not found: its meshes are skipped"; fi
# the bow-tie sharing an edge is not a manifold: under the sizing field it refines along that
# edge down to the floor (2 million moves, 25 s here) and still ends open; its uniform runs
# cover it
for m in $meshes; do for e in $EPS; do
  case "$(basename "$m" .off):$e" in bowtie:a*) continue;; esac
  echo "$m $e"
done; done >"$D/cases.txt"
ncase=$(wc -l <"$D/cases.txt")
xargs -P "$JOBS" -n 2 sh "$0" --one <"$D/cases.txt"

# ---- the table
{
  printf '%-18s %5s %4s %7s %7s %7s %7s %7s %6s %6s %6s %6s  %s\n' mesh eps exit time_s moves collis cgal_th cgal_in first closed status verify verdict
  while read -r m e; do
    r="$D/runs/$(basename "$m" .off)-$e.result"
    if [ -f "$r" ]; then
      set -- $(cat "$r")
      printf '%-18s %5s %4s %7s %7s %7s %7s %7s %6s %6s %6s %6s  %s\n' "$1" "$2" "$3" "$4" "${5:--}" "$6" "$7" "$8" "$9" "${10}" "${11}" "${12}" "${13}"
    else
      printf '%-18s %5s  (no result)\n' "$(basename "$m" .off)" "$e"
    fi
  done <"$D/cases.txt"
} >"$D/results.txt"
cat "$D/results.txt"
npass=$(grep -c ' pass$' "$D/results.txt")
nfail=$((ncase - npass))
nhang=$(grep -c 'hang' "$D/results.txt")
ncoll=$(grep -c 'collisions\|cgal-through' "$D/results.txt")
nlie=$(grep -c 'exit-0-not-closed' "$D/results.txt")
nmis=$(grep -c 'cgal!=host-sim' "$D/results.txt")
[ "$nfail" -eq 0 ] || fail=1
cg="CGAL check on"; [ -x "$CG" ] || cg="CGAL check skipped"
vf="log verify on"; [ "$HAVE_VERIFY" = 1 ] || vf="log verify skipped"
echo "safety: $ncase runs in $(( $(date +%s) - T0 )) s: $npass pass, $nfail fail ($nhang hang, $ncoll move through the object, $nlie exit 0 on an open mesh, $nmis CGAL/host-sim disagree); $cg, $vf"
exit $fail
