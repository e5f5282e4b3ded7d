#!/usr/bin/env bash
# A file dropped on the window, as from a file manager (tests/tools/xdnd.py
# speaks the XDND protocol under Xvfb): a scene file replaces the scene
# shown (its camera, and its settings' size, which the window takes), a
# model is previewed as lanray-render previews it, each the picture
# lanray-render draws at the window's size pixel for pixel, the title
# naming it; the dropped scene's edits are followed from then on; a file
# that cannot be read leaves the scene shown and says why, in the log and
# the title.
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool

start_xvfb 640x480x24
window_server drop --aa 1 --frames 0
window_at
id=$(timeout 5 xdotool search --name '^lanray')

# dropped FILE: FILE dropped on the window's middle
dropped() {
    timeout 10 python3 tests/tools/xdnd.py "$id" $((X + WIDTH / 2)) $((Y + HEIGHT / 2)) "$1" ||
        fail "dropping $1 on the window"
}

# shows NAME RENDER-ARGS...: the window shows lanray-render's picture of
# the ARGS at the window's size, pixel for pixel, at its corner (15 s)
shows() {
    local name=$1 out
    shift
    window_at
    "$BIN/lanray-render" "$@" --aa 1 --width "$WIDTH" --height "$HEIGHT" -o "$dir/ref.ppm" --quiet >/dev/null ||
        fail "$name: the reference"
    out=$(appears "$dir/ref.ppm" 75) || fail "$name: the window does not show lanray-render $* ($out)"
    [ "$out" = "found at $X,$Y" ] || fail "$name: the picture is not at the window's corner $X,$Y ($out)"
    echo "$name: the window shows lanray-render's ${WIDTH}x$HEIGHT picture pixel for pixel"
}

# titled TEXT: the window's title holds TEXT (5 s)
titled() {
    local title=
    for _ in $(seq 25); do
        title=$(timeout 5 xdotool getwindowname "$id")
        [[ "$title" == *"$1"* ]] && return 0
        sleep 0.2
    done
    fail "the title reads '$title', not '$1'"
}

shows "the built-in scene"
dropped models/cornell.scene
titled "lanray - cornell.scene - "
# the Cornell box asks for 512x512: the window takes the most of it the screen has
window_at
[ "$WIDTH" -eq "$HEIGHT" ] || fail "the Cornell box's 512x512 made a ${WIDTH}x$HEIGHT window"
shows "cornell.scene dropped" models/cornell.scene
dropped models/cube.obj
titled "lanray - cube.obj - "
shows "cube.obj dropped (a preview)" models/cube.obj

# a dropped scene's edits are followed
printf 'camera position 0 1.5 4 lookat 0 0.3 0 fov 50\nplane point 0 -0.5 0 normal 0 1 0\nsphere centre -1 0.2 0 radius 0.5\nlight point position 2 4 3\n' >"$dir/d.scene"
dropped "$dir/d.scene"
shows "d.scene dropped" "$dir/d.scene"
sed 's/centre -1 0.2 0/centre 0.5 0.4 0/' "$dir/d.scene" >"$dir/d.tmp" && mv "$dir/d.tmp" "$dir/d.scene"
shows "d.scene edited after its drop" "$dir/d.scene"

# a file that cannot be read: the scene shown stays, the reason said
printf 'sphere centre 0 0\n' >"$dir/bad.scene"
dropped "$dir/bad.scene"
titled "lanray - error: $dir/bad.scene:1:"
grep -q "bad.scene:1: .*(the scene shown stays)" "$dir/drop.err" || fail "the bad file's error is not logged"
shows "bad.scene dropped (the scene shown stays)" "$dir/d.scene"

# a path-traced scene dropped on a Whitted window refines as one opened
# so does (to 1024 samples a pixel: not converged seconds later), where a
# window that kept the Whitted view's still quality showed its one sample
# a pixel as converged at once
{ echo 'settings integrator path'; cat "$dir/d.scene"; } >"$dir/p.scene"
dropped "$dir/p.scene"
titled "lanray - p.scene - "
sleep 3
title=$(timeout 5 xdotool getwindowname "$id")
[[ "$title" == *converged* ]] && fail "the path-traced scene dropped converged at once: '$title'"
echo "p.scene dropped (path-traced): still refining after 3 s ('$title')"
stop_window_server drop
