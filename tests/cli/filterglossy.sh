#!/usr/bin/env bash
# The path integrator's Filter Glossy (settings filter_glossy,
# lanray-render --filter-glossy, Cycles' blur_glossy): glossy lobes,
# mirrors and glass blurred after a bounce unlikely to take its path.
# Only what a path meets after such a bounce changes: a scene of diffuse
# surfaces alone, and one of a mirror and a glass ball alone (every path
# after the camera's a delta's), keep their bytes.  Under a sky with a
# sun (tests/data/cycles/caustics.scene: glass, gold and chrome balls on a
# floor) the fireflies go: 4 x 4 samples come nearer their own 16 x 16
# picture than the unblurred ones do theirs (RMSE 8.7 against 13.5; the
# test holds 15% less); the
# light stays (the blurred 16 x 16 picture within 1.5% of the light of
# Cycles' unblurred frame, where Cycles' own blur loses 3.5%) and the blur
# is Cycles' blur (the blurred picture nearer Cycles' blurred frame than
# the unblurred one is).  A scene's `settings filter_glossy` is the
# option's picture; through a server and a client, lanray-render's (the
# setting travels with the view), the server's --filter-glossy too; a
# negative or too large F is refused, in a scene (naming its line) and
# on the command line.
set -u
source tests/tools/server-lib.sh
render() { "$BIN/lanray-render" "$@" --quiet >/dev/null 2>"$dir/render.err" || fail "lanray-render $*: $(cat "$dir/render.err")"; }
cy=tests/data/cycles
# nothing to blur: the Cornell box's diffuse walls, and delta surfaces alone
untouched_by "under --filter-glossy 10" --filter-glossy 10
# the fireflies, against each picture's own 16 x 16 (the sanitizers' pass
# renders each once, every code path, and leaves the measures to the plain
# pass: the same renders took a third of a minute more there)
if [ $sanitized = 1 ]; then
    for f in 0 1; do render "$cy/caustics.scene" --filter-glossy "$f" --aa 4 -o "$dir/c4-$f.png"; done
else
    rmse() { "$BIN/lanray-imgdiff" --csv "$1" "$2" | cut -d, -f3; }
    for f in 0 1; do
        render "$cy/caustics.scene" --filter-glossy "$f" --aa 4 -o "$dir/c4-$f.png"
        render "$cy/caustics.scene" --filter-glossy "$f" --aa 16 -o "$dir/c16-$f.png"
        render "$cy/caustics.scene" --filter-glossy "$f" --aa 16 -o "$dir/c16-$f.hdr"
    done
    e0=$(rmse "$dir/c4-0.png" "$dir/c16-0.png") e1=$(rmse "$dir/c4-1.png" "$dir/c16-1.png")
    python3 -c "import sys; sys.exit(0 if float(sys.argv[2]) < 0.85 * float(sys.argv[1]) else 1)" "$e0" "$e1" ||
        fail "4 x 4 samples blurred RMSE $e1 from their 16 x 16, unblurred $e0: not 15% less"
    # the light, and Cycles' blur (mean relative error in 4 x 4 blocks, light ratio)
    rel() { "$BIN/lanray-imgdiff" --relative --block 4 --csv "$1" "$2"; }
    IFS=, read -r t1 r1 <<<"$(rel "$dir/c16-1.hdr" "$cy/caustics-96.hdr")"
    IFS=, read -r b1 _ <<<"$(rel "$dir/c16-1.hdr" "$cy/caustics-blur-96.hdr")"
    IFS=, read -r b0 _ <<<"$(rel "$dir/c16-0.hdr" "$cy/caustics-blur-96.hdr")"
    python3 -c "import sys; r = float(sys.argv[1]); sys.exit(0 if abs(r - 1) < 0.015 else 1)" "$r1" ||
        fail "blurred, the light is $r1 of Cycles' unblurred frame's"
    python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < float(sys.argv[2]) else 1)" "$b1" "$b0" ||
        fail "Cycles' blurred frame: $b1 from the blurred picture, $b0 from the unblurred"
fi
# the scene's setting, and through a server
sed -e "s|^texture sky sky.hdr|texture sky $PWD/$cy/sky.hdr|" \
    -e 's/^settings \(.*\)/settings \1 filter_glossy 1/' "$cy/caustics.scene" >"$dir/blur.scene"
render "$dir/blur.scene" --aa 4 -o "$dir/set.png"
cmp -s "$dir/set.png" "$dir/c4-1.png" || fail "settings filter_glossy 1 is not --filter-glossy 1's picture"
cmp -s "$dir/c4-0.png" "$dir/c4-1.png" && fail "--filter-glossy 1 changed nothing: the test cannot tell"
setting_travels blur "$dir/blur.scene" "$cy/caustics.scene" filter_glossy --filter-glossy 1
refused_setting "settings integrator path filter_glossy -1" "'filter_glossy' of settings must be from 0"
out=$("$BIN/lanray-render" "$dir/box.scene" --filter-glossy 11 -o "$dir/no.png" 2>&1)
[ $? = 2 ] && grep -q "filter-glossy" <<<"$out" || fail "--filter-glossy 11: $out"
if [ $sanitized = 1 ]; then
    echo "filterglossy: diffuse walls and delta surfaces alone keep their bytes; blurred and unblurred rendered (measured in the plain pass); the scene's setting is the option's; through a server as lanray-render"
else
    echo "filterglossy: diffuse walls and delta surfaces alone keep their bytes; 4 x 4 samples of the caustics RMSE $e1 from their 16 x 16 blurred, $e0 unblurred; the light $r1 of Cycles' unblurred frame ($t1 from it); Cycles' blurred frame $b1 from the blurred picture, $b0 from the unblurred; the scene's setting is the option's; through a server as lanray-render"
fi
