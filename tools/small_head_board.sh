#!/bin/sh
# Writes the rpi4 gantry as body mode's figures were measured on it: a 12 mm head (the head's
# laser, camera, bracket and hub parts off), Omega a ball of 80 mm about (200, 150, 150) with the
# start above it, the object the 100 x 70 x 50 mm ellipsoid at the centre.
#   sh tools/small_head_board.sh OUT.ini [BOARD]    (BOARD: boards/rpi4-gantry.ini)
[ $# -ge 1 ] || { echo "usage: sh tools/small_head_board.sh OUT.ini [BOARD]" >&2; exit 2; }
IN=${2:-boards/rpi4-gantry.ini}
[ -r "$IN" ] || { echo "small_head_board: cannot read $IN" >&2; exit 2; }
sed -e 's/^ball = .*/ball = 200, 150, 150, 80/' -e 's/^start = .*/start = 200, 150, 232/' \
    -e 's/^clearance = .*/clearance = 12/' -e 's/^surface = .*/surface = ellipsoid*50@200,150,150/' \
    -e 's/^\(laser_body\|camera_body\|bracket\|hub\) = .*/\1 = none/' "$IN" >"$1"
