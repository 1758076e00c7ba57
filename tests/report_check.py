#!/usr/bin/env python3
"""Checks a report page as chromium drew it, independently of the page's own code.

  report_check.py pixels SHOT.png MESH.ply PROBE_LINE
      SHOT.png is chromium's screenshot; MESH.ply the mesh sim wrote (read here, not from the
      page). The mesh is projected with the viewer's documented camera (yaw 0.6, pitch 0.45,
      z up, 40 degree field of view, distance = half the bounding-box diagonal / sin(20 deg)
      x 1.05, looking at the box centre) and rasterised here. Passes when the screenshot is
      not background on >= 98% of the pixels well inside the projection and is background on
      >= 99% of the canvas pixels well outside it.
  report_check.py png PICTURE.png MESH.ply
      voroprobe's --png picture: each of its four 480 x 360 views (host/vp_render.h) checked
      the same way against the mesh projected with that view's yaw and pitch.
  report_check.py numbers DOM.html SUMMARY.json
      The summary cells of the page (id s-vertices, s-facets, s-probes, s-hits, s-genus,
      s-status) must equal the JSON summary of the same session (sim --json).
  report_check.py pick MESH.ply W H
      Where to click on a W x H view to hit a facet, and which: 'X Y FACET' (ray cast here).
  report_check.py live DOM.html SUMMARY.json
      The live page (sim --serve) after the scan: its final state and counts equal sim --json,
      every sample sent was received, and it updated at least twice while the scan ran.
Exit 0 pass, 1 fail (the reason printed)."""
import json
import math
import re
import struct
import sys
import zlib

import numpy as np

BG = (238, 241, 245)


def read_png(path, rows=None):
    d = open(path, 'rb').read()
    assert d[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
    pos, idat = 8, b''
    while pos < len(d):
        n, = struct.unpack('>I', d[pos:pos + 4])
        t, c = d[pos + 4:pos + 8], d[pos + 8:pos + 8 + n]
        pos += 12 + n
        if t == b'IHDR':
            w, h, bd, ct, _, _, il = struct.unpack('>IIBBBBB', c)
            assert bd == 8 and ct in (2, 6) and il == 0, 'unsupported PNG'
        elif t == b'IDAT':
            idat += c
    bpp = 3 if ct == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    out = bytearray(h * stride)
    prev = bytearray(stride)
    i = 0
    for y in range(h if rows is None else min(h, rows)):
        f = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out[y * stride:(y + 1) * stride] = line
        prev = line
    return w, h, bpp, out


def read_ply(path):
    d = open(path, 'rb').read()
    end = d.index(b'end_header\n') + len(b'end_header\n')
    head = d[:end].decode().split('\n')
    assert 'binary_little_endian' in head[1], 'binary PLY expected'
    nv = nt = 0
    for line in head:
        if line.startswith('element vertex'):
            nv = int(line.split()[2])
        if line.startswith('element face'):
            nt = int(line.split()[2])
    assert 'property double x' in head, 'double coordinates expected'
    xyz = struct.unpack_from('<%dd' % (3 * nv), d, end)
    pos, tris = end + 24 * nv, []
    for _ in range(nt):
        k = d[pos]
        tris.append(struct.unpack_from('<%di' % k, d, pos + 1))
        pos += 1 + 4 * k
    return [xyz[3 * i:3 * i + 3] for i in range(nv)], tris


def project(verts, w, h, yaw=0.6, pitch=0.45):
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    rad = 0.5 * math.dist(lo, hi)
    fov = math.radians(40)
    dist = rad / math.sin(fov / 2) * 1.05
    eye = [c[0] + dist * math.cos(pitch) * math.cos(yaw), c[1] + dist * math.cos(pitch) * math.sin(yaw),
           c[2] + dist * math.sin(pitch)]
    f = [c[k] - eye[k] for k in range(3)]
    fl = math.sqrt(sum(x * x for x in f))
    f = [x / fl for x in f]
    r = [f[1] * 1 - f[2] * 0, f[2] * 0 - f[0] * 1, 0.0]
    rl = math.sqrt(sum(x * x for x in r))
    r = [x / rl for x in r]
    u = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]]
    t, a = 1 / math.tan(fov / 2), w / h
    out = []
    for v in verts:
        d = [v[k] - eye[k] for k in range(3)]
        z = sum(d[k] * f[k] for k in range(3))
        out.append((w / 2 + sum(d[k] * r[k] for k in range(3)) / z * t / a * w / 2,
                    h / 2 - sum(d[k] * u[k] for k in range(3)) / z * t * h / 2))
    return out


def raster(pts, tris, w, h):
    mask = bytearray(w * h)
    for tri in tris:
        for i in range(1, len(tri) - 1):
            (ax, ay), (bx, by), (cx, cy) = pts[tri[0]], pts[tri[i]], pts[tri[i + 1]]
            area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            if area == 0:
                continue
            x0, x1 = max(0, int(min(ax, bx, cx))), min(w - 1, int(max(ax, bx, cx)) + 1)
            y0, y1 = max(0, int(min(ay, by, cy))), min(h - 1, int(max(ay, by, cy)) + 1)
            for y in range(y0, y1 + 1):
                py = y + 0.5
                for x in range(x0, x1 + 1):
                    px = x + 0.5
                    e0 = ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / area
                    e1 = ((cx - bx) * (py - by) - (cy - by) * (px - bx)) / area
                    e2 = ((ax - cx) * (py - cy) - (ay - cy) * (px - cx)) / area
                    if e0 >= 0 and e1 >= 0 and e2 >= 0:
                        mask[y * w + x] = 1
    return mask


def grow(mask, w, h, r, value):
    """Pixels within r (Chebyshev) of a pixel equal to value."""
    m = np.frombuffer(bytes(mask), dtype=np.uint8).reshape(h, w) == value
    p = np.pad(m, r)
    hit = np.zeros_like(m)
    for dy in range(2 * r + 1):
        for dx in range(2 * r + 1):
            hit |= p[dy:dy + h, dx:dx + w]
    out = np.frombuffer(bytes(mask), dtype=np.uint8).reshape(h, w).copy()
    out[hit] = value
    return out.reshape(-1)


def check_pixels(shot, ply, probe):
    m = re.search(r'canvas=(\d+),(\d+),(\d+),(\d+)', probe)
    if not m:
        return 'no canvas position in the probe line: ' + probe
    cx, cy, cw, ch = map(int, m.groups())
    w, h, bpp, img = read_png(shot, cy + ch)
    return compare(img, w, bpp, cx, cy, cw, ch, *read_ply(ply))


def compare(img, w, bpp, cx, cy, cw, ch, verts, tris, yaw=0.6, pitch=0.45):
    pts = project(verts, cw, ch, yaw, pitch)
    mask = raster(pts, tris, cw, ch)
    inner = grow(mask, cw, ch, 3, 0)   # eroded: well inside
    outer = grow(mask, cw, ch, 3, 1)   # dilated: anything near the object
    n_in = n_in_drawn = n_out = n_out_bg = 0
    for y in range(ch):
        for x in range(cw):
            i = ((cy + y) * w + cx + x) * bpp
            diff = abs(img[i] - BG[0]) + abs(img[i + 1] - BG[1]) + abs(img[i + 2] - BG[2])
            if inner[y * cw + x]:
                n_in += 1
                n_in_drawn += diff > 12
            elif not outer[y * cw + x]:
                n_out += 1
                n_out_bg += diff <= 12
    if n_in < 500:
        return 'the projected mesh covers only %d pixels: camera mismatch' % n_in
    fin, fout = n_in_drawn / n_in, n_out_bg / max(1, n_out)
    msg = 'inside %d px, %.2f%% drawn; outside %d px, %.2f%% background' % (n_in, 100 * fin, n_out, 100 * fout)
    if fin < 0.98 or fout < 0.99:
        return 'FAIL ' + msg
    return 'ok ' + msg


VIEWS = [(0.6, 0.45), (-math.pi / 2, 0.0), (0.0, 0.0), (-math.pi / 2, 1.5)]


def check_png(png, ply):
    """voroprobe's own picture: 4 tiles of 480 x 360 in 2 columns, the views of host/vp_render.h."""
    w, h, bpp, img = read_png(png)
    if (w, h) != (960, 720):
        return 'FAIL the picture is %d x %d, not 960 x 720' % (w, h)
    verts, tris = read_ply(ply)
    res = []
    for v, (yaw, pitch) in enumerate(VIEWS):
        r = compare(img, w, bpp, (v % 2) * 480, (v // 2) * 360, 480, 360, verts, tris, yaw, pitch)
        if not r.startswith('ok'):
            return 'FAIL view %d: %s' % (v, r)
        res.append(r[3:])
    return 'ok ' + ' | '.join(res)


def pick_target(ply, cw, ch):
    """A facet to click: the one nearest the camera at the centroid of the nearest facet's
    projection (ray cast here against the exact mesh). Prints 'X Y FACET'."""
    verts, tris = read_ply(ply)
    pts = project(verts, cw, ch)
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    d = 0.5 * math.dist(lo, hi) / math.sin(math.radians(20)) * 1.05
    eye = [c[0] + d * math.cos(0.45) * math.cos(0.6), c[1] + d * math.cos(0.45) * math.sin(0.6), c[2] + d * math.sin(0.45)]
    near = min(range(len(tris)), key=lambda f: math.dist(eye, [sum(verts[i][k] for i in tris[f]) / 3 for k in range(3)]))
    x = sum(pts[i][0] for i in tris[near]) / 3
    y = sum(pts[i][1] for i in tris[near]) / 3
    # the ray through that pixel: back-project with the same camera
    f = [c[k] - eye[k] for k in range(3)]
    fl = math.sqrt(sum(v * v for v in f))
    f = [v / fl for v in f]
    r = [f[1], -f[0], 0.0]
    rl = math.hypot(r[0], r[1])
    r = [v / rl for v in r]
    u = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]]
    t = 1 / math.tan(math.radians(20))
    sx, sy = (x / cw * 2 - 1) * (cw / ch) / t, (1 - y / ch * 2) / t
    dirn = [f[k] + sx * r[k] + sy * u[k] for k in range(3)]
    best, bf = float('inf'), -1
    for fi, tri in enumerate(tris):
        p0, p1, p2 = (verts[i] for i in tri[:3])
        e1 = [p1[k] - p0[k] for k in range(3)]
        e2 = [p2[k] - p0[k] for k in range(3)]
        pv = [dirn[1] * e2[2] - dirn[2] * e2[1], dirn[2] * e2[0] - dirn[0] * e2[2], dirn[0] * e2[1] - dirn[1] * e2[0]]
        det = sum(e1[k] * pv[k] for k in range(3))
        if abs(det) < 1e-20:
            continue
        tv = [eye[k] - p0[k] for k in range(3)]
        uu = sum(tv[k] * pv[k] for k in range(3)) / det
        if uu < 0 or uu > 1:
            continue
        qv = [tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]]
        w = sum(dirn[k] * qv[k] for k in range(3)) / det
        if w < 0 or uu + w > 1:
            continue
        tt = sum(e2[k] * qv[k] for k in range(3)) / det
        if 0 < tt < best:
            best, bf = tt, fi
    return '%.1f %.1f %d' % (x, y, bf)


def check_numbers(dom, summary):
    s = json.loads(summary)
    page = {}
    for m in re.finditer(r'<td id="s-([a-z_0-9]+)"[^>]*>([^<]*)</td>', dom):
        page[m.group(1)] = m.group(2)
    bad = []
    for key in ('vertices', 'facets', 'probes', 'hits', 'genus', 'status'):
        want = s.get(key)
        want = '\u2013' if want is None else str(want)
        if page.get(key) != want:
            bad.append('%s: page %r, JSON %r' % (key, page.get(key), want))
    if bad:
        return 'FAIL ' + '; '.join(bad)
    return 'ok vertices %s facets %s probes %s hits %s genus %s status %s' % tuple(
        page[k] for k in ('vertices', 'facets', 'probes', 'hits', 'genus', 'status'))


def check_live(dom, summary):
    """The live page after the scan: it saw the scan running, then its final state, with every
    sample sent received and the final counts equal to sim --json."""
    s = json.loads(summary)
    page = dict(re.findall(r'<td id="l-([a-z]+)">([^<]*)</td>', dom))
    m = re.search(r'<span id="l-state">([^<]*)</span>', dom)
    page['state'] = m.group(1) if m else None
    bad = []
    if page.get('state') != s['status']:
        bad.append('state %r, JSON %r' % (page.get('state'), s['status']))
    for key in ('vertices', 'facets', 'probes', 'hits'):
        if page.get(key) != str(s[key]):
            bad.append('%s: page %r, JSON %r' % (key, page.get(key), s[key]))
    if page.get('final') != 'yes':
        bad.append('no final state')
    if page.get('received') != page.get('samples') or int(page.get('samples', 0)) < s['hits']:
        bad.append('samples sent %r, received %r, hits %r' % (page.get('samples'), page.get('received'), s['hits']))
    if int(page.get('updates', 0)) < 2 or int(page.get('frames', 0)) < 2:
        bad.append('%s updates and %s mesh frames while running' % (page.get('updates'), page.get('frames')))
    if bad:
        return 'FAIL ' + '; '.join(bad)
    return 'ok state %s, %s samples sent and received, %s updates and %s frames, vertices %s facets %s probes %s' % (
        page['state'], page['received'], page['updates'], page['frames'], page['vertices'], page['facets'], page['probes'])


def main():
    if len(sys.argv) == 5 and sys.argv[1] == 'pixels':
        res = check_pixels(sys.argv[2], sys.argv[3], sys.argv[4])
    elif len(sys.argv) == 5 and sys.argv[1] == 'pick':
        print(pick_target(sys.argv[2], int(sys.argv[3]), int(sys.argv[4])))
        return 0
    elif len(sys.argv) == 4 and sys.argv[1] == 'png':
        res = check_png(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == 'live':
        res = check_live(open(sys.argv[2], encoding='utf-8').read(), open(sys.argv[3]).read().strip().split('\n')[-1])
    elif len(sys.argv) == 4 and sys.argv[1] == 'numbers':
        res = check_numbers(open(sys.argv[2], encoding='utf-8').read(), open(sys.argv[3]).read().strip().split('\n')[-1])
    else:
        print(__doc__)
        return 2
    print(res)
    return 0 if res.startswith('ok') else 1


if __name__ == '__main__':
    sys.exit(main())
