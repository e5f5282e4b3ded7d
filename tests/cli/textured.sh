#!/usr/bin/env bash
# Textured models: MTL map_Kd with a PNG, JPEG, TGA and BMP texture (and -s/-o
# placement) travels in the .tmd (version 5 on: the image file's own bytes)
# and shows the texture's colours
# where expected, checked pixel by pixel; a missing texture is a warning and
# leaves the material untextured; a distributed frame of the textured model
# is bit-identical to lanray-render's (the clients get the texture inside
# the model asset); a reader meets an unknown .tmd version with a clear error,
# and a flipped bit with one that names corruption.  A model with a
# 1024 x 1024 texture makes a .tmd at most 1.5 times the OBJ, MTL and image
# together, for an incompressible PNG (3 MB) and a well-compressed one.
# glTF models bring their textures, embedded or beside them.
set -u
source tests/tools/server-lib.sh
D=tests/data/textured
cp "$D/view.scene" "$dir/"
px() { python3 tests/tools/pngpixel.py "$1" 16 16 48 16 16 48 48 48 | tr '\n' '|'; }
near() { # "r g b|..." against "r g b|...": every channel within $3 codes
    python3 - "$1" "$2" "$3" <<'PY'
import sys
a = [int(v) for v in sys.argv[1].replace("|", " ").split()]
b = [int(v) for v in sys.argv[2].replace("|", " ").split()]
sys.exit(0 if len(a) == len(b) and all(abs(x - y) <= int(sys.argv[3]) for x, y in zip(a, b)) else 1)
PY
}
check() { # variant, expected quadrant colours (top left, top right, bottom left, bottom right), tolerance
    "$BIN/obj2tmd" "$D/quad-$1.obj" "$dir/quad-$1.tmd" >"$dir/$1.log" 2>"$dir/$1.err" || fail "obj2tmd quad-$1: $(cat "$dir/$1.err")"
    cp "$dir/quad-$1.tmd" "$dir/quad.tmd"
    "$BIN/lanray-render" "$dir/view.scene" --width 64 --height 64 -o "$dir/$1.png" --quiet >/dev/null 2>&1 || fail "render quad-$1"
    got=$(px "$dir/$1.png")
    near "$got" "$2" "$3" || fail "quad-$1: quadrants $got, expected $2"
}
check png "255 0 0|0 255 0|0 0 255|255 255 255|" 0
check jpg "255 0 0|0 255 0|0 0 255|255 255 255|" 2 # JPEG is lossy: a code or two
check tga "255 0 0|0 255 0|0 0 255|255 255 255|" 0 # run-length coded, rows bottom first
check bmp "255 0 0|0 255 0|0 0 255|255 255 255|" 0
check placed "0 255 0|0 255 0|255 255 255|255 255 255|" 0 # -s 0.5 1 -o 0.5 0: the right half
check missing "255 255 255|255 255 255|255 255 255|255 255 255|" 0
grep -q "obj2tmd: warning: $D/quad-missing.obj: material 'tex': texture not read" "$dir/missing.err" || fail "missing texture warning: $(cat "$dir/missing.err")"
# the OBJ rendered or served straight (no obj2tmd) says so too; --quiet does not
"$BIN/lanray-render" "$D/quad-missing.obj" --width 16 --height 16 -o "$dir/straight.png" >/dev/null 2>"$dir/straight.err" ||
    fail "render quad-missing.obj: $(cat "$dir/straight.err")"
grep -q "^lanray-render: warning: $D/quad-missing.obj: material 'tex': texture not read" "$dir/straight.err" ||
    fail "lanray-render's missing texture warning: $(cat "$dir/straight.err")"
"$BIN/lanray-render" "$D/quad-missing.obj" --width 16 --height 16 -o "$dir/straight.png" --quiet >/dev/null 2>"$dir/straight.err"
[ -s "$dir/straight.err" ] && fail "--quiet printed: $(cat "$dir/straight.err")"
start_server served "$D/quad-missing.obj" --frames 1 --discard --width 16 --height 16
kill "$server_pid"
grep -q "^lanray-server: warning: $D/quad-missing.obj: material 'tex': texture not read" "$dir/served.err" ||
    fail "lanray-server's missing texture warning: $(cat "$dir/served.err")"
# a model moved from the machine that wrote it: absolute Windows paths to its
# library and texture, names in another case; found by file name, textured
"$BIN/obj2tmd" tests/data/moved/crate.obj "$dir/quad.tmd" >"$dir/moved.log" 2>"$dir/moved.err" || fail "obj2tmd moved: $(cat "$dir/moved.err")"
grep -q "crate.obj:2: material library 'C:/Users/artist/My Models/Crate.MTL' not where the file says; using tests/data/moved/crate.mtl" "$dir/moved.err" &&
    grep -q "texture not where the library says; using tests/data/moved/quadrants.png" "$dir/moved.err" || fail "moved model warnings: $(cat "$dir/moved.err")"
"$BIN/lanray-render" "$dir/view.scene" --width 64 --height 64 -o "$dir/moved.png" --quiet >/dev/null 2>&1 || fail "render moved"
near "$(px "$dir/moved.png")" "255 0 0|0 255 0|0 0 255|255 255 255|" 0 || fail "moved model: quadrants $(px "$dir/moved.png")"
"$BIN/obj2tmd" --strict "$D/quad-missing.obj" "$dir/strict.tmd" >/dev/null 2>&1 && fail "--strict converted a model whose texture is missing"
# the version written (6), textured or not
ver() { python3 -c "import struct,sys; print(struct.unpack_from('<I', open(sys.argv[1],'rb').read(), 8)[0])" "$1"; }
[ "$(ver "$dir/quad-png.tmd")" = 6 ] && [ "$(ver "$dir/quad-missing.tmd")" = 6 ] || fail "a .tmd is not version 6"
# a version this build does not know, and a flipped bit
python3 -c "
import sys
d = bytearray(open(sys.argv[1], 'rb').read()); d[8] = 7
open(sys.argv[2], 'wb').write(d)" "$dir/quad-png.tmd" "$dir/quad.tmd"
err=$("$BIN/lanray-render" "$dir/view.scene" --width 8 --height 8 -o "$dir/v7.png" 2>&1); [ $? -eq 1 ] || fail "version 7 accepted"
grep -q "format version 7, this build reads versions 1 to 6" <<<"$err" || fail "version message: $err"
for at in 100 300 -20; do
    python3 -c "
import sys
d = bytearray(open(sys.argv[1], 'rb').read()); d[int(sys.argv[3])] ^= 16
open(sys.argv[2], 'wb').write(d)" "$dir/quad-png.tmd" "$dir/quad.tmd" "$at"
    err=$("$BIN/lanray-render" "$dir/view.scene" --width 8 --height 8 -o "$dir/flip.png" 2>&1); [ $? -eq 1 ] || fail "a flipped bit at $at accepted"
    grep -q "quad.tmd: corrupt: checksum" <<<"$err" || fail "flipped bit message: $err"
done
[ -e "$dir/flip.png" ] && fail "an image written from a corrupt model"
# the size of a .tmd with a 1024 x 1024 texture against the files it came from
for kind in noise smooth; do
    python3 tests/tools/makepng.py "$dir/big-$kind.png" 1024 1024 "$kind"
    sed "s/quadrants.png/big-$kind.png/" "$D/quad-png.mtl" >"$dir/big-$kind.mtl"
    sed "s/quad-png.mtl/big-$kind.mtl/" "$D/quad-png.obj" >"$dir/big-$kind.obj"
    "$BIN/obj2tmd" "$dir/big-$kind.obj" "$dir/big-$kind.tmd" >/dev/null 2>"$dir/big.err" || fail "obj2tmd big-$kind: $(cat "$dir/big.err")"
    src=$(( $(stat -c %s "$dir/big-$kind.obj") + $(stat -c %s "$dir/big-$kind.mtl") + $(stat -c %s "$dir/big-$kind.png") ))
    tmd=$(stat -c %s "$dir/big-$kind.tmd")
    [ $(( tmd * 2 )) -le $(( src * 3 )) ] || fail "big-$kind: a .tmd of $tmd bytes from $src bytes of OBJ, MTL and PNG"
done
# glTF: a GLB with its PNG or JPEG embedded, a glTF with its PNG beside it
# or as a data URI, all textured as the OBJ is; magFilter NEAREST keeps the
# texels square; a missing or broken image is a warning naming it (an error
# with --strict) and leaves the material untextured
python3 tests/tools/gltftex.py "$dir/gltf" "$D/quadrants.png" "$D/quadrants.jpg" || fail "gltftex.py"
# (under --shading diffuse, as the view's `gview.scene`: a glTF's base is a
# dielectric whose clear coat reflects 4% of the white ambient light head
# on, white over every texel, where this test reads the texels themselves)
sed 's/^settings aa 1 shadows off$/settings aa 1 shadows off shading diffuse/' "$dir/view.scene" >"$dir/gview.scene"
grep -q "shading diffuse" "$dir/gview.scene" || fail "gview.scene: view.scene's settings line changed"
gltf() { # model, expected quadrants, tolerance
    "$BIN/obj2tmd" "$dir/gltf/$1" "$dir/quad.tmd" >"$dir/gltf.log" 2>"$dir/gltf.err" || fail "obj2tmd $1: $(cat "$dir/gltf.err")"
    grep -q "textures 1" "$dir/gltf.log" || fail "$1: no texture in the summary: $(cat "$dir/gltf.log")"
    [ -s "$dir/gltf.err" ] && fail "$1: warnings: $(cat "$dir/gltf.err")"
    "$BIN/lanray-render" "$dir/gview.scene" --width 64 --height 64 -o "$dir/gltf.png" --quiet >/dev/null 2>&1 || fail "render $1"
    near "$(px "$dir/gltf.png")" "$2" "$3" || fail "$1: quadrants $(px "$dir/gltf.png"), expected $2"
}
gltf quad.gltf "255 0 0|0 255 0|0 0 255|255 255 255|" 0
gltf quad.glb "255 0 0|0 255 0|0 0 255|255 255 255|" 0
gltf quad-jpg.glb "255 0 0|0 255 0|0 0 255|255 255 255|" 2
gltf quad-data.gltf "255 0 0|0 255 0|0 0 255|255 255 255|" 0
gltf quad.dae "255 0 0|0 255 0|0 0 255|255 255 255|" 0 # COLLADA, through the same importer
# magnified 4x, a pixel a quarter texel from the red-green edge: blended, or red
edge() { "$BIN/obj2tmd" "$dir/gltf/$1" "$dir/quad.tmd" >/dev/null 2>&1 &&
    "$BIN/lanray-render" "$dir/gview.scene" --width 256 --height 256 -o "$dir/edge.png" --quiet >/dev/null 2>&1 &&
    python3 tests/tools/pngpixel.py "$dir/edge.png" 127 64; }
[ "$(edge quad-nearest.glb)" = "255 0 0" ] || fail "magFilter NEAREST: $(edge quad-nearest.glb) at the edge, expected 255 0 0"
[ "$(edge quad.glb)" != "255 0 0" ] || fail "a smooth texture is sharp at the edge"
for bad in quad-missing.gltf:"texture 'nothere.png': not found beside the model" quad-broken.glb:"embedded image 0 (png): png:"; do
    m=${bad%%:*} why=${bad#*:}
    "$BIN/obj2tmd" "$dir/gltf/$m" "$dir/quad.tmd" >"$dir/gltf.log" 2>"$dir/gltf.err" || fail "obj2tmd $m: $(cat "$dir/gltf.err")"
    grep -q "obj2tmd: warning: $dir/gltf/$m: $why.*the material is untextured" "$dir/gltf.err" || fail "$m warning: $(cat "$dir/gltf.err")"
    grep -q "missing textures 1" "$dir/gltf.log" || fail "$m summary: $(cat "$dir/gltf.log")"
    "$BIN/obj2tmd" --strict "$dir/gltf/$m" "$dir/strict.tmd" >/dev/null 2>"$dir/gltf.err" && fail "--strict converted $m"
    grep -q "an error with --strict" "$dir/gltf.err" || fail "$m with --strict: $(cat "$dir/gltf.err")"
done
[ -e "$dir/strict.tmd" ] && fail "--strict left a file"
# a scene that names the GLB itself: converted on load, distributed bit for bit
sed 's/quad.tmd/gltf\/quad.glb/' "$dir/gview.scene" >"$dir/glb.scene"
"$BIN/lanray-render" "$dir/glb.scene" --width 64 --height 64 -o "$dir/glb-ref.png" --quiet >/dev/null 2>&1 || fail "render glb.scene"
near "$(px "$dir/glb-ref.png")" "255 0 0|0 255 0|0 0 255|255 255 255|" 0 || fail "glb.scene: quadrants $(px "$dir/glb-ref.png")"
verify_distributed glb "$dir/glb.scene" "$dir/glb-ref.png" "of the scene naming a GLB"
# distributed: the textured model through a server and a client, bit for bit
cp "$dir/quad-png.tmd" "$dir/quad.tmd"
"$BIN/lanray-render" "$dir/view.scene" --width 64 --height 64 -o "$dir/ref.png" --quiet >/dev/null 2>&1 || fail "reference render"
verify_distributed tex "$dir/view.scene" "$dir/ref.png" "of the textured model"
echo "textured: PNG, JPEG, TGA and BMP textures in .tmd models, placed and missing, local and distributed"
