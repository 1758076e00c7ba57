#!/bin/sh
# make bench: every benchmark against its anchor, measured in the same run.
B=${1:-build}
sh bench/delaunay.sh "$B"
echo
sh bench/planner.sh "$B"
echo
sh bench/machine.sh "$B"
echo
sh bench/accuracy.sh "$B"
echo
sh bench/sizing.sh "$B"
echo
sh bench/rescan.sh "$B"
echo
sh bench/reconstruct.sh "$B"
echo
sh bench/report.sh "$B"
echo
sh bench/live.sh "$B"
