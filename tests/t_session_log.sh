#!/bin/sh
# Session logs through the command line: sim writes PREFIX.vplog; replay rebuilds byte-identical
# PLY/OFF files (here, and on aarch64 under qemu from the same logs); sessions cut at random
# record boundaries, at random byte offsets (torn records) and by a simulated power cut resume
# to the uncut mesh; damaged logs name the bad record and keep the rest; a newer format
# version is refused; a distance bound's session (the smallest ball first, version 8) and one
# logged before that rule (version 3) resume bit for bit; log dump/check, mesh of an incomplete
# session, --help everywhere.
. tests/lib.sh
B=$BUILD
N=${VP_LOG_CUTS:-24}
[ "${VP_TEST_QUICK:-0}" != 0 ] && N=6

for c in replay mesh log certify sim; do
  "$VP" $c --help >/dev/null 2>&1 || bad "$c --help"
done
"$VP" log dump --help | grep -q jsonl || bad "log --help"

# ---- sim -> replay: byte-identical meshes
S="--quiet --hausdorff 0 --sync close"
for spec in "torus:--noise 0.0005 --dropout 0.1" "sphere:--paper" "sphere@2.5,0,0+torus:--dropout 0.05"; do
  surf=${spec%%:*}; opts=${spec#*:}
  name=$(echo "$surf" | tr -c 'a-z0-9\n' '_')
  # exit 4: DONE but not closed (the two-object scene at this eps): still a whole session to replay
  "$VP" sim --surface "$surf" --eps-rel 0.05 $opts --out "$tmp/$name" $S >/dev/null; rc=$?
  [ $rc -eq 0 ] || [ $rc -eq 4 ] || bad "sim $surf: exit $rc"
  [ -s "$tmp/$name.vplog" ] || bad "sim $surf wrote no log"
  "$VP" replay "$tmp/$name.vplog" --out "$tmp/$name.re" >"$tmp/replay.txt" 2>&1 || { bad "replay $surf"; cat "$tmp/replay.txt"; }
  cmp -s "$tmp/$name.ply" "$tmp/$name.re.ply" || bad "replay of $surf: PLY differs"
  cmp -s "$tmp/$name.off" "$tmp/$name.re.off" || bad "replay of $surf: OFF differs"
done
echo "sim -> replay: PLY and OFF byte-identical for 3 sessions"

# ---- the same logs replayed by the aarch64 build under qemu
A="$B/aarch64"
if command -v aarch64-linux-gnu-gcc >/dev/null && command -v qemu-aarch64 >/dev/null; then
  make --no-print-directory -s BUILD="$A" CROSS=aarch64-linux-gnu- "$A/voroprobe" >"$tmp/a64.log" 2>&1 ||
    { tail "$tmp/a64.log"; bad "aarch64 build"; }
  for name in torus sphere; do
    qemu-aarch64 -L /usr/aarch64-linux-gnu "$A/voroprobe" replay "$tmp/$name.vplog" --out "$tmp/$name.arm" --quiet ||
      bad "aarch64 replay $name"
    cmp -s "$tmp/$name.ply" "$tmp/$name.arm.ply" || bad "aarch64 replay of $name: PLY differs from x86-64's"
    cmp -s "$tmp/$name.off" "$tmp/$name.arm.off" || bad "aarch64 replay of $name: OFF differs from x86-64's"
  done
  echo "aarch64 (qemu) replays the x86-64 logs to byte-identical PLY/OFF"
else
  echo "aarch64 cross tools missing: aarch64 replay not checked (make deps)"
  fail=1
fi

# ---- cut and resume
L="$tmp/torus.vplog"
"$VP" log dump "$L" --csv | awk -F, 'NR > 1 {print $2}' >"$tmp/offsets"
size=$(wc -c <"$L")
nrec=$(wc -l <"$tmp/offsets")
awk -v n="$N" -v nrec="$nrec" -v size="$size" -v first="$(head -1 "$tmp/offsets")" 'BEGIN {
  srand(20261125);
  for (i = 0; i < n; i++) print "rec", 1 + int(rand() * nrec);
  for (i = 0; i < n; i++) print "byte", first + int(rand() * (size - first));
}' >"$tmp/cuts"
ok=0; k=0
while read kind at; do
  k=$((k + 1))
  if [ "$kind" = rec ]; then at=$(sed -n "${at}p" "$tmp/offsets"); fi
  head -c "$at" "$L" >"$tmp/cut$k.vplog"
  "$VP" sim --resume "$tmp/cut$k.vplog" $S >"$tmp/resume.txt" 2>&1 || { bad "resume of a cut at $kind $at"; tail -3 "$tmp/resume.txt"; continue; }
  if cmp -s "$tmp/cut$k.ply" "$tmp/torus.ply"; then ok=$((ok + 1)); else bad "cut at byte $at ($kind): resumed mesh differs"; fi
  # the appended log is intact and complete
  "$VP" log check "$tmp/cut$k.vplog" --no-replay >"$tmp/check.txt" || { bad "cut $k: log not intact after resume"; cat "$tmp/check.txt"; }
  grep -q "complete (DONE)" "$tmp/check.txt" || bad "cut $k: resumed log has no DONE"
  rm -f "$tmp/cut$k".*
done <"$tmp/cuts"
echo "resume: $ok of $k cuts ($N at record boundaries, $N torn) give the uncut mesh byte for byte"

# simulated power cuts inside the writer (torn write), resumed twice in a row
for bytes in 777 20000 123457; do
  "$VP" sim --surface torus --eps-rel 0.05 --noise 0.0005 --dropout 0.1 --out "$tmp/pc" $S --power-cut $bytes >/dev/null 2>"$tmp/pc.txt"
  [ $? -ne 0 ] && grep -q "power cut" "$tmp/pc.txt" || bad "power cut at $bytes not reported"
  [ "$(wc -c <"$tmp/pc.vplog")" -eq $bytes ] || bad "power cut at $bytes: log has $(wc -c <"$tmp/pc.vplog") bytes"
  "$VP" sim --resume "$tmp/pc.vplog" $S --power-cut $((bytes + 150000)) >/dev/null 2>&1
  "$VP" sim --resume "$tmp/pc.vplog" $S >/dev/null 2>&1 || bad "resume after power cut at $bytes"
  cmp -s "$tmp/pc.ply" "$tmp/torus.ply" || bad "power cut at $bytes: resumed mesh differs"
done
echo "power cuts at 777, 20000, 123457 bytes (then another one): resumed to the uncut mesh"

# the note keeps a long mesh path with spaces whole: a resumed off: scan is the uncut one
d="$tmp/a folder whose name is long enough to pass sixty-four characters/and more"
mkdir -p "$d" && cp "$tmp/sphere.off" "$d/the object.off"
"$VP" sim --surface "off:$d/the object.off" --eps-rel 0.08 --out "$tmp/lp" $S >/dev/null 2>&1 || bad "sim of an off: mesh at a long path"
"$VP" sim --surface "off:$d/the object.off" --eps-rel 0.08 --out "$tmp/lpc" $S --stop-after 400 >/dev/null 2>&1
"$VP" sim --resume "$tmp/lpc.vplog" $S >"$tmp/lp.txt" 2>&1 || { bad "resume of an off: scan at a long path"; tail -3 "$tmp/lp.txt"; }
cmp -s "$tmp/lp.ply" "$tmp/lpc.ply" || bad "off: scan at a long path: resumed mesh differs"

# the sizing field (--size-rel, --min-size): a version 2 header; replayed and resumed bit for bit
"$VP" sim --surface ellipsoid --eps 0.3 --size-rel 0.15 --min-size 0.01 --out "$tmp/sz" $S >/dev/null 2>&1 || bad "sim --size-rel: exit $?"
"$VP" replay "$tmp/sz.vplog" --out "$tmp/sz.re" >/dev/null 2>&1 && cmp -s "$tmp/sz.ply" "$tmp/sz.re.ply" || bad "sizing field: replay differs"
"$VP" log dump "$tmp/sz.vplog" | head -5 | grep -q -- "--size-rel 0.15" || bad "sizing field: not in the log's note"
"$VP" sim --surface ellipsoid --eps 0.3 --size-rel 0.15 --min-size 0.01 --out "$tmp/szp" $S --stop-after 500 >/dev/null 2>&1
"$VP" sim --resume "$tmp/szp.vplog" $S >/dev/null 2>&1 || bad "sizing field: resume"
cmp -s "$tmp/sz.ply" "$tmp/szp.ply" || bad "sizing field: paused + resumed mesh differs"
"$VP" sim --surface ellipsoid --eps 0.3 --min-size 0.01 --out "$tmp/szb" $S >/dev/null 2>"$tmp/e.txt" && bad "--min-size without --size-rel accepted"
echo "sizing field: a version 2 log, replayed and resumed bit for bit"

# a distance bound in point mode: the smallest ball first, a version 8 log, resumed bit for bit;
# and a session logged before that rule (version 3, the newest task first), made here from a
# --newest-first log whose note loses that option (header length and CRC made good), as a build
# before wrote it: resumed with the newest task first, bit for bit
A="--quiet --sync close"
"$VP" sim --surface torus --accuracy-rel 0.005 --out "$tmp/sb" $A >/dev/null 2>&1 || bad "sim --accuracy-rel: exit $?"
"$VP" log dump "$tmp/sb.vplog" | head -1 | grep -q "format version 8" || bad "the smallest ball first: not a version 8 log"
"$VP" sim --surface torus --accuracy-rel 0.005 --out "$tmp/sbp" $A --stop-after 2500 >/dev/null 2>&1
"$VP" sim --resume "$tmp/sbp.vplog" --quiet >/dev/null 2>&1 || bad "the smallest ball first: resume"
cmp -s "$tmp/sb.ply" "$tmp/sbp.ply" || bad "the smallest ball first: paused + resumed mesh differs"
"$VP" sim --surface torus --accuracy-rel 0.005 --newest-first --out "$tmp/nf" $A >/dev/null 2>&1 || bad "--newest-first: exit $?"
"$VP" sim --surface torus --accuracy-rel 0.005 --newest-first --out "$tmp/nfp" $A --stop-after 2500 >/dev/null 2>&1
cmp -s "$tmp/sb.ply" "$tmp/nf.ply" && bad "the two orders gave one mesh: the old log below would prove nothing"
python3 - "$tmp/nfp.vplog" "$tmp/old.vplog" <<'PY' || bad "could not write the old log"
import struct, sys, zlib
b = open(sys.argv[1], 'rb').read()
H = struct.unpack_from('<I', b, 12)[0]          # the header's length
q = 188 + 24 * struct.unpack_from('<I', b, 184)[0]
q += 2 + struct.unpack_from('<H', b, q)[0]     # past the board name
nl = struct.unpack_from('<H', b, q)[0]
note = b[q + 2:q + 2 + nl]
new = note.replace(b' --newest-first', b'')
assert new != note
h = b[:q] + struct.pack('<H', len(new)) + new + b[q + 2 + nl:H - 4]
h = h[:12] + struct.pack('<I', len(h) + 4) + h[16:]
open(sys.argv[2], 'wb').write(h + struct.pack('<I', zlib.crc32(h) & 0xffffffff) + b[H:])
PY
"$VP" log dump "$tmp/old.vplog" >"$tmp/old.dump" 2>&1 || bad "the old log does not read: $(head -2 "$tmp/old.dump")"
head -1 "$tmp/old.dump" | grep -q "format version 3" && ! head -3 "$tmp/old.dump" | grep -q -- "--newest-first" ||
  bad "the old log is not one a build before wrote: $(head -2 "$tmp/old.dump")"
"$VP" sim --resume "$tmp/old.vplog" --quiet >"$tmp/old.txt" 2>&1 || { bad "a version 3 log with a distance bound: resume"; tail -2 "$tmp/old.txt"; }
cmp -s "$tmp/nf.ply" "$tmp/old.ply" || bad "a version 3 log with a distance bound: resumed mesh differs from the newest task first's"
echo "distance bound: a version 8 log (the smallest ball first) and a version 3 one (the newest task first) resumed bit for bit"
# the smallest ball first picks alike on aarch64: replay there checks each command against the log
if [ -x "$B/aarch64/voroprobe" ]; then
  qemu-aarch64 -L /usr/aarch64-linux-gnu "$B/aarch64/voroprobe" replay "$tmp/sb.vplog" --out "$tmp/sb.arm" --quiet >"$tmp/sbarm.txt" 2>&1 ||
    { bad "aarch64 replay of the smallest ball first's log"; tail -2 "$tmp/sbarm.txt"; }
  cmp -s "$tmp/sb.ply" "$tmp/sb.arm.ply" && cmp -s "$tmp/sb.off" "$tmp/sb.arm.off" ||
    bad "aarch64 replay of the smallest ball first's log: mesh differs from x86-64's"
  echo "aarch64 (qemu) replays the smallest ball first's log to the same PLY/OFF"
fi

# a pause is resumable too
"$VP" sim --surface torus --eps-rel 0.05 --noise 0.0005 --dropout 0.1 --out "$tmp/pa" $S --stop-after 3000 >/dev/null 2>&1
"$VP" log dump "$tmp/pa.vplog" | tail -1 | grep -q "EVENT pause" || bad "--stop-after wrote no PAUSE event"
"$VP" sim --resume "$tmp/pa.vplog" $S >/dev/null 2>&1 || bad "resume after a pause"
cmp -s "$tmp/pa.ply" "$tmp/torus.ply" || bad "paused + resumed mesh differs"
# --stop-after exits 3 (stopped), not 0 or 1
"$VP" sim --surface sphere --eps-rel 0.05 --out "$tmp/pb" $S --stop-after 50 >/dev/null 2>&1; rc=$?
[ $rc -eq 3 ] || bad "--stop-after: exit $rc (3 expected)"

# SIGTERM (a supervisor stopping the scan): a PAUSE event after the current command, exit 3,
# and the resumed session ends with the same mesh as an uncut one
"$VP" sim --surface genus2 --eps 0.02 --out "$tmp/sig" $S --json >"$tmp/sig.txt" 2>&1 &
pid=$!
i=0; while [ $i -lt 100 ] && [ "$( (wc -c <"$tmp/sig.vplog") 2>/dev/null || echo 0)" -lt 200000 ]; do sleep 0.05; i=$((i+1)); done
kill -TERM $pid; wait $pid; rc=$?
[ $rc -eq 3 ] || bad "SIGTERM: exit $rc (3 expected)"
tail -n 1 "$tmp/sig.txt" | grep -q '"status":"stopped","exit":3' || bad "SIGTERM: the JSON does not say stopped"
"$VP" log dump "$tmp/sig.vplog" | tail -1 | grep -q "EVENT pause" || bad "SIGTERM wrote no PAUSE event"
"$VP" sim --resume "$tmp/sig.vplog" $S >/dev/null 2>&1 || bad "resume after SIGTERM: exit $?"
"$VP" sim --surface genus2 --eps 0.02 --out "$tmp/nosig" $S >/dev/null 2>&1 || bad "genus2 0.02 uncut"
cmp -s "$tmp/sig.ply" "$tmp/nosig.ply" || bad "SIGTERM + resume: mesh differs from the uncut scan"

# ---- damage: a flipped byte in the middle
off=$(sed -n "$((nrec / 2))p" "$tmp/offsets")
cp "$L" "$tmp/dmg.vplog"
printf '\377' | dd of="$tmp/dmg.vplog" bs=1 seek=$((off + 30)) conv=notrunc 2>/dev/null
"$VP" log check "$tmp/dmg.vplog" >"$tmp/check.txt"; rc=$?
[ $rc -eq 1 ] || bad "log check of a damaged log: exit $rc"
grep -q "record $((nrec / 2 - 1)) (byte offset $off): CRC mismatch" "$tmp/check.txt" || { bad "damage not named"; cat "$tmp/check.txt"; }
grep -q "replay: the planner reissues" "$tmp/check.txt" || bad "valid part of a damaged log does not replay"
"$VP" replay "$tmp/dmg.vplog" --out "$tmp/dmg" --quiet 2>"$tmp/err.txt" || bad "replay of a damaged log"
grep -q "byte offset $off" "$tmp/err.txt" || bad "replay does not name the damage"
"$VP" replay "$L" --upto $((nrec / 2 - 1)) --out "$tmp/half" --quiet
cmp -s "$tmp/dmg.ply" "$tmp/half.ply" || bad "damaged log: mesh of the valid part differs"
"$VP" sim --resume "$tmp/dmg.vplog" $S >/dev/null 2>&1 || bad "resume of a damaged log"
cmp -s "$tmp/dmg.ply" "$tmp/torus.ply" || bad "damaged log resumed: mesh differs"
echo "damaged log: record $((nrec / 2 - 1)) at byte $off named; the valid part replays and resumes"

# ---- a newer format version is refused (the header intact: its CRC rewritten; the CRC-32 of
# the header's first H-4 bytes is the one in gzip's trailer)
cp "$L" "$tmp/new.vplog"
printf '\377' | dd of="$tmp/new.vplog" bs=1 seek=8 conv=notrunc 2>/dev/null
hl=$(od -An -tu4 -j12 -N4 "$tmp/new.vplog" | tr -d ' ')
head -c $((hl - 4)) "$tmp/new.vplog" | gzip -c | tail -c 8 | head -c 4 |
  dd of="$tmp/new.vplog" bs=1 seek=$((hl - 4)) conv=notrunc 2>/dev/null
"$VP" replay "$tmp/new.vplog" --out "$tmp/new" 2>"$tmp/err.txt" && bad "a newer version was accepted"
grep -q "newer format version" "$tmp/err.txt" || { bad "newer version message"; cat "$tmp/err.txt"; }
"$VP" log check "$tmp/new.vplog" >/dev/null && bad "log check accepted a newer version"

# ---- dumps
"$VP" log dump "$L" --jsonl >"$tmp/d.jsonl" || bad "dump --jsonl"
[ "$(wc -l <"$tmp/d.jsonl")" -eq $((nrec + 1)) ] || bad "jsonl: wrong line count"
if command -v python3 >/dev/null; then
  python3 -c "
import json,sys
n=0
for line in open(sys.argv[1]): json.loads(line); n+=1
print('jsonl: %d valid JSON lines' % n)" "$tmp/d.jsonl" || bad "jsonl is not JSON"
fi
"$VP" log dump "$L" | grep -c PROBE >/dev/null || bad "text dump"

# ---- mesh of an incomplete session: holes reported, not patched
head -c $((size / 3)) "$L" >"$tmp/inc.vplog"
"$VP" mesh "$tmp/inc.vplog" --out "$tmp/inc" --off --points >"$tmp/mesh.txt" 2>&1 || bad "mesh of an incomplete log"
grep -q "INCOMPLETE" "$tmp/mesh.txt" || bad "mesh: incomplete session not said"
grep -Eq "hole\(s\): [0-9]+ boundary edges" "$tmp/mesh.txt" || { bad "mesh: holes not reported"; cat "$tmp/mesh.txt"; }
"$VP" mesh "$L" --out "$tmp/full" >"$tmp/mesh.txt" 2>&1 || bad "mesh of a complete log"
grep -q "closed 2-manifold" "$tmp/mesh.txt" || bad "mesh: complete session not closed"
cmp -s "$tmp/full.ply" "$tmp/torus.ply" || bad "mesh of a complete log differs from the sim's"
sed -n 1,3p "$tmp/mesh.txt"

# ---- certify: a complete log holds H1-H3; an incomplete one names its holes; a bare mesh
"$VP" certify "$L" >"$tmp/cert.txt" || { bad "certify of a complete log"; cat "$tmp/cert.txt"; }
grep -q "^H3 .*holds (all" "$tmp/cert.txt" || bad "certify: H3 not established from the log"
"$VP" certify "$L" --reach 0.3 >"$tmp/cert.txt" && bad "certify: eps >= 0.091 reach accepted"
grep -q "eps < 0.091 reach: FAILS" "$tmp/cert.txt" || bad "certify: reach condition not reported"
"$VP" certify "$tmp/inc.vplog" >"$tmp/cert.txt" 2>/dev/null && bad "certify accepted an incomplete session"
grep -q "a boundary edge: a hole" "$tmp/cert.txt" || bad "certify: holes not named"
"$VP" certify "$tmp/torus.ply" --eps 0.19 --interior -1,0,0 >"$tmp/cert.txt" || bad "certify of a bare mesh"
grep -q "cannot be checked" "$tmp/cert.txt" || bad "certify: bare mesh H3 claimed"
"$VP" certify "$tmp/torus.ply" >/dev/null 2>&1; [ $? -eq 2 ] || bad "certify of a mesh without --eps"
echo "certify: complete log certified (H1-H3), reach condition, holes named, bare mesh limits said"

[ $fail -eq 0 ] && echo "t_session_log: all checks passed"
exit $fail
