#!/usr/bin/env python3
"""A wire between `voroprobe mcu --exec` and the MCU's host build (the program in
$VP_MCU_PROGRAM) that rewrites the MOVE frame number $VP_TAMPER_MOVE: two more step edges on
X, the frame's CRC made good again. The firmware's report is then wrong but well formed:
the bridge's step check (edges against the ideal trapezoid) must catch it, not the CRC.
Frames as doc/mcu-protocol.md: COBS between 0x00 bytes, [version, type, seq, len, payload,
CRC-32]."""
import os
import select
import subprocess
import zlib

MOVE = 0x02


def cobs_decode(b):
    out, i = bytearray(), 0
    while i < len(b):
        code = b[i]
        if code == 0 or i + code > len(b):
            return None
        out += b[i + 1:i + code]
        i += code
        if code < 0xFF and i < len(b):
            out.append(0)
    return bytes(out)


def cobs_encode(b):
    out, block = bytearray([0]), 0
    for x in b:
        if x != 0:
            out.append(x)
        if x == 0 or len(out) - block == 0xFF:
            out[block] = len(out) - block
            block = len(out)
            out.append(0)
    out[block] = len(out) - block
    return bytes(out)


def main():
    target = int(os.environ.get("VP_TAMPER_MOVE", "10"))
    child = subprocess.Popen([os.environ["VP_MCU_PROGRAM"]], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    moves, acc = 0, bytearray()
    fin, fout = 0, 1
    cin, cout = child.stdin.fileno(), child.stdout.fileno()
    while True:
        r, _, _ = select.select([fin, cout], [], [])
        if fin in r:
            d = os.read(fin, 4096)
            if not d:
                break
            os.write(cin, d)
        if cout in r:
            d = os.read(cout, 4096)
            if not d:
                break
            for x in d:
                if x != 0:
                    acc.append(x)
                    continue
                if acc:
                    body = cobs_decode(bytes(acc))
                    if body and len(body) >= 10 and body[1] == MOVE:
                        moves += 1
                        if moves == target:
                            b = bytearray(body[:-4])
                            b[6 + 48] = (b[6 + 48] + 2) & 0xFF
                            body = bytes(b) + zlib.crc32(bytes(b)).to_bytes(4, "little")
                            acc = bytearray(cobs_encode(body))
                    os.write(fout, b"\x00" + bytes(acc) + b"\x00")
                acc = bytearray()
    child.stdin.close()
    child.wait()


if __name__ == "__main__":
    main()
