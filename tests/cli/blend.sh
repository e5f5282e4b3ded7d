#!/usr/bin/env bash
# glTF alphaMode BLEND with an alpha texture: the surface is a see-through
# blend of its texels' alpha (before 2026-11-29 the texture's alpha was
# not read: the whole quad came out solid).  A quad spans x 0..2 at z = 0,
# its texture's columns (u across) of alpha 255, 128, 0 and 255 over white;
# a red plane at z = -1 behind it; a directional lamp whose shadows move
# +2 in x.  Looked at straight on (orthographic, linear output): x 0.25
# solid white; x 0.75 half white, half the lit plane (the quad keeps half
# of its own light, the plane's light through it half); x 1.25 a hole (the
# lit plane); on the plane, x 2.75 in the half-alpha column's shadow at
# half its light, x 3.25 in the hole's shadow lit whole, x 3.75 in the
# solid column's shadow dark.  An alpha texture without alpha (an RGB
# image) leaves BLEND and MASK materials solid (before, the MASK cut its
# dark texels as an MTL map_d's grey level would).  Every SIMD path gives
# the same bytes, a .tmd of the glTF the glTF's, and a server with a client
# lanray-render's.
set -u
source tests/tools/server-lib.sh
python3 - "$dir" <<'PY'
import sys
sys.path.insert(0, "tests/tools")
from quads import png, gltf_quad
d = sys.argv[1]
alphas = [255, 128, 0, 255]
rgba = png(4, 1, [sum(([255, 255, 255, a] for a in alphas), [])], 6)
grey = png(4, 1, [[20] * 12])  # dark, and no alpha
nearest = {"magFilter": 9728, "minFilter": 9728}
gltf_quad(f"{d}/blend.gltf", {"alphaMode": "BLEND",
                              "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
          [rgba], sampler=nearest)
for mode in ("BLEND", "MASK"):
    gltf_quad(f"{d}/{mode.lower()}-rgb.gltf", {"alphaMode": mode, "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicFactor": 0}}, [grey], sampler=nearest)
for name in ("blend", "blend-rgb", "mask-rgb"):
    open(f"{d}/{name}.scene", "w").write(
        "camera position 2 0 5 lookat 2 0 0 ortho 4\nambient 0 0 0\nbackground 0 0 0\n"
        "material red diffuse 1 0 0\nplane point 0 0 -1 normal 0 0 1 material red\n"
        f"model quad {name}.gltf\ninstance quad\nlight directional direction 2 0 -1 intensity 1\n")
PY
# pixel columns at x = 0.25, 0.75, 1.25, 2.75, 3.25, 3.75 (64 pixels across 4 units), row 16
px() { python3 tests/tools/pngpixel.py "$1" 4 16 12 16 20 16 44 16 52 16 60 16 | tr '\n' ' '; }
for s in blend blend-rgb mask-rgb; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 64 --height 32 --aa 1 --linear -o "$dir/$s.png" --quiet \
        >"$dir/$s.log" 2>&1 || fail "render $s: $(cat "$dir/$s.log")"
done
got=$(px "$dir/blend.png")
python3 - "$got" <<'PY' || fail "the blend's pixels: $got"
import sys
v = list(map(int, sys.argv[1].split()))
p = [tuple(v[i:i + 3]) for i in range(0, len(v), 3)]
lit = p[2][0]  # the lit plane through the hole
ok = (lit > 100 and p[2][1] < 5                       # the hole: the lit red plane
      and min(p[0]) > 100                             # solid white
      and abs(p[1][1] - p[0][1] * 128 / 255) <= 3     # half of the white quad's own light
      and abs(p[1][0] - (p[0][0] * 128 / 255 + lit * 127 / 255)) <= 3  # and half the plane's
      and abs(p[3][0] - lit * 127 / 255) <= 3         # the half column's shadow: half lit
      and abs(p[4][0] - lit) <= 1                     # the hole's shadow: lit whole
      and p[5][0] < 5)                                # the solid column's shadow: dark
sys.exit(0 if ok else 1)
PY
for s in blend-rgb mask-rgb; do
    got=$(px "$dir/$s.png")
    set -- $got
    [ "$1" -le 5 ] && [ "$4" -le 5 ] && [ "$7" -le 5 ] && [ "${10}" -le 5 ] && [ "${13}" -le 5 ] && [ "${16}" -le 5 ] ||
        fail "$s: a texture without alpha should leave the quad solid (dark, its shadow dark): $got"
done
"$BIN/lanray-render" "$dir/blend.scene" --width 64 --height 32 --aa 1 -o "$dir/blend-1.png" --quiet >/dev/null 2>&1 ||
    fail "render blend"
same_on_simd_paths "$dir/blend.scene" "$dir/blend-1.png" 64 32 "the blend"
same_through_tmd "$dir/blend.gltf" "$dir/blend.scene" "$dir/blend-1.png" 64 32 "blend"
"$BIN/lanray-render" "$dir/blend.scene" --width 64 --height 64 -o "$dir/blend-ref.png" --quiet >/dev/null 2>&1 ||
    fail "reference"
verify_distributed blend "$dir/blend.scene" "$dir/blend-ref.png" "of the glTF blend"
echo "blend: a glTF BLEND's alpha texture blends it texel by texel (solid, half, a hole) and its shadows alike; textures without alpha leave BLEND and MASK solid; on every SIMD path, in a .tmd and through a server"
