#!/bin/sh
# Installs the Debian 12 packages voroprobe builds and tests with.
# Called by the Makefile before `make check`; safe to run by hand.
# As root it runs apt-get; otherwise it prints the exact command to run.
set -u
PKGS="build-essential clang libclang-rt-14-dev llvm gcc-arm-none-eabi libnewlib-arm-none-eabi \
gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user libgmp-dev libgpiod-dev libv4l-dev libcamera-dev \
libinih-dev libpng-dev python3 python3-numpy python3-open3d binutils"
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
else
  echo "install-deps: missing Debian packages. Run:" >&2
  echo "  sudo apt-get install -y$missing" >&2
  exit 1
fi
