#!/bin/sh
# The microcontroller scanner end to end: boards/cortex-m4's MPS2 AN386 image boots under
# qemu-system-arm (-M mps2-an386, -icount shift=3), plans a scan of host-sim's unit sphere at
# eps 0.35 and streams its session log over the emulated UART to `voroprobe mcu`. Checked by
# code that is not the firmware's:
#  - the mesh is closed: `voroprobe certify` on the written OFF (H1 and H2 hold);
#  - `voroprobe log verify` proves every logged move from the logged probes;
#  - the log is byte-identical to the same sources built for x86-64 over a pipe, and to a
#    qemu run with 40 frames damaged on the link (20 each way: each caught, asked again);
#  - every move's step edges per axis and timer schedule match the ideal trapezoid computed
#    on the host, and the board's own clock saw every edge served before the next was due
#    and each move's last edge within a pulse width of its time; a wire that rewrites one
#    MOVE report (tests/mcu_tamper.py, CRC made good) must be caught by the check (exit 1);
#  - the e-stop is debounced: pressed for 2 reads it is ignored, for 3 it stops the scan.
set -u
B=${BUILD:-build}
VP=${VP:-$B/voroprobe}
command -v qemu-system-arm >/dev/null || { echo "qemu-system-arm missing (make deps)"; exit 1; }
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail() { echo "t_qemu_m4: $*"; exit 1; }
size=$(sh boards/cortex-m4/build.sh "$B") || fail "the firmware does not build"
echo "$size"
S="--surface sphere --eps 0.35 --quiet"
# a body is refused before any link is made: the host's replay, which checks the MCU's log, plans
# a body in another order than the MCU's core (the build before ran the whole scan and then failed
# that check at record 8, exit 1)
"$VP" mcu --exec "$B/m4/voroprobe-m4-host" $S --clearance 0.05 --out "$tmp/body" >"$tmp/body.txt" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q 'mcu: a microcontroller core keeps the probe a point (no --clearance)' "$tmp/body.txt" &&
  [ ! -e "$tmp/body.vplog" ] || fail "--clearance: exit $rc, not refused: $(head -n 1 "$tmp/body.txt")"
"$VP" mcu --exec "$B/m4/voroprobe-m4-host" $S --out "$tmp/host" >"$tmp/host.txt" 2>&1 ||
  { cat "$tmp/host.txt"; fail "the x86-64 build's session failed"; }
t0=$(date +%s)
"$VP" mcu --qemu "$B/m4/voroprobe-an386.elf" $S --out "$tmp/qemu" >"$tmp/qemu.txt" 2>"$tmp/qemu.err" ||
  { cat "$tmp/qemu.txt" "$tmp/qemu.err"; fail "the qemu session failed"; }
secs=$(( $(date +%s) - t0 ))
"$VP" mcu --qemu "$B/m4/voroprobe-an386.elf" $S --corrupt 40 --out "$tmp/qc" >"$tmp/qc.txt" 2>"$tmp/qc.err" ||
  { cat "$tmp/qc.txt" "$tmp/qc.err"; fail "the qemu session with damaged frames failed"; }
cat "$tmp/qemu.txt"
grep -q "status ok" "$tmp/qemu.txt" || fail "the MCU did not reach DONE"
cmp "$tmp/qemu.vplog" "$tmp/host.vplog" || fail "the M4's log differs from the x86-64 one"
cmp "$tmp/qc.vplog" "$tmp/qemu.vplog" || fail "the log with damaged frames differs"
grep -q "damaged frames caught: 20 here, 20 on the MCU (20 + 20 injected)" "$tmp/qc.txt" ||
  { grep link: "$tmp/qc.txt"; fail "not every damaged frame was caught"; }
for r in qemu qc; do
  "$VP" certify "$tmp/$r.off" --eps 0.35 --interior 0,0,0 >"$tmp/cert.txt" 2>&1
  grep -q "^H1 .*: holds" "$tmp/cert.txt" && grep -q "^H2 .*: holds" "$tmp/cert.txt" ||
    { cat "$tmp/cert.txt"; fail "$r: certify does not find a closed mesh around the interior point"; }
  "$VP" log verify "$tmp/$r.vplog" >"$tmp/verify.txt" 2>&1 || { cat "$tmp/verify.txt"; fail "$r: log verify"; }
  grep -q " 0 with wrong edge counts, 0 off schedule" "$tmp/$r.txt" || { grep steps: "$tmp/$r.txt"; fail "$r: step edges"; }
  # measured on the board's free-running clock: every edge's interrupt served before the next
  # edge was due, the last edge of every move within one pulse width (12 us) of its time
  grep -q " 0 served after the next was due" "$tmp/$r.txt" || { grep steps: "$tmp/$r.txt"; fail "$r: late edges"; }
  late=$(sed -n 's/.*last edge \([0-9]*\)\.[0-9] us after.*/\1/p' "$tmp/$r.txt")
  [ -n "$late" ] && [ "$late" -lt 12 ] || { grep steps: "$tmp/$r.txt"; fail "$r: a move's last edge ${late:-?} us late"; }
done
# the step check must catch a wrong report
printf '#!/bin/sh\nexec python3 "%s/tests/mcu_tamper.py"\n' "$(pwd)" >"$tmp/tamper.sh"; chmod +x "$tmp/tamper.sh"
VP_MCU_PROGRAM="$B/m4/voroprobe-m4-host" VP_TAMPER_MOVE=10 "$VP" mcu --exec "$tmp/tamper.sh" $S \
  --out "$tmp/tamper" >"$tmp/tamper.txt" 2>&1
rc=$?
[ $rc -eq 1 ] && grep -q " 1 with wrong edge counts" "$tmp/tamper.txt" ||
  { cat "$tmp/tamper.txt"; fail "a MOVE report with two extra edges was not caught (exit $rc)"; }
# the e-stop (the same sources on this machine, the input pressed on chosen reads after step
# pulses): 2 samples are a glitch (the scan and its log unchanged), 3 stop the scan (PAUSE)
for g in 2 3; do
  VP_M4_ESTOP=1000,$g "$VP" mcu --exec "$B/m4/voroprobe-m4-host" $S --out "$tmp/es$g" >"$tmp/es$g.txt" 2>&1
  echo $? >"$tmp/es$g.rc"
done
[ "$(cat "$tmp/es2.rc")" = 0 ] && cmp -s "$tmp/es2.vplog" "$tmp/host.vplog" ||
  { cat "$tmp/es2.txt"; fail "a 2-sample e-stop glitch changed the scan"; }
[ "$(cat "$tmp/es3.rc")" = 3 ] && "$VP" log dump "$tmp/es3.vplog" | tail -n 1 | grep -q "EVENT pause code -12 'e-stop or limit'" ||
  { cat "$tmp/es3.txt"; fail "a 3-sample e-stop did not stop the scan with a PAUSE event"; }
# clear errors: a board that never speaks, a qemu that is not there
"$VP" mcu --exec /bin/cat $S --timeout 1 --out "$tmp/silent" >"$tmp/silent.txt" 2>&1
[ $? -eq 1 ] && grep -q "the board is silent: no valid frame for 1 s" "$tmp/silent.txt" || { cat "$tmp/silent.txt"; fail "a silent board"; }
# a link that delivers only damaged frames (a wrong baud rate): silent too, not waited on forever
printf '#!/bin/sh\nwhile :; do printf "garbage\\000"; sleep 0.01; done\n' >"$tmp/noise.sh"; chmod +x "$tmp/noise.sh"
timeout 60 "$VP" mcu --exec "$tmp/noise.sh" $S --timeout 1 --out "$tmp/noise" >"$tmp/noise.txt" 2>&1
[ $? -eq 1 ] && grep -q "the board is silent: no valid frame for 1 s (damaged frames only" "$tmp/noise.txt" ||
  { cat "$tmp/noise.txt"; fail "a link of damaged frames only"; }
"$VP" mcu --qemu "$B/m4/voroprobe-an386.elf" --qemu-bin "$tmp/no-qemu" $S --out "$tmp/noq" >"$tmp/noq.txt" 2>&1
[ $? -eq 1 ] && grep -q "is not installed" "$tmp/noq.txt" || { cat "$tmp/noq.txt"; fail "qemu missing"; }
v=$(sed -n 's/.* \([0-9]*\) vertices, \([0-9]*\) facets.*/\1/p' "$tmp/qemu.txt" | head -n 1)
p=$(sed -n 's/.*status ok, [0-9]* commands, \([0-9]*\) probes.*/\1/p' "$tmp/qemu.txt")
lat=$(sed -n 's/.*last edge \([0-9.]*\) us after its time at most (mean \([0-9.]*\) us).*/\1 us max, \2 us mean/p' "$tmp/qemu.txt")
echo "qemu mps2-an386: DONE in ${secs} s, $p probes, $v vertices, closed; log identical to x86-64 and with 40 damaged frames; step edges exact, last edge ${lat} late; a tampered report caught; e-stop: 2-sample glitch ignored, 3 samples stop; a silent link and one of damaged frames only end with an error"
