#!/usr/bin/env python3
"""envmap.py - Radiance .hdr panoramas for tests, without numpy: a constant
light, or a sky over a ground with a round sun (equirectangular, as lanray's
`environment` reads them: u across from -x, the top row straight up).

    python3 tests/tools/envmap.py OUT.hdr constant W H R G B
    python3 tests/tools/envmap.py OUT.hdr sky W H SUN_U SUN_V SUN_RADIUS SUN_LIGHT
    python3 tests/tools/envmap.py OUT.hdr checker W H SQUARE (texels a side: black and white)
    python3 tests/tools/envmap.py OUT.hdr town W H SQUARE (a checker band about the horizon, as a
        town's windows, under the sky's gradient and over a plain ground: detail where a mirror
        ball shrinks it, none at the poles, where no sampling could resolve a checker)
"""
import math
import sys


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mant, e = math.frexp(m)
    s = mant * 256.0 / m
    return bytes((min(255, int(r * s)), min(255, int(g * s)), min(255, int(b * s)), e + 128))


def write_hdr(path, w, h, f):
    """f(u, t) -> (r, g, b) at a texel's centre: u across, t down, in [0, 1]"""
    out = bytearray(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
    for y in range(h):
        for x in range(w):
            out += rgbe(*f((x + 0.5) / w, (y + 0.5) / h))
    open(path, "wb").write(out)


def sky(sun_u, sun_t, sun_r, sun_light):
    def f(u, t):
        du = (u - sun_u) * 2 * math.pi * math.sin(sun_t * math.pi)
        dt = (t - sun_t) * math.pi
        if du * du + dt * dt < sun_r * sun_r:
            return (sun_light, sun_light * 0.9, sun_light * 0.75)
        el = (0.5 - t) * math.pi
        if el <= 0:
            return (0.25, 0.2, 0.15)
        a = 0.3 + 0.5 * el / (math.pi / 2)
        return (0.35 * a, 0.55 * a, a)
    return f


def main():
    a = sys.argv[1:]
    w, h = int(a[2]), int(a[3])
    if a[1] == "constant":
        c = tuple(float(v) for v in a[4:7])
        write_hdr(a[0], w, h, lambda u, t: c)
    elif a[1] == "checker":
        n = int(a[4])
        write_hdr(a[0], w, h, lambda u, t: (1.0,) * 3 if (int(u * w) // n + int(t * h) // n) % 2 else (0.0,) * 3)
    elif a[1] == "town":
        n = int(a[4])
        sky_f = sky(0, 0, 0, 0)

        def town(u, t):
            el = (0.5 - t) * 180
            if el > 30 or el < -20:
                return sky_f(u, t)
            return (0.9, 0.85, 0.7) if (int(u * w) // n + int(t * h) // n) % 2 else (0.05, 0.05, 0.08)
        write_hdr(a[0], w, h, town)
    else:
        write_hdr(a[0], w, h, sky(*(float(v) for v in a[4:8])))


if __name__ == "__main__":
    main()
