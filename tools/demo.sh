#!/bin/sh
# make demo: a full simulated scan of the genus-2 test object, mesh written to out/demo/.
set -e
B=${1:-build}
mkdir -p out/demo
echo "voroprobe demo: scanning a simulated genus-2 object (probe moves only through space it has proven free)"
"$B/voroprobe" sim --surface genus2 --eps 0.05 --out out/demo/genus2
echo
echo "The mesh is in out/demo/genus2.ply (binary PLY) and out/demo/genus2.off."
echo "Open it in MeshLab, CloudCompare or Open3D; run '$B/voroprobe sim --help' for other objects."
v=$("$B/voroprobe" --version)
echo "This build ($B/voroprobe --version): $(echo "$v" | head -n 1); hardware backends: $(echo "$v" | sed -n 2p)"
