#!/bin/sh
# A miss must be seen: vp_planner_spot_hidden against CGAL. tests/core/test_sight --cases scans
# an ellipsoid part way and writes the occluders (the mesh found so far, the boundary of the space
# still unknown) with sight triangles (camera, beam origin, beam end: random, a scanner's, through
# an occluder's vertex, along its edge, in its plane) and the planner's answers;
# tests/cgal_sight.cpp (CGAL's exact do_intersect, no voroprobe code) must agree with every one.
# The case the checker must catch: the same file with two answers flipped.
. tests/lib.sh
D="$BUILD/sight"
rm -rf "$D"; mkdir -p "$D"
if [ ! -f /usr/include/CGAL/intersections.h ] || ! command -v g++ >/dev/null 2>&1; then
  echo "FAIL: no CGAL (libcgal-dev): the sight rule would grade itself"; exit 1
fi
g++ -O2 -o "$D/cgal_sight" tests/cgal_sight.cpp -lgmp -lmpfr >"$D/build.log" 2>&1 ||
  { tail -5 "$D/build.log"; echo "FAIL: tests/cgal_sight.cpp does not build"; exit 1; }
"$BUILD/tests/core/test_sight" --cases "$D/cases.txt" >"$D/cases.out" 2>&1 || { cat "$D/cases.out"; bad "test_sight --cases"; }
out=$("$D/cgal_sight" "$D/cases.txt"); rc=$?
echo "$out"
[ $rc -eq 0 ] || bad "CGAL disagrees with the planner"
# the planner must say both: some triangles meet the mesh, some do not
n1=$(sed '1,/^queries/d' "$D/cases.txt" | grep -c ' 1$'); n0=$(sed '1,/^queries/d' "$D/cases.txt" | grep -c ' 0$')
[ "$n1" -ge 100 ] && [ "$n0" -ge 100 ] || bad "too one-sided a set: $n1 hidden, $n0 not"
# the checker must catch a wrong answer either way: the first 1 and the first 0 flipped
awk 'BEGIN{a=0;b=0} /^queries/{q=1} q && / 1$/ && !a {sub(/ 1$/," 0"); a=1; print; next}
     q && / 0$/ && !b {sub(/ 0$/," 1"); b=1; print; next} {print}' "$D/cases.txt" >"$D/flipped.txt"
got=$("$D/cgal_sight" "$D/flipped.txt" | tail -n 1)
case $got in *"; 2 disagree") ;; *) bad "the checker missed two flipped answers: '$got'";; esac
[ $fail -eq 0 ] && echo "ok: $n1 sight triangles meet an occluder, $n0 do not; CGAL agrees with every one"
exit $fail
