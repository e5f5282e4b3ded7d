#!/usr/bin/env bash
# The window on a desktop, under a window manager (jwm, on Xvfb), where a
# user's F11, maximise button and window edges go through the manager
# rather than to the window (resize.sh resizes a window on a bare X
# screen, where xdotool's request is taken as it is).  The manager frames
# the window (a title bar, borders) and places it; F11 asks it for the
# whole screen (SDL's _NET_WM_STATE_FULLSCREEN) and F11 again for the
# window back at its size; a maximise request (as the title bar's button
# sends) gives the window the screen less the manager's panel; a resize
# through the manager.  Each time the window shows lanray-render's
# picture at the window's own size, pixel for pixel, at its corner.
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool jwm

SW=640 SH=480
start_xvfb ${SW}x${SH}x24
# a manager of the test's own: no panel, focus following the pointer (as a
# bare screen's), one title bar and border
cat >"$dir/jwmrc" <<'JWM'
<?xml version="1.0"?>
<JWM>
    <FocusModel>sloppy</FocusModel>
    <Desktops width="1" height="1"/>
</JWM>
JWM
# (xdotool get_desktop answers only where a manager says it keeps desktops;
# a manager that ended at once, "could not open display" seen once beside
# a loaded CI run, is started again)
for _ in 1 2 3; do
    HOME=$dir jwm -f "$dir/jwmrc" >"$dir/jwm.err" 2>&1 &
    wm=$!
    pids+=($wm)
    for _ in $(seq 50); do
        timeout 5 xdotool get_desktop >/dev/null 2>&1 && break 2
        kill -0 $wm 2>/dev/null || break
        sleep 0.1
    done
done
timeout 5 xdotool get_desktop >/dev/null 2>&1 || fail "jwm did not start: $(cat "$dir/jwm.err")"

# window_at, with X and Y where the window's own pixels start (xdotool's,
# under a manager that frames the window, count the frame's offset twice)
framed_at() {
    window_at
    read -r X Y <<<"$(timeout 5 python3 tests/tools/xwinpos.py "$WINDOW")" || fail "the window's position"
}

WINDOW_AT=framed_at

# shows NAME: the window shows lanray-render's picture of the built-in
# scene at the window's own size, pixel for pixel, at its corner (15 s)
shows() {
    local ref="$dir/ref-${WIDTH}x$HEIGHT.ppm" out
    "$BIN/lanray-render" --aa 1 --width "$WIDTH" --height "$HEIGHT" -o "$ref" --quiet >/dev/null ||
        fail "$1: the ${WIDTH}x$HEIGHT reference"
    out=$(appears "$ref" 75) || fail "$1: the ${WIDTH}x$HEIGHT window does not show the ${WIDTH}x$HEIGHT picture ($out)"
    [ "$out" = "found at $X,$Y" ] || fail "$1: the picture is not at the window's corner $X,$Y ($out)"
    echo "$1: ${WIDTH}x$HEIGHT frames at $X,$Y, lanray-render's picture pixel for pixel"
}

# key K: the key pressed with the pointer on the window (focus follows it)
key() {
    framed_at
    xdotool mousemove $((X + WIDTH / 2)) $((Y + HEIGHT / 2))
    sleep 0.2
    xdotool key "$1"
}

window_server desk --width 320 --height 240 --aa 1 --frames 0
sized 320 240
[ "$Y" -gt 0 ] || fail "the window is at $X,$Y: the manager gave it no title bar"
shows "opened, framed by the manager"
id=$(timeout 5 xdotool search --name '^lanray')
key F11
sized $SW $SH
[ "$X" -eq 0 ] && [ "$Y" -eq 0 ] || fail "F11: the full-screen window is at $X,$Y"
shows "F11, full screen"
key F11
sized 320 240
shows "F11 again, the window back"
timeout 5 python3 tests/tools/xwmstate.py "$id" add maximized_vert maximized_horz || fail "the maximise request"
for _ in $(seq 25); do framed_at; [ "$WIDTH" -gt 320 ] && [ "$HEIGHT" -gt 240 ] && break; sleep 0.2; done
[ "$WIDTH" -gt 320 ] && [ "$WIDTH" -le $SW ] && [ "$HEIGHT" -gt 240 ] && [ "$HEIGHT" -lt $SH ] ||
    fail "maximised: the window is ${WIDTH}x$HEIGHT"
shows "maximised"
timeout 5 python3 tests/tools/xwmstate.py "$id" remove maximized_vert maximized_horz || fail "the restore request"
sized 320 240
xdotool windowsize "$id" 400 180
sized 400 180
shows "resized through the manager"
stop_window_server desk
