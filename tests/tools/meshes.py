#!/usr/bin/env python3
"""meshes.py - test meshes for the SIMD path test (tests/cli/simd.sh).

    meshes.py DIR     writes DIR/bumpy.obj (a displaced sphere, 20480
                      triangles, smooth normals) and DIR/grid.obj (a flat
                      grid of 2 x 64 x 64 triangles: every ray near it
                      crosses shared edges and vertices)

Deterministic: the same files every time."""
import math
import os
import sys


def bumpy(path, n=64, m=160):
    v, vn, f = [], [], []
    for i in range(n + 1):
        th = math.pi * i / n
        for j in range(m):
            ph = 2 * math.pi * j / m
            r = 1 + 0.08 * math.sin(7 * th) * math.cos(5 * ph) + 0.03 * math.sin(23 * ph + 3 * th)
            d = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            v.append(tuple(r * c for c in d))
            vn.append(d)
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, i * m + (j + 1) % m
            c, d = a + m, b + m
            f.append((a, c, b))
            f.append((b, c, d))
    with open(path, "w") as out:
        for p in v:
            out.write("v %.6f %.6f %.6f\n" % p)
        for p in vn:
            out.write("vn %.6f %.6f %.6f\n" % p)
        for t in f:
            out.write("f %s\n" % " ".join("%d//%d" % (k + 1, k + 1) for k in t))


def grid(path, n=64):
    with open(path, "w") as out:
        for i in range(n + 1):
            for j in range(n + 1):
                out.write("v %g 0 %g\n" % (i / n * 2 - 1, j / n * 2 - 1))
        for i in range(n):
            for j in range(n):
                a, b = i * (n + 1) + j + 1, (i + 1) * (n + 1) + j + 1
                out.write("f %d %d %d\nf %d %d %d\n" % (a, b, a + 1, a + 1, b, b + 1))


def main():
    d = sys.argv[1]
    os.makedirs(d, exist_ok=True)
    bumpy(os.path.join(d, "bumpy.obj"))
    grid(os.path.join(d, "grid.obj"))


if __name__ == "__main__":
    main()
