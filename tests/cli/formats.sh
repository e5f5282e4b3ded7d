#!/usr/bin/env bash
# One model in every format obj2tmd reads (tests/tools/formats.py: OBJ, PLY
# ASCII and binary, STL ASCII and binary, glTF 2.0 as .gltf + .bin and as
# .glb), converted and rendered: each image is byte-identical to the OBJ's,
# as is the OBJ's named MODEL.OBJ; an AC3D file (one of Assimp's other
# formats) converts, and a name no reader takes is refused with a reason.
# The one difference the formats force: STL has only facet normals, so the
# STL files are compared with the OBJ without vertex normals.  A damaged
# file, and one that crashes Assimp, fail with the name, exit 1, no output.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
python3 tests/tools/formats.py "$dir" || fail "formats.py"
render() { # model -> png
    "$BIN/obj2tmd" "$dir/$1" "$dir/$1.tmd" >"$dir/$1.log" 2>&1 || fail "obj2tmd $1: $(cat "$dir/$1.log")"
    "$BIN/lanray-render" "$dir/$1.tmd" --width 160 --height 120 --quiet -o "$dir/$1.png" >/dev/null 2>&1 || fail "render $1"
}
render model.obj
render model-flat.obj
for f in model-ascii.ply model-bin.ply model.gltf model.glb; do
    render "$f"
    grep -q "triangles 530," "$dir/$f.log" || fail "$f: $(cat "$dir/$f.log")"
    cmp -s "$dir/model.obj.png" "$dir/$f.png" ||
        fail "$f renders differently from the OBJ: $("$BIN/lanray-imgdiff" "$dir/model.obj.png" "$dir/$f.png")"
done
for f in model-ascii.stl model-bin.stl; do
    render "$f"
    cmp -s "$dir/model-flat.obj.png" "$dir/$f.png" ||
        fail "$f renders differently from the flat OBJ: $("$BIN/lanray-imgdiff" "$dir/model-flat.obj.png" "$dir/$f.png")"
done
# lanray-render previews them directly too
"$BIN/lanray-render" "$dir/model-bin.ply" --width 160 --height 120 --quiet -o "$dir/direct.png" >/dev/null 2>&1 || fail "preview of a PLY"
cmp -s "$dir/direct.png" "$dir/model.obj.png" || fail "a PLY previewed directly differs from its .tmd"
# the extension in any case (models from Windows machines: MODEL.OBJ)
cp "$dir/model.obj" "$dir/UPPER.OBJ"
render UPPER.OBJ
cmp -s "$dir/model.obj.png" "$dir/UPPER.OBJ.png" || fail "MODEL.OBJ renders differently from model.obj"
"$BIN/lanray-render" "$dir/UPPER.OBJ" --width 160 --height 120 --quiet -o "$dir/upper-direct.png" >/dev/null 2>&1 ||
    fail "preview of an .OBJ"
cmp -s "$dir/upper-direct.png" "$dir/model.obj.png" || fail "an .OBJ previewed directly differs from its .tmd"
# the rest of what Assimp reads: an AC3D tetrahedron (.ac)
printf '%s\n' AC3Db 'MATERIAL "w" rgb 0.8 0.8 0.8 amb 0.2 0.2 0.2 emis 0 0 0 spec 0 0 0 shi 10 trans 0' \
    'OBJECT world' 'kids 1' 'OBJECT poly' 'numvert 4' '0 0 0' '1 0 0' '0 1 0' '0 0 1' 'numsurf 4' \
    'SURF 0x10' 'mat 0' 'refs 3' '0 0 0' '2 0 0' '1 0 0' 'SURF 0x10' 'mat 0' 'refs 3' '0 0 0' '1 0 0' '3 0 0' \
    'SURF 0x10' 'mat 0' 'refs 3' '0 0 0' '3 0 0' '2 0 0' 'SURF 0x10' 'mat 0' 'refs 3' '1 0 0' '2 0 0' '3 0 0' \
    'kids 0' >"$dir/tetra.ac"
render tetra.ac
grep -q "triangles 4," "$dir/tetra.ac.log" || fail "tetra.ac: $(cat "$dir/tetra.ac.log")"
# a name no reader takes: said so, not read as an OBJ (whose errors would puzzle)
echo "not a model" >"$dir/notes.txt"
err=$("$BIN/obj2tmd" "$dir/notes.txt" "$dir/notes.tmd" 2>&1); [ $? -eq 1 ] || fail "notes.txt should exit 1"
grep -q "notes.txt: not a model format by its name's extension" <<<"$err" || fail "unknown extension message: $err"
[ ! -e "$dir/notes.tmd" ] || fail "an unknown format left an output"
# damaged: a binary PLY cut short
head -c 2000 "$dir/model-bin.ply" >"$dir/cut.ply"
err=$("$BIN/obj2tmd" "$dir/cut.ply" "$dir/cut.tmd" 2>&1); [ $? -eq 1 ] || fail "a cut PLY should exit 1"
grep -q "cut.ply" <<<"$err" || fail "cut PLY message: $err"
[ ! -e "$dir/cut.tmd" ] || fail "a cut PLY left an output"
# a PLY that crashes Assimp itself (found by fuzz_import): the importer runs
# in a child process, so this is an error naming the file, not a crash
crash=$(ls tests/fuzz/crashes/import-crash-* | head -1)
tail -c +2 "$crash" >"$dir/crash.ply" # the harness's first byte picks the format
err=$("$BIN/obj2tmd" "$dir/crash.ply" "$dir/crash.tmd" 2>&1); rc=$?
[ $rc -eq 1 ] || fail "a PLY that crashes Assimp: exit $rc ($err)"
grep -q "crash.ply: the importer (Assimp) crashed on this file" <<<"$err" || fail "crash message: $err"
[ ! -e "$dir/crash.tmd" ] || fail "a PLY that crashes Assimp left an output"
echo "formats: PLY, STL, glTF, GLB and MODEL.OBJ render byte-identical to model.obj; AC3D converts; an unknown extension is named; a file that crashes Assimp is an error"
