"""quads.py - the test quads of tests/cli's material maps (cutout.sh, normalmap.sh, glow.sh,
metalmap.sh): small PNG images, and a glTF quad x 0..2, y -1..1 at z = 0 with texture coordinates
(u along x, glTF's v down the image: +y is its "up"), optionally normals +z, its material and its
images given, the images embedded as data: URIs."""
import base64
import json
import struct
import zlib


def png(w, h, rows, ctype=2):
    """A PNG of 8-bit rows (ctype 2: RGB, 6: RGBA), no filter."""
    def chunk(t, b):
        return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b) & 0xffffffff)
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, ctype, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def gltf_quad(path, material, images, normals=False, sampler=None):
    """Writes the quad as glTF: `material` its one material, texture i image i (read through
    `sampler` where given); the extensions the material names are declared used."""
    pos = struct.pack("<12f", 0, -1, 0, 2, -1, 0, 2, 1, 0, 0, 1, 0)
    nrm = struct.pack("<12f", *([0, 0, 1] * 4)) if normals else b""
    uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
    idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    buf = pos + nrm + uv + idx
    views, at = [], 0
    for n in (48, len(nrm), 32, 12):
        if n:
            views.append({"buffer": 0, "byteOffset": at, "byteLength": n})
            at += n
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, -1, 0],
                  "max": [2, 1, 0]}]
    attributes = {"POSITION": 0}
    if normals:
        attributes["NORMAL"] = len(accessors)
        accessors.append({"bufferView": len(accessors), "componentType": 5126, "count": 4, "type": "VEC3"})
    attributes["TEXCOORD_0"] = len(accessors)
    accessors.append({"bufferView": len(accessors), "componentType": 5126, "count": 4, "type": "VEC2"})
    accessors.append({"bufferView": len(accessors), "componentType": 5123, "count": 6, "type": "SCALAR"})
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "buffers": [{"byteLength": len(buf),
                      "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
         "bufferViews": views, "accessors": accessors,
         "meshes": [{"primitives": [{"attributes": attributes, "indices": len(accessors) - 1, "material": 0}]}],
         "images": [{"uri": "data:image/png;base64," + base64.b64encode(i).decode()} for i in images],
         "textures": [{"source": i} for i in range(len(images))], "materials": [material]}
    if material.get("extensions"):
        g["extensionsUsed"] = sorted(material["extensions"])
    if sampler:
        g["samplers"] = [sampler]
        for t in g["textures"]:
            t["sampler"] = 0
    with open(path, "w") as f:
        json.dump(g, f)
