#!/usr/bin/env bash
# The window at other sizes than its frame's, under Xvfb: a frame larger
# than the screen opens a window that fits the screen, the whole frame
# scaled down in it (its shape kept); a window resized shows the whole
# frame as large as it fits, centred, black bars beside it.  (F11's full
# screen goes through the window manager, which Xvfb has none of: not
# checked here.)  Each compared
# with lanray-render's picture averaged to the size shown
# (tests/tools/xwdscaled.py: within 6 levels on average, where the frame's
# corner unscaled, what a cropping window shows, is not).
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool

W=480 H=360 SW=400 SH=300
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.ppm" --quiet >/dev/null || fail "reference render"
start_xvfb ${SW}x${SH}x24
window_server resize --width $W --height $H --aa 1 --frames 0

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
[ "$WIDTH" -le $SW ] && [ "$HEIGHT" -le $SH ] || fail "a ${W}x$H frame opened a ${WIDTH}x$HEIGHT window on a ${SW}x$SH screen"
# within a pixel: |WIDTH x H - HEIGHT x W| at most the larger side
d=$((WIDTH * H - HEIGHT * W)); [ ${d#-} -le $W ] ||
    fail "the window (${WIDTH}x$HEIGHT) has not the frame's shape (${W}x$H)"
scaled "opened smaller than its frame"
id=$(timeout 5 xdotool search --name '^lanray')
xdotool windowmove "$id" 0 0
xdotool windowsize "$id" 390 150
scaled "resized wide"
xdotool windowsize "$id" 100 280
scaled "resized tall"
stop_window_server resize
