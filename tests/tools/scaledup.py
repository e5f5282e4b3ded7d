#!/usr/bin/env python3
"""scaledup.py S UP any|all BIG SMALL [BIG SMALL ...] - whether the server's
frames BIG (full size) are the frames SMALL (the same moments at render
scale S, in quarter steps: lanray-render at the small size) brought up UP:
smooth (bilinear between the small pixels' centres, placed where their
rays went: server/upscale.c), blocks (the nearest), or hdr (RGBE smooth,
the light decoded, mixed with the same weights in double and coded again:
upscale_smooth_rgbe).  With any, one pair that matches is enough; with
all, every pair must.  Prints why the others differ; exit 1 where it fails."""
import math, struct, sys
sys.path.insert(0, "tests/tools")
from pngpixel import read as read_png
def read_hdr(path):  # lanray's .hdr: a header, a blank line, the size line, flat RGBE pixels
    head, _, body = open(path, "rb").read().partition(b"\n\n")
    size, _, px = body.partition(b"\n")
    h, w = int(size.split()[1]), int(size.split()[3])
    return w, h, px
def decode(p):
    f = math.ldexp(1.0, p[3] - 136) if p[3] else 0.0
    return [(p[c] + 0.5) * f if p[3] else 0.0 for c in range(3)]
def f32(v):
    return struct.unpack("f", struct.pack("f", v))[0]
def encode(c):
    c = [f32(v) if v > 0 else 0.0 for v in c]
    v = max(c)
    if not v >= 1e-32:
        return bytes(4)
    m, e = math.frexp(v)
    m = m * 256.0 / v
    return bytes([int(x * m) for x in c] + [e + 128])
k2 = 128  # a place to 1/128 of a frame pixel
side = lambda n: (4 * n + s - 1) // s  # s: the render scale in quarter steps (set by main)
def place(t, N, n, sw, W):  # full pixel t's centre among the frame's (camera: sw pixels span W, lines centred), rounded
    num, den = ((2 * t + 1) * sw - N * sw + n * W - W) * k2, 2 * W
    return (2 * num + den) // (2 * den)
def taps(t, N, n, sw, W):  # the frame pixels about it and the right one's weight in 1/128
    u = place(t, N, n, sw, W)
    i, r = u // k2, u % k2
    return min(max(i, 0), n - 1), min(max(i + 1, 0), n - 1), r
def nearest(t, N, n, sw, W):
    return min(max((place(t, N, n, sw, W) + k2 // 2) // k2, 0), n - 1)
def scaled(bigf, smallf, up):  # None where BIG is SMALL brought up, else why not
    if up == "hdr":
        W, H, big = read_hdr(bigf)
        sw, sh, small = read_hdr(smallf)
        lights = [decode(small[4 * i:4 * i + 4]) for i in range(sw * sh)]
    else:
        (rows, _), (srows, _) = read_png(bigf), read_png(smallf)
        W, H, sw, sh = len(rows[0]) // 3, len(rows), len(srows[0]) // 3, len(srows)
    if (sw, sh) != (side(W), side(H)):
        return "the frame is %dx%d, its small one %dx%d" % (W, H, sw, sh)
    for y in range(H):
        j0, j1, t = taps(y, H, sh, sw, W)
        for x in range(W):
            i0, i1, r = taps(x, W, sw, sw, W)
            if up == "hdr":
                w = [float((k2 - r) * (k2 - t)), float(r * (k2 - t)), float((k2 - r) * t), float(r * t)]
                c4 = [lights[j0 * sw + i0], lights[j0 * sw + i1], lights[j1 * sw + i0], lights[j1 * sw + i1]]
                mix = [(w[0] * c4[0][c] + w[1] * c4[1][c] + w[2] * c4[2][c] + w[3] * c4[3][c]) / float(k2 * k2) for c in range(3)]
                got, want = big[4 * (y * W + x):4 * (y * W + x) + 4], encode(mix)
            elif up == "blocks":
                i, j = nearest(x, W, sw, sw, W), nearest(y, H, sh, sw, W)  # the nearest frame pixel
                got, want = rows[y][3 * x:3 * x + 3], srows[j][3 * i:3 * i + 3]
            else:
                mix = lambda line, c: (k2 - r) * line[3 * i0 + c] + r * line[3 * i1 + c]
                got = rows[y][3 * x:3 * x + 3]
                want = bytes(((k2 - t) * mix(srows[j0], c) + t * mix(srows[j1], c) + k2 * k2 // 2) // (k2 * k2) for c in range(3))
            if got != want:
                return "pixel %d,%d" % (x, y)
    return None


if __name__ == "__main__":
    s, up, how = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    files = sys.argv[4:]
    why = [scaled(files[i], files[i + 1], up) for i in range(0, len(files), 2)]
    if all(why) if how == "any" else any(why):
        sys.exit("; ".join("%s: %s" % (files[2 * f], w) for f, w in enumerate(why) if w))
