#!/usr/bin/env bash
# Textured models: MTL map_Kd with a PNG and a JPEG texture (and -s/-o
# placement) travels in the .tmd (version 2) and shows the texture's colours
# where expected, checked pixel by pixel; a missing texture is a warning and
# leaves the material untextured; a distributed frame of the textured model
# is bit-identical to lanray-render's (the clients get the texture inside
# the model asset); a reader meets an unknown .tmd version with a clear error.
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
check placed "0 255 0|0 255 0|255 255 255|255 255 255|" 0 # -s 0.5 1 -o 0.5 0: the right half
check missing "255 255 255|255 255 255|255 255 255|255 255 255|" 0
grep -q "obj2tmd: warning: $D/quad-missing.obj: material 'tex': texture not read" "$dir/missing.err" || fail "missing texture warning: $(cat "$dir/missing.err")"
# a model moved from the machine that wrote it: absolute Windows paths to its
# library and texture, names in another case; found by file name, textured
"$BIN/obj2tmd" tests/data/moved/crate.obj "$dir/quad.tmd" >"$dir/moved.log" 2>"$dir/moved.err" || fail "obj2tmd moved: $(cat "$dir/moved.err")"
grep -q "crate.obj:2: material library 'C:/Users/artist/My Models/Crate.MTL' not where the file says; using tests/data/moved/crate.mtl" "$dir/moved.err" &&
    grep -q "texture not where the library says; using tests/data/moved/quadrants.png" "$dir/moved.err" || fail "moved model warnings: $(cat "$dir/moved.err")"
"$BIN/lanray-render" "$dir/view.scene" --width 64 --height 64 -o "$dir/moved.png" --quiet >/dev/null 2>&1 || fail "render moved"
near "$(px "$dir/moved.png")" "255 0 0|0 255 0|0 0 255|255 255 255|" 0 || fail "moved model: quadrants $(px "$dir/moved.png")"
"$BIN/obj2tmd" --strict "$D/quad-missing.obj" "$dir/strict.tmd" >/dev/null 2>&1 && fail "--strict converted a model whose texture is missing"
# version 2 with textures, version 1 without
python3 -c "import struct,sys; print(struct.unpack_from('<I', open(sys.argv[1],'rb').read(), 8)[0])" "$dir/quad-png.tmd" | grep -qx 2 || fail "a textured .tmd is not version 2"
python3 -c "import struct,sys; print(struct.unpack_from('<I', open(sys.argv[1],'rb').read(), 8)[0])" "$dir/quad-missing.tmd" | grep -qx 1 || fail "an untextured .tmd is not version 1"
# a version this build does not know
python3 -c "
import sys
d = bytearray(open(sys.argv[1], 'rb').read()); d[8] = 5
open(sys.argv[2], 'wb').write(d)" "$dir/quad-png.tmd" "$dir/quad.tmd"
err=$("$BIN/lanray-render" "$dir/view.scene" --width 8 --height 8 -o "$dir/v4.png" 2>&1); [ $? -eq 1 ] || fail "version 5 accepted"
grep -q "format version 5, this build reads versions 1 to 4" <<<"$err" || fail "version message: $err"
# distributed: the textured model through a server and a client, bit for bit
cp "$dir/quad-png.tmd" "$dir/quad.tmd"
"$BIN/lanray-render" "$dir/view.scene" --width 64 --height 64 -o "$dir/ref.png" --quiet >/dev/null 2>&1 || fail "reference render"
verify_distributed tex "$dir/view.scene" "$dir/ref.png" "of the textured model"
echo "textured: PNG and JPEG textures in .tmd models, placed and missing, local and distributed"
