#!/usr/bin/env bash
# Metal-roughness textures: a glTF quad (x 0..2, y -1..1 at z = 0, facing
# +z) of base colour white, metallicFactor 1, roughnessFactor 1, whose
# metallicRoughnessTexture is 4 x 1 texels: the left half blue 255 green
# 0 (metal, smooth: a mirror), the right half blue 0 (not metal).  Seen
# straight on (orthographic) under a lamp from the front, before a red
# background: the left half mirrors the red background, the right half is
# lit white-grey.  Without the texture the material stays diffuse (glTF's
# defaults: white), both halves grey.  Every SIMD path gives the same
# bytes, a .tmd the glTF's, and a server with a client lanray-render's.
set -u
source tests/tools/server-lib.sh
python3 - "$dir" <<'PY'
import base64, json, struct, sys, zlib
d = sys.argv[1]
def png(w, h, rows):
    def chunk(t, b): return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b) & 0xffffffff)
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
mr = png(4, 1, [[0, 0, 255] * 2 + [0, 255, 0] * 2])
pos = struct.pack("<12f", 0, -1, 0, 2, -1, 0, 2, 1, 0, 0, 1, 0)
nrm = struct.pack("<12f", *([0, 0, 1] * 4))
uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
buf = pos + nrm + uv + idx
for name, pbr in (("metal", {"metallicRoughnessTexture": {"index": 0}}), ("plain", {})):
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "buffers": [{"byteLength": len(buf),
                      "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
         "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                         {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                         {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                         {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                        "min": [0, -1, 0], "max": [2, 1, 0]},
                       {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                       {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                       {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                     "material": 0}]}],
         "images": [{"uri": "data:image/png;base64," + base64.b64encode(mr).decode()}],
         "samplers": [{"wrapS": 33071, "wrapT": 33071}], "textures": [{"source": 0, "sampler": 0}],
         "materials": [{"pbrMetallicRoughness": pbr}]}
    open(f"{d}/{name}.gltf", "w").write(json.dumps(g))
    open(f"{d}/{name}.scene", "w").write(
        "camera position 1 0 5 lookat 1 0 0 ortho 2\nambient 0 0 0\nbackground 1 0 0\nsettings shading diffuse\n"
        f"model quad {name}.gltf\ninstance quad\nlight directional direction 0 0 -1 intensity 0.8\n")
PY
# the left and the right half's middle pixels (32 pixels across x 0..2), row 16
px() { python3 tests/tools/pngpixel.py "$1" 8 16 24 16 | tr '\n' '|'; }
for s in metal plain; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 32 --height 32 --aa 1 -o "$dir/$s.png" --quiet >"$dir/$s.log" 2>&1 ||
        fail "render $s: $(cat "$dir/$s.log")"
done
python3 - "$(px "$dir/metal.png")" "$(px "$dir/plain.png")" <<'PY' || fail "metal: $(px "$dir/metal.png"), plain: $(px "$dir/plain.png")"
import sys
(lr, lg, lb), (rr, rg, rb) = [tuple(map(int, p.split())) for p in sys.argv[1].strip("|").split("|")]
plain = [tuple(map(int, p.split())) for p in sys.argv[2].strip("|").split("|")]
ok = lr > 200 and lg < 30 and lb < 30           # the mirror: the red background
ok = ok and rg > 150 and abs(rr - rg) < 5        # not metal: lit white, no red
ok = ok and all(p[1] > 150 and abs(p[0] - p[1]) < 5 for p in plain)  # no texture: diffuse both
sys.exit(0 if ok else 1)
PY
for p in scalar sse avx2 avx512; do
    "$BIN/lanray-render" "$dir/metal.scene" --width 32 --height 32 --aa 1 --simd "$p" -o "$dir/metal-$p.png" --quiet \
        >/dev/null 2>&1 || continue # a path this CPU or build lacks
    cmp -s "$dir/metal.png" "$dir/metal-$p.png" || fail "the $p path renders the metal-roughness texture differently"
done
"$BIN/obj2tmd" "$dir/metal.gltf" "$dir/metal.tmd" >"$dir/tmd.log" 2>&1 || fail "obj2tmd: $(cat "$dir/tmd.log")"
sed 's/metal.gltf/metal.tmd/' "$dir/metal.scene" >"$dir/tmd.scene"
"$BIN/lanray-render" "$dir/tmd.scene" --width 32 --height 32 --aa 1 -o "$dir/tmd.png" --quiet >/dev/null 2>&1 ||
    fail "render tmd"
cmp -s "$dir/metal.png" "$dir/tmd.png" || fail "the .tmd's metal-roughness texture renders differently from the glTF's"
"$BIN/lanray-render" "$dir/metal.scene" --width 64 --height 64 -o "$dir/ref.png" --quiet >/dev/null 2>&1 ||
    fail "reference"
verify_distributed metalmap "$dir/metal.scene" "$dir/ref.png" "of the metal-roughness texture"
echo "metalmap: a glTF metallicRoughnessTexture makes a surface metal where its blue says, on every SIMD path, in a .tmd and through a server"
