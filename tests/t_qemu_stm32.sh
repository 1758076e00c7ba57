#!/bin/sh
# The microcontroller scanner on an STM32F405 (128 KiB of SRAM): boards/cortex-m4's
# board_stm32f405.c image boots under qemu-system-arm -M netduinoplus2 (-icount shift=3), plans
# a scan of host-sim's unit sphere at eps 0.35 in a 100 KiB arena (the planner's split and
# headroom for small arenas) and streams its session log over USART1 to `voroprobe mcu`.
# Checked by code that is not the firmware's:
#  - DONE, and the mesh is closed: `voroprobe certify` on the written OFF (H1 and H2 hold);
#  - `voroprobe log verify` proves every logged move from the logged probes;
#  - the log is byte-identical to the same sources and arena built for x86-64 over a pipe;
#  - every move's step edges per axis and timer schedule match the ideal trapezoid, none served
#    after the next was due, each move's last edge within a pulse width (12 us) of its time;
#  - the image fits the part: flash <= 1 MiB, RAM <= 128 KiB with 10 KiB left for the stack.
set -u
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
command -v qemu-system-arm >/dev/null || { echo "qemu-system-arm missing (make deps)"; exit 1; }
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail() { echo "t_qemu_stm32: $*"; exit 1; }
size=$(sh boards/cortex-m4/build.sh "$B") || fail "the firmware does not build"
line=$(echo "$size" | grep "^stm32f405 image:") || fail "no STM32F405 image"
echo "$line"
flash=$(echo "$line" | sed -n 's/.*flash \([0-9]*\) bytes.*/\1/p')
ram=$(echo "$line" | sed -n 's/.*RAM \([0-9]*\) bytes.*/\1/p')
[ "$flash" -le 1048576 ] && [ "$ram" -le $((131072 - 10240)) ] || fail "the image does not fit: flash $flash, RAM $ram"
S="--surface sphere --eps 0.35 --quiet"
"$VP" mcu --exec "$B/m4/voroprobe-stm32f405-host" $S --out "$tmp/host" >"$tmp/host.txt" 2>&1 ||
  { cat "$tmp/host.txt"; fail "the x86-64 build's session failed"; }
t0=$(date +%s)
"$VP" mcu --qemu "$B/m4/voroprobe-stm32f405.elf" --machine netduinoplus2 $S --out "$tmp/q" >"$tmp/q.txt" 2>"$tmp/q.err" ||
  { cat "$tmp/q.txt" "$tmp/q.err"; fail "the qemu session failed"; }
secs=$(( $(date +%s) - t0 ))
cat "$tmp/q.txt"
grep -q "board stm32f405, status ok" "$tmp/q.txt" || fail "the MCU did not reach DONE"
cmp "$tmp/q.vplog" "$tmp/host.vplog" || fail "the STM32F405's log differs from the x86-64 one"
"$VP" certify "$tmp/q.off" --eps 0.35 --interior 0,0,0 >"$tmp/cert.txt" 2>&1
grep -q "^H1 .*: holds" "$tmp/cert.txt" && grep -q "^H2 .*: holds" "$tmp/cert.txt" ||
  { cat "$tmp/cert.txt"; fail "certify does not find a closed mesh around the interior point"; }
"$VP" log verify "$tmp/q.vplog" >"$tmp/verify.txt" 2>&1 || { cat "$tmp/verify.txt"; fail "log verify"; }
grep -q " 0 with wrong edge counts, 0 off schedule" "$tmp/q.txt" || fail "step edges"
grep -q " 0 served after the next was due" "$tmp/q.txt" || fail "late edges"
late=$(sed -n 's/.*last edge \([0-9]*\)\.[0-9] us after.*/\1/p' "$tmp/q.txt")
[ -n "$late" ] && [ "$late" -lt 12 ] || fail "a move's last edge ${late:-?} us late"
v=$(sed -n 's/.* \([0-9]*\) vertices, \([0-9]*\) facets.*/\1/p' "$tmp/q.txt" | head -n 1)
p=$(sed -n 's/.*status ok, [0-9]* commands, \([0-9]*\) probes.*/\1/p' "$tmp/q.txt")
peak=$(sed -n 's/.*arena peak \([0-9]*\) of \([0-9]*\) bytes.*/\1 of \2/p' "$tmp/q.txt" | head -n 1)
echo "qemu netduinoplus2 (STM32F405): DONE in ${secs} s, $p probes, $v vertices, closed, arena peak $peak bytes; log identical to x86-64; step edges exact, none late"
