#!/usr/bin/env bash
# The window at other sizes than its frame's, under Xvfb.  By default the
# frames follow the window's size, as a renderer's viewport does: a frame
# larger than the screen opens a window that fits the screen and the
# frames become the window's size; a window resized wide or tall renders
# at its new size; a scene file whose settings width/height are edited
# makes the window that size.  Each time the window shows lanray-render's
# picture at the window's size pixel for pixel.  With --fixed-size the
# frames keep their size and a resized window shows the whole frame as
# large as it fits, centred, black bars beside it (compared with
# lanray-render's picture averaged to the size shown, by
# tests/tools/xwdscaled.py: within 6 levels on average, where the frame's
# corner unscaled, what a cropping window shows, is not).  F11's full
# screen and a maximised window go through a window manager, which a bare
# Xvfb has none of: desktop.sh runs one.
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool

W=480 H=360 SW=400 SH=300
start_xvfb ${SW}x${SH}x24


# shows NAME [RENDER-ARGS...]: the window shows lanray-render's picture
# (of the built-in scene at --aa 1 unless the ARGS say) at the window's own
# size, pixel for pixel, at the window's corner (15 s at most)
shows() {
    local name=$1 ref="$dir/ref-${WIDTH}x$HEIGHT.ppm" out
    shift
    "$BIN/lanray-render" --aa 1 "$@" --width "$WIDTH" --height "$HEIGHT" -o "$ref" --quiet >/dev/null ||
        fail "$name: the ${WIDTH}x$HEIGHT reference"
    out=$(appears "$ref" 75) || fail "$name: the ${WIDTH}x$HEIGHT window does not show the ${WIDTH}x$HEIGHT picture ($out)"
    [ "$out" = "found at $X,$Y" ] || fail "$name: the picture is not at the window's corner $X,$Y ($out)"
    echo "$name: ${WIDTH}x$HEIGHT frames, lanray-render's picture pixel for pixel"
}

mkdir "$dir/shots"
WINDOW_CWD=$dir/shots window_server follow --width $W --height $H --aa 1 --frames 0
window_at
[ "$WIDTH" -le $SW ] && [ "$HEIGHT" -le $SH ] || fail "a ${W}x$H frame opened a ${WIDTH}x$HEIGHT window on a ${SW}x$SH screen"
# within a pixel: |WIDTH x H - HEIGHT x W| at most the larger side
d=$((WIDTH * H - HEIGHT * W)); [ ${d#-} -le $W ] ||
    fail "the window (${WIDTH}x$HEIGHT) has not the frame's shape (${W}x$H)"
shows "opened smaller than its frame"
id=$(timeout 5 xdotool search --name '^lanray')
xdotool windowmove "$id" 0 0
xdotool windowsize "$id" 390 150
sized 390 150
shows "resized wide"
# P saves the frame shown, at its new size
xdotool mousemove $((X + 20)) $((Y + 20))
xdotool key p
for _ in $(seq 50); do compgen -G "$dir/shots/lanray-screenshot-*.png" >/dev/null && break; sleep 0.1; done
shot=$(compgen -G "$dir/shots/lanray-screenshot-*.png") || fail "P: no screenshot within 5 s ($(cat "$dir/follow.err"))"
diff=$("$BIN/lanray-imgdiff" --csv "$shot" "$dir/ref-390x150.ppm") || fail "P: cannot compare the screenshot"
[ "${diff%%,*}" = 0 ] || fail "P: the screenshot is not the 390x150 picture shown ($diff)"
echo "resized wide: P saves the 390x150 frame"
xdotool windowsize "$id" 100 280
sized 100 280
shows "resized tall"
stop_window_server follow

# a scene's size edited: the window takes it, and the frames with it
printf 'settings width 200 height 120\ncamera position 0 1.5 4 lookat 0 0.3 0 fov 50\nplane point 0 -0.5 0 normal 0 1 0\nsphere centre -1 0.2 0 radius 0.5\nlight point position 2 4 3\n' >"$dir/e.scene"
window_server edit "$dir/e.scene" --aa 1 --frames 0
sized 200 120
shows "a scene of 200x120" "$dir/e.scene"
sed 's/width 200 height 120/width 260 height 100/' "$dir/e.scene" >"$dir/e.tmp" && mv "$dir/e.tmp" "$dir/e.scene"
sized 260 100
shows "its size edited to 260x100" "$dir/e.scene"
grep -q "e.scene asks for 260x100 frames: the window takes that size" "$dir/edit.err" ||
    fail "the edited size is not said: $(cat "$dir/edit.err")"
stop_window_server edit

# a path-traced, denoised view: its filter and history made again at the
# new size, its converged frame lanray-render's
window_server path models/cornell.scene --integrator path --denoise --still-aa 2 --width 160 --height 160 --frames 0
sized 160 160
id=$(timeout 5 xdotool search --name '^lanray')
xdotool windowsize "$id" 150 110
sized 150 110
shows "path-traced, denoised, resized" models/cornell.scene --integrator path --denoise on --aa 2
stop_window_server path

# --fixed-size: the frame scaled to the window
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.ppm" --quiet >/dev/null || fail "reference render"
window_server fixed --width $W --height $H --aa 1 --frames 0 --fixed-size

# scaled NAME: waits (10 s) until the window shows the frame scaled to fit it
scaled() {
    local out=
    for _ in $(seq 50); do
        window_at
        screenshot
        out=$(python3 tests/tools/xwdscaled.py "$dir/screen.xwd" "$X" "$Y" "$WIDTH" "$HEIGHT" "$dir/ref.ppm") && {
            echo "$1: $out"
            return 0
        }
        sleep 0.2
    done
    fail "$1: $out"
}

window_at
scaled "--fixed-size, opened smaller than its frame"
id=$(timeout 5 xdotool search --name '^lanray')
xdotool windowmove "$id" 0 0
xdotool windowsize "$id" 390 150
sized 390 150
scaled "--fixed-size, resized wide"
xdotool windowsize "$id" 100 280
sized 100 280
scaled "--fixed-size, resized tall"
stop_window_server fixed
