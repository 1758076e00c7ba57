#!/bin/sh
# Inputs and outputs that used to fail quietly (issue 12): a long --out (1229 characters) is
# written whole, one over PATH_MAX is refused before anything is written; NUL bytes inside an
# OFF number, a .node line or an INI value are refused naming the line; /dev/zero as a mesh,
# a .node file, a board or a log is refused at once; a log being written is locked against a
# second writer; the messages for a tiny eps, an out-of-range rangefinder, a damaged log
# header, --eps with --eps-rel and an unknown option say what is wrong, once; a count given as
# '-3', 'abc' or 0 is refused (exit 2) by every command that takes one; report --json alone
# prints the summary; --png makes its folder.
. tests/lib.sh
B=$BUILD
S="--quiet --hausdorff 0 --sync close"

# ---- 1. long paths: 1229 characters are written whole; over PATH_MAX nothing is written
long="$tmp/x"
while [ ${#long} -lt 4200 ]; do long="$long/$(printf '%0200d' 0 | tr 0 e)"; done
d="$tmp"
while [ ${#d} -lt 1000 ]; do d="$d/$(printf '%0200d' 0 | tr 0 d)"; done
mkdir -p "$d" || exit 1
name=$(printf '%01229d' 0 | tr 0 s)
p="$d/$(echo "$name" | cut -c 1-$((1229 - ${#d} - 1)))"
[ ${#p} -eq 1229 ] || { bad "test set-up: --out is ${#p} characters"; }
"$VP" sim --surface sphere --eps 0.3 --out "$p" $S >"$tmp/o.txt" 2>&1 || { bad "sim with a 1229-character --out"; cat "$tmp/o.txt"; }
for x in ply off vplog; do [ -s "$p.$x" ] || bad "1229-character --out: $x not written whole"; done
[ "$(find "$d" -type f | wc -l)" -eq 3 ] || { bad "1229-character --out: other files written"; find "$d" -type f | sed 's/.*\(.\{40\}\)$/  ...\1/'; }
"$VP" log check "$p.vplog" >/dev/null || bad "the log of a 1229-character --out is not intact"
"$VP" replay "$p.vplog" --out "$p.re" >/dev/null 2>&1 && cmp -s "$p.ply" "$p.re.ply" || bad "replay to a long --out"
"$VP" mesh "$p.vplog" --out "$p.m" --points --off >/dev/null 2>&1 && [ -s "$p.m.points.ply" ] && [ -s "$p.m.off" ] ||
  bad "mesh --points to a long --out"
"$VP" replay "$p.vplog" --out "$long" >"$tmp/o.txt" 2>&1 && bad "replay to an --out over PATH_MAX accepted"
grep -q "is too long" "$tmp/o.txt" || { bad "replay: no clear message for an --out over PATH_MAX"; cat "$tmp/o.txt"; }
before=$(find "$tmp" | wc -l)
"$VP" sim --surface sphere --eps 0.3 --out "$long" $S >"$tmp/o.txt" 2>&1 && bad "an --out over PATH_MAX was accepted"
grep -q "is too long: .* bytes, at most" "$tmp/o.txt" || { bad "no clear message for an --out over PATH_MAX"; cat "$tmp/o.txt"; }
grep -q "^wrote" "$tmp/o.txt" && bad "an --out over PATH_MAX says it wrote the mesh"
[ "$(find "$tmp" | wc -l)" -eq "$before" ] || bad "an --out over PATH_MAX wrote something"
"$VP" sim --surface sphere --eps 0.3 --out "$tmp/ok" --log "$long.vplog" $S >"$tmp/o.txt" 2>&1 && bad "a --log over PATH_MAX was accepted"
grep -q "is too long" "$tmp/o.txt" || { bad "no clear message for a --log over PATH_MAX"; cat "$tmp/o.txt"; }
[ -e "$tmp/ok.ply" ] && bad "a --log over PATH_MAX: the mesh was written"
if [ -f boards/sim.ini ]; then
  "$VP" scan --board boards/sim.ini --dry-run --log "$long.vplog" --quiet >"$tmp/o.txt" 2>&1 && bad "scan: a --log over PATH_MAX was accepted"
  grep -q "scan: the path .* is too long" "$tmp/o.txt" || { bad "scan: no clear message for a --log over PATH_MAX"; cat "$tmp/o.txt"; }
  "$VP" scan --board boards/sim.ini --dry-run --log "$tmp/sc.vplog" --out "$long" --quiet >"$tmp/o.txt" 2>&1 && bad "scan: an --out over PATH_MAX was accepted"
  grep -q "scan: the path .* is too long" "$tmp/o.txt" || { bad "scan: no clear message for an --out over PATH_MAX"; cat "$tmp/o.txt"; }
  [ -e "$tmp/sc.vplog" ] && bad "scan: an --out over PATH_MAX: the log was written"
fi
"$VP" sim --surface sphere --eps 0.3 --out "$tmp/$(printf '%0260d' 0)" $S >"$tmp/o.txt" 2>&1 && bad "a 260-byte file name was accepted"
grep -q "in the path .* is too long: 26[0-9] bytes, at most 255" "$tmp/o.txt" || { bad "260-byte name message"; cat "$tmp/o.txt"; }
"$VP" sim --surface "off:$p.off" --eps-rel 0.3 --out "$tmp/s" $S --no-log >"$tmp/o.txt" 2>&1 && bad "a 1233-character surface term accepted"
grep -q "term 1 of the spec is too long: 1237 characters, at most 255" "$tmp/o.txt" || { bad "long surface term message"; cat "$tmp/o.txt"; }
echo "paths: a 1229-character --out written whole; over PATH_MAX or NAME_MAX refused, nothing written"

# ---- 2. NUL bytes inside text are refused, naming the line
printf 'OFF\n4 4 0\n-0.2986 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$tmp/t.off"
"$VP" sim --surface "off:$tmp/t.off" --eps-rel 0.3 --out "$tmp/t" $S --no-log >/dev/null 2>"$tmp/e.txt"
grep -q "line" "$tmp/e.txt" && grep -q "NUL" "$tmp/e.txt" && bad "a clean OFF file was said to hold a NUL"
printf 'OFF\n4 4 0\n-0.\0986 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$tmp/nul.off"
"$VP" sim --surface "off:$tmp/nul.off" --eps-rel 0.3 --out "$tmp/n" $S --no-log >/dev/null 2>"$tmp/e.txt" && bad "an OFF file with a NUL was accepted"
grep -q "line 3: a NUL byte" "$tmp/e.txt" || { bad "OFF NUL: line not named"; cat "$tmp/e.txt"; }
printf '3 3 0 0\n0 0 0 0\n1 1 0\0 0\n2 0 1 0\n' >"$tmp/nul.node"
"$VP" bench-delaunay --node "$tmp/nul.node" >/dev/null 2>"$tmp/e.txt" && bad "a .node file with a NUL was accepted"
grep -q "nul.node:3: a NUL byte" "$tmp/e.txt" || { bad ".node NUL: line not named"; cat "$tmp/e.txt"; }
if [ -f boards/sim.ini ]; then
  # "steps_per_unit = 8<NUL>0" was read as 8
  ln=$(grep -n "^steps_per_unit *= *80" boards/sim.ini | head -1 | cut -d: -f1)
  { head -n $((ln - 1)) boards/sim.ini; printf 'steps_per_unit = 8\0000\n'; tail -n +$((ln + 1)) boards/sim.ini; } >"$tmp/nul.ini"
  "$VP" scan --board "$tmp/nul.ini" --dry-run --log "$tmp/nul.vplog" >/dev/null 2>"$tmp/e.txt" && bad "a board with a NUL was accepted"
  grep -q "nul.ini:$ln: a NUL byte" "$tmp/e.txt" || { bad "INI NUL: line $ln not named"; cat "$tmp/e.txt"; }
  [ -e "$tmp/nul.vplog" ] && bad "a board with a NUL: a log was written"
fi
echo "NUL bytes: OFF, .node and INI refused naming the line"

# ---- 3. devices are refused at once (off:/dev/zero grew to 2.3 GB in 10 s)
t0=$(date +%s)
timeout 10 "$VP" sim --surface off:/dev/zero --eps-rel 0.1 --out "$tmp/z" $S --no-log >/dev/null 2>"$tmp/e.txt"
rc=$?; [ $rc -ne 0 ] && [ $rc -ne 124 ] || bad "off:/dev/zero: exit $rc (124: still reading after 10 s)"
grep -q "/dev/zero is not a regular file" "$tmp/e.txt" || { bad "off:/dev/zero message"; cat "$tmp/e.txt"; }
timeout 10 "$VP" bench-delaunay --node /dev/zero >/dev/null 2>"$tmp/e.txt"
rc=$?; [ $rc -ne 0 ] && [ $rc -ne 124 ] || bad "bench-delaunay --node /dev/zero: exit $rc (124: still reading after 10 s)"
grep -q "/dev/zero is not a regular file" "$tmp/e.txt" || { bad "--node /dev/zero message"; cat "$tmp/e.txt"; }
timeout 10 "$VP" sim --surface ply:/dev/zero --eps-rel 0.1 --out "$tmp/z" $S --no-log >/dev/null 2>&1 && bad "ply:/dev/zero accepted"
timeout 10 "$VP" scan --board /dev/zero --dry-run --log "$tmp/z.vplog" >/dev/null 2>"$tmp/e.txt" && bad "--board /dev/zero accepted"
grep -q "/dev/zero is not a regular file" "$tmp/e.txt" || { bad "--board /dev/zero message"; cat "$tmp/e.txt"; }
timeout 10 "$VP" log check /dev/zero >/dev/null 2>&1 && bad "log check /dev/zero accepted"
timeout 10 "$VP" replay /dev/zero --out "$tmp/z" >/dev/null 2>"$tmp/e.txt" && bad "replay /dev/zero accepted"
grep -q "/dev/zero is not a regular file" "$tmp/e.txt" || { bad "replay /dev/zero message"; cat "$tmp/e.txt"; }
head -c 1000000 /dev/zero >"$tmp/zeros.off"
"$VP" sim --surface "off:$tmp/zeros.off" --eps-rel 0.1 --out "$tmp/z" $S --no-log >/dev/null 2>"$tmp/e.txt" && bad "a file of zeros accepted"
grep -q "neither 'ply' nor 'OFF'" "$tmp/e.txt" || { bad "a file of zeros: no header message"; cat "$tmp/e.txt"; }
[ $(($(date +%s) - t0)) -le 20 ] || bad "refusing devices took $(($(date +%s) - t0)) s"
echo "devices: /dev/zero refused at once as a mesh, .node file, board and log; a file of zeros has no header"

# ---- 4. a log being written is locked
"$VP" sim --surface sphere --eps-rel 0.1 --out "$tmp/lk" --stop-after 300 $S >/dev/null 2>&1   # paused: resumable
"$VP" log dump "$tmp/lk.vplog" 2>/dev/null | grep -qi "pause" || bad "sim for the lock test: no paused log"
cp "$tmp/lk.vplog" "$tmp/keep.vplog"
if command -v flock >/dev/null; then
  # a lock held as another writer holds it (flock(1) takes the same flock(2) lock)
  flock -o "$tmp/lk.vplog" sleep 5 &
  holder=$!
  sleep 0.5
  "$VP" sim --surface sphere --eps-rel 0.1 --out "$tmp/lk" $S >/dev/null 2>"$tmp/e.txt" && bad "a locked log was written"
  grep -q "log $tmp/lk.vplog is being written by another process" "$tmp/e.txt" || { bad "lock message"; cat "$tmp/e.txt"; }
  cmp -s "$tmp/lk.vplog" "$tmp/keep.vplog" || bad "a locked log was changed"
  "$VP" sim --resume "$tmp/lk.vplog" --no-log $S >/dev/null 2>&1 || bad "reading a locked log to resume without a log"
  "$VP" sim --resume "$tmp/lk.vplog" $S >/dev/null 2>"$tmp/e.txt" && bad "a locked paused log was resumed"
  grep -q "is being written by another process" "$tmp/e.txt" || { bad "resume: lock message"; cat "$tmp/e.txt"; }
  if [ -f boards/sim.ini ]; then
    "$VP" scan --board boards/sim.ini --dry-run --log "$tmp/lk.vplog" --quiet >/dev/null 2>"$tmp/e.txt" && bad "scan wrote a locked log"
    grep -q "scan: log $tmp/lk.vplog is being written by another process" "$tmp/e.txt" || { bad "scan: lock message"; cat "$tmp/e.txt"; }
  fi
  cmp -s "$tmp/lk.vplog" "$tmp/keep.vplog" || bad "a locked log was changed"
  kill "$holder" 2>/dev/null; wait "$holder" 2>/dev/null
fi
# two scans at once: the second is refused, the first ends with an intact log
"$VP" sim --surface torus --eps-rel 0.003 --out "$tmp/two" $S >"$tmp/first.txt" 2>&1 &
first=$!
i=0
while [ ! -s "$tmp/two.vplog" ] && [ $i -lt 200 ]; do sleep 0.01; i=$((i + 1)); done
"$VP" sim --surface torus --eps-rel 0.05 --out "$tmp/two" $S >/dev/null 2>"$tmp/e.txt" && bad "two writers of one log: the second succeeded"
grep -q "is being written by another process" "$tmp/e.txt" || { bad "second writer: no lock message"; cat "$tmp/e.txt"; }
wait "$first"   # its exit status says how the scan ended; its log must be whole
grep -q "session log\|being written" "$tmp/first.txt" && { bad "the first writer's log failed"; cat "$tmp/first.txt"; }
grep -q "^wrote" "$tmp/first.txt" || { bad "the first writer did not finish"; cat "$tmp/first.txt"; }
"$VP" log check "$tmp/two.vplog" --no-replay >"$tmp/c.txt" 2>&1 || { bad "two writers: the log is damaged"; cat "$tmp/c.txt"; }
echo "lock: a log being written is refused to a second writer and left intact"

# ---- 5. messages that say what is wrong
m() { "$VP" sim --surface sphere "$@" --out "$tmp/m" $S --no-log >/dev/null 2>"$tmp/e.txt"; }
m --eps 1e-16 && bad "--eps 1e-16 accepted"
grep -q "eps 1e-16 is too small for this object.*the smallest accepted is --eps [0-9.e-]* (--eps-rel" "$tmp/e.txt" || { bad "eps message"; cat "$tmp/e.txt"; }
grep -q "internal consistency" "$tmp/e.txt" && bad "eps: internal consistency message"
small=$(sed -n 's/.*the smallest accepted is --eps \([0-9.e+-]*\) .*/\1/p' "$tmp/e.txt")
if [ -n "$small" ]; then
  # accepted when given back (a paused session: --stop-after needs the log)
  "$VP" sim --surface sphere --eps "$small" --out "$tmp/small" --stop-after 50 $S >/dev/null 2>"$tmp/e2.txt"
  grep -q "too small" "$tmp/e2.txt" && bad "the smallest accepted eps ($small) is refused"
else bad "eps message names no smallest value"; fi
# scan says the same for a board (and writes no log)
"$VP" scan --board boards/sim.ini --dry-run --log "$tmp/e16.vplog" --eps 1e-16 >/dev/null 2>"$tmp/e.txt" && bad "scan --eps 1e-16 accepted"
grep -q "eps 1e-16 is too small for this object.*the smallest accepted is --eps [0-9.e-]*$" "$tmp/e.txt" || { bad "scan eps message"; cat "$tmp/e.txt"; }
[ -e "$tmp/e16.vplog" ] && bad "scan --eps 1e-16 wrote a log"
m --eps 0.1 --dropout 0.8 && bad "--dropout 0.8 accepted"
grep -q "\-\-dropout 0.8 is out of the range the planner supports: 0 to 0.5" "$tmp/e.txt" || { bad "dropout message"; cat "$tmp/e.txt"; }
m --eps 0.1 --noise 1 && bad "--noise 1 accepted"
grep -q "\-\-noise 1 is out of the range the planner supports: 0 to eps/16 (0.00625 at eps 0.1)" "$tmp/e.txt" || { bad "noise message"; cat "$tmp/e.txt"; }
grep -q "not inside the object" "$tmp/e.txt" && bad "noise: 'not inside the object'"
m --eps 0.1 --eps-rel 0.05 && bad "--eps with --eps-rel accepted"
grep -q "\-\-eps and \-\-eps-rel both set eps: give one of them" "$tmp/e.txt" || { bad "--eps with --eps-rel message"; cat "$tmp/e.txt"; }
m --eps-rel 0.05 --eps 0.1 && bad "--eps-rel with --eps accepted"
m --eps 0.1 --bogus && bad "--bogus accepted"
[ "$(grep -c "unknown option" "$tmp/e.txt")" -eq 1 ] && grep -q "unknown option --bogus" "$tmp/e.txt" || { bad "unknown option not said once"; cat "$tmp/e.txt"; }
cp "$tmp/keep.vplog" "$tmp/dmg.vplog"
printf '\001' | dd of="$tmp/dmg.vplog" bs=1 seek=9 conv=notrunc 2>/dev/null   # version 257, the CRC no longer matches
"$VP" replay "$tmp/dmg.vplog" --out "$tmp/dmg" >/dev/null 2>"$tmp/e.txt" && bad "a damaged header was replayed"
grep -q "the header is damaged (header CRC mismatch" "$tmp/e.txt" || { bad "damaged header message"; cat "$tmp/e.txt"; }
grep -q "newer format version" "$tmp/e.txt" && bad "a damaged header was called a newer format version"
"$VP" log check "$tmp/dmg.vplog" >"$tmp/c.txt" 2>&1 && bad "log check accepted a damaged header"
grep -q "header is damaged" "$tmp/c.txt" || { bad "log check: damaged header message"; cat "$tmp/c.txt"; }
echo "messages: eps too small (smallest accepted named), rangefinder ranges, --eps with --eps-rel, unknown option once, damaged header"

# ---- counts are counts: a sign, a letter or nothing is refused with exit 2, naming the value
# (strtoul took '-3' as 2^64 - 3 and 'abc' as 0: the whole log replayed, an empty benchmark)
cnt() { # EXPECTED-TEXT COMMAND...
  want=$1; shift
  "$VP" "$@" >/dev/null 2>"$tmp/e.txt"; r=$?
  [ $r -eq 2 ] && grep -q -- "$want" "$tmp/e.txt" || { bad "$* -> exit $r: $(head -1 "$tmp/e.txt")"; }
}
cnt "--upto takes a count of records (at least 1), not '-3'" replay "$tmp/keep.vplog" --out "$tmp/u" --upto -3
cnt "--upto takes a count of records (at least 1), not '0'" mesh "$tmp/keep.vplog" --out "$tmp/u" --upto 0
cnt "--max-rays takes a positive count, not '-1'" report "$tmp/keep.vplog" --out "$tmp/u.html" --max-rays -1
cnt "--list takes a count, not '-1'" certify "$tmp/keep.vplog" --list -1
cnt "--uniform takes a whole number from 1 to 1e8, not 'abc'" bench-delaunay --uniform abc
cnt "--seed takes a whole number, not '-1'" bench-delaunay --uniform 10 --seed -1
cnt "unknown option --bogus" bench-delaunay --bogus
cnt "unknown option --bogus" reconstruct --generate sphere --n 100 --bogus
cnt "--rounds takes a number of rounds" track --surface torus --eps 0.1 --rounds abc
cnt "--dropout 0.7 is out of the range the planner supports" sim --surface torus --eps 0.1 --dropout 0.7 $S --no-log
cnt "a re-scan keeps the options of the session it re-scans" sim --rescan "$tmp/keep.vplog" --surface sphere --seed 3 $S --out "$tmp/rs"
# report --json alone prints the summary; its answers (the planner's count) sum to the probes
"$VP" report "$tmp/keep.vplog" --json >"$tmp/r.json" 2>"$tmp/e.txt" || bad "report --json alone: $(head -1 "$tmp/e.txt")"
jn() { sed -n "s/.*\"$1\":\([0-9]*\).*/\1/p" "$tmp/r.json"; }
pr=$(jn probes); hi=$(jn hits); mi=$(jn misses); tc=$(jn too_close)
[ -n "$pr" ] && [ -n "$hi" ] && [ -n "$mi" ] && [ -n "$tc" ] && [ "$pr" -gt 0 ] && [ $((hi + mi + tc)) -eq "$pr" ] ||
  bad "report --json: probes '$pr' against hits '$hi' + misses '$mi' + too close '$tc'"
# a picture's folder is made, as --out's, before the scan
"$VP" sim --surface sphere --eps 0.3 --out "$tmp/p/s" --png "$tmp/q/r/s.png" $S >/dev/null 2>"$tmp/e.txt" && [ -s "$tmp/q/r/s.png" ] ||
  bad "sim --png into a new folder: $(head -1 "$tmp/e.txt")"
echo "counts: signs, letters and 0 refused (replay, mesh, report, certify, bench-delaunay, track); report --json alone; --png into a new folder"

[ $fail -eq 0 ] && echo "t_io_guard: all passed"
exit $fail
