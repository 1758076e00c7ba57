#!/bin/sh
# The laser's colour channel (port/vp_cam.c, vp_cam_channel) against numpy's own conversion
# (Debian's python3-numpy, always /usr/bin/python3): random YUYV and RGB24 frames from
# test_port_camctl, every pixel of luma, red, green and blue. numpy builds ITU-R BT.601's
# Y'CbCr matrix from Kr = 0.299, Kb = 0.114 with limited-range scaling (Y' 16..235, Cb Cr
# 16..240) and inverts it; ours must agree within 1 grey level (rounding). The check must fail
# the full-range (JPEG) conversion, which a V4L2 YUYV camera does not send by default.
B=${BUILD:-build}
. tests/need_python.sh
need_python numpy python3-numpy
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
"$B/tests/port/test_port_camctl" "$tmp" >"$tmp/log" 2>&1 || { cat "$tmp/log"; echo "FAIL: test_port_camctl"; exit 1; }
"$PY" - "$tmp" <<'PYEOF'
import sys
import numpy as np
d = sys.argv[1]
W, H = 64, 24
def raw(name, shape):
    return np.fromfile(f"{d}/{name}.raw", dtype=np.uint8).reshape(shape).astype(np.float64)
Kr, Kb = 0.299, 0.114
Kg = 1 - Kr - Kb
# R'G'B' (0..1) -> Y' Pb Pr, then limited range 8-bit
M = np.array([[Kr, Kg, Kb],
              [-Kr / (2 * (1 - Kb)), -Kg / (2 * (1 - Kb)), 0.5],
              [0.5, -Kg / (2 * (1 - Kr)), -Kb / (2 * (1 - Kr))]])
def to_rgb(y, cb, cr, full):
    if full:
        ypbpr = np.stack([y / 255, (cb - 128) / 255, (cr - 128) / 255])
    else:
        ypbpr = np.stack([(y - 16) / 219, (cb - 128) / 224, (cr - 128) / 224])
    rgb = np.tensordot(np.linalg.inv(M), ypbpr, axes=1) * 255
    return np.clip(np.rint(rgb), 0, 255)
f = raw("yuyv", (H, W // 2, 4))
y = np.empty((H, W)); y[:, 0::2] = f[:, :, 0]; y[:, 1::2] = f[:, :, 2]
cb = np.repeat(f[:, :, 1], 2, axis=1); cr = np.repeat(f[:, :, 3], 2, axis=1)
ref = {"luma": y}
for full in (False, True):
    rgb = to_rgb(y, cb, cr, full)
    worst = {}
    for i, ch in enumerate(("red", "green", "blue")):
        worst[ch] = np.abs(raw(f"yuyv-{ch}", (H, W)) - rgb[i]).max()
    if not full:
        worst["luma"] = np.abs(raw("yuyv-luma", (H, W)) - y).max()
        ok = max(worst.values()) <= 1
        print("YUYV (limited range, BT.601): worst", {k: int(v) for k, v in worst.items()})
        if not ok: print("FAIL: YUYV channels differ from numpy's"); sys.exit(1)
    else:
        print("the same check against full-range (JPEG) conversion: worst", {k: int(v) for k, v in worst.items()})
        if max(worst.values()) <= 1: print("FAIL: the check cannot tell the ranges apart"); sys.exit(1)
g = raw("rgb24", (H, W, 3))
lum = np.clip(np.rint(g @ np.array([Kr, Kg, Kb])), 0, 255)
w = {"luma": np.abs(raw("rgb24-luma", (H, W)) - lum).max()}
for i, ch in enumerate(("red", "green", "blue")):
    w[ch] = np.abs(raw(f"rgb24-{ch}", (H, W)) - g[:, :, i]).max()
print("RGB24: worst", {k: int(v) for k, v in w.items()})
if max(w.values()) > 1: print("FAIL: RGB24 channels differ"); sys.exit(1)
PYEOF
rc=$?
[ $rc -eq 0 ] || exit 1
echo "t_camcolour: the laser's channel of YUYV and RGB24 frames (4 channels each, 64x24) within 1 grey level of numpy's BT.601 conversion; full range told apart"
