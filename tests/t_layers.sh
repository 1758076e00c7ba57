#!/bin/sh
# The layers (doc/architecture.md): every #include "..." in core/, mesh/, sim/, port/, host/,
# cli/ and boards/ goes down the stack, never up or across:
#   cli  -> host sim port mesh core      host -> sim port mesh core
#   sim  -> mesh core                    port -> core       mesh -> core
#   core -> core                         boards -> core
# A header is found by its name in the layer folders (core/planner/ is core); a quoted include
# that names no header of a layer fails too. Then the check is run on a copy with one bad
# include added (a mesh file that includes sim's vp_surface.h): it must fail and name it.
set -u
LAYERS="core mesh sim port host cli"
allowed() {  # allowed FROM TO
  case "$1:$2" in
    core:core) return 0;;
    mesh:core|mesh:mesh) return 0;;
    sim:core|sim:mesh|sim:sim) return 0;;
    port:core|port:port) return 0;;
    host:core|host:mesh|host:sim|host:port|host:host) return 0;;
    cli:*) return 0;;
    boards:core) return 0;;
  esac
  return 1
}
# check ROOT: prints each bad include; exit status 1 if any
check() {
  root=$1
  index=$(cd "$root" && for l in $LAYERS; do
            [ -d "$l" ] && find "$l" -name '*.h' | while read -r h; do echo "$(basename "$h") ${h%%/*}"; done
          done)
  bad=0; n=0
  files=$(cd "$root" && for d in $LAYERS boards; do [ -d "$d" ] && find "$d" -name '*.c' -o -name '*.h' -o -name '*.cpp'; done)
  for f in $files; do
    from=${f%%/*}
    incs=$(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$root/$f")
    for i in $incs; do
      n=$((n+1))
      # a path relative to the including file (core/planner/unity includes ../x.c), else a
      # header found by its name in the layer folders
      to=""
      rel=$(cd "$root/$(dirname "$f")" 2>/dev/null && [ -f "$i" ] && cd "$(dirname "$i")" && pwd -P)
      case "$rel" in "$(cd "$root" && pwd -P)"/*) to=${rel#"$(cd "$root" && pwd -P)"/}; to=${to%%/*};; esac
      [ -n "$to" ] || to=$(echo "$index" | awk -v h="$(basename "$i")" '$1 == h {print $2; exit}')
      if [ -z "$to" ]; then
        echo "$f: #include \"$i\": no layer holds it"; bad=1; continue
      fi
      allowed "$from" "$to" || { echo "$f: #include \"$i\" goes from $from to $to"; bad=1; }
    done
  done
  [ $bad -eq 0 ] && echo "layers ok: $n includes in $(echo "$files" | wc -w) files"
  return $bad
}

check . || exit 1

# the check must catch a bad include
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for l in $LAYERS boards; do [ -d "$l" ] && cp -r "$l" "$tmp/"; done
printf '#include "vp_surface.h"\n' >"$tmp/mesh/vp_layer_bad.c"
out=$(check "$tmp"); rc=$?
if [ $rc -eq 0 ] || ! echo "$out" | grep -q 'mesh/vp_layer_bad.c: #include "vp_surface.h" goes from mesh to sim'; then
  echo "t_layers: a mesh file including sim's vp_surface.h was not caught:"; echo "$out"; exit 1
fi
rm "$tmp/mesh/vp_layer_bad.c"
printf '#include "vp_board.h"\n' >"$tmp/sim/vp_layer_bad.h"
out=$(check "$tmp"); rc=$?
if [ $rc -eq 0 ] || ! echo "$out" | grep -q 'sim/vp_layer_bad.h: #include "vp_board.h" goes from sim to host'; then
  echo "t_layers: a sim header including host's vp_board.h was not caught:"; echo "$out"; exit 1
fi
echo "layers ok; a bad include (mesh -> sim, sim -> host) is caught"
