#!/usr/bin/env bash
# The Python tools, which make check does not otherwise run (Blender and
# numpy are not on CI's machines): every one compiles, and scene2cycles
# --check (no Blender) reads every stored Cycles reference scene and
# models/cornell.scene, maps lanray's lights to Cycles' lamps where Cycles
# has the same light, and refuses, naming the line, what it has not: a
# spot (Cycles' cone falls off by the cosine inside it), a light without
# attenuate, a light beside frosted glass (Cycles 3.4's Multiscatter GGX
# glass lights it wrongly), a keyword it does not read; and reads the
# light paths' settings (clamp_indirect, filter_glossy, caustics).
set -u
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
S2C=tools/bench/scene2cycles
n=0
for f in tools/ggx-tables tools/srgb-tables tools/bench/scene2cycles tests/tools/*.py; do
    python3 -c "import sys; compile(open(sys.argv[1]).read(), sys.argv[1], 'exec')" "$f" ||
        fail "$f does not compile"
    n=$((n + 1))
done
for f in tests/data/cycles/*.scene models/cornell.scene; do
    python3 "$S2C" --check "$f" >"$dir/out" 2>&1 || fail "scene2cycles --check refused $f: $(cat "$dir/out")"
done
grep -q "frosted glass: emitters and sky by the paths alone" <(python3 "$S2C" --check tests/data/cycles/frosted.scene) ||
    fail "frosted.scene's emitters are not left to Cycles' paths"
# lights: each mappable kind taken, each other refused with its line
base() {
    cat <<'S'
camera position 0 1 4 lookat 0 0.5 0 fov 40
background 0.2 0.2 0.2
settings width 32 height 24 integrator path
material floor diffuse 0.5 0.5 0.5
sphere centre 0 0.5 0 radius 0.5 material floor
plane point 0 0 0 normal 0 1 0 material floor
S
}
{ base; cat <<'S'
light point position 1 2 1 attenuate intensity 2
light sphere position -1 2 1 radius 0.2 attenuate
light directional direction 0 -1 0.3
light rect corner -1 2 -1 edge1 1 0 0 edge2 0 0 1 attenuate
S
} >"$dir/lights.scene"
out=$(python3 "$S2C" --check "$dir/lights.scene" 2>&1) || fail "mappable lights refused: $out"
case "$out" in *"lights as lamps: point sphere directional rect"*) ;; *) fail "lights not all taken: $out" ;; esac
refuse() { # refuse WHAT LINE WORDS...: the scene with LINE added is refused, naming its line and WORDS
    local what=$1 line=$2
    shift 2
    { base; echo "$line"; } >"$dir/bad.scene"
    local out
    out=$(python3 "$S2C" --check "$dir/bad.scene" 2>&1) && fail "$what taken: $out"
    case "$out" in *"bad.scene:7"*) ;; *) fail "$what refused without its line: $out" ;; esac
    for w in "$@"; do
        case "$out" in *"$w"*) ;; *) fail "$what refused without saying '$w': $out" ;; esac
    done
}
refuse "a spot" "light spot position 0 2 0 direction 0 -1 0 angle 30 attenuate" "spot light"
refuse "a light without attenuate" "light point position 0 2 0" "without attenuate"
refuse "an unknown keyword" "fog 0.1" "'fog' is not read"
refuse "a tinted rim" "material tint reflect 0.5 0.5 0.5 reflect_edge 1 0.9 0.8" "grey reflect_edge"
refuse "caustics of a word it does not know" "settings caustics some" "caustics must be both, reflective, refractive or none"
# the light paths' settings, handed to Cycles' Clamp Indirect, Filter Glossy and Caustics
{ base; echo "settings clamp_indirect 3 filter_glossy 1 caustics refractive"; } >"$dir/paths.scene"
out=$(python3 "$S2C" --check "$dir/paths.scene" 2>&1) || fail "the light paths' settings refused: $out"
case "$out" in *"light paths: clamp indirect 3, filter glossy 1, caustics refractive"*) ;;
*) fail "the light paths' settings not taken: $out" ;; esac
{ base; echo "material frost ior 1.5 roughness 0.4"; echo "light point position 0 2 0 attenuate"; } >"$dir/bad.scene"
out=$(python3 "$S2C" --check "$dir/bad.scene" 2>&1) && fail "a light beside frosted glass taken: $out"
case "$out" in *"beside frosted glass"*) ;; *) fail "a light beside frosted glass refused for another reason: $out" ;; esac
# a glTF instance's own lights and camera (a scene without a camera line),
# from a glTF only
cp tests/data/gltf/lit.glb "$dir/lit.glb"
printf 'model room lit.glb\ninstance room rotate 0 90 0 lights camera\n' >"$dir/gltf.scene"
out=$(python3 "$S2C" --check "$dir/gltf.scene" 2>&1) || fail "a glTF instance's lights and camera refused: $out"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$dir/tri.obj"
printf 'camera position 0 0 5 lookat 0 0 0\nmodel t tri.obj\ninstance t lights\n' >"$dir/objlit.scene"
out=$(python3 "$S2C" --check "$dir/objlit.scene" 2>&1) && fail "an OBJ instance's lights taken: $out"
case "$out" in *"objlit.scene:3"*"from a glTF only"*) ;; *) fail "an OBJ instance's lights refused otherwise: $out" ;; esac
# a .hdr panorama is handed to Cycles as lanray reads it (Blender 3.4 reads
# each mantissa at the bottom of its step: 0.2-0.4% less light): texels of
# run-length coded scanlines are their flat twins', a texel's light is
# Radiance's (m + 0.5) 2^(e - 136), exponent 0 black, and a scanline that
# runs past the file is refused naming the file
python3 - "$S2C" "$dir" <<'PY' || fail "scene2cycles reads a .hdr otherwise than lanray"
import importlib.machinery, importlib.util, os, sys
loader = importlib.machinery.SourceFileLoader("scene2cycles", sys.argv[1])
s2c = importlib.util.module_from_spec(importlib.util.spec_from_loader("scene2cycles", loader))
loader.exec_module(s2c)
d = sys.argv[2]
w, h = 40, 3
texels = bytes((x * 7 + y) % 256 if c < 3 else 120 + y for y in range(h) for x in range(w) for c in range(4))
head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w)
open(os.path.join(d, "flat.hdr"), "wb").write(head + texels)
rle = bytearray(head)
for y in range(h):  # each channel: a run of 12 alike, then 28 literal bytes
    rle += bytes((2, 2, 0, w))
    for c in range(4):
        row = [texels[4 * (y * w + x) + c] for x in range(w)]
        row[:12] = [row[0]] * 12
        rle += bytes((128 + 12, row[0], 28)) + bytes(row[12:])
open(os.path.join(d, "rle.hdr"), "wb").write(bytes(rle))
assert s2c.radiance_read(os.path.join(d, "flat.hdr")) == (w, h, texels)
_, _, got = s2c.radiance_read(os.path.join(d, "rle.hdr"))
want = bytearray(texels)
for y in range(h):
    for c in range(4):
        for x in range(12):
            want[4 * (y * w + x) + c] = texels[4 * (y * w) + c]
assert got == bytes(want), "run-length coded scanlines"
assert s2c.rgbe_light(200, 129) == 200.5 / 128 and s2c.rgbe_light(0, 136) == 0.5 and s2c.rgbe_light(9, 0) == 0
open(os.path.join(d, "short.hdr"), "wb").write(bytes(rle[:-5]))
import contextlib, io
said = io.StringIO()
try:
    with contextlib.redirect_stderr(said):
        s2c.radiance_read(os.path.join(d, "short.hdr"))
    sys.exit("a short file read")
except SystemExit as e:
    assert e.code == 1 and "short.hdr: scanline 2" in said.getvalue(), said.getvalue()
PY
out=$(python3 "$S2C" --check tests/data/cycles/environment.scene 2>&1)
case "$out" in *"sky.hdr (128 x 64, read as lanray reads it)"*) ;; *) fail "the sky not read: $out" ;; esac
echo "scene2cycles: $n Python tools compile; a .hdr panorama read as lanray reads it; --check reads the Cycles reference scenes, maps point, round, sun and panel lights, refuses spots, unattenuated lights, lights beside frosted glass, tinted metal rims, unknown caustics and unread keywords with their lines; takes the light paths' settings and a glTF instance's lights and camera"
