"""A minimal WebSocket client for the gateway tests (no library): the
upgrade, whole messages (fragments joined), masked client frames."""
import json
import os
import socket
import struct
import sys
import time


class Viewer:
    def __init__(self, host, port, origin=None, timeout=30):
        self.s = socket.create_connection((host, int(port)), timeout=timeout)
        origin = origin or f"http://{host}:{port}"
        self.s.sendall((f"GET /ws?format=jpeg HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                        "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                        f"Sec-WebSocket-Version: 13\r\nOrigin: {origin}\r\n\r\n").encode())
        buf = b""
        while b"\r\n\r\n" not in buf:
            buf += self.s.recv(4096)
        head, self.buf = buf.split(b"\r\n\r\n", 1)
        if b" 101 " not in head:
            sys.exit(f"upgrade refused: {head[:80]!r}")

    def _read(self, n):
        while len(self.buf) < n:
            chunk = self.s.recv(65536)
            if not chunk:
                sys.exit("the gateway closed the WebSocket")
            self.buf += chunk
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def message(self):
        """The next whole message: (opcode, payload); 1 text, 2 binary."""
        opcode, payload = 0, b""
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            opcode = (b0 & 0x0F) or opcode  # 0: a fragment continues it
            payload += self._read(n)
            if b0 & 0x80:
                return opcode, payload

    def next_text(self, deadline=30):
        """The next text message as JSON (binary frames skipped)."""
        end = time.monotonic() + deadline
        while time.monotonic() < end:
            opcode, payload = self.message()
            if opcode == 1:
                return json.loads(payload)
        sys.exit("no text message within the hang bound")

    def send(self, obj):
        """A JSON text message (a client's frames are masked)."""
        data = json.dumps(obj).encode()
        mask = os.urandom(4)
        head = bytes([0x81]) + (bytes([0x80 | len(data)]) if len(data) < 126
                                else bytes([0x80 | 126]) + struct.pack(">H", len(data)))
        self.s.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))
