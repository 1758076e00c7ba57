#!/bin/sh
# `sim --track N`: rounds of re-scans of an object that keeps moving (host-sim's --motion clock).
# (1) a bump growing on the unit sphere (bump:1,0,0,0.5,0.001, eps 0.2), 4 rounds: every round
#     DONE, closed, genus 0, 0 collisions with the moving object (host-sim checks each move
#     against the object as it moves), the samples removed per round a small share (the bump's
#     area: 1-15%), most of them moved (the point measured takes the sample's place), the mesh
#     within 0.3 eps of the object at the round's end plus the bump's rise during the round
#     (host-sim's measure against the object at that time; the samples were measured during the
#     round), no two vertices closer than in the first scan;
#     the log verified and replayed to the same mesh (RESCAN events with code 1: the device
#     stays where it stands);
# (2) the object standing still, 2 rounds (`voroprobe track --rounds 2`, the same as
#     `sim --track 2`): each round one probe per sample, none removed, the same mesh;
# (3) the sphere translating (0.15 eps per round), 3 rounds: every sample moved, each round
#     closed and fewer probes than the first scan;
# (4) paper 001's invariants after every round of (1) and (3), checked by
#     tests/track_invariants.py against the object's formula on each round's mesh (OUT.roundK.ply,
#     read by Open3D): sampling, the new vertices' spacing R/3, closed, the nearest-point map
#     one-to-one; and the checker fails a round's mesh moved by 2 eps and one with a vertex pushed
#     inside (skipped when /usr/bin/python3 has no Open3D);
# (5) --track takes 1..1000.
. tests/lib.sh
B=$BUILD
J="$tmp/b.json"
"$VP" sim --surface sphere --eps 0.2 --motion bump:1,0,0,0.5,0.001 --track 4 --out "$tmp/b" --quiet --json >"$J" 2>&1 || bad "bump: exit $?"
python3 - "$J" <<'PY' || fail=1
import json, sys
d = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
r = d["rounds"]
ok = True
def bad(m):
    global ok
    print("FAIL: bump: " + m); ok = False
if len(r) != 5: bad("%d rounds" % len(r))
sp0 = r[0]["min_spacing"]
for k, x in enumerate(r):
    if x["status"] != "ok" or not x["closed"] or x["genus"] != 0 or x["collisions"] != 0:
        bad("round %d: %s" % (k, x))
    if x["hausdorff"] < 0 or x["hausdorff"] > 0.3 * 0.2 + 0.001 * (x["t1"] - x["t0"]):
        bad("round %d: Hausdorff %g at its end" % (k, x["hausdorff"]))
    if x["min_spacing"] < 0.99 * sp0:
        bad("round %d: vertices %g apart (first scan %g)" % (k, x["min_spacing"], sp0))
    if k > 0:
        share = x["dropped"] / float(x["kept"] + x["dropped"])
        if not (0.01 <= share <= 0.15): bad("round %d: %.1f%% of the samples removed" % (k, 100 * share))
        if x["moved"] < x["dropped"] // 2: bad("round %d: %d of %d removed samples moved" % (k, x["moved"], x["dropped"]))
    print("round %d: t %.1f..%.1f s, %d probes, kept %d, removed %d (moved %d), %d vertices, closed, genus %d, 0 collisions, "
          "Hausdorff %.4f" % (k, x["t0"], x["t1"], x["probes"], x["kept"], x["dropped"], x["moved"], x["vertices"], x["genus"],
                              x["hausdorff"]))
sys.exit(0 if ok else 1)
PY
"$VP" log verify "$tmp/b.vplog" >"$tmp/v.txt" 2>&1 || bad "bump: log verify: $(tail -n 1 "$tmp/v.txt")"
grep -q "4 re-scan(s)" "$tmp/v.txt" || bad "bump: log verify saw $(tail -n 1 "$tmp/v.txt")"
"$VP" replay "$tmp/b.vplog" --out "$tmp/r" >"$tmp/r.txt" 2>&1 || bad "bump: replay: $(tail -n 2 "$tmp/r.txt")"
cmp -s "$tmp/r.ply" "$tmp/b.ply" || bad "bump: the replayed mesh differs"

J="$tmp/t.json"
"$VP" sim --surface sphere --eps 0.2 --motion translate:0.0005,0,0 --track 3 --out "$tmp/t" --no-log --quiet --json >"$J" 2>&1 || bad "translate: exit $?"
python3 - "$J" <<'PY' || fail=1
import json, sys
r = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])["rounds"]
ok = len(r) == 4
for k, x in enumerate(r[1:], 1):
    if (x["status"] != "ok" or not x["closed"] or x["genus"] != 0 or x["collisions"] != 0 or x["kept"] != 0
            or x["moved"] < 0.95 * x["dropped"] or x["probes"] >= r[0]["probes"]):
        ok = False
        print("FAIL: translate: round %d: %s" % (k, x))
    print("translate, round %d: %d probes (the first scan %d), %d of %d samples moved, %d vertices, closed"
          % (k, x["probes"], r[0]["probes"], x["moved"], x["dropped"], x["vertices"]))
sys.exit(0 if ok else 1)
PY
if /usr/bin/python3 -c "import open3d, numpy" 2>/dev/null; then
    /usr/bin/python3 tests/track_invariants.py "$tmp/b" "$tmp/b.json" 0.2 bump:1,0,0,0.5,0.001 selftest || bad "bump: paper 001's invariants"
    /usr/bin/python3 tests/track_invariants.py "$tmp/t" "$tmp/t.json" 0.2 translate:0.0005,0,0 || bad "translate: paper 001's invariants"
else
    echo "note: /usr/bin/python3 has no Open3D: paper 001's invariants not checked"
fi

J="$tmp/s.json"
"$VP" track --surface torus --eps-rel 0.04 --rounds 2 --out "$tmp/s" --quiet --json >"$J" 2>&1 || bad "still: exit $?"
python3 - "$J" <<'PY' || fail=1
import json, sys
d = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
r = d["rounds"]
ok = len(r) == 3
for k, x in enumerate(r[1:], 1):
    if x["dropped"] != 0 or x["vertices"] != r[0]["vertices"] or not x["closed"] or x["genus"] != 1 or x["collisions"] != 0:
        ok = False
        print("FAIL: still: round %d: %s" % (k, x))
    print("still, round %d: %d probes for %d samples (the first scan %d), none removed" % (k, x["probes"], x["kept"], r[0]["probes"]))
sys.exit(0 if ok else 1)
PY
"$VP" sim --surface sphere --eps 0.2 --track 0 --no-log --quiet >"$tmp/o.txt" 2>&1
[ $? -eq 2 ] && grep -q "1..1000" "$tmp/o.txt" || bad "--track 0: $(cat "$tmp/o.txt")"
[ $fail -eq 0 ] && echo "track: every round closed with the object's genus, 0 collisions, the changes where the object moved"
exit $fail
