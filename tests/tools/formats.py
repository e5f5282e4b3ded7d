#!/usr/bin/env python3
"""formats.py - one model in every format obj2tmd reads (tests/cli/formats.sh).

    formats.py DIR    writes DIR/model.obj (with vertex normals), model-flat.obj
                      (without), model-ascii.ply and model-bin.ply (with normals),
                      model-ascii.stl and model-bin.stl (facet normals only: STL
                      has no other kind), model.gltf with model.bin, and model.glb

A displaced sphere of 2 x 24 x 11 triangles plus a quad, coordinates and
normal components whole numbers, so that every parser (strtod, Assimp's
own) reads exactly the same floats."""
import json
import math
import os
import struct
import sys


def model():
    n, m = 12, 24
    v, vn, f = [], [], []
    for i in range(n + 1):
        th = math.pi * i / n
        for j in range(m):
            ph = 2 * math.pi * j / m
            r = 100 + 8 * math.sin(3 * th) * math.cos(4 * ph)
            d = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            v.append(tuple(round(r * c) for c in d))
            vn.append(tuple(round(1000 * c) for c in d))
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, i * m + (j + 1) % m
            c, d = a + m, b + m
            if i > 0:
                f.append((a, c, b))
            if i < n - 1:
                f.append((b, c, d))
    # a floor quad under it, two triangles
    base = len(v)
    v += [(-150, -120, -150), (150, -120, -150), (150, -120, 150), (-150, -120, 150)]
    vn += [(0, 1000, 0)] * 4
    f += [(base, base + 2, base + 1), (base, base + 3, base + 2)]
    # drop triangles that rounding made degenerate
    def area2(t):
        p, q, r = (v[k] for k in t)
        u = [q[k] - p[k] for k in range(3)]
        w = [r[k] - p[k] for k in range(3)]
        c = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        return c
    f = [t for t in f if any(area2(t))]
    return v, vn, f, area2


def write_obj(path, v, vn, f, normals):
    with open(path, "w") as out:
        for p in v:
            out.write("v %d %d %d\n" % p)
        if normals:
            for p in vn:
                out.write("vn %d %d %d\n" % p)
            for t in f:
                out.write("f %s\n" % " ".join("%d//%d" % (k + 1, k + 1) for k in t))
        else:
            for t in f:
                out.write("f %d %d %d\n" % tuple(k + 1 for k in t))


def write_ply(path, v, vn, f, binary):
    head = ["ply", "format %s 1.0" % ("binary_little_endian" if binary else "ascii"),
            "comment lanray test model", "element vertex %d" % len(v),
            "property float x", "property float y", "property float z",
            "property float nx", "property float ny", "property float nz",
            "element face %d" % len(f), "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as out:
        out.write(("\n".join(head) + "\n").encode())
        for p, n in zip(v, vn):
            if binary:
                out.write(struct.pack("<6f", *p, *n))
            else:
                out.write(("%d %d %d %d %d %d\n" % (*p, *n)).encode())
        for t in f:
            if binary:
                out.write(struct.pack("<B3i", 3, *t))
            else:
                out.write(("3 %d %d %d\n" % t).encode())


def write_stl(path, v, f, area2, binary):
    with open(path, "wb") as out:
        if binary:
            out.write(b"lanray test model".ljust(80, b" ") + struct.pack("<I", len(f)))
        else:
            out.write(b"solid model\n")
        for t in f:
            c = area2(t)
            l = math.sqrt(sum(x * x for x in c))
            nrm = tuple(x / l for x in c)
            if binary:
                out.write(struct.pack("<3f", *nrm))
                for k in t:
                    out.write(struct.pack("<3f", *v[k]))
                out.write(struct.pack("<H", 0))
            else:
                out.write(("facet normal %g %g %g\n outer loop\n" % nrm).encode())
                for k in t:
                    out.write(("  vertex %d %d %d\n" % v[k]).encode())
                out.write(b" endloop\nendfacet\n")
        if not binary:
            out.write(b"endsolid model\n")


def gltf_parts(v, vn, f):
    pos = b"".join(struct.pack("<3f", *p) for p in v)
    nrm = b"".join(struct.pack("<3f", *[c / math.sqrt(sum(x * x for x in n)) for c in n]) for n in vn)
    idx = b"".join(struct.pack("<3I", *t) for t in f)
    blob = pos + nrm + idx
    lo = [min(p[k] for p in v) for k in range(3)]
    hi = [max(p[k] for p in v) for k in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "lanray tests/tools/formats.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nrm), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos) + len(nrm), "byteLength": len(idx), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(vn), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": 3 * len(f), "type": "SCALAR"},
        ],
    }
    return doc, blob


def main():
    d = sys.argv[1]
    os.makedirs(d, exist_ok=True)
    v, vn, f, area2 = model()
    write_obj(os.path.join(d, "model.obj"), v, vn, f, True)
    write_obj(os.path.join(d, "model-flat.obj"), v, vn, f, False)
    write_ply(os.path.join(d, "model-ascii.ply"), v, vn, f, False)
    write_ply(os.path.join(d, "model-bin.ply"), v, vn, f, True)
    write_stl(os.path.join(d, "model-ascii.stl"), v, f, area2, False)
    write_stl(os.path.join(d, "model-bin.stl"), v, f, area2, True)
    doc, blob = gltf_parts(v, vn, f)
    with open(os.path.join(d, "model.bin"), "wb") as out:
        out.write(blob)
    doc["buffers"][0]["uri"] = "model.bin"
    with open(os.path.join(d, "model.gltf"), "w") as out:
        json.dump(doc, out)
    del doc["buffers"][0]["uri"]
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob += b"\0" * (-len(blob) % 4)
    with open(os.path.join(d, "model.glb"), "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(blob)))
        out.write(struct.pack("<I4s", len(js), b"JSON") + js)
        out.write(struct.pack("<I4s", len(blob), b"BIN\0") + blob)


if __name__ == "__main__":
    main()
