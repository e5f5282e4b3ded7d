#!/usr/bin/env bash
# obj2tmd on good and malformed OBJ files: summaries, exit codes, error
# messages with file and line, and no output file (nor temporary) on failure.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

for kind in sbt mst sah; do
    out=$("$BIN/obj2tmd" --bvh "$kind" models/cube.obj "$dir/cube-$kind.tmd") || fail "$kind conversion failed: $out"
    [ -s "$dir/cube-$kind.tmd" ] || fail "$kind: no output file"
    grep -q "triangles 12, degenerate dropped 0" <<<"$out" || fail "$kind summary: $out"
    grep -q "bvh $kind: .* depth [0-9]*, SAH cost" <<<"$out" || fail "$kind summary lacks the tree: $out"
    grep -q "attributes: uvs materials" <<<"$out" || fail "$kind attributes: $out"
done
"$BIN/obj2tmd" --bvh sbt --axis alternate --leaf 1 --smooth models/cube.obj "$dir/alt.tmd" >/dev/null || fail "options"
# a .tmd in: its tree built again with the options given, the same picture
# (the closest hit does not depend on the tree), textures and all
"$BIN/lanray-render" "$dir/cube-sah.tmd" --width 64 --height 48 --quiet -o "$dir/sah.png" >/dev/null || fail "render cube-sah"
for kind in sbt mst; do
    out=$("$BIN/obj2tmd" --bvh "$kind" "$dir/cube-sah.tmd" "$dir/again-$kind.tmd") || fail "rebuilding a .tmd ($kind): $out"
    grep -q "triangles 12 (a .tmd: its tree built again)" <<<"$out" && grep -q "bvh $kind: " <<<"$out" ||
        fail "rebuilt .tmd summary: $out"
    "$BIN/lanray-render" "$dir/again-$kind.tmd" --width 64 --height 48 --quiet -o "$dir/$kind.png" >/dev/null || fail "render $kind"
    cmp -s "$dir/$kind.png" "$dir/sah.png" || fail "a .tmd rebuilt with $kind renders differently"
done
# a glTF's emission strengths (read from its JSON: Assimp does not) are counted, the twins warned about
out=$("$BIN/obj2tmd" tests/data/gltf/strength.gltf "$dir/strength.tmd" 2>&1) || fail "strength.gltf: $out"
grep -q "emission strengths (KHR_materials_emissive_strength): 2 materials" <<<"$out" || fail "strengths summary: $out"
grep -q "emissive_strength) of 2 materials not applied" <<<"$out" || fail "the twins' warning: $out"
# and its speculars (KHR_materials_specular, also the JSON's): the coats they scale
out=$("$BIN/obj2tmd" tests/data/gltf/pbr.gltf "$dir/pbr.tmd" 2>&1) || fail "pbr.gltf: $out"
grep -q "speculars (KHR_materials_specular): 2 materials" <<<"$out" || fail "speculars summary: $out"
"$BIN/obj2tmd" --smooth "$dir/cube-sah.tmd" "$dir/s.tmd" 2>/dev/null; [ $? -eq 2 ] || fail "--smooth on a .tmd should exit 2"
[ -e "$dir/s.tmd" ] && fail "--smooth on a .tmd left an output"

# malformed input: an index past the vertices on line 5
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n# face\nf 1 2 9\n' >"$dir/bad.obj"
err=$("$BIN/obj2tmd" "$dir/bad.obj" "$dir/bad.tmd" 2>&1)
[ $? -eq 1 ] || fail "malformed OBJ should exit 1"
grep -q "bad.obj:5: bad vertex index in face corner '9'" <<<"$err" || fail "message: $err"
[ ! -e "$dir/bad.tmd" ] || fail "partial output left behind"
ls "$dir" | grep -q '\.tmp\.' && fail "temporary file left behind"

# nothing to convert, unreadable input, bad options, unwritable destination
printf 'v 0 0 0\n' >"$dir/empty.obj"
err=$("$BIN/obj2tmd" "$dir/empty.obj" "$dir/empty.tmd" 2>&1); [ $? -eq 1 ] || fail "empty OBJ should exit 1"
grep -q "no usable triangles" <<<"$err" || fail "empty message: $err"
err=$("$BIN/obj2tmd" "$dir/missing.obj" "$dir/m.tmd" 2>&1); [ $? -eq 1 ] || fail "missing input should exit 1"
grep -q "missing.obj: cannot open" <<<"$err" || fail "missing message: $err"
"$BIN/obj2tmd" --bvh octree models/cube.obj "$dir/x.tmd" 2>/dev/null; [ $? -eq 2 ] || fail "bad --bvh should exit 2"
"$BIN/obj2tmd" --leaf 0 models/cube.obj "$dir/x.tmd" 2>/dev/null; [ $? -eq 2 ] || fail "bad --leaf should exit 2"
err=$("$BIN/obj2tmd" models/cube.obj /nonexistent-dir/x.tmd 2>&1); [ $? -eq 1 ] || fail "unwritable output should exit 1"
grep -q "/nonexistent-dir/x.tmd" <<<"$err" || fail "unwritable message: $err"
[ ! -e "$dir/x.tmd" ] || fail "output written despite bad options"

# exporters' habits (tests/data/obj): converted, each with a warning naming file and line, counted in the summary
D=tests/data/obj
out=$("$BIN/obj2tmd" "$D/undefined-usemtl.obj" "$dir/u.tmd" 2>"$dir/u.err") || fail "undefined usemtl should convert: $(cat "$dir/u.err")"
grep -q "obj2tmd: warning: $D/undefined-usemtl.obj:6: material 'Default' is not defined" "$dir/u.err" || fail "undefined usemtl warning: $(cat "$dir/u.err")"
grep -q "warnings 1: undefined materials 1" <<<"$out" || fail "undefined usemtl summary: $out"
out=$("$BIN/obj2tmd" "$D/skipped.obj" "$dir/s.tmd" 2>"$dir/s.err") || fail "skipped elements should convert"
grep -q "skipped: 1 lines (l), 1 points (p), 5 free-form curves and surfaces, 1 merging groups (mg), 1 level of detail (lod), 1 display attributes, 1 unknown statements" <<<"$out" ||
    fail "skipped summary: $out"
[ "$(grep -c "obj2tmd: warning: $D/skipped.obj:[0-9]*: '" "$dir/s.err")" -eq 7 ] || fail "one warning per skipped kind: $(cat "$dir/s.err")"
# smoothing groups: read (s 1, s 2, s off), the smoothed triangles counted, a bad one named
out=$("$BIN/obj2tmd" "$D/smoothing.obj" "$dir/sg.tmd" 2>"$dir/sg.err") || fail "smoothing groups should convert: $(cat "$dir/sg.err")"
grep -q "smooth normals: 3 triangles (by smoothing group" <<<"$out" || fail "smoothing groups summary: $out"
grep -q "smoothing.obj:17: 's' wants a smoothing group number or 'off'" "$dir/sg.err" || fail "bad s: $(cat "$dir/sg.err")"
for f in missing-mtllib spaces colours habits utf16le utf16be; do
    "$BIN/obj2tmd" "$D/$f.obj" "$dir/$f.tmd" >/dev/null 2>&1 || fail "$f.obj should convert"
    [ -s "$dir/$f.tmd" ] || fail "$f.obj: no output"
done
# --strict: the first warning is an error, exit 1, no output
err=$("$BIN/obj2tmd" --strict "$D/undefined-usemtl.obj" "$dir/strict.tmd" 2>&1); [ $? -eq 1 ] || fail "--strict should exit 1"
grep -q "undefined-usemtl.obj:6: material 'Default'.*(an error with --strict)" <<<"$err" || fail "--strict message: $err"
[ ! -e "$dir/strict.tmd" ] || fail "--strict left an output"
"$BIN/obj2tmd" --strict "$D/habits.obj" "$dir/h.tmd" >/dev/null 2>&1 || fail "--strict refused a file with nothing to warn about"
# wrong data stays an error: exit 1, file and line, no output
for c in "index-zero:5: bad vertex index" "index-range:5: bad vertex index" "two-corners:5: a face needs at least 3" \
    "not-a-number:2: expected 3 finite numbers" "lines-only: no usable triangles" "empty: no usable triangles"; do
    f=${c%%:*}
    err=$("$BIN/obj2tmd" "$D/$f.obj" "$dir/$f.tmd" 2>&1); [ $? -eq 1 ] || fail "$f.obj should exit 1"
    grep -q "$D/$f.obj${c#"$f"}" <<<"$err" || fail "$f.obj message: $err"
    [ ! -e "$dir/$f.tmd" ] || fail "$f.obj left an output"
done
exit 0
