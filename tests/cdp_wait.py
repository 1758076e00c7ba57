#!/usr/bin/env python3
"""Drives a page open in a headless chromium, then prints its DOM.

  cdp_wait.py PORT TIMEOUT_S STEP...

PORT is chromium's --remote-debugging-port. Each STEP, in order, on the first page (through
the DevTools protocol's Runtime.evaluate, over a WebSocket written here with the standard
library): wait=EXPR evaluates the JavaScript expression every 0.1 s until it is true;
eval=EXPR evaluates it once; sleep=S waits S seconds. Prints document.documentElement
.outerHTML; exit 0 when every wait held within TIMEOUT_S in all, 1 otherwise (the DOM is
printed all the same)."""
import base64
import json
import os
import socket
import struct
import sys
import time
import urllib.request


class WebSocket:
    def __init__(self, url):
        assert url.startswith('ws://')
        host, _, path = url[5:].partition('/')
        name, _, port = host.partition(':')
        self.s = socket.create_connection((name, int(port or 80)), timeout=30)
        key = base64.b64encode(os.urandom(16)).decode()
        self.s.sendall(('GET /%s HTTP/1.1\r\nHost: %s\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n'
                        'Sec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\n\r\n' % (path, host, key)).encode())
        head = b''
        while b'\r\n\r\n' not in head:
            chunk = self.s.recv(1)
            if not chunk:
                raise IOError('the WebSocket handshake was cut')
            head += chunk
        if b' 101 ' not in head.split(b'\r\n')[0]:
            raise IOError('no WebSocket: ' + head.decode(errors='replace'))

    def _read(self, n):
        out = b''
        while len(out) < n:
            chunk = self.s.recv(n - len(out))
            if not chunk:
                raise IOError('the WebSocket closed')
            out += chunk
        return out

    def send(self, text):
        data, mask = text.encode(), os.urandom(4)
        n = len(data)
        head = bytes([0x81]) + (bytes([0x80 | n]) if n < 126 else bytes([0x80 | 126]) + struct.pack('>H', n)
                                if n < 65536 else bytes([0x80 | 127]) + struct.pack('>Q', n))
        self.s.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def recv(self):
        msg = b''
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7f
            if n == 126:
                n, = struct.unpack('>H', self._read(2))
            elif n == 127:
                n, = struct.unpack('>Q', self._read(8))
            data = self._read(n)
            if b0 & 0x0f == 0x8:
                raise IOError('the WebSocket closed')
            if b0 & 0x0f in (0x0, 0x1, 0x2):
                msg += data
                if b0 & 0x80:
                    return msg.decode()


def main():
    port, timeout, steps = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3:]
    end = time.time() + timeout
    ws = None
    while ws is None:
        try:
            pages = json.load(urllib.request.urlopen('http://127.0.0.1:%d/json/list' % port, timeout=5))
            pages = [p for p in pages if p.get('type') == 'page']
            if pages:
                ws = WebSocket(pages[0]['webSocketDebuggerUrl'])
        except (OSError, ValueError):
            pass
        if ws is None:
            if time.time() > end:
                print('no page in chromium at port %d' % port, file=sys.stderr)
                return 1
            time.sleep(0.2)
    ids = [0]

    def evaluate(e):
        ids[0] += 1
        ws.send(json.dumps({'id': ids[0], 'method': 'Runtime.evaluate',
                            'params': {'expression': e, 'returnByValue': True}}))
        while True:
            m = json.loads(ws.recv())
            if m.get('id') == ids[0]:
                return m.get('result', {}).get('result', {}).get('value')

    ok = True
    for step in steps:
        kind, _, arg = step.partition('=')
        if kind == 'eval':
            evaluate(arg)
        elif kind == 'sleep':
            time.sleep(float(arg))
        elif kind == 'wait':
            while not evaluate('!!(%s)' % arg):
                if time.time() > end:
                    print('timed out waiting for: ' + arg, file=sys.stderr)
                    ok = False
                    break
                time.sleep(0.1)
        else:
            print('unknown step: ' + step, file=sys.stderr)
            return 2
        if not ok:
            break
    sys.stdout.write(evaluate('document.documentElement.outerHTML') or '')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
