#!/bin/sh
# Everything builds warning-free with clang too (-std=c99 -pedantic -Wall -Wextra -Werror),
# and the core tests pass with it.
set -u
B=${BUILD:-build}
command -v clang >/dev/null || { echo "clang missing (make deps)"; exit 1; }
C="$B/clang"
make --no-print-directory -s BUILD="$C" CC=clang tests >"$B/clang-build.log" 2>&1 || {
  tail -20 "$B/clang-build.log"; echo "clang build failed"; exit 1; }
fail=0
for t in "$C"/tests/core/test_dt "$C"/tests/core/test_gmp_pred; do
  [ -x "$t" ] || continue
  "$t" >"$B/clang-$(basename "$t").log" 2>&1 || { echo "clang $(basename "$t") failed"; tail -5 "$B/clang-$(basename "$t").log"; fail=1; }
done
[ $fail -eq 0 ] && echo "clang build ok: $(ls "$C"/core/*.o | wc -l) core objects, tests pass"
exit $fail
