#!/usr/bin/env bash
# Emission textures: a quad whose material glows by a texture (MTL map_Ke,
# here without Ke: the texture alone; glTF emissiveTexture times
# emissiveFactor) emits where its texels are bright.  The quad spans x
# 0..2, y -1..1 at z = 0, black (no diffuse colour), seen straight on
# (orthographic), no lamp; its texture is 4 x 1 texels, the left half
# black and the right half white, clamped at the edges.  Whitted: the left half dark, the right
# half the emission (white; the glTF's factor 1 0.5 0: orange).  With
# map_Ke dropped the quad does not glow at all (Ke is not given).  The path integrator: a grey floor under the quad, lit
# by its bright half alone: brighter in front of the right half than in
# front of the left.  Every SIMD path gives the same bytes, a .tmd of the OBJ the OBJ's,
# and a server with a client lanray-render's (path-traced).
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
half = png(4, 1, [[0, 0, 0] * 2 + [255, 255, 255] * 2])
open(f"{d}/half.png", "wb").write(half)
quad = "v 0 -1 0\nv 2 -1 0\nv 2 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
open(f"{d}/glow.mtl", "w").write("newmtl panel\nKd 0 0 0\nmap_Ke -clamp on half.png\n")
open(f"{d}/glow.obj", "w").write(f"mtllib glow.mtl\n{quad}usemtl panel\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
pos = struct.pack("<12f", 0, -1, 0, 2, -1, 0, 2, 1, 0, 0, 1, 0)
uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)  # glTF's v runs down the image
idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
buf = pos + uv + idx
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                     {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, -1, 0], "max": [2, 1, 0]},
                   {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                   {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
     "images": [{"uri": "data:image/png;base64," + base64.b64encode(half).decode()}],
     "samplers": [{"wrapS": 33071, "wrapT": 33071}], "textures": [{"source": 0, "sampler": 0}],
     "materials": [{"emissiveFactor": [1, 0.5, 0], "emissiveTexture": {"index": 0},
                    "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}}]}
open(f"{d}/glow.gltf", "w").write(json.dumps(g))
head = "camera position 1 0 5 lookat 1 0 0 ortho 2\nambient 0 0 0\nbackground 0 0 0\n"
for name, model in (("obj", "glow.obj"), ("gltf", "glow.gltf")):
    open(f"{d}/{name}.scene", "w").write(f"{head}model quad {model}\ninstance quad\n")
# the path integrator: a grey floor just under the quad, seen from above and in front
open(f"{d}/floor.scene", "w").write(
    "camera position 1 1.5 5 lookat 1 -0.5 0 fov 40\nambient 0 0 0\nbackground 0 0 0\nsettings integrator path\n"
    "material grey diffuse 0.5 0.5 0.5\nplane point 0 -1 0 normal 0 1 0 material grey\n"
    "model quad glow.obj\ninstance quad\n")
PY
# the left and the right half's middle pixels (32 pixels across x 0..2), row 16
px() { python3 tests/tools/pngpixel.py "$1" 8 16 24 16 | tr '\n' '|'; }
for s in obj gltf; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 32 --height 32 --aa 1 -o "$dir/$s.png" --quiet >"$dir/$s.log" 2>&1 ||
        fail "render $s: $(cat "$dir/$s.log")"
done
[ "$(px "$dir/obj.png")" = "0 0 0|255 255 255|" ] || fail "map_Ke: halves $(px "$dir/obj.png"), not dark and white"
got=$(px "$dir/gltf.png")
[[ $got =~ ^0\ 0\ 0\|255\ 1[89][0-9]\ 0\|$ ]] || fail "glTF emissiveTexture: halves $got, not dark and orange"
# without the texture: map_Ke dropped, no Ke: no glow anywhere
sed -i 's/^map_Ke.*//' "$dir/glow.mtl"
"$BIN/lanray-render" "$dir/obj.scene" --width 32 --height 32 --aa 1 -o "$dir/plain.png" --quiet >/dev/null 2>&1 ||
    fail "render without map_Ke"
[ "$(px "$dir/plain.png")" = "0 0 0|0 0 0|" ] || fail "without map_Ke the quad glows: $(px "$dir/plain.png")"
printf 'newmtl panel\nKd 0 0 0\nmap_Ke -clamp on half.png\n' >"$dir/glow.mtl"
for p in scalar sse avx2 avx512; do
    "$BIN/lanray-render" "$dir/obj.scene" --width 32 --height 32 --aa 1 --simd "$p" -o "$dir/obj-$p.png" --quiet \
        >/dev/null 2>&1 || continue # a path this CPU or build lacks
    cmp -s "$dir/obj.png" "$dir/obj-$p.png" || fail "the $p path renders the emission texture differently"
done
"$BIN/obj2tmd" "$dir/glow.obj" "$dir/glow.tmd" >"$dir/tmd.log" 2>&1 || fail "obj2tmd: $(cat "$dir/tmd.log")"
sed 's/glow.obj/glow.tmd/' "$dir/obj.scene" >"$dir/tmd.scene"
"$BIN/lanray-render" "$dir/tmd.scene" --width 32 --height 32 --aa 1 -o "$dir/tmd.png" --quiet >/dev/null 2>&1 ||
    fail "render tmd"
cmp -s "$dir/obj.png" "$dir/tmd.png" || fail "the .tmd's emission texture renders differently from the OBJ's"
# path-traced: the floor in front of the bright half against in front of the dark one
"$BIN/lanray-render" "$dir/floor.scene" --width 64 --height 64 --aa 4 -o "$dir/floor.png" --quiet >/dev/null 2>&1 ||
    fail "render the floor"
python3 - "$dir/floor.png" <<'PY' || fail "the path-traced floor is not lit by the bright half alone"
import subprocess, sys
def lum(x, y):
    r, g, b = map(int, subprocess.check_output(["python3", "tests/tools/pngpixel.py", sys.argv[1], str(x), str(y)]).split())
    return r + g + b
# the floor just in front of the quad's two halves (pixels 14..22 and 38..46 across, rows 40..46)
left = sum(lum(x, y) for x in range(14, 22, 2) for y in range(40, 46, 2))
right = sum(lum(x, y) for x in range(38, 46, 2) for y in range(40, 46, 2))
if not right > 1.5 * left:
    sys.exit("floor in front of the dark half %d, of the bright half %d" % (left, right))
PY
"$BIN/lanray-render" "$dir/floor.scene" --width 64 --height 64 --aa 1 -o "$dir/floor-ref.png" --quiet >/dev/null 2>&1 ||
    fail "reference"
verify_distributed glow "$dir/floor.scene" "$dir/floor-ref.png" "of the path-traced emission texture"
echo "glow: MTL map_Ke and glTF emissiveTexture emit by their texels, in Whitted and path-traced frames, on every SIMD path, in a .tmd and through a server"
