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
exit 0
