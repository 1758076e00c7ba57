#!/bin/sh
# Installs the Debian 12 packages voroprobe builds, tests and benchmarks with.
# Usage: sh tools/install-deps.sh [build|check|bench]   (default: check)
#   build  what build/voroprobe needs: the compilers, pkg-config (the Makefile asks it for the
#          hardware libraries) and the hardware libraries libgpiod and libcamera; libpng (--png)
#          and libmicrohttpd (--serve)
#   check  build + every tool a test script calls (make check)
#   bench  check + CGAL, re-measured by bench/*.sh (make bench)
# The Makefile calls it before `make`, `make demo` (build), `make check` (check) and `make bench`
# (bench); safe to run by hand. As root it runs apt-get; otherwise it prints the exact command
# to run: for `check` and `bench` that is an error, for `build` a warning (the program then
# builds without what is missing; `voroprobe --version` says which backends it holds).
# Everything else the scripts call is in every Debian (coreutils, grep, sed, mawk, diffutils,
# findutils); tests/*.sh use no bc and no file.
set -u
GROUP=${1:-check}
BUILD_PKGS="build-essential pkg-config libgpiod-dev libcamera-dev libpng-dev libmicrohttpd-dev"
# clang + libclang-rt-14-dev + llvm: t_clang, t_fuzz_smoke (libFuzzer); gcc-arm-none-eabi +
# libnewlib-arm-none-eabi: t_cortex_m4; gcc-aarch64-linux-gnu + libc6-dev-arm64-cross +
# qemu-user: t_aarch64, t_cross_device, t_session_log; libgmp-dev: test_gmp_pred; binutils
# (nm, readelf): t_core_symbols, t_backends, t_cross_device; python3-open3d + python3-numpy:
# t_ply_open3d, t_mesh_open3d, t_session_log; chromium: t_report (headless); libv4l-dev, libinih-dev, libpng-dev: kept for
# port/ (nothing links them at present); libcgal-dev (with libgmp-dev, libmpfr-dev): the exact
# segment/mesh checker of t_safety (tests/cgal_moves.cpp) and bench/cgal_*.cpp.
# qemu-system-arm (with gcc-arm-none-eabi, python3): t_qemu_m4 (the MPS2 AN386 image).
# python3-opencv: t_lens_opencv (the lens distortion model against cv2.projectPoints/undistortPoints).
CHECK_PKGS="$BUILD_PKGS clang libclang-rt-14-dev llvm gcc-arm-none-eabi libnewlib-arm-none-eabi \
gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user libgmp-dev libv4l-dev libinih-dev libpng-dev \
python3 python3-numpy python3-open3d python3-opencv chromium binutils libcgal-dev qemu-system-arm"
BENCH_PKGS="$CHECK_PKGS python3-gudhi"  # python3-gudhi: bench/reconstruct.sh (GUDHI's TangentialComplex)
case $GROUP in
  build) PKGS=$BUILD_PKGS;;
  check) PKGS=$CHECK_PKGS;;
  bench) PKGS=$BENCH_PKGS;;
  *) echo "usage: sh tools/install-deps.sh [build|check|bench]" >&2; exit 2;;
esac
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
if [ "$(id -u)" = 0 ]; then
  echo "install-deps: installing:$missing" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >/dev/null 2>&1 || true
  apt-get install -y -qq --no-install-recommends $missing >/dev/null || {
    echo "install-deps: apt-get install failed for:$missing" >&2; exit 1; }
elif [ "$GROUP" = build ]; then
  echo "install-deps: missing Debian packages (building without them). Run:" >&2
  echo "  sudo apt-get install -y$missing" >&2
else
  echo "install-deps: missing Debian packages. Run:" >&2
  echo "  sudo apt-get install -y$missing" >&2
  exit 1
fi
