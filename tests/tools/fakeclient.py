#!/usr/bin/env python3
"""A misbehaving lanray client for the integration tests.

    fakeclient.py PORT MODE [TOKEN]

MODE is one of:
  garbage     send random bytes instead of a handshake
  version     a correct handshake but protocol version 99
  lie-size    a valid header that claims a 4 GiB packet
  forge-data  complete the handshake, then send pixels for a segment never given
  bad-coded   complete the handshake, then send coded pixels that do not decode
              for every segment it is given, until the server's ERROR
  overclaim   the same, coded pixels as many bytes as the segment's raw ones
  silent      connect and send nothing, wait for the server to close
  slowloris   send a valid HELLO one byte every half second
  storm N     open N connections at once, hold them silent, report how many the server closed
Prints the text of the server's ERROR packet, or 'closed' / 'no error'.
"""
import hashlib, hmac, os, re, socket, struct, sys

# the protocol version this checkout speaks, from the codec's header
_MSG_H = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../common/net/msg.h")
MAGIC, BOM = 0x5941524C, 0x01020304
VERSION = int(re.search(r"#define PROTO_VERSION (\d+)u", open(_MSG_H).read()).group(1))
SERVER_HELLO, HELLO, WELCOME, UPDATE, COMPUTE, DATA, ASSET, ERROR = 1, 2, 3, 4, 5, 6, 7, 8


def read_packet(s):
    head = b""
    while len(head) < 8:
        chunk = s.recv(8 - len(head))
        if not chunk:
            return None, None
        head += chunk
    ptype, size = struct.unpack("=II", head)
    body = b""
    while len(body) < size - 8:
        chunk = s.recv(min(65536, size - 8 - len(body)))
        if not chunk:
            return None, None
        body += chunk
    return ptype, body


def hello(nonce, token, version=VERSION):
    cn = os.urandom(32)
    key = hashlib.sha256(token.encode()).digest()
    proof = hmac.new(key, b"lanray-auth-v1" + nonce + cn, hashlib.sha256).digest()
    # the server's precision: 4 (float build) unless LANRAY_REAL_SIZE says 8
    # codecs 0b111: raw, zstd, LZ4
    body = struct.pack("=IIIIII", MAGIC, version, BOM, 1, int(os.environ.get("LANRAY_REAL_SIZE", "4")), 7) + cn + proof
    return struct.pack("=II", HELLO, 8 + len(body)) + body


def session_packets(s):
    """The server's packets until it closes or sends an ERROR (then printed)."""
    while True:
        ptype, body = read_packet(s)
        if ptype is None:
            print("closed")
            return
        if ptype == ERROR:
            print(body.decode(errors="replace"))
            return
        yield ptype, body


def wait_error(s):
    while True:
        ptype, body = read_packet(s)
        if ptype is None:
            return "closed"
        if ptype == ERROR:
            return body.decode(errors="replace")


def storm(port, n):
    socks = [socket.create_connection(("127.0.0.1", port), timeout=30) for _ in range(n)]
    closed = 0
    for s in socks:
        while True:
            ptype, _ = read_packet(s)
            if ptype is None or ptype == ERROR:
                closed += 1
                break
    print("closed %d of %d" % (closed, n))


def main():
    port, mode = int(sys.argv[1]), sys.argv[2]
    if mode == "storm":
        storm(port, int(sys.argv[3]))
        return
    token = sys.argv[3] if len(sys.argv) > 3 else ""
    s = socket.create_connection(("127.0.0.1", port), timeout=20)
    ptype, body = read_packet(s)
    assert ptype == SERVER_HELLO, ptype
    nonce = body[16:48]
    if mode == "garbage":
        s.sendall(os.urandom(4096))
    elif mode == "version":
        s.sendall(hello(nonce, token, version=99))
    elif mode == "lie-size":
        s.sendall(struct.pack("=II", DATA, 0xFFFFFFFF))
    elif mode == "forge-data":
        s.sendall(hello(nonce, token))
        # forged pixels for every frame: if the frame ended before they
        # arrived, the server drops them as stale, and the next frame's try counts
        for ptype, body in session_packets(s):
            if ptype == UPDATE:
                frame = struct.unpack("=I", body[:4])[0]
                # a segment at the end of the frame that nobody was given yet
                body = struct.pack("=IIIII", frame, 7, 3, 100, 0) + b"\xff" * 9
                s.sendall(struct.pack("=II", DATA, 8 + len(body)) + body)
        return
    elif mode in ("bad-coded", "overclaim"):
        s.sendall(hello(nonce, token))
        coding = None
        # bad pixels for every segment it is given, until the server's
        # ERROR (session_packets prints it): the server decodes only the
        # pixels it takes, and a segment whose frame the others finished
        # first (the tail shared, frames pipelined) comes back stale and
        # unread; answering its first segment alone left the client
        # holding the next frame's, stalled, in two runs on loaded machines
        for ptype, body in session_packets(s):
            if ptype == WELCOME:
                coding = struct.unpack("=II", body[:8])[1]
                if coding == 0:
                    print("the server asked for raw pixels")
                    return
            segs = []
            if ptype == UPDATE:
                frame, nseg = struct.unpack("=I", body[:4])[0], struct.unpack("=I", body[24:28])[0]
                segs = [struct.unpack("=II", body[28 + 8 * k:36 + 8 * k]) for k in range(nseg)]
            elif ptype == COMPUTE:
                frame, first, count = struct.unpack("=III", body[:12])
                segs = [(first, count)]
            for first, count in segs:
                raw = 3 * count
                pix = b"\x5a" * (raw // 2 if mode == "bad-coded" else raw)
                body = struct.pack("=IIIII", frame, first, count, 100, coding) + pix
                try:
                    s.sendall(struct.pack("=II", DATA, 8 + len(body)) + body)
                except OSError:
                    # the server dropped it after an earlier packet: its
                    # ERROR is still there to read (queued before the reset)
                    print(wait_error(s))
                    return
        return
    elif mode == "silent":
        pass
    elif mode == "slowloris":
        import time
        for b in hello(nonce, token):
            try:
                s.send(bytes([b]))
            except OSError:
                break
            time.sleep(0.5)
    print(wait_error(s))


main()
