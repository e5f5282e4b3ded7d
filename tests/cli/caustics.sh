#!/usr/bin/env bash
# The path integrator's caustics (settings caustics both|reflective|
# refractive|none, lanray-render --caustics: Cycles' Reflective and
# Refractive Caustics): a surface reached by a diffuse bounce reflects and
# refracts only as it says.  Only what a path meets right after a diffuse
# bounce changes: the diffuse Cornell box, and a mirror and a glass ball
# alone under a sky (every path after the camera's a delta's), keep their
# bytes without caustics.  Under the sky with its sun
# (tests/data/cycles/caustics.scene: glass, gold and chrome balls on a
# floor) the picture without caustics is Cycles' without them (within
# 1.5% in 4x4 blocks at 256 samples, its light within 1%; 0.51%, 0.9995),
# where the picture with them is 31% off it, and so past a clear veil
# over the floor (0.48%: the diffuse bounce before it counts past it, as
# Cycles' transparent bounces keep it); and the light orders itself:
# none < reflective alone, refractive alone < both.  A scene's setting is
# the option's picture; through a server and a client, lanray-render's
# (the server's --caustics too); a word the format does not know is
# refused naming the scene's line.
set -u
source tests/tools/server-lib.sh
render() { "$BIN/lanray-render" "$@" --quiet >/dev/null 2>"$dir/render.err" || fail "lanray-render $*: $(cat "$dir/render.err")"; }
cy=tests/data/cycles
# nothing reached by a diffuse bounce reflects or refracts
untouched_by "without caustics" --caustics none
# against Cycles' frame without caustics (the sanitizers' pass renders
# each once, every code path, and leaves the measures to the plain pass:
# the same renders took half a minute more there)
if [ $sanitized = 1 ]; then
    for c in both reflective refractive none; do render "$cy/caustics.scene" --caustics "$c" --aa 2 -o "$dir/c-$c.hdr"; done
else
    rel() { "$BIN/lanray-imgdiff" --relative --block 4 --csv "$1" "$2"; }
    for c in both reflective refractive none; do
        render "$cy/caustics.scene" --caustics "$c" --aa 16 -o "$dir/c-$c.hdr"
    done
    IFS=, read -r e_none r_none <<<"$(rel "$dir/c-none.hdr" "$cy/caustics-none-96.hdr")"
    IFS=, read -r e_both _ <<<"$(rel "$dir/c-both.hdr" "$cy/caustics-none-96.hdr")"
    python3 -c "import sys; e, r, b = map(float, sys.argv[1:]); sys.exit(0 if e < 0.015 and abs(r - 1) < 0.01 and b > 0.1 else 1)" \
        "$e_none" "$r_none" "$e_both" ||
        fail "without caustics $e_none (light $r_none) from Cycles' frame without them; with them $e_both"
    # past a clear veil just above the floor (ior 1: a transparent bounce, as
    # Cycles' Transparent BSDF), the floor's diffuse bounce still counts: the
    # same frame without caustics
    sed -e "s|^texture sky sky.hdr|texture sky $PWD/$cy/sky.hdr|" "$cy/caustics.scene" >"$dir/veiled.scene"
    printf 'material veil ior 1 transmit 1 1 1\nplane point 0 0.001 0 normal 0 1 0 material veil\n' >>"$dir/veiled.scene"
    render "$dir/veiled.scene" --caustics none --aa 16 -o "$dir/veiled.hdr"
    IFS=, read -r e_veil r_veil <<<"$(rel "$dir/veiled.hdr" "$cy/caustics-none-96.hdr")"
    python3 -c "import sys; e, r = map(float, sys.argv[1:]); sys.exit(0 if e < 0.015 and abs(r - 1) < 0.01 else 1)" \
        "$e_veil" "$r_veil" || fail "past a clear veil, without caustics $e_veil (light $r_veil) from Cycles' frame without them"
    # the light: none < reflective alone, refractive alone < both (ratios to Cycles' frame with them)
    light() { rel "$1" "$cy/caustics-96.hdr" | cut -d, -f2; }
    l_none=$(light "$dir/c-none.hdr") l_refl=$(light "$dir/c-reflective.hdr") l_refr=$(light "$dir/c-refractive.hdr")
    l_both=$(light "$dir/c-both.hdr")
    python3 -c "import sys; n, a, b, t = map(float, sys.argv[1:]); sys.exit(0 if n < a < t and n < b < t else 1)" \
        "$l_none" "$l_refl" "$l_refr" "$l_both" ||
        fail "the light: none $l_none, reflective $l_refl, refractive $l_refr, both $l_both"
fi
# the scene's setting, and through a server
sed -e "s|^texture sky sky.hdr|texture sky $PWD/$cy/sky.hdr|" \
    -e 's/^settings \(.*\)/settings \1 caustics refractive/' "$cy/caustics.scene" >"$dir/set.scene"
render "$dir/set.scene" --aa 2 -o "$dir/set.png"
render "$cy/caustics.scene" --aa 2 --caustics refractive -o "$dir/opt.png"
cmp -s "$dir/set.png" "$dir/opt.png" || fail "settings caustics refractive is not --caustics refractive's picture"
render "$cy/caustics.scene" --aa 2 -o "$dir/all.png"
cmp -s "$dir/set.png" "$dir/all.png" && fail "caustics refractive changed nothing: the test cannot tell"
setting_travels set "$dir/set.scene" "$cy/caustics.scene" caustics --caustics refractive
refused_setting "settings integrator path caustics some" "'caustics' of settings must be both, reflective, refractive or none"
if [ $sanitized = 1 ]; then
    echo "caustics: diffuse walls and delta surfaces alone keep their bytes; every caustics setting rendered (measured against Cycles in the plain pass); the scene's setting is the option's; through a server as lanray-render"
else
    echo "caustics: diffuse walls and delta surfaces alone keep their bytes; without caustics $e_none from Cycles' frame without them (light $r_none; with them $e_both; past a clear veil $e_veil); light none $l_none < reflective $l_refl, refractive $l_refr < both $l_both of Cycles' with them; the scene's setting is the option's; through a server as lanray-render"
fi
