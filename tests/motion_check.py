#!/usr/bin/env python3
"""An independent check of a session against a translating unit sphere (centre v t, radius 1).

Reads `voroprobe log dump LOG --jsonl`, rebuilds the device's clock from the log alone (each
MOVE takes its trapezoid's time at --speed/--accel, each PROBE --probe-time), and for every move
finds the closest approach of the device to the sphere during the move (sampled, then refined
by golden section); every probe's reading is compared with the exact ray-sphere crossing at the
time its exposure ends. The simulator's collision count must lie between the moves that surely
enter the sphere and those that come within --tol of it.
Prints one line; exit 0 when everything agrees, 1 otherwise."""
import argparse
import json
import math
import sys


def move_time(length, speed, accel):
    if speed <= 0 or length <= 0:
        return 0.0
    if accel <= 0:
        return length / speed
    if length >= speed * speed / accel:
        return length / speed + speed / accel
    return 2.0 * math.sqrt(length / accel)


def travelled(length, total, tau, speed, accel):
    """Distance covered tau seconds into a move of `length` taking `total`."""
    if total <= 0 or tau >= total:
        return length
    if accel <= 0:
        return length * tau / total
    ramp = speed / accel if length >= speed * speed / accel else 0.5 * total
    top = accel * ramp
    if tau < ramp:
        return 0.5 * accel * tau * tau
    if tau > total - ramp:
        return length - 0.5 * accel * (total - tau) ** 2
    return 0.5 * accel * ramp * ramp + top * (tau - ramp)


def closest_approach(a, b, t0, vel, speed, accel):
    d = [b[k] - a[k] for k in range(3)]
    length = math.sqrt(sum(x * x for x in d))
    total = move_time(length, speed, accel)
    u = [x / length for x in d] if length > 0 else [0.0, 0.0, 0.0]

    def gap(tau):
        s = travelled(length, total, tau, speed, accel)
        return math.sqrt(sum((a[k] + s * u[k] - vel[k] * (t0 + tau)) ** 2 for k in range(3))) - 1.0

    if total <= 0:
        return gap(0.0), total
    n = 64
    taus = [total * i / n for i in range(n + 1)]
    vals = [gap(x) for x in taus]
    i = min(range(n + 1), key=lambda j: vals[j])
    lo, hi = taus[max(i - 1, 0)], taus[min(i + 1, n)]
    g = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        m1, m2 = hi - g * (hi - lo), lo + g * (hi - lo)
        if gap(m1) < gap(m2):
            hi = m2
        else:
            lo = m1
    return min(vals[i], gap(0.5 * (lo + hi))), total


def ray_sphere(o, d, rng, c):
    w = [o[k] - c[k] for k in range(3)]
    b = sum(w[k] * d[k] for k in range(3))
    q = sum(x * x for x in w) - 1.0
    disc = b * b - q
    if abs(disc) < 1e-7:
        return None  # grazing: not compared
    if disc < 0:
        return -1.0
    h = math.sqrt(disc)
    for t in (-b - h, -b + h):
        if 0 < t <= rng:
            return t
    return -1.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dump")
    ap.add_argument("--vel", required=True, help="VX,VY,VZ")
    ap.add_argument("--speed", type=float, required=True)
    ap.add_argument("--accel", type=float, required=True)
    ap.add_argument("--probe-time", type=float, required=True)
    ap.add_argument("--tol", type=float, required=True)
    ap.add_argument("--collisions", type=int, required=True, help="the simulator's count")
    a = ap.parse_args()
    vel = [float(x) for x in a.vel.split(",")]
    recs = [json.loads(line) for line in open(a.dump)]
    pos = list(recs[0]["header"]["start"])
    t = 0.0
    sure = maybe = moves = probes = bad_probes = 0
    for r in recs[1:]:
        if r.get("type") == "move":
            gap, total = closest_approach(pos, r["target"], t, vel, a.speed, a.accel)
            moves += 1
            sure += gap < -1e-9
            maybe += gap <= a.tol
            t += total
            pos = list(r["target"])
        elif r.get("type") == "probe":
            t += a.probe_time
            probes += 1
            c = [vel[k] * t for k in range(3)]
            want = ray_sphere(r["origin"], r["dir"], r["range"], c)
            if want is None:
                continue
            got = r["raw"] if r.get("hit") else -1.0
            if (want < 0) != (got < 0) or (want >= 0 and abs(want - got) > 1e-9):
                bad_probes += 1
    ok = sure <= a.collisions <= maybe and bad_probes == 0 and moves > 0
    print("motion_check: %d moves, simulator collisions %d, exact %d sure .. %d within %g; %d probes, %d disagree: %s"
          % (moves, a.collisions, sure, maybe, a.tol, probes, bad_probes, "ok" if ok else "MISMATCH"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
