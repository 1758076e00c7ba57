#!/bin/sh
# Runs every libFuzzer target in BUILD/fuzz for SECONDS seconds each, on a corpus seeded with
# a small simulated session (its log, OFF and PLY files), torn and hand-made variants, the
# planner's configurations and faults, the board files, and lattice point sequences for the
# triangulation, camera frames with a spot or a line, and calibration sessions.
# Crashes and sanitizer reports fail the run (artifacts in BUILD/fuzz/artifacts).
# Usage: sh tests/fuzz/run.sh BUILD SECONDS
set -u
B=${1:-build}; T=${2:-60}
F="$B/fuzz"; S="$F/seeds"
rm -rf "$S"; mkdir -p "$S/log" "$S/off" "$S/ply" "$S/planner" "$S/board" "$S/dt" "$S/frame" "$S/calib" "$F/artifacts"
w="$S/work"; mkdir -p "$w"
"$B/voroprobe" sim --surface sphere --eps-rel 0.3 --out "$w/s" --quiet --hausdorff 0 --sync close >/dev/null &&
"$B/voroprobe" sim --surface torus --eps-rel 0.25 --out "$w/t" --dropout 0.1 --noise 0.001 --quiet --hausdorff 0 \
  --sync close --stop-after 300 >/dev/null 2>&1
"$B/voroprobe" mesh "$w/s.vplog" --out "$w/a" --ascii >/dev/null 2>&1
[ -s "$w/s.vplog" ] && [ -s "$w/a.ply" ] || { echo "fuzz: cannot make the seed corpus with $B/voroprobe"; exit 1; }
cp "$w/s.vplog" "$w/t.vplog" "$S/log/"
hdr=$("$B/voroprobe" log dump "$w/s.vplog" --csv | awk -F, 'NR == 2 {print $2}')
head -c "$hdr" "$w/s.vplog" >"$S/log/header-only"
head -c 1000 "$w/t.vplog" >"$S/log/torn"
cp "$w/s.off" "$S/off/"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n4 1 2 3 0\n' >"$S/off/tet.off"
printf 'OFF\n# comment\n3 1 0\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n' >"$S/off/tri.off"
cp "$w/s.ply" "$S/ply/bin.ply"; cp "$w/a.ply" "$S/ply/ascii.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$S/ply/tri.ply"
rm -rf "$w"
# the planner: configurations (Omega a box or a ball, a body, eps, noise, confirmed misses, a short
# range, a distance bound, tubes, machine time, a line laser, a re-scan), then each kind of fault
# in turn (tests/fuzz/fuzz_planner.c)
f='\315\000\000\000\000\000\334\000\000\000\000\000\346\000\000\000\000\000\360\000\000\000\000\000\200\000\000\000\000\000\367\000\000\000\000\000\012\000\000\000\000\000\372\000\000\000\000\000\001\000\000\000\000\000'   # each fault among true answers
z='\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000'   # the seeds' probes answered truly first
printf '\000\000\010\000'"$z$f$f$f$f" >"$S/planner/c0"
printf '\041\022\017\000'"$z$f$f$f$f" >"$S/planner/c1"
printf '\211\377\003\011'"$z$f$f$f$f" >"$S/planner/c2"
printf '\153\100\010\002'"$z$f$f$f$f" >"$S/planner/c3"
printf '\070\000\017\000'"$z$f$f$f$f" >"$S/planner/c4"
printf '\041\022\057\120'"$z$f$f$f$f" >"$S/planner/c5"   # a body, timed, a re-scan
printf '\000\011\217\140'"$z$f$f$f$f" >"$S/planner/c6"   # a line laser, a re-scan
printf '\150\000\017\022'"$z$f$f$f$f" >"$S/planner/c7"   # a body, tubes, timed, a short range
printf '\000\000\010\000'"$z$f\373\200$f$f\373\040$f" >"$S/planner/c8"   # contacts part way along moves
printf '\000\022\017\200'"$z$f$f$f$f" >"$S/planner/c9"   # two parts
printf '\041\022\057\320'"$z$f$f$f$f" >"$S/planner/c10"  # two parts, a body, timed, a re-scan
printf '\000\222\017\000'"$z$f$f$f$f" >"$S/planner/c11"  # the sight rule of a camera's misses
# true answers only: no move may enter the object (the check a lie switches off)
for c in '\000\000\010\000' '\001\022\017\200' '\211\000\003\011' '\100\011\217\160'; do
  printf "$c" >"$S/planner/true-$(printf "$c" | od -An -tx1 | tr -d ' \n')"
done
# the same for the planner with boxes for the object (fuzz_planner_box.c; b1's bit 6 turns them)
mkdir -p "$S/planner_box"; cp "$S/planner/"* "$S/planner_box/"
printf '\000\100\010\000'"$z$f$f$f$f" >"$S/planner_box/turned"
printf '\041\122\057\120'"$z$f$f$f$f" >"$S/planner_box/turned-body"
# the triangulation: 40 calls (every kind in turn: insertions, batches, removals) in a large arena,
# in a small one, and on a wider lattice scaled by 1/8 (tests/fuzz/fuzz_dt.c)
ops=''; i=0
while [ $i -lt 40 ]; do
  ops="$ops$(printf '\\%03o\\%03o\\%03o\\%03o' $((i * 37 % 256)) $((i * 11 % 256)) $((i * 7 % 256)) $((i * 5 % 256)))"
  i=$((i + 1))
done
printf "\\300\\015$ops" >"$S/dt/big"
printf "\\010\\015$ops" >"$S/dt/small"
printf "\\300\\003$ops" >"$S/dt/wide"
# camera frames (tests/fuzz/fuzz_frame.c: size, flags, band, the spot and the line, then the
# texture): a spot the model reads as a hit, one off the beam, two spots, a line, a line
# over a textured laser-off frame, YUYV with padded rows, a spot clipped at 255 on a large frame, a
# configuration out of range (percentile infinite), the beam's image line turned nearly along the rows
printf '\170\120\014\000\200\200\200\001\200\200' >"$S/frame/hit"
printf '\170\120\014\000\100\140\200\001\200\200' >"$S/frame/off-beam"
printf '\170\120\034\000\100\140\200\001\200\200' >"$S/frame/two-spots"
printf '\170\120\044\001\200\200\200\007\200\200' >"$S/frame/line"
printf '\170\120\244\002\200\200\140\047\120\220\000\000\030\040\050\060\040\030\020\030\377\000\030\020' >"$S/frame/line-textured"
printf '\120\100\017\005\140\100\200\002\200\200\000\000\030\030\034\034' >"$S/frame/yuyv-padded"
printf '\377\377\114\000\120\200\377\002\200\200' >"$S/frame/clipped"
printf '\170\120\014\000\200\200\200\001\200\200\021' >"$S/frame/config-inf"
printf '\170\120\014\001\200\200\200\001\200\200\000\013' >"$S/frame/line-along-rows"
# the calibration fits (tests/fuzz/fuzz_calib.c: the true head, depths, spots, noise, the camera
# alone, then spoilings): exact observations of the nominal head and of moved ones, with noise,
# the camera alone, a NaN, two gross outliers and a copy, one depth, one spot
printf '\200\200\200\200\200\200\200\200\004\030\000\000' >"$S/calib/exact"
printf '\220\160\210\170\100\220\063\240\004\030\000\000' >"$S/calib/moved-exact"
printf '\377\000\377\000\000\377\377\377\004\037\000\000' >"$S/calib/far-exact"
printf '\220\160\210\170\100\220\063\240\004\030\001\000' >"$S/calib/moved-noisy"
printf '\200\200\200\200\200\200\200\200\004\030\000\001' >"$S/calib/camera-exact"
printf '\220\160\210\170\100\220\063\240\004\030\000\000\001\005\000' >"$S/calib/nan"
printf '\220\160\210\170\100\220\063\240\004\030\000\000\003\007\377\003\011\000\004\002\000' >"$S/calib/outliers"
printf '\200\200\200\200\200\200\200\200\000\030\000\000' >"$S/calib/one-depth"
printf '\200\200\200\200\200\200\200\200\004\001\000\000' >"$S/calib/one-spot"
# the board files as they are
cp boards/*.ini "$S/board/"
# inputs that once failed a target (tests/fuzz/regress/KIND/), kept as seeds
for d in tests/fuzz/regress/*/; do [ -d "$d" ] && cp "$d"* "$S/$(basename "$d")/"; done
fail=0
for f in "$F"/fuzz_*; do
  [ -x "$f" ] || continue
  name=$(basename "$f"); kind=${name#fuzz_}
  corpus="$F/corpus/$kind"; mkdir -p "$corpus"
  "$f" -max_total_time="$T" -timeout=20 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
       -artifact_prefix="$F/artifacts/$name-" "$corpus" "$S/$kind" >"$F/$name.log" 2>&1
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$F/$name.log" | grep -o '[0-9]*$')
  if [ $rc -ne 0 ] || grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:' "$F/$name.log"; then
    echo "$name: FAILED (exit $rc) after ${runs:-?} runs; see $F/$name.log"
    grep -E 'ERROR|runtime error|SUMMARY' "$F/$name.log" | head -5
    fail=1
  else
    echo "$name: ${runs:-?} runs in ${T}s, corpus $(ls "$corpus" | wc -l) inputs, no crash, no sanitizer report"
  fi
done
exit $fail
