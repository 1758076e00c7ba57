#!/bin/sh
# The device program cross-built for ARM (make CROSS=aarch64-linux-gnu-) runs under
# qemu-aarch64: a short dry-run scan of boards/sim.ini to DONE (closed mesh, log), the x86-64
# build replays its log to the same mesh bytes, a dry-run calibration fits, and without
# --dry-run it says clearly what hardware support the build lacks.
. tests/lib.sh
B=$BUILD
command -v aarch64-linux-gnu-gcc >/dev/null || { echo "aarch64-linux-gnu-gcc missing (make deps)"; exit 1; }
command -v qemu-aarch64 >/dev/null || { echo "qemu-aarch64 missing (make deps)"; exit 1; }
command -v readelf >/dev/null || { echo "readelf missing (binutils: make deps)"; exit 1; }
C="$B/cross"
make --no-print-directory -s BUILD="$C" CROSS=aarch64-linux-gnu- "$C/voroprobe" >"$B/cross-build.log" 2>&1 || {
  tail -20 "$B/cross-build.log"; echo "cross build failed"; exit 1; }
readelf -h "$C/voroprobe" 2>/dev/null | grep -q "Machine: *AArch64" || { echo "$C/voroprobe is not an aarch64 program"; readelf -h "$C/voroprobe" | grep Machine; exit 1; }
ARM="qemu-aarch64 -L /usr/aarch64-linux-gnu $C/voroprobe"

$ARM scan --help >/dev/null || bad "scan --help under qemu"
t0=$(date +%s%N)
$ARM scan --board boards/sim.ini --dry-run --eps 40 --log "$tmp/arm.vplog" --quiet --sync close >"$tmp/arm.txt" 2>"$tmp/arm.err"; rc=$?
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
secs=$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))
[ $rc -eq 0 ] || { bad "qemu dry run: exit $rc"; tail -5 "$tmp/arm.err"; }
grep -q "^scan: DONE" "$tmp/arm.txt" || bad "qemu dry run: not DONE"
grep -q "closed 2-manifold" "$tmp/arm.txt" || bad "qemu dry run: mesh not closed"
"$VP" replay "$tmp/arm.vplog" --out "$tmp/re" --quiet || bad "x86-64 replay of the ARM log"
cmp -s "$tmp/re.ply" "$tmp/arm.ply" && cmp -s "$tmp/re.off" "$tmp/arm.off" || bad "x86-64 replay of the ARM log: mesh differs"
echo "aarch64 (qemu): $(grep '^scan: DONE' "$tmp/arm.txt" | sed 's/scan: //'), $(grep '^mesh' "$tmp/arm.txt" | cut -d';' -f1 | sed 's/mesh: //') in $secs s; x86-64 replays its log to the same bytes"
# the same dry run natively: the rendered frames use libm, so equal bytes are likely, not promised
"$VP" scan --board boards/sim.ini --dry-run --eps 40 --log "$tmp/x86.vplog" --quiet --sync close >/dev/null 2>&1
if cmp -s "$tmp/x86.ply" "$tmp/arm.ply"; then echo "the x86-64 dry run gives the same mesh bytes"
else echo "note: the x86-64 dry run's mesh differs (libm rounding in the rendered frames)"; fi

$ARM calibrate --board boards/sim.ini --dry-run --target 150,0,0 --far 120 --out "$tmp/sim.calib" >"$tmp/cal.txt" 2>&1 ||
  { bad "qemu calibrate --dry-run"; cat "$tmp/cal.txt"; }
grep "^fit:" "$tmp/cal.txt"

# no hardware support in this build (or no hardware): said clearly, nothing written
$ARM scan --board boards/rpi4-gantry.ini --log "$tmp/hw.vplog" >/dev/null 2>"$tmp/hw.txt"; rc=$?
[ $rc -eq 1 ] || bad "ARM scan without --dry-run: exit $rc"
grep -q "GPIO: gpiod: built without libgpiod\|GPIO: gpiod: cannot open chip" "$tmp/hw.txt" || { bad "ARM: missing GPIO support not named"; cat "$tmp/hw.txt"; }
[ ! -e "$tmp/hw.vplog" ] || bad "ARM: a log was written without hardware"
echo "without --dry-run: $(grep 'GPIO:' "$tmp/hw.txt" | sed 's/^ *//')"
[ $fail -eq 0 ] && echo "aarch64 device program: dry-run scan of boards/sim.ini to DONE under qemu in $secs s, replayed on x86-64 to the same bytes"
exit $fail
