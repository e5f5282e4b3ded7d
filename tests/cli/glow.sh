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
import sys
sys.path.insert(0, "tests/tools")
from quads import png, gltf_quad
d = sys.argv[1]
half = png(4, 1, [[0, 0, 0] * 2 + [255, 255, 255] * 2])
open(f"{d}/half.png", "wb").write(half)
quad = "v 0 -1 0\nv 2 -1 0\nv 2 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
open(f"{d}/glow.mtl", "w").write("newmtl panel\nKd 0 0 0\nmap_Ke -clamp on half.png\n")
open(f"{d}/glow.obj", "w").write(f"mtllib glow.mtl\n{quad}usemtl panel\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
gltf_quad(f"{d}/glow.gltf", {"emissiveFactor": [1, 0.5, 0], "emissiveTexture": {"index": 0},
                             "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}},
          [half], sampler={"wrapS": 33071, "wrapT": 33071})
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
same_on_simd_paths "$dir/obj.scene" "$dir/obj.png" 32 32 "the emission texture"
same_through_tmd "$dir/glow.obj" "$dir/obj.scene" "$dir/obj.png" 32 32 "emission texture"
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
