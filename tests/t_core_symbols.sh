#!/bin/sh
# core/ is allocation-free, OS-free and has no mutable globals: its objects may reference only
# a short list of libc/libm symbols and may define no writable data.
set -u
B=${BUILD:-build}
ALLOW="memcpy memset memmove memcmp sqrt fabs floor ceil"
objs=$(ls "$B"/core/*.o "$B"/core/planner/*.o 2>/dev/null)
[ -n "$objs" ] || { echo "no core objects in $B/core"; exit 1; }
bad=0
defined=$(nm $objs | awk '$2 ~ /^[TtRrVW]$/ {print $3}' | sort -u)
for s in $(nm -u $objs | awk 'NF==2 && $1=="U" {print $2}' | sort -u); do
  case " $ALLOW " in *" $s "*) continue;; esac
  echo "$defined" | grep -qx "$s" && continue
  echo "core references a forbidden symbol: $s ($(nm -A -u $objs | grep " $s\$" | cut -d: -f1 | xargs -n1 basename | tr '\n' ' '))"
  bad=1
done
data=$(nm $objs | awk 'NF==3 && $2 ~ /^[DdBbCcGgSs]$/ {print $3}')
if [ -n "$data" ]; then
  echo "core defines mutable data (globals or statics): $data"
  bad=1
fi
# the core sources themselves: no stdio, no heap
if grep -nE '#include <(stdio|stdlib|malloc|unistd|time|pthread)\.h>' core/*.c core/*.h core/planner/*.c core/planner/*.h; then
  echo "core includes an OS header"; bad=1
fi
[ $bad -eq 0 ] && echo "core symbols ok: $(echo $objs | wc -w) objects, references only: $(nm -u $objs | awk 'NF==2{print $2}' | sort -u | grep -vxF "$defined" | tr '\n' ' ')"
exit $bad
