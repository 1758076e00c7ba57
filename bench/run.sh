#!/bin/sh
# make bench: every benchmark against its anchor, measured in the same run.
B=${1:-build}
sh bench/delaunay.sh "$B"
echo
sh bench/planner.sh "$B"
echo
sh bench/accuracy.sh "$B"
echo
sh bench/sizing.sh "$B"
