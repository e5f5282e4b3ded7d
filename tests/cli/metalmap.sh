#!/usr/bin/env bash
# Metal-roughness textures: a glTF quad (x 0..2, y -1..1 at z = 0, facing
# +z) of base colour white, metallicFactor 1, roughnessFactor 1, whose
# metallicRoughnessTexture is 4 x 1 texels: the left half blue 255 green
# 0 (metal, smooth: a mirror), the right half blue 0 (not metal).  Seen
# straight on (orthographic) under a lamp from the front, before a red
# background: the left half mirrors the red background, the right half is
# lit white-grey.  Without the texture, or with one that cannot be read
# (a warning), the material stays diffuse (glTF's defaults: white), both
# halves grey.  A metal by its factors alone (metallicFactor 1,
# roughnessFactor 0, no metal-roughness texture) whose base colour is a
# texture, yellow on the left and cyan on the right, mirrors the red
# background tinted by it: red on the left, black on the right (its mirror
# was the base colour factor's, white: red on both).  A metal over glass
# (metallicFactor 0.5, KHR_materials_transmission 0.5) loads and shows its
# mirror, its glass and its diffuse share.  Every SIMD path gives the same
# bytes, a .tmd the glTF's, and a server with a client lanray-render's.
set -u
source tests/tools/server-lib.sh
python3 - "$dir" <<'PY'
import sys
sys.path.insert(0, "tests/tools")
from quads import png, gltf_quad
d = sys.argv[1]
mr = png(4, 1, [[0, 0, 255] * 2 + [0, 255, 0] * 2])
for name, pbr, image in (("metal", {"metallicRoughnessTexture": {"index": 0}}, mr), ("plain", {}, mr),
                         ("broken", {"metallicRoughnessTexture": {"index": 0}}, b"not a PNG"),
                         ("tinted", {"baseColorTexture": {"index": 0}, "metallicFactor": 1, "roughnessFactor": 0},
                          png(4, 1, [[255, 255, 0] * 2 + [0, 255, 255] * 2])),
                         ("coated", {"baseColorFactor": [0.8, 1, 0.6, 1], "metallicFactor": 0.5, "roughnessFactor": 0},
                          None)):
    ext = {"KHR_materials_transmission": {"transmissionFactor": 0.5}} if name == "coated" else {}
    gltf_quad(f"{d}/{name}.gltf", {"pbrMetallicRoughness": pbr, **({"extensions": ext} if ext else {})},
              [image] if image else [], normals=True,
              sampler={"wrapS": 33071, "wrapT": 33071})
    open(f"{d}/{name}.scene", "w").write(
        "camera position 1 0 5 lookat 1 0 0 ortho 2\nambient 0 0 0\nbackground 1 0 0\nsettings shading diffuse\n"
        f"model quad {name}.gltf\ninstance quad\nlight directional direction 0 0 -1 intensity 0.8\n")
PY
# the left and the right half's middle pixels (32 pixels across x 0..2), row 16
px() { python3 tests/tools/pngpixel.py "$1" 8 16 24 16 | tr '\n' '|'; }
for s in metal plain broken tinted coated; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 32 --height 32 --aa 1 -o "$dir/$s.png" --quiet >"$dir/$s.log" 2>&1 ||
        fail "render $s: $(cat "$dir/$s.log")"
done
"$BIN/obj2tmd" "$dir/broken.gltf" "$dir/broken.tmd" >"$dir/broken-tmd.log" 2>&1 || fail "obj2tmd of the broken one"
grep -q "warning: .*embedded image 0" "$dir/broken-tmd.log" || fail "a broken metal-roughness texture gives no warning"
cmp -s "$dir/plain.png" "$dir/broken.png" || fail "a metal-roughness texture that cannot be read does not leave the material diffuse"
python3 - "$(px "$dir/metal.png")" "$(px "$dir/plain.png")" <<'PY' || fail "metal: $(px "$dir/metal.png"), plain: $(px "$dir/plain.png")"
import sys
(lr, lg, lb), (rr, rg, rb) = [tuple(map(int, p.split())) for p in sys.argv[1].strip("|").split("|")]
plain = [tuple(map(int, p.split())) for p in sys.argv[2].strip("|").split("|")]
ok = lr > 200 and lg < 30 and lb < 30           # the mirror: the red background
ok = ok and rg > 150 and abs(rr - rg) < 5        # not metal: lit white, no red
ok = ok and all(p[1] > 150 and abs(p[0] - p[1]) < 5 for p in plain)  # no texture: diffuse both
sys.exit(0 if ok else 1)
PY
python3 - "$(px "$dir/tinted.png")" <<'PY' || fail "a factor metal with a base colour texture: $(px "$dir/tinted.png") (red, then black)"
import sys
(lr, lg, lb), (rr, rg, rb) = [tuple(map(int, p.split())) for p in sys.argv[1].strip("|").split("|")]
sys.exit(0 if lr > 200 and max(lg, lb) < 30 and max(rr, rg, rb) < 30 else 1)
PY
# metallic 0.5 over transmission 0.5 (it was refused when the scene
# loaded): a mirror of half the base colour (0.4 0.5 0.3) and glass that
# lets through a quarter of it both see the red background, a quarter
# scatters the light: red 0.4 + 0.19 + 0.16 and more, green 0.2 (code 124),
# blue 0.12 (97)
python3 - "$(px "$dir/coated.png")" <<'PY' || fail "metal over glass: $(px "$dir/coated.png") (red > 200, green 110..140, blue 85..110)"
import sys
for p in sys.argv[1].strip("|").split("|"):
    r, g, b = map(int, p.split())
    if not (r > 200 and 110 <= g <= 140 and 85 <= b <= 110):
        sys.exit(1)
PY
same_through_tmd "$dir/coated.gltf" "$dir/coated.scene" "$dir/coated.png" 32 32 "metal over glass"
same_on_simd_paths "$dir/tinted.scene" "$dir/tinted.png" 32 32 "the factor metal's tint"
same_through_tmd "$dir/tinted.gltf" "$dir/tinted.scene" "$dir/tinted.png" 32 32 "factor metal's tint"
same_on_simd_paths "$dir/metal.scene" "$dir/metal.png" 32 32 "the metal-roughness texture"
same_through_tmd "$dir/metal.gltf" "$dir/metal.scene" "$dir/metal.png" 32 32 "metal-roughness texture"
"$BIN/lanray-render" "$dir/metal.scene" --width 64 --height 64 --aa 1 -o "$dir/ref.png" --quiet >/dev/null 2>&1 ||
    fail "reference"
verify_distributed metalmap "$dir/metal.scene" "$dir/ref.png" "of the metal-roughness texture"
echo "metalmap: a glTF metallicRoughnessTexture makes a surface metal where its blue says, and a factor metal mirrors through its base colour texture, on every SIMD path, in a .tmd and through a server; a metal over glass (metallic with transmission) shows both ($(px "$dir/coated.png"))"
