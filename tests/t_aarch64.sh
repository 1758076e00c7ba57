#!/bin/sh
# The test suite built for aarch64 (gcc-aarch64-linux-gnu) and run under qemu-aarch64: every
# test passes there too, and the triangulation fingerprints equal the x86-64 ones bit for bit.
set -u
B=${BUILD:-build}
command -v aarch64-linux-gnu-gcc >/dev/null || { echo "aarch64-linux-gnu-gcc missing (make deps)"; exit 1; }
command -v qemu-aarch64 >/dev/null || { echo "qemu-aarch64 missing (make deps)"; exit 1; }
A="$B/aarch64"
make --no-print-directory -s BUILD="$A" CROSS=aarch64-linux-gnu- tests >"$B/aarch64-build.log" 2>&1 || {
  tail -20 "$B/aarch64-build.log"; echo "aarch64 build failed"; exit 1; }
fail=0; n=0
for t in "$A"/tests/*/test_*; do
  [ -x "$t" ] || continue
  name=$(basename "$t")
  out=$(VP_TEST_QUICK=1 timeout 600 qemu-aarch64 -L /usr/aarch64-linux-gnu "$t" 2>&1); rc=$?
  n=$((n+1))
  if [ $rc -ne 0 ] && [ $rc -ne 77 ]; then echo "aarch64 $name failed (exit $rc)"; echo "$out" | tail -5; fail=1; continue; fi
  # lines starting with "fingerprint" must equal the native run's
  fa=$(echo "$out" | grep '^fingerprint' || true)
  if [ -n "$fa" ]; then
    fx=$("$B/tests/${t#"$A"/tests/}" 2>/dev/null | grep '^fingerprint' || true)
    if [ "$fa" != "$fx" ]; then echo "aarch64 $name: fingerprint differs:"; echo " arm: $fa"; echo " x86: $fx"; fail=1
    else echo "aarch64 $name: same fingerprint as x86-64: $(echo "$fa" | head -1)"; fi
  fi
done
[ $fail -eq 0 ] && echo "aarch64: $n test programs pass under qemu-aarch64"
exit $fail
