#!/usr/bin/env bash
# Cutouts: a quad whose material has a mask (MTL map_d, a grey PNG; glTF
# alphaMode MASK, its base colour's alpha) is not there where the mask is
# under the cutoff.  The quad spans x 0..2 at z = 0, its left half a hole;
# a red plane at z = -1 behind it; a directional lamp whose shadows move
# +2 in x.  Looked at straight on (orthographic): through the hole the lit
# plane; the solid half white; the plane's shadow of the hole (x 2..3) lit,
# of the solid half (x 3..4) dark.  Without map_d the hole is white and
# its shadow dark, so a mask that does nothing fails.  The OBJ's cut
# triangles are fewer than half of its own (the glTF's are all of it), so
# a SIMD path walks them apart from the wide tree.  Every SIMD path
# gives the same bytes, a .tmd of the OBJ the OBJ's, and a server with a
# client lanray-render's.
set -u
source tests/tools/server-lib.sh
python3 - "$dir" <<'PY'
import sys
sys.path.insert(0, "tests/tools")
from quads import png, gltf_quad
d = sys.argv[1]
# 8 x 2: the left half black (a hole), the right half white; the colour white
open(f"{d}/mask.png", "wb").write(png(8, 2, [[0] * 12 + [255] * 12] * 2))
open(f"{d}/white.png", "wb").write(png(8, 2, [[255] * 24] * 2))
rgba = png(8, 2, [sum(([255, 255, 255, 0 if x < 4 else 255] for x in range(8)), [])] * 2, 6)
quad = "v 0 -1 0\nv 2 -1 0\nv 2 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
# and, out of view, three solid triangles: the cut ones are fewer than half,
# so on a SIMD path they go apart from the wide tree (model_cut.c)
wall = "v 0 -5 0\nv 2 -5 0\nv 2 -4 0\nv 0 -4 0\nusemtl wall\nf 5/1 6/2 7/3\nf 5/1 7/3 8/4\nf 5/1 6/2 8/4\n"
for name, extra in (("cut", "map_d mask.png\n"), ("solid", "")):
    open(f"{d}/{name}.mtl", "w").write("newmtl leaf\nKd 1 1 1\nmap_Kd white.png\n" + extra + "newmtl wall\nKd 1 1 1\n")
    open(f"{d}/{name}.obj", "w").write(f"mtllib {name}.mtl\n{quad}usemtl leaf\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n{wall}")
gltf_quad(f"{d}/cut.gltf", {"alphaMode": "MASK", "alphaCutoff": 0.5,
                            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}, [rgba])
for name in ("cut", "solid", "gltf"):
    model = "cut.gltf" if name == "gltf" else f"{name}.obj"
    open(f"{d}/{name}.scene", "w").write(
        "camera position 2 0 5 lookat 2 0 0 ortho 4\nambient 0.1 0.1 0.1\nbackground 0 0 0\n"
        "material red diffuse 1 0 0\nplane point 0 0 -1 normal 0 0 1 material red\n"
        f"model quad {model}\ninstance quad\nlight directional direction 2 0 -1 intensity 1\n")
PY
# pixel columns at x = 0.5, 1.5, 2.5, 3.5 (64 pixels across 4 units, from x = 0), row 16
px() { python3 tests/tools/pngpixel.py "$1" 8 16 24 16 40 16 56 16 | tr '\n' '|'; }
bright() { # "r g b|..." -> one letter a pixel: W white, R lit red, r dark red
    tr '|' '\n' <<<"$1" | awk 'NF == 3 { print ($2 > 128 ? "W" : $1 > 128 ? "R" : "r") }' | tr -d '\n'
}
for s in cut solid gltf; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 64 --height 32 --aa 1 -o "$dir/$s.png" --quiet >"$dir/$s.log" 2>&1 ||
        fail "render $s: $(cat "$dir/$s.log")"
done
got=$(bright "$(px "$dir/solid.png")")
[ "$got" = WWrr ] || fail "without a mask: hole, solid, their shadows should read WWrr, got $got ($(px "$dir/solid.png"))"
for s in cut gltf; do
    got=$(bright "$(px "$dir/$s.png")")
    [ "$got" = RWRr ] || fail "$s: hole, solid, their shadows should read RWRr, got $got ($(px "$dir/$s.png"))"
done
same_on_simd_paths "$dir/cut.scene" "$dir/cut.png" 64 32 "the cutout"
# through a .tmd: the mask and its texture travel in the file
same_through_tmd "$dir/cut.obj" "$dir/cut.scene" "$dir/cut.png" 64 32 "cutout"
"$BIN/lanray-render" "$dir/gltf.scene" --width 64 --height 64 -o "$dir/gltf-ref.png" --quiet >/dev/null 2>&1 || fail "reference"
verify_distributed cutout "$dir/gltf.scene" "$dir/gltf-ref.png" "of the glTF cutout"
echo "cutout: MTL map_d and glTF MASK holes show what is behind and let light through, on every SIMD path, in a .tmd and through a server"
