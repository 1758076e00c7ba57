#!/bin/sh
# Progress that suits where it goes (host/vp_progress): sim's progress
#   in a pipe or file: plain lines, each ended by a newline, no carriage return or escape, one
#       per period (VP_PROGRESS_SECONDS) and one at the end: never one per command;
#   on a terminal (a pseudo-terminal made by script(1)): one line redrawn in place ("\r", erase
#       to the end of the line) with a bar "[###...] NN%", ended by a newline when the run ends.
# The pipe checker must reject the output the scanner printed before (lines joined by "\r").
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
CR=$(printf '\r')
ESC=$(printf '\033')

# plain lines: no CR or ESC, the file ends with a newline, N progress lines, each a full record
pipe_ok() { # FILE MIN MAX
  grep -q "[$CR$ESC]" "$1" && { echo "a carriage return or escape in the pipe's output"; return 1; }
  [ -z "$(tail -c 1 "$1")" ] || { echo "the output does not end with a newline"; return 1; }
  n=$(grep -c '^  progress: probes [0-9]* *vertices [0-9]* *facets [0-9]* ' "$1")
  [ "$n" -ge "$2" ] && [ "$n" -le "$3" ] || { echo "$n progress lines, not $2..$3"; return 1; }
  echo "$n progress lines"
}

# a short run with the default period (10 s): one line, the last
"$VP" sim --surface torus --eps 0.1 --no-log --out "$T/a" --hausdorff 0 >/dev/null 2>"$T/a.err" || fail "sim exited $?"
res=$(pipe_ok "$T/a.err" 1 1) || fail "default period: $res"
# a longer one every 0.1 s: several lines, bounded by the run's length
t0=$(date +%s%N)
VP_PROGRESS_SECONDS=0.1 "$VP" sim --surface genus2 --eps 0.03 --no-log --out "$T/b" --hausdorff 0 >/dev/null 2>"$T/b.err" \
  || fail "sim exited $?"
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
res=$(pipe_ok "$T/b.err" 2 $((ms / 100 + 2))) || fail "0.1 s period over $ms ms: $res"
pipe_lines=$res
last=$(grep '^  progress:' "$T/b.err" | tail -n 1)
case $last in *"bad balls 0 "*) ;; *) fail "the last progress line is not the end of the run: $last";; esac

# the checker rejects the old carriage-return line that piled up in a pipe
printf '\r  probes 100 vertices 20 facets 30\r  probes 200 vertices 40 facets 70\r  probes 300 vertices 60 facets 116\n' >"$T/old.err"
res=$(pipe_ok "$T/old.err" 1 100) && fail "the pipe check passed carriage-return output: $res"

# a terminal: script(1) gives sim a pseudo-terminal
command -v script >/dev/null 2>&1 || { echo "no script(1): the terminal half is skipped"; exit 77; }
# (a chroot without /dev/pts has no pseudo-terminal to give: then only the pipe half ran)
script -qec true "$T/probe.txt" >/dev/null 2>&1 ||
  { echo "t_progress: pipe: $pipe_lines, no CR; the terminal half skipped: script(1) cannot open a pseudo-terminal here"; exit 77; }
script -qec "$VP sim --surface genus2 --eps 0.03 --no-log --out $T/c --hausdorff 0" "$T/tty.txt" >/dev/null 2>&1 \
  || fail "sim under script exited $?"
grep -q "$CR$ESC\[K\[[#.]*\] *[0-9]*% closed probes" "$T/tty.txt" || fail "no bar redrawn in place on the terminal"
bars=$(tr "$CR" '\n' <"$T/tty.txt" | grep -c '\] *[0-9]*% closed probes')
tr "$CR" '\n' <"$T/tty.txt" | grep -q '\[########################\] 100% closed probes' || fail "the last bar is not full"
grep -q '^mesh: ' "$T/tty.txt" || fail "the summary after the bar is missing"
echo "t_progress: pipe: $pipe_lines over $ms ms at 0.1 s (1 at the default period), no CR; terminal: $bars bar redraws in place, ended by a newline; the old CR output rejected"
