#!/usr/bin/env bash
# Normal maps: a flat quad whose material has one (MTL norm; glTF
# normalTexture) is shaded as the map's normals say.  The quad spans x
# 0..2, y -1..1 at z = 0, facing +z, seen straight on (orthographic), lit
# by a directional lamp from +x and +z (45 degrees), diffuse shading.
# The OBJ's map is 4 x 1 texels: the left half's normal tilts 45 degrees
# towards +u (+x: facing the lamp, fully lit), the right half's towards -u
# (edge-on to it: the ambient term alone); without the map both halves
# take cos 45.  The glTF's map tilts towards +v (its green: glTF's "up",
# +y here), under a lamp from +y and +z: lit fully where it would be at
# cos 45 without.  A grey bump map (MTL bump -bm 1) is a height map: 8 x 1
# texels climbing 64 codes a texel over the left half and falling over the
# right, 1 unit high at white, over the quad's 2 units: the left half
# climbs at 45 degrees along +x (its normal leans away from the lamp: the
# ambient alone), the right half falls (towards it: fully lit).  Every
# SIMD path gives the same bytes, a .tmd of the OBJ the OBJ's, and a
# server with a client lanray-render's.
set -u
source tests/tools/server-lib.sh
python3 - "$dir" <<'PY'
import sys
sys.path.insert(0, "tests/tools")
from quads import png, gltf_quad
d = sys.argv[1]
# 45 degrees: (cos, sin) = 0.7071 -> code 218 (x), 38 for -0.7071; 128 is 0
open(f"{d}/lean.png", "wb").write(png(4, 1, [[218, 128, 218] * 2 + [38, 128, 218] * 2]))
quad = "v 0 -1 0\nv 2 -1 0\nv 2 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
open(f"{d}/heights.png", "wb").write(png(8, 1, [sum(([c] * 3 for c in (0, 64, 128, 192, 192, 128, 64, 0)), [])]))
for name, extra in (("bumpy", "norm lean.png\n"), ("flat", ""), ("hills", "bump -bm 1 heights.png\n")):
    open(f"{d}/{name}.mtl", "w").write("newmtl quad\nKd 1 1 1\n" + extra)
    open(f"{d}/{name}.obj", "w").write(f"mtllib {name}.mtl\n{quad}usemtl quad\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
up = png(1, 1, [[128, 218, 218]])
for name, mat in (("up", {"normalTexture": {"index": 0}}), ("level", {})):
    mat["pbrMetallicRoughness"] = {"metallicFactor": 0}
    gltf_quad(f"{d}/{name}.gltf", mat, [up], normals=True)
for name, model, lamp in (("bumpy", "bumpy.obj", "-1 0 -1"), ("flat", "flat.obj", "-1 0 -1"), ("hills", "hills.obj", "-1 0 -1"),
                          ("up", "up.gltf", "0 -1 -1"), ("level", "level.gltf", "0 -1 -1")):
    open(f"{d}/{name}.scene", "w").write(
        "camera position 1 0 5 lookat 1 0 0 ortho 2\nambient 0.1 0.1 0.1\nbackground 0 0 0\n"
        f"settings shading diffuse\nmodel quad {model}\ninstance quad\nlight directional direction {lamp} intensity 1\n")
PY
# the left and the right half's middle pixels (32 pixels across x 0..2), row 16: their red
px() { python3 tests/tools/pngpixel.py "$1" 8 16 24 16 | awk '{ printf "%s ", $1 }'; }
for s in bumpy flat hills up level; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 32 --height 32 --aa 1 -o "$dir/$s.png" --quiet >"$dir/$s.log" 2>&1 ||
        fail "render $s: $(cat "$dir/$s.log")"
done
# in sRGB codes: fully lit (1 + 0.1 ambient) 255; cos 45 (0.81) 232; the ambient alone (0.1) 89
read -r l r <<<"$(px "$dir/bumpy.png")"
[ "$l" -ge 250 ] && [ "$r" -le 95 ] || fail "the OBJ's normal map: left and right halves $l and $r, not lit and dark"
read -r l r <<<"$(px "$dir/flat.png")"
[ "$l" -ge 225 ] && [ "$l" -le 238 ] && [ "$l" = "$r" ] || fail "without a map: halves $l and $r, not both at cos 45"
read -r l r <<<"$(px "$dir/hills.png")"
[ "$l" -le 95 ] && [ "$r" -ge 250 ] || fail "the OBJ's height map: left and right halves $l and $r, not dark and lit"
grep -q "height map" "$dir/hills.log" && fail "the height map was warned about: $(cat "$dir/hills.log")"
read -r l r <<<"$(px "$dir/up.png")"
[ "$l" -ge 250 ] && [ "$r" -ge 250 ] || fail "the glTF's normal map (green: up): $l and $r, not lit"
read -r l r <<<"$(px "$dir/level.png")"
[ "$l" -ge 225 ] && [ "$l" -le 238 ] || fail "the glTF without a map: $l, not at cos 45"
same_on_simd_paths "$dir/bumpy.scene" "$dir/bumpy.png" 32 32 "the normal map"
same_through_tmd "$dir/bumpy.obj" "$dir/bumpy.scene" "$dir/bumpy.png" 32 32 "normal map"
same_on_simd_paths "$dir/hills.scene" "$dir/hills.png" 32 32 "the height map"
same_through_tmd "$dir/hills.obj" "$dir/hills.scene" "$dir/hills.png" 32 32 "height map"
"$BIN/lanray-render" "$dir/up.scene" --width 64 --height 64 -o "$dir/up-ref.png" --quiet >/dev/null 2>&1 ||
    fail "reference"
verify_distributed normalmap "$dir/up.scene" "$dir/up-ref.png" "of the glTF normal map"
"$BIN/lanray-render" "$dir/hills.scene" --width 64 --height 64 -o "$dir/hills-ref.png" --quiet >/dev/null 2>&1 ||
    fail "height map reference"
verify_distributed heights "$dir/hills.scene" "$dir/hills-ref.png" "of the height map"
echo "normalmap: MTL norm and glTF normalTexture tilt the shading normal as their texels say, and a grey MTL bump map bumps it as its heights would (halves $(px "$dir/hills.png")), on every SIMD path, in a .tmd and through a server"
