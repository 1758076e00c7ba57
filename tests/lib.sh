# What a test script starts with, sourced (`. tests/lib.sh`) from the repository's top: the
# build (BUILD, default build) and its binary (VP), a scratch directory ($tmp) removed on exit,
# and the reporting: `bad MSG` prints a FAIL line and marks the script failed ($fail, which the
# script exits with); `field FILE KEY` reads KEY of the JSON object on FILE's last line (a
# string without its quotes).
set -u
BUILD=${BUILD:-build}
VP=${VP:-$BUILD/voroprobe}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
field() { tail -n 1 "$1" | sed -n "s/.*\"$2\":\([^,}]*\).*/\1/p" | tr -d '"'; }
