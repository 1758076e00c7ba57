#!/bin/sh
# Every hardware backend whose Debian -dev package is installed here is built into $VP:
# libgpiod (GPIO step/dir) when `pkg-config --exists libgpiod`, libcamera when
# `pkg-config --exists libcamera`. Checked twice, independently: what `voroprobe --version`
# says (asked of the libraries at run time), and what the ELF file links (readelf -d NEEDED
# entries and the library's symbols among nm -D's undefined ones). A backend whose package is
# not installed is not required. The two views must also agree with each other.
# This test does fail when a backend is left out: against a build with both forced off,
#   make BUILD=build/nohw HAVE_GPIOD= HAVE_LIBCAMERA= build/nohw/voroprobe
#   VP=build/nohw/voroprobe sh tests/t_backends.sh
# it prints "FAIL: libgpiod-dev is installed but build/nohw/voroprobe is built without it ..."
# (and that it links neither library nor uses its symbols, and the same for libcamera) and
# exits 1; with HAVE_LIBCAMERA= alone, only the three libcamera lines fail.
. tests/lib.sh
B=$BUILD
for t in readelf nm; do
  command -v $t >/dev/null || { echo "$t missing (binutils: make deps)"; exit 1; }
done
[ -x "$VP" ] || { echo "no program $VP"; exit 1; }
ver=$("$VP" --version) || { echo "FAIL: $VP --version: exit $?"; exit 1; }
echo "$ver"
echo "$ver" | head -n 1 | grep -q "^voroprobe [0-9][0-9.]*$" || bad "--version: first line is not 'voroprobe VERSION'"
line=$(echo "$ver" | grep "^GPIO: libgpiod ")
[ -n "$line" ] || { bad "--version does not say which backends are built in"; exit 1; }
"$VP" scan --help | grep -qF "Hardware backends built in: $line." || bad "scan --help does not name the backends"
needed=$(readelf -d "$VP" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' ')
undef=$(nm -D -C --undefined-only "$VP" 2>/dev/null)
pc=$(command -v pkg-config || true)

# $1 -dev package, $2 pkg-config module, $3 what --version says ("libgpiod yes"), $4 NEEDED
# library prefix, $5 an undefined dynamic symbol of that library (grep pattern)
check() {
  if [ -n "$pc" ]; then pkg-config --exists "$2" && inst=1 || inst=0
  else
    # without pkg-config the Makefile cannot see the library: an installed -dev package is then
    # left out, which is a failure of the set-up (make deps installs pkg-config)
    inst=0
    if dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; then
      bad "$1 is installed but pkg-config is not: the Makefile cannot find $2 (make deps)"
    fi
  fi
  says=0; echo "$line" | grep -q "$3 yes" && says=1
  links=0; case " $needed" in *" $4"*) links=1;; esac
  syms=0; echo "$undef" | grep -q "$5" && syms=1
  if [ $inst -eq 1 ]; then
    [ $says -eq 1 ] || bad "$1 is installed but $VP is built without it: --version says '$line'"
    [ $links -eq 1 ] || bad "$1 is installed but $VP does not link $4* (NEEDED: $needed)"
    [ $syms -eq 1 ] || bad "$1 is installed but $VP uses no symbol of $2 (nm -D)"
    [ $says$links$syms = 111 ] &&
      echo "$2 $(pkg-config --modversion "$2") installed: built in, linked ($(echo $needed | tr ' ' '\n' | grep "^$4" | paste -sd' ' -)), symbols used"
  else
    echo "$2: not installed here (not required)"
  fi
  # the program's own word and its ELF file agree, installed or not
  [ $says -eq $links ] && [ $links -eq $syms ] ||
    bad "$2: --version says $([ $says -eq 1 ] && echo yes || echo no), NEEDED $([ $links -eq 1 ] && echo yes || echo no), symbols $([ $syms -eq 1 ] && echo yes || echo no)"
}
check libgpiod-dev libgpiod "libgpiod" "libgpiod.so" "gpiod_chip_open"
check libcamera-dev libcamera "libcamera" "libcamera.so" "libcamera::CameraManager::"
echo "$line" | grep -q "V4L2 yes" || bad "V4L2 not built in"
[ $fail -eq 0 ] && echo "backends: $line"
exit $fail
