#!/bin/sh
# Moves weighed by machine time (body mode on a board: the axes' top speeds and the pan's travel
# go to the planner). On the rpi4 gantry with the geometry the body-mode issue was measured on
# (a 12 mm head, Omega a ball of 80 mm, the 100 x 70 x 50 mm ellipsoid; the head's parts off)
# at eps 16 and 8:
#   - closed, 0 moves through the object, 0 head collisions, the log proven free (`log verify`);
#   - the log's header is version 6 and names the axes' times (`log dump`), `--json` counts the
#     ways round Omega taken level;
#   - read back from the log by Python (its own geometry): every MOVE stays outside the ball
#     Omega, and each way between two probes takes no longer at the axes' top speeds than the
#     great circle round Omega between its ends (at 1.01 R, the planner's fallback); some ways
#     are much quicker (the level ones); probes start on that route sphere (all but the seed's
#     and 2%). The checker must fail on a straight chord through the ball and on a way over the
#     top where the level way was quicker (cases of its own), and on the starts of --by-length;
#   - ordered by length instead (--by-length): no axis times in the log, and more machine time;
#   - cut after 400 commands and resumed: the same commands as the run in one go; a log without
#     the axes' times (as an older build wrote it) resumed goes on by length, as it began.
. tests/lib.sh
B=$BUILD
. tests/need_python.sh
need_python numpy python3-numpy
sh tools/small_head_board.sh "$tmp/old.ini" || exit 1

cat >"$tmp/ways.py" <<'EOF'
# reads `log dump` on stdin: the ways between probes, checked against Omega (a ball) and timed
import sys, math, re
C = (200.0, 150.0, 150.0); R = 80.0
W = [1 / 150.0, 1 / 120.0, 1 / 15.0]          # s per mm at top speed: the board's x, y, z
def top_time(a, b):
    return max(abs(b[k] - a[k]) * W[k] for k in range(3))
def seg_min_dist(a, b):
    d = [b[k] - a[k] for k in range(3)]; ac = [C[k] - a[k] for k in range(3)]
    dd = sum(x * x for x in d)
    t = 0.0 if dd == 0 else max(0.0, min(1.0, sum(d[k] * ac[k] for k in range(3)) / dd))
    p = [a[k] + t * d[k] for k in range(3)]
    return math.dist(p, C)
def great_circle(a, b, n=256):
    # the way at 1.01 R along the great circle from a to b, out and in radially
    rs = 1.01 * R
    ua = [a[k] - C[k] for k in range(3)]; ub = [b[k] - C[k] for k in range(3)]
    la = math.sqrt(sum(x * x for x in ua)); lb = math.sqrt(sum(x * x for x in ub))
    ua = [x / la for x in ua]; ub = [x / lb for x in ub]
    om = math.acos(max(-1.0, min(1.0, sum(ua[k] * ub[k] for k in range(3)))))
    pts = [a]
    for i in range(n + 1):
        s = i / n
        if om < 1e-9: u = ua
        else: u = [(math.sin((1 - s) * om) * ua[k] + math.sin(s * om) * ub[k]) / math.sin(om) for k in range(3)]
        r = max(rs, la + s * (lb - la))
        pts.append(tuple(C[k] + r * u[k] for k in range(3)))
    pts.append(b)
    return sum(top_time(pts[i], pts[i + 1]) for i in range(len(pts) - 1))
def check(ways):
    inside = slower = quicker = 0
    for w in ways:
        for i in range(len(w) - 1):
            if seg_min_dist(w[i], w[i + 1]) < R - 1e-6: inside += 1
        if len(w) < 3: continue
        t = sum(top_time(w[i], w[i + 1]) for i in range(len(w) - 1))
        g = great_circle(w[0], w[-1])
        if t > g * 1.02 + 1e-6: slower += 1
        if t < 0.7 * g: quicker += 1
    return inside, slower, quicker
if sys.argv[1] == 'self':
    # the checker's own cases: a chord through the ball; a way over the top between two points
    # at one height, where the level way is much quicker than ... itself (the great circle)
    a = (C[0] + 64, C[1], C[2] + 48); b = (C[0] - 64, C[1], C[2] + 48)
    top = [a] + [(C[0] + 80.8 * math.cos(t), C[1], C[2] + 80.8 * math.sin(t)) for t in
                 [math.atan2(48, 64) + i * (math.pi - 2 * math.atan2(48, 64)) / 32 for i in range(33)]] + [b]
    level = [a] + [(C[0] + 64.6 * math.cos(t), C[1] + 64.6 * math.sin(t), C[2] + 48.5) for t in
                   [i * math.pi / 32 for i in range(33)]] + [b]
    i1, s1, q1 = check([[a, b]])
    i2, s2, q2 = check([top])
    i3, s3, q3 = check([level])
    print(i1, s1, q1, i2, s2, q2, i3, s3, q3)
    sys.exit(0 if (i1 == 1 and i2 == 0 and q2 == 0 and i3 == 0 and s3 == 0 and q3 == 1) else 1)
ways = []; cur = None
every = [(200.0, 150.0, 232.0)]                 # the board's start, then every place in turn
probes = below = 0                              # probes; those starting inside the route sphere
for line in sys.stdin:
    m = re.search(r'MOVE to (\S+) (\S+) (\S+)', line)
    if m:
        p = tuple(map(float, m.groups()))
        every.append(p)
        if cur is not None: cur.append(p)
        continue
    m = re.search(r'PROBE from (\S+) (\S+) (\S+)', line)
    if m:
        p = tuple(map(float, m.groups()))
        every.append(p)
        probes += 1
        if math.dist(p, C) < 1.01 * R * (1 - 1e-7): below += 1
        if cur is not None and len(cur) > 1: ways.append(cur)
        cur = [p]
inside, slower, quicker = check(ways)
# every move, the ones before the first probe and after the last too
inside += sum(seg_min_dist(every[i], every[i + 1]) < R - 1e-6 for i in range(len(every) - 1))
print(len(ways), inside, slower, quicker, below, probes)
EOF
"$PY" "$tmp/ways.py" self >"$tmp/self.txt" || bad "the ways' checker passes a chord through Omega or misjudges its own cases: $(cat "$tmp/self.txt")"

out=""
for e in 16 8; do
  o="$tmp/e$e"
  "$VP" scan --board "$tmp/old.ini" --dry-run --eps $e --log "$o.vplog" --json --quiet >"$o.txt" 2>"$o.err"
  rc=$?
  [ $rc -eq 0 ] && [ "$(field "$o.txt" closed)" = true ] || bad "eps $e: exit $rc, not closed ($(tail -n 1 "$o.txt" | cut -c1-160))"
  [ "$(field "$o.txt" through)" = 0 ] && [ "$(field "$o.txt" head_collisions)" = 0 ] || bad "eps $e: moves through or head collisions"
  lv=$(field "$o.txt" level_routes); ro=$(field "$o.txt" routes)
  [ "${lv:-0}" -gt 0 ] 2>/dev/null || bad "eps $e: no way round Omega taken level (level_routes '${lv}')"
  "$VP" log verify "$o.vplog" >"$o.verify" 2>&1 || bad "eps $e: log verify: $(tail -n 1 "$o.verify")"
  "$VP" log dump "$o.vplog" >"$o.dump" 2>&1 || bad "eps $e: log dump failed"
  head -n 1 "$o.dump" | grep -q "format version 6" || bad "eps $e: the log's header is not version 6: $(head -n 1 "$o.dump")"
  grep -q "^# moves weighed by machine time: s per unit x 0.0066666666666666671 y 0.0083333333333333332 z 0.066666666666666666" "$o.dump" ||
    bad "eps $e: log dump does not name the axes' times"
  set -- $("$PY" "$tmp/ways.py" run <"$o.dump")
  [ $# -eq 6 ] && [ "$2" = 0 ] && [ "$3" = 0 ] && [ "$4" -gt 5 ] ||
    bad "eps $e: ways read back: $* (ways, pieces inside Omega, slower than the great circle, much quicker)"
  # probes start on the route sphere, where the ways round Omega run (no step out and back in at
  # each end): all but the seed's 4 from the board's start and 2% more (edges that begin nearer
  # dOmega than that sphere: their start stays on the edge)
  [ $# -eq 6 ] && [ "$5" -le $(( 4 + $6 / 50 )) ] ||
    bad "eps $e: ${5:-?} of ${6:-?} probes start inside the route sphere (1.01 R)"
  out="$out eps $e: $(field "$o.txt" vertices) vertices, $(field "$o.txt" machine_s) s of machine time, $lv of $ro ways level, ${4:-?} of ${1:-?} ways under 0.7 of the great circle's time, 0 slower, ${5:-?} of ${6:-?} probes inside the route sphere;"
done
# ordered by length (--by-length, as before the axes' speeds were given): the log carries no
# axis times, --json no level ways, and the machine takes longer (the simulated clock) at both eps
for e in 16 8; do
  o="$tmp/l$e"
  "$VP" scan --board "$tmp/old.ini" --dry-run --eps $e --by-length --log "$o.vplog" --json --quiet >"$o.txt" 2>"$o.err"
  rc=$?
  [ $rc -eq 0 ] && [ "$(field "$o.txt" closed)" = true ] || bad "--by-length eps $e: exit $rc"
  [ -z "$(field "$o.txt" level_routes)" ] || bad "--by-length eps $e: level ways counted"
  "$VP" log dump "$o.vplog" | head -n 1 | grep -q "format version 6" && bad "--by-length eps $e: a version 6 header"
  awk -v t="$(field "$tmp/e$e.txt" machine_s)" -v l="$(field "$o.txt" machine_s)" 'BEGIN { exit !(t > 0 && t < l) }' ||
    bad "eps $e: weighed by machine time $(field "$tmp/e$e.txt" machine_s) s, by length $(field "$o.txt" machine_s) s"
  # the checker of the starts must see these (each on dOmega, inside the route sphere)
  "$VP" log dump "$o.vplog" >"$o.dump" 2>&1
  set -- $("$PY" "$tmp/ways.py" run <"$o.dump")
  [ $# -eq 6 ] && [ "$5" -eq "$6" ] && [ "$6" -gt 0 ] ||
    bad "--by-length eps $e: the starts' checker does not see the probes on dOmega (${5:-?} of ${6:-?})"
  out="$out by length at eps $e: $(field "$o.txt" machine_s) s;"
done
# cut and resumed: the same commands
"$VP" scan --board "$tmp/old.ini" --dry-run --eps 16 --log "$tmp/cut.vplog" --stop-after 400 --quiet >/dev/null 2>&1
"$VP" scan --board "$tmp/old.ini" --dry-run --eps 16 --log "$tmp/cut.vplog" --resume --quiet >"$tmp/cut.txt" 2>&1 ||
  bad "resume: $(tail -n 2 "$tmp/cut.txt")"
"$VP" log dump "$tmp/cut.vplog" | grep -v EVENT | cut -d' ' -f3- >"$tmp/cut.cmds"
grep -v EVENT "$tmp/e16.dump" | cut -d' ' -f3- >"$tmp/whole.cmds"
cmp -s "$tmp/cut.cmds" "$tmp/whole.cmds" || bad "cut after 400 commands and resumed: not the commands of the run in one go"
# a log without the axes' times, as an older build wrote them (a --by-length log whose note no
# longer says so: the header's note and CRC rewritten here), goes on as it began when resumed:
# the commands of --by-length in one go
"$VP" scan --board "$tmp/old.ini" --dry-run --eps 16 --by-length --log "$tmp/lcut.vplog" --stop-after 400 --quiet >/dev/null 2>&1
"$PY" - "$tmp/lcut.vplog" <<'EOF' || bad "could not rewrite the cut log's header"
import sys, struct, zlib
p = sys.argv[1]; b = bytearray(open(p, 'rb').read())
n = struct.unpack_from('<I', b, 12)[0]
i = b.find(b'--by-length ', 0, n)
if i < 0: sys.exit(1)
b[i:i + 12] = b' ' * 12
struct.pack_into('<I', b, n - 4, zlib.crc32(bytes(b[:n - 4])) & 0xffffffff)
open(p, 'wb').write(b)
EOF
"$VP" log dump "$tmp/lcut.vplog" | head -n 2 | grep -q -- "--by-length" && bad "the rewritten note still says --by-length"
"$VP" scan --board "$tmp/old.ini" --dry-run --eps 16 --log "$tmp/lcut.vplog" --resume --quiet >"$tmp/lcut.txt" 2>&1 ||
  bad "resume of a log without axis times: $(tail -n 2 "$tmp/lcut.txt")"
"$VP" log dump "$tmp/lcut.vplog" | grep -v 'EVENT\|^#' | cut -d' ' -f3- >"$tmp/lcut.cmds"
"$VP" log dump "$tmp/l16.vplog" | grep -v 'EVENT\|^#' | cut -d' ' -f3- >"$tmp/lwhole.cmds"
cmp -s "$tmp/lcut.cmds" "$tmp/lwhole.cmds" || bad "a log without axis times, cut and resumed: not the commands of --by-length in one go"
[ $fail = 0 ] || exit 1
echo "t_timed: rpi4 old geometry, moves weighed by machine time:$out cut and resumed: the same commands"
