#!/bin/sh
# A part reaching out of Omega, in 26 places: the board's dry run (`scan --dry-run --reach-out`)
# on a ball of RB mm at Omega's centre and a knob of R mm centred D mm from it (default: 24, 6 and
# 80 on rpi4-gantry.ini, whose Omega is a ball of 83 mm: the knob 3 mm out of it), towards each
# axis and each diagonal of the cube's faces and of the cube. For each: the exit status (1: the
# switch stopped the head, 5: the head's body met the knob), the moves of the laser origin
# through the object, how far past the touch the head went, the head parts counted.
#   sh tools/reach_out_sweep.sh [BUILD] [BOARD] [EPS]
# rpi4-gantry.ini has contact_by = mount: the switch senses every part. A copy with
# contact_by = stylus shows what a stylus at the laser origin guards.
BUILD=${1:-build}
BOARD=${2:-boards/rpi4-gantry.ini}
EPS=${3:-16}
R=${R:-6}; D=${D:-80}; RB=${RB:-24}
VP="$BUILD/voroprobe"
OUT="$BUILD/reach_out_sweep"
mkdir -p "$OUT"
c=$(sed -n 's/^ball *= *\([^#]*\).*/\1/p' "$BOARD" | tr -d ' ')
cx=$(echo "$c" | cut -d, -f1); cy=$(echo "$c" | cut -d, -f2); cz=$(echo "$c" | cut -d, -f3)
[ -n "$cz" ] || { echo "reach_out_sweep: $BOARD has no [omega] ball" >&2; exit 2; }
n=0; stopped=0; crashed=0; refused=0; other=0
for d in "1 0 0" "-1 0 0" "0 1 0" "0 -1 0" "0 0 1" "0 0 -1" "1 1 0" "1 -1 0" "-1 1 0" "-1 -1 0" "1 0 1" "1 0 -1" \
         "-1 0 1" "-1 0 -1" "0 1 1" "0 1 -1" "0 -1 1" "0 -1 -1" "1 1 1" "1 1 -1" "1 -1 1" "1 -1 -1" "-1 1 1" "-1 1 -1" \
         "-1 -1 1" "-1 -1 -1"; do
  set -- $d
  k=$(awk -v x="$1" -v y="$2" -v z="$3" -v D="$D" -v cx="$cx" -v cy="$cy" -v cz="$cz" \
    'BEGIN { n = sqrt(x*x + y*y + z*z); printf "%.3f,%.3f,%.3f", cx + D*x/n, cy + D*y/n, cz + D*z/n }')
  name=$(echo "$d" | tr ' ' '_')
  "$VP" scan --board "$BOARD" --dry-run --reach-out --eps "$EPS" --surface "sphere*$RB@$cx,$cy,$cz+sphere*$R@$k" \
    --log "$OUT/$name.vplog" --quiet --json >"$OUT/$name.out" 2>"$OUT/$name.err"
  rc=$?
  n=$((n + 1))
  j=$(tail -n 1 "$OUT/$name.out")
  f() { echo "$j" | sed -n "s/.*\"$1\":\([^,}]*\).*/\1/p"; }
  case $rc in
    1) if grep -q "holds the laser origin's start" "$OUT/$name.err"; then refused=$((refused + 1)); what="refused (holds the start)"
       else stopped=$((stopped + 1)); what="stopped by the switch"; fi;;
    5) crashed=$((crashed + 1)); what="the head's body met the knob";;
    *) other=$((other + 1)); what="exit $rc";;
  esac
  printf '%-9s knob at %-24s %-30s contacts %s, %s mm past the touch, origin moves through %s; parts: %s\n' "$name" "$k" \
    "$what" "$(f contacts)" "$(f touch_depth_max)" "$(f through)" "$(echo "$j" | sed -n 's/.*"head_parts":{\([^}]*\)}.*/\1/p')"
done
echo "reach-out sweep ($BOARD, eps $EPS, knob $R mm at $D mm): $n places: $stopped stopped by the switch, $crashed met by the head's body first, $refused refused, $other other"
