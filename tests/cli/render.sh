#!/usr/bin/env bash
# lanray-render: the default scene with no arguments, a scene file, and errors;
# the timing line names the models' BVH kinds.
set -u
BIN=${BIN:-bin}
root=$(pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# no arguments: the built-in scene, written to lanray.png in the current directory
out=$(cd "$dir" && "$root/$BIN/lanray-render" --threads 2) || fail "default render failed: $out"
[ "$(head -c 8 "$dir/lanray.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "lanray.png is not a PNG"
grep -q "1024x768 .* Mrays/s" <<<"$out" || fail "no timing line: $out"
# the timing line names the trees the models have: a .tmd keeps the kind it
# was built with (the line said the --bvh default, sah, for an MST file)
"$BIN/obj2tmd" --bvh mst --quiet models/cube.obj "$dir/cube-mst.tmd" >/dev/null || fail "obj2tmd --bvh mst"
line=$("$BIN/lanray-render" "$dir/cube-mst.tmd" --width 8 --height 6 -o "$dir/c.png" --quiet) || fail "render an MST .tmd"
grep -q " bvh mst threads" <<<"$line" || fail "an MST .tmd's line: $line"
line=$("$BIN/lanray-render" "$dir/cube-mst.tmd" --bvh sbt --width 8 --height 6 -o "$dir/c.png" --quiet) || fail "rebuilt"
grep -q " bvh sbt threads" <<<"$line" || fail "an MST .tmd rebuilt with --bvh sbt: $line"

# what the PNG's numbers are: sRGB (sRGB chunk, with gAMA 45455 for older readers), or linear with --linear
chunks() { python3 -c '
import struct, sys
d = open(sys.argv[1], "rb").read()
i = 8
while i < len(d):
    n, t = struct.unpack(">I4s", d[i:i + 8])
    body = d[i + 8:i + 8 + n]
    if t in (b"sRGB", b"gAMA"):
        print(t.decode(), int.from_bytes(body, "big"))
    i += 12 + n' "$1" | tr '\n' ' '; }
[ "$(chunks "$dir/lanray.png")" = "gAMA 45455 sRGB 0 " ] || fail "default PNG chunks: $(chunks "$dir/lanray.png")"
"$BIN/lanray-render" --width 8 --height 8 --linear -o "$dir/lin.png" --quiet >/dev/null || fail "--linear render"
[ "$(chunks "$dir/lin.png")" = "gAMA 100000 " ] || fail "linear PNG chunks: $(chunks "$dir/lin.png")"

# a scene file to PPM at a given size: exact size of header plus pixels
"$BIN/lanray-render" models/example.scene -o "$dir/ex.ppm" --width 33 --height 17 --aa 2 --quiet >/dev/null || fail "scene render"
head -c 15 "$dir/ex.ppm" | grep -q "P6" || fail "not a PPM"
[ "$(stat -c %s "$dir/ex.ppm")" -eq $((13 + 33 * 17 * 3)) ] || fail "PPM size $(stat -c %s "$dir/ex.ppm")"
"$BIN/lanray-render" models/example.scene -o "$dir/a.ppm" --width 1 --height 1 --aa adaptive:3 --bvh mst --quiet >/dev/null || fail "1x1 adaptive mst"

# errors: a bad scene names file and line; nothing is written
printf 'camera position 0 0 5 lookat 0 0 0\nsphere centre 0 0 0 radius nope\n' >"$dir/bad.scene"
err=$("$BIN/lanray-render" "$dir/bad.scene" -o "$dir/bad.png" 2>&1); [ $? -eq 1 ] || fail "bad scene should exit 1"
grep -q "bad.scene:2: 'radius' of sphere expects 1 finite number, got 'nope'" <<<"$err" || fail "message: $err"
[ ! -e "$dir/bad.png" ] || fail "image written for a bad scene"
"$BIN/lanray-render" --aa 33 2>/dev/null; [ $? -eq 2 ] || fail "--aa 33 should exit 2"
"$BIN/lanray-render" --bogus 2>/dev/null; [ $? -eq 2 ] || fail "unknown option should exit 2"
err=$("$BIN/lanray-render" -o "$dir/x.gif" --width 4 --height 4 2>&1); [ $? -eq 2 ] || fail "gif should exit 2"
grep -q "unknown image format" <<<"$err" || fail "format message: $err"
exit 0
