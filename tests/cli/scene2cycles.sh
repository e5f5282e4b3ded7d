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
echo "scene2cycles: $n Python tools compile; --check reads the Cycles reference scenes, maps point, round, sun and panel lights, refuses spots, unattenuated lights, lights beside frosted glass, tinted metal rims, unknown caustics and unread keywords with their lines; takes the light paths' settings and a glTF instance's lights and camera"
