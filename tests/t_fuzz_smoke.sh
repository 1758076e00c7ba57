#!/bin/sh
# A short libFuzzer smoke run (ASan + UBSan) of each fuzz target (the session log reader, the
# OFF and PLY readers, the board file parser, the planner answered by a rangefinder that errs
# about a sphere and about a box,
# the triangulation under insertions and removals of degenerate points in a small arena, the
# camera frames the spot and line finders read, the rangefinder calibration fits)
# on a small seed corpus, with the inputs that once failed: zero crashes, zero sanitizer reports.
# `make fuzz FUZZ_TIME=600` runs them for longer.
set -u
B=${BUILD:-build}
command -v clang >/dev/null || { echo "clang missing (make deps)"; exit 1; }
T=${VP_FUZZ_SECONDS:-3}
make --no-print-directory -s -j2 BUILD="$B" FUZZ_TIME="$T" fuzz >"$B/fuzz-smoke.log" 2>&1
rc=$?
grep -E '^fuzz_' "$B/fuzz-smoke.log"
[ $rc -eq 0 ] || { tail -20 "$B/fuzz-smoke.log"; echo "fuzz smoke failed"; exit 1; }
echo "fuzz smoke: $(grep -c 'no crash' "$B/fuzz-smoke.log") targets, ${T}s each, clean"
