#!/bin/sh
# The lens model of port/vp_calib (Brown-Conrady k1 k2 p1 p2) against OpenCV: python3-opencv
# projects points (cv2.projectPoints) and undistorts pixels (cv2.undistortPointsIter) for random
# cameras; test_port_calib --opencv reads them and compares (and must see p1/p2 swapped differ).
# Debian's python3-opencv: always /usr/bin/python3, not a python3 found on PATH.
BUILD=${BUILD:-build}
PY=/usr/bin/python3
BIN=$BUILD/tests/port/test_port_calib
[ -x "$BIN" ] || { echo "t_lens_opencv: $BIN not built"; exit 1; }
$PY -c 'import cv2, numpy' 2>/dev/null || { echo "t_lens_opencv: skipped: $PY cannot import cv2 (apt-get install python3-opencv)"; exit 77; }
TMP=$(mktemp -d) || exit 1
trap 'rm -rf "$TMP"' EXIT
$PY - "$TMP/cases.txt" <<'PY' || { echo "t_lens_opencv: FAIL: the reference values could not be made"; exit 1; }
import sys
import numpy as np
import cv2
rng = np.random.default_rng(12)
out = open(sys.argv[1], "w")
def fmt(v):
    return " ".join("%.17g" % x for x in v)
for i in range(200):
    fx, fy = rng.uniform(300, 900, 2)
    cx, cy = rng.uniform(280, 360), rng.uniform(200, 280)
    dist = np.array([rng.uniform(-0.3, 0.15), rng.uniform(-0.05, 0.05), rng.uniform(-0.003, 0.003), rng.uniform(-0.003, 0.003)])
    K = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1.0]])
    rvec = rng.uniform(-0.5, 0.5, 3)
    tvec = rng.uniform(-20, 20, 3)
    R = cv2.Rodrigues(rvec)[0]
    # a point in front of the camera, within about 40 degrees of its axis
    xc = np.array([rng.uniform(-0.7, 0.7), rng.uniform(-0.55, 0.55), 1.0]) * rng.uniform(20, 400)
    X = R.T @ (xc - tvec)
    uv = cv2.projectPoints(X.reshape(1, 1, 3), rvec, tvec, K, dist)[0].reshape(2)
    out.write("P %s %s %s %s %s %s\n" % (fmt([fx, fy, cx, cy]), fmt(dist), fmt(R.reshape(9)), fmt(tvec), fmt(X), fmt(uv)))
    # a pixel (the image of a point within the same field of view) back to the normalised point
    xn = np.array([rng.uniform(-0.7, 0.7), rng.uniform(-0.55, 0.55), 1.0])
    px = cv2.projectPoints(xn.reshape(1, 1, 3), np.zeros(3), np.zeros(3), K, dist)[0].reshape(1, 1, 2)
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 500, 1e-16)
    xy = cv2.undistortPointsIter(px, K, dist, None, None, crit).reshape(2)
    out.write("U %s %s %s %s\n" % (fmt([fx, fy, cx, cy]), fmt(dist), fmt(px.reshape(2)), fmt(xy)))
out.close()
PY
OUT=$("$BIN" --opencv "$TMP/cases.txt" 2>&1)
RC=$?
echo "$OUT" | grep "CHECK failed" | head -20 >&2
LINE=$(echo "$OUT" | grep '^opencv:' | head -1)
if [ $RC -eq 0 ]; then echo "t_lens_opencv: ok: ${LINE#opencv: }"; exit 0; fi
echo "t_lens_opencv: FAIL: $(echo "$OUT" | tail -1)"
exit 1
