#!/usr/bin/env bash
# Vertex colours: an OBJ whose vertices carry colours (and no materials)
# renders them as the diffuse colour, interpolated across each triangle,
# checked pixel by pixel against the colours and the sRGB curve; the same
# model as a PLY with byte colours (through Assimp) renders the same bytes;
# the .tmd is version 6; a glTF's COLOR_0 multiplies its material's base
# colour (the picture of an OBJ with those products as its colours);
# colours beside a material in another format through the importer are a
# warning (an error with --strict); an instance with a material of its own shows that
# material instead; a distributed frame is bit-identical to lanray-render's
# (the colours travel inside the model asset).
set -u
source tests/tools/server-lib.sh
D=tests/data/colours
cp "$D/view.scene" "$dir/"
render() { "$BIN/lanray-render" "$dir/$1" --width 64 --height 64 -o "$dir/$2" --quiet >/dev/null 2>&1 || fail "render $2"; }
"$BIN/obj2tmd" "$D/quads.obj" "$dir/quads.tmd" >"$dir/obj.log" 2>"$dir/obj.err" || fail "obj2tmd: $(cat "$dir/obj.err")"
grep -q "vertex colours: 16 coloured vertices, kept as the diffuse colour" "$dir/obj.log" || fail "summary: $(cat "$dir/obj.log")"
[ -s "$dir/obj.err" ] && fail "warnings for a model whose colours are kept: $(cat "$dir/obj.err")"
python3 -c "import struct,sys; print(struct.unpack_from('<I', open(sys.argv[1],'rb').read(), 8)[0])" "$dir/quads.tmd" | grep -qx 6 ||
    fail "a .tmd with vertex colours is not version 6"
render view.scene obj.png
# expected codes: the quadrants' colours; along the bottom right quadrant's
# middle row the colour runs from 0 at x = 32 to 1 at x = 64 (pixel centres)
python3 - "$dir/obj.png" <<'PY' || fail "vertex colours not where expected"
import subprocess, sys
xs = [34, 40, 48, 56, 62]
pts = [(16, 16), (48, 16), (16, 48)] + [(x, 48) for x in xs]
out = subprocess.run(["python3", "tests/tools/pngpixel.py", sys.argv[1]] + [str(c) for p in pts for c in p],
                     capture_output=True, text=True, check=True).stdout.split("\n")
got = [tuple(int(v) for v in line.split()) for line in out if line.strip()]
def srgb(c):
    c = min(max(c, 0.0), 1.0)
    return round(255 * (12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055))
want = [(255, 0, 0), (0, 255, 0), (0, 0, 255)] + [(srgb(((x + 0.5) / 64 - 0.5) / 0.5),) * 3 for x in xs]
bad = [(p, g, w) for p, g, w in zip(pts, got, want) if any(abs(a - b) > 1 for a, b in zip(g, w))]
for p, g, w in bad:
    print("pixel %s: %s, expected %s" % (p, g, w))
sys.exit(1 if bad or len(got) != len(want) else 0)
PY
# the PLY a scanner would write: byte colours through Assimp, the same picture
"$BIN/obj2tmd" "$D/quads.ply" "$dir/quads.tmd" >"$dir/ply.log" 2>"$dir/ply.err" || fail "obj2tmd ply: $(cat "$dir/ply.err")"
render view.scene ply.png
cmp -s "$dir/obj.png" "$dir/ply.png" || fail "the PLY with vertex colours renders differently from the OBJ"
# through the importer, colours beside a material: in a glTF (COLOR_0 and a
# named material) they multiply its base colour (the glTF spec): the picture
# of an OBJ whose vertex colours are those products
python3 - "$dir/painted.gltf" <<'PY' || fail "writing painted.gltf"
import base64, json, struct, sys
blob = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<9f", 1, 0, 0, 0, 1, 0, 0, 0, 1)
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
       "materials": [{"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.5, 0.75, 1], "metallicFactor": 0}}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "material": 0}]}],
       "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                     {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}]}
json.dump(doc, open(sys.argv[1], "w"))
PY
printf 'v 0 0 0 0.25 0 0\nv 1 0 0 0 0.5 0\nv 0 1 0 0 0 0.75\nf 1 2 3\n' >"$dir/painted.obj"
"$BIN/obj2tmd" "$dir/painted.gltf" "$dir/painted-gltf.tmd" >"$dir/painted.log" 2>"$dir/painted.err" || fail "obj2tmd painted.gltf: $(cat "$dir/painted.err")"
[ -s "$dir/painted.err" ] && fail "painted.gltf: warnings: $(cat "$dir/painted.err")"
grep -q "kept as the diffuse colour" "$dir/painted.log" || fail "painted.gltf summary: $(cat "$dir/painted.log")"
"$BIN/obj2tmd" "$dir/painted.obj" "$dir/painted-obj.tmd" >/dev/null 2>&1 || fail "obj2tmd painted.obj"
# (diffuse shading: the glTF's clear coat, its dielectric base's specular
# reflection, which the OBJ has none of, is Phong shading's)
for m in gltf obj; do
    "$BIN/lanray-render" "$dir/painted-$m.tmd" --width 64 --height 48 --shading diffuse --quiet -o "$dir/painted-$m.png" \
        >/dev/null 2>&1 || fail "render painted-$m"
done
cmp -s "$dir/painted-gltf.png" "$dir/painted-obj.png" ||
    fail "a glTF's COLOR_0 does not multiply its base colour: $("$BIN/lanray-imgdiff" "$dir/painted-obj.png" "$dir/painted-gltf.png")"
# in other formats (a DirectX .x with vertex colours and a material): ignored
# with a warning, an error with --strict, no output
printf '%s\n' 'xof 0303txt 0032' 'Mesh tri {' ' 3;' ' 0.0;0.0;0.0;,' ' 1.0;0.0;0.0;,' ' 0.0;1.0;0.0;;' ' 1;' ' 3;0,1,2;;' \
    ' MeshMaterialList {' '  1;' '  1;' '  0;;' '  Material paint {' '   0.2;0.4;0.6;1.0;;' '   1.0;' '   0.0;0.0;0.0;;' \
    '   0.0;0.0;0.0;;' '  }' ' }' ' MeshVertexColors {' '  3;' '  0;1.0;0.0;0.0;1.0;;,' '  1;0.0;1.0;0.0;1.0;;,' \
    '  2;0.0;0.0;1.0;1.0;;;' ' }' '}' >"$dir/painted.x"
"$BIN/obj2tmd" "$dir/painted.x" "$dir/painted.tmd" >"$dir/painted.log" 2>"$dir/painted.err" || fail "obj2tmd painted.x: $(cat "$dir/painted.err")"
grep -q "obj2tmd: warning: $dir/painted.x: vertex colours ignored: the model's materials give its colours" "$dir/painted.err" ||
    fail "no warning for colours beside a material: $(cat "$dir/painted.err")"
grep -q "warnings 1: .*vertex colours ignored" "$dir/painted.log" || fail "summary: $(cat "$dir/painted.log")"
"$BIN/obj2tmd" --strict "$dir/painted.x" "$dir/strict.tmd" >/dev/null 2>"$dir/strict.err" && fail "--strict converted colours beside a material"
grep -q "vertex colours ignored: the model's materials give its colours (an error with --strict)" "$dir/strict.err" ||
    fail "--strict message: $(cat "$dir/strict.err")"
[ -e "$dir/strict.tmd" ] && fail "--strict left an output file"
# an instance's own material replaces the model's colours
sed 's/^instance quads$/material teal diffuse 0 0.5 0.5\ninstance quads material teal/' "$dir/view.scene" >"$dir/teal.scene"
render teal.scene teal.png
got=$(python3 tests/tools/pngpixel.py "$dir/teal.png" 16 16 48 48 | tr '\n' '|')
[ "$got" = "0 188 188|0 188 188|" ] || fail "instance material over vertex colours: $got"
# distributed: the coloured model through a server and a client, bit for bit
verify_distributed col "$dir/view.scene" "$dir/obj.png" "with vertex colours"
echo "colours: vertex colours from OBJ, PLY and glTF (times its base colour), interpolated, overridden by an instance material, local and distributed"
