#!/usr/bin/env python3
"""makepng.py - test images written with zlib alone (no imaging library).

    makepng.py OUT W H KIND [SEED]

KIND: noise (random texels: incompressible, about 3 bytes a texel),
smooth (a gentle gradient: a few bytes per hundred texels), checker (8 x 8
squares of two colours).  An RGB8 PNG; SEED (default 1) makes noise
repeatable."""
import random
import struct
import sys
import zlib


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def main():
    out, w, h, kind = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    rng = random.Random(int(sys.argv[5]) if len(sys.argv) > 5 else 1)
    rows = []
    for y in range(h):
        if kind == "noise":
            row = rng.randbytes(3 * w)
        elif kind == "smooth":
            row = bytes(v for x in range(w) for v in (x * 255 // w, y * 255 // h, 128))
        else:
            row = bytes(v for x in range(w) for v in ((230, 230, 220) if (x * 8 // w + y * 8 // h) % 2 else (40, 60, 180)))
        # filter type 2 (up) for the smooth image compresses it hard; 0 elsewhere
        if kind == "smooth" and y > 0:
            prev = rows[-1][2]
            rows.append((2, bytes((a - b) & 255 for a, b in zip(row, prev)), row))
        else:
            rows.append((0, row, row))
    raw = b"".join(bytes([f]) + data for f, data, _ in rows)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(out, "wb") as f:
        f.write(png)


main()
