#!/usr/bin/env bash
# A glTF's own camera and lights (model/gltf_scene.h) in a preview of the
# file: Blender's export of a red ball and a white box on a floor under a
# point lamp and a sun (tests/data/gltf/lit.glb, tools/bench/make-lit-glb).
# The frame is the camera's (the ball left of the centre, the box right,
# the floor below, the preview's grey background above); the sun and the
# lamp light it, the preview's lamps left out (the frame differs where the
# file's lights are taken out, and they stay under --environment); every
# SIMD path the same bytes, and a server with a client lanray-render's.
# (Against Cycles: tests/cli/pathtrace.sh.)
set -u
source tests/tools/server-lib.sh
glb=tests/data/gltf/lit.glb
"$BIN/lanray-render" "$glb" --width 64 --height 48 --aa 1 --linear -o "$dir/lit.png" --quiet >"$dir/r.log" 2>&1 ||
    fail "render: $(cat "$dir/r.log")"
# the ball (x 20, y 24), the box's lit face (x 44, y 23), the floor (32, 42), the background (32, 2)
got=$(python3 tests/tools/pngpixel.py "$dir/lit.png" 20 24 44 23 32 42 32 2 | tr '\n' ' ')
python3 - "$got" <<'PY' || fail "the glTF's camera and lights: ball, box, floor, background: $got"
import sys
v = list(map(int, sys.argv[1].split()))
ball, box, floor, bg = (tuple(v[i:i + 3]) for i in range(0, 12, 3))
ok = (ball[0] > 2 * ball[1] and ball[0] > 40    # the red ball, lit
      and min(box) > 40 and max(box) - min(box) < 40  # the white box (the lamp warm)
      and min(floor) > 20                          # the lit floor
      and bg == (41, 43, 51))                      # the preview's background (0.16 0.17 0.2)
sys.exit(0 if ok else 1)
PY
# without its lights (the preview's own lamps) the same frame differs
python3 - "$glb" "$dir/unlit.glb" <<'PY'
import json, struct, sys
b = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", b[12:16])[0]
j = json.loads(b[20:20 + n])
j.pop("extensions", None)
j.pop("extensionsUsed", None)
for node in j["nodes"]:
    node.pop("extensions", None)
t = json.dumps(j).encode()
t += b" " * ((4 - len(t) % 4) % 4)
rest = b[20 + n:]
out = b[:8] + struct.pack("<I", 12 + 8 + len(t) + len(rest)) + struct.pack("<II", len(t), 0x4E4F534A) + t + rest
open(sys.argv[2], "wb").write(out)
PY
"$BIN/lanray-render" "$dir/unlit.glb" --width 64 --height 48 --aa 1 --linear -o "$dir/unlit.png" --quiet >/dev/null 2>&1 ||
    fail "render without lights"
cmp -s "$dir/lit.png" "$dir/unlit.png" && fail "the glTF's lights made no difference"
# under --environment its own lights stay (the preview's lamps are what it replaces)
python3 tests/tools/envmap.py "$dir/grey.hdr" constant 16 8 0.5 0.5 0.5
for g in lit unlit; do
    src=$glb; [ $g = unlit ] && src=$dir/unlit.glb
    "$BIN/lanray-render" "$src" --environment "$dir/grey.hdr" --width 64 --height 48 --aa 1 --linear \
        -o "$dir/$g-env.png" --quiet >/dev/null 2>&1 || fail "$g under --environment"
done
env_lit=$(python3 tests/tools/pngpixel.py "$dir/lit-env.png" 20 24 | tr '\n' ' ')
env_unlit=$(python3 tests/tools/pngpixel.py "$dir/unlit-env.png" 20 24 | tr '\n' ' ')
set -- $env_lit $env_unlit
[ "$1" -gt $(($4 + 20)) ] || fail "under --environment the glTF's own lights should still light the ball: $env_lit against $env_unlit"
"$BIN/lanray-render" "$glb" --width 64 --height 48 --aa 1 -o "$dir/lit-1.png" --quiet >/dev/null 2>&1 || fail "render"
same_on_simd_paths "$glb" "$dir/lit-1.png" 64 48 "the glTF's scene"
"$BIN/lanray-render" "$glb" --width 64 --height 64 --aa 1 -o "$dir/ref.png" --quiet >/dev/null 2>&1 || fail "reference"
verify_distributed lit "$glb" "$dir/ref.png" "of the glTF's camera and lights"
# In a scene file: `instance MODEL lights camera` takes the glTF's lamps and
# view, placed with the instance.  Under the preview's background and
# ambient light, the preview's picture byte for byte; moved and turned, the
# same picture (a few pixels a level apart: the placed numbers round);
# without them a different one (no lamp, the default camera)
cp "$glb" "$dir/lit.glb"
cp "$dir/unlit.glb" "$dir/nolights.glb"
look='background 0.16 0.17 0.2\nambient 0.16 0.17 0.2\nmodel room lit.glb\n'
printf "${look}instance room lights camera\n" >"$dir/here.scene"
printf "${look}instance room translate 10 -3 4 rotate 0 90 0 lights camera\n" >"$dir/moved.scene"
printf "${look}instance room translate 10 -3 4 rotate 0 90 0\n" >"$dir/bare.scene"
for sc in here moved bare; do
    "$BIN/lanray-render" "$dir/$sc.scene" --width 64 --height 48 --aa 1 --linear -o "$dir/$sc.png" --quiet \
        >"$dir/$sc.log" 2>&1 || fail "render $sc.scene: $(cat "$dir/$sc.log")"
done
cmp -s "$dir/lit.png" "$dir/here.png" || fail "a scene file's instance with the glTF's lights and camera should render the preview's picture"
moved=$("$BIN/lanray-imgdiff" "$dir/here.png" "$dir/moved.png" 2>&1 | tail -1)
python3 -c 'import re,sys; m=re.search(r"max difference (\d+), differing pixels (\d+)", sys.argv[1]); sys.exit(0 if m and int(m[1]) <= 2 and int(m[2]) <= 20 else 1)' "$moved" ||
    fail "the moved instance's lights and camera should move with it: $moved"
bare=$("$BIN/lanray-imgdiff" "$dir/here.png" "$dir/bare.png" 2>&1 | tail -1)
python3 -c 'import re,sys; m=re.search(r"rmse ([0-9.]+)", sys.argv[1]); sys.exit(0 if m and float(m[1]) > 20 else 1)' "$bare" ||
    fail "without lights and camera the instance should look otherwise: $bare"
# asked of a file that has none: the file and line named, no picture
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$dir/tri.obj"
printf 'model t tri.obj\ninstance t lights\n' >"$dir/obj.scene"
printf 'model room nolights.glb\ninstance room camera\ninstance room lights\n' >"$dir/none.scene"
printf 'model room lit.glb\ninstance room scale 1e38 camera\n' >"$dir/far.scene" # its camera past a float's range
for sc in obj:"only a glTF" none:"none.scene:3: instance 'room' takes its model's lights, but" \
    far:"lit.glb gives none that can be placed there"; do
    name=${sc%%:*} want=${sc#*:}
    "$BIN/lanray-render" "$dir/$name.scene" -o "$dir/$name.png" --quiet >"$dir/$name.log" 2>&1 &&
        fail "$name.scene: an instance taking what its file lacks should fail"
    grep -qF "$want" "$dir/$name.log" || fail "$name.scene: the error should say '$want': $(cat "$dir/$name.log")"
    [ ! -e "$dir/$name.png" ] || fail "$name.scene: a failed render left a picture"
done
"$BIN/lanray-render" "$dir/moved.scene" --width 64 --height 64 --aa 1 -o "$dir/moved-ref.png" --quiet >/dev/null 2>&1 ||
    fail "reference of moved.scene"
verify_distributed moved "$dir/moved.scene" "$dir/moved-ref.png" "of a scene file's glTF lights and camera"
echo "gltfscene: a Blender-exported glTF previewed by its own camera and lights (ball, box, floor, background: $got), on every SIMD path and through a server; in a scene file the same picture by \`instance MODEL lights camera\`, moved with the instance ($moved)"
