#!/usr/bin/env bash
# Occlusion textures: a glTF quad (x 0..2, y -1..1 at z = 0) of base
# colour white whose occlusionTexture is 4 x 1 texels, red 0 on the left
# half and 255 on the right, seen straight on (orthographic) with no lamp:
# the ambient light alone (0.5).  Strength 1: the left half black, the
# right half the ambient's white (code 188); strength 0.5: the left half
# half the ambient (code 137); without the texture both halves 188.
# Every SIMD path gives the same bytes, a .tmd the glTF's, and a server
# with a client lanray-render's.
set -u
source tests/tools/server-lib.sh
python3 - "$dir" <<'PY'
import sys
sys.path.insert(0, "tests/tools")
from quads import png, gltf_quad
d = sys.argv[1]
ao = png(4, 1, [[0, 0, 0] * 2 + [255, 255, 255] * 2])
for name, occ in (("full", {"index": 0}), ("half", {"index": 0, "strength": 0.5}), ("none", None)):
    mat = {"pbrMetallicRoughness": {"metallicFactor": 0}}
    if occ:
        mat["occlusionTexture"] = occ
    gltf_quad(f"{d}/{name}.gltf", mat, [ao], sampler={"wrapS": 33071, "wrapT": 33071})
    open(f"{d}/{name}.scene", "w").write(
        "camera position 1 0 5 lookat 1 0 0 ortho 2\nambient 0.5 0.5 0.5\nbackground 0 0 0\n"
        f"model quad {name}.gltf\ninstance quad\n")
PY
# the left and the right half's middle pixels (32 pixels across x 0..2), row 16: their red
px() { python3 tests/tools/pngpixel.py "$1" 8 16 24 16 | awk '{ printf "%s ", $1 }'; }
for s in full half none; do
    "$BIN/lanray-render" "$dir/$s.scene" --width 32 --height 32 --aa 1 -o "$dir/$s.png" --quiet >"$dir/$s.log" 2>&1 ||
        fail "render $s: $(cat "$dir/$s.log")"
done
[ "$(px "$dir/full.png")" = "0 188 " ] || fail "strength 1: halves $(px "$dir/full.png"), not black and the ambient's"
[ "$(px "$dir/half.png")" = "137 188 " ] || fail "strength 0.5: halves $(px "$dir/half.png"), not half and whole"
[ "$(px "$dir/none.png")" = "188 188 " ] || fail "no occlusion texture: halves $(px "$dir/none.png")"
same_on_simd_paths "$dir/full.scene" "$dir/full.png" 32 32 "the occlusion texture"
same_through_tmd "$dir/full.gltf" "$dir/full.scene" "$dir/full.png" 32 32 "occlusion texture"
"$BIN/lanray-render" "$dir/full.scene" --width 64 --height 64 -o "$dir/ref.png" --quiet >/dev/null 2>&1 || fail "reference"
verify_distributed occlusion "$dir/full.scene" "$dir/ref.png" "of the occlusion texture"
echo "occlusion: a glTF occlusionTexture darkens the ambient light as its red and strength say, on every SIMD path, in a .tmd and through a server"
