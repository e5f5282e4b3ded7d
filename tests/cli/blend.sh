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
# the same quad black and emissive: the see-through share emits nothing
for name, e in (("emit", 0.5), ("emit1", 1)):
    gltf_quad(f"{d}/{name}.gltf", {"alphaMode": "BLEND", "emissiveFactor": [e, e, e], "pbrMetallicRoughness": {
        "baseColorFactor": [0, 0, 0, 1], "baseColorTexture": {"index": 0}, "metallicFactor": 0}}, [rgba], sampler=nearest)
gltf_quad(f"{d}/emithalf.gltf", {"alphaMode": "BLEND", "emissiveFactor": [0.5, 0.5, 0.5], "pbrMetallicRoughness": {
    "baseColorFactor": [0, 0, 0, 0.5], "metallicFactor": 0}}, [])  # half by its factor alone
for name in ("emit", "emithalf"):
    open(f"{d}/{name}.scene", "w").write("camera position 2 0 5 lookat 2 0 0 ortho 4\nambient 0 0 0\nbackground 0 0 0\n"
                                         f"model quad {name}.gltf\ninstance quad\n")
open(f"{d}/emitpath.scene", "w").write(
    "camera position 2 0 5 lookat 2 0 0 ortho 4\nambient 0 0 0\nbackground 0 0 0\nsettings integrator path depth 2\n"
    "material white diffuse 0.8 0.8 0.8\nplane point 0 0 -1 normal 0 0 1 material white\n"
    "model quad emit1.gltf\ninstance quad\n")
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
# an emissive blend (emission 0.5, linear codes): solid 128, the half
# column half of it, the hole nothing (and a blend by its factor 0.5
# alone, no texture, half); path-traced, the plane behind lit by
# it comes out alike whether the lamp is found by next-event estimation
# (emitters.c's glow_at) or by bounces (trace_surface_blend): the blocks
# behind the hole and the half column within 4% (before 2026-11-30 the
# see-through share emitted in full: both, and next-event estimation
# alone from the half column's)
"$BIN/lanray-render" "$dir/emit.scene" --width 64 --height 32 --aa 1 --linear -o "$dir/emit.png" --quiet \
    >"$dir/emit.log" 2>&1 || fail "render emit: $(cat "$dir/emit.log")"
got=$(px "$dir/emit.png")
set -- $got
[ "$1" -ge 125 ] && [ "$1" -le 130 ] && [ $((${4} * 2 - $1)) -ge -3 ] && [ $((${4} * 2 - $1)) -le 3 ] && [ "$7" -le 1 ] ||
    fail "an emissive blend: solid 128, half 64, the hole 0 expected: $got"
"$BIN/lanray-render" "$dir/emithalf.scene" --width 64 --height 32 --aa 1 --linear -o "$dir/emithalf.png" --quiet \
    >"$dir/emithalf.log" 2>&1 || fail "render emithalf: $(cat "$dir/emithalf.log")"
got=$(px "$dir/emithalf.png")
set -- $got
[ "$1" -ge 61 ] && [ "$1" -le 67 ] || fail "an emissive blend of alpha 0.5 by its factor: 64 expected: $got"
for how in nee bsdf; do
    "$BIN/lanray-render" "$dir/emitpath.scene" --width 64 --height 32 --aa 8 --emitter-sampling $how --linear \
        -o "$dir/emit-$how.png" --quiet >/dev/null 2>&1 || fail "render the lit plane ($how)"
done
python3 - "$dir/emit-nee.png" "$dir/emit-bsdf.png" <<'PY' || fail "the plane behind an emissive blend: NEE and bounces disagree"
import sys
sys.path.insert(0, "tests/tools")
from pngpixel import read
a, b = (read(f) for f in sys.argv[1:3])
def block(img, x0, x1):  # the red channel's mean over columns x0..x1, rows 8..23
    rows, ch = img
    return sum(rows[y][ch * x] for y in range(8, 24) for x in range(x0, x1)) / ((x1 - x0) * 16)
for x0, x1 in ((18, 24), (10, 14)):
    na, nb = block(a, x0, x1), block(b, x0, x1)
    print(f"columns {x0}..{x1}: nee {na:.1f}, bounces {nb:.1f}")
    if not (nb > 5 and abs(na - nb) <= 0.04 * nb):
        sys.exit(1)
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
echo "blend: a glTF BLEND's alpha texture blends it texel by texel (solid, half, a hole), its shadows and its emission alike (next-event estimation as bounces); textures without alpha leave BLEND and MASK solid; on every SIMD path, in a .tmd and through a server"
